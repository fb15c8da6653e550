/* explicit.c -- the naive baseline EXDEX_METHOD_EXPLICIT: explicit Coulomb
 * friction with sign(), symplectic Euler steps of dt,
 *     v+ = v + dt M^-1 (Q(t, q, v) + friction(v)),   q+ = q + dt v+,
 * friction -C E^2 u / |E u| (C = mu N, with a grip schedule its mean over
 * the step; the exact surface: C w(u), its maximum-dissipation wrench, and
 * its gauge in every test below that reads |E^-1 .|) and 0 at u = 0
 * exactly; the frame
 * accelerations enter as step means (model_frame_step). An output step
 * holding a switching time of the scene strictly inside (the motion's
 * acceleration switches and velocity jumps, the grip schedule's
 * breakpoints) is taken as sub-steps split there (model_substep), each the
 * step above with its own h; a velocity jump of the frame at a sub-step's
 * end is applied to the relative velocity there (model_velocity_jump) and
 * friction acts on it from the next sub-step on. The recorded wrench and
 * stop forces are means over the output step. Everything below ("per
 * step", h) holds per sub-step. Stops:
 * velocity-level rows G v+ >= -gap(q, t + dt)/dt; 1-DoF: a clamp; planar:
 * v+ is the M-metric projection of v* onto every (stop, vertex) row
 * (ldp_project), stop force lam / dt. Obstacles add their rows
 * (contact_obstacle_rows_pred, their pieces picked with the step's
 * velocity before the rows act, v*) to the same clamp and projection. Penetration
 * per step: every row enforces the linearisation g(q) + h G v+ >= 0 of its
 * gap at the step's start (G = dg/dq, contacts at t + h) and q+ = q + h v+,
 * so a row's gap after the step is at least the remainder
 * g(q + h v+) - g(q) - h G v+ (a vertex's gap is a maximum over faces or
 * edges, so the measured gap is no smaller) and nothing accumulates; with
 * phi = h thd+ (thd+ the rotation rate of v+), v = the centre of mass's
 * velocity in v+, R(phi) the rotation, J = R(pi/2):
 *   a vertex at offset l (|l| <= r_max) against a plane (stop or obstacle
 *   face, normal N): g = N.(r + R(theta) l) + c is linear in r, remainder
 *   N.(R(phi) - I - phi J) R l, at most 1/2 phi^2 r_max;
 *   an obstacle's section vertex y against an object edge (planar; body
 *   normal n0, offset d from the centre of mass): g = R(theta) n0.(y - r) - d,
 *   with n = R n0 the remainder is (R(phi) n - n - phi J n).(y - r)
 *   - h (R(phi) n - n).v, at most 1/2 phi^2 |y - r| + h |phi| |v|, and
 *   |y - r| <= r_max + h |v| when y ends inside the hull;
 *   a rod of radius rho normal to the plate plane (its section a disc,
 *   centre a) against the hull K: the row is the hull point V nearest a
 *   (R0 = |V - a| > 0, n = (V - a) / R0), whose material point moves while
 *   the nearest point slides along the hull, so the remainder of V's row
 *   does not bound the gap. K lies in the half-plane n.(x - V) >= 0 (V is
 *   the projection of a onto K), so the moved hull lies in
 *   R(phi) n.(x - V+) >= 0 and its distance from a is at least
 *   R(phi) n.(V+ - a) = cos(phi) n.(V+ - a) + sin(phi) Jn.(V+ - a). With
 *   V+ = V + h Vd + e (Vd = v + thd J (V - r) the point's velocity,
 *   |e| <= 1/2 phi^2 r_max the rotation's remainder), the row
 *   R0 + h n.Vd >= rho, and Jn.(V - a) = 0, the gap after the step is at
 *   least -(1 - cos phi) rho - |e| (1 + |phi|) - |phi| h |Vd|, i.e. at most
 *   1/2 phi^2 (rho + r_max (1 + |phi|)) + |phi| h (|v| + |thd| r_max)
 *   below 0 (1-DoF rotation: v = 0, r from the pivot; translation: 0).
 *   A tilted rod (an elliptic section) is checked against the same term,
 *   which this argument (Euclidean distance from a) does not cover.
 * So at most 1/2 h^2 thd^2 r_max per step with stops (1-DoF rotation: about
 * the pivot, r_max from it), and 1/2 h^2 thd^2 (r_max + h |v|)
 * + h^2 |thd| |v| for planar scenes with obstacles (the edge normal turns
 * while the object translates), at least the rod's term above with a rod;
 * 0 for translation. At stick
 * it chatters: with a load |Q| < C the velocity never returns to 0 but
 * circulates in (-dt (C - Q)/M, dt (C + Q)/M] (Q > 0) and creeps on average
 * at dt Q / M (1-DoF). Planar, the creep is not bounded by that band: in
 * the scaled slip s = E u (s_3 = e_r times the rotation rate) the step is
 * s+ = s + h K (a - C s / |s|), K = E J M^-1 J^T E, a the load; held
 * (|a| < C), the translational part of s chatters in a band ~ h C / m, and
 * the friction torque, C e_r s_3 / |s|, is then only the fraction
 * s_3 / |s| of C e_r, so the rotation runs until s_3 is comparable to the
 * band: the object turns at up to ~ (h C / m) / e_r (times rho /
 * sqrt(1 - rho^2), rho = |a| / C), first order in h but with a constant
 * 1 / e_r, far above the 1-DoF band h C e_r / I when e_r is small against
 * the object (the re-stick rule below removes it).
 *
 * Static friction (mu_static > mu, capacities C_s > C): the plates hold
 * the object at rest (v+ = 0 exactly) while the wrench that holds it,
 * w_h = -(the applied force as a patch wrench), lies in the static
 * ellipsoid, and else exert the kinetic wrench C w_h / |E^-1 w_h| (1-DoF:
 * -C sign(Q)): a breakaway at the static limit. A slip returns to rest
 * (re-stick) where the step stops it: with the kinetic friction of the
 * step's start the slip u* = u(v*) predicted at the step's end reverses,
 * (E u).(E u*) <= 0, or the mean friction that ends the step at rest,
 * w_st = the patch wrench of -M v / h - F, lies in the kinetic ellipsoid
 * (the step's kinetic friction impulse can stop it); there the slip reaches
 * 0 within the step, and the object is held (v+ = 0, the plates' mean wrench
 * w_st) iff w_h lies in the static ellipsoid; else (1-DoF) the step is
 * split where the kinetic step stops the slip, with the kinetic friction of
 * the load's sign beyond (exact under a load constant over the step), and
 * (planar) the kinetic step v* is kept. Why: under a load constant over the
 * step the exact (Coulomb) slip stops within the step iff the kinetic step
 * reverses it (1-DoF: v v* <= 0,
 * which contains the second test), and then sticks iff |Q| <= C_s, so the
 * rule makes the event method's slip -> stick decision with the step-start
 * load, an O(h) error in the stop time and O(h^2) in position per switch,
 * and the scheme converges at first order. Without it a slip never returns
 * to u = 0 exactly: it chatters as above with the kinetic capacity and
 * slides under loads between C and C_s where the exact solution sticks (an
 * O(1) error). With mu_static = mu the rule is off and the law is the
 * sign() baseline above, friction 0 at u = 0 (the chatter and its creep
 * are O(dt), so the two agree as dt -> 0). */
