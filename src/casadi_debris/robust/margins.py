"""Loop-at-a-time and disk margins of the attitude loop.

The loop is broken at one plant input at a time, the other two closed: the
return ratio L_i(s) from plant input i back to controller output i (negative
feedback, u = -K y). Its margins are read off a dense frequency response
(``MARGIN_GRID``, 1e-4 .. 1e2 rad/s, 0.8 % steps), crossings refined by Brent's method:

- gain margin: at every crossing of the negative real axis, the distance in dB
  from |L_i| to 1; the smaller of the upper (|L| < 1) and lower (|L| > 1, an
  integrating loop is conditionally stable) margins;
- phase margin: the smallest at any gain crossover |L_i| = 1;
- delay margin: phase margin over its crossover frequency, smallest over crossovers.

The return ratios are formed from the plant's and controller's 3 x 3
frequency responses (batched solves), the controller's computed once, so
thousands of sampled plants take seconds. Disk margins (balanced, skew 0) of
the full MIMO loop come from ``control.disk_margins``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import control
import numpy as np
from scipy.optimize import brentq

from casadi_debris.errors import SynthesisError

CHANNELS = ("x", "y", "z")
MARGIN_GRID = np.logspace(-4, 2, 1800)
REFINE_DB = 3.0


class UnstableLoopError(SynthesisError):
    """The closed loop is unstable, so its margins are meaningless."""


@dataclass(frozen=True)
class LoopMargins:
    """Margins of one broken loop.

    Attributes
    ----------
    gain_margin_db : float
        Smaller of upper and lower gain margins, dB, positive (inf if none).
    upper_gain_margin_db, lower_gain_margin_db : float
        Gain increase / decrease to instability, dB, positive (inf if none).
    phase_margin_deg : float
    delay_margin_s : float
    crossover_rad_s : float
        Gain crossover frequency of the smallest phase margin.
    """

    gain_margin_db: float
    upper_gain_margin_db: float
    lower_gain_margin_db: float
    phase_margin_deg: float
    delay_margin_s: float
    crossover_rad_s: float


def closed_loop_matrix(plant: control.StateSpace, controller: control.StateSpace) -> np.ndarray:
    """State matrix of the loop u = -K y (plant strictly proper)."""
    ag, bg, cg = plant.A, plant.B, plant.C
    ak, bk, ck, dk = controller.A, controller.B, controller.C, controller.D
    return np.block([[ag - bg @ dk @ cg, bg @ ck], [-bk @ cg, ak]])


def closed_loop_poles(plant: control.StateSpace, controller: control.StateSpace) -> np.ndarray:
    """Poles of the loop u = -K y around a strictly proper plant."""
    _check_strictly_proper(plant)
    return np.linalg.eigvals(closed_loop_matrix(plant, controller))


def _check_strictly_proper(plant: control.StateSpace) -> None:
    if np.any(plant.D != 0):
        raise SynthesisError("margins need a strictly proper plant (D = 0)")


def return_ratio(
    plant: control.StateSpace, controller: control.StateSpace, channel: int
) -> control.StateSpace:
    """L_i: loop broken at plant input ``channel``, the others closed (negative feedback).

    With states [x_plant, x_controller], controller input -y and plant input
    u_j = (controller output)_j for j != i, v for j = i, L_i = -(v -> u_i).
    """
    _check_strictly_proper(plant)
    n = plant.ninputs
    keep = np.eye(n)
    keep[channel, channel] = 0.0
    bg, cg = plant.B, plant.C
    ck, dk = controller.C, controller.D
    a = np.block(
        [[plant.A - bg @ keep @ dk @ cg, bg @ keep @ ck], [-controller.B @ cg, controller.A]]
    )
    b = np.concatenate([bg[:, [channel]], np.zeros((controller.nstates, 1))])
    c = np.concatenate([-dk[[channel]] @ cg, ck[[channel]]], axis=1)
    return control.ss(a, b, -c, np.zeros((1, 1)))


def state_space_response(system: control.StateSpace, omega: np.ndarray) -> np.ndarray:
    """C (jw I - A)^-1 B + D by batched linear solves, shape (n_omega, n_out, n_in).

    Robust where eigendecompositions are not (the attitude plant's double
    integrators are Jordan blocks).
    """
    a, b, c, d = system.A, system.B, system.C, system.D
    if a.shape[0] == 0:
        return np.broadcast_to(d, (len(omega), *d.shape)).astype(complex)
    shifted = 1j * np.asarray(omega, dtype=float)[:, None, None] * np.eye(a.shape[0]) - a
    return c @ np.linalg.solve(shifted, np.broadcast_to(b, (len(omega), *b.shape))) + d


def return_ratios(plant_response: np.ndarray, controller_response: np.ndarray) -> np.ndarray:
    """L_i(jw) of every channel from the plant and controller responses, shape (n_omega, n).

    Loop broken at plant input i, the others closed, u = -K y: with M = K G and
    E = I - e_i e_i^T, u = -(I + M E)^-1 M e_i v, so L_i = e_i^T (I + M E)^-1 M e_i.
    """
    loop = controller_response @ plant_response
    n = loop.shape[1]
    ratios = np.empty(loop.shape[:2], dtype=complex)
    for i in range(n):
        keep = np.eye(n)
        keep[i, i] = 0.0
        ratios[:, i] = np.linalg.solve(np.eye(n) + loop @ keep, loop[:, :, [i]])[:, i, 0]
    return ratios


def _crossings(values: np.ndarray) -> np.ndarray:
    """Indices k where values changes sign between k and k + 1."""
    return np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)


def _refine(function, low: float, high: float) -> float:
    """Root of a scalar function of frequency bracketed by [low, high] (rad/s), in log w."""
    return math.exp(
        brentq(lambda x: function(math.exp(x)), math.log(low), math.log(high), xtol=1e-13)
    )


def margins_from_response(evaluate, omega: np.ndarray, response: np.ndarray) -> LoopMargins:
    """Margins of a SISO return ratio given on a grid and as a function for refinement.

    Every crossing is first estimated by interpolation on the grid; those that
    can decide a margin (within ``REFINE_DB`` dB or ``REFINE_DEG`` deg of the
    smallest estimate) are refined by Brent's method on ``evaluate``.

    Parameters
    ----------
    evaluate : callable
        w [rad/s] -> L(jw), complex.
    omega, response : ndarray, shape (n_omega,)
        The grid and L on it.
    """
    # Crossings of the negative real axis (Im L changes sign with Re L < 0) -> gain margins.
    axis_crossings = []
    for k in _crossings(response.imag):
        t = response.imag[k] / (response.imag[k] - response.imag[k + 1])
        estimate = response[k].real + t * (response[k + 1].real - response[k].real)
        if estimate < 0:
            axis_crossings.append((k, -20 * math.log10(abs(estimate))))
    upper, lower = [], []
    for sign, bucket in ((1.0, upper), (-1.0, lower)):
        candidates = [(k, sign * db) for k, db in axis_crossings if sign * db > 0]
        if not candidates:
            continue
        best = min(db for _, db in candidates)
        for k, db in candidates:
            if db <= best + REFINE_DB:
                w = _refine(lambda x: float(evaluate(x).imag), omega[k], omega[k + 1])
                point = evaluate(w)
                if point.real < 0:
                    bucket.append(abs(20 * math.log10(abs(point.real))))
    # Gain crossovers |L| = 1 -> phase and delay margins (few: refine them all).
    phases, frequencies = [], []
    for k in _crossings(np.abs(response) - 1.0):
        w = _refine(lambda x: float(abs(evaluate(x))) - 1.0, omega[k], omega[k + 1])
        frequencies.append(w)
        phases.append(180.0 + math.degrees(np.angle(evaluate(w))))
    upper_db, lower_db = min(upper, default=math.inf), min(lower, default=math.inf)
    if not phases:
        return LoopMargins(
            min(upper_db, lower_db), upper_db, lower_db, math.inf, math.inf, math.nan
        )
    phase_arr = np.array(phases)
    phase_arr = np.where(phase_arr > 180.0, phase_arr - 360.0, phase_arr)
    delays = np.where(phase_arr > 0, np.radians(phase_arr) / np.array(frequencies), 0.0)
    worst = int(np.argmin(phase_arr))
    return LoopMargins(
        gain_margin_db=min(upper_db, lower_db),
        upper_gain_margin_db=upper_db,
        lower_gain_margin_db=lower_db,
        phase_margin_deg=float(phase_arr[worst]),
        delay_margin_s=float(np.min(delays)),
        crossover_rad_s=float(frequencies[worst]),
    )


def loop_margins(loop: control.StateSpace, omega: np.ndarray = MARGIN_GRID) -> LoopMargins:
    """Gain, phase and delay margins of a SISO return ratio (negative feedback)."""

    def evaluate(w: float) -> complex:
        return complex(state_space_response(loop, np.array([w]))[0, 0, 0])

    return margins_from_response(evaluate, omega, state_space_response(loop, omega)[:, 0, 0])


def loop_at_a_time(
    plant: control.StateSpace,
    controller: control.StateSpace,
    omega: np.ndarray = MARGIN_GRID,
    controller_response: np.ndarray | None = None,
) -> list[LoopMargins]:
    """Margins of each loop broken at the plant input, the others closed.

    Parameters
    ----------
    plant, controller : control.StateSpace
        u = -K y; the plant strictly proper.
    omega : ndarray
        Grid on which crossings are searched.
    controller_response : ndarray, optional
        K(jw) on ``omega``, to reuse across many plants.

    Raises
    ------
    SynthesisError
        If the closed loop is unstable (margins would be meaningless).
    """
    poles = closed_loop_poles(plant, controller)
    if poles.size and np.max(poles.real) >= 0:
        raise UnstableLoopError(
            f"closed loop unstable (pole at {poles[np.argmax(poles.real)]:.3g})"
        )
    if controller_response is None:
        controller_response = state_space_response(controller, omega)
    ratios = return_ratios(state_space_response(plant, omega), controller_response)

    def channel_evaluator(i: int):
        def evaluate(w: float) -> complex:
            at = np.array([w])
            single = return_ratios(
                state_space_response(plant, at), state_space_response(controller, at)
            )
            return complex(single[0, i])

        return evaluate

    return [
        margins_from_response(channel_evaluator(i), omega, ratios[:, i])
        for i in range(plant.ninputs)
    ]


def disk_margins(
    plant: control.StateSpace, controller: control.StateSpace, omega: np.ndarray
) -> tuple[float, float, float]:
    """Balanced disk margin of the MIMO input loop: (alpha, gain margin dB, phase margin deg)."""
    loop = controller * plant  # input-side loop transfer, u = -K y
    alpha, gain_db, phase_deg = control.disk_margins(loop, omega, skew=0.0)  # dB and deg already
    return float(alpha), float(gain_db), float(phase_deg)
