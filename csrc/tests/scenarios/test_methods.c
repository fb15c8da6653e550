/* test_methods.c -- the event-driven, regularised and explicit methods
 * (hybrid.c, explicit.c) against closed forms, the stability claims with the
 * boundaries derived below, and observed orders of convergence.
 * Every expected value is a closed form written here (or in
 * tests/data/reference.dat), a bound derived here, or an independent
 * method; never an output of the code under test.
 * twin: tests/scenarios/test_methods.py (the same subject through the Python API)
 */
#include "../check.h"
#include "../sim_run.h"
#include "../../exdex.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_roots.h>

#define G 9.81

static double qlast(const sim_run *r, int c) { return r->tr.q[(r->tr.n - 1) * r->ndof + c]; }

#define EXDEX_TEST_PI 3.14159265358979323846

/* 1-DoF vertical scene (B y up), gripper at rest, capacity ratio * m g. */
static exdex_scene_def mvertical(double mass, double ratio, int method)
{
    exdex_scene_def d = scene_vertical(mass, ratio);
    d.method = method;
    return d;
}

/* Fig. 3: m 0.1, capacity 1.5 N, Eq. 7 down first (X1 0.1, T 0.5, beta 0.9). */
static exdex_scene_def mfig3(int method)
{
    exdex_scene_def d = mvertical(0.1, 1.5 / (0.1 * G), method);
    scene_eq7(&d, 0, 0.0, 0.0, -1.0, 0.1, 0.5, 0.9);
    return d;
}

/* Gripper spinning at constant rate w about its plate normal (B z) through
 * B's origin: a trapezoid without ramps (constant speed) until t = 5 s. */
static void spin_motion(exdex_scene_def *d, double w)
{
    scene_trapezoid(d, 1, 0.0, -1.0, 0.0, w * 5.0, 5.0, w);
}

/* ------------------------------------------------------------ closed forms */

EXDEX_TEST(methods_free_fall_closed_form)
{
    /* mu = 0: s = -g t^2 / 2. event and regularised integrate a constant
     * acceleration exactly (any RK of order >= 2). explicit (symplectic
     * Euler, v_k = -g k h, q_n = h sum v_k) has its own closed form
     * q_n = -g h^2 n (n + 1) / 2 = -g t (t + h) / 2. */
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_scene_def d = mvertical(0.3, 1.0, method);
        sim_run r;
        d.mu = 0.0;
        ENSURE(sim_run_def(&d, 0.7, 1e-3, &r) == EXDEX_OK);
        if (method == EXDEX_METHOD_EXPLICIT) {
            ENSURE_CLOSE(qlast(&r, 0), -G * 0.7 * (0.7 + 1e-3) / 2, 1e-12);
        } else {
            ENSURE_CLOSE(qlast(&r, 0), ref("sim_free_fall_0p7"), 1e-12);
            ENSURE_CLOSE(r.tr.v[r.tr.n - 1], -G * 0.7, 1e-12);
        }
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_block_sliding_closed_forms)
{
    /* Capacity c = 0.6 m g, from rest: Coulomb slides at a = 0.4 g.
     * event: s(1) = -0.2 g exactly, friction +0.6 m g. */
    exdex_scene_def d = mvertical(0.2, 0.6, EXDEX_METHOD_EVENT);
    sim_run r;
    double c = 0.6, h = 1e-3, a = 0.4 * G;
    ENSURE(sim_run_def(&d, 1.0, h, &r) == EXDEX_OK);
    ENSURE_CLOSE(qlast(&r, 0), ref("sim_slide_1s"), 1e-12);
    for (size_t i = 1; i < r.tr.n; i += 97) {
        ENSURE_CLOSE(r.tr.q[i], -0.2 * G * r.tr.t[i] * r.tr.t[i], 1e-12);
        ENSURE_CLOSE(r.tr.wrench[3 * i + 1], 0.6 * 0.2 * G, 1e-9);
        ENSURE(!r.tr.stick[i]);
    }
    sim_run_free(&r);

    /* explicit: the first step has v = 0, friction 0 (sign(0) = 0), so
     * v_1 = -g h, then v_k = -g h - (k - 1) a h; q_n = h sum v_k
     * = -g h t - a t (t - h) / 2 at t = n h. */
    d.method = EXDEX_METHOD_EXPLICIT;
    ENSURE(sim_run_def(&d, 1.0, h, &r) == EXDEX_OK);
    ENSURE_CLOSE(qlast(&r, 0), -G * h * 1.0 - a * 1.0 * (1.0 - h) / 2, 1e-12);
    sim_run_free(&r);

    /* regularised, friction -C w / sqrt(w^2 + eps^2) (w the downward speed):
     * the friction deficit C (1 - f(w)) gives a velocity offset
     * eps I(c), I(c) = c int_0^inf (1 - z/sqrt(1+z^2)) / (1 - c z/sqrt(1+z^2)) dz;
     * with z = sinh u, y = e^-u: I = c int_0^1 (1 + y^2)/((1-c) + (1+c) y^2) dy
     * = c/(1+c) + 2c^2/(1+c) atan(sqrt((1+c)/(1-c))) / sqrt(1-c^2)
     * (= 0.997771 at c = 0.6). So s(t) = -a t^2/2 - eps I t + O(eps^2). */
    {
        double eps = 1e-4;
        double I = c / (1 + c) + 2 * c * c / (1 + c) * atan(sqrt((1 + c) / (1 - c))) / sqrt(1 - c * c);
        d.method = EXDEX_METHOD_REGULARISED;
        d.eps = eps;
        ENSURE(sim_run_def(&d, 1.0, h, &r) == EXDEX_OK);
        ENSURE_CLOSE(qlast(&r, 0), -0.2 * G - eps * I, 5e-8);  /* O(eps^2) = 2e-8 */
        report("methods_reg_slide_1s_eps1e-4", qlast(&r, 0));
        sim_run_free(&r);
    }
}

/* Fig. 3 closed form (sim_run.c, independent of the library): exact
 * stick/slip switching under the piecewise-constant gripper accelerations
 * of Eq. 7; also returns the stick time. */
static double fig3_closed_form(double cap_acc, double *t_stick)
{
    double t_sw[4] = {0.0, 0.45, 0.55, 1.0};
    double aH = 2 * 0.1 / (0.9 * 0.25), aL = 2 * 0.1 / (0.1 * 0.25);
    double acc[3] = {-aH, aL, -aH};
    return vertical_closed_form(G, cap_acc, t_sw, acc, 3, t_stick);
}

