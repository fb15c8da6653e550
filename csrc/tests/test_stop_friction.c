/* test_stop_friction.c -- the acceleration-level problem of a planar object against
 * frictional stops (stop_friction.c) against closed forms, a Painleve configuration
 * with no consistent mode, and the slip acceleration of a vertex along a
 * stop (contact_slip_planar) and along an obstacle's section and rod rows
 * (orow_slip) against a central difference of the slip along a trajectory
 * under a turning gripper. */
#include "check.h"
#include "../contact.h"
#include "../ldp.h"
#include "../model.h"
#include "../obstacle_rows.h"
#include "../stop_friction.h"
#include "../tolerances.h"
#include "sf_residual.h"

#include <gsl/gsl_eigen.h>
#include <math.h>
#include <string.h>

#define G 9.81

/* A particle (planar coordinates, rotation idle) on an incline of angle a:
 * normal n = (-sin a, cos a), tangent t = e_z x n = (-cos a, -sin a);
 * gravity (0, -g). Along the incline the weight's part is m g sin a (down
 * the slope, +t direction: t . (0, -g) = g sin a), into it m g cos a. Stick
 * iff mu >= tan a: qdd = 0, lam = m g cos a, beta = -m g sin a. Else it
 * slides along +t with g (sin a - mu cos a), beta = -mu lam. */
EXDEX_TEST(sfric_particle_on_incline_sticks_or_slides_closed_form)
{
    double a = 0.4, m = 0.5, minv[3] = {1.0 / m, 1.0 / m, 10.0}, acc[3] = {0.0, -G, 0.0};
    for (int c = 0; c < 2; c++) {
        double mu = c ? 0.5 : 0.3;  /* tan 0.4 = 0.4228 */
        sf_row row = {{-sin(a), cos(a), 0.0}, 0.0, 0};
        sf_stop st = {{-cos(a), -sin(a), 0.0}, 0.0, mu, SF_ROLL};
        sf_result r;
        ENSURE(sf_solve(1, &row, 1, &st, minv, acc, 1e-12, 1e-12, &r) == 1);
        ENSURE_CLOSE(r.lam[0], m * G * cos(a), 1e-14);
        if (mu >= tan(a)) {
            ENSURE(r.fm[0] == SF_STICK);
            ENSURE_CLOSE(r.beta[0], -m * G * sin(a), 1e-14);
            ENSURE_CLOSE(hypot(r.qdd[0], r.qdd[1]), 0.0, 1e-14);
        } else {
            double at = G * (sin(a) - mu * cos(a));
            ENSURE(r.fm[0] == SF_SLIDE_P);
            ENSURE_CLOSE(r.beta[0], -mu * m * G * cos(a), 1e-14);
            ENSURE_CLOSE(r.acct[0], at, 1e-14);
            ENSURE_CLOSE(r.qdd[0], -at * cos(a), 1e-14);
            ENSURE_CLOSE(r.qdd[1], -at * sin(a), 1e-14);
        }
        ENSURE_CLOSE(r.acc[0], 0.0, 1e-14);
        /* a stop given a mode keeps it: sliding the other way (its slip
         * negative), the friction acts down the slope */
        st.fm = SF_SLIDE_M;
        ENSURE(sf_solve(1, &row, 1, &st, minv, acc, 1e-12, 1e-12, &r) == 1);
        ENSURE(r.fm[0] == SF_SLIDE_M);
        ENSURE_CLOSE(r.beta[0], mu * m * G * cos(a), 1e-14);
        ENSURE_CLOSE(r.acct[0], G * (sin(a) + mu * cos(a)), 1e-14);
        /* lifted off (the free acceleration leaves the stop): no force */
        acc[1] = G;
        st.fm = SF_ROLL;
        ENSURE(sf_solve(1, &row, 1, &st, minv, acc, 1e-12, 1e-12, &r) == 1);
        ENSURE(r.lam[0] == 0.0 && r.beta[0] == 0.0 && r.qdd[1] == G);
        acc[1] = -G;
    }
}

/* A face flat on a wall: two rows of one stop whose tangent rows are equal
 * (the face's corners slip together), the block at rest in the plane, a
 * load f = (fx, fy) at the centre pushing it into the wall (fx < 0, wall
 * normal +x at x = -h) and along it. One tangential unknown per stop keeps
 * the system regular (two tangential unknowns would have dependent rows):
 * stick iff |fy| <= mu |fx|, then lam1 + lam2 = -fx, beta = -fy, and the
 * moments about the centre, -h lam1 (corner (-h, h)) + h lam2 (corner
 * (-h, -h)) - h beta (the friction at x = -h), vanish: lam2 - lam1 = beta.
 * Else it slides along +y, beta = -mu (lam1 + lam2), qdd_y = (fy - mu |fx|)
 * / m. */
EXDEX_TEST(sfric_face_on_wall_sticks_with_one_tangential_force)
{
    double h = 0.01, minv[3] = {10.0, 10.0, 1e4};
    for (int c = 0; c < 2; c++) {
        double fx = -1.0, fy = c ? 0.7 : 0.3, mu = 0.5, acc[3] = {fx * minv[0], fy * minv[1], 0.0};
        /* corners (-h, +h) and (-h, -h) from the centre: G = (n, r x n) with
         * n = (1, 0): r x n = -r_y; T = (t, r x t) with t = (0, 1): r_x */
        sf_row rows[2] = {{{1.0, 0.0, -h}, 0.0, 0}, {{1.0, 0.0, h}, 0.0, 0}};
        sf_stop st = {{0.0, 1.0, -h}, 0.0, mu, SF_ROLL};
        sf_result r;
        ENSURE(sf_solve(2, rows, 1, &st, minv, acc, 1e-12, 1e-12, &r) == 1);
        ENSURE_CLOSE(r.lam[0] + r.lam[1], -fx, 1e-12);
        if (fabs(fy) <= mu * fabs(fx)) {
            ENSURE(r.fm[0] == SF_STICK);
            ENSURE_CLOSE(r.beta[0], -fy, 1e-12);
            ENSURE_CLOSE(fabs(r.qdd[0]) + fabs(r.qdd[1]) + fabs(r.qdd[2]), 0.0, 1e-9);
            /* moments about the centre: -h lam1 + h lam2 - h beta = 0 */
            ENSURE_CLOSE(r.lam[1] - r.lam[0], r.beta[0], 1e-12);
        } else {
            ENSURE(r.fm[0] == SF_SLIDE_P);
            ENSURE_CLOSE(r.beta[0], -mu * (r.lam[0] + r.lam[1]), 1e-12);
            ENSURE_CLOSE(r.qdd[1], (fy - mu * fabs(fx)) * minv[1], 1e-9);
        }
    }
}

/* The face of the test above drawn with N = 13 points on the wall (more
 * rows than SF_ENUM_ROWS): the points (-h, y_i), y_i from h to -h, have
 * G_i = (1, 0, -y_i) and one tangent row. Their forces are a force at the
 * centre of pressure, so the closed form is that of the two corners: stick
 * iff |fy| <= mu |fx|, sum lam = -fx, beta = -fy and the moment sum lam_i
 * (-y_i) - h beta = 0; else slide, qdd_y = (fy - mu |fx|) / m. Every row's
 * gap acceleration is >= 0 (to rounding). */
EXDEX_TEST(sfric_many_points_on_one_line_as_two_corners)
{
    enum { N = 13 };
    double h = 0.01, minv[3] = {10.0, 10.0, 1e4};
    for (int c = 0; c < 2; c++) {
        double fx = -1.0, fy = c ? 0.7 : 0.3, mu = 0.5, acc[3] = {fx * minv[0], fy * minv[1], 0.0}, ls = 0.0,
               mom = 0.0;
        sf_row rows[N];
        sf_stop st = {{0.0, 1.0, -h}, 0.0, mu, SF_ROLL};
        sf_result r;
        for (int i = 0; i < N; i++) {
            double y = h - 2.0 * h * i / (N - 1);
            rows[i] = (sf_row){{1.0, 0.0, -y}, 0.0, 0};
        }
        ENSURE(sf_solve(N, rows, 1, &st, minv, acc, 1e-12, 1e-12, &r) == 1);
        for (int i = 0; i < N; i++) {
            double y = h - 2.0 * h * i / (N - 1);
            ENSURE(r.lam[i] >= 0.0);
            ENSURE(r.acc[i] >= -1e-12);
            ls += r.lam[i];
            mom += -y * r.lam[i];
        }
        ENSURE_CLOSE(ls, -fx, 1e-12);
        if (fabs(fy) <= mu * fabs(fx)) {
            ENSURE(r.fm[0] == SF_STICK);
            ENSURE_CLOSE(r.beta[0], -fy, 1e-12);
            ENSURE_CLOSE(fabs(r.qdd[0]) + fabs(r.qdd[1]) + fabs(r.qdd[2]), 0.0, 1e-9);
            ENSURE_CLOSE(mom - h * r.beta[0], 0.0, 1e-12);
        } else {
            ENSURE(r.fm[0] == SF_SLIDE_P);
            ENSURE_CLOSE(r.beta[0], -mu * ls, 1e-12);
            ENSURE_CLOSE(r.qdd[1], (fy - mu * fabs(fx)) * minv[1], 1e-9);
        }
    }
}

/* Painleve: one row of a stop sliding with a fixed sign whose friction
 * turns the normal force's effect around: G = (0, 1, 1), T = (1, 0, 2), mu
 * = 1, sliding +: the force direction D = G - T = (-1, 1, -1), G M^-1 D =
 * 1 - 10 < 0 with M = diag(1, 1, 0.1); the free acceleration drives the
 * row in (G a = -1). With force lam = (G a) / -(G M^-1 D) < 0; without, the
 * row penetrates: no consistent mode. Frictionless it is consistent. */
EXDEX_TEST(sfric_painleve_has_no_consistent_mode)
{
    double minv[3] = {1.0, 1.0, 10.0}, acc[3] = {0.0, -1.0, 0.0};
    sf_row row = {{0.0, 1.0, 1.0}, 0.0, 0};
    sf_stop st = {{1.0, 0.0, 2.0}, 0.0, 1.0, SF_SLIDE_P};
    sf_result r;
    ENSURE(sf_solve(1, &row, 1, &st, minv, acc, 1e-12, 1e-12, &r) == 0);
    st.fm = SF_NONE;
    ENSURE(sf_solve(1, &row, 1, &st, minv, acc, 1e-12, 1e-12, &r) == 1);
    ENSURE(r.lam[0] > 0.0 && r.beta[0] == 0.0);
    ENSURE_CLOSE(r.acc[0], 0.0, 1e-14);
    /* out of range */
    ENSURE(sf_solve(SF_MAX_ROWS + 1, &row, 1, &st, minv, acc, 1e-12, 1e-12, &r) == 0);
}

