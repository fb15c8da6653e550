/* stop_impulse.c -- the velocity-level contact step with Coulomb friction at
 * the contact rows (stop_impulse.h): mode enumeration, each mode solved
 * exactly. */
#include "stop_impulse.h"
#include "stop_friction.h"
#include "tolerances.h"
#include "util.h"

#include <float.h>
#include <math.h>
#include <string.h>

enum { OFF = FC_OFF, SLIDE_P = FC_SLIDE_P, SLIDE_M = FC_SLIDE_M, STICK = FC_STICK };


static double dotn(int n, const double *a, const double *b)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) s += a[i] * b[i];
    return s;
}

static double norm1(int n, const double *a)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) s += fabs(a[i]);
    return s;
}

/* Plate impulse P(v) = -cap A^T A v / |A v| and its Jacobian dP (n x n);
 * with a limit surface ls, P = cap A^T w(A v) and dP = -cap A^T H A (H the
 * Hessian of its dissipation at A v). Returns 0 at A v = 0 with cap > 0
 * (the sliding law is not defined). */
static int plate(const fc_problem *p, const double v[3], double P[3], double dP[3][3])
{
    int n = p->n;
    double u[3] = {0, 0, 0}, nu, B[3][3];
    for (int i = 0; i < n; i++) {
        P[i] = 0.0;
        for (int j = 0; j < n; j++) dP[i][j] = 0.0;
    }
    if (!(p->cap > 0.0)) return 1;
    for (int i = 0; i < n; i++) u[i] = dotn(n, p->A[i], v);
    nu = sqrt(dotn(n, u, u));
    if (!(nu > 0.0)) return 0;
    if (p->ls) {
        double wu[3], H[9];
        double D = limitsurf_wrench(p->ls, u, wu, H);
        if (!(D > 0.0) || !isfinite(D) || !(isfinite(wu[0]) && isfinite(wu[1]) && isfinite(wu[2]))) return 0;
        for (int i = 0; i < n; i++) {
            double s = 0.0;
            for (int k = 0; k < n; k++) s += p->A[k][i] * wu[k];
            P[i] = p->cap * s;
            for (int j = 0; j < n; j++) {
                double t = 0.0;
                for (int k = 0; k < n; k++)
                    for (int l = 0; l < n; l++) t += p->A[k][i] * H[3 * k + l] * p->A[l][j];
                dP[i][j] = -p->cap * t;
            }
        }
        return 1;
    }
    /* B = (I / nu - u u^T / nu^3) A */
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double s = p->A[i][j] / nu;
            for (int k = 0; k < n; k++) s -= u[i] * u[k] * p->A[k][j] / (nu * nu * nu);
            B[i][j] = s;
        }
    for (int i = 0; i < n; i++) {
        double s = 0.0;
        for (int k = 0; k < n; k++) s += p->A[k][i] * u[k];
        P[i] = -p->cap * s / nu;
        for (int j = 0; j < n; j++) {
            double t = 0.0;
            for (int k = 0; k < n; k++) t += p->A[k][i] * B[k][j];
            dP[i][j] = -p->cap * t;
        }
    }
    return 1;
}

/* The plate rest's split in the plane on the ellipsoid with frictional
 * rows: the limit of a plate creeping under the load (its slip along the
 * ellipsoid's normal, as a viscous band w = -k A v has it). With x = A^-T P
 * (|x| the ellipsoid norm), the creep's velocity is v ~ -A^-1 x, so each
 * row's gap rate G_i v and slip rate T_i v are, up to a positive factor,
 * b_i . x and t_i . x with b_i = A^-T (-G_i), t_i = A^-T (-T_i), while
 * x = a + sum lam_i b_i + sum beta_i t_i, a = A^-T (-M vs). The rows'
 * impulses are complementary to those rates (lam_i >= 0 _|_ b_i . x >= 0)
 * and Coulomb's law holds on each row's slip: the creep's (stick inside
 * the cone or slide at it) where |tb_i| <= vrest, else kinetic of the sign
 * of tb_i (the gripper drags the row past the object). That is
 * stop_friction.h's problem with M = I, one friction group per row and no
 * drift terms (sf_solve). Without friction its solution is the least-norm
 * split (the same complementarity is the KKT system of min |a + sum lam_i
 * b_i|); with friction the least norm over the cones would take the
 * friction most favourable to the plates whichever way they creep, e.g.
 * the plates pressing a block into a frictional incline, which a plate
 * that can only creep along it cannot. Returns 1 with x and the rows'
 * impulses (lam, beta over the nr rows, 0 for rows without force), 0 when
 * a row is out of sf_solve's range or no mode is consistent. */
