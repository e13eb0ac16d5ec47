"""``casadi-debris simulate`` and ``montecarlo``: closed-loop runs and campaigns."""

from __future__ import annotations

import csv
import hashlib
import re
import sys
from pathlib import Path
from typing import Any

import click
import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.cli.common import (
    echo_json,
    friendly_errors,
    in_range,
    json_option,
    main,
    overwrite_option,
    problem_argument,
    workers_option,
)
from casadi_debris.cli.robust import load_controller
from casadi_debris.config import Problem, limits, load_problem, with_duration
from casadi_debris.errors import InputShapeError
from casadi_debris.model import Model, build_model
from casadi_debris.report.campaign_folder import CampaignFolder, CampaignRecord
from casadi_debris.report.common import (
    format_table,
    write_csv,
    write_json_atomic,
)
from casadi_debris.report.folders import (
    RunFolder,
    check_output_folder,
    default_run_folder,
)
from casadi_debris.report.simulation import (
    campaign_summary,
    torque_limits_mNm,
    write_campaign,
    write_run,
)
from casadi_debris.simulation import (
    CampaignSetup,
    Case,
    ClosedLoopResult,
    corner_case,
    corner_cases,
    nominal_case,
    open_loop_rigid,
    run_campaign,
    sample_case,
    sample_cases,
    scenario_reference,
)
from casadi_debris.simulation import (
    simulate as run_simulation,
)
from casadi_debris.simulation.closed_loop import SimulationError, c_compiler

NM_PER_MNM = 1e-3
EXIT_INTERRUPTED = 130  # the shell's code for a process ended by Ctrl-C
NOMINAL_KEYS = (
    "fuel_slew_kg",
    "max_error_deg",
    "max_error_arcsec",
    "fuel_kg",
    "settle_time_s",
    "torque_saturated_s",
    "max_torque_mNm",
)


def run_summary(
    problem: Problem, case: Case, result: ClosedLoopResult, controller_path: Path
) -> dict[str, Any]:
    """The run's figures plus what identifies it (case, seed, files)."""
    return {
        "problem": problem.name,
        "problem_sha256": problem.sha256,
        "case_id": case.case_id,
        "seed": case.seed,
        "controller_path": str(controller_path),
        **result.summary(),
    }


def summary_text(summary: dict[str, Any]) -> str:
    settle = summary["settle_time_s"]
    rows = [
        ["case", summary.get("case_id", "")],
        ["max error [deg]", f"{summary['max_error_deg']:.4g}"],
        ["max error [arcsec]", f"{summary['max_error_arcsec']:.4g}"],
        ["settled (60 arcsec) at [s]", "not settled" if settle is None else f"{settle:.1f}"],
        ["fuel [kg]", f"{summary['fuel_kg']:.4g}"],
        *(
            [["fuel during the slew [kg]", f"{summary['fuel_slew_kg']:.4g}"]]
            if "fuel_slew_kg" in summary
            else []
        ),
        ["worst CubeSat fuel [kg]", f"{summary['fuel_worst_cubesat_kg']:.4g}"],
        ["dv used [m/s]", f"{summary['dv_used_m_s']:.3g}"],
        ["torque saturated [s]", f"{summary['torque_saturated_s']:.1f}"],
        ["max torque x, y, z [mNm]", ", ".join(f"{v:.3g}" for v in summary["max_torque_mNm"])],
        ["stage switches", summary["stage_switches"]],
        ["wall time [s]", f"{summary['wall_time_s']:.2f}"],
    ]
    return format_table(["figure", "value"], rows)


def choose_case(
    problem: Problem, model: Model, corner: int | None, sample: int | None, seed: int | None
) -> Case:
    if corner is not None and sample is not None:
        raise InputShapeError("give either --corner or --sample, not both")
    if corner is not None:
        try:
            return corner_case(problem, model, corner)
        except SimulationError as exc:
            raise InputShapeError(f"--corner: {exc}") from None
    if sample is not None:
        return sample_case(
            problem, model, sample, problem.montecarlo.seed if seed is None else seed
        )
    return nominal_case(model)


