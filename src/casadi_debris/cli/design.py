"""``casadi-debris design``: the paper's method on the user's problem, verified and reported."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, cast

import click

from casadi_debris.cli.common import (
    main,
    out_folder_option,
    output_options,
    problem_argument,
    run_folder,
    uncertainty_sample_options,
    workers_option,
)
from casadi_debris.cli.reproduce import echo_verdicts
from casadi_debris.cli.simulate import stage_progress
from casadi_debris.config import load_problem

if TYPE_CHECKING:
    from casadi_debris.robust.requirements import WeightsChoice
    from casadi_debris.workflows import DesignMethod

TABLE_KEYS = ("result", "required", "ours", "verdict")


@main.command()
@problem_argument
@out_folder_option("design")
@click.option("--quick", is_flag=True, help="Fewer samples and corners, shorter pointing run.")
@click.option(
    "--method",
    type=click.Choice(["mu", "pd", "pid", "lqr"]),
    default="mu",
    show_default=True,
    help="mu: D-K mu-synthesis; pd, pid, lqr: per-axis PD, PID or LQG on the rigid body, "
    "to compare.",
)
@click.option(
    "--weights",
    type=click.Choice(["auto", "derived", "problem"]),
    default="auto",
    show_default=True,
    help="Bandwidth and roll-off of the weights: auto derives them from the body unless the "
    "problem is the paper's body or sets its own; derived always; problem takes [weights] "
    "as they are (inherited ones included).",
)
@uncertainty_sample_options
@workers_option
@output_options
def design(
    problem_file: Path | None,
    out: Path | None,
    quick: bool,
    method: str,
    weights: str,
    samples: int | None,
    seed: int | None,
    workers: int,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Design a robust controller for the problem and verify it against its [requirements]:
    weights from its authority, disturbance and pointing requirement, D-K mu-synthesis
    (searching the best guaranteed pointing when the requirement cannot be met), reduction,
    margins over sampled plants, slew and pointing corner campaigns; writes controller.json
    and report.md. --method pd, pid or lqr designs a classical controller instead and verifies
    it the same way, to compare with the mu design."""
    from casadi_debris.workflows import design as design_job

    problem = load_problem(problem_file)
    folder = run_folder(out, "design", problem.name, overwrite)
    designed = design_job(
        problem,
        out=folder,
        quick=quick,
        method=cast("DesignMethod", method),  # a click.Choice of those
        weights=cast("WeightsChoice", weights),  # a click.Choice of those
        samples=samples,
        seed=seed,
        workers=workers,
        overwrite=overwrite,
        progress=stage_progress(as_json),
    )
    summary = designed.summary
    echo_verdicts(
        summary,
        summary.rows,
        TABLE_KEYS,
        f"{summary.requirements_passed} of {summary.requirements} requirements met; "
        f"controller: {folder.absolute() / 'controller.json'}; "
        f"report: {folder.absolute() / 'report.md'} ({summary.time_s:.0f} s)",
        as_json=as_json,
    )
