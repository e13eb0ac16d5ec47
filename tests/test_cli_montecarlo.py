"""montecarlo on the command line: Ctrl-C, a killed parent, two campaigns on one folder."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
from click.testing import CliRunner

from casadi_debris.cli import main
from casadi_debris.config import default_problem_path

pytestmark = pytest.mark.skipif(not Path("/proc").is_dir(), reason="reads /proc")


@pytest.fixture()
def short_problem(tmp_path: Path) -> Path:
    """The paper's slew cut to 600 s: about a second a case."""
    problem = tmp_path / "short.toml"
    problem.write_text(
        f'extends = "{default_problem_path().parent / "paper_slew.toml"}"\n'
        'name = "short"\n[simulation]\nduration_s = 600.0\n'
    )
    return problem


def _start(tmp_path: Path, problem: Path, out: str = "mc", samples: int = 60) -> subprocess.Popen:
    temporary = tmp_path / "tmp"
    temporary.mkdir(exist_ok=True)
    args = ["montecarlo", str(problem), "--samples", str(samples), "--workers", "2", "--out", out]
    return subprocess.Popen(
        [sys.executable, "-m", "casadi_debris.cli", *args],
        cwd=tmp_path,
        env={**os.environ, "TMPDIR": str(temporary)},
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )


def _wait_for_workers(parent: subprocess.Popen) -> set[int]:
    deadline = time.monotonic() + 120
    workers: set[int] = set()
    while len(workers) < 2 and time.monotonic() < deadline and parent.poll() is None:
        time.sleep(0.2)
        workers = _children(parent.pid)
    assert len(workers) >= 2, "the campaign never started its workers"
    time.sleep(1.0)
    return workers


def _wait_gone(workers: set[int]) -> list[int]:
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(_running(w) for w in workers):
        time.sleep(0.1)
    return [w for w in workers if _running(w)]


def _running(pid: int) -> bool:
    """Whether a process exists and is not a zombie waiting to be reaped."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _children(pid: int) -> set[int]:
    found = set()
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            if int(fields[1]) == pid:
                found.add(int(entry.name))
    return found


def test_killing_the_parent_alone_ends_its_workers_and_leaves_no_temporary(
    tmp_path: Path, short_problem: Path
) -> None:
    parent = _start(tmp_path, short_problem)
    try:
        workers = _wait_for_workers(parent)
        parent.send_signal(signal.SIGKILL)
        parent.wait()
        alive = _wait_gone(workers)
        assert not alive, f"workers {alive} outlived their parent"
        assert list((tmp_path / "tmp").iterdir()) == []
        assert {p.name for p in tmp_path.iterdir()} == {"short.toml", "tmp", "mc.partial"}
        # The next run takes the dead run's lock over and finishes the campaign.
        resumed = CliRunner().invoke(
            main,
            [
                "montecarlo",
                str(short_problem),
                "--samples",
                "60",
                "--workers",
                "2",
                "--out",
                str(tmp_path / "mc"),
                "--json",
            ],
        )
        assert resumed.exit_code == 0, resumed.output
        assert {p.name for p in tmp_path.iterdir()} == {"short.toml", "tmp", "mc"}
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(parent.pid, signal.SIGKILL)


def test_ctrl_c_keeps_the_cases_and_says_how_to_resume(tmp_path: Path, short_problem: Path) -> None:
    # Enough cases that the campaign is still running when Ctrl-C comes: with a warm
    # compiled-step cache on an idle machine, 60 of them end in about a second.
    parent = _start(tmp_path, short_problem, samples=3000)
    try:
        workers = _wait_for_workers(parent)
        os.killpg(parent.pid, signal.SIGINT)  # what Ctrl-C in a terminal does
        _, stderr = parent.communicate(timeout=60)
        assert parent.returncode == 130, stderr
        last = stderr.replace("\r", "\n").strip().splitlines()[-1]
        assert last.startswith("interrupted: ") and "run the same command again" in last
        assert "Traceback" not in stderr
        assert not _wait_gone(workers)
        partial = tmp_path / "mc.partial"
        assert {p.name for p in partial.iterdir()} <= {"campaign.json", "cases"}
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(parent.pid, signal.SIGKILL)


def test_a_second_campaign_on_a_folder_in_use_is_refused(
    tmp_path: Path, short_problem: Path
) -> None:
    first = _start(tmp_path, short_problem)
    try:
        _wait_for_workers(first)
        second = CliRunner().invoke(
            main,
            ["montecarlo", str(short_problem), "--samples", "60", "--out", str(tmp_path / "mc")],
        )
        assert second.exit_code == 2, second.output
        assert f"in use by process {first.pid}" in second.output
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(first.pid, signal.SIGKILL)


@pytest.mark.parametrize(
    "address", ["inproc://x", "tcp://h", "tcp://h:0", "tcp://h:70000", "ucx://h:1", "tcp://a b:1"]
)
def test_a_scheduler_address_must_be_tcp_or_tls(address: str, tmp_path: Path) -> None:
    result = CliRunner().invoke(
        main, ["montecarlo", "--samples", "1", "--scheduler", address, "--out", str(tmp_path / "x")]
    )
    assert result.exit_code == 2
    assert "--scheduler: expected tcp://host:port or tls://host:port" in result.output
    assert not (tmp_path / "x").exists()
