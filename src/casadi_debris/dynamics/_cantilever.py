"""Cantilever mode shapes of a uniform solar array and their participation.

The arrays are modelled as uniform cantilevers clamped at the hinge. Their
modal participation (how much mass and root inertia each mode carries) follows
from the mode shapes, not from invented numbers:

- bending, order k: Euler–Bernoulli cantilever,
  psi(xi) = cosh(b xi) - cos(b xi) - s (sinh(b xi) - sin(b xi)),
  with 1 + cos(b) cosh(b) = 0 and s = (cosh b + cos b) / (sinh b + sin b);
- torsion, order k: uniform shaft clamped at the root, chi(xi) = sin((2k - 1) pi xi / 2),

with xi = s / L the distance from the hinge over the length. For mass-normalised
shapes the translational participation of a bending mode is sqrt(m) * a1 and its
moment about the hinge sqrt(m) * L * a2, with a1 = int psi, a2 = int xi psi over
the normalised shape; the torsion mode's participation about the length axis is
sqrt(I_length) * b1 with b1 = int chi. Effective mass fraction a1^2, root-inertia
fraction 3 a2^2 (of m L^2 / 3), polar-inertia fraction b1^2.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from functools import cache

import numpy as np
import numpy.typing as npt
from scipy.integrate import quad
from scipy.optimize import brentq

from casadi_debris.config import ModeKind

MAX_BENDING_ORDER = 6


@dataclass(frozen=True)
class ShapeIntegrals:
    """Integrals of a normalised mode shape (int shape^2 dxi = 1) over xi in [0, 1].

    Attributes
    ----------
    first : float
        int shape dxi (a1 for bending, b1 for torsion).
    moment : float
        int xi shape dxi (a2; bending only, 0 for torsion).
    """

    first: float
    moment: float

    @property
    def mass_fraction(self) -> float:
        """Effective mass over array mass (bending); polar-inertia fraction (torsion)."""
        return self.first**2

    @property
    def root_inertia_fraction(self) -> float:
        """Effective inertia about the hinge over m L^2 / 3 (bending)."""
        return 3.0 * self.moment**2


@cache
def bending_eigenvalue(order: int) -> float:
    """k-th root b of the cantilever frequency equation 1 + cos(b) cosh(b) = 0."""
    if not 1 <= order <= MAX_BENDING_ORDER:
        raise ValueError(f"bending order must be 1..{MAX_BENDING_ORDER}, got {order}")
    # Roots lie close to (2k - 1) pi / 2, each within its own half period.
    guess = (2 * order - 1) * math.pi / 2
    return brentq(lambda b: 1.0 + math.cos(b) * math.cosh(b), guess - 0.5, guess + 0.5, xtol=1e-14)


def bending_shape(order: int, xi: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Unnormalised Euler–Bernoulli cantilever shape at xi in [0, 1]."""
    b = bending_eigenvalue(order)
    sigma = (math.cosh(b) + math.cos(b)) / (math.sinh(b) + math.sin(b))
    bx = b * np.asarray(xi, dtype=float)
    return np.cosh(bx) - np.cos(bx) - sigma * (np.sinh(bx) - np.sin(bx))


def torsion_shape(order: int, xi: npt.ArrayLike) -> npt.NDArray[np.float64]:
    """Uniform cantilevered shaft twist shape at xi in [0, 1]."""
    return np.sin((2 * order - 1) * math.pi * np.asarray(xi, dtype=float) / 2.0)


@cache
def shape_integrals(kind: ModeKind, order: int) -> ShapeIntegrals:
    """Participation integrals of a normalised cantilever mode, by quadrature.

    Parameters
    ----------
    kind : {"bending", "torsion"}
    order : int
        1 for the first mode of that kind.

    Returns
    -------
    ShapeIntegrals
        Sign fixed so that ``first`` is positive.
    """
    shape = {"bending": bending_shape, "torsion": torsion_shape}[kind]

    def integral(fn: Callable[[float], npt.NDArray[np.float64]]) -> float:
        return quad(lambda xi: float(fn(xi)), 0.0, 1.0, limit=200, epsabs=1e-13, epsrel=1e-12)[0]

    norm = math.sqrt(integral(lambda xi: shape(order, xi) ** 2))
    first = integral(lambda xi: shape(order, xi)) / norm
    moment = integral(lambda xi: xi * shape(order, xi)) / norm if kind == "bending" else 0.0
    sign = 1.0 if first >= 0 else -1.0
    return ShapeIntegrals(sign * first, sign * moment)
