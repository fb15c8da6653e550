/* stop_friction.c -- the acceleration-level contact problem of a planar object
 * against frictional stops (stop_friction.h): mode enumeration, each mode solved
 * exactly. */
#include "stop_friction.h"
#include "ldp.h"
#include "util.h"

#include <math.h>
#include <string.h>

#define MAX_TRIED 4096  /* modes solved at most */
#define KMAX (SF_MAX_ROWS + SF_MAX_STOPS)  /* constraints of one mode */
#define GMAX (2 * SF_MAX_ROWS)             /* force generators of one mode */
enum { LOCKS_NONE = 0, LOCKS_ONLY = 1, LOCKS_TOO = 2 };  /* solve_mode: which modes it solves */

int sf_lock_solve(int k, const double (*C)[3], const double *rhs, const double minv[3], double tol, double x[3])
{
    double Cn[KMAX][3], sq[3], best = 0.0, A[3][3], b[3];
    int sel[3] = {-1, -1, -1};
    if (k < 3 || k > KMAX) return 0;
    for (int c = 0; c < 3; c++) sq[c] = sqrt(minv[c]);
    for (int l = 0; l < k; l++) {
        double nn = 0.0;
        for (int c = 0; c < 3; c++) nn += (C[l][c] * sq[c]) * (C[l][c] * sq[c]);
        nn = sqrt(nn);
        for (int c = 0; c < 3; c++) Cn[l][c] = nn > 0.0 ? C[l][c] * sq[c] / nn : 0.0;
    }
    for (int i = 0; i < k; i++)
        for (int j = i + 1; j < k; j++)
            for (int l = j + 1; l < k; l++) {
                double cr[3], d;
                ex_cross3(cr, Cn[i], Cn[j]);
                d = fabs(ex_dot3(cr, Cn[l]));
                if (d > best) {
                    best = d;
                    sel[0] = i;
                    sel[1] = j;
                    sel[2] = l;
                }
            }
    if (!(best > SF_LOCK_RANK)) return 0;
    for (int l = 0; l < 3; l++) {
        for (int c = 0; c < 3; c++) A[l][c] = C[sel[l]][c];
        b[l] = rhs[sel[l]];
    }
    if (!ldp_solve_small(3, A, b, x)) return 0;
    for (int l = 0; l < k; l++)
        if (!(fabs(ex_dot3(C[l], x) - rhs[l]) <= tol)) return 0;
    return 1;
}

/* Do the rows whose gap acceleration in r is within tol_a of 0 span the
 * plane's three coordinates (unit rows in the metric diag(minv)^1/2, a
 * volume above SF_LOCK_RANK)? Then they fix qdd by themselves. */
static int rows_fix_qdd(int nr, const sf_row *rows, const double minv[3], double tol_a, const sf_result *r)
{
    double Cn[SF_MAX_ROWS][3];
    int n = 0;
    for (int i = 0; i < nr; i++) {
        double nn = 0.0;
        if (!(fabs(r->acc[i]) <= tol_a)) continue;
        for (int c = 0; c < 3; c++) nn += rows[i].G[c] * rows[i].G[c] * minv[c];
        nn = sqrt(nn);
        if (!(nn > 0.0)) continue;
        for (int c = 0; c < 3; c++) Cn[n][c] = rows[i].G[c] * sqrt(minv[c]) / nn;
        n++;
    }
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            for (int l = j + 1; l < n; l++) {
                double cr[3];
                ex_cross3(cr, Cn[i], Cn[j]);
                if (fabs(ex_dot3(cr, Cn[l])) > SF_LOCK_RANK) return 1;
            }
    return 0;
}

/* ------------------------------------------------ the plate (sf_plate) */

/* h(mu) = mu |z| - gam with (I + mu Kh) z = ch, z written. 0 where I + mu Kh
 * is singular (a pole of z). */
static int plate_h(const double Kh[3][3], const double ch[3], double mu, double gam, double *h, double z[3])
{
    double A[3][3], b[3];
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) A[i][j] = (i == j ? 1.0 : 0.0) + mu * Kh[i][j];
        b[i] = ch[i];
    }
    if (!ldp_solve_small(3, A, b, z)) return 0;
    *h = mu * sqrt(ex_dot3(z, z)) - gam;
    return isfinite(*h);
}

/* The least eigenvalue of the symmetric part of K (closed form: the
 * trigonometric solution of its characteristic cubic). */
static double sym_min_eig(const double K[3][3])
{
    double S[3][3], q, p1, p2, p, B[3][3], r, phi;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) S[i][j] = 0.5 * (K[i][j] + K[j][i]);
    p1 = S[0][1] * S[0][1] + S[0][2] * S[0][2] + S[1][2] * S[1][2];
    q = (S[0][0] + S[1][1] + S[2][2]) / 3.0;
    p2 = (S[0][0] - q) * (S[0][0] - q) + (S[1][1] - q) * (S[1][1] - q) + (S[2][2] - q) * (S[2][2] - q) + 2.0 * p1;
    p = sqrt(p2 / 6.0);
    if (!(p > 0.0)) return q;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) B[i][j] = (S[i][j] - (i == j ? q : 0.0)) / p;
    r = 0.5 * (B[0][0] * (B[1][1] * B[2][2] - B[1][2] * B[2][1]) - B[0][1] * (B[1][0] * B[2][2] - B[1][2] * B[2][0]) +
               B[0][2] * (B[1][0] * B[2][1] - B[1][1] * B[2][0]));
    phi = acos(fmax(-1.0, fmin(1.0, r))) / 3.0;
    return q + 2.0 * p * cos(phi + acos(-0.5)); /* phi + 2 pi / 3 */
}

