/* plate_friction.c -- the friction ellipsoid and its maximum-dissipation solve.
 *
 * Plate friction at a patch (paper Eq. 6). The friction
 * impulse p = (p_x, p_y, p_r) of one implicit velocity-level step minimises
 *
 *     f(p) = 0.5 p^T W p + p^T b    over    p^T E^-2 p <= cap^2,
 *
 * whose stationarity condition is exactly the maximum-dissipation law: the
 * slip after the step, u = b + W p, satisfies W p + b = -nu E^-2 p, i.e.
 * p = -E^2 u / nu, p on the ellipsoid whenever u != 0 (Eq. 6).
 *
 * Scaled coordinates used throughout: y = E^-1 p (the ellipsoid becomes the
 * ball |y| <= cap), K = E W E, c = E b, and the eigen-decomposition
 * K = Q diag(lam) Q^T done once in exdex_friction_prepare. With tildes for
 * components in the eigenbasis (c~ = Q^T c):
 *
 *   stick   iff |K^-1 c| <= cap, i.e. sum (c~_i / lam_i)^2 <= cap^2;
 *           then y = -K^-1 c (p = -W^-1 b) and u = 0 exactly.
 *   slip    y(s) = -cap (s I + cap K)^-1 c, i.e. y~_i = -cap x_i(s) with
 *           x_i(s) = c~_i / (s + cap lam_i), and s > 0 the root of the
 *           secular equation |x(s)| = 1. |x| is strictly decreasing, > 1 at
 *           s = 0 when sliding and < 1 at s = |c|, so the root is bracketed.
 *           The multiplier s equals sigma = |E u| (the Fritz-John multiplier
 *           of the paper's four equations, see the MULTIROOT solver), because
 *           E u = c + K y has eigen-components c~_i - cap lam_i x_i = s x_i.
 *
 * Three solvers for the sliding case, all after the same stick test:
 *   SCALAR     safeguarded Newton on g(s) = 1/|x(s)| - 1 (More-Sorensen; g is
 *              nearly linear and concave, so Newton from the left climbs
 *              monotonically to the root), kept in a bracket with a bisection
 *              fallback. No allocation, no GSL call: the hot path.
 *   BRENT      the secular equation phi(s) = |x(s)| - 1 = 0 with GSL's Brent
 *              solver on [0, |c|].
 *   MULTIROOT  the paper's route: the Fritz-John conditions of Eq. 6 as four
 *              quadratic equations in (p, sigma), GSL hybridsj (then GSL's
 *              Newton to polish), in the original coordinates (W, not K),
 *              from starts that do not use the secular solution; only when
 *              all of them fail (about 0.2 % of fuzzed solves, strongly
 *              anisotropic K near the start of slip) from the secular
 *              solution, which is returned itself if even that fails.
 * Every loop is capped (Newton and Brent 200 iterations, hybridsj 100 per
 * start, Newton polish 10, GSL's Jacobi SVD its own sweep limit).
 *
 * Accuracy. K = E W E is strongly graded when e_r << e_t (cond(K) ~
 * cond(W) (e_t/e_r)^2, 1e12 and more), so its eigen-decomposition comes from
 * a one-sided Jacobi SVD (relative accuracy even for the smallest
 * eigenvalues), and the stick and slip impulses get one correction step with
 * the residual formed with W itself: the results are then as accurate as the
 * conditioning of W allows (about cond(W) eps relative), whatever e.
 * Scale. The solve runs at unit scale after exact power-of-two rescalings
 * (homogeneity in (b, cap), and the invariances (e, cap) -> (k e, cap / k),
 * (W, cap) -> (W / k, k cap); see exdex_friction_solve), so b, cap, W and e
 * may lie anywhere in the double range.
 */
#include "exdex.h"
#include "util.h"
#include "tolerances.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_matrix.h>
#include <gsl/gsl_multiroots.h>
#include <gsl/gsl_roots.h>
#include <gsl/gsl_vector.h>

/* max of two non-NaN numbers (fmax is a library call at -O2) */
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* ------------------------------------------------------------ patch e_r */

/* Mean distance of a uniform disc of radius R from its centre:
 * (1 / (pi R^2)) int_0^R r 2 pi r dr = 2R/3. */
double exdex_er_disc(double radius)
{
    if (!(radius > 0.0) || !isfinite(radius)) return NAN;
    return radius * (2.0 / 3.0); /* no overflow for radius near DBL_MAX */
}

/* Mean distance of the uniform rectangle [-a, a] x [-b, b] from its centre
 * (Howe & Cutkosky), d = sqrt(a^2 + b^2):
 *   e_r = [a b d/3 + (a^3/6) ln((b + d)/a) + (b^3/6) ln((a + d)/b)] / (a b).
 * Evaluated without overflow or underflow in the ratio r = a / b <= 1 of the
 * shorter to the longer half side (ln((b + d)/a) = asinh(1/r),
 * ln((a + d)/b) = asinh(r)):
 *   e_r = b [sqrt(1 + r^2)/3 + r^2 asinh(1/r)/6 + asinh(r)/(6 r)],
 * the bracket between 1/2 (thin strip, r -> 0: the mean |y| along the long
 * side) and (sqrt2 + asinh(1))/3 = 0.765 (square). So the result is finite
 * and positive for every finite positive a, b (subnormal only when b is). */
double exdex_er_rectangle(double half_a, double half_b)
{
    double a, b, r, t;
    if (!(half_a > 0.0) || !(half_b > 0.0) || !isfinite(half_a) || !isfinite(half_b)) return NAN;
    a = half_a < half_b ? half_a : half_b;
    b = half_a < half_b ? half_b : half_a;
    r = a / b;  /* in [0, 1]: 0 or subnormal when a / b underflows */
    t = sqrt(1.0 + r * r) / 3.0;
    /* r^2 asinh(1/r) ~ r^2 ln(2/r): below 1e-297 for r <= 1e-150 */
    if (r > 1e-150) t += r * r * asinh(1.0 / r) / 6.0;
    /* asinh(r) / r = 1 - r^2/6 + ...: 1 to rounding for r < 2^-27 */
    t += r > 0x1p-27 ? asinh(r) / (6.0 * r) : 1.0 / 6.0;
    return b * t;
}

