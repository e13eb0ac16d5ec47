"""The figure of the time-optimal slew benchmark in docs/guide/slews.md.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/slew_benchmark_figure.py

Solves the benchmark of Bilimoria & Wie (1993), a rigid body with J = I and
|u_i| <= 1 turned 180 deg about z from rest to rest, twice: the global search
(multi-start, switch times refined) and a single start from the eigenaxis
bang-bang without refinement (a stationary point of the NLP, where a single
start stays), and writes both to ``docs/figures/slew_time_optimal_benchmark.png``.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from casadi_debris.plots import plot_slew_comparison
from casadi_debris.slews import RigidBody, time_optimal_slew

FIGURE = Path(__file__).resolve().parents[1] / "figures" / "slew_time_optimal_benchmark.png"


def main() -> None:
    body = RigidBody(inertia_kgm2=np.eye(3), torque_max_Nm=(1, 1, 1))
    found = time_optimal_slew(body, axis=(0, 0, 1), angle_rad=math.pi, sample_s=0.01)
    eigenaxis = time_optimal_slew(
        body, axis=(0, 0, 1), angle_rad=math.pi, sample_s=0.01, starts=1, refine=False
    )
    plot_slew_comparison({"global search": found, "single start, eigenaxis": eigenaxis}, FIGURE)
    print(f"{FIGURE}: {found.duration_s:.6f} s against {eigenaxis.duration_s:.6f} s")


if __name__ == "__main__":
    main()
