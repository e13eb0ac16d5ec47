"""The figures and numbers of docs/guide/placement.md.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/placement_figures.py [--double-time-limit S]

On the paper's debris with the default candidates (4 x 4 mounts per face, 96 in
all, the paper's 24 among them): the best worst-axis layouts of 12, 16, 20 and
24 CubeSats, the Pareto sweep over 8, 12, ..., 24 CubeSats with the paper's
layout on it, and the best worst-double-failure layouts of 24 CubeSats on the
3 x 3 and 4 x 4 grids (within the time limit: their gap is printed). Writes
``docs/figures/placement_layout_24.png``, ``docs/figures/placement_pareto.png``
and prints the numbers as JSON.
"""

from __future__ import annotations

import argparse
import json
import shutil
import tempfile
from pathlib import Path

import casadi_debris as cd
from casadi_debris.report import json_ready

FACES = ("+x", "-x", "+y", "-y", "+z", "-z")
FIGURES = Path(__file__).resolve().parents[1] / "figures"
KEEP = ("count", "worst_axis", "worst_ratio", "torque_max_zero_force_mNm", "slowest_slew_s",
        "weakest_dv_one_stage_m_s", "added_inertia_kgm2")  # fmt: skip


def brief(summary: dict) -> dict:
    """What the page quotes of one run."""
    solver = summary["solver"]
    return {
        **{key: summary[key] for key in KEEP},
        "faces": sorted({c["face"] for c in summary["chosen"]}),
        "per_face": {f: sum(c["face"] == f for c in summary["chosen"]) for f in FACES},
        "worst_failure_ratio": summary["worst_failure"]["worst_ratio"],
        "optimal": solver["optimal"],
        "gap": solver["gap"],
        "upper_bound": solver["upper_bound"],
        "time_s": solver["time_s"],
        "method": solver["method"],
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--double-time-limit", type=float, default=300.0)
    parser.add_argument("--pareto-time-limit", type=float, default=60.0)
    args = parser.parse_args()
    problem = cd.load_problem()
    numbers: dict = {}
    with tempfile.TemporaryDirectory() as scratch:
        root = Path(scratch)
        for count in (12, 16, 20):
            summary = cd.placement(problem, count=count).summary.to_json()
            numbers[f"best_{count}"] = brief(summary)
        result = cd.placement(
            problem, count=24, time_limit=args.pareto_time_limit, pareto_counts="auto"
        )
        result.save(root / "n24")
        summary = result.summary.to_json()
        numbers["best_24"] = brief(summary)
        numbers["paper"] = {key: summary["input_layout"][key] for key in KEEP}
        numbers["pareto"] = summary["pareto"]
        shutil.copy(root / "n24" / "layout.png", FIGURES / "placement_layout_24.png")
        shutil.copy(root / "n24" / "pareto.png", FIGURES / "placement_pareto.png")
        for grid in (3, 4):
            summary = cd.placement(
                problem,
                count=24,
                objective="worst-double-failure",
                candidates=grid,
                time_limit=args.double_time_limit,
            ).summary.to_json()
            numbers[f"double_{grid}x{grid}"] = brief(summary)
        numbers["paper_worst_double"] = summary["input_layout"]["worst_failure"]
    print(json.dumps(json_ready(numbers), indent=1))


if __name__ == "__main__":
    main()
