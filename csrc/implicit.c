/* sim.c -- relative dynamics of the grasped object in the gripper frame B
 * (paper Eqs. 3-5) and the implicit time-stepping loop with the friction
 * ellipsoid (Eq. 6) and external stops.
 *
 * Equations of motion in B (all vectors in B coordinates). With g_B = R^T g,
 * a0 = R^T a (B origin), w = R^T omega, dw = R^T alpha, the centre of mass at
 * r with relative velocity rd feels, besides friction and stops, the force
 *     F_lin = m (g_B - a0 - dw x r - w x (w x r) - 2 w x rd)           (Eq. 5)
 * (gravity, linear, Euler, centrifugal and Coriolis terms of the moving
 * frame). The object turns about z relative to B at rate thd, so its absolute
 * angular velocity is W = w + thd e_z and Euler's equation, z-component (the
 * plates carry the x and y torques), gives
 *     I_zz thdd = tau_z - [I_B (dw + thd w x e_z)]_z - [W x I_B W]_z
 * with I_B = Rz(theta) I Rz(theta)^T.
 *
 * The reduced coordinates (exdex_dof) turn these into M qdd = Q(t, q, qd)
 * + friction + stops with a 1x1 or 3x3 M.
 *
 * Time stepping (Moreau's midpoint scheme, velocity level):
 *     q_m = q + h/2 v,   forces at (t + h/2, q_m, v),   v* = v + h M^-1 Q,
 *     v+ = v* + M^-1 (J_f^T p + G^T lambda),   q+ = q_m + h/2 v+,
 * with the friction impulse p from the maximum-dissipation problem (Eq. 6)
 * and stop impulses lambda >= 0 keeping every stop gap >= 0 at t + h.
 * Stick is exact: when the friction impulse can hold the object, v+ = 0.
 */
#include "exdex.h"
#include "sim_internal.h"
#include "util.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#define MAX_ROWS (EXDEX_MAX_STOPS * EXDEX_MAX_VERTICES)
#define TOUCH 1e-10   /* a stop gap below this counts as contact [m] */

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
} work;

/* ------------------------------------------------------------ definition */

exdex_scene_def exdex_default_scene_def(void)
{
    exdex_scene_def d;
    memset(&d, 0, sizeof d);
    d.mass = 1.0;
    d.inertia[0] = d.inertia[4] = d.inertia[8] = 1.0;
    d.mu = 0.5;
    d.grip_force = 1.0;
    d.fingers = 2;
    d.e_r = 0.01;
    d.gravity[2] = -9.81;
    d.dof = EXDEX_DOF_TRANSLATION;
    d.slide_axis[1] = 1.0;
    /* B x = A x, B y = A z (up), B z = -A y: columns of R_AB are B's axes. */
    d.R0[0] = 1.0;
    d.R0[5] = -1.0;
    d.R0[7] = 1.0;
    d.motion.kind = EXDEX_MOTION_REST;
    d.motion.axis[2] = 1.0;
    d.motion.duration = 1.0;
    d.motion.beta = 0.5;
    d.motion.v_max = 1.0;
    d.method = EXDEX_METHOD_IMPLICIT;
    d.friction_solver = EXDEX_SOLVER_SCALAR;
    d.eps = 1e-4;
    d.rtol = 1e-8;
    d.atol = 1e-10;
    return d;
}

static int bad(const char **bad_param, const char *name)
{
    if (bad_param) *bad_param = name;
    return EXDEX_EINVAL;
}

/* Cholesky test of a symmetric 3x3 matrix. */
static int spd3(const double A[9])
{
    double l00, l10, l20, l11, l21, d2;
    if (!(A[0] > 0)) return 0;
    l00 = sqrt(A[0]);
    l10 = A[3] / l00;
    l20 = A[6] / l00;
    d2 = A[4] - l10 * l10;
    if (!(d2 > 0)) return 0;
    l11 = sqrt(d2);
    l21 = (A[7] - l20 * l10) / l11;
    d2 = A[8] - l20 * l20 - l21 * l21;
    return d2 > 0;
}

/* Field-by-field validation of everything but R0, the motion, the planar
 * friction problem and the initial stop gaps (those need the model built). */
static int check_fields(const exdex_scene_def *d, const char **bad_param)
{
    double scale;
    if (!d) return bad(bad_param, "scene");
    if (!(isfinite(d->mass) && d->mass > 0)) return bad(bad_param, "mass");
    if (!ex_finite_n(d->inertia, 9)) return bad(bad_param, "inertia");
    scale = fabs(d->inertia[0]) + fabs(d->inertia[4]) + fabs(d->inertia[8]);
    if (fabs(d->inertia[1] - d->inertia[3]) > 1e-9 * scale ||
        fabs(d->inertia[2] - d->inertia[6]) > 1e-9 * scale ||
        fabs(d->inertia[5] - d->inertia[7]) > 1e-9 * scale || !spd3(d->inertia))
        return bad(bad_param, "inertia");
    if (d->n_vertices < 0 || d->n_vertices > EXDEX_MAX_VERTICES)
        return bad(bad_param, "n_vertices");
    if (!ex_finite_n(&d->vertices[0][0], 2 * d->n_vertices)) return bad(bad_param, "vertices");
    if (!(isfinite(d->mu) && d->mu >= 0)) return bad(bad_param, "mu");
    if (!(isfinite(d->grip_force) && d->grip_force >= 0)) return bad(bad_param, "grip_force");
    if (d->fingers != 1 && d->fingers != 2) return bad(bad_param, "fingers");
    if (!(isfinite(d->e_r) && d->e_r > 0)) return bad(bad_param, "e_r");
    if (!ex_finite_n(d->patch_center, 2)) return bad(bad_param, "patch_center");
    if (!ex_finite_n(d->gravity, 3)) return bad(bad_param, "gravity");
    if (d->dof < EXDEX_DOF_TRANSLATION || d->dof > EXDEX_DOF_PLANAR) return bad(bad_param, "dof");
    if (!ex_finite_n(d->slide_axis, 2) ||
        fabs(hypot(d->slide_axis[0], d->slide_axis[1]) - 1.0) > 1e-9)
        return bad(bad_param, "slide_axis");
    if (!ex_finite_n(d->q0, 3)) return bad(bad_param, "q0");
    if (!ex_finite_n(d->v0, 3)) return bad(bad_param, "v0");
    if (!ex_finite_n(d->p0, 3)) return bad(bad_param, "p0");
    if (d->n_stops < 0 || d->n_stops > EXDEX_MAX_STOPS) return bad(bad_param, "n_stops");
    for (int k = 0; k < d->n_stops; k++) {
        if (!ex_finite_n(d->stop_point[k], 3)) return bad(bad_param, "stop_point");
        if (!ex_finite_n(d->stop_normal[k], 3) ||
            fabs(sqrt(ex_dot3(d->stop_normal[k], d->stop_normal[k])) - 1.0) > 1e-9)
            return bad(bad_param, "stop_normal");
    }
    if (d->method < EXDEX_METHOD_IMPLICIT || d->method > EXDEX_METHOD_EXPLICIT) return bad(bad_param, "method");
    if (d->friction_solver < EXDEX_SOLVER_SCALAR || d->friction_solver > EXDEX_SOLVER_MULTIROOT)
        return bad(bad_param, "friction_solver");
    if (!(isfinite(d->eps) && d->eps > 0)) return bad(bad_param, "eps");
    if (!(isfinite(d->rtol) && d->rtol > 0)) return bad(bad_param, "rtol");
    if (!(isfinite(d->atol) && d->atol > 0)) return bad(bad_param, "atol");
    return EXDEX_OK;
}