static int creep_rest(const fc_problem *p, const double Ainv[3][3], const double a[3], double x[3], double *lam,
                      double *beta, fc_result *res)
{
    static const double one[3] = {1.0, 1.0, 1.0};
    sf_row rows[SF_MAX_ROWS];
    sf_stop st[SF_MAX_STOPS];
    sf_result sr;
    int who[SF_MAX_ROWS], m = 0, ok;
    double tol;
    for (int i = 0; i < p->nr; i++) {
        const fc_row *r = &p->rows[i];
        if (r->rest == 0 || !(norm1(3, r->G) > 0.0)) continue;
        if (m >= SF_MAX_ROWS) return 0;
        for (int c = 0; c < 3; c++) {
            rows[m].G[c] = st[m].T[c] = 0.0;
            for (int k = 0; k < 3; k++) {
                rows[m].G[c] -= Ainv[k][c] * r->G[k];
                st[m].T[c] -= Ainv[k][c] * r->T[k];
            }
        }
        rows[m].gdd0 = 0.0;
        rows[m].stop = m;
        st[m].sdd0 = 0.0;
        st[m].mu = r->mu;
        st[m].fm = !(r->mu > 0.0) ? SF_NONE : fabs(r->tb) <= p->vrest ? SF_ROLL : r->tb > 0.0 ? SF_SLIDE_P : SF_SLIDE_M;
        who[m++] = i;
    }
    tol = SF_TOL * fmax(sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]), p->cap_rest > p->cap ? p->cap_rest : p->cap);
    ok = sf_solve(m, rows, m, st, one, a, tol, tol, &sr);
    res->iters += sr.tried;
    if (!ok) return 0;
    for (int i = 0; i < p->nr; i++) lam[i] = beta[i] = 0.0;
    for (int j = 0; j < m; j++) {
        lam[who[j]] = sr.lam[j];
        beta[who[j]] = sr.beta[j];
    }
    memcpy(x, sr.qdd, 3 * sizeof *x);
    return 1;
}

/* Plate rest, v = 0: the rows that may carry force at rest give the
 * generators of their reaction cones (G; G +- mu T for a static contact,
 * |tb| <= vrest; G - mu sign(tb) T for a contact the gripper drags past the
 * object), and the plate impulse P = -M vs - sum l_j g_j must lie in the
 * ellipsoid, |A^-T P| <= cap. The least ellipsoid norm over l >= 0
 * (ldp_min_combination) decides, and its minimiser is the split with the
 * least plate friction: the contacts carry what they can. In the plane on
 * the ellipsoid with a frictional row the split is the creeping plate's
 * instead (creep_rest; where its problem has no consistent mode, the least
 * norm over the cones). */
