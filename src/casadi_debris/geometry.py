"""Geometry and mass properties of the combined body (debris hub + arrays + CubeSats).

Frames
------
The paper gives points in a *hub-corner* frame (origin at a hub corner, axes
along the hub edges, hub spanning [0, size] per axis). The toolkit works in the
body frame B: same axes, origin at the combined centre of gravity (hub, arrays
undeformed at their nominal angle, CubeSats). ``*_corner_m`` names mark the
corner frame; everything else is in B.

CubeSats and engines
--------------------
The problem lists its CubeSats (an explicit ``[[cubesats]]`` list, or one a
``[cubesat_layout]`` generated: see :mod:`casadi_debris.config`), each
with one or more engines. Every engine is one column of the torque and force
maps: its force direction, applied at the CubeSat's CoG plus the engine's
offset.

Array angle
-----------
Array ``i`` extends from its hinge along ``e_L``. At theta_SA = 0 its normal
``n`` is the hub axis after ``e_L``'s main axis in cyclic order (+x for arrays
along z), made normal to ``e_L``; theta_SA turns the array about the positive
hinge axis. The
array frame is (length ``e_L``, width ``w = n x e_L``, normal ``n``), the axes of
the problem's principal array inertia. Functions of the angle accept floats
and CasADi symbols alike, so the symbolic model and the numbers printed here
come from one piece of code.
"""

from __future__ import annotations

import math
from collections.abc import Iterator, Mapping
from dataclasses import dataclass

import casadi as ca
import numpy as np
from scipy.linalg import block_diag
from scipy.optimize import linprog

from casadi_debris.config import AXIS_NAMES, SIGNED_AXES, Array, Problem
from casadi_debris.errors import CasadiDebrisError
from casadi_debris.units import MN_PER_N


def _next_axis(axis: int) -> np.ndarray:
    vector = np.zeros(3)
    vector[(axis + 1) % 3] = 1.0
    return vector


@dataclass(frozen=True, eq=False)
class CubeSatMount:
    """One docked CubeSat.

    Attributes
    ----------
    index : int
        0-based (CubeSat ``index + 1`` to a user), in the problem's order.
    face : str or None
        Signed axis of the face it docks on, when known.
    position_m : ndarray, shape (3,)
        CoG in body frame B.
    mass_kg : float
    engines : tuple of int
        Its engines (0-based indices into ``Geometry.engines``).
    """

    index: int
    face: str | None
    position_m: np.ndarray
    mass_kg: float
    engines: tuple[int, ...]


@dataclass(frozen=True, eq=False)
class EngineMount:
    """One engine, a column of the torque and force maps.

    Attributes
    ----------
    index : int
        0-based, CubeSat by CubeSat.
    cubesat : int
        0-based index of its CubeSat.
    position_m : ndarray, shape (3,)
        Where its force acts, body frame B.
    direction : ndarray, shape (3,)
        Unit force the engine exerts on the body.
    max_thrust_N : float
        Thrust of one stage.
    """

    index: int
    cubesat: int
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
        The arrays as rigid bodies about the combined CoG at their nominal angles.
    inertia_total_kgm2 : ndarray, shape (3, 3)
        Full rigid inertia (sum of the two above).
    hinges_m : ndarray, shape (n_arrays, 3)
        Hinge points in B.
    array_directions : ndarray, shape (n_arrays, 3)
        Unit vectors along which the arrays extend.
    cubesats : tuple of CubeSatMount
    engines : tuple of EngineMount
    torque_map : ndarray, shape (3, n_engines)
        Torque about the CoG per newton of each engine [N m / N].
    force_map : ndarray, shape (3, n_engines)
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
    engines: tuple[EngineMount, ...]
    torque_map: np.ndarray
    force_map: np.ndarray

    @property
    def engine_cubesat(self) -> np.ndarray:
        """The CubeSat (0-based) of every engine, shape (n_engines,)."""
        return np.array([engine.cubesat for engine in self.engines], dtype=int)


def point_mass_inertia(mass_kg: float, offset_m: np.ndarray) -> np.ndarray:
    """Parallel-axis term m (|r|^2 I - r r^T) of a mass at ``offset_m``, shape (3, 3)."""
    r = np.asarray(offset_m, dtype=float)
    return mass_kg * (float(r @ r) * np.eye(3) - np.outer(r, r))