/* False position with the Illinois halving (the end that stays has its
 * value halved) on a bracket lo < hi of h (hlo < 0 < hhi), to |h| <=
 * PLATE_ROOT_TOL gam or a bracket within PLATE_ROOT_TOL of mu (where the
 * rounding of h, which grows with mu, is above the first); z and *mu at the
 * root. Returns 0 when the steps run out or h cannot be evaluated. */
static int plate_refine(const double Kh[3][3], const double ch[3], double gam, double lo, double hlo, double hi,
                        double hhi, double z[3], double *mu)
{
    int side = 0;
    double h;
    for (int it = 0; it < PLATE_ROOT_MAX; it++) {
        *mu = (lo * hhi - hi * hlo) / (hhi - hlo);
        if (!(*mu > lo && *mu < hi)) *mu = 0.5 * (lo + hi);
        if (!plate_h(Kh, ch, *mu, gam, &h, z)) return 0;
        if (fabs(h) <= PLATE_ROOT_TOL * gam || hi - lo <= PLATE_ROOT_TOL * hi) return 1;
        if (h < 0.0) {
            lo = *mu;
            hlo = h;
            if (side < 0) hhi *= 0.5;
            side = -1;
        } else {
            hi = *mu;
            hhi = h;
            if (side > 0) hlo *= 0.5;
            side = 1;
        }
    }
    return 0;
}

/* p(x) for the coefficients p[0 .. n]. */
static double poly_at(const double *p, int n, double x)
{
    double v = p[n];
    for (int i = n - 1; i >= 0; i--) v = v * x + p[i];
    return v;
}

/* The roots of p (degree n, 1 <= n <= 6, p[n] != 0) in (lo, hi), ascending:
 * p is monotone between consecutive roots of its derivative, which are found
 * in turn the same way (from the linear derivative up), so each of those
 * intervals holds at most one root, located by bisection on its sign change
 * (PLATE_POLY_BISECT steps at most; a root of even multiplicity, without a
 * sign change, is not returned). Returns their count. */
static int poly_roots(const double *p, int n, double lo, double hi, double r[6])
{
    double d[7][7], x[8], y[6];
    int nx, ny = 0;
    for (int i = 0; i <= n; i++) d[0][i] = p[i];
    for (int k = 1; k < n; k++)
        for (int i = 0; i <= n - k; i++) d[k][i] = (i + 1) * d[k - 1][i + 1];
    {
        double t = -d[n - 1][0] / d[n - 1][1];
        if (t > lo && t < hi) y[ny++] = t;
    }
    for (int k = n - 2; k >= 0; k--) {
        nx = 0;
        x[nx++] = lo;
        for (int i = 0; i < ny; i++) x[nx++] = y[i];
        x[nx++] = hi;
        ny = 0;
        for (int i = 0; i + 1 < nx; i++) {
            double a = x[i], b = x[i + 1], fa = poly_at(d[k], n - k, a), fb = poly_at(d[k], n - k, b);
            if ((fa < 0.0) == (fb < 0.0)) continue;
            for (int it = 0; it < PLATE_POLY_BISECT; it++) {
                double m = 0.5 * (a + b), fm;
                if (!(m > a && m < b)) break;
                fm = poly_at(d[k], n - k, m);
                if ((fm < 0.0) == (fa < 0.0)) {
                    a = m;
                    fa = fm;
                } else {
                    b = m;
                }
            }
            y[ny++] = 0.5 * (a + b);
        }
    }
    for (int i = 0; i < ny; i++) r[i] = y[i];
    return ny;
}

/* The degree-6 polynomial P(s) = |adj(Kh + s I) ch|^2 - gam^2 det(Kh + s I)^2,
 * whose positive roots away from the poles of z (det = 0) are the roots of
 * h at mu = 1 / s (h(mu) = |y(s)| - gam, y = (Kh + s I)^-1 ch, and P =
 * det^2 (|y|^2 - gam^2): of h's sign). */
static void plate_poly(const double Kh[3][3], const double ch[3], double gam, double P[7])
{
    double m[3][3][2], C[3][3][3], v[3][3] = {{0}}, det[4] = {0, 0, 0, 0};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            m[i][j][0] = Kh[i][j];
            m[i][j][1] = i == j ? 1.0 : 0.0;
        }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int r1 = i == 0 ? 1 : 0, r2 = i == 2 ? 1 : 2, c1 = j == 0 ? 1 : 0, c2 = j == 2 ? 1 : 2;
            double sg = (i + j) % 2 ? -1.0 : 1.0;
            const double *a = m[r1][c1], *b = m[r2][c2], *c = m[r1][c2], *e = m[r2][c1];
            C[i][j][0] = sg * (a[0] * b[0] - c[0] * e[0]);
            C[i][j][1] = sg * (a[0] * b[1] + a[1] * b[0] - c[0] * e[1] - c[1] * e[0]);
            C[i][j][2] = sg * (a[1] * b[1] - c[1] * e[1]);
        }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int q = 0; q < 3; q++) v[i][q] += C[j][i][q] * ch[j];
    for (int j = 0; j < 3; j++)
        for (int q = 0; q < 3; q++) {
            det[q] += m[0][j][0] * C[0][j][q];
            det[q + 1] += m[0][j][1] * C[0][j][q];
        }
    for (int q = 0; q < 7; q++) P[q] = 0.0;
    for (int i = 0; i < 3; i++)
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) P[a + b] += v[i][a] * v[i][b];
    for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++) P[a + b] -= gam * gam * det[a] * det[b];
}

