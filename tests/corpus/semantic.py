"""``M…`` entries: each value well typed and in its own range, the problem still wrong.

Values checked against other keys or against physics (a stage's propellant
heavier than its CubeSat, an inertia that breaks the triangle inequality, a
failure of a CubeSat that does not exist ...), and controls that must pass.
"""

from __future__ import annotations

import copy
import math
from typing import Any

from .entry import Entry, FileSpec
from .expectations import Path_
from .mutations import get_path, set_path
from .problem_files import problem_runs
from .shipped import flattened
from .toml_writer import toml_dumps

_FAILURE = {"cubesat": 1, "time_s": 10.0}

# (description, base problem, {path: value}, expect, names, fast); the value None
# deletes duration_s from the table at that path.
CASES: list[tuple[str, str, dict[Path_, Any], str, tuple[str, ...], bool]] = [
    (
        "a stage's propellant heavier than its CubeSat (stage_life_h = 50000)",
        "paper",
        {("engine", "stage_life_h"): 50000.0},
        "reject",
        ("engine.", "cubesats.mass_kg"),
        True,
    ),
    (
        "CubeSat of 0.1 kg, lighter than its propellant",
        "paper",
        {("cubesats", "mass_kg"): 0.1},
        "reject",
        ("engine.", "cubesats.mass_kg"),
        False,
    ),
    (
        "hub inertia breaks the triangle inequality (75, 40, 200)",
        "paper",
        {("hub", "inertia_kgm2"): [[75.0, 0.0, 0.0], [0.0, 40.0, 0.0], [0.0, 0.0, 200.0]]},
        "reject",
        ("hub.inertia_kgm2",),
        True,
    ),
    (
        "hub inertia symmetric but not positive definite",
        "paper",
        {("hub", "inertia_kgm2"): [[75.0, 80.0, 2.0], [80.0, 40.0, -1.0], [2.0, -1.0, 80.0]]},
        "reject",
        ("hub.inertia_kgm2",),
        True,
    ),
    (
        "array inertia breaks the triangle inequality (17, 62, 100)",
        "paper",
        {("arrays", "inertia_kgm2"): [17.0, 62.0, 100.0]},
        "reject",
        ("arrays.inertia_kgm2",),
        False,
    ),
    (
        "a hinge off every hub face",
        "paper",
        {("arrays", "hinges_corner_m"): [[0.4, 1.4, 0.5], [0.4, 1.4, 1.0]]},
        "reject",
        ("arrays.hinges_corner_m", "arrays.directions"),
        False,
    ),
    (
        "both arrays towards -z (the second through the hub)",
        "paper",
        {("arrays", "directions"): ["-z", "-z"]},
        "reject",
        ("arrays.directions", "arrays.hinges_corner_m"),
        False,
    ),
    (
        "orbit inclination 200 deg",
        "paper",
        {("orbit", "inclination_deg"): 200.0},
        "reject",
        ("orbit.inclination_deg",),
        False,
    ),
    (
        "orbit altitude 1e6 km",
        "paper",
        {("orbit", "altitude_km"): 1e6},
        "either",
        ("orbit.altitude_km",),
        False,
    ),
    (
        "control_rate_hz = 1e-9",
        "paper",
        {("simulation", "control_rate_hz"): 1e-9},
        "reject",
        ("simulation.control_rate_hz",),
        True,
    ),
    (
        "control_rate_hz = 1e6",
        "paper",
        {("simulation", "control_rate_hz"): 1e6},
        "reject",
        ("simulation.control_rate_hz", "simulation."),
        False,
    ),
    (
        "integrator_steps = 1000000000",
        "paper",
        {("simulation", "integrator_steps"): 10**9},
        "reject",
        ("simulation.integrator_steps", "simulation."),
        True,
    ),
    (
        "simulation.duration_s = 1e12",
        "paper",
        {("simulation", "duration_s"): 1e12},
        "reject",
        ("simulation.duration_s",),
        False,
    ),
    (
        "uncertainty.samples = 1000000000",
        "paper",
        {("uncertainty", "samples"): 10**9},
        "reject",
        ("uncertainty.samples",),
        True,
    ),
    (
        "montecarlo.samples = 1000000000",
        "paper",
        {("montecarlo", "samples"): 10**9},
        "reject",
        ("montecarlo.samples",),
        False,
    ),
    (
        "montecarlo.corner_array_angles = 1000000",
        "paper",
        {("montecarlo", "corner_array_angles"): 10**6},
        "reject",
        ("montecarlo.corner_array_angles",),
        False,
    ),
    (
        "engine.stages = 1000",
        "paper",
        {("engine", "stages"): 1000},
        "reject",
        ("engine.stages", "engine.", "cubesats.mass_kg"),
        False,
    ),
    (
        "first bending mode at 1e6 rad/s",
        "paper",
        {("arrays", "modes", 0, "omega_rad_s"): 1e6},
        "either",
        ("arrays.modes",),
        False,
    ),
    (
        "two modes named alike",
        "paper",
        {("arrays", "modes", 1, "name"): "bending1"},
        "reject",
        ("arrays.modes",),
        False,
    ),
    (
        "mode order 0",
        "paper",
        {("arrays", "modes", 2, "order"): 0},
        "reject",
        ("arrays.modes",),
        False,
    ),
    (
        "failure of CubeSat 25 (there are 24)",
        "paper",
        {("simulation", "failures"): [{"cubesat": 25, "time_s": 10.0}]},
        "reject",
        ("simulation.failures",),
        True,
    ),
    (
        "failure of CubeSat 0 (numbered from 1)",
        "paper",
        {("simulation", "failures"): [{"cubesat": 0, "time_s": 10.0}]},
        "reject",
        ("simulation.failures",),
        False,
    ),
    (
        "failure of stage 4 (there are 3)",
        "paper",
        {("simulation", "failures"): [{"cubesat": 1, "stage": 4, "time_s": 10.0}]},
        "reject",
        ("simulation.failures",),
        False,
    ),
    (
        "failure at t = -5 s",
        "paper",
        {("simulation", "failures"): [{"cubesat": 1, "time_s": -5.0}]},
        "reject",
        ("simulation.failures",),
        False,
    ),
    (
        "failure at t = nan",
        "paper",
        {("simulation", "failures"): [{"cubesat": 1, "time_s": math.nan}]},
        "reject",
        ("simulation.failures",),
        False,
    ),
    (
        "failure with an unknown key",
        "paper",
        {("simulation", "failures"): [{**_FAILURE, "severity": 1}]},
        "reject",
        ("simulation.failures",),
        False,
    ),
    (
        "failures = a table, not an array",
        "paper",
        {("simulation", "failures"): _FAILURE},
        "reject",
        ("simulation.failures",),
        False,
    ),
    (
        "failure of CubeSat 1 at 10 s (control)",
        "paper",
        {("simulation", "failures"): [_FAILURE]},
        "ok",
        (),
        True,
    ),
    (
        "slew torque_fraction = 1.5",
        "paper_slew",
        {("simulation", "slew", "torque_fraction"): 1.5},
        "reject",
        ("simulation.slew.torque_fraction",),
        False,
    ),
    (
        "bang-bang slew with thrusters = true",
        "paper_slew",
        {("simulation", "slew", "thrusters"): True},
        "reject",
        ("simulation.slew.thrusters",),
        False,
    ),
    (
        "fuel-optimal slew without a duration",
        "paper_slew",
        {("simulation", "slew", "method"): "fuel-optimal", ("simulation", "slew"): None},
        "reject",
        ("simulation.slew.duration_s", "simulation.slew"),
        False,
    ),
    (
        "slew start_s = -1",
        "paper_slew",
        {("simulation", "slew", "start_s"): -1.0},
        "reject",
        ("simulation.slew.start_s",),
        False,
    ),
    (
        'slew feedforward = "yes"',
        "paper_slew",
        {("simulation", "slew", "feedforward"): "yes"},
        "reject",
        ("simulation.slew.feedforward",),
        False,
    ),
    (
        "slew angle 181 deg",
        "paper_slew",
        {("simulation", "slew", "angle_deg"): 181.0},
        "reject",
        ("simulation.slew.angle_deg",),
        True,
    ),
    (
        "slew duration 1 s (below the minimum time)",
        "paper_slew",
        {("simulation", "slew", "duration_s"): 1.0},
        "either",
        ("simulation.slew.duration_s", "simulation.slew"),
        False,
    ),
    (
        'slew axis "-z"',
        "paper_slew",
        {("simulation", "slew", "axis"): "-z"},
        "either",
        ("simulation.slew.axis",),
        False,
    ),
    (
        "slew start_s 10 (control)",
        "paper_slew",
        {("simulation", "slew", "start_s"): 10.0},
        "ok",
        (),
        False,
    ),
]


def semantic_entries() -> list[Entry]:
    """Each value well typed and in its own range, the problem still wrong (or, controls, right)."""
    bases = {"paper": flattened("paper"), "paper_slew": flattened("paper_slew")}
    entries = []
    for i, (desc, base, changes, expect, names, fast) in enumerate(CASES, 1):
        data = copy.deepcopy(bases[base])
        for path, value in changes.items():
            if value is None:  # the marker for "delete duration_s" in that table
                get_path(data, path).pop("duration_s", None)
            else:
                set_path(data, path, copy.deepcopy(value))
        entries.append(
            Entry(
                id=f"M{i:03d}",
                description=f"{base}.toml: {desc}",
                runs=problem_runs(("simulation",), "semantic"),
                files=(FileSpec("p.toml", "text", toml_dumps(data)),),
                expect=expect,
                names=names,
                fast=fast,
                category="semantic",
            )
        )
    return entries
