/* fuzz_ldp.c -- the small dense solvers of the contact solves (ldp.h, a
 * private header of the core): least distance, least combination and the
 * metric projection, on 1..8 rows of reasonable or extreme entries.
 *
 * Checks: no crash, no hang (every loop is bounded); on finite input, a
 * solved least-distance problem has a finite z that satisfies every row to
 * the rounding of its terms and of the problem's scale (max |c_j| / |a_j|), multipliers y >= 0 and z = A' y; the least
 * combination is finite, never above |a| (lam = 0 is a candidate), with
 * lam >= 0; the projection returns a finite v that satisfies every row it
 * can act on, unless it warns (inconsistent rows). */
#include "fuzz.h"
#include "../ldp.h"

#include <math.h>

#define T "ldp"

static int mod(double x) { return x == 0.0 || (fabs(x) >= 1e-100 && fabs(x) <= 1e100); }

static double norm3(const double a[3]) { return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]); }

int fuzz_ldp(const uint8_t *data, size_t size)
{
    fz f;
    int m, ok, dim;
    double a[8][3], c[8], tol[8], z[3], y[8], lam[8], minv[3], v[3], vs[3], a0[3], best;
    size_t it = 0, warn = 0;
    int finite = 1, moderate = 1;
    fz_init(&f, data, size);
    m = fz_pick(&f, 1, 8);
    dim = fz_pick(&f, 1, 3);
    for (int i = 0; i < m; i++) {
        for (int d = 0; d < 3; d++) a[i][d] = d < dim ? fz_num(&f, -10.0, 10.0) : 0.0;
        c[i] = fz_num(&f, -10.0, 10.0);
        tol[i] = fz_pick(&f, 0, 1) ? fz_log(&f, 1e-16, 1e-3) : 0.0;
    }
    for (int d = 0; d < 3; d++) {
        a0[d] = fz_num(&f, -10.0, 10.0);
        minv[d] = fz_log(&f, 1e-3, 1e3);
        vs[d] = fz_num(&f, -10.0, 10.0);
    }
    finite = f.nonfinite == 0;
    /* entries within 1e+-100 of 1 (or 0): no product or sum of the solve
     * can overflow or underflow, and every check must hold */
    for (int i = 0; i < m; i++)
        for (int d = 0; d < 3; d++) moderate &= mod(a[i][d]);
    for (int i = 0; i < m; i++) moderate &= mod(c[i]);
    for (int i = 0; i < m; i++) moderate &= tol[i] >= 0.0 && tol[i] <= 1e100;
    for (int d = 0; d < 3; d++) moderate &= mod(a0[d]) && mod(vs[d]) && minv[d] >= 1e-100 && minv[d] <= 1e100;
    if (moderate) f.wild = 0;

    ok = ldp_min_norm(m, (const double (*)[3])a, c, tol, z, y, NULL);
    FZ_CHECK(T, ok == 0 || ok == 1);
    if (finite && ok) {
        /* the solve is accurate relative to its scale S = max |c_j - tol_j| / |a_j| */
        double nz = norm3(z), S = 0.0;
        for (int j = 0; j < m; j++)
            if (norm3(a[j]) > 0.0) S = fmax(S, fabs(c[j] - tol[j]) / norm3(a[j]));
        FZ_EXTREME(T, &f, isfinite(nz));
        for (int i = 0; i < m && isfinite(nz); i++) {
            double s = a[i][0] * z[0] + a[i][1] * z[1] + a[i][2] * z[2];
            double scale = norm3(a[i]) * (nz + S) + fabs(c[i]) + tol[i];
            FZ_EXTREME(T, &f, s >= c[i] - tol[i] - 1e-9 * scale);
            FZ_CHECK(T, y[i] >= 0.0);
        }
        for (int d = 0; d < 3 && isfinite(nz); d++) {
            double zy = 0.0, sc = 0.0;
            for (int i = 0; i < m; i++) {
                zy += y[i] * a[i][d];
                sc += fabs(y[i] * a[i][d]);
            }
            FZ_EXTREME(T, &f, fabs(zy - z[d]) <= 1e-9 * (sc + nz));
        }
    }
    if (finite && !ok) fuzz_note_count(T, "inconsistent rows");

    best = ldp_min_combination(m, a0, (const double (*)[3])a, lam, NULL);
    if (finite) {
        FZ_EXTREME(T, &f, isfinite(best) && best <= norm3(a0) * (1.0 + 1e-12));
        for (int j = 0; j < m; j++) FZ_CHECK(T, lam[j] >= 0.0 || isnan(lam[j]));
    }

    /* the projection's metric must be positive (the model's inverse masses) */
    if (!(minv[0] > 0.0 && minv[1] > 0.0 && minv[2] > 0.0)) return 0;
    ok = ldp_project(minv, m, (const double (*)[3])a, c, vs, 1e-12, v, lam, &it, &warn);
    if (finite) {
        FZ_EXTREME(T, &f, isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]));
        if (ok && !warn) {
            for (int i = 0; i < m; i++) {
                double s = a[i][0] * v[0] + a[i][1] * v[1] + a[i][2] * v[2];
                /* rounding of the solve in z = M^1/2 (v - vs): |C_i| |z|, C_i = a_i M^-1/2 */
                double z2 = 0.0, C2 = 0.0, S = 0.0, scale;
                for (int d = 0; d < 3; d++) {
                    z2 += (v[d] - vs[d]) * (v[d] - vs[d]) / minv[d];
                    C2 += a[i][d] * a[i][d] * minv[d];
                }
                /* and its scale S = max |c'_j| / |C_j|, c' = c - a vs */
                for (int j = 0; j < m; j++) {
                    double Cj = 0.0, cj = c[j] - (a[j][0] * vs[0] + a[j][1] * vs[1] + a[j][2] * vs[2]);
                    for (int d = 0; d < 3; d++) Cj += a[j][d] * a[j][d] * minv[d];
                    if (Cj > 0.0) S = fmax(S, fabs(cj) / sqrt(Cj));
                }
                scale = sqrt(C2) * (sqrt(z2) + S) + norm3(a[i]) * (norm3(v) + norm3(vs)) + fabs(c[i]);
                if (fabs(a[i][0]) + fabs(a[i][1]) + fabs(a[i][2]) > 1e-12)
                    FZ_EXTREME(T, &f, s >= c[i] - 1e-9 * scale);
            }
        }
    }
    return 0;
}
