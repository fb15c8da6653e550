/* simulate.c -- exdex_simulate: checks the call, records the initial
 * sample, runs the scene's method through the method table (method.h) with
 * a workspace of its own, and checks and returns what it recorded. */
#include "exdex.h"
#include "method.h"
#include "model.h"

#include <math.h>
#include <string.h>

size_t exdex_n_samples(double t_end, double dt)
{
    double r;
    double steps;
    if (!(isfinite(t_end) && isfinite(dt) && dt > 0 && t_end > 0 && dt <= t_end)) return 0;
    r = t_end / dt;
    steps = floor(r + 0.5);
    if (fabs(r - steps) > 1e-9 * r) steps = ceil(r);
    if (steps < 1) steps = 1;
    if (steps > EXDEX_MAX_STEPS) return 0;
    return (size_t)steps + 1;
}

static const method_impl *const methods[] = {
    [EXDEX_METHOD_IMPLICIT] = &method_implicit,
    [EXDEX_METHOD_EVENT] = &method_event,
    [EXDEX_METHOD_REGULARISED] = &method_regularised,
    [EXDEX_METHOD_EXPLICIT] = &method_explicit,
    [EXDEX_METHOD_ANALYTIC] = &method_analytic,
};

const method_impl *method_get(int method)
{
    if (method < EXDEX_METHOD_IMPLICIT || method > EXDEX_METHOD_ANALYTIC) return NULL;
    return methods[method];
}

/* A run that returned OK must not have recorded a non-finite number (e.g. a
 * capacity mu N that overflows makes the explicit friction infinite). */
static int output_finite(const exdex_model *m, const exdex_trajectory *out)
{
    size_t n = out->n, nq = n * (size_t)m->ndof, ns = n * (size_t)m->n_src;
    for (size_t i = 0; i < nq; i++)
        if (!isfinite(out->q[i]) || !isfinite(out->v[i])) return 0;
    for (size_t i = 0; i < 3 * n; i++)
        if (!isfinite(out->wrench[i])) return 0;
    for (size_t i = 0; i < ns; i++)
        if (!isfinite(out->stop_force[i])) return 0;
    return 1;
}

/* Impacts of a time-stepping run: impact_scan over the recorded
 * per-step stop impulses P_i = stop_force_i (t_i - t_{i-1}). */
typedef struct out_steps {
    const exdex_trajectory *out;
    size_t ns;
} out_steps;

static double out_impulse(const void *ctx, int k, size_t i)
{
    const out_steps *o = ctx;
    return i == 0 ? 0.0 : o->out->stop_force[i * o->ns + (size_t)k] * (o->out->t[i] - o->out->t[i - 1]);
}

static double out_time(const void *ctx, size_t i)
{
    return ((const out_steps *)ctx)->out->t[i];
}

static void impacts_from_steps(const exdex_model *m, const exdex_trajectory *out, exdex_stats *st)
{
    out_steps o = {out, (size_t)m->n_src};
    impact_steps s = {out_impulse, out_time, &o, out->n};
    for (int k = 0; k < m->n_src; k++) impact_scan(&s, k, 1, 0, st);
}

int exdex_simulate(const exdex_model *m, double t_end, double dt, exdex_trajectory *out,
                   exdex_stats *stats)
{
    size_t n = exdex_n_samples(t_end, dt);
    int nd, status = EXDEX_OK;
    double q[3], v[3];
    const method_impl *impl;
    void *ws;
    exdex_stats st;
    exdex_trajectory lost;
    if (!m || !out || n == 0 || out->n != n || !out->t || !out->q || !out->v || !out->wrench ||
        !out->stick || (m->n_src && !out->stop_force))
        return EXDEX_EINVAL;
    if (m->def.method < EXDEX_METHOD_IMPLICIT || m->def.method > EXDEX_METHOD_ANALYTIC) return EXDEX_EINVAL;
    impl = methods[m->def.method];
    memset(&st, 0, sizeof st);
    st.min_gap = INFINITY;
    st.first_warning_t = NAN;
    st.max_impulse_t = NAN;
    st.max_impulse_stop = -1;
    st.fail_time = NAN;
    st.lost_t = NAN;
    nd = m->ndof;
    model_initial_state(m, q, v);
    out->t[0] = 0.0;
    for (int i = 0; i < nd; i++) {
        out->q[i] = q[i];
        out->v[i] = v[i];
    }
    out->stick[0] = (v[0] == 0.0 && (nd == 1 || (v[1] == 0.0 && v[2] == 0.0)));
    /* row 0's wrench: the one holding the object where it starts held, else 0 */
    if (!(out->stick[0] && model_holding_wrench(m, 0.0, q, out->wrench)))
        out->wrench[0] = out->wrench[1] = out->wrench[2] = 0.0;
    for (int k = 0; k < m->n_src; k++) out->stop_force[k] = 0.0;
    ws = impl->alloc(m, &status);
    if (!ws) return status ? status : EXDEX_ENOMEM;
    if (impl->run) {
        status = impl->run(m, ws, t_end, dt, out, &st);
    } else {
        size_t n = out->n;
        status = impl->begin(m, ws, t_end, dt, &st);
        for (size_t i = 1; i < n && status == EXDEX_OK; i++) {
            status = impl->advance(m, ws, i == n - 1 ? t_end : (double)i * dt, 0, out, i, &st);
            if (status == EXDEX_OK && m->pads && model_pads_lost(m, out->q + i * (size_t)nd)) {
                /* the grasp is lost: the run stops at this sample */
                st.lost_t = out->t[i];
                st.lost_sample = i;
                break;
            }
        }
    }
    impl->free(ws);
    if (st.lost_sample) {
        /* only the samples written are checked and scanned */
        lost = *out;
        lost.n = st.lost_sample + 1;
        out = &lost;
    }
    if (status == EXDEX_OK && !impl->checks_finite && !output_finite(m, out)) status = EXDEX_ENONFINITE;
    if (status == EXDEX_OK && impl->impacts_from_steps && m->n_src) impacts_from_steps(m, out, &st);
    if (status != EXDEX_OK && st.fail_cause == EXDEX_FAIL_NONE)
        st.fail_cause = status == EXDEX_ENOCONV ? EXDEX_FAIL_SOLVER : EXDEX_FAIL_NONFINITE;
    if (stats) *stats = st;
    /* the model and arguments were valid: an "invalid argument" from the
     * motion or a solver inside the run means the state left the finite
     * range */
    return status == EXDEX_EINVAL ? EXDEX_ENONFINITE : status;
}
