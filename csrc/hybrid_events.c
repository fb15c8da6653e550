/* hybrid_events.c -- event location of the hybrid methods (hybrid.h): the
 * guard functions of each mode, their roots on the stepper's one-step map
 * (Brent), the extrema of guards inside a step and the within-step dip
 * searches (hyb_gap_dips, hyb_obst_dips, hyb_row_dip). */
#include "hybrid.h"

/* Guards of the stops' friction modes at (t, y) (planar, contact set not
 * empty) into g; returns their count. At rest, per frictional stop with
 * set rows: zsw - |tb| (static) or sigma tb - zsw (sliding past). Else +1
 * / -1 (a consistent mode exists or not), and per frictional stop with set
 * rows: sliding, sigma s; sticking, mu sum lam (1 + FRICTION_BAND) - |beta|, or
 * in a lock (stop_friction.h) its margin. */
static int sf_guards(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, hyb_guard *g)
{
    sf_set S;
    sf_result res;
    double a[3];
    int n = 0, ok = 0;
    int nr = hyb_sf_build(H, kin, y, &S);
    if (H->mode == MODE_STICK) {
        for (int k = 0; k < S.ng; k++) {
            if (!(S.has[k] && S.st[k].mu > 0.0)) continue;
            g[n++] = hg(G_SF_REST, k, 0, H->fm[k] == SF_STICK     ? H->zsw - fabs(S.tb[k])
                     : H->fm[k] == SF_SLIDE_P ? S.tb[k] - H->zsw
                     : H->fm[k] == SF_SLIDE_M ? -S.tb[k] - H->zsw
                                              : 1.0);
        }
        return n;
    }
    memset(&res, 0, sizeof res);
    if (nr >= 0 && hyb_sf_free_acc(H, f, kin, y, a) == EXDEX_OK) ok = hyb_sf_solve_at(H, kin, y, a, &res);
    g[n++] = hg(G_SF_CONSISTENT, -1, 0, ok ? 1.0 : -1.0);
    {
        /* a sliding group's friction turning its normal force around (a
         * jam, hyb_sf_jam_ratio): |D / D_0| reaches JAM_DIR */
        double r = ok ? hyb_sf_jam_ratio(H, &S, &res) : NAN;
        g[n++] = hg(G_SF_JAM, -1, 0, isnan(r) ? 1.0 : fabs(r) - JAM_DIR);
    }
    for (int k = 0; k < S.ng; k++) {
        if (!(S.has[k] && S.st[k].mu > 0.0)) continue;
        if (H->fm[k] == SF_SLIDE_P)
            g[n++] = hg(G_SF_SLIDES, k, 1, S.s[k]);
        else if (H->fm[k] == SF_SLIDE_M)
            g[n++] = hg(G_SF_SLIDES, k, -1, -S.s[k]);
        else if (H->fm[k] == SF_STICK && ok && res.lock)
            g[n++] = hg(G_SF_LOCK, k, 0, res.margin);
        else if (H->fm[k] == SF_STICK && ok)
            g[n++] = hg(G_SF_CONE, k, 0, S.st[k].mu * res.lsum[k] * (1.0 + FRICTION_BAND) - fabs(res.beta[k]));
        else
            g[n++] = hg(G_SF_IDLE, k, 0, 1.0);
    }
    return n;
}

/* ---------------------------------------------------------------- guards */

/* Planar guards of the obstacles' free rows at (kin, y), as the stops':
 * per polytope the gap of each outline vertex's row not in the contact set
 * and the smallest gap of its section rows not in the set (a length of the
 * scene when there are none: the count stays fixed between events), per
 * rod its row's gap unless in the set. Returns how many. */
static int obst_guards(const hyb *H, const exdex_kinematics *kin, const double *y, hyb_guard *g)
{
    const exdex_model *m = H->m;
    int code[MAX_ROWS], n = 0, base = H->ns * H->nv, no = 0;
    double gap[MAX_ROWS];
    no = orow_all(m, kin, y, NULL, 1, code, gap);
    if (m->disc_r > 0.0) {
        /* a disc: one row per obstacle, whose kind changes with its
         * feature: its gap while out of the contact set */
        for (int o = 0; o < no; o++) {
            int in = 0;
            for (int c = 0; c < H->ncs && !in; c++) in = H->cs[c] >= base && orow_obst(H->cs[c] - base) == o;
            g[n++] = hg(G_OBST_GAP, o, 0, in ? m->scale.L : gap[o]);
        }
        return n;
    }
    for (int o = 0, i = 0; o < H->no; o++) {
        int poly = m->def.obstacles[o].kind == EXDEX_OBSTACLE_POLYTOPE;
        double smin = m->scale.L;
        for (; i < no && orow_obst(code[i]) == o; i++) {
            int in = 0;
            for (int c = 0; c < H->ncs && !in; c++)
                in = H->cs[c] >= base && orow_pair(H->cs[c] - base) == orow_pair(code[i]);
            if (orow_kind(code[i]) == OROW_SECTION) {
                if (!in) smin = fmin(smin, gap[i]);
            } else if (!in) {
                g[n++] = hg(G_OBST_GAP, o, 0, gap[i]);
            }
        }
        if (poly) g[n++] = hg(G_OBST_GAP, o, 0, smin);
    }
    return n;
}

