/* test_obstacles.c -- convex obstacles fixed in the world (contact.c): their
 * section by the plate plane, and the implicit method against them. Every
 * expected value is a closed form stated beside it.
 * twin: tests/scenarios/test_obstacles.py (the same subject through the Python API)
 */
#include "../check.h"
#include "../sim_run.h"
#include "../../exdex.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define G 9.81
#define PI 3.14159265358979323846

/* A box of half sides h centred at c, its edges along the columns of Q. */
static exdex_obstacle_def box(const double c[3], const double h[3], const double Q[9])
{
    exdex_obstacle_def o;
    memset(&o, 0, sizeof o);
    o.kind = EXDEX_OBSTACLE_POLYTOPE;
    o.n_faces = 6;
    for (int i = 0; i < 3; i++)
        for (int s = 0; s < 2; s++) {
            int f = 2 * i + s;
            double sg = s ? -1.0 : 1.0;
            for (int k = 0; k < 3; k++) {
                o.face_normal[f][k] = sg * Q[3 * k + i];
                o.face_point[f][k] = c[k] + sg * h[i] * Q[3 * k + i];
            }
        }
    return o;
}

static void rot_z(double Q[9], double a)
{
    double c = cos(a), s = sin(a);
    double R[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
    memcpy(Q, R, sizeof R);
}

EXDEX_TEST(obstacle_section_box_turned_about_plate_normal)
{
    /* A box turned by 0.3 rad about z, cut by the plane z = 0 of the
     * identity pose: the rectangle of sides 2 h_x, 2 h_y turned by 0.3 rad
     * about the centre, corners c + Rz(0.3) (+-h_x, +-h_y). */
    double c[3] = {0.1, -0.2, 0.05}, h[3] = {0.3, 0.1, 0.4}, Q[9], I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p[3] = {0, 0, 0};
    double xy[EXDEX_MAX_FACES][2], area = 0.0;
    exdex_obstacle_def o;
    int n;
    rot_z(Q, 0.3);
    o = box(c, h, Q);
    n = exdex_obstacle_section(&o, I, p, xy, NULL);
    ENSURE(n == 4);
    for (int i = 0; i < n; i++) {
        int found = 0;
        for (int sx = -1; sx <= 1; sx += 2)
            for (int sy = -1; sy <= 1; sy += 2) {
                double x = c[0] + cos(0.3) * sx * h[0] - sin(0.3) * sy * h[1];
                double y = c[1] + sin(0.3) * sx * h[0] + cos(0.3) * sy * h[1];
                found |= fabs(x - xy[i][0]) < 1e-14 && fabs(y - xy[i][1]) < 1e-14;
            }
        ENSURE(found);
        area += 0.5 * (xy[i][0] * xy[(i + 1) % n][1] - xy[(i + 1) % n][0] * xy[i][1]);
    }
    ENSURE_CLOSE(area, 4.0 * h[0] * h[1], 1e-14); /* counter-clockwise: positive */
    /* the plane above the box misses it: no section */
    p[2] = 1.0;
    ENSURE(exdex_obstacle_section(&o, I, p, xy, NULL) == 0);
}

EXDEX_TEST(obstacle_section_box_corner_cut_is_a_triangle)
{
    /* The unit cube [0, 1]^3 cut by the plane x + y + z = 1/2 (normal along
     * (1, 1, 1)): the triangle with corners (1/2, 0, 0), (0, 1/2, 0),
     * (0, 0, 1/2), side sqrt(2)/2, area sqrt(3)/4 (sqrt(2)/2)^2 = sqrt(3)/8. */
    double c[3] = {0.5, 0.5, 0.5}, h[3] = {0.5, 0.5, 0.5}, Q[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double s3 = sqrt(3.0), s2 = sqrt(2.0), s6 = sqrt(6.0);
    /* B's axes in A: x = (1, -1, 0)/sqrt2, y = (1, 1, -2)/sqrt6, z = (1, 1, 1)/sqrt3 */
    double R[9] = {1 / s2, 1 / s6, 1 / s3, -1 / s2, 1 / s6, 1 / s3, 0, -2 / s6, 1 / s3};
    double p[3] = {1.0 / 6, 1.0 / 6, 1.0 / 6}, xy[EXDEX_MAX_FACES][2], area = 0.0;
    exdex_obstacle_def o = box(c, h, Q);
    int n = exdex_obstacle_section(&o, R, p, xy, NULL);
    ENSURE(n == 3);
    for (int i = 0; i < n; i++) {
        /* back in A: on the plane, two coordinates 0 and one 1/2 */
        double x[3];
        int zeros = 0;
        for (int k = 0; k < 3; k++) {
            x[k] = p[k] + R[3 * k] * xy[i][0] + R[3 * k + 1] * xy[i][1];
            zeros += fabs(x[k]) < 1e-14;
        }
        ENSURE(zeros == 2);
        ENSURE_CLOSE(x[0] + x[1] + x[2], 0.5, 1e-14);
        area += 0.5 * (xy[i][0] * xy[(i + 1) % n][1] - xy[(i + 1) % n][0] * xy[i][1]);
    }
    ENSURE_CLOSE(area, s3 / 8.0, 1e-14);
}

/* twin: tests/scenarios/test_obstacles.py::test_rod_section_disc_and_ellipse */
EXDEX_TEST(obstacle_section_rod_disc_and_ellipse)
{
    /* A rod of radius r along z through (0.1, 0.2): a disc of radius r there.
     * Tilted by 60 deg from the plate normal in the x-z plane: an ellipse
     * with semi-axes r / cos 60 = 2 r (along x) and r. */
    exdex_obstacle_def o;
    double I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, p[3] = {0, 0, 0}, xy[EXDEX_MAX_FACES][2], ab[3];
    memset(&o, 0, sizeof o);
    o.kind = EXDEX_OBSTACLE_CYLINDER;
    o.center[0] = 0.1;
    o.center[1] = 0.2;
    o.center[2] = 0.7;
    o.axis[2] = 1.0;
    o.radius = 0.03;
    ENSURE(exdex_obstacle_section(&o, I, p, xy, ab) == 1);
    ENSURE_CLOSE(xy[0][0], 0.1, 1e-15);
    ENSURE_CLOSE(xy[0][1], 0.2, 1e-15);
    ENSURE_CLOSE(ab[0], 0.03, 1e-15);
    ENSURE_CLOSE(ab[1], 0.03, 1e-15);
    o.axis[0] = sin(PI / 3);
    o.axis[2] = cos(PI / 3);
    ENSURE(exdex_obstacle_section(&o, I, p, xy, ab) == 1);
    ENSURE_CLOSE(ab[0], 0.06, 1e-14);
    ENSURE_CLOSE(ab[1], 0.03, 1e-15);
    ENSURE_CLOSE(ab[2], 0.0, 1e-15);
    /* the axis meets z = 0 at centre - 0.7 / cos60 * axis */
    ENSURE_CLOSE(xy[0][0], 0.1 - 0.7 * tan(PI / 3), 1e-14);
    o.axis[0] = 1.0;
    o.axis[2] = 0.0;
    ENSURE(exdex_obstacle_section(&o, I, p, xy, ab) == 0); /* a strip */
    o.radius = 0.0;
    ENSURE(exdex_obstacle_section(&o, I, p, xy, ab) == -EXDEX_EINVAL);
}

/* The paper's Fig. 4 set-up (test_sim.c): a 2 x 4 cm box resting on a floor
 * while the gripper moves down 5 cm. */
static exdex_scene_def fig4(void)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = 0.1;
    d.mu = 0.5;
    d.grip_force = 1.5 / (2 * d.mu);
    scene_rect(&d, 0.01, 0.02);
    scene_trapezoid(&d, 0, 0.0, 0.0, -1.0, 0.05, 0.5, 0.12);
    return d;
}

/* The run ra of a scene with a plane stop and the run rb of the same scene
 * with that stop as a one-face obstacle: the same trajectory and stop
 * forces bit for bit, or, for the explicit 1-DoF method (rounding = 1),
 * whose stop clamp forms the gap as n.(R x + p - point) in another order
 * than the planar row the obstacle shares (contact_row_1dof), equal to
 * rounding (q to 1e-15, the forces to 1e-9). */
static void stop_run_is_the_obstacle_run(const sim_run *ra, const sim_run *rb, int rounding)
{
    if (rounding) {
        for (size_t i = 0; i < ra->tr.n; i++) {
            ENSURE_CLOSE(ra->tr.q[i], rb->tr.q[i], 1e-15);
            ENSURE_CLOSE(ra->tr.stop_force[i], rb->tr.stop_force[i], 1e-9);
        }
    } else {
        ENSURE(memcmp(ra->tr.q, rb->tr.q, ra->tr.n * (size_t)ra->ndof * sizeof(double)) == 0);
        ENSURE(memcmp(ra->tr.v, rb->tr.v, ra->tr.n * (size_t)ra->ndof * sizeof(double)) == 0);
        ENSURE(memcmp(ra->tr.stop_force, rb->tr.stop_force, ra->tr.n * sizeof(double)) == 0);
    }
}

/* twin: tests/scenarios/test_obstacles.py::test_one_face_obstacle_is_the_stop_bit_for_bit */
EXDEX_TEST(obstacle_one_face_is_the_stop_bit_for_bit)
{
    /* A plane stop is an obstacle with one face (the same point and
     * normal): the same rows, the same arithmetic, the same trajectory, in
     * 1-DoF and in the plane, implicit, explicit (1-DoF: to rounding),
     * event and regularised. */
    for (int c = 0; c < 8; c++) {
        int planar = c % 2;
        exdex_scene_def a = fig4(), b;
        sim_run ra, rb;
        const int meth[4] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EXPLICIT, EXDEX_METHOD_EVENT,
                             EXDEX_METHOD_REGULARISED};
        a.method = meth[c / 2];
        if (planar) {
            a.dof = EXDEX_DOF_PLANAR;
            a.q0[2] = 0.2; /* lands on a corner and turns */
        }
        b = a;
        scene_stop(&a, 0, 0.0, 0.0, -0.03, 0.0, 0.0, 1.0);
        b.n_obstacles = 1;
        b.obstacles[0].kind = EXDEX_OBSTACLE_POLYTOPE;
        b.obstacles[0].n_faces = 1;
        b.obstacles[0].face_point[0][2] = -0.03;
        b.obstacles[0].face_normal[0][2] = 1.0;
        if (!planar && c >= 4) {
            /* 1-DoF event, regularised: with friction too (the same tangent) */
            a.stop_mu[0] = 0.3;
            b.obstacles[0].mu = 0.3;
        }
        ENSURE(sim_run_def(&a, 1.0, 1e-3, &ra) == EXDEX_OK);
        ENSURE(sim_run_def(&b, 1.0, 1e-3, &rb) == EXDEX_OK);
        ENSURE(rb.nstops == 1);
        stop_run_is_the_obstacle_run(&ra, &rb, c == 2);
        if (c != 2) ENSURE(ra.st.min_gap == rb.st.min_gap);
        sim_run_free(&ra);
        sim_run_free(&rb);
    }
}

