"""Random valid problems and independent references for ``test_valid_problems.py``.

A problem is drawn as the parsed TOML a user would write: a hub of random size,
mass and (rotated) inertia, zero to two arrays leaving random faces at random
hinge points and angles, and an explicit ``[[cubesats]]`` list of CubeSats on
random faces, each with one to three engines in random directions and random
limits. Everything else is the paper's file.

The references are computed here from those numbers, not by the package: the
combined mass properties (parallel-axis sums, the array frame as
``docs/guide`` and the geometry module's docstring describe it), each engine's
torque and force columns, and the torque authority as linear programmes
(scipy's HiGHS).
"""

from __future__ import annotations

import copy
import json
import math
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path
from typing import Any

import numpy as np
from hypothesis import strategies as st
from scipy.optimize import linprog

from casadi_debris.config import default_problem_path

SIGNED_AXES = ("+x", "-x", "+y", "-y", "+z", "-z")
G0_M_S2 = 9.80665


@cache
def paper_data() -> dict[str, Any]:
    with default_problem_path().open("rb") as handle:
        return tomllib.load(handle)


# ------------------------------------------------------------------ drawing problems


def _unit(draw: st.DrawFn) -> list[float]:
    """A random unit vector (normalised Gaussian, redrawn when too short)."""
    while True:
        v = np.array([draw(st.floats(-1.0, 1.0)) for _ in range(3)])
        if np.linalg.norm(v) > 0.2:
            return (v / np.linalg.norm(v)).tolist()


def _rotation(draw: st.DrawFn) -> np.ndarray:
    """A random rotation matrix (axis-angle)."""
    axis = np.array(_unit(draw))
    angle = draw(st.floats(-math.pi, math.pi))
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def _box_moments(mass_kg: float, a: float, b: float, c: float) -> list[float]:
    """Principal moments of a homogeneous box, kg m^2 (always a valid inertia)."""
    return [
        mass_kg * (b * b + c * c) / 12,
        mass_kg * (a * a + c * c) / 12,
        mass_kg * (a * a + b * b) / 12,
    ]


def _face_point(
    draw: st.DrawFn, size: list[float], face: str, height_m: float, inset: float
) -> list[float]:
    """A point on (or ``height_m`` above) the hub face ``face``, corner frame."""
    axis = "xyz".index(face[1])
    point = [draw(st.floats(inset, 1.0 - inset)) * s for s in size]
    point[axis] = size[axis] + height_m if face[0] == "+" else -height_m
    return point


def _hub(draw: st.DrawFn) -> dict[str, Any]:
    size = [draw(st.floats(0.4, 4.0)) for _ in range(3)]
    mass = draw(st.floats(50.0, 3000.0))
    # A box's inertia, each moment scaled by up to 10 % (uneven fill), kept valid by
    # mixing with the box's own, then turned by a random rotation: products appear.
    moments = np.array(_box_moments(mass, *size))
    scale = np.array([draw(st.floats(0.95, 1.05)) for _ in range(3)])
    moments = moments * scale
    if not all(moments[i] < moments[(i + 1) % 3] + moments[(i + 2) % 3] for i in range(3)):
        moments = np.array(_box_moments(mass, *size))
    rotation = _rotation(draw) if draw(st.booleans()) else np.eye(3)
    inertia = rotation @ np.diag(moments) @ rotation.T
    inertia = 0.5 * (inertia + inertia.T)
    cog = [s * draw(st.floats(0.4, 0.6)) for s in size]
    return {
        "mass_kg": mass,
        "size_m": size,
        "cog_corner_m": cog,
        "inertia_kgm2": inertia.tolist(),
    }