/* A square block (half side h, at rest, centre at the origin) in the
 * corner of a wall at x = h (normal -x, mu_w) and a floor at y = -h
 * (normal +y, mu_f), each face flush: rows G = (n, r x n) at the corners
 * (h, h), (h, -h) on the wall (r x n = r_y) and (-h, -h), (h, -h) on the
 * floor (r x n = r_x); tangents t = e_z x n, T = (t, r x t): the wall's
 * (0, -1, -h), the floor's (-1, 0, -h). A load (fx, fy) at the centre
 * pushes it into the wall (fx > 0). It stays (qdd = 0) iff stop forces in
 * the cones give -F. For |fy| <= mu_w fx the wall alone does it (normal
 * force fx, friction -fy, its moment h fy about the centre within what the
 * wall's two corners carry, h fx, for mu_w < 1): the floor is not needed,
 * and the least constrained consistent mode is that one, no lock. For fy <
 * -mu_w fx both stops are needed: the floor takes -fy and the wall fx
 * through the centre, no friction needed: a lock (the four rows fix qdd).
 * For fy > mu_w fx the floor cannot pull and the wall cannot hold: the
 * block slides up the wall off the floor, qdd = (0, (fy - mu_w fx) / m, 0),
 * the wall's slip s = T v = -v_y negative (SF_SLIDE_M), its normal force
 * fx. */
#undef G /* the rows' member below, not gravity */
EXDEX_TEST(sfric_block_in_corner_is_a_lock_or_slides_up_the_wall_per_coulomb)
{
    double h = 0.015, m = 0.1, minv[3] = {1.0 / m, 1.0 / m, 1e4}, mu_w = 0.5, mu_f = 0.4, fx = 1.0;
    const double fys[6] = {-0.8, -0.3, 0.3, 0.49, 0.51, 0.8};
    sf_row rows[4] = {{{-1.0, 0.0, h}, 0.0, 0}, {{-1.0, 0.0, -h}, 0.0, 0},
                      {{0.0, 1.0, -h}, 0.0, 1}, {{0.0, 1.0, h}, 0.0, 1}};
    for (int c = 0; c < 6; c++) {
        double fy = fys[c], acc[3] = {fx * minv[0], fy * minv[1], 0.0}, F[3] = {fx, fy, 0.0};
        sf_stop st[2] = {{{0.0, -1.0, -h}, 0.0, mu_w, SF_ROLL}, {{-1.0, 0.0, -h}, 0.0, mu_f, SF_ROLL}};
        sf_result r;
        ENSURE(sf_solve(4, rows, 2, st, minv, acc, 1e-12, 1e-12, &r) == 1);
        if (fy <= mu_w * fx) {
            double sum[3] = {F[0], F[1], F[2]};
            ENSURE(r.fm[0] == SF_STICK);
            if (fy < -mu_w * fx)
                ENSURE(r.fm[1] == SF_STICK && r.lock == 1 && r.mask == 0xfu && r.margin >= 0.0);
            else
                ENSURE(r.lock == 0 && r.lam[2] == 0.0 && r.lam[3] == 0.0);
            ENSURE_CLOSE(r.qdd[0], 0.0, 1e-14);
            ENSURE_CLOSE(r.qdd[1], 0.0, 1e-14);
            ENSURE_CLOSE(r.qdd[2], 0.0, 1e-13 / h);
            /* the split gives -F, inside the cones */
            for (int i = 0; i < 4; i++) {
                ENSURE(r.lam[i] >= 0.0);
                for (int k = 0; k < 3; k++) sum[k] += r.lam[i] * rows[i].G[k];
            }
            for (int j = 0; j < 2; j++) {
                ENSURE(fabs(r.beta[j]) <= st[j].mu * r.lsum[j] * (1.0 + FRICTION_BAND));
                for (int k = 0; k < 3; k++) sum[k] += r.beta[j] * st[j].T[k];
            }
            ENSURE_CLOSE(fabs(sum[0]) + fabs(sum[1]) + fabs(sum[2]) / h, 0.0, 1e-12);
        } else {
            ENSURE(r.lock == 0 && r.fm[0] == SF_SLIDE_M);
            ENSURE_CLOSE(r.qdd[0], 0.0, 1e-12);
            ENSURE_CLOSE(r.qdd[1], (fy - mu_w * fx) / m, 1e-12);
            ENSURE_CLOSE(r.qdd[2], 0.0, 1e-9);
            ENSURE_CLOSE(r.lam[0] + r.lam[1], fx, 1e-12);
            ENSURE(r.lam[2] == 0.0 && r.lam[3] == 0.0 && r.acc[2] > 0.0 && r.acc[3] > 0.0);
            ENSURE_CLOSE(r.beta[0], mu_w * fx, 1e-12);
        }
        /* both stops given stick (a decided lock): kept, the margin's sign
         * says whether it still holds */
        st[0].fm = st[1].fm = SF_STICK;
        ENSURE(sf_solve(4, rows, 2, st, minv, acc, 1e-12, 1e-12, &r) == 1);
        ENSURE(r.lock == 1 && (r.margin >= 0.0) == (fy <= mu_w * fx));
    }
}

#define G 9.81

/* The lock's rows: three of four rows and two tangents (five constraints,
 * rank 3) give back x; inconsistent or rank-deficient rows are refused. */
EXDEX_TEST(sfric_lock_solve_checks_rank_and_consistency)
{
    double minv[3] = {10.0, 10.0, 1e4}, x[3];
    double C[5][3] = {{-1.0, 0.0, 0.015}, {-1.0, 0.0, -0.015}, {0.0, 1.0, -0.015}, {0.0, -1.0, -0.015},
                      {-1.0, 0.0, -0.015}};
    double x0[3] = {0.3, -0.2, 5.0}, rhs[5];
    for (int l = 0; l < 5; l++) rhs[l] = C[l][0] * x0[0] + C[l][1] * x0[1] + C[l][2] * x0[2];
    ENSURE(sf_lock_solve(5, (const double (*)[3])C, rhs, minv, 1e-12, x) == 1);
    for (int k = 0; k < 3; k++) ENSURE_CLOSE(x[k], x0[k], 1e-12);
    rhs[4] += 1e-6;
    ENSURE(sf_lock_solve(5, (const double (*)[3])C, rhs, minv, 1e-9, x) == 0);
    /* rank 2: only translations along x and y constrained */
    {
        double D[3][3] = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {1.0, 1.0, 0.0}}, r3[3] = {1.0, 2.0, 3.0};
        ENSURE(sf_lock_solve(3, (const double (*)[3])D, r3, minv, 1e-9, x) == 0);
    }
}

/* A planar object of mass 0.1 kg, a square of side 2 cm (disc 0) or a disc
 * of radius 2 cm centred at (4, -2) mm (disc 1), in a gripper turning about
 * a tilted axis (a rotation shake: w and dw change, a stop's or an
 * obstacle's trace in the plate plane turns). */
static exdex_scene_def turning_object(int disc)
{
    exdex_scene_def d = exdex_default_scene_def();
    double verts[4][2] = {{0.01, 0.01}, {-0.01, 0.01}, {-0.01, -0.01}, {0.01, -0.01}};
    d.dof = EXDEX_DOF_PLANAR;
    d.mass = 0.1;
    if (disc) {
        d.disc_radius = 0.02;
        d.disc_center[0] = 0.004;
        d.disc_center[1] = -0.002;
    } else {
        d.n_vertices = 4;
        memcpy(d.vertices, verts, sizeof verts);
    }
    d.motion.kind = EXDEX_MOTION_SHAKE;
    d.motion.rotation = 1;
    d.motion.axis[0] = 0.3;
    d.motion.axis[1] = 1.0;
    d.motion.axis[2] = 0.5;
    d.motion.center[0] = 0.05;
    d.motion.amplitude = 0.3;
    d.motion.frequency = 2.0;
    d.motion.duration = 1.0;
    return d;
}

/* Two obstacles of Coulomb coefficient 0.5: a wedge (two faces tilted out
 * of the plate normal, meeting below, and a floor far below) and a rod of
 * radius 0.01 through (0.2, 0, 0) tilted by 0.2 rad from A's z. */
static void wedge_and_rod(exdex_scene_def *d)
{
    double ca = cos(0.3), sa = sin(0.3), cb = cos(0.2), sb = sin(0.2);
    double n[3][3] = {{ca, 0.1, sa}, {-ca, 0.05, sa}, {0.0, 0.0, -1.0}};
    d->n_obstacles = 2;
    d->obstacles[0].kind = EXDEX_OBSTACLE_POLYTOPE;
    d->obstacles[0].n_faces = 3;
    for (int f = 0; f < 3; f++) {
        double l = sqrt(n[f][0] * n[f][0] + n[f][1] * n[f][1] + n[f][2] * n[f][2]);
        for (int c = 0; c < 3; c++) d->obstacles[0].face_normal[f][c] = n[f][c] / l;
        d->obstacles[0].face_point[f][2] = f == 2 ? -1.0 : -0.5;
    }
    d->obstacles[0].mu = 0.5;
    d->obstacles[1].kind = EXDEX_OBSTACLE_CYLINDER;
    d->obstacles[1].center[0] = 0.2;
    d->obstacles[1].axis[0] = sb;
    d->obstacles[1].axis[2] = cb;
    d->obstacles[1].radius = 0.01;
    d->obstacles[1].mu = 0.5;
}

/* The slip acceleration: along q(t) = q0 + v0 t + qdd t^2 / 2 under a
 * gripper turning about a tilted axis (a rotation shake: w and dw change,
 * the stop's trace in the plate plane turns), ds/dt by a central
 * difference must equal T qdd + sdd0. */
EXDEX_TEST(sfric_slip_acceleration_matches_central_difference)
{
    exdex_scene_def d = turning_object(0);
    const char *bad = NULL;
    int status = 0;
    exdex_model *m;
    d.n_stops = 1;
    d.stop_point[0][2] = -0.02;
    d.stop_normal[0][0] = 0.3;
    d.stop_normal[0][2] = sqrt(1.0 - 0.09);
    d.stop_mu[0] = 0.5;
    m = exdex_model_alloc(&d, &status, &bad);
    ENSURE(m != NULL);
    if (!m) return;
    {
        double q0[3] = {0.001, 0.002, 0.3}, v0[3] = {0.05, -0.02, 1.5}, qdd[3] = {0.7, -1.1, 20.0};
        double t = 0.13, h = 1e-5;
        for (int j = 0; j < 4; j++) {
            double s[2], T[3], tb, sdd0, q[3], v[3];
            exdex_kinematics k;
            for (int e = 0; e < 2; e++) {
                double tau = e ? h : -h;
                for (int c = 0; c < 3; c++) {
                    q[c] = q0[c] + v0[c] * tau + 0.5 * qdd[c] * tau * tau;
                    v[c] = v0[c] + qdd[c] * tau;
                }
                ENSURE(exdex_motion_eval(m->motion, t + tau, &k) == EXDEX_OK);
                s[e] = contact_slip_planar(m, &k, 0, j, q, v, T, &tb, NULL);
            }
            ENSURE(exdex_motion_eval(m->motion, t, &k) == EXDEX_OK);
            contact_slip_planar(m, &k, 0, j, q0, v0, T, &tb, &sdd0);
            ENSURE(fabs(T[0] * qdd[0] + T[1] * qdd[1] + T[2] * qdd[2] + sdd0) > 1e-3); /* not trivially 0 */
            ENSURE_CLOSE((s[1] - s[0]) / (2.0 * h), T[0] * qdd[0] + T[1] * qdd[1] + T[2] * qdd[2] + sdd0, 1e-6);
        }
    }
    exdex_model_free(m);
}

