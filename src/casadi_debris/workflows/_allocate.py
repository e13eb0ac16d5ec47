"""Thrust of every CubeSat engine for one torque demand (``casadi-debris allocate``).

Least fuel and exact where the demand is reachable, its direction kept where it is not,
with CubeSats, engines or stages taken out first.

Example
-------
>>> import casadi_debris as cd
>>> result = cd.allocate(torque_mNm=(1.0, 0.5, -0.8))
>>> result.summary.feasible, result.summary.mode
(True, 'exact')
>>> [round(t, 4) for t in result.summary.torque_achieved_mNm]
[1.0, 0.5, -0.8]
"""

from __future__ import annotations

import json
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.config import Problem, read_regular_file
from casadi_debris.errors import AllocationError, InputShapeError, UnreadableFileError
from casadi_debris.records import Record
from casadi_debris.store import write_json_atomic
from casadi_debris.units import MN_PER_N, MNM_PER_NM, US_PER_S
from casadi_debris.workflows._result import JobResult, ProblemLike, as_problem

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from casadi_debris.allocation import (
        Allocation,
        Allocator,
        DemandError,
        PropulsionState,
        SaturationMode,
    )
    from casadi_debris.geometry import Authority, Geometry

Vector = Sequence[float]

# The demand arguments of the allocator, and the keywords (and display units) they come
# from, for a refusal said in the units the user typed.
DEMAND_KEYWORDS = {"torque_Nm": ("--torque-mNm", "mNm"), "force_N": ("--force-mN", "mN")}


@dataclass(frozen=True)
class AllocationSummary(Record):
    """``casadi-debris allocate --json``: one allocation in display units.

    Per engine (in the problem's order): ``thrust_mN``, ``thrust_limit_mN`` (0 for an
    engine out), ``engine_cubesat`` (its CubeSat's id, from 1) and ``active_stage`` (from
    1; None where it has no stage left). ``failed_cubesats`` lists the CubeSats that cannot
    fire (ids from 1), ``failed_engines`` the engines failed on their own as [CubeSat,
    engine of that CubeSat] pairs (from 1). ``scale`` is the saturation's alpha (1 when
    ``feasible``); ``force_demand_mN`` is None when the force was left free;
    ``torque_authority_mNm`` is the largest torque by signed axis (``"+x"`` ... ``"-z"``).
    """

    problem: str
    feasible: bool
    mode: str
    scale: float
    thrust_mN: tuple[float, ...]
    thrust_limit_mN: tuple[float, ...]
    engine_cubesat: tuple[int, ...]
    active_stage: tuple[int | None, ...]
    failed_cubesats: tuple[int, ...]
    failed_engines: tuple[tuple[int, int], ...]
    torque_demand_mNm: tuple[float, ...]
    torque_achieved_mNm: tuple[float, ...]
    force_demand_mN: tuple[float, ...] | None
    force_achieved_mN: tuple[float, ...]
    fuel_rate_kg_s: float
    torque_authority_mNm: dict[str, float]
    solver: str
    iterations: int
    solve_time_us: float


@dataclass(frozen=True)
class AllocationResult(JobResult):
    """One allocation: the thrusts (SI), the state they were solved for, and the summary.

    Attributes
    ----------
    allocation : casadi_debris.allocation.Allocation
        Thrust of every engine [N], achieved torque [N m] and force [N], the demand,
        mode, scale and solver figures.
    state : PropulsionState
        Stages and failures the allocation was solved for (after ``failed``,
        ``failed_engines`` and ``stage_state``).
    geometry : Geometry
        The swarm (each CubeSat's docking face, each engine's position and direction).
    summary : AllocationSummary
        What ``casadi-debris allocate --json`` prints.
    """

    allocation: Allocation
    state: PropulsionState
    geometry: Geometry
    summary: AllocationSummary

    command = "allocate"

    def plot(self) -> dict[str, Figure]:
        """``thrust``: every engine's thrust against its limit, and the torque asked for
        against the torque made. Nothing is written."""
        from casadi_debris.plots import allocation_figure

        summary = self.summary
        status = "met" if summary.feasible else f"saturated, scale {summary.scale:.4g}"
        return {
            "thrust": allocation_figure(
                summary.thrust_mN,
                summary.thrust_limit_mN,
                summary.engine_cubesat,
                (summary.torque_demand_mNm, summary.torque_achieved_mNm),
                f"{summary.problem}: demand {status} ({summary.mode})",
            )
        }

    def _write(self, staging: Path, out: Path, *, plots: bool) -> None:
        """``summary.json`` and (with ``plots``) ``thrust.png`` (the command prints the
        summary and writes nothing)."""
        write_json_atomic(staging / "summary.json", self.summary)
        if plots:
            from casadi_debris.plots import save_figure

            for name, figure in self.plot().items():
                save_figure(figure, staging / f"{name}.png")


