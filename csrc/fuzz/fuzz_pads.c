/* fuzz_pads.c -- the pads' contact region (pads.h, a private header of the
 * core): a decoded pad and face (convex polygons of 3 .. 12 vertices with a
 * decoded wobble, or discs; sometimes arbitrary points), intersected.
 *
 * Checks: no crash, no hang; pads_poly_ccw accepts only polygons it leaves
 * counter-clockwise (positive signed area); for accepted finite shapes the
 * region is finite, its area at most the smaller shape's (to rounding), its
 * centroid inside both shapes' bounding boxes (to rounding), its e_r at
 * most the region's largest vertex distance from the centroid, and the
 * intersection is symmetric in its two arguments (same area to rounding). */
#include "fuzz.h"
#include "../pads.h"

#include <math.h>
#include <string.h>

#define T "pads"

static int shape(fz *f, pads_shape *s, double *area, double box[4])
{
    memset(s, 0, sizeof *s);
    if (fz_pick(f, 0, 3) == 0) {
        s->c[0] = fz_num(f, -1.0, 1.0);
        s->c[1] = fz_num(f, -1.0, 1.0);
        s->r = fz_log(f, 1e-3, 1.0);
        if (!(isfinite(s->c[0]) && isfinite(s->c[1]) && isfinite(s->r) && s->r > 0.0)) return 0;
        *area = 3.14159265358979323846 * s->r * s->r;
        /* the 32-gon of the disc's area reaches 1.0033 r */
        box[0] = s->c[0] - 1.0033 * s->r, box[1] = s->c[0] + 1.0033 * s->r;
        box[2] = s->c[1] - 1.0033 * s->r, box[3] = s->c[1] + 1.0033 * s->r;
        return 1;
    }
    s->n = fz_pick(f, 3, 12);
    {
        int regular = fz_pick(f, 0, 2) != 0;
        double rad = fz_log(f, 1e-3, 1.0), ph = fz_num(f, 0.0, 6.283185307179586);
        double cx = fz_num(f, -1.0, 1.0), cy = fz_num(f, -1.0, 1.0);
        for (int i = 0; i < s->n; i++) {
            if (regular) {
                double a = ph + 6.283185307179586 * i / s->n, w = 1.0 + fz_num(f, 0.0, 0.2);
                s->v[i][0] = cx + rad * w * cos(a), s->v[i][1] = cy + rad * w * sin(a);
            } else {
                s->v[i][0] = fz_num(f, -1.0, 1.0);
                s->v[i][1] = fz_num(f, -1.0, 1.0);
            }
        }
    }
    if (!pads_poly_ccw(s->v, s->n)) return 0;
    FZ_CHECK(T, pads_signed_area2((const double (*)[2])s->v, s->n) > 0.0);
    *area = 0.5 * pads_signed_area2((const double (*)[2])s->v, s->n);
    box[0] = box[2] = INFINITY;
    box[1] = box[3] = -INFINITY;
    for (int i = 0; i < s->n; i++) {
        box[0] = fmin(box[0], s->v[i][0]), box[1] = fmax(box[1], s->v[i][0]);
        box[2] = fmin(box[2], s->v[i][1]), box[3] = fmax(box[3], s->v[i][1]);
    }
    return 1;
}

int fuzz_pads(const uint8_t *data, size_t size)
{
    fz f;
    pads_shape a, b;
    pads_region r, r2;
    double Aa, Ab, ba[4], bb[4];
    fz_init(&f, data, size);
    if (!shape(&f, &a, &Aa, ba) || !shape(&f, &b, &Ab, bb)) return 0;
    pads_intersect(&a, &b, &r);
    pads_intersect(&b, &a, &r2);
    fuzz_count_status(T, r.area > 0.0 ? EXDEX_OK : EXDEX_EINVAL);
    FZ_CHECK(T, isfinite(r.area) && r.area >= 0.0);
    if (!(r.area > 0.0)) return 0;
    {
        double sc = fmax(fmax(fabs(ba[0]), fabs(ba[1])), fmax(fabs(bb[2]), fabs(bb[3])));
        double tol = 1e-9 * (sc + fmax(ba[1] - ba[0], bb[1] - bb[0]));
        FZ_EXTREME(T, &f, r.area <= fmin(Aa, Ab) * (1.0 + 2e-2) + 1e-300);
        FZ_EXTREME(T, &f, isfinite(r.c[0]) && isfinite(r.c[1]) && isfinite(r.er) && r.er > 0.0);
        FZ_EXTREME(T, &f, r.c[0] >= fmax(ba[0], bb[0]) - tol && r.c[0] <= fmin(ba[1], bb[1]) + tol);
        FZ_EXTREME(T, &f, r.c[1] >= fmax(ba[2], bb[2]) - tol && r.c[1] <= fmin(ba[3], bb[3]) + tol);
        if (!r.disc) {
            double reach = 0.0;
            for (int i = 0; i < r.n; i++) reach = fmax(reach, hypot(r.v[i][0] - r.c[0], r.v[i][1] - r.c[1]));
            FZ_EXTREME(T, &f, r.er <= reach * (1.0 + 1e-9));
        }
        FZ_EXTREME(T, &f, fabs(r.area - r2.area) <= 1e-9 * fmax(Aa, Ab) + 1e-300);
    }
    return 0;
}