def array_axes(
    direction: np.ndarray, angle_rad: float | ca.SX
) -> tuple[ca.DM, ca.SX | ca.DM, ca.SX | ca.DM]:
    """Length, width and normal unit vectors of an array at angle theta_SA.

    Parameters
    ----------
    direction : ndarray, shape (3,)
        Unit vector along which the array extends.
    angle_rad : float or casadi.SX
        theta_SA, about the positive hinge axis (``direction`` or its opposite,
        whichever is positive along its main body axis).

    Returns
    -------
    e_length, e_width, e_normal : casadi column vectors, shape (3, 1)
        ``casadi.DM``, the last two ``casadi.SX`` for a symbolic angle.
    """
    direction = np.asarray(direction, dtype=float)
    axis = int(np.argmax(np.abs(direction)))
    hinge_axis = direction if direction[axis] > 0 else -direction
    # The next hub axis, made normal to the hinge axis (a no-op for an array along an axis).
    n0 = _next_axis(axis)
    n0 = n0 - float(n0 @ hinge_axis) * hinge_axis
    n0 = n0 / np.linalg.norm(n0)
    normal = ca.cos(angle_rad) * ca.DM(n0) + ca.sin(angle_rad) * ca.DM(np.cross(hinge_axis, n0))
    e_length = ca.DM(direction)
    e_width = ca.cross(normal, e_length)
    return e_length, e_width, normal


def array_rigid_inertia(
    array: Array, hinge_m: np.ndarray, angle_rad: float | ca.SX
) -> ca.SX | ca.DM:
    """Inertia of one undeformed array about the origin of B, shape (3, 3).

    Principal inertia rotated into B (R diag(I) R^T) plus the parallel-axis
    term of its CoG, half a length out from the hinge along the hinge axis.

    Parameters
    ----------
    array : Array
    hinge_m : ndarray, shape (3,)
        Its hinge in B.
    angle_rad : float or casadi.SX
        theta_SA.
    """
    e_length, e_width, normal = array_axes(array.direction, angle_rad)
    rotation = ca.horzcat(e_length, e_width, normal)
    own = rotation @ ca.diag(ca.DM(array.inertia_kgm2)) @ rotation.T
    cog = hinge_m + 0.5 * array.length_m * array.direction
    return own + ca.DM(point_mass_inertia(array.mass_kg, cog))


def build_geometry(problem: Problem) -> Geometry:
    """Place the CubeSats and engines and compute the combined mass properties.

    Parameters
    ----------
    problem : Problem

    Returns
    -------
    Geometry
        Everything in SI, positions in body frame B.
    """
    hub, arrays, cubesats = problem.hub, problem.arrays, problem.cubesats
    array_cogs = [a.hinge_corner_m + 0.5 * a.length_m * a.direction for a in arrays]
    masses = [hub.mass_kg] + [c.mass_kg for c in cubesats] + [a.mass_kg for a in arrays]
    points = [hub.cog_corner_m] + [c.position_corner_m for c in cubesats] + array_cogs
    mass = float(sum(masses))
    cog = np.asarray(sum(m * p for m, p in zip(masses, points, strict=True)) / mass)

    inertia_hc = hub.inertia_kgm2 + point_mass_inertia(hub.mass_kg, hub.cog_corner_m - cog)
    mounts: list[CubeSatMount] = []
    engines: list[EngineMount] = []
    for index, cubesat in enumerate(cubesats):
        position = cubesat.position_corner_m - cog
        inertia_hc = (
            inertia_hc + cubesat.inertia_kgm2 + point_mass_inertia(cubesat.mass_kg, position)
        )
        first = len(engines)
        for engine in cubesat.engines:
            engines.append(
                EngineMount(
                    index=len(engines),
                    cubesat=index,
                    position_m=position + engine.offset_m,
                    direction=engine.direction,
                    max_thrust_N=engine.thrust_per_stage_mN / MN_PER_N,
                )
            )
        engine_ids = tuple(range(first, len(engines)))
        mounts.append(CubeSatMount(index, cubesat.face, position, cubesat.mass_kg, engine_ids))

    hinges = np.array([a.hinge_corner_m - cog for a in arrays]).reshape(-1, 3)
    # Starts from zeros so that a debris without arrays has a (3, 3) zero, not 0.
    inertia_arrays = sum(
        (
            np.array(array_rigid_inertia(a, h, math.radians(a.angle_deg)))
            for a, h in zip(arrays, hinges, strict=True)
        ),
        np.zeros((3, 3)),
    )
    force_map = np.array([e.direction for e in engines]).T
    torque_map = np.cross(np.array([e.position_m for e in engines]), force_map.T).T
    return Geometry(
        mass_kg=mass,
        cog_corner_m=cog,
        inertia_hub_cubesats_kgm2=inertia_hc,
        inertia_arrays_kgm2=inertia_arrays,
        inertia_total_kgm2=inertia_hc + inertia_arrays,
        hinges_m=hinges,
        array_directions=np.array([a.direction for a in arrays]).reshape(-1, 3),
        cubesats=tuple(mounts),
        engines=tuple(engines),
        torque_map=torque_map,
        force_map=force_map,
    )


