/* certify.c -- the certificate of a reduced (1-DoF) run: does the planar
 * model admit the motion the reduced model computed?
 *
 * A translation run assumes the object neither turns nor moves across the
 * slide axis; a rotation run assumes an ideal pin at the pivot. Along the
 * recorded trajectory, the planar equations (mass matrix M = diag(m, m,
 * I_zz), gravity and the frame's inertial terms F, Eqs. 3-5) give the plate
 * friction wrench w the neglected coordinates need to stay still, at the
 * model's contact point (the centre of pressure, patch coordinates of
 * model_patch_of_gen). Stops and obstacles touching the object (gap below
 * tol.touch) may push along their normals with any force lambda >= 0 and,
 * with friction mu, along their tangent in the plate plane with |beta| <=
 * mu lambda (opposing the contact point's slip where it slides: the
 * reduced motion's and the gripper's past the contact). With the exact
 * surface and stops, the stop forces are those that leave the load
 * smallest in the ellipsoid's metric (a verdict that can only err towards
 * failing). The reduction holds
 *   while the reduced coordinate sticks: iff some lambda >= 0 leaves a w
 *     inside the static limit surface (gauge <= 1);
 *   while it slips: maximum dissipation fixes the friction w_f of the
 *     reduced slip twist (a pure translation slip gets no moment, a pure
 *     rotation about the centre of pressure no force), the reduced
 *     coordinate's acceleration a is free (its own equation decides it) and
 *     the part of the load w_f cannot give must be carried by the stops:
 *     min over a, lambda >= 0 of |E^-1 r| <= CERT_SLIP_TOL (scale.F +
 *     |E^-1 b|), r the unbalanced wrench.
 * The limit surface enters through cert_gauge and cert_slip_wrench only
 * (and, with stops, the ellipsoid's metric that picks their forces).
 *
 * Where it is checked: at every output sample with the sample's state and
 * mode (stick flag; a sample at rest that is not flagged stick is checked as
 * at rest), and at every switching time of the scene (model.sw_t: the
 * motion's and the grip schedule's) inside an output interval with the
 * state of the interval's end. A failure is located between the last
 * sample that holds and the first that fails by Brent's method on the
 * certificate's excess with the state held (a stick state is exact between
 * samples: the coordinate does not move). Between samples the check is
 * exact where the load is piecewise constant in time (a translation run in
 * a gripper that translates with Eq. 7, a trapezoid or at rest, a constant
 * grip force: the load does not depend on the state, and it changes only at
 * switching times); elsewhere (a turning gripper, a shake, a log, a grip
 * schedule, a rotation run whose load moves with the angle) the check is at
 * samples and switching times; between two stuck samples (the state is
 * the same), the interval is proven by a block's enclosure (prove_block,
 * below) or halved up to CERT_BETWEEN_DEPTH times with the middles
 * evaluated (stuck_between), so a stuck load's excursion inside one output
 * interval is seen to a sixteenth of it where no proof holds (and not
 * where stops carry the load: the enclosures have no stop force); a
 * slip's, to the output grid's resolution.
 *
 * Cost: a sample needs no evaluation where its mode is proven for its piece
 * (prove_pieces: one evaluation per piece and mode for a constant load, a
 * closed-form bound for a gripper turning about a fixed axis) or for a
 * block of samples in a gripper that does not turn (prove_block: the
 * translation's and the rotation's loads enclosed over the block) or turns
 * (prove_block_turning: the load enclosed over the frame's enclosure,
 * motion_frame_box, and the block's angles or slide coordinates and
 * rates); only
 * the samples of the other modes, and those whose interval holds a
 * switching time, are evaluated. The result is that of evaluating every sample
 * (exdex_certify_samples; the C suite compares them). */
#include "exdex.h"
#include "model.h"
#include "contact.h"
#include "pose.h"
#include "util.h"

#include <math.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

/* Columns of the stop problem (the first contact rows in contact; a
 * frictional row takes two). */
#define CERT_MAX_COLS 16

/* ------------------------------------------------------- limit surface
 * The one place that knows the surface, through the limit-surface
 * interface (limitsurf.h): the model's ellipsoid w^T E^-2 w <= C^2 (E =
 * diag(1, 1, e_r) of the model's patch, or of the pads' region at the
 * start), or the exact surface of uniform pressure over the patch's region
 * (Grasp(limit_surface="exact")). */

/* The load's gauge times the capacity: |E^-1 w| for the ellipsoid, the
 * exact surface's gauge g(w) (NaN if its search fails). */
static double cert_gauge(const exdex_model *m, const double w[3])
{
    return model_ls_gauge(m, w);
}

/* Maximum dissipation for the slip twist u != 0 at the patch: the friction
 * wrench C w(u) (ellipsoid: -C E^2 u / |E u|). */
static void cert_slip_wrench(const exdex_model *m, const double u[3], double C, double w[3])
{
    double eu = 0.0;
    if (m->ls_exact) {
        if (u[0] == 0.0 && u[1] == 0.0 && u[2] == 0.0) {
            w[0] = w[1] = w[2] = 0.0;
            return;
        }
        limitsurf_wrench(&m->ls, u, w, NULL);
        for (int c = 0; c < 3; c++) w[c] *= C;
        return;
    }
    for (int c = 0; c < 3; c++) eu += m->e[c] * m->e[c] * u[c] * u[c];
    eu = sqrt(eu);
    for (int c = 0; c < 3; c++) w[c] = eu > 0.0 ? -C * m->e[c] * m->e[c] * u[c] / eu : 0.0;
}

/* ------------------------------------------- smallest unbalanced wrench
 * min |y0 + sum_k x_k c_k| over x_k free (k < nfree) and x_k >= 0 (the
 * others), in R^3 (E^-1-scaled patch wrenches). Convex: some optimum has a
 * linearly independent support of at most 3 columns whose least-squares
 * solution is feasible (Caratheodory), so the smallest residual over the
 * supports of up to 3 columns that contain every free column and solve
 * feasibly is the minimum. ncol <= 1 + CERT_MAX_COLS. */
static double ls_residual(const double y0[3], const double (*c)[3], const int *idx, int k, double *x)
{
    double A[3][3], b[3], r[3];
    for (int i = 0; i < k; i++) {
        b[i] = 0.0;
        for (int d = 0; d < 3; d++) b[i] -= c[idx[i]][d] * y0[d];
        for (int j = 0; j < k; j++) {
            A[i][j] = 0.0;
            for (int d = 0; d < 3; d++) A[i][j] += c[idx[i]][d] * c[idx[j]][d];
        }
    }
    if (k == 1) {
        if (!(A[0][0] > 0.0)) return -1.0;
        x[0] = b[0] / A[0][0];
    } else if (k == 2) {
        double det = A[0][0] * A[1][1] - A[0][1] * A[1][0];
        if (!(fabs(det) > 1e-14 * A[0][0] * A[1][1])) return -1.0;
        x[0] = (b[0] * A[1][1] - A[0][1] * b[1]) / det;
        x[1] = (A[0][0] * b[1] - A[1][0] * b[0]) / det;
    } else if (k == 3) {
        double c0 = A[1][1] * A[2][2] - A[1][2] * A[2][1], c1 = A[1][2] * A[2][0] - A[1][0] * A[2][2],
               c2 = A[1][0] * A[2][1] - A[1][1] * A[2][0];
        double det = A[0][0] * c0 + A[0][1] * c1 + A[0][2] * c2;
        if (!(fabs(det) > 1e-14 * A[0][0] * A[1][1] * A[2][2])) return -1.0;
        /* Cramer */
        for (int i = 0; i < 3; i++) {
            double M[3][3];
            memcpy(M, A, sizeof M);
            for (int j = 0; j < 3; j++) M[j][i] = b[j];
            x[i] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                    M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) / det;
        }
    }
    for (int d = 0; d < 3; d++) {
        r[d] = y0[d];
        for (int i = 0; i < k; i++) r[d] += x[i] * c[idx[i]][d];
    }
    return sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
}

static double min_residual(const double y0[3], const double (*c)[3], int nfree, int ncol, double rbest[3])
{
    double best = -1.0;
    memcpy(rbest, y0, 3 * sizeof *rbest);
    int nn = ncol - nfree, kmax = 3 - nfree;
    if (nfree > 1) return -1.0;
    /* supports: the free column (if any) and a < b < e of the others (-1: none) */
    for (int a = -1; a < nn; a++) {
        for (int b = -1; b < nn; b++) {
            if (b >= 0 && (a < 0 || b <= a)) continue;
            for (int e = -1; e < nn; e++) {
                if (e >= 0 && (b < 0 || e <= b)) continue;
                int idx[3], k = 0, ok = 1, extra = (a >= 0) + (b >= 0) + (e >= 0);
                double x[3] = {0, 0, 0}, r;
                if (extra > kmax) continue;
                if (nfree) idx[k++] = 0;
                if (a >= 0) idx[k++] = nfree + a;
                if (b >= 0) idx[k++] = nfree + b;
                if (e >= 0) idx[k++] = nfree + e;
                if (k == 0) {
                    r = sqrt(y0[0] * y0[0] + y0[1] * y0[1] + y0[2] * y0[2]);
                } else {
                    r = ls_residual(y0, c, idx, k, x);
                    if (r < 0.0) continue;
                    for (int i = nfree; i < k; i++)
                        if (x[i] < 0.0) ok = 0;
                }
                if (ok && (best < 0.0 || r < best)) {
                    best = r;
                    for (int d = 0; d < 3; d++) {
                        rbest[d] = y0[d];
                        for (int q = 0; q < k; q++) rbest[d] += x[q] * c[idx[q]][d];
                    }
                }
            }
        }
    }
    return best < 0.0 ? sqrt(y0[0] * y0[0] + y0[1] * y0[1] + y0[2] * y0[2]) : best;
}

/* -------------------------------------------------------- one instant */

typedef struct cert_eval {
    double excess;     /* > 0: fails (stick: gauge / Cs - 1 beyond the stick band; slip: residual / tol - 1) */
    double crossing;   /* where a failure is located: its root (stick: gauge / Cs - 1; slip: excess) */
    double gauge;      /* stick: |E^-1 w| / Cs; slip: |E^-1 r| / C */
    double load[3];    /* the wrench the neglected coordinates need (patch frame) */
    double cap;        /* capacity used (static while stuck) */
    int stick;
    double th;
    double along;      /* |generalised load along the free coordinate| (a stuck reduced model needs <= its capacity) */
    double gen;        /* that load with its sign */
    double own;        /* stick: the static gauge of that load alone (its component along the free
                        * coordinate's direction, with nothing neglected) */
} cert_eval;

/* The verdict for the load b (patch wrench with no stop force) with the
 * columns cols (the free acceleration first when nfree = 1, then stop
 * rows): stuck (vf NULL) against the static surface, slipping at the planar
 * velocity vf against the slip's friction. */
