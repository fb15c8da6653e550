/* test_ldp.c -- the small dense solvers (ldp.c): least distance, least
 * combination and the metric projection against closed forms, and against
 * an independent brute force on seeded random problems: the least-distance
 * point z = A_S' y_S is supported on some set S of at most 3 linearly
 * independent rows, active there (A_S z = c_S, y_S >= 0) (Caratheodory), so
 * trying every such S, keeping the feasible z of least norm, gives the
 * solution (or none: the rows are inconsistent). The brute force solves each
 * support in closed form on its own vectors (cross products and Cramer's
 * rule on A_S: accurate to the support's condition; the normal equations
 * A_S A_S' would square it, and drop the nearly dependent supports that
 * random rows draw), not by ldp.c. */
#include "check.h"
#include "../ldp.h"

#include <math.h>
#include <string.h>

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static void cross3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[1] * b[2] - a[2] * b[1];
    o[1] = a[2] * b[0] - a[0] * b[2];
    o[2] = a[0] * b[1] - a[1] * b[0];
}

/* The rows of the support `mask` in set[] (at most 3); returns their
 * number, 4 when there are more than 3. */
static int support(int mask, int m, int set[3])
{
    int n = 0;
    for (int j = 0; j < m; j++)
        if (mask & (1 << j)) {
            if (n == 3) return 4;
            set[n++] = j;
        }
    return n;
}

/* The point z in the span of the n <= 3 vectors v[] with v_i . z = c_i, and
 * its coefficients w (z = sum w_i v_i), in closed form: z = c v / |v|^2 (one
 * vector); z = (c_1 v_2 x nv - c_2 v_1 x nv) / |nv|^2 with nv = v_1 x v_2
 * (two); Cramer's rule on the 3 x 3 matrix of rows v (three). 0 where the
 * vectors are dependent to 1e-12 of their sizes. */
static int span_solve(int n, const double *v[3], const double c[3], double z[3], double w[3])
{
    double nv[3], t[3], u[3], det, q;
    if (n == 0) {
        z[0] = z[1] = z[2] = 0.0;
        return 1;
    }
    if (n == 1) {
        q = dot3(v[0], v[0]);
        if (!(q > 0.0)) return 0;
        w[0] = c[0] / q;
        for (int d = 0; d < 3; d++) z[d] = w[0] * v[0][d];
        return 1;
    }
    if (n == 2) {
        cross3(v[0], v[1], nv);
        q = dot3(nv, nv);
        if (!(sqrt(q) > 1e-12 * norm3(v[0]) * norm3(v[1]))) return 0;
        cross3(v[1], nv, t);
        cross3(v[0], nv, u);
        for (int d = 0; d < 3; d++) z[d] = (c[0] * t[d] - c[1] * u[d]) / q;
        cross3(z, v[1], t);
        cross3(v[0], z, u);
        w[0] = dot3(t, nv) / q;
        w[1] = dot3(u, nv) / q;
        return 1;
    }
    {
        double k[3][3];
        cross3(v[1], v[2], k[0]);
        cross3(v[2], v[0], k[1]);
        cross3(v[0], v[1], k[2]);
        det = dot3(v[0], k[0]);
        if (!(fabs(det) > 1e-12 * norm3(v[0]) * norm3(v[1]) * norm3(v[2]))) return 0;
        for (int d = 0; d < 3; d++) z[d] = (c[0] * k[0][d] + c[1] * k[1][d] + c[2] * k[2][d]) / det;
        for (int i = 0; i < 3; i++) w[i] = dot3(z, k[i]) / det;
        return 1;
    }
}

/* Brute-force least distance over every support of <= 3 rows: 1 and z if
 * feasible (every row within ftol of the size of its terms, |a_i| |z| +
 * |c_i|, of holding), 0 if no support is. */
static int brute_ldp(int m, const double (*a)[3], const double *c, double ftol, double z[3])
{
    double best = INFINITY;
    for (int mask = 0; mask < (1 << m); mask++) {
        int set[3], n = support(mask, m, set), ok = 1;
        const double *v[3];
        double rhs[3], y[3], zt[3];
        if (n > 3) continue;
        for (int i = 0; i < n; i++) {
            v[i] = a[set[i]];
            rhs[i] = c[set[i]];
        }
        if (!span_solve(n, v, rhs, zt, y)) continue;
        for (int i = 0; i < n; i++) ok &= y[i] >= 0.0;
        if (!ok) continue;
        for (int j = 0; j < m; j++) ok &= dot3(a[j], zt) >= c[j] - ftol * (norm3(a[j]) * norm3(zt) + fabs(c[j]));
        if (ok && dot3(zt, zt) < best) {
            best = dot3(zt, zt);
            memcpy(z, zt, sizeof zt);
        }
    }
    return best < INFINITY;
}

