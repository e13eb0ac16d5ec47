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

import contextlib
import uuid
from collections.abc import Callable, Generator, Iterable, Iterator
from dataclasses import dataclass, field
from types import TracebackType
from typing import Any, Generic, NoReturn, TypeVar

from casadi_debris.errors import RemoteError, SchedulerUnavailableError, WorkerStartError
from casadi_debris.parallel._interrupts import Interrupts, keep_ctrl_c
from casadi_debris.parallel._items import (
    SLOT,
    Job,
    Raised,
    Returned,
    StartFailed,
    Worker,
    call_item,
    describe_error,
)
from casadi_debris.parallel._local import THREAD_VARIABLES, local_map

__all__ = [
    "THREAD_VARIABLES",
    "ItemFailure",
    "ItemResult",
    "MapResults",
    "RemoteError",
    "SchedulerUnavailableError",
    "WorkerStartError",
    "describe_error",
    "keep_ctrl_c",
    "no_context",
    "parallel_map",
]

T = TypeVar("T")  # an item
R = TypeVar("R")  # what the function returns for an item
C = TypeVar("C")  # a worker's context


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
    job = Job(uuid.uuid4().hex, function, initializer)
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


def _run_dask_item(job: Job, item: Any) -> Returned:
    """A Dask task: one item, in the worker state of this Dask worker process."""
    return call_item(SLOT.worker_for(job), item, crosses=True)


# ----------------------------------------------------------------------------- in the caller

Outcome = ItemResult[Any, Any] | ItemFailure[Any]


def _outcome(
    index: int,
    item: Any,
    returned: Returned,
    names: Callable[[Any], str] | None,
    *,
    remote: bool = True,
) -> Outcome:
    if isinstance(returned, StartFailed):
        raised = returned.raised
        raise WorkerStartError(
            f"a worker's initializer raised {raised.error_type}: {raised.message}\n"
            f"{raised.traceback}"
        )
    if isinstance(returned, Raised):
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
    job: Job, items: list[Any], names: Callable[[Any], str] | None
) -> Generator[Outcome, None, None]:
    if not items:
        return
    with Interrupts() as interrupts:
        worker = Worker(job, job.initializer())  # its exception is the caller's to see
        for index, item in enumerate(items):
            returned = call_item(worker, item, crosses=False)
            # A Ctrl-C that the item's solver caught (CasADi's IPOPT does) ends the map here.
            interrupts.check()
            yield _outcome(index, item, returned, names, remote=False)


def _process_map(
    job: Job, items: list[Any], workers: int, names: Callable[[Any], str] | None
) -> Generator[Outcome, None, None]:
    with contextlib.closing(local_map(job, items, workers)) as stream:
        for index, returned in stream:
            yield _outcome(index, items[index], returned, names)


def _dask_map(
    job: Job, items: list[Any], scheduler: str, names: Callable[[Any], str] | None
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
                returned = Raised.capture(error, crosses=False)
            yield _outcome(index, items[index], returned, names)
    except BaseException:
        client.cancel(list(futures))
        raise
    finally:
        client.close()
