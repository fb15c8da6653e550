/* hybrid.c -- the driver of the event-driven and regularised methods
 * (hybrid.h describes both): the ODE workspace, the run's start and the
 * advance from one output sample to the next (integrate to the first event,
 * locate it, decide, apply impulses, restart), save and restore, and the
 * method tables. */
#include "hybrid.h"

/* ------------------------------------------------------ the hybrid loop */

/* Stiff planar slip. The sliding law's direction E u / |E u| relaxes onto
 * the one where the friction balances the load at the rate C |K| / |E u|
 * (hybrid.h), and rk8pd is stable only for steps below ~5 |E u| / (C
 * |K|): a slip that lingers at a small speed (a load just beyond the
 * friction limit, growing it slowly) holds the explicit stepper to steps
 * ~5 (|E u| / V) T whatever the tolerance. Such a slip, below SLIP_STIFF
 * zsw for STIFF_AFTER consecutive accepted steps (a slip passing through
 * that band on its way up or down at an acceleration of the scene's scale
 * A takes a few steps; a brief lingering costs at most STIFF_AFTER explicit
 * steps and keeps rk8pd's answer), is integrated by GSL's bsimp (Bader-Deuflhard
 * semi-implicit extrapolation, stable on the relaxing direction), whose
 * steps are set by the same error control alone; it goes back to rk8pd
 * above 2 SLIP_STIFF zsw and at every event (the mode decided again). The
 * same ODE under the same rtol, atol: the answer differs from an rk8pd run
 * by the tolerance, not by the output grid or the step budget. */
static void stiff_track(hyb *H, const double *y, int reset)
{
    hyb_pads(H, y);
    double u[3], eu[3], s;
    if (reset || H->ndof != 3 || H->law != LAW_COULOMB || H->mode != MODE_SLIP || H->small) {
        H->stiff = 0;
        H->nlow = 0;
        return;
    }
    model_patch_slip(H->m, MODEL_CS(y[2]), y + 3, u);
    for (int c = 0; c < 3; c++) eu[c] = H->m->e[c] * u[c];
    s = sqrt(ex_dot3(eu, eu));
    if (s < SLIP_STIFF * H->zsw) {
        if (H->nlow < STIFF_AFTER) H->nlow++;
        if (H->nlow >= STIFF_AFTER) H->stiff = 1;
    } else if (!H->stiff || !(s <= 2.0 * SLIP_STIFF * H->zsw)) {
        H->stiff = 0;
        H->nlow = 0;
    }
}

/* ------------------------------------------- the Chebyshev (RKC) stepper */

/* A planar slip near its end or its start from rest: the sliding law's
 * direction relaxes at the rate rho = C lam_max(K) / |E u| (K = E W E,
 * stiff_track above), real and negative, while the slip itself (its speed
 * falling or rising at the load's rate, its direction on the quasi-static
 * one) is smooth. rk8pd is held to steps ~5 / rho there whatever the
 * tolerance: each step covers a fixed share of the time left to the stop,
 * so the steps to a stop grow as log(V / zsw) and do not fall with rtol.
 * The second-order Runge-Kutta-Chebyshev method (Sommeijer, Shampine and
 * Verwer 1998, damping 2/13) with s stages is stable for h rho <= 0.653
 * (s^2 - 1): its steps are set by the error control, at a cost of
 * s ~ sqrt(1.54 h rho) right-hand sides. cheb_rho is the bound it is
 * given: CHEB_RHO_SAFETY C |K|_F / |E u| plus the scene's 1 / T, K the
 * free plate's (model_prep: no contact solve). Rows in contact only take
 * mobility away (W_c = W - W J' (J W J')^-1 J W <= W, so lam_max(E W_c E)
 * <= lam_max(K) <= |K|_F): the bound holds against stops too. cheb_track
 * decides when it integrates the slip (the thresholds: tolerances.h). */
typedef struct cheb_ws {
    size_t n;
    double *f0, *yjm1, *yjm2, *yn, *fj;
} cheb_ws;

static double cheb_rho(hyb *H, const double *y)
{
    const exdex_model *m = H->m;
    const exdex_friction_prep *p;
    double cs[2] = {cos(y[2]), sin(y[2])}, u[3], eu[3], s, k2 = 0.0;
    hyb_pads(H, y);
    model_patch_slip(m, cs, y + 3, u);
    for (int c = 0; c < 3; c++) eu[c] = m->e[c] * u[c];
    s = sqrt(ex_dot3(eu, eu));
    p = model_prep(m);
    for (int c = 0; c < 9; c++) k2 += p->K[c] * p->K[c];
    /* |K|_F >= lam_max(K) */
    return CHEB_RHO_SAFETY * H->cap * sqrt(k2) / s + 1.0 / m->scale.T;
}

static void *cheb_alloc(size_t n)
{
    cheb_ws *w = calloc(1, sizeof *w);
    if (!w) return NULL;
    w->n = n;
    w->f0 = malloc(5 * n * sizeof(double));
    if (!w->f0) {
        free(w);
        return NULL;
    }
    w->yjm1 = w->f0 + n;
    w->yjm2 = w->f0 + 2 * n;
    w->yn = w->f0 + 3 * n;
    w->fj = w->f0 + 4 * n;
    return w;
}

static void cheb_free(void *state)
{
    cheb_ws *w = state;
    if (w) free(w->f0);
    free(w);
}

static int cheb_reset(void *state, size_t n)
{
    (void)state;
    (void)n;
    return GSL_SUCCESS;
}

static unsigned int cheb_order(void *state)
{
    (void)state;
    return 2;
}

/* One RKC step of h from (t, y): y the result, yerr the method's error
 * estimate 0.8 (y_n - y_n+1) + 0.4 h (f_n + f_n+1). A step that would need
 * more than CHEB_STAGES_MAX stages is refused with an infinite error (the
 * control shrinks it). */