/* Brute-force least combination: min |a + sum lam_j b_j|, lam >= 0, over
 * every support of <= 3 vectors; on a support, the lam_S minimising
 * |a + B_S lam_S| are the coefficients of -a's part in the span of b_S
 * (span_solve with c_i = -b_i . a) and the residual is a's part across it:
 * |a x b| / |b| (one vector), |a . nv| / |nv| (two), 0 (three). */
static double brute_comb(int m, const double a[3], const double (*b)[3])
{
    double best = norm3(a);
    for (int mask = 1; mask < (1 << m); mask++) {
        int set[3], n = support(mask, m, set), ok = 1;
        const double *v[3];
        double rhs[3], lam[3], p[3], r;
        if (n > 3) continue;
        for (int i = 0; i < n; i++) {
            v[i] = b[set[i]];
            rhs[i] = -dot3(b[set[i]], a);
        }
        if (!span_solve(n, v, rhs, p, lam)) continue;
        for (int i = 0; i < n; i++) ok &= lam[i] >= 0.0;
        if (!ok) continue;
        if (n == 1) {
            cross3(a, v[0], p);
            r = norm3(p) / norm3(v[0]);
        } else if (n == 2) {
            double nv[3];
            cross3(v[0], v[1], nv);
            r = fabs(dot3(a, nv)) / norm3(nv);
        } else {
            r = 0.0;
        }
        best = fmin(best, r);
    }
    return best;
}

static unsigned long long lcg_state, lcg_seed; /* restarted at each test from its seed */
static double urand(void)
{
    if (lcg_seed != check_seed()) lcg_state = lcg_seed = check_seed();
    lcg_state = lcg_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(lcg_state >> 11) / 9007199254740992.0;
}
static double nrand(void)
{
    double u = urand(), v = urand();
    return sqrt(-2.0 * log(u + 1e-300)) * cos(6.283185307179586 * v);
}

EXDEX_TEST(ldp_solve_small_closed_form)
{
    /* [[2,1,0],[1,3,1],[0,1,4]] x = (3, 5, 5): x = (1, 1, 1) */
    double A[3][3] = {{2, 1, 0}, {1, 3, 1}, {0, 1, 4}}, b[3] = {3, 5, 5}, x[3];
    double S[3][3] = {{1, 2, 3}, {2, 4, 6}, {0, 1, 1}}, bs[3] = {1, 2, 3};
    ENSURE(ldp_solve_small(3, A, b, x));
    for (int i = 0; i < 3; i++) ENSURE_CLOSE(x[i], 1.0, 1e-15);
    ENSURE(!ldp_solve_small(3, S, bs, x)); /* rank 2 */
}

EXDEX_TEST(ldp_min_norm_closed_forms)
{
    double z[3], y[4];
    /* one row: z = c a / |a|^2, y = c / |a|^2 */
    {
        const double a[1][3] = {{3, 4, 0}}, c[1] = {10};
        ENSURE(ldp_min_norm(1, a, c, NULL, z, y, NULL));
        ENSURE_CLOSE(z[0], 1.2, 1e-15);
        ENSURE_CLOSE(z[1], 1.6, 1e-15);
        ENSURE_SMALL(z[2], 1e-15);
        ENSURE_CLOSE(y[0], 0.4, 1e-15);
    }
    /* a row holding at 0 (c <= 0): z = 0, y = 0 */
    {
        const double a[1][3] = {{1, 2, 3}}, c[1] = {-1};
        ENSURE(ldp_min_norm(1, a, c, NULL, z, y, NULL));
        ENSURE(z[0] == 0.0 && z[1] == 0.0 && z[2] == 0.0 && y[0] == 0.0);
    }
    /* two orthogonal rows and a slack one: z = (1, 2, 0) */
    {
        const double a[3][3] = {{1, 0, 0}, {0, 2, 0}, {1, 1, 0}}, c[3] = {1, 4, 0.5};
        ENSURE(ldp_min_norm(3, a, c, NULL, z, y, NULL));
        ENSURE_CLOSE(z[0], 1.0, 1e-15);
        ENSURE_CLOSE(z[1], 2.0, 1e-15);
        ENSURE_SMALL(z[2], 1e-15);
        ENSURE_CLOSE(y[0], 1.0, 1e-15);
        ENSURE_CLOSE(y[1], 1.0, 1e-15);  /* z_y = 2 y_1 */
        ENSURE(y[2] == 0.0);
    }
    /* the tolerance relaxes each row: c - tol */
    {
        const double a[1][3] = {{0, 0, 2}}, c[1] = {1}, tol[1] = {0.25};
        ENSURE(ldp_min_norm(1, a, c, tol, z, y, NULL));
        ENSURE_CLOSE(z[2], 0.375, 1e-15);
    }
    /* inconsistent rows (an object pinched between two stops): 0 */
    {
        const double a[2][3] = {{1, 0, 0}, {-1, 0, 0}}, c[2] = {1, 1};
        ENSURE(!ldp_min_norm(2, a, c, NULL, z, y, NULL));
    }
    /* a zero row that must hold with c > 0 is inconsistent */
    {
        const double a[2][3] = {{0, 0, 0}, {1, 0, 0}}, c[2] = {1, 1};
        ENSURE(!ldp_min_norm(2, a, c, NULL, z, y, NULL));
    }
}