/* The first root mu > 0 of h (plate_h; h(0) = -gam < 0), the least mu (the
 * fastest slip, the largest dissipation cap |z| = cap gam / mu), z at it.
 * With y(s) = (Kh + s I)^-1 ch, s = 1 / mu: h(mu) = |y(s)| - gam and d|y|^2
 * / ds = -2 v^T (Ks + s I) v for v = (Kh + s I)^-1 y, Ks the symmetric part
 * of Kh. For s above s0 = -(Ks's least eigenvalue) Kh + s I has no pole and
 * h increases strictly in mu: on (0, 1 / s0) h has at most one root, the
 * least of all. Where s0 <= 0 (Ks positive semidefinite, as for every
 * symmetric K of stop_friction.h's modes) h increases on all mu > 0 and
 * its one root lies at or above gam (|z| <= |ch| = 1). The root is
 * bracketed by doubling from gam; where z has a pole at the trial point (I
 * + mu Kh singular: only without symmetry) the point moves halfway back to
 * the last one below 0 (|z| grows without bound at a pole, so h > 0 next
 * to it: a root lies before it). That root is the least where s0 <= 0 or
 * it lies below 1 / s0. Else, where h(1 / s0) > 0, the least root is
 * bracketed by (0, 1 / s0). Else (s0 > 0, no root below 1 / s0) the roots
 * lie at s in (0, s0), where h need not be monotone and may be several
 * (also below gam, where the doubling does not look): every one is a sign
 * change of plate_poly on (0, s0) (poly_roots), and the one of the largest
 * s, where the doubling went past it (its mu below the doubling's by the
 * factor PLATE_ROOT_SEP), is bracketed around it (1e-9 .. 1e-2 of s either
 * side, where h changes sign) and taken instead. Each bracket is refined by
 * plate_refine. Returns 0 when no root is found (none by the doubling
 * within PLATE_BRACKET_MAX trial points nor from the polynomial: no slip)
 * or the steps run out. */
static int plate_root(const double Kh[3][3], const double ch[3], double gam, double z[3])
{
    double lo = 0.0, hlo = -gam, hi = gam, hhi = 0.0, mu = 0.0, s0 = -sym_min_eig(Kh), P[7], sr[6], zt[3], ht;
    int ok = 0, nr;
    for (int n = 0; n < PLATE_BRACKET_MAX; n++) {
        if (!plate_h(Kh, ch, hi, gam, &hhi, z)) {
            hi = lo + 0.5 * (hi - lo);
            continue;
        }
        if (hhi > 0.0) {
            ok = plate_refine(Kh, ch, gam, lo, hlo, hi, hhi, z, &mu);
            break;
        }
        lo = hi;
        hlo = hhi;
        hi *= 2.0;
    }
    /* proven the least: h increases on all mu > 0, or the root lies where it does */
    if (!(s0 > 0.0) || (ok && mu * s0 < 1.0)) return ok;
    /* a root below 1 / s0, which the doubling went past: the least */
    if (plate_h(Kh, ch, 1.0 / s0, gam, &ht, zt) && ht > 0.0) {
        double mr;
        if (!plate_refine(Kh, ch, gam, 0.0, -gam, 1.0 / s0, ht, zt, &mr)) return ok;
        memcpy(z, zt, sizeof zt);
        return 1;
    }
    /* every root at s = 1 / mu in (0, s0): the largest s, if the doubling
     * went past it */
    plate_poly(Kh, ch, gam, P);
    if (!(P[6] != 0.0) || !ex_finite_n(P, 7)) return ok;
    nr = poly_roots(P, 6, 0.0, s0, sr);
    if (nr == 0 || (ok && !(1.0 / sr[nr - 1] < mu * (1.0 - PLATE_ROOT_SEP)))) return ok;
    for (double d = 1e-9; d <= 1e-2; d *= 16.0) {
        double zl[3], zh[3], ml = 1.0 / (sr[nr - 1] * (1.0 + d)), mh = 1.0 / (sr[nr - 1] * (1.0 - d)), hl, hh, mr;
        if (!plate_h(Kh, ch, ml, gam, &hl, zl) || !plate_h(Kh, ch, mh, gam, &hh, zh)) continue;
        if (!(hl < 0.0 && hh > 0.0)) continue;
        if (plate_refine(Kh, ch, gam, ml, hl, mh, hh, zt, &mr)) {
            memcpy(z, zt, sizeof zt);
            return 1;
        }
        break;
    }
    return ok;
}

/* The plate's wrench w of a mode whose patch slip is u = b + W w
 * (stop_friction.h, sf_plate): w = -cap E z / |z|, z = E u the root of the
 * scalar equation, scaled by K's largest entry kap and |E b| (mu = kap lam,
 * gam = kap cap / |E b|). Returns 0 when there is none (no slip). */
