/* test_motion.c -- prescribed gripper motions (csrc/motion.c).
 *
 * References used here, never the code's own output:
 *  - closed forms of the paper's Eqs. 7-9 and of the trapezoidal profile,
 *    worked out by hand in the comments;
 *  - an independent numerical double integration of Eq. 7 (Heaviside form);
 *  - central finite differences of the evaluated pose;
 *  - analytic trajectories (position, rotation matrix, angular velocity and
 *    acceleration derived by hand) sampled and fed to the spline motion, with
 *    tolerances from the cubic-spline error bounds of Hall & Meyer (1976). */
#include "check.h"
#include "../exdex.h"

#include <float.h>
#include <string.h>

#define PI 3.14159265358979323846

/* ---------------------------------------------------------------- helpers */

static exdex_motion_def zero_def(void)
{
    exdex_motion_def d;
    memset(&d, 0, sizeof d);
    d.kind = EXDEX_MOTION_REST;
    return d;
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(double r[3], const double a[3], const double b[3])
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }

static double dist3(const double a[3], const double b[3])
{
    double d[3] = {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
    return norm3(d);
}

static void matmul3(double C[9], const double A[9], const double B[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            C[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

/* max |R R^T - I| and det R */
static double orth_err(const double R[9])
{
    double e = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = fabs(dot3(R + 3 * i, R + 3 * j) - (i == j));
            if (d > e) e = d;
        }
    return e;
}

static double det3(const double R[9])
{
    return R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6])
         + R[2] * (R[3] * R[7] - R[4] * R[6]);
}

/* vee((Rp - Rm)/(2h) R^T): angular velocity in A from a central difference */
static void fd_omega(double w[3], const double Rp[9], const double Rm[9], const double R[9],
                     double h)
{
    double D[9], Rt[9], S[9];
    for (int i = 0; i < 9; i++) D[i] = (Rp[i] - Rm[i]) / (2.0 * h);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) Rt[3 * i + j] = R[3 * j + i];
    matmul3(S, D, Rt);
    w[0] = 0.5 * (S[7] - S[5]);
    w[1] = 0.5 * (S[2] - S[6]);
    w[2] = 0.5 * (S[3] - S[1]);
}

/* Eq. 7 written literally with a right-continuous Heaviside H(0) = 1 and
 * Eq. 9 for a_H, a_L -- the test's own transcription, independent of motion.c */
static double heav(double x) { return x >= 0.0 ? 1.0 : 0.0; }

static double eq7_accel(double X1, double T, double beta, double t)
{
    double aH = 2.0 * X1 / (beta * T * T), aL = 2.0 * X1 / ((beta - 1.0) * T * T);
    double a = aH * heav(t) + (aL - aH) * heav(t - beta * T) + (aH - aL) * heav(t - (2.0 - beta) * T);
    return t >= 2.0 * T ? 0.0 : a;  /* Eq. 7 is used on [0, 2T]: rest afterwards */
}

/* Double integration on a uniform grid of N cells over [0, 2T]: velocity by
 * the midpoint rule of a (exact for piecewise-constant a when the switches
 * fall on grid nodes, as for the N used below), position by the trapezoid
 * rule of v (exact for piecewise-linear v). Compares against the profile at
 * every node and returns the largest |s - s_num|. */
static double eq7_integration_error(double X1, double T, double beta, int N, double *max_sd_err)
{
    double dt = 2.0 * T / N, v = 0.0, s = 0.0, err = 0.0, verr = 0.0;
    for (int i = 0; i <= N; i++) {
        double t = i * dt, sp, sdp, sddp;
        exdex_profile_asymmetric(X1, T, beta, t, &sp, &sdp, &sddp);
        if (fabs(sp - s) > err) err = fabs(sp - s);
        if (fabs(sdp - v) > verr) verr = fabs(sdp - v);
        {
            double vn = v + eq7_accel(X1, T, beta, t + 0.5 * dt) * dt;
            s += 0.5 * (v + vn) * dt;
            v = vn;
        }
    }
    *max_sd_err = verr;
    return err;
}

/* ----------------------------------------------------- Eq. 7 profile */

EXDEX_TEST(motion_asymmetric_profile_fig3)
{
    /* Fig. 3 of the paper: beta 0.9, X1 0.1 m, T 0.5 s.
     * Eq. 9a: a_H = 2 X1/(beta T^2) = 0.2/0.225 = 8/9 m/s^2;
     * Eq. 9b: a_L = 2 X1/((beta - 1) T^2) = 0.2/(-0.025) = -8 m/s^2. */
    const double X1 = 0.1, T = 0.5, beta = 0.9;
    double s, sd, sdd, aH, aL;

    exdex_profile_asymmetric(X1, T, beta, 0.1, &s, &sd, &aH);
    exdex_profile_asymmetric(X1, T, beta, 0.5, &s, &sd, &aL);
    ENSURE_CLOSE(aH, ref("motion_fig3_a_H"), 1e-15);
    ENSURE_CLOSE(aL, ref("motion_fig3_a_L"), 1e-14);
    report("motion_fig3_a_H", aH);
    report("motion_fig3_a_L", aL);
    /* Eq. 8 from the accelerations the profile actually uses */
    ENSURE_CLOSE(0.5 * aH * beta * beta * T * T * (1.0 - aH / aL), X1, 1e-16);

    /* s(T) = X1 at rest, s(2T) = 0 at rest */
    exdex_profile_asymmetric(X1, T, beta, T, &s, &sd, &sdd);
    ENSURE_CLOSE(s, X1, 1e-16);
    ENSURE_SMALL(sd, 1e-16);
    exdex_profile_asymmetric(X1, T, beta, 2.0 * T, &s, &sd, &sdd);
    ENSURE(s == 0.0 && sd == 0.0 && sdd == 0.0);
    exdex_profile_asymmetric(X1, T, beta, nextafter(2.0 * T, 0.0), &s, &sd, &sdd);
    ENSURE_SMALL(s, 1e-16);
    ENSURE_SMALL(sd, 1e-14);
    ENSURE_CLOSE(sdd, aH, 1e-15);

    /* closed-form points: s(0.25) = a_H 0.25^2 / 2 = 1/36 (phase 1);
     * s(0.52) = X1 + a_L (0.02)^2 / 2 = 0.0984 (phase 2, vertex at T);
     * s(0.75) = s(2T - 0.75) = s(0.25) = 1/36 (phase 3 mirrors phase 1) */
    exdex_profile_asymmetric(X1, T, beta, 0.25, &s, &sd, &sdd);
    ENSURE_CLOSE(s, ref("motion_fig3_s_0p25"), 1e-16);
    ENSURE_CLOSE(sd, 8.0 / 9.0 * 0.25, 1e-15);
    report("motion_fig3_s_0p25", s);
    exdex_profile_asymmetric(X1, T, beta, 0.52, &s, &sd, &sdd);
    ENSURE_CLOSE(s, ref("motion_fig3_s_0p52"), 1e-15);
    ENSURE_CLOSE(sd, -8.0 * 0.02, 1e-14);
    report("motion_fig3_s_0p52", s);
    exdex_profile_asymmetric(X1, T, beta, 0.75, &s, &sd, &sdd);
    ENSURE_CLOSE(s, 1.0 / 36.0, 1e-15);
    ENSURE_CLOSE(sd, -8.0 / 9.0 * 0.25, 1e-15);
    ENSURE_CLOSE(sdd, 8.0 / 9.0, 1e-15);

    /* before the start */
    exdex_profile_asymmetric(X1, T, beta, -1e-3, &s, &sd, &sdd);
    ENSURE(s == 0.0 && sd == 0.0 && sdd == 0.0);
}

EXDEX_TEST(motion_asymmetric_profile_phases)
{
    /* For several (X1, T, beta): sdd equals a_H / a_L (Eq. 9) inside each
     * phase, right-continuous at the switches, and s, sd are continuous
     * across the switches: the jump over one ulp of time is bounded by
     * |sd| dt + |a| dt (tiny), far below 1e-12. */
    const double cases[][3] = {{0.1, 0.5, 0.9}, {-0.3, 2.0, 0.3}, {100.0 * PI / 180.0, 3.0, 0.7},
                               {1e-3, 0.05, 0.5}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double X1 = cases[c][0], T = cases[c][1], beta = cases[c][2];
        double aH = 2.0 * X1 / (beta * T * T), aL = 2.0 * X1 / ((beta - 1.0) * T * T);
        double sw[3] = {beta * T, (2.0 - beta) * T, 2.0 * T};
        double sdd_right[3] = {aL, aH, 0.0};
        double scale = fabs(X1);
        for (int k = 0; k < 3; k++) {
            double sl, sdl, sddl, sr, sdr, sddr;
            exdex_profile_asymmetric(X1, T, beta, nextafter(sw[k], 0.0), &sl, &sdl, &sddl);
            exdex_profile_asymmetric(X1, T, beta, sw[k], &sr, &sdr, &sddr);
            ENSURE_CLOSE(sl, sr, 1e-12 * scale);
            ENSURE_CLOSE(sdl, sdr, 1e-12 * scale / T);
            ENSURE_CLOSE(sddr, sdd_right[k], 1e-12 * fabs(aL));
        }
        for (int i = 0; i < 200; i++) {
            double t = (i + 0.5) * 2.0 * T / 200.0, s, sd, sdd;
            double want = (t < beta * T || t >= (2.0 - beta) * T) ? aH : aL;
            exdex_profile_asymmetric(X1, T, beta, t, &s, &sd, &sdd);
            ENSURE_CLOSE(sdd, want, 1e-12 * fabs(aL));
        }
        /* peak and rest values: s(T) = X1, sd(T) = 0, sd(beta T) = 2 X1 / T */
        {
            double s, sd, sdd;
            exdex_profile_asymmetric(X1, T, beta, T, &s, &sd, &sdd);
            ENSURE_CLOSE(s, X1, 1e-14 * scale);
            ENSURE_SMALL(sd, 1e-14 * scale / T);
            exdex_profile_asymmetric(X1, T, beta, beta * T, &s, &sd, &sdd);
            ENSURE_CLOSE(sd, 2.0 * X1 / T, 1e-13 * scale / T);
            ENSURE_CLOSE(s, beta * X1, 1e-14 * scale);
        }
    }
}

