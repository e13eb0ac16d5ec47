"""The MEKF against a truth simulated independently (scipy rotations, numpy noise).

Consistency: over M seeded runs the average normalised estimation error squared
(NEES) of the 6 error states must lie within the chi-square bounds of 6 M degrees
of freedom (Bar-Shalom, Li and Kirubarajan, Estimation with Applications to
Tracking and Navigation, section 5.4).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation
from scipy.stats import chi2

from casadi_debris.simulation._estimation import (
    MekfState,
    initial_filter_state,
    mekf_step,
)

PERIOD_S = 0.1
STEPS = 400
RUNS = 24
ARCSEC = np.pi / 180 / 3600
SIGMA_ST = 10 * ARCSEC
SIGMA_V = 0.15 * np.pi / 180 / 60  # 0.15 deg/sqrt(h) -> rad/sqrt(s)
SIGMA_U = 20 * np.pi / 180 / 3600 / 60  # 20 deg/h/sqrt(h) -> rad/s/sqrt(s)
P0_ATT = 30 * ARCSEC
P0_BIAS = 50 * np.pi / 180 / 3600
EVERY = 5  # star tracker at 2 Hz


def _scalar_first(rotation: Rotation) -> np.ndarray:
    return np.roll(rotation.as_quat(), 1, axis=-1)


def _truth_and_readings(seed: int):
    """Truth (rotations, biases) and the sensors' readings of one run."""
    rng = np.random.default_rng(seed)
    t = np.arange(STEPS) * PERIOD_S
    rate = np.stack([1e-3 * np.sin(0.01 * t), 2e-3 * np.cos(0.013 * t), 5e-4 + 0 * t], axis=1)
    bias = np.zeros((STEPS + 1, 3))
    bias[0] = rng.normal(0.0, P0_BIAS, 3)
    attitude = [Rotation.from_rotvec(rng.normal(0.0, 1.0, 3))]
    for k in range(STEPS):
        bias[k + 1] = bias[k] + SIGMA_U * np.sqrt(PERIOD_S) * rng.normal(size=3)
        attitude.append(attitude[k] * Rotation.from_rotvec(rate[k] * PERIOD_S))
    gyro = rate + bias[:STEPS] + SIGMA_V / np.sqrt(PERIOD_S) * rng.normal(size=(STEPS, 3))
    noise = Rotation.from_rotvec(SIGMA_ST * rng.normal(size=(STEPS, 3)))
    measured = [attitude[k] * noise[k] for k in range(STEPS)]
    initial_error = Rotation.from_rotvec(P0_ATT * rng.normal(size=3))
    return attitude, bias, gyro, measured, attitude[0] * initial_error


def _nees_series(seed: int) -> np.ndarray:
    """NEES of the updated estimate at each star-tracker reading of one run."""
    attitude, bias, gyro, measured, start = _truth_and_readings(seed)
    step = mekf_step()
    state = initial_filter_state(_scalar_first(start), P0_ATT, P0_BIAS)
    noise = [SIGMA_ST**2, SIGMA_V**2, SIGMA_U**2]
    nees = []
    for k in range(STEPS):
        valid = 1.0 if k % EVERY == 0 else 0.0
        prior = state
        state_next, q_post = step(
            prior, gyro[k], _scalar_first(measured[k]), valid, noise, PERIOD_S
        )
        if valid:
            # The posterior covariance: one update without propagation (h = 0, no noise).
            posterior, _ = step(
                prior, np.zeros(3), _scalar_first(measured[k]), 1.0, [SIGMA_ST**2, 0, 0], 0.0
            )
            posterior = np.asarray(posterior).ravel()
            estimate = Rotation.from_quat(np.roll(np.asarray(q_post).ravel(), -1))
            error = np.concatenate(
                [(estimate.inv() * attitude[k]).as_rotvec(), bias[k] - posterior[MekfState.BIAS]]
            )
            covariance = posterior[MekfState.COVARIANCE].reshape(6, 6, order="F")
            nees.append(error @ np.linalg.solve(covariance, error))
        state = np.asarray(state_next).ravel()
    return np.array(nees)


@pytest.fixture(scope="module")
def nees() -> np.ndarray:
    return np.array([_nees_series(seed) for seed in range(RUNS)])


def test_average_nees_within_chi_square_bounds(nees: np.ndarray) -> None:
    # After the initial transient, at each reading the average over the runs
    # lies in its two-sided 99 % interval at least 95 % of the time.
    average = nees[:, 20:].mean(axis=0)
    low, high = chi2.ppf([0.005, 0.995], 6 * RUNS) / RUNS
    inside = np.mean((average >= low) & (average <= high))
    assert inside >= 0.95, (inside, average.min(), average.max(), low, high)


def test_time_averaged_nees_near_dimension(nees: np.ndarray) -> None:
    # The grand mean is 6 for a consistent filter; the readings of one run are
    # correlated, so the bound is that of the runs alone (one value each).
    grand = nees[:, 20:].mean(axis=1)
    low, high = chi2.ppf([0.005, 0.995], 6 * RUNS) / RUNS
    assert low <= grand.mean() <= high


def test_estimate_beats_the_star_tracker(nees: np.ndarray) -> None:
    # Gyro-smoothed estimate: its attitude sigma below the tracker's alone.
    attitude, _, gyro, measured, start = _truth_and_readings(123)
    step = mekf_step()
    state = initial_filter_state(_scalar_first(start), P0_ATT, P0_BIAS)
    errors = []
    for k in range(STEPS):
        valid = 1.0 if k % EVERY == 0 else 0.0
        state_next, q_post = step(
            state,
            gyro[k],
            _scalar_first(measured[k]),
            valid,
            [SIGMA_ST**2, SIGMA_V**2, SIGMA_U**2],
            PERIOD_S,
        )
        estimate = Rotation.from_quat(np.roll(np.asarray(q_post).ravel(), -1))
        errors.append((estimate.inv() * attitude[k]).as_rotvec())
        state = np.asarray(state_next).ravel()
    rms = np.sqrt(np.mean(np.square(errors[200:])))
    assert rms < SIGMA_ST
