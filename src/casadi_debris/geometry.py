"""Geometry and mass properties of the combined body (debris hub + arrays + CubeSats).

Frames
------
The paper gives points in a *hub-corner* frame (origin at a hub corner, axes
along the hub edges, hub spanning [0, size] per axis). The toolkit works in the
body frame B: same axes, origin at the combined centre of gravity (hub, arrays
undeformed at their nominal angle, CubeSats). ``*_corner_m`` names mark the
corner frame; everything else is in B.

CubeSat layout (paper, Section II.D)
------------------------------------
Four CubeSats on every hub face, one near each corner of the face, inset from
both edges by ``edge_margin_fraction`` of the half edge length, their CoG
``standoff_m`` above the face. Each fires its iESE along the face's inward
normal, one direction only. Reading the 10 % margin as a fraction of the half
edge (not of the whole edge) is what reproduces the paper's torque authority
(4.61, 1.96, 4.26 mNm); with the whole edge it would be 11 % lower.

Array angle
-----------
Array ``i`` extends from its hinge along ``e_L`` (a signed hub axis). At
theta_SA = 0 its normal ``n`` is the next hub axis in cyclic order (+x for
arrays along z); theta_SA turns both arrays about the positive hinge axis. The
array frame is (length ``e_L``, width ``w = n x e_L``, normal ``n``), the axes of
the problem's principal array inertia. Functions of the angle accept floats
and CasADi symbols alike, so the symbolic model and the numbers printed here
come from one piece of code.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np
from scipy.optimize import linprog

from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, Problem
from casadi_debris.units import MN_PER_N


def signed_axis_vector(name: str) -> np.ndarray:
    """Unit vector of a signed axis name such as ``"-z"``, shape (3,)."""
    vector = np.zeros(3)
    vector[AXIS_NAMES.index(name[1])] = 1.0 if name[0] == "+" else -1.0
    return vector


def _next_axis(axis: int) -> np.ndarray:
    vector = np.zeros(3)
    vector[(axis + 1) % 3] = 1.0
    return vector


@dataclass(frozen=True, eq=False)
class CubeSatMount:
    """One docked CubeSat and its engine.

    Attributes
    ----------
    index : int
        0-based id, faces in the order +x, -x, +y, -y, +z, -z.
    face : str
        Signed axis of the face's outward normal.
    position_m : ndarray, shape (3,)
        CoG (and thrust application point) in body frame B.
    direction : ndarray, shape (3,)
        Unit force the engine exerts on the body (inward face normal).
    max_thrust_N : float
        Thrust of one stage.
    """

    index: int
    face: str
    position_m: np.ndarray
    direction: np.ndarray
    max_thrust_N: float


@dataclass(frozen=True, eq=False)
class Geometry:
    """Placement and mass properties derived from a :class:`Problem`.

    Attributes
    ----------
    mass_kg : float
        Total mass (hub + arrays + CubeSats).
    cog_corner_m : ndarray, shape (3,)
        Combined CoG in the hub-corner frame (origin of B).
    inertia_hub_cubesats_kgm2 : ndarray, shape (3, 3)
        Hub + CubeSats about the combined CoG (the paper's I_tot).
    inertia_arrays_kgm2 : ndarray, shape (3, 3)
        Both arrays as rigid bodies about the combined CoG at the nominal angle.
    inertia_total_kgm2 : ndarray, shape (3, 3)
        Full rigid inertia (sum of the two above).
    hinges_m : ndarray, shape (n_arrays, 3)
        Hinge points in B.
    array_directions : ndarray, shape (n_arrays, 3)
        Unit vectors along which the arrays extend.
    cubesats : tuple of CubeSatMount
    torque_map : ndarray, shape (3, n_cubesats)
        Torque about the CoG per newton of each engine [N m / N].
    force_map : ndarray, shape (3, n_cubesats)
        Force on the body per newton of each engine.
    """

    mass_kg: float
    cog_corner_m: np.ndarray
    inertia_hub_cubesats_kgm2: np.ndarray
    inertia_arrays_kgm2: np.ndarray
    inertia_total_kgm2: np.ndarray
    hinges_m: np.ndarray
    array_directions: np.ndarray
    cubesats: tuple[CubeSatMount, ...]
    torque_map: np.ndarray
    force_map: np.ndarray


def point_mass_inertia(mass_kg: float, offset_m: np.ndarray) -> np.ndarray:
    """Parallel-axis term m (|r|^2 I - r r^T) of a mass at ``offset_m``, shape (3, 3)."""
    r = np.asarray(offset_m, dtype=float)
    return mass_kg * (float(r @ r) * np.eye(3) - np.outer(r, r))


def _cubesat_layout(problem: Problem) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """Faces, corner-frame positions and force directions of the corner layout."""
    size = problem.hub.size_m
    margin = problem.cubesats.edge_margin_fraction
    standoff = problem.cubesats.standoff_m
    centre = size / 2.0
    layout: list[tuple[str, np.ndarray, np.ndarray]] = []
    for face in SIGNED_AXES:
        normal = signed_axis_vector(face)
        axis = AXIS_NAMES.index(face[1])
        in_face = [a for a in range(3) if a != axis]
        for s1 in (+1.0, -1.0):
            for s2 in (+1.0, -1.0):
                offset = normal * (centre[axis] + standoff)
                offset[in_face[0]] = s1 * (1.0 - margin) * centre[in_face[0]]
                offset[in_face[1]] = s2 * (1.0 - margin) * centre[in_face[1]]
                layout.append((face, centre + offset, -normal))
    return layout


def _cubesat_own_inertia(problem: Problem, face: str) -> np.ndarray:
    """CubeSat inertia in hub axes: its x (thrust) axis along the face normal, long axis next."""
    axis = AXIS_NAMES.index(face[1])
    moments = problem.cubesats.inertia_kgm2
    # CubeSat axes x, y, z (long) map to hub axes: normal, the one after the long one, next.
    hub_axis_of = {0: axis, 2: (axis + 1) % 3, 1: (axis + 2) % 3}
    inertia = np.zeros((3, 3))
    for own, hub_axis in hub_axis_of.items():
        inertia[hub_axis, hub_axis] = moments[own]
    return inertia


def array_axes(
    direction: np.ndarray, angle_rad: float | ca.SX
) -> tuple[ca.DM, ca.SX | ca.DM, ca.SX | ca.DM]:
    """Length, width and normal unit vectors of an array at angle theta_SA.

    Parameters
    ----------
    direction : ndarray, shape (3,)
        Signed hub axis along which the array extends.
    angle_rad : float or casadi.SX
        theta_SA, about the positive hinge axis.

    Returns
    -------
    e_length, e_width, e_normal : casadi column vectors, shape (3, 1)
        ``casadi.DM``, the last two ``casadi.SX`` for a symbolic angle.
    """
    axis = int(np.argmax(np.abs(direction)))
    positive_axis = np.zeros(3)
    positive_axis[axis] = 1.0
    n0 = _next_axis(axis)
    normal = ca.cos(angle_rad) * ca.DM(n0) + ca.sin(angle_rad) * ca.DM(np.cross(positive_axis, n0))
    e_length = ca.DM(direction)
    e_width = ca.cross(normal, e_length)
    return e_length, e_width, normal


def array_rigid_inertia(
    problem: Problem, hinge_m: np.ndarray, direction: np.ndarray, angle_rad: float | ca.SX
) -> ca.SX:
    """Inertia of one undeformed array about the origin of B, shape (3, 3).

    Principal inertia rotated into B (R diag(I) R^T) plus the parallel-axis
    term of its CoG, half a length out from the hinge along the hinge axis.
    """
    arrays = problem.arrays
    e_length, e_width, normal = array_axes(direction, angle_rad)
    rotation = ca.horzcat(e_length, e_width, normal)
    own = rotation @ ca.diag(ca.DM(arrays.inertia_kgm2)) @ rotation.T
    cog = hinge_m + 0.5 * arrays.length_m * direction
    return own + ca.DM(point_mass_inertia(arrays.mass_kg, cog))


def build_geometry(problem: Problem) -> Geometry:
    """Place the CubeSats and compute the combined mass properties.

    Parameters
    ----------
    problem : Problem

    Returns
    -------
    Geometry
        Everything in SI, positions in body frame B.
    """
    hub, arrays, cubesats = problem.hub, problem.arrays, problem.cubesats
    layout = _cubesat_layout(problem)
    directions = np.array([signed_axis_vector(d) for d in arrays.directions])
    array_cogs = arrays.hinges_corner_m + 0.5 * arrays.length_m * directions

    masses = [hub.mass_kg] + [cubesats.mass_kg] * len(layout) + [arrays.mass_kg] * len(directions)
    points = [hub.cog_corner_m] + [p for _, p, _ in layout] + list(array_cogs)
    mass = float(sum(masses))
    cog = sum(m * p for m, p in zip(masses, points, strict=True)) / mass

    inertia_hc = hub.inertia_kgm2 + point_mass_inertia(hub.mass_kg, hub.cog_corner_m - cog)
    mounts = []
    thrust_N = problem.engine.thrust_per_stage_mN / MN_PER_N
    for index, (face, position_corner, force_direction) in enumerate(layout):
        position = position_corner - cog
        inertia_hc = (
            inertia_hc
            + _cubesat_own_inertia(problem, face)
            + point_mass_inertia(cubesats.mass_kg, position)
        )
        mounts.append(CubeSatMount(index, face, position, force_direction, thrust_N))

    hinges = arrays.hinges_corner_m - cog
    angle = math.radians(arrays.angle_deg)
    # Starts from zeros so that a debris without arrays has a (3, 3) zero, not 0.
    inertia_arrays = sum(
        (
            np.array(array_rigid_inertia(problem, h, d, angle))
            for h, d in zip(hinges, directions, strict=True)
        ),
        np.zeros((3, 3)),
    )
    force_map = np.array([m.direction for m in mounts]).T
    torque_map = np.cross(np.array([m.position_m for m in mounts]), force_map.T).T
    return Geometry(
        mass_kg=mass,
        cog_corner_m=cog,
        inertia_hub_cubesats_kgm2=inertia_hc,
        inertia_arrays_kgm2=inertia_arrays,
        inertia_total_kgm2=inertia_hc + inertia_arrays,
        hinges_m=hinges,
        array_directions=directions,
        cubesats=tuple(mounts),
        torque_map=torque_map,
        force_map=force_map,
    )


def max_thrust_N(geometry: Geometry) -> np.ndarray:
    """Per-engine thrust limit of the active stage, shape (n_cubesats,)."""
    return np.array([m.max_thrust_N for m in geometry.cubesats])


def torque_authority(
    geometry: Geometry, zero_net_force: bool = False, available: np.ndarray | None = None
) -> dict[str, float]:
    """Largest pure torque about each signed body axis, by linear programming.

    For each signed axis a, maximise tau_a subject to the other two torque
    components being zero, 0 <= f_i <= f_max,i and, optionally, zero net force.

    Parameters
    ----------
    geometry : Geometry
    zero_net_force : bool
        Also require the engines' forces to cancel.
    available : ndarray of bool, shape (n_cubesats,), optional
        Engines that may fire (default all).

    Returns
    -------
    dict
        ``{"+x": tau [N m], "-x": ..., ...}``.
    """
    limits = max_thrust_N(geometry)
    if available is not None:
        limits = np.where(available, limits, 0.0)
    authority: dict[str, float] = {}
    for name in SIGNED_AXES:
        axis = AXIS_NAMES.index(name[1])
        sign = 1.0 if name[0] == "+" else -1.0
        others = [a for a in range(3) if a != axis]
        a_eq = geometry.torque_map[others]
        if zero_net_force:
            a_eq = np.vstack([a_eq, geometry.force_map])
        result = linprog(
            -sign * geometry.torque_map[axis],
            A_eq=a_eq,
            b_eq=np.zeros(len(a_eq)),
            bounds=list(zip(np.zeros_like(limits), limits, strict=True)),
            method="highs",
        )
        authority[name] = (
            -float(result.fun) if result.status == 0 and result.fun is not None else 0.0
        )
    return authority
