/* cone.c -- twist cones of a pushed planar object, their volumes inside a
 * box, and the assistive-tool optimisation (paper Section 3, Eqs. 10-13).
 *
 * The feasible twist set of a rigid planar object touching fixed surfaces
 * without friction is the polyhedral cone {x : A x >= 0}; the paper measures
 * it by its volume inside a cuboid of twists (Eq. 13) and picks the tool
 * angle minimising the volume summed over attack angles (Eq. 12).
 */
#include "exdex.h"
#include "util.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_min.h>
#include <gsl/gsl_multimin.h>
#include <gsl/gsl_qrng.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_vector.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------ rows */

void exdex_contact_row(double row[3], const double r[2], const double n[2])
{
    // velocity of the material point r: v + w x r = (Vx - wz r_y, Vy + wz r_x);
    // n . that = n_x Vx + n_y Vy + (r_x n_y - r_y n_x) wz
    row[0] = n[0];
    row[1] = n[1];
    row[2] = r[0] * n[1] - r[1] * n[0];
}

int exdex_contact_rows_friction(double rows[6], const double r[2], const double n[2],
                                double mu)
{
    if (!(mu >= 0.0) || !isfinite(mu) || !isfinite(r[0]) || !isfinite(r[1]) ||
        !isfinite(n[0]) || !isfinite(n[1]))
        return EXDEX_EINVAL;
    // Friction cone edges (paper Fig. 10), normalised so a large mu keeps
    // the rows of order one.
    double t[2] = {-n[1], n[0]};
    double c = 1.0 / sqrt(1.0 + mu * mu);
    for (int k = 0; k < 2; k++) {
        double sg = k == 0 ? 1.0 : -1.0;
        double e[2] = {c * (n[0] + sg * mu * t[0]), c * (n[1] + sg * mu * t[1])};
        exdex_contact_row(rows + 3 * k, r, e);
    }
    // r x e overflows for |r| near DBL_MAX
    return ex_finite_n(rows, 6) ? EXDEX_OK : EXDEX_ENONFINITE;
}

void exdex_cone_rows_paper(double rows[6], double phi, double theta)
{
    // Eq. 10: Vx sin(phi) + Vy cos(phi) - 1/2 (1 - sin(phi)) wz >= 0
    rows[0] = sin(phi);
    rows[1] = cos(phi);
    rows[2] = -0.5 * (1.0 - sin(phi));
    // Eq. 11: -Vx sin(theta - phi) + Vy cos(theta - phi) - 1/2 (1 - sin(theta - phi)) wz >= 0
    double p = theta - phi;
    rows[3] = -sin(p);
    rows[4] = cos(p);
    rows[5] = -0.5 * (1.0 - sin(p));
}

/* --------------------------------------------------------- exact volume */

static int box_ok(const double lo[3], const double hi[3])
{
    double vol = 1.0;
    for (int j = 0; j < 3; j++) {
        if (!isfinite(lo[j]) || !isfinite(hi[j]) || !(hi[j] > lo[j]) || !isfinite(hi[j] - lo[j])) return 0;
        vol *= hi[j] - lo[j];
    }
    return isfinite(vol) && vol > 0.0; /* the box volume must be representable (fuzzing) */
}

static int rows_ok(const double *rows, int m)
{
    if (m < 0 || m > EXDEX_CONE_MAX_ROWS) return 0;
    if (m > 0 && !rows) return 0;
    return ex_finite_n(rows, 3 * m);
}

/* Every volume method works on the unit cube C = [-1/2, 1/2]^3 of
 * coordinates s, x = lo + w (s + 1/2) with w = hi - lo (rounded once), where
 * a row a . x >= 0 reads b . s + beta >= 0 with
 *     b_j  = a_j w_j 2^-S,     beta = sum_j a_j (lo_j + w_j / 2) 2^-S,
 * S chosen so that max |b_j| is in [1/4, 1). The cone's apex (x = 0) may be
 * arbitrarily far from the box relative to its size (a thin box far from
 * the origin); beta is then a sum of large, cancelling products. It is
 * formed exactly (every product split exactly with fma and summed in a
 * fixed-point accumulator wide enough for the whole double range) and
 * rounded once, so the plane's position in C is off by a few eps, whatever
 * the box; |beta| is capped at 2^60 (the plane then misses C, the cap only
 * keeps the side). No product overflows or underflows: the factors are
 * split with frexp first. */

#define SA_LIMBS 76
#define SA_BASE (-2400)  /* weight of bit 0 of limb 0: 2^SA_BASE */

typedef struct sacc {
    uint64_t w[SA_LIMBS];  /* two's complement fixed point */
} sacc;

/* acc += x 2^e, x a finite double whose bits all lie above 2^(SA_BASE - e) */
static void sa_add(sacc *acc, double x, int e)
{
    if (x == 0.0) return;
    int k;
    double mant = frexp(fabs(x), &k);
    uint64_t M = (uint64_t)ldexp(mant, 53);
    int s = k - 53 + e - SA_BASE;
    int i = s / 64, off = s % 64;
    uint64_t part[2] = {M << off, off ? M >> (64 - off) : 0};
    uint64_t c = 0;
    for (int j = i; j < SA_LIMBS; j++) {
        uint64_t d = j - i < 2 ? part[j - i] : 0, t = acc->w[j];
        if (x > 0) {
            uint64_t u = t + d, u2 = u + c;
            c = (uint64_t)(u < d) | (uint64_t)(u2 < c);
            acc->w[j] = u2;
        } else {
            uint64_t u = t - d, u2 = u - c;
            c = (uint64_t)(t < d) | (uint64_t)(u < c);
            acc->w[j] = u2;
        }
        if (j > i && c == 0) break;
    }
}

/* acc += a b 2^e exactly (a b = (p + r) 2^(ka + kb), p and r exact by fma) */
static void sa_add_product(sacc *acc, double a, double b, int e)
{
    if (a == 0.0 || b == 0.0) return;
    int ka, kb;
    double ma = frexp(a, &ka), mb = frexp(b, &kb);
    double p = ma * mb, r = fma(ma, mb, -p);
    sa_add(acc, p, ka + kb + e);
    sa_add(acc, r, ka + kb + e);
}

/* The accumulated value times 2^scale, rounded (relative error <= 2^-51),
 * its magnitude capped at sat (a power of two). */