EXDEX_TEST(motion_asymmetric_profile_vs_quadrature)
{
    /* Independent double integration of the literal Eq. 7 (see
     * eq7_integration_error). N = 20000 cells over 2T puts beta T and
     * (2 - beta) T on nodes for beta = 0.9, 0.7, 0.35, so the only error is
     * rounding: ~N eps |s| < 1e-10 |X1|. */
    const double cases[][3] = {{0.1, 0.5, 0.9}, {-1.745, 3.0, 0.7}, {0.02, 0.2, 0.35}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        double verr, err = eq7_integration_error(cases[c][0], cases[c][1], cases[c][2], 20000, &verr);
        ENSURE_SMALL(err, 1e-10 * fabs(cases[c][0]));
        ENSURE_SMALL(verr, 1e-10 * fabs(cases[c][0]) / cases[c][1]);
    }
}

EXDEX_TEST(motion_profile_bad_arguments)
{
    /* out-of-range arguments give NaN, never a plausible number */
    double s, sd, sdd;
    exdex_profile_asymmetric(0.1, 0.5, 1.0, 0.1, &s, &sd, &sdd);
    ENSURE(isnan(s) && isnan(sd) && isnan(sdd));
    exdex_profile_asymmetric(0.1, 0.0, 0.5, 0.1, &s, &sd, &sdd);
    ENSURE(isnan(s));
    exdex_profile_trapezoid(0.05, 0.5, 0.09, 0.1, &s, &sd, &sdd);  /* < |X1|/T = 0.1 */
    ENSURE(isnan(s) && isnan(sd) && isnan(sdd));
    exdex_profile_trapezoid(0.05, 0.5, 0.21, 0.1, &s, &sd, &sdd);  /* > 2|X1|/T = 0.2 */
    ENSURE(isnan(s));
    exdex_profile_trapezoid(0.05, -0.5, 0.12, 0.1, &s, &sd, &sdd);
    ENSURE(isnan(s));
    /* zero amplitude trapezoid is the rest profile */
    exdex_profile_trapezoid(0.0, 0.5, 0.0, 0.1, &s, &sd, &sdd);
    ENSURE(s == 0.0 && sd == 0.0 && sdd == 0.0);
}

/* ------------------------------------------------------- trapezoid */

EXDEX_TEST(motion_trapezoid_profile_fig4)
{
    /* Fig. 4 of the paper: V_max 0.12 m/s, X1 0.05 m, T 0.5 s.
     * t_a = T - X1/V = 0.5 - 0.05/0.12 = 1/12 s; accel = V/t_a = 1.44 m/s^2;
     * s(t_a) = V t_a / 2 = 0.005 m; s(T/2) = X1/2 = 0.025 m (symmetry);
     * s(T) = X1. */
    const double X1 = 0.05, T = 0.5, V = 0.12;
    double s, sd, sdd;
    exdex_profile_trapezoid(X1, T, V, 0.5 / 12.0, &s, &sd, &sdd);  /* mid-ramp */
    ENSURE_CLOSE(sdd, ref("motion_fig4_accel"), 1e-13);
    report("motion_fig4_accel", sdd);
    exdex_profile_trapezoid(X1, T, V, 1.0 / 12.0, &s, &sd, &sdd);
    ENSURE_CLOSE(s, ref("motion_fig4_s_t_a"), 1e-16);
    ENSURE_CLOSE(sd, V, 1e-15);  /* v_max reached */
    ENSURE(sdd == 0.0);          /* right-continuous: cruise starts at t_a */
    report("motion_fig4_s_t_a", s);
    exdex_profile_trapezoid(X1, T, V, 0.25, &s, &sd, &sdd);
    ENSURE_CLOSE(s, ref("motion_fig4_s_half"), 1e-16);
    ENSURE_CLOSE(sd, V, 1e-16);
    report("motion_fig4_s_half", s);
    exdex_profile_trapezoid(X1, T, V, T, &s, &sd, &sdd);
    ENSURE(s == X1 && sd == 0.0 && sdd == 0.0);
    exdex_profile_trapezoid(X1, T, V, nextafter(T, 0.0), &s, &sd, &sdd);
    ENSURE_CLOSE(s, X1, 1e-16);
    ENSURE_SMALL(sd, 1e-14);
    ENSURE_CLOSE(sdd, -1.44, 1e-13);
    /* decel ramp: s(T - 0.05) = X1 - accel 0.05^2 / 2 = 0.05 - 0.0018 */
    exdex_profile_trapezoid(X1, T, V, T - 0.05, &s, &sd, &sdd);
    ENSURE_CLOSE(s, 0.0482, 1e-15);
    ENSURE_CLOSE(sd, 1.44 * 0.05, 1e-14);
}

EXDEX_TEST(motion_trapezoid_profile_limits)
{
    /* ta = 0 (v_max = |X1|/T): constant speed s = X1 t / T.
     * triangle (v_max = 2|X1|/T): t_a = T/2, accel = 4|X1|/T^2,
     * s(T/2) = X1/2 with sd = v_max; s(T/4) = accel (T/4)^2 / 2 = X1/8.
     * Negative X1 mirrors everything. */
    const double T = 0.8;
    for (int sign = -1; sign <= 1; sign += 2) {
        double X1 = 0.3 * sign, s, sd, sdd;
        for (int i = 0; i < 10; i++) {
            double t = 0.08 * i;
            exdex_profile_trapezoid(X1, T, fabs(X1) / T, t, &s, &sd, &sdd);
            ENSURE_CLOSE(s, X1 * t / T, 1e-15);
            ENSURE_CLOSE(sd, X1 / T, 1e-15);
            ENSURE(sdd == 0.0);
        }
        exdex_profile_trapezoid(X1, T, 2.0 * fabs(X1) / T, T / 4.0, &s, &sd, &sdd);
        ENSURE_CLOSE(s, X1 / 8.0, 1e-15);
        ENSURE_CLOSE(sdd, 4.0 * X1 / (T * T), 1e-14);
        exdex_profile_trapezoid(X1, T, 2.0 * fabs(X1) / T, T / 2.0, &s, &sd, &sdd);
        ENSURE_CLOSE(s, X1 / 2.0, 1e-15);
        ENSURE_CLOSE(sd, 2.0 * X1 / T, 1e-15);
        ENSURE_CLOSE(sdd, -4.0 * X1 / (T * T), 1e-14);
        exdex_profile_trapezoid(X1, T, 2.0 * fabs(X1) / T, 0.75 * T, &s, &sd, &sdd);
        ENSURE_CLOSE(s, X1 - X1 / 8.0, 1e-15);
        /* general trapezoid, closed form at t_a and T/2 */
        {
            double V = 1.5 * fabs(X1) / T, ta = T - fabs(X1) / V;
            exdex_profile_trapezoid(X1, T, V, ta, &s, &sd, &sdd);
            ENSURE_CLOSE(s, sign * V * ta / 2.0, 1e-15);
            ENSURE_CLOSE(sd, sign * V, 1e-15);
            exdex_profile_trapezoid(X1, T, V, T / 2.0, &s, &sd, &sdd);
            ENSURE_CLOSE(s, X1 / 2.0, 1e-15);
            exdex_profile_trapezoid(X1, T, V, 2.0 * T, &s, &sd, &sdd);
            ENSURE(s == X1 && sd == 0.0);
        }
    }
}

/* ------------------------------------------------------ rigid motions */

/* a rotation matrix: B y up (B x = A x, B y = A z, B z = -A y) */
static const double R_YUP[9] = {1, 0, 0, 0, 0, -1, 0, 1, 0};