static int try_rest(const fc_problem *p, double *lam, double *beta, fc_result *res)
{
    int n = p->n, m = 0, who[LDP_MAX_ROWS], it = 0;
    double g[LDP_MAX_ROWS][3], sgn[LDP_MAX_ROWS], a[3] = {0, 0, 0}, b[LDP_MAX_ROWS][3], l[LDP_MAX_ROWS];
    double Ainv[3][3], Mvs[3] = {0, 0, 0}, best, P[3];
    if (n == 1) {
        if (!(p->A[0][0] != 0.0)) return 0;
        Ainv[0][0] = 1.0 / p->A[0][0];
    } else {
        /* A^-1 by the adjugate (A is a scaled rotation and shear: well conditioned) */
        const double(*A)[3] = p->A;
        double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                     A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
        if (!(fabs(det) > 0.0) || !isfinite(det)) return 0;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
                Ainv[i][j] = (A[i1][j1] * A[i2][j2] - A[i1][j2] * A[i2][j1]) / det;
            }
    }
    for (int i = 0; i < p->nr; i++) {
        const fc_row *r = &p->rows[i];
        if (r->rest < 0) return 0;
        if (r->rest == 0 || !(norm1(n, r->G) > 0.0)) continue;
        if (m + 2 > LDP_MAX_ROWS) return 0;
        if (r->mu > 0.0 && fabs(r->tb) <= p->vrest) {
            for (int s = -1; s <= 1; s += 2) {
                for (int c = 0; c < n; c++) g[m][c] = r->G[c] + s * r->mu * r->T[c];
                sgn[m] = s;
                who[m++] = i;
            }
        } else {
            double s = r->mu > 0.0 ? -copysign(1.0, r->tb) : 0.0;
            for (int c = 0; c < n; c++) g[m][c] = r->G[c] + s * r->mu * r->T[c];
            sgn[m] = s;
            who[m++] = i;
        }
    }
    /* a = A^-T (-M vs), b_j = A^-T (-g_j) */
    for (int c = 0; c < n; c++) Mvs[c] = p->Md[c] * p->vs[c];
    for (int i = 0; i < 3; i++) {
        a[i] = 0.0;
        for (int j = 0; j < m; j++) b[j][i] = 0.0;
    }
    for (int i = 0; i < n; i++)
        for (int k = 0; k < n; k++) {
            a[i] -= Ainv[k][i] * Mvs[k];
            for (int j = 0; j < m; j++) b[j][i] -= Ainv[k][i] * g[j][k];
        }
    if (n == 3 && !p->ls) {
        int fric = 0;
        double x[3];
        for (int i = 0; i < p->nr; i++) fric |= p->rows[i].rest == 1 && p->rows[i].mu > 0.0;
        if (fric && creep_rest(p, (const double (*)[3])Ainv, a, x, lam, beta, res)) {
            double cr = p->cap_rest > p->cap ? p->cap_rest : p->cap;
            if (!(sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) <= cr * (1.0 + 1e-12))) return 0;
            for (int c = 0; c < 3; c++) {
                P[c] = -Mvs[c];
                for (int i = 0; i < p->nr; i++) P[c] -= lam[i] * p->rows[i].G[c] + beta[i] * p->rows[i].T[c];
                res->v[c] = 0.0;
                res->P[c] = P[c];
            }
            res->rest = 1;
            return 1;
        }
    }
    {
        double cr = p->cap_rest > p->cap ? p->cap_rest : p->cap;
        /* a limit surface: its least gauge over the splits, stopping at the
         * first one it carries (limitsurf_min_combination) */
        best = p->ls && n == 3 ? limitsurf_min_combination(p->ls, m, a, (const double (*)[3])b, cr, l, &it)
                               : ldp_min_combination(m, a, (const double (*)[3])b, l, &it);
        res->iters += it;
        if (!(best <= cr * (1.0 + 1e-12))) return 0;
    }
    for (int i = 0; i < p->nr; i++) lam[i] = beta[i] = 0.0;
    for (int c = 0; c < n; c++) P[c] = -Mvs[c];
    for (int j = 0; j < m; j++) {
        const fc_row *r = &p->rows[who[j]];
        lam[who[j]] += l[j];
        beta[who[j]] += sgn[j] * r->mu * l[j];
        for (int c = 0; c < n; c++) P[c] -= l[j] * g[j][c];
    }
    for (int c = 0; c < 3; c++) {
        res->v[c] = 0.0;
        res->P[c] = c < n ? P[c] : 0.0;
    }
    res->rest = 1;
    return 1;
}

/* Slip directions of the sliding modes: SLIDE_P slips with s > 0 (beta =
 * -mu lam), SLIDE_M with s < 0 (beta = +mu lam). */
static double slide_sign(int mode) { return mode == SLIDE_P ? 1.0 : -1.0; }

