/* test_certify.c -- the certificate's proofs per piece against the check of
 * every sample: exdex_certify skips the samples whose mode it has proven to
 * hold in their piece (a constant load, or a bound on a turning gripper's
 * load); exdex_certify_samples evaluates each of them. Both must give the
 * same certificate, on scenes on both sides of their thresholds, in every
 * method that solves them.
 * twin: tests/test_certify.py (the same subject through the Python API: closed forms) */
#include "check.h"
#include "sim_run.h"

#include <stdlib.h>
#include <string.h>

static int n_held, n_failed;

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
    n_held += a.holds;
    n_failed += !a.holds;
    sim_run_free(&r);
    exdex_model_free(m);
}

static const int methods[5] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EXPLICIT, EXDEX_METHOD_ANALYTIC,
                                EXDEX_METHOD_EVENT, EXDEX_METHOD_REGULARISED};

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
                d.grip_n = 4;
                d.grip_times = times;
                d.grip_forces = forces;
                d.grip_kind = kinds[g];
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