#include "exdex.h"
#include "contact.h"
#include "stop_impulse.h"
#include "ldp.h"
#include "method.h"
#include "model.h"
#include "util.h"

#include <stdlib.h>
#include <string.h>

/* Coulomb friction at the stops for the explicit step: the plate friction
 * is explicit (already in vs), so the contact step is the velocity-level
 * frictional problem of stop_impulse.h without a plate term (cap = 0): the
 * stop rows G v+ >= b with their tangential rows, exact complementarity by
 * mode enumeration. Applied when a frictional row carries an impulse in
 * the frictionless projection (else that projection is a solution of the
 * frictional problem too); rows (G, b, stop) as the caller built them at
 * t + h, with q the coordinates of the step's start: the stop rows r = k
 * nv + j first, then the obstacles' rows, each acting at cp[r - n_stops nv]
 * (contact_obstacle_rows; cp may be NULL without obstacle rows). Where no
 * consistent mode exists the frictionless projection is kept and a warning
 * counted. Returns 1 if v and lam were replaced. */
static int explicit_stop_friction(const exdex_model *m, const exdex_kinematics *kin_end, const double *q, int nr,
                                  const double (*Gr)[3], const double *b, const double *gap, const int *stop,
                                  const contact_point *cp, const double vs[3], double *v, double *lam,
                                  exdex_stats *st)
{
    fc_row rows[MAX_ROWS];
    fc_problem p;
    fc_result res;
    unsigned char hint[MAX_ROWS];
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], l[MAX_ROWS], beta[MAX_ROWS];
    int nv, need = 0, n = m->ndof;
    for (int i = 0; i < nr; i++) need |= lam[i] > 0.0 && model_source_mu(m, stop[i]) > 0.0;
    if (!need) return 0;
    nv = contact_vertices(m, q, xb, vx);
    memset(&p, 0, sizeof p);
    for (int i = 0; i < nr; i++) {
        fc_row *r = &rows[i];
        int j = i % nv;
        for (int c = 0; c < 3; c++) r->G[c] = c < n ? Gr[i][c] : 0.0;
        /* stop rows are r = k nv + j; an obstacle's row without its point
         * (cp NULL) stays frictionless */
        r->mu = i < m->n_stops * nv || cp ? model_source_mu(m, stop[i]) : 0.0;
        r->T[0] = r->T[1] = r->T[2] = 0.0;
        r->tb = 0.0;
        if (r->mu > 0.0) {
            if (i < m->n_stops * nv) {
                contact_stop_tangent(m, kin_end, stop[i], xb[j], vx[j], r->T, &r->tb);
            } else {
                const contact_point *c = &cp[i - m->n_stops * nv];
                contact_tangent(m, kin_end, c->x, c->vx, c->nB, r->T, &r->tb);
            }
        }
        r->rhs = b[i];
        r->rest = b[i] > m->tol.rate ? -1 : gap[i] <= m->tol.touch && b[i] >= -m->tol.rate ? 1 : 0;
        hint[i] = lam[i] > 0.0;
    }
    p.n = n;
    p.nr = nr;
    p.rows = rows;
    p.cap = 0.0;
    p.vrest = m->tol.rate;
    for (int c = 0; c < 3; c++) {
        p.A[c][c] = 1.0;
        p.vs[c] = c < n ? vs[c] : 0.0;
        p.Md[c] = 1.0;
    }
    if (n == 1) {
        p.Md[0] = m->def.dof == EXDEX_DOF_TRANSLATION ? m->m : m->mrot;
        p.vscale = m->scale.V * m->scale.q / m->scale.L;
    } else {
        for (int c = 0; c < 3; c++) p.Md[c] = 1.0 / m->minv[c];
        p.vscale = m->scale.V;
    }
    if (!fc_solve(&p, hint, v, NULL, l, beta, &res)) {
        st->warnings++;
        return 0;
    }
    st->stop_iterations += (size_t)res.iters;
    for (int c = 0; c < n; c++) v[c] = res.v[c];
    for (int i = 0; i < nr; i++) lam[i] = l[i];
    return 1;
}

