"""Controller files: the shipped paper design, or one written by ``synthesize``.

A controller file records the plant it was designed for
(:attr:`casadi_debris.config.Problem.plant_sha256`). :func:`controller_for`
gives the controller to fly on a problem and refuses one designed for another
plant unless told to fly it anyway.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

from casadi_debris.config import (
    Problem,
    default_controller_path,
    limits,
    read_regular_file,
)
from casadi_debris.errors import ControllerMismatchError, ProblemFileError, UnreadableFileError
from casadi_debris.robust.plant import Controller
from casadi_debris.store import default_run_folder

LOGGER = logging.getLogger(__name__)


def load_controller(path: str | Path | None = None) -> tuple[Controller, Path]:
    """Read a controller file.

    Parameters
    ----------
    path : str or Path, optional
        A JSON controller file; default the one shipped for the paper's problem.

    Returns
    -------
    Controller
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
    return Controller.from_dict(data, str(resolved)), resolved


def controller_for(
    problem: Problem, path: str | Path | None = None, *, allow_mismatch: bool = False
) -> tuple[Controller, Path]:
    """The controller to fly on ``problem``, checked against the plant it was designed for.

    Parameters
    ----------
    problem : Problem
    path : str or Path, optional
        A controller file. Without one, the shipped paper controller, and only
        for a problem whose plant is the paper's.
    allow_mismatch : bool
        Fly a controller designed for another plant anyway (a robustness study).

    Returns
    -------
    Controller
    Path
        The file read, absolute.

    Raises
    ------
    ControllerMismatchError
        The plants differ and ``allow_mismatch`` is false, or no file was given for a
        problem that is not the paper's. A file that records no plant (a controller
        of the user's own: only ``A``, ``B``, ``C``, ``D``) is flown as given, with a
        warning.
    """
    record, resolved = load_controller(path)
    plant = problem.plant_sha256
    if record.problem_sha256 == plant:
        return record, resolved
    if path is None and not allow_mismatch:
        raise ControllerMismatchError(
            "--controller",
            f"the shipped controller was designed for the paper's plant, and {problem.name} "
            "describes another; design one for it (casadi-debris design PROBLEM.toml) and pass "
            f"--controller {default_run_folder('design', problem.name) / 'controller.json'}, "
            "or pass --allow-mismatch to fly the paper's controller on it anyway",
        )
    if not record.problem_sha256:
        # A controller of the user's own (plain A, B, C, D): nothing to check it against.
        LOGGER.warning(
            "%s records no plant it was designed for: flying it on %s as given",
            resolved.name,
            problem.name,
        )
        return record, resolved
    if not allow_mismatch:
        designed = record.problem_sha256[:12]
        raise ControllerMismatchError(
            "--controller",
            f"{resolved.name} was designed for another plant (sha256 {designed}) than "
            f"{problem.name}'s ({plant[:12]}); pass --allow-mismatch to fly it anyway",
        )
    LOGGER.warning(
        "flying %s, designed for another plant, on %s (--allow-mismatch)",
        resolved.name,
        problem.name,
    )
    return record, resolved
