"""``casadi-debris compare``: fuel budgets of problem variants side by side."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path
from typing import Any

import click
import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.cli.common import (
    echo_json,
    friendly_errors,
    json_option,
    main,
    overwrite_option,
)
from casadi_debris.cli.robust import load_controller
from casadi_debris.config import SLEW_METHODS, Problem, load_problem
from casadi_debris.errors import InputShapeError
from casadi_debris.model import build_model
from casadi_debris.plots.simulation import plot_fuel_comparison
from casadi_debris.report.common import (
    format_table,
    write_csv,
    write_json_atomic,
)
from casadi_debris.report.folders import RunFolder, check_output_folder
from casadi_debris.simulation import scenario_reference, simulate

COLUMNS = (
    ("variant", "variant"),
    ("fuel_kg", "fuel [kg]"),
    ("fuel_worst_cubesat_kg", "worst CubeSat [kg]"),
    ("dv_left_m_s", "Δv left [m/s]"),
    ("stage_switches", "stage switches"),
    ("slew_duration_s", "slew [s]"),
    ("max_error_deg", "max error [deg]"),
    ("torque_saturated_s", "saturated [s]"),
)


def variants(problems: list[Problem], methods: list[str] | None) -> list[tuple[str, Problem]]:
    """Each problem, and for slew problems each requested slew method."""
    chosen = []
    for problem in problems:
        slew = problem.simulation.slew
        if not methods or slew is None:
            chosen.append((problem.name, problem))
            continue
        for method in methods:
            settings = replace(slew, method=method)
            if method == "time-optimal":
                settings = replace(settings, duration_s=None)
            elif method == "fuel-optimal" and settings.duration_s is None:
                raise InputShapeError(
                    f"{problem.name}: fuel-optimal needs simulation.slew.duration_s"
                )
            variant = replace(problem, simulation=replace(problem.simulation, slew=settings))
            chosen.append((f"{problem.name} / {method}", variant))
    return chosen


def compare_row(label: str, problem: Problem, controller: Any) -> dict[str, Any]:
    """One variant's nominal closed-loop run, reduced to the budget figures."""
    model = build_model(problem)
    reference = scenario_reference(problem)
    allocator = Allocator.from_problem(problem, model.geometry)
    result = simulate(problem, model, controller, reference, allocator=allocator)
    summary = result.summary()
    left_kg = float(result.propulsion.propellant_kg.sum())
    mass_now = result.total_mass_kg - summary["fuel_kg"]
    exhaust = result.propulsion.exhaust_velocity_m_s
    return {
        "variant": label,
        "problem": problem.name,
        "fuel_kg": summary["fuel_kg"],
        "fuel_worst_cubesat_kg": summary["fuel_worst_cubesat_kg"],
        "dv_left_m_s": exhaust * math.log(mass_now / (mass_now - left_kg)),
        "stage_switches": summary["stage_switches"],
        "slew_duration_s": None if reference.slew is None else reference.slew.duration_s,
        "max_error_deg": summary["max_error_deg"],
        "torque_saturated_s": summary["torque_saturated_s"],
        "failed_cubesats": int(result.propulsion.failed_cubesats.sum()),
    }


def comparison_markdown(rows: list[dict[str, Any]]) -> str:
    header = "| " + " | ".join(title for _, title in COLUMNS) + " |"
    rule = "| " + " | ".join("---" for _ in COLUMNS) + " |"
    lines = [header, rule]
    for row in rows:
        cells = [_cell(row[key]) for key, _ in COLUMNS]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def _cell(value: Any) -> str:
    if value is None:
        return "—"
    if isinstance(value, str | int):
        return str(value)
    return f"{value:.4g}"


@main.command()
@click.argument(
    "problem_files", nargs=-1, required=True, type=click.Path(path_type=Path, dir_okay=False)
)
@click.option(
    "--methods",
    help=f"Slew methods to compare on slew problems, comma-separated ({', '.join(SLEW_METHODS)}).",
)
@click.option("--controller", "controller_path", type=click.Path(path_type=Path, dir_okay=False))
@click.option(
    "--out",
    type=click.Path(path_type=Path, file_okay=False),
    default=Path("runs") / "compare",
    show_default=True,
)
@overwrite_option
@json_option
@friendly_errors
def compare(
    problem_files: tuple[Path, ...],
    methods: str | None,
    controller_path: Path | None,
    out: Path,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Compare fuel budgets of problem variants (placements, failures, slew methods).

    Runs the nominal closed loop of every PROBLEM.toml (and every --methods
    slew) and tabulates fuel (total and worst CubeSat), Δv left, stage
    switches, slew time and max error: comparison.csv, comparison.md and
    fuel.png in --out.
    """
    chosen_methods = None
    if methods:
        chosen_methods = [m.strip() for m in methods.split(",") if m.strip()]
        unknown = sorted(set(chosen_methods) - set(SLEW_METHODS))
        if unknown:
            raise InputShapeError(
                f"--methods: unknown {', '.join(unknown)}; choose from {', '.join(SLEW_METHODS)}"
            )
    problems = [load_problem(path) for path in problem_files]
    record, resolved = load_controller(controller_path)
    check_output_folder(out, overwrite=overwrite)
    rows = []
    for label, problem in variants(problems, chosen_methods):
        if not as_json:
            click.echo(f"  {label} ...", err=True)
        rows.append(compare_row(label, problem, record.reduced))
    summary = {"controller_path": str(resolved), "variants": rows, "out_dir": str(out.resolve())}
    with RunFolder.claim(out, overwrite=overwrite, command="compare") as staging:
        columns = {key: np.array([row[key] for row in rows], dtype=object) for key, _ in COLUMNS}
        write_csv(staging / "comparison.csv", columns)
        (staging / "comparison.md").write_text(comparison_markdown(rows))
        plot_fuel_comparison(
            [row["variant"] for row in rows],
            [row["fuel_kg"] for row in rows],
            [row["fuel_worst_cubesat_kg"] for row in rows],
            staging / "fuel.png",
        )
        write_json_atomic(staging / "summary.json", summary)
    if as_json:
        echo_json(summary)
        return
    click.echo(format_table([t for _, t in COLUMNS], [[r[k] for k, _ in COLUMNS] for r in rows]))
    click.echo(f"written to {out.resolve()}")
