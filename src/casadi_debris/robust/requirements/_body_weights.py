"""The dynamic weights We and Wu derived from the body, for a debris that is not the paper's.

The paper chose its closed-loop bandwidth (0.028 rad/s) and control roll-off
(3.75 rad/s) by hand for its 668 kg body; a problem that ``extends = "paper"``
inherits them. On another body they are wrong: on a 1,500 kg bus with a 12 m array
(pitch and yaw inertia above 6,000 kg m^2, first bending 1.2 rad/s) 0.028 rad/s asks
five times the torque the swarm has, and a roll-off at 3.75 rad/s sits above the
array's first mode. Here they follow from the body:

- Bandwidth. A loop of bandwidth w on inertia J answers an error e with a torque of
  about J w^2 e (its stiffness). The largest error it must answer without saturating
  is the slew error it is allowed, ``[requirements] slew_error_deg``, and the torque it
  may use is what the disturbance leaves of the authority, tau_i - A_i. So per axis
  ``w_i = sqrt((tau_i - A_i) / (J_i e_slew))``, and the design takes the smallest (one
  We for every axis), at most :data:`ROLLOFF_SEPARATION` below the roll-off. On the
  paper's body this gives 0.0167 rad/s (pitch), 0.6 times the paper's hand-tuned
  0.028 rad/s, which its design reached with the paper's smaller I_tot in mind.
- Roll-off. Below the lowest first bending frequency of the uncertainty set, by
  :data:`ROLLOFF_BELOW_MODE`: ``w_u = (1 - spread) min w_b1 / 1.2``, 3.73 rad/s for
  the paper (its 3.75). A rigid body has no mode: the roll-off is a tenth of the
  slower of the star tracker's bandwidth and the control loop's Nyquist frequency.
- epsilon and the high-frequency gain keep the problem's values (they shape, not size).

Which weights a design uses (:func:`body_weights`): a problem whose body is the
paper's keeps its ``[weights]`` (they were tuned for it). On any other body a weight
equal to the paper's is taken as inherited and derived here; a weight the problem
sets to another value is the problem's own and is kept.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from casadi_debris.config import Problem, load_problem
from casadi_debris.errors import SynthesisError
from casadi_debris.geometry import Geometry, build_geometry
from casadi_debris.records import Record
from casadi_debris.robust.plant import PerformanceWeights, dynamic_weights
from casadi_debris.robust.requirements._scalings import authority_per_axis_mNm
from casadi_debris.units import NM_PER_MNM

ROLLOFF_BELOW_MODE = 1.2
"""The roll-off sits this factor below the lowest first bending frequency (the paper:
3.75 rad/s against 4.48, the 5.6 rad/s mode 20 % low)."""
RIGID_ROLLOFF_FRACTION = 0.1
"""A rigid body's roll-off: this share of the slower of the star tracker and Nyquist."""
ROLLOFF_SEPARATION = 30.0
"""The bandwidth stays at least this factor below the roll-off (the paper's: 134)."""
BODY_TABLES = (
    "hub",
    "arrays",
    "cubesats",
    "cubesat_layout",
    "engine",
    "disturbance",
    "requirements",
    "uncertainty",
    "sensor",
)
"""The tables that make a body (and what it must do): the paper's weights were tuned for
the paper's values of these."""

WeightsChoice = Literal["auto", "derived", "problem"]
WEIGHTS_CHOICES: tuple[WeightsChoice, ...] = ("auto", "derived", "problem")
Origin = Literal["derived", "problem", "paper"]


@dataclass(frozen=True)
class BodySummary(Record):
    """The body figures the dynamic weights come from, and where each weight came from.

    Attributes
    ----------
    inertia_kgm2 : tuple of float
        Diagonal of the nominal total inertia.
    authority_mNm, disturbance_mNm : tuple of float
        Torque authority with zero net force (weaker sign) and disturbance amplitude, per axis.
    hold_bandwidth_rad_s : tuple of float
        sqrt((tau - A) / (J e_slew)) per axis.
    first_mode_rad_s : float or None
        Lowest first bending frequency of the uncertainty set (None: rigid).
    bandwidth_rad_s, rolloff_rad_s : float
        The We and Wu the design uses.
    derived_bandwidth_rad_s, derived_rolloff_rad_s : float
        What the rules give (equal to the above when derived).
    bandwidth_from, rolloff_from : str
        "derived", "problem" (the problem's own value) or "paper" (the paper's body and weights).
    paper_bandwidth_rad_s, paper_rolloff_rad_s : float
        The paper's hand-tuned values, for comparison.
    """

    inertia_kgm2: tuple[float, ...]
    authority_mNm: tuple[float, ...]
    disturbance_mNm: tuple[float, ...]
    hold_bandwidth_rad_s: tuple[float, ...]
    first_mode_rad_s: float | None
    bandwidth_rad_s: float
    rolloff_rad_s: float
    derived_bandwidth_rad_s: float
    derived_rolloff_rad_s: float
    bandwidth_from: str
    rolloff_from: str
    paper_bandwidth_rad_s: float
    paper_rolloff_rad_s: float


