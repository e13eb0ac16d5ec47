"""Closed-loop simulation: the nonlinear model, star tracker, robust controller,
allocator and engines together; Monte Carlo over the uncertainty set.

- :func:`simulate`: one scenario (:class:`ClosedLoopResult`).
- :func:`open_loop_rigid`: the rigid body under a held torque table.
- :func:`sample_reference`, :func:`generate_slew`: what the loop follows.
"""

from casadi_debris.simulation.closed_loop import (
    SimulationError,
    build_loop_step,
    discretize_controller,
)
from casadi_debris.simulation.open_loop import OpenLoopResult, open_loop_rigid
from casadi_debris.simulation.reference import Reference, generate_slew, sample_reference
from casadi_debris.simulation.run import ClosedLoopResult, simulate

__all__ = [
    "ClosedLoopResult",
    "OpenLoopResult",
    "Reference",
    "SimulationError",
    "build_loop_step",
    "discretize_controller",
    "generate_slew",
    "open_loop_rigid",
    "sample_reference",
    "simulate",
]
