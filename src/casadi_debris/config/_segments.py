"""Manoeuvres of a closed-loop run: attitude targets and ``[[simulation.segments]]``.

A run's reference is a sequence of segments flown one after the other:

- ``slew``: rest-to-rest from the attitude the previous segment left to a target,
  by any slew method (bang-bang, time-optimal, fuel-optimal, optionally flexible
  with the OCP or the zero-vibration shaper); it lasts as long as the slew.
- ``hold``: keep the attitude the previous segment left.
- ``track``: follow the orbit's LVLH frame, or point a body axis at nadir.
- ``burn``: a track of the LVLH frame that holds ``body_axis`` (default the swarm's
  strongest torque-free thrust direction) along ``direction`` (prograde, retrograde,
  normal, antinormal) while the engines thrust along it: ``thrust_fraction`` (default 1)
  of the largest torque-free thrust, or ``thrust_mN``. The engines fire once the body
  turns with the frame (after ``blend_s``) until the segment ends (or starts to stop).

Targets (:class:`Target`), each written with one group of keys:

- ``axis`` + ``angle_deg``: a turn about a body axis (``"x"``, ``"-y"`` or any
  vector ``[a, b, c]``) from the attitude the segment starts at;
- ``quaternion = [w, x, y, z]``: the attitude q_BN (scalar first, unit norm to
  1e-3, then normalised);
- ``euler_deg = [a1, a2, a3]`` with ``euler_sequence`` (default ``"ZYX"``): the
  attitude as scipy's ``Rotation.from_euler(euler_sequence, euler_deg)``
  (upper case intrinsic, lower case extrinsic; angles in the sequence's order, so
  ``"ZYX"`` takes yaw, pitch, roll);
- ``frame = "lvlh"`` or ``"nadir"``: the frame's attitude (the end of a slew
  lands on it); ``lvlh`` takes the body's attitude relative to the frame from the
  keys above (default aligned: x along track, y against the orbit normal, z to
  nadir); ``nadir`` points ``nadir_axis`` (default ``"+z"``) at the Earth's centre
  with ``along_axis`` (default ``"+x"``, made perpendicular) towards the velocity.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from casadi_debris.config import limits
from casadi_debris.config._table import Table, frozen_array
from casadi_debris.errors import InputShapeError
from casadi_debris.units import MN_PER_N

SlewMethod = Literal["bang-bang", "time-optimal", "fuel-optimal"]
SLEW_METHODS: tuple[SlewMethod, ...] = ("bang-bang", "time-optimal", "fuel-optimal")
SegmentKind = Literal["slew", "hold", "track", "burn"]
TargetKind = Literal["rotation", "attitude", "frame"]
TrackFrame = Literal["lvlh", "nadir"]
SEGMENT_KINDS: tuple[SegmentKind, ...] = ("slew", "hold", "track", "burn")
BurnDirection = Literal["prograde", "retrograde", "normal", "antinormal"]
BURN_DIRECTIONS: tuple[BurnDirection, ...] = ("prograde", "retrograde", "normal", "antinormal")
"""Where a burn thrusts, in the orbit's LVLH frame: along track, against it, along the
orbit normal, against it."""
_BURN_KEYS = ("direction", "body_axis", "thrust_fraction", "thrust_mN")
TRACK_FRAMES: tuple[TrackFrame, ...] = ("lvlh", "nadir")
FLEXIBLE_METHODS = ("ocp", "shaper")
AXIS_TEXTS = ("x", "y", "z", "+x", "+y", "+z", "-x", "-y", "-z")
EULER_SEQUENCES = tuple(
    "".join(letters)
    for case in ("XYZ", "xyz")
    for letters in itertools.product(case, repeat=3)
    if letters[0] != letters[1] and letters[1] != letters[2]
)
"""The 24 sequences scipy's ``Rotation.from_euler`` takes (12 intrinsic, 12 extrinsic)."""
DEFAULT_EULER_SEQUENCE = "ZYX"
DEFAULT_BLEND_S = 1200.0
"""Seconds over which a reference moving at a different rate is joined (see
:mod:`casadi_debris.guidance`)."""
_TARGET_KEYS = ("axis", "angle_deg", "quaternion", "euler_deg", "euler_sequence")
_NADIR_KEYS = ("nadir_axis", "along_axis")
_SLEW_KEYS = (
    "method",
    "torque_fraction",
    "feedforward",
    "thrusters",
    "flexible",
    "flexible_method",
)