/* ------------------------------------------------------------ kinematics */

/* Centre of mass position in B (z = 0) and orientation for coordinates q. */
void sim_com_pose(const exdex_model *m, const double *q, double r[3], double *th)
{
    r[2] = 0.0;
    switch (m->ndof == 3 ? EXDEX_DOF_PLANAR : m->def.dof) {
    case EXDEX_DOF_TRANSLATION:
        r[0] = m->r0[0] + (q[0] - m->s0) * m->d[0];
        r[1] = m->r0[1] + (q[0] - m->s0) * m->d[1];
        *th = m->th0;
        break;
    case EXDEX_DOF_ROTATION: {
        double rho[2];
        rot2(rho, q[0], m->c);
        r[0] = m->pivot[0] + rho[0];
        r[1] = m->pivot[1] + rho[1];
        *th = q[0];
        break;
    }
    default:
        r[0] = q[0];
        r[1] = q[1];
        *th = q[2];
    }
}

int sim_frame_at(const exdex_model *m, double t, frame *f, exdex_kinematics *k)
{
    int st = exdex_motion_eval(m->motion, t, k);
    if (st) return st;
    ex_mulmtv3(f->gB, k->R, m->g);
    ex_mulmtv3(f->a0, k->R, k->a);
    ex_mulmtv3(f->w, k->R, k->w);
    ex_mulmtv3(f->dw, k->R, k->dw);
    return EXDEX_OK;
}

int sim_frame_step(const exdex_model *m, const exdex_kinematics *kin0, double t_eval, double t1, double h,
                   frame *f, exdex_kinematics *kin, exdex_kinematics *kin_end)
{
    double dv[3], dwv[3];
    int status = sim_frame_at(m, t_eval, f, kin);
    if (status) return status;
    status = exdex_motion_eval(m->motion, t1, kin_end);
    if (status) return status;
    for (int i = 0; i < 3; i++) {
        dv[i] = (kin_end->v[i] - kin0->v[i]) / h;
        dwv[i] = (kin_end->w[i] - kin0->w[i]) / h;
    }
    ex_mulmtv3(f->a0, kin->R, dv);
    ex_mulmtv3(f->dw, kin->R, dwv);
    return EXDEX_OK;
}

/* Inertial + gravity force on the centre of mass (Eq. 5), B coordinates. */
void sim_force_lin(const exdex_model *m, const frame *f, const double r[3],
                      const double rd[3], double F[3])
{
    double t1[3], t2[3], t3[3];
    ex_cross3(t1, f->dw, r);          /* Euler */
    ex_cross3(t2, f->w, r);
    ex_cross3(t3, f->w, t2);          /* centrifugal */
    ex_cross3(t2, f->w, rd);          /* Coriolis / 2 */
    for (int i = 0; i < 3; i++)
        F[i] = m->m * (f->gB[i] - f->a0[i] - t1[i] - t3[i] - 2.0 * t2[i]);
}

/* Inertial torque about z on the body turning at thd relative to B at angle th. */
double sim_torque_z(const exdex_model *m, const frame *f, double th, double thd)
{
    double IB[9], Rz[9], T[9], v[3], Iv[3], W[3], IW[3], wxe[3];
    const double ez[3] = {0.0, 0.0, 1.0};
    double c = cos(th), s = sin(th);
    /* Only the z-row of I_B is needed, plus I_B W for the gyroscopic term. */
    Rz[0] = c; Rz[1] = -s; Rz[2] = 0; Rz[3] = s; Rz[4] = c; Rz[5] = 0; Rz[6] = 0; Rz[7] = 0; Rz[8] = 1;
    ex_mulmm3(T, Rz, m->I);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            IB[3 * i + j] = T[3 * i] * Rz[3 * j] + T[3 * i + 1] * Rz[3 * j + 1] + T[3 * i + 2] * Rz[3 * j + 2];
    ex_cross3(wxe, f->w, ez);
    for (int i = 0; i < 3; i++) v[i] = f->dw[i] + thd * wxe[i];
    ex_mulmv3(Iv, IB, v);
    W[0] = f->w[0];
    W[1] = f->w[1];
    W[2] = f->w[2] + thd;
    ex_mulmv3(IW, IB, W);
    return -Iv[2] - (W[0] * IW[1] - W[1] * IW[0]);
}

/* ------------------------------------------------------------ model */

static void stop_rows_clear(work *w) { w->n_rows = 0; }

/* Gap of vertex j against stop k for coordinates q, gripper pose k, and the
 * row G (d gap / d qdot). */
