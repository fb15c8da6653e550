/* stepper.c -- exdex_stepper (exdex.h): one run of the scene's method
 * advanced one output interval at a time through the method table's begin
 * and advance (method.h), each step with its own grip force.
 *
 * The grip force goes through the one capacity accessor every method reads
 * (model_capacity and friends, model.h): the stepper owns a copy of the
 * model's numbers and sets, per step, either the scene's own grip (its
 * grip_n, capF and grip_force) or a constant one (grip_n = 0, capF = capk F,
 * the product the model compiles a constant grip force to). Pointers in the
 * copy (motion, schedule) are the model's and only read.
 *
 * What exdex_simulate does after a run, the stepper does after each step:
 * the finiteness check of methods that do not check every step, and the
 * status and failure-cause mapping. The impacts of the time-stepping methods
 * (implicit, explicit) come from the stop impulses of a few steps around
 * each (impact_scan, method.h): the stepper keeps the impulses of its last
 * IMP_WIN steps, counts an impact once no later step can change its
 * decision, and scans the undecided last steps as the end of a run when
 * the stats are read, so they are exdex_simulate's over the same steps. */
#include "exdex.h"
#include "method.h"
#include "model.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#define SNAPSHOT_MAGIC 0x78656478u   /* "xdex" */
#define N_SRC (EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES)
/* samples kept for the impact scan: a final scan that stopped at step i
 * (i + 2 IMPACT_STEPS >= n samples) reads P_{i-1} on, and goes on after the
 * next step */
#define IMP_WIN (2 * IMPACT_STEPS + 2)

/* Everything of a stepper that a snapshot holds besides the method state. */
typedef struct stepper_core {
    unsigned magic;
    unsigned long long check;   /* FNV-1a of the snapshot with this field 0 */
    const exdex_model *model;   /* the model it steps (restore checks it) */
    int method, ndof, n_stops;
    int started, failed;
    double t;                   /* time reached */
    double t_base, dt, dt0;     /* grid: t_base + k dt; the first step's dt */
    double k;                   /* steps of dt since t_base */
    double grip;                /* the last step's grip force (NaN: the scene's) */
    double capF, capS, grip_force;   /* the copy's capacity fields */
    size_t grip_n;
    exdex_stepper_sample last;
    exdex_stats st;
    /* impacts of a time-stepping method: samples imp_n (steps + 1), the
     * end times and stop impulses of samples imp_n - IMP_WIN .. imp_n - 1
     * (sample i in slot i % IMP_WIN), each source's first undecided step,
     * and the final impacts (impacts, max_impulse and its time and stop) */
    size_t imp_n;
    size_t imp_next[N_SRC];
    double imp_t[IMP_WIN], imp_P[N_SRC][IMP_WIN];
    exdex_stats imp;
    /* prescribed gripper poses: posed = 1 once a step gave one (every later
     * step must), gk the gripper's pose and twist at t then */
    int posed;
    exdex_kinematics gk;
    /* the certificate of a 1-DoF run (exdex_certify_last): the last three
     * samples' t, q, v, stick (sample i in slot i % 3) and the verdict */
    double cw_t[3], cw_q[3], cw_v[3];
    unsigned char cw_stick[3];
    exdex_certificate cert;
} stepper_core;


struct exdex_stepper {
    stepper_core c;
    exdex_model mc;             /* the model's numbers with this step's grip (and motion) */
    exdex_motion *smo;          /* the motion of a step with a prescribed gripper pose */
    const method_impl *impl;
    void *ws;
    /* the one-row output of advance */
    double t1, q[3], v[3], wr[3], sf[N_SRC];
    unsigned char stick;
    exdex_trajectory out;
};

/* Set the copy's grip: F >= 0 a constant force, NaN the scene's own.
 * Returns 1 if the capacity changed. */
