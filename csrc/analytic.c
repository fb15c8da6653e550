/* analytic.c -- EXDEX_METHOD_ANALYTIC: the exact solution, phase by phase,
 * of 1-DoF scenes whose drive is piecewise constant.
 *
 * Scenes (exdex_analytic_unsupported says which, and why not):
 *   translation: the gripper translates (Eq. 7, trapezoid with ramps, or
 *     rest), so w = dw = 0 and Eq. 5 on the slide axis d is
 *         m sdd = m (g_B - a0(t)) . d + f,
 *     with a0 constant in each phase of the profile;
 *   rotation about the centre of mass (patch centre 0): the gripper turns
 *     about the plate normal (or rests), so w and dw are along z, the
 *     gyroscopic terms of Euler's equation have no z-component, gravity has
 *     no moment about the pivot, and
 *         I_zz thdd = -I_zz dw_z(t) + tau_f;
 *   no stops; constant grip force.
 * With the drive d(t) = Q / M constant on each phase, the kinetic friction
 * capacity c = C / M (C = mu N, or mu N e_r for the torque) and the static
 * one c_s = C_s / M (mu_static in place of mu, c_s >= c) the Coulomb
 * problem  qdd = d + f / M,  |f| <= C_s at rest, f = -C sign(qd) sliding,
 * exact stick  has the solution:
 *   at rest (qd = 0): it stays at rest while |d| <= c_s (1 + TOLF) (the band
 *     that the event method uses), else it slips in the direction of d with
 *     qdd = d - c sign(d) (c_s >= c: it accelerates away from rest);
 *   sliding (qd != 0): qdd = d - c sign(qd), a quadratic in time; if it
 *     decelerates the slip stops at tau = -qd / qdd (a root of a linear
 *     equation) and the rest test applies again.
 * Events are the phase switches (the profile's own times) and the slip
 * stops; nothing is integrated, and each sample is evaluated from the start
 * of its segment, so the output grid does not change the answer. The recorded friction is the mean over each
 * output interval, M ((qd_i - qd_{i-1}) - integral of d) / h, accumulated
 * segment by segment as M (qdd - d) times the segment's length. */
#include "exdex.h"
#include "method.h"
#include "model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define TOLF 1e-12       /* relative band at the friction limit, as the event method */
#define MAX_PHASES 5

typedef struct phase {
    double t0;   /* start [s]; the phase lasts until the next one's start */
    double d;    /* drive Q / M, constant in the phase [m/s^2 or rad/s^2] */
} phase;

/* The run's state between output intervals: the current segment starts at
 * ts in state (xs, vs) with acceleration a, in phase k; t_rec is the last
 * recorded time; c, cs the kinetic and static capacities per unit M it
 * runs with. */
typedef struct analytic_state {
    double ts, xs, vs, a, t_rec, c, cs;
    int k;
} analytic_state;

typedef struct analytic_ws {
    int np;
    phase ph[MAX_PHASES];
    double M, c;   /* generalised mass; kinetic capacity per unit M */
    double cs;     /* static capacity per unit M */
    analytic_state S;
} analytic_ws;

/* The profile's phase starts (as motion.c switches them: t >= switch belongs
 * to the next phase), the drive of each evaluated inside it. */
static int build_phases(const exdex_model *m, analytic_ws *w)
{
    const exdex_motion_def *mo = &m->def.motion;
    double ts[MAX_PHASES], q[3], v[3];
    int n = 0;
    ts[n++] = 0.0;
    if (mo->kind == EXDEX_MOTION_ASYMMETRIC) {
        ts[n++] = mo->beta * mo->duration;
        ts[n++] = (2.0 - mo->beta) * mo->duration;
        ts[n++] = 2.0 * mo->duration;
    } else if (mo->kind == EXDEX_MOTION_TRAPEZOID && mo->amplitude != 0.0) {
        double T = mo->duration, t_a = T - fabs(mo->amplitude) / mo->v_max;
        if (t_a > 0.5 * T) t_a = 0.5 * T;
        ts[n++] = t_a;
        ts[n++] = T - t_a;
        ts[n++] = T;
    }
    model_initial_state(m, q, v);
    w->np = 0;
    for (int i = 0; i < n; i++) {
        frame f;
        exdex_kinematics k;
        double t_in, Q;
        if (i + 1 < n && !(ts[i + 1] > ts[i])) continue;   /* an empty phase (triangle profile) */
        t_in = i + 1 < n ? 0.5 * (ts[i] + ts[i + 1]) : ts[i] + 1.0 + ts[i];
        if (model_frame_at(m, t_in, &f, &k)) return EXDEX_ENONFINITE;
        Q = model_force_1dof(m, &f, q[0], v[0]);
        w->ph[w->np].t0 = ts[i];
        w->ph[w->np].d = Q / w->M;
        if (!isfinite(w->ph[w->np].d)) return EXDEX_ENONFINITE;
        w->np++;
    }
    return EXDEX_OK;
}

static void *analytic_alloc(const exdex_model *m, int *status)
{
    analytic_ws *w = malloc(sizeof *w);
    if (!w) {
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        w->M = m->m;
        w->c = m->capF / m->m;
        w->cs = m->capS / m->m;
    } else {
        w->M = m->mrot;
        w->c = m->capF * m->e[2] / m->mrot;
        w->cs = m->capS * m->e[2] / m->mrot;
    }
    *status = build_phases(m, w);
    if (*status) {
        free(w);
        return NULL;
    }
    return w;
}

