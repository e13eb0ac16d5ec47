"""The figure and the numbers of docs/guide/realism.md.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/realism_figures.py

Writes ``docs/figures/realism_slew_pointing.png``: the paper's slew
(``paper_slew``) and one-orbit pointing (``paper_pointing``) with the paper's
ideal sensors and engines, beside the same runs with the realistic ones of
``problems/paper_realistic.toml`` (star tracker, MEMS gyro, MEKF, delay, engine
noise, misalignment, ramp, latency and minimum impulse bit), and the
estimator's error in the realistic pointing run. Prints the runs' figures as
JSON, with a slew whose engines are allocated by the step itself but have no
other effect (the cost of the step's axis-by-axis allocation alone).
Takes several minutes (five runs on CasADi's virtual machine).
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from casadi_debris import load_problem
from casadi_debris.config import Actuators, Problem, default_controller_path, realism_fields
from casadi_debris.dynamics import build_model
from casadi_debris.guidance import scenario_reference
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import ClosedLoopResult, simulate_closed_loop
from casadi_debris.units import ARCSEC_PER_RAD

FIGURES = Path(__file__).resolve().parents[1] / "figures"
# Skipped when quoting the pointing run's steady figures: the realistic
# estimator starts from the true attitude with its initial covariance.
SETTLED_S = 60.0
ALLOCATION_ONLY = Actuators(minimum_impulse_bit_uNs=1e-6)


def realistic(problem: Problem, realism: Problem) -> Problem:
    """``problem`` with the sensors, estimator, delay and engines of ``realism``."""
    return dataclasses.replace(problem, **realism_fields(realism))


def run(problem: Problem, record: Controller) -> ClosedLoopResult:
    return simulate_closed_loop(build_model(problem), record.reduced, scenario_reference(problem))


def figures(result: ClosedLoopResult) -> dict:
    summary = result.summary()
    settled = result.time_s >= SETTLED_S
    steady = np.abs(result.error_rad[settled]).max() * ARCSEC_PER_RAD
    figures = {
        "max_error_deg": summary.max_error_deg,
        "max_error_after_60s_arcsec": float(steady),
        "fuel_kg": summary.fuel_kg,
        "fuel_slew_kg": summary.fuel_slew_kg,
        "noise_seed": summary.noise_seed,
    }
    if summary.noise_seed is not None:
        estimation = result.estimation_error_rad[settled[:-1]] * ARCSEC_PER_RAD
        figures["estimation_error_rms_arcsec"] = float(np.sqrt(np.mean(estimation**2)))
    return figures


def main() -> None:
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    real = load_problem("paper_realistic")
    slew, pointing = load_problem("paper_slew"), load_problem("paper_pointing")
    runs = {
        "slew_ideal": run(slew, record),
        "slew_realistic": run(real, record),
        "pointing_ideal": run(pointing, record),
        "pointing_realistic": run(realistic(pointing, real), record),
        # Engines allocated by the step (1e-6 uNs: no engine is below it) and nothing else.
        "slew_step_allocation": run(dataclasses.replace(slew, actuators=ALLOCATION_ONLY), record),
        "pointing_step_allocation": run(
            dataclasses.replace(pointing, actuators=ALLOCATION_ONLY), record
        ),
    }
    numbers = {name: figures(result) for name, result in runs.items()}
    ideal_fuel = numbers["slew_ideal"]["fuel_slew_kg"]
    numbers["slew_step_allocation_fuel_over_allocator"] = (
        numbers["slew_step_allocation"]["fuel_slew_kg"] / ideal_fuel
    )
    numbers["pointing_step_allocation_fuel_over_allocator"] = (
        numbers["pointing_step_allocation"]["fuel_kg"] / numbers["pointing_ideal"]["fuel_kg"]
    )
    plot(runs, slew.requirements.slew_error_deg, pointing.requirements.pointing_arcsec)
    print(json.dumps(numbers, indent=2))


def plot(runs: dict[str, ClosedLoopResult], slew_limit_deg: float, pointing_arcsec: float) -> None:
    figure, axes = plt.subplots(3, 1, figsize=(8, 10))
    styles = {"ideal": {"color": "tab:blue"}, "realistic": {"color": "tab:orange", "alpha": 0.8}}
    for kind, style in styles.items():
        result = runs[f"slew_{kind}"]
        error = np.degrees(np.linalg.norm(result.error_rad, axis=1))
        axes[0].plot(result.time_s, error, lw=0.9, label=f"{kind} sensors and engines", **style)
        result = runs[f"pointing_{kind}"]
        error = np.abs(result.error_rad).max(axis=1) * ARCSEC_PER_RAD
        axes[1].plot(result.time_s / 60.0, error, lw=0.6, label=f"{kind}", **style)
    axes[0].axhline(slew_limit_deg, color="grey", ls="--", lw=0.8, label="requirement 0.6°")
    axes[0].set_ylabel("|attitude error| [deg]")
    axes[0].set_xlabel("time [s]")
    axes[0].set_title("180° slew about z in 1228 s (paper, Fig. 4)", fontsize=10)
    axes[1].axhline(pointing_arcsec, color="grey", ls="--", lw=0.8, label="requirement 60″")
    axes[1].set_ylabel("largest error component [arcsec]")
    axes[1].set_xlabel("time [min]")
    axes[1].set_title("Holding the attitude for one orbit (paper, Fig. 5)", fontsize=10)
    result = runs["pointing_realistic"]
    estimation = result.estimation_error_rad * ARCSEC_PER_RAD
    for axis, name in enumerate("xyz"):
        axes[2].plot(result.time_s[:-1] / 60.0, estimation[:, axis], lw=0.4, label=f"{name}")
    axes[2].set_ylabel("estimate − truth [arcsec]")
    axes[2].set_xlabel("time [min]")
    axes[2].set_title(
        "MEKF attitude error in the realistic pointing run (includes the tracker's bias)",
        fontsize=10,
    )
    for ax in axes:
        ax.grid(alpha=0.3)
        ax.legend(loc="upper right", fontsize=8, ncol=3)
    figure.suptitle("The paper's slew and pointing: ideal against realistic sensors and engines")
    figure.tight_layout()
    figure.savefig(FIGURES / "realism_slew_pointing.png", dpi=120)


if __name__ == "__main__":
    main()
