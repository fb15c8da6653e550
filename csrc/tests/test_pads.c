/* test_pads.c -- the contact region of pads on the fingers (pads.c) and
 * its use by the methods.
 *
 * References, test by test:
 *   edge crossing   a square pad under a rectangle face whose edge crosses
 *                   it: the region is the rectangle [e, a] x [-a, a] (hand
 *                   derived), area 2 a (a - e), centroid (e + a) / 2, and
 *                   e_r the rectangle's (Howe and Cutkosky's closed form,
 *                   exdex_er_rectangle).
 *   turned face     a square face turned over a square pad: area, centroid
 *                   and mean distance against a brute-force grid (each cell
 *                   centre tested against both shapes' half-planes).
 *   disc segment    a disc pad under a polygon edge: the circular segment's
 *                   area R^2 acos(d/R) - d sqrt(R^2 - d^2) and centroid
 *                   2 (R^2 - d^2)^(3/2) / (3 A), to the stated 32-gon bound.
 *   containment     a disc inside the face is exact (e_r = 2R/3); a face
 *                   beyond the pad leaves no region.
 *   translation     a 1-DoF translation with pads on the fingers is the
 *                   patch's run sample for sample (mu N whatever the region)
 *                   until the face leaves the pad, where the run stops.
 */
#include "check.h"
#include "../exdex.h"
#include "../pads.h"

#include <math.h>
#include <string.h>

static void square(pads_shape *s, double a, double cx, double cy)
{
    memset(s, 0, sizeof *s);
    s->n = 4;
    s->v[0][0] = cx - a, s->v[0][1] = cy - a;
    s->v[1][0] = cx + a, s->v[1][1] = cy - a;
    s->v[2][0] = cx + a, s->v[2][1] = cy + a;
    s->v[3][0] = cx - a, s->v[3][1] = cy + a;
}

EXDEX_TEST(pads_edge_crossing_rectangle)
{
    const double a = 0.01;
    for (int k = 0; k <= 20; k++) {
        /* face [e, e + 0.2] x [-0.05, 0.05]: its left edge at e crosses the pad */
        double e = -a + 2 * a * (k + 0.5) / 21.0;
        pads_shape pad, face;
        pads_region rg;
        square(&pad, a, 0.0, 0.0);
        memset(&face, 0, sizeof face);
        face.n = 4;
        face.v[0][0] = e, face.v[0][1] = -0.05;
        face.v[1][0] = e + 0.2, face.v[1][1] = -0.05;
        face.v[2][0] = e + 0.2, face.v[2][1] = 0.05;
        face.v[3][0] = e, face.v[3][1] = 0.05;
        pads_intersect(&pad, &face, &rg);
        ENSURE_CLOSE(rg.area, 2 * a * (a - e), 1e-15);
        ENSURE_CLOSE(rg.c[0], 0.5 * (e + a), 1e-15);
        ENSURE_SMALL(rg.c[1], 1e-15);
        ENSURE_CLOSE(rg.er, exdex_er_rectangle(0.5 * (a - e), a), 1e-14);
    }
}

static int inside_poly(const double (*v)[2], int n, double x, double y)
{
    for (int i = 0; i < n; i++) {
        const double *p = v[i], *q = v[(i + 1) % n];
        if ((q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]) < 0) return 0;
    }
    return 1;
}

