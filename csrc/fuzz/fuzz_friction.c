/* fuzz_friction.c -- exdex_friction_prepare + exdex_friction_solve, all three
 * solvers, on fuzzed Delassus matrices W, semi-axes e, slip b and capacity.
 *
 * W is made SPD (L L^T, or J M^-1 J^T of a planar patch as model.c builds it)
 * or taken raw (symmetric or not), so both the valid and the rejected paths
 * are exercised. Checks beyond "no crash": non-finite or out-of-range input
 * gives EXDEX_EINVAL; EXDEX_OK gives finite p, u, sigma with p inside the
 * ellipsoid, p . u <= 0 (maximum dissipation never adds energy), the
 * objective 1/2 p'Wp + p'b <= 0 = its value at p = 0, u == 0 at stick; a
 * failed solve leaves NaN in the result (documented in plate_friction.c). */
#include "fuzz.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#define T "friction"

#ifndef DBL_TRUE_MIN /* C11 */
#define DBL_TRUE_MIN 4.9406564584124654e-324
#endif

static void decode_W(fz *f, double W[9], int mode)
{
    double s = fz_log(f, 1e-6, 1e6);
    if (mode == 0) {
        /* L L^T + d I, L lower triangular */
        double L[9] = {0}, d = fz_log(f, 1e-12, 1.0);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j <= i; j++) L[3 * i + j] = fz_num(f, -1.0, 1.0);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double a = 0.0;
                for (int k = 0; k < 3; k++) a += L[3 * i + k] * L[3 * j + k];
                W[3 * i + j] = s * (a + (i == j ? d : 0.0));
            }
    } else if (mode == 1) {
        /* J M^-1 J^T of a planar patch at pc (as model.c): mass m, izz */
        double m = fz_log(f, 1e-4, 1e3), izz = fz_log(f, 1e-9, 1e2);
        double px = fz_num(f, -0.2, 0.2), py = fz_num(f, -0.2, 0.2);
        double J[9] = {1, 0, -py, 0, 1, px, 0, 0, 1}, mi[3] = {1 / m, 1 / m, 1 / izz};
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double a = 0.0;
                for (int k = 0; k < 3; k++) a += J[3 * i + k] * mi[k] * J[3 * j + k];
                W[3 * i + j] = a;
            }
    } else {
        /* raw entries; mode 2 mirrored to symmetric */
        for (int i = 0; i < 9; i++) W[i] = s * fz_num(f, -1.0, 1.0);
        if (mode == 2)
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < i; j++) W[3 * i + j] = W[3 * j + i];
    }
}

