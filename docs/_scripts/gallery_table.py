"""The results table of docs/guide/gallery.md: the paper's problem and every gallery problem.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/gallery_table.py              # rewrite the table in gallery.md
    python docs/_scripts/gallery_table.py my.toml ...  # print the table for your files

Without arguments the script computes one row per problem (``problems/paper.toml``,
then ``problems/gallery/*.toml`` in name order) and replaces what lies between the
two markers of ``docs/guide/gallery.md``, recording the date, the machine, the git
commit and its own run time; the rest of the page is left as it is. With problem
files it prints their table to stdout and writes nothing.

Per problem: CubeSats, engines, total mass, the full rigid inertia's diagonal, the
torque authority with zero net force per signed axis (an LP over the engines), the
weakest axis' authority over the disturbance amplitude, the rigid time-optimal 180°
slews about x, y and z at thruster level with zero net force (IPOPT: a local
optimum), the z slew's propellant and the budget's one-stage all-faces Δv. A slew
that fails shows ``failed: <reason>`` in its cell.
"""

from __future__ import annotations

import argparse
import datetime
import math
import os
import platform
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import casadi
import numpy as np

from casadi_debris import load_problem
from casadi_debris.budgets import budgets_as_dict, compute_budgets
from casadi_debris.config import Problem, default_problem_path
from casadi_debris.errors import CasadiDebrisError
from casadi_debris.geometry import build_geometry, torque_authority
from casadi_debris.slews import time_optimal_slew

REPOSITORY = Path(__file__).resolve().parents[2]
PAGE = REPOSITORY / "docs" / "guide" / "gallery.md"
BEGIN = "<!-- gallery-table:begin (written by docs/_scripts/gallery_table.py; do not edit) -->"
END = "<!-- gallery-table:end -->"
AXES = ("x", "y", "z")
SLEW_ANGLE_RAD = math.pi
MNM_PER_NM = 1e3
G_PER_KG = 1e3
STATUS_NOTES = {"Solve_Succeeded": "", "Solved_To_Acceptable_Level": " (acceptable)"}
"""What a slew's cell adds to its duration for IPOPT's return status (others verbatim)."""
HEADER = (
    "| problem | CubeSats | engines | total mass [kg] "
    "| inertia diagonal, full rigid [kg m²] "
    "| torque authority, zero net force, x / y / z [mNm] "
    "| weakest axis / disturbance "
    "| 180° slew about x [s] | about y [s] | about z [s] "
    "| z slew fuel [g] | Δv, one stage, all faces [m/s] |\n"
    "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |"
)


@dataclass(frozen=True)
class Slew:
    """One time-optimal slew: its duration and fuel, or why it failed."""

    duration_s: float = math.nan
    fuel_kg: float = math.nan
    status: str = ""
    failure: str = ""

    def cell(self) -> str:
        if self.failure:
            return f"failed: {self.failure}"
        note = STATUS_NOTES.get(self.status, f" ({self.status})")
        return f"{self.duration_s:.1f}{note}"


def problem_files() -> list[Path]:
    """The paper's problem, then the gallery's in name order."""
    paper = default_problem_path()
    return [paper, *sorted((paper.parent / "gallery").glob("*.toml"))]


def label(path: Path) -> str:
    """``paper`` or ``gallery/<name>`` for the shipped files, else the path as given."""
    problems = default_problem_path().parent
    try:
        return f"`{path.resolve().relative_to(problems).with_suffix('').as_posix()}`"
    except ValueError:
        return f"`{path}`"


def one_line(error: BaseException) -> str:
    """An error as one table-safe line."""
    text = " ".join(str(error).split()) or type(error).__name__
    return text.replace("|", "\\|")


def time_optimal(problem: Problem, axis: str) -> Slew:
    """The rigid time-optimal 180° slew about ``axis``, thruster level, zero net force."""
    try:
        slew = time_optimal_slew(
            problem,
            axis,
            SLEW_ANGLE_RAD,
            thrusters=True,
            zero_net_force=True,
            check_vibration=False,
        )
    except (CasadiDebrisError, RuntimeError) as error:  # infeasible, IPOPT, CasADi
        return Slew(failure=one_line(error))
    return Slew(slew.duration_s, slew.fuel_kg, slew.solver_status)


def authority_cell(authority: dict[str, float]) -> str:
    """``4.61 / 2.02 / 4.32``; an axis whose signs differ as ``+4.99 −1.15``."""
    parts = []
    for axis in AXES:
        plus, minus = (max(0.0, MNM_PER_NM * authority[f"{sign}{axis}"]) for sign in "+-")
        if math.isclose(plus, minus, rel_tol=1e-6, abs_tol=1e-9):
            parts.append(f"{plus:.2f}")
        else:
            parts.append(f"+{plus:.2f} −{minus:.2f}")
    return " / ".join(parts)


