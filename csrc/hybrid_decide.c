/* hybrid_decide.c -- the decision of the hybrid methods (hybrid.h): the mode
 * after an event or at a segment start (decide_modes, the stop friction's
 * modes sf_decide), the contact set's tie rules and the projections onto the
 * contact set after a step. */
#include "hybrid.h"

/* A contact-set row whose separation was located at t and that the
 * decision there put back into the set, twice at the same time: at the
 * separation instant its force and gap acceleration both vanish, and the
 * complementarity solve at the decided state may return a force of
 * rounding size (lam > 0) with the guard lam G M^-1 G^T - gap acceleration
 * of rounding size below 0, which the next step then finds falling (the row
 * separates with the row still in the set: the step would be taken with a
 * violated guard and the row's gap unwatched, its stop no longer able to
 * act as an impact). The event's own answer stands: the row leaves the set
 * (its free gap guard watches it again; a row that still pushes comes back
 * by an impact at rate ~0); with frictional rows the friction groups and
 * modes of the rows left are decided again (hyb_sf_redecide). */
void hyb_set_tie_leaves(hyb *H, int r)
{
    int n = 0;
    for (int i = 0; i < H->ncs; i++)
        if (H->cs[i] != r) H->cs[n++] = H->cs[i];
    H->ncs = n;
}

static void planar_prune_set(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y);

/* The other tie: a free stop row whose gap crossing was located at t, twice
 * at the same time, with the decision leaving it free: a corner (or a face,
 * two corners) arriving at its stop tangentially (normal rate ~0, the
 * object sliding along it) and pressed into it, whose rate at the located
 * point is positive by up to the gap acceleration times the location
 * tolerance, above tol.rate, so that it neither takes an impact nor joins
 * the contact set, and the next step drives it into the stop. The event's
 * answer stands: every touching stop row (gap <= tol.touch) whose rate is
 * below zsw joins the set, where the complementarity solve keeps the rows
 * that push (planar_prune_set). */
void hyb_set_tie_joins(hyb *H, const double *y, double t)
{
    frame f;
    exdex_kinematics kin;
    unsigned char in[MAX_ROWS];
    if (hyb_frame_seg(H, t, &f, &kin)) return;
    memset(in, 0, (size_t)(H->ns * H->nv));
    for (int i = 0; i < H->ncs; i++)
        if (H->cs[i] < H->ns * H->nv) in[H->cs[i]] = 1;
    for (int r = 0; r < H->ns * H->nv && H->ncs < MAX_ROWS; r++) {
        double G[3], gd;
        if (in[r]) continue;
        if (contact_row_planar(H->m, &kin, r / H->nv, r % H->nv, y, y + 3, G, &gd, NULL) <= H->m->tol.touch &&
            fabs(gd) <= H->zsw)
            H->cs[H->ncs++] = r;
    }
    planar_prune_set(H, &f, &kin, y);
}

/* Keep in the planar contact set only the rows that push (lam > 0) under
 * the accelerations of the current (non-stick) mode at (t, y); in a lock
 * (stop_friction.h) the rows it holds: their forces are indeterminate, a row
 * without force in one split carries it in another, and they all hold (gap
 * acceleration 0) while the lock lasts. */
static void planar_prune_set(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    hyb_pads(H, y);
    double F[3], w[3], P[3], a[3], qdd[3], lam[MAX_ROWS];
    int n = 0;
    if (!H->ncs || H->mode == MODE_STICK) return;
    if (hyb_planar_friction(H, f, kin, y, F, w)) return;
    model_gen_of_patch(H->m, MODEL_CS(y[2]), w, P);
    for (int i = 0; i < 3; i++) a[i] = H->m->minv[i] * (F[i] + P[i]);
    unsigned lk = 0u;
    hyb_contact_acc_planar(H, kin, y, a, qdd, lam, NULL, &lk);
    for (int i = 0; i < H->ncs; i++)
        if (lam[i] > 0.0 || (lk >> i & 1u)) H->cs[n++] = H->cs[i];
    H->ncs = n;
}

/* ------------------------------------ planar frictional stops: modes */

/* In a lock of the current modes at (t, y) (S its problem): y's velocity
 * replaced by the one holding the lock's rows at rate 0 and its sticking
 * stops' slips at 0 (sf_lock_solve to tol.rate), provided the set's other
 * rows do not approach at it. Returns 1 if replaced. */
static int sf_lock_velocity(hyb *H, const frame *f, const exdex_kinematics *kin, double *y, const sf_set *S)
{
    double a[3], qdd[3], lamc[MAX_ROWS], C[SF_MAX_ROWS + SF_MAX_STOPS][3], hyb_rhs[SF_MAX_ROWS + SF_MAX_STOPS], v[3],
        Go[SF_MAX_ROWS][3], bo[SF_MAX_ROWS];
    unsigned lk = 0u;
    int k = 0, no = 0;
    if (hyb_sf_free_acc(H, f, kin, y, a) != EXDEX_OK) return 0;
    hyb_contact_acc_planar(H, kin, y, a, qdd, lamc, NULL, &lk);
    if (!lk) return 0;
    for (int i = 0; i < H->ncs && i < SF_MAX_ROWS; i++) {
        double G[3], gd;
        hyb_hrow_planar(H, kin, H->cs[i], y, y + 3, G, &gd, NULL);
        if (lk >> i & 1u) {
            memcpy(C[k], G, sizeof G);
            hyb_rhs[k++] = -(gd - ex_dot3(G, y + 3));
        } else {
            memcpy(Go[no], G, sizeof G);
            bo[no++] = -(gd - ex_dot3(G, y + 3));
        }
    }
    for (int j = 0; j < S->ng; j++) {
        if (!(S->has[j] && S->st[j].mu > 0.0 && H->fm[j] == SF_STICK)) continue;
        memcpy(C[k], S->st[j].T, sizeof C[k]);
        hyb_rhs[k++] = -S->tb[j];
    }
    if (!sf_lock_solve(k, (const double (*)[3])C, hyb_rhs, H->m->minv, H->m->tol.rate, v)) return 0;
    for (int i = 0; i < no; i++)
        if (!(ex_dot3(Go[i], v) >= bo[i] - H->m->tol.rate)) return 0;
    memcpy(y + 3, v, sizeof v);
    return 1;
}