static int set_grip(exdex_stepper *s, double F)
{
    const exdex_model *m = s->c.model;
    double cap0 = s->mc.capF, caps0 = s->mc.capS;
    size_t n0 = s->mc.grip_n;
    if (isnan(F)) {
        s->mc.grip_n = m->grip_n;
        s->mc.capF = m->capF;
        s->mc.capS = m->capS;
        s->mc.def.grip_force = m->def.grip_force;
    } else {
        s->mc.grip_n = 0;
        s->mc.capF = m->capk * F;
        /* the static capacity as the model compiles a constant grip force:
         * the kinetic one times mu_static / mu, or mu_static fingers F when
         * mu = 0 */
        s->mc.capS = m->def.mu > 0.0 || m->def.mu_static == 0.0 || m->def.mu_static == m->def.mu
                         ? s->mc.capF * m->cap_ratio
                         : m->capks * F;
        s->mc.def.grip_force = F;
    }
    return s->mc.capF != cap0 || s->mc.capS != caps0 || s->mc.grip_n != n0;
}

/* After sample k = last.steps: the check of the newest sample, until one fails. */
static int certify_step(exdex_stepper *s)
{
    stepper_core *c = &s->c;
    size_t k = c->last.steps, n = k + 1 < 3 ? k + 1 : 3, j0 = k + 1 - n;
    double t[3], q[3], v[3];
    unsigned char st[3];
    exdex_trajectory tr;
    int status;
    c->cw_t[k % 3] = c->last.t;
    c->cw_q[k % 3] = c->last.q[0];
    c->cw_v[k % 3] = c->last.v[0];
    c->cw_stick[k % 3] = (unsigned char)c->last.stick;
    if (k > 0 && (c->ndof != 1 || !c->cert.holds)) return EXDEX_OK;
    for (size_t j = 0; j < n; j++) {
        t[j] = c->cw_t[(j0 + j) % 3];
        q[j] = c->cw_q[(j0 + j) % 3];
        v[j] = c->cw_v[(j0 + j) % 3];
        st[j] = c->cw_stick[(j0 + j) % 3];
    }
    memset(&tr, 0, sizeof tr);
    tr.n = n;
    tr.t = t;
    tr.q = q;
    tr.v = v;
    tr.stick = st;
    status = exdex_certify_last(&s->mc, &tr, j0, &c->cert);
    return status;
}

static void initial_sample(exdex_stepper *s)
{
    exdex_stepper_sample *x = &s->c.last;
    const exdex_model *m = s->c.model;
    memset(x, 0, sizeof *x);
    model_initial_state(m, x->q, x->v);
    x->stick = x->v[0] == 0.0 && (m->ndof == 1 || (x->v[1] == 0.0 && x->v[2] == 0.0));
    /* the wrench that holds it there (as exdex_simulate's row 0), else 0 */
    if (x->stick) model_holding_wrench(m, 0.0, x->q, x->wrench);
    x->grip_force = NAN;
}

exdex_stepper *exdex_stepper_alloc(const exdex_model *m, int *status)
{
    exdex_stepper *s;
    const method_impl *impl = m ? method_get(m->def.method) : NULL;
    int st = EXDEX_OK;
    if (!impl || !impl->begin) {
        if (status) *status = EXDEX_EINVAL;
        return NULL;
    }
    s = calloc(1, sizeof *s);
    if (!s) {
        if (status) *status = EXDEX_ENOMEM;
        return NULL;
    }
    s->impl = impl;
    s->mc = *m;
    s->smo = motion_step_alloc();
    s->ws = s->smo ? impl->alloc(&s->mc, &st) : NULL;
    if (!s->ws) {
        exdex_motion_free(s->smo);
        free(s);
        if (status) *status = st ? st : EXDEX_ENOMEM;
        return NULL;
    }
    s->c.magic = SNAPSHOT_MAGIC;
    s->c.model = m;
    s->c.method = m->def.method;
    s->c.ndof = m->ndof;
    s->c.n_stops = m->n_src;
    s->c.grip = NAN;
    s->c.st.min_gap = INFINITY;
    s->c.st.first_warning_t = NAN;
    s->c.st.max_impulse_t = NAN;
    s->c.st.max_impulse_stop = -1;
    s->c.st.fail_time = NAN;
    s->c.st.lost_t = NAN;
    s->c.imp.max_impulse_t = NAN;
    s->c.imp.max_impulse_stop = -1;
    s->c.imp_n = 1;   /* sample 0: t = 0, no impulse */
    for (int k = 0; k < N_SRC; k++) s->c.imp_next[k] = 1;
    initial_sample(s);
    certify_step(s);
    s->out.n = 1;
    s->out.t = &s->t1;
    s->out.q = s->q;
    s->out.v = s->v;
    s->out.wrench = s->wr;
    s->out.stick = &s->stick;
    s->out.stop_force = s->sf;
    if (status) *status = EXDEX_OK;
    return s;
}