static int cert_decide(const exdex_model *m, double t, const double b[3], const double *vf, const double cs[2],
                       const double (*cols)[3], int nfree, int ncol, cert_eval *ce)
{
    double y0[3], rb[3];
    if (!vf) {
        double Cs = model_capacity_static(m, t), res;
        for (int c = 0; c < 3; c++) y0[c] = b[c] / m->e[c];
        if (ncol) {
            /* the stop forces that bring the load closest to the centre in
             * E^-1 (the ellipsoid's gauge at its least); the exact
             * surface's gauge of what they leave */
            res = min_residual(y0, cols, nfree, ncol, rb);
            if (m->ls_exact) {
                double w[3] = {rb[0] * m->e[0], rb[1] * m->e[1], rb[2] * m->e[2]};
                res = cert_gauge(m, w);
            }
        } else {
            res = cert_gauge(m, b);
        }
        ce->cap = Cs;
        ce->gauge = Cs > 0.0 ? res / Cs : (res > 0.0 ? INFINITY : 0.0);
        /* the methods' own stick test: a load sticks while it is within
         * FRICTION_BAND of the surface (at a slip's onset the load is on it
         * to rounding). A time-stepping method holds a stick up to its step
         * past the onset, where the reduced coordinate's own load alone is
         * beyond the surface: that is the reduced model's slip decision,
         * not a load of the neglected coordinates, so the gauge is compared
         * with that of the own load where it is larger. A failed search of
         * the exact surface's gauge counts as a failure. */
        ce->excess = ce->gauge == ce->gauge ? ce->gauge - fmax(1.0, ce->own) * (1.0 + FRICTION_BAND) : INFINITY;
        ce->crossing = ce->gauge == ce->gauge ? ce->gauge - 1.0 : INFINITY;
    } else {
        double C = model_capacity(m, t), u[3], wf[3], res, tol;
        model_patch_slip(m, cs, vf, u);
        cert_slip_wrench(m, u, C, wf);
        for (int c = 0; c < 3; c++) y0[c] = (b[c] - wf[c]) / m->e[c];
        res = min_residual(y0, cols, nfree, ncol, rb);
        tol = CERT_SLIP_TOL * (m->scale.F + model_ell_norm(m, b) + C);
        ce->cap = C;
        ce->gauge = C > 0.0 ? res / C : res;
        ce->excess = res / tol - 1.0;
        ce->crossing = ce->excess;
    }
    return EXDEX_OK;
}

/* The certificate at time t for reduced coordinate q, rate v, mode stick;
 * use_stops = 0: without stop forces (the verdict then does not depend on
 * which stops touch). */
static int cert_at_frame(const exdex_model *m, double t, const frame *fp, const exdex_kinematics *kinp, double q,
                         double v, int stick, int use_stops, cert_eval *ce);

static int cert_at_stops(const exdex_model *m, double t, double q, double v, int stick, int use_stops,
                         cert_eval *ce)
{
    frame f;
    exdex_kinematics kin;
    int st = model_frame_at(m, t, &f, &kin);
    if (st) return st;
    return cert_at_frame(m, t, &f, &kin, q, v, stick, use_stops, ce);
}

/* The same with the frame f, kin of time t given (kin is read for the stop
 * rows only). */
static int cert_at_frame(const exdex_model *m, double t, const frame *fp, const exdex_kinematics *kinp, double q,
                         double v, int stick, int use_stops, cert_eval *ce)
{
    double r[3], th, qf[3], vf[3], kap[3] = {0, 0, 0}, T[3], F[3], P[3], b[3], cs[2], gM[3];
    double cols[1 + CERT_MAX_COLS][3];
    int ncol = 0, nfree = 0;
    {
        double qq[3] = {q, 0.0, 0.0};
        pose_com(m, qq, r, &th);
    }
    cs[0] = cos(th);
    cs[1] = sin(th);
    qf[0] = r[0];
    qf[1] = r[1];
    qf[2] = th;
    if (stick) v = 0.0;
    if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        vf[0] = v * m->d[0];
        vf[1] = v * m->d[1];
        vf[2] = 0.0;
        T[0] = m->d[0];
        T[1] = m->d[1];
        T[2] = 0.0;
    } else {
        double rho[2] = {r[0] - m->pivot[0], r[1] - m->pivot[1]};
        vf[0] = -v * rho[1];
        vf[1] = v * rho[0];
        vf[2] = v;
        kap[0] = -v * v * rho[0];
        kap[1] = -v * v * rho[1];
        T[0] = -rho[1];
        T[1] = rho[0];
        T[2] = 1.0;
    }
    model_force_planar(m, fp, qf, vf, F);
    /* the friction needed with a = 0 and no stop force: M kappa - F */
    P[0] = m->m * kap[0] - F[0];
    P[1] = m->m * kap[1] - F[1];
    P[2] = m->izz * kap[2] - F[2];
    model_patch_of_gen(m, cs, P, b);
    memcpy(ce->load, b, sizeof b);
    ce->gen = P[0] * T[0] + P[1] * T[1] + P[2] * T[2];
    ce->along = fabs(ce->gen);
    {
        double tt = T[0] * T[0] + T[1] * T[1] + T[2] * T[2], k, Pa[3], ba[3], Cs = model_capacity_static(m, t);
        k = (P[0] * T[0] + P[1] * T[1] + P[2] * T[2]) / tt;
        for (int c = 0; c < 3; c++) Pa[c] = k * T[c];
        model_patch_of_gen(m, cs, Pa, ba);
        ba[2] = 0.0;    /* the force alone: its moment about the patch is a neglected load */
        /* the translation model only: a rotation's own load (a moment about
         * the pivot) has no wrench of its own apart from the pin force the
         * neglected coordinates carry */
        ce->own = Cs > 0.0 && m->def.dof == EXDEX_DOF_TRANSLATION ? cert_gauge(m, ba) / Cs : 0.0;
    }
    ce->stick = stick || v == 0.0;
    ce->th = th;
    if (!ce->stick) {
        /* the free acceleration a: wrench M T per unit a */
        double MT[3] = {m->m * T[0], m->m * T[1], m->izz * T[2]};
        model_patch_of_gen(m, cs, MT, gM);
        for (int c = 0; c < 3; c++) cols[ncol][c] = gM[c] / m->e[c];
        ncol++;
        nfree = 1;
    }
    if (m->n_src && use_stops) {
        /* without a stop force first: stops are looked for only where it fails */
        cert_eval free_ce = *ce;
        int fst = cert_decide(m, t, b, ce->stick ? NULL : vf, cs, (const double(*)[3])cols, nfree, ncol, &free_ce);
        if (fst) return fst;
        if (!(free_ce.excess > 0.0)) {
            *ce = free_ce;
            return EXDEX_OK;
        }
    }
    if (m->n_src && use_stops) {
        /* stops and obstacles in contact push along their normals with
         * lambda >= 0 and, with friction mu, along the tangent T with
         * |beta| <= mu lambda: the cone of G + mu T and G - mu T; where the
         * contact point slides along it (the reduced motion's slip s =
         * T . v + tb, the gripper's motion past a fixed contact included)
         * the friction opposes the slip, G - mu sgn(s) T alone */
        int nv = contact_nv(m), nrow = 0;
        double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
        double RG[MAX_ROWS][3], RT[MAX_ROWS][3], Rs[MAX_ROWS], Rmu[MAX_ROWS];
        /* the contact geometry in the planar coordinates: the model read
         * as planar (its rows and tangents then have three entries) */
        exdex_model mp = *m;
        mp.ndof = 3;
        contact_vertices(&mp, qf, xb, vx);
        for (int k = 0; k < m->n_stops; k++) {
            for (int j = 0; j < nv && nrow < MAX_ROWS; j++) {
                double G[3], T[3] = {0, 0, 0}, tb = 0.0;
                double gap = contact_row_planar(m, kinp, k, j, qf, vf, G, NULL, NULL);
                if (!(gap < m->tol.touch)) continue;
                if (fabs(G[0]) + fabs(G[1]) + fabs(G[2]) < FQ_MIN) continue;
                Rmu[nrow] = m->smu[k];
                if (Rmu[nrow] > 0.0) contact_stop_tangent(&mp, kinp, k, xb[j], vx[j], T, &tb);
                memcpy(RG[nrow], G, sizeof G);
                memcpy(RT[nrow], T, sizeof T);
                Rs[nrow] = T[0] * vf[0] + T[1] * vf[1] + T[2] * vf[2] + tb;
                nrow++;
            }
        }
        if (m->n_obst) {
            double G[MAX_ROWS][3], gap[MAX_ROWS], rnd[MAX_ROWS];
            int src[MAX_ROWS];
            contact_point cp[MAX_ROWS];
            int no = contact_obstacle_rows(&mp, kinp, qf, G, gap, rnd, src, cp);
            for (int i = 0; i < no && nrow < MAX_ROWS; i++) {
                double T[3] = {0, 0, 0}, tb = 0.0;
                if (!(gap[i] < m->tol.touch)) continue;
                if (fabs(G[i][0]) + fabs(G[i][1]) + fabs(G[i][2]) < FQ_MIN) continue;
                Rmu[nrow] = model_source_mu(m, src[i]);
                if (Rmu[nrow] > 0.0) contact_tangent(&mp, kinp, cp[i].x, cp[i].vx, cp[i].nB, T, &tb);
                memcpy(RG[nrow], G[i], sizeof G[i]);
                memcpy(RT[nrow], T, sizeof T);
                Rs[nrow] = T[0] * vf[0] + T[1] * vf[1] + T[2] * vf[2] + tb;
                nrow++;
            }
        }
        for (int r = 0; r < nrow; r++) {
            double sig[2];
            int ns = 0;
            if (Rmu[r] > 0.0 && fabs(RT[r][0]) + fabs(RT[r][1]) + fabs(RT[r][2]) >= FQ_MIN) {
                if (fabs(Rs[r]) > m->tol.rate) {
                    sig[ns++] = Rs[r] > 0.0 ? -1.0 : 1.0;
                } else {
                    sig[ns++] = 1.0;
                    sig[ns++] = -1.0;
                }
            } else {
                sig[ns++] = 0.0;
            }
            for (int e = 0; e < ns && ncol < 1 + CERT_MAX_COLS; e++) {
                double Gc[3], g[3];
                for (int c = 0; c < 3; c++) Gc[c] = RG[r][c] + sig[e] * Rmu[r] * RT[r][c];
                /* the reaction on the object is lambda Gc; the friction needed drops by it */
                model_patch_of_gen(m, cs, Gc, g);
                for (int c = 0; c < 3; c++) cols[ncol][c] = -g[c] / m->e[c];
                ncol++;
            }
        }
    }
    return cert_decide(m, t, b, ce->stick ? NULL : vf, cs, (const double(*)[3])cols, nfree, ncol, ce);
}

static int cert_at(const exdex_model *m, double t, double q, double v, int stick, cert_eval *ce)
{
    return cert_at_stops(m, t, q, v, stick, 1, ce);
}

/* -------------------------------------------------------- along a run */

typedef struct root_par {
    const exdex_model *m;
    double q, v;
    int stick;
    int err;
} root_par;

static double excess_of(double t, void *par)
{
    root_par *p = par;
    cert_eval ce;
    if (cert_at(p->m, t, p->q, p->v, p->stick, &ce)) {
        p->err = 1;
        return 1.0;
    }
    return ce.crossing;
}

/* The first time in (a, b] where the excess at state (q, v, stick) turns
 * > 0, given a verdict that holds at a and fails at b: Brent on the sign
 * change of the crossing (the gauge against the surface itself, where the
 * full model's guard lies; a jump of the load converges onto the jump; a
 * at once where the crossing is already past 0 there, inside the band). */
static double locate(const exdex_model *m, double a, double b, double q, double v, int stick)
{
    root_par p = {m, q, v, stick, 0};
    gsl_function F = {excess_of, &p};
    gsl_root_fsolver *s = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    double lo = a, hi = b;
    gsl_error_handler_t *old;
    if (!s) return a;
    old = gsl_set_error_handler_off();
    if (gsl_root_fsolver_set(s, &F, a, b) == GSL_SUCCESS) {
        for (int it = 0; it < 100; it++) {
            if (gsl_root_fsolver_iterate(s) != GSL_SUCCESS || p.err) break;
            lo = gsl_root_fsolver_x_lower(s);
            hi = gsl_root_fsolver_x_upper(s);
            if (hi - lo <= m->tol.root) break;
        }
    }
    gsl_set_error_handler(old);
    gsl_root_fsolver_free(s);
    /* the last time known to hold */
    return excess_of(hi, &p) > 0.0 ? lo : hi;
}