@dataclass(frozen=True, eq=False)
class Target:
    """Where a segment points.

    Attributes
    ----------
    kind : {"rotation", "attitude", "frame"}
        A turn from the start attitude (``axis``, ``angle_deg``); an attitude
        q_BN (``quaternion``); or the frame ``frame`` (``quaternion`` the body's
        attitude in it, q_OB, taking body components to frame components).
    axis : str or tuple of 3 floats, or None
        Body axis of a rotation: a name (``"x"``, ``"-z"``) or a vector (not
        necessarily unit).
    angle_deg : float or None
    quaternion : ndarray, shape (4,), or None
        Scalar first, unit norm.
    frame : {"lvlh", "nadir"} or None
    """

    kind: TargetKind
    axis: str | tuple[float, float, float] | None = None
    angle_deg: float | None = None
    quaternion: np.ndarray | None = None
    frame: TrackFrame | None = None


@dataclass(frozen=True, eq=False)
class SlewRequest:
    """What a slew does: its target, method, timing and authority (``[simulation.slew]``,
    a slew segment, or the ``slew`` job's options).

    Every slew is rest to rest (no start or end rate). How an optimal one is solved
    (grid, starts, checks) is a :class:`~casadi_debris.slews.OptimalSlewSettings`,
    derived from the request (:meth:`~casadi_debris.slews.OptimalSlewSettings.for_request`);
    the request resolved to quaternions for a start attitude is a
    :class:`~casadi_debris.slews.SlewTarget`.

    Attributes
    ----------
    target : Target
        A turn about a body axis (``axis``, ``angle_deg``), an attitude, or a frame.
    method : {"bang-bang", "time-optimal", "fuel-optimal"}
    start_s : float or None
        When it starts [s]; None: when the segment before ends (a segment's own rule).
    duration_s : float or None
        Its length [s]: a deadline for time-optimal, needed by fuel-optimal; None: the
        method picks it.
    torque_fraction : float or None
        Share of the authority to use, (0, 1]; None: the method's own.
    rate_limit_rad_s : float or None
        A bang-bang's largest rate [rad/s] (it coasts at it); None: no limit.
    feedforward : bool
        The profile's torque is added to the controller's demand (the paper's loop has
        none).
    thrusters : bool
        An optimal slew solved at thruster level, so that its torque is one the engines
        can give.
    zero_net_force : bool
        At thruster level, the engines' net force kept zero at every instant, as the
        closed loop's allocator keeps it (a problem file's ``thrusters`` sets both).
    flexible : bool
        An optimal slew keeps the array vibration left bounded ...
    flexible_method : {"ocp", "shaper"}
        ... by the OCP or by the zero-vibration shaper.
    """

    target: Target
    method: SlewMethod = "bang-bang"
    start_s: float | None = None
    duration_s: float | None = None
    torque_fraction: float | None = None
    rate_limit_rad_s: float | None = None
    feedforward: bool = False
    thrusters: bool = False
    zero_net_force: bool = False
    flexible: bool = False
    flexible_method: str = "ocp"

    @property
    def axis(self) -> str | tuple[float, float, float]:
        """The body axis of a turn (a name or a vector, normalised by the slew methods)."""
        if self.target.axis is None:
            raise InputShapeError(f"axis: {self._not_a_turn()}")
        return self.target.axis

    @property
    def angle_deg(self) -> float:
        """The angle of a turn [deg]."""
        if self.target.angle_deg is None:
            raise InputShapeError(f"angle_deg: {self._not_a_turn()}")
        return self.target.angle_deg

    def _not_a_turn(self) -> str:
        what = "an attitude" if self.target.kind == "attitude" else "a frame"
        return f"the slew's target is {what}, not a turn about a body axis"


def slew_about(
    axis: str | tuple[float, float, float], angle_deg: float, **fields: Any
) -> SlewRequest:
    """A request to turn ``angle_deg`` about a body ``axis``; ``fields`` are the rest of
    :class:`SlewRequest`'s (``method``, ``duration_s``, ...)."""
    return SlewRequest(Target("rotation", axis=axis, angle_deg=angle_deg), **fields)


@dataclass(frozen=True, eq=False)
class BurnRequest:
    """What a burn does (a burn segment, or the ``burn`` job's options), SI inside.

    The plan flown (the axis as a unit vector, the firing time) is derived from it:
    :func:`~casadi_debris.guidance.plan_burn`.

    Attributes
    ----------
    direction : {"prograde", "retrograde", "normal", "antinormal"}
        Where the thrust points, in the orbit's LVLH frame.
    body_axis : str or tuple of 3 floats, or None
        The thrust axis in body axes, a name (``"-y"``) or a vector (None: the swarm's
        strongest torque-free direction).
    thrust_fraction : float
        Of the largest torque-free thrust along the axis (ignored when ``thrust_N`` is
        given).
    thrust_N : float or None
        The thrust itself [N] (``thrust_mN`` in a problem file and on the command line).
    duration_s : float or None
        Engines on [s]; None: a segment's window sets it (after its blend).
    """

    direction: BurnDirection
    body_axis: str | tuple[float, float, float] | None = None
    thrust_fraction: float = 1.0
    thrust_N: float | None = None
    duration_s: float | None = None


