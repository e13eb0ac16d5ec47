"""Monte Carlo campaigns: many closed-loop cases in parallel, summaries and envelope.

A campaign runs :func:`~casadi_debris.simulation.simulate_closed_loop` for each
:class:`~casadi_debris.campaigns.Case` on local processes (default),
or on a Dask cluster when a scheduler address is given, through
``casadi_debris.parallel.parallel_map``. Each case returns
its summary and its :class:`Bands`: the minimum and maximum of the attitude
error and the torque over consecutive time bins, per body axis, small enough
to keep for hundreds of cases and exact as an envelope at the bin resolution
(the summary's maxima are exact at every step).

Results come back through a callback as they finish, so the caller (the
CLI) can show progress and write each case to disk; to resume an
interrupted campaign it leaves out the cases already on disk. A case that
raises is recorded as a :class:`CaseFailure` (through another callback) and
the campaign goes on. Nothing here writes files.
"""

from __future__ import annotations

import functools
import logging
import math
import time
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field, fields
from typing import Any

import control
import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.campaigns._cases import Case, CaseBatch, CaseIdentity, batches
from casadi_debris.config import Problem, problem_with_values
from casadi_debris.dynamics import Model, build_model
from casadi_debris.errors import CasesFailedError, SchedulerError
from casadi_debris.guidance import Reference
from casadi_debris.parallel import (
    ItemFailure,
    MapResults,
    SchedulerUnavailableError,
    describe_error,
    parallel_map,
)
from casadi_debris.records import FLATTENED, Record
from casadi_debris.simulation import (
    ClosedLoopResult,
    LoopSettings,
    RunInputs,
    RunSummary,
    SimulationError,
    release_batched_loops,
    release_compiled_steps,
    simulate_closed_loop,
    simulate_many,
)

MAX_BINS = 2000
DEFAULT_BATCH_CASES = 16
"""Cases of one compiled call in a batched campaign: enough that Python's share per
period is small, few enough that two workers get several batches each."""
LOGGER = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class CampaignSetup:
    """What every case of a campaign shares (sent once to each worker).

    Attributes
    ----------
    problem : Problem
    controller : control.StateSpace
        Continuous controller, attitude error [deg] -> torque [mNm].
    reference : Reference
    bin_s : float
        Width of the envelope's time bins [s].
    jit : bool
        Run each case's step as compiled C when a C compiler is found
        (compiled once per machine, loaded once per worker).
    batch_cases : int
        With ``jit``: cases run together, as one compiled function mapped over
        them (:func:`~casadi_debris.simulation.simulate_many`); 1 runs them
        one by one. Same numbers either way.
    """

    problem: Problem
    controller: control.StateSpace
    reference: Reference
    bin_s: float
    jit: bool = True
    batch_cases: int = 1

    @classmethod
    def create(
        cls,
        problem: Problem,
        controller: control.StateSpace,
        reference: Reference,
        *,
        jit: bool = True,
        batch_cases: int = DEFAULT_BATCH_CASES,
    ) -> CampaignSetup:
        """Bins of 1 s, wider for long runs (at most ``MAX_BINS``)."""
        duration = float(reference.time_s[-1] - reference.time_s[0])
        bin_s = max(1.0, duration / MAX_BINS)
        return cls(problem, controller, reference, bin_s, jit, batch_cases)

    @property
    def batched(self) -> bool:
        """Whether cases run in batches (compiled, more than one per batch)."""
        return self.jit and self.batch_cases > 1

    @property
    def n_bins(self) -> int:
        duration = float(self.reference.time_s[-1] - self.reference.time_s[0])
        return max(1, math.ceil(duration / self.bin_s - 1e-9))

    @property
    def bin_start_s(self) -> np.ndarray:
        """Start time of every bin, shape (n_bins,)."""
        return self.reference.time_s[0] + self.bin_s * np.arange(self.n_bins)


@dataclass(frozen=True, eq=False)
class Extremes:
    """The smallest and the largest value of one quantity in every time bin, per axis.

    Attributes
    ----------
    min : ndarray, shape (n_bins, 3)
        Smallest value in each bin, per body axis x, y, z.
    max : ndarray, shape (n_bins, 3)
        Largest value in each bin, per body axis x, y, z.
    """

    min: np.ndarray
    max: np.ndarray

    def widened(self, other: Extremes) -> Extremes:
        """The extremes of both, bin by bin (a NaN loses to a number, as in ``numpy.fmin``)."""
        return Extremes(np.fmin(self.min, other.min), np.fmax(self.max, other.max))