static int cheb_apply(void *state, size_t n, double t, double h, double y[], double yerr[], const double dydt_in[],
                      double dydt_out[], const gsl_odeiv2_system *sys)
{
    cheb_ws *w = state;
    hyb *H = sys->params;
    double rho = cheb_rho(H, y), w0, w1, t1, t2, arg, bjm1, bjm2, thjm1, thjm2, zjm1, zjm2, dzjm1, dzjm2, d2zjm1,
           d2zjm2, mus;
    double ns = 1.0 + floor(sqrt(1.54 * fabs(h) * rho + 1.0));
    int s = ns < 2.0 ? 2 : (int)fmin(ns, CHEB_STAGES_MAX + 1.0);
    if (!(rho > 0.0) || !isfinite(rho) || s > CHEB_STAGES_MAX) {
        for (size_t i = 0; i < n; i++) yerr[i] = INFINITY;
        return GSL_SUCCESS;
    }
    memcpy(w->yn, y, n * sizeof *y);
    if (dydt_in)
        memcpy(w->f0, dydt_in, n * sizeof *w->f0);
    else if (GSL_ODEIV_FN_EVAL(sys, t, w->yn, w->f0) != GSL_SUCCESS)
        return GSL_EBADFUNC;
    w0 = 1.0 + 2.0 / (13.0 * s * s);
    t1 = w0 * w0 - 1.0;
    t2 = sqrt(t1);
    arg = s * log(w0 + t2);
    w1 = sinh(arg) * t1 / (cosh(arg) * s * t2 - w0 * sinh(arg));
    bjm1 = 1.0 / (4.0 * w0 * w0);
    bjm2 = bjm1;
    mus = w1 * bjm1;
    memcpy(w->yjm2, w->yn, n * sizeof *y);
    for (size_t i = 0; i < n; i++) w->yjm1[i] = w->yn[i] + h * mus * w->f0[i];
    thjm2 = 0.0;
    thjm1 = mus;
    zjm1 = w0;
    zjm2 = 1.0;
    dzjm1 = 1.0;
    dzjm2 = 0.0;
    d2zjm1 = 0.0;
    d2zjm2 = 0.0;
    for (int j = 2; j <= s; j++) {
        double zj = 2.0 * w0 * zjm1 - zjm2, dzj = 2.0 * w0 * dzjm1 - dzjm2 + 2.0 * zjm1;
        double d2zj = 2.0 * w0 * d2zjm1 - d2zjm2 + 4.0 * dzjm1, bj = d2zj / (dzj * dzj);
        double ajm1 = 1.0 - zjm1 * bjm1, mu = 2.0 * w0 * bj / bjm1, nu = -bj / bjm2, mj = mu * w1 / w0;
        if (GSL_ODEIV_FN_EVAL(sys, t + h * thjm1, w->yjm1, w->fj) != GSL_SUCCESS) {
            memcpy(y, w->yn, n * sizeof *y);
            return GSL_EBADFUNC;
        }
        for (size_t i = 0; i < n; i++)
            y[i] = mu * w->yjm1[i] + nu * w->yjm2[i] + (1.0 - mu - nu) * w->yn[i] +
                   h * mj * (w->fj[i] - ajm1 * w->f0[i]);
        {
            double thj = mu * thjm1 + nu * thjm2 + mj * (1.0 - ajm1);
            thjm2 = thjm1;
            thjm1 = thj;
        }
        if (j < s) {
            memcpy(w->yjm2, w->yjm1, n * sizeof *y);
            memcpy(w->yjm1, y, n * sizeof *y);
        }
        bjm2 = bjm1;
        bjm1 = bj;
        zjm2 = zjm1;
        zjm1 = zj;
        dzjm2 = dzjm1;
        dzjm1 = dzj;
        d2zjm2 = d2zjm1;
        d2zjm1 = d2zj;
    }
    if (GSL_ODEIV_FN_EVAL(sys, t + h, y, w->fj) != GSL_SUCCESS) {
        memcpy(y, w->yn, n * sizeof *y);
        return GSL_EBADFUNC;
    }
    for (size_t i = 0; i < n; i++) yerr[i] = 0.8 * (w->yn[i] - y[i]) + 0.4 * h * (w->f0[i] + w->fj[i]);
    if (dydt_out) memcpy(dydt_out, w->fj, n * sizeof *dydt_out);
    return GSL_SUCCESS;
}

static const gsl_odeiv2_step_type cheb_type = {"rkc", 1, 1, cheb_alloc, cheb_apply, NULL, cheb_reset, cheb_order,
                                               cheb_free};

/* Whether the Chebyshev stepper integrates the slip from here: a Coulomb
 * planar slip of the ellipsoid law, without stop friction or the stiff
 * stepper, whose last rk8pd steps were held near their stability limit
 * (h rho >= CHEB_ON for CHEB_AFTER steps in a row), and, with no row in
 * contact, slower than CHEB_SLOW V (a free slip dying out or starting from
 * rest; a faster free slip stays with rk8pd, whose eighth order serves its
 * accuracy better). Along a stop the rows leave the plate a stiff mobility
 * at any slip speed: rk8pd's steps there sit at h rho 4 to 10 whatever the
 * tolerance, so the speed does not decide. Back to rk8pd where rk8pd's step
 * would be stable again (h rho < CHEB_OFF with the step the error control
 * chose), on a free slip above CHEB_SLOW V, and at every event (reset). */
