"""Run every script of ``examples/`` with its quick settings and keep one figure of each
for the examples page (``docs/figures/examples/<script>.png``).

    python docs/_scripts/examples_figures.py

Each figure is the one named in ``FIGURES``; the page says they come from the quick
settings.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
TARGET = ROOT / "docs" / "figures" / "examples"
FIGURES = {
    "fly_a_slew": "closed_loop.png",
    "optimal_slew": "time_optimal_slew.png",
    "allocation_with_failures": "thrust.png",
    "budgets_compared": "budgets.png",
    "design_and_fly": "closed_loop.png",
    "montecarlo_in_xarray": "envelope.png",
    "mission_to_reentry": "mission.png",
}


def main() -> None:
    TARGET.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as scratch:
        environment = {
            **os.environ,
            "CASADI_DEBRIS_EXAMPLES_QUICK": "1",
            "CASADI_DEBRIS_EXAMPLES_OUT": scratch,
            "MPLBACKEND": "Agg",
        }
        for script, figure in FIGURES.items():
            subprocess.run(
                [sys.executable, f"{script}.py"], cwd=EXAMPLES, env=environment, check=True
            )
            shutil.copyfile(Path(scratch) / script / figure, TARGET / f"{script}.png")
            print(f"{script}: {TARGET / f'{script}.png'}")


if __name__ == "__main__":
    main()
