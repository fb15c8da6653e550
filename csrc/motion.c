/* motion.c -- prescribed gripper trajectories (the kinematics of frame B in A).
 *
 * Scalar profiles s(t) (paper Eq. 7 and a trapezoidal velocity) drive either a
 * translation along a unit axis or a rotation about an axis through a point;
 * sampled motions (robot logs) interpolate poses with cubic splines.
 *
 * Conventions fixed here (see also exdex.h):
 * - motion.axis need not be unit: any finite non-zero vector is accepted and
 *   normalised (it is only used by ASYMMETRIC and TRAPEZOID motions).
 * - R0 and p0 may be NULL (identity, zero). They are validated for every kind;
 *   SAMPLED motions use them only with motion.relative.
 * - Every motion is right-continuous in time: at a switching time of a profile
 *   the next phase's value is returned (t >= switch belongs to the next
 *   phase), and a sampled motion is at rest from its last sample time on.
 *   Where the velocity jumps (exdex_motion_jumps) that is its right limit.
 *
 * Sampled motions. Each of the 7 pose components (x y z of the logged
 * frame's origin, and the sign-consistent unit quaternion qw qx qy qz) is a
 * C2 cubic spline in Hermite form: values y_i and slopes m_i at the sample
 * times, the interior slopes solving the tridiagonal continuity conditions of
 * the second derivative,
 *     h_i m_{i-1} + 2 (h_{i-1} + h_i) m_i + h_{i-1} m_{i+1}
 *         = 3 (h_i d_{i-1} + h_{i-1} d_i),   d_i = (y_{i+1} - y_i) / h_i,
 * and the two end slopes prescribed (a clamped spline). The end slopes are
 * the user's (end_given) or come from the data, separately for the position
 * and the orientation and at each end (end_slopes): the end velocity
 * estimated by the quadratic through the three end samples,
 *     v0 = d1 (2 h1 + h2) / (h1 + h2) - d2 h1 / (h1 + h2)
 * (d1, d2 the first two difference quotients counted from the end, h1, h2
 * their intervals; exact for a uniformly accelerated end), is taken, unless
 * the data leave the end pose as a start from rest does:
 *     v0 . D1 <= |D1|^2 / (2 h1),   D1 = y1 - y0 the first displacement,
 * i.e. the estimated end velocity along the first displacement is at most
 * half the mean velocity over the first interval. Then the end is at rest
 * and its slope is 0 (clamped). The test compares two velocities of the
 * same data, so it does not depend on the units of length or time. A log
 * that holds its pose (D1 = 0) or leaves it with a uniform acceleration
 * (v0 = 0) is at rest; one cruising at a constant speed (v0 . D1 = |D1|^2
 * / h1) or decelerating is not; a start accelerating from a speed below
 * a h1 / 2 (the speed the acceleration adds in half an interval, which the
 * samples cannot resolve) counts as at rest.
 *
 * The gripper frame B is the logged frame L composed with two fixed
 * transforms: B(t) = P L(t) X, X = tool_pose (B in the logged flange frame,
 * identity without motion.tool) and P = (R0, p0) (L(t_0) X)^-1 with
 * motion.relative (the log's motion of B replayed from the initial gripper
 * pose; P = identity for absolute poses). Velocities compose exactly: with
 * r = R_L p_X, w_B = R_P w_L, v_B = R_P (v_L + w_L x r), and the
 * accelerations likewise.
 */
#include "exdex.h"
#include "model.h"
#include "util.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.283185307179586476925286766559


/* relative slack of the trapezoid's v_max range check (|X1|/T <= v_max <=
 * 2|X1|/T), so that a bound computed by the caller in floating point passes */
#define TRAP_RANGE_RTOL 1e-12
/* R0 must satisfy R0 R0^T = I and det R0 = 1 to this absolute tolerance */
#define ROT_TOL 1e-9

struct exdex_motion {
    int kind;
    int rotation;
    double axis[3];      /* unit */
    double center[3];
    double R0[9];
    double p0[3];
    double r0[3];        /* rotation: p0 - center */
    /* ASYMMETRIC (Eq. 7): precomputed constants */
    double amplitude, T;
    double a_H, a_L;     /* Eq. 9a, 9b */
    double t_1, t_2;     /* switches beta T, (2 - beta) T */
    /* TRAPEZOID */
    double sign, v_max, t_a, accel;
    /* SAMPLED: the logged frame L, x y z qw qx qy qz, each a clamped cubic
     * spline in Hermite form (values and slopes at the sample times) */
    size_t n;
    double *tk;          /* (n,) sample times */
    double *yk, *mk;     /* (7, n) values and slopes, component-major */
    double t_first, t_last;
    int fixed_R;         /* 1: every quaternion value equal and every slope 0 (B does not turn) */
    double PR[9], Pp[3]; /* B = P L X: P (identity for absolute poses) */
    double XR[9], Xp[3]; /* X = tool pose (identity without a tool) */
    /* velocity jumps of B (exdex_motion_jumps) */
    int n_jumps;
    double jt[EXDEX_MOTION_MAX_JUMPS], jv[EXDEX_MOTION_MAX_JUMPS][3], jw[EXDEX_MOTION_MAX_JUMPS][3];
    double end;          /* exdex_motion_end */
    /* SHAKE: amplitude, T = D, omega = 2 pi f */
    double omega;
    /* CHAIN: pieces, their start times T_i (T0[np] = end) and local origins
     * o_i (a sampled piece plays from its first sample); the pieces' own
     * switching times in (o_i, end_i] and their chain times (phase_fix) */
    int np;
    exdex_motion *piece[EXDEX_MOTION_MAX_PIECES];
    double T0[EXDEX_MOTION_MAX_PIECES + 1], origin[EXDEX_MOTION_MAX_PIECES];
    int n_psw[EXDEX_MOTION_MAX_PIECES];
    double psw[EXDEX_MOTION_MAX_PIECES][4], psw_chain[EXDEX_MOTION_MAX_PIECES][4];
    int n_sw;
    double sw[EXDEX_MOTION_MAX_SWITCHES];
    /* STEP (motion_step_set): position x y z and quaternion qw qx qy qz of
     * B, each a cubic in Hermite form on [st0, st0 + sh]: values sy and
     * slopes sm at the two ends */
    double st0, sh, sy[2][7], sm[2][7];
    /* SHIFT (def.time_shift > 0): the motion inner played from its time shift on */
    exdex_motion *inner;
    double shift;
};

/* the kind of a one-step motion (motion_step_alloc), which
 * exdex_motion_alloc does not make */
#define MOTION_STEP (-1)
/* a motion played from a later time of its own (exdex_motion_def.time_shift) */
#define MOTION_SHIFT (-2)

/* ----------------------------------------------------------- profiles */

/* Eq. 7: a = a_H on [0, bT), a_L on [bT, (2-b)T), a_H on [(2-b)T, 2T).
 * Integrated exactly: the first phase from rest at 0; the middle phase about
 * its vertex at t = T where s = X1, sd = 0; the last phase mirrors the first
 * (a(t) is symmetric about T, so s(2T - tau) = s(tau)). Continuity of s and sd
 * at bT follows from Eq. 9: a_H b T = -a_L (1 - b) T = 2 X1 / T. */
static inline void asym_core(double X1, double T, double a_H, double a_L, double t_1,
                             double t_2, double t, double *s, double *sd, double *sdd)
{
    if (!(t >= 0.0) || t >= 2.0 * T) {
        /* before the start, or back at rest at 0 */
        *s = 0.0; *sd = 0.0; *sdd = 0.0;
    } else if (t < t_1) {
        *s = 0.5 * a_H * t * t; *sd = a_H * t; *sdd = a_H;
    } else if (t < t_2) {
        double u = t - T;
        *s = X1 + 0.5 * a_L * u * u; *sd = a_L * u; *sdd = a_L;
    } else {
        double tau = 2.0 * T - t;
        *s = 0.5 * a_H * tau * tau; *sd = -a_H * tau; *sdd = a_H;
    }
}

/* Trapezoidal velocity: ramp [0, t_a) with acceleration accel, cruise at v_max,
 * symmetric ramp down on [T - t_a, T), at rest at X1 afterwards. t_a == 0 is a
 * constant speed X1/T with velocity jumps at 0 and T (exdex_motion_jumps). */
static inline void trap_core(double X1, double T, double sign, double v_max, double t_a,
                             double accel, double t, double *s, double *sd, double *sdd)
{
    if (!(t >= 0.0) || X1 == 0.0) {
        *s = 0.0; *sd = 0.0; *sdd = 0.0;
    } else if (t >= T) {
        *s = X1; *sd = 0.0; *sdd = 0.0;
    } else if (t < t_a) {
        *s = sign * 0.5 * accel * t * t; *sd = sign * accel * t; *sdd = sign * accel;
    } else if (t < T - t_a) {
        *s = sign * v_max * (t - 0.5 * t_a); *sd = sign * v_max; *sdd = 0.0;
    } else {
        double tau = T - t;
        *s = X1 - sign * 0.5 * accel * tau * tau; *sd = sign * accel * tau; *sdd = -sign * accel;
    }
}

/* Shake: s = A (1 - cos w t) on [0, D), held at s(D) from D on. */
static inline void shake_core(double A, double w, double D, double t, double *s, double *sd, double *sdd)
{
    if (!(t >= 0.0)) {
        *s = 0.0; *sd = 0.0; *sdd = 0.0;
    } else if (t >= D) {
        *s = A * (1.0 - cos(w * D)); *sd = 0.0; *sdd = 0.0;
    } else {
        double c = cos(w * t);
        *s = A * (1.0 - c); *sd = A * w * sin(w * t); *sdd = A * w * w * c;
    }
}

/* ramp time of a trapezoid; NaN when the arguments are out of range */
static double trap_ramp(double X1, double T, double v_max)
{
    double ax = fabs(X1), t_a;
    if (!(T > 0.0) || !isfinite(T) || !isfinite(X1) || !isfinite(v_max)) return NAN;
    if (X1 == 0.0) return (v_max >= 0.0) ? 0.0 : NAN;
    if (!(v_max > 0.0)) return NAN;
    if (v_max < (ax / T) * (1.0 - TRAP_RANGE_RTOL) || v_max > (2.0 * ax / T) * (1.0 + TRAP_RANGE_RTOL))
        return NAN;
    t_a = T - ax / v_max;
    if (t_a < 0.0) t_a = 0.0;            /* v_max a rounding below |X1|/T */
    if (t_a > 0.5 * T) t_a = 0.5 * T;    /* v_max a rounding above 2|X1|/T */
    return t_a;
}

static void put3(double *s, double *sd, double *sdd, double a, double b, double c)
{
    if (s) *s = a;
    if (sd) *sd = b;
    if (sdd) *sdd = c;
}

void exdex_profile_asymmetric(double amplitude, double T, double beta, double t,
                              double *s, double *sd, double *sdd)
{
    double a, b, c;
    if (!(T > 0.0) || !isfinite(T) || !(beta > 0.0 && beta < 1.0) || !isfinite(amplitude)
        || isnan(t)) {
        put3(s, sd, sdd, NAN, NAN, NAN);
        return;
    }
    /* Eq. 9a, 9b */
    asym_core(amplitude, T, 2.0 * amplitude / (beta * T * T),
              2.0 * amplitude / ((beta - 1.0) * T * T), beta * T, (2.0 - beta) * T, t,
              &a, &b, &c);
    put3(s, sd, sdd, a, b, c);
}

void exdex_profile_trapezoid(double amplitude, double T, double v_max, double t,
                             double *s, double *sd, double *sdd)
{
    double a, b, c, t_a = trap_ramp(amplitude, T, v_max);
    if (isnan(t_a) || isnan(t)) {
        put3(s, sd, sdd, NAN, NAN, NAN);
        return;
    }
    trap_core(amplitude, T, amplitude < 0.0 ? -1.0 : 1.0, v_max, t_a,
              t_a > 0.0 ? v_max / t_a : 0.0, t, &a, &b, &c);
    put3(s, sd, sdd, a, b, c);
}

/* --------------------------------------------------------- validation */

static int fail(int *status, const char **bad_param, const char *name)
{
    if (status) *status = EXDEX_EINVAL;
    if (bad_param) *bad_param = name;
    return 0;
}

static int check_rotation_matrix(const double R[9])
{
    double det;
    if (!ex_finite_n(R, 9)) return 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double d = ex_dot3(R + 3 * i, R + 3 * j) - (i == j ? 1.0 : 0.0);
            if (!(fabs(d) <= ROT_TOL)) return 0;
        }
    det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6])
        + R[2] * (R[3] * R[7] - R[4] * R[6]);
    return fabs(det - 1.0) <= ROT_TOL;
}