static int plate_wrench(const sf_plate *pl, const double b[3], const double W[3][3], double w[3])
{
    double c[3], K[3][3], Kh[3][3], ch[3], z[3], kap = 0.0, nc, nz;
    if (!(pl->cap > 0.0)) {
        w[0] = w[1] = w[2] = 0.0;
        return 1;
    }
    for (int i = 0; i < 3; i++) {
        c[i] = pl->e[i] * b[i];
        for (int j = 0; j < 3; j++) {
            K[i][j] = pl->e[i] * W[i][j] * pl->e[j];
            kap = fmax(kap, fabs(K[i][j]));
        }
    }
    nc = sqrt(ex_dot3(c, c));
    if (!(nc > 0.0) || !isfinite(kap)) return 0;
    if (kap == 0.0) {
        memcpy(z, c, sizeof z);
    } else {
        for (int i = 0; i < 3; i++) {
            ch[i] = c[i] / nc;
            for (int j = 0; j < 3; j++) Kh[i][j] = K[i][j] / kap;
        }
        if (!plate_root((const double (*)[3])Kh, ch, kap * pl->cap / nc, z)) return 0;
    }
    nz = sqrt(ex_dot3(z, z));
    if (!(nz > 0.0)) return 0;
    for (int i = 0; i < 3; i++) w[i] = -pl->cap * pl->e[i] * z[i] / nz;
    return ex_finite_n(w, 3);
}

/* The plate alone holds the object (qdd = 0, no row carrying force): w = -A^-1
 * M a, inside the ellipsoid, |E^-1 w| <= cap (1 + FRICTION_BAND). Returns 1
 * with w written if it does. */
static int plate_holds(const sf_plate *pl, const double minv[3], const double a[3], double w[3])
{
    double A[3][3], b[3], g = 0.0;
    for (int c = 0; c < 3; c++) {
        for (int j = 0; j < 3; j++) A[c][j] = pl->A[c][j];
        b[c] = -a[c] / minv[c];
    }
    if (!ldp_solve_small(3, A, b, w)) return 0;
    for (int j = 0; j < 3; j++) g += (w[j] / pl->e[j]) * (w[j] / pl->e[j]);
    return sqrt(g) <= pl->cap * (1.0 + FRICTION_BAND);
}

/* a + M^-1 A w: the acceleration without the stops with the plate's wrench w. */
static void plate_acc(const sf_plate *pl, const double minv[3], const double a[3], const double w[3], double ae[3])
{
    for (int c = 0; c < 3; c++) ae[c] = a[c] + minv[c] * (pl->A[c][0] * w[0] + pl->A[c][1] * w[1] + pl->A[c][2] * w[2]);
}

/* A mode whose constraints fix qdd by themselves (a lock, stop_friction.h): qdd
 * from sf_lock_solve (its constraints dependent but consistent to tol_a,
 * else no lock). The stop forces are then any
 * combination with coefficients c >= 0 of the mode's generators D_g (a
 * sticking stop's row: G_i + mu T and G_i - mu T, a sliding one's: G_i -
 * mu sigma T, a frictionless one's: G_i) that gives M (qdd - a); in the
 * scaled coordinates x_c sqrt(minv_c / minv_0) (forces, and torques over
 * the radius of gyration) such a combination exists iff the required R
 * lies in the cone spanned by the D_g: the margin is the least signed
 * distance of R to the cone's facets (planes through pairs of generators
 * with every generator on one side), plus the band FRICTION_BAND |R|. A cone that
 * is all of R^3 has no facet: any force is available (margin |R| +
 * band). Generators of rank below 3 are no lock (returns 0). The split
 * written into r is the combination nearest R (ldp_min_combination). */
