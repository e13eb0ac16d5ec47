"""Local worker processes of :func:`~casadi_debris.parallel.parallel_map`, read by the caller.

Each worker is a process that leads a process group of its own and takes one item
at a time through a pipe of its own. The caller's thread, the one that iterates the
map, sends the items, waits on the pipes and on the workers' exits, and reads the
results: no helper thread takes part. So an interrupt (Ctrl-C, an exception in the
caller's loop, a ``close()``) kills every worker's group and returns at once,
whatever the workers were doing (an item, a compiler, a result of megabytes sent
half-way), and nothing is left waiting.

``concurrent.futures.ProcessPoolExecutor``, used here before, cannot promise that:
its shutdown joins a manager thread that, once a worker is killed half-way through
sending a large result (a batch of campaign cases is about a megabyte, the pipe
holds 64 KiB), waits forever for the rest; and a Ctrl-C that lands while
``concurrent.futures.wait`` holds the futures' locks leaves them held, so that the
manager thread blocks on them. Both hang the interrupted caller; both need a
loaded machine and results in flight, which is why an interrupt worked alone and
not in a long test run.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import multiprocessing
import os
import pickle
import signal
import threading
import time
from collections import deque
from collections.abc import Generator, Sequence
from concurrent.futures.process import BrokenProcessPool
from dataclasses import dataclass
from multiprocessing.connection import Connection, wait
from multiprocessing.context import BaseContext
from multiprocessing.process import BaseProcess
from typing import Any

# threadpoolctl ships no type information (no py.typed, no stubs).
from threadpoolctl import threadpool_limits  # type: ignore[import-untyped]

from casadi_debris.parallel._interrupts import Interrupts
from casadi_debris.parallel._items import SLOT, Job, Raised, Returned, call_item

# Read by OpenMP and BLAS libraries when they load: a worker sets them for the libraries it
# loads after it started (threadpoolctl limits those already loaded).
THREAD_VARIABLES = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS")
_PARENT_WATCH_S = 1.0
_PR_SET_PDEATHSIG = 1
_STOP = b""  # an empty message: no more items, end
_EXIT_WAIT_S = 5.0  # a worker asked to end is killed if it has not ended by then
_PROTOCOL = pickle.HIGHEST_PROTOCOL


@dataclass(eq=False)
class _Process:
    """A worker as the caller sees it: the process, its pipe, the item it runs."""

    process: BaseProcess
    pipe: Connection
    index: int | None = None


def local_map(
    job: Job, items: Sequence[Any], workers: int
) -> Generator[tuple[int, Returned], None, None]:
    """Run ``job`` on ``items`` in ``workers`` processes; ``(index, returned)`` as each ends.

    Closing the generator before the end (or an exception while it waits, Ctrl-C
    included) kills the workers and what they run; leaving it at the end stops them.

    Raises
    ------
    BrokenProcessPool
        A worker ended while it ran an item (killed, or crashed in compiled code).
    """
    running: list[_Process] = []
    todo = deque(range(len(items)))
    try:
        with Interrupts() as interrupts:
            context = _start_method()
            for _ in range(workers):
                _start(context, job, running)
                interrupts.check()
            for worker in running:
                yield from _give_next(worker, items, todo)
            while busy := [w for w in running if w.index is not None]:
                interrupts.check()
                waited: list[Any] = [w.pipe for w in busy] + [w.process.sentinel for w in busy]
                if interrupts.wakeup is not None:
                    waited.append(interrupts.wakeup)
                ready = set(wait(waited))
                interrupts.check()
                for worker in busy:
                    if worker.pipe in ready or worker.process.sentinel in ready:
                        answer = _receive(worker)
                        # The worker's next item first: it works while the caller reads.
                        unsent = list(_give_next(worker, items, todo))
                        yield answer
                        yield from unsent
    except BaseException:
        # Interrupted, closed early or failed: stop what runs instead of waiting for it.
        for worker in running:
            _kill(worker.process)
        raise
    finally:
        _end(running)


def _start_method() -> BaseContext:
    """Fork where there is one: a worker starts in milliseconds with what the caller imported.

    Named, not the process-wide default, which a caller (or a library it imported)
    may have changed, and which is a fork server from Python 3.14 on Linux: a
    worker's parent must be the caller, for it to die with the caller.
    """
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    return multiprocessing.get_context(method)


def _start(context: BaseContext, job: Job, running: list[_Process]) -> None:
    """Start one worker into ``running``, keeping the caller's end of its pipe only."""
    mine, theirs = context.Pipe(duplex=True)
    process = context.Process(  # type: ignore[attr-defined]
        target=_serve, args=(job, os.getpid(), theirs, mine), name="casadi_debris-worker"
    )
    # Ctrl-C held back while forking: raised in a fork hook (logging has one), Python drops
    # it; released once the worker is in ``running``, to be killed with the others.
    held = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT})
    try:
        process.start()
        # The caller's copy of the worker's end closed: its death reads as an end of file.
        theirs.close()
        running.append(_Process(process, mine))
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, held)


