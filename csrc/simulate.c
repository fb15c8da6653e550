/* simulate.c -- exdex_simulate: checks the call, records the initial
 * sample, runs the scene's method through the method table (method.h) with
 * a workspace of its own, and checks and returns what it recorded. */
#include "exdex.h"
#include "method.h"
#include "model.h"

#include <math.h>
#include <stdlib.h>
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

/* The checks of exdex_simulate's arguments: the method's table entry, or
 * NULL for bad ones. */
static const method_impl *run_checks(const exdex_model *m, double t_end, double dt, const exdex_trajectory *out)
{
    size_t n = exdex_n_samples(t_end, dt);
    if (!m || !out || n == 0 || out->n != n || !out->t || !out->q || !out->v || !out->wrench ||
        !out->stick || (m->n_src && !out->stop_force))
        return NULL;
    if (m->def.method < EXDEX_METHOD_IMPLICIT || m->def.method > EXDEX_METHOD_ANALYTIC) return NULL;
    return methods[m->def.method];
}

/* The stats a run starts from and its sample 0: the initial state, the
 * wrench holding the object where it starts held (else 0), no stop force. */
static void run_start(const exdex_model *m, exdex_trajectory *out, exdex_stats *st)
{
    int nd = m->ndof;
    double q[3], v[3];
    memset(st, 0, sizeof *st);
    st->min_gap = INFINITY;
    st->first_warning_t = NAN;
    st->max_impulse_t = NAN;
    st->max_impulse_stop = -1;
    st->fail_time = NAN;
    st->lost_t = NAN;
    model_initial_state(m, q, v);
    out->t[0] = 0.0;
    for (int i = 0; i < nd; i++) {
        out->q[i] = q[i];
        out->v[i] = v[i];
    }
    out->stick[0] = (v[0] == 0.0 && (nd == 1 || (v[1] == 0.0 && v[2] == 0.0)));
    if (!(out->stick[0] && model_holding_wrench(m, 0.0, q, out->wrench)))
        out->wrench[0] = out->wrench[1] = out->wrench[2] = 0.0;
    for (int k = 0; k < m->n_src; k++) out->stop_force[k] = 0.0;
}

/* The end of a run whose samples 0 .. n_out-1 were written: their checks
 * and impact scan, the failure cause, the stats; the status returned. */
static int run_finish(const exdex_model *m, const method_impl *impl, int status, exdex_trajectory *out,
                      size_t n_out, exdex_stats *st, exdex_stats *stats)
{
    exdex_trajectory part = *out;
    part.n = n_out;
    if (status == EXDEX_OK && !impl->checks_finite && !output_finite(m, &part)) status = EXDEX_ENONFINITE;
    if (status == EXDEX_OK && impl->impacts_from_steps && m->n_src) impacts_from_steps(m, &part, st);
    if (status != EXDEX_OK && st->fail_cause == EXDEX_FAIL_NONE)
        st->fail_cause = status == EXDEX_ENOCONV ? EXDEX_FAIL_SOLVER : EXDEX_FAIL_NONFINITE;
    if (stats) *stats = *st;
    /* the model and arguments were valid: an "invalid argument" from the
     * motion or a solver inside the run means the state left the finite
     * range */
    return status == EXDEX_EINVAL ? EXDEX_ENONFINITE : status;
}

/* Advance sample i (t_i = i dt, the last one t_end); *lost = 1 where the
 * pads' region vanished there (the grasp is lost: the run stops). */
static int run_sample(const exdex_model *m, const method_impl *impl, void *ws, double t_end, double dt,
                      exdex_trajectory *out, size_t i, exdex_stats *st, int *lost)
{
    int status = impl->advance(m, ws, i == out->n - 1 ? t_end : (double)i * dt, 0, out, i, st);
    *lost = 0;
    if (status == EXDEX_OK && m->pads && model_pads_lost(m, out->q + i * (size_t)m->ndof)) {
        st->lost_t = out->t[i];
        st->lost_sample = i;
        *lost = 1;
    }
    return status;
}

int exdex_simulate(const exdex_model *m, double t_end, double dt, exdex_trajectory *out,
                   exdex_stats *stats)
{
    int status = EXDEX_OK;
    const method_impl *impl = run_checks(m, t_end, dt, out);
    void *ws;
    exdex_stats st;
    if (!impl) return EXDEX_EINVAL;
    run_start(m, out, &st);
    ws = impl->alloc(m, &status);
    if (!ws) return status ? status : EXDEX_ENOMEM;
    if (impl->run) {
        status = impl->run(m, ws, t_end, dt, out, &st);
    } else {
        int lost = 0;
        status = impl->begin(m, ws, t_end, dt, &st);
        for (size_t i = 1; i < out->n && status == EXDEX_OK && !lost; i++)
            status = run_sample(m, impl, ws, t_end, dt, out, i, &st, &lost);
    }
    impl->free(ws);
    /* only the samples written are checked and scanned */
    return run_finish(m, impl, status, out, st.lost_sample ? st.lost_sample + 1 : out->n, &st, stats);
}