/* The velocity of a planar object with sticking stops (H->fm SF_STICK,
 * not at rest) projected in the M metric onto their slips 0 (T v = -tb)
 * and the contact-set rows' no-approach G v >= -(gd - G v). In a lock
 * (stop_friction.h: more such rows than coordinates, dependent) the velocity is
 * the one that holds the lock's rows at rate 0 and its stops' slips at 0
 * (sf_lock_solve, to tol.rate), the set's other rows not approaching; the
 * projection of the dependent rows as inequality pairs would be
 * inconsistent by rounding. */
static void sf_project_stick(hyb *H, const frame *f, const exdex_kinematics *kin, double *y)
{
    sf_set S;
    double Gr[SF_MAX_ROWS + 2 * SF_MAX_STOPS][3], b[SF_MAX_ROWS + 2 * SF_MAX_STOPS],
        lam[SF_MAX_ROWS + 2 * SF_MAX_STOPS], v[3];
    int n = 0, stick = 0;
    if (H->mode == MODE_STICK || !H->ncs || hyb_sf_build(H, kin, y, &S) < 0) return;
    for (int k = 0; k < S.ng; k++) stick += S.has[k] && S.st[k].mu > 0.0 && H->fm[k] == SF_STICK;
    if (!stick) return;
    if (H->ncs + stick > 3 && sf_lock_velocity(H, f, kin, y, &S)) return;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double gd;
        hyb_hrow_planar(H, kin, r, y, y + 3, Gr[n], &gd, NULL);
        b[n] = -(gd - ex_dot3(Gr[n], y + 3));
        n++;
    }
    for (int k = 0; k < S.ng; k++) {
        if (!(S.has[k] && S.st[k].mu > 0.0 && H->fm[k] == SF_STICK)) continue;
        n = hyb_sf_slip_pair(&S, k, Gr, b, n);
    }
    if (ldp_project(H->m->minv, n, (const double (*)[3])Gr, b, y + 3, FQ_MIN, v, lam, &H->st->stop_iterations,
                    &H->st->warnings))
        memcpy(y + 3, v, sizeof v);
}

/* The problem of the contact set at (t, y) on the plate friction of the
 * current modes H->fm (hyb_sf_free_acc: in a small slip the plate friction
 * depends on them), solved with every group rolling (its modes decided by
 * the problem, stop_friction.h) into res. Returns 1 with a consistent mode,
 * 0 with none, -1 when the free acceleration failed (H->err). */
static int sf_solve_rolling(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, int ng,
                            sf_result *res)
{
    double a[3];
    int fs = hyb_sf_free_acc(H, f, kin, y, a);
    if (fs) {
        H->err = H->err ? H->err : fs;
        return -1;
    }
    for (int k = 0; k < ng; k++) H->fm[k] = SF_ROLL;
    return hyb_sf_solve_at(H, kin, y, a, res);
}

/* T9 in a small slip: its plate friction is the maximum-dissipation wrench
 * of the constrained slip acceleration, so it depends on the stop forces
 * and their modes. With the ellipsoid the plate is one more contact of the
 * problem, solved jointly with the stop rows (hyb_sf_solve_plate, every
 * group rolling): the first mode in stop_friction.h's order that is
 * consistent at its own plate wrench. With the exact surface (not an
 * sf_plate) a consistent mode is a fixed point of modes -> plate friction
 * (hyb_planar_friction's iteration) -> the problem's modes: the rolling
 * groups' modes (at most 3 of them) are searched in stop_friction.h's order
 * (per group stick, slide +, slide -, the first group fastest) and the
 * first that the problem decides again from its own plate friction is
 * kept; none (or more than 3 rolling groups): the modes the problem finds
 * with every group rolling, on the plate friction of that same problem.
 * Returns as sf_solve_rolling. */
static int sf_small_slip_modes(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y,
                               const sf_set *S, sf_result *res)
{
    static const int cand[3] = {SF_STICK, SF_SLIDE_P, SF_SLIDE_M};
    int roll[SF_MAX_STOPS], nroll = 0, ncand = 1;
    if (!H->m->ls_exact) {
        for (int k = 0; k < S->ng; k++) H->fm[k] = SF_ROLL;
        return hyb_sf_solve_plate(H, f, kin, y, res);
    }
    for (int k = 0; k < S->ng; k++)
        if (S->has[k] && S->st[k].mu > 0.0 && S->st[k].fm == SF_ROLL) roll[nroll++] = k;
    for (int i = 0; i < nroll && nroll <= 3; i++) ncand *= 3;
    for (int combo = 0; nroll <= 3 && combo < ncand; combo++) {
        int ok, same = 1;
        for (int k = 0; k < S->ng; k++) H->fm[k] = SF_ROLL;
        for (int i = 0, c = combo; i < nroll; i++, c /= 3) H->fm[roll[i]] = cand[c % 3];
        ok = sf_solve_rolling(H, f, kin, y, S->ng, res);
        if (ok <= 0) {
            if (ok < 0) return ok;
            continue;
        }
        for (int i = 0, c = combo; i < nroll; i++, c /= 3) same &= res->fm[roll[i]] == cand[c % 3];
        if (same) return 1;
    }
    if (!nroll) return 0;
    for (int k = 0; k < S->ng; k++) H->fm[k] = SF_ROLL;
    return sf_solve_rolling(H, f, kin, y, S->ng, res);
}

/* The stops' friction modes after decide_modes at (t, y) (every H->fm was
 * SF_ROLL during it; T9): at rest from each group's slip at rest tb; else
 * the mode that the acceleration-level problem finds (in a small slip:
 * sf_small_slip_modes), and a sticking stop's slip projected to 0. No
 * consistent mode (Painleve, or a small slip whose coupled problem has
 * none): the stops frictionless, a warning. */