EXDEX_TEST(motion_translation)
{
    /* p(t) = p0 + s(t) axis/|axis| with s from the (separately tested)
     * profile; R constant; v, a = sd, sdd along the axis; no rotation. */
    exdex_motion_def d = zero_def();
    const double p0[3] = {0.1, -0.2, 0.3}, u[3] = {0.0, 0.6, 0.8};
    int status = -1;
    const char *bad = NULL;
    exdex_motion *m;
    d.kind = EXDEX_MOTION_ASYMMETRIC;
    d.axis[0] = 0.0; d.axis[1] = 3.0; d.axis[2] = 4.0;  /* normalised to u */
    d.amplitude = 0.1; d.duration = 0.5; d.beta = 0.9;
    m = exdex_motion_alloc(&d, R_YUP, p0, &status, &bad);
    ENSURE(m != NULL && status == EXDEX_OK);
    if (!m) return;
    ENSURE(exdex_motion_end(m) == 1.0);
    for (int i = -5; i <= 120; i++) {
        double t = 0.00937 * i, s, sd, sdd;
        exdex_kinematics k;
        ENSURE(exdex_motion_eval(m, t, &k) == EXDEX_OK);
        exdex_profile_asymmetric(0.1, 0.5, 0.9, t, &s, &sd, &sdd);
        for (int j = 0; j < 3; j++) {
            ENSURE_CLOSE(k.p[j], p0[j] + s * u[j], 1e-15);
            ENSURE_CLOSE(k.v[j], sd * u[j], 1e-15);
            ENSURE_CLOSE(k.a[j], sdd * u[j], 1e-14);
            ENSURE(k.w[j] == 0.0 && k.dw[j] == 0.0);
        }
        for (int j = 0; j < 9; j++) ENSURE(k.R[j] == R_YUP[j]);
    }
    exdex_motion_free(m);

    /* trapezoid translation, Fig. 4: ends at p0 + X1 u at t = T */
    d.kind = EXDEX_MOTION_TRAPEZOID;
    d.amplitude = -0.05; d.v_max = 0.12;
    m = exdex_motion_alloc(&d, R_YUP, p0, &status, &bad);
    ENSURE(m != NULL && status == EXDEX_OK);
    if (!m) return;
    ENSURE(exdex_motion_end(m) == 0.5);
    {
        exdex_kinematics k;
        ENSURE(exdex_motion_eval(m, 0.7, &k) == EXDEX_OK);
        for (int j = 0; j < 3; j++) {
            ENSURE_CLOSE(k.p[j], p0[j] - 0.05 * u[j], 1e-16);
            ENSURE(k.v[j] == 0.0 && k.a[j] == 0.0);
        }
        ENSURE(exdex_motion_eval(m, 0.25, &k) == EXDEX_OK);
        ENSURE_CLOSE(dot3(k.v, u), -0.12, 1e-15);
    }
    exdex_motion_free(m);
}

/* Checks one rotation motion at times away from the profile's switches.
 * Reference: central differences with h = 1e-5 of the evaluated pose.
 * Within a phase s(t) is a quadratic, so p(t) = c + Rot(s)(p0 - c) is smooth.
 * With |r| <= 1 m, |sd| <= 2 rad/s, |sdd| <= 2 rad/s^2 here:
 *  - v vs (p+ - p-)/(2h): truncation h^2/6 |p'''| (|p'''| <= |sd|^3 |r| +
 *    3 |sd||sdd||r| <= 20) ~ 3e-10, rounding eps |p|/h ~ 1e-10: tol 2e-9;
 *  - a vs (p+ - 2p + p-)/h^2: rounding 4 eps |p| / h^2 ~ 2e-5, truncation
 *    h^2/12 |p''''| ~ 1e-9: tol 5e-5;
 *  - a vs (v+ - v-)/(2h): as for v: tol 2e-9;
 *  - w vs vee(R' R^T): truncation h^2/6 |R'''| <= 3e-10, rounding ~1e-11: tol 2e-9;
 *  - dw vs (w+ - w-)/(2h): w = sd axis is linear in t: rounding only, tol 2e-9. */
static void check_rotation_motion(const exdex_motion *m, const double axis[3],
                                  const double center[3], const double R0[9], const double p0[3],
                                  const double *times, int nt, double *worst_a2)
{
    const double h = 1e-5;
    for (int i = 0; i < nt; i++) {
        double t = times[i], w_fd[3], RR0t[9], R0t[9], ax[3], r0[3], r[3];
        exdex_kinematics k, kp, km;
        ENSURE(exdex_motion_eval(m, t, &k) == EXDEX_OK);
        ENSURE(exdex_motion_eval(m, t + h, &kp) == EXDEX_OK);
        ENSURE(exdex_motion_eval(m, t - h, &km) == EXDEX_OK);
        ENSURE_SMALL(orth_err(k.R), 1e-14);
        ENSURE_CLOSE(det3(k.R), 1.0, 1e-14);
        for (int j = 0; j < 3; j++) {
            double vfd = (kp.p[j] - km.p[j]) / (2.0 * h);
            double afd2 = (kp.p[j] - 2.0 * k.p[j] + km.p[j]) / (h * h);
            double afd = (kp.v[j] - km.v[j]) / (2.0 * h);
            double dwfd = (kp.w[j] - km.w[j]) / (2.0 * h);
            ENSURE_CLOSE(k.v[j], vfd, 2e-9);
            ENSURE_CLOSE(k.a[j], afd2, 5e-5);
            ENSURE_CLOSE(k.a[j], afd, 2e-9);
            ENSURE_CLOSE(k.dw[j], dwfd, 2e-9);
            if (fabs(k.a[j] - afd2) > *worst_a2) *worst_a2 = fabs(k.a[j] - afd2);
        }
        fd_omega(w_fd, kp.R, km.R, k.R, h);
        for (int j = 0; j < 3; j++) ENSURE_CLOSE(k.w[j], w_fd[j], 2e-9);
        /* w is along the axis */
        cross3(ax, k.w, axis);
        ENSURE_SMALL(norm3(ax), 1e-15);
        /* rigid rotation about the axis: R R0^T fixes the axis, the distance to
         * the centre and the height along the axis are preserved */
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) R0t[3 * a + b] = R0[3 * b + a];
        matmul3(RR0t, k.R, R0t);
        {
            double Ra[3] = {dot3(RR0t, axis), dot3(RR0t + 3, axis), dot3(RR0t + 6, axis)};
            ENSURE_SMALL(dist3(Ra, axis), 1e-14);
        }
        for (int j = 0; j < 3; j++) {
            r0[j] = p0[j] - center[j];
            r[j] = k.p[j] - center[j];
        }
        ENSURE_CLOSE(norm3(r), norm3(r0), 1e-14);
        ENSURE_CLOSE(dot3(r, axis), dot3(r0, axis), 1e-14);
    }
}

EXDEX_TEST(motion_rotation_asymmetric_fig6)
{
    /* Fig. 6 profile as an angle: beta 0.7, theta1 100 deg, T 3 s, about the
     * unit axis (1, 2, 2)/3 through c; B starts at R0 (B y up) and p0 off the
     * axis. At t = T: trace(R R0^T) = 1 + 2 cos(theta1). */
    exdex_motion_def d = zero_def();
    const double c[3] = {0.2, 0.1, -0.3}, p0[3] = {0.5, -0.4, 0.1};
    const double u[3] = {1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0};
    const double th1 = 100.0 * PI / 180.0;
    double times[40], worst = 0.0;
    int n = 0, status = -1;
    const char *bad = NULL;
    exdex_motion *m;
    d.kind = EXDEX_MOTION_ASYMMETRIC;
    d.rotation = 1;
    d.axis[0] = 1.0; d.axis[1] = 2.0; d.axis[2] = 2.0;
    memcpy(d.center, c, sizeof c);
    d.amplitude = th1; d.duration = 3.0; d.beta = 0.7;
    m = exdex_motion_alloc(&d, R_YUP, p0, &status, &bad);
    ENSURE(m != NULL && status == EXDEX_OK);
    if (!m) return;
    ENSURE(exdex_motion_end(m) == 6.0);
    /* switches at 2.1, 3.9, 6.0: sample (0, 6) avoiding them by >= 1e-3 */
    for (int i = 0; i < 40; i++) {
        double t = 0.013 + 0.1497 * i;
        if (fabs(t - 2.1) > 1e-3 && fabs(t - 3.9) > 1e-3 && t < 6.0 - 1e-3) times[n++] = t;
    }
    check_rotation_motion(m, u, c, R_YUP, p0, times, n, &worst);
    report("motion_fd_worst_a_second_difference", worst);
    {
        exdex_kinematics k;
        double R0t[9], Q[9];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) R0t[3 * a + b] = R_YUP[3 * b + a];
        ENSURE(exdex_motion_eval(m, 3.0, &k) == EXDEX_OK);
        matmul3(Q, k.R, R0t);
        ENSURE_CLOSE(Q[0] + Q[4] + Q[8], 1.0 + 2.0 * cos(th1), 1e-14);
        ENSURE_SMALL(norm3(k.w), 1e-15);
        /* back at the start, at rest, after 2T */
        ENSURE(exdex_motion_eval(m, 7.0, &k) == EXDEX_OK);
        for (int j = 0; j < 9; j++) ENSURE_CLOSE(k.R[j], R_YUP[j], 1e-15);
        for (int j = 0; j < 3; j++) {
            ENSURE_CLOSE(k.p[j], p0[j], 1e-15);
            ENSURE(k.v[j] == 0.0 && k.a[j] == 0.0 && k.w[j] == 0.0 && k.dw[j] == 0.0);
        }
    }
    exdex_motion_free(m);
}

EXDEX_TEST(motion_rotation_trapezoid)
{
    /* -90 deg about a unit A z axis through c in 2 s at 1.2 |X1|/T: B's x axis
     * (R0 column 0 = A x) ends at A -y; the origin p0 = c + (1, 0, 0) ends at
     * c + (0, -1, 0). Finite-difference checks as above. */
    exdex_motion_def d = zero_def();
    const double c[3] = {0.0, 0.5, 0.25}, p0[3] = {1.0, 0.5, 0.6}, u[3] = {0, 0, 1};
    const double X1 = -PI / 2.0, T = 2.0, V = 1.2 * PI / 2.0 / 2.0;
    const double ta = T - fabs(X1) / V;
    double times[30], worst = 0.0;
    int n = 0, status = -1;
    const char *bad = NULL;
    exdex_motion *m;
    d.kind = EXDEX_MOTION_TRAPEZOID;
    d.rotation = 1;
    d.axis[2] = 1.0;
    memcpy(d.center, c, sizeof c);
    d.amplitude = X1; d.duration = T; d.v_max = V;
    m = exdex_motion_alloc(&d, R_YUP, p0, &status, &bad);
    ENSURE(m != NULL && status == EXDEX_OK);
    if (!m) return;
    for (int i = 0; i < 30; i++) {
        double t = 0.011 + 0.0661 * i;
        if (fabs(t - ta) > 1e-3 && fabs(t - (T - ta)) > 1e-3 && t < T - 1e-3) times[n++] = t;
    }
    check_rotation_motion(m, u, c, R_YUP, p0, times, n, &worst);
    {
        exdex_kinematics k;
        const double pend[3] = {0.0, -0.5, 0.6};
        ENSURE(exdex_motion_eval(m, 2.5, &k) == EXDEX_OK);
        ENSURE_CLOSE(k.R[0], 0.0, 1e-15);
        ENSURE_CLOSE(k.R[3], -1.0, 1e-15);
        ENSURE_CLOSE(k.R[6], 0.0, 1e-15);
        for (int j = 0; j < 3; j++) ENSURE_CLOSE(k.p[j], pend[j], 1e-15);
    }
    exdex_motion_free(m);
}