EXDEX_TEST(obstacle_frictional_face_is_the_frictional_stop_in_every_method_that_solves_it)
{
    /* The Fig. 4 scene against a tilted floor (normal (0.3, 0, 1), through
     * z = -0.03) with Coulomb coefficient 0.4: as a stop and as a one-face
     * obstacle with the same friction, the same trajectory and forces in
     * the implicit and explicit methods, planar (bit for bit) and 1-DoF
     * (explicit: to rounding, its stop clamp forms the gap in another
     * order, as above), and the friction acts (the frictionless floor gives
     * other forces, and in the plane another motion). */
    const double nz = 1.0 / hypot(0.3, 1.0), nx = 0.3 * nz;
    for (int c = 0; c < 4; c++) {
        int planar = c % 2;
        exdex_scene_def a = fig4(), b, f;
        sim_run ra, rb, rf;
        int differs = 0;
        a.method = c < 2 ? EXDEX_METHOD_IMPLICIT : EXDEX_METHOD_EXPLICIT;
        if (planar) {
            a.dof = EXDEX_DOF_PLANAR;
            a.q0[2] = 0.2;
        }
        b = a;
        scene_stop(&a, 0, 0.0, 0.0, -0.03, nx, 0.0, nz);
        a.stop_mu[0] = 0.4;
        f = a;
        f.stop_mu[0] = 0.0;
        b.n_obstacles = 1;
        b.obstacles[0].kind = EXDEX_OBSTACLE_POLYTOPE;
        b.obstacles[0].n_faces = 1;
        b.obstacles[0].face_point[0][2] = -0.03;
        b.obstacles[0].face_normal[0][0] = nx;
        b.obstacles[0].face_normal[0][2] = nz;
        b.obstacles[0].mu = 0.4;
        ENSURE(sim_run_def(&a, 1.0, 1e-3, &ra) == EXDEX_OK);
        ENSURE(sim_run_def(&b, 1.0, 1e-3, &rb) == EXDEX_OK);
        ENSURE(sim_run_def(&f, 1.0, 1e-3, &rf) == EXDEX_OK);
        stop_run_is_the_obstacle_run(&ra, &rb, c == 2);
        /* 1-DoF: the friction shares the stop's push along the free coordinate (another
         * normal force); planar: it changes the motion too */
        for (size_t i = 0; i < ra.tr.n; i++)
            differs |= fabs(ra.tr.stop_force[i] - rf.tr.stop_force[i]) > 1e-3 &&
                       (!planar || fabs(ra.tr.q[i * 3 + 2] - rf.tr.q[i * 3 + 2]) > 1e-6);
        ENSURE(differs);
        sim_run_free(&ra);
        sim_run_free(&rb);
        sim_run_free(&rf);
    }
}

