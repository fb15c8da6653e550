/* test_plate_friction.c -- the friction ellipsoid (plate_friction.c).
 *
 * References, test by test:
 *   e_r            closed form 2R/3 (disc), the square's closed form
 *                  a (sqrt2 + ln(1 + sqrt2)) / 3, and numerical quadrature
 *                  (mpmath one-off in tests/data/reference.dat, plus GSL
 *                  nested QAG computed here).
 *   isotropic      closed form derived below.
 *   decoupled      1-D closed forms; 2-D brute force over the ellipse; 3-D
 *                  bisection on the multiplier of the diagonal problem.
 *   fixed solve    mpmath root of the paper's Fritz-John system (50 digits).
 *   random cases   the three solvers against each other, and each against
 *                  solver-independent checks: optimality (KKT) residuals,
 *                  the stick test by LU, kinetic energy, random feasible
 *                  points (brute force).
 */
#include "check.h"
#include "../exdex.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_integration.h>
#include <gsl/gsl_linalg.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "friction_cases.h"

static const double PI = 3.14159265358979323846;
static const int SOLVERS[3] = {EXDEX_SOLVER_SCALAR, EXDEX_SOLVER_BRENT, EXDEX_SOLVER_MULTIROOT};
static const char *SOLVER_NAME[3] = {"scalar", "brent", "multiroot"};

/* ---------------------------------------------------------------- helpers */

static double rel_err(double a, double b) { return fabs(a - b) / fabs(b); }

static double norm3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* |E^-1 p| */
static double ell_norm(const double p[3], const double e[3])
{
    double n = 0.0;
    for (int i = 0; i < 3; i++) n += (p[i] / e[i]) * (p[i] / e[i]);
    return sqrt(n);
}

/* Objective minimised by the step: f(p) = 0.5 p^T W p + b^T p. */
static double objective(const double W[9], const double b[3], const double p[3])
{
    double Wp[3];
    matvec(Wp, W, p);
    return 0.5 * (p[0] * Wp[0] + p[1] * Wp[1] + p[2] * Wp[2]) + b[0] * p[0] + b[1] * p[1]
           + b[2] * p[2];
}

/* ----------------------------------------------------------------- e_r */

/* Reference: closed form (1/(pi R^2)) int_0^R r 2 pi r dr = 2R/3, and a
 * Cartesian mpmath quadrature over the disc (reference.dat). */
EXDEX_TEST(friction_er_disc)
{
    ENSURE_CLOSE(exdex_er_disc(0.01), 2.0 * 0.01 / 3.0, 1e-18);
    ENSURE_CLOSE(exdex_er_disc(3.0), 2.0, 1e-15);
    ENSURE(rel_err(exdex_er_disc(0.01), ref("friction_er_disc_0p01")) <= 1e-15);
    ENSURE(isnan(exdex_er_disc(0.0)));
    ENSURE(isnan(exdex_er_disc(-1.0)));
    ENSURE(isnan(exdex_er_disc(NAN)));
    ENSURE(isnan(exdex_er_disc(INFINITY)));
    report("friction_er_disc_0p01", exdex_er_disc(0.01));
}

/* Reference: mpmath quadrature of the mean distance (reference.dat). */
EXDEX_TEST(friction_er_rectangle_reference)
{
    static const struct { double a, b; const char *key; } cases[] = {
        {1.0, 1.0, "friction_er_rect_1_1"},
        {0.01, 0.02, "friction_er_rect_0p01_0p02"},
        {0.03, 0.005, "friction_er_rect_0p03_0p005"},
        {0.02, 0.0001, "friction_er_rect_0p02_0p0001"},
        {0.5, 0.05, "friction_er_rect_0p5_0p05"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        double v = exdex_er_rectangle(cases[k].a, cases[k].b);
        ENSURE(rel_err(v, ref(cases[k].key)) <= 4e-15);
        report(cases[k].key, v);
    }
}

/* Reference: the square's closed form a (sqrt2 + ln(1 + sqrt2)) / 3 (the
 * general formula with a = b, worked by hand); symmetry in (a, b) and
 * scaling e_r(k a, k b) = k e_r(a, b) from the definition; NaN on bad input. */
EXDEX_TEST(friction_er_rectangle_square_and_bad_input)
{
    double sq = (sqrt(2.0) + log(1.0 + sqrt(2.0))) / 3.0;
    ENSURE(rel_err(exdex_er_rectangle(1.0, 1.0), sq) <= 2e-16);
    ENSURE(rel_err(exdex_er_rectangle(0.7, 0.7), 0.7 * sq) <= 4e-16);
    ENSURE(rel_err(exdex_er_rectangle(1e-3, 1e-3), 1e-3 * sq) <= 4e-16);
    ENSURE(rel_err(exdex_er_rectangle(0.03, 0.005), exdex_er_rectangle(0.005, 0.03)) <= 2e-16);
    ENSURE(rel_err(exdex_er_rectangle(0.3, 0.05), 10.0 * exdex_er_rectangle(0.03, 0.005)) <= 4e-16);
    /* a very thin strip of half-length a: mean distance -> a/2 */
    ENSURE(rel_err(exdex_er_rectangle(1.0, 1e-9), 0.5) <= 1e-15);
    ENSURE(isnan(exdex_er_rectangle(0.0, 1.0)));
    ENSURE(isnan(exdex_er_rectangle(1.0, -1.0)));
    ENSURE(isnan(exdex_er_rectangle(NAN, 1.0)));
    ENSURE(isnan(exdex_er_rectangle(1.0, INFINITY)));
}

/* Reference: GSL nested adaptive quadrature (QAG, 61-point Gauss-Kronrod) of
 * the mean distance over the first quadrant, independent of the closed form,
 * for 20 random shapes (aspect ratios 1e-2..1e2). */
typedef struct { double x, b; gsl_integration_workspace *w; int bad; } rect_quad;

static double rect_inner(double y, void *params)
{
    const rect_quad *q = params;
    return hypot(q->x, y);
}

/* Inner integral over [0, b], split at y = x where sqrt(x^2 + y^2) turns
 * from ~x to ~y (QAG reports round-off otherwise when x << b). */
static double rect_outer(double x, void *params)
{
    rect_quad *q = params;
    gsl_function f = {rect_inner, q};
    double v1 = 0.0, v2 = 0.0, err, m = fmin(x, q->b);
    q->x = x;
    if (gsl_integration_qag(&f, 0.0, m, 0.0, 1e-12, 1000, GSL_INTEG_GAUSS61, q->w, &v1, &err))
        q->bad++;
    if (m < q->b
        && gsl_integration_qag(&f, m, q->b, 0.0, 1e-12, 1000, GSL_INTEG_GAUSS61, q->w, &v2, &err))
        q->bad++;
    return v1 + v2;
}

EXDEX_TEST(friction_er_rectangle_gsl_quadrature)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_integration_workspace *wo = gsl_integration_workspace_alloc(1000);
    rect_quad q;
    double worst = 0.0;
    q.w = gsl_integration_workspace_alloc(1000);
    q.bad = 0;
    gsl_rng_set(rng, 4242);
    for (int k = 0; k < 20; k++) {
        double a = pow(10.0, gsl_ran_flat(rng, -3.0, 0.0));
        double b = a * pow(10.0, gsl_ran_flat(rng, -2.0, 2.0));
        gsl_function f = {rect_outer, &q};
        double v = 0.0, err;
        q.b = b;
        ENSURE(gsl_integration_qag(&f, 0.0, a, 0.0, 1e-12, 1000, GSL_INTEG_GAUSS61, wo, &v, &err)
               == GSL_SUCCESS);
        worst = fmax(worst, rel_err(exdex_er_rectangle(a, b), v / (a * b)));
    }
    ENSURE(q.bad == 0);
    ENSURE(worst <= 1e-12);
    gsl_integration_workspace_free(q.w);
    gsl_integration_workspace_free(wo);
    gsl_rng_free(rng);
}

/* ----------------------------------------------------------- closed forms */

/* Isotropic patch W = w I, e = (1, 1, 1): K = w I, the ellipsoid is the ball
 * |p| <= cap. Stick iff |W^-1 b| = |b| / w <= cap, then p = -b / w, u = 0.
 * Otherwise maximum dissipation makes p antiparallel to u = b + w p, hence
 * to b: p = -cap b / |b|, u = (1 - w cap / |b|) b, sigma = |u| = |b| - w cap
 * (derived by hand). */