/* ------------------------------------------------------------ workspace */

struct exdex_friction_ws {
    gsl_root_fsolver *brent;         /* BRENT */
    gsl_multiroot_fdfsolver *hybrid; /* MULTIROOT, n = 4 */
    gsl_multiroot_fdfsolver *newton; /* MULTIROOT polish, n = 4 */
    gsl_vector *x0;                  /* MULTIROOT start, length 4 */
};

exdex_friction_ws *exdex_friction_ws_alloc(void)
{
    exdex_friction_ws *ws = calloc(1, sizeof *ws);
    if (!ws) return NULL;
    ws->brent = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    ws->hybrid = gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_hybridsj, 4);
    ws->newton = gsl_multiroot_fdfsolver_alloc(gsl_multiroot_fdfsolver_newton, 4);
    ws->x0 = gsl_vector_alloc(4);
    if (!ws->brent || !ws->hybrid || !ws->newton || !ws->x0) {
        exdex_friction_ws_free(ws);
        return NULL;
    }
    return ws;
}

void exdex_friction_ws_free(exdex_friction_ws *ws)
{
    if (!ws) return;
    if (ws->brent) gsl_root_fsolver_free(ws->brent);
    if (ws->hybrid) gsl_multiroot_fdfsolver_free(ws->hybrid);
    if (ws->newton) gsl_multiroot_fdfsolver_free(ws->newton);
    if (ws->x0) gsl_vector_free(ws->x0);
    free(ws);
}

/* -------------------------------------------------------------- prepare */

/* Eigen-decomposition of the Gram matrix G = S L L^T S = B^T B, B = L^T S,
 * S = diag(s), L lower triangular (Lc row-major, upper part ignored), from
 * the SVD B = U Sigma V^T by one-sided Jacobi (GSL): G = V Sigma^2 V^T.
 * One-sided Jacobi gets even the smallest singular values of a
 * column-scaled B to high relative accuracy (Demmel & Veselic 1992), where
 * a QR-based symmetric eigensolver gives small eigenvalues only to eps |G|
 * absolute. Ascending lam, eigenvectors in the columns of V. No workspace. */
static int gram_eigen(const double Lc[9], const double s[3], double lam[3], double V[9])
{
    double B[9], sv[3];
    gsl_matrix_view Bm = gsl_matrix_view_array(B, 3, 3), Vm = gsl_matrix_view_array(V, 3, 3);
    gsl_vector_view Sv = gsl_vector_view_array(sv, 3), Lv = gsl_vector_view_array(lam, 3);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) B[3 * i + j] = (j >= i ? Lc[3 * j + i] : 0.0) * s[j];
    if (gsl_linalg_SV_decomp_jacobi(&Bm.matrix, &Vm.matrix, &Sv.vector) != GSL_SUCCESS) return 0;
    for (int i = 0; i < 3; i++) lam[i] = sv[i] * sv[i];
    return gsl_eigen_symmv_sort(&Lv.vector, &Vm.matrix, GSL_EIGEN_SORT_VAL_ASC) == GSL_SUCCESS;
}

int exdex_friction_prepare(exdex_friction_prep *prep, const double W[9],
                           const double e[3])
{
    double Ws[9], Lc[9], V[9], lam[3], dinv[3], K[9], wmax = 0.0;
    gsl_matrix_view Lm;
    int i, j;

    if (!prep || !W || !e) return EXDEX_EINVAL;
    if (!ex_finite_n(W, 9) || !ex_finite_n(e, 3)) return EXDEX_EINVAL;
    for (i = 0; i < 3; i++)
        if (!(e[i] > 0.0)) return EXDEX_EINVAL;

    /* Symmetric to FRICTION_SYM_REL of the largest entry; keep the mean. */
    for (i = 0; i < 9; i++) wmax = fmax(wmax, fabs(W[i]));
    if (!(wmax > 0.0)) return EXDEX_EINVAL;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            if (fabs(W[3 * i + j] - W[3 * j + i]) > FRICTION_SYM_REL * wmax) return EXDEX_EINVAL;
            Ws[3 * i + j] = 0.5 * (W[3 * i + j] + W[3 * j + i]);
        }

    /* Positive definite: Cholesky W = L L^T succeeds (GSL_EDOM otherwise)... */
    memcpy(Lc, Ws, sizeof Lc);
    Lm = gsl_matrix_view_array(Lc, 3, 3);
    if (gsl_linalg_cholesky_decomp1(&Lm.matrix) != GSL_SUCCESS) return EXDEX_EINVAL;

    /* ... and not singular to working precision: eigenvalues of the
     * unit-diagonal D^-1 W D^-1 = Gram matrix of L^T D^-1. */
    for (i = 0; i < 3; i++) dinv[i] = 1.0 / sqrt(Ws[4 * i]);
    if (!gram_eigen(Lc, dinv, lam, V)) return EXDEX_EINVAL;
    if (!(lam[0] > lam[2] / FRICTION_MAX_COND)) return EXDEX_EINVAL;

    /* K = E W E = Gram matrix of L^T E. K is strongly graded when
     * e_r << e_t: cond(K) ~ cond(W) (e_t / e_r)^2. */
    if (!gram_eigen(Lc, e, lam, V)) return EXDEX_EINVAL;
    /* eigenvalues normal numbers (no underflow) and K representable */
    if (!(lam[0] >= DBL_MIN) || !isfinite(lam[2])) return EXDEX_EINVAL;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++) {
            K[3 * i + j] = e[i] * Ws[3 * i + j] * e[j];
            if (!isfinite(K[3 * i + j])) return EXDEX_EINVAL;
        }
    memcpy(prep->W, Ws, sizeof Ws);
    memcpy(prep->K, K, sizeof K);
    memcpy(prep->Q, V, sizeof V);
    memcpy(prep->lam, lam, sizeof lam);
    memcpy(prep->e, e, 3 * sizeof(double));
    return EXDEX_OK;
}

