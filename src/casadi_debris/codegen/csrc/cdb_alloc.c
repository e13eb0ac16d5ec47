/* cdb_alloc.c - least-fuel thrust allocation, the same answer as casadi_debris' Allocator.
 *
 * Scaled units as the Allocator's: thrust u = f / f_ref, wrench rows in units of the
 * largest lever arm (force per newton) times f_ref. Each stage is the strictly convex QP
 *
 *     minimise  eps/2 |x|^2 + c'x   subject to   A x = b,   0 <= x <= hi,
 *
 * solved through its dual: for multipliers l of A x = b the minimiser over the box is
 * x(l) = clip(-(c + A'l) / eps, 0, hi), and the dual function is concave, piecewise
 * quadratic and differentiable, with gradient A x(l) - b. Newton's method on it (the
 * Hessian from the engines strictly inside their bounds, a backtracking line search)
 * ends on the optimal piece, where one full step solves the KKT system exactly: the
 * same unique minimiser as any active-set solver's (DAQP's in Python) to round-off.
 *
 * Stages (the Allocator's and the closed loop's):
 * 1. least fuel at the demand (eps = 1e-3, c = each engine's mass flow weight);
 *    a demand below a tenth of an engine's torque is solved stretched by 2^k;
 * 2. if it cannot be met: the largest scale alpha with alpha * demand reachable
 *    (variables (u, alpha), eps = 1e-6, c = (0, -1), A = [rows, -target], b = 0),
 *    then, as the loop does, least fuel at alpha (1 - 1e-10) times the demand.
 */
#include <math.h>
#include <stddef.h>
#include "cdb_flight.h"

#define NE CDB_N_ENGINES
#define NX (CDB_N_ENGINES + 1)
#define NR CDB_N_ROWS

#define EXACT_PROXIMAL ((cdb_real)1e-3)
#define SATURATION_BACKOFF ((cdb_real)1e-10)
#define ALPHA_RESOLUTION ((cdb_real)1e-10)
#define THRUST_ROUND_OFF ((cdb_real)1e-12)
#define LIMIT_ACTIVE_RTOL ((cdb_real)1e-9)
#define SMALL_DEMAND ((cdb_real)0.1)
#define N_SMALL_LEVELS 4
#define QP_MAX_NEWTON 4
#define QP_DIVERGED ((cdb_real)1e8)
#ifdef CDB_FLOAT
#define POLISH_TOLERANCE ((cdb_real)1e-6)
#define QP_TOLERANCE ((cdb_real)1e-6)
#define QP_ACCEPT ((cdb_real)1e-4)
#define QP_REGULARISATION ((cdb_real)1e-6)
#else
#define POLISH_TOLERANCE ((cdb_real)1e-13)
#define QP_TOLERANCE ((cdb_real)1e-13)
#define QP_ACCEPT ((cdb_real)1e-11)
#define QP_REGULARISATION ((cdb_real)1e-12)
#endif

typedef struct {
    int n;                /* variables */
    int stride;           /* columns stored per row of a */
    const cdb_real *a;    /* NR rows of `stride` entries */
    const cdb_real *b;    /* NR */
    const cdb_real *c;    /* n (NULL: zero but the last, -1: the scale stage) */
    const cdb_real *hi;   /* n */
    cdb_real eps;
} qp_data;

static cdb_real magnitude(cdb_real v) { return v < (cdb_real)0 ? -v : v; }

static cdb_real largest_magnitude(const cdb_real *v, int n) {
    cdb_real m = (cdb_real)0;
    int i;
    for (i = 0; i < n; ++i) {
        if (magnitude(v[i]) > m) {
            m = magnitude(v[i]);
        }
    }
    return m;
}

static cdb_real linear_cost(const qp_data *d, int i) {
    if (d->c != NULL) {
        return d->c[i];
    }
    return i == d->n - 1 ? (cdb_real)-1 : (cdb_real)0;
}

/* Solve M y = r for the symmetric positive definite NR x NR matrix M (overwritten by its
 * Cholesky factor); r is overwritten by y. Returns 0 when M is not positive definite. */
static int cholesky_solve(cdb_real m[NR * NR], cdb_real r[NR]) {
    int i, j, k;
    for (j = 0; j < NR; ++j) {
        cdb_real diagonal = m[j * NR + j];
        for (k = 0; k < j; ++k) {
            diagonal -= m[j * NR + k] * m[j * NR + k];
        }
        if (!(diagonal > (cdb_real)0)) {
            return 0;
        }
        diagonal = (cdb_real)sqrt((double)diagonal);
        m[j * NR + j] = diagonal;
        for (i = j + 1; i < NR; ++i) {
            cdb_real v = m[i * NR + j];
            for (k = 0; k < j; ++k) {
                v -= m[i * NR + k] * m[j * NR + k];
            }
            m[i * NR + j] = v / diagonal;
        }
    }
    for (i = 0; i < NR; ++i) {
        cdb_real v = r[i];
        for (k = 0; k < i; ++k) {
            v -= m[i * NR + k] * r[k];
        }
        r[i] = v / m[i * NR + i];
    }
    for (i = NR - 1; i >= 0; --i) {
        cdb_real v = r[i];
        for (k = i + 1; k < NR; ++k) {
            v -= m[k * NR + i] * r[k];
        }
        r[i] = v / m[i * NR + i];
    }
    return 1;
}

