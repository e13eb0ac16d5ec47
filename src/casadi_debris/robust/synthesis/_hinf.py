"""H-infinity controller synthesis by gamma bisection over fixed-gamma Riccati solves.

``control.hinfsyn`` starts SLICOT's own gamma search at 1e100 and can take
seconds, or fail, on D-scaled plants; a fixed-gamma solve (SB10AD, job 4)
takes milliseconds. Whether such a solve succeeds depends on how the
realisation is scaled: a D-scaled plant's raw realisation (cond(A) ~ 1e24)
fails everywhere, while a minimal and A-balanced one of a plant with a
near-integrator (the distillation column's performance weight, pole at
-1e-6 rad/s) returns controllers whose loop is 40 times worse than the
gamma they were built for. So each gamma is tried on several realisations of
the same transfer function (system-balanced then in real Schur form; minimal
and system-balanced; as given; minimal in Schur form), the one that last
worked first, and a solve only counts when the controller it returns, closed
around the plant *as given*, is stable with an H-infinity norm at most
``(1 + NORM_SLACK)`` gamma. The controller returned is the smallest-norm
verified controller met on the way, and its norm is the closed loop's,
recomputed, never the gamma it was built for.
"""

from __future__ import annotations

import logging
from collections.abc import Callable
from dataclasses import dataclass

import control
import numpy as np
import scipy.linalg
import slycot
from slycot.exceptions import SlycotError

from casadi_debris.errors import SynthesisError

MAX_BISECTIONS = 60
GAMMA_CEILING = 1e8
# A central controller built for gamma has a loop norm below gamma in exact
# arithmetic; a few per cent above is rounding near the optimum, far above is a
# failed solve that did not report itself.
NORM_SLACK = 0.05
TIGHT = 1e-3
NORM_TOLERANCE = 1e-5  # relative accuracy of the verifying H-infinity norms (AB13DD)

_log = logging.getLogger(__name__)


@dataclass(frozen=True, eq=False)
class HinfResult:
    """Controller and closed loop at the best gamma found.

    Attributes
    ----------
    controller : control.StateSpace
        From the measurements to the controls.
    closed_loop : control.StateSpace
        From the exogenous inputs to the performance outputs, the plant as given
        closed by ``controller``.
    gamma : float
        Its H-infinity norm (achieved, recomputed on the plant as given).
    realisation : str
        Realisation of the plant the controller was computed on ("schur",
        "minimal", "as given" or "minimal schur").
    """

    controller: control.StateSpace
    closed_loop: control.StateSpace
    gamma: float
    realisation: str = "schur"


def balanced(system: control.StateSpace) -> control.StateSpace:
    """Diagonal similarity balancing of A (same states, same transfer function).

    Parameters
    ----------
    system : control.StateSpace

    Returns
    -------
    control.StateSpace
        ``T^-1 A T, T^-1 B, C T, D`` with ``T`` diagonal (powers of 2, exact).
    """
    if system.nstates == 0:
        return system
    _, (scale, _) = scipy.linalg.matrix_balance(system.A, permute=False, separate=True)
    return control.ss(
        system.A * (1.0 / scale)[:, None] * scale[None, :],
        system.B / scale[:, None],
        system.C * scale[None, :],
        system.D,
    )


def well_conditioned(system: control.StateSpace) -> control.StateSpace:
    """Minimal, balanced realisation of a system (same transfer function).

    D-scaled plants carry poles from 1e-5 to 1e3 rad/s; their raw realisation
    (cond(A) ~ 1e24) makes every fixed-gamma Riccati solve fail, while the
    minimal realisation of SLICOT TB01PD followed by diagonal balancing solves.

    Parameters
    ----------
    system : control.StateSpace

    Returns
    -------
    control.StateSpace
    """
    return balanced(control.minreal(system, verbose=False))


def system_balanced(system: control.StateSpace) -> control.StateSpace:
    """Diagonal balancing of the whole system matrix [[A, B], [C, 0]] (SLICOT TB01ID).

    Balancing A alone leaves a (block) diagonal A as it is, however badly its
    states are scaled against B and C; the system matrix pins them down.

    Parameters
    ----------
    system : control.StateSpace

    Returns
    -------
    control.StateSpace
        Same transfer function, states scaled by powers of 2.
    """
    if system.nstates == 0 or system.ninputs == 0 or system.noutputs == 0:
        return system
    _, a, b, c, _ = slycot.tb01id(
        system.nstates,
        system.ninputs,
        system.noutputs,
        0.0,
        np.array(system.A, dtype=float),
        np.array(system.B, dtype=float),
        np.array(system.C, dtype=float),
        job="A",
    )
    return control.ss(a, b, c, system.D)


def schur(system: control.StateSpace) -> control.StateSpace:
    """Real Schur realisation: A upper quasi-triangular by an orthogonal change of state.

    Orthogonal, so no entry grows; the modes come out ordered and decoupled
    below the diagonal, which is what lets SB10AD solve plants whose realisation
    as composed (weights, D-scales) returns central controllers far from the gamma
    they were built for.

    Parameters
    ----------
    system : control.StateSpace

    Returns
    -------
    control.StateSpace
    """
    if system.nstates == 0:
        return system
    triangular, basis = scipy.linalg.schur(system.A, output="real")
    return control.ss(triangular, basis.T @ system.B, system.C @ basis, system.D)


def _minimal(system: control.StateSpace) -> control.StateSpace:
    return system_balanced(control.minreal(system, verbose=False))


_REALISATIONS: dict[str, Callable[[control.StateSpace], control.StateSpace]] = {
    "schur": lambda system: schur(system_balanced(system)),
    "minimal": _minimal,
    "as given": lambda system: system,
    "minimal schur": lambda system: schur(_minimal(system)),
}


