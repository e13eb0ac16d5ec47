"""What every benchmark keeps beside its figures, and where it writes them.

Each script in ``benchmarks/`` prints one JSON object. With ``--record`` it also
writes it to ``docs/benchmarks/<name>.json``, from which the documentation's
benchmark page renders its tables at build time; with ``--out FILE`` to ``FILE``.
``--quick`` runs a reduced version (fewer samples or repeats, same measurements).

A script starts with :func:`start_benchmark`, given a table of its options: each
:class:`Setting` it records, with its value in the full and in the quick run, and
any other option as ``add_argument`` keywords.

The object gets two entries besides the benchmark's own:

- ``machine``: CPU count and model, platform, the versions of Python and of
  the libraries that do the work;
- ``run``: the command, quick or full, the settings it resolved to, when it
  started (UTC), how long it took, the git commit and whether the checkout had
  uncommitted changes to the code, and how busy the machine was with other
  work: the CPU time all processes used during the run (``/proc/stat``) less
  the benchmark's own and its child processes', as a share of the machine's
  capacity over the run (0.5 on 2 CPUs: one CPU's worth of other work), and
  the 1-minute load average before and after.
"""

from __future__ import annotations

import argparse
import datetime
import importlib.metadata
import json
import os
import platform
import resource
import shlex
import subprocess
import sys
import time
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from casadi_debris.report import json_ready, write_json_atomic

ROOT = Path(__file__).resolve().parents[1]
RESULTS = ROOT / "docs" / "benchmarks"
LIBRARIES = ("numpy", "scipy", "casadi")
CODE_PATHS = ("src", "benchmarks", "pyproject.toml")


def add_options(parser: argparse.ArgumentParser, name: str, quick: str) -> None:
    """``--quick`` (described by ``quick``), ``--record``, ``--out FILE`` and ``--note``."""
    group = parser.add_argument_group("recording")
    group.add_argument("--quick", action="store_true", help=f"reduced run: {quick}")
    group.add_argument(
        "--record",
        action="store_true",
        help=f"also write the JSON to docs/benchmarks/{name}.json (the docs' tables)",
    )
    group.add_argument("--out", type=Path, help="also write the JSON to FILE")
    group.add_argument("--note", help="a remark kept with the results (what else ran, ...)")


def resolve(args: argparse.Namespace, full: dict[str, Any], quick: dict[str, Any]) -> dict:
    """Fill the options left at ``None`` from ``quick`` or ``full``; the settings used."""
    chosen = quick if args.quick else full
    for key, value in chosen.items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    return {key: getattr(args, key) for key in full}


@dataclass(frozen=True)
class Setting:
    """A benchmark option whose value the run records: in the full run and in ``--quick``.

    Its type is that of ``full`` (a string option takes the text as given).
    """

    full: Any
    quick: Any
    help: str

    def keywords(self) -> dict[str, Any]:
        """The keywords of :meth:`argparse.ArgumentParser.add_argument` (default None)."""
        kind = type(self.full)
        return {"help": self.help} if kind is str else {"type": kind, "help": self.help}


def start_benchmark(
    name: str,
    description: str | None,
    quick: str,
    options: Mapping[str, Setting | Mapping[str, Any]],
    *,
    libraries: tuple[str, ...] = (),
    argv: list[str] | None = None,
) -> tuple[argparse.Namespace, Recording, dict[str, Any]]:
    """What every benchmark's ``main`` does first: its command line, its recording, its settings.

    ``options`` are the benchmark's own, by flag (``"--repeat"``), in the order ``--help``
    lists them: a :class:`Setting`, or the keywords of
    :meth:`argparse.ArgumentParser.add_argument` for an option the settings do not
    record. The recording options follow (:func:`add_options`, ``quick`` describing the
    reduced run). The recording starts (its clock, the machine's load) once the command
    line is read; the settings left at ``None`` take their full or quick value
    (:func:`resolve`). Returns the parsed options, the recording and the settings used.
    """
    parser = argparse.ArgumentParser(description=description)
    full, reduced = {}, {}
    for flag, option in options.items():
        if isinstance(option, Setting):
            key = flag.lstrip("-").replace("-", "_")
            full[key], reduced[key] = option.full, option.quick
            parser.add_argument(flag, **option.keywords())
        else:
            parser.add_argument(flag, **option)
    add_options(parser, name, quick)
    args = parser.parse_args(argv)
    recording = Recording(name, args, libraries)
    return args, recording, resolve(args, full, reduced)