/* ---------------------------------------------------------------- solve */

/* Data of the secular equation: c~ and a_i = cap lam_i. */
typedef struct secular {
    double ct[3];
    double a[3];
} secular;

/* |x(s)|^2 and q(s) = sum x_i^2 / (s + a_i) (so d|x|^2/ds = -2 q). */
static inline double secular_norm2(const secular *sec, double s, double *q)
{
    double n2 = 0.0, qq = 0.0;
    for (int i = 0; i < 3; i++) {
        double inv = 1.0 / (s + sec->a[i]);
        double x = sec->ct[i] * inv;
        n2 += x * x;
        qq += x * x * inv;
    }
    if (q) *q = qq;
    return n2;
}

/* SCALAR: safeguarded Newton on g(s) = 1/|x(s)| - 1, root in (0, |c|).
 * Newton step for g: s+ = s + |x|^2 (|x| - 1) / q (More-Sorensen with radius
 * 1). Stops when |x| = 1 to rounding (4 eps; y = -cap x is then on the ball
 * to rounding, and a root s closer than that is not determined by the data)
 * or when the step is below 2 eps relative. Returns the iteration count, or
 * -1 if it did not converge. */
static int secular_newton(const secular *sec, double hi, double *root)
{
    /* |x(s)| >= |c| / (s + a_max), so the root is >= |c| - a_max: start
     * there (left of the root, where Newton on the concave g climbs
     * monotonically), or at 0. */
    double amax = dmax(sec->a[0], dmax(sec->a[1], sec->a[2]));
    double lo = 0.0, s = dmax(0.0, hi - amax);
    for (int it = 1; it <= FRICTION_SECULAR_MAX; it++) {
        double q, n2 = secular_norm2(sec, s, &q), nx = sqrt(n2), snew;
        if (fabs(nx - 1.0) <= FRICTION_ROUND_ULPS * DBL_EPSILON || (s == 0.0 && nx <= 1.0)) {
            /* (s = 0: slip just beginning, |K^-1 c| = cap to rounding) */
            *root = s;
            return it;
        }
        if (nx > 1.0)
            lo = s;  /* g(s) < 0: root to the right */
        else
            hi = s;  /* g(s) >= 0: root to the left (or here) */
        snew = s + n2 * (nx - 1.0) / q;
        if (!(snew > lo && snew < hi)) snew = 0.5 * (lo + hi);  /* bisect */
        if (fabs(snew - s) <= 2.0 * DBL_EPSILON * snew || hi - lo <= 2.0 * DBL_EPSILON * hi) {
            *root = snew;
            return it;
        }
        s = snew;
    }
    return -1;
}

/* BRENT: phi(s) = |x(s)| - 1, strictly decreasing. */
static double secular_phi(double s, void *params)
{
    return sqrt(secular_norm2((const secular *)params, s, NULL)) - 1.0;
}

static int secular_brent(gsl_root_fsolver *solver, secular *sec, double hi,
                         double *root)
{
    gsl_function fn;
    double lo = 0.0;
    fn.function = secular_phi;
    fn.params = sec;
    if (secular_phi(hi, sec) >= 0.0) {
        *root = hi;  /* as in secular_newton */
        return 1;
    }
    if (secular_phi(lo, sec) <= 0.0) {
        *root = lo;  /* slip just beginning, |K^-1 c| = cap to rounding */
        return 1;
    }
    if (gsl_root_fsolver_set(solver, &fn, lo, hi) != GSL_SUCCESS) return -1;
    for (int it = 1; it <= FRICTION_SECULAR_MAX; it++) {
        double s;
        if (gsl_root_fsolver_iterate(solver) != GSL_SUCCESS) return -1;
        s = gsl_root_fsolver_root(solver);
        lo = gsl_root_fsolver_x_lower(solver);
        hi = gsl_root_fsolver_x_upper(solver);
        /* Bracket 4 eps relative (Brent's own smallest step is 0.5 eps |s|,
         * so this is reachable), or |x(s)| = 1 to rounding as for SCALAR. */
        if (gsl_root_test_interval(lo, hi, DBL_MIN, FRICTION_ROUND_ULPS * DBL_EPSILON) == GSL_SUCCESS
            || (s > 0.0 && fabs(secular_phi(s, sec)) <= FRICTION_ROUND_ULPS * DBL_EPSILON)) {
            *root = s;
            return it;
        }
    }
    return -1;
}

/* MULTIROOT: the Fritz-John conditions of Eq. 6 in the
 * unknowns (p_1, p_2, p_3, sigma):
 *   F_i = sigma p_i + cap e_i^2 (b + W p)_i = 0,   i = 1..3,
 *   F_4 = sum p_i^2 / e_i^2 - cap^2 = 0.
 * The residual is evaluated exactly in this form, with W (not K). The solver
 * sees it diagonally scaled, which changes neither the roots nor the Newton
 * steps, only what hybridsj's trust region and our stopping test call
 * "small": unknowns X = (p_i / (cap e_i), sigma / |E b|), all O(1) at the
 * root, and rows F_i / (cap e_i |E b|), F_4 / (2 cap^2), all O(1). */
typedef struct fritz_john {
    const double *W, *e, *b;
    double cap;
    double col[4];  /* (p, sigma) = col * X */
    double row[4];  /* residual rows multiplied by row */
} fritz_john;

static void fj_unscale(const fritz_john *fj, const gsl_vector *X, double p[3], double *sig)
{
    for (int i = 0; i < 3; i++) p[i] = fj->col[i] * gsl_vector_get(X, i);
    *sig = fj->col[3] * gsl_vector_get(X, 3);
}