void exdex_stepper_free(exdex_stepper *s)
{
    if (!s) return;
    s->impl->free(s->ws);
    exdex_motion_free(s->smo);
    free(s);
}

static double ring_impulse(const void *ctx, int k, size_t i)
{
    return i == 0 ? 0.0 : ((const stepper_core *)ctx)->imp_P[k][i % IMP_WIN];
}

static double ring_time(const void *ctx, size_t i)
{
    return ((const stepper_core *)ctx)->imp_t[i % IMP_WIN];
}

/* Record the step that ended at t1 after t0 for the impact scan and, for a
 * time-stepping method (scan = 1), count the impacts it decides. */
static void impacts_step(stepper_core *c, const double *sf, int ns, double t0, double t1, int scan)
{
    size_t slot = c->imp_n % IMP_WIN;
    impact_steps w = {ring_impulse, ring_time, c, c->imp_n + 1};
    c->imp_t[slot] = t1;
    for (int k = 0; k < ns; k++) c->imp_P[k][slot] = sf[k] * (t1 - t0);
    c->imp_n++;
    for (int k = 0; k < ns && scan; k++) c->imp_next[k] = impact_scan(&w, k, c->imp_next[k], 1, &c->imp);
}

static int finite_n(const double *x, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}

int exdex_stepper_step(exdex_stepper *s, double dt, double grip_force)
{
    return exdex_stepper_step_gripper(s, dt, grip_force, NULL);
}