EXDEX_TEST(motion_rest)
{
    exdex_motion_def d = zero_def();
    const double p0[3] = {1, 2, 3};
    exdex_kinematics k;
    int status = -1;
    exdex_motion *m = exdex_motion_alloc(&d, R_YUP, p0, &status, NULL);
    ENSURE(m != NULL && status == EXDEX_OK);
    if (!m) return;
    ENSURE(exdex_motion_end(m) == 0.0);
    ENSURE(exdex_motion_eval(m, 0.3, &k) == EXDEX_OK);
    for (int j = 0; j < 9; j++) ENSURE(k.R[j] == R_YUP[j]);
    for (int j = 0; j < 3; j++) {
        ENSURE(k.p[j] == p0[j]);
        ENSURE(k.v[j] == 0.0 && k.a[j] == 0.0 && k.w[j] == 0.0 && k.dw[j] == 0.0);
    }
    ENSURE(exdex_motion_eval(m, NAN, &k) == EXDEX_EINVAL);
    exdex_motion_free(m);
}

/* ------------------------------------------------------------ sampled */

/* Analytic test trajectories.
 * Position: p(t) = (sin t, cos 2t, t^2).
 * Orientation 0 ("fixed axis"): R = Rot(k, th), th = 0.5 sin t, k = (2,-1,2)/3;
 *   w = th' k, dw = th'' k.  q = (cos(th/2), sin(th/2) k).
 * Orientation 1 ("varying axis"): R = Rz(a) Rx(b), a = t, b = 0.3 sin 2t;
 *   world w = a' ez + b' Rz(a) ex (the second rotation's axis is carried by
 *   the first), dw = a'' ez + b'' Rz(a) ex + b' a' ez x Rz(a) ex;
 *   q = qz(a) qx(b) = (ca cb, ca sb, sa sb, sa cb), ca = cos(a/2), ... */
static void traj_pos(double t, double p[3], double v[3], double a[3])
{
    p[0] = sin(t); p[1] = cos(2.0 * t); p[2] = t * t;
    v[0] = cos(t); v[1] = -2.0 * sin(2.0 * t); v[2] = 2.0 * t;
    a[0] = -sin(t); a[1] = -4.0 * cos(2.0 * t); a[2] = 2.0;
}

static void traj_rot(int which, double t, double q[4], double R[9], double w[3], double dw[3])
{
    if (which == 0) {
        const double k[3] = {2.0 / 3.0, -1.0 / 3.0, 2.0 / 3.0};
        double th = 0.5 * sin(t), thd = 0.5 * cos(t), thdd = -0.5 * sin(t);
        double c = cos(th), s = sin(th), C = 1.0 - c;
        q[0] = cos(0.5 * th);
        for (int j = 0; j < 3; j++) {
            q[1 + j] = sin(0.5 * th) * k[j];
            w[j] = thd * k[j];
            dw[j] = thdd * k[j];
        }
        /* Rodrigues, written out here for the test */
        R[0] = c + k[0] * k[0] * C;        R[1] = k[0] * k[1] * C - k[2] * s; R[2] = k[0] * k[2] * C + k[1] * s;
        R[3] = k[1] * k[0] * C + k[2] * s; R[4] = c + k[1] * k[1] * C;        R[5] = k[1] * k[2] * C - k[0] * s;
        R[6] = k[2] * k[0] * C - k[1] * s; R[7] = k[2] * k[1] * C + k[0] * s; R[8] = c + k[2] * k[2] * C;
    } else {
        double a = t, ad = 1.0, add = 0.0;
        double b = 0.3 * sin(2.0 * t), bd = 0.6 * cos(2.0 * t), bdd = -1.2 * sin(2.0 * t);
        double ca = cos(0.5 * a), sa = sin(0.5 * a), cb = cos(0.5 * b), sb = sin(0.5 * b);
        double Rz[9] = {cos(a), -sin(a), 0, sin(a), cos(a), 0, 0, 0, 1};
        double Rx[9] = {1, 0, 0, 0, cos(b), -sin(b), 0, sin(b), cos(b)};
        double ez[3] = {0, 0, 1}, ex_a[3] = {cos(a), sin(a), 0}, zx[3];
        q[0] = ca * cb; q[1] = ca * sb; q[2] = sa * sb; q[3] = sa * cb;
        matmul3(R, Rz, Rx);
        cross3(zx, ez, ex_a);
        for (int j = 0; j < 3; j++) {
            w[j] = ad * ez[j] + bd * ex_a[j];
            dw[j] = add * ez[j] + bdd * ex_a[j] + bd * ad * zx[j];
        }
    }
}

/* Grid: t_i = i h on [0, 4], h = 0.01 (401 samples). Hall & Meyer bounds for
 * cubic spline interpolation with |f''''| <= M4:
 *   |s - f| <= 5/384 h^4 M4,  |s' - f'| <= h^3 M4 / 24,  |s'' - f''| <= 3/8 h^2 M4.
 * M4 = 16 bounds every component used here (cos 2t: 16; sin t: 1; t^2: 0;
 * quaternion components: <= 11 by Faa di Bruno for the varying axis, < 1 for
 * the fixed one). They hold for the complete (clamped) spline; the natural
 * end conditions add an error that decays by 2 - sqrt(3) ~ 0.27 per interval
 * away from the ends, so the check runs on [0.3, 3.7] (>= 30 intervals in:
 * factor < 1e-16). Bounds: 2.1e-9 (position), 6.7e-7 (velocity), 6e-4
 * (acceleration). w = 2 vec(n' n*) mixes four quaternion components (vector
 * norm <= 2 x component bound) times 2, and normalisation adds terms of the
 * order of the position bound: w tolerance 4x the velocity bound, dw 4x the
 * acceleration bound (one more factor for the product-rule terms). */
#define SP_N 401
#define SP_H 0.01
#define SP_M4 16.0

static void fill_samples(int which, double *times, double *poses, int negate_every)
{
    for (int i = 0; i < SP_N; i++) {
        double t = i * SP_H, p[3], v[3], a[3], q[4], R[9], w[3], dw[3];
        traj_pos(t, p, v, a);
        traj_rot(which, t, q, R, w, dw);
        times[i] = t;
        for (int j = 0; j < 3; j++) poses[7 * i + j] = p[j];
        for (int j = 0; j < 4; j++)
            poses[7 * i + 3 + j] = (negate_every && i % negate_every == 0) ? -q[j] : q[j];
    }
}

static exdex_motion *sampled_motion(const double *times, const double *poses, size_t n)
{
    exdex_motion_def d = zero_def();
    int status = -1;
    const char *bad = NULL;
    exdex_motion *m;
    d.kind = EXDEX_MOTION_SAMPLED;
    d.n_samples = n;
    d.times = times;
    d.poses = poses;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, &bad);
    ENSURE(m != NULL && status == EXDEX_OK);
    return m;
}

static double max_err[6];  /* p, v, a, R, w, dw over the last check */

static void check_sampled(const exdex_motion *m, int which)
{
    const double bp = 5.0 / 384.0 * pow(SP_H, 4) * SP_M4;
    const double bv = pow(SP_H, 3) * SP_M4 / 24.0;
    const double ba = 3.0 / 8.0 * SP_H * SP_H * SP_M4;
    for (int j = 0; j < 6; j++) max_err[j] = 0.0;
    /* 341 points: nodes, midpoints and off-grid points of [0.3, 3.7] */
    for (int i = 0; i <= 340; i++) {
        double t = 0.3 + i * 0.01 + (i % 3) * 0.00333;
        double p[3], v[3], a[3], q[4], R[9], w[3], dw[3], e[6];
        exdex_kinematics k;
        if (t > 3.7) t = 3.7;
        traj_pos(t, p, v, a);
        traj_rot(which, t, q, R, w, dw);
        ENSURE(exdex_motion_eval(m, t, &k) == EXDEX_OK);
        e[0] = dist3(k.p, p);
        e[1] = dist3(k.v, v);
        e[2] = dist3(k.a, a);
        e[3] = 0.0;
        for (int j = 0; j < 9; j++)
            if (fabs(k.R[j] - R[j]) > e[3]) e[3] = fabs(k.R[j] - R[j]);
        e[4] = dist3(k.w, w);
        e[5] = dist3(k.dw, dw);
        for (int j = 0; j < 6; j++)
            if (e[j] > max_err[j]) max_err[j] = e[j];
        ENSURE_SMALL(orth_err(k.R), 1e-14);
        ENSURE_CLOSE(det3(k.R), 1.0, 1e-14);
    }
    /* vector-norm errors: sqrt(3) x component bounds, rounded up to 2x */
    ENSURE_SMALL(max_err[0], 2.0 * bp);
    ENSURE_SMALL(max_err[1], 2.0 * bv);
    ENSURE_SMALL(max_err[2], 2.0 * ba);
    ENSURE_SMALL(max_err[3], 4.0 * bp);  /* R quadratic in n, |dR| <= 4 |dn| */
    ENSURE_SMALL(max_err[4], 4.0 * bv);
    ENSURE_SMALL(max_err[5], 4.0 * ba);
}

