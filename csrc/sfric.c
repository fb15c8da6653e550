/* sfric.c -- the acceleration-level contact problem of a planar object
 * against frictional stops (sfric.h): mode enumeration, each mode solved
 * exactly. */
#include "sfric.h"
#include "ldp.h"
#include "util.h"

#include <math.h>
#include <string.h>


/* Solve one mode: rows i with on[i] carry force, stop k has mode m[k] (a
 * stop without such rows is left as given). Returns 1 if its signs hold
 * (every row's: the rows left out of the enumeration too). */
static int solve_mode(int nr, const sf_row *rows, int ns, const sf_stop *st, const int *roll, const double minv[3],
                      const double a[3], const unsigned char *on, const int *m, double tol_a, double tol_f,
                      sf_result *r)
{
    double C[3][3], D[3][3], c0[3], A[3][3], b[3], x[3] = {0, 0, 0};
    int kind[3], idx[3], k = 0, nh = 0, hs[3];
    /* unknowns and constraints: each row carrying force (lam, its gap
     * acceleration 0), each sticking stop with such rows (beta, its slip
     * acceleration 0); at most 3 rows carry force, so at most 3 stops have
     * force (hs) */
    for (int i = 0; i < nr; i++) {
        const sf_stop *s = &st[rows[i].stop];
        int mk = m[rows[i].stop], seen = 0;
        if (!on[i]) continue;
        if (k == 3) return 0;
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
        for (int h = 0; h < nh; h++) seen |= hs[h] == rows[i].stop;
        if (!seen) hs[nh++] = rows[i].stop;
    }
    /* the sticking stops in increasing index */
    for (int p = 0; p < nh; p++)
        for (int q = p + 1; q < nh; q++)
            if (hs[q] < hs[p]) {
                int t = hs[p];
                hs[p] = hs[q];
                hs[q] = t;
            }
    for (int h = 0; h < nh; h++) {
        int j = hs[h];
        if (!(st[j].mu > 0.0) || m[j] != SF_STICK) continue;
        if (k == 3) return 0;
        for (int c = 0; c < 3; c++) C[k][c] = D[k][c] = st[j].T[c];
        c0[k] = st[j].sdd0;
        kind[k] = 1;
        idx[k++] = j;
    }
    r->tried++;
    for (int l = 0; l < k; l++) {
        for (int j = 0; j < k; j++) {
            A[l][j] = 0.0;
            for (int c = 0; c < 3; c++) A[l][j] += C[l][c] * minv[c] * D[j][c];
        }
        b[l] = -(ex_dot3(C[l], a) + c0[l]);
    }
    if (k && !ldp_solve_small(k, A, b, x)) return 0;
    for (int c = 0; c < 3; c++) {
        r->qdd[c] = a[c];
        for (int j = 0; j < k; j++) r->qdd[c] += x[j] * minv[c] * D[j][c];
    }
    for (int j = 0; j < ns; j++) {
        int hj = 0;
        for (int h = 0; h < nh; h++) hj |= hs[h] == j;
        r->beta[j] = r->lsum[j] = 0.0;
        r->acct[j] = ex_dot3(st[j].T, r->qdd) + st[j].sdd0;
        r->fm[j] = hj ? m[j] : st[j].fm;
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
        if (on[i]) {
            if (!(r->lam[i] >= -tol_f)) return 0;
        } else if (!(r->acc[i] >= -tol_a)) {
            return 0;
        }
    }
    for (int h = 0; h < nh; h++) {
        int j = hs[h];
        if (!(st[j].mu > 0.0)) continue;
        if (m[j] == SF_STICK && roll[j]) {
            if (!(fabs(r->beta[j]) <= st[j].mu * r->lsum[j] * (1.0 + SF_BAND))) return 0;
        } else if (m[j] == SF_SLIDE_P || m[j] == SF_SLIDE_M) {
            double sg = m[j] == SF_SLIDE_P ? 1.0 : -1.0;
            r->beta[j] = -st[j].mu * sg * r->lsum[j];
            if (roll[j] && !(sg * r->acct[j] >= -tol_a)) return 0;
        }
    }
    return 1;
}

/* Squared distance of two rows' G. */
static double gdist2(const sf_row *p, const sf_row *q)
{
    double s = 0.0;
    for (int c = 0; c < 3; c++) s += (p->G[c] - q->G[c]) * (p->G[c] - q->G[c]);
    return s;
}

/* The rows whose modes are enumerated into en (returns their count, in
 * increasing index). Up to SF_ENUM_ROWS rows: every row. Beyond, a stop's
 * rows are points on one line with one normal n, so G_i = (n, arm_i) with
 * the arm affine in the point's place along the line: every G_i is a convex
 * combination of the two extreme rows' (the pair farthest apart in G), and
 * so are the gap accelerations G_i qdd + gdd0_i (gdd0 is affine in the
 * point too). A force sum lam_i G_i, lam >= 0, is therefore a force
 * on the extremes alone, and the extremes' gap accelerations >= 0 hold the
 * others': a stop with more than two rows enters the enumeration with its
 * two extremes, the others carry no force and keep their sign checks. */
