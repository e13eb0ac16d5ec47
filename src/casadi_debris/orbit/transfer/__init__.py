"""The low-thrust orbit transfer with the swarm's staged engines.

:func:`plan_transfer` plans the problem's ``[transfer]``: the swarm's thrust directions
and their torque-free thrust, the burn schedule (each direction's stages in turn, then
hypothetical extra stage lives if the swarm's own do not suffice), Edelbaum steering
flown in closed loop on the orbit-averaged dynamics with J2
(:func:`edelbaum_guidance`), and the optimal control problem started from it
(:func:`solve_transfer_ocp`); the answer (:class:`TransferSummary`) says whether the
swarm's own stages reach the target orbit, how far they get if not, and what more it
would take.

The pieces are public for those who want them: the averaged dynamics
(:func:`averaged_dynamics`, :func:`averaged_step`) and Edelbaum's analytic transfer
(:func:`edelbaum_dv`, :func:`edelbaum_yaw`); the burns and their staging (:class:`Burn`,
:func:`burn_schedule`, :func:`stage_use`, :func:`stage_switch_times_s`,
:func:`dv_of_burns`).

Example
-------
>>> from casadi_debris import load_problem
>>> from casadi_debris.orbit.transfer import plan_transfer
>>> plan = plan_transfer(load_problem())  # doctest: +SKIP
>>> round(plan.result.transfer_dv_m_s, 1), plan.result.swarm_suffices  # doctest: +SKIP
(143.9, False)
"""

from casadi_debris.orbit.transfer._averaged import (
    N_SLOW,
    QUADRATURE_NODES,
    averaged_dynamics,
    averaged_step,
    edelbaum_dv,
    edelbaum_yaw,
    radius_inclination,
)
from casadi_debris.orbit.transfer._guidance import (
    GuidedTransfer,
    edelbaum_guidance,
    remaining_dv_m_s,
)
from casadi_debris.orbit.transfer._ocp import (
    Objective,
    OptimalTransfer,
    TransferTarget,
    solve_transfer_ocp,
)
from casadi_debris.orbit.transfer._plan import (
    TARGET_SEGMENTS,
    TransferPlan,
    check_transfer,
    plan_transfer,
    transfer_dv_m_s,
)
from casadi_debris.orbit.transfer._summary import TransferSummary, summarise, trajectory_dv_m_s
from casadi_debris.orbit.transfer._thrust import (
    Burn,
    StageUse,
    burn_schedule,
    dv_of_burns,
    stage_switch_times_s,
    stage_use,
)

__all__ = [
    "N_SLOW",
    "QUADRATURE_NODES",
    "TARGET_SEGMENTS",
    "Burn",
    "GuidedTransfer",
    "Objective",
    "OptimalTransfer",
    "StageUse",
    "TransferPlan",
    "TransferSummary",
    "TransferTarget",
    "averaged_dynamics",
    "averaged_step",
    "burn_schedule",
    "check_transfer",
    "dv_of_burns",
    "edelbaum_dv",
    "edelbaum_guidance",
    "edelbaum_yaw",
    "plan_transfer",
    "radius_inclination",
    "remaining_dv_m_s",
    "solve_transfer_ocp",
    "stage_switch_times_s",
    "stage_use",
    "summarise",
    "trajectory_dv_m_s",
    "transfer_dv_m_s",
]