/* The slip along an obstacle's rows whose contact point moves over the
 * object (orow_slip): a section vertex of a tilted box against the square's
 * edges, and a tilted rod's nearest hull point (its vertex and its edge
 * interior), each with its feature held, along the trajectory q(tau) = q0 +
 * v0 tau + qdd tau^2 / 2 in a turning gripper: the central difference of s
 * must equal T qdd + sdd0, and T v + tb must be the slip of contact_tangent
 * at orow_point. */
EXDEX_TEST(sfric_obstacle_row_slip_acceleration_matches_central_difference)
{
    exdex_scene_def d = turning_object(0);
    const char *bad = NULL;
    int status = 0, codes[6], nc = 0;
    exdex_model *m;
    wedge_and_rod(&d);
    m = exdex_model_alloc(&d, &status, &bad);
    ENSURE(m != NULL);
    if (!m) return;
    /* the section vertex of faces 0, 1 against hull edges 0 and 2; the rod
     * against hull vertex 1 and the interior of hull edge 3 */
    codes[nc++] = orow_code(0, OROW_SECTION, 0, 1, 0);
    codes[nc++] = orow_code(0, OROW_SECTION, 0, 1, 2);
    codes[nc++] = orow_code(1, OROW_ROD, 0, 0, 1);
    codes[nc++] = orow_code(1, OROW_ROD, 0, 0, 32 + 3);
    {
        double q0[3] = {0.001, 0.002, 0.3}, v0[3] = {0.05, -0.02, 1.5}, qdd[3] = {0.7, -1.1, 20.0};
        double t = 0.13, h = 1e-5;
        for (int i = 0; i < nc; i++) {
            double s[2], T[3], T2[3], tb, tb2, sdd0, q[3], v[3], s0;
            exdex_kinematics k;
            contact_point cp;
            ENSURE(orow_valid(m, codes[i]));
            for (int e = 0; e < 2; e++) {
                double tau = e ? h : -h;
                for (int c = 0; c < 3; c++) {
                    q[c] = q0[c] + v0[c] * tau + 0.5 * qdd[c] * tau * tau;
                    v[c] = v0[c] + qdd[c] * tau;
                }
                ENSURE(exdex_motion_eval(m->motion, t + tau, &k) == EXDEX_OK);
                s[e] = orow_slip(m, &k, codes[i], q, v, T, &tb, NULL);
            }
            ENSURE(exdex_motion_eval(m->motion, t, &k) == EXDEX_OK);
            s0 = orow_slip(m, &k, codes[i], q0, v0, T, &tb, &sdd0);
            orow_point(m, &k, codes[i], q0, &cp);
            contact_tangent(m, &k, cp.x, cp.vx, cp.nB, T2, &tb2);
            ENSURE_CLOSE(s0, T2[0] * v0[0] + T2[1] * v0[1] + T2[2] * v0[2] + tb2, 1e-15);
            ENSURE(fabs(T[0] * qdd[0] + T[1] * qdd[1] + T[2] * qdd[2] + sdd0) > 1e-3); /* not trivially 0 */
            ENSURE_CLOSE((s[1] - s[0]) / (2.0 * h), T[0] * qdd[0] + T[1] * qdd[1] + T[2] * qdd[2] + sdd0, 1e-6);
        }
    }
    exdex_model_free(m);
}

/* A disc outline's obstacle rows (obstacle_rows.c): the rim point nearest a tilted
 * rod (an envelope over the rim angle) and the centre against a wedge's
 * section vertex, each with its feature held, along q(tau) = q0 + v0 tau +
 * qdd tau^2 / 2 in a turning gripper: the central differences of the gap
 * must give its rate and G qdd + gdd0, those of the slip T qdd + sdd0; a
 * rotation scene's row (orow_1dof) the same with Fq, Fqq, Ft, Ftq, Ftt. */
EXDEX_TEST(sfric_disc_obstacle_rows_match_central_differences)
{
    for (int dof = 0; dof < 2; dof++) {
        exdex_scene_def d = turning_object(1);
        const char *bad = NULL;
        int status = 0, codes[2];
        exdex_model *m;
        d.dof = dof ? EXDEX_DOF_ROTATION : EXDEX_DOF_PLANAR;
        wedge_and_rod(&d);
        m = exdex_model_alloc(&d, &status, &bad);
        ENSURE(m != NULL);
        if (!m) return;
        codes[0] = orow_code(1, OROW_ROD, 0, 0, 0);
        codes[1] = orow_code(0, OROW_SECTION, 0, 1, 0);
        for (int i = 0; i < 2; i++) {
            double t = 0.13, h = 1e-4;
            exdex_kinematics k;
            ENSURE(orow_valid(m, codes[i]));
            if (!dof) {
                double q0[3] = {0.001, 0.002, 0.3}, v0[3] = {0.05, -0.02, 1.5}, qdd[3] = {0.7, -1.1, 20.0};
                double g[3], s[2], Gr[3], gd, gdd0, T[3], tb, sdd0;
                for (int e = 0; e < 3; e++) {
                    double tau = (e - 1) * h, q[3], v[3];
                    for (int c = 0; c < 3; c++) {
                        q[c] = q0[c] + v0[c] * tau + 0.5 * qdd[c] * tau * tau;
                        v[c] = v0[c] + qdd[c] * tau;
                    }
                    ENSURE(exdex_motion_eval(m->motion, t + tau, &k) == EXDEX_OK);
                    g[e] = orow_planar(m, &k, codes[i], q, v, Gr, NULL, NULL);
                    if (e != 1) s[e / 2] = orow_slip(m, &k, codes[i], q, v, T, &tb, NULL);
                }
                ENSURE(exdex_motion_eval(m->motion, t, &k) == EXDEX_OK);
                orow_planar(m, &k, codes[i], q0, v0, Gr, &gd, &gdd0);
                orow_slip(m, &k, codes[i], q0, v0, T, &tb, &sdd0);
                ENSURE_CLOSE((g[2] - g[0]) / (2.0 * h), gd, 1e-6); /* difference error h^2 |g'''| / 6 */
                ENSURE(fabs(Gr[0] * qdd[0] + Gr[1] * qdd[1] + Gr[2] * qdd[2] + gdd0) > 1e-3);
                ENSURE_CLOSE((g[2] - 2.0 * g[1] + g[0]) / (h * h), Gr[0] * qdd[0] + Gr[1] * qdd[1] + Gr[2] * qdd[2] + gdd0,
                             1e-5);
                ENSURE(fabs(T[0] * qdd[0] + T[1] * qdd[1] + T[2] * qdd[2] + sdd0) > 1e-3);
                ENSURE_CLOSE((s[1] - s[0]) / (2.0 * h), T[0] * qdd[0] + T[1] * qdd[1] + T[2] * qdd[2] + sdd0, 1e-6);
            } else {
                double q0 = 0.3, v0 = 1.5, a0 = 20.0, F[3];
                crow c;
                for (int e = 0; e < 3; e++) {
                    double tau = (e - 1) * h;
                    ENSURE(exdex_motion_eval(m->motion, t + tau, &k) == EXDEX_OK);
                    orow_1dof(m, &k, codes[i], q0 + v0 * tau + 0.5 * a0 * tau * tau, &c);
                    F[e] = c.F;
                }
                ENSURE(exdex_motion_eval(m->motion, t, &k) == EXDEX_OK);
                orow_1dof(m, &k, codes[i], q0, &c);
                ENSURE_CLOSE((F[2] - F[0]) / (2.0 * h), c.Fq * v0 + c.Ft, 1e-6);
                ENSURE_CLOSE((F[2] - 2.0 * F[1] + F[0]) / (h * h),
                             c.Fqq * v0 * v0 + 2.0 * c.Ftq * v0 + c.Ftt + c.Fq * a0, 1e-5);
            }
        }
        exdex_model_free(m);
    }
}

/* ------------------------------------------------ the plate as a contact */

/* The plate alone (no rows): qdd = a + M^-1 A w and the patch slip u = A^T
 * qdd = b + W w with b = A^T a, W = A^T M^-1 A (the patch's Delassus
 * matrix), w of maximum dissipation on the ellipsoid at capacity cap: the
 * problem of one friction step (exdex_friction_solve, u+ = b + W p), whose
 * secular-equation solver (eigen-decomposition of E W E, safeguarded
 * Newton) is the reference. A turned frame with the patch off the centre of
 * mass (A: the rotation by 0.7 rad and the patch at (3, -2) mm); caps half
 * and twice the gauge of the stick wrench -W^-1 b: a slip whose wrench and
 * slip agree with the step's to 1e-12, and a stick (the step sticks): the
 * plate holds the object, w the stick wrench, qdd = 0. */
EXDEX_TEST(sfric_plate_alone_is_the_friction_step_of_its_delassus_matrix)
{
    const double th = 0.7, pc[2] = {0.003, -0.002}, m = 0.2, I = 4e-5, e[3] = {1.0, 1.0, 0.006};
    const double c = cos(th), s = sin(th), minv[3] = {1.0 / m, 1.0 / m, 1.0 / I}, a[3] = {1.3, -9.81, 40.0};
    sf_plate pl = {{{c, -s, 0.0}, {s, c, 0.0}, {-pc[1], pc[0], 1.0}}, {e[0], e[1], e[2]}, 0.0};
    double W[9], b[3], Wm[3][3], bs[3], ps[3], g;
    exdex_friction_prep prep;
    for (int i = 0; i < 3; i++) {
        b[i] = 0.0;
        for (int k = 0; k < 3; k++) b[i] += pl.A[k][i] * a[k];
        for (int j = 0; j < 3; j++) {
            W[3 * i + j] = 0.0;
            for (int k = 0; k < 3; k++) W[3 * i + j] += pl.A[k][i] * minv[k] * pl.A[k][j];
            Wm[i][j] = W[3 * i + j];
        }
        bs[i] = -b[i];
    }
    ENSURE(ldp_solve_small(3, Wm, bs, ps) == 1);
    g = sqrt(ps[0] * ps[0] / (e[0] * e[0]) + ps[1] * ps[1] / (e[1] * e[1]) + ps[2] * ps[2] / (e[2] * e[2]));
    ENSURE(exdex_friction_prepare(&prep, W, e) == EXDEX_OK);
    for (int k = 0; k < 2; k++) {
        exdex_friction_result fr;
        sf_result r;
        pl.cap = k ? 2.0 * g : 0.5 * g;
        ENSURE(exdex_friction_solve(&prep, b, pl.cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &fr) == EXDEX_OK);
        ENSURE(fr.stick == k);
        ENSURE(sf_solve_plate(0, NULL, 0, NULL, minv, a, &pl, 1e-12, 1e-12, &r) == 1);
        for (int i = 0; i < 3; i++) {
            double u = 0.0, q = a[i] + minv[i] * (pl.A[i][0] * r.w[0] + pl.A[i][1] * r.w[1] + pl.A[i][2] * r.w[2]);
            for (int j = 0; j < 3; j++) u += pl.A[j][i] * r.qdd[j];
            ENSURE_CLOSE(r.w[i], fr.p[i], 1e-12 * g * e[i]);
            ENSURE_CLOSE(u, fr.u[i], 1e-12 * (k ? fabs(b[i]) : fr.sigma / e[i]));
            ENSURE_CLOSE(r.qdd[i], q, 1e-12 * fabs(a[i]));
        }
        if (k) ENSURE(fabs(r.qdd[0]) + fabs(r.qdd[1]) <= 1e-12 * fabs(a[1]) && fabs(r.qdd[2]) <= 1e-12 * fabs(a[2]));
    }
}