/* twin: tests/scenarios/test_obstacles.py::test_box_top_face_acts_as_the_equivalent_stop */
EXDEX_TEST(obstacle_box_floor_carries_the_load_like_a_stop)
{
    /* The Fig. 4 floor as the top face of a box (the other faces far from
     * the object): while the plates slide past, the box carries m g + the
     * capacity 1.5 N, and the object ends 5 cm up in B (test_sim.c's closed
     * form for the stop). */
    exdex_scene_def d = fig4();
    double c[3] = {0.0, 0.0, -0.53}, h[3] = {0.5, 0.5, 0.5}, Q[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    sim_run r;
    d.n_obstacles = 1;
    d.obstacles[0] = box(c, h, Q);
    for (int k = 0; k < 3; k++) {
        const int meth[3] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EVENT, EXDEX_METHOD_REGULARISED};
        d.method = meth[k];
        ENSURE(sim_run_def(&d, 1.0, 1e-4, &r) == EXDEX_OK);
        ENSURE(r.st.min_gap >= -1e-15);
        ENSURE_CLOSE(r.tr.q[r.tr.n - 1], 0.05 - 0.01, 1e-7); /* falls 1 cm onto it first */
        /* regularised: the sliding friction is within (eps / v)^2 of the
         * capacity at the plates' slip speed v (~0.1 m/s) */
        for (size_t i = 1500; i <= 4000; i += 500) ENSURE_CLOSE(r.tr.stop_force[i], 0.1 * G + 1.5, k == 2 ? 1e-6 : 1e-9);
        sim_run_free(&r);
    }
}

