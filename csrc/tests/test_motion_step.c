/* test_motion_step.c -- the one-step motion of a prescribed gripper pose
 * (motion_step_set, motion.c), against closed forms:
 *  - a rotation at constant rate w about a fixed axis a: the quaternion
 *    n(t) = (cos(w t / 2), sin(w t / 2) a) has components whose fourth
 *    derivative is at most (w / 2)^4; the cubic Hermite interpolant of such
 *    a component on a step h errs by at most h^4 / 384 (w / 2)^4 in value
 *    and (sqrt 3 / 216) h^3 (w / 2)^4 in slope (Birkhoff-Priver bounds),
 *    which the normalisation changes only at higher order: R to a few
 *    times the first, the angular velocity (2 vec(n' n*)) to a few times
 *    the second;
 *  - a position cubic in time: reproduced with its acceleration exactly;
 *  - the secants: the mean velocity (p1 - p0) / h and, for R1 = Rot(a, phi)
 *    R0, the angular velocity (phi / h) a. */
#include "check.h"
#include "../model.h"

#include <math.h>
#include <string.h>

static void axis_rot(double R[9], const double a[3], double phi)
{
    double c = cos(phi), s = sin(phi), C = 1.0 - c;
    R[0] = c + a[0] * a[0] * C;        R[1] = a[0] * a[1] * C - a[2] * s; R[2] = a[0] * a[2] * C + a[1] * s;
    R[3] = a[1] * a[0] * C + a[2] * s; R[4] = c + a[1] * a[1] * C;        R[5] = a[1] * a[2] * C - a[0] * s;
    R[6] = a[2] * a[0] * C - a[1] * s; R[7] = a[2] * a[1] * C + a[0] * s; R[8] = c + a[2] * a[2] * C;
}

EXDEX_TEST(motion_step_constant_rate_rotation_and_cubic_position)
{
    const double a[3] = {2.0 / 7.0, 3.0 / 7.0, 6.0 / 7.0}, w = 3.0, h = 0.05, t0 = 0.4;
    /* position p(t) = P0 + B u + C u^2 + D u^3, u = t - t0 */
    const double P0[3] = {0.1, -0.2, 0.3}, B[3] = {0.5, 0.0, -1.0}, Cc[3] = {2.0, 1.0, 0.0}, D[3] = {-3.0, 4.0, 1.0};
    double R1[9], p1[3], v1[3], w1[3], eR = 4.0 * pow(h, 4) / 384.0 * pow(w / 2.0, 4),
           ew = 4.0 * 2.0 * sqrt(3.0) / 216.0 * pow(h, 3) * pow(w / 2.0, 4);
    exdex_kinematics k0, k, k1;
    exdex_motion *m = motion_step_alloc();
    ENSURE(m != NULL);
    if (!m) return;
    memset(&k0, 0, sizeof k0);
    axis_rot(k0.R, a, 0.7);
    for (int j = 0; j < 3; j++) {
        k0.p[j] = P0[j];
        k0.v[j] = B[j];
        k0.w[j] = w * a[j];
    }
    {
        double Q[9];
        axis_rot(Q, a, w * h);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                R1[3 * i + j] = Q[3 * i] * k0.R[j] + Q[3 * i + 1] * k0.R[3 + j] + Q[3 * i + 2] * k0.R[6 + j];
    }
    for (int j = 0; j < 3; j++) {
        p1[j] = P0[j] + B[j] * h + Cc[j] * h * h + D[j] * h * h * h;
        v1[j] = B[j] + 2.0 * Cc[j] * h + 3.0 * D[j] * h * h;
        w1[j] = w * a[j];
    }
    ENSURE(motion_step_set(m, t0, t0 + h, &k0, R1, p1, v1, w1, &k1) == EXDEX_OK);
    for (int i = 0; i <= 8; i++) {
        double u = h * i / 8.0, Re[9], Q[9];
        ENSURE(exdex_motion_eval(m, t0 + u, &k) == EXDEX_OK);
        for (int j = 0; j < 3; j++) {
            ENSURE(fabs(k.p[j] - (P0[j] + B[j] * u + Cc[j] * u * u + D[j] * u * u * u)) <= 1e-15);
            ENSURE(fabs(k.v[j] - (B[j] + 2.0 * Cc[j] * u + 3.0 * D[j] * u * u)) <= 1e-13);
            ENSURE(fabs(k.a[j] - (2.0 * Cc[j] + 6.0 * D[j] * u)) <= 1e-10);
            ENSURE(fabs(k.w[j] - w * a[j]) <= ew + 1e-14);
        }
        axis_rot(Q, a, w * u);
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++)
                Re[3 * r + c] = Q[3 * r] * k0.R[c] + Q[3 * r + 1] * k0.R[3 + c] + Q[3 * r + 2] * k0.R[6 + c];
        for (int j = 0; j < 9; j++) ENSURE(fabs(k.R[j] - Re[j]) <= eR + 1e-15);
    }
    /* the bounds are small against what they bound: the step's turn w h
     * (0.15 rad) and the rate w */
    ENSURE(eR < 1e-5 * w * h && ew < 1e-4 * w);
    /* the secants */
    ENSURE(motion_step_set(m, t0, t0 + h, &k0, R1, p1, NULL, NULL, &k1) == EXDEX_OK);
    for (int j = 0; j < 3; j++) {
        ENSURE_CLOSE(k1.v[j], (p1[j] - P0[j]) / h, 1e-13);
        ENSURE(fabs(k1.w[j] - w * a[j]) <= 1e-12);
    }
    ENSURE(exdex_motion_eval(m, t0 + h, &k) == EXDEX_OK);
    for (int j = 0; j < 9; j++) ENSURE(fabs(k.R[j] - R1[j]) <= 1e-15);
    /* bad input: the motion unchanged */
    ENSURE(motion_step_set(m, t0, t0, &k0, R1, p1, NULL, NULL, NULL) == EXDEX_EINVAL);
    R1[0] += 1e-6;
    ENSURE(motion_step_set(m, t0, t0 + h, &k0, R1, p1, NULL, NULL, NULL) == EXDEX_EINVAL);
    ENSURE(exdex_motion_eval(m, t0 + h, &k) == EXDEX_OK && fabs(k.R[0] - (R1[0] - 1e-6)) <= 1e-15);
    exdex_motion_free(m);
}