/* A square (half side h, mass m, the patch at its centre, frame unturned:
 * A = I) standing on a floor (normal +y) with friction mu, gravity tilted
 * toward +x by beta (tan beta 0.8), plate capacity C = 0.1 m g, from rest.
 * Rows: the lower corners (+-h, -h), G = (0, 1, x_j); the floor's tangent
 * t = e_z x n = (-1, 0), T = (-1, 0, -h). The weight along the floor, m g
 * sin beta = 0.625 m g, exceeds what both frictions take, mu m g cos beta +
 * C = 0.334 m g (mu 0.3), so the square slides along +x (slip T v < 0:
 * SF_SLIDE_M), both corners on the floor, not turning. Closed form: the
 * normal force N = m g cos beta, the stop's friction -mu N along x, the
 * plate's wrench w = (-C, 0, 0) (the slip u = (a_x, 0, 0)), a_x = g sin beta
 * - mu g cos beta - C / m, and no moment about the centre: lam_R - lam_L =
 * mu N (the floor's friction at the corners' depth h). The stick is tried
 * first and refused: at qdd = 0 the plate has no slip. The mode decided
 * again from rolling without the plate, at its own plate wrench, is the
 * same (consistent at its own wrench). */
EXDEX_TEST(sfric_plate_and_floor_friction_slide_a_square_closed_form)
{
    const double h = 0.02, m = 0.2, mu = 0.3, tb = 0.8, cb = 1.0 / sqrt(1.0 + tb * tb), sb = tb * cb;
    const double minv[3] = {1.0 / m, 1.0 / m, 6.0 / (m * 4.0 * h * h)}, a[3] = {G * sb, -G * cb, 0.0};
    const double C = 0.1 * m * G, N = m * G * cb, ax = G * sb - mu * G * cb - C / m;
    sf_row rows[2] = {{{0.0, 1.0, h}, 0.0, 0}, {{0.0, 1.0, -h}, 0.0, 0}};
    sf_stop st = {{-1.0, 0.0, -h}, 0.0, mu, SF_ROLL};
    sf_plate pl = {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}, {1.0, 1.0, 0.006}, C};
    sf_result r, r2;
    double aw[3];
    ENSURE(ax > 0.0);
    ENSURE(sf_solve_plate(2, rows, 1, &st, minv, a, &pl, 1e-12, 1e-12, &r) == 1);
    ENSURE(r.fm[0] == SF_SLIDE_M && r.lock == 0);
    ENSURE_CLOSE(r.qdd[0], ax, 1e-12 * G);
    ENSURE_CLOSE(r.qdd[1], 0.0, 1e-12 * G);
    ENSURE_CLOSE(r.qdd[2], 0.0, 1e-12 * G / h);
    ENSURE_CLOSE(r.w[0], -C, 1e-12 * C);
    ENSURE_CLOSE(r.w[1], 0.0, 1e-12 * C);
    ENSURE_CLOSE(r.w[2], 0.0, 1e-12 * C * h);
    ENSURE_CLOSE(r.lam[0], N * (1.0 + mu) / 2.0, 1e-12 * N);
    ENSURE_CLOSE(r.lam[1], N * (1.0 - mu) / 2.0, 1e-12 * N);
    ENSURE_CLOSE(r.beta[0], mu * N, 1e-12 * N);
    for (int i = 0; i < 3; i++) aw[i] = a[i] + minv[i] * r.w[i];
    ENSURE(sf_solve(2, rows, 1, &st, minv, aw, 1e-12, 1e-12, &r2) == 1);
    ENSURE(r2.fm[0] == r.fm[0] && r2.lock == 0);
}

/* The decisions that the plate as one more contact changes on zoo-inputs
 * scenes 0 .. 1499 (tests/scenarios/test_zoo_inputs.py, input_scene; event
 * runs of zoo.run): small slips of seeds 384 and 1274, each against one
 * contact-set row of a frictional stop (group 1; group 0, without rows, is
 * left as given). Each problem as the decision formed it (hybrid_laws.c,
 * hyb_sf_solve_plate: the rows, the groups with their given or rolling
 * modes, M^-1, the acceleration without stops and plate friction, the
 * plate's A, E and capacity, the sign slacks), its rolling group's mode
 * decided by the combination search (old) and by the joint problem (new):
 *   384, 20 decisions like the first two: old slide +, new slide -;
 *   384, 1 decision: old slide +, new stick;
 *   1274, 3 decisions: old slide -, new stick;
 *   1274, 1 decision: old stick, new slide -.
 * The joint mode is consistent at its own plate wrench: the problem
 * without the plate, solved from rolling on the acceleration with that
 * wrench, decides it again, and the wrench is the maximum-dissipation
 * wrench of the mode's own slip u = A^T qdd, on the ellipsoid (to the
 * rounding of u, rho = |a| / |qdd| times that of the accelerations it is
 * formed from: 1e-12 rho cap; rho is 1e4 for seed 384's near-stick slips).
 * Between decisions the plate's friction is that joint problem's on the
 * decided modes: with the new mode given it returns the decision's wrench.
 * The old mode is not consistent: with it given, the joint problem has no solution,
 * or one at whose wrench the problem from rolling decides another mode; and
 * the plain fixed-point iteration of the plate wrench with it given (from
 * the plate's own friction step, 16 steps) does not settle: its last step
 * still moves the wrench by more than cap (a 2-cycle for seed 384), or a
 * step finds no mode at all. */
typedef struct zoo_decision {
    int seed, nr, ns, old_fm[2], new_fm[2];
    sf_row rows[1];
    sf_stop st[2];
    double minv[3], a[3];
    sf_plate pl;
    double tol_a, tol_f;
} zoo_decision;

static const zoo_decision ZOO_DECISIONS[] = {
    {384, 1, 2, {0, 2}, {0, 3}, {{{-0.59476947534023994, -0.79971052423316957, -0.009770776822244245}, 0.0020468970334288129, 1},}, {{{0, 0, 0}, 0, 0.85473336389789778, 0}, {{0.80240807997854013, -0.59677573106247594, -0.027163867575185113}, 0.0017196412702898309, 0.76468665627995636, 0},}, {11.947446712726482, 11.947446712726482, 42976.997637724038}, {1.7403117661544618, -9.6516878283712657, -0}, {{{0.99992033226663957, 0.012622563914402623, 0}, {-0.012622563914402623, 0.99992033226663957, 0}, {-0.0053032936912274968, 0.00022981836521636983, 1}}, {1, 1, 0.0008770618933975423}, 1.0826143381873499}, 1.2934477115927008e-09, 1.0826143381873497e-10},
    {384, 1, 2, {0, 2}, {0, 3}, {{{-0.59476947534023994, -0.79971052423316957, -0.0097707767706389642}, 0.0018642417807663053, 1},}, {{{0, 0, 0}, 0, 0.85473336389789778, 0}, {{0.80240807997854013, -0.59677573106247594, -0.027163867593872848}, 0.0015661887024127359, 0.76468665627995636, 0},}, {11.947446712726482, 11.947446712726482, 42976.997637724038}, {1.7403260777781324, -9.6519257214179444, -0}, {{{0.99992033229070043, 0.012622562008369578, 0}, {-0.012622562008369578, 0.99992033229070043, 0}, {-0.0053032936912274968, 0.00022981836521636983, 1}}, {1, 1, 0.0008770618933975423}, 1.0826143381873499}, 1.2934477115927008e-09, 1.0826143381873497e-10},
    {384, 1, 2, {0, 2}, {0, 1}, {{{-0.59476947534023994, -0.79971052423316957, -0.0097707754397396776}, -0.0019436538813743115, 1},}, {{{0, 0, 0}, 0, 0.85473336389789778, 0}, {{0.80240807997854013, -0.59677573106247594, -0.027163868075829087}, -0.0016329049434936262, 0.76468665627995636, 0},}, {11.947446712726482, 11.947446712726482, 42976.997637724038}, {1.7406244385521656, -9.6568851834033342, -0}, {{{0.99992033291123039, 0.012622512851811681, 0}, {-0.012622512851811681, 0.99992033291123039, 0}, {-0.0053032936912274968, 0.00022981836521636983, 1}}, {1, 1, 0.0008770618933975423}, 1.0826143381873499}, 1.2934477115927008e-09, 1.0826143381873497e-10},
    {1274, 1, 2, {0, 3}, {0, 1}, {{{0.56195406133042647, 0.48302188084388947, -0.00077092262034442985}, 0.61957830284841653, 1},}, {{{0, 0, 0}, 0, 0.87736098558802822, 0}, {{-0.65183862684782379, 0.7583577022415896, -0.0013784347171699337}, 5.2869427658692105, 0.40350869281985446, 0},}, {10207.591189772253, 10207.591189772253, 8224379498.5535946}, {3.7381516025978758, -11.755339057018253, -0}, {{{-0.99798594633800253, 0.063435407398719834, 0}, {-0.063435407398719834, -0.99798594633800253, -0}, {5.4291596621347249e-05, -0.0009345726422170179, 1}}, {1, 1, 6.7527998674026782e-05}, 0.0019934550799390379}, 2.0348374511192469e-09, 1.9934550799390379e-13},
    {1274, 1, 2, {0, 1}, {0, 3}, {{{0.56195406133042647, 0.48302188084388947, -0.00070711838940932332}, -0.61957830284455417, 1},}, {{{0, 0, 0}, 0, 0.87736098558802822, 0}, {{-0.65183862684782379, 0.7583577022415896, -0.0014393841220628973}, -5.2869427660274777, 0.40350869281985446, 0},}, {10207.591189772253, 10207.591189772253, 8224379498.5535946}, {-7.3346388771581008, -7.3297059022906197, -0}, {{{-0.9922508283452508, 0.12425093017021517, 0}, {-0.12425093017021517, -0.9922508283452508, -0}, {5.4291596621347249e-05, -0.0009345726422170179, 1}}, {1, 1, 6.7527998674026782e-05}, 0.0019934550799390379}, 2.0348374511192469e-09, 1.9934550799390379e-13},
};

/* a + M^-1 A w */
static void plate_acc_of(const zoo_decision *z, const double w[3], double aw[3])
{
    for (int c = 0; c < 3; c++)
        aw[c] = z->a[c] + z->minv[c] * (z->pl.A[c][0] * w[0] + z->pl.A[c][1] * w[1] + z->pl.A[c][2] * w[2]);
}