int exdex_stepper_step_gripper(exdex_stepper *s, double dt, double grip_force, const exdex_gripper_pose *pose)
{
    stepper_core *c;
    double k, base, t1;
    int status, regrip, nd;
    exdex_kinematics k0, k1;
    if (!s || s->c.failed || s->c.st.lost_sample) return EXDEX_EINVAL;
    c = &s->c;
    if (!(isfinite(dt) && dt > 0.0)) return EXDEX_EINVAL;
    if (!(isnan(grip_force) || (isfinite(grip_force) && grip_force >= 0.0))) return EXDEX_EINVAL;
    /* a pose on every step from the first that gives one; none for the
     * analytic method (its phases are the scene's motion) */
    if (pose ? c->method == EXDEX_METHOD_ANALYTIC : c->posed) return EXDEX_EINVAL;
    if (c->started && dt == c->dt) {
        k = c->k + 1.0;
        base = c->t_base;
    } else {
        k = 1.0;
        base = c->t;
    }
    t1 = base + k * dt;
    if (!(k <= EXDEX_MAX_STEPS) || !isfinite(t1) || !(t1 > c->t)) return EXDEX_EINVAL;
    if (pose) {
        /* the step's motion, from the gripper's state at t: the last given
         * pose, or the scene's motion there */
        if (c->posed) k0 = c->gk;
        else if (exdex_motion_eval(c->model->motion, c->t, &k0)) return EXDEX_EINVAL;
        if (motion_step_set(s->smo, c->t, t1, &k0, pose->R, pose->p, pose->given_v ? pose->v : NULL,
                            pose->given_w ? pose->w : NULL, &k1))
            return EXDEX_EINVAL;
    }
    if (!c->started) {
        /* the run starts with the scene's grip (the switching times include
         * its schedule's breakpoints) and motion */
        set_grip(s, NAN);
        status = s->impl->begin(&s->mc, s->ws, INFINITY, dt, &c->st);
        if (status) goto failed;
        c->started = 1;
        c->dt0 = dt;
    }
    if (pose) s->mc.motion = s->smo;
    regrip = set_grip(s, grip_force);
    status = s->impl->advance(&s->mc, s->ws, t1, regrip, &s->out, 0, &c->st);
    nd = s->mc.ndof;
    if (status == EXDEX_OK && !s->impl->checks_finite &&
        !(finite_n(s->q, nd) && finite_n(s->v, nd) && finite_n(s->wr, 3) && finite_n(s->sf, s->mc.n_src)))
        status = EXDEX_ENONFINITE;
    if (status) goto failed;
    impacts_step(c, s->sf, s->mc.n_src, c->t, t1, s->impl->impacts_from_steps);
    c->t = t1;
    c->t_base = base;
    c->k = k;
    c->dt = dt;
    c->grip = grip_force;
    c->capF = s->mc.capF;
    c->capS = s->mc.capS;
    c->grip_force = s->mc.def.grip_force;
    c->grip_n = s->mc.grip_n;
    c->last.t = t1;
    memcpy(c->last.q, s->q, (size_t)nd * sizeof *s->q);
    memcpy(c->last.v, s->v, (size_t)nd * sizeof *s->v);
    memcpy(c->last.wrench, s->wr, sizeof s->wr);
    c->last.stick = s->stick;
    memcpy(c->last.stop_force, s->sf, (size_t)s->mc.n_src * sizeof *s->sf);
    c->last.grip_force = grip_force;
    c->last.steps++;
    if (s->mc.pads && model_pads_lost(&s->mc, s->q)) {
        /* pads: the grasp is lost at this step, the last one the stepper takes */
        c->st.lost_t = t1;
        c->st.lost_sample = c->last.steps;
    }
    if (pose) {
        c->posed = 1;
        c->gk = k1;
    }
    status = certify_step(s);
    if (status) goto failed;
    return EXDEX_OK;
failed:
    c->failed = 1;
    if (c->st.fail_cause == EXDEX_FAIL_NONE)
        c->st.fail_cause = status == EXDEX_ENOCONV ? EXDEX_FAIL_SOLVER : EXDEX_FAIL_NONFINITE;
    /* as exdex_simulate: an invalid argument inside a method means the state
     * left the finite range */
    return status == EXDEX_EINVAL ? EXDEX_ENONFINITE : status;
}

int exdex_stepper_certificate(const exdex_stepper *s, exdex_certificate *c)
{
    if (!s || !c) return EXDEX_EINVAL;
    *c = s->c.cert;
    return EXDEX_OK;
}

int exdex_stepper_get(const exdex_stepper *s, exdex_stepper_sample *out, exdex_stats *stats)
{
    if (!s) return EXDEX_EINVAL;
    if (out) *out = s->c.last;
    if (stats) {
        *stats = s->c.st;
        if (s->impl->impacts_from_steps && s->c.n_stops && !s->c.failed) {
            /* the final impacts, and the undecided last steps scanned as
             * the end of a run (exdex_simulate counts only after a run that
             * returned EXDEX_OK) */
            exdex_stats imp = s->c.imp;
            impact_steps w = {ring_impulse, ring_time, &s->c, s->c.imp_n};
            for (int k = 0; k < s->c.n_stops; k++) impact_scan(&w, k, s->c.imp_next[k], 0, &imp);
            stats->impacts = imp.impacts;
            stats->max_impulse = imp.max_impulse;
            stats->max_impulse_t = imp.max_impulse_t;
            stats->max_impulse_stop = imp.max_impulse_stop;
        }
    }
    return EXDEX_OK;
}

size_t exdex_stepper_state_size(const exdex_stepper *s)
{
    return s ? sizeof(stepper_core) + s->impl->state_size : 0;
}

