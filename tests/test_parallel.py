"""The parallel map: same results as a serial map, failures kept, one BLAS thread per
worker, no worker left behind, one initialiser call per worker."""

from __future__ import annotations

import functools
import os
import signal
import subprocess
import sys
import threading
import time
import uuid
from pathlib import Path

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


def sleeper(folder: Path, x: int) -> int:
    """Item 0 returns at once; the others start a longer-lived child process and sleep."""
    if x == 0:
        return os.getpid()
    child = subprocess.Popen(["sleep", "120"])
    (folder / f"child-{child.pid}").touch()
    (folder / f"worker-{os.getpid()}").touch()
    time.sleep(30)
    return x


def the_folder(folder: str) -> Path:
    return Path(folder)


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


def _wait_gone(pids: set[int], timeout_s: float = 10.0) -> list[int]:
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline and any(_running(p) for p in pids):
        time.sleep(0.05)
    return sorted(p for p in pids if _running(p))


def _pids(folder: Path, prefix: str) -> set[int]:
    return {int(p.name.split("-")[1]) for p in folder.glob(f"{prefix}-*")}


def _wait_for(folder: Path, prefix: str, count: int, timeout_s: float = 60.0) -> set[int]:
    deadline = time.monotonic() + timeout_s
    while len(_pids(folder, prefix)) < count and time.monotonic() < deadline:
        time.sleep(0.05)
    found = _pids(folder, prefix)
    assert len(found) >= count, f"only {len(found)} of {count} {prefix} processes started"
    return found


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
def test_an_interrupted_map_leaves_no_live_process(tmp_path: Path, how: str) -> None:
    timer = None
    with (
        pytest.raises(KeyboardInterrupt),
        parallel_map(
            sleeper, range(6), functools.partial(the_folder, str(tmp_path)), workers=2
        ) as results,
    ):
        first = next(results)
        assert isinstance(first, ItemResult) and first.index == 0
        # Both workers busy, each with a child process of its own (as a compiler would be).
        children = _wait_for(tmp_path, "child", 2)
        workers = _wait_for(tmp_path, "worker", 2) | {first.value}
        stopping = time.monotonic()
        if how == "Ctrl-C while waiting":
            timer = threading.Timer(0.5, os.kill, (os.getpid(), signal.SIGINT))
            timer.start()
            next(results)
        raise KeyboardInterrupt
    # Killed, not waited for (each item sleeps 30 s).
    assert time.monotonic() - stopping < 10.0
    if timer is not None:
        timer.join()
    assert len(workers) == 2
    alive = _wait_gone(workers | children)
    assert not alive, f"processes {alive} outlived the interrupted map"


@needs_proc
def test_workers_end_when_their_parent_is_killed(tmp_path: Path) -> None:
    script = (
        "import functools, sys\n"
        "sys.path.insert(0, sys.argv[2])\n"
        "from test_parallel import sleeper, the_folder\n"
        "from casadi_debris.parallel import parallel_map\n"
        "with parallel_map(sleeper, [1, 2], functools.partial(the_folder, sys.argv[1]),"
        " workers=2) as results:\n"
        "    list(results)\n"
    )
    parent = subprocess.Popen(
        [sys.executable, "-c", script, str(tmp_path), str(Path(__file__).parent)],
        start_new_session=True,
    )
    try:
        workers = _wait_for(tmp_path, "worker", 2)
        children = _wait_for(tmp_path, "child", 2)
        parent.send_signal(signal.SIGKILL)
        parent.wait()
        # The workers die with their parent; their children are their group's to stop.
        alive = _wait_gone(workers)
        assert not alive, f"workers {alive} outlived their parent"
    finally:
        if parent.poll() is None:
            parent.kill()
        for pid in _pids(tmp_path, "child"):
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
