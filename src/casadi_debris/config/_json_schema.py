"""The JSON Schema of a problem file, taken from the readers themselves.

The readers of :mod:`casadi_debris.config` are the one statement of what a problem
file may hold. :func:`problem_schema` reads a few complete example problems with
:func:`~casadi_debris.config._table.recording` on, so every key a reader takes, with
its type, shape, range, choices and count, is noted; the notes become a JSON Schema
(draft 2020-12). Tables allow no other keys. Which keys may be left out (they have
defaults) and the checks across keys (a hinge on the hub, propellant below the
CubeSat's mass) are the loader's: the schema is for editors and other tools, the
loader stays the judge.
"""

from __future__ import annotations

import copy
import re
from collections.abc import Mapping
from typing import Any

from casadi_debris.config._loader import default_problem_path, merge_problem
from casadi_debris.config._reader import problem_from_dict
from casadi_debris.config._table import recording
from casadi_debris.config.limits import Range

SCHEMA_URI = "https://json-schema.org/draft/2020-12/schema"
_INDEX = re.compile(r"\[\d+\]$")


REALISM_EXAMPLE: dict[str, Any] = {
    "sensors": {
        "seed": 1,
        "star_tracker": {
            "noise_arcsec": 5.0,
            "bias_arcsec": [1.0, 0.0, 0.0],
            "update_rate_hz": 5.0,
            "outages_s": [[100.0, 200.0]],
        },
        "gyro": {
            "angle_random_walk_deg_rt_h": 0.15,
            "bias_random_walk_deg_h_rt_h": 0.5,
            "initial_bias_deg_h": [1.0, -1.0, 0.5],
        },
    },
    "estimation": {
        "filter": "mekf",
        "initial_attitude_sigma_arcsec": 10.0,
        "initial_bias_sigma_deg_h": 1.0,
    },
    "actuators": {
        "thrust_noise_fraction": 0.01,
        "misalignment_deg": 0.5,
        "ramp_time_constant_s": 0.1,
        "latency_s": 0.05,
        "minimum_impulse_bit_uNs": 1.0,
    },
    "controller": {"delay_s": 0.02},
}


