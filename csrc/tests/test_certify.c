/* test_certify.c -- the certificate's proofs per piece against the check of
 * every sample: exdex_certify skips the samples whose mode it has proven to
 * hold in their piece (a constant load, or a bound on a turning gripper's
 * load); exdex_certify_samples evaluates each of them. Both must give the
 * same certificate, on scenes on both sides of their thresholds, in every
 * method that solves them; and so must the run certified as it goes
 * (exdex_simulate_certified), which stops where the reduction fails.
 * twin: tests/scenarios/test_certify.py (the same subject through the Python API: closed forms) */
#include "check.h"
#include "sim_run.h"
#include "../model.h"
#include "../pose.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int n_held, n_failed;

/* The run certified as it goes (exdex_simulate_certified) against the
 * whole run r and its certificate a: where the reduction holds, the same
 * samples, stats and certificate; where it fails, the same certificate,
 * the samples before the failing one bit for bit, and the run's last
 * sample at valid_until (the grid's sample before it, or one step on). */
static void same_as_it_goes(const exdex_model *m, const sim_run *r, const exdex_certificate *a, double t_end,
                            double dt)
{
    size_t n = r->tr.n, nw = 0, f, keep;
    int nd = r->ndof, ns = r->nstops;
    exdex_trajectory o;
    exdex_stats st;
    exdex_certificate c;
    o.n = n;
    o.t = calloc(n, sizeof(double));
    o.q = calloc(n * 3, sizeof(double));
    o.v = calloc(n * 3, sizeof(double));
    o.wrench = calloc(n * 3, sizeof(double));
    o.stick = calloc(n, 1);
    o.stop_force = calloc(n * (ns + 1), sizeof(double));
    ENSURE(o.t && o.q && o.v && o.wrench && o.stick && o.stop_force);
    if (o.t && o.q && o.v && o.wrench && o.stick && o.stop_force) {
        ENSURE(exdex_simulate_certified(m, t_end, dt, &o, &st, &c, &nw) == EXDEX_OK);
        ENSURE(c.holds == a->holds && c.first_bad == a->first_bad && c.reduced == a->reduced);
        ENSURE(c.stick == a->stick && c.coordinate == a->coordinate);
        ENSURE(c.gauge == a->gauge || (a->gauge != a->gauge && c.gauge != c.gauge));
        for (int k = 0; k < 3; k++) ENSURE(c.load[k] == a->load[k]);
        f = a->holds ? n : a->first_bad;
        keep = f ? f : 1;
        if (a->holds) {
            ENSURE(nw == n && c.valid_until == a->valid_until);
            ENSURE(memcmp(&st, &r->st, sizeof st) == 0);
        } else {
            /* the step to the failure's time may not return: the run then ends on the sample before */
            ENSURE(nw == keep || nw == keep + 1);
            ENSURE(c.valid_until == a->valid_until || (nw == keep && c.valid_until == o.t[keep - 1]));
            ENSURE(o.t[nw - 1] == c.valid_until);
            ENSURE(st.stick_steps <= r->st.stick_steps && st.steps <= r->st.steps);
        }
        ENSURE(memcmp(o.t, r->tr.t, keep * sizeof(double)) == 0);
        ENSURE(memcmp(o.q, r->tr.q, keep * nd * sizeof(double)) == 0);
        ENSURE(memcmp(o.v, r->tr.v, keep * nd * sizeof(double)) == 0);
        ENSURE(memcmp(o.wrench, r->tr.wrench, keep * 3 * sizeof(double)) == 0);
        ENSURE(memcmp(o.stick, r->tr.stick, keep) == 0);
        ENSURE(memcmp(o.stop_force, r->tr.stop_force, keep * ns * sizeof(double)) == 0);
    }
    free(o.t);
    free(o.q);
    free(o.v);
    free(o.wrench);
    free(o.stick);
    free(o.stop_force);
}

static void same_certificate(const exdex_scene_def *d, double t_end, double dt)
{
    const char *bad = NULL;
    int status;
    exdex_model *m = exdex_model_alloc(d, &status, &bad);
    sim_run r;
    exdex_certificate a, b;
    ENSURE(m != NULL);
    if (!m) return;
    ENSURE(sim_run_def(d, t_end, dt, &r) == EXDEX_OK);
    ENSURE(exdex_certify(m, &r.tr, &a) == EXDEX_OK);
    ENSURE(exdex_certify_samples(m, &r.tr, &b) == EXDEX_OK);
    ENSURE(a.reduced == 1 && b.reduced == 1);
    ENSURE(a.holds == b.holds);
    ENSURE(a.first_bad == b.first_bad);
    ENSURE(a.valid_until == b.valid_until);
    ENSURE(a.stick == b.stick && a.coordinate == b.coordinate);
    ENSURE(a.gauge == b.gauge || (a.gauge != a.gauge && b.gauge != b.gauge));
    for (int c = 0; c < 3; c++) ENSURE(a.load[c] == b.load[c]);
    same_as_it_goes(m, &r, &a, t_end, dt);
    n_held += a.holds;
    n_failed += !a.holds;
    sim_run_free(&r);
    exdex_model_free(m);
}

static const int methods[5] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EXPLICIT, EXDEX_METHOD_ANALYTIC,
                                EXDEX_METHOD_EVENT, EXDEX_METHOD_REGULARISED};

/* A grip schedule of 4 breakpoints (times [s], forces [N per finger], kind
 * enum exdex_grip_kind) on d; the arrays must outlive d's runs. */
static void grip_schedule(exdex_scene_def *d, const double *times, const double *forces, int kind)
{
    d->grip_n = 4;
    d->grip_times = times;
    d->grip_forces = forces;
    d->grip_kind = kind;
}

/* A 0.2 kg box held by the plates, the patch `offset` off its centre of
 * mass, gravity in the plate plane. */
static exdex_scene_def box(double ratio, double offset, int method)
{
    exdex_scene_def d = scene_vertical(0.2, ratio);
    d.inertia[0] = d.inertia[4] = d.inertia[8] = 4e-4;
    d.patch_center[0] = offset;
    d.e_r = 0.0076520;
    d.method = method;
    return d;
}

