"""The forked child of one run: the command line called in-process, as the console script would.

It chdirs into its working folder, which is its HOME and TMPDIR, reads a stdin
that never ends (like a terminal), writes stdout and stderr to files of the run
folder, and has its address space and file sizes bounded.
"""

from __future__ import annotations

import contextlib
import io
import os
import resource
import signal
import sys
import tempfile
import traceback
from pathlib import Path


def _vm_size_bytes() -> int:
    with open("/proc/self/status", encoding="ascii") as handle:
        for line in handle:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return 0


def _redirect(rundir: Path) -> None:
    """stdout and stderr into ``rundir``; stdin a pipe nobody writes to."""
    out = os.open(rundir / "stdout", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    err = os.open(rundir / "stderr", os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
    os.dup2(out, 1)
    os.dup2(err, 2)
    read_end, _write_end = os.pipe()  # a stdin that never ends, like a terminal
    os.dup2(read_end, 0)
    sys.stdin = io.TextIOWrapper(open(0, "rb", closefd=False), encoding="utf-8")  # noqa: SIM115
    sys.stdout = io.TextIOWrapper(
        open(1, "wb", closefd=False),  # noqa: SIM115
        encoding="utf-8",
        errors="backslashreplace",
        line_buffering=True,
    )
    sys.stderr = io.TextIOWrapper(
        open(2, "wb", closefd=False),  # noqa: SIM115
        encoding="utf-8",
        errors="backslashreplace",
        line_buffering=True,
    )


def _confine(cwd: Path) -> None:
    """Limits, the working folder as HOME and TMPDIR, default signal handling."""
    limit = _vm_size_bytes() + (3 << 30)
    resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    resource.setrlimit(resource.RLIMIT_FSIZE, (1 << 30, 1 << 30))
    os.chdir(cwd)
    tmp = cwd / ".tmp"
    tmp.mkdir(exist_ok=True)
    os.environ.update(HOME=str(cwd), TMPDIR=str(tmp), PWD=str(cwd))
    os.environ.pop("CASADI_DEBRIS_DEBUG", None)
    tempfile.tempdir = None
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


def _call_main(args: tuple[str, ...]) -> int:
    """The exit status the console script would give."""
    from casadi_debris.cli import main

    sys.argv = ["casadi-debris", *args]
    try:
        main.main(args=list(args), prog_name="casadi-debris", standalone_mode=True)
        code = 0
    except SystemExit as exc:
        if exc.code is None:
            code = 0
        elif isinstance(exc.code, int):
            code = exc.code
        else:
            print(exc.code, file=sys.stderr)
            code = 1
    except BaseException:  # what Python prints for an uncaught exception
        traceback.print_exc()
        code = 1
    with contextlib.suppress(Exception):
        sys.stdout.flush()
        sys.stderr.flush()
    return code


def run_child(args: tuple[str, ...], cwd: Path, rundir: Path) -> None:
    """In the forked child: run one invocation as the console script would; never return."""
    code = 98
    try:
        os.setpgid(0, 0)
        _redirect(rundir)
        _confine(cwd)
        code = _call_main(args)
    except BaseException:
        with contextlib.suppress(Exception):
            traceback.print_exc()
            sys.stderr.flush()
        code = 97
    os._exit(code)