EXDEX_TEST(methods_event_fig3_closed_form_exact_stillness)
{
    /* The event method resolves the Fig. 3 switches exactly: the final
     * displacement to 1e-12 at any output grid, and exactly still (v == 0,
     * stick) from the stick time on. */
    double ts, xcf = fig3_closed_form(15.0, &ts);
    double dts[3] = {1e-2, 1e-3, 0.0123};
    ENSURE_CLOSE(xcf, ref("sim_fig3_grip1p5_final"), 1e-15);
    for (int k = 0; k < 3; k++) {
        exdex_scene_def d = mfig3(EXDEX_METHOD_EVENT);
        sim_run r;
        int still = 1;
        ENSURE(sim_run_def(&d, 1.5, dts[k], &r) == EXDEX_OK);
        ENSURE_CLOSE(qlast(&r, 0), xcf, 1e-12);
        for (size_t i = 0; i < r.tr.n; i++)
            if (r.tr.t[i] > ts + 1e-9) still &= r.tr.v[i] == 0.0 && r.tr.stick[i];
        ENSURE(still);
        if (k == 0) report("methods_event_fig3_final_dt1e-2", qlast(&r, 0));
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_regularised_fig3_error_first_order_in_eps)
{
    /* Regularised Fig. 3, first order in eps, derived by hand: with
     * z(Q) = Q / sqrt(C^2 - Q^2) (creep speed / eps under a load Q) and the
     * onset deficit I(c, z0) = c int_0^y0 (1+y^2)/((1-c)+(1+c)y^2) dy,
     * y0 = sqrt(1 + z0^2) - z0 (as in the sliding block, starting from the
     * creep speed z0 instead of rest), the error is
     *   -eps [ z1 0.45 + (z1 + I(C/Q2, z1)) (t_s - 0.45)
     *          + z1 (1.0 - t_s) + z4 0.5 ]
     * (creep in the stick phases, the velocity offset carried through the
     * slip, creep after the stop and after the motion; the rest is
     * O(eps^2 log eps)). Q1 = m (g - a_H), Q2 = m (g + |a_L|), Q4 = m g. */
    double ts, xcf = fig3_closed_form(15.0, &ts), C = 1.5, m = 0.1;
    double aH = 2 * 0.1 / (0.9 * 0.25), aL = 2 * 0.1 / (0.1 * 0.25);
    double Q1 = m * (G - aH), Q2 = m * (G + aL), Q4 = m * G;
    double z1 = Q1 / sqrt(C * C - Q1 * Q1), z4 = Q4 / sqrt(C * C - Q4 * Q4);
    double c = C / Q2, y0 = sqrt(1 + z1 * z1) - z1;
    double I = c * (y0 / (1 + c) + 2 * c / (1 + c) * atan(y0 * sqrt((1 + c) / (1 - c))) / sqrt(1 - c * c));
    double k_pred = -(z1 * 0.45 + (z1 + I) * (ts - 0.45) + z1 * (1.0 - ts) + z4 * 0.5);
    double eps = 1e-4;
    exdex_scene_def d = mfig3(EXDEX_METHOD_REGULARISED);
    sim_run r;
    d.eps = eps;
    ENSURE(sim_run_def(&d, 1.5, 1e-2, &r) == EXDEX_OK);
    ENSURE_CLOSE((qlast(&r, 0) - xcf) / eps / k_pred, 1.0, 2e-3);
    /* and it never sticks: after the motion it creeps at -eps z4 */
    ENSURE_CLOSE(r.tr.v[r.tr.n - 1] / (-eps * z4), 1.0, 1e-6);
    ENSURE(!r.tr.stick[r.tr.n - 1]);
    report("methods_reg_fig3_err_over_eps", (qlast(&r, 0) - xcf) / eps);
    report("methods_reg_fig3_err_over_eps_pred", k_pred);
    sim_run_free(&r);
}

EXDEX_TEST(methods_fig4_stop_all_methods)
{
    /* Paper Fig. 4 (test_sim.c): the object stays on a world-fixed stop
     * while the gripper moves 5 cm down. Every method: +5 cm relative slip,
     * gap never negative. event: while the plates slide past (cruise), the
     * stop carries m g + capacity; once the gripper rests, m g (the stop
     * carries what it can) and the object is exactly still. */
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_scene_def d = mvertical(0.1, 1.5 / (0.1 * G), method);
        sim_run r;
        scene_rect(&d, 0.01, 0.02);
        d.n_stops = 1;
        d.stop_point[0][2] = -0.02;
        d.stop_normal[0][2] = 1.0;
        scene_trapezoid(&d, 0, 0.0, 0.0, -1.0, 0.05, 0.5, 0.12);
        ENSURE(sim_run_def(&d, 1.0, 1e-3, &r) == EXDEX_OK);
        ENSURE(r.st.min_gap >= -1e-15);
        ENSURE_CLOSE(qlast(&r, 0), 0.05, 1e-12);
        if (method == EXDEX_METHOD_EVENT) {
            for (size_t i = 100; i <= 400; i += 50) ENSURE_CLOSE(r.tr.stop_force[i], 0.1 * G + 1.5, 1e-9);
            for (size_t i = 510; i < r.tr.n; i += 50) {
                ENSURE_CLOSE(r.tr.stop_force[i], 0.1 * G, 1e-9);
                ENSURE(r.tr.v[i] == 0.0 && r.tr.stick[i]);
            }
        }
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_event_rotation_stop_matches_implicit)
{
    /* Rotation scene with a stop: a bar (vertices +-5 cm) pinned at the
     * patch, the gripper turning about its plate normal (Eq. 7), a world
     * stop that one end hits and slides along. Independent method: the
     * implicit one at dt = 1e-5 (first order, error ~1e-9 here). */
    exdex_scene_def d = mvertical(0.1, 1.0, EXDEX_METHOD_EVENT);
    sim_run a, b;
    d.dof = EXDEX_DOF_ROTATION;
    d.inertia[8] = 1e-4;
    d.grip_force = 0.05;
    d.gravity[2] = 0.0;
    d.n_vertices = 2;
    d.vertices[0][0] = 0.05;
    d.vertices[1][0] = -0.05;
    scene_eq7(&d, 1, 0.0, -1.0, 0.0, 1.0, 0.5, 0.7);
    d.n_stops = 1;
    d.stop_point[0][2] = -0.01;
    d.stop_normal[0][2] = 1.0;
    ENSURE(sim_run_def(&d, 1.2, 1e-3, &a) == EXDEX_OK);
    d.method = EXDEX_METHOD_IMPLICIT;
    ENSURE(sim_run_def(&d, 1.2, 1e-5, &b) == EXDEX_OK);
    ENSURE_CLOSE(qlast(&a, 0), qlast(&b, 0), 1e-8);
    ENSURE(a.st.min_gap >= -1e-15);
    {
        double smax = 0.0;
        for (size_t i = 0; i < a.tr.n; i++) smax = fmax(smax, a.tr.stop_force[i]);
        ENSURE(smax > 1e-3); /* the stop did act */
    }
    ENSURE(a.tr.stick[a.tr.n - 1] && a.tr.v[a.tr.n - 1] == 0.0);
    report("methods_event_rot_stop_final", qlast(&a, 0));
    sim_run_free(&a);
    sim_run_free(&b);
}

/* ------------------------------------------------------ stability claims */

EXDEX_TEST(methods_stillness_map_event_implicit)
{
    /* (a) and (b) hold exact stick over the map (dt, capacity / load):
     * a load inside the ellipsoid never moves the object, bit for bit, and
     * every sample reports stick. Gripper at rest (load m g), 1-DoF. */
    double dts[5] = {1e-5, 1e-4, 1e-3, 1e-2, 1e-1};
    double ratios[6] = {1.0 + 1e-9, 1.001, 1.1, 2.0, 10.0, 1e3};
    int methods[2] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EVENT};
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 5; i++)
            for (int j = 0; j < 6; j++) {
                exdex_scene_def d = mvertical(0.1, ratios[j], methods[k]);
                sim_run r;
                int moved = 0, slipped = 0;
                double t_end = fmax(200 * dts[i], 0.5);
                d.q0[1] = -0.02;
                ENSURE(sim_run_def(&d, t_end, dts[i], &r) == EXDEX_OK);
                for (size_t s = 0; s < r.tr.n; s++) {
                    moved |= r.tr.q[s] != -0.02 || r.tr.v[s] != 0.0;
                    slipped |= !r.tr.stick[s];
                }
                ENSURE(!moved);
                ENSURE(!slipped);
                ENSURE_CLOSE(r.tr.wrench[3 * (r.tr.n - 1) + 1], 0.1 * G, 1e-12);
                sim_run_free(&r);
            }
}

EXDEX_TEST(methods_stillness_moving_gripper_and_planar)
{
    /* Moving gripper: Eq. 7 of Fig. 3 with capacity 2 N above the peak load
     * m (g + |a_L|) = 1.781 N: the object never moves relative to the
     * fingers (implicit and event). Planar: off-centre patch, the load
     * (m g at the centre of mass = a force and a moment at the patch)
     * inside the ellipsoid. */
    int methods[2] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EVENT};
    for (int k = 0; k < 2; k++) {
        exdex_scene_def d = mfig3(methods[k]);
        sim_run r;
        int moved = 0;
        d.grip_force = 2.0 / (2 * d.mu);
        ENSURE(sim_run_def(&d, 1.5, 1e-3, &r) == EXDEX_OK);
        for (size_t s = 0; s < r.tr.n; s++) moved |= r.tr.q[s] != 0.0 || r.tr.v[s] != 0.0 || !r.tr.stick[s];
        ENSURE(!moved);
        sim_run_free(&r);

        d = mvertical(0.1, 2.0, methods[k]);
        d.dof = EXDEX_DOF_PLANAR;
        d.inertia[8] = 1e-3;
        d.patch_center[0] = 0.004;
        d.e_r = 0.02;
        d.q0[0] = 0.003;
        d.q0[1] = -0.02;
        ENSURE(sim_run_def(&d, 2.0, 1e-3, &r) == EXDEX_OK);
        moved = 0;
        for (size_t s = 0; s < r.tr.n; s++) {
            moved |= r.tr.q[3 * s] != 0.003 || r.tr.q[3 * s + 1] != -0.02 || r.tr.q[3 * s + 2] != 0.0;
            moved |= r.tr.v[3 * s] != 0.0 || r.tr.v[3 * s + 1] != 0.0 || r.tr.v[3 * s + 2] != 0.0;
            moved |= !r.tr.stick[s];
        }
        ENSURE(!moved);
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_explicit_chatters_band_and_creep)
{
    /* (d) explicit Coulomb at a load Q (here -m g) inside the capacity C:
     * with v > 0 each step adds h (Q - C)/M, with v < 0 it adds h (Q + C)/M,
     * so v is a rotation on the circle J = (h (Q - C)/M, h (Q + C)/M] of
     * length 2 h C / M: it never settles at 0 (chatter) and, for an
     * irrational rotation number (C - |Q|)/(2C), fills J uniformly, so the
     * mean velocity (the creep) is the centre of J, h Q / M.
     * Boundary: the chatter amplitude max |v| -> h (C + |Q|)/M, so a
     * velocity resolution v_res is exceeded iff dt > v_res M / (C + |Q|).
     * Capacity ratio r = 2 + sqrt(5) (rotation number 1 - golden ratio). */
    double r_cap = 2.0 + sqrt(5.0), dts[3] = {1e-4, 1e-3, 1e-2};
    for (int i = 0; i < 3; i++) {
        exdex_scene_def d = mvertical(0.1, r_cap, EXDEX_METHOD_EXPLICIT);
        sim_run r;
        double h = dts[i], lo = h * (-G - r_cap * G), hi = h * (-G + r_cap * G), vmax = 0.0, vmin = 0.0;
        size_t zeros = 0, n;
        ENSURE(sim_run_def(&d, 4000 * h, h, &r) == EXDEX_OK);
        n = r.tr.n;
        for (size_t s = 2; s < n; s++) {
            vmax = fmax(vmax, r.tr.v[s]);
            vmin = fmin(vmin, r.tr.v[s]);
            zeros += r.tr.v[s] == 0.0;
        }
        ENSURE(zeros == 0);
        ENSURE(vmin > lo * (1 + 1e-9) && vmax <= hi * (1 + 1e-9));
        ENSURE(vmin < 0.99 * lo && vmax > 0.99 * hi);  /* the band is filled */
        /* mean creep speed over the run: h Q / M = -h g (1%) */
        ENSURE_CLOSE((r.tr.q[n - 1] - r.tr.q[1]) / (r.tr.t[n - 1] - r.tr.t[1]) / (-h * G), 1.0, 1e-2);
        ENSURE(!r.tr.stick[n - 1]);
        sim_run_free(&r);
    }
    /* the resolution boundary for v_res = 1e-3 m/s */
    {
        double v_res = 1e-3, h_star = v_res / (G * (1.0 + r_cap));
        double f[2] = {0.8, 1.25};
        for (int k = 0; k < 2; k++) {
            exdex_scene_def d = mvertical(0.1, r_cap, EXDEX_METHOD_EXPLICIT);
            sim_run r;
            double vabs = 0.0;
            ENSURE(sim_run_def(&d, 4000 * f[k] * h_star, f[k] * h_star, &r) == EXDEX_OK);
            for (size_t s = 1; s < r.tr.n; s++) vabs = fmax(vabs, fabs(r.tr.v[s]));
            if (k == 0)
                ENSURE(vabs < v_res);
            else
                ENSURE(vabs > v_res);
            sim_run_free(&r);
        }
        report("methods_explicit_h_star_vres1e-3", h_star);
    }
}

