/* test_hybrid_events.c -- the within-step dip searches of the hybrid methods'
 * event location (hybrid_events.c), called directly on the state of a begun
 * event run, against closed forms.
 *
 * The scene: a box (a x b) spinning freely (mu = 0, gravity along the plate
 * normal, gripper at rest, B = A) past a stop y >= -d placed eps short of its
 * corners' reach, d = R_c cos(eps) (R_c the half-diagonal): a corner dips
 * below the stop plane only over a turn of 2 eps. The motion is exact in
 * closed form, q(t) = q0 + v0 t, and so is the stepper's one-step map that the
 * searches evaluate (rk8pd on a motion linear in t: exact to rounding). Over
 * a step [t0, t1] that covers the dip, from a turn of 2 eps before it to 2 eps
 * after it, both end gaps are positive (R_c (cos eps - cos 3 eps) ~ 4 eps^2
 * R_c): the end values do not show the impact, only an interior minimum
 * does.
 *   corner j (angle alpha_j, radius R_c) is at height
 *     y_j(t) = vy t + R_c sin(alpha_j + w0 t)   (planar; vy = 0 for 1-DoF)
 *   and first reaches -d at the root t* of y_j(t) + d (closed form for vy = 0:
 *   alpha_j + w0 t* = -pi/2 - eps mod 2 pi; with vy != 0 the root is
 *   bisected here to 1e-15 s on that formula, independent of exdex).
 * Each test also checks that a step ending before the dip finds nothing
 * (the search fails where it should not fire).
 *
 * hyb_obst_dips: a point (one outline vertex) in free flight at (vx, vy),
 * vy > 0, reaches the left face x = X0 of a thin obstacle slab (x in [X0,
 * X0 + W], top y = Y) at t_in = X0 / vx, d below its top, and would leave
 * it through the top at t_in + d / vy: the row's gap max(X0 - x, y - Y,
 * ...) is negative only in between, positive at both ends of a step over
 * both times, its rate jumping where the active face changes (no smooth
 * turn). The first crossing of 0 is t_in. */
#include "check.h"
#include "hybrid_scene.h"
#include "sim_run.h"

#include <math.h>
#include <string.h>

#define BOX_A 0.04
#define BOX_B 0.02
#define EPS_TURN 0.05

static exdex_scene_def spin_def(int dof, double vx, double vy, double w0)
{
    double a = BOX_A, b = BOX_B, Rc = 0.5 * hypot(a, b);
    exdex_scene_def d = scene_plate_box(a, b, 0.01, 0.1);
    d.grip_force = 1.0;
    d.fingers = 2;
    d.e_r = 0.0033;
    d.dof = dof;
    d.v0[0] = vx;
    d.v0[1] = vy;
    d.v0[2] = w0;
    if (dof == EXDEX_DOF_ROTATION) d.v0[0] = w0;
    scene_stop(&d, 0, 0.0, -Rc * cos(EPS_TURN), 0.0, 0.0, 1.0, 0.0);
    d.method = EXDEX_METHOD_EVENT;
    d.rtol = 1e-10;
    d.atol = 1e-10;
    return d;
}

/* Height of corner j plus d at t (the closed-form gap of its stop row). */
static double corner_gap(int j, double vy, double w0, double t)
{
    double a = BOX_A, b = BOX_B, Rc = 0.5 * hypot(a, b);
    double cx = (j < 2 ? a : -a) / 2, cy = (j == 0 || j == 3 ? -b : b) / 2;
    return vy * t + sin(w0 * t) * cx + cos(w0 * t) * cy + Rc * cos(EPS_TURN);
}

/* The first crossing t* of 0 by any corner's gap in (0, T), bisected on the
 * closed form; *jmin gets the corner. */
static double first_crossing(double vy, double w0, double T, int *jmin)
{
    double best = INFINITY;
    int n = 200000;
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < n; i++) {
            double lo = T * i / n, hi = T * (i + 1) / n;
            if (!(corner_gap(j, vy, w0, lo) > 0.0 && corner_gap(j, vy, w0, hi) <= 0.0)) continue;
            for (int it = 0; it < 200 && hi - lo > 1e-15; it++) {
                double mid = 0.5 * (lo + hi);
                if (corner_gap(j, vy, w0, mid) > 0.0)
                    lo = mid;
                else
                    hi = mid;
            }
            if (hi < best) {
                best = hi;
                *jmin = j;
            }
            break;
        }
    return best;
}

