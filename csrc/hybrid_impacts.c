/* hybrid_impacts.c -- impacts of the hybrid methods (hybrid.h): 1-DoF
 * impulses on a stop, planar plastic impacts with Coulomb friction at the
 * impulse level (stop_impulse.h), the hold of a face landing flat, positions
 * pushed back out of the stops, and the gripper's velocity jumps. */
#include "hybrid.h"

/* Normal impulse of a 1-DoF impact on row (k, j) (c its row at q): the
 * velocity v goes to vn = -Ft / Fq (no approach), plastic. With a
 * frictional stop the impact is Coulomb's at the impulse level (stop_impulse.h's
 * problem with no plate impulse: the plates' friction is bounded, its
 * impulse over the impact 0; the implicit step's impulse as the step
 * vanishes): M (vn - v) = lam Fq + beta T, beta = -mu lam sigma, sigma the
 * sign of the row's slip s = T vn + tb after the impact, so lam = M (vn -
 * v) / D with D = Fq - mu sigma T (hyb_contact_dir's). The velocity after the
 * impact is vn either way (one free coordinate); the friction changes the
 * impulse the stop takes. Where D Fq <= 0 no lam >= 0 is consistent (the
 * friction turns the impulse's generalized direction around: a jam, as
 * for the contact mode): the frictionless impulse and a warning. */
double hyb_impact_impulse_1dof(hyb *H, const exdex_kinematics *kin, int k, int j, double q, const crow *c,
                               double v, double vn)
{
    double mu = model_source_mu(H->m, k), T = 0.0, sl, D = c->Fq;
    if (mu > 0.0) {
        sl = hyb_row_slip_1dof(H, kin, k, j, q, vn, &T);
        if (sl != 0.0) D = c->Fq - mu * (sl > 0.0 ? 1.0 : -1.0) * T;
        if (!(D * c->Fq > 0.0)) {
            H->st->warnings++;
            D = c->Fq;
        }
    }
    return H->M * (vn - v) / D;
}

/* ------------------------------------------------- frictional impacts
 * An impact on frictional rows is plastic with Coulomb friction at the
 * rows: the impulse-level problem of stop_impulse.h (Stewart-Trinkle velocity
 * level, exact mode enumeration) over the vanishing duration of the impact,
 *     M (v+ - v) = sum_i (lam_i G_i + beta_i T_i),
 *     0 <= lam_i  _|_  G_i v+ - b_i >= 0    (b_i = -(gd_i - G_i v): no approach),
 *     |beta_i| <= mu_i lam_i, beta_i = -mu_i lam_i sign(s_i) where the
 *     post-impact slip s_i = T_i v+ + tb_i != 0,
 * with no plate impulse: the plates' friction force is bounded by the grip
 * force (cap = 0 in stop_impulse.h), so its impulse over the impact is 0. This
 * is the implicit step's impulse (stop_impulse.h with the plate term cap h) in
 * the limit of a vanishing step h, and the explicit method's (cap = 0 as
 * here). Frictionless rows make it the plastic M-metric projection
 * (ldp_project), which is solved first: where no frictional row carries an
 * impulse there, that projection is the answer, and the arithmetic is that
 * of frictionless stops bit for bit.
 * Friction applies at every approach speed: the impulses scale with the
 * approach, the law does not. The one touch that is not an impact is a
 * stop grazing a resting object within the rest's own tolerance
 * (sf_graze): there the rows join the rest as contacts, at the
 * acceleration level. */

/* Coulomb coefficient of planar row r at (kin, y) and, when > 0, its slip
 * row: s = T v + tb along the tangent in the plate plane (stop rows:
 * contact_slip_planar; obstacle rows: orow_slip, the tangent at the row's
 * point). */
static double hrow_friction_planar(const hyb *H, const exdex_kinematics *kin, int r, const double *y, double T[3],
                                   double *tb)
{
    double mu;
    int base = H->ns * H->nv;
    T[0] = T[1] = T[2] = 0.0;
    *tb = 0.0;
    mu = model_source_mu(H->m, hyb_hrow_src(H, r));
    if (!(mu > 0.0)) return mu;
    if (r < base)
        contact_slip_planar(H->m, kin, r / H->nv, r % H->nv, y, y + 3, T, tb, NULL);
    else
        orow_slip(H->m, kin, r - base, y, y + 3, T, tb, NULL);
    return mu;
}