def _examples(paper: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Complete problems that between them take every branch of the readers."""
    slew = {"axis": "z", "angle_deg": 90.0, "method": "time-optimal", "start_s": 10.0}
    slew |= {"flexible": True, "flexible_method": "shaper"}
    slew |= {"duration_s": 1200.0, "torque_fraction": 0.9, "feedforward": True}
    slew |= {"thrusters": True}
    runs = {
        "extends": "paper.toml",
        "simulation": {
            "reference": "slew",
            "slew": slew,
            "failures": [
                {"time_s": 1.0, "cubesat": 1, "stage": 1},
                {"time_s": 2.0, "cubesat": 2, "engine": 1},
            ],
        },
        "requirements": {"pointing_arcsec": 60.0, "slew_error_deg": 0.6},
        "uncertainty": {"independent_array_angles": True},
        "montecarlo": {
            "corner_array_angles": 2,
            "vary": [
                {"path": "mass_kg", "distribution": "normal", "mean": 668.0, "sigma": 10.0}
                | {"low": 600.0, "high": 700.0},
                {"path": "inertia_scale_x", "distribution": "uniform", "low": 0.9, "high": 1.1},
                {"path": "inertia_scale_y", "distribution": "corners", "low": 0.9, "high": 1.1},
            ],
        },
        "orbit": {"raan_deg": 30.0, "argument_of_latitude_deg": 45.0},
        "environment": {
            "torques": ["gravity_gradient", "aerodynamic", "solar_pressure", "magnetic"],
            "density_kg_m3": 1e-13,
            "drag_coefficient": 2.2,
            "solar_pressure_N_m2": 4.56e-6,
            "specular_reflectivity": 0.1,
            "diffuse_reflectivity": 0.2,
            "sun_longitude_deg": 0.0,
            "eclipse": True,
            "residual_dipole_Am2": [0.0, 0.0, 1.0],
            "field_equator_T": 2.98e-5,
            "dipole_tilt_deg": 9.41,
            "dipole_longitude_deg": -72.68,
            "greenwich_angle_deg": 0.0,
        },
    }
    vector_axis = {
        "extends": "paper.toml",
        "simulation": {"reference": "slew", "slew": {"axis": [0.0, 1.0, 1.0], "angle_deg": 9.0}},
    }
    runs |= REALISM_EXAMPLE
    engine = {"direction": [0.0, 0.0, -1.0], "offset_m": [0.0, 0.0, 0.0], "stages": 1}
    engine |= {"emitters_per_stage": 32, "thrust_per_stage_mN": 0.64, "isp_s": 1000.0}
    engine |= {"stage_life_h": 500.0}
    explicit = {
        "cubesats": [
            {
                "position_corner_m": [0.375, 1.5, 1.0],
                "mass_kg": 3.5,
                "face": "+z",
                "inertia_kgm2": [0.05, 0.05, 0.01],
                "engines": [engine, {"direction": "+x"}],
            },
            {
                "position_corner_m": [0.375, 1.5, 0.0],
                "mass_kg": 3.5,
                "inertia_kgm2": [[0.05, 0, 0], [0, 0.05, 0], [0, 0, 0.01]],
                "engines": [{"direction": "-x"}],
            },
        ],
        "arrays": [{**paper["arrays"][0], "direction": [0.0, 0.0, -1.0]}],
    }
    return [
        copy.deepcopy(dict(paper)),
        merge_problem(copy.deepcopy(dict(paper)), runs),
        merge_problem(copy.deepcopy(dict(paper)), explicit),
        merge_problem(copy.deepcopy(dict(paper)), _sequence_example()),
        merge_problem(copy.deepcopy(dict(paper)), vector_axis),
    ]


def _sequence_example() -> dict[str, Any]:
    """A ``[[simulation.segments]]`` manoeuvre taking every kind of segment and target."""
    flexible = {"method": "time-optimal", "flexible": True, "flexible_method": "shaper"}
    options = {"torque_fraction": 0.5, "feedforward": True, "thrusters": True}
    segments = [
        {"kind": "slew", "axis": [1.0, 1.0, 1.0], "angle_deg": 90.0, **flexible, **options},
        {"kind": "slew", "axis": "-y", "angle_deg": 10.0, "start_s": 100.0, "duration_s": 50.0},
        {"kind": "slew", "quaternion": [1.0, 0.0, 0.0, 0.0]},
        {"kind": "slew", "euler_deg": [10.0, 0.0, 0.0], "euler_sequence": "ZYX"},
        {"kind": "hold", "duration_s": 10.0},
        {"kind": "slew", "frame": "nadir", "nadir_axis": "-x", "along_axis": [0.0, 1.0, 0.0]},
        {
            "kind": "track",
            "frame": "nadir",
            "nadir_axis": [0, 0, 1],
            "along_axis": "+x",
            "duration_s": 100.0,
        },
        {"kind": "track", "frame": "lvlh", "euler_deg": [0.0, 5.0, 0.0], "duration_s": 100.0},
        {"kind": "track", "frame": "lvlh", "axis": "z", "angle_deg": 5.0, "duration_s": 100.0},
        {"kind": "burn", "direction": "retrograde", "body_axis": "-y", "duration_s": 200.0},
        {"kind": "burn", "direction": "normal", "thrust_fraction": 0.5, "duration_s": 200.0},
        {"kind": "burn", "direction": "prograde", "thrust_mN": 1.0, "duration_s": 200.0},
        {"kind": "track", "frame": "lvlh", "quaternion": [1.0, 0.0, 0.0, 0.0], "blend_s": 60.0},
    ]
    return {
        "extends": "paper.toml",
        "simulation": {"reference": "sequence", "segments": segments},
    }


def _leaf(spec: Mapping[str, Any]) -> dict[str, Any]:
    kind = spec["kind"]
    if kind in ("text", "label", "prose"):
        schema: dict[str, Any] = {"type": "string"}
        if spec.get("choices"):
            schema["enum"] = list(spec["choices"])
        if kind == "label":
            schema["pattern"] = f"^{spec['pattern']}$"
        if kind == "prose":
            schema["maxLength"] = spec["max_length"]
        return schema
    if kind == "texts":
        items = {"type": "string", "enum": list(spec["choices"])}
        return {"type": "array", "items": items, "minItems": 1, "maxItems": spec["max_count"]}
    if kind == "boolean":
        return {"type": "boolean"}
    if kind == "integer":
        return {"type": "integer", **_bounds(spec["bounds"])}
    return _shaped(tuple(spec["shape"]), spec["bounds"], spec.get("max_rows"))


def _bounds(bounds: Range) -> dict[str, float]:
    low = "exclusiveMinimum" if bounds.low_open else "minimum"
    high = "exclusiveMaximum" if bounds.high_open else "maximum"
    return {low: bounds.low, high: bounds.high}


def _shaped(shape: tuple[int | None, ...], bounds: Range, max_rows: int | None) -> dict[str, Any]:
    if not shape:
        return {"type": "number", **_bounds(bounds)}
    length, rest = shape[0], shape[1:]
    array: dict[str, Any] = {"type": "array", "items": _shaped(rest, bounds, max_rows)}
    array["minItems"] = length if length is not None else 1
    array["maxItems"] = length if length is not None else max_rows
    return array


def _tree(calls: list[tuple[str, dict[str, Any]]]) -> dict[str, Any]:
    """Nested {name: node}; a node has ``specs`` (leaf notes), ``children`` and ``list``."""
    root: dict[str, Any] = {"children": {}, "specs": [], "list": None}
    for key, spec in calls:
        node = root
        for part in key.split("."):
            name = _INDEX.sub("", part)
            child = node["children"].setdefault(name, {"children": {}, "specs": [], "list": None})
            if part != name:
                child["list"] = child["list"] or {}
            node = child
        if spec["kind"] == "tables":
            node["list"] = {"maxItems": spec["max_count"]}
        elif spec["kind"] != "table":
            node["specs"].append(spec)
    return root


def _node_schema(node: Mapping[str, Any]) -> dict[str, Any]:
    if node["children"]:
        properties = {name: _node_schema(child) for name, child in sorted(node["children"].items())}
        schema: dict[str, Any] = {
            "type": "object",
            "properties": properties,
            "additionalProperties": False,
        }
        if node["list"] is not None:
            return {"type": "array", "items": schema, **node["list"]}
        return schema
    # A label or prose is also read as text: keep the stricter note.
    kinds = {spec["kind"] for spec in node["specs"]}
    specs = [s for s in node["specs"] if not (s["kind"] == "text" and kinds & {"label", "prose"})]
    shapes = []
    for spec in specs:
        leaf = _leaf(spec)
        if leaf not in shapes:
            shapes.append(leaf)
    return shapes[0] if len(shapes) == 1 else {"anyOf": shapes}


def problem_schema() -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of a problem file, as a dict."""
    import tomllib

    with default_problem_path().open("rb") as file:
        paper = tomllib.load(file)
    with recording() as calls:
        for example in _examples(paper):
            problem_from_dict(example, "<schema example>")
    schema = _node_schema(_tree(calls))
    schema["properties"]["arrays"]["minItems"] = 0  # none: a rigid debris
    return {
        "$schema": SCHEMA_URI,
        "title": "casadi_debris problem file",
        "description": (
            "Every number carries its unit in its key. The loader also checks what a "
            "schema cannot: keys left out take defaults only where the documentation "
            "says so, a hinge lies on the hub, propellant stays below its CubeSat's mass."
        ),
        **schema,
    }
