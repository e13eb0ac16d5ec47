"""A Monte-Carlo campaign (``casadi-debris montecarlo``): the cases chosen, flown in
parallel, summarised with the nominal run and their statistics.

Given a folder (``out``), the campaign writes every case as it finishes into
``<out>.partial`` and resumes from there after an interruption, as the command does;
without one it runs in memory and :meth:`MonteCarloResult.save` writes the same files
later.

Example
-------
>>> import casadi_debris as cd
>>> mc = cd.montecarlo("paper_slew", max_cases=8, workers=2)  # doctest: +SKIP
>>> mc.summary.worst["max_error_deg"].value  # doctest: +SKIP
>>> mc.dataset.fuel_kg.to_pandas().describe()  # doctest: +SKIP
>>> mc.save("runs/slew-mc")  # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
import hashlib
import logging
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from casadi_debris.allocation import Allocator
from casadi_debris.campaigns import (
    DEFAULT_BATCH_CASES,
    CampaignSetup,
    Case,
    CaseFailure,
    CaseResult,
    nominal_case,
    run_campaign,
    statistics_of,
)
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, build_model
from casadi_debris.errors import (
    CampaignInterrupted,
    CasesFailedError,
    InputShapeError,
    SchedulerError,
)
from casadi_debris.guidance import scenario_reference
from casadi_debris.report import (
    CampaignRun,
    CampaignSummary,
    FailedCase,
    campaign_envelope,
    campaign_summary,
    write_campaign,
)
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import ClosedLoopResult, c_compiler, simulate_closed_loop
from casadi_debris.store import (
    RECORD_NAME,
    CampaignFolder,
    CampaignIdentity,
    check_output_folder,
    write_case,
    write_failure,
    write_json_atomic,
)
from casadi_debris.workflows._campaign import (
    CaseSelection,
    Progress,
    SimulationSummary,
    check_scheduler_address,
    run_summary,
)
from casadi_debris.workflows._controller import controller_for
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

LOGGER = logging.getLogger(__name__)

NOMINAL_KEYS = (
    "fuel_slew_kg",
    "max_error_deg",
    "max_error_arcsec",
    "fuel_kg",
    "settle_time_s",
    "torque_saturated_s",
    "max_torque_mNm",
)
"""The nominal run's figures a campaign summary gives beside the worst cases."""


