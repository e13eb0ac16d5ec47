"""CubeSat layout generators: ``[cubesat_layout]`` expanded to the explicit CubeSat list.

Positions are in the hub-corner frame. A CubeSat on face ``f`` (a signed axis,
the face's outward normal n) has its CoG ``standoff_m`` above the face and
fires its main engine along -n (into the hub); side-panel engines push along
the face's plane.

``face_corners`` (the paper, Section II.D): four per face, one near each
corner (numbered per face: +,+ then +,- then -,+ then -,- along the face's two
axes in x, y, z order), inset from both edges by ``edge_margin_fraction`` of the half edge
length. Reading the 10 % margin as a fraction of the half edge (not of the whole
edge) is what reproduces the paper's torque authority (4.61, 1.96, 4.26 mNm);
with the whole edge it would be 11 % lower.

``face_grid``: ``per_face`` CubeSats at the centres of an r x c grid of equal
cells covering the inset face, r x c = per_face with r <= c as close as
possible, the c columns along the longer face edge.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from casadi_debris.config._schema import (
    AXIS_NAMES,
    CubeSat,
    CubeSatLayout,
    Engine,
    EngineDefaults,
    SignedAxis,
)


def signed_axis_vector(name: str) -> np.ndarray:
    """Unit vector of a signed axis name such as ``"-z"``, shape (3,)."""
    vector = np.zeros(3)
    vector[AXIS_NAMES.index(name[1])] = 1.0 if name[0] == "+" else -1.0
    return vector


def face_axes(face: str) -> tuple[int, int, int]:
    """The face's normal axis and its two in-face axes, in cyclic order after the normal."""
    axis = AXIS_NAMES.index(face[1])
    return axis, (axis + 1) % 3, (axis + 2) % 3


def grid_shape(count: int) -> tuple[int, int]:
    """Rows r and columns c with r x c = count, r <= c, as square as possible."""
    rows = max(r for r in range(1, math.isqrt(count) + 1) if count % r == 0)
    return rows, count // rows


def _in_face_offsets(layout: CubeSatLayout, half: np.ndarray, face: str) -> list[np.ndarray]:
    """Offsets of the CubeSats from the face centre along the two in-face axes."""
    _, first, second = face_axes(face)
    usable = (1.0 - layout.edge_margin_fraction) * half
    if layout.kind == "face_corners":
        # In-face axes in index order (not cyclic): the paper's CubeSat numbering.
        low, high = sorted((first, second))
        return [
            _offset(low, s1 * usable[low], high, s2 * usable[high])
            for s1 in (+1.0, -1.0)
            for s2 in (+1.0, -1.0)
        ]
    rows, columns = grid_shape(layout.per_face)
    long_axis, short_axis = (first, second) if half[first] >= half[second] else (second, first)
    return [
        _offset(
            long_axis,
            usable[long_axis] * (-1.0 + (2 * j + 1) / columns),
            short_axis,
            usable[short_axis] * (-1.0 + (2 * i + 1) / rows),
        )
        for i in range(rows)
        for j in range(columns)
    ]


def _offset(axis_a: int, value_a: float, axis_b: int, value_b: float) -> np.ndarray:
    offset = np.zeros(3)
    offset[axis_a], offset[axis_b] = value_a, value_b
    return offset


def cubesat_inertia_on_face(moments: np.ndarray, face: str) -> np.ndarray:
    """A CubeSat's inertia in hub axes: its x (thrust) axis along the face normal, long z next.

    CubeSat axes x, y, z (long) map to hub axes: the normal, the one after the
    long one, and the one after the normal.
    """
    normal, after_normal, last = face_axes(face)
    inertia = np.zeros((3, 3))
    for own, hub_axis in ((0, normal), (2, after_normal), (1, last)):
        inertia[hub_axis, hub_axis] = moments[own]
    return inertia


def _engines(layout: CubeSatLayout, face: str, defaults: EngineDefaults) -> tuple[Engine, ...]:
    return face_engines(face, layout.main_engine, layout.side_engines, defaults)


def face_engines(
    face: str, main_engine: bool, side_engines: int, defaults: EngineDefaults
) -> tuple[Engine, ...]:
    """The engines of a CubeSat docked on ``face``, at its CoG.

    Parameters
    ----------
    face : str
        Signed axis of the face (its outward normal).
    main_engine : bool
        One engine pushing along the face's inward normal.
    side_engines : {0, 2, 4}
        Side-panel engines pushing both ways along the first in-face axis after
        the normal in cyclic order (2), or along both in-face axes (4).
    defaults : EngineDefaults
        Their stages, thrust, Isp and life.
    """
    _, first, second = face_axes(face)
    directions = [-signed_axis_vector(face)] if main_engine else []
    side_axes = {0: (), 2: (first,), 4: (first, second)}[side_engines]
    for axis in side_axes:
        for sign in (+1.0, -1.0):
            direction = np.zeros(3)
            direction[axis] = sign
            directions.append(direction)
    stage_values = dataclasses.asdict(defaults)
    return tuple(
        Engine(direction=direction, offset_m=np.zeros(3), **stage_values)
        for direction in directions
    )


def expand_layout(
    layout: CubeSatLayout, hub_size_m: np.ndarray, defaults: EngineDefaults
) -> tuple[CubeSat, ...]:
    """The CubeSats a layout places on a hub of the given size, face by face.

    Parameters
    ----------
    layout : CubeSatLayout
    hub_size_m : ndarray, shape (3,)
        Hub edge lengths; the hub spans [0, size] per axis in the corner frame.
    defaults : EngineDefaults
        The engines' stages, thrust, Isp and life.

    Returns
    -------
    tuple of CubeSat
        Positions in the hub-corner frame.
    """
    centre = np.asarray(hub_size_m, dtype=float) / 2.0
    cubesats = []
    face: SignedAxis
    for face in layout.faces:
        normal = signed_axis_vector(face)
        axis = AXIS_NAMES.index(face[1])
        lift = normal * (centre[axis] + layout.standoff_m)
        for offset in _in_face_offsets(layout, centre, face):
            cubesats.append(
                CubeSat(
                    position_corner_m=centre + lift + offset,
                    mass_kg=layout.mass_kg,
                    inertia_kgm2=cubesat_inertia_on_face(layout.inertia_kgm2, face),
                    face=face,
                    engines=_engines(layout, face, defaults),
                )
            )
    return tuple(cubesats)
