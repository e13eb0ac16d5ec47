"""Performance scalings derived from a problem, and the pointing a design guarantees.

The paper tunes the static scalings of its four-block design by hand (Section
III.C): Vu "the available torques", Vd "the expected disturbances as a first
guess", Ve "the maximum allowable errors", then adjusted. Here they follow from
the problem so that any debris gets a design without hand tuning:

- Vu_i: the smaller of the two signed torque authorities about axis i with zero
  net force [mNm] (the paper's 4.61 / 1.96 / 4.26 are its authorities);
- Vd_i: :data:`DISTURBANCE_TO_AUTHORITY` of Vu_i, shaped by the disturbance
  (``Vd_i = 0.01 Vu_i A_i / max A``): the paper's Vd is 1 % of its Vu on every
  axis, and its disturbance is equal on every axis;
- Ve_i: the largest error scaling whose robust-performance guarantee meets
  ``[requirements] pointing_arcsec`` (below).

The guarantee. With mu <= beta <= 1, every plant the uncertainty weight covers
has ``sigma_max(F(jw)) <= beta`` for the performance channels, so for the
problem's sine disturbance of amplitudes A at w_d the steady error on axis i is
at most ``beta Ve_i ||Vd^-1 A||_2 / |We(j w_d)|``. Ve is set so that this
bound equals the requirement at beta = 1, times a ``ve_ratio``: above 1 when the
requirement cannot be guaranteed, below 1 for a design that does better.

The reference scaling Vr (what the loop must follow, w_e's size) is the paper's, Ve,
up to the requirement's Ve, and stays there when Ve loosens beyond it: in the paper's
form a looser Ve also asks the loop to follow a reference ``ve_ratio`` times larger with
the same torque, and μ rose as Ve loosened (0.917, 0.978, 1.69, 3.25 at 1, 2, 4, 8 times
Ve for the shipped controller on the paper's plant), so the search, which loosens Ve
when μ > 1, walked away from its goal. Held, a looser Ve only scales the error rows
down, and μ of any fixed controller cannot rise. At or below ratio 1 nothing changes
from the paper's form (the paper's own design is the same).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from casadi_debris.config import Problem
from casadi_debris.errors import SynthesisError
from casadi_debris.geometry import Geometry, build_geometry, torque_authority
from casadi_debris.records import Record
from casadi_debris.robust.plant import PerformanceWeights, frequency_response, performance_weights
from casadi_debris.units import ARCSEC_PER_DEG, MN_PER_N, SECONDS_PER_MINUTE

DISTURBANCE_TO_AUTHORITY = 0.01
"""Vd as a fraction of Vu (the paper's ratio on every axis)."""
SMALLEST_DISTURBANCE_SHARE = 1e-3
"""Floor of A_i / max A, so that an undisturbed axis keeps a finite Vd^-1."""


@dataclass(frozen=True)
class DerivedScalings:
    """The static scalings of a design, derived from the problem.

    Attributes
    ----------
    error_deg, control_mNm, disturbance_mNm : ndarray, shape (3,)
        Ve [deg], Vu [mNm], Vd [mNm].
    ve_ratio : float
        Ve over the Ve whose guarantee is the pointing requirement.
    disturbance_frequency_rad_s : float
        w_d of the problem's disturbance.
    pointing_per_mu_arcsec : ndarray, shape (3,)
        The guaranteed steady pointing error per unit mu [arcsec]:
        ``Ve_i ||Vd^-1 A||_2 / |We(j w_d)|``.
    reference_deg : ndarray, shape (3,)
        Vr [deg]: Ve up to ``ve_ratio`` 1, the Ve at ratio 1 beyond (see the module's note).
    base : PerformanceWeights, optional
        Whose We and Wu the design uses (default: the problem's ``[weights]``).
    """

    error_deg: np.ndarray
    control_mNm: np.ndarray
    disturbance_mNm: np.ndarray
    ve_ratio: float
    disturbance_frequency_rad_s: float
    pointing_per_mu_arcsec: np.ndarray
    reference_deg: np.ndarray
    base: PerformanceWeights | None = None

    def guaranteed_pointing_arcsec(self, mu_peak: float) -> np.ndarray | None:
        """The pointing bound of a design reaching ``mu_peak`` (None when mu > 1).

        Returns
        -------
        ndarray, shape (3,), or None
        """
        if not math.isfinite(mu_peak) or mu_peak > 1.0:
            return None
        return mu_peak * self.pointing_per_mu_arcsec

    def performance_weights(self, problem: Problem) -> PerformanceWeights:
        """We and Wu (:attr:`base`, else the problem's) with these Ve, Vr, Vu and Vd."""
        base = self.base or performance_weights(problem)
        return PerformanceWeights(
            error=base.error,
            control_effort=base.control_effort,
            error_scaling=np.diag(self.error_deg),
            control_scaling=np.diag(self.control_mNm),
            disturbance_scaling=np.diag(self.disturbance_mNm),
            reference_scaling=np.diag(self.reference_deg),
            parameters=base.parameters,
        )

    def figures(self) -> ScalingSummary:
        """The scalings as a summary gives them, units in the names."""
        return ScalingSummary(
            error_scaling_deg=tuple(self.error_deg.tolist()),
            control_scaling_mNm=tuple(self.control_mNm.tolist()),
            disturbance_scaling_mNm=tuple(self.disturbance_mNm.tolist()),
            ve_ratio=self.ve_ratio,
            disturbance_frequency_rad_s=self.disturbance_frequency_rad_s,
            pointing_per_mu_arcsec=tuple(self.pointing_per_mu_arcsec.tolist()),
            reference_scaling_deg=tuple(self.reference_deg.tolist()),
        )


@dataclass(frozen=True)
class ScalingSummary(Record):
    """:class:`DerivedScalings` in a summary: Ve [deg], Vu and Vd [mNm] per axis, Ve over
    the requirement's, the disturbance frequency [rad/s] and the pointing error per unit
    of μ [arcsec] per axis, and Vr [deg] (the reference scaling: Ve, held at the
    requirement's Ve when Ve loosens beyond it)."""

    error_scaling_deg: tuple[float, ...]
    control_scaling_mNm: tuple[float, ...]
    disturbance_scaling_mNm: tuple[float, ...]
    ve_ratio: float
    disturbance_frequency_rad_s: float
    pointing_per_mu_arcsec: tuple[float, ...]
    reference_scaling_deg: tuple[float, ...] = ()


def authority_per_axis_mNm(geometry: Geometry) -> np.ndarray:
    """min(+, -) torque authority with zero net force about x, y, z [mNm], shape (3,)."""
    return torque_authority(geometry, zero_net_force=True).weakest_Nm * MN_PER_N


def derived_scalings(
    problem: Problem,
    ve_ratio: float = 1.0,
    geometry: Geometry | None = None,
    base: PerformanceWeights | None = None,
) -> DerivedScalings:
    """Ve, Vu and Vd for ``problem`` (see the module's note).

    Parameters
    ----------
    problem : Problem
    ve_ratio : float
        > 0: Ve is this times the Ve whose guarantee is the pointing requirement.
    geometry : Geometry, optional
        The problem's (built when not given).
    base : PerformanceWeights, optional
        Whose We (for the guarantee) and Wu the design uses; default the problem's
        (:mod:`~casadi_debris.robust.requirements` derives them from the body).

    Raises
    ------
    SynthesisError
        An axis without torque authority, no disturbance or one the authority cannot
        overcome, or a ve_ratio not > 0.
    """
    if not math.isfinite(ve_ratio) or ve_ratio <= 0.0:
        raise SynthesisError(f"ve_ratio: must be > 0, got {ve_ratio}")
    control = authority_per_axis_mNm(geometry or build_geometry(problem))
    if np.any(control <= 0.0):
        weak = ", ".join(a for a, c in zip("xyz", control, strict=True) if c <= 0.0)
        raise SynthesisError(
            f"no torque about {weak} with zero net force: no attitude controller can be designed"
        )
    amplitude = np.abs(np.asarray(problem.disturbance.amplitude_mNm, dtype=float))
    if not np.any(amplitude > 0.0):
        raise SynthesisError(
            "disturbance.amplitude_mNm: all zero; a design needs the disturbance it must reject"
        )
    overcome = [
        f"{a} ({c:.3g} mNm)" for a, c, d in zip("xyz", control, amplitude, strict=True) if d >= c
    ]
    if overcome:
        raise SynthesisError(
            "disturbance.amplitude_mNm: at least the torque authority with zero net force about "
            f"{', '.join(overcome)}: no controller can hold the attitude"
        )
    share = np.maximum(amplitude / amplitude.max(), SMALLEST_DISTURBANCE_SHARE)
    disturbance = DISTURBANCE_TO_AUTHORITY * control * share
    omega_d = 2.0 * math.pi / (SECONDS_PER_MINUTE * problem.disturbance.period_min)
    error_weight = (base or performance_weights(problem)).error
    error_gain = abs(complex(frequency_response(error_weight, np.array([omega_d]))[0, 0, 0]))
    per_unit = float(np.linalg.norm(amplitude / disturbance)) / error_gain
    required_deg = problem.requirements.pointing_arcsec / ARCSEC_PER_DEG
    error = np.full(3, ve_ratio * required_deg / per_unit)
    reference = min(ve_ratio, 1.0) * error / ve_ratio
    return DerivedScalings(
        error_deg=error,
        control_mNm=control,
        disturbance_mNm=disturbance,
        ve_ratio=float(ve_ratio),
        disturbance_frequency_rad_s=omega_d,
        pointing_per_mu_arcsec=error * per_unit * ARCSEC_PER_DEG,
        reference_deg=reference,
        base=base,
    )
