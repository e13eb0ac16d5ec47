"""Robust control: uncertainty weight, mu-synthesis on any generalised plant, reduction, margins.

Design units of the paper's problem are the paper's: attitude in deg, torque in mNm.
The package has five parts, each exporting its public names from its ``__init__``;
lower parts never import upper ones:

- :mod:`casadi_debris.robust.synthesis`: H-infinity, D-K iteration, reduction, the
  paper's design end to end, classical controllers;
- :mod:`casadi_debris.robust.mu`: μ analysis, complex and mixed, bounded above and
  below, and over the real parametric uncertainty;
- :mod:`casadi_debris.robust.margins`: loop-at-a-time and disk margins, nominal and
  sampled;
- :mod:`casadi_debris.robust.requirements`: scalings and weights derived from the
  problem and the body, and the limit that binds when a design misses;
- :mod:`casadi_debris.robust.plant`: the loop's parts as data (frequency responses,
  uncertainty samples, weights, the generalised plant, the controller file).

The names most used are also here:

- :func:`musyn`: D-K iteration on any generalised plant and block structure
  (full complex blocks of any size, repeated real scalars), e.g.
  ``musyn(plant, [("complex", 1), ("complex", 1), ("complex", 2)], 2, 2)``.
- :class:`MusynResult`: its controller, peak mu, history and why it stopped.
- :func:`mu_upper_bound`: the mu upper bound of frequency responses.
- :func:`mu_bounds`: mixed real/complex mu, upper (D-G scalings) and lower
  bounds per frequency with the destabilising perturbation (:class:`MuBounds`).
- :func:`hinf_synthesis`: H-infinity synthesis, verified on the plant as given.

Example
-------
>>> from casadi_debris.robust import musyn
>>> from casadi_debris.robust.examples import DISTILLATION_BLOCKS, distillation_column
>>> result = musyn(distillation_column(), DISTILLATION_BLOCKS, 2, 2)  # doctest: +SKIP
>>> round(result.mu_peak, 2)  # doctest: +SKIP
1.04
"""

from casadi_debris.robust.mu import Block, MuBound, MuBounds, mu_bounds, mu_upper_bound
from casadi_debris.robust.synthesis import HinfResult, MusynResult, hinf_synthesis, musyn

__all__ = [
    "Block",
    "HinfResult",
    "MuBound",
    "MuBounds",
    "MusynResult",
    "hinf_synthesis",
    "mu_bounds",
    "mu_upper_bound",
    "musyn",
]