static int fj_f(const gsl_vector *X, void *params, gsl_vector *F)
{
    const fritz_john *fj = params;
    double p[3], u[3], sig, n = 0.0;
    fj_unscale(fj, X, p, &sig);
    ex_mulmv3(u, fj->W, p);
    for (int i = 0; i < 3; i++) {
        double ei2 = fj->e[i] * fj->e[i];
        u[i] += fj->b[i];
        gsl_vector_set(F, i, fj->row[i] * (sig * p[i] + fj->cap * ei2 * u[i]));
        n += p[i] * p[i] / ei2;
    }
    gsl_vector_set(F, 3, fj->row[3] * (n - fj->cap * fj->cap));
    return GSL_SUCCESS;
}

/* Analytic Jacobian: dF_i/dp_j = sigma delta_ij + cap e_i^2 W_ij,
 * dF_i/dsigma = p_i, dF_4/dp_j = 2 p_j / e_j^2, dF_4/dsigma = 0. */
static int fj_df(const gsl_vector *X, void *params, gsl_matrix *J)
{
    const fritz_john *fj = params;
    double p[3], sig;
    fj_unscale(fj, X, p, &sig);
    for (int i = 0; i < 3; i++) {
        double ei2 = fj->e[i] * fj->e[i];
        for (int j = 0; j < 3; j++)
            gsl_matrix_set(J, i, j, fj->row[i] * fj->col[j]
                                        * ((i == j ? sig : 0.0) + fj->cap * ei2 * fj->W[3 * i + j]));
        gsl_matrix_set(J, i, 3, fj->row[i] * fj->col[3] * p[i]);
        gsl_matrix_set(J, 3, i, fj->row[3] * fj->col[i] * 2.0 * p[i] / ei2);
    }
    gsl_matrix_set(J, 3, 3, 0.0);
    return GSL_SUCCESS;
}

static int fj_fdf(const gsl_vector *X, void *params, gsl_vector *F, gsl_matrix *J)
{
    fj_f(X, params, F);
    return fj_df(X, params, J);
}

/* Start: p0 = dir scaled onto the ellipsoid, sigma0 = |E u(p0)|. */
static int fj_start(gsl_vector *x0, const fritz_john *fj, const double dir[3])
{
    double n = 0.0, p[3], u[3], su = 0.0;
    for (int i = 0; i < 3; i++) n += dir[i] * dir[i] / (fj->e[i] * fj->e[i]);
    n = sqrt(n);
    if (!(n > 0.0) || !isfinite(n)) return 0;
    for (int i = 0; i < 3; i++) p[i] = fj->cap * dir[i] / n;
    ex_mulmv3(u, fj->W, p);
    for (int i = 0; i < 3; i++) {
        double eu = fj->e[i] * (u[i] + fj->b[i]);
        su += eu * eu;
        gsl_vector_set(x0, i, p[i] / fj->col[i]);
    }
    su = sqrt(su);
    if (!(su > 0.0) || !isfinite(su)) return 0;
    gsl_vector_set(x0, 3, su / fj->col[3]);
    return 1;
}


/* Relative residual of the unscaled equations: max_i |F_i| over the sum of
 * the magnitudes of the terms F_i is made of. A value of a few eps means the
 * point is an exact root of equations perturbed at rounding level. */
static double fj_relres(const fritz_john *fj, const double X[4])
{
    double p[3], sig, n = 0.0, rel = 0.0;
    for (int i = 0; i < 3; i++) p[i] = fj->col[i] * X[i];
    sig = fj->col[3] * X[3];
    for (int i = 0; i < 3; i++) {
        double ei2 = fj->e[i] * fj->e[i], u = fj->b[i], ua = fabs(fj->b[i]), f, t;
        for (int j = 0; j < 3; j++) {
            u += fj->W[3 * i + j] * p[j];
            ua += fabs(fj->W[3 * i + j] * p[j]);
        }
        f = sig * p[i] + fj->cap * ei2 * u;
        t = fabs(sig * p[i]) + fj->cap * ei2 * ua;
        rel = fmax(rel, fabs(f) / t);
        n += p[i] * p[i] / ei2;
    }
    return fmax(rel, fabs(n - fj->cap * fj->cap) / (n + fj->cap * fj->cap));
}

/* sigma > 0, or sigma zero to rounding: the point with sigma set to 0 is a
 * root as well, to FJ_SIGMA_ZERO relative (slip just beginning, u ~ 0, where the
 * rounding of the data leaves the sign of sigma undetermined). Roots with a
 * real sigma < 0 (setting it to 0 leaves an O(1) residual) are rejected. */
static int fj_sigma_ok(const fritz_john *fj, const double X[4])
{
    double X0[4];
    if (X[3] > 0.0) return 1;
    X0[0] = X[0];
    X0[1] = X[1];
    X0[2] = X[2];
    X0[3] = 0.0;
    return fj_relres(fj, X0) <= FJ_SIGMA_ZERO;
}

static double fj_resid(const gsl_vector *f)
{
    double r = 0.0;
    for (int i = 0; i < 4; i++) r = fmax(r, fabs(gsl_vector_get(f, i)));
    return r;
}

/* One run from x0: hybridsj (globally convergent dogleg) until the scaled
 * residual is below FJ_HYBRID_DONE, then GSL's plain Newton solver, quadratically
 * convergent from there, to polish the root to rounding level (hybridsj's
 * trust region crawls in the narrow valleys of strongly anisotropic cases
 * and stalls on the rounding noise of ill-conditioned ones). Of the
 * iterates with an admissible sigma (fj_sigma_ok), the one of smallest
 * relative residual is kept, and accepted if that is below FJ_RELRES.
 * Adds its iterations (hybridsj and Newton) to *iters. Returns 1 on an
 * accepted root, the scaled root in X. */