/* One mode: the candidate rows C (nc) with modes md. Equalities: G_i v =
 * rhs_i for every row that is on, T v = -tb once per group of sticking
 * rows with the same T and tb (the two corners of an edge flush against a
 * contact slip together: one equation, one tangential impulse for the
 * group, split in proportion to the rows' bounds mu_i lam_i). With v = vp +
 * N z on the affine set of the equalities (m independent ones), the
 * unknowns are z (n - m), lam of the rows that are on and beta of the
 * sticking groups: n in all, for the n equations
 *     R = M (v - vs) - P(v) - sum lam_i D_i - sum beta_g T_g = 0,
 * D_i = G_i - mu_i sigma_i T_i for a row sliding with slip sign sigma_i,
 * G_i for a sticking one. R is linear in lam, beta and smooth in z (the
 * plate slides, A v != 0); Newton's method with backtracking on |R|_M^-1
 * converges quadratically. Then the signs are checked. Returns 1 with the
 * solution if the mode is consistent. wide: the enumeration of fc_solve's
 * wide candidates (a start without plate slip is allowed there). */
static int try_mode(const fc_problem *p, const int *C, int nc, const int *md, const double v0[3], int wide,
                    double *lam, double *beta, fc_result *res)
{
    int n = p->n, m = 0, on[FC_MAX_WIDE], k = 0, grp[FC_MAX_WIDE], gfirst[FC_MAX_WIDE], ng = 0;
    double E[3][3], e[3], Q[3][3], N[3][3], vp[3] = {0, 0, 0}, z[3] = {0, 0, 0}, x[3] = {0, 0, 0};
    double D[FC_MAX_WIDE][3], v[3] = {0, 0, 0}, Pf[3], dP[3][3], Ls, vtol;
    int nz, converged = 0;
    /* equalities */
    for (int a = 0; a < nc; a++) {
        const fc_row *r = &p->rows[C[a]];
        grp[a] = -1;
        if (md[a] == OFF) continue;
        if (m >= n) return 0;
        for (int c = 0; c < n; c++) E[m][c] = r->G[c];
        e[m++] = r->rhs;
        on[k++] = a;
        for (int c = 0; c < n; c++)
            D[a][c] = md[a] == STICK ? r->G[c] : r->G[c] - r->mu * slide_sign(md[a]) * r->T[c];
    }
    for (int a = 0; a < nc; a++) {
        const fc_row *r = &p->rows[C[a]];
        int g = -1;
        if (md[a] != STICK) continue;
        for (int h = 0; h < ng && g < 0; h++) {
            const fc_row *q = &p->rows[C[gfirst[h]]];
            double d = 0.0;
            for (int c = 0; c < n; c++) d += fabs(q->T[c] - r->T[c]);
            if (d <= 1e-12 * norm1(n, r->T) && fabs(q->tb - r->tb) <= FRICTION_BAND * (p->vscale + fabs(r->tb))) g = h;
        }
        if (g < 0) {
            if (m >= n || ng >= FC_MAX_WIDE) return 0;
            g = ng;
            gfirst[ng++] = a;
            for (int c = 0; c < n; c++) E[m][c] = r->T[c];
            e[m++] = -r->tb;
        }
        grp[a] = g;
    }
    /* orthonormal basis Q of the equalities' span (Gram-Schmidt); dependent
     * equalities make the impulses indeterminate: not a mode of its own */
    for (int i = 0; i < m; i++) {
        double w[3], nn0 = sqrt(dotn(n, E[i], E[i])), nn;
        for (int c = 0; c < n; c++) w[c] = E[i][c];
        for (int pass = 0; pass < 2; pass++)
            for (int j = 0; j < i; j++) {
                double d = dotn(n, Q[j], w);
                for (int c = 0; c < n; c++) w[c] -= d * Q[j][c];
            }
        nn = sqrt(dotn(n, w, w));
        if (!(nn > 1e-9 * nn0)) return 0;
        for (int c = 0; c < n; c++) Q[i][c] = w[c] / nn;
    }
    if (m > 0) {
        double Gm[3][3], y[3];
        for (int i = 0; i < m; i++)
            for (int j = 0; j < m; j++) Gm[i][j] = dotn(n, E[i], E[j]);
        if (!ldp_solve_small(m, Gm, e, y)) return 0;
        for (int c = 0; c < n; c++)
            for (int i = 0; i < m; i++) vp[c] += y[i] * E[i][c];
    }
    nz = n - m;
    /* null-space basis: unit vectors orthogonalised against Q, the largest
     * residuals first */
    {
        int used[3] = {0, 0, 0};
        double W[3][3];
        for (int j = 0; j < n; j++) {
            for (int c = 0; c < n; c++) W[j][c] = c == j ? 1.0 : 0.0;
            for (int i = 0; i < m; i++) {
                double d = Q[i][j];
                for (int c = 0; c < n; c++) W[j][c] -= d * Q[i][c];
            }
        }
        for (int b = 0; b < nz; b++) {
            int best = -1;
            double bn = 0.0;
            for (int j = 0; j < n; j++) {
                double w[3], nn;
                if (used[j]) continue;
                for (int c = 0; c < n; c++) w[c] = W[j][c];
                for (int i = 0; i < b; i++) {
                    double d = 0.0;
                    for (int c = 0; c < n; c++) d += N[c][i] * w[c];
                    for (int c = 0; c < n; c++) w[c] -= d * N[c][i];
                }
                nn = sqrt(dotn(n, w, w));
                if (nn > bn) {
                    bn = nn;
                    best = j;
                    for (int c = 0; c < n; c++) W[j][c] = w[c];
                }
            }
            if (best < 0 || !(bn > 1e-6)) return 0;
            used[best] = 1;
            for (int c = 0; c < n; c++) N[c][b] = W[best][c] / bn;
        }
    }
    for (int j = 0; j < nz; j++) {
        z[j] = 0.0;
        for (int c = 0; c < n; c++) z[j] += N[c][j] * (v0[c] - vp[c]);
    }
    /* Newton on x = (z, lam_on, beta_groups) */
    for (int it = 0; it < 40; it++) {
        double R[3], J[3][3], dx[3], r0 = 0.0, t = 1.0, xs[3], vv[3], zs[3];
        for (int c = 0; c < n; c++) {
            v[c] = vp[c];
            for (int j = 0; j < nz; j++) v[c] += N[c][j] * z[j];
        }
        int lin = 0;
        if (!plate(p, v, Pf, dP)) {
            /* the start has no plate slip (A v = 0), where the sliding law
             * is not defined: in the wide enumeration the first iterate
             * solves the mode without the plate term (linear, one step),
             * a velocity at which the plate slides, and Newton goes on
             * from there */
            if (!(wide && it == 0 && p->cap > 0.0)) return 0;
            lin = 1;
            for (int c = 0; c < n; c++) {
                Pf[c] = 0.0;
                for (int d = 0; d < n; d++) dP[c][d] = 0.0;
            }
        }
        for (int c = 0; c < n; c++) {
            R[c] = p->Md[c] * (v[c] - p->vs[c]) - Pf[c];
            for (int a = 0; a < k; a++) R[c] -= x[a] * D[on[a]][c];
            for (int g = 0; g < ng; g++) R[c] -= x[k + g] * p->rows[C[gfirst[g]]].T[c];
            r0 += R[c] * R[c] / p->Md[c];
        }
        for (int c = 0; c < n; c++) {
            for (int j = 0; j < nz; j++) {
                double s = p->Md[c] * N[c][j];
                for (int d = 0; d < n; d++) s -= dP[c][d] * N[d][j];
                J[c][j] = s;
            }
            for (int a = 0; a < k; a++) J[c][nz + a] = -D[on[a]][c];
            for (int g = 0; g < ng; g++) J[c][nz + k + g] = -p->rows[C[gfirst[g]]].T[c];
            R[c] = -R[c];
        }
        if (!ldp_solve_small(n, J, R, dx)) return 0;
        res->iters++;
        if (lin) {
            for (int j = 0; j < nz; j++) z[j] += dx[j];
            for (int a = 0; a < k + ng; a++) x[a] += dx[nz + a];
            continue;
        }
        if (!(p->cap > 0.0)) {
            /* linear: one step is exact */
            for (int j = 0; j < nz; j++) z[j] += dx[j];
            for (int a = 0; a < k + ng; a++) x[a] += dx[nz + a];
            converged = 1;
            break;
        }
        /* backtracking on |R|^2_{M^-1}, accepting rounding-level increases */
        for (int ls = 0; ls < 30; ls++) {
            double rt = 0.0, Pt[3], dPt[3][3];
            for (int j = 0; j < nz; j++) zs[j] = z[j] + t * dx[j];
            for (int a = 0; a < k + ng; a++) xs[a] = x[a] + t * dx[nz + a];
            for (int c = 0; c < n; c++) {
                vv[c] = vp[c];
                for (int j = 0; j < nz; j++) vv[c] += N[c][j] * zs[j];
            }
            if (plate(p, vv, Pt, dPt)) {
                for (int c = 0; c < n; c++) {
                    double rc = p->Md[c] * (vv[c] - p->vs[c]) - Pt[c];
                    for (int a = 0; a < k; a++) rc -= xs[a] * D[on[a]][c];
                    for (int g = 0; g < ng; g++) rc -= xs[k + g] * p->rows[C[gfirst[g]]].T[c];
                    rt += rc * rc / p->Md[c];
                }
                if (rt <= r0 * (1.0 - 1e-4 * t) || rt <= 1e-28 * (r0 + 1e-300)) break;
                if (rt <= r0 + 64.0 * DBL_EPSILON * r0) break;
            }
            t *= 0.5;
        }
        for (int j = 0; j < nz; j++) z[j] = zs[j];
        for (int a = 0; a < k + ng; a++) x[a] = xs[a];
        {
            double sn = 0.0, vn = 0.0;
            for (int c = 0; c < n; c++) {
                double d = 0.0;
                for (int j = 0; j < nz; j++) d += N[c][j] * t * dx[j];
                sn += p->Md[c] * d * d;
                vn += p->Md[c] * vv[c] * vv[c];
            }
            if (sqrt(sn) <= 1e-14 * (1e-3 * p->vscale * sqrt(p->Md[0]) + sqrt(vn))) {
                converged = 1;
                break;
            }
        }
    }
    if (!converged) return 0;
    for (int c = 0; c < n; c++) {
        v[c] = vp[c];
        for (int j = 0; j < nz; j++) v[c] += N[c][j] * z[j];
    }
    if (!plate(p, v, Pf, dP)) return 0;
    /* signs */
    Ls = p->cap;
    for (int c = 0; c < n; c++) Ls += p->Md[c] * (fabs(v[c]) + fabs(p->vs[c]));
    vtol = FRICTION_BAND * (p->vscale + norm1(n, v));
    for (int a = 0; a < k; a++) {
        int i = on[a];
        const fc_row *r = &p->rows[C[i]];
        if (x[a] < -FRICTION_BAND * Ls) return 0;
        if (md[i] == SLIDE_P || md[i] == SLIDE_M) {
            double s = dotn(n, r->T, v) + r->tb;
            if (r->mu > 0.0 && slide_sign(md[i]) * s < -(vtol + FRICTION_BAND * fabs(r->tb))) return 0;
        }
    }
    for (int g = 0; g < ng; g++) {
        double bound = 0.0;
        for (int a = 0; a < k; a++)
            if (grp[on[a]] == g) bound += p->rows[C[on[a]]].mu * fmax(x[a], 0.0);
        if (!(fabs(x[k + g]) <= bound * (1.0 + FRICTION_BAND) + FRICTION_BAND * Ls)) return 0;
    }
    /* separating candidates hold (the other rows: fc_solve) */
    for (int a = 0; a < nc; a++) {
        const fc_row *r = &p->rows[C[a]];
        if (md[a] != OFF) continue;
        if (dotn(n, r->G, v) - r->rhs < -FRICTION_BAND * (p->vscale * norm1(n, r->G) + fabs(r->rhs))) return 0;
    }
    /* consistent: the impulses */
    for (int i = 0; i < p->nr; i++) lam[i] = beta[i] = 0.0;
    for (int a = 0; a < k; a++) {
        int i = on[a];
        const fc_row *r = &p->rows[C[i]];
        double l = fmax(x[a], 0.0);
        lam[C[i]] = l;
        if (md[i] == SLIDE_P || md[i] == SLIDE_M) {
            beta[C[i]] = -slide_sign(md[i]) * r->mu * l;
        } else {
            double bound = 0.0;
            int g = grp[i];
            for (int b = 0; b < k; b++)
                if (grp[on[b]] == g) bound += p->rows[C[on[b]]].mu * fmax(x[b], 0.0);
            beta[C[i]] = bound > 0.0 ? x[k + g] * r->mu * l / bound : 0.0;
        }
    }
    for (int c = 0; c < 3; c++) {
        res->v[c] = c < n ? v[c] : 0.0;
        res->P[c] = c < n ? Pf[c] : 0.0;
    }
    res->rest = 0;
    return 1;
}

