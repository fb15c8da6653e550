/* test_static_friction.c -- static and kinetic friction (exdex_scene_def.mu_static):
 * the input check, closed forms of a stick after a slip and of a breakaway
 * in every method, and mu_static = mu giving the one-coefficient results
 * bit for bit.
 * twin: tests/scenarios/test_static_friction.py (the same subject through the Python API)
 */
#include "../check.h"
#include "../sim_run.h"

#include <string.h>

/* The default scene: vertical plates, the object slides along B y = A z
 * (up), m = 1 kg, g = 9.81 m/s^2 down, two fingers of grip F: kinetic
 * capacity ck = 2 mu F, static cs = 2 mu_static F, per unit mass. */
static exdex_scene_def vertical(double mu, double mu_static, double grip, double v0, int method)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mu = mu;
    d.mu_static = mu_static;
    d.grip_force = grip;
    d.v0[1] = v0;
    d.method = method;
    d.rtol = 1e-12;
    d.atol = 1e-14;
    return d;
}

EXDEX_TEST(static_rejects_bad_mu_static)
{
    const char *bad = NULL;
    exdex_scene_def d = vertical(0.5, 0.4, 1.0, 0.0, EXDEX_METHOD_IMPLICIT);
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && !strcmp(bad, "mu_static"));
    d.mu_static = NAN;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && !strcmp(bad, "mu_static"));
    d.mu_static = INFINITY;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && !strcmp(bad, "mu_static"));
    d.mu_static = -0.5;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && !strcmp(bad, "mu_static"));
    d.mu_static = 0.0;   /* equal to mu */
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_OK);
    d.mu_static = 0.5;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_OK);
    d.mu = 0.0;          /* no kinetic friction, static friction only */
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_OK);
}

/* Thrown up at v0 with g < cs: the slip decelerates at g + ck, stops at
 * t1 = v0 / (g + ck) after s1 = v0^2 / (2 (g + ck)), and the static
 * friction holds the weight from then on (g <= cs). With mu_static = mu
 * (cs = ck < g) it slides back down at g - ck instead:
 * s(t) = s1 - (g - ck) (t - t1)^2 / 2. Implicit: the stick test of a step
 * with the static capacity can stop the slip one step early, an error of
 * at most v0 dt in s (the speed over that step is at most v0); explicit:
 * symplectic Euler steps at most v0 dt off s1 each, stopped in the step
 * whose kinetic update reverses the slip (its re-stick rule), which is
 * at most one step from t1: at most v0 dt; event: rtol; analytic:
 * rounding. */
EXDEX_TEST(static_stick_after_slip_closed_form)
{
    const double g = 9.81, v0 = 1.0, grip = 8.0, ck = 2 * 0.5 * grip, t_end = 0.3, dt = 1e-4;
    const double t1 = v0 / (g + ck), s1 = v0 * v0 / (2 * (g + ck));
    int methods[4] = {EXDEX_METHOD_ANALYTIC, EXDEX_METHOD_EVENT, EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EXPLICIT};
    double tol[4] = {1e-15, 1e-10, v0 * dt, v0 * dt};
    for (int i = 0; i < 4; i++) {
        exdex_scene_def d = vertical(0.5, 0.8, grip, v0, methods[i]);
        sim_run r;
        size_t n;
        ENSURE(sim_run_def(&d, t_end, dt, &r) == EXDEX_OK);
        n = r.tr.n;
        ENSURE_CLOSE(r.tr.q[n - 1] - r.tr.q[0], s1, tol[i]);
        ENSURE(r.tr.v[n - 1] == 0.0 && r.tr.stick[n - 1]);
        sim_run_free(&r);
        d.mu_static = 0.5;
        ENSURE(sim_run_def(&d, t_end, dt, &r) == EXDEX_OK);
        ENSURE_CLOSE(r.tr.q[r.tr.n - 1] - r.tr.q[0], s1 - 0.5 * (g - ck) * (t_end - t1) * (t_end - t1),
                     i >= 2 ? 20 * v0 * dt : tol[i]);
        ENSURE(r.tr.v[r.tr.n - 1] < 0.0);
        sim_run_free(&r);
    }
}

