"""The set of torques the engines can make, as facets: ``{tau : N tau <= b}``.

With unidirectional engines the reachable torques at zero net force,

    T = { B f : 0 <= f <= f_max, F f = 0 },

form a polytope (the image of a polytope under a linear map). Its facets are
found exactly by the outer/inner scheme of support functions: start from
the hull of the vertices found in the six axis directions, then, for every
facet of the current hull, ask a linear program for the support point in
the facet's normal direction; a point beyond the facet is a new vertex.
When no facet moves the hull is the polytope itself (each LP returns a
vertex of T, and a facet whose normal's support equals its offset is a
facet of T).

The facets give the direction-keeping saturation in closed form: the
largest ``alpha`` in [0, 1] with ``alpha tau`` in T is

    alpha = min(1, min_{i : n_i . tau > 0} b_i / (n_i . tau)),

cheap enough to sit in every step of a simulation.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog
from scipy.spatial import ConvexHull

from casadi_debris.errors import AllocationError

# Relative tolerance (of the largest support value) for a point to count as
# beyond a facet, and for merging coplanar facets of the triangulated hull.
SUPPORT_RTOL = 1e-9
MERGE_DECIMALS = 9
MAX_ROUNDS = 50


@dataclass(frozen=True)
class AuthorityPolytope:
    """Reachable torques ``{tau : normals @ tau <= offsets}`` [N m].

    Attributes
    ----------
    normals : ndarray, shape (m, 3)
        Unit outward facet normals.
    offsets : ndarray, shape (m,)
        Support value of each facet [N m]; positive when every direction can be
        torqued, zero for a facet through the origin.
    vertices : ndarray, shape (k, 3)
        Extreme torques [N m].
    """

    normals: np.ndarray
    offsets: np.ndarray
    vertices: np.ndarray

    def axis_reach(self) -> np.ndarray:
        """Largest pure torque about +x, -x, +y, -y, +z, -z (magnitudes), shape (6,) [N m].

        Along a unit direction d the polytope reaches ``min_{n_i . d > 0} b_i / (n_i . d)``.
        """
        directions = np.repeat(np.eye(3), 2, axis=0) * np.tile([1.0, -1.0], 3)[:, None]
        reach = directions @ self.normals.T
        with np.errstate(divide="ignore", invalid="ignore"):
            ratios = np.where(reach > SUPPORT_RTOL, self.offsets / reach, np.inf)
        return ratios.min(axis=1)

    def scale(self, torque_Nm: np.ndarray) -> np.ndarray:
        """Largest alpha in [0, 1] with ``alpha * tau`` reachable, for each row.

        Parameters
        ----------
        torque_Nm : array_like, shape (3,) or (k, 3)

        Returns
        -------
        ndarray, shape () or (k,)
        """
        torque = np.asarray(torque_Nm, dtype=float)
        reach = torque @ self.normals.T
        with np.errstate(divide="ignore", invalid="ignore"):
            ratios = np.where(reach > 0, self.offsets / reach, np.inf)
        return np.minimum(1.0, ratios.min(axis=-1))


def _support(
    direction: np.ndarray,
    torque_map: np.ndarray,
    equality: np.ndarray,
    upper: np.ndarray,
    force: np.ndarray | None = None,
) -> np.ndarray:
    """Torque of the engines' point that maximises ``direction . tau`` (net force ``force``,
    default zero, when ``equality`` holds the force rows)."""
    rhs = np.zeros(len(equality)) if force is None else force
    result = linprog(
        -(direction @ torque_map),
        A_eq=equality if len(equality) else None,
        b_eq=rhs if len(equality) else None,
        bounds=list(zip(np.zeros_like(upper), upper, strict=True)),
        method="highs",
    )
    if result.status != 0 or result.x is None:
        raise AllocationError(f"authority polytope: support LP failed ({result.message})")
    return torque_map @ result.x


def authority_polytope(
    torque_map: np.ndarray,
    force_map: np.ndarray,
    max_thrust_N: np.ndarray,
    *,
    free_force: bool = False,
    force_N: np.ndarray | None = None,
) -> AuthorityPolytope:
    """Facets of the torque polytope of unidirectional engines.

    With ``force_N`` it is the slice of the wrench polytope at that net force,
    ``{B f : 0 <= f <= f_max, F f = force_N}``: the torques the engines can add
    while they deliver the force exactly (a burn's).

    Parameters
    ----------
    torque_map, force_map : ndarray, shape (3, n)
        Torque [N m / N] and force [N / N] per unit thrust of each engine.
    max_thrust_N : ndarray, shape (n,)
        Thrust limit of every engine [N] (0 for a failed engine).
    free_force : bool
        Drop the zero-net-force condition.
    force_N : ndarray, shape (3,), optional
        Net force held [N] instead of zero (not with ``free_force``).

    Returns
    -------
    AuthorityPolytope
        The same object for the same maps and limits (the process keeps the
        last :data:`KNOWN_POLYTOPES`: a campaign's runs meet the same engines
        again and again, and each costs about a hundred LPs).

    Raises
    ------
    AllocationError
        The reachable torques do not span three dimensions (too many engines
        lost for any torque in some plane), or an LP failed.

    Example
    -------
    >>> from casadi_debris import load_problem
    >>> from casadi_debris.geometry import build_geometry, max_thrust_N
    >>> g = build_geometry(load_problem())
    >>> limits = max_thrust_N(g)
    >>> polytope = authority_polytope(g.torque_map, g.force_map, limits)
    >>> round(float(polytope.scale([1.0, 0.0, 0.0])) * 1e3, 3)  # mNm about +x
    4.608
    """
    torque_map = np.asarray(torque_map, dtype=float)
    upper = np.asarray(max_thrust_N, dtype=float)
    equality = np.zeros((0, len(upper))) if free_force else np.asarray(force_map, dtype=float)
    force = None
    if force_N is not None:
        if free_force:
            raise AllocationError("give either force_N or free_force, not both")
        force = np.asarray(force_N, dtype=float).reshape(3)
    key = _key(torque_map, equality, upper, *([] if force is None else [force]))
    known = _KNOWN.get(key)
    if known is None:
        known = _KNOWN[key] = _polytope(torque_map, equality, upper, force)
        for array in (known.normals, known.offsets, known.vertices):
            array.flags.writeable = False  # shared by every caller from now on
        if len(_KNOWN) > KNOWN_POLYTOPES:
            _KNOWN.pop(next(iter(_KNOWN)))
    return known


# The polytopes this process found, by their engines (a campaign's runs share a few).
_KNOWN: dict[bytes, AuthorityPolytope] = {}
KNOWN_POLYTOPES = 1024


def _key(*arrays: np.ndarray) -> bytes:
    digest = hashlib.sha256()
    for array in arrays:
        digest.update(f"{array.shape}".encode())
        digest.update(np.ascontiguousarray(array).tobytes())
    return digest.digest()


def _flat_message(
    axes: np.ndarray, points: list[np.ndarray], tolerance: float, force: np.ndarray | None
) -> str:
    """Which signed body axes the engines cannot torque about, for a flat polytope."""
    names = ("+x", "+y", "+z", "-x", "-y", "-z")
    reach = [float(axis @ point) for axis, point in zip(axes, points, strict=True)]
    weak = [name for name, value in zip(names, reach, strict=True) if value <= tolerance]
    at = "zero net force" if force is None else "the demanded net force"
    about = ", ".join(weak) if weak else "one direction"
    return (
        f"the engines cannot torque about {about} at {at} (a flat authority polytope): give "
        "that axis engines with a lever arm about it (e.g. side engines or CubeSats on "
        "another face)"
    )


def _polytope(
    torque_map: np.ndarray, equality: np.ndarray, upper: np.ndarray, force: np.ndarray | None
) -> AuthorityPolytope:
    """The body of :func:`authority_polytope` (which keeps what it found)."""
    axes = np.vstack([np.eye(3), -np.eye(3)])
    points = [_support(d, torque_map, equality, upper, force) for d in axes]
    size = max(float(np.abs(points).max()), np.finfo(float).tiny)
    tolerance = SUPPORT_RTOL * size
    for _ in range(MAX_ROUNDS):
        try:
            hull = ConvexHull(np.array(points))
        except Exception as exc:  # scipy raises QhullError for flat point sets
            raise AllocationError(
                _flat_message(axes, points[: len(axes)], tolerance, force)
            ) from exc
        normals = hull.equations[:, :3]
        offsets = -hull.equations[:, 3]
        new_points = []
        for normal, offset in zip(*_unique_facets(normals, offsets), strict=True):
            point = _support(normal, torque_map, equality, upper, force)
            if normal @ point > offset + tolerance:
                new_points.append(point)
        if not new_points:
            unique_normals, unique_offsets = _unique_facets(normals, offsets)
            return AuthorityPolytope(
                normals=unique_normals,
                offsets=np.maximum(unique_offsets, 0.0),
                vertices=np.array(points)[hull.vertices],
            )
        points.extend(new_points)
    raise AllocationError(f"authority polytope did not converge in {MAX_ROUNDS} rounds")


def _unique_facets(normals: np.ndarray, offsets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Merge the triangles of one facet (same normal) into one row."""
    size = max(float(np.abs(offsets).max()), np.finfo(float).tiny)
    keys = np.round(np.column_stack([normals, offsets / size]), MERGE_DECIMALS)
    _, first = np.unique(keys, axis=0, return_index=True)
    first = np.sort(first)
    return normals[first], offsets[first]
