/* test_contact.c -- contact.c: plane geometry (hull, section vertices,
 * farthest line), the stops' vertex gaps and the obstacle rows of
 * contact_obstacle_build (gap, G, normal, point, feature; the tie rules;
 * the section rows' order), against hand geometry. */
#include "check.h"
#include "../contact.h"
#include "../model.h"

#include <float.h>
#include <math.h>
#include <string.h>

/* The unit square's corners among interior points and an edge midpoint:
 * the hull is the four corners, counter-clockwise (shoelace area +4). */
EXDEX_TEST(contact_hull_of_square_with_inner_points)
{
    const double v[8][2] = {{0.2, 0.1}, {1, 1}, {-1, -1}, {0, 1}, {1, -1}, {-0.5, 0.3}, {-1, 1}, {0, 0}};
    double h[8][2], area = 0.0;
    int n = contact_hull(v, 8, h);
    ENSURE(n == 4);
    for (int i = 0; i < n && n == 4; i++) {
        int j = (i + 1) % n;
        ENSURE(fabs(h[i][0]) == 1.0 && fabs(h[i][1]) == 1.0);
        area += 0.5 * (h[i][0] * h[j][1] - h[j][0] * h[i][1]);
    }
    ENSURE_CLOSE(area, 4.0, 1e-15);
    ENSURE(contact_hull(v, 0, h) == 1 && h[0][0] == 0.0 && h[0][1] == 0.0);
}

/* |x| <= 1, |y| <= 1 and a redundant x <= 5: the corners (+-1, +-1), each
 * with the two lines meeting there. */
EXDEX_TEST(contact_section_vertices_of_a_square)
{
    const double a[5][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 0}};
    const double b[5] = {1, 1, 1, 1, 5};
    double ys[EXDEX_MAX_FACES][2];
    int fg[EXDEX_MAX_FACES][2], n = contact_section_vertices(5, a, b, ys, fg);
    ENSURE(n == 4);
    for (int i = 0; i < n && n == 4; i++) {
        ENSURE(fabs(ys[i][0]) == 1.0 && fabs(ys[i][1]) == 1.0);
        ENSURE(fg[i][0] < fg[i][1] && fg[i][1] < 4);
        for (int k = 0; k < 2; k++) ENSURE_SMALL(a[fg[i][k]][0] * ys[i][0] + a[fg[i][k]][1] * ys[i][1] - 1.0, 1e-15);
    }
}

/* From (3, 0.5) the farthest line of the square is x <= 1 at 2, its foot
 * (1, 0.5) on the square; from (3, 3) x <= 1 and y <= 1 tie at 2 (the first
 * is taken), its foot (1, 3) outside y <= 1. No lines: -1. */
EXDEX_TEST(contact_farthest_line_of_a_square)
{
    const double a[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}};
    const double b[4] = {1, 1, 1, 1};
    double db;
    int on;
    ENSURE(contact_farthest_line(4, a, b, (const double[3]){3.0, 0.5, 0.0}, &db, &on) == 0);
    ENSURE_CLOSE(db, 2.0, 1e-15);
    ENSURE(on == 1);
    ENSURE(contact_farthest_line(4, a, b, (const double[3]){3.0, 3.0, 0.0}, &db, &on) == 0);
    ENSURE_CLOSE(db, 2.0, 1e-15);
    ENSURE(on == 0);
    ENSURE(contact_farthest_line(0, a, b, (const double[3]){0.0, 0.0, 0.0}, &db, &on) == -1);
}

/* A square of half side s at (x, y, theta) in a planar scene with B = A and
 * the stop y >= y_s: vertex j's gap is y + (Rz(theta) c_j)_y - y_s and the
 * smallest over the outline the lowest corner's, y - s (cos th + sin th) - y_s
 * for 0 <= theta <= pi/2. */
