"""``casadi-debris simulate`` and ``montecarlo``: closed-loop runs and campaigns."""

from __future__ import annotations

import csv
import dataclasses
import io
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from casadi_debris.cli.common import (
    batch_option,
    controller_options,
    counter_progress,
    echo_json,
    failed_cubesat_indices,
    folder_option,
    in_range,
    is_quiet,
    main,
    no_jit_option,
    output_options,
    problem_argument,
    run_folder,
    run_folder_options,
    say,
    workers_option,
)
from casadi_debris.cli.slew import axis_options
from casadi_debris.config import (
    Problem,
    limits,
    load_problem,
    read_regular_file,
)
from casadi_debris.errors import InputShapeError, UnreadableFileError
from casadi_debris.report import format_figure, format_table
from casadi_debris.store import RunFolder, check_output_folder, write_csv, write_json_atomic
from casadi_debris.units import NM_PER_MNM

if TYPE_CHECKING:
    import numpy as np

    from casadi_debris.campaigns import CampaignStatistics
    from casadi_debris.simulation import SegmentRunSummary
    from casadi_debris.workflows import SimulationSummary

EXIT_INTERRUPTED = 130  # the shell's code for a process ended by Ctrl-C


def summary_text(summary: SimulationSummary) -> str:
    run = summary.run
    settle = run.settle_time_s
    rows: list[list[Any]] = [
        ["case", summary.case_id],
        ["max error [deg]", f"{run.max_error_deg:.4g}"],
        ["max error [arcsec]", f"{run.max_error_arcsec:.4g}"],
        ["settled (60 arcsec) at [s]", "not settled" if settle is None else f"{settle:.1f}"],
        ["fuel [kg]", f"{run.fuel_kg:.4g}"],
        *(
            [["fuel during the slew [kg]", f"{run.fuel_slew_kg:.4g}"]]
            if run.fuel_slew_kg is not None
            else []
        ),
        ["worst CubeSat fuel [kg]", f"{run.fuel_worst_cubesat_kg:.4g}"],
        ["dv used [m/s]", f"{run.dv_used_m_s:.3g}"],
        ["torque saturated [s]", f"{run.torque_saturated_s:.1f}"],
        ["max torque x, y, z [mNm]", ", ".join(f"{v:.3g}" for v in run.max_torque_mNm)],
        ["stage switches", run.stage_switches],
        ["wall time [s]", f"{run.wall_time_s:.2f}"],
        ["requirements met", format_figure(summary.requirements_met)],
    ]
    return format_table(["figure", "value"], rows)


def segments_text(segments: Sequence[SegmentRunSummary] | None) -> str:
    """A manoeuvre's segments (window, largest error and fuel of each) on the lines after a
    newline; nothing without segments."""
    if segments is None:
        return ""
    rows = [
        [
            "" if f.segment is None else f.segment,
            f.kind,
            f"{f.start_s:.1f}",
            f"{f.end_s:.1f}",
            f"{f.max_error_deg:.4g}",
            f"{f.max_error_arcsec:.4g}",
            f"{f.fuel_kg:.4g}",
        ]
        for f in segments
    ]
    header = ["segment", "kind", "start [s]", "end [s]", "max error [deg]", "[arcsec]"]
    return "\n" + format_table([*header, "fuel [kg]"], rows)


