/* test_disc.c -- disc outlines (exdex_scene_def.disc_radius): a disc against
 * stops and obstacles in every method that solves them. Every expected value
 * is a closed form stated beside it. */
#include "check.h"
#include "sim_run.h"
#include "../exdex.h"

#include <math.h>
#include <string.h>

#define G 9.81

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
        ENSURE_CLOSE(r.tr.stop_force[r.tr.n - 1], 0.1 * G, 1e-12);
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
    double acc = 2.0 / 3.0 * G * sin(al), s, t;
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
    ENSURE_CLOSE(r.tr.stop_force[r.tr.n - 1], 0.1 * G * cos(al), 1e-9);
    ENSURE(r.st.warnings == 0);
    sim_run_free(&r);
}

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
        ENSURE_CLOSE(r.tr.stop_force[r.tr.n - 1], 0.1 * G, 1e-12);
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