/* Outline vertices in B at coordinates q: xb[j] (position) and vx[j] (offset
 * from the centre of mass), one cos/sin for all of them. Returns the count. */
static int body_vertices(const exdex_model *m, const double *q, double xb[][3], double vx[][3])
{
    double r[3], th, c, s;
    int nv = m->n_vert ? m->n_vert : 1;
    sim_com_pose(m, q, r, &th);
    c = cos(th);
    s = sin(th);
    for (int j = 0; j < nv; j++) {
        double px = m->n_vert ? m->vert[j][0] : 0.0, py = m->n_vert ? m->vert[j][1] : 0.0;
        vx[j][0] = c * px - s * py;
        vx[j][1] = s * px + c * py;
        vx[j][2] = 0.0;
        xb[j][0] = r[0] + vx[j][0];
        xb[j][1] = r[1] + vx[j][1];
        xb[j][2] = 0.0;
    }
    return nv;
}

/* Gap of the vertex at xb (offset vx from the centre of mass) against stop k
 * for the gripper pose kin; G (may be NULL) gets d gap / d qdot. */
static double gap_at(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3],
                     const double vx[3], double G[3])
{
    double xa[3], nB[3];
    ex_mulmv3(xa, kin->R, xb);
    for (int i = 0; i < 3; i++) xa[i] += kin->p[i] - m->sp[k][i];
    if (G) {
        ex_mulmtv3(nB, kin->R, m->sn[k]);
        if (m->ndof == 3) {
            /* columns: d xb / dx, dy, dtheta = e_z x vx */
            G[0] = nB[0];
            G[1] = nB[1];
            G[2] = -nB[0] * vx[1] + nB[1] * vx[0];
        } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
            G[0] = nB[0] * m->d[0] + nB[1] * m->d[1];
        } else {
            /* rotation about the pivot: d xb / dtheta = e_z x (xb - pivot) */
            double ax = xb[0] - m->pivot[0], ay = xb[1] - m->pivot[1];
            G[0] = -nB[0] * ay + nB[1] * ax;
        }
    }
    return ex_dot3(xa, m->sn[k]);
}

double sim_vertex_gap(const exdex_model *m, const exdex_kinematics *kin, int k,
                         const double *q, int j, double G[3])
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
    body_vertices(m, q, xb, vx);
    return gap_at(m, kin, k, xb[j], vx[j], G);
}

void exdex_model_free(exdex_model *m)
{
    if (!m) return;
    exdex_motion_free(m->motion);
    free(m);
}

static exdex_model *build_model(const exdex_scene_def *def, int *status, const char **bad_param)
{
    exdex_model *m;
    int st = check_fields(def, bad_param);
    int dummy;
    if (!status) status = &dummy;
    if (st) {
        *status = st;
        return NULL;
    }
    m = calloc(1, sizeof *m);
    if (!m) {
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    m->def = *def;
    m->def.motion.times = NULL;
    m->def.motion.poses = NULL;
    m->motion = exdex_motion_alloc(&def->motion, def->R0, def->p0, status, bad_param);
    if (!m->motion) {
        free(m);
        return NULL;
    }
    m->ndof = def->dof == EXDEX_DOF_PLANAR ? 3 : 1;
    m->m = def->mass;
    memcpy(m->I, def->inertia, sizeof m->I);
    m->izz = def->inertia[8];
    m->capF = def->mu * def->fingers * def->grip_force;
    m->e[0] = m->e[1] = 1.0;
    m->e[2] = def->e_r;
    m->pc[0] = def->patch_center[0];
    m->pc[1] = def->patch_center[1];
    memcpy(m->g, def->gravity, sizeof m->g);
    m->d[0] = def->slide_axis[0];
    m->d[1] = def->slide_axis[1];
    m->r0[0] = def->q0[0];
    m->r0[1] = def->q0[1];
    m->th0 = def->q0[2];
    m->s0 = m->d[0] * m->r0[0] + m->d[1] * m->r0[1];
    /* rotation: pivot at the centre of pressure, fixed in B */
    {
        double pcB[2];
        rot2(pcB, m->th0, m->pc);
        m->pivot[0] = m->r0[0] + pcB[0];
        m->pivot[1] = m->r0[1] + pcB[1];
        m->c[0] = -m->pc[0];
        m->c[1] = -m->pc[1];
        m->mrot = m->izz + m->m * (m->c[0] * m->c[0] + m->c[1] * m->c[1]);
    }
    /* planar: W = J' M'^-1 J'^T in object-frame patch coordinates, with the
     * patch slip u = (vx' - pc_y thd, vy' + pc_x thd, thd). */
    m->minv[0] = m->minv[1] = 1.0 / m->m;
    m->minv[2] = 1.0 / m->izz;
    if (m->ndof == 3) {
        double J[9] = {1, 0, -m->pc[1], 0, 1, m->pc[0], 0, 0, 1}, W[9];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double s = 0;
                for (int k = 0; k < 3; k++) s += J[3 * i + k] * m->minv[k] * J[3 * j + k];
                W[3 * i + j] = s;
            }
        st = exdex_friction_prepare(&m->prep, W, m->e);
        if (st) {
            exdex_model_free(m);
            *status = st;
            if (bad_param) *bad_param = "inertia";
            return NULL;
        }
    }
    m->n_stops = def->n_stops;
    for (int k = 0; k < def->n_stops; k++) {
        memcpy(m->sp[k], def->stop_point[k], sizeof m->sp[k]);
        memcpy(m->sn[k], def->stop_normal[k], sizeof m->sn[k]);
    }
    m->n_vert = def->n_vertices;
    memcpy(m->vert, def->vertices, sizeof m->vert);
    /* no vertex may start beyond a stop */
    if (m->n_stops) {
        exdex_kinematics kin;
        double q[3];
        int nv = m->n_vert ? m->n_vert : 1;
        if (m->ndof == 3) {
            memcpy(q, def->q0, sizeof q);
        } else {
            q[0] = def->dof == EXDEX_DOF_TRANSLATION ? m->s0 : m->th0;
        }
        st = exdex_motion_eval(m->motion, 0.0, &kin);
        for (int k = 0; !st && k < m->n_stops; k++)
            for (int j = 0; j < nv; j++)
                if (sim_vertex_gap(m, &kin, k, q, j, NULL) < -1e-9) st = EXDEX_EINVAL;
        if (st) {
            exdex_model_free(m);
            *status = st;
            if (bad_param) *bad_param = "q0 (the object starts beyond a stop)";
            return NULL;
        }
    }
    *status = EXDEX_OK;
    return m;
}