EXDEX_TEST(methods_regularised_creep_rate)
{
    /* (c) regularised friction never sticks: under a load w_L (the patch
     * wrench of the applied forces) inside the ellipsoid the steady slip
     * solves cap E^2 u / sqrt(|E u|^2 + eps^2) = w_L, i.e.
     *     E u = eps E^-1 w_L / sqrt(C^2 - |E^-1 w_L|^2).
     * 1-DoF vertical, load m g, C = 2 m g: v = -eps / sqrt(3). */
    {
        exdex_scene_def d = mvertical(0.1, 2.0, EXDEX_METHOD_REGULARISED);
        sim_run r;
        d.eps = 1e-4;
        ENSURE(sim_run_def(&d, 0.05, 1e-3, &r) == EXDEX_OK);
        ENSURE_CLOSE(r.tr.v[r.tr.n - 1] / (-1e-4 / sqrt(3.0)), 1.0, 1e-6);
        ENSURE(!r.tr.stick[r.tr.n - 1]);
        sim_run_free(&r);
    }
    /* Planar, patch at pc = (px, 0) from the centre of mass, theta = 0:
     * w_L = (0, -m g, px m g) (force, and its moment about the patch), so
     * u = eps E^-2 w_L / D, D = sqrt(C^2 - (m g)^2 - (px m g / e_r)^2), and
     * the coordinates follow from u = J' v: thd = u_r, yd = u_y - px thd,
     * xd = u_x = 0. Checked at t = 0.01 s (relaxation ~1e-5 s; the
     * rotation by then, ~1e-5 rad, changes the load by < 1e-5). */
    {
        exdex_scene_def d = mvertical(0.1, 2.0, EXDEX_METHOD_REGULARISED);
        sim_run r;
        double eps = 1e-4, px = 0.004, er = 0.02, mg = 0.1 * G, C = 2.0 * mg;
        double D = sqrt(C * C - mg * mg - (px * mg / er) * (px * mg / er));
        double uy = -eps * mg / D, ur = eps * px * mg / (er * er * D);
        d.dof = EXDEX_DOF_PLANAR;
        d.inertia[8] = 1e-3;
        d.patch_center[0] = px;
        d.e_r = er;
        d.eps = eps;
        ENSURE(sim_run_def(&d, 0.01, 1e-3, &r) == EXDEX_OK);
        ENSURE_CLOSE(r.tr.v[3 * (r.tr.n - 1) + 2] / ur, 1.0, 1e-4);
        ENSURE_CLOSE(r.tr.v[3 * (r.tr.n - 1) + 1] / (uy - px * ur), 1.0, 1e-4);
        ENSURE(fabs(r.tr.v[3 * (r.tr.n - 1)]) < 1e-4 * fabs(uy));
        report("methods_reg_planar_creep_thd", r.tr.v[3 * (r.tr.n - 1) + 2]);
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_regularised_step_collapse)
{
    /* (c) stiffness: at the creep speed the friction slope is
     * k = C (1 - (Q/C)^2)^(3/2) / (M eps) [1/s], and an explicit RK step is
     * stable only for h k below the real stability interval of its
     * stability polynomial; for GSL's rk8pd |R(-x)| <= 1 up to x = 5.1666
     * (reference.dat, from the tableau). The steps collapse to h ~ 5.17 / k:
     * steps ~ t k / 5.17, i.e. proportional to 1/eps. */
    double eps[2] = {1e-5, 1e-6}, t_end[2] = {0.05, 0.005}, x_stab = ref("methods_rk8pd_stability_interval");
    for (int i = 0; i < 2; i++) {
        exdex_scene_def d = mvertical(0.1, 2.0, EXDEX_METHOD_REGULARISED);
        sim_run r;
        double k = 2.0 * G * pow(0.75, 1.5) / eps[i], pred = t_end[i] * k / x_stab;
        d.eps = eps[i];
        ENSURE(sim_run_def(&d, t_end[i], 1e-3, &r) == EXDEX_OK);
        ENSURE((double)r.st.steps >= 0.9 * pred && (double)r.st.steps <= 1.3 * pred);
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_budget_step_collapse_returns_enoconv)
{
    /* Budgets (hybrid.c header): at most 1e5 ODE steps per output interval,
     * and a suggested step of at least 16 ulps of t.
     * (1) From rest under a load Q = m g with C = 2 m g the object creeps
     * (k = C (1 - (Q/C)^2)^(3/2) / (M eps), methods_regularised_step_collapse),
     * rk8pd needs h k < 5.17, so one output interval of dt costs about
     * dt k / 5.17 steps: with eps = 1e-9, dt = 1e-3 that is 2.5e6 > 1e5, so
     * the run must stop with EXDEX_ENOCONV after at most 1e5 accepted steps,
     * in the first interval. */
    {
        double x_stab = ref("methods_rk8pd_stability_interval"), eps = 1e-9, dt = 1e-3;
        double k = 2.0 * G * pow(0.75, 1.5) / eps;
        exdex_scene_def d = mvertical(0.1, 2.0, EXDEX_METHOD_REGULARISED);
        sim_run r;
        ENSURE(dt * k / x_stab > 10.0 * 1e5);
        d.eps = eps;
        ENSURE(sim_run_def(&d, 0.01, dt, &r) == EXDEX_ENOCONV);
        ENSURE(r.st.steps <= 100000 && r.st.steps >= 1000);
        ENSURE(r.st.warnings >= 1);
        /* the failure says why (the step budget) and when: inside the
         * first output interval, 1e5 steps of at most 5.17 / k */
        ENSURE(r.st.fail_cause == EXDEX_FAIL_STEP_BUDGET);
        ENSURE(r.st.fail_time > 0.0 && r.st.fail_time <= dt);
        ENSURE(r.st.fail_time <= 1e5 * x_stab / k * 1.01);
        sim_run_free(&r);
        /* the same scene with eps = 1e-6 needs ~2500 steps per interval: runs */
        d.eps = 1e-6;
        ENSURE(sim_run_def(&d, 0.01, dt, &r) == EXDEX_OK);
        ENSURE(r.st.fail_cause == EXDEX_FAIL_NONE && isnan(r.st.fail_time));
        sim_run_free(&r);
    }
    /* (2) the step floor: sliding down at 1 m/s with C = 2 m g, the object
     * decelerates at g and stops at t = 1/g ~ 0.1 s, then creeps with
     * h <= 5.17 M eps / C ~ 5.17 * 1e-16 / (2 g) = 2.6e-17 s, below
     * 16 ulps of t (16 * 2.2e-16 * 0.1 = 3.6e-16 s): EXDEX_ENOCONV without
     * spending the step budget (one output interval of 0.5 s), and the
     * trajectory up to the collapse is not recorded as a success. */
    {
        exdex_scene_def d = mvertical(0.1, 2.0, EXDEX_METHOD_REGULARISED);
        sim_run r;
        d.eps = 1e-16;
        d.v0[1] = -1.0;
        ENSURE(sim_run_def(&d, 0.5, 0.5, &r) == EXDEX_ENOCONV);
        ENSURE(r.st.steps < 100000);
        /* a collapse of the step near the stop at t = 1/g: reported as the
         * floor, or as the budget when the rejected steps of the collapse
         * (counted in it) reach 1e5 first */
        report("methods_budget_floor_cause", (double)r.st.fail_cause);
        ENSURE(r.st.fail_cause == EXDEX_FAIL_STEP_FLOOR || r.st.fail_cause == EXDEX_FAIL_STEP_BUDGET);
        ENSURE(fabs(r.st.fail_time - 1.0 / G) < 1e-3);
        report("methods_budget_floor_steps", (double)r.st.steps);
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_event_slip_onset_inside_a_phase)
{
    /* Translation along B x, gripper turning about the horizontal A y axis
     * through the centre of mass (B z = -A y) at w = 1.5 rad/s after a ramp
     * of t_a = 0.2 s (trapezoid: 1.2 rad in 1 s). While it sticks the object
     * is on the axis: only gravity acts along the slide, g sin s(t), s the
     * turned angle, s = w t_a/2 + w (t - t_a) in the cruise. Slip starts at
     * m g sin(s*) = C, s* = arcsin(C / (m g)): t* = t_a + (s* - w t_a / 2) / w.
     * Then (tau = t - t*) q'' = g sin(s* + w tau) - C/m + w^2 q (centrifugal;
     * Coriolis is normal to the slide), q(0) = q'(0) = 0:
     *   q = A sin(s* + w tau) + B + c1 cosh(w tau) + c2 sinh(w tau),
     *   A = -g/(2w^2), B = C/(m w^2), c1 = -C/(2 m w^2), c2 = g cos(s*) / (2 w^2).
     * The onset error inferred from q at t_end, (q - q_exact)/q'_exact, must
     * be below 1e-9 s for output dt = t_end, t_end/8 and 1 ms (a slip that
     * starts at the next output sample would be up to dt late). */
    double m = 0.1, w = 1.5, ta = 0.2, t_end = 0.5, C, s_star, t_star, tau, A, B, c1, c2, q, qd;
    double dts[3] = {0.5, 0.5 / 8, 1e-3};
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = m;
    d.mu = 0.5;
    d.grip_force = 0.25;
    d.fingers = 2;
    C = 2 * d.mu * d.grip_force;
    d.gravity[2] = -G;
    d.slide_axis[0] = 1.0;
    d.slide_axis[1] = 0.0;
    scene_trapezoid(&d, 1, 0.0, 1.0, 0.0, 1.2, 1.0, w);
    d.method = EXDEX_METHOD_EVENT;
    s_star = asin(C / (m * G));
    t_star = ta + (s_star - 0.5 * w * ta) / w;
    ENSURE(t_star > ta && t_star < t_end);
    tau = t_end - t_star;
    A = -G / (2 * w * w);
    B = C / (m * w * w);
    c1 = -C / (2 * m * w * w);
    c2 = G * cos(s_star) / (2 * w * w);
    q = A * sin(s_star + w * tau) + B + c1 * cosh(w * tau) + c2 * sinh(w * tau);
    qd = w * (A * cos(s_star + w * tau) + c1 * sinh(w * tau) + c2 * cosh(w * tau));
    for (int i = 0; i < 3; i++) {
        sim_run r;
        ENSURE(sim_run_def(&d, t_end, dts[i], &r) == EXDEX_OK);
        ENSURE(fabs(qlast(&r, 0) - q) / qd < 1e-9);
        if (i == 0) report("methods_event_slip_onset_error_s", (qlast(&r, 0) - q) / qd);
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_event_short_slip_inside_a_stick_step)
{
    /* The scene above with a peak load: the gripper turns 2 rad in 3 s
     * (trapezoid, cruise at w = 0.9 rad/s from t_a = 7/9 s to 20/9 s), the
     * load along the slide m g sin s(t) peaks at s = pi/2 in the cruise (t_p
     * = t_a + (pi/2 - w t_a/2) / w = 2.134 s), and the capacity is C = m g
     * (1 - delta), delta = 1e-5: the object slips only while |s - pi/2| <
     * arccos(1 - delta), about 5 ms, inside a stick whose steps (constant
     * state) span far more. With tau = t - t_p, q'' = g cos(w tau) - C/m from
     * rest at tau1 = -arccos(1 - delta)/w:
     *   q' = (g/w)(sin w tau - sin w tau1) - (C/m)(tau - tau1),
     *   q  = -(g/w^2)(cos w tau - cos w tau1) - (g/w) sin(w tau1) (tau - tau1)
     *        - (C/m)(tau - tau1)^2 / 2,
     * until q' = 0 at tau2 (bisection), then stick. The centrifugal term w^2 q
     * adds w^2 q / (g delta) ~ 2e-5 of it (left out). The final q must be
     * that for output dt = t_end / 2 (one output interval spans the slip)
     * and 2^-8 s, to 1e-4 of itself. */
    double m = 0.1, w = 0.9, delta = 1e-5, T = 3.0, C, tau1, lo, hi, dtau, x;
    double dts[2] = {1.5, 1.0 / 256};
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = m;
    d.mu = 0.5;
    d.fingers = 2;
    C = m * G * (1 - delta);
    d.grip_force = C / (2 * d.mu);
    d.gravity[2] = -G;
    d.slide_axis[0] = 1.0;
    d.slide_axis[1] = 0.0;
    scene_trapezoid(&d, 1, 0.0, 1.0, 0.0, 2.0, T, w);
    d.method = EXDEX_METHOD_EVENT;
    d.rtol = 1e-10;
    d.atol = 1e-13;
    tau1 = -acos(1 - delta) / w;
    lo = -tau1 * 1.0001;
    hi = -10 * tau1;
    for (int it = 0; it < 200; it++) {
        double mid = 0.5 * (lo + hi);
        double v = (G / w) * (sin(w * mid) - sin(w * tau1)) - (C / m) * (mid - tau1);
        if (v > 0) lo = mid; else hi = mid;
    }
    dtau = 0.5 * (lo + hi) - tau1;
    x = -(G / (w * w)) * (cos(w * (tau1 + dtau)) - cos(w * tau1)) - (G / w) * sin(w * tau1) * dtau -
        (C / m) * dtau * dtau / 2;
    ENSURE(x > 5e-9 && x < 6e-9);
    for (int i = 0; i < 2; i++) {
        sim_run r;
        ENSURE(sim_run_def(&d, T, dts[i], &r) == EXDEX_OK);
        ENSURE_CLOSE(qlast(&r, 0) / x, 1.0, 1e-4);
        sim_run_free(&r);
    }
}

/* --------------------------------------------------------- observed orders */

/* Centrifugal slide with friction (no events): gripper spinning at w, the
 * object on a radial line, capacity c m: s'' = w^2 s - c while sliding
 * outward, s(t) = c/w^2 + (s0 - c/w^2) cosh(w t). Relative error at t = 2. */
static double centrifugal_error(int method, double dt, double rtol)
{
    exdex_scene_def d = exdex_default_scene_def();
    sim_run r;
    double w = 2.0, s0 = 0.05, c = w * w * 0.02, ex;
    d.mass = 0.1;
    d.mu = 0.5;
    d.grip_force = c * 0.1 / (2 * 0.5);
    d.gravity[2] = 0.0;
    d.slide_axis[0] = 1.0;
    d.slide_axis[1] = 0.0;
    d.q0[0] = s0;
    spin_motion(&d, w);
    d.method = method;
    d.rtol = rtol;
    d.atol = rtol;
    if (sim_run_def(&d, 2.0, dt, &r) != EXDEX_OK) return NAN;
    ex = c / (w * w) + (s0 - c / (w * w)) * cosh(w * 2.0);
    ex = fabs(qlast(&r, 0) - ex) / ex;
    sim_run_free(&r);
    return ex;
}

EXDEX_TEST(methods_observed_orders)
{
    /* event, between events: with a loose tolerance (rtol = atol = 1) the
     * steps are the output grid dt, so the error shows the stepper's
     * order: rk8pd, 8. */
    {
        double e1 = centrifugal_error(EXDEX_METHOD_EVENT, 0.5, 1.0);
        double e2 = centrifugal_error(EXDEX_METHOD_EVENT, 0.25, 1.0);
        double e3 = centrifugal_error(EXDEX_METHOD_EVENT, 0.125, 1.0);
        double p1 = log2(e1 / e2), p2 = log2(e2 / e3);
        ENSURE(p1 > 7.0 && p1 < 9.5);
        ENSURE(p2 > 7.0 && p2 < 9.5);
        report("methods_order_event_rk8pd_1", p1);
        report("methods_order_event_rk8pd_2", p2);
    }
    /* implicit, smooth 1-DoF slip: the midpoint rule is second order */
    {
        double e1 = centrifugal_error(EXDEX_METHOD_IMPLICIT, 2e-3, 1e-8);
        double e2 = centrifugal_error(EXDEX_METHOD_IMPLICIT, 1e-3, 1e-8);
        ENSURE(log2(e1 / e2) > 1.9 && log2(e1 / e2) < 2.1);
        report("methods_order_implicit_smooth_slip", log2(e1 / e2));
    }
    /* explicit: first order */
    {
        double e1 = centrifugal_error(EXDEX_METHOD_EXPLICIT, 2e-3, 1e-8);
        double e2 = centrifugal_error(EXDEX_METHOD_EXPLICIT, 1e-3, 1e-8);
        ENSURE(log2(e1 / e2) > 0.9 && log2(e1 / e2) < 1.1);
        report("methods_order_explicit_smooth_slip", log2(e1 / e2));
    }
    /* implicit on Fig. 3 with grids that do not hit the switching times
     * 0.45 s, 0.55 s: the step holding one is split there (model_substep),
     * so the stick -> slip onset at the switch is exact and the
     * accelerations are constant inside every sub-step, where the midpoint
     * rule is exact. The slip -> stick inside a step is located where the
     * slip stops under the step's constant force and kinetic friction
     * (implicit.c, slip_stop_in_step: t* = |v| / d, displacement v t* / 2),
     * which is exact for constant accelerations: the final displacement
     * equals the closed form to rounding at every grid. (A stick at the
     * step's end, q + h v / 2, stops early by up to h (C + |Q|) / M times h:
     * O(h^2); a step taking the onset as a step mean errs O(h).) */
    {
        double ts, xcf = fig3_closed_form(15.0, &ts), worst = 0.0;
        for (int k = 0; k < 12; k++) {
            double dt = 0.0123 * pow(0.5, k * 0.5);
            exdex_scene_def d = mfig3(EXDEX_METHOD_IMPLICIT);
            sim_run r;
            ENSURE(sim_run_def(&d, 1.5, dt, &r) == EXDEX_OK);
            worst = fmax(worst, fabs(qlast(&r, 0) - xcf));
            sim_run_free(&r);
        }
        ENSURE(worst <= 1e-13 * fabs(xcf));
        report("methods_implicit_fig3_misaligned_worst_error", worst);
    }
}

/* Planar scene with a rotating gripper (Eq. 7 about the plate normal), an
 * off-centre patch and a friction capacity 0.8 m g: slips throughout. */
static exdex_scene_def planar_rot(int method)
{
    exdex_scene_def d = mvertical(0.1, 0.8, method);
    d.dof = EXDEX_DOF_PLANAR;
    d.inertia[8] = 1e-4;
    d.patch_center[0] = 0.01;
    scene_eq7(&d, 1, 0.0, -1.0, 0.0, 1.0, 0.5, 0.7);
    return d;
}

EXDEX_TEST(methods_implicit_planar_slip_stops_inside_a_step)
{
    /* Planar, gripper at rest, gravity along the plate normal (no load in
     * the plane), patch centre at the centre of mass and I_zz = m e_r^2:
     * then A = E J' M^-1 J'^T E = I / m, and the scaled slip z = E u obeys
     * zdot = -C A z / |z| = -(C / m) z / |z|: a straight line decelerated
     * at C / m, for any mix of slide and spin. From v0 it stops at t* = m
     * |E v0| / C, having moved v0 t* / 2. A slide and a spin alone are
     * straight lines for any inertia: t* = m |v| / C and t* = I_zz
     * |thetad| / (C e_r). The first implicit step (h > t*) ends at rest, and
     * the slip's stop inside it (slip_stop_in_step_planar, integrated on the
     * slip's own clock) must give that displacement to its integration
     * tolerance. */
    const double m = 0.1, er = 0.01, C = 5.0, cases[3][4] = {
        {2e-3, -1e-3, 0.15, 1.0},   /* slide and spin, I_zz = m e_r^2 */
        {2e-3, -1e-3, 0.0, 7.0},    /* slide alone, I_zz = 7 m e_r^2 */
        {0.0, 0.0, -2.0, 0.3},      /* spin alone, I_zz = 0.3 m e_r^2 */
    };
    double worst = 0.0;
    for (int k = 0; k < 3; k++) {
        exdex_scene_def d = exdex_default_scene_def();
        double izz = cases[k][3] * m * er * er, v[3] = {cases[k][0], cases[k][1], cases[k][2]}, ts;
        sim_run r;
        d.method = EXDEX_METHOD_IMPLICIT;
        d.dof = EXDEX_DOF_PLANAR;
        d.mass = m;
        d.inertia[8] = izz;
        d.e_r = er;
        d.mu = 0.5;
        d.fingers = 2;
        d.grip_force = C / (2 * d.mu);
        d.gravity[0] = d.gravity[2] = 0.0;
        d.gravity[1] = -G;   /* along B's z (the default R0 maps B z to -A y) */
        for (int c = 0; c < 3; c++) d.v0[c] = v[c];
        if (k == 0) ts = m * sqrt(v[0] * v[0] + v[1] * v[1] + er * er * v[2] * v[2]) / C;
        else if (k == 1) ts = m * sqrt(v[0] * v[0] + v[1] * v[1]) / C;
        else ts = izz * fabs(v[2]) / (C * er);
        ENSURE(ts < 0.5e-3);
        ENSURE(sim_run_def(&d, 3e-3, 1e-3, &r) == EXDEX_OK);
        for (int c = 0; c < 3; c++) {
            double want = d.q0[c] + 0.5 * v[c] * ts, scale = 0.5 * fabs(v[c]) * ts + (c < 2 ? 1e-3 : 1e-1) * ts;
            worst = fmax(worst, fabs(qlast(&r, c) - want) / scale);
            ENSURE(fabs(qlast(&r, c) - want) <= 1e-9 * scale);
        }
        for (size_t i = 1; i < r.tr.n; i++)
            for (int c = 0; c < 3; c++) ENSURE(r.tr.v[i * 3 + c] == 0.0);
        sim_run_free(&r);
    }
    report("methods_implicit_planar_slip_stop_worst_rel", worst);
}

EXDEX_TEST(methods_implicit_planar_slip_through_the_sub_step_after_a_jump)
{
    /* A log cruising at V (A coordinates) ends at speed at t_last = 0.2 s -
     * 0.25 ms, between grid points of dt = 1 ms; planar, patch centre at the
     * centre of mass, no load in the plane (gravity along the plate normal):
     * the object is held until t_last, then slides at v = R0^T V relative to
     * the resting gripper, decelerated at C / m along a straight line, and
     * stops after t* = m |v| / C = 0.6 ms, having moved v t* / 2. The slip
     * slides through the 0.25 ms sub-step after the jump
     * (slip_through_step_planar) and stops inside the next step
     * (slip_stop_in_step_planar): the closed form to the integration's
     * tolerance. */
    const double m = 0.1, C = 5.0, V[3] = {0.024, 0.0, 0.018}, tl = 0.2 - 2.5e-4;
    double times[8], poses[8 * 7], v[3] = {V[0], V[2], 0.0}, ts = m * 0.03 / C;
    exdex_scene_def d = exdex_default_scene_def();
    sim_run r;
    for (int i = 0; i < 8; i++) {
        times[i] = tl * i / 7.0;
        for (int c = 0; c < 3; c++) poses[7 * i + c] = V[c] * times[i];
        poses[7 * i + 3] = poses[7 * i + 4] = sqrt(0.5);   /* R0: B y = A z */
        poses[7 * i + 5] = poses[7 * i + 6] = 0.0;
    }
    d.method = EXDEX_METHOD_IMPLICIT;
    d.dof = EXDEX_DOF_PLANAR;
    d.mass = m;
    d.inertia[8] = 1e-5;
    d.mu = 0.5;
    d.fingers = 2;
    d.grip_force = C / (2 * d.mu);
    d.gravity[0] = d.gravity[2] = 0.0;
    d.gravity[1] = -G;   /* along B's z */
    d.motion.kind = EXDEX_MOTION_SAMPLED;
    d.motion.n_samples = 8;
    d.motion.times = times;
    d.motion.poses = poses;
    for (int e = 0; e < 2; e++) {
        d.motion.end_given[e] = 1;
        for (int c = 0; c < 3; c++) d.motion.end_velocity[e][c] = V[c];
    }
    ENSURE(ts > 2.5e-4 && ts < 1.25e-3);
    ENSURE(sim_run_def(&d, 0.205, 1e-3, &r) == EXDEX_OK);
    for (int c = 0; c < 3; c++) ENSURE(fabs(qlast(&r, c) - (d.q0[c] + 0.5 * v[c] * ts)) <= 1e-9 * 0.5 * 0.03 * ts);
    ENSURE(r.tr.stick[r.tr.n - 1]);
    sim_run_free(&r);
}

EXDEX_TEST(methods_planar_event_is_the_implicit_limit)
{
    /* Two independent methods agree in the limit: the implicit solution
     * converges to the event solution (tight tolerance) at first order in
     * planar slip (the friction direction is taken at the end of the step),
     * error ratio 10 per decade of dt; and the event method itself agrees
     * between tolerances 1e-8 and 1e-12. */
    exdex_scene_def d = planar_rot(EXDEX_METHOD_EVENT);
    sim_run ev, evl, a, b;
    double ea = 0.0, eb = 0.0, el = 0.0;
    d.rtol = 1e-12;
    d.atol = 1e-14;
    ENSURE(sim_run_def(&d, 1.0, 1e-3, &ev) == EXDEX_OK);
    d.rtol = 1e-8;
    d.atol = 1e-10;
    ENSURE(sim_run_def(&d, 1.0, 1e-2, &evl) == EXDEX_OK);
    d.method = EXDEX_METHOD_IMPLICIT;
    ENSURE(sim_run_def(&d, 1.0, 1e-3, &a) == EXDEX_OK);
    ENSURE(sim_run_def(&d, 1.0, 1e-4, &b) == EXDEX_OK);
    for (int c = 0; c < 3; c++) {
        ea = fmax(ea, fabs(qlast(&a, c) - qlast(&ev, c)));
        eb = fmax(eb, fabs(qlast(&b, c) - qlast(&ev, c)));
        el = fmax(el, fabs(qlast(&evl, c) - qlast(&ev, c)));
    }
    ENSURE(el < 1e-8);
    ENSURE(ea / eb > 8.0 && ea / eb < 12.5);
    ENSURE(eb < 1e-3);
    report("methods_order_implicit_planar_slip", log10(ea / eb));
    sim_run_free(&ev);
    sim_run_free(&evl);
    sim_run_free(&a);
    sim_run_free(&b);
}

EXDEX_TEST(methods_planar_spin_to_rest_event_exact_stick)
{
    /* Gripper at rest, no gravity, a planar object sliding and spinning:
     * only friction acts, so it must come to rest in finite time and then
     * stay exactly still (event); kinetic energy never increases; the
     * implicit solution converges to it. */
    exdex_scene_def d = mvertical(0.1, 1.0, EXDEX_METHOD_EVENT);
    sim_run r, im;
    int ok = 1, still = 1, seen = 0;
    d.gravity[2] = 0.0;
    d.grip_force = 0.3;
    d.dof = EXDEX_DOF_PLANAR;
    d.inertia[8] = 2e-4;
    d.patch_center[0] = 0.01;
    d.patch_center[1] = -0.005;
    d.v0[0] = 0.3;
    d.v0[1] = -0.2;
    d.v0[2] = 5.0;
    ENSURE(sim_run_def(&d, 1.0, 1e-3, &r) == EXDEX_OK);
    for (size_t i = 1; i < r.tr.n; i++) {
        const double *v0 = r.tr.v + 3 * (i - 1), *v1 = r.tr.v + 3 * i;
        double e0 = 0.1 * (v0[0] * v0[0] + v0[1] * v0[1]) + 2e-4 * v0[2] * v0[2];
        double e1 = 0.1 * (v1[0] * v1[0] + v1[1] * v1[1]) + 2e-4 * v1[2] * v1[2];
        ok &= e1 <= e0 * (1 + 1e-9);
        if (r.tr.stick[i]) seen = 1;
        if (seen) still &= r.tr.stick[i] && v1[0] == 0.0 && v1[1] == 0.0 && v1[2] == 0.0;
    }
    ENSURE(ok);
    ENSURE(seen && still);
    d.method = EXDEX_METHOD_IMPLICIT;
    ENSURE(sim_run_def(&d, 1.0, 1e-5, &im) == EXDEX_OK);
    for (int c = 0; c < 3; c++) ENSURE_CLOSE(qlast(&im, c), qlast(&r, c), 1e-4);
    sim_run_free(&r);
    sim_run_free(&im);
}

EXDEX_TEST(methods_planar_slow_steady_slip_event)
{
    /* A planar slip lingering at a small speed (the sliding law's direction
     * relaxes at C / (m |v|): stiff). Gripper at rest, patch at the centre
     * of mass, in-plane gravity g' = C / m along B x (the friction limit
     * exactly), launched at v0 along B y. With phi the angle of v from x:
     * dv/dt = g' (cos phi - 1), v dphi/dt = -g' sin phi, so v (1 + cos phi)
     * = v0: the speed tends to v0 / 2 along x, y to 2/3 v0^2 / g', and x -
     * v0 t / 2 to -3/16 v0^2 / g' (the integrals in tests/scenarios/test_event.py),
     * within a few v0 / g'. v0 = 2e-6 m/s (~3e-6 of the velocity scale)
     * for 2 s: the run returns on one output interval and matches. */
    exdex_scene_def d = mvertical(0.1, 1.0, EXDEX_METHOD_EVENT);
    double v0 = 2e-6, t_end = 2.0, gp, want[3];
    sim_run r;
    d.dof = EXDEX_DOF_PLANAR;
    d.inertia[8] = 1e-4;
    gp = d.mu * d.fingers * d.grip_force / d.mass;
    d.gravity[0] = gp;
    d.gravity[1] = -G;
    d.gravity[2] = 0.0;
    d.v0[1] = v0;
    d.rtol = 1e-10;
    d.atol = 1e-13;
    want[0] = v0 / 2 * t_end - 3.0 / 16.0 * v0 * v0 / gp;
    want[1] = 2.0 / 3.0 * v0 * v0 / gp;
    want[2] = 0.0;
    ENSURE(sim_run_def(&d, t_end, t_end, &r) == EXDEX_OK);
    for (int c = 0; c < 3; c++) ENSURE_CLOSE(qlast(&r, c), want[c], 1e-9 * want[0]);
    sim_run_free(&r);
}

/* Planar box (20 x 40 mm, 0.1 kg) held with friction capacity 0.8 m g
 * (cannot hold the weight alone), centre of pressure 4 mm off the centre of
 * mass, 10 mm above a floor tilted by 0.2 rad; gripper at rest. It slides
 * and turns, lands on a corner (impact), slides along the floor and comes to
 * rest on it, the floor carrying part of the weight. */
static exdex_scene_def planar_floor(int method)
{
    exdex_scene_def d = mvertical(0.1, 0.8, method);
    double tilt = 0.2;
    scene_rect(&d, 0.01, 0.02);
    d.dof = EXDEX_DOF_PLANAR;
    d.inertia[8] = 0.1 * (0.02 * 0.02 + 0.04 * 0.04) / 12;
    d.patch_center[0] = 0.004;
    d.n_stops = 1;
    d.stop_normal[0][0] = sin(tilt);
    d.stop_normal[0][2] = cos(tilt);
    d.stop_point[0][2] = -0.03 - 0.01 * sin(tilt);
    return d;
}

static double pose_err(const sim_run *a, const sim_run *b, size_t ia, size_t ib)
{
    double e = 0.0;
    for (int c = 0; c < 3; c++) e = fmax(e, fabs(a->tr.q[3 * ia + c] - b->tr.q[3 * ib + c]) * (c == 2 ? 0.02 : 1.0));
    return e; /* [m]: theta weighted by the half-length of the box */
}

EXDEX_TEST(methods_planar_stop_every_method_agrees)
{
    /* Reference: the event method at rtol 1e-12 (exact Coulomb, located
     * impact and stop). Independent check of it: the implicit method
     * converges to it at first order (impacts and the stop fall inside
     * steps): error <= 3 dt [m / s] at dt = 1e-5 and falling from 1e-4
     * to 1e-5 by more than 5x. Each other method against it, at t = 0.2 s
     * (resting on the floor) and t = 0.1 s (sliding on the floor):
     *   event rtol 1e-8: within 1e-7 m (tolerance-proportional);
     *   regularised eps 1e-5: O(eps) (creep at rest, eps-wide friction
     *     transition), within 2e-5 m;
     *   explicit: first order (creep at stick dt Q / M, paper), within
     *     3 dt [m / s] at dt = 1e-5 and falling by > 5x per decade. */
    exdex_scene_def d = planar_floor(EXDEX_METHOD_EVENT);
    sim_run ref_r, r1, r2;
    size_t i1 = 100, i2 = 200; /* t = 0.1, 0.2 on the 1e-3 grid */
    double e1, e2;
    d.rtol = 1e-12;
    d.atol = 1e-14;
    ENSURE(sim_run_def(&d, 0.2, 1e-3, &ref_r) == EXDEX_OK);
    ENSURE(ref_r.tr.stick[i2] && ref_r.tr.v[3 * i2] == 0.0 && ref_r.tr.v[3 * i2 + 2] == 0.0);
    d.rtol = 1e-8;
    d.atol = 1e-10;
    ENSURE(sim_run_def(&d, 0.2, 1e-3, &r1) == EXDEX_OK);
    ENSURE(pose_err(&r1, &ref_r, i1, i1) < 1e-7 && pose_err(&r1, &ref_r, i2, i2) < 1e-7);
    report("methods_planar_stop_event_rtol1e-8_err", fmax(pose_err(&r1, &ref_r, i1, i1), pose_err(&r1, &ref_r, i2, i2)));
    sim_run_free(&r1);

    d.method = EXDEX_METHOD_REGULARISED;
    d.eps = 1e-5;
    ENSURE(sim_run_def(&d, 0.2, 1e-3, &r1) == EXDEX_OK);
    e1 = fmax(pose_err(&r1, &ref_r, i1, i1), pose_err(&r1, &ref_r, i2, i2));
    ENSURE(e1 < 2e-5);
    report("methods_planar_stop_regularised_eps1e-5_err", e1);
    sim_run_free(&r1);

    for (int method = EXDEX_METHOD_IMPLICIT; method <= EXDEX_METHOD_EXPLICIT; method += 3) {
        d.method = method;
        ENSURE(sim_run_def(&d, 0.2, 1e-4, &r1) == EXDEX_OK);
        ENSURE(sim_run_def(&d, 0.2, 1e-5, &r2) == EXDEX_OK);
        e1 = fmax(pose_err(&r1, &ref_r, 10 * i1, i1), pose_err(&r1, &ref_r, 10 * i2, i2));
        e2 = fmax(pose_err(&r2, &ref_r, 100 * i1, i1), pose_err(&r2, &ref_r, 100 * i2, i2));
        ENSURE(e2 < 3.0 * 1e-5);
        ENSURE(e1 / e2 > 5.0);
        report(method == EXDEX_METHOD_IMPLICIT ? "methods_planar_stop_implicit_err_dt1e-5"
                                               : "methods_planar_stop_explicit_err_dt1e-5", e2);
        report(method == EXDEX_METHOD_IMPLICIT ? "methods_planar_stop_implicit_ratio_per_decade"
                                               : "methods_planar_stop_explicit_ratio_per_decade", e1 / e2);
        sim_run_free(&r1);
        sim_run_free(&r2);
    }
    sim_run_free(&ref_r);
}

EXDEX_TEST(methods_planar_stop_penetration_bounds)
{
    /* event, regularised: an impact is located to ROOT_TOL = 1e-13 s (at
     * most ~0.2 m/s approach here: 2e-14 m) and the contact rows are
     * projected back after every step: min gap >= -1e-12 m.
     * explicit: the rows are linear in v+ but the vertex moves on a circle:
     * gap(q + h v+) = gap(q) + h G v+ + 1/2 h^2 thd^2 d^2gap/dth^2, with
     * |d^2gap/dth^2| <= r_max (the outline's largest vertex distance from
     * the centre of mass), so the penetration is at most 1/2 h^2 thd^2 r_max
     * (thd the largest |thd| of the run). */
    double rmax = sqrt(0.01 * 0.01 + 0.02 * 0.02);
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_scene_def d = planar_floor(method);
        sim_run r;
        double h = 1e-3, wmax = 0.0, bound;
        d.eps = 1e-5;
        ENSURE(sim_run_def(&d, 0.3, h, &r) == EXDEX_OK);
        for (size_t i = 0; i < r.tr.n; i++) wmax = fmax(wmax, fabs(r.tr.v[3 * i + 2]));
        bound = method == EXDEX_METHOD_EXPLICIT ? 0.5 * h * h * wmax * wmax * rmax + 1e-15 : 1e-12;
        ENSURE(r.st.min_gap >= -bound);
        ENSURE(r.st.min_gap < 1e-6); /* it did land */
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_planar_rest_on_stop_holds)
{
    /* After landing the box rests on the floor: friction alone (0.8 m g)
     * cannot hold the weight, the floor carries the rest. Event: exactly
     * still (v = 0, stick) from t = 0.15 s on, the floor force >= 0, the
     * plate wrench inside the ellipsoid (|E^-1 w| <= mu N), and the static
     * balance of the forces in B: w_xy + lam n_B + m g_B = 0 (gripper at
     * rest, B y up: g_B = (0, -g); n_B = (sin 0.2, cos 0.2)). The implicit
     * method (its own rest solve, implicit.c) gives the same floor force to 1e-3 N. */
    exdex_scene_def d = planar_floor(EXDEX_METHOD_EVENT);
    sim_run r, im;
    double nB[2] = {sin(0.2), cos(0.2)}, cap = 0.8 * 0.1 * G;
    int ok = 1;
    ENSURE(sim_run_def(&d, 0.4, 1e-3, &r) == EXDEX_OK);
    d.method = EXDEX_METHOD_IMPLICIT;
    ENSURE(sim_run_def(&d, 0.4, 1e-4, &im) == EXDEX_OK);
    for (size_t i = 150; i < r.tr.n; i++) {
        const double *w = r.tr.wrench + 3 * i;
        double lam = r.tr.stop_force[i], en;
        ok &= r.tr.stick[i] && r.tr.v[3 * i] == 0.0 && r.tr.v[3 * i + 1] == 0.0 && r.tr.v[3 * i + 2] == 0.0;
        ok &= r.tr.q[3 * i + 2] == r.tr.q[3 * 150 + 2];
        ok &= lam > 0.0;
        en = sqrt(w[0] * w[0] + w[1] * w[1] + (w[2] / d.e_r) * (w[2] / d.e_r));
        ok &= en <= cap * (1 + 1e-9);
        ok &= fabs(w[0] + lam * nB[0]) < 1e-9 && fabs(w[1] + lam * nB[1] - 0.1 * G) < 1e-9;
    }
    ENSURE(ok);
    ENSURE_CLOSE(r.tr.stop_force[r.tr.n - 1], im.tr.stop_force[im.tr.n - 1], 1e-3);
    report("methods_planar_rest_stop_force", r.tr.stop_force[r.tr.n - 1]);
    sim_run_free(&r);
    sim_run_free(&im);
}

EXDEX_TEST(methods_1dof_contact_vertex_handover)
{
    /* 1-DoF translation (B y up), capacity 0.5 m g: the object rests on a
     * horizontal floor with the lower of its two bottom corners (40 mm apart,
     * the right one 1 mm higher). The gripper turns about its plate normal at
     * 1 rad/s, so after atan(1/40) = 0.025 rad the right corner is the lower
     * one: the contact must pass to it (the other corner of the contact stop
     * is guarded too). Without that the right corner went 3 mm through the
     * floor by t = 0.1 s, silently (event, regularised; found by the fuzz). Every
     * corner stays above the floor to rounding and event location, no
     * warning (nothing here is unavoidable); explicit: translation rows are
     * linear in q, so rounding too. */
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_scene_def d = mvertical(0.1, 0.5, method);
        sim_run r;
        d.n_vertices = 2;
        d.vertices[0][0] = -0.02;
        d.vertices[0][1] = -0.011;
        d.vertices[1][0] = 0.02;
        d.vertices[1][1] = -0.010;
        d.n_stops = 1;
        d.stop_normal[0][2] = 1.0;
        d.stop_point[0][2] = -0.011;
        d.eps = 1e-5;
        spin_motion(&d, 1.0);
        d.motion.amplitude = -5.0; /* turning the right corner down */
        ENSURE(sim_run_def(&d, 0.1, 1e-3, &r) == EXDEX_OK);
        ENSURE(r.st.min_gap >= -1e-12);
        ENSURE(r.st.min_gap < 1e-9); /* it does rest on the floor */
        ENSURE(r.st.warnings == 0);
        if (method == EXDEX_METHOD_EVENT) {
            /* the corner on the floor fixes s: the implicit method (its own
             * stop rows and position projection, implicit.c) agrees */
            sim_run im;
            d.method = EXDEX_METHOD_IMPLICIT;
            ENSURE(sim_run_def(&d, 0.1, 1e-3, &im) == EXDEX_OK);
            ENSURE_CLOSE(qlast(&r, 0), qlast(&im, 0), 1e-9);
            sim_run_free(&im);
        }
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_unavoidable_penetration_is_warned)
{
    /* 1-DoF rotation about the pivot (the centre of pressure, at the centre
     * of mass here), a one-vertex outline 10 mm from it; the gripper moves
     * down by 50 mm onto a floor 20 mm below the pivot: once the floor is
     * less than 10 mm below the pivot no angle keeps the vertex above it
     * (the scene drives the pinned pivot through the stop). Every method must count a
     * warning for it (stats.warnings), not penetrate silently. */
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_scene_def d = mvertical(0.1, 2.0, method);
        sim_run r;
        d.dof = EXDEX_DOF_ROTATION;
        d.n_vertices = 1; /* one vertex 10 mm below the pivot (no pinch between vertices) */
        d.vertices[0][0] = 0.0;
        d.vertices[0][1] = -0.01;
        d.n_stops = 1;
        d.stop_normal[0][2] = 1.0;
        d.stop_point[0][2] = -0.02;
        d.motion.kind = EXDEX_MOTION_TRAPEZOID;
        d.motion.axis[2] = -1.0;
        d.motion.amplitude = 0.05;
        d.motion.duration = 0.5;
        d.motion.v_max = 0.2;
        ENSURE(sim_run_def(&d, 0.5, 1e-3, &r) == EXDEX_OK || r.status == EXDEX_ENOCONV);
        ENSURE(r.st.min_gap < -1e-3);
        ENSURE(r.st.warnings > 0);
        sim_run_free(&r);
    }
}

/* ------------------------------------------------------ failure of (a) */

/* twin: tests/scenarios/test_methods.py::test_event_zeno_like_toggling_raises_solver_error */
EXDEX_TEST(methods_event_zeno_like_toggling_fails_loudly)
{
    /* Event-driven friction pays two events for every crossing of the
     * friction limit. A gripper vibrating vertically, z = A sin(2 pi f t),
     * with acceleration amplitude A (2 pi f)^2 = 2 g and capacity 1.5 m g:
     * the load m (g + z'') crosses the capacity twice per period, so the
     * work grows with f, and with one output interval for 1 s of a 1 kHz
     * vibration (> 1000 events in it) the method gives up with
     * EXDEX_ENOCONV instead of looping. At 20 Hz it finishes. */
    double freqs[2] = {20.0, 1000.0};
    for (int k = 0; k < 2; k++) {
        double f = freqs[k], wf = 2 * 3.14159265358979 * f, A = 2 * G / (wf * wf);
        size_t ns = (size_t)(40 * f) + 1;
        double *times = malloc(ns * sizeof *times), *poses = malloc(ns * 7 * sizeof *poses);
        exdex_scene_def d = mvertical(0.1, 1.5, EXDEX_METHOD_EVENT);
        sim_run r;
        int st;
        for (size_t i = 0; i < ns; i++) {
            double t = (double)i / (40 * f);
            times[i] = t;
            memset(poses + 7 * i, 0, 7 * sizeof *poses);
            poses[7 * i + 2] = A * sin(wf * t);
            /* R0 of the default scene: B y = A z; quaternion of R_AB */
            poses[7 * i + 3] = sqrt(0.5);
            poses[7 * i + 4] = sqrt(0.5);
        }
        d.motion.kind = EXDEX_MOTION_SAMPLED;
        d.motion.n_samples = ns;
        d.motion.times = times;
        d.motion.poses = poses;
        st = sim_run_def(&d, 1.0, k == 0 ? 1e-2 : 1.0, &r);
        if (k == 0) {
            ENSURE(st == EXDEX_OK);
            ENSURE(r.tr.q[r.tr.n - 1] < 0.0); /* it slipped down */
            report("methods_event_vibration_20Hz_brent_iterations", (double)r.st.solver_iterations);
        } else {
            ENSURE(st == EXDEX_ENOCONV);
        }
        sim_run_free(&r);
        free(times);
        free(poses);
    }
}

/* ----------------------------------------------------------- contract */

EXDEX_TEST(methods_bad_input_and_determinism)
{
    const char *bad = NULL;
    int status;
    exdex_scene_def d = exdex_default_scene_def();
    sim_run a, b;
    d.method = EXDEX_METHOD_ANALYTIC + 1;   /* no such method */
    ENSURE(exdex_model_alloc(&d, &status, &bad) == NULL && status == EXDEX_EINVAL);
    ENSURE(bad && strcmp(bad, "method") == 0);
    /* planar scenes with stops: every method */
    d = exdex_default_scene_def();
    d.dof = EXDEX_DOF_PLANAR;
    d.n_stops = 1;
    d.stop_normal[0][2] = 1.0;
    d.stop_point[0][2] = -1.0;
    for (int method = EXDEX_METHOD_IMPLICIT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_model *m;
        d.method = method;
        m = exdex_model_alloc(&d, &status, &bad);
        ENSURE(m != NULL && status == EXDEX_OK);
        exdex_model_free(m);
    }
    /* same input, same bits */
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_scene_def p = planar_rot(method);
        ENSURE(sim_run_def(&p, 0.5, 1e-3, &a) == EXDEX_OK);
        ENSURE(sim_run_def(&p, 0.5, 1e-3, &b) == EXDEX_OK);
        ENSURE(memcmp(a.tr.q, b.tr.q, a.tr.n * 3 * sizeof(double)) == 0);
        ENSURE(memcmp(a.tr.wrench, b.tr.wrench, a.tr.n * 3 * sizeof(double)) == 0);
        sim_run_free(&a);
        sim_run_free(&b);
    }
}

/* A friction capacity mu * fingers * grip_force that overflows (mu = DBL_MAX:
 * the fuzzer's input) makes the explicit friction impulse infinite on the
 * first sliding step; the run must end with EXDEX_ENONFINITE, never EXDEX_OK
 * with non-finite samples (the fuzzer's case returned OK with infinite stop
 * forces). A translation scene with an initial slip and a floor stop under
 * the object. The implicit method has the same contract. */
EXDEX_TEST(methods_overflowing_capacity_is_not_ok)
{
    /* the fuzzer's scene (decoded values to 6 digits) */
    static const double R0[9] = {-0.284103, -0.0532491, 0.957314, 0.958791, -0.0132247, 0.283805,
                                 -0.00245218, 0.998494, 0.0548119};
    for (int method = EXDEX_METHOD_IMPLICIT; method <= EXDEX_METHOD_EXPLICIT; method++) {
        exdex_scene_def d = exdex_default_scene_def();
        sim_run r;
        int st;
        double n0[3] = {0.600459, 0.697336, -0.391371}, n1[3] = {0.609054, -0.5443, 0.576879};
        double nn0 = sqrt(n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]);
        double nn1 = sqrt(n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2]);
        double ax = hypot(-0.986489, -0.163826), back = 1e-4;
        d.mass = 0.0349442;
        memset(d.inertia, 0, sizeof d.inertia);
        d.inertia[0] = 7.44052e-05;
        d.inertia[4] = 0.000144045;
        d.inertia[8] = 3.85991e-05;
        d.mu = DBL_MAX;
        d.grip_force = 0.99058;
        d.e_r = 0.000958726;
        d.patch_center[0] = 0.00303998;
        d.patch_center[1] = 0.0135353;
        d.gravity[0] = -7.74766;
        d.gravity[1] = 6.92394;
        d.gravity[2] = -7.33837;
        d.dof = EXDEX_DOF_TRANSLATION;
        d.slide_axis[0] = -0.986489 / ax;
        d.slide_axis[1] = -0.163826 / ax;
        d.q0[0] = 0.0246603;
        d.q0[1] = 0.0178307;
        d.q0[2] = 1.79764;
        d.v0[0] = 0.397299;
        memcpy(d.R0, R0, sizeof R0);
        {
            /* re-orthonormalise the 6-digit rows (Gram-Schmidt) */
            double *a0 = d.R0, *a1 = d.R0 + 3, *a2 = d.R0 + 6, k;
            k = sqrt(a0[0] * a0[0] + a0[1] * a0[1] + a0[2] * a0[2]);
            for (int i = 0; i < 3; i++) a0[i] /= k;
            k = a1[0] * a0[0] + a1[1] * a0[1] + a1[2] * a0[2];
            for (int i = 0; i < 3; i++) a1[i] -= k * a0[i];
            k = sqrt(a1[0] * a1[0] + a1[1] * a1[1] + a1[2] * a1[2]);
            for (int i = 0; i < 3; i++) a1[i] /= k;
            a2[0] = a0[1] * a1[2] - a0[2] * a1[1];
            a2[1] = a0[2] * a1[0] - a0[0] * a1[2];
            a2[2] = a0[0] * a1[1] - a0[1] * a1[0];
        }
        d.p0[0] = -1.16034;
        d.p0[1] = 0.914303;
        d.p0[2] = -0.603891;
        d.n_stops = 2;
        d.stop_point[0][0] = 0.0987222;
        d.stop_point[0][1] = 0.11465;
        d.stop_point[0][2] = -0.0643458;
        d.stop_point[1][0] = -0.950178;
        d.stop_point[1][1] = 0.849156;
        d.stop_point[1][2] = -0.899982;
        for (int i = 0; i < 3; i++) {
            d.stop_normal[0][i] = n0[i] / nn0;
            d.stop_normal[1][i] = n1[i] / nn1;
            /* 6-digit values put the start just beyond a stop: back off */
            d.stop_point[0][i] -= back * d.stop_normal[0][i];
            d.stop_point[1][i] -= back * d.stop_normal[1][i];
        }
        d.method = method;
        st = sim_run_def(&d, 0.0053901154634270233, 0.0017544261973184241, &r);
        if (st == EXDEX_OK) {
            /* then every sample must be finite */
            for (size_t i = 0; i < r.tr.n; i++) {
                ENSURE(isfinite(r.tr.q[i]) && isfinite(r.tr.v[i]) && isfinite(r.tr.wrench[3 * i]) &&
                       isfinite(r.tr.wrench[3 * i + 1]) && isfinite(r.tr.wrench[3 * i + 2]));
                for (int k = 0; k < 2; k++) ENSURE(isfinite(r.tr.stop_force[2 * i + (size_t)k]));
            }
        } else {
            ENSURE(st == EXDEX_ENONFINITE);
        }
        sim_run_free(&r);
    }
}