static void sf_decide(hyb *H, double t, double *y)
{
    frame f;
    exdex_kinematics kin;
    sf_set S;
    sf_result res;
    int nr, ok = 0, fs;
    if (!H->ncs) return;
    fs = hyb_frame_seg(H, t, &f, &kin);
    if (fs) {
        H->err = H->err ? H->err : fs;
        return;
    }
    nr = hyb_sf_build(H, &kin, y, &S);
    if (H->mode == MODE_STICK) {
        for (int k = 0; k < S.ng; k++)
            if (S.has[k] && S.st[k].mu > 0.0)
                H->fm[k] = fabs(S.tb[k]) <= H->zsw ? SF_STICK : S.tb[k] > 0.0 ? SF_SLIDE_P : SF_SLIDE_M;
        return;
    }
    if (nr >= 0)
        ok = H->mode == MODE_SLIP && H->small ? sf_small_slip_modes(H, &f, &kin, y, &S, &res)
                                              : sf_solve_rolling(H, &f, &kin, y, S.ng, &res);
    if (ok < 0) return;
    for (int k = 0; k < S.ng; k++) {
        if (!(S.has[k] && S.st[k].mu > 0.0)) continue;
        H->fm[k] = ok ? res.fm[k] : SF_NONE;
    }
    if (!ok) {
        H->st->warnings++;
        return;
    }
    sf_project_stick(H, &f, &kin, y);
}

/* ------------------------------------------------------------- decisions
 *
 * One decision per event. hyb_decide_event is the decision at a located
 * event (the driver calls nothing else there), hyb_decide the decision at
 * t = 0, at a switching time of the motion or the grip and at a regrip;
 * both end in decide_modes, which chooses the next mode of the whole
 * contact state at (t, y) in one pass of stages: the impacts of the rows
 * that close (planar: hyb_planar_impact_and_set, the impulse-level
 * problem with its friction; 1-DoF: impacts_1dof), the rows left in
 * contact at rate ~0 (planar: the contact set and the complementarity
 * solve of planar_prune_set; 1-DoF: contact_1dof), the plate friction at
 * the state reached (stick, slip, small slip: the stick test is
 * load_holds, one rule for every contact kind), and last the stop
 * friction's modes of the set (sf_decide, the acceleration-level problem
 * of stop_friction.h on the rows in contact).
 *
 * The policy for ties and hysteresis, every rule of it here:
 *   T1 (stick band) a load sticks iff its gauge (1-DoF |load|, planar
 *      |E^-1 w|, the exact surface's gauge, a stop contact's friction) is
 *      <= C_s (1 + FRICTION_BAND): a load sitting on the limit sticks
 *      (load_holds; hyb_planar_load_held, hybrid_laws.c, the same test of
 *      a planar load at rest); a 1-DoF rest against a stop that pushes
 *      leaves the plates exactly 0 (hyb_contact_forces), so it holds at
 *      every capacity, 0 (a released grip) included;
 *   T2 (small slip) a planar Coulomb slip below zsw is a small slip (its
 *      friction the maximum-dissipation wrench of the current load) unless
 *      the load can be held, then it stops (qd = 0); a small slip stays
 *      small up to SLIP_UP zsw (hysteresis: the band of the decision is
 *      SLIP_UP zsw while the slip is small, zsw otherwise), so an event of
 *      another guard within the band does not turn it into a slip whose
 *      decay guard would fire at once (planar_slow_slip); a small slip
 *      against contact-set rows that grows to SLIP_UP zsw (G_SMALL_GROWS)
 *      stops where its load can be held at rest on them
 *      (hyb_decide_event), else it slips on;
 *   T3 (rest instead of push) a slip that stopped against stops moving in
 *      B, that they would push on below SLIP_PUSH zsw, or that a set row
 *      held while its stop recedes, is a rest on every touching row
 *      (planar_stop_at_stops; its tol.rest_gap guard ends it);
 *   T4 (1-DoF stop at rest in B) the object slides with the stop in the
 *      direction of its acceleration, or rests against it where that
 *      acceleration gains less than tol.vzero over T (contact_1dof);
 *   T5 (zero stop force) a stop force exactly 0 keeps no contact
 *      (contact_1dof; planar: the rows with lam > 0, or held by a lock);
 *   T6 (jam) a frictional 1-DoF contact whose friction would turn the
 *      normal force around (D / Fq <= JAM_DIR) is taken frictionless,
 *      a warning (contact_1dof);
 *   T7 (repeated instant) a decision taken twice at the same time (same
 *      >= 1) keeps the event's own answer: a separating set row leaves
 *      the set (hyb_set_tie_leaves), a free stop row arriving
 *      tangentially joins it (hyb_set_tie_joins); a crossing that would
 *      round to the step's start is taken at the next representable time
 *      (the driver, before the decision);
 *   T8 (decayed slip) a slip decaying below zsw (G_SLIP_DECAYS) where
 *      the load cannot be held slips on as a small slip with its velocity
 *      kept; a slip turning against its reference direction above zsw is
 *      a turn (only the reference renews), below it a stop
 *      (hyb_decide_event);
 *   T9 (stop friction) the stops' friction modes are decided afresh from
 *      SF_ROLL at every decision: at rest from each group's slip (|tb| <=
 *      zsw sticks); else stop_friction.h's first consistent mode in its
 *      fixed order (every row carrying force first, stick before slide,
 *      locks last); in a small slip, whose plate friction depends on the
 *      stop forces, the plate is one more contact of that problem, solved
 *      jointly with the stop rows: the first mode in that order consistent
 *      at its own plate wrench (with the exact surface, a search of the
 *      modes' fixed points; sf_small_slip_modes); none: the stops
 *      frictionless, a warning. */

/* T1: a load of gauge g (in the units of H->caps) sticks. */
static int load_holds(const hyb *H, double g)
{
    return g <= H->caps * (1.0 + FRICTION_BAND);
}

static int planar_moving(const double *y)
{
    return y[3] != 0.0 || y[4] != 0.0 || y[5] != 0.0;
}

