"""Files written whole or not at all: JSON, CSV, and any file through a writer."""

from __future__ import annotations

import csv
import json
import os
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.records import Record, to_jsonable
from casadi_debris.store._folders import temporary_path


def json_ready(value: Any) -> Any:
    """``value`` for ``json.dumps``: records by field, numpy as lists, non-finite as None."""
    return to_jsonable(value)


def write_csv(path: Path, columns: dict[str, np.ndarray]) -> Path:
    """Columns of equal length as CSV, names in the header."""
    with path.open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(columns)
        writer.writerows(np.column_stack(list(columns.values())).tolist())
    return path


def write_json_atomic(path: str | Path, payload: dict[str, Any] | Record) -> Path:
    """Write JSON so that ``path`` holds either the old file or the whole new one."""
    target = Path(path).resolve()
    target.parent.mkdir(parents=True, exist_ok=True)
    temporary = temporary_path(target, "tmp")
    try:
        with temporary.open("x") as stream:
            json.dump(json_ready(payload), stream, indent=1)
            stream.write("\n")
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return target


def write_atomically(target: Path, write: Callable[[Path], None]) -> Path:
    """Write ``target`` through ``write(path)`` so that it is either whole or absent.

    ``write`` creates the file it is given: a temporary sibling of ``target``
    that names this process (removed by a later run if this one is killed),
    renamed over ``target`` once written.
    """
    temporary = temporary_path(target, "tmp")
    try:
        write(temporary)
        os.replace(temporary, target)
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    return target