/* scaled Euclidean norm (no overflow for finite input); 0 or NaN on bad input */
static double norm_n(const double *x, int n)
{
    double big = 0.0, sum = 0.0;
    for (int i = 0; i < n; i++) {
        if (!isfinite(x[i])) return NAN;
        if (fabs(x[i]) > big) big = fabs(x[i]);
    }
    if (big == 0.0) return 0.0;
    for (int i = 0; i < n; i++) sum += (x[i] / big) * (x[i] / big);
    return big * sqrt(sum);
}

/* ------------------------------------------------------ pose helpers */

/* R = R(n) for a unit quaternion n = (w, x, y, z): x_A = n x_B n* */
static void quat_to_R(double R[9], const double n[4])
{
    double w = n[0], x = n[1], y = n[2], z = n[3];
    R[0] = 1.0 - 2.0 * (y * y + z * z); R[1] = 2.0 * (x * y - w * z); R[2] = 2.0 * (x * z + w * y);
    R[3] = 2.0 * (x * y + w * z); R[4] = 1.0 - 2.0 * (x * x + z * z); R[5] = 2.0 * (y * z - w * x);
    R[6] = 2.0 * (x * z - w * y); R[7] = 2.0 * (y * z + w * x); R[8] = 1.0 - 2.0 * (x * x + y * y);
}

/* r = 2 vec(a b*): with a = (a0, A), b = (b0, B), b* = (b0, -B),
 * vec(a b*) = b0 A - a0 B - A x B. */
static void two_vec_conj_product(double r[3], const double a[4], const double b[4])
{
    double c[3];
    ex_cross3(c, a + 1, b + 1);
    for (int i = 0; i < 3; i++) r[i] = 2.0 * (b[0] * a[1 + i] - a[0] * b[1 + i] - c[i]);
}

/* R = A B^T */
static void mulmmt3(double R[9], const double A[9], const double B[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            R[3 * i + j] = A[3 * i] * B[3 * j] + A[3 * i + 1] * B[3 * j + 1] + A[3 * i + 2] * B[3 * j + 2];
}

static void rest_at(exdex_kinematics *k, const double R[9], const double p[3])
{
    memcpy(k->R, R, sizeof k->R);
    memcpy(k->p, p, sizeof k->p);
    for (int i = 0; i < 3; i++) k->v[i] = k->a[i] = k->w[i] = k->dw[i] = 0.0;
}

static void profile_kin(const exdex_motion *m, double s, double sd, double sdd, exdex_kinematics *k);

/* ------------------------------------------------------ alloc / free */

void exdex_motion_free(exdex_motion *m)
{
    if (!m) return;
    exdex_motion_free(m->inner);
    for (int i = 0; i < m->np; i++) exdex_motion_free(m->piece[i]);
    free(m->tk);
    free(m->yk);
    free(m->mk);
    free(m);
}

/* Slope at one end of the sample series y (stride 1, n values at times t)
 * for the components [c0, c1) of a part (position or quaternion), from the
 * data (see the header): end 0 is the first sample, end 1 the last. */
static void end_slopes(const exdex_motion *m, int end, int c0, int c1, double *slope)
{
    size_t n = m->n, i0 = end ? n - 1 : 0, i1 = end ? n - 2 : 1, i2 = end ? n - 3 : 2;
    /* times counted away from the end: h1, h2 > 0 */
    double h1 = fabs(m->tk[i1] - m->tk[i0]), h2 = fabs(m->tk[i2] - m->tk[i1]);
    double v0[4], vd = 0.0, dd = 0.0;
    for (int c = c0; c < c1; c++) {
        const double *y = m->yk + (size_t)c * n;
        double D1 = y[i1] - y[i0], D2 = y[i2] - y[i1];
        /* quadratic through the three samples, slope at the end, in the
         * time running away from the end */
        v0[c - c0] = (D1 / h1) * ((2.0 * h1 + h2) / (h1 + h2)) - (D2 / h2) * (h1 / (h1 + h2));
        vd += v0[c - c0] * D1;
        dd += D1 * D1;
    }
    for (int c = c0; c < c1; c++) {
        double s = vd <= dd / (2.0 * h1) ? 0.0 : v0[c - c0];
        /* back to forward time at the last sample */
        slope[c] = end ? -s : s;
    }
}

/* Slopes m_i of a clamped C2 cubic spline with end slopes m_0, m_{n-1}
 * given (in mk[0], mk[n-1]): the tridiagonal system of the header, solved by
 * the Thomas algorithm (strictly diagonally dominant: no pivoting). w is
 * scratch of n doubles. */
static void clamped_slopes(size_t n, const double *t, const double *y, double *mk, double *w)
{
    if (n == 2) return;
    /* unknowns m_1 .. m_{n-2}; row i: a m_{i-1} + b m_i + c m_{i+1} = r */
    for (size_t i = 1; i + 1 < n; i++) {
        double hl = t[i] - t[i - 1], hr = t[i + 1] - t[i];
        double dl = (y[i] - y[i - 1]) / hl, dr = (y[i + 1] - y[i]) / hr;
        double a = hr, b = 2.0 * (hl + hr), c = hl, r = 3.0 * (hr * dl + hl * dr);
        if (i == 1) r -= a * mk[0];
        if (i + 2 == n) r -= c * mk[n - 1];
        if (i > 1) {
            /* eliminate m_{i-1}: row i-1 reads m_{i-1} + w[i-1] m_i = mk[i-1] */
            b -= a * w[i - 1];
            r -= a * mk[i - 1];
        }
        w[i] = c / b;
        mk[i] = r / b;
    }
    for (size_t i = n - 2; i >= 1; i--) {
        if (i + 2 < n) mk[i] -= w[i] * mk[i + 1];
        if (i == 1) break;
    }
}

/* The cubic with values y0, y1 and slopes m0, m1 at the ends of an
 * interval of length h, at s = (t - start) / h: value, first and second
 * derivatives. */
static void hermite_at(double y0, double y1, double m0, double m1, double h, double s, double *y, double *yd,
                       double *ydd)
{
    double s2 = s * s, s3 = s2 * s, dy = y0 - y1;
    *y = (2.0 * s3 - 3.0 * s2 + 1.0) * y0 + (-2.0 * s3 + 3.0 * s2) * y1
         + h * ((s3 - 2.0 * s2 + s) * m0 + (s3 - s2) * m1);
    *yd = (6.0 * s2 - 6.0 * s) * dy / h + (3.0 * s2 - 4.0 * s + 1.0) * m0 + (3.0 * s2 - 2.0 * s) * m1;
    *ydd = ((12.0 * s - 6.0) * dy / h + (6.0 * s - 4.0) * m0 + (6.0 * s - 2.0) * m1) / h;
}

/* Hermite evaluation of component c on the interval [t_i, t_{i+1}]. */
static void hermite(const exdex_motion *m, int c, size_t i, double t, double *y, double *yd, double *ydd)
{
    const double *Y = m->yk + (size_t)c * m->n, *M = m->mk + (size_t)c * m->n;
    double h = m->tk[i + 1] - m->tk[i], s = (t - m->tk[i]) / h;
    hermite_at(Y[i], Y[i + 1], M[i], M[i + 1], h, s, y, yd, ydd);
}

static int pose_kin(const double y[7], const double yd[7], const double ydd[7], exdex_kinematics *k);

/* Kinematics of the logged frame L on the interval i at time t (s = 1 at
 * t = t_{i+1} gives the left limit there), in the log's coordinates. */
static int eval_log(const exdex_motion *m, size_t i, double t, exdex_kinematics *k)
{
    double y[7], yd[7], ydd[7];
    for (int c = 0; c < 7; c++) hermite(m, c, i, t, &y[c], &yd[c], &ydd[c]);
    return pose_kin(y, yd, ydd, k);
}

/* Kinematics of a frame whose position x y z and (not normalised)
 * quaternion qw qx qy qz are y, with first and second time derivatives yd,
 * ydd. */
static int pose_kin(const double y[7], const double yd[7], const double ydd[7], exdex_kinematics *k)
{
    double n[4], nd[4], ndd[4], qn2 = 0.0, qn, md, mdd;
    for (int j = 0; j < 3; j++) {
        k->p[j] = y[j];
        k->v[j] = yd[j];
        k->a[j] = ydd[j];
    }
    /* n = q/|q| with m = |q|, m' = n.q', m'' = n'.q' + n.q'':
     *   n'  = (q' - n m') / m,   n'' = (q'' - 2 n' m' - n m'') / m */
    for (int c = 0; c < 4; c++) qn2 += y[3 + c] * y[3 + c];
    qn = sqrt(qn2);
    if (!(qn > 0.0) || !isfinite(qn)) return EXDEX_ENONFINITE;
    md = 0.0;
    for (int c = 0; c < 4; c++) {
        n[c] = y[3 + c] / qn;
        md += n[c] * yd[3 + c];
    }
    mdd = 0.0;
    for (int c = 0; c < 4; c++) {
        nd[c] = (yd[3 + c] - n[c] * md) / qn;
        mdd += nd[c] * yd[3 + c] + n[c] * ydd[3 + c];
    }
    for (int c = 0; c < 4; c++) ndd[c] = (ydd[3 + c] - 2.0 * nd[c] * md - n[c] * mdd) / qn;
    quat_to_R(k->R, n);
    /* World-frame angular velocity: d/dt (n x n*) = w x (n x n*) holds for
     * n' = (1/2) w n, so w = 2 vec(n' n*) (the scalar part n'.n is 0).
     * dw = 2 vec(n'' n*) + 2 vec(n' n'*), and n' n'* = |n'|^2 is real. */
    two_vec_conj_product(k->w, nd, n);
    two_vec_conj_product(k->dw, ndd, n);
    return EXDEX_OK;
}

/* B = P L X (see the header): kinematics of B from those of L, in place. */
static int compose(const exdex_motion *m, exdex_kinematics *k)
{
    double r[3], wr[3], t1[3], t2[3], v[3], a[3], RX[9];
    ex_mulmv3(r, k->R, m->Xp);                  /* r = R_L p_X */
    ex_cross3(wr, k->w, r);
    ex_cross3(t1, k->dw, r);
    ex_cross3(t2, k->w, wr);
    for (int j = 0; j < 3; j++) {
        v[j] = k->v[j] + wr[j];
        a[j] = k->a[j] + t1[j] + t2[j];
        r[j] += k->p[j];                        /* origin of B in the log's coordinates */
    }
    ex_mulmm3(RX, k->R, m->XR);
    ex_mulmm3(k->R, m->PR, RX);
    ex_mulmv3(k->p, m->PR, r);
    for (int j = 0; j < 3; j++) k->p[j] += m->Pp[j];
    ex_mulmv3(k->v, m->PR, v);
    ex_mulmv3(k->a, m->PR, a);
    ex_mulmv3(t1, m->PR, k->w);
    memcpy(k->w, t1, sizeof t1);
    ex_mulmv3(t1, m->PR, k->dw);
    memcpy(k->dw, t1, sizeof t1);
    if (!ex_finite_n(k->R, 9) || !ex_finite_n(k->w, 3) || !ex_finite_n(k->dw, 3)
        || !ex_finite_n(k->p, 3) || !ex_finite_n(k->v, 3) || !ex_finite_n(k->a, 3))
        return EXDEX_ENONFINITE;
    return EXDEX_OK;
}

/* Unit quaternion of a pose row's quaternion; 0 if it is zero or not finite. */
static int unit_quat(double n[4], const double q[4])
{
    double qn = norm_n(q, 4);
    if (!(qn > 0.0)) return 0;
    for (int c = 0; c < 4; c++) n[c] = q[c] / qn;
    return ex_finite_n(n, 4);
}

static int setup_sampled(exdex_motion *m, const exdex_motion_def *def, const double R0[9],
                         const double p0[3], int *status, const char **bad_param)
{
    size_t n = def->n_samples;
    double *w;
    static const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (n < 4 || n > ((size_t)-1) / (8 * sizeof(double))) return fail(status, bad_param, "motion.n_samples");
    if (!def->times) return fail(status, bad_param, "motion.times");
    if (!def->poses) return fail(status, bad_param, "motion.poses");
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(def->times[i]) || (i > 0 && !(def->times[i] > def->times[i - 1])))
            return fail(status, bad_param, "motion.times");
        if (!ex_finite_n(def->poses + 7 * i, 7) || !(norm_n(def->poses + 7 * i + 3, 4) > 0.0))
            return fail(status, bad_param, "motion.poses");
    }
    /* every interval must be representable: h > 0 and finite */
    for (size_t i = 1; i < n; i++)
        if (!(isfinite(def->times[i] - def->times[i - 1]))) return fail(status, bad_param, "motion.times");
    for (int e = 0; e < 2; e++) {
        if (def->end_given[e] != 0 && def->end_given[e] != 1) return fail(status, bad_param, "motion.end_given");
        if (def->end_given[e] && !ex_finite_n(def->end_velocity[e], 3))
            return fail(status, bad_param, "motion.end_velocity");
        if (def->end_given[e] && !ex_finite_n(def->end_omega[e], 3))
            return fail(status, bad_param, "motion.end_omega");
    }
    if (def->relative != 0 && def->relative != 1) return fail(status, bad_param, "motion.relative");
    if (def->tool != 0 && def->tool != 1) return fail(status, bad_param, "motion.tool");
    memcpy(m->XR, eye, sizeof m->XR);
    memcpy(m->PR, eye, sizeof m->PR);
    if (def->tool) {
        double nx[4];
        if (!ex_finite_n(def->tool_pose, 3) || !unit_quat(nx, def->tool_pose + 3))
            return fail(status, bad_param, "motion.tool_pose");
        quat_to_R(m->XR, nx);
        memcpy(m->Xp, def->tool_pose, sizeof m->Xp);
    }
    m->n = n;
    m->tk = malloc(n * sizeof *m->tk);
    m->yk = malloc(7 * n * sizeof *m->yk);
    m->mk = malloc(7 * n * sizeof *m->mk);
    w = malloc(n * sizeof *w);
    if (!m->tk || !m->yk || !m->mk || !w) {
        free(w);
        if (status) *status = EXDEX_ENOMEM;
        return 0;
    }
    memcpy(m->tk, def->times, n * sizeof *m->tk);
    for (size_t i = 0; i < n; i++) {
        const double *row = def->poses + 7 * i;
        double qn = norm_n(row + 3, 4), flip = 1.0;
        for (int c = 0; c < 3; c++) m->yk[c * n + i] = row[c];
        /* unit quaternions, sign chosen so consecutive samples have a
         * non-negative dot product (q and -q are the same rotation; the
         * spline must not pass through 0 between them) */
        if (i > 0) {
            double d = 0.0;
            for (int c = 3; c < 7; c++) d += m->yk[c * n + i - 1] * row[c];
            if (d < 0.0) flip = -1.0;
        }
        for (int c = 3; c < 7; c++) m->yk[c * n + i] = flip * row[c] / qn;
    }
    /* end slopes: the user's, or from the data */
    for (int e = 0; e < 2; e++) {
        double sl[7];
        size_t ie = e ? n - 1 : 0;
        if (def->end_given[e]) {
            /* p' = v; n' = (1/2) (0, w) n for the world-frame (log-frame) w */
            double q[4], wq[4];
            for (int c = 0; c < 4; c++) q[c] = m->yk[(3 + c) * n + ie];
            const double *om = def->end_omega[e];
            wq[0] = -(om[0] * q[1] + om[1] * q[2] + om[2] * q[3]);
            wq[1] = om[0] * q[0] + om[1] * q[3] - om[2] * q[2];
            wq[2] = om[1] * q[0] + om[2] * q[1] - om[0] * q[3];
            wq[3] = om[2] * q[0] + om[0] * q[2] - om[1] * q[1];
            for (int c = 0; c < 3; c++) sl[c] = def->end_velocity[e][c];
            for (int c = 0; c < 4; c++) sl[3 + c] = 0.5 * wq[c];
        } else {
            end_slopes(m, e, 0, 3, sl);
            end_slopes(m, e, 3, 7, sl);
        }
        for (int c = 0; c < 7; c++) {
            if (!isfinite(sl[c])) {
                free(w);
                return fail(status, bad_param, def->end_given[e] ? "motion.end_velocity" : "motion.times");
            }
            m->mk[c * n + ie] = sl[c];
        }
    }
    for (int c = 0; c < 7; c++) {
        clamped_slopes(n, m->tk, m->yk + c * n, m->mk + c * n, w);
        for (size_t i = 0; i < n; i++)
            if (!isfinite(m->mk[c * n + i])) {
                free(w);
                return fail(status, bad_param, "motion.times");
            }
    }
    free(w);
    m->t_first = def->times[0];
    m->t_last = def->times[n - 1];
    m->end = m->t_last;
    if (def->relative) {
        /* P = (R0, p0) (L(t_0) X)^-1 */
        double RL[9], nq[4], RLX[9], pLX[3];
        for (int c = 0; c < 4; c++) nq[c] = m->yk[(3 + c) * n];
        quat_to_R(RL, nq);
        ex_mulmm3(RLX, RL, m->XR);
        ex_mulmv3(pLX, RL, m->Xp);
        for (int c = 0; c < 3; c++) pLX[c] += m->yk[c * n];
        mulmmt3(m->PR, R0, RLX);
        ex_mulmv3(m->Pp, m->PR, pLX);
        for (int c = 0; c < 3; c++) m->Pp[c] = p0[c] - m->Pp[c];
        if (!ex_finite_n(m->Pp, 3)) return fail(status, bad_param, "motion.poses");
    }
    /* velocity jumps of B: at the first sample from rest to the spline's
     * start velocity, at the last one back to rest */
    for (int e = 0; e < 2; e++) {
        exdex_kinematics k;
        int st = eval_log(m, e ? n - 2 : 0, e ? m->t_last : m->t_first, &k);
        if (!st) st = compose(m, &k);
        if (st) {
            if (status) *status = EXDEX_EINVAL;
            if (bad_param) *bad_param = "motion.poses";
            return 0;
        }
        if (k.v[0] != 0.0 || k.v[1] != 0.0 || k.v[2] != 0.0 || k.w[0] != 0.0 || k.w[1] != 0.0 || k.w[2] != 0.0) {
            int j = m->n_jumps++;
            m->jt[j] = e ? m->t_last : m->t_first;
            for (int c = 0; c < 3; c++) {
                m->jv[j][c] = e ? -k.v[c] : k.v[c];
                m->jw[j][c] = e ? -k.w[c] : k.w[c];
            }
        }
    }
    m->fixed_R = 1;
    for (int c = 3; c < 7 && m->fixed_R; c++)
        for (size_t i = 0; i < n; i++)
            if (m->yk[c * n + i] != m->yk[c * n] || m->mk[c * n + i] != 0.0) {
                m->fixed_R = 0;
                break;
            }
    return 1;
}
/* Chain tolerances (exdex.h): a position or rotation-matrix mismatch, and a
 * velocity jump, within these relative sizes of the values compared is
 * rounding of the pieces' own evaluation (a relative log replays its first
 * pose from R0, p0 through a product of rotations). */
