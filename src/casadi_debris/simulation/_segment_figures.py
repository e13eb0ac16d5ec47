"""A closed-loop run of a manoeuvre, figured segment by segment."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.guidance import Piece, segment_records
from casadi_debris.records import Record
from casadi_debris.simulation._run import ClosedLoopResult
from casadi_debris.simulation._summary import fuel_between_kg
from casadi_debris.units import ARCSEC_PER_RAD


@dataclass(frozen=True)
class SegmentRunSummary(Record):
    """One segment of a closed-loop run.

    Attributes
    ----------
    segment : int or None
        Its ``[[simulation.segments]]`` entry from 1; None for a hold the sequence adds.
    kind : {"slew", "hold", "track"}
    start_s, end_s : float
    max_error_deg, max_error_arcsec : float
        Largest attitude error component over the control instants in [start, end].
    fuel_kg : float
        Propellant the engines burnt in the steps starting in [start, end).
    """

    segment: int | None
    kind: str
    start_s: float
    end_s: float
    max_error_deg: float
    max_error_arcsec: float
    fuel_kg: float


def segment_figures(
    result: ClosedLoopResult, pieces: tuple[Piece, ...] | list[Piece]
) -> tuple[SegmentRunSummary, ...]:
    """Each piece of the reference ``result`` flew, with its largest error and its fuel."""
    figures = []
    for record in segment_records(pieces):
        inside = (result.time_s >= record.start_s) & (result.time_s <= record.end_s)
        peak = float(np.abs(result.error_rad[inside]).max()) if inside.any() else 0.0
        figures.append(
            SegmentRunSummary(
                segment=record.segment,
                kind=record.kind,
                start_s=record.start_s,
                end_s=record.end_s,
                max_error_deg=math.degrees(peak),
                max_error_arcsec=peak * ARCSEC_PER_RAD,
                fuel_kg=fuel_between_kg(result, record.start_s, record.end_s),
            )
        )
    return tuple(figures)
