"""A Monte-Carlo campaign over the uncertainty set, opened as an xarray Dataset.

Each case is one closed-loop run of the paper's slew on a sampled plant; the dataset
holds every case's figures with their seed. ``out=`` would write the campaign case by
case (and resume it after a Ctrl-C); here it stays in memory.

Command line: ``casadi-debris montecarlo paper_slew --samples 16 --out runs/mc``.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

from _settings import QUICK, folder

import casadi_debris as cd

out = folder("montecarlo_in_xarray")
campaign = cd.montecarlo(
    "paper_slew",
    samples=4 if QUICK else 64,
    max_cases=4 if QUICK else None,
    workers=1 if QUICK else None,
)
data = campaign.dataset  # one row per case along "case", time series along "time"
print(f"dimensions: {dict(data.sizes)}")
errors = data["max_error_deg"]
print(f"largest error [deg]: median {float(errors.median()):.4f}, worst {float(errors.max()):.4f}")
worst = data.isel(case=int(errors.argmax(dim="case")))
print(f"worst case {worst['case'].item()}: fuel {float(worst['fuel_kg']):.3e} kg")
statistics = campaign.summary.to_json()["statistics"]
print(
    f"{statistics['passed']} of {statistics['cases']} cases meet "
    f"{statistics['requirement_figure']} <= {statistics['requirement']}"
)
for name, figure in campaign.plot().items():
    figure.savefig(out / f"{name.replace('/', '_')}.png", dpi=110)
print(f"written to {out}")