/* A stop touching a resting object at a tangency of its path (event
 * method, v = 0 held exactly by a rest): is every row that the touching
 * stops drive into the object (approach b_i > tol.rate at v = 0) a graze
 * the rest already tolerates? At the held pose the gap is a function of t
 * alone, gap(t) = -b_i (t - t0) + gdd0_i (t - t0)^2 / 2 + ..., gdd0_i its
 * acceleration at v = 0: with gdd0_i > 0 the stop's path turns back after
 * reaching at most b_i^2 / (2 gdd0_i) into the held pose. Where that is
 * within tol.rest_gap for every such row, the touch is a contact of the
 * rest (the rows join its contact set, the rest split with the stops'
 * friction decides whether it holds, and the rest ends where a row's gap
 * leaves +-tol.rest_gap), not an impact: a rest against stops moving in B
 * holds q exactly while their gaps stay within +-tol.rest_gap, so a dip
 * below that is below the resolution of the held pose (an exact tangency,
 * rate 0, arrives at a rate up to sqrt(2 gdd0 tol.rest_gap) from the held
 * pose's offset). An impulse there would be the Coulomb impulse of an
 * approach that the held pose does not determine: near a Painleve
 * configuration of the stop's friction (the friction nearly cancelling the
 * normal impulse's effect on the gap) it moves the object at many times
 * the approach, where the exact motion stays at rest. A stop whose path
 * keeps approaching (gdd0_i <= 0: a stop moving at a constant or growing
 * rate into the object), or dips deeper, strikes it: the impact with
 * Coulomb friction, at every approach speed. Returns 1 for a graze. */
static int sf_graze(const hyb *H, const exdex_kinematics *kin, const double *y, int n, const int *rows, const double *b)
{
    const exdex_model *m = H->m;
    double zero[3] = {0.0, 0.0, 0.0};
    int any = 0;
    if (H->law != LAW_COULOMB || y[3] != 0.0 || y[4] != 0.0 || y[5] != 0.0) return 0;
    for (int i = 0; i < n; i++) {
        double G[3], gd = 0.0, gdd0 = 0.0;
        if (!(b[i] > m->tol.rate)) continue;
        hyb_hrow_planar(H, kin, rows[i], y, zero, G, &gd, &gdd0);
        if (!(gdd0 > 0.0 && b[i] * b[i] <= 2.0 * gdd0 * m->tol.rest_gap)) return 0;
        any = 1;
    }
    return any;
}

/* The planar impact with friction at (kin, y): rows (their G, bounds b as
 * hyb_planar_impact_and_set builds them: the touching rows), v and lam the
 * frictionless impact (ldp_project), replaced by the frictional one when a
 * frictional row carries an impulse in it and some row is approached
 * (b_i - G_i v > tol.rate: below that a row's rate is 0 to the method, as
 * for the contact set and the impact count, and the projection only
 * removes rounding). Where stop_impulse.h finds no consistent mode (none
 * among its candidates: fc_solve) the frictionless impact stands and a
 * warning is counted. Returns 1 if v and lam were replaced, 2 for a graze
 * of a rest (sf_graze: no impulse, v and lam untouched), else 0. */
static int sf_impact(hyb *H, const exdex_kinematics *kin, const double *y, int n, const int *rows,
                     const double (*Gr)[3], const double *b, double v[3], double *lam)
{
    const exdex_model *m = H->m;
    fc_row fr[MAX_ROWS];
    fc_problem p;
    fc_result res;
    unsigned char hint[MAX_ROWS];
    double lf[MAX_ROWS], bf[MAX_ROWS], T[3], tb;
    int fric = 0, approach = 0;
    for (int i = 0; i < n; i++) {
        if (lam[i] > 0.0 && hrow_friction_planar(H, kin, rows[i], y, T, &tb) > 0.0) fric = 1;
        if (b[i] - ex_dot3(Gr[i], y + 3) > m->tol.rate) approach = 1;
    }
    if (!fric || !approach) return 0;
    if (sf_graze(H, kin, y, n, rows, b)) return 2;
    if (n > LDP_MAX_ROWS / 2) {
        H->st->warnings++;
        return 0;
    }
    for (int i = 0; i < n; i++) {
        fc_row *r = &fr[i];
        memcpy(r->G, Gr[i], sizeof r->G);
        r->mu = hrow_friction_planar(H, kin, rows[i], y, r->T, &r->tb);
        r->rhs = b[i];
        /* at v = 0 a row can carry an impulse only where its bound is 0
         * (a stop at rest in B, or moving along its face): one the gripper
         * drives into the object excludes rest, one it leaves behind
         * carries nothing (as the implicit step's rows) */
        r->rest = b[i] > m->tol.rate ? -1 : b[i] >= -m->tol.rate ? 1 : 0;
        hint[i] = lam[i] > 0.0;
    }
    memset(&p, 0, sizeof p);
    p.n = 3;
    for (int c = 0; c < 3; c++) {
        p.Md[c] = 1.0 / m->minv[c];
        p.vs[c] = y[3 + c];
        p.A[c][c] = 1.0;
    }
    p.cap = p.cap_rest = 0.0;
    p.vscale = m->scale.V;
    p.vrest = m->tol.rate;
    p.nr = n;
    p.rows = fr;
    if (!fc_solve(&p, hint, v, NULL, lf, bf, &res)) {
        H->st->warnings++;
        return 0;
    }
    H->st->stop_iterations += (size_t)res.iters;
    memcpy(v, res.v, 3 * sizeof *v);
    for (int i = 0; i < n; i++) lam[i] = lf[i];
    return 1;
}

