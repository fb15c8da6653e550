/* test_analytic.c -- EXDEX_METHOD_ANALYTIC against closed forms, the event
 * method, and the scenes it must refuse.
 * twin: tests/scenarios/test_analytic.py (the same subject through the Python API)
 */
#include "check.h"
#include "sim_run.h"

#include <string.h>

/* Paper Fig. 3: Eq. 7 (beta 0.9, X1 0.1 m, T 0.5 s) downward first, vertical
 * plates, m 0.1 kg, mu 0.5, two fingers. */
static exdex_scene_def fig3(double grip, int method)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = 0.1;
    d.mu = 0.5;
    d.grip_force = grip;
    d.motion.kind = EXDEX_MOTION_ASYMMETRIC;
    d.motion.amplitude = 0.1;
    d.motion.duration = 0.5;
    d.motion.beta = 0.9;
    d.motion.axis[0] = d.motion.axis[1] = 0.0;
    d.motion.axis[2] = -1.0;
    d.method = method;
    return d;
}

/* Final slip in closed form: the object sticks on [0, beta T), slips for
 * tau = (2 - 2 beta) T at the rate -u (u = g + |a_L| - c, c the capacity per
 * unit mass), decelerates at D - u (D = a_H + |a_L|) and sticks again:
 * s = -u tau^2 D / (2 (D - u)) (a_H = 2 X1 / (beta T^2), |a_L| =
 * 2 X1 / ((1 - beta) T^2), Eq. 9). */
static double fig3_slip(double grip)
{
    double a_h = 2 * 0.1 / (0.9 * 0.25), a_l = 2 * 0.1 / (0.1 * 0.25), c = 0.5 * 2 * grip / 0.1;
    double u = 9.81 + a_l - c, D = a_h + a_l, tau = 0.2 * 0.5;
    return -u * tau * tau * D / (2 * (D - u));
}

EXDEX_TEST(analytic_fig3_closed_form)
{
    double grips[3] = {1.3, 1.50514, 1.7};
    for (int i = 0; i < 3; i++) {
        exdex_scene_def d = fig3(grips[i], EXDEX_METHOD_ANALYTIC);
        sim_run r;
        ENSURE(sim_run_def(&d, 1.5, 1.5, &r) == EXDEX_OK);
        ENSURE_CLOSE(r.tr.q[1] - r.tr.q[0], fig3_slip(grips[i]), 1e-15);
        ENSURE(r.tr.v[1] == 0.0 && r.tr.stick[1]);
        sim_run_free(&r);
    }
}

EXDEX_TEST(analytic_agrees_with_event_and_ignores_output_grid)
{
    double grips[4] = {0.9, 1.3, 1.6, 3.0};
    for (int i = 0; i < 4; i++) {
        exdex_scene_def da = fig3(grips[i], EXDEX_METHOD_ANALYTIC), de = fig3(grips[i], EXDEX_METHOD_EVENT);
        sim_run a, b, e;
        de.rtol = 1e-12;
        de.atol = 1e-15;
        ENSURE(sim_run_def(&da, 1.5, 1e-3, &a) == EXDEX_OK);
        ENSURE(sim_run_def(&da, 1.5, 1.5, &b) == EXDEX_OK);
        ENSURE(sim_run_def(&de, 1.5, 1e-3, &e) == EXDEX_OK);
        for (size_t k = 0; k < a.tr.n; k++) {
            ENSURE_CLOSE(a.tr.q[k], e.tr.q[k], 1e-13);
            ENSURE_CLOSE(a.tr.v[k], e.tr.v[k], 1e-12);
            ENSURE(a.tr.stick[k] == e.tr.stick[k]);
            /* mean friction over each interval (the event method integrates it) */
            ENSURE_CLOSE(a.tr.wrench[3 * k + 1], e.tr.wrench[3 * k + 1], 1e-9);
        }
        /* samples are evaluated from their segment's start: the same final state */
        ENSURE(a.tr.q[a.tr.n - 1] == b.tr.q[1] && a.tr.v[a.tr.n - 1] == b.tr.v[1]);
        sim_run_free(&a);
        sim_run_free(&b);
        sim_run_free(&e);
    }
}

