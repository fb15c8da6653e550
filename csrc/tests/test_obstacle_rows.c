/* test_obstacle_rows.c -- obstacle_rows.c: the row codes, and the rows of a
 * box obstacle against a square object at a known pose against hand
 * geometry.
 *
 * The scene: B = A (the plate plane is A's x-y plane), a square of half
 * side S, planar coordinates q = (x, y, theta); the obstacle a box
 * |x| <= 0.1, TOP - H <= y <= TOP, |z| <= 0.05 (faces 2 i + s: normal
 * +-e_i). Its section by the plane is the rectangle of corners (+-0.1, TOP)
 * and (+-0.1, TOP - H). By hand:
 *   vertex row of corner c_j (in C): its world point p = r + Rz(theta) c_j
 *     is inside the obstacle's side and bottom slabs by far, so its largest
 *     face distance is the top face's, gap = p_y - TOP, feature face 2;
 *     d gap / d q = (0, 1, (d/dtheta Rz c_j)_y) = (0, 1, cos th cx - sin th cy);
 *   section row of a corner P of the rectangle: P in C, u = Rz(-theta) (P - r),
 *     against the square's edges: the largest edge distance
 *     max(|u_x|, |u_y|) - S. */
#include "check.h"
#include "hybrid_scene.h"
#include "../model.h"
#include "../obstacle_rows.h"
#include "../contact.h"

#include <math.h>
#include <string.h>

#define S 0.02
#define TOP -0.03
#define H 0.05
#define TH 0.1

static exdex_scene_def box_def(void)
{
    exdex_scene_def d = scene_plate_box(2 * S, 2 * S, 0.0, 0.1);
    memset(d.inertia, 0, sizeof d.inertia);
    d.inertia[0] = d.inertia[4] = 1e-5;
    d.inertia[8] = 0.1 * (2 * S) * (2 * S) / 6.0;
    /* lowest corner 1 mm above the top face */
    d.q0[0] = 0.01;
    d.q0[1] = TOP + S * (cos(TH) + sin(TH)) + 1e-3;
    d.q0[2] = TH;
    scene_obstacle_box(&d, 0, (const double[3]){0.0, TOP - H / 2, 0.0}, (const double[3]){0.1, H / 2, 0.05});
    d.method = EXDEX_METHOD_EVENT;
    return d;
}

/* The code packs (o, kind, a, b, feat) and the accessors unpack them. */
EXDEX_TEST(obstacle_rows_code_round_trip)
{
    for (int o = 0; o < EXDEX_MAX_OBSTACLES; o++)
        for (int kind = 0; kind < 3; kind++)
            for (int a = 0; a < 32; a += 7)
                for (int b = 0; b < 32; b += 5)
                    for (int f = 0; f < 64; f += 9) {
                        int c = orow_code(o, kind, a, b, f);
                        ENSURE(c >= 0);
                        ENSURE(orow_obst(c) == o && orow_kind(c) == kind && orow_a(c) == a && orow_b(c) == b &&
                               orow_feat(c) == f);
                        ENSURE(orow_pair(c) == orow_pair(orow_code(o, kind, a, b, 63 - f)));
                    }
}