/* x(l), which variables are strictly inside their bounds, the gradient A x - b; returns
 * the dual value. */
static cdb_real dual_point(const qp_data *d, const cdb_real lambda[NR], cdb_real x[NX],
                           unsigned char inside[NX], cdb_real gradient[NR]) {
    cdb_real value = (cdb_real)0;
    int i, j;
    for (i = 0; i < d->n; ++i) {
        cdb_real s = linear_cost(d, i);
        cdb_real v;
        for (j = 0; j < NR; ++j) {
            s += d->a[j * d->stride + i] * lambda[j];
        }
        v = -s / d->eps;
        inside[i] = 0;
        if (v <= (cdb_real)0) {
            v = (cdb_real)0;
        } else if (v >= d->hi[i]) {
            v = d->hi[i];
        } else {
            inside[i] = 1;
        }
        x[i] = v;
        value += (d->eps / (cdb_real)2 * v + s) * v;
    }
    for (j = 0; j < NR; ++j) {
        cdb_real g = -d->b[j];
        for (i = 0; i < d->n; ++i) {
            g += d->a[j * d->stride + i] * x[i];
        }
        gradient[j] = g;
        value -= lambda[j] * d->b[j];
    }
    return value;
}

/* Derivative of the dual along `step` at t (with s = c + A'lambda and w = A'step). */
static cdb_real dual_slope(const qp_data *d, const cdb_real s[NX], const cdb_real w[NX],
                           cdb_real step_b, cdb_real t) {
    cdb_real f = -step_b;
    int i;
    for (i = 0; i < d->n; ++i) {
        cdb_real v = -(s[i] + t * w[i]) / d->eps;
        v = v < (cdb_real)0 ? (cdb_real)0 : (v > d->hi[i] ? d->hi[i] : v);
        f += w[i] * v;
    }
    return f;
}

/* The step length along `step` that maximises the dual: the derivative along it is
 * nonincreasing and piecewise linear in t, with kinks where an engine reaches a bound;
 * its root, found between the sorted kinks (t = 1, the Newton step, when no kink lies
 * before it). Returns -1 when the derivative stays positive: the dual grows without
 * bound along `step`, and no x in the box meets A x = b. */
static cdb_real exact_step(const qp_data *d, const cdb_real lambda[NR], const cdb_real step[NR],
                           cdb_real slope) {
    cdb_real s[NX], w[NX], kinks[2 * NX] = {0};
    cdb_real step_b = (cdb_real)0, previous_t = (cdb_real)0, previous_f = slope, f;
    int n_kinks = 0, i, j, k;
    for (j = 0; j < NR; ++j) {
        step_b += step[j] * d->b[j];
    }
    for (i = 0; i < d->n; ++i) {
        s[i] = linear_cost(d, i);
        w[i] = (cdb_real)0;
        for (j = 0; j < NR; ++j) {
            s[i] += d->a[j * d->stride + i] * lambda[j];
            w[i] += d->a[j * d->stride + i] * step[j];
        }
        if (w[i] != (cdb_real)0) {
            cdb_real t0 = -s[i] / w[i], t1 = -(s[i] + d->eps * d->hi[i]) / w[i];
            if (t0 > (cdb_real)0) {
                kinks[n_kinks++] = t0;
            }
            if (t1 > (cdb_real)0) {
                kinks[n_kinks++] = t1;
            }
        }
    }
    {
        /* No kink before the Newton step: it is the root (the common case near the end). */
        cdb_real first = (cdb_real)2;
        for (k = 0; k < n_kinks; ++k) {
            first = kinks[k] < first ? kinks[k] : first;
        }
        if (first >= (cdb_real)1) {
            return (cdb_real)1;
        }
    }
    for (k = 1; k < n_kinks; ++k) { /* insertion sort: at most 2 NX entries */
        cdb_real v = kinks[k];
        for (j = k - 1; j >= 0 && kinks[j] > v; --j) {
            kinks[j + 1] = kinks[j];
        }
        kinks[j + 1] = v;
    }
    for (k = 0; k < n_kinks; ++k) {
        f = dual_slope(d, s, w, step_b, kinks[k]);
        if (f <= (cdb_real)0) {
            if (previous_f - f <= (cdb_real)0) {
                return kinks[k];
            }
            return previous_t + previous_f * (kinks[k] - previous_t) / (previous_f - f);
        }
        previous_t = kinks[k];
        previous_f = f;
    }
    return (cdb_real)-1;
}

/* Newton's method on the dual from `lambda` (updated). Returns 1 when A x = b was met to
 * QP_TOLERANCE (x is then the minimiser), or to QP_ACCEPT where Newton stalls at
 * round-off on a degenerate optimum (the polish that follows removes that residual as it
 * does DAQP's); 0 when not (diverging multipliers: no x in the box meets A x = b). */