static int run(const uint8_t *data, size_t size, exdex_friction_ws *ws)
{
    fz f;
    double W[9], e[3], b[3], warm[3], cap, bs;
    int mode, use_warm, st;
    exdex_friction_prep prep;
    exdex_friction_result res[3];
    int status[3];
    fz_init(&f, data, size);
    mode = fz_pick(&f, 0, 3);
    decode_W(&f, W, mode);
    if (fz_pick(&f, 0, 1)) {
        e[0] = e[1] = 1.0;
    } else {
        e[0] = fz_log(&f, 1e-3, 1e3);
        e[1] = fz_pick(&f, 0, 1) ? e[0] : fz_log(&f, 1e-3, 1e3);
    }
    e[2] = fz_log(&f, 1e-5, 1.0);
    bs = fz_log(&f, 1e-9, 1e6);
    for (int i = 0; i < 3; i++) b[i] = bs * fz_num(&f, -1.0, 1.0);
    cap = fz_pick(&f, 0, 15) == 0 ? 0.0 : fz_log(&f, 1e-9, 1e4);
    use_warm = fz_pick(&f, 0, 1);
    for (int i = 0; i < 3; i++) warm[i] = fz_num(&f, -1.0, 1.0) * cap;

    st = exdex_friction_prepare(&prep, W, e);
    FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL);
    if (!fz_all_finite(W, 9) || !fz_all_finite(e, 3)) FZ_CHECK(T, st == EXDEX_EINVAL);
    for (int i = 0; i < 3; i++)
        if (!(e[i] > 0)) FZ_CHECK(T, st == EXDEX_EINVAL);
    fuzz_count_status(T, st);
    if (st) return 0;
    if (fz_trace)
        fprintf(stderr, "  W (%.17g %.17g %.17g; %.17g %.17g %.17g; %.17g %.17g %.17g)\n  e (%.17g %.17g %.17g) b (%.17g %.17g %.17g) cap %.17g lam (%.17g %.17g %.17g)\n",
                W[0], W[1], W[2], W[3], W[4], W[5], W[6], W[7], W[8], e[0], e[1], e[2], b[0], b[1], b[2], cap,
                prep.lam[0], prep.lam[1], prep.lam[2]);
    FZ_CHECK(T, fz_all_finite(prep.K, 9) && fz_all_finite(prep.Q, 9) && fz_all_finite(prep.lam, 3));
    FZ_CHECK(T, prep.lam[0] > 0 && prep.lam[1] > 0 && prep.lam[2] > 0);

    /* invalid solver ids and a missing workspace are rejected */
    FZ_CHECK(T, exdex_friction_solve(&prep, b, cap, 3, ws, NULL, &res[0]) == EXDEX_EINVAL);
    FZ_CHECK(T, exdex_friction_solve(&prep, b, cap, -1, ws, NULL, &res[0]) == EXDEX_EINVAL);
    FZ_CHECK(T, exdex_friction_solve(&prep, b, cap, EXDEX_SOLVER_BRENT, NULL, NULL, &res[0]) ==
                    EXDEX_EINVAL);
    FZ_CHECK(T, exdex_friction_solve(&prep, b, cap, EXDEX_SOLVER_SCALAR, NULL, NULL, NULL) ==
                    EXDEX_EINVAL);

    for (int s = 0; s < 3; s++) {
        exdex_friction_result *r = &res[s];
        int inval = !fz_all_finite(b, 3) || !(cap >= 0) || !isfinite(cap) ||
                    (use_warm && !fz_all_finite(warm, 3));
        st = status[s] = exdex_friction_solve(&prep, b, cap, s, ws, use_warm ? warm : NULL, r);
        fuzz_count_status(T, st);
        if (fz_trace)
            fprintf(stderr, "  solver %d: status %d stick %d it %d p (%.17g %.17g %.17g) u (%.17g %.17g %.17g) sigma %.17g\n",
                    s, st, r->stick, r->iterations, r->p[0], r->p[1], r->p[2], r->u[0], r->u[1], r->u[2], r->sigma);
        FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL || st == EXDEX_ENOCONV || st == EXDEX_ENONFINITE);
        if (inval) {
            FZ_CHECK(T, st == EXDEX_EINVAL);
            continue;
        }
        FZ_CHECK(T, st != EXDEX_EINVAL);
        if (st == EXDEX_ENONFINITE) {
            /* only when a result is beyond the double range: p <= cap e,
             * u <= |b| + |W| cap e, sigma = |E u| (estimates, each entry
             * within a factor 10 of DBL_MAX at least) */
            double big = 0.0, emax = fmax(e[0], fmax(e[1], e[2])), wmax = 0.0;
            for (int i = 0; i < 9; i++) wmax = fmax(wmax, fabs(prep.W[i]));
            for (int i = 0; i < 3; i++) big = fmax(big, fabs(b[i]) * fmax(1.0, emax));
            big = fmax(big, cap * emax * fmax(1.0, wmax) * fmax(1.0, emax));
            FZ_CHECK(T, big > 1e-1 * DBL_MAX);
            fuzz_note_keep(T, "ENONFINITE on valid input (result beyond the double range)");
        }
        /* no solver fails on valid input (MULTIROOT falls back to the
         * secular solution, exdex.h) */
        FZ_CHECK(T, st != EXDEX_ENOCONV);
        if (st != EXDEX_OK) {
            FZ_CHECK(T, isnan(r->p[0]) && isnan(r->u[0]) && isnan(r->sigma));
            continue;
        }
        FZ_CHECK(T, fz_all_finite(r->p, 3) && fz_all_finite(r->u, 3) && isfinite(r->sigma));
        FZ_CHECK(T, r->stick == 0 || r->stick == 1);
        FZ_CHECK(T, r->iterations >= 0 && !(r->sigma < 0));
        if (!fz_all_finite(r->p, 3) || !fz_all_finite(r->u, 3)) continue;
        {
            /* inside the ellipsoid; p . u <= 0 (maximum dissipation);
             * 1/2 p'Wp + p'b <= 0 = its value at the feasible p = 0. All
             * with p, u, b scaled by their largest entries (no overflow). */
            double n2 = 0.0, pu = 0.0, pn = 0.0, un = 0.0, obj = 0.0, objs = 0.0;
            double ps = 0.0, us = 0.0, bsc = 0.0, P[3], U[3], B[3];
            for (int i = 0; i < 3; i++) {
                /* (p / e) / cap: e cap may underflow for a subnormal cap;
                 * a subnormal p_i is exact only to its absolute spacing, so
                 * the check takes |p_i| less two such spacings */
                double pi = fabs(r->p[i]) < DBL_MIN ? fmax(fabs(r->p[i]) - 2 * DBL_TRUE_MIN, 0.0) : r->p[i];
                double y = cap > 0 ? (pi / e[i]) / cap : r->p[i];
                n2 += y * y;
                ps = fmax(ps, fabs(r->p[i]));
                us = fmax(us, fabs(r->u[i]));
                bsc = fmax(bsc, fabs(b[i]));
            }
            for (int i = 0; i < 3; i++) {
                P[i] = ps > 0 ? r->p[i] / ps : 0.0;
                U[i] = us > 0 ? r->u[i] / us : 0.0;
                B[i] = bsc > 0 ? b[i] / bsc : 0.0;
                pu += P[i] * U[i];
                pn += P[i] * P[i];
                un += U[i] * U[i];
            }
            /* inside to rounding (a sliding p is rescaled onto the
             * ellipsoid, whatever cond(K)) */
            FZ_CHECK(T, cap > 0 ? n2 <= 1.0 + 1e-13 : n2 == 0.0);
            FZ_CHECK(T, pu <= 1e-9 * sqrt(pn) * sqrt(un));
            if (ps > 0 && bsc > 0) {
                /* obj / (ps bsc) = 1/2 (ps / bsc) P'WP + P'B */
                double ratio = ps / bsc;
                for (int i = 0; i < 3; i++) {
                    double WP = prep.W[3 * i] * P[0] + prep.W[3 * i + 1] * P[1] + prep.W[3 * i + 2] * P[2];
                    obj += 0.5 * ratio * P[i] * WP + P[i] * B[i];
                    objs += fabs(0.5 * ratio * P[i] * WP) + fabs(P[i] * B[i]);
                }
                if (isfinite(obj)) FZ_CHECK(T, obj <= 1e-9 * objs);
            }
            if (r->stick) FZ_CHECK(T, r->u[0] == 0 && r->u[1] == 0 && r->u[2] == 0 && r->sigma == 0);
        }
    }
    /* the solvers agree (counted, not failed: ill-conditioned W may differ) */
    if (status[0] == EXDEX_OK)
        for (int s = 1; s < 3; s++)
            if (status[s] == EXDEX_OK) {
                for (int i = 0; i < 3; i++)
                    if (!(fabs(res[s].p[i] - res[0].p[i]) <= 1e-6 * cap * e[i] + 1e-300)) {
                        fuzz_note_keep(T, s == 1 ? "BRENT differs from SCALAR by > 1e-6 cap e" : "MULTIROOT differs from SCALAR by > 1e-6 cap e");
                        break;
                    }
                FZ_CHECK(T, res[s].stick == res[0].stick);
            }
    return 0;
}

/* The workspace of the input in progress: a driver that abandons a hung
 * input (siglongjmp) leaves it here, and the next input frees it. */
static exdex_friction_ws *ws_in_progress;

int fuzz_friction(const uint8_t *data, size_t size)
{
    /* a workspace per input, so nothing is left allocated at exit */
    exdex_friction_ws_free(ws_in_progress);
    ws_in_progress = exdex_friction_ws_alloc();
    exdex_friction_ws_free(NULL);
    if (!ws_in_progress) {
        fuzz_fail(T, __FILE__, __LINE__, "exdex_friction_ws_alloc failed");
        return 0;
    }
    run(data, size, ws_in_progress);
    exdex_friction_ws_free(ws_in_progress);
    ws_in_progress = NULL;
    return 0;
}
