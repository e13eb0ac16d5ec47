"""The mission as a run folder (``casadi-debris mission``).

Files: ``summary.json`` (:class:`~casadi_debris.studies.mission.MissionSummary`),
``phases.csv`` (the timeline), ``propellant.csv`` (per CubeSat and phase, g),
``mission.png`` (timeline and propellant) and ``decay.png`` (perigee and apogee per solar
case, from the burn's start).
"""

from __future__ import annotations

import csv
from pathlib import Path

from casadi_debris.plots.deorbit import plot_decay
from casadi_debris.plots.mission import plot_mission
from casadi_debris.report.common import write_json_atomic
from casadi_debris.studies.mission import Mission

G_PER_KG = 1e3


def write_mission(folder: Path, mission: Mission) -> None:
    """Every file of the run folder (see the module's text)."""
    summary = mission.summary
    write_json_atomic(folder / "summary.json", summary)
    with (folder / "phases.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["phase", "start_days", "duration_days", "dv_m_s", "propellant_kg", "note"])
        for p in summary.phases:
            writer.writerow(
                [p.name, p.start_days, p.duration_days, p.dv_m_s, p.propellant_kg, p.note]
            )
    with (folder / "propellant.csv").open("w", newline="") as handle:
        writer = csv.writer(handle)
        phases = list(summary.propellant_per_cubesat_kg)
        writer.writerow(["cubesat", *(f"{name.replace(' ', '_')}_g" for name in phases)])
        columns = [summary.propellant_per_cubesat_kg[name] for name in phases]
        for k, row in enumerate(zip(*columns, strict=True), start=1):
            writer.writerow([k, *(value * G_PER_KG for value in row)])
    plot_mission(summary, folder / "mission.png")
    plot_decay(
        mission.trajectories, folder / "decay.png", title=summary.problem,
        limit_years=summary.limit_years,
    )  # fmt: skip
