"""The paper's parametric uncertainty as real scalar blocks: a sample-fitted LFT of the plant.

The paper lumps inertia (+-17 % per axis), mass (+-20 %), array angle
(+-180 deg) and first bending frequency (+-20 %) into one complex
input-multiplicative block. Here each parameter stays a real scalar. At one
array angle, the linear plant's matrices are fitted affine in the other
parameters' normalised positions z in [-1, 1]:

    A(z) = A0 + sum_i z_i A_i,    B(z) = B0 + sum_i z_i B_i,

A0, B0 the plant at z = 0 and the slopes A_i, B_i by least squares over the
3^k grid of the box (levels -1, 0, 1). Each [A_i B_i] is factored as L_i R_i
(its numerical rank r_i, after scaling rows and columns by the nominal
plant's), which gives the linear fractional form

    x_dot = A0 x + B0 u + sum_i L_i w_i,   q_i = R_i [x; u],   w_i = z_i q_i,

one real scalar z_i repeated r_i times per parameter.

Why fitted rather than an exact LFT: the parameters reach the state
equations through the inverse of the mass matrix (inertia, mass) and the
square of the modal frequency, so the exact dependence is rational and an
exact LFT would need the CasADi mass matrix rewritten block by block. The
affine fit keeps the CasADi model as the only source of the plant and is
exact where the dependence is affine; its worst entry-wise residual over
the grid, relative to the largest parametric change, is recorded
(``residual``, about 7 % on the paper's plant: mostly the bending
frequency's square and the inertia's inverse).

Why the angle is gridded: +-180 deg is a full turn, the plant is periodic in
it, and no affine (or low-order rational) function of one real scalar in
[-1, 1] describes a turn. The analysis takes the worst over a grid of angles
(the corner campaign's eight, every 45 deg, by default).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import casadi as ca
import control
import numpy as np

from casadi_debris.dynamics import Model, Units, linearization_function, linearize
from casadi_debris.robust.plant import parameters_from_normalized

# Singular values of a scaled slope below this fraction of its largest are dropped.
RANK_TOLERANCE = 1e-6


@dataclass(frozen=True, eq=False)
class ParametricPlant:
    """Plant with the real parameters pulled out: inputs [w, u], outputs [q, y].

    Attributes
    ----------
    real_names : tuple of str
        The model parameters kept as real scalars, in block order.
    real_indices : tuple of int
        Their positions in the model's parameter vector.
    fixed_normalized : ndarray, shape (n_parameters,)
        Normalised position of every parameter that is not a real block
        (the array angle), zero elsewhere.
    a0 : ndarray, shape (n, n)
    b0 : ndarray, shape (n, 3)
    c0 : ndarray, shape (3, n)
        The plant at z = 0 (torque [mNm] to measured attitude [deg] by default).
    left : tuple of ndarray
        L_i, each (n, r_i).
    right : tuple of ndarray
        R_i, each (r_i, n + 3).
    residual : float
        Largest entry-wise error of the affine fit over the grid, relative to
        the largest entry-wise change of [A B] over it.
    """

    real_names: tuple[str, ...]
    real_indices: tuple[int, ...]
    fixed_normalized: np.ndarray
    a0: np.ndarray
    b0: np.ndarray
    c0: np.ndarray
    left: tuple[np.ndarray, ...]
    right: tuple[np.ndarray, ...]
    residual: float

    @property
    def ranks(self) -> tuple[int, ...]:
        """r_i: how many times each real scalar repeats."""
        return tuple(r.shape[0] for r in self.right)

    @property
    def blocks(self) -> tuple[tuple[str, int], ...]:
        """The real blocks, ``("real", r_i)``, in order."""
        return tuple(("real", r) for r in self.ranks)

    @property
    def n_real(self) -> int:
        """Total size of the real blocks (sum r_i)."""
        return sum(self.ranks)

    def matrices(self, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """A(z), B(z) of the affine model at real-parameter positions ``z`` (k,)."""
        z = np.asarray(z, dtype=float)
        ab = np.hstack([self.a0, self.b0])
        for value, left, right in zip(z, self.left, self.right, strict=True):
            ab = ab + value * left @ right
        n = self.a0.shape[0]
        return ab[:, :n], ab[:, n:]

    def system(self) -> control.StateSpace:
        """The LFT's plant: inputs ``w[..]`` then ``up[..]``, outputs ``q[..]`` then ``y[..]``."""
        n = self.a0.shape[0]
        left = np.hstack(self.left) if self.left else np.zeros((n, 0))
        right = np.vstack(self.right) if self.right else np.zeros((0, n + 3))
        r = left.shape[1]
        b = np.hstack([left, self.b0])
        c = np.vstack([right[:, :n], self.c0])
        d = np.zeros((r + 3, r + 3))
        d[:r, r:] = right[:, n:]
        names_in = [f"w[{i}]" for i in range(r)] + [f"up[{i}]" for i in range(3)]
        names_out = [f"q[{i}]" for i in range(r)] + [f"y[{i}]" for i in range(3)]
        return control.ss(self.a0, b, c, d, inputs=names_in, outputs=names_out, name="lft")

    def normalized(self, z: np.ndarray) -> np.ndarray:
        """Every parameter's normalised position: ``z`` at the real blocks, fixed elsewhere."""
        full = self.fixed_normalized.copy()
        full[list(self.real_indices)] = np.asarray(z, dtype=float)
        return full


