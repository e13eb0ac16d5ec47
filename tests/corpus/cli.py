"""``python -m tests.corpus``: list the entries, run them and print the report, or write one out."""

from __future__ import annotations

import argparse
import json
import shlex
import signal
import sys
import time
from pathlib import Path
from typing import Any

from . import __doc__ as package_doc
from .catalogue import SEED, corpus
from .entry import Entry
from .report import counts, failure_table, grouped, json_payload
from .repository import git_status, new_repo_files
from .runner import run_corpus
from .sandbox import working_folder, write_files


def materialize(entry_id: str, folder: Path, seed: int = SEED) -> Entry:
    """Write one entry's files into ``folder`` as a run would have them."""
    entry = next(e for e in corpus(seed) if e.id == entry_id)
    folder = folder.resolve()
    write_files(entry, working_folder(folder), folder)
    return entry


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m tests.corpus",
        description=package_doc,
        formatter_class=argparse.RawTextHelpFormatter,
    )
    parser.add_argument("--report", action="store_true", help="run the corpus and print counts")
    parser.add_argument("--fast", action="store_true", help="only the fast subset")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--only", default="", help="comma-separated entry ids or id prefixes")
    parser.add_argument("--seed", type=int, default=SEED)
    parser.add_argument("--json", type=Path, help="write every result to this JSON file")
    parser.add_argument("--list", action="store_true", help="list the entries")
    parser.add_argument("--materialize", nargs=2, metavar=("ID", "FOLDER"))
    return parser


def _materialize_command(entry_id: str, folder: str, seed: int) -> int:
    entry = materialize(entry_id, Path(folder), seed)
    print(f"{entry.id}: {entry.description} (expect {entry.expect})")
    print(f"cd {shlex.quote(str(working_folder(Path(folder).resolve())))}")
    for command in entry.commands():
        print(command)
    return 0


def _selected(args: argparse.Namespace) -> list[Entry]:
    entries = corpus(args.seed)
    if args.fast:
        entries = [e for e in entries if e.fast]
    if args.only:
        wanted = [w for w in args.only.split(",") if w]
        entries = [e for e in entries if any(e.id == w or e.id.startswith(w) for w in wanted)]
    return entries


def _list(entries: list[Entry]) -> int:
    for e in entries:
        flag = "fast" if e.fast else "slow"
        commands = " ; ".join(e.commands())[:160]
        print(f"{e.id} {flag} {e.expect:6} {e.description[:100]} :: {commands}")
    print(f"{len(entries)} entries", file=sys.stderr)
    return 0


def _stop(signum: int, frame: Any) -> None:
    raise KeyboardInterrupt  # so that the runs are killed and the folders removed


def _report(entries: list[Entry], args: argparse.Namespace) -> int:
    signal.signal(signal.SIGTERM, _stop)
    started = time.monotonic()
    repo_before = git_status()
    results = run_corpus(entries, jobs=args.jobs, progress=True)
    repo_new = new_repo_files(repo_before, git_status())
    import casadi_debris

    print(f"# casadi_debris from {Path(casadi_debris.__file__).parent}")
    print(
        f"# bad-input corpus: seed {args.seed}, {len(entries)} entries, "
        f"{time.monotonic() - started:.0f} s, {args.jobs} jobs"
    )
    for name, value in counts(results).items():
        print(f"{name:40} {value}")
    print(f"{'new files in the repository':40} {len(repo_new)} {repo_new[:10]}")
    print("\n# failures grouped\n" + grouped(results))
    print("\n# failures\n" + failure_table(results))
    if args.json:
        args.json.write_text(json.dumps(json_payload(results), indent=1), encoding="utf-8")
    return 0 if all(r.ok for r in results) and not repo_new else 1


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.materialize:
        return _materialize_command(*args.materialize, args.seed)
    entries = _selected(args)
    if args.list or not args.report:
        return _list(entries)
    return _report(entries, args)
