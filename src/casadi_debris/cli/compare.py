"""``casadi-debris compare``: fuel budgets of problem variants side by side."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import click

from casadi_debris.cli.common import (
    comma_list,
    controller_options,
    echo_json,
    folder_option,
    main,
    output_options,
    run_folder,
    say,
)
from casadi_debris.config import SLEW_METHODS, load_problem
from casadi_debris.report import format_table


@main.command()
@click.argument(
    "problem_files", nargs=-1, required=True, type=click.Path(path_type=Path, dir_okay=False)
)
@click.option(
    "--methods",
    help=f"Slew methods to compare on slew problems, comma-separated ({', '.join(SLEW_METHODS)}).",
)
@controller_options
@folder_option(None, default=Path("runs") / "compare")
@output_options
def compare(
    problem_files: tuple[Path, ...],
    methods: str | None,
    controller: Path | None,
    allow_mismatch: bool,
    out: Path,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Compare fuel budgets of problem variants (placements, failures, slew methods).

    Runs the nominal closed loop of every PROBLEM.toml (and every --methods
    slew) and tabulates fuel (over each run, over the window all flew, during
    the slew, worst CubeSat), Δv left, stage switches, slew time, max error and
    its verdict against the problem's requirements: comparison.csv,
    comparison.md, comparison.png and summary.json in --out. A variant whose
    run fails says why in its row.
    """
    from casadi_debris.report import COLUMNS, cell
    from casadi_debris.workflows import compare as compare_variants

    chosen = None if methods is None else comma_list(methods, "--methods", "bang-bang,time-optimal")
    problems = [load_problem(path) for path in problem_files]
    folder = run_folder(out, "compare", "", overwrite)

    def progress(label: str) -> None:
        if not as_json:
            say(f"  {label} ...")

    result = compare_variants(
        problems,
        methods=chosen,
        controller=controller,
        allow_mismatch=allow_mismatch,
        progress=progress,
    )
    result.save(folder, overwrite=overwrite)
    summary = dataclasses.replace(result.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(summary)
        return
    cells = [[cell(row, key) for key, _ in COLUMNS] for row in summary.variants]
    click.echo(format_table([title for _, title in COLUMNS], cells))
    click.echo(f"fuel over the common window: the first {summary.window_s:.6g} s of every run")
    click.echo(f"written to {summary.out_dir}")
