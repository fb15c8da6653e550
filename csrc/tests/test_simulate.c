/* test_simulate.c -- simulate.c: exdex_n_samples, the output grid, the
 * argument checks and the stats of exdex_simulate. */
#include "check.h"
#include "sim_run.h"
#include "../exdex.h"

#include <math.h>

/* Samples = steps + 1, the last step shortened to end at t_end; invalid
 * (t_end, dt) give 0. Counted by hand. */
EXDEX_TEST(simulate_n_samples_counts_steps)
{
    ENSURE(exdex_n_samples(1.0, 0.25) == 5);   /* 4 full steps */
    ENSURE(exdex_n_samples(1.0, 0.3) == 5);    /* 0.3, 0.6, 0.9, then 0.1 */
    ENSURE(exdex_n_samples(1.0, 1.0) == 2);
    ENSURE(exdex_n_samples(0.7, 1e-3) == 701); /* 0.7 / 1e-3 rounds to 700 */
    ENSURE(exdex_n_samples(1.0, 0.0) == 0);
    ENSURE(exdex_n_samples(1.0, -0.1) == 0);
    ENSURE(exdex_n_samples(1.0, 2.0) == 0);
    ENSURE(exdex_n_samples(0.0, 0.1) == 0);
    ENSURE(exdex_n_samples(NAN, 0.1) == 0);
    ENSURE(exdex_n_samples(INFINITY, 0.1) == 0);
    ENSURE(exdex_n_samples(1e10, 1.0) == 0);   /* beyond EXDEX_MAX_STEPS */
}

/* A held scene (capacity 2 m g, gripper at rest) on a grid whose last step
 * is short: t_i = i dt then t_end, q and v stay at rest, every step sticks,
 * the plates carry the weight m g along B y (gravity is -g along B y), the
 * stats count the steps and nothing else. */
EXDEX_TEST(simulate_held_scene_grid_and_stats)
{
    const double m = 0.2, g = 9.81;
    exdex_scene_def d = scene_vertical(m, 2.0);
    sim_run r;
    ENSURE(sim_run_def(&d, 1.0, 0.3, &r) == EXDEX_OK);
    ENSURE(r.tr.n == 5 && r.ndof == 1 && r.nstops == 0);
    if (r.tr.n == 5) {
        const double t_ref[5] = {0.0, 0.3, 0.6, 0.9, 1.0};
        for (int i = 0; i < 5; i++) {
            ENSURE_CLOSE(r.tr.t[i], t_ref[i], 1e-15);
            ENSURE(r.tr.q[i] == r.tr.q[0]);
            ENSURE(r.tr.v[i] == 0.0);
            ENSURE_SMALL(r.tr.wrench[3 * i + 0], 1e-12);
            ENSURE_CLOSE(r.tr.wrench[3 * i + 1], m * g, 1e-12);
            ENSURE_SMALL(r.tr.wrench[3 * i + 2], 1e-12);
            if (i > 0) ENSURE(r.tr.stick[i] == 1);
        }
    }
    ENSURE(r.st.steps == 4);
    ENSURE(r.st.stick_steps == 4);
    ENSURE(r.st.impacts == 0 && r.st.warnings == 0);
    ENSURE(r.st.max_impulse == 0.0 && r.st.max_impulse_stop == -1 && isnan(r.st.max_impulse_t));
    ENSURE(r.st.fail_cause == EXDEX_FAIL_NONE && isnan(r.st.fail_time));
    ENSURE(isnan(r.st.lost_t) && r.st.lost_sample == 0);
    ENSURE(isnan(r.st.first_warning_t));
    sim_run_free(&r);
}

/* Bad arguments are EXDEX_EINVAL: no model, a grid exdex_n_samples rejects,
 * arrays shorter than the grid or missing. */
EXDEX_TEST(simulate_rejects_bad_arguments)
{
    exdex_scene_def d = scene_vertical(0.2, 2.0);
    int status;
    exdex_model *mdl = exdex_model_alloc(&d, &status, NULL);
    double t[5], q[5], v[5], w[15];
    unsigned char stick[5];
    exdex_trajectory tr = {5, t, q, v, w, stick, NULL};
    exdex_stats st;
    ENSURE(mdl != NULL);
    ENSURE(exdex_simulate(NULL, 1.0, 0.25, &tr, &st) == EXDEX_EINVAL);
    ENSURE(exdex_simulate(mdl, 1.0, 0.0, &tr, &st) == EXDEX_EINVAL);
    ENSURE(exdex_simulate(mdl, 1.0, 2.0, &tr, &st) == EXDEX_EINVAL);
    ENSURE(exdex_simulate(mdl, NAN, 0.25, &tr, &st) == EXDEX_EINVAL);
    tr.n = 4;   /* the grid has 5 samples */
    ENSURE(exdex_simulate(mdl, 1.0, 0.25, &tr, &st) == EXDEX_EINVAL);
    tr.n = 5;
    tr.q = NULL;
    ENSURE(exdex_simulate(mdl, 1.0, 0.25, &tr, &st) == EXDEX_EINVAL);
    tr.q = q;
    ENSURE(exdex_simulate(mdl, 1.0, 0.25, &tr, &st) == EXDEX_OK);
    exdex_model_free(mdl);
}