EXDEX_TEST(methods_hybrid_grazing_corner_impact_inside_one_step)
{
    /* A 4 x 2 cm box spins freely about its centre of mass (mu = 0, gravity
     * along the plate normal, B = A) at w0 = 2 pi rad/s past a stop placed
     * eps = 0.05 rad short of its corners' reach: a corner is below the
     * stop plane only while it turns through 2 eps. The free spin is
     * integrated exactly, so one step can span the output interval and
     * both end gaps are positive. Closed form: corner j (angle alpha_j)
     * reaches the stop when alpha_j + w0 t = -pi/2 - eps (mod 2 pi); the
     * first such t* stops the spin (the inelastic impact kills the only
     * velocity, no torque acts after it): theta = w0 t*, rate 0. */
    const double a = 0.04, b = 0.02, eps = 0.05, w0 = 2.0 * EXDEX_TEST_PI, Rc = 0.5 * hypot(a, b);
    int methods[2] = {EXDEX_METHOD_EVENT, EXDEX_METHOD_REGULARISED};
    double t_star = INFINITY;
    for (int sx = -1; sx <= 1; sx += 2)
        for (int sy = -1; sy <= 1; sy += 2) {
            double al = atan2(sy * b / 2, sx * a / 2), x = fmod(-EXDEX_TEST_PI / 2 - eps - al, 2 * EXDEX_TEST_PI);
            if (x < 0) x += 2 * EXDEX_TEST_PI;
            t_star = fmin(t_star, x / w0);
        }
    for (int k = 0; k < 2; k++) {
        exdex_scene_def d = exdex_default_scene_def();
        sim_run r;
        d.method = methods[k];
        d.mass = 0.1;
        d.mu = 0.0;
        d.grip_force = 1.0;
        d.fingers = 2;
        d.dof = EXDEX_DOF_ROTATION;
        d.gravity[0] = d.gravity[1] = 0.0;
        d.gravity[2] = -G;
        for (int i = 0; i < 9; i++) d.R0[i] = i % 4 == 0 ? 1.0 : 0.0;
        d.v0[2] = w0;
        d.n_vertices = 4;
        d.vertices[0][0] = a / 2, d.vertices[0][1] = b / 2;
        d.vertices[1][0] = -a / 2, d.vertices[1][1] = b / 2;
        d.vertices[2][0] = -a / 2, d.vertices[2][1] = -b / 2;
        d.vertices[3][0] = a / 2, d.vertices[3][1] = -b / 2;
        d.n_stops = 1;
        d.stop_point[0][0] = d.stop_point[0][2] = 0.0;
        d.stop_point[0][1] = -Rc * cos(eps);
        d.stop_normal[0][0] = d.stop_normal[0][2] = 0.0;
        d.stop_normal[0][1] = 1.0;
        d.rtol = 1e-9;
        ENSURE(sim_run_def(&d, 1.0, 1.0, &r) == EXDEX_OK);
        ENSURE(r.st.impacts == 1);
        ENSURE_CLOSE(r.tr.q[r.tr.n - 1], w0 * t_star, 1e-8);
        ENSURE(r.tr.v[r.tr.n - 1] == 0.0);
        ENSURE(r.st.min_gap >= -1e-12);
        sim_run_free(&r);
    }
}