@dataclass(frozen=True, eq=False)
class Segment:
    """One ``[[simulation.segments]]`` entry.

    Attributes
    ----------
    kind : {"slew", "hold", "track", "burn"}
    start_s : float or None
        When it starts [s]; None: when the previous one ends (a gap between
        segments holds the attitude the previous one left).
    duration_s : float or None
        A slew's own duration (None: its method picks it); a hold's or a
        track's length (None: to the end of the run, for the last one only).
    target : Target or None
        A slew's target, a track's frame; None for a hold.
    slew : SlewRequest or None
        Given for a slew (its ``target``, ``start_s`` and ``duration_s`` are the
        segment's: :meth:`of_slew`).
    blend_s : float
        A track: how long its start (and a segment after it) takes to join
        the new reference, rate and attitude [s].
    burn : BurnRequest or None
        Given for a burn (a track of the LVLH frame whose offset the burn sets).
    """

    kind: SegmentKind
    start_s: float | None
    duration_s: float | None
    target: Target | None = None
    slew: SlewRequest | None = None
    blend_s: float = DEFAULT_BLEND_S
    burn: BurnRequest | None = None

    @classmethod
    def of_slew(cls, request: SlewRequest) -> Segment:
        """The slew segment flying ``request`` (its start, duration and target)."""
        return cls("slew", request.start_s, request.duration_s, request.target, request)


def read_axis(t: Table, name: str) -> str | tuple[float, float, float]:
    """An axis: a name (``x``, ``-y``) or three numbers, not all zero."""
    if isinstance(t.data.get(name), str):
        return t.text(name, AXIS_TEXTS)
    vector = t.array(name, (3,), limits.AXIS_COMPONENT)
    if not np.any(vector):
        raise t.error(t.key(name), "must not be the zero vector")
    return (float(vector[0]), float(vector[1]), float(vector[2]))


def axis_unit_vector(axis: str | tuple[float, float, float]) -> np.ndarray:
    """Unit vector of an axis name or vector, shape (3,)."""
    if isinstance(axis, str):
        vector = np.zeros(3)
        vector["xyz".index(axis[-1])] = -1.0 if axis.startswith("-") else 1.0
        return vector
    vector = np.asarray(axis, dtype=float)
    return vector / np.linalg.norm(vector)


def _read_quaternion(t: Table) -> np.ndarray:
    q = np.array(t.array("quaternion", (4,), limits.QUATERNION_COMPONENT))
    norm = float(np.linalg.norm(q))
    if abs(norm - 1.0) > limits.QUATERNION_NORM_TOLERANCE:
        raise t.error(
            t.key("quaternion"),
            f"must have unit norm [w, x, y, z] (within {limits.QUATERNION_NORM_TOLERANCE:g}); "
            f"its norm is {norm:.6g}",
        )
    return frozen_array(q / norm)


def _read_euler(t: Table) -> np.ndarray:
    angles = t.array("euler_deg", (3,), limits.ANGLE_DEG)
    sequence = (
        t.text("euler_sequence", EULER_SEQUENCES)
        if t.has("euler_sequence")
        else DEFAULT_EULER_SEQUENCE
    )
    from scipy.spatial.transform import Rotation  # late: scipy.spatial costs `--help` 0.8 s

    xyzw = Rotation.from_euler(sequence, angles, degrees=True).as_quat()
    return frozen_array(xyzw[[3, 0, 1, 2]])


def _given(t: Table, names: tuple[str, ...]) -> list[str]:
    return [name for name in names if t.has(name)]


