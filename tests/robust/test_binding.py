"""The limit named when a requirement is missed, and the remedy's numbers, against the
scaling laws written out here."""

from __future__ import annotations

import math

import numpy as np
import pytest

from casadi_debris.robust.requirements import BodyLimits, mu_limit, pointing_limit, slew_limit


def _body() -> BodyLimits:
    inertia = np.array([6630.0, 1312.0, 6309.0])
    authority = np.array([2.73e-3, 3.89e-3, 3.58e-3])
    disturbance = np.full(3, 0.7e-3)
    hold = np.sqrt((authority - disturbance) / (inertia * math.radians(0.6)))
    return BodyLimits(inertia, authority, disturbance, hold, 2 * math.pi / 5910.0)


def test_pointing_names_the_slowest_axis_and_the_authority_that_meets_the_requirement():
    body = _body()
    limit = pointing_limit(body, worst_arcsec=81.4, required_arcsec=60.0)
    assert limit.figures["axis"] == "x"  # the lowest hold bandwidth: 6630 kg m^2 on 2.73 mNm
    needed = limit.figures["authority_needed_mNm"] * 1e-3
    # The law: error ∝ (tau - A)^-3/2, so 81.4 at 2.73 mNm becomes 60 at the authority named.
    a, tau = 0.7e-3, 2.73e-3
    assert 81.4 * ((tau - a) / (needed - a)) ** 1.5 == pytest.approx(60.0, rel=1e-12)
    assert "about x" in limit.remedies[0] and "82 arcsec" in limit.remedies[1]
    assert limit.requirement == "pointing_arcsec" and "worst corner points to 81.4" in limit.limit
    bound = pointing_limit(body, worst_arcsec=81.4, required_arcsec=60.0, guaranteed=True)
    assert bound.requirement == "guaranteed_pointing_arcsec" and "μ guarantees 81.4" in bound.limit


def test_slew_gives_a_slower_slew_that_meets_the_requirement():
    limit = slew_limit(worst_deg=0.9, required_deg=0.6, torque_fraction=0.5, saturated_s=120.0)
    # The law: error ∝ acceleration ∝ fraction ∝ 1 / T^2.
    assert limit.figures["duration_factor"] == pytest.approx(math.sqrt(0.9 / 0.6), rel=1e-12)
    assert "torque fraction 0.333" in limit.remedies[0]
    assert "120 s" in limit.limit and "0.90 deg" in limit.remedies[1]
    assert "fraction" not in slew_limit(0.9, 0.6, None, None).remedies[0]


def test_mu_names_the_uncertainty_with_the_lowest_mu():
    limit = mu_limit(1.31, 64.0, 64.0)
    assert "1.31" in limit.limit and limit.figures["lowest_mu"] == 1.31
