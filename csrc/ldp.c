/* ldp.c -- the small dense solvers of the exdex core (ldp.h): Gaussian
 * elimination for n <= 3, Lawson-Hanson non-negative least squares in four
 * rows, and on it the least-distance problem of the contact solves. */
#include "ldp.h"
#include "util.h"
#include "tolerances.h"

#include <math.h>
#include <string.h>

/* Small dense solve A x = b for n <= 3 (Gaussian elimination, partial
 * pivoting); returns 0 if A is numerically singular. A and b are clobbered. */
int ldp_solve_small(int n, double A[3][3], double b[3], double x[3])
{
    double scale = 0.0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) scale = fmax(scale, fabs(A[i][j]));
    for (int c = 0; c < n; c++) {
        int piv = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(A[r][c]) > fabs(A[piv][c])) piv = r;
        if (!(fabs(A[piv][c]) > 1e-12 * scale)) return 0;
        if (piv != c) {
            for (int k = 0; k < n; k++) {
                double t = A[c][k];
                A[c][k] = A[piv][k];
                A[piv][k] = t;
            }
            {
                double t = b[c];
                b[c] = b[piv];
                b[piv] = t;
            }
        }
        for (int r = c + 1; r < n; r++) {
            double f = A[r][c] / A[c][c];
            for (int k = c; k < n; k++) A[r][k] -= f * A[c][k];
            b[r] -= f * b[c];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        double acc = b[r];
        for (int k = r + 1; k < n; k++) acc -= A[r][k] * x[k];
        x[r] = acc / A[r][r];
    }
    return 1;
}

/* ------------------------------------------- planar stops: velocity QP */

/* Lawson-Hanson NNLS in 4 rows: min |E u - f| over u >= 0, E given by its m
 * columns col[j] (4 entries each). The passive set holds at most 4 linearly
 * independent columns; each least-squares solve is a modified Gram-Schmidt
 * QR of those columns. Bounded: at most 3 m + 12 outer iterations and
 * 8 inner ones per outer. Returns 1 if it converged (the multipliers of the
 * columns not in the passive set are <= tol), 0 otherwise (u is the last
 * feasible iterate); tol is NNLS_TOL (tolerances.h). */
static int ls_passive(const double (*col)[4], const int *P, int k, const double f[4], double *z)
{
    double Q[4][4], R[4][4], qf[4];
    for (int a = 0; a < k; a++) {
        double v[4], nrm0, nrm;
        for (int i = 0; i < 4; i++) v[i] = col[P[a]][i];
        nrm0 = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
        for (int pass = 0; pass < 2; pass++) /* MGS with one reorthogonalisation */
            for (int b = 0; b < a; b++) {
                double d = Q[b][0] * v[0] + Q[b][1] * v[1] + Q[b][2] * v[2] + Q[b][3] * v[3];
                if (pass == 0) R[b][a] = d; else R[b][a] += d;
                for (int i = 0; i < 4; i++) v[i] -= d * Q[b][i];
            }
        nrm = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
        if (!(nrm > 1e-12 * nrm0)) return 0; /* dependent */
        R[a][a] = nrm;
        for (int i = 0; i < 4; i++) Q[a][i] = v[i] / nrm;
    }
    for (int a = 0; a < k; a++) qf[a] = Q[a][0] * f[0] + Q[a][1] * f[1] + Q[a][2] * f[2] + Q[a][3] * f[3];
    for (int a = k - 1; a >= 0; a--) {
        double acc = qf[a];
        for (int b = a + 1; b < k; b++) acc -= R[a][b] * z[b];
        z[a] = acc / R[a][a];
    }
    return 1;
}