/* FNV-1a (64 bit) of a snapshot, its check field counted as 0: restore
 * rejects a snapshot that was changed after save (a corrupted or
 * hand-made buffer), before any of its fields is used. */
static unsigned long long snapshot_check(const void *buf, size_t size)
{
    const unsigned char *p = buf;
    size_t lo = offsetof(stepper_core, check), hi = lo + sizeof(unsigned long long);
    unsigned long long h = 14695981039346656037ull;
    for (size_t i = 0; i < size; i++) {
        h ^= i >= lo && i < hi ? 0u : p[i];
        h *= 1099511628211ull;
    }
    return h;
}

int exdex_stepper_save(const exdex_stepper *s, void *buf, size_t size)
{
    unsigned long long check;
    if (!s || !buf || size != exdex_stepper_state_size(s)) return EXDEX_EINVAL;
    memset(buf, 0, size);
    memcpy(buf, &s->c, sizeof s->c);
    if (s->c.started) s->impl->save(s->ws, (char *)buf + sizeof s->c);
    check = snapshot_check(buf, size);
    memcpy((char *)buf + offsetof(stepper_core, check), &check, sizeof check);
    return EXDEX_OK;
}

int exdex_stepper_restore(exdex_stepper *s, const void *buf, size_t size)
{
    stepper_core c;
    if (!s || !buf || size != exdex_stepper_state_size(s)) return EXDEX_EINVAL;
    memcpy(&c, buf, sizeof c);
    if (c.check != snapshot_check(buf, size)) return EXDEX_EINVAL;
    if (c.magic != SNAPSHOT_MAGIC || c.model != s->c.model || c.method != s->c.method || c.ndof != s->c.ndof ||
        c.n_stops != s->c.n_stops || (c.started != 0 && c.started != 1) || (c.failed != 0 && c.failed != 1) ||
        c.imp_n != c.last.steps + 1 || (c.posed != 0 && c.posed != 1))
        return EXDEX_EINVAL;
    for (int k = 0; k < c.n_stops && s->impl->impacts_from_steps; k++)
        if (c.imp_next[k] < 1 || c.imp_next[k] > c.imp_n || c.imp_next[k] + 2 * IMPACT_STEPS < c.imp_n)
            return EXDEX_EINVAL;
    if (c.started) {
        /* the workspace's fixed part (switching times) from begin, with
         * the scene's grip and the snapshot's first dt; then its state. A
         * state the method rejects leaves the stepper as it was. */
        exdex_stats scratch;
        char *own = NULL;
        int bad;
        if (!(isfinite(c.dt0) && c.dt0 > 0.0)) return EXDEX_EINVAL;
        if (s->c.started) {
            own = malloc(s->impl->state_size);
            if (!own) return EXDEX_ENOMEM;
            s->impl->save(s->ws, own);
        }
        memset(&scratch, 0, sizeof scratch);
        set_grip(s, NAN);
        s->mc.motion = s->c.model->motion;
        bad = s->impl->begin(&s->mc, s->ws, INFINITY, c.dt0, &scratch) ||
              s->impl->restore(s->ws, (const char *)buf + sizeof c);
        if (bad) {
            if (own) {
                s->impl->begin(&s->mc, s->ws, INFINITY, s->c.dt0, &scratch);
                s->impl->restore(s->ws, own);
            }
            s->mc.grip_n = s->c.grip_n;
            s->mc.capF = s->c.capF;
            s->mc.capS = s->c.capS;
            s->mc.def.grip_force = s->c.grip_force;
            if (!s->c.started) set_grip(s, NAN);
            if (s->c.posed) s->mc.motion = s->smo;
            free(own);
            return EXDEX_EINVAL;
        }
        free(own);
        s->mc.grip_n = c.grip_n;
        s->mc.capF = c.capF;
        s->mc.capS = c.capS;
        s->mc.def.grip_force = c.grip_force;
    } else {
        set_grip(s, NAN);
    }
    s->mc.motion = c.posed ? s->smo : s->c.model->motion;
    s->c = c;
    return EXDEX_OK;
}
