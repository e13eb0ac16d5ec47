"""The parallel map: same results as a serial map, failures kept, one BLAS thread per
worker, no worker left behind, one initialiser call per worker."""

from __future__ import annotations

import functools
import os
import select
import signal
import subprocess
import sys
import threading
import time
import uuid
from collections.abc import Iterator
from pathlib import Path

import numpy as np
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

from casadi_debris.parallel import (
    ItemFailure,
    ItemResult,
    RemoteError,
    WorkerStartError,
    no_context,
    parallel_map,
)

# Each Ctrl-C of these tests raises KeyboardInterrupt however the run was started.
pytestmark = pytest.mark.usefixtures("ctrl_c_raises")

needs_proc = pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc")


# ----------------------------------------------------------------------------- worker functions
# Module-level: workers receive them by name.


class Context:
    """A worker's state: made once by the initialiser, then seen by every item it runs."""

    def __init__(self, offset: int, starts: Path | None = None) -> None:
        self.offset = offset
        self.token = uuid.uuid4().hex
        if starts is not None:
            with starts.open("a") as stream:
                stream.write(f"{os.getpid()}\n")


def shifted_square(context: Context, x: int) -> int:
    return x * x + context.offset


def fails_on_three(context: None, x: int) -> int:
    if x == 3:
        raise ValueError(f"three is refused (got {x})")
    return 10 * x


def who_runs(context: Context, x: int) -> tuple[int, str, bool]:
    """The worker's id, its context's token, and whether it leads its own process group."""
    return os.getpid(), context.token, os.getpgid(0) == os.getpid()


def blas_threads(context: None, x: int) -> list[int]:
    return [entry["num_threads"] for entry in threadpool_info() if entry["user_api"] == "blas"]


# How long a busy item sleeps: a map that stops at once never lets one finish.
SLEEP_S = 120.0


def announce(fifo: Path, *words: object) -> None:
    """Tell the test what this worker started: one line on the test's FIFO (atomic)."""
    handle = os.open(fifo, os.O_WRONLY)
    try:
        os.write(handle, (" ".join(map(str, words)) + "\n").encode())
    finally:
        os.close(handle)


def sleeper(fifo: Path, x: int) -> int:
    """Item 0 returns at once; the others start a longer-lived child process and sleep."""
    if x == 0:
        return os.getpid()
    child = subprocess.Popen(["sleep", "120"])
    announce(fifo, "child", child.pid)
    announce(fifo, "worker", os.getpid())
    # Long enough that a map which waited for its items instead of killing them would be
    # seen: the "finished" line comes only from an item left to run to its end.
    time.sleep(SLEEP_S)
    announce(fifo, "finished", os.getpid())
    return x


def streamer(fifo: Path, x: int) -> np.ndarray:
    """Results of 4 MB (a pipe holds 64 KiB); item 5 tells the caller Ctrl-C and sleeps."""
    if x == 5:
        announce(fifo, "worker", os.getpid())
        announce(fifo, "sigint", time.monotonic())
        os.kill(os.getppid(), signal.SIGINT)
        time.sleep(SLEEP_S)
        announce(fifo, "finished", os.getpid())
    return np.full(512 * 1024, float(x))


def catches_ctrl_c(calls: list[int], x: int) -> int:
    """Ctrl-C during the item, caught by the item as CasADi's IPOPT does (a failed solve)."""
    calls.append(x)
    try:
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1.0)  # the handler runs here, before the sleep ends
    except KeyboardInterrupt:
        return -1
    return x


_CTRL_C_IN_FORK_HOOK = threading.Event()


def _ctrl_c_in_fork_hook() -> None:
    # Ctrl-C typed while the caller forks a worker: Python runs the handler in this hook
    # and drops the KeyboardInterrupt it raises ("Exception ignored in ...").
    if _CTRL_C_IN_FORK_HOOK.is_set():
        _CTRL_C_IN_FORK_HOOK.clear()
        os.kill(os.getpid(), signal.SIGINT)
        sum(range(1000))  # bytecodes: the handler's chance to run here