def _array(draw: st.DrawFn, size: list[float], face: str) -> dict[str, Any]:
    mass = draw(st.floats(5.0, 100.0))
    length = draw(st.floats(0.5, 12.0))
    width = draw(st.floats(0.3, 3.0))
    thickness = 0.03
    modes = [
        {
            "name": "bending1",
            "kind": "bending",
            "order": 1,
            "omega_rad_s": draw(st.floats(0.5, 10.0)),
        }
    ]
    if draw(st.booleans()):
        modes.append(
            {
                "name": "torsion1",
                "kind": "torsion",
                "order": 1,
                "omega_rad_s": draw(st.floats(10.0, 30.0)),
            }
        )
    if draw(st.integers(0, 4)) == 0:
        modes = []  # a rigid appendage
    return {
        "hinge_corner_m": _face_point(draw, size, face, 0.0, 0.2),
        "direction": face,
        "mass_kg": mass,
        "length_m": length,
        "width_m": width,
        # Length, width and normal moments of a thin plate (strictly valid thanks to
        # its thickness).
        "inertia_kgm2": [
            mass * (width**2 + thickness**2) / 12,
            mass * (length**2 + thickness**2) / 12,
            mass * (length**2 + width**2) / 12,
        ],
        "angle_deg": draw(st.floats(-180.0, 180.0)),
        "damping_ratio": draw(st.floats(0.001, 0.05)),
        "modes": modes,
    }


def _engine(draw: st.DrawFn, cubesat_mass_kg: float) -> dict[str, Any]:
    stages = draw(st.integers(1, 3))
    thrust_mN = draw(st.floats(0.05, 5.0))
    isp_s = draw(st.floats(300.0, 4000.0))
    # Life such that this engine's propellant is at most a tenth of its CubeSat's mass
    # (three engines then stay below the mass, as the loader requires).
    most_h = 0.1 * cubesat_mass_kg * isp_s * G0_M_S2 / (stages * thrust_mN * 1e-3) / 3600
    return {
        "direction": _unit(draw),
        "offset_m": [draw(st.floats(-0.05, 0.05)) for _ in range(3)],
        "stages": stages,
        "thrust_per_stage_mN": thrust_mN,
        "isp_s": isp_s,
        "stage_life_h": min(500.0, most_h * draw(st.floats(0.1, 1.0))),
    }


def _cubesat(draw: st.DrawFn, size: list[float]) -> dict[str, Any]:
    face = draw(st.sampled_from(SIGNED_AXES))
    mass = draw(st.floats(1.0, 12.0))
    dims = [draw(st.floats(0.1, 0.4)) for _ in range(3)]
    return {
        "position_corner_m": _face_point(draw, size, face, draw(st.floats(0.0, 0.2)), 0.05),
        "mass_kg": mass,
        "inertia_kgm2": _box_moments(mass, *dims),
        "face": face,
        "engines": [_engine(draw, mass) for _ in range(draw(st.integers(1, 3)))],
    }


@st.composite
def problems(draw: st.DrawFn) -> dict[str, Any]:
    """Parsed TOML of a random valid problem, without its disturbance scaled yet."""
    data = copy.deepcopy(paper_data())
    data.pop("cubesat_layout", None)
    hub = _hub(draw)
    faces = draw(st.permutations(SIGNED_AXES))
    data["name"] = "valid"
    data["hub"] = hub
    data["arrays"] = [_array(draw, hub["size_m"], faces[i]) for i in range(draw(st.integers(0, 2)))]
    data["cubesats"] = [_cubesat(draw, hub["size_m"]) for _ in range(draw(st.integers(5, 12)))]
    data["disturbance"]["phase_deg"] = [draw(st.floats(0.0, 360.0)) for _ in range(3)]
    data["_disturbance_fraction"] = [draw(st.floats(0.05, 0.8)) for _ in range(3)]
    return data


# ------------------------------------------------------------------ references


@dataclass(frozen=True)
class Reference:
    """What a problem's numbers imply, computed here (SI, body frame B at the CoG)."""

    mass_kg: float
    cog_corner_m: np.ndarray
    inertia_kgm2: np.ndarray  # (3, 3) about the CoG, arrays at their nominal angle
    torque_per_N: np.ndarray  # (3, n_engines): r x d
    direction: np.ndarray  # (3, n_engines): unit force per N
    max_thrust_N: np.ndarray  # (n_engines,)

    def authority_Nm(self, zero_net_force: bool) -> dict[str, float]:
        return lp_authority_Nm(self.torque_per_N, self.direction, self.max_thrust_N, zero_net_force)