/* the maximum-dissipation wrench -cap E^2 u / |E u| of u = A^T qdd */
static void plate_maxdiss(const sf_plate *pl, const double qdd[3], double w[3])
{
    double eu[3], n;
    for (int j = 0; j < 3; j++) eu[j] = pl->e[j] * (pl->A[0][j] * qdd[0] + pl->A[1][j] * qdd[1] + pl->A[2][j] * qdd[2]);
    n = sqrt(eu[0] * eu[0] + eu[1] * eu[1] + eu[2] * eu[2]);
    for (int j = 0; j < 3; j++) w[j] = -pl->cap * pl->e[j] * eu[j] / n;
}

EXDEX_TEST(sfric_plate_joint_modes_of_zoo_inputs_384_and_1274_are_consistent_at_their_own_wrench)
{
    const int n = (int)(sizeof ZOO_DECISIONS / sizeof ZOO_DECISIONS[0]);
    for (int i = 0; i < n; i++) {
        const zoo_decision *z = &ZOO_DECISIONS[i];
        sf_stop given[2];
        sf_result r, r2, ro, ro2;
        double aw[3], wd[3], rho, g = 0.0, w[3], W[9], b[3], d = 0.0;
        exdex_friction_prep prep;
        exdex_friction_result fr;
        int okg, settled = 0;
        /* new: the joint problem's mode, consistent at its own wrench */
        ENSURE(sf_solve_plate(z->nr, z->rows, z->ns, z->st, z->minv, z->a, &z->pl, z->tol_a, z->tol_f, &r) == 1);
        ENSURE(r.fm[1] == z->new_fm[1] && r.lock == 0);
        plate_acc_of(z, r.w, aw);
        ENSURE(sf_solve(z->nr, z->rows, z->ns, z->st, z->minv, aw, z->tol_a, z->tol_f, &r2) == 1);
        ENSURE(r2.fm[1] == z->new_fm[1]);
        rho = hypot(z->a[0], z->a[1]) / hypot(r.qdd[0], r.qdd[1]);
        plate_maxdiss(&z->pl, r.qdd, wd);
        for (int j = 0; j < 3; j++) {
            ENSURE_CLOSE(r.w[j], wd[j], 1e-12 * rho * z->pl.cap * z->pl.e[j]);
            g += (r.w[j] / z->pl.e[j]) * (r.w[j] / z->pl.e[j]);
        }
        ENSURE_CLOSE(sqrt(g), z->pl.cap, 1e-12 * z->pl.cap);
        /* between decisions the plate's friction is the joint problem's on
         * the decided modes (hyb_planar_friction): with the new mode given
         * it is the decision's wrench */
        memcpy(given, z->st, sizeof given);
        given[1].fm = z->new_fm[1];
        ENSURE(sf_solve_plate(z->nr, z->rows, z->ns, given, z->minv, z->a, &z->pl, z->tol_a, z->tol_f, &ro) == 1);
        for (int j = 0; j < 3; j++) ENSURE_CLOSE(ro.w[j], r.w[j], 1e-12 * z->pl.cap * z->pl.e[j]);
        /* old: with its mode given, no joint solution or another decision there */
        memcpy(given, z->st, sizeof given);
        given[1].fm = z->old_fm[1];
        okg = sf_solve_plate(z->nr, z->rows, z->ns, given, z->minv, z->a, &z->pl, z->tol_a, z->tol_f, &ro);
        if (okg) {
            plate_acc_of(z, ro.w, aw);
            ENSURE(sf_solve(z->nr, z->rows, z->ns, z->st, z->minv, aw, z->tol_a, z->tol_f, &ro2) == 1);
            ENSURE(ro2.fm[1] != z->old_fm[1]);
        }
        /* old: the plain iteration with its mode given does not settle */
        for (int p = 0; p < 3; p++) {
            b[p] = 0.0;
            for (int c = 0; c < 3; c++) b[p] += z->pl.A[c][p] * z->a[c];
            for (int q = 0; q < 3; q++) {
                W[3 * p + q] = 0.0;
                for (int c = 0; c < 3; c++) W[3 * p + q] += z->pl.A[c][p] * z->minv[c] * z->pl.A[c][q];
            }
        }
        ENSURE(exdex_friction_prepare(&prep, W, z->pl.e) == EXDEX_OK);
        ENSURE(exdex_friction_solve(&prep, b, z->pl.cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &fr) == EXDEX_OK);
        memcpy(w, fr.p, sizeof w);
        for (int it = 0; it < 16; it++) {
            sf_result q;
            double wn[3];
            plate_acc_of(z, w, aw);
            if (!sf_solve(z->nr, z->rows, z->ns, given, z->minv, aw, z->tol_a, z->tol_f, &q)) {
                d = INFINITY;
                break;
            }
            plate_maxdiss(&z->pl, q.qdd, wn);
            d = 0.0;
            for (int j = 0; j < 3; j++) {
                d = fmax(d, fabs(wn[j] - w[j]) / z->pl.e[j]);
                w[j] = wn[j];
            }
            if (d <= 1e-12 * z->pl.cap) settled = 1;
        }
        ENSURE(!settled && d > z->pl.cap);
    }
}

/* sf_residual (tests/sf_residual.h) on the square sliding on its frictional
 * floor above, at the closed form written out by hand (no solver): every
 * condition holds to rounding; each condition, broken alone, shows in its
 * own part: the wrench turned by 0.1 rad (mdp), scaled by 1.1 (gauge), a
 * corner's force moved by 10% (Newton-Euler), a corner given a gap
 * acceleration while it carries force (complementarity), the floor's
 * friction halved (Coulomb), the floor's mode given as a stick while it
 * slides (Coulomb: its slip acceleration is not 0) and given as the slide
 * of the other sign (guard). */
EXDEX_TEST(sfric_residual_is_rounding_at_a_closed_form_and_sees_each_condition_broken)
{
    const double h = 0.02, m = 0.2, mu = 0.3, tb = 0.8, cb = 1.0 / sqrt(1.0 + tb * tb), sb = tb * cb;
    const double minv[3] = {1.0 / m, 1.0 / m, 6.0 / (m * 4.0 * h * h)}, a[3] = {G * sb, -G * cb, 0.0};
    const double C = 0.1 * m * G, N = m * G * cb, ax = G * sb - mu * G * cb - C / m, s0 = 0.0;
    sf_row rows[2] = {{{0.0, 1.0, h}, 0.0, 0}, {{0.0, 1.0, -h}, 0.0, 0}};
    sf_stop st = {{-1.0, 0.0, -h}, 0.0, mu, SF_ROLL};
    const sf_plate pl = {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}, {1.0, 1.0, 0.006}, C};
    const double qdd[3] = {ax, 0.0, 0.0}, w[3] = {-C, 0.0, 0.0}, beta[1] = {mu * N};
    const double lam[2] = {N * (1.0 + mu) / 2.0, N * (1.0 - mu) / 2.0};
    sfr_problem p = {2, 1, rows, &st, &s0, 1e-9, minv, a, &pl};
    double part[SFR_N], wt[3] = {-C * cos(0.1), -C * sin(0.1), 0.0}, ws[3] = {-1.1 * C, 0.0, 0.0};
    double lm[2] = {1.1 * lam[0], lam[1]}, bh[1] = {0.5 * beta[0]};
    ENSURE(sf_residual(&p, qdd, lam, beta, w, part) <= 1e-15);
    ENSURE(part[SFR_GUARD] == 0.0);
    sf_residual(&p, qdd, lam, beta, wt, part);
    ENSURE(part[SFR_MDP] > 0.01);
    sf_residual(&p, qdd, lam, beta, ws, part);
    ENSURE(part[SFR_GAUGE] > 0.05 && part[SFR_MDP] <= 1e-15);
    sf_residual(&p, qdd, lm, beta, w, part);
    ENSURE(part[SFR_NE] > 0.01);
    rows[0].gdd0 = 0.1 * G;
    sf_residual(&p, qdd, lam, beta, w, part);
    ENSURE(part[SFR_COMPL] > 0.01);
    rows[0].gdd0 = 0.0;
    sf_residual(&p, qdd, lam, bh, w, part);
    ENSURE(part[SFR_COUL] > 0.01);
    st.fm = SF_STICK;
    sf_residual(&p, qdd, lam, beta, w, part);
    ENSURE(part[SFR_COUL] > 0.1 && part[SFR_GUARD] == 0.0);
    st.fm = SF_SLIDE_P;
    sf_residual(&p, qdd, lam, beta, w, part);
    ENSURE(part[SFR_GUARD] > 0.1);
}

/* Small-slip states against frictional stops captured at the right-hand
 * side of event runs of zoo-inputs scenes (tests/scenarios/test_zoo_inputs.py,
 * input_scene; zoo.run), on the runs the joint problem changes, at states
 * where the plate's friction of the joint problem and that of the
 * fixed-point iteration differ (old = 0: along the run with the joint
 * problem, 1: along the run with the iteration), every stop's mode as the
 * last decision gave it (and the slide of its sign for a rolling group
 * above zsw), each inside the guards of its modes: the rows, the groups
 * (their slips s), zsw, M^-1, the acceleration without stops and plate
 * friction, the plate, the sign slacks; two per run (the least and the
 * largest residual of the iteration) on the joint problem's runs, one on
 * the iteration's. */
typedef struct zoo_state {
    int seed, old, nr, ns;
    sf_row rows[2];
    sf_stop st[2];
    double s[2], zsw, minv[3], a[3];
    sf_plate pl;
    double tol_a, tol_f;
} zoo_state;

