/* ldp.h -- private to the exdex core: the one home of its small dense
 * solvers. Gaussian elimination for n <= 3, Lawson-Hanson non-negative
 * least squares (NNLS) in four rows, and on it the least-distance problem
 * (LDP) min |z| s.t. a_i . z >= c_i, which every contact solve of the
 * methods reduces to: velocity and acceleration projections onto stop rows
 * in the mass metric, position projections, and the least-friction split
 * of a rest against stops. Pure numerics: no model, no allocation, every
 * loop bounded. */
#ifndef EXDEX_LDP_H
#define EXDEX_LDP_H

#include <stddef.h>

#define LDP_MAX_ROWS 256  /* EXDEX_MAX_STOPS * EXDEX_MAX_VERTICES */

/* A x = b for n <= 3 (Gaussian elimination, partial pivoting); returns 0 if
 * A is numerically singular (a pivot below 1e-12 of the largest entry). A
 * and b are clobbered. */
int ldp_solve_small(int n, double A[3][3], double b[3], double x[3]);

/* NNLS in four rows: min |E u - f| over u >= 0, E given by its
 * m <= LDP_MAX_ROWS columns col[j]. Lawson-Hanson active set; the passive
 * set holds at most 4 linearly independent columns, each least-squares
 * solve a modified Gram-Schmidt QR of them. At most 3 m + 12 outer and 8
 * inner iterations per outer one. Returns 1 when converged (no column
 * outside the passive set has a multiplier above 1e-13 |f|-relative), 0
 * otherwise (u is then the last feasible iterate); *iters gets the outer
 * iterations added. */
int ldp_nnls(int m, const double (*col)[4], const double f[4], double *u, int *iters);

/* Least distance: z = argmin |z| over { z in R^3 : a_i . z >= c_i - tol_i,
 * i < m <= LDP_MAX_ROWS } (tol may be NULL: all 0; a problem in fewer
 * dimensions has zero components in every a_i). y (m entries) gets the
 * multipliers, y >= 0, z = sum y_i a_i, y_i > 0 only on rows that hold with
 * equality. Returns 1 if solved, 0 if the rows are inconsistent (no z
 * satisfies them all) or NNLS did not converge; z = 0 then. iters may be
 * NULL. */
int ldp_min_norm(int m, const double (*a)[3], const double *c, const double *tol, double z[3], double *y,
                 int *iters);

/* The least combination: lam = argmin |a + sum_j lam_j b_j| over lam >= 0
 * (m <= LDP_MAX_ROWS vectors b_j); returns that minimum. Up to 3 vectors by
 * trying every support, more by NNLS. iters (may be NULL) gets the NNLS
 * iterations added. */
double ldp_min_combination(int m, const double a[3], const double (*b)[3], double *lam, int *iters);

/* The projection of vs onto rows G_i v >= b_i (i < nr) in the metric
 * diag(1 / minv): min 1/2 (v - vs)' M (v - vs), v = vs + M^-1 G' lam with
 * lam >= 0 complementary to the rows. Rows with |G_i|_1 <= fq_min cannot act
 * and are skipped. One row that can act is projected onto in closed form
 * (lam = viol / (G M^-1 G'), one iteration counted). If the rows cannot all hold or NNLS fails, the most
 * violated row alone is enforced and *warnings incremented. Returns 1 if
 * some row acted; *iters gets the NNLS iterations added. */
int ldp_project(const double minv[3], int nr, const double (*G)[3], const double *b, const double vs[3],
                double fq_min, double v[3], double *lam, size_t *iters, size_t *warnings);

#endif
