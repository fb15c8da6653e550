/* test_stepper.c -- exdex_stepper (stepper.c): stepping reproduces
 * exdex_simulate bit for bit (an independent driver of the same methods:
 * the whole-run loop), save / restore branches repeat exactly, bad
 * arguments are rejected by status, and a grip change between steps acts
 * as its closed form says:
 *   held (capacity above m g) until t_r, then released (grip 0): free fall
 *   from rest, s(t) = s(t_r) - g (t - t_r)^2 / 2, v = -g (t - t_r);
 *   the midpoint rule is exact for a constant acceleration, the event
 *   method integrates it to its tolerance.
 * twin: tests/test_stepper.py (the same subject through the Python API)
 */
#include "check.h"
#include "sim_run.h"
#include "../exdex.h"
#include "../hybrid.h"   /* ode, hyb_rhs: the event method's workspace (the budget test) */
#include "../method.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define G 9.81

static exdex_scene_def vertical(int method)
{
    exdex_scene_def d = scene_vertical(0.2, 1.5);
    scene_eq7(&d, 0, 0.0, 0.0, -1.0, 0.1, 0.2, 0.8);
    d.method = method;
    return d;
}

/* planar: a 4 cm square turned by an Eq. 7 rotation of the gripper about
 * the plate normal, a floor stop below it */
static exdex_scene_def planar(int method)
{
    exdex_scene_def d = exdex_default_scene_def();
    const double hx = 0.02;
    d.mass = 0.1;
    d.inertia[0] = d.inertia[4] = d.inertia[8] = d.mass * (2 * hx) * (2 * hx) / 6;
    d.mu = 0.4;
    d.grip_force = 0.9;
    d.dof = EXDEX_DOF_PLANAR;
    scene_rect(&d, hx, hx);
    d.n_stops = 1;
    d.stop_point[0][2] = -0.03;
    d.stop_normal[0][2] = 1.0;
    d.motion.kind = EXDEX_MOTION_ASYMMETRIC;
    d.motion.rotation = 1;
    d.motion.axis[0] = 0.0;
    d.motion.axis[1] = -1.0;   /* B z = -A y: about the plate normal */
    d.motion.axis[2] = 0.0;
    d.motion.amplitude = 0.6;
    d.motion.duration = 0.25;
    d.motion.beta = 0.7;
    d.method = method;
    return d;
}

static int same_bits(const void *a, const void *b, size_t n) { return memcmp(a, b, n) == 0; }

/* n steps of dt against exdex_simulate(m, n dt, dt): every sample, the
 * stats (impacts included) and the status. */
static void check_bit_identical(const exdex_scene_def *d, int n, double dt)
{
    int status;
    exdex_model *m = exdex_model_alloc(d, &status, NULL);
    exdex_stepper *s;
    exdex_trajectory tr;
    exdex_stats st, ss;
    size_t ns;
    int nd, nst, sim_status;
    ENSURE(m != NULL);
    if (!m) return;
    nd = exdex_model_ndof(m);
    nst = exdex_model_nstops(m);
    ns = exdex_n_samples(n * dt, dt);
    ENSURE(ns == (size_t)n + 1);
    tr.n = ns;
    tr.t = malloc(ns * sizeof(double));
    tr.q = malloc(ns * 3 * sizeof(double));
    tr.v = malloc(ns * 3 * sizeof(double));
    tr.wrench = malloc(ns * 3 * sizeof(double));
    tr.stick = malloc(ns);
    tr.stop_force = malloc((ns * EXDEX_MAX_STOPS + 1) * sizeof(double));
    sim_status = exdex_simulate(m, n * dt, dt, &tr, &st);
    s = exdex_stepper_alloc(m, &status);
    ENSURE(s != NULL);
    if (s) {
        exdex_stepper_sample x;
        exdex_stepper_get(s, &x, NULL);
        ENSURE(x.t == 0.0 && same_bits(x.q, tr.q, nd * sizeof(double)) && x.stick == tr.stick[0]);
        for (int i = 1; i <= n; i++) {
            status = exdex_stepper_step(s, dt, NAN);
            if (status) break;
            exdex_stepper_get(s, &x, NULL);
            ENSURE(x.t == tr.t[i]);
            ENSURE(same_bits(x.q, tr.q + (size_t)i * nd, nd * sizeof(double)));
            ENSURE(same_bits(x.v, tr.v + (size_t)i * nd, nd * sizeof(double)));
            ENSURE(same_bits(x.wrench, tr.wrench + 3 * (size_t)i, 3 * sizeof(double)));
            ENSURE(x.stick == tr.stick[i]);
            if (nst) ENSURE(same_bits(x.stop_force, tr.stop_force + (size_t)i * nst, nst * sizeof(double)));
        }
        ENSURE(status == sim_status);
        exdex_stepper_get(s, NULL, &ss);
        ENSURE(ss.steps == st.steps && ss.stick_steps == st.stick_steps);
        ENSURE(ss.solver_iterations == st.solver_iterations && ss.stop_iterations == st.stop_iterations);
        ENSURE(ss.warnings == st.warnings && same_bits(&ss.min_gap, &st.min_gap, sizeof(double)));
        ENSURE(ss.impacts == st.impacts && same_bits(&ss.max_impulse, &st.max_impulse, sizeof(double)));
        ENSURE(same_bits(&ss.max_impulse_t, &st.max_impulse_t, sizeof(double)) &&
               ss.max_impulse_stop == st.max_impulse_stop);
    }
    exdex_stepper_free(s);
    free(tr.t);
    free(tr.q);
    free(tr.v);
    free(tr.wrench);
    free(tr.stick);
    free(tr.stop_force);
    exdex_model_free(m);
}

