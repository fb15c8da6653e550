/* test_explicit.c -- explicit.c (symplectic Euler with Coulomb sign())
 * against closed forms of its own recurrence. */
#include "check.h"
#include "sim_run.h"
#include "../exdex.h"

/* mu = 0: v_{k+1} = v_k - g h, q_{k+1} = q_k + h v_{k+1} from rest give
 * v_k = -g h k and q_k - q_0 = -g h^2 k (k + 1) / 2 (summing the
 * velocities): one step -g h^2, twice the exact fall. */
static void free_flight(double t_end, double dt, int n_expected)
{
    const double g = 9.81;
    exdex_scene_def d = scene_vertical(0.3, 1.0);
    sim_run r;
    d.mu = 0.0;
    d.method = EXDEX_METHOD_EXPLICIT;
    ENSURE(sim_run_def(&d, t_end, dt, &r) == EXDEX_OK);
    ENSURE((int)r.tr.n == n_expected);
    for (size_t k = 1; k < r.tr.n && (int)r.tr.n == n_expected; k++) {
        double kk = (double)k;
        ENSURE_CLOSE(r.tr.q[k] - r.tr.q[0], -0.5 * g * dt * dt * kk * (kk + 1.0), 1e-12);
        ENSURE_CLOSE(r.tr.v[k], -g * dt * kk, 1e-12);
        ENSURE_SMALL(r.tr.wrench[3 * k + 1], 1e-15);
    }
    sim_run_free(&r);
}

EXDEX_TEST(explicit_one_step_of_free_flight)
{
    free_flight(1e-2, 1e-2, 2);
}

EXDEX_TEST(explicit_free_flight_many_steps)
{
    free_flight(0.5, 1e-2, 51);
}

/* Sliding down under the kinetic friction of capacity c = 0.5 m g (below
 * the weight). sign(0) = 0: the first step from rest has no friction,
 * v_1 = -g h; after it the object slides and the net acceleration is
 * -(g - c/m) = -g/2 = -a: v_k = -g h - a h (k - 1), and summing the
 * velocities q_k - q_0 = -h^2 (g k + a k (k - 1) / 2). */
EXDEX_TEST(explicit_sliding_steps_follow_the_net_acceleration)
{
    const double g = 9.81, h = 1e-3, a = 0.5 * g;
    exdex_scene_def d = scene_vertical(0.2, 0.5);
    sim_run r;
    d.method = EXDEX_METHOD_EXPLICIT;
    ENSURE(sim_run_def(&d, 0.1, h, &r) == EXDEX_OK);
    ENSURE(r.tr.n == 101);
    for (size_t k = 1; k < r.tr.n && r.tr.n == 101; k++) {
        double kk = (double)k;
        ENSURE_CLOSE(r.tr.v[k], -g * h - a * h * (kk - 1.0), 1e-12);
        ENSURE_CLOSE(r.tr.q[k] - r.tr.q[0], -h * h * (g * kk + 0.5 * a * kk * (kk - 1.0)), 1e-12);
        ENSURE(r.tr.stick[k] == 0);
    }
    sim_run_free(&r);
}
