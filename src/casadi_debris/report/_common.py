"""Shared pieces of the reports: tables, figures and verdicts as text.

Writing files (JSON, CSV, atomically) is :mod:`casadi_debris.store`'s.

The paper's figures and tolerances are in :mod:`casadi_debris.report._paper`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

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