/* E u at the planar state y (u the patch slip of y's velocity). */
static void planar_eu(const hyb *H, const double *y, double eu[3])
{
    double u[3];
    model_patch_slip(H->m, MODEL_CS(y[2]), y + 3, u);
    for (int i = 0; i < 3; i++) eu[i] = H->m->e[i] * u[i];
}

/* T2: a planar Coulomb slip (not known to have stopped) below the decision's
 * band. Returns 1 when it is held (qd to be set to 0), 2 when it was decided
 * a small slip, 0 when it is not below the band. */
static int planar_slow_slip(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    double band = H->mode == MODE_SLIP && H->small ? SLIP_UP * H->zsw : H->zsw, eu[3];
    planar_eu(H, y, eu);
    if (sqrt(ex_dot3(eu, eu)) >= band) return 0;
    if (hyb_planar_load_held(H, f, kin, y)) return 1;
    H->mode = MODE_SLIP;
    H->small = 1;
    planar_prune_set(H, f, kin, y);
    return 2;
}

/* T3: a planar slip stopped (qd = 0) at (t, y) in a scene with stops or
 * obstacles: the stops moving in B push it on at their own speed (the
 * plastic impact on v = 0). If that slip is below SLIP_PUSH zsw it would
 * soon count as stopped again (Zeno-like restarts); it is a rest instead,
 * on every touching row, which the tol.rest_gap guard ends once the stops
 * have moved (a drift below tol.rest_gap). The same for a touching stop
 * that recedes in B at a rate below SLIP_PUSH zsw (the slip that followed
 * it stopped): left out of the set, the load would push the object back
 * onto it at once, an impact at the same time, and so on. And for a slip
 * that stopped (below zsw) while a contact-set row held it, when that
 * row's stop recedes faster and friction alone cannot hold the load
 * (hyb_planar_set_recedes: the object followed the stop, pushing on it):
 * at rest the row would separate at once and the load drive the object
 * back onto it, an impact every few hundred ns; the rest on the touching
 * rows lags the stop by at most tol.rest_gap before its guard ends it, as
 * for a slow recession. */
static void planar_stop_at_stops(hyb *H, const frame *f, const exdex_kinematics *kin, double t, double *y)
{
    const exdex_model *m = H->m;
    double ysv[NSRC_MAX], eu[3], Ga[MAX_ROWS][3], ga[MAX_ROWS], gda[MAX_ROWS];
    int recede = hyb_planar_set_recedes(H, f, kin, y), ra[MAX_ROWS], na;
    memcpy(ysv, y + 9, (size_t)(H->ns + H->no) * sizeof *ysv);
    hyb_planar_impact_and_set(H, t, kin, y);
    planar_eu(H, y, eu);
    na = hyb_hrow_all_planar(H, kin, y, ra, Ga, ga, gda);
    if (!planar_moving(y))
        for (int i = 0; i < na && !recede; i++)
            if (ga[i] <= m->tol.touch && gda[i] > m->tol.rate && gda[i] < SLIP_PUSH * H->zsw) recede = 1;
    if (!recede && !(planar_moving(y) && sqrt(ex_dot3(eu, eu)) < SLIP_PUSH * H->zsw)) return;
    memcpy(y + 9, ysv, (size_t)(H->ns + H->no) * sizeof *ysv);
    y[3] = y[4] = y[5] = 0.0;
    H->ncs = 0;
    na = hyb_hrow_all_planar(H, kin, y, ra, Ga, ga, NULL);
    for (int i = 0; i < na; i++)
        if (ga[i] <= m->tol.touch) H->cs[H->ncs++] = ra[i];
}

/* A planar Coulomb object at rest at (t, y) (qd = 0) that its load does not
 * hold: it starts to slip, a small slip, in the direction of the slip
 * acceleration (the maximum-dissipation solve of the limit surface for an
 * infinitesimal step, limitsurf_step; against stops along the constrained
 * acceleration of the friction just found). F: the generalized load at rest. */
static void planar_slip_start(hyb *H, const frame *f, const exdex_kinematics *kin, double *y, const double F[3])
{
    const exdex_model *m = H->m;
    double wF[3], b[3];
    exdex_friction_result res;
    int st;
    model_patch_of_gen(m, MODEL_CS(y[2]), F, wF);
    ex_mulmv3(b, model_prep(m)->W, wF);
    st = limitsurf_step(&m->ls, model_prep(m), b, H->cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &res);
    if (st) {
        H->err = H->err ? H->err : st;
        return;
    }
    H->mode = MODE_SLIP;
    H->small = 1;
    for (int i = 0; i < 3; i++) H->uref[i] = m->e[i] * res.u[i];
    if (H->ncs) {
        double P[3], a[3], qdd[3], lam[MAX_ROWS], ua[3];
        model_gen_of_patch(m, MODEL_CS(y[2]), res.p, P);
        for (int i = 0; i < 3; i++) a[i] = m->minv[i] * (F[i] + P[i]);
        hyb_contact_acc_planar(H, kin, y, a, qdd, lam, NULL, NULL);
        model_patch_slip(m, MODEL_CS(y[2]), qdd, ua);
        for (int i = 0; i < 3; i++) H->uref[i] = m->e[i] * ua[i];
        planar_prune_set(H, f, kin, y);
    }
}

/* The planar decision (decide_modes' stages in order). */
static void decide_planar(hyb *H, const frame *f, const exdex_kinematics *kin, double t, double *y, int vzero)
{
    const exdex_model *m = H->m;
    double F[3], w[3], zero[3] = {0, 0, 0}, g;
    if (H->ns || H->no) {
        hyb_planar_unpenetrate(H, kin, y);
        hyb_planar_impact_and_set(H, t, kin, y);
    }
    if (H->law == LAW_SMOOTH) {
        H->mode = MODE_FREE;
        planar_prune_set(H, f, kin, y);
        return;
    }
    if (!vzero && planar_moving(y)) {
        int slow = planar_slow_slip(H, f, kin, y);
        if (slow == 2) return;
        vzero = slow == 1;
    }
    if (vzero) {
        y[3] = y[4] = y[5] = 0.0;
        if (H->ns || H->no) planar_stop_at_stops(H, f, kin, t, y);
    }
    H->small = 0;
    if (planar_moving(y)) {
        H->mode = MODE_SLIP;
        planar_eu(H, y, H->uref);
        planar_prune_set(H, f, kin, y);
        return;
    }
    model_force_planar(m, f, y, zero, F);
    if (H->ncs) {
        double lam[MAX_ROWS];
        g = hyb_planar_rest(H, kin, y, F, w, lam);
    } else {
        double mF[3] = {-F[0], -F[1], -F[2]};
        model_patch_of_gen(m, MODEL_CS(y[2]), mF, w);
        g = model_ls_gauge(m, w);
    }
    if (load_holds(H, g))
        H->mode = MODE_STICK;
    else
        planar_slip_start(H, f, kin, y, F);
}

