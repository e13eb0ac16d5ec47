"""A placement study as files: ``placement.toml``, ``summary.json``, ``report.md``, figures.

``placement.toml`` is a problem file: ``extends`` the input problem (by its
absolute path) and lists the chosen CubeSats explicitly (``[[cubesats]]`` with
their ``[[cubesats.engines]]``), numbers written in full precision so that the
file loads to exactly the layout the study judged.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from casadi_debris.config import CubeSat, Problem
from casadi_debris.report._common import format_figure
from casadi_debris.store import write_json_atomic
from casadi_debris.studies.placement import ParetoPoint, PlacementStudy, PlacementSummary

if TYPE_CHECKING:
    from matplotlib.figure import Figure

PLACEMENT_FILE = "placement.toml"
NAME_LENGTH = 64
SUFFIX = "-placement"


def _number(value: float) -> str:
    return repr(float(value))


def _vector(values: np.ndarray) -> str:
    return "[" + ", ".join(_number(v + 0.0) for v in np.asarray(values, dtype=float)) + "]"


def _cubesat_toml(cubesat: CubeSat) -> list[str]:
    inertia = ", ".join(_vector(row) for row in cubesat.inertia_kgm2)
    lines = ["", "[[cubesats]]", f"position_corner_m = {_vector(cubesat.position_corner_m)}"]
    if cubesat.face is not None:
        lines.append(f'face = "{cubesat.face}"')
    lines += [f"mass_kg = {_number(cubesat.mass_kg)}", f"inertia_kgm2 = [{inertia}]"]
    for engine in cubesat.engines:
        lines += [
            "",
            "[[cubesats.engines]]",
            f"direction = {_vector(engine.direction)}",
            f"offset_m = {_vector(engine.offset_m)}",
            f"stages = {engine.stages}",
            f"emitters_per_stage = {engine.emitters_per_stage}",
            f"thrust_per_stage_mN = {_number(engine.thrust_per_stage_mN)}",
            f"isp_s = {_number(engine.isp_s)}",
            f"stage_life_h = {_number(engine.stage_life_h)}",
        ]
    return lines


def placement_toml(problem: Problem, cubesats: tuple[CubeSat, ...], note: str) -> str:
    """A problem file extending ``problem`` with these CubeSats (see the module).

    Parameters
    ----------
    problem : Problem
        Loaded from a file (``problem.source``), which the result extends.
    cubesats : tuple of CubeSat
    note : str
        One line for the file's description (what was optimised).
    """
    name = problem.name[: NAME_LENGTH - len(SUFFIX)] + SUFFIX
    source = str(Path(problem.source).resolve())
    description = (
        f"{problem.name} with {len(cubesats)} CubeSats placed by casadi-debris placement: {note}"
    )
    header = [
        "# Written by casadi-debris placement. Everything but the CubeSats comes from the",
        "# problem it extends; its [weights] scalings were set for that problem's swarm.",
        f"extends = {json.dumps(source)}",
        f"name = {json.dumps(name)}",
        f"description = {json.dumps(description)}",
    ]
    body = [line for cubesat in cubesats for line in _cubesat_toml(cubesat)]
    return "\n".join(header + body) + "\n"


def failure_label(failures: int) -> str:
    """What the failure row counts: the least authority over disturbance of any signed
    axis, over every set of ``failures`` CubeSats failed at once."""
    if failures == 0:
        return "worst authority / disturbance, no CubeSat failed"
    sets = "any one CubeSat failed" if failures == 1 else f"any {failures} CubeSats failed together"
    return f"worst authority / disturbance, {sets}"


def placement_markdown(summary: PlacementSummary) -> str:
    """``report.md``: the chosen layout beside the input one, the solver's status."""
    solver, chosen, own = summary.solver, summary.figures, summary.input_layout.figures
    rows = [
        ("CubeSats", chosen.count, own.count),
        ("worst axis", chosen.worst_axis, own.worst_axis),
        ("worst authority / disturbance", chosen.worst_ratio, own.worst_ratio),
        (
            "authority +x,-x,+y,-y,+z,-z [mNm]",
            list(chosen.torque_max_zero_force_mNm.values()),
            list(own.torque_max_zero_force_mNm.values()),
        ),
        (
            failure_label(summary.worst_failure.failures),
            summary.worst_failure.worst_ratio,
            summary.input_layout.worst_failure.worst_ratio,
        ),
        (
            "rigid slew x,y,z [s]",
            list(chosen.rigid_slew_s.values()),
            list(own.rigid_slew_s.values()),
        ),
        (
            "one-stage Δv, weakest direction [m/s]",
            chosen.weakest_dv_one_stage_m_s,
            own.weakest_dv_one_stage_m_s,
        ),
        (
            "added inertia x,y,z [kg m²]",
            list(chosen.added_inertia_kgm2.values()),
            list(own.added_inertia_kgm2.values()),
        ),
    ]
    lines = [
        f"# Placement for {summary.problem} ({summary.objective})",
        "",
        "| figure | chosen | input layout |",
        "| --- | --- | --- |",
        *(f"| {name} | {_cell(a)} | {_cell(b)} |" for name, a, b in rows),
        "",
        f"Solver: {solver.backend}, {solver.method} form, "
        f"{'optimal' if solver.optimal else 'NOT proven optimal'}: objective "
        f"{format_figure(solver.objective)}, bound {format_figure(solver.upper_bound)}, "
        f"gap {format_figure(solver.gap)}, {format_figure(solver.time_s)} s.",
        "",
        "![layout](layout.png)",
    ]
    if summary.pareto:
        lines += ["", "![Pareto front](pareto.png)"]
    return "\n".join(lines) + "\n"


def _cell(value: Any) -> str:
    return value if isinstance(value, str) else format_figure(value)


def write_placement(
    folder: Path,
    study: PlacementStudy,
    summary: PlacementSummary,
    pareto: list[ParetoPoint],
    *,
    plots: bool = True,
) -> None:
    """``placement.toml``, ``summary.json``, ``report.md`` and, with ``plots``,
    ``layout.png`` (and ``pareto.png`` after a sweep)."""
    cubesats = study.candidates.cubesats(study.solution.chosen)
    (folder / PLACEMENT_FILE).write_text(
        placement_toml(
            study.problem,
            cubesats,
            f"{summary.objective}, worst ratio "
            f"{study.metrics.worst_ratio:.4g} ({study.metrics.worst_axis})",
        )
    )
    if plots:
        from casadi_debris.plots import save_figure

        for stem, figure in placement_figures(study, pareto).items():
            save_figure(figure, folder / f"{stem}.png")
    (folder / "report.md").write_text(placement_markdown(summary))
    write_json_atomic(folder / "summary.json", summary)


def placement_figures(study: PlacementStudy, pareto: list[ParetoPoint]) -> dict[str, Figure]:
    """``layout`` (the hub in three projections with the chosen CubeSats) and, after a
    sweep, ``pareto`` (worst authority against count, slew time and Δv)."""
    from casadi_debris.plots import layout_figure, pareto_figure

    figures = {"layout": layout_figure(study)}
    if pareto:
        figures["pareto"] = pareto_figure(pareto)
    return figures
