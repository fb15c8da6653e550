/* ldp.c -- the small dense solvers of the exdex core (ldp.h): Gaussian
 * elimination for n <= 3, Lawson-Hanson non-negative least squares in four
 * rows, and on it the least-distance problem of the contact solves. */
#include "ldp.h"
#include "util.h"

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
 * feasible iterate). */
#define NNLS_TOL 1e-13
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
            int ok = ls_passive(col, P, k, f, z);
            if (!ok) {
                /* the new column depends on the passive ones: never again */
                banned[P[--k]] = 1;
                u[jb] = 0.0;
                break;
            }
            for (int a = 0; a < k; a++)
                if (z[a] <= 0.0) {
                    double d = u[P[a]] - z[a], al = d > 0.0 ? u[P[a]] / d : 0.0;
                    if (al < alpha) alpha = al;
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

/* Project vs onto the stop rows in the metric of M = diag(1 / minv):
 *     min 1/2 (v - vs)' M (v - vs)  s.t.  G_i v >= b_i  (i < nr),
 * v = vs + M^-1 G' lam, lam >= 0 the row impulses (complementary to the
 * rows). Exact: with z = M^1/2 (v - vs) it is the least-distance problem
 * min |z| s.t. C z >= c, C = G M^-1/2, c = b - G vs, solved as the NNLS
 * min |E u - (0, 0, 0, 1)|, E = [C'; c'] (Lawson & Hanson, LDP, ch. 23):
 * z = C' u / (1 - c' u), lam = u / (1 - c' u). Rows are scaled to unit |C_i|
 * and c to max |c_i| = 1 first (neither changes the solution). Rows with
 * |G_i| <= FQ_MIN cannot act and are skipped. If the rows cannot all hold
 * (stops pinch the object: E u = f has a solution) or NNLS fails, the most
 * violated row alone is enforced and a warning counted. Returns 1 if some
 * row acted. */
int ldp_project(const double minv[3], int nr, const double (*G)[3], const double *b, const double vs[3],
                double fq_min, double v[3], double *lam, size_t *iters, size_t *warnings)
{
    double col[LDP_MAX_ROWS][4], nrm[LDP_MAX_ROWS], u[LDP_MAX_ROWS], sq[3], scale = 0.0, f[4] = {0, 0, 0, 1}, r[4];
    int idx[LDP_MAX_ROWS], m = 0, worst = -1, it = 0, ok;
    double wv = 0.0;
    for (int c = 0; c < 3; c++) {
        v[c] = vs[c];
        sq[c] = sqrt(minv[c]);
    }
    for (int i = 0; i < nr; i++) {
        double viol = b[i] - ex_dot3(G[i], vs);
        lam[i] = 0.0;
        if (!(fabs(G[i][0]) + fabs(G[i][1]) + fabs(G[i][2]) > fq_min)) continue;
        if (viol > wv) {
            wv = viol;
            worst = i;
        }
    }
    if (worst < 0) return 0; /* every row holds at vs */
    for (int i = 0; i < nr; i++) {
        double C[3], n, c;
        if (!(fabs(G[i][0]) + fabs(G[i][1]) + fabs(G[i][2]) > fq_min)) continue;
        for (int a = 0; a < 3; a++) C[a] = G[i][a] * sq[a];
        n = sqrt(ex_dot3(C, C));
        if (!(n > 0.0)) continue;
        c = (b[i] - ex_dot3(G[i], vs)) / n;
        for (int a = 0; a < 3; a++) col[m][a] = C[a] / n;
        col[m][3] = c;
        nrm[m] = n;
        idx[m++] = i;
        if (fabs(c) > scale) scale = fabs(c);
    }
    for (int j = 0; j < m; j++) col[j][3] /= scale;
    ok = ldp_nnls(m, (const double (*)[4])col, f, u, &it);
    *iters += (size_t)it;
    for (int i = 0; i < 4; i++) {
        r[i] = -f[i];
        for (int j = 0; j < m; j++) r[i] += col[j][i] * u[j];
    }
    if (ok && r[3] < -1e-12) {
        double z[3];
        for (int a = 0; a < 3; a++) {
            z[a] = -r[a] / r[3] * scale;
            v[a] = vs[a] + sq[a] * z[a];
        }
        for (int j = 0; j < m; j++) lam[idx[j]] = u[j] / (-r[3]) * scale / nrm[j];
        return 1;
    }
    /* pinched (no v satisfies every row) or no convergence */
    (*warnings)++;
    {
        double gmg = 0.0, l;
        for (int a = 0; a < 3; a++) gmg += G[worst][a] * G[worst][a] * minv[a];
        l = (b[worst] - ex_dot3(G[worst], vs)) / gmg;
        for (int a = 0; a < 3; a++) v[a] = vs[a] + minv[a] * G[worst][a] * l;
        lam[worst] = l;
    }
    return 1;
}

/* Minimum-norm point of { z : a_i . z >= c_i - tol_i, i in cand } (z in
 * R^n, n <= 3), exactly: the minimiser is z = sum_S y_i a_i with y >= 0 on
 * a support S of at most n linearly independent rows (Caratheodory), active
 * there (A_S A_S^T y = c_S); every such support with y >= 0 whose z satisfies
 * all the candidate rows is tried (nc <= PROJ_CAND: at most 92 solves of
 * size <= 3) and the shortest z kept. Returns 0 if none is feasible (the
 * rows contradict each other, e.g. two stops pinching the object). */

int ldp_min_norm_enum(int n, const double (*a)[3], const double *c, const double *tol, const int *cand, int nc,
                         double z[3])
{
    double best = INFINITY;
    for (int mask = 1; mask < (1 << nc); mask++) {
        int set[3], ns = 0, ok = 1;
        double H[3][3], rhs[3], y[3], zt[3] = {0, 0, 0}, zn;
        for (int j = 0; j < nc; j++)
            if (mask & (1 << j)) {
                if (ns < 3) set[ns] = cand[j];
                ns++;
            }
        if (ns > n) continue;
        for (int i = 0; i < ns; i++) {
            for (int j = 0; j < ns; j++) H[i][j] = ex_dot3(a[set[i]], a[set[j]]);
            rhs[i] = c[set[i]];
        }
        if (!ldp_solve_small(ns, H, rhs, y)) continue;
        for (int i = 0; i < ns; i++) ok &= y[i] >= 0.0;
        if (!ok) continue;
        for (int i = 0; i < ns; i++)
            for (int d = 0; d < 3; d++) zt[d] += y[i] * a[set[i]][d];
        for (int j = 0; j < nc; j++) ok &= ex_dot3(a[cand[j]], zt) >= c[cand[j]] - tol[cand[j]];
        if (!ok) continue;
        zn = ex_dot3(zt, zt);
        if (zn < best) {
            best = zn;
            memcpy(z, zt, sizeof zt);
        }
    }
    return best < INFINITY;
}
