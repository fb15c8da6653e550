/* test_contact.c -- contact.c: plane geometry (hull, section vertices,
 * farthest line) and the stops' vertex gaps, against hand geometry. */
#include "check.h"
#include "../contact.h"
#include "../model.h"

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