/* The hold of a face landing flat (hyb_planar_impact_and_set) on frictional
 * stops: the held rows' normal rates are taken as 0 below zsw; a held
 * frictional stop whose slip along it is below zsw there too is decided
 * sticking (sf_decide) and its slip projected to 0 on the contact set with
 * inequality rows (sf_project_stick), which can lift a corner of the face
 * just held flat again (the tangential impulse's torque) and restart the
 * cascade the hold ends. Both are the same band: the hold takes the slip
 * to 0 with the normal rates, in one M-metric projection (the held rows as
 * equality pairs G2 v = b2 and, per held frictional stop with |T v2 + tb|
 * <= zsw, T v = -tb at its first held row). v2 and lam2 (the normal pairs'
 * multipliers, first n2 entries) are replaced when that projection
 * succeeds with finite multipliers. */
static void sf_hold_stick(hyb *H, const exdex_kinematics *kin, const double *y, int n, const int *rows,
                          const double (*Gr)[3], const double *b, int n2, double (*G2)[3], double *b2, double *v2,
                          double *lam2)
{
    double G3[2 * MAX_ROWS + 2 * NSRC_MAX][3], b3[2 * MAX_ROWS + 2 * NSRC_MAX], lam3[2 * MAX_ROWS + 2 * NSRC_MAX], v3[3];
    int done[NSRC_MAX] = {0}, n3 = n2, add = 0;
    memcpy(G3, G2, (size_t)n2 * sizeof *G3);
    memcpy(b3, b2, (size_t)n2 * sizeof *b3);
    for (int i = 0; i < n; i++) {
        double T[3], tb, rate = ex_dot3(Gr[i], y + 3) - b[i];
        int src = hyb_hrow_src(H, rows[i]);
        if (rate > H->zsw || done[src]) continue;
        done[src] = 1;
        if (!(hrow_friction_planar(H, kin, rows[i], y, T, &tb) > 0.0)) continue;
        if (!(fabs(ex_dot3(T, v2) + tb) <= H->zsw)) continue;
        for (int c = 0; c < 3; c++) {
            G3[n3][c] = T[c];
            G3[n3 + 1][c] = -T[c];
        }
        b3[n3] = -tb;
        b3[n3 + 1] = tb;
        n3 += 2;
        add = 1;
    }
    if (!add || !ldp_project(H->m->minv, n3, (const double (*)[3])G3, b3, y + 3, FQ_MIN, v3, lam3,
                             &H->st->stop_iterations, &H->st->warnings))
        return;
    for (int i = 0; i < n3; i++)
        if (!isfinite(lam3[i])) return;
    memcpy(v2, v3, sizeof v3);
    memcpy(lam2, lam3, (size_t)n2 * sizeof *lam2);
}

/* Impacts of a planar object on the touching rows (gap <= tol.touch) at
 * (t, y): the plastic impact projects v onto G v >= -(gd - G v) (no
 * approach) in the M metric; with frictional rows carrying an impulse
 * there, the impact with Coulomb friction replaces it (sf_impact); the
 * impulses go into the stops' force integrals. Then the contact set: the
 * touching rows whose rate is ~0 and which push (lam > 0) under the
 * accelerations of the mode. */
