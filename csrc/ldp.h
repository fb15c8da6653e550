/* ldp.h -- private to the exdex core: the one home of its small dense
 * solvers (Gaussian elimination for n <= 3, Lawson-Hanson NNLS, the
 * least-distance problem). Pure numerics: no model, no allocation. */
#ifndef EXDEX_LDP_H
#define EXDEX_LDP_H

#include <stddef.h>

#define LDP_MAX_ROWS 256  /* EXDEX_MAX_STOPS * EXDEX_MAX_VERTICES */

/* A x = b for n <= 3 (Gaussian elimination, partial pivoting); returns 0 if
 * A is numerically singular (a pivot below 1e-12 of the largest entry). A
 * and b are clobbered. */
int ldp_solve_small(int n, double A[3][3], double b[3], double x[3]);

/* Lawson-Hanson NNLS in four rows: min |E u - f| over u >= 0, E given by its
 * m <= LDP_MAX_ROWS columns col[j]. Returns 1 when converged, 0 otherwise
 * (u is then the last feasible iterate); *iters gets the outer iterations
 * added. */
int ldp_nnls(int m, const double (*col)[4], const double f[4], double *u, int *iters);

/* The projection of vs onto rows G_i v >= b_i (i < nr) in the metric
 * diag(1 / minv): min 1/2 (v - vs)' M (v - vs), v = vs + M^-1 G' lam with
 * lam >= 0 complementary to the rows. Rows with |G_i|_1 <= fq_min are
 * skipped. If the rows cannot all hold or NNLS fails, the most violated row
 * alone is enforced and *warnings incremented. Returns 1 if some row
 * acted; *iters gets the NNLS iterations added. */
int ldp_project(const double minv[3], int nr, const double (*G)[3], const double *b, const double vs[3],
                double fq_min, double v[3], double *lam, size_t *iters, size_t *warnings);

#define PROJ_CAND 8
int ldp_min_norm_enum(int n, const double (*a)[3], const double *c, const double *tol, const int *cand, int nc, double z[3]);

#endif