EXDEX_TEST(contact_vertex_gaps_of_a_turned_square_on_a_stop)
{
    const double s = 0.02, th = 0.3, ys = -0.05, c[4][2] = {{s, -s}, {s, s}, {-s, s}, {-s, -s}};
    exdex_scene_def d = exdex_default_scene_def();
    exdex_kinematics kin;
    frame f;
    int status;
    d.mu = 0.0;
    d.dof = EXDEX_DOF_PLANAR;
    memset(d.R0, 0, sizeof d.R0);
    d.R0[0] = d.R0[4] = d.R0[8] = 1.0;
    d.gravity[0] = d.gravity[1] = 0.0;
    d.gravity[2] = -9.81;
    d.n_vertices = 4;
    memcpy(d.vertices, c, sizeof c);
    d.q0[0] = 0.004;
    d.q0[1] = ys + s * (cos(th) + sin(th)) + 2e-3;
    d.q0[2] = th;
    d.n_stops = 1;
    d.stop_point[0][0] = 0.0;
    d.stop_point[0][1] = ys;
    d.stop_point[0][2] = 0.0;
    d.stop_normal[0][0] = 0.0;
    d.stop_normal[0][1] = 1.0;
    d.stop_normal[0][2] = 0.0;
    exdex_model *m = exdex_model_alloc(&d, &status, NULL);
    ENSURE(m != NULL);
    if (!m) return;
    ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
    for (int j = 0; j < 4; j++) {
        double G[3], g = contact_vertex_gap(m, &kin, 0, d.q0, j, G);
        ENSURE_CLOSE(g, d.q0[1] + sin(th) * c[j][0] + cos(th) * c[j][1] - ys, 1e-15);
        ENSURE_SMALL(G[0], 1e-15);
        ENSURE_CLOSE(G[1], 1.0, 1e-15);
        ENSURE_CLOSE(G[2], cos(th) * c[j][0] - sin(th) * c[j][1], 1e-15);
    }
    ENSURE_CLOSE(contact_min_gap(m, &kin, d.q0), 2e-3, 1e-15);
    exdex_model_free(m);
}

/* ------------------------------------------------ obstacle rows (contact_obstacle_build)
 * Scenes: B = A (the plate plane is A's x-y plane), the gripper at rest, a
 * square of half side OS (planar q = (x, y, theta), its centre of mass at
 * its centre) or a disc of radius OR; a box |x| <= OB, -1 <= y <= 0,
 * |z| <= 0.5 (faces 2 i + s: normal +-e_i; its section the rectangle of
 * corners (+-OB, 0), (+-OB, -1)), or a rod along z. Dyadic sizes, so every
 * distance below is exact in binary and the ties are exact. */
#define OS 0.25
#define OB 0.5
#define OR 0.125

static exdex_model *obstacle_model(int disc, const exdex_obstacle_def *ob)
{
    exdex_scene_def d = exdex_default_scene_def();
    const char *bad = NULL;
    int status = 0;
    exdex_model *m;
    d.mass = 0.1;
    memset(d.inertia, 0, sizeof d.inertia);
    d.inertia[0] = d.inertia[4] = d.inertia[8] = 1e-3;
    d.mu = 0.0;
    memset(d.R0, 0, sizeof d.R0);
    d.R0[0] = d.R0[4] = d.R0[8] = 1.0;
    d.dof = EXDEX_DOF_PLANAR;
    if (disc) {
        d.n_vertices = 0;
        d.disc_radius = OR;
    } else {
        d.n_vertices = 4;
        for (int j = 0; j < 4; j++) {
            d.vertices[j][0] = (j == 0 || j == 3) ? -OS : OS;
            d.vertices[j][1] = j < 2 ? -OS : OS;
        }
    }
    d.n_obstacles = 1;
    d.obstacles[0] = *ob;
    d.q0[0] = 0.0;   /* well clear of the obstacle (the model checks it) */
    d.q0[1] = 4.0;
    d.q0[2] = 0.0;
    m = exdex_model_alloc(&d, &status, &bad);
    if (!m) printf("    alloc: %s (%s)\n", exdex_strerror(status), bad ? bad : "");
    return m;
}

static exdex_obstacle_def obstacle_box(void)
{
    exdex_obstacle_def o;
    const double ctr[3] = {0.0, -0.5, 0.0}, half[3] = {OB, 0.5, 0.5};
    memset(&o, 0, sizeof o);
    o.kind = EXDEX_OBSTACLE_POLYTOPE;
    o.n_faces = 6;
    for (int i = 0; i < 3; i++)
        for (int s = 0; s < 2; s++) {
            o.face_normal[2 * i + s][i] = s ? -1.0 : 1.0;
            o.face_point[2 * i + s][i] = ctr[i] + (s ? -half[i] : half[i]);
        }
    return o;
}

