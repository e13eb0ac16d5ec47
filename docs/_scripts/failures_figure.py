"""The heat map of docs/guide/failures.md: authority lost by each failed CubeSat of the paper.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/failures_figure.py [RUN_FOLDER]

With a folder written by ``casadi-debris failures problems/paper_slew.toml`` it copies
that run's ``authority_loss.png``; without one it draws it from the authority alone
(``--no-closed-loop``, half a minute), which is all the heat map shows. Writes
``docs/figures/failures_authority_loss.png``.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
from pathlib import Path

import casadi_debris as cd
from casadi_debris.report import HEATMAP

FIGURE = Path(__file__).resolve().parents[1] / "figures" / "failures_authority_loss.png"


def main() -> None:
    if len(sys.argv) > 1:
        shutil.copyfile(Path(sys.argv[1]) / HEATMAP, FIGURE)
    else:
        with tempfile.TemporaryDirectory() as folder:
            out = Path(folder) / "failures"
            cd.failures("paper_slew", max_failed=1, closed_loop=False).save(out)
            shutil.copyfile(out / HEATMAP, FIGURE)
    print(FIGURE)


if __name__ == "__main__":
    main()