def max_thrust_N(geometry: Geometry) -> np.ndarray:
    """Per-engine thrust of one stage, shape (n_engines,)."""
    return np.array([e.max_thrust_N for e in geometry.engines])


def signed_axis(name: str) -> tuple[int, float]:
    """Axis index and sign of ``"+x"`` ... ``"-z"``."""
    return AXIS_NAMES.index(name[1]), 1.0 if name[0] == "+" else -1.0


def axis_authority_Nm(
    torque_map: np.ndarray,
    force_map: np.ndarray,
    max_thrust_N: np.ndarray,
    zero_net_force: bool = True,
) -> np.ndarray:
    """Largest pure torque about each signed body axis [N m], by one linear programme.

    For each signed axis a, maximise tau_a subject to the other two torque
    components being zero, 0 <= f_i <= f_max,i and, optionally, zero net force.
    The six axes are independent blocks of one LP (the sum of six independent
    maxima is maximised by each block's own maximum), which saves five solver
    calls; thrust is counted in units of the largest bound, so that HiGHS'
    absolute tolerances see numbers of order one.

    Parameters
    ----------
    torque_map, force_map : ndarray, shape (3, n)
        Per newton of each engine (about any point when the force cancels).
    max_thrust_N : ndarray, shape (n,)
        Upper thrust bounds (0 for an engine that may not fire).
    zero_net_force : bool
        Also require the engines' forces to cancel.

    Returns
    -------
    ndarray, shape (6,)
        In the order of ``SIGNED_AXES`` (+x, -x, +y, -y, +z, -z).

    Raises
    ------
    CasadiDebrisError
        HiGHS failed (the LP itself is always feasible: no thrust at all).
    """
    limits = np.asarray(max_thrust_N, dtype=float)
    n = len(limits)
    if n == 0 or not np.any(limits > 0):
        return np.zeros(len(SIGNED_AXES))
    unit = float(np.max(limits))
    blocks, objective = [], []
    for name in SIGNED_AXES:
        axis, sign = signed_axis(name)
        rows = torque_map[[a for a in range(3) if a != axis]]
        blocks.append(np.vstack([rows, force_map]) if zero_net_force else rows)
        objective.append(-sign * torque_map[axis])
    a_eq = block_diag(*blocks)
    upper = np.tile(limits / unit, len(SIGNED_AXES))
    result = linprog(
        np.concatenate(objective),
        A_eq=a_eq,
        b_eq=np.zeros(a_eq.shape[0]),
        bounds=[(0.0, float(u)) for u in upper],
        method="highs",
    )
    if result.status != 0 or result.x is None:
        raise CasadiDebrisError(f"torque authority LP failed: {result.message}")
    per_block = -np.array(objective) * result.x.reshape(len(SIGNED_AXES), n)
    return np.maximum(per_block.sum(axis=1), 0.0) * unit + 0.0  # + 0.0: no -0.0


