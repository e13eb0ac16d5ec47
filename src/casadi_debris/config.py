"""Problem parameters: frozen dataclasses loaded from TOML and validated.

A problem file holds every number of a scenario with its unit in the key name
(``mass_kg``, ``omega_rad_s``). :func:`load_problem` reads one (default: the
shipped ``problems/paper.toml``), checks every key and returns a
:class:`Problem`. Nothing downstream reads a file.

A problem file may start from another one with ``extends = "paper.toml"``
(path relative to the file): its tables are merged key by key, arrays and
scalars replaced whole.

Example
-------
>>> from casadi_debris import load_problem
>>> problem = load_problem()
>>> problem.hub.mass_kg
500.0
"""

from __future__ import annotations

import hashlib
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.errors import ProblemFileError

AXIS_NAMES = ("x", "y", "z")
SIGNED_AXES = ("+x", "-x", "+y", "-y", "+z", "-z")
MODE_KINDS = ("bending", "torsion")
TRIANGLE_TOLERANCE = 0.02


def _frozen_array(values: Any) -> np.ndarray:
    array = np.array(values, dtype=float)
    array.flags.writeable = False
    return array


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
    kind: str
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
    directions: tuple[str, ...]
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
    """Staged ion-electrospray engine of one CubeSat."""

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
    """Half-ranges of the uncertainty set (relative or absolute as named)."""

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


REFERENCE_KINDS = ("hold", "slew")
SLEW_METHODS = ("bang-bang", "time-optimal", "fuel-optimal")


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

    axis: str
    angle_deg: float
    method: str
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
    """Closed-loop run: length, sampling, reference and failures (``[simulation]``)."""

    duration_s: float
    control_rate_hz: float
    integrator_steps: int
    reference: str
    slew: SlewReference | None
    failures: tuple[FailureEvent, ...]


