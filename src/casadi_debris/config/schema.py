"""The frozen dataclasses of a validated problem, and the names they use.

Every field carries its unit in its name (``mass_kg``, ``omega_rad_s``);
``problems/paper.toml`` documents every key with its bounds. Instances are built
only by :func:`casadi_debris.config.problem_from_dict` (or
:func:`~casadi_debris.config.load_problem`), which validates them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np

AxisName = Literal["x", "y", "z"]
SignedAxis = Literal["+x", "-x", "+y", "-y", "+z", "-z"]
ModeKind = Literal["bending", "torsion"]
AXIS_NAMES: tuple[AxisName, ...] = ("x", "y", "z")
SIGNED_AXES: tuple[SignedAxis, ...] = ("+x", "-x", "+y", "-y", "+z", "-z")
MODE_KINDS: tuple[ModeKind, ...] = ("bending", "torsion")


@dataclass(frozen=True, eq=False)
class Hub:
    """Rigid centre body of the debris.

    Attributes
    ----------
    mass_kg : float
    size_m : ndarray, shape (3,)
        Edge lengths along x, y, z.
    cog_corner_m : ndarray, shape (3,)
        Centre of gravity in the hub-corner frame.
    inertia_kgm2 : ndarray, shape (3, 3)
        Inertia about the hub CoG, hub axes.
    """

    mass_kg: float
    size_m: np.ndarray
    cog_corner_m: np.ndarray
    inertia_kgm2: np.ndarray


@dataclass(frozen=True, eq=False)
class Mode:
    """One cantilevered (hub-clamped) mode of a solar array.

    Attributes
    ----------
    name : str
    kind : {"bending", "torsion"}
        Bending: out-of-plane deflection along the array normal (Euler–Bernoulli
        cantilever shape of the given order). Torsion: twist about the length
        axis (uniform-shaft cantilever shape of the given order).
    order : int
        1 for the first mode of its kind, 2 for the second, ...
    omega_rad_s : float
        Cantilever natural frequency.
    """

    name: str
    kind: ModeKind
    order: int
    omega_rad_s: float


@dataclass(frozen=True, eq=False)
class Arrays:
    """The (identical) flexible solar arrays.

    Attributes
    ----------
    mass_kg, length_m, width_m : float
        Per array; length along the hinge axis.
    inertia_kgm2 : ndarray, shape (3,)
        Principal inertia about the array's own CoG: length axis, width axis, normal.
    hinges_corner_m : ndarray, shape (n_arrays, 3)
        Hinge (root) points in the hub-corner frame.
    directions : tuple of str
        Axis ("+x" ... "-z") along which each array extends from its hinge.
    angle_deg : float
        Array angle theta_SA about the hinge axis (0: normal along +x, or +y for
        arrays along x).
    damping_ratio : float
    modes : tuple of Mode
    """

    mass_kg: float
    length_m: float
    width_m: float
    inertia_kgm2: np.ndarray
    hinges_corner_m: np.ndarray
    directions: tuple[SignedAxis, ...]
    angle_deg: float
    damping_ratio: float
    modes: tuple[Mode, ...]

    @property
    def count(self) -> int:
        """Number of arrays."""
        return len(self.directions)


@dataclass(frozen=True, eq=False)
class CubeSats:
    """Docked CubeSats (one per face corner).

    Attributes
    ----------
    per_face : int
    mass_kg : float
    inertia_kgm2 : ndarray, shape (3,)
        Principal inertia about the CubeSat CoG (long axis last).
    edge_margin_fraction : float
        Inset from each face edge as a fraction of the half edge length.
    standoff_m : float
        Height of the CubeSat CoG above the face.
    """

    per_face: int
    mass_kg: float
    inertia_kgm2: np.ndarray
    edge_margin_fraction: float
    standoff_m: float


@dataclass(frozen=True, eq=False)
class Engine:
    """Staged ion-electrospray engine of one CubeSat.

    Attributes
    ----------
    stages : int
        1 to 16.
    emitters_per_stage : int
    thrust_per_stage_mN : float
    isp_s : float
    stage_life_h : float
        Firing life of one stage [h]; the propellant of all stages,
        ``stages x thrust x life / (Isp g0)``, must stay below the CubeSat's mass.
    """

    stages: int
    emitters_per_stage: int
    thrust_per_stage_mN: float
    isp_s: float
    stage_life_h: float


@dataclass(frozen=True, eq=False)
class Disturbance:
    """Sine disturbance torque per body axis."""

    amplitude_mNm: np.ndarray
    period_min: float
    phase_deg: np.ndarray


@dataclass(frozen=True, eq=False)
class Sensor:
    """Star tracker as a first-order low pass."""

    star_tracker_bandwidth_rad_s: float


@dataclass(frozen=True, eq=False)
class Uncertainty:
    """Half-ranges of the uncertainty set (relative or absolute as named).

    ``samples`` (1 to 10 000) models fit the uncertainty weight, drawn with
    ``seed`` (0 to 2^32 - 1).
    """

    inertia_fraction: float
    mass_fraction: float
    array_angle_deg: float
    bending_frequency_fraction: float
    samples: int
    seed: int


@dataclass(frozen=True, eq=False)
class Weights:
    """Four-block mixed-sensitivity weights and scalings (paper, Section III)."""

    closed_loop_bandwidth_rad_s: float
    epsilon: float
    control_rolloff_rad_s: float
    control_rolloff_high_frequency_gain: float
    error_scaling_deg: np.ndarray
    control_scaling_mNm: np.ndarray
    disturbance_scaling_mNm: np.ndarray


@dataclass(frozen=True, eq=False)
class Orbit:
    altitude_km: float
    inclination_deg: float


@dataclass(frozen=True, eq=False)
class Transfer:
    from_altitude_km: float
    from_inclination_deg: float
    to_altitude_km: float
    to_inclination_deg: float


@dataclass(frozen=True, eq=False)
class Detumble:
    initial_rate_rad_s: np.ndarray


@dataclass(frozen=True, eq=False)
class Constants:
    earth_mu_km3_s2: float
    earth_radius_km: float
    standard_gravity_m_s2: float


ReferenceKind = Literal["hold", "slew"]
SlewMethod = Literal["bang-bang", "time-optimal", "fuel-optimal"]
REFERENCE_KINDS: tuple[ReferenceKind, ...] = ("hold", "slew")
SLEW_METHODS: tuple[SlewMethod, ...] = ("bang-bang", "time-optimal", "fuel-optimal")


@dataclass(frozen=True, eq=False)
class SlewReference:
    """Rest-to-rest slew commanded to the closed loop (``[simulation.slew]``).

    ``duration_s`` and ``torque_fraction`` are optional (None): the slew
    methods then pick their own (see :mod:`casadi_debris.slew`). With
    ``feedforward`` the profile's torque is added to the controller's demand
    (the paper's loop has none). With ``thrusters`` an optimal slew is solved at
    thruster level with zero net force, as the closed loop's allocator keeps it,
    so that its torque is one the engines can give there.
    """

    axis: AxisName
    angle_deg: float
    method: SlewMethod
    start_s: float
    duration_s: float | None
    torque_fraction: float | None
    feedforward: bool = False
    thrusters: bool = False


@dataclass(frozen=True, eq=False)
class FailureEvent:
    """A CubeSat (or one of its stages) lost at a given time (``[[simulation.failures]]``).

    Indices are 0-based here; the file numbers CubeSats and stages from 1, as
    ``casadi-debris model`` lists them.
    """

    time_s: float
    cubesat: int
    stage: int | None


@dataclass(frozen=True, eq=False)
class Simulation:
    """Closed-loop run: length, sampling, reference and failures (``[simulation]``).

    Attributes
    ----------
    duration_s : float
        Simulated time [s], (0, 1e7], and 1 to 1e6 control periods.
    control_rate_hz : float
        Controller and allocator rate [Hz], 0.01 to 1000.
    integrator_steps : int
        Runge-Kutta steps per control period, 1 to 1000, short enough for the
        fastest dynamics (step x rate <= 2) and at most 1e7 in the run.
    reference : {"hold", "slew"}
    slew : SlewReference or None
        Given exactly when ``reference`` is ``"slew"``.
    failures : tuple of FailureEvent
        By time, at most 1000.

    The ranges and why are in :mod:`casadi_debris.config.limits`.
    """

    duration_s: float
    control_rate_hz: float
    integrator_steps: int
    reference: ReferenceKind
    slew: SlewReference | None
    failures: tuple[FailureEvent, ...]


@dataclass(frozen=True, eq=False)
class MonteCarlo:
    """Corner and random cases of the uncertainty set (``[montecarlo]``).

    The corners combine the two extremes of every relative uncertainty
    (inertia per axis, mass, first bending frequency) with
    ``corner_array_angles`` array angles spread evenly over the angle range
    (the +-180 deg extremes are one and the same attitude of the arrays).

    Attributes
    ----------
    corner_array_angles : int
        1 to 64 (2^5 x 64 = 2048 corner cases at most).
    samples : int
        Random cases when a campaign gives no count, 1 to 100 000.
    seed : int
        0 to 2^32 - 1.
    """

    corner_array_angles: int
    samples: int
    seed: int


DEFAULT_SIMULATION = {
    "duration_s": 5908.0,
    "control_rate_hz": 10.0,
    "integrator_steps": 4,
    "reference": "hold",
}
DEFAULT_MONTECARLO = {"corner_array_angles": 8, "samples": 100, "seed": 1}


@dataclass(frozen=True, eq=False)
class Problem:
    """A whole validated scenario. See ``problems/paper.toml`` for every key.

    ``name`` is a label (it names output folders): a letter or digit, then at
    most 63 letters, digits, ``.``, ``_`` or ``-``. Every number lies in its
    range of :mod:`casadi_debris.config.limits`.
    """

    name: str
    description: str
    hub: Hub
    arrays: Arrays
    cubesats: CubeSats
    engine: Engine
    disturbance: Disturbance
    sensor: Sensor
    uncertainty: Uncertainty
    weights: Weights
    orbit: Orbit
    transfer: Transfer
    detumble: Detumble
    constants: Constants
    simulation: Simulation = field(default=None)  # type: ignore[assignment]
    montecarlo: MonteCarlo = field(default=None)  # type: ignore[assignment]
    source: str = field(default="<dict>")
    sha256: str = field(default="")
