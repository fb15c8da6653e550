/* test_obstacle_rows.c -- obstacle_rows.c: the row codes, the rows of a
 * box obstacle against a square object at a known pose against hand
 * geometry, and a disc's rod row held (orow_planar, orow_point) against
 * the builder's (contact_obstacle_build, contact.c's tests).
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

/* Why a disc's rim point nearest a rod is xc + r u with u the minimiser
 * contact_circle_min returns, in the builder and in the rows with their
 * feature held (not the point at the angle atan2(u), whose cosine and sine
 * differ from u in the last bits): the row the event method holds
 * (orow_planar, its jets started at u) and its guard's gap (orow_all, the
 * builder) are then the same number at the same state, so the switch of
 * the contact set and the row's root agree; and the point orow_point gives
 * the friction is the steppers' (contact_obstacle_rows). Random rods tilted
 * up to 0.6 rad (elliptic sections, u off the line of centres) beside the
 * disc of radius 0.02: bit for bit. */
static double lcg(unsigned long *s)
{
    *s = *s * 6364136223846793005UL + 1442695040888963407UL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

EXDEX_TEST(obstacle_rows_disc_rim_point_is_the_builders_bit_for_bit)
{
    unsigned long seed = 2024;
    int checked = 0;
    for (int trial = 0; trial < 200; trial++) {
        exdex_scene_def d = exdex_default_scene_def();
        double tilt = 1.2 * (lcg(&seed) - 0.5), turn = 6.283185307179586 * lcg(&seed);
        double ang = 6.283185307179586 * lcg(&seed);
        double rr = 0.005 + 0.01 * lcg(&seed), dist = 0.02 + rr + 0.002 + 0.02 * lcg(&seed), zero[3] = {0, 0, 0};
        double q[3] = {0.0, 0.0, 6.283185307179586 * lcg(&seed)}, gap[4], G[4][3], g[4], rnd[4], Gh[3];
        int status, code[4], n;
        const char *bad = NULL;
        exdex_obstacle_def *o = &d.obstacles[0];
        contact_point cp[4], cph;
        frame f;
        exdex_kinematics kin;
        exdex_model *m;
        d.dof = EXDEX_DOF_PLANAR;
        memset(d.R0, 0, sizeof d.R0);
        d.R0[0] = d.R0[4] = d.R0[8] = 1.0;
        d.n_vertices = 0;
        d.disc_radius = 0.02;
        d.n_obstacles = 1;
        memset(o, 0, sizeof *o);
        o->kind = EXDEX_OBSTACLE_CYLINDER;
        /* the axis meets the plate plane at distance dist from the origin, outside the disc */
        o->axis[0] = sin(tilt) * cos(turn);
        o->axis[1] = sin(tilt) * sin(turn);
        o->axis[2] = cos(tilt);
        o->center[0] = dist * cos(ang);
        o->center[1] = dist * sin(ang);
        o->radius = rr;
        d.q0[0] = -o->center[0];
        d.q0[1] = -o->center[1];
        m = exdex_model_alloc(&d, &status, &bad);
        ENSURE(m != NULL);
        if (!m) {
            printf("    trial %d: %s (%s)\n", trial, exdex_strerror(status), bad ? bad : "");
            continue;
        }
        ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
        n = orow_all(m, &kin, q, NULL, 1, code, gap);
        ENSURE(n == 1 && contact_obstacle_rows(m, &kin, q, G, g, rnd, NULL, cp) == 1);
        if (n == 1) {
            ENSURE(orow_kind(code[0]) == OROW_ROD);
            ENSURE(orow_planar(m, &kin, code[0], q, zero, Gh, NULL, NULL) == gap[0]);
            ENSURE(gap[0] == g[0]);
            orow_point(m, &kin, code[0], q, &cph);
            ENSURE(cph.x[0] == cp[0].x[0] && cph.x[1] == cp[0].x[1]);
            checked++;
        }
        exdex_model_free(m);
    }
    ENSURE(checked == 200);
}
