"""Benchmark of the NMPC's solve time per period on the paper's debris; prints JSON.

Usage: python benchmarks/nmpc.py [--periods N] [--full-periods N] [--horizons 10,20,40]
[--quick] [--record] [--out FILE] [--note TEXT]

``--record`` also writes ``docs/benchmarks/nmpc.json`` (see ``recording.py``).

For each horizon (10, 20, 40 intervals of 1 s), prediction (rigid; flexible with each
array's first bending mode) and solver (real-time iteration: one SQP step with sparse qpoases;
full: IPOPT to convergence), a closed loop of a 1 deg slew about z: the paper's debris
with every array mode (the model's Function integrated by CVODES), the true state fed
back. Kept per period: the wall time of the solver call (``NmpcStep.solve_time_s``);
reported: its median, 99th percentile and maximum over the periods after the first
(the first, a cold start, is reported apart), and the attitude error at the end.
Targets (RTI, default horizon 20, 1 s period): median <= 20 ms, maximum <= 100 ms.
Also the QP solvers of the real-time iteration compared at the default horizon.
"""

from __future__ import annotations

import math
import statistics

import casadi as ca
import numpy as np

from casadi_debris import load_problem
from casadi_debris.controllers import NmpcController, NmpcSettings
from casadi_debris.dynamics import Model, attitude_error, axis_angle_quaternion, build_model
from recording import Setting, start_benchmark

SLEW_DEG = 1.0
TARGET_MEDIAN_S = 0.020
TARGET_MAX_S = 0.100

OPTIONS = {
    "--periods": Setting(120, 30, "closed-loop periods of each RTI case (120)"),
    "--full-periods": Setting(30, 8, "closed-loop periods of each full-solve case (30)"),
    "--horizons": Setting("10,20,40", "10,20,40", "horizons N, comma-separated (10,20,40)"),
}


def estimate_map(controller: NmpcController, plant: Model) -> np.ndarray:
    """Indices of the plant's state that make the controller model's state (the modes
    the controller's model keeps, by label; the star tracker last)."""
    mine, theirs = controller.model.layout, plant.layout
    labels = list(theirs.mode_labels)
    kept = [labels.index(label) for label in mine.mode_labels]
    index = list(range(10))
    index += [theirs.eta.start + i for i in kept] + [theirs.eta_dot.start + i for i in kept]
    return np.array(index + list(range(theirs.q_st.start, theirs.q_st.stop)))


def fly(controller: NmpcController, plant: Model, periods: int) -> dict[str, float]:
    """Closed loop of the slew; solve-time statistics and the final error."""
    period = controller.settings.period_s
    x = ca.MX.sym("x", plant.layout.size)
    u = ca.MX.sym("u", 9)
    ode = plant.dynamics(x, u, ca.DM(plant.nominal_parameters))
    integrate = ca.integrator(
        "plant", "cvodes", {"x": x, "p": u, "ode": ode}, 0.0, period, {"abstol": 1e-10}
    )
    target = axis_angle_quaternion([0.0, 0.0, 1.0], math.radians(SLEW_DEG))
    engines = controller.engines
    state = plant.initial_state()
    seen = estimate_map(controller, plant)
    times, iterations, failures = [], [], 0
    for k in range(periods):
        step = controller.step(k * period, state[seen], target)
        times.append(step.solve_time_s)
        iterations.append(step.sqp_iterations)
        failures += not step.success
        thrust = step.thrust_N
        inputs = np.concatenate(
            [
                engines.torque_map @ thrust,
                np.array(plant.disturbance(k * period)).ravel(),
                engines.force_map @ thrust,
            ]
        )
        state = np.array(integrate(x0=state, p=inputs)["xf"]).ravel()
    error = float(np.linalg.norm(attitude_error(target, state[plant.layout.q])))
    rest = np.array(times[1:])
    return {
        "first_solve_s": times[0],
        "median_s": float(np.median(rest)),
        "p99_s": float(np.percentile(rest, 99)),
        "max_s": float(rest.max()),
        "iterations_median": statistics.median(iterations),
        "periods": periods,
        "unsuccessful_periods": failures,
        "final_error_arcsec": math.degrees(error) * 3600.0,
    }


def main() -> None:
    _args, recording, settings = start_benchmark("nmpc", __doc__, "fewer periods", OPTIONS)
    problem = load_problem()
    plant = build_model(problem)
    first_modes = build_model(problem, modes="first")
    cases = {}
    horizons = [int(text) for text in settings["horizons"].split(",")]
    for horizon in horizons:
        for prediction, model in (("rigid", plant), ("flexible", first_modes)):
            for solver in ("rti", "full"):
                name = f"{prediction}_{solver}_N{horizon}"
                nmpc = NmpcSettings(
                    horizon_steps=horizon,
                    period_s=1.0,
                    prediction=prediction,  # type: ignore[arg-type]
                    solver=solver,  # type: ignore[arg-type]
                )
                controller = NmpcController(model, nmpc)
                periods = settings["periods"] if solver == "rti" else settings["full_periods"]
                result = fly(controller, plant, periods)
                result["integrator_steps"] = controller.integrator_steps
                cases[name] = result
                print(name, result, flush=True)
    qp = {}
    for qp_solver in ("qpoases", "qrqp", "daqp"):
        controller = NmpcController(plant, NmpcSettings(qp_solver=qp_solver))
        qp[qp_solver] = fly(controller, plant, min(settings["periods"], 20))
        print(qp_solver, qp[qp_solver], flush=True)
    default = cases.get("rigid_rti_N20", {"median_s": math.inf, "max_s": math.inf})
    payload = {
        "problem": problem.name,
        "scenario": f"{SLEW_DEG} deg slew about z, closed loop, 1 s period, plant with every mode",
        "targets": {
            "rti_default_median_s_max": TARGET_MEDIAN_S,
            "rti_default_max_s_max": TARGET_MAX_S,
            "median_met": default["median_s"] <= TARGET_MEDIAN_S,
            "max_met": default["max_s"] <= TARGET_MAX_S,
        },
        "cases": cases,
        "qp_solvers_rigid_rti_N20": qp,
    }
    recording.finish(settings, payload)


if __name__ == "__main__":
    main()