def read_orientation(t: Table, *, rotation: bool) -> Target | None:
    """The target an attitude's keys give, or None when none is given.

    With ``rotation``, ``axis`` + ``angle_deg`` is a turn from the start attitude;
    otherwise (a frame's offset) it is the attitude in the frame.
    """
    groups = {
        "axis": _given(t, ("axis", "angle_deg")),
        "quaternion": _given(t, ("quaternion",)),
        "euler_deg": _given(t, ("euler_deg", "euler_sequence")),
    }
    given = [name for name, keys in groups.items() if keys]
    if len(given) > 1:
        raise t.error(t.key(given[1]), f"give one target: {given[0]} or {given[1]}, not both")
    if not given:
        return None
    if given[0] == "quaternion":
        return Target("attitude", quaternion=_read_quaternion(t))
    if given[0] == "euler_deg":
        if not t.has("euler_deg"):
            raise t.error(t.key("euler_deg"), "missing: euler_sequence needs its angles")
        return Target("attitude", quaternion=_read_euler(t))
    axis = read_axis(t, "axis")
    angle_deg = t.number("angle_deg", limits.SLEW_ANGLE_DEG)
    if rotation:
        return Target("rotation", axis=axis, angle_deg=angle_deg)
    q = np.concatenate(
        [
            [np.cos(np.radians(angle_deg) / 2)],
            np.sin(np.radians(angle_deg) / 2) * axis_unit_vector(axis),
        ]
    )
    return Target("attitude", quaternion=frozen_array(q))


def _nadir_offset(t: Table) -> np.ndarray:
    """q_OB pointing ``nadir_axis`` at o3 (nadir) and ``along_axis`` towards o1."""
    nadir = axis_unit_vector(read_axis(t, "nadir_axis")) if t.has("nadir_axis") else np.eye(3)[2]
    along = axis_unit_vector(read_axis(t, "along_axis")) if t.has("along_axis") else np.eye(3)[0]
    along = along - (along @ nadir) * nadir
    if np.linalg.norm(along) < limits.AXIS_PARALLEL_TOLERANCE:
        raise t.error(t.key("along_axis"), "must not be parallel to nadir_axis")
    along /= np.linalg.norm(along)
    # Columns: the frame's axes o1, o2 = o3 x o1, o3 in body components (C_BO).
    c_bo = np.column_stack([along, np.cross(nadir, along), nadir])
    from scipy.spatial.transform import Rotation  # late: see _read_euler

    xyzw = Rotation.from_matrix(c_bo.T).as_quat()  # C_OB: body components to frame ones
    return frozen_array(xyzw[[3, 0, 1, 2]])


def read_frame_target(t: Table) -> Target:
    """``frame`` and its offset: the attitude keys for lvlh, the axes for nadir."""
    frame = t.text("frame", TRACK_FRAMES)
    if frame == "nadir":
        extra = _given(t, _TARGET_KEYS)
        if extra:
            raise t.error(
                t.key(extra[0]), 'only with frame = "lvlh" (nadir: nadir_axis, along_axis)'
            )
        return Target("frame", quaternion=_nadir_offset(t), frame=frame)
    extra = _given(t, _NADIR_KEYS)
    if extra:
        raise t.error(t.key(extra[0]), 'only with frame = "nadir"')
    offset = read_orientation(t, rotation=False)
    identity = frozen_array([1.0, 0.0, 0.0, 0.0])
    return Target(
        "frame", quaternion=identity if offset is None else offset.quaternion, frame=frame
    )


def read_slew_request(
    t: Table,
    methods: tuple[SlewMethod, ...],
    target: Callable[[], Target],
    timing: Callable[[], tuple[float | None, float | None]],
) -> SlewRequest:
    """A slew with the method and options of its table (``[simulation.slew]`` or a slew
    segment); ``thrusters`` is thruster level at zero net force, as the closed loop's
    allocator keeps it.

    ``target`` and ``timing`` (start and duration [s]) are read after the options, so
    that a table with several mistakes names the same one first whatever reads it.
    """
    method: SlewMethod = t.text("method", methods) if t.has("method") else "bang-bang"
    torque_fraction = (
        t.number("torque_fraction", limits.positive(1.0)) if t.has("torque_fraction") else None
    )
    feedforward = t.boolean("feedforward") if t.has("feedforward") else False
    thrusters = t.boolean("thrusters") if t.has("thrusters") else False
    flexible = t.boolean("flexible") if t.has("flexible") else False
    flexible_method = (
        t.text("flexible_method", FLEXIBLE_METHODS) if t.has("flexible_method") else "ocp"
    )
    if method == "bang-bang":
        for name, given in (("thrusters", thrusters), ("flexible", flexible)):
            if given:
                raise t.error(
                    t.key(name), "only for time-optimal and fuel-optimal slews (not bang-bang)"
                )
    if t.has("flexible_method") and not flexible:
        raise t.error(t.key("flexible_method"), "only with flexible = true")
    goal = target()
    start_s, duration_s = timing()
    if method == "fuel-optimal" and duration_s is None:
        raise t.error(t.key("duration_s"), "missing: a fuel-optimal slew needs its duration")
    return SlewRequest(
        target=goal,
        method=method,
        start_s=start_s,
        duration_s=duration_s,
        torque_fraction=torque_fraction,
        feedforward=feedforward,
        thrusters=thrusters,
        zero_net_force=thrusters,
        flexible=flexible,
        flexible_method=flexible_method,
    )