/* 1-DoF guards of the obstacles at (kin, q): per obstacle the smallest gap
 * of its rows (in contact with it: of its other rows, a length of the scene
 * when there are none). Returns how many. */
static int obst_guards_1dof(const hyb *H, const exdex_kinematics *kin, double q, hyb_guard *g)
{
    const exdex_model *m = H->m;
    int code[MAX_ROWS], n = 0, no, contact = H->mode == MODE_CONTACT;
    double gap[MAX_ROWS];
    no = orow_all(m, kin, &q, NULL, 0, code, gap);
    for (int o = 0, i = 0; o < H->no; o++) {
        int own = contact && H->ck == H->ns + o;
        double gmin = own ? m->scale.L : INFINITY;
        for (; i < no && orow_obst(code[i]) == o; i++)
            if (!(own && (m->disc_r > 0.0 || orow_pair(code[i]) == orow_pair(H->cj))) && gap[i] < gmin) gmin = gap[i];
        g[n++] = hg(G_OBST_GAP, o, 0, gmin);
    }
    return n;
}

/* The free gaps among the guards, in hyb_guards' order: planar, the gap of
 * every (stop, vertex) row outside the contact set; 1-DoF, each stop's
 * smallest vertex gap (the contact stop: its other vertices'). Functions of
 * (t, q) alone, so their rates along the motion are those of q' = qd. */
static int gap_guards(const hyb *H, const exdex_kinematics *kin, const double *y, hyb_guard *g)
{
    const exdex_model *m = H->m;
    int n = 0;
    if (H->ndof == 3) {
        unsigned char in[MAX_ROWS];
        double csv[2];
        const double *cs = hyb_stop_cs(H, y, csv);
        memset(in, 0, (size_t)(H->ns * H->nv));
        for (int i = 0; i < H->ncs; i++)
            if (H->cs[i] < H->ns * H->nv) in[H->cs[i]] = 1;
        for (int k = 0; k < H->ns; k++)
            for (int j = 0; j < H->nv; j++) {
                double G[3];
                if (!in[k * H->nv + j]) g[n++] = hg(G_GAP, k * H->nv + j, 0, contact_row_planar_cs(m, kin, k, j, y, cs, y + 3, G, NULL, NULL));
            }
        if (H->no) n += obst_guards(H, kin, y, g + n);
        return n;
    }
    for (int k = 0; k < H->ns; k++) {
        double q = y[0];
        if (H->mode == MODE_CONTACT && k == H->ck) {
            /* the other vertices of the contact stop: the gripper's
             * rotation (or the object's) can bring one of them onto
             * the stop while the contact vertex is held at 0 */
            double gmin = INFINITY;
            for (int j = 0; j < H->nv; j++)
                if (j != H->cj) gmin = fmin(gmin, contact_vertex_gap(m, kin, k, &q, j, NULL));
            if (H->nv > 1) g[n++] = hg(G_STOP_GAP, k, 0, gmin);
            continue;
        }
        g[n++] = hg(G_STOP_GAP, k, 0, contact_stop_gap(m, kin, k, q, NULL));
    }
    if (H->no) n += obst_guards_1dof(H, kin, y[0], g + n);
    return n;
}

/* The guards of the current mode at (t, y) into g (records, hybrid.h: each
 * value >= 0 while the mode holds), in the order the header lists; returns
 * how many (<= NG_MAX). */