/* 1-DoF impacts: a touching stop row approached by the object stops it
 * (plastic, like the implicit step), the most approaching row first, at
 * most 3 passes (a third: stops pinch the object, a warning); the normal
 * impulse is counted in the stop's force integral. Returns 1 if any. */
static int impacts_1dof(hyb *H, double t, const exdex_kinematics *kin, double q, double *y, const int *rk,
                        const int *rj, int nr)
{
    const exdex_model *m = H->m;
    int any = 0;
    for (int pass = 0; pass < 3 && nr; pass++) {
        int kb = -1, jb = -1;
        double worst = -m->tol.rate, vn, ln;
        crow cb;
        for (int r = 0; r < nr; r++) {
            double rate;
            crow c;
            hyb_hrow_1dof(H, kin, rk[r], rj[r], q, &c);
            if (c.F > m->tol.touch || !(fabs(c.Fq) > m->tol.fq_min)) continue;
            rate = c.Fq * y[1] + c.Ft;
            if (rate < worst) {
                worst = rate;
                kb = rk[r];
                jb = rj[r];
                cb = c;
            }
        }
        if (kb < 0) break;
        vn = -cb.Ft / cb.Fq;
        ln = hyb_impact_impulse_1dof(H, kin, kb, jb, q, &cb, y[1], vn);
        y[3 + kb] += ln;
        method_note_impact(H->st, t, kb, ln);
        y[1] = vn;
        any = 1;
        if (pass == 2) H->st->warnings++; /* stops pinch the object */
    }
    return any;
}

/* 1-DoF contact with the touching stop row (k, j) at rate ~0: taken (mode
 * contact, y onto the constraint by Newton on F(q, t) = 0) iff its stop force
 * is > 0 (T5) and, at rest (s = 0), its friction holds (T1). The slip
 * direction along the stop (T4), the stop friction's sign ss opposing the
 * vertex's slip along the stop (located guards put a reversal just past
 * its zero: the new sign) and the jam (T6). Returns 1 if taken; else the
 * slip direction and the stop friction are left as they were (ck, cj
 * name the row tried last). */
static int contact_1dof(hyb *H, const frame *f, const exdex_kinematics *kin, int k, int j, double *y, int vzero)
{
    const exdex_model *m = H->m;
    double q = y[0], rate, v, Q, R, fr, lam, s_old = H->s, sl, T = 0.0;
    crow c;
    hyb_hrow_1dof(H, kin, k, j, q, &c);
    if (c.F > m->tol.touch || !(fabs(c.Fq) > m->tol.fq_min)) return 0;
    rate = c.Fq * y[1] + c.Ft;
    if (fabs(rate) > m->tol.rate) return 0;
    v = -c.Ft / c.Fq;
    if (H->law == LAW_COULOMB) {
        if (fabs(v) > m->tol.vzero && !vzero) {
            H->s = v > 0 ? 1.0 : -1.0;
        } else {
            /* T4: the stop at rest in B. An acceleration that gains less
             * than tol.vzero of speed over the time scale T counts as 0: a
             * stop fixed in B (a gripper moving along it) has Ftt of a few
             * ulps, whose sign must not choose a sliding contact (kinetic
             * friction of a sign set by rounding, the rest ending at C
             * instead of C_s); a real acceleration that small reaches
             * tol.vzero, where the rest's guard decides again, after at
             * least T */
            double a = hyb_contact_qdd(&c, 0.0), a0 = m->tol.vzero / m->scale.T;
            H->s = a > a0 ? 1.0 : a < -a0 ? -1.0 : 0.0;
            v = 0.0;
        }
    }
    Q = model_force_1dof(m, f, q, v);
    /* a rest (s = 0): the stop's acceleration counts as 0 (T4), the load is
     * the one at rest that the stick test and the rest's guard use */
    R = H->law == LAW_COULOMB && H->s == 0.0 ? -Q : H->M * hyb_contact_qdd(&c, v) - Q;
    H->ck = k;
    H->cj = j;
    H->ss = 0.0;
    H->jam = 0.0;
    if (model_source_mu(m, k) > 0.0) {
        sl = hyb_contact_slip_1dof(H, kin, q, v, &T);
        H->ss = sl > 0.0 ? 1.0 : sl < 0.0 ? -1.0 : 0.0;
        if (H->ss != 0.0 && !(hyb_contact_dir(H, &c, T) / c.Fq > JAM_DIR)) {
            H->jam = H->ss;
            H->ss = 0.0;
            H->st->warnings++;
        }
    }
    hyb_contact_forces(H, &c, T, R, v, &fr, &lam);
    if (lam > 0.0 && (H->law == LAW_SMOOTH || H->s != 0.0 || load_holds(H, fabs(fr)))) {
        H->mode = MODE_CONTACT;
        for (int it = 0; it < ROW_NEWTON_MAX && fabs(c.F) > 0.0; it++) {
            double dq = c.F / c.Fq;
            q -= dq;
            hyb_hrow_1dof(H, kin, k, j, q, &c);
            H->st->stop_iterations++;
            if (fabs(dq) <= ROW_NEWTON_TOL * (m->scale.q + fabs(q))) break;
        }
        y[0] = q;
        y[1] = (H->law == LAW_COULOMB && H->s == 0.0) ? 0.0 : -c.Ft / c.Fq;
        return 1;
    }
    H->s = s_old;
    H->ss = 0.0;
    H->jam = 0.0;
    return 0;
}

