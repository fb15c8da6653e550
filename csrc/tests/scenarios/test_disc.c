/* test_disc.c -- disc outlines (exdex_scene_def.disc_radius): a disc against
 * stops and obstacles in every method that solves them. Every expected value
 * is a closed form stated beside it.
 * twin: tests/scenarios/test_disc.py (the same subject through the Python API)
 */
#include "../check.h"
#include "../sim_run.h"
#include "../../contact.h"
#include "../../exdex.h"
#include "../../model.h"

#include <math.h>
#include <string.h>

#define GRAV 9.81

/* A uniform disc (mass 0.1 kg, radius R = 2 cm, I_zz = m R^2 / 2) in the
 * default grasp with frictionless plates; gravity -9.81 along B's y (the
 * default gripper rotation: B y = A z). */
static exdex_scene_def disc_def(int dof, int method)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = 0.1;
    memset(d.inertia, 0, sizeof d.inertia);
    d.inertia[0] = d.inertia[4] = 0.1 * (3 * 4e-4 + 1e-4) / 12.0;
    d.inertia[8] = 0.1 * 4e-4 / 2.0;
    d.mu = 0.0;
    d.dof = dof;
    d.method = method;
    d.disc_radius = 0.02;
    return d;
}

/* twin: tests/scenarios/test_disc.py::test_disc_rests_on_a_floor_at_its_radius_carrying_its_weight */
EXDEX_TEST(disc_rests_on_a_floor_at_its_radius_in_every_method)
{
    /* Dropped from 1 cm above a floor at A z = -0.03 (B y = -0.03), turned by
     * 0.3 rad: it rests with its centre R above the floor (its support point
     * on it), the floor carrying m g (frictionless plates). */
    int methods[4] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EXPLICIT, EXDEX_METHOD_EVENT, EXDEX_METHOD_REGULARISED};
    for (int c = 0; c < 8; c++) {
        int planar = c % 2;
        exdex_scene_def d = disc_def(planar ? EXDEX_DOF_PLANAR : EXDEX_DOF_TRANSLATION, methods[c / 2]);
        sim_run r;
        d.q0[1] = -0.03 + 0.02 + 0.01;
        d.q0[2] = 0.3;
        d.n_stops = 1;
        d.stop_point[0][2] = -0.03;
        d.stop_normal[0][2] = 1.0;
        ENSURE(sim_run_def(&d, 0.3, 1e-3, &r) == EXDEX_OK);
        ENSURE_CLOSE(r.tr.q[(r.tr.n - 1) * (size_t)r.ndof + (planar ? 1 : 0)], -0.01, 1e-15);
        ENSURE_CLOSE(r.tr.stop_force[r.tr.n - 1], 0.1 * GRAV, 1e-12);
        sim_run_free(&r);
    }
}

EXDEX_TEST(disc_rolls_down_a_frictional_incline)
{
    /* Incline through A's origin with normal (-sin a, 0, cos a), Coulomb
     * coefficient 0.5 >= tan(a) / 3: the disc rolls, acceleration 2/3 g sin
     * a along the slope (m a = m g sin a - f, I w' = f R, a = R w', I = m
     * R^2 / 2), turning by s / R. Constant accelerations from rest: the
     * implicit step's v_k = a k h, q_k = a h^2 k (k + 1) / 2. */
    const double al = 0.3, R = 0.02, h = 1e-4;
    exdex_scene_def d = disc_def(EXDEX_DOF_PLANAR, EXDEX_METHOD_IMPLICIT);
    sim_run r;
    double acc = 2.0 / 3.0 * GRAV * sin(al), s, t;
    d.q0[0] = -R * sin(al);
    d.q0[1] = R * cos(al);
    d.n_stops = 1;
    d.stop_normal[0][0] = -sin(al);
    d.stop_normal[0][2] = cos(al);
    d.stop_mu[0] = 0.5;
    ENSURE(sim_run_def(&d, 0.2, h, &r) == EXDEX_OK);
    t = r.tr.t[r.tr.n - 1];
    s = -(r.tr.q[(r.tr.n - 1) * 3] - d.q0[0]) * cos(al) - (r.tr.q[(r.tr.n - 1) * 3 + 1] - d.q0[1]) * sin(al);
    ENSURE_CLOSE(s, 0.5 * acc * t * (t + h), 1e-9 * s);
    ENSURE_CLOSE(r.tr.q[(r.tr.n - 1) * 3 + 2], s / R, 1e-9 * s / R);
    ENSURE_CLOSE(r.tr.stop_force[r.tr.n - 1], 0.1 * GRAV * cos(al), 1e-9);
    ENSURE(r.st.warnings == 0);
    sim_run_free(&r);
}

