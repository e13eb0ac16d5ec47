"""One parallel map: local worker processes (or a Dask cluster), per-worker state, failures kept.

:func:`parallel_map` calls ``function(context, item)`` for every item and
yields each result as it completes. ``context`` is what ``initializer()``
returned in that worker: expensive state (a model, compiled functions) built
once per worker and kept in this module's one slot, never in a caller's
global.

An exception raised by one item is recorded as an :class:`ItemFailure`
(item id, exception type, message, traceback text) and the other items go
on, as Basilisk's Monte Carlo controller does; the caller decides what a
failure means. An exception raised by ``initializer`` is not an item's
failure: the map stops with :class:`WorkerStartError`.

Local workers (``workers > 1``):

- each leads a process group of its own, so that Ctrl-C in a terminal
  reaches the caller alone, and stopping a worker stops what it runs (a C
  compiler, say);
- each dies with the caller, however the caller ends (``prctl(PR_SET_PDEATHSIG)``
  on Linux, a watcher thread elsewhere);
- each runs BLAS and OpenMP on one thread (``threadpoolctl``), so that ``n``
  workers on ``n`` cores do not oversubscribe them;
- all are killed when the map is interrupted (Ctrl-C, an exception in the
  caller's loop, a ``close()``), instead of being waited for.

With a Dask scheduler address the items run on that cluster instead (needs
the ``distributed`` package); its workers keep their own process and thread
settings (a Dask nanny starts them with one BLAS thread already).
"""

from __future__ import annotations

import ctypes
import ctypes.util
import os
import pickle
import signal
import threading
import time
import traceback
import uuid
from collections.abc import Callable, Generator, Iterable, Iterator
from concurrent.futures import FIRST_COMPLETED, Future, ProcessPoolExecutor, wait
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass, field
from types import TracebackType
from typing import Any, Generic, NoReturn, TypeVar

# threadpoolctl ships no type information (no py.typed, no stubs).
from threadpoolctl import threadpool_limits  # type: ignore[import-untyped]

T = TypeVar("T")  # an item
R = TypeVar("R")  # what the function returns for an item
C = TypeVar("C")  # a worker's context

# Read by OpenMP and BLAS libraries when they load: a worker sets them for the libraries it
# loads after it started (threadpoolctl limits those already loaded).
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
_PARENT_WATCH_S = 1.0
_PR_SET_PDEATHSIG = 1


class WorkerStartError(RuntimeError):
    """A worker's ``initializer`` raised; the message holds the worker's traceback."""


class SchedulerUnavailableError(RuntimeError):
    """The Dask scheduler asked for cannot be used (``distributed`` missing, unreachable)."""


class RemoteError(Exception):
    """An exception raised in another process, as its traceback text (a ``__cause__``)."""

    def __init__(self, text: str) -> None:
        super().__init__(text)
        self.text = text

    def __str__(self) -> str:
        return self.text


@dataclass(frozen=True)
class ItemResult(Generic[T, R]):
    """An item that completed.

    Attributes
    ----------
    index : int
        Position of the item in the items given.
    item : object
        The item.
    value : object
        What the function returned.
    """

    index: int
    item: T
    value: R


@dataclass(frozen=True)
class ItemFailure(Generic[T]):
    """An item whose function raised: what was raised, where, and the item it was.

    Attributes
    ----------
    index : int
        Position of the item in the items given.
    item : object
        The item.
    item_id : str
        The item's id (``item_id(item)``, or the index by default).
    error_type : str
        Qualified name of the exception's class (``numpy.linalg.LinAlgError``).
    message : str
        ``str()`` of the exception.
    traceback : str
        The formatted traceback, as the worker printed it.
    exception : Exception or None
        The exception itself when it could be sent back from the worker
        (:meth:`reraise` raises it), None when it cannot be pickled.
    remote : bool
        Whether it was raised in another process (a worker).
    """

    index: int
    item: T
    item_id: str
    error_type: str
    message: str
    traceback: str
    exception: Exception | None = field(default=None, repr=False, compare=False)
    remote: bool = False

    def reraise(self) -> NoReturn:
        """Raise the item's exception in this process (its worker's traceback as its cause).

        Raises
        ------
        Exception
            The item's own exception, or a ``RuntimeError`` that names
            it when it could not be sent back.
        """
        error = self.exception
        if error is None:
            error = RuntimeError(f"item {self.item_id}: {self.error_type}: {self.message}")
        if self.remote or error.__traceback__ is None:  # raised in another process
            raise error from RemoteError(self.traceback)
        raise error