/* A square of half side a turning about its centre of mass (rotation
 * scene: a pin at the patch centre, mu 0.5, grip 1 N) and a frictionless
 * rod of radius r normal to the plates at x = dx right of the pin, starting
 * g0 below the bottom edge; the gripper moves down 5 mm over 1 s (a
 * trapezoid of peak speed 7.5 mm/s: rho stays above a + r, the rod never
 * jams the square). B x = A x, B y = A z, B z = -A y: the rod along A's y
 * is normal to the plates. */
static exdex_scene_def pinned_square_rod(double a, double r, double dx, double g0)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.dof = EXDEX_DOF_ROTATION;
    d.mass = 0.1;
    d.inertia[0] = d.inertia[4] = d.inertia[8] = 0.1 * (2 * a) * (2 * a) / 6;
    d.mu = 0.5;
    d.grip_force = 1.0;
    scene_rect(&d, a, a);
    scene_trapezoid(&d, 0, 0.0, 0.0, -1.0, 0.005, 1.0, 0.0075);
    d.n_obstacles = 1;
    d.obstacles[0].kind = EXDEX_OBSTACLE_CYLINDER;
    d.obstacles[0].radius = r;
    d.obstacles[0].center[0] = dx;
    d.obstacles[0].center[2] = -(a + r + g0);
    d.obstacles[0].axis[1] = 1.0;
    return d;
}

