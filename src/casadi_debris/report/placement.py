"""A placement study as files: ``placement.toml``, ``summary.json``, ``report.md``, figures.

``placement.toml`` is a problem file: ``extends`` the input problem (by its
absolute path) and lists the chosen CubeSats explicitly (``[[cubesats]]`` with
their ``[[cubesats.engines]]``), numbers written in full precision so that the
file loads to exactly the layout the study judged.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, Problem
from casadi_debris.config.schema import CubeSat
from casadi_debris.plots.placement import plot_layout, plot_pareto
from casadi_debris.report.common import format_figure, write_json_atomic
from casadi_debris.studies.placement import InputLayout, PlacementStudy
from casadi_debris.studies.placement_authority import WorstFailures
from casadi_debris.studies.placement_metrics import LayoutMetrics
from casadi_debris.studies.placement_pareto import ParetoPoint
from casadi_debris.units import MNM_PER_NM

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


def _mNm(values: dict[str, float] | np.ndarray) -> dict[str, float]:
    if isinstance(values, dict):
        return {name: float(values[name]) * MNM_PER_NM for name in SIGNED_AXES}
    return {name: float(v) * MNM_PER_NM for name, v in zip(SIGNED_AXES, values, strict=True)}


def metrics_dict(metrics: LayoutMetrics) -> dict[str, Any]:
    """A layout's figures with units in the names."""
    return {
        "count": metrics.count,
        "torque_max_zero_force_mNm": _mNm(metrics.authority_Nm),
        "ratio_to_disturbance": {name: float(metrics.ratio[name]) for name in SIGNED_AXES},
        "worst_axis": metrics.worst_axis,
        "worst_ratio": metrics.worst_ratio,
        "rigid_slew_s": dict(zip(AXIS_NAMES, metrics.slew_s.tolist(), strict=True)),
        "slowest_slew_s": metrics.slowest_slew_s,
        "dv_one_stage_m_s": {name: metrics.dv_one_stage_m_s[name] for name in SIGNED_AXES},
        "weakest_dv_one_stage_m_s": metrics.weakest_dv_m_s,
        "added_inertia_kgm2": dict(
            zip(AXIS_NAMES, metrics.added_inertia_kgm2.tolist(), strict=True)
        ),
        "mass_kg": metrics.mass_kg,
    }


def failures_dict(
    worst: WorstFailures, ids: dict[int, int], disturbance_Nm: np.ndarray
) -> dict[str, Any]:
    """The worst failure set per axis, CubeSats by their 1-based ids in the layout."""
    ratio = worst.ratio(disturbance_Nm)
    return {
        "failures": worst.failures,
        "sets": worst.sets,
        "torque_min_zero_force_mNm": _mNm(worst.authority_Nm),
        "worst_ratio": float(np.min(ratio)),
        "failed": {
            name: sorted(ids[c] for c in failed)
            for name, failed in zip(SIGNED_AXES, worst.worst_set, strict=True)
        },
    }


def _input_dict(layout: InputLayout, disturbance_Nm: np.ndarray) -> dict[str, Any]:
    ids = {i: i + 1 for i in range(layout.metrics.count)}
    return {
        **metrics_dict(layout.metrics),
        "among_candidates": layout.among_candidates is not None,
        "worst_failure": failures_dict(layout.worst, ids, disturbance_Nm),
    }


def pareto_dicts(points: list[ParetoPoint]) -> list[dict[str, Any]]:
    return [
        {
            "label": p.label,
            "count": p.metrics.count,
            "worst_ratio": p.metrics.worst_ratio,
            "worst_axis": p.metrics.worst_axis,
            "slowest_slew_s": p.metrics.slowest_slew_s,
            "weakest_dv_one_stage_m_s": p.metrics.weakest_dv_m_s,
            "max_slew_s": p.max_slew_s,
            "optimal": p.optimal,
            "on_front": p.on_front,
            "candidates": None if p.chosen is None else [c + 1 for c in p.chosen],
        }
        for p in points
    ]


def placement_summary(
    study: PlacementStudy, objective: str, pareto: list[ParetoPoint]
) -> dict[str, Any]:
    """What ``summary.json`` and ``--json`` hold (display units in the names)."""
    solution, data_d = study.solution, np.abs(study.problem.disturbance.amplitude_mNm) / MNM_PER_NM
    ids = {candidate: i + 1 for i, candidate in enumerate(solution.chosen)}
    chosen = [
        {
            "cubesat": i + 1,
            "candidate": c.index + 1,
            "mount": c.mount + 1,
            "face": c.face,
            "template": c.template,
            "position_corner_m": c.cubesat.position_corner_m.tolist(),
        }
        for i, c in enumerate(study.chosen)
    ]
    candidates = study.candidates
    return {
        "problem": study.problem.name,
        "problem_sha256": study.problem.sha256,
        "objective": objective,
        "count_limits": list(study.settings.count),
        "candidates": {
            "grid_per_face": list(candidates.grid),
            "mounts": candidates.n_mounts,
            "candidates": len(candidates.candidates),
            "side_engines": list(candidates.side_engine_options),
        },
        "limits": {
            "max_added_inertia_kgm2": study.settings.max_added_inertia_kgm2,
            "max_slew_s": study.settings.max_slew_s,
            "slew_angle_deg": study.settings.slew_angle_deg,
        },
        "solver": _solver_dict(study),
        "chosen": chosen,
        **metrics_dict(study.metrics),
        "worst_failure": failures_dict(solution.worst, ids, data_d),
        "input_layout": _input_dict(study.input_layout, data_d),
        "pareto": pareto_dicts(pareto),
    }


