"""An NLP solution as a :class:`~casadi_debris.slews._profile.SlewProfile`.

The held controls are integrated (CVODES) on the flexible model when the slew
is flexible, else on the rigid one, sampled on the output grid with every
control knot, and assembled with the propellant and, if asked, the check of
the vibration left on the full flexible model.
"""

from __future__ import annotations

from collections.abc import Mapping

import casadi as ca
import numpy as np

from casadi_debris.dynamics import Model
from casadi_debris.slews._ocp_problem import SlewOcp
from casadi_debris.slews._profile import (
    REFERENCE_INTEGRATOR_OPTIONS,
    ProfileRequest,
    ProfileSettings,
    SlewProfile,
    finish_profile,
    sample_grid,
    simulate_open_loop,
    zoh_input_function,
)
from casadi_debris.slews._transcription import COLLOCATION_DEGREE, NlpSolution


def slew_profile(
    ocp: SlewOcp,
    solution: NlpSolution,
    *,
    fuel: bool,
    solve_time_s: float,
    check_vibration: bool,
    figures: Mapping[str, object],
) -> SlewProfile:
    """The solution as a profile, integrated on the flexible model if there is one.

    Parameters
    ----------
    ocp : SlewOcp
        The OCP solved.
    solution : NlpSolution
        Its knots (s) and held controls (SI).
    fuel : bool
        The objective was propellant (``"fuel-optimal"``), else time.
    solve_time_s : float
        Wall time of the solve, s.
    check_vibration : bool
        Integrate the result on the full flexible model for the residual vibration.
    figures : mapping
        The method's own figures (units in the keys), added to the common ones in
        the profile's ``settings`` record.
    """
    knots, controls = solution.knots_s, solution.controls
    model = ocp.rigid_model if ocp.flexible_model is None else ocp.flexible_model
    lay = model.layout
    total = float(knots[-1])
    torque, force = ocp.model_inputs(controls, fuel)
    input_function = zoh_input_function(knots, torque, force)
    grid = sample_grid(total, ocp.options.sample_s, knots)
    states, accelerations, rate_error = _motion(ocp, model, input_function, grid)
    final_error = np.array(model.attitude_error(ocp.target.q_final_BN, states[-1, lay.q])).ravel()
    record: dict[str, object] = {
        "control_intervals": len(knots) - 1,
        "collocation_degree": COLLOCATION_DEGREE,
        "final_attitude_error_rad": float(np.linalg.norm(final_error)),
        "final_rate_rad_s": float(np.linalg.norm(states[-1, lay.omega])),
        **({} if rate_error is None else {"integration_rate_error_rad_s": rate_error}),
        "single_axis": ocp.options.single_axis,
        **figures,
    }
    if ocp.thrusters:
        record["delta_v_m_s"] = float(np.linalg.norm(states[-1, lay.v]))
        record["zero_net_force"] = ocp.options.zero_net_force
    request = ProfileRequest(
        method="fuel-optimal" if fuel else "time-optimal",
        target=ocp.target,
        flexible=ocp.options.flexible,
        thrusters=ocp.thrusters,
        time_s=grid,
        quaternion_BN=states[:, lay.q],
        rate_rad_s=states[:, lay.omega],
        acceleration_rad_s2=accelerations,
        input_function=input_function,
        knots_s=knots,
        interval_thrust_N=controls if ocp.thrusters else None,
        duration_s=total,
        limit_duration_s=ocp.limit_duration_s,
        solve_time_s=solve_time_s,
        solver_status=solution.status,
        figures=record,
    )
    settings = ProfileSettings(
        torque_fraction=ocp.options.torque_fraction,
        check_vibration=check_vibration,
        # The closed loop's allocator keeps the net force zero; a thruster-level
        # profile carries its own thrust and the rule it was solved with.
        zero_net_force=ocp.options.zero_net_force if ocp.thrusters else True,
    )
    return finish_profile(
        problem=ocp.problem if ocp.flexible_model is None else ocp.flexible_model,
        geometry=ocp.geometry,
        request=request,
        settings=settings,
        inertia_kgm2=ocp.inertia,
    )


def _motion(
    ocp: SlewOcp, model: Model, input_function: ca.Function, grid: np.ndarray
) -> tuple[np.ndarray, np.ndarray, float | None]:
    """States (shape (n, n_state)) and body angular accelerations (rad/s^2, shape
    (n, 3)) of ``model`` from rest under ``input_function`` at the times ``grid`` (s), and,
    on the rigid model, the largest error of the rates (rad/s): their difference from an
    integration at tolerances a hundred times tighter (None on a flexible model, whose
    stiff modes make that second integration long, and whose hub is not checked by the
    rigid body's equation)."""
    start = model.initial_state(ocp.target.q_initial_BN)
    states = simulate_open_loop(model, input_function, grid, start, ocp.parameters)
    rate_error = None
    if ocp.flexible_model is None:
        reference = simulate_open_loop(
            model,
            input_function,
            grid,
            start,
            ocp.parameters,
            options=REFERENCE_INTEGRATOR_OPTIONS,
        )
        omega = model.layout.omega
        rate_error = float(np.max(np.abs(states[:, omega] - reference[:, omega])))
    inputs = np.array(input_function.map(len(grid))(grid)).T
    accelerations = np.array(
        [
            np.array(model.dynamics(x, u, ocp.parameters)).ravel()[model.layout.omega]
            for x, u in zip(states, inputs, strict=True)
        ]
    )
    return states, accelerations, rate_error
