"""What a design is asked for and what limits it: performance scalings and weights derived
from the problem and the body, and the physical limit that binds when a design misses.

- :func:`derived_scalings`: the error, control and disturbance scalings (Ve, Vu, Vd) of
  a problem from its pointing requirement and torque authority
  (:class:`DerivedScalings`, :class:`ScalingSummary`).
- :func:`body_weights`: the dynamic weights We and Wu derived from the body (its hold
  bandwidth and first flexible mode) for a debris that is not the paper's
  (:class:`BodyWeights`, :class:`BodySummary`).
- :func:`pointing_limit`, :func:`slew_limit`, :func:`mu_limit`, :func:`margins_limit`:
  which limit binds for each requirement missed, with its numbers and what would meet it
  (:class:`BindingLimit`).
"""

from casadi_debris.robust.requirements._binding import (
    BindingLimit,
    BodyLimits,
    margins_limit,
    mu_limit,
    pointing_limit,
    slew_limit,
)
from casadi_debris.robust.requirements._body_weights import (
    WEIGHTS_CHOICES,
    BodySummary,
    BodyWeights,
    WeightsChoice,
    body_weights,
    derived_rolloff_rad_s,
    first_mode_rad_s,
    hold_bandwidth_rad_s,
    is_papers_body,
)
from casadi_debris.robust.requirements._scalings import (
    DISTURBANCE_TO_AUTHORITY,
    DerivedScalings,
    ScalingSummary,
    authority_per_axis_mNm,
    derived_scalings,
)

__all__ = [
    "DISTURBANCE_TO_AUTHORITY",
    "WEIGHTS_CHOICES",
    "BindingLimit",
    "BodyLimits",
    "BodySummary",
    "BodyWeights",
    "DerivedScalings",
    "ScalingSummary",
    "WeightsChoice",
    "authority_per_axis_mNm",
    "body_weights",
    "derived_rolloff_rad_s",
    "derived_scalings",
    "first_mode_rad_s",
    "hold_bandwidth_rad_s",
    "is_papers_body",
    "margins_limit",
    "mu_limit",
    "pointing_limit",
    "slew_limit",
]