def allocate(
    problem: ProblemLike = None,
    *,
    torque_mNm: Vector,
    force_mN: Vector | None = None,
    free_force: bool = False,
    failed: Sequence[int] = (),
    failed_engines: Sequence[tuple[int, int]] = (),
    stage_state: str | Path | PropulsionState | None = None,
    solver: str = "daqp",
    saturation: SaturationMode = "scale",
) -> AllocationResult:
    """Thrust of every CubeSat engine for a torque (and force) demand.

    Least fuel and the torque exact when the demand is reachable; otherwise the torque
    cut back along its own direction (``saturation="scale"``) or the reachable torque
    closest to it (``"least_squares"``). Thrust limits are never exceeded.

    Parameters
    ----------
    problem : Problem, str or Path, optional
        A problem, a problem file or a shipped name; default the paper.
    torque_mNm : sequence of 3 floats
        Torque demand about the CoG, body frame [mN m].
    force_mN : sequence of 3 floats, optional
        Net force demand, body frame [mN]; default zero.
    free_force : bool
        Leave the net force free (not with ``force_mN``).
    failed : sequence of int
        Failed CubeSats by id (from 1, as ``cd.model`` lists them).
    failed_engines : sequence of (int, int)
        Failed engines as (CubeSat id, engine of that CubeSat), both from 1 (the
        thruster's ``cubesat_engine`` in ``cd.model``); the CubeSat's others fire on.
    stage_state : str, Path or PropulsionState, optional
        The propulsion state (propellant, firing time, failed stages ...): a JSON file as
        ``PropulsionState.to_dict`` writes it (ids from 1), or the state itself (not
        changed); default every engine full, on its first stage.
    solver : str
        QP back-end: ``"daqp"``, ``"osqp"`` or any solver qpsolvers finds.
    saturation : {"scale", "least_squares"}
        What an unreachable demand gets.

    Returns
    -------
    AllocationResult

    Raises
    ------
    AllocationError
        A demand that is not finite or absurdly large, an unknown solver, ids out of
        range, an unreadable state file, no engine left (each named).
    """
    from casadi_debris.allocation import DemandError, NoEngineError
    from casadi_debris.geometry import build_geometry

    if force_mN is not None and free_force:
        raise AllocationError("give either --force-mN or --free-force, not both")
    problem = as_problem(problem)
    geometry = build_geometry(problem)
    state = _state(problem, stage_state, failed, failed_engines)
    took_out = {
        "--failed": bool(failed),
        "--failed-engines": bool(failed_engines),
        "--stage-state": stage_state is not None,
    }
    allocator = _allocator(problem, geometry, state, (solver, saturation), took_out)
    torque = _demand(torque_mNm, "torque_Nm", MNM_PER_NM)
    force = None if force_mN is None else _demand(force_mN, "force_N", MN_PER_N)
    try:
        allocation = allocator.allocate(torque, force, free_force=free_force)
    except DemandError as error:
        raise AllocationError(_demand_message(error, torque_mNm, force_mN)) from None
    except NoEngineError as error:
        raise _no_engine(error, took_out) from None
    authority = allocator.torque_authority(free_force=free_force)
    summary = _summary(problem.name, allocation, allocator, state, authority)
    return AllocationResult(allocation=allocation, state=state, geometry=geometry, summary=summary)


def _allocator(
    problem: Problem,
    geometry: Geometry,
    state: PropulsionState,
    how: tuple[str, SaturationMode],
    took_out: dict[str, bool],
) -> Allocator:
    """The allocator of ``problem`` for ``state`` (``how``: the solver and the saturation
    mode); an unknown solver or no engine left refused by name."""
    from casadi_debris.allocation import Allocator, NoEngineError, UnknownSolverError

    solver, saturation = how
    try:
        return Allocator.from_problem(
            problem, geometry, state=state, solver=solver, saturation=saturation
        )
    except UnknownSolverError as error:
        raise AllocationError(f"--solver: {error}") from None
    except NoEngineError as error:
        raise _no_engine(error, took_out) from None


def _demand(values: Any, argument: str, per_si: float) -> Any:
    """A demand in display units as SI (what cannot be read as numbers goes to the
    allocator as it is, which names the argument)."""
    try:
        return np.asarray(values, dtype=float) / per_si
    except (TypeError, ValueError):
        option, unit = DEMAND_KEYWORDS[argument]
        raise AllocationError(f"{option}: three numbers [{unit}], got {values!r}") from None


