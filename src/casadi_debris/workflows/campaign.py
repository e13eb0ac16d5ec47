"""A Monte-Carlo campaign into a folder: cases chosen, run in parallel, written as they
finish, resumed after an interruption, summarised with the nominal run.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.workflows.campaign import CaseSelection, run_campaign_folder
>>> problem = load_problem("problems/paper_slew.toml")  # doctest: +SKIP
>>> summary = run_campaign_folder(  # doctest: +SKIP
...     problem, None, CaseSelection(max_cases=8), "runs/slew-mc", workers=2
... )
>>> summary["worst"]["max_error_deg"]  # doctest: +SKIP
>>> from casadi_debris.report.campaign_dataset import open_campaign
>>> ds = open_campaign("runs/slew-mc")  # doctest: +SKIP
"""

from __future__ import annotations

import hashlib
import logging
import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import Problem
from casadi_debris.dynamics import Model, Parameters, build_model
from casadi_debris.errors import CampaignInterrupted, InputShapeError, ModelError
from casadi_debris.guidance import scenario_reference
from casadi_debris.records import FLATTENED, OPTIONAL, Record
from casadi_debris.report.campaign_folder import CampaignFolder, CampaignRecord
from casadi_debris.report.folders import check_output_folder
from casadi_debris.report.simulation import (
    CampaignRun,
    CampaignSummary,
    FailedCase,
    campaign_summary,
    write_campaign,
)
from casadi_debris.robust.controller import ControllerRecord
from casadi_debris.robust.uncertainty import normalized_from_parameters
from casadi_debris.simulation import (
    CampaignSetup,
    Case,
    CaseOutcome,
    ClosedLoopResult,
    corner_case,
    corner_cases,
    nominal_case,
    run_campaign,
    sample_case,
    sample_cases,
    simulate,
)
from casadi_debris.simulation.closed_loop import SimulationError, c_compiler
from casadi_debris.simulation.monte_carlo import (
    DEFAULT_BATCH_CASES,
    CaseFailure,
    CasesFailedError,
    SchedulerError,
)
from casadi_debris.simulation.sampling import varied_case, varied_cases
from casadi_debris.simulation.statistics import requirement_shortfalls, statistics_of
from casadi_debris.simulation.summary import RunSummary
from casadi_debris.workflows.controller import controller_for

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
_SCHEDULER_ADDRESS = re.compile(r"(tcp|tls)://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9.-]{1,253}):(\d{1,5})")

Progress = Callable[[int, int], None]
"""``progress(done, total)``: cases finished in this run, of the cases it runs."""


@dataclass(frozen=True)
class CaseSelection:
    """Which cases a campaign runs.

    Attributes
    ----------
    corners : bool
        Every corner of the uncertainty set (the default when ``samples`` is None
        and the problem has no ``[[montecarlo.vary]]``).
    samples : int, optional
        That many seeded random samples instead (of the uncertainty set, or the
        draws of ``[[montecarlo.vary]]``: see :mod:`casadi_debris.simulation.sampling`).
    seed : int, optional
        Seed of the samples (default the problem's ``montecarlo.seed``).
    max_cases : int, optional
        Keep that many cases spread evenly over the list (a quick look).
    """

    corners: bool = False
    samples: int | None = None
    seed: int | None = None
    max_cases: int | None = None

    def cases(self, problem: Problem, model: Model) -> list[Case]:
        """The chosen cases, in campaign order."""
        if self.samples is not None and self.corners:
            raise InputShapeError("give either --corners or --samples, not both")
        if problem.montecarlo.vary and not self.corners:
            seed = problem.montecarlo.seed if self.seed is None else self.seed
            count = problem.montecarlo.samples if self.samples is None else self.samples
            chosen = varied_cases(problem, model, count, seed)
        elif self.samples is not None:
            seed = problem.montecarlo.seed if self.seed is None else self.seed
            chosen = sample_cases(problem, model, self.samples, seed)
        else:
            chosen = corner_cases(problem, model)
        if self.max_cases is not None and self.max_cases < len(chosen):
            picks = np.unique(np.linspace(0, len(chosen) - 1, self.max_cases).round().astype(int))
            chosen = [chosen[i] for i in picks]
        return chosen