static double sa_value(const sacc *acc, int scale, double sat)
{
    uint64_t w[SA_LIMBS];
    memcpy(w, acc->w, sizeof w);
    int neg = (int)(w[SA_LIMBS - 1] >> 63);
    if (neg) {
        uint64_t c = 1;
        for (int j = 0; j < SA_LIMBS; j++) {
            w[j] = ~w[j] + c;
            c = c && w[j] == 0;
        }
    }
    int i = SA_LIMBS - 1;
    while (i >= 0 && w[i] == 0) i--;
    if (i < 0) return 0.0;
    double v = ldexp((double)w[i], 128);
    if (i >= 1) v += ldexp((double)w[i - 1], 64);
    if (i >= 2) v += (double)w[i - 2];
    int ex = 64 * (i - 2) + SA_BASE + scale;  /* result = v 2^ex, v < 2^192 */
    v = ilogb(v) + ex > ilogb(sat) ? sat : ldexp(v, ex);
    return neg ? -v : v;
}

/* b[0..3] = (b, beta) of row a (see above); 0 for an all-zero row (no
 * constraint), else 1. */
static int row_to_cube(const double a[3], const double lo[3], const double w[3], double b[4])
{
    int S = INT_MIN, ka[3], kw[3];
    double ma[3], mw[3];
    for (int j = 0; j < 3; j++) {
        if (a[j] == 0.0) continue;
        ma[j] = frexp(a[j], &ka[j]);
        mw[j] = frexp(w[j], &kw[j]);
        if (ka[j] + kw[j] > S) S = ka[j] + kw[j];
    }
    if (S == INT_MIN) return 0;
    for (int j = 0; j < 3; j++) b[j] = a[j] == 0.0 ? 0.0 : ldexp(ma[j] * mw[j], ka[j] + kw[j] - S);
    // Fast path (Ogita-Rump-Oishi Dot2): fma-split products, compensated
    // sum; error <= eps |beta| + 8 eps^2 sum |terms|, accepted when the
    // second part is below eps 2^(S-2) (eps relative to max |b_j|) and no
    // product or error term can underflow or overflow.
    {
        double t[6] = {a[0] * lo[0], a[1] * lo[1], a[2] * lo[2],
                       a[0] * (0.5 * w[0]), a[1] * (0.5 * w[1]), a[2] * (0.5 * w[2])};
        double f1[6] = {a[0], a[1], a[2], a[0], a[1], a[2]};
        double f2[6] = {lo[0], lo[1], lo[2], 0.5 * w[0], 0.5 * w[1], 0.5 * w[2]};
        double hi_s = 0.0, lo_s = 0.0, abs_s = 0.0;
        int ok = 1;
        for (int i = 0; i < 6 && ok; i++) {
            double x = t[i];
            if (x == 0.0) {
                if (f1[i] != 0.0 && f2[i] != 0.0) ok = 0;  /* underflowed */
                continue;
            }
            double ax = fabs(x);
            if (!(ax >= 0x1p-900 && ax <= 0x1p900)) { ok = 0; break; }
            double e = fma(f1[i], f2[i], -x);
            double sN = hi_s + x, bb = sN - hi_s;
            lo_s += (hi_s - (sN - bb)) + (x - bb) + e;
            hi_s = sN;
            abs_s += ax;
        }
        if (ok && 8.0 * DBL_EPSILON * DBL_EPSILON * abs_s <= ldexp(DBL_EPSILON, S - 2)) {
            double r = hi_s + lo_s;
            b[3] = r != 0.0 && ilogb(r) - S > 60 ? copysign(0x1p60, r) : ldexp(r, -S);
            return 1;
        }
    }
    sacc acc;
    memset(&acc, 0, sizeof acc);
    for (int j = 0; j < 3; j++) {
        sa_add_product(&acc, a[j], lo[j], 0);
        sa_add_product(&acc, a[j], w[j], -1);
    }
    b[3] = sa_value(&acc, -S, 0x1p60);
    return 1;
}

/* Rows of one cone in cube form; returns the number of non-zero rows. */
static int rows_to_cube(const double *rows, int m, const double lo[3], const double w[3],
                        double *B)
{
    int k = 0;
    for (int r = 0; r < m; r++) k += row_to_cube(rows + 3 * r, lo, w, B + 4 * k);
    return k;
}

/* A convex polytope inside C as a list of faces (vertex cycles in one
 * pool), each with its outward unit normal and the distance h of its plane
 * from the centre, measured along that normal. */
typedef struct cpoly {
    double (*v)[3];
    int nv, capv;
    int *first, *count;
    double (*nrm)[3];
    double *h;
    int nf;
} cpoly;

typedef struct cap_pt {
    double ang, p[3];
} cap_pt;

typedef struct exact_ws {
    cpoly P[2];
    int capf;          /* faces per polytope: 6 + rows */
    double *d;         /* (capv of the current polytope) */
    int capd;
    cap_pt *cap;
    int capc;
    double B[4 * EXDEX_CONE_MAX_ROWS];
} exact_ws;

static void exact_ws_free(exact_ws *ws)
{
    for (int i = 0; i < 2; i++) {
        free(ws->P[i].v); free(ws->P[i].first); free(ws->P[i].count);
        free(ws->P[i].nrm); free(ws->P[i].h);
    }
    free(ws->d);
    free(ws->cap);
    memset(ws, 0, sizeof *ws);
}

static int grow(void **p, int *cap, int need, size_t elem)
{
    if (need <= *cap) return EXDEX_OK;
    int n = *cap > 0 ? *cap : 64;
    while (n < need) n *= 2;
    void *q = realloc(*p, elem * (size_t)n);
    if (!q) return EXDEX_ENOMEM;
    *p = q;
    *cap = n;
    return EXDEX_OK;
}

static void exact_ws_init(exact_ws *ws)
{
    memset(ws, 0, sizeof *ws);
}

/* The polytope arrays, allocated on first use (apex far from the box). */
static int exact_ws_poly(exact_ws *ws, int m)
{
    if (ws->capf >= 6 + m) return EXDEX_OK;
    exact_ws keep = *ws;
    for (int i = 0; i < 2; i++) {
        free(keep.P[i].v); free(keep.P[i].first); free(keep.P[i].count);
        free(keep.P[i].nrm); free(keep.P[i].h);
        memset(&ws->P[i], 0, sizeof ws->P[i]);
    }
    ws->capf = 6 + m;
    for (int i = 0; i < 2; i++) {
        cpoly *P = &ws->P[i];
        P->first = malloc(sizeof(int) * (size_t)ws->capf);
        P->count = malloc(sizeof(int) * (size_t)ws->capf);
        P->nrm = malloc(sizeof(double[3]) * (size_t)ws->capf);
        P->h = malloc(sizeof(double) * (size_t)ws->capf);
        if (!P->first || !P->count || !P->nrm || !P->h ||
            grow((void **)&P->v, &P->capv, 24 + 8 * m, sizeof(double[3]))) {
            exact_ws_free(ws);
            return EXDEX_ENOMEM;
        }
    }
    return EXDEX_OK;
}

