"""Monte Carlo campaigns: many closed-loop cases in parallel, summaries and envelope.

A campaign runs :func:`~casadi_debris.simulation.simulate` for each
:class:`~casadi_debris.simulation.cases.Case` on local processes (default),
or on a Dask cluster when a scheduler address is given. Each case returns
its summary and its :class:`Bands`: the minimum and maximum of the attitude
error and the torque over consecutive time bins, per body axis, small enough
to keep for hundreds of cases and exact as an envelope at the bin resolution
(the summary's maxima are exact at every step).

Results come back through a callback as they finish, so the caller (the
CLI) can show progress and write each case to disk; cases already on disk
are passed as ``skip`` to resume an interrupted campaign. Nothing here
writes files.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import math
import os
import signal
import tempfile
import threading
import time
from collections.abc import Callable, Iterable, Iterator, Mapping
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from dataclasses import dataclass, fields
from pathlib import Path
from typing import Any

import control
import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import Problem
from casadi_debris.model import Model, build_model
from casadi_debris.simulation.cases import Case
from casadi_debris.simulation.closed_loop import (
    JIT_FOLDER_ENV,
    JIT_PREFIX,
    SimulationError,
    release_compiled_steps,
)
from casadi_debris.simulation.reference import Reference
from casadi_debris.simulation.run import ClosedLoopResult, simulate

MAX_BINS = 2000


class SchedulerError(SimulationError):
    """The Dask scheduler asked for cannot be used (not installed, not reachable)."""


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
        (compiled once per worker).
    """

    problem: Problem
    controller: control.StateSpace
    reference: Reference
    bin_s: float
    jit: bool = True

    @classmethod
    def create(
        cls,
        problem: Problem,
        controller: control.StateSpace,
        reference: Reference,
        *,
        jit: bool = True,
    ) -> CampaignSetup:
        """Bins of 1 s, wider for long runs (at most ``MAX_BINS``)."""
        duration = float(reference.time_s[-1] - reference.time_s[0])
        return cls(problem, controller, reference, max(1.0, duration / MAX_BINS), jit)

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
class CaseOutcome:
    """One finished case.

    Attributes
    ----------
    case : Case
    summary : dict
        :meth:`ClosedLoopResult.summary` plus the case's identity.
    bands : Bands
        Error and torque per time bin.
    """

    case: Case
    summary: dict[str, Any]
    bands: Bands


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


# Per-process cache: the model of the campaign's problem, built once.
_WORKER: dict[str, Any] = {}


def _worker_parts(problem: Problem) -> tuple[Model, Allocator]:
    key = f"{problem.sha256}:{problem.name}:{id(problem)}"
    if _WORKER.get("key") != key:
        _WORKER.update(key=key, model=build_model(problem))
    model = _WORKER["model"]
    # A fresh allocator (about 1 ms) for every case: its QP workspaces keep the
    # last solution as a warm start, which would make a case's last bits depend
    # on the case the worker ran before it, and a resumed campaign differ.
    return model, Allocator.from_problem(problem, model.geometry)


def run_case(setup: CampaignSetup, case: Case) -> CaseOutcome:
    """Simulate one case of a campaign (what each worker runs)."""
    model, allocator = _worker_parts(setup.problem)
    result = simulate(
        setup.problem,
        model,
        setup.controller,
        setup.reference,
        parameters=case.parameters,
        allocator=allocator,
        jit=setup.jit,
    )
    summary = {
        "case_id": case.case_id,
        "kind": case.kind,
        "index": case.index,
        "seed": case.seed,
        "normalized": case.normalized.tolist(),
        **result.summary(),
    }
    return CaseOutcome(case, summary, bin_bands(setup, result))


_SETUP: dict[str, CampaignSetup] = {}
_PARENT_WATCH_S = 1.0
_PR_SET_PDEATHSIG = 1


def _die_with_parent(parent_pid: int) -> None:
    """Make this worker end when the campaign's process ends, however it ends.

    A killed parent (SIGKILL included) cannot stop its workers itself: on
    Linux the kernel sends them SIGKILL (``prctl(PR_SET_PDEATHSIG)``); a
    watcher thread covers other systems by checking the parent's id.
    """
    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent_pid:  # the parent died before the line above
        os._exit(1)

    def watch() -> None:
        while True:
            time.sleep(_PARENT_WATCH_S)
            if os.getppid() != parent_pid:
                os._exit(1)

    threading.Thread(target=watch, name="parent-watch", daemon=True).start()