/* The free motion's state at t from q0 (NULL: 0); the force integrals stay 0. */
static void free_state_from(const hyb *H, const double *q0, const double *v0, double t, double *y)
{
    memset(y, 0, (size_t)H->ny * sizeof *y);
    for (int c = 0; c < H->ndof; c++) {
        y[c] = (q0 ? q0[c] : 0.0) + v0[c] * t;
        y[H->ndof + c] = v0[c];
    }
}

static void free_state(const hyb *H, const double *v0, double t, double *y)
{
    free_state_from(H, NULL, v0, t, y);
}

EXDEX_TEST(row_dip_finds_a_corner_grazing_a_stop_inside_one_step)
{
    /* 1-DoF rotation about the centre of mass: the stop's guard is the least
     * gap over the outline, whose end rates can be another corner's, so the
     * free (stop, vertex) rows are searched one by one (hyb_row_dip) */
    const double w0 = 2.0 * M_PI;
    exdex_scene_def d = spin_def(EXDEX_DOF_ROTATION, 0.0, 0.0, w0);
    begun b;
    int j = -1;
    double t_star = first_crossing(0.0, w0, 1.0, &j), y0[NY_MAX], y1[NY_MAX], tau, v0[1] = {w0};
    double t_closed = INFINITY;
    ENSURE(begin_run(&d, 1.0, &b) == EXDEX_OK);
    hyb *H = &b.O->S.H;
    for (int k = 0; k < 4; k++) {
        double alpha = atan2(d.vertices[k][1], d.vertices[k][0]);
        t_closed = fmin(t_closed, fmod(fmod(-M_PI / 2 - EPS_TURN - alpha, 2 * M_PI) + 2 * M_PI, 2 * M_PI) / w0);
    }
    ENSURE_CLOSE(t_star, t_closed, 1e-12);
    /* a step over the dip: both ends above the stop */
    double t0 = t_star - 2.0 * EPS_TURN / w0, t1 = t_star + 4.0 * EPS_TURN / w0;
    free_state(H, v0, t0, y0);
    free_state(H, v0, t1, y1);
    ENSURE(corner_gap(j, 0.0, w0, t0) > 0.0 && corner_gap(j, 0.0, w0, t1) > 0.0);
    ENSURE(hyb_row_dip(H, b.O, t0, y0, t1, y1, &tau) == EXDEX_OK);
    ENSURE_CLOSE(tau, t_star - t0, 1e-9);
    /* a step ending before the dip: nothing */
    t1 = t_star - 0.5 * EPS_TURN / w0;
    free_state(H, v0, t1, y1);
    ENSURE(hyb_row_dip(H, b.O, t0, y0, t1, y1, &tau) == EXDEX_OK);
    ENSURE(isinf(tau));
    end_run(&b);
}

EXDEX_TEST(gap_dips_finds_a_planar_corner_grazing_a_stop_inside_one_step)
{
    /* planar free flight: each free (stop, vertex) row is a guard of its
     * own (G_GAP); its dip is found from the gaps' rates at the step's ends
     * (hyb_gap_dips) and located on the stepper's map */
    const double w0 = 3.0, vx = 0.01, vy = 0.0, v0[3] = {vx, vy, w0};
    exdex_scene_def d = spin_def(EXDEX_DOF_PLANAR, vx, vy, w0);
    begun b;
    int j = -1, e_best = -1, ng0, ng1;
    double t_star = first_crossing(vy, w0, 2.0 * M_PI / w0, &j), y0[NY_MAX], y1[NY_MAX], tau = INFINITY, t0, t1;
    hyb_guard g0[NG_MAX], g1[NG_MAX];
    ENSURE(begin_run(&d, 2.0, &b) == EXDEX_OK);
    hyb *H = &b.O->S.H;
    ENSURE(isfinite(t_star));
    t0 = t_star - 2.0 * EPS_TURN / w0;
    t1 = t_star + 4.0 * EPS_TURN / w0;
    free_state(H, v0, t0, y0);
    free_state(H, v0, t1, y1);
    ENSURE(corner_gap(j, vy, w0, t0) > 0.0 && corner_gap(j, vy, w0, t1) > 0.0);
    ng0 = hyb_guards(H, t0, y0, g0);
    ng1 = hyb_guards(H, t1, y1, g1);
    ENSURE(ng0 == ng1 && ng0 > 0);
    for (int e = 0; e < ng0; e++) ENSURE(g0[e].value > 0.0 && g1[e].value > 0.0);   /* the end values do not show it */
    ENSURE(hyb_gap_dips(H, b.O, t0, y0, t1, y1, ng0, g0, g1, &tau, &e_best) == EXDEX_OK);
    ENSURE_CLOSE(tau, t_star - t0, 1e-9);
    ENSURE(e_best >= 0 && g0[e_best].kind == G_GAP && g0[e_best].row == j);
    /* a step ending before the dip: nothing */
    tau = INFINITY;
    e_best = -1;
    t1 = t_star - 0.5 * EPS_TURN / w0;
    free_state(H, v0, t1, y1);
    hyb_guards(H, t1, y1, g1);
    ENSURE(hyb_gap_dips(H, b.O, t0, y0, t1, y1, ng0, g0, g1, &tau, &e_best) == EXDEX_OK);
    ENSURE(e_best == -1 && isinf(tau));
    end_run(&b);
}

