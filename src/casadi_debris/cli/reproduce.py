"""``casadi-debris reproduce``: the whole paper, end to end, with a report."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path
from typing import Any

import click

from casadi_debris.allocation import Allocator
from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.cli.common import (
    echo_json,
    friendly_errors,
    json_option,
    main,
    overwrite_option,
    workers_option,
)
from casadi_debris.cli.robust import load_controller
from casadi_debris.cli.simulate import run_montecarlo
from casadi_debris.config import default_problem_path, load_problem
from casadi_debris.geometry import build_geometry
from casadi_debris.report.common import format_table, write_json_atomic
from casadi_debris.report.describe import describe_model
from casadi_debris.report.folders import RunFolder
from casadi_debris.report.reproduce import report_markdown, reproduction_rows
from casadi_debris.report.robust import margin_report
from casadi_debris.report.simulation import torque_limits_mNm
from casadi_debris.robust.design import SynthesisSettings, design_controller

FULL = {"margin_samples": 3000, "slew_cases": None, "pointing_cases": None}
# --quick: a few minutes on two cores (CI); corners spread evenly over the set.
QUICK = {
    "margin_samples": 200,
    "slew_cases": 8,
    "pointing_cases": 4,
    "pointing_duration_s": 1500.0,
}


@main.command()
@click.option(
    "--out",
    type=click.Path(path_type=Path, file_okay=False),
    default=Path("runs") / "reproduce",
    show_default=True,
    help="Report folder.",
)
@click.option("--quick", is_flag=True, help="Fewer samples and corners, shorter pointing run (CI).")
@click.option("--resynthesize", is_flag=True, help="Design the controller anew (≈1 min).")
@workers_option
@overwrite_option
@json_option
@friendly_errors
def reproduce(
    out: Path, quick: bool, resynthesize: bool, workers: int, overwrite: bool, as_json: bool
) -> None:
    """Reproduce the paper: model, budgets, controller, margins, slew and pointing
    with their Monte-Carlo envelopes; writes report.md with every figure of the
    paper next to ours."""
    started = time.perf_counter()
    plan = {**FULL, **(QUICK if quick else {})}
    problems = default_problem_path().parent
    problem = load_problem(problems / "paper.toml")
    slew_problem = load_problem(problems / "paper_slew.toml")
    pointing_problem = load_problem(problems / "paper_pointing.toml")
    if "pointing_duration_s" in plan:
        pointing_problem = replace(
            pointing_problem,
            simulation=replace(pointing_problem.simulation, duration_s=plan["pointing_duration_s"]),
        )

    def say(text: str) -> None:
        if not as_json:
            click.echo(text, err=True)

    with RunFolder.claim(out, overwrite=overwrite, command="reproduce") as staging:
        say("model and budgets ...")
        model_summary = describe_model(problem)
        budgets = budgets_as_dict(compute_budgets(problem))
        if resynthesize:
            say("synthesising the controller (D-K iteration) ...")
            design = design_controller(problem, SynthesisSettings())
            controller_path = write_json_atomic(
                staging / "controller.json", design.record.to_dict()
            )
        record, controller_path = load_controller(None if not resynthesize else controller_path)
        say(f"margins over {plan['margin_samples']} sampled plants ...")
        margins = margin_report(
            problem,
            record,
            controller_path,
            plan["margin_samples"],
            None,
            staging / "margins",
            True,
            None,
            out_dir=out / "margins",
        )
        say("slew Monte Carlo ...")
        cases = {"corners": True, "samples": None, "seed": None}
        slew = run_montecarlo(
            slew_problem,
            controller_path,
            {**cases, "max_cases": plan["slew_cases"]},
            workers,
            None,
            staging / "slew",
            progress=not as_json,
        )
        slew["slew_duration_s"] = slew_problem.simulation.slew.duration_s
        say("pointing Monte Carlo ...")
        pointing = run_montecarlo(
            pointing_problem,
            controller_path,
            {**cases, "max_cases": plan["pointing_cases"]},
            workers,
            None,
            staging / "pointing",
            progress=not as_json,
        )
        limits = torque_limits_mNm(Allocator.from_problem(problem, build_geometry(problem)))
        rows = reproduction_rows(
            model_summary,
            budgets,
            {
                "mu_peak": record.mu_peak,
                "mu_peak_reduced": record.mu_peak_reduced,
                "order_full": None if record.full is None else record.full.nstates,
                "order_reduced": record.reduced.nstates,
            },
            margins,
            slew,
            pointing,
            limits,
        )
        summary: dict[str, Any] = {
            "problem": problem.name,
            "problem_sha256": problem.sha256,
            "controller_path": str(controller_path),
            "quick": quick,
            "workers": workers,
            "time_s": time.perf_counter() - started,
            "reproduced": sum("✅" in row[-1] for row in rows),
            "rows": len(rows),
            "table": [
                dict(zip(("result", "paper", "accepted", "ours", "verdict"), r, strict=True))
                for r in rows
            ],
            "out_dir": str(out.resolve()),
        }
        figures = [
            ("Slew (paper Fig. 4): error and torque, corner envelope shaded", "slew/envelope.png"),
            (
                "Pointing (paper Fig. 5): error against 60 arcsec, torque against limits",
                "pointing/envelope.png",
            ),
            ("μ of the robust-performance problem", "margins/mu.png"),
            (
                "Uncertainty weight W over the sampled relative errors",
                "margins/uncertainty_weight.png",
            ),
            ("Loop shapes", "margins/loop_shapes.png"),
            ("Margins over sampled plants", "margins/margins.png"),
        ]
        figures = [(t, p) for t, p in figures if (staging / p).exists()]
        (staging / "report.md").write_text(report_markdown(rows, summary, figures))
        write_json_atomic(staging / "summary.json", summary)
    if as_json:
        echo_json(summary)
        return
    click.echo(format_table(["result", "paper", "accepted", "ours", "verdict"], rows))
    click.echo(
        f"{summary['reproduced']} of {summary['rows']} rows reproduced; "
        f"report: {out.resolve() / 'report.md'} ({summary['time_s']:.0f} s)"
    )
