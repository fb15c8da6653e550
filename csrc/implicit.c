/* implicit.c -- the implicit time-stepping method (EXDEX_METHOD_IMPLICIT)
 * with the friction ellipsoid (paper Eq. 6) and external stops, on the
 * model's equations of motion M qdd = Q(t, q, qd) + friction + stops
 * (model.c, paper Eqs. 3-5).
 *
 * Time stepping (Moreau's midpoint scheme, velocity level):
 *     q_m = q + h/2 v,   forces at (t + h/2, q_m, v),   v* = v + h M^-1 Q,
 *     v+ = v* + M^-1 (J_f^T p + G^T lambda),   q+ = q_m + h/2 v+,
 * with the friction impulse p from the maximum-dissipation problem (Eq. 6)
 * and stop impulses lambda >= 0 keeping every stop gap >= 0 at t + h.
 * Stick is exact: when the friction impulse can hold the object, v+ = 0.
 *
 * Sub-steps: an output step (t, t1] that holds one of the scene's switching
 * times (the motion's acceleration switches and velocity jumps, the grip
 * schedule's breakpoints) strictly inside is taken as sub-steps split there
 * (model_substep), each the step above with its own h; so the frame's
 * step-mean accelerations and the capacity's step mean are those of one
 * smooth phase, and a stick -> slip onset at a switch starts there. A
 * velocity jump of the frame at the end of a sub-step is applied to the
 * relative velocity there (model_velocity_jump: the plates carry no
 * impulse), and friction acts on it from the next sub-step on: the slide
 * it starts carries the scheme's own errors (the slide stopping inside a
 * step of length h from a slip speed u <= h C / M moves h u / 2 instead of
 * u^2 / (2 a), a the deceleration: at most h min(|dqd|, h a) / 2 for a
 * jump dqd), not an error of the jump; where it stops inside a step that
 * is located (slip_stop_in_step, slip_stop_in_step_planar), and a planar
 * slip that slides through the sub-step after the jump, whose length the
 * jump's position sets (the same on nested grids), follows the slip's own
 * law over it (slip_through_step_planar). Samples stay on the output grid;
 * the recorded wrench and stop forces are means over the output step. The
 * velocity extrapolated for the midpoint's velocity-dependent terms is not
 * carried across a switching time (it restarts from the step's start
 * velocity).
 *
 * Static and kinetic friction (capacities C_s = mu_static N >= C = mu N):
 * a step that starts at rest sticks with the static capacity (the impulse
 * that makes v+ = 0, stops included, inside the ellipsoid of capacity h
 * C_s) and else slides with the kinetic capacity h C (the
 * maximum-dissipation impulse on that ellipsoid): it breaks away once the
 * load leaves the static ellipsoid. A step that starts slipping is solved
 * with the kinetic capacity alone: it ends at rest where the kinetic
 * impulse can stop the slip within the step, and where the kinetic step
 * passes the slip through zero (1-DoF: v+ reverses; planar: restick_planar)
 * the slip stopped inside the step and the static capacity decides whether
 * it stays (slip_stop_in_step). So slip -> stick needs the slip to reach
 * zero under the kinetic law, as in the exact solution: a slip that slows
 * to a speed below h C_s / M without stopping slides on (a static test on
 * it would stick it, an O(1) error however short the step). With mu_static
 * = mu the two capacities are the same number and the step is the
 * one-coefficient step.
 *
 * Where the slip stops inside a step, the step's end state is that of the
 * slip stopping under the step's force (slip_stop_in_step, 1-DoF: also a
 * reversal through zero, stopping and breaking away; the planar form
 * slip_stop_in_step_planar), and a translation step that a stop pushes
 * ends with the held contact's velocity (held_velocity_1dof): errors that
 * the step's own end state would make depend on where the switch falls in
 * the step, the same on every level of a nested step ladder.
 */
#include "exdex.h"
#include "contact.h"
#include "stop_impulse.h"
#include "ldp.h"
#include "method.h"
#include "model.h"
#include "obstacle_rows.h"
#include "util.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>

/* Mutable per-call workspace (nothing is allocated in the step loop). */
typedef struct work {
    exdex_friction_ws *fws;
    double p_prev[3];
    int have_prev;
    int n_rows;
    int row_stop[MAX_ROWS];
    double G[MAX_ROWS][3];
    double rhs[MAX_ROWS];
    double lam[MAX_ROWS];
    double gap[MAX_ROWS];
    /* the run's state between steps (begin, advance; saved with p_prev,
     * have_prev and fmode) */
    struct {
        double q[3], v[3], vprev[3], hprev, t;
        exdex_kinematics kin0;
    } S;
    double beta[MAX_ROWS];   /* friction impulses of the rows (stop friction) */
    int fmode[MAX_ROWS];     /* each row's contact mode in the last frictional solve (stop_impulse.h) */
    contact_point cpt[MAX_ROWS];  /* where each obstacle row acts (build_rows; rows from n_stops nv on) */
    model_sw_cache swc;           /* model_substep's */
    /* the in-step slip stop's integrator (slip_stop_in_step_planar; planar
     * models only, NULL otherwise) */
    gsl_odeiv2_step *slip_step;
    gsl_odeiv2_control *slip_con;
    gsl_odeiv2_evolve *slip_evo;
    exdex_model *mc;   /* pads on the fingers: the model whose contact follows the state
                          (model_pads_follow); NULL without pads */
} work;

/* ------------------------------------------------------------ stops */

/* Collect the stop rows for the step from t (coordinates q) to t+h: the
 * linearised gap of q + h v+ at the gripper pose of t+h must be >= 0, i.e.
 * G v+ >= -gap(q, t+h) / h. (A row on the midpoint position, gap(q_m) +
 * h/2 G v+ >= 0, makes v+ = 2 V - v against a stop moving at V: a period-2
 * velocity oscillation that never decays. Any penetration this row leaves
 * through the midpoint position update, h/2 |v+ - v| at most, is removed by
 * project_positions after the step.) */
/* A gap within its own rounding of zero counts as exactly 0 in the row
 * (rhs = 0, not -gap/h). An object resting against a stop that does not move
 * relative to B sits at a gap that is 0 in exact arithmetic, and the sign of
 * the rounding (which depends on the world frame the data is given in: gap_at
 * works in A) decides whether the stop bound on v+ is +-1e-14 m/s. Across
 * that sign Coulomb friction switches from static (stick, no stop impulse) to
 * kinetic (sliding at 1e-14 m/s, the stop carries the rest) and the position
 * update from Moreau's midpoint to "pushed" (see exdex_simulate), a jump of
 * h/2 |v - v+| in q: a rounding-level change of the frame moved a trajectory
 * by 2e-7 m. Counting such gaps as 0 makes both frames take the static
 * branch. The bound is 8 rounding units of the sum of the magnitudes gap_at
 * adds (|x_B|, |p|, |stop point|; R is orthonormal). */

static void build_rows(const exdex_model *m, const exdex_kinematics *kin_end, const double *q,
                       const double *vp, double h, work *w)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
    int nv = contact_vertices(m, q, xb, vx);
    w->n_rows = 0;
    for (int k = 0; k < m->n_stops; k++)
        for (int j = 0; j < nv; j++) {
            int i = w->n_rows++;
            double tau = contact_gap_round(m, kin_end, k, xb[j]);
            w->row_stop[i] = k;
            w->gap[i] = contact_gap(m, kin_end, k, xb[j], vx[j], w->G[i]);
            w->rhs[i] = fabs(w->gap[i]) <= tau ? 0.0 : -w->gap[i] / h;
            w->lam[i] = 0.0;
        }
    if (m->n_obst) {
        /* the obstacles' rows, in the same form (contact_obstacle_rows) */
        double rnd[MAX_ROWS];
        int i0 = w->n_rows,
            no = contact_obstacle_rows_pred(m, kin_end, q, vp, h, w->G + i0, w->gap + i0, rnd, w->row_stop + i0,
                                            w->cpt + i0);
        for (int i = i0; i < i0 + no; i++) {
            w->rhs[i] = fabs(w->gap[i]) <= rnd[i - i0] ? 0.0 : -w->gap[i] / h;
            w->lam[i] = 0.0;
        }
        w->n_rows += no;
    }
}

/* The step's rows (build_rows), none in a scene without stops and
 * obstacles. The obstacles' rows take their pieces by the tie rule of
 * contact_obstacle_rows_pred with the predicted velocity vs = v + h M^-1 Q,
 * the step's velocity without contact or friction impulses: at rest (v = 0)
 * it is the direction the applied forces drive the object in. */
static void build_rows_or_none(const exdex_model *m, const exdex_kinematics *kin_end, const double *q,
                               const double *vs, double h, work *w)
{
    if (m->n_stops || m->n_obst) {
        build_rows(m, kin_end, q, vs, h, w);
    } else {
        w->n_rows = 0;
    }
}

/* 1-DoF step: min 1/2 M (v - vs)^2 + c |v| subject to G_i v >= rhs_i
 * (c the kinetic capacity of the step, cs the capacity of its stick test).
 * Exact: soft-threshold, then clamp into the feasible interval. The impulse
 * split is unique while sliding (friction = capacity, the binding stop the
 * rest). At rest (v+ = 0) against a touching stop it is statically
 * indeterminate; exdex lets the stops carry what they can (the split with the
 * least friction), as in the planar case. */