exdex_model *exdex_model_alloc(const exdex_scene_def *def, int *status, const char **bad_param)
{
    return build_model(def, status, bad_param);
}

/* Everything model_alloc rejects as bad input is rejected here with the same
 * bad_param, by construction: the fields first, then the model is built (R0
 * and the motion by exdex_motion_alloc, the planar friction problem, the
 * initial stop gaps) and freed again. */
int exdex_scene_check(const exdex_scene_def *d, const char **bad_param)
{
    int st = check_fields(d, bad_param), st_build = EXDEX_OK;
    const char *b = NULL;
    exdex_model *m;
    if (st) return st;
    m = build_model(d, &st_build, &b);
    if (m) {
        exdex_model_free(m);
        return EXDEX_OK;
    }
    /* EINVAL: bad input; ENOMEM passes through; ENONFINITE (the motion
     * overflows at t = 0) is not a bad field: the check passes */
    if (st_build == EXDEX_EINVAL && bad_param) *bad_param = b;
    return st_build == EXDEX_ENONFINITE ? EXDEX_OK : st_build;
}

int exdex_model_ndof(const exdex_model *m) { return m ? m->ndof : 0; }
int exdex_model_nstops(const exdex_model *m) { return m ? m->n_stops : 0; }

size_t exdex_n_samples(double t_end, double dt)
{
    double r;
    double steps;
    if (!(isfinite(t_end) && isfinite(dt) && dt > 0 && t_end > 0 && dt <= t_end)) return 0;
    r = t_end / dt;
    steps = floor(r + 0.5);
    if (fabs(r - steps) > 1e-9 * r) steps = ceil(r);
    if (steps < 1) steps = 1;
    if (steps > EXDEX_MAX_STEPS) return 0;
    return (size_t)steps + 1;
}

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
#define GAP_ROUND (8.0 * DBL_EPSILON)

/* Rounding bound of gap_at for the vertex at xb (B) against stop k at the
 * gripper pose kin: GAP_ROUND times the sum of the magnitudes it adds. */
static double gap_round(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3])
{
    return GAP_ROUND * (sqrt(ex_dot3(xb, xb)) + sqrt(ex_dot3(kin->p, kin->p)) + sqrt(ex_dot3(m->sp[k], m->sp[k])));
}

static void build_rows(const exdex_model *m, const exdex_kinematics *kin_end, const double *q,
                       double h, work *w)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
    int nv = body_vertices(m, q, xb, vx);
    stop_rows_clear(w);
    for (int k = 0; k < m->n_stops; k++)
        for (int j = 0; j < nv; j++) {
            int i = w->n_rows++;
            double tau = gap_round(m, kin_end, k, xb[j]);
            w->row_stop[i] = k;
            w->gap[i] = gap_at(m, kin_end, k, xb[j], vx[j], w->G[i]);
            w->rhs[i] = fabs(w->gap[i]) <= tau ? 0.0 : -w->gap[i] / h;
            w->lam[i] = 0.0;
        }
}

/* 1-DoF step: min 1/2 M (v - vs)^2 + c |v| subject to G_i v >= rhs_i.
 * Exact: soft-threshold, then clamp into the feasible interval. The impulse
 * split is unique while sliding (friction = capacity, the binding stop the
 * rest). At rest (v+ = 0) against a touching stop it is statically
 * indeterminate; exdex lets the stops carry what they can (the split with the
 * least friction), as in the planar case. */
static void step_1dof(double M, double c, double vs, work *w, double *v_out, double *pf,
                      exdex_stats *st)
{
    double vu, v, P, lo = -INFINITY, hi = INFINITY;
    int ilo = -1, ihi = -1, ib;
    if (fabs(M * vs) <= c)
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
            if (w->gap[i] <= TOUCH && w->G[i][0] * P > 0) ib = i;
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

/* ------------------------------------------------------------ the step loop */

/* generalized planar vector (x, y, theta) rotated about z by the angle
 * whose cosine and sine are cs[0], sign * cs[1] (sign = -1: the inverse) */
static inline void rotate_gen(double out[3], const double in[3], const double cs[2], double sign)
{
    double c = cs[0], sn = sign * cs[1];
    double x = c * in[0] - sn * in[1], y = sn * in[0] + c * in[1];
    out[0] = x;
    out[1] = y;
    out[2] = in[2];
}

/* Patch impulse (object frame) of a B-frame generalized impulse P:
 * p = J'^-T Rg(-th) P, with J'^-T = [[1,0,0],[0,1,0],[pc_y,-pc_x,1]]. */
static void patch_impulse(const exdex_model *m, const double cs[2], const double P[3], double p[3])
{
    double Po[3];
    rotate_gen(Po, P, cs, -1.0);
    p[0] = Po[0];
    p[1] = Po[1];
    p[2] = Po[2] + m->pc[1] * Po[0] - m->pc[0] * Po[1];
}

/* Small dense solve A x = b for n <= 3 (Gaussian elimination, partial
 * pivoting); returns 0 if A is numerically singular. A and b are clobbered. */
static int solve_small(int n, double A[3][3], double b[3], double x[3])
{
    double scale = 0.0;
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) scale = fmax(scale, fabs(A[i][j]));
    for (int c = 0; c < n; c++) {
        int piv = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(A[r][c]) > fabs(A[piv][c])) piv = r;
        if (!(fabs(A[piv][c]) > 1e-12 * scale)) return 0;
        if (piv != c) {
            for (int k = 0; k < n; k++) {
                double t = A[c][k];
                A[c][k] = A[piv][k];
                A[piv][k] = t;
            }
            {
                double t = b[c];
                b[c] = b[piv];
                b[piv] = t;
            }
        }
        for (int r = c + 1; r < n; r++) {
            double f = A[r][c] / A[c][c];
            for (int k = c; k < n; k++) A[r][k] -= f * A[c][k];
            b[r] -= f * b[c];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        double acc = b[r];
        for (int k = r + 1; k < n; k++) acc -= A[r][k] * x[k];
        x[r] = acc / A[r][r];
    }
    return 1;
}