void hyb_planar_impact_and_set(hyb *H, double t, const exdex_kinematics *kin, double *y)
{
    const exdex_model *m = H->m;
    double Gr[MAX_ROWS][3], b[MAX_ROWS], lam[MAX_ROWS], v[3], ga[MAX_ROWS], gda[MAX_ROWS];
    int rows[MAX_ROWS], n = 0, na = hyb_hrow_all_planar(H, kin, y, rows, Gr, ga, gda), graze = 0;
    for (int i = 0; i < na; i++) {
        if (ga[i] > m->tol.touch) continue;
        memcpy(Gr[n], Gr[i], sizeof Gr[n]);
        b[n] = -(gda[i] - ex_dot3(Gr[n], y + 3));
        rows[n++] = rows[i];
    }
    H->ncs = 0;
    if (!n) return;
    if (ldp_project(m->minv, n, (const double (*)[3])Gr, b, y + 3, FQ_MIN, v, lam, &H->st->stop_iterations, &H->st->warnings)) {
        double G2[2 * MAX_ROWS][3], b2[2 * MAX_ROWS], lam2[2 * MAX_ROWS], v2[3];
        if (H->sfric) graze = sf_impact(H, kin, y, n, rows, (const double (*)[3])Gr, b, v, lam) == 2;
        if (graze) {
            /* a graze of a rest (sf_graze): no impulse, the rows join the
             * rest's contact set */
            memcpy(v, y + 3, sizeof v);
            for (int i = 0; i < n; i++) lam[i] = 0.0;
        }
        double per_stop[NSRC_MAX] = {0};
        int n2 = 0, lift = 0;
        for (int i = 0; i < n; i++) {
            y[9 + hyb_hrow_src(H, rows[i])] += lam[i];
            /* an approached row (gap rate below -tol.rate) takes an impact */
            if (lam[i] > 0 && ex_dot3(Gr[i], y + 3) - b[i] < -m->tol.rate)
                per_stop[hyb_hrow_src(H, rows[i])] += lam[i];
        }
        for (int k = 0; k < H->ns + H->no; k++) method_note_impact(H->st, t, k, per_stop[k]);
        memcpy(y + 3, v, sizeof v);
        /* A plastic impact at one corner of a face that lands flat lifts
         * the other corner off, which falls back, impacts, lifts the first:
         * rates shrinking geometrically, events accumulating at a finite
         * time (Zeno). Once the lift-off rates are below zsw the touching
         * rows that would separate that slowly are held at rate 0 instead
         * (equality rows, an M-metric projection again): the face rests. */
        for (int i = 0; i < n; i++) {
            double rate = ex_dot3(Gr[i], y + 3) - b[i];
            if (rate > m->tol.rate && rate <= H->zsw) lift = 1;
        }
        for (int i = 0; lift && i < n; i++) {
            double rate = ex_dot3(Gr[i], y + 3) - b[i];
            if (rate > H->zsw) continue;
            for (int c = 0; c < 3; c++) {
                G2[n2][c] = Gr[i][c];
                G2[n2 + 1][c] = -Gr[i][c];
            }
            b2[n2] = b[i];
            b2[n2 + 1] = -b[i];
            n2 += 2;
        }
        if (lift && ldp_project(m->minv, n2, (const double (*)[3])G2, b2, y + 3, FQ_MIN, v2, lam2,
                                &H->st->stop_iterations, &H->st->warnings)) {
            /* The hold may pull a stop (the lifting corner of a face held
             * flat, or an object held between two stops while the other
             * stop pushes), but a hold that pushes nowhere is no contact
             * reaction: when no stop of this event gets a positive net
             * impulse (impact + hold), e.g. an object between two nearly
             * opposed stops both pulled, or a non-finite hold, the hold is
             * not applied: the plastic impact velocity stands and the
             * rows separate. */
            double net[NSRC_MAX] = {0};
            int pull = 1;
            for (int i = 0, r = 0; i < n; i++) {
                double rate = ex_dot3(Gr[i], y + 3) - b[i];
                net[hyb_hrow_src(H, rows[i])] += lam[i];
                if (rate > H->zsw) continue;
                net[hyb_hrow_src(H, rows[i])] += lam2[r] - lam2[r + 1];
                r += 2;
            }
            for (int k = 0; k < H->ns + H->no; k++)
                if (net[k] > 0.0) pull = 0;
            for (int k = 0; k < H->ns + H->no; k++)
                if (!isfinite(net[k])) pull = 1;
            if (!pull && H->sfric) sf_hold_stick(H, kin, y, n, rows, (const double (*)[3])Gr, b, n2, G2, b2, v2, lam2);
            for (int i = 0, r = 0; !pull && i < n; i++) {
                double rate = ex_dot3(Gr[i], y + 3) - b[i];
                if (rate > H->zsw) continue;
                y[9 + hyb_hrow_src(H, rows[i])] += lam2[r] - lam2[r + 1];
                r += 2;
            }
            if (!pull) memcpy(y + 3, v2, sizeof v2);
        }
    }
    for (int i = 0; i < n; i++) {
        double rate = ex_dot3(Gr[i], y + 3) - b[i];
        if (fabs(rate) <= m->tol.rate || (graze && rate < 0.0)) H->cs[H->ncs++] = rows[i];
    }
}