static void step_1dof(double M, double c, double cs, double vs, double touch, work *w, double *v_out,
                      double *pf, exdex_stats *st)
{
    double vu, v, P, lo = -INFINITY, hi = INFINITY;
    int ilo = -1, ihi = -1, ib;
    /* stick if the static capacity cs holds, else slide against c */
    if (fabs(M * vs) <= cs)
        vu = 0.0;
    else
        vu = vs - copysign(c / M, vs);
    for (int i = 0; i < w->n_rows; i++) {
        double g = w->G[i][0];
        if (g > 0) {
            double b = w->rhs[i] / g;
            if (b > lo) { lo = b; ilo = i; }
        } else if (g < 0) {
            double b = w->rhs[i] / g;
            if (b < hi) { hi = b; ihi = i; }
        } else if (w->rhs[i] > 0) {
            st->warnings++;  /* a stop parallel to the free direction cannot act */
        }
    }
    if (lo > hi) {  /* stops pinch the object: keep the lower bound, count it */
        st->warnings++;
        hi = lo;
    }
    v = vu;
    ib = -1;
    if (v < lo) { v = lo; ib = ilo; }
    if (v > hi) { v = hi; ib = ihi; }
    P = M * (v - vs);  /* total impulse: friction + stops */
    if (v == 0.0) {
        /* at rest: a touching stop pushing the way P points takes it all */
        ib = -1;
        for (int i = 0; i < w->n_rows; i++)
            if (w->gap[i] <= touch && w->G[i][0] * P > 0) ib = i;
        if (ib >= 0) {
            w->lam[ib] = P / w->G[ib][0];
            *pf = 0.0;
        } else {
            *pf = P;
        }
    } else if (ib >= 0) {
        double p = -copysign(c, v), lam = (P - p) / w->G[ib][0];
        *pf = p;
        w->lam[ib] = lam > 0 ? lam : 0.0;
    } else {
        *pf = P;
    }
    *v_out = v;
}

/* A 1-DoF step that starts slipping (v != 0) and ends at rest or slipping
 * the other way (v+ = 0 or sign v+ = -sign v), with no stop impulse: where
 * inside the step the slip stops. With the step's applied force Q and
 * kinetic capacity C (forces; torques for a rotation) held constant over the
 * step, the slip decelerates at d = (C - s Q) / M (s = sign v) and stops at
 * t* = |v| / d, having moved v t* / 2. If t* < h, the step's end state is
 * that of this motion: at rest at q + v t* / 2 when the static capacity
 * holds the load (|Q| <= C_s), else broken away at once the way Q points,
 * v+ = a (h - t*) with a = (Q - C sign Q) / M, at q + v t* / 2 + v+ (h - t*)
 * / 2. Otherwise (d <= 0: the kinetic law never stops this slip, or t* >= h)
 * the step keeps its own end state.
 *
 * Why: the step's own end state treats the whole step as one friction
 * phase. A stick step ends where Moreau's midpoint puts it, h v / 2 from q
 * (v t* / 2 exactly); a reversal either stalls at rest until the step's end
 * (v+ off by (h - t*) |a|) or slides through it with the friction of the
 * new direction over the whole step (v+ off by 2 C t* / M). These errors
 * are set by where t* falls in its step, and in a ladder of nested grids (h,
 * h/2, h/4, ...) a t* near an end of a step of the coarsest grid falls in
 * the fine step at that end on every level down to a fine enough one: the
 * error is the same on those levels, and their differences do not show it.
 * With t* located to O(h^2) (the variation of Q over the step) none of these
 * errors remains at first order. A slip that starts at a velocity jump of
 * the frame (model_substep) and stops within the short sub-step after it is
 * the same case. With C_s = C, t* < h exactly when the step's own end state
 * is at rest or reversed. Returns 1 and sets *v_end and *dq (the step's
 * displacement) when t* < h. */
static int slip_stop_in_step(double M, double Q, double C, double Cs, double h, double v, double *v_end, double *dq)
{
    double d = (C - (v > 0.0 ? Q : -Q)) / M, ts;
    if (!(d > 0.0)) return 0;
    ts = fabs(v) / d;
    if (!(ts < h)) return 0;
    if (fabs(Q) <= Cs) {
        *v_end = 0.0;
        *dq = 0.5 * v * ts;
    } else {
        *v_end = (Q - copysign(C, Q)) / M * (h - ts);
        *dq = 0.5 * v * ts + 0.5 * *v_end * (h - ts);
    }
    return 1;
}

/* A translation step in which a stop row pushes the object along (v+ != 0
 * set by that row's bound, impulse lam > 0) ends with the object on the
 * stop: its position is where the row put it, q + h v+ (gap 0: the row is
 * linear in q), but v+ = -gap(q, t + h) / (h G) is the stop's mean rate
 * over the step, off the velocity of the held contact at t + h by O(h)
 * (half the step times the stop's acceleration in B). While the contact holds that error stays in
 * v and never reaches q; where the object leaves the stop it carries into
 * the free motion, and where it leaves at a switching time of the motion
 * (the stop's acceleration changes sign there) it is set by the sub-step
 * before the switch, whose length is the same on every level of a nested
 * grid ladder that has the same grid point before the switch: an error
 * that differences between levels do not show. The end velocity is
 * therefore the held contact's, the v_e with F_q v_e + F_t = 0 at t + h
 * and q + h v+ (contact_row_1dof: the gap's rates), and the row's impulse
 * carries the change, lam += M (v_e - v+) / G, so that the step's momentum
 * balance M (v_e - v) = h Q + p_f + G lam still holds: for a row of a
 * plane fixed in A (a stop, or an outline vertex on a polytope's face).
 * Several rows pushing the same way (an edge flush against a stop): v_e is
 * the held velocity that keeps every one's gap from closing (the largest
 * of theirs along the push), its row carrying the change. Left as it is
 * when rows push from both sides, when v_e and v+ have opposite signs (the
 * stop turns from pushing to receding inside the step: whether the object
 * follows it is a stick decision), for the other obstacle rows (a
 * section vertex on the outline's edge, a rod, a disc outline), when F_q =
 * 0, or when the change would make lam negative (the contact would
 * have to pull: the object leaves the stop there). A rotation's row is
 * linearised in q, so its step ends off the stop by the row's curvature
 * and v+ is what closes that over the next steps: left too (and a zoo
 * rotation scene has stops only where they do not move in B, F_t = 0).
 * Returns v_e, or NAN when left. */
static double held_rate_1dof(const exdex_model *m, const exdex_kinematics *kin_end, double qe, const double *q,
                             const work *w, int i)
{
    int nv = contact_nv(m);
    crow c;
    if (i < m->n_stops * nv) {
        contact_row_1dof(m, kin_end, w->row_stop[i], i % nv, qe, &c);
    } else {
        /* an obstacle's row: the same row as the event method holds it
         * (orow_all and contact_obstacle_rows_pred are views of one
         * builder: the same rows in the same order; orow_all's feature the
         * largest piece at q), its feature kept at the step's end; an
         * outline vertex on a polytope's face only (a plane fixed in A, as
         * a stop) */
        int code[MAX_ROWS], io = i - m->n_stops * nv, no;
        if (m->disc_r > 0.0) return NAN;
        no = orow_all(m, kin_end, q, NULL, 0, code, NULL);
        if (no != w->n_rows - m->n_stops * nv || orow_kind(code[io]) != OROW_VERTEX) return NAN;
        orow_1dof(m, kin_end, code[io], qe, &c);
    }
    return c.Fq != 0.0 ? -c.Ft / c.Fq : NAN;
}

static double held_velocity_1dof(const exdex_model *m, const exdex_kinematics *kin_end, double q, double h,
                                 double M, double v, work *w)
{
    int ib = -1, sign = 0;
    double ve = NAN, lam;
    if (v == 0.0 || m->def.dof != EXDEX_DOF_TRANSLATION) return NAN;
    for (int i = 0; i < w->n_rows; i++) {
        double vi;
        int si;
        if (!(w->lam[i] > 0.0)) continue;
        si = w->G[i][0] > 0.0 ? 1 : w->G[i][0] < 0.0 ? -1 : 0;
        if (!si || (sign && si != sign)) return NAN;
        sign = si;
        vi = held_rate_1dof(m, kin_end, q + h * v, &q, w, i);
        if (!isfinite(vi)) return NAN;
        /* the held velocity keeps every pushing row's gap from closing */
        if (ib < 0 || (sign > 0 ? vi > ve : vi < ve)) {
            ib = i;
            ve = vi;
        }
    }
    /* a stop whose rate passes zero inside the step (ve against v+) turns
     * from pushing to receding: whether the object follows it or stays is a
     * stick decision the held contact does not make */
    if (ib < 0 || ve * v < 0.0) return NAN;
    lam = w->lam[ib] + M * (ve - v) / w->G[ib][0];
    if (!(lam >= 0.0)) return NAN;
    w->lam[ib] = lam;
    return ve;
}

/* ------------------------------------------------------------ the step loop */

/* Can the object stay exactly at rest (v+ = 0) with stop impulses lambda >= 0
 * on the touching rows and a friction impulse inside the ellipsoid? The
 * friction needed is p(lambda) = -J^-T (M v* + G^T lambda); minimise
 * |E^-1 p(lambda)| over lambda >= 0 (ldp_min_combination). Rest holds iff
 * that minimum <= cap; the minimiser is the split with the least friction
 * (the stops carry what they can). The exact surface: its gauge in place of
 * |E^-1 .| (limitsurf_min_combination, which stops at the first split the
 * surface carries). */
static int try_rest(const exdex_model *m, const double cs[2], double cap, const double vs[3], work *w,
                    double pfB[3], exdex_friction_result *fr, exdex_stats *st)
{
    int rows[MAX_ROWS], k = 0, it = 0;
    double a[3], B[MAX_ROWS][3], lam[MAX_ROWS], P[3], best;
    for (int i = 0; i < w->n_rows; i++) {
        if (w->rhs[i] > 0.0 && w->gap[i] < -m->tol.touch) return 0; /* rest would penetrate */
        if (w->gap[i] <= m->tol.touch) rows[k++] = i;
    }
    for (int i = 0; i < 3; i++) P[i] = vs[i] / m->minv[i];
    model_patch_of_gen(m, cs, P, a);
    if (m->ls_exact) {
        /* the exact surface's least gauge over the stop forces */
        for (int j = 0; j < k; j++) model_patch_of_gen(m, cs, w->G[rows[j]], B[j]);
        best = limitsurf_min_combination(&m->ls, k, a, (const double (*)[3])B, cap, lam, &it);
    } else {
        for (int i = 0; i < 3; i++) a[i] /= m->e[i];
        for (int j = 0; j < k; j++) {
            model_patch_of_gen(m, cs, w->G[rows[j]], B[j]);
            for (int i = 0; i < 3; i++) B[j][i] /= m->e[i];
        }
        best = ldp_min_combination(k, a, (const double (*)[3])B, lam, &it);
    }
    st->stop_iterations += (size_t)it;
    if (!(best <= cap * (1.0 + FRICTION_BAND))) return 0;
    for (int i = 0; i < w->n_rows; i++) w->lam[i] = 0.0;
    for (int j = 0; j < k; j++) {
        w->lam[rows[j]] = lam[j];
        for (int c = 0; c < 3; c++) P[c] += lam[j] * w->G[rows[j]][c];
    }
    for (int c = 0; c < 3; c++) pfB[c] = -P[c];
    model_patch_of_gen(m, cs, pfB, fr->p);
    fr->u[0] = fr->u[1] = fr->u[2] = 0.0;
    fr->sigma = 0.0;
    fr->stick = 1;
    fr->iterations = 0;
    return 1;
}

