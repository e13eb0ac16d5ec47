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

import casadi_debris as cd
from casadi_debris.config import default_problem_path

FIGURES = Path(__file__).resolve().parents[1] / "figures"
PROBLEMS = ("paper.toml", "gallery/side_engines_12.toml")
NAMES = {"mission.png": "mission_{}.png", "altitude.png": "mission_altitude_{}.png",
         "decay.png": "mission_decay_{}.png"}  # fmt: skip


def main() -> None:
    for path in PROBLEMS:
        problem = cd.load_problem(default_problem_path().parent / path)
        with tempfile.TemporaryDirectory() as folder:
            out = Path(folder) / "mission"
            result = cd.mission(problem)
            result.save(out)
            summary = result.summary
            for name, target in NAMES.items():
                shutil.copyfile(out / name, FIGURES / target.format(problem.name))
        print(problem.name, summary.reentry_years, summary.meets_five_year_rule)


if __name__ == "__main__":
    main()