int hyb_guards(hyb *H, double t, const double *y, hyb_guard *g)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    int n = 0, fs = hyb_frame_seg(H, t, &f, &kin);
    if (fs) {
        H->err = H->err ? H->err : fs;
        return 0;
    }
    if (H->ndof == 3) {
        if (H->law == LAW_SMOOTH) {
            /* one coefficient: no friction guard. Two: the held regime's
             * (hybrid.h), its first guard: held, it breaks away where
             * the slip is beyond the band and the object could not rest
             * in B (the load at rest leaves the static ellipsoid, or a
             * contact-set row's stop moves into it: a forced slip); not
             * held, it is held again where the slip slows into the band */
            if (hyb_smooth_two(H)) {
                double sig = hyb_planar_slip_speed(H, y);
                if (H->held) {
                    double gh = H->caps * (1.0 + FRICTION_BAND) - hyb_planar_load(H, &f, &kin, y), zero[3] = {0, 0, 0};
                    for (int i = 0; i < H->ncs; i++) {
                        double G[3], gd;
                        hyb_hrow_planar(H, &kin, H->cs[i], y, zero, G, &gd, NULL);
                        gh = fmin(gh, H->caps * (gd + m->tol.rate) / m->scale.V);
                    }
                    g[n++] = hg(G_HELD, -1, 0, fmax(H->eps - sig, gh));
                } else {
                    g[n++] = hg(G_HELD, -1, 0, sig - H->eps);
                }
            }
        } else if (H->mode == MODE_SLIP) {
            double u[3], eu[3], sig;
            model_patch_slip(m, MODEL_CS(y[2]), y + 3, u);
            for (int i = 0; i < 3; i++) eu[i] = m->e[i] * u[i];
            sig = sqrt(ex_dot3(eu, eu));
            if (H->small) {
                /* small slip growing from rest: it stops when the load
                 * falls back inside the ellipsoid (the stick guard with the
                 * sign reversed) and becomes a (large) slip at |E u| =
                 * SLIP_UP zsw */
                double F[3], w[3], zero[3] = {0, 0, 0}, lam[MAX_ROWS];
                model_force_planar(m, &f, y, zero, F);
                if (H->ncs) {
                    g[n++] = hg(G_SMALL_STOPS, -1, 0, hyb_planar_rest(H, &kin, y, F, w, lam) - H->cap * (1.0 + FRICTION_BAND));
                } else {
                    for (int i = 0; i < 3; i++) F[i] = -F[i];
                    model_patch_of_gen(m, MODEL_CS(y[2]), F, w);
                    g[n++] = hg(G_SMALL_STOPS, -1, 0, model_ls_gauge(m, w) - H->cap * (1.0 + FRICTION_BAND));
                }
                g[n++] = hg(G_SMALL_GROWS, -1, 0, SLIP_UP * H->zsw - sig);
            } else {
                /* the slip reverses (E u turns against its direction at
                 * the start of the step: a stop, or a turn when |E u| is
                 * large there) or decays below zsw (a slip dying out,
                 * against stops too, without reversing) */
                g[n++] = hg(G_SLIP_TURNS, -1, 0, ex_dot3(eu, H->uref));
                g[n++] = hg(G_SLIP_DECAYS, -1, 0, sig - H->zsw);
            }
        } else {
            double F[3], w[3], zero[3] = {0, 0, 0}, lam[MAX_ROWS];
            model_force_planar(m, &f, y, zero, F);
            if (H->ncs) {
                g[n++] = hg(G_STICK_LEAVES, -1, 0, H->caps * (1.0 + FRICTION_BAND) - hyb_planar_rest(H, &kin, y, F, w, lam));
            } else {
                for (int i = 0; i < 3; i++) F[i] = -F[i];
                model_patch_of_gen(m, MODEL_CS(y[2]), F, w);
                g[n++] = hg(G_STICK_LEAVES, -1, 0, H->caps * (1.0 + FRICTION_BAND) - model_ls_gauge(m, w));
            }
        }
        if (H->ns || H->no) {
            /* stops: free rows, their gap (impact when it reaches 0); rows of
             * the contact set, lam_i G_i M^-1 G_i^T - gap acceleration_i (> 0
             * while the row pushes, < 0 once it separates) */
            n += gap_guards(H, &kin, y, g + n);
            if (H->ncs && H->mode == MODE_STICK) {
                /* at rest against stops that move in B the contact ends
                 * once a set row's gap leaves +-tol.rest_gap */
                for (int i = 0; i < H->ncs; i++) {
                    int r = H->cs[i];
                    double G[3];
                    g[n++] = hg(G_REST_GAP, r, 0, m->tol.rest_gap - fabs(hyb_hrow_planar(H, &kin, r, y, y + 3, G, NULL, NULL)));
                }
            } else if (H->ncs) {
                double F[3], w[3], P[3], a[3], qdd[3], lam[MAX_ROWS], acc[MAX_ROWS];
                int st = hyb_planar_friction(H, &f, &kin, y, F, w);
                if (st) {
                    H->err = H->err ? H->err : st;
                    return 0;
                }
                model_gen_of_patch(m, MODEL_CS(y[2]), w, P);
                for (int i = 0; i < 3; i++) a[i] = m->minv[i] * (F[i] + P[i]);
                /* in a lock (stop_friction.h) the rows' forces are one split of
                 * indeterminate ones: the lock's margin (sf_guards) says
                 * when a row must separate or a stop slide */
                unsigned lk = 0u;
                hyb_contact_acc_planar(H, &kin, y, a, qdd, lam, acc, &lk);
                for (int i = 0; i < H->ncs; i++) {
                    int r = H->cs[i];
                    double G[3], d = 0.0;
                    hyb_hrow_planar(H, &kin, r, y, y + 3, G, NULL, NULL);
                    for (int c = 0; c < 3; c++) d += G[c] * G[c] * m->minv[c];
                    g[n++] = hg(G_SEPARATES, r, 0, (lk >> i & 1u) ? 1.0 : lam[i] * d - acc[i]);
                }
            }
            /* an obstacle row of the set: its feature stays the active one */
            for (int i = 0; i < H->ncs; i++)
                if (H->cs[i] >= H->ns * H->nv) g[n++] = hg(G_FEATURE, H->cs[i], 0, orow_feature_guard(m, &kin, H->cs[i] - H->ns * H->nv, y));
            if (H->sfric && H->ncs) n += sf_guards(H, &f, &kin, y, g + n);
        }
        return n;
    }
    {
        double q = y[0], v = y[1];
        if (H->mode == MODE_SLIP) {
            g[n++] = hg(G_SLIP_STOPS, -1, H->s, H->s * v);
        } else if (H->mode == MODE_STICK) {
            g[n++] = hg(G_STICK_LEAVES, -1, 0, H->caps * (1.0 + FRICTION_BAND) - fabs(model_force_1dof(m, &f, q, 0.0)));
        } else if (H->mode == MODE_CONTACT) {
            crow c;
            double R, fr, lam, T = 0.0;
            hyb_hrow_1dof(H, &kin, H->ck, H->cj, q, &c);
            if (H->ss != 0.0) hyb_contact_slip_1dof(H, &kin, q, v, &T);
            R = H->M * hyb_contact_qdd(&c, v) - model_force_1dof(m, &f, q, v);
            if (H->law == LAW_COULOMB && H->s == 0.0) {
                /* at rest against the stop (q and the stop at rest in B,
                 * |qd| <= tol.vzero): the load at rest, R = -Q(q, 0), the
                 * same number that the decision at its end tests against
                 * C_s (decide_modes), so a rest that ends there is not
                 * taken up again as a stick and left by the stick guard at
                 * once */
                R = -model_force_1dof(m, &f, q, 0.0);
                g[n++] = hg(G_REST_LEAVES, -1, 0, fmax(R / hyb_contact_dir(H, &c, T), H->caps * (1.0 + FRICTION_BAND) - fabs(R)));
                g[n++] = hg(G_REST_MOVES, -1, 0, m->tol.vzero - fabs(v));
            } else {
                hyb_contact_forces(H, &c, T, R, v, &fr, &lam);
                g[n++] = hg(G_CONTACT_PUSH, -1, 0, lam);
                if (H->law == LAW_COULOMB) g[n++] = hg(G_CONTACT_STOPS, -1, H->s, H->s * v);
            }
        }
        n += gap_guards(H, &kin, y, g + n);
        /* a frictional contact: its vertex keeps slipping the same way
         * along the stop (at a reversal the friction turns: decided again) */
        if (H->mode == MODE_CONTACT && H->ss != 0.0) {
            double T = 0.0;
            crow c;
            g[n++] = hg(G_CONTACT_SLIP, -1, H->ss, H->ss * hyb_contact_slip_1dof(H, &kin, q, v, &T));
            /* ... and its friction does not jam the contact (JAM_DIR) */
            hyb_hrow_1dof(H, &kin, H->ck, H->cj, q, &c);
            g[n++] = hg(G_CONTACT_JAM, -1, H->ss, hyb_contact_dir(H, &c, T) / c.Fq - JAM_DIR);
        }
        if (H->mode == MODE_CONTACT && H->jam != 0.0) {
            /* taken frictionless at a jam: until the slip reverses or its
             * friction would no longer jam the contact */
            double T = 0.0;
            crow c;
            g[n++] = hg(G_JAM_SLIP, -1, H->jam, H->jam * hyb_contact_slip_1dof(H, &kin, q, v, &T));
            hyb_hrow_1dof(H, &kin, H->ck, H->cj, q, &c);
            g[n++] = hg(G_JAM_ENDS, -1, H->jam, JAM_DIR - (c.Fq - model_source_mu(m, H->ck) * H->jam * T) / c.Fq);
        }
        /* in contact with an obstacle row: its feature stays the active one */
        if (H->mode == MODE_CONTACT && H->ck >= H->ns) g[n++] = hg(G_FEATURE, H->cj, 0, orow_feature_guard(m, &kin, H->cj, &q));
    }
    return n;
}

