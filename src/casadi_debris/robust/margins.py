"""Loop-at-a-time and disk margins of the attitude loop.

The loop is broken at one plant input at a time, the other two closed: the
return ratio L_i(s) from plant input i back to controller output i (negative
feedback, u = -K y). Its margins are read off a dense frequency response
(``MARGIN_GRID``, 1e-5 .. 1e3 rad/s), crossings refined by Brent's method:

- gain margin: at every crossing of the negative real axis, the distance in dB
  from |L_i| to 1; the smaller of the upper (|L| < 1) and lower (|L| > 1, an
  integrating loop is conditionally stable) margins;
- phase margin: the smallest at any gain crossover |L_i| = 1;
- delay margin: phase margin over its crossover frequency, smallest over crossovers.

The return ratios are formed from the state-space matrices directly and
evaluated through an eigendecomposition, so thousands of sampled plants take
seconds. Disk margins (balanced, skew 0) of the full MIMO loop come from
``control.disk_margins``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import control
import numpy as np
from scipy.optimize import brentq

from casadi_debris.errors import SynthesisError

CHANNELS = ("x", "y", "z")
MARGIN_GRID = np.logspace(-5, 3, 3200)


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


def _siso_evaluator(loop: control.StateSpace):
    """w -> L(jw) through an eigendecomposition of A (direct solves if ill-conditioned)."""
    a, b, c, d = loop.A, loop.B, loop.C, loop.D
    if a.shape[0] == 0:
        return lambda omega: np.full(np.shape(omega), complex(d[0, 0]))
    eigenvalues, vectors = np.linalg.eig(a)
    if np.linalg.cond(vectors) < 1e10:
        weights = (c @ vectors).ravel() * np.linalg.solve(vectors, b).ravel()

        def evaluate(omega):
            w = np.atleast_1d(np.asarray(omega, dtype=float))
            return (weights / (1j * w[:, None] - eigenvalues)).sum(axis=1) + d[0, 0]

        return evaluate
    eye = np.eye(a.shape[0])

    def evaluate_directly(omega):
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        return np.array([(c @ np.linalg.solve(1j * x * eye - a, b))[0, 0] + d[0, 0] for x in w])

    return evaluate_directly


def _crossings(values: np.ndarray) -> np.ndarray:
    """Indices k where values changes sign between k and k + 1."""
    return np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)


def _refine(function, low: float, high: float) -> float:
    """Root of a scalar function of log frequency bracketed by [low, high] (rad/s)."""
    return math.exp(
        brentq(lambda x: function(math.exp(x)), math.log(low), math.log(high), xtol=1e-13)
    )


def loop_margins(loop: control.StateSpace, omega: np.ndarray = MARGIN_GRID) -> LoopMargins:
    """Gain, phase and delay margins of a SISO return ratio (negative feedback).

    Crossings are located on the grid ``omega`` and refined by Brent's method.
    """
    evaluate = _siso_evaluator(loop)
    response = evaluate(omega)
    upper, lower = [], []
    # Crossings of the negative real axis: Im L changes sign with Re L < 0.
    for k in _crossings(response.imag):
        w = _refine(lambda x: float(evaluate(x)[0].imag), omega[k], omega[k + 1])
        point = evaluate(w)[0]
        if point.real < 0:
            margin_db = -20 * math.log10(abs(point.real))
            (upper if margin_db > 0 else lower).append(abs(margin_db))
    phases, frequencies = [], []
    for k in _crossings(np.abs(response) - 1.0):
        w = _refine(lambda x: float(abs(evaluate(x)[0])) - 1.0, omega[k], omega[k + 1])
        frequencies.append(w)
        phases.append(180.0 + math.degrees(np.angle(evaluate(w)[0])))
    upper_db, lower_db = min(upper, default=math.inf), min(lower, default=math.inf)
    if not phases:
        return LoopMargins(
            min(upper_db, lower_db), upper_db, lower_db, math.inf, math.inf, math.nan
        )
    phases_arr = np.array(phases)
    phases_arr = np.where(phases_arr > 180.0, phases_arr - 360.0, phases_arr)
    delays = np.where(phases_arr > 0, np.radians(phases_arr) / np.array(frequencies), 0.0)
    worst = int(np.argmin(phases_arr))
    return LoopMargins(
        gain_margin_db=min(upper_db, lower_db),
        upper_gain_margin_db=upper_db,
        lower_gain_margin_db=lower_db,
        phase_margin_deg=float(phases_arr[worst]),
        delay_margin_s=float(np.min(delays)),
        crossover_rad_s=float(frequencies[worst]),
    )


def loop_at_a_time(plant: control.StateSpace, controller: control.StateSpace) -> list[LoopMargins]:
    """Margins of each loop broken at the plant input, the others closed.

    Raises
    ------
    SynthesisError
        If the closed loop is unstable (margins would be meaningless).
    """
    poles = closed_loop_poles(plant, controller)
    if poles.size and np.max(poles.real) >= 0:
        raise SynthesisError(f"closed loop unstable (pole at {poles[np.argmax(poles.real)]:.3g})")
    return [loop_margins(return_ratio(plant, controller, i)) for i in range(plant.ninputs)]


def disk_margins(
    plant: control.StateSpace, controller: control.StateSpace, omega: np.ndarray
) -> tuple[float, float, float]:
    """Balanced disk margin of the MIMO input loop: (alpha, gain margin dB, phase margin deg)."""
    loop = controller * plant  # input-side loop transfer, u = -K y
    alpha, gain, phase = control.disk_margins(loop, omega, skew=0.0)
    gain_db = 20 * math.log10(gain) if np.isfinite(gain) and gain > 0 else math.inf
    return float(alpha), gain_db, float(phase)
