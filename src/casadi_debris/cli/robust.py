"""``casadi-debris synthesize`` and ``casadi-debris margins``: the robust controller."""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import TYPE_CHECKING

import click

from casadi_debris.cli.common import (
    bounded_option,
    comma_list,
    controller_options,
    echo_json,
    folder_option,
    in_range,
    main,
    output_options,
    problem_argument,
    run_folder,
    say,
    uncertainty_sample_options,
)
from casadi_debris.config import limits, load_problem
from casadi_debris.config.limits import (
    D_ORDER,
    DK_ITERATIONS,
    MARGIN_SAMPLES,
    MAX_D_ORDERS_TRIED,
    MU_POINTS,
)
from casadi_debris.errors import InputShapeError, SynthesisError
from casadi_debris.report import format_table

if TYPE_CHECKING:
    from casadi_debris.robust.synthesis import Iteration


@main.command()
@problem_argument
@folder_option(
    "Run folder for controller.json and summary.json [runs/synthesize-<problem>].",
)
@bounded_option("--mu-points", MU_POINTS, 150, "Frequencies of the mu grid.")
@bounded_option("--max-iterations", DK_ITERATIONS, 8, "D-K iterations at most.")
@click.option(
    "--d-orders",
    default="1,2,4",
    show_default=True,
    help=f"D-scale orders tried at each step (1 to {MAX_D_ORDERS_TRIED} of {D_ORDER}).",
)
@uncertainty_sample_options
@output_options
def synthesize(
    problem_file: Path | None,
    out: Path | None,
    mu_points: int,
    max_iterations: int,
    d_orders: str,
    samples: int | None,
    seed: int | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """mu-synthesis of the attitude controller (the paper's Section III), reduced and checked.

    Writes controller.json (fly it with --controller) and summary.json into --out.
    """
    from casadi_debris.workflows import synthesize as synthesize_job

    problem = load_problem(problem_file)
    orders = _d_orders(d_orders)
    if out is not None and out.suffix == ".json":
        raise InputShapeError(
            f"--out: a run folder (the controller goes to {out.with_suffix('')}/"
            f"controller.json), not a .json file name: {out}"
        )
    folder = run_folder(out, "synthesize", problem.name, overwrite)

    def progress(stage: str, iteration: Iteration | None) -> None:
        if iteration is None:
            say(f"  {stage} done")
            return
        what = (
            "H-inf"
            if iteration.index == 0
            else f"D-K {iteration.index} (D order {iteration.d_order})"
        )
        say(
            f"  {what}: gamma {iteration.gamma:.4f}, mu {iteration.mu_peak:.4f}, "
            f"{iteration.controller_order} states, {iteration.time_s:.1f} s"
        )

    say(f"Synthesising for {problem.name} ...")
    design = synthesize_job(
        problem,
        mu_points=mu_points,
        max_iterations=max_iterations,
        d_orders=orders,
        samples=samples,
        seed=seed,
        progress=progress,
    )
    design.save(folder, overwrite=overwrite)
    controller_path = (folder / "controller.json").absolute()
    summary = dataclasses.replace(design.summary, controller_path=str(controller_path))
    if as_json:
        echo_json(summary)
        return
    rows = [[key, value] for key, value in summary.to_json().items()]
    click.echo(format_table(["figure", "value"], rows))


def _d_orders(text: str) -> tuple[int, ...]:
    """``--d-orders 1,2,4`` as integers, each in D_ORDER, at most MAX_D_ORDERS_TRIED."""
    try:
        orders = tuple(int(part) for part in comma_list(text, "--d-orders", "1,2,4"))
    except ValueError:
        orders = ()
    if not 1 <= len(orders) <= MAX_D_ORDERS_TRIED or any(D_ORDER.violation(o) for o in orders):
        raise SynthesisError(
            f"--d-orders: 1 to {MAX_D_ORDERS_TRIED} comma-separated integers in {D_ORDER}, "
            f"got {text!r}"
        )
    return orders


@main.command()
@problem_argument
@controller_options
@bounded_option("--samples", MARGIN_SAMPLES, 3000, "Sampled uncertain plants.")
@click.option(
    "--seed", type=in_range(limits.SEED), default=None, help="Seed of the samples [problem's]."
)
@folder_option("Folder for summary.json and the plots [runs/margins-<problem>].")
@click.option("--no-plots", is_flag=True, help="Skip the figures.")
@output_options
def margins(
    problem_file: Path | None,
    controller: Path | None,
    allow_mismatch: bool,
    samples: int,
    seed: int | None,
    out: Path | None,
    no_plots: bool,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Loop-at-a-time, delay and disk margins: nominal and over sampled plants."""
    from casadi_debris.workflows import margins as margins_job

    problem = load_problem(problem_file)
    folder = run_folder(out, "margins", problem.name, overwrite)

    def progress(done: int, total: int) -> None:
        say(f"  {done}/{total} sampled plants")

    study = margins_job(
        problem,
        controller=controller,
        allow_mismatch=allow_mismatch,
        samples=samples,
        seed=seed,
        progress=progress,
    )
    study.save(folder, overwrite=overwrite, plots=not no_plots)
    summary = dataclasses.replace(study.summary, out_dir=str(folder.absolute()))
    if as_json:
        echo_json(summary)
        return
    rows = []
    sampled_data = f"nominal, sampled at {summary.control_rate_hz:g} Hz"
    for label, m in (
        ("nominal", summary.nominal),
        (sampled_data, summary.nominal_sampled_data),
        ("sampled_min", summary.sampled_min),
    ):
        rows.append([label, m.gain_margin_db, m.phase_margin_deg, m.delay_margin_s])
    click.echo(
        f"Controller {summary.controller_path} ({summary.controller_order} states) "
        f"on {problem.name}"
    )
    click.echo(
        format_table(["", "gain margin [dB]", "phase margin [deg]", "delay margin [s]"], rows)
    )
    per = summary.per_channel
    click.echo(
        format_table(
            ["channel", "GM [dB]", "upper", "lower", "PM [deg]", "delay [s]", "crossover [rad/s]"],
            [
                [
                    a,
                    v["gain_margin_db"],
                    v["upper_gain_margin_db"],
                    v["lower_gain_margin_db"],
                    v["phase_margin_deg"],
                    v["delay_margin_s"],
                    v["crossover_rad_s"],
                ]
                for a, v in per.items()
            ],
        )
    )
    disk = summary.disk_margin
    click.echo(
        f"disk margin alpha {disk.alpha:.3f} ({disk.gain_margin_db:.2f} dB, "
        f"{disk.phase_margin_deg:.1f} deg); {summary.unstable_samples} of "
        f"{summary.samples} sampled loops unstable; seed {summary.seed}"
    )
    click.echo(f"written: {summary.out_dir}")
