"""The best performance level a design can guarantee, searched over the error scaling Ve.

:func:`search_design` designs first at the scalings the problem's requirements
give (:func:`~casadi_debris.robust.requirements.derived_scalings`). When the
reduced controller's mu is at most 1 there, it halves Ve while mu stays <= 1
(a tighter design tracks and rejects better); when mu exceeds 1, nothing is
guaranteed, so it doubles Ve until mu <= 1. It then bisects (in log Ve) between
the last failure and the first success and keeps the design with the smallest
guaranteed pointing. The uncertainty fit is made once and shared by every
attempt. mu is an upper bound from a D-K iteration that may stop in a local
optimum, so "fails" means "this D-K did not reach mu <= 1".
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

from casadi_debris.config import Problem
from casadi_debris.geometry import build_geometry
from casadi_debris.records import Record
from casadi_debris.robust.plant import performance_weights
from casadi_debris.robust.requirements import (
    BodyWeights,
    DerivedScalings,
    WeightsChoice,
    body_weights,
    derived_scalings,
    is_papers_body,
)
from casadi_debris.robust.synthesis._design import (
    ControllerDesign,
    SynthesisSettings,
    UncertaintyFit,
    design_controller,
    fit_uncertainty,
)
from casadi_debris.robust.synthesis._musyn import Iteration

LOGGER = logging.getLogger(__name__)

MAX_VE_RATIO = 64.0
MIN_VE_RATIO = 0.25
"""Ve searched within these multiples of the one whose guarantee is the requirement: at
most 4 times tighter (the paper's hand-tuned roll Ve is 0.24 times the requirement's
level on its plant), at most 64 times looser."""
REFINEMENTS = 3
"""Bisections (in log Ve) between the last failure and the first success: within 2^(1/8)."""


@dataclass(frozen=True)
class DesignAttempt(Record):
    """One D-K design at one performance level.

    Attributes
    ----------
    ve_ratio : float
        Ve over the Ve of the pointing requirement.
    mu_peak, mu_peak_reduced : float
        Peak mu of the full and the reduced controller.
    guaranteed_pointing_arcsec : tuple of float or None
        Per axis, from the reduced controller's mu (None: mu > 1, nothing guaranteed).
    iterations : int
        D-K steps after the first H-infinity design.
    time_s : float
    """

    ve_ratio: float
    mu_peak: float
    mu_peak_reduced: float
    guaranteed_pointing_arcsec: tuple[float, ...] | None
    iterations: int
    time_s: float

    @property
    def guarantees(self) -> bool:
        """Whether the reduced controller has mu <= 1."""
        return self.guaranteed_pointing_arcsec is not None


@dataclass(frozen=True, eq=False)
class DesignSearch:
    """The design kept and how it was found.

    Attributes
    ----------
    design : ControllerDesign
        The attempt with the smallest guaranteed pointing, or the one with the
        lowest mu when no attempt guarantees anything.
    scalings : DerivedScalings
        Its Ve, Vu and Vd.
    attempts : list of DesignAttempt
        In the order tried.
    body : BodyWeights or None
        The dynamic weights We and Wu and the body figures they come from (None: the
        problem's ``[weights]``).
    """

    design: ControllerDesign
    scalings: DerivedScalings
    attempts: list[DesignAttempt]
    body: BodyWeights | None = None

    @property
    def chosen(self) -> DesignAttempt:
        """The attempt of :attr:`design`."""
        return next(a for a in self.attempts if a.ve_ratio == self.scalings.ve_ratio)


Announce = Callable[[str], None]


def search_design(
    problem: Problem,
    settings: SynthesisSettings | None = None,
    announce: Announce | None = None,
    *,
    min_ve_ratio: float = MIN_VE_RATIO,
    max_ve_ratio: float = MAX_VE_RATIO,
    refinements: int = REFINEMENTS,
    weights: WeightsChoice = "auto",
) -> DesignSearch:
    """The design with the best guaranteed pointing (see the module's note).

    Parameters
    ----------
    problem : Problem
    settings : SynthesisSettings, optional
    announce : callable, optional
        Called with one line per stage and per attempt.
    min_ve_ratio, max_ve_ratio : float
        Smallest and largest Ve tried, relative to the requirement's.
    refinements : int
        Bisections between the last failure and the first success.
    weights : {"auto", "derived", "problem"}
        Where We and Wu come from (:func:`~casadi_debris.robust.requirements.body_weights`).

    Returns
    -------
    DesignSearch
    """
    settings = settings or SynthesisSettings()
    say = announce or LOGGER.info
    say("sampling the uncertainty set and fitting its weight")
    fit = fit_uncertainty(problem, settings)
    geometry = build_geometry(problem)
    body = body_weights(problem, weights, geometry)
    base = body.apply(performance_weights(problem))
    warning = body.inherited_warning(is_papers_body(problem))
    if warning:
        LOGGER.warning(warning)
    say(
        f"weights: bandwidth {body.bandwidth_rad_s:.4g} rad/s ({body.figures.bandwidth_from}), "
        f"roll-off {body.rolloff_rad_s:.4g} rad/s ({body.figures.rolloff_from})"
    )
    found: dict[float, tuple[ControllerDesign, DerivedScalings, DesignAttempt]] = {}

    def attempt(ve_ratio: float) -> DesignAttempt:
        scalings = derived_scalings(problem, ve_ratio, geometry, base)
        say(f"D-K at Ve = {scalings.error_deg[0]:.4g} deg ({ve_ratio:.3g} x the requirement's)")
        design, outcome = _design_at(problem, settings, fit, scalings, say)
        found[ve_ratio] = (design, scalings, outcome)
        return outcome

    failing, passing = _bracket(attempt, min_ve_ratio, max_ve_ratio)
    if passing is not None and failing is not None:
        for _ in range(refinements):
            middle = math.sqrt(failing * passing)
            if attempt(middle).guarantees:
                passing = middle
            else:
                failing = middle
    attempts = [entry[2] for entry in found.values()]
    design, scalings, _ = found[_best(attempts).ve_ratio]
    return DesignSearch(design, scalings, attempts, body)


def _bracket(
    attempt: Callable[[float], DesignAttempt], min_ve_ratio: float, max_ve_ratio: float
) -> tuple[float | None, float | None]:
    """(a Ve ratio that failed, the best neighbour that guaranteed), by halving or doubling
    from 1; either is None when the search hit its end."""
    if attempt(1.0).guarantees:
        passing, ratio = 1.0, 0.5
        while ratio >= min_ve_ratio:
            if not attempt(ratio).guarantees:
                return ratio, passing
            passing, ratio = ratio, 0.5 * ratio
        return None, passing
    failing, ratio = 1.0, 2.0
    while ratio <= max_ve_ratio:
        if attempt(ratio).guarantees:
            return failing, ratio
        failing, ratio = ratio, 2.0 * ratio
    return failing, None


def _best(attempts: list[DesignAttempt]) -> DesignAttempt:
    """The smallest worst-axis guaranteed pointing (the tighter Ve on a tie); without any,
    the lowest mu."""
    guaranteeing = [a for a in attempts if a.guaranteed_pointing_arcsec is not None]
    if guaranteeing:
        return min(
            guaranteeing,
            key=lambda a: (max(a.guaranteed_pointing_arcsec or (math.inf,)), a.ve_ratio),
        )
    return min(attempts, key=lambda a: a.mu_peak_reduced)


def _design_at(
    problem: Problem,
    settings: SynthesisSettings,
    fit: UncertaintyFit,
    scalings: DerivedScalings,
    say: Announce,
) -> tuple[ControllerDesign, DesignAttempt]:
    """One D-K design at ``scalings``, with its attempt record."""
    start = time.perf_counter()

    def progress(stage: str, iteration: Iteration | None) -> None:
        if iteration is not None:
            say(f"  step {iteration.index}: mu {iteration.mu_peak:.4f} ({iteration.time_s:.1f} s)")

    design = design_controller(
        problem,
        settings,
        progress,
        performance=scalings.performance_weights(problem),
        uncertainty=fit,
    )
    guaranteed = scalings.guaranteed_pointing_arcsec(design.mu_reduced.peak)
    outcome = DesignAttempt(
        ve_ratio=scalings.ve_ratio,
        mu_peak=design.musyn.mu_peak,
        mu_peak_reduced=design.mu_reduced.peak,
        guaranteed_pointing_arcsec=None if guaranteed is None else tuple(guaranteed.tolist()),
        iterations=len(design.musyn.iterations) - 1,
        time_s=time.perf_counter() - start,
    )
    verdict = (
        "no guarantee"
        if guaranteed is None
        else f"guaranteed pointing {max(guaranteed):.1f} arcsec"
    )
    say(f"  mu {outcome.mu_peak:.4f} (reduced {outcome.mu_peak_reduced:.4f}): {verdict}")
    return design, outcome
