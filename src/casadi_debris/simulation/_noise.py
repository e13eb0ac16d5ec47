"""The seeded noise of a closed-loop run: sensors' errors, engines' thrust noise and misalignment.

Everything random in a realistic run is drawn here, in numpy, before the run,
and enters the compiled step as inputs: the step itself is deterministic, and
one compiled step serves every seed and every noise level. Each stream has its
own generator spawned from ``[sensors] seed`` (``numpy.random.SeedSequence``),
so that switching one effect on or off leaves the others' draws unchanged.

Gyro (IEEE Std 952 model, sampled at the control period h): the reading of
period k is ``w_k + b_k + sv / sqrt(h) n_k`` and the bias walks as
``b_k+1 = b_k + su sqrt(h) m_k`` (n, m standard normal; ``sv`` the angle random
walk [rad/sqrt(s)], ``su`` the rate random walk [rad/s/sqrt(s)]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.spatial.transform import Rotation

from casadi_debris.config import Problem
from casadi_debris.geometry import Geometry
from casadi_debris.units import ARCSEC_PER_RAD, DEG_PER_RAD, SECONDS_PER_HOUR

# Time round-off allowed when a star-tracker reading falls on a control instant.
_TIME_ROUND_OFF = 1e-9


def arw_rad_rt_s(deg_rt_h: float) -> float:
    """Angle random walk [deg/sqrt(h)] in rad/sqrt(s)."""
    return deg_rt_h / DEG_PER_RAD / math.sqrt(SECONDS_PER_HOUR)


def rrw_rad_s_rt_s(deg_h_rt_h: float) -> float:
    """Rate random walk [deg/h/sqrt(h)] in rad/s/sqrt(s)."""
    return deg_h_rt_h / DEG_PER_RAD / SECONDS_PER_HOUR / math.sqrt(SECONDS_PER_HOUR)


@dataclass(frozen=True, eq=False)
class NoiseStreams:
    """What the sensors and engines add, per control period (SI units).

    Attributes
    ----------
    seed : int
    star_tracker_rad : ndarray, shape (n, 3)
        Rotation vector from the low-passed attitude to the reading (bias + noise).
    star_tracker_valid : ndarray, shape (n,)
        1 where a new reading arrives at the start of the period, else 0.
    gyro_error_rad_s : ndarray, shape (n, 3)
        Bias plus rate noise of the gyro's reading.
    gyro_bias_rad_s : ndarray, shape (n, 3)
        The bias alone (what an estimator should find).
    thrust_factor : ndarray, shape (n, n_engines)
        Thrust as a multiple of the commanded one.
    torque_map, force_map : ndarray, shape (3, n_engines)
        The engines' torque and force per newton with their misalignment.
    """

    seed: int
    star_tracker_rad: np.ndarray
    star_tracker_valid: np.ndarray
    gyro_error_rad_s: np.ndarray
    gyro_bias_rad_s: np.ndarray
    thrust_factor: np.ndarray
    torque_map: np.ndarray
    force_map: np.ndarray


def draw_noise(
    problem: Problem, geometry: Geometry, time_s: np.ndarray, seed: int | None = None
) -> NoiseStreams:
    """The noise of a run at the control instants ``time_s`` (uniform), shape (n,).

    ``seed`` defaults to the problem's ``[sensors] seed``.
    """
    seed = problem.sensors.seed if seed is None else int(seed)
    streams = [np.random.default_rng(s) for s in np.random.SeedSequence(seed).spawn(4)]
    n = len(time_s)
    period = float(time_s[1] - time_s[0]) if n > 1 else 1.0
    tracker = problem.sensors.star_tracker
    error = tracker.bias_arcsec / ARCSEC_PER_RAD + (
        tracker.noise_arcsec / ARCSEC_PER_RAD
    ) * streams[0].standard_normal((n, 3))
    gyro = problem.sensors.gyro
    bias = np.empty((n, 3))
    bias[0] = gyro.initial_bias_deg_h / DEG_PER_RAD / SECONDS_PER_HOUR
    steps = rrw_rad_s_rt_s(gyro.bias_random_walk_deg_h_rt_h) * math.sqrt(period)
    bias[1:] = bias[0] + np.cumsum(steps * streams[1].standard_normal((n - 1, 3)), axis=0)
    rate_noise = arw_rad_rt_s(gyro.angle_random_walk_deg_rt_h) / math.sqrt(period)
    actuators = problem.actuators
    n_engines = geometry.torque_map.shape[1]
    factor = 1.0 + actuators.thrust_noise_fraction * streams[2].standard_normal((n, n_engines))
    torque_map, force_map = misaligned_maps(geometry, actuators.misalignment_deg, streams[3])
    return NoiseStreams(
        seed=seed,
        star_tracker_rad=error,
        star_tracker_valid=reading_flags(
            time_s, tracker.update_rate_hz, np.asarray(tracker.outages_s)
        ),
        gyro_error_rad_s=bias + rate_noise * streams[1].standard_normal((n, 3)),
        gyro_bias_rad_s=bias,
        thrust_factor=factor,
        torque_map=torque_map,
        force_map=force_map,
    )


def reading_flags(time_s: np.ndarray, rate_hz: float | None, outages_s: np.ndarray) -> np.ndarray:
    """1 at the control instants where a new star-tracker reading has arrived, else 0.

    A reading arrives at every multiple of ``1 / rate_hz`` (every instant when
    None); the loop sees it at the first control instant at or after it. None
    arrives inside an outage [start, end).
    """
    t = np.asarray(time_s, dtype=float)
    if rate_hz is None:
        valid = np.ones(len(t))
    else:
        count = np.floor(t * rate_hz + _TIME_ROUND_OFF)
        valid = np.concatenate([[1.0], (np.diff(count) > 0).astype(float)])
    for start, end in outages_s.reshape(-1, 2):
        valid[(t >= start) & (t < end)] = 0.0
    return valid


def misaligned_maps(
    geometry: Geometry, sigma_deg: float, rng: np.random.Generator
) -> tuple[np.ndarray, np.ndarray]:
    """Torque and force maps with each engine tilted by two normal angles of ``sigma_deg``."""
    torque_map = np.array(geometry.torque_map, dtype=float)
    force_map = np.array(geometry.force_map, dtype=float)
    tilts = np.radians(sigma_deg) * rng.standard_normal((len(geometry.engines), 2))
    if sigma_deg == 0.0:
        return torque_map, force_map
    for engine, (a, b) in zip(geometry.engines, tilts, strict=True):
        d = np.asarray(engine.direction, dtype=float)
        across = np.linalg.svd(d[None, :])[2][1:]  # two unit vectors normal to d
        tilted = Rotation.from_rotvec(a * across[0] + b * across[1]).apply(d)
        column = engine.index
        torque_map[:, column] += np.cross(engine.position_m, tilted - d)
        force_map[:, column] += tilted - d
    return torque_map, force_map
