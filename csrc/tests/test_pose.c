/* test_pose.c -- pose.h: the centre-of-mass pose of each kind of
 * coordinates against hand geometry (a slide along the axis, the planar
 * coordinates themselves, quarter turns about the pin). */
#include "check.h"
#include "sim_run.h"
#include "../model.h"
#include "../pose.h"

#include <math.h>

/* Translation: r(q) - r(q0) = (q - q0) slide_axis, theta fixed; planar:
 * r = (x, y), theta = q[2]. */
EXDEX_TEST(pose_com_translation_and_planar)
{
    exdex_scene_def d = scene_vertical(0.2, 2.0);
    int status;
    const double ax[2] = {0.6, 0.8};
    double q0[3], v0[3], r0[3], r1[3], th0, th1, q1[3] = {0.0, 0.0, 0.0};
    d.slide_axis[0] = ax[0];
    d.slide_axis[1] = ax[1];
    exdex_model *m = exdex_model_alloc(&d, &status, NULL);
    ENSURE(m != NULL);
    if (m) {
        model_initial_state(m, q0, v0);
        pose_com(m, q0, r0, &th0);
        q1[0] = q0[0] + 0.37;
        pose_com(m, q1, r1, &th1);
        ENSURE_CLOSE(r1[0] - r0[0], 0.37 * ax[0], 1e-15);
        ENSURE_CLOSE(r1[1] - r0[1], 0.37 * ax[1], 1e-15);
        ENSURE(r0[2] == 0.0 && r1[2] == 0.0 && th1 == th0);
        ENSURE(v0[0] == 0.0);
    }
    exdex_model_free(m);

    d = scene_vertical(0.2, 2.0);
    d.dof = EXDEX_DOF_PLANAR;
    d.q0[0] = 0.01;
    d.q0[1] = -0.02;
    d.q0[2] = 0.3;
    scene_rect(&d, 0.02, 0.03);
    m = exdex_model_alloc(&d, &status, NULL);
    ENSURE(m != NULL && exdex_model_ndof(m) == 3);
    if (m) {
        double q[3];
        model_initial_state(m, q, v0);
        ENSURE(q[0] == 0.01 && q[1] == -0.02 && q[2] == 0.3);
        pose_com(m, q, r0, &th0);
        ENSURE(r0[0] == 0.01 && r0[1] == -0.02 && r0[2] == 0.0 && th0 == 0.3);
    }
    exdex_model_free(m);
}

/* Rotation about the pin: the centre of mass stays at |patch_center| from
 * the pivot (found as the mean of the poses a quarter turn apart), and a
 * quarter turn of q turns r - pivot by a quarter turn. */
EXDEX_TEST(pose_com_rotation_turns_about_the_pin)
{
    exdex_scene_def d = scene_vertical(0.2, 2.0);
    int status;
    d.dof = EXDEX_DOF_ROTATION;
    d.patch_center[0] = 0.003;
    d.patch_center[1] = -0.004;   /* |c| = 0.005 */
    exdex_model *m = exdex_model_alloc(&d, &status, NULL);
    ENSURE(m != NULL);
    if (m) {
        double r[4][3], th, p[2] = {0.0, 0.0};
        for (int k = 0; k < 4; k++) {
            double q[3] = {0.2 + k * 1.5707963267948966, 0.0, 0.0};   /* quarter turns */
            pose_com(m, q, r[k], &th);
            ENSURE(th == q[0]);
            p[0] += r[k][0] / 4;
            p[1] += r[k][1] / 4;
        }
        for (int k = 0; k < 4; k++) {
            double a[2] = {r[k][0] - p[0], r[k][1] - p[1]};
            double b[2] = {r[(k + 1) % 4][0] - p[0], r[(k + 1) % 4][1] - p[1]};
            ENSURE_CLOSE(hypot(a[0], a[1]), 0.005, 1e-15);
            ENSURE_CLOSE(b[0], -a[1], 1e-15);   /* Rz(pi/2) a */
            ENSURE_CLOSE(b[1], a[0], 1e-15);
        }
    }
    exdex_model_free(m);
}