static int fj_run(exdex_friction_ws *ws, gsl_multiroot_function_fdf *fdf, double X[4],
                  int *iters)
{
    const fritz_john *fj = fdf->params;
    gsl_multiroot_fdfsolver *hy = ws->hybrid, *nt = ws->newton;
    int found = 0, resets = 0;
    double best = HUGE_VAL;
    if (gsl_multiroot_fdfsolver_set(hy, fdf, ws->x0) != GSL_SUCCESS) return 0;
    for (int it = 1; it <= FJ_HYBRID_MAX; it++) {
        int st = gsl_multiroot_fdfsolver_iterate(hy);
        (*iters)++;
        if (st != GSL_SUCCESS || !ex_finite_n(hy->x->data, 4)) return 0;
        if (fj_resid(hy->f) <= FJ_HYBRID_DONE) {
            found = 1;
            break;
        }
        /* Keep the search in sigma > 0, where the wanted root is: an iterate
         * that crossed to sigma < 0 is put back at sigma = 0.01 |sigma| and
         * hybridsj restarted there (a projected step; 10 times at most). A
         * plain hybridsj run otherwise often settles on a root with sigma < 0
         * when the wanted sigma is small. */
        if (gsl_vector_get(hy->x, 3) < 0.0 && resets < FJ_RESETS_MAX) {
            resets++;
            gsl_vector_memcpy(ws->x0, hy->x);
            gsl_vector_set(ws->x0, 3, -0.01 * gsl_vector_get(hy->x, 3));
            if (gsl_multiroot_fdfsolver_set(hy, fdf, ws->x0) != GSL_SUCCESS) return 0;
        }
    }
    if (!found) return 0;
    for (int i = 0; i < 4; i++) X[i] = gsl_vector_get(hy->x, i);
    if (fj_sigma_ok(fj, X)) best = fj_relres(fj, X);
    if (gsl_multiroot_fdfsolver_set(nt, fdf, hy->x) != GSL_SUCCESS) return 0;
    for (int it = 1; it <= FJ_NEWTON_MAX && best > FRICTION_ROUND_ULPS * DBL_EPSILON; it++) {
        double dx = 0.0, rel;
        int st = gsl_multiroot_fdfsolver_iterate(nt);
        (*iters)++;
        if (st != GSL_SUCCESS || !ex_finite_n(nt->x->data, 4)) break;
        rel = fj_relres(fj, nt->x->data);
        if (rel < best && fj_sigma_ok(fj, nt->x->data)) {
            best = rel;
            for (int i = 0; i < 4; i++) X[i] = gsl_vector_get(nt->x, i);
        }
        for (int i = 0; i < 4; i++)
            dx = fmax(dx, fabs(gsl_vector_get(nt->dx, i)) / fmax(1.0, fabs(X[i])));
        if (dx <= FRICTION_ROUND_ULPS * DBL_EPSILON) break;
    }
    return best <= FJ_RELRES;
}

/* Stick impulse p = -W^-1 b = E y, y = -Q diag(1/lam) c~, plus one step of
 * iterative refinement with the residual b + W p formed with W itself: the
 * eigen-decomposition of K = E W E carries errors of order eps |K| that the
 * scaling by E can magnify (e_r << e_t); the refinement brings p back to the
 * accuracy set by W alone. */
static void stick_impulse(const exdex_friction_prep *prep, const double b[3],
                          const double ct[3], double p[3])
{
    const double *e = prep->e, *lam = prep->lam;
    double yt[3], y[3], r[3];
    for (int i = 0; i < 3; i++) yt[i] = -ct[i] / lam[i];
    ex_mulmv3(y, prep->Q, yt);
    for (int i = 0; i < 3; i++) p[i] = e[i] * y[i];
    ex_mulmv3(r, prep->W, p);
    for (int i = 0; i < 3; i++) r[i] = e[i] * (r[i] + b[i]);
    ex_mulmtv3(yt, prep->Q, r);
    for (int i = 0; i < 3; i++) yt[i] = -yt[i] / lam[i];
    ex_mulmv3(y, prep->Q, yt);
    for (int i = 0; i < 3; i++) p[i] += e[i] * y[i];
}

/* Sliding solution from the secular root s: y~ = -cap x(s), nu = s / cap
 * (y = -(K + nu I)^-1 c), then one Newton step on the full optimality system
 *     G1 = (K + nu I) y + c = E (b + W p) + nu y = 0,  G2 = (|y|^2 - cap^2)/2 = 0
 * with G1 formed with W (as for the stick impulse), solved in the eigenbasis:
 *     dnu = (G2 - y~.D G1~) / (y~.D y~),  dy~ = -D (G1~ + y~ dnu),
 * D = diag(1 / (lam + nu)). Writes p = E Q y~ and returns nu. */
static double slip_impulse(const exdex_friction_prep *prep, const double b[3],
                           const double ct[3], double cap, double s, double p[3])
{
    const double *e = prep->e, *lam = prep->lam;
    double yt[3], y[3], g[3], gt[3], d[3], nu = s / cap, g2, A = 0.0, B = 0.0, dnu;
    for (int i = 0; i < 3; i++) yt[i] = -cap * ct[i] / (s + cap * lam[i]);
    ex_mulmv3(y, prep->Q, yt);
    for (int i = 0; i < 3; i++) p[i] = e[i] * y[i];
    ex_mulmv3(g, prep->W, p);
    for (int i = 0; i < 3; i++) g[i] = e[i] * (g[i] + b[i]) + nu * y[i];
    g2 = 0.5 * ((ex_dot3(y, y) - cap * cap));
    ex_mulmtv3(gt, prep->Q, g);
    for (int i = 0; i < 3; i++) {
        d[i] = 1.0 / (lam[i] + nu);
        A += yt[i] * d[i] * gt[i];
        B += yt[i] * yt[i] * d[i];
    }
    dnu = (g2 - A) / B;
    if (!(nu + dnu > 0.0) || !isfinite(dnu)) return nu;  /* keep the unrefined root */
    for (int i = 0; i < 3; i++) yt[i] -= d[i] * (gt[i] + yt[i] * dnu);
    /* Back onto the ball |y| = cap (a second-order change; it matters only
     * when K is so ill-conditioned that the linearisation is poor). */
    g2 = cap / sqrt(yt[0] * yt[0] + yt[1] * yt[1] + yt[2] * yt[2]);
    if (!isfinite(g2)) return nu;
    for (int i = 0; i < 3; i++) yt[i] *= g2;
    ex_mulmv3(y, prep->Q, yt);
    for (int i = 0; i < 3; i++) p[i] = e[i] * y[i];
    return nu + dnu;
}