@dataclass(frozen=True)
class BodyWeights:
    """We and Wu for a design, with the figures they come from.

    Attributes
    ----------
    bandwidth_rad_s, epsilon, rolloff_rad_s, high_frequency_gain : float
        The parameters of We and Wu (see :func:`~casadi_debris.robust.plant.dynamic_weights`).
    figures : BodySummary
    """

    bandwidth_rad_s: float
    epsilon: float
    rolloff_rad_s: float
    high_frequency_gain: float
    figures: BodySummary

    def parameters(self) -> dict[str, float]:
        """The weights as a controller file records them."""
        return {
            "closed_loop_bandwidth_rad_s": self.bandwidth_rad_s,
            "epsilon": self.epsilon,
            "control_rolloff_rad_s": self.rolloff_rad_s,
            "control_rolloff_high_frequency_gain": self.high_frequency_gain,
        }

    def inherited_warning(self, papers_body: bool) -> str | None:
        """What using the paper's bandwidth or roll-off on another body costs (None: it does
        not)."""
        f = self.figures
        if papers_body:
            return None
        costs = []
        if f.bandwidth_from == "problem" and f.bandwidth_rad_s == f.paper_bandwidth_rad_s:
            ratio = (f.bandwidth_rad_s / f.derived_bandwidth_rad_s) ** 2
            costs.append(
                f"bandwidth {f.bandwidth_rad_s:.4g} rad/s asks {ratio:.3g} times the torque the "
                f"authority holds at the slew error (this body's: {f.derived_bandwidth_rad_s:.4g})"
            )
        if f.rolloff_from == "problem" and f.rolloff_rad_s == f.paper_rolloff_rad_s:
            if f.first_mode_rad_s is not None and f.rolloff_rad_s > f.first_mode_rad_s:
                where = f"above the first mode ({f.first_mode_rad_s:.3g} rad/s)"
            else:
                where = f"where this body's rule puts {f.derived_rolloff_rad_s:.4g}"
            costs.append(f"roll-off {f.rolloff_rad_s:.4g} rad/s, {where}")
        if not costs:
            return None
        return "using the paper's weights, tuned for another body: " + "; ".join(costs)

    def apply(self, weights: PerformanceWeights) -> PerformanceWeights:
        """``weights`` with these We and Wu."""
        error, effort = dynamic_weights(
            self.bandwidth_rad_s, self.epsilon, self.rolloff_rad_s, self.high_frequency_gain
        )
        return PerformanceWeights(
            error,
            effort,
            weights.error_scaling,
            weights.control_scaling,
            weights.disturbance_scaling,
            weights.reference_scaling,
            self.parameters(),
        )


def hold_bandwidth_rad_s(
    inertia_kgm2: np.ndarray, authority_Nm: np.ndarray, disturbance_Nm: np.ndarray, error_rad: float
) -> np.ndarray:
    """sqrt((tau - A) / (J e)) per axis [rad/s] (0 where the disturbance takes it all).

    Parameters
    ----------
    inertia_kgm2, authority_Nm, disturbance_Nm : ndarray, shape (3,)
    error_rad : float
        The largest error the loop must answer without saturating.
    """
    spare = np.maximum(np.asarray(authority_Nm) - np.asarray(disturbance_Nm), 0.0)
    return np.sqrt(spare / (np.asarray(inertia_kgm2) * error_rad))


def first_mode_rad_s(problem: Problem) -> float | None:
    """The lowest first bending frequency the uncertainty set allows [rad/s] (None: rigid)."""
    first = [
        m.omega_rad_s
        for array in problem.arrays
        for m in array.modes
        if (m.kind, m.order) == ("bending", 1)
    ]
    if not first:
        return None
    return (1.0 - problem.uncertainty.bending_frequency_fraction) * min(first)