static void fill(const exdex_model *m, exdex_certificate *c, const cert_eval *ce, double t, size_t i)
{
    double wb[3], cs[2] = {cos(ce->th), sin(ce->th)};
    c->holds = 0;
    c->valid_until = t;
    c->first_bad = i;
    c->stick = ce->stick;
    model_to_b(cs, ce->load, wb);
    memcpy(c->load, wb, sizeof wb);
    c->capacity = ce->cap;
    c->gauge = ce->gauge;
    if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        /* across the slide axis (patch frame force perpendicular to d) or the turn */
        double dp[2], perp;
        double dth[2] = {cs[0] * m->d[0] + cs[1] * m->d[1], -cs[1] * m->d[0] + cs[0] * m->d[1]};
        dp[0] = -dth[1];
        dp[1] = dth[0];
        perp = ce->load[0] * dp[0] + ce->load[1] * dp[1];
        c->coordinate = fabs(ce->load[2]) / m->e[2] > fabs(perp) ? 2 : 1;
    } else {
        c->coordinate = 0;
    }
}

/* Does the reduced coordinate count as at rest at (t, q, v) after a step
 * of h? At rest to the model's rate threshold (|v| <= tol.vzero), or, for the methods without true stick,
 * within their own resolution of rest while the reduced load Q is inside
 * the reduced surface (|Q| < C, C e_r for a rotation): the regularised
 * method creeps at |E u| = eps g / sqrt(1 - g^2) (g = |Q| / C), counted at
 * rest up to twice that plus eps; the explicit method chatters within
 * |v| <= h (|Q| + C) / M (a step's update h (Q - C sgn v) / M). Qp: the
 * load |Q| when known (NULL: evaluated at t). */
static int at_rest_q(const exdex_model *m, double h, double t, double q, double v, const double *Qp)
{
    int rot = m->def.dof == EXDEX_DOF_ROTATION;
    double C, Q, M, g;
    if (fabs(v) <= m->tol.vzero) return 1;   /* the methods' own zero rate (a rest against a stop) */
    if (m->def.method != EXDEX_METHOD_REGULARISED && m->def.method != EXDEX_METHOD_EXPLICIT) return 0;
    C = model_capacity(m, t) * (rot ? m->e[2] : 1.0);
    M = rot ? m->mrot : m->m;
    if (Qp) {
        Q = *Qp;
    } else {
        frame f;
        exdex_kinematics kin;
        if (model_frame_at(m, t, &f, &kin)) return 0;
        Q = fabs(model_force_1dof(m, &f, q, v));
    }
    if (!(Q < C)) return 0;
    if (m->def.method == EXDEX_METHOD_EXPLICIT) return fabs(v) <= h * (Q + C) / M;
    g = Q / C;
    return fabs(v) * (rot ? m->e[2] : 1.0) <= m->def.eps * (1.0 + 2.0 * g / sqrt(1.0 - g * g));
}

static int at_rest(const exdex_model *m, double h, double t, double q, double v)
{
    return at_rest_q(m, h, t, q, v, NULL);
}

/* ------------------------------------------------ proofs per piece
 * The scene's switching times (model.sw_t) cut the time axis into pieces.
 * Where a piece's load is known to hold for every state the run visits in
 * one mode (stuck, slipping forwards, backwards), the samples of that mode
 * strictly inside the piece need no evaluation; only the others are
 * evaluated, as before. Two kinds of proof:
 *   constant load: a translation run in a
 *     gripper that rests or translates with a piecewise-constant
 *     acceleration (rest, Eq. 7, a trapezoid): the load is the same for
 *     every time in a piece and every state (it has no term in the
 *     position or the rate), so one evaluation per piece and mode decides
 *     it, without the stops' forces (a verdict that holds without them
 *     holds with them; one that fails is evaluated per sample with them);
 *   a bound: a 1-DoF run in a gripper that
 *     rests, translates as above or turns about a fixed axis with a
 *     piecewise-constant angular acceleration. A point fixed in B at
 *     distance rho from the axis then has the acceleration
 *     rho sqrt(alpha^2 + omega^4) (alpha constant in the piece, omega
 *     linear, so at most its larger end value), the gravity in the plate
 *     plane keeps its size when the axis is the plate normal (else at most
 *     |g|), and the force the stuck object needs in the plate plane is at
 *     most B_f = m (g_p + rho_max sqrt(alpha^2 + omega_max^4)), rho_max
 *     bounding the distance of the centre of mass from the axis over the
 *     states the run visits; its moment at the patch at most
 *     B_z = |T_z| + |pc| B_f with the inertial torque
 *     |T_z| <= I_zz alpha + 2 |I| |u_xy| (alpha + omega^2) (u the axis in B,
 *     constant). Stuck: the gauge is at most hypot(B_f, B_z / e_r) (over
 *     k_min for the exact surface); a rotation about the centre of mass
 *     (pivot at it) slipping: the slip's friction is a pure moment and
 *     the force the pin needs, at most B_f, must be zero to the
 *     certificate's tolerance. */
#define CERT_MAX_PIECES 16

typedef struct pieces {
    int n;                 /* 0: no proofs */
    double lo[CERT_MAX_PIECES], hi[CERT_MAX_PIECES];
    unsigned char proven[CERT_MAX_PIECES][3];   /* mode key: 0 stuck, 1 v > 0, 2 v < 0 */
    int qknown;            /* 1: Q[k] is the reduced load |Q| of every time and state of piece k */
    double Q[CERT_MAX_PIECES];
} pieces;

static int key_of(int rest, double v)
{
    return rest ? 0 : (v > 0.0 ? 1 : 2);
}

static double norm3(const double a[3])
{
    return sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
}

/* Is the motion one the proofs know: rest, or Eq. 7 / a trapezoid with
 * ramps, translating (*turns = 0) or turning about a fixed axis
 * (*turns = 1), or a shake turning about a fixed axis (*turns = 1),
 * played from its start? (Translating shakes, logs and chains: the block
 * proofs.) */
static int proof_motion(const exdex_model *m, int *turns)
{
    const exdex_motion_def *d = &m->def.motion;
    *turns = 0;
    if (m->motion != m->sw_motion || d->time_shift != 0.0) return 0;
    if (d->kind == EXDEX_MOTION_REST) return 1;
    if (d->kind == EXDEX_MOTION_SHAKE && d->rotation) {
        /* a turn about a fixed axis; its angular rate and acceleration at
         * most |A| w and |A| w^2 (prove_pieces) */
        *turns = 1;
        return 1;
    }
    if (d->kind != EXDEX_MOTION_ASYMMETRIC && d->kind != EXDEX_MOTION_TRAPEZOID) return 0;
    if (d->kind == EXDEX_MOTION_TRAPEZOID && d->amplitude != 0.0 &&
        !(d->duration - fabs(d->amplitude) / d->v_max > 0.0))
        return 0;   /* a velocity jump */
    *turns = d->rotation != 0;
    return 1;
}

static int prove_pieces(const exdex_model *m, const exdex_trajectory *out, pieces *pv)
{
    int turns, pc, st;
    size_t n = out->n;
    double t_first = out->t[0], t_last = out->t[n - 1];
    double dq = 0.0, rho_ref = 0.0, u_xy = 0.0, g_p = 0.0, Inorm = 0.0, nax[3] = {0, 0, 0};
    pv->n = 0;
    pv->qknown = 0;
    if (!proof_motion(m, &turns)) return EXDEX_OK;
    if (m->sw_n + 1 > CERT_MAX_PIECES) return EXDEX_OK;
    pc = m->def.dof == EXDEX_DOF_TRANSLATION && !turns;
    if (!pc) {
        /* the bound: the reference point (the pivot, or the centre of mass
         * at the start) and how far the centre of mass gets from it */
        double rref[3] = {0, 0, 0};
        if (m->def.dof == EXDEX_DOF_ROTATION) {
            rref[0] = m->pivot[0];
            rref[1] = m->pivot[1];
            dq = hypot(m->c[0], m->c[1]);
        } else {
            rref[0] = m->r0[0];
            rref[1] = m->r0[1];
            for (size_t i = 0; i < n; i++) {
                double a = fabs(out->q[i] - m->s0);
                if (a > dq) dq = a;
            }
        }
        for (int i = 0; i < 9; i++) Inorm += m->I[i] * m->I[i];
        Inorm = sqrt(Inorm);
        if (turns) {
            const exdex_motion_def *d = &m->def.motion;
            exdex_kinematics k;
            double na = norm3(d->axis), x[3], xn = 0.0, npl[3], cr[3], gn = 0.0;
            st = exdex_motion_eval(m->motion, t_first, &k);
            if (st) return st;
            if (!(na > 0.0)) return EXDEX_OK;
            for (int c = 0; c < 3; c++) nax[c] = d->axis[c] / na;
            /* the point in A, its distance from the axis */
            for (int c = 0; c < 3; c++)
                x[c] = k.p[c] + k.R[3 * c] * rref[0] + k.R[3 * c + 1] * rref[1] + k.R[3 * c + 2] * rref[2] -
                       d->center[c];
            for (int c = 0; c < 3; c++) xn += x[c] * nax[c];
            for (int c = 0; c < 3; c++) x[c] -= xn * nax[c];
            rho_ref = norm3(x) * (1.0 + CERT_ROUND);
            /* the axis in B (constant: the axis is fixed in A and turns B about itself) */
            {
                double ub[3];
                ex_mulmtv3(ub, k.R, nax);
                u_xy = hypot(ub[0], ub[1]);
            }
            /* gravity in the plate plane */
            npl[0] = k.R[2];
            npl[1] = k.R[5];
            npl[2] = k.R[8];
            ex_cross3(cr, nax, npl);
            if (norm3(cr) <= 1e-12) {
                double gp[3];
                for (int c = 0; c < 3; c++) gn += m->g[c] * npl[c];
                for (int c = 0; c < 3; c++) gp[c] = m->g[c] - gn * npl[c];
                g_p = norm3(gp) + CERT_ROUND * norm3(m->g);
            } else {
                g_p = norm3(m->g);
            }
        }
    }
    pv->qknown = pc && !m->grip_n;
    for (size_t k = 0; k <= m->sw_n; k++) {
        double lo = k ? m->sw_t[k - 1] : -INFINITY, hi = k < m->sw_n ? m->sw_t[k] : INFINITY;
        double a = lo > t_first ? lo : t_first, b = hi < t_last ? hi : t_last, tm = a + 0.5 * (b - a);
        double Csmin, Csmax, Cmin;
        int j = pv->n;
        if (hi <= t_first) continue;
        if (lo > t_last) break;
        pv->lo[j] = lo;
        pv->hi[j] = hi;
        pv->proven[j][0] = pv->proven[j][1] = pv->proven[j][2] = 0;
        /* a grip schedule: the capacities' least (and the static one's
         * largest) over the piece, at its ends (linear, step and Steffen's
         * monotone cubic pieces are monotone between breakpoints, which
         * are switching times), the far end taken CERT_PIECE_INSIDE of the
         * piece inside it and widened by as much of the piece's change */
        if (m->grip_n) {
            double te = b > a ? b - CERT_PIECE_INSIDE * (b - a) : a, s0 = model_capacity_static(m, a),
                   s1 = model_capacity_static(m, te), k0 = model_capacity(m, a), k1 = model_capacity(m, te);
            Csmin = fmin(s0, s1) - CERT_PIECE_INSIDE * fabs(s1 - s0);
            Csmax = fmax(s0, s1) + CERT_PIECE_INSIDE * fabs(s1 - s0);
            Cmin = fmin(k0, k1) - CERT_PIECE_INSIDE * fabs(k1 - k0);
        } else {
            Csmin = Csmax = model_capacity_static(m, tm);
            Cmin = model_capacity(m, tm);
        }
        if (pc) {
            for (int key = 0; key < 3; key++) {
                cert_eval ce;
                st = cert_at_stops(m, tm, out->q[0], key == 0 ? 0.0 : (key == 1 ? m->scale.V : -m->scale.V),
                                   key == 0, 0, &ce);
                if (st) return st;
                /* no sample sticks where the reduced load exceeds the static
                 * capacity (unless a stop holds it) */
                if (!m->grip_n) {
                    pv->proven[j][key] =
                        !(ce.excess > 0.0) || (key == 0 && !m->n_src && ce.along > ce.cap * (1.0 + 1e-9));
                } else if (key == 0) {
                    /* the same load against the least static capacity */
                    pv->proven[j][key] = ce.gauge * ce.cap <= Csmin || (!m->n_src && ce.along > Csmax * (1.0 + 1e-9));
                } else {
                    /* the slip's residual against the tolerance of the least capacity */
                    pv->proven[j][key] =
                        ce.gauge * ce.cap <= CERT_SLIP_TOL * (m->scale.F + model_ell_norm(m, ce.load) + Cmin) &&
                        !(ce.excess > 0.0);
                }
            }
            {
                frame f;
                exdex_kinematics kin;
                st = model_frame_at(m, tm, &f, &kin);
                if (st) return st;
                pv->Q[j] = fabs(model_force_1dof(m, &f, out->q[0], 0.0));
            }
        } else {
            double Bf, Bz, Cs = Csmin, C = Cmin, gauge;
            if (turns) {
                /* omega at the piece's ends (linear inside), alpha inside */
                double om = 0.0, al = 0.0, ts[3] = {a + CERT_PIECE_INSIDE * (b - a), tm, b - CERT_PIECE_INSIDE * (b - a)}, s;
                for (int e = 0; e < 3; e++) {
                    exdex_kinematics kk;
                    st = exdex_motion_eval(m->motion, ts[e], &kk);
                    if (st) return st;
                    if (norm3(kk.w) > om) om = norm3(kk.w);
                    if (norm3(kk.dw) > al) al = norm3(kk.dw);
                }
                om *= 1.0 + CERT_PIECE_INSIDE;   /* the ends evaluated CERT_PIECE_INSIDE of the piece inside it */
                if (m->def.motion.kind == EXDEX_MOTION_SHAKE && a < m->def.motion.duration) {
                    /* theta = A (1 - cos w t): |theta'| <= |A| w, |theta''| <= |A| w^2 */
                    double w = 2.0 * 3.14159265358979323846 * m->def.motion.frequency, A = fabs(m->def.motion.amplitude);
                    om = fmax(om, A * w * (1.0 + CERT_ROUND));
                    al = fmax(al, A * w * w * (1.0 + CERT_ROUND));
                }
                s = sqrt(al * al + om * om * om * om);
                Bf = m->m * (g_p + (rho_ref + dq) * s);
                Bz = m->izz * al * (1.0 + CERT_ROUND) + 2.0 * Inorm * u_xy * (al + om * om) + hypot(m->pc[0], m->pc[1]) * Bf;
            } else {
                /* rest or a translating gripper: gravity and B's acceleration, constant in the piece */
                frame f;
                exdex_kinematics kin;
                st = model_frame_at(m, tm, &f, &kin);
                if (st) return st;
                Bf = m->m * hypot(f.gB[0] - f.a0[0], f.gB[1] - f.a0[1]) * (1.0 + CERT_ROUND);
                Bz = hypot(m->pc[0], m->pc[1]) * Bf;
            }
            gauge = hypot(Bf, Bz / m->e[2]);
            if (m->ls_exact) gauge = m->ls.kmin > 0.0 ? gauge / m->ls.kmin : INFINITY;
            pv->proven[j][0] = gauge <= Cs * (1.0 - CERT_ROUND);
            if (m->def.dof == EXDEX_DOF_ROTATION && m->c[0] == 0.0 && m->c[1] == 0.0 && !m->ls_exact &&
                Bf <= 0.5 * CERT_SLIP_TOL * (m->scale.F + C))
                pv->proven[j][1] = pv->proven[j][2] = 1;
        }
        pv->n++;
    }
    return EXDEX_OK;
}