static exdex_obstacle_def obstacle_rod(double cx, double cy, double r)
{
    exdex_obstacle_def o;
    memset(&o, 0, sizeof o);
    o.kind = EXDEX_OBSTACLE_CYLINDER;
    o.center[0] = cx;
    o.center[1] = cy;
    o.axis[2] = 1.0;
    o.radius = r;
    return o;
}

/* The hull edge of m from hull point (x0, y0) to (x1, y1) (C), or -1. */
static int hull_edge(const exdex_model *m, double x0, double y0, double x1, double y1)
{
    for (int e = 0; e < m->n_hull; e++) {
        const double *u = m->hull[e], *w = m->hull[(e + 1) % m->n_hull];
        if (u[0] == x0 && u[1] == y0 && w[0] == x1 && w[1] == y1) return e;
    }
    return -1;
}

/* The square turned by theta above the box top (every corner over the top
 * face, |x| < OB): outline vertex j at p_j = r + Rz(theta) c_j has the
 * top face's distance p_y as its largest (the side and bottom faces are
 * farther inside), so its row is face 2's: gap p_y, G = (n_B, (e_z x
 * (p_j - r)) . n_B) = (0, 1, (Rz c_j)_x), normal +e_y, feature (vertex j,
 * face 2), acting at p_j; rounding bound 8 eps (|p_j| + |face point|).
 * Section vertex P (a box corner) against the square's edge lines: in the
 * square's frame u = Rz(-theta) (P - r), the largest distance max(|u_x|,
 * |u_y|) - OS over the edge whose outward normal is sign(u_i) Rz e_i
 * (i the larger), acting at P with the inward normal n = -sign(u_i) Rz e_i:
 * G = (n, n_y (P - r)_x - n_x (P - r)_y). Rows: the 4 vertices, then the
 * 4 section vertices in contact_section_vertices' order: face pairs (0, 2),
 * (0, 3), (1, 2), (1, 3). */
EXDEX_TEST(obstacle_build_box_face_and_section_rows_by_hand)
{
    exdex_obstacle_def ob = obstacle_box();
    exdex_model *m = obstacle_model(0, &ob);
    const double th = 0.3, c = cos(th), s = sin(th), q[3] = {0.05, 0.5, th};
    const int pairs[4][2] = {{0, 2}, {0, 3}, {1, 2}, {1, 3}};
    double G[16][3], gap[16], rnd[16];
    int src[16], n;
    contact_point cp[16];
    contact_feature ft[16];
    frame f;
    exdex_kinematics kin;
    ENSURE(m != NULL);
    if (!m) return;
    ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
    n = contact_obstacle_build(m, &kin, q, NULL, G, gap, rnd, src, cp, ft);
    ENSURE(n == 8 && n <= contact_obstacle_max_rows(m));
    for (int j = 0; j < 4 && n == 8; j++) {
        double cx = m->vert[j][0], cy = m->vert[j][1], px = q[0] + c * cx - s * cy, py = q[1] + s * cx + c * cy;
        ENSURE(ft[j].obst == 0 && ft[j].kind == OROW_VERTEX && ft[j].a == j && ft[j].b == 0 && ft[j].feat == 2);
        ENSURE(src[j] == m->n_stops);
        ENSURE_CLOSE(gap[j], py, 1e-15);
        ENSURE(G[j][0] == 0.0 && G[j][1] == 1.0);
        ENSURE_CLOSE(G[j][2], c * cx - s * cy, 1e-15);
        ENSURE(cp[j].nB[0] == 0.0 && cp[j].nB[1] == 1.0 && cp[j].nB[2] == 0.0);
        ENSURE_CLOSE(cp[j].x[0], px, 1e-15);
        ENSURE_CLOSE(cp[j].x[1], py, 1e-15);
        /* the face point is the origin */
        ENSURE_CLOSE(rnd[j], 8.0 * DBL_EPSILON * hypot(px, py), 1e-12 * DBL_EPSILON);
    }
    for (int i = 0; i < 4 && n == 8; i++) {
        int r = 4 + i, fa = pairs[i][0], fb = pairs[i][1], k;
        double P[2] = {fa == 0 ? OB : -OB, fb == 2 ? 0.0 : -1.0}, dx = P[0] - q[0], dy = P[1] - q[1];
        double u[2] = {c * dx + s * dy, -s * dx + c * dy}, no[2], gref, Gz;
        ENSURE(ft[r].kind == OROW_SECTION && ft[r].a == fa && ft[r].b == fb);
        k = fabs(u[0]) > fabs(u[1]) ? 0 : 1;
        gref = fabs(u[k]) - OS;
        /* the inward normal, in B */
        no[0] = k == 0 ? -(u[0] > 0 ? 1 : -1) * c : (u[1] > 0 ? 1 : -1) * s;
        no[1] = k == 0 ? -(u[0] > 0 ? 1 : -1) * s : -(u[1] > 0 ? 1 : -1) * c;
        Gz = no[1] * dx - no[0] * dy;
        ENSURE_CLOSE(gap[r], gref, 1e-15);
        ENSURE_CLOSE(cp[r].x[0], P[0], 0.0);
        ENSURE_CLOSE(cp[r].x[1], P[1], 0.0);
        ENSURE_CLOSE(cp[r].nB[0], no[0], 1e-15);
        ENSURE_CLOSE(cp[r].nB[1], no[1], 1e-15);
        ENSURE_CLOSE(G[r][0], no[0], 1e-15);
        ENSURE_CLOSE(G[r][1], no[1], 1e-15);
        ENSURE_CLOSE(G[r][2], Gz, 1e-15);
        /* the feature: the hull edge of that outward normal */
        {
            const double *a = m->hull[ft[r].feat], *b = m->hull[(ft[r].feat + 1) % m->n_hull];
            double ex = b[0] - a[0], ey = b[1] - a[1], len = hypot(ex, ey);
            ENSURE_CLOSE(c * ey / len - s * (-ex / len), -no[0], 1e-15);
            ENSURE_CLOSE(s * ey / len + c * (-ex / len), -no[1], 1e-15);
        }
    }
    exdex_model_free(m);
}

