"""The reference of a manoeuvre: slews, holds and tracks flown one after the other.

A run starts at rest at q_BN = [1, 0, 0, 0]. Each segment
(:class:`~casadi_debris.config.Segment`) starts from the attitude the one before
left at its start time:

- a slew is solved from there to its target by its method
  (:func:`~casadi_debris.guidance._slew.solve_slew`), a target in the
  LVLH frame being the frame's attitude at the slew's end (found by fixed-point
  iteration on the slew's duration when the method picks it);
- a hold keeps that attitude;
- a track follows its frame (:mod:`casadi_debris.guidance._targets`); a burn is a
  track of the LVLH frame holding its thrust axis along its direction, whose engines
  fire from ``blend_s`` on (:mod:`casadi_debris.guidance._burn_plan`).

Slews and holds start and end at rest, so where they meet the reference is
continuous in attitude and rate as it stands. A track moves at the orbit rate:
the first ``blend_s`` of a track, and of the segment after one, join the old
reference to the new one with :func:`~casadi_debris.guidance._targets.blend`
(attitude and rate continuous; the join is at most the segment long). A gap
between segments holds the attitude the segment before left.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from casadi_debris.allocation import Allocator
from casadi_debris.config import (
    Problem,
    Segment,
    Simulation,
    SlewRequest,
    Target,
)
from casadi_debris.environment import CircularOrbit
from casadi_debris.errors import InputShapeError, ProblemFileError
from casadi_debris.guidance._burn_plan import (
    BurnPlan,
    attitude_limits,
    burn_offset,
    burn_thrust_N,
    plan_burn,
)
from casadi_debris.guidance._slew import slew_quaternions, solve_slew
from casadi_debris.guidance._targets import body_rates, frame_attitude, track_attitudes
from casadi_debris.records import Record
from casadi_debris.slews import LimitCheck, SlewProfile, SlewTarget, slew_about_axis, slew_between

IDENTITY = np.array([1.0, 0.0, 0.0, 0.0])
TRACKS = ("track", "burn")
"""Segments that turn with the LVLH frame (a burn is a track that also thrusts)."""
FRAME_ITERATIONS = 12
"""Largest number of secant steps putting a slew's end onto a moving frame."""
FRAME_DURATION_TOLERANCE_S = 1e-3
"""A slew ends within 1 ms of where it aims on the frame (n x 1 ms: 0.2 arcsec at orbit rates)."""

Attitudes = Callable[[np.ndarray], np.ndarray]
"""Times [s], shape (n,) -> quaternions q_BN, shape (n, 4)."""


@dataclass(frozen=True, eq=False)
class Piece:
    """One stretch of the reference.

    Attributes
    ----------
    kind : {"slew", "hold", "track", "burn"}
    start_s, end_s : float
        Its window [s] (``end_s`` the run's end for the last).
    attitude : callable
        q_BN at any times (a slew held at its ends, a track continued).
    index : int or None
        Its ``[[simulation.segments]]`` entry (0-based), None for a gap's hold.
    slew : SlewProfile or None
    feedforward : bool
        The slew's torque is added to the controller's demand.
    blend_s : float
        Joined to the piece before over its first ``blend_s`` (0: as it stands).
    burn : BurnPlan or None
        A burn's plan (its ``duration_s`` the firing's).
    firing_s : (float, float) or None
        When a burn's engines fire [s]: once the body turns with the frame, until the
        piece ends or starts to stop.
    """

    kind: str
    start_s: float
    end_s: float
    attitude: Attitudes
    index: int | None = None
    slew: SlewProfile | None = None
    feedforward: bool = False
    blend_s: float = 0.0
    burn: BurnPlan | None = None
    firing_s: tuple[float, float] | None = None

    def end_attitude(self) -> np.ndarray:
        """q_BN at the piece's end, shape (4,)."""
        return self.attitude(np.array([self.end_s]))[0]