/* twin: tests/scenarios/test_obstacles.py::test_rod_turns_a_pinned_square_as_the_tangent_predicts */
EXDEX_TEST(obstacle_rod_turns_a_pinned_square_as_the_tangent_predicts)
{
    /* Rotation about the centre of mass (a pin at the patch centre), a square
     * of half side a; a rod of radius r normal to the plates, at x = d right
     * of the pin, starts g0 below the bottom edge. The gripper moves down by
     * delta(t): in B the rod rises, c = (d, -(a + r + g0) + delta). The plates'
     * friction torque stops the square as soon as the rod stops pushing, so
     * the bottom edge stays tangent to the rod: with the edge's outward
     * normal n = (sin th, -cos th) the tangency is n . c = a + r, i.e.
     *   d sin th + (a + r + g0 - delta) cos th = a + r,
     *   th = psi - acos((a + r) / rho),  rho = hypot(d, a + r + g0 - delta),
     *   psi = atan2(d, a + r + g0 - delta)  (the branch through th = 0),
     * and th = 0 before contact (rho cos psi > a + r). */
    const double a = 0.02, r = 0.005, dx = 0.015, g0 = 1e-3;
    exdex_scene_def d = pinned_square_rod(a, r, dx, g0);
    sim_run run;
    for (int k = 0; k < 2; k++) {
        /* implicit (dt 1e-4, its error O(dt)); event (exact contact: to the
         * closed form's rounding and rtol) */
        d.method = k ? EXDEX_METHOD_EVENT : EXDEX_METHOD_IMPLICIT;
        ENSURE(sim_run_def(&d, 1.2, k ? 1e-3 : 1e-4, &run) == EXDEX_OK);
        ENSURE(run.st.min_gap >= -1e-12);
        for (size_t i = 0; i < run.tr.n; i += k ? 25 : 250) {
            double s, sd, sdd, L, rho, psi, th;
            exdex_profile_trapezoid(0.005, 1.0, 0.0075, run.tr.t[i], &s, &sd, &sdd);
            L = a + r + g0 - s;
            rho = hypot(dx, L);
            psi = atan2(dx, L);
            th = L > a + r ? 0.0 : psi - acos((a + r) / rho);
            ENSURE_CLOSE(run.tr.q[i], th, k ? 1e-12 : 2e-6);
        }
        ENSURE(run.tr.q[run.tr.n - 1] > 0.3); /* it did turn */
        sim_run_free(&run);
    }
}