EXDEX_TEST(certify_proofs_held_box_and_slides)
{
    n_held = n_failed = 0;
    for (int k = 0; k < 5; k++) {
        for (int j = 0; j < 4; j++) {
            /* the turning threshold of the box: 3 N per finger, offset 22.11 mm */
            double offsets[4] = {0.0, 0.02, 0.0225, 0.06}, ratios[4] = {3.06, 3.06, 3.06, 1.5};
            exdex_scene_def d = box(ratios[j], offsets[j], methods[k]);
            same_certificate(&d, 0.3, methods[k] == EXDEX_METHOD_REGULARISED ? 3e-3 : 1e-3);
            /* Eq. 7 along the plates (the slide axis) and across them */
            scene_eq7(&d, 0, 0.0, 0.0, -1.0, 0.1, 0.3, 0.7);
            same_certificate(&d, 0.8, methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3);
            scene_eq7(&d, 0, 1.0, 0.0, 0.0, 0.1, 0.3, 0.7);
            same_certificate(&d, 0.8, methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3);
        }
    }
    ENSURE(n_held >= 10 && n_failed >= 10);
}

EXDEX_TEST(certify_proofs_turning_gripper)
{
    n_held = n_failed = 0;
    for (int k = 0; k < 5; k++) {
        if (methods[k] == EXDEX_METHOD_ANALYTIC) continue;
        for (int j = 0; j < 4; j++) {
            /* a translation in a gripper that turns 30 deg about the plate normal (A -y) */
            double ratios[4] = {3.0, 1.05, 0.8, 3.0}, offsets[4] = {0.0, 0.0, 0.0, 0.03};
            exdex_scene_def d = box(ratios[j], offsets[j], methods[k]);
            scene_eq7(&d, 1, 0.0, -1.0, 0.0, 0.5236, 0.5, 0.8);
            same_certificate(&d, 1.2, methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3);
            /* the axis off the centre of mass */
            d.motion.center[0] = 0.05;
            same_certificate(&d, 1.2, methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3);
        }
    }
    ENSURE(n_held >= 4 && n_failed >= 4);
}

EXDEX_TEST(certify_proofs_rotation)
{
    n_held = n_failed = 0;
    for (int k = 0; k < 5; k++) {
        for (int j = 0; j < 6; j++) {
            /* Fig. 6's rotation: about the centre of mass, the gripper turning about the
             * plate normal through it; gravity along the normal (j even) or in the plane */
            double ratios[3] = {0.5, 3.0, 30.0};
            exdex_scene_def d = box(ratios[j / 2], 0.0, methods[k]);
            d.dof = EXDEX_DOF_ROTATION;
            d.inertia[8] = 0.04;
            if (j % 2 == 0) {
                d.gravity[2] = 0.0;
                d.gravity[1] = -9.81;
            }
            scene_eq7(&d, 1, 0.0, -1.0, 0.0, 1.745, 3.0, 0.7);
            same_certificate(&d, 8.0, methods[k] == EXDEX_METHOD_REGULARISED ? 2e-2 : 1e-2);
            if (methods[k] == EXDEX_METHOD_ANALYTIC) continue;
            /* the pivot off the centre of mass, and the axis off the pivot */
            d.patch_center[0] = 0.01;
            same_certificate(&d, 8.0, methods[k] == EXDEX_METHOD_REGULARISED ? 2e-2 : 1e-2);
            d.patch_center[0] = 0.0;
            d.motion.center[0] = 0.02;
            same_certificate(&d, 8.0, methods[k] == EXDEX_METHOD_REGULARISED ? 2e-2 : 1e-2);
        }
    }
    ENSURE(n_held >= 5 && n_failed >= 5);
}

EXDEX_TEST(certify_proofs_stop_holds_the_box)
{
    /* a stop under the box (its outline's bottom edge) while the patch is off its centre of mass */
    for (int k = 0; k < 5; k++) {
        if (methods[k] == EXDEX_METHOD_ANALYTIC) continue;
        for (int j = 0; j < 2; j++) {
            exdex_scene_def d = box(j ? 1.5 : 0.8, 0.06, methods[k]);
            scene_rect(&d, 0.075, 0.04);
            scene_stop(&d, 0, 0.0, 0.0, -0.04, 0.0, 0.0, 1.0);
            same_certificate(&d, 0.3, methods[k] == EXDEX_METHOD_REGULARISED ? 3e-3 : 1e-3);
            /* a frictional stop */
            d.stop_mu[0] = 0.7;
            same_certificate(&d, 0.3, methods[k] == EXDEX_METHOD_REGULARISED ? 3e-3 : 1e-3);
            scene_trapezoid(&d, 0, 0.0, 0.0, -1.0, 0.05, 0.5, 0.12);
            same_certificate(&d, 0.8, methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3);
            d.stop_mu[0] = 0.0;
            same_certificate(&d, 0.8, methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3);
        }
    }
}

EXDEX_TEST(certify_proofs_grip_schedule)
{
    /* the grip force ramps down through the held box's and the turning
     * gripper's thresholds, and up again (every kind of schedule) */
    static const double times[4] = {0.0, 0.2, 0.5, 0.9};
    static const double forces[4] = {1.0, 0.25, 0.5, 1.2};
    const int kinds[3] = {EXDEX_GRIP_LINEAR, EXDEX_GRIP_STEP, EXDEX_GRIP_CUBIC};
    n_held = n_failed = 0;
    for (int k = 0; k < 5; k++) {
        for (int g = 0; g < 3; g++) {
            for (int j = 0; j < 3; j++) {
                double ratios[3] = {6.0, 3.5, 12.0}, offsets[3] = {0.0, 0.0, 0.01};
                exdex_scene_def d = box(ratios[j], offsets[j], methods[k]);
                grip_schedule(&d, times, forces, kinds[g]);
                if (methods[k] == EXDEX_METHOD_ANALYTIC && kinds[g] == EXDEX_GRIP_CUBIC) continue;
                same_certificate(&d, 1.2, methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3);
                if (methods[k] == EXDEX_METHOD_ANALYTIC) continue;
                scene_eq7(&d, 1, 0.0, -1.0, 0.0, 0.5236, 0.5, 0.8);
                same_certificate(&d, 1.2, methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3);
            }
        }
    }
    ENSURE(n_held >= 5 && n_failed >= 5);
}

/* Shakes, logs and chains, on random scenes around the held box's
 * thresholds: the block proofs (translating gripper) and the bound of a
 * shake turning about the plate normal, against every sample's check. */
static unsigned long lcg = 12345;
static double urand(double lo, double hi)
{
    lcg = lcg * 6364136223846793005UL + 1442695040888963407UL;
    return lo + (hi - lo) * (double)(lcg >> 11) / 9007199254740992.0;
}

/* The random motions of the block proofs' tests: a shake along the scene's
 * axis (half or whole cycles: no jump), a log of a constant orientation at
 * uneven sample times (positions a random walk) or a chain (a whole-cycle
 * shake, a pause, Eq. 7), amplitude amp, frequency f; the log and the
 * chain use the caller's buffers. */
