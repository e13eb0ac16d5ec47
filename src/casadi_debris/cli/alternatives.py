"""``casadi-debris alternatives``: swarm designs side by side, without a controller."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import click

from casadi_debris.cli.common import (
    echo_json,
    folder_option,
    main,
    output_options,
    run_folder,
    say,
)
from casadi_debris.report import format_table


@main.command()
@click.argument(
    "problem_files",
    nargs=-1,
    type=click.Path(path_type=Path, dir_okay=False),
    metavar="[PROBLEM]...",
)
@click.option(
    "--max-failed",
    type=click.IntRange(0, 2),
    default=2,
    show_default=True,
    help="Fail every set of up to this many CubeSats (an LP per set).",
)
@folder_option(default=Path("runs") / "alternatives")
@output_options
def alternatives(
    problem_files: tuple[Path, ...], max_failed: int, out: Path, overwrite: bool, as_json: bool
) -> None:
    """Compare swarm designs: authority, fuel per torque·time, failure tolerance, mass.

    For each PROBLEM (files or shipped names; default the paper's swarm and the
    alternatives it names: side-panel engines, 2U CubeSats firing differentially,
    fewer CubeSats with more thrust per stage, two per face): the largest pure torque
    per signed axis at zero net force, the weakest axis over the disturbance, the
    least propellant per mN·m held an hour, and the weakest-axis margin left after the
    worst single and double CubeSat failure. Writes summary.json, alternatives.csv,
    alternatives.md and alternatives.png in --out.
    """
    from casadi_debris.workflows import alternatives as alternatives_job

    folder = run_folder(out, "alternatives", "", overwrite)
    result = alternatives_job(
        problem_files, max_failed=max_failed, progress=lambda name: say(f"{name} ...")
    )
    result.save(folder, overwrite=overwrite)
    report = dataclasses.replace(result.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(report)
        return
    rows = [
        [
            d.problem,
            d.cubesats,
            d.swarm_mass_kg,
            f"{d.weakest_ratio:.2f} ({d.weakest_axis})",
            "—" if d.single_failure is None else f"{d.single_failure.worst_ratio:.2f}",
            "—" if d.double_failure is None else f"{d.double_failure.worst_ratio:.2f}",
        ]
        for d in report.designs
    ]
    headers = [
        "design",
        "CubeSats",
        "swarm mass [kg]",
        "weakest / disturbance",
        "worst single",
        "worst double",
    ]
    click.echo(format_table(headers, rows))
    click.echo(f"written to {report.out_dir} ({report.wall_time_s:.0f} s)")