/* twin: tests/scenarios/test_obstacles.py::test_square_slides_off_a_slope_past_the_box_corner */
EXDEX_TEST(obstacle_square_slides_past_a_box_corner_on_a_slope)
{
    /* A square of half side a (planar, frictionless plates and box) rests
     * flush on the top face of a box turned by alpha about A's y (the plate
     * normal), its leading edge L0 before the box's downhill top corner K
     * (at B's origin), its edges parallel to the box's. Gravity's component
     * along the face, g sin(alpha), is the only force along it and the
     * weight passes through the square's base, so it translates:
     *   c(t) = c0 + 1/2 g sin(alpha) t^2 s,  theta = theta0,
     * s the downhill direction, through the instant its leading corner meets
     * K (the vertex's two face distances and K's two edge distances tie at
     * 0) and on while it overhangs (checked to an overhang of a / 2, the
     * centre of mass still over the box). The steps q+ = q + h v+ miss the
     * path by h v(t) / 2 + O(h^2) along s: bound h v(t); theta exact. */
    exdex_scene_def d = exdex_default_scene_def();
    const double a = 0.02, al = 0.3, L0 = 0.01, hs = 0.05;
    /* B x = A x, B y = A z: the box's axes in B are e1 = (cos al, -sin al)
     * and its top face normal n = (sin al, cos al); downhill s = e1 */
    double Q[9] = {cos(al), 0, sin(al), 0, 1, 0, -sin(al), 0, cos(al)};
    double s[2] = {cos(al), -sin(al)}, n[2] = {sin(al), cos(al)}, c[3], hh[3] = {hs, hs, hs}, c0[2];
    sim_run run;
    c[0] = -hs * s[0] - hs * n[0];
    c[1] = 0.0;
    c[2] = -hs * s[1] - hs * n[1];
    c0[0] = -(L0 + a) * s[0] + a * n[0];
    c0[1] = -(L0 + a) * s[1] + a * n[1];
    d.dof = EXDEX_DOF_PLANAR;
    d.mass = 0.1;
    d.inertia[0] = d.inertia[4] = d.inertia[8] = 0.1 * (2 * a) * (2 * a) / 6;
    d.mu = 0.0;
    d.grip_force = 1.0;
    scene_rect(&d, a, a);
    d.q0[0] = c0[0];
    d.q0[1] = c0[1];
    d.q0[2] = -al;
    d.n_obstacles = 1;
    d.obstacles[0] = box(c, hh, Q);
    for (int k = 0; k < 2; k++) {
        d.method = k ? EXDEX_METHOD_EXPLICIT : EXDEX_METHOD_IMPLICIT;
        ENSURE(sim_run_def(&d, 0.12, 1e-4, &run) == EXDEX_OK);
        ENSURE(run.st.min_gap >= -1e-12);
        for (size_t i = 0; i < run.tr.n; i++) {
            double t = run.tr.t[i], acc = G * sin(al), dd = 0.5 * acc * t * t;
            if (dd > L0 + 0.5 * a) break;
            ENSURE(hypot(run.tr.q[3 * i] - (c0[0] + dd * s[0]), run.tr.q[3 * i + 1] - (c0[1] + dd * s[1])) <=
                   1e-4 * acc * t + 1e-12);
            ENSURE_CLOSE(run.tr.q[3 * i + 2], -al, 1e-12);
        }
        ENSURE(0.5 * G * sin(al) * 0.12 * 0.12 > L0 + 0.5 * a); /* the run reaches past the corner */
        sim_run_free(&run);
    }
}

/* The frictional rod's moment about the pin per unit normal force (the
 * pinned square turned by the rod, below) at time t: with the tangency th,
 * the edge's outward normal n = (sin th, -cos th) and tangent t = (cos th,
 * sin th), the contact p = c - r n (c = (dx, -L) the rod's centre, L = a + r
 * + g0 - delta), th' = delta' cos th / (dx cos th - L sin th) (d/dt of
 * dx sin th + L cos th = a + r), the square's slip along the rod s = (th'
 * e_z x p - delta' e_y) . t and the rod's force per unit N, -n - mu sign(s)
 * t: its moment p x (-n - mu sign(s) t). */
static double rod_moment(double t, double a, double r, double dx, double g0, double mu)
{
    double sv, sd, sdd, L, th, thd, n[2], tv[2], p[2], sl, f[2];
    exdex_profile_trapezoid(0.005, 1.0, 0.0075, t, &sv, &sd, &sdd);
    L = a + r + g0 - sv;
    th = atan2(dx, L) - acos((a + r) / hypot(dx, L));
    thd = sd * cos(th) / (dx * cos(th) - L * sin(th));
    n[0] = sin(th); n[1] = -cos(th);
    tv[0] = cos(th); tv[1] = sin(th);
    p[0] = dx - r * n[0];
    p[1] = -L - r * n[1];
    sl = -thd * p[1] * tv[0] + (thd * p[0] - sd) * tv[1];
    f[0] = -n[0] - mu * (sl > 0 ? 1.0 : -1.0) * tv[0];
    f[1] = -n[1] - mu * (sl > 0 ? 1.0 : -1.0) * tv[1];
    return p[0] * f[1] - p[1] * f[0];
}