/* Can the object stay exactly at rest (v+ = 0) with stop impulses lambda >= 0
 * on the touching rows and a friction impulse inside the ellipsoid? The
 * friction needed is p(lambda) = -J^-T (M v* + G^T lambda); minimise
 * |E^-1 p(lambda)| over lambda >= 0 (a tiny non-negative least-squares
 * problem, solved exactly by trying every support of size <= 3: in 3-D an
 * optimal support never needs more). Rest holds iff that minimum <= cap; the
 * minimiser is the split with the least friction (the stops carry what they
 * can). */
static int try_rest(const exdex_model *m, const double cs[2], double cap, const double vs[3], work *w,
                    double pfB[3], exdex_friction_result *fr)
{
    int rows[8], k = 0, best_set[3] = {-1, -1, -1}, best_n = 0;
    double a[3], B[8][3], P[3], best, best_lam[3] = {0, 0, 0};
    for (int i = 0; i < w->n_rows; i++) {
        if (w->rhs[i] > 0.0 && w->gap[i] < -TOUCH) return 0; /* rest would penetrate */
        if (w->gap[i] <= TOUCH && k < 8) rows[k++] = i;
    }
    for (int i = 0; i < 3; i++) P[i] = vs[i] / m->minv[i];
    patch_impulse(m, cs, P, a);
    for (int i = 0; i < 3; i++) a[i] /= m->e[i];
    for (int j = 0; j < k; j++) {
        patch_impulse(m, cs, w->G[rows[j]], B[j]);
        for (int i = 0; i < 3; i++) B[j][i] /= m->e[i];
    }
    best = sqrt(ex_dot3(a, a)); /* empty support */
    for (int mask = 1; mask < (1 << k); mask++) {
        int set[3], n = 0, ok = 1;
        double A[3][3], rhs[3], lam[3], r[3], norm;
        for (int j = 0; j < k && n <= 3; j++)
            if (mask & (1 << j)) {
                if (n < 3) set[n] = j;
                n++;
            }
        if (n > 3) continue;
        for (int i = 0; i < n; i++) {
            for (int j = 0; j < n; j++) A[i][j] = ex_dot3(B[set[i]], B[set[j]]);
            rhs[i] = -ex_dot3(B[set[i]], a);
        }
        if (!solve_small(n, A, rhs, lam)) continue;
        for (int i = 0; i < n; i++) ok &= lam[i] >= 0.0;
        if (!ok) continue;
        for (int c = 0; c < 3; c++) {
            r[c] = a[c];
            for (int i = 0; i < n; i++) r[c] += lam[i] * B[set[i]][c];
        }
        norm = sqrt(ex_dot3(r, r));
        if (norm < best) {
            best = norm;
            best_n = n;
            for (int i = 0; i < n; i++) {
                best_set[i] = rows[set[i]];
                best_lam[i] = lam[i];
            }
        }
    }
    if (!(best <= cap * (1.0 + 1e-12))) return 0;
    for (int i = 0; i < 3; i++) P[i] = vs[i] / m->minv[i];
    for (int i = 0; i < w->n_rows; i++) w->lam[i] = 0.0;
    for (int i = 0; i < best_n; i++) {
        w->lam[best_set[i]] = best_lam[i];
        for (int c = 0; c < 3; c++) P[c] += best_lam[i] * w->G[best_set[i]][c];
    }
    for (int c = 0; c < 3; c++) pfB[c] = -P[c];
    patch_impulse(m, cs, pfB, fr->p);
    fr->u[0] = fr->u[1] = fr->u[2] = 0.0;
    fr->sigma = 0.0;
    fr->stick = 1;
    fr->iterations = 0;
    return 1;
}

/* Friction slip map in B generalized coordinates, scaled: r = E J_f v with
 * J_f v = J' Rg(-th) v, J' = [[1,0,-pc_y],[0,1,pc_x],[0,0,1]]. */
static void ejf(const exdex_model *m, const double cs[2], const double v[3], double r[3])
{
    double vo[3];
    rotate_gen(vo, v, cs, -1.0);
    r[0] = m->e[0] * (vo[0] - m->pc[1] * vo[2]);
    r[1] = m->e[1] * (vo[1] + m->pc[0] * vo[2]);
    r[2] = m->e[2] * vo[2];
}

