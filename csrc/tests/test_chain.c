/* test_chain.c -- shake and chained motions (csrc/motion.c, exdex.h).
 *
 * References are closed forms worked out in the comments:
 *  - shake s(t) = A (1 - cos w t): v = A w sin w t, a = A w^2 cos w t;
 *  - a chain plays each piece from the pose where the previous one ended,
 *    so a translation chain's position is the sum of the finished pieces'
 *    displacements plus the running piece's profile;
 *  - a trapezoid with ramps: t_a = T - |X1| / v_max, accel = v_max / t_a. */
#include "check.h"
#include "../exdex.h"

#include <math.h>
#include <string.h>

#define PI 3.14159265358979323846

static exdex_motion_def piece(int kind)
{
    exdex_motion_def d;
    memset(&d, 0, sizeof d);
    d.kind = kind;
    d.axis[0] = 1.0;
    return d;
}

EXDEX_TEST(shake_closed_form_and_end_jump)
{
    const double A = 0.01, f = 2.0, w = 2.0 * PI * f, p0[3] = {0.1, 0.2, 0.3};
    double ts[EXDEX_MOTION_MAX_SWITCHES], tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3],
        dw[EXDEX_MOTION_MAX_JUMPS][3];
    exdex_motion_def d = piece(EXDEX_MOTION_SHAKE);
    exdex_motion *m;
    exdex_kinematics k;
    int status;
    d.axis[0] = 0.0;
    d.axis[2] = 2.0;   /* normalised to z */
    d.amplitude = A;
    d.frequency = f;
    d.duration = 1.5;  /* three whole cycles: ends at rest */
    m = exdex_motion_alloc(&d, NULL, p0, &status, NULL);
    ENSURE(m != NULL);
    if (!m) return;
    for (int i = 0; i <= 40; i++) {
        double t = 0.04 * i - 0.05;
        double tt = t < 0 ? 0 : t > 1.5 ? 1.5 : t, s = A * (1 - cos(w * tt));
        double v = (t < 0 || t >= 1.5) ? 0 : A * w * sin(w * t), a = (t < 0 || t >= 1.5) ? 0 : A * w * w * cos(w * t);
        ENSURE(exdex_motion_eval(m, t, &k) == EXDEX_OK);
        ENSURE_CLOSE(k.p[2], p0[2] + s, 1e-16);
        ENSURE(k.p[0] == p0[0] && k.p[1] == p0[1]);
        ENSURE_CLOSE(k.v[2], v, 1e-15);
        ENSURE_CLOSE(k.a[2], a, 1e-13);
    }
    ENSURE(exdex_motion_switches(m, ts) == 1 && ts[0] == 1.5);
    ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 0);
    ENSURE(exdex_motion_end(m) == 1.5);
    exdex_motion_free(m);
    /* a quarter cycle more: it ends at full speed A w (sin(w D) = 1) and
     * the velocity jumps back to rest: dv = -A w z */
    d.duration = 1.625;
    m = exdex_motion_alloc(&d, NULL, p0, &status, NULL);
    ENSURE(m != NULL);
    if (!m) return;
    ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 1);
    ENSURE(tj[0] == 1.625);
    ENSURE_CLOSE(dv[0][2], -A * w, 1e-14);
    ENSURE(exdex_motion_eval(m, 2.0, &k) == EXDEX_OK);
    ENSURE_CLOSE(k.p[2], p0[2] + A, 1e-15);   /* held at s(D) = A (1 - cos(pi/2)) */
    exdex_motion_free(m);
    /* bad input names the field */
    {
        const char *bad = NULL;
        d.frequency = 0.0;
        ENSURE(exdex_motion_alloc(&d, NULL, NULL, &status, &bad) == NULL && status == EXDEX_EINVAL);
        ENSURE(bad && strcmp(bad, "motion.frequency") == 0);
        d.frequency = 1e6;
        d.duration = 1e4;   /* 1e10 cycles */
        ENSURE(exdex_motion_alloc(&d, NULL, NULL, &status, &bad) == NULL);
        ENSURE(bad && strcmp(bad, "motion.duration") == 0);
    }
}

/* trapezoid along x (X1 = 0.1, T = 1, v_max = 0.15: t_a = 1/3, accel =
 * 0.45), a pause of 0.5 s, a shake along z (A = 0.01, f = 2, 3 cycles),
 * then an Eq. 7 rotation about z through c (which moves the origin on a
 * circle): the chain's kinematics are each piece's from the end pose of the
 * one before. */