/* s' of the brief slip below (closed form; params: K, delta, w, tau1) */
static double brief_slip_rate(double tau, void *p)
{
    const double *c = p;
    return c[0] * ((1 - c[1]) * (tau - c[3]) - (sin(c[2] * tau) - sin(c[2] * c[3])) / c[2]);
}

EXDEX_TEST(methods_event_brief_slip_inside_one_stick_step)
{
    /* A held object under a vertical shake A (1 - cos w t), A < 0: the
     * gripper's upward acceleration peaks at |A| w^2 at t = pi / w and the
     * capacity m (g + (1 - delta) |A| w^2) lets the object slip only near
     * that peak. With tau = t - pi / w and K = |A| w^2 it slips down from
     * tau1 = -acos(1 - delta) / w with s'' = K ((1 - delta) - cos w tau):
     *   s'(tau) = K ((1 - delta) (tau - tau1) - (sin w tau - sin w tau1) / w),
     *   s(tau)  = K ((1 - delta) (tau - tau1)^2 / 2
     *             + (cos w tau - cos w tau1) / w^2 + sin(w tau1) (tau - tau1) / w),
     * until s' = 0 at tau2 > -tau1 (GSL Brent here), then holds. Output
     * grid one interval, loose tolerance: the rest is one step across the
     * peak unless the slip is found inside it. */
    const double m = 0.1, A = -0.01, f = 2.0, delta = 0.01, w = 2.0 * EXDEX_TEST_PI * f, K = fabs(A) * w * w;
    double c[4] = {K, delta, w, -acos(1 - delta) / w}, tau2 = 0.0, s2;
    gsl_function F = {brief_slip_rate, c};
    gsl_root_fsolver *rs = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    ENSURE(rs != NULL);
    gsl_root_fsolver_set(rs, &F, -c[3], EXDEX_TEST_PI / w);
    for (int it = 0; it < 200; it++) {
        gsl_root_fsolver_iterate(rs);
        tau2 = gsl_root_fsolver_root(rs);
        if (gsl_root_fsolver_x_upper(rs) - gsl_root_fsolver_x_lower(rs) < 1e-15) break;
    }
    gsl_root_fsolver_free(rs);
    s2 = K * ((1 - delta) * (tau2 - c[3]) * (tau2 - c[3]) / 2 + (cos(w * tau2) - cos(w * c[3])) / (w * w) +
              sin(w * c[3]) * (tau2 - c[3]) / w);
    ENSURE(s2 < -1e-6);
    for (int k = 0; k < 2; k++) {
        double rtol = k ? 1e-8 : 1e-6;
        exdex_scene_def d = mvertical(m, (G + (1 - delta) * K) / G, EXDEX_METHOD_EVENT);
        sim_run r;
        d.motion.kind = EXDEX_MOTION_SHAKE;
        d.motion.axis[0] = d.motion.axis[1] = 0.0;
        d.motion.axis[2] = 1.0;
        d.motion.amplitude = A;
        d.motion.frequency = f;
        d.motion.duration = 1.0 / f;
        d.rtol = rtol;
        d.atol = 1e-3 * rtol;
        ENSURE(sim_run_def(&d, 1.0, 1.0, &r) == EXDEX_OK);
        ENSURE_CLOSE(r.tr.q[r.tr.n - 1], s2, 10 * rtol * fabs(s2));
        sim_run_free(&r);
    }
}

