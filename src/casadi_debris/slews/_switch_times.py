"""Switch-time refinement of a bang-bang time-optimal slew, and its verification.

Collocation on uniform intervals cannot put a switch between two nodes: the
interval that holds it takes an intermediate torque, and the slew comes out a
little long (the Bilimoria & Wie benchmark: 3.2442 on 40 intervals against
3.2431). When every torque channel of the best collocation solution is
saturated but for isolated intervals, the control is bang-bang and its switch
structure can be read off:

- each channel's sign on every saturated interval; a run of at most
  ``MAX_TRANSITION`` intermediate intervals between two signs is a switch
  placed where the run's mean torque puts it, f = (1 + s_before mean(v)) / 2
  of the way through (v the torque scaled to [-1, 1]); between equal signs it
  is a pulse of the other sign, centred;
- the switches of the three channels merged in time order give K segments,
  each with one torque corner held.

The segments' lengths d_k >= 0 are then the decision variables of a small NLP,

    min  sum_k d_k   s.t.  x(sum_k d_k) on target at rest,

each segment integrated by CVODES (tolerances 1e-13) with its forward
sensitivities (IPOPT with a quasi-Newton Hessian: a few variables, an
integration deep). The result is verified by integrating the bang-bang control
again, restarted at every switch: the residual is the attitude error and the
rate at the end, accepted below ``VERIFY_TOLERANCE``. A channel with a longer run of
intermediate torque (a singular arc) is not bang-bang: no refinement, and the
reason is returned.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import casadi as ca
import numpy as np

from casadi_debris.errors import NotBangBangError
from casadi_debris.parallel import keep_ctrl_c
from casadi_debris.slews._multistart import RigidSlew, StartOutcome
from casadi_debris.slews._rigid_body import N_RIGID_STATE, scaled_rigid_ode
from casadi_debris.slews._transcription import ACCEPTED_STATUS, SolverOptions

SATURATED = 1e-3  # |v| >= 1 - SATURATED: the channel is at a bound
MAX_TRANSITION = 3  # intermediate intervals one switch may spread over
MIN_PULSE = 1e-3  # shorter pulses (fraction of an interval) are rounding, not switches
VERIFY_TOLERANCE = 1e-9  # rad, and rad per scaled time
DEGREE = 5  # Radau IIA on every sub-interval: order 9
MAX_STEP = 0.1  # longest sub-interval at the guess, scaled time
REFINEMENTS = 3
REFINE_OPTIONS: SolverOptions = {
    "expand": True,
    "print_time": False,
    "ipopt.print_level": 0,
    "ipopt.sb": "yes",
    "ipopt.max_iter": 200,
    "ipopt.tol": 1e-10,
    "ipopt.constr_viol_tol": 1e-13,
}
CVODES_OPTIONS = {"abstol": 1e-14, "reltol": 1e-13, "max_num_steps": 100000}


@dataclass(frozen=True)
class SwitchStructure:
    """A bang-bang control as segments.

    Attributes
    ----------
    signs : ndarray, shape (K, 3)
        +1 (upper bound) or -1 (lower bound) of each channel on each segment.
    durations : ndarray, shape (K,)
        Segment lengths, scaled time.
    """

    signs: np.ndarray
    durations: np.ndarray

    def controls(self, slew: RigidSlew) -> np.ndarray:
        """Scaled torque of each segment, shape (K, 3)."""
        return np.where(self.signs > 0, slew.upper[None, :], slew.lower[None, :])

    def switch_times(self) -> list[list[float]]:
        """Per channel, the (scaled) times its sign changes."""
        edges = np.cumsum(self.durations)[:-1]
        changes = np.diff(self.signs, axis=0) != 0
        return [edges[changes[:, i]].tolist() for i in range(3)]


@dataclass(frozen=True)
class RefinedSlew:
    """The refined bang-bang and its check.

    Attributes
    ----------
    structure : SwitchStructure
        Signs and optimal segment lengths.
    duration : float
        Scaled length.
    status : str
        IPOPT's status on the last refinement.
    attitude_error_rad, rate_error : float
        Attitude error (rad) and scaled rate at the end, from CVODES.
    """

    structure: SwitchStructure
    duration: float
    status: str
    attitude_error_rad: float
    rate_error: float

    @property
    def verified(self) -> bool:
        """Converged, and the end state within ``VERIFY_TOLERANCE`` of the target."""
        return (
            self.status in ACCEPTED_STATUS
            and self.attitude_error_rad <= VERIFY_TOLERANCE
            and self.rate_error <= VERIFY_TOLERANCE
        )


def switch_structure(slew: RigidSlew, outcome: StartOutcome) -> SwitchStructure:
    """Read the switch structure off a collocation solution (module notes).

    Raises
    ------
    NotBangBangError
        A channel with more than ``MAX_TRANSITION`` intermediate intervals in a row.
    """
    controls = outcome.controls
    n = controls.shape[0]
    step = outcome.duration / n
    middle, half = (slew.upper + slew.lower) / 2.0, (slew.upper - slew.lower) / 2.0
    scaled = (controls - middle) / half
    events: list[tuple[float, int, float]] = []  # (time, channel, sign after)
    initial = np.zeros(3)
    for channel in range(3):
        first, switches = _channel_switches(scaled[:, channel], "xyz"[channel])
        initial[channel] = first
        events.extend((at * step, channel, sign) for at, sign in switches)
    events.sort()
    signs, times = [initial.copy()], [0.0]
    for at, channel, sign in events:
        current = signs[-1].copy()
        current[channel] = sign
        signs.append(current)
        times.append(at)
    times.append(outcome.duration)
    return SwitchStructure(np.array(signs), np.diff(np.array(times)))


def _channel_switches(values: np.ndarray, name: str) -> tuple[float, list[tuple[float, float]]]:
    """The first sign and the (time in intervals, new sign) switches of one channel."""
    saturated = np.abs(values) >= 1.0 - SATURATED
    if not np.any(saturated):
        raise NotBangBangError(f"torque {name} never reaches a bound")
    signs = np.where(values >= 0.0, 1.0, -1.0)
    n = len(values)
    switches: list[tuple[float, float]] = []
    current: float | None = None
    first = 0.0
    k = 0
    while k < n:
        if saturated[k]:
            if current is None:
                current = first = signs[k]
            elif signs[k] != current:
                switches.append((float(k), signs[k]))
                current = signs[k]
            k += 1
            continue
        stop = k
        while stop < n and not saturated[stop]:
            stop += 1
        if stop - k > MAX_TRANSITION:
            raise NotBangBangError(
                f"torque {name} is between its bounds on intervals {k + 1} to {stop}"
                " (a singular arc, or too few intervals)"
            )
        before = current if current is not None else -signs[stop]
        after = signs[stop] if stop < n else -before
        if current is None:
            first = before
        switches += _transition(k, stop - k, before, after, float(np.mean(values[k:stop])))
        current = after if stop < n else before
        k = stop
    # A switch within a pulse's width of either end is no switch: the end's sign holds.
    while switches and switches[0][0] <= MIN_PULSE:
        first = switches.pop(0)[1]
    while switches and switches[-1][0] >= n - MIN_PULSE:
        switches.pop()
    return float(first), switches


def _transition(
    start: int, width: int, before: float, after: float, mean: float
) -> list[tuple[float, float]]:
    """The switches that give ``mean`` over ``width`` intervals from ``start`` between a
    run of sign ``before`` and one of sign ``after`` (times in intervals)."""
    if before != after:
        return [(start + width * (1.0 + before * mean) / 2.0, after)]
    pulse = width * (1.0 - before * mean) / 2.0
    if pulse <= MIN_PULSE:
        return []
    centre = start + width / 2.0
    return [(centre - pulse / 2.0, -before), (centre + pulse / 2.0, before)]


def refine(slew: RigidSlew, structure: SwitchStructure) -> RefinedSlew:
    """Optimise the segment lengths of ``structure`` and verify the result (module notes).

    Sub-intervals are doubled until the verification passes, at most ``REFINEMENTS`` times.
    """
    controls = structure.controls(slew)
    durations = structure.durations
    max_step = MAX_STEP
    for attempt in range(1, REFINEMENTS + 1):
        status, durations = _solve_lengths(slew, controls, durations, max_step)
        attitude, rate = verify(slew, controls, durations)
        result = RefinedSlew(
            SwitchStructure(structure.signs, durations),
            float(np.sum(durations)),
            status,
            attitude,
            rate,
        )
        if result.verified or status not in ACCEPTED_STATUS or attempt == REFINEMENTS:
            return result
        max_step /= 2.0
    raise AssertionError("unreachable: the last attempt returns")


def _solve_lengths(
    slew: RigidSlew, controls: np.ndarray, durations: np.ndarray, max_step: float
) -> tuple[str, np.ndarray]:
    """IPOPT on the segment lengths, each segment collocated on sub-intervals of at most
    ``max_step`` (scaled, at the guess); the status and the lengths (scaled)."""
    ode = scaled_rigid_ode(slew.body, slew.time_scale_s)
    tau = [float(t) for t in ca.collocation_points(DEGREE, "radau")]
    C, D, _ = (ca.DM(m) for m in ca.collocation_coeff(tau))
    lengths = ca.SX.sym("d", len(durations))
    state: ca.SX = ca.SX(np.concatenate([slew.q_initial_BN, np.zeros(3)]))
    numeric = np.concatenate([slew.q_initial_BN, np.zeros(3)])
    variables, guesses, constraints = [lengths], [durations], []
    for k, (control, length) in enumerate(zip(controls, durations, strict=True)):
        count = max(1, math.ceil(length / max_step))
        points = ca.SX.sym(f"x{k}", N_RIGID_STATE, count * DEGREE)
        variables.append(ca.vec(points))
        trajectory = _held_states(slew, numeric, control, length, count, tau)
        guesses.append(trajectory.ravel())  # column by column, as ca.vec(points)
        numeric = trajectory[-1]
        u, h = ca.DM(control), lengths[k] / count
        for j in range(count):
            inner = points[:, j * DEGREE : (j + 1) * DEGREE]
            z = ca.horzcat(state, inner)
            slopes = ca.horzcat(*[ode(inner[:, i], u) for i in range(DEGREE)])
            constraints.append(ca.vec(h * slopes - z @ C))
            state = z @ D
    constraints.append(slew.terminal_error(state))
    x = ca.vertcat(*variables)
    solver = ca.nlpsol(
        "switch_times",
        "ipopt",
        {"x": x, "f": ca.sum1(lengths), "g": ca.vertcat(*constraints)},
        REFINE_OPTIONS,
    )
    n_d = len(durations)
    lower = np.concatenate([np.zeros(n_d), np.full(x.shape[0] - n_d, -np.inf)])
    with keep_ctrl_c():
        result = solver(x0=np.concatenate(guesses), lbx=lower, lbg=0.0, ubg=0.0)
    status = str(solver.stats()["return_status"])
    return status, np.maximum(np.array(result["x"]).ravel()[:n_d], 0.0)


def _held_states(
    slew: RigidSlew,
    start: np.ndarray,
    control: np.ndarray,
    length: float,
    count: int,
    tau: list[float],
) -> np.ndarray:
    """Scaled states at the collocation points of ``count`` equal sub-intervals of a held
    segment from ``start``, by CVODES, shape (count * DEGREE, 7)."""
    grid = [(j + t) / count for j in range(count) for t in tau]
    x, u, duration = ca.SX.sym("x", N_RIGID_STATE), ca.SX.sym("u", 3), ca.SX.sym("length")
    ode = scaled_rigid_ode(slew.body, slew.time_scale_s)
    dae = {"x": x, "p": ca.vertcat(u, duration), "ode": duration * ode(x, u)}
    integrator = ca.integrator("held", "cvodes", dae, 0.0, grid, CVODES_OPTIONS)
    return np.array(integrator(x0=start, p=np.concatenate([control, [length]]))["xf"]).T


def verify(slew: RigidSlew, controls: np.ndarray, durations: np.ndarray) -> tuple[float, float]:
    """Attitude error (rad) and scaled rate norm at the end of the bang-bang, by CVODES.

    Parameters
    ----------
    controls : ndarray, shape (K, 3)
        Scaled torque held on each segment.
    durations : ndarray, shape (K,)
        Segment lengths, scaled time.
    """
    final = integrate_segments(slew, controls, durations)
    error = _attitude_error(slew.q_final_BN, final[0:4])
    return float(np.linalg.norm(error)), float(np.linalg.norm(final[4:7]))


def integrate_segments(slew: RigidSlew, controls: np.ndarray, durations: np.ndarray) -> np.ndarray:
    """Scaled state at the end of held segments, from rest at the start, by CVODES,
    shape (7,)."""
    integrator = _segment_integrator(slew)
    state = np.concatenate([slew.q_initial_BN, np.zeros(3)])
    for control, duration in zip(controls, durations, strict=True):
        if duration > 0.0:
            parameters = np.concatenate([control, [duration]])
            state = np.array(integrator(x0=state, p=parameters)["xf"]).ravel()
    return state


def _segment_integrator(slew: RigidSlew) -> ca.Function:
    """CVODES over one held segment: ``x0`` the scaled state, ``p`` = [u (3), length]."""
    x, u, length = ca.SX.sym("x", N_RIGID_STATE), ca.SX.sym("u", 3), ca.SX.sym("length")
    ode = scaled_rigid_ode(slew.body, slew.time_scale_s)
    # The segment on [0, 1] with its length as a parameter: one integrator for all.
    dae = {"x": x, "p": ca.vertcat(u, length), "ode": length * ode(x, u)}
    return ca.integrator("segment", "cvodes", dae, 0.0, 1.0, CVODES_OPTIONS)


def _attitude_error(q_reference: np.ndarray, q: np.ndarray) -> np.ndarray:
    """Doubled vector part of q_ref^-1 (x) q, short way (rad), shape (3,); q need not be
    of unit norm."""
    r0, rv = q_reference[0], -q_reference[1:4]
    q = q / np.linalg.norm(q)
    scalar = r0 * q[0] - rv @ q[1:4]
    vector = r0 * q[1:4] + q[0] * rv + np.cross(rv, q[1:4])
    return 2.0 * (1.0 if scalar >= 0.0 else -1.0) * vector
