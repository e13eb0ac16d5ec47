"""The realistic control period: sensors, estimator, delay and engines around the controller.

With a problem's ``[sensors.*]``, ``[estimation]``, ``[actuators]`` or
``[controller]`` set, the step of :mod:`~casadi_debris.simulation._closed_loop`
replaces its ideal control law by :func:`realistic_law`, one period:

1. star tracker: the reading ``q_m = q_ST (x) exp(e_k)`` of the low-passed
   attitude ``q_ST`` (the plant's first-order tracker state) with the drawn
   error ``e_k`` (bias + noise) when a reading arrives (``valid``);
2. estimate: with ``filter = "none"`` the last reading held; with ``"mekf"`` the
   filter of :mod:`~casadi_debris.simulation._estimation`, propagated with the
   gyro reading ``w_k + gyro error``;
3. controller and saturation, as in the ideal loop, on the estimate;
4. delay: the controller's computation delay plus the engines' latency,
   ``D = (m + f) h`` with m whole periods and a fraction f: over period k the
   loop applies ``(1 - f) a_k-m + f a_k-m-1`` of the saturated commands ``a``
   (the torque whose impulse over the period equals the delayed command's);
5. engines (when an effect acts per engine): the command's torque, as the
   allocator gives it exactly, plus what the engines' effects change in it.
   The effects act on the command's thrust ``f_c``, the allocator's least-fuel
   thrust along each signed body axis superposed (:class:`EngineBasis`; exact
   along one axis, and for the torques of the pointing runs): engines commanded
   below the minimum impulse bit switched off (``f_c h < I_min``); a
   first-order lag of time constant T (the thrust's mean over the period
   ``f_c + (f_prev - f_c) T / h (1 - exp(-h / T))`` is held); the drawn thrust
   factor (kept non-negative); the misaligned torque and force maps. The run
   books the allocator's thrust for the command plus the change ``f_a - f_c``
   (kept within 0 and the engine's limit).

Every noise sample, noise variance and misaligned map enters as a row of the
step's input ``s`` (:class:`RealismInputs`): the graph depends only on which
effects act, the delay's whole periods and the engine count.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, quaternion_product
from casadi_debris.simulation._estimation import STATE_SIZE, initial_filter_state, mekf_step
from casadi_debris.simulation._noise import NoiseStreams, arw_rad_rt_s, rrw_rad_s_rt_s
from casadi_debris.units import ARCSEC_PER_RAD, DEG_PER_RAD, SECONDS_PER_HOUR

BASE_INPUTS = 8
# The last sample of an axis stays this far (relative) inside its reach.
_REACH_BACKOFF = 1e-9
# Fraction of a period below which a delay counts as whole periods (time round-off).
_DELAY_ROUND_OFF = 1e-9
MICRO = 1e-6


@dataclass(frozen=True)
class Realism:
    """Which realistic effects a run has: what the compiled step's graph depends on.

    Attributes
    ----------
    sensors : bool
        A star tracker with noise, bias, a rate or outages, or an estimator.
    filter : {"none", "mekf"}
    delay_periods : int
        Whole control periods of delay (controller plus engine latency).
    delay_fraction : float
        The rest, as a fraction of a period, in [0, 1).
    engine_level : bool
        An effect acts per engine (noise, misalignment, ramp, minimum impulse).
    n_engines : int
    """

    sensors: bool
    filter: str
    delay_periods: int
    delay_fraction: float
    engine_level: bool
    n_engines: int

    @classmethod
    def of(cls, problem: Problem, period_s: float) -> Realism | None:
        """The problem's realism at a control period; None for the paper's ideal loop."""
        delay = (problem.controller.delay_s + problem.actuators.latency_s) / period_s
        whole = math.floor(delay + _DELAY_ROUND_OFF)
        fraction = max(0.0, delay - whole)
        fraction = 0.0 if fraction < _DELAY_ROUND_OFF else fraction
        realism = cls(
            sensors=not problem.sensors.star_tracker.ideal or problem.estimation.filter != "none",
            filter=problem.estimation.filter,
            delay_periods=whole,
            delay_fraction=fraction,
            engine_level=problem.actuators.engine_level,
            n_engines=len(problem.engines),
        )
        return realism if realism.active else None

    @property
    def active(self) -> bool:
        return self.sensors or self.delayed or self.engine_level

    @property
    def delayed(self) -> bool:
        return self.delay_periods > 0 or self.delay_fraction > 0

    @property
    def sensor_size(self) -> int:
        if not self.sensors:
            return 0
        return STATE_SIZE if self.filter == "mekf" else 4

    @property
    def delay_size(self) -> int:
        return 3 * (self.delay_periods + 1) if self.delayed else 0

    @property
    def aux_size(self) -> int:
        """Entries of the step's state after the plant's and the controller's."""
        return self.sensor_size + self.delay_size + (self.n_engines if self.engine_level else 0)

    @property
    def inputs(self) -> RealismInputs:
        return RealismInputs(self.n_engines if self.engine_level else 0)

    @property
    def output_size(self) -> int:
        """Rows of the step's output: the ideal 7, torque and force (6), and at engine
        level the command (3) and each engine's thrust change (n)."""
        return 13 + (3 + self.n_engines if self.engine_level else 0)

    def initial_aux(self, problem: Problem, quaternion: np.ndarray) -> np.ndarray:
        """The extra state at t = 0: estimate on the true attitude, nothing fired yet."""
        parts = []
        if self.sensors and self.filter == "mekf":
            estimation = problem.estimation
            parts.append(
                initial_filter_state(
                    quaternion,
                    estimation.initial_attitude_sigma_arcsec / ARCSEC_PER_RAD,
                    estimation.initial_bias_sigma_deg_h / DEG_PER_RAD / SECONDS_PER_HOUR,
                )
            )
        elif self.sensors:
            parts.append(np.asarray(quaternion, dtype=float))
        parts.append(np.zeros(self.aux_size - self.sensor_size))
        return np.concatenate(parts)