/* Most violated row outside the candidates at v, or -1. */
static int worst_row(const fc_problem *p, const int *C, int nc, const double v[3])
{
    int worst = -1;
    double wv = 0.0;
    for (int i = 0; i < p->nr; i++) {
        const fc_row *r = &p->rows[i];
        double viol = r->rhs - dotn(p->n, r->G, v);
        int in = 0;
        for (int a = 0; a < nc; a++) in |= C[a] == i;
        if (in) continue;
        if (viol > FRICTION_BAND * (p->vscale * norm1(p->n, r->G) + fabs(r->rhs)) && viol > wv) {
            wv = viol;
            worst = i;
        }
    }
    return worst;
}

/* The rounds of the enumeration from the candidates C (nc, room for cap):
 * every mode of the candidates (per row: the guess, stick, the other slide,
 * separate; a frictionless row: on or off), the first consistent one; then
 * a row outside the candidates that it violates joins them and the modes
 * are enumerated again. Returns 1 with the solution (and modes), 0 when a
 * round has no consistent mode or the candidates would exceed cap. */
static int enumerate(const fc_problem *p, int *C, int nc, int cap, const double v0[3], int *modes, double *lam,
                     double *beta, fc_result *res)
{
    int guess[FC_MAX_WIDE], ord[FC_MAX_WIDE][4], nord[FC_MAX_WIDE], md[FC_MAX_WIDE];
    for (int round = 0; round <= cap; round++) {
        int total = 1, found = 0;
        for (int a = 0; a < nc; a++) {
            const fc_row *r = &p->rows[C[a]];
            double s = dotn(p->n, r->T, v0) + r->tb;
            guess[a] = !(r->mu > 0.0) ? SLIDE_P
                       : modes && modes[C[a]] != OFF ? modes[C[a]]
                       : fabs(s) <= FRICTION_BAND * (p->vscale + fabs(r->tb)) ? STICK
                       : s > 0.0                                      ? SLIDE_P
                                                                      : SLIDE_M;
        }
        /* each row's modes in the order: the guess, stick, the other
         * slide, separate (a frictionless row: on or off); the first
         * code is the guess */
        for (int a = 0; a < nc; a++) {
            int g = guess[a], *o = ord[a], k = 0;
            o[k++] = g;
            if (p->rows[C[a]].mu > 0.0) {
                if (g != STICK) o[k++] = STICK;
                if (g != SLIDE_P) o[k++] = SLIDE_P;
                if (g != SLIDE_M) o[k++] = SLIDE_M;
            }
            o[k++] = OFF;
            nord[a] = k;
            total *= k;
        }
        for (int code = 0; code < total && !found; code++) {
            int c = code;
            for (int a = 0; a < nc; a++) {
                md[a] = ord[a][c % nord[a]];
                c /= nord[a];
            }
            found = try_mode(p, C, nc, md, v0, cap > FC_MAX_CAND, lam, beta, res);
        }
        if (!found) return 0;
        {
            /* a row outside the candidates violated: enumerate with it */
            int w = worst_row(p, C, nc, res->v);
            if (w < 0) {
                if (modes) {
                    for (int i = 0; i < p->nr; i++) modes[i] = OFF;
                    for (int a = 0; a < nc; a++) modes[C[a]] = md[a];
                }
                return 1;
            }
            if (nc == cap) return 0;
            C[nc++] = w;
        }
    }
    return 0;
}