/* A rod along z through (cx, cy), radius R, against the unturned square at
 * (0, 1): below its bottom edge's interior (|cx| < OS, cy < 1 - OS) the
 * nearest hull point is the foot (cx, 1 - OS) on the bottom edge, gap (1 -
 * OS - cy) - R, normal +e_y, feature 32 + that edge; beyond its corner
 * (OS, 1 - OS) diagonally (cx > OS, cy < 1 - OS) the corner, gap
 * hypot(cx - OS, 1 - OS - cy) - R along (corner - c) / |corner - c|,
 * feature that hull vertex. G = (n, n_y (x - r)_x - n_x (x - r)_y). */
EXDEX_TEST(obstacle_build_rod_edge_and_vertex_rows_by_hand)
{
    const double q[3] = {0.0, 1.0, 0.0}, R = 0.0625, cases[2][2] = {{0.125, 0.5}, {0.5, 0.375}};
    for (int k = 0; k < 2; k++) {
        exdex_obstacle_def ob = obstacle_rod(cases[k][0], cases[k][1], R);
        exdex_model *m = obstacle_model(0, &ob);
        double G[4][3], gap[4], rnd[4], x[2], nref[2], gref;
        contact_point cp[4];
        contact_feature ft[4];
        frame f;
        exdex_kinematics kin;
        int n, feat;
        ENSURE(m != NULL);
        if (!m) continue;
        ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
        n = contact_obstacle_build(m, &kin, q, NULL, G, gap, rnd, NULL, cp, ft);
        ENSURE(n == 1);
        if (k == 0) {
            x[0] = cases[k][0];
            x[1] = 1.0 - OS;
            nref[0] = 0.0;
            nref[1] = 1.0;
            gref = (1.0 - OS - cases[k][1]) - R;
            feat = 32 + hull_edge(m, -OS, -OS, OS, -OS);
        } else {
            double dx = OS - cases[k][0], dy = 1.0 - OS - cases[k][1], dd = hypot(dx, dy);
            int e = hull_edge(m, OS, -OS, OS, OS);
            x[0] = OS;
            x[1] = 1.0 - OS;
            nref[0] = dx / dd;
            nref[1] = dy / dd;
            gref = dd - R;
            feat = e;   /* the hull vertex (OS, -OS) starts the right edge */
        }
        ENSURE(ft[0].kind == OROW_ROD && ft[0].feat == feat && feat >= 0);
        ENSURE_CLOSE(gap[0], gref, 1e-15);
        ENSURE_CLOSE(cp[0].x[0], x[0], 1e-15);
        ENSURE_CLOSE(cp[0].x[1], x[1], 1e-15);
        ENSURE_CLOSE(cp[0].nB[0], nref[0], 1e-15);
        ENSURE_CLOSE(cp[0].nB[1], nref[1], 1e-15);
        ENSURE_CLOSE(G[0][0], nref[0], 1e-15);
        ENSURE_CLOSE(G[0][1], nref[1], 1e-15);
        ENSURE_CLOSE(G[0][2], nref[1] * (x[0] - q[0]) - nref[0] * (x[1] - q[1]), 1e-15);
        exdex_model_free(m);
    }
}

