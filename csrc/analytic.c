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
 *   no stops; a constant grip force or a piecewise-linear or step grip
 *   schedule (not the cubic one).
 * With the drive d(t) = Q / M constant on each phase, the kinetic friction
 * capacity c = C / M (C = mu N, or mu N e_r for the torque) and the static
 * one c_s = C_s / M (mu_static in place of mu, c_s >= c) the Coulomb
 * problem  qdd = d + f / M,  |f| <= C_s at rest, f = -C sign(qd) sliding,
 * exact stick  has the solution:
 *   at rest (qd = 0): it stays at rest while |d| <= c_s (1 + FRICTION_BAND) (the band
 *     that the event method uses), else it slips in the direction of d with
 *     qdd = d - c sign(d) (c_s >= c: it accelerates away from rest);
 *   sliding (qd != 0): qdd = d - c sign(qd), a quadratic in time; if it
 *     decelerates the slip stops at tau = -qd / qdd (a root of a linear
 *     equation) and the rest test applies again.
 * A grip schedule makes the capacities linear in time within each phase
 * (the phases also start at the schedule's times): c(t) = c0 + c1 (t - t0),
 * c_s likewise, which raises each polynomial's degree by one:
 *   at rest: it stays while |d| <= c_s(t) (1 + FRICTION_BAND); a falling c_s ends
 *     the rest at the root of the linear equation c_s(t) (1 + FRICTION_BAND) = |d|,
 *     where it slips in the direction of d;
 *   sliding: qdd = alpha + beta (t - ts), alpha = d - s c(ts), beta =
 *     -s c1 (s the slip direction), so qd is a quadratic and q a cubic in
 *     time; the slip stops at the first positive root of qd (a quadratic,
 *     solved in the cancellation-free form).
 * Events are the phase switches (the profile's own times, the schedule's
 * times), the slip stops and the ends of rest; nothing is integrated, and
 * each sample is evaluated from the start of its segment, so the output
 * grid does not change the answer. The recorded friction is the mean over each
 * output interval, M ((qd_i - qd_{i-1}) - integral of d) / h, accumulated
 * segment by segment as M times the integral of (qdd - d) over the segment. */
#include "exdex.h"
#include "method.h"
#include "model.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define MOTION_PHASES 5

typedef struct phase {
    double t0;   /* start [s]; the phase lasts until the next one's start */
    double d;    /* drive Q / M, constant in the phase [m/s^2 or rad/s^2] */
    double c0, c1;    /* grip schedule: kinetic capacity per unit M at t0 and its rate */
    double cs0, cs1;  /* grip schedule: static capacity per unit M at t0 and its rate */
} phase;

/* The run's state between output intervals: the current segment starts at
 * ts in state (xs, vs) with acceleration a and its rate b (a grip
 * schedule), in phase k; t_rec is the last recorded time; c, cs the
 * kinetic and static capacities per unit M it runs with (constant grip). */
typedef struct analytic_state {
    double ts, xs, vs, a, t_rec, c, cs, b;
    int k;
} analytic_state;

typedef struct analytic_ws {
    int np;
    phase *ph;     /* np phases (motion phases split at the grip schedule's times) */
    int sched;     /* 1: the capacities are the phases' (a grip schedule), 0: c, cs */
    double M, c;   /* generalised mass; kinetic capacity per unit M */
    double cs;     /* static capacity per unit M */
    analytic_state S;
} analytic_ws;

/* The profile's phase starts (as motion.c switches them: t >= switch belongs
 * to the next phase) merged with the grip schedule's times, the drive of
 * each evaluated inside it and the capacities at its start with their
 * rates (right derivatives: linear up to the next start). ts: scratch for
 * 2 (MOTION_PHASES + 1 + grip_n) times. */
static int build_phases(const exdex_model *m, analytic_ws *w, double *ts)
{
    const exdex_motion_def *mo = &m->def.motion;
    double tm[MOTION_PHASES], q[3], v[3], ke = m->def.dof == EXDEX_DOF_TRANSLATION ? 1.0 : m->e[2];
    double *gb = ts + MOTION_PHASES + 1 + m->grip_n;  /* the schedule's times in (0, inf), after the merged list */
    int n = 0, nm = 0;
    size_t ng = m->grip_n ? model_grip_breaks(m, INFINITY, gb) : 0, jg = 0;
    tm[nm++] = 0.0;
    if (mo->kind == EXDEX_MOTION_ASYMMETRIC) {
        tm[nm++] = mo->beta * mo->duration;
        tm[nm++] = (2.0 - mo->beta) * mo->duration;
        tm[nm++] = 2.0 * mo->duration;
    } else if (mo->kind == EXDEX_MOTION_TRAPEZOID && mo->amplitude != 0.0) {
        double T = mo->duration, t_a = T - fabs(mo->amplitude) / mo->v_max;
        if (t_a > 0.5 * T) t_a = 0.5 * T;
        tm[nm++] = t_a;
        tm[nm++] = T - t_a;
        tm[nm++] = T;
    }
    /* merge (a motion phase that is empty stays a repeated time, skipped below) */
    for (int i = 0; i < nm || jg < ng;) {
        if (jg >= ng || (i < nm && tm[i] <= gb[jg])) {
            ts[n++] = tm[i++];
        } else {
            if (gb[jg] > ts[n - 1]) ts[n++] = gb[jg];
            jg++;
        }
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
        if (m->grip_n) {
            double r = model_grip_sched_rate(m, ts[i]);
            w->ph[w->np].c0 = model_capacity(m, ts[i]) * ke / w->M;
            w->ph[w->np].c1 = m->capk * r * ke / w->M;
            w->ph[w->np].cs0 = model_capacity_static(m, ts[i]) * ke / w->M;
            w->ph[w->np].cs1 = m->capks * r * ke / w->M;
        } else {
            w->ph[w->np].c0 = w->c;
            w->ph[w->np].cs0 = w->cs;
            w->ph[w->np].c1 = w->ph[w->np].cs1 = 0.0;
        }
        if (!isfinite(w->ph[w->np].d) || !isfinite(w->ph[w->np].c0) || !isfinite(w->ph[w->np].c1) ||
            !isfinite(w->ph[w->np].cs0) || !isfinite(w->ph[w->np].cs1))
            return EXDEX_ENONFINITE;
        w->np++;
    }
    return EXDEX_OK;
}

static void analytic_free(void *ws)
{
    analytic_ws *w = ws;
    if (w) free(w->ph);
    free(w);
}

static void *analytic_alloc(const exdex_model *m, int *status)
{
    analytic_ws *w = malloc(sizeof *w);
    double *ts;
    size_t cap = MOTION_PHASES + 1 + m->grip_n;
    if (!w) {
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    w->ph = malloc(cap * sizeof *w->ph);
    ts = malloc(2 * cap * sizeof *ts);
    if (!w->ph || !ts) {
        free(ts);
        analytic_free(w);
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
    w->sched = m->grip_n != 0;
    *status = build_phases(m, w, ts);
    free(ts);
    if (*status) {
        analytic_free(w);
        return NULL;
    }
    return w;
}

/* Capacities per unit M at t in phase p: the phase's linear ones with a
 * grip schedule, else the constant c, c_s. */
static double cap_kin(const analytic_ws *w, const phase *p, double t)
{
    return !w->sched ? w->c : p->c1 == 0.0 ? p->c0 : p->c0 + p->c1 * (t - p->t0);
}
static double cap_static(const analytic_ws *w, const phase *p, double t)
{
    return !w->sched ? w->cs : p->cs1 == 0.0 ? p->cs0 : p->cs0 + p->cs1 * (t - p->t0);
}

/* The segment that starts at t with velocity v in phase k: its acceleration
 * *a at t and the acceleration's rate *b (0 for a constant grip). At rest
 * it stays while the plates hold (|d| <= c_s (1 + FRICTION_BAND)), else it slips in
 * the direction of d; leave_rest: a rest ended here (the static capacity
 * fell to the load), so it slips without the test, accelerating away from
 * rest (s a >= 0: rounding at the limit removed). */
static void segment_accel(const analytic_ws *w, int k, double t, double v, int leave_rest, double *a, double *b)
{
    const phase *p = &w->ph[k];
    double d = p->d, s;
    if (v == 0.0) {
        if (!leave_rest && fabs(d) <= cap_static(w, p, t) * (1.0 + FRICTION_BAND)) {
            *a = *b = 0.0;
            return;
        }
        s = d > 0.0 ? 1.0 : -1.0;
        *a = d - copysign(cap_kin(w, p, t), d);
        if (leave_rest && s * *a < 0.0) *a = 0.0;
    } else {
        s = v > 0.0 ? 1.0 : -1.0;
        *a = d - copysign(cap_kin(w, p, t), v);
    }
    *b = !w->sched || p->c1 == 0.0 ? 0.0 : -s * p->c1;
}

/* First tau > 0 with v + a tau + b tau^2 / 2 = 0 (a slip stops; b != 0),
 * INFINITY if none: the quadratic's roots in the cancellation-free form. */
static double slip_stop(double v, double a, double b)
{
    double disc, q, r1, r2, r = INFINITY;
    if (v == 0.0) {
        r1 = -2.0 * a / b;
        return r1 > 0.0 ? r1 : INFINITY;
    }
    disc = a * a - 2.0 * b * v;
    if (!(disc >= 0.0)) return INFINITY;
    q = -(a + copysign(sqrt(disc), a));
    if (q == 0.0) return INFINITY;
    r1 = q / b;
    r2 = 2.0 * v / q;
    if (r1 > 0.0) r = r1;
    if (r2 > 0.0 && r2 < r) r = r2;
    return r;
}

static int analytic_begin(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st)
{
    analytic_ws *w = ws;
    double q[3], v[3];
    (void)t_end;
    (void)dt;
    (void)st;
    model_initial_state(m, q, v);
    memset(&w->S, 0, sizeof w->S);   /* padding too: a snapshot's checksum reads every byte */
    /* the capacities of the model (a stepper's earlier run may have changed
     * them), computed as analytic_alloc does */
    if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        w->c = m->capF / m->m;
        w->cs = m->capS / m->m;
    } else {
        w->c = m->capF * m->e[2] / m->mrot;
        w->cs = m->capS * m->e[2] / m->mrot;
    }
    w->S.ts = w->S.t_rec = 0.0;
    w->S.xs = q[0];
    w->S.vs = v[0];
    w->S.k = 0;
    w->S.c = w->c;
    w->S.cs = w->cs;
    segment_accel(w, 0, 0.0, v[0], 0, &w->S.a, &w->S.b);
    return EXDEX_OK;
}

/* The interval from the last recorded time to ti, recorded as sample i.
 * A new capacity (regrip: the model's constant capacity changed) starts a
 * new segment at the interval's start. */
static int analytic_advance(const exdex_model *m, void *ws, double ti, int regrip, exdex_trajectory *out,
                            size_t i, exdex_stats *st)
{
    analytic_ws *w = ws;
    /* the current segment: starts at ts in state (xs, vs), acceleration a
     * (rate b) in phase k; samples are evaluated from its start, so the
     * output grid never changes the segments (the final state is the same
     * for any dt) */
    double ts = w->S.ts, xs = w->S.xs, vs = w->S.vs, a = w->S.a, b = w->S.b;
    int k = w->S.k;
    if (regrip) {
        double tau = w->S.t_rec - ts;
        w->c = m->def.dof == EXDEX_DOF_TRANSLATION ? m->capF / m->m : m->capF * m->e[2] / m->mrot;
        w->cs = m->def.dof == EXDEX_DOF_TRANSLATION ? m->capS / m->m : m->capS * m->e[2] / m->mrot;
        w->sched = m->grip_n != 0;
        if (b == 0.0) {
            xs += vs * tau + 0.5 * a * tau * tau;
            vs += a * tau;
        } else {
            xs += vs * tau + 0.5 * a * tau * tau + b * tau * tau * tau / 6.0;
            vs += a * tau + 0.5 * b * tau * tau;
        }
        ts = w->S.t_rec;
        segment_accel(w, k, ts, vs, 0, &a, &b);
    }
    do {
        double h = ti - w->S.t_rec, tc = w->S.t_rec;
        double fint = 0.0, tau;
        for (;;) {
            const phase *p = &w->ph[k];
            double te = k + 1 < w->np ? w->ph[k + 1].t0 : INFINITY, d = p->d, tstop, trest = INFINITY, tev;
            if (b == 0.0) {
                tstop = vs != 0.0 && a * vs < 0.0 ? ts + (-vs / a) : INFINITY;
            } else {
                tstop = ts + slip_stop(vs, a, b);
            }
            if (w->sched && vs == 0.0 && a == 0.0 && b == 0.0 && p->cs1 < 0.0) {
                /* at rest under a falling static capacity: it ends where
                 * c_s(t) (1 + FRICTION_BAND) = |d| */
                double tr = p->t0 + (fabs(d) / (1.0 + FRICTION_BAND) - p->cs0) / p->cs1;
                trest = tr > ts ? tr : ts;
            }
            tev = te < tstop ? te : tstop;
            if (trest < tev) tev = trest;
            if (tev > ti) {
                if (b == 0.0)
                    fint += w->M * (a - d) * (ti - tc);
                else
                    fint += w->M * ((a - d) * (ti - tc) + 0.5 * b * ((ti - ts) * (ti - ts) - (tc - ts) * (tc - ts)));
                break;
            }
            /* an event inside the interval: the phase switches, the slip stops or the rest ends */
            if (b == 0.0)
                fint += w->M * (a - d) * (tev - tc);
            else
                fint += w->M * ((a - d) * (tev - tc) + 0.5 * b * ((tev - ts) * (tev - ts) - (tc - ts) * (tc - ts)));
            tau = tev - ts;
            if (b == 0.0) {
                xs += vs * tau + 0.5 * a * tau * tau;
                vs = tev == tstop ? 0.0 : vs + a * tau;
            } else {
                xs += vs * tau + 0.5 * a * tau * tau + b * tau * tau * tau / 6.0;
                vs = tev == tstop ? 0.0 : vs + a * tau + 0.5 * b * tau * tau;
            }
            ts = tc = tev;
            if (tev == te) k++;
            if (tev == tstop) st->solver_iterations++;
            segment_accel(w, k, ts, vs, tev == trest && tev != te, &a, &b);
        }
        tau = ti - ts;
        out->t[i] = ti;
        if (b == 0.0) {
            out->q[i] = xs + vs * tau + 0.5 * a * tau * tau;
            out->v[i] = vs + a * tau;
        } else {
            out->q[i] = xs + vs * tau + 0.5 * a * tau * tau + b * tau * tau * tau / 6.0;
            out->v[i] = vs + a * tau + 0.5 * b * tau * tau;
        }
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
    w->S.b = b;
    w->S.k = k;
    w->S.t_rec = ti;
    w->S.c = w->c;
    w->S.cs = w->cs;
    return EXDEX_OK;
}

static int analytic_advance_samples(const exdex_model *m, void *ws, double t_end, double dt, exdex_trajectory *out,
                                    size_t i0, size_t i1, exdex_stats *st)
{
    size_t n = out->n;
    for (size_t i = i0; i <= i1; i++) analytic_advance(m, ws, i == n - 1 ? t_end : (double)i * dt, 0, out, i, st);
    return EXDEX_OK;
}

static int analytic_run(const exdex_model *m, void *ws, double t_end, double dt, exdex_trajectory *out,
                        exdex_stats *st)
{
    analytic_begin(m, ws, t_end, dt, st);
    return out->n > 1 ? analytic_advance_samples(m, ws, t_end, dt, out, 1, out->n - 1, st) : EXDEX_OK;
}

static void analytic_save(const void *ws, void *buf)
{
    memcpy(buf, &((const analytic_ws *)ws)->S, sizeof(analytic_state));
}

static int analytic_restore(void *ws, const void *buf)
{
    analytic_ws *w = ws;
    analytic_state S;
    memcpy(&S, buf, sizeof S);
    if (S.k < 0 || S.k >= w->np) return EXDEX_EINVAL;
    w->S = S;
    w->c = S.c;
    w->cs = S.cs;
    return EXDEX_OK;
}

const method_impl method_analytic = {"analytic", analytic_alloc, analytic_run, analytic_free, 0, 0,
                                     analytic_begin, analytic_advance, sizeof(analytic_state), analytic_save,
                                     analytic_restore, analytic_advance_samples};
