"""Candidate mounts for a placement study: a grid of docking points on every hub face.

Each face carries an ``n1 x n2`` grid of mounts along its two in-face axes (in
x, y, z order), spread evenly from edge to edge of the face inset by the
problem's edge margin (a fraction of the half edge, as the paper's corner
layout reads it). The grid's extreme points are the paper's four corner mounts,
so every grid of at least 2 x 2 holds the paper's 24 mounts; 2 x 2 is exactly
the paper's set. Mounts are numbered face by face in the order +x, -x, +y, -y,
+z, -z, and within a face from the + corner down, so that the 2 x 2 grid
numbers its mounts as the paper numbers its CubeSats.

A mount can carry one of several *engine templates* (the main engine along the
inward normal, with 0, 2 or 4 side-panel engines): each (mount, template) pair
is one candidate CubeSat, and a mount takes at most one of its candidates.

The CubeSat itself (mass, inertia in its own axes, standoff above the face)
is the problem's ``[cubesat_layout]``; for a problem with an explicit
``[[cubesats]]`` list it is CubeSat 1 (mass; its principal moments, largest
first, as its own x, y, z), with a 10 % edge margin and no standoff.
"""

from __future__ import annotations

import dataclasses
import re
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import (
    SIGNED_AXES,
    CubeSat,
    Problem,
    cubesat_inertia_on_face,
    face_axes,
    face_engines,
    signed_axis_vector,
)
from casadi_debris.errors import InputShapeError

DEFAULT_GRID = (4, 4)
"""Mounts per face along its two in-face axes: 96 in all, the paper's 24 among them."""
MAX_GRID = 12
"""Mounts along one in-face axis at most (144 per face)."""
DEFAULT_EDGE_MARGIN = 0.1
MATCH_TOLERANCE_M = 1e-9
_GRID = re.compile(r"^\s*(\d+)\s*(?:[xX]\s*(\d+)\s*)?$")


@dataclass(frozen=True, eq=False)
class CubeSatTemplate:
    """The CubeSat every candidate is a copy of, apart from its place and engines.

    Attributes
    ----------
    mass_kg : float
    moments_kgm2 : ndarray, shape (3,)
        Principal inertia about its CoG in its own axes (x along the face normal).
    standoff_m : float
        CoG height above the face.
    edge_margin_fraction : float
        Inset of the mount grid from each face edge, fraction of the half edge.
    main_engine : bool
    """

    mass_kg: float
    moments_kgm2: np.ndarray
    standoff_m: float
    edge_margin_fraction: float
    main_engine: bool


@dataclass(frozen=True, eq=False)
class Candidate:
    """One candidate CubeSat: a mount and an engine template.

    Attributes
    ----------
    index : int
        0-based among the candidates (``index + 1`` to a user).
    mount : int
        0-based mount (docking point); candidates of one mount exclude each other.
    face : str
        Signed axis of the face.
    side_engines : int
        Side-panel engines of its template (0, 2 or 4).
    cubesat : CubeSat
        The CubeSat as a problem file would give it (hub-corner frame).
    """

    index: int
    mount: int
    face: str
    side_engines: int
    cubesat: CubeSat

    @property
    def template(self) -> str:
        """Name of the engine template: ``main``, ``main+2side``, ``2side`` ..."""
        parts = (["main"] if self.cubesat.engines and _has_main(self) else []) + (
            [f"{self.side_engines}side"] if self.side_engines else []
        )
        return "+".join(parts)


def _has_main(candidate: Candidate) -> bool:
    inward = -signed_axis_vector(candidate.face)
    return any(np.allclose(e.direction, inward) for e in candidate.cubesat.engines)


@dataclass(frozen=True, eq=False)
class CandidateSet:
    """The candidates of a placement study.

    Attributes
    ----------
    grid : tuple of int
        Mounts per face along its two in-face axes.
    side_engine_options : tuple of int
        The engine templates offered at every mount (side-panel engine counts).
    template : CubeSatTemplate
    candidates : tuple of Candidate
        Mount by mount, each mount's templates in the order given.
    """

    grid: tuple[int, int]
    side_engine_options: tuple[int, ...]
    template: CubeSatTemplate
    candidates: tuple[Candidate, ...]

    @property
    def n_mounts(self) -> int:
        return 1 + max(c.mount for c in self.candidates)

    def cubesats(self, chosen: tuple[int, ...] | list[int]) -> tuple[CubeSat, ...]:
        """The CubeSats of the chosen candidates (0-based), in that order."""
        return tuple(self.candidates[i].cubesat for i in chosen)

    def match(self, cubesats: tuple[CubeSat, ...]) -> tuple[int, ...] | None:
        """The candidates that are exactly these CubeSats (place, face, engines), or None."""
        found = []
        for cubesat in cubesats:
            hits = [c.index for c in self.candidates if _same_cubesat(c.cubesat, cubesat)]
            if not hits:
                return None
            found.append(hits[0])
        return tuple(found) if len(set(found)) == len(found) else None