/* Rows i and j lie on one line of contact: frictional, the same Coulomb
 * coefficient, the same tangent row and frame slip (T = (t, r x t) is the
 * same for every point of a line with tangent t) and the same normal part
 * of G (n = 3: G = (n, r x n)). */
static int same_line(const fc_problem *p, int i, int j)
{
    const fc_row *a = &p->rows[i], *b = &p->rows[j];
    double dt = 0.0, tn = norm1(3, a->T), gn = fabs(a->G[0]) + fabs(a->G[1]);
    if (p->n != 3 || !(a->mu > 0.0) || a->mu != b->mu) return 0;
    for (int c = 0; c < 3; c++) dt += fabs(a->T[c] - b->T[c]);
    return dt <= 1e-12 * tn && fabs(a->tb - b->tb) <= FRICTION_BAND * (p->vscale + fabs(a->tb)) &&
           fabs(a->G[0] - b->G[0]) + fabs(a->G[1] - b->G[1]) <= 1e-12 * gn;
}

/* Squared distance of rows i and j's G. */
static double gdist2(const fc_problem *p, int i, int j)
{
    double d = 0.0;
    for (int c = 0; c < p->n; c++) d += (p->rows[i].G[c] - p->rows[j].G[c]) * (p->rows[i].G[c] - p->rows[j].G[c]);
    return d;
}

