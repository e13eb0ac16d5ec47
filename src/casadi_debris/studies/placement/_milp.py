"""The placement mixed-integer programme, solved by HiGHS through :func:`scipy.optimize.milp`.

Variables: a binary ``y_j`` per candidate CubeSat, the objective ``z``, and one
*block* per (set of failed mounts S, signed axis a): a thrust per engine
``f`` (in units of the largest stage thrust) and the torque ``t`` it makes.
Each block states

- ``0 <= f_e <= f_max,e y_j(e)`` (``f_e = 0`` for the engines of S),
- zero net force ``F f = 0``,
- torque ``t`` about a and none about the other two axes (``T f = ±t e_a``),
- ``z <= t / d_a`` (``d_a`` the disturbance amplitude about the axis),

and the programme maximises ``z``: the worst signed axis's zero-net-force
authority over its disturbance, taken over every block, i.e. over every
failure set. Besides: ``A <= sum y <= B`` CubeSats, at most one candidate per
mount, optionally ``sum_j y_j I_j,aa <= limit_a`` on the added inertia and a
rigid slew time limit (see :func:`slew_rows`). Torques are taken about the bare
debris' CoG (see :func:`~casadi_debris.studies.placement.placement_data` for why that is exact).

Failure sets: none (``failures = 0``), every mount alone (1), every pair of
mounts (2). All of them at once (*extensive* form) has
``C(mounts, k) x 6`` blocks of ``engines + 1`` variables each, which grows past
what HiGHS solves in minutes for double failures on a fine grid (4 x 4 per face:
96 mounts, 4560 pairs, 2.6 million variables). Above ``max_extensive_variables``
the blocks are generated instead: solve with the blocks found so far (an upper
bound, since it is a relaxation), find the chosen layout's worst set per axis by
LP over all its failure sets (a lower bound), add those blocks and repeat until
the bounds meet within the MIP gap. Both forms are exact at convergence.
"""

from __future__ import annotations

import contextlib
import itertools
import logging
import math
import os
import sys
import tempfile
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from scipy import sparse
from scipy.optimize import Bounds, LinearConstraint, milp

from casadi_debris.config import SIGNED_AXES
from casadi_debris.errors import InputShapeError
from casadi_debris.geometry import signed_axis
from casadi_debris.studies.placement._authority import (
    WorstFailures,
    layout_authority_Nm,
    worst_failures,
)
from casadi_debris.studies.placement._data import PlacementData

LOGGER = logging.getLogger(__name__)

OBJECTIVES = {"worst-axis": 0, "worst-single-failure": 1, "worst-double-failure": 2}
"""Objective names and the number of failed CubeSats each guards against."""
Method = Literal["extensive", "generated"]
ROUND_SHARE = 3.0
"""A generated round may take this share of the time left (1 / ROUND_SHARE)."""
MIN_ROUND_S = 5.0
GAP_ABSOLUTE = 1e-9
"""Bounds this close (in authority over disturbance) are equal."""
Block = tuple[tuple[int, ...], int]
"""(failed mounts, signed-axis index into SIGNED_AXES)."""


@dataclass(frozen=True)
class PlacementSettings:
    """What to optimise and under which limits.

    Attributes
    ----------
    count : tuple of int
        Least and most CubeSats (equal for a fixed count).
    failures : {0, 1, 2}
        Failed CubeSats the worst authority is taken over.
    max_added_inertia_kgm2 : tuple of float, optional
        Per axis (x, y, z): the CubeSats' inertia about the bare debris' CoG.
    max_slew_s : float, optional
        Rigid rest-to-rest bang-bang time of a ``slew_angle_deg`` slew about each
        body axis, with the nominal zero-net-force authority.
    min_per_face : int
        CubeSats on every face at least (so that engines push along every
        direction without turning the body).
    slew_angle_deg : float
    mip_rel_gap : float
        HiGHS' relative gap, and the generation's stopping gap.
    time_limit_s : float
        For the whole solve (all rounds).
    max_extensive_variables : int
        Largest extensive form built; larger ones are generated.
    max_rounds : int
        Generation rounds at most.
    """

    count: tuple[int, int]
    failures: int = 0
    max_added_inertia_kgm2: tuple[float, float, float] | None = None
    max_slew_s: float | None = None
    min_per_face: int = 0
    slew_angle_deg: float = 180.0
    mip_rel_gap: float = 1e-6
    time_limit_s: float = 600.0
    max_extensive_variables: int = 50_000
    max_rounds: int = 60