/* ------------------------------------------------ proofs per block
 * A 1-DoF run in a gripper that does not turn over [ta, tb]
 * (motion_accel_box: rest, translating profiles and shakes, logs of a
 * constant orientation, chains of them): the frame has no angular rate or
 * acceleration, gravity in B is constant, and B's acceleration a0 has its
 * plate-plane part in the box the motion gives.
 *   Translation: the load the neglected coordinates need is that of
 *     m (g_B - a0) at the patch, the same for every state of one mode (no
 *     term in the position or the rate), and affine in a0.
 *   Rotation (angle theta of the body, rate omega, the centre of mass at
 *     rho = Rz(theta) c from the pivot): the plate-plane friction the pin
 *     needs is m (-omega^2 rho) - m (g_B - a0), and the inertial torque
 *     about the normal is zero (w = dw = 0), so in the patch frame the load
 *     is b = L f with L f = (f, pc_y f_x - pc_x f_y) linear and
 *         f = Rz(-theta) m (a0 - g_B) - m omega^2 c
 *     (Rz(-theta) rho = c). Over the block's samples theta lies in
 *     [th0, th1] and omega^2 in [w0^2, w1^2] (the samples of one sign of
 *     the rate); f lies in the Minkowski sum of S = {Rz(-theta) u : theta in
 *     [th0, th1], u in the box U of m (a0 - g_B)} and the segment
 *     {-m s c : s in [w0^2, w1^2]}. Enclosure of S: a point Rz(-theta) u
 *     with u = sum_k l_k u_k (the corners u_k of U, l_k >= 0, sum 1) is
 *     sum_k l_k Rz(-theta) u_k, and Rz(-theta) u_k lies on the arc of
 *     radius |u_k| over the angles [arg u_k - th1, arg u_k - th0], of half
 *     span h = (th1 - th0) / 2 < pi / 2. That arc lies in the triangle of
 *     its ends Rz(-th0) u_k, Rz(-th1) u_k and the tangents' meeting point
 *     Rz(-thm) u_k / cos h (thm the middle): the arc is on the origin's
 *     side of both end tangents and beyond its chord. So f lies in the
 *     convex hull of the points (Rz(-theta_j) u_j + (-m s c)) over the
 *     triangles' vertices (theta_j, u_j in {(th0, u_k), (th1, u_k),
 *     (thm, u_k / cos h)}) and s in {w0^2, w1^2}; each is the load of the
 *     state (theta_j, +-sqrt(s)) in a frame with m (a0 - g_B) = u_j (for
 *     u_k / cos h: a0 = g_B + (a0_k - g_B) / cos h). A stuck state has
 *     omega = 0 (s = 0). The slip's friction is that of the twist
 *     omega (perp(c + pc), 1) (fixed in the patch frame but for omega's
 *     sign) and the free acceleration's column is fixed too, so a slip's
 *     least residual is convex in b as well.
 * The gauge, and a slip's least residual over its free acceleration, are
 * convex in the load, so their largest value over the enclosure is at one
 * of its vertices: a mode that holds at the vertices (stuck: a gauge
 * within the least static capacity over [ta, tb], where a grip schedule is
 * monotone between its switching times; slipping, with a constant grip:
 * the residual within the certificate's tolerance without the load's own
 * share) holds at every sample of the block, as its own evaluation would
 * find (the stick test has FRICTION_BAND, the slip test the load's share
 * of its tolerance, beyond the rounding of the vertices and the samples).
 * Evaluated without the stops' forces (a verdict that holds without them
 * holds with them). need[key]: the modes to prove; pr[key] = 1 where
 * proven. Samples i0 .. i1 - 1 (their intervals (t_{i-1}, t_i]). */
#define CERT_BLOCK_MIN 16
/* A rotation block is tried only while its samples' angles span at most
 * twice this (cos of it >= 0.92: the enclosure stays tight). */
#define CERT_ROT_HALF_SPAN 0.39269908169872414

/* The arc of radius r = |u| over the angles [arg u - th1, arg u - th0],
 * half span h < pi / 2, lies in the triangle of its ends A = Rz(-th0) u,
 * B = Rz(-th1) u and Q = Rz(-thm) u / cos h (thm the middle angle, e the
 * unit vector of the arc's middle, Q = r e / cos h). Every point P of the
 * arc has P . A <= |P| |A| = r^2 and P . B <= r^2 (the circle lies on the
 * origin's side of its tangents at A and B), and P . e = r cos(angle of P
 * from e) >= r cos h (it lies beyond the chord). Those three half planes
 * meet in the triangle ABQ: the line P . A = r^2 holds A and Q
 * (Q . A = r^2 cos h / cos h), P . B = r^2 holds B and Q, and
 * P . e = r cos h holds A and B. */
int certify_arc_triangle(double th0, double th1, double half_max, double th[3], double sc[3])
{
    double h = 0.5 * (th1 - th0);
    if (!(h >= 0.0 && h <= half_max && half_max < 1.5707963267948966)) return 0;
    th[0] = th0;
    sc[0] = 1.0;
    if (h == 0.0) return 1;
    th[1] = th1;
    sc[1] = 1.0;
    th[2] = th0 + h;
    sc[2] = 1.0 / cos(h);
    return 3;
}

static int prove_block_turning(const exdex_model *m, const exdex_trajectory *out, size_t i0, size_t i1,
                               const int need[3], unsigned char pr[3], double qr[2], frame_box_cache *fc);

/* A rotation block's samples i0 .. i1-1: the range [th0, th1] of their
 * angles, and of |omega| of each sign of the moving ones in [wl, wh] (key
 * 1: v > 0, key 2: v < 0; key_of), each widening what it is given; with
 * vlo, vhi, the range of v too. */
static void block_ranges(const exdex_model *m, const exdex_trajectory *out, size_t i0, size_t i1, double *th0,
                         double *th1, double wl[3], double wh[3], double *vlo, double *vhi)
{
    const double *qs = out->q, *vs = out->v, vzero = m->tol.vzero;
    const unsigned char *stick = out->stick;
    double t0 = *th0, t1 = *th1, lo = vlo ? *vlo : 0.0, hi = vhi ? *vhi : 0.0;
    double l1 = wl[1], l2 = wl[2], h1 = wh[1], h2 = wh[2];
    for (size_t j = i0; j < i1; j++) {
        double v = vs[j], a = fabs(v), q = qs[j];
        if (v < lo) lo = v;
        if (v > hi) hi = v;
        if (q < t0) t0 = q;
        if (q > t1) t1 = q;
        if (stick[j] || a <= vzero) continue;
        if (v > 0.0) {
            if (a < l1) l1 = a;
            if (a > h1) h1 = a;
        } else {
            if (a < l2) l2 = a;
            if (a > h2) h2 = a;
        }
    }
    *th0 = t0;
    *th1 = t1;
    wl[1] = l1;
    wl[2] = l2;
    wh[1] = h1;
    wh[2] = h2;
    if (vlo) {
        *vlo = lo;
        *vhi = hi;
    }
}

/* The static capacity held over a block [ta, tb] (midpoint tm): a grip
 * schedule's least at the block's ends (monotone between breakpoints, as
 * for the pieces above), widened by CERT_PIECE_INSIDE of its change;
 * without one, the constant capacity. */
static double block_static_capacity(const exdex_model *m, double ta, double tb, double tm)
{
    if (m->grip_n) {
        double s0 = model_capacity_static(m, ta), s1 = model_capacity_static(m, tb);
        return fmin(s0, s1) - CERT_PIECE_INSIDE * fabs(s1 - s0);
    }
    return model_capacity_static(m, tm);
}

