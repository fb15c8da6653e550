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

#endif
