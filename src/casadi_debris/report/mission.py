"""The mission as a run folder (``casadi-debris mission``).

Files: ``summary.json`` (:class:`~casadi_debris.studies.mission.MissionSummary`),
``phases.csv`` (the timeline), ``propellant.csv`` (per CubeSat, stage and phase, g,
with each stage's capacity and what is left), ``mission.png`` (timeline, and propellant
per CubeSat and stage stacked by phase), ``altitude.png`` (mean altitude and perigee per
solar case from the start of the transfer) and ``decay.png`` (perigee and apogee per
solar case, from the burn's start); every figure also as PDF.
"""

from __future__ import annotations

import csv
from pathlib import Path

from casadi_debris.plots.deorbit import plot_decay
from casadi_debris.plots.mission import plot_altitude, plot_mission
from casadi_debris.report.common import write_json_atomic
from casadi_debris.studies.mission import Mission
from casadi_debris.units import G_PER_KG


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
        phases = [book.phase.replace(" ", "_") + "_g" for book in summary.books]
        writer.writerow(["cubesat", "stage", "capacity_g", *phases, "left_g"])
        for k, capacity in enumerate(summary.capacity_per_stage_kg):
            for s, full in enumerate(capacity):
                burnt = [book.per_stage_kg[k][s] for book in summary.books]
                left = full - sum(burnt)
                writer.writerow([k + 1, s + 1, *(G_PER_KG * v for v in (full, *burnt, left))])
    plot_mission(summary, folder / "mission.png")
    plot_altitude(summary, mission.trajectories, folder / "altitude.png")
    plot_decay(
        mission.trajectories, folder / "decay.png", title=summary.problem,
        limit_years=summary.limit_years,
    )  # fmt: skip