@dataclass(frozen=True)
class RealismInputs:
    """Rows of the realistic step's input after the ideal ones
    (:class:`~casadi_debris.simulation.StepInput`)."""

    n_engines: int

    STAR_TRACKER_RAD = slice(8, 11)
    VALID = 11
    GYRO_ERROR_RAD_S = slice(12, 15)
    NOISE_VARIANCE = slice(15, 18)
    MINIMUM_IMPULSE_NS = 18
    RAMP = slice(19, 21)
    SENSOR_END = 19

    @property
    def thrust_factor(self) -> slice:
        return slice(21, 21 + self.n_engines)

    @property
    def torque_map(self) -> slice:
        start = 21 + self.n_engines
        return slice(start, start + 3 * self.n_engines)

    @property
    def force_map(self) -> slice:
        start = 21 + 4 * self.n_engines
        return slice(start, start + 3 * self.n_engines)

    @property
    def size(self) -> int:
        return self.SENSOR_END if self.n_engines == 0 else 21 + 7 * self.n_engines

    def rows(
        self, problem: Problem, noise: NoiseStreams, period_s: float, k: int, stop: int
    ) -> np.ndarray:
        """The extra rows of periods k .. stop - 1, shape (size - 8, stop - k)."""
        used = stop - k
        rows = np.zeros((self.size - BASE_INPUTS, used))

        def put(where: slice | int, values: np.ndarray) -> None:
            if isinstance(where, int):
                rows[where - BASE_INPUTS] = values
            else:
                rows[where.start - BASE_INPUTS : where.stop - BASE_INPUTS] = values

        put(self.STAR_TRACKER_RAD, noise.star_tracker_rad[k:stop].T)
        put(self.VALID, noise.star_tracker_valid[k:stop])
        put(self.GYRO_ERROR_RAD_S, noise.gyro_error_rad_s[k:stop].T)
        sensors, gyro = problem.sensors, problem.sensors.gyro
        variances = [
            max(sensors.star_tracker.noise_arcsec / ARCSEC_PER_RAD, MICRO / ARCSEC_PER_RAD) ** 2,
            arw_rad_rt_s(gyro.angle_random_walk_deg_rt_h) ** 2,
            rrw_rad_s_rt_s(gyro.bias_random_walk_deg_h_rt_h) ** 2,
        ]
        put(self.NOISE_VARIANCE, np.repeat(np.array(variances)[:, None], used, axis=1))
        if self.n_engines:
            actuators = problem.actuators
            put(self.MINIMUM_IMPULSE_NS, np.full(used, actuators.minimum_impulse_bit_uNs * MICRO))
            lag = actuators.ramp_time_constant_s
            decay = math.exp(-period_s / lag) if lag > 0 else 0.0
            mean = lag / period_s * (1.0 - decay) if lag > 0 else 0.0
            put(self.RAMP, np.repeat(np.array([[decay], [mean]]), used, axis=1))
            put(self.thrust_factor, noise.thrust_factor[k:stop].T)
            put(self.torque_map, np.repeat(noise.torque_map.reshape(-1, 1, order="F"), used, 1))
            put(self.force_map, np.repeat(noise.force_map.reshape(-1, 1, order="F"), used, 1))
        return rows


