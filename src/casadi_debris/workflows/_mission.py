"""The mission from the CubeSats' transfer to the debris' re-entry (``casadi-debris mission``).

Example
-------
>>> import casadi_debris as cd
>>> result = cd.mission("paper", solar=("mean",))  # doctest: +SKIP
>>> result.summary.meets_five_year_rule, result.summary.reentry_years  # doctest: +SKIP
(True, {'mean': 5.0})
>>> result.save("runs/mission-paper")  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.config import check_transfer_end
from casadi_debris.orbit import DeorbitSettings
from casadi_debris.report import mission_figures, write_mission
from casadi_debris.studies.mission import Mission, MissionSummary, plan_mission
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure


@dataclass(frozen=True)
class MissionResult(JobResult):
    """The mission: its summary and what its figures draw.

    Attributes
    ----------
    summary : MissionSummary
        The phases, the propellant books, each solar case's re-entry and the verdict
        (what ``summary.json`` holds).
    mission : Mission
        The detumble run, each case's decay, the deorbit plan and its model (SI).
    horizon_years : float
        How long the decay was flown [years]: a later re-entry is reported as None.
    """

    summary: MissionSummary
    mission: Mission
    horizon_years: float

    command = "mission"

    def plot(self) -> dict[str, Figure]:
        """``mission`` (the timeline and the propellant per CubeSat and stage),
        ``altitude`` (mean altitude and perigee per solar case from the transfer's start)
        and ``decay`` (from the burn's start); nothing is written."""
        return mission_figures(self.mission)

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json``, ``phases.csv``, ``propellant.csv`` and, with ``plots``,
        ``mission.png``, ``altitude.png`` and ``decay.png`` (each with its PDF)."""
        write_mission(staging, self.mission, plots=plots)


def mission(
    problem: ProblemLike = None,
    *,
    solar: Sequence[str] = ("low", "mean", "high"),
    limit_years: float = 5.0,
    progress: Callable[[str], None] | None = None,
) -> MissionResult:
    """The mission to re-entry: transfer, detumble, deorbit burns, decay; the verdict.

    Each CubeSat flies the ``[transfer]`` alone (Edelbaum, rocket equation), then the
    swarm detumbles the debris in closed loop, then burns what propellant is left, engine
    by engine, to lower the orbit (least Δv per solar case, NRLMSIS, torque-free thrust),
    then the debris decays.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper. Its
        ``[transfer]`` must end on its ``[orbit]``.
    solar : sequence of str
        Solar-activity cases among ``"low"``, ``"mean"``, ``"high"``, each once.
    limit_years : float
        Re-entry within this long of the burn's start [years].
    progress : callable, optional
        ``progress(line)`` once the inputs are checked, as the long part starts.

    Returns
    -------
    MissionResult

    Raises
    ------
    ProblemFileError
        The ``[transfer]`` does not end on the debris' ``[orbit]``.
    InputShapeError
        An unknown solar case or a limit out of range (named).
    """
    problem = as_problem(problem)
    check_transfer_end(problem)
    settings = DeorbitSettings(
        solar=tuple(solar), limit_years=limit_years, minimum_swarm=False, samples=0
    )
    if progress is not None:
        progress(f"Mission of {problem.name}: transfer, detumble, deorbit, decay ...")
    planned = plan_mission(problem, settings)
    return MissionResult(
        summary=planned.summary, mission=planned, horizon_years=settings.horizon_years
    )