static void poly_cube(cpoly *P)
{
    P->nf = 0;
    P->nv = 0;
    static const double uv[4][2] = {{-0.5, -0.5}, {0.5, -0.5}, {0.5, 0.5}, {-0.5, 0.5}};
    for (int j = 0; j < 3; j++)
        for (int sg = -1; sg <= 1; sg += 2) {
            int iu = (j + 1) % 3, iv = (j + 2) % 3, f = P->nf++;
            P->first[f] = P->nv;
            P->count[f] = 4;
            P->nrm[f][0] = P->nrm[f][1] = P->nrm[f][2] = 0.0;
            P->nrm[f][j] = (double)sg;
            P->h[f] = 0.5;
            for (int c = 0; c < 4; c++) {
                double *q = P->v[P->nv++];
                q[j] = 0.5 * sg;
                q[iu] = uv[c][0];
                q[iv] = uv[c][1];
            }
        }
}

/* Close the face whose vertices were emitted from index start on (a last
 * vertex equal to the first is dropped): a face of >= 3 vertices with the
 * outward normal nrm at distance h, else no face. */
static void close_face(cpoly *Q, int start, const double nrm[3], double h)
{
    int cnt = Q->nv - start;
    if (cnt >= 2) {
        const double *a = Q->v[start], *z = Q->v[Q->nv - 1];
        if (a[0] == z[0] && a[1] == z[1] && a[2] == z[2]) { Q->nv--; cnt--; }
    }
    if (cnt >= 3) {
        int g = Q->nf++;
        Q->first[g] = start;
        Q->count[g] = cnt;
        memcpy(Q->nrm[g], nrm, sizeof(double[3]));
        Q->h[g] = h;
    } else {
        Q->nv = start;
    }
}

static void emit(cpoly *P, int start, const double q[3])
{
    if (P->nv > start) {
        const double *l = P->v[P->nv - 1];
        if (l[0] == q[0] && l[1] == q[1] && l[2] == q[2]) return;
    }
    double *o = P->v[P->nv++];
    o[0] = q[0]; o[1] = q[1]; o[2] = q[2];
}

static int cap_cmp(const void *x, const void *y)
{
    const cap_pt *a = x, *b = y;
    if (a->ang != b->ang) return a->ang < b->ang ? -1 : 1;
    for (int j = 0; j < 3; j++)
        if (a->p[j] != b->p[j]) return a->p[j] < b->p[j] ? -1 : 1;
    return 0;
}

/* Clip the polytope ws->P[*cur] by b . s + beta >= 0. */
static int poly_clip(exact_ws *ws, int *cur, const double b[4])
{
    cpoly *P = &ws->P[*cur], *Q = &ws->P[1 - *cur];
    int st = grow((void **)&ws->d, &ws->capd, P->nv, sizeof(double));
    if (st) return st;
    // A vertex within rounding of the plane counts as on it: a plane (nearly)
    // through a face, e.g. a repeated row, then leaves the polytope alone
    // instead of cutting that face at random places.
    double tau = 8.0 * DBL_EPSILON * (0.5 * (fabs(b[0]) + fabs(b[1]) + fabs(b[2])) + fabs(b[3]));
    double dmin = INFINITY, dmax = -INFINITY;
    for (int i = 0; i < P->nv; i++) {
        const double *p = P->v[i];
        double d = b[0] * p[0] + b[1] * p[1] + b[2] * p[2] + b[3];
        if (fabs(d) <= tau) d = 0.0;
        ws->d[i] = d;
        dmin = fmin(dmin, d);
        dmax = fmax(dmax, d);
    }
    if (dmin >= 0.0) return EXDEX_OK;  /* the whole polytope is inside */
    if (dmax <= 0.0) {                  /* at most a face is left */
        P->nf = 0;
        return EXDEX_OK;
    }
    Q->nf = 0;
    Q->nv = 0;
    int ncap = 0;
    for (int f = 0; f < P->nf; f++) {
        int n = P->count[f], f0 = P->first[f];
        st = grow((void **)&Q->v, &Q->capv, Q->nv + 2 * n, sizeof(double[3]));
        if (!st) st = grow((void **)&ws->cap, &ws->capc, ncap + 2 * n, sizeof(cap_pt));
        if (st) return st;
        int start = Q->nv;
        for (int i = 0; i < n; i++) {
            int ip = f0 + i, iq = f0 + (i + 1) % n;
            const double *p = P->v[ip], *q = P->v[iq];
            double dp = ws->d[ip], dq = ws->d[iq];
            if (dp >= 0.0) {
                emit(Q, start, p);
                if (dp == 0.0) memcpy(ws->cap[ncap++].p, p, sizeof(double[3]));
            }
            // the crossing point is computed from the inside vertex, so the
            // two faces sharing the edge get the same point bit for bit
            const double *in = NULL, *out = NULL;
            double din = 0.0, dout = 0.0;
            if (dp > 0.0 && dq < 0.0) { in = p; out = q; din = dp; dout = dq; }
            else if (dp < 0.0 && dq > 0.0) { in = q; out = p; din = dq; dout = dp; }
            if (in) {
                double t = din / (din - dout), x[3];
                for (int j = 0; j < 3; j++) x[j] = in[j] + t * (out[j] - in[j]);
                emit(Q, start, x);
                memcpy(ws->cap[ncap++].p, x, sizeof x);
            }
        }
        close_face(Q, start, P->nrm[f], P->h[f]);
    }
    // The cap: the points of the polytope on the plane, in angular order
    // about their centroid (they are the vertices of a convex polygon).
    double bn = sqrt(b[0] * b[0] + b[1] * b[1] + b[2] * b[2]);
    if (ncap >= 3 && Q->nf < ws->capf) {
        double nh[3] = {-b[0] / bn, -b[1] / bn, -b[2] / bn}, u[3], v[3], g[3] = {0, 0, 0};
        int k = 0;
        for (int j = 1; j < 3; j++)
            if (fabs(nh[j]) < fabs(nh[k])) k = j;
        double e[3] = {0, 0, 0};
        e[k] = 1.0;
        ex_cross3(u, nh, e);
        double un = sqrt(ex_dot3(u, u));
        for (int j = 0; j < 3; j++) u[j] /= un;
        ex_cross3(v, nh, u);
        for (int i = 0; i < ncap; i++)
            for (int j = 0; j < 3; j++) g[j] += ws->cap[i].p[j];
        for (int j = 0; j < 3; j++) g[j] /= ncap;
        for (int i = 0; i < ncap; i++) {
            double r[3];
            for (int j = 0; j < 3; j++) r[j] = ws->cap[i].p[j] - g[j];
            ws->cap[i].ang = atan2(ex_dot3(r, v), ex_dot3(r, u));
        }
        qsort(ws->cap, (size_t)ncap, sizeof(cap_pt), cap_cmp);
        st = grow((void **)&Q->v, &Q->capv, Q->nv + ncap, sizeof(double[3]));
        if (st) return st;
        int start = Q->nv;
        for (int i = 0; i < ncap; i++) emit(Q, start, ws->cap[i].p);
        /* outward normal nh = -b/|b|: s . nh = beta / |b| on the plane */
        close_face(Q, start, nh, b[3] / bn);
    }
    *cur = 1 - *cur;
    return EXDEX_OK;
}

