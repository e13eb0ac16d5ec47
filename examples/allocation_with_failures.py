"""Thrust allocation with failed CubeSats and engines: which torque the swarm still
gives, at what thrust per engine and what propellant rate.

Command line: ``casadi-debris allocate --torque-mNm 1,-0.5,0.8 --failed 3 --failed-engines 5:1``
(every id 1-based, as ``casadi-debris model`` lists them).
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

from _settings import folder

import casadi_debris as cd

out = folder("allocation_with_failures")
torque_mNm = (1.0, -0.5, 0.8)

healthy = cd.allocate("paper", torque_mNm=torque_mNm)
degraded = cd.allocate("paper", torque_mNm=torque_mNm, failed=[3], failed_engines=[(5, 1)])
for name, result in (("healthy", healthy), ("CubeSat 3 and engine 5:1 failed", degraded)):
    summary = result.summary
    print(
        f"{name}: feasible {summary.feasible}, torque made {summary.torque_achieved_mNm} mNm, "
        f"propellant {summary.fuel_rate_kg_s:.3e} kg/s"
    )

# What the failures cost in authority, per signed axis [mNm].
for axis, before in healthy.summary.torque_authority_mNm.items():
    after = degraded.summary.torque_authority_mNm[axis]
    print(f"  {axis}: {before:.3f} -> {after:.3f} mNm")

for name, figure in degraded.plot().items():
    figure.savefig(out / f"{name}.png", dpi=110)
print(f"written to {out}")