/* The stepper's one-step map from (t0, y0) over tau, into out. The
 * right-hand side at (t0, y0), the map's first stage, is evaluated once
 * per step (O->f0: the maps of one step all start from its start, in one
 * mode) and given to the stepper as its input derivative. */
int hyb_one_step(ode *O, double t0, const double *y0, double tau, double *out)
{
    size_t ny = O->sys.dimension;
    memcpy(out, y0, ny * sizeof *out);
    if (tau <= 0.0) return GSL_SUCCESS;
    O->maps++;
    if (!(O->f0_ok && O->f0_t == t0 && !memcmp(O->f0_y, y0, ny * sizeof *y0))) {
        int s = GSL_ODEIV_FN_EVAL(&O->sys, t0, y0, O->f0);
        O->f0_ok = 0;
        if (s != GSL_SUCCESS) return s;
        O->f0_t = t0;
        memcpy(O->f0_y, y0, ny * sizeof *y0);
        O->f0_ok = 1;
    }
    return gsl_odeiv2_step_apply(O->step, t0, tau, out, O->yerr, O->f0, NULL, &O->sys);
}

typedef struct rootctx {
    hyb *H;
    ode *O;
    double t0;
    const double *y0;
    int e;
    int fail;
    double off;   /* added to the function's value (a row's gap or guard e) */
} rootctx;

