"""Cantilever mode integrals against the closed-form Euler–Bernoulli and torsion values."""

from __future__ import annotations

import math

import pytest

from casadi_debris.dynamics import bending_eigenvalue, shape_integrals

# Roots of 1 + cos b cosh b = 0 (tabulated, e.g. Blevins, Formulas for Natural Frequency)
BETA = [1.87510407, 4.69409113, 7.85475744]


@pytest.mark.parametrize("order", [1, 2, 3])
def test_eigenvalues_tabulated(order):
    assert bending_eigenvalue(order) == pytest.approx(BETA[order - 1], abs=1e-8)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_bending_fractions_closed_form(order):
    # For the normalised cantilever shape: int psi = 2 sigma / b and int xi psi = 2 / b^2,
    # so the effective mass fraction is 4 sigma^2 / b^2 and the root-inertia fraction 12 / b^4.
    b = BETA[order - 1]
    sigma = (math.cosh(b) + math.cos(b)) / (math.sinh(b) + math.sin(b))
    integrals = shape_integrals("bending", order)
    assert integrals.mass_fraction == pytest.approx(4 * sigma**2 / b**2, rel=1e-6)
    assert integrals.root_inertia_fraction == pytest.approx(12 / b**4, rel=1e-6)


def test_bending_fractions_textbook_values():
    fractions = [shape_integrals("bending", k).mass_fraction for k in (1, 2, 3)]
    assert fractions == pytest.approx([0.613, 0.188, 0.065], abs=5e-4)
    assert shape_integrals("bending", 1).root_inertia_fraction == pytest.approx(0.97, abs=1e-3)


def test_torsion_fraction_closed_form():
    # chi = sin(pi xi / 2): (int chi)^2 / int chi^2 = (2/pi)^2 / (1/2) = 8 / pi^2
    assert shape_integrals("torsion", 1).mass_fraction == pytest.approx(8 / math.pi**2, rel=1e-9)
    assert shape_integrals("torsion", 2).mass_fraction == pytest.approx(
        8 / (9 * math.pi**2), rel=1e-9
    )


def test_bad_order_rejected():
    with pytest.raises(ValueError, match="bending order"):
        bending_eigenvalue(0)