class _Solver:
    """Fixed-gamma solves of one plant over its realisations, verified on the plant as given."""

    def __init__(
        self,
        plant: control.StateSpace,
        n_measurements: int,
        n_controls: int,
        first: str | None = None,
    ) -> None:
        self.plant = plant
        self.n_measurements = n_measurements
        self.n_controls = n_controls
        self.order = list(_REALISATIONS)
        if first in self.order:
            self.order.remove(first)
            self.order.insert(0, first)
        self._built: dict[str, control.StateSpace | None] = {}

    def realisation(self, name: str) -> control.StateSpace | None:
        if name not in self._built:
            try:
                self._built[name] = _REALISATIONS[name](self.plant)
            except (ValueError, np.linalg.LinAlgError):
                self._built[name] = None
        return self._built[name]

    def verified(self, controller: control.StateSpace, name: str) -> HinfResult | None:
        """The controller closed around the plant as given, if stable with a finite norm."""
        closed = self.plant.lft(controller, self.n_controls, self.n_measurements)
        if closed.nstates and np.max(np.linalg.eigvals(closed.A).real) >= 0:
            return None
        norm = float(control.linfnorm(closed, tol=NORM_TOLERANCE)[0])
        if not np.isfinite(norm):
            return None
        return HinfResult(controller, closed, norm, name)

    def at(self, gamma: float) -> tuple[HinfResult | None, HinfResult | None]:
        """(a verified controller of norm <= (1 + NORM_SLACK) gamma or None, the best
        verified controller met, whatever its norm, or None).

        The realisations are tried until one gives a controller of norm at most
        (1 + TIGHT) gamma, as exact arithmetic would; otherwise the best within
        the slack counts. The one that worked moves to the front of the order: most
        gammas of a bisection succeed or fail on the same realisation.
        """
        best = None
        for name in list(self.order):
            system = self.realisation(name)
            if system is None:
                continue
            controller = _central_controller(system, self.n_measurements, self.n_controls, gamma)
            result = None if controller is None else self.verified(controller, name)
            if result is None:
                continue
            if best is None or result.gamma < best.gamma:
                best = result
            if result.gamma <= (1.0 + TIGHT) * gamma:
                break
        if best is None or best.gamma > (1.0 + NORM_SLACK) * gamma:
            return None, best
        self.order.remove(best.realisation)
        self.order.insert(0, best.realisation)
        return best, best


def _central_controller(
    plant: control.StateSpace, n_measurements: int, n_controls: int, gamma: float
) -> control.StateSpace | None:
    """SB10AD's central controller at a fixed gamma, or None if its Riccati solve fails."""
    n, m, p = plant.nstates, plant.ninputs, plant.noutputs
    try:
        out = slycot.sb10ad(
            n, m, p, n_controls, n_measurements, gamma, plant.A, plant.B, plant.C, plant.D, job=4
        )
    except (SlycotError, ValueError, np.linalg.LinAlgError):
        return None
    controller = control.ss(*out[1:5])
    if not all(np.all(np.isfinite(x)) for x in out[1:5]):
        return None
    return controller


def hinf_synthesis(
    plant: control.StateSpace,
    n_measurements: int,
    n_controls: int,
    *,
    gamma_start: float = 1.0,
    tolerance: float = 0.01,
    first_realisation: str | None = None,
) -> HinfResult:
    """Smallest-gamma H-infinity controller, to a relative ``tolerance``.

    Parameters
    ----------
    plant : control.StateSpace
        Generalised plant; the last ``n_measurements`` outputs and
        ``n_controls`` inputs are the controller's.
    n_measurements, n_controls : int
        Number of measured outputs and of control inputs.
    gamma_start : float
        First gamma tried; multiplied by 4 until feasible.
    tolerance : float
        Relative width of the final bisection interval.
    first_realisation : str, optional
        Realisation to try first ("schur", "minimal", "as given", "minimal schur"),
        e.g. the one that worked on the previous plant of a D-K iteration.

    Returns
    -------
    HinfResult
        The controller of smallest verified closed-loop norm.

    Raises
    ------
    SynthesisError
        No stabilising controller up to gamma 1e8 on any realisation.

    Examples
    --------
    >>> import control
    >>> plant = control.ss(control.augw(control.tf([1], [1, 1]), control.tf([1], [1, 0.1])))
    >>> result = hinf_synthesis(plant, 1, 1)
    >>> bool(result.gamma > 0)
    True
    """
    solver = _Solver(plant, n_measurements, n_controls, first_realisation)
    upper = gamma_start
    found, best = solver.at(upper)
    while found is None:
        upper *= 4.0
        if upper > GAMMA_CEILING:
            if best is not None:
                return best
            raise SynthesisError(
                f"no stabilising H-infinity controller up to gamma {GAMMA_CEILING:g} on any "
                f"realisation ({', '.join(_REALISATIONS)}): check stabilisability and "
                "detectability of the generalised plant, and that D12 and D21 have full rank"
            )
        found, met = solver.at(upper)
        if met is not None and (best is None or met.gamma < best.gamma):
            best = met
    if best is None or found.gamma < best.gamma:
        best = found
    upper = min(upper, best.gamma)
    lower = 0.0
    for _ in range(MAX_BISECTIONS):
        if upper - lower <= tolerance * upper:
            break
        gamma = 0.5 * (lower + upper)
        found, met = solver.at(gamma)
        if met is not None and met.gamma < best.gamma:
            best = met
        if found is None:
            lower = gamma
        else:
            upper = min(gamma, found.gamma)
    _log.debug("H-infinity: gamma %.6g on the %s realisation", best.gamma, best.realisation)
    return best