def _same_cubesat(a: CubeSat, b: CubeSat) -> bool:
    if a.face != b.face or len(a.engines) != len(b.engines) or a.mass_kg != b.mass_kg:
        return False
    if not np.allclose(a.position_corner_m, b.position_corner_m, rtol=0, atol=MATCH_TOLERANCE_M):
        return False
    if not np.allclose(a.inertia_kgm2, b.inertia_kgm2, rtol=1e-12, atol=0):
        return False
    return all(
        np.allclose(x.direction, y.direction) and np.allclose(x.offset_m, y.offset_m)
        for x, y in zip(a.engines, b.engines, strict=True)
    ) and all(
        dataclasses.astuple(x)[2:] == dataclasses.astuple(y)[2:]
        for x, y in zip(a.engines, b.engines, strict=True)
    )


def parse_grid(text: str, option: str = "--candidates") -> tuple[int, int]:
    """``"4x4"`` or ``"4"`` (square) as mounts per face along its two in-face axes.

    Raises
    ------
    InputShapeError
        Naming ``option`` for anything else, or counts outside 1 .. MAX_GRID.
    """
    match = _GRID.match(text)
    if match is None:
        raise InputShapeError(f"{option}: a per-face grid such as 4x4 or 3; got {text!r}")
    first = int(match[1])
    second = int(match[2]) if match[2] is not None else first
    if not (1 <= first <= MAX_GRID and 1 <= second <= MAX_GRID):
        raise InputShapeError(
            f"{option}: 1 to {MAX_GRID} mounts along each face axis; got {text!r}"
        )
    return first, second


def cubesat_template(problem: Problem) -> CubeSatTemplate:
    """The CubeSat of the problem's layout, or CubeSat 1 of its explicit list (see module)."""
    layout = problem.cubesat_layout
    if layout is not None:
        return CubeSatTemplate(
            mass_kg=layout.mass_kg,
            moments_kgm2=np.asarray(layout.inertia_kgm2, dtype=float),
            standoff_m=layout.standoff_m,
            edge_margin_fraction=layout.edge_margin_fraction,
            main_engine=layout.main_engine,
        )
    first = problem.cubesats[0]
    return CubeSatTemplate(
        mass_kg=first.mass_kg,
        moments_kgm2=np.sort(np.linalg.eigvalsh(first.inertia_kgm2))[::-1],
        standoff_m=0.0,
        edge_margin_fraction=DEFAULT_EDGE_MARGIN,
        main_engine=True,
    )


def _axis_values(count: int, half: float, margin: float) -> np.ndarray:
    """Mount offsets along one in-face axis, + edge first."""
    if count == 1:
        return np.zeros(1)
    return (1.0 - margin) * half * np.linspace(1.0, -1.0, count)


def face_candidates(
    problem: Problem,
    grid: tuple[int, int] = DEFAULT_GRID,
    side_engine_options: tuple[int, ...] | None = None,
    template: CubeSatTemplate | None = None,
) -> CandidateSet:
    """Candidate CubeSats on an ``n1 x n2`` grid of mounts on every hub face.

    Parameters
    ----------
    problem : Problem
        Its hub, ``[engine]`` and CubeSat (see the module).
    grid : tuple of int
        Mounts along the face's two in-face axes (x, y, z order).
    side_engine_options : tuple of int, optional
        Engine templates offered at each mount as side-panel engine counts
        (0, 2, 4); default the problem layout's own (0 for the paper).
    template : CubeSatTemplate, optional
        Default :func:`cubesat_template` of the problem.

    Returns
    -------
    CandidateSet
    """
    template = template or cubesat_template(problem)
    if side_engine_options is None:
        layout = problem.cubesat_layout
        side_engine_options = (layout.side_engines if layout is not None else 0,)
    bad = [s for s in side_engine_options if s not in (0, 2, 4)]
    if bad or not side_engine_options or len(set(side_engine_options)) != len(side_engine_options):
        raise InputShapeError(
            f"--side-engines: distinct counts among 0, 2, 4; got {list(side_engine_options)}"
        )
    if not template.main_engine and 0 in side_engine_options:
        raise InputShapeError("--side-engines: a CubeSat without a main engine needs 2 or 4")
    size = np.asarray(problem.hub.size_m, dtype=float)
    centre = size / 2.0
    candidates: list[Candidate] = []
    mount = 0
    for face in SIGNED_AXES:
        normal_axis, first, second = face_axes(face)
        low, high = sorted((first, second))
        lift = signed_axis_vector(face) * (centre[normal_axis] + template.standoff_m)
        inertia = cubesat_inertia_on_face(template.moments_kgm2, face)
        margin = template.edge_margin_fraction
        for u in _axis_values(grid[0], centre[low], margin):
            for v in _axis_values(grid[1], centre[high], margin):
                position = centre + lift
                position[low] += u
                position[high] += v
                for side in side_engine_options:
                    cubesat = CubeSat(
                        position_corner_m=position,
                        mass_kg=template.mass_kg,
                        inertia_kgm2=inertia,
                        face=face,
                        engines=face_engines(face, template.main_engine, side, problem.engine),
                    )
                    candidates.append(Candidate(len(candidates), mount, face, side, cubesat))
                mount += 1
    return CandidateSet(grid, tuple(side_engine_options), template, tuple(candidates))