EXDEX_TEST(obstacle_rows_box_against_square_by_hand)
{
    exdex_scene_def d = box_def();
    const double cth = cos(TH), sth = sin(TH);
    int status, code[64], n, nv = 0, ns = 0;
    const char *bad = NULL;
    double gap[64], q[3] = {d.q0[0], d.q0[1], d.q0[2]}, sec_ref[4], sec_got[4];
    frame f;
    exdex_kinematics kin;
    exdex_model *m = exdex_model_alloc(&d, &status, &bad);
    ENSURE(m != NULL);
    if (!m) {
        printf("    alloc: %s (%s)\n", exdex_strerror(status), bad ? bad : "");
        return;
    }
    ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
    n = orow_all(m, &kin, q, NULL, 1, code, gap);
    ENSURE(n == 8 && n <= contact_obstacle_max_rows(m));
    for (int i = 0; i < n; i++) {
        ENSURE(orow_valid(m, code[i]));
        ENSURE(orow_obst(code[i]) == 0);
        if (orow_kind(code[i]) == OROW_VERTEX) {
            int j = orow_a(code[i]);
            double cx = d.vertices[j][0], cy = d.vertices[j][1];
            double py = q[1] + sth * cx + cth * cy, G[3], gd;
            ENSURE(j == nv);   /* outline vertices in order */
            nv++;
            ENSURE(orow_feat(code[i]) == 2);
            ENSURE_CLOSE(gap[i], py - TOP, 1e-15);
            ENSURE_CLOSE(orow_planar(m, &kin, code[i], q, (const double[3]){0.0, 0.0, 0.0}, G, &gd, NULL),
                         py - TOP, 1e-15);
            ENSURE_SMALL(G[0], 1e-15);
            ENSURE_CLOSE(G[1], 1.0, 1e-15);
            ENSURE_CLOSE(G[2], cth * cx - sth * cy, 1e-15);
            ENSURE_SMALL(gd, 0.0);
        } else if (orow_kind(code[i]) == OROW_SECTION && ns < 4) {
            ENSURE(nv == 4);   /* section rows after the outline's */
            sec_got[ns++] = gap[i];
        }
    }
    ENSURE(nv == 4 && ns == 4);
    {
        const double P[4][2] = {{0.1, TOP}, {-0.1, TOP}, {0.1, TOP - H}, {-0.1, TOP - H}};
        for (int k = 0; k < 4; k++) {
            double dx = P[k][0] - q[0], dy = P[k][1] - q[1];
            double ux = cth * dx + sth * dy, uy = -sth * dx + cth * dy;
            sec_ref[k] = fmax(fabs(ux), fabs(uy)) - S;
        }
        /* as sets: sort both (4 values) */
        for (int a = 0; a < 4; a++)
            for (int b = a + 1; b < 4; b++) {
                if (sec_ref[b] < sec_ref[a]) { double t = sec_ref[a]; sec_ref[a] = sec_ref[b]; sec_ref[b] = t; }
                if (sec_got[b] < sec_got[a]) { double t = sec_got[a]; sec_got[a] = sec_got[b]; sec_got[b] = t; }
            }
        for (int k = 0; k < 4 && ns == 4; k++) ENSURE_CLOSE(sec_got[k], sec_ref[k], 1e-15);
    }
    ENSURE(!orow_valid(m, orow_code(1, OROW_VERTEX, 0, 0, 2)));   /* one obstacle only */
    ENSURE(!orow_valid(m, orow_code(0, OROW_VERTEX, 4, 0, 2)));   /* four outline vertices */
    ENSURE(!orow_valid(m, orow_code(0, OROW_VERTEX, 0, 0, 6)));   /* six faces */
    exdex_model_free(m);
}

/* The contract of obstacle_rows.h: orow_all's gaps (without velocities,
 * planar = 0) are contact_obstacle_rows' gaps, bit for bit, row for row in
 * the outline vertices' order and the rod's row, as a set for a polytope's
 * section vertices (contact_obstacle_rows takes them counter-clockwise);
 * the same count. Random poses of the square above, beside and inside
 * the box, the box turned at random, and a tilted rod in place of it. */