enum { RANDOM_SHAKE, RANDOM_LOG, RANDOM_CHAIN };
static void random_motion(exdex_scene_def *d, int kind, double amp, double f, double times[12], double poses[12 * 7],
                          exdex_motion_def pc[3])
{
    if (kind == RANDOM_SHAKE) {
        d->motion.kind = EXDEX_MOTION_SHAKE;
        d->motion.amplitude = amp;
        d->motion.frequency = f;
        d->motion.duration = 0.5 * floor(urand(1.0, 6.0)) / f;   /* whole or half cycles: no jump */
        d->motion.allow_jump = 0;
    } else if (kind == RANDOM_LOG) {
        double t = 0.0;
        for (int i = 0; i < 12; i++) {
            times[i] = t;
            t += urand(0.03, 0.1);
            for (int c = 0; c < 3; c++) poses[7 * i + c] = i == 0 ? 0.0 : poses[7 * (i - 1) + c] + urand(-0.003, 0.003);
            poses[7 * i + 3] = 1.0;
            poses[7 * i + 4] = poses[7 * i + 5] = poses[7 * i + 6] = 0.0;
        }
        d->motion.kind = EXDEX_MOTION_SAMPLED;
        d->motion.n_samples = 12;
        d->motion.times = times;
        d->motion.poses = poses;
        d->motion.relative = 1;
    } else {
        exdex_motion_def c0 = d->motion;
        memset(pc, 0, 3 * sizeof *pc);
        pc[0].kind = EXDEX_MOTION_SHAKE;
        memcpy(pc[0].axis, c0.axis, sizeof c0.axis);
        pc[0].amplitude = amp;
        pc[0].frequency = f;
        pc[0].duration = 2.0 / f;
        pc[1].kind = EXDEX_MOTION_REST;
        pc[1].axis[0] = 1.0;
        pc[1].duration = 0.1;
        pc[2].kind = EXDEX_MOTION_ASYMMETRIC;
        memcpy(pc[2].axis, c0.axis, sizeof c0.axis);
        pc[2].amplitude = 10.0 * amp;
        pc[2].duration = 0.2;
        pc[2].beta = 0.6;
        memset(&d->motion, 0, sizeof d->motion);
        d->motion.kind = EXDEX_MOTION_CHAIN;
        d->motion.axis[0] = 1.0;
        d->motion.n_pieces = 3;
        d->motion.pieces = pc;
    }
}

EXDEX_TEST(certify_proofs_shakes_logs_chains)
{
    static double times[12], poses[12 * 7];
    static const double gt[4] = {0.0, 0.3, 0.6, 1.0}, gf[4] = {1.0, 0.4, 0.7, 1.1};
    exdex_motion_def pc[3];
    n_held = n_failed = 0;
    for (int s = 0; s < 40; s++) {
        int kind = s % 4, k = (int[]){0, 1, 3, 4}[(s / 4) % 4];   /* no analytic: these motions are not piecewise constant */
        double ratio = urand(1.2, 5.0), offset = urand(0.0, 0.9) * 0.0076520 * sqrt(ratio * ratio - 1.0), amp = urand(-0.004, 0.004), f = urand(2.0, 6.0);
        double dt = methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3;
        exdex_scene_def d = box(ratio, offset, methods[k]);
        d.motion.axis[0] = urand(-1, 1);
        d.motion.axis[1] = urand(-1, 1);
        d.motion.axis[2] = urand(-1, 1);
        if (kind == 0 || kind == 1) {
            /* a shake translating, or turning about the plate normal (A -y) */
            random_motion(&d, RANDOM_SHAKE, kind ? 40.0 * amp : amp, f, times, poses, pc);
            if (kind == 1) {
                /* near the turning threshold at rest: the turn's inertial moment decides */
                d.patch_center[0] = urand(0.8, 0.99) * 0.0076520 * sqrt(ratio * ratio - 1.0);
                d.motion.rotation = 1;
                d.motion.axis[0] = d.motion.axis[2] = 0.0;
                d.motion.axis[1] = -1.0;
                d.motion.center[0] = urand(-0.08, 0.08);
            }
        } else {
            random_motion(&d, kind == 2 ? RANDOM_LOG : RANDOM_CHAIN, amp, f, times, poses, pc);
        }
        if (s % 5 == 4) grip_schedule(&d, gt, gf, EXDEX_GRIP_LINEAR);
        same_certificate(&d, 0.9, dt);
    }
    /* the offset keeps the box held at rest: a failure is the motion's */
    ENSURE(n_held >= 8 && n_failed >= 8);
}

/* Rotation runs in a gripper that does not turn: the block proofs (the
 * load's enclosure over the block's angles and rates) against every
 * sample's check, on random scenes around two thresholds:
 *   held: the pivot (the centre of pressure) `offset` off the centre of
 *     mass, gravity in the plate plane; the stuck load's gauge is
 *     hypot(1, offset / e_r) / ratio at rest (ratio the capacity over the
 *     weight), so offset = e_r sqrt(ratio^2 - 1) is the threshold, the
 *     shake's acceleration moving it;
 *   slipping: gravity along the plate normal, the gripper shaken along it,
 *     the object spun at the start; the pin must carry the centripetal
 *     force m omega^2 |c| alone (c the centre of mass from the pivot), the
 *     slip holds while it is within the certificate's tolerance
 *     (CERT_SLIP_TOL of the force scale), so |c| log-uniform over
 *     1e-11 .. 1e-6 m puts scenes on both sides (the rate falls as the
 *     torsional friction brakes the spin, so the first sample decides). */
