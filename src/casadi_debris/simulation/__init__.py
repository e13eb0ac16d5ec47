"""The closed loop: the nonlinear model, sensors and estimator, the robust controller,
the allocator and the engines, run together over time.

- :func:`simulate_closed_loop`: one scenario (:class:`ClosedLoopResult`, and its figures as a
  :class:`RunSummary`); :func:`simulate_many`: several, with ``jit`` as one compiled
  function mapped over them.
- :func:`build_loop_step`: one control period as a compiled CasADi Function.
- :func:`segment_figures`: a manoeuvre's run, figured segment by segment.
- :func:`open_loop_rigid`: the rigid body under a held torque table.

Beside the loop, as subpackages: the detumble runs
(:mod:`casadi_debris.simulation.detumble`) and the burn runs
(:mod:`casadi_debris.simulation.burn`). Campaigns of many runs are
:mod:`casadi_debris.campaigns`, one layer above; what the loop follows
(references, sequences, burn plans) is :mod:`casadi_debris.guidance`.
"""

from casadi_debris.errors import SimulationError
from casadi_debris.processes import c_compiler
from casadi_debris.simulation._batched import release_batched_loops
from casadi_debris.simulation._closed_loop import (
    DiscreteController,
    StepInput,
    StepOutput,
    build_loop_step,
    discretize_controller,
    release_compiled_steps,
)
from casadi_debris.simulation._events import RunEvent
from casadi_debris.simulation._noise import draw_noise
from casadi_debris.simulation._open_loop import OpenLoopResult, open_loop_rigid
from casadi_debris.simulation._realism import Realism, engine_basis
from casadi_debris.simulation._run import (
    ClosedLoopResult,
    LoopSettings,
    RunInputs,
    simulate_closed_loop,
    simulate_many,
)
from casadi_debris.simulation._segment_figures import SegmentRunSummary, segment_figures
from casadi_debris.simulation._summary import (
    SETTLE_BAND_ARCSEC,
    EventSummary,
    RunSummary,
    fuel_between_kg,
)

__all__ = [
    "SETTLE_BAND_ARCSEC",
    "ClosedLoopResult",
    "DiscreteController",
    "EventSummary",
    "LoopSettings",
    "OpenLoopResult",
    "Realism",
    "RunEvent",
    "RunInputs",
    "RunSummary",
    "SegmentRunSummary",
    "SimulationError",
    "StepInput",
    "StepOutput",
    "build_loop_step",
    "c_compiler",
    "discretize_controller",
    "draw_noise",
    "engine_basis",
    "fuel_between_kg",
    "open_loop_rigid",
    "release_batched_loops",
    "release_compiled_steps",
    "segment_figures",
    "simulate_closed_loop",
    "simulate_many",
]