EXDEX_TEST(obstacle_frictional_rod_jams_the_pinned_square_event_goes_on)
{
    /* The rod turning the pinned square (above) with friction mu = 0.5: the
     * rod's moment about the pin per unit normal force (rod_moment) falls to
     * 0 at t_jam (bisection), where the normal force the turn needs grows
     * without bound (Painleve: no frictional solution beyond). The event
     * method runs on to 1 s, counts the jam as a warning first within the
     * output step after t_jam, keeps the tangency (closed form above: the
     * friction does not enter the kinematics) and from the jam on carries
     * the frictionless rod force. */
    exdex_scene_def d;
    const double a = 0.02, r = 0.005, dx = 0.015, g0 = 1e-3, mu = 0.5, dt = 1e-3;
    double lo = 0.5, hi = 0.9, t_jam;
    sim_run run, run0;
    ENSURE(rod_moment(lo, a, r, dx, g0, mu) > 0.0 && rod_moment(hi, a, r, dx, g0, mu) < 0.0);
    for (int it = 0; it < 60; it++) {
        double mid = 0.5 * (lo + hi);
        if (rod_moment(mid, a, r, dx, g0, mu) > 0.0) lo = mid; else hi = mid;
    }
    t_jam = 0.5 * (lo + hi);
    d = pinned_square_rod(a, r, dx, g0);
    d.method = EXDEX_METHOD_EVENT;
    ENSURE(sim_run_def(&d, 1.0, dt, &run0) == EXDEX_OK);
    d.obstacles[0].mu = mu;
    ENSURE(sim_run_def(&d, 1.0, dt, &run) == EXDEX_OK);
    ENSURE(run0.st.warnings == 0);
    ENSURE(run.st.warnings >= 1);
    ENSURE(run.st.first_warning_t >= t_jam && run.st.first_warning_t <= t_jam + dt);
    for (size_t i = 0; i < run.tr.n; i++) {
        double s, sd, sdd, L, rho, psi, th;
        exdex_profile_trapezoid(0.005, 1.0, 0.0075, run.tr.t[i], &s, &sd, &sdd);
        L = a + r + g0 - s;
        rho = hypot(dx, L);
        psi = atan2(dx, L);
        th = L > a + r ? 0.0 : psi - acos((a + r) / rho);
        ENSURE_CLOSE(run.tr.q[i], th, 1e-12);
        if (run.tr.t[i] > t_jam + dt) ENSURE_CLOSE(run.tr.stop_force[i], run0.tr.stop_force[i], 1e-9 * run0.tr.stop_force[i]);
    }
    sim_run_free(&run);
    sim_run_free(&run0);
}

/* The default scene with a rod of radius 0.1 along A's y (normal to the
 * plates) 1 m below B's origin. */
static exdex_scene_def rod_below(void)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.n_obstacles = 1;
    d.obstacles[0].kind = EXDEX_OBSTACLE_CYLINDER;
    d.obstacles[0].axis[1] = 1.0;
    d.obstacles[0].center[2] = -1.0;
    d.obstacles[0].radius = 0.1;
    return d;
}

EXDEX_TEST(obstacle_bad_input_status)
{
    exdex_scene_def d;
    const char *bad = NULL;
    int status;
#define EXPECT_BAD_OBST(field_expr, name)                                    \
    do {                                                                     \
        d = rod_below();                                                     \
        field_expr;                                                          \
        bad = NULL;                                                          \
        ENSURE(exdex_model_alloc(&d, &status, &bad) == NULL);                \
        ENSURE(status == EXDEX_EINVAL);                                      \
        ENSURE(bad != NULL && strncmp(bad, name, strlen(name)) == 0);        \
        ENSURE(exdex_scene_check(&d, &bad) == EXDEX_EINVAL);                 \
    } while (0)
    EXPECT_BAD_OBST(d.n_obstacles = EXDEX_MAX_OBSTACLES + 1, "n_obstacles");
    EXPECT_BAD_OBST(d.n_obstacles = -1, "n_obstacles");
    EXPECT_BAD_OBST(d.obstacles[0].radius = 0.0, "obstacles");
    EXPECT_BAD_OBST(d.obstacles[0].radius = NAN, "obstacles");
    EXPECT_BAD_OBST(d.obstacles[0].axis[1] = 2.0, "obstacles");
    EXPECT_BAD_OBST(d.obstacles[0].kind = 7, "obstacles");
    EXPECT_BAD_OBST((d.obstacles[0].kind = EXDEX_OBSTACLE_POLYTOPE, d.obstacles[0].n_faces = 0), "obstacles");
    EXPECT_BAD_OBST((d.obstacles[0].kind = EXDEX_OBSTACLE_POLYTOPE, d.obstacles[0].n_faces = EXDEX_MAX_FACES + 1),
                    "obstacles");
    EXPECT_BAD_OBST(d.method = EXDEX_METHOD_ANALYTIC, "method");
    /* planar obstacle friction, and frictional stops beside obstacles, in
     * every method that takes obstacles */
    for (int meth = EXDEX_METHOD_IMPLICIT; meth <= EXDEX_METHOD_EXPLICIT; meth++)
        for (int c = 0; c < 2; c++) {
            exdex_model *m;
            d = rod_below();
            d.dof = EXDEX_DOF_PLANAR;
            d.method = meth;
            d.obstacles[0].mu = c ? 0.0 : 0.5;
            if (c) {
                d.n_stops = 1;
                d.stop_normal[0][2] = 1.0;
                d.stop_point[0][2] = -0.5;
                d.stop_mu[0] = 0.3;
            }
            m = exdex_model_alloc(&d, &status, &bad);
            ENSURE(m != NULL && status == EXDEX_OK);
            exdex_model_free(m);
        }
    EXPECT_BAD_OBST(d.obstacles[0].mu = -0.1, "obstacles");
    EXPECT_BAD_OBST(d.obstacles[0].mu = NAN, "obstacles");
    EXPECT_BAD_OBST(d.obstacles[0].center[2] = -0.05, "q0"); /* the object (its centre) starts inside */
    {
        /* a valid one builds */
        exdex_model *m;
        d = rod_below();
        m = exdex_model_alloc(&d, &status, &bad);
        ENSURE(m != NULL && status == EXDEX_OK);
        ENSURE(exdex_model_nstops(m) == 1);
        exdex_model_free(m);
    }
#undef EXPECT_BAD_OBST
}

