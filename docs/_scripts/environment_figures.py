"""The figures and the figures' numbers of docs/guide/environment.md.

Run from anywhere (the package must import: installed, or ``PYTHONPATH=src``)::

    python docs/_scripts/environment_figures.py

Writes

- ``docs/figures/environment_torques_one_orbit.png``: the four environment
  torques on the paper's debris (nominal, arrays at 0 deg) holding the inertial
  attitude of the pointing run (body axes = inertial axes) over one orbit of
  ``problems/paper_environment.toml``, beside the paper's 0.7 mNm sine;
- ``docs/figures/environment_pointing.png``: the paper's pointing run
  (``paper_pointing``), the same run with the environment torques instead of
  the sine, and with both (``paper_environment``): the attitude error per axis
  against the 60 arcsec requirement;

and prints the peak of each torque and the runs' largest errors as JSON.
Takes a few minutes (three one-orbit runs, compiled).
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
from casadi_debris.config import ENVIRONMENT_TORQUES, Problem, default_controller_path
from casadi_debris.dynamics import build_model
from casadi_debris.environment import EnvironmentTorques
from casadi_debris.geometry import build_geometry
from casadi_debris.guidance import scenario_reference
from casadi_debris.robust.plant import Controller
from casadi_debris.simulation import LoopSettings, simulate_closed_loop
from casadi_debris.units import ARCSEC_PER_RAD, MNM_PER_NM

FIGURES = Path(__file__).resolve().parents[1] / "figures"
TITLES = {
    "gravity_gradient": "gravity gradient",
    "aerodynamic": "aerodynamic (ρ = 1e-13 kg/m³)",
    "solar_pressure": "solar pressure",
    "magnetic": "residual dipole (1 A m²)",
}
# Skipped at the start of the runs when quoting the steady error: the environment
# torques switch on at t = 0 on a loop at rest (a kick the real loop never sees).
SETTLED_S = 600.0


def torques_over_one_orbit() -> dict[str, float]:
    problem = load_problem("paper_environment")
    geometry = build_geometry(problem)
    environment = EnvironmentTorques.of(problem, geometry)
    period = environment.orbit.period_s
    times = np.linspace(0.0, period, 721)
    series = {name: [] for name in ENVIRONMENT_TORQUES}
    for t in times:
        for name, tau in environment.torques(t, np.eye(3), geometry.inertia_total_kgm2).items():
            series[name].append(tau)
    sine = problem.disturbance.amplitude_mNm[0]
    figure, axes = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
    for ax, name in zip(axes, ENVIRONMENT_TORQUES, strict=True):
        values = np.array(series[name]) * MNM_PER_NM
        for axis, label in enumerate(("x", "y", "z")):
            ax.plot(times / 60.0, values[:, axis], label=f"τ{label}")
        ax.set_title(TITLES[name], fontsize=10)
        ax.set_ylabel("torque [mNm]")
        ax.grid(alpha=0.3)
    axes[0].axhline(sine, color="grey", ls="--", lw=0.8, label="paper's sine amplitude")
    axes[0].axhline(-sine, color="grey", ls="--", lw=0.8)
    axes[0].legend(loc="upper right", fontsize=8, ncol=4)
    axes[-1].set_xlabel("time [min] (one orbit at 685 km, 98.1°, held inertial attitude)")
    figure.suptitle("Environment torques on the paper's debris over one orbit")
    figure.tight_layout()
    figure.savefig(FIGURES / "environment_torques_one_orbit.png", dpi=120)
    plt.close(figure)
    return {
        f"{name}_peak_mNm": float(np.abs(np.array(series[name])).max() * MNM_PER_NM)
        for name in ENVIRONMENT_TORQUES
    }


def _variants() -> dict[str, Problem]:
    """The paper's pointing run, its disturbance replaced by the environment, and both."""
    both = load_problem("paper_environment")
    silent = dataclasses.replace(both.disturbance, amplitude_mNm=np.zeros(3))
    return {
        "paper_pointing": load_problem("paper_pointing"),
        "environment_only": dataclasses.replace(both, disturbance=silent),
        "paper_environment": both,
    }


TITLE = {
    "paper_pointing": "ideal: the paper's 0.7 mNm sine",
    "environment_only": "the environment torques instead of the sine",
    "paper_environment": "the sine + the environment torques",
}


def pointing_runs() -> dict[str, float]:
    record = Controller.from_dict(json.loads(default_controller_path().read_text()))
    figure, axes = plt.subplots(3, 1, figsize=(8, 8.5), sharex=True)
    numbers = {}
    for ax, (name, problem) in zip(axes, _variants().items(), strict=True):
        model = build_model(problem)
        jit = LoopSettings(jit=True)
        result = simulate_closed_loop(
            model, record.reduced, scenario_reference(problem), settings=jit
        )
        error = result.error_rad * ARCSEC_PER_RAD
        for axis, label in enumerate(("Φ", "Θ", "Ψ")):
            ax.plot(result.time_s / 60.0, error[:, axis], lw=0.8, label=label)
        limit = problem.requirements.pointing_arcsec
        ax.axhline(limit, color="red", ls="--", lw=0.8, label=f"requirement ±{limit:g}″")
        ax.axhline(-limit, color="red", ls="--", lw=0.8)
        worst = float(np.abs(error).max())
        settled = float(np.abs(error[result.time_s >= SETTLED_S]).max())
        numbers[f"{name}_max_error_arcsec"] = worst
        numbers[f"{name}_max_error_after_{SETTLED_S:g}_s_arcsec"] = settled
        numbers[f"{name}_peak_disturbance_mNm"] = float(
            np.abs(result.disturbance_Nm).max() * MNM_PER_NM
        )
        numbers[f"{name}_fuel_kg"] = float(result.fuel_per_cubesat_kg.sum())
        ax.set_title(f"{TITLE[name]}: max {worst:.1f}″", fontsize=10)
        ax.set_ylabel("attitude error [arcsec]")
        ax.set_ylim(-1.25 * limit, 1.25 * limit)
        ax.grid(alpha=0.3)
        ax.legend(loc="lower right", fontsize=8, ncol=4)
    axes[-1].set_xlabel("time [min]")
    figure.suptitle("The paper's one-orbit pointing, with and without the environment torques")
    figure.tight_layout()
    figure.savefig(FIGURES / "environment_pointing.png", dpi=120)
    plt.close(figure)
    return numbers


def main() -> None:
    numbers = torques_over_one_orbit()
    numbers |= pointing_runs()
    print(json.dumps(numbers, indent=2))


if __name__ == "__main__":
    main()