def _array_frame(direction: np.ndarray, angle_rad: float) -> np.ndarray:
    """Columns: length, width, normal, as documented: the normal at angle 0 is the hub
    axis after the length's main axis in cyclic order; the angle turns it about the
    positive hinge axis; width = normal x length."""
    main = int(np.argmax(np.abs(direction)))
    hinge = direction if direction[main] > 0 else -direction
    n0 = np.zeros(3)
    n0[(main + 1) % 3] = 1.0
    n0 = n0 - (n0 @ hinge) * hinge
    n0 /= np.linalg.norm(n0)
    normal = math.cos(angle_rad) * n0 + math.sin(angle_rad) * np.cross(hinge, n0)
    return np.column_stack([direction, np.cross(normal, direction), normal])


def _signed_axis(value: str | list[float]) -> np.ndarray:
    if isinstance(value, str):
        v = np.zeros(3)
        v["xyz".index(value[1])] = 1.0 if value[0] == "+" else -1.0
        return v
    v = np.asarray(value, dtype=float)
    return v / np.linalg.norm(v)


def _parallel(mass_kg: float, r: np.ndarray) -> np.ndarray:
    return mass_kg * (float(r @ r) * np.eye(3) - np.outer(r, r))


def reference(data: dict[str, Any]) -> Reference:
    """Mass properties and engine maps of parsed problem data, by hand."""
    bodies: list[tuple[float, np.ndarray, np.ndarray]] = []  # mass, CoG (corner), own inertia
    hub = data["hub"]
    bodies.append((hub["mass_kg"], np.array(hub["cog_corner_m"]), np.array(hub["inertia_kgm2"])))
    for array in data["arrays"]:
        d = _signed_axis(array["direction"])
        frame = _array_frame(d, math.radians(array["angle_deg"]))
        own = frame @ np.diag(array["inertia_kgm2"]) @ frame.T
        cog = np.array(array["hinge_corner_m"]) + 0.5 * array["length_m"] * d
        bodies.append((array["mass_kg"], cog, own))
    for cubesat in data["cubesats"]:
        own = np.diag(cubesat["inertia_kgm2"])
        bodies.append((cubesat["mass_kg"], np.array(cubesat["position_corner_m"]), own))
    mass = sum(m for m, _, _ in bodies)
    cog = sum(m * r for m, r, _ in bodies) / mass
    inertia = sum(own + _parallel(m, r - cog) for m, r, own in bodies)
    torques, directions, limits = [], [], []
    for cubesat in data["cubesats"]:
        for engine in cubesat["engines"]:
            d = _signed_axis(engine["direction"])
            r = np.array(cubesat["position_corner_m"]) + np.array(engine.get("offset_m", [0, 0, 0]))
            torques.append(np.cross(r - cog, d))
            directions.append(d)
            # An engine without its own limit takes the file's [engine] one.
            thrust_mN = engine.get("thrust_per_stage_mN", data["engine"]["thrust_per_stage_mN"])
            limits.append(thrust_mN * 1e-3)
    return Reference(
        mass_kg=mass,
        cog_corner_m=cog,
        inertia_kgm2=inertia,
        torque_per_N=np.array(torques).T,
        direction=np.array(directions).T,
        max_thrust_N=np.array(limits),
    )


def lp_authority_Nm(
    torque_per_N: np.ndarray, direction: np.ndarray, max_thrust_N: np.ndarray, zero_net_force: bool
) -> dict[str, float]:
    """Largest pure torque about each signed axis, by an LP per axis [N m].

    max s.t. torque along the axis, none about the others, (no net force),
    0 <= f <= f_max. Posed in mN and mNm, as :func:`lp_reach` (HiGHS' tolerances are
    absolute: a pure torque of 1e-7 N m is below them in newtons).
    """
    authority = {}
    for name in SIGNED_AXES:
        axis = "xyz".index(name[1])
        sign = 1.0 if name[0] == "+" else -1.0
        others = [a for a in range(3) if a != axis]
        rows = [torque_per_N[others]] + ([direction] if zero_net_force else [])
        equalities = np.vstack(rows)
        result = linprog(
            -sign * torque_per_N[axis],
            A_eq=equalities,
            b_eq=np.zeros(len(equalities)),
            bounds=[(0.0, f * 1e3) for f in max_thrust_N],
            method="highs",
        )
        assert result.status == 0, result.message
        authority[name] = max(0.0, -result.fun) * 1e-3
    return authority