EXDEX_TEST(ldp_min_norm_matches_brute_force)
{
    /* 3000 seeded problems: 1..8 rows in 1, 2 or 3 dimensions (the unused
     * components of every row 0), right-hand sides of mixed sign, scales
     * from 1e-6 to 1e6. Same feasibility; z satisfies every row; y >= 0,
     * z = A' y, each row with y_i > 0 active to 1e-10 of the size of its
     * terms; the same z as the brute force, to 1e-12 (1 + rho^2) of the
     * problem's size, rho = |z| / max |c_i| / |a_i|: the least-distance
     * problem through NNLS gives z = -r_{1..3} / r_4 with r_4 about
     * -1 / (1 + rho^2), so the rounding of r reaches z magnified by
     * 1 + rho^2 (rho is 1e3 .. 1e5 where a few nearly dependent rows put z
     * far out; elsewhere the bound is 1e-12 of the size). */
    int feasible = 0, infeasible = 0;
    for (int trial = 0; trial < 3000; trial++) {
        int m = 1 + (int)(urand() * 8), dim = 1 + trial % 3;
        double a[8][3], c[8], z[3], zb[3], y[8], s = pow(10.0, 12.0 * urand() - 6.0), nz, cmax = 0.0, rho;
        int ok, okb;
        for (int i = 0; i < m; i++) {
            for (int d = 0; d < 3; d++) a[i][d] = d < dim ? nrand() : 0.0;
            c[i] = s * nrand();
            cmax = fmax(cmax, fabs(c[i]) / norm3(a[i]));
        }
        ok = ldp_min_norm(m, (const double (*)[3])a, c, NULL, z, y, NULL);
        okb = brute_ldp(m, (const double (*)[3])a, c, 1e-9, zb);
        nz = okb ? norm3(zb) : 0.0;
        rho = nz / cmax;
        /* beyond rho = 1e5, r_4 is within E u's rounding and ldp_min_norm
         * may call consistent rows inconsistent (its documented limit) */
        ENSURE(ok == okb || (okb && rho > 1e5));
        if (!ok || !okb) {
            infeasible++;
            continue;
        }
        feasible++;
        for (int d = 0; d < 3; d++) ENSURE_CLOSE(z[d], zb[d], 1e-12 * (1.0 + rho * rho) * (nz + s));
        for (int i = 0; i < m; i++) {
            double slack = dot3(a[i], z) - c[i];
            ENSURE(slack >= -1e-10 * (nz + s));
            ENSURE(y[i] >= 0.0);
            if (y[i] > 0.0) ENSURE(fabs(slack) <= 1e-10 * (norm3(a[i]) * nz + fabs(c[i])));
        }
        for (int d = 0; d < 3; d++) {
            double zy = 0.0;
            for (int i = 0; i < m; i++) zy += y[i] * a[i][d];
            ENSURE_CLOSE(zy, z[d], 1e-9 * (nz + s));
        }
    }
    ENSURE(feasible > 500 && infeasible > 100); /* both branches exercised */
}

