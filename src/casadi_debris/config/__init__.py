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

Modules: :mod:`~casadi_debris.config.schema` (the frozen dataclasses),
:mod:`~casadi_debris.config.limits` (the range of every number, and why),
:mod:`~casadi_debris.config.table` (the typed table reader),
:mod:`~casadi_debris.config.checks` (physical checks),
:mod:`~casadi_debris.config.bodies` and :mod:`~casadi_debris.config.runs` (the
readers of the debris and swarm tables, and of the run tables),
:mod:`~casadi_debris.config.reader` (:func:`problem_from_dict` and the checks
across tables) and :mod:`~casadi_debris.config.loader` (files and ``extends``).
"""

from __future__ import annotations

from casadi_debris.config.checks import TRIANGLE_TOLERANCE, check_inertia
from casadi_debris.config.layouts import signed_axis_vector
from casadi_debris.config.loader import (
    default_controller_path,
    default_problem_path,
    load_problem,
    problem_path,
    shipped_problems,
)
from casadi_debris.config.reader import problem_from_dict, problem_with_values
from casadi_debris.config.realism import (
    ESTIMATION_FILTERS,
    Actuators,
    ControllerTiming,
    Estimation,
    EstimationFilter,
    Gyro,
    Sensors,
    StarTracker,
)
from casadi_debris.config.runs import with_duration
from casadi_debris.config.schema import (
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
from casadi_debris.config.segments import (
    BURN_DIRECTIONS,
    SEGMENT_KINDS,
    SLEW_METHODS,
    TRACK_FRAMES,
    BurnDirection,
    BurnSettings,
    Segment,
    SegmentKind,
    SlewMethod,
    SlewReference,
    SlewSettings,
    Target,
    TrackFrame,
)

__all__ = [
    "AXIS_NAMES",
    "BURN_DIRECTIONS",
    "DEFAULT_MONTECARLO",
    "DEFAULT_REQUIREMENTS",
    "DEFAULT_SIMULATION",
    "ENVIRONMENT_TORQUES",
    "ESTIMATION_FILTERS",
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
    "BurnSettings",
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
    "SlewReference",
    "SlewSettings",
    "StarTracker",
    "Target",
    "TrackFrame",
    "Transfer",
    "Uncertainty",
    "VariedQuantity",
    "Weights",
    "check_inertia",
    "default_controller_path",
    "default_problem_path",
    "load_problem",
    "problem_from_dict",
    "problem_path",
    "problem_with_values",
    "shipped_problems",
    "signed_axis_vector",
    "with_duration",
]