def one_slew_segments(simulation: Simulation) -> tuple[Segment, ...]:
    """The segments a run flies: its ``[[simulation.segments]]``, or its one
    ``[simulation.slew]`` as a slew segment, or none (a hold)."""
    if simulation.reference == "sequence":
        return simulation.segments
    slew = simulation.slew
    if simulation.reference != "slew" or slew is None:
        return ()
    return (Segment.of_slew(slew),)


def _held(q: np.ndarray) -> Attitudes:
    return lambda times: np.tile(q, (len(times), 1))


def _frame(orbit: CircularOrbit, target: Target) -> Attitudes:
    offset = IDENTITY if target.quaternion is None else target.quaternion
    return lambda times: frame_attitude(orbit, offset, times)


def _slew_attitudes(profile: SlewProfile, start_s: float) -> Attitudes:
    return lambda times: slew_quaternions(profile, np.asarray(times) - start_s)


@dataclass
class _Builder:
    problem: Problem
    sample_s: float
    run_s: float
    key: str = ""
    """The table every error names (``simulation.slew`` for the one slew), else each
    segment's own."""

    def __post_init__(self) -> None:
        self.orbit = CircularOrbit.from_problem(self.problem)
        self.pieces: list[Piece] = []
        self.time_s = 0.0

    @property
    def attitude(self) -> np.ndarray:
        """Where the reference is at the current time, shape (4,)."""
        if not self.pieces:
            return IDENTITY
        return self.pieces[-1].attitude(np.array([self.time_s]))[0]

    def add(self, index: int, segment: Segment, following: Segment | None) -> None:
        """Append ``segment`` (and the hold before it, if it starts later); ``following``
        is the segment after it, None for the last."""
        start = self.time_s if segment.start_s is None else segment.start_s
        if start > self.time_s:
            self.pieces.append(Piece("hold", self.time_s, start, _held(self.attitude)))
        self.time_s = start
        key = self.key or f"simulation.segments[{index}]"
        lead_s = following.blend_s / 2 if following and following.kind in TRACKS else 0.0
        if segment.kind == "slew":
            piece = self._slew(segment, index, key, lead_s)
        else:
            end = self.run_s if segment.duration_s is None else start + segment.duration_s
            if segment.kind == "hold":
                piece = Piece("hold", start, end, _held(self.attitude), index)
            else:
                piece = self._track(segment, index, (start, end), following)
        # The one [simulation.slew] may outlast the run (the run then ends during it).
        if piece.end_s > self.run_s + 1e-9 and not self.key:
            raise ProblemFileError(
                f"{key}.duration_s" if segment.duration_s is not None else key,
                f"ends at {piece.end_s:.6g} s, past the run's {self.run_s:g} s",
                self.problem.source,
            )
        self.pieces.append(piece)
        self.time_s = piece.end_s
        if following is None and piece.end_s < self.run_s:
            self.pieces.append(Piece("hold", piece.end_s, self.run_s, _held(self.attitude)))

    def _track(
        self,
        segment: Segment,
        index: int,
        window_s: tuple[float, float],
        following: Segment | None,
    ) -> Piece:
        """A track, from rest (or from the track before) and, unless the run ends or a
        track follows, to rest (:func:`~casadi_debris.guidance._targets.track_attitudes`)."""
        # The reader gives every track its frame; a burn's comes from its axis and direction.
        assert segment.target is not None or segment.burn is not None
        before = self.pieces[-1] if self.pieces else None
        stop = following is not None and following.kind not in TRACKS
        needed = segment.blend_s * (2 if stop else 1)
        if window_s[1] - window_s[0] < needed:
            raise ProblemFileError(
                f"{self.key or f'simulation.segments[{index}]'}.blend_s",
                f"{segment.blend_s:g} s to reach the frame"
                + (" and as long to stop" if stop else "")
                + f" does not fit in the track's {window_s[1] - window_s[0]:g} s",
                self.problem.source,
            )
        burn, firing = None, None
        if segment.burn is not None:
            burn, target = self._burn(segment, index, window_s, stop)
            firing = (window_s[0] + segment.blend_s, window_s[1] - (segment.blend_s if stop else 0))
        else:
            assert segment.target is not None
            target = segment.target
        offset = IDENTITY if target.quaternion is None else target.quaternion
        attitudes = track_attitudes(
            self.orbit,
            offset,
            window_s,
            segment.blend_s,
            None if before is None else before.attitude,
            from_track=before is not None and before.kind in TRACKS,
            stop=stop,
        )
        kind = "track" if burn is None else "burn"
        return Piece(
            kind, *window_s, attitudes, index, blend_s=segment.blend_s, burn=burn, firing_s=firing
        )

    def _burn(
        self, segment: Segment, index: int, window_s: tuple[float, float], stop: bool
    ) -> tuple[BurnPlan, Target]:
        """A burn segment's plan and the LVLH offset holding its axis along its direction."""
        request = segment.burn
        assert request is not None
        firing = window_s[1] - window_s[0] - segment.blend_s * (2 if stop else 1)
        if firing <= 0.0:
            raise ProblemFileError(
                f"{self.key or f'simulation.segments[{index}]'}.duration_s",
                "leaves the engines no time to fire: the burn reaches the frame after "
                f"blend_s ({segment.blend_s:g} s)" + (" and stops as long" if stop else ""),
                self.problem.source,
            )
        plan = plan_burn(self.problem, request, firing)
        offset = burn_offset(plan.body_axis, plan.direction_lvlh)
        return plan, Target("frame", quaternion=offset, frame="lvlh")

    def _slew(self, segment: Segment, index: int, key: str, lead_s: float) -> Piece:
        """A slew from where the reference is; onto a frame, aimed at its attitude
        ``lead_s`` after the slew's end (half the next track's start-up: see
        :func:`~casadi_debris.guidance._targets.track_attitudes`)."""
        assert segment.target is not None and segment.slew is not None  # the reader's
        start, q0, target = self.time_s, self.attitude, segment.target
        request: SlewRequest = segment.slew

        def solve(end_s: float) -> SlewProfile:
            goal = self._slew_target(target, q0, end_s + lead_s, key)
            return solve_slew(self.problem, goal, request, self.sample_s, key)

        profile = solve(start + (segment.duration_s or 0.0))
        if target.kind == "frame" and segment.duration_s is None:
            profile = self._onto_frame(solve, start, profile, key)
        return Piece(
            "slew",
            start,
            start + profile.duration_s,
            _slew_attitudes(profile, start),
            index,
            profile,
            request.feedforward,
        )

    def _onto_frame(
        self,
        solve: Callable[[float], SlewProfile],
        start: float,
        first: SlewProfile,
        key: str,
    ) -> SlewProfile:
        """The slew whose end meets the moving frame: a root of g(e) = start + T(e) - e,
        T(e) the duration of the slew aimed at the frame's attitude at e, by secant steps."""
        x0, g0 = start, first.duration_s
        x1 = start + first.duration_s
        g1 = g0
        for _ in range(FRAME_ITERATIONS):
            profile = solve(x1)
            g1 = start + profile.duration_s - x1
            if abs(g1) <= FRAME_DURATION_TOLERANCE_S:
                return profile
            step = g1 * (x1 - x0) / (g1 - g0) if g1 != g0 else g1
            x0, g0, x1 = x1, g1, x1 - step
        raise ProblemFileError(
            key,
            f"the slew's end did not meet the moving frame in {FRAME_ITERATIONS} solves "
            f"(off by {abs(g1):.3g} s); give its duration_s",
            self.problem.source,
        )

    def _slew_target(self, target: Target, q0: np.ndarray, end_s: float, key: str) -> SlewTarget:
        try:
            if target.kind == "rotation":
                assert target.axis is not None and target.angle_deg is not None
                return slew_about_axis(target.axis, math.radians(target.angle_deg), q0)
            if target.kind == "attitude":
                assert target.quaternion is not None
                return slew_between(q0, target.quaternion)
            return slew_between(q0, _frame(self.orbit, target)(np.array([end_s]))[0])
        except InputShapeError as exc:  # the target is where the slew starts
            raise ProblemFileError(key, str(exc), self.problem.source) from None


