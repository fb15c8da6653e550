/* motion.c -- prescribed gripper trajectories (the kinematics of frame B in A).
 *
 * Scalar profiles s(t) (paper Eq. 7 and a trapezoidal velocity) drive either a
 * translation along a unit axis or a rotation about an axis through a point;
 * sampled motions interpolate absolute poses with GSL cubic splines.
 *
 * Conventions fixed here (see also exdex.h):
 * - motion.axis need not be unit: any finite non-zero vector is accepted and
 *   normalised (it is only used by ASYMMETRIC and TRAPEZOID motions).
 * - R0 and p0 may be NULL (identity, zero). They are validated for every kind
 *   but ignored by SAMPLED motions, whose poses are absolute.
 * - At a switching time of a profile the right-continuous value is returned
 *   (t >= switch belongs to the next phase).
 * - A trapezoid of zero amplitude is the rest profile; its v_max is then only
 *   required to be finite and >= 0.
 */
#include "exdex.h"
#include "util.h"

#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_interp.h>
#include <gsl/gsl_spline.h>

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
    /* SAMPLED: x y z qw qx qy qz, each a natural cubic spline of time */
    gsl_spline *spline[7];
    double t_first, t_last;
    double pose_first[7], pose_last[7];  /* unit, sign-consistent quaternions */
    double end;          /* exdex_motion_end */
};

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
 * constant speed X1/T with velocity jumps at 0 and T (no impulse reported). */
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

/* ------------------------------------------------------ alloc / free */

void exdex_motion_free(exdex_motion *m)
{
    if (!m) return;
    for (int i = 0; i < 7; i++) gsl_spline_free(m->spline[i]);  /* NULL-safe */
    free(m);
}