@dataclass(frozen=True)
class MilpSolve:
    """One HiGHS call: its status, bound and size."""

    status: int
    message: str
    objective: float | None
    upper_bound: float | None
    mip_gap: float | None
    nodes: int | None
    time_s: float
    variables: int
    binaries: int
    rows: int
    blocks: int


@dataclass(frozen=True)
class PlacementSolution:
    """The chosen candidates and how sure the solver is of them.

    Attributes
    ----------
    chosen : tuple of int
        Candidates (0-based), ascending.
    objective : float
        Worst authority over disturbance of the chosen layout over every failure
        set, recomputed by LP (not the solver's own value).
    upper_bound : float
        Proven bound on the best objective of any layout.
    gap : float
        ``(upper_bound - objective) / upper_bound``.
    optimal : bool
        Every HiGHS call proved optimality and the gap is within ``mip_rel_gap``.
    method : {"extensive", "generated"}
    blocks_total : int
        (failure set, axis) blocks of the extensive form.
    blocks_used : int
        Blocks in the last solve.
    worst : WorstFailures
        The chosen layout's worst set per axis.
    solves : tuple of MilpSolve
    time_s : float
    """

    chosen: tuple[int, ...]
    objective: float
    upper_bound: float
    gap: float
    optimal: bool
    method: Method
    blocks_total: int
    blocks_used: int
    worst: WorstFailures
    solves: tuple[MilpSolve, ...] = field(repr=False)
    time_s: float = 0.0


@dataclass
class _Rows:
    """A growing sparse constraint matrix (COO triplets and bounds)."""

    n_columns: int
    rows: list[np.ndarray] = field(default_factory=list)
    columns: list[np.ndarray] = field(default_factory=list)
    values: list[np.ndarray] = field(default_factory=list)
    lower: list[np.ndarray] = field(default_factory=list)
    upper: list[np.ndarray] = field(default_factory=list)
    count: int = 0

    def add(
        self,
        row: np.ndarray,
        column: np.ndarray,
        value: np.ndarray,
        lo: float | np.ndarray,
        hi: float | np.ndarray,
        n_rows: int,
    ) -> None:
        self.rows.append(np.asarray(row) + self.count)
        self.columns.append(np.asarray(column))
        self.values.append(np.asarray(value, dtype=float))
        self.lower.append(np.broadcast_to(np.asarray(lo, dtype=float), (n_rows,)))
        self.upper.append(np.broadcast_to(np.asarray(hi, dtype=float), (n_rows,)))
        self.count += n_rows

    def constraint(self) -> LinearConstraint:
        matrix = sparse.csr_array(
            (
                np.concatenate(self.values),
                (np.concatenate(self.rows), np.concatenate(self.columns)),
            ),
            shape=(self.count, self.n_columns),
        )
        return LinearConstraint(matrix, np.concatenate(self.lower), np.concatenate(self.upper))


def failure_sets(n_mounts: int, failures: int) -> list[tuple[int, ...]]:
    """Every set of ``failures`` mounts (the empty set for none)."""
    return list(itertools.combinations(range(n_mounts), failures))


def _block_rows(
    rows: _Rows, data: PlacementData, block: Block, start: int, unit: float
) -> np.ndarray:
    """A block's thrust bounds, zero force, pure torque and ``z <= t / d`` rows.

    Returns the columns of its failed engines (the caller bounds them to zero).
    """
    failed, axis_index = block
    axis, sign = signed_axis(SIGNED_AXES[axis_index])
    n_e = data.n_engines
    engines = np.arange(n_e)
    t_column = start + n_e
    others = [a for a in range(3) if a != axis]
    wrench = np.vstack([data.force_map, data.torque_map[others], sign * data.torque_map[axis]])
    r, c = np.nonzero(np.abs(wrench) > 0)
    rows.add(
        np.append(r, 5), np.append(start + c, t_column), np.append(wrench[r, c], -1.0), 0.0, 0.0, 6
    )
    mounts = data.candidate_mount[data.engine_candidate]
    alive = engines[~np.isin(mounts, failed)]
    k = len(alive)
    rows.add(
        np.concatenate([np.arange(k), np.arange(k)]),
        np.concatenate([start + alive, data.engine_candidate[alive]]),
        np.concatenate([np.ones(k), -data.max_thrust_N[alive] / unit]),
        -np.inf,
        0.0,
        k,
    )
    z_column = data.n_candidates
    rows.add(
        np.zeros(2, dtype=int),
        np.array([z_column, t_column]),
        np.array([1.0, -unit / data.disturbance_Nm[axis]]),
        -np.inf,
        0.0,
        1,
    )
    return start + engines[np.isin(mounts, failed)]