EXDEX_TEST(motion_sampled_fixed_axis)
{
    static double times[SP_N], poses[7 * SP_N];
    exdex_motion *m;
    fill_samples(0, times, poses, 0);
    m = sampled_motion(times, poses, SP_N);
    if (!m) return;
    check_sampled(m, 0);
    report("motion_sampled_fixed_err_v", max_err[1]);
    report("motion_sampled_fixed_err_w", max_err[4]);
    report("motion_sampled_fixed_err_dw", max_err[5]);
    ENSURE(exdex_motion_end(m) == times[SP_N - 1]);
    exdex_motion_free(m);
}

EXDEX_TEST(motion_sampled_varying_axis)
{
    /* distinguishes world-frame w = 2 vec(n' n*) from the body-frame
     * 2 vec(n* n'), which differ here by R^T */
    static double times[SP_N], poses[7 * SP_N];
    exdex_motion *m;
    fill_samples(1, times, poses, 0);
    m = sampled_motion(times, poses, SP_N);
    if (!m) return;
    check_sampled(m, 1);
    report("motion_sampled_varying_err_p", max_err[0]);
    report("motion_sampled_varying_err_a", max_err[2]);
    report("motion_sampled_varying_err_w", max_err[4]);
    report("motion_sampled_varying_err_dw", max_err[5]);
    exdex_motion_free(m);
}

EXDEX_TEST(motion_sampled_sign_flips_and_ends)
{
    /* -q is the same rotation: negating every third sample (including the
     * first) and scaling others must give the same motion (up to rounding of
     * the normalisation). Outside [t_0, t_last] the end poses are held at rest,
     * and at the sample times the spline reproduces the samples. */
    static double times[SP_N], poses[7 * SP_N], poses2[7 * SP_N];
    exdex_motion *m, *m2;
    double errmax = 0.0;
    fill_samples(1, times, poses, 0);
    fill_samples(1, times, poses2, 3);
    for (int i = 1; i < SP_N; i += 7)
        for (int j = 3; j < 7; j++) poses2[7 * i + j] *= 2.5;
    m = sampled_motion(times, poses, SP_N);
    m2 = sampled_motion(times, poses2, SP_N);
    if (m && m2) {
        for (int i = 0; i < 200; i++) {
            double t = -0.1 + i * 0.0211;
            exdex_kinematics k, k2;
            ENSURE(exdex_motion_eval(m, t, &k) == EXDEX_OK);
            ENSURE(exdex_motion_eval(m2, t, &k2) == EXDEX_OK);
            for (int j = 0; j < 9; j++) ENSURE_CLOSE(k.R[j], k2.R[j], 1e-13);
            for (int j = 0; j < 3; j++) {
                ENSURE_CLOSE(k.w[j], k2.w[j], 1e-12);
                ENSURE_CLOSE(k.dw[j], k2.dw[j], 1e-10);
                if (fabs(k.w[j] - k2.w[j]) > errmax) errmax = fabs(k.w[j] - k2.w[j]);
            }
        }
        report("motion_sampled_flip_w_diff", errmax);
        /* samples reproduced at the nodes: exact interpolation */
        for (int i = 0; i < SP_N; i += 50) {
            exdex_kinematics k;
            double p[3], v[3], a[3], q[4], R[9], w[3], dw[3];
            traj_pos(times[i], p, v, a);
            traj_rot(1, times[i], q, R, w, dw);
            ENSURE(exdex_motion_eval(m2, times[i], &k) == EXDEX_OK);
            for (int j = 0; j < 3; j++) ENSURE_CLOSE(k.p[j], p[j], 1e-14);
            for (int j = 0; j < 9; j++) ENSURE_CLOSE(k.R[j], R[j], 1e-14);
        }
        /* held end poses */
        {
            exdex_kinematics k;
            double p[3], v[3], a[3], q[4], R[9], w[3], dw[3];
            ENSURE(exdex_motion_eval(m2, 10.0, &k) == EXDEX_OK);
            traj_pos(4.0, p, v, a);
            traj_rot(1, 4.0, q, R, w, dw);
            for (int j = 0; j < 3; j++) {
                ENSURE_CLOSE(k.p[j], p[j], 1e-14);
                ENSURE(k.v[j] == 0.0 && k.a[j] == 0.0 && k.w[j] == 0.0 && k.dw[j] == 0.0);
            }
            for (int j = 0; j < 9; j++) ENSURE_CLOSE(k.R[j], R[j], 1e-14);
            ENSURE(exdex_motion_eval(m2, -1.0, &k) == EXDEX_OK);
            traj_pos(0.0, p, v, a);
            traj_rot(1, 0.0, q, R, w, dw);
            for (int j = 0; j < 3; j++) {
                ENSURE_CLOSE(k.p[j], p[j], 1e-15);
                ENSURE(k.v[j] == 0.0 && k.w[j] == 0.0);
            }
            for (int j = 0; j < 9; j++) ENSURE_CLOSE(k.R[j], R[j], 1e-15);
        }
    }
    exdex_motion_free(m);
    exdex_motion_free(m2);
}

/* ---------------------------------------------------------- bad input */

static void expect_bad(const exdex_motion_def *d, const double *R0, const double *p0,
                       const char *name)
{
    int status = -1;
    const char *bad = NULL;
    exdex_motion *m = exdex_motion_alloc(d, R0, p0, &status, &bad);
    ENSURE(m == NULL);
    ENSURE(status == EXDEX_EINVAL);
    ENSURE(bad != NULL && strcmp(bad, name) == 0);
    if (bad && strcmp(bad, name) != 0) printf("    expected %s, got %s\n", name, bad);
    exdex_motion_free(m);
}

EXDEX_TEST(motion_bad_input)
{
    static double times[8] = {0, 1, 2, 3, 4, 5, 6, 7}, poses[56];
    const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p0[3] = {0, 0, 0};
    exdex_motion_def base = zero_def(), d;
    double R[9];

    base.kind = EXDEX_MOTION_ASYMMETRIC;
    base.axis[2] = 1.0;
    base.amplitude = 0.1; base.duration = 0.5; base.beta = 0.9; base.v_max = 0.15;
    for (int i = 0; i < 8; i++) {
        for (int j = 0; j < 7; j++) poses[7 * i + j] = 0.0;
        poses[7 * i + 3] = 1.0;
    }
    {   /* the base definitions are valid */
        int status = -1;
        exdex_motion *m = exdex_motion_alloc(&base, eye, p0, &status, NULL);
        ENSURE(m != NULL && status == EXDEX_OK);
        exdex_motion_free(m);
    }

    d = base; d.kind = EXDEX_MOTION_CHAIN + 1; expect_bad(&d, eye, p0, "motion.kind");
    d = base; d.kind = -1; expect_bad(&d, eye, p0, "motion.kind");
    d = base; d.rotation = 2; expect_bad(&d, eye, p0, "motion.rotation");
    d = base; d.axis[2] = 0.0; expect_bad(&d, eye, p0, "motion.axis");
    d = base; d.axis[0] = NAN; expect_bad(&d, eye, p0, "motion.axis");
    d = base; d.rotation = 1; d.center[1] = INFINITY; expect_bad(&d, eye, p0, "motion.center");
    d = base; d.amplitude = NAN; expect_bad(&d, eye, p0, "motion.amplitude");
    d = base; d.amplitude = 1e300; d.duration = 1e-10; expect_bad(&d, eye, p0, "motion.amplitude");
    d = base; d.duration = 0.0; expect_bad(&d, eye, p0, "motion.duration");
    d = base; d.duration = -1.0; expect_bad(&d, eye, p0, "motion.duration");
    d = base; d.duration = INFINITY; expect_bad(&d, eye, p0, "motion.duration");
    d = base; d.beta = 0.0; expect_bad(&d, eye, p0, "motion.beta");
    d = base; d.beta = 1.0; expect_bad(&d, eye, p0, "motion.beta");
    d = base; d.beta = NAN; expect_bad(&d, eye, p0, "motion.beta");
    d = base; d.kind = EXDEX_MOTION_TRAPEZOID; d.v_max = 0.19; expect_bad(&d, eye, p0, "motion.v_max");
    d = base; d.kind = EXDEX_MOTION_TRAPEZOID; d.v_max = 0.41; expect_bad(&d, eye, p0, "motion.v_max");
    d = base; d.kind = EXDEX_MOTION_TRAPEZOID; d.v_max = 0.0; expect_bad(&d, eye, p0, "motion.v_max");
    d = base; d.kind = EXDEX_MOTION_TRAPEZOID; d.v_max = NAN; expect_bad(&d, eye, p0, "motion.v_max");
    {   /* the trapezoid boundaries themselves are valid: 0.2 and 0.4 m/s */
        int status = -1;
        exdex_motion *m;
        d = base; d.kind = EXDEX_MOTION_TRAPEZOID; d.v_max = 0.1 / 0.5;
        m = exdex_motion_alloc(&d, eye, p0, &status, NULL);
        ENSURE(m != NULL && status == EXDEX_OK);
        exdex_motion_free(m);
        d.v_max = 2.0 * 0.1 / 0.5;
        m = exdex_motion_alloc(&d, eye, p0, &status, NULL);
        ENSURE(m != NULL && status == EXDEX_OK);
        exdex_motion_free(m);
    }
    /* R0: not orthonormal, a reflection (det -1), slightly off, non-finite */
    memcpy(R, eye, sizeof R); R[0] = 1.1; expect_bad(&base, R, p0, "R0");
    memcpy(R, eye, sizeof R); R[8] = -1.0; expect_bad(&base, R, p0, "R0");
    memcpy(R, eye, sizeof R); R[1] = 1e-7; expect_bad(&base, R, p0, "R0");
    memcpy(R, eye, sizeof R); R[4] = NAN; expect_bad(&base, R, p0, "R0");
    {
        const double pinf[3] = {0, INFINITY, 0};
        expect_bad(&base, eye, pinf, "p0");
    }
    /* sampled */
    d = zero_def(); d.kind = EXDEX_MOTION_SAMPLED; d.n_samples = 8; d.times = times; d.poses = poses;
    {
        int status = -1;
        exdex_motion *m = exdex_motion_alloc(&d, NULL, NULL, &status, NULL);
        ENSURE(m != NULL && status == EXDEX_OK);
        ENSURE(exdex_motion_end(m) == 7.0);
        exdex_motion_free(m);
    }
    d.n_samples = 3; expect_bad(&d, eye, p0, "motion.n_samples");
    d.n_samples = 8; d.times = NULL; expect_bad(&d, eye, p0, "motion.times");
    d.times = times; d.poses = NULL; expect_bad(&d, eye, p0, "motion.poses");
    d.poses = poses;
    times[4] = 3.0; expect_bad(&d, eye, p0, "motion.times");   /* not strictly increasing */
    times[4] = NAN; expect_bad(&d, eye, p0, "motion.times");
    times[4] = 4.0;
    poses[7 * 2 + 1] = INFINITY; expect_bad(&d, eye, p0, "motion.poses");
    poses[7 * 2 + 1] = 0.0;
    poses[7 * 5 + 3] = 0.0; expect_bad(&d, eye, p0, "motion.poses");  /* zero quaternion */
    poses[7 * 5 + 3] = 1.0;

    /* NULL definition, NULL free */
    {
        int status = -1;
        ENSURE(exdex_motion_alloc(NULL, eye, p0, &status, NULL) == NULL);
        ENSURE(status == EXDEX_EINVAL);
    }
    exdex_motion_free(NULL);
    /* a zeroed definition is a valid rest motion */
    d = zero_def();
    {
        int status = -1;
        exdex_motion *m = exdex_motion_alloc(&d, eye, p0, &status, NULL);
        ENSURE(m != NULL && status == EXDEX_OK);
        exdex_motion_free(m);
    }
}