EXDEX_TEST(pads_turned_face_against_grid)
{
    const double a = 0.01;
    const double poses[4][3] = {{0.012, 0.004, 0.3}, {-0.009, 0.011, 0.8}, {0.0, -0.013, 1.2}, {0.015, 0.015, 0.1}};
    for (int p = 0; p < 4; p++) {
        pads_shape pad, face;
        pads_region rg;
        double c = cos(poses[p][2]), s = sin(poses[p][2]), A = 0, cx = 0, cy = 0, F = 0;
        const int N = 800;
        const double h = 2 * a / N;
        square(&pad, a, 0.0, 0.0);
        square(&face, a, 0.0, 0.0);
        for (int i = 0; i < 4; i++) {
            double x = face.v[i][0], y = face.v[i][1];
            face.v[i][0] = poses[p][0] + c * x - s * y;
            face.v[i][1] = poses[p][1] + s * x + c * y;
        }
        pads_intersect(&pad, &face, &rg);
        for (int i = 0; i < N; i++)
            for (int j = 0; j < N; j++) {
                double x = -a + (i + 0.5) * h, y = -a + (j + 0.5) * h;
                if (!inside_poly((const double (*)[2])face.v, 4, x, y)) continue;
                A += h * h;
                cx += x * h * h;
                cy += y * h * h;
            }
        cx /= A;
        cy /= A;
        for (int i = 0; i < N; i++)
            for (int j = 0; j < N; j++) {
                double x = -a + (i + 0.5) * h, y = -a + (j + 0.5) * h;
                if (inside_poly((const double (*)[2])face.v, 4, x, y)) F += hypot(x - cx, y - cy) * h * h;
            }
        /* the grid's error: the boundary cells, ~ perimeter h / area */
        ENSURE(rg.area > 0.0);
        ENSURE_CLOSE(rg.area, A, 4e-3 * A);
        ENSURE_CLOSE(rg.c[0], cx, 4e-3 * a);
        ENSURE_CLOSE(rg.c[1], cy, 4e-3 * a);
        ENSURE_CLOSE(rg.er, F / A, 4e-3 * a);
    }
}

EXDEX_TEST(pads_disc_under_edge_segment)
{
    const double R = 0.01;
    for (int k = 0; k < 9; k++) {
        /* the face x >= d (a large square), the disc pad about the origin */
        double d = -0.8 * R + 1.6 * R * k / 8.0;
        pads_shape pad, face;
        pads_region rg;
        double A, xc;
        memset(&pad, 0, sizeof pad);
        pad.r = R;
        square(&face, 0.5, d + 0.5, 0.0);
        pads_intersect(&pad, &face, &rg);
        A = R * R * acos(d / R) - d * sqrt(R * R - d * d);
        xc = 2 * pow(R * R - d * d, 1.5) / (3 * A);
        ENSURE_CLOSE(rg.area, A, 1e-2 * A);
        ENSURE_CLOSE(rg.c[0], xc, 3.3e-3 * R);
        ENSURE_SMALL(rg.c[1], 3.3e-3 * R);
    }
}

EXDEX_TEST(pads_containment_and_empty)
{
    pads_shape pad, face;
    pads_region rg;
    memset(&pad, 0, sizeof pad);
    pad.r = 0.01;
    pad.c[0] = 0.003;
    square(&face, 0.05, 0.0, 0.0);
    pads_intersect(&pad, &face, &rg);
    ENSURE(rg.disc == 1);
    ENSURE(rg.er == exdex_er_disc(0.01));
    ENSURE_CLOSE(rg.c[0], 0.003, 0.0);
    /* the face beyond the pad */
    square(&face, 0.05, 0.07, 0.0);
    pads_intersect(&pad, &face, &rg);
    ENSURE(rg.area == 0.0);
    square(&pad, 0.01, 0.0, 0.0);
    square(&face, 0.05, 0.0601, 0.0);
    pads_intersect(&pad, &face, &rg);
    ENSURE(rg.area == 0.0);
}

