/* hybrid_laws.c -- the slip laws and right-hand sides of the hybrid methods
 * (hybrid.h): the contact rows in one numbering, the frame terms of the
 * current segment, the plate friction of each mode (Coulomb slip, small slip,
 * rest, the regularised law), the acceleration-level problem of the stops in
 * contact (frictionless: ldp_project; frictional: stop_friction.h) and the
 * ODE right-hand side and its Jacobian. */
#include "hybrid.h"

/* ---------------------------------------------------------- contact rows
 * The stops' rows and the obstacles' (obstacle_rows.h) in one numbering: planar row
 * r < ns nv is stop r / nv against outline vertex r % nv, r >= ns nv the
 * obstacle row of code r - ns nv (its feature held); the 1-DoF contact
 * (ck, cj) is a stop and a vertex, or ck = ns + o and cj an obstacle row
 * code. Obstacle rows take the stops' code path everywhere: gaps, rates,
 * impacts, contact forces, rests; their force is source ns + o's. */

/* Source (stop_force column) of planar row r. */
int hyb_hrow_src(const hyb *H, int r)
{
    int base = H->ns * H->nv;
    return r < base ? r / H->nv : H->ns + orow_obst(r - base);
}

/* Planar row r at (q, v): contact_row_planar's contract. */
double hyb_hrow_planar(const hyb *H, const exdex_kinematics *kin, int r, const double *q, const double *v,
                       double G[3], double *gd, double *gdd0)
{
    return hyb_hrow_planar_cs(H, kin, r, q, NULL, v, G, gd, gdd0);
}

double hyb_hrow_planar_cs(const hyb *H, const exdex_kinematics *kin, int r, const double *q, const double *cs,
                          const double *v, double G[3], double *gd, double *gdd0)
{
    int base = H->ns * H->nv;
    if (r < base) return contact_row_planar_cs(H->m, kin, r / H->nv, r % H->nv, q, cs, v, G, gd, gdd0);
    return orow_planar(H->m, kin, r - base, q, v, G, gd, gdd0);
}

/* Every planar row at (kin, y), an obstacle's with its active feature:
 * rows, G, gaps and (gd may be NULL) gap rates. Returns the count. */
int hyb_hrow_all_planar(const hyb *H, const exdex_kinematics *kin, const double *y, int *rows, double (*G)[3],
                        double *gap, double *gd)
{
    int n = 0;
    double csv[2];
    const double *cs = hyb_stop_cs(H, y, csv);
    for (int k = 0; k < H->ns; k++)
        for (int j = 0; j < H->nv; j++) {
            gap[n] = contact_row_planar_cs(H->m, kin, k, j, y, cs, y + 3, G[n], gd ? &gd[n] : NULL, NULL);
            rows[n++] = k * H->nv + j;
        }
    if (H->no) {
        int code[MAX_ROWS], no = orow_all(H->m, kin, y, y + 3, 1, code, NULL);
        for (int i = 0; i < no && n < MAX_ROWS; i++) {
            rows[n] = H->ns * H->nv + code[i];
            gap[n] = orow_planar(H->m, kin, code[i], y, y + 3, G[n], gd ? &gd[n] : NULL, NULL);
            n++;
        }
    }
    return n;
}

/* 1-DoF row (k, j) (a stop and vertex, or an obstacle and row code) at q. */
void hyb_hrow_1dof(const hyb *H, const exdex_kinematics *kin, int k, int j, double q, crow *c)
{
    if (k < H->ns)
        contact_row_1dof(H->m, kin, k, j, q, c);
    else
        orow_1dof(H->m, kin, j, q, c);
}

/* Every 1-DoF row at (kin, q, v): sources k and rows j (vertex or code),
 * the stops' first (r = k nv + j). Returns the count. */
int hyb_hrow_all_1dof(const hyb *H, const exdex_kinematics *kin, double q, const double *v, int *k, int *j)
{
    int n = 0;
    for (int s = 0; s < H->ns; s++)
        for (int v = 0; v < H->nv; v++) {
            k[n] = s;
            j[n++] = v;
        }
    if (H->no) {
        int code[MAX_ROWS], no = orow_all(H->m, kin, &q, v, 0, code, NULL);
        for (int i = 0; i < no && n < MAX_ROWS; i++) {
            k[n] = H->ns + orow_obst(code[i]);
            j[n++] = code[i];
        }
    }
    return n;
}

/* ---------------------------------------------------------- shared terms */

/* t clamped into the current segment: right-continuous at its start, left
 * limit (a few ulps before) at its end, so an RK stage on the segment end
 * never sees the next phase's acceleration or grip force. */
static double seg_time(const hyb *H, double t)
{
    double lo = H->lo, hi = H->hi;
    if (isfinite(hi)) hi -= FEW_ULPS * DBL_EPSILON * fmax(1.0, fabs(hi));
    if (t > hi) t = hi;
    if (t < lo) t = lo;
    return t;
}

/* Frame terms at t inside the current motion segment (seg_time); with a
 * grip schedule also the friction capacities H->cap, H->caps at that time (segments end
 * at the schedule's breakpoints too), which every friction law, guard and
 * decision below reads: the stick guard C(t) (1 + FRICTION_BAND) - |load|_E is
 * located on the stepper's dense map like every other guard. */
int hyb_frame_seg(hyb *H, double t, frame *f, exdex_kinematics *k)
{
    t = seg_time(H, t);
    if (H->m->grip_n) {
        H->cap = H->capk * model_capacity(H->m, t);
        H->caps = H->capk * model_capacity_static(H->m, t);
    }
    return model_frame_at(H->m, t, f, k);
}

/* Regularised friction per unit slip at slip speed sig = |E u| (same
 * units as eps): the wrench is -smooth_gain E^2 u (1-DoF: -smooth_gain v).
 * One coefficient: C / sqrt(sig^2 + eps^2). Static and kinetic (caps >
 * cap): the stick band C_s / eps for sig <= eps, Coulomb C / sig beyond
 * (hybrid.h). */
static double smooth_gain(const hyb *H, double sig)
{
    if (H->caps == H->cap) return H->cap / sqrt(sig * sig + H->eps * H->eps);
    return sig <= H->eps ? H->caps / H->eps : (H->held ? H->caps : H->cap) / sig;
}

/* Constraint acceleration of q along the row (F(q(t), t) = 0 held). */
double hyb_contact_qdd(const crow *c, double v)
{
    return -(c->Ftt + 2.0 * c->Ftq * v + c->Fqq * v * v) / c->Fq;
}

/* Slip of the 1-DoF row (k, j) (a stop and vertex, or an obstacle and row
 * code) along its stop at (q, v) and pose kin: s = T v + tb
 * (contact_stop_tangent; an obstacle row: contact_tangent at its point,
 * orow_point); T (may be NULL) gets d s / d qdot. hyb_contact_slip_1dof: of the
 * contact row (H->ck, H->cj). */
