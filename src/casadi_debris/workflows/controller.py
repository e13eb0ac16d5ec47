"""Controller files: the shipped paper design, or one written by ``synthesize``."""

from __future__ import annotations

import json
from pathlib import Path

from casadi_debris.config import default_controller_path
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
        data = json.loads(resolved.read_text())
    except FileNotFoundError:
        raise ProblemFileError("", "no such controller file", str(resolved)) from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ProblemFileError(
            "", f"not a readable JSON controller file ({exc})", str(resolved)
        ) from None
    if not isinstance(data, dict):
        raise ProblemFileError("", "a controller file holds a JSON object", str(resolved))
    return ControllerRecord.from_dict(data, str(resolved)), resolved
