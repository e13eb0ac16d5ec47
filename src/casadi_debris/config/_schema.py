"""The frozen dataclasses of a validated problem, and the names they use.

Every field carries its unit in its name (``mass_kg``, ``omega_rad_s``);
``problems/paper.toml`` documents every key with its bounds. Instances are built
only by :func:`casadi_debris.config.problem_from_dict` (or
:func:`~casadi_debris.config.load_problem`), which validates them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from casadi_debris.config._identity import plant_sha256
from casadi_debris.config._realism import Actuators, ControllerTiming, Estimation, Sensors
from casadi_debris.config._segments import Segment, SlewRequest
from casadi_debris.units import MN_PER_N, SECONDS_PER_HOUR

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
class Array:
    """One flexible appendage (a solar array), cantilevered at its hinge (``[[arrays]]``).

    Attributes
    ----------
    hinge_corner_m : ndarray, shape (3,)
        Hinge (root) point in the hub-corner frame, on the hub's surface.
    direction : ndarray, shape (3,)
        Unit vector along which the array extends from its hinge (outward).
    mass_kg, length_m, width_m : float
        Length along ``direction``.
    inertia_kgm2 : ndarray, shape (3,)
        Principal inertia about the array's own CoG: length axis, width axis, normal.
    angle_deg : float
        Angle theta_SA about the hinge axis (0: normal along the hub axis after
        the array's main axis in cyclic order, +x for arrays along z).
    damping_ratio : float
    modes : tuple of Mode
        Cantilever modes (none: a rigid appendage).
    """

    hinge_corner_m: np.ndarray
    direction: np.ndarray
    mass_kg: float
    length_m: float
    width_m: float
    inertia_kgm2: np.ndarray
    angle_deg: float
    damping_ratio: float
    modes: tuple[Mode, ...]


@dataclass(frozen=True, eq=False)
class Engine:
    """One staged ion-electrospray engine of a CubeSat (``[[cubesats.engines]]``).

    Attributes
    ----------
    direction : ndarray, shape (3,)
        Unit vector, body axes: the force the engine exerts on the body.
    offset_m : ndarray, shape (3,)
        Engine point relative to its CubeSat's CoG (where the force acts).
    stages : int
    emitters_per_stage : int
    thrust_per_stage_mN : float
    isp_s : float
    stage_life_h : float
        Firing life of one stage [h]; the propellant of all the CubeSat's
        engines and stages (``stages x thrust x life / (Isp g0)`` each) must stay
        below the CubeSat's mass.
    """

    direction: np.ndarray
    offset_m: np.ndarray
    stages: int
    emitters_per_stage: int
    thrust_per_stage_mN: float
    isp_s: float
    stage_life_h: float

    def stage_propellant_kg(self, standard_gravity_m_s2: float) -> float:
        """Propellant one stage burns over its life: thrust x life / (Isp g0) [kg].

        The one statement of a stage's load: the loader's propellant check, the
        propulsion state's capacities and the budgets all take it from here.
        """
        thrust_N = self.thrust_per_stage_mN / MN_PER_N
        life_s = self.stage_life_h * SECONDS_PER_HOUR
        return thrust_N * life_s / (self.isp_s * standard_gravity_m_s2)


@dataclass(frozen=True, eq=False)
class EngineDefaults:
    """``[engine]``: what an engine that does not say otherwise has."""

    stages: int
    emitters_per_stage: int
    thrust_per_stage_mN: float
    isp_s: float
    stage_life_h: float


@dataclass(frozen=True, eq=False)
class CubeSat:
    """One docked CubeSat (``[[cubesats]]``, or generated by ``[cubesat_layout]``).

    Attributes
    ----------
    position_corner_m : ndarray, shape (3,)
        CoG in the hub-corner frame.
    mass_kg : float
    inertia_kgm2 : ndarray, shape (3, 3)
        Inertia about its own CoG, body axes.
    face : str or None
        Signed axis of the hub face it docks on (outward normal), if given.
    engines : tuple of Engine
    """

    position_corner_m: np.ndarray
    mass_kg: float
    inertia_kgm2: np.ndarray
    face: SignedAxis | None
    engines: tuple[Engine, ...]


LayoutKind = Literal["face_corners", "face_grid"]
LAYOUT_KINDS: tuple[LayoutKind, ...] = ("face_corners", "face_grid")


@dataclass(frozen=True, eq=False)
class CubeSatLayout:
    """``[cubesat_layout]``: a generator of the CubeSat list.

    Attributes
    ----------
    kind : {"face_corners", "face_grid"}
        ``face_corners``: four per face, one near each corner (the paper's).
        ``face_grid``: ``per_face`` on a grid of cells filling each face.
    faces : tuple of str
        The faces used, in order (CubeSats are numbered face by face).
    per_face : int
    edge_margin_fraction : float
        Inset from each face edge as a fraction of the half edge length.
    standoff_m : float
        Height of the CubeSat CoG above the face.
    mass_kg : float
    inertia_kgm2 : ndarray, shape (3,)
        Principal inertia about the CubeSat's CoG in its own axes: x along the
        face normal, z (long) along the face axis after the normal in cyclic
        order.
    main_engine : bool
        An engine pushing along the face's inward normal.
    side_engines : int
        0, 2 or 4 engines on the side panels, pushing along the face's plane
        (2: both ways along the first in-face axis after the normal in cyclic
        order; 4: both in-face axes).
    """

    kind: LayoutKind
    faces: tuple[SignedAxis, ...]
    per_face: int
    edge_margin_fraction: float
    standoff_m: float
    mass_kg: float
    inertia_kgm2: np.ndarray
    main_engine: bool
    side_engines: int


@dataclass(frozen=True, eq=False)
class Requirements:
    """``[requirements]``: what the controller must achieve.

    Attributes
    ----------
    pointing_arcsec : float
        Largest pointing error while holding an attitude [arcsec].
    slew_error_deg : float
        Largest attitude error during a slew [deg].
    """

    pointing_arcsec: float
    slew_error_deg: float


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
    ``seed`` (0 to 2^32 - 1). With ``independent_array_angles`` every array's angle
    is its own uncertain parameter (default: one angle offset for all arrays).
    """

    inertia_fraction: float
    mass_fraction: float
    array_angle_deg: float
    bending_frequency_fraction: float
    samples: int
    seed: int
    independent_array_angles: bool = False


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
    """The debris' circular orbit (``[orbit]``).

    Attributes
    ----------
    altitude_km : float
        Above the equatorial radius of ``[constants]``.
    inclination_deg : float
    raan_deg : float
        Right ascension of the ascending node (default 0: the node on the
        vernal equinox).
    argument_of_latitude_deg : float
        Angle from the ascending node to the debris at t = 0 (default 0).
    """

    altitude_km: float
    inclination_deg: float
    raan_deg: float = 0.0
    argument_of_latitude_deg: float = 0.0


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


EnvironmentTorque = Literal["gravity_gradient", "aerodynamic", "solar_pressure", "magnetic"]
ENVIRONMENT_TORQUES: tuple[EnvironmentTorque, ...] = (
    "gravity_gradient",
    "aerodynamic",
    "solar_pressure",
    "magnetic",
)


@dataclass(frozen=True, eq=False)
class Environment:
    """Disturbance torques from the orbit (``[environment]``), added to ``[disturbance]``.

    None act unless listed in ``torques`` (the paper's runs have none). The
    equations are in :mod:`casadi_debris.environment`.

    Attributes
    ----------
    torques : tuple of str
        Which act: ``gravity_gradient``, ``aerodynamic``, ``solar_pressure``,
        ``magnetic``.
    density_kg_m3 : float
        Air density along the orbit (constant; 1e-13 by default, between solar
        minimum and maximum at 685 km).
    drag_coefficient : float
        C_D of every panel (2.2).
    solar_pressure_N_m2 : float
        Radiation pressure of the sunlight (4.56e-6 at 1 AU).
    specular_reflectivity, diffuse_reflectivity : float
        Fractions of the light reflected (0.1, 0.2); the rest is absorbed.
    sun_longitude_deg : float
        Ecliptic longitude of the Sun at t = 0 (0: vernal equinox).
    eclipse : bool
        Whether the Earth's cylindrical shadow switches the sunlight off.
    residual_dipole_Am2 : ndarray, shape (3,)
        The debris' residual magnetic dipole, body axes ([0, 0, 1]).
    field_equator_T : float
        The Earth's dipole field at the equator's surface (2.98e-5, IGRF 2020).
    dipole_tilt_deg, dipole_longitude_deg : float
        Colatitude (9.41) and east longitude (-72.68) of the dipole's northern
        pole (0 tilt: the field aligned with the spin axis).
    greenwich_angle_deg : float
        Angle of the Greenwich meridian from the vernal equinox at t = 0.
    """

    torques: tuple[EnvironmentTorque, ...] = ()
    density_kg_m3: float = 1e-13
    drag_coefficient: float = 2.2
    solar_pressure_N_m2: float = 4.56e-6
    specular_reflectivity: float = 0.1
    diffuse_reflectivity: float = 0.2
    sun_longitude_deg: float = 0.0
    eclipse: bool = True
    residual_dipole_Am2: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    field_equator_T: float = 2.98e-5
    dipole_tilt_deg: float = 9.41
    dipole_longitude_deg: float = -72.68
    greenwich_angle_deg: float = 0.0

    def acts(self, torque: EnvironmentTorque) -> bool:
        """Whether ``torque`` is switched on."""
        return torque in self.torques


ReferenceKind = Literal["hold", "slew", "sequence"]
REFERENCE_KINDS: tuple[ReferenceKind, ...] = ("hold", "slew", "sequence")


@dataclass(frozen=True, eq=False)
class FailureEvent:
    """A CubeSat, one of its stages or one of its engines lost at a given time
    (``[[simulation.failures]]``).

    Indices are 0-based here; the file numbers CubeSats, stages and engines from 1,
    ``engine`` counting the CubeSat's own engines in the order the problem lists
    them (``cubesat_engine`` in ``casadi-debris model --json``).
    """

    time_s: float
    cubesat: int
    stage: int | None
    engine: int | None = None


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
    reference : {"hold", "slew", "sequence"}
    slew : SlewRequest or None
        Given exactly when ``reference`` is ``"slew"``: a turn about a body axis,
        starting at ``slew.start_s``.
    failures : tuple of FailureEvent
        By time, at most 1000.
    segments : tuple of Segment
        ``[[simulation.segments]]``, given exactly when ``reference`` is
        ``"sequence"`` (see :mod:`casadi_debris.config._segments`).

    The ranges and why are in :mod:`casadi_debris.config.limits`.
    """

    duration_s: float
    control_rate_hz: float
    integrator_steps: int
    reference: ReferenceKind
    slew: SlewRequest | None
    failures: tuple[FailureEvent, ...]
    segments: tuple[Segment, ...] = ()


Distribution = Literal["uniform", "normal", "corners"]
DISTRIBUTIONS: tuple[Distribution, ...] = ("uniform", "normal", "corners")


@dataclass(frozen=True, eq=False)
class VariedQuantity:
    """One quantity a Monte-Carlo campaign varies (``[[montecarlo.vary]]``).

    Attributes
    ----------
    path : str
        What varies: a model parameter by name (``mass_kg``,
        ``inertia_scale_x``, ``array_angle_offset_rad``,
        ``bending_frequency_scale``), varied in the compiled step at no cost;
        or a dotted key of the problem file (``environment.density_kg_m3``,
        ``disturbance.amplitude_mNm[2]``, ``arrays[0].mass_kg``; indices from
        0 as in the loader's messages), for which every case rebuilds its problem.
    distribution : {"uniform", "normal", "corners"}
        ``uniform`` between ``low`` and ``high``; ``normal`` of ``mean`` and
        ``sigma``, truncated to ``[low, high]`` (default: the key's allowed
        range); ``corners``: ``low`` or ``high``, every combination with the
        other corner quantities.
    low, high : float or None
        In the key's unit.
    mean, sigma : float or None
        Of a normal distribution, in the key's unit.
    """

    path: str
    distribution: Distribution
    low: float | None = None
    high: float | None = None
    mean: float | None = None
    sigma: float | None = None

    @property
    def is_parameter(self) -> bool:
        """A model parameter (no dot, no index), varied without rebuilding the problem."""
        return "." not in self.path and "[" not in self.path


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
    vary : tuple of VariedQuantity
        What a campaign varies, and how (none: the uncertainty set's corners
        or uniform samples in it).
    """

    corner_array_angles: int
    samples: int
    seed: int
    vary: tuple[VariedQuantity, ...] = ()


DEFAULT_SIMULATION = {
    "duration_s": 5908.0,
    "control_rate_hz": 10.0,
    "integrator_steps": 4,
    "reference": "hold",
}
DEFAULT_MONTECARLO = {"corner_array_angles": 8, "samples": 100, "seed": 1}
# The paper's requirements: 60 arcsec pointing, 0.6 deg during a slew.
DEFAULT_REQUIREMENTS = {"pointing_arcsec": 60.0, "slew_error_deg": 0.6}


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
    arrays: tuple[Array, ...]
    cubesats: tuple[CubeSat, ...]
    cubesat_layout: CubeSatLayout | None
    engine: EngineDefaults
    requirements: Requirements
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
    environment: Environment = field(default_factory=Environment)
    sensors: Sensors = field(default_factory=Sensors)
    estimation: Estimation = field(default_factory=Estimation)
    actuators: Actuators = field(default_factory=Actuators)
    controller: ControllerTiming = field(default_factory=ControllerTiming)
    source: str = field(default="<dict>")
    sha256: str = field(default="")
    # The tables as read (after ``extends``): a campaign that varies a key rebuilds from them.
    data: Mapping[str, Any] = field(default_factory=dict, repr=False)

    @property
    def plant_sha256(self) -> str:
        """Hash of the plant this problem describes (what a controller is designed for).

        See :mod:`casadi_debris.config._identity`.
        """
        return plant_sha256(self)

    @property
    def engines(self) -> tuple[Engine, ...]:
        """Every engine, CubeSat by CubeSat."""
        return tuple(engine for cubesat in self.cubesats for engine in cubesat.engines)

    @property
    def engine_cubesats(self) -> tuple[int, ...]:
        """The CubeSat (0-based) of each engine of :attr:`engines`."""
        return tuple(i for i, cubesat in enumerate(self.cubesats) for _ in cubesat.engines)
