"""Robust control: uncertainty weight, mu-synthesis on any generalised plant, reduction, margins.

Design units of the paper's problem are the paper's: attitude in deg, torque in mNm.

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

from casadi_debris.robust.blocks import Block
from casadi_debris.robust.hinf import HinfResult, hinf_synthesis
from casadi_debris.robust.mixed_mu import MuBounds, mu_bounds
from casadi_debris.robust.mu import MuBound, mu_upper_bound
from casadi_debris.robust.musyn import MusynResult, musyn

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