@dataclass(frozen=True, eq=False)
class MonteCarlo:
    """Corner and random cases of the uncertainty set (``[montecarlo]``).

    The corners combine the two extremes of every relative uncertainty
    (inertia per axis, mass, first bending frequency) with
    ``corner_array_angles`` array angles spread evenly over the angle range
    (the +-180 deg extremes are one and the same attitude of the arrays).
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
    """A whole validated scenario. See ``problems/paper.toml`` for every key."""

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


# --------------------------------------------------------------------------- reading


class _Table:
    """Reads one TOML table, naming the dotted key in every error.

    Every key must be taken exactly once; :meth:`done` rejects the rest.
    """

    def __init__(self, data: Any, path: str, source: str | None) -> None:
        self.path = path
        self.source = source
        if not isinstance(data, Mapping):
            raise self.error(path or "<top level>", "must be a table")
        self.data = data
        self.taken: set[str] = set()

    def key(self, name: str) -> str:
        return f"{self.path}.{name}" if self.path else name

    def error(self, key: str, message: str) -> ProblemFileError:
        return ProblemFileError(key, message, self.source)

    def raw(self, name: str) -> Any:
        self.taken.add(name)
        if name not in self.data:
            raise self.error(self.key(name), "missing")
        return self.data[name]

    def table(self, name: str) -> _Table:
        return _Table(self.raw(name), self.key(name), self.source)

    def tables(self, name: str) -> list[_Table]:
        value = self.raw(name)
        if not isinstance(value, list) or not value:
            raise self.error(self.key(name), "must be a non-empty array of tables")
        return [_Table(v, f"{self.key(name)}[{i}]", self.source) for i, v in enumerate(value)]

    def text(self, name: str, choices: tuple[str, ...] | None = None) -> str:
        value = self.raw(name)
        if not isinstance(value, str):
            raise self.error(self.key(name), f"must be a string, got {value!r}")
        if choices is not None and value not in choices:
            raise self.error(self.key(name), f"must be one of {', '.join(choices)}; got {value!r}")
        return value

    def texts(self, name: str, choices: tuple[str, ...]) -> tuple[str, ...]:
        value = self.raw(name)
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            raise self.error(self.key(name), "must be an array of strings")
        for v in value:
            if v not in choices:
                raise self.error(self.key(name), f"entries must be among {', '.join(choices)}")
        return tuple(value)

    def boolean(self, name: str) -> bool:
        value = self.raw(name)
        if not isinstance(value, bool):
            raise self.error(self.key(name), f"must be true or false, got {value!r}")
        return value

    def integer(self, name: str, minimum: int | None = None) -> int:
        value = self.raw(name)
        if isinstance(value, bool) or not isinstance(value, int):
            raise self.error(self.key(name), f"must be an integer, got {value!r}")
        if minimum is not None and value < minimum:
            raise self.error(self.key(name), f"must be at least {minimum}, got {value}")
        return value

    def number(
        self,
        name: str,
        *,
        positive: bool = False,
        nonnegative: bool = False,
        below: float | None = None,
        at_most: float | None = None,
    ) -> float:
        return float(
            self.array(
                name,
                (),
                positive=positive,
                nonnegative=nonnegative,
                below=below,
                at_most=at_most,
            )
        )

    def array(
        self,
        name: str,
        shape: tuple[int | None, ...],
        *,
        positive: bool = False,
        nonnegative: bool = False,
        below: float | None = None,
        at_most: float | None = None,
    ) -> np.ndarray:
        """A number (shape ``()``) or nested list of numbers of the given shape."""
        key = self.key(name)
        value = self.raw(name)
        try:
            array = np.array(value, dtype=float)
        except (TypeError, ValueError):
            raise self.error(key, f"must be numbers of shape {shape}, got {value!r}") from None
        if isinstance(value, bool) or _has_bool(value):
            raise self.error(key, "must be numbers, not true/false")
        if array.ndim != len(shape) or any(
            s is not None and s != n for s, n in zip(shape, array.shape, strict=True)
        ):
            want = "a number" if not shape else f"shape {tuple(s or 'n' for s in shape)}"
            raise self.error(key, f"must be {want}, got shape {array.shape}")
        if not np.all(np.isfinite(array)):
            raise self.error(key, "must be finite (no NaN or inf)")
        if positive and np.any(array <= 0):
            raise self.error(key, f"must be positive, got {value!r}")
        if nonnegative and np.any(array < 0):
            raise self.error(key, f"must not be negative, got {value!r}")
        if below is not None and np.any(array >= below):
            raise self.error(key, f"must be below {below}, got {value!r}")
        if at_most is not None and np.any(array > at_most):
            raise self.error(key, f"must be at most {at_most}, got {value!r}")
        return _frozen_array(array)

    def done(self) -> None:
        unknown = sorted(set(self.data) - self.taken)
        if unknown:
            raise self.error(self.key(unknown[0]), "unknown key")


def _has_bool(value: Any) -> bool:
    if isinstance(value, bool):
        return True
    if isinstance(value, list):
        return any(_has_bool(v) for v in value)
    return False


def check_inertia(inertia: np.ndarray, key: str, source: str | None = None) -> None:
    """Raise unless ``inertia`` is a physical rigid-body inertia.

    Parameters
    ----------
    inertia : ndarray, shape (3, 3) or (3,)
        Full matrix, or principal moments [kg m^2].
    key : str
        Dotted name for the message.

    Raises
    ------
    ProblemFileError
        Not symmetric, not positive definite, or principal moments violating
        the triangle inequality (I1 <= I2 + I3 for every permutation) by more
        than ``TRIANGLE_TOLERANCE``: a thin plate sits on the equality, and
        published values are rounded (the paper's array, 80 > 17 + 62, is one).
    """
    matrix = np.diag(inertia) if inertia.ndim == 1 else inertia
    scale = float(np.max(np.abs(matrix)))
    if not np.allclose(matrix, matrix.T, rtol=0.0, atol=1e-9 * scale):
        raise ProblemFileError(key, "inertia must be symmetric", source)
    moments = np.linalg.eigvalsh(matrix)
    if moments[0] <= 0:
        raise ProblemFileError(
            key, f"inertia must be positive definite (principal moments {moments})", source
        )
    if moments[2] > (moments[0] + moments[1]) * (1.0 + TRIANGLE_TOLERANCE):
        raise ProblemFileError(
            key,
            "principal moments violate the triangle inequality "
            f"({moments[2]:.4g} > {moments[0]:.4g} + {moments[1]:.4g})",
            source,
        )


def _read_hub(t: _Table) -> Hub:
    size = t.array("size_m", (3,), positive=True)
    cog = t.array("cog_corner_m", (3,))
    if np.any(cog < 0) or np.any(cog > size):
        raise t.error(t.key("cog_corner_m"), f"must lie inside the hub (0 .. {list(size)} m)")
    inertia = t.array("inertia_kgm2", (3, 3))
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    hub = Hub(t.number("mass_kg", positive=True), size, cog, inertia)
    t.done()
    return hub


def _read_mode(t: _Table) -> Mode:
    mode = Mode(
        name=t.text("name"),
        kind=t.text("kind", MODE_KINDS),
        order=t.integer("order", minimum=1),
        omega_rad_s=t.number("omega_rad_s", positive=True),
    )
    t.done()
    return mode


def _read_arrays(t: _Table, hub_size: np.ndarray) -> Arrays:
    inertia = t.array("inertia_kgm2", (3,), positive=True)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    hinges = t.array("hinges_corner_m", (None, 3))
    directions = t.texts("directions", SIGNED_AXES)
    if len(directions) != len(hinges):
        raise t.error(
            t.key("directions"), f"needs one entry per hinge ({len(hinges)}), got {len(directions)}"
        )
    for i, (hinge, direction) in enumerate(zip(hinges, directions, strict=True)):
        _check_on_face(t, f"hinges_corner_m[{i}]", hinge, direction, hub_size)
    modes = tuple(_read_mode(m) for m in t.tables("modes"))
    names = [m.name for m in modes]
    if len(set(names)) != len(names):
        raise t.error(t.key("modes"), f"mode names must be unique, got {names}")
    kinds_orders = [(m.kind, m.order) for m in modes]
    if len(set(kinds_orders)) != len(kinds_orders):
        raise t.error(t.key("modes"), "two modes have the same kind and order")
    if ("bending", 1) not in kinds_orders:
        raise t.error(t.key("modes"), "needs the first bending mode (kind bending, order 1)")
    arrays = Arrays(
        mass_kg=t.number("mass_kg", positive=True),
        length_m=t.number("length_m", positive=True),
        width_m=t.number("width_m", positive=True),
        inertia_kgm2=inertia,
        hinges_corner_m=hinges,
        directions=directions,
        angle_deg=t.number("angle_deg"),
        damping_ratio=t.number("damping_ratio", nonnegative=True, below=1.0),
        modes=modes,
    )
    t.done()
    return arrays


def _check_on_face(
    t: _Table, name: str, point: np.ndarray, direction: str, hub_size: np.ndarray
) -> None:
    """A hinge must sit on the hub face whose outward normal is its array's direction."""
    axis = AXIS_NAMES.index(direction[1])
    face = hub_size[axis] if direction[0] == "+" else 0.0
    tolerance = 1e-9 * float(np.max(hub_size))
    others = [a for a in range(3) if a != axis]
    on_face = abs(point[axis] - face) <= tolerance and all(
        -tolerance <= point[a] <= hub_size[a] + tolerance for a in others
    )
    if not on_face:
        raise t.error(
            f"{t.path}.{name}",
            f"{list(point)} m is not on the hub face {direction} "
            f"(hub spans 0 .. {list(hub_size)} m); an array extends outward from its face",
        )


def _read_cubesats(t: _Table) -> CubeSats:
    inertia = t.array("inertia_kgm2", (3,), positive=True)
    check_inertia(inertia, t.key("inertia_kgm2"), t.source)
    per_face = t.integer("per_face", minimum=1)
    if per_face != 4:
        raise t.error(t.key("per_face"), f"only the corner layout (4) is supported, got {per_face}")
    cubesats = CubeSats(
        per_face=per_face,
        mass_kg=t.number("mass_kg", positive=True),
        inertia_kgm2=inertia,
        edge_margin_fraction=t.number("edge_margin_fraction", nonnegative=True, below=1.0),
        standoff_m=t.number("standoff_m", nonnegative=True),
    )
    t.done()
    return cubesats


def _read_engine(t: _Table) -> Engine:
    engine = Engine(
        stages=t.integer("stages", minimum=1),
        emitters_per_stage=t.integer("emitters_per_stage", minimum=1),
        thrust_per_stage_mN=t.number("thrust_per_stage_mN", positive=True),
        isp_s=t.number("isp_s", positive=True),
        stage_life_h=t.number("stage_life_h", positive=True),
    )
    t.done()
    return engine


def _read_disturbance(t: _Table) -> Disturbance:
    disturbance = Disturbance(
        amplitude_mNm=t.array("amplitude_mNm", (3,), nonnegative=True),
        period_min=t.number("period_min", positive=True),
        phase_deg=t.array("phase_deg", (3,)),
    )
    t.done()
    return disturbance


def _read_sensor(t: _Table) -> Sensor:
    sensor = Sensor(t.number("star_tracker_bandwidth_rad_s", positive=True))
    t.done()
    return sensor


def _read_uncertainty(t: _Table) -> Uncertainty:
    uncertainty = Uncertainty(
        inertia_fraction=t.number("inertia_fraction", nonnegative=True, below=1.0),
        mass_fraction=t.number("mass_fraction", nonnegative=True, below=1.0),
        array_angle_deg=t.number("array_angle_deg", nonnegative=True, at_most=180.0),
        bending_frequency_fraction=t.number(
            "bending_frequency_fraction", nonnegative=True, below=1.0
        ),
        samples=t.integer("samples", minimum=1),
        seed=t.integer("seed", minimum=0),
    )
    t.done()
    return uncertainty


def _read_weights(t: _Table) -> Weights:
    weights = Weights(
        closed_loop_bandwidth_rad_s=t.number("closed_loop_bandwidth_rad_s", positive=True),
        epsilon=t.number("epsilon", positive=True, below=1.0),
        control_rolloff_rad_s=t.number("control_rolloff_rad_s", positive=True),
        control_rolloff_high_frequency_gain=t.number(
            "control_rolloff_high_frequency_gain", positive=True, below=1.0
        ),
        error_scaling_deg=t.array("error_scaling_deg", (3,), positive=True),
        control_scaling_mNm=t.array("control_scaling_mNm", (3,), positive=True),
        disturbance_scaling_mNm=t.array("disturbance_scaling_mNm", (3,), positive=True),
    )
    t.done()
    return weights


def _read_slew(t: _Table) -> SlewReference:
    axis = t.text("axis", AXIS_NAMES)
    slew = SlewReference(
        axis=axis,
        angle_deg=t.number("angle_deg", positive=True, at_most=180.0),
        method=t.text("method", SLEW_METHODS) if "method" in t.data else "bang-bang",
        start_s=t.number("start_s", nonnegative=True) if "start_s" in t.data else 0.0,
        duration_s=t.number("duration_s", positive=True) if "duration_s" in t.data else None,
        torque_fraction=(
            t.number("torque_fraction", positive=True, at_most=1.0)
            if "torque_fraction" in t.data
            else None
        ),
        feedforward=t.boolean("feedforward") if "feedforward" in t.data else False,
        thrusters=t.boolean("thrusters") if "thrusters" in t.data else False,
    )
    if slew.method == "fuel-optimal" and slew.duration_s is None:
        raise t.error(t.key("duration_s"), "missing: a fuel-optimal slew needs its duration")
    if slew.thrusters and slew.method == "bang-bang":
        raise t.error(
            t.key("thrusters"), "only for time-optimal and fuel-optimal slews (not bang-bang)"
        )
    t.done()
    return slew


def _read_failure(t: _Table, n_cubesats: int, n_stages: int) -> FailureEvent:
    cubesat = t.integer("cubesat", minimum=1)
    if cubesat > n_cubesats:
        raise t.error(t.key("cubesat"), f"CubeSats are numbered 1 to {n_cubesats}; got {cubesat}")
    stage = t.integer("stage", minimum=1) if "stage" in t.data else None
    if stage is not None and stage > n_stages:
        raise t.error(t.key("stage"), f"stages are numbered 1 to {n_stages}; got {stage}")
    event = FailureEvent(
        time_s=t.number("time_s", nonnegative=True),
        cubesat=cubesat - 1,
        stage=None if stage is None else stage - 1,
    )
    t.done()
    return event


def _read_simulation(t: _Table, n_cubesats: int, n_stages: int) -> Simulation:
    reference = t.text("reference", REFERENCE_KINDS)
    has_slew = "slew" in t.data
    if reference == "slew" and not has_slew:
        raise t.error(t.key("slew"), 'missing: reference = "slew" needs a [simulation.slew] table')
    if reference == "hold" and has_slew:
        raise t.error(t.key("slew"), 'only allowed with reference = "slew"')
    simulation = Simulation(
        duration_s=t.number("duration_s", positive=True),
        control_rate_hz=t.number("control_rate_hz", positive=True),
        integrator_steps=t.integer("integrator_steps", minimum=1),
        reference=reference,
        slew=_read_slew(t.table("slew")) if has_slew else None,
        failures=tuple(
            sorted(
                (_read_failure(f, n_cubesats, n_stages) for f in t.tables("failures")),
                key=lambda event: event.time_s,
            )
        )
        if "failures" in t.data
        else (),
    )
    t.done()
    return simulation


def _read_montecarlo(t: _Table) -> MonteCarlo:
    montecarlo = MonteCarlo(
        corner_array_angles=t.integer("corner_array_angles", minimum=1),
        samples=t.integer("samples", minimum=1),
        seed=t.integer("seed", minimum=0),
    )
    t.done()
    return montecarlo


def _optional_table(top: _Table, name: str, defaults: Mapping[str, Any]) -> _Table:
    """The table ``name`` with missing keys taken from ``defaults`` (absent table: all)."""
    given = top.data.get(name, {})
    top.taken.add(name)
    if not isinstance(given, Mapping):
        raise top.error(top.key(name), "must be a table")
    return _Table({**defaults, **given}, top.key(name), top.source)


def _read_simple(t: _Table, cls: type, names: tuple[str, ...], **checks: Any) -> Any:
    value = cls(*(t.number(n, **checks) for n in names))
    t.done()
    return value


def problem_from_dict(
    data: Mapping[str, Any], source: str | None = None, sha256: str = ""
) -> Problem:
    """Validate a parsed problem (as from TOML) and return it frozen.

    Parameters
    ----------
    data : mapping
        The problem's tables, as :func:`tomllib.load` returns them.
    source : str, optional
        Where it came from, for messages.
    sha256 : str, optional
        Hash of the file's bytes, recorded with results.

    Raises
    ------
    ProblemFileError
        Naming the first offending key.
    """
    top = _Table(data, "", source)
    hub = _read_hub(top.table("hub"))
    detumble_table = top.table("detumble")
    detumble = Detumble(detumble_table.array("initial_rate_rad_s", (3,)))
    detumble_table.done()
    transfer = _read_simple(
        top.table("transfer"),
        Transfer,
        ("from_altitude_km", "from_inclination_deg", "to_altitude_km", "to_inclination_deg"),
        nonnegative=True,
    )
    cubesats = _read_cubesats(top.table("cubesats"))
    engine = _read_engine(top.table("engine"))
    problem = Problem(
        name=top.text("name"),
        description=top.text("description"),
        hub=hub,
        arrays=_read_arrays(top.table("arrays"), hub.size_m),
        cubesats=cubesats,
        engine=engine,
        disturbance=_read_disturbance(top.table("disturbance")),
        sensor=_read_sensor(top.table("sensor")),
        uncertainty=_read_uncertainty(top.table("uncertainty")),
        weights=_read_weights(top.table("weights")),
        orbit=_read_simple(
            top.table("orbit"), Orbit, ("altitude_km", "inclination_deg"), nonnegative=True
        ),
        transfer=transfer,
        detumble=detumble,
        constants=_read_simple(
            top.table("constants"),
            Constants,
            ("earth_mu_km3_s2", "earth_radius_km", "standard_gravity_m_s2"),
            positive=True,
        ),
        simulation=_read_simulation(
            _optional_table(top, "simulation", DEFAULT_SIMULATION),
            n_cubesats=6 * cubesats.per_face,
            n_stages=engine.stages,
        ),
        montecarlo=_read_montecarlo(_optional_table(top, "montecarlo", DEFAULT_MONTECARLO)),
        source=source or "<dict>",
        sha256=sha256,
    )
    if "extends" in data:
        top.taken.add("extends")
    top.done()
    return problem


def _merge(base: Mapping[str, Any], override: Mapping[str, Any]) -> dict[str, Any]:
    merged = dict(base)
    for key, value in override.items():
        if isinstance(value, Mapping) and isinstance(merged.get(key), Mapping):
            merged[key] = _merge(merged[key], value)
        else:
            merged[key] = value
    return merged


def _read_toml(path: Path, chain: tuple[Path, ...] = ()) -> tuple[dict[str, Any], bytes]:
    """Parse a problem file, following ``extends``; returns data and the bytes hashed."""
    source = str(path)
    if path in chain:
        raise ProblemFileError("extends", f"circular chain {[str(p) for p in chain]}", source)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise ProblemFileError("", "no such problem file", source) from None
    except OSError as exc:
        raise ProblemFileError("", f"cannot be read ({exc.strerror})", source) from None
    try:
        data = tomllib.loads(raw.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ProblemFileError("", f"not valid TOML ({exc})", source) from None
    parent = data.get("extends")
    if parent is None:
        return data, raw
    if not isinstance(parent, str):
        raise ProblemFileError("extends", "must be a path string", source)
    base, base_raw = _read_toml((path.parent / parent).resolve(), (*chain, path))
    return _merge(base, data), base_raw + raw


def default_problem_path() -> Path:
    """Path of the shipped default problem (the paper's setup)."""
    return Path(str(resources.files("casadi_debris") / "problems" / "paper.toml"))


def default_controller_path() -> Path:
    """Path of the shipped controller designed for the default problem."""
    return Path(str(resources.files("casadi_debris") / "data" / "paper_controller.json"))


def load_problem(path: str | Path | None = None) -> Problem:
    """Load and validate a problem file.

    Parameters
    ----------
    path : str or Path, optional
        A TOML problem file; default the shipped ``problems/paper.toml``.

    Returns
    -------
    Problem
        Frozen, validated parameters; ``sha256`` hashes the file (and the
        files it extends).

    Raises
    ------
    ProblemFileError
        Missing or unreadable file, invalid TOML, or a bad key (named).
    """
    resolved = Path(path).resolve() if path is not None else default_problem_path()
    data, raw = _read_toml(resolved)
    return problem_from_dict(data, str(resolved), hashlib.sha256(raw).hexdigest())
