"""A controller designed for a new debris and flown on it.

``design`` derives the weights from the body (its authority, inertia and modes),
synthesises the controller, checks its margins and flies the problem's slew and
pointing over the uncertainty corners; ``simulate`` then flies the designed controller,
bound to the plant it was designed for.

Command line: ``casadi-debris design one_array --out runs/design-one_array`` then
``casadi-debris simulate one_array --controller runs/design-one_array/controller.json``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

from _settings import QUICK, folder

import casadi_debris as cd

out = folder("design_and_fly")
problem = "rigid_no_arrays" if QUICK else "one_array"
design = cd.design(
    problem,
    out=out / "design",
    overwrite=True,
    quick=QUICK,
    method="pd" if QUICK else "mu",  # quick: a PD design in seconds, not mu-synthesis
    workers=1 if QUICK else None,
)
summary = design.summary.to_json()
print(f"design for {problem}: requirements met {summary['requirements_met']}")
controller = design.folder / "controller.json"

run = cd.simulate(problem, controller=controller, duration_s=300.0 if QUICK else None)
print(
    f"flown: largest error {run.summary.max_error_deg:.4f} deg, fuel {run.summary.fuel_kg:.3e} kg, "
    f"requirements met: {run.summary.requirements_met}"
)
for name, figure in run.plot().items():
    figure.savefig(out / f"{name}.png", dpi=110)
print(f"written to {out}")
