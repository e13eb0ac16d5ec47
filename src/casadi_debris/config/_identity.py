"""What a controller is designed for: a hash of the plant a problem describes.

A controller fits a plant (hub, appendages, CubeSats and engines, sensor,
disturbance, uncertainty, weights, requirements), not a file: comments, the
name, the runs (``[simulation]``, ``[montecarlo]``), the orbit and the way the
CubeSats were written (a ``[cubesat_layout]`` or the list it expands to) do
not change it. :func:`plant_sha256` hashes the validated values of exactly
those parts, so two files that describe one plant share the hash.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # the schema's Problem calls this module: no import at run time
    from casadi_debris.config._schema import Problem

PLANT_FIELDS = (
    "hub",
    "arrays",
    "cubesats",
    "engine",
    "disturbance",
    "sensor",
    "uncertainty",
    "weights",
    "requirements",
)


def _plain(value: Any) -> Any:
    """JSON-ready values: dataclasses by field, arrays as float lists, numbers as floats."""
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        # A field left at its default is left out, so that adding an optional setting to
        # the toolkit does not change the hash of a plant that does not use it.
        return {
            f.name: _plain(getattr(value, f.name))
            for f in dataclasses.fields(value)
            if f.default is dataclasses.MISSING or getattr(value, f.name) != f.default
        }
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, int | float | np.number):
        return repr(float(value) + 0.0)  # 3 and 3.0 are one plant, and so are -0.0 and 0.0
    raise TypeError(f"cannot hash {type(value).__name__}")


def plant_sha256(problem: Problem) -> str:
    """SHA-256 of the plant ``problem`` describes (see the module's note), hex."""
    plant = {name: _plain(getattr(problem, name)) for name in PLANT_FIELDS}
    text = json.dumps(plant, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()