os.register_at_fork(after_in_parent=_ctrl_c_in_fork_hook)


def broken_start() -> None:
    raise OSError("no model here")


# ----------------------------------------------------------------------------- helpers


def _running(pid: int) -> bool:
    """Whether a process exists and is not a zombie (a killed one waiting to be reaped)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _wait_gone(pids: set[int], limit_s: float = 120.0) -> list[int]:
    """The processes of ``pids`` still running once each has ended (killed ones may take a
    moment): each end is an event, its pidfd turning readable, not a state polled against a
    deadline; ``limit_s`` only bounds a hang."""
    for pid in pids:
        try:
            handle = os.pidfd_open(pid)
        except ProcessLookupError:
            continue  # already ended and reaped
        try:
            select.select([handle], [], [], limit_s)
        finally:
            os.close(handle)
    return sorted(p for p in pids if _running(p))


class Announcements:
    """A FIFO the workers write a line to when they start something: the test reads it as
    events (a blocking read), instead of polling for files against a deadline."""

    def __init__(self, folder: Path) -> None:
        self.path = folder / "announcements"
        os.mkfifo(self.path)
        self._reader = os.open(self.path, os.O_RDONLY | os.O_NONBLOCK)
        # A writer held open: with none, a read ends at once instead of waiting for a line.
        self._writer = os.open(self.path, os.O_WRONLY)
        self._pending = b""
        self.lines: list[list[str]] = []

    def pids(self, kind: str) -> set[int]:
        return {int(words[1]) for words in self.lines if words[0] == kind}

    def wait_for(self, kind: str, count: int, limit_s: float = 300.0) -> set[int]:
        """The pids of ``kind`` once ``count`` are announced (``limit_s`` only bounds a hang)."""
        while len(self.pids(kind)) < count:
            ready, _, _ = select.select([self._reader], [], [], limit_s)
            assert ready, f"only {len(self.pids(kind))} of {count} {kind} announced"
            self._read()
        return self.pids(kind)

    def drain(self) -> None:
        """Read what is there (lines written before the workers were killed)."""
        while select.select([self._reader], [], [], 0)[0]:
            if not self._read():
                return

    def _read(self) -> bool:
        data = os.read(self._reader, 65536)
        *lines, self._pending = (self._pending + data).split(b"\n")
        self.lines += [line.decode().split() for line in lines]
        return bool(data)

    def close(self) -> None:
        os.close(self._reader)
        os.close(self._writer)


@pytest.fixture()
def announcements(tmp_path: Path) -> Iterator[Announcements]:
    fifo = Announcements(tmp_path)
    yield fifo
    fifo.close()


# ----------------------------------------------------------------------------- tests


@pytest.mark.parametrize("workers", [1, 2])
def test_results_equal_a_serial_map(workers: int) -> None:
    items = list(range(23))
    with parallel_map(
        shifted_square, items, functools.partial(Context, 5), workers=workers
    ) as results:
        got = list(results)
    assert all(isinstance(r, ItemResult) for r in got)
    assert sorted(r.index for r in got) == items
    assert {r.index: r.value for r in got} == {x: x * x + 5 for x in items}
    assert all(r.item == r.index for r in got)


@pytest.mark.parametrize("workers", [1, 2])
def test_a_raising_item_is_recorded_with_its_id_and_the_others_complete(workers: int) -> None:
    items = list(range(8))
    with parallel_map(
        fails_on_three, items, no_context, workers=workers, item_id=lambda x: f"item-{x:02d}"
    ) as results:
        got = list(results)
    failures = [r for r in got if isinstance(r, ItemFailure)]
    assert len(failures) == 1
    failure = failures[0]
    assert (failure.index, failure.item, failure.item_id) == (3, 3, "item-03")
    assert failure.error_type == "ValueError"
    assert failure.message == "three is refused (got 3)"
    assert "Traceback" in failure.traceback and "fails_on_three" in failure.traceback
    done = {r.index: r.value for r in got if isinstance(r, ItemResult)}
    assert done == {x: 10 * x for x in items if x != 3}
    with pytest.raises(ValueError, match="three is refused") as raised:
        failure.reraise()
    if workers > 1:  # the worker's traceback comes along as the cause
        assert isinstance(raised.value.__cause__, RemoteError)
        assert "fails_on_three" in str(raised.value.__cause__)


def test_workers_run_blas_on_one_thread() -> None:
    # Two threads in this process (a fork's workers start with its settings): the workers
    # must bring it down to one themselves.
    with (
        threadpool_limits(limits=2, user_api="blas"),
        parallel_map(blas_threads, range(4), no_context, workers=2) as results,
    ):
        got = [r.value for r in results if isinstance(r, ItemResult)]
    assert len(got) == 4
    assert all(threads and set(threads) == {1} for threads in got), got


def test_the_initialiser_runs_once_per_worker(tmp_path: Path) -> None:
    starts = tmp_path / "starts"
    with parallel_map(
        who_runs, range(30), functools.partial(Context, 0, starts), workers=2
    ) as results:
        got = [r.value for r in results if isinstance(r, ItemResult)]
    assert len(got) == 30
    started = [int(line) for line in starts.read_text().split()]
    assert len(started) == len(set(started)) <= 2, "an initialiser ran twice in one worker"
    assert {pid for pid, _, _ in got} <= set(started)
    tokens = {pid: {token for p, token, _ in got if p == pid} for pid, _, _ in got}
    assert all(len(t) == 1 for t in tokens.values()), "a worker's items saw two contexts"
    assert all(own_group for _, _, own_group in got), "a worker shares its caller's group"
    assert os.getpid() not in started


def test_an_initialiser_that_raises_stops_the_map() -> None:
    with (
        pytest.raises(WorkerStartError, match="OSError: no model here"),
        parallel_map(fails_on_three, range(4), broken_start, workers=2) as results,
    ):
        list(results)
    with (
        pytest.raises(OSError, match="no model here"),
        parallel_map(fails_on_three, range(4), broken_start, workers=1) as results,
    ):
        list(results)


@needs_proc
@pytest.mark.parametrize("how", ["exception in the loop", "Ctrl-C while waiting"])
def test_an_interrupted_map_leaves_no_live_process(announcements: Announcements, how: str) -> None:
    fifo = str(announcements.path)
    with (
        pytest.raises(KeyboardInterrupt),
        parallel_map(sleeper, range(6), functools.partial(Path, fifo), workers=2) as results,
    ):
        first = next(results)
        assert isinstance(first, ItemResult) and first.index == 0
        # Both workers busy, each with a child process of its own (as a compiler would be).
        announcements.wait_for("child", 2)
        announcements.wait_for("worker", 2)
        if how == "Ctrl-C while waiting":
            # What a terminal does, from another thread while this one waits for a result.
            threading.Thread(target=os.kill, args=(os.getpid(), signal.SIGINT)).start()
            next(results)
        raise KeyboardInterrupt
    # Killed, not waited for: no item slept to its end.
    announcements.drain()
    assert not announcements.pids("finished")
    workers = announcements.pids("worker") | {first.value}
    assert len(workers) == 2
    alive = _wait_gone(workers | announcements.pids("child"))
    assert not alive, f"processes {alive} outlived the interrupted map"


@needs_proc
def test_ctrl_c_while_results_of_megabytes_stream_in_stops_at_once(
    announcements: Announcements,
) -> None:
    # A worker killed half-way through sending its result must not leave the caller waiting
    # for the rest (ProcessPoolExecutor's shutdown did, for ever). Item 5 sends Ctrl-C to the
    # caller while the other worker streams 4 MB results, then sleeps a minute.
    received = 0
    fifo = str(announcements.path)
    with (
        pytest.raises(KeyboardInterrupt),
        parallel_map(streamer, range(400), functools.partial(Path, fifo), workers=2) as results,
    ):
        for result in results:
            assert isinstance(result, ItemResult)
            assert result.value.shape == (512 * 1024,) and result.value[0] == result.index
            received += 1
    announcements.drain()
    assert len([words for words in announcements.lines if words[0] == "sigint"]) == 1
    assert not announcements.pids("finished"), "the map waited for the sleeping item"
    assert received < 399  # the sleeping item never answered, the rest were cut short
    assert not _wait_gone(announcements.pids("worker"))


def test_a_ctrl_c_the_item_caught_ends_the_map_after_that_item() -> None:
    calls: list[int] = []
    with (
        pytest.raises(KeyboardInterrupt),
        parallel_map(catches_ctrl_c, range(5), functools.partial(lambda c: c, calls)) as results,
    ):
        list(results)
    assert calls == [0]


@needs_proc
def test_a_ctrl_c_dropped_in_a_fork_hook_still_stops_the_map(
    announcements: Announcements,
) -> None:
    fifo = str(announcements.path)
    _CTRL_C_IN_FORK_HOOK.set()
    try:
        with (
            pytest.raises(KeyboardInterrupt),
            parallel_map(sleeper, range(1, 5), functools.partial(Path, fifo), workers=2) as rs,
        ):
            list(rs)
    finally:
        _CTRL_C_IN_FORK_HOOK.clear()
    announcements.drain()  # a worker may have started its item before it was killed
    assert not _wait_gone(announcements.pids("worker") | announcements.pids("child"))


@needs_proc
def test_workers_end_when_their_parent_is_killed(announcements: Announcements) -> None:
    script = (
        "import functools, pathlib, sys\n"
        "sys.path.insert(0, sys.argv[2])\n"
        "from test_map import sleeper\n"
        "from casadi_debris.parallel import parallel_map\n"
        "with parallel_map(sleeper, [1, 2], functools.partial(pathlib.Path, sys.argv[1]),"
        " workers=2) as results:\n"
        "    list(results)\n"
    )
    parent = subprocess.Popen(
        [sys.executable, "-c", script, str(announcements.path), str(Path(__file__).parent)],
        start_new_session=True,
    )
    try:
        workers = announcements.wait_for("worker", 2)
        children = announcements.wait_for("child", 2)
        parent.send_signal(signal.SIGKILL)
        parent.wait()
        # The workers die with their parent; their children are their group's to stop.
        alive = _wait_gone(workers)
        assert not alive, f"workers {alive} outlived their parent"
    finally:
        if parent.poll() is None:
            parent.kill()
        announcements.drain()
        for pid in announcements.pids("child"):
            if _running(pid):
                os.kill(pid, signal.SIGKILL)
    assert children


def test_the_dask_back_end_records_failures_and_starts_each_worker_once(tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    starts = tmp_path / "starts"
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None
    ) as cluster:
        with parallel_map(
            who_runs,
            range(12),
            functools.partial(Context, 0, starts),
            scheduler=cluster.scheduler_address,
        ) as results:
            got = [r.value for r in results if isinstance(r, ItemResult)]
        with parallel_map(
            fails_on_three, range(6), no_context, scheduler=cluster.scheduler_address
        ) as results:
            outcome = list(results)
    assert len(got) == 12 and len({token for _, token, _ in got}) == 1
    assert len(starts.read_text().split()) == 1
    failures = [r for r in outcome if isinstance(r, ItemFailure)]
    assert [(f.item_id, f.error_type) for f in failures] == [("3", "ValueError")]
    assert sorted(r.value for r in outcome if isinstance(r, ItemResult)) == [0, 10, 20, 40, 50]


def test_fewer_than_one_worker_is_refused() -> None:
    with pytest.raises(ValueError, match="at least 1"):
        parallel_map(shifted_square, [1], no_context, workers=0)
