"""Attitudes a manoeuvre points at: the orbit's LVLH frame, and smooth joins between references.

The LVLH frame O of :class:`~casadi_debris.environment.CircularOrbit`
(o1 along track, o2 against the orbit normal, o3 to nadir) has the attitude
q_ON with rotation matrix C_NO = [o1 o2 o3] (frame components to inertial ones).
A body held at q_OB in it (:class:`~casadi_debris.config.Target` of kind
``"frame"``) has

    q_BN(t) = q_ON(t) (x) q_OB,

and turns with the frame at the orbit rate n about the orbit normal h (fixed in N):
q_BN(t + d) = q_h(n d) (x) q_BN(t), q_h(a) the turn by a about h.

A track (:func:`track_attitudes`) starts and ends at rest, so that it meets slews
and holds (which do) with attitude and rate continuous. Over its first T =
``blend_s`` the rate about h rises from 0 to n as the :func:`smoothstep` s, while a
body-fixed correction (zero when the track starts where the frame will be at
t0 + T/2) is taken out:

    q(t) = q_h(n T S(tau)) (x) q_0 (x) exp(s(tau) delta),
    delta = log(q_0^-1 (x) q_frame(t0 + T / 2)),  S(tau) = integral of s = 1/2 at tau = 1,

reaching the frame at t0 + T with its rate; over its last T the rate falls to 0
the same way, leaving the body at rest at the frame's attitude of t_end - T/2.
Peak angular acceleration: 1.875 n / T. A track following a track is joined by
:func:`blend` instead (both turn at the same rate).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.spatial.transform import Rotation

from casadi_debris.dynamics import (
    axis_angle_quaternion,
    quaternion_multiply,
    quaternion_to_rotation,
    rotation_to_quaternion,
)
from casadi_debris.environment import CircularOrbit


def lvlh_matrices(orbit: CircularOrbit, time_s: np.ndarray) -> np.ndarray:
    """C_ON at each time: rows o1, o2, o3 in N, shape (n, 3, 3)."""
    position = np.atleast_2d(orbit.position_m(np.asarray(time_s, dtype=float)))
    o3 = -position / np.linalg.norm(position, axis=1, keepdims=True)
    o2 = np.broadcast_to(-orbit.normal, o3.shape)
    o1 = np.cross(o2, o3)
    return np.stack([o1, o2, o3], axis=1)


def frame_attitude(orbit: CircularOrbit, offset_OB: np.ndarray, time_s: np.ndarray) -> np.ndarray:
    """q_BN = q_ON (x) q_OB of a body held at ``offset_OB`` in the LVLH frame, shape (n, 4).

    Signs are made continuous along ``time_s`` (neighbours' dot product >= 0).
    """
    c_no = np.swapaxes(lvlh_matrices(orbit, time_s), 1, 2)
    q_on = rotation_to_quaternion(Rotation.from_matrix(c_no))
    return continuous_sign(quaternion_multiply(q_on, np.broadcast_to(offset_OB, q_on.shape)))


def continuous_sign(quaternion: np.ndarray) -> np.ndarray:
    """The same rotations with signs flipped so that neighbours never point apart, (n, 4)."""
    q = np.array(quaternion, dtype=float, copy=True)
    if len(q) < 2:
        return q
    flips = np.cumsum(np.einsum("ij,ij->i", q[1:], q[:-1]) < 0.0) % 2
    q[1:][flips == 1] *= -1.0
    return q


def smoothstep(fraction: np.ndarray) -> np.ndarray:
    """s = 10 f^3 - 15 f^4 + 6 f^5 on f clipped to [0, 1]: 0 to 1 with s' = s'' = 0 at both ends."""
    f = np.clip(fraction, 0.0, 1.0)
    return f**3 * (10.0 + f * (-15.0 + 6.0 * f))


def blend(q_old: np.ndarray, q_new: np.ndarray, fraction: np.ndarray) -> np.ndarray:
    """From one reference to another, attitude and rate continuous at both ends, (n, 4).

        q(t) = q_new(t) (x) exp((1 - s(f)) log(q_new(t)^-1 (x) q_old(t)))

    with s the :func:`smoothstep` of the fraction f of the join done: q_old (and
    its rate) at f = 0, q_new (and its rate) at f = 1. The rotation between the
    two is taken the short way.
    """
    new = quaternion_to_rotation(q_new)
    gap = (new.inv() * quaternion_to_rotation(q_old)).as_rotvec()
    left = (1.0 - smoothstep(np.asarray(fraction, dtype=float)))[:, None]
    return rotation_to_quaternion(new * Rotation.from_rotvec(left * gap))


def smoothstep_integral(fraction: np.ndarray) -> np.ndarray:
    """S(f) = integral of :func:`smoothstep` from 0 to f = 5/2 f^4 - 3 f^5 + f^6 (1/2 at 1),
    continued linearly (slope 1) past f = 1."""
    f = np.clip(fraction, 0.0, 1.0)
    inside = f**4 * (2.5 + f * (-3.0 + f))
    return np.asarray(inside + np.maximum(np.asarray(fraction, dtype=float) - 1.0, 0.0))


def track_attitudes(
    orbit: CircularOrbit,
    offset_OB: np.ndarray,
    window_s: tuple[float, float],
    blend_s: float,
    before: Callable[[np.ndarray], np.ndarray] | None,
    *,
    from_track: bool,
    stop: bool,
) -> Callable[[np.ndarray], np.ndarray]:
    """q_BN(t) of a track of the LVLH frame held at ``offset_OB``, started and ended at rest.

    Parameters
    ----------
    orbit : CircularOrbit
    offset_OB : ndarray, shape (4,)
    window_s : (float, float)
        The track's start t0 and end [s].
    blend_s : float
        T: the time its start (and end, with ``stop``) takes [s].
    before : callable or None
        The reference before t0 (continued past it); None: at rest at [1, 0, 0, 0].
    from_track : bool
        ``before`` is a track (turning with the frame): joined by :func:`blend`.
    stop : bool
        Come to rest over the window's last T (something other than a track follows).

    Returns
    -------
    callable
        Times [s], shape (n,) -> q_BN, shape (n, 4); held at the end past it when
        ``stop``, else the frame continued.
    """
    t0, t_end = window_s
    n, axis = orbit.mean_motion_rad_s, orbit.normal

    def frame(times: np.ndarray) -> np.ndarray:
        return frame_attitude(orbit, offset_OB, times)

    def turned(angle: np.ndarray, q: np.ndarray) -> np.ndarray:
        return quaternion_multiply(axis_angle_quaternion(axis, angle), q)

    q0 = np.array([1.0, 0.0, 0.0, 0.0]) if before is None else before(np.array([t0]))[0]
    delta = (
        quaternion_to_rotation(q0).inv()
        * quaternion_to_rotation(frame(np.array([t0 + blend_s / 2])))
    ).as_rotvec()
    stop_start = t_end - blend_s
    q_stop = frame(np.array([stop_start]))

    def attitudes(times: np.ndarray) -> np.ndarray:
        times = np.asarray(times, dtype=float)
        fraction = (times - t0) / blend_s
        q = frame(times)
        rising = fraction < 1.0
        if rising.any() and from_track and before is not None:
            q[rising] = blend(before(times[rising]), q[rising], fraction[rising])
        elif rising.any():
            f = fraction[rising]
            spun = turned(n * blend_s * smoothstep_integral(f), np.tile(q0, (len(f), 1)))
            correction = Rotation.from_rotvec(smoothstep(f)[:, None] * delta)
            q[rising] = rotation_to_quaternion(quaternion_to_rotation(spun) * correction)
        if stop:
            falling = times > stop_start
            f = (times[falling] - stop_start) / blend_s
            down = np.minimum(f, 1.0) - smoothstep_integral(f) + np.maximum(f - 1.0, 0.0)
            q[falling] = turned(n * blend_s * down, np.tile(q_stop, (len(f), 1)))
        return continuous_sign(q)

    return attitudes


def body_rates(time_s: np.ndarray, quaternion_BN: np.ndarray) -> np.ndarray:
    """Body rates omega_BN in B of an attitude series, shape (n, 3) [rad/s].

    Central differences of the rotation: the mean of rotvec(q_k^-1 (x) q_k+1) / dt
    over the steps either side of each sample (one side at the ends);
    second-order accurate for a uniform series.
    """
    rotations = quaternion_to_rotation(quaternion_BN)
    steps = (rotations[:-1].inv() * rotations[1:]).as_rotvec() / np.diff(time_s)[:, None]
    rates = np.empty((len(time_s), 3))
    rates[0], rates[-1] = steps[0], steps[-1]
    rates[1:-1] = 0.5 * (steps[:-1] + steps[1:])
    return rates