EXDEX_TEST(obst_dips_finds_a_point_cutting_an_obstacle_corner_inside_one_step)
{
    const double vx = 0.02, vy = 0.001, X0 = 0.01, W = 0.002, Y = 0.0, dd = 1e-5;
    const double t_in = X0 / vx, q0[3] = {0.0, Y - dd - vy * t_in, 0.0}, v0[3] = {vx, vy, 0.0};
    exdex_scene_def d = spin_def(EXDEX_DOF_PLANAR, vx, vy, 0.0);
    begun b;
    int e_best = -1, ng0, ng1, any = 0;
    double y0[NY_MAX], y1[NY_MAX], tau = INFINITY, t0 = t_in - 0.05, t1 = t_in + 0.06;
    hyb_guard g0[NG_MAX], g1[NG_MAX];
    d.n_vertices = 1;
    d.vertices[0][0] = d.vertices[0][1] = 0.0;
    d.inertia[0] = d.inertia[4] = d.inertia[8] = 1e-5;
    d.n_stops = 0;
    d.q0[0] = q0[0];
    d.q0[1] = q0[1];
    d.obstacles[0].mu = 0.0;
    scene_obstacle_box(&d, 0, (const double[3]){X0 + W / 2, Y - 0.05, 0.0}, (const double[3]){W / 2, 0.05, 0.05});
    ENSURE(t1 > t_in + dd / vy && vx * t1 < X0 + W);   /* out through the top, not the far side */
    ENSURE(begin_run(&d, 1.0, &b) == EXDEX_OK);
    hyb *H = &b.O->S.H;
    free_state_from(H, q0, v0, t0, y0);
    free_state_from(H, q0, v0, t1, y1);
    ng0 = hyb_guards(H, t0, y0, g0);
    ng1 = hyb_guards(H, t1, y1, g1);
    ENSURE(ng0 == ng1 && ng0 > 0);
    for (int e = 0; e < ng0; e++) {
        ENSURE(g0[e].value > 0.0 && g1[e].value > 0.0);   /* the end values do not show it */
        any |= g0[e].kind == G_OBST_GAP;
    }
    ENSURE(any);
    ENSURE(hyb_obst_dips(H, b.O, t0, y0, t1, y1, ng0, g0, g1, &tau, &e_best) == EXDEX_OK);
    ENSURE_CLOSE(tau, t_in - t0, 1e-9);
    ENSURE(e_best >= 0 && g0[e_best].kind == G_OBST_GAP);
    /* a step ending before the face is reached: nothing */
    tau = INFINITY;
    e_best = -1;
    t1 = t_in - 0.01;
    free_state_from(H, q0, v0, t1, y1);
    hyb_guards(H, t1, y1, g1);
    ENSURE(hyb_obst_dips(H, b.O, t0, y0, t1, y1, ng0, g0, g1, &tau, &e_best) == EXDEX_OK);
    ENSURE(e_best == -1 && isinf(tau));
    end_run(&b);
}