def _solver_dict(study: PlacementStudy) -> dict[str, Any]:
    solution = study.solution
    return {
        "backend": "HiGHS (scipy.optimize.milp)",
        "optimal": solution.optimal,
        "objective": solution.objective,
        "upper_bound": solution.upper_bound,
        "gap": solution.gap,
        "mip_rel_gap": study.settings.mip_rel_gap,
        "method": solution.method,
        "blocks_extensive": solution.blocks_total,
        "blocks_used": solution.blocks_used,
        "time_s": solution.time_s,
        "solves": [
            {
                "status": s.status,
                "message": s.message,
                "time_s": s.time_s,
                "variables": s.variables,
                "binaries": s.binaries,
                "rows": s.rows,
                "blocks": s.blocks,
                "nodes": s.nodes,
                "mip_gap": s.mip_gap,
            }
            for s in solution.solves
        ],
    }


def placement_markdown(summary: dict[str, Any]) -> str:
    """``report.md``: the chosen layout beside the input one, the solver's status."""
    solver = summary["solver"]
    input_layout = summary["input_layout"]
    rows = [
        ("CubeSats", summary["count"], input_layout["count"]),
        ("worst axis", summary["worst_axis"], input_layout["worst_axis"]),
        ("worst authority / disturbance", summary["worst_ratio"], input_layout["worst_ratio"]),
        (
            "authority +x,-x,+y,-y,+z,-z [mNm]",
            list(summary["torque_max_zero_force_mNm"].values()),
            list(input_layout["torque_max_zero_force_mNm"].values()),
        ),
        (
            f"worst of {summary['worst_failure']['failures']} failed: authority / disturbance",
            summary["worst_failure"]["worst_ratio"],
            input_layout["worst_failure"]["worst_ratio"],
        ),
        (
            "rigid slew x,y,z [s]",
            list(summary["rigid_slew_s"].values()),
            list(input_layout["rigid_slew_s"].values()),
        ),
        (
            "one-stage Δv, weakest direction [m/s]",
            summary["weakest_dv_one_stage_m_s"],
            input_layout["weakest_dv_one_stage_m_s"],
        ),
        (
            "added inertia x,y,z [kg m²]",
            list(summary["added_inertia_kgm2"].values()),
            list(input_layout["added_inertia_kgm2"].values()),
        ),
    ]
    lines = [
        f"# Placement for {summary['problem']} ({summary['objective']})",
        "",
        "| figure | chosen | input layout |",
        "| --- | --- | --- |",
        *(f"| {name} | {_cell(a)} | {_cell(b)} |" for name, a, b in rows),
        "",
        f"Solver: {solver['backend']}, {solver['method']} form, "
        f"{'optimal' if solver['optimal'] else 'NOT proven optimal'}: objective "
        f"{format_figure(solver['objective'])}, bound {format_figure(solver['upper_bound'])}, "
        f"gap {format_figure(solver['gap'])}, {format_figure(solver['time_s'])} s.",
        "",
        "![layout](layout.png)",
    ]
    if summary["pareto"]:
        lines += ["", "![Pareto front](pareto.png)"]
    return "\n".join(lines) + "\n"


def _cell(value: Any) -> str:
    return value if isinstance(value, str) else format_figure(value)


def write_placement(
    folder: Path, study: PlacementStudy, summary: dict[str, Any], pareto: list[ParetoPoint]
) -> None:
    """``placement.toml``, ``summary.json``, ``report.md``, ``layout.png`` (and ``pareto.png``)."""
    cubesats = study.candidates.cubesats(study.solution.chosen)
    (folder / PLACEMENT_FILE).write_text(
        placement_toml(
            study.problem,
            cubesats,
            f"{summary['objective']}, worst ratio "
            f"{study.metrics.worst_ratio:.4g} ({study.metrics.worst_axis})",
        )
    )
    plot_layout(study, folder / "layout.png")
    if pareto:
        plot_pareto(pareto, folder / "pareto.png")
    (folder / "report.md").write_text(placement_markdown(summary))
    write_json_atomic(folder / "summary.json", summary)
