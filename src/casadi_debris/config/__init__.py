"""Problem parameters: frozen dataclasses loaded from TOML and validated.

A problem file holds every number of a scenario with its unit in the key name
(``mass_kg``, ``omega_rad_s``). :func:`load_problem` reads one (default: the
shipped ``problems/paper.toml``), checks every key and returns a
:class:`Problem`. Nothing downstream reads a file.

A problem file may start from another one with ``extends = "paper.toml"``
(path relative to the file): its tables are merged key by key, arrays and
scalars replaced whole (an ``[[arrays]]`` or ``[[cubesats]]`` list whole; a child
that gives its CubeSats, as a list or a ``[cubesat_layout]``, drops the parent's).

Example
-------
>>> from casadi_debris import load_problem
>>> problem = load_problem()
>>> problem.hub.mass_kg
500.0

The package exports the schema's frozen dataclasses (:class:`Problem` and its
tables), the readers (:func:`problem_from_dict`, :func:`problem_with_values`), the
loader (:func:`load_problem`, :func:`shipped_problems`) and the physical checks
(:func:`check_inertia`); its modules are private, except
:mod:`~casadi_debris.config.limits` (the range of every number, and why), which the
commands read as a namespace.
"""

from __future__ import annotations

from casadi_debris.config._checks import TRIANGLE_TOLERANCE, check_inertia, check_transfer_end
from casadi_debris.config._json_schema import problem_schema
from casadi_debris.config._layouts import (
    cubesat_inertia_on_face,
    expand_layout,
    face_axes,
    face_engines,
    signed_axis_vector,
)
from casadi_debris.config._loader import (
    default_controller_path,
    default_problem_path,
    load_problem,
    merge_problem,
    problem_path,
    read_regular_file,
    shipped_problems,
)
from casadi_debris.config._reader import problem_from_dict, problem_with_values
from casadi_debris.config._realism import (
    ESTIMATION_FILTERS,
    Actuators,
    ControllerTiming,
    Estimation,
    EstimationFilter,
    Gyro,
    Sensors,
    StarTracker,
    realism_fields,
)
from casadi_debris.config._runs import run_length_violation, with_duration
from casadi_debris.config._schema import (
    AXIS_NAMES,
    DEFAULT_MONTECARLO,
    DEFAULT_REQUIREMENTS,
    DEFAULT_SIMULATION,
    ENVIRONMENT_TORQUES,
    MODE_KINDS,
    REFERENCE_KINDS,
    SIGNED_AXES,
    Array,
    AxisName,
    Constants,
    CubeSat,
    CubeSatLayout,
    Detumble,
    Disturbance,
    Engine,
    EngineDefaults,
    Environment,
    EnvironmentTorque,
    FailureEvent,
    Hub,
    Mode,
    ModeKind,
    MonteCarlo,
    Orbit,
    Problem,
    ReferenceKind,
    Requirements,
    Sensor,
    SignedAxis,
    Simulation,
    Transfer,
    Uncertainty,
    VariedQuantity,
    Weights,
)
from casadi_debris.config._segments import (
    AXIS_TEXTS,
    BURN_DIRECTIONS,
    EULER_SEQUENCES,
    SEGMENT_KINDS,
    SLEW_METHODS,
    TRACK_FRAMES,
    BurnDirection,
    BurnRequest,
    Segment,
    SegmentKind,
    SlewMethod,
    SlewRequest,
    Target,
    TrackFrame,
    axis_unit_vector,
    slew_about,
)
from casadi_debris.config._varied import key_of, parse_path, with_value

__all__ = [
    "AXIS_NAMES",
    "AXIS_TEXTS",
    "BURN_DIRECTIONS",
    "DEFAULT_MONTECARLO",
    "DEFAULT_REQUIREMENTS",
    "DEFAULT_SIMULATION",
    "ENVIRONMENT_TORQUES",
    "ESTIMATION_FILTERS",
    "EULER_SEQUENCES",
    "MODE_KINDS",
    "REFERENCE_KINDS",
    "SEGMENT_KINDS",
    "SIGNED_AXES",
    "SLEW_METHODS",
    "TRACK_FRAMES",
    "TRIANGLE_TOLERANCE",
    "Actuators",
    "Array",
    "AxisName",
    "BurnDirection",
    "BurnRequest",
    "Constants",
    "ControllerTiming",
    "CubeSat",
    "CubeSatLayout",
    "Detumble",
    "Disturbance",
    "Engine",
    "EngineDefaults",
    "Environment",
    "EnvironmentTorque",
    "Estimation",
    "EstimationFilter",
    "FailureEvent",
    "Gyro",
    "Hub",
    "Mode",
    "ModeKind",
    "MonteCarlo",
    "Orbit",
    "Problem",
    "ReferenceKind",
    "Requirements",
    "Segment",
    "SegmentKind",
    "Sensor",
    "Sensors",
    "SignedAxis",
    "Simulation",
    "SlewMethod",
    "SlewRequest",
    "StarTracker",
    "Target",
    "TrackFrame",
    "Transfer",
    "Uncertainty",
    "VariedQuantity",
    "Weights",
    "axis_unit_vector",
    "check_inertia",
    "check_transfer_end",
    "cubesat_inertia_on_face",
    "default_controller_path",
    "default_problem_path",
    "expand_layout",
    "face_axes",
    "face_engines",
    "key_of",
    "load_problem",
    "merge_problem",
    "parse_path",
    "problem_from_dict",
    "problem_path",
    "problem_schema",
    "problem_with_values",
    "read_regular_file",
    "realism_fields",
    "run_length_violation",
    "shipped_problems",
    "signed_axis_vector",
    "slew_about",
    "with_duration",
    "with_value",
]