def slew_rows(
    rows: _Rows,
    data: PlacementData,
    settings: PlacementSettings,
    nominal_start: dict[int, int],
    unit: float,
) -> None:
    """Rigid slew time ``2 sqrt(theta I_aa / t_a) <= T`` about every axis, both signs.

    Squared and rearranged it is linear: ``t_a >= (4 theta / T^2) I_aa``, with
    ``I_aa`` the bare debris' plus the chosen CubeSats' (an upper bound on the
    inertia about the combined CoG, see
    :func:`~casadi_debris.studies.placement.placement_data`). Products of inertia are left
    out (the exact eigenaxis time is reported afterwards).
    """
    assert settings.max_slew_s is not None
    gain = 4.0 * math.radians(settings.slew_angle_deg) / settings.max_slew_s**2 / unit
    for axis_index, start in nominal_start.items():
        axis, _ = signed_axis(SIGNED_AXES[axis_index])
        columns = np.append(np.arange(data.n_candidates), start + data.n_engines)
        values = np.append(-gain * data.added_inertia_kgm2[:, axis], 1.0)
        rows.add(
            np.zeros(len(columns), dtype=int),
            columns,
            values,
            gain * data.inertia_bare_kgm2[axis, axis],
            np.inf,
            1,
        )


def _choice_rows(rows: _Rows, data: PlacementData, settings: PlacementSettings) -> None:
    """Count, one candidate per mount, CubeSats per face, added inertia."""
    n_c = data.n_candidates
    everyone = np.arange(n_c)
    rows.add(np.zeros(n_c, dtype=int), everyone, np.ones(n_c), *settings.count, 1)
    if settings.min_per_face > 0:
        faces = [SIGNED_AXES.index(c.face) for c in data.candidates.candidates]
        rows.add(
            np.array(faces),
            everyone,
            np.ones(n_c),
            float(settings.min_per_face),
            np.inf,
            len(SIGNED_AXES),
        )
    if data.candidates.n_mounts < n_c:
        rows.add(
            data.candidate_mount, everyone, np.ones(n_c), -np.inf, 1.0, data.candidates.n_mounts
        )
    if settings.max_added_inertia_kgm2 is not None:
        r, c = np.nonzero(data.added_inertia_kgm2.T > 0)
        rows.add(
            r,
            c,
            data.added_inertia_kgm2.T[r, c],
            -np.inf,
            np.asarray(settings.max_added_inertia_kgm2, dtype=float),
            3,
        )


def solve_blocks(
    data: PlacementData, blocks: list[Block], settings: PlacementSettings, time_limit_s: float
) -> tuple[MilpSolve, np.ndarray | None]:
    """One MILP over the given blocks; returns its record and y (None without a solution)."""
    n_c, n_e = data.n_candidates, data.n_engines
    if settings.max_slew_s is not None:
        blocks = blocks + [((), a) for a in range(len(SIGNED_AXES)) if ((), a) not in blocks]
    n_vars = n_c + 1 + len(blocks) * (n_e + 1)
    unit = float(np.max(data.max_thrust_N))
    rows = _Rows(n_vars)
    nominal_start = {}
    upper = np.full(n_vars, np.inf)
    upper[:n_c] = 1.0
    for b, block in enumerate(blocks):
        start = n_c + 1 + b * (n_e + 1)
        upper[_block_rows(rows, data, block, start, unit)] = 0.0
        if not block[0]:
            nominal_start[block[1]] = start
    _choice_rows(rows, data, settings)
    if settings.max_slew_s is not None:
        slew_rows(rows, data, settings, nominal_start, unit)
    objective = np.zeros(n_vars)
    objective[n_c] = -1.0
    integrality = np.zeros(n_vars, dtype=int)
    integrality[:n_c] = 1
    began = time.perf_counter()
    with solver_output_logged("HiGHS"):
        result = milp(
            objective,
            integrality=integrality,
            bounds=Bounds(np.zeros(n_vars), upper),
            constraints=rows.constraint(),
            options={
                "disp": False,
                "mip_rel_gap": settings.mip_rel_gap,
                "time_limit": max(time_limit_s, 1.0),
            },
        )
    elapsed = time.perf_counter() - began
    x = result.x
    dual = getattr(result, "mip_dual_bound", None)
    gap = getattr(result, "mip_gap", None)
    nodes = getattr(result, "mip_node_count", None)
    record = MilpSolve(
        status=int(result.status),
        message=str(result.message),
        objective=-float(result.fun) if x is not None and result.fun is not None else None,
        upper_bound=-float(dual) if dual is not None and math.isfinite(dual) else None,
        mip_gap=float(gap) if gap is not None else None,
        nodes=int(nodes) if nodes is not None else None,
        time_s=elapsed,
        variables=n_vars,
        binaries=n_c,
        rows=rows.count,
        blocks=len(blocks),
    )
    LOGGER.info(
        "MILP %d blocks, %d variables: %s in %.2f s", len(blocks), n_vars, record.message, elapsed
    )
    return record, (np.round(x[:n_c]) if x is not None else None)


