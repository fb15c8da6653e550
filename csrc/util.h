/* util.h -- private small-vector helpers of the exdex core (not installed).
 * Output first, sized arrays, row-major 3x3 matrices (MuJoCo style). */
#ifndef EXDEX_UTIL_H
#define EXDEX_UTIL_H

#include <math.h>

#define EXDEX_PI 3.14159265358979323846

static inline double ex_dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void ex_cross3(double r[3], const double a[3], const double b[3])
{
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    r[0] = x; r[1] = y; r[2] = z;
}

/* r = M v */
static inline void ex_mulmv3(double r[3], const double M[9], const double v[3])
{
    double x = M[0] * v[0] + M[1] * v[1] + M[2] * v[2];
    double y = M[3] * v[0] + M[4] * v[1] + M[5] * v[2];
    double z = M[6] * v[0] + M[7] * v[1] + M[8] * v[2];
    r[0] = x; r[1] = y; r[2] = z;
}

/* r = M^T v */
static inline void ex_mulmtv3(double r[3], const double M[9], const double v[3])
{
    double x = M[0] * v[0] + M[3] * v[1] + M[6] * v[2];
    double y = M[1] * v[0] + M[4] * v[1] + M[7] * v[2];
    double z = M[2] * v[0] + M[5] * v[1] + M[8] * v[2];
    r[0] = x; r[1] = y; r[2] = z;
}

/* R = A B (R may not alias A or B) */
static inline void ex_mulmm3(double R[9], const double A[9], const double B[9])
{
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            R[3 * i + j] = A[3 * i] * B[j] + A[3 * i + 1] * B[3 + j] + A[3 * i + 2] * B[6 + j];
}

