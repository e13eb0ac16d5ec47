"""Fly the paper's 180° slew in closed loop, then fly it about another axis.

One call runs the μ controller, the allocator and the staged engines on the flexible
model; the result holds the arrays (SI), the summary the command prints, and the
figures.

Command line: ``casadi-debris simulate paper_slew --out runs/slew``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

from _settings import QUICK, folder

import casadi_debris as cd

out = folder("fly_a_slew")
duration_s = 120.0 if QUICK else None  # quick: the first two minutes only

run = cd.simulate("paper_slew", duration_s=duration_s)
summary = run.summary
print(f"paper slew: largest error {summary.max_error_deg:.4f} deg, fuel {summary.fuel_kg:.3e} kg")
print(f"requirements met: {summary.requirements_met}")

# The error is in body axes, rad, one row per control instant.
error_deg = run.result.error_rad * 180.0 / 3.141592653589793
print(f"final error [deg]: {error_deg[-1].round(5).tolist()}")

# The same slew about the body's x axis, with CubeSat 3 failed from the start.
turned = cd.simulate("paper_slew", axis="x", failed=[3], duration_s=duration_s)
print(
    f"about x with CubeSat 3 failed: largest error {turned.summary.max_error_deg:.4f} deg, "
    f"requirements met: {turned.summary.requirements_met}"
)

for name, figure in run.plot().items():
    figure.savefig(out / f"{name}.png", dpi=110)
run.save(out / "run", overwrite=True)
print(f"written to {out}")