EXDEX_TEST(chain_closed_form)
{
    exdex_motion_def pc[4], d = piece(EXDEX_MOTION_CHAIN);
    const double A = 0.01, w = 4.0 * PI, ta = 1.0 / 3.0, acc = 0.45;
    double ts[EXDEX_MOTION_MAX_SWITCHES];
    exdex_motion *m;
    exdex_kinematics k;
    int status, n;
    pc[0] = piece(EXDEX_MOTION_TRAPEZOID);
    pc[0].amplitude = 0.1; pc[0].duration = 1.0; pc[0].v_max = 0.15;
    pc[1] = piece(EXDEX_MOTION_REST);
    pc[1].duration = 0.5;
    pc[2] = piece(EXDEX_MOTION_SHAKE);
    pc[2].axis[0] = 0.0; pc[2].axis[2] = 1.0;
    pc[2].amplitude = A; pc[2].frequency = 2.0; pc[2].duration = 1.5;
    pc[3] = piece(EXDEX_MOTION_ASYMMETRIC);
    pc[3].axis[0] = 0.0; pc[3].axis[2] = 1.0; pc[3].rotation = 1;
    pc[3].center[0] = 0.2; pc[3].amplitude = 0.5; pc[3].duration = 0.5; pc[3].beta = 0.5;
    d.n_pieces = 4;
    d.pieces = pc;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, NULL);
    ENSURE(m != NULL);
    if (!m) return;
    ENSURE(exdex_motion_end(m) == 4.0);
    /* switches: t_a, 1 - t_a, 1 (trapezoid), 1.5 (pause), 3 (shake), 3.25,
     * 3.75, 4 (Eq. 7 with beta = 0.5, T = 0.5: beta T, (2 - beta) T, 2T) */
    n = exdex_motion_switches(m, ts);
    ENSURE(n == 8);
    if (n == 8) {
        const double want[8] = {ta, 1 - ta, 1.0, 1.5, 3.0, 3.25, 3.75, 4.0};
        for (int i = 0; i < 8; i++) ENSURE_CLOSE(ts[i], want[i], 1e-15);
    }
    ENSURE(exdex_motion_jumps(m, NULL, NULL, NULL) == 0);
    /* trapezoid ramp */
    ENSURE(exdex_motion_eval(m, 0.2, &k) == 0);
    ENSURE_CLOSE(k.p[0], 0.5 * acc * 0.04, 1e-16);
    ENSURE_CLOSE(k.v[0], acc * 0.2, 1e-16);
    /* pause: at rest at x = 0.1 */
    ENSURE(exdex_motion_eval(m, 1.2, &k) == 0);
    ENSURE_CLOSE(k.p[0], 0.1, 1e-16);
    ENSURE(k.v[0] == 0.0 && k.a[0] == 0.0 && k.p[2] == 0.0);
    /* shake from (0.1, 0, 0) at local time 0.6 */
    ENSURE(exdex_motion_eval(m, 2.1, &k) == 0);
    ENSURE_CLOSE(k.p[0], 0.1, 1e-16);
    ENSURE_CLOSE(k.p[2], A * (1 - cos(w * 0.6)), 1e-15);
    ENSURE_CLOSE(k.v[2], A * w * sin(w * 0.6), 1e-14);
    /* rotation about z through (0.2, 0, 0) from (0.1, 0, 0): r0 = (-0.1, 0,
     * 0); at local 0.5 = T the angle is X1 = 0.5 (the round trip's apex) */
    ENSURE(exdex_motion_eval(m, 3.5, &k) == 0);
    ENSURE_CLOSE(k.p[0], 0.2 - 0.1 * cos(0.5), 1e-15);
    ENSURE_CLOSE(k.p[1], -0.1 * sin(0.5), 1e-15);
    ENSURE_SMALL(k.p[2], 1e-16);
    ENSURE_CLOSE(k.R[0], cos(0.5), 1e-15);
    /* right-continuous at a shifted switch: 3.25 belongs to the a_L phase */
    ENSURE(exdex_motion_eval(m, 3.25, &k) == 0);
    ENSURE_CLOSE(k.dw[2], 2 * 0.5 / ((0.5 - 1) * 0.25), 1e-12);
    ENSURE(exdex_motion_eval(m, nextafter(3.25, 0), &k) == 0);
    ENSURE_CLOSE(k.dw[2], 2 * 0.5 / (0.5 * 0.25), 1e-12);
    /* after the end: at rest at the end pose (back at angle 0) */
    ENSURE(exdex_motion_eval(m, 9.0, &k) == 0);
    ENSURE_CLOSE(k.p[0], 0.1, 1e-15);
    ENSURE(k.v[0] == 0.0 && k.w[2] == 0.0);
    exdex_motion_free(m);
}

