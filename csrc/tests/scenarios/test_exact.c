/* test_exact.c -- scenes with the exact limit surface
 * (exdex_scene_def.limit_surface): validation, and the free sliding and
 * spinning uniform disc.
 *
 * The free disc: a uniform disc (inertia m R^2 / 2) pressed by plates of
 * uniform pressure over the whole disc, launched sliding at v0 and spinning
 * at w0, no other force. References:
 *   exact surface  both motions stop at the same instant, and v / (R w)
 *                  tends to 0.653 whatever the start (Farkas, Bartels,
 *                  Unger and Wolf, Phys. Rev. Lett. 90, 248302, 2003).
 *   ellipsoid      (e_r = 2R/3) derived here: m v' = -C v / S,
 *                  I w' = -C e_r^2 w / S, S = sqrt(v^2 + e_r^2 w^2), so
 *                  d ln(v/w) / d ln w = I / (m e_r^2) - 1 = 1/8 and
 *                  v / (R w) = eps0 (w / w0)^(1/8): the ratio keeps a memory
 *                  of its start and drifts to 0 as the spin stops.
 */
#include "../check.h"
#include "../sim_run.h"
#include "../../exdex.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

static exdex_scene_def free_disc(int surface, int method, double R, double v0, double w0)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.dof = EXDEX_DOF_PLANAR;
    d.mass = 1.0;
    d.inertia[0] = d.inertia[4] = 0.25 * R * R;
    d.inertia[8] = 0.5 * R * R;
    d.gravity[2] = 0.0;
    d.mu = 0.5;
    d.grip_force = 1.0; /* C = 2 mu F = 1 N */
    d.e_r = 2.0 * R / 3.0;
    d.limit_surface = surface;
    d.region_kind = EXDEX_REGION_DISC;
    d.region_radius = R;
    d.v0[0] = v0;
    d.v0[2] = w0;
    d.method = method;
    d.rtol = 1e-10;
    d.atol = 1e-12;
    return d;
}

EXDEX_TEST(exact_rejects)
{
    exdex_scene_def d = free_disc(EXDEX_LS_EXACT, EXDEX_METHOD_IMPLICIT, 0.02, 1, 1);
    int st;
    const char *bad = NULL;
    exdex_model *m = exdex_model_alloc(&d, &st, &bad);
    ENSURE(m && st == EXDEX_OK);
    exdex_model_free(m);
    d.region_kind = EXDEX_REGION_NONE;
    bad = NULL;
    ENSURE(!exdex_model_alloc(&d, &st, &bad) && st == EXDEX_EINVAL && bad && strcmp(bad, "region_kind") == 0);
    d = free_disc(EXDEX_LS_EXACT, EXDEX_METHOD_IMPLICIT, 0.02, 1, 1);
    d.region_kind = EXDEX_REGION_POLYGON;
    d.region_n = 3;
    /* clockwise: rejected; counter-clockwise: accepted */
    d.region_vertices[0][0] = 0.0, d.region_vertices[0][1] = 0.0;
    d.region_vertices[1][0] = 0.0, d.region_vertices[1][1] = 0.01;
    d.region_vertices[2][0] = 0.01, d.region_vertices[2][1] = 0.0;
    ENSURE(!exdex_model_alloc(&d, &st, &bad) && st == EXDEX_EINVAL && strcmp(bad, "region_kind") == 0);
    d.region_vertices[1][0] = 0.01, d.region_vertices[1][1] = 0.0;
    d.region_vertices[2][0] = 0.0, d.region_vertices[2][1] = 0.01;
    m = exdex_model_alloc(&d, &st, &bad);
    ENSURE(m && st == EXDEX_OK);
    exdex_model_free(m);
    d.limit_surface = 2;
    ENSURE(!exdex_model_alloc(&d, &st, &bad) && st == EXDEX_EINVAL && strcmp(bad, "limit_surface") == 0);
    /* the implicit method with a frictional stop: accepted (its stop friction takes the exact surface) */
    d = free_disc(EXDEX_LS_EXACT, EXDEX_METHOD_IMPLICIT, 0.02, 1, 1);
    d.n_stops = 1;
    d.stop_normal[0][2] = 1.0;
    d.stop_point[0][2] = -1.0;
    d.stop_mu[0] = 0.3;
    d.n_vertices = 3;
    m = exdex_model_alloc(&d, &st, &bad);
    ENSURE(m && st == EXDEX_OK);
    exdex_model_free(m);
}

/* the last sample whose spin is still above frac * w0 (the slip, before the stop) */
static size_t sample_at(const sim_run *r, double w0, double frac)
{
    size_t k = 0;
    for (size_t i = 0; i < r->tr.n; i++)
        if (fabs(r->tr.v[3 * i + 2]) > frac * fabs(w0)) k = i;
    return k;
}