/* ------------------------------------------- a run certified as it goes
 * A 1-DoF run is advanced a window of samples at a time and each window
 * certified (certify_window) before the next: the first window
 * RUN_WINDOW_MIN samples, each later one half the samples so far (a
 * failure costs at most half the run up to it again, the windows' count
 * grows with the log of its length). The state after each certified window is saved:
 * a failure in the next one restores it, advances again (bit for bit) to
 * the sample before the failure and from there to the failure's time. */
#define RUN_WINDOW_MIN 32

int exdex_simulate_certified(const exdex_model *m, double t_end, double dt, exdex_trajectory *out,
                             exdex_stats *stats, exdex_certificate *c, size_t *n_out)
{
    int status = EXDEX_OK, lost = 0, failed = 0;
    const method_impl *impl = run_checks(m, t_end, dt, out);
    size_t n, s = 0, i = 1, last, nw;
    void *ws, *buf;
    exdex_stats st, st_s;
    certify_run *cr;
    if (!impl || !c || !n_out) return EXDEX_EINVAL;
    memset(c, 0, sizeof *c);
    if (m->ndof != 1) {
        /* planar: nothing is neglected */
        exdex_trajectory part = *out;
        status = exdex_simulate(m, t_end, dt, out, &st);
        if (stats) *stats = st;
        *n_out = part.n = st.lost_sample ? st.lost_sample + 1 : out->n;
        return status ? status : exdex_certify(m, &part, c);
    }
    n = out->n;
    run_start(m, out, &st);
    ws = impl->alloc(m, &status);
    if (!ws) return status ? status : EXDEX_ENOMEM;
    buf = malloc(impl->state_size ? impl->state_size : 1);
    cr = certify_run_new(m, t_end);
    if (!buf || !cr) {
        impl->free(ws);
        free(buf);
        certify_run_free(cr);
        return EXDEX_ENOMEM;
    }
    status = impl->begin(m, ws, t_end, dt, &st);
    if (status == EXDEX_OK) impl->save(ws, buf);
    st_s = st;
    while (status == EXDEX_OK) {
        size_t w = s / 2 > RUN_WINDOW_MIN ? s / 2 : RUN_WINDOW_MIN, e = s + w < n - 1 ? s + w : n - 1;
        if (impl->advance_samples && !m->pads) {
            /* the window in one call; a failure: where is not known, the whole window is not used */
            status = impl->advance_samples(m, ws, t_end, dt, out, s + 1, e, &st);
            i = status == EXDEX_OK ? e + 1 : s + 2;
        } else {
            for (i = s + 1; i <= e && status == EXDEX_OK && !lost; i++)
                status = run_sample(m, impl, ws, t_end, dt, out, i, &st, &lost);
        }
        last = i - 1 - (status != EXDEX_OK);   /* the last sample written */
        if (last > s) {
            /* its samples s+1 .. last, with the two before them (s = 0: the run so far) */
            size_t v0 = s ? s - 1 : 0;
            exdex_trajectory view = *out;
            int cs;
            view.t += v0;
            view.q += v0;
            view.v += v0;
            view.wrench += 3 * v0;
            view.stick += v0;
            if (view.stop_force) view.stop_force += v0 * (size_t)m->n_src;
            view.n = last + 1 - v0;
            cs = certify_window(m, &view, s ? 2 : 0, cr, c);
            if (cs) {
                status = cs;
                break;
            }
            c->first_bad += v0;
            if (!c->holds) {
                failed = 1;
                status = EXDEX_OK;   /* a solver failure after it does not count */
                break;
            }
        }
        if (status != EXDEX_OK || lost || last == n - 1) break;
        s = last;
        impl->save(ws, buf);
        st_s = st;
    }
    nw = status != EXDEX_OK ? i - 1 : st.lost_sample ? st.lost_sample + 1 : n;
    if (failed) {
        /* back to sample s, on to the sample before the failure (f) and to its time */
        double ta = c->valid_until;
        size_t f = c->first_bad;
        st = st_s;
        nw = f ? f : 1;
        if (f > s + 1 || (f > 0 && ta > out->t[f - 1])) {
            status = impl->restore(ws, buf);
            for (i = s + 1; i < f && status == EXDEX_OK; i++)
                status = run_sample(m, impl, ws, t_end, dt, out, i, &st, &lost);
            if (status == EXDEX_OK && ta > out->t[f - 1]) {
                exdex_stats st_f = st;
                if (impl->advance(m, ws, ta, 0, out, f, &st) == EXDEX_OK) {
                    nw = f + 1;
                } else {
                    /* no step to the failure's time: the run ends at the sample before it */
                    st = st_f;
                    c->valid_until = out->t[f - 1];
                }
            }
        }
    }
    impl->free(ws);
    free(buf);
    certify_run_free(cr);
    *n_out = nw;
    status = run_finish(m, impl, status, out, nw, &st, stats);
    if (status == EXDEX_OK && !failed) {
        /* held to the last sample written */
        c->valid_until = out->t[nw - 1];
        c->first_bad = nw;
    }
    return status;
}
