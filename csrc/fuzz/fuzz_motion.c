/* fuzz_motion.c -- exdex_motion_alloc / _eval / _end and the scalar profiles
 * on fuzzed motion definitions (every kind, translation and rotation,
 * sampled poses with their end conditions, relative replay and tool offset,
 * shakes, chains of profile pieces and pauses),
 * initial poses and evaluation times.
 *
 * Checks: a non-finite value in a field the kind uses gives EXDEX_EINVAL; a
 * failed alloc returns NULL with a status and names the field; EXDEX_OK from
 * eval gives finite kinematics with an orthonormal R; a NaN time gives
 * EXDEX_EINVAL; the profiles give all-NaN for invalid arguments and finite
 * values otherwise. */
#include "fuzz.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define T "motion"
#define MAX_SAMPLES FZ_MAX_SAMPLES



void fz_quat_to_R(double R[9], const double q_in[4])
{
    double n = sqrt(q_in[0] * q_in[0] + q_in[1] * q_in[1] + q_in[2] * q_in[2] + q_in[3] * q_in[3]);
    double w = q_in[0] / n, x = q_in[1] / n, y = q_in[2] / n, z = q_in[3] / n;
    R[0] = 1 - 2 * (y * y + z * z); R[1] = 2 * (x * y - w * z); R[2] = 2 * (x * z + w * y);
    R[3] = 2 * (x * y + w * z); R[4] = 1 - 2 * (x * x + z * z); R[5] = 2 * (y * z - w * x);
    R[6] = 2 * (x * z - w * y); R[7] = 2 * (y * z + w * x); R[8] = 1 - 2 * (x * x + y * y);
}

static int nf(const double *x, int n) { return !fz_all_finite(x, (size_t)n); }