/* The gripper carries the object down at V along the slide axis (B y up,
 * gravity along it) and stops instantly at T (a trapezoid without ramps:
 * v_max = |X1| / T, a velocity jump at T; the one at 0 is the start). The
 * object, held before T (capacity 2 m g >= m g), keeps its absolute
 * velocity through the stop (the plates carry no impulse), slides down at
 * V relative to the plates, decelerated by friction minus gravity,
 * a = C / m - g = g, and slides V^2 / (2 a). T = 0.3001 s falls inside a
 * step of every dt below (the step is split there). implicit: at rest
 * before T, exact under the trapezoid rule after it but for the step in
 * which it sticks, which starts at a slip speed u <= min(V, h a) and moves
 * h u / 2 instead of u^2 / (2 a): |err| <= h min(V, h a) / 2 (a step taking
 * the jump as a step-mean acceleration errs by V h / 2 at dt = 1e-4, or
 * absorbs the whole slide at dt = 1e-3, where h a >= V). explicit (its
 * velocity chatters about rest in a band h (C / m + g) before T and after
 * the stop): |err| <= V h (C/m + g) / a + (h (C/m + g))^2 / (2 a) + h V / 2
 * + h^2 a + h (C/m + g) (t_end - t_stop). Measured from the sample before T. */
