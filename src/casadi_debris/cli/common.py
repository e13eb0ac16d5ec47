"""The command group and what every subcommand shares: errors, options, JSON output."""

from __future__ import annotations

import functools
import json
import logging
import math
import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

import click

from casadi_debris._version import __version__
from casadi_debris.config.limits import SEED, UNCERTAINTY_SAMPLES, Range
from casadi_debris.errors import CasadiDebrisError, InputShapeError, InternalError
from casadi_debris.report import json_ready

EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 3
PAPER_PROBLEM_NAME = "paper"


def friendly_errors(command: Callable[..., None]) -> Callable[..., None]:
    """Turn toolkit errors into one stderr line and a non-zero exit."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> None:
        try:
            command(*args, **kwargs)
        except InternalError as exc:
            _internal(exc)
        except CasadiDebrisError as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(EXIT_BAD_INPUT)
        except Exception as exc:  # a bug, not bad input: say so without a traceback
            _internal(exc)

    return wrapper


def _internal(exc: Exception) -> None:
    """A bug, not bad input: one line and exit 3, or the traceback when debugging."""
    if os.environ.get("CASADI_DEBRIS_DEBUG", "") not in ("", "0"):
        raise exc
    click.echo(
        f"internal error: {type(exc).__name__}: {exc} "
        "(please report it; set CASADI_DEBRIS_DEBUG=1 for the traceback)",
        err=True,
    )
    sys.exit(EXIT_INTERNAL)


problem_argument = click.argument(
    "problem_file",
    required=False,
    type=click.Path(path_type=Path, dir_okay=False),
    metavar="[PROBLEM.toml]",
)
json_option = click.option("--json", "as_json", is_flag=True, help="Print JSON for scripts.")


Decorator = Callable[[Callable[..., Any]], Callable[..., Any]]


def folder_option(
    help: str | None = "Run folder.", *, default: Path | None = None, name: str = "out"
) -> Decorator:
    """``--out DIR``: the folder a command writes into (a folder, never a file), passed to
    the command as ``name``; a ``default`` other than None is shown in the help."""
    return click.option(
        "--out",
        name,
        type=click.Path(path_type=Path, file_okay=False),
        default=default,
        show_default=default is not None,
        help=help,
    )


def out_folder_option(command: str) -> Decorator:
    """``--out DIR``: the run folder, by default ``runs/<command>-<problem>``."""
    return folder_option(f"Run folder [runs/{command}-<problem>].")


def run_folder(out: Path | None, command: str, problem_name: str, overwrite: bool) -> Path:
    """The run folder ``--out`` names (default ``runs/<command>-<problem>``), checked
    before any work or progress line, so that a refusal is the only line printed."""
    from casadi_debris.report.folders import check_output_folder, default_run_folder

    folder = out or default_run_folder(command, problem_name)
    check_output_folder(folder, overwrite=overwrite)
    return folder


controller_option = click.option(
    "--controller",
    "controller",
    type=click.Path(path_type=Path, dir_okay=False),
    default=None,
    help="Controller file written by synthesize [the shipped paper controller, for the paper's "
    "plant only].",
)
allow_mismatch_option = click.option(
    "--allow-mismatch",
    is_flag=True,
    help="Fly a controller designed for another plant (a robustness study); the summary "
    "records both plants' hashes.",
)
MAX_WORKERS = 256
"""Local worker processes at most (one per core of a large node)."""
workers_option = click.option(
    "--workers",
    type=click.IntRange(1, MAX_WORKERS),
    default=os.cpu_count() or 1,
    show_default=True,
    help="Local worker processes.",
)
batch_option = click.option(
    "--batch",
    "batch_cases",
    type=click.IntRange(1, 256),
    default=16,
    show_default=True,
    help="Cases per compiled call: each worker runs a batch of cases as one compiled "
    "function mapped over them (1: one by one). The numbers are the same either way.",
)
no_jit_option = click.option(
    "--no-jit",
    is_flag=True,
    help="Run the step on CasADi's virtual machine even where a C compiler is found "
    "(one case after the other).",
)
overwrite_option = click.option(
    "--overwrite",
    is_flag=True,
    help="Replace an existing result written by casadi-debris (atomically); "
    "without it an existing non-empty output is refused.",
)


def output_options(command: Callable[..., None]) -> Callable[..., None]:
    """What every command that writes ends with: ``--overwrite``, ``--json`` and toolkit
    errors as one stderr line (:func:`friendly_errors`)."""
    return overwrite_option(json_option(friendly_errors(command)))


def run_folder_options(command: str) -> Decorator:
    """``--out DIR`` (by default ``runs/<command>-<problem>``), then :func:`output_options`."""

    def decorate(function: Callable[..., None]) -> Callable[..., Any]:
        return out_folder_option(command)(output_options(function))

    return decorate


def controller_options(command: Callable[..., Any]) -> Callable[..., Any]:
    """``--controller FILE`` and ``--allow-mismatch``: the controller a command flies."""
    return controller_option(allow_mismatch_option(command))


def comma_list(text: str, option: str, example: str) -> list[str]:
    """The parts of ``a,b,c``: none empty, at least one; else one line naming ``option``."""
    parts = [part.strip() for part in text.split(",")]
    if not text.strip() or any(not part for part in parts):
        raise InputShapeError(f"{option}: comma-separated values such as {example}; got {text!r}")
    return parts


def failed_cubesat_indices(text: str | None, count: int) -> list[int]:
    """0-based indices of ``--failed`` CubeSat ids (1 .. count, as ``casadi-debris model``
    numbers them), sorted, without repeats."""
    if text is None:
        return []
    try:
        ids = sorted({int(part) for part in comma_list(text, "--failed", "3,17")})
    except ValueError:
        raise InputShapeError(
            f"--failed takes comma-separated CubeSat ids such as 3,17; got {text!r}"
        ) from None
    bad = [i for i in ids if not 1 <= i <= count]
    if bad:
        raise InputShapeError(f"--failed: CubeSat ids run from 1 to {count}; got {bad}")
    return [i - 1 for i in ids]


def echo_json(payload: Any) -> None:
    """Print a result as indented JSON (numpy converted, non-finite as null)."""
    click.echo(json.dumps(json_ready(payload), indent=2))


class BoundedFloat(click.ParamType):
    """A finite number inside a range: NaN, inf and out-of-range values are usage errors.

    (click's ``FloatRange`` lets NaN through: every comparison with NaN is false.)
    """

    name = "float"

    def __init__(
        self, low: float, high: float, *, low_open: bool = False, high_open: bool = False
    ) -> None:
        self.low, self.high = low, high
        self.low_open, self.high_open = low_open, high_open

    def describe(self) -> str:
        left = "(" if self.low_open else "["
        right = ")" if self.high_open else "]"
        return f"{left}{self.low:g}, {self.high:g}{right}"

    def convert(
        self, value: Any, param: click.Parameter | None, ctx: click.Context | None
    ) -> float:
        number = click.FLOAT.convert(value, param, ctx)
        if not math.isfinite(number):
            self.fail(f"must be a finite number, got {value!r}", param, ctx)
        too_low = number <= self.low if self.low_open else number < self.low
        too_high = number >= self.high if self.high_open else number > self.high
        if too_low or too_high:
            self.fail(f"must lie in {self.describe()}, got {value!r}", param, ctx)
        return number

    def get_metavar(self, param: click.Parameter, ctx: click.Context | None = None) -> str:
        return f"FLOAT {self.describe()}"


def in_range(allowed: Range) -> click.ParamType:
    """The click type of an option whose values must lie in ``allowed``.

    Whole-number bounds give :class:`click.IntRange`, others :class:`BoundedFloat`.
    """
    if isinstance(allowed.low, int) and isinstance(allowed.high, int):
        return click.IntRange(allowed.low, allowed.high)
    return BoundedFloat(
        allowed.low, allowed.high, low_open=allowed.low_open, high_open=allowed.high_open
    )


def bounded_option(flag: str, allowed: Range, default: float, help: str) -> Decorator:
    """An option whose values must lie in ``allowed`` (:func:`in_range`), its default shown."""
    return click.option(flag, type=in_range(allowed), default=default, show_default=True, help=help)


def uncertainty_sample_options(command: Callable[..., Any]) -> Callable[..., Any]:
    """``--samples`` and ``--seed`` of a design's uncertainty-weight fit."""
    command = click.option(
        "--seed", type=in_range(SEED), default=None, help="Seed of those models [problem's]."
    )(command)
    return click.option(
        "--samples",
        type=in_range(UNCERTAINTY_SAMPLES),
        default=None,
        help="Models for the uncertainty-weight fit W [problem's].",
    )(command)


class OneLineErrorGroup(click.Group):
    """The command group: a usage error is one line, ``error: <what>``, exit 2."""

    def main(
        self,
        args: Sequence[str] | None = None,
        prog_name: str | None = None,
        complete_var: str | None = None,
        standalone_mode: bool = True,
        **extra: Any,
    ) -> Any:
        if not standalone_mode:
            return super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        try:
            result = super().main(args, prog_name, complete_var, standalone_mode=False, **extra)
        except click.UsageError as exc:
            command = exc.ctx.command_path if exc.ctx is not None else "casadi-debris"
            click.echo(f"error: {exc.format_message()} (see {command} --help)", err=True)
            sys.exit(exc.exit_code)
        except click.ClickException as exc:
            click.echo(f"error: {exc.format_message()}", err=True)
            sys.exit(exc.exit_code)
        except click.exceptions.Abort:
            click.echo("aborted", err=True)
            sys.exit(1)
        sys.exit(result if isinstance(result, int) else 0)


_QUIET_KEY = "casadi_debris.quiet"
_HANDLER_NAME = "casadi-debris-cli"


def configure_output(verbose: int, quiet: bool) -> None:
    """Route the toolkit's log to stderr: warnings by default, more with -v, errors with -q."""
    logger = logging.getLogger("casadi_debris")
    level = (
        logging.ERROR if quiet else (logging.WARNING, logging.INFO, logging.DEBUG)[min(verbose, 2)]
    )
    logger.setLevel(level)
    for handler in [h for h in logger.handlers if h.get_name() == _HANDLER_NAME]:
        logger.removeHandler(handler)
    handler = logging.StreamHandler(sys.stderr)
    handler.set_name(_HANDLER_NAME)
    detail = "%(levelname)s %(name)s: %(message)s" if verbose >= 2 else "%(message)s"
    handler.setFormatter(logging.Formatter(detail))
    logger.addHandler(handler)
    logger.propagate = False


def is_quiet() -> bool:
    """Whether the user asked for errors only (``casadi-debris -q``)."""
    context = click.get_current_context(silent=True)
    return bool(context is not None and context.find_root().meta.get(_QUIET_KEY))


def say(text: str, *, newline: bool = True) -> None:
    """Progress and notes on stderr, unless ``-q``."""
    if not is_quiet():
        click.echo(text, nl=newline, err=True)


@click.group(cls=OneLineErrorGroup, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="casadi-debris")
@click.option("-v", "--verbose", count=True, help="Say more: -v each stage, -vv debugging detail.")
@click.option("-q", "--quiet", is_flag=True, help="Errors only: no progress, no notes.")
@click.pass_context
def main(context: click.Context, verbose: int, quiet: bool) -> None:
    """Attitude control of space debris with docked iESE CubeSats.

    PROBLEM.toml defaults to the paper's setup (problems/paper.toml). Results go
    to --out (never over a folder you made; see --overwrite). Shell completion:
    eval "$(_CASADI_DEBRIS_COMPLETE=bash_source casadi-debris)" (zsh_source, fish_source).
    """
    context.meta[_QUIET_KEY] = quiet
    configure_output(verbose, quiet)


PROGRESS_LINE_S = 30.0
"""Off a terminal, a progress line at least this often [s] (and at every tenth done)."""
BAR_WIDTH = 24


def counter_progress(label: str, unit: str = "cases") -> Callable[[int, int], None]:
    """``progress(done, total)`` on stderr, silent with ``-q``.

    On a terminal a bar redrawn in place, with the elapsed time and an estimate of what
    is left; otherwise (a log file, CI) a whole line at every tenth of the work done or
    every :data:`PROGRESS_LINE_S` seconds, and at the end, so that a log shows the run
    is alive without a line per case.
    """
    import time

    started = time.monotonic()
    last = {"time": started, "tenth": -1}
    terminal = sys.stderr.isatty()

    def show(done: int, total: int) -> None:
        now = time.monotonic()
        elapsed = now - started
        left = elapsed / done * (total - done) if done else None
        timing = f"{_clock(elapsed)} elapsed" + ("" if left is None else f", {_clock(left)} left")
        if terminal:
            filled = BAR_WIDTH * done // max(total, 1)
            bar = "#" * filled + "-" * (BAR_WIDTH - filled)
            end = "\n" if done == total else ""
            say(f"\r{label} [{bar}] {done}/{total} {unit}, {timing}{end}", newline=False)
            return
        tenth = 10 * done // max(total, 1)
        if done == total or tenth > last["tenth"] or now - last["time"] >= PROGRESS_LINE_S:
            last.update(time=now, tenth=tenth)
            say(f"{label}: {done}/{total} {unit}, {timing}")

    return show


def _clock(seconds: float) -> str:
    """``m:ss`` (or ``h:mm:ss``) of a duration."""
    minutes, secs = divmod(round(seconds), 60)
    hours, minutes = divmod(minutes, 60)
    return f"{hours}:{minutes:02d}:{secs:02d}" if hours else f"{minutes}:{secs:02d}"