EXDEX_TEST(friction_isotropic_closed_form)
{
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    const double w = 2.5, e[3] = {1.0, 1.0, 1.0};
    const double W[9] = {w, 0, 0, 0, w, 0, 0, 0, w};
    const double bs[3][3] = {{0.3, -0.4, 1.2}, {1.0, 0.0, 0.0}, {-0.01, 0.02, 0.003}};
    const double caps[4] = {0.0, 0.01, 0.2, 10.0};
    exdex_friction_prep prep;
    ENSURE(ws != NULL);
    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int s = 0; s < 3; s++)
        for (int ib = 0; ib < 3; ib++)
            for (int ic = 0; ic < 4; ic++) {
                const double *b = bs[ib];
                double cap = caps[ic], nb = norm3(b);
                exdex_friction_result r;
                ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
                if (cap == 0.0) {
                    for (int i = 0; i < 3; i++) ENSURE(r.p[i] == 0.0 && r.u[i] == b[i]);
                    ENSURE(!r.stick);
                } else if (nb / w <= cap) {
                    ENSURE(r.stick && r.sigma == 0.0 && r.iterations == 0);
                    for (int i = 0; i < 3; i++) {
                        ENSURE_CLOSE(r.p[i], -b[i] / w, 1e-15 * nb / w);
                        ENSURE(r.u[i] == 0.0);
                    }
                } else {
                    ENSURE(!r.stick);
                    ENSURE_CLOSE(r.sigma, nb - w * cap, 1e-13 * nb);
                    for (int i = 0; i < 3; i++) {
                        ENSURE_CLOSE(r.p[i], -cap * b[i] / nb, 1e-13 * cap);
                        ENSURE_CLOSE(r.u[i], (1.0 - w * cap / nb) * b[i], 1e-13 * nb);
                    }
                }
            }
    exdex_friction_ws_free(ws);
}

/* Diagonal W (no coupling), b along one axis i: a 1-D problem, derived by
 * hand. The bound on p_i is cap e_i; stick iff |b_i| <= w_i e_i cap, then
 * p_i = -b_i / w_i; else p_i = -cap e_i sgn(b_i), u_i = b_i + w_i p_i,
 * sigma = e_i |u_i|. Axis 3 is pure twisting against the torsional limit
 * m_max = e_r mu N. */
EXDEX_TEST(friction_decoupled_1d_closed_form)
{
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    const double e[3] = {1.0, 1.0, 0.004};
    const double W[9] = {3.0, 0, 0, 0, 0.5, 0, 0, 0, 2000.0};
    const double cap = 0.2;
    exdex_friction_prep prep;
    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int s = 0; s < 3; s++)
        for (int ax = 0; ax < 3; ax++)
            for (int sg = -1; sg <= 1; sg += 2)
                for (int k = 0; k < 2; k++) {
                    /* k = 0: 0.9 of the stick limit; k = 1: 3.7 times it */
                    double wi = W[4 * ax], lim = wi * e[ax] * cap;
                    double b[3] = {0, 0, 0};
                    exdex_friction_result r;
                    b[ax] = sg * (k ? 3.7 : 0.9) * lim;
                    ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
                    for (int i = 0; i < 3; i++)
                        if (i != ax) ENSURE_SMALL(r.p[i], 1e-15 * cap);
                    if (!k) {
                        ENSURE(r.stick && r.u[ax] == 0.0);
                        ENSURE_CLOSE(r.p[ax], -b[ax] / wi, 1e-15 * cap * e[ax]);
                    } else {
                        double pi = -cap * e[ax] * sg, ui = b[ax] + wi * pi;
                        ENSURE(!r.stick);
                        ENSURE_CLOSE(r.p[ax], pi, 1e-14 * cap * e[ax]);
                        ENSURE_CLOSE(r.u[ax], ui, 1e-13 * fabs(b[ax]));
                        ENSURE_CLOSE(r.sigma, e[ax] * fabs(ui), 1e-13 * e[ax] * fabs(b[ax]));
                    }
                }
    exdex_friction_ws_free(ws);
}

/* Diagonal W, b in the (x, r) plane: p stays in that plane, on the ellipse
 * p = cap (cos t, 0, e_r sin t) when sliding. Brute force independent of the
 * secular equation: scan f(p(t)) over 20000 angles for the global minimum,
 * then bisect f'(t) = u(t) . dp/dt = 0 on the bracketing grid cell. */
static double ellipse_dfdt(const double W[9], const double e[3], const double b[3], double cap,
                           double t)
{
    double p[3] = {cap * e[0] * cos(t), 0.0, cap * e[2] * sin(t)};
    double dp[3] = {-cap * e[0] * sin(t), 0.0, cap * e[2] * cos(t)}, u[3];
    matvec(u, W, p);
    for (int i = 0; i < 3; i++) u[i] += b[i];
    return u[0] * dp[0] + u[2] * dp[2];
}

EXDEX_TEST(friction_decoupled_2d_brute_force)
{
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    const double e[3] = {1.0, 1.0, 0.01};
    const double W[9] = {4.0, 0, 0, 0, 7.0, 0, 0, 0, 900.0};
    const double bs[4][3] = {{1.0, 0.0, 3.0}, {-0.2, 0.0, 5.0}, {2.0, 0.0, -0.1}, {-0.5, 0.0, -0.8}};
    const double cap = 0.15;
    const int n = 20000;
    exdex_friction_prep prep;
    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int ib = 0; ib < 4; ib++) {
        const double *b = bs[ib];
        double best = HUGE_VAL, tb = 0.0, lo, hi, p_ref[3];
        for (int k = 0; k < n; k++) {
            double t = 2.0 * PI * k / n;
            double p[3] = {cap * e[0] * cos(t), 0.0, cap * e[2] * sin(t)};
            double f = objective(W, b, p);
            if (f < best) {
                best = f;
                tb = t;
            }
        }
        lo = tb - 2.0 * PI / n;
        hi = tb + 2.0 * PI / n;
        ENSURE(ellipse_dfdt(W, e, b, cap, lo) < 0.0 && ellipse_dfdt(W, e, b, cap, hi) > 0.0);
        for (int it = 0; it < 200 && hi - lo > 1e-16; it++) {
            double mid = 0.5 * (lo + hi);
            if (ellipse_dfdt(W, e, b, cap, mid) < 0.0) lo = mid; else hi = mid;
        }
        p_ref[0] = cap * e[0] * cos(0.5 * (lo + hi));
        p_ref[1] = 0.0;
        p_ref[2] = cap * e[2] * sin(0.5 * (lo + hi));
        for (int s = 0; s < 3; s++) {
            exdex_friction_result r;
            ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            ENSURE(!r.stick);
            for (int i = 0; i < 3; i++) ENSURE_CLOSE(r.p[i], p_ref[i], 1e-13 * cap);
        }
    }
    exdex_friction_ws_free(ws);
}

/* Diagonal W, general b: the Fritz-John equations decouple,
 *   p_i = -cap e_i^2 b_i / (sigma + cap e_i^2 w_i),
 *   sum_i e_i^2 b_i^2 / (sigma + cap e_i^2 w_i)^2 = 1,
 * and the left side decreases in sigma: plain bisection on [0, |E b|] here,
 * written out for the diagonal case (no eigenbasis, no Newton). */
EXDEX_TEST(friction_decoupled_3d_bisection)
{
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    const double e[3] = {1.0, 1.0, 0.02};
    const double W[9] = {1.5, 0, 0, 0, 40.0, 0, 0, 0, 3000.0};
    const double b[3] = {0.7, -0.9, 4.0};
    const double caps[3] = {0.05, 0.01, 0.0015};
    exdex_friction_prep prep;
    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int ic = 0; ic < 3; ic++) {
        double cap = caps[ic], lo = 0.0, hi = 0.0, sig, p_ref[3];
        for (int i = 0; i < 3; i++) hi += e[i] * e[i] * b[i] * b[i];
        hi = sqrt(hi);
        for (int it = 0; it < 300; it++) {
            double mid = 0.5 * (lo + hi), phi = 0.0;
            for (int i = 0; i < 3; i++) {
                double t = e[i] * b[i] / (mid + cap * e[i] * e[i] * W[4 * i]);
                phi += t * t;
            }
            if (phi > 1.0) lo = mid; else hi = mid;
        }
        sig = 0.5 * (lo + hi);
        for (int i = 0; i < 3; i++)
            p_ref[i] = -cap * e[i] * e[i] * b[i] / (sig + cap * e[i] * e[i] * W[4 * i]);
        for (int s = 0; s < 3; s++) {
            exdex_friction_result r;
            ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            ENSURE(!r.stick);
            ENSURE(rel_err(r.sigma, sig) <= 1e-12);
            for (int i = 0; i < 3; i++) ENSURE_CLOSE(r.p[i], p_ref[i], 1e-13 * cap);
        }
    }
    exdex_friction_ws_free(ws);
}