static void cheb_track(hyb *H, const double *y, double h, int reset)
{
    double hr;
    if (reset || H->ndof != 3 || H->law != LAW_COULOMB || H->mode != MODE_SLIP || H->small || H->stiff ||
        H->sfric || H->m->ls_exact || (y[3] == 0.0 && y[4] == 0.0 && y[5] == 0.0)) {
        H->cheb = 0;
        H->ncheb = 0;
        return;
    }
    if (!H->ncs && !(hyb_planar_slip_speed(H, y) < CHEB_SLOW * H->m->scale.V)) {
        H->cheb = 0;
        H->ncheb = 0;
        return;
    }
    hr = h * cheb_rho(H, y) / CHEB_RHO_SAFETY;
    if (H->cheb) {
        if (!(hr >= CHEB_OFF)) H->cheb = 0, H->ncheb = 0;
    } else if (hr >= CHEB_ON) {
        if (++H->ncheb >= CHEB_AFTER) H->cheb = 1;
    } else {
        H->ncheb = 0;
    }
}

/* The stepper of the slip's state (stiff_track, cheb_track). */
static gsl_odeiv2_step *hyb_stepper(ode *O, const hyb *H)
{
    return H->stiff ? O->bs : H->cheb ? O->ck : O->rk;
}

static void ode_free(ode *O)
{
    if (!O) return;
    free(O->mc);
    if (O->root) gsl_root_fsolver_free(O->root);
    if (O->evo) gsl_odeiv2_evolve_free(O->evo);
    if (O->con) gsl_odeiv2_control_free(O->con);
    if (O->rk) gsl_odeiv2_step_free(O->rk);
    if (O->bs) gsl_odeiv2_step_free(O->bs);
    if (O->ck) gsl_odeiv2_step_free(O->ck);
    free(O->ts);
    free(O->gb);
    free(O);
}

/* The GSL workspaces of one run (the method table's alloc); the system's
 * parameters are set by the run. */
static void *hybrid_alloc(const exdex_model *m, int *status)
{
    size_t ny = (size_t)(m->ndof == 3 ? 9 + m->n_src : 3 + m->n_src);
    ode *O = calloc(1, sizeof *O);
    if (!O) {
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    O->rk = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, ny);
    O->bs = gsl_odeiv2_step_alloc(gsl_odeiv2_step_bsimp, ny);
    O->ck = gsl_odeiv2_step_alloc(&cheb_type, ny);
    O->step = O->rk;
    {
        /* atol is relative to the scene's scales: each state component's
         * absolute tolerance is atol times its own scale (positions L,
         * angles 1 rad, velocities L / T and 1 / T, force integrals F T,
         * torque integrals F L T), so the error control (and with it every
         * step) is the same in any units */
        const model_scales *s = &m->scale;
        double sc[NY_MAX];
        size_t k = 0;
        if (m->ndof == 3) {
            double row[9] = {s->L, s->L, 1.0, s->V, s->V, 1.0 / s->T, s->F * s->T, s->F * s->T, s->F * s->L * s->T};
            for (; k < 9; k++) sc[k] = row[k];
        } else {
            sc[k++] = s->q;
            sc[k++] = s->q / s->T;
            sc[k++] = s->F * s->T * s->L / s->q;
        }
        for (; k < ny; k++) sc[k] = s->F * s->T;
        O->con = gsl_odeiv2_control_scaled_new(m->def.atol, m->def.rtol, 1.0, 0.0, sc, ny);
    }
    O->evo = gsl_odeiv2_evolve_alloc(ny);
    O->root = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    O->ts = malloc((EXDEX_MOTION_MAX_SWITCHES + m->grip_n) * sizeof *O->ts);
    O->gb = malloc((EXDEX_MOTION_MAX_SWITCHES + m->grip_n) * sizeof *O->gb);
    if (m->pads) O->mc = calloc(1, sizeof *O->mc);
    if (!O->rk || !O->bs || !O->ck || !O->con || !O->evo || !O->root || !O->ts || !O->gb || (m->pads && !O->mc)) {
        ode_free(O);
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    /* the evolve object's vectors go into a saved state (hybrid_save) also
     * before its first step writes them (a run stuck from the start): they
     * start at 0, not as malloc left them */
    memset(O->evo->y0, 0, ny * sizeof(double));
    memset(O->evo->yerr, 0, ny * sizeof(double));
    memset(O->evo->dydt_in, 0, ny * sizeof(double));
    memset(O->evo->dydt_out, 0, ny * sizeof(double));
    O->sys.function = hyb_rhs;
    O->sys.jacobian = hyb_slip_jac;
    O->sys.dimension = ny;
    O->sys.params = NULL;
    return O;
}

static void hybrid_free(void *ws) { ode_free(ws); }

/* Forget the last accepted step. GSL's evolve object starts a step from
 * the previous step's end derivative (dydt_out, at the state it returned)
 * while its step count is > 0, for steppers that take an input derivative
 * (rk8pd does): after any change of y or of the right-hand side between two
 * gsl_odeiv2_evolve_apply calls (an event, a projection, a velocity jump, a
 * new motion or grip segment, a new mode) the next step must evaluate it
 * afresh. */
static void ode_restart(ode *O)
{
    gsl_odeiv2_evolve_reset(O->evo);
    gsl_odeiv2_step_reset(O->step);
}

/* The switching times in (0, t_end], increasing: the motion's
 * (exdex_motion_switches: its acceleration switches and velocity jumps) and
 * the grip schedule's breakpoints (model_grip_breaks: the capacity or its
 * derivatives jump there), merged; gb is scratch for the breakpoints. A
 * jump at t_end is applied too, so the state recorded there is its right
 * limit, as at every other time. */
static size_t switch_times(const exdex_model *m, double t_end, double *ts, double *gb)
{
    double c[EXDEX_MOTION_MAX_SWITCHES];
    int n = exdex_motion_switches(m->motion, c);
    size_t k = 0, ng = model_grip_breaks(m, t_end, gb), i = 0, j = 0;
    while (i < (size_t)n || j < ng) {
        double x;
        if (j >= ng || (i < (size_t)n && c[i] <= gb[j]))
            x = c[i++];
        else
            x = gb[j++];
        if (x > 0.0 && x <= t_end && (k == 0 || x > ts[k - 1])) ts[k++] = x;
    }
    return k;
}

static int is_still(const hyb *H, const double *y)
{
    if (H->ndof == 1) return y[1] == 0.0;
    return y[3] == 0.0 && y[4] == 0.0 && y[5] == 0.0;
}

/* The failure record of a run that stopped at t with status. */
static void hybrid_failed(const hyb *H, int status, double t, exdex_stats *st)
{
    /* the stepper and event location fail with ENOCONV, the inner
     * solvers with their own status (simulate.c names those) */
    if (status == EXDEX_ENOCONV && st->fail_cause == EXDEX_FAIL_NONE && !H->err)
        st->fail_cause = EXDEX_FAIL_STEPPER;
    st->fail_time = t;
}

/* The initial state and mode; the switching times in (0, t_end]. */
static int hybrid_begin(const exdex_model *m, ode *O, int law, double t_end, double dt, exdex_stats *st)
{
    hyb H;
    double y[NY_MAX], *ts = O->ts, h;
    size_t nsw;
    int nd, ns;
    if (O->mc) m = model_pads_follow(m, O->mc);
    nd = m->ndof;
    ns = m->n_stops;
    memset(&H, 0, sizeof H);
    H.m = m;
    H.mc = O->mc;
    H.law = law;
    H.ndof = nd;
    H.ns = ns;
    H.no = m->n_obst;
    H.ny = nd == 3 ? 9 + m->n_src : 3 + m->n_src;
    H.nv = m->n_vert ? m->n_vert : 1;
    H.st = st;
    for (int k = 0; nd == 3 && k < ns + m->n_obst; k++) H.sfric |= model_source_mu(m, k) > 0.0;
    /* eps is a slip speed |E u| [m/s]; a 1-DoF rotation slips at
     * |E u| = e_r |thd|, so its smoothing rate is eps / e_r [rad/s] */
    H.eps = m->ndof == 1 && m->def.dof == EXDEX_DOF_ROTATION ? m->def.eps / m->e[2] : m->def.eps;
    if (nd == 3) {
        H.M = 1.0;
        H.capk = 1.0;
        H.cap = m->capF;
        H.caps = m->capS;
        H.zsw = SLIP_FLOOR * m->scale.V;  /* a slip speed |E u| */
    } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        H.M = m->m;
        H.capk = 1.0;
        H.cap = m->capF;
        H.caps = m->capS;
    } else {
        H.M = m->mrot;
        H.capk = m->e[2];
        H.cap = m->capF * m->e[2];
        H.caps = m->capS * m->e[2];
    }
    O->sys.params = &H;
    nsw = switch_times(m, t_end, ts, O->gb);
    memset(y, 0, sizeof y);
    if (nd == 3) {
        model_initial_state(m, y, y + 3);
    } else {
        model_initial_state(m, y, y + 1);
    }
    H.lo = 0.0;
    H.hi = nsw ? ts[0] : INFINITY;
    hyb_decide(&H, 0.0, y, 0);
    h = fmin(dt, m->tol.h0);
    O->S.H = H;
    memcpy(O->S.y, y, sizeof y);
    O->S.t = O->S.t_rec = 0.0;
    O->S.h = h;
    O->S.nsw = nsw;
    O->sys.params = &O->S.H;
    O->step = O->rk;
    /* GSL's objects as allocated: a begin after a run starts afresh */
    gsl_odeiv2_evolve_reset(O->evo);
    gsl_odeiv2_step_reset(O->step);
    /* a failure in the decision at t = 0 stops the run before it starts */
    if (H.err) hybrid_failed(&H, H.err, 0.0, st);
    return H.err;
}