static void analytic_free(void *ws) { free(ws); }

/* Acceleration of the segment that starts with velocity v in a phase of
 * drive d: 0 at rest while the plates hold, else the Coulomb slip. */
static double segment_accel(const analytic_ws *w, double d, double v)
{
    if (v == 0.0) return fabs(d) <= w->cs * (1.0 + TOLF) ? 0.0 : d - copysign(w->c, d);
    return d - copysign(w->c, v);
}

static int analytic_begin(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st)
{
    analytic_ws *w = ws;
    double q[3], v[3];
    (void)t_end;
    (void)dt;
    (void)st;
    model_initial_state(m, q, v);
    w->S.ts = w->S.t_rec = 0.0;
    w->S.xs = q[0];
    w->S.vs = v[0];
    w->S.k = 0;
    w->S.c = w->c;
    w->S.cs = w->cs;
    w->S.a = segment_accel(w, w->ph[0].d, v[0]);
    return EXDEX_OK;
}

/* The interval from the last recorded time to ti, recorded as sample i.
 * A new capacity (regrip) starts a new segment at the interval's start. */
static int analytic_advance(const exdex_model *m, void *ws, double ti, int regrip, exdex_trajectory *out,
                            size_t i, exdex_stats *st)
{
    analytic_ws *w = ws;
    /* the current segment: starts at ts in state (xs, vs), acceleration a
     * in phase k; samples are evaluated from its start, so the output grid
     * never changes the segments (the final state is the same for any dt) */
    double ts = w->S.ts, xs = w->S.xs, vs = w->S.vs, a = w->S.a;
    int k = w->S.k;
    if (regrip) {
        double tau = w->S.t_rec - ts;
        w->c = m->def.dof == EXDEX_DOF_TRANSLATION ? m->capF / m->m : m->capF * m->e[2] / m->mrot;
        w->cs = m->def.dof == EXDEX_DOF_TRANSLATION ? m->capS / m->m : m->capS * m->e[2] / m->mrot;
        xs += vs * tau + 0.5 * a * tau * tau;
        vs += a * tau;
        ts = w->S.t_rec;
        a = segment_accel(w, w->ph[k].d, vs);
    }
    do {
        double h = ti - w->S.t_rec, tc = w->S.t_rec;
        double fint = 0.0, tau;
        for (;;) {
            double te = k + 1 < w->np ? w->ph[k + 1].t0 : INFINITY, d = w->ph[k].d;
            double tstop = vs != 0.0 && a * vs < 0.0 ? ts + (-vs / a) : INFINITY;
            double tev = te < tstop ? te : tstop;
            if (tev > ti) {
                fint += w->M * (a - d) * (ti - tc);
                break;
            }
            /* an event inside the interval: the phase switches or the slip stops */
            fint += w->M * (a - d) * (tev - tc);
            tau = tev - ts;
            xs += vs * tau + 0.5 * a * tau * tau;
            vs = tev == tstop ? 0.0 : vs + a * tau;
            ts = tc = tev;
            if (tev == te) k++;
            if (tev == tstop) st->solver_iterations++;
            a = segment_accel(w, w->ph[k].d, vs);
        }
        tau = ti - ts;
        out->t[i] = ti;
        out->q[i] = xs + vs * tau + 0.5 * a * tau * tau;
        out->v[i] = vs + a * tau;
        if (m->def.dof == EXDEX_DOF_TRANSLATION) {
            out->wrench[3 * i] = fint / h * m->d[0];
            out->wrench[3 * i + 1] = fint / h * m->d[1];
            out->wrench[3 * i + 2] = 0.0;
        } else {
            out->wrench[3 * i] = out->wrench[3 * i + 1] = 0.0;
            out->wrench[3 * i + 2] = fint / h;
        }
        out->stick[i] = out->v[i] == 0.0;
        st->stick_steps += out->stick[i];
        st->steps++;
    } while (0);
    w->S.ts = ts;
    w->S.xs = xs;
    w->S.vs = vs;
    w->S.a = a;
    w->S.k = k;
    w->S.t_rec = ti;
    w->S.c = w->c;
    w->S.cs = w->cs;
    return EXDEX_OK;
}

static int analytic_run(const exdex_model *m, void *ws, double t_end, double dt, exdex_trajectory *out,
                        exdex_stats *st)
{
    size_t n = out->n;
    analytic_begin(m, ws, t_end, dt, st);
    for (size_t i = 1; i < n; i++) analytic_advance(m, ws, i == n - 1 ? t_end : (double)i * dt, 0, out, i, st);
    return EXDEX_OK;
}

static void analytic_save(const void *ws, void *buf)
{
    memcpy(buf, &((const analytic_ws *)ws)->S, sizeof(analytic_state));
}

static void analytic_restore(void *ws, const void *buf)
{
    analytic_ws *w = ws;
    memcpy(&w->S, buf, sizeof w->S);
    w->c = w->S.c;
    w->cs = w->S.cs;
}

const method_impl method_analytic = {"analytic", analytic_alloc, analytic_run, analytic_free, 0, 0,
                                     analytic_begin, analytic_advance, sizeof(analytic_state), analytic_save,
                                     analytic_restore};