static void result_nan(exdex_friction_result *res)
{
    for (int i = 0; i < 3; i++) res->p[i] = res->u[i] = NAN;
    res->sigma = NAN;
    res->stick = 0;
    res->iterations = 0;
}

/* Sliding result from an impulse p on (or within rounding of) the
 * ellipsoid and the multiplier nu = sigma / cap >= 0: p is put on the
 * ellipsoid exactly to rounding, |E^-1 p| = cap (the refinement and, for
 * MULTIROOT, the acceptance test leave it there only to about
 * cond(K) eps), then the slip comes from the maximum-dissipation law itself,
 * u = -nu E^-2 p (Eq. 6; equal to b + W p at the solution, but free of the
 * cancellation b + W p suffers when the slip is tiny next to b, so p . u <= 0
 * holds exactly), and sigma = |E u| = nu |E^-1 p|. */
static void slip_finish(const exdex_friction_prep *prep, double cap, double nu,
                        exdex_friction_result *res)
{
    const double *e = prep->e;
    double n = 0.0, un = 0.0;
    if (!(nu >= 0.0)) nu = 0.0;
    for (int i = 0; i < 3; i++) {
        double y = (res->p[i] / e[i]) / cap;  /* no underflow of e cap */
        n += y * y;
    }
    n = sqrt(n);
    if (n > 0.0 && isfinite(n))
        for (int i = 0; i < 3; i++) res->p[i] /= n;
    for (int i = 0; i < 3; i++) {
        res->u[i] = -nu * res->p[i] / (e[i] * e[i]);
        un += e[i] * e[i] * res->u[i] * res->u[i];
    }
    res->sigma = sqrt(un);
    res->stick = 0;
}

/* The secular root s (SCALAR: safeguarded Newton, otherwise GSL Brent) and
 * the refined sliding impulse p from it. Returns the iteration count, or -1
 * if the root was not found. *s receives the refined multiplier s = nu cap. */
static int solve_secular(const exdex_friction_prep *prep, const double b[3],
                         const double ct[3], double cap, double cn, int solver,
                         exdex_friction_ws *ws, double *s, double p[3])
{
    secular sec;
    int it;
    double root = 0.0;
    for (int i = 0; i < 3; i++) {
        sec.ct[i] = ct[i];
        sec.a[i] = cap * prep->lam[i];
    }
    if (solver == EXDEX_SOLVER_SCALAR)
        it = secular_newton(&sec, cn, &root);
    else
        it = secular_brent(ws->brent, &sec, cn, &root);
    if (it < 0 || !(root >= 0.0)) return -1;
    *s = cap * slip_impulse(prep, b, ct, cap, root, p);
    return it;
}

/* MULTIROOT, sliding case: the Fritz-John system from up to five starts, none
 * of them the secular solution (that one is the fallback, see below):
 *   0. the warm guess (e.g. the previous step's impulse), if given;
 *   1. the stick impulse -W^-1 b scaled onto the ellipsoid (exact in the
 *      limit of slip just beginning);
 *   2. -E^2 b, i.e. p = -cap E^2 b / |E b| (exact in the limit of fast slip);
 *   3. -E^2 W b, a third direction;
 *   4. start 1 with a 100 times smaller sigma.
 * Each start gets sigma0 = |E u(p0)| (start 4 excepted). The positive-sigma
 * root is unique (it is the minimiser), so any accepted root is the answer. */
static int solve_multiroot(const exdex_friction_prep *prep, const double b[3],
                           const double ct[3], double cap, double cn,
                           exdex_friction_ws *ws, const double *warm,
                           exdex_friction_result *res)
{
    const double *e = prep->e;
    fritz_john fj;
    gsl_multiroot_function_fdf fdf;
    double dir[3], X[4];
    int ok = 0, iters = 0;

    fj.W = prep->W;
    fj.e = e;
    fj.b = b;
    fj.cap = cap;
    for (int i = 0; i < 3; i++) {
        fj.col[i] = cap * e[i];
        fj.row[i] = 1.0 / (cap * e[i] * cn);
    }
    fj.col[3] = cn;
    fj.row[3] = 0.5 / (cap * cap);
    fdf.f = fj_f;
    fdf.df = fj_df;
    fdf.fdf = fj_fdf;
    fdf.n = 4;
    fdf.params = &fj;

    for (int start = 0; start < 5 && !ok; start++) {
        int have = 0;
        if (start == 0) {
            if (warm) have = fj_start(ws->x0, &fj, warm);
        } else if (start == 1 || start == 4) {
            stick_impulse(prep, b, ct, dir);
            have = fj_start(ws->x0, &fj, dir);
            if (start == 4) gsl_vector_set(ws->x0, 3, 0.01 * gsl_vector_get(ws->x0, 3));
        } else if (start == 2) {
            for (int i = 0; i < 3; i++) dir[i] = -e[i] * e[i] * b[i];
            have = fj_start(ws->x0, &fj, dir);
        } else {
            ex_mulmv3(dir, prep->W, b);
            for (int i = 0; i < 3; i++) dir[i] *= -e[i] * e[i];
            have = fj_start(ws->x0, &fj, dir);
        }
        if (have) ok = fj_run(ws, &fdf, X, &iters);
    }
    if (!ok) {
        /* Fallback (documented in exdex.h): none of the independent starts
         * converged (hybridsj stalls in some strongly anisotropic cases,
         * cond(K) ~ 1e12, when the slip is just beginning). Start 5 is the
         * secular solution: polished on the Fritz-John system and accepted
         * by the same residual test, or, if even that fails, returned as it
         * is (it is the same minimiser). */
        double s = 0.0, p[3];
        int it = solve_secular(prep, b, ct, cap, cn, EXDEX_SOLVER_SCALAR, ws, &s, p);
        if (it < 0) {
            res->iterations = iters;
            return EXDEX_ENOCONV;
        }
        iters += it;
        for (int i = 0; i < 3; i++) gsl_vector_set(ws->x0, i, p[i] / fj.col[i]);
        gsl_vector_set(ws->x0, 3, s / fj.col[3]);
        ok = fj_run(ws, &fdf, X, &iters);
        if (!ok) {
            for (int i = 0; i < 3; i++) X[i] = p[i] / fj.col[i];
            X[3] = s / fj.col[3];
        }
    }
    res->iterations = iters;

    /* The impulse from the root, sigma = col[3] X[3] (>= 0 up to rounding,
     * fj_sigma_ok), nu = sigma / cap. */
    for (int i = 0; i < 3; i++) res->p[i] = fj.col[i] * X[i];
    slip_finish(prep, cap, fj.col[3] * X[3] / cap, res);
    return EXDEX_OK;
}

