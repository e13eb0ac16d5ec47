"""One symbolic CasADi model of the combined body, compiled and linearised.

See :mod:`casadi_debris.dynamics.flexible_body` for the equations.
"""

from casadi_debris.dynamics.compiled import Model, build_model, select_modes
from casadi_debris.dynamics.flexible_body import INPUT_NAMES, StateLayout
from casadi_debris.dynamics.linearize import (
    Units,
    assembled_modes,
    flexible_frequencies,
    linearization_function,
    linearize,
    state_names,
)
from casadi_debris.dynamics.parameters import INERTIA_SCALE_NAMES, ParameterLayout, Parameters

__all__ = [
    "INERTIA_SCALE_NAMES",
    "INPUT_NAMES",
    "Model",
    "ParameterLayout",
    "Parameters",
    "StateLayout",
    "Units",
    "assembled_modes",
    "build_model",
    "flexible_frequencies",
    "linearization_function",
    "linearize",
    "select_modes",
    "state_names",
]