EXDEX_TEST(certify_proofs_rotation_blocks)
{
    static double times[12], poses[12 * 7];
    exdex_motion_def pc[3];
    int slip_held = 0, slip_failed = 0;
    n_held = n_failed = 0;
    lcg = 777;
    for (int s = 0; s < 144; s++) {
        int kind = s % 4, k = (int[]){0, 1, 3, 4}[(kind == 3 ? s / 12 : s / 4) % 4];
        double ratio = urand(1.2, 5.0), amp = urand(-0.004, 0.004), f = urand(2.0, 6.0);
        double offset = urand(0.0, 1.15) * 0.0076520 * sqrt(ratio * ratio - 1.0);
        double dt = methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3;
        exdex_scene_def d = box(ratio, offset, methods[k]);
        d.dof = EXDEX_DOF_ROTATION;
        d.motion.axis[0] = urand(-1, 1);
        d.motion.axis[1] = urand(-1, 1);
        d.motion.axis[2] = urand(-1, 1);
        if (kind == 0 || kind == 3) {
            /* a translating shake */
            random_motion(&d, RANDOM_SHAKE, amp, f, times, poses, pc);
            if (kind == 3) {
                /* spun, gravity and the shake along the plate normal (A y) */
                d.gravity[2] = 0.0;
                d.gravity[1] = -9.81;
                d.motion.axis[0] = d.motion.axis[2] = 0.0;
                d.motion.axis[1] = 1.0;
                d.inertia[8] = 0.04;
                double w0 = urand(1.5, 4.0), tol, ang = urand(0.0, 6.283185307179586), x;
                d.v0[2] = (s / 4) % 2 ? w0 : -w0;
                {
                    /* the slip's tolerance (certify.c): CERT_SLIP_TOL (F + C), the load's own share ~1e-9 of it */
                    const char *bad = NULL;
                    int status;
                    exdex_model *m0 = exdex_model_alloc(&d, &status, &bad);
                    ENSURE(m0 != NULL);
                    if (!m0) return;
                    tol = CERT_SLIP_TOL * (m0->scale.F + model_capacity(m0, 0.0));
                    exdex_model_free(m0);
                }
                /* |c| with the centripetal force at the start x of the tolerance */
                x = urand(0.3, 3.0);
                d.patch_center[0] = x * tol / (d.mass * w0 * w0) * cos(ang);
                d.patch_center[1] = x * tol / (d.mass * w0 * w0) * sin(ang);
                if ((s / 4) % 3) {
                    /* a pause, then the shake tilted off the normal: its plate-plane
                     * acceleration (at most y of the tolerance) and the centripetal
                     * force add or cancel as the object turns */
                    double y = urand(0.4, 0.7), wf = 6.283185307179586 * f;
                    exdex_motion_def c0 = d.motion;
                    x = urand(0.5, 0.8);
                    d.inertia[8] = s % 8 == 3 ? 0.4 : 0.04;   /* the spin lasts (the angle sweeps) or slows */
                    d.patch_center[0] = x * tol / (d.mass * w0 * w0) * cos(ang);
                    d.patch_center[1] = x * tol / (d.mass * w0 * w0) * sin(ang);
                    ang = urand(0.0, 6.283185307179586);
                    memset(pc, 0, sizeof pc);
                    pc[0].kind = EXDEX_MOTION_REST;
                    pc[0].axis[0] = 1.0;
                    pc[0].duration = urand(0.05, 0.3);
                    pc[1] = c0;
                    pc[1].amplitude = 0.004;
                    pc[1].axis[0] = y * tol / (d.mass * 0.004 * wf * wf) * cos(ang);
                    pc[1].axis[2] = y * tol / (d.mass * 0.004 * wf * wf) * sin(ang);
                    memset(&d.motion, 0, sizeof d.motion);
                    d.motion.kind = EXDEX_MOTION_CHAIN;
                    d.motion.axis[0] = 1.0;
                    d.motion.n_pieces = 2;
                    d.motion.pieces = pc;
                }
            }
        } else {
            random_motion(&d, kind == 1 ? RANDOM_LOG : RANDOM_CHAIN, amp, f, times, poses, pc);
        }
        if (kind != 3 && s % 3 == 2) {
            /* gravity along the plate normal: only the gripper's acceleration loads the pin */
            d.gravity[2] = 0.0;
            d.gravity[1] = -9.81;
        }
        {
            int h0 = n_held;
            same_certificate(&d, 0.9, dt);
            if (kind == 3) {
                slip_held += n_held > h0;
                slip_failed += n_held == h0;
            }
        }
    }
    ENSURE(n_held >= 8 && n_failed >= 8);
    ENSURE(slip_held >= 2 && slip_failed >= 2);
}

