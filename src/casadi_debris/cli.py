"""The ``casadi-debris`` command.

Every subcommand takes an optional problem file (default: the shipped paper
setup) and ``--json`` for scripts. Bad input ends with one line on stderr
naming the problem and exit status 2; never a traceback.
"""

from __future__ import annotations

import functools
import json
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import click

from casadi_debris import __version__
from casadi_debris.budgets import budgets_as_dict
from casadi_debris.config import Problem, load_problem
from casadi_debris.errors import CasadiDebrisError
from casadi_debris.report import (
    budget_text,
    describe_budgets,
    describe_model,
    json_ready,
    model_text,
)

EXIT_BAD_INPUT = 2
EXIT_INTERNAL = 3
PAPER_PROBLEM_NAME = "paper"


def _friendly_errors(command: Callable[..., None]) -> Callable[..., None]:
    """Turn toolkit errors into one stderr line and a non-zero exit."""

    @functools.wraps(command)
    def wrapper(*args: Any, **kwargs: Any) -> None:
        try:
            command(*args, **kwargs)
        except CasadiDebrisError as exc:
            click.echo(f"error: {exc}", err=True)
            sys.exit(EXIT_BAD_INPUT)
        except Exception as exc:  # a bug, not bad input: say so without a traceback
            click.echo(
                f"internal error: {type(exc).__name__}: {exc} "
                "(please report it; set CASADI_DEBRIS_DEBUG=1 for the traceback)",
                err=True,
            )
            if _debug():
                raise
            sys.exit(EXIT_INTERNAL)

    return wrapper


def _debug() -> bool:
    import os

    return os.environ.get("CASADI_DEBRIS_DEBUG", "") not in ("", "0")


problem_argument = click.argument(
    "problem_file",
    required=False,
    type=click.Path(path_type=Path, dir_okay=False),
    metavar="[PROBLEM.toml]",
)
json_option = click.option("--json", "as_json", is_flag=True, help="Print JSON for scripts.")


def _load(problem_file: Path | None) -> Problem:
    return load_problem(problem_file)


def _echo_json(payload: dict[str, Any]) -> None:
    click.echo(json.dumps(json_ready(payload), indent=2))


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="casadi-debris")
def main() -> None:
    """Attitude control of space debris with docked iESE CubeSats.

    PROBLEM.toml defaults to the paper's setup (problems/paper.toml).
    """


@main.command()
@problem_argument
@json_option
@_friendly_errors
def model(problem_file: Path | None, as_json: bool) -> None:
    """Describe the combined system: mass, inertia, CoG, torque authority, modes, engines."""
    problem = _load(problem_file)
    summary = describe_model(problem)
    if as_json:
        _echo_json(summary)
    else:
        click.echo(model_text(summary, show_paper=problem.name == PAPER_PROBLEM_NAME))


@main.command()
@problem_argument
@json_option
@_friendly_errors
def budget(problem_file: Path | None, as_json: bool) -> None:
    """Δv, propellant, lifetime, transfer and detumble budgets."""
    problem = _load(problem_file)
    items = describe_budgets(problem)
    if as_json:
        payload = {"problem": problem.name, "problem_sha256": problem.sha256}
        payload.update(budgets_as_dict(items))
        payload["how"] = {item.key: item.how for item in items}
        _echo_json(payload)
    else:
        click.echo(
            budget_text(
                items, f"{problem.name} ({problem.source})", problem.name == PAPER_PROBLEM_NAME
            )
        )


if __name__ == "__main__":
    main()