/* Gap of the (stop, vertex) row r = k nv + j at (t, y) (the value its stop
 * guard takes for that vertex); rate (may be NULL) gets d gap / dt. */
static double row_gap(hyb *H, double t, const double *y, int r, double *rate)
{
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    int k = r / H->nv, j = r % H->nv, fs = hyb_frame_seg(H, t, &f, &kin);
    if (fs) {
        H->err = H->err ? H->err : fs;
        return 0.0;
    }
    if (H->ndof == 3) {
        double G[3], gd;
        double g = contact_row_planar(m, &kin, k, j, y, y + 3, G, &gd, NULL);
        if (rate) *rate = gd;
        return g;
    }
    if (rate) {
        crow c;
        contact_row_1dof(m, &kin, k, j, y[0], &c);
        *rate = c.Fq * y[1] + c.Ft;
    }
    return contact_vertex_gap(m, &kin, k, y, j, NULL);
}

/* e >= 0: guard e; e < 0: the gap of row -1 - e (row_gap). */
static double root_fn(double tau, void *p)
{
    rootctx *c = p;
    hyb_guard g[NG_MAX];
    if (hyb_one_step(c->O, c->t0, c->y0, tau, c->O->ytmp) != GSL_SUCCESS) {
        c->fail = 1;
        return 0.0;
    }
    if (c->e < 0) return row_gap(c->H, c->t0 + tau, c->O->ytmp, -1 - c->e, NULL) + c->off;
    hyb_guards(c->H, c->t0 + tau, c->O->ytmp, g);
    return g[c->e].value + c->off;
}

/* Golden-section search for the extremum of guard e over [0, tau1] on the
 * stepper's map (dir +1: the minimum, -1: the maximum), at most 60
 * iterations, stopping early once the guard has the sign sought (dir +1:
 * g < 0, -1: g > 0). *tau, *g: the best point found. EXDEX_ENOCONV if the
 * stepper fails. */
static int extremum(rootctx *cp, double tau1, double dir, double *tau, double *g);

int hyb_guard_extremum(hyb *H, ode *O, double t0, const double *y0, double tau1, int e, double dir,
                       double *tau, double *g)
{
    rootctx c = {H, O, t0, y0, e, 0, 0.0};
    return extremum(&c, tau1, dir, tau, g);
}

/* hyb_guard_extremum on the function of c (a guard, or a row's gap plus c.off) */
static int extremum(rootctx *cp, double tau1, double dir, double *tau, double *g)
{
    rootctx c = *cp;
    hyb *H = c.H;
    double a = 0.0, b = tau1, r = 0.5 * (3.0 - sqrt(5.0));
    double x1 = a + r * (b - a), x2 = b - r * (b - a), f1 = dir * root_fn(x1, &c), f2 = dir * root_fn(x2, &c);
    for (int it = 0; it < GOLDEN_MAX && f1 >= 0.0 && f2 >= 0.0 && !c.fail && b - a > H->m->tol.root; it++) {
        if (f1 < f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = a + r * (b - a);
            f1 = dir * root_fn(x1, &c);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = b - r * (b - a);
            f2 = dir * root_fn(x2, &c);
        }
        H->st->solver_iterations++;
    }
    if (c.fail || H->err) return H->err ? H->err : EXDEX_ENOCONV;
    *tau = f1 < f2 ? x1 : x2;
    *g = dir * (f1 < f2 ? f1 : f2);
    return EXDEX_OK;
}

/* A free gap can dip below 0 and recover within one accepted step (a corner
 * of a turning outline grazing a stop): both end values are positive and
 * the impact would be missed. The gaps are functions of (t, q), so their
 * rates at the step's ends follow from q' = qd (one-sided differences over
 * DIP_DELTA of the step). A gap falling at the start and rising at the end
 * has an interior minimum; the cubic Hermite interpolant of the end values
 * and rates estimates it with an error O(h^4 max |g^(4)|), far below its end
 * values for a step the error control accepted, so a minimum estimated
 * below DIP_MARGIN of the smaller end value is searched for on the
 * stepper's map (hyb_guard_extremum) and, if negative, its crossing located
 * (the event is the first crossing, in [0, the minimum]). Candidates
 * improve *tau_best, *e_best. */

