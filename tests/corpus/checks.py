"""What a run gave and what is wrong with it.

The checks of every run: no traceback, exit status not 3 (nor anything but 0
and 2), no hang, no signal, nothing written outside the run's folder and no
file present before the run changed, no process left behind, and the entry's
expectation (``reject``: exit 2 with one ``error:`` line naming one of its
names; ``ok``: exit 0).
"""

from __future__ import annotations

import re
import shlex
from collections.abc import Iterable
from dataclasses import dataclass, field

from .entry import Entry

TIMEOUT_S = 20.0
_TRACEBACK = "Traceback (most recent call last)"


@dataclass
class RunResult:
    args: tuple[str, ...]
    code: int | None = None  # exit status; None: killed (hang) or signal
    signal: int | None = None
    timed_out: bool = False
    stdout: str = ""
    stderr: str = ""
    seconds: float = 0.0
    outside: list[str] = field(default_factory=list)  # written outside its folder
    changed: list[str] = field(default_factory=list)  # files there before, changed or gone
    leftover: bool = False  # processes still in its group after it ended


@dataclass
class EntryResult:
    entry: Entry
    runs: list[RunResult]
    problems: list[str]

    @property
    def ok(self) -> bool:
        return not self.problems


def _error_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if re.match(r"(?i)^(internal )?error\b", line)]


def names_match(message: str, names: Iterable[str]) -> bool:
    """Does the message name one of these keys, table prefixes (``hub.``) or options?"""
    for name in names:
        if name.endswith("."):
            pattern = rf"(?<![\w.]){re.escape(name)}\w"
        elif name.startswith("-"):
            pattern = rf"{re.escape(name)}(?![\w-])"
        else:
            pattern = rf"(?<![\w.]){re.escape(name)}(?![\w])"
        if re.search(pattern, message):
            return True
    return False


def _status_problems(run: RunResult, line: str, where: str) -> list[str]:
    """Hangs, signals, tracebacks, exit statuses other than 0 and 2."""
    problems: list[str] = []
    output = run.stdout + run.stderr
    if run.timed_out:
        problems.append(f"hang: no answer in {TIMEOUT_S:.0f} s [{where}]")
    elif run.signal is not None:
        problems.append(f"killed by signal {run.signal} [{where}]")
    if _TRACEBACK in output:
        last = [ln for ln in output.splitlines() if ln.strip()][-1:]
        problems.append(f"traceback: {last[0] if last else ''} [{where}]")
    if run.code == 3:
        problems.append(f"exit 3: {line} [{where}]")
    elif run.code not in (None, 0, 2, 3):
        problems.append(f"exit {run.code}: {line} [{where}]")
    return problems


def _trace_problems(run: RunResult, where: str) -> list[str]:
    """Files written outside the run's folder or changed in it, processes left behind."""
    problems: list[str] = []
    if run.outside:
        problems.append(f"wrote outside its folder: {run.outside[:5]} [{where}]")
    if run.changed:
        problems.append(f"changed files it did not create: {run.changed[:5]} [{where}]")
    if run.leftover:
        problems.append(f"left processes running [{where}]")
    return problems


def _answer_problems(
    entry: Entry, run: RunResult, errors: list[str], line: str, where: str
) -> list[str]:
    """The entry's expectation: accepted or refused, the one error line, the names."""
    problems: list[str] = []
    if run.code == 0 and entry.expect == "reject":
        problems.append(f"silent: bad input accepted (exit 0) [{where}]")
    if run.code == 2 and entry.expect == "ok":
        problems.append(f"valid input rejected: {line} [{where}]")
    if run.code == 2:
        if len(errors) != 1:
            problems.append(f"exit 2 without exactly one error line ({len(errors)}) [{where}]")
        elif entry.names and not names_match(errors[0], entry.names):
            problems.append(
                f"exit 2 names none of {list(entry.names)}: {errors[0][:300]} [{where}]"
            )
    if run.code == 0:
        found = [s for s in entry.forbid_stdout if s in run.stdout]
        if found:
            problems.append(f"output contains {found} [{where}]")
    return problems


def _run_problems(entry: Entry, run: RunResult) -> list[str]:
    """The problems of one run, in the order the checks are listed above."""
    where = shlex.join(run.args)
    errors = _error_lines(run.stderr)
    line = errors[-1] if errors else (run.stderr.strip().splitlines() or [""])[-1]
    return [
        *_status_problems(run, line, where),
        *_answer_problems(entry, run, errors, line, where),
        *_trace_problems(run, where),
    ]


def check(entry: Entry, runs: list[RunResult]) -> EntryResult:
    """The problems of one entry's runs (empty: it passed)."""
    problems = [problem for run in runs for problem in _run_problems(entry, run)]
    return EntryResult(entry, runs, problems)