def no_context() -> None:
    """An ``initializer`` for functions that need no per-worker state."""
    return None


def parallel_map(
    function: Callable[[C, T], R],
    items: Iterable[T],
    initializer: Callable[[], C],
    *,
    workers: int = 1,
    scheduler: str | None = None,
    item_id: Callable[[T], str] | None = None,
) -> MapResults[T, R]:
    """Map ``function(context, item)`` over ``items`` in parallel, results as they complete.

    Parameters
    ----------
    function : callable
        ``function(context, item) -> result``; a module-level function (sent
        to workers by name). Its exceptions are recorded, not raised.
    items : iterable
        The items; each is pickled to a worker, and so is each result.
    initializer : callable
        ``initializer() -> context``, run once in each worker before its
        first item (once in this process when ``workers`` is 1). Picklable:
        a module-level function or a :func:`functools.partial` of one.
        Use :func:`no_context` when there is no per-worker state.
    workers : int
        Local worker processes, at most one per item (1: every item in this
        process, one after the other, with no thread limit). Ignored with
        ``scheduler``.
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:8786``) to run the items on
        instead; each Dask worker runs ``initializer`` once per map.
    item_id : callable, optional
        ``item_id(item) -> str``: how failures name an item (default its index).

    Returns
    -------
    MapResults
        Iterates :class:`ItemResult` and :class:`ItemFailure`, in completion
        order. Use it in a ``with`` block: leaving the block early (an
        exception, a ``break``, Ctrl-C) kills the workers at once.

    Raises
    ------
    ValueError
        ``workers`` is below 1.
    WorkerStartError
        While iterating: ``initializer`` raised in a worker. In this process
        (``workers`` 1) its own exception is raised instead.
    SchedulerUnavailableError
        While iterating: ``distributed`` is not installed, or the scheduler
        cannot be reached.
    concurrent.futures.process.BrokenProcessPool
        While iterating: a worker died (killed, or crashed in compiled code).

    Examples
    --------
    >>> import math
    >>> from casadi_debris.parallel import ItemFailure, no_context, parallel_map
    >>> def root(context, x):
    ...     return math.sqrt(x)
    >>> with parallel_map(root, [4.0, -1.0, 9.0], no_context) as results:
    ...     got = sorted(results, key=lambda r: r.index)
    >>> [r.value for r in got if not isinstance(r, ItemFailure)], got[1].message
    ([2.0, 3.0], 'math domain error')

    Local processes (``workers=2``) need ``root`` importable from a module,
    as every function a worker runs is sent to it by name.
    """
    if workers < 1:
        raise ValueError(f"workers must be at least 1, got {workers}")
    chosen = list(items)
    job = _Job(uuid.uuid4().hex, function, initializer)
    names = item_id
    if scheduler is not None:
        stream = _dask_map(job, chosen, scheduler, names)
    elif min(workers, len(chosen)) <= 1:
        stream = _serial_map(job, chosen, names)
    else:
        stream = _process_map(job, chosen, min(workers, len(chosen)), names)
    return MapResults(stream)


class MapResults(Generic[T, R]):
    """The results of :func:`parallel_map`: an iterator, and a context manager that stops it.

    Closing (the end of its ``with`` block, or :meth:`close`) before the last
    result kills the local workers still running and cancels what is left.
    """

    def __init__(self, stream: Generator[ItemResult[T, R] | ItemFailure[T], None, None]) -> None:
        self._stream = stream

    def __iter__(self) -> Iterator[ItemResult[T, R] | ItemFailure[T]]:
        return self

    def __next__(self) -> ItemResult[T, R] | ItemFailure[T]:
        return next(self._stream)

    def close(self) -> None:
        """Stop: kill the workers still running (nothing happens once every result is in)."""
        self._stream.close()

    def __enter__(self) -> MapResults[T, R]:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        trace: TracebackType | None,
    ) -> None:
        self.close()