/* a M^-1 b for generalized vectors a, b (M^-1 = diag(minv)). */
static double gmg(const exdex_model *m, const double a[3], const double b[3])
{
    return a[0] * m->minv[0] * b[0] + a[1] * m->minv[1] * b[1] + a[2] * m->minv[2] * b[2];
}

/* Friction slip map in B generalized coordinates, scaled: r = E J_f v. */
static void ejf(const exdex_model *m, const double cs[2], const double v[3], double r[3])
{
    model_patch_slip(m, cs, v, r);
    for (int i = 0; i < 3; i++) r[i] *= m->e[i];
}

/* The planar form of slip_stop_in_step, for a step that starts slipping
 * (v != 0) and ends at rest with no stop impulse. The slip under the step's
 * applied force F (held constant, as the orientation cs) and kinetic
 * friction obeys
 *     M vdot = F + J^T w,   w = -C E z / |z|,   z = E J v
 * (the patch wrench opposing the scaled slip z, ejf; C the kinetic
 * capacity). M^-1 commutes with the plane rotation in J, so
 *     zdot = A (b - C z / |z|),   A = E J' M^-1 J'^T E,
 * b = E^-1 J^-T F (the load of try_rest's test; z . b is the rate at which F
 * feeds the slip). The friction's direction turns as the slip decays, unless
 * F and A are aligned with it, at a rate ~ C |A| / |z| that grows without
 * bound as z -> 0 (towards A's weakest directions, where the object can
 * still move most: often a slow spin): no closed form, and a fixed division
 * of the stop time misses the end of the slip. On the slip's own clock
 * ds = C dt / |z| the law is
 *     dz/ds = A (b |z| / C - z),   dt/ds = |z| / C,   dZ/ds = z |z| / C
 * (Z the integral of z over time), Lipschitz and homogeneous of degree 1 in
 * z: z decays exponentially in s, stiff by A's condition number, while t
 * converges to the stop time t*. It is integrated by GSL's bsimp (linearly
 * implicit Bulirsch-Stoer, with the Jacobian below) in the units r0 = |z0|,
 * a = tr A, C (y = (z / r0, t C a / r0, Z a C / r0^2), s a), until |z| <=
 * SLIP_END r0; the step's displacement is dq = Rz J'^-1 E^-1 Z. The slip
 * stops when |b| < C: V = z^T A^-1 z / 2 has dV/dt = z . (b - C z / |z|) <=
 * -(C - |b|) |z|, so from |z| = r it stops within r / (lmin (C - |b|)) at
 * speeds |z| <= r sqrt(lmax / lmin) (lmin, lmax A's eigenvalues), and the
 * part of Z left out is at most r^2 sqrt(lmax / lmin) / (lmin (C - |b|)):
 * with r = SLIP_END r0 a fraction 1e-20 (lmax / lmin)^(3/2) / (1 - |b| / C)
 * of r0^2 / (lmax C) (the slide's scale in its stiffest direction). Applied
 * when the load at rest is held (|b| <= C_s: the object stays at rest after
 * the stop) and t* < h; otherwise (a load beyond the static capacity
 * breaks away at once, t* >= h, or the integration fails or takes more than
 * SLIP_STEPS steps) the step keeps its own end state, q + h v / 2 at rest.
 * Returns 1 and sets dq (the step's displacement) when applied. */
#define SLIP_END 1e-10    /* |z| / |z0| where the integration ends */
#define SLIP_TOL 1e-12    /* its absolute and relative error per step (scaled units) */
#define SLIP_STEPS 2000   /* its step budget */
#define SLIP_DIM 7

typedef struct slip_law {
    double A[3][3];   /* A / a */
    double b[3];      /* b / C */
} slip_law;

static int slip_rhs(double s, const double y[], double f[], void *par)
{
    const slip_law *L = par;
    double r = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]), d[3];
    (void)s;
    for (int i = 0; i < 3; i++) d[i] = L->b[i] * r - y[i];
    for (int i = 0; i < 3; i++) {
        f[i] = L->A[i][0] * d[0] + L->A[i][1] * d[1] + L->A[i][2] * d[2];
        f[4 + i] = y[i] * r;
    }
    f[3] = r;
    return GSL_SUCCESS;
}

static int slip_jac(double s, const double y[], double *J, double dfdt[], void *par)
{
    const slip_law *L = par;
    double r = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]), n[3];
    (void)s;
    for (int i = 0; i < 3; i++) n[i] = r > 0.0 ? y[i] / r : 0.0;
    for (int i = 0; i < SLIP_DIM * SLIP_DIM; i++) J[i] = 0.0;
    for (int i = 0; i < 3; i++) {
        /* d/dz of A (b |z| - z): A (b n^T - I) */
        double Ab = L->A[i][0] * L->b[0] + L->A[i][1] * L->b[1] + L->A[i][2] * L->b[2];
        for (int j = 0; j < 3; j++) {
            J[i * SLIP_DIM + j] = Ab * n[j] - L->A[i][j];
            /* d/dz of z |z|: |z| I + z n^T */
            J[(4 + i) * SLIP_DIM + j] = (i == j ? r : 0.0) + y[i] * n[j];
        }
        J[3 * SLIP_DIM + i] = n[i];   /* d|z|/dz */
    }
    for (int i = 0; i < SLIP_DIM; i++) dfdt[i] = 0.0;
    return GSL_SUCCESS;
}

static int slip_stop_in_step_planar(const exdex_model *m, work *w, const double cs[2], double C, double Cs,
                                    double h, const double v0[3], const double F[3], double dq[3])
{
    slip_law L;
    gsl_odeiv2_system sys = {slip_rhs, slip_jac, SLIP_DIM, &L};
    double b[3], bb, z[3], r0, a = 0.0, y[SLIP_DIM], s = 0.0, ds, tmax, Z[3], u[3];
    if (!w->slip_evo) return 0;
    model_patch_of_gen(m, cs, F, b);
    for (int i = 0; i < 3; i++) b[i] /= m->e[i];
    bb = ex_dot3(b, b);
    if (!(bb <= Cs * Cs) || !(C * C - bb > 0.0)) return 0;
    ejf(m, cs, v0, z);
    r0 = sqrt(ex_dot3(z, z));
    if (!(r0 > 0.0) || !isfinite(r0)) return 0;
    {
        /* A = E W E, W = J' M^-1 J'^T (J' = [[1, 0, -pc_y], [0, 1, pc_x], [0, 0, 1]]) */
        double Jp[3][3] = {{1.0, 0.0, -m->pc[1]}, {0.0, 1.0, m->pc[0]}, {0.0, 0.0, 1.0}};
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double sum = 0.0;
                for (int k = 0; k < 3; k++) sum += Jp[i][k] * m->minv[k] * Jp[j][k];
                L.A[i][j] = m->e[i] * sum * m->e[j];
            }
        for (int i = 0; i < 3; i++) a += L.A[i][i];
        if (!(a > 0.0) || !isfinite(a)) return 0;
        for (int i = 0; i < 3; i++) {
            for (int j = 0; j < 3; j++) L.A[i][j] /= a;
            L.b[i] = b[i] / C;
            y[i] = z[i] / r0;
            y[4 + i] = 0.0;
        }
        y[3] = 0.0;
    }
    tmax = h * C * a / r0;   /* the step's length in the units of y[3] */
    if (!(tmax > 0.0)) return 0;
    gsl_odeiv2_step_reset(w->slip_step);
    gsl_odeiv2_evolve_reset(w->slip_evo);
    ds = 1e-3;
    for (int k = 0; k < SLIP_STEPS; k++) {
        int st = gsl_odeiv2_evolve_apply(w->slip_evo, w->slip_con, w->slip_step, &sys, &s, INFINITY, &ds, y);
        if (st != GSL_SUCCESS || !ex_finite_n(y, SLIP_DIM)) return 0;
        if (!(y[3] < tmax)) return 0;
        if (y[0] * y[0] + y[1] * y[1] + y[2] * y[2] <= SLIP_END * SLIP_END) {
            /* Z, then the displacement: u = E^-1 Z, J'^-1 u, rotated by th */
            double c = cs[0], sn = cs[1], px, py;
            for (int i = 0; i < 3; i++) Z[i] = y[4 + i] * r0 * r0 / (a * C);
            for (int i = 0; i < 3; i++) u[i] = Z[i] / m->e[i];
            px = u[0] + m->pc[1] * u[2];
            py = u[1] - m->pc[0] * u[2];
            dq[0] = c * px - sn * py;
            dq[1] = sn * px + c * py;
            dq[2] = u[2];
            return ex_finite_n(dq, 3);
        }
    }
    return 0;
}

/* The slip of slip_stop_in_step_planar over a whole (sub-)step that it does
 * not stop in, on the time axis: in the units of slip_stop_in_step_planar
 * (zeta = z / r0, T = t C a / r0, Zeta = Z a C / r0^2)
 *     dzeta/dT = A (b - zeta / |zeta|) / a,   dZeta/dT = zeta
 * (y[3] unused), integrated by the same bsimp to T = h C a / r0, the
 * Jacobian -A (I - n n^T) / (a |zeta|) and I. Sets the end velocity v_end =
 * Rz J'^-1 E^-1 z(h) and the displacement dq = Rz J'^-1 E^-1 Z(h). Returns
 * 0 (the step keeps its own end state) where the slip comes within
 * SLIP_NEAR |z0| of rest inside the step (a stop, which the step's own test
 * decides), or the integration fails or takes more than SLIP_STEPS steps. */