/* Smallest value on [0, h] of the cubic with values g0, g1 and slopes r0, r1
 * at the ends. */
static double hermite_min(double g0, double g1, double r0, double r1, double h)
{
    /* p(s) = g0 + r0 s + c2 s^2 + c3 s^3; p'(s) = r0 + 2 c2 s + 3 c3 s^2 */
    double c2 = (3.0 * (g1 - g0) / h - 2.0 * r0 - r1) / h, c3 = (r0 + r1 - 2.0 * (g1 - g0) / h) / (h * h);
    double a = 3.0 * c3, b = 2.0 * c2, c = r0, pmin = fmin(g0, g1), roots[2];
    int nr = 0;
    if (fabs(a) * h <= HERMITE_FLAT * fabs(b)) {
        if (b != 0.0) roots[nr++] = -c / b;
    } else {
        double disc = b * b - 4.0 * a * c;
        if (disc >= 0.0) {
            double sq = sqrt(disc), qq = -0.5 * (b + (b >= 0.0 ? sq : -sq));
            if (qq != 0.0) {
                roots[nr++] = qq / a;
                roots[nr++] = c / qq;
            }
        }
    }
    for (int i = 0; i < nr; i++)
        if (roots[i] > 0.0 && roots[i] < h) {
            double x = roots[i];
            pmin = fmin(pmin, g0 + x * (r0 + x * (c2 + x * c3)));
        }
    return pmin;
}

int hyb_gap_dips(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, int ng,
                 const hyb_guard *g0, const hyb_guard *g1, double *tau_best, int *e_best)
{
    /* at rest (Coulomb stick) q and qd are held, so every guard is a
     * function of t alone (the load, the stops' motion in B): all of them;
     * else the free gaps (one block, gap_guards) */
    int stick = H->law == LAW_COULOMB && H->mode == MODE_STICK;
    int a = 0, b = ng, nd = H->ndof, want = 0, fs = 0;
    double h = t1 - t0, d = DIP_DELTA * h, ya[NY_MAX], yb[NY_MAX];
    hyb_guard ga[NG_MAX], gb[2 * NG_MAX];
    double cap = H->cap, caps = H->caps;
    exdex_kinematics ka, kb;
    frame fa, fb;
    if (!stick) {
        for (a = 0; a < ng && !hyb_guard_is_gap(g0[a].kind); a++) {}
        for (b = a; b < ng && hyb_guard_is_gap(g0[b].kind); b++) {}
    }
    if (b <= a || !(h > 0.0)) return EXDEX_OK;
    for (int e = a; e < b; e++) want |= g0[e].value > 0.0 && g1[e].value >= 0.0;
    if (!want) return EXDEX_OK;
    memcpy(ya, y0, (size_t)H->ny * sizeof *ya);
    memcpy(yb, y1, (size_t)H->ny * sizeof *yb);
    for (int c = 0; c < nd; c++) {
        ya[c] += d * y0[nd + c];
        yb[c] -= d * y1[nd + c];
    }
    if (stick) {
        int na = hyb_guards(H, t0 + d, ya, ga), nb = hyb_guards(H, t1 - d, yb, gb);
        hyb_guards(H, t1, y1, gb + ng); /* H as after the step's own evaluation */
        if (H->err) return H->err;
        if (na != ng || nb != ng) return EXDEX_OK;
    } else {
        fs = hyb_frame_seg(H, t0 + d, &fa, &ka);
        if (!fs) fs = hyb_frame_seg(H, t1 - d, &fb, &kb);
        H->cap = cap; /* hyb_frame_seg reads the capacities at its time: keep t1's */
        H->caps = caps;
        if (fs) return fs;
        if (gap_guards(H, &ka, ya, ga + a) != b - a || gap_guards(H, &kb, yb, gb + a) != b - a) return EXDEX_OK;
    }
    for (int e = a; e < b; e++) {
        double v0 = g0[e].value, v1 = g1[e].value, r0 = (ga[e].value - v0) / d, r1 = (v1 - gb[e].value) / d, tm, gm, tau;
        int st;
        if (!(v0 > 0.0 && v1 >= 0.0 && r0 < 0.0 && r1 > 0.0)) continue;
        if (!(hermite_min(v0, v1, r0, r1, h) < DIP_MARGIN * fmin(v0, v1))) continue;
        st = hyb_guard_extremum(H, O, t0, y0, h, e, 1.0, &tm, &gm);
        if (st) return st;
        if (!(gm < 0.0)) continue;
        st = hyb_locate(H, O, t0, y0, 0.0, tm, e, &tau);
        if (st) return st;
        if (tau < *tau_best) {
            *tau_best = tau;
            *e_best = e;
        }
    }
    return EXDEX_OK;
}

