"""``casadi-debris allocate``: thrust of every CubeSat engine for one torque demand."""

from __future__ import annotations

import json
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
from casadi_debris.config.loader import UnreadableFileError, read_regular_file
from casadi_debris.errors import AllocationError, InputShapeError
from casadi_debris.units import MN_PER_N, MNM_PER_NM, US_PER_S

if TYPE_CHECKING:
    from casadi_debris.allocation import (
        AllocationResult,
        Allocator,
        DemandError,
        PropulsionState,
    )
    from casadi_debris.allocation.paths import SaturationMode

# The allocator's own values (a test checks they agree); written here so that the
# command's help does not load the QP back-ends.
DEFAULT_SOLVER = "daqp"
SATURATION_MODES = ("scale", "least_squares")

# The API's demand arguments and the options (and display units) they come from.
DEMAND_OPTIONS = {"torque_Nm": ("--torque-mNm", "mNm"), "force_N": ("--force-mN", "mN")}


def _failed_engines(text: str | None, state: PropulsionState) -> list[tuple[int, int]]:
    """0-based (CubeSat, engine of that CubeSat) of ``CUBESAT:ENGINE`` pairs, ids from 1."""
    if text is None:
        return []
    pairs = []
    for part in comma_list(text, "--failed-engines", "3:2,17:1"):
        cubesat, _, engine = part.partition(":")
        try:
            pair = (int(cubesat), int(engine))
        except ValueError:
            raise AllocationError(
                "--failed-engines takes comma-separated CUBESAT:ENGINE pairs such as 3:2,17:1 "
                f"(the engine counted among its CubeSat's own); got {part!r}"
            ) from None
        if not 1 <= pair[0] <= state.n_cubesats:
            raise AllocationError(
                f"--failed-engines {part}: CubeSat ids run from 1 to {state.n_cubesats}"
            )
        count = int((state.engine_cubesat == pair[0] - 1).sum())
        if not 1 <= pair[1] <= count:
            raise AllocationError(
                f"--failed-engines {part}: CubeSat {pair[0]} has engines 1..{count}"
            )
        pairs.append((pair[0] - 1, pair[1] - 1))
    return pairs


def _demand_message(
    error: DemandError,
    torque_mNm: tuple[float, float, float],
    force_mN: tuple[float, float, float] | None,
) -> str:
    """The API's refusal of a demand, said with the option and the units the user typed."""
    from casadi_debris.allocation.demand import ABSURD_FACTOR

    option, unit = DEMAND_OPTIONS.get(error.argument, (error.argument, ""))
    given = torque_mNm if error.argument == "torque_Nm" else force_mN
    typed = " ".join(f"{value:g}" for value in given or ())
    if error.bound is None:
        return f"{option} {typed}: {error.problem}"
    largest = error.bound / ABSURD_FACTOR * MN_PER_N
    return (
        f"{option} {typed}: more than {ABSURD_FACTOR:g} times the largest component any "
        f"thrust within the limits can make ({largest:.6g} {unit}); check the units"
    )


def _no_engine(error: Exception, options: dict[str, Any]) -> AllocationError:
    """No engine left: name the options (given ones of ``{name: value}``) that took them out."""
    given = " and ".join(name for name, value in options.items() if value)
    return AllocationError(f"{given or 'the problem'}: {error}")


def _read_state(path: Path | None, template: PropulsionState) -> PropulsionState:
    if path is None:
        return template
    try:
        data = json.loads(read_regular_file(path))
    except UnreadableFileError as exc:
        raise AllocationError(f"--stage-state {path}: {exc}") from None
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError) as exc:
        raise AllocationError(
            f"--stage-state {path}: not a readable JSON stage state ({str(exc)[:200]})"
        ) from None
    try:
        return template.updated_from_dict(data)
    except (AllocationError, InputShapeError) as exc:
        raise AllocationError(f"--stage-state {path}: {exc}") from None


def _payload(
    problem_name: str,
    result: AllocationResult,
    allocator: Allocator,
    state: PropulsionState,
    authority_Nm: dict[str, float],
) -> dict[str, Any]:
    limits = allocator.max_thrust_N
    firing = {int(c) for c, limit in zip(state.engine_cubesat, limits, strict=True) if limit > 0}
    dead = [cubesat + 1 for cubesat in range(state.n_cubesats) if cubesat not in firing]
    return {
        "problem": problem_name,
        "feasible": result.feasible,
        "mode": result.mode,
        "scale": result.scale,
        "thrust_mN": result.thrust_N * MN_PER_N,
        "thrust_limit_mN": limits * MN_PER_N,
        # Per engine, ids 1-based; a stage None where the engine has none left.
        "engine_cubesat": (state.engine_cubesat + 1).tolist(),
        "active_stage": [
            None if stage >= state.n_stages else int(stage) + 1 for stage in state.active_stage
        ],
        "failed_cubesats": dead,
        # [CubeSat, engine of that CubeSat], 1-based, for engines failed on their own.
        "failed_engines": state.to_dict()["failed_engines"],
        "torque_demand_mNm": result.demand_torque_Nm * MNM_PER_NM,
        "torque_achieved_mNm": result.torque_Nm * MNM_PER_NM,
        "force_demand_mN": None
        if result.demand_force_N is None
        else result.demand_force_N * MN_PER_N,
        "force_achieved_mN": result.force_N * MN_PER_N,
        "fuel_rate_kg_s": result.fuel_rate_kg_s,
        "torque_authority_mNm": {k: v * MNM_PER_NM for k, v in authority_Nm.items()},
        "solver": result.solver,
        "iterations": result.iterations,
        "solve_time_us": result.solve_time_s * US_PER_S,
    }


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
    from casadi_debris.allocation import Allocator, DemandError, NoEngineError, PropulsionState
    from casadi_debris.allocation.backends import UnknownSolverError
    from casadi_debris.geometry import build_geometry

    if force_mN is not None and free_force:
        raise AllocationError("give either --force-mN or --free-force, not both")
    problem = load_problem(problem_file)
    geometry = build_geometry(problem)
    state = _read_state(stage_state, PropulsionState.from_problem(problem))
    for index in failed_cubesat_indices(failed, len(geometry.cubesats)):
        state.fail_cubesat(index)
    for cubesat, engine in _failed_engines(failed_engines, state):
        state.fail_engine(cubesat, engine)
    took_out = {
        "--failed": failed,
        "--failed-engines": failed_engines,
        "--stage-state": stage_state,
    }
    try:
        allocator = Allocator.from_problem(
            problem,
            geometry,
            state=state,
            solver=solver,
            saturation=cast("SaturationMode", saturation),  # a click.Choice of those
        )
    except UnknownSolverError as error:
        raise AllocationError(f"--solver: {error}") from None
    except NoEngineError as error:
        raise _no_engine(error, took_out) from None
    force_N = None if force_mN is None else [f / MN_PER_N for f in force_mN]
    try:
        result = allocator.allocate(
            [t / MNM_PER_NM for t in torque_mNm], force_N, free_force=free_force
        )
    except DemandError as error:
        raise AllocationError(_demand_message(error, torque_mNm, force_mN)) from None
    except NoEngineError as error:
        raise _no_engine(error, took_out) from None
    authority = allocator.torque_authority(free_force=free_force)
    payload = _payload(problem.name, result, allocator, state, authority)
    if as_json:
        echo_json(payload)
    else:
        click.echo(_text(payload, [m.face for m in geometry.cubesats]))