int ldp_nnls(int m, const double (*col)[4], const double f[4], double *u, int *iters)
{
    int P[4], k = 0, outer;
    unsigned char banned[LDP_MAX_ROWS];
    for (int j = 0; j < m; j++) {
        u[j] = 0.0;
        banned[j] = 0;
    }
    for (outer = 0; outer < 3 * m + 12; outer++) {
        double r[4], wbest = NNLS_TOL, z[4];
        int jb = -1;
        for (int i = 0; i < 4; i++) r[i] = f[i];
        for (int a = 0; a < k; a++)
            for (int i = 0; i < 4; i++) r[i] -= col[P[a]][i] * u[P[a]];
        for (int j = 0; j < m; j++) {
            int in = 0;
            double w;
            for (int a = 0; a < k; a++) in |= P[a] == j;
            if (in || banned[j]) continue;
            w = col[j][0] * r[0] + col[j][1] * r[1] + col[j][2] * r[2] + col[j][3] * r[3];
            if (w > wbest) {
                wbest = w;
                jb = j;
            }
        }
        if (jb < 0) {
            *iters += outer;
            return 1;
        }
        if (k == 4) break;
        P[k++] = jb;
        for (int inner = 0;; inner++) {
            double alpha = INFINITY;
            int ok = ls_passive(col, P, k, f, z), ablock = -1;
            if (!ok) {
                /* the new column depends on the passive ones: never again */
                banned[P[--k]] = 1;
                u[jb] = 0.0;
                break;
            }
            for (int a = 0; a < k; a++)
                if (z[a] <= 0.0) {
                    double d = u[P[a]] - z[a], al = d > 0.0 ? u[P[a]] / d : 0.0;
                    if (al < alpha) {
                        alpha = al;
                        ablock = a;
                    }
                }
            if (alpha == INFINITY) {
                for (int a = 0; a < k; a++) u[P[a]] = z[a];
                break;
            }
            if (inner >= 8) {
                *iters += outer;
                return 0;
            }
            for (int a = 0; a < k; a++) u[P[a]] += alpha * (z[a] - u[P[a]]);
            /* the blocking column reaches 0 exactly (its step can leave a
             * rounding residue > 0 that would block every later step) */
            u[P[ablock]] = 0.0;
            /* drop the passive columns that reached 0 */
            for (int a = 0; a < k;)
                if (u[P[a]] <= 0.0) {
                    u[P[a]] = 0.0;
                    P[a] = P[--k];
                } else {
                    a++;
                }
            if (k == 0) break;
        }
    }
    *iters += outer;
    return 0;
}

/* Least distance (Lawson & Hanson, Solving Least Squares Problems, ch. 23):
 * min |z| s.t. A z >= c is the NNLS problem min |E u - f| over u >= 0 with
 * E = [A'; c'] (4 x m) and f = (0, 0, 0, 1). With r = E u - f at its
 * solution, the rows are consistent iff r_4 < 0, and then
 *     z = -r_{1..3} / r_4,   y = u / (-r_4)   (z = A' y, y >= 0 the
 * multipliers, complementary to the rows). Rows are first scaled to unit
 * |a_i| and c to max |c_i| = 1, which changes neither z nor the active set.
 * With rho = |z| / max |c_i| / |a_i|, r_4 is about -1 / (1 + rho^2), so
 * E u's rounding reaches z magnified by 1 + rho^2 (the test bound: 1e-12
 * (1 + rho^2) of the size), and beyond rho of about 1e5 (a few nearly
 * dependent rows whose only common points are far out: a pinch) r_4 is
 * within that rounding and consistent rows may be called inconsistent. */
int ldp_min_norm(int m, const double (*a)[3], const double *c, const double *tol, double z[3], double *y,
                 int *iters)
{
    double col[LDP_MAX_ROWS][4], nrm[LDP_MAX_ROWS], u[LDP_MAX_ROWS], scale = 0.0, f[4] = {0, 0, 0, 1}, r[4];
    int idx[LDP_MAX_ROWS], k = 0, ok, it = 0;
    z[0] = z[1] = z[2] = 0.0;
    for (int i = 0; i < m; i++) {
        double n = sqrt(ex_dot3(a[i], a[i])), ci;
        y[i] = 0.0;
        if (!(n > 0.0)) continue;
        ci = (tol ? c[i] - tol[i] : c[i]) / n;
        for (int d = 0; d < 3; d++) col[k][d] = a[i][d] / n;
        col[k][3] = ci;
        nrm[k] = n;
        idx[k++] = i;
        if (fabs(ci) > scale) scale = fabs(ci);
    }
    /* a zero row must hold at z = 0 itself */
    for (int i = 0; i < m; i++)
        if (!(sqrt(ex_dot3(a[i], a[i])) > 0.0) && (tol ? c[i] - tol[i] : c[i]) > 0.0) return 0;
    if (!(scale > 0.0)) return 1;  /* every c_i = 0: z = 0 */
    for (int j = 0; j < k; j++) col[j][3] /= scale;
    ok = ldp_nnls(k, (const double (*)[4])col, f, u, &it);
    if (iters) *iters += it;
    for (int i = 0; i < 4; i++) {
        r[i] = -f[i];
        for (int j = 0; j < k; j++) r[i] += col[j][i] * u[j];
    }
    {
        /* consistent iff r_4 < 0 beyond the rounding of E u (|E u| <=
         * sqrt(2) sum u): nearly opposed rows need a large u to close the
         * cone, and then r_4 = 0 is only known to that rounding */
        double usum = 0.0;
        for (int j = 0; j < k; j++) usum += u[j];
        if (!(ok && r[3] < -1e-12 * (1.0 + usum))) return 0;
    }
    for (int d = 0; d < 3; d++) z[d] = -r[d] / r[3] * scale;
    for (int j = 0; j < k; j++) y[idx[j]] = u[j] / (-r[3]) * scale / nrm[j];
    return 1;
}