# ----------------------------------------------------------------------------- in a worker


@dataclass(frozen=True)
class _Job:
    """What every worker of one map needs: sent once to each, not with every item."""

    token: str
    function: Callable[[Any, Any], Any]
    initializer: Callable[[], Any]


@dataclass(frozen=True)
class _Succeeded:
    value: Any


@dataclass(frozen=True)
class _Raised:
    error_type: str
    message: str
    traceback: str
    exception: Exception | None

    @classmethod
    def capture(cls, error: Exception, *, crosses: bool) -> _Raised:
        """What ``error`` was; ``crosses``: it goes to another process (kept only if it pickles)."""
        name, message, text = describe_error(error)
        return cls(name, message, text, _sendable(error) if crosses else error)


def describe_error(error: BaseException) -> tuple[str, str, str]:
    """An exception as a failure records it: qualified type name, message, traceback text.

    Examples
    --------
    >>> describe_error(ValueError("bad"))[:2]
    ('ValueError', 'bad')
    """
    kind = type(error)
    name = kind.__qualname__
    if kind.__module__ not in ("builtins", "__main__"):
        name = f"{kind.__module__}.{name}"
    return name, str(error), "".join(traceback.format_exception(error))


@dataclass(frozen=True)
class _StartFailed:
    raised: _Raised


@dataclass
class _Worker:
    """A worker process's state for one map: its job and the context its initializer built."""

    job: _Job
    context: Any = None
    start_error: _Raised | None = None


class _Slot:
    """The one place a worker keeps its state (one map at a time per worker process)."""

    def __init__(self) -> None:
        self.worker: _Worker | None = None
        self.lock = threading.Lock()

    def start(self, job: _Job) -> _Worker:
        """Run ``job``'s initializer, or keep its failure for the items to report."""
        worker = _Worker(job)
        try:
            worker.context = job.initializer()
        except Exception as error:
            worker.start_error = _Raised.capture(error, crosses=True)
        self.worker = worker
        return worker

    def worker_for(self, job: _Job) -> _Worker:
        """This process's worker of ``job``, started on first use (Dask: threads share it)."""
        with self.lock:
            worker = self.worker
            if worker is None or worker.job.token != job.token:
                worker = self.start(job)
            return worker


_SLOT = _Slot()


def _sendable(error: Exception) -> Exception | None:
    """``error`` if it survives pickling (as it must to cross processes), else None."""
    try:
        pickle.loads(pickle.dumps(error))
    except Exception:
        return None
    return error


def _call(worker: _Worker, item: Any, *, crosses: bool) -> _Succeeded | _Raised | _StartFailed:
    if worker.start_error is not None:
        return _StartFailed(worker.start_error)
    try:
        return _Succeeded(worker.job.function(worker.context, item))
    except Exception as error:
        return _Raised.capture(error, crosses=crosses)


def _start_local_worker(job: _Job, parent_pid: int) -> None:
    # A group of its own: Ctrl-C reaches the parent alone, which decides what to do,
    # and the parent can stop a worker together with the compiler it may be running.
    os.setpgrp()
    _die_with_parent(parent_pid)
    for name in THREAD_VARIABLES:
        os.environ[name] = "1"
    # One thread per worker: the workers already share the cores between them.
    threadpool_limits(limits=1)
    _SLOT.start(job)


def _run_local_item(item: Any) -> _Succeeded | _Raised | _StartFailed:
    worker = _SLOT.worker
    if worker is None:  # the pool always runs its initializer first
        raise RuntimeError("parallel_map: a worker ran an item before its initializer")
    return _call(worker, item, crosses=True)


def _run_dask_item(job: _Job, item: Any) -> _Succeeded | _Raised | _StartFailed:
    return _call(_SLOT.worker_for(job), item, crosses=True)