double hyb_row_slip_1dof(const hyb *H, const exdex_kinematics *kin, int k, int j, double q, double v, double *T)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], Tv[3], tb;
    if (k >= H->ns) {
        contact_point cp;
        orow_point(H->m, kin, j, &q, &cp);
        contact_tangent(H->m, kin, cp.x, cp.vx, cp.nB, Tv, &tb);
        if (T) *T = Tv[0];
        return Tv[0] * v + tb;
    }
    contact_vertices(H->m, &q, xb, vx);
    contact_stop_tangent(H->m, kin, k, xb[j], vx[j], Tv, &tb);
    if (T) *T = Tv[0];
    return Tv[0] * v + tb;
}

double hyb_contact_slip_1dof(const hyb *H, const exdex_kinematics *kin, double q, double v, double *T)
{
    return hyb_row_slip_1dof(H, kin, H->ck, H->cj, q, v, T);
}

/* The stop's generalized force per unit normal force in contact: Fq, less
 * mu ss T with a frictional stop (its Coulomb force -mu lam ss along the
 * tangent, generalized force -mu lam ss T). */
double hyb_contact_dir(const hyb *H, const crow *c, double T)
{
    double mu = model_source_mu(H->m, H->ck);
    return mu > 0.0 && H->ss != 0.0 ? c->Fq - mu * H->ss * T : c->Fq;
}

/* Friction f and stop force lam in contact (M qdd = Q + f + lam D, D =
 * hyb_contact_dir: Fq for a frictionless stop); T the tangent row of the
 * contact vertex (hyb_contact_slip_1dof). */
void hyb_contact_forces(const hyb *H, const crow *c, double T, double R, double v, double *f, double *lam)
{
    double D = hyb_contact_dir(H, c, T);
    if (H->law == LAW_SMOOTH) {
        *f = H->caps == H->cap ? -H->cap * v / sqrt(v * v + H->eps * H->eps) : -smooth_gain(H, fabs(v)) * v;
        *lam = (R - *f) / D;
    } else if (H->s != 0.0) {
        *f = -H->s * H->cap;
        *lam = (R - *f) / D;
    } else {
        /* at rest against the stop: the stop carries what it can (as the
         * implicit method). A stop that pushes (R / D > 0) carries all of
         * R, so the plates carry exactly 0: the rounding residual R - (R /
         * D) D (an ulp of R) is not a friction load, and the rest's stick
         * test (T1) must not find it beyond a capacity of 0 (a released
         * grip) and send the object slipping into the stop that holds it */
        double l = R / D;
        *lam = l > 0.0 ? l : 0.0;
        *f = l > 0.0 ? 0.0 : R;
    }
}

/* ------------------------------------------------ planar frictional stops
 * Coulomb friction between a stop with stop_mu > 0 (or an obstacle with mu
 * > 0) and the points of a planar object touching it, exact (not
 * regularised, also in the regularised method, which smooths the plate
 * friction only): the acceleration-level problem of stop_friction.h on the
 * contact-set rows. The rows fall into friction groups, lines of contact
 * (sf_groups: a stop's rows, an obstacle face's vertex rows, the section
 * vertices on one edge of the object, a rod's row), fixed at each decision
 * (hyb_sf_fix_groups) and held with the contact set. Each group with
 * contact-set rows has a friction mode H->fm (one per group: its touching
 * points lie on its line and slip together): sliding with the sign of its
 * slip s (along the tangent of contact_slip_planar, or orow_slip for an
 * obstacle row, whose contact point may move over the object) or
 * sticking. The modes are decided at every decision (decide: sf_decide)
 * and held between decisions, where their guards (sf_guards) say when they
 * end: a sliding stop's slip reaching 0 (sigma s), a sticking stop's force
 * reaching its cone (mu sum lam (1 + FRICTION_BAND) - |beta|). A slip with |s| <=
 * zsw is decided as rolling (stick or slide, the acceleration-level mode
 * enumeration: a slip located at its reversal is within rounding of 0
 * there), and a sticking stop's slip is projected to 0 at the decision and
 * after every step (sf_project_stick), like the gap of a contact row.
 * Normal forces and separations stay as without friction (the contact set,
 * its separation guards); impacts are frictional at the impulse level
 * (sf_impact, hybrid_impacts.c).
 * At rest (stick) the split of hyb_planar_rest is the creeping plate's
 * (sf_rest_creep): each stop's friction opposes the creep's slip along it
 * (stick within its cone, or slide at it) while the stop's slip past the
 * resting object |tb| <= zsw; a stop moving past it faster slides: G - mu
 * sign(tb) T. On the exact surface (or where the creep's problem has no
 * consistent mode) the least-friction split over the cones instead, {lam
 * (G + mu c T) : -1 <= c <= 1}, generated by G + mu T and G - mu T
 * (ldp_min_combination over the generators). The stop's mode is
 * decided with the rest and held through it (the rest's
 * load is then smooth in time), its guards |tb| leaving or entering the
 * band. A stop whose mode is not decided (inside a decision) is classified
 * by its tb as it stands.
 * Painleve: where no mode of the acceleration-level problem is consistent
 * (a sliding stop whose friction turns the normal force's effect around:
 * a jam, or more rows than sf_solve reduces to its enumeration), the stops
 * of the contact set are taken frictionless until the next decision, and a
 * warning is counted, as for a 1-DoF jam; the loss of consistency is a
 * located guard (+1 / -1). The velocity-level (impulse) solution would
 * exist there (stop_impulse.h), but it is a jump of the velocity that the
 * acceleration-level machine would have to apply as an impact at a time it
 * cannot locate from a smooth guard; the implicit method, which is that
 * velocity-level step, reports the same scenes with its own warning.
 * A consistent sliding mode that runs into a jam (the normal forces
 * growing without bound as the mode's determinant ratio D / D_0 falls to
 * 0, hyb_sf_jam_ratio: their integral stays finite, the steps collapse
 * before the jam) has a smooth guard, |D / D_0| - JAM_DIR (G_SF_JAM): at
 * that event the sliding groups' slip is arrested by an impulse, the
 * impact without collision of the rigid limit (hyb_planar_jam_impulse,
 * hybrid_impacts.c), and the mode is decided again at the new velocity. */

/* The unit in-plane normal (B) of planar row r at (kin, y): the direction
 * its gap grows in when the object's point moves (a stop's, an obstacle
 * face's, or orow_point's). */
