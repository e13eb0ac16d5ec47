"""Fuel budgets of two swarm designs side by side: the paper's four CubeSats per face
against two per face.

Command line: ``casadi-debris budget paper --json`` and
``casadi-debris budget two_per_face --json``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt
from _settings import folder

import casadi_debris as cd

out = folder("budgets_compared")
designs = ("paper", "two_per_face")
keys = (
    "dv_one_stage_one_face_m_s",
    "dv_three_stages_one_face_m_s",
    "dv_one_stage_all_faces_m_s",
    "dv_all_stages_all_faces_m_s",
)
budgets = {name: cd.budget(name).summary.to_json() for name in designs}
for key in keys:
    print(f"{key:>32}: " + "  ".join(f"{name} {budgets[name][key]:7.1f}" for name in designs))
print(
    "detumble from 1 rad/s [h]: "
    + "  ".join(f"{n} {budgets[n]['detumble_time_h']:.1f}" for n in designs)
)

figure, axes = plt.subplots(figsize=(7, 3.5))
width = 0.38
for offset, name in enumerate(designs):
    axes.bar(
        [i + (offset - 0.5) * width for i in range(len(keys))],
        [budgets[name][key] for key in keys],
        width,
        label=name,
    )
axes.set_xticks(range(len(keys)), ["1 stage, 1 face", "3 stages, 1 face", "1 stage, all", "all"])
axes.set_ylabel("Δv [m/s]")
axes.legend()
figure.tight_layout()
figure.savefig(out / "budgets.png", dpi=110)
print(f"written to {out}")
