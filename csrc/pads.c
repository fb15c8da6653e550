/* pads.c -- the contact region of a pad and the object's face (pads.h).
 *
 * Clipping: Sutherland-Hodgman of one convex polygon by the half-planes of
 * the other's edges (both convex, so the result is the convex
 * intersection). The region's area, centroid and mean distance from the
 * centroid are region.c's closed forms. */
#include <math.h>
#include <string.h>

#include "pads.h"
#include "region.h"
#include "util.h"

double pads_signed_area2(const double (*v)[2], int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++) {
        int j = i + 1 == n ? 0 : i + 1;
        s += v[i][0] * v[j][1] - v[j][0] * v[i][1];
    }
    return s;
}

int pads_poly_ccw(double (*v)[2], int n)
{
    double a2, scale = 0.0;
    int sgn = 0;
    if (n < 3) return 0;
    for (int i = 0; i < n; i++) {
        if (!isfinite(v[i][0]) || !isfinite(v[i][1])) return 0;
        scale = fmax(scale, fmax(fabs(v[i][0]), fabs(v[i][1])));
    }
    if (!(scale > 0.0)) return 0;
    /* every turn the same way, none flat or doubled back (to rounding of
     * the polygon's size) */
    for (int i = 0; i < n; i++) {
        const double *p = v[i], *q = v[(i + 1) % n], *r = v[(i + 2) % n];
        double cr = (q[0] - p[0]) * (r[1] - q[1]) - (q[1] - p[1]) * (r[0] - q[0]);
        int s = cr > 1e-12 * scale * scale ? 1 : cr < -1e-12 * scale * scale ? -1 : 0;
        if (s == 0 || (sgn && s != sgn)) return 0;
        sgn = s;
    }
    /* turning the same way, the edges wind once (a star polygon winds more) */
    {
        double turn = 0.0;
        for (int i = 0; i < n; i++) {
            const double *p = v[i], *q = v[(i + 1) % n], *r = v[(i + 2) % n];
            double a1 = atan2(q[1] - p[1], q[0] - p[0]), a2b = atan2(r[1] - q[1], r[0] - q[0]), d = a2b - a1;
            while (d > EXDEX_PI) d -= 2 * EXDEX_PI;
            while (d < -EXDEX_PI) d += 2 * EXDEX_PI;
            turn += d;
        }
        if (fabs(fabs(turn) - 2 * EXDEX_PI) > 1e-6) return 0;
    }
    a2 = pads_signed_area2((const double (*)[2])v, n);
    if (a2 < 0.0)
        for (int i = 0, j = n - 1; i < j; i++, j--) {
            double x = v[i][0], y = v[i][1];
            v[i][0] = v[j][0];
            v[i][1] = v[j][1];
            v[j][0] = x;
            v[j][1] = y;
        }
    return 1;
}

void pads_disc_poly(const double c[2], double r, double (*out)[2])
{
    const int N = PADS_DISC_N;
    /* equal area: N/2 R'^2 sin(2 pi / N) = pi r^2 */
    double rr = r * sqrt(2.0 * EXDEX_PI / (N * sin(2.0 * EXDEX_PI / N)));
    for (int i = 0; i < N; i++) {
        double a = 2.0 * EXDEX_PI * i / N;
        out[i][0] = c[0] + rr * cos(a);
        out[i][1] = c[1] + rr * sin(a);
    }
}

int pads_clip(const double (*s)[2], int ns, const double (*k)[2], int nk, double (*out)[2])
{
    /* a pass over one edge adds at most one vertex to a convex polygon;
     * rounding of a nearly flat one may add more: room for twice the
     * bound, and each pass is cut there */
    double A[2 * PADS_MAX_REGION][2], Bv[2 * PADS_MAX_REGION][2];
    double (*in)[2] = A, (*o)[2] = Bv;
    int n = ns, cap = 2 * PADS_MAX_REGION;
    if (ns > PADS_MAX_REGION || nk > PADS_MAX_REGION) return 0;
    memcpy(A, s, (size_t)ns * sizeof A[0]);
    for (int e = 0; e < nk && n > 0; e++) {
        const double *p = k[e], *q = k[e + 1 == nk ? 0 : e + 1];
        double ex = q[0] - p[0], ey = q[1] - p[1];
        int m = 0;
        for (int i = 0; i < n && m < cap - 1; i++) {
            const double *a = in[i], *b = in[i + 1 == n ? 0 : i + 1];
            /* inside: left of the edge p -> q (ccw clip polygon) */
            double da = ex * (a[1] - p[1]) - ey * (a[0] - p[0]);
            double db = ex * (b[1] - p[1]) - ey * (b[0] - p[0]);
            if (da >= 0.0) {
                o[m][0] = a[0];
                o[m][1] = a[1];
                m++;
            }
            if ((da >= 0.0) != (db >= 0.0)) {
                double t = da / (da - db);
                o[m][0] = a[0] + t * (b[0] - a[0]);
                o[m][1] = a[1] + t * (b[1] - a[1]);
                m++;
            }
        }
        {
            double (*tmp)[2] = in;
            in = o;
            o = tmp;
        }
        n = m;
        /* a convex clip of convex polygons keeps at most ns + nk vertices */
        if (n > PADS_MAX_REGION) n = PADS_MAX_REGION;
    }
    /* drop vertices repeated by the clipping (a vertex on an edge) */
    {
        int m = 0;
        for (int i = 0; i < n; i++) {
            const double *a = in[i], *b = m ? out[m - 1] : NULL;
            if (b && a[0] == b[0] && a[1] == b[1]) continue;
            out[m][0] = a[0];
            out[m][1] = a[1];
            m++;
        }
        while (m > 1 && out[0][0] == out[m - 1][0] && out[0][1] == out[m - 1][1]) m--;
        n = m;
    }
    return n;
}