/* The impact without collision at a jam (the guard G_SF_JAM: a sliding
 * group's mode with |D / D_0| <= JAM_DIR, hyb_sf_jam_ratio). Approaching
 * D = 0 the mode's normal forces grow without bound; at D = 0 an impulse
 * along the sliding groups' forces (G_i - mu sigma T) leaves the set rows'
 * gap rates unchanged (that is what D = 0 says) and changes the slip, so
 * the rigid limit of the contact is an impulse, in impulse time, that
 * slides until the slip is 0 (the impact without collision). The
 * velocity-level step (the implicit and explicit methods) takes that
 * impulse in the step that reaches the jam at most step sizes, to the
 * first-order error of the step; at others its step lands on the jam with
 * a part of it, scattered with the step size (zoo-inputs 3478 and the C
 * test hybrid_impacts_jam_run_returns_with_the_implicit_methods_limit
 * give the figures). It is the velocity that holds the set rows'
 * gap rates >= their rates at v = 0 (no approach) and the slips of the
 * groups carrying force at 0 (sticking groups stay stuck), nearest to v in
 * the M metric (ldp_project: rows G_i v >= b_i, pairs T_k v = -tb_k): its
 * tangential impulse beta_k lies on the cone, |beta_k| = mu_k sum lam /
 * (1 - D / D_0) for one row, so within JAM_DIR of it at the located
 * event. Taken where each arrested sliding group's impulse opposes its
 * slip and |beta_k| (1 - JAM_DIR) <= mu_k sum lam (1 + FRICTION_BAND) (the
 * Coulomb impulse of the slide to rest); the normal impulses go into the
 * stops' force integrals and count as impacts. Else (no such impulse, a
 * failed projection) nothing changes and a warning is counted. Returns 1
 * when applied. */
int hyb_planar_jam_impulse(hyb *H, double t, double *y)
{
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    sf_set S;
    sf_result res;
    double a[3], G2[LDP_MAX_ROWS][3], b2[LDP_MAX_ROWS], lam2[LDP_MAX_ROWS], v[3], per_src[NSRC_MAX] = {0};
    int pair[SF_MAX_STOPS], n2 = 0, arrest = 0;
    if (H->ndof != 3 || !H->sfric || !H->ncs || H->ncs > SF_MAX_ROWS) return 0;
    hyb_pads(H, y);
    if (hyb_frame_seg(H, t, &f, &kin) || hyb_sf_build(H, &kin, y, &S) < 0) return 0;
    memset(&res, 0, sizeof res);
    if (hyb_sf_free_acc(H, &f, &kin, y, a) || !hyb_sf_solve_at(H, &kin, y, a, &res) ||
        isnan(hyb_sf_jam_ratio(H, &S, &res)) || H->ncs + 2 * S.ng > LDP_MAX_ROWS) {
        H->st->warnings++;
        return 0;
    }
    for (int i = 0; i < H->ncs; i++) {
        double gd = 0.0;
        hyb_hrow_planar(H, &kin, H->cs[i], y, y + 3, G2[n2], &gd, NULL);
        b2[n2] = -(gd - ex_dot3(G2[n2], y + 3));
        n2++;
    }
    for (int k = 0; k < S.ng; k++) {
        pair[k] = -1;
        if (!(S.has[k] && S.st[k].mu > 0.0 && res.lsum[k] > 0.0)) continue;
        if (res.fm[k] != SF_STICK && res.fm[k] != SF_SLIDE_P && res.fm[k] != SF_SLIDE_M) continue;
        pair[k] = n2;
        n2 = hyb_sf_slip_pair(&S, k, G2, b2, n2);
        arrest |= res.fm[k] != SF_STICK;
    }
    if (!arrest || !ldp_project(m->minv, n2, (const double (*)[3])G2, b2, y + 3, FQ_MIN, v, lam2,
                                &H->st->stop_iterations, &H->st->warnings)) {
        H->st->warnings++;
        return 0;
    }
    for (int k = 0; k < S.ng; k++) {
        double L = 0.0, beta, sg;
        if (pair[k] < 0 || res.fm[k] == SF_STICK) continue;
        for (int i = 0; i < H->ncs; i++)
            if (S.grp[i] == k) L += lam2[i];
        beta = lam2[pair[k]] - lam2[pair[k] + 1];
        sg = res.fm[k] == SF_SLIDE_P ? 1.0 : -1.0;
        if (!(L > 0.0 && sg * beta <= 0.0 && fabs(beta) * (1.0 - JAM_DIR) <= S.st[k].mu * L * (1.0 + FRICTION_BAND))) {
            H->st->warnings++;
            return 0;
        }
    }
    for (int i = 0; i < n2; i++)
        if (!isfinite(lam2[i])) {
            H->st->warnings++;
            return 0;
        }
    for (int i = 0; i < H->ncs; i++) {
        int src = hyb_hrow_src(H, H->cs[i]);
        y[9 + src] += lam2[i];
        per_src[src] += lam2[i];
    }
    for (int k = 0; k < H->ns + H->no; k++) method_note_impact(H->st, t, k, per_src[k]);
    memcpy(y + 3, v, sizeof v);
    return 1;
}

