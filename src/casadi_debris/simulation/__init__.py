"""Closed-loop simulation: the nonlinear model, star tracker, robust controller,
allocator and engines together; Monte Carlo over the uncertainty set.

- :func:`simulate`: one scenario (:class:`ClosedLoopResult`); :func:`simulate_many`:
  several, with ``jit`` as one compiled function mapped over them.
- :func:`run_campaign`: Monte Carlo over :func:`corner_cases` / :func:`sample_cases`
  on processes or Dask, with an :class:`Envelope`.
- :func:`open_loop_rigid`: the rigid body under a held torque table.

What the loop follows (references, sequences, burn plans) is :mod:`casadi_debris.guidance`.
"""

from casadi_debris.simulation.cases import (
    Case,
    CaseIdentity,
    corner_case,
    corner_cases,
    nominal_case,
    sample_case,
    sample_cases,
)
from casadi_debris.simulation.closed_loop import (
    SimulationError,
    build_loop_step,
    discretize_controller,
)
from casadi_debris.simulation.events import RunEvent
from casadi_debris.simulation.monte_carlo import (
    CampaignSetup,
    CaseOutcome,
    CaseSummary,
    Envelope,
    run_campaign,
    run_case,
)
from casadi_debris.simulation.open_loop import OpenLoopResult, open_loop_rigid
from casadi_debris.simulation.run import (
    ClosedLoopResult,
    LoopSettings,
    RunInputs,
    simulate,
    simulate_many,
)
from casadi_debris.simulation.summary import EventRecord, RunSummary

__all__ = [
    "CampaignSetup",
    "Case",
    "CaseIdentity",
    "CaseOutcome",
    "CaseSummary",
    "ClosedLoopResult",
    "Envelope",
    "EventRecord",
    "LoopSettings",
    "OpenLoopResult",
    "RunEvent",
    "RunInputs",
    "RunSummary",
    "SimulationError",
    "build_loop_step",
    "corner_case",
    "corner_cases",
    "discretize_controller",
    "nominal_case",
    "open_loop_rigid",
    "run_campaign",
    "run_case",
    "sample_case",
    "sample_cases",
    "simulate",
    "simulate_many",
]