/* twin: tests/scenarios/test_disc.py::test_disc_rests_on_top_of_a_rod_at_the_sum_of_the_radii */
EXDEX_TEST(disc_rests_on_a_rod_at_the_sum_of_the_radii)
{
    /* A rod of radius 5 mm along A's y (the plate normal) through (0, 0,
     * -0.03): its section is the disc of that radius about (0, -0.03) in B.
     * The disc held above it rests with its centre R + r above the axis, the
     * rod carrying m g; implicit and explicit. */
    for (int c = 0; c < 2; c++) {
        exdex_scene_def d = disc_def(EXDEX_DOF_PLANAR, c ? EXDEX_METHOD_EXPLICIT : EXDEX_METHOD_IMPLICIT);
        sim_run r;
        d.q0[1] = -0.03 + 0.005 + 0.02 + 0.002;
        d.n_obstacles = 1;
        d.obstacles[0].kind = EXDEX_OBSTACLE_CYLINDER;
        d.obstacles[0].center[2] = -0.03;
        d.obstacles[0].axis[1] = 1.0;
        d.obstacles[0].radius = 0.005;
        ENSURE(sim_run_def(&d, 0.3, 1e-4, &r) == EXDEX_OK);
        ENSURE_CLOSE(r.tr.q[(r.tr.n - 1) * 3 + 1], -0.005, 1e-15);
        ENSURE_CLOSE(r.tr.stop_force[r.tr.n - 1], 0.1 * GRAV, 1e-12);
        sim_run_free(&r);
    }
}

EXDEX_TEST(disc_bad_input_named)
{
    exdex_scene_def d = disc_def(EXDEX_DOF_PLANAR, EXDEX_METHOD_IMPLICIT);
    const char *bad = NULL;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_OK);
    d.disc_radius = -0.01;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && strcmp(bad, "disc_radius") == 0);
    d.disc_radius = NAN;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && strcmp(bad, "disc_radius") == 0);
    d.disc_radius = 0.02;
    d.n_vertices = 1;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && strcmp(bad, "disc_radius") == 0);
    d.n_vertices = 0;
    d.disc_center[1] = INFINITY;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && strcmp(bad, "disc_center") == 0);
    d.disc_center[1] = 0.0;
    /* starting beyond a stop: the support point, not the centre, counts */
    d.n_stops = 1;
    d.stop_point[0][2] = -0.019;
    d.stop_normal[0][2] = 1.0;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL && strstr(bad, "beyond a stop"));
    d.stop_point[0][2] = -0.02;
    ENSURE(exdex_scene_check(&d, &bad) == EXDEX_OK);
}

/* ------------------------------------------- obstacle rows against brute force */

static unsigned long lcg_state = 12345;
/* Distance from the rod's axis of the rim point at angle ph of the disc
 * (centre xc, radius r) in the plane z = 0. */
static double axd(const double xc[2], double r, const exdex_obstacle_def *ob, double ph)
{
    double x[3] = {xc[0] + r * cos(ph) - ob->center[0], xc[1] + r * sin(ph) - ob->center[1], -ob->center[2]};
    double t = x[0] * ob->axis[0] + x[1] * ob->axis[1] + x[2] * ob->axis[2];
    return sqrt(fmax(0.0, x[0] * x[0] + x[1] * x[1] + x[2] * x[2] - t * t));
}