@dataclass(frozen=True, eq=False)
class Bands:
    """Attitude error and torque of a case (or an envelope of cases), binned in time.

    Attributes
    ----------
    error_rad : Extremes
        Attitude error (doubled vector part of the error quaternion, about
        body axes x, y, z) [rad], per bin, shapes (n_bins, 3).
    torque_Nm : Extremes
        Torque applied by the engines [N m], per bin, shapes (n_bins, 3). A
        torque held over a control period counts in the bin of its start.

    Examples
    --------
    >>> import numpy as np
    >>> zero = Extremes(np.zeros((2, 3)), np.zeros((2, 3)))
    >>> bands = Bands(error_rad=zero, torque_Nm=zero)
    >>> sorted(bands.to_arrays())
    ['error_rad_max', 'error_rad_min', 'torque_Nm_max', 'torque_Nm_min']
    >>> Bands.from_arrays(bands.to_arrays()).error_rad.max.shape
    (2, 3)
    """

    error_rad: Extremes
    torque_Nm: Extremes

    @property
    def n_bins(self) -> int:
        """Number of time bins."""
        return int(self.error_rad.min.shape[0])

    def quantities(self) -> dict[str, Extremes]:
        """Every quantity by its field name (the unit is in the name)."""
        return {item.name: getattr(self, item.name) for item in fields(self)}

    def widened(self, other: Bands) -> Bands:
        """The envelope of both, bin by bin."""
        return Bands(
            error_rad=self.error_rad.widened(other.error_rad),
            torque_Nm=self.torque_Nm.widened(other.torque_Nm),
        )

    def to_arrays(self) -> dict[str, np.ndarray]:
        """Flat named float64 arrays (``error_rad_min``, ...), e.g. for ``numpy.savez``."""
        return {
            f"{name}_{bound}": np.asarray(getattr(extremes, bound), dtype=np.float64)
            for name, extremes in self.quantities().items()
            for bound in ("min", "max")
        }

    @classmethod
    def from_arrays(cls, arrays: Mapping[str, np.ndarray]) -> Bands:
        """Inverse of :meth:`to_arrays`.

        Raises
        ------
        KeyError
            An array is missing.
        ValueError
            The arrays are not all of one shape (n_bins, 3).
        """
        parts = {
            item.name: Extremes(
                np.asarray(arrays[f"{item.name}_min"], dtype=np.float64),
                np.asarray(arrays[f"{item.name}_max"], dtype=np.float64),
            )
            for item in fields(cls)
        }
        shapes = {a.shape for e in parts.values() for a in (e.min, e.max)}
        shape = shapes.pop() if len(shapes) == 1 else ()
        if len(shape) != 2 or shape[1] != 3:
            raise ValueError("bands must all be of one shape (n_bins, 3)")
        return cls(**parts)


@dataclass(frozen=True, eq=False)
class CaseResult:
    """One finished case.

    Attributes
    ----------
    case : Case
    summary : CaseSummary
        The case's identity and its run's figures.
    bands : Bands
        Error and torque per time bin.
    """

    case: Case
    summary: CaseSummary
    bands: Bands

    @classmethod
    def from_saved(
        cls, case: Case, summary: dict[str, Any], arrays: Mapping[str, np.ndarray]
    ) -> CaseResult:
        """The case as its files keep it: its summary's JSON and its bands' named arrays
        (:meth:`Bands.to_arrays`); a layout of another version raises ValueError,
        KeyError or TypeError."""
        return cls(case, CaseSummary.from_json(summary), Bands.from_arrays(arrays))


@dataclass(frozen=True)
class CaseSummary(Record):
    """One case's row: who it is and its run's figures, in one flat JSON object."""

    identity: CaseIdentity = field(metadata=FLATTENED)
    run: RunSummary = field(metadata=FLATTENED)


@dataclass(frozen=True)
class CaseFailureSummary(Record):
    """A case that raised, as its JSON records it."""

    identity: CaseIdentity = field(metadata=FLATTENED)
    error_type: str
    message: str
    traceback: str


@dataclass(frozen=True, eq=False)
class CaseFailure:
    """A case that raised while it ran: the campaign records it and goes on.

    Attributes
    ----------
    case : Case
        The case (its seed and index re-run it alone).
    error_type : str
        Qualified name of the exception's class.
    message : str
    traceback : str
        As the worker formatted it.
    """

    case: Case
    error_type: str
    message: str
    traceback: str

    def summary(self) -> CaseFailureSummary:
        """The case's identity and what it raised."""
        identity = self.case.identity()
        return CaseFailureSummary(identity, self.error_type, self.message, self.traceback)


def bin_bands(setup: CampaignSetup, result: ClosedLoopResult) -> Bands:
    """Min/max of the error and the torque per time bin of ``setup``."""
    n_bins = setup.n_bins
    t0 = setup.reference.time_s[0]
    error_bins = np.minimum(((result.time_s - t0) / setup.bin_s).astype(int), n_bins - 1)
    # The torque is held from one sample to the next: one value fewer than the error.
    return Bands(
        error_rad=_extremes(result.error_rad, error_bins, n_bins),
        torque_Nm=_extremes(result.torque_Nm, error_bins[:-1], n_bins),
    )


