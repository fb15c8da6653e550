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

/* Impacts of a time-stepping run, read from its per-step stop impulses
 * P_i = stop_force_i h_i. A stop force bounded by the loads gives impulses of
 * order h that change little from step to step; an impact (a velocity jump)
 * gives impulses of order M v, independent of h, in one step or spread over
 * a few (the velocity-level rows of the explicit method let the object cover
 * the last gap in the first of them). With base_j = min(P_j .. P_j+W), the
 * load level just after step j (W = IMPACT_STEPS), an impact of stop k is a
 * burst: steps i .. j-1 (at most W of them) where P_i > IMPACT_RATIO P_{i-1}
 * (P_0 = 0) and every P_l > IMPACT_RATIO base_l, whose largest impulse
 * exceeds IMPACT_RATIO base_j. Its impulse is the burst's sum, its time the
 * end of its largest step. This resolves approach speeds above about
 * IMPACT_RATIO h times the loading acceleration; slower touch-downs are not
 * distinguishable from a contact that starts to carry a load, and a burst
 * that the end of the run cuts off is not counted. */
#define IMPACT_RATIO 4.0
#define IMPACT_STEPS 4

static double step_impulse(const exdex_trajectory *out, int ns, int k, size_t i)
{
    return i == 0 ? 0.0 : out->stop_force[i * ns + k] * (out->t[i] - out->t[i - 1]);
}

static double base_after(const exdex_trajectory *out, int ns, int k, size_t j)
{
    double b = step_impulse(out, ns, k, j);
    for (size_t l = j + 1; l < out->n && l <= j + IMPACT_STEPS; l++) {
        double P = step_impulse(out, ns, k, l);
        if (P < b) b = P;
    }
    return b;
}

static void impacts_from_steps(const exdex_model *m, const exdex_trajectory *out, exdex_stats *st)
{
    size_t n = out->n;
    int ns = m->n_src;
    for (int k = 0; k < ns; k++)
        for (size_t i = 1; i < n; i++) {
            double P = step_impulse(out, ns, k, i), peak = P, sum = P;
            size_t ipk = i, j;
            if (!(P > 0.0 && P > IMPACT_RATIO * step_impulse(out, ns, k, i - 1))) continue;
            for (j = i + 1; j < n && j < i + IMPACT_STEPS; j++) {
                double Pj = step_impulse(out, ns, k, j);
                if (!(Pj > IMPACT_RATIO * base_after(out, ns, k, j))) break;   /* the burst is over */
                sum += Pj;
                if (Pj > peak) {
                    peak = Pj;
                    ipk = j;
                }
            }
            if (j < n && peak > IMPACT_RATIO * base_after(out, ns, k, j)) {
                method_note_impact(st, out->t[ipk], k, sum);
                i = j - 1;   /* continue after the burst */
            }
        }
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
    nd = m->ndof;
    model_initial_state(m, q, v);
    out->t[0] = 0.0;
    for (int i = 0; i < nd; i++) {
        out->q[i] = q[i];
        out->v[i] = v[i];
    }
    out->wrench[0] = out->wrench[1] = out->wrench[2] = 0.0;
    out->stick[0] = (v[0] == 0.0 && (nd == 1 || (v[1] == 0.0 && v[2] == 0.0)));
    for (int k = 0; k < m->n_src; k++) out->stop_force[k] = 0.0;
    ws = impl->alloc(m, &status);
    if (!ws) return status ? status : EXDEX_ENOMEM;
    status = impl->run(m, ws, t_end, dt, out, &st);
    impl->free(ws);
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