static void sf_row_normal(const hyb *H, const exdex_kinematics *kin, int r, const double *y, double n[2])
{
    int base = H->ns * H->nv;
    double nB[3], nn;
    if (r < base) {
        ex_mulmtv3(nB, kin->R, H->m->sn[r / H->nv]);
    } else {
        contact_point cp;
        orow_point(H->m, kin, r - base, y, &cp);
        memcpy(nB, cp.nB, sizeof nB);
    }
    nn = hypot(nB[0], nB[1]);
    n[0] = nn > 0.0 ? nB[0] / nn : 0.0;
    n[1] = nn > 0.0 ? nB[1] / nn : 0.0;
}

/* Friction groups of the contact-set rows at (kin, y) into grp: a group is
 * a line of contact, whose rows slip together (one slip, one tangent row:
 * two points on one line have the same arm of the tangent about the centre
 * of mass and the same frame slip along it). Stop k's rows are group k;
 * an obstacle's rows join the first group of the same obstacle whose
 * normal agrees to SF_SAME_LINE (the vertices on one face; the section
 * vertices on one edge of the object; both, where a face lies flush on an
 * edge), else start one, numbered from ns. Returns the count, -1 beyond
 * SF_MAX_STOPS. */
static int sf_groups(const hyb *H, const exdex_kinematics *kin, const double *y, int *grp)
{
    double gn[SF_MAX_STOPS][2];
    int gsrc[SF_MAX_STOPS], ng = H->ns, base = H->ns * H->nv;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i], src, g;
        double n[2];
        if (r < base) {
            grp[i] = r / H->nv;
            continue;
        }
        src = hyb_hrow_src(H, r);
        sf_row_normal(H, kin, r, y, n);
        for (g = H->ns; g < ng; g++)
            if (gsrc[g] == src && fabs(n[0] - gn[g][0]) <= SF_SAME_LINE && fabs(n[1] - gn[g][1]) <= SF_SAME_LINE) break;
        if (g == ng) {
            if (ng == SF_MAX_STOPS) return -1;
            gsrc[ng] = src;
            gn[ng][0] = n[0];
            gn[ng][1] = n[1];
            ng++;
        }
        grp[i] = g;
    }
    return ng;
}

/* The contact-set rows at (kin, y) as stop_friction.h's problem into S (groups:
 * those fixed at the decision, else sf_groups); a group's slip is its first
 * set row's (contact_slip_planar, orow_slip). A group in SF_ROLL with |s| >
 * zsw is given the slide of its sign. Returns the row count, or -1 when it
 * exceeds SF_MAX_ROWS or the groups SF_MAX_STOPS (rows then hold only the
 * first SF_MAX_ROWS; with the groups found, grp, has, s, tb, st are
 * complete). */
int hyb_sf_build(hyb *H, const exdex_kinematics *kin, const double *y, sf_set *S)
{
    const exdex_model *m = H->m;
    int base = H->ns * H->nv;
    if (H->sgn > 0) {
        memcpy(S->grp, H->sg, (size_t)H->ncs * sizeof *S->grp);
        S->ng = H->sgn;
    } else {
        S->ng = sf_groups(H, kin, y, S->grp);
        if (S->ng < 0) {
            S->ng = 0;
            return -1;
        }
    }
    for (int k = 0; k < S->ng; k++) {
        S->has[k] = 0;
        S->s[k] = S->tb[k] = 0.0;
        S->st[k].mu = k < H->ns ? model_source_mu(m, k) : 0.0;
        S->st[k].fm = H->fm[k];
        S->st[k].sdd0 = 0.0;
        S->st[k].T[0] = S->st[k].T[1] = S->st[k].T[2] = 0.0;
    }
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i], k = S->grp[i];
        sf_stop *st = &S->st[k];
        if (i < SF_MAX_ROWS) {
            hyb_hrow_planar(H, kin, r, y, y + 3, S->rows[i].G, NULL, &S->rows[i].gdd0);
            S->rows[i].stop = k;
        }
        if (S->has[k]) continue;
        S->has[k] = 1;
        if (r < base) {
            S->s[k] = contact_slip_planar(m, kin, k, r % H->nv, y, y + 3, st->T, &S->tb[k], &st->sdd0);
        } else {
            st->mu = model_source_mu(m, hyb_hrow_src(H, r));
            S->s[k] = orow_slip(m, kin, r - base, y, y + 3, st->T, &S->tb[k], &st->sdd0);
        }
        if (st->fm == SF_ROLL && fabs(S->s[k]) > H->zsw) st->fm = S->s[k] > 0.0 ? SF_SLIDE_P : SF_SLIDE_M;
    }
    return H->ncs > SF_MAX_ROWS ? -1 : H->ncs;
}

/* The groups of the contact set fixed for the mode after a decision at
 * (t, y), so that between decisions (the contact set held) every guard and
 * mode keeps its group. */
void hyb_sf_fix_groups(hyb *H, double t, const double *y)
{
    frame f;
    exdex_kinematics kin;
    int ng;
    H->sgn = 0;
    if (!H->ncs || hyb_frame_seg(H, t, &f, &kin)) return;
    ng = sf_groups(H, &kin, y, H->sg);
    H->sgn = ng > 0 ? ng : 0;
}

/* The problem solved at (kin, y) with the acceleration a without stops
 * (sf_solve); res (may be NULL) gets the solution. Returns 0 when no mode is
 * consistent (then nothing is written but res). */
int hyb_sf_solve_at(hyb *H, const exdex_kinematics *kin, const double *y, const double a[3], sf_result *res)
{
    sf_set S;
    int ok;
    const model_scales *sc = &H->m->scale;
    if (hyb_sf_build(H, kin, y, &S) < 0) return 0;
    ok = sf_solve(H->ncs, S.rows, S.ng, S.st, H->m->minv, a, SF_TOL * sc->V / sc->T, SF_TOL * sc->F, res);
    H->st->stop_iterations += (size_t)res->tried;
    return ok;
}

/* det of the n x n (n <= 3) leading block of A. */
static double det_n(int n, const double (*A)[3])
{
    if (n == 1) return A[0][0];
    if (n == 2) return A[0][0] * A[1][1] - A[0][1] * A[1][0];
    return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
           A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
}

/* The jam ratio D / D_0 of the mode res that sf_solve found on the set S
 * (the planar counterpart of a 1-DoF contact's D / Fq, hybrid.h "Frictional
 * stops"). The mode's constraints J are the rows carrying force (lam > 0)
 * and the slip rows T_k of the sticking groups carrying force; the columns
 * K of their unknowns are G_i - mu_k sigma_k T_k for a row of a sliding
 * group (its friction -mu_k sigma_k lam_i along T_k), G_i for any other
 * row, T_k for a sticking group's tangential force. D = det(J M^-1 K^T) is
 * the determinant of the mode's equations, D_0 = det(J M^-1 J^T) > 0 that
 * of the same constraints without the sliding friction: the ratio is 1
 * without friction and falls to 0 where the friction turns the normal
 * forces' effect on the gaps around, the forces -(J a + sdd0) / (J M^-1
 * K^T) growing without bound (a jam: a sliding corner on a stop with mu
 * near its Painleve limit). NAN where no sliding group carries force, in a
 * lock, with more than 3 constraints, or with constraints dependent to
 * SET_ROW_DEPENDENT (D_0 at most that share of the product of its
 * diagonal, Hadamard's bound). */
