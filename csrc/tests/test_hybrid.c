/* test_hybrid.c -- hybrid.c (the event and regularised drivers) against
 * closed forms of the 1-DoF vertical problem. */
#include "check.h"
#include "sim_run.h"
#include "../exdex.h"

#include <math.h>

/* mu = 0: free fall along B y, q - q0 = -g t^2 / 2, v = -g t on the output
 * grid (rk8pd is exact to rounding on a polynomial of degree 2), for both
 * drivers. */
EXDEX_TEST(hybrid_event_and_regularised_free_fall)
{
    const int methods[2] = {EXDEX_METHOD_EVENT, EXDEX_METHOD_REGULARISED};
    for (int k = 0; k < 2; k++) {
        exdex_scene_def d = scene_vertical(0.3, 1.0);
        sim_run r;
        d.mu = 0.0;
        d.method = methods[k];
        ENSURE(sim_run_def(&d, 0.5, 0.05, &r) == EXDEX_OK);
        ENSURE(r.tr.n == 11);
        for (size_t i = 0; i < r.tr.n && r.tr.n == 11; i++) {
            double t = r.tr.t[i];
            ENSURE_CLOSE(t, 0.05 * (double)i, 1e-15);
            ENSURE_CLOSE(r.tr.q[i] - r.tr.q[0], -0.5 * 9.81 * t * t, 1e-12);
            ENSURE_CLOSE(r.tr.v[i], -9.81 * t, 1e-12);
        }
        ENSURE(r.st.fail_cause == EXDEX_FAIL_NONE);
        sim_run_free(&r);
    }
}

/* Capacity 0.6 m g below the weight: the event method slides at the net
 * acceleration -(g - 0.6 g) from the start, q - q0 = -0.2 g t^2, to its
 * tolerance (rtol 1e-8 of the default def, tightened here to 1e-12). */
EXDEX_TEST(hybrid_event_slide_follows_the_net_acceleration)
{
    exdex_scene_def d = scene_vertical(0.2, 0.6);
    sim_run r;
    d.method = EXDEX_METHOD_EVENT;
    d.rtol = 1e-12;
    d.atol = 1e-12;
    ENSURE(sim_run_def(&d, 1.0, 0.1, &r) == EXDEX_OK);
    ENSURE(r.tr.n == 11);
    for (size_t i = 1; i < r.tr.n && r.tr.n == 11; i++) {
        double t = r.tr.t[i];
        ENSURE_CLOSE(r.tr.q[i] - r.tr.q[0], -0.5 * 0.4 * 9.81 * t * t, 1e-10);
        ENSURE_CLOSE(r.tr.v[i], -0.4 * 9.81 * t, 1e-10);
        ENSURE(r.tr.stick[i] == 0);
    }
    sim_run_free(&r);
}