@dataclass(frozen=True, eq=False)
class EngineBasis:
    """The allocator's least-fuel thrust along each signed axis, as linear pieces.

    Along +x, -x, +y, -y, +z, -z (``axis`` 0 .. 5) the least-fuel thrust is
    piecewise linear in the torque's magnitude m (cheapest engines first, others
    joining as they saturate); piece s adds ``slope[:, s] * clip(m - start_Nm[s],
    0, length_Nm[s])``.

    Attributes
    ----------
    axis : ndarray of int, shape (S,)
    start_Nm, length_Nm : ndarray, shape (S,)
    slope : ndarray, shape (n_engines, S)
        Thrust per N m [N / N m].
    max_thrust_N : ndarray, shape (n_engines,)
    torque_map, force_map : ndarray, shape (3, n_engines)
        The allocator's (nominal) maps.
    """

    axis: np.ndarray
    start_Nm: np.ndarray
    length_Nm: np.ndarray
    slope: np.ndarray
    max_thrust_N: np.ndarray
    torque_map: np.ndarray
    force_map: np.ndarray

    def thrust(self, magnitudes: ca.SX) -> ca.SX:
        """Thrust (n_engines,) for the signed-axis magnitudes [m+x, m-x, ..., m-z] (6,)."""
        pieces = [
            ca.fmin(ca.fmax(magnitudes[int(a)] - start, 0.0), length)
            for a, start, length in zip(self.axis, self.start_Nm, self.length_Nm, strict=True)
        ]
        return ca.DM(self.slope) @ ca.vertcat(*pieces)


def measured_attitude(
    realism: Realism, model: Model, x: ca.SX, aux: ca.SX, s: ca.SX, period_s: float
) -> tuple[ca.SX, ca.SX]:
    """(the attitude the controller uses, the sensor part of the next aux)."""
    q_st = x[model.layout.q_st]
    if not realism.sensors:
        return q_st, ca.SX.zeros(0, 1)
    rows = RealismInputs
    error = s[rows.STAR_TRACKER_RAD]
    angle = ca.sqrt(ca.sumsqr(error) + 1e-40)
    reading = ca.vertcat(ca.cos(angle / 2), ca.sin(angle / 2) / angle * error)
    q_m = quaternion_product(q_st, reading)
    valid = s[rows.VALID]
    if realism.filter == "mekf":
        rate = x[model.layout.omega] + s[rows.GYRO_ERROR_RAD_S]
        state = aux[: realism.sensor_size]
        next_state, q_post = mekf_step()(state, rate, q_m, valid, s[rows.NOISE_VARIANCE], period_s)
        return q_post, next_state
    held = aux[:4]
    used = ca.if_else(valid > 0.5, q_m, held)
    return used, used


def delayed_command(realism: Realism, applied: ca.SX, aux: ca.SX) -> tuple[ca.SX, ca.SX]:
    """(the command acting over the period, the delay line's next state)."""
    if not realism.delayed:
        return applied, ca.SX.zeros(0, 1)
    start = realism.sensor_size
    line = aux[start : start + realism.delay_size]
    history = ca.vertcat(applied, line)  # a_k, a_k-1, ..., a_k-m-1
    m, f = realism.delay_periods, realism.delay_fraction
    acting = (1.0 - f) * history[3 * m : 3 * m + 3] + f * history[3 * m + 3 : 3 * m + 6]
    return acting, history[: realism.delay_size]


def engine_wrench(
    realism: Realism, basis: EngineBasis, command: ca.SX, aux: ca.SX, s: ca.SX, period_s: float
) -> tuple[ca.SX, ca.SX, ca.SX, ca.SX]:
    """(torque, force, thrust change, the ramp's next state) for a torque command.

    The command's torque is applied exactly (as the allocator gives it); the
    engines' effects add the difference they make to the command's thrust
    ``f_c`` (superposed axis by axis, :class:`EngineBasis`):
    ``T' f_a - T f_c`` and ``F' f_a - F f_c`` with ``f_a`` the thrust as fired
    and ``T'``, ``F'`` the misaligned maps. The thrust change ``f_a - f_c`` is
    returned for the run's books.
    """
    rows = realism.inputs
    n = realism.n_engines
    signed = ca.vertcat(*(ca.vertcat(ca.fmax(c, 0), ca.fmax(-c, 0)) for c in ca.vertsplit(command)))
    nominal = basis.thrust(signed)
    fired = ca.if_else(nominal * period_s >= s[rows.MINIMUM_IMPULSE_NS], nominal, 0.0)
    start = realism.sensor_size + realism.delay_size
    previous = aux[start : start + n]
    decay, mean = s[rows.RAMP.start], s[rows.RAMP.start + 1]
    held = fired + (previous - fired) * mean
    ramp_next = fired + (previous - fired) * decay
    actual = ca.fmax(held * s[rows.thrust_factor], 0.0)
    torque_map = ca.reshape(s[rows.torque_map], 3, n)
    force_map = ca.reshape(s[rows.force_map], 3, n)
    torque = command + torque_map @ actual - ca.DM(basis.torque_map) @ nominal
    force = force_map @ actual - ca.DM(basis.force_map) @ nominal
    return torque, force, actual - nominal, ramp_next