#define CHAIN_POSE_RTOL 1e-9
#define CHAIN_POS_ATOL 1e-12
#define CHAIN_JUMP_RTOL 1e-9

static const char *const piece_names[EXDEX_MOTION_MAX_PIECES] = {
    "motion.pieces[0]", "motion.pieces[1]", "motion.pieces[2]", "motion.pieces[3]",
    "motion.pieces[4]", "motion.pieces[5]", "motion.pieces[6]", "motion.pieces[7]",
    "motion.pieces[8]", "motion.pieces[9]", "motion.pieces[10]", "motion.pieces[11]",
    "motion.pieces[12]", "motion.pieces[13]", "motion.pieces[14]", "motion.pieces[15]"};

/* Chain time of a piece's own time u (its jumps and switches): its origin
 * and end map exactly onto T_i and T_i+1. */
static double chain_time(const exdex_motion *m, int i, double u)
{
    double o = m->origin[i], e = exdex_motion_end(m->piece[i]);
    if (u == o) return m->T0[i];
    if (u == e && m->piece[i]->kind != EXDEX_MOTION_REST) return m->T0[i + 1];
    return m->T0[i] + (u - o);
}

static int norm3_le(const double a[3], double tol)
{
    return sqrt(ex_dot3(a, a)) <= tol;
}

/* Jumps of a chain: the pieces' own jumps at their chain times, summed where
 * they coincide; at an interior boundary a jump above rounding is an error
 * unless allowed, one within rounding is dropped. 0 on success, else the
 * index + 1 of the piece that starts with a jump. */