static int prove_block(const exdex_model *m, const exdex_trajectory *out, size_t i0, size_t i1, const int need[3],
                       unsigned char pr[3], double qr[2], frame_box_cache *fc)
{
    double glo = INFINITY, ghi = -INFINITY;
    double ta = out->t[i0 - 1], tb = out->t[i1 - 1], q = out->q[i0];
    double lo[3], hi[3], tm = ta + 0.5 * (tb - ta), bl[2] = {INFINITY, INFINITY}, bh[2] = {-INFINITY, -INFINITY};
    double Cs, C, ax[2][2];
    /* rotation: the samples' angles, and |omega| of each sign (key 1: v > 0, key 2: v < 0) */
    double th0 = q, th1 = q, wl[3] = {0.0, INFINITY, INFINITY}, wh[3] = {0.0, 0.0, 0.0}, vth[3] = {q, q, q};
    double vsc[3] = {1.0, 1.0, 1.0};
    int nth = 1;
    int rot = m->def.dof == EXDEX_DOF_ROTATION;
    frame f;
    exdex_kinematics kin;
    int st, nx, ny;
    pr[0] = pr[1] = pr[2] = 0;
    qr[0] = 0.0;
    qr[1] = INFINITY;
    if (m->def.dof != EXDEX_DOF_TRANSLATION && !rot) return EXDEX_OK;
    if (!motion_accel_box(m->motion, ta, tb, lo, hi))
        return prove_block_turning(m, out, i0, i1, need, pr, qr, fc);
    for (int c = 0; c < 3; c++)
        if (!isfinite(lo[c]) || !isfinite(hi[c])) return EXDEX_OK;
    if (rot) {
        block_ranges(m, out, i0, i1, &th0, &th1, wl, wh, NULL, NULL);
        nth = certify_arc_triangle(th0, th1, CERT_ROT_HALF_SPAN, vth, vsc);
        if (!nth) return EXDEX_OK;
    }
    st = model_frame_at(m, tm, &f, &kin);
    if (st) return st;
    /* the box's corners in B (R constant over [ta, tb]), its plate-plane bounding box */
    for (int k = 0; k < 8; k++) {
        double a[3] = {(k & 1 ? hi : lo)[0], (k & 2 ? hi : lo)[1], (k & 4 ? hi : lo)[2]}, aB[3];
        ex_mulmtv3(aB, kin.R, a);
        for (int c = 0; c < 2; c++) {
            if (aB[c] < bl[c]) bl[c] = aB[c];
            if (aB[c] > bh[c]) bh[c] = aB[c];
        }
    }
    for (int c = 0; c < 3; c++) f.w[c] = f.dw[c] = 0.0;
    ax[0][0] = bl[0];
    ax[0][1] = bh[0];
    ax[1][0] = bl[1];
    ax[1][1] = bh[1];
    nx = bl[0] < bh[0] ? 2 : 1;
    ny = bl[1] < bh[1] ? 2 : 1;
    Cs = block_static_capacity(m, ta, tb, tm);
    C = model_capacity(m, tm);
    for (int key = 0; key < 3; key++) {
        int ok = 1;
        /* rotation: the arc's triangle (one vertex for a single angle), the rate's ends */
        int nw = rot && key && wh[key] > wl[key] ? 2 : 1;
        if (!need[key] || (key && m->grip_n)) continue;
        if (rot && key && !(wl[key] <= wh[key])) continue;   /* no sample of that mode */
        for (int i = 0; i < nx && ok; i++) {
            for (int j = 0; j < ny && ok; j++) {
                for (int a = 0; a < nth && ok; a++) {
                    for (int b = 0; b < nw && ok; b++) {
                        cert_eval ce;
                        double th = vth[a], sc = vsc[a], v = key == 0 ? 0.0 : (key == 1 ? m->scale.V : -m->scale.V);
                        if (rot && key) v = (key == 1 ? 1.0 : -1.0) * (b ? wh[key] : wl[key]);
                        /* the corner; for the tangents' meeting point m (a0 - g_B) scaled by sc */
                        f.a0[0] = sc == 1.0 ? ax[0][i] : f.gB[0] + (ax[0][i] - f.gB[0]) * sc;
                        f.a0[1] = sc == 1.0 ? ax[1][j] : f.gB[1] + (ax[1][j] - f.gB[1]) * sc;
                        st = cert_at_frame(m, tm, &f, &kin, th, v, key == 0, 0, &ce);
                        if (st) return st;
                        if (key == 0) {
                            ok = ce.gauge * ce.cap <= Cs;
                            if (ce.gen < glo) glo = ce.gen;
                            if (ce.gen > ghi) ghi = ce.gen;
                        } else ok = ce.gauge * ce.cap <= CERT_SLIP_TOL * (m->scale.F + C) && !(ce.excess > 0.0);
                    }
                }
            }
        }
        pr[key] = (unsigned char)ok;
        if (key == 0 && ok) {
            /* |Q| over the block: Q is linear in the load's enclosure (the
             * centripetal term has no moment about the pivot), so it lies
             * between its values at the vertices */
            qr[0] = glo > 0.0 ? glo : (ghi < 0.0 ? -ghi : 0.0);
            qr[1] = fmax(fabs(glo), fabs(ghi));
        }
    }
    return EXDEX_OK;
}

/* ------------------------------------------ proofs per block, turning
 * A rotation run in a gripper that turns over [ta, tb]: motion_frame_box
 * encloses the frame's g_B, a0, w, dw (B coordinates) over the block's
 * times, the samples give the angle theta in [th0, th1] and the rate v in
 * [wl, wh] (one sign, key 1 or 2; v = 0 stuck). The load is that of
 * cert_at_frame with a = 0 and no stop force, in interval arithmetic
 * (util.h: each interval holds the exact value of its formula over its
 * operands' intervals): with rho = Rz(theta) c, r = pivot + rho,
 * rd = v ez x rho,
 *   F = m (g_B - a0 - dw x r - w x (w x r) - 2 w x rd)   (plate plane),
 *   P_xy = -m v^2 rho - F,   P_z = (I_B (dw + v w x ez))_z + (W x I_B W)_z,
 *   I_B = Rz(theta) I Rz(theta)^T, W = w + v ez,
 * and b the patch wrench of P (model_patch_of_gen), so every sample's
 * exact load lies in the box of b. The samples compute it in floating
 * point (some hundred operations on numbers bounded by the terms' size S
 * below), so the box is widened by CERT_ROUND S, beyond that rounding. The
 * gauge and a slip's least residual over its free acceleration are convex
 * in b (for a slip the friction and the free column are fixed in the
 * patch frame up to the rate's sign: u = v (perp(c + pc), 1) there), so
 * their largest value over the box is at one of its 8 corners; a mode
 * that holds at the corners (as prove_block: a stuck gauge within the
 * least static capacity, a slip's residual within the tolerance without
 * the load's own share) holds at every sample of the block. The slip's
 * friction and column are evaluated at one state of the block (its middle
 * angle, the least rate): they differ from a sample's by rounding only,
 * far inside the tolerance's share left out. A translation run is the
 * same with the slide coordinate's range for the angle's (iv_trans_load:
 * the body's angle fixed, its slip twist and free column the slide
 * axis's). The rest band of the
 * explicit and regularised methods depends on the rate here (Coriolis
 * and gyroscopic terms): qr is left unknown. */
/* P_z = (I_B (dw + V w x ez))_z + (W x I_B W)_z, W = w + V ez, I_B = Rz(theta)
 * I Rz(theta)^T with ct, st its cosine and sine (the torque's negative,
 * model_torque_z_cs in interval arithmetic). */
static ex_iv iv_inertia_z(const exdex_model *m, const frame_box *fb, ex_iv ct, ex_iv st, ex_iv V)
{
    ex_iv IB[9], vv[3], W[3], Iv[3], IW[3], R[9], RI[9];
    /* I_B = Rz I Rz^T */
    for (int i = 0; i < 9; i++) R[i] = ex_iv_pt(0.0);
    R[0] = ct;
    R[1] = ex_iv_neg(st);
    R[3] = st;
    R[4] = ct;
    R[8] = ex_iv_pt(1.0);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            ex_iv a = ex_iv_pt(0.0);
            for (int k = 0; k < 3; k++) a = ex_iv_add(a, ex_iv_scale(m->I[3 * k + j], R[3 * i + k]));
            RI[3 * i + j] = a;
        }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            ex_iv a = ex_iv_pt(0.0);
            for (int k = 0; k < 3; k++) a = ex_iv_add(a, ex_iv_mul(RI[3 * i + k], R[3 * j + k]));
            IB[3 * i + j] = a;
        }
    /* dw + v w x ez, w x ez = (w_y, -w_x, 0); W = w + v ez */
    vv[0] = ex_iv_add(fb->dw[0], ex_iv_mul(V, fb->w[1]));
    vv[1] = ex_iv_sub(fb->dw[1], ex_iv_mul(V, fb->w[0]));
    vv[2] = fb->dw[2];
    W[0] = fb->w[0];
    W[1] = fb->w[1];
    W[2] = ex_iv_add(fb->w[2], V);
    for (int i = 0; i < 3; i++) {
        Iv[i] = ex_iv_add(ex_iv_add(ex_iv_mul(IB[3 * i], vv[0]), ex_iv_mul(IB[3 * i + 1], vv[1])), ex_iv_mul(IB[3 * i + 2], vv[2]));
        IW[i] = ex_iv_add(ex_iv_add(ex_iv_mul(IB[3 * i], W[0]), ex_iv_mul(IB[3 * i + 1], W[1])), ex_iv_mul(IB[3 * i + 2], W[2]));
    }
    /* P_z = -torque_z = (I_B v)_z + (W x I_B W)_z */
    return ex_iv_add(Iv[2], ex_iv_sub(ex_iv_mul(W[0], IW[1]), ex_iv_mul(W[1], IW[0])));
}

/* The frame's part of the load at the centre of mass r moving at rd in B:
 * F_xy = m (g_B - a0 - dw x r - w x (w x r) - 2 w x rd), and the sizes of
 * the frame's terms for the load's scale (|r|, |w|, |dw|, |g_B|, |a0|, |I|). */
typedef struct { double rm, om, dm, gm, am, In; } load_sizes;

static void iv_frame_force(const exdex_model *m, const frame_box *fb, const ex_iv r[3], const ex_iv rd[3], ex_iv F[2],
                           load_sizes *z)
{
    ex_iv t1[3], t2[3], t3[3], t4[3];
    ex_iv_cross3(t1, fb->dw, r);
    ex_iv_cross3(t2, fb->w, r);
    ex_iv_cross3(t3, fb->w, t2);
    ex_iv_cross3(t4, fb->w, rd);
    for (int c = 0; c < 2; c++) {
        ex_iv f = ex_iv_sub(ex_iv_sub(fb->gB[c], fb->a0[c]), ex_iv_add(ex_iv_add(t1[c], t3[c]), ex_iv_scale(2.0, t4[c])));
        F[c] = ex_iv_scale(m->m, f);
    }
    z->rm = ex_iv_mag(r[0]) + ex_iv_mag(r[1]);
    z->om = ex_iv_mag(fb->w[0]) + ex_iv_mag(fb->w[1]) + ex_iv_mag(fb->w[2]);
    z->dm = ex_iv_mag(fb->dw[0]) + ex_iv_mag(fb->dw[1]) + ex_iv_mag(fb->dw[2]);
    z->gm = z->am = z->In = 0.0;
    for (int c = 0; c < 3; c++) {
        z->gm += ex_iv_mag(fb->gB[c]);
        z->am += ex_iv_mag(fb->a0[c]);
    }
    for (int i = 0; i < 9; i++) z->In += fabs(m->I[i]);
}