/* The solve proper, for b scaled to max |b_i| in [1, 2) (or b = 0); cap
 * may be 0 or +inf after the scaling. */
static int solve_scaled(const exdex_friction_prep *prep, const double b[3], double cap,
                        int solver, exdex_friction_ws *ws, const double *warm,
                        exdex_friction_result *res)
{
    const double *e = prep->e, *lam = prep->lam;
    double c[3], ct[3], r[3], rm = 0.0, st = 0.0, cn = 0.0, s = 0.0;
    int it;

    /* c = E b, c~ = Q^T c. */
    for (int i = 0; i < 3; i++) c[i] = e[i] * b[i];
    ex_mulmtv3(ct, prep->Q, c);

    if (cap == 0.0) {
        /* No friction capacity: p = 0, u = b, sigma = |E b|; "stick" only
         * when there is nothing to stop (b = 0). */
        for (int i = 0; i < 3; i++) {
            res->p[i] = 0.0;
            res->u[i] = b[i];
            cn += c[i] * c[i];
        }
        res->sigma = sqrt(cn);
        res->stick = (b[0] == 0.0 && b[1] == 0.0 && b[2] == 0.0);
        return EXDEX_OK;
    }

    /* Stick test first (all solvers): |K^-1 c| <= cap, in the eigenbasis:
     * t = sum (r_i / cap)^2 <= 1, r = Lam^-1 c~, formed without overflow.
     * Within FRICTION_STICK_REFINE of the boundary the decision is taken on the refined stick
     * impulse instead (its accuracy is set by W alone, see stick_impulse). */
    if (isinf(cap)) {
        st = 0.0;  /* b negligible next to the capacity */
    } else {
        double invcap = 1.0 / cap;
        for (int i = 0; i < 3; i++) {
            double t;
            r[i] = ct[i] / lam[i];
            t = r[i] * invcap;
            st += t * t;
            cn += ct[i] * ct[i];
        }
        if (!(st <= DBL_MAX)) {
            /* overflow (or 0 * inf): the same sum, scaled by max |r_i| */
            for (int i = 0; i < 3; i++) rm = dmax(rm, fabs(r[i]));
            st = 0.0;
            if (rm > 0.0) {
                for (int i = 0; i < 3; i++) st += (r[i] / rm) * (r[i] / rm);
                st *= (rm / cap) * (rm / cap);
            }
        }
    }
    if (st <= 1.0 + FRICTION_STICK_REFINE) {
        double n = 0.0;
        stick_impulse(prep, b, ct, res->p);
        for (int i = 0; i < 3; i++) n += ((res->p[i] / e[i]) / cap) * ((res->p[i] / e[i]) / cap);
        if (st >= 1.0 - FRICTION_STICK_REFINE) st = n;
        if (st <= 1.0) {
            /* p = -W^-1 b (pulled back onto the ellipsoid if rounding put it
             * just outside); u = 0 exactly (set, not computed). */
            if (n > 1.0)
                for (int i = 0; i < 3; i++) res->p[i] /= sqrt(n);
            for (int i = 0; i < 3; i++) res->u[i] = 0.0;
            res->sigma = 0.0;
            res->stick = 1;
            return EXDEX_OK;
        }
    }
    cn = sqrt(cn);  /* |c| = |E b|: the secular root lies in (0, |c|) */

    if (solver == EXDEX_SOLVER_MULTIROOT) return solve_multiroot(prep, b, ct, cap, cn, ws, warm, res);

    /* Secular equation (SCALAR, BRENT). */
    it = solve_secular(prep, b, ct, cap, cn, solver, ws, &s, res->p);
    if (it < 0) return EXDEX_ENOCONV;
    res->iterations = it;
    slip_finish(prep, cap, s / cap, res);
    return EXDEX_OK;
}