static int chain_jumps(exdex_motion *m, int allow)
{
    double t[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    double sv[EXDEX_MOTION_MAX_JUMPS], sw[EXDEX_MOTION_MAX_JUMPS];
    int n = 0;
    for (int i = 0; i < m->np; i++) {
        double pt[EXDEX_MOTION_MAX_JUMPS], pv[EXDEX_MOTION_MAX_JUMPS][3], pw[EXDEX_MOTION_MAX_JUMPS][3];
        int nj = exdex_motion_jumps(m->piece[i], pt, pv, pw);
        for (int j = 0; j < nj; j++) {
            double tc = chain_time(m, i, pt[j]);
            int k = 0;
            while (k < n && t[k] != tc) k++;
            if (k == n) {
                if (n == EXDEX_MOTION_MAX_JUMPS) return i + 1;
                t[n] = tc;
                sv[n] = sw[n] = 0.0;
                for (int c = 0; c < 3; c++) dv[n][c] = dw[n][c] = 0.0;
                n++;
            }
            for (int c = 0; c < 3; c++) {
                dv[k][c] += pv[j][c];
                dw[k][c] += pw[j][c];
            }
            sv[k] += sqrt(ex_dot3(pv[j], pv[j]));
            sw[k] += sqrt(ex_dot3(pw[j], pw[j]));
        }
    }
    m->n_jumps = 0;
    for (int k = 0; k < n; k++) {
        int b = 0;   /* the piece starting at t[k] when it is an interior boundary */
        for (int i = 1; i < m->np; i++)
            if (t[k] == m->T0[i]) b = i;
        if (b && norm3_le(dv[k], CHAIN_JUMP_RTOL * sv[k]) && norm3_le(dw[k], CHAIN_JUMP_RTOL * sw[k]))
            continue;   /* continuous to rounding */
        if (b && !allow) return b + 1;
        m->jt[m->n_jumps] = t[k];
        memcpy(m->jv[m->n_jumps], dv[k], sizeof dv[k]);
        memcpy(m->jw[m->n_jumps], dw[k], sizeof dw[k]);
        m->n_jumps++;
    }
    /* increasing times (pieces in order, each piece's jumps increasing) */
    for (int a = 1; a < m->n_jumps; a++)
        for (int b = a; b > 0 && m->jt[b] < m->jt[b - 1]; b--) {
            double tt = m->jt[b], v[3], w[3];
            memcpy(v, m->jv[b], sizeof v);
            memcpy(w, m->jw[b], sizeof w);
            m->jt[b] = m->jt[b - 1];
            memcpy(m->jv[b], m->jv[b - 1], sizeof v);
            memcpy(m->jw[b], m->jw[b - 1], sizeof w);
            m->jt[b - 1] = tt;
            memcpy(m->jv[b - 1], v, sizeof v);
            memcpy(m->jw[b - 1], w, sizeof w);
        }
    return 0;
}

static int setup_chain(exdex_motion *m, const exdex_motion_def *def, const double R0[9], const double p0[3],
                       int *status, const char **bad_param)
{
    size_t n = def->n_pieces;
    double R[9], p[3], T = 0.0;
    int bad;
    if (n < 1 || n > EXDEX_MOTION_MAX_PIECES) return fail(status, bad_param, "motion.n_pieces");
    if (!def->pieces) return fail(status, bad_param, "motion.pieces");
    if (def->allow_jump != 0 && def->allow_jump != 1) return fail(status, bad_param, "motion.allow_jump");
    memcpy(R, R0, sizeof R);
    memcpy(p, p0, sizeof p);
    for (size_t i = 0; i < n; i++) {
        const exdex_motion_def *pd = &def->pieces[i];
        exdex_motion *c;
        exdex_kinematics k;
        double o, len, sw[EXDEX_MOTION_MAX_SWITCHES], dp[3], tol;
        int st = EXDEX_OK, nsw;
        if (pd->kind == EXDEX_MOTION_CHAIN) return fail(status, bad_param, piece_names[i]);
        if (pd->kind == EXDEX_MOTION_REST && !(pd->duration > 0.0 && isfinite(pd->duration)))
            return fail(status, bad_param, piece_names[i]);
        c = exdex_motion_alloc(pd, R, p, &st, NULL);
        if (!c) {
            if (st == EXDEX_ENOMEM) {
                if (status) *status = st;
                return 0;
            }
            return fail(status, bad_param, piece_names[i]);
        }
        m->piece[m->np++] = c;
        o = c->kind == EXDEX_MOTION_SAMPLED ? c->t_first : 0.0;
        len = c->kind == EXDEX_MOTION_REST ? pd->duration : c->end - o;
        m->origin[i] = o;
        m->T0[i] = T;
        if (!(len > 0.0) || !isfinite(T + len)) return fail(status, bad_param, piece_names[i]);
        /* the piece starts where the one before ended */
        st = exdex_motion_eval(c, o, &k);
        if (st) return fail(status, bad_param, piece_names[i]);
        for (int j = 0; j < 3; j++) dp[j] = k.p[j] - p[j];
        tol = CHAIN_POSE_RTOL * (sqrt(ex_dot3(k.p, k.p)) + sqrt(ex_dot3(p, p))) + CHAIN_POS_ATOL;
        if (!norm3_le(dp, tol)) return fail(status, bad_param, piece_names[i]);
        for (int j = 0; j < 9; j++)
            if (!(fabs(k.R[j] - R[j]) <= CHAIN_POSE_RTOL)) return fail(status, bad_param, piece_names[i]);
        T += len;
        m->T0[i + 1] = T;
        /* its switching times after its origin, and their chain times */
        nsw = exdex_motion_switches(c, sw);
        m->n_psw[i] = 0;
        for (int j = 0; j < nsw; j++)
            if (sw[j] > o && m->n_psw[i] < 4) {
                m->psw[i][m->n_psw[i]] = sw[j];
                m->psw_chain[i][m->n_psw[i]++] = chain_time(m, (int)i, sw[j]);
            }
        /* the pose where it ends: the next piece's start */
        st = exdex_motion_eval(c, c->kind == EXDEX_MOTION_REST ? 0.0 : c->end, &k);
        if (st) return fail(status, bad_param, piece_names[i]);
        memcpy(R, k.R, sizeof R);
        memcpy(p, k.p, sizeof p);
    }
    m->end = T;
    /* switching times: the pieces' own inside each piece, and every boundary */
    m->n_sw = 0;
    for (int i = 0; i < m->np; i++) {
        for (int j = 0; j < m->n_psw[i]; j++) {
            double tc = m->psw_chain[i][j];
            if (tc > m->T0[i] && tc < m->T0[i + 1] && (m->n_sw == 0 || tc > m->sw[m->n_sw - 1]))
                m->sw[m->n_sw++] = tc;
        }
        if (m->n_sw == 0 || m->T0[i + 1] > m->sw[m->n_sw - 1]) m->sw[m->n_sw++] = m->T0[i + 1];
    }
    bad = chain_jumps(m, def->allow_jump);
    if (bad) return fail(status, bad_param, piece_names[bad - 1]);
    return 1;
}

/* Shake (exdex.h): frequency and cycles checked, the end jump when it ends
 * mid-cycle. */
static int setup_shake(exdex_motion *m, const exdex_motion_def *def, int *status, const char **bad_param)
{
    double f = def->frequency, D = def->duration, ph;
    if (!(f > 0.0) || !isfinite(f)) return fail(status, bad_param, "motion.frequency");
    if (!(f * D <= 1e9)) return fail(status, bad_param, "motion.duration");
    m->omega = TWO_PI * f;
    m->end = D;
    ph = m->omega * D;
    if (!isfinite(m->amplitude * m->omega * m->omega)) return fail(status, bad_param, "motion.amplitude");
    {
        /* rounding of the phase: sin(2 pi n) of whole cycles is not 0 in
         * floating point */
        double sn = sin(ph);
        if (fabs(sn) > 16.0 * DBL_EPSILON * ph && m->amplitude != 0.0) {
            exdex_kinematics k1;
            double s, sd, sdd;
            shake_core(m->amplitude, m->omega, D, D, &s, &sd, &sdd);
            profile_kin(m, s, m->amplitude * m->omega * sn, 0.0, &k1);
            m->n_jumps = 1;
            m->jt[0] = D;
            for (int i = 0; i < 3; i++) {
                m->jv[0][i] = -k1.v[i];
                m->jw[0][i] = -k1.w[i];
            }
            if (!ex_finite_n(m->jv[0], 3) || !ex_finite_n(m->jw[0], 3))
                return fail(status, bad_param, "motion.amplitude");
        }
    }
    return 1;
}

exdex_motion *exdex_motion_alloc(const exdex_motion_def *def, const double R0[9],
                                 const double p0[3], int *status,
                                 const char **bad_param)
{
    static const double eye[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    static const double zero[3] = {0, 0, 0};
    exdex_motion *m;
    int ok = 1;

    if (status) *status = EXDEX_OK;
    if (!def) {
        fail(status, bad_param, "motion");
        return NULL;
    }
    if (!R0) R0 = eye;
    if (!p0) p0 = zero;
    if (!check_rotation_matrix(R0)) {
        fail(status, bad_param, "R0");
        return NULL;
    }
    if (!ex_finite_n(p0, 3)) {
        fail(status, bad_param, "p0");
        return NULL;
    }
    if (def->kind < EXDEX_MOTION_REST || def->kind > EXDEX_MOTION_CHAIN) {
        fail(status, bad_param, "motion.kind");
        return NULL;
    }
    if (!(def->time_shift >= 0.0) || !isfinite(def->time_shift)) {
        fail(status, bad_param, "motion.time_shift");
        return NULL;
    }
    if (def->time_shift > 0.0) {
        /* the same motion unshifted, played from time_shift on */
        exdex_motion_def d = *def;
        exdex_motion *in;
        double ts[EXDEX_MOTION_MAX_SWITCHES], jt[EXDEX_MOTION_MAX_JUMPS], jv[EXDEX_MOTION_MAX_JUMPS][3],
            jw[EXDEX_MOTION_MAX_JUMPS][3];
        int ns, nj;
        d.time_shift = 0.0;
        in = exdex_motion_alloc(&d, R0, p0, status, bad_param);
        if (!in) return NULL;
        m = calloc(1, sizeof *m);
        if (!m) {
            exdex_motion_free(in);
            if (status) *status = EXDEX_ENOMEM;
            return NULL;
        }
        m->kind = MOTION_SHIFT;
        m->inner = in;
        m->shift = def->time_shift;
        memcpy(m->R0, R0, sizeof m->R0);
        memcpy(m->p0, p0, sizeof m->p0);
        m->end = in->end > m->shift ? in->end - m->shift : 0.0;
        ns = exdex_motion_switches(in, ts);
        for (int i = 0; i < ns; i++)
            if (ts[i] > m->shift) m->sw[m->n_sw++] = ts[i] - m->shift;
        nj = exdex_motion_jumps(in, jt, jv, jw);
        for (int j = 0; j < nj; j++)
            if (jt[j] > m->shift) {
                m->jt[m->n_jumps] = jt[j] - m->shift;
                memcpy(m->jv[m->n_jumps], jv[j], sizeof jv[j]);
                memcpy(m->jw[m->n_jumps], jw[j], sizeof jw[j]);
                m->n_jumps++;
            }
        return m;
    }

    m = calloc(1, sizeof *m);
    if (!m) {
        if (status) *status = EXDEX_ENOMEM;
        return NULL;
    }
    m->kind = def->kind;
    memcpy(m->R0, R0, sizeof m->R0);
    memcpy(m->p0, p0, sizeof m->p0);

    if (def->kind == EXDEX_MOTION_ASYMMETRIC || def->kind == EXDEX_MOTION_TRAPEZOID ||
        def->kind == EXDEX_MOTION_SHAKE) {
        double na = norm_n(def->axis, 3), X1 = def->amplitude, T = def->duration;
        if (def->rotation != 0 && def->rotation != 1)
            ok = fail(status, bad_param, "motion.rotation");
        else if (!(na > 0.0))
            ok = fail(status, bad_param, "motion.axis");
        else if (def->rotation && !ex_finite_n(def->center, 3))
            ok = fail(status, bad_param, "motion.center");
        else if (!isfinite(X1))
            ok = fail(status, bad_param, "motion.amplitude");
        else if (!(T > 0.0) || !isfinite(T))
            ok = fail(status, bad_param, "motion.duration");
        if (ok) {
            m->rotation = def->rotation;
            /* scale by the largest component first: na itself overflows to
             * inf for components near DBL_MAX (the axis would become 0 and
             * Rot(axis, s) lose orthonormality) */
            double big = 0.0, sum = 0.0;
            for (int i = 0; i < 3; i++)
                if (fabs(def->axis[i]) > big) big = fabs(def->axis[i]);
            for (int i = 0; i < 3; i++) sum += (def->axis[i] / big) * (def->axis[i] / big);
            for (int i = 0; i < 3; i++) m->axis[i] = (def->axis[i] / big) / sqrt(sum);
            if (m->rotation)
                for (int i = 0; i < 3; i++) {
                    m->center[i] = def->center[i];
                    m->r0[i] = p0[i] - def->center[i];
                }
            m->amplitude = X1;
            m->T = T;
        }
        if (ok && def->kind == EXDEX_MOTION_SHAKE) {
            ok = setup_shake(m, def, status, bad_param);
        } else if (ok && def->kind == EXDEX_MOTION_ASYMMETRIC) {
            double b = def->beta;
            if (!(b > 0.0 && b < 1.0)) {
                ok = fail(status, bad_param, "motion.beta");
            } else {
                m->a_H = 2.0 * X1 / (b * T * T);           /* Eq. 9a */
                m->a_L = 2.0 * X1 / ((b - 1.0) * T * T);   /* Eq. 9b */
                m->t_1 = b * T;
                m->t_2 = (2.0 - b) * T;
                m->end = 2.0 * T;
                if (!isfinite(m->a_H) || !isfinite(m->a_L) || !isfinite(m->end))
                    ok = fail(status, bad_param, "motion.amplitude");
            }
        } else if (ok) {
            double t_a = trap_ramp(X1, T, def->v_max);
            if (isnan(t_a)) {
                ok = fail(status, bad_param, "motion.v_max");
            } else {
                m->sign = X1 < 0.0 ? -1.0 : 1.0;
                m->v_max = def->v_max;
                m->t_a = t_a;
                m->accel = t_a > 0.0 ? def->v_max / t_a : 0.0;
                m->end = T;
                if (!isfinite(m->accel)) ok = fail(status, bad_param, "motion.v_max");
                if (ok && t_a == 0.0 && X1 != 0.0) {
                    /* constant speed: a jump from rest at 0 and back to rest at T */
                    exdex_kinematics k0, k1;
                    profile_kin(m, 0.0, m->sign * m->v_max, 0.0, &k0);
                    profile_kin(m, X1, m->sign * m->v_max, 0.0, &k1);
                    m->n_jumps = 2;
                    m->jt[0] = 0.0;
                    m->jt[1] = T;
                    for (int i = 0; i < 3; i++) {
                        m->jv[0][i] = k0.v[i];
                        m->jw[0][i] = k0.w[i];
                        m->jv[1][i] = -k1.v[i];
                        m->jw[1][i] = -k1.w[i];
                    }
                    if (!ex_finite_n(m->jv[0], 3) || !ex_finite_n(m->jv[1], 3))
                        ok = fail(status, bad_param, "motion.v_max");
                }
            }
        }
    } else if (def->kind == EXDEX_MOTION_SAMPLED) {
        ok = setup_sampled(m, def, R0, p0, status, bad_param);
    } else if (def->kind == EXDEX_MOTION_CHAIN) {
        ok = setup_chain(m, def, R0, p0, status, bad_param);
    } else {
        m->end = 0.0;  /* REST */
    }
    if (!ok) {
        exdex_motion_free(m);
        return NULL;
    }
    return m;
}

double exdex_motion_end(const exdex_motion *m)
{
    return m ? m->end : NAN;
}

int exdex_motion_jumps(const exdex_motion *m, double t[EXDEX_MOTION_MAX_JUMPS],
                       double dv[EXDEX_MOTION_MAX_JUMPS][3], double dw[EXDEX_MOTION_MAX_JUMPS][3])
{
    if (!m) return 0;
    for (int j = 0; j < m->n_jumps; j++) {
        if (t) t[j] = m->jt[j];
        if (dv) memcpy(dv[j], m->jv[j], sizeof m->jv[j]);
        if (dw) memcpy(dw[j], m->jw[j], sizeof m->jw[j]);
    }
    return m->n_jumps;
}

/* The switching times of m as a non-decreasing list: the kind's own (at
 * most 3, written to c) or a chain's; *list points at them. */
static int switch_list(const exdex_motion *m, double c[3], const double **list)
{
    int n = 0;
    *list = c;
    switch (m->kind) {
    case EXDEX_MOTION_ASYMMETRIC:
        c[n++] = m->t_1;
        c[n++] = m->t_2;
        c[n++] = m->end;
        break;
    case EXDEX_MOTION_TRAPEZOID:
        if (m->amplitude == 0.0) break;
        c[n++] = m->t_a;
        c[n++] = m->T - m->t_a;
        c[n++] = m->T;
        break;
    case EXDEX_MOTION_SAMPLED:
        c[n++] = m->t_first;
        c[n++] = m->t_last;
        break;
    case EXDEX_MOTION_SHAKE:
        c[n++] = m->end;
        break;
    case EXDEX_MOTION_CHAIN:
    case MOTION_SHIFT:
        *list = m->sw;
        n = m->n_sw;
        break;
    default:
        break;
    }
    return n;
}

int exdex_motion_switches(const exdex_motion *m, double ts[EXDEX_MOTION_MAX_SWITCHES])
{
    double c[3];
    const double *list;
    int n, k = 0;
    if (!m) return 0;
    n = switch_list(m, c, &list);
    /* increasing, without repeats (a trapezoid without ramps, or with two
     * ramps meeting at T/2) */
    for (int i = 0; i < n; i++)
        if (k == 0 || list[i] > ts[k - 1]) ts[k++] = list[i];
    return k;
}

double exdex_motion_next_switch(const exdex_motion *m, double lo)
{
    double c[3];
    const double *list;
    int n, a = 0, b;
    if (!m) return INFINITY;
    n = switch_list(m, c, &list);
    /* every list is non-decreasing: bisect for its first entry above lo */
    b = n;
    while (a < b) {
        int mid = a + (b - a) / 2;
        if (list[mid] > lo) b = mid;
        else a = mid + 1;
    }
    return a < n ? list[a] : INFINITY;
}

/* The first knot of a sampled log's splines above t (exdex.h), on the
 * motion's own time: its sample times, t_first for t before it, INFINITY
 * from t_last on. */
static double sampled_next_knot(const exdex_motion *m, double t)
{
    size_t lo = 0, hi = m->n - 1;
    if (!(t < m->t_last)) return INFINITY;
    if (t < m->t_first) return m->t_first;
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (m->tk[mid] <= t) lo = mid;
        else hi = mid;
    }
    return m->tk[hi];
}

double exdex_motion_next_knot(const exdex_motion *m, double t)
{
    int i = 0;
    double u, k;
    if (!m) return INFINITY;
    if (m->kind == EXDEX_MOTION_SAMPLED) return sampled_next_knot(m, t);
    if (m->kind == MOTION_SHIFT) {
        /* the inner motion's knots above t + shift, on this motion's time
         * (the first one the rounding of k - shift leaves above t) */
        for (k = exdex_motion_next_knot(m->inner, t + m->shift); isfinite(k);
             k = exdex_motion_next_knot(m->inner, k))
            if (k - m->shift > t) return k - m->shift;
        return INFINITY;
    }
    if (m->kind != EXDEX_MOTION_CHAIN) return INFINITY;
    /* the piece holding t (as eval_chain), a sampled one's knots on its
     * own time u = t - T_i + o_i mapped to chain time; its end T_i+1 is a
     * switching time */
    while (i + 1 < m->np && t >= m->T0[i + 1]) i++;
    if (m->piece[i]->kind != EXDEX_MOTION_SAMPLED) return INFINITY;
    u = t - m->T0[i] + m->origin[i];
    for (k = sampled_next_knot(m->piece[i], u); isfinite(k); k = sampled_next_knot(m->piece[i], k)) {
        double tc = chain_time(m, i, k);
        if (!(tc < m->T0[i + 1])) break;
        if (tc > t) return tc;  /* the rounding of u may put t at or past it */
    }
    return INFINITY;
}

/* ------------------------------------------------------------ evaluation */

static int eval_sampled(const exdex_motion *m, double t, exdex_kinematics *k)
{
    size_t lo = 0, hi = m->n - 1;
    if (t < m->t_first || t >= m->t_last) {
        /* at rest at the end pose (right-continuous at t_last) */
        size_t i = t < m->t_first ? 0 : m->n - 1;
        double nq[4];
        for (int c = 0; c < 4; c++) nq[c] = m->yk[(3 + c) * m->n + i];
        for (int c = 0; c < 3; c++) k->p[c] = m->yk[c * m->n + i];
        quat_to_R(k->R, nq);
        for (int c = 0; c < 3; c++) k->v[c] = k->a[c] = k->w[c] = k->dw[c] = 0.0;
        return compose(m, k);
    }
    /* the interval [t_lo, t_lo+1) holding t (binary search, no shared state) */
    while (hi - lo > 1) {
        size_t mid = lo + (hi - lo) / 2;
        if (m->tk[mid] <= t) lo = mid;
        else hi = mid;
    }
    if (eval_log(m, lo, t, k)) return EXDEX_ENONFINITE;
    return compose(m, k);
}

/* Kinematics of a profile motion at the profile value (s, sd, sdd). */
static void profile_kin(const exdex_motion *m, double s, double sd, double sdd, exdex_kinematics *k)
{
    if (!m->rotation) {
        /* p = p0 + s axis, R = R0 */
        memcpy(k->R, m->R0, sizeof k->R);
        for (int i = 0; i < 3; i++) {
            k->p[i] = m->p0[i] + s * m->axis[i];
            k->v[i] = sd * m->axis[i];
            k->a[i] = sdd * m->axis[i];
            k->w[i] = 0.0;
            k->dw[i] = 0.0;
        }
    } else {
        /* R = Rot(axis, s) R0, p = c + Rot(axis, s)(p0 - c); with r = p - c:
         * w = sd axis, dw = sdd axis, v = w x r, a = dw x r + w x (w x r) */
        double Q[9], r[3], wr[3], t1[3], t2[3];
        ex_axis_angle(Q, m->axis, s);
        ex_mulmm3(k->R, Q, m->R0);
        ex_mulmv3(r, Q, m->r0);
        for (int i = 0; i < 3; i++) {
            k->p[i] = m->center[i] + r[i];
            k->w[i] = sd * m->axis[i];
            k->dw[i] = sdd * m->axis[i];
        }
        ex_cross3(wr, k->w, r);
        ex_cross3(t1, k->dw, r);
        ex_cross3(t2, k->w, wr);
        for (int i = 0; i < 3; i++) {
            k->v[i] = wr[i];
            k->a[i] = t1[i] + t2[i];
        }
    }
}

/* A chain at time t: the piece holding t (right-continuous at every T_i),
 * on its own time u = t - T_i + o_i, with u put on the same side of each of
 * the piece's switching times as t is of the switch's chain time (the
 * rounding of t - T_i + o_i must not move t across a phase switch). */
static int eval_chain(const exdex_motion *m, double t, exdex_kinematics *k)
{
    int i = 0;
    double u;
    while (i + 1 < m->np && t >= m->T0[i + 1]) i++;
    u = t - m->T0[i] + m->origin[i];
    for (int j = 0; j < m->n_psw[i]; j++) {
        double s = m->psw[i][j];
        if (t >= m->psw_chain[i][j] && u < s) u = s;
        else if (t < m->psw_chain[i][j] && u >= s) u = nextafter(s, -INFINITY);
    }
    return exdex_motion_eval(m->piece[i], u, k);
}

/* ---------------------------------------------------- one-step motion */

exdex_motion *motion_step_alloc(void)
{
    exdex_motion *m = calloc(1, sizeof *m);
    if (!m) return NULL;
    m->kind = MOTION_STEP;
    m->sh = 1.0;
    m->sy[0][3] = m->sy[1][3] = 1.0;
    m->end = INFINITY;
    return m;
}

/* Quaternion (w, x, y, z) of a rotation matrix (Shepperd: from the largest
 * of the four squared components, so no cancellation). */
static void R_to_quat(double q[4], const double R[9])
{
    double tr = R[0] + R[4] + R[8], d[4] = {tr, R[0], R[4], R[8]}, r;
    int i = 0;
    for (int j = 1; j < 4; j++)
        if (d[j] > d[i]) i = j;
    if (i == 0) {
        r = sqrt(1.0 + tr);
        q[0] = 0.5 * r;
        q[1] = 0.5 * (R[7] - R[5]) / r;
        q[2] = 0.5 * (R[2] - R[6]) / r;
        q[3] = 0.5 * (R[3] - R[1]) / r;
    } else if (i == 1) {
        r = sqrt(1.0 + R[0] - R[4] - R[8]);
        q[0] = 0.5 * (R[7] - R[5]) / r;
        q[1] = 0.5 * r;
        q[2] = 0.5 * (R[1] + R[3]) / r;
        q[3] = 0.5 * (R[2] + R[6]) / r;
    } else if (i == 2) {
        r = sqrt(1.0 - R[0] + R[4] - R[8]);
        q[0] = 0.5 * (R[2] - R[6]) / r;
        q[1] = 0.5 * (R[1] + R[3]) / r;
        q[2] = 0.5 * r;
        q[3] = 0.5 * (R[5] + R[7]) / r;
    } else {
        r = sqrt(1.0 - R[0] - R[4] + R[8]);
        q[0] = 0.5 * (R[3] - R[1]) / r;
        q[1] = 0.5 * (R[2] + R[6]) / r;
        q[2] = 0.5 * (R[5] + R[7]) / r;
        q[3] = 0.5 * r;
    }
}

/* The quaternion's rate n' = (1/2) (0, w) n for the angular velocity w in A
 * (the convention of eval_log: w = 2 vec(n' n*)). */
static void quat_rate(double nd[4], const double n[4], const double w[3])
{
    double c[3];
    ex_cross3(c, w, n + 1);
    nd[0] = -0.5 * (w[0] * n[1] + w[1] * n[2] + w[2] * n[3]);
    for (int i = 0; i < 3; i++) nd[1 + i] = 0.5 * (n[0] * w[i] + c[i]);
}

int motion_step_set(exdex_motion *m, double t0, double t1, const exdex_kinematics *k0, const double R1[9],
                    const double p1[3], const double *v1, const double *w1, exdex_kinematics *k1)
{
    double n0[4], n1[4], dot = 0.0, nd[4], v[3], w[3], h = t1 - t0;
    if (!m || m->kind != MOTION_STEP || !k0 || !R1 || !p1) return EXDEX_EINVAL;
    if (!(isfinite(t0) && isfinite(t1) && t1 > t0 && isfinite(h))) return EXDEX_EINVAL;
    if (!check_rotation_matrix(R1) || !ex_finite_n(p1, 3) || (v1 && !ex_finite_n(v1, 3)) ||
        (w1 && !ex_finite_n(w1, 3)))
        return EXDEX_EINVAL;
    if (!ex_finite_n(k0->R, 9) || !ex_finite_n(k0->p, 3) || !ex_finite_n(k0->v, 3) || !ex_finite_n(k0->w, 3))
        return EXDEX_EINVAL;
    R_to_quat(n0, k0->R);
    R_to_quat(n1, R1);
    /* the end quaternion on the start's side: the shorter way round */
    for (int c = 0; c < 4; c++) dot += n0[c] * n1[c];
    if (dot < 0.0)
        for (int c = 0; c < 4; c++) n1[c] = -n1[c];
    /* the secants of the step where no end twist is given: the mean
     * velocity (p1 - p0) / h, and the constant angular velocity that turns
     * R0 into R1 over h, angle 2 atan2(|vec r|, r_w) about vec r for
     * r = n1 n0* (r_w = n1 . n0 >= 0) */
    for (int j = 0; j < 3; j++) v[j] = v1 ? v1[j] : (p1[j] - k0->p[j]) / h;
    if (w1) {
        memcpy(w, w1, sizeof w);
    } else {
        double r[3], rn, ang;
        two_vec_conj_product(r, n1, n0);   /* 2 vec(n1 n0*) */
        rn = norm_n(r, 3);
        ang = 2.0 * atan2(0.5 * rn, fabs(dot));
        for (int j = 0; j < 3; j++) w[j] = rn > 0.0 ? ang / h * (r[j] / rn) : 0.0;
    }
    if (!ex_finite_n(v, 3) || !ex_finite_n(w, 3)) return EXDEX_EINVAL;
    m->st0 = t0;
    m->sh = h;
    for (int j = 0; j < 3; j++) {
        m->sy[0][j] = k0->p[j];
        m->sy[1][j] = p1[j];
        m->sm[0][j] = k0->v[j];
        m->sm[1][j] = v[j];
    }
    if (k1) {
        memcpy(k1->R, R1, sizeof k1->R);
        memcpy(k1->p, p1, sizeof k1->p);
        memcpy(k1->v, v, sizeof k1->v);
        memcpy(k1->w, w, sizeof k1->w);
        for (int j = 0; j < 3; j++) k1->a[j] = k1->dw[j] = 0.0;
    }
    quat_rate(nd, n0, k0->w);
    for (int c = 0; c < 4; c++) {
        m->sy[0][3 + c] = n0[c];
        m->sm[0][3 + c] = nd[c];
    }
    quat_rate(nd, n1, w);
    for (int c = 0; c < 4; c++) {
        m->sy[1][3 + c] = n1[c];
        m->sm[1][3 + c] = nd[c];
    }
    m->end = t1;
    return EXDEX_OK;
}

static int eval_step(const exdex_motion *m, double t, exdex_kinematics *k)
{
    double y[7], yd[7], ydd[7], s = (t - m->st0) / m->sh;
    for (int c = 0; c < 7; c++) hermite_at(m->sy[0][c], m->sy[1][c], m->sm[0][c], m->sm[1][c], m->sh, s, &y[c], &yd[c],
                                           &ydd[c]);
    if (pose_kin(y, yd, ydd, k)) return EXDEX_ENONFINITE;
    if (!ex_finite_n(k->p, 3) || !ex_finite_n(k->v, 3) || !ex_finite_n(k->a, 3) || !ex_finite_n(k->w, 3) ||
        !ex_finite_n(k->dw, 3))
        return EXDEX_ENONFINITE;
    return EXDEX_OK;
}

int exdex_motion_eval(const exdex_motion *m, double t, exdex_kinematics *k)
{
    double s, sd, sdd;
    if (!m || !k || isnan(t)) return EXDEX_EINVAL;
    switch (m->kind) {
    case MOTION_SHIFT:
        return exdex_motion_eval(m->inner, t + m->shift, k);
    case MOTION_STEP:
        return eval_step(m, t, k);
    case EXDEX_MOTION_SHAKE:
        shake_core(m->amplitude, m->omega, m->T, t, &s, &sd, &sdd);
        break;
    case EXDEX_MOTION_CHAIN:
        return eval_chain(m, t, k);
    case EXDEX_MOTION_ASYMMETRIC:
        asym_core(m->amplitude, m->T, m->a_H, m->a_L, m->t_1, m->t_2, t, &s, &sd, &sdd);
        break;
    case EXDEX_MOTION_TRAPEZOID:
        trap_core(m->amplitude, m->T, m->sign, m->v_max, m->t_a, m->accel, t, &s, &sd, &sdd);
        break;
    case EXDEX_MOTION_SAMPLED:
        return eval_sampled(m, t, k);
    default:
        rest_at(k, m->R0, m->p0);
        return EXDEX_OK;
    }
    profile_kin(m, s, sd, sdd, k);
    /* a finite profile can still overflow for absurd amplitudes */
    if (!isfinite(s) || !isfinite(sd) || !isfinite(sdd) || !ex_finite_n(k->p, 3) || !ex_finite_n(k->v, 3)
        || !ex_finite_n(k->a, 3))
        return EXDEX_ENONFINITE;
    return EXDEX_OK;
}

/* ------------------------------------------- acceleration bounds (model.h) */

static void box_add(double lo[3], double hi[3], const double a[3])
{
    for (int c = 0; c < 3; c++) {
        if (a[c] < lo[c]) lo[c] = a[c];
        if (a[c] > hi[c]) hi[c] = a[c];
    }
}

/* the profile's acceleration sdd in [s0, s1] along the unit axis */
static void box_axis(const exdex_motion *m, double s0, double s1, double lo[3], double hi[3])
{
    double a[3], b[3];
    for (int c = 0; c < 3; c++) {
        a[c] = s0 * m->axis[c];
        b[c] = s1 * m->axis[c];
    }
    box_add(lo, hi, a);
    box_add(lo, hi, b);
}

static int accel_box(const exdex_motion *m, double ta, double tb, double lo[3], double hi[3])
{
    static const double zero[3] = {0.0, 0.0, 0.0};
    switch (m->kind) {
    case EXDEX_MOTION_REST:
        box_add(lo, hi, zero);
        return 1;
    case MOTION_SHIFT:
        return accel_box(m->inner, ta + m->shift, tb + m->shift, lo, hi);
    case EXDEX_MOTION_ASYMMETRIC:
    case EXDEX_MOTION_TRAPEZOID: {
        /* piecewise constant: its values at ta and at each switch in (ta, tb] */
        double c[3], s, sd, sdd, smin, smax;
        const double *list;
        int n = switch_list(m, c, &list);
        if (m->rotation) return 0;
        if (m->kind == EXDEX_MOTION_ASYMMETRIC) asym_core(m->amplitude, m->T, m->a_H, m->a_L, m->t_1, m->t_2, ta, &s, &sd, &sdd);
        else trap_core(m->amplitude, m->T, m->sign, m->v_max, m->t_a, m->accel, ta, &s, &sd, &sdd);
        smin = smax = sdd;
        for (int i = 0; i < n; i++) {
            if (!(list[i] > ta && list[i] <= tb)) continue;
            if (m->kind == EXDEX_MOTION_ASYMMETRIC)
                asym_core(m->amplitude, m->T, m->a_H, m->a_L, m->t_1, m->t_2, list[i], &s, &sd, &sdd);
            else trap_core(m->amplitude, m->T, m->sign, m->v_max, m->t_a, m->accel, list[i], &s, &sd, &sdd);
            smin = fmin(smin, sdd);
            smax = fmax(smax, sdd);
        }
        box_axis(m, smin, smax, lo, hi);
        return 1;
    }
    case EXDEX_MOTION_SHAKE: {
        /* sdd = A w^2 cos(w t) on [0, D), 0 outside */
        double a = fmax(ta, 0.0), b = fmin(tb, m->T), A = m->amplitude * m->omega * m->omega, cmin, cmax;
        if (m->rotation) return 0;
        if (ta < 0.0 || tb >= m->T) box_add(lo, hi, zero);
        if (!(a <= b) || (a == b && b >= m->T)) return 1;
        {
            double pa = m->omega * a, pb = m->omega * b, ca = cos(pa), cb = cos(pb);
            /* the phase's multiples of pi inside [pa, pb] */
            const double pi = 3.14159265358979323846;
            double k0 = ceil(pa / pi), k1 = floor(pb / pi);
            cmin = fmin(ca, cb);
            cmax = fmax(ca, cb);
            for (double k = k0; k <= k1 && k <= k0 + 1.0; k++) {
                if (fmod(k, 2.0) == 0.0) cmax = 1.0;
                else cmin = -1.0;
            }
            /* widened by the rounding of cos at the samples' phases */
            cmin = fmax(-1.0, cmin - 1e-12);
            cmax = fmin(1.0, cmax + 1e-12);
        }
        box_axis(m, A * cmin, A * cmax, lo, hi);
        return 1;
    }
    case EXDEX_MOTION_SAMPLED: {
        /* B does not turn: its acceleration is linear in time between two
         * knots (cubic positions), so the box of its values at ta, tb and
         * the knots between bounds it */
        exdex_kinematics k;
        size_t n = m->n, i;
        double a = fmax(ta, m->t_first), b = fmin(tb, m->t_last);
        if (!m->fixed_R) return 0;
        if (ta < m->t_first || tb >= m->t_last) box_add(lo, hi, zero);
        if (!(a < b)) return 1;
        /* the interval [tk[i], tk[i+1]) holding a */
        {
            size_t l = 0, h = n - 1;
            while (h - l > 1) {
                size_t mid = l + (h - l) / 2;
                if (m->tk[mid] <= a) l = mid;
                else h = mid;
            }
            i = l;
        }
        if (eval_log(m, i, a, &k) || compose(m, &k)) return 0;
        box_add(lo, hi, k.a);
        for (; i + 1 < n && m->tk[i + 1] < b; i++) {
            if (eval_log(m, i + 1, m->tk[i + 1], &k) || compose(m, &k)) return 0;
            box_add(lo, hi, k.a);
        }
        if (eval_log(m, i, b, &k) || compose(m, &k)) return 0;
        box_add(lo, hi, k.a);
        return 1;
    }
    case EXDEX_MOTION_CHAIN: {
        /* each piece on its own time (the chain's rounding of t - T_i + o_i
         * moves a time by at most a few ulp across a switch, whose two sides
         * the pieces' boxes hold) */
        for (int i = 0; i < m->np; i++) {
            double a = m->T0[i], b = i + 1 < m->np ? m->T0[i + 1] : INFINITY, u0, u1;
            if (tb < a || ta >= b) continue;
            u0 = fmax(ta, a) - m->T0[i] + m->origin[i];
            u1 = fmin(tb, b) - m->T0[i] + m->origin[i];
            if (!(u1 < INFINITY)) u1 = tb - m->T0[i] + m->origin[i];
            if (!accel_box(m->piece[i], u0 - 1e-12 * (1.0 + fabs(u0)), u1 + 1e-12 * (1.0 + fabs(u1)), lo, hi))
                return 0;
        }
        return 1;
    }
    default:
        return 0;
    }
}

int motion_accel_box(const exdex_motion *m, double ta, double tb, double lo[3], double hi[3])
{
    if (!m || !(ta <= tb)) return 0;
    for (int c = 0; c < 3; c++) {
        lo[c] = INFINITY;
        hi[c] = -INFINITY;
    }
    return accel_box(m, ta, tb, lo, hi);
}

/* --------------------------------------------- frame enclosures (model.h)
 * Intervals (util.h: outward rounding, so each holds the exact values of
 * its formula over its operands' intervals) of the frame's quantities in
 * B over [ta, tb], by kind:
 *   profiles and shakes: the profile s, sd, sdd over [ta, tb] (between
 *     the profile's switching times Eq. 7 and the trapezoid have a constant
 *     sdd, so sd is linear and s quadratic: sd between its end values, s
 *     between its end values and, where sd changes sign, its vertex
 *     s0 - sd0^2 / (2 sdd); a shake's phase w t in [w a, w b] gives cos and
 *     sin over it); translating: R = R0, a0 = R0^T sdd axis; turning about
 *     the axis k through the centre c (R = Rot(k, s) R0, r = Rot(k, s) r0):
 *     R^T w = sd u, R^T dw = sdd u (u = R0^T k: Rot(k, s)^T k = k),
 *     R^T a = sdd u x r0B + sd^2 u x (u x r0B) (r0B = R0^T r0: a rotation
 *     keeps cross products) and R^T g = R0^T (g_k + cos s g_perp - sin s
 *     k x g), g_k = (k . g) k;
 *   logs: on each knot interval every component of the pose row is the
 *     cubic of hermite_at in s = (t - t_i) / h, its range over the
 *     interval's s the hull of its Bernstein coefficients (convex hull
 *     property; the same for the derivative's quadratic and the second
 *     derivative's line). With q the quaternion row (not normalised,
 *     D = |q|^2 > 0) and n = q / |q|: n* n' = q* q' / D - (|q|' / |q|) is
 *     the body rate's quaternion less a real part, so the rate in L's
 *     body axes is w_L = 2 vec(q* q') / D and its derivative
 *     dw_L = 2 vec(q* q'') / D - w_L D' / D (vec(q*' q') = 0), D' = 2 q . q';
 *     R_L^T x = ((q0^2 - |Q|^2) x + 2 (Q . x) Q - 2 q0 Q x x) / D. With
 *     B = P L X (the header): R_B^T w_B = XR^T w_L, R_B^T dw_B = XR^T dw_L,
 *     R_B^T a_B = XR^T (R_L^T a_L + dw_L x Xp + w_L x (w_L x Xp)) and
 *     R_B^T g = XR^T R_L^T PR^T g; at rest before and after the log;
 *   chains: each piece over the part of [ta, tb] it plays, on its own
 *     time (widened by 1e-12 of it, as motion_accel_box does), so a block
 *     that holds a piece's start is enclosed on both sides of it;
 *   rest: its pose.
 * The enclosure bounds the exact formulas; model_frame_at evaluates them
 * in floating point (some hundred operations on numbers bounded by the
 * quantity's scale: |g|; |w|; |dw| + |w|^2; |a0| + the lever arm
 * (|r0|, |Xp|) times |dw| + |w|^2), so the result is widened by 1e-10 of
 * that scale (far beyond their rounding, far below the load's margins). */
typedef struct fbox {
    frame_box b;
    double mag[4];   /* g_B, a0, w, dw: the scales of their rounding */
} fbox;

static ex_iv iv_empty(void)
{
    ex_iv r = {INFINITY, -INFINITY};
    return r;
}

static void fb_add(fbox *F, const ex_iv gB[3], const ex_iv a0[3], const ex_iv w[3], const ex_iv dw[3],
                   const double mag[4])
{
    for (int c = 0; c < 3; c++) {
        F->b.gB[c] = ex_iv_hull(F->b.gB[c], gB[c]);
        F->b.a0[c] = ex_iv_hull(F->b.a0[c], a0[c]);
        F->b.w[c] = ex_iv_hull(F->b.w[c], w[c]);
        F->b.dw[c] = ex_iv_hull(F->b.dw[c], dw[c]);
    }
    for (int k = 0; k < 4; k++) F->mag[k] = ex_max(F->mag[k], mag[k]);
}

static double iv3_mag(const ex_iv a[3])
{
    return ex_iv_mag(a[0]) + ex_iv_mag(a[1]) + ex_iv_mag(a[2]);
}

/* the frame of one instant's kinematics k */
static void fb_add_kin(fbox *F, const exdex_kinematics *k, const double g[3])
{
    ex_iv gv[3], av[3], wv[3], dv[3], gB[3], a0[3], w[3], dw[3];
    double mag[4];
    for (int c = 0; c < 3; c++) {
        gv[c] = ex_iv_pt(g[c]);
        av[c] = ex_iv_pt(k->a[c]);
        wv[c] = ex_iv_pt(k->w[c]);
        dv[c] = ex_iv_pt(k->dw[c]);
    }
    ex_iv_mulmtv3(gB, k->R, gv);
    ex_iv_mulmtv3(a0, k->R, av);
    ex_iv_mulmtv3(w, k->R, wv);
    ex_iv_mulmtv3(dw, k->R, dv);
    mag[0] = iv3_mag(gB);
    mag[1] = iv3_mag(a0);
    mag[2] = iv3_mag(w);
    mag[3] = iv3_mag(dw);
    fb_add(F, gB, a0, w, dw, mag);
}

static void iv_add_pt(ex_iv *r, double x)
{
    *r = ex_iv_hull(*r, ex_iv_out(x, x));
}

/* s, sd, sdd of a profile or shake over [ta, tb] (hulled into s[3]) */
static int profile_ranges(const exdex_motion *m, double ta, double tb, ex_iv s[3])
{
    double v[3];
    if (m->kind == EXDEX_MOTION_SHAKE) {
        double a = fmax(ta, 0.0), b = fmin(tb, m->T);
        if (ta < 0.0)
            for (int j = 0; j < 3; j++) iv_add_pt(&s[j], 0.0);
        if (tb >= m->T) {
            shake_core(m->amplitude, m->omega, m->T, m->T, &v[0], &v[1], &v[2]);
            for (int j = 0; j < 3; j++) iv_add_pt(&s[j], v[j]);
        }
        if (a <= b && a < m->T) {
            ex_iv ph = ex_iv_mul(ex_iv_pt(m->omega), (ex_iv){a, b}), cs = ex_iv_cos_sin(ph, 0), sn = ex_iv_cos_sin(ph, 1);
            ex_iv A = ex_iv_pt(m->amplitude), Aw = ex_iv_mul(A, ex_iv_pt(m->omega));
            s[0] = ex_iv_hull(s[0], ex_iv_mul(A, ex_iv_sub(ex_iv_pt(1.0), cs)));
            s[1] = ex_iv_hull(s[1], ex_iv_mul(Aw, sn));
            s[2] = ex_iv_hull(s[2], ex_iv_mul(ex_iv_mul(Aw, ex_iv_pt(m->omega)), cs));
        }
        return 1;
    }
    if (m->kind == EXDEX_MOTION_ASYMMETRIC || m->kind == EXDEX_MOTION_TRAPEZOID) {
        double c[3], cut[6];
        const double *list;
        int n = switch_list(m, c, &list), nc = 0;
        cut[nc++] = ta;
        if (0.0 > ta && 0.0 < tb) cut[nc++] = 0.0;   /* the start: at rest before it */
        for (int i = 0; i < n; i++)
            if (list[i] > ta && list[i] < tb) cut[nc++] = list[i];
        cut[nc++] = tb;
        for (int i = 0; i < nc; i++) {
            /* [cut[i], cut[i+1]): its start and the left limit at its end; and tb itself */
            double x = cut[i], y = i + 1 < nc ? nextafter(cut[i + 1], -INFINITY) : cut[i], v1[3];
            if (y < x) y = x;
            if (m->kind == EXDEX_MOTION_ASYMMETRIC) {
                asym_core(m->amplitude, m->T, m->a_H, m->a_L, m->t_1, m->t_2, x, &v[0], &v[1], &v[2]);
                asym_core(m->amplitude, m->T, m->a_H, m->a_L, m->t_1, m->t_2, y, &v1[0], &v1[1], &v1[2]);
            } else {
                trap_core(m->amplitude, m->T, m->sign, m->v_max, m->t_a, m->accel, x, &v[0], &v[1], &v[2]);
                trap_core(m->amplitude, m->T, m->sign, m->v_max, m->t_a, m->accel, y, &v1[0], &v1[1], &v1[2]);
            }
            if (v[2] != v1[2]) return 0;   /* not one phase: not a switching time the list knows */
            for (int j = 0; j < 3; j++) {
                iv_add_pt(&s[j], v[j]);
                iv_add_pt(&s[j], v1[j]);
            }
            if ((v[1] < 0.0 && v1[1] > 0.0) || (v[1] > 0.0 && v1[1] < 0.0)) {
                /* sd = 0 inside: the vertex s0 - sd0^2 / (2 sdd) */
                ex_iv sv = ex_iv_sub(ex_iv_pt(v[0]), ex_iv_div_pos(ex_iv_sqr(ex_iv_pt(v[1])), ex_iv_pt(2.0 * fabs(v[2]))));
                if (v[2] < 0.0) sv = ex_iv_add(ex_iv_pt(v[0]), ex_iv_div_pos(ex_iv_sqr(ex_iv_pt(v[1])), ex_iv_pt(2.0 * fabs(v[2]))));
                s[0] = ex_iv_hull(s[0], sv);
            }
        }
        return 1;
    }
    return 0;
}

static int profile_box(const exdex_motion *m, double ta, double tb, const double g[3], fbox *F)
{
    ex_iv s[3] = {iv_empty(), iv_empty(), iv_empty()}, gB[3], a0[3], w[3], dw[3], t[3];
    double mag[4];
    if (!profile_ranges(m, ta, tb, s)) return 0;
    if (!m->rotation) {
        ex_iv gv[3];
        for (int c = 0; c < 3; c++) {
            gv[c] = ex_iv_pt(g[c]);
            t[c] = ex_iv_scale(m->axis[c], s[2]);
            w[c] = dw[c] = ex_iv_pt(0.0);
        }
        ex_iv_mulmtv3(gB, m->R0, gv);
        ex_iv_mulmtv3(a0, m->R0, t);
        mag[0] = iv3_mag(gB);
        mag[1] = ex_iv_mag(s[2]);
        mag[2] = mag[3] = 0.0;
    } else {
        double u[3], r0B[3], ur[3], uur[3], gk = ex_dot3(m->axis, g), kg[3], gA0[3];
        ex_iv cs = ex_iv_cos_sin(s[0], 0), sn = ex_iv_cos_sin(s[0], 1), sd2 = ex_iv_sqr(s[1]), gA[3];
        ex_mulmtv3(u, m->R0, m->axis);
        ex_mulmtv3(r0B, m->R0, m->r0);
        ex_cross3(ur, u, r0B);
        ex_cross3(uur, u, ur);
        ex_cross3(kg, m->axis, g);
        for (int c = 0; c < 3; c++) {
            double gp = gk * m->axis[c];
            gA0[c] = gp;
            /* g_k + cos s (g - g_k) - sin s k x g */
            gA[c] = ex_iv_sub(ex_iv_add(ex_iv_pt(gp), ex_iv_mul(cs, ex_iv_sub(ex_iv_pt(g[c]), ex_iv_pt(gp)))),
                              ex_iv_scale(kg[c], sn));
            w[c] = ex_iv_scale(u[c], s[1]);
            dw[c] = ex_iv_scale(u[c], s[2]);
            a0[c] = ex_iv_add(ex_iv_scale(ur[c], s[2]), ex_iv_scale(uur[c], sd2));
        }
        (void)gA0;
        ex_iv_mulmtv3(gB, m->R0, gA);
        mag[0] = sqrt(ex_dot3(g, g)) * 3.0;
        mag[2] = ex_iv_mag(s[1]);
        mag[3] = ex_iv_mag(s[2]) + mag[2] * mag[2];
        mag[1] = iv3_mag(a0) + sqrt(ex_dot3(m->r0, m->r0)) * 3.0 * mag[3];
    }
    fb_add(F, gB, a0, w, dw, mag);
    return 1;
}

/* The range of a_0 + a_1 s + ... + a_deg s^deg (deg <= 3) over S: the hull
 * of its Bernstein coefficients on S (the polynomial Taylor-shifted to
 * S.lo, the k-th coefficient times L^k, L = S.hi - S.lo). */
static ex_iv poly_range(const ex_iv *a, int deg, ex_iv S)
{
    static const double binom[4][4] = {{1, 0, 0, 0}, {1, 1, 0, 0}, {1, 2, 1, 0}, {1, 3, 3, 1}};
    ex_iv c[4], L = ex_iv_sub(ex_iv_pt(S.hi), ex_iv_pt(S.lo)), Lk = ex_iv_pt(1.0), r = iv_empty();
    ex_iv sa = ex_iv_pt(S.lo);
    if (L.lo < 0.0) L.lo = 0.0;
    for (int k = 0; k <= deg; k++) {
        /* c_k = sum_{j >= k} C(j, k) a_j sa^(j - k), times L^k */
        ex_iv acc = ex_iv_pt(0.0), p = ex_iv_pt(1.0);
        for (int j = k; j <= deg; j++) {
            acc = ex_iv_add(acc, ex_iv_scale(binom[j][k], ex_iv_mul(a[j], p)));
            p = ex_iv_mul(p, sa);
        }
        c[k] = ex_iv_mul(acc, Lk);
        Lk = ex_iv_mul(Lk, L);
    }
    for (int i = 0; i <= deg; i++) {
        /* b_i = sum_{k <= i} C(i, k) / C(deg, k) c_k */
        ex_iv b = ex_iv_pt(0.0);
        for (int k = 0; k <= i; k++) b = ex_iv_add(b, ex_iv_mul(ex_iv_div_pos(ex_iv_pt(binom[i][k]), ex_iv_pt(binom[deg][k])), c[k]));
        r = ex_iv_hull(r, b);
    }
    return r;
}

/* vec(a* b) of quaternions (a0, A), (b0, B): a0 B - b0 A - A x B */
static void iv_vec_conj(ex_iv r[3], const ex_iv a[4], const ex_iv b[4])
{
    ex_iv x[3];
    ex_iv_cross3(x, a + 1, b + 1);
    for (int i = 0; i < 3; i++) r[i] = ex_iv_sub(ex_iv_sub(ex_iv_mul(a[0], b[1 + i]), ex_iv_mul(b[0], a[1 + i])), x[i]);
}

/* R(q)^T x |q|^2 = (q0^2 - |Q|^2) x + 2 (Q . x) Q - 2 q0 Q x x */
static void iv_rot_t(ex_iv r[3], const ex_iv q[4], const ex_iv x[3], ex_iv D)
{
    ex_iv qq = ex_iv_sub(ex_iv_sqr(q[0]), ex_iv_add(ex_iv_add(ex_iv_sqr(q[1]), ex_iv_sqr(q[2])), ex_iv_sqr(q[3])));
    ex_iv qx = ex_iv_dot3(q + 1, x), cr[3];
    ex_iv_cross3(cr, q + 1, x);
    for (int i = 0; i < 3; i++)
        r[i] = ex_iv_div_pos(ex_iv_sub(ex_iv_add(ex_iv_mul(qq, x[i]), ex_iv_scale(2.0, ex_iv_mul(qx, q[1 + i]))),
                                       ex_iv_scale(2.0, ex_iv_mul(q[0], cr[i]))),
                             D);
}

/* knot interval i of a log over [x, y] inside it */
static int knot_box(const exdex_motion *m, size_t i, double x, double y, const double g[3], fbox *F)
{
    double h = m->tk[i + 1] - m->tk[i];
    ex_iv S, Y[7], YD[7], YDD[7], D, Dd, wl[3], dwl[3], t1[3], t2[3], gP[3], gL[3], aL[3], xp[3], wxp[3];
    ex_iv gB[3], a0[3], w[3], dw[3], H = ex_iv_pt(h);
    double mag[4], PRg[3];
    S.lo = ex_iv_div_pos(ex_iv_sub(ex_iv_pt(x), ex_iv_pt(m->tk[i])), H).lo;
    S.hi = ex_iv_div_pos(ex_iv_sub(ex_iv_pt(y), ex_iv_pt(m->tk[i])), H).hi;
    if (!ex_iv_ok(S)) return 0;
    for (int c = 0; c < 7; c++) {
        double y0 = m->yk[(size_t)c * m->n + i], y1 = m->yk[(size_t)c * m->n + i + 1];
        double m0 = m->mk[(size_t)c * m->n + i], m1 = m->mk[(size_t)c * m->n + i + 1];
        ex_iv a[4], d[3], dd[2], hm0 = ex_iv_mul(H, ex_iv_pt(m0)), hm1 = ex_iv_mul(H, ex_iv_pt(m1));
        a[0] = ex_iv_pt(y0);
        a[1] = hm0;
        a[2] = ex_iv_sub(ex_iv_sub(ex_iv_scale(3.0, ex_iv_sub(ex_iv_pt(y1), ex_iv_pt(y0))), ex_iv_scale(2.0, hm0)), hm1);
        a[3] = ex_iv_add(ex_iv_add(ex_iv_scale(2.0, ex_iv_sub(ex_iv_pt(y0), ex_iv_pt(y1))), hm0), hm1);
        d[0] = a[1];
        d[1] = ex_iv_scale(2.0, a[2]);
        d[2] = ex_iv_scale(3.0, a[3]);
        dd[0] = d[1];
        dd[1] = ex_iv_scale(6.0, a[3]);
        if (x == m->tk[i] && y == m->tk[i + 1]) {
            /* the whole interval, s in [0, 1] (the motion's s = (t - t_i) / h
             * is 0 at t_i and 1 at t_i+1, monotone between): the Hermite form's Bernstein
             * coefficients y0, y0 + h m0 / 3, y1 - h m1 / 3, y1; the
             * derivative's (in s) h m0, 3 (y1 - y0) - h (m0 + m1), h m1 and
             * the second's 2 a2, 2 a2 + 6 a3 (a_k the power coefficients) */
            ex_iv y0i = ex_iv_pt(y0), y1i = ex_iv_pt(y1), b1 = ex_iv_add(y0i, ex_iv_scale(1.0 / 3.0, hm0));
            ex_iv b2 = ex_iv_sub(y1i, ex_iv_scale(1.0 / 3.0, hm1));
            ex_iv mid = ex_iv_sub(ex_iv_scale(3.0, ex_iv_sub(y1i, y0i)), ex_iv_add(hm0, hm1));
            /* 1/3 is rounded: the exact third lies within 2^-54 of it, a
             * relative error the hull below is widened by */
            b1.lo -= ex_iv_mag(hm0) * 0x1p-53;
            b1.hi += ex_iv_mag(hm0) * 0x1p-53;
            b2.lo -= ex_iv_mag(hm1) * 0x1p-53;
            b2.hi += ex_iv_mag(hm1) * 0x1p-53;
            Y[c] = ex_iv_hull(ex_iv_hull(y0i, y1i), ex_iv_hull(b1, b2));
            YD[c] = ex_iv_div_pos(ex_iv_hull(ex_iv_hull(hm0, hm1), mid), H);
            YDD[c] = ex_iv_div_pos(ex_iv_hull(dd[0], ex_iv_add(dd[0], dd[1])), ex_iv_sqr(H));
        } else {
            Y[c] = poly_range(a, 3, S);
            YD[c] = ex_iv_div_pos(poly_range(d, 2, S), H);
            YDD[c] = ex_iv_div_pos(poly_range(dd, 1, S), ex_iv_sqr(H));
        }
    }
    D = ex_iv_add(ex_iv_add(ex_iv_sqr(Y[3]), ex_iv_sqr(Y[4])), ex_iv_add(ex_iv_sqr(Y[5]), ex_iv_sqr(Y[6])));
    Dd = ex_iv_pt(0.0);
    for (int c = 0; c < 4; c++) Dd = ex_iv_add(Dd, ex_iv_mul(Y[3 + c], YD[3 + c]));
    Dd = ex_iv_scale(2.0, Dd);
    if (!(D.lo > 0.0)) return 0;
    iv_vec_conj(t1, Y + 3, YD + 3);
    iv_vec_conj(t2, Y + 3, YDD + 3);
    for (int c = 0; c < 3; c++) wl[c] = ex_iv_div_pos(ex_iv_scale(2.0, t1[c]), D);
    for (int c = 0; c < 3; c++)
        dwl[c] = ex_iv_sub(ex_iv_div_pos(ex_iv_scale(2.0, t2[c]), D), ex_iv_div_pos(ex_iv_mul(wl[c], Dd), D));
    /* gravity: XR^T R_L^T PR^T g */
    ex_mulmtv3(PRg, m->PR, g);
    for (int c = 0; c < 3; c++) gP[c] = ex_iv_pt(PRg[c]);
    iv_rot_t(gL, Y + 3, gP, D);
    ex_iv_mulmtv3(gB, m->XR, gL);
    /* the origin: XR^T (R_L^T a_L + dw_L x Xp + w_L x (w_L x Xp)) */
    iv_rot_t(aL, Y + 3, YDD, D);
    for (int c = 0; c < 3; c++) xp[c] = ex_iv_pt(m->Xp[c]);
    ex_iv_cross3(t1, dwl, xp);
    ex_iv_cross3(wxp, wl, xp);
    ex_iv_cross3(t2, wl, wxp);
    for (int c = 0; c < 3; c++) t1[c] = ex_iv_add(ex_iv_add(aL[c], t1[c]), t2[c]);
    ex_iv_mulmtv3(a0, m->XR, t1);
    ex_iv_mulmtv3(w, m->XR, wl);
    ex_iv_mulmtv3(dw, m->XR, dwl);
    mag[0] = 3.0 * sqrt(ex_dot3(g, g));
    mag[2] = iv3_mag(w);
    mag[3] = iv3_mag(dw) + mag[2] * mag[2];
    mag[1] = iv3_mag(aL) + iv3_mag(YDD) + 3.0 * sqrt(ex_dot3(m->Xp, m->Xp)) * mag[3];
    fb_add(F, gB, a0, w, dw, mag);
    return 1;
}

/* The boxes of a log's whole knot intervals (knot_box over [t_i, t_i+1]),
 * each computed once per cache: the box of a block across several is the
 * hull of those it meets, the same box as computing each interval anew
 * (hulls and maxima are exact and do not depend on their order). */
typedef struct fb_entry {
    const exdex_motion *m;   /* the sampled motion node */
    fbox *box;               /* box[i]: interval i, valid where state[i] == 1 */
    unsigned char *state;    /* 0 not computed, 1 computed, 2 knot_box failed */
} fb_entry;

struct frame_box_cache {
    double g[3];
    int n;
    fb_entry e[FRAME_BOX_CACHE_LOGS];
};

frame_box_cache *motion_frame_cache_new(const double g[3])
{
    frame_box_cache *c;
    if (!g) return NULL;
    c = calloc(1, sizeof *c);
    if (!c) return NULL;
    for (int k = 0; k < 3; k++) c->g[k] = g[k];
    return c;
}

void motion_frame_cache_free(frame_box_cache *c)
{
    if (!c) return;
    for (int k = 0; k < c->n; k++) {
        free(c->e[k].box);
        free(c->e[k].state);
    }
    free(c);
}

/* the cache's intervals of the sampled node m for gravity g; NULL where
 * there is none (no cache, another g, the cache full, no memory) */
static fb_entry *fb_entry_of(frame_box_cache *c, const exdex_motion *m, const double g[3])
{
    fb_entry *e;
    if (!c || m->n < 2 || c->g[0] != g[0] || c->g[1] != g[1] || c->g[2] != g[2]) return NULL;
    for (int k = 0; k < c->n; k++)
        if (c->e[k].m == m) return c->e[k].box ? &c->e[k] : NULL;
    if (c->n == FRAME_BOX_CACHE_LOGS) return NULL;
    e = &c->e[c->n++];
    e->m = m;
    e->box = malloc((m->n - 1) * sizeof *e->box);
    e->state = calloc(m->n - 1, 1);
    if (!e->box || !e->state) {
        free(e->box);
        free(e->state);
        e->box = NULL;
        e->state = NULL;
        return NULL;
    }
    return e;
}

/* knot_box over the whole interval i, from the cache where it holds it */
static int whole_knot_box(const exdex_motion *m, size_t i, const double g[3], fbox *F, fb_entry *e)
{
    fbox *B;
    if (!e) return knot_box(m, i, m->tk[i], m->tk[i + 1], g, F);
    B = &e->box[i];
    if (!e->state[i]) {
        for (int c = 0; c < 3; c++) B->b.gB[c] = B->b.a0[c] = B->b.w[c] = B->b.dw[c] = iv_empty();
        for (int k = 0; k < 4; k++) B->mag[k] = 0.0;
        e->state[i] = knot_box(m, i, m->tk[i], m->tk[i + 1], g, B) ? 1 : 2;
    }
    if (e->state[i] != 1) return 0;
    fb_add(F, B->b.gB, B->b.a0, B->b.w, B->b.dw, B->mag);
    return 1;
}

static int sampled_box(const exdex_motion *m, double ta, double tb, const double g[3], fbox *F,
                       frame_box_cache *cache)
{
    size_t n = m->n, i;
    double a = fmax(ta, m->t_first), b = fmin(tb, m->t_last);
    exdex_kinematics k;
    fb_entry *e = NULL;
    int one;
    if (ta < m->t_first) {
        if (eval_sampled(m, ta, &k)) return 0;
        fb_add_kin(F, &k, g);
    }
    if (tb >= m->t_last) {
        if (eval_sampled(m, tb, &k)) return 0;
        fb_add_kin(F, &k, g);
    }
    if (!(a <= b && a < m->t_last)) return 1;
    {
        size_t l = 0, hh = n - 1;
        while (hh - l > 1) {
            size_t mid = l + (hh - l) / 2;
            if (m->tk[mid] <= a) l = mid;
            else hh = mid;
        }
        i = l;
    }
    /* [a, b] inside one knot interval: the box of that part; across
     * several: the hull of the whole intervals it meets (each a bound of
     * its parts, computed once per cache) */
    one = i + 2 >= n || !(m->tk[i + 1] < b);
    for (;;) {
        double x = fmax(a, m->tk[i]), y = fmin(b, m->tk[i + 1]);
        if ((x == m->tk[i] && y == m->tk[i + 1]) || !one) {
            if (!e && cache) e = fb_entry_of(cache, m, g);
            if (!whole_knot_box(m, i, g, F, e)) return 0;
        } else if (!knot_box(m, i, x, y, g, F)) {
            return 0;
        }
        if (!(i + 2 < n && m->tk[i + 1] < b)) break;
        i++;
    }
    return 1;
}

static int frame_box_of(const exdex_motion *m, double ta, double tb, const double g[3], fbox *F,
                        frame_box_cache *cache)
{
    exdex_kinematics k;
    switch (m->kind) {
    case EXDEX_MOTION_REST:
        if (exdex_motion_eval(m, ta, &k)) return 0;
        fb_add_kin(F, &k, g);
        return 1;
    case MOTION_SHIFT:
        return frame_box_of(m->inner, ta + m->shift, tb + m->shift, g, F, cache);
    case EXDEX_MOTION_ASYMMETRIC:
    case EXDEX_MOTION_TRAPEZOID:
    case EXDEX_MOTION_SHAKE:
        return profile_box(m, ta, tb, g, F);
    case EXDEX_MOTION_SAMPLED:
        return sampled_box(m, ta, tb, g, F, cache);
    case EXDEX_MOTION_CHAIN:
        /* the first piece plays before the chain's start too (eval_chain) */
        for (int i = 0; i < m->np; i++) {
            double a = i ? m->T0[i] : -INFINITY, b = i + 1 < m->np ? m->T0[i + 1] : INFINITY, u0, u1;
            if (tb < a || ta >= b) continue;
            u0 = fmax(ta, a) - m->T0[i] + m->origin[i];
            u1 = fmin(tb, b) - m->T0[i] + m->origin[i];
            if (!(u1 < INFINITY)) u1 = tb - m->T0[i] + m->origin[i];
            if (!frame_box_of(m->piece[i], u0 - 1e-12 * (1.0 + fabs(u0)), u1 + 1e-12 * (1.0 + fabs(u1)), g, F,
                              cache)) return 0;
        }
        return 1;
    default:
        return 0;
    }
}

int motion_frame_box_cached(const exdex_motion *m, double ta, double tb, const double g[3], frame_box *fb,
                            frame_box_cache *cache)
{
    fbox F;
    if (!m || !fb || !(ta <= tb)) return 0;
    for (int c = 0; c < 3; c++) F.b.gB[c] = F.b.a0[c] = F.b.w[c] = F.b.dw[c] = iv_empty();
    for (int k = 0; k < 4; k++) F.mag[k] = 0.0;
    if (!frame_box_of(m, ta, tb, g, &F, cache)) return 0;
    for (int c = 0; c < 3; c++) {
        ex_iv *q[4] = {&F.b.gB[c], &F.b.a0[c], &F.b.w[c], &F.b.dw[c]};
        for (int k = 0; k < 4; k++) {
            double e = 1e-10 * F.mag[k];
            q[k]->lo -= e;
            q[k]->hi += e;
            if (!ex_iv_ok(*q[k])) return 0;
        }
    }
    *fb = F.b;
    return 1;
}

int motion_frame_box(const exdex_motion *m, double ta, double tb, const double g[3], frame_box *fb)
{
    return motion_frame_box_cached(m, ta, tb, g, fb, NULL);
}