double hyb_sf_jam_ratio(const hyb *H, const sf_set *S, const sf_result *res)
{
    const double *mi = H->m->minv;
    double J[3][3], K[3][3], N[3][3], N0[3][3], d0, dd = 1.0;
    int n = 0, slide = 0;
    if (res->lock) return NAN;
    for (int i = 0; i < H->ncs && i < SF_MAX_ROWS; i++) {
        int k = S->rows[i].stop;
        const sf_stop *st = &S->st[k];
        double sg = 0.0;
        if (!(res->lam[i] > 0.0)) continue;
        if (n == 3) return NAN;
        if (st->mu > 0.0 && (res->fm[k] == SF_SLIDE_P || res->fm[k] == SF_SLIDE_M)) {
            sg = res->fm[k] == SF_SLIDE_P ? 1.0 : -1.0;
            slide = 1;
        }
        for (int c = 0; c < 3; c++) {
            J[n][c] = S->rows[i].G[c];
            K[n][c] = S->rows[i].G[c] - st->mu * sg * st->T[c];
        }
        n++;
    }
    for (int k = 0; slide && k < S->ng; k++) {
        if (!(S->has[k] && S->st[k].mu > 0.0 && res->fm[k] == SF_STICK && res->lsum[k] > 0.0)) continue;
        if (n == 3) return NAN;
        memcpy(J[n], S->st[k].T, sizeof J[n]);
        memcpy(K[n], S->st[k].T, sizeof K[n]);
        n++;
    }
    if (!slide) return NAN;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            N[i][j] = N0[i][j] = 0.0;
            for (int c = 0; c < 3; c++) {
                N[i][j] += J[i][c] * mi[c] * K[j][c];
                N0[i][j] += J[i][c] * mi[c] * J[j][c];
            }
        }
    for (int i = 0; i < n; i++) dd *= N0[i][i];
    d0 = det_n(n, (const double (*)[3])N0);
    if (!(d0 > SET_ROW_DEPENDENT * dd)) return NAN;
    return det_n(n, (const double (*)[3])N) / d0;
}

/* The problem of the contact set at (f, kin, y) with the plate's small-slip
 * friction (the ellipsoid at capacity H->cap: the maximum-dissipation wrench
 * of the slip acceleration) as one more contact, solved jointly with the
 * stop rows (sf_solve_plate) on the current modes H->fm; res (not NULL) gets
 * the solution, res->w the plate's wrench. Returns 1 with a consistent mode,
 * 0 with none (or with the exact surface, which sf_plate does not take). */
int hyb_sf_solve_plate(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, sf_result *res)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    const model_scales *sc = &m->scale;
    const double cs[2] = {cos(y[2]), sin(y[2])};
    double F[3], a[3];
    sf_set S;
    sf_plate pl;
    int ok;
    if (m->ls_exact || hyb_sf_build(H, kin, y, &S) < 0) return 0;
    model_force_planar(m, f, y, y + 3, F);
    for (int j = 0; j < 3; j++) {
        double ej[3] = {0, 0, 0}, P[3];
        ej[j] = 1.0;
        model_gen_of_patch(m, cs, ej, P);
        for (int c = 0; c < 3; c++) pl.A[c][j] = P[c];
        pl.e[j] = m->e[j];
    }
    pl.cap = H->cap;
    for (int c = 0; c < 3; c++) a[c] = m->minv[c] * F[c];
    ok = sf_solve_plate(H->ncs, S.rows, S.ng, S.st, m->minv, a, &pl, SF_TOL * sc->V / sc->T, SF_TOL * sc->F, res);
    H->st->stop_iterations += (size_t)res->tried;
    return ok;
}

/* hyb_contact_acc_planar with frictional stops: 1 with qdd, lam, acc as it
 * defines them (2: the mode is a lock, stop_friction.h: lam is one split of
 * indeterminate forces, lock_rows (may be NULL) the set rows it holds, bit
 * i for H->cs[i]), 0 when no mode is consistent (the caller then takes the
 * stops frictionless). */
static int sf_acc(hyb *H, const exdex_kinematics *kin, const double *y, const double afree[3], double qdd[3],
                  double *lam, double *acc, unsigned *lock_rows)
{
    sf_result res;
    if (!hyb_sf_solve_at(H, kin, y, afree, &res)) return 0;
    if (lock_rows) *lock_rows = res.lock ? res.mask : 0u;
    memcpy(qdd, res.qdd, sizeof res.qdd);
    for (int i = 0; i < H->ncs; i++) {
        lam[i] = res.lam[i];
        if (acc) acc[i] = res.acc[i];
    }
    return 1 + res.lock;
}

/* The rest split against frictional rows on the ellipsoid (sf_rest): the
 * limit of a plate that creeps under the load. A plate whose friction is
 * viscous below a slip speed (the regularised method's band, w = -(C_s /
 * eps) E^2 u) holds a load at a creep u of size eps; with x = E^-1 w (the
 * gauge is |x|), the plate's slip is E u = -x (eps / C_s), the velocity qd
 * = A^-T u (A: patch wrench -> generalized force), and each row's gap rate
 * and each group's slip rate are, up to the factor eps / C_s > 0,
 *     G_i qd  ->  b_i . x,   b_i = E^-1 patch(-G_i),
 *     T_k qd  ->  t_k . x,   t_k = E^-1 patch(-T_k),
 * while equilibrium is x = a + sum lam_i b_i + sum beta_k t_k, a = E^-1
 * patch(-F). The rows' forces are complementary to those rates (lam_i >= 0
 * _|_ b_i . x >= 0) and each group's friction is Coulomb's on its slip:
 * against the creep's slip t_k . x where the stop does not slide past the
 * object (|tb| <= zsw: stick with |beta| <= mu sum lam, or slide at the
 * cone), kinetic of the sign of tb where it does (or the group's mode
 * given at the decision, if a slide). That is stop_friction.h's problem
 * with M = I, the rows b_i, the tangents t_k and no drift terms, solved as
 * the contact problem of every other mode (sf_solve); in the limit eps ->
 * 0 the rest holds iff |x| <= C_s (the caller's test). Without friction
 * its solution is the least-gauge split (the KKT conditions of min |a +
 * sum lam_i b_i| over lam >= 0 are the complementarity above); with
 * friction the least gauge over the stop forces in their cones would take
 * the friction that helps the plate most, whichever way the creep slips,
 * and hold loads that a creeping plate lets go (the object then leaves
 * the row and slips). Returns the gauge |x| with w = E x and lam the
 * rows' normal forces, or -1 when no mode is consistent (a Painleve case
 * of the creep problem) or S has no groups. */