static int enum_rows(int nr, const sf_row *rows, int ns, int *en)
{
    int ne = 0, cnt[SF_MAX_STOPS], first[SF_MAX_STOPS], ea[SF_MAX_STOPS], eb[SF_MAX_STOPS];
    double da[SF_MAX_STOPS], db[SF_MAX_STOPS];
    if (nr <= SF_ENUM_ROWS) {
        for (int i = 0; i < nr; i++) en[ne++] = i;
        return ne;
    }
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

/* The friction modes of the stops with force under the row set `on` (the
 * stops' options opt, nopt; mixed radix, the lowest stop fastest), each
 * solved (solve_mode). Returns 1 at the first consistent one, 0 when none
 * is, -1 when SF_MAX_TRIED modes have been solved. */
static int try_modes(int nr, const sf_row *rows, int ns, const sf_stop *st, const int *roll, const int (*opt)[3],
                     const int *nopt, const double minv[3], const double a[3], const unsigned char *on, int *m,
                     double tol_a, double tol_f, sf_result *res)
{
    int os[3], pick[3] = {0, 0, 0}, no = 0;
    for (int i = 0; i < nr; i++) {
        int seen = 0;
        if (!on[i]) continue;
        for (int h = 0; h < no; h++) seen |= os[h] == rows[i].stop;
        if (!seen) {
            if (no == 3) return 0;  /* more than 3 rows carry force: not a mode (solve_mode) */
            os[no++] = rows[i].stop;
        }
    }
    for (int p = 0; p < no; p++)
        for (int q = p + 1; q < no; q++)
            if (os[q] < os[p]) {
                int t = os[p];
                os[p] = os[q];
                os[q] = t;
            }
    for (int j = 0; j < ns; j++) m[j] = opt[j][0];
    for (;;) {
        int h = 0;
        for (int l = 0; l < no; l++) m[os[l]] = opt[os[l]][pick[l]];
        if (res->tried >= SF_MAX_TRIED) return -1;
        if (solve_mode(nr, rows, ns, st, roll, minv, a, on, m, tol_a, tol_f, res)) return 1;
        while (h < no && ++pick[h] >= nopt[os[h]]) pick[h++] = 0;
        if (h == no) return 0;
    }
}

int sf_solve(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3], const double a[3],
             double tol_a, double tol_f, sf_result *res)
{
    int opt[SF_MAX_STOPS][3], nopt[SF_MAX_STOPS], roll[SF_MAX_STOPS], m[SF_MAX_STOPS];
    unsigned char on[SF_MAX_ROWS];
    int has[SF_MAX_STOPS], en[SF_MAX_ROWS], ne;
    res->tried = 0;
    for (int c = 0; c < 3; c++) res->qdd[c] = 0.0;
    if (nr < 0 || nr > SF_MAX_ROWS || ns < 0 || ns > SF_MAX_STOPS) return 0;
    for (int i = 0; i < nr; i++) res->lam[i] = res->acc[i] = 0.0;
    for (int j = 0; j < ns; j++) {
        res->beta[j] = res->lsum[j] = res->acct[j] = 0.0;
        res->fm[j] = 0;
        has[j] = 0;
    }
    for (int i = 0; i < nr; i++) {
        if (rows[i].stop < 0 || rows[i].stop >= ns) return 0;
        has[rows[i].stop] = 1;
        on[i] = 0;
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
    ne = enum_rows(nr, rows, ns, en);
    /* the row sets carrying force (at most 3 rows: in the plane more are
     * dependent, solve_mode) in decreasing binary order of their bits over
     * en (bit b: row en[b]): the set of the highest bit h1 with each set
     * below it, then the sets below h1; the empty set last. Per set, the
     * stops' friction modes (try_modes). */
    for (int h1 = ne - 1; h1 >= -1; h1--)
        for (int h2 = h1 >= 0 ? h1 - 1 : -1; h2 >= -1; h2--)
            for (int h3 = h2 >= 0 ? h2 - 1 : -1; h3 >= -1; h3--) {
                int got;
                if (h1 >= 0) on[en[h1]] = 1;
                if (h2 >= 0) on[en[h2]] = 1;
                if (h3 >= 0) on[en[h3]] = 1;
                got = try_modes(nr, rows, ns, st, roll, (const int (*)[3])opt, nopt, minv, a, on, m, tol_a, tol_f,
                                res);
                if (h1 >= 0) on[en[h1]] = 0;
                if (h2 >= 0) on[en[h2]] = 0;
                if (h3 >= 0) on[en[h3]] = 0;
                if (got) return got > 0;
            }
    return 0;
}