def _give_next(
    worker: _Process, items: Sequence[Any], todo: deque[int]
) -> Generator[tuple[int, Returned], None, None]:
    """Send ``worker`` the next item; yield at once the items that cannot be sent."""
    while todo:
        index = todo.popleft()
        try:
            payload = pickle.dumps(items[index], protocol=_PROTOCOL)
        except Exception as error:  # as the item's failure, the others go on
            yield index, Raised.capture(error, crosses=False)
            continue
        try:
            worker.pipe.send_bytes(payload)
        except OSError as exc:
            raise _broken(worker, index) from exc
        worker.index = index
        return


def _receive(worker: _Process) -> tuple[int, Returned]:
    """The answer of ``worker`` to its item (it is then free)."""
    index = worker.index
    if index is None:
        raise RuntimeError("parallel_map: a result from a worker that was given no item")
    try:
        data = worker.pipe.recv_bytes()
    except (EOFError, OSError) as exc:
        raise _broken(worker, index) from exc
    worker.index = None
    try:
        returned: Returned = pickle.loads(data)
    except Exception as error:  # the result's class cannot be rebuilt here
        returned = Raised.capture(error, crosses=False)
    return index, returned


def _broken(worker: _Process, index: int) -> BrokenProcessPool:
    worker.process.join(_EXIT_WAIT_S)
    return BrokenProcessPool(
        f"worker process {worker.process.pid} ended while it ran item {index} "
        f"(exit code {worker.process.exitcode})"
    )


def _end(running: list[_Process]) -> None:
    """Ask each worker to end, wait for it briefly, kill it if it does not; close the pipes."""
    for worker in running:
        with contextlib.suppress(OSError):
            worker.pipe.send_bytes(_STOP)
    deadline = time.monotonic() + _EXIT_WAIT_S
    for worker in running:
        worker.process.join(max(0.0, deadline - time.monotonic()))
        if worker.process.exitcode is None:
            _kill(worker.process)
            worker.process.join()
        worker.pipe.close()
        with contextlib.suppress(ValueError):
            worker.process.close()


def _kill(process: BaseProcess) -> None:
    """Kill a worker and what it runs (its process group), or the worker alone."""
    pid = process.pid
    if pid is None or process.exitcode is not None:
        return
    try:
        if os.getpgid(pid) == pid:
            os.killpg(pid, signal.SIGKILL)
            return
        os.kill(pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass  # already gone


# ----------------------------------------------------------------------------- in a worker


def _serve(job: Job, parent_pid: int, pipe: Connection, callers_end: Connection) -> None:
    """A worker's life: start, then answer items until told to end or the caller is gone."""
    callers_end.close()
    signal.signal(signal.SIGINT, signal.default_int_handler)  # not the caller's map's
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})  # held back by the fork
    # A group of its own: Ctrl-C reaches the caller alone, which decides what to do,
    # and the caller can stop a worker together with the compiler it may be running.
    os.setpgrp()
    _die_with_parent(parent_pid)
    for name in THREAD_VARIABLES:
        os.environ[name] = "1"
    # One thread per worker: the workers already share the cores between them.
    threadpool_limits(limits=1)
    worker = SLOT.start(job)
    while True:
        try:
            payload = pipe.recv_bytes()
        except EOFError:
            return  # the caller closed its end
        if payload == _STOP:
            return
        try:
            returned = call_item(worker, pickle.loads(payload), crosses=True)
            data = pickle.dumps(returned, protocol=_PROTOCOL)
        except Exception as error:  # the item or its result cannot cross
            data = pickle.dumps(Raised.capture(error, crosses=True), protocol=_PROTOCOL)
        pipe.send_bytes(data)


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