static double sf_rest_creep(hyb *H, const sf_set *S, const double *y, const double F[3], double w[3], double *lam)
{
    const exdex_model *m = H->m;
    const model_scales *sc = &m->scale;
    const double one[3] = {1.0, 1.0, 1.0};
    sf_row rows[SF_MAX_ROWS];
    sf_stop st[SF_MAX_STOPS];
    sf_result res;
    double a[3], mF[3];
    int ok;
    if (S->ng <= 0 || H->ncs > SF_MAX_ROWS) return -1.0;
    for (int c = 0; c < 3; c++) mF[c] = -F[c];
    model_patch_of_gen(m, MODEL_CS(y[2]), mF, a);
    for (int c = 0; c < 3; c++) a[c] /= m->e[c];
    for (int i = 0; i < H->ncs; i++) {
        double mG[3] = {-S->rows[i].G[0], -S->rows[i].G[1], -S->rows[i].G[2]};
        model_patch_of_gen(m, MODEL_CS(y[2]), mG, rows[i].G);
        for (int c = 0; c < 3; c++) rows[i].G[c] /= m->e[c];
        rows[i].gdd0 = 0.0;
        rows[i].stop = S->rows[i].stop;
    }
    for (int k = 0; k < S->ng; k++) {
        double mT[3] = {-S->st[k].T[0], -S->st[k].T[1], -S->st[k].T[2]};
        int fm = H->fm[k];
        model_patch_of_gen(m, MODEL_CS(y[2]), mT, st[k].T);
        for (int c = 0; c < 3; c++) st[k].T[c] /= m->e[c];
        st[k].sdd0 = 0.0;
        st[k].mu = S->st[k].mu;
        if (fm != SF_NONE && fm != SF_SLIDE_P && fm != SF_SLIDE_M)
            fm = fabs(S->tb[k]) <= H->zsw ? SF_ROLL : S->tb[k] > 0.0 ? SF_SLIDE_P : SF_SLIDE_M;
        st[k].fm = fm;
    }
    ok = sf_solve(H->ncs, rows, S->ng, st, one, a, SF_TOL * sc->F, SF_TOL * sc->F, &res);
    H->st->stop_iterations += (size_t)res.tried;
    if (!ok) return -1.0;
    for (int i = 0; i < H->ncs; i++) lam[i] = res.lam[i];
    for (int c = 0; c < 3; c++) w[c] = m->e[c] * res.qdd[c];
    return sqrt(ex_dot3(res.qdd, res.qdd));
}

/* hyb_planar_rest with frictional stops (the same contract): on the
 * ellipsoid the creeping plate's split (sf_rest_creep); on the exact
 * surface, or where that problem has no consistent mode, the least plate
 * friction over the stop forces in their cones (above). Returns -1 when
 * the generators exceed ldp_min_combination's rows (hyb_planar_rest then
 * takes the stops frictionless). */
static double sf_rest(hyb *H, const exdex_kinematics *kin, const double *y, const double F[3], double w[3],
                      double *lam)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    double D[LDP_MAX_ROWS][3], B[LDP_MAX_ROWS][3], c[LDP_MAX_ROWS], a[3], mF[3], P[3];
    double gm = NAN;
    int own[LDP_MAX_ROWS], ng = 0, it = 0;
    sf_set S;
    hyb_sf_build(H, kin, y, &S);
    if (H->ncs && S.ng == 0) return -1.0;
    if (!m->ls_exact) {
        double g = sf_rest_creep(H, &S, y, F, w, lam);
        if (g >= 0.0) return g;
    }
    if (2 * H->ncs > LDP_MAX_ROWS) return -1.0;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i], k = S.grp[i], fm;
        double G[3], mu = S.st[k].mu;
        const double *T = S.st[k].T, tb = S.tb[k];
        hyb_hrow_planar(H, kin, r, y, y + 3, G, NULL, NULL);
        fm = H->fm[k] == SF_ROLL ? (fabs(tb) <= H->zsw ? SF_STICK : tb > 0.0 ? SF_SLIDE_P : SF_SLIDE_M) : H->fm[k];
        if (!(mu > 0.0) || fm == SF_NONE) {
            memcpy(D[ng], G, sizeof G);
            own[ng++] = i;
        } else if (fm == SF_STICK) {
            for (int c2 = 0; c2 < 3; c2++) {
                D[ng][c2] = G[c2] + mu * T[c2];
                D[ng + 1][c2] = G[c2] - mu * T[c2];
            }
            own[ng++] = i;
            own[ng++] = i;
        } else {
            double sg = fm == SF_SLIDE_P ? 1.0 : -1.0;
            for (int c2 = 0; c2 < 3; c2++) D[ng][c2] = G[c2] - mu * sg * T[c2];
            own[ng++] = i;
        }
    }
    for (int c2 = 0; c2 < 3; c2++) mF[c2] = -F[c2];
    model_patch_of_gen(m, MODEL_CS(y[2]), mF, a);
    if (m->ls_exact) {
        /* the exact surface's least gauge over the generators (the minimum: guards read it) */
        for (int g = 0; g < ng; g++) {
            double mD[3] = {-D[g][0], -D[g][1], -D[g][2]};
            model_patch_of_gen(m, MODEL_CS(y[2]), mD, B[g]);
        }
        gm = limitsurf_min_combination(&m->ls, ng, a, (const double (*)[3])B, NAN, c, &it);
    } else {
        for (int c2 = 0; c2 < 3; c2++) a[c2] /= m->e[c2];
        for (int g = 0; g < ng; g++) {
            double mD[3] = {-D[g][0], -D[g][1], -D[g][2]};
            model_patch_of_gen(m, MODEL_CS(y[2]), mD, B[g]);
            for (int c2 = 0; c2 < 3; c2++) B[g][c2] /= m->e[c2];
        }
        ldp_min_combination(ng, a, (const double (*)[3])B, c, &it);
    }
    H->st->stop_iterations += (size_t)it;
    for (int i = 0; i < H->ncs; i++) lam[i] = 0.0;
    for (int c2 = 0; c2 < 3; c2++) P[c2] = -F[c2];
    for (int g = 0; g < ng; g++) {
        lam[own[g]] += c[g];
        for (int c2 = 0; c2 < 3; c2++) P[c2] -= c[g] * D[g][c2];
    }
    model_patch_of_gen(m, MODEL_CS(y[2]), P, w);
    /* the exact surface: the minimum is the gauge of the solver's w (w here
     * to rounding); no second gauge solve */
    return m->ls_exact && !isnan(gm) ? gm : model_ls_gauge(m, w);
}

