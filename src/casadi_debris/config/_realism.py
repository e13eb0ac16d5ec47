"""Sensors, estimation, engines and computation delay (``[sensors.*]``, ``[estimation]``,
``[actuators]``, ``[controller]``): the dataclasses and their readers.

Every table is optional and every key defaults to the paper's ideal loop: a
noiseless star tracker read at every control period (the first-order low pass
of ``[sensor]`` stays the tracker's dynamics), no estimator, instantaneous
engines that give exactly the allocated thrust, no computation delay. With
the defaults the closed-loop step is the paper's, graph for graph. Every
setting is a plain number (or an array of numbers) so that a Monte Carlo can
sample it; the noise streams and the engines' misalignment are drawn from
``[sensors] seed``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np

from casadi_debris.config import limits
from casadi_debris.config._table import Table, frozen_array

EstimationFilter = Literal["none", "mekf"]
ESTIMATION_FILTERS: tuple[EstimationFilter, ...] = ("none", "mekf")

NOISE_ARCSEC = limits.Range(0.0, 3.6e6)
BIAS_ARCSEC = limits.Range(-3.6e5, 3.6e5)
UPDATE_RATE_HZ = limits.Range(0.0, 1000.0, low_open=True)
OUTAGE_S = limits.Range(0.0, 1e7)
MAX_OUTAGES = 1000
ARW_DEG_RT_H = limits.Range(0.0, 100.0)
RRW_DEG_H_RT_H = limits.Range(0.0, 1e4)
GYRO_BIAS_DEG_H = limits.Range(-1e5, 1e5)
SIGMA_ARCSEC = limits.Range(1e-3, 3.6e6)
SIGMA_DEG_H = limits.Range(1e-6, 1e5)
NOISE_FRACTION = limits.Range(0.0, 1.0)
MISALIGNMENT_DEG = limits.Range(0.0, 10.0)
TIME_CONSTANT_S = limits.Range(0.0, 1e3)
DELAY_S = limits.Range(0.0, 1e3)
IMPULSE_UNS = limits.Range(0.0, 1e9)


def _zeros3() -> np.ndarray:
    return frozen_array(np.zeros(3))


@dataclass(frozen=True, eq=False)
class StarTracker:
    """``[sensors.star_tracker]``: what the tracker adds to the low-passed attitude.

    Attributes
    ----------
    noise_arcsec : float
        White noise, 1 sigma per body axis, independent at each reading.
    bias_arcsec : ndarray, shape (3,)
        Constant error of the reading (mounting, calibration), body axes.
    update_rate_hz : float or None
        Readings per second; None: one at every control period. Between
        readings the loop uses the last one (or the estimator propagates).
    outages_s : ndarray, shape (n, 2)
        Intervals [start, end) without readings (Sun or Earth in the field
        of view, lost in space).
    """

    noise_arcsec: float = 0.0
    bias_arcsec: np.ndarray = field(default_factory=_zeros3)
    update_rate_hz: float | None = None
    outages_s: np.ndarray = field(default_factory=lambda: frozen_array(np.zeros((0, 2))))

    @property
    def ideal(self) -> bool:
        return (
            self.noise_arcsec == 0.0
            and not np.any(self.bias_arcsec)
            and self.update_rate_hz is None
            and len(self.outages_s) == 0
        )


@dataclass(frozen=True, eq=False)
class Gyro:
    """``[sensors.gyro]``: a rate-integrating gyro (what the estimator propagates with).

    Attributes
    ----------
    angle_random_walk_deg_rt_h : float
        Angle random walk N [deg/sqrt(h)]: white rate noise of density N.
    bias_random_walk_deg_h_rt_h : float
        Rate random walk K [deg/h/sqrt(h)]: the bias drifts as a Wiener process.
    initial_bias_deg_h : ndarray, shape (3,)
        Bias at t = 0, body axes [deg/h].
    """

    angle_random_walk_deg_rt_h: float = 0.0
    bias_random_walk_deg_h_rt_h: float = 0.0
    initial_bias_deg_h: np.ndarray = field(default_factory=_zeros3)


@dataclass(frozen=True, eq=False)
class Sensors:
    """``[sensors]``: the star tracker, the gyro and the seed of every noise stream.

    ``seed`` (0 to 2^32 - 1) draws the sensors' noise, the engines' thrust noise
    and their misalignment; results record it.
    """

    star_tracker: StarTracker = field(default_factory=StarTracker)
    gyro: Gyro = field(default_factory=Gyro)
    seed: int = 0


@dataclass(frozen=True, eq=False)
class Estimation:
    """``[estimation]``: what stands between the sensors and the controller.

    Attributes
    ----------
    filter : {"none", "mekf"}
        ``none``: the controller reads the star tracker's last reading;
        ``mekf``: a multiplicative extended Kalman filter of the attitude and
        the gyro bias, propagated with the gyro at the control rate and
        updated with each star-tracker reading.
    initial_attitude_sigma_arcsec : float
        1 sigma of the initial attitude estimate per axis.
    initial_bias_sigma_deg_h : float
        1 sigma of the initial gyro-bias estimate per axis (the estimate starts at 0).
    """

    filter: EstimationFilter = "none"
    initial_attitude_sigma_arcsec: float = 10.0
    initial_bias_sigma_deg_h: float = 1.0


@dataclass(frozen=True, eq=False)
class Actuators:
    """``[actuators]``: the engines as they are, not as allocated.

    Attributes
    ----------
    thrust_noise_fraction : float
        1 sigma of each engine's thrust error, relative to its thrust, drawn at
        each control period.
    misalignment_deg : float
        1 sigma of each engine's tilt about each of the two axes across its
        thrust direction, drawn once per run.
    ramp_time_constant_s : float
        First-order lag of each engine's thrust (0: a step).
    latency_s : float
        From command to the start of the thrust response.
    minimum_impulse_bit_uNs : float
        An engine commanded below this impulse over a control period does not
        fire [micro N s].
    """

    thrust_noise_fraction: float = 0.0
    misalignment_deg: float = 0.0
    ramp_time_constant_s: float = 0.0
    latency_s: float = 0.0
    minimum_impulse_bit_uNs: float = 0.0

    @property
    def engine_level(self) -> bool:
        """Whether an effect acts per engine (the step then allocates thrust itself)."""
        return bool(
            self.thrust_noise_fraction
            or self.misalignment_deg
            or self.ramp_time_constant_s
            or self.minimum_impulse_bit_uNs
        )


@dataclass(frozen=True, eq=False)
class ControllerTiming:
    """``[controller]``: ``delay_s``, from the sensor reading to the torque command."""

    delay_s: float = 0.0


def read_sensors(top: Table) -> Sensors:
    """``[sensors]`` with its optional ``star_tracker`` and ``gyro`` tables."""
    t = _optional(top, "sensors")
    if t is None:
        return Sensors()
    d = Sensors()
    tracker = _read_star_tracker(t)
    gyro = _read_gyro(t)
    seed = t.integer("seed", limits.SEED) if t.has("seed") else d.seed
    t.done()
    return Sensors(star_tracker=tracker, gyro=gyro, seed=seed)


def _read_star_tracker(parent: Table) -> StarTracker:
    def outages(t: Table) -> dict[str, Any]:
        if not t.has("outages_s"):
            return {}
        intervals = t.array("outages_s", (None, 2), OUTAGE_S, max_rows=MAX_OUTAGES)
        if np.any(intervals[:, 1] <= intervals[:, 0]):
            raise t.error(t.key("outages_s"), "every interval must end after it starts")
        return {"outages_s": intervals}

    numbers = {"noise_arcsec": NOISE_ARCSEC, "update_rate_hz": UPDATE_RATE_HZ}
    vectors = {"bias_arcsec": BIAS_ARCSEC}
    return _read(parent, "star_tracker", StarTracker(), numbers, vectors, outages)


def _read_gyro(parent: Table) -> Gyro:
    numbers = {
        "angle_random_walk_deg_rt_h": ARW_DEG_RT_H,
        "bias_random_walk_deg_h_rt_h": RRW_DEG_H_RT_H,
    }
    return _read(parent, "gyro", Gyro(), numbers, {"initial_bias_deg_h": GYRO_BIAS_DEG_H})


def read_estimation(top: Table) -> Estimation:
    """``[estimation]`` (absent: no estimator)."""

    def chosen(t: Table) -> dict[str, Any]:
        return {"filter": t.text("filter", ESTIMATION_FILTERS)} if t.has("filter") else {}

    numbers = {
        "initial_attitude_sigma_arcsec": SIGMA_ARCSEC,
        "initial_bias_sigma_deg_h": SIGMA_DEG_H,
    }
    return _read(top, "estimation", Estimation(), numbers, extra=chosen)


ACTUATOR_RANGES = {
    "thrust_noise_fraction": NOISE_FRACTION,
    "misalignment_deg": MISALIGNMENT_DEG,
    "ramp_time_constant_s": TIME_CONSTANT_S,
    "latency_s": DELAY_S,
    "minimum_impulse_bit_uNs": IMPULSE_UNS,
}


def read_actuators(top: Table) -> Actuators:
    """``[actuators]`` (absent: ideal engines)."""
    return _read(top, "actuators", Actuators(), ACTUATOR_RANGES)


def read_controller_timing(top: Table) -> ControllerTiming:
    """``[controller]`` (absent: no computation delay)."""
    return _read(top, "controller", ControllerTiming(), {"delay_s": DELAY_S})


REALISM_FIELDS = ("sensors", "estimation", "actuators", "controller")


def read_realism(top: Table) -> dict[str, Any]:
    """The four tables, by the name of their field of the problem."""
    return {
        "sensors": read_sensors(top),
        "estimation": read_estimation(top),
        "actuators": read_actuators(top),
        "controller": read_controller_timing(top),
    }


def realism_fields(problem: Any) -> dict[str, Any]:
    """A problem's four realism settings by field name, to give another problem:
    ``dataclasses.replace(other, **realism_fields(problem))``."""
    return {name: getattr(problem, name) for name in REALISM_FIELDS}


def _read(
    parent: Table,
    name: str,
    default: Any,
    numbers: dict[str, limits.Range],
    vectors: dict[str, limits.Range] | None = None,
    extra: Callable[[Table], dict[str, Any]] | None = None,
) -> Any:
    """The table ``name`` of ``parent`` as ``default`` with the keys it gives (absent: default)."""
    t = _optional(parent, name)
    if t is None:
        return default
    values = _fields(t, default, numbers, vectors)
    if extra is not None:
        values |= extra(t)
    t.done()
    return dataclasses.replace(default, **values)


def _optional(top: Table, name: str) -> Table | None:
    if not top.has(name):
        top.taken.add(name)
        return None
    return top.table(name)


def _number(t: Table, name: str, default: Any, bounds: limits.Range) -> Any:
    return t.number(name, bounds) if t.has(name) else default


def _fields(
    t: Table,
    default: Any,
    numbers: dict[str, limits.Range],
    vectors: dict[str, limits.Range] | None = None,
) -> dict[str, Any]:
    """The given keys of ``t`` (numbers, and body-axis vectors of 3), the rest as ``default``."""
    values = {name: _number(t, name, getattr(default, name), b) for name, b in numbers.items()}
    for name, bounds in (vectors or {}).items():
        values[name] = t.array(name, (3,), bounds) if t.has(name) else getattr(default, name)
    return values