EXDEX_TEST(motion_rotation_axis_near_dbl_max)
{
    /* The axis is normalised (exdex.h): components near DBL_MAX are a valid
     * axis whose Euclidean norm overflows; a plain normalisation makes the
     * axis 0 and R = cos(s) I, which is not orthonormal. Closed form at t = T of an
     * asymmetric profile (s = X1, Eq. 8): R = Rot(u, X1) with
     * u = (-1, 0, 1)/sqrt(2), so R u = u and trace R = 1 + 2 cos X1. */
    static const double big[2] = {DBL_MAX, 1e308};
    for (int b = 0; b < 2; b++) {
        exdex_motion_def d = zero_def();
        const double u[3] = {-1.0 / sqrt(2.0), 0.0, 1.0 / sqrt(2.0)};
        const double th1 = 1.0;
        exdex_kinematics k;
        int status = -1;
        const char *bad = NULL;
        exdex_motion *m;
        d.kind = EXDEX_MOTION_ASYMMETRIC;
        d.rotation = 1;
        d.axis[0] = -big[b]; d.axis[1] = 0.0; d.axis[2] = big[b];
        d.amplitude = th1; d.duration = 1.0; d.beta = 0.5;
        m = exdex_motion_alloc(&d, NULL, NULL, &status, &bad);
        ENSURE(m != NULL && status == EXDEX_OK);
        if (!m) continue;
        ENSURE(exdex_motion_eval(m, 1.0, &k) == EXDEX_OK);
        ENSURE_SMALL(orth_err(k.R), 1e-14);
        ENSURE_CLOSE(det3(k.R), 1.0, 1e-14);
        ENSURE_CLOSE(k.R[0] + k.R[4] + k.R[8], 1.0 + 2.0 * cos(th1), 1e-14);
        {
            double Ru[3] = {dot3(k.R, u), dot3(k.R + 3, u), dot3(k.R + 6, u)};
            ENSURE_SMALL(dist3(Ru, u), 1e-15);
        }
        exdex_motion_free(m);
    }
}

/* ------------------------------------------------ sampled logs: end conditions
 *
 * References: polynomials the clamped spline reproduces exactly (a cubic
 * spline with exact end slopes reproduces every cubic, so a quadratic log
 * with the right end slopes comes back exactly), hand-composed poses, and
 * the end rule's threshold worked out by hand: for x = v0 t + a t^2 / 2
 * sampled at steps h, the quadratic through the first three samples is x
 * itself, its start velocity v0, D1 = v0 h + a h^2 / 2, so
 * v0 . D1 <= |D1|^2 / (2 h)  <=>  v0 <= a h / 2. */

static exdex_motion *sampled_def(exdex_motion_def *d, const double *times, const double *poses, size_t n,
                                 const double *R0, const double *p0)
{
    int status = -1;
    const char *bad = NULL;
    exdex_motion *m;
    d->kind = EXDEX_MOTION_SAMPLED;
    d->n_samples = n;
    d->times = times;
    d->poses = poses;
    m = exdex_motion_alloc(d, R0, p0, &status, &bad);
    ENSURE(m != NULL && status == EXDEX_OK);
    return m;
}

/* x(t) = x0 + v0 t + a t^2 / 2 along e, identity orientation, at times t */
static void fill_quadratic(double *poses, const double *t, size_t n, const double x0[3], const double e[3],
                           double v0, double a)
{
    for (size_t i = 0; i < n; i++) {
        double s = v0 * t[i] + 0.5 * a * t[i] * t[i];
        for (int j = 0; j < 3; j++) poses[7 * i + j] = x0[j] + s * e[j];
        poses[7 * i + 3] = 1.0;
        poses[7 * i + 4] = poses[7 * i + 5] = poses[7 * i + 6] = 0.0;
    }
}

EXDEX_TEST(motion_sampled_uniform_acceleration_from_rest_is_exact)
{
    /* a log of x = a t^2 / 2 (non-uniform sample times from t = 0): the start
     * is at rest (v0 = 0 exactly), the end slope is the quadratic's, so the
     * spline is the quadratic: v = a t e, acc = a e everywhere inside */
    double t[9], poses[7 * 9], x0[3] = {0.1, -0.2, 0.3}, e[3] = {2.0 / 3.0, -1.0 / 3.0, 2.0 / 3.0};
    double a = 0.7, tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    exdex_motion_def d = zero_def();
    exdex_motion *m;
    for (int i = 0; i < 9; i++) t[i] = 0.05 * (i + 0.3 * sin((double)i));
    fill_quadratic(poses, t, 9, x0, e, 0.0, a);
    m = sampled_def(&d, t, poses, 9, NULL, NULL);
    if (!m) return;
    for (int i = 0; i <= 50; i++) {
        double tt = t[0] + (t[8] - t[0]) * i / 50.0 * (1.0 - 1e-12);
        exdex_kinematics k;
        ENSURE(exdex_motion_eval(m, tt, &k) == EXDEX_OK);
        for (int j = 0; j < 3; j++) {
            ENSURE_CLOSE(k.p[j], x0[j] + 0.5 * a * tt * tt * e[j], 1e-15);
            ENSURE_CLOSE(k.v[j], a * tt * e[j], 1e-13);
            ENSURE_CLOSE(k.a[j], a * e[j], 1e-11);
            ENSURE(k.w[j] == 0.0 && k.dw[j] == 0.0);
        }
    }
    {
        exdex_kinematics k;
        ENSURE(exdex_motion_eval(m, t[0], &k) == EXDEX_OK);
        ENSURE(k.v[0] == 0.0 && k.v[1] == 0.0 && k.v[2] == 0.0);  /* clamped: exactly at rest */
    }
    /* one jump: back to rest at the last sample, -a t_last e */
    ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 1);
    ENSURE(tj[0] == t[8]);
    for (int j = 0; j < 3; j++) {
        ENSURE_CLOSE(dv[0][j], -a * t[8] * e[j], 1e-13);
        ENSURE(dw[0][j] == 0.0);
    }
    exdex_motion_free(m);
}

EXDEX_TEST(motion_sampled_constant_speed_jumps_at_both_ends)
{
    /* x = x0 + v t sampled from 0.5 s to 1.2 s: both ends at speed; the
     * spline is the line; the gripper rests before and after (right-
     * continuous: at rest from t_last on) and jumps by +v and -v */
    double t[8], poses[7 * 8], x0[3] = {0, 0, 0}, e[3] = {0.6, 0.0, 0.8}, v = 0.25, tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    exdex_motion_def d = zero_def();
    exdex_kinematics k;
    exdex_motion *m;
    for (int i = 0; i < 8; i++) t[i] = 0.5 + 0.1 * i;
    fill_quadratic(poses, t, 8, x0, e, v, 0.0);
    m = sampled_def(&d, t, poses, 8, NULL, NULL);
    if (!m) return;
    ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 2);
    ENSURE(tj[0] == t[0] && tj[1] == t[7]);
    for (int j = 0; j < 3; j++) {
        ENSURE_CLOSE(dv[0][j], v * e[j], 1e-14);
        ENSURE_CLOSE(dv[1][j], -v * e[j], 1e-14);
        ENSURE(dw[0][j] == 0.0 && dw[1][j] == 0.0);
    }
    ENSURE(exdex_motion_eval(m, 0.8, &k) == EXDEX_OK);
    for (int j = 0; j < 3; j++) ENSURE_CLOSE(k.v[j], v * e[j], 1e-14);
    ENSURE(exdex_motion_eval(m, t[7], &k) == EXDEX_OK);
    for (int j = 0; j < 3; j++) {
        ENSURE(k.v[j] == 0.0 && k.a[j] == 0.0);
        ENSURE_CLOSE(k.p[j], poses[7 * 7 + j], 1e-16);
    }
    ENSURE(exdex_motion_eval(m, 0.4, &k) == EXDEX_OK);
    for (int j = 0; j < 3; j++) ENSURE(k.v[j] == 0.0 && k.p[j] == poses[j]);
    exdex_motion_free(m);
}