/* The plates' wrench b from the load P in B, the body at angle (ct, st):
 * P_xy turned into the body, and the torque about the patch centre. */
static void iv_plate_load(const exdex_model *m, ex_iv ct, ex_iv st, const ex_iv P[3], ex_iv b[3])
{
    ex_iv px = ex_iv_add(ex_iv_mul(ct, P[0]), ex_iv_mul(st, P[1]));
    ex_iv py = ex_iv_sub(ex_iv_mul(ct, P[1]), ex_iv_mul(st, P[0]));
    b[0] = px;
    b[1] = py;
    b[2] = ex_iv_add(P[2], ex_iv_sub(ex_iv_scale(m->pc[1], px), ex_iv_scale(m->pc[0], py)));
}

static void iv_patch_load(const exdex_model *m, const frame_box *fb, ex_iv TH, ex_iv V, ex_iv b[3], double *S,
                          ex_iv *gen)
{
    ex_iv ct = ex_iv_cos_sin(TH, 0), st = ex_iv_cos_sin(TH, 1), rho[3], r[3], rd[3];
    ex_iv F[2], P[3], v2 = ex_iv_sqr(V);
    double mm = m->m;
    load_sizes z;
    rho[0] = ex_iv_sub(ex_iv_scale(m->c[0], ct), ex_iv_scale(m->c[1], st));
    rho[1] = ex_iv_add(ex_iv_scale(m->c[0], st), ex_iv_scale(m->c[1], ct));
    rho[2] = ex_iv_pt(0.0);
    for (int c = 0; c < 3; c++) r[c] = c < 2 ? ex_iv_add(ex_iv_pt(m->pivot[c]), rho[c]) : ex_iv_pt(0.0);
    rd[0] = ex_iv_neg(ex_iv_mul(V, rho[1]));
    rd[1] = ex_iv_mul(V, rho[0]);
    rd[2] = ex_iv_pt(0.0);
    iv_frame_force(m, fb, r, rd, F, &z);
    for (int c = 0; c < 2; c++) P[c] = ex_iv_sub(ex_iv_neg(ex_iv_scale(mm, ex_iv_mul(v2, rho[c]))), F[c]);
    P[2] = iv_inertia_z(m, fb, ct, st, V);
    /* the generalised load P . T, T = (-rho_y, rho_x, 1) */
    *gen = ex_iv_add(ex_iv_sub(ex_iv_mul(rho[0], P[1]), ex_iv_mul(rho[1], P[0])), P[2]);
    iv_plate_load(m, ct, st, P, b);
    {
        /* the terms' size */
        double vm = ex_iv_mag(V), cm = fabs(m->c[0]) + fabs(m->c[1]);
        *S = (1.0 + fabs(m->pc[0]) + fabs(m->pc[1])) *
             (mm * (z.gm + z.am + z.dm * z.rm + z.om * z.om * z.rm + 2.0 * z.om * vm * cm + vm * vm * cm) +
              z.In * (z.dm + vm * z.om + (z.om + vm) * (z.om + vm)));
    }
}

/* The same load of a translation run in a turning gripper: the centre of
 * mass at r = r0 + (Q - s0) d moving at rd = V d, the body's angle th0
 * fixed (no rate of its own: kappa = 0 and the torque's rate 0), so
 *   P_xy = -m (g_B - a0 - dw x r - w x (w x r) - 2 w x rd),
 *   P_z = (I_B dw)_z + (w x I_B w)_z,
 * and gen = P . (d, 0), the load along the slide axis. */
static void iv_trans_load(const exdex_model *m, const frame_box *fb, ex_iv Q, ex_iv V, ex_iv b[3], double *S,
                          ex_iv *gen)
{
    ex_iv TH = ex_iv_pt(m->th0), ct = ex_iv_cos_sin(TH, 0), st = ex_iv_cos_sin(TH, 1), r[3], rd[3];
    ex_iv F[2], P[3], dq = ex_iv_sub(Q, ex_iv_pt(m->s0));
    double mm = m->m;
    load_sizes z;
    for (int c = 0; c < 2; c++) {
        r[c] = ex_iv_add(ex_iv_pt(m->r0[c]), ex_iv_scale(m->d[c], dq));
        rd[c] = ex_iv_scale(m->d[c], V);
    }
    r[2] = rd[2] = ex_iv_pt(0.0);
    iv_frame_force(m, fb, r, rd, F, &z);
    for (int c = 0; c < 2; c++) P[c] = ex_iv_neg(F[c]);
    P[2] = iv_inertia_z(m, fb, ct, st, ex_iv_pt(0.0));
    *gen = ex_iv_add(ex_iv_scale(m->d[0], P[0]), ex_iv_scale(m->d[1], P[1]));
    iv_plate_load(m, ct, st, P, b);
    {
        /* the terms' size */
        double vm = ex_iv_mag(V);
        *S = (1.0 + fabs(m->pc[0]) + fabs(m->pc[1])) *
             (mm * (z.gm + z.am + z.dm * z.rm + z.om * z.om * z.rm + 2.0 * z.om * vm) + z.In * (z.dm + z.om * z.om));
    }
}

/* The run's load: th the angle (rotation) or the slide coordinate (translation). */
static void iv_load(const exdex_model *m, const frame_box *fb, ex_iv th, ex_iv v, ex_iv b[3], double *S, ex_iv *gen)
{
    if (m->def.dof == EXDEX_DOF_TRANSLATION) iv_trans_load(m, fb, th, v, b, S, gen);
    else iv_patch_load(m, fb, th, v, b, S, gen);
}

/* The load's box over the frame's enclosure fb (widened for the samples'
 * rounding); 0 if not finite. */
static int turning_load(const exdex_model *m, const frame_box *fb, ex_iv th, ex_iv v, ex_iv b[3])
{
    double S;
    ex_iv gen;
    if (!ex_iv_ok(th) || !ex_iv_ok(v)) return 0;
    iv_load(m, fb, th, v, b, &S, &gen);
    for (int c = 0; c < 3; c++) {
        b[c].lo -= CERT_ROUND * S;
        b[c].hi += CERT_ROUND * S;
        if (!ex_iv_ok(b[c])) return 0;
    }
    return 1;
}

int certify_turning_load(const exdex_model *m, double ta, double tb, ex_iv th, ex_iv v, ex_iv b[3])
{
    frame_box fb;
    if (m->ndof != 1 || (m->def.dof != EXDEX_DOF_ROTATION && m->def.dof != EXDEX_DOF_TRANSLATION)) return 0;
    if (!motion_frame_box(m->motion, ta, tb, m->g, &fb)) return 0;
    return turning_load(m, &fb, th, v, b);
}

static int prove_block_turning(const exdex_model *m, const exdex_trajectory *out, size_t i0, size_t i1,
                               const int need[3], unsigned char pr[3], double qr[2], frame_box_cache *fc)
{
    double ta = out->t[i0 - 1], tb = out->t[i1 - 1], tm = ta + 0.5 * (tb - ta), q = out->q[i0];
    double th0 = q, th1 = q, wl[3] = {0.0, INFINITY, INFINITY}, wh[3] = {0.0, 0.0, 0.0}, Cs, C, vlo = 0.0, vhi = 0.0;
    int expl = m->def.method == EXDEX_METHOD_REGULARISED || m->def.method == EXDEX_METHOD_EXPLICIT;
    frame_box fb;
    int rot = m->def.dof == EXDEX_DOF_ROTATION;
    block_ranges(m, out, i0, i1, &th0, &th1, wl, wh, &vlo, &vhi);
    if (rot && !(th1 - th0 <= 2.0 * CERT_ROT_HALF_SPAN)) return EXDEX_OK;
    if (!motion_frame_box_cached(m->motion, ta, tb, m->g, &fb, fc)) return EXDEX_OK;
    Cs = block_static_capacity(m, ta, tb, tm);
    C = model_capacity(m, tm);
    for (int key = 0; key < 3; key++) {
        ex_iv b[3], TH = {th0, th1}, V = {0.0, 0.0};
        double cs[2], vf[3], cols[1][3];
        int ok = 1, nfree = 0;
        if (!need[key] || (key && m->grip_n)) continue;
        if (key && !(wl[key] <= wh[key])) continue;   /* no sample of that mode */
        if (key) {
            V.lo = key == 1 ? wl[key] : -wh[key];
            V.hi = key == 1 ? wh[key] : -wl[key];
        }
        if (!turning_load(m, &fb, TH, V, b)) return EXDEX_OK;
        if (key && !rot) {
            /* a translation's slip twist and free column: the slide axis's */
            double v = key == 1 ? wl[key] : -wl[key], MT[3] = {m->m * m->d[0], m->m * m->d[1], 0.0}, gM[3];
            cs[0] = cos(m->th0);
            cs[1] = sin(m->th0);
            vf[0] = v * m->d[0];
            vf[1] = v * m->d[1];
            vf[2] = 0.0;
            model_patch_of_gen(m, cs, MT, gM);
            for (int c = 0; c < 3; c++) cols[0][c] = gM[c] / m->e[c];
            nfree = 1;
        } else if (key) {
            /* the slip's twist and free column at one state of the block */
            double th = th0 + 0.5 * (th1 - th0), v = key == 1 ? wl[key] : -wl[key], rho[2], MT[3], gM[3];
            rot2(rho, th, m->c);
            cs[0] = cos(th);
            cs[1] = sin(th);
            vf[0] = -v * rho[1];
            vf[1] = v * rho[0];
            vf[2] = v;
            MT[0] = -m->m * rho[1];
            MT[1] = m->m * rho[0];
            MT[2] = m->izz;
            model_patch_of_gen(m, cs, MT, gM);
            for (int c = 0; c < 3; c++) cols[0][c] = gM[c] / m->e[c];
            nfree = 1;
        } else {
            double th = rot ? th0 : m->th0;
            cs[0] = cos(th);
            cs[1] = sin(th);
        }
        for (int k = 0; k < 8 && ok; k++) {
            double bk[3] = {(k & 1 ? b[0].hi : b[0].lo), (k & 2 ? b[1].hi : b[1].lo), (k & 4 ? b[2].hi : b[2].lo)};
            cert_eval ce;
            memset(&ce, 0, sizeof ce);
            int st = cert_decide(m, tm, bk, key ? vf : NULL, cs, (const double(*)[3])cols, nfree, nfree, &ce);
            if (st) return st;
            if (key == 0) ok = ce.gauge * ce.cap <= Cs;
            else ok = ce.gauge * ce.cap <= CERT_SLIP_TOL * (m->scale.F + C) && !(ce.excess > 0.0);
        }
        pr[key] = (unsigned char)ok;
        if (key == 0 && ok && expl) {
            /* |Q| over the block for the rest band: Q = -P . T (the pin's
             * centripetal force has no moment about the pivot) over every
             * rate of the block's samples (Q depends on it here) */
            ex_iv bq[3], Vq = {vlo, vhi}, g;
            double S;
            iv_load(m, &fb, TH, Vq, bq, &S, &g);
            if (ex_iv_ok(g)) {
                double e = CERT_ROUND * S;
                g.lo -= e;
                g.hi += e;
                qr[0] = g.lo > 0.0 ? g.lo : (g.hi < 0.0 ? -g.hi : 0.0);
                qr[1] = fmax(fabs(g.lo), fabs(g.hi));
            }
        }
    }
    return EXDEX_OK;
}

/* Is the sample (h, t, v) surely at rest for at_rest (the methods whose rest
 * is a band), given |Q| in [qr[0], qr[1]]? Its tests are monotone in |Q|:
 * |Q| < C, and |v| within a band that widens with |Q|, taken at qr[0]. */