def lp_reach(ref: Reference, unit: np.ndarray, zero_net_force: bool) -> float:
    """Largest s with s * unit a torque the engines make (with zero net force) [N m].

    Posed in mN and mNm (HiGHS' tolerances are absolute; thrusts are of order 1e-3 N)."""
    n = ref.max_thrust_N.size
    # Variables: thrusts f, then s. B f - s u = 0 (and F f = 0); maximise s.
    a_eq = np.hstack([ref.torque_per_N, -unit[:, None]])
    if zero_net_force:
        a_eq = np.vstack([a_eq, np.hstack([ref.direction, np.zeros((3, 1))])])
    result = linprog(
        np.r_[np.zeros(n), -1.0],
        A_eq=a_eq,
        b_eq=np.zeros(a_eq.shape[0]),
        bounds=[(0.0, f * 1e3) for f in ref.max_thrust_N] + [(0.0, None)],
        method="highs",
    )
    assert result.status == 0, result.message
    return float(-result.fun) * 1e-3


def lp_gauge(ref: Reference, torque_Nm: np.ndarray, zero_net_force: bool) -> np.ndarray:
    """Gauge of each torque (rows) in the engines' torque set: |tau| / (reach along
    tau / |tau|), 0 for a zero torque; one LP per distinct row, shape (n,)."""
    torque = np.atleast_2d(np.asarray(torque_Nm, dtype=float))
    sizes = np.linalg.norm(torque, axis=1)
    gauge = np.zeros(len(torque))
    active = np.flatnonzero(sizes > 1e-12 * max(float(sizes.max(initial=0.0)), 1e-300))
    if active.size == 0:
        return gauge
    rows, inverse = np.unique(torque[active], axis=0, return_inverse=True)
    values = np.array(
        [np.linalg.norm(r) / lp_reach(ref, r / np.linalg.norm(r), zero_net_force) for r in rows]
    )
    gauge[active] = values[np.ravel(inverse)]
    return gauge


def with_disturbance(data: dict[str, Any], ref: Reference) -> dict[str, Any]:
    """The data with its disturbance a drawn fraction of the zero-net-force authority."""
    authority = ref.authority_Nm(zero_net_force=True)
    fractions = data["_disturbance_fraction"]
    out = {k: v for k, v in data.items() if k != "_disturbance_fraction"}
    out["disturbance"] = dict(out["disturbance"])
    out["disturbance"]["amplitude_mNm"] = [
        fractions[i] * 1e3 * min(authority[f"+{a}"], authority[f"-{a}"])
        for i, a in enumerate("xyz")
    ]
    return out


# ------------------------------------------------------------------ TOML out


def _value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        assert math.isfinite(value), value
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_value(v) for v in value) + "]"
    raise TypeError(f"no TOML for {type(value).__name__}")


def _is_table_list(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _emit(table: dict[str, Any], prefix: str, lines: list[str]) -> None:
    for key, value in table.items():
        if not isinstance(value, dict) and not _is_table_list(value):
            lines.append(f"{key} = {_value(value)}")
    for key, value in table.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            lines.append(f"\n[{name}]")
            _emit(value, f"{name}.", lines)
        elif _is_table_list(value):
            for item in value:
                lines.append(f"\n[[{name}]]")
                _emit(item, f"{name}.", lines)


def write_toml(data: dict[str, Any], path: Path) -> Path:
    """Write parsed problem data back as a TOML file (what a user would write)."""
    lines: list[str] = []
    # An empty array list must stay an empty list (a rigid debris), not vanish.
    _emit(data, "", lines)
    path.write_text("\n".join(lines) + "\n")
    with path.open("rb") as handle:
        assert tomllib.load(handle) == data
    return path