def _init_process(setup: CampaignSetup, parent_pid: int) -> None:
    # A group of its own: Ctrl-C reaches the parent alone, which decides what to do,
    # and the parent can stop a worker together with the compiler it may be running.
    os.setpgrp()
    _die_with_parent(parent_pid)
    _SETUP["setup"] = setup


def _run_in_process(case: Case) -> CaseOutcome:
    return run_case(_SETUP["setup"], case)


def run_campaign(
    setup: CampaignSetup,
    cases: Iterable[Case],
    *,
    workers: int = 1,
    scheduler: str | None = None,
    on_result: Callable[[CaseOutcome], None] | None = None,
    build_folder: Path | None = None,
) -> list[CaseOutcome]:
    """Run cases, in parallel, calling ``on_result`` as each finishes.

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
        Called with each :class:`CaseOutcome` in completion order.
    build_folder : Path, optional
        Where the compiled control steps go (default: a private temporary
        folder, removed at the end). The caller removes a folder it gives.

    Returns
    -------
    list of CaseOutcome
        In the order of ``cases``.
    """
    cases = list(cases)
    if workers < 1:
        raise SimulationError(f"workers must be at least 1, got {workers}")
    with _build_folder(build_folder) as folder:
        if scheduler is not None:
            finished = _dask_outcomes(setup, cases, scheduler)
        elif workers == 1 or len(cases) <= 1:
            finished = (run_case(setup, case) for case in cases)
        else:
            finished = _process_outcomes(setup, cases, min(workers, len(cases)), folder)
        by_id: dict[str, CaseOutcome] = {}
        for outcome in finished:
            by_id[outcome.case.case_id] = outcome
            if on_result is not None:
                on_result(outcome)
    return [by_id[case.case_id] for case in cases]


@contextlib.contextmanager
def _build_folder(given: Path | None) -> Iterator[Path]:
    """The JIT folder of this campaign, announced to this process and its workers."""
    with contextlib.ExitStack() as stack:
        if given is None:
            folder = Path(
                stack.enter_context(
                    tempfile.TemporaryDirectory(prefix=f"{JIT_PREFIX}{os.getpid()}_")
                )
            )
        else:
            folder = Path(given)
            folder.mkdir(parents=True, exist_ok=True)
        previous = os.environ.get(JIT_FOLDER_ENV)
        os.environ[JIT_FOLDER_ENV] = str(folder)
        try:
            yield folder
        finally:
            release_compiled_steps()
            if previous is None:
                os.environ.pop(JIT_FOLDER_ENV, None)
            else:
                os.environ[JIT_FOLDER_ENV] = previous


def _process_outcomes(
    setup: CampaignSetup, cases: list[Case], workers: int, build_folder: Path
) -> Iterator[CaseOutcome]:
    # One thread per process: CasADi and BLAS would otherwise compete for the cores.
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    pool = ProcessPoolExecutor(
        max_workers=workers, initializer=_init_process, initargs=(setup, os.getpid())
    )
    try:
        pending = {pool.submit(_run_in_process, case) for case in cases}
        while pending:
            done, pending = wait(pending, return_when=FIRST_COMPLETED)
            for future in done:
                yield future.result()
    except BaseException:
        # Interrupted (Ctrl-C) or failed: stop the cases under way instead of waiting.
        for process in list(getattr(pool, "_processes", {}).values()):
            _kill_worker(process.pid)
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _kill_worker(pid: int) -> None:
    """Kill a worker and what it runs (its process group), or the worker alone."""
    try:
        if os.getpgid(pid) == pid:
            os.killpg(pid, signal.SIGKILL)
            return
        os.kill(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass  # already gone


def _dask_outcomes(
    setup: CampaignSetup, cases: list[Case], scheduler: str
) -> Iterator[CaseOutcome]:
    try:
        from distributed import Client, as_completed
    except ImportError as exc:
        raise SchedulerError(
            "the Dask 'distributed' package is needed: pip install 'casadi_debris[dask]'"
        ) from exc
    try:
        client = Client(scheduler, timeout="10s")
    except OSError as exc:
        raise SchedulerError(f"cannot reach the Dask scheduler at {scheduler}: {exc}") from exc
    try:
        shared = client.scatter(setup, broadcast=True)
        futures = [client.submit(run_case, shared, case, pure=False) for case in cases]
        for future in as_completed(futures):
            yield future.result()
    finally:
        client.close()


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
