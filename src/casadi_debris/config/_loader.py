"""Reading problem files: TOML, ``extends`` chains, the shipped defaults.

Only regular files are read (never a FIFO, a terminal or a device, which could
block or never end), each of at most ``limits.MAX_FILE_BYTES``, and an
``extends`` chain holds at most ``limits.MAX_EXTENDS_DEPTH`` files below the
one loaded.
"""

from __future__ import annotations

import difflib
import hashlib
import os
import stat
import tomllib
from collections.abc import Mapping
from importlib import resources
from pathlib import Path
from typing import Any

from casadi_debris.config._reader import problem_from_dict
from casadi_debris.config._schema import Problem
from casadi_debris.config._table import show
from casadi_debris.config.limits import MAX_EXTENDS_DEPTH, MAX_FILE_BYTES
from casadi_debris.errors import ProblemFileError, UnreadableFileError


def _merge(base: Mapping[str, Any], override: Mapping[str, Any]) -> dict[str, Any]:
    merged = dict(base)
    for key, value in override.items():
        if isinstance(value, Mapping) and isinstance(merged.get(key), Mapping):
            merged[key] = _merge(merged[key], value)
        else:
            merged[key] = value
    return merged


# A child file's CubeSats replace the parent's, however either gives them.
_ALTERNATIVES = {"cubesats": "cubesat_layout", "cubesat_layout": "cubesats"}


def merge_problem(base: Mapping[str, Any], child: Mapping[str, Any]) -> dict[str, Any]:
    """A child problem file over its parent (``extends``).

    Tables merge key by key; arrays (``[[arrays]]``, ``[[cubesats]]``, any list)
    and scalars are replaced whole. A child that gives its CubeSats (as a
    ``[[cubesats]]`` list or a ``[cubesat_layout]``) drops the parent's, in
    either form.
    """
    trimmed = {
        key: value
        for key, value in base.items()
        if not any(key == _ALTERNATIVES.get(given) for given in child)
    }
    return _merge(trimmed, child)


def read_regular_file(path: Path, max_bytes: int = MAX_FILE_BYTES) -> bytes:
    """The bytes of a regular file of at most ``max_bytes``.

    Every file a user names (problem files, controllers, tables, stage states)
    is read through this.

    Checked before opening (a FIFO would block the open, a device such as
    /dev/zero never ends), opened without blocking, and checked again on the
    open descriptor in case the path was swapped in between.

    Raises
    ------
    UnreadableFileError
        Missing, not a regular file, too large, or unreadable.
    """
    try:
        if not stat.S_ISREG(os.stat(path).st_mode):
            raise UnreadableFileError("is not a regular file")
        flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
        descriptor = os.open(path, flags | getattr(os, "O_CLOEXEC", 0))
        try:
            if not stat.S_ISREG(os.fstat(descriptor).st_mode):
                raise UnreadableFileError("is not a regular file")
            # One byte more than allowed tells a file over the limit (st_size can lie: /proc).
            raw = os.read(descriptor, max_bytes + 1)
            while len(raw) <= max_bytes:
                more = os.read(descriptor, max_bytes + 1 - len(raw))
                if not more:
                    break
                raw += more
        finally:
            os.close(descriptor)
    except UnreadableFileError:
        raise  # already says why (it is an OSError too, so it must pass the next clause)
    except FileNotFoundError:
        raise UnreadableFileError("does not exist") from None
    except OSError as exc:
        raise UnreadableFileError(f"cannot be read ({exc.strerror or exc})") from None
    except ValueError:  # a NUL byte in the path
        raise UnreadableFileError("is not a valid path") from None
    if len(raw) > max_bytes:
        raise UnreadableFileError(f"is larger than {max_bytes} bytes")
    return raw


def _parse(raw: bytes) -> dict[str, Any]:
    """TOML of ``raw``; raises UnreadableFileError for anything that is not valid TOML."""
    try:
        return tomllib.loads(raw.decode("utf-8"))
    except RecursionError:
        raise UnreadableFileError("is not valid TOML (nested too deeply)") from None
    except ValueError as exc:  # TOMLDecodeError, UnicodeDecodeError, integers of 4300+ digits
        raise UnreadableFileError(f"is not valid TOML ({str(exc)[:200]})") from None


