"""``casadi-debris model``, ``budget`` and ``schema``: describe the combined system and the file."""

from __future__ import annotations

from pathlib import Path
from typing import Any

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
    from casadi_debris.report.describe import describe_model, model_text

    problem = load_problem(problem_file)
    summary = describe_model(problem)
    if as_json:
        echo_json(summary)
    else:
        click.echo(model_text(summary, show_paper=problem.name == PAPER_PROBLEM_NAME))


@main.command()
@problem_argument
@json_option
@friendly_errors
def budget(problem_file: Path | None, as_json: bool) -> None:
    """Δv, propellant, lifetime, transfer and detumble budgets."""
    from casadi_debris.budgets import budgets_as_dict, compute_budgets
    from casadi_debris.report.describe import budget_text

    problem = load_problem(problem_file)
    items = compute_budgets(problem)
    if as_json:
        payload: dict[str, Any] = {"problem": problem.name, "problem_sha256": problem.sha256}
        payload.update(budgets_as_dict(items))
        payload["how"] = {item.key: item.how for item in items}
        echo_json(payload)
    else:
        label = f"{problem.name} ({problem.source})"
        click.echo(budget_text(items, label, problem.name == PAPER_PROBLEM_NAME))


@main.command()
@friendly_errors
def schema() -> None:
    """Print the JSON Schema of problem files (draft 2020-12), for editors and tools.

    Taken from the loader's own readers: every key with its type, shape, range and
    choices. The loader still checks what a schema cannot (a hinge on the hub,
    propellant below its CubeSat's mass, which keys may be left out).
    """
    from casadi_debris.config.json_schema import problem_schema

    echo_json(problem_schema())