/* Barycentric coordinates' least of p in the triangle a, b, c. */
static double tri_min_bary(const double a[2], const double b[2], const double c[2], const double p[2])
{
    double det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    double l1 = ((p[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (p[1] - a[1])) / det;
    double l2 = ((b[0] - a[0]) * (p[1] - a[1]) - (p[0] - a[0]) * (b[1] - a[1])) / det;
    double l0 = 1.0 - l1 - l2;
    return fmin(l0, fmin(l1, l2));
}

/* The enclosure of a rotated vector (certify_arc_triangle) by geometry: every
 * Rz(-theta) u, theta in [th0, th1], lies in the triangle of the returned
 * angles and scales; with the tangents' meeting point taken unscaled (the
 * triangle inscribed in the arc) the arc's quarter points leave it, so the
 * containment check can fail. */
EXDEX_TEST(certify_arc_triangle_encloses_the_arc)
{
    double th[3], sc[3];
    lcg = 99;
    ENSURE(certify_arc_triangle(0.3, 0.3, 0.4, th, sc) == 1 && th[0] == 0.3 && sc[0] == 1.0);
    ENSURE(certify_arc_triangle(0.3, 0.2, 0.4, th, sc) == 0);
    ENSURE(certify_arc_triangle(0.0, 0.81, 0.4, th, sc) == 0);
    ENSURE(certify_arc_triangle(0.0, NAN, 0.4, th, sc) == 0);
    ENSURE(certify_arc_triangle(0.0, 1.0, 1.6, th, sc) == 0);
    for (int s = 0; s < 200; s++) {
        double th0 = urand(-7.0, 7.0), h = s < 20 ? urand(1e-9, 1e-3) : urand(0.0, 1.5), u[2] = {urand(-2, 2), urand(-2, 2)};
        double V[3][2], worst = INFINITY, mid[2], chord[2], cm = cos(th0 + 0.5 * h), sm = sin(th0 + 0.5 * h);
        int n = certify_arc_triangle(th0, th0 + 2.0 * h, 1.5, th, sc);
        ENSURE(n == 3);
        if (n != 3) continue;
        for (int k = 0; k < 3; k++) {
            double c = cos(th[k]), sn = sin(th[k]);
            V[k][0] = sc[k] * (c * u[0] + sn * u[1]);
            V[k][1] = sc[k] * (-sn * u[0] + c * u[1]);
        }
        for (int j = 0; j <= 100; j++) {
            double a = th0 + 2.0 * h * j / 100.0, p[2] = {cos(a) * u[0] + sin(a) * u[1], -sin(a) * u[0] + cos(a) * u[1]};
            double b = tri_min_bary(V[0], V[1], V[2], p);
            if (b < worst) worst = b;
        }
        /* rounding of the coordinates: ~1e-16 over the triangle's ~h^2 relative height */
        ENSURE(worst >= -1e-15 / (h * h));
        /* the inscribed triangle (the meeting point unscaled: the arc's middle) misses the arc
         * between its ends and its middle */
        mid[0] = cm * u[0] + sm * u[1];
        mid[1] = -sm * u[0] + cm * u[1];
        chord[0] = V[2][0] / sc[2];
        chord[1] = V[2][1] / sc[2];
        if (h > 0.05) ENSURE(tri_min_bary(V[0], V[1], chord, mid) < 0.0 && tri_min_bary(V[0], V[1], V[2], mid) > 0.0);
    }
}

/* A random turning motion for the frame enclosures and the rotation's
 * turning blocks: kind 0 a log turning about axes that wander (relative,
 * a tool pose off B's origin), 1 a chain (a pause, Eq. 7 turning about a
 * random axis through a point off B, a turning shake, a translating shake),
 * 2 Eq. 7 or a trapezoid turning about a random axis, 3 a chain with a log
 * piece. Angles scale with amp (rad). */
static void random_turning_motion(exdex_motion_def *d, int kind, double amp, double times[12], double poses[12 * 7],
                                  exdex_motion_def pc[4])
{
    memset(d, 0, sizeof *d);
    if (kind == 0 || kind == 3) {
        double t = 0.0, q[4] = {1, 0, 0, 0}, ax[3] = {urand(-1, 1), urand(-1, 1), urand(-1, 1)};
        for (int i = 0; i < 12; i++) {
            double dq[4], a = urand(-1.0, 1.0) * amp, nq = 0.0, nx;
            times[i] = t;
            t += urand(0.03, 0.1);
            for (int c = 0; c < 3; c++) ax[c] += urand(-0.5, 0.5);
            nx = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
            dq[0] = cos(0.5 * a);
            for (int c = 0; c < 3; c++) dq[1 + c] = sin(0.5 * a) * ax[c] / nx;
            if (i > 0) {
                /* q <- dq q */
                double r[4] = {dq[0] * q[0] - dq[1] * q[1] - dq[2] * q[2] - dq[3] * q[3],
                               dq[0] * q[1] + dq[1] * q[0] + dq[2] * q[3] - dq[3] * q[2],
                               dq[0] * q[2] - dq[1] * q[3] + dq[2] * q[0] + dq[3] * q[1],
                               dq[0] * q[3] + dq[1] * q[2] - dq[2] * q[1] + dq[3] * q[0]};
                memcpy(q, r, sizeof q);
            }
            for (int c = 0; c < 4; c++) nq += q[c] * q[c];
            for (int c = 0; c < 3; c++) poses[7 * i + c] = i == 0 ? 0.0 : poses[7 * (i - 1) + c] + urand(-0.003, 0.003);
            for (int c = 0; c < 4; c++) poses[7 * i + 3 + c] = q[c] / sqrt(nq);
        }
        d->kind = EXDEX_MOTION_SAMPLED;
        d->n_samples = 12;
        d->times = times;
        d->poses = poses;
        d->relative = 1;
        d->tool = 1;
        d->tool_pose[0] = urand(-0.05, 0.05);
        d->tool_pose[1] = urand(-0.05, 0.05);
        d->tool_pose[2] = urand(-0.05, 0.05);
        d->tool_pose[3] = 1.0;
        if (kind == 3) {
            exdex_motion_def c0 = *d;
            memset(pc, 0, 4 * sizeof *pc);
            pc[0].kind = EXDEX_MOTION_REST;
            pc[0].axis[0] = 1.0;
            pc[0].duration = 0.1;
            pc[1] = c0;
            pc[1].relative = 1;
            memset(d, 0, sizeof *d);
            d->kind = EXDEX_MOTION_CHAIN;
            d->axis[0] = 1.0;
            d->n_pieces = 2;
            d->pieces = pc;
            d->allow_jump = 1;   /* the log starts at its own speed */
        }
        return;
    }
    if (kind == 2) {
        d->kind = urand(0, 1) < 0.5 ? EXDEX_MOTION_ASYMMETRIC : EXDEX_MOTION_TRAPEZOID;
        d->rotation = 1;
        for (int c = 0; c < 3; c++) {
            d->axis[c] = urand(-1, 1);
            d->center[c] = urand(-0.05, 0.05);
        }
        d->amplitude = 3.0 * amp;
        d->duration = urand(0.2, 0.6);
        d->beta = urand(0.2, 0.8);
        d->v_max = fabs(d->amplitude) / d->duration * urand(1.1, 1.9);
        return;
    }
    memset(pc, 0, 4 * sizeof *pc);
    pc[0].kind = EXDEX_MOTION_REST;
    pc[0].axis[0] = 1.0;
    pc[0].duration = urand(0.02, 0.1);
    pc[1].kind = EXDEX_MOTION_ASYMMETRIC;
    pc[1].rotation = 1;
    for (int c = 0; c < 3; c++) {
        pc[1].axis[c] = urand(-1, 1);
        pc[1].center[c] = urand(-0.05, 0.05);
    }
    pc[1].amplitude = 3.0 * amp;
    pc[1].duration = urand(0.2, 0.4);
    pc[1].beta = urand(0.2, 0.8);
    pc[2].kind = EXDEX_MOTION_SHAKE;
    pc[2].rotation = 1;
    pc[2].axis[1] = 1.0;
    pc[2].amplitude = amp;
    pc[2].frequency = urand(2.0, 6.0);
    pc[2].duration = 1.0 / pc[2].frequency;
    pc[3].kind = EXDEX_MOTION_SHAKE;
    for (int c = 0; c < 3; c++) pc[3].axis[c] = urand(-1, 1);
    pc[3].amplitude = 0.003;
    pc[3].frequency = urand(2.0, 6.0);
    pc[3].duration = 1.0 / pc[3].frequency;
    d->kind = EXDEX_MOTION_CHAIN;
    d->axis[0] = 1.0;
    d->n_pieces = 4;
    d->pieces = pc;
}

/* motion_frame_box against dense samples: on random blocks of random
 * turning motions every sample's g_B, a0, w, dw (model_frame_at's
 * formulas) lies in the enclosure, and the samples' range covers most of
 * it for most components that move (a dropped term or a shrunk range
 * moves samples out of it). */
EXDEX_TEST(certify_frame_box_holds_dense_samples)
{
    static double times[12], poses[12 * 7];
    exdex_motion_def pc[4], d;
    static const double R0[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0}, p0[3] = {0.01, -0.02, 0.03};
    const double g[3] = {0.0, 0.0, -9.81};
    int n_boxes = 0, n_tight = 0, n_moving = 0, n_tight_log = 0, n_moving_log = 0;
    lcg = 4242;
    for (int s = 0; s < 48; s++) {
        int status;
        const char *bad = NULL;
        exdex_motion *m;
        random_turning_motion(&d, s % 4, urand(0.05, 0.3), times, poses, pc);
        m = exdex_motion_alloc(&d, R0, p0, &status, &bad);
        ENSURE(m != NULL);
        if (!m) continue;
        for (int b = 0; b < 20; b++) {
            double end = exdex_motion_end(m), ta = urand(-0.05, end + 0.05), L = exp(urand(log(1e-4), log(0.2))), tb = ta + L;
            double lo[12], hi[12];
            frame_box fb;
            int ok = motion_frame_box(m, ta, tb, g, &fb);
            ENSURE(ok);
            if (!ok) continue;
            n_boxes++;
            for (int q = 0; q < 12; q++) {
                lo[q] = INFINITY;
                hi[q] = -INFINITY;
            }
            for (int j = 0; j <= 400; j++) {
                double t = j == 400 ? tb : ta + (tb - ta) * j / 400.0, v[12];
                exdex_kinematics k;
                ENSURE(exdex_motion_eval(m, t, &k) == EXDEX_OK);
                ex_mulmtv3(v, k.R, g);
                ex_mulmtv3(v + 3, k.R, k.a);
                ex_mulmtv3(v + 6, k.R, k.w);
                ex_mulmtv3(v + 9, k.R, k.dw);
                for (int q = 0; q < 12; q++) {
                    const ex_iv *iv = (q < 3 ? fb.gB : q < 6 ? fb.a0 : q < 9 ? fb.w : fb.dw) + q % 3;
                    ENSURE(v[q] >= iv->lo && v[q] <= iv->hi);
                    lo[q] = fmin(lo[q], v[q]);
                    hi[q] = fmax(hi[q], v[q]);
                }
            }
            for (int q = 0; q < 12; q++) {
                const ex_iv *iv = (q < 3 ? fb.gB : q < 6 ? fb.a0 : q < 9 ? fb.w : fb.dw) + q % 3;
                double w = iv->hi - iv->lo;
                if (!(hi[q] - lo[q] > 1e-3 * w && hi[q] > lo[q])) continue;
                /* profiles: the samples' range within 1 % of the enclosure; logs (interval arithmetic
                 * through the quaternion's normalisation): a quarter of it */
                if (s % 4 == 1 || s % 4 == 2) {
                    n_moving++;
                    n_tight += hi[q] - lo[q] >= (1.0 - 1e-2) * w;
                } else {
                    n_moving_log++;
                    n_tight_log += hi[q] - lo[q] >= 0.25 * w;
                }
            }
        }
        exdex_motion_free(m);
    }
    ENSURE(n_boxes == 48 * 20);
    ENSURE(n_moving > 1000 && n_tight > 0.8 * n_moving);
    ENSURE(n_moving_log > 1000 && n_tight_log > 0.8 * n_moving_log);
}

/* motion_frame_box_cached against motion_frame_box: on random logs and
 * chains with a log piece (both gripper kinds of random_turning_motion that
 * hold a log), 60 blocks per motion through one cache (random blocks,
 * blocks from knot to knot, blocks inside one knot interval, blocks past
 * the motion's ends; the cache filled by earlier blocks), the two boxes
 * are equal bit for bit, as is the result for a gravity the cache was not
 * made for. */
EXDEX_TEST(certify_cached_frame_box_equals_the_direct_box)
{
    static double times[12], poses[12 * 7];
    exdex_motion_def pc[4], d;
    static const double R0[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0}, p0[3] = {0.01, -0.02, 0.03};
    const double g[3] = {0.0, 0.0, -9.81}, g2[3] = {0.0, -9.81, 0.0};
    int n_cmp = 0;
    lcg = 777;
    for (int s = 0; s < 32; s++) {
        int status, kind = s % 2 ? 3 : 0;
        const char *bad = NULL;
        exdex_motion *m;
        frame_box_cache *fc;
        random_turning_motion(&d, kind, urand(0.05, 0.3), times, poses, pc);
        m = exdex_motion_alloc(&d, R0, p0, &status, &bad);
        fc = motion_frame_cache_new(g);
        ENSURE(m != NULL && fc != NULL);
        if (!m || !fc) {
            exdex_motion_free(m);
            motion_frame_cache_free(fc);
            continue;
        }
        for (int b = 0; b < 60; b++) {
            double end = exdex_motion_end(m), off = kind == 3 ? 0.1 : 0.0, ta, tb;
            const double *gg = b % 10 == 9 ? g2 : g;
            frame_box f1, f2;
            int k0 = (int)urand(0, 10.999), k1 = k0 + 1 + (int)urand(0, 10.999 - k0);
            switch (b % 4) {
            case 0: /* from knot to knot */
                ta = off + times[k0];
                tb = off + times[k1 > 11 ? 11 : k1];
                break;
            case 1: /* inside one knot interval */
                ta = off + times[k0] + urand(0.0, 0.5) * (times[k0 + 1] - times[k0]);
                tb = ta + urand(0.0, 0.5) * (times[k0 + 1] - times[k0]);
                break;
            case 2: /* past an end */
                ta = urand(-0.05, 0.5 * end);
                tb = end + urand(0.0, 0.05);
                break;
            default:
                ta = urand(-0.05, end + 0.05);
                tb = ta + exp(urand(log(1e-4), log(0.5)));
            }
            {
                int ok1 = motion_frame_box(m, ta, tb, gg, &f1), ok2 = motion_frame_box_cached(m, ta, tb, gg, &f2, fc);
                ENSURE(ok1 && ok2);
                if (!(ok1 && ok2)) continue;
            }
            for (int c = 0; c < 3; c++) {
                ENSURE(f1.gB[c].lo == f2.gB[c].lo && f1.gB[c].hi == f2.gB[c].hi);
                ENSURE(f1.a0[c].lo == f2.a0[c].lo && f1.a0[c].hi == f2.a0[c].hi);
                ENSURE(f1.w[c].lo == f2.w[c].lo && f1.w[c].hi == f2.w[c].hi);
                ENSURE(f1.dw[c].lo == f2.dw[c].lo && f1.dw[c].hi == f2.dw[c].hi);
            }
            n_cmp++;
        }
        motion_frame_cache_free(fc);
        exdex_motion_free(m);
    }
    ENSURE(n_cmp == 32 * 60);
    motion_frame_cache_free(NULL);
    ENSURE(motion_frame_cache_new(NULL) == NULL);
}

/* A log's box over a block: across knots it is the box of the whole knot
 * intervals the block meets, bit for bit (random logs, blocks from inside
 * interval k to inside interval l > k against the box from t_k to t_l+1,
 * short of the log's end);
 * inside one interval it is that part's own, inside the whole interval's
 * box and narrower in most of the components that move there. */
EXDEX_TEST(certify_log_box_across_knots_is_the_whole_intervals_box)
{
    static double times[12], poses[12 * 7];
    exdex_motion_def pc[4], d;
    static const double R0[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0}, p0[3] = {0.01, -0.02, 0.03};
    const double g[3] = {0.0, 0.0, -9.81};
    int n_cmp = 0, n_part = 0, n_moving = 0, n_narrow = 0;
    lcg = 919;
    for (int s = 0; s < 24; s++) {
        int status;
        const char *bad = NULL;
        exdex_motion *m;
        random_turning_motion(&d, 0, urand(0.05, 0.3), times, poses, pc);
        m = exdex_motion_alloc(&d, R0, p0, &status, &bad);
        ENSURE(m != NULL);
        if (!m) continue;
        for (int b = 0; b < 40; b++) {
            int k = (int)urand(0, 8.999), l = b % 2 ? k : k + 1 + (int)urand(0, 9.999 - k - 1);
            double ta = times[k] + urand(0.05, 0.45) * (times[k + 1] - times[k]);
            double tb = times[l] + urand(0.55, 0.95) * (times[l + 1] - times[l]);
            frame_box f1, f2;
            const ex_iv *a[4], *w[4];
            int ok1 = motion_frame_box(m, ta, tb, g, &f1), ok2 = motion_frame_box(m, times[k], times[l + 1], g, &f2);
            ENSURE(ok1 && ok2);
            if (!(ok1 && ok2)) continue;
            for (int c = 0; c < 3; c++) {
                a[0] = f1.gB + c, a[1] = f1.a0 + c, a[2] = f1.w + c, a[3] = f1.dw + c;
                w[0] = f2.gB + c, w[1] = f2.a0 + c, w[2] = f2.w + c, w[3] = f2.dw + c;
                for (int q = 0; q < 4; q++) {
                    if (l > k) {
                        ENSURE(a[q]->lo == w[q]->lo && a[q]->hi == w[q]->hi);
                        continue;
                    }
                    ENSURE(a[q]->lo >= w[q]->lo && a[q]->hi <= w[q]->hi);
                    if (w[q]->hi - w[q]->lo > 1e-6 * (fabs(w[q]->lo) + fabs(w[q]->hi))) {
                        n_moving++;
                        n_narrow += a[q]->hi - a[q]->lo < w[q]->hi - w[q]->lo;
                    }
                }
            }
            n_cmp += l > k;
            n_part += l == k;
        }
        exdex_motion_free(m);
    }
    ENSURE(n_cmp == 24 * 20 && n_part == 24 * 20);
    ENSURE(n_moving > 1000 && n_narrow > 0.9 * n_moving);
}

/* Rotation runs in a gripper that turns (logs, chains with turning pieces,
 * Eq. 7 or a trapezoid turning about a random axis: the pieces' bound does
 * not apply off the plate normal): the turning blocks' proofs (the load
 * enclosed over motion_frame_box's frame and the block's angles and rates)
 * against every sample's check, on random scenes around the held box's
 * threshold (the pivot `offset` off the centre of mass, as in
 * certify_proofs_rotation_blocks; the turn's inertial and gravity terms
 * move it), in three seeds, with a falling grip in some. */
EXDEX_TEST(certify_proofs_rotation_turning_blocks)
{
    static double times[12], poses[12 * 7];
    static const double gt[4] = {0.0, 0.3, 0.6, 1.0}, gf[4] = {1.0, 0.8, 0.7, 0.6};
    exdex_motion_def pc[4];
    static const unsigned long seeds[3] = {99, 2024, 31337};
    n_held = n_failed = 0;
    for (int sd = 0; sd < 3; sd++) {
        lcg = seeds[sd];
        for (int s = 0; s < 32; s++) {
            int kind = s % 4, k = (int[]){0, 1, 3, 4}[(s / 4) % 4];
            double ratio = urand(1.2, 5.0), amp = urand(0.03, 0.3) * (urand(0, 1) < 0.5 ? -1.0 : 1.0);
            double offset = urand(0.0, 1.15) * 0.0076520 * sqrt(ratio * ratio - 1.0);
            double dt = methods[k] == EXDEX_METHOD_REGULARISED ? 4e-3 : 1e-3;
            exdex_scene_def d = box(ratio, offset, methods[k]);
            d.dof = EXDEX_DOF_ROTATION;
            random_turning_motion(&d.motion, kind, amp, times, poses, pc);
            if (s % 3 == 2) {
                /* gravity along the plate normal */
                d.gravity[2] = 0.0;
                d.gravity[1] = -9.81;
            }
            if (s % 5 == 4) grip_schedule(&d, gt, gf, EXDEX_GRIP_LINEAR);
            same_certificate(&d, 0.9, dt);
        }
    }
    ENSURE(n_held >= 15 && n_failed >= 15);
}

/* The load at (t, theta, v) as the certificate states it (cert_at_frame
 * with a = 0 and no stop force): P = M kappa - F, kappa the pin's
 * centripetal acceleration -v^2 rho, F the planar model's gravity and
 * frame terms, in patch coordinates. */
static void rotation_load(const exdex_model *m, double t, double th, double v, double b[3])
{
    frame f;
    exdex_kinematics k;
    double rho[2] = {cos(th) * m->c[0] - sin(th) * m->c[1], sin(th) * m->c[0] + cos(th) * m->c[1]};
    double qf[3] = {m->pivot[0] + rho[0], m->pivot[1] + rho[1], th}, vf[3] = {-v * rho[1], v * rho[0], v}, F[3], P[3];
    double cs[2] = {cos(th), sin(th)};
    ENSURE(model_frame_at(m, t, &f, &k) == EXDEX_OK);
    model_force_planar(m, &f, qf, vf, F);
    P[0] = -m->m * v * v * rho[0] - F[0];
    P[1] = -m->m * v * v * rho[1] - F[1];
    P[2] = -F[2];
    model_patch_of_gen(m, cs, P, b);
}

/* The same for a translation run at slide coordinate q and rate v: the
 * centre of mass on the slide axis, the body's angle fixed. */
static void translation_load(const exdex_model *m, double t, double q, double v, double b[3])
{
    frame f;
    exdex_kinematics k;
    double qq[3] = {q, 0.0, 0.0}, r[3], th, qf[3], vf[3] = {v * m->d[0], v * m->d[1], 0.0}, F[3], P[3], cs[2];
    pose_com(m, qq, r, &th);
    qf[0] = r[0];
    qf[1] = r[1];
    qf[2] = th;
    cs[0] = cos(th);
    cs[1] = sin(th);
    ENSURE(model_frame_at(m, t, &f, &k) == EXDEX_OK);
    model_force_planar(m, &f, qf, vf, F);
    for (int c = 0; c < 3; c++) P[c] = -F[c];
    model_patch_of_gen(m, cs, P, b);
}

/* certify_turning_load against dense samples: on random blocks of random
 * turning motions, random angle (slide coordinate) and rate ranges of a
 * rotation (translation) run, the load of every sample (times, angles or
 * coordinates and rates over the ranges, their ends included) lies in the
 * enclosure, and for most components that move the samples cover at least
 * a quarter of it (a dropped Coriolis, Euler, centripetal or gyroscopic
 * term moves samples out of it). */
EXDEX_TEST(certify_turning_load_holds_dense_samples)
{
    static double times[12], poses[12 * 7];
    exdex_motion_def pc[4];
    int n_boxes = 0, n_moving = 0, n_cover = 0;
    lcg = 5151;
    for (int s = 0; s < 64; s++) {
        const char *bad = NULL;
        int status, rot = s < 32;
        exdex_scene_def d = box(3.0, urand(-0.02, 0.02), EXDEX_METHOD_IMPLICIT);
        exdex_model *m;
        d.dof = rot ? EXDEX_DOF_ROTATION : EXDEX_DOF_TRANSLATION;
        d.patch_center[1] = urand(-0.02, 0.02);
        d.inertia[1] = d.inertia[3] = urand(-1e-4, 1e-4);
        d.inertia[2] = d.inertia[6] = urand(-1e-4, 1e-4);
        random_turning_motion(&d.motion, s % 4, urand(0.1, 0.5), times, poses, pc);
        if (s % 2) {
            d.gravity[2] = 0.0;
            d.gravity[1] = -9.81;
        }
        m = exdex_model_alloc(&d, &status, &bad);
        ENSURE(m != NULL);
        if (!m) continue;
        for (int bk = 0; bk < 12; bk++) {
            double end = exdex_motion_end(m->motion), ta = urand(0.0, end), tb = ta + exp(urand(log(2e-3), log(5e-2)));
            double th0 = urand(-3.0, 3.0) * (rot ? 1.0 : 0.01), v0 = urand(-8.0, 8.0) * (rot ? 1.0 : 0.01);
            double lo[3] = {INFINITY, INFINITY, INFINITY};
            double hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            double sc = rot ? 1.0 : 0.01;
            ex_iv th = {th0, th0 + (bk % 3 ? urand(0.0, 0.3) * sc : 0.0)};
            ex_iv v = {v0, v0 + (bk % 3 == 1 ? urand(0.0, 2.0) * sc : 0.0)}, b[3];
            int ok = certify_turning_load(m, ta, tb, th, v, b);
            ENSURE(ok);
            if (!ok) continue;
            n_boxes++;
            for (int j = 0; j <= 60; j++) {
                double t = ta + (tb - ta) * j / 60.0;
                for (int a = 0; a < 3; a++)
                    for (int c = 0; c < 3; c++) {
                        double x[3], tt = th.lo + (th.hi - th.lo) * a / 2.0, vv = v.lo + (v.hi - v.lo) * c / 2.0;
                        if (rot) rotation_load(m, t, tt, vv, x);
                        else translation_load(m, t, tt, vv, x);
                        for (int q = 0; q < 3; q++) {
                            ENSURE(x[q] >= b[q].lo && x[q] <= b[q].hi);
                            lo[q] = fmin(lo[q], x[q]);
                            hi[q] = fmax(hi[q], x[q]);
                        }
                    }
            }
            for (int q = 0; q < 3; q++) {
                double w = b[q].hi - b[q].lo;
                if (!(hi[q] - lo[q] > 1e-3 * w)) continue;
                n_moving++;
                n_cover += hi[q] - lo[q] >= 0.25 * w;
            }
        }
        exdex_model_free(m);
        if (s == 31) {
            /* the rotation runs' share: as many again for the translation runs */
            ENSURE(n_moving > 600 && n_cover > 0.6 * n_moving);
            n_moving = n_cover = 0;
        }
    }
    ENSURE(n_boxes == 64 * 12);
    ENSURE(n_moving > 600 && n_cover > 0.6 * n_moving);
}

/* The run certified as it goes: bad arguments, a planar model (nothing
 * neglected: exdex_simulate's run), and a reduction that fails at t = 0
 * (the box, 6 cm off its pads at 1.5 m g: gravity's moment beyond
 * the torsional capacity from the start, tests/scenarios/test_certify.py's
 * closed form) ending on sample 0. */
EXDEX_TEST(certify_as_it_goes_edges)
{
    const char *bad = NULL;
    int status;
    exdex_scene_def d = box(1.5, 0.06, EXDEX_METHOD_IMPLICIT);
    exdex_model *m = exdex_model_alloc(&d, &status, &bad), *mp;
    sim_run r;
    exdex_certificate c;
    exdex_stats st;
    size_t nw = 7;
    ENSURE(m != NULL);
    if (!m) return;
    ENSURE(sim_run_def(&d, 0.3, 1e-3, &r) == EXDEX_OK);
    ENSURE(exdex_simulate_certified(NULL, 0.3, 1e-3, &r.tr, &st, &c, &nw) == EXDEX_EINVAL);
    ENSURE(exdex_simulate_certified(m, 0.3, 1e-3, &r.tr, &st, NULL, &nw) == EXDEX_EINVAL);
    ENSURE(exdex_simulate_certified(m, 0.3, 1e-3, &r.tr, &st, &c, NULL) == EXDEX_EINVAL);
    ENSURE(exdex_simulate_certified(m, 0.3, 2e-3, &r.tr, &st, &c, &nw) == EXDEX_EINVAL);   /* out->n */
    ENSURE(nw == 7);
    ENSURE(exdex_simulate_certified(m, 0.3, 1e-3, &r.tr, &st, &c, &nw) == EXDEX_OK);
    ENSURE(!c.holds && c.valid_until == 0.0 && c.first_bad == 0 && nw == 1 && r.tr.t[0] == 0.0);
    ENSURE(st.steps == 0 && st.stick_steps == 0);
    sim_run_free(&r);
    d.dof = EXDEX_DOF_PLANAR;
    mp = exdex_model_alloc(&d, &status, &bad);
    ENSURE(mp != NULL);
    if (mp) {
        sim_run a;
        ENSURE(sim_run_def(&d, 0.3, 1e-3, &r) == EXDEX_OK && sim_run_def(&d, 0.3, 1e-3, &a) == EXDEX_OK);
        ENSURE(exdex_simulate_certified(mp, 0.3, 1e-3, &r.tr, &st, &c, &nw) == EXDEX_OK);
        ENSURE(c.reduced == 0 && c.holds && nw == r.tr.n);
        ENSURE(memcmp(r.tr.q, a.tr.q, 3 * r.tr.n * sizeof(double)) == 0);
        ENSURE(memcmp(&st, &a.st, sizeof st) == 0);
        sim_run_free(&a);
        sim_run_free(&r);
        exdex_model_free(mp);
    }
    exdex_model_free(m);
}
