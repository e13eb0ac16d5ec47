"""Controller files: the shipped paper design, or one written by ``synthesize``."""

from __future__ import annotations

import json
from pathlib import Path

from casadi_debris.config import default_controller_path, limits
from casadi_debris.config.loader import UnreadableFileError, read_regular_file
from casadi_debris.errors import ProblemFileError
from casadi_debris.robust.controller import ControllerRecord


def load_controller(path: str | Path | None = None) -> tuple[ControllerRecord, Path]:
    """Read a controller file.

    Parameters
    ----------
    path : str or Path, optional
        A JSON controller file; default the one shipped for the paper's problem.

    Returns
    -------
    ControllerRecord
    Path
        The file read, absolute.

    Raises
    ------
    ProblemFileError
        Missing, unreadable or malformed file.
    """
    resolved = Path(path or default_controller_path()).resolve()
    try:
        data = json.loads(read_regular_file(resolved, limits.MAX_CONTROLLER_BYTES))
    except UnreadableFileError as exc:
        raise ProblemFileError("", f"controller file {exc}", str(resolved)) from None
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise ProblemFileError(
            "", f"not a readable JSON controller file ({str(exc)[:200]})", str(resolved)
        ) from None
    if not isinstance(data, dict):
        raise ProblemFileError("", "a controller file holds a JSON object", str(resolved))
    return ControllerRecord.from_dict(data, str(resolved)), resolved