def sequence_pieces(problem: Problem, sample_s: float) -> list[Piece]:
    """The pieces of the problem's manoeuvre, covering [0, ``simulation.duration_s``].

    Parameters
    ----------
    problem : Problem
    sample_s : float
        Sample spacing of the slew profiles [s].

    Raises
    ------
    ProblemFileError
        A segment cannot be flown as written (a slew infeasible, a target equal
        to the start, a segment past the run's end), naming it.
    """
    run_s = problem.simulation.duration_s
    one_slew = problem.simulation.reference == "slew"
    builder = _Builder(problem, sample_s, run_s, "simulation.slew" if one_slew else "")
    segments = one_slew_segments(problem.simulation)
    for index, segment in enumerate(segments):
        builder.add(index, segment, segments[index + 1] if index + 1 < len(segments) else None)
    if not builder.pieces:
        return [Piece("hold", 0.0, run_s, _held(IDENTITY))]
    return builder.pieces


def sample_pieces(pieces: list[Piece], time_s: np.ndarray) -> np.ndarray:
    """q_BN of the piece in force at each time, shape (n, 4)."""
    starts = np.array([piece.start_s for piece in pieces])
    which = np.clip(np.searchsorted(starts, time_s, side="right") - 1, 0, len(pieces) - 1)
    quaternion = np.zeros((len(time_s), 4))
    for i, piece in enumerate(pieces):
        mask = which == i
        if mask.any():
            quaternion[mask] = piece.attitude(time_s[mask])
    return quaternion


