/* test_stop_friction.c -- Coulomb friction at the stops (stop_mu) through
 * the public API: a 1-DoF closed form with every method that supports it,
 * and the named rejections.
 * twin: tests/scenarios/test_stop_friction.py (the same subject through the Python API)
 */
#include "../check.h"
#include "../sim_run.h"
#include "../../exdex.h"

#include <math.h>
#include <string.h>

#define G 9.81

/* The centre of mass (the outline) slides along B's y (vertical) and rests
 * on an incline fixed in A with in-plane normal n = (sin a, cos a) (A: (sin
 * a, 0, cos a), B's y being A's z), while the gripper translates along x at
 * speed V (trapezoid with ramps). The gap n . (V_g + v d) = 0 fixes v =
 * -tan(a) V; the point slips along t = (-cos a, sin a) at s = -V / cos(a),
 * so the stop's friction on it is -mu lam sign(s) t, with generalized force
 * lam (cos a - sign(s) mu sin a) = lam D. At constant speed the balance on
 * the free coordinate is 0 = -m g - cap sign(v) + lam D:
 *     lam = (m g + cap sign(v)) / D.
 * Time stepping reaches it exactly (a fixed point), the event method holds
 * it exactly; the regularised one is off by cap eps^2 / (2 v^2) / D. */
static exdex_scene_def incline(double mu_s, double V, int method)
{
    exdex_scene_def d = exdex_default_scene_def();
    double a = 0.5;
    d.mass = 0.1;
    d.mu = 0.5;
    d.grip_force = 0.5;  /* capacity 2 mu F = 0.5 N */
    d.gravity[2] = -G;
    d.method = method;
    d.motion.kind = EXDEX_MOTION_TRAPEZOID;
    d.motion.axis[0] = 1.0;
    d.motion.axis[1] = d.motion.axis[2] = 0.0;
    d.motion.amplitude = copysign(0.95 * fabs(V), V);
    d.motion.duration = 1.0;
    d.motion.v_max = fabs(V);
    d.n_stops = 1;
    d.stop_normal[0][0] = sin(a);
    d.stop_normal[0][2] = cos(a);
    d.stop_mu[0] = mu_s;
    return d;
}

EXDEX_TEST(stop_friction_1dof_incline_every_method)
{
    double a = 0.5, m = 0.1, cap = 0.5, eps = 1e-4;
    for (int method = EXDEX_METHOD_IMPLICIT; method <= EXDEX_METHOD_EXPLICIT; method++)
        for (int dir = -1; dir <= 1; dir += 2) {
            double V = 0.05 * dir, v = -tan(a) * V, s = -V / cos(a);
            double D = cos(a) - copysign(1.0, s) * 0.4 * sin(a), lam = (m * G + cap * copysign(1.0, v)) / D;
            double tol = method == EXDEX_METHOD_REGULARISED ? 2 * cap * eps * eps / (2 * v * v) / D : 1e-10 * lam;
            exdex_scene_def d = incline(0.4, V, method);
            sim_run r;
            d.eps = eps;
            ENSURE(sim_run_def(&d, 0.5, 1e-3, &r) == EXDEX_OK);
            ENSURE(r.st.warnings == 0);
            ENSURE_CLOSE(r.tr.v[r.tr.n - 1], v, 1e-12 * fabs(v));
            ENSURE_CLOSE(r.tr.stop_force[r.tr.n - 1], lam, tol);
            sim_run_free(&r);
        }
}

/* stop_mu: finite and >= 0 (by name); a planar scene accepts it with every
 * method that supports stops. */
EXDEX_TEST(stop_friction_bad_input_named)
{
    const char *bad = NULL;
    exdex_scene_def d = incline(-0.1, 0.05, EXDEX_METHOD_IMPLICIT);
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && strcmp(bad, "stop_mu") == 0);
    d.stop_mu[0] = NAN;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && strcmp(bad, "stop_mu") == 0);
    d.stop_mu[0] = 0.3;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_OK);
    d.dof = EXDEX_DOF_PLANAR;
    d.q0[1] = 0.01;
    for (int method = EXDEX_METHOD_IMPLICIT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        d.method = method;
        bad = NULL;
        ENSURE(exdex_scene_check(&d, &bad) == EXDEX_OK);
    }
}
