"""Run summaries for tests of what stores and reads them (not of what computes them)."""

from __future__ import annotations

import dataclasses
import typing
from typing import Any

from casadi_debris.simulation import RunSummary


def zero_run_summary(**figures: Any) -> RunSummary:
    """A run summary with every field a zero of its type, except ``figures``."""
    zeros: dict[Any, Any] = {float: 0.0, int: 0, bool: False, str: ""}
    hints = typing.get_type_hints(RunSummary)
    values = {}
    for field in dataclasses.fields(RunSummary):
        origin = typing.get_origin(hints[field.name])
        values[field.name] = {tuple: (), dict: {}}.get(origin, zeros.get(hints[field.name]))
    return RunSummary(**{**values, **figures})
