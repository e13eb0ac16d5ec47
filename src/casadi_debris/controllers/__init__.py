"""Controllers that decide the engines' thrust in the loop: nonlinear MPC.

- :class:`NmpcController`: thruster-level nonlinear MPC on the toolkit's CasADi model
  (rigid or flexible prediction), real-time iteration or full solves.
- :class:`NmpcSettings`: horizon, period, weights, terminal treatment and solver.
- :class:`NmpcEngines`: the engines as decision variables (maps, limits, Isp).
- :class:`NmpcReference`, :class:`NmpcStep`, :class:`NmpcScales`: what it follows,
  what one period gives, and the units of its scaled problem.

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.dynamics import build_model
>>> from casadi_debris.controllers import NmpcController, NmpcSettings
>>> controller = NmpcController(build_model(load_problem(), modes=()), NmpcSettings())
>>> step = controller.step(0.0, controller.model.initial_state(), [1.0, 0.0, 0.0, 0.0])
>>> bool(step.success)
True
"""

from casadi_debris.controllers._engines import NmpcEngines
from casadi_debris.controllers._nmpc import NmpcController, NmpcReference, NmpcScales, NmpcStep
from casadi_debris.controllers._settings import (
    FULL_SOLVERS,
    QP_SOLVERS,
    NmpcSettings,
)

__all__ = [
    "FULL_SOLVERS",
    "QP_SOLVERS",
    "NmpcController",
    "NmpcEngines",
    "NmpcReference",
    "NmpcScales",
    "NmpcSettings",
    "NmpcStep",
]