EXDEX_TEST(ldp_min_norm_blocking_step_leaves_no_residue)
{
    /* eight rows in the plane, feasible (z = (2.7e7, -3.1e7) clears every
     * row by 1e7: an LP margin, found outside the suite). NNLS takes rows 0,
     * 7, 5; row 0's multiplier then blocks the step, and the step leaves it
     * 5.6e-17 instead of 0: unless the blocking column is set to 0 the inner
     * loop shrinks it by 1e-16 a pass and gives up, calling the rows
     * infeasible. Against the brute force over every support (independent
     * of NNLS): feasible, the same z, rows 5 and 7 active. */
    const double a[8][3] = {{0.50304691512535904, -1.0476932925981897, 0},
                            {1.5911643844826513, 0.0061038469658194266, 0},
                            {1.5142851392377685, -1.0166002436420976, 0},
                            {-0.83629228114828291, -2.5211878994384631, 0},
                            {-0.2670279141384429, -0.55975281363666352, 0},
                            {-0.81304574832916066, -1.4911088873551659, 0},
                            {-0.85856487657691238, -1.4530568883124835, 0},
                            {1.5657405517274445, 1.0695008296540172, 0}};
    const double c[8] = {81248.545961230411, -225946.15845954666, 83832.069102212801,
                         24579.380843656123, -54284.584585504439, 49853.51887179591,
                         -146300.54873640538, 9562.1140931214959};
    const double s = 107341.0, zfar[3] = {2.7e7, -3.1e7, 0.0};
    double z[3], zb[3], y[8];
    for (int i = 0; i < 8; i++) ENSURE(dot3(a[i], zfar) >= c[i] + 1e6);
    ENSURE(brute_ldp(8, a, c, 1e-9, zb));
    ENSURE(ldp_min_norm(8, a, c, NULL, z, y, NULL));
    for (int d = 0; d < 3; d++) ENSURE_CLOSE(z[d], zb[d], 1e-9 * (sqrt(dot3(zb, zb)) + s));
    for (int i = 0; i < 8; i++) {
        double slack = dot3(a[i], z) - c[i];
        ENSURE(y[i] >= 0.0);
        if (i == 5 || i == 7) ENSURE(y[i] > 0.0 && fabs(slack) <= 1e-9 * s);
        else ENSURE(y[i] == 0.0 && slack > 1e3);
    }
}

EXDEX_TEST(ldp_min_combination_closed_forms_and_brute_force)
{
    double lam[8];
    {
        const double a[3] = {1, 0, 0}, b[1][3] = {{-2, 0, 0}};
        ENSURE_SMALL(ldp_min_combination(1, a, b, lam, NULL), 1e-15);
        ENSURE_CLOSE(lam[0], 0.5, 1e-15);
    }
    {
        const double a[3] = {1, 0, 0}, b[1][3] = {{1, 0, 0}};
        ENSURE_CLOSE(ldp_min_combination(1, a, b, lam, NULL), 1.0, 1e-15);
        ENSURE(lam[0] == 0.0);
    }
    {
        const double a[3] = {1, 1, 0}, b[2][3] = {{-1, 0, 0}, {0, 1, 0}};
        ENSURE_CLOSE(ldp_min_combination(2, a, b, lam, NULL), 1.0, 1e-15);
        ENSURE_CLOSE(lam[0], 1.0, 1e-15);
        ENSURE(lam[1] == 0.0);
    }
    for (int trial = 0; trial < 2000; trial++) {
        int m = 1 + (int)(urand() * 8);
        double a[3], b[8][3], s = pow(10.0, 8.0 * urand() - 4.0), got, want;
        for (int d = 0; d < 3; d++) a[d] = s * nrand();
        for (int j = 0; j < m; j++)
            for (int d = 0; d < 3; d++) b[j][d] = nrand();
        got = ldp_min_combination(m, a, (const double (*)[3])b, lam, NULL);
        want = brute_comb(m, a, (const double (*)[3])b);
        ENSURE_CLOSE(got, want, 1e-9 * s);
        for (int j = 0; j < m; j++) ENSURE(lam[j] >= 0.0);
    }
}

EXDEX_TEST(ldp_min_combination_nearly_dependent_support)
{
    /* -a is a positive combination of three vectors whose matrix has
     * condition 1.1e4 (lam = (1.755, 3.632, 11.53) by Cramer's rule on the
     * vectors, span_solve; exactly so in rational arithmetic): the least
     * combination is 0. Each support's least squares by the normal
     * equations squares the condition and leaves 7.6e-10 of |a|; by the
     * vectors' QR the residual is the rounding of a + B lam. */
    const double a[3] = {-0.0024099122218854498, -0.0010892620820545111, -0.0018901084845926446};
    const double b[3][3] = {{-0.78982302607030197, -0.06234355172724354, 2.32234327985508},
                            {0.86056724324164702, -0.80394276542713405, 0.49588592688624195},
                            {-0.15061649218519907, 0.26280128633844285, -0.50953031005241822}};
    const double *v[3] = {b[0], b[1], b[2]};
    double rhs[3], p[3], want[3], lam[3], got;
    for (int i = 0; i < 3; i++) rhs[i] = -dot3(b[i], a);
    ENSURE(span_solve(3, v, rhs, p, want));
    for (int i = 0; i < 3; i++) ENSURE(want[i] > 1.0);
    got = ldp_min_combination(3, a, b, lam, NULL);
    ENSURE_SMALL(got, 1e-11 * norm3(a));
    for (int i = 0; i < 3; i++) ENSURE_CLOSE(lam[i], want[i], 1e-10 * want[i]);
}