/* At rest under its weight: it stays exactly at rest while g <= cs
 * (grip 6.2: cs = 9.92), in every method but the regularised one (which
 * creeps); with cs < g (grip 6.0: cs = 9.6) it breaks away at t = 0 and
 * slides against ck = 2 mu grip = 6: s(t) = -(g - ck) t^2 / 2. The explicit method holds the load at rest by the
 * static rule and, once sliding (a load above ck, never reversing), is
 * symplectic Euler: s error <= (g - ck) t dt. */
EXDEX_TEST(static_breakaway_at_the_static_limit)
{
    const double g = 9.81, t_end = 0.5, dt = 1e-3;
    int methods[4] = {EXDEX_METHOD_ANALYTIC, EXDEX_METHOD_EVENT, EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EXPLICIT};
    for (int i = 0; i < 4; i++) {
        exdex_scene_def d = vertical(0.5, 0.8, 6.2, 0.0, methods[i]);
        sim_run r;
        double ck = 6.0, s;
        ENSURE(sim_run_def(&d, t_end, dt, &r) == EXDEX_OK);
        for (size_t k = 1; k < r.tr.n; k++) ENSURE(r.tr.v[k] == 0.0 && r.tr.q[k] == r.tr.q[0] && r.tr.stick[k]);
        /* the friction holds the weight exactly: the mean wrench is m g up */
        ENSURE_CLOSE(r.tr.wrench[3 * (r.tr.n - 1) + 1], g, 1e-12);
        sim_run_free(&r);
        d.grip_force = 6.0;
        ENSURE(sim_run_def(&d, t_end, dt, &r) == EXDEX_OK);
        s = -0.5 * (g - ck) * t_end * t_end;
        ENSURE_CLOSE(r.tr.q[r.tr.n - 1] - r.tr.q[0], s, i < 2 ? 1e-10 : (g - ck) * t_end * dt);
        ENSURE(!r.tr.stick[r.tr.n - 1]);
        sim_run_free(&r);
    }
}

/* The regularised law with two coefficients (hybrid.c: a stick band
 * |u| <= eps, viscous up to cs, Coulomb with ck beyond) is first order in
 * eps, on the two closed forms above:
 *   thrown up at v0 (grip 8: cs = 12.8 > g): the slip decelerates under the
 *   exact kinetic law down to |u| = eps, then the band catches it at the
 *   creep speed eps g / cs < eps: |s - s1| <= eps t_end;
 *   from rest with cs < g (grip 6: cs = 9.6): the band lets the load through
 *   (u' <= -(g - cs) while |u| < eps), so the slip leaves it within
 *   tau = eps / (g - cs), where the exact one has (g - ck) tau: the speeds
 *   differ by at most eps (g - ck) / (g - cs) from then on, and
 *   |s + (g - ck) t^2 / 2| <= eps (g - ck) / (g - cs) t_end.
 * Both errors fall by 3.5 .. 4.5 for a factor 4 of eps. */
EXDEX_TEST(static_regularised_first_order)
{
    const double g = 9.81, v0 = 1.0, ck8 = 8.0, ck6 = 6.0, cs6 = 9.6, t_end = 0.3;
    const double s1 = v0 * v0 / (2 * (g + ck8));
    double err[2][2];
    for (int k = 0; k < 2; k++) {
        double eps = k ? 2.5e-5 : 1e-4;
        for (int c = 0; c < 2; c++) {
            exdex_scene_def d = vertical(0.5, 0.8, c ? 6.0 : 8.0, c ? 0.0 : v0, EXDEX_METHOD_REGULARISED);
            sim_run r;
            double s, want = c ? -0.5 * (g - ck6) * t_end * t_end : s1;
            d.eps = eps;
            d.rtol = 1e-10;
            d.atol = 1e-13;
            ENSURE(sim_run_def(&d, t_end, 1e-3, &r) == EXDEX_OK);
            s = r.tr.q[r.tr.n - 1] - r.tr.q[0];
            err[k][c] = fabs(s - want);
            ENSURE(err[k][c] <= (c ? eps * (g - ck6) / (g - cs6) * t_end : eps * t_end));
            sim_run_free(&r);
        }
    }
    for (int c = 0; c < 2; c++) ENSURE(err[0][c] > 3.5 * err[1][c] && err[0][c] < 4.5 * err[1][c]);
}