void pads_poly_props(const double (*v)[2], int n, double *area, double c[2], double *er)
{
    region rg;
    *area = 0.0;
    c[0] = c[1] = 0.0;
    *er = 0.0;
    if (n < 3 || n > REGION_MAX_VERTICES) return;
    rg.kind = REGION_POLYGON;
    rg.n = n;
    memcpy(rg.v, v, (size_t)n * sizeof rg.v[0]);
    if (region_check(&rg) != EXDEX_OK) return;
    *area = region_area(&rg);
    region_centroid(&rg, c);
    *er = region_mean_distance(&rg, c);
}

static void region_disc(const double c[2], double r, pads_region *out)
{
    out->n = 0;
    out->disc = 1;
    out->r = r;
    out->area = EXDEX_PI * r * r;
    out->c[0] = c[0];
    out->c[1] = c[1];
    out->er = exdex_er_disc(r);
}

static void region_poly(const double (*v)[2], int n, pads_region *out)
{
    out->disc = 0;
    out->r = 0.0;
    out->n = n;
    if (n >= 3) {
        memcpy(out->v, v, (size_t)n * sizeof out->v[0]);
        pads_poly_props((const double (*)[2])out->v, n, &out->area, out->c, &out->er);
    } else {
        out->n = 0;
        out->area = 0.0;
        out->c[0] = out->c[1] = 0.0;
        out->er = 0.0;
    }
    if (!(out->area > 0.0)) {
        out->n = 0;
        out->area = 0.0;
    }
}

/* disc (c, r) against the ccw polygon p (n): the region */
static void disc_poly(const double c[2], double r, const double (*p)[2], int n, pads_region *out)
{
    double dmin = INFINITY, vmax = 0.0, dv[PADS_DISC_N][2], tmp[PADS_MAX_REGION][2];
    for (int e = 0; e < n; e++) {
        const double *a = p[e], *b = p[e + 1 == n ? 0 : e + 1];
        double ex = b[0] - a[0], ey = b[1] - a[1], len = hypot(ex, ey);
        /* signed distance of the centre inside the edge's half-plane */
        double d = (ex * (c[1] - a[1]) - ey * (c[0] - a[0])) / len;
        dmin = fmin(dmin, d);
        vmax = fmax(vmax, hypot(a[0] - c[0], a[1] - c[1]));
    }
    if (dmin >= r) {
        region_disc(c, r, out);
        return;
    }
    if (dmin <= -r) {
        region_poly(NULL, 0, out);
        return;
    }
    if (vmax <= r) {
        region_poly(p, n, out);
        return;
    }
    pads_disc_poly(c, r, dv);
    region_poly((const double (*)[2])tmp, pads_clip((const double (*)[2])dv, PADS_DISC_N, p, n, tmp), out);
}

void pads_intersect(const pads_shape *a, const pads_shape *b, pads_region *out)
{
    double tmp[PADS_MAX_REGION][2];
    memset(out, 0, sizeof *out);
    if (a->n == 0 && b->n == 0) {
        double d = hypot(a->c[0] - b->c[0], a->c[1] - b->c[1]);
        if (d + a->r <= b->r) {
            region_disc(a->c, a->r, out);
        } else if (d + b->r <= a->r) {
            region_disc(b->c, b->r, out);
        } else if (d >= a->r + b->r) {
            region_poly(NULL, 0, out);
        } else {
            double pa[PADS_DISC_N][2], pb[PADS_DISC_N][2];
            pads_disc_poly(a->c, a->r, pa);
            pads_disc_poly(b->c, b->r, pb);
            region_poly((const double (*)[2])tmp,
                        pads_clip((const double (*)[2])pa, PADS_DISC_N, (const double (*)[2])pb, PADS_DISC_N, tmp), out);
        }
        return;
    }
    if (a->n == 0) {
        disc_poly(a->c, a->r, (const double (*)[2])b->v, b->n, out);
        return;
    }
    if (b->n == 0) {
        disc_poly(b->c, b->r, (const double (*)[2])a->v, a->n, out);
        return;
    }
    region_poly((const double (*)[2])tmp, pads_clip((const double (*)[2])a->v, a->n, (const double (*)[2])b->v, b->n, tmp),
                out);
}