static double urand(double lo, double hi)
{
    lcg_state = lcg_state * 6364136223846793005UL + 1442695040888963407UL;
    return lo + (hi - lo) * (double)(lcg_state >> 11) / 9007199254740992.0;
}

/* A planar disc model (radius r about (cx, cy) in C) with one obstacle, the
 * gripper at rest at the identity pose (B = A), the object started far
 * away (the model checks the initial gap). */
static exdex_model *disc_model(double r, double cx, double cy, const exdex_obstacle_def *ob)
{
    exdex_scene_def d = disc_def(EXDEX_DOF_PLANAR, EXDEX_METHOD_IMPLICIT);
    int st;
    const char *bad;
    memset(d.R0, 0, sizeof d.R0);
    d.R0[0] = d.R0[4] = d.R0[8] = 1.0;
    d.disc_radius = r;
    d.disc_center[0] = cx;
    d.disc_center[1] = cy;
    d.q0[0] = 10.0;
    d.n_obstacles = 1;
    d.obstacles[0] = *ob;
    return exdex_model_alloc(&d, &st, &bad);
}

/* disc_model with the disc's centre drawn in (-0.01, 0.01)^2 and a pose q
 * drawn in (-span, span)^2 x (-3, 3): its one obstacle row's gap in g[0]
 * and the disc's centre in B in xc. Returns the model (NULL: it failed). */
static exdex_model *disc_random_row(double r, const exdex_obstacle_def *ob, double span, double g[MAX_ROWS],
                                    double xc[2])
{
    double G[MAX_ROWS][3], rnd[MAX_ROWS], q[3];
    exdex_kinematics kin;
    exdex_model *m = disc_model(r, urand(-0.01, 0.01), urand(-0.01, 0.01), ob);
    ENSURE(m != NULL);
    if (!m) return NULL;
    q[0] = urand(-span, span);
    q[1] = urand(-span, span);
    q[2] = urand(-3.0, 3.0);
    ENSURE(exdex_motion_eval(m->motion, 0.0, &kin) == EXDEX_OK);
    ENSURE(contact_obstacle_rows(m, &kin, q, G, g, rnd, NULL, NULL) == 1);
    xc[0] = q[0] + cos(q[2]) * m->vert[0][0] - sin(q[2]) * m->vert[0][1];
    xc[1] = q[1] + sin(q[2]) * m->vert[0][0] + cos(q[2]) * m->vert[0][1];
    return m;
}

EXDEX_TEST(disc_rod_row_is_the_brute_force_rim_distance_from_the_axis)
{
    /* Random rods (axis at any angle to the plate plane, down to 0.05 rad)
     * and disc poses, the gripper at the identity pose: the row's gap is the
     * least distance of a rim point from the axis less the rod's radius
     * (when the axis meets the plane outside the disc), brute force over
     * 20000 rim angles refined by a golden-section search on the best
     * sample's neighbours (the distance is smooth in the angle). */
    for (int c = 0; c < 100; c++) {
        exdex_obstacle_def ob;
        exdex_model *m;
        double r = urand(0.005, 0.03), el = urand(0.05, 1.5707963), az = urand(0.0, 6.2831853);
        double g[MAX_ROWS], best = INFINITY, c0[2], xc[2];
        int ib = 0;
        const int N = 20000;
        memset(&ob, 0, sizeof ob);
        ob.kind = EXDEX_OBSTACLE_CYLINDER;
        ob.axis[0] = cos(el) * cos(az);
        ob.axis[1] = cos(el) * sin(az);
        ob.axis[2] = sin(el);
        ob.center[0] = urand(-0.05, 0.05);
        ob.center[1] = urand(-0.05, 0.05);
        ob.center[2] = urand(-0.05, 0.05);
        ob.radius = urand(0.002, 0.02);
        m = disc_random_row(r, &ob, 0.08, g, xc);
        if (!m) continue;
        c0[0] = ob.center[0] - ob.center[2] / ob.axis[2] * ob.axis[0];
        c0[1] = ob.center[1] - ob.center[2] / ob.axis[2] * ob.axis[1];
        if (hypot(xc[0] - c0[0], xc[1] - c0[1]) < r) {
            exdex_model_free(m);
            continue;  /* the axis meets the plane inside the disc: a penetration measure */
        }
        for (int i = 0; i < N; i++) {
            double dd = axd(xc, r, &ob, 6.283185307179586 * i / N);
            if (dd < best) {
                best = dd;
                ib = i;
            }
        }
        {
            double a = 6.283185307179586 * (ib - 1) / N, b = 6.283185307179586 * (ib + 1) / N;
            for (int it = 0; it < 100; it++) {
                double m1 = a + 0.381966 * (b - a), m2 = b - 0.381966 * (b - a);
                if (axd(xc, r, &ob, m1) < axd(xc, r, &ob, m2)) b = m2; else a = m1;
            }
            best = fmin(best, axd(xc, r, &ob, 0.5 * (a + b)));
        }
        ENSURE_CLOSE(g[0], best - ob.radius, 1e-12);
        exdex_model_free(m);
    }
}