/* The 1-DoF decision (decide_modes' stages in order): impacts, a contact
 * with a touching stop, else the plate friction alone: a slip on in the
 * sign of qd, or from rest a stick (T1) or a slip in the sign of the load. */
static void decide_1dof(hyb *H, const frame *f, const exdex_kinematics *kin, double t, double *y, int vzero)
{
    int rk[MAX_ROWS], rj[MAX_ROWS], nr;
    double Q0;
    if (vzero && H->mode != MODE_CONTACT) y[1] = 0.0;
    nr = (H->ns || H->no) ? hyb_hrow_all_1dof(H, kin, y[0], y + 1, rk, rj) : 0;
    if (impacts_1dof(H, t, kin, y[0], y, rk, rj, nr)) vzero = 0;
    for (int r = 0; r < nr; r++)
        if (contact_1dof(H, f, kin, rk[r], rj[r], y, vzero)) return;
    if (H->law == LAW_SMOOTH) {
        H->mode = MODE_FREE;
        return;
    }
    if (y[1] != 0.0 && !vzero) {
        H->mode = MODE_SLIP;
        H->s = y[1] > 0 ? 1.0 : -1.0;
        return;
    }
    Q0 = model_force_1dof(H->m, f, y[0], 0.0);
    y[1] = 0.0;
    if (load_holds(H, fabs(Q0))) {
        H->mode = MODE_STICK;
        H->s = 0.0;
    } else {
        H->mode = MODE_SLIP;
        H->s = Q0 > 0 ? 1.0 : -1.0;
    }
}

/* Choose the mode at (t, y) (after an event, at a segment start, at t = 0).
 * vzero: qd is known to be 0 (a slip just stopped). May change y (impacts,
 * projection onto a stop). */
static void decide_modes(hyb *H, double t, double *y, int vzero)
{
    frame f;
    exdex_kinematics kin;
    int fs;
    hyb_pads(H, y);
    fs = hyb_frame_seg(H, t, &f, &kin);
    if (fs) {
        H->err = H->err ? H->err : fs;
        return;
    }
    if (H->ndof == 3)
        decide_planar(H, &f, &kin, t, y, vzero);
    else
        decide_1dof(H, &f, &kin, t, y, vzero);
}

/* decide_modes, and with frictional stops in a planar scene the stops'
 * friction modes after it (decided afresh at every decision: sf_decide). */
void hyb_decide(hyb *H, double t, double *y, int vzero)
{
    double v0[3] = {0, 0, 0};
    if (H->sfric)
        for (int k = 0; k < SF_MAX_STOPS; k++) H->fm[k] = SF_ROLL;
    H->sgn = 0;
    if (H->ndof == 3) memcpy(v0, y + 3, sizeof v0);
    decide_modes(H, t, y, vzero);
    if (hyb_smooth_two(H)) {
        /* the held regime: held in the band; a velocity changed by an
         * impact is a slip (kinetic beyond the band); else as it was */
        if (hyb_planar_slip_speed(H, y) <= H->eps)
            H->held = 1;
        else if (y[3] != v0[0] || y[4] != v0[1] || y[5] != v0[2])
            H->held = 0;
    }
    if (H->sfric && !H->err) {
        hyb_sf_fix_groups(H, t, y);
        sf_decide(H, t, y);
    }
}

/* The decision at an event located at t (the state y there, g the guard
 * that fell below 0, same: how often in a row an event fell at this time):
 * what the event's kind implies (a slip stopping, a small slip grown, a
 * slip decaying or turning: T2, T8; the held regime toggled; a jammed
 * sliding mode's arrest impulse, hyb_planar_jam_impulse), the
 * decision (hyb_decide), then the tie rules at a repeated instant (T7).
 * Returns EXDEX_OK or EXDEX_ENOCONV (the frame failed). */
int hyb_decide_event(hyb *H, double t, double *y, hyb_guard g, int same)
{
    int kind = g.kind, keep = 0, sep = -1, join = 0, vz;
    /* the first guard of 1-DoF slip (and of moving contact, the second) is
     * the slip speed: it stopped. A rest against a stop (1-DoF contact, s =
     * 0) ends at its first guard (the stop no longer pushes and the load
     * leaves the static capacity) from rest: the velocity it carries is the
     * stop's, below tol.vzero (its second guard), whose sign must not choose
     * a slip */
    vz = kind == G_SLIP_STOPS || kind == G_CONTACT_STOPS || kind == G_REST_LEAVES;
    if (kind == G_SMALL_STOPS || kind == G_SMALL_GROWS || kind == G_SLIP_TURNS || kind == G_SLIP_DECAYS) {
        /* planar: a small slip stops (G_SMALL_STOPS) or has grown to
         * SLIP_UP zsw (on as a (large) slip, no stop); a slip decays below
         * zsw or reverses: a stop, unless |E u| is still above zsw where E u
         * turned against its direction at the step start (a turn: on as a
         * slip with the new reference direction) */
        double eu[3];
        hyb_pads(H, y);
        planar_eu(H, y, eu);
        if (H->small) {
            vz = kind == G_SMALL_STOPS;
            if (kind == G_SMALL_GROWS) {
                /* T2 at its band's edge: a small slip against set rows
                 * stops where the load can be held at rest on them */
                H->small = 0;
                if (H->ncs) {
                    frame fk;
                    exdex_kinematics kk;
                    if (hyb_frame_seg(H, t, &fk, &kk)) return EXDEX_ENOCONV;
                    vz = hyb_planar_load_held(H, &fk, &kk, y);
                }
            }
        } else {
            vz = kind == G_SLIP_DECAYS || !(sqrt(ex_dot3(eu, eu)) > H->zsw);
            if (kind == G_SLIP_DECAYS) {
                /* T8: decayed below zsw: it stops where the load can be
                 * held; else it slips on as a small slip, velocity kept
                 * (what a stop dropped would persist where the friction
                 * cannot take it back, e.g. mu = 0) */
                frame fk;
                exdex_kinematics kk;
                if (hyb_frame_seg(H, t, &fk, &kk)) return EXDEX_ENOCONV;
                keep = !hyb_planar_load_held(H, &fk, &kk, y);
            }
        }
    }
    /* planar, a contact-set row separating (its guard lam G M^-1 G^T - gap
     * acceleration), a free stop row's gap */
    if (H->law == LAW_COULOMB && kind == G_SEPARATES) sep = g.row;
    if (H->law == LAW_COULOMB && H->mode == MODE_SLIP && !H->sfric && kind == G_GAP) join = 1;
    hyb_hold_set_rows(H, t, y);
    /* a sliding group's mode jammed (G_SF_JAM): the impact without
     * collision arrests its slip, then the decision at the new velocity */
    if (kind == G_SF_JAM) hyb_planar_jam_impulse(H, t, y);
    /* regularised, planar, two coefficients: the held regime's guard: it
     * broke away, or a slip slowed into the band */
    if (hyb_smooth_two(H) && kind == G_HELD) H->held = !H->held;
    if (keep)
        H->small = 1;
    else
        hyb_decide(H, t, y, vz);
    if (sep >= 0 && same >= 1 && H->mode == MODE_SLIP) {
        hyb_set_tie_leaves(H, sep);
        if (H->sfric) hyb_sf_redecide(H, t, y);
    }
    if (join && same >= 1 && H->mode == MODE_SLIP) hyb_set_tie_joins(H, y, t);
    return EXDEX_OK;
}