void fz_decode_motion(fz *f, fz_motion *m)
{
    exdex_motion_def *d = &m->def;
    int n, rmode;
    memset(m, 0, sizeof *m);
    d->kind = fz_int(f, 0, 3);
    d->rotation = fz_int(f, 0, 1);
    for (int i = 0; i < 3; i++) d->axis[i] = fz_num(f, -1.0, 1.0);
    for (int i = 0; i < 3; i++) d->center[i] = fz_num(f, -1.0, 1.0);
    d->amplitude = fz_num(f, -1.0, 1.0) * (d->rotation ? 3.0 : 0.2);
    d->duration = fz_log(f, 1e-2, 10.0);
    d->beta = fz_num(f, 0.05, 0.95);
    d->v_max = fabs(d->amplitude) / d->duration * fz_num(f, 1.0, 2.0);
    n = fz_int(f, 4, MAX_SAMPLES);
    /* n_samples larger than the arrays would be the harness's own overrun;
     * negative values become huge size_t, which must be rejected unread */
    d->n_samples = n > MAX_SAMPLES ? MAX_SAMPLES : (size_t)(long)n;
    if (d->kind == EXDEX_MOTION_SAMPLED) {
        double t = fz_num(f, -1.0, 1.0);
        for (int i = 0; i < MAX_SAMPLES; i++) {
            m->times[i] = t;
            t += fz_log(f, 1e-3, 1.0);
        }
        for (int i = 0; i < MAX_SAMPLES; i++)
            for (int c = 0; c < 7; c++) m->poses[7 * i + c] = fz_num(f, -1.0, 1.0);
        d->times = fz_pick(f, 0, 31) ? m->times : NULL;
        d->poses = fz_pick(f, 0, 31) ? m->poses : NULL;
        /* end conditions, relative replay, tool offset */
        for (int e = 0; e < 2; e++) {
            d->end_given[e] = fz_int(f, 0, 1);
            for (int c = 0; c < 3; c++) d->end_velocity[e][c] = fz_num(f, -1.0, 1.0);
            for (int c = 0; c < 3; c++) d->end_omega[e][c] = fz_num(f, -3.0, 3.0);
        }
        d->relative = fz_int(f, 0, 1);
        d->tool = fz_int(f, 0, 1);
        for (int c = 0; c < 7; c++) d->tool_pose[c] = fz_num(f, -1.0, 1.0);
    }
    rmode = fz_pick(f, 0, 7);
    if (rmode == 0) {
        m->have_R0 = 0;
    } else if (rmode == 1) {
        m->have_R0 = 1;
        for (int i = 0; i < 9; i++) m->R0[i] = fz_num(f, -1.0, 1.0);
    } else {
        double q[4];
        m->have_R0 = 1;
        for (int i = 0; i < 4; i++) q[i] = fz_num(f, -1.0, 1.0);
        fz_quat_to_R(m->R0, q);
    }
    m->have_p0 = fz_pick(f, 0, 7) != 0;
    for (int i = 0; i < 3; i++) m->p0[i] = fz_num(f, -2.0, 2.0);

    /* fields the kind must validate */
    if ((m->have_R0 && nf(m->R0, 9)) || (m->have_p0 && nf(m->p0, 3))) m->used_nonfinite = 1;
    if ((d->kind == EXDEX_MOTION_ASYMMETRIC || d->kind == EXDEX_MOTION_TRAPEZOID) &&
        (d->rotation == 0 || d->rotation == 1)) {
        if (nf(d->axis, 3) || !isfinite(d->amplitude) || !isfinite(d->duration) ||
            (d->rotation && nf(d->center, 3)) ||
            (d->kind == EXDEX_MOTION_ASYMMETRIC && !isfinite(d->beta)) ||
            (d->kind == EXDEX_MOTION_TRAPEZOID && !isfinite(d->v_max)))
            m->used_nonfinite = 1;
    }
    if (d->kind == EXDEX_MOTION_SAMPLED && d->times && d->poses && d->n_samples <= MAX_SAMPLES &&
        (nf(m->times, (int)d->n_samples) || nf(m->poses, 7 * (int)d->n_samples)))
        m->used_nonfinite = 1;
    if (d->kind == EXDEX_MOTION_SAMPLED) {
        for (int e = 0; e < 2; e++)
            if (d->end_given[e] == 1 && (nf(d->end_velocity[e], 3) || nf(d->end_omega[e], 3))) m->used_nonfinite = 1;
        if (d->tool == 1 && nf(d->tool_pose, 7)) m->used_nonfinite = 1;
    }
}

/* Shakes and chains of profile pieces (a nested chain among them is
 * rejected), decoded after fz_decode_motion by this target only (the
 * simulate target's input stream stays as it is). */