@dataclass(frozen=True)
class MonteCarloResult(JobResult):
    """A finished campaign: every case, the nominal run, the summary and the statistics.

    Attributes
    ----------
    problem : Problem
    summary : CampaignSummary
        What ``summary.json`` holds (and ``--json`` prints): the worst case of every
        figure, the nominal run's figures, the statistics; ``summary.run.out_dir`` is
        None for a campaign run without a folder.
    record : CampaignIdentity
        What identifies the campaign (``campaign.json``: hashes, case list, bins).
    setup : CampaignSetup
        What every case shared (controller, reference, time bins).
    outcomes : tuple of CaseResult
        Every finished case (resumed or run), in campaign order: its figures and its
        min/max bands per time bin.
    failures : tuple of CaseFailure
        The cases of this run that raised (the campaign went on without them).
    nominal : ClosedLoopResult
        The nominal run, SI units.
    nominal_summary : SimulationSummary
        Its figures in display units.
    """

    problem: Problem
    summary: CampaignSummary
    record: CampaignIdentity
    setup: CampaignSetup
    outcomes: tuple[CaseResult, ...]
    failures: tuple[CaseFailure, ...]
    nominal: ClosedLoopResult
    nominal_summary: SimulationSummary

    command = "montecarlo"

    @property
    def dataset(self) -> xr.Dataset:
        """Every case as labelled arrays (what ``campaign.nc`` holds; see
        :func:`casadi_debris.store.open_campaign`): the figures per ``case``, the
        bands per ``case``, ``time``, ``bound`` and ``axis``, the parameters."""
        from casadi_debris.campaigns import campaign_dataset

        names = list(self.nominal.parameters)
        return campaign_dataset(self.record, self.setup.bin_start_s, list(self.outcomes), names)

    def plot(self) -> dict[str, Figure]:
        """The campaign's figures by the file stem ``save`` writes them under:
        ``envelope`` (the nominal run inside the cases' min/max), ``statistics``
        (histograms against the requirement, rank correlations), and the nominal run's
        ``nominal/closed_loop`` and ``nominal/thrust``. Nothing is written; close them
        with ``matplotlib.pyplot.close``."""
        from casadi_debris.report import campaign_figures, run_figures

        outcomes = list(self.outcomes)
        envelope = campaign_envelope(self.setup, outcomes)
        figures = campaign_figures(self.problem, outcomes, self.nominal, self.summary, envelope)
        nominal = run_figures(self.nominal, self.problem)
        return {**figures, **{f"nominal/{name}": f for name, f in nominal.items()}}

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``campaign.json`` and ``cases/`` (every case's bands and figures, every failure
        with its traceback), then the tables, ``campaign.nc``, ``nominal/`` and the
        figures (with ``plots``): the folder the command leaves."""
        write_json_atomic(staging / RECORD_NAME, self.record.to_dict())
        for outcome in self.outcomes:
            write_case(staging, outcome.case.case_id, outcome.bands.to_arrays(), outcome.summary)
        for failure in self.failures:
            write_failure(staging, failure.case.case_id, failure.summary())
        self._write_tables(staging, out, plots=plots)

    def _write_tables(self, staging: Path, out: Path, *, plots: bool) -> None:
        """What follows the cases: the summary (naming ``out``), ``cases.csv``,
        ``envelope.csv``, ``campaign.nc``, ``nominal/`` and the figures."""
        run = dataclasses.replace(self.summary.run, out_dir=str(out.absolute()))
        write_campaign(
            staging,
            self.problem,
            self.setup,
            list(self.outcomes),
            self.nominal,
            self.nominal_summary,
            dataclasses.replace(self.summary, run=run),
            self.record,
            with_plots=plots,
        )


def montecarlo(
    problem: ProblemLike = None,
    *,
    corners: bool = False,
    samples: int | None = None,
    seed: int | None = None,
    max_cases: int | None = None,
    workers: int | None = None,
    scheduler: str | None = None,
    controller: str | Path | None = None,
    allow_mismatch: bool = False,
    no_jit: bool = False,
    batch_cases: int = DEFAULT_BATCH_CASES,
    out: str | Path | None = None,
    overwrite: bool = False,
    progress: Progress | None = None,
    moved_to: tuple[Path, Path] | None = None,
) -> MonteCarloResult:
    """Fly the problem's reference over the corners of its uncertainty set (the paper's
    256), seeded random samples, or the draws of its ``[[montecarlo.vary]]``.

    A campaign runs for minutes to hours, so the folder may be given up front: with
    ``out``, each case is written into ``<out>.partial`` as it finishes, a campaign
    interrupted resumes from there when called again with the same inputs, and the
    folder is moved to ``out`` whole at the end (what ``montecarlo --out`` does).
    Without ``out`` nothing is written; ``save(folder)`` writes the same files later.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name (``"paper_slew"``); default the paper.
    corners, samples, seed, max_cases : optional
        Every corner of the uncertainty set (the default without ``[[montecarlo.vary]]``),
        or ``samples`` seeded random samples (with ``[[montecarlo.vary]]``: draws; seed
        default the problem's ``montecarlo.seed``); ``max_cases`` keeps that many cases
        spread evenly over the list (a quick look).
    workers, scheduler : optional
        Local worker processes (default one per core), or a Dask scheduler address
        (``tcp://host:8786``, ``tls://...``; Dask unpickles what it sends: trust it).
    controller, allow_mismatch : optional
        A controller file (``controller.json`` of ``design``; default the shipped paper
        controller, for the paper's plant only); fly one of another plant anyway.
    no_jit, batch_cases : optional
        Run the step on CasADi's virtual machine even where a C compiler is found; cases
        per compiled call (1: one by one), the numbers the same either way.
    out, overwrite : optional
        The campaign folder, written as the campaign goes (see above); replace one this
        toolkit wrote there.
    progress : callable, optional
        ``progress(done, total)`` as the cases this call runs finish.
    moved_to : (Path, Path), optional
        ``(staging, final)``: ``out`` and the controller lie in a report's staging
        folder, moved to ``final`` later; the summaries record the final paths.

    Returns
    -------
    MonteCarloResult

    Raises
    ------
    InputShapeError, OutputError
        An option that does not fit, a folder that cannot be written (named).
    CampaignInterrupted
        On Ctrl-C; with ``out`` the finished cases stay for a resume.
    CasesFailedError
        Every case raised (a case that raises is recorded and the rest go on).
    """
    problem = as_problem(problem)
    if scheduler is not None:
        check_scheduler_address(scheduler)
    if out is not None:
        check_output_folder(Path(out), overwrite=overwrite)
    how = _How.of(workers, scheduler, jit=not no_jit)
    selection = CaseSelection(corners, samples, seed, max_cases)
    plan = _Plan.create(problem, selection, controller, allow_mismatch, not no_jit, batch_cases)
    if out is None:
        outcomes, failures = _run_missing(plan.setup, plan.cases, {}, None, how, progress)
        run = _described(plan, plan.controller_path, None, 0, failures, how)
        return _finished(plan, outcomes, failures, run)
    return _into_folder(plan, Path(out), overwrite, how, progress, moved_to)


@dataclass(frozen=True)
class _Plan:
    """What a campaign flies: the problem's model, the controller, the cases."""

    record: Controller
    controller_path: Path
    model: Model
    cases: list[Case]
    setup: CampaignSetup
    identity: CampaignIdentity

    @classmethod
    def create(
        cls,
        problem: Problem,
        selection: CaseSelection,
        controller: str | Path | None,
        allow_mismatch: bool,
        jit: bool,
        batch_cases: int,
    ) -> _Plan:
        record, resolved = controller_for(problem, controller, allow_mismatch=allow_mismatch)
        model = build_model(problem)
        cases = selection.cases(model)
        reference = scenario_reference(problem)
        setup = CampaignSetup.create(
            problem, record.reduced, reference, jit=jit, batch_cases=batch_cases
        )
        return cls(record, resolved, model, cases, setup, _identity(setup, cases, resolved))


def _into_folder(
    plan: _Plan,
    out: Path,
    overwrite: bool,
    how: _How,
    progress: Progress | None,
    moved_to: tuple[Path, Path] | None,
) -> MonteCarloResult:
    """The campaign written case by case into ``<out>.partial`` (resumed from the cases
    already there), then its tables, and the folder moved to ``out``."""
    with CampaignFolder.open(out, plan.identity, overwrite=overwrite) as folder:
        done = _finished_cases(folder, plan.cases)
        outcomes, failures = _run_missing(plan.setup, plan.cases, done, folder, how, progress)
        controller, final = (_final(p, moved_to) for p in (plan.controller_path, out.absolute()))
        run = _described(plan, controller, final, len(done), failures, how)
        result = _finished(plan, outcomes, failures, run)
        result._write_tables(folder.partial, final, plots=True)
        folder.finish()
    return result


@dataclass(frozen=True)
class _How:
    """How the cases ran: local processes or a Dask scheduler, a compiled step or not."""

    workers: int
    scheduler: str | None
    compiled_step: bool

    @classmethod
    def of(cls, workers: int | None, scheduler: str | None, *, jit: bool) -> _How:
        """``workers`` (None: one per core); the step compiled if ``jit`` and a compiler
        is found."""
        count = (os.cpu_count() or 1) if workers is None else workers
        return cls(count, scheduler, compiled_step=bool(jit and c_compiler()))


def _described(
    plan: _Plan,
    controller_path: Path,
    out: Path | None,
    resumed_cases: int,
    failures: list[CaseFailure],
    how: _How,
) -> CampaignRun:
    """What was run and how, as the summary gives it beside the worst cases: the files
    and plants it names (the controller and the folder, as they will end up)."""
    return CampaignRun(
        controller_path=str(controller_path),
        controller_sha256=plan.identity.controller_sha256,
        plant_sha256=plan.setup.problem.plant_sha256,
        controller_plant_sha256=plan.record.problem_sha256,
        out_dir=None if out is None else str(out),
        case_kind=plan.identity.case_kind,
        seed=plan.identity.seed,
        workers=how.workers,
        scheduler=how.scheduler,
        resumed_cases=resumed_cases,
        compiled_step=how.compiled_step,
        failed_cases=[FailedCase(f.case.case_id, f.error_type, f.message) for f in failures],
    )


def _final(path: Path, moved_to: tuple[Path, Path] | None) -> Path:
    """Where ``path`` will be once a staging folder is moved (``(staging, final)``)."""
    if moved_to is None:
        return path
    staging, final = (Path(p).absolute() for p in moved_to)
    try:
        return final / Path(path).absolute().relative_to(staging)
    except ValueError:
        return path


def _finished(
    plan: _Plan, outcomes: list[CaseResult], failures: list[CaseFailure], run: CampaignRun
) -> MonteCarloResult:
    """Run the nominal case and summarise the campaign (worst cases, statistics)."""
    setup, model, identity = plan.setup, plan.model, plan.identity
    if not outcomes:
        raise CasesFailedError(failures)  # nothing to summarise; a folder stays for a resume
    problem = setup.problem
    allocator = Allocator.from_problem(problem, model.geometry)
    nominal = simulate_closed_loop(model, setup.controller, setup.reference, allocator=allocator)
    nominal_summary = run_summary(problem, nominal_case(model), nominal, Path(run.controller_path))
    statistics = statistics_of(
        problem, outcomes, model.parameter_layout.names, len(run.failed_cases)
    )
    LOGGER.info(
        "%s: %d of %d cases within %s <= %g",
        problem.name,
        statistics.passed,
        statistics.cases + statistics.failed_cases,
        statistics.requirement_figure,
        statistics.requirement,
    )
    nominal_figures = {key: getattr(nominal_summary.run, key) for key in NOMINAL_KEYS}
    return MonteCarloResult(
        problem=problem,
        summary=campaign_summary(problem, setup, outcomes, nominal_figures, run, statistics),
        record=identity,
        setup=setup,
        outcomes=tuple(outcomes),
        failures=tuple(failures),
        nominal=nominal,
        nominal_summary=nominal_summary,
    )


def _identity(setup: CampaignSetup, cases: list[Case], controller_path: Path) -> CampaignIdentity:
    """What the campaign is, as its folder records it for a resume."""
    return CampaignIdentity(
        problem_name=setup.problem.name,
        problem_sha256=setup.problem.sha256,
        controller_sha256=hashlib.sha256(controller_path.read_bytes()).hexdigest(),
        case_kind=cases[0].kind,
        seed=cases[0].seed,
        case_ids=tuple(c.case_id for c in cases),
        envelope_bin_s=setup.bin_s,
    )


def _run_missing(
    setup: CampaignSetup,
    cases: list[Case],
    done: dict[str, CaseResult],
    folder: CampaignFolder | None,
    how: _How,
    progress: Progress | None,
) -> tuple[list[CaseResult], list[CaseFailure]]:
    """Run the cases not in ``done``, each written into ``folder`` (if any) as it finishes.

    Returns every finished case (resumed or run), in campaign order, and the
    cases of this run that raised (each recorded in the folder as it fails).
    """
    todo = [c for c in cases if c.case_id not in done]
    LOGGER.info(
        "%s: %d cases (%d on disk, %d to run)",
        setup.problem.name,
        len(cases),
        len(done),
        len(todo),
    )
    finished: dict[str, CaseResult] = {}
    failures: list[CaseFailure] = []

    def keep(outcome: CaseResult) -> None:
        if folder is not None:
            folder.write_case(outcome.case.case_id, outcome.bands.to_arrays(), outcome.summary)
        finished[outcome.case.case_id] = outcome
        if progress is not None:
            progress(len(finished) + len(failures), len(todo))

    def record(failure: CaseFailure) -> None:
        failures.append(failure)
        where = (
            ""
            if folder is None
            else f" (traceback in cases/{_write_failure(folder, failure).name})"
        )
        LOGGER.warning(
            "%s failed (%s: %s); the campaign goes on without it%s",
            failure.case.case_id,
            failure.error_type,
            failure.message,
            where,
        )
        if progress is not None:
            progress(len(finished) + len(failures), len(todo))

    try:
        if progress is not None:
            progress(0, len(todo))
        run_campaign(
            setup,
            todo,
            workers=how.workers,
            scheduler=how.scheduler,
            on_result=keep,
            on_failure=record,
        )
    except KeyboardInterrupt:
        # What a resume will find: a Ctrl-C between a case's write and its count leaves
        # one more case on disk than counted here.
        kept = len(done) + len(finished) if folder is None else len(_finished_cases(folder, cases))
        if folder is None:
            raise KeyboardInterrupt(
                f"interrupted after {kept} of {len(cases)} cases; give a folder (out=...) "
                "to keep finished cases for a resume"
            ) from None
        raise CampaignInterrupted(kept, len(cases), folder.partial) from None
    except SchedulerError as exc:
        raise InputShapeError(f"--scheduler: {exc}") from None
    every = {**done, **finished}
    return [every[c.case_id] for c in cases if c.case_id in every], failures


def _finished_cases(folder: CampaignFolder, cases: list[Case]) -> dict[str, CaseResult]:
    """The cases of ``cases`` already written in ``folder``, as outcomes."""
    by_id = {case.case_id: case for case in cases}
    return folder.finished_cases(
        by_id,
        lambda case_id, summary, arrays: CaseResult.from_saved(by_id[case_id], summary, arrays),
    )


def _write_failure(folder: CampaignFolder, failure: CaseFailure) -> Path:
    """A case that raised, as ``cases/<id>.failed.json`` (a resume runs it again)."""
    return folder.write_failure(failure.case.case_id, failure.summary())