int exdex_friction_solve(const exdex_friction_prep *prep, const double b[3],
                         double cap, int solver, exdex_friction_ws *ws,
                         const double *warm, exdex_friction_result *res)
{
    double bs[3], cs[3], ws3[3], bmax = 0.0, inv, cn = 0.0, caps = 0.0;
    int status, k, it, kb = 0, ka = 0, ke = 0;
    exdex_friction_prep local;
    const exdex_friction_prep *pp = prep;

    if (!res) return EXDEX_EINVAL;
    result_nan(res);
    if (!prep || !b) return EXDEX_EINVAL;
    if (!(cap >= 0.0) || !isfinite(cap) || !ex_finite_n(b, 3)) return EXDEX_EINVAL;
    if (solver != EXDEX_SOLVER_SCALAR && solver != EXDEX_SOLVER_BRENT
        && solver != EXDEX_SOLVER_MULTIROOT)
        return EXDEX_EINVAL;
    if (solver != EXDEX_SOLVER_SCALAR && !ws) return EXDEX_EINVAL;
    if (warm && !ex_finite_n(warm, 3)) return EXDEX_EINVAL;

    /* A subnormal capacity is no capacity: its impulse would not be
     * representable to any accuracy. */
    if (cap < DBL_MIN) cap = 0.0;

    /* Three exact invariances bring the solve to unit scale:
     *   (b, cap) -> (b, cap) / 2^kb         p, u, sigma scale by 2^-kb;
     *   (e, cap) -> (2^ke e, 2^-ke cap)     K, lam by 2^(2 ke), sigma by 2^ke;
     *   (W, cap) -> (2^-ka W, 2^ka cap)     K, lam by 2^-ka, p by 2^ka.
     * kb brings max |b_i| into [1, 2). Only when e or the capacity are then
     * far from 1 (beyond 2^+-200: magnitudes where |E b| could overflow,
     * the capacity turn subnormal or nu = s / cap overflow), ke brings
     * max e_i into [1, 2) and ka the capacity into [1, 2), as far as lam
     * stays normal and W finite (a scaled copy of prep). p, u, sigma are
     * scaled back exactly: no overflow or underflow for b, cap, W, e anywhere
     * in the double range, short of a result that does not fit in it (then
     * EXDEX_ENONFINITE). */
    for (int i = 0; i < 3; i++) bmax = dmax(bmax, fabs(b[i]));
    if (bmax >= DBL_MIN) {
        frexp(bmax, &k);  /* bmax in [2^(k-1), 2^k) */
        kb = k - 1;
        inv = ldexp(1.0, -kb);  /* exact: a normal power of two */
    } else {
        inv = 0.0;  /* an all-subnormal b is no slip, like a subnormal cap */
    }
    if (inv > 0.0 && cap > 0.0) {
        int em = ilogb(dmax(prep->e[0], dmax(prep->e[1], prep->e[2]))), ec;
        if (em < -200 || em > 200) ke = -em;
        ec = ilogb(cap) - kb - ke;  /* capacity in [2^ec, 2^(ec + 1)) */
        if (ec < -200 || ec > 200 || ke != 0) {
            double wmax = 0.0;
            int l0 = ilogb(prep->lam[0]) + 2 * ke, l2 = ilogb(prep->lam[2]) + 2 * ke;
            for (int i = 0; i < 9; i++) wmax = dmax(wmax, fabs(prep->W[i]));
            ka = -ec;
            if (ka < ilogb(wmax) - 1000) ka = ilogb(wmax) - 1000;
            if (ka > l0 + 1000) ka = l0 + 1000;
            if (ka < l2 - 1000) ka = l2 - 1000;
            local = *prep;
            for (int i = 0; i < 9; i++) {
                local.W[i] = ldexp(prep->W[i], -ka);
                local.K[i] = ldexp(prep->K[i], 2 * ke - ka);
            }
            for (int i = 0; i < 3; i++) {
                local.lam[i] = ldexp(prep->lam[i], 2 * ke - ka);
                local.e[i] = ldexp(prep->e[i], ke);
            }
            pp = &local;
        }
        caps = ldexp(cap, ka - kb - ke);
    }
    for (int i = 0; i < 3; i++) {
        bs[i] = b[i] * inv;
        cs[i] = pp->e[i] * bs[i];
        cn += cs[i] * cs[i];
        if (warm) ws3[i] = ldexp(warm[i], ka - kb);
    }
    cn = sqrt(cn);
    if (caps > 0.0 && cn > 0.0 && caps * pp->lam[2] <= DBL_EPSILON * cn) {
        /* Negligible capacity, cap |K| <= eps |E b| (all solvers): the
         * secular root is s = |E b| to rounding and y = -cap E b / |E b|
         * (fast slip) exactly to rounding; evaluated in the original units,
         * where the scaled capacity could underflow. sigma = |E u| scaled by
         * its largest term. */
        double eu[3], m = 0.0, un = 0.0;
        for (int i = 0; i < 3; i++) res->p[i] = -(cap * (cs[i] / cn)) * prep->e[i];
        ex_mulmv3(res->u, prep->W, res->p);
        for (int i = 0; i < 3; i++) {
            res->u[i] += b[i];
            eu[i] = prep->e[i] * res->u[i];
            m = dmax(m, fabs(eu[i]));
        }
        if (m > 0.0 && isfinite(m))
            for (int i = 0; i < 3; i++) un += (eu[i] / m) * (eu[i] / m);
        res->sigma = m * sqrt(un);
        res->stick = 0;
        res->iterations = 0;
        status = EXDEX_OK;
    } else {
        status = solve_scaled(pp, bs, caps, solver, ws, warm ? ws3 : NULL, res);
        if (status == EXDEX_OK) {
            for (int i = 0; i < 3; i++) {
                res->p[i] = ldexp(res->p[i], kb - ka);
                res->u[i] = ldexp(res->u[i], kb);
            }
            res->sigma = ldexp(res->sigma, kb - ke);
        }
    }
    if (status != EXDEX_OK) {
        it = res->iterations;
        result_nan(res);
        res->iterations = it;
        return status;
    }
    if (!ex_finite_n(res->p, 3) || !ex_finite_n(res->u, 3) || !isfinite(res->sigma)) {
        it = res->iterations;
        result_nan(res);
        res->iterations = it;
        return EXDEX_ENONFINITE;
    }
    return EXDEX_OK;
}
