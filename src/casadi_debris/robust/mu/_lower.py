"""Lower bound of mixed real/complex mu and the perturbation that attains it.

Any Delta in the structure with sigma_max(Delta) <= 1 gives a lower bound: if
M Delta has an eigenvalue lambda, det(I - M Delta / lambda) = 0, and Delta /
lambda is in the structure when lambda is real (or when every block is complex,
whose phases absorb lambda's), so mu(M) >= |lambda| (Packard and Doyle 1993;
Young and Doyle 1997: mu = max rho_R(M Q) over the structure's unit ball).

The search, per matrix:

1. a power iteration (Packard and Doyle 1993) with real blocks relaxed to
   complex scalars: each step sets every block to the maximiser of the
   linearised spectral radius, Delta_j = e^{j phi} w_j x_j^H / (|w_j| |x_j|) from
   the right eigenvector x and w = M^H y of the left one y, which is the
   complex power iteration's fixed point; from a few seeded random starts;
2. with real blocks, a local solve from each start's end point (the relaxed
   real blocks projected onto [-1, 1]): minimise t subject to
   det(I - t M Delta) = 0, real blocks in [-1, 1], complex blocks u v^H with
   |u|, |v| <= 1 (SLSQP), then mu >= 1/t with Delta / t the perturbation.

The bound reported is evaluated from the perturbation itself, so it is a lower
bound whatever the search does; the search only decides how tight it is.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg
from scipy.optimize import minimize

from casadi_debris.robust.mu._blocks import Block

_REAL_TOL = 1e-7  # an eigenvalue is real when |Im| <= this times |lambda|
_LOCAL_SOLVES = 1


@dataclass(frozen=True)
class _Layout:
    """Where each block sits: kind, start index and size."""

    kinds: tuple[str, ...]
    starts: tuple[int, ...]
    sizes: tuple[int, ...]

    @classmethod
    def of(cls, structure: Sequence[Block]) -> _Layout:
        starts = np.concatenate([[0], np.cumsum([b.size for b in structure])[:-1]])
        return cls(
            tuple(b.kind for b in structure),
            tuple(int(s) for s in starts),
            tuple(b.size for b in structure),
        )

    @property
    def n(self) -> int:
        return self.starts[-1] + self.sizes[-1]

    @property
    def has_real(self) -> bool:
        return "real" in self.kinds

    def blocks(self) -> list[tuple[str, slice]]:
        return [
            (kind, slice(start, start + size))
            for kind, start, size in zip(self.kinds, self.starts, self.sizes, strict=True)
        ]


def _leading(product: np.ndarray) -> tuple[complex, np.ndarray, np.ndarray]:
    """Eigenvalue of largest modulus with its right and left eigenvectors."""
    values, left, right = scipy.linalg.eig(product, left=True, right=True)
    k = int(np.argmax(np.abs(values)))
    return complex(values[k]), right[:, k], left[:, k]


def _power_iteration(
    matrix: np.ndarray, layout: _Layout, delta: np.ndarray, iterations: int
) -> np.ndarray:
    """Relaxed power iteration from ``delta``; returns the last perturbation (unit blocks)."""
    previous = 0.0
    for _ in range(iterations):
        lam, x, y = _leading(matrix @ delta)
        w = matrix.conj().T @ y
        scale = np.vdot(y, x)
        if abs(lam) == 0.0 or abs(scale) == 0.0:
            break
        # Rotate so that the step increases |lambda| along lambda's own phase.
        c = np.exp(-1j * np.angle(lam)) / scale
        updated = np.zeros_like(delta)
        for kind, part in layout.blocks():
            wj, xj = c.conjugate() * w[part], x[part]
            nw, nx = np.linalg.norm(wj), np.linalg.norm(xj)
            if nw == 0.0 or nx == 0.0:
                updated[part, part] = delta[part, part]
            elif kind == "complex":
                updated[part, part] = np.outer(wj / nw, xj.conj() / nx)
            else:
                inner = np.vdot(wj, xj).conjugate()  # w^H x of the block, conjugated
                phase = inner / abs(inner) if abs(inner) > 0 else 1.0
                updated[part, part] = phase * np.eye(part.stop - part.start)
        delta = updated
        if abs(abs(lam) - previous) <= 1e-9 * abs(lam):
            break
        previous = abs(lam)
    return delta


def evaluate(matrix: np.ndarray, layout: _Layout, delta: np.ndarray) -> tuple[float, np.ndarray]:
    """The lower bound a unit perturbation gives, and the destabilising Delta / lambda.

    Returns ``(0, zeros)`` when no admissible eigenvalue exists (with real
    blocks: no real eigenvalue of M Delta).
    """
    size = float(np.linalg.norm(delta, 2))
    if size == 0.0:
        return 0.0, np.zeros_like(delta)
    values = np.linalg.eigvals(matrix @ delta)
    magnitudes = np.abs(values)
    if layout.has_real:
        real = np.abs(values.imag) <= _REAL_TOL * np.maximum(magnitudes, 1e-300)
        magnitudes = np.where(real, magnitudes, 0.0)
        values = values.real.astype(complex)
    k = int(np.argmax(magnitudes))
    if magnitudes[k] == 0.0:
        return 0.0, np.zeros_like(delta)
    # sigma_max(Delta / lambda) = size / |lambda|: the bound is |lambda| / size.
    return float(magnitudes[k] / size), delta / values[k]


def _random_start(layout: _Layout, rng: np.random.Generator) -> np.ndarray:
    delta = np.zeros((layout.n, layout.n), dtype=complex)
    for kind, part in layout.blocks():
        size = part.stop - part.start
        if kind == "complex":
            u = rng.normal(size=size) + 1j * rng.normal(size=size)
            v = rng.normal(size=size) + 1j * rng.normal(size=size)
            delta[part, part] = np.outer(u / np.linalg.norm(u), v.conj() / np.linalg.norm(v))
        else:
            delta[part, part] = np.exp(2j * np.pi * rng.random()) * np.eye(size)
    return delta


def lower_bound(
    matrix: np.ndarray,
    structure: Sequence[Block],
    restarts: int = 4,
    seed: int = 0,
    iterations: int = 60,
    warm: np.ndarray | None = None,
) -> tuple[float, np.ndarray]:
    """Best lower bound of mu(M) found and its destabilising perturbation.

    Parameters
    ----------
    matrix : ndarray, shape (n, n)
    structure : sequence of Block
    restarts : int
        Seeded random starts besides the identity start.
    seed : int
    iterations : int
        Power-iteration steps per start.
    warm : ndarray, shape (n, n), optional
        A perturbation to start from as well (a neighbouring frequency's).

    Returns
    -------
    lower : float
    perturbation : ndarray, shape (n, n)
        Block-diagonal Delta in the structure with sigma_max(Delta) = 1/lower
        and det(I - M Delta) = 0 (zeros when ``lower`` is 0).
    """
    layout = _Layout.of(structure)
    matrix = np.asarray(matrix, dtype=complex)
    rng = np.random.default_rng(seed)
    starts = [np.eye(layout.n, dtype=complex)]
    starts += [_random_start(layout, rng) for _ in range(restarts)]
    if warm is not None and np.any(warm):
        starts.insert(0, warm / np.linalg.norm(warm, 2))
    ends = [_power_iteration(matrix, layout, start, iterations) for start in starts]
    complex_only = _complex_only(matrix, layout, iterations) if layout.has_real else None
    if layout.has_real:
        # The local solve costs most: run it from the two ends of largest relaxed radius.
        radius = [float(np.max(np.abs(np.linalg.eigvals(matrix @ d)))) for d in ends]
        order = np.argsort(radius)[::-1][:_LOCAL_SOLVES]
        projected = [_project(layout, ends[k]) for k in order]
        # A projection that already reaches the relaxed radius is optimal: skip its solve.
        ends = [
            d
            if evaluate(matrix, layout, d)[0] >= (1 - 1e-9) * radius[k]
            else _local_solve(matrix, layout, d)
            for k, d in zip(order, projected, strict=True)
        ]
    if complex_only is not None:
        # Real blocks at zero: at least the complex blocks' own mu (a nominal performance
        # level), which the relaxed iteration, with every real block at +-1, can miss.
        ends += [complex_only, _local_solve(matrix, layout, complex_only)]
    best: tuple[float, np.ndarray] = (0.0, np.zeros_like(matrix))
    for delta in ends:
        candidate = evaluate(matrix, layout, delta)
        if candidate[0] > best[0]:
            best = candidate
    return best


def _complex_only(matrix: np.ndarray, layout: _Layout, iterations: int) -> np.ndarray | None:
    """Power iteration over the complex blocks alone, the real blocks at zero, phased so
    that the leading eigenvalue of M Delta is real (None without complex blocks)."""
    parts = [part for kind, part in layout.blocks() if kind == "complex"]
    if not parts:
        return None
    index = np.concatenate([np.arange(p.start, p.stop) for p in parts])
    sub = _Layout.of([Block("complex", p.stop - p.start) for p in parts])
    sub_matrix = matrix[np.ix_(index, index)]
    sub_delta = _power_iteration(sub_matrix, sub, np.eye(sub.n, dtype=complex), iterations)
    lam = _leading(sub_matrix @ sub_delta)[0]
    delta = np.zeros_like(matrix)
    delta[np.ix_(index, index)] = sub_delta * (np.exp(-1j * np.angle(lam)) if lam else 1.0)
    return delta


def _project(layout: _Layout, delta: np.ndarray) -> np.ndarray:
    """Real blocks of a relaxed perturbation onto real scalars in [-1, 1]."""
    projected = delta.copy()
    for kind, part in layout.blocks():
        if kind == "real":
            value = delta[part.start, part.start]
            projected[part, part] = np.sign(value.real or 1.0) * np.eye(part.stop - part.start)
    return projected


def _unpack(x: np.ndarray, layout: _Layout) -> tuple[float, np.ndarray]:
    """(t, Delta) from the local solve's variables."""
    delta = np.zeros((layout.n, layout.n), dtype=complex)
    i = 1
    for kind, part in layout.blocks():
        size = part.stop - part.start
        if kind == "real":
            delta[part, part] = x[i] * np.eye(size)
            i += 1
        else:
            u = x[i : i + size] + 1j * x[i + size : i + 2 * size]
            v = x[i + 2 * size : i + 3 * size] + 1j * x[i + 3 * size : i + 4 * size]
            delta[part, part] = np.outer(u, v.conj())
            i += 4 * size
    return float(x[0]), delta


def _pack(layout: _Layout, delta: np.ndarray, t: float) -> np.ndarray:
    x = [t]
    for kind, part in layout.blocks():
        block = delta[part, part]
        if kind == "real":
            x.append(float(np.clip(block[0, 0].real, -1.0, 1.0)))
        else:
            left, sigma, right = np.linalg.svd(block)
            u, v = left[:, 0] * min(sigma[0], 1.0), right[0].conj()
            x += [*u.real, *u.imag, *v.real, *v.imag]
    return np.array(x)


def _local_solve(matrix: np.ndarray, layout: _Layout, delta: np.ndarray) -> np.ndarray:
    """Minimise t with det(I - t M Delta) = 0 over the structure's unit ball, from ``delta``.

    Returns the unit perturbation found (``delta`` itself if the solve fails).
    """
    values = np.linalg.eigvals(matrix @ delta)
    radius = float(np.max(np.abs(values)))
    if radius == 0.0:
        return delta
    x0 = _pack(layout, delta, 1.0 / radius)
    n = layout.n
    eye = np.eye(n)
    all_real = not np.iscomplexobj(matrix) or not np.any(matrix.imag)
    all_real = all_real and "complex" not in layout.kinds

    def singular(x: np.ndarray) -> np.ndarray:
        t, d = _unpack(x, layout)
        det = np.linalg.det(eye - t * matrix @ d)
        return np.array([det.real]) if all_real else np.array([det.real, det.imag])

    def singular_jac(x: np.ndarray) -> np.ndarray:
        grad = _det_gradient(matrix, layout, x)
        return grad.real[None] if all_real else np.vstack([grad.real, grad.imag])

    constraints: list[dict[str, Any]] = [{"type": "eq", "fun": singular, "jac": singular_jac}]
    bounds: list[tuple[float, float | None]] = [(0.0, None)]
    i = 1
    for kind, part in layout.blocks():
        size = part.stop - part.start
        if kind == "real":
            bounds.append((-1.0, 1.0))
            i += 1
            continue
        bounds += [(-1.0, 1.0)] * (4 * size)
        for offset in (i, i + 2 * size):
            constraints.append(
                {
                    "type": "ineq",
                    "fun": lambda x, o=offset, k=size: 1.0 - x[o : o + 2 * k] @ x[o : o + 2 * k],
                    "jac": lambda x, o=offset, k=size: _norm_jac(x, o, 2 * k),
                }
            )
        i += 4 * size
    result = minimize(  # type: ignore[call-overload]
        lambda x: float(x[0]),
        x0,
        jac=lambda x: np.eye(len(x))[0],
        method="SLSQP",
        bounds=bounds,
        constraints=constraints,
        options={"maxiter": 60, "ftol": 1e-12},
    )
    return _unpack(result.x, layout)[1] if np.all(np.isfinite(result.x)) else delta


def _norm_jac(x: np.ndarray, offset: int, count: int) -> np.ndarray:
    grad = np.zeros_like(x)
    grad[offset : offset + count] = -2.0 * x[offset : offset + count]
    return grad


def _adjugate(a: np.ndarray) -> np.ndarray:
    """adj(A) from the SVD, finite where A is singular (adj(A) = det(A) A^-1 elsewhere)."""
    u, s, vh = np.linalg.svd(a)
    others = np.array([np.prod(np.delete(s, i)) for i in range(len(s))])
    phase = np.linalg.det(u) * np.linalg.det(vh)
    return phase * (vh.conj().T * others) @ u.conj().T


def _det_gradient(matrix: np.ndarray, layout: _Layout, x: np.ndarray) -> np.ndarray:
    """Gradient of det(I - t M Delta) in the local solve's variables (complex values).

    d det(A) = tr(adj(A) dA); with K = E^T adj(A) M E for a block's selector E,
    a real scalar gives -t tr(K) and a block u v^H gives -t v^H K du and -t dv^H K u.
    """
    t, delta = _unpack(x, layout)
    adj_m = _adjugate(np.eye(layout.n) - t * matrix @ delta) @ matrix
    grad = np.zeros(len(x), dtype=complex)
    grad[0] = -np.trace(adj_m @ delta)
    i = 1
    for kind, part in layout.blocks():
        size = part.stop - part.start
        k = adj_m[part, part]
        if kind == "real":
            grad[i] = -t * np.trace(k)
            i += 1
            continue
        u = x[i : i + size] + 1j * x[i + size : i + 2 * size]
        v = x[i + 2 * size : i + 3 * size] + 1j * x[i + 3 * size : i + 4 * size]
        row, col = v.conj() @ k, k @ u
        grad[i : i + size] = -t * row
        grad[i + size : i + 2 * size] = -1j * t * row
        grad[i + 2 * size : i + 3 * size] = -t * col
        grad[i + 3 * size : i + 4 * size] = 1j * t * col
        i += 4 * size
    return grad
