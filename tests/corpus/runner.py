"""Running entries: each invocation in a forked child, a few at a time, then checked.

Each run forks after the imports (no interpreter start-up per run), in a fresh
folder (:mod:`.sandbox`), and is killed after :data:`~.checks.TIMEOUT_S`. The
folders above its working folder are listed before and after, and its files
snapshot, to see what it wrote outside or changed.
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import signal
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .checks import TIMEOUT_S, EntryResult, RunResult, check
from .child import run_child
from .entry import Entry
from .processes import children_of, kill_tree, reap_orphans, set_subreaper
from .sandbox import GUARDS, listing, snapshot_files, working_folder, write_files


@dataclass
class _Pending:
    entry: Entry
    index: int
    args: tuple[str, ...]
    pid: int
    rundir: Path
    cwd: Path
    started: float
    before: dict[str, tuple[Any, ...]]
    listings: dict[Path, set[str]]


def prepare_parent() -> list[str]:
    """Imports done once, before any fork (children only run the command)."""
    import matplotlib

    matplotlib.use("Agg")
    import importlib
    import pkgutil

    import matplotlib.font_manager
    import matplotlib.pyplot

    import casadi_debris

    # The commands import their modules when run: import every module once here,
    # or each forked run pays for it (seconds).
    failed: list[str] = []
    for module in pkgutil.walk_packages(casadi_debris.__path__, "casadi_debris."):
        if module.name.endswith("__main__"):
            continue  # runs the command line when imported
        try:
            importlib.import_module(module.name)
        except Exception as exc:
            failed.append(f"{module.name}: {type(exc).__name__}: {exc}")
    return failed


def _collect(item: _Pending, result: RunResult, units_dir: Path) -> None:
    """Output, and what appeared or went outside the working folder or changed in it."""
    for name in ("stdout", "stderr"):
        with contextlib.suppress(OSError):
            data = (item.rundir / name).read_bytes()
            setattr(result, name, data.decode("utf-8", "backslashreplace"))
    for folder, names in item.listings.items():
        now = listing(folder)
        if folder == item.rundir:
            new = now - names - {"stdout", "stderr"}
        elif folder == units_dir:
            new = {n for n in now - names if not re.fullmatch(r"[A-Z]\d+-\d+", n)}
        else:
            new = now - names
        result.outside.extend(str(folder / n) for n in sorted(new))
        gone = names - now
        if folder != units_dir:
            result.outside.extend(f"{folder / n} (deleted)" for n in sorted(gone))
    after = snapshot_files(item.cwd) if item.cwd.exists() else {}
    for path, state in item.before.items():
        if path.startswith(".tmp"):
            continue
        if path not in after:
            result.changed.append(f"{path} (deleted)")
        elif after[path] != state:
            result.changed.append(f"{path} (changed)")


@dataclass
class _Batch:
    """The runs under way and the results so far."""

    root: Path
    timeout: float
    keep: bool
    progress: bool
    total: int
    subreaper: bool = False
    known_children: set[int] = field(default_factory=set)
    pending: list[_Pending] = field(default_factory=list)
    results: dict[str, list[RunResult | None]] = field(default_factory=dict)
    done: int = 0

    @property
    def units_dir(self) -> Path:
        return self.root / "units"

    def start(self, entry: Entry, index: int, args: tuple[str, ...]) -> None:
        """Write the run's files, note what is there, fork the child."""
        rundir = self.units_dir / f"{entry.id}-{index}"
        cwd = working_folder(rundir)
        write_files(entry, cwd, rundir)
        before = snapshot_files(cwd)
        guards = [rundir.joinpath(*GUARDS[:i]) for i in range(len(GUARDS) + 1)]
        listings = {folder: listing(folder) for folder in (self.root, self.units_dir, *guards)}
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            run_child(args, cwd, rundir)
        with contextlib.suppress(OSError):
            os.setpgid(pid, pid)
        started = time.monotonic()
        self.pending.append(
            _Pending(entry, index, args, pid, rundir, cwd, started, before, listings)
        )

    def poll(self, item: _Pending) -> None:
        """Finish ``item`` if it ended, or kill it if its time is up."""
        finished, status = os.waitpid(item.pid, os.WNOHANG)
        elapsed = time.monotonic() - item.started
        result = RunResult(item.args, seconds=elapsed)
        if finished == 0:
            if elapsed < self.timeout:
                return
            kill_tree(item.pid)
            os.waitpid(item.pid, 0)
            result.timed_out = True
        elif os.WIFSIGNALED(status):
            result.signal = os.WTERMSIG(status)
        else:
            result.code = os.WEXITSTATUS(status)
        self.pending.remove(item)
        self._settle(item, result)

    def _settle(self, item: _Pending, result: RunResult) -> None:
        """Processes left behind killed, the result collected, the folder removed."""
        try:
            os.killpg(item.pid, signal.SIGKILL)
            result.leftover = not result.timed_out
        except (ProcessLookupError, PermissionError):
            pass
        if self.subreaper:
            keep_pids = self.known_children | {p.pid for p in self.pending}
            orphans = reap_orphans(keep_pids)
            result.leftover = result.leftover or (orphans and not result.timed_out)
        _collect(item, result, self.units_dir)
        self.results[item.entry.id][item.index] = result
        self.done += 1
        if self.progress and self.done % 50 == 0:
            print(f"  {self.done}/{self.total} runs", file=sys.stderr, flush=True)
        if not self.keep:
            shutil.rmtree(item.rundir, ignore_errors=True)

    def stop(self) -> None:
        """Kill what still runs (an interrupt), reap orphans, remove the folders."""
        for item in self.pending:
            kill_tree(item.pid)
            with contextlib.suppress(ChildProcessError):
                os.waitpid(item.pid, 0)
        if self.subreaper:
            reap_orphans(self.known_children)
            set_subreaper(False)
        if not self.keep:
            shutil.rmtree(self.root, ignore_errors=True)


def run_corpus(
    entries: list[Entry],
    jobs: int = 1,
    timeout: float = TIMEOUT_S,
    progress: bool = False,
    keep: bool = False,
) -> list[EntryResult]:
    """Run every entry's invocations, each in a forked child; return checked results."""
    for failure in prepare_parent():  # a tree half-way through an edit: results will show it
        print(f"warning: cannot import {failure}", file=sys.stderr, flush=True)
    queue = [(e, i, run) for e in entries for i, run in enumerate(e.runs)]
    queue.reverse()
    root = Path(tempfile.mkdtemp(prefix="casadi-debris-corpus-"))
    batch = _Batch(root, timeout, keep, progress, total=len(queue))
    batch.units_dir.mkdir()
    batch.subreaper = set_subreaper(True)
    batch.known_children = children_of(os.getpid())
    batch.results = {e.id: [None] * len(e.runs) for e in entries}
    try:
        while queue or batch.pending:
            while queue and len(batch.pending) < jobs:
                batch.start(*queue.pop())
            time.sleep(0.01)
            for item in list(batch.pending):
                batch.poll(item)
    finally:
        batch.stop()
    return [check(e, [r for r in batch.results[e.id] if r is not None]) for e in entries]
