"""The numbers a placement study works on: engine maps of every candidate, the inertia
each adds, the bare debris' inertia and the disturbance.

Why the problem is linear in the choice
---------------------------------------
With zero net force the torque of a set of thrusts does not depend on the point
it is taken about (sum r x f - c x sum f = sum r x f), so the torque map may be
taken about a fixed point, the bare debris' CoG, whichever CubeSats are docked:
the combined CoG moves with the choice, the zero-net-force authority does not.

Inertia about the fixed point is the bare debris' plus one parallel-axis term
per docked CubeSat, linear in the choice. About the combined CoG it is that
minus ``M (|c|^2 I - c c^T)`` (``c`` the CoG shift, ``M`` the total mass), never
more: a limit on the linear sum is therefore conservative, and exact for a
layout that keeps the CoG where it was.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.errors import InputShapeError
from casadi_debris.geometry import array_rigid_inertia, point_mass_inertia
from casadi_debris.studies.placement._candidates import CandidateSet
from casadi_debris.units import N_PER_MN, NM_PER_MNM


@dataclass(frozen=True, eq=False)
class PlacementData:
    """Candidate engines and masses about the bare debris' CoG.

    Attributes
    ----------
    candidates : CandidateSet
    cog_bare_corner_m : ndarray, shape (3,)
        CoG of the hub and arrays, hub-corner frame.
    inertia_bare_kgm2 : ndarray, shape (3, 3)
        Hub and rigid arrays about that CoG.
    engine_candidate : ndarray of int, shape (n_engines,)
        Candidate (0-based) of each engine.
    torque_map : ndarray, shape (3, n_engines)
        Torque about the bare CoG per newton [N m / N].
    force_map : ndarray, shape (3, n_engines)
    max_thrust_N : ndarray, shape (n_engines,)
        One stage's thrust.
    added_inertia_kgm2 : ndarray, shape (n_candidates, 3)
        Diagonal of each candidate's own inertia plus its parallel-axis term
        about the bare CoG.
    candidate_mount : ndarray of int, shape (n_candidates,)
    disturbance_Nm : ndarray, shape (3,)
        Disturbance amplitude about x, y, z.
    """

    candidates: CandidateSet
    cog_bare_corner_m: np.ndarray
    inertia_bare_kgm2: np.ndarray
    engine_candidate: np.ndarray
    torque_map: np.ndarray
    force_map: np.ndarray
    max_thrust_N: np.ndarray
    added_inertia_kgm2: np.ndarray
    candidate_mount: np.ndarray
    disturbance_Nm: np.ndarray

    @property
    def n_candidates(self) -> int:
        return len(self.candidates.candidates)

    @property
    def n_engines(self) -> int:
        return len(self.max_thrust_N)

    def engines_of(self, chosen: np.ndarray | list[int] | tuple[int, ...]) -> np.ndarray:
        """Engine indices (0-based) of the chosen candidates."""
        return np.flatnonzero(np.isin(self.engine_candidate, np.asarray(chosen, dtype=int)))


def bare_debris(problem: Problem) -> tuple[np.ndarray, np.ndarray]:
    """CoG (hub-corner frame) and rigid inertia about it of the hub and arrays alone."""
    hub, arrays = problem.hub, problem.arrays
    masses = [hub.mass_kg] + [a.mass_kg for a in arrays]
    points = [hub.cog_corner_m] + [
        a.hinge_corner_m + 0.5 * a.length_m * a.direction for a in arrays
    ]
    cog = np.sum([m * np.asarray(p) for m, p in zip(masses, points, strict=True)], axis=0) / sum(
        masses
    )
    inertia = hub.inertia_kgm2 + point_mass_inertia(hub.mass_kg, hub.cog_corner_m - cog)
    for array in arrays:
        hinge = array.hinge_corner_m - cog
        inertia = inertia + np.array(
            array_rigid_inertia(array, hinge, math.radians(array.angle_deg))
        )
    return cog, inertia


def placement_data(problem: Problem, candidates: CandidateSet) -> PlacementData:
    """Engine maps and added inertia of every candidate (see the module).

    Raises
    ------
    InputShapeError
        When the disturbance amplitude is zero about an axis (the ratio to it is the
        objective).
    """
    amplitude = np.abs(np.asarray(problem.disturbance.amplitude_mNm, dtype=float))
    if np.any(amplitude <= 0.0):
        raise InputShapeError(
            "disturbance.amplitude_mNm: placement maximises authority over the disturbance "
            f"per axis and needs every amplitude > 0; got {amplitude.tolist()}"
        )
    cog, inertia_bare = bare_debris(problem)
    owners, positions, directions, thrusts = [], [], [], []
    added = []
    for candidate in candidates.candidates:
        cubesat = candidate.cubesat
        offset = cubesat.position_corner_m - cog
        added.append(np.diag(cubesat.inertia_kgm2 + point_mass_inertia(cubesat.mass_kg, offset)))
        for engine in cubesat.engines:
            owners.append(candidate.index)
            positions.append(offset + engine.offset_m)
            directions.append(engine.direction)
            thrusts.append(engine.thrust_per_stage_mN * N_PER_MN)
    force_map = np.array(directions, dtype=float).T
    torque_map = np.cross(np.array(positions, dtype=float), force_map.T).T
    return PlacementData(
        candidates=candidates,
        cog_bare_corner_m=cog,
        inertia_bare_kgm2=inertia_bare,
        engine_candidate=np.array(owners, dtype=int),
        torque_map=torque_map,
        force_map=force_map,
        max_thrust_N=np.array(thrusts, dtype=float),
        added_inertia_kgm2=np.array(added, dtype=float),
        candidate_mount=np.array([c.mount for c in candidates.candidates], dtype=int),
        disturbance_Nm=amplitude * NM_PER_MNM,
    )