static void decode_shake_chain(fz *f, fz_motion *m)
{
    exdex_motion_def *d = &m->def;
    switch (fz_int(f, 0, 7)) {
    case 6:
        d->kind = EXDEX_MOTION_SHAKE;
        m->used_nonfinite = (m->have_R0 && nf(m->R0, 9)) || (m->have_p0 && nf(m->p0, 3));
        d->frequency = fz_log(f, 1e-2, 100.0);
        if ((d->rotation == 0 || d->rotation == 1) &&
            (nf(d->axis, 3) || !isfinite(d->amplitude) || !isfinite(d->duration) || !isfinite(d->frequency) ||
             (d->rotation && nf(d->center, 3))))
            m->used_nonfinite = 1;
        break;
    case 7: {
        int np = fz_int(f, 0, 5), nonfinite = 0;
        d->kind = EXDEX_MOTION_CHAIN;
        m->used_nonfinite = (m->have_R0 && nf(m->R0, 9)) || (m->have_p0 && nf(m->p0, 3));
        /* more pieces than the harness holds would be its own overrun;
         * negative or beyond EXDEX_MOTION_MAX_PIECES must be rejected unread */
        d->n_pieces = np < 0 ? (size_t)(long)np : np > 5 && np <= EXDEX_MOTION_MAX_PIECES ? 5 : (size_t)np;
        d->pieces = fz_pick(f, 0, 31) ? m->pieces : NULL;
        d->allow_jump = fz_int(f, 0, 2);
        for (int i = 0; i < 5; i++) {
            exdex_motion_def *p = &m->pieces[i];
            memset(p, 0, sizeof *p);
            p->kind = fz_int(f, 0, 5);
            if (p->kind == EXDEX_MOTION_SAMPLED) p->kind = EXDEX_MOTION_REST;
            p->rotation = fz_int(f, 0, 1);
            for (int c = 0; c < 3; c++) p->axis[c] = fz_num(f, -1.0, 1.0);
            for (int c = 0; c < 3; c++) p->center[c] = fz_num(f, -1.0, 1.0);
            p->amplitude = fz_num(f, -1.0, 1.0) * (p->rotation ? 3.0 : 0.2);
            p->duration = fz_log(f, 1e-2, 10.0);
            p->beta = fz_num(f, 0.05, 0.95);
            p->v_max = fabs(p->amplitude) / p->duration * fz_num(f, 1.0, 2.0);
            p->frequency = fz_log(f, 1e-2, 100.0);
            if (i < np && p->kind != EXDEX_MOTION_CHAIN &&
                (!isfinite(p->duration) ||
                 (p->kind != EXDEX_MOTION_REST && (p->rotation == 0 || p->rotation == 1) &&
                  (nf(p->axis, 3) || !isfinite(p->amplitude) || (p->rotation && nf(p->center, 3)) ||
                   (p->kind == EXDEX_MOTION_ASYMMETRIC && !isfinite(p->beta)) ||
                   (p->kind == EXDEX_MOTION_TRAPEZOID && !isfinite(p->v_max)) ||
                   (p->kind == EXDEX_MOTION_SHAKE && !isfinite(p->frequency))))))
                nonfinite = 1;
        }
        if (nonfinite && d->pieces && np >= 1 && np <= EXDEX_MOTION_MAX_PIECES) m->used_nonfinite = 1;
        break;
    }
    default:
        break;
    }
}

static void check_profiles(fz *f)
{
    fz *fp = f;
    double X1 = fz_num(f, -1.0, 1.0), Tt = fz_log(f, 1e-2, 10.0), beta = fz_num(f, 0.0, 1.0);
    double vm = fabs(X1) / Tt * fz_num(f, 0.9, 2.1), t = fz_num(f, -1.0, 25.0);
    double s = 0, sd = 0, sdd = 0;
    int valid;
    if (fz_trace)
        fprintf(stderr, "profiles: X1 %.17g T %.17g beta %.17g v_max %.17g t %.17g\n", X1, Tt, beta, vm, t);
    exdex_profile_asymmetric(X1, Tt, beta, t, &s, &sd, &sdd);
    exdex_profile_asymmetric(X1, Tt, beta, t, NULL, NULL, NULL);  /* NULL outputs allowed */
    valid = isfinite(X1) && isfinite(Tt) && Tt > 0 && beta > 0 && beta < 1 && !isnan(t);
    if (valid) {
        /* finite, unless the data overflow (|X1| / (beta T^2) beyond DBL_MAX) */
        if (isfinite(2.0 * X1 / (beta * Tt * Tt)) && isfinite(2.0 * X1 / ((beta - 1) * Tt * Tt)) &&
            isfinite(t * t))
            FZ_EXTREME(T, fp, isfinite(s) && isfinite(sd) && isfinite(sdd));
    } else {
        FZ_CHECK(T, isnan(s) && isnan(sd) && isnan(sdd));
    }
    /* v_max > 0 is required whenever X1 != 0, also when |X1|/T underflows to 0
     * (the range test alone then accepts v_max = 0) */
    exdex_profile_trapezoid(X1, Tt, vm, t, &s, &sd, &sdd);
    exdex_profile_trapezoid(X1, Tt, vm, t, NULL, NULL, NULL);
    valid = isfinite(X1) && isfinite(Tt) && Tt > 0 && isfinite(vm) && !isnan(t) &&
            (X1 == 0 ? vm >= 0 : (vm > 0 && vm >= fabs(X1) / Tt * (1 - 1e-12) && vm <= 2 * fabs(X1) / Tt * (1 + 1e-12)));
    if (!valid && !isnan(t) && isfinite(X1) && isfinite(Tt) && Tt > 0 && isfinite(vm)) valid = -1;  /* near a bound */
    if (valid == 1) {
        if (isfinite(vm * vm) && isfinite(vm / Tt))
            FZ_EXTREME(T, fp, isfinite(s) && isfinite(sd) && isfinite(sdd));
    } else if (valid == 0) {
        FZ_CHECK(T, isnan(s) && isnan(sd) && isnan(sdd));
    }
}