static int qp_solve(const qp_data *d, cdb_real lambda[NR], cdb_real x[NX], int *iterations) {
    unsigned char inside[NX];
    cdb_real gradient[NR], step[NR], m[NR * NR];
    cdb_real tolerance, accept;
    int newton, i, j, k;
    tolerance = QP_TOLERANCE * ((cdb_real)1 + largest_magnitude(d->b, NR));
    accept = QP_ACCEPT * ((cdb_real)1 + largest_magnitude(d->b, NR));
    (void)dual_point(d, lambda, x, inside, gradient);
    for (newton = 0; newton < QP_MAX_NEWTON; ++newton) {
        cdb_real slope = (cdb_real)0, t;
        if (largest_magnitude(gradient, NR) <= tolerance) {
            return 1;
        }
        if (largest_magnitude(lambda, NR) > QP_DIVERGED) {
            return 0;
        }
        *iterations += 1;
        for (j = 0; j < NR; ++j) {
            for (k = 0; k <= j; ++k) {
                cdb_real v = (cdb_real)0;
                for (i = 0; i < d->n; ++i) {
                    if (inside[i]) {
                        v += d->a[j * d->stride + i] * d->a[k * d->stride + i];
                    }
                }
                v /= d->eps;
                m[j * NR + k] = v;
                m[k * NR + j] = v;
            }
            m[j * NR + j] += QP_REGULARISATION;
            step[j] = gradient[j];
        }
        if (!cholesky_solve(m, step)) {
            return 0;
        }
        for (j = 0; j < NR; ++j) {
            slope += gradient[j] * step[j];
        }
        t = exact_step(d, lambda, step, slope);
        if (t < (cdb_real)0) {
            return 0; /* unbounded dual: the target is beyond reach */
        }
        for (j = 0; j < NR; ++j) {
            lambda[j] += t * step[j];
        }
        (void)dual_point(d, lambda, x, inside, gradient);
        if (t * largest_magnitude(step, NR) <= QP_TOLERANCE * largest_magnitude(lambda, NR)) {
            /* No ascent left at round-off: x(lambda) is the answer if it meets A x = b. */
            return largest_magnitude(gradient, NR) <= accept;
        }
    }
    return largest_magnitude(gradient, NR) <= accept;
}

/* The Allocator's polish: clip, zero the round-off, and one least-norm step of the free
 * engines onto A u = target when the residual is above POLISH_TOLERANCE. */
static int polish_once(cdb_real u[NE], const cdb_real target[NR], const cdb_real upper[NE]) {
    cdb_real m[NR * NR], step[NR], polished[NE];
    cdb_real worst = (cdb_real)0, after = (cdb_real)0;
    int i, j, k, n_free = 0;
    for (i = 0; i < NE; ++i) {
        if (u[i] > upper[i]) {
            u[i] = upper[i];
        }
        if (u[i] < THRUST_ROUND_OFF) {
            u[i] = (cdb_real)0;
        }
    }
    for (j = 0; j < NR; ++j) {
        cdb_real r = target[j];
        for (i = 0; i < NE; ++i) {
            r -= cdb_rows[j * NE + i] * u[i];
        }
        step[j] = r;
        if (magnitude(r) > worst) {
            worst = magnitude(r);
        }
    }
    if (worst <= POLISH_TOLERANCE * largest_magnitude(target, NR)) {
        return 0;
    }
    for (i = 0; i < NE; ++i) {
        n_free += (u[i] > (cdb_real)0 && u[i] < upper[i]) ? 1 : 0;
    }
    if (n_free == 0) {
        return 0;
    }
    for (j = 0; j < NR; ++j) {
        for (k = 0; k < NR; ++k) {
            cdb_real v = (cdb_real)0;
            for (i = 0; i < NE; ++i) {
                if (u[i] > (cdb_real)0 && u[i] < upper[i]) {
                    v += cdb_rows[j * NE + i] * cdb_rows[k * NE + i];
                }
            }
            m[j * NR + k] = v;
        }
    }
    {
        /* The Gram matrix of nearly dependent free engines may not factor: then with a
         * regularisation of 1e-12 of its largest diagonal (a least-norm-like step). */
        cdb_real copy[NR * NR], rhs[NR], largest = (cdb_real)0;
        for (j = 0; j < NR * NR; ++j) {
            copy[j] = m[j];
        }
        for (j = 0; j < NR; ++j) {
            rhs[j] = step[j];
            largest = m[j * NR + j] > largest ? m[j * NR + j] : largest;
        }
        if (!cholesky_solve(m, step)) {
            for (j = 0; j < NR; ++j) {
                copy[j * NR + j] += (cdb_real)1e-12 * largest;
                step[j] = rhs[j];
            }
            if (!cholesky_solve(copy, step)) {
                return 0;
            }
        }
    }
    for (i = 0; i < NE; ++i) {
        polished[i] = u[i];
        if (u[i] > (cdb_real)0 && u[i] < upper[i]) {
            cdb_real v = u[i];
            for (j = 0; j < NR; ++j) {
                v += cdb_rows[j * NE + i] * step[j];
            }
            polished[i] = v < (cdb_real)0 ? (cdb_real)0 : (v > upper[i] ? upper[i] : v);
        }
    }
    for (j = 0; j < NR; ++j) {
        cdb_real r = target[j];
        for (i = 0; i < NE; ++i) {
            r -= cdb_rows[j * NE + i] * polished[i];
        }
        if (magnitude(r) > after) {
            after = magnitude(r);
        }
    }
    if (after < worst) {
        for (i = 0; i < NE; ++i) {
            u[i] = polished[i];
        }
        return 1;
    }
    return 0;
}