EXDEX_TEST(analytic_refuses_other_scenes)
{
    const char *bad = NULL;
    int status = 0;
    exdex_scene_def d = fig3(1.5, EXDEX_METHOD_ANALYTIC);
    ENSURE(exdex_analytic_unsupported(&d) == NULL);
    d.dof = EXDEX_DOF_PLANAR;
    ENSURE(exdex_analytic_unsupported(&d) != NULL);
    ENSURE(exdex_model_alloc(&d, &status, &bad) == NULL && status == EXDEX_EINVAL && !strcmp(bad, "method"));
    d = fig3(1.5, EXDEX_METHOD_ANALYTIC);
    d.n_stops = 1;
    d.stop_point[0][2] = -1.0;
    d.stop_normal[0][2] = 1.0;
    ENSURE(exdex_analytic_unsupported(&d) != NULL);
    d = fig3(1.5, EXDEX_METHOD_ANALYTIC);
    d.motion.rotation = 1;               /* a turning gripper in a translation scene */
    ENSURE(exdex_analytic_unsupported(&d) != NULL);
    d = fig3(1.5, EXDEX_METHOD_ANALYTIC);
    d.motion.kind = EXDEX_MOTION_TRAPEZOID;
    d.motion.v_max = 0.1 / 0.5;          /* |X1| / T: constant speed, velocity jumps */
    ENSURE(exdex_analytic_unsupported(&d) != NULL);
    d.motion.v_max = 0.3;                /* ramps */
    ENSURE(exdex_analytic_unsupported(&d) == NULL);
    /* rotation: about the centre of mass, the gripper turning about the
     * plate normal (B z = -A y for the default R0) */
    d = fig3(1.5, EXDEX_METHOD_ANALYTIC);
    d.dof = EXDEX_DOF_ROTATION;
    d.motion.rotation = 1;
    d.motion.axis[0] = 0.0;
    d.motion.axis[1] = -1.0;
    d.motion.axis[2] = 0.0;
    ENSURE(exdex_analytic_unsupported(&d) == NULL);
    d.patch_center[0] = 0.01;            /* an offset centre of mass: a pendulum */
    ENSURE(exdex_analytic_unsupported(&d) != NULL);
    d.patch_center[0] = 0.0;
    d.motion.axis[2] = 1e-3;             /* tilted axis: gyroscopic terms */
    ENSURE(exdex_analytic_unsupported(&d) != NULL);
}

/* Rotation about the centre of mass: I_zz thdd = -I_zz dw_z + tau_f; a gripper
 * at rest and an initial spin omega0 decelerate at c = mu N e_r / I_zz and stop
 * after omega0^2 / (2 c). */
EXDEX_TEST(analytic_spin_down_closed_form)
{
    exdex_scene_def d = exdex_default_scene_def();
    sim_run r;
    double c;
    d.dof = EXDEX_DOF_ROTATION;
    d.method = EXDEX_METHOD_ANALYTIC;
    d.inertia[8] = 2e-3;
    d.e_r = 0.01;
    d.v0[2] = 3.0;
    c = d.mu * 2 * d.grip_force * d.e_r / d.inertia[8];
    ENSURE(sim_run_def(&d, 2.0, 0.25, &r) == EXDEX_OK);
    ENSURE_CLOSE(r.tr.q[r.tr.n - 1] - r.tr.q[0], 9.0 / (2 * c), 1e-14);
    ENSURE(r.tr.v[r.tr.n - 1] == 0.0);
    /* at t = 0.25 s it still turns: omega0 t - c t^2 / 2 */
    ENSURE_CLOSE(r.tr.q[1] - r.tr.q[0], 3.0 * 0.25 - 0.5 * c * 0.0625, 1e-15);
    sim_run_free(&r);
}