#define SLIP_NEAR 1e-3

static int slip_rhs_t(double s, const double y[], double f[], void *par)
{
    const slip_law *L = par;
    double r = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]), d[3];
    (void)s;
    if (!(r > 0.0)) return GSL_EBADFUNC;
    for (int i = 0; i < 3; i++) d[i] = L->b[i] - y[i] / r;
    for (int i = 0; i < 3; i++) {
        f[i] = L->A[i][0] * d[0] + L->A[i][1] * d[1] + L->A[i][2] * d[2];
        f[4 + i] = y[i];
    }
    f[3] = 0.0;
    return GSL_SUCCESS;
}

static int slip_jac_t(double s, const double y[], double *J, double dfdt[], void *par)
{
    const slip_law *L = par;
    double r = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]), n[3], P[3][3];
    (void)s;
    if (!(r > 0.0)) return GSL_EBADFUNC;
    for (int i = 0; i < 3; i++) n[i] = y[i] / r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) P[i][j] = ((i == j ? 1.0 : 0.0) - n[i] * n[j]) / r;
    for (int i = 0; i < SLIP_DIM * SLIP_DIM; i++) J[i] = 0.0;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            J[i * SLIP_DIM + j] = -(L->A[i][0] * P[0][j] + L->A[i][1] * P[1][j] + L->A[i][2] * P[2][j]);
        J[(4 + i) * SLIP_DIM + i] = 1.0;
    }
    for (int i = 0; i < SLIP_DIM; i++) dfdt[i] = 0.0;
    return GSL_SUCCESS;
}

/* v = Rz J'^-1 E^-1 z: the generalized velocity (or displacement) of a scaled
 * patch slip z (the inverse of ejf) */
static void gen_of_slip(const exdex_model *m, const double cs[2], const double z[3], double v[3])
{
    double u[3], px, py;
    for (int i = 0; i < 3; i++) u[i] = z[i] / m->e[i];
    px = u[0] + m->pc[1] * u[2];
    py = u[1] - m->pc[0] * u[2];
    v[0] = cs[0] * px - cs[1] * py;
    v[1] = cs[1] * px + cs[0] * py;
    v[2] = u[2];
}

/* A and b of the slip law in the units of slip_stop_in_step_planar (L->A =
 * A / a, L->b = b / C), the initial slip z0 = E J v0 and *a = tr A; 0 if
 * they are not finite or v0 does not slip. */
static int slip_law_set(const exdex_model *m, const double cs[2], double C, const double v0[3], const double F[3],
                        slip_law *L, double z0[3], double *a)
{
    double Jp[3][3] = {{1.0, 0.0, -m->pc[1]}, {0.0, 1.0, m->pc[0]}, {0.0, 0.0, 1.0}}, b[3];
    model_patch_of_gen(m, cs, F, b);
    ejf(m, cs, v0, z0);
    *a = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double sum = 0.0;
            for (int k = 0; k < 3; k++) sum += Jp[i][k] * m->minv[k] * Jp[j][k];
            L->A[i][j] = m->e[i] * sum * m->e[j];
        }
    for (int i = 0; i < 3; i++) *a += L->A[i][i];
    if (!(*a > 0.0) || !isfinite(*a) || !(C > 0.0)) return 0;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) L->A[i][j] /= *a;
        L->b[i] = b[i] / m->e[i] / C;
    }
    return ex_finite_n(z0, 3) && (z0[0] != 0.0 || z0[1] != 0.0 || z0[2] != 0.0);
}

static int slip_through_step_planar(const exdex_model *m, work *w, const double cs[2], double C, double h,
                                    const double v0[3], const double F[3], double v_end[3], double dq[3])
{
    slip_law L;
    gsl_odeiv2_system sys = {slip_rhs_t, slip_jac_t, SLIP_DIM, &L};
    double z[3], r0, a, y[SLIP_DIM], s = 0.0, ds, tmax, Z[3];
    if (!w->slip_evo || !slip_law_set(m, cs, C, v0, F, &L, z, &a)) return 0;
    r0 = sqrt(ex_dot3(z, z));
    tmax = h * C * a / r0;
    if (!(r0 > 0.0) || !(tmax > 0.0) || !isfinite(tmax)) return 0;
    for (int i = 0; i < 3; i++) {
        y[i] = z[i] / r0;
        y[4 + i] = 0.0;
    }
    y[3] = 0.0;
    gsl_odeiv2_step_reset(w->slip_step);
    gsl_odeiv2_evolve_reset(w->slip_evo);
    ds = tmax / 16.0;
    for (int k = 0; k < SLIP_STEPS && s < tmax; k++) {
        int st = gsl_odeiv2_evolve_apply(w->slip_evo, w->slip_con, w->slip_step, &sys, &s, tmax, &ds, y);
        if (st != GSL_SUCCESS || !ex_finite_n(y, SLIP_DIM)) return 0;
        if (!(y[0] * y[0] + y[1] * y[1] + y[2] * y[2] > SLIP_NEAR * SLIP_NEAR)) return 0;
    }
    if (!(s >= tmax)) return 0;
    for (int i = 0; i < 3; i++) {
        z[i] = y[i] * r0;
        Z[i] = y[4 + i] * r0 * r0 / (a * C);
    }
    gen_of_slip(m, cs, z, v_end);
    gen_of_slip(m, cs, Z, dq);
    return ex_finite_n(v_end, 3) && ex_finite_n(dq, 3);
}

/* 1 if one of the frame's velocity jumps is at t (model_substep's snap):
 * a sub-step starting at t starts with the slip the jump set */
static int jump_at(const exdex_model *m, double t)
{
    double tj[EXDEX_MOTION_MAX_JUMPS], jv[EXDEX_MOTION_MAX_JUMPS][3], jw[EXDEX_MOTION_MAX_JUMPS][3];
    int nj = exdex_motion_jumps(m->motion, NULL, NULL, NULL);
    if (!nj) return 0;
    nj = exdex_motion_jumps(m->motion, tj, jv, jw);
    for (int j = 0; j < nj; j++)
        if (fabs(tj[j] - t) <= model_substep_snap(m, t)) return 1;
    return 0;
}

/* Static and kinetic friction, a step that starts slipping (v != 0) and
 * slides (the kinetic impulse cannot end it at rest): does the slip stop
 * inside the step and stay there? Under the kinetic law the slip z = E J v
 * (ejf) keeps or turns its direction; if the kinetic step's end slip points
 * against the start's, z(v).z(v+) <= 0, it passed through 0 inside the step,
 * and there the object is held iff the load lies in the static ellipsoid,
 * |E^-1 b| <= C_s (b the applied force F as a patch wrench, the test of
 * slip_stop_in_step_planar). That is the event method's slip -> stick
 * decision with the step's load; a slip that slows without reaching 0 does
 * not stick however slow it gets. Applied where no stop row carries an
 * impulse and rest keeps every row's bound (0 >= rhs). */
static int restick_planar(const exdex_model *m, const double cs[2], double Cs, const double v[3],
                          const double vn[3], const double F[3], const work *w)
{
    double z0[3], z1[3], b[3];
    for (int i = 0; i < w->n_rows; i++)
        if (w->lam[i] != 0.0 || w->rhs[i] > 0.0) return 0;
    ejf(m, cs, v, z0);
    ejf(m, cs, vn, z1);
    if (!(ex_dot3(z0, z1) <= 0.0)) return 0;
    model_patch_of_gen(m, cs, F, b);
    for (int i = 0; i < 3; i++) b[i] /= m->e[i];
    return ex_dot3(b, b) <= Cs * Cs;
}

/* Sliding with the stop rows of `act` held as equalities:
 *     min_v 1/2 (v - vs)^T M (v - vs) + cap |E J_f v|   s.t.  G_A v = rhs_A.
 * With v = vp + N z (N a basis of null(G_A)), the objective is smooth in z
 * wherever E J_f v != 0, which holds at the optimum once rest is excluded
 * (try_rest), so a damped Newton method converges quadratically.
 * Returns 1 on convergence with v, the friction impulse p (object frame) and
 * the stop impulses lam (least squares from stationarity), 2 with the same
 * outputs when the 60 Newton iterations ran out first (the caller counts a
 * warning), 0 on failure. */