EXDEX_TEST(stepper_bit_identical_to_simulate)
{
    const int methods[5] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EVENT, EXDEX_METHOD_REGULARISED,
                            EXDEX_METHOD_EXPLICIT, EXDEX_METHOD_ANALYTIC};
    for (int k = 0; k < 5; k++) {
        exdex_scene_def d = vertical(methods[k]);
        check_bit_identical(&d, 300, 1e-3);
        if (methods[k] != EXDEX_METHOD_ANALYTIC) {
            d = planar(methods[k]);
            d.eps = 1e-3;
            check_bit_identical(&d, 300, 2e-3);
        }
    }
}

/* step, save, step on; restore, step on again: the same bits */
EXDEX_TEST(stepper_save_restore_branches_exactly)
{
    const int methods[4] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EVENT, EXDEX_METHOD_EXPLICIT,
                            EXDEX_METHOD_ANALYTIC};
    for (int k = 0; k < 4; k++) {
        exdex_scene_def d = methods[k] == EXDEX_METHOD_ANALYTIC ? vertical(methods[k]) : planar(methods[k]);
        int status;
        exdex_model *m = exdex_model_alloc(&d, &status, NULL);
        exdex_stepper *s = m ? exdex_stepper_alloc(m, &status) : NULL, *s2 = m ? exdex_stepper_alloc(m, &status) : NULL;
        size_t size = exdex_stepper_state_size(s);
        char *snap = malloc(size), *bad = malloc(size);
        exdex_stepper_sample a[40], b;
        ENSURE(s && s2 && snap && bad);
        if (!s || !s2 || !snap || !bad) goto done;
        for (int i = 0; i < 60; i++) ENSURE(exdex_stepper_step(s, 2e-3, i < 30 ? NAN : 0.2 + 0.01 * i) == 0);
        ENSURE(exdex_stepper_save(s, snap, size) == 0);
        for (int i = 0; i < 40; i++) {
            ENSURE(exdex_stepper_step(s, i < 20 ? 2e-3 : 3e-3, 0.5 - 0.01 * i) == 0);
            exdex_stepper_get(s, &a[i], NULL);
        }
        /* into the same stepper and into a fresh one of the same model */
        for (int r = 0; r < 2; r++) {
            exdex_stepper *t = r ? s2 : s;
            ENSURE(exdex_stepper_restore(t, snap, size) == 0);
            for (int i = 0; i < 40; i++) {
                ENSURE(exdex_stepper_step(t, i < 20 ? 2e-3 : 3e-3, 0.5 - 0.01 * i) == 0);
                exdex_stepper_get(t, &b, NULL);
                ENSURE(same_bits(&a[i], &b, sizeof b));
            }
        }
        /* a corrupted snapshot or a wrong size is rejected, and the
         * stepper carries on as if nothing happened */
        memcpy(bad, snap, size);
        memset(bad, 0, 8);
        ENSURE(exdex_stepper_restore(s, bad, size) == EXDEX_EINVAL);
        memcpy(bad, snap, size);
        bad[size - 3] ^= 0x5a;
        ENSURE(exdex_stepper_restore(s, bad, size) == EXDEX_EINVAL);
        {
            exdex_stepper_sample before, after1, after2;
            exdex_stepper_get(s, &before, NULL);
            ENSURE(exdex_stepper_step(s, 1e-3, 0.3) == 0);
            exdex_stepper_get(s, &after1, NULL);
            ENSURE(exdex_stepper_restore(s2, snap, size) == 0);   /* s2 replays s from the snapshot */
            for (int i = 0; i < 40; i++) exdex_stepper_step(s2, i < 20 ? 2e-3 : 3e-3, 0.5 - 0.01 * i);
            ENSURE(exdex_stepper_step(s2, 1e-3, 0.3) == 0);
            exdex_stepper_get(s2, &after2, NULL);
            ENSURE(before.steps == 100 && same_bits(&after1, &after2, sizeof after1));
        }
        ENSURE(exdex_stepper_restore(s, snap, size - 1) == EXDEX_EINVAL);
        ENSURE(exdex_stepper_save(s, snap, size + 1) == EXDEX_EINVAL);
    done:
        free(snap);
        free(bad);
        exdex_stepper_free(s);
        exdex_stepper_free(s2);
        exdex_model_free(m);
    }
}