EXDEX_TEST(chain_velocity_jumps)
{
    exdex_motion_def pc[2], d = piece(EXDEX_MOTION_CHAIN);
    double tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    exdex_motion *m;
    const char *bad = NULL;
    int status;
    /* two constant-speed pieces at 0.1 m/s along x: continuous at 1 s; the
     * chain jumps from rest at 0 and back to rest at 3 */
    pc[0] = piece(EXDEX_MOTION_TRAPEZOID);
    pc[0].amplitude = 0.1; pc[0].duration = 1.0; pc[0].v_max = 0.1;
    pc[1] = pc[0];
    pc[1].amplitude = 0.2; pc[1].duration = 2.0;
    d.n_pieces = 2;
    d.pieces = pc;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, NULL);
    ENSURE(m != NULL);
    ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 2);
    ENSURE(tj[0] == 0.0 && tj[1] == 3.0);
    ENSURE_CLOSE(dv[0][0], 0.1, 1e-16);
    ENSURE_CLOSE(dv[1][0], -0.1, 1e-16);
    exdex_motion_free(m);
    /* a constant speed then a ramped trapezoid: the speed drops to 0 at 1 s,
     * an error naming the second piece unless allowed */
    pc[1].v_max = 0.15;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, &bad);
    ENSURE(m == NULL && status == EXDEX_EINVAL && bad && strcmp(bad, "motion.pieces[1]") == 0);
    d.allow_jump = 1;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, &bad);
    ENSURE(m != NULL);
    ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 2);
    ENSURE(tj[0] == 0.0 && tj[1] == 1.0);
    ENSURE_CLOSE(dv[1][0], -0.1, 1e-16);
    exdex_motion_free(m);
    d.allow_jump = 2;
    ENSURE(exdex_motion_alloc(&d, NULL, NULL, &status, &bad) == NULL && strcmp(bad, "motion.allow_jump") == 0);
}

EXDEX_TEST(chain_position_jump_and_bad_pieces)
{
    exdex_motion_def pc[2], d = piece(EXDEX_MOTION_CHAIN);
    double times[4] = {5.0, 5.5, 6.0, 6.5}, poses[28];
    exdex_motion *m;
    exdex_kinematics k;
    const char *bad = NULL;
    int status;
    /* a pause, then an absolute log held at (1, 0, 0): the gripper starts
     * at the origin, so the log starts 1 m away */
    memset(poses, 0, sizeof poses);
    for (int i = 0; i < 4; i++) {
        poses[7 * i] = 1.0;
        poses[7 * i + 3] = 1.0;
    }
    pc[0] = piece(EXDEX_MOTION_REST);
    pc[0].duration = 1.0;
    pc[1] = piece(EXDEX_MOTION_SAMPLED);
    pc[1].n_samples = 4; pc[1].times = times; pc[1].poses = poses;
    d.n_pieces = 2;
    d.pieces = pc;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, &bad);
    ENSURE(m == NULL && bad && strcmp(bad, "motion.pieces[1]") == 0);
    /* replayed relative to the end of the pause it starts there; the log
     * plays from its first sample: the chain lasts 1 + 1.5 s */
    pc[1].relative = 1;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, &bad);
    ENSURE(m != NULL);
    ENSURE(exdex_motion_end(m) == 2.5);
    ENSURE(exdex_motion_eval(m, 2.0, &k) == 0);
    ENSURE_SMALL(k.p[0], 1e-15);
    exdex_motion_free(m);
    /* a pause without a duration, a nested chain, no pieces */
    pc[0].duration = 0.0;
    ENSURE(exdex_motion_alloc(&d, NULL, NULL, &status, &bad) == NULL && strcmp(bad, "motion.pieces[0]") == 0);
    pc[0] = d;
    ENSURE(exdex_motion_alloc(&d, NULL, NULL, &status, &bad) == NULL && strcmp(bad, "motion.pieces[0]") == 0);
    d.n_pieces = 0;
    ENSURE(exdex_motion_alloc(&d, NULL, NULL, &status, &bad) == NULL && strcmp(bad, "motion.n_pieces") == 0);
    d.n_pieces = EXDEX_MOTION_MAX_PIECES + 1;
    ENSURE(exdex_motion_alloc(&d, NULL, NULL, &status, &bad) == NULL && strcmp(bad, "motion.n_pieces") == 0);
    d.n_pieces = 1;
    d.pieces = NULL;
    ENSURE(exdex_motion_alloc(&d, NULL, NULL, &status, &bad) == NULL && strcmp(bad, "motion.pieces") == 0);
}