/* Volume of the polytope (C has volume 1): divergence theorem with
 * F(s) = s / 3 about the cube centre, V = 1/3 sum_f h_f area_f; every term
 * is O(1), so the rounding is a few eps per face. */
static double poly_volume(const cpoly *P)
{
    double acc = 0.0;
    for (int f = 0; f < P->nf; f++) {
        const double (*v)[3] = (const double (*)[3])P->v + P->first[f];
        int n = P->count[f];
        double S[3] = {0, 0, 0};
        for (int i = 1; i + 1 < n; i++) {
            double a[3], b[3], c[3];
            for (int j = 0; j < 3; j++) { a[j] = v[i][j] - v[0][j]; b[j] = v[i + 1][j] - v[0][j]; }
            ex_cross3(c, a, b);
            for (int j = 0; j < 3; j++) S[j] += c[j];
        }
        acc += P->h[f] * fabs(ex_dot3(S, P->nrm[f]));
    }
    return acc / 6.0;
}

/* Apex near the box: the divergence theorem with F(s) = (s - p) / 3 about
 * the apex p, where every cone facet passes through p and adds nothing, so
 * only the box faces count: V = 1/3 sum_faces (1/2 -+ p_j) A(face), each A a
 * square clipped by the rows (Sutherland-Hodgman, shoelace). Every face is
 * clipped on its own, so this is immune to degenerate cones (many facets
 * through the apex at tiny angles); the terms are O(1 + |p|), hence it is
 * used only for |p_j| <= APEX_NEAR. */
#define APEX_NEAR 4.0

static double face_area(const double *B, int k, int j, double c)
{
    enum { CAP = EXDEX_CONE_MAX_ROWS + 8 };
    double pa[CAP][2], pb[CAP][2];
    double (*in)[2] = pa, (*out)[2] = pb;
    int iu = (j + 1) % 3, iv = (j + 2) % 3;
    int n = 4;
    in[0][0] = -0.5; in[0][1] = -0.5;
    in[1][0] = 0.5; in[1][1] = -0.5;
    in[2][0] = 0.5; in[2][1] = 0.5;
    in[3][0] = -0.5; in[3][1] = 0.5;
    for (int r = 0; r < k && n > 0; r++) {
        const double *a = B + 4 * r;
        double au = a[iu], av = a[iv], a0 = a[j] * c + a[3];
        if (au == 0.0 && av == 0.0) {
            if (a0 < 0.0) return 0.0;  // the whole face is cut away
            continue;                  // a0 >= 0: no constraint on this face
        }
        int no = 0;
        for (int i = 0; i < n && no + 2 <= CAP; i++) {
            const double *p = in[i], *q = in[(i + 1) % n];
            double dp = au * p[0] + av * p[1] + a0;
            double dq = au * q[0] + av * q[1] + a0;
            if (dp >= 0.0) {
                out[no][0] = p[0]; out[no][1] = p[1]; no++;
                if (dq < 0.0) {
                    double t = dp / (dp - dq);
                    out[no][0] = p[0] + t * (q[0] - p[0]);
                    out[no][1] = p[1] + t * (q[1] - p[1]);
                    no++;
                }
            } else if (dq >= 0.0) {
                double t = dp / (dp - dq);
                out[no][0] = p[0] + t * (q[0] - p[0]);
                out[no][1] = p[1] + t * (q[1] - p[1]);
                no++;
            }
        }
        double (*tmp)[2] = in; in = out; out = tmp;
        n = no;
    }
    if (n < 3) return 0.0;
    double s = 0.0;
    for (int i = 1; i + 1 < n; i++)
        s += (in[i][0] - in[0][0]) * (in[i + 1][1] - in[0][1]) -
             (in[i + 1][0] - in[0][0]) * (in[i][1] - in[0][1]);
    return 0.5 * fabs(s);
}

static double apex_fraction(const double *B, int k, const double p[3])
{
    double v = 0.0;
    for (int j = 0; j < 3; j++)
        v += (0.5 - p[j]) * face_area(B, k, j, 0.5) + (0.5 + p[j]) * face_area(B, k, j, -0.5);
    return v / 3.0;
}

/* Fraction of the box inside the cone, in [0, 1], for k cube-form rows. */
static int cube_fraction(exact_ws *ws, const double *B, int k, const double p[3], double *frac)
{
    if (k == 0) {  /* no constraint: the whole box, exactly */
        *frac = 1.0;
        return EXDEX_OK;
    }
    if (fabs(p[0]) <= APEX_NEAR && fabs(p[1]) <= APEX_NEAR && fabs(p[2]) <= APEX_NEAR) {
        double v = apex_fraction(B, k, p);
        *frac = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
        return EXDEX_OK;
    }
    int cur = 0, st = exact_ws_poly(ws, k);
    if (st) return st;
    poly_cube(&ws->P[0]);
    for (int r = 0; r < k && ws->P[cur].nf > 0; r++) {
        st = poly_clip(ws, &cur, B + 4 * r);
        if (st) return st;
    }
    double v = ws->P[cur].nf > 0 ? poly_volume(&ws->P[cur]) : 0.0;
    *frac = v < 0.0 ? 0.0 : v > 1.0 ? 1.0 : v;
    return EXDEX_OK;
}

static int volume_exact_ws(exact_ws *ws, const double *rows, int m, const double lo[3],
                           const double hi[3], double *volume)
{
    double w[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]}, frac, p[3];
    for (int j = 0; j < 3; j++) p[j] = -(lo[j] + 0.5 * w[j]) / w[j];  /* the apex x = 0 */
    int k = rows_to_cube(rows, m, lo, w, ws->B);
    int st = cube_fraction(ws, ws->B, k, p, &frac);
    if (st) return st;
    *volume = frac * (w[0] * w[1] * w[2]);
    return EXDEX_OK;
}

