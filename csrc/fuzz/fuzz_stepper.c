/* fuzz_stepper.c -- exdex_stepper_* on fuzzed scenes (1-DoF and planar,
 * every method, rest, Eq. 7, shake and chain motions, a stop) driven by a
 * fuzzed sequence of steps (step lengths and grip forces, wild ones
 * included; in some runs a prescribed gripper pose per step, valid or
 * not), saves, restores and corrupted restores.
 *
 * Checks: a non-finite or non-positive dt, and a negative or infinite grip
 * force, and a pose whose R is not a rotation, give EXDEX_EINVAL and leave
 * the stepper unchanged, as do a pose with the analytic method and a step
 * without a pose after one with; a step returns
 * EXDEX_OK (then finite state, time advanced), EXDEX_EINVAL, EXDEX_ENOCONV
 * or EXDEX_ENONFINITE, and after a failure only EXDEX_EINVAL until a
 * restore; a snapshot with one byte changed is rejected and leaves the
 * stepper unchanged; steps after a restore repeat the steps after the save
 * bit for bit. */
#include "fuzz.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T "stepper"
#define OPS 10

static void decode_scene(fz *f, exdex_scene_def *d, exdex_motion_def pieces[2])
{
    int kind;
    *d = exdex_default_scene_def();
    d->mass = fz_log(f, 0.01, 2.0);
    d->mu = fz_num(f, 0.0, 1.0);
    d->grip_force = fz_num(f, 0.0, 5.0) * d->mass * 9.81;
    d->dof = fz_pick(f, 1, 3);
    d->e_r = fz_log(f, 1e-3, 0.02);
    d->patch_center[0] = d->dof == EXDEX_DOF_ROTATION ? fz_num(f, -0.03, 0.03) : 0.0;
    d->inertia[0] = d->inertia[4] = d->inertia[8] = d->mass * 1e-3;
    d->method = fz_pick(f, 0, 4);
    d->eps = 1e-3;
    d->rtol = 1e-7;
    d->atol = 1e-9;
    if (fz_pick(f, 0, 2) == 0) {
        double h = 0.02;
        d->n_vertices = 4;
        d->vertices[0][0] = -h; d->vertices[0][1] = -h;
        d->vertices[1][0] = h;  d->vertices[1][1] = -h;
        d->vertices[2][0] = h;  d->vertices[2][1] = h;
        d->vertices[3][0] = -h; d->vertices[3][1] = h;
        d->n_stops = 1;
        d->stop_point[0][2] = -0.03 - fz_num(f, 0.0, 0.01);
        d->stop_normal[0][2] = 1.0;
    }
    kind = fz_pick(f, 0, 3);
    d->motion.axis[2] = -1.0;
    d->motion.amplitude = fz_num(f, -0.1, 0.1);
    d->motion.duration = fz_log(f, 0.05, 0.5);
    d->motion.beta = fz_num(f, 0.1, 0.9);
    d->motion.frequency = fz_log(f, 0.5, 20.0);
    if (kind == 1) d->motion.kind = EXDEX_MOTION_ASYMMETRIC;
    if (kind == 2) d->motion.kind = EXDEX_MOTION_SHAKE;
    if (kind == 3) {
        memset(pieces, 0, 2 * sizeof *pieces);
        pieces[0].kind = EXDEX_MOTION_REST;
        pieces[0].duration = fz_log(f, 0.01, 0.2);
        pieces[1] = d->motion;
        pieces[1].kind = EXDEX_MOTION_ASYMMETRIC;
        d->motion.kind = EXDEX_MOTION_CHAIN;
        d->motion.n_pieces = 2;
        d->motion.pieces = pieces;
    }
}

/* field by field (the struct has padding), NaN grip forces equal */
static int same_sample(const exdex_stepper_sample *a, const exdex_stepper_sample *b)
{
    return memcmp(&a->t, &b->t, sizeof a->t) == 0 && memcmp(a->q, b->q, sizeof a->q) == 0 &&
           memcmp(a->v, b->v, sizeof a->v) == 0 && memcmp(a->wrench, b->wrench, sizeof a->wrench) == 0 &&
           a->stick == b->stick && memcmp(a->stop_force, b->stop_force, sizeof a->stop_force) == 0 &&
           memcmp(&a->grip_force, &b->grip_force, sizeof a->grip_force) == 0 && a->steps == b->steps;
}

/* A pose near the initial one: R0 turned about A z by up to 0.3 rad, p0
 * moved by up to 1 cm, the twist given or not; bad = 1 scales R by 1.01
 * (not a rotation). */
static void decode_pose(fz *f, const exdex_scene_def *d, exdex_gripper_pose *pose, int bad)
{
    double phi = fz_num(f, -0.3, 0.3), c = cos(phi), sn = sin(phi);
    for (int j = 0; j < 3; j++) {
        pose->R[j] = c * d->R0[j] - sn * d->R0[3 + j];
        pose->R[3 + j] = sn * d->R0[j] + c * d->R0[3 + j];
        pose->R[6 + j] = d->R0[6 + j];
        pose->p[j] = d->p0[j] + fz_num(f, -0.01, 0.01);
        pose->v[j] = fz_num(f, -0.5, 0.5);
        pose->w[j] = fz_num(f, -5.0, 5.0);
    }
    if (bad) pose->R[0] *= 1.01;
    pose->given_v = fz_pick(f, 0, 1);
    pose->given_w = fz_pick(f, 0, 1);
}