static inline int ex_finite_n(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

/* Rotation matrix of angle th about the unit axis k (Rodrigues). */
static inline void ex_axis_angle(double R[9], const double k[3], double th)
{
    double c = cos(th), s = sin(th), C = 1.0 - c;
    double x = k[0], y = k[1], z = k[2];
    R[0] = c + x * x * C;     R[1] = x * y * C - z * s; R[2] = x * z * C + y * s;
    R[3] = y * x * C + z * s; R[4] = c + y * y * C;     R[5] = y * z * C - x * s;
    R[6] = z * x * C - y * s; R[7] = z * y * C + x * s; R[8] = c + z * z * C;
}

/* ------------------------------------------------ interval arithmetic
 * Closed intervals [lo, hi] with outward rounding: each operation computes
 * its ends in round-to-nearest (within half an ulp of the exact end) and
 * moves them outwards by |x| 2^-52 + 2^-300 (at least an ulp of x: the
 * move, rounded to nearest, still ends at least half an ulp out), so the
 * result holds every exact value of the operation over its operands'
 * intervals. A NaN end makes the interval fail ex_iv_ok. The absolute part,
 * 2^-300 (about 5e-91, far below any quantity of a scene), keeps the ends
 * of an interval about zero normal numbers whose products with each other
 * stay normal too (a move of 2^-1074 would make every product with such an
 * end a denormal number, which some CPUs compute by slow assists). */
typedef struct ex_iv {
    double lo, hi;
} ex_iv;

/* The lesser and the greater of a and b, inline and without a branch (x86-64's
 * minsd and maxsd): of equal operands (+0 and -0) the second; a NaN in b is
 * kept (an interval end it reaches fails ex_iv_ok), one in a gives b. */
static inline double ex_min(double a, double b)
{
    return a < b ? a : b;
}

static inline double ex_max(double a, double b)
{
    return a > b ? a : b;
}

static inline ex_iv ex_iv_out(double lo, double hi)
{
    ex_iv r = {lo - (fabs(lo) * 0x1p-52 + 0x1p-300), hi + (fabs(hi) * 0x1p-52 + 0x1p-300)};
    return r;
}

static inline ex_iv ex_iv_pt(double x)
{
    ex_iv r = {x, x};
    return r;
}

static inline ex_iv ex_iv_hull(ex_iv a, ex_iv b)
{
    ex_iv r = {ex_min(a.lo, b.lo), ex_max(a.hi, b.hi)};
    return r;
}

static inline int ex_iv_ok(ex_iv a)
{
    return a.lo <= a.hi && isfinite(a.lo) && isfinite(a.hi);
}

static inline double ex_iv_mag(ex_iv a)
{
    return ex_max(fabs(a.lo), fabs(a.hi));
}

static inline ex_iv ex_iv_add(ex_iv a, ex_iv b)
{
    return ex_iv_out(a.lo + b.lo, a.hi + b.hi);
}

static inline ex_iv ex_iv_sub(ex_iv a, ex_iv b)
{
    return ex_iv_out(a.lo - b.hi, a.hi - b.lo);
}

static inline ex_iv ex_iv_neg(ex_iv a)
{
    ex_iv r = {-a.hi, -a.lo};
    return r;
}

static inline ex_iv ex_iv_mul(ex_iv a, ex_iv b)
{
    double p0 = a.lo * b.lo, p1 = a.lo * b.hi, p2 = a.hi * b.lo, p3 = a.hi * b.hi;
    return ex_iv_out(ex_min(ex_min(p0, p1), ex_min(p2, p3)), ex_max(ex_max(p0, p1), ex_max(p2, p3)));
}

/* k a: the ends' products in the order k's sign gives them (the same ends
 * as ex_iv_mul's least and greatest of four; a NaN k gives NaN ends) */
static inline ex_iv ex_iv_scale(double k, ex_iv a)
{
    return k >= 0.0 ? ex_iv_out(k * a.lo, k * a.hi) : ex_iv_out(k * a.hi, k * a.lo);
}

/* a^2 (not a a: the square of an interval holding 0 starts at 0) */
static inline ex_iv ex_iv_sqr(ex_iv a)
{
    double l = fabs(a.lo), h = fabs(a.hi);
    if (a.lo <= 0.0 && a.hi >= 0.0) {
        ex_iv r = {0.0, ex_iv_out(0.0, ex_max(l * l, h * h)).hi};
        return r;
    }
    return ex_iv_out(ex_min(l * l, h * h), ex_max(l * l, h * h));
}

/* a / b for b > 0 throughout (else NaN): the least quotient is a.lo's over
 * b.hi where a.lo >= 0, over b.lo where not; the greatest a.hi's over b.lo
 * where a.hi >= 0, over b.hi where not (rounding to nearest is monotone, so
 * these are the least and greatest of the four rounded quotients too) */
static inline ex_iv ex_iv_div_pos(ex_iv a, ex_iv b)
{
    if (!(b.lo > 0.0)) {
        ex_iv r = {NAN, NAN};
        return r;
    }
    return ex_iv_out(a.lo / (a.lo >= 0.0 ? b.hi : b.lo), a.hi / (a.hi >= 0.0 ? b.lo : b.hi));
}

/* r = a x b, r = a . b, r = M^T a (M a point matrix) */
static inline void ex_iv_cross3(ex_iv r[3], const ex_iv a[3], const ex_iv b[3])
{
    ex_iv x = ex_iv_sub(ex_iv_mul(a[1], b[2]), ex_iv_mul(a[2], b[1]));
    ex_iv y = ex_iv_sub(ex_iv_mul(a[2], b[0]), ex_iv_mul(a[0], b[2]));
    ex_iv z = ex_iv_sub(ex_iv_mul(a[0], b[1]), ex_iv_mul(a[1], b[0]));
    r[0] = x;
    r[1] = y;
    r[2] = z;
}

static inline ex_iv ex_iv_dot3(const ex_iv a[3], const ex_iv b[3])
{
    return ex_iv_add(ex_iv_add(ex_iv_mul(a[0], b[0]), ex_iv_mul(a[1], b[1])), ex_iv_mul(a[2], b[2]));
}

static inline void ex_iv_mulmtv3(ex_iv r[3], const double M[9], const ex_iv a[3])
{
    ex_iv x[3];
    for (int i = 0; i < 3; i++)
        x[i] = ex_iv_add(ex_iv_add(ex_iv_scale(M[i], a[0]), ex_iv_scale(M[3 + i], a[1])), ex_iv_scale(M[6 + i], a[2]));
    r[0] = x[0];
    r[1] = x[1];
    r[2] = x[2];
}

/* cos and sin over x (libm's cos and sin within an ulp, moved outwards
 * twice); an extremum inside x (the multiples of pi, of pi/2 off them,
 * looked for in x widened by 1e-15 of its size: only a looser bound) gives
 * its value 1 or -1. */
static inline ex_iv ex_iv_cos_sin(ex_iv x, int sine)
{
    ex_iv r;
    double a = sine ? sin(x.lo) : cos(x.lo), b = sine ? sin(x.hi) : cos(x.hi), sl = 1e-15 * (1.0 + fabs(x.lo) + fabs(x.hi));
    double off = sine ? 0.5 * EXDEX_PI : 0.0, k0, k1;
    if (!(x.hi - x.lo < 6.0)) {
        r.lo = -1.0;
        r.hi = 1.0;
        return r;
    }
    r = ex_iv_out(ex_min(a, b), ex_max(a, b));
    r = ex_iv_out(r.lo, r.hi);
    k0 = ceil((x.lo - sl - off) / EXDEX_PI);
    k1 = floor((x.hi + sl - off) / EXDEX_PI);
    for (double k = k0; k <= k1; k++) {
        /* cos(k pi) = (-1)^k; sin(pi/2 + k pi) = (-1)^k */
        if (fmod(fabs(k), 2.0) == 0.0) r.hi = 1.0;
        else r.lo = -1.0;
    }
    r.lo = ex_max(r.lo, -1.0);
    r.hi = ex_min(r.hi, 1.0);
    return r;
}

#endif