def one_case(
    problem: Problem, model: Model, corner: int | None, sample: int | None, seed: int | None
) -> Case:
    """Corner ``corner``, sample ``sample`` (with ``seed``), or the nominal case.

    With ``[[montecarlo.vary]]``, ``sample`` is that campaign's case of that index.
    """
    if corner is not None and sample is not None:
        raise InputShapeError("give either --corner or --sample, not both")
    if corner is not None:
        try:
            return corner_case(problem, model, corner)
        except SimulationError as exc:
            raise InputShapeError(f"--corner: {exc}") from None
    if sample is not None:
        seed = problem.montecarlo.seed if seed is None else seed
        if problem.montecarlo.vary:
            try:
                return varied_case(problem, model, sample, seed)
            except SimulationError as exc:
                raise InputShapeError(f"--sample: {exc}") from None
        return sample_case(problem, model, sample, seed)
    return nominal_case(model)


def parameters_case(problem: Problem, model: Model, values: Any, case_id: str) -> Case:
    """A case at given parameter values: ``values`` maps every model parameter name
    (``inertia_scale_x`` ... ``bending_frequency_scale``, SI) to its value, as the
    ``parameters`` of a file that ``worstcase`` writes.

    Raises
    ------
    InputShapeError
        Not a mapping, unknown or missing names, or values that are not positive
        finite numbers where they must be.
    """
    where = "--parameters: parameters"
    if not isinstance(values, dict):
        raise InputShapeError(f"{where}: expected an object of name: value")
    if any(isinstance(v, bool) or not isinstance(v, int | float) for v in values.values()):
        raise InputShapeError(f"{where}: every value must be a number")
    try:
        named = Parameters.from_mapping(model.parameter_layout, values)
    except ModelError as exc:
        raise InputShapeError(f"{where}: {exc}") from None
    p = named.to_vector()
    z = normalized_from_parameters(problem, model, p)
    return Case(case_id, "parameters", 0, None, z, p)


@dataclass(frozen=True, kw_only=True)
class RunRecord(Record):
    """A run's figures and what identifies it: the case, its seed, the files, the plants.

    Attributes
    ----------
    problem, problem_sha256, plant_sha256 : str
    controller_plant_sha256 : str or None
        The plant the controller was designed for (None: not recorded).
    case_id : str
    seed : int or None
    controller_path : str
    out_dir : str or None
        Where the run was written, if it was.
    run : RunSummary
        The figures, written into the same JSON object.
    requirements_met : bool or None
        Whether the run meets the problem's ``[requirements]`` (None: not judged).
    requirement_shortfalls : tuple of str or None
        How it misses them, one sentence each (None when met or not judged).
    """

    problem: str
    problem_sha256: str
    plant_sha256: str
    controller_plant_sha256: str | None
    case_id: str
    seed: int | None
    controller_path: str
    out_dir: str | None = None
    run: RunSummary = field(metadata=FLATTENED)
    requirements_met: bool | None = field(default=None, metadata=OPTIONAL)
    requirement_shortfalls: tuple[str, ...] | None = field(default=None, metadata=OPTIONAL)

    def __getattr__(self, name: str) -> Any:
        # The JSON form flattens ``run`` into the record, so ``summary.max_error_deg`` reads
        # in Python as it does in summary.json.
        if name.startswith("__") or name == "run":
            raise AttributeError(name)
        return getattr(self.run, name)


def run_summary(
    problem: Problem,
    case: Case,
    result: ClosedLoopResult,
    controller_path: Path,
    record: ControllerRecord | None = None,
) -> RunRecord:
    """A run's figures plus what identifies it (case, seed, files, the plants), judged
    against the problem's ``[requirements]``."""
    run = result.summary()
    shortfalls = requirement_shortfalls(problem, run)
    return RunRecord(
        problem=problem.name,
        problem_sha256=problem.sha256,
        plant_sha256=problem.plant_sha256,
        controller_plant_sha256=None if record is None else record.problem_sha256,
        case_id=case.case_id,
        seed=case.seed,
        controller_path=str(controller_path),
        run=run,
        requirements_met=not shortfalls,
        requirement_shortfalls=shortfalls or None,
    )


