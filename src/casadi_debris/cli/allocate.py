"""``casadi-debris allocate``: thrust of every CubeSat engine for one torque demand."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any, cast

import click

from casadi_debris.cli.common import (
    comma_list,
    echo_json,
    failed_cubesat_indices,
    friendly_errors,
    json_option,
    main,
    problem_argument,
)
from casadi_debris.config import load_problem
from casadi_debris.errors import AllocationError

if TYPE_CHECKING:
    from casadi_debris.allocation import SaturationMode

# The allocator's own values (a test checks they agree); written here so that the
# command's help does not load the QP back-ends.
DEFAULT_SOLVER = "daqp"
SATURATION_MODES = ("scale", "least_squares")


def _failed_engines(text: str | None) -> list[tuple[int, int]]:
    """(CubeSat, engine of that CubeSat) of ``CUBESAT:ENGINE`` pairs, ids from 1 (their range
    is checked by the job)."""
    if text is None:
        return []
    pairs = []
    for part in comma_list(text, "--failed-engines", "3:2,17:1"):
        cubesat, _, engine = part.partition(":")
        try:
            pairs.append((int(cubesat), int(engine)))
        except ValueError:
            raise AllocationError(
                "--failed-engines takes comma-separated CUBESAT:ENGINE pairs such as 3:2,17:1 "
                f"(the engine counted among its CubeSat's own); got {part!r}"
            ) from None
    return pairs


def _text(payload: dict[str, Any], faces: list[str | None]) -> str:
    def triple(values: Any) -> str:
        return "[" + ", ".join(f"{v:+.4f}" for v in values) + "]"

    status = "feasible" if payload["feasible"] else f"saturated, scale {payload['scale']:.6f}"
    lines = [
        f"allocation ({payload['problem']}): {status} ({payload['mode']})",
        f"  torque demand    {triple(payload['torque_demand_mNm'])} mNm",
        f"  torque achieved  {triple(payload['torque_achieved_mNm'])} mNm",
        f"  force achieved   {triple(payload['force_achieved_mN'])} mN"
        + ("  (free)" if payload["force_demand_mN"] is None else ""),
        f"  fuel rate        {payload['fuel_rate_kg_s']:.4e} kg/s",
        f"  solver           {payload['solver']}, {payload['iterations']} iterations, "
        f"{payload['solve_time_us']:.1f} us",
        "  authority (mNm)  "
        + ", ".join(f"{k} {v:.3f}" for k, v in payload["torque_authority_mNm"].items()),
        "",
        "  engine  cubesat  face  stage  thrust_mN  limit_mN",
    ]
    for index, (cubesat, thrust, limit, stage) in enumerate(
        zip(
            payload["engine_cubesat"],
            payload["thrust_mN"],
            payload["thrust_limit_mN"],
            payload["active_stage"],
            strict=True,
        )
    ):
        stage_text = "-" if limit == 0 or stage is None else str(stage)
        face = faces[cubesat - 1] or "-"
        lines.append(
            f"  {index + 1:6d}  {cubesat:7d}  {face:>4}  {stage_text:>5}  {thrust:9.4f}"
            f"  {limit:8.4f}"
        )
    return "\n".join(lines)


@main.command()
@problem_argument
@click.option(
    "--torque-mNm",
    "torque_mNm",
    nargs=3,
    type=float,
    required=True,
    metavar="TX TY TZ",
    help="Torque demand about the CoG, body frame [mNm]; finite, and no component beyond"
    " 1e6 times the largest the engines can make.",
)
@click.option(
    "--force-mN",
    "force_mN",
    nargs=3,
    type=float,
    default=None,
    metavar="FX FY FZ",
    help="Net force demand [mN] (default zero).",
)
@click.option("--free-force", is_flag=True, help="Leave the net force free.")
@click.option(
    "--failed",
    default=None,
    metavar="I,J,...",
    help="Failed CubeSats by id (1..24, as `casadi-debris model` lists them).",
)
@click.option(
    "--failed-engines",
    default=None,
    metavar="C:E,...",
    help="Failed engines as CUBESAT:ENGINE pairs, the engine counted among its CubeSat's own"
    " (cubesat_engine in `casadi-debris model --json`); the CubeSat's other engines fire on.",
)
@click.option(
    "--stage-state",
    type=click.Path(path_type=Path, dir_okay=False),
    default=None,
    help="JSON propulsion state (propellant_kg, firing_time_s, failed_cubesats, failed_stages,"
    " failed_engines; CubeSats, stages and engines numbered from 1, as PropulsionState.to_dict"
    " writes them).",
)
@click.option(
    "--solver",
    default=DEFAULT_SOLVER,
    show_default=True,
    help="QP back-end (daqp, osqp, or any solver qpsolvers finds).",
)
@click.option(
    "--saturation",
    type=click.Choice(SATURATION_MODES),
    default="scale",
    show_default=True,
    help="Infeasible demands: keep the direction (scale) or least squares.",
)
@json_option
@friendly_errors
def allocate(
    problem_file: Path | None,
    torque_mNm: tuple[float, float, float],
    force_mN: tuple[float, float, float] | None,
    free_force: bool,
    failed: str | None,
    failed_engines: str | None,
    stage_state: Path | None,
    solver: str,
    saturation: str,
    as_json: bool,
) -> None:
    """Thrust of every CubeSat engine for a torque (and force) demand: least fuel, exact when
    reachable, direction kept when not."""
    from casadi_debris.workflows import allocate as allocate_job

    problem = load_problem(problem_file)
    result = allocate_job(
        problem,
        torque_mNm=torque_mNm,
        force_mN=force_mN,
        free_force=free_force,
        failed=[i + 1 for i in failed_cubesat_indices(failed, len(problem.cubesats))],
        failed_engines=_failed_engines(failed_engines),
        stage_state=stage_state,
        solver=solver,
        saturation=cast("SaturationMode", saturation),  # a click.Choice of those
    )
    if as_json:
        echo_json(result.summary)
    else:
        click.echo(_text(result.summary.to_json(), [m.face for m in result.geometry.cubesats]))