def derived_rolloff_rad_s(problem: Problem) -> float:
    """The roll-off the body allows (see the module's note) [rad/s]."""
    mode = first_mode_rad_s(problem)
    if mode is not None:
        return mode / ROLLOFF_BELOW_MODE
    nyquist = math.pi * problem.simulation.control_rate_hz
    return RIGID_ROLLOFF_FRACTION * min(problem.sensor.star_tracker_bandwidth_rad_s, nyquist)


def _paper() -> Problem:
    return load_problem("paper")


def is_papers_body(problem: Problem) -> bool:
    """Whether every table of :data:`BODY_TABLES` is the paper's."""
    paper = _paper().data
    return all(_canonical(problem.data.get(k)) == _canonical(paper.get(k)) for k in BODY_TABLES)


def _canonical(table: Any) -> str:
    """A table as sorted JSON, so that two readings of the same values compare equal."""
    return json.dumps(table, sort_keys=True, default=str)


def body_weights(
    problem: Problem, choice: WeightsChoice = "auto", geometry: Geometry | None = None
) -> BodyWeights:
    """We and Wu for ``problem`` (see the module's note for ``"auto"``).

    Parameters
    ----------
    problem : Problem
    choice : {"auto", "derived", "problem"}
        ``"derived"``: both from the body; ``"problem"``: the problem's ``[weights]``
        as they are (inherited or not).
    geometry : Geometry, optional
        The problem's (built when not given).

    Returns
    -------
    BodyWeights

    Raises
    ------
    SynthesisError
        An unknown choice, or no torque left about an axis once the disturbance is met.
    """
    if choice not in WEIGHTS_CHOICES:
        raise SynthesisError(f"weights: one of {', '.join(WEIGHTS_CHOICES)}, got {choice!r}")
    geometry = geometry or build_geometry(problem)
    inertia = np.diag(geometry.inertia_total_kgm2)
    authority = authority_per_axis_mNm(geometry)
    disturbance = np.abs(np.asarray(problem.disturbance.amplitude_mNm, dtype=float))
    error = math.radians(problem.requirements.slew_error_deg)
    hold = hold_bandwidth_rad_s(inertia, authority * NM_PER_MNM, disturbance * NM_PER_MNM, error)
    rolloff = derived_rolloff_rad_s(problem)
    bandwidth = min(float(hold.min()), rolloff / ROLLOFF_SEPARATION)
    if bandwidth <= 0.0:
        raise SynthesisError(
            "disturbance.amplitude_mNm: the disturbance takes the whole torque authority about "
            f"{'xyz'[int(np.argmin(hold))]}: no bandwidth is left for a controller"
        )
    paper = _paper().weights
    own = problem.weights
    papers_body = is_papers_body(problem)

    def pick(value: float, papers: float, derived: float) -> tuple[float, Origin]:
        if choice == "derived":
            return derived, "derived"
        if choice == "problem":
            return value, "problem"
        if papers_body:
            return value, "paper"
        return (derived, "derived") if value == papers else (value, "problem")

    used_bandwidth, bandwidth_from = pick(
        own.closed_loop_bandwidth_rad_s, paper.closed_loop_bandwidth_rad_s, bandwidth
    )
    used_rolloff, rolloff_from = pick(
        own.control_rolloff_rad_s, paper.control_rolloff_rad_s, rolloff
    )
    figures = BodySummary(
        inertia_kgm2=tuple(inertia.tolist()),
        authority_mNm=tuple(authority.tolist()),
        disturbance_mNm=tuple(disturbance.tolist()),
        hold_bandwidth_rad_s=tuple(hold.tolist()),
        first_mode_rad_s=first_mode_rad_s(problem),
        bandwidth_rad_s=used_bandwidth,
        rolloff_rad_s=used_rolloff,
        derived_bandwidth_rad_s=bandwidth,
        derived_rolloff_rad_s=rolloff,
        bandwidth_from=bandwidth_from,
        rolloff_from=rolloff_from,
        paper_bandwidth_rad_s=paper.closed_loop_bandwidth_rad_s,
        paper_rolloff_rad_s=paper.control_rolloff_rad_s,
    )
    return BodyWeights(
        bandwidth_rad_s=used_bandwidth,
        epsilon=own.epsilon,
        rolloff_rad_s=used_rolloff,
        high_frequency_gain=own.control_rolloff_high_frequency_gain,
        figures=figures,
    )
