"""Reading problem files: TOML, ``extends`` chains, the shipped defaults."""

from __future__ import annotations

import hashlib
import tomllib
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

from casadi_debris.config.reader import problem_from_dict
from casadi_debris.config.schema import Problem
from casadi_debris.errors import ProblemFileError


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