EXDEX_TEST(motion_sampled_rest_threshold_is_scale_free)
{
    /* x = v0 t + a t^2 / 2, steps h: at rest iff v0 <= a h / 2 (header).
     * The same decision after scaling lengths by 1e-3 and times by 7. */
    const double e[3] = {0.0, 1.0, 0.0}, x0[3] = {0, 0, 0};
    for (int sc = 0; sc < 2; sc++) {
        double L = sc ? 1e-3 : 1.0, T = sc ? 7.0 : 1.0, h = 0.1 * T, a = 2.0 * L / (T * T);
        for (int c = 0; c < 2; c++) {
            double v0 = (c ? 0.55 : 0.45) * a * h, t[6], poses[7 * 6];
            exdex_motion_def d = zero_def();
            exdex_kinematics k;
            exdex_motion *m;
            for (int i = 0; i < 6; i++) t[i] = i * h;
            fill_quadratic(poses, t, 6, x0, e, v0, a);
            m = sampled_def(&d, t, poses, 6, NULL, NULL);
            if (!m) continue;
            ENSURE(exdex_motion_eval(m, 0.0, &k) == EXDEX_OK);
            if (c == 0)
                ENSURE(k.v[1] == 0.0);                  /* clamped at rest */
            else
                ENSURE_CLOSE(k.v[1], v0, 1e-12 * v0);  /* the quadratic's start velocity */
            exdex_motion_free(m);
        }
    }
}

/* unit quaternion of a rotation by th about the unit axis u */
static void quat_axis(double q[4], const double u[3], double th)
{
    q[0] = cos(0.5 * th);
    for (int j = 0; j < 3; j++) q[1 + j] = sin(0.5 * th) * u[j];
}

EXDEX_TEST(motion_sampled_orientation_rule_separate_from_position)
{
    /* the orientation turns from rest with a uniform angular acceleration
     * (angle al t^2 / 2 about a fixed axis) while the origin cruises at a
     * constant velocity: the start is clamped for the orientation (w = 0
     * exactly) but not for the position (v = the cruise velocity) */
    const double u[3] = {0.0, 0.6, 0.8}, vel[3] = {0.1, 0.0, -0.05}, al = 3.0;
    double t[10], poses[7 * 10];
    exdex_motion_def d = zero_def();
    exdex_kinematics k;
    exdex_motion *m;
    for (int i = 0; i < 10; i++) {
        t[i] = 0.02 * i;
        for (int j = 0; j < 3; j++) poses[7 * i + j] = vel[j] * t[i];
        quat_axis(poses + 7 * i + 3, u, 0.5 * al * t[i] * t[i]);
    }
    m = sampled_def(&d, t, poses, 10, NULL, NULL);
    if (!m) return;
    ENSURE(exdex_motion_eval(m, 0.0, &k) == EXDEX_OK);
    for (int j = 0; j < 3; j++) {
        ENSURE(k.w[j] == 0.0);
        ENSURE_CLOSE(k.v[j], vel[j], 1e-15);
    }
    exdex_motion_free(m);
}

EXDEX_TEST(motion_sampled_given_end_velocities)
{
    /* the user's end velocities are the spline's end slopes: at the first
     * sample (right value) and in the jump at the last (minus the left
     * value) they come back to rounding (w through n' = w n / 2 and
     * w = 2 vec(n' n*)) */
    const double u[3] = {0.48, 0.6, 0.64};
    double t[7], poses[7 * 7], tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    exdex_motion_def d = zero_def();
    exdex_kinematics k;
    exdex_motion *m;
    for (int i = 0; i < 7; i++) {
        t[i] = 0.1 * i;
        poses[7 * i] = 0.1 * sin(3.0 * t[i]);
        poses[7 * i + 1] = 0.05 * t[i];
        poses[7 * i + 2] = -0.2 * t[i] * t[i];
        quat_axis(poses + 7 * i + 3, u, 0.4 * t[i] + 0.3);
    }
    d.end_given[0] = d.end_given[1] = 1;
    d.end_velocity[0][0] = 0.3; d.end_velocity[0][1] = -0.1; d.end_velocity[0][2] = 0.02;
    d.end_omega[0][0] = 0.5; d.end_omega[0][1] = -1.5; d.end_omega[0][2] = 0.25;
    d.end_velocity[1][2] = -0.4;
    d.end_omega[1][1] = 2.0;
    m = sampled_def(&d, t, poses, 7, NULL, NULL);
    if (!m) return;
    ENSURE(exdex_motion_eval(m, 0.0, &k) == EXDEX_OK);
    for (int j = 0; j < 3; j++) {
        ENSURE(k.v[j] == d.end_velocity[0][j]);
        ENSURE_CLOSE(k.w[j], d.end_omega[0][j], 1e-15);
    }
    ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 2);
    for (int j = 0; j < 3; j++) {
        ENSURE(dv[0][j] == d.end_velocity[0][j]);
        ENSURE_CLOSE(dw[0][j], d.end_omega[0][j], 1e-15);
        ENSURE(dv[1][j] == -d.end_velocity[1][j]);
        ENSURE_CLOSE(dw[1][j], -d.end_omega[1][j], 1e-15);
    }
    exdex_motion_free(m);
    /* given zero velocities: no jump at all */
    d = zero_def();
    d.end_given[0] = d.end_given[1] = 1;
    m = sampled_def(&d, t, poses, 7, NULL, NULL);
    if (!m) return;
    ENSURE(exdex_motion_jumps(m, NULL, NULL, NULL) == 0);
    exdex_motion_free(m);
}

/* R of a unit quaternion, by hand (x_A = q x_B q*) */
static void quat_R(double R[9], const double q[4])
{
    double w = q[0], x = q[1], y = q[2], z = q[3];
    R[0] = w * w + x * x - y * y - z * z; R[1] = 2 * (x * y - w * z);       R[2] = 2 * (x * z + w * y);
    R[3] = 2 * (x * y + w * z);       R[4] = w * w - x * x + y * y - z * z; R[5] = 2 * (y * z - w * x);
    R[6] = 2 * (x * z - w * y);       R[7] = 2 * (y * z + w * x);       R[8] = w * w - x * x - y * y + z * z;
}

static void mattmul3(double C[9], const double A[9], const double B[9])  /* A B^T */
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            C[3 * i + j] = A[3 * i] * B[3 * j] + A[3 * i + 1] * B[3 * j + 1] + A[3 * i + 2] * B[3 * j + 2];
}

static void matvec3(double r[3], const double A[9], const double v[3])
{
    for (int i = 0; i < 3; i++) r[i] = A[3 * i] * v[0] + A[3 * i + 1] * v[1] + A[3 * i + 2] * v[2];
}