static int solve_lock(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3],
                      const double a_in[3], const sf_plate *pl, unsigned mask, const int *m, const int *roll,
                      const double (*C)[3], const double *c0, int k, double tol_a, double tol_f, sf_result *r)
{
    double qdd[3], R[3], Rs[3], D[GMAX][3], Ds[GMAX][3], coef[GMAX], mR[3], mc0[KMAX], margin = INFINITY, nR, a[3],
        w[3] = {0, 0, 0};
    int ng = 0, own[GMAX], rank3 = 0, given = 1;
    double sgn[GMAX];
    for (int l = 0; l < k; l++) mc0[l] = -c0[l];
    if (!sf_lock_solve(k, C, mc0, minv, tol_a, qdd)) return 0;
    r->tried++;
    memcpy(a, a_in, sizeof a);
    if (pl && pl->cap > 0.0) {
        /* the plate's wrench of the lock's slip u = A^T qdd */
        double eu[3], n;
        for (int j = 0; j < 3; j++) eu[j] = pl->e[j] * (pl->A[0][j] * qdd[0] + pl->A[1][j] * qdd[1] + pl->A[2][j] * qdd[2]);
        n = sqrt(ex_dot3(eu, eu));
        if (!(n > 0.0)) return 0;
        for (int j = 0; j < 3; j++) w[j] = -pl->cap * pl->e[j] * eu[j] / n;
        plate_acc(pl, minv, a_in, w, a);
    }
    /* generators, scaled (above) */
    for (int i = 0; i < nr; i++) {
        const sf_stop *s = &st[rows[i].stop];
        int mk = m[rows[i].stop];
        if (!(mask >> i & 1u)) continue;
        if (s->mu > 0.0 && roll[rows[i].stop]) given = 0;
        if (s->mu > 0.0 && mk == SF_STICK) {
            for (int c = 0; c < 3; c++) {
                D[ng][c] = rows[i].G[c] + s->mu * s->T[c];
                D[ng + 1][c] = rows[i].G[c] - s->mu * s->T[c];
            }
            own[ng] = own[ng + 1] = i;
            sgn[ng] = 1.0;
            sgn[ng + 1] = -1.0;
            ng += 2;
        } else if (s->mu > 0.0 && (mk == SF_SLIDE_P || mk == SF_SLIDE_M)) {
            double sg = mk == SF_SLIDE_P ? 1.0 : -1.0;
            for (int c = 0; c < 3; c++) D[ng][c] = rows[i].G[c] - s->mu * sg * s->T[c];
            own[ng] = i;
            sgn[ng++] = -sg;
        } else {
            memcpy(D[ng], rows[i].G, sizeof D[ng]);
            own[ng] = i;
            sgn[ng++] = 0.0;
        }
    }
    for (int c = 0; c < 3; c++) {
        double s0 = sqrt(minv[c] / minv[0]);
        R[c] = (qdd[c] - a[c]) / minv[c];
        Rs[c] = R[c] * s0;
        mR[c] = -Rs[c];
        for (int g = 0; g < ng; g++) Ds[g][c] = D[g][c] * s0;
    }
    nR = sqrt(ex_dot3(Rs, Rs));
    /* facets of the generators' cone */
    for (int g = 0; g < ng; g++)
        for (int h = g + 1; h < ng; h++) {
            double n[3], nn, lg = sqrt(ex_dot3(Ds[g], Ds[g])), lh = sqrt(ex_dot3(Ds[h], Ds[h]));
            int pos = 1, neg = 1;
            ex_cross3(n, Ds[g], Ds[h]);
            nn = sqrt(ex_dot3(n, n));
            if (!(nn > SF_LOCK_RANK * lg * lh)) continue;
            for (int c = 0; c < 3; c++) n[c] /= nn;
            for (int j = 0; j < ng; j++) {
                double d = ex_dot3(n, Ds[j]), lj = sqrt(ex_dot3(Ds[j], Ds[j]));
                if (d > SF_LOCK_RANK * lj) neg = 0;
                if (d < -SF_LOCK_RANK * lj) pos = 0;
                if (fabs(d) > SF_LOCK_RANK * lj) rank3 = 1;
            }
            if (pos && !neg) margin = fmin(margin, ex_dot3(n, Rs));
            if (neg && !pos) margin = fmin(margin, -ex_dot3(n, Rs));
        }
    if (!rank3) return 0;
    margin = (isfinite(margin) ? margin : nR) + FRICTION_BAND * nR;
    if (!given && !(margin >= 0.0)) return 0;
    ldp_min_combination(ng, mR, (const double (*)[3])Ds, coef, NULL);
    for (int c = 0; c < 3; c++) r->qdd[c] = qdd[c];
    for (int j = 0; j < ns; j++) {
        r->beta[j] = r->lsum[j] = 0.0;
        r->acct[j] = ex_dot3(st[j].T, r->qdd) + st[j].sdd0;
        r->fm[j] = st[j].fm;
    }
    for (int i = 0; i < nr; i++) {
        r->lam[i] = 0.0;
        r->acc[i] = ex_dot3(rows[i].G, r->qdd) + rows[i].gdd0;
        if (mask >> i & 1u) r->fm[rows[i].stop] = m[rows[i].stop];
    }
    for (int g = 0; g < ng; g++) {
        int i = own[g], j = rows[i].stop;
        r->lam[i] += coef[g];
        r->lsum[j] += coef[g];
        r->beta[j] += sgn[g] * st[j].mu * coef[g];
    }
    for (int i = 0; i < nr; i++)
        if (!(mask >> i & 1u) && !(r->acc[i] >= -tol_a)) return 0;
    for (int j = 0; j < ns; j++) {
        double sg;
        if (!(st[j].mu > 0.0) || !(m[j] == SF_SLIDE_P || m[j] == SF_SLIDE_M)) continue;
        sg = m[j] == SF_SLIDE_P ? 1.0 : -1.0;
        if (roll[j] && !(sg * r->acct[j] >= -tol_a)) return 0;
    }
    (void)tol_f;
    memcpy(r->w, w, sizeof w);
    r->lock = 1;
    r->margin = margin;
    r->mask = mask;
    return 1;
}

/* Solve one mode: rows in `mask` carry force, stop k has mode m[k] (a
 * stop without such rows is left as given). Returns 1 if its signs hold. */
