"""The mission's propellant books: engine by engine, stage by stage, phase after phase.

Each phase hands the books what each engine burnt; the books draw it from the engine's
stages in order (a stage is used up before the next one starts, as the staging of
:class:`~casadi_debris.allocation.PropulsionState` fires them) and report, per CubeSat,
what the phase burnt from each of its stages and which stages it has begun by the
phase's end. An engine cannot burn more than it carries: a phase that asks for more is
an error naming the engine, never a negative tank.

The detumble's run reports propellant per CubeSat; with one engine per CubeSat that is
each engine's. With several, the run's torques are replayed through the same allocator
and staging to split it among the engines (:func:`detumble_engine_kg`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from casadi_debris.allocation import Allocator, PropulsionState
from casadi_debris.config import Problem
from casadi_debris.errors import AllocationError
from casadi_debris.records import Record
from casadi_debris.simulation.detumble import DetumbleRunResult

LOGGER = logging.getLogger(__name__)
STARTED_KG = 1e-12
"""A stage that has burnt more than this has begun [kg]."""
OVERDRAW_RTOL = 1e-9


@dataclass(frozen=True)
class PhaseBook(Record):
    """What one phase burnt, CubeSat by CubeSat and stage by stage (CubeSat ``k + 1`` at
    index ``k``, stage ``s + 1`` at index ``s``).

    Attributes
    ----------
    phase : str
    propellant_kg : float
        The whole swarm's, in this phase.
    per_cubesat_kg : list of float
        Burnt in this phase.
    per_stage_kg : list of list of float
        Burnt in this phase from each stage (summed over the CubeSat's engines).
    stages_started : list of list of int
        1-based ids of the stages each CubeSat has begun by the end of this phase.
    left_per_cubesat_kg : list of float
        What each CubeSat still carries at the end of this phase.
    """

    phase: str
    propellant_kg: float
    per_cubesat_kg: list[float]
    per_stage_kg: list[list[float]]
    stages_started: list[list[int]]
    left_per_cubesat_kg: list[float]


@dataclass(eq=False)
class PropellantBooks:
    """Every engine's stages, full at first, drawn from phase after phase.

    Attributes
    ----------
    capacity_kg : ndarray, shape (n_engines, n_stages)
        A full stage's propellant (0 for stages an engine does not have).
    used_kg : ndarray, shape (n_engines, n_stages)
        Burnt so far.
    exhaust_m_s : ndarray, shape (n_engines,)
        Isp g0 of each engine.
    engine_cubesat : ndarray of int, shape (n_engines,)
        0-based CubeSat of each engine.
    """

    capacity_kg: np.ndarray
    used_kg: np.ndarray
    exhaust_m_s: np.ndarray
    engine_cubesat: np.ndarray

    @classmethod
    def from_problem(cls, problem: Problem) -> PropellantBooks:
        """Full tanks, with the stage loads the staging model uses."""
        state = PropulsionState.from_problem(problem)
        capacity = np.array(state.stage_capacity_kg, dtype=float)
        return cls(
            capacity_kg=capacity,
            used_kg=np.zeros_like(capacity),
            exhaust_m_s=np.array(state.exhaust_velocity_m_s, dtype=float),
            engine_cubesat=np.array(state.engine_cubesat, dtype=int),
        )

    @property
    def n_cubesats(self) -> int:
        return int(self.engine_cubesat.max()) + 1

    def left_kg(self) -> np.ndarray:
        """What each engine still carries, shape (n_engines,) [kg]."""
        return np.asarray((self.capacity_kg - self.used_kg).sum(axis=1))

    def left_impulse_Ns(self) -> np.ndarray:
        """The impulse of what each engine still carries, shape (n_engines,) [N s]."""
        return self.left_kg() * self.exhaust_m_s

    def per_cubesat(self, engine_values: np.ndarray) -> np.ndarray:
        """Sums over each CubeSat's engines, shape (n_cubesats, ...) from (n_engines, ...)."""
        values = np.asarray(engine_values, dtype=float)
        out = np.zeros((self.n_cubesats, *values.shape[1:]))
        np.add.at(out, self.engine_cubesat, values)
        return out

    def burn(self, phase: str, engine_kg: np.ndarray) -> PhaseBook:
        """Draw ``engine_kg`` (shape (n_engines,), kg) from each engine's stages in order.

        Raises
        ------
        AllocationError
            An engine asked for more than it carries (named, 1-based).
        """
        engine_kg = np.asarray(engine_kg, dtype=float)
        left = self.left_kg()
        over = np.flatnonzero(engine_kg > left * (1.0 + OVERDRAW_RTOL) + STARTED_KG)
        if over.size:
            i = int(over[0])
            raise AllocationError(
                f"{phase}: engine {i + 1} (CubeSat {self.engine_cubesat[i] + 1}) needs "
                f"{engine_kg[i] * 1e3:.2f} g but carries {left[i] * 1e3:.2f} g"
            )
        drawn = np.zeros_like(self.used_kg)
        need = np.clip(engine_kg, 0.0, None)
        for stage in range(self.capacity_kg.shape[1]):
            room = self.capacity_kg[:, stage] - self.used_kg[:, stage]
            drawn[:, stage] = np.minimum(need, room)
            need = need - drawn[:, stage]
        self.used_kg += drawn
        started = self.per_cubesat(self.used_kg) > STARTED_KG
        return PhaseBook(
            phase=phase,
            propellant_kg=float(drawn.sum()),
            per_cubesat_kg=self.per_cubesat(drawn.sum(axis=1)).tolist(),
            per_stage_kg=self.per_cubesat(drawn).tolist(),
            stages_started=[(np.flatnonzero(row) + 1).tolist() for row in started],
            left_per_cubesat_kg=self.per_cubesat(self.left_kg()).tolist(),
        )


def detumble_engine_kg(problem: Problem, run: DetumbleRunResult) -> np.ndarray:
    """Propellant each engine burnt in the detumble ``run``, shape (n_engines,) [kg].

    One engine per CubeSat: the run's per-CubeSat figures. Otherwise the run's torques
    are replayed, period by period, through the allocator and the staging the run used
    (re-planned after every change of an engine's thrust limit, as the run does); the
    replay's per-CubeSat sums are checked against the run's.
    """
    engine_cubesat = np.asarray(problem.engine_cubesats, dtype=int)
    per_cubesat = np.asarray(run.summary.fuel_per_cubesat_kg, dtype=float)
    if len(engine_cubesat) == len(per_cubesat):
        return np.asarray(per_cubesat[engine_cubesat])
    allocator = Allocator.from_problem(problem)
    state = PropulsionState.from_problem(problem)
    torque, period = np.asarray(run.torque_Nm), run.summary.control_period_s
    done = 0
    while done < len(torque):
        allocator.update_from_state(state)
        thrust = allocator.allocate_series(torque[done:]).thrust_N
        steps, _ = state.advance_series(thrust, period)
        done += steps
    engine_kg = np.asarray((state.stage_capacity_kg - state.propellant_kg).sum(axis=1))
    replayed = np.bincount(engine_cubesat, weights=engine_kg, minlength=len(per_cubesat))
    if not np.allclose(replayed, per_cubesat, rtol=1e-6, atol=1e-9):
        LOGGER.warning(
            "the detumble's replay burns %.6f kg against the run's %.6f kg: "
            "the split among engines is approximate",
            replayed.sum(),
            per_cubesat.sum(),
        )
    return engine_kg