/* mu = 0 with mu_static > 0: no kinetic friction at all, but the static
 * capacity holds a load inside it. */
EXDEX_TEST(static_without_kinetic_friction)
{
    exdex_scene_def d = vertical(0.0, 1.0, 6.0, 0.0, EXDEX_METHOD_IMPLICIT);
    sim_run r;
    ENSURE(sim_run_def(&d, 0.2, 1e-3, &r) == EXDEX_OK);   /* cs = 12 > g: held */
    ENSURE(r.tr.v[r.tr.n - 1] == 0.0 && r.tr.q[r.tr.n - 1] == r.tr.q[0]);
    sim_run_free(&r);
    d.v0[1] = -0.1;   /* sliding: free fall relative to the plates, s = -0.1 t - g t^2 / 2 */
    d.method = EXDEX_METHOD_EVENT;
    ENSURE(sim_run_def(&d, 0.2, 1e-3, &r) == EXDEX_OK);
    ENSURE_CLOSE(r.tr.q[r.tr.n - 1] - r.tr.q[0], -0.1 * 0.2 - 0.5 * 9.81 * 0.04, 1e-10);
    sim_run_free(&r);
}

static int same_run(const sim_run *a, const sim_run *b, int nd, int ns)
{
    size_t n = a->tr.n;
    return a->status == b->status && n == b->tr.n && !memcmp(a->tr.q, b->tr.q, n * nd * sizeof(double)) &&
           !memcmp(a->tr.v, b->tr.v, n * nd * sizeof(double)) &&
           !memcmp(a->tr.wrench, b->tr.wrench, n * 3 * sizeof(double)) && !memcmp(a->tr.stick, b->tr.stick, n) &&
           (!ns || !memcmp(a->tr.stop_force, b->tr.stop_force, n * ns * sizeof(double)));
}

/* mu_static = mu and mu_static = 0 (its "equal" default) give the same bits
 * in every method, on a 1-DoF scene with a stop and a planar box on a
 * stop, both under an asymmetric shake. */
EXDEX_TEST(static_equal_is_bit_identical)
{
    int methods[5] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EVENT, EXDEX_METHOD_REGULARISED, EXDEX_METHOD_EXPLICIT,
                      EXDEX_METHOD_ANALYTIC};
    for (int planar = 0; planar < 2; planar++)
        for (int i = 0; i < 5; i++) {
            exdex_scene_def d = vertical(0.5, 0.0, 1.2, 0.0, methods[i]);
            sim_run a, b;
            if (planar && methods[i] == EXDEX_METHOD_ANALYTIC) continue;
            d.mass = 0.1;
            d.inertia[0] = d.inertia[4] = d.inertia[8] = 1e-4;
            d.motion.kind = EXDEX_MOTION_ASYMMETRIC;
            d.motion.amplitude = 0.1;
            d.motion.duration = 0.3;
            d.motion.beta = 0.8;
            d.motion.axis[0] = d.motion.axis[1] = 0.0;
            d.motion.axis[2] = -1.0;
            d.rtol = 1e-8;
            d.atol = 1e-10;
            if (planar) {
                d.dof = EXDEX_DOF_PLANAR;
                d.patch_center[0] = 0.01;
                scene_rect(&d, 0.03, 0.03);
                d.n_stops = 1;
                d.stop_point[0][2] = -0.1;
                d.stop_normal[0][2] = 1.0;
            }
            ENSURE(sim_run_def(&d, 0.8, 1e-3, &a) == EXDEX_OK);
            d.mu_static = d.mu;
            ENSURE(sim_run_def(&d, 0.8, 1e-3, &b) == EXDEX_OK);
            ENSURE(same_run(&a, &b, a.ndof, a.nstops));
            ENSURE(a.st.steps == b.st.steps && a.st.stick_steps == b.st.stick_steps &&
                   a.st.solver_iterations == b.st.solver_iterations);
            sim_run_free(&a);
            sim_run_free(&b);
        }
}