def _state(
    problem: Problem,
    stage_state: str | Path | PropulsionState | None,
    failed: Sequence[int],
    failed_engines: Sequence[tuple[int, int]],
) -> PropulsionState:
    """The propulsion state asked for: the file's or the given one (copied), with the
    CubeSats and engines failed (ids from 1)."""
    from casadi_debris.allocation import PropulsionState

    template = PropulsionState.from_problem(problem)
    if isinstance(stage_state, PropulsionState):
        state = stage_state.copy()
    elif stage_state is None:
        state = template
    else:
        state = _read_state(Path(stage_state), template)
    bad = sorted({i for i in failed if not 1 <= i <= state.n_cubesats})
    if bad:
        raise InputShapeError(f"--failed: CubeSat ids run from 1 to {state.n_cubesats}; got {bad}")
    for cubesat in sorted(set(failed)):
        state.fail_cubesat(cubesat - 1)
    for cubesat, engine in _checked_engines(failed_engines, state):
        state.fail_engine(cubesat, engine)
    return state


def _checked_engines(
    pairs: Sequence[tuple[int, int]], state: PropulsionState
) -> list[tuple[int, int]]:
    """0-based (CubeSat, engine of that CubeSat) of 1-based pairs, each checked."""
    checked = []
    for cubesat, engine in pairs:
        given = f"{cubesat}:{engine}"
        if not 1 <= cubesat <= state.n_cubesats:
            raise AllocationError(
                f"--failed-engines {given}: CubeSat ids run from 1 to {state.n_cubesats}"
            )
        count = int((state.engine_cubesat == cubesat - 1).sum())
        if not 1 <= engine <= count:
            raise AllocationError(
                f"--failed-engines {given}: CubeSat {cubesat} has engines 1..{count}"
            )
        checked.append((cubesat - 1, engine - 1))
    return checked


def _read_state(path: Path, template: PropulsionState) -> PropulsionState:
    """``template`` updated from the JSON stage state at ``path``."""
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


def _demand_message(error: DemandError, torque_mNm: Vector, force_mN: Vector | None) -> str:
    """The allocator's refusal of a demand, said with the option and the units the user
    typed."""
    from casadi_debris.allocation import ABSURD_FACTOR

    option, unit = DEMAND_KEYWORDS.get(error.argument, (error.argument, ""))
    given = torque_mNm if error.argument == "torque_Nm" else force_mN
    typed = " ".join(f"{value:g}" for value in np.ravel(np.asarray(given or (), dtype=float)))
    if error.bound is None:
        return f"{option} {typed}: {error.problem}"
    largest = error.bound / ABSURD_FACTOR * MN_PER_N
    return (
        f"{option} {typed}: more than {ABSURD_FACTOR:g} times the largest component any "
        f"thrust within the limits can make ({largest:.6g} {unit}); check the units"
    )


def _no_engine(error: Exception, took_out: dict[str, bool]) -> AllocationError:
    """No engine left: name the options (those given of ``took_out``) that took them out."""
    given = " and ".join(name for name, value in took_out.items() if value)
    return AllocationError(f"{given or 'the problem'}: {error}")


def _summary(
    problem_name: str,
    allocation: Allocation,
    allocator: Allocator,
    state: PropulsionState,
    authority_Nm: Authority,
) -> AllocationSummary:
    """The allocation in display units, ids from 1."""
    limits = allocator.max_thrust_N
    firing = {int(c) for c, limit in zip(state.engine_cubesat, limits, strict=True) if limit > 0}
    return AllocationSummary(
        problem=problem_name,
        feasible=bool(allocation.feasible),
        mode=allocation.mode,
        scale=float(allocation.scale),
        thrust_mN=_floats(allocation.thrust_N * MN_PER_N),
        thrust_limit_mN=_floats(limits * MN_PER_N),
        engine_cubesat=tuple(int(c) + 1 for c in state.engine_cubesat),
        active_stage=tuple(
            None if stage >= state.n_stages else int(stage) + 1 for stage in state.active_stage
        ),
        failed_cubesats=tuple(c + 1 for c in range(state.n_cubesats) if c not in firing),
        failed_engines=tuple((int(c), int(e)) for c, e in state.to_dict()["failed_engines"]),
        torque_demand_mNm=_floats(allocation.demand_torque_Nm * MNM_PER_NM),
        torque_achieved_mNm=_floats(allocation.torque_Nm * MNM_PER_NM),
        force_demand_mN=None
        if allocation.demand_force_N is None
        else _floats(allocation.demand_force_N * MN_PER_N),
        force_achieved_mN=_floats(allocation.force_N * MN_PER_N),
        fuel_rate_kg_s=float(allocation.fuel_rate_kg_s),
        torque_authority_mNm=authority_Nm.to_mNm(),
        solver=allocation.solver,
        iterations=int(allocation.iterations),
        solve_time_us=allocation.solve_time_s * US_PER_S,
    )


def _floats(values: np.ndarray) -> tuple[float, ...]:
    return tuple(float(v) for v in values)