/* Reference: mpmath root of the paper's four Fritz-John equations at 50
 * digits (reference.dat, friction_fixed_*). */
EXDEX_TEST(friction_fixed_solve)
{
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    const double W[9] = {20, 3, -1, 3, 15, 2, -1, 2, 8};
    const double e[3] = {1.0, 1.0, 0.02}, b[3] = {0.3, -0.2, 5.0}, cap = 0.05;
    const char *pk[3] = {"friction_fixed_p0", "friction_fixed_p1", "friction_fixed_p2"};
    const char *uk[3] = {"friction_fixed_u0", "friction_fixed_u1", "friction_fixed_u2"};
    exdex_friction_prep prep;
    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int s = 0; s < 3; s++) {
        exdex_friction_result r;
        ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
        ENSURE(!r.stick && r.iterations > 0);
        for (int i = 0; i < 3; i++) {
            ENSURE_CLOSE(r.p[i], ref(pk[i]), 1e-14 * cap);
            ENSURE(rel_err(r.u[i], ref(uk[i])) <= 1e-12);
        }
        ENSURE(rel_err(r.sigma, ref("friction_fixed_sigma")) <= 1e-13);
        if (s == 0) {
            for (int i = 0; i < 3; i++) report(pk[i], r.p[i]);
            report("friction_fixed_sigma", r.sigma);
        }
    }
    exdex_friction_ws_free(ws);
}