EXDEX_TEST(motion_sampled_relative_and_tool_composition)
{
    /* B(t) = P L(t) X with X the tool pose and P = G0 (L0 X)^-1 (relative);
     * composed here by hand from the plain log's kinematics (same spline:
     * the tool and the relative frame do not change the interpolated L):
     * R_B = R_P R_L R_X, p_B = p_P + R_P (p_L + R_L p_X), w_B = R_P w_L,
     * v_B = R_P (v_L + w_L x R_L p_X). At the sample times B(t_0) = G0. */
    const double u[3] = {0.0, 0.8, -0.6}, uX[3] = {1.0, 0.0, 0.0};
    double t[6], poses[7 * 6], R0[9], p0[3] = {0.4, -0.1, 0.9}, q0[4], RX[9], RL0[9], RLX[9], RP[9], pP[3], pX[3] = {0.01, 0.02, 0.15};
    exdex_motion_def d = zero_def(), dp = zero_def();
    exdex_motion *m, *mp;
    quat_axis(q0, u, 0.7);
    quat_R(R0, q0);
    for (int i = 0; i < 6; i++) {
        t[i] = 0.2 * i;
        poses[7 * i] = 1.0 + 0.3 * t[i];
        poses[7 * i + 1] = -0.5 * t[i] * t[i];
        poses[7 * i + 2] = 0.2 + 0.1 * sin(4.0 * t[i]);
        quat_axis(poses + 7 * i + 3, u, 1.2 * t[i] * t[i] - 0.4);
    }
    d.relative = 1;
    d.tool = 1;
    memcpy(d.tool_pose, pX, sizeof pX);
    quat_axis(d.tool_pose + 3, uX, 0.5 * PI);
    m = sampled_def(&d, t, poses, 6, R0, p0);
    mp = sampled_def(&dp, t, poses, 6, NULL, NULL);
    if (!m || !mp) {
        exdex_motion_free(m);
        exdex_motion_free(mp);
        return;
    }
    quat_R(RX, d.tool_pose + 3);
    quat_R(RL0, poses + 3);
    matmul3(RLX, RL0, RX);
    mattmul3(RP, R0, RLX);
    {
        double a[3];
        matvec3(a, RL0, pX);
        for (int j = 0; j < 3; j++) a[j] += poses[j];
        matvec3(pP, RP, a);
        for (int j = 0; j < 3; j++) pP[j] = p0[j] - pP[j];
    }
    for (int i = 0; i <= 20; i++) {
        double tt = i == 0 ? 0.0 : 0.0497 * i, RB[9], T1[9], pB[3], a[3], b[3], wB[3], vB[3];
        exdex_kinematics k, kl;
        ENSURE(exdex_motion_eval(m, tt, &k) == EXDEX_OK);
        ENSURE(exdex_motion_eval(mp, tt, &kl) == EXDEX_OK);
        matmul3(T1, kl.R, RX);
        matmul3(RB, RP, T1);
        matvec3(a, kl.R, pX);
        for (int j = 0; j < 3; j++) b[j] = kl.p[j] + a[j];
        matvec3(pB, RP, b);
        matvec3(wB, RP, kl.w);
        cross3(b, kl.w, a);
        for (int j = 0; j < 3; j++) b[j] += kl.v[j];
        matvec3(vB, RP, b);
        for (int j = 0; j < 9; j++) ENSURE_CLOSE(k.R[j], RB[j], 1e-14);
        for (int j = 0; j < 3; j++) {
            ENSURE_CLOSE(k.p[j], pP[j] + pB[j], 1e-14);
            ENSURE_CLOSE(k.w[j], wB[j], 1e-13);
            ENSURE_CLOSE(k.v[j], vB[j], 1e-13);
        }
        if (i == 0) {
            /* the replay starts at the initial gripper pose */
            for (int j = 0; j < 9; j++) ENSURE_CLOSE(k.R[j], R0[j], 1e-15);
            for (int j = 0; j < 3; j++) ENSURE_CLOSE(k.p[j], p0[j], 1e-15);
        }
    }
    /* velocity of B's origin against central differences of its position */
    {
        double hh = 1e-6, tt = 0.53;
        exdex_kinematics k, kp, km;
        ENSURE(exdex_motion_eval(m, tt, &k) == EXDEX_OK);
        ENSURE(exdex_motion_eval(m, tt + hh, &kp) == EXDEX_OK);
        ENSURE(exdex_motion_eval(m, tt - hh, &km) == EXDEX_OK);
        for (int j = 0; j < 3; j++) {
            ENSURE_CLOSE(k.v[j], (kp.p[j] - km.p[j]) / (2 * hh), 1e-7);
            ENSURE_CLOSE(k.a[j], (kp.v[j] - km.v[j]) / (2 * hh), 1e-6);
        }
    }
    exdex_motion_free(m);
    exdex_motion_free(mp);
}

EXDEX_TEST(motion_switches_and_trapezoid_jumps)
{
    double ts[EXDEX_MOTION_MAX_SWITCHES], tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    exdex_motion_def d = zero_def();
    exdex_motion *m;
    int status;
    /* Eq. 7: beta T, (2 - beta) T, 2 T; no velocity jump */
    d.kind = EXDEX_MOTION_ASYMMETRIC;
    d.axis[2] = 1.0; d.amplitude = 0.1; d.duration = 0.5; d.beta = 0.8;
    m = exdex_motion_alloc(&d, NULL, NULL, &status, NULL);
    ENSURE(m && exdex_motion_switches(m, ts) == 3);
    if (m) {
        ENSURE_CLOSE(ts[0], 0.4, 1e-16);
        ENSURE_CLOSE(ts[1], 0.6, 1e-16);
        ENSURE(ts[2] == 1.0);
        ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 0);
    }
    exdex_motion_free(m);
    /* a trapezoid without ramps (v_max = X1/T) rotating about an axis
     * through c: jumps at 0 (+w axis, v = w x (p0 - c)) and T (minus the
     * same at the end pose Rot(axis, X1)) */
    d = zero_def();
    d.kind = EXDEX_MOTION_TRAPEZOID;
    d.rotation = 1;
    d.axis[2] = 1.0; d.center[0] = 0.1; d.amplitude = 0.5 * PI; d.duration = 2.0; d.v_max = 0.25 * PI;
    {
        const double p0[3] = {0.3, 0.0, 0.0};
        m = exdex_motion_alloc(&d, NULL, p0, &status, NULL);
    }
    ENSURE(m != NULL);
    if (!m) return;
    ENSURE(exdex_motion_switches(m, ts) == 2 && ts[0] == 0.0 && ts[1] == 2.0);
    ENSURE(exdex_motion_jumps(m, tj, dv, dw) == 2);
    ENSURE(tj[0] == 0.0 && tj[1] == 2.0);
    /* r0 = (0.2, 0, 0): v = w x r0 = (0, 0.2 w, 0); at T r = (0, 0.2, 0):
     * v = (-0.2 w, 0, 0) */
    ENSURE_CLOSE(dw[0][2], 0.25 * PI, 1e-15);
    ENSURE_CLOSE(dv[0][1], 0.2 * 0.25 * PI, 1e-15);
    ENSURE_CLOSE(dw[1][2], -0.25 * PI, 1e-15);
    ENSURE_CLOSE(dv[1][0], 0.2 * 0.25 * PI, 1e-15);
    ENSURE_SMALL(dv[1][1], 1e-15);
    exdex_motion_free(m);
}

EXDEX_TEST(motion_sampled_option_bad_input)
{
    double t[5] = {0, 1, 2, 3, 4}, poses[7 * 5];
    exdex_motion_def d = zero_def();
    const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p0[3] = {0, 0, 0};
    memset(poses, 0, sizeof poses);
    for (int i = 0; i < 5; i++) poses[7 * i + 3] = 1.0;
    d.kind = EXDEX_MOTION_SAMPLED; d.n_samples = 5; d.times = t; d.poses = poses;
    d.end_given[1] = 2; expect_bad(&d, eye, p0, "motion.end_given");
    d.end_given[1] = 1; d.end_velocity[1][2] = NAN; expect_bad(&d, eye, p0, "motion.end_velocity");
    d.end_velocity[1][2] = 0.0; d.end_omega[1][0] = INFINITY; expect_bad(&d, eye, p0, "motion.end_omega");
    /* not given: the values are ignored */
    d.end_given[1] = 0;
    {
        int status = -1;
        exdex_motion *m = exdex_motion_alloc(&d, eye, p0, &status, NULL);
        ENSURE(m != NULL && status == EXDEX_OK);
        exdex_motion_free(m);
    }
    d.end_omega[1][0] = 0.0;
    d.relative = -1; expect_bad(&d, eye, p0, "motion.relative");
    d.relative = 1; d.tool = 3; expect_bad(&d, eye, p0, "motion.tool");
    d.tool = 1; expect_bad(&d, eye, p0, "motion.tool_pose");  /* zero quaternion */
    d.tool_pose[3] = 1.0; d.tool_pose[0] = NAN; expect_bad(&d, eye, p0, "motion.tool_pose");
    d.tool_pose[0] = 0.0;
    {
        int status = -1;
        exdex_motion *m = exdex_motion_alloc(&d, eye, p0, &status, NULL);
        ENSURE(m != NULL && status == EXDEX_OK);
        exdex_motion_free(m);
    }
}

EXDEX_TEST(motion_log_ending_at_speed_every_method_jumps)
{
    /* Translation along B x (= A x), no gravity component along it, mu = 0:
     * the gripper cruises at v and the log ends at speed at t_last = 0.2 s.
     * Before t_last the object moves with the gripper (relative rest, no
     * load along the axis). Through the jump it keeps its absolute velocity
     * v (the plates cannot transmit an impulse), so from t_last on its
     * relative velocity is +v exactly, for every method (the state recorded
     * at t_last is the right limit), and it moves v (t_end - t_last)
     * relative to the gripper by t_end. */
    const double v = 0.29;
    double t[21], poses[7 * 21];
    for (int i = 0; i < 21; i++) {
        t[i] = 0.01 * i;
        memset(poses + 7 * i, 0, 7 * sizeof(double));
        poses[7 * i] = v * t[i];
        /* R_AB of the default scene: B y = A z, a quarter turn about A x */
        poses[7 * i + 3] = sqrt(0.5);
        poses[7 * i + 4] = sqrt(0.5);
    }
    for (int method = EXDEX_METHOD_IMPLICIT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_scene_def d = exdex_default_scene_def();
        exdex_model *mo;
        exdex_trajectory tr;
        exdex_stats st;
        double tt[401], q[401], vv[401], w[3 * 401];
        unsigned char stick[401];
        int status;
        d.mu = 0.0;
        d.mass = 0.1;
        d.slide_axis[0] = 1.0; d.slide_axis[1] = 0.0;
        d.method = method;
        d.motion.kind = EXDEX_MOTION_SAMPLED;
        d.motion.n_samples = 21; d.motion.times = t; d.motion.poses = poses;
        mo = exdex_model_alloc(&d, &status, NULL);
        ENSURE(mo != NULL);
        if (!mo) continue;
        tr.n = 401; tr.t = tt; tr.q = q; tr.v = vv; tr.wrench = w; tr.stick = stick; tr.stop_force = NULL;
        ENSURE(exdex_simulate(mo, 0.4, 1e-3, &tr, &st) == EXDEX_OK);
        ENSURE_CLOSE(vv[199], 0.0, 1e-12);    /* t = 0.199: still with the gripper */
        ENSURE_CLOSE(vv[200], v, 1e-12);      /* t = 0.2: the right limit */
        ENSURE_CLOSE(vv[400], v, 1e-12);
        ENSURE_CLOSE(q[400] - q[200], v * 0.2, 1e-12);
        exdex_model_free(mo);
    }
}