int exdex_cone_volume_exact(const double *rows, int m, const double lo[3],
                            const double hi[3], double *volume)
{
    if (!volume || !box_ok(lo, hi) || !rows_ok(rows, m)) return EXDEX_EINVAL;
    exact_ws ws;
    exact_ws_init(&ws);
    int st = volume_exact_ws(&ws, rows, m, lo, hi, volume);
    exact_ws_free(&ws);
    return st;
}

/* ------------------------------------------------------------------ grid */

static double volume_grid(const double *B, int k, const double w[3], long n)
{
    // Paper Section 3.1: discretise the cuboid, count the cells whose centre
    // satisfies every row (cube-form rows B, k of them: the centre of cell i
    // along an axis is s = (2 i + 1 - n) / (2 n) in C). Partial sums per
    // axis keep the inner loop at k multiply-adds per cell.
    double part[EXDEX_CONE_MAX_ROWS];
    long count = 0;
    for (long i = 0; i < n; i++) {
        double x = (double)(2 * i + 1 - n) / (2.0 * (double)n);
        for (long l2 = 0; l2 < n; l2++) {
            double y = (double)(2 * l2 + 1 - n) / (2.0 * (double)n);
            for (int r = 0; r < k; r++) part[r] = B[4 * r] * x + B[4 * r + 1] * y + B[4 * r + 3];
            for (long l = 0; l < n; l++) {
                double z = (double)(2 * l + 1 - n) / (2.0 * (double)n);
                int in = 1;
                for (int r = 0; r < k; r++)
                    if (part[r] + B[4 * r + 2] * z < 0.0) { in = 0; break; }
                count += in;
            }
        }
    }
    double box = w[0] * w[1] * w[2];
    return box * ((double)count / ((double)n * (double)n * (double)n));
}

/* ------------------------------------------------------------------- QMC */

typedef struct qmc_ws {
    gsl_qrng *q;
    gsl_rng *rng;
    double *shift;   /* (shifts, 3) */
    long *count;     /* (shifts,) */
} qmc_ws;

static void qmc_free(qmc_ws *w)
{
    if (w->q) gsl_qrng_free(w->q);
    if (w->rng) gsl_rng_free(w->rng);
    free(w->shift);
    free(w->count);
    w->q = NULL; w->rng = NULL; w->shift = NULL; w->count = NULL;
}

static int qmc_alloc(qmc_ws *w, int shifts)
{
    w->q = gsl_qrng_alloc(gsl_qrng_sobol, 3);
    w->rng = gsl_rng_alloc(gsl_rng_mt19937);
    w->shift = malloc(sizeof(double) * 3 * (size_t)shifts);
    w->count = malloc(sizeof(long) * (size_t)shifts);
    if (!w->q || !w->rng || !w->shift || !w->count) {
        qmc_free(w);
        return EXDEX_ENOMEM;
    }
    return EXDEX_OK;
}

static int volume_qmc(qmc_ws *w, const double *B, int m, const double h[3],
                      const exdex_volume_opts *o, double *vol, double *err)
{
    // cube-form rows B (m of them): a point t of [0,1)^3 is s = t - 1/2 in C
    int K = o->qmc_shifts;
    gsl_qrng_init(w->q);
    gsl_rng_set(w->rng, o->seed);
    // Cranley-Patterson rotations: the same Sobol points shifted mod 1 by K
    // independent uniform vectors give K unbiased, independent estimates.
    for (int k = 0; k < K; k++) {
        for (int j = 0; j < 3; j++)
            w->shift[3 * k + j] = K > 1 ? gsl_rng_uniform(w->rng) : 0.0;
        w->count[k] = 0;
    }
    double u[3];
    for (long i = 0; i < o->qmc_points; i++) {
        if (gsl_qrng_get(w->q, u) != GSL_SUCCESS) return EXDEX_EINVAL;
        for (int k = 0; k < K; k++) {
            double x[3];
            for (int j = 0; j < 3; j++) {
                double t = u[j] + w->shift[3 * k + j];
                if (t >= 1.0) t -= 1.0;
                x[j] = t - 0.5;
            }
            int in = 1;
            for (int r = 0; r < m; r++) {
                const double *a = B + 4 * r;
                if (a[0] * x[0] + a[1] * x[1] + a[2] * x[2] + a[3] < 0.0) { in = 0; break; }
            }
            w->count[k] += in;
        }
    }
    double box = h[0] * h[1] * h[2];
    double mean = 0.0;
    for (int k = 0; k < K; k++) mean += (double)w->count[k];
    mean /= (double)K;
    double var = 0.0;
    for (int k = 0; k < K; k++) {
        double d = (double)w->count[k] - mean;
        var += d * d;
    }
    // fractions of the box first (a subnormal box volume keeps its digits)
    double n = (double)o->qmc_points;
    *vol = box * (mean / n);
    *err = K > 1 ? box * (sqrt(var / (double)(K - 1) / (double)K) / n) : NAN;
    return EXDEX_OK;
}

/* ------------------------------------------------------------ vectorised */

exdex_volume_opts exdex_default_volume_opts(void)
{
    exdex_volume_opts o;
    o.grid_n = 64;
    o.qmc_points = 1L << 16;
    o.qmc_shifts = 16;
    o.seed = 1;
    return o;
}