static int solve_mode(int nr, const sf_row *rows, int ns, const sf_stop *st, const int *roll, const double minv[3],
                      const double a_in[3], const sf_plate *pl, unsigned mask, const int *m, double tol_a,
                      double tol_f, int locks, sf_result *r)
{
    double C[KMAX][3], D[KMAX][3], c0[KMAX], A[3][3], A0[3][3], b[3], x[3] = {0, 0, 0}, a[3];
    int kind[KMAX], idx[KMAX], k = 0, has[SF_MAX_STOPS] = {0}, kinematic;
    for (int i = 0; i < nr; i++)
        if (mask >> i & 1u) has[rows[i].stop] = 1;
    /* unknowns and constraints: each row carrying force (lam, its gap
     * acceleration 0), each sticking stop with such rows (beta, its slip
     * acceleration 0) */
    for (int i = 0; i < nr; i++) {
        const sf_stop *s = &st[rows[i].stop];
        int mk = m[rows[i].stop];
        if (!(mask >> i & 1u)) continue;
        for (int c = 0; c < 3; c++) {
            C[k][c] = rows[i].G[c];
            D[k][c] = rows[i].G[c];
        }
        if (s->mu > 0.0 && (mk == SF_SLIDE_P || mk == SF_SLIDE_M)) {
            double sg = mk == SF_SLIDE_P ? 1.0 : -1.0;
            for (int c = 0; c < 3; c++) D[k][c] -= s->mu * sg * s->T[c];
        }
        c0[k] = rows[i].gdd0;
        kind[k] = 0;
        idx[k++] = i;
    }
    for (int j = 0; j < ns; j++) {
        if (!has[j] || !(st[j].mu > 0.0) || m[j] != SF_STICK) continue;
        for (int c = 0; c < 3; c++) C[k][c] = D[k][c] = st[j].T[c];
        c0[k] = st[j].sdd0;
        kind[k] = 1;
        idx[k++] = j;
    }
    r->lock = 0;
    r->margin = 0.0;
    r->mask = 0u;
    memcpy(r->w, (const double[3]){0, 0, 0}, sizeof r->w);
    if (k > 3) return locks && solve_lock(nr, rows, ns, st, minv, a_in, pl, mask, m, roll, (const double (*)[3])C, c0,
                                          k, tol_a, tol_f, r);
    r->tried++;
    memcpy(a, a_in, sizeof a);
    for (int l = 0; l < k; l++) {
        for (int j = 0; j < k; j++) {
            A[l][j] = 0.0;
            for (int c = 0; c < 3; c++) A[l][j] += C[l][c] * minv[c] * D[j][c];
            A0[l][j] = A[l][j];
        }
        b[l] = -(ex_dot3(C[l], a) + c0[l]);
    }
    kinematic = k == 3;
    if (k && !ldp_solve_small(k, A, b, x))
        return locks && k == 3 &&
               solve_lock(nr, rows, ns, st, minv, a_in, pl, mask, m, roll, (const double (*)[3])C, c0, k, tol_a,
                          tol_f, r);
    if (locks == LOCKS_ONLY) return 0;
    if (pl && pl->cap > 0.0) {
        /* the plate as one more contact: x = x0 + X w, qdd = q0 + N w, the
         * patch slip u = A^T q0 + A^T N w (stop_friction.h, sf_plate) */
        double X[3][3] = {{0}}, q0[3], N[3][3], bu[3], Wu[3][3], w[3];
        for (int j = 0; j < 3; j++) {
            double Aj[3][3], bj[3], xj[3] = {0, 0, 0};
            for (int l = 0; l < k; l++) {
                for (int i = 0; i < k; i++) Aj[l][i] = A0[l][i];
                bj[l] = 0.0;
                for (int c = 0; c < 3; c++) bj[l] -= C[l][c] * minv[c] * pl->A[c][j];
            }
            if (k && !ldp_solve_small(k, Aj, bj, xj)) return 0;
            for (int l = 0; l < k; l++) X[l][j] = xj[l];
        }
        for (int c = 0; c < 3; c++) {
            q0[c] = a[c];
            for (int l = 0; l < k; l++) q0[c] += x[l] * minv[c] * D[l][c];
            for (int j = 0; j < 3; j++) {
                N[c][j] = minv[c] * pl->A[c][j];
                for (int l = 0; l < k; l++) N[c][j] += X[l][j] * minv[c] * D[l][c];
            }
        }
        for (int i = 0; i < 3; i++) {
            bu[i] = pl->A[0][i] * q0[0] + pl->A[1][i] * q0[1] + pl->A[2][i] * q0[2];
            for (int j = 0; j < 3; j++) Wu[i][j] = pl->A[0][i] * N[0][j] + pl->A[1][i] * N[1][j] + pl->A[2][i] * N[2][j];
        }
        if (!(k == 0 && plate_holds(pl, minv, a, w)) && !plate_wrench(pl, bu, (const double (*)[3])Wu, w)) return 0;
        for (int l = 0; l < k; l++) x[l] += X[l][0] * w[0] + X[l][1] * w[1] + X[l][2] * w[2];
        plate_acc(pl, minv, a_in, w, a);
        memcpy(r->w, w, sizeof w);
    }
    for (int c = 0; c < 3; c++) {
        r->qdd[c] = a[c];
        for (int j = 0; j < k; j++) r->qdd[c] += x[j] * minv[c] * D[j][c];
    }
    for (int j = 0; j < ns; j++) {
        r->beta[j] = r->lsum[j] = 0.0;
        r->acct[j] = ex_dot3(st[j].T, r->qdd) + st[j].sdd0;
        r->fm[j] = has[j] ? m[j] : st[j].fm;
    }
    for (int i = 0; i < nr; i++) {
        r->lam[i] = 0.0;
        r->acc[i] = ex_dot3(rows[i].G, r->qdd) + rows[i].gdd0;
    }
    for (int l = 0; l < k; l++) {
        if (kind[l] == 0) {
            r->lam[idx[l]] = x[l];
            r->lsum[rows[idx[l]].stop] += x[l];
        } else {
            r->beta[idx[l]] = x[l];
        }
    }
    for (int i = 0; i < nr; i++) {
        if (mask >> i & 1u) {
            if (!(r->lam[i] >= -tol_f)) return 0;
        } else if (!(r->acc[i] >= -tol_a)) {
            return 0;
        }
    }
    for (int j = 0; j < ns; j++) {
        if (!has[j] || !(st[j].mu > 0.0)) continue;
        if (m[j] == SF_STICK && roll[j]) {
            if (!(fabs(r->beta[j]) <= st[j].mu * r->lsum[j] * (1.0 + FRICTION_BAND))) return 0;
        } else if (m[j] == SF_SLIDE_P || m[j] == SF_SLIDE_M) {
            double sg = m[j] == SF_SLIDE_P ? 1.0 : -1.0;
            r->beta[j] = -st[j].mu * sg * r->lsum[j];
            if (roll[j] && !(sg * r->acct[j] >= -tol_a)) return 0;
            /* three constraints (rows carrying force, sticking stops), or
             * the rows held at gap acceleration 0 (within tol_a) with or
             * without force, fix qdd whatever the friction: the slip
             * acceleration is the kinematics', and one within tol_a of 0
             * is no slide either way (the stop is held: a lock, with its
             * stick mode) */
            if (roll[j] && !(sg * r->acct[j] > tol_a) && (kinematic || rows_fix_qdd(nr, rows, minv, tol_a, r)))
                return 0;
        }
    }
    return 1;
}