def margin_cell(authority: dict[str, float], amplitude_mNm: np.ndarray) -> str:
    """min over the axes of (weaker sign's authority) / (that axis' disturbance amplitude)."""
    ratios = {}
    for axis, amplitude in zip(AXES, np.abs(amplitude_mNm), strict=True):
        if amplitude > 0.0:
            weaker = max(0.0, MNM_PER_NM * min(authority[f"+{axis}"], authority[f"-{axis}"]))
            ratios[axis] = weaker / amplitude
    if not ratios:
        return "no disturbance"
    axis = min(ratios, key=lambda a: ratios[a])
    return f"{ratios[axis]:.2f} ({axis})"


def row(path: Path) -> str:
    """The table row of one problem file."""
    problem = load_problem(path)
    geometry = build_geometry(problem)
    authority = torque_authority(geometry, zero_net_force=True)
    slews = {axis: time_optimal(problem, axis) for axis in AXES}
    z = slews["z"]
    fuel = "–" if z.failure else f"{G_PER_KG * z.fuel_kg:.3f}"
    dv = budgets_as_dict(compute_budgets(problem, geometry))["dv_one_stage_all_faces_m_s"]
    inertia = np.diag(geometry.inertia_total_kgm2)
    cells = [
        label(path),
        str(len(geometry.cubesats)),
        str(len(geometry.engines)),
        f"{geometry.mass_kg:.1f}",
        " / ".join(f"{value:.1f}" if value < 1e4 else f"{value:.0f}" for value in inertia),
        authority_cell(authority),
        margin_cell(authority, problem.disturbance.amplitude_mNm),
        *(slews[axis].cell() for axis in AXES),
        fuel,
        f"{dv:.1f}",
    ]
    return "| " + " | ".join(cells) + " |"


def table(paths: list[Path]) -> str:
    """The Markdown table, one row per problem, each printed to stderr as it is done."""
    rows = []
    for path in paths:
        started = time.perf_counter()
        rows.append(row(path))
        print(f"{path.name}: {time.perf_counter() - started:.1f} s", file=sys.stderr)
    return "\n".join([HEADER, *rows])


def git_commit() -> str:
    """HEAD's hash, and whether src/ differs from it."""
    try:
        head = subprocess.run(
            ["git", "rev-parse", "HEAD"],
            cwd=REPOSITORY,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        changed = subprocess.run(
            ["git", "status", "--porcelain", "--", "src"],
            cwd=REPOSITORY,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown (no git checkout)"
    if not changed:
        return f"`{head}`"
    paths = [line[3:] for line in changed.splitlines()]
    shown = ", ".join(f"`{path}`" for path in paths[:5]) + (", ..." if len(paths) > 5 else "")
    return f"`{head}` with uncommitted changes to {shown}"


def machine() -> str:
    """CPU, cores, OS and the versions that set the numbers."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as cpuinfo:
            names = [line.split(":", 1)[1].strip() for line in cpuinfo if "model name" in line]
        cpu = names[0] if names else cpu
    except OSError:
        pass
    return (
        f"{cpu}, {os.cpu_count()} CPUs, {platform.system()} {platform.machine()}, "
        f"Python {platform.python_version()}, CasADi {casadi.__version__}"
    )


def rewrite_page(body: str, begin: str = BEGIN, end: str = END) -> None:
    """Replace what lies between the page's markers ``begin`` and ``end`` with ``body``."""
    text = PAGE.read_text(encoding="utf-8")
    if text.count(begin) != 1 or text.count(end) != 1 or text.index(begin) > text.index(end):
        raise SystemExit(f"{PAGE}: needs one line {begin!r} and, after it, one {end!r}")
    head, rest = text.split(begin)
    _, tail = rest.split(end)
    PAGE.write_text(f"{head}{begin}\n{body}\n{end}{tail}", encoding="utf-8")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "problems",
        nargs="*",
        type=Path,
        help="problem files: print their table instead of rewriting docs/guide/gallery.md",
    )
    arguments = parser.parse_args(argv)
    started = time.perf_counter()
    commit = git_commit()  # before the run: the checkout that computed the numbers
    result = table(arguments.problems or problem_files())
    if arguments.problems:
        print(result)
        return
    elapsed = time.perf_counter() - started
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    record = (
        f"Computed {now} by `python docs/_scripts/gallery_table.py` in {elapsed:.0f} s "
        f"(one process), at commit {commit}, on {machine()}."
    )
    rewrite_page(f"\n{result}\n\n{record}\n")
    print(f"wrote {PAGE} in {elapsed:.0f} s", file=sys.stderr)


if __name__ == "__main__":
    main()