/* Accelerations in planar contact: qdd = M^-1 (F + P + G_A^T lam), lam >= 0
 * the stop forces of the contact-set rows, complementary to their gap
 * accelerations G_i qdd + gdd0_i >= 0 (the small LCP G M^-1 G^T lam =
 * -(G M^-1 (F + P) + gdd0) with complementarity): the M-metric projection
 * of the free acceleration (ldp_project). The plate friction does not depend on
 * the stop forces (the grip force is given). acc_i (may be NULL) gets the
 * gap acceleration of every contact-set row. Returns 1 when the stop
 * friction's mode is a lock (sf_acc; lock_rows, may be NULL, gets its rows),
 * else 0. */
static int contact_acc_planar_cs(hyb *H, const exdex_kinematics *kin, const double *y, const double *cs,
                                 const double afree[3], double qdd[3], double *lam, double *acc, unsigned *lock_rows);

int hyb_contact_acc_planar(hyb *H, const exdex_kinematics *kin, const double *y, const double afree[3],
                           double qdd[3], double *lam, double *acc, unsigned *lock_rows)
{
    return contact_acc_planar_cs(H, kin, y, NULL, afree, qdd, lam, acc, lock_rows);
}

/* hyb_contact_acc_planar with cs = (cos y[2], sin y[2]) given (NULL: computed by the rows). */
static int contact_acc_planar_cs(hyb *H, const exdex_kinematics *kin, const double *y, const double *cs,
                                 const double afree[3], double qdd[3], double *lam, double *acc, unsigned *lock_rows)
{
    double Gr[MAX_ROWS][3], b[MAX_ROWS];
    int lk = H->sfric ? sf_acc(H, kin, y, afree, qdd, lam, acc, lock_rows) : 0;
    if (lock_rows && lk != 2) *lock_rows = 0u;
    if (lk) return lk - 1;
    b[0] = 0.0;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double gdd0 = 0.0;
        hyb_hrow_planar_cs(H, kin, r, y, cs, y + 3, Gr[i], NULL, &gdd0);
        b[i] = -gdd0;
    }
    ldp_project(H->m->minv, H->ncs, (const double (*)[3])Gr, b, afree, FQ_MIN, qdd, lam, &H->st->stop_iterations, &H->st->warnings);
    if (acc)
        for (int i = 0; i < H->ncs; i++) acc[i] = ex_dot3(Gr[i], qdd) - b[i];
    return 0;
}

/* Rest against the contact-set rows (event method, stick): can the object
 * stay at rest with stop forces lam >= 0 and a plate wrench inside the
 * limit surface? The wrench needed is w(lam) = patch(-(F + G^T lam));
 * minimise its gauge over lam >= 0 (the ellipsoid: |E^-1 w(lam)|,
 * ldp_min_combination; the exact surface: limitsurf_min_combination, the
 * minimum itself, as a guard's value must be); the minimiser is the split
 * with the least friction, as in the implicit method. Returns the minimum
 * (rest holds iff <= cap (1 + FRICTION_BAND)); w, lam the split. */
double hyb_planar_rest(hyb *H, const exdex_kinematics *kin, const double *y, const double F[3], double w[3],
                       double *lam)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    double B[MAX_ROWS][3], a[3], mF[3], P[3], gm = NAN;
    int it = 0;
    if (H->sfric) {
        double r = sf_rest(H, kin, y, F, w, lam);
        if (r >= 0.0) return r;
    }
    const double cs[2] = {cos(y[2]), sin(y[2])};  /* (cos, sin) of theta for the rows and patch maps */
    for (int c = 0; c < 3; c++) mF[c] = -F[c];
    model_patch_of_gen(m, cs, mF, a);
    if (!m->ls_exact)
        for (int c = 0; c < 3; c++) a[c] /= m->e[c];
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double G[3], mG[3];
        hyb_hrow_planar_cs(H, kin, r, y, cs, y + 3, G, NULL, NULL);
        for (int c = 0; c < 3; c++) mG[c] = -G[c];
        model_patch_of_gen(m, cs, mG, B[i]);
        if (!m->ls_exact)
            for (int c = 0; c < 3; c++) B[i][c] /= m->e[c];
    }
    if (m->ls_exact) {  /* the exact surface's least gauge over the stop forces (the minimum: guards read it) */
        if (H->ncs > LDP_MAX_ROWS) return NAN;
        gm = limitsurf_min_combination(&m->ls, H->ncs, a, (const double (*)[3])B, NAN, lam, &it);
    } else
        ldp_min_combination(H->ncs, a, (const double (*)[3])B, lam, &it);
    H->st->stop_iterations += (size_t)it;
    for (int c = 0; c < 3; c++) P[c] = -F[c];
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double G[3];
        hyb_hrow_planar_cs(H, kin, r, y, cs, y + 3, G, NULL, NULL);
        for (int c = 0; c < 3; c++) P[c] -= lam[i] * G[c];
    }
    model_patch_of_gen(m, cs, P, w);
    return m->ls_exact && !isnan(gm) ? gm : model_ls_gauge(m, w);  /* as sf_rest */
}

/* The load at (t, y) (f, kin its frame terms): the ellipsoid norm |E^-1 w|
 * of the plate wrench w that holds the object at zero velocity (against
 * the contact-set rows: the least-friction split of hyb_planar_rest).
 * hyb_planar_load_held: would the object stay at rest there (the stick test of
 * decide): that load inside the static ellipsoid? */
double hyb_planar_load(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    double F[3], w[3], zero[3] = {0, 0, 0}, lam[MAX_ROWS];
    model_force_planar(m, f, y, zero, F);
    if (H->ncs) return hyb_planar_rest(H, kin, y, F, w, lam);
    for (int i = 0; i < 3; i++) F[i] = -F[i];
    model_patch_of_gen(m, MODEL_CS(y[2]), F, w);
    return model_ls_gauge(m, w);
}

int hyb_planar_load_held(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    return hyb_planar_load(H, f, kin, y) <= H->caps * (1.0 + FRICTION_BAND);
}

/* Regularised, planar, C_s > C: whether the held regime applies (see the
 * top), and the slip speed |E u| at y. */
int hyb_smooth_two(const hyb *H)
{
    return H->law == LAW_SMOOTH && H->ndof == 3 && H->m->capks > H->m->capk;
}