static const zoo_state ZOO_STATES[] = {
    {624, 0, 1, 1, {{{0.7473448523550161, -0.6644363563641434, -5.1457545600529144e-05}, -4.898023710680008, 0}}, {{{0.6644363563641436, 0.7473448523550162, -0.0006598778764606026}, -3.403488968764735, 0.6950686189651535, 3}}, {-0.009558528421698617}, 9.947413019690234e-08, {198557.79620505153, 198557.79620505153, 908290917023.9247}, {4.473663167166148, -10.339602206788992, -0.0}, {{{0.6934266857101302, 0.7205271900109421, 0.0}, {-0.7205271900109421, 0.6934266857101302, 0.0}, {-0.0002732323444253126, -0.0002358641078203496, 1.0}}, {1.0, 1.0, 9.941787745615614e-05}, 7.529277902427991e-05}, 1.4949968273214951e-09, 7.5292779024279919e-15},
    {624, 0, 1, 1, {{{0.7473448523550161, -0.6644363563641434, -4.774654170074729e-05}, -4.903990828737451, 0}}, {{{0.6644363563641436, 0.7473448523550162, -0.0006601567681975271}, -3.403023650467971, 0.6950686189651535, 3}}, {-9.861569645937838e-08}, 9.947413019690234e-08, {198557.79620505153, 198557.79620505153, 908290917023.9247}, {4.473663167166148, -10.339602206788992, -0.0}, {{{0.697466918778339, 0.716616980827171, 0.0}, {-0.716616980827171, 0.697466918778339, 0.0}, {-0.0002732323444253126, -0.0002358641078203496, 1.0}}, {1.0, 1.0, 9.941787745615614e-05}, 7.529277902427991e-05}, 1.4949968273214951e-09, 7.5292779024279919e-15},
    {667, 0, 1, 1, {{{0.1547902584813055, 0.9879473548116269, 0.0010540578109070884}, 2.3155063282962742, 0}}, {{{-0.9879473548116269, 0.1547902584813055, -0.0008478343628850153}, 1.639822324167388, 0.39781747953585656, 2}}, {1.5134434939595138e-07}, 1.15196431920562e-07, {204451.8348066437, 204451.8348066437, 335192406740.70624}, {3.577896838768584, -11.917126440184225, -0.0}, {{{0.17244770980224458, -0.9850186736219577, 0.0}, {0.9850186736219577, 0.17244770980224458, 0.0}, {-0.0005711322149370651, -0.00027955541287552415, 1.0}}, {1.0, 1.0, 5.0039529734723304e-05}, 3.895108862346699e-05}, 9.8100000000000002e-10, 4.7981961175734209e-15},
    {667, 0, 1, 1, {{{0.1547902584813055, 0.9879473548116269, 0.0010540578109021809}, 2.315506328300462, 0}}, {{{-0.9879473548116269, 0.1547902584813055, -0.0008478343628911167}, 1.6398223241725944, 0.39781747953585656, 2}}, {1.7151727006006863e-07}, 1.15196431920562e-07, {204451.8348066437, 204451.8348066437, 335192406740.70624}, {3.577896838768584, -11.917126440184225, -0.0}, {{{0.17244770980794613, -0.9850186736209595, 0.0}, {0.9850186736209595, 0.17244770980794613, 0.0}, {-0.0005711322149370651, -0.00027955541287552415, 1.0}}, {1.0, 1.0, 5.0039529734723304e-05}, 3.895108862346699e-05}, 9.8100000000000002e-10, 4.7981961175734209e-15},
    {443, 0, 1, 1, {{{0.2819914255864189, 0.9594169249579346, 0.0034691110872041688}, -2.553991862300096, 0}}, {{{-0.9594169249579346, 0.28199142558641893, -0.0050403537245066864}, 5.97624069741346, 0.7754758861445661, 1}}, {-5.467761729494036e-10}, 2.91556394272971e-07, {547.237455818648, 547.237455818648, 24326627.73024033}, {8.995257859065205, -8.458666242370928, -0.0}, {{{-0.9594169249579346, -0.2819914255864189, -0.0}, {0.2819914255864189, -0.9594169249579346, 0.0}, {-0.0004939836408052352, 0.004131598327491129, 1.0}}, {1.0, 1.0, 0.0017380097268453606}, 0.007699736121447682}, 9.8100000000000002e-10, 1.7926404517257661e-12},
    {443, 0, 1, 1, {{{0.2885745276220479, 0.9574574361336967, 0.0035037610984191975}, -2.5950984349019306, 0}}, {{{-0.9574574361336968, 0.2885745276220477, -0.0050403537245066864}, 5.9423265887161465, 0.7754758861445661, 1}}, {5.197139160001418e-12}, 2.91556394272971e-07, {547.237455818648, 547.237455818648, 24326627.73024033}, {8.995257859065205, -8.458666242370928, -0.0}, {{{-0.9574574361336967, -0.28857452762204777, -0.0}, {0.28857452762204777, -0.9574574361336967, 0.0}, {-0.0004939836408052352, 0.004131598327491129, 1.0}}, {1.0, 1.0, 0.0017380097268453606}, 0.007699736121447682}, 9.8100000000000002e-10, 1.7926404517257661e-12},
    {489, 0, 1, 2, {{{0.5291657994885455, 0.5730530120196877, -0.05614453658909988}, 0.0, 0}}, {{{-0.7346796065640974, 0.678414236067333, -0.07002214041305103}, 0.0, 0.13009183973022856, 0}, {{0.0, 0.0, 0.0}, 0.0, 0.3241332240466901, 0}}, {0.0, 0.0}, 3.7966635355755953e-06, {0.2617599914593973, 0.2617599914593973, 77.87236680434764}, {-3.718742707600958, -8.555742758472554, -0.0}, {{{-0.6664553067262408, 0.7455449846497744, 0.0}, {-0.7455449846497744, -0.6664553067262408, -0.0}, {0.03993267751864707, -0.03698600588753482, 1.0}}, {1.0, 1.0, 0.015320514385913}, 22.68085879553595}, 1.4354353868762759e-08, 5.4837845114268819e-08},
    {489, 0, 1, 2, {{{0.5291657994885455, 0.5730530120196877, -0.05614453661044036}, 1.5674038153966438e-09, 0}}, {{{-0.7346796065640974, 0.678414236067333, -0.07002214038492668}, -2.0656626163491227e-09, 0.13009183973022856, 2}, {{0.0, 0.0, 0.0}, 0.0, 0.3241332240466901, 0}}, {1.327103977305789e-05, 0.0}, 3.7966635355755953e-06, {0.2617599914593973, 0.2617599914593973, 77.87236680434764}, {-3.718742707600958, -8.555742758472554, -0.0}, {{{-0.6664553070175443, 0.7455449843893732, 0.0}, {-0.7455449843893732, -0.6664553070175443, -0.0}, {0.03993267751864707, -0.03698600588753482, 1.0}}, {1.0, 1.0, 0.015320514385913}, 22.68085879553595}, 1.4354353868762759e-08, 5.4837845114268819e-08},
    {418, 0, 1, 2, {{{-0.09148162524205337, -0.5648322243639404, -0.0001369220431551916}, -5.840603619522908, 1}}, {{{0.0, 0.0, 0.0}, 0.0, 0.5113467654940972, 0}, {{0.9871366051268922, -0.159879088121475, -0.0006370313321056884}, -2.532784301872345, 0.666243544105049, 1}}, {0.0, -7.341515988059863e-05}, 1.3484613724429032e-07, {562103.8103194013, 562103.8103194013, 3641587878194.7017}, {0.2664128888964823, -14.983824009475175, -0.0}, {{{-0.8870606755731575, 0.46165285426572783, 0.0}, {-0.46165285426572783, -0.8870606755731575, -0.0}, {-8.60064316382655e-05, -0.00021426244687163863, 1.0}}, {1.0, 1.0, 0.0001222600158929972}, 4.7537572063505543e-05}, 2.6721050390229599e-09, 4.7537572063505558e-15},
    {418, 0, 1, 2, {{{-0.09148162524205337, -0.5648322243639404, -0.00013907896384149427}, 12.039281703208326, 1}}, {{{0.0, 0.0, 0.0}, 0.0, 0.5113467654940972, 0}, {{0.9871366051268922, -0.159879088121475, -0.0006356025798386724}, 5.176861315802278, 0.666243544105049, 1}}, {0.0, -0.001861767610381764}, 1.3484613724429032e-07, {562103.8103194013, 562103.8103194013, 3641587878194.7017}, {-4.797541526781751, 1.950552577390237, -0.0}, {{{-0.8897799393656209, 0.4563898109100509, 0.0}, {-0.4563898109100509, -0.8897799393656209, -0.0}, {-8.60064316382655e-05, -0.00021426244687163863, 1.0}}, {1.0, 1.0, 0.0001222600158929972}, 4.7537572063505543e-05}, 2.6721050390229599e-09, 4.7537572063505558e-15},
    {384, 0, 1, 2, {{{-0.5947694753402397, -0.7997105242331694, -0.00977079419170561}, 0.01549835781470393, 1}}, {{{0.0, 0.0, 0.0}, 0.0, 0.8547333638978978, 0}, {{0.8024080799785402, -0.5967757310624758, -0.027163861285205468}, 0.013020451800568034, 0.7646866562799564, 3}}, {0.0, -1.3951014374683016e-05}, 6.111734918131621e-07, {11.947446712726482, 11.947446712726482, 42976.99763772404}, {1.7392578042971774, -9.634168488448093, -0.0}, {{{0.9999203241679286, 0.012623205452831463, 0.0}, {-0.012623205452831463, 0.9999203241679286, 0.0}, {-0.005303293691227497, 0.00022981836521636983, 1.0}}, {1.0, 1.0, 0.0008770618933975423}, 1.0826143381873499}, 1.2934477115927008e-09, 1.0826143381873497e-10},
    {384, 0, 1, 2, {{{-0.5947694753402399, -0.7997105242331696, -0.009770800769510151}, 0.04239478335242281, 1}}, {{{0.0, 0.0, 0.0}, 0.0, 0.8547333638978978, 0}, {{0.8024080799785401, -0.596775731062476, -0.027163858903190674}, 0.035616743746123655, 0.7646866562799564, 3}}, {0.0, -6.363000052969071e-06}, 6.111734918131621e-07, {11.947446712726482, 11.947446712726482, 42976.99763772404}, {1.7371503811885338, -9.5991381301097, -0.0}, {{{0.9999203211008438, 0.012623448403084644, 0.0}, {-0.012623448403084644, 0.9999203211008438, 0.0}, {-0.005303293691227497, 0.00022981836521636983, 1.0}}, {1.0, 1.0, 0.0008770618933975423}, 1.0826143381873499}, 1.2934477115927008e-09, 1.0826143381873497e-10},
    {1274, 0, 1, 2, {{{0.5619540613304265, 0.4830218808438895, -0.0007709226203444299}, 0.6195783028484165, 1}}, {{{0.0, 0.0, 0.0}, 0.0, 0.8773609855880282, 0}, {{-0.6518386268478238, 0.7583577022415896, -0.0013784347171699337}, 5.2869427658692105, 0.40350869281985446, 0}}, {0.0, 1.370056415023503e-07}, 1.874595403080946e-07, {10207.591189772253, 10207.591189772253, 8224379498.553595}, {3.738151602597876, -11.755339057018253, -0.0}, {{{-0.9979859463380025, 0.06343540739871983, 0.0}, {-0.06343540739871983, -0.9979859463380025, -0.0}, {5.429159662134725e-05, -0.0009345726422170179, 1.0}}, {1.0, 1.0, 6.752799867402678e-05}, 0.001993455079939038}, 2.0348374511192469e-09, 1.9934550799390379e-13},
    {1274, 0, 1, 2, {{{0.5619540613304265, 0.4830218808438895, -0.0007697364587381842}, 0.5820535430307231, 1}}, {{{0.0, 0.0, 0.0}, 0.0, 0.8773609855880282, 0}, {{-0.6518386268478238, 0.7583577022415896, -0.0013796413933481952}, 4.93472529533233, 0.40350869281985446, 1}}, {0.0, 2.469685794412313e-09}, 1.874595403080946e-07, {10207.591189772253, 10207.591189772253, 8224379498.553595}, {3.372882642406748, -11.609346371292803, -0.0}, {{{-0.9979116410193742, 0.06459378234799035, 0.0}, {-0.06459378234799035, -0.9979116410193742, -0.0}, {5.429159662134725e-05, -0.0009345726422170179, 1.0}}, {1.0, 1.0, 6.752799867402678e-05}, 0.001993455079939038}, 2.0348374511192469e-09, 1.9934550799390379e-13},
    {384, 1, 1, 2, {{{-0.5947694753402399, -0.7997105242331696, -0.009770801774611485}, 0.05310991934969484, 1}}, {{{0.0, 0.0, 0.0}, 0.0, 0.8547333638978978, 0}, {{0.8024080799785401, -0.596775731062476, -0.027163858539214016}, 0.044618765532494956, 0.7646866562799564, 3}}, {0.0, -7.831772907035741e-07}, 6.111734918131621e-07, {11.947446712726482, 11.947446712726482, 42976.99763772404}, {1.7363108154796358, -9.585182561571667, -0.0}, {{{0.9999203206321821, 0.012623485526358133, 0.0}, {-0.012623485526358133, 0.9999203206321821, 0.0}, {-0.005303293691227497, 0.00022981836521636983, 1.0}}, {1.0, 1.0, 0.0008770618933975423}, 1.0826143381873499}, 1.2934477115927008e-09, 1.0826143381873497e-10},
    {1274, 1, 1, 2, {{{0.5619540613304265, 0.4830218808438895, -0.0007594979329619141}, 0.9756189231286985, 1}}, {{{0.0, 0.0, 0.0}, 0.0, 0.8773609855880282, 0}, {{-0.6518386268478238, 0.7583577022415896, -0.0013899368218167946}, 4.558056297643267, 0.40350869281985446, 1}}, {0.0, -3.6117776321814565e-09}, 1.874595403080946e-07, {10207.591189772253, 10207.591189772253, 8224379498.553595}, {3.3868635719816442, -11.614934345306553, -0.0}, {{{-0.9972174933807723, 0.07454710521119855, 0.0}, {-0.07454710521119855, -0.9972174933807723, -0.0}, {5.429159662134725e-05, -0.0009345726422170179, 1.0}}, {1.0, 1.0, 6.752799867402678e-05}, 0.001993455079939038}, 2.0348374511192469e-09, 1.9934550799390379e-13},
    {667, 1, 1, 1, {{{0.1547902584813055, 0.9879473548116269, 0.0010540578109058418}, 2.315506328300287, 0}}, {{{-0.9879473548116269, 0.1547902584813055, -0.000847834362886565}, 1.6398223241723762, 0.39781747953585656, 2}}, {1.1827063765254565e-07}, 1.15196431920562e-07, {204451.8348066437, 204451.8348066437, 335192406740.70624}, {3.577896838768584, -11.917126440184225, -0.0}, {{{0.17244770980369273, -0.9850186736217041, 0.0}, {0.9850186736217041, 0.17244770980369273, 0.0}, {-0.0005711322149370651, -0.00027955541287552415, 1.0}}, {1.0, 1.0, 5.0039529734723304e-05}, 3.895108862346699e-05}, 9.8100000000000002e-10, 4.7981961175734209e-15},
};