@dataclass(frozen=True)
class SegmentPlanSummary(Record):
    """One stretch of a manoeuvre as a user reads it.

    Attributes
    ----------
    segment : int or None
        Its ``[[simulation.segments]]`` entry, numbered from 1; None for a hold
        the sequence adds (before a late start, after the last segment).
    kind : {"slew", "hold", "track", "burn"}
    start_s, end_s : float
    method : str or None
        A slew's method.
    angle_deg : float or None
        A slew's eigenaxis angle.
    axis : tuple of 3 floats or None
        A slew's unit eigenaxis in body axes (those of its start).
    fuel_kg : float or None
        A slew profile's propellant (open loop).
    limits_ok : bool or None
        A slew profile, a track or a burn within the engines' authority over its whole
        window, gyroscopic torque included (:mod:`casadi_debris.slews._limits`; a track's
        torque is that of its attitude, a burn's within the torques the engines add to its
        thrust); None for a hold.
    worst_authority_share : float or None
        The largest share of the authority the slew's (track's, burn's) torque needs: its
        gauge in the engines' torque set (above 1 the loop cannot follow it; the per-axis
        ratios of the slew's check are information, :mod:`casadi_debris.slews._limits`).
    limits_note : str or None
        What the check found over the limits, with the figures ("" when within them).
    """

    segment: int | None
    kind: str
    start_s: float
    end_s: float
    method: str | None = None
    angle_deg: float | None = None
    axis: tuple[float, ...] | None = None
    fuel_kg: float | None = None
    limits_ok: bool | None = None
    worst_authority_share: float | None = None
    limits_note: str | None = None


# Sample spacing of a track's limit check [s], and at least this many samples per blend.
TRACK_CHECK_S = 1.0
TRACK_CHECK_BLEND_SAMPLES = 100


def track_limits(problem: Problem, piece: Piece) -> LimitCheck:
    """A track's or burn's attitude over its window against the engines
    (:func:`~casadi_debris.guidance._burn_plan.attitude_limits`): a burn's while its engines
    fire within the torques they add to its thrust, elsewhere at zero net force."""
    step = TRACK_CHECK_S
    if piece.blend_s > 0.0:
        step = min(step, piece.blend_s / TRACK_CHECK_BLEND_SAMPLES)
    count = max(3, math.ceil((piece.end_s - piece.start_s) / step - 1e-9) + 1)
    times = np.linspace(piece.start_s, piece.end_s, count)
    force = None
    if piece.burn is not None and piece.firing_s is not None:
        thrust = burn_thrust_N(Allocator.from_problem(problem), piece.burn, strict=False)
        firing = (times >= piece.firing_s[0]) & (times <= piece.firing_s[1])
        force = np.where(firing[:, None], thrust * piece.burn.body_axis[None, :], 0.0)
    return attitude_limits(problem, times, piece.attitude(times), force)