/* A disc of radius OR (centre = centre of mass) against the box: centred
 * above the top face (|x| < OB) its row is face 2's plane row, gap y - OR
 * at the support point (x, y - OR), G = (0, 1, 0), feature (0, face 2);
 * centred up and right of the corner (OB, 0) (beyond both face lines: the
 * centre's foot on the farthest line lies off the face) the corner's: gap
 * |c - P| - OR along (c - P) / |c - P|, acting at c - OR n, feature the
 * section vertex of faces (0, 2). Against a rod along z through (cx, cy) of
 * radius R: gap |c - (cx, cy)| - OR - R at the rim point c + OR u, u the
 * unit toward the axis, normal -u, feature OROW_ROD. */
EXDEX_TEST(obstacle_build_disc_rows_by_hand)
{
    exdex_obstacle_def box = obstacle_box(), rod = obstacle_rod(0.75, 0.25, 0.0625);
    const double qs[3][3] = {{0.125, 0.375, 0.7}, {0.875, 0.5, -0.2}, {0.25, 1.0, 0.1}};
    for (int k = 0; k < 3; k++) {
        exdex_model *m = obstacle_model(1, k < 2 ? &box : &rod);
        const double *q = qs[k];
        double G[2][3], gap[2], rnd[2], nref[2], gref, dx, dy, dd;
        contact_point cp[2];
        contact_feature ft[2];
        frame f;
        exdex_kinematics kin;
        ENSURE(m != NULL);
        if (!m) continue;
        ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
        ENSURE(contact_obstacle_build(m, &kin, q, NULL, G, gap, rnd, NULL, cp, ft) == 1);
        if (k == 0) {
            ENSURE(ft[0].kind == OROW_VERTEX && ft[0].a == 0 && ft[0].feat == 2);
            nref[0] = 0.0;
            nref[1] = 1.0;
            gref = q[1] - OR;
        } else if (k == 1) {
            dx = q[0] - OB;
            dy = q[1] - 0.0;
            dd = hypot(dx, dy);
            ENSURE(ft[0].kind == OROW_SECTION && ft[0].a == 0 && ft[0].b == 2 && ft[0].feat == 0);
            nref[0] = dx / dd;
            nref[1] = dy / dd;
            gref = dd - OR;
        } else {
            dx = q[0] - 0.75;
            dy = q[1] - 0.25;
            dd = hypot(dx, dy);
            ENSURE(ft[0].kind == OROW_ROD && ft[0].feat == 0);
            nref[0] = dx / dd;
            nref[1] = dy / dd;
            gref = dd - OR - 0.0625;
        }
        ENSURE_CLOSE(gap[0], gref, 1e-15);
        ENSURE_CLOSE(cp[0].nB[0], nref[0], 1e-15);
        ENSURE_CLOSE(cp[0].nB[1], nref[1], 1e-15);
        ENSURE_CLOSE(cp[0].x[0], q[0] - OR * nref[0], 1e-15);
        ENSURE_CLOSE(cp[0].x[1], q[1] - OR * nref[1], 1e-15);
        ENSURE_CLOSE(G[0][0], nref[0], 1e-15);
        ENSURE_CLOSE(G[0][1], nref[1], 1e-15);
        ENSURE_SMALL(G[0][2], 1e-15);   /* the normal passes through the centre */
        exdex_model_free(m);
    }
}

/* The rate of a feature for the rate tie rule, in closed form for the
 * unturned square moving at v = (vx, vy, 0) past the box at rest: a vertex
 * row's face distance n_f . p grows at n_f . v; a section vertex P (fixed)
 * lies at n_e . (P - u) outside the edge line (outward normal n_e, u moving
 * at v), which grows at -n_e . v. */
static double box_rate(const exdex_model *m, const exdex_kinematics *kin, const contact_feature *f, const double *q,
                       const double *v)
{
    (void)kin;
    (void)q;
    if (f->kind == OROW_VERTEX) {
        const double *n = m->def.obstacles[0].face_normal[f->feat];
        return n[0] * v[0] + n[1] * v[1];
    } else {
        const double *a = m->hull[f->feat], *b = m->hull[(f->feat + 1) % m->n_hull];
        double ex = b[0] - a[0], ey = b[1] - a[1], len = hypot(ex, ey);
        return -(ey / len * v[0] - ex / len * v[1]);
    }
}