def _parent_path(path: Path, parent: Any, chain: tuple[Path, ...]) -> Path:
    """The resolved file ``extends = parent`` of ``path`` names, checked."""
    source = str(path)
    if not isinstance(parent, str) or not parent:
        raise ProblemFileError("extends", f"must be a path string, got {show(parent)}", source)
    if len(chain) >= MAX_EXTENDS_DEPTH:
        raise ProblemFileError(
            "extends", f"chains at most {MAX_EXTENDS_DEPTH} files below the one loaded", source
        )
    try:
        resolved = (path.parent / parent).resolve()
        if not resolved.exists():
            resolved = problem_path(parent).resolve()
    except (OSError, RuntimeError, ValueError):  # a symlink loop, a NUL byte
        raise ProblemFileError("extends", f"{show(parent)} is not a valid path", source) from None
    if resolved in (*chain, path):
        names = [str(p) for p in (*chain, path, resolved)]
        raise ProblemFileError("extends", f"circular chain {names}", source)
    return resolved


def _read_toml(path: Path, chain: tuple[Path, ...] = ()) -> tuple[dict[str, Any], bytes]:
    """Parse a problem file, following ``extends``; returns data and the bytes hashed.

    Errors in the loaded file name it; errors in a file it extends name
    ``extends`` in the file that points there.
    """
    try:
        raw = read_regular_file(path)
        data = _parse(raw)
    except UnreadableFileError as exc:
        missing = str(exc) == "does not exist"
        if not chain:
            message = f"no such problem file {_nor_shipped(path)}" if missing else str(exc)
            raise ProblemFileError("", message, str(path)) from None
        hint = f" {_nor_shipped(path)}" if missing else ""
        raise ProblemFileError("extends", f"{path} {exc}{hint}", str(chain[-1])) from None
    parent = data.get("extends")
    if parent is None:
        return data, raw
    base, base_raw = _read_toml(_parent_path(path, parent, chain), (*chain, path))
    try:
        return merge_problem(base, data), base_raw + raw
    except RecursionError:
        raise ProblemFileError("", "tables nested too deeply", str(path)) from None


def _nor_shipped(path: Path) -> str:
    """What to say of a missing problem file: the shipped problem whose name is closest
    to its name (a typo of ``paper_slew``), if one is close, and where the list is."""
    names = list(shipped_problems())
    close = difflib.get_close_matches(path.name.removesuffix(".toml"), names, n=1, cutoff=0.6)
    if path.suffix in ("", ".toml") and close:
        return (
            f"(nor a shipped problem: did you mean {close[0]}? casadi-debris problems lists them)"
        )
    return "(nor a shipped problem: casadi-debris problems lists them)"


def shipped_problems() -> dict[str, Path]:
    """The problem files shipped with the toolkit, by name (file name without ``.toml``).

    The paper's (``paper``, ``paper_slew``, ``paper_pointing``) and the gallery's.
    A command or an ``extends`` that names one of these, and no file of that name
    exists where it looks, reads the shipped file.
    """
    root = Path(str(resources.files("casadi_debris") / "problems"))
    # The paper's first, then the gallery's (sub-folders), each by name.
    paths = sorted(root.rglob("*.toml"), key=lambda p: (len(p.relative_to(root).parts), p.name))
    return {path.stem: path for path in paths}


def problem_path(name_or_path: str | Path) -> Path:
    """The file ``name_or_path`` means: that file if it exists, else the shipped problem
    of that name (``"paper_slew"`` or ``"paper_slew.toml"``), else the path as given."""
    path = Path(name_or_path)
    if path.exists() or len(path.parts) != 1 or path.suffix not in ("", ".toml"):
        return path
    return shipped_problems().get(path.name.removesuffix(".toml"), path)


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
        A TOML problem file, or the name of a shipped one (see
        :func:`shipped_problems`); default the shipped ``problems/paper.toml``.

    Returns
    -------
    Problem
        Frozen, validated parameters; ``sha256`` hashes the file (and the
        files it extends).

    Raises
    ------
    ProblemFileError
        Missing, unreadable or oversized file (or not a regular file: no FIFO,
        no device), invalid TOML, a broken ``extends`` chain, or a bad key
        (named).
    """
    try:
        resolved = problem_path(path).resolve() if path is not None else default_problem_path()
    except (OSError, RuntimeError, ValueError):  # a symlink loop, a NUL byte
        raise ProblemFileError("", "is not a valid path", str(path)) from None
    data, raw = _read_toml(resolved)
    return problem_from_dict(data, str(resolved), hashlib.sha256(raw).hexdigest())
