"""``M…`` entries: each value well typed and in its own range, the problem still wrong.

Values checked against other keys or against physics (a stage's propellant
heavier than its CubeSat, an inertia that breaks the triangle inequality, a
failure of a CubeSat that does not exist, an array pointing into the hub ...),
the rules of the CubeSat list and layout, the old single-table forms, and
controls that must pass. Then the controller check: a valid problem whose plant
is not the paper's through ``simulate``, ``margins``, ``montecarlo`` and
``compare``, refused naming ``--controller`` unless a controller is given (and
``--allow-mismatch`` for one designed for another plant).

Each problem runs through ``model``, ``budget`` and ``simulate``; a valid
problem whose plant is not the paper's only through ``model`` and ``budget``
(``simulate`` would refuse to fly the paper's controller on it: the entries of
category ``controller`` at the end test that refusal).
"""

from __future__ import annotations

import copy
import functools
import math
import tomllib
from typing import Any, NamedTuple

from .entry import Entry, FileSpec
from .expectations import Path_
from .mutations import get_path, set_path
from .problem_files import problem_runs
from .shipped import flattened, load_shipped, paper_cubesat_list
from .toml_writer import toml_dumps

_FAILURE = {"cubesat": 1, "time_s": 10.0}
# The forms before [[arrays]] and [cubesat_layout]: one [arrays] table for both
# arrays, one [cubesats] table.
OLD_ARRAYS = """
[arrays]
mass_kg = 42.0
length_m = 2.5
width_m = 2.0
inertia_kgm2 = [17.0, 62.0, 80.0]
hinges_corner_m = [[0.4, 1.4, 0.0], [0.4, 1.4, 1.0]]
directions = ["-z", "+z"]
angle_deg = 0.0
damping_ratio = 0.005

[[arrays.modes]]
name = "bending1"
kind = "bending"
order = 1
omega_rad_s = 5.6
"""
OLD_CUBESATS = """
[cubesats]
per_face = 4
mass_kg = 3.5
inertia_kgm2 = [0.0513, 0.0513, 0.0082]
edge_margin_fraction = 0.1
standoff_m = 0.0
"""


class Case(NamedTuple):
    """One entry: ``changes`` maps a path to its new value (None: the key deleted)."""

    desc: str
    base: str
    changes: dict[Path_, Any]
    expect: str
    names: tuple[str, ...]
    fast: bool = False


def _vary(path: str, low: float = 1e-13, high: float = 5e-12) -> dict[str, Any]:
    """A ``[[montecarlo.vary]]`` entry, uniform from ``low`` to ``high``."""
    return {"path": path, "distribution": "uniform", "low": low, "high": high}


def _engines(count: int) -> list[dict[str, Any]]:
    """``count`` copies of the first CubeSat's engine of the paper's list."""
    engine = paper_cubesat_list()["cubesats"][0]["engines"][0]
    return [copy.deepcopy(engine) for _ in range(count)]


def _cubesats(count: int, engines: int = 1) -> list[dict[str, Any]]:
    """``count`` copies of the paper's second CubeSat, each with ``engines`` engines."""
    cubesat = copy.deepcopy(paper_cubesat_list()["cubesats"][1])
    directions = ([-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0])
    cubesat["engines"] = [{"direction": directions[i % 4]} for i in range(engines)]
    return [copy.deepcopy(cubesat) for _ in range(count)]


