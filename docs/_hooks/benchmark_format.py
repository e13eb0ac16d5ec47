"""Formatting shared by the benchmark tables: numbers, tables, reading the recorded JSON."""

from __future__ import annotations

import math
from typing import Any

Data = dict[str, Any]


class MissingFigureError(KeyError):
    """A figure a table needs is not in the recorded JSON."""


def _get(data: Data, *keys: str) -> Any:
    value: Any = data
    for key in keys:
        if not isinstance(value, dict) or key not in value:
            raise MissingFigureError(".".join(keys))
        value = value[key]
    return value


def num(value: float | None, digits: int = 3) -> str:
    """``digits`` significant figures, no exponent from 0.001 to 1e6, thousands separated."""
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "–"
    if value == 0:
        return "0"
    size = abs(value)
    if size >= 1e6 or size < 1e-3:
        mantissa, exponent = f"{value:.{max(digits - 1, 0)}e}".split("e")
        return f"{mantissa}e{int(exponent)}"
    decimals = max(0, digits - 1 - math.floor(math.log10(size)))
    return f"{value:,.{decimals}f}"


def fraction(value: float) -> str:
    """A fraction near 1 as ``1 − 8e-16``, others to 3 decimals."""
    if value == 1.0:
        return "1"
    if 0.0 < 1.0 - value < 1e-3:
        return f"1 − {num(1.0 - value, 1)}"
    return f"{value:.3f}"


def when(run: Data) -> str:
    """``2026-11-24 12:17 UTC`` from the run's ISO date (recorded in UTC)."""
    return run["date"].replace("T", " ")[:16] + " UTC"


def table(header: list[str], rows: list[list[str]], align: str | None = None) -> str:
    """A Markdown table; ``align``: one of ``l``/``r`` per column (default: first left)."""
    align = align or "l" + "r" * (len(header) - 1)
    rule = ["---:" if a == "r" else "---" for a in align]
    lines = [header, rule, *rows]
    return "\n".join("| " + " | ".join(line) + " |" for line in lines) + "\n"


def _label(key: str, labels: dict[str, str]) -> str:
    return labels.get(key, key.replace("_", " "))


def _runs(repeat: int) -> str:
    return "one run" if repeat == 1 else f"medians of {repeat} runs"


def _met(met: bool) -> str:
    return "**met**" if met else "**not met**"


def _target(value: float | None, unit: str) -> str:
    return "" if value is None else f"≤ {value:g} {unit}"