/* The stops' friction groups and modes of the contact set decided again at
 * (t, y) after the set changed outside decide (hyb_set_tie_leaves), as decide
 * makes them after decide_modes: groups afresh, every mode from SF_ROLL. */
void hyb_sf_redecide(hyb *H, double t, double *y)
{
    for (int k = 0; k < SF_MAX_STOPS; k++) H->fm[k] = SF_ROLL;
    hyb_sf_fix_groups(H, t, y);
    if (!H->err) sf_decide(H, t, y);
}

/* The rows of the planar contact set held as equalities (hyb_hold_set_rows):
 * given the n set rows G_i x >= b_i (in the set's order), appends
 * -G_i x >= -b_i for each row whose G_i is independent of the set rows
 * before it (in the M^-1 metric, a residual above 1e-6 of its norm; a row
 * within that of their span is implied by them to rounding, and its
 * mirror would make the rows inconsistent by rounding). Returns the new
 * count (n when the mirrors would exceed LDP_MAX_ROWS). */
static int set_row_equalities(const hyb *H, int n, double (*Gr)[3], double *b)
{
    double basis[3][3];
    int nb = 0, m = n;
    if (n + 3 > LDP_MAX_ROWS) return n;
    for (int i = 0; i < n && nb < 3; i++) {
        double u[3], n0, nn;
        for (int c = 0; c < 3; c++) u[c] = Gr[i][c] * sqrt(H->m->minv[c]);
        n0 = ex_dot3(u, u);
        for (int k = 0; k < nb; k++) {
            double p = ex_dot3(u, basis[k]);
            for (int c = 0; c < 3; c++) u[c] -= p * basis[k][c];
        }
        nn = ex_dot3(u, u);
        if (!(nn > SET_ROW_DEPENDENT * n0)) continue;
        for (int c = 0; c < 3; c++) basis[nb][c] = u[c] / sqrt(nn);
        nb++;
        for (int c = 0; c < 3; c++) Gr[m][c] = -Gr[i][c];
        b[m++] = -b[i];
    }
    return m;
}

/* The planar contact set at a decision (t, y) (an event, a switching time
 * of the motion or the grip before its jump, a regrip), outside a rest: a
 * set row pushes (lam > 0) until its separation, the located root of its
 * guard, so its exact gap and rate are 0 over the whole contact, up to and
 * at that root. The integrated state leaves them off by the integrator's
 * error (hyb_project_contact after each step removes only penetration and
 * approach), up to its tolerance, far above tol.touch and tol.rate, the
 * bands in which the decision takes a row as touching at rate 0
 * (hyb_planar_impact_and_set): it would find a pushing row separating and drop
 * it from the set, a free flight of that row with its friction lost until
 * an impact brings it back. Where a set row is beyond either band, q and
 * then v are projected (M metric) onto every set row at gap 0 and rate 0
 * (equalities; the rows implied by others one-sided); within both bands the
 * decision takes them so already and y is left as it is. The event method
 * in scenes with obstacles; a scene of stops alone, and the regularised
 * method, keep their state as integrated. */
void hyb_hold_set_rows(hyb *H, double t, double *y)
{
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    double Gr[MAX_ROWS + 3][3], b[MAX_ROWS + 3], lam[MAX_ROWS + 3], zero[3] = {0, 0, 0}, dq[3], v[3];
    int off = 0, n;
    if (H->law != LAW_COULOMB || H->ndof != 3 || !H->no || !H->ncs || H->mode == MODE_STICK) return;
    if (hyb_frame_seg(H, t, &f, &kin)) return;
    for (int i = 0; i < H->ncs && !off; i++) {
        double gd, g = hyb_hrow_planar(H, &kin, H->cs[i], y, y + 3, Gr[i], &gd, NULL);
        off = g > m->tol.touch || gd > m->tol.rate;
    }
    if (!off) return;
    for (int i = 0; i < H->ncs; i++) b[i] = -hyb_hrow_planar(H, &kin, H->cs[i], y, y + 3, Gr[i], NULL, NULL);
    n = set_row_equalities(H, H->ncs, Gr, b);
    if (ldp_project(m->minv, n, (const double (*)[3])Gr, b, zero, FQ_MIN, dq, lam, &H->st->stop_iterations, &H->st->warnings))
        for (int c = 0; c < 3; c++) y[c] += dq[c];
    if (contact_min_gap(m, &kin, y) < 0.0) hyb_planar_unpenetrate(H, &kin, y);
    for (int i = 0; i < H->ncs; i++) {
        double gd;
        hyb_hrow_planar(H, &kin, H->cs[i], y, y + 3, Gr[i], &gd, NULL);
        b[i] = -(gd - ex_dot3(Gr[i], y + 3));
    }
    n = set_row_equalities(H, H->ncs, Gr, b);
    if (ldp_project(m->minv, n, (const double (*)[3])Gr, b, y + 3, FQ_MIN, v, lam, &H->st->stop_iterations, &H->st->warnings))
        memcpy(y + 3, v, sizeof v);
}

