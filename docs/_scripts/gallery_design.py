"""The design table of docs/guide/gallery.md: `casadi-debris design --quick` on every problem.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/gallery_design.py              # rewrite the design table
    python docs/_scripts/gallery_design.py my.toml ...  # print the table for your files

Per problem (``problems/paper.toml``, then ``problems/gallery/*.toml``): the design's
peak mu (full / reduced), the guaranteed pointing (worst axis) and the Ve it was reached
at relative to the requirement's, the pointing and slew errors nominal / worst corner
of the quick campaigns (8 slew and 4 pointing corners spread over the set, 1500 s of
pointing), the worst sampled margins and the requirements met. A problem the design
refuses (a disturbance above the torque authority, ...) shows why. Each design runs in a
temporary folder that is removed afterwards; takes minutes per problem on two cores.
"""

from __future__ import annotations

import argparse
import datetime
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from gallery_table import git_commit, label, machine, one_line, problem_files, rewrite_page

import casadi_debris as cd
from casadi_debris.errors import CasadiDebrisError

BEGIN = "<!-- gallery-design:begin (written by docs/_scripts/gallery_design.py; do not edit) -->"
END = "<!-- gallery-design:end -->"
HEADER = (
    "| problem | μ full / reduced | guaranteed pointing [arcsec] | Ve / required "
    "| pointing, nominal / worst [arcsec] | slew, nominal / worst [deg] "
    "| margins over sampled plants [dB, deg] | requirements met |\n"
    "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
)


def _value(row: dict[str, Any], index: int = 0) -> float:
    return float(row["values"][index])


def row(path: Path, workers: int) -> str:
    """The design row of one problem file."""
    with tempfile.TemporaryDirectory() as folder:
        try:
            designed = cd.design(path, out=Path(folder) / "design", quick=True, workers=workers)
            summary = designed.summary.to_json()
        except CasadiDebrisError as error:
            return f"| {label(path)} | refused: {one_line(error)} |  |  |  |  |  |  |"
    rows = {r["key"]: r for r in summary["rows"]}
    chosen = next(
        a for a in summary["attempts"] if a["ve_ratio"] == summary["scalings"]["ve_ratio"]
    )
    guaranteed = summary["guaranteed_pointing_arcsec"]
    cells = [
        label(path),
        f"{chosen['mu_peak']:.3f} / {chosen['mu_peak_reduced']:.3f}",
        "none (μ > 1)" if guaranteed is None else f"{max(guaranteed):.1f}",
        f"{summary['scalings']['ve_ratio']:.3g}",
        f"{_value(rows['pointing_arcsec']):.1f} / {_value(rows['pointing_arcsec'], 1):.1f}",
        f"{_value(rows['slew_max_error_deg']):.3f} / {_value(rows['slew_max_error_deg'], 1):.3f}",
        f"{_value(rows['margins_sampled']):.1f} / {_value(rows['margins_sampled'], 1):.1f}",
        f"{summary['requirements_passed']} of {summary['requirements']}",
    ]
    return "| " + " | ".join(cells) + " |"


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("problems", nargs="*", type=Path, help="print their table instead")
    parser.add_argument("--workers", type=int, default=2, help="processes for the campaigns")
    arguments = parser.parse_args(argv)
    started = time.perf_counter()
    commit = git_commit()
    rows = []
    for path in arguments.problems or problem_files():
        one = time.perf_counter()
        rows.append(row(path, arguments.workers))
        print(f"{path.name}: {time.perf_counter() - one:.0f} s", file=sys.stderr)
    result = "\n".join([HEADER, *rows])
    if arguments.problems:
        print(result)
        return
    elapsed = time.perf_counter() - started
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    record = (
        f"Computed {now} by `python docs/_scripts/gallery_design.py` in {elapsed:.0f} s "
        f"({arguments.workers} workers), at commit {commit}, on {machine()}."
    )
    rewrite_page(f"\n{result}\n\n{record}\n", BEGIN, END)
    print(f"wrote the design table in {elapsed:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