/* B-frame generalized impulse of a patch impulse p (object frame). */
static void gen_impulse(const exdex_model *m, const double cs[2], const double p[3], double P[3])
{
    double Po[3] = {p[0], p[1], p[2] - m->pc[1] * p[0] + m->pc[0] * p[1]};
    rotate_gen(P, Po, cs, 1.0);
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
    int nz = 3 - k, converged = 0;
    for (int i = 0; i < 3; i++) Mdiag[i] = 1.0 / m->minv[i];
    /* particular solution (least norm) and null-space basis */
    {
        double A[3][3], b[3], y[3];
        for (int i = 0; i < k; i++) {
            for (int j = 0; j < k; j++) A[i][j] = ex_dot3(w->G[act[i]], w->G[act[j]]);
            b[i] = w->rhs[act[i]];
        }
        if (k > 0) {
            if (!solve_small(k, A, b, y)) return 0;
            for (int i = 0; i < k; i++)
                for (int c = 0; c < 3; c++) vp[c] += y[i] * w->G[act[i]][c];
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
        ejf(m, cs, vp, r0);
        for (int j = 0; j < nz; j++) {
            double col[3] = {N[0][j], N[1][j], N[2][j]}, bc[3];
            ejf(m, cs, col, bc);
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
            if (!solve_small(nz, Hs, gs, step)) return 0;
            /* backtracking on the objective keeps the damped Newton step
             * monotone. Near the optimum the decrease of a Newton step
             * (~ |g| |step|) falls below the rounding of f itself; a step whose
             * objective differs from f0 by no more than that rounding (fscale
             * below, the sum of the terms' magnitudes) is accepted, else the
             * search would shrink t to nothing and the iteration stall short of
             * the optimum (found by the frame-invariance test: a stall at a
             * gradient 1e-10 left a 1e-10 relative velocity error that
             * depended on the rounding of the world frame). */
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
                ft = cap * sqrt(ex_dot3(rt, rt));
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
                 * optimum of the local model), not the damped one, is tiny */
                double sn = 0, zn = 0;
                for (int j = 0; j < nz; j++) {
                    sn += step[j] * step[j];
                    zn += z[j] * z[j];
                }
                if (sqrt(sn) <= 1e-14 * (1e-3 + sqrt(zn))) {
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
        ejf(m, cs, v, r);
        nr = sqrt(ex_dot3(r, r));
        if (!(nr > 0)) return 0;
        for (int c = 0; c < 3; c++) p[c] = -cap * m->e[c] * r[c] / nr;
        gen_impulse(m, cs, p, P);
        /* G_A^T lam = M (v - vs) - P_f, least squares */
        for (int c = 0; c < 3; c++) res[c] = Mdiag[c] * (v[c] - vs[c]) - P[c];
        for (int i = 0; i < k; i++) {
            for (int j = 0; j < k; j++) A[i][j] = ex_dot3(w->G[act[i]], w->G[act[j]]);
            b[i] = ex_dot3(w->G[act[i]], res);
        }
        if (k > 0 && !solve_small(k, A, b, lam)) return 0;
    }
    return converged ? 1 : 2;
}

/* Planar friction + stops: friction alone first; if a stop row is violated,
 * exact rest (try_rest), else a primal active set over the stop rows with the
 * smooth sliding subproblem (solve_active). */
static int step_planar(const exdex_model *m, double h, double th, const double vs[3], work *w,
                       double v[3], double pfB[3], exdex_friction_result *fr, exdex_stats *st)
{
    double cap = h * m->capF, b[3], vo[3], cs[2] = {cos(th), sin(th)};
    int s, act[3], k = 0, round;
    rotate_gen(vo, vs, cs, -1.0);
    b[0] = vo[0] - m->pc[1] * vo[2];
    b[1] = vo[1] + m->pc[0] * vo[2];
    b[2] = vo[2];
    s = exdex_friction_solve(&m->prep, b, cap, m->def.friction_solver, w->fws, w->have_prev ? w->p_prev : NULL, fr);
    if (s) return s;
    st->solver_iterations += (size_t)fr->iterations;
    gen_impulse(m, cs, fr->p, pfB);
    for (int i = 0; i < 3; i++) v[i] = fr->stick ? 0.0 : vs[i] + m->minv[i] * pfB[i];
    for (round = 0; round < 12; round++) {
        int worst = -1, neg = -1;
        double wv = 0.0, lam[3] = {0, 0, 0}, p[3], vn[3];
        for (int i = 0; i < w->n_rows; i++) {
            double viol = w->rhs[i] - ex_dot3(w->G[i], v);
            int in = 0;
            for (int a = 0; a < k; a++) in |= act[a] == i;
            if (!in && viol > 1e-13 * (1.0 + fabs(w->rhs[i])) && viol > wv) {
                wv = viol;
                worst = i;
            }
        }
        if (worst < 0) break; /* every row satisfied: done */
        if (round == 0 && try_rest(m, cs, cap, vs, w, pfB, fr)) {
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
        gen_impulse(m, cs, p, pfB);
    }
    if (round == 12) st->warnings++; /* active-set rounds ran out: last iterate kept */
done:
    w->p_prev[0] = fr->p[0];
    w->p_prev[1] = fr->p[1];
    w->p_prev[2] = fr->p[2];
    w->have_prev = 1;
    return EXDEX_OK;
}

/* Minimum-norm point of { z : a_i . z >= c_i - tol_i, i in cand } (z in
 * R^n, n <= 3), exactly: the minimiser is z = sum_S y_i a_i with y >= 0 on
 * a support S of at most n linearly independent rows (Caratheodory), active
 * there (A_S A_S^T y = c_S); every such support with y >= 0 whose z satisfies
 * all the candidate rows is tried (nc <= PROJ_CAND: at most 92 solves of
 * size <= 3) and the shortest z kept. Returns 0 if none is feasible (the
 * rows contradict each other, e.g. two stops pinching the object). */
#define PROJ_CAND 8

static int proj_min_norm(int n, const double a[][3], const double *c, const double *tol, const int *cand, int nc,
                         double z[3])
{
    double best = INFINITY;
    for (int mask = 1; mask < (1 << nc); mask++) {
        int set[3], ns = 0, ok = 1;
        double H[3][3], rhs[3], y[3], zt[3] = {0, 0, 0}, zn;
        for (int j = 0; j < nc; j++)
            if (mask & (1 << j)) {
                if (ns < 3) set[ns] = cand[j];
                ns++;
            }
        if (ns > n) continue;
        for (int i = 0; i < ns; i++) {
            for (int j = 0; j < ns; j++) H[i][j] = ex_dot3(a[set[i]], a[set[j]]);
            rhs[i] = c[set[i]];
        }
        if (!solve_small(ns, H, rhs, y)) continue;
        for (int i = 0; i < ns; i++) ok &= y[i] >= 0.0;
        if (!ok) continue;
        for (int i = 0; i < ns; i++)
            for (int d = 0; d < 3; d++) zt[d] += y[i] * a[set[i]][d];
        for (int j = 0; j < nc; j++) ok &= ex_dot3(a[cand[j]], zt) >= c[cand[j]] - tol[cand[j]];
        if (!ok) continue;
        zn = ex_dot3(zt, zt);
        if (zn < best) {
            best = zn;
            memcpy(z, zt, sizeof zt);
        }
    }
    return best < INFINITY;
}

/* Remove the residual penetration left by the midpoint position update and
 * the linearised rotation (see build_rows): Newton passes on the vertex
 * gaps, each the least M-norm correction dq with every linearised gap
 * g_i + G_i dq >= 0 (a small QP over all vertex rows, solved by
 * proj_min_norm on a growing set of candidate rows: start with the deepest,
 * add the row most violated by the current dq until none is). A gap within
 * its rounding bound (gap_round) of 0 counts as 0, as in build_rows: the
 * sign of a rounding-level gap is not determined by the data.
 * (Found by the property test test_stop_never_penetrated: the previous
 * projection moved along M^-1 G^T of the deepest vertex alone. With an edge
 * of the box flush against the stop, its two vertices equally deep, each
 * such step rotates the box and pushes the other vertex in: the penetration
 * alternated between them and shrank only by a factor 0.7 per pass, 16
 * passes left 5e-8 m; and rounding-level gaps of -1e-18 m, which no
 * projection removes, used up all passes and counted a warning each step.
 * Both vertex rows together give the pure translation at once.) */
static void project_positions(const exdex_model *m, const exdex_kinematics *kin, double *q,
                              exdex_stats *st)
{
    int nv = m->n_vert ? m->n_vert : 1, n = m->ndof, nr = m->n_stops * nv;
    double sq[3] = {0, 0, 0};  /* M^-1/2 (the metric of the correction) */
    if (n == 1) {
        sq[0] = 1.0;
    } else {
        sq[0] = sq[1] = 1.0 / sqrt(m->m);
        sq[2] = 1.0 / sqrt(m->izz);
    }
    for (int pass = 0; pass < 16; pass++) {
        double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], a[MAX_ROWS][3], g[MAX_ROWS], c[MAX_ROWS],
            tol[MAX_ROWS], z[3] = {0, 0, 0}, depth = 0.0;
        int cand[PROJ_CAND], nc = 0, deep = -1, solved = 0;
        body_vertices(m, q, xb, vx);
        for (int k = 0; k < m->n_stops; k++)
            for (int j = 0; j < nv; j++) {
                int i = k * nv + j;
                double G[3] = {0, 0, 0};
                g[i] = gap_at(m, kin, k, xb[j], vx[j], G);
                tol[i] = gap_round(m, kin, k, xb[j]);
                for (int d = 0; d < 3; d++) a[i][d] = G[d] * sq[d];
                if (g[i] < -tol[i] && (deep < 0 || g[i] < g[deep])) deep = i;
            }
        if (deep < 0) return;  /* every gap >= 0 to rounding */
        depth = -g[deep];
        /* target gap slightly positive (1e-12 of the depth): the next pass
         * then sees no rounding-level penetration from this one */
        for (int i = 0; i < nr; i++) c[i] = -g[i] + 1e-12 * depth;
        cand[nc++] = deep;
        for (;;) {
            int worst = -1;
            double wv = 0.0;
            if (!proj_min_norm(n, a, c, tol, cand, nc, z)) break;
            for (int i = 0; i < nr; i++) {
                double viol = c[i] - tol[i] - ex_dot3(a[i], z);
                if (viol > wv) {
                    wv = viol;
                    worst = i;
                }
            }
            if (worst < 0) {
                solved = 1;
                break;
            }
            if (nc == PROJ_CAND) break;
            cand[nc++] = worst;
        }
        if (!solved) {
            /* contradictory rows (pinched object) or too many candidates:
             * the deepest row alone, as far as it can act */
            double aa = ex_dot3(a[deep], a[deep]);
            if (!(aa > 0.0)) break;
            for (int d = 0; d < 3; d++) z[d] = a[deep][d] * c[deep] / aa;
        }
        for (int d = 0; d < n; d++) q[d] += sq[d] * z[d];
    }
    /* still penetrating after every pass (e.g. the prescribed motion drives a
     * pinned pivot through a stop): report it rather than stay silent */
    st->warnings++;
}

static void record_gap(const exdex_model *m, const exdex_kinematics *kin, const double *q,
                       exdex_stats *st)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
    int nv = body_vertices(m, q, xb, vx);
    for (int k = 0; k < m->n_stops; k++)
        for (int j = 0; j < nv; j++) {
            double gap = gap_at(m, kin, k, xb[j], vx[j], NULL);
            if (gap < st->min_gap) st->min_gap = gap;
        }
}

int exdex_simulate(const exdex_model *m, double t_end, double dt, exdex_trajectory *out,
                   exdex_stats *stats)
{
    size_t n = exdex_n_samples(t_end, dt);
    int n_dof, ns, status = EXDEX_OK;
    double q[3], v[3], vprev[3], hprev = 0.0, t;
    exdex_kinematics kin0;
    work *w;
    exdex_stats st;
    if (!m || !out || n == 0 || out->n != n || !out->t || !out->q || !out->v || !out->wrench ||
        !out->stick || (m->n_stops && !out->stop_force))
        return EXDEX_EINVAL;
    if (m->def.method != EXDEX_METHOD_IMPLICIT) return sim_simulate_method(m, t_end, dt, out, stats);
    /* malloc, not calloc: the row arrays (~13 kB) are written before they are
     * read (build_rows), and zeroing them cost ~7 % of a short planar run */
    w = malloc(sizeof *w);
    if (!w) return EXDEX_ENOMEM;
    w->fws = NULL;
    w->p_prev[0] = w->p_prev[1] = w->p_prev[2] = 0.0;
    w->have_prev = 0;
    w->n_rows = 0;
    if (m->def.friction_solver != EXDEX_SOLVER_SCALAR && m->ndof == 3) {
        w->fws = exdex_friction_ws_alloc();
        if (!w->fws) {
            free(w);
            return EXDEX_ENOMEM;
        }
    }
    memset(&st, 0, sizeof st);
    st.min_gap = INFINITY;
    n_dof = m->ndof;
    ns = m->n_stops;
    if (n_dof == 3) {
        memcpy(q, m->def.q0, sizeof q);
        memcpy(v, m->def.v0, sizeof v);
    } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        q[0] = m->s0;
        v[0] = m->d[0] * m->def.v0[0] + m->d[1] * m->def.v0[1];
    } else {
        q[0] = m->th0;
        v[0] = m->def.v0[2];
    }
    /* sample 0 */
    out->t[0] = 0.0;
    for (int i = 0; i < n_dof; i++) {
        out->q[i] = q[i];
        out->v[i] = v[i];
    }
    out->wrench[0] = out->wrench[1] = out->wrench[2] = 0.0;
    out->stick[0] = (v[0] == 0.0 && (n_dof == 1 || (v[1] == 0.0 && v[2] == 0.0)));
    for (int k = 0; k < ns; k++) out->stop_force[k] = 0.0;

    t = 0.0;
    status = exdex_motion_eval(m->motion, 0.0, &kin0);
    for (size_t step = 1; step < n && status == EXDEX_OK; step++) {
        double t1 = step == n - 1 ? t_end : (double)step * dt;
        double h = t1 - t, tm = t + 0.5 * h, qm[3], vmid[3], r[3], rd[3], th, F[3], vs[3], vn[3];
        double wrench[3] = {0, 0, 0};
        frame f;
        exdex_kinematics kin, kin_end;
        int stick;
        /* step-mean frame accelerations (a midpoint sample would make an
         * acceleration jump inside the step an O(h) error) */
        status = sim_frame_step(m, &kin0, tm, t1, h, &f, &kin, &kin_end);
        if (status) break;
        for (int i = 0; i < n_dof; i++) {
            qm[i] = q[i] + 0.5 * h * v[i];
            /* velocity at the midpoint, extrapolated from the last step, for
             * the velocity-dependent (Coriolis, gyroscopic) terms: second
             * order in smooth phases, and exactly 0 while the object sticks */
            vmid[i] = hprev > 0.0 ? v[i] + 0.5 * h * (v[i] - vprev[i]) / hprev : v[i];
        }
        sim_com_pose(m, qm, r, &th);
        if (ns) {
            build_rows(m, &kin_end, q, h, w);
        } else {
            w->n_rows = 0;
        }
        if (n_dof == 1) {
            double M, Q, c, pf;
            if (m->def.dof == EXDEX_DOF_TRANSLATION) {
                rd[0] = vmid[0] * m->d[0];
                rd[1] = vmid[0] * m->d[1];
                rd[2] = 0.0;
                sim_force_lin(m, &f, r, rd, F);
                M = m->m;
                Q = F[0] * m->d[0] + F[1] * m->d[1];
                c = h * m->capF;  /* |E j| = e_t = 1 */
            } else {
                double rho[2];
                rot2(rho, qm[0], m->c);
                rd[0] = -vmid[0] * rho[1];
                rd[1] = vmid[0] * rho[0];
                rd[2] = 0.0;
                sim_force_lin(m, &f, r, rd, F);
                M = m->mrot;
                Q = -rho[1] * F[0] + rho[0] * F[1] + sim_torque_z(m, &f, qm[0], vmid[0]);
                c = h * m->capF * m->e[2];  /* pure spin at the centre of pressure */
            }
            vs[0] = v[0] + h * Q / M;
            step_1dof(M, c, vs[0], w, &vn[0], &pf, &st);
            if (m->def.dof == EXDEX_DOF_TRANSLATION) {
                wrench[0] = pf * m->d[0] / h;
                wrench[1] = pf * m->d[1] / h;
            } else {
                wrench[2] = pf / h;
            }
            stick = vn[0] == 0.0;
        } else {
            exdex_friction_result fr;
            double pfB[3], fo[3];
            rd[0] = vmid[0];
            rd[1] = vmid[1];
            rd[2] = 0.0;
            sim_force_lin(m, &f, r, rd, F);
            F[2] = sim_torque_z(m, &f, th, vmid[2]);
            for (int i = 0; i < 3; i++) vs[i] = v[i] + h * m->minv[i] * F[i];
            status = step_planar(m, h, th, vs, w, vn, pfB, &fr, &st);
            if (status) break;
            /* report the patch wrench (not the generalized impulse), in B */
            rot2(fo, th, fr.p);
            wrench[0] = fo[0] / h;
            wrench[1] = fo[1] / h;
            wrench[2] = fr.p[2] / h;
            stick = vn[0] == 0.0 && vn[1] == 0.0 && vn[2] == 0.0;
        }
        {
            /* A step in which a stop pushes ends where its row put it: q + h v+
             * (gap exactly 0 for a translating contact); otherwise Moreau's
             * midpoint update q_m + h/2 v+. */
            int pushed = 0;
            for (int i = 0; i < w->n_rows; i++) pushed |= w->lam[i] > 0.0;
            for (int i = 0; i < n_dof; i++) {
                q[i] = pushed ? q[i] + h * vn[i] : qm[i] + 0.5 * h * vn[i];
                vprev[i] = v[i];
                v[i] = vn[i];
            }
        }
        if (ns) {
            project_positions(m, &kin_end, q, &st);
            record_gap(m, &kin_end, q, &st);
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
        kin0 = kin_end;
        st.steps++;
        st.stick_steps += (size_t)stick;
        out->t[step] = t1;
        for (int i = 0; i < n_dof; i++) {
            out->q[step * n_dof + i] = q[i];
            out->v[step * n_dof + i] = v[i];
        }
        for (int i = 0; i < 3; i++) out->wrench[3 * step + i] = wrench[i];
        out->stick[step] = (unsigned char)stick;
        for (int k = 0; k < ns; k++) out->stop_force[step * ns + k] = 0.0;
        for (int i = 0; i < w->n_rows; i++)
            out->stop_force[step * ns + w->row_stop[i]] += w->lam[i] / h;
    }
    exdex_friction_ws_free(w->fws);
    free(w);
    if (stats) *stats = st;
    /* the model and arguments were valid: an "invalid argument" from a solver
     * inside the loop means the state left the finite range */
    return status == EXDEX_EINVAL ? EXDEX_ENONFINITE : status;
}