EXDEX_TEST(stepper_bad_arguments)
{
    exdex_scene_def d = vertical(EXDEX_METHOD_IMPLICIT);
    int status;
    exdex_model *m = exdex_model_alloc(&d, &status, NULL);
    exdex_stepper *s = exdex_stepper_alloc(m, &status);
    exdex_stepper_sample x;
    ENSURE(exdex_stepper_alloc(NULL, &status) == NULL && status == EXDEX_EINVAL);
    ENSURE(s != NULL);
    if (!s) return;
    ENSURE(exdex_stepper_step(s, 0.0, NAN) == EXDEX_EINVAL);
    ENSURE(exdex_stepper_step(s, -1e-3, NAN) == EXDEX_EINVAL);
    ENSURE(exdex_stepper_step(s, NAN, NAN) == EXDEX_EINVAL);
    ENSURE(exdex_stepper_step(s, INFINITY, NAN) == EXDEX_EINVAL);
    ENSURE(exdex_stepper_step(s, 1e-3, -1.0) == EXDEX_EINVAL);
    ENSURE(exdex_stepper_step(s, 1e-3, INFINITY) == EXDEX_EINVAL);
    ENSURE(exdex_stepper_step(NULL, 1e-3, NAN) == EXDEX_EINVAL);
    ENSURE(exdex_stepper_get(NULL, &x, NULL) == EXDEX_EINVAL);
    exdex_stepper_get(s, &x, NULL);
    ENSURE(x.t == 0.0 && x.steps == 0);   /* unchanged */
    ENSURE(exdex_stepper_step(s, 1e-3, NAN) == EXDEX_OK);
    /* a step too small to advance the time */
    ENSURE(exdex_stepper_step(s, 1e-300, NAN) == EXDEX_EINVAL);
    exdex_stepper_free(s);
    exdex_stepper_free(NULL);
    exdex_model_free(m);
}

EXDEX_TEST(stepper_release_is_free_fall)
{
    const int methods[3] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EVENT, EXDEX_METHOD_ANALYTIC};
    for (int k = 0; k < 3; k++) {
        exdex_scene_def d = vertical(methods[k]);
        int status;
        exdex_model *m;
        exdex_stepper *s;
        exdex_stepper_sample x;
        d.motion.kind = EXDEX_MOTION_REST;
        m = exdex_model_alloc(&d, &status, NULL);
        s = exdex_stepper_alloc(m, &status);
        ENSURE(s != NULL);
        if (!s) continue;
        for (int i = 0; i < 100; i++) ENSURE(exdex_stepper_step(s, 1e-3, NAN) == 0);
        exdex_stepper_get(s, &x, NULL);
        ENSURE(x.q[0] == 0.0 && x.v[0] == 0.0 && x.stick);   /* held exactly */
        for (int i = 0; i < 200; i++) ENSURE(exdex_stepper_step(s, 1e-3, 0.0) == 0);
        exdex_stepper_get(s, &x, NULL);
        ENSURE_CLOSE(x.t, 0.3, 1e-15);
        ENSURE_CLOSE(x.q[0], -0.5 * G * 0.2 * 0.2, 1e-10);
        ENSURE_CLOSE(x.v[0], -G * 0.2, 1e-10);
        ENSURE(!x.stick && x.wrench[1] == 0.0);
        /* caught again: a capacity of 10 m g decelerates it at 9 g, so
         * |v| = 1.962 m/s stops after 1.962 / (9 g) = 22.2 ms, inside the
         * next 100 ms, and it sticks from then on */
        for (int i = 0; i < 100; i++) ENSURE(exdex_stepper_step(s, 1e-3, 10.0 * d.mass * G / (2 * d.mu)) == 0);
        exdex_stepper_get(s, &x, NULL);
        ENSURE(x.v[0] == 0.0 && x.stick);
        exdex_stepper_free(s);
        exdex_model_free(m);
    }
}

