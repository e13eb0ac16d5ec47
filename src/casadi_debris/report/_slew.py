"""Slew profiles and manoeuvre references as CSV time series, in display units."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from casadi_debris.dynamics import euler_angles_321
from casadi_debris.store import write_csv
from casadi_debris.units import MN_PER_N, MNM_PER_NM

if TYPE_CHECKING:
    from casadi_debris.slews import SlewProfile


def write_profile_csv(profile: SlewProfile, path: Path, thrust: bool) -> Path:
    """``profile.csv`` of one slew: time (s), quaternion q_BN (scalar first), 3-2-1 Euler
    angles (deg), rate (deg/s), acceleration (deg/s^2), torque (mNm) and, with ``thrust``,
    the thrust of every engine (mN, ``thrust_01_mN`` for engine 1)."""
    columns: dict[str, np.ndarray] = {"time_s": profile.time_s}
    for i in range(4):
        columns[f"q{i}_BN"] = profile.quaternion_BN[:, i]
    for i, name in enumerate(("roll", "pitch", "yaw")):
        columns[f"{name}_deg"] = np.degrees(profile.euler_angles_rad[:, i])
    for i, axis in enumerate("xyz"):
        columns[f"rate_{axis}_deg_s"] = np.degrees(profile.rate_rad_s[:, i])
    for i, axis in enumerate("xyz"):
        columns[f"acceleration_{axis}_deg_s2"] = np.degrees(profile.acceleration_rad_s2[:, i])
    for i, axis in enumerate("xyz"):
        columns[f"torque_{axis}_mNm"] = profile.torque_Nm[:, i] * MNM_PER_NM
    if thrust:
        for i in range(profile.thrust_N.shape[1]):
            columns[f"thrust_{i + 1:02d}_mN"] = profile.thrust_N[:, i] * MN_PER_N
    return write_csv(path, columns)


def write_reference_csv(
    time_s: np.ndarray, quaternion_BN: np.ndarray, rate_rad_s: np.ndarray, path: Path
) -> Path:
    """``profile.csv`` of a manoeuvre: time (s), quaternion q_BN (scalar first), 3-2-1
    Euler angles (deg) and rate (deg/s); arrays of shape (n,), (n, 4) and (n, 3)."""
    columns: dict[str, np.ndarray] = {"time_s": time_s}
    for i in range(4):
        columns[f"q{i}_BN"] = quaternion_BN[:, i]
    angles = euler_angles_321(quaternion_BN)
    for i, name in enumerate(("roll", "pitch", "yaw")):
        columns[f"{name}_deg"] = np.degrees(angles[:, i])
    for i, axis in enumerate("xyz"):
        columns[f"rate_{axis}_deg_s"] = np.degrees(rate_rad_s[:, i])
    return write_csv(path, columns)
