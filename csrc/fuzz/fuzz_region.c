/* fuzz_region.c -- the contact region's integrals (region.h, a private
 * header of the core): random polygons (3 .. 12 decoded vertices, convex or
 * not, either orientation) and discs, at a decoded point.
 *
 * Checks: no crash, no hang; region_check accepts only finite convex
 * counter-clockwise polygons of positive area and finite discs of positive
 * radius; for an accepted region and a finite point: finite integrals,
 * F >= A |centroid - c| (Jensen: the mean distance is at least the distance
 * of the mean) and F <= A reach, |G| <= A, Phi >= 0, trace H = Phi and H positive semi-definite, each to the rounding of the
 * integrals' scale. */
#include "fuzz.h"
#include "../region.h"

#include <math.h>

#define T "region"

int fuzz_region(const uint8_t *data, size_t size)
{
    fz f;
    region rg;
    region_moments mo;
    double c[2];
    fz_init(&f, data, size);
    rg.kind = fz_pick(&f, 0, 3) == 0 ? REGION_DISC : REGION_POLYGON;
    if (rg.kind == REGION_DISC) {
        rg.c[0] = fz_num(&f, -1.0, 1.0);
        rg.c[1] = fz_num(&f, -1.0, 1.0);
        rg.r = fz_log(&f, 1e-3, 10.0);
        rg.n = 0;
    } else {
        rg.n = fz_pick(&f, 3, 12);
        int regular = fz_pick(&f, 0, 1);
        double rad = fz_log(&f, 1e-3, 10.0), ph = fz_num(&f, 0.0, 6.283185307179586);
        for (int i = 0; i < rg.n; i++) {
            if (regular) {
                /* a convex polygon (with a decoded wobble of the radius) */
                double a = ph + 6.283185307179586 * i / rg.n, w = 1.0 + fz_num(&f, 0.0, 0.3);
                rg.v[i][0] = rad * w * cos(a), rg.v[i][1] = rad * w * sin(a);
            } else {
                rg.v[i][0] = fz_num(&f, -1.0, 1.0);
                rg.v[i][1] = fz_num(&f, -1.0, 1.0);
            }
        }
    }
    c[0] = fz_num(&f, -5.0, 5.0);
    c[1] = fz_num(&f, -5.0, 5.0);
    int finite = f.nonfinite == 0;
    int st = region_check(&rg);
    fuzz_count_status(T, st);
    FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL);
    if (!finite && rg.kind == REGION_DISC && !(isfinite(rg.c[0]) && isfinite(rg.c[1]) && isfinite(rg.r)))
        FZ_CHECK(T, st == EXDEX_EINVAL);
    if (st != EXDEX_OK) return 0;
    if (rg.kind == REGION_POLYGON) {
        /* an accepted polygon is convex and counter-clockwise: every vertex
         * on the left of (or on) every edge line, to rounding */
        double sz = 0.0;
        for (int i = 0; i < rg.n; i++) sz = fmax(sz, fmax(fabs(rg.v[i][0]), fabs(rg.v[i][1])));
        for (int i = 0; i < rg.n; i++) {
            const double *p = rg.v[i], *q = rg.v[(i + 1) % rg.n];
            for (int j = 0; j < rg.n; j++) {
                double cr = (q[0] - p[0]) * (rg.v[j][1] - p[1]) - (q[1] - p[1]) * (rg.v[j][0] - p[0]);
                FZ_EXTREME(T, &f, cr >= -1e-9 * sz * sz);
            }
        }
    }
    st = region_moments_at(&rg, c, &mo);
    FZ_CHECK(T, st == (isfinite(c[0]) && isfinite(c[1]) ? EXDEX_OK : EXDEX_EINVAL));
    if (st != EXDEX_OK) return 0;
    double A = region_area(&rg), g[2], reach = region_reach(&rg, c);
    region_centroid(&rg, g);
    double dist = hypot(g[0] - c[0], g[1] - c[1]);
    int fin = isfinite(mo.dist) && isfinite(mo.dir[0]) && isfinite(mo.dir[1]) && isfinite(mo.inv);
    FZ_EXTREME(T, &f, fin && A > 0.0);
    if (!fin) return 0;
    double tol = 1e-9 * (1.0 + reach / sqrt(A));
    FZ_EXTREME(T, &f, mo.dist >= A * dist * (1.0 - tol) - 1e-300);
    FZ_EXTREME(T, &f, mo.dist <= A * reach * (1.0 + tol) + 1e-300);
    FZ_EXTREME(T, &f, hypot(mo.dir[0], mo.dir[1]) <= A * (1.0 + tol) + 1e-300);
    FZ_EXTREME(T, &f, mo.inv >= -tol * A / reach);
    {
        FZ_EXTREME(T, &f, isfinite(mo.dyad[0]) && isfinite(mo.dyad[1]) && isfinite(mo.dyad[2]));
        /* H of a far point is a small difference (Phi - |G| / |c|, ...):
         * its rounding grows like (reach^2 / A) */
        double sc = fabs(mo.inv) + A / reach, q = reach * reach / A, ht = 1e-10 * (1.0 + q);
        FZ_EXTREME(T, &f, fabs(mo.dyad[0] + mo.dyad[2] - mo.inv) <= ht * sc);
        FZ_EXTREME(T, &f, mo.dyad[0] >= -ht * sc && mo.dyad[2] >= -ht * sc);
        FZ_EXTREME(T, &f, mo.dyad[0] * mo.dyad[2] - mo.dyad[1] * mo.dyad[1] >= -ht * sc * sc);
    }
    return 0;
}