static int rest_band_sure(const exdex_model *m, double h, double t, double v, const double qr[2])
{
    int rot = m->def.dof == EXDEX_DOF_ROTATION;
    double C = model_capacity(m, t) * (rot ? m->e[2] : 1.0), M = rot ? m->mrot : m->m, g;
    if (fabs(v) <= m->tol.vzero) return 1;
    if (!(qr[1] * (1.0 + CERT_ROUND) < C)) return 0;
    if (m->def.method == EXDEX_METHOD_EXPLICIT) return fabs(v) <= h * (qr[0] + C) / M * (1.0 - CERT_ROUND);
    if (m->def.method != EXDEX_METHOD_REGULARISED) return 0;
    g = qr[0] / C;
    return fabs(v) * (rot ? m->e[2] : 1.0) <= m->def.eps * (1.0 + 2.0 * g / sqrt(1.0 - g * g)) * (1.0 - CERT_ROUND);
}

/* First index e in [i, n) with t[e] + snap(t[e]) >= hi (n if none). */
static size_t piece_end(const exdex_model *m, const double *t, size_t i, size_t n, double hi)
{
    size_t a = i, b = n;
    if (!(hi < INFINITY)) return n;
    while (a < b) {
        size_t mid = a + (b - a) / 2;
        if (t[mid] + model_substep_snap(m, t[mid]) >= hi) b = mid;
        else a = mid + 1;
    }
    return a;
}

/* -------------------------------------------------------- a sample's check */

typedef struct scan {
    const exdex_model *m;
    const exdex_trajectory *out;
    size_t sw;
    int pc;                /* constant loads: one evaluation per piece and mode */
    double pt_lo, pt_hi;
    cert_eval pk[3];
    int pk_have[3];
    frame_box_cache *fc;   /* the turning frame's boxes (NULL: computed directly) */
} scan;

/* A slip the samples do not show: the reduced coordinate moved over
 * (t_{i-1}, t_i] while both samples are stuck (an adaptive run's slip, or
 * a sub-step's, that starts and ends inside one output interval): the sign
 * of the move, else 0. The methods with exact stick only: the band of rest
 * of regularised and explicit runs lets a held coordinate creep. */
static int hidden_slip(const exdex_model *m, const exdex_trajectory *out, size_t i)
{
    double dq;
    if (i == 0 || !out->stick[i] || !out->stick[i - 1]) return 0;
    if (m->def.method == EXDEX_METHOD_REGULARISED || m->def.method == EXDEX_METHOD_EXPLICIT) return 0;
    dq = out->q[i] - out->q[i - 1];
    return dq > 0.0 ? 1 : dq < 0.0 ? -1 : 0;
}

/* A stuck state q held over [a, b] (its verdict holds at a and at b):
 * proven over [a, b] by the block proof's enclosure, or else halved (up to
 * depth more times) with its middle evaluated; *ta >= 0 the last time known
 * to hold and *bad the failing verdict where a middle fails (located from
 * the part's start by Brent), *ta < 0 where none is found. */
static int stuck_between(const scan *sc, double a, double b, double q, int depth, cert_eval *bad, double *ta)
{
    const exdex_model *m = sc->m;
    double tt[2] = {a, b}, qq[2] = {q, q}, vv[2] = {0.0, 0.0}, qr[2], mid;
    unsigned char ss[2] = {1, 1}, pr[3];
    int need[3] = {1, 0, 0}, st;
    exdex_trajectory blk;
    memset(&blk, 0, sizeof blk);
    blk.n = 2;
    blk.t = tt;
    blk.q = qq;
    blk.v = vv;
    blk.stick = ss;
    *ta = -1.0;
    st = prove_block(m, &blk, 1, 2, need, pr, qr, sc->fc);
    if (st || pr[0] || depth == 0) return st;
    mid = a + 0.5 * (b - a);
    if (!(mid > a && mid < b)) return EXDEX_OK;
    st = cert_at(m, mid, q, 0.0, 1, bad);
    if (st) return st;
    if (bad->excess > 0.0) {
        *ta = locate(m, a, mid, q, 0.0, 1);
        return EXDEX_OK;
    }
    st = stuck_between(sc, a, mid, q, depth - 1, bad, ta);
    if (st || *ta >= 0.0) return st;
    return stuck_between(sc, mid, b, q, depth - 1, bad, ta);
}

/* Sample i >= 1 (the interval (t_{i-1}, t_i]): *failed = 1 and c filled
 * where it fails. */
static int check_sample(scan *sc, size_t i, exdex_certificate *c, int *failed)
{
    const exdex_model *m = sc->m;
    const exdex_trajectory *out = sc->out;
    double t0 = out->t[i - 1], t1 = out->t[i], q1 = out->q[i], v1 = out->v[i], te;
    int s1 = out->stick[i] || at_rest(m, t1 - t0, t1, q1, v1);
    int key = key_of(s1, v1), st;
    int expl = m->def.method == EXDEX_METHOD_REGULARISED || m->def.method == EXDEX_METHOD_EXPLICIT;
    cert_eval ce;
    *failed = 0;
    if (hidden_slip(m, out, i)) {
        /* the slip is checked at both ends of the interval with the
         * interval's mean rate (its direction); where either fails, the
         * reduction is known to hold up to t0 only */
        double vm = (q1 - out->q[i - 1]) / (t1 - t0);
        cert_eval ca, cb;
        st = cert_at(m, t0, out->q[i - 1], vm, 0, &ca);
        if (st) return st;
        st = cert_at(m, t1, q1, vm, 0, &cb);
        if (st) return st;
        if (ca.excess > 0.0 || cb.excess > 0.0) {
            fill(m, c, ca.excess > 0.0 ? &ca : &cb, t0, i);
            *failed = 1;
            return EXDEX_OK;
        }
    }
    /* switching times inside (t0, t1): checked with the end state */
    while (sc->sw < m->sw_n && m->sw_t[sc->sw] <= t0) sc->sw++;
    for (size_t k = sc->sw; k < m->sw_n && m->sw_t[k] < t1 - model_substep_snap(m, t1); k++) {
        cert_eval cs;
        st = cert_at(m, m->sw_t[k], q1, v1, s1, &cs);
        if (st) return st;
        if (cs.excess > 0.0) {
            double ta = t0;
            cert_eval c0;
            st = cert_at(m, t0, q1, v1, s1, &c0);
            if (st) return st;
            if (!(c0.excess > 0.0)) ta = locate(m, t0, m->sw_t[k], q1, v1, s1);
            fill(m, c, &cs, ta, i);
            *failed = 1;
            return EXDEX_OK;
        }
    }
    /* the sample closes the interval (t0, t1]: a switching time on t1
     * (to rounding) belongs to the next one, so the load is its left
     * limit there */
    te = t1;
    if (sc->sw < m->sw_n) {
        size_t k = sc->sw;
        while (k < m->sw_n && m->sw_t[k] < t1 - model_substep_snap(m, t1)) k++;
        if (k < m->sw_n && m->sw_t[k] <= t1 + model_substep_snap(m, t1)) te = m->sw_t[k] - CERT_PIECE_INSIDE * (t1 - t0);
    }
    if (sc->pc && sc->pk_have[key] && te >= sc->pt_lo && te < sc->pt_hi) {
        ce = sc->pk[key];
    } else {
        st = cert_at(m, te, q1, v1, s1, &ce);
        if (st) return st;
        if (sc->pc) {
            /* the piece holding te: [pt_lo, pt_hi) between switching times */
            size_t k = sc->sw;
            double lo, hi;
            while (k < m->sw_n && m->sw_t[k] <= te) k++;
            lo = k ? m->sw_t[k - 1] : -INFINITY;
            hi = k < m->sw_n ? m->sw_t[k] : INFINITY;
            if (lo != sc->pt_lo || hi != sc->pt_hi) sc->pk_have[0] = sc->pk_have[1] = sc->pk_have[2] = 0;
            sc->pt_lo = lo;
            sc->pt_hi = hi;
            sc->pk[key] = ce;
            sc->pk_have[key] = 1;
        }
    }
    if (ce.excess > 0.0) {
        /* locate it in (t0, t1] */
        double ta = t0;
        int s0 = out->stick[i - 1] || at_rest(m, i > 1 ? t0 - out->t[i - 2] : t1 - t0, t0, out->q[i - 1], out->v[i - 1]);
        cert_eval c0;
        if (s1) {
            st = cert_at(m, t0, q1, 0.0, 1, &c0);
            if (st) return st;
            if (!(c0.excess > 0.0)) ta = locate(m, t0, t1, q1, 0.0, 1);
        } else if (s0) {
            /* a slip from stick: the stick state fails first where its load leaves the surface */
            double q0 = out->q[i - 1];
            cert_eval c1;
            st = cert_at(m, t1, q0, 0.0, 1, &c1);
            if (st) return st;
            if (c1.excess > 0.0) ta = locate(m, t0, t1, q0, 0.0, 1);
        } else {
            st = cert_at(m, t0, q1, v1, 0, &c0);
            if (st) return st;
            if (!(c0.excess > 0.0)) ta = locate(m, t0, t1, q1, v1, 0);
        }
        fill(m, c, &ce, ta, i);
        *failed = 1;
        return EXDEX_OK;
    }
    /* a stuck interval (the coordinate did not move: the state is exact
     * between the samples; for the methods whose rest is a band, both
     * samples at rest, the state held at the end's) with no switching time
     * inside and a load that reads the time: its excursions between the
     * samples; not where stops carry the load (the enclosure has no stop
     * force) */
    if (!sc->pc && s1 && te == t1 && (sc->sw >= m->sw_n || m->sw_t[sc->sw] >= t1 - model_substep_snap(m, t1)) &&
        (expl ? out->stick[i - 1] || at_rest(m, i > 1 ? t0 - out->t[i - 2] : t1 - t0, t0, out->q[i - 1], out->v[i - 1])
              : out->stick[i] && out->stick[i - 1] && out->q[i - 1] == q1)) {
        double ta;
        cert_eval bad;
        if (m->n_src) {
            cert_eval cf;
            st = cert_at_stops(m, t1, q1, 0.0, 1, 0, &cf);
            if (st) return st;
            if (cf.excess > 0.0) return EXDEX_OK;
        }
        st = stuck_between(sc, t0, t1, q1, CERT_BETWEEN_DEPTH, &bad, &ta);
        if (st) return st;
        if (ta >= 0.0) {
            fill(m, c, &bad, ta, i);
            *failed = 1;
        }
    }
    return EXDEX_OK;
}

/* Is the load piecewise constant in time (changing only at switching
 * times) and independent of the state? A translation run with no stop or
 * obstacle, a constant grip force and a gripper that only translates with a
 * piecewise-constant acceleration (rest, Eq. 7, a trapezoid). */
static int piecewise_constant(const exdex_model *m)
{
    int turns;
    if (m->def.dof != EXDEX_DOF_TRANSLATION || m->n_src || m->grip_n) return 0;
    return proof_motion(m, &turns) && !turns;
}

/* The certificate of out's samples from index skip on (skip = 0: the whole
 * run, sample 0 included; skip >= 2: a window of a run whose first skip
 * samples are known to hold, the two before the first one checked giving
 * its interval and the band of rest before it); first_bad counts from
 * out's sample 0. */