static int solve_active(const exdex_model *m, const double cs[2], double cap, const double vs[3], const work *w,
                        const int *act, int k, const double v_start[3], double v[3], double p[3],
                        double lam[3], int *iters)
{
    double N[3][3], vp[3] = {0, 0, 0}, z[2] = {0, 0}, Mdiag[3];
    int nz = 3 - k, converged = 0, ex = m->ls_exact;
    /* the exact surface: the slip r = J_f v unscaled and cap D(r) in place
     * of cap |E J_f v| (D's gradient -w(r) and Hessian, limitsurf.h) */
    void (*slip)(const exdex_model *, const double *, const double *, double *) = ex ? model_patch_slip : ejf;
    for (int i = 0; i < 3; i++) Mdiag[i] = 1.0 / m->minv[i];
    /* particular solution (least norm in the mass metric, vp = M^-1 G_A' y,
     * G_A M^-1 G_A' y = rhs: the rows' own units, so that two vertices of
     * one edge on a stop, whose rows differ only in the rotation column,
     * stay distinguishable at any size of the object) and null-space basis */
    {
        double A[3][3], b[3], y[3];
        for (int i = 0; i < k; i++) {
            for (int j = 0; j < k; j++) A[i][j] = gmg(m, w->G[act[i]], w->G[act[j]]);
            b[i] = w->rhs[act[i]];
        }
        if (k > 0) {
            if (!ldp_solve_small(k, A, b, y)) return 0;
            for (int i = 0; i < k; i++)
                for (int c = 0; c < 3; c++) vp[c] += y[i] * m->minv[c] * w->G[act[i]][c];
        }
        if (k == 1) {
            const double *g = w->G[act[0]];
            double e0[3] = {0, 0, 0}, n1[3], n2[3], nn;
            e0[fabs(g[0]) < fabs(g[1]) ? (fabs(g[0]) < fabs(g[2]) ? 0 : 2) : (fabs(g[1]) < fabs(g[2]) ? 1 : 2)] = 1.0;
            ex_cross3(n1, g, e0);
            nn = sqrt(ex_dot3(n1, n1));
            for (int c = 0; c < 3; c++) n1[c] /= nn;
            ex_cross3(n2, g, n1);
            nn = sqrt(ex_dot3(n2, n2));
            for (int c = 0; c < 3; c++) {
                N[c][0] = n1[c];
                N[c][1] = n2[c] / nn;
            }
        } else if (k == 2) {
            double n1[3], nn;
            ex_cross3(n1, w->G[act[0]], w->G[act[1]]);
            nn = sqrt(ex_dot3(n1, n1));
            if (!(nn > 0)) return 0;
            for (int c = 0; c < 3; c++) N[c][0] = n1[c] / nn;
        }
    }
    /* start from the projection of v_start onto the affine set */
    for (int j = 0; j < nz; j++) {
        z[j] = 0.0;
        for (int c = 0; c < 3; c++) z[j] += N[c][j] * (v_start[c] - vp[c]);
    }
    *iters = 0;
    if (nz > 0) {
        /* On the affine set the scaled slip is linear, r(z) = r0 + B z, and the
         * quadratic part is 1/2 z^T H0 z + h0 . z + const: all set up once. */
        double r0[3], B[3][2], H0[2][2], h0[2];
        slip(m, cs, vp, r0);
        for (int j = 0; j < nz; j++) {
            double col[3] = {N[0][j], N[1][j], N[2][j]}, bc[3];
            slip(m, cs, col, bc);
            for (int c = 0; c < 3; c++) B[c][j] = bc[c];
            h0[j] = 0.0;
            for (int c = 0; c < 3; c++) h0[j] += N[c][j] * Mdiag[c] * (vp[c] - vs[c]);
            for (int i = 0; i < nz; i++) {
                H0[i][j] = 0.0;
                for (int c = 0; c < 3; c++) H0[i][j] += N[c][i] * Mdiag[c] * N[c][j];
            }
        }
        for (int it = 0; it < 60; it++) {
            double r[3], nr, g[2], Br[2], step[3], Hs[3][3], gs[3], f0, fscale, t = 1.0, znew[2] = {0, 0};
            for (int c = 0; c < 3; c++) {
                r[c] = r0[c];
                for (int j = 0; j < nz; j++) r[c] += B[c][j] * z[j];
            }
            if (ex) {
                double wr[3], HD[9];
                nr = limitsurf_wrench(&m->ls, r, wr, HD);
                if (!(nr > 0) || !isfinite(nr)) return 0;
                for (int j = 0; j < nz; j++) {
                    g[j] = h0[j] - cap * (B[0][j] * wr[0] + B[1][j] * wr[1] + B[2][j] * wr[2]);
                    for (int i = 0; i < nz; i++) g[j] += H0[j][i] * z[i];
                }
                for (int i = 0; i < nz; i++) {
                    for (int j = 0; j < nz; j++) {
                        double bhb = 0.0;
                        for (int a = 0; a < 3; a++)
                            for (int c = 0; c < 3; c++) bhb += B[a][i] * HD[3 * a + c] * B[c][j];
                        Hs[i][j] = H0[i][j] + cap * bhb;
                    }
                    gs[i] = -g[i];
                }
            } else {
                nr = sqrt(ex_dot3(r, r));
                if (!(nr > 0)) return 0;
                for (int j = 0; j < nz; j++) {
                    Br[j] = B[0][j] * r[0] + B[1][j] * r[1] + B[2][j] * r[2];
                    g[j] = h0[j] + cap * Br[j] / nr;
                    for (int i = 0; i < nz; i++) g[j] += H0[j][i] * z[i];
                }
                for (int i = 0; i < nz; i++) {
                    for (int j = 0; j < nz; j++) {
                        double btb = B[0][i] * B[0][j] + B[1][i] * B[1][j] + B[2][i] * B[2][j];
                        Hs[i][j] = H0[i][j] + cap / nr * (btb - Br[i] * Br[j] / (nr * nr));
                    }
                    gs[i] = -g[i];
                }
            }
            if (!ldp_solve_small(nz, Hs, gs, step)) return 0;
            /* backtracking on the objective keeps the damped Newton step
             * monotone. Near the optimum the decrease of a Newton step
             * (~ |g| |step|) falls below the rounding of f itself; a step whose
             * objective differs from f0 by no more than that rounding (fscale
             * below, the sum of the terms' magnitudes) is accepted, else the
             * search would shrink t to nothing and the iteration stall short of
             * the optimum, at an error set by the rounding of the world frame
             * (a stall at a gradient 1e-10 leaves a 1e-10 relative velocity
             * error). */
            f0 = cap * nr;
            fscale = fabs(f0);
            for (int i = 0; i < nz; i++) {
                f0 += h0[i] * z[i];
                fscale += fabs(h0[i] * z[i]);
                for (int j = 0; j < nz; j++) {
                    f0 += 0.5 * z[i] * H0[i][j] * z[j];
                    fscale += fabs(0.5 * z[i] * H0[i][j] * z[j]);
                }
            }
            for (int ls = 0; ls < 30; ls++) {
                double rt[3], ft;
                for (int j = 0; j < nz; j++) znew[j] = z[j] + t * step[j];
                for (int c = 0; c < 3; c++) {
                    rt[c] = r0[c];
                    for (int j = 0; j < nz; j++) rt[c] += B[c][j] * znew[j];
                }
                ft = cap * (ex ? limitsurf_dissipation(&m->ls, rt) : sqrt(ex_dot3(rt, rt)));
                for (int i = 0; i < nz; i++) {
                    ft += h0[i] * znew[i];
                    for (int j = 0; j < nz; j++) ft += 0.5 * znew[i] * H0[i][j] * znew[j];
                }
                if (ft <= f0 + 16.0 * DBL_EPSILON * fscale || t < 1e-6) break;
                t *= 0.5;
            }
            for (int j = 0; j < nz; j++) z[j] = znew[j];
            (*iters)++;
            {
                /* converged when the full Newton step (the distance to the
                 * optimum of the local model), not the damped one, is tiny
                 * in the mass metric (the one norm of the velocities that
                 * has a unit: sqrt(kg) m/s) */
                double sn = 0, zn = 0;
                for (int c = 0; c < 3; c++) {
                    double dc = 0.0, vc = vp[c];
                    for (int j = 0; j < nz; j++) {
                        dc += N[c][j] * step[j];
                        vc += N[c][j] * z[j];
                    }
                    sn += Mdiag[c] * dc * dc;
                    zn += Mdiag[c] * vc * vc;
                }
                if (sqrt(sn) <= 1e-14 * (1e-3 * m->scale.V * sqrt(Mdiag[0]) + sqrt(zn))) {
                    converged = 1;
                    break;
                }
            }
        }
    } else {
        converged = 1;  /* k = 3: v is the particular solution */
    }
    for (int c = 0; c < 3; c++) {
        v[c] = vp[c];
        for (int j = 0; j < nz; j++) v[c] += N[c][j] * z[j];
    }
    {
        double r[3], nr, P[3], res[3], A[3][3], b[3];
        if (ex) {
            double wr[3];
            model_patch_slip(m, cs, v, r);
            nr = limitsurf_wrench(&m->ls, r, wr, NULL);
            if (!(nr > 0) || !isfinite(nr)) return 0;
            for (int c = 0; c < 3; c++) p[c] = cap * wr[c];
        } else {
            ejf(m, cs, v, r);
            nr = sqrt(ex_dot3(r, r));
            if (!(nr > 0)) return 0;
            for (int c = 0; c < 3; c++) p[c] = -cap * m->e[c] * r[c] / nr;
        }
        model_gen_of_patch(m, cs, p, P);
        /* G_A^T lam = M (v - vs) - P_f, least squares in the metric M^-1 */
        for (int c = 0; c < 3; c++) res[c] = Mdiag[c] * (v[c] - vs[c]) - P[c];
        for (int i = 0; i < k; i++) {
            for (int j = 0; j < k; j++) A[i][j] = gmg(m, w->G[act[i]], w->G[act[j]]);
            b[i] = gmg(m, w->G[act[i]], res);
        }
        if (k > 0 && !ldp_solve_small(k, A, b, lam)) return 0;
    }
    return converged ? 1 : 2;
}

/* Planar friction + stops: friction alone first; if a stop row is violated,
 * exact rest (try_rest), else a primal active set over the stop rows with the
 * smooth sliding subproblem (solve_active). */