def _extremes(values: np.ndarray, bins: np.ndarray, n_bins: int) -> Extremes:
    """Min/max of ``values`` (n, 3) grouped by ``bins`` (n,); +-inf in an empty bin."""
    low = np.full((n_bins, values.shape[1]), np.inf)
    high = np.full((n_bins, values.shape[1]), -np.inf)
    np.minimum.at(low, bins, values)
    np.maximum.at(high, bins, values)
    return Extremes(low, high)


def run_case(setup: CampaignSetup, case: Case, *, model: Model | None = None) -> CaseResult:
    """Simulate one case of a campaign.

    A case that varies keys of the problem file (``Case.file_values``) flies
    its own problem, read again with them, and its own model; model parameters
    only change the parameter vector of the step every case shares.

    Parameters
    ----------
    setup : CampaignSetup
    case : Case
    model : Model, optional
        The model of ``setup.problem``, when it is already built (a worker
        builds it once for all its cases, see :class:`CaseRunner`).
    """
    problem, jit = setup.problem, setup.jit
    if case.file_values:
        problem, model = _rebuilt(problem, case)
        # Its own step would be compiled for it alone: about 20 s of C compiling for a
        # run of about 9 s on CasADi's virtual machine (the paper's slew).
        jit = False
    elif model is None:
        model = build_model(problem)
    result = fly_case(model, setup.controller, setup.reference, case, jit=jit)
    summary = CaseSummary(case.identity(), result.summary())
    return CaseResult(case, summary, bin_bands(setup, result))


def fly_case(
    model: Model,
    controller: control.StateSpace,
    reference: Reference,
    case: Case,
    *,
    jit: bool = False,
) -> ClosedLoopResult:
    """The closed loop of one case of ``model.problem``: its parameters, failures and
    noise seed.

    A fresh allocator (about 1 ms) for every case: its QP workspaces keep the
    last solution as a warm start, which would make a case's last bits depend
    on the case run before it, and a resumed campaign differ.
    """
    problem = model.problem
    return simulate_closed_loop(
        model,
        controller,
        reference,
        parameters=case.parameters,
        failures=case.failures,
        allocator=Allocator.from_problem(problem, model.geometry),
        noise_seed=case.noise_seed(problem),
        settings=LoopSettings(jit=jit),
    )


def _rebuilt(problem: Problem, case: Case) -> tuple[Problem, Model]:
    """The case's own problem and model, when it varies keys of the problem file.

    Reading the problem again takes a few milliseconds and building its model
    about 0.2 s; the case then runs on CasADi's virtual machine (see :func:`run_case`).
    """
    start = time.perf_counter()
    own = problem_with_values(problem, case.file_values)
    model = build_model(own)
    LOGGER.debug(
        "%s: problem and model rebuilt for %s in %.2f s",
        case.case_id,
        ", ".join(name for name, _ in case.file_values),
        time.perf_counter() - start,
    )
    return own, model


class CaseRunner:
    """What a campaign's worker keeps: the setup and the model of its problem, built once.

    Parameters
    ----------
    setup : CampaignSetup
    """

    def __init__(self, setup: CampaignSetup) -> None:
        self.setup = setup
        self.model = build_model(setup.problem)

    def __call__(self, case: Case) -> CaseResult:
        """Simulate ``case`` (see :func:`run_case`)."""
        return run_case(self.setup, case, model=self.model)

    def batch(self, batch: CaseBatch) -> list[CaseResult | CaseFailure]:
        """Simulate the cases of ``batch`` together; each one's outcome, or its failure."""
        setup, model = self.setup, self.model
        # A fresh allocator per case, as run_case: a case's numbers never depend on its batch.
        runs = [
            RunInputs(
                case.parameters,
                case.failures,
                Allocator.from_problem(setup.problem, model.geometry),
                noise_seed=case.noise_seed(setup.problem),
            )
            for case in batch.cases
        ]
        results = simulate_many(
            model,
            setup.controller,
            setup.reference,
            runs,
            settings=LoopSettings(jit=setup.jit),
            slots=batch.slots,
        )
        pairs = zip(batch.cases, results, strict=True)
        return [_outcome(setup, case, result) for case, result in pairs]


def _outcome(
    setup: CampaignSetup, case: Case, result: ClosedLoopResult | Exception
) -> CaseResult | CaseFailure:
    if not isinstance(result, Exception):
        try:
            summary = CaseSummary(case.identity(), result.summary())
            return CaseResult(case, summary, bin_bands(setup, result))
        except Exception as exc:  # this case's failure, as run_case would raise it
            result = exc
    return CaseFailure(case, *describe_error(result))