/* The least |a + B_S lam| over lam on a support of n <= 3 of the vectors
 * (lam unconstrained): in closed form on the vectors themselves, accurate to
 * the support's condition (the normal equations B_S B_S' would square it:
 * a combination of nearly dependent vectors that reaches -a exactly would
 * be missed by 1e-9 of |a|): lam = -a . b / |b|^2 (one vector); with
 * nv = b_1 x b_2, lam_1 = -(a x b_2) . nv / |nv|^2, lam_2 = -(b_1 x a) . nv
 * / |nv|^2 (two); Cramer's rule on B_S (three). 0 where the vectors are
 * dependent to 1e-12 of their sizes. */
static int comb_support(int n, const double a[3], const double *v[3], double l[3])
{
    double c[3], d[3], q;
    if (n == 1) {
        q = ex_dot3(v[0], v[0]);
        if (!(q > 0.0)) return 0;
        l[0] = -ex_dot3(a, v[0]) / q;
        return 1;
    }
    if (n == 2) {
        double nv[3];
        ex_cross3(nv, v[0], v[1]);
        q = ex_dot3(nv, nv);
        if (!(q > 1e-24 * ex_dot3(v[0], v[0]) * ex_dot3(v[1], v[1]))) return 0;
        ex_cross3(c, a, v[1]);
        ex_cross3(d, v[0], a);
        l[0] = -ex_dot3(c, nv) / q;
        l[1] = -ex_dot3(d, nv) / q;
        return 1;
    }
    {
        double k[3][3], det;
        ex_cross3(k[0], v[1], v[2]);
        ex_cross3(k[1], v[2], v[0]);
        ex_cross3(k[2], v[0], v[1]);
        det = ex_dot3(v[0], k[0]);
        if (!(det * det > 1e-24 * ex_dot3(v[0], v[0]) * ex_dot3(v[1], v[1]) * ex_dot3(v[2], v[2]))) return 0;
        for (int i = 0; i < 3; i++) l[i] = -ex_dot3(a, k[i]) / det;
        return 1;
    }
}

/* Up to three vectors: every support S tried (the minimiser's support is
 * one with lam_S >= 0 minimising |a + B_S lam_S|, comb_support), at most 7
 * solves of size <= 3: cheaper than NNLS there. */
static double min_combination_small(int m, const double a[3], const double (*b)[3], double *lam)
{
    double best = sqrt(ex_dot3(a, a));
    for (int j = 0; j < m; j++) lam[j] = 0.0;
    for (int mask = 1; mask < (1 << m); mask++) {
        int set[3], n = 0, ok = 1;
        const double *v[3];
        double l[3], r[3], norm;
        for (int j = 0; j < m; j++)
            if (mask & (1 << j)) {
                v[n] = b[j];
                set[n++] = j;
            }
        if (!comb_support(n, a, v, l)) continue;
        for (int i = 0; i < n; i++) ok &= l[i] >= 0.0;
        if (!ok) continue;
        for (int d = 0; d < 3; d++) {
            r[d] = a[d];
            for (int i = 0; i < n; i++) r[d] += l[i] * v[i][d];
        }
        norm = sqrt(ex_dot3(r, r));
        if (norm < best) {
            best = norm;
            for (int j = 0; j < m; j++) lam[j] = 0.0;
            for (int i = 0; i < n; i++) lam[set[i]] = l[i];
        }
    }
    return best;
}

/* With b = -a / |a| and the columns b_j / |b_j|, min |a + B lam| over
 * lam >= 0 is |a| min |B' u - b| over u >= 0 (NNLS with a zero fourth row),
 * lam_j = u_j |a| / |b_j|. */
