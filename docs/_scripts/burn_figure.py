"""The figure and numbers of docs/guide/burn.md: a retrograde burn of the paper's debris.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/burn_figure.py

Flies one hour of retrograde thrust on the flexible model, the engines' first stages
holding 20 minutes of full thrust (so that the stages switch during it), and writes
``docs/figures/burn_paper.png``; prints the summary as JSON.
"""

from __future__ import annotations

import json
import shutil
import tempfile
from pathlib import Path

from casadi_debris import load_problem
from casadi_debris.workflows.burn import BurnRequest, burn_into

FIGURE = Path(__file__).resolve().parents[1] / "figures" / "burn_paper.png"


def main() -> None:
    request = BurnRequest(direction="retrograde", duration_s=3600.0, first_stage_left_s=1200.0)
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "burn"
        report = burn_into(load_problem(), out, request)
        shutil.copyfile(out / "burn.png", FIGURE)
    figures = {k: v for k, v in report.to_json().items() if k not in ("parameters", "events")}
    print(json.dumps(figures, indent=1))
    print(FIGURE)


if __name__ == "__main__":
    main()
