"""A designed controller as data: what the controller file holds.

Sign convention: input e = reference - measured attitude [deg] (Phi, Theta,
Psi), output torque demand [mNm] (x, y, z); u = K e, continuous time.
Reading and writing the JSON file is the edges' job (CLI, report); this module
only converts to and from plain dicts.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import control
import numpy as np

from casadi_debris.errors import ProblemFileError

CONTROLLER_FORMAT_VERSION = 1
# No designed controller comes near this; a larger entry is a corrupted file.
MAX_ENTRY = 1e12
REQUIRED_KEYS = ("A", "B", "C", "D")
# What a design adds to the matrices; a controller of the user's own may leave it out.
DESIGN_KEYS = ("mu_peak", "mu_peak_reduced", "order_full", "order_reduced")


def _toolkit_version() -> str:
    from casadi_debris._version import __version__

    return __version__


@dataclass(frozen=True, eq=False)
class Controller:
    """Reduced controller plus how it was obtained.

    Attributes
    ----------
    reduced : control.StateSpace
        The controller to fly (attitude error [deg] -> torque [mNm]).
    full : control.StateSpace or None
        The full-order mu-synthesis controller.
    mu_peak, mu_peak_reduced : float or None
        Peak robust-performance mu of the full and reduced controllers (None: a
        controller not designed by μ-synthesis, e.g. a user's own).
    problem_sha256 : str
        The plant it was designed for (:attr:`casadi_debris.config.Problem.plant_sha256`;
        "" when the file records none).
    seed : int
        Seed of the uncertainty samples the weight was fitted on.
    details : dict
        Everything else worth keeping (weights, mu per iteration, timings).
    toolkit_version : str
        The casadi_debris version that designed it ("" when the file does not say).
    """

    reduced: control.StateSpace
    full: control.StateSpace | None
    mu_peak: float | None
    mu_peak_reduced: float | None
    problem_sha256: str
    seed: int
    details: dict[str, Any] = field(default_factory=dict)
    toolkit_version: str = field(default_factory=_toolkit_version)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready dict: the reduced A, B, C, D at the top level, as rows."""
        payload: dict[str, Any] = {
            "format_version": CONTROLLER_FORMAT_VERSION,
            "input": "attitude error e = reference - measured [deg] (phi, theta, psi)",
            "output": "torque demand [mNm] (x, y, z), u = K e",
            **_matrices(self.reduced),
            "mu_peak": self.mu_peak,
            "mu_peak_reduced": self.mu_peak_reduced,
            "order_full": None if self.full is None else self.full.nstates,
            "order_reduced": self.reduced.nstates,
            "problem_sha256": self.problem_sha256,
            "seed": self.seed,
            "toolkit_version": self.toolkit_version,
        }
        if self.full is not None:
            payload["full"] = _matrices(self.full)
        payload.update(self.details)
        return payload

    @classmethod
    def from_dict(cls, data: dict[str, Any], source: str | None = None) -> Controller:
        """Rebuild from :meth:`to_dict` output; names the missing or bad key."""
        for key in REQUIRED_KEYS:
            if key not in data:
                raise ProblemFileError(key, "missing from the controller file", source)
        version = data.get("format_version", CONTROLLER_FORMAT_VERSION)
        if isinstance(version, bool) or version != CONTROLLER_FORMAT_VERSION:
            raise ProblemFileError(
                "format_version",
                f"this toolkit reads controller files of format {CONTROLLER_FORMAT_VERSION}, "
                f"got {version!r}",
                source,
            )
        for key in ("mu_peak", "mu_peak_reduced"):
            value = data.get(key)
            if value is None:
                continue
            if isinstance(value, bool) or not isinstance(value, int | float) or not value >= 0:
                raise ProblemFileError(key, f"must be a non-negative number, got {value!r}", source)
        reduced = _system(data, "", source)
        full = _system(data["full"], "full.", source) if "full" in data else None
        known = {
            "format_version",
            "input",
            "output",
            "full",
            "problem_sha256",
            "seed",
            "toolkit_version",
        }
        details = {
            k: v
            for k, v in data.items()
            if k not in known and k not in REQUIRED_KEYS and k not in DESIGN_KEYS
        }
        return cls(
            reduced=reduced,
            full=full,
            mu_peak=_optional_float(data.get("mu_peak")),
            mu_peak_reduced=_optional_float(data.get("mu_peak_reduced")),
            problem_sha256=str(data.get("problem_sha256", "")),
            seed=int(data.get("seed", 0)),
            details=details,
            toolkit_version=str(data.get("toolkit_version", "")),
        )


def _optional_float(value: Any) -> float | None:
    return None if value is None else float(value)


def _matrices(system: control.StateSpace) -> dict[str, list]:
    return {
        name: np.asarray(m, dtype=float).tolist()
        for name, m in zip("ABCD", control.ssdata(system), strict=True)
    }


def _system(data: dict[str, Any], prefix: str, source: str | None) -> control.StateSpace:
    """A 3-input, 3-output state-space system from its rows, every shape and value checked."""
    key = f"{prefix}A/B/C/D"
    try:
        a, b, c, d = (np.array(data[k], dtype=float) for k in "ABCD")
    except (KeyError, TypeError, ValueError) as exc:
        raise ProblemFileError(key, f"not numeric matrices ({exc})", source) from None
    n = a.shape[0] if a.ndim == 2 else -1
    if a.size == 0:
        n = 0
        a = a.reshape(0, 0)
        b = b.reshape(0, 3) if b.size == 0 else b
        c = c.reshape(3, 0) if c.size == 0 else c
    shapes = {"A": (n, n), "B": (n, 3), "C": (3, n), "D": (3, 3)}
    for name, matrix in zip("ABCD", (a, b, c, d), strict=True):
        if n < 0 or matrix.shape != shapes[name]:
            raise ProblemFileError(
                f"{prefix}{name}",
                f"must be {shapes['A'][0] if n >= 0 else 'n'} states of a 3-input, "
                f"3-output system: A n x n, B n x 3, C 3 x n, D 3 x 3; got {matrix.shape}",
                source,
            )
        if not np.all(np.isfinite(matrix)) or np.any(np.abs(matrix) > MAX_ENTRY):
            raise ProblemFileError(
                f"{prefix}{name}", f"entries must be finite and at most {MAX_ENTRY:g}", source
            )
    return control.ss(a, b, c, d)
