"""Staged iESE engines: propellant, firing time, active stage and failures per engine.

Each engine carries its own electrospray stages, fired one after the other
(paper, Section II.D). A stage holds the propellant it burns in its rated life
at full thrust,

    m_stage = F_stage * t_life / (Isp * g0),

and burns ``F / (Isp g0)`` kilograms per second at thrust ``F``. When the
active stage runs dry the next healthy stage takes over (within the same
time step, at the instant of depletion); when every stage of an engine is
spent or failed, the engine drops out of the allocation (limit 0).

Engines belong to CubeSats (the paper's have one each). Failures are
scheduled per CubeSat: a failed CubeSat takes all its engines out, a failed
stage that stage of each of its engines, a failed engine that engine alone
(the CubeSat's other engines keep firing). Engines with fewer stages
than the most of any have stages of zero capacity in the remaining columns,
which never fire.

A commanded thrust is assumed to be held through a stage switch, limited
to the thrust of the stage that takes over.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
import numpy.typing as npt

from casadi_debris.allocation._state_input import (
    checked_id,
    checked_pair,
    engine_stage_matrix,
    listed,
    per_engine,
    per_stage,
)
from casadi_debris.config import Problem
from casadi_debris.errors import AllocationError, InputShapeError
from casadi_debris.units import MN_PER_N

# Propellant below this fraction of a stage's load counts as spent: it avoids
# a stage that lingers on a rounding residue for one more step.
DEPLETED_FRACTION = 1e-12
# A commanded thrust may exceed its limit by this relative margin (solver round-off).
THRUST_LIMIT_RTOL = 1e-9

FloatArray = npt.NDArray[np.float64]
BoolArray = npt.NDArray[np.bool_]
IntArray = npt.NDArray[np.int_]


@dataclass(frozen=True)
class StageEvent:
    """A stage of one engine ran dry during :meth:`PropulsionState.advance`.

    Attributes
    ----------
    engine : int
        0-based.
    cubesat : int
        Its CubeSat, 0-based.
    stage : int
        The stage that was depleted (0-based).
    time_s : float
        When, from the start of the step [s].
    next_stage : int or None
        The stage that took over; None when the engine has none left.
    """

    engine: int
    cubesat: int
    stage: int
    time_s: float
    next_stage: int | None


@dataclass(eq=False, init=False)
class PropulsionState:
    """Propellant, firing time and failures of every engine's stages.

    Attributes
    ----------
    stage_thrust_N : ndarray, shape (n_engines, n_stages)
        Full thrust of each stage [N].
    exhaust_velocity_m_s : ndarray, shape (n_engines,)
        Isp g0 of each engine [m/s]; mass flow is thrust / exhaust velocity.
    stage_capacity_kg : ndarray, shape (n_engines, n_stages)
        Propellant of a full stage [kg] (0 for stages an engine does not have).
    propellant_kg : ndarray, shape (n_engines, n_stages)
        Propellant left [kg].
    firing_time_s : ndarray, shape (n_engines, n_stages)
        Time each stage has fired with non-zero thrust [s].
    engine_cubesat : ndarray of int, shape (n_engines,)
        The CubeSat (0-based) each engine belongs to.
    failed_cubesats : ndarray of bool, shape (n_cubesats,)
    failed_stages : ndarray of bool, shape (n_cubesats, n_stages)
    failed_engines : ndarray of bool, shape (n_engines,)

    Example
    -------
    >>> from casadi_debris import load_problem
    >>> state = PropulsionState.from_problem(load_problem())
    >>> state.active_stage[:3]
    array([0, 0, 0])
    """

    stage_thrust_N: FloatArray
    exhaust_velocity_m_s: FloatArray
    stage_capacity_kg: FloatArray
    propellant_kg: FloatArray
    firing_time_s: FloatArray
    engine_cubesat: IntArray
    failed_cubesats: BoolArray
    failed_stages: BoolArray
    failed_engines: BoolArray

    # Written out, not generated: the optional arguments default to one engine per
    # CubeSat, no firing time and no failures, while the attributes are always arrays.
    def __init__(
        self,
        stage_thrust_N: npt.ArrayLike,
        exhaust_velocity_m_s: npt.ArrayLike,
        stage_capacity_kg: npt.ArrayLike,
        propellant_kg: npt.ArrayLike,
        *,
        firing_time_s: npt.ArrayLike | None = None,
        failed_cubesats: npt.ArrayLike | None = None,
        failed_stages: npt.ArrayLike | None = None,
        engine_cubesat: npt.ArrayLike | None = None,
        failed_engines: npt.ArrayLike | None = None,
    ) -> None:
        self.propellant_kg = engine_stage_matrix(propellant_kg, "propellant_kg", None)
        n_engines, n_stages = self.propellant_kg.shape
        shape = (n_engines, n_stages)
        self.stage_thrust_N = per_stage(stage_thrust_N, "stage_thrust_N", shape)
        self.stage_capacity_kg = per_stage(stage_capacity_kg, "stage_capacity_kg", shape)
        self.exhaust_velocity_m_s = per_engine(exhaust_velocity_m_s, n_engines)
        if firing_time_s is None:
            firing_time_s = np.zeros(shape)
        self.firing_time_s = engine_stage_matrix(
            firing_time_s, "firing_time_s", n_stages, n_engines
        )
        self.engine_cubesat = (
            np.arange(n_engines) if engine_cubesat is None else np.array(engine_cubesat, dtype=int)
        )
        n_cubesats = int(self.engine_cubesat.max()) + 1 if n_engines else 0
        if failed_cubesats is None:
            failed_cubesats = np.zeros(n_cubesats, dtype=bool)
        if failed_stages is None:
            failed_stages = np.zeros((n_cubesats, n_stages), dtype=bool)
        self.failed_cubesats = np.array(failed_cubesats, dtype=bool)
        self.failed_stages = np.array(failed_stages, dtype=bool)
        self.failed_engines = np.array(
            np.zeros(n_engines, dtype=bool) if failed_engines is None else failed_engines,
            dtype=bool,
        )
        self._check()

    def _check(self) -> None:
        """Shapes agree, values in range (after construction, and after an update)."""
        n_engines, n_stages = self.propellant_kg.shape
        if self.engine_cubesat.shape != (n_engines,) or (
            n_engines
            and not np.array_equal(np.unique(self.engine_cubesat), np.arange(self.n_cubesats))
        ):
            raise InputShapeError(
                f"engine_cubesat must give each of the {n_engines} engines a CubeSat, "
                "numbering the CubeSats 0, 1, ... without gaps"
            )
        n_cubesats = self.n_cubesats
        if self.failed_cubesats.shape != (n_cubesats,):
            raise InputShapeError(
                f"failed_cubesats must have shape ({n_cubesats},), got {self.failed_cubesats.shape}"
            )
        if self.failed_stages.shape != (n_cubesats, n_stages):
            raise InputShapeError(
                f"failed_stages must have shape ({n_cubesats}, {n_stages}), "
                f"got {self.failed_stages.shape}"
            )
        if self.failed_engines.shape != (n_engines,):
            raise InputShapeError(
                f"failed_engines must have shape ({n_engines},), got {self.failed_engines.shape}"
            )
        if not np.all(np.isfinite(self.exhaust_velocity_m_s)) or np.any(
            self.exhaust_velocity_m_s <= 0
        ):
            raise AllocationError(
                f"exhaust_velocity_m_s must be positive, got {self.exhaust_velocity_m_s}"
            )
        for name, values in (
            ("stage_thrust_N", self.stage_thrust_N),
            ("stage_capacity_kg", self.stage_capacity_kg),
            ("propellant_kg", self.propellant_kg),
            ("firing_time_s", self.firing_time_s),
        ):
            if np.any(values < 0):
                raise AllocationError(f"{name} must not be negative")
        if np.any(self.propellant_kg > self.stage_capacity_kg * (1.0 + THRUST_LIMIT_RTOL)):
            raise AllocationError("propellant_kg exceeds the capacity of a stage")

    # ------------------------------------------------------------------ construction

    @classmethod
    def from_problem(cls, problem: Problem) -> PropulsionState:
        """Every engine of the problem with full, healthy stages.

        Parameters
        ----------
        problem : Problem
            Engine data (stages, thrust per stage, Isp, stage life per engine) and g0.
        """
        engines = problem.engines
        g0 = problem.constants.standard_gravity_m_s2
        n_stages = max(engine.stages for engine in engines)
        thrust = np.zeros((len(engines), n_stages))
        capacity = np.zeros((len(engines), n_stages))
        for row, engine in enumerate(engines):
            thrust_N = engine.thrust_per_stage_mN / MN_PER_N
            thrust[row, : engine.stages] = thrust_N
            capacity[row, : engine.stages] = engine.stage_propellant_kg(g0)
        # Stages an engine lacks have no thrust either: give them the first stage's, so
        # that limits stay finite; with no propellant they never fire.
        thrust = np.where(capacity > 0, thrust, thrust[:, :1])
        return cls(
            stage_thrust_N=thrust,
            exhaust_velocity_m_s=np.array([engine.isp_s * g0 for engine in engines]),
            stage_capacity_kg=capacity,
            propellant_kg=capacity.copy(),
            engine_cubesat=problem.engine_cubesats,
        )

    def copy(self) -> PropulsionState:
        """An independent copy."""
        return PropulsionState(
            self.stage_thrust_N.copy(),
            self.exhaust_velocity_m_s.copy(),
            self.stage_capacity_kg.copy(),
            self.propellant_kg.copy(),
            firing_time_s=self.firing_time_s.copy(),
            failed_cubesats=self.failed_cubesats.copy(),
            failed_stages=self.failed_stages.copy(),
            engine_cubesat=self.engine_cubesat.copy(),
            failed_engines=self.failed_engines.copy(),
        )

    # ------------------------------------------------------------------ queries

    @property
    def n_engines(self) -> int:
        """Number of engines (rows)."""
        return len(self.propellant_kg)

    @property
    def n_cubesats(self) -> int:
        """Number of CubeSats."""
        return int(self.engine_cubesat.max()) + 1 if len(self.engine_cubesat) else 0

    @property
    def n_stages(self) -> int:
        """Stages of the engine with the most (columns)."""
        return int(self.propellant_kg.shape[1])

    def _usable(self) -> BoolArray:
        """Stages that can still fire, shape (n_engines, n_stages)."""
        owner = self.engine_cubesat
        usable: BoolArray = (
            (self.propellant_kg > DEPLETED_FRACTION * self.stage_capacity_kg)
            & ~self.failed_stages[owner]
            & ~self.failed_cubesats[owner][:, None]
            & ~self.failed_engines[:, None]
        )
        return usable

    @property
    def active_stage(self) -> np.ndarray:
        """Index of the stage each engine fires now, ``n_stages`` when none is left, shape (n,)."""
        usable = self._usable()
        return np.where(usable.any(axis=1), np.argmax(usable, axis=1), self.n_stages)

    @property
    def available(self) -> np.ndarray:
        """Engines that can fire, bool, shape (n_engines,)."""
        return np.asarray(self._usable().any(axis=1))

    def max_thrust_N(self) -> np.ndarray:
        """Thrust limit of each engine's active stage (0 when it has none), shape (n,) [N]."""
        active = self.active_stage
        limits = np.zeros(self.n_engines)
        firing = np.flatnonzero(active < self.n_stages)
        limits[firing] = self.stage_thrust_N[firing, active[firing]]
        return limits

    @property
    def fuel_used_kg(self) -> np.ndarray:
        """Propellant burnt per engine and stage, shape (n_engines, n_stages) [kg]."""
        return self.stage_capacity_kg - self.propellant_kg

    def per_cubesat(self, values: np.ndarray) -> np.ndarray:
        """Sum per-engine values (first axis, or the last for a series) over each CubeSat's engines.

        Parameters
        ----------
        values : ndarray, shape (n_engines, ...) or (k, n_engines)
            ``(k, n_engines)`` is taken as a series (engines along the last axis)
            when its first axis is not the engines'.

        Returns
        -------
        ndarray, shape (n_cubesats, ...) or (k, n_cubesats)
        """
        values = np.asarray(values, dtype=float)
        if values.shape[0] == self.n_engines:
            summed = np.zeros((self.n_cubesats, *values.shape[1:]))
            np.add.at(summed, self.engine_cubesat, values)
            return summed
        summed = np.zeros((*values.shape[:-1], self.n_cubesats))
        for engine, cubesat in enumerate(self.engine_cubesat):
            summed[..., cubesat] += values[..., engine]
        return summed

    def remaining_life_s(self) -> np.ndarray:
        """Full-thrust firing time left in each engine's usable stages, shape (n,) [s]."""
        mass_flow = self.stage_thrust_N / self.exhaust_velocity_m_s[:, None]
        return np.sum(np.where(self._usable(), self.propellant_kg / mass_flow, 0.0), axis=1)

    # ------------------------------------------------------------------ changes

    def fail_cubesat(self, cubesat: int) -> None:
        """Take a whole CubeSat out (all its engines and stages); ``cubesat`` 0-based."""
        self._check_index(cubesat)
        self.failed_cubesats[cubesat] = True

    def fail_stage(self, cubesat: int, stage: int) -> None:
        """Take one stage of each of a CubeSat's engines out; the next healthy stage takes over."""
        self._check_index(cubesat)
        if not 0 <= stage < self.n_stages:
            raise AllocationError(f"stage {stage} out of range 0..{self.n_stages - 1}")
        self.failed_stages[cubesat, stage] = True

    def engine_index(self, cubesat: int, engine: int) -> int:
        """Row of a CubeSat's ``engine``-th engine (both 0-based), in the order the problem
        lists them."""
        self._check_index(cubesat)
        rows = np.flatnonzero(self.engine_cubesat == cubesat)
        if not 0 <= engine < len(rows):
            raise AllocationError(
                f"CubeSat {cubesat + 1} has engines 1..{len(rows)}, got engine {engine + 1}"
            )
        return int(rows[engine])

    def fail_engine(self, cubesat: int, engine: int) -> None:
        """Take one engine of a CubeSat out (0-based, its ``engine``-th); the others fire on."""
        self.failed_engines[self.engine_index(cubesat, engine)] = True

    def _check_index(self, cubesat: int) -> None:
        if not 0 <= cubesat < self.n_cubesats:
            raise AllocationError(f"CubeSat {cubesat} out of range 0..{self.n_cubesats - 1}")

    def advance(self, thrust_N: np.ndarray, dt_s: float) -> list[StageEvent]:
        """Fire every engine's active stage at the given thrust for ``dt_s``.

        Parameters
        ----------
        thrust_N : array_like, shape (n_engines,)
            Thrust held over the step [N]; within each active stage's limit,
            zero for engines that cannot fire.
        dt_s : float
            Step length [s], non-negative.

        Returns
        -------
        list of StageEvent
            Stages that ran dry during the step, in time order per engine.

        Raises
        ------
        InputShapeError
            Wrong shape, NaN or infinite values.
        AllocationError
            Negative thrust or step, thrust above a limit, or thrust asked
            of an engine that cannot fire.
        """
        thrust = self._checked_thrust(thrust_N, dt_s, series=False)
        limits = self.max_thrust_N()
        over = thrust > limits * (1.0 + THRUST_LIMIT_RTOL)
        if np.any(over):
            worst = int(np.argmax(np.where(over, thrust - limits, -np.inf)))
            raise AllocationError(
                f"engine {worst + 1}: thrust {thrust[worst] * MN_PER_N:.6g} mN above its active "
                f"stage limit {limits[worst] * MN_PER_N:.6g} mN"
            )
        thrust = np.minimum(thrust, limits)
        events: list[StageEvent] = []
        for engine in np.flatnonzero(thrust > 0):
            events.extend(self._burn(int(engine), float(thrust[engine]), float(dt_s)))
        return events

    def _checked_thrust(self, thrust_N: Any, dt_s: float, *, series: bool) -> np.ndarray:
        """Thrust as an array of shape (n,) or (k, n), finite and non-negative, like dt_s."""
        thrust = np.asarray(thrust_N, dtype=float)
        n = self.n_engines
        if series:
            good, want = thrust.ndim == 2 and thrust.shape[1] == n, f"(k, {n})"
        else:
            good, want = thrust.shape == (n,), f"({n},)"
        if not good:
            raise InputShapeError(f"thrust_N must have shape {want}, got {thrust.shape}")
        if not np.all(np.isfinite(thrust)) or not np.isfinite(dt_s):
            raise InputShapeError("thrust_N and dt_s must be finite")
        if dt_s < 0 or np.any(thrust < 0):
            raise AllocationError("thrust_N and dt_s must not be negative")
        return thrust

    def advance_series(
        self, thrust_N: np.ndarray, dt_s: float, *, stop_on_limit_change: bool = True
    ) -> tuple[int, list[tuple[int, StageEvent]]]:
        """Fire a history of thrusts, each held for ``dt_s``, as :meth:`advance` would step by step.

        Steps in which no stage runs dry are applied all at once (sums per
        engine); a step in which one does goes through :meth:`advance`.

        Parameters
        ----------
        thrust_N : ndarray, shape (k, n_engines)
            Thrust of every engine in each step [N].
        dt_s : float
            Step length [s].
        stop_on_limit_change : bool
            Stop after the first step that changes an engine's thrust limit
            (an engine spent, or a stage of other thrust taking over): the
            thrust after it was planned with the old limits.

        Returns
        -------
        steps_done : int
            Steps applied (``k`` unless stopped early).
        events : list of (int, StageEvent)
            Step index and event, in order.
        """
        thrust = self._checked_thrust(thrust_N, dt_s, series=True)
        events: list[tuple[int, StageEvent]] = []
        done = 0
        while done < len(thrust):
            rest = thrust[done:]
            usable = self._usable()
            active = self.active_stage
            # What an active stage can burn before :meth:`_burn` calls it spent.
            left = np.array(
                [
                    self.propellant_kg[i, a] - DEPLETED_FRACTION * self.stage_capacity_kg[i, a]
                    if a < self.n_stages and usable[i, a]
                    else np.inf
                    for i, a in enumerate(active)
                ]
            )
            burnt = np.cumsum(rest, axis=0) * (dt_s / self.exhaust_velocity_m_s)
            dry = burnt >= left
            first = int(np.argmax(dry.any(axis=1))) if dry.any() else len(rest)
            if first > 0:
                self.advance_sum(rest[:first], dt_s)
                done += first
            if first == len(rest):
                break
            limits = self.max_thrust_N()
            events.extend((done, event) for event in self.advance(rest[first], dt_s))
            done += 1
            if stop_on_limit_change and not np.array_equal(limits, self.max_thrust_N()):
                break
        return done, events

    def advance_sum(self, thrust_N: np.ndarray, dt_s: float) -> None:
        """Fire steps in which no stage runs dry: propellant and firing time summed per engine."""
        limits = self.max_thrust_N()
        if np.any(thrust_N > limits * (1.0 + THRUST_LIMIT_RTOL)) or np.any(thrust_N < 0):
            worst = np.unravel_index(np.argmax(thrust_N - limits), thrust_N.shape)
            raise AllocationError(
                f"engine {worst[1] + 1}: thrust {thrust_N[worst] * MN_PER_N:.6g} mN outside "
                f"0 .. {limits[worst[1]] * MN_PER_N:.6g} mN"
            )
        active = self.active_stage
        firing = active < self.n_stages
        rows = np.flatnonzero(firing)
        self.propellant_kg[rows, active[rows]] -= (
            np.minimum(thrust_N, limits).sum(axis=0)[rows] * dt_s / self.exhaust_velocity_m_s[rows]
        )
        self.firing_time_s[rows, active[rows]] += (thrust_N[:, rows] > 0).sum(axis=0) * dt_s

    def _burn(self, engine: int, thrust_N: float, dt_s: float) -> list[StageEvent]:
        """Burn one engine's stages in order for ``dt_s``, switching at depletion."""
        events = []
        elapsed = 0.0
        stage = int(self.active_stage[engine])
        exhaust = float(self.exhaust_velocity_m_s[engine])
        while elapsed < dt_s and stage < self.n_stages:
            mass_flow = min(thrust_N, float(self.stage_thrust_N[engine, stage])) / exhaust
            left = float(self.propellant_kg[engine, stage])
            burn_s = min(dt_s - elapsed, left / mass_flow)
            self.propellant_kg[engine, stage] = left - mass_flow * burn_s
            self.firing_time_s[engine, stage] += burn_s
            elapsed += burn_s
            if self.propellant_kg[engine, stage] > DEPLETED_FRACTION * float(
                self.stage_capacity_kg[engine, stage]
            ):
                break
            self.propellant_kg[engine, stage] = 0.0
            next_stage = int(self.active_stage[engine])
            taken_over = next_stage if next_stage < self.n_stages else None
            cubesat = int(self.engine_cubesat[engine])
            events.append(StageEvent(engine, cubesat, stage, elapsed, taken_over))
            stage = next_stage
        return events

    # ------------------------------------------------------------------ serialisation

    def to_dict(self) -> dict[str, Any]:
        """Plain data (lists) for JSON, SI units in the key names.

        As everything a user reads, CubeSats and stages are numbered from 1:
        ``failed_cubesats`` lists CubeSat ids, ``failed_stages`` [CubeSat, stage]
        pairs, ``failed_engines`` [CubeSat, engine of that CubeSat] pairs; the rows of
        ``propellant_kg`` and ``firing_time_s`` are engines 1..n (one per CubeSat in
        the paper's swarm) and their columns stages 1..m.
        """
        return {
            "propellant_kg": self.propellant_kg.tolist(),
            "firing_time_s": self.firing_time_s.tolist(),
            "failed_cubesats": (np.flatnonzero(self.failed_cubesats) + 1).tolist(),
            "failed_stages": [[int(c) + 1, int(s) + 1] for c, s in np.argwhere(self.failed_stages)],
            "failed_engines": [
                [int(c) + 1, int(np.sum(self.engine_cubesat[:row] == c)) + 1]
                for row, c in enumerate(self.engine_cubesat)
                if self.failed_engines[row]
            ],
        }

    def updated_from_dict(self, data: dict[str, Any]) -> PropulsionState:
        """A copy with the entries present in ``data`` (as :meth:`to_dict` writes) replaced.

        CubeSat and stage ids in ``data`` are 1-based, as :meth:`to_dict` writes them.

        Raises
        ------
        AllocationError
            Unknown keys, indices out of range, values out of range.
        InputShapeError
            Arrays of the wrong shape or non-finite.
        """
        known = {
            "propellant_kg",
            "firing_time_s",
            "failed_cubesats",
            "failed_stages",
            "failed_engines",
        }
        if not isinstance(data, dict):
            raise AllocationError("a propulsion state must be a JSON object")
        unknown = sorted(set(data) - known)
        if unknown:
            raise AllocationError(
                f"unknown propulsion state key {unknown[0]!r}; known: {', '.join(sorted(known))}"
            )
        state = self.copy()
        for key in ("propellant_kg", "firing_time_s"):
            if key in data:
                values = engine_stage_matrix(data[key], key, self.n_stages, self.n_engines)
                setattr(state, key, values)
        for cubesat in listed(data, "failed_cubesats", "CubeSat ids"):
            state.fail_cubesat(checked_id(cubesat, "failed_cubesats", "CubeSat", self.n_cubesats))
        cubesats = ("CubeSat", self.n_cubesats)
        for pair in listed(data, "failed_stages", "[cubesat, stage] pairs"):
            state.fail_stage(
                *checked_pair(pair, "failed_stages", cubesats, ("stage", self.n_stages))
            )
        for pair in listed(data, "failed_engines", "[cubesat, engine] pairs"):
            # The pair's form first, then the engine against its own CubeSat's count.
            cubesat, _ = checked_pair(pair, "failed_engines", cubesats, ("engine", self.n_engines))
            count = int(np.sum(self.engine_cubesat == cubesat))
            state.fail_engine(cubesat, checked_id(pair[1], "failed_engines", "engine", count))
        state._check()
        return state