/* One output interval, from the last recorded time to ti, recorded as
 * sample i. regrip: the model's capacity changed since the last interval
 * (the stepper's grip force): the mode is decided again at its start. */
/* The state of one output interval's loop (hybrid_advance): the run's
 * state, the step under way and the first event found in it. */
typedef struct adv {
    hyb H;
    ode *O;
    exdex_stats *st;
    double t, h, y[NY_MAX];   /* time reached, the stepper's next step, the state */
    double ti;                /* the interval's end */
    const double *ts;         /* switching times (nsw of them) */
    size_t nsw, k;            /* k: the segment of the step (ts[k - 1] <= t < ts[k]) */
    /* the step */
    double t0, y0[NY_MAX];    /* its start */
    hyb_guard g0[NG_MAX], g1[NG_MAX];  /* the guards at its start and at its end */
    int ng;
    double tau_best;          /* the first event: t0 + tau_best, guard e_best (-1: none) */
    int e_best;
    /* the interval */
    int events, same;         /* events, and how often in a row one fell at the same time */
    double t_event;
    unsigned long ode_steps;
    size_t brent0;            /* Brent iterations count in the step budget */
    unsigned long maps0;      /* ... or the one-step maps, if more */
} adv;

/* The interval's step budget is spent (hybrid.h, "Budgets"). */
static int over_budget(const adv *A)
{
    size_t it = A->st->solver_iterations - A->brent0;
    unsigned long maps = A->O->maps - A->maps0;
    return A->ode_steps + (maps > it ? maps : it) > STEPS_MAX;
}

/* The step from A->t: its segment, where it must end (tstop: the interval's
 * end, the segment's, the motion's next knot), the slip's reference
 * direction, the guards at its start and the stepper of the mode. */