static int certify_with(const exdex_model *m, const exdex_trajectory *out, exdex_certificate *c, int proofs,
                        frame_box_cache *fc, size_t skip, const pieces *given)
{
    size_t n, i;
    int st, failed, expl;
    cert_eval cp;
    pieces pv;
    scan sc;
    if (!m || !out || !c || !out->t || !out->q || !out->v || !out->stick || out->n == 0) return EXDEX_EINVAL;
    memset(c, 0, sizeof *c);
    n = out->n;
    c->valid_until = out->t[n - 1];
    c->first_bad = n;
    c->holds = 1;
    c->coordinate = -1;
    if (m->ndof != 1) return EXDEX_OK;
    c->reduced = 1;
    memset(&sc, 0, sizeof sc);
    sc.m = m;
    sc.out = out;
    sc.pc = piecewise_constant(m);
    sc.pt_lo = sc.pt_hi = -INFINITY;
    sc.fc = fc;
    pv.n = pv.qknown = 0;
    if (given) {
        pv = *given;
    } else if (proofs) {
        st = prove_pieces(m, out, &pv);
        if (st) return st;
    }
    /* the methods whose rest is a band around v = 0 (at_rest) */
    expl = m->def.method == EXDEX_METHOD_REGULARISED || m->def.method == EXDEX_METHOD_EXPLICIT;
    /* sample 0; at rest there but slipping right after, it is the start of
     * that slip, which sample 1 checks (a slip from rest) */
    if (skip == 0 &&
        !(n > 1 && out->v[0] == 0.0 && !(out->stick[1] || at_rest(m, out->t[1] - out->t[0], out->t[1], out->q[1], out->v[1])))) {
        int k0 = 0, proven = 0;
        while (k0 + 1 < pv.n && out->t[0] >= pv.lo[k0 + 1]) k0++;
        if (pv.n && out->t[0] >= pv.lo[k0] && out->t[0] < pv.hi[k0])
            proven = pv.proven[k0][key_of(out->stick[0] || out->v[0] == 0.0, out->v[0])];
        if (!proven) {
            st = cert_at(m, out->t[0], out->q[0], out->v[0], out->stick[0], &cp);
            if (st) return st;
            if (cp.excess > 0.0) {
                fill(m, c, &cp, out->t[0], 0);
                return EXDEX_OK;
            }
        }
    }
    i = skip > 1 ? skip : 1;
    {
        int k = 0;
        /* block proofs (prove_block) where no piece proof applies: bs the
         * block's size in samples (the rest of the piece at first, doubled
         * after a proof, halved after a failed one down to CERT_BLOCK_MIN),
         * chk the samples to evaluate one by one before the next try */
        int blk = proofs && !pv.n && (m->def.dof == EXDEX_DOF_TRANSLATION || m->def.dof == EXDEX_DOF_ROTATION);
        size_t bs = 0, chk = 0, swk = 0, edge = 0;   /* edge: the sample the last block failed at first */
        int again;
        while (i < n) {
            if (blk && !chk) {
                double hi;
                while (swk < m->sw_n && m->sw_t[swk] <= out->t[i - 1]) swk++;
                hi = swk < m->sw_n ? m->sw_t[swk] : INFINITY;
                if (out->t[i] + model_substep_snap(m, out->t[i]) < hi) {
                    size_t e = piece_end(m, out->t, i, n, hi), e2;
                    int need[3] = {expl, 0, 0};
                    unsigned char pr[3];
                    double qr[2];
                    if (bs == 0 || bs > e - i) bs = e - i;
                    e2 = i + bs;
                    for (size_t j = i; j < e2; j++) {
                        double v = out->v[j];
                        if (!(out->stick[j] || fabs(v) <= m->tol.vzero)) need[key_of(0, v)] = 1;
                        else need[0] = 1;
                    }
                    size_t i_start = i;
                    st = prove_block(m, out, i, e2, need, pr, qr, fc);
                    if (st) return st;
                    for (; i < e2; i++) {
                        double v = out->v[i];
                        int rest = out->stick[i] || fabs(v) <= m->tol.vzero;
                        /* a slip the samples do not show: its states are not in the block's enclosure */
                        if (hidden_slip(m, out, i)) break;
                        /* the methods whose rest is a band (at_rest): a sample off v = 0 proven in both modes,
                         * or (a rotation) stuck where it is surely within the band */
                        if (rest ? pr[0] : !expl ? pr[key_of(0, v)]
                                         : pr[0] && (pr[key_of(0, v)] ||
                                                     (m->def.dof == EXDEX_DOF_ROTATION &&
                                                      rest_band_sure(m, out->t[i] - out->t[i - 1], out->t[i], v, qr))))
                            continue;
                        break;
                    }
                    again = i == i_start && i == edge;
                    edge = i == i_start ? i : 0;
                    if (i == e2) {
                        bs *= 2;
                        continue;
                    }
                    if (again && expl && pr[0] && !(out->stick[i] || fabs(out->v[i]) <= m->tol.vzero) &&
                        !pr[key_of(0, out->v[i])]) {
                        /* failed at its first sample, as the block before it did (again), a moving
                         * sample the block proves stuck but not surely within the band of rest (at
                         * its edge: only a much smaller block settles it): the size cut by 8, not
                         * halved; at CERT_BLOCK_MIN, that many samples evaluated one by one */
                        if (bs > CERT_BLOCK_MIN) {
                            bs = bs / 8 > CERT_BLOCK_MIN ? bs / 8 : CERT_BLOCK_MIN;
                            continue;
                        }
                        chk = CERT_BLOCK_MIN;
                    } else if (bs > CERT_BLOCK_MIN) {
                        bs /= 2;
                        continue;
                    } else {
                        chk = CERT_BLOCK_MIN;
                    }
                }
            }
            if (chk) chk--;
            if (pv.n) {
                /* samples strictly inside a piece (no switching time in (t_{i-1}, t_i + snap]) whose mode
                 * is proven there need no evaluation */
                while (k + 1 < pv.n && out->t[i - 1] >= pv.lo[k + 1]) k++;
                if (out->t[i - 1] >= pv.lo[k] && out->t[i] + model_substep_snap(m, out->t[i]) < pv.hi[k]) {
                    size_t e = piece_end(m, out->t, i, n, pv.hi[k]);
                    const unsigned char *pr = pv.proven[k];
                    /* a slip the samples do not show is covered where the load reads no state (sc.pc:
                     * its proof holds at any rate), else evaluated */
                    if (pr[0] && pr[1] && pr[2]) {
                        if (sc.pc) i = e;
                        else
                            while (i < e && !hidden_slip(m, out, i)) i++;
                    } else if (!expl) {
                        for (; i < e; i++) {
                            double v = out->v[i];
                            int rest = out->stick[i] || fabs(v) <= m->tol.vzero, h = hidden_slip(m, out, i);
                            if (!pr[key_of(rest, v)] || (h && !(sc.pc && pr[key_of(0, h)]))) break;
                        }
                    } else if (pv.qknown) {
                        double Q = pv.Q[k];
                        for (; i < e; i++) {
                            double v = out->v[i];
                            int rest = out->stick[i] || at_rest_q(m, out->t[i] - out->t[i - 1], out->t[i], out->q[i], v, &Q);
                            if (!pr[key_of(rest, v)]) break;
                        }
                    } else {
                        /* the band of rest is not known: both modes proven */
                        for (; i < e; i++) {
                            double v = out->v[i];
                            if (!(out->stick[i] || fabs(v) <= m->tol.vzero ? pr[0] : pr[0] && pr[key_of(0, v)]))
                                break;
                        }
                    }
                    if (i == e) continue;
                }
            }
            st = check_sample(&sc, i, c, &failed);
            if (st) return st;
            if (failed) return EXDEX_OK;
            i++;
        }
    }
    return EXDEX_OK;
}

/* certify_with through a cache of the turning frame's boxes, owned by the call */
static int certify(const exdex_model *m, const exdex_trajectory *out, exdex_certificate *c, int proofs)
{
    frame_box_cache *fc = proofs && m ? motion_frame_cache_new(m->g) : NULL;
    int st = certify_with(m, out, c, proofs, fc, 0, NULL);
    motion_frame_cache_free(fc);
    return st;
}

int exdex_certify(const exdex_model *m, const exdex_trajectory *out, exdex_certificate *c)
{
    return certify(m, out, c, 1);
}

int exdex_certify_samples(const exdex_model *m, const exdex_trajectory *out, exdex_certificate *c)
{
    return certify(m, out, c, 0);
}

int exdex_certify_last(const exdex_model *m, const exdex_trajectory *out, size_t n_before, exdex_certificate *c)
{
    size_t n, i, g;
    int st, failed;
    scan sc;
    if (!m || !out || !c || !out->t || !out->q || !out->v || !out->stick || out->n == 0 || out->n > 3)
        return EXDEX_EINVAL;
    n = out->n;
    i = n - 1;
    g = n_before + i;
    if (g >= 2 && n < 3) return EXDEX_EINVAL;
    if (g == 1 && n != 2) return EXDEX_EINVAL;
    memset(c, 0, sizeof *c);
    c->valid_until = out->t[i];
    c->first_bad = g + 1;
    c->holds = 1;
    c->coordinate = -1;
    if (m->ndof != 1) return EXDEX_OK;
    c->reduced = 1;
    if (g == 0) return EXDEX_OK;   /* the initial sample: decided with the next one (certify) */
    memset(&sc, 0, sizeof sc);
    sc.m = m;
    sc.out = out;
    sc.pt_lo = sc.pt_hi = -INFINITY;
    if (g == 1 && !(out->v[0] == 0.0 && !(out->stick[1] || at_rest(m, out->t[1] - out->t[0], out->t[1], out->q[1], out->v[1])))) {
        cert_eval cp;
        st = cert_at(m, out->t[0], out->q[0], out->v[0], out->stick[0], &cp);
        if (st) return st;
        if (cp.excess > 0.0) {
            fill(m, c, &cp, out->t[0], 0);
            return EXDEX_OK;
        }
    }
    st = check_sample(&sc, i, c, &failed);
    if (st) return st;
    if (failed) c->first_bad = g;
    else {
        c->holds = 1;
        c->valid_until = out->t[i];
        c->first_bad = g + 1;
    }
    return EXDEX_OK;
}

struct certify_run {
    frame_box_cache *fc;
    double t_end;
    int shared;    /* 1: the piece proofs read no state of the run (a translation in a gripper
                      that does not turn, a rotation): made once, over [0, t_end], as the whole
                      run's certificate makes them */
    int have;      /* 1: pv holds them */
    pieces pv;
};

certify_run *certify_run_new(const exdex_model *m, double t_end)
{
    certify_run *r = calloc(1, sizeof *r);
    int turns;
    if (!r) return NULL;
    r->fc = motion_frame_cache_new(m->g);
    if (!r->fc) {
        free(r);
        return NULL;
    }
    r->t_end = t_end;
    r->shared = m->def.dof == EXDEX_DOF_ROTATION ||
                (m->def.dof == EXDEX_DOF_TRANSLATION && (!proof_motion(m, &turns) || !turns));
    return r;
}

void certify_run_free(certify_run *r)
{
    if (!r) return;
    motion_frame_cache_free(r->fc);
    free(r);
}

int certify_window(const exdex_model *m, const exdex_trajectory *out, size_t skip, certify_run *r,
                   exdex_certificate *c)
{
    if (!m || !out || !r || skip == 1 || skip >= out->n) return EXDEX_EINVAL;
    if (r->shared && !r->have && m->ndof == 1) {
        /* the run's first window (skip 0: out starts at the run's sample 0) */
        double t[2] = {out->t[0], r->t_end}, q[2] = {out->q[0], out->q[0]};
        exdex_trajectory span = *out;
        int st;
        if (skip) return EXDEX_EINVAL;
        span.n = 2;
        span.t = t;
        span.q = q;
        st = prove_pieces(m, &span, &r->pv);
        if (st) return st;
        r->have = 1;
    }
    return certify_with(m, out, c, 1, r->fc, skip, r->shared ? &r->pv : NULL);
}