static double lcg(unsigned long *s)
{
    *s = *s * 6364136223846793005UL + 1442695040888963407UL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static void sort_up(double *x, int n)
{
    for (int a = 0; a < n; a++)
        for (int b = a + 1; b < n; b++)
            if (x[b] < x[a]) { double t = x[a]; x[a] = x[b]; x[b] = t; }
}

EXDEX_TEST(obstacle_rows_gaps_are_contact_obstacle_rows_bit_for_bit)
{
    unsigned long seed = 12345;
    int checked = 0, rods = 0, sections = 0;
    for (int trial = 0; trial < 400; trial++) {
        exdex_scene_def d = box_def();
        int status, code[MAX_ROWS], n, no;
        const char *bad = NULL;
        double gap[MAX_ROWS], G[MAX_ROWS][3], g[MAX_ROWS], rnd[MAX_ROWS], q[3];
        frame f;
        exdex_kinematics kin;
        exdex_model *m;
        if (trial % 4 == 3) {
            /* a rod tilted in the plate's x-z plane and turned about z */
            double tilt = 1.2 * (lcg(&seed) - 0.5), turn = 6.283185307179586 * lcg(&seed);
            exdex_obstacle_def *o = &d.obstacles[0];
            memset(o, 0, sizeof *o);
            o->kind = EXDEX_OBSTACLE_CYLINDER;
            o->center[0] = 0.04 * (lcg(&seed) - 0.5);
            o->center[1] = TOP + 0.04 * (lcg(&seed) - 0.5);
            o->axis[0] = sin(tilt) * cos(turn);
            o->axis[1] = sin(tilt) * sin(turn);
            o->axis[2] = cos(tilt);
            o->radius = 0.005 + 0.01 * lcg(&seed);
        } else {
            /* the box turned about a random axis by up to 0.6 rad: rotate its normals and points */
            double ax[3] = {lcg(&seed) - 0.5, lcg(&seed) - 0.5, lcg(&seed) - 0.5}, an = 0.6 * lcg(&seed), len, R[9];
            len = sqrt(ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]);
            for (int i = 0; i < 3; i++) ax[i] /= len;
            {
                double c = cos(an), s = sin(an), t = 1.0 - c, x = ax[0], y = ax[1], z = ax[2];
                double Rr[9] = {t * x * x + c, t * x * y - s * z, t * x * z + s * y,
                                t * x * y + s * z, t * y * y + c, t * y * z - s * x,
                                t * x * z - s * y, t * y * z + s * x, t * z * z + c};
                memcpy(R, Rr, sizeof R);
            }
            for (int fc = 0; fc < d.obstacles[0].n_faces; fc++) {
                double n0[3], p0[3];
                memcpy(n0, d.obstacles[0].face_normal[fc], sizeof n0);
                memcpy(p0, d.obstacles[0].face_point[fc], sizeof p0);
                p0[1] -= TOP;   /* about the top face's middle */
                for (int i = 0; i < 3; i++) {
                    d.obstacles[0].face_normal[fc][i] = R[3 * i] * n0[0] + R[3 * i + 1] * n0[1] + R[3 * i + 2] * n0[2];
                    d.obstacles[0].face_point[fc][i] = R[3 * i] * p0[0] + R[3 * i + 1] * p0[1] + R[3 * i + 2] * p0[2];
                }
                d.obstacles[0].face_point[fc][1] += TOP;
            }
        }
        d.q0[0] = 0.0;   /* the start well clear of the obstacle (the model checks it) */
        d.q0[1] = 1.0;
        m = exdex_model_alloc(&d, &status, &bad);
        ENSURE(m != NULL);
        if (!m) {
            printf("    trial %d: %s (%s)\n", trial, exdex_strerror(status), bad ? bad : "");
            continue;
        }
        ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
        q[0] = 0.16 * (lcg(&seed) - 0.5);
        q[1] = TOP + 0.08 * (lcg(&seed) - 0.5);
        q[2] = 6.283185307179586 * lcg(&seed);
        n = orow_all(m, &kin, q, NULL, 0, code, gap);
        no = contact_obstacle_rows(m, &kin, q, G, g, rnd, NULL, NULL);
        ENSURE(n == no);
        if (n == no) {
            double a[MAX_ROWS], b[MAX_ROWS];
            int ns = 0;
            for (int i = 0; i < n; i++) {
                if (orow_kind(code[i]) == OROW_SECTION) {
                    a[ns] = gap[i];
                    b[ns++] = g[i];
                    continue;
                }
                if (orow_kind(code[i]) == OROW_ROD) rods++;
                ENSURE(gap[i] == g[i]);
                if (gap[i] != g[i]) printf("    trial %d row %d: %.17g != %.17g\n", trial, i, gap[i], g[i]);
            }
            sort_up(a, ns);
            sort_up(b, ns);
            for (int i = 0; i < ns; i++) ENSURE(a[i] == b[i]);
            sections += ns;
            checked++;
        }
        exdex_model_free(m);
    }
    ENSURE(checked == 400 && rods == 100 && sections > 100);
}
