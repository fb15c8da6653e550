/* fuzz_tool.c -- tool design (paper Section 3.1, Eq. 12): the problem check,
 * exdex_tool_rows, exdex_tool_volumes, exdex_tool_objective,
 * exdex_tool_optimise_theta and exdex_tool_optimise on fuzzed object
 * outlines (convex or arbitrary polygons), attack angles, twist boxes,
 * friction, push wrenches and tool parameters (with or without a plunger).
 *
 * Checks: an invalid problem is rejected with bad_param set and by every
 * entry point; EXDEX_OK gives at most EXDEX_CONE_MAX_ROWS finite rows (rows
 * that overflow, from data near DBL_MAX, give EXDEX_ENONFINITE),
 * volumes in [0, box volume], an objective equal to the sum of the volumes,
 * and optimum values that are finite and no worse than the scan; the
 * optimised theta lies in [theta_lo, theta_hi] (angles beyond
 * EXDEX_TOOL_ANGLE_MAX give EXDEX_EINVAL). */
#include "fuzz.h"

#include <math.h>
#include <string.h>

#define T "tool"
#define MAXV 8
#define MAXPHI 256  /* n_phi beyond this would overrun the harness's own array */

int fuzz_tool(const uint8_t *data, size_t size)
{
    fz f;
    exdex_tool_problem p;
    exdex_tool_def tool;
    int nvs[2], ns_dec, st, valid;
    double verts[2 * 2 * EXDEX_MAX_VERTICES], phi[MAXPHI], rows[3 * EXDEX_CONE_MAX_ROWS], vol[2 * MAXPHI];
    double bv;
    const char *bad = NULL;

    fz_init(&f, data, size);
    memset(&p, 0, sizeof p);
    memset(verts, 0, sizeof verts);
    p.model = fz_int(&f, 0, 1);
    p.n_shapes = fz_int(&f, 1, 2);
    if (p.n_shapes > 2) p.n_shapes = 2;  /* the length of our n_vertices array */
    ns_dec = p.n_shapes < 1 ? 0 : p.n_shapes;
    {
        size_t off = 0;
        for (int s = 0; s < ns_dec; s++) {
            int nv = fz_int(&f, 3, MAXV), nd;
            nvs[s] = nv;
            nd = nv < 0 ? 0 : nv > EXDEX_MAX_VERTICES ? EXDEX_MAX_VERTICES : nv;
            if (fz_pick(&f, 0, 3)) {
                /* convex: increasing angles on a circle, then stretched */
                double sx = fz_num(&f, 0.2, 1.0), sy = fz_num(&f, 0.2, 1.0), a0 = fz_num(&f, 0, 6.283185307179586);
                for (int i = 0; i < nd; i++) {
                    double a = a0 + 6.283185307179586 * (i + fz_num(&f, 0.0, 0.8)) / nd;
                    verts[2 * (off + i)] = sx * cos(a);
                    verts[2 * (off + i) + 1] = sy * sin(a);
                }
            } else {
                for (int i = 0; i < 2 * nd; i++) verts[2 * off + i] = fz_num(&f, -1.0, 1.0);
            }
            if (fz_pick(&f, 0, 7) == 0 && nd >= 2)  /* a repeated vertex */
                memcpy(verts + 2 * off + 2, verts + 2 * off, 2 * sizeof(double));
            off += (size_t)nd;
        }
    }
    p.n_vertices = nvs;
    p.vertices = verts;
    p.n_phi = fz_int(&f, 1, 4);
    if (p.n_phi > MAXPHI) p.n_phi = MAXPHI;
    for (int k = 0; k < 4; k++) phi[k] = fz_num(&f, -3.2, 3.2);
    for (int k = 4; k < MAXPHI; k++) phi[k] = phi[k % 4] + 0.01 * k;
    p.phi = phi;
    for (int j = 0; j < 3; j++) {
        p.hi[j] = fz_log(&f, 0.1, 3.0);
        p.lo[j] = fz_pick(&f, 0, 3) ? -p.hi[j] : fz_num(&f, -3.0, 0.0);
    }
    p.mu = fz_pick(&f, 0, 1) ? 0.0 : fz_num(&f, 0.0, 1.5);
    p.has_push = fz_pick(&f, 0, 1);
    for (int j = 0; j < 3; j++) p.push[j] = fz_num(&f, -1.0, 1.0);
    tool.alpha1 = fz_num(&f, -0.6, 0.6);
    tool.alpha2 = tool.alpha1 + fz_num(&f, 0.1, 3.1);
    tool.plunger = fz_pick(&f, 0, 1);
    tool.s = fz_num(&f, -1.0, 1.0);
    bv = (p.hi[0] - p.lo[0]) * (p.hi[1] - p.lo[1]) * (p.hi[2] - p.lo[2]);

    st = exdex_tool_problem_check(&p, &bad);
    fuzz_count_status(T, st);
    FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL);
    FZ_CHECK(T, (st == EXDEX_OK) == (bad == NULL));
    FZ_CHECK(T, exdex_tool_problem_check(NULL, NULL) == EXDEX_EINVAL);
    valid = st == EXDEX_OK;
    if (p.n_phi >= 1 && !fz_all_finite(phi, (size_t)p.n_phi)) FZ_CHECK(T, !valid);
    if (!fz_all_finite(p.lo, 3) || !fz_all_finite(p.hi, 3) || !isfinite(p.mu)) FZ_CHECK(T, !valid);
    if (p.has_push && !fz_all_finite(p.push, 3)) FZ_CHECK(T, !valid);

    if (valid) {
        int ns = p.model == EXDEX_TOOL_PAPER ? 1 : p.n_shapes, tool_ok = 1;
        double sum = 0.0, obj = NAN;
        for (int s = 0; s <= ns; s++)
            for (int k = 0; k < p.n_phi; k++) {
                int nrows = -1;
                st = exdex_tool_rows(&p, &tool, s, phi[k], rows, &nrows);
                fuzz_count_status(T, st);
                FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL || st == EXDEX_ENONFINITE);
                if (s == ns && p.model == EXDEX_TOOL_CONTACT) FZ_CHECK(T, st == EXDEX_EINVAL);
                /* a row overflows only for vertices or a push near DBL_MAX */
                if (st == EXDEX_ENONFINITE) FZ_CHECK(T, f.wild > 0);
                if (st == EXDEX_OK) {
                    FZ_CHECK(T, nrows >= 0 && nrows <= EXDEX_CONE_MAX_ROWS);
                    FZ_CHECK(T, fz_all_finite(rows, 3 * (size_t)nrows));
                } else if (s < ns) {
                    tool_ok = 0;
                }
            }
        if (!isfinite(tool.alpha1) || !isfinite(tool.alpha2) || (tool.plunger && !isfinite(tool.s)))
            FZ_CHECK(T, !tool_ok);
        st = exdex_tool_volumes(&p, 1, &tool, vol);
        fuzz_count_status(T, st);
        FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL || st == EXDEX_ENONFINITE);
        if (st == EXDEX_OK)
            for (int i = 0; i < ns * p.n_phi; i++) {
                FZ_CHECK(T, isfinite(vol[i]) && vol[i] >= 0 && vol[i] <= bv);
                sum += vol[i];
            }
        {
            int st2 = exdex_tool_objective(&p, &tool, &obj);
            /* the sum overflows only for boxes near DBL_MAX: ENONFINITE */
            FZ_CHECK(T, st2 == st || (st == EXDEX_OK && st2 == EXDEX_ENONFINITE && !isfinite(sum)));
            if (st == EXDEX_OK && st2 == EXDEX_OK) FZ_CHECK(T, fabs(obj - sum) <= 1e-12 * fabs(sum) + 1e-300);
        }
        FZ_CHECK(T, exdex_tool_volumes(&p, 1, NULL, vol) == EXDEX_EINVAL);
        FZ_CHECK(T, exdex_tool_objective(&p, &tool, NULL) == EXDEX_EINVAL);
        if (fz_pick(&f, 0, 3) == 0) {
            double th_lo = fz_num(&f, 0.1, 1.5), th_hi = th_lo + fz_num(&f, 0.05, 1.5), xtol = fz_log(&f, 1e-8, 1e-2);
            int n_scan = fz_int(&f, 3, 8), use_scan = fz_pick(&f, 0, 1);
            double scan[8];
            exdex_tool_opt_result res;
            if (n_scan > 8) use_scan = 0;  /* our buffer; NULL lets the library allocate */
            if (n_scan > 64) n_scan = 64;  /* bounded runtime */
            st = exdex_tool_optimise_theta(&p, &tool, th_lo, th_hi, n_scan, xtol, use_scan ? scan : NULL, &res);
            fuzz_count_status(T, st);
            FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL || st == EXDEX_ENOCONV || st == EXDEX_ENOMEM ||
                        st == EXDEX_ENONFINITE);
            if (!isfinite(th_lo) || !isfinite(th_hi) || !(th_hi > th_lo) || n_scan < 3 || !(xtol > 0))
                FZ_CHECK(T, st == EXDEX_EINVAL);
            /* angles beyond the bound: alpha1 + theta cannot resolve theta */
            if (!(fabs(tool.alpha1) <= EXDEX_TOOL_ANGLE_MAX) || !(fabs(th_lo) <= EXDEX_TOOL_ANGLE_MAX) ||
                !(fabs(th_hi) <= EXDEX_TOOL_ANGLE_MAX))
                FZ_CHECK(T, st == EXDEX_EINVAL);
            if (st == EXDEX_OK) {
                double th = res.x[1] - res.x[0];
                /* s is handed back as given (it is unused without a plunger) */
                FZ_CHECK(T, isfinite(res.f) && fz_all_finite(res.x, 2) && (res.x[2] == tool.s || isnan(tool.s)));
                /* every accepted input: |alpha1|, |theta| <= EXDEX_TOOL_ANGLE_MAX
                 * (1e6) make th off by <= eps/2 (2e6) = 2.3e-10 at most */
                FZ_CHECK(T, th >= th_lo - 1e-9 * (1 + fabs(th_lo)) && th <= th_hi + 1e-9 * (1 + fabs(th_hi)));
                if (use_scan)
                    for (int i = 0; i < n_scan; i++) FZ_CHECK(T, res.f <= scan[i]);
            }
        }
        if (fz_pick(&f, 0, 3) == 0) {
            int fr[3] = {fz_pick(&f, 0, 1), fz_pick(&f, 0, 1), fz_pick(&f, 0, 1)};
            double step[3] = {fz_num(&f, 0.01, 0.5), fz_num(&f, 0.01, 0.5), fz_num(&f, 0.01, 0.5)};
            int max_iter = fz_int(&f, 1, 15);
            double size_tol = fz_log(&f, 1e-6, 1e-2);
            exdex_tool_opt_result res;
            if (max_iter > 200) max_iter = 200;  /* bounded runtime */
            st = exdex_tool_optimise(&p, &tool, fr, step, max_iter, size_tol, &res);
            fuzz_count_status(T, st);
            FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL || st == EXDEX_ENOCONV || st == EXDEX_ENOMEM ||
                        st == EXDEX_ENONFINITE);
            if (!fr[0] && !fr[1] && !fr[2]) FZ_CHECK(T, st == EXDEX_EINVAL);
            if (st == EXDEX_OK) FZ_CHECK(T, isfinite(res.f) && fz_all_finite(res.x, 3));
        }
    } else {
        double obj;
        FZ_CHECK(T, exdex_tool_volumes(&p, 1, &tool, vol) == EXDEX_EINVAL);
        FZ_CHECK(T, exdex_tool_objective(&p, &tool, &obj) == EXDEX_EINVAL);
    }
    return 0;
}