/* The run's state between steps (its whole workspace). */
typedef struct explicit_ws {
    double q[3], v[3], t;
    exdex_kinematics kin0;
    model_sw_cache swc;   /* model_substep's */
} explicit_ws;

/* The workspace: the run's state (saved and restored as a whole) and, with
 * pads on the fingers, the model whose contact follows the state
 * (model_pads_follow; NULL without pads). */
typedef struct explicit_run {
    explicit_ws s;
    exdex_model *mc;
} explicit_run;

static int explicit_begin(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st)
{
    explicit_ws *w = ws;
    (void)t_end;
    (void)dt;
    (void)st;
    memset(w, 0, sizeof *w);
    model_sw_cache_reset(&w->swc);
    model_initial_state(m, w->q, w->v);
    return exdex_motion_eval(m->motion, 0.0, &w->kin0);
}

/* One sub-step from the time reached, w->t, to sub->te (model_substep):
 * the scheme at the top with h = te - t; then the frame's velocity jumps at
 * te, if any. On return (EXDEX_OK) the state is at te, wrench holds the
 * sub-step's plate wrench, lamsum each source's mean stop force and *still
 * the stick flag. */
static int explicit_substep(const exdex_model *m, explicit_ws *w, const model_sub *sub, double wrench[3],
                            double *lamsum, int *still, exdex_stats *st)
{
    int nd = m->ndof, ns = m->n_stops, nv = m->n_vert ? m->n_vert : 1, status = EXDEX_OK;
    double *q = w->q, *v = w->v, t = w->t, t1 = sub->te;
    exdex_kinematics kin0 = w->kin0;
    double rmax = contact_rot_radius(m);
    do {
        double h = t1 - t;
        exdex_kinematics kin, kin_end;
        frame f;
        wrench[0] = wrench[1] = wrench[2] = 0.0;
        status = model_frame_substep(m, &kin0, t, sub, h, &f, &kin, &kin_end);
        if (status) break;
        for (int k = 0; k < m->n_src; k++) lamsum[k] = 0.0;
        if (nd == 1) {
            int tr = m->def.dof == EXDEX_DOF_TRANSLATION;
            double capm = model_capacity_mean(m, t, t1), M = tr ? m->m : m->mrot, C = tr ? capm : capm * m->e[2];
            double Q = model_force_1dof(m, &f, q[0], v[0]);
            double fr = v[0] > 0.0 ? -C : v[0] < 0.0 ? C : 0.0;  /* -C sign(v) */
            double vn, lo = -INFINITY, hi = INFINITY, fqlo = 0.0, fqhi = 0.0;
            int klo = -1, khi = -1, jlo = -1, jhi = -1;  /* jlo, jhi: the stop row's vertex (-1: an obstacle's) */
            int held = 0;
            if (v[0] == 0.0 && m->capks != m->capk) {
                /* at rest: the static capacity holds, else kinetic breakaway */
                double capsm = model_capacity_static_mean(m, t, t1), Cs = tr ? capsm : capsm * m->e[2];
                held = fabs(Q) <= Cs;
                fr = held ? -Q : Q > 0.0 ? -C : C;
            } else if (m->capks != m->capk && v[0] * (v[0] + h * (Q + fr) / M) <= 0.0) {
                /* re-stick: the kinetic step reverses the slip, so it stops
                 * within the step; held iff the static capacity holds Q */
                double capsm = model_capacity_static_mean(m, t, t1), Cs = tr ? capsm : capsm * m->e[2];
                if (fabs(Q) <= Cs) {
                    held = 1;
                    fr = -M * v[0] / h - Q;   /* the step's mean friction: v+ = 0 */
                } else {
                    /* not held: it stops at tau = -M v / (Q + fr) inside the
                     * step and slides on the other way, driven by Q, for the
                     * rest of it: the step's mean friction is (tau fr + (h -
                     * tau) (-C sign Q)) / h, so v+ = (h - tau) (Q - C sign
                     * Q) / M, the exact slip under the step's load (the
                     * kinetic step v* keeps fr beyond the stop: a velocity
                     * off by 2 C (h - tau) / M, set by where the grid falls
                     * relative to the stop) */
                    double tau = -M * v[0] / (Q + fr);
                    fr = (tau * fr + (h - tau) * (Q > 0.0 ? -C : C)) / h;
                }
            }
            vn = held ? 0.0 : v[0] + h * (Q + fr) / M;  /* held: exactly at rest */
            /* stop rows at t + h: Fq v+ >= -gap(q, t + h) / h */
            for (int k = 0; k < ns; k++)
                for (int j = 0; j < nv; j++) {
                    crow c;
                    double b;
                    contact_row_1dof(m, &kin_end, k, j, q[0], &c);
                    if (!(fabs(c.Fq) > m->tol.fq_min)) continue;
                    /* held by static friction: a row whose gap closes at a
                     * rate below tol.rate (a touching stop's rounding, or its
                     * linearisation's remainder) does not move the object */
                    b = held && fabs(c.F / h) <= m->tol.rate ? 0.0 : -c.F / h / c.Fq;
                    if (c.Fq > 0 && b > lo) {
                        lo = b;
                        klo = k;
                        jlo = j;
                        fqlo = c.Fq;
                    } else if (c.Fq < 0 && b < hi) {
                        hi = b;
                        khi = k;
                        jhi = j;
                        fqhi = c.Fq;
                    }
                }
            if (m->n_obst) {
                /* the obstacles' rows, in the same form (contact_obstacle_rows) */
                double Go[MAX_ROWS][3], go[MAX_ROWS], ro[MAX_ROWS];
                double vp[3] = {vn, 0.0, 0.0};
                int so[MAX_ROWS], no = contact_obstacle_rows_pred(m, &kin_end, q, vp, h, Go, go, ro, so, NULL);
                for (int r = 0; r < no; r++) {
                    double b;
                    if (!(fabs(Go[r][0]) > m->tol.fq_min)) continue;
                    b = -go[r] / h / Go[r][0];
                    if (Go[r][0] > 0 && b > lo) {
                        lo = b;
                        klo = so[r];
                        jlo = -1;
                        fqlo = Go[r][0];
                    } else if (Go[r][0] < 0 && b < hi) {
                        hi = b;
                        khi = so[r];
                        jhi = -1;
                        fqhi = Go[r][0];
                    }
                }
            }
            if (lo > hi) {
                st->warnings++;
                hi = lo;
            }
            {
                double vc = vn < lo ? lo : vn > hi ? hi : vn;
                int kb = vc != vn ? (vn < lo ? klo : khi) : -1, jb = vn < lo ? jlo : jhi;
                double fq = vn < lo ? fqlo : fqhi;
                if (kb >= 0) lamsum[kb] = M * (vc - vn) / fq;
                if (kb >= 0 && m->stop_friction && model_source_mu(m, kb) > 0.0) {
                    /* the frictional rows: every (stop, vertex) row, then
                     * the obstacles' rows, as above */
                    double Gr[MAX_ROWS][3], b[MAX_ROWS] = {0}, gp[MAX_ROWS] = {0}, lam[MAX_ROWS], vv[3] = {vc, 0, 0};
                    double vs3[3] = {vn, 0, 0};
                    contact_point cpo[MAX_ROWS];
                    int stop[MAX_ROWS] = {0}, nr = 0, bound = 0;
                    for (int k = 0; k < ns; k++)
                        for (int j = 0; j < nv; j++) {
                            crow c;
                            contact_row_1dof(m, &kin_end, k, j, q[0], &c);
                            Gr[nr][0] = fabs(c.Fq) > m->tol.fq_min ? c.Fq : 0.0;
                            Gr[nr][1] = Gr[nr][2] = 0.0;
                            b[nr] = -c.F / h;
                            gp[nr] = c.F;
                            lam[nr] = k == kb && j == jb ? lamsum[kb] : 0.0;
                            bound |= k == kb && j == jb;
                            stop[nr++] = k;
                        }
                    if (m->n_obst) {
                        double ro[MAX_ROWS];
                        int i0 = nr;
                        nr += contact_obstacle_rows_pred(m, &kin_end, q, vs3, h, Gr + i0, gp + i0, ro, stop + i0, cpo);
                        for (int r = i0; r < nr; r++) {
                            /* the clamping row: the first of its obstacle with that bound */
                            int clamp = !bound && stop[r] == kb && fabs(Gr[r][0]) > m->tol.fq_min &&
                                        Gr[r][0] == (vn < lo ? fqlo : fqhi) && -gp[r] / h / Gr[r][0] == (vn < lo ? lo : hi);
                            if (!(fabs(Gr[r][0]) > m->tol.fq_min)) Gr[r][0] = 0.0;
                            Gr[r][1] = Gr[r][2] = 0.0;
                            b[r] = -gp[r] / h;
                            lam[r] = clamp ? lamsum[kb] : 0.0;
                            bound |= clamp;
                        }
                    }
                    if (explicit_stop_friction(m, &kin_end, q, nr, (const double (*)[3])Gr, b, gp, stop,
                                               m->n_obst ? cpo : NULL, vs3, vv, lam, st)) {
                        vc = vv[0];
                        for (int k = 0; k < m->n_src; k++) lamsum[k] = 0.0;
                        for (int r = 0; r < nr; r++) lamsum[stop[r]] += lam[r];
                    }
                }
                vn = vc;
            }
            q[0] += h * vn;
            v[0] = vn;
            if (tr) {
                wrench[0] = fr * m->d[0];
                wrench[1] = fr * m->d[1];
            } else {
                wrench[2] = fr;
            }
            *still = v[0] == 0.0;
        } else {
            double F[3], u[3], eu[3], sig, w[3] = {0, 0, 0}, P[3], wu[3] = {0, 0, 0};
            /* pads on the fingers: the contact region at the step's start */
            if (m->pads) model_pads_set((exdex_model *)m, q);
            model_force_planar(m, &f, q, v, F);
            model_patch_slip(m, MODEL_CS(q[2]), v, u);
            for (int c = 0; c < 3; c++) eu[c] = m->e[c] * u[c];
            /* the exact surface: its maximum-dissipation wrench of the slip,
             * D(u) > 0 for u != 0 */
            sig = !m->ls_exact ? sqrt(ex_dot3(eu, eu)) :
                  u[0] != 0.0 || u[1] != 0.0 || u[2] != 0.0 ? limitsurf_wrench(&m->ls, u, wu, NULL) : 0.0;
            if (m->ls_exact && !(isfinite(sig) && ex_finite_n(wu, 3))) {
                status = EXDEX_ENONFINITE;
                break;
            }
            int held = 0;
            if (sig > 0.0) {
                double capm = model_capacity_mean(m, t, t1);
                for (int c = 0; c < 3; c++) w[c] = m->ls_exact ? capm * wu[c] : -capm * m->e[c] * eu[c] / sig;
                if (m->capks != m->capk) {
                    /* re-stick (see the top): the kinetic step reverses the
                     * slip, or its friction can stop it within the step */
                    double vk[3], uk[3], rev = 0.0, Pst[3], wst[3];
                    model_gen_of_patch(m, MODEL_CS(q[2]), w, P);
                    for (int c = 0; c < 3; c++) {
                        vk[c] = v[c] + h * m->minv[c] * (F[c] + P[c]);
                        Pst[c] = -v[c] / (h * m->minv[c]) - F[c];
                    }
                    model_patch_slip(m, MODEL_CS(q[2]), vk, uk);
                    /* reversed: the step-start friction does work on the
                     * predicted slip (the ellipsoid: (E u) . (E u*) <= 0) */
                    if (m->ls_exact)
                        rev = -ex_dot3(wu, uk);
                    else
                        for (int c = 0; c < 3; c++) rev += eu[c] * m->e[c] * uk[c];
                    model_patch_of_gen(m, MODEL_CS(q[2]), Pst, wst);
                    if (rev <= 0.0 || model_ls_gauge(m, wst) <= capm) {
                        double mF[3] = {-F[0], -F[1], -F[2]}, wh[3];
                        model_patch_of_gen(m, MODEL_CS(q[2]), mF, wh);
                        held = model_ls_gauge(m, wh) <= model_capacity_static_mean(m, t, t1);
                        if (held) memcpy(w, wst, sizeof w);
                    }
                }
            } else if (m->capks != m->capk) {
                /* at rest: the static capacity holds, else kinetic breakaway */
                double mF[3] = {-F[0], -F[1], -F[2]}, nh;
                model_patch_of_gen(m, MODEL_CS(q[2]), mF, w);
                nh = model_ls_gauge(m, w);
                held = nh <= model_capacity_static_mean(m, t, t1);
                if (!held)
                    for (int c = 0; c < 3; c++) w[c] *= model_capacity_mean(m, t, t1) / nh;
            }
            model_gen_of_patch(m, MODEL_CS(q[2]), w, P);
            model_to_b(MODEL_CS(q[2]), w, wrench);
            for (int c = 0; c < 3; c++) v[c] = held ? 0.0 : v[c] + h * m->minv[c] * (F[c] + P[c]);
            if (ns || m->n_obst) {
                /* stop rows at t + h: G v+ >= -gap(q, t + h) / h, v+ the
                 * M-metric projection of v* (ldp_project); the obstacles'
                 * rows after the stops' */
                double Gr[MAX_ROWS][3], gap[MAX_ROWS], b[MAX_ROWS], lam[MAX_ROWS], vs[3];
                contact_point cpo[MAX_ROWS];
                int stop[MAX_ROWS], nr = contact_rows(m, &kin_end, q, Gr, gap, stop);
                if (m->n_obst) {
                    double ro[MAX_ROWS];
                    nr += contact_obstacle_rows_pred(m, &kin_end, q, v, h, Gr + nr, gap + nr, ro, stop + nr, cpo);
                }
                for (int r = 0; r < nr; r++)
                    b[r] = held && fabs(gap[r] / h) <= m->tol.rate ? 0.0 : -gap[r] / h;  /* as in 1-DoF */
                memcpy(vs, v, sizeof vs);
                if (ldp_project(m->minv, nr, (const double (*)[3])Gr, b, vs, FQ_MIN, v, lam, &st->stop_iterations, &st->warnings)) {
                    if (m->stop_friction)
                        explicit_stop_friction(m, &kin_end, q, nr, (const double (*)[3])Gr, b, gap, stop,
                                               m->n_obst ? cpo : NULL, vs, v, lam, st);
                    for (int r = 0; r < nr; r++) lamsum[stop[r]] += lam[r];
                }
            }
            for (int c = 0; c < 3; c++) q[c] += h * v[c];
            *still = v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0;
        }
        if (!ex_finite_n(q, nd) || !ex_finite_n(v, nd)) {
            status = EXDEX_ENONFINITE;
            break;
        }
        if (ns || m->n_obst) {
            /* beyond the scheme's own per-step bound (the remainder of the
             * rows' linearisation, derived at the top): the scene drives
             * the object through a stop (see tol.pen) */
            double thd = nd == 3 ? v[2] : m->def.dof == EXDEX_DOF_ROTATION ? v[0] : 0.0;
            double gmin = contact_min_gap(m, &kin_end, q), pen = 0.5 * h * h * thd * thd * rmax;
            double sp = nd == 3 ? hypot(v[0], v[1]) : 0.0, rho = 0.0;
            if (nd == 3 && m->n_obst) {
                /* a section vertex against an object edge (see the top) */
                pen += 0.5 * h * h * thd * thd * h * sp + h * h * fabs(thd) * sp;
            }
            for (int o = 0; o < m->n_obst; o++)
                if (m->def.obstacles[o].kind == EXDEX_OBSTACLE_CYLINDER) rho = fmax(rho, m->def.obstacles[o].radius);
            if (rho > 0.0 && thd != 0.0) {
                /* a rod's row: the hull point nearest its axis (see the top) */
                double phi = fabs(h * thd);
                pen = fmax(pen, 0.5 * phi * phi * (rho + rmax * (1.0 + phi)) + phi * h * (sp + fabs(thd) * rmax));
            }
            if (gmin < st->min_gap) st->min_gap = gmin;
            if (gmin < -(m->tol.pen + pen) || contact_unreachable(m, &kin_end, q))
                st->warnings++;
        }
        t = t1;
        for (int k = 0; k < m->n_src; k++) lamsum[k] /= h;
        if (sub->jumps) {
            /* the frame's velocity jumps at te: the relative velocity jumps
             * (the plates carry no impulse); friction acts on it from the
             * next sub-step on */
            model_substep_jump(m, sub, q, v, &kin_end);
            if (!ex_finite_n(v, nd)) {
                status = EXDEX_ENONFINITE;
                break;
            }
            *still = nd == 1 ? v[0] == 0.0 : v[0] == 0.0 && v[1] == 0.0 && v[2] == 0.0;
        }
        kin0 = kin_end;
    } while (0);
    w->t = t;
    w->kin0 = kin0;
    return status;
}

