"""The mission to re-entry: detumble, transfer, and the deorbit burn that brings the
debris down within five years, with the propellant each leg takes from the swarm.

Command line: ``casadi-debris mission paper``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

from _settings import QUICK, folder

import casadi_debris as cd

out = folder("mission_to_reentry")
solar = ("mean",) if QUICK else ("low", "mean", "high")
mission = cd.mission("paper", solar=solar)
summary = mission.summary.to_json()
for key in ("deorbit_dv_m_s", "governing_case", "meets_five_year_rule"):
    print(f"{key}: {summary[key]}")
for name, figure in mission.plot().items():
    figure.savefig(out / f"{name}.png", dpi=110)
print(f"written to {out}")
