"""``casadi-debris model``, ``budget`` and ``schema``: describe the combined system and the file."""

from __future__ import annotations

from pathlib import Path

import click

from casadi_debris.cli.common import (
    PAPER_PROBLEM_NAME,
    echo_json,
    friendly_errors,
    json_option,
    main,
    problem_argument,
)
from casadi_debris.config import load_problem


@main.command()
@problem_argument
@json_option
@friendly_errors
def model(problem_file: Path | None, as_json: bool) -> None:
    """Describe the combined system: mass, inertia, CoG, torque authority, modes, engines."""
    from casadi_debris.report import model_text
    from casadi_debris.workflows import model as model_job

    described = model_job(problem_file)
    if as_json:
        echo_json(described.summary)
    else:
        show_paper = described.problem.name == PAPER_PROBLEM_NAME
        click.echo(model_text(described.summary, show_paper=show_paper))


@main.command()
@problem_argument
@json_option
@friendly_errors
def budget(problem_file: Path | None, as_json: bool) -> None:
    """Δv, propellant, lifetime, transfer and detumble budgets."""
    from casadi_debris.report import budget_text
    from casadi_debris.workflows import budget as budget_job

    budgets = budget_job(problem_file)
    if as_json:
        echo_json(budgets.summary)
    else:
        problem = budgets.problem
        label = f"{problem.name} ({problem.source})"
        click.echo(budget_text(budgets.items, label, problem.name == PAPER_PROBLEM_NAME))


@main.command()
@friendly_errors
def schema() -> None:
    """Print the JSON Schema of problem files (draft 2020-12), for editors and tools.

    Taken from the loader's own readers: every key with its type, shape, range and
    choices. The loader still checks what a schema cannot (a hinge on the hub,
    propellant below its CubeSat's mass, which keys may be left out).
    """
    from casadi_debris.config import problem_schema

    echo_json(problem_schema())


@main.command()
@json_option
@friendly_errors
def problems(as_json: bool) -> None:
    """List the shipped problems: any command takes their name in place of a file.

    ``casadi-debris simulate paper_slew`` flies the shipped paper_slew.toml, and a
    problem file of yours may say ``extends = "paper_slew"`` from any folder. A file
    of that name where the command runs is read first.
    """
    from casadi_debris.config import shipped_problems
    from casadi_debris.report import format_table

    rows = []
    for name, path in shipped_problems().items():
        problem = load_problem(path)
        rows.append({"name": name, "description": problem.description, "path": str(path)})
    if as_json:
        echo_json({"problems": rows})
        return
    table = [[row["name"], _shortened(row["description"])] for row in rows]
    click.echo(format_table(["name", "description"], table))


def _shortened(text: str, width: int = 90) -> str:
    """The description on one line, cut to ``width`` characters."""
    line = " ".join(text.split())
    return line if len(line) <= width else line[: width - 1] + "…"