/* A sampled log's knots (exdex_motion_next_knot) are its sample times: the
 * first one above t, the first sample before it, none from the last on;
 * inside a chain the running log piece's, at chain time T_i + (t_k - o_i)
 * (its origin o_i the first sample), up to the piece's end (a switching
 * time, not a knot); other motions have none. */
EXDEX_TEST(sampled_and_chain_knots)
{
    exdex_motion_def pc[3], d = piece(EXDEX_MOTION_CHAIN), log = piece(EXDEX_MOTION_SAMPLED);
    double times[4] = {5.0, 5.5, 6.0, 6.5}, poses[28];
    exdex_motion *m;
    const char *bad = NULL;
    int status;
    memset(poses, 0, sizeof poses);
    for (int i = 0; i < 4; i++) poses[7 * i + 3] = 1.0;
    log.n_samples = 4; log.times = times; log.poses = poses;
    m = exdex_motion_alloc(&log, NULL, NULL, &status, &bad);
    ENSURE(m != NULL);
    ENSURE(exdex_motion_next_knot(m, 4.0) == 5.0);
    ENSURE(exdex_motion_next_knot(m, 5.0) == 5.5);
    ENSURE(exdex_motion_next_knot(m, 5.2) == 5.5);
    ENSURE(exdex_motion_next_knot(m, 5.5) == 6.0);
    ENSURE(exdex_motion_next_knot(m, 6.4) == 6.5);
    ENSURE(isinf(exdex_motion_next_knot(m, 6.5)) && isinf(exdex_motion_next_knot(m, 7.0)));
    exdex_motion_free(m);
    /* played from its time 5.75 on (time_shift): the knots 6.0 and 6.5 at
     * 0.25 and 0.75 */
    log.time_shift = 5.75;
    m = exdex_motion_alloc(&log, NULL, NULL, &status, &bad);
    ENSURE(m != NULL);
    ENSURE(exdex_motion_next_knot(m, 0.0) == 0.25);
    ENSURE(exdex_motion_next_knot(m, 0.25) == 0.75);
    ENSURE(isinf(exdex_motion_next_knot(m, 0.75)));
    exdex_motion_free(m);
    log.time_shift = 0.0;
    /* a pause of 1 s, the log (from its first sample), a pause: chain knots
     * at 1.5 and 2.0 s, the log's end 2.5 s a piece boundary */
    pc[0] = piece(EXDEX_MOTION_REST);
    pc[0].duration = 1.0;
    pc[1] = log;
    pc[1].relative = 1;
    pc[2] = pc[0];
    d.n_pieces = 3;
    d.pieces = pc;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, &bad);
    ENSURE(m != NULL);
    ENSURE(isinf(exdex_motion_next_knot(m, 0.5)));
    ENSURE(exdex_motion_next_knot(m, 1.0) == 1.5);
    ENSURE(exdex_motion_next_knot(m, 1.7) == 2.0);
    ENSURE(isinf(exdex_motion_next_knot(m, 2.0)) && isinf(exdex_motion_next_knot(m, 3.0)));
    exdex_motion_free(m);
    d = piece(EXDEX_MOTION_SHAKE);
    d.amplitude = 0.01; d.frequency = 2.0; d.duration = 1.0;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, &bad);
    ENSURE(m != NULL && isinf(exdex_motion_next_knot(m, 0.1)));
    exdex_motion_free(m);
    ENSURE(isinf(exdex_motion_next_knot(NULL, 0.0)));
}