/* sf_solve on at most SF_ENUM_ROWS rows: every row's modes enumerated. */
static int solve_enum(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3], const double a[3],
                      const sf_plate *pl, double tol_a, double tol_f, sf_result *res)
{
    int opt[SF_MAX_STOPS][3], nopt[SF_MAX_STOPS], roll[SF_MAX_STOPS], has[SF_MAX_STOPS] = {0}, pick[SF_MAX_STOPS],
        m[SF_MAX_STOPS], anyroll = 0;
    /* res zeroed where it is read (rows 0 .. nr - 1, stops 0 .. ns - 1) */
    memset(res->qdd, 0, sizeof res->qdd);
    memset(res->w, 0, sizeof res->w);
    res->tried = res->lock = 0;
    res->margin = 0.0;
    res->mask = 0u;
    if (nr < 0 || nr > SF_ENUM_ROWS || ns < 0 || ns > SF_MAX_STOPS) return 0;
    for (int i = 0; i < nr; i++) res->lam[i] = res->acc[i] = 0.0;
    for (int j = 0; j < ns; j++) {
        res->beta[j] = res->lsum[j] = res->acct[j] = 0.0;
        res->fm[j] = 0;
    }
    for (int i = 0; i < nr; i++) {
        if (rows[i].stop < 0 || rows[i].stop >= ns) return 0;
        has[rows[i].stop] = 1;
    }
    for (int j = 0; j < ns; j++) {
        roll[j] = 0;
        if (!(st[j].mu > 0.0) || st[j].fm == SF_NONE || !has[j]) {
            opt[j][0] = st[j].fm;
            nopt[j] = 1;
        } else if (st[j].fm == SF_ROLL) {
            opt[j][0] = SF_STICK;
            opt[j][1] = SF_SLIDE_P;
            opt[j][2] = SF_SLIDE_M;
            nopt[j] = 3;
            roll[j] = 1;
        } else {
            opt[j][0] = st[j].fm;
            nopt[j] = 1;
        }
    }
    /* the rows carrying force: every row first, then fewer (binary count
     * down); per row set, the stops' friction modes (mixed radix). With a
     * rolling stop, locks only after every other mode (two passes, see
     * stop_friction.h); with every mode given, in the one order */
    for (int j = 0; j < ns; j++) anyroll |= roll[j];
    for (int pass = anyroll ? 0 : 1; pass < 2; pass++)
    for (unsigned mask = (1u << nr) - 1u;; mask--) {
        int on[SF_MAX_STOPS] = {0};
        for (int i = 0; i < nr; i++)
            if (mask >> i & 1u) on[rows[i].stop] = 1;
        for (int j = 0; j < ns; j++) pick[j] = 0;
        for (;;) {
            int dup = 0;
            for (int j = 0; j < ns; j++) {
                m[j] = opt[j][pick[j]];
                dup |= !on[j] && pick[j] > 0;  /* a stop without force: its mode does not matter */
            }
            if (!dup) {
                if (res->tried >= MAX_TRIED) return 0;
                if (solve_mode(nr, rows, ns, st, roll, minv, a, pl, mask, m, tol_a, tol_f,
                               !anyroll ? LOCKS_TOO : pass ? LOCKS_ONLY : LOCKS_NONE, res))
                    return 1;
            }
            {
                int j = 0;
                while (j < ns && ++pick[j] >= nopt[j]) pick[j++] = 0;
                if (j == ns) break;
            }
        }
        if (mask == 0u) break;
    }
    return 0;
}

