"""One symbolic CasADi model of the combined body, compiled and linearised.

See :mod:`casadi_debris.dynamics._flexible_body` for the equations.
"""

from casadi_debris.dynamics._attitude import (
    attitude_error,
    attitude_error_vector,
    axis_angle_quaternion,
    error_quaternion,
    euler_angles_321,
    quaternion_axis_angle,
    quaternion_conjugate,
    quaternion_multiply,
    quaternion_product,
    quaternion_rate,
    quaternion_to_rotation,
    rotation_matrix,
    rotation_to_quaternion,
)
from casadi_debris.dynamics._cantilever import bending_eigenvalue, shape_integrals
from casadi_debris.dynamics._compiled import Model, build_model, select_modes
from casadi_debris.dynamics._flexible_body import INPUT_NAMES, StateLayout
from casadi_debris.dynamics._linearize import (
    Units,
    assembled_modes,
    flexible_frequencies,
    linearization_function,
    linearize,
    state_names,
)
from casadi_debris.dynamics._parameters import INERTIA_SCALE_NAMES, ParameterLayout, Parameters

__all__ = [
    "INERTIA_SCALE_NAMES",
    "INPUT_NAMES",
    "Model",
    "ParameterLayout",
    "Parameters",
    "StateLayout",
    "Units",
    "assembled_modes",
    "attitude_error",
    "attitude_error_vector",
    "axis_angle_quaternion",
    "bending_eigenvalue",
    "build_model",
    "error_quaternion",
    "euler_angles_321",
    "flexible_frequencies",
    "linearization_function",
    "linearize",
    "quaternion_axis_angle",
    "quaternion_conjugate",
    "quaternion_multiply",
    "quaternion_product",
    "quaternion_rate",
    "quaternion_to_rotation",
    "rotation_matrix",
    "rotation_to_quaternion",
    "select_modes",
    "shape_integrals",
    "state_names",
]