static double step_start(adv *A)
{
    hyb *H = &A->H;
    ode *O = A->O;
    const exdex_model *m = H->m;
    int nd = H->ndof, law = H->law;
    double tstop;
    A->t0 = A->t;
    O->f0_ok = 0;   /* a new step, perhaps in a new mode */
    A->tau_best = INFINITY;
    A->e_best = -1;
    A->k = 0;
    while (A->k < A->nsw && A->ts[A->k] <= A->t) A->k++;
    H->lo = A->k ? A->ts[A->k - 1] : 0.0;
    H->hi = A->k < A->nsw ? A->ts[A->k] : INFINITY;
    tstop = fmin(A->ti, H->hi);
    tstop = fmin(tstop, exdex_motion_next_knot(m->motion, A->t));  /* a step ends at a knot: header */
    if (nd == 3 && H->mode == MODE_SLIP && law == LAW_COULOMB &&
        (A->y[3] != 0.0 || A->y[4] != 0.0 || A->y[5] != 0.0)) {
        double u[3];
        hyb_pads(H, A->y);
        model_patch_slip(m, MODEL_CS(A->y[2]), A->y + 3, u);
        for (int c = 0; c < 3; c++) H->uref[c] = m->e[c] * u[c];
    }
    memcpy(A->y0, A->y, sizeof A->y);
    A->ng = hyb_guards(H, A->t0, A->y0, A->g0);
    if (O->step != hyb_stepper(O, H)) {
        O->step = hyb_stepper(O, H);
        ode_restart(O);
    }
    return tstop;
}

/* One accepted step of the stepper towards tstop, within the step budget
 * and above the step floor (hybrid.h); the guards at its end. */
static int step_integrate(adv *A, double tstop)
{
    hyb *H = &A->H;
    ode *O = A->O;
    exdex_stats *st = A->st;
    int gs;
    {
        unsigned long c0 = O->evo->count + O->evo->failed_steps;
        gs = gsl_odeiv2_evolve_apply(O->evo, O->con, O->step, &O->sys, &A->t, tstop, &A->h, A->y);
        A->ode_steps += O->evo->count + O->evo->failed_steps - c0;
    }
    if (H->err) return H->err;
    if (gs != GSL_SUCCESS) {
        st->fail_cause = EXDEX_FAIL_STEPPER;
        return EXDEX_ENOCONV;
    }
    st->steps++;
    /* step budget and step floor (hybrid.h) */
    if (over_budget(A) || (A->t < tstop && !(A->h >= H_FLOOR_ULPS * DBL_EPSILON * fabs(A->t)))) {
        st->warnings++;
        st->fail_cause = over_budget(A) ? EXDEX_FAIL_STEP_BUDGET : EXDEX_FAIL_STEP_FLOOR;
        return EXDEX_ENOCONV;
    }
    hyb_guards(H, A->t, A->y, A->g1);
    return EXDEX_OK;
}

/* A 1-DoF slip that stops and restarts the same way within the step: the
 * step is cut at the dip (guard 0, s qd, violated there). */
static int slip_dip_1dof(adv *A)
{
    hyb *H = &A->H;
    ode *O = A->O;
    int status = EXDEX_OK;
    if (H->ndof != 1 || H->law != LAW_COULOMB) return EXDEX_OK;
    if (H->mode == MODE_SLIP && A->g0[0].value > 0.0 && A->g1[0].value >= 0.0) {
        /* the slip can stop and restart the same way within one
         * step (the load falls inside the friction limit and
         * leaves it again): s qd dips below 0 and recovers, which
         * the end values do not show. s qd has an interior minimum
         * when its rate turns from falling to rising over the step;
         * then a golden-section search for it on the stepper's map
         * (bounded), and a negative minimum bounds the root */
        double d0[NY_MAX], d1[NY_MAX];
        if (hyb_rhs(A->t0, A->y0, d0, H) == GSL_SUCCESS && hyb_rhs(A->t, A->y, d1, H) == GSL_SUCCESS &&
            H->s * d0[1] < 0.0 && H->s * d1[1] > 0.0) {
            double tm, gm;
            status = hyb_guard_extremum(H, O, A->t0, A->y0, A->t - A->t0, 0, 1.0, &tm, &gm);
            if (status) return status;
            if (gm < 0.0) {
                /* the step ends at the dip; the guard is violated there */
                if (hyb_one_step(O, A->t0, A->y0, tm, A->y) != GSL_SUCCESS) {
                    status = EXDEX_ENOCONV;
                    return status;
                }
                A->t = A->t0 + tm;
                hyb_guards(H, A->t, A->y, A->g1);
            }
        }
    }
    return EXDEX_OK;
}

/* The guards violated at the step's end: each one's first crossing
 * (located), the earliest into A->tau_best, A->e_best. */
static int crossings(adv *A)
{
    hyb *H = &A->H;
    ode *O = A->O;
    exdex_stats *st = A->st;
    int status = EXDEX_OK;
    for (int e = 0; e < A->ng; e++) {
        double tau;
        if (!(A->g1[e].value < 0.0)) continue;
        if (A->g0[e].value <= 0.0) {
            /* violated from the start: an event at t0 unless the
             * guard is recovering (a touching stop left behind), or
             * the decision at t0 keeps being undone (a tie: let the
             * step decide, counted as a warning) */
            if (!(A->g1[e].value < A->g0[e].value - GUARD_RECOVER)) continue;
            {
                /* it may recover first and cross later within the
                 * step (a corner lifted off a stop by an impact at
                 * t0 falls back): locate that crossing */
                double tm, gm;
                status = hyb_guard_extremum(H, O, A->t0, A->y0, A->t - A->t0, e, -1.0, &tm, &gm);
                if (status) break;
                if (gm > 0.0) {
                    status = hyb_locate(H, O, A->t0, A->y0, tm, A->t - A->t0, e, &tau);
                    if (status) break;
                    if (tau < A->tau_best) {
                        A->tau_best = tau;
                        A->e_best = e;
                    }
                    continue;
                }
            }
            if (A->same >= 4) {
                st->warnings++;
                continue;
            }
            tau = 0.0;
        } else {
            status = hyb_locate(H, O, A->t0, A->y0, 0.0, A->t - A->t0, e, &tau);
            if (status) break;
        }
        if (tau < A->tau_best) {
            A->tau_best = tau;
            A->e_best = e;
        }
    }
    return status;
}

/* Guards that dip below 0 and recover within the step (their end values
 * do not show it): free gaps, obstacle rows through a feature switch,
 * 1-DoF corners. */