static int step_planar(const exdex_model *m, double h, double capm, double capsm, double th, const double vs[3], work *w,
                       double v[3], double pfB[3], exdex_friction_result *fr, exdex_stats *st)
{
    double cap = h * capm, caps = h * capsm, b[3], cs[2] = {cos(th), sin(th)};
    int s, act[3], k = 0, round;
    const exdex_friction_prep *prep = model_prep(m);
    model_patch_slip(m, cs, vs, b);
    /* stick with the static capacity, else slide with the kinetic one. The
     * solve's own stick test, |K^-1 E b| <= caps (K = E W E), is done here
     * first where it clearly fails (by more than its 1e-6 band, with margin
     * for rounding): the solve with caps would slide and be discarded, so
     * only the kinetic one runs (the same result, without the wasted slide) */
    {
        int skip_static = 0;
        if (caps != cap && !m->ls_exact) {
            double c[3], ct[3], t = 0.0;
            for (int i = 0; i < 3; i++) c[i] = prep->e[i] * b[i];
            ex_mulmtv3(ct, prep->Q, c);
            for (int i = 0; i < 3; i++) {
                double r = ct[i] / prep->lam[i] / caps;
                t += r * r;
            }
            skip_static = isfinite(t) && t > 1.0 + 1e-5;
        }
        s = limitsurf_step(&m->ls, prep, b, skip_static ? cap : caps, m->def.friction_solver, w->fws,
                           w->have_prev ? w->p_prev : NULL, fr);
        if (s) return s;
        st->solver_iterations += (size_t)fr->iterations;
        if (skip_static) goto friction_done;
    }
    if (!fr->stick && caps != cap) {
        s = limitsurf_step(&m->ls, prep, b, cap, m->def.friction_solver, w->fws, w->have_prev ? w->p_prev : NULL, fr);
        if (s) return s;
        st->solver_iterations += (size_t)fr->iterations;
    }
friction_done:
    model_gen_of_patch(m, cs, fr->p, pfB);
    for (int i = 0; i < 3; i++) v[i] = fr->stick ? 0.0 : vs[i] + m->minv[i] * pfB[i];
    for (round = 0; round < 12; round++) {
        int worst = -1, neg = -1;
        double wv = 0.0, lam[3] = {0, 0, 0}, p[3], vn[3];
        for (int i = 0; i < w->n_rows; i++) {
            double viol = w->rhs[i] - ex_dot3(w->G[i], v);
            int in = 0;
            for (int a = 0; a < k; a++) in |= act[a] == i;
            if (!in && viol > 1e-13 * (m->scale.V + fabs(w->rhs[i])) && viol > wv) {
                wv = viol;
                worst = i;
            }
        }
        if (worst < 0) break; /* every row satisfied: done */
        if (round == 0 && try_rest(m, cs, caps, vs, w, pfB, fr, st)) {
            v[0] = v[1] = v[2] = 0.0;
            goto done;
        }
        if (k == 3) { /* cannot add more independent rows */
            st->warnings++;
            break;
        }
        act[k++] = worst;
        for (;;) {
            int it = 0, sa = solve_active(m, cs, cap, vs, w, act, k, v, vn, p, lam, &it);
            if (!sa) {
                st->warnings++;
                k--; /* keep the previous solution */
                goto done;
            }
            if (sa == 2) st->warnings++; /* Newton iteration cap: solution kept */
            st->stop_iterations += (size_t)it;
            /* drop a row whose impulse came out negative (it should separate) */
            neg = -1;
            for (int a = 0; a < k; a++)
                if (lam[a] < 0.0 && (neg < 0 || lam[a] < lam[neg])) neg = a;
            if (neg < 0 || k == 1) break;
            act[neg] = act[--k];
        }
        for (int c = 0; c < 3; c++) v[c] = vn[c];
        for (int i = 0; i < w->n_rows; i++) w->lam[i] = 0.0;
        for (int a = 0; a < k; a++) w->lam[act[a]] = lam[a] > 0.0 ? lam[a] : 0.0;
        memcpy(fr->p, p, sizeof fr->p);
        fr->stick = 0;
        model_gen_of_patch(m, cs, p, pfB);
    }
    if (round == 12) st->warnings++; /* active-set rounds ran out: last iterate kept */
done:
    if (m->ls_exact) {
        /* the exact surface's warm start is the last slip twist (its
         * direction starts the next sliding step's search) */
        if (!fr->stick) {
            memcpy(w->p_prev, fr->u, sizeof w->p_prev);
            w->have_prev = 1;
        }
        return EXDEX_OK;
    }
    w->p_prev[0] = fr->p[0];
    w->p_prev[1] = fr->p[1];
    w->p_prev[2] = fr->p[2];
    w->have_prev = 1;
    return EXDEX_OK;
}


/* Remove the residual penetration left by the midpoint position update and
 * the linearised rotation (see build_rows): Newton passes on the vertex
 * gaps, each the least M-norm correction dq with every linearised gap
 * g_i + G_i dq >= 0 over all (stop, vertex) rows at once (ldp_min_norm in
 * z = M^1/2 dq): with an edge flush against a stop its two vertices are
 * equally deep, and only both rows together give the pure translation that
 * removes the penetration of both (one row at a time rotates the box and
 * pushes the other vertex in). A penetrating row targets a gap slightly
 * positive (1e-12 of the deepest penetration), so the next pass sees no
 * rounding-level penetration from this one; a gap within its rounding bound
 * (contact_gap_round) of 0 counts as 0, as in build_rows, and may stay
 * there: the sign of a rounding-level gap is not determined by the data.
 * Returns the smallest gap at the final q (contact_min_gap: the gaps of the
 * last pass when it moved nothing). */
static double project_positions(const exdex_model *m, const exdex_kinematics *kin, double *q,
                                exdex_stats *st)
{
    int nv = contact_nv(m), n = m->ndof, nr = m->n_stops * nv;
    double sq[3] = {0, 0, 0};  /* M^-1/2 (the metric of the correction) */
    if (n == 1) {
        sq[0] = 1.0;
    } else {
        sq[0] = sq[1] = 1.0 / sqrt(m->m);
        sq[2] = 1.0 / sqrt(m->izz);
    }
    for (int pass = 0; pass < 16; pass++) {
        double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], a[MAX_ROWS][3], g[MAX_ROWS], c[MAX_ROWS],
            tol[MAX_ROWS], y[MAX_ROWS], z[3] = {0, 0, 0}, depth = 0.0;
        int deep = -1;
        contact_vertices(m, q, xb, vx);
        for (int k = 0; k < m->n_stops; k++)
            for (int j = 0; j < nv; j++) {
                int i = k * nv + j;
                double G[3] = {0, 0, 0};
                g[i] = contact_gap(m, kin, k, xb[j], vx[j], G);
                tol[i] = contact_gap_round(m, kin, k, xb[j]);
                for (int d = 0; d < 3; d++) a[i][d] = G[d] * sq[d];
                if (g[i] < -tol[i] && (deep < 0 || g[i] < g[deep])) deep = i;
            }
        if (m->n_obst) {
            /* the obstacles' rows after the stops' (their count may change
             * with q: a section vertex row exists for each vertex) */
            int i0 = m->n_stops * nv;
            double Go[MAX_ROWS][3];
            nr = i0 + contact_obstacle_rows(m, kin, q, Go, g + i0, tol + i0, NULL, NULL);
            for (int i = i0; i < nr; i++) {
                for (int d = 0; d < 3; d++) a[i][d] = (d < n ? Go[i - i0][d] : 0.0) * sq[d];
                if (g[i] < -tol[i] && (deep < 0 || g[i] < g[deep])) deep = i;
            }
        }
        if (deep < 0) {
            /* every gap >= 0 to rounding */
            double gmin = INFINITY;
            for (int i = 0; i < nr; i++)
                if (g[i] < gmin) gmin = g[i];
            return gmin;
        }
        depth = -g[deep];
        for (int i = 0; i < nr; i++) {
            c[i] = -g[i] + 1e-12 * depth;
            if (g[i] < -tol[i]) tol[i] = 0.0;
        }
        if (!ldp_min_norm(nr, (const double (*)[3])a, c, tol, z, y, NULL)) {
            /* contradictory rows (pinched object): the deepest row alone,
             * as far as it can act */
            double aa = ex_dot3(a[deep], a[deep]);
            if (!(aa > 0.0)) break;
            for (int d = 0; d < 3; d++) z[d] = a[deep][d] * c[deep] / aa;
        }
        for (int d = 0; d < n; d++) q[d] += sq[d] * z[d];
    }
    /* still penetrating after every pass (e.g. the prescribed motion drives a
     * pinned pivot through a stop): report it rather than stay silent */
    st->warnings++;
    return contact_min_gap(m, kin, q);
}

/* Coulomb friction at the stops (some stop with mu > 0). The frictionless
 * step above is a solution of the frictional problem too when no
 * frictional row carries an impulse (a row without normal impulse has no
 * friction): it is kept, so a scene whose frictional stops never push is
 * stepped exactly as without friction. Otherwise the step is solved again
 * with the friction of the rows (stop_impulse.h: Stewart-Trinkle velocity-level
 * complementarity, the plate's limit surface with its prescribed normal force,
 * exact mode enumeration), with the frictionless solution's active rows as
 * the candidates, and the last step's modes and velocity as the first
 * guess and Newton's start when the last step was frictional too (else the
 * slip signs and velocity of the frictionless solution). The rows are
 * those of build_rows (gaps at t + h, rhs = -gap / h), with the tangential
 * rows T and the gripper's slip tb of each vertex at the pose of t + h. Where fc_solve finds no consistent
 * mode among its candidates the frictionless step is kept and a warning counted.
 * n = 1: A = 1 and cap the step's capacity c (friction -c sign(v)); n = 3:
 * A = E J_f at the step's angle. cap_s is the static capacity of the step
 * (the plates' rest test), cap the kinetic one (sliding); v_old the
 * velocity before the step. On return v, the plate impulse P
 * (generalized), w->lam and w->beta hold the step; *rest is 1 at plate
 * rest. Returns 1 if the step was changed. */