/* Squared distance of two rows' G. */
static double gdist2(const sf_row *p, const sf_row *q)
{
    double s = 0.0;
    for (int c = 0; c < 3; c++) s += (p->G[c] - q->G[c]) * (p->G[c] - q->G[c]);
    return s;
}

/* The rows enumerated when there are more than SF_ENUM_ROWS (stop_friction.h) into
 * en, in increasing index; returns their count. A stop's rows are points
 * on one line with one normal n, so G_i = (n, arm_i) with the arm affine
 * in the point's place along the line: every G_i is a convex combination of
 * the two extreme rows' (the pair farthest apart in G), and so are the gap
 * accelerations G_i qdd + gdd0_i (gdd0 is affine in the point too). A force
 * sum lam_i G_i, lam >= 0, is therefore a force on the extremes alone, and
 * the extremes' gap accelerations >= 0 hold the others': a stop with more
 * than two rows enters with its two extremes. */
static int enum_rows(int nr, const sf_row *rows, int ns, int *en)
{
    int ne = 0, cnt[SF_MAX_STOPS], first[SF_MAX_STOPS], ea[SF_MAX_STOPS], eb[SF_MAX_STOPS];
    double da[SF_MAX_STOPS], db[SF_MAX_STOPS];
    for (int j = 0; j < ns; j++) {
        cnt[j] = 0;
        first[j] = ea[j] = eb[j] = -1;
        da[j] = db[j] = -1.0;
    }
    for (int i = 0; i < nr; i++) {
        int j = rows[i].stop;
        if (!cnt[j]++) first[j] = i;
    }
    /* ea: the row farthest from the stop's first; eb: the row farthest from ea */
    for (int i = 0; i < nr; i++) {
        int j = rows[i].stop;
        double d = gdist2(&rows[i], &rows[first[j]]);
        if (d > da[j]) {
            da[j] = d;
            ea[j] = i;
        }
    }
    for (int i = 0; i < nr; i++) {
        int j = rows[i].stop;
        double d = gdist2(&rows[i], &rows[ea[j]]);
        if (d > db[j]) {
            db[j] = d;
            eb[j] = i;
        }
    }
    for (int i = 0; i < nr; i++) {
        int j = rows[i].stop;
        if (cnt[j] <= 2 || i == ea[j] || i == eb[j]) en[ne++] = i;
    }
    return ne;
}

/* sf_solve and sf_solve_plate (pl NULL: no plate). */
static int solve_all(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3], const double a[3],
                     const sf_plate *pl, double tol_a, double tol_f, sf_result *res)
{
    sf_row rr[SF_ENUM_ROWS];
    sf_result sub;
    int en[SF_MAX_ROWS], ne, ok;
    if (nr <= SF_ENUM_ROWS) return solve_enum(nr, rows, ns, st, minv, a, pl, tol_a, tol_f, res);
    memset(res->qdd, 0, sizeof res->qdd);
    memset(res->w, 0, sizeof res->w);
    res->tried = res->lock = 0;
    res->margin = 0.0;
    res->mask = 0u;
    if (nr > SF_MAX_ROWS || ns < 0 || ns > SF_MAX_STOPS) return 0;
    for (int i = 0; i < nr; i++)
        if (rows[i].stop < 0 || rows[i].stop >= ns) return 0;
    /* the reduced problem (enum_rows), then every row's force (0 off the
     * extremes) and gap acceleration, each >= -tol_a */
    ne = enum_rows(nr, rows, ns, en);
    if (ne > SF_ENUM_ROWS) return 0;
    for (int b = 0; b < ne; b++) rr[b] = rows[en[b]];
    ok = solve_enum(ne, rr, ns, st, minv, a, pl, tol_a, tol_f, &sub);
    memcpy(res->qdd, sub.qdd, sizeof res->qdd);
    memcpy(res->w, sub.w, sizeof res->w);
    res->tried = sub.tried;
    res->lock = sub.lock;
    res->margin = sub.margin;
    for (int j = 0; j < ns; j++) {
        res->beta[j] = sub.beta[j];
        res->lsum[j] = sub.lsum[j];
        res->acct[j] = sub.acct[j];
        res->fm[j] = sub.fm[j];
    }
    for (int i = 0; i < nr; i++) {
        res->lam[i] = 0.0;
        res->acc[i] = ex_dot3(rows[i].G, res->qdd) + rows[i].gdd0;
    }
    for (int b = 0; b < ne; b++) {
        res->lam[en[b]] = sub.lam[b];
        res->acc[en[b]] = sub.acc[b];
        if (sub.mask >> b & 1u) {
            if (en[b] >= 32) return 0;  /* a lock's rows must fit the mask's bits */
            res->mask |= 1u << en[b];
        }
    }
    if (!ok) return 0;
    for (int i = 0; i < nr; i++)
        if (!(res->acc[i] >= -tol_a)) return 0;
    return 1;
}

int sf_solve(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3], const double a[3],
             double tol_a, double tol_f, sf_result *res)
{
    return solve_all(nr, rows, ns, st, minv, a, NULL, tol_a, tol_f, res);
}

int sf_solve_plate(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3], const double a[3],
                   const sf_plate *pl, double tol_a, double tol_f, sf_result *res)
{
    return solve_all(nr, rows, ns, st, minv, a, pl, tol_a, tol_f, res);
}