def _run_with(runner: CaseRunner, case: Case) -> CaseResult:
    return runner(case)


def _run_batch_with(runner: CaseRunner, batch: CaseBatch) -> list[CaseResult | CaseFailure]:
    return runner.batch(batch)


def _case_id(case: Case) -> str:
    return case.case_id


def _batch_id(batch: CaseBatch) -> str:
    return ",".join(case.case_id for case in batch.cases)


def run_campaign(
    setup: CampaignSetup,
    cases: Iterable[Case],
    *,
    workers: int = 1,
    scheduler: str | None = None,
    on_result: Callable[[CaseResult], None] | None = None,
    on_failure: Callable[[CaseFailure], None] | None = None,
) -> list[CaseResult]:
    """Run cases, in parallel, calling ``on_result`` as each finishes.

    A case that raises is recorded as a :class:`CaseFailure` and the others
    go on (see ``casadi_debris.parallel.parallel_map``, which also says
    what local workers do: own process group, death with this process, one
    BLAS thread, killed on Ctrl-C).

    Parameters
    ----------
    setup : CampaignSetup
    cases : iterable of Case
    workers : int
        Local processes (1: in this process). Ignored with ``scheduler``.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``); needs the
        ``distributed`` package (``pip install 'casadi_debris[dask]'``).
    on_result : callable, optional
        Called with each :class:`CaseResult` in completion order.
    on_failure : callable, optional
        Called with each :class:`CaseFailure` in completion order. Without
        it, failed cases raise :class:`CasesFailedError` once every other
        case has finished.

    Returns
    -------
    list of CaseResult
        The cases that finished, in the order of ``cases``.

    Raises
    ------
    SimulationError
        ``workers`` below 1.
    SchedulerError
        ``scheduler`` cannot be used.
    CasesFailedError
        Cases failed and there is no ``on_failure``.
    """
    cases = list(cases)
    if workers < 1:
        raise SimulationError(f"workers must be at least 1, got {workers}")
    runner = functools.partial(CaseRunner, setup)
    mapped: MapResults[Any, Any]
    try:
        if setup.batched:
            mapped = parallel_map(
                _run_batch_with,
                batches(cases, setup.batch_cases, workers),
                runner,
                workers=workers,
                scheduler=scheduler,
                item_id=_batch_id,
            )
        else:
            mapped = parallel_map(
                _run_with, cases, runner, workers=workers, scheduler=scheduler, item_id=_case_id
            )
        with mapped as finished:
            by_id, failures = _collect(finished, on_result, on_failure)
    except SchedulerUnavailableError as exc:
        raise SchedulerError(str(exc)) from exc
    finally:
        release_compiled_steps()
        release_batched_loops()
    if failures and on_failure is None:
        raise CasesFailedError(failures)
    return [by_id[case.case_id] for case in cases if case.case_id in by_id]


def _collect(
    finished: Iterable[Any],
    on_result: Callable[[CaseResult], None] | None,
    on_failure: Callable[[CaseFailure], None] | None,
) -> tuple[dict[str, CaseResult], list[CaseFailure]]:
    """Outcomes by case id and the failures, calling back on each as it comes."""
    by_id: dict[str, CaseResult] = {}
    failures: list[CaseFailure] = []
    for item in finished:
        for done in _cases_of(item):
            if isinstance(done, CaseFailure):
                failures.append(done)
                if on_failure is not None:
                    on_failure(done)
                continue
            by_id[done.case.case_id] = done
            if on_result is not None:
                on_result(done)
    return by_id, failures


def _cases_of(item: Any) -> list[CaseResult | CaseFailure]:
    """What one item of the map gives: a case's outcome, or a batch's, or their failure."""
    if isinstance(item, ItemFailure):
        cases = item.item.cases if isinstance(item.item, CaseBatch) else (item.item,)
        return [CaseFailure(c, item.error_type, item.message, item.traceback) for c in cases]
    return item.value if isinstance(item.value, list) else [item.value]


@dataclass(eq=False)
class Envelope:
    """Running envelope (min/max per time bin) over the cases added.

    Attributes
    ----------
    bin_start_s : ndarray, shape (n_bins,)
        Start of every time bin [s].
    bands : Bands or None
        The envelope of every case added (None before the first).
    count : int
        Cases added.
    """

    bin_start_s: np.ndarray
    bands: Bands | None = None
    count: int = 0

    def add(self, bands: Bands) -> None:
        """Widen the envelope by one case's bands."""
        self.bands = bands if self.bands is None else self.bands.widened(bands)
        self.count += 1