static int dips(adv *A)
{
    hyb *H = &A->H;
    ode *O = A->O;
    int status = EXDEX_OK;
    /* a free gap that dipped below 0 and recovered within the step */
    if (!status) status = hyb_gap_dips(H, O, A->t0, A->y0, A->t, A->y, A->ng, A->g0, A->g1, &A->tau_best, &A->e_best);
    /* ... or through an obstacle row's feature switch */
    if (!status) status = hyb_obst_dips(H, O, A->t0, A->y0, A->t, A->y, A->ng, A->g0, A->g1, &A->tau_best, &A->e_best);
    if (!status && H->ns && H->ndof == 1) {
        /* 1-DoF: a corner's gap dipping below 0 within the step
         * (hyb_row_dip): the event is its stop guard, violated at the
         * crossing */
        hyb_guard gt[NG_MAX];
        double tau, ye[NY_MAX], t1 = A->t;
        const double *y1 = A->y;
        if (A->tau_best < A->t - A->t0) {
            /* only a dip before the event found matters */
            if (hyb_one_step(O, A->t0, A->y0, A->tau_best, O->ytmp) != GSL_SUCCESS || H->err) {
                status = H->err ? H->err : EXDEX_ENOCONV;
                return status;
            }
            memcpy(ye, O->ytmp, (size_t)H->ny * sizeof *ye);
            t1 = A->t0 + A->tau_best;
            y1 = ye;
        }
        status = hyb_row_dip(H, O, A->t0, A->y0, t1, y1, &tau);
        if (!status && tau < A->tau_best) {
            if (hyb_one_step(O, A->t0, A->y0, tau, O->ytmp) != GSL_SUCCESS || H->err) {
                status = H->err ? H->err : EXDEX_ENOCONV;
            } else {
                hyb_guards(H, A->t0 + tau, O->ytmp, gt);
                for (int e = 0; e < A->ng; e++)
                    if (A->g0[e].value > 0.0 && gt[e].value < 0.0) {
                        A->tau_best = tau;
                        A->e_best = e;
                        break;
                    }
            }
        }
    }
    return status;
}

/* The earliest crossing before the event found (a guard dipping and
 * recovering before it, seen at the event's point; at most ng passes). */
static int earliest(adv *A)
{
    hyb *H = &A->H;
    ode *O = A->O;
    int status = EXDEX_OK;
    /* a guard can dip below 0 and recover within one step (its end
     * value is >= 0): the located event's point shows it; take the
     * earliest such crossing instead (at most ng passes) */
    for (int pass = 0; A->e_best >= 0 && A->tau_best > 0.0 && !status && pass < A->ng; pass++) {
        hyb_guard gt[NG_MAX];
        double tau_new = A->tau_best;
        int e_new = -1;
        if (hyb_one_step(O, A->t0, A->y0, A->tau_best, O->ytmp) != GSL_SUCCESS || H->err) {
            status = H->err ? H->err : EXDEX_ENOCONV;
            break;
        }
        hyb_guards(H, A->t0 + A->tau_best, O->ytmp, gt);
        for (int e = 0; e < A->ng && !status; e++) {
            double tau;
            if (e == A->e_best || !(A->g0[e].value > 0.0) || !(gt[e].value < 0.0)) continue;
            status = hyb_locate(H, O, A->t0, A->y0, 0.0, A->tau_best, e, &tau);
            if (!status && tau < tau_new) {
                tau_new = tau;
                e_new = e;
            }
        }
        if (e_new < 0) break;
        A->tau_best = tau_new;
        A->e_best = e_new;
    }
    return status;
}

/* The first event inside the step [t0, t] into A->tau_best, A->e_best (-1:
 * none), within the step budget. */
static int find_event(adv *A)
{
    exdex_stats *st = A->st;
    int status = slip_dip_1dof(A);
    if (!status) status = crossings(A);
    if (!status) status = dips(A);
    if (!status) status = earliest(A);
    if (!status && over_budget(A)) {
        st->warnings++;
        st->fail_cause = EXDEX_FAIL_STEP_BUDGET;
        status = EXDEX_ENOCONV;
    }
    return status;
}

/* The state at the event (the step cut there), the decision there
 * (hyb_decide_event: the next mode and the tie rules), the event budget. */
static int take_event(adv *A)
{
    hyb *H = &A->H;
    ode *O = A->O;
    exdex_stats *st = A->st;
    int status = EXDEX_OK;
    if (A->tau_best > 0.0 && A->t0 + A->tau_best == A->t0 && A->g0[A->e_best].value > 0.0 && A->t > A->t0) {
        /* a crossing within half an ulp of t0: the event time
         * would round to t0, where the guard holds and the
         * decision at the same state would be taken again
         * (no progress, events piling up at one time): the
         * event is at the next representable time */
        A->tau_best = nextafter(A->t0, INFINITY) - A->t0;
    }
    if (hyb_one_step(O, A->t0, A->y0, A->tau_best, A->y) != GSL_SUCCESS || H->err) {
        status = H->err ? H->err : EXDEX_ENOCONV;
        return status;
    }
    A->t = A->t0 + A->tau_best;
    A->same = A->t == A->t_event ? A->same + 1 : 0;
    A->t_event = A->t;
    status = hyb_decide_event(H, A->t, A->y, A->g0[A->e_best], A->same);
    if (status) return status;
    gsl_odeiv2_evolve_reset(O->evo);
    gsl_odeiv2_step_reset(O->step);
    if (++A->events > EVENTS_MAX) {
        st->warnings++;
        st->fail_cause = EXDEX_FAIL_EVENTS;
        status = EXDEX_ENOCONV;
        return status;
    }
    return EXDEX_OK;
}