/* The Allocator's polish (one step), repeated while a step still lowers the residual
 * above POLISH_TOLERANCE (ill-conditioned free engines, at most three steps). */
static void polish(cdb_real u[NE], const cdb_real target[NR], const cdb_real upper[NE]) {
    int round;
    for (round = 0; round < 3; ++round) {
        if (!polish_once(u, target, upper)) {
            break;
        }
    }
}

/* Largest alpha in [0, 1] with alpha * target reachable: the linear program
 *
 *     maximise alpha   subject to   A u - alpha target = 0,   0 <= u <= upper,   0 <= alpha <= 1,
 *
 * by the bounded-variable primal simplex on its dense tableau, Bland's rule (no cycling:
 * the start u = 0, alpha = 0 is fully degenerate), artificial variables fixed at zero
 * starting the basis. The Allocator solves the same program as a QP with a proximal term
 * too small to move its optimum; a vertex of the simplex is that optimum to round-off.
 * Returns -1 when the pivots run out (never seen). */
#define NS (NX + NR)
#define SIMPLEX_MAX_PIVOTS 400
#define SIMPLEX_COST_TOLERANCE ((cdb_real)1e-12)
#define SIMPLEX_PIVOT_TOLERANCE ((cdb_real)1e-11)

static void pivot_on(cdb_real tableau[NR * NS], int r, int entering) {
    cdb_real p = tableau[r * NS + entering];
    int i, j;
    for (j = 0; j < NS; ++j) {
        tableau[r * NS + j] /= p;
    }
    for (i = 0; i < NR; ++i) {
        cdb_real f = tableau[i * NS + entering];
        if (i == r || f == (cdb_real)0) {
            continue;
        }
        for (j = 0; j < NS; ++j) {
            tableau[i * NS + j] -= f * tableau[r * NS + j];
        }
    }
}

static cdb_real largest_scale(const cdb_real target[NR], const cdb_real upper[NE],
                              cdb_real vertex[NE], unsigned char in_basis[NE],
                              int *iterations) {
    cdb_real tableau[NR * NS], basic[NR], hi[NS];
    int basis[NR], is_basic[NS];
    unsigned char at_upper[NS];
    cdb_real alpha;
    int pivot, i, j, r;
    for (j = 0; j < NS; ++j) {
        hi[j] = j < NE ? upper[j] : (j == NE ? (cdb_real)1 : (cdb_real)0);
        at_upper[j] = 0;
        is_basic[j] = -1;
    }
    for (i = 0; i < NR; ++i) {
        for (j = 0; j < NE; ++j) {
            tableau[i * NS + j] = cdb_rows[i * NE + j];
        }
        tableau[i * NS + NE] = -target[i];
        for (j = NX; j < NS; ++j) {
            tableau[i * NS + j] = (j - NX == i) ? (cdb_real)1 : (cdb_real)0;
        }
        basis[i] = NX + i;
        is_basic[NX + i] = i;
        basic[i] = (cdb_real)0;
    }
    for (pivot = 0; pivot < SIMPLEX_MAX_PIVOTS; ++pivot) {
        int entering = -1, leaving = -1, row_alpha = is_basic[NE];
        cdb_real direction, step, best_bound = (cdb_real)0;
        int leaves_upper = 0;
        for (j = 0; j < NS && entering < 0; ++j) {
            cdb_real reduced;
            if (is_basic[j] >= 0 || !(hi[j] > (cdb_real)0)) {
                continue;
            }
            /* Cost -alpha: reduced cost c_j - c_B' B^-1 a_j. */
            reduced = (j == NE) ? (cdb_real)-1 : (cdb_real)0;
            if (row_alpha >= 0) {
                reduced += tableau[row_alpha * NS + j];
            }
            if ((!at_upper[j] && reduced < -SIMPLEX_COST_TOLERANCE) ||
                (at_upper[j] && reduced > SIMPLEX_COST_TOLERANCE)) {
                entering = j;
            }
        }
        if (entering < 0) {
            break; /* optimal */
        }
        *iterations += 1;
        direction = at_upper[entering] ? (cdb_real)-1 : (cdb_real)1;
        step = hi[entering]; /* a bound flip, unless a basic variable stops it first */
        for (i = 0; i < NR; ++i) {
            cdb_real change = -direction * tableau[i * NS + entering];
            cdb_real limit;
            int to_upper;
            if (change < -SIMPLEX_PIVOT_TOLERANCE) {
                limit = basic[i] / -change;
                to_upper = 0;
            } else if (change > SIMPLEX_PIVOT_TOLERANCE) {
                limit = (hi[basis[i]] - basic[i]) / change;
                to_upper = 1;
            } else {
                continue;
            }
            if (limit < (cdb_real)0) {
                limit = (cdb_real)0;
            }
            if (limit < step || (limit == step && leaving >= 0 && basis[i] < basis[leaving])) {
                step = limit;
                leaving = i;
                leaves_upper = to_upper;
            }
        }
        for (i = 0; i < NR; ++i) {
            basic[i] -= direction * step * tableau[i * NS + entering];
        }
        if (leaving < 0) {
            at_upper[entering] = (unsigned char)!at_upper[entering];
            continue;
        }
        best_bound = at_upper[entering] ? hi[entering] - step : step;
        r = leaving;
        at_upper[basis[r]] = (unsigned char)leaves_upper;
        is_basic[basis[r]] = -1;
        pivot_on(tableau, r, entering);
        basis[r] = entering;
        is_basic[entering] = r;
        at_upper[entering] = 0;
        basic[r] = best_bound;
    }
    if (pivot == SIMPLEX_MAX_PIVOTS) {
        return (cdb_real)-1;
    }
    if (is_basic[NE] >= 0) {
        alpha = basic[is_basic[NE]];
    } else {
        alpha = at_upper[NE] ? (cdb_real)1 : (cdb_real)0;
    }
    /* Engines in place of alpha and the artificials in the basis (degenerate pivots: no
     * value changes), so that the basic engines' columns span the rows: the working set
     * the active-set method starts from is then linearly independent. */
    for (r = 0; r < NR; ++r) {
        int entering = -1;
        cdb_real largest = SIMPLEX_PIVOT_TOLERANCE;
        if (basis[r] < NE) {
            continue;
        }
        for (j = 0; j < NE; ++j) {
            if (is_basic[j] < 0 && hi[j] > (cdb_real)0 && magnitude(tableau[r * NS + j]) > largest) {
                largest = magnitude(tableau[r * NS + j]);
                entering = j;
            }
        }
        if (entering < 0) {
            continue;
        }
        {
            int leaving = basis[r];
            cdb_real value = at_upper[entering] ? hi[entering] : (cdb_real)0;
            at_upper[leaving] = (unsigned char)(basic[r] >= hi[leaving] && hi[leaving] > (cdb_real)0);
            is_basic[leaving] = -1;
            pivot_on(tableau, r, entering);
            basis[r] = entering;
            is_basic[entering] = r;
            at_upper[entering] = 0;
            basic[r] = value;
        }
    }
    for (j = 0; j < NE; ++j) {
        in_basis[j] = (unsigned char)(is_basic[j] >= 0);
        vertex[j] = is_basic[j] >= 0 ? basic[is_basic[j]] : (at_upper[j] ? hi[j] : (cdb_real)0);
        vertex[j] = vertex[j] < (cdb_real)0 ? (cdb_real)0 : (vertex[j] > hi[j] ? hi[j] : vertex[j]);
    }
    alpha = alpha < (cdb_real)0 ? (cdb_real)0 : (alpha > (cdb_real)1 ? (cdb_real)1 : alpha);
    if (alpha * largest_magnitude(target, NR) <= ALPHA_RESOLUTION) {
        return (cdb_real)0;
    }
    return alpha;
}