/* A free obstacle row's gap is a largest distance over features (obstacle_rows.h):
 * continuous, but its rate jumps where the active feature changes. Within
 * one step an outline vertex can cross a face close to the section's corner
 * and leave the polytope again past the next face (it cuts through the
 * corner), or a section vertex an outline edge near its end: the gap falls
 * below 0 and is back above it at a feature switch, with no turn of a smooth
 * rate for hyb_gap_dips to see; from a touching start (a row the decision left
 * free at gap 0 with a small rate, which the load turns back) the end
 * values even look like a recovery. So where an obstacle row's active
 * feature differs at the step's ends, each obstacle guard that is not
 * violated at the end is searched for a value below -tol.touch (beyond the
 * touching band) on the stepper's map (golden section towards its minimum,
 * extremum); found, the first crossing of 0 before it is located, from the
 * step start if the guard is positive there, else from a point after it
 * where the guard is positive (searched towards its largest value); a guard
 * that stays <= 0 from the start up to that point is the decision's at t0,
 * not an event. Candidates improve *tau_best, *e_best. */
int hyb_obst_dips(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, int ng,
                  const hyb_guard *g0, const hyb_guard *g1, double *tau_best, int *e_best)
{
    const exdex_model *m = H->m;
    int c0[MAX_ROWS], c1[MAX_ROWS], n0, n1, changed, fs;
    double h = t1 - t0, cap = H->cap, caps = H->caps;
    exdex_kinematics k0, k1;
    frame f0, f1;
    if (!H->no || H->ndof != 3 || !(h > 0.0)) return EXDEX_OK;
    fs = hyb_frame_seg(H, t0, &f0, &k0);
    if (!fs) fs = hyb_frame_seg(H, t1, &f1, &k1);
    H->cap = cap; /* hyb_frame_seg reads the capacities at its time: keep t1's */
    H->caps = caps;
    if (fs) return fs;
    n0 = orow_all(m, &k0, y0, NULL, 1, c0, NULL);
    n1 = orow_all(m, &k1, y1, NULL, 1, c1, NULL);
    changed = n0 != n1;
    for (int i = 0; i < n0 && !changed; i++) changed = c0[i] != c1[i];
    if (!changed) return EXDEX_OK;
    for (int e = 0; e < ng; e++) {
        rootctx c = {H, O, t0, y0, e, 0, m->tol.touch};
        double tm, gm, lo = 0.0, tau;
        int st;
        if (g0[e].kind != G_OBST_GAP) continue;
        if (!(g1[e].value >= 0.0)) continue; /* violated at the end: the main loop's */
        st = extremum(&c, h, 1.0, &tm, &gm);
        if (st) return st;
        if (!(gm < 0.0)) continue;
        if (!(g0[e].value > 0.0)) {
            double tx, gx;
            st = hyb_guard_extremum(H, O, t0, y0, tm, e, -1.0, &tx, &gx);
            if (st) return st;
            if (!(gx > 0.0)) continue;
            lo = tx;
        }
        st = hyb_locate(H, O, t0, y0, lo, tm, e, &tau);
        if (st) return st;
        if (tau < *tau_best) {
            *tau_best = tau;
            *e_best = e;
        }
    }
    return EXDEX_OK;
}

/* Locate the root of guard e in [tau0, tau1] (g(tau0) > 0 > g(tau1)) with Brent;
 * returns the upper end of the final bracket (the guard is just violated). */
int hyb_locate(hyb *H, ode *O, double t0, const double *y0, double tau0, double tau1, int e, double *tau)
{
    rootctx c = {H, O, t0, y0, e, 0, 0.0};
    gsl_function F = {root_fn, &c};
    double lo = tau0, hi = tau1;
    int st = gsl_root_fsolver_set(O->root, &F, lo, hi);
    if (st) {
        /* no bracket: the one-step map does not reproduce at tau1 the
         * violated sign that the accepted step found there (the guard
         * within rounding of 0, the step's map and the evolved state
         * differing in the last bits): the event is at the step's end */
        if (c.fail) return EXDEX_ENOCONV;
        *tau = tau1;
        return EXDEX_OK;
    }
    for (int it = 0; it < BRENT_MAX; it++) {
        st = gsl_root_fsolver_iterate(O->root);
        if (st || c.fail) return EXDEX_ENOCONV;
        H->st->solver_iterations++;
        lo = gsl_root_fsolver_x_lower(O->root);
        hi = gsl_root_fsolver_x_upper(O->root);
        if (hi - lo <= H->m->tol.root) break;
    }
    /* The event is the first point where the guard is violated (g < 0):
     * Brent may stop on a point with g >= 0 (an exact zero included, where
     * the mode would be decided again unchanged and the switch be missed
     * until the next step). Step forward from it, doubling, to a point with
     * g < 0 (g(tau1) < 0 bounds the search). */
    {
        double d = fmax(H->m->tol.root, FEW_ULPS * DBL_EPSILON * fabs(t0 + hi)), d0 = d, lo2 = hi;
        for (int k = 0; k < DOUBLING_MAX && hi < tau1 && !(root_fn(hi, &c) < 0.0) && !c.fail; k++) {
            lo2 = hi;
            hi = fmin(tau1, hi + d);
            d *= 2.0;
        }
        /* Brent can stop on a zero that is no crossing: a gap lifted off
         * by an impact at the step start is 0 to rounding just after it
         * (g >= 0 there, and the crossing sought where it comes back down
         * later in the step). The doubling then passes over the crossing
         * by up to its last increment, a good part of the step: an
         * increment beyond 2^DOUBLING_EXACT d0 is bisected (g >= 0 at lo2,
         * < 0 at hi) to tol.root (a search that ends sooner leaves the
         * event at most 2^(DOUBLING_EXACT + 1) tol.root, ~6e-9 T, late). */
        if (hi - lo2 > ldexp(d0, DOUBLING_EXACT) && !c.fail && root_fn(hi, &c) < 0.0) {
            for (int it = 0; it < 2 * BRENT_MAX && hi - lo2 > H->m->tol.root && !c.fail; it++) {
                double mid = lo2 + 0.5 * (hi - lo2);
                if (!(mid > lo2 && mid < hi)) break;
                H->st->solver_iterations++;
                if (root_fn(mid, &c) < 0.0)
                    hi = mid;
                else
                    lo2 = mid;
            }
        }
    }
    if (c.fail) return EXDEX_ENOCONV;
    *tau = hi;
    return EXDEX_OK;
}