static int setup_sampled(exdex_motion *m, const exdex_motion_def *def, int *status,
                         const char **bad_param)
{
    size_t n = def->n_samples;
    double *y;
    if (n < 4 || n > ((size_t)-1) / (8 * sizeof(double))) return fail(status, bad_param, "motion.n_samples");
    if (!def->times) return fail(status, bad_param, "motion.times");
    if (!def->poses) return fail(status, bad_param, "motion.poses");
    for (size_t i = 0; i < n; i++) {
        if (!isfinite(def->times[i]) || (i > 0 && !(def->times[i] > def->times[i - 1])))
            return fail(status, bad_param, "motion.times");
        if (!ex_finite_n(def->poses + 7 * i, 7) || !(norm_n(def->poses + 7 * i + 3, 4) > 0.0))
            return fail(status, bad_param, "motion.poses");
    }
    /* y: the 7 component series, each contiguous (n,) */
    y = malloc(7 * n * sizeof *y);
    if (!y) {
        if (status) *status = EXDEX_ENOMEM;
        return 0;
    }
    for (size_t i = 0; i < n; i++) {
        const double *row = def->poses + 7 * i;
        double qn = norm_n(row + 3, 4), flip = 1.0;
        for (int c = 0; c < 3; c++) y[c * n + i] = row[c];
        /* unit quaternions, sign chosen so consecutive samples have a
         * non-negative dot product (q and -q are the same rotation; the
         * spline must not pass through 0 between them) */
        if (i > 0) {
            double d = 0.0;
            for (int c = 3; c < 7; c++) d += y[c * n + i - 1] * row[c];
            if (d < 0.0) flip = -1.0;
        }
        for (int c = 3; c < 7; c++) y[c * n + i] = flip * row[c] / qn;
    }
    for (int c = 0; c < 7; c++) {
        m->spline[c] = gsl_spline_alloc(gsl_interp_cspline, n);
        if (!m->spline[c] || gsl_spline_init(m->spline[c], def->times, y + c * n, n) != GSL_SUCCESS) {
            free(y);
            if (status) *status = m->spline[c] ? EXDEX_EINVAL : EXDEX_ENOMEM;
            if (m->spline[c] && bad_param) *bad_param = "motion.times";
            return 0;
        }
        m->pose_first[c] = y[c * n];
        m->pose_last[c] = y[c * n + n - 1];
    }
    free(y);
    m->t_first = def->times[0];
    m->t_last = def->times[n - 1];
    m->end = m->t_last;
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
    if (def->kind < EXDEX_MOTION_REST || def->kind > EXDEX_MOTION_SAMPLED) {
        fail(status, bad_param, "motion.kind");
        return NULL;
    }

    m = calloc(1, sizeof *m);
    if (!m) {
        if (status) *status = EXDEX_ENOMEM;
        return NULL;
    }
    m->kind = def->kind;
    memcpy(m->R0, R0, sizeof m->R0);
    memcpy(m->p0, p0, sizeof m->p0);

    if (def->kind == EXDEX_MOTION_ASYMMETRIC || def->kind == EXDEX_MOTION_TRAPEZOID) {
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
             * inf for components near DBL_MAX (found by fuzzing: the axis
             * became 0 and Rot(axis, s) lost orthonormality) */
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
        if (ok && def->kind == EXDEX_MOTION_ASYMMETRIC) {
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
            }
        }
    } else if (def->kind == EXDEX_MOTION_SAMPLED) {
        ok = setup_sampled(m, def, status, bad_param);
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

/* ------------------------------------------------------------ evaluation */

static void rest_at(exdex_kinematics *k, const double R[9], const double p[3])
{
    memcpy(k->R, R, sizeof k->R);
    memcpy(k->p, p, sizeof k->p);
    for (int i = 0; i < 3; i++) k->v[i] = k->a[i] = k->w[i] = k->dw[i] = 0.0;
}

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

static void pose_at_rest(exdex_kinematics *k, const double pose[7])
{
    double R[9];
    quat_to_R(R, pose + 3);
    rest_at(k, R, pose);
}

static int eval_sampled(const exdex_motion *m, double t, exdex_kinematics *k)
{
    double y[7], yd[7], ydd[7], n[4], nd[4], ndd[4], qn2 = 0.0, qn, md, mdd;
    /* A stack accelerator: the search cost is paid once for the 21 spline
     * evaluations below, and nothing in the model is written (thread-safe). */
    gsl_interp_accel acc = {0, 0, 0};

    if (t < m->t_first) {
        pose_at_rest(k, m->pose_first);
        return EXDEX_OK;
    }
    if (t > m->t_last) {
        pose_at_rest(k, m->pose_last);
        return EXDEX_OK;
    }
    for (int c = 0; c < 7; c++) {
        if (gsl_spline_eval_e(m->spline[c], t, &acc, &y[c]) != GSL_SUCCESS
            || gsl_spline_eval_deriv_e(m->spline[c], t, &acc, &yd[c]) != GSL_SUCCESS
            || gsl_spline_eval_deriv2_e(m->spline[c], t, &acc, &ydd[c]) != GSL_SUCCESS)
            return EXDEX_EINVAL;
    }
    for (int i = 0; i < 3; i++) {
        k->p[i] = y[i];
        k->v[i] = yd[i];
        k->a[i] = ydd[i];
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
    if (!ex_finite_n(k->R, 9) || !ex_finite_n(k->w, 3) || !ex_finite_n(k->dw, 3)
        || !ex_finite_n(k->p, 3) || !ex_finite_n(k->v, 3) || !ex_finite_n(k->a, 3))
        return EXDEX_ENONFINITE;
    return EXDEX_OK;
}

int exdex_motion_eval(const exdex_motion *m, double t, exdex_kinematics *k)
{
    double s, sd, sdd;
    if (!m || !k || isnan(t)) return EXDEX_EINVAL;
    switch (m->kind) {
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
        if (!ex_finite_n(k->v, 3) || !ex_finite_n(k->a, 3) || !ex_finite_n(k->p, 3))
            return EXDEX_ENONFINITE;
    }
    /* a finite profile can still overflow for absurd amplitudes (found by fuzzing) */
    if (!isfinite(s) || !isfinite(sd) || !isfinite(sdd) || !ex_finite_n(k->p, 3)) return EXDEX_ENONFINITE;
    return EXDEX_OK;
}
