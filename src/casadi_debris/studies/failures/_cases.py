"""The cases of a failure campaign: every set of up to k failed CubeSats, and a lost stage.

A failed CubeSat stays docked (its mass and inertia are unchanged) but none
of its engines fires again, as a ``[[simulation.failures]]`` entry without a
stage does. A *failed stage* is read as the propulsion model reads it
(:mod:`casadi_debris.allocation`): that stage of each of the
CubeSat's engines is lost and the next healthy stage takes over. Every stage
of an engine has the same thrust, so a stage lost at the start leaves the
torque authority as it was and takes away one stage of propellant (a third of
the paper's CubeSat's); only an engine with a single stage loses its thrust.
The campaign fails stage 1, the one that fires first, at time 0, so that the
run starts on stage 2.

Every failure of a case happens at time 0: the campaign asks what the swarm can
still do, not how it copes with the instant of the failure.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import comb

from casadi_debris.allocation import PropulsionState
from casadi_debris.config import FailureEvent, Problem
from casadi_debris.errors import FailureStudyError
from casadi_debris.studies.failures._sets import failure_sets

FAILED_STAGE = 0
"""The stage a stage-failure case loses (0-based): the first, so the next takes over at once."""


@dataclass(frozen=True)
class FailureCase:
    """One configuration of a failure campaign.

    Attributes
    ----------
    cubesats : tuple of int
        Failed CubeSats, 0-based, increasing (``failed`` numbers them from 1).
    stage_of : tuple of int
        CubeSats (0-based) that lost their stage :data:`FAILED_STAGE`.
    """

    cubesats: tuple[int, ...] = ()
    stage_of: tuple[int, ...] = ()

    @property
    def case_id(self) -> str:
        """``"none"``, ``"failed-3-17"`` or ``"stage-3"`` (ids from 1), unique in a campaign."""
        parts = []
        if self.cubesats:
            parts.append("failed-" + "-".join(str(i + 1) for i in self.cubesats))
        if self.stage_of:
            parts.append("stage-" + "-".join(str(i + 1) for i in self.stage_of))
        return "_".join(parts) or "none"

    @property
    def label(self) -> str:
        """What failed, in words, ids from 1."""
        parts = []
        if self.cubesats:
            parts.append("CubeSat " + ", ".join(str(i + 1) for i in self.cubesats))
        if self.stage_of:
            stage = FAILED_STAGE + 1
            parts.append(", ".join(f"stage {stage} of CubeSat {i + 1}" for i in self.stage_of))
        return "; ".join(parts) or "none"

    @property
    def events(self) -> tuple[FailureEvent, ...]:
        """The failures as a run takes them (all at time 0)."""
        return tuple(FailureEvent(0.0, i, None) for i in self.cubesats) + tuple(
            FailureEvent(0.0, i, FAILED_STAGE) for i in self.stage_of
        )

    def propulsion(self, problem: Problem) -> PropulsionState:
        """The problem's engines, full, with this case's failures applied."""
        state = PropulsionState.from_problem(problem)
        for cubesat in self.cubesats:
            state.fail_cubesat(cubesat)
        for cubesat in self.stage_of:
            state.fail_stage(cubesat, FAILED_STAGE)
        return state


def check_max_failed(max_failed: int, n_cubesats: int) -> None:
    """Refuse a count of failed CubeSats below 1 or above the swarm's size.

    Raises
    ------
    FailureStudyError
        Naming ``max_failed`` and the range.
    """
    if isinstance(max_failed, bool) or not isinstance(max_failed, int):
        raise FailureStudyError(f"max_failed must be an integer; got {max_failed!r}")
    if not 1 <= max_failed <= n_cubesats:
        raise FailureStudyError(
            f"max_failed must lie in 1..{n_cubesats} (the swarm's CubeSats); got {max_failed}"
        )


def case_count(n_cubesats: int, max_failed: int, stages: bool = False) -> int:
    """How many cases :func:`failure_cases` gives: sum of C(n, k) for k = 1..max_failed,
    plus one stage case per CubeSat."""
    return sum(comb(n_cubesats, k) for k in range(1, max_failed + 1)) + (
        n_cubesats if stages else 0
    )


def failure_cases(n_cubesats: int, max_failed: int, *, stages: bool = True) -> list[FailureCase]:
    """Every set of 1 to ``max_failed`` failed CubeSats, then one failed stage per CubeSat.

    Parameters
    ----------
    n_cubesats : int
    max_failed : int
        1 to ``n_cubesats``.
    stages : bool
        Also a case per CubeSat that loses its first stage.

    Returns
    -------
    list of FailureCase
        Singles, then pairs, ... in lexicographic order, then the stage cases
        (24 + 276 + 24 for the paper's swarm and ``max_failed = 2``).

    Raises
    ------
    FailureStudyError
        ``max_failed`` out of range.
    """
    check_max_failed(max_failed, n_cubesats)
    cases = [
        FailureCase(cubesats=failed)
        for size in range(1, max_failed + 1)
        for failed in failure_sets(range(n_cubesats), size)
    ]
    if stages:
        cases += [FailureCase(stage_of=(i,)) for i in range(n_cubesats)]
    return cases