def _die_with_parent(parent_pid: int) -> None:
    """Make this worker end when the process that started it ends, however it ends.

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


# ----------------------------------------------------------------------------- in the caller

Outcome = ItemResult[Any, Any] | ItemFailure[Any]


def _outcome(
    index: int,
    item: Any,
    returned: _Succeeded | _Raised | _StartFailed,
    names: Callable[[Any], str] | None,
    *,
    remote: bool = True,
) -> Outcome:
    if isinstance(returned, _StartFailed):
        raised = returned.raised
        raise WorkerStartError(
            f"a worker's initializer raised {raised.error_type}: {raised.message}\n"
            f"{raised.traceback}"
        )
    if isinstance(returned, _Raised):
        return ItemFailure(
            index,
            item,
            str(index) if names is None else names(item),
            returned.error_type,
            returned.message,
            returned.traceback,
            returned.exception,
            remote,
        )
    return ItemResult(index, item, returned.value)


def _serial_map(
    job: _Job, items: list[Any], names: Callable[[Any], str] | None
) -> Generator[Outcome, None, None]:
    if not items:
        return
    worker = _Worker(job, job.initializer())  # its exception is the caller's to see
    for index, item in enumerate(items):
        yield _outcome(index, item, _call(worker, item, crosses=False), names, remote=False)


def _process_map(
    job: _Job, items: list[Any], workers: int, names: Callable[[Any], str] | None
) -> Generator[Outcome, None, None]:
    pool = ProcessPoolExecutor(
        max_workers=workers, initializer=_start_local_worker, initargs=(job, os.getpid())
    )
    try:
        pending: dict[Future[Any], int] = {
            pool.submit(_run_local_item, item): index for index, item in enumerate(items)
        }
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for future in sorted(done, key=pending.__getitem__):
                index = pending.pop(future)
                yield _outcome(index, items[index], _returned(future), names)
    except BaseException:
        # Interrupted (Ctrl-C), closed early or failed: stop what runs instead of waiting.
        for process in list((getattr(pool, "_processes", None) or {}).values()):
            _kill_worker(process.pid)
        pool.shutdown(wait=True, cancel_futures=True)
        raise
    pool.shutdown(wait=True)


def _returned(future: Future[Any]) -> _Succeeded | _Raised | _StartFailed:
    """What the worker returned for a finished item."""
    try:
        result: _Succeeded | _Raised | _StartFailed = future.result()
    except BrokenProcessPool:
        raise
    except Exception as error:  # the item or its result could not be sent across
        return _Raised.capture(error, crosses=False)
    return result


def _kill_worker(pid: int) -> None:
    """Kill a worker and what it runs (its process group), or the worker alone."""
    try:
        if os.getpgid(pid) == pid:
            os.killpg(pid, signal.SIGKILL)
            return
        os.kill(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass  # already gone


def _dask_map(
    job: _Job, items: list[Any], scheduler: str, names: Callable[[Any], str] | None
) -> Generator[Outcome, None, None]:
    try:
        from distributed import Client, as_completed
    except ImportError as exc:
        raise SchedulerUnavailableError(
            "the Dask 'distributed' package is needed: pip install 'casadi_debris[dask]'"
        ) from exc
    try:
        client = Client(scheduler, timeout="10s")
    except OSError as exc:
        raise SchedulerUnavailableError(
            f"cannot reach the Dask scheduler at {scheduler}: {exc}"
        ) from exc
    futures: dict[Any, int] = {}
    try:
        shared = client.scatter(job, broadcast=True)
        futures = {
            client.submit(_run_dask_item, shared, item, pure=False): index
            for index, item in enumerate(items)
        }
        for future in as_completed(futures):
            index = futures[future]
            try:
                returned = future.result()
            except Exception as error:  # the item or its result could not be sent across
                returned = _Raised.capture(error, crosses=False)
            yield _outcome(index, items[index], returned, names)
    except BaseException:
        client.cancel(list(futures))
        raise
    finally:
        client.close()