EXDEX_TEST(disc_box_row_is_the_distance_from_the_section_less_the_radius)
{
    /* Random boxes turned about the plate normal (their faces normal to the
     * plate plane, so a face row's gap is the in-plane distance) and disc
     * poses outside them: the row's gap is the disc centre's distance from
     * the section rectangle (point-to-segment distances over its edges, from
     * exdex_obstacle_section) less the disc's radius. */
    for (int c = 0; c < 400; c++) {
        exdex_obstacle_def ob;
        exdex_model *m;
        double h[3] = {urand(0.005, 0.05), urand(0.005, 0.05), 0.1}, ang = urand(0.0, 3.14159), ctr[3];
        double g[MAX_ROWS], xy[EXDEX_MAX_FACES][2], xc[2], dist = INFINITY;
        double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p0[3] = {0, 0, 0}, r = urand(0.002, 0.03);
        int ns, inside = 1;
        ctr[0] = urand(-0.03, 0.03);
        ctr[1] = urand(-0.03, 0.03);
        ctr[2] = 0.0;
        memset(&ob, 0, sizeof ob);
        ob.kind = EXDEX_OBSTACLE_POLYTOPE;
        ob.n_faces = 6;
        for (int i = 0; i < 3; i++)
            for (int s = 0; s < 2; s++) {
                int f = 2 * i + s;
                double sg = s ? -1.0 : 1.0, col[3];
                col[0] = i == 0 ? cos(ang) : i == 1 ? -sin(ang) : 0.0;
                col[1] = i == 0 ? sin(ang) : i == 1 ? cos(ang) : 0.0;
                col[2] = i == 2 ? 1.0 : 0.0;
                for (int k = 0; k < 3; k++) {
                    ob.face_normal[f][k] = sg * col[k];
                    ob.face_point[f][k] = ctr[k] + sg * h[i] * col[k];
                }
            }
        m = disc_random_row(r, &ob, 0.1, g, xc);
        if (!m) continue;
        ns = exdex_obstacle_section(&ob, I, p0, xy, NULL);
        ENSURE(ns == 4);
        for (int e = 0; e < ns; e++) {
            const double *u = xy[e], *v = xy[(e + 1) % ns];
            double ex = v[0] - u[0], ey = v[1] - u[1], t = ((xc[0] - u[0]) * ex + (xc[1] - u[1]) * ey) / (ex * ex + ey * ey);
            t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
            dist = fmin(dist, hypot(xc[0] - u[0] - t * ex, xc[1] - u[1] - t * ey));
            if (ex * (xc[1] - u[1]) - ey * (xc[0] - u[0]) < 0.0) inside = 0;  /* right of a ccw edge */
        }
        if (!inside) ENSURE_CLOSE(g[0], dist - r, 1e-13);
        else ENSURE_CLOSE(g[0], -dist - r, 1e-13);
        exdex_model_free(m);
    }
}