EXDEX_TEST(obstacle_rod_explicit_spinning_square_within_its_per_step_bound)
{
    /* A square of half side a spinning at 20 rad/s, free in the plate plane
     * (frictionless plates), falls under gravity onto a rod of radius r = 3 a
     * normal to the plates and rolls its corners over it. The explicit method's rows
     * hold each step's linearised gap; the nearest hull point slides along
     * the hull as the square turns, so the gap after a step may fall below 0
     * by the rod's per-step term derived in explicit.c,
     *   1/2 phi^2 (r + r_max (1 + phi)) + phi h (|v| + |thd| r_max),
     * phi = h |thd|, r_max = a sqrt(2): the run's smallest gap must stay
     * above the largest of its samples' terms (each sample one step), and
     * the method's own check, the same bound, must count no warning. */
    exdex_scene_def d = exdex_default_scene_def();
    const double a = 0.02, r = 3.0 * a, h = 2e-3, rmax = a * sqrt(2.0);
    double worst = 0.0;
    sim_run run;
    d.dof = EXDEX_DOF_PLANAR;
    d.method = EXDEX_METHOD_EXPLICIT;
    d.mass = 0.1;
    d.inertia[0] = d.inertia[4] = d.inertia[8] = 0.1 * (2 * a) * (2 * a) / 6;
    d.mu = 0.0;
    scene_rect(&d, a, a);
    d.v0[2] = 20.0;
    d.n_obstacles = 1;
    d.obstacles[0].kind = EXDEX_OBSTACLE_CYLINDER;
    d.obstacles[0].radius = r;
    /* B x = A x, B y = A z: the rod along A's y is normal to the plates,
     * 5 mm below the square's reach, slightly off centre (the per-step
     * bound without the rod's term, 1/2 phi^2 (r_max + h |v|) + phi h |v|,
     * is 5.6e-5 m here, below the run's smallest gap, -9.2e-5 m) */
    d.obstacles[0].center[0] = 0.3 * a;
    d.obstacles[0].center[2] = -(rmax + r + 0.005);
    d.obstacles[0].axis[1] = 1.0;
    ENSURE(sim_run_def(&d, 0.5, h, &run) == EXDEX_OK);
    for (size_t i = 1; i < run.tr.n; i++) {
        const double *v = run.tr.v + 3 * i;
        double phi = h * fabs(v[2]), P = 0.5 * phi * phi * (r + rmax * (1.0 + phi)) +
                                         phi * h * (hypot(v[0], v[1]) + fabs(v[2]) * rmax);
        worst = fmax(worst, P);
    }
    ENSURE(run.st.min_gap < 0.0);   /* it does touch the rod */
    ENSURE(run.st.min_gap >= -(worst + 1e-12));
    ENSURE(run.st.warnings == 0);
    sim_run_free(&run);
}
