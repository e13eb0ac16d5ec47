"""μ analysis: the structured singular value of a loop, bounded above and below.

- :class:`Block` and :func:`block_structure`: the uncertainty's block structure (full
  complex blocks of any size, repeated real scalars).
- :func:`mu_upper_bound`: the complex upper bound on a frequency grid (:class:`MuBound`).
- :func:`mu_bounds`: mixed real/complex μ, the D-G upper bound (:func:`lmi_upper_bound`)
  and a lower bound with the destabilising perturbation (:func:`lower_bound`), per
  frequency (:class:`MuBounds`).
- The paper's parametric uncertainty as real scalar blocks: a sample-fitted LFT of the
  plant (:func:`fit_parametric_plant`), the controller's loop around it
  (:func:`parametric_closed_loop`) and the robust stability and performance over it
  with the worst perturbation found (:func:`parametric_mu`, :class:`ParametricMu`).

Example
-------
>>> import numpy as np
>>> from casadi_debris.robust.mu import mu_bounds
>>> bounds = mu_bounds(np.eye(2)[None], [("complex", 1), ("complex", 1)])
>>> round(float(bounds.upper[0]), 6), round(float(bounds.lower[0]), 6)
(1.0, 1.0)
"""

from casadi_debris.robust.mu._blocks import Block, BlockLike, block_structure, expanded, total_size
from casadi_debris.robust.mu._lft import ParametricPlant, fit_parametric_plant
from casadi_debris.robust.mu._lmi import lmi_upper_bound
from casadi_debris.robust.mu._loop import (
    N_PERFORMANCE,
    parametric_closed_loop,
    parametric_generalized_plant,
)
from casadi_debris.robust.mu._lower import lower_bound
from casadi_debris.robust.mu._mixed import MuBounds, PeakBounds, mu_bounds
from casadi_debris.robust.mu._parametric import (
    KINDS,
    ParametricMu,
    ParametricMuSummary,
    RealMuBounds,
    WorstPerturbation,
    parametric_mu,
    top_frequencies,
)
from casadi_debris.robust.mu._upper import MuBound, mu_upper_bound, scaled_norm

__all__ = [
    "KINDS",
    "N_PERFORMANCE",
    "Block",
    "BlockLike",
    "MuBound",
    "MuBounds",
    "ParametricMu",
    "ParametricMuSummary",
    "ParametricPlant",
    "PeakBounds",
    "RealMuBounds",
    "WorstPerturbation",
    "block_structure",
    "expanded",
    "fit_parametric_plant",
    "lmi_upper_bound",
    "lower_bound",
    "mu_bounds",
    "mu_upper_bound",
    "parametric_closed_loop",
    "parametric_generalized_plant",
    "parametric_mu",
    "scaled_norm",
    "top_frequencies",
    "total_size",
]