/* The equality-constrained step of the active-set method: with the free engines' columns
 * M = A_F' (n_free x NR), the multipliers l minimising |g_F + M l| and the step
 * p_F = -(g_F + M l) / eps, by Householder QR with column pivoting of M (orthogonal: the
 * residual is exact to round-off even where the free columns are nearly dependent, which
 * the normal equations would square). Columns below RANK_TOLERANCE of the largest are
 * dropped (their multiplier is zero). */
#define RANK_TOLERANCE ((cdb_real)1e-10)
static void equality_step(const unsigned char bound[NE], const cdb_real g[NE], cdb_real p[NE],
                          cdb_real lambda[NR]) {
    cdb_real m[NE * NR], residual[NE], column_norm[NR], diagonal[NR] = {0}, y[NR];
    int order[NR], free_index[NE];
    int n_free = 0, rank = 0, i, j, k;
    cdb_real largest = (cdb_real)0;
    for (i = 0; i < NE; ++i) {
        p[i] = (cdb_real)0;
        if (bound[i] == 0) {
            free_index[n_free] = i;
            residual[n_free] = g[i];
            for (j = 0; j < NR; ++j) {
                m[n_free * NR + j] = cdb_rows[j * NE + i];
            }
            ++n_free;
        }
    }
    for (j = 0; j < NR; ++j) {
        order[j] = j;
        lambda[j] = (cdb_real)0;
        y[j] = (cdb_real)0;
    }
    for (k = 0; k < NR && k < n_free; ++k) {
        int best = k;
        cdb_real norm2 = (cdb_real)0, alpha, vtv = (cdb_real)0;
        for (j = k; j < NR; ++j) {
            cdb_real c = (cdb_real)0;
            for (i = k; i < n_free; ++i) {
                c += m[i * NR + j] * m[i * NR + j];
            }
            column_norm[j] = c;
            if (c > column_norm[best]) {
                best = j;
            }
        }
        if (best != k) {
            int t = order[k];
            order[k] = order[best];
            order[best] = t;
            for (i = 0; i < n_free; ++i) {
                cdb_real v = m[i * NR + k];
                m[i * NR + k] = m[i * NR + best];
                m[i * NR + best] = v;
            }
        }
        norm2 = column_norm[best];
        if (k == 0) {
            largest = (cdb_real)sqrt((double)norm2);
        }
        if (!((cdb_real)sqrt((double)norm2) > RANK_TOLERANCE * largest)) {
            break;
        }
        /* Householder reflection of rows k.. of column k onto its first entry. */
        alpha = (cdb_real)sqrt((double)norm2);
        if (m[k * NR + k] > (cdb_real)0) {
            alpha = -alpha;
        }
        m[k * NR + k] -= alpha;
        for (i = k; i < n_free; ++i) {
            vtv += m[i * NR + k] * m[i * NR + k];
        }
        if (vtv > (cdb_real)0) {
            for (j = k + 1; j < NR; ++j) {
                cdb_real dot = (cdb_real)0;
                for (i = k; i < n_free; ++i) {
                    dot += m[i * NR + k] * m[i * NR + j];
                }
                dot = (cdb_real)2 * dot / vtv;
                for (i = k; i < n_free; ++i) {
                    m[i * NR + j] -= dot * m[i * NR + k];
                }
            }
            {
                cdb_real dot = (cdb_real)0;
                for (i = k; i < n_free; ++i) {
                    dot += m[i * NR + k] * residual[i];
                }
                dot = (cdb_real)2 * dot / vtv;
                for (i = k; i < n_free; ++i) {
                    residual[i] -= dot * m[i * NR + k];
                }
            }
        }
        diagonal[k] = alpha;
        rank = k + 1;
    }
    /* Q'g: the first `rank` entries are fitted by the columns, the rest is the residual. */
    for (k = rank - 1; k >= 0; --k) {
        cdb_real v = -residual[k];
        for (j = k + 1; j < rank; ++j) {
            v -= m[k * NR + j] * y[j];
        }
        y[k] = v / diagonal[k];
    }
    for (k = 0; k < rank; ++k) {
        lambda[order[k]] = y[k];
    }
    /* p_F = -(g_F + M l) / eps, from the multipliers (exact to round-off of M l). */
    for (i = 0; i < n_free; ++i) {
        int e = free_index[i];
        cdb_real v = g[e];
        for (j = 0; j < NR; ++j) {
            v += cdb_rows[j * NE + e] * lambda[j];
        }
        p[e] = -v / EXACT_PROXIMAL;
    }
}

