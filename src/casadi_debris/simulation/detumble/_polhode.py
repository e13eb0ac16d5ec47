"""Torque-free precession of the angular momentum in body axes, and averages over it.

A rigid body's angular momentum ``H = J omega`` moves in body axes as
``dH/dt = tau - omega x H``. Without torque both ``|H|`` and the kinetic energy
are kept, so the unit direction ``m = H / |H|`` stays on a *polhode*: the curve
of the unit sphere with ``m . J^-1 m = s``. The label ``s = 2 E / |H|^2`` lies
between the inverse largest and the inverse smallest principal moment; below the
middle one's inverse the polhode circles the axis of largest inertia, above it
the axis of smallest inertia.

In principal axes with ``a_1 > a_2 > a_3`` the inverse moments, the polhode is
given by Jacobi's elliptic functions of ``u``, and ``u`` grows uniformly in
time; so the points at equal steps of ``u`` over a period ``4 K(k)`` are equal
steps in time, and a mean over them is the time average over the polhode.
Around the axis of largest inertia

    m = (m1 cn u, m2 sn u, m3 dn u),  k^2 = 1 - m3_min^2 / m3^2,

and around the axis of smallest inertia the first and last components swap
their roles. On a braking body the torque changes ``|H|`` and ``s`` only slowly
(``|tau| / (|H| |omega|)`` is about 1e-6 for the paper's tumble), so the means
over a polhode give the drift of ``|H|`` and ``s`` (averaging).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import ellipj, ellipk

from casadi_debris.errors import SimulationError

# Closest approach of the modulus to 1 (the separatrix, an infinite period).
MAX_MODULUS = 1.0 - 1e-12
# Principal moments whose relative spread is below this are taken as equal.
EQUAL_MOMENTS_RTOL = 1e-9


@dataclass(frozen=True)
class PrincipalBody:
    """A rigid body in its principal axes.

    Attributes
    ----------
    inverse_moments : ndarray, shape (3,)
        ``a_1 > a_2 > a_3``: the inverse principal moments [1 / (kg m^2)].
    axes : ndarray, shape (3, 3)
        Columns: the principal axes in body axes, in the order of ``inverse_moments``
        (``J = axes @ diag(1 / a) @ axes.T``).
    """

    inverse_moments: np.ndarray
    axes: np.ndarray

    @classmethod
    def from_inertia(cls, inertia_kgm2: np.ndarray) -> PrincipalBody:
        """Principal axes of a symmetric positive definite inertia, shape (3, 3) [kg m^2]."""
        moments, axes = np.linalg.eigh(np.asarray(inertia_kgm2, dtype=float))
        if not moments[0] > 0.0:
            raise SimulationError(f"inertia: must be positive definite, got moments {moments}")
        return cls(1.0 / moments, axes)

    @property
    def spherical(self) -> bool:
        """All three principal moments equal: every direction is a steady spin."""
        a = self.inverse_moments
        return bool(a[0] - a[2] <= EQUAL_MOMENTS_RTOL * a[0])

    def label(self, direction: np.ndarray) -> float:
        """``s = m . J^-1 m`` of a unit direction given in principal axes [1 / (kg m^2)]."""
        return float(direction @ (self.inverse_moments * direction))

    def drift_direction(self, points: np.ndarray, label: float) -> np.ndarray:
        """``J^-1 m - s m`` at points of the polhode ``s``: a torque along it raises ``s``.

        ``ds/dt = 2 (J^-1 m - s m) . tau / |H|`` (the gyroscopic term keeps ``s``).
        """
        return points * self.inverse_moments - label * points


def polhode_points(body: PrincipalBody, label: float, n: int) -> np.ndarray:
    """``n`` points of the polhode ``s = label`` at equal steps of time, principal axes.

    Parameters
    ----------
    body : PrincipalBody
        Not spherical.
    label : float
        ``s`` in ``[a_3, a_1]``; clipped into it [1 / (kg m^2)].
    n : int

    Returns
    -------
    ndarray, shape (n, 3)
        Unit vectors; the copy of the polhode on the positive side of the axis it circles
        (the other copy is its mirror image through the origin).
    """
    a1, a2, a3 = body.inverse_moments
    s = float(np.clip(label, a3, a1))
    if s <= a2:
        # Around the axis of largest inertia: m3 never vanishes.
        # (With a_2 = a_3 only s = a_3 is here: the spin about axis 3, a point.)
        top = (a1 - s) / (a1 - a3)
        bottom = (a2 - s) / (a2 - a3) if a2 > a3 else top
        amplitudes = np.sqrt([(s - a3) / (a1 - a3), (s - a3) / max(a2 - a3, 1e-300), top])
        order = (1, 0, 2)  # cn, sn, dn
    else:
        top, bottom = (s - a3) / (a1 - a3), (s - a2) / (a1 - a2)
        amplitudes = np.sqrt([top, (a1 - s) / (a1 - a2), (a1 - s) / (a1 - a3)])
        order = (2, 0, 1)  # dn, sn, cn
    modulus = min(1.0 - bottom / top, MAX_MODULUS) if top > 0.0 else 0.0
    u = 4.0 * ellipk(modulus) * (np.arange(n) + 0.5) / n
    elliptic = np.stack(ellipj(u, modulus)[:3])  # sn, cn, dn
    points = amplitudes[None, :] * elliptic[list(order)].T
    return points / np.linalg.norm(points, axis=1, keepdims=True)


@dataclass(frozen=True)
class PolhodeAverages:
    """Means over a polhode of the braking policy ``u(m) = argmin_v w(m) . v``.

    The policy weighs braking against steering the polhode: ``w = cos(theta) m +
    sin(theta) (J^-1 m - s m) / (a_1 - a_3)`` (``theta = 0`` brakes ``|H|`` greedily).
    Tabulated on a grid of labels ``s`` and angles ``theta``.

    Attributes
    ----------
    labels : ndarray, shape (n_s,)
        ``s`` [1 / (kg m^2)].
    angles : ndarray, shape (n_theta,)
        ``theta`` [rad].
    braking_Nm : ndarray, shape (n_s, n_theta)
        ``<m . u>``: the mean of ``d|H|/dt`` [N m], negative.
    drift_Nm_per_kgm2 : ndarray, shape (n_s, n_theta)
        ``<2 (J^-1 m - s m) . u>``: ``|H| ds/dt`` on average.
    fuel_kg_s : ndarray, shape (n_s, n_theta)
        Mean propellant flow of the vertices used [kg/s].
    """

    labels: np.ndarray
    angles: np.ndarray
    braking_Nm: np.ndarray
    drift_Nm_per_kgm2: np.ndarray
    fuel_kg_s: np.ndarray


def polhode_averages(
    body: PrincipalBody,
    vertices_Nm: np.ndarray,
    vertex_fuel_kg_s: np.ndarray,
    *,
    labels: np.ndarray,
    angles: np.ndarray,
    n_phase: int = 720,
) -> PolhodeAverages:
    """Tabulate the means of the vertex policy over polhodes (see :class:`PolhodeAverages`).

    Parameters
    ----------
    body : PrincipalBody
    vertices_Nm : ndarray, shape (k, 3)
        Vertices of the torque polytope in *principal* axes [N m].
    vertex_fuel_kg_s : ndarray, shape (k,)
        Propellant flow at each vertex [kg/s].
    labels, angles : ndarray
        Grids of ``s`` and ``theta``.
    n_phase : int
        Points per polhode.

    Notes
    -----
    The mean is over one copy of the polhode; the other copy gives the same means only
    when the polytope is centrally symmetric (the caller checks).
    """
    scale = body.inverse_moments[0] - body.inverse_moments[2]
    shape = (len(labels), len(angles))
    braking, drift, fuel = np.empty(shape), np.empty(shape), np.empty(shape)
    cosines, sines = np.cos(angles)[:, None, None], np.sin(angles)[:, None, None]
    for i, label in enumerate(labels):
        points = polhode_points(body, label, n_phase)
        steer = body.drift_direction(points, label)
        # All angles at once: weights of shape (n_theta, n_phase, 3).
        weights = cosines * points[None] + sines * steer[None] / scale
        chosen = np.argmin(weights @ vertices_Nm.T, axis=2)
        torque = vertices_Nm[chosen]
        braking[i] = np.mean(np.einsum("pj,apj->ap", points, torque), axis=1)
        drift[i] = 2.0 * np.mean(np.einsum("pj,apj->ap", steer, torque), axis=1)
        fuel[i] = np.mean(vertex_fuel_kg_s[chosen], axis=1)
    return PolhodeAverages(np.asarray(labels), np.asarray(angles), braking, drift, fuel)
