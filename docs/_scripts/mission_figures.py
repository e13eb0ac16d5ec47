"""The figures of docs/guide/mission.md: the paper's mission and side_engines_12's.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/mission_figures.py

Runs ``casadi-debris mission`` on the paper's problem and on
``problems/gallery/side_engines_12.toml`` (a few minutes) and copies each run's
``mission.png``, ``altitude.png`` and ``decay.png`` to
``docs/figures/mission[_altitude|_decay]_<problem>.png``.
"""

from __future__ import annotations

import shutil
import tempfile
from pathlib import Path

from casadi_debris import load_problem
from casadi_debris.config import default_problem_path
from casadi_debris.workflows.mission import mission_into

FIGURES = Path(__file__).resolve().parents[1] / "figures"
PROBLEMS = ("paper.toml", "gallery/side_engines_12.toml")
NAMES = {"mission.png": "mission_{}.png", "altitude.png": "mission_altitude_{}.png",
         "decay.png": "mission_decay_{}.png"}  # fmt: skip


def main() -> None:
    for path in PROBLEMS:
        problem = load_problem(default_problem_path().parent / path)
        with tempfile.TemporaryDirectory() as folder:
            out = Path(folder) / "mission"
            summary = mission_into(problem, out)
            for name, target in NAMES.items():
                shutil.copyfile(out / name, FIGURES / target.format(problem.name))
        print(problem.name, summary.reentry_years, summary.meets_five_year_rule)


if __name__ == "__main__":
    main()