/* A prescribed gripper pose per step (exdex_stepper_step_gripper). The
 * gripper rises along A z (B's slide axis y) as p(t) = p0 + c t^3, given at
 * each step's end with its velocity 3 c t^2: the cubic Hermite
 * interpolation of a cubic is the cubic itself, so the frame's
 * acceleration is 6 c t exactly. With grip 0 the object falls freely in A:
 * relative to B, s(t) = s0 - g t^2 / 2 - c t^3 (closed form), which the
 * event method integrates to its tolerance. Then the contract's errors. */
EXDEX_TEST(stepper_gripper_pose_cubic_rise_is_free_fall)
{
    exdex_scene_def d = vertical(EXDEX_METHOD_EVENT);
    const double c = 0.8, dt = 2e-3;
    int status;
    exdex_model *m;
    exdex_stepper *s;
    exdex_stepper_sample x;
    exdex_gripper_pose pose;
    d.motion.kind = EXDEX_MOTION_REST;
    d.rtol = 1e-12;
    d.atol = 1e-14;
    m = exdex_model_alloc(&d, &status, NULL);
    s = m ? exdex_stepper_alloc(m, &status) : NULL;
    ENSURE(s != NULL);
    if (!s) {
        exdex_model_free(m);
        return;
    }
    memset(&pose, 0, sizeof pose);
    memcpy(pose.R, d.R0, sizeof pose.R);
    pose.given_v = pose.given_w = 1;
    for (int i = 1; i <= 150; i++) {
        double t = i * dt;
        pose.p[2] = d.p0[2] + c * t * t * t;
        pose.v[2] = 3.0 * c * t * t;
        ENSURE(exdex_stepper_step_gripper(s, dt, 0.0, &pose) == EXDEX_OK);
    }
    exdex_stepper_get(s, &x, NULL);
    ENSURE_CLOSE(x.q[0] - d.q0[1], -0.5 * G * 0.09 - c * 0.027, 1e-9);
    ENSURE_CLOSE(x.v[0], -G * 0.3 - 3.0 * c * 0.09, 1e-9);
    /* once posed, every step must give a pose; a pose must be a rotation */
    ENSURE(exdex_stepper_step(s, dt, 0.0) == EXDEX_EINVAL);
    pose.R[0] = 1.1;
    ENSURE(exdex_stepper_step_gripper(s, dt, 0.0, &pose) == EXDEX_EINVAL);
    memcpy(pose.R, d.R0, sizeof pose.R);
    pose.v[0] = NAN;
    ENSURE(exdex_stepper_step_gripper(s, dt, 0.0, &pose) == EXDEX_EINVAL);
    exdex_stepper_get(s, &x, NULL);
    ENSURE(x.steps == 150);   /* unchanged */
    exdex_stepper_free(s);
    exdex_model_free(m);
    /* the analytic method follows the scene's motion: no poses */
    d = vertical(EXDEX_METHOD_ANALYTIC);
    m = exdex_model_alloc(&d, &status, NULL);
    s = m ? exdex_stepper_alloc(m, &status) : NULL;
    ENSURE(s != NULL);
    if (s) {
        memcpy(pose.R, d.R0, sizeof pose.R);
        memcpy(pose.p, d.p0, sizeof pose.p);
        pose.given_v = pose.given_w = 0;
        ENSURE(exdex_stepper_step_gripper(s, dt, NAN, &pose) == EXDEX_EINVAL);
        ENSURE(exdex_stepper_step_gripper(s, dt, NAN, NULL) == EXDEX_OK);
    }
    exdex_stepper_free(s);
    exdex_model_free(m);
}

