"""Thruster-level allocation, staged engines and fuel tracking.

- :class:`Allocator`: torque (and force) demand -> thrust of every CubeSat
  engine; exact and least fuel when reachable, direction-preserving
  saturation (or least squares) when not; set up once, solved per call.
- :class:`PropulsionState`: propellant, firing time, active stage and
  failures per CubeSat and stage; advances with the applied thrust.
- :meth:`Allocator.allocate_series`: a whole history of demands at once
  (saturation by the facets of :func:`authority_polytope`, least fuel by
  reusing active sets).
- :class:`PseudoInverseAllocator`: the clipped pseudo-inverse, for comparison only.
- :class:`DemandError`: a demand refused (not finite, absurd, wrong shape), by name.
- :func:`available_solvers`: the QP back-ends that can be named.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.allocation import Allocator, PropulsionState
>>> problem = load_problem()
>>> state = PropulsionState.from_problem(problem)
>>> allocator = Allocator.from_problem(problem, state=state)
>>> result = allocator.allocate([0.0, 0.0, 2e-3])
>>> events = state.advance(result.thrust_N, 60.0)
"""

from casadi_debris.allocation._allocator import (
    DEFAULT_SOLVER,
    SATURATION_MODES,
    Allocator,
    NoEngineError,
)
from casadi_debris.allocation._authority import AuthorityPolytope, authority_polytope
from casadi_debris.allocation._backends import QpSolution, UnknownSolverError, available_solvers
from casadi_debris.allocation._baseline import PseudoInverseAllocator
from casadi_debris.allocation._demand import ABSURD_FACTOR, DemandError
from casadi_debris.allocation._paths import AllocationInternalError, SaturationMode
from casadi_debris.allocation._propulsion import PropulsionState, StageEvent
from casadi_debris.allocation._results import Allocation, BatchAllocation, SeriesAllocation

__all__ = [
    "ABSURD_FACTOR",
    "DEFAULT_SOLVER",
    "SATURATION_MODES",
    "Allocation",
    "AllocationInternalError",
    "Allocator",
    "AuthorityPolytope",
    "BatchAllocation",
    "DemandError",
    "NoEngineError",
    "PropulsionState",
    "PseudoInverseAllocator",
    "QpSolution",
    "SaturationMode",
    "SeriesAllocation",
    "StageEvent",
    "UnknownSolverError",
    "authority_polytope",
    "available_solvers",
]
