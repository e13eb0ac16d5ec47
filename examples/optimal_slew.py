"""An optimal slew of your own body: bang-bang against time-optimal, about any axis.

``rigid_no_arrays`` stands in for your debris (a problem file of your own works the same
way: ``cd.slew("my_debris.toml", ...)``). Every profile is checked against the engines:
``limits_ok`` says whether the allocator can give its torque at every instant.

Command line: ``casadi-debris slew rigid_no_arrays --method time-optimal --axis 1,1,1``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

from _settings import QUICK, folder

import casadi_debris as cd

out = folder("optimal_slew")
problem = "rigid_no_arrays"
angle_deg = 30.0 if QUICK else 180.0  # quick: a shorter turn solves in seconds

bang_bang = cd.slew(problem, method="bang-bang", axis=(1.0, 1.0, 1.0), angle_deg=angle_deg)
fastest = cd.slew(
    problem,
    method="time-optimal",
    axis=(1.0, 1.0, 1.0),
    angle_deg=angle_deg,
    starts=1 if QUICK else None,
    workers=1 if QUICK else None,
)
for name, result in (("bang-bang", bang_bang), ("time-optimal", fastest)):
    summary = result.summary
    print(
        f"{name:>12}: {summary.duration_s:8.1f} s, fuel {summary.fuel_kg:.3e} kg, "
        f"peak share of the engines' torque set {summary.worst_torque_set_ratio:.3f}, "
        f"limits ok: {summary.limits_ok}"
    )
assert fastest.summary.duration_s <= bang_bang.summary.duration_s

# The profile's arrays are SI: time [s], quaternion, rate [rad/s], torque [N m].
profile = fastest.profile
print(f"peak rate {abs(profile.rate_rad_s).max():.2e} rad/s over {len(profile.time_s)} samples")

for name, figure in fastest.plot().items():
    figure.savefig(out / f"time_optimal_{name}.png", dpi=110)
fastest.save(out / "time_optimal", overwrite=True)
print(f"written to {out}")