/* A free (stop, vertex) row of a 1-DoF scene can meet its stop and leave it
 * again within one step (planar rows are guards of their own, hyb_gap_dips; a
 * 1-DoF stop's guard is its least gap over the outline, whose end rates can
 * belong to another corner): a vertex sweeping past a stop that cuts its path only a little (a
 * turning object, a corner passing a stop at a shallow angle) has a gap that
 * is positive at both ends of the step and negative in between, which the
 * guards' end values do not show; the exact motion has an impact there.
 * Where a free row's gap is positive at both ends and its rate turns from
 * approaching (< 0) at t0 to receding (> 0) at t1, the gap has an interior
 * minimum. It is searched (golden section on the stepper's one-step map,
 * extremum) unless the cubic Hermite interpolant of the end values and
 * rates keeps its minimum above the touching band by at least its own depth
 * below the ends (the interpolant's error is of fourth order in the step,
 * the depth of second: a step that resolves the motion resolves the dip
 * to well within its depth); where the minimum falls below -tol.touch (a
 * penetration beyond the touching band: rows touching at either end, gap <=
 * tol.touch, are the impact and contact-set logic's, and a rounding-level
 * dip of a row left at 0 is no impact) the first crossing of 0 is located
 * (Brent, locate). A gap without such a turn over one step (two turns
 * within one step) is beyond the stepper's resolution of the motion and
 * not searched. *tau: the earliest crossing, INFINITY if none. Rows in the
 * contact set, and the 1-DoF contact row, are not free. */
int hyb_row_dip(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, double *tau)
{
    int nr = H->ns * H->nv;
    double touch = H->m->tol.touch;
    unsigned char in[MAX_ROWS];
    *tau = INFINITY;
    if (!H->ns || !(t1 > t0)) return EXDEX_OK;
    memset(in, 0, (size_t)nr);
    if (H->ndof == 3)
        for (int i = 0; i < H->ncs; i++) in[H->cs[i]] = 1;
    else if (H->mode == MODE_CONTACT && H->ck < H->ns)   /* an obstacle's contact row is not a stop row */
        in[H->ck * H->nv + H->cj] = 1;
    for (int r = 0; r < nr; r++) {
        double ga, gb, ra, rb, tm, gm, tr;
        int st;
        if (in[r]) continue;
        ga = row_gap(H, t0, y0, r, &ra);
        gb = row_gap(H, t1, y1, r, &rb);
        if (H->err) return H->err;
        if (!(ga > touch && gb > touch && ra < 0.0 && rb > 0.0)) continue;
        {
            /* screen: the cubic Hermite interpolant of (ga, ra, gb, rb)
             * has its minimum pm at least its own depth below the ends
             * (min(ga, gb) - pm) above the touching band: no search */
            double pm = hermite_min(ga, gb, ra, rb, t1 - t0);
            if (pm - touch >= fmin(ga, gb) - pm) continue;
        }
        {
            rootctx c = {H, O, t0, y0, -1 - r, 0, touch};
            st = extremum(&c, t1 - t0, 1.0, &tm, &gm);
        }
        if (st) return st;
        if (!(gm < 0.0)) continue;
        st = hyb_locate(H, O, t0, y0, 0.0, tm, -1 - r, &tr);
        if (st) return st;
        if (tr < *tau) *tau = tr;
    }
    return EXDEX_OK;
}