int exdex_cone_volumes(int method, size_t n_cases, int m, const double *rows,
                       const double lo[3], const double hi[3],
                       const exdex_volume_opts *opts, double *volume, double *err)
{
    exdex_volume_opts o = opts ? *opts : exdex_default_volume_opts();
    if (!volume || !box_ok(lo, hi) || m < 0 || m > EXDEX_CONE_MAX_ROWS ||
        (n_cases > 0 && m > 0 && !rows))
        return EXDEX_EINVAL;
    if (method == EXDEX_VOLUME_GRID && !(o.grid_n >= 1 && o.grid_n <= 100000))
        return EXDEX_EINVAL;
    if (method == EXDEX_VOLUME_QMC &&
        !(o.qmc_points >= 1 && o.qmc_points <= (1L << 30) && o.qmc_shifts >= 1 &&
          o.qmc_shifts <= 4096))
        return EXDEX_EINVAL;
    if (method < EXDEX_VOLUME_EXACT || method > EXDEX_VOLUME_QMC) return EXDEX_EINVAL;
    for (size_t c = 0; c < n_cases; c++)
        if (!rows_ok(rows + 3 * (size_t)m * c, m)) return EXDEX_EINVAL;

    qmc_ws w = {NULL, NULL, NULL, NULL};
    exact_ws ws;
    exact_ws_init(&ws);
    int status = EXDEX_OK;
    if (method == EXDEX_VOLUME_QMC) status = qmc_alloc(&w, o.qmc_shifts);
    double wd[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    for (size_t c = 0; c < n_cases && status == EXDEX_OK; c++) {
        const double *a = rows + 3 * (size_t)m * c;
        double e = NAN;
        switch (method) {
        case EXDEX_VOLUME_EXACT:
            status = volume_exact_ws(&ws, a, m, lo, hi, &volume[c]);
            break;
        case EXDEX_VOLUME_GRID:
            volume[c] = volume_grid(ws.B, rows_to_cube(a, m, lo, wd, ws.B), wd, o.grid_n);
            break;
        default:
            status = volume_qmc(&w, ws.B, rows_to_cube(a, m, lo, wd, ws.B), wd, &o,
                                &volume[c], &e);
            break;
        }
        if (err) err[c] = e;
    }
    qmc_free(&w);
    exact_ws_free(&ws);
    return status;
}

/* ------------------------------------------------------------ tool rows */

int exdex_tool_problem_check(const exdex_tool_problem *p, const char **bad_param)
{
    const char *bad = NULL;
    if (!p) bad = "problem";
    else if (p->model != EXDEX_TOOL_CONTACT && p->model != EXDEX_TOOL_PAPER) bad = "model";
    else if (p->n_phi < 1 || !p->phi || !ex_finite_n(p->phi, p->n_phi)) bad = "phi";
    else if (!box_ok(p->lo, p->hi)) bad = "box";
    else if (!(p->mu >= 0.0) || !isfinite(p->mu)) bad = "mu";
    else if (p->has_push && !ex_finite_n(p->push, 3)) bad = "push";
    else if (p->model == EXDEX_TOOL_CONTACT) {
        if (p->n_shapes < 1 || !p->n_vertices || !p->vertices) bad = "shapes";
        else {
            size_t off = 0;
            for (int s = 0; s < p->n_shapes && !bad; s++) {
                int nv = p->n_vertices[s];
                if (nv < 3 || nv > EXDEX_MAX_VERTICES) { bad = "shapes"; break; }
                const double *v = p->vertices + 2 * off;
                if (!ex_finite_n(v, 2 * nv)) bad = "shapes";
                double area = 0.0;
                for (int i = 0; i < nv; i++) {
                    int k = (i + 1) % nv;
                    area += v[2 * i] * v[2 * k + 1] - v[2 * k] * v[2 * i + 1];
                }
                if (!(fabs(area) > 0.0)) bad = "shapes";
                off += (size_t)nv;
            }
        }
    }
    if (bad_param) *bad_param = bad;
    return bad ? EXDEX_EINVAL : EXDEX_OK;
}

static const double *shape_vertices(const exdex_tool_problem *p, int shape, int *nv)
{
    size_t off = 0;
    for (int s = 0; s < shape; s++) off += (size_t)p->n_vertices[s];
    *nv = p->n_vertices[shape];
    return p->vertices + 2 * off;
}

/* Append the row(s) of one contact (object frame), with friction if mu > 0. */
static int add_contact(double *rows, int *nrows, const double r[2], const double n[2],
                       double mu)
{
    int need = mu > 0.0 ? 2 : 1;
    if (*nrows + need > EXDEX_CONE_MAX_ROWS) return EXDEX_EINVAL;
    if (mu > 0.0) {
        int st = exdex_contact_rows_friction(rows + 3 * *nrows, r, n, mu);
        if (st) return st;
    } else {
        exdex_contact_row(rows + 3 * *nrows, r, n);
    }
    *nrows += need;
    return EXDEX_OK;
}

int exdex_tool_rows(const exdex_tool_problem *p, const exdex_tool_def *tool, int shape,
                    double phi, double *rows, int *nrows)
{
    if (!p || !tool || !rows || !nrows || !isfinite(phi) || !isfinite(tool->alpha1) ||
        !isfinite(tool->alpha2) || (tool->plunger && !isfinite(tool->s)))
        return EXDEX_EINVAL;
    *nrows = 0;
    double cp = cos(phi), sp = sin(phi);
    if (p->model == EXDEX_TOOL_PAPER) {
        exdex_cone_rows_paper(rows, phi - tool->alpha1, tool->alpha2 - tool->alpha1);
        *nrows = 2;
    } else {
        if (shape < 0 || shape >= p->n_shapes) return EXDEX_EINVAL;
        int nv;
        const double *v = shape_vertices(p, shape, &nv);
        double radius = 0.0;
        for (int i = 0; i < nv; i++)
            radius = fmax(radius, hypot(v[2 * i], v[2 * i + 1]));
        double tol = 1e-9 * radius;
        double alpha[2] = {tool->alpha1, tool->alpha2};
        double nw[2][2], h[2];  // world normals, support offsets
        for (int s = 0; s < 2; s++) {
            nw[s][0] = -sin(alpha[s]);
            nw[s][1] = cos(alpha[s]);
            // the surface normal in the object frame: R(-phi) n
            double n[2] = {cp * nw[s][0] + sp * nw[s][1], -sp * nw[s][0] + cp * nw[s][1]};
            double dmin = INFINITY;
            for (int i = 0; i < nv; i++)
                dmin = fmin(dmin, n[0] * v[2 * i] + n[1] * v[2 * i + 1]);
            h[s] = -dmin;
            for (int i = 0; i < nv; i++) {
                if (n[0] * v[2 * i] + n[1] * v[2 * i + 1] <= dmin + tol) {
                    int st = add_contact(rows, nrows, v + 2 * i, n, p->mu);
                    if (st) return st;
                }
            }
        }
        double det = nw[0][0] * nw[1][1] - nw[0][1] * nw[1][0];
        if (tool->plunger && fabs(det) > 1e-9) {
            // Wedged position c of the reference point: n_s . (c + R v) >= 0
            // with equality at the support vertices, n_s . c = h_s.
            double c[2] = {(h[0] * nw[1][1] - h[1] * nw[0][1]) / det,
                           (nw[0][0] * h[1] - nw[1][0] * h[0]) / det};
            double area = 0.0;
            for (int i = 0; i < nv; i++) {
                int k = (i + 1) % nv;
                area += v[2 * i] * v[2 * k + 1] - v[2 * k] * v[2 * i + 1];
            }
            double best = -INFINITY, bx = 0.0, by = 0.0, bnx = 0.0, bny = 0.0;
            for (int i = 0; i < nv; i++) {
                int k = (i + 1) % nv;
                double ax = c[0] + cp * v[2 * i] - sp * v[2 * i + 1];
                double ay = c[1] + sp * v[2 * i] + cp * v[2 * i + 1];
                double qx = c[0] + cp * v[2 * k] - sp * v[2 * k + 1];
                double qy = c[1] + sp * v[2 * k] + cp * v[2 * k + 1];
                double x0 = fmin(ax, qx), x1 = fmax(ax, qx);
                if (!(tool->s >= x0 && tool->s <= x1) || x1 - x0 <= 0.0) continue;
                double y = ay + (tool->s - ax) / (qx - ax) * (qy - ay);
                if (y > best) {
                    // inward normal of the edge: left of the edge direction for
                    // a counter-clockwise polygon, right for a clockwise one
                    double dx = qx - ax, dy = qy - ay, len = hypot(dx, dy);
                    double sg = area > 0.0 ? 1.0 : -1.0;
                    best = y; bx = tool->s; by = y;
                    bnx = -sg * dy / len; bny = sg * dx / len;
                }
            }
            if (best > -INFINITY) {
                // to the object frame: r = R(-phi) (p - c), n = R(-phi) n_w
                double px = bx - c[0], py = by - c[1];
                double r[2] = {cp * px + sp * py, -sp * px + cp * py};
                double n[2] = {cp * bnx + sp * bny, -sp * bnx + cp * bny};
                int st = add_contact(rows, nrows, r, n, p->mu);
                if (st) return st;
            }
        }
    }
    if (p->has_push) {
        // push . x >= 0: quasi-static motion must be driven by the push
        // (the contacts only dissipate). Force to the object frame.
        if (*nrows + 1 > EXDEX_CONE_MAX_ROWS) return EXDEX_EINVAL;
        double *a = rows + 3 * *nrows;
        a[0] = cp * p->push[0] + sp * p->push[1];
        a[1] = -sp * p->push[0] + cp * p->push[1];
        a[2] = p->push[2];
        *nrows += 1;
    }
    // a row overflows only for data near DBL_MAX (vertices, push)
    return ex_finite_n(rows, 3 * *nrows) ? EXDEX_OK : EXDEX_ENONFINITE;
}

int exdex_tool_volumes(const exdex_tool_problem *p, size_t n_tools,
                       const exdex_tool_def *tools, double *volume)
{
    if (exdex_tool_problem_check(p, NULL) || (n_tools > 0 && (!tools || !volume)))
        return EXDEX_EINVAL;
    int ns = p->model == EXDEX_TOOL_PAPER ? 1 : p->n_shapes;
    double rows[3 * EXDEX_CONE_MAX_ROWS];
    size_t idx = 0;
    exact_ws ws;
    exact_ws_init(&ws);
    int st = EXDEX_OK;
    for (size_t t = 0; t < n_tools && !st; t++)
        for (int s = 0; s < ns && !st; s++)
            for (int k = 0; k < p->n_phi && !st; k++) {
                int m;
                st = exdex_tool_rows(p, &tools[t], s, p->phi[k], rows, &m);
                if (!st) st = volume_exact_ws(&ws, rows, m, p->lo, p->hi, &volume[idx]);
                idx++;
            }
    exact_ws_free(&ws);
    return st;
}

int exdex_tool_objective(const exdex_tool_problem *p, const exdex_tool_def *tool,
                         double *sum)
{
    if (!sum || !tool || exdex_tool_problem_check(p, NULL)) return EXDEX_EINVAL;
    int ns = p->model == EXDEX_TOOL_PAPER ? 1 : p->n_shapes;
    double rows[3 * EXDEX_CONE_MAX_ROWS];
    double acc = 0.0;
    exact_ws ws;
    exact_ws_init(&ws);
    int st = EXDEX_OK;
    for (int s = 0; s < ns && !st; s++)
        for (int k = 0; k < p->n_phi && !st; k++) {
            int m;
            double v = 0.0;
            st = exdex_tool_rows(p, tool, s, p->phi[k], rows, &m);
            if (!st) st = volume_exact_ws(&ws, rows, m, p->lo, p->hi, &v);
            acc += v;
        }
    exact_ws_free(&ws);
    if (!st && !isfinite(acc)) st = EXDEX_ENONFINITE;  /* volumes near DBL_MAX add up past it */
    if (!st) *sum = acc;
    return st;
}

/* ------------------------------------------------------- optimisation */

typedef struct theta_ctx {
    const exdex_tool_problem *p;
    exdex_tool_def tool;
    int status;
    int evals;
} theta_ctx;

static double theta_f(double theta, void *params)
{
    theta_ctx *c = params;
    exdex_tool_def t = c->tool;
    t.alpha2 = t.alpha1 + theta;
    double f = NAN;
    int st = exdex_tool_objective(c->p, &t, &f);
    if (st && !c->status) c->status = st;
    c->evals++;
    return f;
}

int exdex_tool_optimise_theta(const exdex_tool_problem *p, const exdex_tool_def *tool,
                              double theta_lo, double theta_hi, int n_scan, double xtol,
                              double *scan_f, exdex_tool_opt_result *res)
{
    if (!tool || !res || exdex_tool_problem_check(p, NULL) || !isfinite(theta_lo) ||
        !isfinite(theta_hi) || !(theta_hi > theta_lo) || n_scan < 3 || !(xtol > 0.0))
        return EXDEX_EINVAL;
    // alpha2 = alpha1 + theta resolves theta to eps (|alpha1| + |theta|): for
    // |alpha1| ~ 1e16 theta is lost entirely (alpha1 ~ 1e128 gives
    // alpha2 - alpha1 = 0, outside [theta_lo, theta_hi]). Bounded angles
    // keep the returned theta within 2.3e-10 rad of the one evaluated.
    if (!(fabs(tool->alpha1) <= EXDEX_TOOL_ANGLE_MAX) || !(fabs(theta_lo) <= EXDEX_TOOL_ANGLE_MAX) ||
        !(fabs(theta_hi) <= EXDEX_TOOL_ANGLE_MAX))
        return EXDEX_EINVAL;
    theta_ctx ctx = {p, *tool, EXDEX_OK, 0};
    // Coarse scan (Eq. 12 over a grid of theta); keep the first best value.
    int best = 0;
    double fbest = INFINITY, dth = (theta_hi - theta_lo) / (n_scan - 1);
    double fprev = NAN, fnext = NAN;
    double *f = scan_f ? scan_f : malloc(sizeof(double) * (size_t)n_scan);
    if (!f) return EXDEX_ENOMEM;
    for (int i = 0; i < n_scan; i++) {
        f[i] = theta_f(theta_lo + i * dth, &ctx);
        if (ctx.status) break;
        if (f[i] < fbest) { fbest = f[i]; best = i; }
    }
    if (!ctx.status && best > 0 && best < n_scan - 1) {
        fprev = f[best - 1];
        fnext = f[best + 1];
    }
    if (!scan_f) free(f);
    if (ctx.status) return ctx.status;
    res->x[0] = tool->alpha1;
    res->x[1] = tool->alpha1 + theta_lo + best * dth;
    res->x[2] = tool->s;
    res->f = fbest;
    res->iterations = 0;
    res->bracketed = 0;
    if (!(best > 0 && best < n_scan - 1 && fbest < fprev && fbest < fnext)) {
        res->evaluations = ctx.evals;
        return EXDEX_OK;  // minimum at a bound or on a plateau: no bracket
    }
    // Brent on the two cells around the scan minimum (gsl_min_fminimizer_brent).
    gsl_min_fminimizer *s = gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent);
    if (!s) return EXDEX_ENOMEM;
    gsl_function F = {theta_f, &ctx};
    double a = theta_lo + (best - 1) * dth, b = theta_lo + (best + 1) * dth;
    double xm = theta_lo + best * dth;
    int status = EXDEX_OK;
    int gs = gsl_min_fminimizer_set_with_values(s, &F, xm, fbest, a, fprev, b, fnext);
    if (gs != GSL_SUCCESS) status = EXDEX_ENOCONV;
    int it = 0;
    while (!status && it < 200) {
        it++;
        gs = gsl_min_fminimizer_iterate(s);
        if (ctx.status) { status = ctx.status; break; }
        if (gs != GSL_SUCCESS) { status = EXDEX_ENOCONV; break; }
        double lo = gsl_min_fminimizer_x_lower(s), hi = gsl_min_fminimizer_x_upper(s);
        // Brent cannot resolve a minimum below ~sqrt(DBL_EPSILON) relative
        // (the objective is flat to rounding there): clamp the tolerance.
        double xm_now = gsl_min_fminimizer_x_minimum(s);
        if (hi - lo <= fmax(xtol, 3e-8 * fmax(1.0, fabs(xm_now)))) break;
    }
    if (!status && it >= 200) status = EXDEX_ENOCONV;
    if (!status) {
        double xb = gsl_min_fminimizer_x_minimum(s), fb = gsl_min_fminimizer_f_minimum(s);
        if (fb <= fbest) {
            res->x[1] = tool->alpha1 + xb;
            res->f = fb;
        }
        res->bracketed = 1;
        res->iterations = it;
    }
    res->evaluations = ctx.evals;
    gsl_min_fminimizer_free(s);
    return status;
}