/* After an accepted step in contact: back onto the constraint (the
 * integrated q drifts off it at the tolerance level). */
void hyb_project_contact(hyb *H, double t, double *y)
{
    frame f;
    exdex_kinematics kin;
    crow c;
    if (H->ndof == 3 && H->ncs) {
        /* planar: remove the penetration and the approach speed of the
         * contact-set rows (M-metric projections; a row drifting off its
         * stop is left to the accelerations) */
        double Gr[MAX_ROWS][3], b[MAX_ROWS], lam[MAX_ROWS], zero[3] = {0, 0, 0}, dq[3], v[3];
        if (hyb_frame_seg(H, t, &f, &kin)) return;
        for (int i = 0; i < H->ncs; i++) {
            int r = H->cs[i];
            b[i] = -hyb_hrow_planar(H, &kin, r, y, y + 3, Gr[i], NULL, NULL);
        }
        if (ldp_project(H->m->minv, H->ncs, (const double (*)[3])Gr, b, zero, FQ_MIN, dq, lam, &H->st->stop_iterations, &H->st->warnings))
            for (int c2 = 0; c2 < 3; c2++) y[c2] += dq[c2];
        /* the projection (a rotation about a set row) can push a row off
         * the set into its stop: then onto every row */
        if (contact_min_gap(H->m, &kin, y) < 0.0) hyb_planar_unpenetrate(H, &kin, y);
        for (int i = 0; i < H->ncs; i++) {
            int r = H->cs[i];
            double gd;
            hyb_hrow_planar(H, &kin, r, y, y + 3, Gr[i], &gd, NULL);
            b[i] = -(gd - ex_dot3(Gr[i], y + 3));
        }
        if (ldp_project(H->m->minv, H->ncs, (const double (*)[3])Gr, b, y + 3, FQ_MIN, v, lam, &H->st->stop_iterations, &H->st->warnings))
            memcpy(y + 3, v, sizeof v);
        if (H->sfric) sf_project_stick(H, &f, &kin, y);
        return;
    }
    if (H->ndof != 1 || H->mode != MODE_CONTACT) return;
    if (hyb_frame_seg(H, t, &f, &kin)) return;
    hyb_hrow_1dof(H, &kin, H->ck, H->cj, y[0], &c);
    for (int it = 0; it < ROW_NEWTON_MAX && fabs(c.F) > 0.0; it++) {
        double dq = c.F / c.Fq;
        y[0] -= dq;
        hyb_hrow_1dof(H, &kin, H->ck, H->cj, y[0], &c);
        H->st->stop_iterations++;
        if (fabs(dq) <= ROW_NEWTON_TOL * (H->m->scale.q + fabs(y[0]))) break;
    }
    if (!(H->law == LAW_COULOMB && H->s == 0.0)) y[1] = -c.Ft / c.Fq;
}

/* The plate's record of the mode fields. */
static hyb_row_state plate_state(const hyb *H)
{
    hyb_row_state p = {ROW_PLATE, -1, -1, -1, RS_SLIP, H->ndof == 1 ? H->s : 0.0};
    if (H->law == LAW_SMOOTH)
        p.mode = H->held && hyb_smooth_two(H) ? RS_HELD : RS_SMOOTH;
    else if (H->mode == MODE_STICK || (H->mode == MODE_CONTACT && H->s == 0.0))
        p.mode = RS_STICK;
    else if (H->ndof == 3 && H->small)
        p.mode = RS_SMALL_SLIP;
    else if (H->ndof == 3 && H->stiff)
        p.mode = RS_STIFF_SLIP;
    return p;
}

/* The mode of H as one array of row states (hybrid.h, hyb_row_state) into
 * rs (HYB_ROWS_MAX records); returns the count. */
int hyb_row_states(const hyb *H, hyb_row_state *rs)
{
    static const int group_mode[] = {[SF_ROLL] = RS_ROLL, [SF_STICK] = RS_GROUP_STICK, [SF_SLIDE_P] = RS_SLIDE,
                                     [SF_SLIDE_M] = RS_SLIDE, [SF_NONE] = RS_FRICTIONLESS};
    int n = 0;
    rs[n++] = plate_state(H);
    if (H->ndof == 1) {
        if (H->mode == MODE_CONTACT) {
            hyb_row_state c = {H->ck < H->ns ? ROW_STOP : ROW_OBSTACLE, H->cj, H->ck, -1,
                               H->jam != 0.0 ? RS_JAM : RS_CONTACT, H->jam != 0.0 ? H->jam : H->ss};
            rs[n++] = c;
        }
        return n;
    }
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        hyb_row_state c = {r < H->ns * H->nv ? ROW_STOP : ROW_OBSTACLE, r, hyb_hrow_src(H, r),
                           H->sgn > 0 ? H->sg[i] : -1, RS_CONTACT, 0.0};
        rs[n++] = c;
    }
    for (int k = 0; k < H->sgn; k++) {
        int used = -1, fm = H->fm[k];
        for (int i = 0; i < H->ncs && used < 0; i++)
            if (H->sg[i] == k) used = i;
        if (used < 0) continue;
        {
            /* a frictionless group keeps SF_ROLL (sf_decide sets the others) */
            int mode = model_source_mu(H->m, hyb_hrow_src(H, H->cs[used])) > 0.0 && fm >= SF_ROLL && fm <= SF_NONE
                           ? group_mode[fm]
                           : RS_FRICTIONLESS;
            hyb_row_state g = {ROW_GROUP, k, -1, k, mode, fm == SF_SLIDE_P ? 1.0 : fm == SF_SLIDE_M ? -1.0 : 0.0};
            rs[n++] = g;
        }
    }
    return n;
}
