/* test_implicit.c -- implicit.c (the Moreau midpoint step) against closed
 * forms of frictionless flight. */
#include "check.h"
#include "sim_run.h"
#include "../exdex.h"

/* mu = 0: the object falls freely along B y under -g. The midpoint step
 * (q_m = q0 + h/2 v0, v1 = v0 + h a, q1 = q_m + h/2 v1) is exact for a
 * constant acceleration: q = q0 - g t^2 / 2, v = -g t, after one step and
 * after many. */
static void free_flight(double t_end, double dt, int n_expected)
{
    const double g = 9.81;
    exdex_scene_def d = scene_vertical(0.3, 1.0);
    sim_run r;
    d.mu = 0.0;
    d.method = EXDEX_METHOD_IMPLICIT;
    ENSURE(sim_run_def(&d, t_end, dt, &r) == EXDEX_OK);
    ENSURE((int)r.tr.n == n_expected);
    for (size_t i = 1; i < r.tr.n && (int)r.tr.n == n_expected; i++) {
        double t = r.tr.t[i];
        ENSURE_CLOSE(r.tr.q[i] - r.tr.q[0], -0.5 * g * t * t, 1e-12);
        ENSURE_CLOSE(r.tr.v[i], -g * t, 1e-12);
        ENSURE(r.tr.stick[i] == 0);
        ENSURE_SMALL(r.tr.wrench[3 * i + 1], 1e-15);
    }
    ENSURE(r.st.stick_steps == 0);
    sim_run_free(&r);
}

EXDEX_TEST(implicit_one_step_of_free_flight)
{
    free_flight(1e-2, 1e-2, 2);
}

EXDEX_TEST(implicit_free_flight_many_steps)
{
    free_flight(0.5, 1e-2, 51);
}

/* The gripper at rest, capacity 2 m g: the first step sticks exactly
 * (the maximum-dissipation solve holds the object), v stays 0. */
EXDEX_TEST(implicit_one_step_holds_inside_the_cone)
{
    exdex_scene_def d = scene_vertical(0.3, 2.0);
    sim_run r;
    d.method = EXDEX_METHOD_IMPLICIT;
    ENSURE(sim_run_def(&d, 1e-2, 1e-2, &r) == EXDEX_OK);
    ENSURE(r.tr.n == 2);
    if (r.tr.n == 2) {
        ENSURE(r.tr.stick[1] == 1);
        ENSURE(r.tr.v[1] == 0.0 && r.tr.q[1] == r.tr.q[0]);
        ENSURE_CLOSE(r.tr.wrench[4], 0.3 * 9.81, 1e-12);
    }
    sim_run_free(&r);
}
