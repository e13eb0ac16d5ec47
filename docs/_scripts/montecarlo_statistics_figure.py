"""The figure of docs/guide/results.md: statistics of the paper's slew under dispersions.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/montecarlo_statistics_figure.py [RUN_FOLDER]

With a folder written by ``casadi-debris montecarlo paper_slew_dispersions`` it draws
that campaign's ``statistics.png`` again from its case files; without one it runs the
campaign (64 cases of the 1500 s slew on two processes, about ten minutes on a busy
two-core machine) in a temporary folder. Writes
``docs/figures/montecarlo_slew_statistics.png`` and prints the pass rate and drivers.
"""

from __future__ import annotations

import json
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

import casadi_debris as cd
from casadi_debris import load_problem
from casadi_debris.campaigns import FIGURES, CaseSummary, campaign_statistics, requirement_of
from casadi_debris.plots import plot_statistics
from casadi_debris.report import figure_title

NAME = "paper_slew_dispersions"
FIGURE = Path(__file__).resolve().parents[1] / "figures" / "montecarlo_slew_statistics.png"


def main() -> None:
    if len(sys.argv) > 1:  # drawn again from the folder's case files
        folder = Path(sys.argv[1])
        problem = load_problem(NAME)
        cases = [
            CaseSummary.from_json(json.loads(path.read_text()))
            for path in sorted((folder / "cases").glob("*.json"))
            if not path.name.endswith(".failed.json")
        ]
        runs = [case.run for case in cases]
        figures = {
            name: np.array([np.nan if getattr(r, name) is None else getattr(r, name) for r in runs])
            for name in FIGURES
        }
        names = list(cases[0].identity.varied)
        quantities = {n: np.array([c.identity.varied[n] for c in cases]) for n in names}
        ids = [case.identity.case_id for case in cases]
        record = campaign_statistics(ids, figures, quantities, requirement_of(problem))
        plot_statistics(record, figures, FIGURE, title=figure_title(problem))
        statistics = record.to_json()
    else:
        problem = load_problem(NAME)
        with tempfile.TemporaryDirectory() as temporary:
            out = Path(temporary) / "mc"
            campaign = cd.montecarlo(problem, workers=2)
            campaign.save(out)
            shutil.copyfile(out / "statistics.png", FIGURE)
        assert campaign.summary.statistics is not None
        statistics = campaign.summary.statistics.to_json()
    print(FIGURE)
    print(
        f"pass rate {statistics['pass_rate']:.3f} ({statistics['passed']} of {statistics['cases']})"
    )
    for driver in statistics["drivers"]:
        ranked = zip(
            driver["quantities"], driver["spearman_rho"], driver["first_order_index"], strict=True
        )
        print(driver["figure"], [f"{n} {r:+.2f} S {s}" for n, r, s in ranked][:4])


if __name__ == "__main__":
    main()
