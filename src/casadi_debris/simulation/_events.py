"""What changes the engines during a run: failures and depleted stages, as events.

:func:`apply_failure` applies a scheduled failure to the engines' state and
:func:`depleted_event` turns the propulsion's depleted stage into a
:class:`RunEvent`; the closed loop (:mod:`~casadi_debris.simulation._run`)
rebuilds its torque authority after each.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from casadi_debris.allocation import PropulsionState, StageEvent
from casadi_debris.config import FailureEvent
from casadi_debris.simulation._summary import EventSummary

EVENT_KINDS = ("stage_depleted", "stage_failed", "cubesat_failed", "engine_failed")


@dataclass(frozen=True)
class RunEvent:
    """Something that changed the engines during a run.

    Attributes
    ----------
    time_s : float
        When [s].
    kind : {"stage_depleted", "stage_failed", "cubesat_failed", "engine_failed"}
    cubesat : int
        0-based (``text`` and the summary number CubeSats from 1).
    stage : int or None
        The stage depleted or failed (0-based); None for a whole CubeSat or engine.
    next_stage : int or None
        The stage firing afterwards; None when the CubeSat has none left.
    switched : bool
        Whether the stage that fires changed (a depleted stage always; a failed
        stage only when it was the one firing).
    engine : int or None
        The engine that failed or whose stage ran dry, counted among its
        CubeSat's own engines (0-based), for a CubeSat with several; None otherwise.
    """

    time_s: float
    kind: str
    cubesat: int
    stage: int | None = None
    next_stage: int | None = None
    switched: bool = False
    engine: int | None = None

    @property
    def text(self) -> str:
        """The event in words, CubeSats, engines and stages numbered from 1."""
        who = f"CubeSat {self.cubesat + 1}"
        if self.engine is not None:
            who += f" engine {self.engine + 1}"
        if self.kind in ("cubesat_failed", "engine_failed"):
            return f"{who} failed"
        if self.kind == "stage_failed":
            return f"{who}: stage {_number(self.stage)} failed"
        then = "none left" if self.next_stage is None else f"stage {self.next_stage + 1} takes over"
        return f"{who}: stage {_number(self.stage)} empty, {then}"

    def record(self) -> EventSummary:
        """The event as a user reads it: 1-based ids, in words."""
        return EventSummary(
            time_s=self.time_s,
            kind=self.kind,
            cubesat=self.cubesat + 1,
            engine=None if self.engine is None else self.engine + 1,
            stage=None if self.stage is None else self.stage + 1,
            next_stage=None if self.next_stage is None else self.next_stage + 1,
            stage_switch=self.switched,
            event=self.text,
        )


def _number(stage: int | None) -> str:
    return "?" if stage is None else str(stage + 1)


def depleted_event(event: StageEvent, time_s: float, propulsion: PropulsionState) -> RunEvent:
    """The event of a stage that ran dry at ``time_s`` [s]."""
    siblings = np.flatnonzero(propulsion.engine_cubesat == event.cubesat)
    several = len(siblings) > 1
    return RunEvent(
        time_s,
        "stage_depleted",
        event.cubesat,
        event.stage,
        event.next_stage,
        switched=True,
        engine=int(np.searchsorted(siblings, event.engine)) if several else None,
    )


def apply_failure(failure: FailureEvent, propulsion: PropulsionState, time_s: float) -> RunEvent:
    """Fail what ``failure`` names in ``propulsion`` (in place); the event, at ``time_s`` [s]."""
    cubesat = failure.cubesat
    if failure.engine is not None:
        propulsion.fail_engine(cubesat, failure.engine)
        return RunEvent(time_s, "engine_failed", cubesat, engine=failure.engine)
    if failure.stage is None:
        propulsion.fail_cubesat(cubesat)
        return RunEvent(time_s, "cubesat_failed", cubesat)
    engines = np.flatnonzero(propulsion.engine_cubesat == cubesat)
    before = propulsion.active_stage[engines]
    propulsion.fail_stage(cubesat, failure.stage)
    after = propulsion.active_stage[engines]
    firing = after[after < propulsion.n_stages]
    return RunEvent(
        time_s,
        "stage_failed",
        cubesat,
        failure.stage,
        int(firing.min()) if len(firing) else None,
        switched=bool(np.any((after != before) & (before == failure.stage))),
    )
