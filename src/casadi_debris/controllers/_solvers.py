"""Set-up of the NMPC's solvers: QP options, the Gauss-Newton Hessian, a quiet build."""

from __future__ import annotations

import contextlib
import ctypes
import io
import os
import sys
from collections.abc import Iterator
from typing import Any

import casadi as ca

# Weight of the proximal term added to the Gauss-Newton Hessian (scaled variables).
PROXIMAL_WEIGHT = 1e-6


@contextlib.contextmanager
def c_stdout_silenced() -> Iterator[None]:
    """Python's stdout and file descriptor 1 sent nowhere for the duration."""
    sys.stdout.flush()
    try:
        saved = os.dup(1)
    except OSError:  # no file descriptor 1 (an embedding host): nothing to silence
        yield
        return
    try:
        # CasADi sends its C++ output stream through Python's sys.stdout: both go.
        with open(os.devnull, "w") as null, contextlib.redirect_stdout(io.StringIO()):
            os.dup2(null.fileno(), 1)
            yield
            sys.stdout.flush()
    finally:
        # C's stdout is block-buffered when it is not a terminal: empty it into the
        # null device before fd 1 is given back.
        _flush_c_stdio()
        os.dup2(saved, 1)
        os.close(saved)


def _flush_c_stdio() -> None:
    """fflush(NULL) of the C library, where there is one to call."""
    with contextlib.suppress(OSError, AttributeError):
        ctypes.CDLL(None).fflush(None)


def gauss_newton(nlp: dict[str, ca.SX], residual: ca.SX) -> ca.Function:
    """Hessian of the Lagrangian as the SQP iterations see it: 2 lam_f J_r^T J_r, the
    Gauss-Newton approximation of the sum of squares (the dynamics' curvature left out),
    positive semidefinite without any convexification (the classical real-time iteration)."""
    w, p = nlp["x"], nlp["p"]
    lam_f = ca.SX.sym("lam_f")
    lam_g = ca.SX.sym("lam_g", nlp["g"].numel())
    jacobian = ca.jacobian(residual, w)
    # A small proximal term (Levenberg-Marquardt) makes every QP strictly convex: the
    # translation states carry no cost, and qrqp stalled on the singular Hessian about
    # once in 40 periods. It damps the step only; a converged point is unchanged.
    proximal = PROXIMAL_WEIGHT * ca.DM.eye(w.numel())
    hessian = 2.0 * lam_f * ca.mtimes(jacobian.T, jacobian) + proximal
    return ca.Function(
        "nlp_hess_l",
        [w, p, lam_f, lam_g],
        [hessian],
        ["x", "p", "lam_f", "lam_g"],
        ["hess_gamma_x_x"],
    )


def qp_options(qp_solver: str) -> dict[str, Any]:
    """Quiet options of each QP solver, accurate enough for the equality constraints."""
    if qp_solver == "qrqp":
        # Bounds and equalities to 1e-12 of their scale (default 1e-8): the plan keeps
        # a failed engine at zero and the net force at zero to round-off.
        return {
            "print_iter": False,
            "print_header": False,
            "error_on_fail": False,
            "constr_viol_tol": 1e-10,
            "dual_inf_tol": 1e-10,
        }
    if qp_solver == "osqp":
        return {
            "osqp": {
                "verbose": False,
                "eps_abs": 1e-9,
                "eps_rel": 1e-9,
                "max_iter": 20000,
                "polish": True,
            },
            "error_on_fail": False,
        }
    if qp_solver == "qpoases":
        # The sparse (Schur-free) variant: the dense one costs about 1 s per period here.
        return {"printLevel": "none", "sparse": True, "error_on_fail": False}
    return {"error_on_fail": False}