static int stop_friction_step(const exdex_model *m, const exdex_kinematics *kin_end, const double *q, double th,
                               double cap, double cap_s, const double vs[3], const double *v_old, work *w,
                               double *v, double *P, int *rest,
                               exdex_stats *st)
{
    fc_row rows[MAX_ROWS];
    fc_problem p;
    fc_result res;
    unsigned char hint[MAX_ROWS];
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], lam[MAX_ROWS], beta[MAX_ROWS], v_start[3];
    int nv, need = 0, n = m->ndof;
    for (int i = 0; i < w->n_rows; i++) {
        w->beta[i] = 0.0;
        need |= w->lam[i] > 0.0 && model_source_mu(m, w->row_stop[i]) > 0.0;
    }
    if (!need) return 0;
    nv = contact_vertices(m, q, xb, vx);
    for (int i = 0; i < w->n_rows; i++) {
        int k = w->row_stop[i], j = i % nv;
        fc_row *r = &rows[i];
        memcpy(r->G, w->G[i], sizeof r->G);
        for (int c = n; c < 3; c++) r->G[c] = 0.0;
        /* stop rows are r = k nv + j (build_rows), the obstacles' rows
         * follow with the point where each acts (w->cpt) */
        r->mu = model_source_mu(m, k);
        r->T[0] = r->T[1] = r->T[2] = 0.0;
        r->tb = 0.0;
        if (r->mu > 0.0) {
            if (i < m->n_stops * nv)
                contact_stop_tangent(m, kin_end, k, xb[j], vx[j], r->T, &r->tb);
            else
                contact_tangent(m, kin_end, w->cpt[i].x, w->cpt[i].vx, w->cpt[i].nB, r->T, &r->tb);
        }
        r->rhs = w->rhs[i];
        /* at rest (v = 0) a row holds with a force only where its bound is
         * 0 (to tol.rate): a stop the gripper drives into the object
         * (rhs > 0) excludes rest, one it leaves behind carries nothing */
        r->rest = w->rhs[i] > m->tol.rate ? -1 : w->gap[i] <= m->tol.touch && w->rhs[i] >= -m->tol.rate ? 1 : 0;
        hint[i] = w->lam[i] > 0.0;
    }
    memset(&p, 0, sizeof p);
    p.n = n;
    p.cap = cap;
    p.cap_rest = cap_s;
    p.nr = w->n_rows;
    p.rows = rows;
    p.vrest = m->tol.rate;
    if (n == 1) {
        p.Md[0] = m->def.dof == EXDEX_DOF_TRANSLATION ? m->m : m->mrot;
        p.A[0][0] = 1.0;
        p.vscale = m->scale.V * m->scale.q / m->scale.L;
    } else {
        double cs[2] = {cos(th), sin(th)};
        /* the exact surface: the unscaled slip map and the surface itself */
        if (m->ls_exact) p.ls = &m->ls;
        for (int c = 0; c < 3; c++) {
            double ec[3] = {0, 0, 0}, r[3];
            ec[c] = 1.0;
            if (m->ls_exact)
                model_patch_slip(m, cs, ec, r);
            else
                ejf(m, cs, ec, r);
            for (int i = 0; i < 3; i++) p.A[i][c] = r[i];
            p.Md[c] = 1.0 / m->minv[c];
        }
        p.vscale = m->scale.V;
    }
    for (int c = 0; c < 3; c++) p.vs[c] = c < n ? vs[c] : 0.0;
    {
        /* Newton's start: the last step's velocity when that step was solved
         * with friction too (a steady slide changes little per step), else
         * the frictionless solution */
        int cached = 0;
        for (int i = 0; i < w->n_rows; i++) cached |= hint[i] && w->fmode[i] != FC_OFF;
        for (int c = 0; c < 3; c++) v_start[c] = c < n ? (cached ? v_old[c] : v[c]) : 0.0;
    }
    if (!fc_solve(&p, hint, v_start, w->fmode, lam, beta, &res)) {
        st->warnings++;  /* no consistent mode: the frictionless step is kept */
        return 0;
    }
    st->stop_iterations += (size_t)res.iters;
    for (int i = 0; i < w->n_rows; i++) {
        w->lam[i] = lam[i];
        w->beta[i] = beta[i];
    }
    for (int c = 0; c < n; c++) {
        v[c] = res.v[c];
        P[c] = res.P[c];
    }
    *rest = res.rest;
    return 1;
}

/* The run's workspace: malloc, not calloc: the row arrays (~13 kB) are
 * written before they are read (build_rows), and zeroing them costs ~7 % of
 * a short planar run. */
static void implicit_free(void *ws);