def segment_records(
    pieces: list[Piece] | tuple[Piece, ...], problem: Problem | None = None
) -> tuple[SegmentPlanSummary, ...]:
    """The pieces as records (1-based segment numbers, slews' figures); with ``problem``,
    tracks and burns checked against the engines too (:func:`track_limits`)."""
    records = []
    for piece in pieces:
        slew = piece.slew
        check = slew.limits if slew is not None else None
        if check is None and problem is not None and piece.kind in TRACKS:
            check = track_limits(problem, piece)
        records.append(
            SegmentPlanSummary(
                segment=None if piece.index is None else piece.index + 1,
                kind=piece.kind,
                start_s=piece.start_s,
                end_s=piece.end_s,
                method=None if slew is None else slew.method,
                angle_deg=None if slew is None else math.degrees(slew.target.angle_rad),
                axis=None if slew is None else tuple(float(v) for v in slew.target.axis_B),
                fuel_kg=None if slew is None else slew.fuel_kg,
                limits_ok=None if check is None else check.limits_ok,
                # The torque-set gauge: what limits_ok tests.
                worst_authority_share=None if check is None else check.worst_torque_set_ratio,
                limits_note=None if check is None else check.limits_note,
            )
        )
    return tuple(records)


@dataclass(frozen=True)
class ManoeuvreSummary(Record):
    """A manoeuvre's reference, segment by segment (``casadi-debris slew`` of a sequence).

    Attributes
    ----------
    problem : str
    duration_s : float
        The run's length.
    segments : tuple of SegmentPlanSummary
    fuel_slews_kg : float
        The slew profiles' propellant, summed (open loop: no feedback, no disturbance).
    wall_time_s : float
        Solving every slew and sampling the reference.
    slews_within_limits : bool
        Every slew within the engines' authority (each slew segment's ``limits_ok``).
    tracks_within_limits : bool
        Every LVLH track and burn within it (each such segment's ``limits_ok``).
    """

    problem: str
    duration_s: float
    segments: tuple[SegmentPlanSummary, ...]
    fuel_slews_kg: float
    wall_time_s: float
    slews_within_limits: bool = True
    tracks_within_limits: bool = True


@dataclass(frozen=True, eq=False)
class ManoeuvreReference:
    """A manoeuvre's reference sampled uniformly, and its summary.

    Attributes
    ----------
    time_s : ndarray, shape (n,)
    quaternion_BN : ndarray, shape (n, 4)
    rate_rad_s : ndarray, shape (n, 3)
        Body rates by central differences of the attitude.
    summary : ManoeuvreSummary
    """

    time_s: np.ndarray
    quaternion_BN: np.ndarray
    rate_rad_s: np.ndarray
    summary: ManoeuvreSummary


def manoeuvre_reference(problem: Problem, sample_s: float) -> ManoeuvreReference:
    """The problem's manoeuvre (``[simulation]``) sampled every ``sample_s`` [s]."""
    started = time.perf_counter()
    pieces = sequence_pieces(problem, sample_s)
    run_s = problem.simulation.duration_s
    times = np.append(np.arange(0.0, run_s, sample_s), run_s)
    quaternion = sample_pieces(pieces, times)
    records = segment_records(pieces, problem)
    summary = ManoeuvreSummary(
        problem=problem.name,
        duration_s=run_s,
        segments=records,
        fuel_slews_kg=float(sum(r.fuel_kg for r in records if r.fuel_kg is not None)),
        wall_time_s=time.perf_counter() - started,
        slews_within_limits=all(r.limits_ok is not False for r in records if r.kind == "slew"),
        tracks_within_limits=all(r.limits_ok is not False for r in records if r.kind != "slew"),
    )
    return ManoeuvreReference(times, quaternion, body_rates(times, quaternion), summary)
