"""The processes of the runs: the runner as their subreaper, their trees found and killed."""

from __future__ import annotations

import contextlib
import os
import signal

PR_SET_CHILD_SUBREAPER = 36


def set_subreaper(on: bool) -> bool:
    """Orphans of the runs become this process's children (Linux), so that none is missed."""
    try:
        import ctypes

        libc = ctypes.CDLL(None, use_errno=True)
        return libc.prctl(PR_SET_CHILD_SUBREAPER, int(on), 0, 0, 0) == 0
    except (OSError, AttributeError):
        return False


def processes() -> dict[int, tuple[int, str]]:
    """pid -> (parent pid, state) of every process."""
    out: dict[int, tuple[int, str]] = {}
    for name in os.listdir("/proc"):
        if not name.isdigit():
            continue
        try:
            with open(f"/proc/{name}/stat", encoding="ascii", errors="replace") as handle:
                stat = handle.read()
        except OSError:
            continue
        fields = stat[stat.rfind(")") + 2 :].split()
        out[int(name)] = (int(fields[1]), fields[0])
    return out


def children_of(pid: int) -> set[int]:
    return {p for p, (ppid, _) in processes().items() if ppid == pid}


def kill_tree(pid: int) -> None:
    """SIGKILL a process, its process group and every descendant."""
    procs = processes()
    tree, frontier = set(), [pid]
    while frontier:
        parent = frontier.pop()
        children = [p for p, (pp, _) in procs.items() if pp == parent and p not in tree]
        tree.update(children)
        frontier.extend(children)
    with contextlib.suppress(ProcessLookupError, PermissionError):
        os.killpg(pid, signal.SIGKILL)
    for p in (pid, *tree):
        with contextlib.suppress(ProcessLookupError, PermissionError):
            os.kill(p, signal.SIGKILL)


def reap_orphans(keep: set[int]) -> bool:
    """Kill and reap processes handed to us as orphans; True if any was still running."""
    me = os.getpid()
    running = False
    for pid, (ppid, state) in processes().items():
        if ppid != me or pid in keep:
            continue
        if state not in ("Z", "X"):
            running = True
            kill_tree(pid)
        with contextlib.suppress(ChildProcessError):
            os.waitpid(pid, 0)
    return running
