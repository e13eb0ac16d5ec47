"""Which physical limit binds when a design misses its requirements, with the numbers,
and what would meet them.

Each figure here is an estimate from a scaling law, stated with it, from the body's
figures (inertia J, authority tau and disturbance A per axis) and what the
verification measured:

- Pointing. The loop holds the disturbance with integral action; below its
  crossover its gain rises as (w_c / w)^3, so the steady error under a slow
  disturbance falls as w_c^-3. The bandwidth the authority can hold grows as
  sqrt(tau - A) (:func:`~casadi_debris.robust.requirements.hold_bandwidth_rad_s`),
  so the error falls as (tau - A)^(-3/2): to bring a worst error e down to the
  requirement p takes ``tau' = A + (tau - A) (e / p)^(2/3)`` about the axis that
  binds (the one whose hold bandwidth is the lowest). Or a pointing requirement of e.
- Slew. The feedback corrects what the feed-forward gets wrong: the inertia's
  uncertainty times the acceleration, so the error grows with the acceleration, which
  a bang-bang of fixed angle makes ∝ 1/T^2. A torque fraction f reaching error e
  meets the requirement e_req at ``f e_req / e``, a slew ``sqrt(e / e_req)`` times as
  long; or a slew-error requirement of e.
- μ. When no performance level gives μ <= 1, nothing is guaranteed: the uncertainty
  the weight covers is too large for the weights; the lowest μ reached is given.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.records import Record

AXES = "xyz"


@dataclass(frozen=True)
class BindingLimit(Record):
    """One requirement a design misses, the limit that binds and what would meet it.

    Attributes
    ----------
    requirement : str
        The requirement row's key (``"pointing_arcsec"``, ``"slew_max_error_deg"``, ``"mu_peak"``).
    limit : str
        The limit that binds, in words with its numbers.
    remedies : tuple of str
        What would meet the requirement, each with its number.
    figures : dict
        The numbers behind them, units in the keys.
    """

    requirement: str
    limit: str
    remedies: tuple[str, ...]
    figures: dict[str, float | int | str | None]


@dataclass(frozen=True)
class BodyLimits:
    """What a body can do per axis, SI.

    Attributes
    ----------
    inertia_kgm2, authority_Nm, disturbance_Nm, hold_bandwidth_rad_s : ndarray, shape (3,)
    disturbance_frequency_rad_s : float
    """

    inertia_kgm2: np.ndarray
    authority_Nm: np.ndarray
    disturbance_Nm: np.ndarray
    hold_bandwidth_rad_s: np.ndarray
    disturbance_frequency_rad_s: float

    @property
    def binding_axis(self) -> int:
        """The axis whose hold bandwidth is the lowest (0-based)."""
        return int(np.argmin(self.hold_bandwidth_rad_s))


def pointing_limit(
    body: BodyLimits, worst_arcsec: float, required_arcsec: float, *, guaranteed: bool = False
) -> BindingLimit:
    """The pointing requirement missed: the axis that binds and the authority that would meet it.

    Parameters
    ----------
    body : BodyLimits
    worst_arcsec, required_arcsec : float
        Worst pointing error over the corners (or the bound μ guarantees), and the
        requirement [arcsec].
    guaranteed : bool
        ``worst_arcsec`` is the guaranteed bound, not a simulated error.
    """
    k = body.binding_axis
    tau, a = float(body.authority_Nm[k]), float(body.disturbance_Nm[k])
    needed = a + (tau - a) * (worst_arcsec / required_arcsec) ** (2.0 / 3.0)
    axis = AXES[k]
    ratio = body.hold_bandwidth_rad_s[k] / body.disturbance_frequency_rad_s
    limit = (
        f"authority about {axis}: {tau * 1e3:.3g} mNm against a {a * 1e3:.3g} mNm disturbance "
        f"on {body.inertia_kgm2[k]:.4g} kg m^2 holds a bandwidth of "
        f"{body.hold_bandwidth_rad_s[k]:.3g} rad/s, {ratio:.3g} times the disturbance's "
        f"frequency; {'μ guarantees' if guaranteed else 'the worst corner points to'} "
        f"{worst_arcsec:.3g} arcsec against {required_arcsec:.3g}"
    )
    remedies = (
        f"about {needed * 1e3:.3g} mNm of authority about {axis} (now {tau * 1e3:.3g}; "
        "estimate: the error falls as (tau - A)^-3/2)",
        f"a pointing requirement of {math.ceil(worst_arcsec):d} arcsec",
    )
    return BindingLimit(
        requirement="guaranteed_pointing_arcsec" if guaranteed else "pointing_arcsec",
        limit=limit,
        remedies=remedies,
        figures={
            "axis": axis,
            "authority_mNm": tau * 1e3,
            "disturbance_mNm": a * 1e3,
            "inertia_kgm2": float(body.inertia_kgm2[k]),
            "hold_bandwidth_rad_s": float(body.hold_bandwidth_rad_s[k]),
            "worst_arcsec": worst_arcsec,
            "required_arcsec": required_arcsec,
            "authority_needed_mNm": needed * 1e3,
        },
    )


def slew_limit(
    worst_deg: float,
    required_deg: float,
    torque_fraction: float | None,
    saturated_s: float | None,
) -> BindingLimit:
    """The slew-error requirement missed: the feed-forward's share and a slower slew.

    Parameters
    ----------
    worst_deg, required_deg : float
        Worst slew error over the corners, and the requirement [deg].
    torque_fraction : float or None
        Share of the authority the slew's bang-bang uses (None: a profile of the problem's).
    saturated_s : float or None
        The longest time any corner spent at the torque limit [s].
    """
    scale = math.sqrt(worst_deg / required_deg)
    saturation = (
        ""
        if saturated_s is None
        else f"; the worst corner is at the torque limit for {saturated_s:.0f} s"
    )
    share = "" if torque_fraction is None else f" at {torque_fraction:.3g} of the authority"
    limit = (
        f"the slew's acceleration{share}: the feedback corrects what the uncertain inertia "
        f"makes of it, {worst_deg:.3g} deg at the worst corner against {required_deg:.3g}"
        f"{saturation}"
    )
    remedies = [f"a slew {scale:.2f} times as long (the error grows as 1/T^2)"]
    if torque_fraction is not None:
        remedies[0] += f": torque fraction {torque_fraction * required_deg / worst_deg:.3g}"
    remedies.append(f"a slew-error requirement of {math.ceil(worst_deg * 100) / 100:.2f} deg")
    return BindingLimit(
        requirement="slew_max_error_deg",
        limit=limit,
        remedies=tuple(remedies),
        figures={
            "worst_deg": worst_deg,
            "required_deg": required_deg,
            "torque_fraction": torque_fraction,
            "torque_saturated_s": saturated_s,
            "duration_factor": scale,
        },
    )


def mu_limit(lowest_mu: float, at_ve_ratio: float, max_ve_ratio: float) -> BindingLimit:
    """No performance level gave μ <= 1: the uncertainty binds.

    Parameters
    ----------
    lowest_mu : float
        The lowest reduced-controller μ of the search.
    at_ve_ratio : float
        Its Ve over the requirement's.
    max_ve_ratio : float
        The loosest Ve tried, over the requirement's.
    """
    return BindingLimit(
        requirement="mu_peak",
        limit=(
            f"the uncertainty: the lowest μ reached is {lowest_mu:.3g} (at Ve {at_ve_ratio:.3g} x "
            f"the requirement's); up to {max_ve_ratio:.3g} x no design guarantees performance "
            "for every plant the uncertainty weight covers"
        ),
        remedies=(
            "a smaller uncertainty set ([uncertainty]), or weights of your own ([weights]; "
            "design --weights problem)",
        ),
        figures={"lowest_mu": lowest_mu, "at_ve_ratio": at_ve_ratio},
    )


def margins_limit(
    gain_margin_db: float,
    phase_margin_deg: float,
    unstable: int,
    samples: int,
    bandwidth_rad_s: float | None,
) -> BindingLimit:
    """Margins over the sampled plants below the conventional ones, or unstable samples.

    Parameters
    ----------
    gain_margin_db, phase_margin_deg : float
        Smallest over the samples.
    unstable : int
        Sampled loops that are unstable.
    samples : int
    bandwidth_rad_s : float or None
        The design's We bandwidth (None: not a μ design).
    """
    lower = (
        "a lower bandwidth"
        if bandwidth_rad_s is None
        else f"a bandwidth below {bandwidth_rad_s:.3g} rad/s"
    )
    return BindingLimit(
        requirement="margins_sampled",
        limit=(
            f"the uncertainty at crossover: over {samples} sampled plants the smallest margins "
            f"are {gain_margin_db:.3g} dB and {phase_margin_deg:.3g} deg, {unstable} loops unstable"
        ),
        remedies=(
            f"{lower} ([weights] closed_loop_bandwidth_rad_s), or a smaller uncertainty set",
        ),
        figures={
            "gain_margin_db": gain_margin_db,
            "phase_margin_deg": phase_margin_deg,
            "unstable_samples": unstable,
            "samples": samples,
        },
    )