@dataclass(frozen=True, eq=False)
class Authority(Mapping[str, float]):
    """The largest pure torque about each signed body axis [N m], with or without net force.

    The one form of a torque authority: read it by signed axis (``authority["-y"]``, as a
    mapping in the order ``SIGNED_AXES``) or through its named arrays; it becomes mN·m
    only at the edges (:meth:`to_mNm`). Equal to a mapping of the same values.

    Attributes
    ----------
    torque_Nm : ndarray, shape (6,)
        About +x, -x, +y, -y, +z, -z (magnitudes, >= 0) [N m].
    zero_net_force : bool
        Whether the engines' forces cancel (as the closed loop's allocator keeps them).
    """

    torque_Nm: np.ndarray
    zero_net_force: bool

    def __post_init__(self) -> None:
        torque = np.array(self.torque_Nm, dtype=float)
        if torque.shape != (len(SIGNED_AXES),):
            raise CasadiDebrisError(f"authority: six signed axes, got shape {torque.shape}")
        torque.setflags(write=False)
        object.__setattr__(self, "torque_Nm", torque)

    def __getitem__(self, signed_axis: str) -> float:
        return float(self.torque_Nm[SIGNED_AXES.index(signed_axis)])

    def __iter__(self) -> Iterator[str]:
        return iter(SIGNED_AXES)

    def __len__(self) -> int:
        return len(SIGNED_AXES)

    @property
    def positive_Nm(self) -> np.ndarray:
        """About +x, +y, +z [N m], shape (3,)."""
        return np.asarray(self.torque_Nm[0::2])

    @property
    def negative_Nm(self) -> np.ndarray:
        """About -x, -y, -z (magnitudes) [N m], shape (3,)."""
        return np.asarray(self.torque_Nm[1::2])

    @property
    def weakest_Nm(self) -> np.ndarray:
        """The smaller of the two signs about x, y, z [N m], shape (3,)."""
        return np.minimum(self.positive_Nm, self.negative_Nm)

    def to_mNm(self) -> dict[str, float]:
        """``{"+x": tau [mN m], ...}``, as the JSON files write it."""
        return {name: value * MN_PER_N for name, value in self.items()}


def torque_authority(
    geometry: Geometry, zero_net_force: bool = False, available: np.ndarray | None = None
) -> Authority:
    """Largest pure torque about each signed body axis, by linear programming
    (:func:`axis_authority_Nm` on the geometry's engines).

    Parameters
    ----------
    geometry : Geometry
    zero_net_force : bool
        Also require the engines' forces to cancel.
    available : ndarray of bool, shape (n_engines,), optional
        Engines that may fire (default all).

    Returns
    -------
    Authority
    """
    limits = max_thrust_N(geometry)
    if available is not None:
        limits = np.where(available, limits, 0.0)
    authority = axis_authority_Nm(geometry.torque_map, geometry.force_map, limits, zero_net_force)
    return Authority(authority, zero_net_force)


def thrust_directions(geometry: Geometry) -> list[tuple[np.ndarray, list[int]]]:
    """The engines grouped by the direction of their force: (unit direction, engine indices).

    Directions within 1e-6 of each other are one; in order of first appearance.
    """
    groups: list[tuple[np.ndarray, list[int]]] = []
    for engine in geometry.engines:
        for direction, members in groups:
            if np.linalg.norm(direction - engine.direction) < 1e-6:
                members.append(engine.index)
                break
        else:
            groups.append((engine.direction, [engine.index]))
    return groups


def force_authority(
    geometry: Geometry, direction: np.ndarray, available: np.ndarray | None = None
) -> tuple[float, np.ndarray]:
    """Largest pure force along a body direction at zero net torque, by linear programming.

    Maximise s subject to ``force_map f = s d``, ``torque_map f = 0`` and
    0 <= f_i <= f_max,i: the force part of :func:`torque_authority`'s LP.

    Parameters
    ----------
    geometry : Geometry
    direction : ndarray, shape (3,)
        Unit direction d in body frame B.
    available : ndarray of bool, shape (n_engines,), optional
        Engines that may fire (default all).

    Returns
    -------
    force_N : float
        s, 0 when no thrust along d can be balanced.
    thrust_N : ndarray, shape (n_engines,)
        The engines' thrusts giving it.
    """
    limits = max_thrust_N(geometry)
    if available is not None:
        limits = np.where(available, limits, 0.0)
    d = np.asarray(direction, dtype=float)
    n = len(limits)
    # Variables [f (n), s]: F f - s d = 0, B f = 0.
    a_eq = np.block([[geometry.force_map, -d[:, None]], [geometry.torque_map, np.zeros((3, 1))]])
    cost = np.zeros(n + 1)
    cost[-1] = -1.0
    result = linprog(
        cost,
        A_eq=a_eq,
        b_eq=np.zeros(6),
        bounds=[*zip(np.zeros(n), limits, strict=True), (0.0, None)],
        method="highs",
    )
    if result.status != 0 or result.x is None:
        return 0.0, np.zeros(n)
    return float(result.x[-1]), np.asarray(result.x[:n])
