"""What a worker of :func:`~casadi_debris.parallel.parallel_map` runs: its job, its state, an item.

The same in a local worker process, a Dask worker and the caller's own process
(one worker): an item's exception is captured with its traceback, and kept only
when it can cross to another process.
"""

from __future__ import annotations

import pickle
import threading
import traceback
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Job:
    """What every worker of one map needs: sent once to each, not with every item."""

    token: str
    function: Callable[[Any, Any], Any]
    initializer: Callable[[], Any]


@dataclass(frozen=True)
class Succeeded:
    """An item's function returned ``value``."""

    value: Any


@dataclass(frozen=True)
class Raised:
    """An item's function raised: the exception's type name, message, traceback and itself."""

    error_type: str
    message: str
    traceback: str
    exception: Exception | None

    @classmethod
    def capture(cls, error: Exception, *, crosses: bool) -> Raised:
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
class StartFailed:
    """The worker's initializer raised (reported in answer to every item it is given)."""

    raised: Raised


@dataclass
class Worker:
    """A worker process's state for one map: its job and the context its initializer built."""

    job: Job
    context: Any = None
    start_error: Raised | None = None


class _Slot:
    """The one place a worker keeps its state (one map at a time per worker process)."""

    def __init__(self) -> None:
        self.worker: Worker | None = None
        self.lock = threading.Lock()

    def start(self, job: Job) -> Worker:
        """Run ``job``'s initializer, or keep its failure for the items to report."""
        worker = Worker(job)
        try:
            worker.context = job.initializer()
        except Exception as error:
            worker.start_error = Raised.capture(error, crosses=True)
        self.worker = worker
        return worker

    def worker_for(self, job: Job) -> Worker:
        """This process's worker of ``job``, started on first use (Dask: threads share it)."""
        with self.lock:
            worker = self.worker
            if worker is None or worker.job.token != job.token:
                worker = self.start(job)
            return worker


SLOT = _Slot()
"""This process's worker state (one map at a time per worker process)."""


def _sendable(error: Exception) -> Exception | None:
    """``error`` if it survives pickling (as it must to cross processes), else None."""
    try:
        pickle.loads(pickle.dumps(error))
    except Exception:
        return None
    return error


Returned = Succeeded | Raised | StartFailed
"""What a worker sends back for an item."""


def call_item(worker: Worker, item: Any, *, crosses: bool) -> Returned:
    """Run ``worker``'s function on ``item``; ``crosses``: the answer goes to another process."""
    if worker.start_error is not None:
        return StartFailed(worker.start_error)
    try:
        return Succeeded(worker.job.function(worker.context, item))
    except Exception as error:
        return Raised.capture(error, crosses=crosses)