static double ratio_at(const sim_run *r, double R, double w0, double frac)
{
    size_t i = sample_at(r, w0, frac);
    return hypot(r->tr.v[3 * i], r->tr.v[3 * i + 1]) / (R * fabs(r->tr.v[3 * i + 2]));
}

EXDEX_TEST(exact_free_disc_ratio)
{
    const double R = 0.02;
    /* starts of very different ratios eps0 = v0 / (R w0), and one on the
     * attractor */
    const double eps0[4] = {0.3, 1.0, 3.0, 0.653};
    for (int method = 0; method < 2; method++)
        for (int k = 0; k < 4; k++) {
            double w0 = 40.0, v0 = eps0[k] * R * w0;
            exdex_scene_def d = free_disc(EXDEX_LS_EXACT, method ? EXDEX_METHOD_EVENT : EXDEX_METHOD_IMPLICIT, R, v0, w0);
            sim_run r;
            int st = sim_run_def(&d, 3.0, method ? 1e-4 : 2e-5, &r);
            ENSURE(st == EXDEX_OK);
            if (st == EXDEX_OK) {
                double r1 = ratio_at(&r, R, w0, 1e-1), r2 = ratio_at(&r, R, w0, 1e-2), r3 = ratio_at(&r, R, w0, 1e-3);
                if (k < 3) {
                    /* a monotone approach to 0.653 as the motion dies out */
                    ENSURE(fabs(r3 - 0.653) < fabs(r2 - 0.653) && fabs(r2 - 0.653) < fabs(r1 - 0.653));
                    ENSURE(fabs(r3 - 0.653) < 0.03);
                } else {
                    /* on the attractor the ratio stays (the implicit step to its first-order error) */
                    double tol = method ? 1e-4 : 2e-3;
                    ENSURE_CLOSE(r1, 0.653, tol);
                    ENSURE_CLOSE(r2, 0.653, tol);
                    ENSURE_CLOSE(r3, 0.653, tol);
                }
                char key[96];
                snprintf(key, sizeof key, "exact free disc v/(R w) at w = 1e-3 w0 %s eps0=%g", method ? "event" : "implicit",
                         eps0[k]);
                report(key, r3);
                /* both stop at the same instant: the first sample at rest has v = w = 0,
                 * and before it neither motion has stopped alone */
                size_t j = 0;
                while (j < r.tr.n && !(r.tr.v[3 * j] == 0.0 && r.tr.v[3 * j + 1] == 0.0 && r.tr.v[3 * j + 2] == 0.0)) j++;
                ENSURE(j < r.tr.n && j > 1);
                for (size_t q = 1; q < j; q++) ENSURE(fabs(r.tr.v[3 * q + 2]) > 0.0 && hypot(r.tr.v[3 * q], r.tr.v[3 * q + 1]) > 0.0);
                for (size_t q = j; q < r.tr.n; q++) ENSURE(r.tr.v[3 * q] == 0.0 && r.tr.v[3 * q + 2] == 0.0);
            }
            sim_run_free(&r);
        }
}

EXDEX_TEST(exact_free_disc_ellipsoid_drift)
{
    const double R = 0.02, w0 = 40.0;
    for (int k = 0; k < 2; k++) {
        double eps0 = k ? 2.0 : 0.5, v0 = eps0 * R * w0;
        exdex_scene_def d = free_disc(EXDEX_LS_ELLIPSOID, EXDEX_METHOD_EVENT, R, v0, w0);
        sim_run r;
        ENSURE(sim_run_def(&d, 3.0, 2e-4, &r) == EXDEX_OK);
        /* v / (R w) = eps0 (w / w0)^(1/8) along the whole slip */
        for (int f = 1; f <= 4; f++) {
            size_t i = sample_at(&r, w0, pow(10.0, -f));
            double v = hypot(r.tr.v[3 * i], r.tr.v[3 * i + 1]), w = fabs(r.tr.v[3 * i + 2]);
            ENSURE_CLOSE(v / (R * w), eps0 * pow(w / w0, 0.125), 1e-6 * eps0);
        }
        size_t i = sample_at(&r, w0, 1e-4);
        double v = hypot(r.tr.v[3 * i], r.tr.v[3 * i + 1]), w = fabs(r.tr.v[3 * i + 2]);
        report(k ? "ellipsoid free disc v/(R w) at w = 1e-4 w0, eps0=2" : "ellipsoid free disc v/(R w) at w = 1e-4 w0, eps0=0.5",
               v / (R * w));
        sim_run_free(&r);
    }
}