def read_torque_table(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """``t_s,tau_x_mNm,tau_y_mNm,tau_z_mNm`` rows -> times [s], torques [N m]."""
    expected = ["t_s", "tau_x_mNm", "tau_y_mNm", "tau_z_mNm"]
    try:
        with path.open(newline="") as handle:
            rows = list(csv.reader(handle))
    except OSError as exc:
        raise InputShapeError(f"{path}: cannot be read ({exc.strerror})") from None
    if not rows or [c.strip() for c in rows[0]] != expected:
        raise InputShapeError(f"{path}: the header must be {','.join(expected)}")
    try:
        values = np.array([[float(c) for c in row] for row in rows[1:] if row], dtype=float)
    except ValueError as exc:
        raise InputShapeError(f"{path}: {exc}") from None
    if values.ndim != 2 or values.shape[1] != 4 or len(values) == 0:
        raise InputShapeError(f"{path}: need at least one row of 4 numbers")
    return values[:, 0], values[:, 1:] * NM_PER_MNM


@main.command()
@problem_argument
@click.option(
    "--corner", type=click.IntRange(0), help="Run corner K of the uncertainty set (0-based)."
)
@click.option(
    "--sample",
    type=click.IntRange(0, limits.MONTECARLO_SAMPLES.high - 1),
    help="Run random sample N (with --seed).",
)
@click.option(
    "--seed",
    type=in_range(limits.SEED),
    help="Seed of --sample (default the problem's montecarlo.seed).",
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
@click.option("--controller", "controller_path", type=click.Path(path_type=Path, dir_okay=False))
@click.option("--out", type=click.Path(path_type=Path, file_okay=False), help="Run folder.")
@click.option("--no-plots", is_flag=True, help="Skip the PNGs.")
@overwrite_option
@json_option
@friendly_errors
def simulate(
    problem_file: Path | None,
    corner: int | None,
    sample: int | None,
    seed: int | None,
    open_loop: Path | None,
    rigid: bool,
    duration_s: float | None,
    controller_path: Path | None,
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
    if duration_s is not None:
        problem = with_duration(problem, duration_s, field="--duration-s")
    record, resolved = load_controller(controller_path)
    model = build_model(problem)
    case = choose_case(problem, model, corner, sample, seed)
    reference = scenario_reference(problem)
    allocator = Allocator.from_problem(problem, model.geometry)
    result = run_simulation(
        problem, model, record.reduced, reference, parameters=case.parameters, allocator=allocator
    )
    summary = run_summary(problem, case, result, resolved)
    if out is not None:
        with RunFolder.claim(out, overwrite=overwrite, command="simulate") as staging:
            summary["out_dir"] = str(out.absolute())
            write_run(
                staging,
                result,
                summary,
                problem,
                torque_limits_mNm(allocator),
                with_plots=not no_plots,
                title=f"{problem.name} ({case.case_id})",
            )
    if as_json:
        echo_json(summary)
    else:
        click.echo(summary_text(summary))


def _open_loop(
    problem: Problem,
    table: Path,
    duration_s: float | None,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
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


_SCHEDULER_ADDRESS = re.compile(r"(tcp|tls)://(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9.-]{1,253}):(\d{1,5})")


def check_scheduler_address(address: str) -> None:
    """Refuse anything but ``tcp://host:port`` or ``tls://host:port`` (no other schemes)."""
    match = _SCHEDULER_ADDRESS.fullmatch(address)
    if match is None or not 1 <= int(match[3]) <= 65535:
        raise InputShapeError(
            f"--scheduler: expected tcp://host:port or tls://host:port, got {address!r}"
        )


def select_cases(
    problem: Problem,
    model: Model,
    corners: bool,
    samples: int | None,
    seed: int | None,
    max_cases: int | None,
) -> list[Case]:
    """The campaign's cases; ``max_cases`` keeps that many spread evenly over the list."""
    if samples is not None and corners:
        raise InputShapeError("give either --corners or --samples, not both")
    if samples is not None:
        if samples < 1:
            raise InputShapeError(f"--samples must be at least 1, got {samples}")
        chosen = sample_cases(
            problem, model, samples, problem.montecarlo.seed if seed is None else seed
        )
    else:
        chosen = corner_cases(problem, model)
    if max_cases is not None:
        if max_cases < 1:
            raise InputShapeError(f"--max-cases must be at least 1, got {max_cases}")
        if max_cases < len(chosen):
            picks = np.unique(np.linspace(0, len(chosen) - 1, max_cases).round().astype(int))
            chosen = [chosen[i] for i in picks]
    return chosen


def run_montecarlo(
    problem: Problem,
    controller_path: Path | None,
    cases_spec: dict[str, Any],
    workers: int,
    scheduler: str | None,
    out: Path,
    progress: bool = True,
    jit: bool = True,
    overwrite: bool = False,
) -> dict[str, Any]:
    """A whole campaign into ``out`` (resuming from ``out.partial``); returns its summary."""
    check_output_folder(out, overwrite=overwrite)
    record, resolved = load_controller(controller_path)
    model = build_model(problem)
    cases = select_cases(problem, model, **cases_spec)
    reference = scenario_reference(problem)
    setup = CampaignSetup.create(problem, record.reduced, reference, jit=jit)
    identity = CampaignRecord(
        problem_name=problem.name,
        problem_sha256=problem.sha256,
        controller_sha256=hashlib.sha256(resolved.read_bytes()).hexdigest(),
        case_kind=cases[0].kind,
        seed=cases[0].seed,
        case_ids=tuple(c.case_id for c in cases),
        envelope_bin_s=setup.bin_s,
    )
    with CampaignFolder.open(out, identity, overwrite=overwrite) as folder:
        done = folder.finished_cases(cases)
        todo = [c for c in cases if c.case_id not in done]
        label = f"{problem.name}: {len(cases)} cases ({len(done)} on disk)"
        with click.progressbar(length=len(todo), label=label, hidden=not progress) as bar:

            def finished(outcome: Any) -> None:
                folder.write_case(outcome)
                done[outcome.case.case_id] = outcome
                bar.update(1)

            try:
                run_campaign(
                    setup,
                    todo,
                    workers=workers,
                    scheduler=scheduler,
                    on_result=finished,
                    build_folder=folder.build_folder,
                )
            except KeyboardInterrupt:
                raise CampaignInterrupted(len(done), len(cases), folder.partial) from None
        outcomes = [done[c.case_id] for c in cases]
        allocator = Allocator.from_problem(problem, model.geometry)
        nominal = run_simulation(problem, model, record.reduced, reference, allocator=allocator)
        nominal_summary = run_summary(problem, nominal_case(model), nominal, resolved)
        summary = campaign_summary(
            problem,
            setup,
            outcomes,
            {
                "controller_path": str(resolved),
                "controller_sha256": identity.controller_sha256,
                "case_kind": identity.case_kind,
                "seed": identity.seed,
                "workers": workers,
                "scheduler": scheduler,
                "resumed_cases": len(cases) - len(todo),
                "compiled_step": bool(jit and c_compiler()),
                "nominal": {key: nominal_summary.get(key) for key in NOMINAL_KEYS},
                "out_dir": str(out.absolute()),
            },
        )
        limits = torque_limits_mNm(allocator)
        write_campaign(
            folder.partial, problem, setup, outcomes, nominal, nominal_summary, limits, summary
        )
        folder.finish()
    return summary


class CampaignInterrupted(KeyboardInterrupt):
    """Ctrl-C during a campaign: the finished cases are on disk for a resume."""

    def __init__(self, done: int, total: int, partial: Path) -> None:
        super().__init__(
            f"interrupted: {done} of {total} cases are kept in {partial}; "
            "run the same command again to resume"
        )


@main.command()
@problem_argument
@click.option("--corners", is_flag=True, help="Every corner of the uncertainty set (default).")
@click.option(
    "--samples",
    type=in_range(limits.MONTECARLO_SAMPLES),
    help="N random samples instead of the corners.",
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
@click.option("--controller", "controller_path", type=click.Path(path_type=Path, dir_okay=False))
@click.option(
    "--no-jit",
    is_flag=True,
    help="Run the step on CasADi's virtual machine even where a C compiler is found.",
)
@click.option(
    "--out",
    type=click.Path(path_type=Path, file_okay=False),
    help="Campaign folder (default runs/montecarlo-<problem>).",
)
@overwrite_option
@json_option
@friendly_errors
def montecarlo(
    problem_file: Path | None,
    corners: bool,
    samples: int | None,
    seed: int | None,
    max_cases: int | None,
    workers: int,
    scheduler: str | None,
    controller_path: Path | None,
    no_jit: bool,
    out: Path | None,
    overwrite: bool,
    as_json: bool,
) -> None:
    """Closed-loop Monte Carlo: all corners (the paper's 256) or seeded random samples.

    Runs in parallel; where a C compiler is found each worker compiles the
    control step to C once (a few seconds) and runs every case on it. An
    interrupted campaign resumes from the cases in <out>.partial. Writes
    summary.json, cases.csv, envelope.csv/png and the nominal run.
    """
    problem = load_problem(problem_file)
    if scheduler is not None:
        check_scheduler_address(scheduler)
    out = out or default_run_folder("montecarlo", problem.name)
    try:
        summary = run_montecarlo(
            problem,
            controller_path,
            {"corners": corners, "samples": samples, "seed": seed, "max_cases": max_cases},
            workers,
            scheduler,
            out,
            progress=not as_json,
            jit=not no_jit,
            overwrite=overwrite,
        )
    except CampaignInterrupted as interrupted:
        click.echo(str(interrupted), err=True)
        sys.exit(EXIT_INTERRUPTED)
    if as_json:
        echo_json(summary)
        return
    worst = summary["worst"]
    rows = [
        [key, worst[key]["value"], worst[key]["case_id"]]
        for key in ("max_error_deg", "max_error_arcsec", "fuel_kg", "torque_saturated_s")
    ]
    click.echo(format_table(["worst over cases", "value", "case"], rows))
    click.echo(f"{summary['cases']} cases written to {summary['out_dir']}")