static double min_combination_nnls(int m, const double a[3], const double (*b)[3], double *lam, int *iters)
{
    double col[LDP_MAX_ROWS][4], nb[LDP_MAX_ROWS], u[LDP_MAX_ROWS], fv[4], na = sqrt(ex_dot3(a, a)), r[3];
    int it = 0;
    for (int j = 0; j < m; j++) lam[j] = 0.0;
    if (m && na > 0.0) {
        for (int j = 0; j < m; j++) {
            nb[j] = sqrt(ex_dot3(b[j], b[j]));
            for (int d = 0; d < 3; d++) col[j][d] = nb[j] > 0.0 ? b[j][d] / nb[j] : 0.0;
            col[j][3] = 0.0;
        }
        for (int d = 0; d < 3; d++) fv[d] = -a[d] / na;
        fv[3] = 0.0;
        ldp_nnls(m, (const double (*)[4])col, fv, u, &it);
        if (iters) *iters += it;
        for (int j = 0; j < m; j++) lam[j] = nb[j] > 0.0 ? u[j] * na / nb[j] : 0.0;
    }
    for (int d = 0; d < 3; d++) {
        r[d] = a[d];
        for (int j = 0; j < m; j++) r[d] += lam[j] * b[j][d];
    }
    return sqrt(ex_dot3(r, r));
}

double ldp_min_combination(int m, const double a[3], const double (*b)[3], double *lam, int *iters)
{
    return m <= 3 ? min_combination_small(m, a, b, lam) : min_combination_nnls(m, a, b, lam, iters);
}

/* In z = M^1/2 (v - vs) the projection is the least-distance problem
 * min |z| s.t. C z >= c, C_i = G_i M^-1/2, c_i = b_i - G_i vs (ldp_min_norm),
 * v = vs + M^-1/2 z, lam the multipliers of the rows. */
int ldp_project(const double minv[3], int nr, const double (*G)[3], const double *b, const double vs[3],
                double fq_min, double v[3], double *lam, size_t *iters, size_t *warnings)
{
    double C[LDP_MAX_ROWS][3], c[LDP_MAX_ROWS], y[LDP_MAX_ROWS], sq[3], z[3], wv = 0.0;
    int idx[LDP_MAX_ROWS], m = 0, worst = -1, it = 0, ok;
    for (int d = 0; d < 3; d++) {
        v[d] = vs[d];
        sq[d] = sqrt(minv[d]);
    }
    for (int i = 0; i < nr; i++) {
        double viol = b[i] - ex_dot3(G[i], vs);
        lam[i] = 0.0;
        if (!(fabs(G[i][0]) + fabs(G[i][1]) + fabs(G[i][2]) > fq_min)) continue;  /* cannot act */
        if (viol > wv) {
            wv = viol;
            worst = i;
        }
        for (int d = 0; d < 3; d++) C[m][d] = G[i][d] * sq[d];
        c[m] = viol;
        idx[m++] = i;
    }
    if (worst < 0) return 0; /* every row holds at vs */
    if (m == 1) {
        /* one row that can act, violated at vs: the projection onto its
         * half-space, lam = viol / (G M^-1 G'), in closed form (what the
         * LDP of one row gives; counted as one iteration) */
        double gmg = 0.0, l;
        for (int d = 0; d < 3; d++) gmg += G[worst][d] * G[worst][d] * minv[d];
        l = wv / gmg;
        for (int d = 0; d < 3; d++) v[d] = vs[d] + minv[d] * G[worst][d] * l;
        lam[worst] = l;
        (*iters)++;
        return 1;
    }
    ok = ldp_min_norm(m, (const double (*)[3])C, c, NULL, z, y, &it);
    *iters += (size_t)it;
    if (ok) {
        for (int d = 0; d < 3; d++) v[d] = vs[d] + sq[d] * z[d];
        for (int j = 0; j < m; j++) lam[idx[j]] = y[j];
        return 1;
    }
    /* pinched (no v satisfies every row) or no convergence: the most
     * violated row alone */
    (*warnings)++;
    {
        double gmg = 0.0, l;
        for (int d = 0; d < 3; d++) gmg += G[worst][d] * G[worst][d] * minv[d];
        l = (b[worst] - ex_dot3(G[worst], vs)) / gmg;
        for (int d = 0; d < 3; d++) v[d] = vs[d] + minv[d] * G[worst][d] * l;
        lam[worst] = l;
    }
    return 1;
}