def realistic_law(
    realism: Realism,
    model: Model,
    controller_law: ca.Function,
    basis: EngineBasis | None,
    n_plant: int,
    n_controller: int,
    period_s: float,
) -> ca.Function:
    """``law(z, s) -> (torque, force, z_next without the plant, y)`` of one period.

    ``controller_law(q, xc, q_ref, feedforward) -> (applied, xc_next, demand,
    scale, error)`` is the ideal loop's controller and saturation.
    """
    z = ca.SX.sym("z", n_plant + n_controller + realism.aux_size)
    s = ca.SX.sym("s", realism.inputs.size)
    x, xc, aux = z[:n_plant], z[n_plant : n_plant + n_controller], z[n_plant + n_controller :]
    q_used, sensor_next = measured_attitude(realism, model, x, aux, s, period_s)
    applied, xc_next, demand, scale, error = controller_law(q_used, xc, s[1:5], s[5:8])
    acting, delay_next = delayed_command(realism, applied, aux)
    if realism.engine_level:
        if basis is None:
            raise ValueError("engine-level effects need the allocator's engine basis")
        torque, force, change, ramp_next = engine_wrench(realism, basis, acting, aux, s, period_s)
        extra = [acting, change]
    else:
        torque, force, ramp_next, extra = acting, ca.SX.zeros(3), ca.SX.zeros(0, 1), []
    outputs = ca.vertcat(demand, scale, error, torque, force, *extra)
    rest_next = ca.vertcat(xc_next, sensor_next, delay_next, ramp_next)
    return ca.Function(
        "realistic_law",
        [z, s],
        [torque, force, rest_next, outputs],
        ["z", "s"],
        ["torque", "force", "rest_next", "y"],
    )


def engine_basis(allocator: Allocator, samples: int = 64) -> EngineBasis:
    """The allocator's least-fuel thrust along each signed axis up to its reach, in pieces.

    Sampled at ``samples`` magnitudes per axis; neighbouring pieces of one slope
    merge. Between samples the thrust is a convex combination of two of the
    allocator's answers: exact torque, zero net force, within the limits.
    """
    reach = allocator.authority_polytope().axis_reach()
    axes: list[int] = []
    starts: list[float] = []
    lengths: list[float] = []
    slopes: list[np.ndarray] = []
    for j in range(6):
        if not reach[j] > 0:
            continue
        direction = np.zeros(3)
        direction[j // 2] = 1.0 if j % 2 == 0 else -1.0
        magnitudes = np.linspace(0.0, reach[j] * (1.0 - _REACH_BACKOFF), samples + 1)
        thrust = [np.zeros(allocator.n_engines)] + [
            np.asarray(allocator.allocate(m * direction).thrust_N) for m in magnitudes[1:]
        ]
        for k in range(samples):
            slope = (thrust[k + 1] - thrust[k]) / (magnitudes[k + 1] - magnitudes[k])
            same = axes and axes[-1] == j and np.allclose(slope, slopes[-1], rtol=1e-6, atol=1e-9)
            if same:
                lengths[-1] += magnitudes[k + 1] - magnitudes[k]
                continue
            axes.append(j)
            starts.append(magnitudes[k])
            lengths.append(magnitudes[k + 1] - magnitudes[k])
            slopes.append(slope)
    return EngineBasis(
        axis=np.array(axes, dtype=int),
        start_Nm=np.array(starts),
        length_Nm=np.array(lengths),
        slope=np.array(slopes).T.reshape(allocator.n_engines, len(slopes)),
        max_thrust_N=np.asarray(allocator.max_thrust_N, dtype=float),
        torque_map=allocator.torque_map,
        force_map=allocator.force_map,
    )