@contextlib.contextmanager
def solver_output_logged(solver: str) -> Iterator[None]:
    """Send what C code prints on standard output meanwhile to the log (INFO: shown with
    ``-v``), each line prefixed by ``solver``.

    HiGHS prints some lines from C whatever its log options say; caught at the file
    descriptor, they can neither clutter a terminal nor break JSON on stdout.
    """
    sys.stdout.flush()
    saved = os.dup(1)
    with tempfile.TemporaryFile() as caught:
        try:
            os.dup2(caught.fileno(), 1)
            yield
        finally:
            sys.stdout.flush()
            os.dup2(saved, 1)
            os.close(saved)
            caught.seek(0)
            for line in caught.read().decode(errors="replace").splitlines():
                if line.strip():
                    LOGGER.info("%s: %s", solver, line.rstrip())


def extensive_variables(data: PlacementData, failures: int) -> tuple[int, int]:
    """Blocks and variables of the extensive form."""
    blocks = len(failure_sets(data.candidates.n_mounts, failures)) * len(SIGNED_AXES)
    return blocks, data.n_candidates + 1 + blocks * (data.n_engines + 1)


def _infeasible(settings: PlacementSettings, record: MilpSolve) -> InputShapeError:
    limits = [
        name
        for name, value in (
            ("--max-added-inertia", settings.max_added_inertia_kgm2),
            ("--max-slew-s", settings.max_slew_s),
            ("--min-per-face", settings.min_per_face or None),
        )
        if value is not None
    ]
    what = " or ".join(limits) if limits else "--count"
    return InputShapeError(
        f"{what}: no layout of {settings.count[0]} to {settings.count[1]} CubeSats among the "
        f"candidates meets the limits ({record.message})"
    )


def _chosen(y: np.ndarray) -> tuple[int, ...]:
    return tuple(int(i) for i in np.flatnonzero(y > 0.5))


def _mounts(data: PlacementData, candidates: tuple[int, ...]) -> tuple[int, ...]:
    return tuple(sorted(int(data.candidate_mount[c]) for c in candidates))


def _judged(
    data: PlacementData, chosen: tuple[int, ...], failures: int
) -> tuple[float, tuple[int, ...], WorstFailures]:
    """A layout's worst authority over disturbance over its failure sets, by LP."""
    worst = worst_failures(data, chosen, failures)
    return float(np.min(worst.ratio(data.disturbance_Nm))), chosen, worst


def _new_blocks(data: PlacementData, worst: WorstFailures, blocks: list[Block]) -> list[Block]:
    """The worst failure set per axis as blocks, those not in ``blocks`` yet."""
    found = [(_mounts(data, s), a) for a, s in enumerate(worst.worst_set)]
    return [b for b in dict.fromkeys(found) if b not in blocks]


def _gap(upper: float, value: float) -> float:
    """Relative gap between the proven bound and the verified objective (0 when they meet)."""
    if upper - value <= GAP_ABSOLUTE:
        return 0.0
    return (upper - value) / upper if math.isfinite(upper) else math.inf


def _first_blocks(data: PlacementData, settings: PlacementSettings) -> tuple[list[Block], bool]:
    """Every block when the extensive form is small enough (True), else the nominal ones."""
    _, variables = extensive_variables(data, settings.failures)
    if settings.failures == 0 or variables <= settings.max_extensive_variables:
        sets = failure_sets(data.candidates.n_mounts, settings.failures)
        return [(s, a) for s in sets for a in range(len(SIGNED_AXES))], True
    LOGGER.warning(
        "the extensive form would have %d variables (more than %d): generating failure "
        "sets instead",
        variables,
        settings.max_extensive_variables,
    )
    # No failure at all is a valid relaxation: nominal authority bounds every failure's.
    return [((), a) for a in range(len(SIGNED_AXES))], False