/* The right-hand side between decisions (hybrid_laws.c): the plate's
 * wrench w of the joint problem on the given modes (hyb_planar_friction),
 * then the stops' problem on the acceleration with that wrench
 * (hyb_contact_acc_planar). Returns 0 if either has no solution. */
static int rhs_joint(const zoo_state *z, sf_result *q, double w[3])
{
    sf_result jr;
    double aw[3];
    if (!sf_solve_plate(z->nr, z->rows, z->ns, z->st, z->minv, z->a, &z->pl, z->tol_a, z->tol_f, &jr)) return 0;
    memcpy(w, jr.w, 3 * sizeof *w);
    for (int c = 0; c < 3; c++)
        aw[c] = z->a[c] + z->minv[c] * (z->pl.A[c][0] * w[0] + z->pl.A[c][1] * w[1] + z->pl.A[c][2] * w[2]);
    return sf_solve(z->nr, z->rows, z->ns, z->st, z->minv, aw, z->tol_a, z->tol_f, q);
}

/* The right-hand side with the fixed-point iteration of the plate's wrench
 * in place of the joint problem: from the plate's own friction step, w <-
 * the maximum-dissipation wrench of the slip of the stops' problem on the
 * acceleration with w, at most SMALL_SLIP_FIX_MAX steps, until a step moves
 * w by at most SMALL_SLIP_FIX_TOL cap (E-scaled components); then the
 * stops' problem with the last w. d1 gets the last step's move, d2 the
 * move over the last two steps (both / cap). Returns 0 if a problem has no
 * solution. */
static int rhs_iteration(const zoo_state *z, sf_result *q, double w[3], double *d1, double *d2)
{
    double W[9], b[3], aw[3], prev[3];
    exdex_friction_prep prep;
    exdex_friction_result fr;
    *d1 = *d2 = 0.0;
    for (int i = 0; i < 3; i++) {
        b[i] = 0.0;
        for (int c = 0; c < 3; c++) b[i] += z->pl.A[c][i] * z->a[c];
        for (int j = 0; j < 3; j++) {
            W[3 * i + j] = 0.0;
            for (int c = 0; c < 3; c++) W[3 * i + j] += z->pl.A[c][i] * z->minv[c] * z->pl.A[c][j];
        }
    }
    if (exdex_friction_prepare(&prep, W, z->pl.e) != EXDEX_OK) return 0;
    if (exdex_friction_solve(&prep, b, z->pl.cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &fr) != EXDEX_OK) return 0;
    memcpy(w, fr.p, 3 * sizeof *w);
    memcpy(prev, w, sizeof prev);
    for (int it = 0; it < SMALL_SLIP_FIX_MAX; it++) {
        double eu[3], n = 0.0, d = 0.0, dd = 0.0;
        for (int c = 0; c < 3; c++)
            aw[c] = z->a[c] + z->minv[c] * (z->pl.A[c][0] * w[0] + z->pl.A[c][1] * w[1] + z->pl.A[c][2] * w[2]);
        if (!sf_solve(z->nr, z->rows, z->ns, z->st, z->minv, aw, z->tol_a, z->tol_f, q)) return 0;
        for (int j = 0; j < 3; j++) {
            eu[j] = z->pl.e[j] * (z->pl.A[0][j] * q->qdd[0] + z->pl.A[1][j] * q->qdd[1] + z->pl.A[2][j] * q->qdd[2]);
            n += eu[j] * eu[j];
        }
        n = sqrt(n);
        if (!(n > 0.0)) break;
        for (int j = 0; j < 3; j++) {
            double wn = -z->pl.cap * z->pl.e[j] * eu[j] / n;
            d = fmax(d, fabs(wn - w[j]) / z->pl.e[j]);
            dd = fmax(dd, fabs(wn - prev[j]) / z->pl.e[j]);
            prev[j] = w[j];
            w[j] = wn;
        }
        *d1 = d / z->pl.cap;
        *d2 = dd / z->pl.cap;
        if (d <= SMALL_SLIP_FIX_TOL * z->pl.cap) break;
    }
    for (int c = 0; c < 3; c++)
        aw[c] = z->a[c] + z->minv[c] * (z->pl.A[c][0] * w[0] + z->pl.A[c][1] * w[1] + z->pl.A[c][2] * w[2]);
    return sf_solve(z->nr, z->rows, z->ns, z->st, z->minv, aw, z->tol_a, z->tol_f, q);
}

/* At each captured state the right-hand side of the joint problem meets the
 * model's contact conditions (sf_residual: Newton-Euler, the plate's wrench
 * on the ellipsoid with maximum dissipation, the rows' complementarity,
 * the stops' Coulomb law in their modes) to rounding, 1e-12, and the state
 * is inside its modes' guards; the right-hand side of the fixed-point
 * iteration does not: its plate wrench is off the maximum-dissipation
 * wrench of the slip it produces by more than 1e-2 (0.07 .. 0.49 on these
 * states), and the iteration has not settled: a 2-cycle, its last step
 * moves w by more than 0.1 cap (0.37 .. 2.0 here) while two steps return
 * it to within 5% of that (3e-10 .. 6e-3 cap). */
EXDEX_TEST(sfric_small_slip_rhs_meets_the_contact_conditions_at_captured_zoo_states)
{
    const int n = (int)(sizeof ZOO_STATES / sizeof ZOO_STATES[0]);
    for (int i = 0; i < n; i++) {
        const zoo_state *z = &ZOO_STATES[i];
        const sfr_problem p = {z->nr, z->ns, z->rows, z->st, z->s, z->zsw, z->minv, z->a, &z->pl};
        sf_result q;
        double w[3], part[SFR_N], d1, d2;
        ENSURE(rhs_joint(z, &q, w) == 1);
        ENSURE(sf_residual(&p, q.qdd, q.lam, q.beta, w, part) <= 1e-12);
        ENSURE(part[SFR_GUARD] == 0.0);
        ENSURE(rhs_iteration(z, &q, w, &d1, &d2) == 1);
        ENSURE(sf_residual(&p, q.qdd, q.lam, q.beta, w, part) > 1e-2);
        ENSURE(part[SFR_MDP] > 1e-2);
        ENSURE(d1 > 0.1 && d2 <= 0.05 * d1);
    }
}

#undef G /* below, G is sf_row's field */

/* x of the k x k system C x = r (k <= 3), by Gaussian elimination with
 * partial pivoting (the test's own, not ldp.c's). Returns 0 if singular. */
static int small_solve(int k, double C[3][3], double r[3], double x[3])
{
    for (int i = 0; i < k; i++) {
        int p = i;
        for (int j = i + 1; j < k; j++)
            if (fabs(C[j][i]) > fabs(C[p][i])) p = j;
        if (!(fabs(C[p][i]) > 0.0)) return 0;
        for (int c = 0; c < k; c++) {
            double t = C[i][c];
            C[i][c] = C[p][c];
            C[p][c] = t;
        }
        double t = r[i];
        r[i] = r[p];
        r[p] = t;
        for (int j = i + 1; j < k; j++) {
            double f = C[j][i] / C[i][i];
            for (int c = i; c < k; c++) C[j][c] -= f * C[i][c];
            r[j] -= f * r[i];
        }
    }
    for (int i = k - 1; i >= 0; i--) {
        x[i] = r[i];
        for (int c = i + 1; c < k; c++) x[i] -= C[i][c] * x[c];
        x[i] /= C[i][i];
    }
    return 1;
}

/* qdd of a captured state's mode at the plate wrench w: the rows of mask
 * carry force (gap acceleration 0), each with its stop's friction in the
 * stop's mode fm (sliding: along G - sigma mu T; sticking: one more
 * unknown along T, the slip acceleration 0). Returns 0 if singular. */