def read_torque_table(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """``t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm`` rows -> times [s], torques [N m].

    Times finite, from 0 to the longest run, strictly increasing; torques finite
    and within the range a problem's torques may take.
    """
    import numpy as np

    expected = ["t_s", "tau_x_mNm", "tau_y_mNm", "tau_z_mNm"]
    where = f"--open-loop {path}"
    try:
        text = read_regular_file(path, limits.MAX_TABLE_BYTES).decode("utf-8")
    except UnreadableFileError as exc:
        raise InputShapeError(f"{where}: {exc}") from None
    except UnicodeDecodeError:
        raise InputShapeError(f"{where}: not UTF-8 text") from None
    rows = list(csv.reader(io.StringIO(text, newline="")))
    if not rows or [c.strip() for c in rows[0]] != expected:
        raise InputShapeError(f"{where}: the header must be {','.join(expected)}")
    try:
        values = np.array([[float(c) for c in row] for row in rows[1:] if row], dtype=float)
    except ValueError as exc:
        raise InputShapeError(f"{where}: {exc}") from None
    if values.ndim != 2 or values.shape[1] != 4 or len(values) == 0:
        raise InputShapeError(f"{where}: need at least one row of 4 numbers")
    times, torque = values[:, 0], values[:, 1:]
    if not np.all(np.isfinite(values)):
        raise InputShapeError(f"{where}: every entry must be finite (no NaN or inf)")
    if limits.Range(0.0, limits.DURATION_S.high).violation(times):
        raise InputShapeError(f"{where}: t_s must lie in [0, {limits.DURATION_S.high:g}] s")
    if np.any(np.diff(times) <= 0):
        raise InputShapeError(f"{where}: t_s must increase strictly")
    problem = limits.DISTURBANCE_MNM.violation(np.abs(torque))
    if problem:
        raise InputShapeError(f"{where}: torques (their magnitude) {problem} mNm")
    return times, torque * NM_PER_MNM


@main.command()
@problem_argument
@click.option(
    "--corner", type=click.IntRange(0), help="Run corner K of the uncertainty set (0-based)."
)
@click.option(
    "--sample",
    type=click.IntRange(0, int(limits.MONTECARLO_SAMPLES.high) - 1),
    help="Run random sample N (with --seed); case N of the campaign of [[montecarlo.vary]] "
    "when the problem has one.",
)
@click.option(
    "--seed",
    type=in_range(limits.SEED),
    help="Seed of --sample (default the problem's montecarlo.seed).",
)
@click.option(
    "--parameters",
    "parameters",
    type=click.Path(path_type=Path, dir_okay=False),
    help='Run at the parameters of a JSON file ({"parameters": {name: value}}, as '
    "worstcase writes them).",
)
@click.option(
    "--open-loop",
    "open_loop",
    type=click.Path(path_type=Path, dir_okay=False),
    help="Torque table t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm (held); needs --rigid.",
)
@click.option("--rigid", is_flag=True, help="Rigid body, full rigid inertia (with --open-loop).")
@click.option(
    "--duration-s", type=in_range(limits.DURATION_S), help="End time (default the problem's)."
)
@axis_options(
    "the problem's [simulation.slew]; a bang-bang timed by its duration keeps that "
    "duration's torque fraction",
    "the problem's [simulation.slew]",
)
@click.option(
    "--failed",
    default=None,
    metavar="I,J,...",
    help="CubeSats failed from the start, by id (as `casadi-debris model` lists them), added "
    "to the problem's [[simulation.failures]].",
)
@controller_options
@folder_option()
@click.option("--no-plots", is_flag=True, help="Skip the PNGs.")
@output_options
def simulate(
    problem_file: Path | None,
    corner: int | None,
    sample: int | None,
    seed: int | None,
    parameters: Path | None,
    open_loop: Path | None,
    rigid: bool,
    duration_s: float | None,
    axis: str | tuple[float, float, float] | None,
    angle_deg: float | None,
    failed: str | None,
    controller: Path | None,
    allow_mismatch: bool,
    out: Path | None,
    no_plots: bool,
    overwrite: bool,
    as_json: bool,
) -> None:
    """One closed-loop run: flexible model, star tracker, mu controller, allocator, engines.

    Follows the problem's [simulation] reference (paper_slew.toml: the 180 deg
    slew; paper_pointing.toml: one orbit of pointing). Writes summary.json,
    series.csv, closed_loop.png and thrust.png to --out.
    """
    problem = load_problem(problem_file)
    if out is not None:
        check_output_folder(out, overwrite=overwrite)
    if open_loop is not None or rigid:
        if open_loop is None or not rigid:
            raise InputShapeError("--open-loop TORQUE.csv and --rigid go together")
        _open_loop(problem, open_loop, duration_s, out, overwrite, as_json)
        return
    from casadi_debris.workflows import simulate as simulate_run

    run = simulate_run(
        problem,
        controller=controller,
        allow_mismatch=allow_mismatch,
        corner=corner,
        sample=sample,
        seed=seed,
        parameters=parameters,
        duration_s=duration_s,
        axis=axis,
        angle_deg=angle_deg,
        failed=[i + 1 for i in failed_cubesat_indices(failed, len(problem.cubesats))],
    )
    summary = run.summary
    if out is not None:
        run.save(out, overwrite=overwrite, plots=not no_plots)
        summary = dataclasses.replace(summary, out_dir=str(out.absolute()))
    if as_json:
        echo_json(summary)
    else:
        click.echo(summary_text(summary) + segments_text(run.segments))
    if summary.requirement_shortfalls:
        click.echo(
            "warning: the run misses its requirements: "
            + "; ".join(summary.requirement_shortfalls),
            err=True,
        )


def _open_loop(
    problem: Problem,
    table: Path,
    duration_s: float | None,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    from casadi_debris.simulation import open_loop_rigid

    times, torque = read_torque_table(table)
    result = open_loop_rigid(problem, times, torque, duration_s)
    summary = {
        "problem": problem.name,
        "final_quaternion": result.quaternion_BN[-1].tolist(),
        "final_rate_rad_s": result.rate_rad_s[-1].tolist(),
        "duration_s": float(result.time_s[-1]),
        "inertia_kgm2": result.inertia_kgm2.tolist(),
    }
    columns = {"time_s": result.time_s}
    for i in range(4):
        columns[f"q{i}_BN"] = result.quaternion_BN[:, i]
    for i, axis in enumerate("xyz"):
        columns[f"rate_{axis}_rad_s"] = result.rate_rad_s[:, i]
    for i, axis in enumerate("xyz"):
        columns[f"tau_{axis}_mNm"] = result.torque_Nm[:, i] * 1e3
    if out is not None:
        with RunFolder.claim(out, overwrite=overwrite, command="simulate") as staging:
            summary["out_dir"] = str(out.absolute())
            write_csv(staging / "series.csv", columns)
            write_json_atomic(staging / "summary.json", summary)
    if as_json:
        echo_json({**summary, "series": {k: v.tolist() for k, v in columns.items()}})
    else:
        q = ", ".join(f"{v:.9f}" for v in summary["final_quaternion"])
        w = ", ".join(f"{v:.6e}" for v in summary["final_rate_rad_s"])
        click.echo(f"final quaternion (scalar first): {q}\nfinal rate [rad/s]: {w}")


def cases_progress(label: str) -> Callable[[int, int], None]:
    """Finished cases on stderr: a bar on a terminal, periodic lines otherwise
    (:func:`~casadi_debris.cli.common.counter_progress`)."""
    return counter_progress(label, "cases")


def stage_progress(as_json: bool) -> Callable[[str], Callable[[int, int], None] | None]:
    """A workflow's ``progress(stage)``: each stage announced on stderr (not with ``--json``
    or ``-q``), a campaign's ("... Monte Carlo") given a case counter."""

    def progress(stage: str) -> Callable[[int, int], None] | None:
        if as_json or is_quiet():
            return None
        say(stage)
        return cases_progress(f"  {stage}") if stage.endswith("Monte Carlo") else None

    return progress


@main.command()
@problem_argument
@click.option(
    "--corners",
    is_flag=True,
    help="Every corner of the uncertainty set (the default without [[montecarlo.vary]]).",
)
@click.option(
    "--samples",
    type=in_range(limits.MONTECARLO_SAMPLES),
    help="N random samples instead of the corners (with [[montecarlo.vary]]: N draws).",
)
@click.option(
    "--seed", type=in_range(limits.SEED), help="Seed of --samples (default the problem's)."
)
@click.option(
    "--max-cases",
    type=in_range(limits.MONTECARLO_SAMPLES),
    help="Keep N cases spread evenly (a quick look).",
)
@workers_option
@click.option(
    "--scheduler",
    help="Dask scheduler address (tcp://host:8786 or tls://host:8786) instead of local "
    "processes. Connects only there; Dask unpickles what the scheduler sends, so give only "
    "a scheduler you trust.",
)
@controller_options
@no_jit_option
@batch_option
@run_folder_options("montecarlo")
def montecarlo(
    problem_file: Path | None,
    corners: bool,
    samples: int | None,
    seed: int | None,
    max_cases: int | None,
    workers: int,
    scheduler: str | None,
    controller: Path | None,
    allow_mismatch: bool,
    no_jit: bool,
    batch_cases: int,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Closed-loop Monte Carlo: all corners (the paper's 256), seeded random samples, or
    what the problem's [[montecarlo.vary]] lists, with statistics.

    Runs in parallel; where a C compiler is found the cases run in batches,
    each batch as one compiled function mapped over its cases (compiled once
    per machine, a few seconds, then kept in the cache). An
    interrupted campaign resumes from the cases in <out>.partial. Writes
    summary.json (with the pass rate against [requirements], percentiles, 3 sigma and
    rank correlations of every figure), cases.csv, envelope.csv/png, statistics.png,
    campaign.nc (every case, for xarray) and the nominal run.
    """
    from casadi_debris.errors import CampaignInterrupted
    from casadi_debris.workflows import montecarlo as run_montecarlo

    problem = load_problem(problem_file)
    folder = run_folder(out, "montecarlo", problem.name, overwrite)
    try:
        result = run_montecarlo(
            problem,
            corners=corners,
            samples=samples,
            seed=seed,
            max_cases=max_cases,
            workers=workers,
            scheduler=scheduler,
            controller=controller,
            allow_mismatch=allow_mismatch,
            no_jit=no_jit,
            batch_cases=batch_cases,
            out=folder,
            overwrite=overwrite,
            progress=None if as_json or is_quiet() else cases_progress(problem.name),
        )
    except CampaignInterrupted as interrupted:
        click.echo(f"\n{interrupted}", err=True)
        sys.exit(EXIT_INTERRUPTED)
    summary = result.summary
    if as_json:
        echo_json(summary)
        return
    worst = summary.worst
    rows = [
        [key, worst[key].value, worst[key].case_id]
        for key in ("max_error_deg", "max_error_arcsec", "fuel_kg", "torque_saturated_s")
    ]
    click.echo(format_table(["worst over cases", "value", "case"], rows))
    if summary.statistics is not None:
        click.echo(statistics_text(summary.statistics))
    click.echo(f"{summary.cases} cases written to {summary.run.out_dir}")


def statistics_text(statistics: CampaignStatistics) -> str:
    """The campaign's statistics as a table, the pass rate and what drives the error and the
    fuel most (every figure's drivers are in summary.json)."""
    columns = ("mean", "std", "p50", "p95", "p99", "mean_plus_3sigma", "max")
    rows = [[item.figure, *(getattr(item, c) for c in columns)] for item in statistics.figures]
    lines = [format_table(["figure", *columns], rows)]
    total = statistics.cases + statistics.failed_cases
    lines.append(
        f"pass rate {100 * statistics.pass_rate:.1f} % ({statistics.passed} of {total} "
        f"cases with {statistics.requirement_figure} <= {statistics.requirement:g})"
    )
    shown = (statistics.requirement_figure, "fuel_slew_kg", "fuel_kg")
    for driver in (d for d in statistics.drivers if d.figure in shown):
        ranked = ", ".join(
            f"{name} (rho {rho:+.2f}" + ("" if index is None else f", S {index:.2f}") + ")"
            for name, rho, index in zip(
                driver.quantities[:3],
                driver.spearman_rho[:3],
                driver.first_order_index[:3],
                strict=True,
            )
        )
        lines.append(f"drivers of {driver.figure}: {ranked or 'none varies'}")
    return "\n".join(lines)
