"""The command group and what every subcommand shares: errors, options, JSON output."""

from __future__ import annotations

import functools
import json
import os
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click

from casadi_debris import __version__
from casadi_debris.errors import CasadiDebrisError
from casadi_debris.report.common import json_ready

EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 3
PAPER_PROBLEM_NAME = "paper"


def friendly_errors(command: Callable[..., None]) -> Callable[..., None]:
    """Turn toolkit errors into one stderr line and a non-zero exit."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> None:
        try:
            command(*args, **kwargs)
        except CasadiDebrisError as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(EXIT_BAD_INPUT)
        except Exception as exc:  # a bug, not bad input: say so without a traceback
            if os.environ.get("CASADI_DEBRIS_DEBUG", "") not in ("", "0"):
                raise
            click.echo(
                f"internal error: {type(exc).__name__}: {exc} "
                "(please report it; set CASADI_DEBRIS_DEBUG=1 for the traceback)",
                err=True,
            )
            sys.exit(EXIT_INTERNAL)

    return wrapper


problem_argument = click.argument(
    "problem_file",
    required=False,
    type=click.Path(path_type=Path, dir_okay=False),
    metavar="[PROBLEM.toml]",
)
json_option = click.option("--json", "as_json", is_flag=True, help="Print JSON for scripts.")
overwrite_option = click.option(
    "--overwrite",
    is_flag=True,
    help="Replace an existing result written by casadi-debris (atomically); "
    "without it an existing non-empty output is refused.",
)


def echo_json(payload: dict[str, Any]) -> None:
    """Print a result as indented JSON (numpy converted, non-finite as null)."""
    click.echo(json.dumps(json_ready(payload), indent=2))


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="casadi-debris")
def main() -> None:
    """Attitude control of space debris with docked iESE CubeSats.

    PROBLEM.toml defaults to the paper's setup (problems/paper.toml).
    """