/* cap = 0: nothing resists; p = 0, u = b, sigma = |E b|; "stick" only if b = 0. */
EXDEX_TEST(friction_zero_capacity)
{
    const double W[9] = {2, 0.5, 0, 0.5, 1, 0, 0, 0, 3}, e[3] = {1, 1, 0.1};
    const double b[3] = {0.1, -0.2, 3.0}, z[3] = {0, 0, 0};
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    exdex_friction_prep prep;
    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int s = 0; s < 3; s++) {
        exdex_friction_result r;
        ENSURE(exdex_friction_solve(&prep, b, 0.0, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
        ENSURE(!r.stick && r.iterations == 0);
        for (int i = 0; i < 3; i++) ENSURE(r.p[i] == 0.0 && r.u[i] == b[i]);
        ENSURE_CLOSE(r.sigma, sqrt(0.01 + 0.04 + 0.09), 1e-15);
        ENSURE(exdex_friction_solve(&prep, z, 0.0, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
        ENSURE(r.stick && r.sigma == 0.0);
        /* b = 0 with capacity: stick, p = 0 */
        ENSURE(exdex_friction_solve(&prep, z, 0.3, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
        ENSURE(r.stick && r.p[0] == 0.0 && r.p[1] == 0.0 && r.p[2] == 0.0);
    }
    exdex_friction_ws_free(ws);
}

/* --------------------------------------------------------- random cases */

/* Random SPD W = R diag(d) R^T, d log-spread with condition number up to
 * 1e6 and overall scale 1e-2..1e2, R a random rotation (1 in 5 cases a
 * permutation: axis-aligned, strongly anisotropic); e = (1, 1, e_r), e_r
 * log-uniform in [1e-3, 1]. 60% generic: cap = |E^-1 W^-1 b| * 10^U(-2, 1)
 * (stick or slip); 40% near the stick/slip boundary: b = -W p_st with
 * |E^-1 p_st| = m, cap = m / (1 +- 10^-k), k = 3..9. */
#define N_RANDOM 12000
#define SEED 20240611UL

/* The three solvers agree: |p_a - p_b| <= 1e-10 cap, same stick decision,
 * MULTIROOT never fails. (No external reference: agreement of a secular
 * Newton, GSL Brent and the paper's four-equation system.) */
EXDEX_TEST(friction_solvers_agree_random)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    double maxd[3] = {0, 0, 0}; /* scalar-brent, scalar-multiroot, brent-multiroot */
    long iters[3] = {0, 0, 0};
    int itmax[3] = {0, 0, 0}, fails[3] = {0, 0, 0}, n_slip = 0, n_near = 0, n_stick = 0;
    ENSURE(ws != NULL);
    gsl_rng_set(rng, SEED);
    for (int k = 0; k < N_RANDOM; k++) {
        rcase c;
        exdex_friction_prep prep;
        exdex_friction_result r[3];
        int ok = 1;
        random_case(rng, k, &c);
        ENSURE(exdex_friction_prepare(&prep, c.W, c.e) == EXDEX_OK);
        n_near += c.near;
        for (int s = 0; s < 3; s++) {
            int st = exdex_friction_solve(&prep, c.b, c.cap, SOLVERS[s], ws, NULL, &r[s]);
            if (st != EXDEX_OK) {
                fails[s]++;
                ok = 0;
            }
        }
        if (!ok) continue;
        ENSURE(r[0].stick == r[1].stick && r[0].stick == r[2].stick);
        if (r[0].stick) {
            n_stick++;
            continue;
        }
        n_slip++;
        for (int s = 0; s < 3; s++) {
            iters[s] += r[s].iterations;
            if (r[s].iterations > itmax[s]) itmax[s] = r[s].iterations;
        }
        for (int i = 0; i < 3; i++) {
            maxd[0] = fmax(maxd[0], fabs(r[0].p[i] - r[1].p[i]) / c.cap);
            maxd[1] = fmax(maxd[1], fabs(r[0].p[i] - r[2].p[i]) / c.cap);
            maxd[2] = fmax(maxd[2], fabs(r[1].p[i] - r[2].p[i]) / c.cap);
        }
    }
    for (int s = 0; s < 3; s++) ENSURE(fails[s] == 0);
    for (int j = 0; j < 3; j++) ENSURE(maxd[j] <= 1e-10);
    ENSURE(n_slip >= 5000 && n_stick >= 3000 && n_near >= 4000);
    /* SCALAR: typically 3-6 iterations */
    ENSURE((double)iters[0] / n_slip <= 6.0);
    report("friction_random_cases", N_RANDOM);
    report("friction_random_slip", n_slip);
    report("friction_random_multiroot_failures", fails[2]);
    report("friction_random_maxdiff_scalar_brent", maxd[0]);
    report("friction_random_maxdiff_scalar_multiroot", maxd[1]);
    report("friction_random_maxdiff_brent_multiroot", maxd[2]);
    for (int s = 0; s < 3; s++) {
        char key[96];
        snprintf(key, sizeof key, "friction_random_iter_mean_%s", SOLVER_NAME[s]);
        report(key, (double)iters[s] / n_slip);
        snprintf(key, sizeof key, "friction_random_iter_max_%s", SOLVER_NAME[s]);
        report(key, itmax[s]);
    }
    exdex_friction_ws_free(ws);
    gsl_rng_free(rng);
}

/* Optimality, checked from the problem data only, for every solver:
 *  - stick iff outside: the stick impulse by LU (GSL), ratio
 *    rho = |E^-1 W^-1 b| / cap; rho < 1 - 1e-8 must stick, rho > 1 + 1e-8
 *    must slide (in between both are right to rounding); at stick p = the
 *    LU impulse (1e-9 cap: both carry cond(W) eps errors), u = 0 exactly;
 *  - sliding: p on the ellipsoid, |E^-1 p| = cap to 1e-12 relative;
 *  - maximum dissipation: with u = b + W p formed here and y = E^-1 p, in
 *    the scaled coordinates where the ellipsoid is the ball |y| <= cap,
 *    E u = -nu y for the least-squares nu, to 1e-12 of the magnitude of
 *    the terms (a backward-error test: p is the exact answer for b and W
 *    perturbed at that level), and nu >= 0 (p opposes the slip) to the same
 *    level;
 *  - the reported u and sigma match b + W p and |E u| to the same level;
 *  - energy: 0.5 u^T W^-1 u <= 0.5 b^T W^-1 b (1 + 1e-12), W^-1 by LU. */
EXDEX_TEST(friction_optimality_random)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    double worst_ell = 0.0, worst_kkt = 0.0, worst_u = 0.0, worst_stick = 0.0, worst_energy = -1.0;
    int wrong_side = 0, negative_nu = 0, n_checked = 0;
    gsl_rng_set(rng, SEED);
    for (int k = 0; k < N_RANDOM; k++) {
        rcase c;
        exdex_friction_prep prep;
        double p_st[3], rho, Winv_b[3], e0;
        random_case(rng, k, &c);
        ENSURE(exdex_friction_prepare(&prep, c.W, c.e) == EXDEX_OK);
        lu_solve(p_st, c.W, c.b);
        for (int i = 0; i < 3; i++) p_st[i] = -p_st[i];
        rho = ell_norm(p_st, c.e) / c.cap;
        lu_solve(Winv_b, c.W, c.b);
        e0 = 0.5 * (c.b[0] * Winv_b[0] + c.b[1] * Winv_b[1] + c.b[2] * Winv_b[2]);
        for (int s = 0; s < 3; s++) {
            exdex_friction_result r;
            double u[3], Winv_u[3], e1;
            if (exdex_friction_solve(&prep, c.b, c.cap, SOLVERS[s], ws, NULL, &r) != EXDEX_OK)
                continue;  /* counted in friction_solvers_agree_random */
            n_checked++;
            if ((rho < 1.0 - 1e-8 && !r.stick) || (rho > 1.0 + 1e-8 && r.stick)) wrong_side++;
            matvec(u, c.W, r.p);
            for (int i = 0; i < 3; i++) u[i] += c.b[i];
            if (r.stick) {
                ENSURE(r.u[0] == 0.0 && r.u[1] == 0.0 && r.u[2] == 0.0 && r.sigma == 0.0);
                for (int i = 0; i < 3; i++)
                    worst_stick = fmax(worst_stick, fabs(r.p[i] - p_st[i]) / c.cap);
                continue;
            } else {
                /* scaled coordinates: y = E^-1 p on the ball, E u = -nu y */
                double y[3], yy = 0.0, pu = 0.0, nu, scale = 0.0, rk = 0.0, ru = 0.0, eu = 0.0;
                worst_ell = fmax(worst_ell, rel_err(ell_norm(r.p, c.e), c.cap));
                for (int i = 0; i < 3; i++) {
                    y[i] = r.p[i] / c.e[i];
                    yy += y[i] * y[i];
                    pu += r.p[i] * u[i];
                }
                nu = -pu / yy;
                for (int i = 0; i < 3; i++) {
                    double t = fabs(c.b[i]) + fabs(c.W[3 * i] * r.p[0]) + fabs(c.W[3 * i + 1] * r.p[1])
                               + fabs(c.W[3 * i + 2] * r.p[2]);
                    scale = fmax(scale, c.e[i] * t + fabs(nu * y[i]));
                    rk = fmax(rk, fabs(c.e[i] * u[i] + nu * y[i]));
                    ru = fmax(ru, c.e[i] * fabs(r.u[i] - u[i]));
                    eu += c.e[i] * c.e[i] * u[i] * u[i];
                }
                if (nu * c.cap < -1e-12 * scale) negative_nu++;
                worst_kkt = fmax(worst_kkt, rk / scale);
                worst_u = fmax(worst_u, fmax(ru, fabs(r.sigma - sqrt(eu))) / scale);
            }
            lu_solve(Winv_u, c.W, r.u);
            e1 = 0.5 * (r.u[0] * Winv_u[0] + r.u[1] * Winv_u[1] + r.u[2] * Winv_u[2]);
            worst_energy = fmax(worst_energy, (e1 - e0) / e0);
        }
    }
    ENSURE(n_checked == 3 * N_RANDOM);
    ENSURE(wrong_side == 0);
    ENSURE(negative_nu == 0);
    ENSURE(worst_stick <= 1e-9);
    ENSURE(worst_ell <= 1e-12);
    ENSURE(worst_kkt <= 1e-12);
    ENSURE(worst_u <= 1e-12);
    ENSURE(worst_energy <= 1e-12);
    report("friction_random_worst_ellipsoid_rel", worst_ell);
    report("friction_random_worst_kkt_backward", worst_kkt);
    report("friction_random_worst_energy_gain_rel", worst_energy);
    report("friction_random_worst_stick_vs_lu", worst_stick);
    report("friction_random_worst_u_sigma", worst_u);
    exdex_friction_ws_free(ws);
    gsl_rng_free(rng);
}

/* Brute force: on 300 random cases, no feasible point beats the solver's p
 * on the objective f(p) = 0.5 p^T W p + b^T p: 300 random points of the
 * ellipsoid (surface and inside) and 300 nearby points (p perturbed by
 * 1e-3 cap and 1e-5 cap, pulled back into the ellipsoid). The slack is the
 * rounding of f, 1e-13 (|b| |p| + |W| |p|^2). */
EXDEX_TEST(friction_optimality_sampling)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    gsl_rng *pick = gsl_rng_alloc(gsl_rng_mt19937);
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    int beaten = 0;
    gsl_rng_set(rng, SEED + 1);
    gsl_rng_set(pick, 99);
    for (int k = 0; k < 300; k++) {
        rcase c;
        exdex_friction_prep prep;
        random_case(rng, k, &c);
        ENSURE(exdex_friction_prepare(&prep, c.W, c.e) == EXDEX_OK);
        for (int s = 0; s < 3; s++) {
            exdex_friction_result r;
            double f0, wn = 0.0, slack;
            ENSURE(exdex_friction_solve(&prep, c.b, c.cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            f0 = objective(c.W, c.b, r.p);
            for (int i = 0; i < 9; i++) wn = fmax(wn, fabs(c.W[i]));
            slack = 1e-13 * (norm3(c.b) * norm3(r.p) + 3.0 * wn * norm3(r.p) * norm3(r.p));
            for (int j = 0; j < 600; j++) {
                double q[3], n;
                if (j < 300) {
                    double rad = j % 2 ? 1.0 : cbrt(gsl_rng_uniform(pick));
                    for (int i = 0; i < 3; i++) q[i] = gsl_ran_gaussian(pick, 1.0);
                    n = norm3(q);
                    for (int i = 0; i < 3; i++) q[i] = c.cap * rad * c.e[i] * q[i] / n;
                } else {
                    double h = (j % 2 ? 1e-3 : 1e-5) * c.cap;
                    for (int i = 0; i < 3; i++) q[i] = r.p[i] + h * c.e[i] * gsl_ran_gaussian(pick, 1.0);
                    n = ell_norm(q, c.e) / c.cap;
                    if (n > 1.0)
                        for (int i = 0; i < 3; i++) q[i] /= n;
                }
                if (objective(c.W, c.b, q) < f0 - slack) beaten++;
            }
        }
    }
    ENSURE(beaten == 0);
    exdex_friction_ws_free(ws);
    gsl_rng_free(pick);
    gsl_rng_free(rng);
}

/* Warm start: a slowly turning b (a sliding patch over 200 steps), MULTIROOT
 * started from the previous impulse matches SCALAR and needs fewer
 * iterations than cold starts. */
EXDEX_TEST(friction_multiroot_warm_start)
{
    const double W[9] = {5, 1, 0.2, 1, 3, -0.1, 0.2, -0.1, 400}, e[3] = {1, 1, 0.01};
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    exdex_friction_prep prep;
    double prev[3] = {0, 0, 0};
    long warm_it = 0, cold_it = 0;
    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int k = 0; k < 200; k++) {
        double t = 0.01 * k, b[3] = {cos(t), sin(t), 0.5 * sin(3.0 * t)}, cap = 0.08;
        exdex_friction_result rs, rw, rc;
        ENSURE(exdex_friction_solve(&prep, b, cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &rs) == EXDEX_OK);
        ENSURE(exdex_friction_solve(&prep, b, cap, EXDEX_SOLVER_MULTIROOT, ws, k ? prev : NULL, &rw)
               == EXDEX_OK);
        ENSURE(exdex_friction_solve(&prep, b, cap, EXDEX_SOLVER_MULTIROOT, ws, NULL, &rc) == EXDEX_OK);
        ENSURE(!rs.stick);
        for (int i = 0; i < 3; i++) {
            ENSURE_CLOSE(rw.p[i], rs.p[i], 1e-12 * cap);
            prev[i] = rw.p[i];
        }
        if (k) {
            warm_it += rw.iterations;
            cold_it += rc.iterations;
        }
    }
    ENSURE(warm_it < cold_it);
    report("friction_warm_iter_mean", warm_it / 199.0);
    report("friction_cold_iter_mean", cold_it / 199.0);
    exdex_friction_ws_free(ws);
}

/* Same inputs, same bits (workspace reuse must not leak state). */
EXDEX_TEST(friction_deterministic)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    gsl_rng_set(rng, 7);
    for (int k = 0; k < 50; k++) {
        rcase c;
        exdex_friction_prep p1, p2;
        random_case(rng, k, &c);
        ENSURE(exdex_friction_prepare(&p1, c.W, c.e) == EXDEX_OK);
        ENSURE(exdex_friction_prepare(&p2, c.W, c.e) == EXDEX_OK);
        ENSURE(memcmp(&p1, &p2, sizeof p1) == 0);
        for (int s = 0; s < 3; s++) {
            exdex_friction_result a, b;
            ENSURE(exdex_friction_solve(&p1, c.b, c.cap, SOLVERS[s], ws, NULL, &a) == EXDEX_OK);
            ENSURE(exdex_friction_solve(&p2, c.b, c.cap, SOLVERS[s], ws, NULL, &b) == EXDEX_OK);
            ENSURE(memcmp(&a, &b, sizeof a) == 0);
        }
    }
    exdex_friction_ws_free(ws);
    gsl_rng_free(rng);
}

/* Scale: the solution is homogeneous of degree 1 in (b, cap) (f(p) and the
 * ellipsoid scale together), so scaling b and cap by 2^k must scale p, u,
 * sigma by exactly 2^k, bit for bit, across the double range; plus the
 * limits at the ends of the range, each derived by hand. */
EXDEX_TEST(friction_extreme_scales)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    const int ks[6] = {-900, -400, -60, 60, 400, 900};
    gsl_rng_set(rng, 11);
    for (int k = 0; k < 40; k++) {
        rcase c;
        exdex_friction_prep prep;
        random_case(rng, k, &c);
        ENSURE(exdex_friction_prepare(&prep, c.W, c.e) == EXDEX_OK);
        for (int s = 0; s < 3; s++) {
            exdex_friction_result r0, r1;
            ENSURE(exdex_friction_solve(&prep, c.b, c.cap, SOLVERS[s], ws, NULL, &r0) == EXDEX_OK);
            for (int j = 0; j < 6; j++) {
                double b2[3];
                for (int i = 0; i < 3; i++) b2[i] = ldexp(c.b[i], ks[j]);
                ENSURE(exdex_friction_solve(&prep, b2, ldexp(c.cap, ks[j]), SOLVERS[s], ws, NULL, &r1)
                       == EXDEX_OK);
                ENSURE(r1.stick == r0.stick && r1.iterations == r0.iterations);
                ENSURE(r1.sigma == ldexp(r0.sigma, ks[j]));
                for (int i = 0; i < 3; i++)
                    ENSURE(r1.p[i] == ldexp(r0.p[i], ks[j]) && r1.u[i] == ldexp(r0.u[i], ks[j]));
            }
        }
    }
    {
        const double W[9] = {2, 0.5, 0, 0.5, 1, 0.1, 0, 0.1, 3}, e[3] = {1, 1, 0.05};
        const double big[3] = {3e300, -4e300, 1e300}, sub[3] = {1e-320, 0, -3e-321};
        const double over[3] = {1.5e308, -1.5e308, 0}, small[3] = {0.3, -0.2, 0.1};
        exdex_friction_prep prep;
        ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
        for (int s = 0; s < 3; s++) {
            exdex_friction_result r;
            double eb = 0.0, Winv_b[3];
            /* cap << |b|: the fast-slip limit p = -cap E (E b) / |E b| */
            for (int i = 0; i < 3; i++) eb += (e[i] * big[i] / 1e300) * (e[i] * big[i] / 1e300);
            eb = sqrt(eb);
            ENSURE(exdex_friction_solve(&prep, big, 2.0, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            ENSURE(!r.stick);
            for (int i = 0; i < 3; i++) {
                ENSURE(rel_err(r.p[i], -2.0 * e[i] * e[i] * (big[i] / 1e300) / eb) <= 1e-15);
                ENSURE(rel_err(r.u[i], big[i]) <= 1e-15);
            }
            ENSURE(rel_err(r.sigma, 1e300 * eb) <= 1e-15);
            /* cap >> |b|: stick, p = -W^-1 b (LU) */
            lu_solve(Winv_b, W, small);
            ENSURE(exdex_friction_solve(&prep, small, 1e300, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            ENSURE(r.stick);
            for (int i = 0; i < 3; i++) ENSURE(rel_err(r.p[i], -Winv_b[i]) <= 1e-15);
            /* subnormal capacity: no capacity (p = 0, u = b) */
            ENSURE(exdex_friction_solve(&prep, big, 1e-310, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            ENSURE(!r.stick && r.p[0] == 0.0 && r.p[1] == 0.0 && r.p[2] == 0.0 && r.u[1] == big[1]);
            /* all-subnormal b: no slip (p = 0, stick) */
            ENSURE(exdex_friction_solve(&prep, sub, 0.1, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            ENSURE(r.stick && r.p[0] == 0.0 && r.p[1] == 0.0 && r.p[2] == 0.0);
            /* b at the top of the range, still representable results: the
             * fast-slip limit, u = b to rounding, sigma = |E b| */
            {
                const double top[3] = {1.7e308, 0.0, 0.0};
                ENSURE(exdex_friction_solve(&prep, top, 1.0, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
                ENSURE(!r.stick && rel_err(r.p[0], -1.0) <= 1e-15 && r.p[1] == 0.0 && r.p[2] == 0.0);
                ENSURE(rel_err(r.u[0], top[0]) <= 1e-15 && rel_err(r.sigma, top[0]) <= 1e-15);
            }
            /* sigma = |E u| ~ 2.1e308 does not fit: EXDEX_ENONFINITE, NaN out */
            ENSURE(exdex_friction_solve(&prep, over, 1.0, SOLVERS[s], ws, NULL, &r)
                   == EXDEX_ENONFINITE);
            ENSURE(isnan(r.p[0]) && isnan(r.sigma));
        }
    }
    exdex_friction_ws_free(ws);
    gsl_rng_free(rng);
}

/* Bad input: EXDEX_EINVAL, never a crash; free(NULL) harmless. */
EXDEX_TEST(friction_bad_input)
{
    const double W[9] = {2, 0.5, 0, 0.5, 1, 0, 0, 0, 3}, e[3] = {1, 1, 0.1};
    const double b[3] = {0.1, -0.2, 3.0};
    double Wb[9], eb[3], bb[3];
    exdex_friction_prep prep;
    exdex_friction_result r;
    exdex_friction_ws *ws = exdex_friction_ws_alloc();

    /* not symmetric (beyond 1e-12 relative), indefinite, singular, zero */
    memcpy(Wb, W, sizeof Wb);
    Wb[1] += 1e-9;
    ENSURE(exdex_friction_prepare(&prep, Wb, e) == EXDEX_EINVAL);
    Wb[1] = W[1] + 1e-14;  /* within the tolerance: accepted, symmetrised */
    ENSURE(exdex_friction_prepare(&prep, Wb, e) == EXDEX_OK);
    ENSURE(prep.W[1] == prep.W[3]);
    {
        const double ind[9] = {1, 0, 0, 0, -1, 0, 0, 0, 1};
        const double sing[9] = {1, 1, 0, 1, 1, 0, 0, 0, 1};
        const double zero[9] = {0};
        ENSURE(exdex_friction_prepare(&prep, ind, e) == EXDEX_EINVAL);
        ENSURE(exdex_friction_prepare(&prep, sing, e) == EXDEX_EINVAL);
        /* singular to working precision: D^-1 W D^-1 has eigenvalues 2, 1, 1e-14 */
        const double near_sing[9] = {1, 1 - 1e-14, 0, 1 - 1e-14, 1, 0, 0, 0, 1};
        /* eigenvalues of K below the normal range */
        const double tiny[9] = {1e-310, 0, 0, 0, 1e-310, 0, 0, 0, 1e-310};
        /* a diagonal W is well conditioned at any grading; K's eigenvalues
         * (here W's diagonal) come out to full relative accuracy even at
         * cond(K) = 1e20 (closed form: K = W when e = 1) */
        const double graded[9] = {1e-10, 0, 0, 0, 1, 0, 0, 0, 1e10};
        const double e1[3] = {1, 1, 1};
        ENSURE(exdex_friction_prepare(&prep, zero, e) == EXDEX_EINVAL);
        ENSURE(exdex_friction_prepare(&prep, near_sing, e) == EXDEX_EINVAL);
        ENSURE(exdex_friction_prepare(&prep, tiny, e) == EXDEX_EINVAL);
        ENSURE(exdex_friction_prepare(&prep, graded, e1) == EXDEX_OK);
        ENSURE(rel_err(prep.lam[0], 1e-10) <= 1e-15 && rel_err(prep.lam[1], 1.0) <= 1e-15
               && rel_err(prep.lam[2], 1e10) <= 1e-15);
    }
    for (int i = 0; i < 9; i++) {
        memcpy(Wb, W, sizeof Wb);
        Wb[i] = NAN;
        ENSURE(exdex_friction_prepare(&prep, Wb, e) == EXDEX_EINVAL);
        Wb[i] = INFINITY;
        ENSURE(exdex_friction_prepare(&prep, Wb, e) == EXDEX_EINVAL);
    }
    for (int i = 0; i < 3; i++) {
        const double bad[4] = {0.0, -1.0, NAN, INFINITY};
        for (int j = 0; j < 4; j++) {
            memcpy(eb, e, sizeof eb);
            eb[i] = bad[j];
            ENSURE(exdex_friction_prepare(&prep, W, eb) == EXDEX_EINVAL);
        }
    }
    ENSURE(exdex_friction_prepare(NULL, W, e) == EXDEX_EINVAL);
    ENSURE(exdex_friction_prepare(&prep, NULL, e) == EXDEX_EINVAL);
    ENSURE(exdex_friction_prepare(&prep, W, NULL) == EXDEX_EINVAL);

    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int s = 0; s < 3; s++) {
        const double warm_bad[3] = {0.0, NAN, 0.0};
        ENSURE(exdex_friction_solve(&prep, b, -1e-3, SOLVERS[s], ws, NULL, &r) == EXDEX_EINVAL);
        ENSURE(isnan(r.p[0]) && isnan(r.u[0]));
        ENSURE(exdex_friction_solve(&prep, b, NAN, SOLVERS[s], ws, NULL, &r) == EXDEX_EINVAL);
        ENSURE(exdex_friction_solve(&prep, b, INFINITY, SOLVERS[s], ws, NULL, &r) == EXDEX_EINVAL);
        for (int i = 0; i < 3; i++) {
            memcpy(bb, b, sizeof bb);
            bb[i] = NAN;
            ENSURE(exdex_friction_solve(&prep, bb, 0.1, SOLVERS[s], ws, NULL, &r) == EXDEX_EINVAL);
            bb[i] = -INFINITY;
            ENSURE(exdex_friction_solve(&prep, bb, 0.1, SOLVERS[s], ws, NULL, &r) == EXDEX_EINVAL);
        }
        ENSURE(exdex_friction_solve(&prep, b, 0.1, SOLVERS[s], ws, warm_bad, &r) == EXDEX_EINVAL);
        ENSURE(exdex_friction_solve(NULL, b, 0.1, SOLVERS[s], ws, NULL, &r) == EXDEX_EINVAL);
        ENSURE(exdex_friction_solve(&prep, NULL, 0.1, SOLVERS[s], ws, NULL, &r) == EXDEX_EINVAL);
        ENSURE(exdex_friction_solve(&prep, b, 0.1, SOLVERS[s], ws, NULL, NULL) == EXDEX_EINVAL);
    }
    ENSURE(exdex_friction_solve(&prep, b, 0.1, 7, ws, NULL, &r) == EXDEX_EINVAL);
    ENSURE(exdex_friction_solve(&prep, b, 0.1, -1, ws, NULL, &r) == EXDEX_EINVAL);
    /* BRENT and MULTIROOT need the workspace, SCALAR does not */
    ENSURE(exdex_friction_solve(&prep, b, 0.1, EXDEX_SOLVER_BRENT, NULL, NULL, &r) == EXDEX_EINVAL);
    ENSURE(exdex_friction_solve(&prep, b, 0.1, EXDEX_SOLVER_MULTIROOT, NULL, NULL, &r) == EXDEX_EINVAL);
    ENSURE(exdex_friction_solve(&prep, b, 0.1, EXDEX_SOLVER_SCALAR, NULL, NULL, &r) == EXDEX_OK);
    exdex_friction_ws_free(ws);
    exdex_friction_ws_free(NULL);
}

/* ------------------------------------------------------------ hardening */

#ifndef DBL_TRUE_MIN /* C11 */
#define DBL_TRUE_MIN 4.9406564584124654e-324
#endif

/* Textbook form of the rectangle's mean distance (Howe & Cutkosky), in long
 * double: an independent evaluation for moderate sizes. */
static long double er_rect_ld(long double a, long double b)
{
    long double d = sqrtl(a * a + b * b);
    return d / 3 + (a * a / (6 * b)) * asinhl(b / a) + (b * b / (6 * a)) * asinhl(a / b);
}

/* e_r at the ends of the double range (the textbook form overflowed for half
 * sizes above ~1e154 and underflowed below ~1e-154). References: the square's
 * closed form a (sqrt2 + ln(1 + sqrt2)) / 3 at every scale; the thin-strip
 * limit r = a/b -> 0 of b [sqrt(1 + r^2)/3 + r^2 asinh(1/r)/6 + asinh(r)/(6r)],
 * which is b (1/3 + 0 + 1/6) = b/2 (the mean |y| along the long side); the
 * textbook form in long double at unit scale times the exact power-of-two
 * scale 2^k (homogeneity of the definition); 2R/3 in long double for the
 * disc. Subnormal results are checked to their absolute spacing. */
EXDEX_TEST(friction_er_extreme_sizes)
{
    const double sq = (sqrt(2.0) + log(1.0 + sqrt(2.0))) / 3.0;
    const double sizes[8] = {1e-307, 1e-300, 1e-200, 1e-155, 1e155, 1e200, 1e300, DBL_MAX};
    const int ks[4] = {-1000, -600, 600, 1000};
    /* R (2/3) with the rounded constant is within 1 ulp (2.3e-16 relative) of
     * 2R/3; the long double reference rounded to double adds nothing when
     * long double really is extended, but half an ulp (1.12e-16) where it is
     * evaluated in double (valgrind emulates x87 long double in 64 bits; R / 3
     * first, so that R = DBL_MAX does not overflow there) */
    volatile long double one = 1.0L, tiny = LDBL_EPSILON;
    const double disc_tol = (one + tiny != one) ? 2.3e-16 : 2.3e-16 + 1.12e-16;
    const double shapes[6][2] = {{1, 1}, {0.3, 1}, {1, 1e-3}, {1, 1e-8}, {0.02, 1e-6}, {1e-12, 1}};
    for (int i = 0; i < 8; i++) {
        ENSURE(rel_err(exdex_er_rectangle(sizes[i], sizes[i]), sizes[i] * sq) <= 4e-16);
        /* thin strip b/a = 1e-200 and below: a/2 to rounding */
        ENSURE(rel_err(exdex_er_rectangle(sizes[i], sizes[i] * 1e-200), 0.5 * sizes[i]) <= 2.3e-16
               || sizes[i] * 1e-200 == 0.0);
        ENSURE(rel_err(exdex_er_disc(sizes[i]), (double)((long double)sizes[i] / 3.0L * 2.0L)) <= disc_tol);
    }
    ENSURE(rel_err(exdex_er_rectangle(DBL_MAX, DBL_TRUE_MIN), 0.5 * DBL_MAX) <= 2.3e-16);
    ENSURE(rel_err(exdex_er_rectangle(1e-300, 1e300), 0.5e300) <= 2.3e-16);
    for (int s = 0; s < 6; s++)
        for (int j = 0; j < 4; j++) {
            double a = ldexp(shapes[s][0], ks[j]), b = ldexp(shapes[s][1], ks[j]);
            double ref1 = ldexp((double)er_rect_ld(shapes[s][0], shapes[s][1]), ks[j]);
            if (fmin(a, b) < DBL_MIN) continue;  /* not an exact scaling */
            ENSURE(rel_err(exdex_er_rectangle(a, b), ref1) <= 4e-16);
            ENSURE(exdex_er_rectangle(a, b) == exdex_er_rectangle(b, a));
        }
    /* subnormal sizes: positive, within one spacing of the value */
    {
        const double sub[3] = {DBL_TRUE_MIN, 7 * DBL_TRUE_MIN, 1e-310};
        for (int i = 0; i < 3; i++) {
            long double ref2 = (long double)sub[i] * (long double)sq;
            double e = exdex_er_rectangle(sub[i], sub[i]);
            ENSURE(e > 0 && fabsl(e - ref2) <= DBL_TRUE_MIN);
            e = exdex_er_disc(sub[i]);
            ENSURE(e > 0 && fabsl(e - (long double)sub[i] * 2.0L / 3.0L) <= DBL_TRUE_MIN);
        }
        ENSURE(exdex_er_rectangle(DBL_TRUE_MIN, 1.0) == 0.5);
    }
    /* moderate random shapes, aspect ratios 1e-12..1e12: the textbook form
     * in long double */
    {
        gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
        double worst = 0.0;
        gsl_rng_set(rng, 77);
        for (int k = 0; k < 2000; k++) {
            double a = pow(10.0, gsl_ran_flat(rng, -4.0, 1.0));
            double b = a * pow(10.0, gsl_ran_flat(rng, -12.0, 12.0));
            worst = fmax(worst, fabsl((exdex_er_rectangle(a, b) - er_rect_ld(a, b)) / er_rect_ld(a, b)));
        }
        ENSURE(worst <= 6e-16);
        gsl_rng_free(rng);
    }
}

/* Unit-scale solve for extreme W, e and capacity. Three exact invariances of
 * the problem (derived from f(p) = p'Wp/2 + p'b over p'E^-2 p <= cap^2):
 *   (b, cap) * 2^kb:               p, u, sigma * 2^kb;
 *   (e * 2^ke, cap * 2^-ke):       p, u unchanged, sigma * 2^ke;
 *   (W * 2^-ka, cap * 2^ka):       p * 2^ka, u, sigma unchanged.
 * Reference: the same problem at moderate scale (SCALAR), scaled by these
 * factors. The transformed problems put W near 1e298 and b near 1e301 with
 * a moderate capacity (the fuzzer's ENONFINITE and precision-loss cases:
 * the capacity relative to b below the normal range), or e near 1e150 /
 * 1e-136 with W near 1e-301 / 1e271. Tolerance: the solvers' agreement
 * level, 1e-10 cap e_i for p, 1e-10 of |b| + |W p| for u, 1e-10 |E b| for
 * sigma (in the moderate problem's units). */
EXDEX_TEST(friction_extreme_W_e_scales)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    const int tr[4][3] = {{-990, 0, 1000}, {1000, 500, 0}, {-900, -450, 0}, {-990, 0, 950}};
    int bad = 0, fails = 0, n_slip = 0, skipped = 0;
    gsl_rng_set(rng, 12);
    for (int k = 0; k < 60; k++) {
        rcase c;
        exdex_friction_prep prep, prep2;
        exdex_friction_result r0;
        double eb = 0.0, wp[3];
        random_case(rng, k, &c);
        ENSURE(exdex_friction_prepare(&prep, c.W, c.e) == EXDEX_OK);
        ENSURE(exdex_friction_solve(&prep, c.b, c.cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &r0) == EXDEX_OK);
        n_slip += !r0.stick;
        matvec(wp, c.W, r0.p);
        for (int i = 0; i < 3; i++) eb += c.e[i] * c.e[i] * c.b[i] * c.b[i];
        eb = sqrt(eb);
        for (int t = 0; t < 4; t++) {
            int ka = tr[t][0], ke = tr[t][1], kb = tr[t][2];
            double W2[9], e2[3], b2[3], cap2 = ldexp(c.cap, kb - ke + ka);
            for (int i = 0; i < 9; i++) W2[i] = ldexp(c.W[i], -ka);
            for (int i = 0; i < 3; i++) {
                e2[i] = ldexp(c.e[i], ke);
                b2[i] = ldexp(c.b[i], kb);
            }
            if (!isfinite(b2[0] + b2[1] + b2[2])) {
                skipped++;  /* the large-b transforms on the largest b */
                continue;
            }
            ENSURE(exdex_friction_prepare(&prep2, W2, e2) == EXDEX_OK);
            for (int s = 0; s < 3; s++) {
                exdex_friction_result r;
                if (exdex_friction_solve(&prep2, b2, cap2, SOLVERS[s], ws, NULL, &r) != EXDEX_OK) {
                    fails++;
                    continue;
                }
                if (r.stick != r0.stick) bad++;
                for (int i = 0; i < 3; i++) {
                    double tu = fabs(c.b[i]) + fabs(wp[i]);
                    if (!(fabs(ldexp(r.p[i], -(kb + ka)) - r0.p[i]) <= 1e-10 * c.cap * c.e[i])) bad++;
                    if (!(fabs(ldexp(r.u[i], -kb) - r0.u[i]) <= 1e-10 * tu)) bad++;
                }
                if (!(fabs(ldexp(r.sigma, -(kb + ke)) - r0.sigma) <= 1e-10 * eb)) bad++;
            }
        }
    }
    ENSURE(fails == 0);
    ENSURE(bad == 0);
    ENSURE(n_slip >= 15 && skipped <= 20);
    exdex_friction_ws_free(ws);
    gsl_rng_free(rng);
}

/* Two inputs of the fuzzer, each against a reference by hand:
 *  1. W ~ 1e299, b ~ 1e300, cap = 1.6e-9 (the capacity below the normal
 *     range relative to b: ENONFINITE before). Reference: the problem
 *     divided by 2^996 in W and b (same p, u / 2^996, sigma / 2^996; the
 *     invariances of friction_extreme_W_e_scales), solved at moderate
 *     scale by SCALAR.
 *  2. e = (1e300, 1e300, 1e150), W ~ 1e-301, cap = 1e-300, b ~ 4e-3: cap |K|
 *     ~ 1 <= eps |E b| ~ 1e297, the negligible-capacity (fast-slip) limit
 *     p = -cap E (E b) / |E b|, u = b + W p = b to rounding, sigma = |E b|
 *     ~ 5e297 (|E b| overflowed in the sum of squares before). */
EXDEX_TEST(friction_fuzz_extreme_cases)
{
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    {
        const double W[9] = {3.4197155213350294e299, 3.9434942315121967e299, -1.1245739861323934e299,
                             3.9434942315121967e299, 4.6594926503640803e299, -1.8442376018391633e299,
                             -1.1245739861323934e299, -1.8442376018391633e299, 3.4564530991314162e299};
        const double e[3] = {127.01669164705831, 0.010003878092745838, 0.019151135194109489};
        const double b[3] = {9.683853465844949e298, -7.7417785703289306e299, -7.991677646399491e299};
        const double cap = 1.555360154371731e-09;
        double Ws[9], bs[3];
        exdex_friction_prep prep, preps;
        exdex_friction_result r0, r;
        for (int i = 0; i < 9; i++) Ws[i] = ldexp(W[i], -996);
        for (int i = 0; i < 3; i++) bs[i] = ldexp(b[i], -996);
        ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
        ENSURE(exdex_friction_prepare(&preps, Ws, e) == EXDEX_OK);
        ENSURE(exdex_friction_solve(&preps, bs, cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &r0) == EXDEX_OK);
        ENSURE(!r0.stick);
        for (int s = 0; s < 3; s++) {
            ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            ENSURE(!r.stick);
            for (int i = 0; i < 3; i++) {
                ENSURE(fabs(r.p[i] - r0.p[i]) <= 1e-10 * cap * e[i]);
                ENSURE(rel_err(r.u[i], ldexp(r0.u[i], 996)) <= 1e-12);
            }
            ENSURE(rel_err(r.sigma, ldexp(r0.sigma, 996)) <= 1e-12);
        }
    }
    {
        const double W[9] = {3.3357883520334415e-301, 3.1109924673452873e-303, -3.1511838021025092e-301,
                             3.1109924673452873e-303, 3.6891699513229833e-301, -2.9388282991689772e-303,
                             -3.1511838021025092e-301, -2.9388282991689772e-303, 0.99999999999999989};
        const double e[3] = {1e300, 1e300, 1e150};
        const double b[3] = {0.004461955808439627, -0.001980784754917672, -0.0019500932614573191};
        const double cap = 1e-300;
        double c[3], cn, m = 0.0;
        exdex_friction_prep prep;
        exdex_friction_result r;
        /* |E b| by hand, scaled by 1e300 (e_3 b_3 = 2e147 is negligible) */
        for (int i = 0; i < 3; i++) c[i] = (e[i] / 1e300) * b[i];
        cn = norm3(c);
        ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
        for (int s = 0; s < 3; s++) {
            ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            ENSURE(!r.stick);
            for (int i = 0; i < 3; i++) {
                ENSURE(fabs(r.p[i] - (-cap * e[i] * c[i] / cn)) <= 1e-15 * cap * e[i]);
                ENSURE(rel_err(r.u[i], b[i]) <= 1e-15);
                m = fmax(m, fabs(r.p[i]));
            }
            ENSURE(m > 0.1);
            ENSURE(rel_err(r.sigma, cn * 1e300) <= 1e-15);
        }
    }
    exdex_friction_ws_free(ws);
}

/* Sliding p exactly on the ellipsoid at cond(K) up to ~1e18 (e_r 1e-7..1e-6
 * with cond(W) up to 1e6; an unscaled solve leaves p outside by ~1e-9
 * relative at cond(K) ~ 2e14), and no solver failure there (MULTIROOT's
 * fallback to the secular solution). Reference: the constraint
 * itself, |E^-1 p| = cap, to rounding (8 eps). */
EXDEX_TEST(friction_on_ellipsoid_ill_conditioned)
{
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    double worst = 0.0;
    int n_slip = 0, fails = 0;
    gsl_rng_set(rng, 13);
    for (int k = 0; k < 3000; k++) {
        rcase c;
        exdex_friction_prep prep;
        random_case(rng, k, &c);
        c.e[2] = pow(10.0, gsl_ran_flat(rng, -7.0, -6.0));
        if (exdex_friction_prepare(&prep, c.W, c.e) != EXDEX_OK) continue;
        for (int s = 0; s < 3; s++) {
            exdex_friction_result r;
            if (exdex_friction_solve(&prep, c.b, c.cap, SOLVERS[s], ws, NULL, &r) != EXDEX_OK) {
                fails++;
                continue;
            }
            if (r.stick) continue;
            n_slip++;
            worst = fmax(worst, rel_err(ell_norm(r.p, c.e), c.cap));
        }
    }
    ENSURE(fails == 0);
    ENSURE(n_slip >= 1000);
    ENSURE(worst <= 8 * DBL_EPSILON);
    report("friction_illcond_worst_ellipsoid_rel", worst);
    exdex_friction_ws_free(ws);
    gsl_rng_free(rng);
}

/* Two more fuzzer inputs, references solver-independent:
 *  1. slip just beginning (sigma ~ 1e-27 against |b| ~ 1e-5, cond(W) ~ 1e17):
 *     maximum dissipation, p . u <= 0, and u parallel to -E^-2 p (Eq. 6),
 *     for every solver (MULTIROOT reported u = b + W p, pure rounding noise
 *     of any direction, before);
 *  2. e = (97.7, 2.7e-3, 5.0e-5), cond(K) ~ 3e12, where GSL's hybridsj
 *     fails from all of MULTIROOT's independent starts (ENOCONV before):
 *     MULTIROOT (secular fallback) returns OK and agrees with SCALAR and
 *     BRENT to 1e-10 cap e_i, and the KKT backward error (E u = -nu E^-1 p,
 *     nu >= 0, u = b + W p formed here) is at rounding level. */
EXDEX_TEST(friction_fuzz_slip_onset_cases)
{
    exdex_friction_ws *ws = exdex_friction_ws_alloc();
    {
        const double W[9] = {11.334962315203507, -1.6141605807731817e-17, -2e-16,
                             -1.6141605807731817e-17, 11.334962315203507, 8.0708029038659083e-18,
                             -2e-16, 8.0708029038659083e-18, 9.9999999999999998e-17};
        const double e[3] = {0.0031016247379785995, 0.0031016247379785995, 2.9389372378358935e-05};
        const double b[3] = {3.3451115722419757e-06, 6.32250954880994e-06, 3.7173400880042199e-97};
        const double cap = 0.0004768077574988019;
        exdex_friction_prep prep;
        ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
        for (int s = 0; s < 3; s++) {
            exdex_friction_result r;
            double pu = 0.0, q[3], qn, un, cross;
            ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r) == EXDEX_OK);
            if (r.stick) continue;
            for (int i = 0; i < 3; i++) {
                pu += r.p[i] * r.u[i];
                q[i] = -r.p[i] / (e[i] * e[i]);
            }
            ENSURE(pu <= 0.0);
            qn = norm3(q);
            un = norm3(r.u);
            if (un > 0.0) {
                /* |u x q| / (|u| |q|) at rounding level, and u . q >= 0 */
                double cx = r.u[1] * q[2] - r.u[2] * q[1], cy = r.u[2] * q[0] - r.u[0] * q[2],
                       cz = r.u[0] * q[1] - r.u[1] * q[0];
                cross = sqrt(cx * cx + cy * cy + cz * cz) / (un * qn);
                ENSURE(cross <= 1e-14);
            }
        }
    }
    {
        const double W[9] = {3.4197155213350294, 3.8491111198379206, 0.50042432627942057,
                             3.8491111198379206, 4.7074361948073893, 0.30395936754052932,
                             0.50042432627942057, 0.30395936754052932, 4.4023618973520122};
        const double e[3] = {97.683100797377932, 0.002697535802061302, 5.0194349383158649e-05};
        const double b[3] = {7.7373581416860284e-06, 9.2601540801638934e-06, 1.791922715063028e-06};
        const double cap = 0.00064946816226744508;
        exdex_friction_prep prep;
        exdex_friction_result r[3];
        ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
        for (int s = 0; s < 3; s++) {
            double u[3], y[3], yy = 0.0, pu = 0.0, nu, scale = 0.0, rk = 0.0;
            ENSURE(exdex_friction_solve(&prep, b, cap, SOLVERS[s], ws, NULL, &r[s]) == EXDEX_OK);
            ENSURE(!r[s].stick);
            matvec(u, W, r[s].p);
            for (int i = 0; i < 3; i++) {
                u[i] += b[i];
                y[i] = r[s].p[i] / e[i];
                yy += y[i] * y[i];
                pu += r[s].p[i] * u[i];
            }
            nu = -pu / yy;
            for (int i = 0; i < 3; i++) {
                double t = fabs(b[i]) + fabs(W[3 * i] * r[s].p[0]) + fabs(W[3 * i + 1] * r[s].p[1])
                           + fabs(W[3 * i + 2] * r[s].p[2]);
                scale = fmax(scale, e[i] * t + fabs(nu * y[i]));
                rk = fmax(rk, fabs(e[i] * u[i] + nu * y[i]));
            }
            ENSURE(nu * cap >= -1e-12 * scale);
            ENSURE(rk <= 1e-12 * scale);
            ENSURE(rel_err(ell_norm(r[s].p, e), cap) <= 8 * DBL_EPSILON);
        }
        for (int s = 1; s < 3; s++)
            for (int i = 0; i < 3; i++) ENSURE(fabs(r[s].p[i] - r[0].p[i]) <= 1e-10 * cap * e[i]);
    }
    exdex_friction_ws_free(ws);
}