static void *implicit_alloc(const exdex_model *m, int *status)
{
    work *w = malloc(sizeof *w);
    if (!w) {
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    w->fws = NULL;
    w->slip_step = NULL;
    w->slip_con = NULL;
    w->slip_evo = NULL;
    w->mc = NULL;
    if (m->pads && !(w->mc = calloc(1, sizeof *w->mc))) {
        free(w);
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    w->p_prev[0] = w->p_prev[1] = w->p_prev[2] = 0.0;
    w->have_prev = 0;
    w->n_rows = 0;
    for (int i = 0; i < MAX_ROWS; i++) w->fmode[i] = FC_OFF;
    if (m->def.friction_solver != EXDEX_SOLVER_SCALAR && m->ndof == 3) {
        w->fws = exdex_friction_ws_alloc();
        if (!w->fws) {
            free(w->mc);
            free(w);
            *status = EXDEX_ENOMEM;
            return NULL;
        }
    }
    if (m->ndof == 3) {
        w->slip_step = gsl_odeiv2_step_alloc(gsl_odeiv2_step_bsimp, SLIP_DIM);
        w->slip_con = gsl_odeiv2_control_y_new(SLIP_TOL, SLIP_TOL);
        w->slip_evo = gsl_odeiv2_evolve_alloc(SLIP_DIM);
        if (!w->slip_step || !w->slip_con || !w->slip_evo) {
            implicit_free(w);
            *status = EXDEX_ENOMEM;
            return NULL;
        }
    }
    return w;
}

static void implicit_free(void *ws)
{
    work *w = ws;
    if (!w) return;
    exdex_friction_ws_free(w->fws);
    free(w->mc);
    if (w->slip_evo) gsl_odeiv2_evolve_free(w->slip_evo);
    if (w->slip_con) gsl_odeiv2_control_free(w->slip_con);
    if (w->slip_step) gsl_odeiv2_step_free(w->slip_step);
    free(w);
}

static int implicit_begin(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st)
{
    work *w = ws;
    (void)t_end;
    (void)dt;
    (void)st;
    memset(&w->S, 0, sizeof w->S);
    model_initial_state(m, w->S.q, w->S.v);
    w->p_prev[0] = w->p_prev[1] = w->p_prev[2] = 0.0;
    w->have_prev = 0;
    for (int i = 0; i < MAX_ROWS; i++) w->fmode[i] = FC_OFF;
    model_sw_cache_reset(&w->swc);
    return exdex_motion_eval(m->motion, 0.0, &w->S.kin0);
}

/* One sub-step from the time reached, w->S.t, to sub->te (model_substep):
 * the scheme at the top with h = te - t; then the frame's velocity jumps at
 * te, if any. On return (EXDEX_OK) the state is at te, wrench holds the
 * sub-step's mean plate wrench (impulse / h), sf each source's mean stop
 * force and *stick the stick flag. */
static int implicit_substep(const exdex_model *m, work *w, const model_sub *sub, double wrench[3], double *sf,
                            int *stick, exdex_stats *st)
{
    int n_dof = m->ndof, ns = m->n_stops, status = EXDEX_OK;
    double *q = w->S.q, *v = w->S.v, *vprev = w->S.vprev, hprev = w->S.hprev, t = w->S.t, t1 = sub->te;
    exdex_kinematics kin0 = w->S.kin0;
    do {
        double h = t1 - t, tm = t + 0.5 * h, qm[3], vmid[3], F[3], vs[3], vn[3], qset[3], vheld = NAN;
        int moved = 0;   /* qset holds the step's end position (a slip stopped inside it) */
        frame f;
        exdex_kinematics kin, kin_end;
        wrench[0] = wrench[1] = wrench[2] = 0.0;
        /* step-mean frame accelerations (a midpoint sample would make an
         * acceleration jump inside the step an O(h) error); no switch lies
         * inside the sub-step */
        status = model_frame_substep(m, &kin0, tm, sub, h, &f, &kin, &kin_end);
        if (status) break;
        for (int i = 0; i < n_dof; i++) {
            qm[i] = q[i] + 0.5 * h * v[i];
            /* velocity at the midpoint, extrapolated from the last step, for
             * the velocity-dependent (Coriolis, gyroscopic) terms: second
             * order in smooth phases, and exactly 0 while the object sticks */
            vmid[i] = hprev > 0.0 ? v[i] + 0.5 * h * (v[i] - vprev[i]) / hprev : v[i];
        }
        if (n_dof == 1) {
            int tr = m->def.dof == EXDEX_DOF_TRANSLATION;
            double M = tr ? m->m : m->mrot, Q = model_force_1dof(m, &f, qm[0], vmid[0]), pf;
            /* friction capacity of the step: the capacity's mean over the
             * step times h (the largest impulse the plates carry), |E j| =
             * e_t = 1 for a slide, e_r for a pure spin at the centre of
             * pressure; c_s the static one */
            double capm = model_capacity_mean(m, t, t1), c = tr ? h * capm : h * capm * m->e[2];
            double capsm = model_capacity_static_mean(m, t, t1), c_s = tr ? h * capsm : h * capsm * m->e[2];
            /* the stick test's capacity: static for a step that starts at
             * rest, kinetic for one that starts slipping (the slip must stop
             * under the kinetic law first; slip_stop_in_step then holds it
             * with the static one) */
            double c_t = v[0] != 0.0 ? c : c_s;
            vs[0] = v[0] + h * Q / M;
            build_rows_or_none(m, &kin_end, q, vs, h, w);
            step_1dof(M, c, c_t, vs[0], m->tol.touch, w, &vn[0], &pf, st);
            if (m->stop_friction) {
                int rest = 0;
                stop_friction_step(m, &kin_end, q, 0.0, c, c_t, vs, v, w, vn, &pf, &rest, st);
            }
            if (v[0] != 0.0 && (vn[0] == 0.0 || (vn[0] > 0.0) != (v[0] > 0.0))) {
                /* a slip that stops or reverses inside the step
                 * (slip_stop_in_step), where no stop acts and the end
                 * position keeps every row's bound */
                double ve, dq;
                int ok = slip_stop_in_step(M, Q, c / h, c_s / h, h, v[0], &ve, &dq);
                for (int i = 0; ok && i < w->n_rows; i++)
                    ok = w->lam[i] == 0.0 && w->G[i][0] * dq >= w->rhs[i] * h;
                if (ok) {
                    vn[0] = ve;
                    pf = M * (ve - vs[0]);
                    qset[0] = q[0] + dq;
                    moved = 1;
                }
            }
            if (!m->stop_friction && !moved) vheld = held_velocity_1dof(m, &kin_end, q[0], h, M, vn[0], w);
            if (m->def.dof == EXDEX_DOF_TRANSLATION) {
                wrench[0] = pf * m->d[0] / h;
                wrench[1] = pf * m->d[1] / h;
            } else {
                wrench[2] = pf / h;
            }
            *stick = vn[0] == 0.0;
        } else {
            exdex_friction_result fr;
            double pfB[3], fo[3];
            /* pads on the fingers: the contact region at the step's midpoint */
            if (w->mc) model_pads_set(w->mc, qm);
            model_force_planar(m, &f, qm, vmid, F);
            /* the stick test's capacity: static for a step that starts at
             * rest, kinetic for one that starts slipping (see restick_planar) */
            int slipping = v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0;
            double capm = model_capacity_mean(m, t, t1), capsm = model_capacity_static_mean(m, t, t1);
            double capt = slipping ? capm : capsm;
            for (int i = 0; i < 3; i++) vs[i] = v[i] + h * m->minv[i] * F[i];
            build_rows_or_none(m, &kin_end, q, vs, h, w);
            size_t warn0 = st->warnings;
            status = step_planar(m, h, capm, capt, qm[2], vs, w, vn, pfB, &fr, st);
            if (status) {
                st->fail_time = t;
                break;
            }
            if (m->stop_friction) {
                int rest = fr.stick;
                size_t warn1 = st->warnings;
                if (stop_friction_step(m, &kin_end, q, qm[2], h * capm, h * capt, vs, v, w, vn, pfB, &rest, st)) {
                    model_patch_of_gen(m, MODEL_CS(qm[2]), pfB, fr.p);
                    fr.stick = rest;
                    /* the frictional solve replaced the frictionless one: the
                     * latter's soft problems are not the step's (with the exact
                     * surface its Newton runs to its cap at a rest against a
                     * stop, where D is not differentiable at the optimum) */
                    if (m->ls_exact) st->warnings = warn0 + (st->warnings - warn1);
                }
            }
            /* the in-step refinements below integrate the ellipsoid's slip
             * law: the exact surface takes the plain step */
            if (slipping && !fr.stick && capsm != capm && !m->ls_exact && restick_planar(m, MODEL_CS(qm[2]), capsm, v, vn, F, w)) {
                /* the slip stops inside the step and the static capacity
                 * holds the load: at rest, the plates' impulse the one that
                 * ends the step there */
                for (int i = 0; i < 3; i++) {
                    vn[i] = 0.0;
                    pfB[i] = -vs[i] / m->minv[i];
                }
                model_patch_of_gen(m, MODEL_CS(qm[2]), pfB, fr.p);
                fr.stick = 1;
            }
            if (fr.stick && !m->ls_exact && (v[0] != 0.0 || v[1] != 0.0 || v[2] != 0.0)) {
                /* a slip that stops inside the step (slip_stop_in_step_planar),
                 * where no stop acts and the end position keeps every row's
                 * bound */
                double dq[3];
                int ok = slip_stop_in_step_planar(m, w, MODEL_CS(qm[2]), model_capacity_mean(m, t, t1),
                                                  model_capacity_static_mean(m, t, t1), h, v, F, dq);
                for (int i = 0; ok && i < w->n_rows; i++)
                    ok = w->lam[i] == 0.0 && ex_dot3(w->G[i], dq) >= w->rhs[i] * h;
                if (ok) {
                    for (int i = 0; i < 3; i++) qset[i] = q[i] + dq[i];
                    moved = 1;
                }
            }
            if (!fr.stick && !moved && slipping && !m->ls_exact && jump_at(m, t)) {
                /* a sub-step that starts at a velocity jump of the frame
                 * with the slip the jump set, and slides through: the slip
                 * integrated over it (slip_through_step_planar), where no
                 * stop acts and the end position keeps every row's bound.
                 * Its length is set by where the jump falls between grid
                 * points, the same on every level of a nested step ladder
                 * whose grids share the point after the jump, so the
                 * scheme's own error there (the friction's turn over the
                 * sub-step) would be the same on those levels. */
                double ve[3], dq[3];
                int ok = 1;
                for (int i = 0; i < w->n_rows; i++) ok = ok && w->lam[i] == 0.0;
                ok = ok && slip_through_step_planar(m, w, MODEL_CS(qm[2]), capm, h, v, F, ve, dq);
                for (int i = 0; ok && i < w->n_rows; i++) ok = ex_dot3(w->G[i], dq) >= w->rhs[i] * h;
                if (ok) {
                    for (int i = 0; i < 3; i++) {
                        vn[i] = ve[i];
                        qset[i] = q[i] + dq[i];
                        pfB[i] = (ve[i] - v[i]) / m->minv[i] - h * F[i];
                    }
                    model_patch_of_gen(m, MODEL_CS(qm[2]), pfB, fr.p);
                    moved = 1;
                }
            }
            /* report the patch wrench (not the generalized impulse), in B */
            model_to_b(MODEL_CS(qm[2]), fr.p, fo);
            for (int i = 0; i < 3; i++) wrench[i] = fo[i] / h;
            *stick = vn[0] == 0.0 && vn[1] == 0.0 && vn[2] == 0.0;
        }
        {
            /* A step in which a stop pushes ends where its row put it: q + h v+
             * (gap exactly 0 for a translating contact); otherwise Moreau's
             * midpoint update q_m + h/2 v+. */
            int pushed = 0;
            for (int i = 0; i < w->n_rows; i++) pushed |= w->lam[i] > 0.0;
            for (int i = 0; i < n_dof; i++) {
                q[i] = pushed ? q[i] + h * vn[i] : qm[i] + 0.5 * h * vn[i];
                if (moved) q[i] = qset[i];
                if (!isnan(vheld)) vn[i] = vheld;
                vprev[i] = v[i];
                v[i] = vn[i];
            }
        }
        if (ns || m->n_obst) {
            double gmin = project_positions(m, &kin_end, q, st);
            if (gmin < st->min_gap) st->min_gap = gmin;
        }
        if (!ex_finite_n(q, n_dof) || !ex_finite_n(v, n_dof) || !ex_finite_n(wrench, 3)) {
            status = EXDEX_ENONFINITE;
            break;
        }
        {
            /* stop forces (impulse / h) must be finite too: an overflow in the
             * impulses alone is reported, not recorded */
            int finite_lam = 1;
            for (int i = 0; i < w->n_rows; i++) finite_lam &= isfinite(w->lam[i] / h);
            if (!finite_lam) {
                status = EXDEX_ENONFINITE;
                break;
            }
        }
        t = t1;
        hprev = h;
        for (int k = 0; k < m->n_src; k++) sf[k] = 0.0;
        for (int i = 0; i < w->n_rows; i++) sf[w->row_stop[i]] += w->lam[i] / h;
        if (sub->jumps) {
            /* the frame's velocity jumps at te: the relative velocity jumps
             * (the plates carry no impulse); friction acts on it from the
             * next sub-step on. The last step's velocity change no longer
             * extrapolates. */
            model_substep_jump(m, sub, q, v, &kin_end);
            if (!ex_finite_n(v, n_dof)) {
                status = EXDEX_ENONFINITE;
                break;
            }
            *stick = 0;
            for (int i = 0; i < n_dof; i++) *stick |= v[i] != 0.0;
            *stick = !*stick;
        }
        /* across a switching time the acceleration jumps: no extrapolation
         * of the last (sub-)step's velocity change past it */
        if (sub->split || sub->jumps) hprev = 0.0;
        kin0 = kin_end;
    } while (0);
    w->S.hprev = hprev;
    w->S.t = t;
    w->S.kin0 = kin0;
    return status;
}

/* One output step from the time reached to t1, recorded as sample `step`:
 * its sub-steps (model_substep), the recorded wrench and stop forces their
 * means over the output step weighted by their lengths (one sub-step: its
 * own values, bit for bit), the stick flag set when every sub-step stuck
 * (the object held through the whole output step). */
static int implicit_advance(const exdex_model *m, void *ws, double t1, int regrip, exdex_trajectory *out,
                            size_t step, exdex_stats *st)
{
    work *w = ws;
    double t0 = w->S.t, H = t1 - t0, wrench[3] = {0, 0, 0}, sf[EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES];
    int status = EXDEX_OK, stick = 0, first = 1, split = 0;
    (void)regrip;   /* the capacity is read at every step */
    if (w->mc) m = model_pads_follow(m, w->mc);
    while (w->S.t < t1) {
        model_sub sub;
        int sub_stick = 0;
        double wr[3], sfs[EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES], ts = w->S.t, wt;
        int whole;
        model_substep(m, &w->swc, ts, t1, &sub);
        /* the whole output step as one sub-step records its own values */
        whole = first && !sub.split;
        status = implicit_substep(m, w, &sub, whole ? wrench : wr, whole ? sf : sfs, whole ? &stick : &sub_stick, st);
        if (status) return status;
        if (whole) break;
        split |= sub.split;
        stick = first ? sub_stick : stick && sub_stick;
        wt = (sub.te - ts) / H;
        method_add_sub(first, wt, wr, sfs, m->n_src, wrench, sf);
        first = 0;
    }
    /* a split output step: the next one does not extrapolate from its last,
     * possibly very short, sub-step */
    if (split) w->S.hprev = 0.0;
    st->steps++;   /* one step per sample: its sub-steps are parts of it */
    method_record(m, out, st, step, t1, w->S.q, w->S.v, wrench, stick, sf);
    return status;
}

typedef struct implicit_state {
    double p_prev[3];
    int have_prev;
    int fmode[MAX_ROWS];  /* the stop-friction solve's first guess: part of the state */
} implicit_state;

static void implicit_save(const void *ws, void *buf)
{
    const work *w = ws;
    implicit_state x;
    memset(&x, 0, sizeof x);   /* padding too: a snapshot's checksum reads every byte */
    memcpy(x.p_prev, w->p_prev, sizeof x.p_prev);
    x.have_prev = w->have_prev;
    memcpy(x.fmode, w->fmode, sizeof x.fmode);
    memcpy(buf, &w->S, sizeof w->S);
    memcpy((char *)buf + sizeof w->S, &x, sizeof x);
}

static int implicit_restore(void *ws, const void *buf)
{
    work *w = ws;
    implicit_state x;
    memcpy(&x, (const char *)buf + sizeof w->S, sizeof x);
    for (int i = 0; i < MAX_ROWS; i++)
        if (x.fmode[i] < FC_OFF || x.fmode[i] > FC_STICK) return EXDEX_EINVAL;
    memcpy(&w->S, buf, sizeof w->S);
    memcpy(w->p_prev, x.p_prev, sizeof x.p_prev);
    w->have_prev = x.have_prev != 0;
    memcpy(w->fmode, x.fmode, sizeof x.fmode);
    return EXDEX_OK;
}

const method_impl method_implicit = {"implicit", implicit_alloc, NULL, implicit_free, 1, 1,
                                     implicit_begin, implicit_advance,
                                     sizeof(((work *)0)->S) + sizeof(implicit_state), implicit_save,
                                     implicit_restore, NULL};
