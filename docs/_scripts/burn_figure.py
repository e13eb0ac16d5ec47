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

import casadi_debris as cd

FIGURE = Path(__file__).resolve().parents[1] / "figures" / "burn_paper.png"


def main() -> None:
    result = cd.burn("paper", direction="retrograde", hours=1.0, first_stage_left_s=1200.0)
    with tempfile.TemporaryDirectory() as folder:
        out = result.save(Path(folder) / "burn")
        shutil.copyfile(out / "burn.png", FIGURE)
    summary = result.summary.to_json()
    figures = {k: v for k, v in summary.items() if k not in ("parameters", "events")}
    print(json.dumps(figures, indent=1))
    print(FIGURE)


if __name__ == "__main__":
    main()