double hyb_planar_slip_speed(const hyb *H, const double *y)
{
    hyb_pads(H, y);
    double u[3], eu[3];
    model_patch_slip(H->m, MODEL_CS(y[2]), y + 3, u);
    if (H->m->ls_exact)   /* the exact surface's slip speed: D(u), its dissipation per unit capacity */
        return limitsurf_dissipation(&H->m->ls, u);
    for (int i = 0; i < 3; i++) eu[i] = H->m->e[i] * u[i];
    return sqrt(ex_dot3(eu, eu));
}

/* Does a contact-set row's stop recede in B, at zero velocity, at SLIP_PUSH
 * zsw or faster, while friction alone cannot hold the load at rest (see
 * decide)? f, kin the frame terms at (t, y). */
int hyb_planar_set_recedes(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    hyb_pads(H, y);
    double zero[3] = {0, 0, 0}, F[3], w[3];
    if (!H->ncs) return 0;
    model_force_planar(H->m, f, y, zero, F);
    for (int i = 0; i < 3; i++) F[i] = -F[i];
    model_patch_of_gen(H->m, MODEL_CS(y[2]), F, w);
    if (model_ls_gauge(H->m, w) <= H->caps * (1.0 + FRICTION_BAND)) return 0;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double G[3], gd;
        hyb_hrow_planar(H, kin, r, y, zero, G, &gd, NULL);
        if (gd >= SLIP_PUSH * H->zsw) return 1;
    }
    return 0;
}

/* Planar applied force F (B, generalized) and plate friction wrench w
 * (patch) of the current mode at (t, y): stick holds everything (w = -F as
 * a patch wrench; the stop forces of a rest against stops are not part of
 * it), slip the sliding law (the maximum-dissipation direction from rest),
 * regularised the smooth law. */
static int planar_friction_cs(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y,
                              const double cs[2], double F[3], double w[3])
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    const double *v = y + 3;
    model_force_planar_cs(m, f, y, v, cs, F);
    if (H->mode == MODE_STICK) {
        double mF[3] = {-F[0], -F[1], -F[2]};
        model_patch_of_gen(m, cs, mF, w);
    } else {
        double u[3], eu[3], sig;
        model_patch_slip(m, cs, v, u);
        for (int i = 0; i < 3; i++) eu[i] = m->e[i] * u[i];
        sig = sqrt(ex_dot3(eu, eu));
        if (H->law == LAW_SMOOTH && m->ls_exact) {
            /* the exact surface: the same gain of the slip speed D(u) (its
             * dissipation per unit capacity, |E u| for the ellipsoid) along
             * its maximum-dissipation wrench, gain D w(u) (-gain E^2 u for
             * the ellipsoid) */
            double ws[3] = {0, 0, 0}, D = u[0] != 0.0 || u[1] != 0.0 || u[2] != 0.0
                                               ? limitsurf_wrench(&m->ls, u, ws, NULL) : 0.0;
            double gn = H->caps == H->cap ? H->cap / sqrt(D * D + H->eps * H->eps) : smooth_gain(H, D);
            for (int i = 0; i < 3; i++) w[i] = D > 0.0 ? gn * D * ws[i] : 0.0;
            if (!ex_finite_n(w, 3)) return EXDEX_ENONFINITE;
        } else if (H->law == LAW_SMOOTH) {
            if (H->caps == H->cap) {
                double den = sqrt(sig * sig + H->eps * H->eps);
                for (int i = 0; i < 3; i++) w[i] = -H->cap * m->e[i] * eu[i] / den;
            } else {
                double gn = smooth_gain(H, sig);
                for (int i = 0; i < 3; i++) w[i] = -gn * m->e[i] * eu[i];
            }
        } else if (sig > 0.0 && !H->small) {
            if (m->ls_exact) {
                /* the exact surface's maximum-dissipation wrench of the slip */
                limitsurf_wrench(&m->ls, u, w, NULL);
                for (int i = 0; i < 3; i++) w[i] *= H->cap;
            } else {
                for (int i = 0; i < 3; i++) w[i] = -H->cap * m->e[i] * eu[i] / sig;
            }
        } else {
            /* slip starting from rest, and a small slip growing from rest:
             * the maximum-dissipation wrench for an infinitesimal step,
             * u' = b + W w (paper Eq. 6). While |E u| is small the sliding
             * law's direction E u / |E u| relaxes onto this one at the rate
             * C |K| / |E u| (K = E W E): infinitely stiff as the slip starts,
             * and below the error control's resolution (atol) E u carries no
             * direction at all. The slip follows this direction to within
             * |E u| |d(direction)/dt| / (C |K|) (quasi-static relaxation) */
            double wF[3], b[3];
            exdex_friction_result res;
            int st;
            model_patch_of_gen(m, cs, F, wF);
            ex_mulmv3(b, model_prep(m)->W, wF);
            st = limitsurf_step(&m->ls, model_prep(m), b, H->cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &res);
            if (st) return st;
            memcpy(w, res.p, 3 * sizeof *w);
            if (H->ncs && kin && H->sfric && !m->ls_exact) {
                /* against frictional stops (the ellipsoid): the plate as one
                 * more contact of their problem on the current modes, solved
                 * jointly (hyb_sf_solve_plate), as the decision chose them;
                 * where those modes have no joint solution (a mode at its
                 * end, which its guard locates) the iteration below */
                sf_result jr;
                if (hyb_sf_solve_plate(H, f, kin, y, &jr)) {
                    memcpy(w, jr.w, 3 * sizeof *w);
                    return EXDEX_OK;
                }
            }
            if (H->ncs && kin) {
                /* against stops the slip starts along the constrained
                 * acceleration: the friction and the stop forces are
                 * found together, by the fixed point w = -C E^2 E u'/|E u'|
                 * of u' the patch slip of the M-metric projection of the
                 * free acceleration (bounded; the last iterate is kept) */
                for (int it = 0; it < SMALL_SLIP_FIX_MAX; it++) {
                    double P[3], a[3], qdd[3], lam[MAX_ROWS], ua[3], ea[3], sa, wn[3], d = 0.0;
                    model_gen_of_patch(m, cs, w, P);
                    for (int i = 0; i < 3; i++) a[i] = m->minv[i] * (F[i] + P[i]);
                    hyb_contact_acc_planar(H, kin, y, a, qdd, lam, NULL, NULL);
                    model_patch_slip(m, cs, qdd, ua);
                    for (int i = 0; i < 3; i++) ea[i] = m->e[i] * ua[i];
                    sa = sqrt(ex_dot3(ea, ea));
                    if (!(sa > 0.0)) break;
                    /* the exact surface: its maximum-dissipation wrench of u' */
                    if (m->ls_exact) limitsurf_wrench(&m->ls, ua, wn, NULL);
                    for (int i = 0; i < 3; i++) {
                        wn[i] = m->ls_exact ? H->cap * wn[i] : -H->cap * m->e[i] * ea[i] / sa;
                        d = fmax(d, fabs(wn[i] - w[i]) / m->e[i]);
                        w[i] = wn[i];
                    }
                    H->st->stop_iterations++;
                    if (d <= SMALL_SLIP_FIX_TOL * H->cap) break;
                }
            }
        }
    }
    return EXDEX_OK;
}