def check_scheduler_address(address: str) -> None:
    """Refuse anything but ``tcp://host:port`` or ``tls://host:port`` (no other schemes).

    Dask unpickles what a scheduler sends: only the address the user gave is
    contacted, and only over Dask's own TCP or TLS transports.
    """
    match = _SCHEDULER_ADDRESS.fullmatch(address)
    if match is None or not 1 <= int(match[3]) <= 65535:
        raise InputShapeError(
            f"--scheduler: expected tcp://host:port or tls://host:port, got {address!r}"
        )


def run_campaign_folder(
    problem: Problem,
    controller_path: str | Path | None,
    selection: CaseSelection,
    out: str | Path,
    *,
    workers: int = 1,
    scheduler: str | None = None,
    jit: bool = True,
    batch_cases: int = DEFAULT_BATCH_CASES,
    overwrite: bool = False,
    progress: Progress | None = None,
    allow_mismatch: bool = False,
    moved_to: tuple[Path, Path] | None = None,
) -> CampaignSummary:
    """Run a campaign into ``out``, resuming from the cases already in ``out.partial``.

    Parameters
    ----------
    problem : Problem
    controller_path : str or Path, optional
        Controller file (default the shipped one; see
        :func:`~casadi_debris.workflows.controller.controller_for`).
    selection : CaseSelection
    out : str or Path
        Campaign folder (see :mod:`casadi_debris.report.campaign_folder`).
    workers : int
        Local processes.
    scheduler : str, optional
        A Dask scheduler address instead of local processes.
    jit, batch_cases : bool, int
        Compile the step to C where a compiler is found; cases per compiled call.
    overwrite : bool
        Replace an existing campaign folder this toolkit wrote.
    progress : callable, optional
        Called as cases finish (see :data:`Progress`).
    allow_mismatch : bool
        Fly a controller designed for another plant.
    moved_to : (Path, Path), optional
        ``(staging, final)``: ``out`` and the controller lie in a report's staging
        folder, moved to ``final`` later; the summaries record the final paths.

    Returns
    -------
    CampaignSummary
        What ``summary.json`` holds.

    Raises
    ------
    OutputError
        ``out`` cannot be written, or ``out.partial`` holds another campaign or is in use.
    CampaignInterrupted
        On Ctrl-C; the finished cases stay for a resume.
    CasesFailedError
        Every case raised (otherwise a raising case is recorded in
        ``cases/<id>.failed.json`` and ``failed_cases``, and the rest go on).
    """
    out = Path(out)
    if scheduler is not None:
        check_scheduler_address(scheduler)
    check_output_folder(out, overwrite=overwrite)
    record, resolved = controller_for(problem, controller_path, allow_mismatch=allow_mismatch)
    model = build_model(problem)
    cases, setup = selection.cases(problem, model), _setup(problem, record, jit, batch_cases)
    identity = _identity(setup, cases, resolved)
    with CampaignFolder.open(out, identity, overwrite=overwrite) as folder:
        done = folder.finished_cases(cases)
        outcomes, failures = _run_missing(setup, cases, done, folder, workers, scheduler, progress)
        if not outcomes:
            raise CasesFailedError(failures)  # nothing to summarise; the folder stays
        run = _described(
            problem, record, identity, (resolved, out.absolute()), moved_to, workers=workers,
            scheduler=scheduler, resumed_cases=len(done),
            compiled_step=bool(jit and c_compiler()), failures=failures,
        )  # fmt: skip
        summary = _summarise_and_write(folder, setup, model, identity, outcomes, run)
        folder.finish()
    return summary


def _setup(problem: Problem, record: ControllerRecord, jit: bool, batch: int) -> CampaignSetup:
    """What every case of the campaign shares (``batch`` cases per compiled call)."""
    reference = scenario_reference(problem)
    return CampaignSetup.create(problem, record.reduced, reference, jit=jit, batch_cases=batch)


