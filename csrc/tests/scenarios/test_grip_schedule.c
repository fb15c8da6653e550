/* test_grip_schedule.c -- grip-force schedules (exdex_scene_def.grip_n): validation,
 * the force and its rate through exdex_model_grip, and closed-form runs of
 * a 1-DoF vertical slide under gravity with every method.
 *
 * Scene: translation along B's y (up), gripper at rest, gravity g down,
 * mass m, mu, two fingers: the capacity is C(t) = 2 mu F(t) and
 *     m s'' = -m g + f,   |f| <= C(t),   f = C(t) while sliding down.
 * twin: tests/scenarios/test_grip_schedule.py (the same subject through the Python API)
 */
#include "../check.h"
#include "../sim_run.h"
#include "../../exdex.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define G 9.81

static exdex_scene_def vertical_sched(double mass, const double *t, const double *f, size_t n, int kind)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = mass;
    d.mu = 0.5;
    d.fingers = 2;
    d.grip_force = 1.0;
    d.gravity[2] = -G;
    d.grip_n = n;
    d.grip_times = t;
    d.grip_forces = f;
    d.grip_kind = kind;
    return d;
}

EXDEX_TEST(grip_bad_input_named)
{
    double t[3] = {0.0, 0.5, 1.0}, f[3] = {2.0, 1.0, 0.0}, tb[3] = {0.0, 0.5, 0.5}, fb[3] = {2.0, -1.0, 0.0};
    double tn[3] = {0.0, NAN, 1.0}, fi[3] = {2.0, INFINITY, 0.0};
    exdex_scene_def d = vertical_sched(0.1, t, f, 3, EXDEX_GRIP_LINEAR);
    const char *bad = NULL;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_OK);
    d.grip_times = tb;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_times"));
    d.grip_times = tn;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_times"));
    d.grip_times = NULL;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_times"));
    d.grip_times = t;
    d.grip_forces = fb;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_forces"));
    d.grip_forces = fi;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_forces"));
    d.grip_forces = NULL;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_forces"));
    d.grip_forces = f;
    d.grip_kind = 3;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_kind"));
    d.grip_kind = EXDEX_GRIP_STEP;
    d.grip_n = (size_t)EXDEX_MAX_GRIP_POINTS + 1;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_n"));
    /* slopes that overflow: forces 1e300 apart over 1e-10 s */
    {
        double ts[2] = {0.0, 1e-10}, fs[2] = {0.0, 1e300};
        exdex_scene_def e = vertical_sched(0.1, ts, fs, 2, EXDEX_GRIP_LINEAR);
        ENSURE(exdex_scene_check(&e, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_times"));
        fs[1] = 1.0;  /* a steep but finite slope (1e10 N/s) is fine */
        ENSURE(exdex_scene_check(&e, &bad) == EXDEX_OK);
        e.grip_kind = EXDEX_GRIP_CUBIC;  /* the cubic's 1 / h^3 coefficient: 1e30 */
        ENSURE(exdex_scene_check(&e, &bad) == EXDEX_OK);
        ts[1] = 1e-110;
        ENSURE(exdex_scene_check(&e, &bad) == EXDEX_EINVAL && bad && !strcmp(bad, "grip_times"));
    }
    /* the analytic method solves linear and step schedules, reports a
     * varying cubic one; a flat one is a constant */
    d.grip_n = 3;
    ENSURE(exdex_analytic_unsupported(&d) == NULL);
    d.grip_kind = EXDEX_GRIP_LINEAR;
    ENSURE(exdex_analytic_unsupported(&d) == NULL);
    d.grip_kind = EXDEX_GRIP_CUBIC;
    ENSURE(exdex_analytic_unsupported(&d) != NULL);
    {
        double ff[2] = {1.0, 1.0};
        d.grip_n = 2;
        d.grip_forces = ff;
        ENSURE(exdex_analytic_unsupported(&d) == NULL);
    }
}

EXDEX_TEST(grip_force_and_rate_by_kind)
{
    /* points (0, 2), (1, 0), (2, 1), scaled by grip_force = 3:
     * linear: F(0.25) = 3 (2 - 2 0.25) = 4.5, rate -6; F(1.5) = 1.5, rate 3;
     * step: F(0.25) = 6, F(1) = 0 (right-continuous), rate 0;
     * held outside: F(-1) = 6, F(5) = 3; cubic (Steffen) through the points,
     * never outside the neighbouring values, continuous slope. */
    double t[3] = {0.0, 1.0, 2.0}, f[3] = {2.0, 0.0, 1.0}, F, R, Fl, Fr, Rl, Rr;
    exdex_scene_def d = vertical_sched(0.1, t, f, 3, EXDEX_GRIP_LINEAR);
    int st;
    exdex_model *m;
    d.grip_force = 3.0;
    m = exdex_model_alloc(&d, &st, NULL);
    ENSURE(m != NULL);
    ENSURE(exdex_model_grip(m, 0.25, &F, &R) == EXDEX_OK);
    ENSURE_CLOSE(F, 4.5, 1e-15);
    ENSURE_CLOSE(R, -6.0, 1e-15);
    exdex_model_grip(m, 1.5, &F, &R);
    ENSURE_CLOSE(F, 1.5, 1e-15);
    ENSURE_CLOSE(R, 3.0, 1e-15);
    exdex_model_grip(m, -1.0, &F, &R);
    ENSURE(F == 6.0 && R == 0.0);
    exdex_model_grip(m, 5.0, &F, &R);
    ENSURE(F == 3.0 && R == 0.0);
    ENSURE(exdex_model_grip(m, NAN, &F, &R) == EXDEX_EINVAL);
    exdex_model_free(m);
    d.grip_kind = EXDEX_GRIP_STEP;
    m = exdex_model_alloc(&d, &st, NULL);
    exdex_model_grip(m, 0.25, &F, &R);
    ENSURE(F == 6.0 && R == 0.0);
    exdex_model_grip(m, 1.0, &F, NULL);
    ENSURE(F == 0.0);
    exdex_model_grip(m, 2.0, &F, NULL);
    ENSURE(F == 3.0);
    exdex_model_free(m);
    d.grip_kind = EXDEX_GRIP_CUBIC;
    m = exdex_model_alloc(&d, &st, NULL);
    for (int i = 0; i <= 200; i++) {
        double x = 0.01 * i;
        exdex_model_grip(m, x, &F, NULL);
        ENSURE(F >= 0.0 && F <= 6.0);
        if (x <= 1.0) ENSURE(F >= 0.0 && F <= 6.0 + 1e-15);
        if (x >= 1.0) ENSURE(F <= 3.0 + 1e-15);
    }
    exdex_model_grip(m, 1.0, &F, NULL);
    ENSURE_CLOSE(F, 0.0, 1e-15);
    /* slope continuous at the inner point */
    exdex_model_grip(m, 1.0 - 1e-9, &Fl, &Rl);
    exdex_model_grip(m, 1.0 + 1e-9, &Fr, &Rr);
    ENSURE_CLOSE(Rl, Rr, 1e-6);
    exdex_model_free(m);
}

/* Closed form of the ramp-down (forces F0 -> 0 linearly over [0, Tr]): the
 * object sticks while C(t) = 2 mu F0 (1 - t/Tr) >= m g, i.e. until
 *     t* = Tr (1 - m g / (2 mu F0));
 * then s'' = -g + C(t)/m = -k (t - t*), k = 2 mu F0 / (m Tr), so
 *     v = -k (t - t*)^2 / 2,   s = -k (t - t*)^3 / 6      (t* <= t <= Tr)
 * and free fall after Tr. */
static void ramp_closed_form(double m, double mu, double F0, double Tr, double t, double *s, double *v)
{
    double ts = Tr * (1.0 - m * G / (2.0 * mu * F0)), k = 2.0 * mu * F0 / (m * Tr), tau;
    if (t <= ts) {
        *s = *v = 0.0;
        return;
    }
    tau = fmin(t, Tr) - ts;
    *s = -k * tau * tau * tau / 6.0;
    *v = -k * tau * tau / 2.0;
    if (t > Tr) {
        double u = t - Tr;
        *s += *v * u - 0.5 * G * u * u;
        *v -= G * u;
    }
}

EXDEX_TEST(grip_ramp_down_closed_form_every_method)
{
    /* m 0.1, mu 0.5, F0 2 N, Tr 0.5 s: t* = 0.25475 s; t_end 0.6 s (0.1 s
     * of free fall). Event: to the integrator's tolerance (1e-9 m);
     * implicit (first order, exact impulse bound per step) within one
     * step's travel at the largest speed, 2 dt |v|max. */
    double t[2] = {0.0, 0.5}, f[2] = {2.0, 0.0}, s, v, vmax;
    exdex_scene_def d = vertical_sched(0.1, t, f, 2, EXDEX_GRIP_LINEAR);
    sim_run r;
    ramp_closed_form(0.1, 0.5, 2.0, 0.5, 0.6, &s, &v);
    vmax = fabs(v);
    d.method = EXDEX_METHOD_EVENT;
    ENSURE(sim_run_def(&d, 0.6, 0.01, &r) == EXDEX_OK);
    for (size_t i = 0; i < r.tr.n; i++) {
        double si, vi;
        ramp_closed_form(0.1, 0.5, 2.0, 0.5, r.tr.t[i], &si, &vi);
        ENSURE_CLOSE(r.tr.q[i], si, 1e-9);
        ENSURE_CLOSE(r.tr.v[i], vi, 1e-8);
        if (r.tr.t[i] < 0.25) ENSURE(r.tr.stick[i] && r.tr.v[i] == 0.0);
    }
    sim_run_free(&r);
    d.method = EXDEX_METHOD_IMPLICIT;
    ENSURE(sim_run_def(&d, 0.6, 1e-3, &r) == EXDEX_OK);
    ENSURE_CLOSE(r.tr.q[r.tr.n - 1], s, 2e-3 * vmax);
    sim_run_free(&r);
    /* analytic: the same polynomials evaluated, to rounding (1e-14 m) */
    d.method = EXDEX_METHOD_ANALYTIC;
    ENSURE(sim_run_def(&d, 0.6, 0.01, &r) == EXDEX_OK);
    for (size_t i = 0; i < r.tr.n; i++) {
        double si, vi;
        ramp_closed_form(0.1, 0.5, 2.0, 0.5, r.tr.t[i], &si, &vi);
        ENSURE_CLOSE(r.tr.q[i], si, 1e-14);
        ENSURE_CLOSE(r.tr.v[i], vi, 1e-13);
    }
    sim_run_free(&r);
}

/* twin: tests/scenarios/test_grip_schedule.py::test_step_release_and_regrip */
EXDEX_TEST(grip_step_release_regrip_closed_form)
{
    /* step schedule: 2 N until t1 = 0.1, 0 until t2 = 0.15, then 3 N.
     * Free fall for tau = t2 - t1: v2 = -g tau, s2 = -g tau^2 / 2; then the
     * capacity C2 = 2 mu 3 = 3 N decelerates at a = C2/m - g until v = 0 at
     * t_s = t2 + g tau / a; slip s_s = s2 - (g tau)^2 / (2 a); then it sticks
     * (C2 > m g) exactly still. */
    double t[3] = {0.0, 0.1, 0.15}, f[3] = {2.0, 0.0, 3.0};
    double m = 0.1, tau = 0.05, a = 3.0 / m - G, ts = 0.15 + G * tau / a;
    double ss = -0.5 * G * tau * tau - (G * tau) * (G * tau) / (2.0 * a);
    exdex_scene_def d = vertical_sched(m, t, f, 3, EXDEX_GRIP_STEP);
    sim_run r;
    int still = 1;
    for (int meth = 0; meth < 2; meth++) {
        d.method = meth ? EXDEX_METHOD_ANALYTIC : EXDEX_METHOD_EVENT;
        ENSURE(sim_run_def(&d, 0.4, 0.01, &r) == EXDEX_OK);
        ENSURE_CLOSE(r.tr.q[r.tr.n - 1], ss, meth ? 1e-15 : 1e-9);
        for (size_t i = 0; i < r.tr.n; i++)
            if (r.tr.t[i] > ts + 1e-9 || r.tr.t[i] < 0.1) still &= r.tr.v[i] == 0.0 && r.tr.stick[i];
        ENSURE(still);
        sim_run_free(&r);
    }
}

/* model_substep's whole-step test (a switch list cached per run) against
 * the full search, model_substep_full, on a motion with every kind of
 * switching time: a chain (trapezoid with ramps, a constant-speed piece
 * with velocity jumps, a shake, Eq. 7 as a turn) and a 6-point grip
 * schedule. Steps of random length, some ending within rounding of a
 * switching time (a grid chosen to land on it), and jumps back in time (a
 * restored state): every sub-step must be the full search's, bit for bit;
 * and exdex_motion_next_switch is the first listed switch above lo. */
#include "../../model.h"
#include <gsl/gsl_rng.h>

EXDEX_TEST(grip_substep_whole_step_test_equals_full_search)
{
    double gt[6] = {0.0, 0.7, 1.3, 2.0, 3.1, 4.5}, gf[6] = {2.0, 1.5, 1.5, 0.4, 1.0, 2.0};
    double ts[EXDEX_MOTION_MAX_SWITCHES];
    exdex_motion_def pc[4];
    exdex_scene_def d = vertical_sched(0.1, gt, gf, 6, EXDEX_GRIP_LINEAR);
    exdex_model *m;
    gsl_rng *r = gsl_rng_alloc(gsl_rng_mt19937);
    model_sw_cache c;
    int st = -1, n, mism = 0, splits = 0, jumps = 0;
    double t = 0.0, t_end = 5.5;
    memset(pc, 0, sizeof pc);
    for (int i = 0; i < 4; i++) pc[i].axis[1] = 1.0;
    pc[0].kind = EXDEX_MOTION_TRAPEZOID; pc[0].amplitude = 0.1; pc[0].duration = 1.0; pc[0].v_max = 0.15;
    pc[1].kind = EXDEX_MOTION_TRAPEZOID; pc[1].amplitude = 0.1; pc[1].duration = 1.0; pc[1].v_max = 0.1;
    pc[2].kind = EXDEX_MOTION_SHAKE; pc[2].amplitude = 0.01; pc[2].frequency = 2.0; pc[2].duration = 1.3;
    pc[3].kind = EXDEX_MOTION_ASYMMETRIC; pc[3].rotation = 1; pc[3].center[0] = 0.2;
    pc[3].amplitude = 0.5; pc[3].duration = 0.5; pc[3].beta = 0.5;
    d.motion.kind = EXDEX_MOTION_CHAIN; d.motion.n_pieces = 4; d.motion.pieces = pc; d.motion.allow_jump = 1;
    m = exdex_model_alloc(&d, &st, NULL);
    ENSURE(m != NULL && st == EXDEX_OK && r != NULL);
    if (!m || !r) {
        exdex_model_free(m);
        if (r) gsl_rng_free(r);
        return;
    }
    n = exdex_motion_switches(m->motion, ts);
    ENSURE(n >= 8 && exdex_motion_jumps(m->motion, NULL, NULL, NULL) >= 2);
    for (int i = 0; i < 2000; i++) {
        double lo = gsl_rng_uniform(r) < 0.2 ? ts[gsl_rng_uniform_int(r, (unsigned long)n)] : 6.0 * gsl_rng_uniform(r);
        double want = INFINITY;
        for (int k = 0; k < n; k++)
            if (ts[k] > lo) {
                want = ts[k];
                break;
            }
        mism += exdex_motion_next_switch(m->motion, lo) != want;
    }
    ENSURE(mism == 0);
    model_sw_cache_reset(&c);
    for (int i = 0; i < 20000; i++) {
        double u = gsl_rng_uniform(r), t1;
        model_sub a, b;
        if (u < 0.05) t = t_end * gsl_rng_uniform(r);          /* a restored state */
        if (u > 0.9) {                                          /* onto a switching time, within rounding */
            double sw = exdex_motion_next_switch(m->motion, t);
            t1 = isfinite(sw) && sw < t + 0.2 ? sw * (1.0 + 1e-15 * (gsl_rng_uniform(r) - 0.5)) : t + 0.01;
            if (!(t1 > t)) t1 = t + 0.01;
        } else {
            t1 = t + 0.2 * gsl_rng_uniform_pos(r);
        }
        model_substep(m, &c, t, t1, &a);
        model_substep_full(m, t, t1, &b);
        splits += b.split;
        jumps += b.jumps > 0;
        if (a.te != b.te || a.split != b.split || a.jumps != b.jumps) mism++;
        else if (a.jumps)
            for (int k = 0; k < 3; k++)
                mism += a.dv[k] != b.dv[k] || a.dw[k] != b.dw[k] || a.dvl[k] != b.dvl[k] || a.dwl[k] != b.dwl[k];
        t = b.te < t_end ? b.te : 0.0;   /* a new run */
    }
    ENSURE(mism == 0);
    ENSURE(splits > 500 && jumps > 100);
    gsl_rng_free(r);
    exdex_model_free(m);
}