int fuzz_motion(const uint8_t *data, size_t size)
{
    fz f;
    fz_motion mm;
    exdex_motion *m;
    int status = -1;
    const char *bad = NULL;

    fz_init(&f, data, size);
    fz_decode_motion(&f, &mm);
    decode_shake_chain(&f, &mm);
    m = exdex_motion_alloc(&mm.def, mm.have_R0 ? mm.R0 : NULL, mm.have_p0 ? mm.p0 : NULL, &status, &bad);
    fuzz_count_status(T, status);
    if (!m) {
        FZ_CHECK(T, status == EXDEX_EINVAL || status == EXDEX_ENOMEM);
        if (status == EXDEX_EINVAL) FZ_CHECK(T, bad != NULL);
    } else {
        FZ_CHECK(T, status == EXDEX_OK);
    }
    if (mm.used_nonfinite) FZ_CHECK(T, m == NULL && status == EXDEX_EINVAL);
    /* NULL status / bad_param pointers are allowed */
    {
        exdex_motion *m2 = exdex_motion_alloc(&mm.def, mm.have_R0 ? mm.R0 : NULL,
                                              mm.have_p0 ? mm.p0 : NULL, NULL, NULL);
        FZ_CHECK(T, (m2 == NULL) == (m == NULL));
        exdex_motion_free(m2);
    }
    FZ_CHECK(T, exdex_motion_eval(NULL, 0.0, NULL) == EXDEX_EINVAL);
    if (m) {
        double end = exdex_motion_end(m);
        FZ_CHECK(T, isfinite(end));
        for (int k = 0; k < 8; k++) {
            exdex_kinematics kin;
            double t = fz_num(&f, -0.5, 1.5 * fabs(end) + 0.5);
            int st = exdex_motion_eval(m, t, &kin);
            fuzz_count_status(T, st);
            FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL || st == EXDEX_ENONFINITE);
            if (isnan(t)) FZ_CHECK(T, st == EXDEX_EINVAL);
            if (st == EXDEX_OK) {
                FZ_EXTREME(T, &f, fz_all_finite(kin.R, 9) && fz_all_finite(kin.p, 3) && fz_all_finite(kin.v, 3) &&
                                      fz_all_finite(kin.a, 3) && fz_all_finite(kin.w, 3) &&
                                      fz_all_finite(kin.dw, 3));
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) {
                        double d = kin.R[3 * i] * kin.R[3 * j] + kin.R[3 * i + 1] * kin.R[3 * j + 1] +
                                   kin.R[3 * i + 2] * kin.R[3 * j + 2] - (i == j);
                        /* every input: R0 is validated to 1e-9, Rot(axis, s) is
                         * orthonormal to rounding for any finite s (the axis is
                         * normalised without overflow since the fix for
                         * components near DBL_MAX) */
                        FZ_CHECK(T, fabs(d) <= 1e-6);
                    }
            }
        }
        FZ_CHECK(T, exdex_motion_eval(m, 0.0, NULL) == EXDEX_EINVAL);
    }
    exdex_motion_free(m);
    exdex_motion_free(NULL);
    check_profiles(&f);
    return 0;
}