def meets_limits(data: PlacementData, settings: PlacementSettings, chosen: tuple[int, ...]) -> bool:
    """Whether a layout satisfies the programme's constraints (count, mounts, faces, limits)."""
    mounts = data.candidate_mount[list(chosen)]
    if not settings.count[0] <= len(chosen) <= settings.count[1] or len(set(mounts)) < len(chosen):
        return False
    faces = [data.candidates.candidates[c].face for c in chosen]
    if any(faces.count(face) < settings.min_per_face for face in SIGNED_AXES):
        return False
    added = data.added_inertia_kgm2[list(chosen)].sum(axis=0)
    if settings.max_added_inertia_kgm2 is not None and np.any(
        added > np.asarray(settings.max_added_inertia_kgm2)
    ):
        return False
    if settings.max_slew_s is None:
        return True
    gain = 4.0 * math.radians(settings.slew_angle_deg) / settings.max_slew_s**2
    inertia = np.diag(data.inertia_bare_kgm2) + added
    authority = layout_authority_Nm(data, chosen).weakest_Nm
    return bool(np.all(authority >= gain * inertia))


def solve_placement(
    data: PlacementData, settings: PlacementSettings, incumbents: Sequence[tuple[int, ...]] = ()
) -> PlacementSolution:
    """Choose the CubeSats that maximise the worst authority over disturbance (see module).

    Parameters
    ----------
    data : PlacementData
    settings : PlacementSettings
    incumbents : sequence of tuple of int
        Known layouts (candidates, 0-based), e.g. the input problem's own: each
        that meets the limits is a lower bound from the start, and its worst
        failure sets seed the generated form. The answer is never worse than them.

    Returns
    -------
    PlacementSolution
        With its proven upper bound and gap; ``optimal`` is False when a time or
        round limit stopped the search.

    Raises
    ------
    InputShapeError
        When no layout meets the count and limits.
    """
    lo, hi = settings.count
    if not 1 <= lo <= hi <= data.candidates.n_mounts:
        raise InputShapeError(
            f"--count: between 1 and the {data.candidates.n_mounts} mounts; got {lo}..{hi}"
        )
    began = time.perf_counter()
    blocks, extensive = _first_blocks(data, settings)
    solves: list[MilpSolve] = []
    best: tuple[float, tuple[int, ...], WorstFailures] | None = None
    upper = math.inf
    for known in (tuple(sorted(k)) for k in incumbents if meets_limits(data, settings, k)):
        judged = _judged(data, known, settings.failures)
        best = judged if best is None or judged[0] > best[0] else best
        if not extensive:
            blocks += _new_blocks(data, judged[2], blocks)
    for _ in range(1 if extensive else settings.max_rounds):
        remaining = settings.time_limit_s - (time.perf_counter() - began)
        if not extensive:  # leave time for later rounds, whose relaxations are tighter
            remaining = max(remaining / ROUND_SHARE, min(remaining, MIN_ROUND_S))
        record, y = solve_blocks(data, blocks, settings, remaining)
        solves.append(record)
        if record.status == 2:
            raise _infeasible(settings, record)
        if record.upper_bound is not None:
            upper = min(upper, record.upper_bound)
        if y is None:
            break
        judged = _judged(data, _chosen(y), settings.failures)
        best = judged if best is None or judged[0] > best[0] else best
        if extensive or upper - best[0] <= settings.mip_rel_gap * abs(upper) + GAP_ABSOLUTE:
            break
        new = _new_blocks(data, judged[2], blocks)
        if not new or time.perf_counter() - began >= settings.time_limit_s:
            break
        blocks = blocks + new
    if best is None:
        raise InputShapeError(f"placement: HiGHS found no layout ({solves[-1].message})")
    value, chosen, worst = best
    gap = _gap(upper, value)
    optimal = solves[-1].status == 0 and gap <= settings.mip_rel_gap + GAP_ABSOLUTE
    return PlacementSolution(
        chosen=chosen,
        objective=value,
        upper_bound=upper,
        gap=gap,
        optimal=optimal,
        method="extensive" if extensive else "generated",
        blocks_total=extensive_variables(data, settings.failures)[0],
        blocks_used=solves[-1].blocks,
        worst=worst,
        solves=tuple(solves),
        time_s=time.perf_counter() - began,
    )
