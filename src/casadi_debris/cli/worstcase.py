"""``casadi-debris worstcase``: real-parametric mu bounds and the worst slew in the box."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING

import click

from casadi_debris.cli.common import (
    controller_options,
    counter_progress,
    echo_json,
    in_range,
    is_quiet,
    main,
    problem_argument,
    run_folder,
    run_folder_options,
    say,
)
from casadi_debris.config import limits, load_problem
from casadi_debris.report import format_table

if TYPE_CHECKING:  # the worst-case report imports plotting: loaded by the command
    from casadi_debris.report import WorstCaseSummary


@main.command()
@problem_argument
@controller_options
@click.option(
    "--budget",
    type=click.IntRange(1, 1000),
    default=50,
    show_default=True,
    help="Simulations of the search at most.",
)
@click.option(
    "--seed", type=in_range(limits.SEED), default=0, show_default=True, help="Seed of the search."
)
@click.option(
    "--angles",
    type=click.IntRange(1, 64),
    help="Array angles of the mu grid [the corner campaign's].",
)
@click.option("--no-mu", is_flag=True, help="Skip the mu bounds.")
@click.option("--no-search", is_flag=True, help="Skip the search.")
@click.option(
    "--campaign",
    type=click.Path(path_type=Path, file_okay=False, exists=True),
    help="A finished corner campaign (montecarlo --out) to compare with and draw under the "
    "worst run.",
)
@run_folder_options("worstcase")
def worstcase(
    problem_file: Path | None,
    controller: Path | None,
    allow_mismatch: bool,
    budget: int,
    seed: int,
    angles: int | None,
    no_mu: bool,
    no_search: bool,
    campaign: Path | None,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Worst cases of the controller over the uncertainty box.

    Robust stability and performance mu with the parameters kept real (upper
    and lower bounds, the gap, the worst perturbation as parameters), then a
    local search through the closed loop for the run of largest attitude error
    (paper_slew.toml: the 180 deg slew). Writes summary.json,
    worst_parameters.json and mu_*_parameters.json (for simulate --parameters),
    evaluations.csv and worstcase.png.
    """
    from casadi_debris.workflows import worstcase as find_worst_cases

    problem = load_problem(problem_file)
    folder = run_folder(out, "worstcase", problem.name, overwrite)

    def progress(stage: str):  # type: ignore[no-untyped-def]
        if as_json or is_quiet():
            return None
        say(stage)
        counter = counter_progress("  search", "runs")
        return lambda done, error: counter(done, budget)

    result = find_worst_cases(
        problem,
        controller=controller,
        allow_mismatch=allow_mismatch,
        budget=budget,
        seed=seed,
        angles=angles,
        no_mu=no_mu,
        no_search=no_search,
        campaign=campaign,
        progress=progress,
    )
    result.save(folder, overwrite=overwrite)
    summary = result.summary
    summary = dataclasses.replace(
        summary, identity=dataclasses.replace(summary.identity, out_dir=str(folder.absolute()))
    )
    if as_json:
        echo_json(summary)
        return
    if not is_quiet():
        say("")
    click.echo(format_table(["figure", "value", "note"], _rows(summary)))
    click.echo(f"written to {summary.identity.out_dir}")


def _rows(summary: WorstCaseSummary) -> list[list[str]]:
    """The table the command prints: the bounds, the search, the campaign's worst; a stage
    skipped says so (with both skipped the table is not left empty)."""
    rows = []
    if summary.mu is None:
        rows.append(["mu robust stability, performance", "skipped", "--no-mu"])
    else:
        for kind, bounds in (
            ("stability", summary.mu.stability),
            ("performance", summary.mu.performance),
        ):
            rows.append(
                [
                    f"mu robust {kind}",
                    f"{bounds.mu_lower:.4f} .. {bounds.mu_upper:.4f}",
                    f"gap {bounds.gap:.1%}",
                ]
            )
    if summary.search is None:
        rows.append(["worst max error [deg]", "skipped", "--no-search"])
    else:
        found = summary.search
        rows.append(
            ["worst max error [deg]", f"{found.max_error_deg:.4f}", f"{found.simulations} runs"]
        )
    if summary.campaign is not None:
        rows.append(
            [
                "corner campaign worst [deg]",
                f"{summary.campaign.worst_max_error_deg:.4f}",
                ", ".join(summary.campaign.worst_cases[:2]),
            ]
        )
    return rows
