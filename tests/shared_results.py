"""Expensive, immutable results built once per test session and shared by every file (and
every xdist worker) that needs the same one.

A result is pickled into the session's folder (``conftest.py`` sets it up before the
workers start, and removes it at the end); a worker that asks while another is building it
waits on the result's lock instead of building it again. Only for objects the tests read
and never change (a solved slew), so that no result depends on which test asked first.
"""

from __future__ import annotations

import fcntl
import os
import pickle
from collections.abc import Callable
from pathlib import Path
from typing import Any

FOLDER_VARIABLE = "CASADI_DEBRIS_TEST_SHARED"
_LOADED: dict[str, Any] = {}


def shared_result(key: str, build: Callable[[], Any]) -> Any:
    """``build()``'s value, built by the first test of the session that asks for ``key``
    (in any worker) and loaded by the others."""
    if key in _LOADED:
        return _LOADED[key]
    folder = Path(os.environ[FOLDER_VARIABLE])
    path = folder / f"{key}.pickle"
    with (folder / f"{key}.lock").open("w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if path.exists():
            value = pickle.loads(path.read_bytes())
        else:
            value = build()
            partial = path.with_suffix(".partial")
            partial.write_bytes(pickle.dumps(value))
            os.replace(partial, path)
    _LOADED[key] = value
    return value


def paper_z_time_optimal(problem: Any) -> Any:
    """The paper's time-optimal 180° slew about z (torque level, no vibration check),
    solved by several test files; ``problem`` is the paper's.

    Request it from a module-scoped fixture of a module that imports
    ``slew_reference.every_profile_checked``: the profile is then checked independently
    where it is solved (a session fixture would be solved before that module's check is
    in place).
    """
    import math

    from casadi_debris.slews import time_optimal_slew

    assert problem.name == "paper", problem.name
    return shared_result(
        "paper_z_time_optimal",
        lambda: time_optimal_slew(problem, "z", math.pi, check_vibration=False),
    )
