"""Shared pieces of the reports: tables, JSON, atomic writes.

The paper's figures and tolerances are in :mod:`casadi_debris.report._paper`.
"""

from __future__ import annotations

import csv
import json
import os
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.records import Record, to_jsonable
from casadi_debris.report.folders import temporary_path

# ----------------------------------------------------------------------------- text


def format_table(headers: Sequence[str], rows: Sequence[Sequence[Any]]) -> str:
    """Left-aligned plain-text table with a rule under the header."""
    cells = [[str(h) for h in headers]] + [[format_cell(c) for c in row] for row in rows]
    widths = [max(len(row[i]) for row in cells) for i in range(len(headers))]
    lines = [
        "  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)).rstrip() for row in cells
    ]
    lines.insert(1, "  ".join("-" * w for w in widths))
    return "\n".join(lines)


def format_cell(value: Any) -> str:
    if isinstance(value, float):
        if value == 0:
            return "0"
        return f"{value:.4g}" if 1e-3 <= abs(value) < 1e5 else f"{value:.3e}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(format_cell(v) for v in value) + "]"
    return "" if value is None else str(value)


def format_figure(value: Any, digits: int = 4) -> str:
    """A figure as a report prints it: 4 significant digits, " / " between components,
    "—" for none, yes/no for a flag."""
    if value is None:
        return "—"
    if isinstance(value, str):
        return value
    if isinstance(value, list | tuple | np.ndarray):
        return " / ".join(format_figure(v, digits) for v in value)
    if isinstance(value, bool):
        return "yes" if value else "no"
    if isinstance(value, int | np.integer):
        return str(int(value))
    return f"{float(value):.{digits}g}"


def verdict_text(outcome: bool | None, word: str) -> str:
    """A verdict as printed: ``✅ <word>``, ``❌ not <word>``, or ``—`` when not judged."""
    if outcome is None:
        return "—"
    return f"✅ {word}" if outcome else f"❌ not {word}"


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