/* One output step from the time reached to t1, recorded as sample i: its
 * sub-steps (model_substep), the recorded wrench and stop forces their
 * means over the output step weighted by their lengths (one sub-step: its
 * own values, bit for bit), the stick flag set when every sub-step stuck
 * (the object held through the whole output step). */
static int explicit_advance(const exdex_model *m, void *ws, double t1, int regrip, exdex_trajectory *out,
                            size_t i, exdex_stats *st)
{
    explicit_ws *w = ws;
    double t0 = w->t, H = t1 - t0, wrench[3] = {0, 0, 0}, sf[EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES];
    int status = EXDEX_OK, still = 0, first = 1;
    (void)regrip;   /* the capacity is read at every step */
    /* with pads m is then the run's own copy (model_pads_set writes it) */
    if (((explicit_run *)ws)->mc) m = model_pads_follow(m, ((explicit_run *)ws)->mc);
    while (w->t < t1) {
        model_sub sub;
        int sub_still = 0;
        double wr[3], sfs[EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES], ts = w->t, wt;
        int whole;
        model_substep(m, &w->swc, ts, t1, &sub);
        /* the whole output step as one sub-step records its own values */
        whole = first && !sub.split;
        status = explicit_substep(m, w, &sub, whole ? wrench : wr, whole ? sf : sfs, whole ? &still : &sub_still, st);
        if (status) return status;
        if (whole) break;
        still = first ? sub_still : still && sub_still;
        wt = (sub.te - ts) / H;
        method_add_sub(first, wt, wr, sfs, m->n_src, wrench, sf);
        first = 0;
    }
    st->steps++;   /* one step per sample: its sub-steps are parts of it */
    method_record(m, out, st, i, t1, w->q, w->v, wrench, still, sf);
    return status;
}

static void *explicit_alloc(const exdex_model *m, int *status)
{
    explicit_run *w = malloc(sizeof *w);
    if (!w) {
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    w->mc = NULL;
    if (m->pads && !(w->mc = calloc(1, sizeof *w->mc))) {
        free(w);
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    return w;
}

static void explicit_free(void *ws)
{
    if (ws) free(((explicit_run *)ws)->mc);
    free(ws);
}

static void explicit_save(const void *ws, void *buf) { memcpy(buf, ws, sizeof(explicit_ws)); }
static int explicit_restore(void *ws, const void *buf)
{
    memcpy(ws, buf, sizeof(explicit_ws));
    return EXDEX_OK;
}

const method_impl method_explicit = {"explicit", explicit_alloc, NULL, explicit_free, 1, 0,
                                     explicit_begin, explicit_advance, sizeof(explicit_ws), explicit_save,
                                     explicit_restore, NULL};