static int mode_qdd(const zoo_state *z, unsigned mask, const int *fm, const double w[3], double qdd[3])
{
    double Dr[3][3], Cr[3][3], c0[3], M[3][3], r[3], x[3], af[3];
    int k = 0;
    for (int c = 0; c < 3; c++)
        af[c] = z->a[c] + z->minv[c] * (z->pl.A[c][0] * w[0] + z->pl.A[c][1] * w[1] + z->pl.A[c][2] * w[2]);
    for (int i = 0; i < z->nr; i++) {
        const sf_stop *st = &z->st[z->rows[i].stop];
        const int m = fm[z->rows[i].stop];
        double sg = m == SF_SLIDE_P ? 1.0 : m == SF_SLIDE_M ? -1.0 : 0.0;
        if (!(mask >> i & 1u)) continue;
        for (int c = 0; c < 3; c++) {
            Cr[k][c] = z->rows[i].G[c];
            Dr[k][c] = z->rows[i].G[c] - sg * st->mu * st->T[c];
        }
        c0[k++] = z->rows[i].gdd0;
        if (m == SF_STICK && st->mu > 0.0) {
            for (int c = 0; c < 3; c++) Cr[k][c] = Dr[k][c] = st->T[c];
            c0[k++] = st->sdd0;
        }
    }
    for (int l = 0; l < k; l++) {
        r[l] = -c0[l];
        for (int c = 0; c < 3; c++) r[l] -= Cr[l][c] * af[c];
        for (int j = 0; j < k; j++) {
            M[l][j] = 0.0;
            for (int c = 0; c < 3; c++) M[l][j] += Cr[l][c] * z->minv[c] * Dr[j][c];
        }
    }
    if (k && !small_solve(k, M, r, x)) return 0;
    for (int c = 0; c < 3; c++) {
        qdd[c] = af[c];
        for (int l = 0; l < k; l++) qdd[c] += z->minv[c] * Dr[l][c] * x[l];
    }
    return 1;
}

/* Every plate wrench of a mode, from its affine patch slip u = b + W w (W, b
 * read off mode_qdd at w = 0 and the unit wrenches): with z = E u, c = E b,
 * K = E W E, the wrench w = -E y of y = (K + s I)^-1 c, |y| = cap, s = 1 /
 * lam > 0 (stop_friction.h, sf_plate). Each such s is a real eigenvalue of
 * the quadratic eigenproblem (s^2 I + s (K + K^T) + K K^T - c c^T / cap^2) v
 * = 0 (v = (K + s I)^-T y: (K + s I)(K + s I)^T v = y = c (c^T v) / cap^2),
 * solved as the 6 x 6 companion problem: all roots, not the first found
 * along lam. Writes the wrenches of the roots (|y| within 1e-9 cap of cap)
 * in order of decreasing s (the first: the fastest slip, the largest
 * dissipation cap |z| = cap^2 s); returns their count (-1 on failure). */
static int mode_all_plate_wrenches(const zoo_state *z, unsigned mask, const int *fm, double wr[6][3], double sr[6])
{
    double q0[3], u0[3], W[3][3], K[3][3], c[3], Lm[36];
    const double *e = z->pl.e, cap = z->pl.cap;
    int n = 0;
    if (!mode_qdd(z, mask, fm, (const double[3]){0, 0, 0}, q0)) return -1;
    for (int i = 0; i < 3; i++) u0[i] = z->pl.A[0][i] * q0[0] + z->pl.A[1][i] * q0[1] + z->pl.A[2][i] * q0[2];
    for (int j = 0; j < 3; j++) {
        double ej[3] = {0, 0, 0}, qj[3];
        ej[j] = 1.0;
        if (!mode_qdd(z, mask, fm, ej, qj)) return -1;
        for (int i = 0; i < 3; i++) W[i][j] = z->pl.A[0][i] * qj[0] + z->pl.A[1][i] * qj[1] + z->pl.A[2][i] * qj[2] - u0[i];
    }
    for (int i = 0; i < 3; i++) {
        c[i] = e[i] * u0[i];
        for (int j = 0; j < 3; j++) K[i][j] = e[i] * W[i][j] * e[j];
    }
    memset(Lm, 0, sizeof Lm);
    for (int i = 0; i < 3; i++) {
        Lm[6 * i + 3 + i] = 1.0;
        for (int j = 0; j < 3; j++) {
            double KK = 0.0;
            for (int l = 0; l < 3; l++) KK += K[i][l] * K[j][l];
            Lm[6 * (3 + i) + j] = -(KK - c[i] * c[j] / (cap * cap));
            Lm[6 * (3 + i) + 3 + j] = -(K[i][j] + K[j][i]);
        }
    }
    gsl_matrix_view L = gsl_matrix_view_array(Lm, 6, 6);
    gsl_vector_complex *ev = gsl_vector_complex_alloc(6);
    gsl_eigen_nonsymm_workspace *ws = gsl_eigen_nonsymm_alloc(6);
    int st = ev && ws ? gsl_eigen_nonsymm(&L.matrix, ev, ws) : -1;
    for (int q = 0; st == 0 && q < 6; q++) {
        gsl_complex v = gsl_vector_complex_get(ev, q);
        double s = GSL_REAL(v), Ms[3][3], y[3], cy[3], ny;
        if (!(s > 0.0) || fabs(GSL_IMAG(v)) > 1e-9 * s) continue;
        /* polished by Newton steps on |y(s)| = cap, d|y|/ds = -y^T (K + s I)^-1 y / |y| */
        int ok = 1;
        for (int it = 0; it < 8 && ok; it++) {
            double Ms2[3][3], yy[3], t[3], d = 0.0;
            for (int i = 0; i < 3; i++) {
                cy[i] = c[i];
                for (int j = 0; j < 3; j++) Ms[i][j] = Ms2[i][j] = K[i][j] + (i == j ? s : 0.0);
            }
            if (!small_solve(3, Ms, cy, y)) ok = 0;
            ny = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
            memcpy(yy, y, sizeof yy);
            if (ok && !small_solve(3, Ms2, yy, t)) ok = 0;
            for (int i = 0; i < 3; i++) d -= y[i] * t[i] / ny;
            if (ok && d != 0.0 && it < 7) s -= (ny - cap) / d;
        }
        if (!ok || !(s > 0.0) || !(fabs(ny - cap) <= 1e-9 * cap)) continue;
        int at = n++;
        while (at > 0 && sr[at - 1] < s) {
            sr[at] = sr[at - 1];
            memcpy(wr[at], wr[at - 1], sizeof wr[at]);
            at--;
        }
        sr[at] = s;
        for (int i = 0; i < 3; i++) wr[at][i] = -e[i] * y[i];
    }
    if (ws) gsl_eigen_nonsymm_free(ws);
    if (ev) gsl_vector_complex_free(ev);
    return st == 0 ? n : -1;
}

/* With a sliding stop K is not symmetric and the plate's equation can have
 * several roots, of which sf_solve_plate takes the first it brackets along
 * lam. At the captured states above the mode that sf_solve_plate returns
 * (10 of the 17 with a row carrying force against a sliding stop, 6 against
 * a sticking one, 1 without a row carrying force) has exactly one root:
 * all of them found by the quadratic eigenproblem (mode_all_plate_wrenches,
 * GSL's nonsymmetric eigensolver: an independent method), and its wrench
 * is sf_solve_plate's to 1e-12 cap (8e-15 here); where no row carries force
 * the plate holds the object alone and the mode has no root. */
EXDEX_TEST(sfric_plate_root_is_the_only_one_of_its_mode_at_captured_zoo_states)
{
    const int n = (int)(sizeof ZOO_STATES / sizeof ZOO_STATES[0]);
    int nsliding = 0;
    for (int i = 0; i < n; i++) {
        const zoo_state *z = &ZOO_STATES[i];
        sf_result jr;
        double wr[6][3], sr[6];
        unsigned mask = 0u;
        int nroot, sliding = 0;
        ENSURE(sf_solve_plate(z->nr, z->rows, z->ns, z->st, z->minv, z->a, &z->pl, z->tol_a, z->tol_f, &jr) == 1);
        ENSURE(jr.lock == 0);
        for (int r = 0; r < z->nr; r++)
            if (jr.lam[r] > 0.0) {
                mask |= 1u << r;
                sliding |= jr.fm[z->rows[r].stop] == SF_SLIDE_P || jr.fm[z->rows[r].stop] == SF_SLIDE_M;
            }
        nroot = mode_all_plate_wrenches(z, mask, jr.fm, wr, sr);
        nsliding += sliding;
        if (!mask) {
            /* no row carrying force: the plate holds the object alone, no slip */
            ENSURE(nroot == 0);
            continue;
        }
        ENSURE(nroot == 1);
        for (int j = 0; j < 3 && nroot == 1; j++) ENSURE_CLOSE(jr.w[j], wr[0][j], 1e-12 * z->pl.cap * z->pl.e[j]);
    }
    ENSURE(nsliding == 10);
}

/* A problem where the plate's equation has several roots: one row whose
 * stop slides (SF_SLIDE_M, mu 2.41), drawn at random (a body of 0.2 kg, the
 * patch turned by -1.96 rad and 8.6 mm off the centre of mass); K's symmetric
 * part has the eigenvalue -0.70 of K's largest entry, and the mode has three
 * roots (mode_all_plate_wrenches), two of them with the row's force
 * positive (0.89 and 0.33; the middle one -0.63). sf_solve_plate takes the
 * one of the fastest slip and the largest dissipation, cap |z| = cap^2 / lam
 * (73.5 against 35.2 and 2.19): the first root along lam, which lies below
 * gam, where the doubling from gam does not look (it bracketed the third). Its
 * right-hand side meets the contact conditions (sf_residual) to 1e-12. */
EXDEX_TEST(sfric_plate_takes_the_root_of_largest_dissipation_among_several)
{
    static const zoo_state z = {0, 0, 1, 1, {{{0.9589472483556314, -0.28358451098598986, -0.006091080672422484}, -0.2529660104611294, 0}}, {{{0.28358451098598986, 0.9589472483556314, 0.04179202758201164}, -0.12831480530653094, 2.4135084450776563, SF_SLIDE_M}}, {0.0}, 1e-9, {5.0, 5.0, 45092.29663164528}, {1.9244838576808985, -4.009587912039275, 0.0}, {{{-0.38020424479558756, 0.9249025528343063, 0.0}, {-0.9249025528343063, -0.38020424479558756, 0.0}, {0.002249927433175185, -0.008277129338145832, 1.0}}, {1.0, 1.0, 0.009835985061916675}, 3.8484127780484068}, 1e-12, 1e-15};
    const int fm[1] = {SF_SLIDE_M};
    const sfr_problem p = {z.nr, z.ns, z.rows, z.st, z.s, z.zsw, z.minv, z.a, &z.pl};
    sf_result jr, q;
    double wr[6][3], sr[6], w[3];
    ENSURE(mode_all_plate_wrenches(&z, 1u, fm, wr, sr) == 3);
    ENSURE(sr[0] > 1.5 * sr[1] && sr[1] > 1.5 * sr[2]);
    ENSURE(sf_solve_plate(z.nr, z.rows, z.ns, z.st, z.minv, z.a, &z.pl, z.tol_a, z.tol_f, &jr) == 1);
    ENSURE(jr.lock == 0 && jr.lam[0] > 0.0);
    for (int j = 0; j < 3; j++) ENSURE_CLOSE(jr.w[j], wr[0][j], 1e-12 * z.pl.cap * z.pl.e[j]);
    ENSURE(rhs_joint(&z, &q, w) == 1);
    ENSURE(sf_residual(&p, q.qdd, q.lam, q.beta, w, NULL) <= 1e-12);
}