/* Primal active-set method for the least-fuel QP from a feasible u (A u = target, within
 * the bounds): each iteration solves the equality-constrained QP of the free engines
 * exactly, stops at the first bound in the way (which joins the working set), or, at the
 * minimiser of the working set, frees the bound whose multiplier has the wrong sign.
 * Finite; ends with the multipliers of A u = target in `lambda`. Returns 1 at the optimum. */
#define ACTIVE_SET_MAX_ITERATIONS (4 * NE + 20)
#define ACTIVE_SET_DUAL_TOLERANCE ((cdb_real)1e-12)
#define ACTIVE_SET_ROUND_OFF ((cdb_real)1e-13)
static int active_set(const cdb_real upper[NE], const unsigned char in_basis[NE], cdb_real u[NE],
                      cdb_real lambda[NR], int *iterations) {
    unsigned char bound[NE]; /* 0 free, 1 at zero, 2 at its limit */
    cdb_real g[NE], p[NE];
    int iteration, i, j;
    for (i = 0; i < NE; ++i) {
        if (in_basis[i] && upper[i] > (cdb_real)0) {
            bound[i] = 0;
        } else if (!(upper[i] > (cdb_real)0) || u[i] < upper[i]) {
            u[i] = (cdb_real)0;
            bound[i] = 1;
        } else {
            u[i] = upper[i]; /* a nonbasic engine is on one of its bounds */
            bound[i] = 2;
        }
    }
    for (iteration = 0; iteration < ACTIVE_SET_MAX_ITERATIONS; ++iteration) {
        cdb_real step = (cdb_real)1;
        int blocking = -1;
        *iterations += 1;
        for (i = 0; i < NE; ++i) {
            g[i] = EXACT_PROXIMAL * u[i] + cdb_cost[i];
        }
        equality_step(bound, g, p, lambda);
        {
            /* A step of the size of the round-off of g + A'l over eps is no step: the
             * working set's minimiser is reached (moving along it would only drift). */
            cdb_real largest_g = (cdb_real)1;
            cdb_real largest_p = (cdb_real)0;
            for (i = 0; i < NE; ++i) {
                largest_g = magnitude(g[i]) > largest_g ? magnitude(g[i]) : largest_g;
                largest_p = magnitude(p[i]) > largest_p ? magnitude(p[i]) : largest_p;
            }
            if (EXACT_PROXIMAL * largest_p <= ACTIVE_SET_ROUND_OFF * largest_g) {
                for (i = 0; i < NE; ++i) {
                    p[i] = (cdb_real)0;
                }
            }
        }
        for (i = 0; i < NE; ++i) {
            cdb_real limit;
            if (bound[i] != 0 || p[i] == (cdb_real)0) {
                continue;
            }
            limit = p[i] < (cdb_real)0 ? -u[i] / p[i] : (upper[i] - u[i]) / p[i];
            if (limit < step) {
                step = limit < (cdb_real)0 ? (cdb_real)0 : limit;
                blocking = i;
            }
        }
        for (i = 0; i < NE; ++i) {
            if (bound[i] == 0) {
                u[i] += step * p[i];
            }
        }
        if (blocking >= 0) {
            bound[blocking] = p[blocking] < (cdb_real)0 ? 1 : 2;
            u[blocking] = bound[blocking] == 1 ? (cdb_real)0 : upper[blocking];
        } else {
            /* The minimiser of this working set: free the worst wrong-signed bound. */
            cdb_real worst = ACTIVE_SET_DUAL_TOLERANCE;
            int release = -1;
            for (i = 0; i < NE; ++i) {
                cdb_real s, violation;
                if (bound[i] == 0 || !(upper[i] > (cdb_real)0)) {
                    continue;
                }
                s = EXACT_PROXIMAL * u[i] + cdb_cost[i];
                for (j = 0; j < NR; ++j) {
                    s += cdb_rows[j * NE + i] * lambda[j];
                }
                violation = bound[i] == 1 ? -s : s;
                if (violation > worst) {
                    worst = violation;
                    release = i;
                }
            }
            if (release < 0) {
                return 1;
            }
            bound[release] = 0;
        }
    }
    return 0;
}