def _read_slew_target(t: Table) -> Target:
    target = read_frame_target(t) if t.has("frame") else read_orientation(t, rotation=True)
    if target is None:
        raise t.error(
            t.key("axis"),
            "missing: a slew needs a target (axis and angle_deg, quaternion, euler_deg or frame)",
        )
    return target


def _read_segment(t: Table, methods: tuple[SlewMethod, ...], run_s: float) -> Segment:
    kind = t.text("kind", SEGMENT_KINDS)
    start_s = t.number("start_s", limits.nonnegative(run_s)) if t.has("start_s") else None
    duration_s = t.number("duration_s", limits.SLEW_DURATION_S) if t.has("duration_s") else None
    target: Target | None = None
    slew: SlewRequest | None = None
    burn: BurnRequest | None = None
    blend_s = DEFAULT_BLEND_S
    if kind == "slew":
        slew = read_slew_request(
            t, methods, lambda: _read_slew_target(t), lambda: (start_s, duration_s)
        )
        target = slew.target
    elif kind == "track":
        target = read_frame_target(t)
    elif kind == "burn":
        burn = _read_burn(t)
    if kind in ("track", "burn") and t.has("blend_s"):
        blend_s = t.number("blend_s", limits.BLEND_S)
    if kind != "burn":
        extra = _given(t, _BURN_KEYS)
        if extra:
            raise t.error(t.key(extra[0]), "only for a burn segment")
    if kind != "slew":
        extra = _given(t, _SLEW_KEYS)
        if extra:
            raise t.error(t.key(extra[0]), "only for a slew segment")
    if kind in ("hold", "burn"):
        extra = _given(t, (*_TARGET_KEYS, *_NADIR_KEYS, "frame"))
        why = {
            "hold": "a hold keeps the attitude it starts at: no target",
            "burn": "a burn points body_axis along direction: no other target",
        }
        if extra:
            raise t.error(t.key(extra[0]), why[kind])
    t.done()
    return Segment(kind, start_s, duration_s, target, slew, blend_s, burn)


def _read_burn(t: Table) -> BurnRequest:
    """A burn's keys: ``direction`` (required), ``body_axis``, ``thrust_fraction`` or
    ``thrust_mN``."""
    if not t.has("direction"):
        raise t.error(t.key("direction"), f"missing: a burn needs one of {BURN_DIRECTIONS}")
    if t.has("thrust_fraction") and t.has("thrust_mN"):
        raise t.error(t.key("thrust_mN"), "give thrust_fraction or thrust_mN, not both")
    direction: BurnDirection = t.text("direction", BURN_DIRECTIONS)
    return BurnRequest(
        direction=direction,
        body_axis=read_axis(t, "body_axis") if t.has("body_axis") else None,
        thrust_fraction=(
            t.number("thrust_fraction", limits.positive(1.0)) if t.has("thrust_fraction") else 1.0
        ),
        thrust_N=(
            t.number("thrust_mN", limits.THRUST_MN) / MN_PER_N if t.has("thrust_mN") else None
        ),
    )


def read_segments(
    parent: Table, methods: tuple[SlewMethod, ...], run_s: float
) -> tuple[Segment, ...]:
    """``[[simulation.segments]]``: in time order, none overlapping, all within the run.

    A slew's end is known only once its method has solved it; the order and the
    starts given are checked here, the rest when the reference is generated.
    """
    tables = parent.tables("segments", limits.MAX_SEGMENTS)
    segments = tuple(_read_segment(t, methods, run_s) for t in tables)
    earliest = 0.0
    for index, (t, segment) in enumerate(zip(tables, segments, strict=True)):
        if segment.start_s is not None:
            if segment.start_s < earliest:
                raise t.error(
                    t.key("start_s"),
                    f"overlaps the segment before, which runs to {earliest:g} s at least",
                )
            earliest = segment.start_s
        if segment.kind != "slew" and segment.duration_s is None and index < len(segments) - 1:
            raise t.error(
                t.key("duration_s"),
                "missing: only the last segment may run to the end of the run",
            )
        earliest += segment.duration_s or 0.0
        if earliest > run_s:
            raise t.error(
                t.key("duration_s" if segment.duration_s else "start_s"),
                f"the segments run to {earliest:g} s, past the run's {run_s:g} s",
            )
    return segments
