"""Loop-at-a-time and disk margins of the attitude loop.

The loop is broken at one plant input at a time, the other two closed: the
return ratio L_i(s) from plant input i back to controller output i (negative
feedback, u = -K y). Its margins are read off a dense frequency response
(``MARGIN_GRID``, 1e-4 .. 1e2 rad/s, 0.8 % steps), every crossing bracketed
by two grid points and refined to 1e-12 in log w by Chandrupatla's method,
all brackets of all channels at once:

- gain margin: at every crossing of the negative real axis, the distance in dB
  from |L_i| to 1; the smaller of the upper (|L| < 1) and lower (|L| > 1, an
  integrating loop is conditionally stable) margins;
- phase margin: the smallest at any gain crossover |L_i| = 1;
- delay margin: phase margin over its crossover frequency, smallest over crossovers.

The return ratios are formed from the plant's and controller's 3 x 3
frequency responses (:class:`FrequencyResponse`: one block-diagonal Schur
decomposition per system, then O(n) work per frequency instead of a dense
O(n^3) solve), the controller's computed once for many plants
(:class:`LoopAtATime`), so thousands of sampled plants take seconds. Disk
margins (balanced, skew 0) of the full MIMO loop come from ``control.disk_margins``.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import control
import numpy as np

from casadi_debris.errors import SynthesisError, UnstableLoopError
from casadi_debris.robust.plant import FrequencyResponse, state_space_response

CHANNELS = ("x", "y", "z")
MARGIN_GRID = np.logspace(-4, 2, 1800)
REFINE_DB = 3.0
ROOT_XTOL = 1e-12  # absolute tolerance of the refined crossings, in log(w / (rad/s))


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


def return_ratios(plant_response: np.ndarray, controller_response: np.ndarray) -> np.ndarray:
    """L_i(jw) of every channel from the plant and controller responses, shape (n_omega, n).

    Loop broken at plant input i, the others closed, u = -K y: with M = K G and
    E = I - e_i e_i^T, L_i = e_i^T (I + M E)^-1 M e_i. Eliminating the closed
    channels r (a Schur complement) gives L_i = M_ii - M_ir (I + M_rr)^-1 M_ri,
    written out for three channels (all at once) and solved for others.
    """
    loop = controller_response @ plant_response
    n = loop.shape[1]
    if n == 3:
        i, j, k = np.arange(3), np.array([1, 0, 0]), np.array([2, 2, 1])
        m_jj, m_kk = 1.0 + loop[:, j, j], 1.0 + loop[:, k, k]
        m_jk, m_kj, m_ji, m_ki = loop[:, j, k], loop[:, k, j], loop[:, j, i], loop[:, k, i]
        determinant = m_jj * m_kk - m_jk * m_kj
        x_j = (m_kk * m_ji - m_jk * m_ki) / determinant
        x_k = (m_jj * m_ki - m_kj * m_ji) / determinant
        return loop[:, i, i] - loop[:, i, j] * x_j - loop[:, i, k] * x_k
    ratios = np.empty(loop.shape[:2], dtype=complex)
    for m in range(n):
        rest = [j for j in range(n) if j != m]
        closed = np.eye(n - 1) + loop[:, rest][:, :, rest]
        x = np.linalg.solve(closed, loop[:, rest, m][:, :, None])
        ratios[:, m] = loop[:, m, m] - (loop[:, [m], rest][:, None, :] @ x)[:, 0, 0]
    return ratios


def _crossings(values: np.ndarray) -> np.ndarray:
    """Indices k where values changes sign between k and k + 1."""
    return np.flatnonzero(np.sign(values[:-1]) * np.sign(values[1:]) < 0)


def _bracketed_roots(
    function: Callable[[np.ndarray, np.ndarray], np.ndarray],
    low: np.ndarray,
    high: np.ndarray,
    f_low: np.ndarray,
    f_high: np.ndarray,
) -> np.ndarray:
    """Roots of ``function`` in the brackets [low, high], all at once (Chandrupatla's method).

    Chandrupatla (1997), Adv. Eng. Software 28(3) 145-149: inverse quadratic
    interpolation where it is safe, bisection otherwise, like Brent's method;
    vectorised over the brackets so that each iteration is one batched call.

    Parameters
    ----------
    function : callable
        ``function(x, which)`` -> values at ``x`` for the brackets ``which`` (indices).
    low, high : ndarray, shape (m,)
        Brackets, ``f_low`` and ``f_high`` of opposite signs.

    Returns
    -------
    ndarray, shape (m,)
        Roots, each within 2 ``ROOT_XTOL`` (plus rounding) of a sign change.
    """
    roots = np.empty(len(low))
    which = np.arange(len(low))
    a, fa, b, fb = high, f_high, low, f_low
    c, fc = a, fa
    best = b  # replaced in the first iteration
    # The first step is the secant (regula falsi) point: the grid brackets are narrow.
    step = np.clip(f_high / (f_high - f_low), 0.01, 0.99)
    with np.errstate(divide="ignore", invalid="ignore"):
        for _ in range(200):
            x = a + step * (b - a)
            fx = function(x, which)
            same = np.sign(fx) == np.sign(fa)
            c, fc = np.where(same, a, b), np.where(same, fa, fb)
            b, fb = np.where(same, b, a), np.where(same, fb, fa)
            a, fa = x, fx
            a_best = np.abs(fa) < np.abs(fb)
            best, f_best = np.where(a_best, a, b), np.where(a_best, fa, fb)
            limit = (4 * np.finfo(float).eps * np.abs(best) + ROOT_XTOL) / np.abs(b - a)
            done = (limit > 0.5) | (f_best == 0)
            roots[which[done]] = best[done]
            if done.all():
                return roots
            keep = ~done
            which, a, fa, b, fb, c, fc = (v[keep] for v in (which, a, fa, b, fb, c, fc))
            best, limit = best[keep], limit[keep]
            xi, phi = (a - b) / (c - b), (fa - fb) / (fc - fb)
            interpolate = (phi**2 < xi) & ((1 - phi) ** 2 < 1 - xi)
            quadratic = fa / (fb - fa) * fc / (fb - fc) + (c - a) / (b - a) * fa / (fc - fa) * (
                fb / (fc - fb)
            )
            step = np.clip(np.where(interpolate, quadratic, 0.5), limit, 1 - limit)
    roots[which] = best  # not reached: the bracket at least halves every few steps
    return roots


def _margins(
    evaluate: Callable[[np.ndarray], np.ndarray], omega: np.ndarray, responses: np.ndarray
) -> list[LoopMargins]:
    """Margins of several SISO return ratios given on a grid and as a function for refinement.

    Every crossing is first estimated by interpolation on the grid; those that
    can decide a margin (gain margins within ``REFINE_DB`` dB of the smallest
    estimate of their kind, every gain crossover) are refined together.

    Parameters
    ----------
    evaluate : callable
        w [rad/s], shape (k,) -> L(jw) of every loop, shape (k, n_loops).
    omega : ndarray, shape (n_omega,)
    responses : ndarray, shape (n_omega, n_loops)
    """
    # Brackets [omega[k], omega[k + 1]] as (loop, k, kind, sign): kind 0 for Im L = 0, an upper
    # (sign +1) or lower (-1) gain margin; kind 1 for |L| = 1, a gain crossover.
    brackets = []
    for i in range(responses.shape[1]):
        response = responses[:, i]
        ks = _crossings(response.imag)
        fraction = response.imag[ks] / (response.imag[ks] - response.imag[ks + 1])
        estimate = response.real[ks] + fraction * (response.real[ks + 1] - response.real[ks])
        on_axis = estimate < 0  # crossings of the negative real axis -> gain margins
        ks, db = ks[on_axis], -20 * np.log10(np.abs(estimate[on_axis]))
        for side in (1, -1):
            candidate = side * db > 0
            if candidate.any():
                best = np.min(side * db[candidate])
                refine = candidate & (side * db <= best + REFINE_DB)
                brackets += [(i, k, 0, side) for k in ks[refine]]
        brackets += [(i, k, 1, 0) for k in _crossings(np.abs(response) - 1.0)]
    loop, low, kind, sign = np.array(brackets, dtype=int).reshape(-1, 4).T

    def condition(values: np.ndarray, which: np.ndarray) -> np.ndarray:
        return np.where(kind[which] == 0, values.imag, np.abs(values) - 1.0)

    frequencies = np.empty(0)
    points = np.empty(0, dtype=complex)
    if brackets:
        log_omega = np.log(omega)
        every = np.arange(len(low))
        roots = _bracketed_roots(
            lambda x, which: condition(evaluate(np.exp(x))[np.arange(len(x)), loop[which]], which),
            log_omega[low],
            log_omega[low + 1],
            condition(responses[low, loop], every),
            condition(responses[low + 1, loop], every),
        )
        frequencies = np.exp(roots)
        points = evaluate(frequencies)[every, loop]
    return [
        _assemble(
            points[(loop == i) & (kind == 0) & (sign == 1)],
            points[(loop == i) & (kind == 0) & (sign == -1)],
            points[(loop == i) & (kind == 1)],
            frequencies[(loop == i) & (kind == 1)],
        )
        for i in range(responses.shape[1])
    ]


def _assemble(
    upper_points: np.ndarray,
    lower_points: np.ndarray,
    crossover_points: np.ndarray,
    crossover_rad_s: np.ndarray,
) -> LoopMargins:
    """LoopMargins from L at refined axis crossings (estimated |L| < 1, > 1) and crossovers."""

    def gain_db(points: np.ndarray) -> float:
        on_axis = points[points.real < 0]
        return float(np.min(np.abs(20 * np.log10(np.abs(on_axis.real))), initial=math.inf))

    upper_db, lower_db = gain_db(upper_points), gain_db(lower_points)
    if not len(crossover_points):
        return LoopMargins(
            min(upper_db, lower_db), upper_db, lower_db, math.inf, math.inf, math.nan
        )
    phase = 180.0 + np.degrees(np.angle(crossover_points))
    phase = np.where(phase > 180.0, phase - 360.0, phase)
    delays = np.where(phase > 0, np.radians(phase) / crossover_rad_s, 0.0)
    worst = int(np.argmin(phase))
    return LoopMargins(
        gain_margin_db=min(upper_db, lower_db),
        upper_gain_margin_db=upper_db,
        lower_gain_margin_db=lower_db,
        phase_margin_deg=float(phase[worst]),
        delay_margin_s=float(np.min(delays)),
        crossover_rad_s=float(crossover_rad_s[worst]),
    )


def margins_from_response(
    evaluate: Callable[[np.ndarray], np.ndarray], omega: np.ndarray, response: np.ndarray
) -> LoopMargins:
    """Margins of a SISO return ratio given on a grid and as a function for refinement.

    Parameters
    ----------
    evaluate : callable
        w [rad/s], shape (k,) -> L(jw), shape (k,), complex.
    omega, response : ndarray, shape (n_omega,)
        The grid and L on it.
    """
    return _margins(lambda w: evaluate(w)[:, None], omega, response[:, None])[0]


def loop_margins(loop: control.StateSpace, omega: np.ndarray = MARGIN_GRID) -> LoopMargins:
    """Gain, phase and delay margins of a SISO return ratio (negative feedback)."""

    def evaluate(w: np.ndarray) -> np.ndarray:
        return state_space_response(loop, w)[:, 0, 0]

    return margins_from_response(evaluate, omega, evaluate(omega))


class LoopAtATime:
    """Loop-at-a-time margins of many plants around one controller.

    The controller's decomposition and its response on the grid are computed
    once; each plant then costs one :class:`FrequencyResponse` on the grid and
    a few batched evaluations to refine its crossings.

    Parameters
    ----------
    controller : control.StateSpace
        u = -K y.
    omega : ndarray
        Grid on which crossings are searched [rad/s].
    """

    def __init__(
        self,
        controller: control.StateSpace,
        omega: np.ndarray = MARGIN_GRID,
        sample_time_s: float | None = None,
    ):
        self.controller = controller
        self.sample_time_s = sample_time_s
        self.omega = np.asarray(omega, dtype=float)
        if sample_time_s is not None:  # up to the Nyquist frequency
            self.omega = self.omega[self.omega < math.pi / sample_time_s]
        self._controller = FrequencyResponse(controller, sample_time_s)
        self._on_grid = self._controller(self.omega)

    def __call__(self, plant: control.StateSpace) -> list[LoopMargins]:
        """Margins of each loop of ``plant`` (strictly proper) broken at its input.

        Raises
        ------
        UnstableLoopError
            If the closed loop is unstable (margins would be meaningless).
        """
        poles = closed_loop_poles(plant, self.controller)
        if self.sample_time_s is None:
            worst = int(np.argmax(poles.real)) if poles.size else -1
            unstable = poles.size and poles.real[worst] >= 0
        else:
            worst = int(np.argmax(np.abs(poles))) if poles.size else -1
            unstable = poles.size and abs(poles[worst]) >= 1.0
        if unstable:
            raise UnstableLoopError(f"closed loop unstable (pole at {poles[worst]:.3g})")
        response = FrequencyResponse(plant, self.sample_time_s)

        def evaluate(w: np.ndarray) -> np.ndarray:
            return return_ratios(response(w), self._controller(w))

        return _margins(evaluate, self.omega, return_ratios(response(self.omega), self._on_grid))


def loop_at_a_time(
    plant: control.StateSpace, controller: control.StateSpace, omega: np.ndarray = MARGIN_GRID
) -> list[LoopMargins]:
    """Margins of each loop broken at the plant input, the others closed.

    Parameters
    ----------
    plant, controller : control.StateSpace
        u = -K y; the plant strictly proper.
    omega : ndarray
        Grid on which crossings are searched. For many plants around one
        controller, use :class:`LoopAtATime`.

    Raises
    ------
    SynthesisError
        If the closed loop is unstable (margins would be meaningless).
    """
    return LoopAtATime(controller, omega)(plant)


def sampled_loop_at_a_time(
    plant: control.StateSpace,
    controller: control.StateSpace,
    period_s: float,
    omega: np.ndarray = MARGIN_GRID,
) -> list[LoopMargins]:
    """Margins of the sampled-data loop: plant and controller held and sampled every ``period_s``.

    Both are discretised with a zero-order hold (the closed loop's own
    discretisation of the controller; the plant seen from the held input to the
    sampled output) and the discrete loop is broken at each plant input, the others
    closed, on the grid below the Nyquist frequency pi / period_s: the margins of
    the loop the simulation flies, hold and sampling included.

    Parameters
    ----------
    plant, controller : control.StateSpace
        Continuous, u = -K y; the plant strictly proper.
    period_s : float
        Sample period [s].
    omega : ndarray
        Grid on which crossings are searched [rad/s] (cut at the Nyquist frequency).

    Raises
    ------
    SynthesisError
        If the sampled closed loop is unstable, or the period is not positive.
    """
    if not period_s > 0:
        raise SynthesisError(f"period_s: must be positive, got {period_s}")
    sampled_plant = control.sample_system(plant, period_s, method="zoh")
    sampled_controller = control.sample_system(controller, period_s, method="zoh")
    return LoopAtATime(sampled_controller, omega, period_s)(sampled_plant)


def disk_margins(
    plant: control.StateSpace, controller: control.StateSpace, omega: np.ndarray
) -> tuple[float, float, float]:
    """Balanced disk margin of the MIMO input loop: (alpha, gain margin dB, phase margin deg)."""
    loop = controller * plant  # input-side loop transfer, u = -K y
    alpha, gain_db, phase_deg = control.disk_margins(loop, omega, skew=0.0)  # dB and deg already
    return float(alpha), float(gain_db), float(phase_deg)