def _modes(count: int) -> list[dict[str, Any]]:
    """``count`` modes named apart, bending then torsion of orders 1 to 6 (then again)."""
    return [
        {
            "name": f"mode{i}",
            "kind": ("bending", "torsion")[i // 6 % 2],
            "order": 1 + i % 6,
            "omega_rad_s": 5.0 + i,
        }
        for i in range(count)
    ]


_CASES: list[tuple[str, str, dict[Path_, Any], str, tuple[str, ...], bool]] = [
    (
        "a stage's propellant heavier than its CubeSat (stage_life_h = 50000)",
        "paper",
        {("engine", "stage_life_h"): 50000.0},
        "reject",
        ("engine.", "cubesat_layout.mass_kg"),
        True,
    ),
    (
        "CubeSat of 0.1 kg, lighter than its propellant",
        "paper",
        {("cubesat_layout", "mass_kg"): 0.1},
        "reject",
        ("engine.", "cubesat_layout.mass_kg"),
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
        {("arrays", 0, "inertia_kgm2"): [17.0, 62.0, 100.0]},
        "reject",
        ("arrays[0].inertia_kgm2",),
        False,
    ),
    (
        "a hinge off every hub face",
        "paper",
        {("arrays", 0, "hinge_corner_m"): [0.4, 1.4, 0.5]},
        "reject",
        ("arrays[0].hinge_corner_m", "arrays[0].direction"),
        False,
    ),
    (
        "both arrays towards -z (the second through the hub)",
        "paper",
        {("arrays", 1, "direction"): "-z"},
        "reject",
        ("arrays[1].direction",),
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
        ("engine.stages", "engine.", "cubesat_layout.mass_kg"),
        False,
    ),
    (
        "first bending mode at 1e6 rad/s",
        "paper",
        {("arrays", 0, "modes", 0, "omega_rad_s"): 1e6},
        "either",
        ("arrays[0].modes",),
        False,
    ),
    (
        "two modes named alike",
        "paper",
        {("arrays", 0, "modes", 1, "name"): "bending1"},
        "reject",
        ("arrays[0].modes",),
        False,
    ),
    (
        "mode order 0",
        "paper",
        {("arrays", 0, "modes", 2, "order"): 0},
        "reject",
        ("arrays[0].modes",),
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
        "failure of engine 2 of CubeSat 1 (it has 1)",
        "paper",
        {("simulation", "failures"): [{**_FAILURE, "engine": 2}]},
        "reject",
        ("simulation.failures[0].engine",),
        True,
    ),
    (
        "failure of engine 0 (numbered from 1)",
        "paper",
        {("simulation", "failures"): [{**_FAILURE, "engine": 0}]},
        "reject",
        ("simulation.failures[0].engine",),
        False,
    ),
    (
        "failure of an engine and a stage at once",
        "paper",
        {("simulation", "failures"): [{**_FAILURE, "engine": 1, "stage": 1}]},
        "reject",
        ("simulation.failures[0].engine",),
        False,
    ),
    (
        "failure of engine 1 of CubeSat 1 at 10 s (control)",
        "paper",
        {("simulation", "failures"): [{**_FAILURE, "engine": 1}]},
        "ok",
        (),
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
        {
            ("simulation", "slew", "method"): "fuel-optimal",
            ("simulation", "slew", "duration_s"): None,
        },
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
    # ---- the [[cubesats]] list (the paper's 24 CubeSats written out)
    (
        "a CubeSat inside the hub",
        "paper_list",
        {("cubesats", 0, "position_corner_m"): [0.375, 1.5, 0.5]},
        "reject",
        ("cubesats[0].position_corner_m",),
        True,
    ),
    (
        'a CubeSat on the +z face with face = "+x"',
        "paper_list",
        {("cubesats", 0, "position_corner_m"): [0.375, 1.5, 1.0]},
        "reject",
        ("cubesats[0].position_corner_m", "cubesats[0].face"),
        False,
    ),
    (
        "an engine direction [0, 0, 0]",
        "paper_list",
        {("cubesats", 0, "engines", 0, "direction"): [0.0, 0.0, 0.0]},
        "reject",
        ("cubesats[0].engines[0].direction",),
        True,
    ),
    (
        "17 engines on one CubeSat (at most 16)",
        "paper_list",
        {("cubesats", 0, "engines"): _engines(17)},
        "reject",
        ("cubesats[0].engines",),
        False,
    ),
    (
        "the second CubeSat's propellant heavier than it (its stage_life_h = 50000)",
        "paper_list",
        {("cubesats", 1, "engines", 0, "stage_life_h"): 50000.0},
        "reject",
        ("cubesats[1].engines[0].stage_life_h",),
        True,
    ),
    (
        "the third CubeSat of 0.1 kg, lighter than its propellant",
        "paper_list",
        {("cubesats", 2, "mass_kg"): 0.1},
        "reject",
        ("cubesats[2].engines[0].stage_life_h", "cubesats[2].mass_kg"),
        False,
    ),
    (
        "two engines on a 0.5 kg CubeSat: each engine's propellant below its mass, the sum above",
        "paper_list",
        {("cubesats", 0, "mass_kg"): 0.5, ("cubesats", 0, "engines"): _engines(2)},
        "reject",
        ("cubesats[0].engines[0].stage_life_h", "cubesats[0].mass_kg"),
        False,
    ),
    (
        "a CubeSat's 3 x 3 inertia not symmetric",
        "paper_list",
        {("cubesats", 1, "inertia_kgm2", 0, 1): 0.001},
        "reject",
        ("cubesats[1].inertia_kgm2",),
        False,
    ),
    (
        "a CubeSat's principal inertia breaks the triangle inequality (0.0513, 0.0082, 0.1)",
        "paper_list",
        {("cubesats", 0, "inertia_kgm2"): [0.0513, 0.0082, 0.1]},
        "reject",
        ("cubesats[0].inertia_kgm2",),
        False,
    ),
    (
        "257 CubeSats (at most 256)",
        "paper_list",
        {("cubesats",): _cubesats(257)},
        "reject",
        ("cubesats",),
        False,
    ),
    (
        "200 CubeSats of 3 engines: 600 engines (at most 512)",
        "paper_list",
        {("cubesats",): _cubesats(200, engines=3)},
        "reject",
        ("cubesats",),
        False,
    ),
    (
        "[[cubesats]] list and the paper's [cubesat_layout] both",
        "paper_list",
        {("cubesat_layout",): load_shipped("paper")["cubesat_layout"]},
        "reject",
        ("cubesats", "cubesat_layout"),
        True,
    ),
    (
        "the 24 CubeSats as a [[cubesats]] list (the paper's plant, its controller flies; control)",
        "paper_list",
        {},
        "ok",
        (),
        True,
    ),
    (
        'the 24 CubeSats as a list, every engine direction a signed axis ("-x", ...; control)',
        "paper_list",
        {
            ("cubesats", i, "engines", 0, "direction"): axis
            for i, axis in enumerate(
                [face for face in ("-x", "+x", "-y", "+y", "-z", "+z") for _ in range(4)]
            )
        },
        "ok",
        (),
        False,
    ),
    # ---- [cubesat_layout]
    (
        'kind = "face_ring"',
        "paper",
        {("cubesat_layout", "kind"): "face_ring"},
        "reject",
        ("cubesat_layout.kind",),
        True,
    ),
    (
        'per_face = 2 with kind = "face_corners" (four corners)',
        "paper",
        {("cubesat_layout", "per_face"): 2},
        "reject",
        ("cubesat_layout.per_face",),
        True,
    ),
    (
        'faces = ["+x", "-x", "+x"] (a face twice)',
        "paper",
        {("cubesat_layout", "faces"): ["+x", "-x", "+x"]},
        "reject",
        ("cubesat_layout.faces",),
        False,
    ),
    (
        "side_engines = 3 (0, 2 or 4)",
        "paper",
        {("cubesat_layout", "side_engines"): 3},
        "reject",
        ("cubesat_layout.side_engines",),
        False,
    ),
    (
        "main_engine = false and side_engines = 0: no engine at all",
        "paper",
        {("cubesat_layout", "main_engine"): False},
        "reject",
        ("cubesat_layout.main_engine", "cubesat_layout.side_engines"),
        True,
    ),
    (
        'kind = "face_grid", per_face = 64: 384 CubeSats (at most 256)',
        "paper",
        {("cubesat_layout", "kind"): "face_grid", ("cubesat_layout", "per_face"): 64},
        "reject",
        ("cubesat_layout",),
        False,
    ),
    (
        'kind = "face_grid", per_face = 40, side_engines = 4: 1200 engines (at most 512)',
        "paper",
        {
            ("cubesat_layout", "kind"): "face_grid",
            ("cubesat_layout", "per_face"): 40,
            ("cubesat_layout", "side_engines"): 4,
        },
        "reject",
        ("cubesat_layout",),
        False,
    ),
    (
        'kind = "face_grid", 6 per face on four faces, side_engines = 2 (control)',
        "paper",
        {
            ("cubesat_layout", "kind"): "face_grid",
            ("cubesat_layout", "per_face"): 6,
            ("cubesat_layout", "faces"): ["+x", "-x", "+z", "-z"],
            ("cubesat_layout", "side_engines"): 2,
        },
        "ok",
        (),
        False,
    ),
    (
        "main_engine = false, side_engines = 4 (control)",
        "paper",
        {("cubesat_layout", "main_engine"): False, ("cubesat_layout", "side_engines"): 4},
        "ok",
        (),
        False,
    ),
    # ---- the old single tables
    (
        "the old [arrays] table (hinges_corner_m, directions, [[arrays.modes]])",
        "paper",
        {("arrays",): tomllib.loads(OLD_ARRAYS)["arrays"]},
        "reject",
        ("arrays",),
        True,
    ),
    (
        "the old [cubesats] table (per_face ...) instead of [cubesat_layout]",
        "paper",
        {("cubesat_layout",): None, ("cubesats",): tomllib.loads(OLD_CUBESATS)["cubesats"]},
        "reject",
        ("cubesats",),
        True,
    ),
    (
        "the old [cubesats] table beside [cubesat_layout]",
        "paper",
        {("cubesats",): tomllib.loads(OLD_CUBESATS)["cubesats"]},
        "reject",
        ("cubesats", "cubesat_layout"),
        False,
    ),
    # ---- [[arrays]]
    (
        "an array's direction [0, 0, 1] into the hub from its hinge on the -z face",
        "paper",
        {("arrays", 0, "direction"): [0.0, 0.0, 1.0]},
        "reject",
        ("arrays[0].direction",),
        True,
    ),
    (
        'an array\'s direction "+x" along the -z face its hinge is on',
        "paper",
        {("arrays", 0, "direction"): "+x"},
        "reject",
        ("arrays[0].direction",),
        False,
    ),
    ("arrays = [] (a rigid debris; control)", "paper", {("arrays",): []}, "ok", (), True),
    (
        "17 arrays (at most 16)",
        "paper",
        {("arrays",): [load_shipped("paper")["arrays"][0]] * 17},
        "reject",
        ("arrays",),
        False,
    ),
    (
        "an array with 17 modes (at most 16)",
        "paper",
        {("arrays", 0, "modes"): _modes(17)},
        "reject",
        ("arrays[0].modes",),
        False,
    ),
    (
        "the first mode of the second array torsion, like its second (same kind and order)",
        "paper",
        {("arrays", 1, "modes", 0, "kind"): "torsion"},
        "reject",
        ("arrays[1].modes",),
        False,
    ),
    (
        'a third array, hinge on the +y face, direction "+y", without modes (control)',
        "paper",
        {
            ("arrays", 2): {
                **{k: v for k, v in load_shipped("paper")["arrays"][0].items() if k != "modes"},
                "hinge_corner_m": [0.375, 3.0, 0.5],
                "direction": "+y",
            }
        },
        "ok",
        (),
        False,
    ),
    (
        "an array on the +x face along the vector [1, 0, 1] (control)",
        "paper",
        {
            ("arrays", 0, "hinge_corner_m"): [0.75, 1.5, 0.5],
            ("arrays", 0, "direction"): [1.0, 0.0, 1.0],
        },
        "ok",
        (),
        False,
    ),
    # ---- [requirements]
    (
        "requirements.slew_error_deg = 181",
        "paper",
        {("requirements", "slew_error_deg"): 181.0},
        "reject",
        ("requirements.slew_error_deg",),
        False,
    ),
    (
        "no [requirements] (the defaults; control)",
        "paper",
        {("requirements",): None},
        "ok",
        (),
        False,
    ),
    # ---- [environment]
    (
        "environment: specular 0.7 + diffuse 0.4 reflectivity (above all the light)",
        "paper",
        {("environment",): {"specular_reflectivity": 0.7, "diffuse_reflectivity": 0.4}},
        "reject",
        ("environment.diffuse_reflectivity",),
        True,
    ),
    (
        'environment: torques = ["drag"] (not one of the four)',
        "paper",
        {("environment",): {"torques": ["drag"]}},
        "reject",
        ("environment.torques",),
        True,
    ),
    (
        "environment: every torque on, the orbit's node and phase given (control)",
        "paper",
        {
            ("environment",): {
                "torques": ["gravity_gradient", "aerodynamic", "solar_pressure", "magnetic"],
                "density_kg_m3": 1e-12,
                "residual_dipole_Am2": [1.0, -1.0, 2.0],
            },
            ("orbit", "raan_deg"): 90.0,
            ("orbit", "argument_of_latitude_deg"): 30.0,
        },
        "ok",
        (),
        False,
    ),
    # ---- [[montecarlo.vary]]
    (
        "montecarlo.vary: a key the problem does not have",
        "paper",
        {("montecarlo", "vary"): [_vary("environment.densty_kg_m3")]},
        "reject",
        ("montecarlo.vary[0].path",),
        True,
    ),
    (
        "montecarlo.vary: a whole array, not one element",
        "paper",
        {("montecarlo", "vary"): [_vary("disturbance.amplitude_mNm", 0.1, 2.0)]},
        "reject",
        ("montecarlo.vary[0].path",),
        False,
    ),
    (
        "montecarlo.vary: a text key",
        "paper",
        {("montecarlo", "vary"): [_vary("simulation.reference", 0.1, 2.0)]},
        "reject",
        ("montecarlo.vary[0].path",),
        False,
    ),
    (
        "montecarlo.vary: low below the key's range",
        "paper",
        {("montecarlo", "vary"): [_vary("environment.density_kg_m3", -1.0, 1e-12)]},
        "reject",
        ("montecarlo.vary[0].low",),
        False,
    ),
    (
        "montecarlo.vary: high at or below low",
        "paper",
        {("montecarlo", "vary"): [_vary("environment.density_kg_m3", 1e-12, 1e-12)]},
        "reject",
        ("montecarlo.vary[0].high",),
        False,
    ),
    (
        "montecarlo.vary: a bound that breaks a check across keys (reflectivities above 1)",
        "paper",
        {("montecarlo", "vary"): [_vary("environment.specular_reflectivity", 0.1, 0.95)]},
        "reject",
        ("montecarlo.vary[0].high",),
        False,
    ),
    (
        "montecarlo.vary: a normal without sigma",
        "paper",
        {("montecarlo", "vary"): [{"path": "mass_kg", "distribution": "normal", "mean": 1.0}]},
        "reject",
        ("montecarlo.vary[0].sigma",),
        False,
    ),
    (
        "montecarlo.vary: a key, a parameter and corners (control)",
        "paper",
        {
            ("montecarlo", "vary"): [
                _vary("environment.density_kg_m3"),
                {"path": "mass_kg", "distribution": "normal", "mean": 668.0, "sigma": 20.0},
                _vary("disturbance.amplitude_mNm[2]", 0.5, 0.9) | {"distribution": "corners"},
            ]
        },
        "ok",
        (),
        False,
    ),
]
CASES = [Case(*case) for case in _CASES]


def _problem(base: str, changes: dict[Path_, Any]) -> dict[str, Any]:
    """The base problem with the changes made (a value None deletes the key)."""
    data = copy.deepcopy(_bases()[base])
    for path, value in changes.items():
        if value is None:
            get_path(data, path[:-1]).pop(path[-1], None)
        elif isinstance(path[-1], int) and path[-1] == len(get_path(data, path[:-1])):
            get_path(data, path[:-1]).append(copy.deepcopy(value))  # one more entry
        else:
            set_path(data, path, copy.deepcopy(value))
    return data


@functools.cache
def _bases() -> dict[str, dict[str, Any]]:
    return {
        "paper": flattened("paper"),
        "paper_slew": flattened("paper_slew"),
        "paper_list": paper_cubesat_list(),
    }


def _paper_plant(data: dict[str, Any]) -> bool:
    """Is ``data`` the paper's plant, or refused (so that no command reaches the controller)?"""
    from casadi_debris.config import load_problem, problem_from_dict
    from casadi_debris.errors import ProblemFileError

    try:
        problem = problem_from_dict(data)
    except ProblemFileError:
        return True
    return problem.plant_sha256 == load_problem().plant_sha256


_BASE_FILES = {
    "paper": "paper.toml",
    "paper_slew": "paper_slew.toml",
    "paper_list": "paper.toml, CubeSats as a list",
}


def semantic_entries() -> list[Entry]:
    """Each value well typed and in its own range, the problem still wrong (or, controls, right)."""
    entries = []
    for i, case in enumerate(CASES, 1):
        data = _problem(case.base, case.changes)
        runs = problem_runs(("simulation",), "semantic")
        if not _paper_plant(data):  # valid, another plant: simulate wants --controller
            runs = runs[:2]
        entries.append(
            Entry(
                id=f"M{i:03d}",
                description=f"{_BASE_FILES[case.base]}: {case.desc}",
                runs=runs,
                files=(FileSpec("p.toml", "text", toml_dumps(data)),),
                expect=case.expect,
                names=case.names,
                fast=case.fast,
                category="semantic",
            )
        )
    return [*entries, *controller_entries(len(entries) + 1)]


# The commands that fly a controller, each kept short.
_SIMULATE = ("simulate", "p.toml", "--duration-s", "2", "--no-plots", "--out", "out", "--json")
_MARGINS = ("margins", "p.toml", "--samples", "2", "--no-plots", "--out", "out", "--json")
_MONTECARLO = (
    *("montecarlo", "p.toml", "--samples", "1", "--max-cases", "1", "--workers", "1"),
    *("--no-jit", "--out", "out", "--json"),
)
_COMPARE = ("compare", "p.toml", "--out", "out", "--json")
_FLYING = (_SIMULATE, _MARGINS, _MONTECARLO, _COMPARE)


def _with(runs: tuple[tuple[str, ...], ...], *extra: str) -> tuple[tuple[str, ...], ...]:
    return tuple((*run, *extra) for run in runs)


def controller_entries(first: int) -> list[Entry]:
    """Problems that are (or are not) the paper's plant through the commands that fly a controller.

    ``p.toml`` runs 2 s (``[simulation]`` is not part of the plant); ``ctl.json`` is
    a copy of the shipped controller, designed for the paper's plant.
    """
    from casadi_debris.config import default_controller_path

    shipped = FileSpec("ctl.json", content=default_controller_path().read_text(encoding="utf-8"))
    short = {("simulation", "duration_s"): 2.0}
    rigid = {**short, ("name",): "rigid", ("arrays",): []}
    cases = [
        _Flight(
            "arrays = [] (a rigid debris, another plant) without --controller",
            rigid,
            _FLYING,
            "reject",
            ("--controller",),
            (),
            True,
        ),
        _Flight(
            "requirements.pointing_arcsec = 30 (another plant) without --controller",
            {**short, ("name",): "pointing-30", ("requirements", "pointing_arcsec"): 30.0},
            (_SIMULATE, _MARGINS),
            "reject",
            ("--controller",),
            (),
            False,
        ),
        _Flight(
            "arrays = [] with the shipped controller as --controller ctl.json, no --allow-mismatch",
            rigid,
            _with(_FLYING, "--controller", "ctl.json"),
            "reject",
            ("--controller", "--allow-mismatch", "ctl.json"),
            (shipped,),
            False,
        ),
        _Flight(
            "arrays = [] with the shipped controller and --allow-mismatch (control)",
            rigid,
            _with(_FLYING, "--controller", "ctl.json", "--allow-mismatch"),
            "ok",
            (),
            (shipped,),
            False,
        ),
        _Flight(
            "another name, orbit and [montecarlo] seed: the paper's plant (control)",
            {
                **short,
                ("name",): "renamed",
                ("orbit", "altitude_km"): 700.0,
                ("montecarlo", "seed"): 7,
            },
            _FLYING,
            "ok",
            (),
            (),
            False,
        ),
    ]
    return [
        Entry(
            id=f"M{first + i:03d}",
            description=f"paper.toml: {desc}",
            runs=runs,
            files=(FileSpec("p.toml", "text", toml_dumps(_problem("paper", changes))), *files),
            expect=expect,
            names=names,
            fast=fast,
            category="controller",
        )
        for i, (desc, changes, runs, expect, names, files, fast) in enumerate(cases)
    ]


class _Flight(NamedTuple):
    """A problem (the paper with ``changes``) through commands that fly a controller."""

    desc: str
    changes: dict[Path_, Any]
    runs: tuple[tuple[str, ...], ...]
    expect: str
    names: tuple[str, ...]
    files: tuple[FileSpec, ...]
    fast: bool