/* Least fuel at the scaled target; 1 when solved (u polished). Newton on the dual from
 * the last step's multipliers first (the common case: one or two iterations); where it
 * does not converge, the simplex finds a thrust meeting the target (or shows there is
 * none) and the primal active-set method goes from there to the least-fuel one. */
static int least_fuel(const cdb_real target[NR], const cdb_real upper[NE], cdb_real u[NE],
                      int try_newton, cdb_real *alpha, int *iterations, cdb_state *state) {
    qp_data d;
    cdb_real x[NX], saved[NR], reach = (cdb_real)0, scale;
    unsigned char in_basis[NE];
    int i, j;
    d.n = NE;
    d.stride = NE;
    d.a = cdb_rows;
    d.b = target;
    d.c = cdb_cost;
    d.hi = upper;
    d.eps = EXACT_PROXIMAL;
    *alpha = (cdb_real)-1;
    if (try_newton && state->warm_exact) {
        for (j = 0; j < NR; ++j) {
            saved[j] = state->lambda_exact[j];
        }
        if (qp_solve(&d, state->lambda_exact, x, iterations)) {
            for (i = 0; i < NE; ++i) {
                u[i] = x[i];
            }
            polish(u, target, upper);
            return 1;
        }
        /* Keep the last good multipliers: the next target may be near them again. */
        for (j = 0; j < NR; ++j) {
            state->lambda_exact[j] = saved[j];
        }
    }
    for (j = 0; j < NR; ++j) {
        cdb_real r = (cdb_real)0;
        for (i = 0; i < NE; ++i) {
            r += magnitude(cdb_rows[j * NE + i]) * upper[i];
        }
        reach = r > reach ? r : reach;
    }
    if (largest_magnitude(target, NR) > reach) {
        return 0;
    }
    scale = largest_scale(target, upper, u, in_basis, iterations);
    if (scale < (cdb_real)1) {
        *alpha = scale; /* the largest scale of this target (-1: the pivots ran out) */
        return 0;
    }
    if (!active_set(upper, in_basis, u, state->lambda_exact, iterations)) {
        state->warm_exact = 0;
        return 0;
    }
    state->warm_exact = 1;
    polish(u, target, upper);
    return 1;
}

/* k with the largest component of 2^k wrench / reference in (size, 2 size] (as the
 * Allocator's stretch_exponent). */
static int stretch_exponent(const cdb_real wrench[NR], cdb_real size) {
    cdb_real normalised = (cdb_real)0;
    int exponent, extra, j;
    (void)frexp((double)largest_magnitude(wrench, NR), &exponent);
    for (j = 0; j < NR; ++j) {
        cdb_real v = magnitude((cdb_real)ldexp((double)wrench[j], -exponent)) / cdb_wrench_ref[j];
        if (v > normalised) {
            normalised = v;
        }
    }
    (void)frexp((double)(size / normalised), &extra);
    return extra - exponent;
}

static int any_on_limit(const cdb_real u[NE], const cdb_real upper[NE]) {
    int i;
    for (i = 0; i < NE; ++i) {
        if (upper[i] > (cdb_real)0 && u[i] >= upper[i] * ((cdb_real)1 - LIMIT_ACTIVE_RTOL)) {
            return 1;
        }
    }
    return 0;
}

/* Least fuel for a wrench in SI, stretched by 2^k when small (the Allocator's exact and
 * small-demand paths). Returns 1 and the thrust in N when met. */
