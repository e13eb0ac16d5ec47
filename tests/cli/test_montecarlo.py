"""montecarlo on the command line: Ctrl-C, a killed parent, two campaigns on one folder."""

from __future__ import annotations

import contextlib
import fcntl
import os
import pty
import re
import select
import signal
import subprocess
import sys
import termios
from collections.abc import Iterator
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


class Campaign:
    """``casadi-debris montecarlo`` run on a terminal of its own (a pseudo-terminal), as a
    user runs it: its progress bar, redrawn at every case, tells the test when cases are
    done, and Ctrl-C is typed on the terminal."""

    def __init__(self, tmp_path: Path, problem: Path, samples: int, *options: str) -> None:
        temporary = tmp_path / "tmp"
        temporary.mkdir(exist_ok=True)
        args = ["montecarlo", str(problem), "--samples", str(samples), "--workers", "2"]
        self.terminal, user_side = pty.openpty()
        self.process = subprocess.Popen(
            [sys.executable, "-m", "casadi_debris.cli", *args, *options, "--out", "mc"],
            cwd=tmp_path,
            env={**os.environ, "TMPDIR": str(temporary)},
            stdin=user_side,
            stdout=subprocess.DEVNULL,
            stderr=user_side,
            start_new_session=True,
            preexec_fn=_take_terminal,
        )
        os.close(user_side)
        self.output = ""
        self.pid = self.process.pid

    def wait_for_cases(self, count: int, limit_s: float = 300.0) -> int:
        """Cases done, once at least ``count`` are (``limit_s`` only bounds a hang)."""
        while (done := self.done()) < count:
            ready, _, _ = select.select([self.terminal], [], [], limit_s)
            assert ready and self._read(), f"{done} cases done, then nothing:\n{self.output}"
        return done

    def done(self) -> int:
        counts = re.findall(r"(\d+)/\d+ cases", self.output)
        return int(counts[-1]) if counts else 0

    def ctrl_c(self) -> None:
        os.write(self.terminal, b"\x03")

    def finish(self) -> int:
        """Read the terminal to its end; the exit status."""
        while self._read():
            pass
        return self.process.wait()

    def _read(self) -> bool:
        try:
            data = os.read(self.terminal, 65536)
        except OSError:  # the other side closed: the campaign ended
            return False
        self.output += data.decode(errors="replace")
        return bool(data)

    def close(self) -> None:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(self.pid, signal.SIGKILL)
        self.process.wait()
        os.close(self.terminal)


def _take_terminal() -> None:
    """In the campaign's process: its terminal becomes the session's controlling terminal,
    and a Ctrl-C typed there interrupts it, as a user's would, even when the tests were
    started with SIGINT ignored (a disposition a new program inherits)."""
    fcntl.ioctl(0, termios.TIOCSCTTY, 0)
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.fixture()
def campaigns() -> Iterator[list[Campaign]]:
    started: list[Campaign] = []
    yield started
    for campaign in started:
        campaign.close()


def _wait_gone(workers: set[int], limit_s: float = 120.0) -> list[int]:
    """The workers still running once each has ended: each end is an event, its pidfd
    turning readable (a zombie has ended), not a state polled against a deadline;
    ``limit_s`` only bounds a hang."""
    for pid in workers:
        try:
            handle = os.pidfd_open(pid)
        except ProcessLookupError:
            continue  # already ended and reaped
        try:
            select.select([handle], [], [], limit_s)
        finally:
            os.close(handle)
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
    tmp_path: Path, short_problem: Path, campaigns: list[Campaign]
) -> None:
    # Cases one by one on CasADi's virtual machine (about a second each): the campaign of
    # 12 is still running when the test, told a case is done, kills it.
    campaign = Campaign(tmp_path, short_problem, 12, "--no-jit")
    campaigns.append(campaign)
    campaign.wait_for_cases(1)
    workers = _children(campaign.pid)
    assert len(workers) == 2
    os.kill(campaign.pid, signal.SIGKILL)
    campaign.finish()
    alive = _wait_gone(workers)
    assert not alive, f"workers {alive} outlived their parent"
    assert list((tmp_path / "tmp").iterdir()) == []
    assert {p.name for p in tmp_path.iterdir()} == {"short.toml", "tmp", "mc.partial"}
    # The next run takes the dead run's lock over and finishes the campaign.
    again = ["--samples", "12", "--workers", "2", "--no-jit", "--out", str(tmp_path / "mc")]
    resumed = CliRunner().invoke(main, ["montecarlo", str(short_problem), *again, "--json"])
    assert resumed.exit_code == 0, resumed.output
    assert {p.name for p in tmp_path.iterdir()} == {"short.toml", "tmp", "mc"}


def test_ctrl_c_keeps_the_cases_and_says_how_to_resume(
    tmp_path: Path, short_problem: Path, campaigns: list[Campaign]
) -> None:
    # More cases than can run before Ctrl-C, whatever the machine: it is typed once the
    # first is done, while the workers run their next batches and send their results.
    campaign = Campaign(tmp_path, short_problem, 3000)
    campaigns.append(campaign)
    campaign.wait_for_cases(1)
    workers = _children(campaign.pid)
    campaign.ctrl_c()
    status = campaign.finish()
    assert status == 130, campaign.output
    last = campaign.output.replace("\r", "\n").strip().splitlines()[-1]
    kept = re.fullmatch(r"interrupted: (\d+) of 3000 cases are kept in (.+); (.+)", last)
    assert kept and kept[3] == "run the same command again to resume", last
    assert "Traceback" not in campaign.output
    assert not _wait_gone(workers)
    partial = tmp_path / "mc.partial"
    assert Path(kept[2]).resolve() == partial.resolve()
    assert {p.name for p in partial.iterdir()} <= {"campaign.json", "cases"}
    # Stopped, not run to its end (how soon is tests/parallel/test_map.py's: no item finishes).
    assert len(list((partial / "cases").glob("*.json"))) == int(kept[1]) >= 1
    assert int(kept[1]) < 3000


def test_a_second_campaign_on_a_folder_in_use_is_refused(
    tmp_path: Path, short_problem: Path, campaigns: list[Campaign]
) -> None:
    first = Campaign(tmp_path, short_problem, 3000, "--no-jit")
    campaigns.append(first)
    first.wait_for_cases(1)
    second = CliRunner().invoke(
        main,
        ["montecarlo", str(short_problem), "--samples", "60", "--out", str(tmp_path / "mc")],
    )
    assert second.exit_code == 2, second.output
    assert f"in use by process {first.pid}" in second.output


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