def _cpu_model() -> str | None:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or None


def _git(*command: str) -> str | None:
    try:
        done = subprocess.run(
            ["git", "-C", str(ROOT), *command], capture_output=True, text=True, check=True
        )
    except (OSError, subprocess.CalledProcessError):
        return None
    return done.stdout.strip()


def _version(package: str) -> str | None:
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return None


def machine(libraries: tuple[str, ...] = ()) -> dict[str, Any]:
    """The machine and the software versions a benchmark ran with."""
    return {
        "cpus": os.cpu_count(),
        "cpus_usable": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
        "cpu_model": _cpu_model(),
        "platform": platform.platform(),
        "python": platform.python_version(),
        **{package: _version(package) for package in (*LIBRARIES, *libraries)},
    }


def _load() -> float | None:
    return os.getloadavg()[0] if hasattr(os, "getloadavg") else None


def _machine_cpu_s() -> tuple[float, float] | None:
    """CPU seconds all processes used since boot, and those stolen by the hypervisor (Linux)."""
    try:
        fields = Path("/proc/stat").read_text().split("\n", 1)[0].split()
    except OSError:
        return None
    user, nice, system, _idle, _iowait, irq, softirq, steal = (int(v) for v in fields[1:9])
    tick = os.sysconf("SC_CLK_TCK")
    return (user + nice + system + irq + softirq) / tick, steal / tick


def own_cpu_s() -> float:
    """CPU seconds of this process and of its children that have ended."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def _command() -> str:
    """The command line, quoted as for a shell, without ``--note`` (kept on its own)."""
    options, skip = [], False
    for word in sys.argv[1:]:
        if skip or word == "--note":
            skip = not skip
            continue
        if not word.startswith("--note="):
            options.append(word)
    script = Path(sys.argv[0]).resolve().relative_to(ROOT).as_posix()
    return shlex.join(["python", script, *options])


class Recording:
    """Started when a benchmark starts; :meth:`finish` prints and writes its JSON."""

    def __init__(self, name: str, args: argparse.Namespace, libraries: tuple[str, ...] = ()):
        self.name, self.args, self.libraries = name, args, libraries
        self.started = datetime.datetime.now(datetime.UTC)
        self.clock = time.perf_counter()
        self.load_before = _load()
        self.machine_cpu = _machine_cpu_s()
        self.own_cpu = own_cpu_s()

    def finish(self, settings: dict[str, Any], results: dict[str, Any]) -> dict[str, Any]:
        """Print ``results`` with ``machine`` and ``run``; write to the files asked for."""
        elapsed_s = time.perf_counter() - self.clock
        own_s = own_cpu_s() - self.own_cpu
        machine_now = _machine_cpu_s()
        other_share = steal_share = None
        if machine_now is not None and self.machine_cpu is not None:
            capacity_s = elapsed_s * (os.cpu_count() or 1)
            other_s = machine_now[0] - self.machine_cpu[0] - own_s
            other_share = max(0.0, other_s) / capacity_s
            steal_share = (machine_now[1] - self.machine_cpu[1]) / capacity_s
        changed = _git("status", "--porcelain", "--", *CODE_PATHS)
        run = {
            "command": _command(),
            "mode": "quick" if self.args.quick else "full",
            "settings": settings,
            "date": self.started.isoformat(timespec="seconds"),
            "elapsed_s": elapsed_s,
            "git_commit": _git("rev-parse", "HEAD"),
            "git_uncommitted_changes": None if changed is None else bool(changed),
            "own_cpu_s": own_s,
            "other_work_cpu_share": other_share,
            "steal_cpu_share": steal_share,
            "load_average_1min_before": self.load_before,
            "load_average_1min_after": _load(),
            "note": self.args.note,
        }
        payload = {
            "benchmark": self.name,
            **results,
            "machine": machine(self.libraries),
            "run": run,
        }
        print(json.dumps(json_ready(payload), indent=2))
        targets = [RESULTS / f"{self.name}.json"] if self.args.record else []
        targets += [self.args.out] if self.args.out else []
        for target in targets:
            written = write_json_atomic(target, payload)
            print(f"wrote {written}", file=sys.stderr)
        return payload