static int exact_thrust(const cdb_real wrench[NR], const cdb_real upper[NE],
                        cdb_real thrust_N[NE], int try_newton, cdb_real *alpha,
                        int *iterations, cdb_state *state) {
    static const cdb_real levels[N_SMALL_LEVELS] = {(cdb_real)0.1, (cdb_real)1e-2,
                                                    (cdb_real)1e-4, (cdb_real)1e-6};
    cdb_real target[NR], u[NE];
    int i, j, level, k = 0;
    for (j = 0; j < NR; ++j) {
        target[j] = wrench[j] / cdb_wrench_ref[j];
    }
    if (largest_magnitude(target, NR) >= SMALL_DEMAND) {
        if (!least_fuel(target, upper, u, try_newton, alpha, iterations, state)) {
            return 0;
        }
    } else {
        int found = 0;
        for (level = 0; level < N_SMALL_LEVELS; ++level) {
            k = stretch_exponent(wrench, levels[level]);
            if (k < 0) {
                k = 0;
            }
            for (j = 0; j < NR; ++j) {
                target[j] = (cdb_real)ldexp((double)wrench[j], k) / cdb_wrench_ref[j];
            }
            if (least_fuel(target, upper, u, try_newton, alpha, iterations, state)) {
                if (k == 0 || level == N_SMALL_LEVELS - 1 || !any_on_limit(u, upper)) {
                    found = 1;
                    break;
                }
            } else if (k == 0) {
                break;
            }
        }
        if (!found) {
            return 0;
        }
    }
    for (i = 0; i < NE; ++i) {
        cdb_real v = u[i] > upper[i] ? upper[i] : u[i];
        v = v < THRUST_ROUND_OFF ? (cdb_real)0 : v;
        thrust_N[i] = (cdb_real)ldexp((double)(v * cdb_thrust_ref_N), -k);
    }
    return 1;
}

unsigned int cdb_allocate(const cdb_real demand_Nm[3], const cdb_real limit_N[CDB_N_ENGINES],
                          cdb_real thrust_N[CDB_N_ENGINES], cdb_real *scale, int *iterations,
                          cdb_state *state) {
    cdb_real upper[NE], wrench[NR], target[NR], vertex[NE];
    unsigned char in_basis[NE];
    cdb_real size, reach = (cdb_real)0, alpha = (cdb_real)-1, unused;
    int i, j, any = 0;
    *scale = (cdb_real)1;
    for (i = 0; i < NE; ++i) {
        thrust_N[i] = (cdb_real)0;
        upper[i] = limit_N[i] / cdb_thrust_ref_N;
        any |= upper[i] > (cdb_real)0;
        if (upper[i] != state->limit[i]) {
            state->limit[i] = upper[i];
            state->warm_exact = 0;
            state->saturated = 0;
        }
    }
    if (!any) {
        *scale = (cdb_real)0;
        return CDB_FLAG_NO_ENGINE | CDB_FLAG_INFEASIBLE;
    }
    for (j = 0; j < NR; ++j) {
        wrench[j] = j < 3 ? demand_Nm[j] : (cdb_real)0;
        target[j] = wrench[j] / cdb_wrench_ref[j];
    }
    size = largest_magnitude(target, NR);
    if (size == (cdb_real)0) {
        return 0u; /* exactly zero: exactly zero thrust */
    }
    /* After a saturated period the next demand is most likely beyond reach as well: no
     * Newton attempt on it (the simplex answers both questions at once). */
    if (exact_thrust(wrench, upper, thrust_N, !state->saturated, &alpha, iterations, state)) {
        state->saturated = 0;
        return 0u;
    }
    state->saturated = 1;
    if (size >= SMALL_DEMAND && alpha >= (cdb_real)0) {
        /* The simplex of the least-fuel attempt found the largest scale of the demand
         * itself: the same number as for the demand brought to the engines' reach. */
        reach = size;
    } else {
        /* The largest scale along the demand, found for the demand brought to the size
         * of what the engines reach. */
        for (j = 0; j < NR; ++j) {
            cdb_real r = (cdb_real)0;
            for (i = 0; i < NE; ++i) {
                r += magnitude(cdb_rows[j * NE + i]) * upper[i];
            }
            if (r > reach) {
                reach = r;
            }
        }
        for (j = 0; j < NR; ++j) {
            target[j] *= reach / size;
        }
        alpha = largest_scale(target, upper, vertex, in_basis, iterations);
        if (alpha < (cdb_real)0) {
            *scale = (cdb_real)0;
            return CDB_FLAG_INFEASIBLE;
        }
    }
    alpha *= reach / size;
    if (alpha > (cdb_real)1) {
        alpha = (cdb_real)1;
    }
    *scale = alpha;
    if (alpha <= (cdb_real)0) {
        return CDB_FLAG_SATURATED;
    }
    {
        /* The loop's pull-in first; where round-off still puts that torque out of reach
         * (a nearly flat authority, CubeSats failed), ten and a hundred times more. */
        static const cdb_real backoffs[3] = {SATURATION_BACKOFF, (cdb_real)10 * SATURATION_BACKOFF,
                                             (cdb_real)100 * SATURATION_BACKOFF};
        cdb_real applied[NR];
        int attempt;
        for (attempt = 0; attempt < 3; ++attempt) {
            for (j = 0; j < NR; ++j) {
                applied[j] = wrench[j] * (alpha * ((cdb_real)1 - backoffs[attempt]));
            }
            if (exact_thrust(applied, upper, thrust_N, 1, &unused, iterations, state)) {
                return alpha < (cdb_real)1 ? CDB_FLAG_SATURATED : 0u;
            }
        }
    }
    for (i = 0; i < NE; ++i) {
        thrust_N[i] = (cdb_real)0;
    }
    return CDB_FLAG_SATURATED | CDB_FLAG_INFEASIBLE;
}
