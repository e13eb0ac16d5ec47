"""Benchmark of the slew methods on the paper's 180 deg z slew; prints JSON.

Usage: python benchmarks/slew.py [--repeat N] [--quick] [--record] [--out FILE] [--note TEXT]

``--record`` also writes ``docs/benchmarks/slew.json`` (see ``recording.py``).
``--quick``: each method once (default: 3 times).

For each method: duration, fuel, residual vibration on the full flexible
model, and the medians of the solve time (the profile's ``solve_time_s``: the
OCP from transcription to solution, or evaluating the bang-bang) and of the
whole call's wall time (with the check on the flexible model), against the
rigid eigenaxis limit 2 sqrt(theta J / tau). Targets: every
time-optimal slew <= 5 s to solve; flexible within 1.10 x the limit.
"""

from __future__ import annotations

import math
import statistics
import time
from collections.abc import Callable

from casadi_debris import load_problem
from casadi_debris.slews import (
    SlewProfile,
    bang_bang_slew,
    fuel_optimal_slew,
    time_optimal_slew,
)
from recording import Setting, start_benchmark

PAPER_DURATION_S = 1228.0
PAPER_FUEL_KG = 2.8e-4


def measure(
    make: Callable[[], SlewProfile], repeat: int
) -> tuple[SlewProfile, list[float], list[float]]:
    """Run ``make`` ``repeat`` times: the last profile, each run's wall and solve time (s)."""
    walls, solves, profile = [], [], None
    for _ in range(repeat):
        started = time.perf_counter()
        profile = make()
        walls.append(time.perf_counter() - started)
        solves.append(profile.solve_time_s)
    return profile, walls, solves


OPTIONS = {
    "--repeat": Setting(3, 1, "runs of each method, medians kept (3)"),
}


def main() -> None:
    args, recording, settings = start_benchmark("slew", __doc__, "each method once", OPTIONS)
    problem = load_problem()
    z, pi = "z", math.pi
    cases = {
        "bang_bang_paper_1228s": lambda: bang_bang_slew(
            problem, z, pi, duration_s=PAPER_DURATION_S
        ),
        "bang_bang_full_torque": lambda: bang_bang_slew(problem, z, pi),
        "time_optimal_rigid": lambda: time_optimal_slew(problem, z, pi),
        "time_optimal_rigid_thrusters": lambda: time_optimal_slew(problem, z, pi, thrusters=True),
        "time_optimal_flexible": lambda: time_optimal_slew(problem, z, pi, flexible=True),
        "time_optimal_flexible_thrusters": lambda: time_optimal_slew(
            problem, z, pi, flexible=True, thrusters=True
        ),
        "time_optimal_flexible_zv_shaper": lambda: time_optimal_slew(
            problem, z, pi, flexible=True, flexible_method="shaper"
        ),
        "fuel_optimal_1228s": lambda: fuel_optimal_slew(
            problem, z, pi, duration_s=PAPER_DURATION_S
        ),
        "fuel_optimal_1228s_thrusters": lambda: fuel_optimal_slew(
            problem, z, pi, duration_s=PAPER_DURATION_S, thrusters=True
        ),
    }
    results = {}
    for name, make in cases.items():
        repeat = args.repeat
        profile, walls, solves = measure(make, repeat)
        results[name] = {
            "duration_s": profile.duration_s,
            "duration_over_limit": profile.duration_s / profile.limit_duration_s,
            "fuel_kg": profile.fuel_kg,
            "fuel_over_paper": profile.fuel_kg / PAPER_FUEL_KG,
            "max_torque_mNm": profile.max_torque_Nm * 1e3,
            "residual_vibration_rad": profile.residual_vibration_rad,
            "residual_energy_J": profile.residual_energy_J,
            "solve_time_s": statistics.median(solves),
            "wall_time_median_s": statistics.median(walls),
            "runs": repeat,
            "solver_status": profile.solver_status,
            "engine_torque_shortfall_mNm": profile.settings.get("engine_torque_shortfall_Nm", 0.0)
            * 1e3,
            "torque_fraction": profile.settings.get("torque_fraction"),
        }
        for key in (
            "flexible_method",
            "residual_energy_limit_J",
            "rigid_duration_s",
            "predicted_residual_energy_J",
            "bang_bang_residual_energy_J",
            "reference_energy_time_s",
            "window_s",
        ):
            if key in profile.settings:
                results[name][key] = profile.settings[key]
    limit = profile.limit_duration_s  # every method's profile carries the same rigid limit
    payload = {
        "problem": problem.name,
        "slew": "180 deg about z, rest to rest",
        "limit_duration_s": limit,
        "paper": {"duration_s": PAPER_DURATION_S, "fuel_kg": PAPER_FUEL_KG},
        "targets": {
            "time_optimal_solve_time_s_max": 5.0,
            "flexible_duration_over_limit_max": 1.10,
            "time_optimal_met": all(
                results[name]["solve_time_s"] <= 5.0
                for name in results
                if name.startswith("time_optimal")
            ),
            "flexible_met": results["time_optimal_flexible"]["duration_over_limit"] <= 1.10,
        },
        "methods": results,
    }
    recording.finish(settings, payload)


if __name__ == "__main__":
    main()
