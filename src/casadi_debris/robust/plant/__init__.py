"""The loop's parts as data: the plant's frequency responses, its uncertainty, the weights
and generalised plant of the design, and a designed controller.

- :func:`sample_uncertainty` samples the problem's uncertainty set (inertia, mass, array
  angle, first bending frequency) and :func:`relative_errors` /
  :func:`diagonal_cover` measure how far the sampled plants stray from the nominal one;
  :func:`parameters_from_normalized` maps a point of the unit box to the parameters.
- :class:`PerformanceWeights` and :class:`UncertaintyWeight` are the design weights
  (:func:`performance_weights`, :func:`dynamic_weights`,
  :func:`fit_uncertainty_weight`); :func:`generalized_plant` builds the four-block
  generalised plant from them (:class:`GeneralizedPlant`).
- :class:`FrequencyResponse` evaluates C (jw I - A)^-1 B + D of any state-space system
  on any grid, after one block-diagonal Schur decomposition.
- :class:`Controller` is a designed controller as the controller file holds it,
  bound to the problem it was designed for.
"""

from casadi_debris.robust.plant._controller import CONTROLLER_FORMAT_VERSION, Controller
from casadi_debris.robust.plant._interconnect import (
    GeneralizedPlant,
    generalized_plant,
    named,
    signals,
    static_gain,
)
from casadi_debris.robust.plant._response import FrequencyResponse, state_space_response
from casadi_debris.robust.plant._uncertainty import (
    FULL_CIRCLE_DEG,
    UncertaintySamples,
    box_corners,
    corner_angles,
    diagonal_cover,
    frequency_response,
    normalized_from_parameters,
    parameters_from_normalized,
    relative_errors,
    sample_uncertainty,
)
from casadi_debris.robust.plant._weights import (
    W_ORDER,
    PerformanceWeights,
    UncertaintyWeight,
    dynamic_weights,
    fit_uncertainty_weight,
    performance_weights,
    recorded_performance_weights,
    second_order_magnitude,
    weight_system,
)

__all__ = [
    "CONTROLLER_FORMAT_VERSION",
    "FULL_CIRCLE_DEG",
    "W_ORDER",
    "Controller",
    "FrequencyResponse",
    "GeneralizedPlant",
    "PerformanceWeights",
    "UncertaintySamples",
    "UncertaintyWeight",
    "box_corners",
    "corner_angles",
    "diagonal_cover",
    "dynamic_weights",
    "fit_uncertainty_weight",
    "frequency_response",
    "generalized_plant",
    "named",
    "normalized_from_parameters",
    "parameters_from_normalized",
    "performance_weights",
    "recorded_performance_weights",
    "relative_errors",
    "sample_uncertainty",
    "second_order_magnitude",
    "signals",
    "state_space_response",
    "static_gain",
    "weight_system",
]
