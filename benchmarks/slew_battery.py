"""Solve times of the optimal slews over four slews, not one; prints JSON.

Usage: python benchmarks/slew_battery.py [--slews z_180deg,x_90deg,...] [--quick] [--record]
       [--out FILE] [--note TEXT]

``--record`` also writes ``docs/benchmarks/slew_battery.json`` (see ``recording.py``).
``--quick``: two of the slews, 180 deg about z and 45 deg about y (default: all four).

IPOPT's path on these nonconvex problems moves with small changes (local optima
of the thruster-level slews differ by up to 0.15 %, iteration counts by 2-5x),
so a setting is judged on several slews: 180 deg about z (the paper's), 90 deg
about x, 2 rad about [1, 1, 1], 45 deg about y. For each method: duration and
solve time (the profile's ``solve_time_s``) per slew, and the range of the
solve times against the 5 s target. Fuel-optimal slews are given 1.3 x
the rigid eigenaxis limit of their slew.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from casadi_debris import load_problem
from casadi_debris.config import Problem
from casadi_debris.slews import SlewProfile, bang_bang_slew, fuel_optimal_slew, time_optimal_slew
from recording import Setting, start_benchmark

SLEWS = {
    "z_180deg": ("z", math.pi),
    "x_90deg": ("x", math.pi / 2),
    "xyz_2rad": ((1.0, 1.0, 1.0), 2.0),
    "y_45deg": ("y", math.pi / 4),
}
FUEL_DURATION_OVER_LIMIT = 1.3
TARGET_S = 5.0


def rigid_limit_s(problem: Problem, axis: str | tuple, angle_rad: float) -> float:
    """2 sqrt(theta J / tau) of the rigid body about the slew's eigenaxis (s)."""
    return bang_bang_slew(problem, axis, angle_rad, check_vibration=False).limit_duration_s


def methods(problem: Problem) -> dict[str, Callable[[str | tuple, float], SlewProfile]]:
    common = {"check_vibration": False}

    def fuel(axis: str | tuple, angle: float, **options: bool) -> SlewProfile:
        duration = FUEL_DURATION_OVER_LIMIT * rigid_limit_s(problem, axis, angle)
        return fuel_optimal_slew(problem, axis, angle, duration_s=duration, **options, **common)

    return {
        "time_optimal_rigid": lambda a, t: time_optimal_slew(problem, a, t, **common),
        "time_optimal_thrusters": lambda a, t: time_optimal_slew(
            problem, a, t, thrusters=True, **common
        ),
        "time_optimal_flexible": lambda a, t: time_optimal_slew(
            problem, a, t, flexible=True, **common
        ),
        "time_optimal_flexible_thrusters": lambda a, t: time_optimal_slew(
            problem, a, t, flexible=True, thrusters=True, **common
        ),
        "fuel_optimal_thrusters": lambda a, t: fuel(a, t, thrusters=True),
        "fuel_optimal_flexible": lambda a, t: fuel(a, t, flexible=True),
    }


OPTIONS = {
    "--slews": Setting(
        ",".join(SLEWS), "z_180deg,y_45deg", f"comma-separated, of {', '.join(SLEWS)} (all)"
    ),
}


def main() -> None:
    args, recording, settings = start_benchmark(
        "slew_battery", __doc__, "180 deg about z and 45 deg about y", OPTIONS
    )
    slews = {name: SLEWS[name] for name in args.slews.split(",")}
    problem = load_problem()
    results = {}
    for name, solve in methods(problem).items():
        per_slew = {}
        for slew, (axis, angle) in slews.items():
            profile = solve(axis, angle)
            per_slew[slew] = {
                "duration_s": profile.duration_s,
                "solve_time_s": profile.solve_time_s,
                "solver_status": profile.solver_status,
                "flexible_method": profile.settings.get("flexible_method"),
            }
        times = [case["solve_time_s"] for case in per_slew.values()]
        results[name] = {
            "slews": per_slew,
            "solve_time_min_s": min(times),
            "solve_time_max_s": max(times),
            "within_target": sum(t <= TARGET_S for t in times),
        }
    payload = {
        "problem": problem.name,
        "target_solve_time_s": TARGET_S,
        "methods": results,
    }
    recording.finish(settings, payload)


if __name__ == "__main__":
    main()