EXDEX_TEST(methods_stop_from_speed_slide_closed_form)
{
    const double V = 0.005, T = 0.3001, t_end = 0.32, a = G, ca = 3 * G, exact = -V * V / (2 * a);
    const double dts[3] = {1e-3, 1e-4, 1e-5};
    const int methods[2] = {EXDEX_METHOD_IMPLICIT, EXDEX_METHOD_EXPLICIT};
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 3; i++) {
            double h = dts[i], d, bound, t_stop = T + V / a;
            exdex_scene_def sd = mvertical(0.1, 2.0, methods[k]);
            sim_run r;
            size_t j0;
            scene_trapezoid(&sd, 0, 0.0, 0.0, -1.0, V * T, T, V);
            ENSURE(sim_run_def(&sd, t_end, h, &r) == EXDEX_OK);
            j0 = (size_t)floor(T / h);   /* the sample before T */
            ENSURE(r.tr.t[j0] < T && r.tr.t[j0 + 1] > T);
            d = qlast(&r, 0) - r.tr.q[j0 * (size_t)r.ndof];
            bound = k == 0 ? h * fmin(V, h * a) / 2
                           : V * h * ca / a + (h * ca) * (h * ca) / (2 * a) + h * V / 2 + h * h * a +
                                 h * ca * (t_end - t_stop);
            ENSURE(fabs(d - exact) <= bound + 1e-15);
            if (i == 2) report(k == 0 ? "methods_stop_slide_err_implicit_1e-5" : "methods_stop_slide_err_explicit_1e-5",
                               d - exact);
            sim_run_free(&r);
        }
}