/* The step budget bounds the work of one output interval (hybrid.h,
 * "Budgets"): at most STEPS_MAX stepper applications (ODE steps, accepted
 * and rejected, and every one-step map of event location) plus the last
 * step's location. The scene (fuzz stepper corpus budget-19428): a 1-DoF
 * rotation against a stop, driven by an Eq. 7 rotation of amplitude
 * 2e277, whose first step of 0.2 ms the event method cannot integrate: each
 * accepted step then starts with guards violated, whose extremum searches
 * cost two one-step maps each. Reference: the status and cause the contract
 * names (EXDEX_ENOCONV, EXDEX_FAIL_STEP_BUDGET), and the right-hand-side
 * evaluations counted independently (the ODE system's function wrapped):
 * rk8pd (Prince-Dormand 8(7)) has 13 stages, and an application evaluates at
 * most those and the end derivative, 14, so the interval may take at most
 * 14 (STEPS_MAX + 10^4) evaluations (10^4: far above one step's location,
 * at most a few guards times GOLDEN_MAX + BRENT_MAX + DOUBLING_MAX maps). */
static unsigned long budget_rhs_calls;

static int budget_counting_rhs(double t, const double y[], double dy[], void *params)
{
    budget_rhs_calls++;
    return hyb_rhs(t, y, dy, params);
}

static exdex_scene_def budget_scene(void)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = 1.0964742683788926;
    d.mu = 0.82725090431011417;
    d.grip_force = 2.4801186545572889 * d.mass * G;
    d.dof = EXDEX_DOF_ROTATION;
    d.e_r = 0.0012574999964089192;
    d.patch_center[0] = 0.0061031815803676073;
    d.inertia[0] = d.inertia[4] = d.inertia[8] = d.mass * 1e-3;
    d.method = EXDEX_METHOD_EVENT;
    d.eps = 1e-3;
    d.rtol = 1e-7;
    d.atol = 1e-9;
    scene_rect(&d, 0.02, 0.02);
    d.n_stops = 1;
    d.stop_point[0][2] = -0.03 - 0.0063795430392033486;
    d.stop_normal[0][2] = 1.0;
    d.motion.kind = EXDEX_MOTION_ASYMMETRIC;
    d.motion.axis[2] = -1.0;
    d.motion.amplitude = 1.9757582782045212e+277;
    d.motion.duration = 0.29141994790714226;
    d.motion.beta = 0.32957028655930493;
    d.motion.frequency = 1.042016933560957;
    return d;
}

EXDEX_TEST(stepper_step_budget_bounds_event_location_work)
{
    const double dt = 0.00019912298590696358;
    exdex_scene_def d = budget_scene();
    int status;
    exdex_model *m = exdex_model_alloc(&d, &status, NULL);
    const method_impl *impl = method_get(EXDEX_METHOD_EVENT);
    exdex_stepper *s;
    exdex_stats st;
    ode *O;
    double t1, q[3], v[3], wr[3], sf[EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES];
    unsigned char stick;
    exdex_trajectory out = {1, &t1, q, v, wr, &stick, sf};
    ENSURE(m != NULL);
    if (!m) return;
    /* through the stepper: the contract's status and cause */
    s = exdex_stepper_alloc(m, &status);
    ENSURE(s != NULL);
    if (s) {
        ENSURE(exdex_stepper_step(s, dt, NAN) == EXDEX_ENOCONV);
        exdex_stepper_get(s, NULL, &st);
        ENSURE(st.fail_cause == EXDEX_FAIL_STEP_BUDGET);
        exdex_stepper_free(s);
    }
    /* the same interval through the method table, as the stepper runs it,
     * with the right-hand side counted */
    O = impl->alloc(m, &status);
    ENSURE(O != NULL);
    if (O) {
        memset(&st, 0, sizeof st);
        st.min_gap = INFINITY;
        O->sys.function = budget_counting_rhs;
        budget_rhs_calls = 0;
        ENSURE(impl->begin(m, O, INFINITY, dt, &st) == EXDEX_OK);
        ENSURE(impl->advance(m, O, dt, 0, &out, 0, &st) == EXDEX_ENOCONV);
        ENSURE(st.fail_cause == EXDEX_FAIL_STEP_BUDGET);
        report("budget_rhs_calls", (double)budget_rhs_calls);
        ENSURE(budget_rhs_calls <= 14ul * (STEPS_MAX + 10000ul));
        impl->free(O);
    }
    exdex_model_free(m);
}