/* No event in the step: the contact set's projection (a planar rest holds q). */
static void settle_step(adv *A)
{
    hyb *H = &A->H;
    ode *O = A->O;
    int nd = H->ndof, law = H->law;
    /* the projection moves y off the evolve object's last
     * output: the next step must not start from that output's
     * derivative */
    double yp[NY_MAX];
    memcpy(yp, A->y, sizeof yp);
    /* a planar rest holds q (hyb_reported_pose) */
    if (!(nd == 3 && law == LAW_COULOMB && H->mode == MODE_STICK)) hyb_project_contact(H, A->t, A->y);
    if (memcmp(yp, A->y, (size_t)H->ny * sizeof *A->y)) ode_restart(O);
}

/* After the step: the stepper's choice, the smallest gap, the next motion
 * segment at a switching time (velocity jumps, a decision). */
static int after_step(adv *A)
{
    hyb *H = &A->H;
    ode *O = A->O;
    exdex_stats *st = A->st;
    const exdex_model *m = H->m;
    int ns = H->ns, status = EXDEX_OK;
    stiff_track(H, A->y, A->e_best >= 0);
    cheb_track(H, A->y, A->t - A->t0, A->e_best >= 0);
    /* a penetration left after the step: the scene drives the
     * object through a stop (see tol.pen) */
    if (ns || m->n_obst) {
        exdex_kinematics kt;
        double yr[NY_MAX];
        const double *yq = hyb_reported_pose(H, A->t, A->y, yr);
        double gmin = exdex_motion_eval(m->motion, A->t, &kt) ? INFINITY : contact_min_gap(m, &kt, yq);
        if (gmin < st->min_gap) st->min_gap = gmin;
        if (gmin < -m->tol.pen) st->warnings++;
    }
    if (A->t == H->hi) {
        /* a switching time of the motion: next segment */
        hyb_hold_set_rows(H, A->t, A->y);
        H->lo = H->hi;
        A->k++;
        H->hi = A->k < A->nsw ? A->ts[A->k] : INFINITY;
        status = hyb_apply_jump(H, A->t, A->y);
        if (status) return status;
        hyb_decide(H, A->t, A->y, 0);
        stiff_track(H, A->y, 1);
        cheb_track(H, A->y, 0.0, 1);
        ode_restart(O);
    }
    if (!ex_finite_n(A->y, H->ny)) status = EXDEX_ENONFINITE;
    return status;
}

/* The sample at the interval's end: the interval's integrals (friction,
 * stop forces) as means over its length hs; then they restart from 0. */
static void record_sample(adv *A, exdex_trajectory *out, size_t i, double hs)
{
    hyb *H = &A->H;
    exdex_stats *st = A->st;
    const exdex_model *m = H->m;
    int nd = H->ndof, law = H->law;
/* the interval's integrals (friction, stop forces) as means
 * over it; then they restart from 0 */
int off = nd == 1 ? 2 : 6, nw = nd == 1 ? 1 : 3;
double wrench[3] = {0, 0, 0}, sf[NSRC_MAX], yr[NY_MAX];
const double *yq;
if (nd == 3) {
    for (int c = 0; c < 3; c++) wrench[c] = A->y[6 + c] / hs;
} else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
    wrench[0] = A->y[2] / hs * m->d[0];
    wrench[1] = A->y[2] / hs * m->d[1];
} else {
    wrench[2] = A->y[2] / hs;
}
for (int k2 = 0; k2 < m->n_src; k2++) sf[k2] = A->y[off + nw + k2] / hs;
yq = hyb_reported_pose(H, A->ti, A->y, yr);
method_record(m, out, st, i, A->ti, yq, yq + nd, wrench,
              law == LAW_COULOMB && H->mode == MODE_STICK ? 1 : is_still(H, A->y), sf);
for (int c = off; c < H->ny; c++) A->y[c] = 0.0;
}

/* One output interval: steps to ti, each a pipeline (the step, its first
 * event, the decision there or the projection, the segment's end), then
 * the sample. */
static int hybrid_advance(const exdex_model *m, ode *O, double ti, int regrip, exdex_trajectory *out, size_t i,
                          exdex_stats *st)
{
    adv A;
    hyb *H = &A.H;
    int status = EXDEX_OK;
    A.H = O->S.H;
    A.O = O;
    A.st = st;
    A.ti = ti;
    A.ts = O->ts;
    A.nsw = O->S.nsw;
    A.t = O->S.t;
    A.h = O->S.h;
    if (O->mc) m = model_pads_follow(m, O->mc);
    memcpy(A.y, O->S.y, sizeof A.y);
    H->m = m;
    H->mc = O->mc;
    H->st = st;
    O->sys.params = H;
    O->step = hyb_stepper(O, H);
    if (regrip) {
        H->cap = H->capk * model_capacity(m, A.t);
        H->caps = H->capk * model_capacity_static(m, A.t);
        hyb_hold_set_rows(H, A.t, A.y);
        hyb_decide(H, A.t, A.y, 0);
        stiff_track(H, A.y, 1);
        cheb_track(H, A.y, 0.0, 1);
        O->step = O->rk;
        gsl_odeiv2_evolve_reset(O->evo);
        gsl_odeiv2_step_reset(O->step);
        status = H->err;
    }
    do {
        double hs = ti - O->S.t_rec;
        if (status) break;
        A.events = A.same = 0;
        A.ode_steps = 0;
        A.brent0 = st->solver_iterations;
        A.maps0 = O->maps;
        A.t_event = -1.0;
        while (A.t < ti && status == EXDEX_OK && !H->err) {
            double tstop = step_start(&A);
            status = step_integrate(&A, tstop);
            if (!status) status = find_event(&A);
            if (status) break;
            if (A.e_best >= 0)
                status = take_event(&A);
            else
                settle_step(&A);
            if (!status) status = after_step(&A);
            if (!status && O->mc) {
                /* pads on the fingers: a region that vanished inside the
                 * interval ends the integration there; the sample holds the
                 * pose where it vanished and exdex_simulate stops at it */
                double yr[NY_MAX];
                if (model_pads_lost(m, hyb_reported_pose(H, A.t, A.y, yr))) break;
            }
        }
        if (H->err && !status) status = H->err;
        if (status) break;
        record_sample(&A, out, i, hs);
    } while (0);
    if (!status && H->err) status = H->err;
    if (status) hybrid_failed(H, status, A.t, st);
    O->S.H = A.H;
    memcpy(O->S.y, A.y, sizeof A.y);
    O->S.t = A.t;
    O->S.h = A.h;
    O->S.t_rec = ti;
    O->sys.params = &O->S.H;
    return status;
}