typedef struct multi_ctx {
    const exdex_tool_problem *p;
    exdex_tool_def base;
    int idx[3];  /* free parameter -> index into (alpha1, alpha2, s) */
    int nfree;
    int status;
    int evals;
} multi_ctx;

static double multi_f(const gsl_vector *x, void *params)
{
    multi_ctx *c = params;
    exdex_tool_def t = c->base;
    double *q[3] = {&t.alpha1, &t.alpha2, &t.s};
    for (int i = 0; i < c->nfree; i++) *q[c->idx[i]] = gsl_vector_get(x, (size_t)i);
    double f = NAN;
    int st = exdex_tool_objective(c->p, &t, &f);
    c->evals++;
    if (st) {
        if (!c->status) c->status = st;
        return GSL_POSINF;
    }
    return f;
}

int exdex_tool_optimise(const exdex_tool_problem *p, const exdex_tool_def *start,
                        const int free_param[3], const double step[3], int max_iter,
                        double size_tol, exdex_tool_opt_result *res)
{
    if (!start || !free_param || !step || !res || exdex_tool_problem_check(p, NULL) ||
        max_iter < 1 || !(size_tol > 0.0))
        return EXDEX_EINVAL;
    multi_ctx ctx;
    ctx.p = p;
    ctx.base = *start;
    ctx.nfree = 0;
    ctx.status = EXDEX_OK;
    ctx.evals = 0;
    double x0[3] = {start->alpha1, start->alpha2, start->s};
    for (int i = 0; i < 3; i++) {
        if (!isfinite(x0[i])) return EXDEX_EINVAL;
        if (free_param[i]) {
            if (!(step[i] > 0.0) || !isfinite(step[i])) return EXDEX_EINVAL;
            ctx.idx[ctx.nfree++] = i;
        }
    }
    if (ctx.nfree == 0) return EXDEX_EINVAL;
    res->x[0] = x0[0]; res->x[1] = x0[1]; res->x[2] = x0[2];
    res->f = NAN;
    res->bracketed = 0;
    gsl_multimin_fminimizer *s =
        gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, (size_t)ctx.nfree);
    gsl_vector *x = gsl_vector_alloc((size_t)ctx.nfree);
    gsl_vector *ss = gsl_vector_alloc((size_t)ctx.nfree);
    int status = EXDEX_OK;
    if (!s || !x || !ss) status = EXDEX_ENOMEM;
    if (!status) {
        for (int i = 0; i < ctx.nfree; i++) {
            gsl_vector_set(x, (size_t)i, x0[ctx.idx[i]]);
            gsl_vector_set(ss, (size_t)i, step[ctx.idx[i]]);
        }
        gsl_multimin_function F = {multi_f, (size_t)ctx.nfree, &ctx};
        if (gsl_multimin_fminimizer_set(s, &F, x, ss) != GSL_SUCCESS) status = EXDEX_ENOCONV;
        if (ctx.status) status = ctx.status;
    }
    int it = 0;
    while (!status) {
        if (it >= max_iter) { status = EXDEX_ENOCONV; break; }
        it++;
        int gs = gsl_multimin_fminimizer_iterate(s);
        if (ctx.status) { status = ctx.status; break; }
        if (gs != GSL_SUCCESS) { status = EXDEX_ENOCONV; break; }
        if (gsl_multimin_test_size(gsl_multimin_fminimizer_size(s), size_tol) == GSL_SUCCESS)
            break;
    }
    if (s && (status == EXDEX_OK || status == EXDEX_ENOCONV) && it > 0) {
        // report the best point even when the iteration cap was hit
        const gsl_vector *xb = gsl_multimin_fminimizer_x(s);
        for (int i = 0; i < ctx.nfree; i++) res->x[ctx.idx[i]] = gsl_vector_get(xb, (size_t)i);
        res->f = gsl_multimin_fminimizer_minimum(s);
    }
    res->iterations = it;
    res->evaluations = ctx.evals;
    if (s) gsl_multimin_fminimizer_free(s);
    if (x) gsl_vector_free(x);
    if (ss) gsl_vector_free(ss);
    return status;
}
