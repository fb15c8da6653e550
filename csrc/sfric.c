/* sfric.c -- the acceleration-level contact problem of a planar object
 * against frictional stops (sfric.h): mode enumeration, each mode solved
 * exactly. */
#include "sfric.h"
#include "ldp.h"
#include "util.h"

#include <math.h>
#include <string.h>

#define MAX_TRIED 4096  /* modes solved at most */

/* Solve one mode: rows in `mask` carry force, stop k has mode m[k] (a
 * stop without such rows is left as given). Returns 1 if its signs hold. */
static int solve_mode(int nr, const sf_row *rows, int ns, const sf_stop *st, const int *roll, const double minv[3],
                      const double a[3], unsigned mask, const int *m, double tol_a, double tol_f, sf_result *r)
{
    double C[3][3], D[3][3], c0[3], A[3][3], b[3], x[3] = {0, 0, 0};
    int kind[3], idx[3], k = 0, has[SF_MAX_STOPS] = {0};
    for (int i = 0; i < nr; i++)
        if (mask >> i & 1u) has[rows[i].stop] = 1;
    /* unknowns and constraints: each row carrying force (lam, its gap
     * acceleration 0), each sticking stop with such rows (beta, its slip
     * acceleration 0) */
    for (int i = 0; i < nr; i++) {
        const sf_stop *s = &st[rows[i].stop];
        int mk = m[rows[i].stop];
        if (!(mask >> i & 1u)) continue;
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
    }
    for (int j = 0; j < ns; j++) {
        if (!has[j] || !(st[j].mu > 0.0) || m[j] != SF_STICK) continue;
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
            if (!(fabs(r->beta[j]) <= st[j].mu * r->lsum[j] * (1.0 + SF_BAND))) return 0;
        } else if (m[j] == SF_SLIDE_P || m[j] == SF_SLIDE_M) {
            double sg = m[j] == SF_SLIDE_P ? 1.0 : -1.0;
            r->beta[j] = -st[j].mu * sg * r->lsum[j];
            if (roll[j] && !(sg * r->acct[j] >= -tol_a)) return 0;
        }
    }
    return 1;
}

int sf_solve(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3], const double a[3],
             double tol_a, double tol_f, sf_result *res)
{
    int opt[SF_MAX_STOPS][3], nopt[SF_MAX_STOPS], roll[SF_MAX_STOPS], has[SF_MAX_STOPS] = {0}, pick[SF_MAX_STOPS],
        m[SF_MAX_STOPS];
    memset(res, 0, sizeof *res);
    if (nr < 0 || nr > SF_MAX_ROWS || ns < 0 || ns > SF_MAX_STOPS) return 0;
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
     * down); per row set, the stops' friction modes (mixed radix) */
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
                if (solve_mode(nr, rows, ns, st, roll, minv, a, mask, m, tol_a, tol_f, res)) return 1;
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
