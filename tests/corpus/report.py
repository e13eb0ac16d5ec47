"""The report of a corpus run: counts, failures grouped by kind, the failure table, JSON."""

from __future__ import annotations

from collections import defaultdict
from typing import Any

from .checks import EntryResult


def counts(results: list[EntryResult]) -> dict[str, int]:
    runs = [r for res in results for r in res.runs]
    problems = [p for res in results for p in res.problems]
    return {
        "inputs tried (entries)": len(results),
        "invocations": len(runs),
        "exit 0": sum(r.code == 0 for r in runs),
        "exit 2": sum(r.code == 2 for r in runs),
        "exit 3": sum(r.code == 3 for r in runs),
        "other exit": sum(r.code not in (None, 0, 2, 3) for r in runs),
        "hangs": sum(r.timed_out for r in runs),
        "signals": sum(r.signal is not None for r in runs),
        "silent (bad input accepted)": sum(p.startswith("silent") for p in problems),
        "tracebacks": sum(p.startswith("traceback") for p in problems),
        "files written outside / changed": sum(bool(r.outside or r.changed) for r in runs),
        "valid input rejected": sum(p.startswith("valid input rejected") for p in problems),
        "exit 2 not naming the key/option": sum(
            p.startswith("exit 2 names none") for p in problems
        ),
        "exit 2 without one error line": sum(p.startswith("exit 2 without") for p in problems),
        "processes left": sum(r.leftover for r in runs),
        "entries failing": sum(not res.ok for res in results),
    }


_KINDS = (
    "hang",
    "killed by signal",
    "traceback",
    "exit 3",
    "silent",
    "valid input rejected",
    "exit 2 names none",
    "exit 2 without",
    "wrote outside",
    "changed files",
    "left processes",
    "output contains",
    "exit",
)


def _kind(problem: str) -> str:
    for prefix in _KINDS:
        if problem.startswith(prefix):
            return prefix
    return problem.split(":")[0]


def failure_table(results: list[EntryResult], limit: int | None = None) -> str:
    lines = []
    for res in results:
        if res.ok:
            continue
        e = res.entry
        lines.append(f"{e.id} [{e.expect}] {e.description}")
        for problem in res.problems:
            lines.append(f"    {problem}")
    if limit is not None and len(lines) > limit:
        lines = [*lines[:limit], f"... ({len(lines) - limit} more lines)"]
    return "\n".join(lines)


def grouped(results: list[EntryResult]) -> str:
    """Failures grouped by kind of problem, then by command and mutation."""
    groups: dict[tuple[str, str], list[tuple[EntryResult, str]]] = defaultdict(list)
    for res in results:
        for problem in res.problems:
            command = problem.rsplit("[", 1)[-1].split()[0] if "[" in problem else "?"
            groups[(_kind(problem), f"{command} / {res.entry.category}")].append((res, problem))
    lines = []
    for (kind, sub), items in sorted(groups.items(), key=lambda kv: (kv[0][0], -len(kv[1]))):
        res, problem = items[0]
        lines.append(f"{kind} — {sub}: {len(items)}; e.g. {res.entry.id}: {res.entry.description}")
        lines.append(f"      {problem[:240]}")
    return "\n".join(lines)


def json_payload(results: list[EntryResult]) -> list[dict[str, Any]]:
    """Every result, for ``--json``."""
    return [
        {
            "id": r.entry.id,
            "description": r.entry.description,
            "expect": r.entry.expect,
            "commands": r.entry.commands(),
            "problems": r.problems,
            "codes": [run.code for run in r.runs],
            "stderr": [run.stderr[-2000:] for run in r.runs],
        }
        for r in results
    ]