/* Candidates of the wide enumeration into C (returns their count, -1 beyond
 * FC_MAX_WIDE): the rows that may carry an impulse, i.e. the hint's rows,
 * the rows touching at rest (rest 1) and the rows v0 violates, each line
 * of contact (same_line) by its two extreme rows (the pair farthest apart
 * in G). On one line G_i = (n, r_i x n) is affine in the point's place, so
 * every other row's G is a convex combination of the extremes': an impulse
 * on it is one on the extremes, and its gap rate G_i v - rhs_i (rhs affine
 * too: the gaps of points on the line) holds when theirs do; worst_row
 * still checks it. */
static int wide_candidates(const fc_problem *p, const unsigned char *hint, const double v0[3], int *C)
{
    int nc = 0;
    for (int i = 0; i < p->nr; i++) {
        const fc_row *r = &p->rows[i];
        int want = (hint && hint[i]) || r->rest == 1 ||
                   dotn(p->n, r->G, v0) - r->rhs < -FRICTION_BAND * (p->vscale * norm1(p->n, r->G) + fabs(r->rhs));
        int ea = i, eb = i;
        double da = 0.0, db = 0.0;
        if (!want) continue;
        /* the line's extremes among all its rows: ea the farthest from row
         * i, eb the farthest from ea */
        for (int j = 0; j < p->nr; j++)
            if (same_line(p, i, j) && gdist2(p, i, j) > da) {
                da = gdist2(p, i, j);
                ea = j;
            }
        for (int j = 0; j < p->nr; j++)
            if (same_line(p, i, j) && gdist2(p, ea, j) > db) {
                db = gdist2(p, ea, j);
                eb = j;
            }
        for (int e = 0; e < 2; e++) {
            int x = e ? eb : ea, dup = 0;
            for (int a = 0; a < nc; a++) dup |= C[a] == x;
            if (dup) continue;
            if (nc == FC_MAX_WIDE) return -1;
            C[nc++] = x;
        }
    }
    return nc;
}

int fc_solve(const fc_problem *p, const unsigned char *hint, const double v0[3], int *modes, double *lam,
             double *beta, fc_result *res)
{
    int C[FC_MAX_WIDE], nc = 0, over = 0;
    res->iters = 0;
    if (try_rest(p, lam, beta, res)) {
        if (modes)
            for (int i = 0; i < p->nr; i++) modes[i] = lam[i] > 0.0 ? STICK : OFF;
        return 1;
    }
    for (int i = 0; i < p->nr && hint; i++)
        if (hint[i]) {
            if (nc == FC_MAX_CAND) {
                over = 1;
                break;
            }
            C[nc++] = i;
        }
    if (!over && enumerate(p, C, nc, FC_MAX_CAND, v0, modes, lam, beta, res)) return 1;
    /* the hint's rows did not suffice (a row it leaves out must carry an
     * impulse, or more than FC_MAX_CAND rows): the wide candidates */
    nc = wide_candidates(p, hint, v0, C);
    return nc >= 0 && enumerate(p, C, nc, FC_MAX_WIDE, v0, modes, lam, beta, res);
}