/* Corner on corner: the square's lower-left corner exactly on the box's
 * corner (OB, 0) (q = (OB + OS, OS, 0)). Its vertex row has two pieces at
 * distance 0, the +x face (0) and the top face (2); the section row of that
 * box corner two, the square's left and bottom edges. The set max(g_i) >= 0
 * is not convex there and a linearised row holds one piece: the one the
 * corner moves along, never one it leaves (holding that would stop a motion
 * the obstacle allows).
 *  - Moving up and left, v = (-1/2, 1): the corner rises off the top face
 *    while it crosses the side's line: the top face (rate 1 > -1/2) and,
 *    for the section row, the square's bottom edge (the box corner drops
 *    below it at rate 1). Without a rule the first piece of the largest
 *    distance, face 0, would be held and block the move.
 *  - Moving right and down, v = (1, -1/2): the +x face and the left edge.
 * Both rules pick these at the exact tie: the rate rule by the rates (the
 * pieces within tol.touch of the largest), the step rule by the predicted
 * distances g_i + h G_i . v (g_i = 0, so the order of G_i . v, the rates).
 * They differ off the tie: the corner 1/1024 left of the box's corner
 * (only the top face at distance 0, the +x face at -1/1024, far beyond
 * tol.touch) moving at (1, -1/2) with h = 1/64: the step rule holds the +x
 * face, the largest at the step's end (-1/1024 + h > -h / 2: the corner
 * slides past the box corner within the step), the rate rule the top face
 * (the largest at the next instant; the event method decides again where
 * the two cross). */
EXDEX_TEST(obstacle_build_tie_rules_at_a_corner_on_a_corner)
{
    exdex_obstacle_def ob = obstacle_box();
    exdex_model *m = obstacle_model(0, &ob);
    const double vs[2][3] = {{-0.5, 1.0, 0.0}, {1.0, -0.5, 0.0}}, h = 1.0 / 64.0;
    frame f;
    exdex_kinematics kin;
    int jc = -1, eleft, ebottom;
    ENSURE(m != NULL);
    if (!m) return;
    ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
    for (int j = 0; j < 4; j++)
        if (m->vert[j][0] == -OS && m->vert[j][1] == -OS) jc = j;
    eleft = hull_edge(m, -OS, OS, -OS, -OS);
    ebottom = hull_edge(m, -OS, -OS, OS, -OS);
    ENSURE(jc >= 0 && eleft >= 0 && ebottom >= 0);
    for (int k = 0; k < 2 && jc >= 0; k++) {
        const double q[3] = {OB + OS, OS, 0.0};
        const int face = k == 0 ? 2 : 0, edge = k == 0 ? ebottom : eleft;
        contact_obuild rate = {NULL, 0.0, vs[k], box_rate, 0}, step = {vs[k], h, NULL, NULL, 0};
        double G[16][3], gap[16];
        contact_feature fr[16], fs[16], f0[16];
        int n = contact_obstacle_build(m, &kin, q, &rate, G, gap, NULL, NULL, NULL, fr), sec = -1;
        ENSURE(contact_obstacle_build(m, &kin, q, &step, G, gap, NULL, NULL, NULL, fs) == n);
        ENSURE(contact_obstacle_build(m, &kin, q, NULL, G, gap, NULL, NULL, NULL, f0) == n);
        /* no rule: the first of the tied pieces, face 0, the first edge */
        ENSURE(gap[jc] == 0.0 && f0[jc].feat == 0);
        ENSURE(fr[jc].kind == OROW_VERTEX && fr[jc].feat == face);
        ENSURE(fs[jc].feat == face);
        for (int i = 4; i < n; i++)
            if (fr[i].kind == OROW_SECTION && fr[i].a == 0 && fr[i].b == 2) sec = i;
        ENSURE(sec >= 0);
        if (sec < 0) continue;
        ENSURE(gap[sec] == 0.0);
        ENSURE(f0[sec].feat == (eleft < ebottom ? eleft : ebottom));
        ENSURE(fr[sec].feat == edge);
        ENSURE(fs[sec].feat == edge);
    }
    {
        const double q[3] = {OB + OS - 1.0 / 1024.0, OS, 0.0};
        contact_obuild rate = {NULL, 0.0, vs[1], box_rate, 0}, step = {vs[1], h, NULL, NULL, 0};
        double G[16][3], gap[16];
        contact_feature fr[16], fs[16];
        ENSURE(m->tol.touch < 1.0 / 1024.0 * 1e-3);
        contact_obstacle_build(m, &kin, q, &rate, G, gap, NULL, NULL, NULL, fr);
        contact_obstacle_build(m, &kin, q, &step, G, gap, NULL, NULL, NULL, fs);
        ENSURE(jc >= 0 && fr[jc].feat == 2 && fs[jc].feat == 0);
        ENSURE(jc >= 0 && gap[jc] == -1.0 / 1024.0);   /* the step rule's piece's distance */
    }
    exdex_model_free(m);
}

