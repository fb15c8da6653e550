/* sim_run.c -- see sim_run.h. */
#include "sim_run.h"

#include <stdlib.h>
#include <string.h>

void sim_run_free(sim_run *r)
{
    free(r->tr.t);
    free(r->tr.q);
    free(r->tr.v);
    free(r->tr.wrench);
    free(r->tr.stick);
    free(r->tr.stop_force);
    memset(r, 0, sizeof *r);
}

int sim_run_def(const exdex_scene_def *def, double t_end, double dt, sim_run *r)
{
    const char *bad = NULL;
    int status;
    exdex_model *m = exdex_model_alloc(def, &status, &bad);
    size_t n = exdex_n_samples(t_end, dt);
    memset(r, 0, sizeof *r);
    if (!m) return r->status = status;
    r->ndof = exdex_model_ndof(m);
    r->nstops = exdex_model_nstops(m);
    r->tr.n = n;
    r->tr.t = calloc(n, sizeof(double));
    r->tr.q = calloc(n * 3, sizeof(double));
    r->tr.v = calloc(n * 3, sizeof(double));
    r->tr.wrench = calloc(n * 3, sizeof(double));
    r->tr.stick = calloc(n, 1);
    r->tr.stop_force = calloc(n * (r->nstops + 1), sizeof(double));
    r->status = exdex_simulate(m, t_end, dt, &r->tr, &r->st);
    exdex_model_free(m);
    return r->status;
}