int fuzz_stepper(const uint8_t *data, size_t size)
{
    fz f;
    exdex_scene_def d;
    exdex_motion_def pieces[2];
    exdex_model *m;
    exdex_stepper *s;
    int status, failed = 0;
    size_t ss;
    unsigned char *snap = NULL, *bad = NULL;
    int have_snap = 0, posing, posed = 0, snap_posed = 0;
    exdex_gripper_pose pose;

    fz_init(&f, data, size);
    decode_scene(&f, &d, pieces);
    posing = fz_pick(&f, 0, 2) == 0;   /* steps give the gripper pose */
    m = exdex_model_alloc(&d, &status, NULL);
    if (fz_trace)
        fprintf(stderr, "scene: method %d dof %d motion %d stops %d mu %.17g grip %.17g mass %.17g\n", d.method, d.dof,
                d.motion.kind, d.n_stops, d.mu, d.grip_force, d.mass);
    if (!m) return 0;
    s = exdex_stepper_alloc(m, &status);
    fuzz_count_status(T, status);
    /* the method's workspace may refuse an overflowing scene (the analytic
     * drive), as exdex_simulate would */
    FZ_CHECK(T, s != NULL ? status == EXDEX_OK : status == EXDEX_ENONFINITE || status == EXDEX_ENOMEM);
    if (!s) {
        exdex_model_free(m);
        return 0;
    }
    ss = exdex_stepper_state_size(s);
    snap = malloc(ss);
    bad = malloc(ss);
    if (!snap || !bad) goto done;
    for (int op = 0; op < OPS; op++) {
        int what = fz_pick(&f, 0, 7);
        exdex_stepper_sample before, after;
        exdex_stepper_get(s, &before, NULL);
        if (what <= 4) {
            double dt = fz_log(&f, 1e-4, 0.02), grip = fz_pick(&f, 0, 2) ? fz_num(&f, 0.0, 3.0) : NAN;
            int bad_arg = !(isfinite(dt) && dt > 0.0) || !(isnan(grip) || (isfinite(grip) && grip >= 0.0));
            int with_pose = posing && fz_pick(&f, 0, 15) != 0, bad_pose = with_pose && fz_pick(&f, 0, 15) == 0;
            if (with_pose) decode_pose(&f, &d, &pose, bad_pose);
            bad_arg = bad_arg || bad_pose || (with_pose && d.method == EXDEX_METHOD_ANALYTIC) ||
                      (!with_pose && posed);
            status = exdex_stepper_step_gripper(s, dt, grip, with_pose ? &pose : NULL);
            if (status == EXDEX_OK && with_pose) posed = 1;
            fuzz_count_status(T, status);
            exdex_stepper_get(s, &after, NULL);
            FZ_CHECK(T, status == EXDEX_OK || status == EXDEX_EINVAL || status == EXDEX_ENOCONV ||
                            status == EXDEX_ENONFINITE);
            if (bad_arg || failed) FZ_CHECK(T, status == EXDEX_EINVAL && same_sample(&before, &after));
            if (status == EXDEX_OK) {
                FZ_CHECK(T, after.t > before.t && after.steps == before.steps + 1);
                FZ_EXTREME(T, &f, isfinite(after.t) && fz_all_finite(after.q, 3) && fz_all_finite(after.v, 3) &&
                                      fz_all_finite(after.wrench, 3));
            } else if (status != EXDEX_EINVAL) {
                failed = 1;
            }
        } else if (what == 5) {
            FZ_CHECK(T, exdex_stepper_save(s, snap, ss) == EXDEX_OK);
            have_snap = 1;
            snap_posed = posed;
            if (!failed) {
                /* two steps, back, the same two steps: the same bits */
                exdex_stepper_sample a[2], b[2];
                exdex_gripper_pose pk[2];
                int st1[2], st2[2];
                for (int k = 0; k < 2; k++) {
                    decode_pose(&f, &d, &pk[k], 0);
                    st1[k] = exdex_stepper_step_gripper(s, 1e-3 * (k + 1), k ? 0.5 : NAN, posed ? &pk[k] : NULL);
                    exdex_stepper_get(s, &a[k], NULL);
                }
                FZ_CHECK(T, exdex_stepper_restore(s, snap, ss) == EXDEX_OK);
                for (int k = 0; k < 2; k++) {
                    st2[k] = exdex_stepper_step_gripper(s, 1e-3 * (k + 1), k ? 0.5 : NAN, posed ? &pk[k] : NULL);
                    exdex_stepper_get(s, &b[k], NULL);
                    FZ_CHECK(T, st1[k] == st2[k] && same_sample(&a[k], &b[k]));
                }
                failed = st2[0] > EXDEX_EINVAL || st2[1] > EXDEX_EINVAL;
            }
        } else if (what == 6 && have_snap) {
            status = exdex_stepper_restore(s, snap, ss);
            FZ_CHECK(T, status == EXDEX_OK);
            failed = 0;
            posed = snap_posed;
            {
                exdex_stepper_sample x;
                exdex_stats st;
                exdex_stepper_get(s, &x, &st);
                failed = st.fail_cause != EXDEX_FAIL_NONE;
            }
        } else if (what == 7 && have_snap) {
            size_t at = (size_t)fz_pick(&f, 0, 1 << 20) % ss;
            memcpy(bad, snap, ss);
            bad[at] ^= (unsigned char)(1 + fz_pick(&f, 0, 254));
            status = exdex_stepper_restore(s, bad, ss);
            exdex_stepper_get(s, &after, NULL);
            FZ_CHECK(T, status == EXDEX_EINVAL && same_sample(&before, &after));
        }
    }
    FZ_CHECK(T, exdex_stepper_restore(s, snap, ss - 1) == EXDEX_EINVAL);
done:
    free(snap);
    free(bad);
    exdex_stepper_free(s);
    exdex_model_free(m);
    return 0;
}