def real_parameter_indices(model: Model) -> tuple[int, ...]:
    """Positions of the parameters kept as real scalars (all but the array angles)."""
    layout = model.parameter_layout
    angles = set(layout.angle_names)
    return tuple(i for i, name in enumerate(layout.names) if name not in angles)


def fit_parametric_plant(
    model: Model,
    angle_normalized: float | np.ndarray = 0.0,
    *,
    units: Units = "deg_mNm",
    function: ca.Function | None = None,
) -> ParametricPlant:
    """Fit the affine real-parametric plant at one array angle (see the module).

    Parameters
    ----------
    model : Model
        Sets the plant (its modes; the uncertainty is ``model.problem``'s);
        linearised with the star tracker.
    angle_normalized : float or ndarray
        Position of the array angle(s) in their range, -1 .. 1 (ignored
        without arrays).
    units : {"deg_mNm", "SI"}
    function : casadi.Function, optional
        ``linearization_function(model, sensor=True)``, to reuse.

    Returns
    -------
    ParametricPlant
    """
    layout = model.parameter_layout
    indices = real_parameter_indices(model)
    fixed = np.zeros(layout.size)
    angle_positions = [i for i in range(layout.size) if i not in indices]
    fixed[angle_positions] = angle_normalized
    function = function or linearization_function(model, sensor=True)
    grid = np.array(list(itertools.product((-1.0, 0.0, 1.0), repeat=len(indices))))
    normalized = np.tile(fixed, (len(grid), 1))
    normalized[:, list(indices)] = grid
    stacked = np.array(
        [
            _plant_matrices(model, p, units, function)
            for p in parameters_from_normalized(model, normalized)
        ]
    )
    center = int(np.flatnonzero(~grid.any(axis=1))[0])
    nominal = stacked[center]
    change = (stacked - nominal).reshape(len(grid), -1)
    slopes, *_ = np.linalg.lstsq(grid, change, rcond=None)
    scale = float(np.max(np.abs(change))) or 1.0
    residual = float(np.max(np.abs(change - grid @ slopes))) / scale
    n = nominal.shape[0]
    rows = np.maximum(np.linalg.norm(nominal, axis=1), 1e-300)
    cols = np.maximum(np.linalg.norm(nominal, axis=0), 1e-300)
    factors = [_factor(s.reshape(nominal.shape), rows, cols) for s in slopes]
    plant = linearize(
        model,
        parameters_from_normalized(model, fixed),
        sensor=True,
        units=units,
        function=function,
    )
    return ParametricPlant(
        real_names=tuple(layout.names[i] for i in indices),
        real_indices=indices,
        fixed_normalized=fixed,
        a0=nominal[:, :n],
        b0=nominal[:, n:],
        c0=np.asarray(plant.C),
        left=tuple(f[0] for f in factors),
        right=tuple(f[1] for f in factors),
        residual=residual,
    )


def _plant_matrices(
    model: Model, parameters: np.ndarray, units: Units, function: ca.Function
) -> np.ndarray:
    plant = linearize(model, parameters, sensor=True, units=units, function=function)
    return np.hstack([plant.A, plant.B])


def _factor(slope: np.ndarray, rows: np.ndarray, cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """L, R with L R = slope, of the numerical rank of the row- and column-scaled slope."""
    u, s, vh = np.linalg.svd(slope / rows[:, None] / cols[None, :])
    rank = max(1, int(np.sum(s > RANK_TOLERANCE * s[0]))) if s[0] > 0 else 1
    root = np.sqrt(s[:rank])
    return rows[:, None] * u[:, :rank] * root, (root[:, None] * vh[:rank]) * cols[None, :]