def _described(
    problem: Problem,
    record: ControllerRecord,
    identity: CampaignRecord,
    paths: tuple[Path, Path],
    moved_to: tuple[Path, Path] | None,
    *,
    workers: int,
    scheduler: str | None,
    resumed_cases: int,
    compiled_step: bool,
    failures: list[CaseFailure],
) -> CampaignRun:
    """What was run and how, as the summary gives it beside the worst cases: the files
    and plants it names (``paths``: the controller and the folder, as they will end up)."""
    controller_path, out = (_final(path, moved_to) for path in paths)
    return CampaignRun(
        controller_path=str(controller_path),
        controller_sha256=identity.controller_sha256,
        plant_sha256=problem.plant_sha256,
        controller_plant_sha256=record.problem_sha256,
        out_dir=str(out),
        case_kind=identity.case_kind,
        seed=identity.seed,
        workers=workers,
        scheduler=scheduler,
        resumed_cases=resumed_cases,
        compiled_step=compiled_step,
        failed_cases=[_failure_record(f) for f in failures],
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


def _failure_record(failure: CaseFailure) -> FailedCase:
    """A failed case as the summary lists it."""
    return FailedCase(failure.case.case_id, failure.error_type, failure.message)


def _summarise_and_write(
    folder: CampaignFolder,
    setup: CampaignSetup,
    model: Model,
    identity: CampaignRecord,
    outcomes: list[CaseOutcome],
    run: CampaignRun,
) -> CampaignSummary:
    """Run the nominal case, then write the campaign's tables, figures and summary."""
    problem = setup.problem
    controller_path = Path(run.controller_path)
    allocator = Allocator.from_problem(problem, model.geometry)
    nominal = simulate(problem, model, setup.controller, setup.reference, allocator=allocator)
    nominal_summary = run_summary(problem, nominal_case(model), nominal, controller_path)
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
    summary = campaign_summary(problem, setup, outcomes, nominal_figures, run, statistics)
    write_campaign(
        folder.partial,
        problem,
        setup,
        outcomes,
        nominal,
        nominal_summary,
        summary,
        identity,
    )
    return summary


def _identity(setup: CampaignSetup, cases: list[Case], controller_path: Path) -> CampaignRecord:
    """What the campaign is, as its folder records it for a resume."""
    return CampaignRecord(
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
    done: dict[str, CaseOutcome],
    folder: CampaignFolder,
    workers: int,
    scheduler: str | None,
    progress: Progress | None,
) -> tuple[list[CaseOutcome], list[CaseFailure]]:
    """Run the cases not in ``done``, writing each as it finishes.

    Returns every finished case (resumed or run), in campaign order, and the
    cases of this run that raised (each recorded in the folder as it fails).
    """
    resumed = dict(done)
    todo = [c for c in cases if c.case_id not in resumed]
    LOGGER.info(
        "%s: %d cases (%d on disk, %d to run)",
        setup.problem.name,
        len(cases),
        len(resumed),
        len(todo),
    )
    finished: dict[str, CaseOutcome] = {}
    failures: list[CaseFailure] = []

    def keep(outcome: CaseOutcome) -> None:
        folder.write_case(outcome)
        finished[outcome.case.case_id] = outcome
        if progress is not None:
            progress(len(finished) + len(failures), len(todo))

    def record(failure: CaseFailure) -> None:
        path = folder.write_failure(failure)
        failures.append(failure)
        LOGGER.warning(
            "%s failed (%s: %s); the campaign goes on without it (traceback in cases/%s)",
            failure.case.case_id,
            failure.error_type,
            failure.message,
            path.name,
        )
        if progress is not None:
            progress(len(finished) + len(failures), len(todo))

    try:
        if progress is not None:
            progress(0, len(todo))
        run_campaign(
            setup,
            todo,
            workers=workers,
            scheduler=scheduler,
            on_result=keep,
            on_failure=record,
        )
    except KeyboardInterrupt:
        kept = len(resumed) + len(finished)
        raise CampaignInterrupted(kept, len(cases), folder.partial) from None
    except SchedulerError as exc:
        raise InputShapeError(f"--scheduler: {exc}") from None
    every = {**resumed, **finished}
    return [every[c.case_id] for c in cases if c.case_id in every], failures