EXDEX_TEST(pads_polygon_orientation_and_convexity)
{
    double cw[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    double star[5][2] = {{1, 0}, {-0.809, 0.588}, {0.309, -0.951}, {0.309, 0.951}, {-0.809, -0.588}};
    double dent[5][2] = {{0, 0}, {2, 0}, {2, 2}, {1, 0.5}, {0, 2}};
    ENSURE(pads_poly_ccw(cw, 4) == 1);
    ENSURE(pads_signed_area2((const double (*)[2])cw, 4) > 0.0);
    ENSURE(pads_poly_ccw(star, 5) == 0);
    ENSURE(pads_poly_ccw(dent, 5) == 0);
}

static exdex_scene_def slide_def(int pads)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = 0.1;
    d.mu = 0.3;
    d.grip_force = 1.0;
    d.dof = EXDEX_DOF_TRANSLATION;
    d.method = EXDEX_METHOD_IMPLICIT;
    /* gravity along B's y pulls it down the slide axis: 9.81 m/s^2 against 6 m/s^2 of friction */
    if (pads) {
        d.pad_n = 4;
        d.pad[0][0] = -0.01, d.pad[0][1] = -0.01;
        d.pad[1][0] = 0.01, d.pad[1][1] = -0.01;
        d.pad[2][0] = 0.01, d.pad[2][1] = 0.01;
        d.pad[3][0] = -0.01, d.pad[3][1] = 0.01;
        d.face_n = 4;
        d.face[0][0] = -0.02, d.face[0][1] = -0.05;
        d.face[1][0] = 0.02, d.face[1][1] = -0.05;
        d.face[2][0] = 0.02, d.face[2][1] = 0.05;
        d.face[3][0] = -0.02, d.face[3][1] = 0.05;
    }
    return d;
}

EXDEX_TEST(pads_translation_unaffected_until_lost)
{
    exdex_scene_def a = slide_def(0), b = slide_def(1);
    enum { N = 401 };
    static double t1[N], q1[N], v1[N], w1[3 * N], t2[N], q2[N], v2[N], w2[3 * N];
    static unsigned char s1[N], s2[N];
    exdex_trajectory A = {N, t1, q1, v1, w1, s1, NULL}, B = {N, t2, q2, v2, w2, s2, NULL};
    exdex_stats sa, sb;
    int st;
    exdex_model *ma = exdex_model_alloc(&a, &st, NULL), *mb = exdex_model_alloc(&b, &st, NULL);
    ENSURE(ma && mb);
    if (!ma || !mb) return;
    ENSURE(exdex_simulate(ma, 0.4, 0.001, &A, &sa) == EXDEX_OK);
    ENSURE(exdex_simulate(mb, 0.4, 0.001, &B, &sb) == EXDEX_OK);
    ENSURE(isnan(sa.lost_t) && sa.lost_sample == 0);
    /* the face (half-length 0.05 m along y) leaves the pad (half-size 0.01)
     * when it has slid 0.06 m: lost at the first sample beyond */
    ENSURE(sb.lost_sample > 0 && sb.lost_sample < N - 1);
    ENSURE(fabs(q2[sb.lost_sample]) >= 0.06 && fabs(q2[sb.lost_sample - 1]) < 0.06);
    ENSURE(sb.lost_t == t2[sb.lost_sample]);
    for (size_t i = 0; i <= sb.lost_sample; i++) ENSURE(q1[i] == q2[i] && v1[i] == v2[i]);
    exdex_model_free(ma);
    exdex_model_free(mb);
}

EXDEX_TEST(pads_bad_input_named)
{
    exdex_scene_def d = slide_def(1);
    const char *bad = NULL;
    int st;
    d.face[3][0] = 0.5;   /* no longer convex */
    d.face[3][1] = -0.2;
    ENSURE(exdex_model_alloc(&d, &st, &bad) == NULL && st == EXDEX_EINVAL && bad && !strcmp(bad, "face"));
    d = slide_def(1);
    d.pad_radius = 0.01;  /* both a polygon and a disc */
    ENSURE(exdex_model_alloc(&d, &st, &bad) == NULL && st == EXDEX_EINVAL && bad && !strcmp(bad, "pad_radius"));
    d = slide_def(1);
    d.q0[0] = 0.5;        /* no region at the start */
    ENSURE(exdex_model_alloc(&d, &st, &bad) == NULL && st == EXDEX_EINVAL && bad && !strcmp(bad, "pad"));
}