/* Positions back onto the stops at (t, y), when a row penetrates: the
 * M-metric projection of q onto G dq >= -gap of every row (a located impact
 * lies up to |gap rate| ROOT_TOL beyond its stop, a rest against a stop
 * moving in B up to REST_GAP). The rows that do not penetrate are
 * constraints too: projecting only the penetrating ones can turn the object
 * into a touching neighbour (a rotation about one corner pushes the next
 * corner in), by as much as it removes. */
void hyb_planar_unpenetrate(hyb *H, const exdex_kinematics *kin, double *y)
{
    double Gr[MAX_ROWS][3], b[MAX_ROWS], lam[MAX_ROWS], zero[3] = {0, 0, 0}, dq[3];
    int rows[MAX_ROWS], n = hyb_hrow_all_planar(H, kin, y, rows, Gr, b, NULL), pen = 0;
    for (int i = 0; i < n; i++) {
        if (b[i] < 0.0) pen = 1;
        b[i] = -b[i];
    }
    if (pen && ldp_project(H->m->minv, n, (const double (*)[3])Gr, b, zero, FQ_MIN, dq, lam, &H->st->stop_iterations, &H->st->warnings))
        for (int c = 0; c < 3; c++) y[c] += dq[c];
}

/* The pose reported at (t, y) (an output sample, the smallest gap): a
 * planar rest holds q exactly, also while a stop or an obstacle moving in B
 * (an obstacle is fixed in the world, so it moves in B with the gripper)
 * closes in on it (up to tol.rest_gap, where the rest ends); reported is
 * the held pose pushed out of the stops and obstacles (hyb_planar_unpenetrate,
 * the projection the decision at the rest's end makes), a function of q
 * and t alone. Projecting the
 * held q itself after every step would move it by the stop's travel over
 * each step: the rest's end, and the answer, would depend on where steps
 * end (the output grid among them). Any other mode: y as it is. */
const double *hyb_reported_pose(hyb *H, double t, const double *y, double *buf)
{
    frame f;
    exdex_kinematics kin;
    if (H->ndof != 3 || !(H->ns || H->no) || H->law != LAW_COULOMB || H->mode != MODE_STICK) return y;
    memcpy(buf, y, (size_t)H->ny * sizeof *y);
    if (!hyb_frame_seg(H, t, &f, &kin)) hyb_planar_unpenetrate(H, &kin, buf);
    return buf;
}

/* A gripper velocity jump at a switching time ts (exdex_motion_jumps: a
 * trapezoid without ramps, a sampled motion starting or ending at speed):
 * the object's relative velocity jumps as model_velocity_jump derives
 * (friction cannot oppose an impulse: the grip force is finite). */
int hyb_apply_jump(hyb *H, double ts, double *y)
{
    const exdex_model *m = H->m;
    exdex_kinematics k;
    double tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    int nj = exdex_motion_jumps(m->motion, tj, dv, dw), st;
    for (int j = 0; j < nj; j++) {
        if (tj[j] != ts) continue;
        st = exdex_motion_eval(m->motion, ts, &k);
        if (st) return st;
        model_velocity_jump(m, k.R, y, dv[j], dw[j], y + (H->ndof == 1 ? 1 : 3));
        H->held = 0;  /* a slip (regularised, planar): held again by the decision if in the band */
    }
    return EXDEX_OK;
}