/* Why the section rows follow contact_section_vertices' (f, g) order and
 * not the counter-clockwise order about the section's mean (atan2, as
 * exdex_obstacle_section draws the polygon): the row order must be a
 * function of which face pairs meet, so that a row keeps its index (and
 * the rows of two views of the same pose, a stepper's and the event
 * method's, match index for index) while the pose moves. The angle order
 * jumps where a vertex crosses the angle pi about the mean: the diamond
 * |x| + |y| <= 1 turned by +-1e-9 about z has its left vertex just below
 * or just above the negative x axis, first in one counter-clockwise list
 * and last in the other, while its rows list the same face pairs in the
 * same order. */
EXDEX_TEST(obstacle_build_section_rows_keep_their_order_across_the_angle_pi)
{
    const double dl = 1e-9, R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p[3] = {0, 0, 0};
    contact_feature fts[2][16];
    int ns[2] = {0, 0}, first_left[2] = {0, 0};
    for (int k = 0; k < 2; k++) {
        exdex_obstacle_def o;
        const double tu = k ? -dl : dl, q[3] = {0.0, 4.0, 0.0};
        double xy[EXDEX_MAX_FACES][2], G[16][3], gap[16];
        contact_feature ft[16];
        exdex_model *m;
        frame f;
        exdex_kinematics kin;
        int n, ny;
        memset(&o, 0, sizeof o);
        o.kind = EXDEX_OBSTACLE_POLYTOPE;
        o.n_faces = 4;
        for (int i = 0; i < 4; i++) {
            double sx = (i & 1) ? -1.0 : 1.0, sy = (i & 2) ? -1.0 : 1.0;
            double nx = (cos(tu) * sx - sin(tu) * sy) / sqrt(2.0), nyy = (sin(tu) * sx + cos(tu) * sy) / sqrt(2.0);
            o.face_normal[i][0] = nx;
            o.face_normal[i][1] = nyy;
            o.face_point[i][0] = nx / sqrt(2.0);
            o.face_point[i][1] = nyy / sqrt(2.0);
        }
        ny = exdex_obstacle_section(&o, R, p, xy, NULL);
        ENSURE(ny == 4);
        if (ny == 4) first_left[k] = xy[0][0] < -0.5 ? 1 : xy[3][0] < -0.5 ? -1 : 0;
        m = obstacle_model(0, &o);
        ENSURE(m != NULL);
        if (!m) continue;
        ENSURE(model_frame_at(m, 0.0, &f, &kin) == EXDEX_OK);
        n = contact_obstacle_build(m, &kin, q, NULL, G, gap, NULL, NULL, NULL, ft);
        for (int i = 0; i < n; i++)
            if (ft[i].kind == OROW_SECTION) fts[k][ns[k]++] = ft[i];
        exdex_model_free(m);
    }
    /* the counter-clockwise lists: the left vertex first at +dl, last at -dl */
    ENSURE(first_left[0] == 1 && first_left[1] == -1);
    ENSURE(ns[0] == 4 && ns[1] == 4);
    for (int i = 0; i < 4 && ns[0] == 4 && ns[1] == 4; i++) {
        ENSURE(fts[0][i].a == fts[1][i].a && fts[0][i].b == fts[1][i].b);
        ENSURE(fts[0][i].a < fts[0][i].b);
        if (i)
            ENSURE(fts[0][i - 1].a < fts[0][i].a ||
                   (fts[0][i - 1].a == fts[0][i].a && fts[0][i - 1].b < fts[0][i].b));
    }
}