EXDEX_TEST(ldp_project_metric_closed_form)
{
    /* planar mass m = 2, I = 0.5; one row v_y >= 1 from rest: the impulse
     * lam = m (the velocity change 1 = lam / m), v = (0, 1, 0) */
    const double minv[3] = {0.5, 0.5, 2.0}, G[2][3] = {{0, 1, 0}, {0, 0, 0}}, b[2] = {1, 5}, vs[3] = {0, 0, 0};
    double v[3], lam[2];
    size_t it = 0, warn = 0;
    ENSURE(ldp_project(minv, 2, G, b, vs, 1e-12, v, lam, &it, &warn));
    ENSURE_SMALL(v[0], 1e-15);
    ENSURE_CLOSE(v[1], 1.0, 1e-15);
    ENSURE_SMALL(v[2], 1e-15);
    ENSURE_CLOSE(lam[0], 2.0, 1e-15);
    ENSURE(lam[1] == 0.0); /* a row that cannot act is skipped */
    ENSURE(warn == 0);
    /* a row through the rotation: G = (0, 1, 1), b = 1: v = M^-1 G' lam,
     * G M^-1 G' lam = 1, lam = 1 / (0.5 + 2) = 0.4, v = (0, 0.2, 0.8) */
    {
        const double G2[1][3] = {{0, 1, 1}}, b2[1] = {1};
        ENSURE(ldp_project(minv, 1, G2, b2, vs, 1e-12, v, lam, &it, &warn));
        ENSURE_CLOSE(v[1], 0.2, 1e-15);
        ENSURE_CLOSE(v[2], 0.8, 1e-15);
        ENSURE_CLOSE(lam[0], 0.4, 1e-15);
    }
    /* pinched: the most violated row alone, and a warning */
    {
        const double G3[2][3] = {{1, 0, 0}, {-1, 0, 0}}, b3[2] = {1, 2};
        ENSURE(ldp_project(minv, 2, G3, b3, vs, 1e-12, v, lam, &it, &warn));
        ENSURE(warn == 1);
        ENSURE_CLOSE(v[0], -2.0, 1e-15);
    }
    /* every row holding at vs: nothing acts */
    {
        const double G4[1][3] = {{1, 0, 0}}, b4[1] = {-1};
        ENSURE(!ldp_project(minv, 1, G4, b4, vs, 1e-12, v, lam, &it, &warn));
        ENSURE(v[0] == 0.0 && lam[0] == 0.0);
    }
    /* one violated row (the closed form, one iteration counted) and the
     * same row with a second one that holds by a wide margin at vs (NNLS):
     * the same projection. Closed form: viol = 0.9 - G vs = 0.595, G M^-1 G'
     * = 0.045 + 0.72 + 0.98 = 1.745, lam = 0.595 / 1.745 */
    {
        const double G5[2][3] = {{0.3, -1.2, 0.7}, {1, 0, 0}}, b5[2] = {0.9, -100.0};
        const double vs5[3] = {0.1, -0.2, 0.05};
        double v1[3], l1[2], v2[3], l2[2], lc = 0.595 / 1.745;
        size_t it1 = 0, it2 = 0;
        ENSURE(ldp_project(minv, 1, G5, b5, vs5, 1e-12, v1, l1, &it1, &warn));
        ENSURE(it1 == 1);
        ENSURE_CLOSE(l1[0], lc, 1e-15);
        for (int d = 0; d < 3; d++) ENSURE_CLOSE(v1[d], vs5[d] + minv[d] * G5[0][d] * lc, 1e-15);
        ENSURE(ldp_project(minv, 2, G5, b5, vs5, 1e-12, v2, l2, &it2, &warn));
        ENSURE(it2 >= 1);
        ENSURE_CLOSE(l2[0], lc, 1e-14);
        ENSURE(l2[1] == 0.0);
        for (int d = 0; d < 3; d++) ENSURE_CLOSE(v2[d], v1[d], 1e-14);
    }
}