int hyb_planar_friction(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, double F[3],
                        double w[3])
{
    const double cs[2] = {cos(y[2]), sin(y[2])};
    return planar_friction_cs(H, f, kin, y, cs, F, w);
}

/* The acceleration without stops of the current (non-stick) mode at y. */
int hyb_sf_free_acc(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, double a[3])
{
    hyb_pads(H, y);
    double F[3], w[3], P[3];
    int st = hyb_planar_friction(H, f, kin, y, F, w);
    if (st) return st;
    model_gen_of_patch(H->m, MODEL_CS(y[2]), w, P);
    for (int i = 0; i < 3; i++) a[i] = H->m->minv[i] * (F[i] + P[i]);
    return EXDEX_OK;
}

/* ------------------------------------------------------- right-hand side */

int hyb_rhs(double t, const double y[], double dy[], void *params)
{
    hyb *H = params;
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    int st = hyb_frame_seg(H, t, &f, &kin);
    if (st) {
        if (!H->err) H->err = st;
        return GSL_EBADFUNC;
    }
    for (int i = 0; i < H->ny; i++) dy[i] = 0.0;
    if (H->ndof == 1) {
        double q = y[0], v = y[1];
        if (H->mode == MODE_STICK) {
            dy[2] = -model_force_1dof(m, &f, q, 0.0);
        } else if (H->mode == MODE_CONTACT) {
            crow c;
            double qdd, R, fr, lam;
            double T = 0.0;
            hyb_hrow_1dof(H, &kin, H->ck, H->cj, q, &c);
            if (H->ss != 0.0) hyb_contact_slip_1dof(H, &kin, q, v, &T);
            qdd = hyb_contact_qdd(&c, v);
            R = H->M * qdd - model_force_1dof(m, &f, q, v);
            hyb_contact_forces(H, &c, T, R, v, &fr, &lam);
            dy[0] = v;
            dy[1] = qdd;
            dy[2] = fr;
            dy[3 + H->ck] = lam;
        } else {
            double Q = model_force_1dof(m, &f, q, v), fr;
            if (H->law == LAW_SMOOTH)
                fr = H->caps == H->cap ? -H->cap * v / sqrt(v * v + H->eps * H->eps) : -smooth_gain(H, fabs(v)) * v;
            else
                fr = -H->s * H->cap;
            dy[0] = v;
            dy[1] = (Q + fr) / H->M;
            dy[2] = fr;
        }
    } else {
        double F[3], w[3], P[3];
        const double *v = y + 3, cs[2] = {cos(y[2]), sin(y[2])};  /* one (cos, sin) of theta for the whole rhs */
        st = planar_friction_cs(H, &f, &kin, y, cs, F, w);
        if (st) {
            if (!H->err) H->err = st;
            return GSL_EBADFUNC;
        }
        if (H->mode == MODE_STICK && H->ncs) {
            double lam[MAX_ROWS];
            hyb_planar_rest(H, &kin, y, F, w, lam);
            for (int i = 0; i < H->ncs; i++) dy[9 + hyb_hrow_src(H, H->cs[i])] += lam[i];
        }
        if (H->mode != MODE_STICK) {
            double a[3];
            model_gen_of_patch(m, cs, w, P);
            for (int i = 0; i < 3; i++) {
                dy[i] = v[i];
                a[i] = m->minv[i] * (F[i] + P[i]);
                dy[3 + i] = a[i];
            }
            if (H->ncs) {
                double lam[MAX_ROWS];
                contact_acc_planar_cs(H, &kin, y, cs, a, dy + 3, lam, NULL, NULL);
                for (int i = 0; i < H->ncs; i++) dy[9 + hyb_hrow_src(H, H->cs[i])] += lam[i];
            }
        }
        dy[6] = cs[0] * w[0] - cs[1] * w[1];
        dy[7] = cs[1] * w[0] + cs[0] * w[1];
        dy[8] = w[2];
    }
    for (int i = 0; i < H->ny; i++)
        if (!isfinite(dy[i])) {
            if (!H->err) H->err = EXDEX_ENONFINITE;
            return GSL_EBADFUNC;
        }
    return GSL_SUCCESS;
}

/* The Jacobian of rhs for bsimp, by forward differences: the columns of
 * the configuration and velocity (planar: 6; the force integrals do not
 * enter rhs, their columns are 0), each perturbed by sqrt(DBL_EPSILON)
 * times the larger of its size and its scale (L, 1 rad, V, 1 / T), and
 * d/dt likewise over sqrt(DBL_EPSILON) max(|t|, T), backwards at the end
 * of the motion segment (rhs clamps t into it). */
int hyb_slip_jac(double t, const double y[], double *dfdy, double dfdt[], void *params)
{
    hyb *H = params;
    const model_scales *sc = &H->m->scale;
    int ny = H->ny, nq = H->ndof == 3 ? 6 : 2;
    double f0[NY_MAX], f1[NY_MAX], yp[NY_MAX], dt;
    double scale[6] = {sc->L, sc->L, 1.0, sc->V, sc->V, 1.0 / sc->T};
    if (H->ndof == 1) {
        scale[0] = sc->q;
        scale[1] = sc->q / sc->T;
    }
    if (hyb_rhs(t, y, f0, H) != GSL_SUCCESS) return GSL_EBADFUNC;
    memset(dfdy, 0, (size_t)(ny * ny) * sizeof *dfdy);
    memcpy(yp, y, (size_t)ny * sizeof *yp);
    for (int j = 0; j < nq; j++) {
        double d = sqrt(DBL_EPSILON) * fmax(fabs(y[j]), scale[j]);
        yp[j] = y[j] + d;
        d = yp[j] - y[j];
        if (hyb_rhs(t, yp, f1, H) != GSL_SUCCESS) return GSL_EBADFUNC;
        for (int i = 0; i < ny; i++) dfdy[i * ny + j] = (f1[i] - f0[i]) / d;
        yp[j] = y[j];
    }
    dt = sqrt(DBL_EPSILON) * fmax(fabs(t), sc->T);
    if (seg_time(H, t + dt) < t + dt) dt = -dt;
    dt = (t + dt) - t;
    if (hyb_rhs(t + dt, y, f1, H) != GSL_SUCCESS) return GSL_EBADFUNC;
    for (int i = 0; i < ny; i++) dfdt[i] = (f1[i] - f0[i]) / dt;
    return GSL_SUCCESS;
}