/* ------------------------------------------------------------ entry points */

static int event_begin(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st)
{
    return hybrid_begin(m, ws, LAW_COULOMB, t_end, dt, st);
}

static int regularised_begin(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st)
{
    return hybrid_begin(m, ws, LAW_SMOOTH, t_end, dt, st);
}

static int hybrid_advance_ws(const exdex_model *m, void *ws, double t1, int regrip, exdex_trajectory *out,
                             size_t i, exdex_stats *st)
{
    return hybrid_advance(m, ws, t1, regrip, out, i, st);
}

/* The state: O->S with the evolve object's fields (the switching times
 * are fixed by begin; the stepper and control objects are not saved: the
 * rk8pd and bsimp steppers recompute all their stages (bsimp also its
 * Jacobian) from y and dydt_in in each application, the one in use is
 * H.stiff's, and the scaled control has no state). */
static void hybrid_save(const void *ws, void *buf)
{
    const ode *O = ws;
    struct hyb_state S;
    size_t n = O->evo->dimension;
    memcpy(&S, &O->S, sizeof S);
    S.count = O->evo->count;
    S.failed_steps = O->evo->failed_steps;
    S.last_step = O->evo->last_step;
    memcpy(S.e_y0, O->evo->y0, n * sizeof(double));
    memcpy(S.e_yerr, O->evo->yerr, n * sizeof(double));
    memcpy(S.e_dydt_in, O->evo->dydt_in, n * sizeof(double));
    memcpy(S.e_dydt_out, O->evo->dydt_out, n * sizeof(double));
    memcpy(buf, &S, sizeof S);
}

static int hybrid_restore(void *ws, const void *buf)
{
    ode *O = ws;
    struct hyb_state S;
    const hyb *B = &O->S.H;   /* as begin set it up for this model and law */
    int nr;
    memcpy(&S, buf, sizeof S);
    nr = B->ns * B->nv;
    if (S.H.law != B->law || S.H.ndof != B->ndof || S.H.ns != B->ns || S.H.no != B->no || S.H.ny != B->ny ||
        S.H.nv != B->nv || S.nsw != O->S.nsw || S.H.mode < MODE_SLIP || S.H.mode > MODE_FREE || S.H.ncs < 0 ||
        S.H.ncs > MAX_ROWS ||
        (S.H.mode == MODE_CONTACT && !(S.H.ck >= 0 && S.H.ck < B->ns && S.H.cj >= 0 && S.H.cj < B->nv) &&
         !(S.H.ck >= B->ns && S.H.ck < B->ns + B->no && orow_valid(B->m, S.H.cj) &&
           orow_obst(S.H.cj) == S.H.ck - B->ns)))
        return EXDEX_EINVAL;
    for (int i = 0; i < S.H.ncs; i++)
        if (S.H.cs[i] < 0 || (S.H.cs[i] >= nr && !(B->no && orow_valid(B->m, S.H.cs[i] - nr)))) return EXDEX_EINVAL;
    if (S.H.sfric != B->sfric || (S.H.stiff != 0 && S.H.stiff != 1) || (S.H.cheb != 0 && S.H.cheb != 1) ||
        S.H.ncheb < 0 || S.H.ncheb > CHEB_AFTER || S.H.nlow < 0 || S.H.nlow > STIFF_AFTER ||
        (S.H.jam != 0.0 && S.H.jam != 1.0 && S.H.jam != -1.0) || (S.H.held != 0 && S.H.held != 1))
        return EXDEX_EINVAL;
    for (int k = 0; k < SF_MAX_STOPS; k++)
        if (S.H.fm[k] < SF_ROLL || S.H.fm[k] > SF_NONE) return EXDEX_EINVAL;
    if (S.H.sgn < 0 || S.H.sgn > SF_MAX_STOPS || (S.H.sgn > 0 && S.H.ndof != 3)) return EXDEX_EINVAL;
    for (int i = 0; S.H.sgn > 0 && i < S.H.ncs; i++)
        if (S.H.sg[i] < 0 || S.H.sg[i] >= S.H.sgn) return EXDEX_EINVAL;
    O->S = S;
    O->sys.params = &O->S.H;
    {
        size_t n = O->evo->dimension;
        O->evo->count = S.count;
        O->evo->failed_steps = S.failed_steps;
        O->evo->last_step = S.last_step;
        memcpy(O->evo->y0, S.e_y0, n * sizeof(double));
        memcpy(O->evo->yerr, S.e_yerr, n * sizeof(double));
        memcpy(O->evo->dydt_in, S.e_dydt_in, n * sizeof(double));
        memcpy(O->evo->dydt_out, S.e_dydt_out, n * sizeof(double));
    }
    return EXDEX_OK;
}

#define HYBRID_STATE_SIZE sizeof(((ode *)0)->S)

const method_impl method_event = {"event", hybrid_alloc, NULL, hybrid_free, 0, 0, event_begin,
                                  hybrid_advance_ws, HYBRID_STATE_SIZE, hybrid_save, hybrid_restore, NULL};
const method_impl method_regularised = {"regularised", hybrid_alloc, NULL, hybrid_free, 0, 0,
                                        regularised_begin, hybrid_advance_ws, HYBRID_STATE_SIZE, hybrid_save,
                                        hybrid_restore, NULL};
