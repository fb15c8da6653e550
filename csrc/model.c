/* model.c -- a scene definition (exdex_scene_def) checked and compiled into
 * the immutable model (model.h), the kinematics of the gripper frame B, and
 * the paper's Eqs. 3-5: the gravity and inertial force and torque that the
 * moving frame puts on the object, in B coordinates.
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
 * + friction + stops with a 1x1 or 3x3 M (model_force_1dof,
 * model_force_planar). */
#include "exdex.h"
#include "model.h"
#include "contact.h"
#include "pose.h"
#include "util.h"
#include "region.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_sort.h>

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

/* Pads on the fingers: 0 without them; else the pad (B) and face (C) as
 * shapes into pad, face (may be NULL), or EXDEX_EINVAL naming the field. */
static int check_pads(const exdex_scene_def *d, pads_shape *pad, pads_shape *face, const char **bad_param)
{
    pads_shape tmp[2];
    const int np[2] = {d->pad_n, d->face_n};
    const double *rad[2] = {&d->pad_radius, &d->face_radius}, *cen[2] = {d->pad_center, d->face_center};
    const double (*pv[2])[2] = {d->pad, d->face};
    static const char *names[2][3] = {{"pad_n", "pad_radius", "pad_center"}, {"face_n", "face_radius", "face_center"}};
    if (!pad) pad = &tmp[0];
    if (!face) face = &tmp[1];
    if (d->pad_n < 0 || d->pad_n > EXDEX_MAX_PAD_VERTICES) return bad(bad_param, "pad_n");
    if (!(isfinite(d->pad_radius) && d->pad_radius >= 0.0)) return bad(bad_param, "pad_radius");
    if (d->pad_n == 0 && d->pad_radius == 0.0) {
        /* no pads: the face is not read */
        return EXDEX_OK;
    }
    for (int k = 0; k < 2; k++) {
        pads_shape *s = k ? face : pad;
        if (np[k] < 0 || np[k] > EXDEX_MAX_PAD_VERTICES) return bad(bad_param, names[k][0]);
        if (!(isfinite(*rad[k]) && *rad[k] >= 0.0)) return bad(bad_param, names[k][1]);
        if ((np[k] > 0) == (*rad[k] > 0.0)) return bad(bad_param, np[k] ? names[k][1] : names[k][0]);
        memset(s, 0, sizeof *s);
        if (np[k]) {
            double sc = k == 0 && d->pad_scale != 0.0 ? d->pad_scale : 1.0;
            s->n = np[k];
            if (k == 0 && !(isfinite(d->pad_scale) && d->pad_scale >= 0.0)) return bad(bad_param, "pad_scale");
            if (k == 0 && !ex_finite_n(d->pad_center, 2)) return bad(bad_param, "pad_center");
            for (int i = 0; i < np[k]; i++) {
                s->v[i][0] = k == 0 ? d->pad_center[0] + sc * pv[k][i][0] : pv[k][i][0];
                s->v[i][1] = k == 0 ? d->pad_center[1] + sc * pv[k][i][1] : pv[k][i][1];
            }
            if (!pads_poly_ccw(s->v, s->n)) return bad(bad_param, k ? "face" : "pad");
        } else {
            if (!ex_finite_n(cen[k], 2)) return bad(bad_param, names[k][2]);
            s->r = *rad[k];
            s->c[0] = cen[k][0];
            s->c[1] = cen[k][1];
        }
    }
    return EXDEX_OK;
}

/* Field-by-field validation of everything but R0, the motion, the planar
 * friction problem and the initial stop gaps (those need the model built). */
int model_region(const exdex_scene_def *d, region *rg)
{
    if (d->region_kind == EXDEX_REGION_DISC) {
        region_set_disc(rg, 0.0, 0.0, d->region_radius);
    } else if (d->region_kind == EXDEX_REGION_POLYGON) {
        if (d->region_n < 3 || d->region_n > EXDEX_REGION_MAX_VERTICES) return EXDEX_EINVAL;
        memset(rg, 0, sizeof *rg);
        rg->kind = REGION_POLYGON;
        rg->n = d->region_n;
        memcpy(rg->v, d->region_vertices, (size_t)d->region_n * sizeof rg->v[0]);
    } else {
        return EXDEX_EINVAL;
    }
    return region_check(rg);
}

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
    if (!(isfinite(d->disc_radius) && d->disc_radius >= 0.0) || (d->disc_radius > 0.0 && d->n_vertices != 0))
        return bad(bad_param, "disc_radius");
    if (!ex_finite_n(d->disc_center, 2)) return bad(bad_param, "disc_center");
    {
        int st = check_pads(d, NULL, NULL, bad_param);
        if (st) return st;
    }
    if (!(isfinite(d->mu) && d->mu >= 0)) return bad(bad_param, "mu");
    if (!(isfinite(d->grip_force) && d->grip_force >= 0)) return bad(bad_param, "grip_force");
    if (!(isfinite(d->mu_static) && (d->mu_static == 0.0 || d->mu_static >= d->mu)))
        return bad(bad_param, "mu_static");
    if (d->grip_n > EXDEX_MAX_GRIP_POINTS) return bad(bad_param, "grip_n");
    if (d->grip_n) {
        if (d->grip_kind < EXDEX_GRIP_LINEAR || d->grip_kind > EXDEX_GRIP_STEP) return bad(bad_param, "grip_kind");
        if (!d->grip_times || !ex_finite_n(d->grip_times, (int)d->grip_n)) return bad(bad_param, "grip_times");
        for (size_t i = 1; i < d->grip_n; i++)
            if (!(d->grip_times[i] > d->grip_times[i - 1])) return bad(bad_param, "grip_times");
        if (!d->grip_forces) return bad(bad_param, "grip_forces");
        for (size_t i = 0; i < d->grip_n; i++)
            if (!(isfinite(d->grip_forces[i]) && d->grip_forces[i] >= 0)) return bad(bad_param, "grip_forces");
        /* the scaled forces must stay finite, and so must the slopes of the
         * interpolant: |dF| / h (and |dF| / h^3 for the cubic's coefficients)
         * for each interval h between the points */
        for (size_t i = 0; i < d->grip_n; i++)
            if (!isfinite(d->grip_force * d->grip_forces[i])) return bad(bad_param, "grip_forces");
        for (size_t i = 1; i < d->grip_n; i++) {
            double h = d->grip_times[i] - d->grip_times[i - 1];
            double dF = fabs(d->grip_force * d->grip_forces[i] - d->grip_force * d->grip_forces[i - 1]);
            if (dF > 0.0 && !(isfinite(dF / h) && (d->grip_kind != EXDEX_GRIP_CUBIC || isfinite(dF / (h * h * h)))))
                return bad(bad_param, "grip_times");
        }
    }
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
        if (!(isfinite(d->stop_mu[k]) && d->stop_mu[k] >= 0)) return bad(bad_param, "stop_mu");
    }
    if (d->n_obstacles < 0 || d->n_obstacles > EXDEX_MAX_OBSTACLES) return bad(bad_param, "n_obstacles");
    for (int o = 0; o < d->n_obstacles; o++)
        if (!contact_obstacle_valid(&d->obstacles[o])) return bad(bad_param, "obstacles");
    if (d->method < EXDEX_METHOD_IMPLICIT || d->method > EXDEX_METHOD_ANALYTIC) return bad(bad_param, "method");
    if (d->n_obstacles && d->method == EXDEX_METHOD_ANALYTIC) return bad(bad_param, "method");
    for (int o = 0; o < d->n_obstacles; o++)
        if (d->obstacles[o].mu > 0.0 && d->method != EXDEX_METHOD_IMPLICIT && d->method != EXDEX_METHOD_EXPLICIT &&
            d->method != EXDEX_METHOD_EVENT && d->method != EXDEX_METHOD_REGULARISED)
            return bad(bad_param, "method");
    if (d->method == EXDEX_METHOD_ANALYTIC && exdex_analytic_unsupported(d)) return bad(bad_param, "method");
    if (d->friction_solver < EXDEX_SOLVER_SCALAR || d->friction_solver > EXDEX_SOLVER_MULTIROOT)
        return bad(bad_param, "friction_solver");
    if (d->limit_surface != EXDEX_LS_ELLIPSOID && d->limit_surface != EXDEX_LS_EXACT)
        return bad(bad_param, "limit_surface");
    if (d->region_kind != EXDEX_REGION_NONE) {
        region rg;
        if (model_region(d, &rg) != EXDEX_OK) return bad(bad_param, "region_kind");
    }
    if (d->limit_surface == EXDEX_LS_EXACT) {
        /* the region: the patch's, or pad and face (pads on the fingers) */
        if (d->region_kind == EXDEX_REGION_NONE && !(d->pad_n > 0 || d->pad_radius > 0.0))
            return bad(bad_param, "region_kind");
    }
    if (!(isfinite(d->eps) && d->eps > 0)) return bad(bad_param, "eps");
    if (!(isfinite(d->rtol) && d->rtol > 0)) return bad(bad_param, "rtol");
    if (!(isfinite(d->atol) && d->atol > 0)) return bad(bad_param, "atol");
    return EXDEX_OK;
}

/* ------------------------------------------------ method applicability */

#define PARALLEL 1e-12   /* rotation axis parallel to the plate normal to this (|axis x n|) */

const char *exdex_analytic_unsupported(const exdex_scene_def *d)
{
    const exdex_motion_def *mo;
    if (!d) return "no scene";
    mo = &d->motion;
    if (d->dof != EXDEX_DOF_TRANSLATION && d->dof != EXDEX_DOF_ROTATION)
        return "the analytic method solves 1-DoF scenes (translation or rotation), not planar ones";
    if (d->n_stops != 0 || d->n_obstacles != 0) return "the analytic method solves scenes without stops";
    if (d->pad_n > 0 || d->pad_radius > 0.0)
        return "the analytic method solves the patch fixed on the object, not pads on the fingers";
    if (mo->time_shift != 0.0) return "the analytic method plays a motion from its start (no time shift)";
    if (mo->kind == EXDEX_MOTION_SHAKE || mo->kind == EXDEX_MOTION_CHAIN)
        return "the analytic method needs a piecewise-constant gripper acceleration (Eq. 7, trapezoid or "
               "rest), not a shake or a chain";
    if (d->grip_n > 1 && d->grip_forces && d->grip_kind == EXDEX_GRIP_CUBIC)
        for (size_t i = 1; i < d->grip_n; i++)
            if (d->grip_forces[i] != d->grip_forces[0])
                return "the analytic method solves a constant, piecewise-linear or step grip force, not a cubic "
                       "grip schedule";
    if (mo->kind == EXDEX_MOTION_SAMPLED)
        return "the analytic method needs a piecewise-constant gripper acceleration (Eq. 7, trapezoid or "
               "rest), not a sampled log";
    if (mo->kind == EXDEX_MOTION_TRAPEZOID && mo->amplitude != 0.0 &&
        !(mo->duration - fabs(mo->amplitude) / mo->v_max > 0.0))
        return "the analytic method needs a trapezoid with ramps (v_max > |amplitude| / duration), not a "
               "velocity jump";
    if (d->dof == EXDEX_DOF_TRANSLATION) {
        if (mo->kind != EXDEX_MOTION_REST && mo->rotation)
            return "the analytic method solves translation scenes whose gripper translates";
    } else {
        double n[3] = {d->R0[2], d->R0[5], d->R0[8]}, a[3], x[3], na;
        if (d->patch_center[0] != 0.0 || d->patch_center[1] != 0.0)
            return "the analytic method solves rotation scenes about the centre of mass (patch centre 0); "
                   "an offset centre of mass is a pendulum";
        if (mo->kind != EXDEX_MOTION_REST) {
            if (!mo->rotation) return "the analytic method solves rotation scenes whose gripper turns";
            a[0] = mo->axis[0];
            a[1] = mo->axis[1];
            a[2] = mo->axis[2];
            na = sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
            x[0] = a[1] * n[2] - a[2] * n[1];
            x[1] = a[2] * n[0] - a[0] * n[2];
            x[2] = a[0] * n[1] - a[1] * n[0];
            if (!(na > 0.0) || !(sqrt(x[0] * x[0] + x[1] * x[1] + x[2] * x[2]) <= PARALLEL * na))
                return "the analytic method solves rotation scenes whose gripper turns about the plate normal";
        }
    }
    return NULL;
}

/* ------------------------------------------------------------ kinematics */

void model_initial_state(const exdex_model *m, double *q, double *v)
{
    if (m->ndof == 3) {
        memcpy(q, m->def.q0, 3 * sizeof *q);
        memcpy(v, m->def.v0, 3 * sizeof *v);
    } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        q[0] = m->s0;
        v[0] = m->d[0] * m->def.v0[0] + m->d[1] * m->def.v0[1];
    } else {
        q[0] = m->th0;
        v[0] = m->def.v0[2];
    }
}

int model_frame_at(const exdex_model *m, double t, frame *f, exdex_kinematics *k)
{
    int st = exdex_motion_eval(m->motion, t, k);
    if (st) return st;
    ex_mulmtv3(f->gB, k->R, m->g);
    ex_mulmtv3(f->a0, k->R, k->a);
    ex_mulmtv3(f->w, k->R, k->w);
    ex_mulmtv3(f->dw, k->R, k->dw);
    return EXDEX_OK;
}

int model_frame_step(const exdex_model *m, const exdex_kinematics *kin0, double t_eval, double t1, double h,
                   frame *f, exdex_kinematics *kin, exdex_kinematics *kin_end)
{
    double dv[3], dwv[3];
    int status = model_frame_at(m, t_eval, f, kin);
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

/* Sub-steps at switching times (model.h). snap(x): the distance from a
 * step end within which a switching time counts as on it. */
#define substep_snap model_substep_snap

void model_substep_full(const exdex_model *m, double tc, double t1, model_sub *s)
{
    double tj[EXDEX_MOTION_MAX_JUMPS], jv[EXDEX_MOTION_MAX_JUMPS][3], jw[EXDEX_MOTION_MAX_JUMPS][3];
    double lo = tc + substep_snap(m, tc), hi = t1 - substep_snap(m, t1), te = t1, top, ts;
    int nj;
    s->jumps = 0;
    for (int c = 0; c < 3; c++) s->dv[c] = s->dw[c] = s->dvl[c] = s->dwl[c] = 0.0;
    /* both lists increase: the first time past lo is the only candidate */
    ts = exdex_motion_next_switch(m->motion, lo);
    if (ts < hi) te = ts;
    if (m->grip_n) {
        size_t a = 0, b = m->grip_n;
        while (a < b) {
            size_t mid = a + (b - a) / 2;
            if (m->grip_t[mid] > lo) b = mid;
            else a = mid + 1;
        }
        if (a < m->grip_n && m->grip_t[a] < te && m->grip_t[a] < hi) te = m->grip_t[a];
    }
    nj = exdex_motion_jumps(m->motion, NULL, NULL, NULL);
    if (nj) nj = exdex_motion_jumps(m->motion, tj, jv, jw);
    for (int j = 0; j < nj; j++)   /* jump times are switching times; kept if one were not */
        if (tj[j] > lo && tj[j] < hi && tj[j] < te) te = tj[j];
    s->te = te;
    s->split = te < t1;
    if (!nj) return;
    top = te + substep_snap(m, te);
    for (int j = 0; j < nj; j++) {
        if (!(tj[j] > lo && tj[j] <= top)) continue;
        s->jumps++;
        for (int c = 0; c < 3; c++) {
            s->dv[c] += jv[j][c];
            s->dw[c] += jw[j][c];
            if (tj[j] <= te) {
                s->dvl[c] += jv[j][c];
                s->dwl[c] += jw[j][c];
            }
        }
    }
}

int model_frame_substep_jumps(const exdex_model *m, const exdex_kinematics *kin0, double t_eval,
                              const model_sub *s, double h, frame *f, exdex_kinematics *kin,
                              exdex_kinematics *kin_end)
{
    double dv[3], dwv[3];
    int status;
    status = model_frame_at(m, t_eval, f, kin);
    if (status) return status;
    status = exdex_motion_eval(m->motion, s->te, kin_end);
    if (status) return status;
    for (int i = 0; i < 3; i++) {
        kin_end->v[i] -= s->dvl[i];
        kin_end->w[i] -= s->dwl[i];
        dv[i] = (kin_end->v[i] - kin0->v[i]) / h;
        dwv[i] = (kin_end->w[i] - kin0->w[i]) / h;
    }
    ex_mulmtv3(f->a0, kin->R, dv);
    ex_mulmtv3(f->dw, kin->R, dwv);
    return EXDEX_OK;
}

void model_substep_jump(const exdex_model *m, const model_sub *s, const double *q, double *v,
                        exdex_kinematics *kin_end)
{
    if (!s->jumps) return;
    model_velocity_jump(m, kin_end->R, q, s->dv, s->dw, v);
    for (int i = 0; i < 3; i++) {
        kin_end->v[i] += s->dv[i];
        kin_end->w[i] += s->dw[i];
    }
}

/* Inertial + gravity force on the centre of mass (Eq. 5), B coordinates. */
void model_force_lin(const exdex_model *m, const frame *f, const double r[3],
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
double model_torque_z(const exdex_model *m, const frame *f, double th, double thd)
{
    const double cs[2] = {cos(th), sin(th)};
    return model_torque_z_cs(m, f, cs, thd);
}

/* I_B = Rz(th) I Rz(th)^T and the torque -(I_B v)_z - (W x I_B W)_z with
 * v = dw + thd (w x e_z), W = w + thd e_z. Rz's zero entries are left out of
 * the sums (their terms are 0), its unit entry taken as a factor of 1. */
double model_torque_z_cs(const exdex_model *m, const frame *f, const double cs[2], double thd)
{
    const double *I = m->I, *w = f->w;
    double c = cs[0], s = cs[1], T[9], IB[9], v[3], W[3], Iv2, IW0, IW1;
    for (int j = 0; j < 3; j++) {
        T[j] = c * I[j] - s * I[3 + j];          /* T = Rz I */
        T[3 + j] = s * I[j] + c * I[3 + j];
        T[6 + j] = I[6 + j];
    }
    for (int i = 0; i < 3; i++) {                /* I_B = T Rz^T */
        IB[3 * i] = T[3 * i] * c - T[3 * i + 1] * s;
        IB[3 * i + 1] = T[3 * i] * s + T[3 * i + 1] * c;
        IB[3 * i + 2] = T[3 * i + 2];
    }
    v[0] = f->dw[0] + thd * w[1];                /* w x e_z = (w_y, -w_x, 0) */
    v[1] = f->dw[1] + thd * -w[0];
    v[2] = f->dw[2];
    W[0] = w[0];
    W[1] = w[1];
    W[2] = w[2] + thd;
    Iv2 = IB[6] * v[0] + IB[7] * v[1] + IB[8] * v[2];
    IW0 = IB[0] * W[0] + IB[1] * W[1] + IB[2] * W[2];
    IW1 = IB[3] * W[0] + IB[4] * W[1] + IB[5] * W[2];
    return -Iv2 - (W[0] * IW1 - W[1] * IW0);
}

double model_force_1dof(const exdex_model *m, const frame *f, double q, double v)
{
    double r[3], th, rd[3], F[3], q3[3] = {q, 0.0, 0.0};
    pose_com(m, q3, r, &th);
    if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        rd[0] = v * m->d[0];
        rd[1] = v * m->d[1];
        rd[2] = 0.0;
        model_force_lin(m, f, r, rd, F);
        return F[0] * m->d[0] + F[1] * m->d[1];
    } else {
        double rho[2];
        rot2(rho, q, m->c);
        rd[0] = -v * rho[1];
        rd[1] = v * rho[0];
        rd[2] = 0.0;
        model_force_lin(m, f, r, rd, F);
        return -rho[1] * F[0] + rho[0] * F[1] + model_torque_z(m, f, q, v);
    }
}

void model_force_planar(const exdex_model *m, const frame *f, const double *q, const double *v, double F[3])
{
    const double cs[2] = {cos(q[2]), sin(q[2])};
    model_force_planar_cs(m, f, q, v, cs, F);
}

void model_force_planar_cs(const exdex_model *m, const frame *f, const double *q, const double *v,
                           const double cs[2], double F[3])
{
    double r[3] = {q[0], q[1], 0.0}, rd[3] = {v[0], v[1], 0.0};
    model_force_lin(m, f, r, rd, F);
    F[2] = model_torque_z_cs(m, f, cs, v[2]);
}

void model_velocity_jump(const exdex_model *m, const double R[9], const double *q, const double dv[3],
                         const double dw[3], double *v)
{
    frame fj;
    memset(&fj, 0, sizeof fj);
    ex_mulmtv3(fj.a0, R, dv);
    ex_mulmtv3(fj.dw, R, dw);
    if (m->ndof == 1) {
        double M = m->def.dof == EXDEX_DOF_TRANSLATION ? m->m : m->mrot;
        v[0] += model_force_1dof(m, &fj, q[0], 0.0) / M;
    } else {
        double P[3], zero[3] = {0, 0, 0};
        model_force_planar(m, &fj, q, zero, P);
        for (int i = 0; i < 3; i++) v[i] += m->minv[i] * P[i];
    }
}

/* ----------------------------------------------------- patch coordinates */

void model_patch_slip(const exdex_model *m, const double cs[2], const double v[3], double u[3])
{
    double c = cs[0], s = cs[1], vx = c * v[0] + s * v[1], vy = -s * v[0] + c * v[1];
    u[0] = vx - m->pc[1] * v[2];
    u[1] = vy + m->pc[0] * v[2];
    u[2] = v[2];
}

void model_gen_of_patch(const exdex_model *m, const double cs[2], const double w[3], double P[3])
{
    double c = cs[0], s = cs[1], w2 = w[2] - m->pc[1] * w[0] + m->pc[0] * w[1];
    P[0] = c * w[0] - s * w[1];
    P[1] = s * w[0] + c * w[1];
    P[2] = w2;
}

void model_patch_of_gen(const exdex_model *m, const double cs[2], const double P[3], double w[3])
{
    double c = cs[0], s = cs[1], px = c * P[0] + s * P[1], py = -s * P[0] + c * P[1];
    w[0] = px;
    w[1] = py;
    w[2] = P[2] + m->pc[1] * px - m->pc[0] * py;
}

/* ------------------------------------------------ pads on the fingers */

/* W = J' M^-1 J'^T of the patch at m->pc (planar). */
static void patch_delassus(const exdex_model *m, double W[9])
{
    double J[9] = {1, 0, -m->pc[1], 0, 1, m->pc[0], 0, 0, 1};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double s = 0;
            for (int k = 0; k < 3; k++) s += J[3 * i + k] * m->minv[k] * J[3 * j + k];
            W[3 * i + j] = s;
        }
}

/* The friction problem of the patch at pc with semi-axes e (planar), as
 * exdex_friction_prepare makes it from W = J' M^-1 J'^T, but from the
 * factor W = F F^T, F = J' M^-1/2 (known here, and W positive definite by
 * construction): K = E W E = B^T B with B = F^T E, its eigen-decomposition
 * from B's one-sided Jacobi SVD (Hestenes; 3 x 3, inline, to full relative
 * accuracy as friction.c's), eigenvalues ascending. EXDEX_EINVAL where
 * exdex_friction_prepare would refuse K (an eigenvalue below DBL_MIN or not
 * finite, or no convergence). */
int model_pads_prepare(const exdex_model *m, const double pc[2], const double e[3], exdex_friction_prep *p)
{
    double F[9], B[3][3], V[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, lam[3], d0 = sqrt(m->minv[0]),
           d2 = sqrt(m->minv[2]);
    int order[3] = {0, 1, 2}, sweep;
    /* F = J' diag(d0, d0, d2), J' = [[1, 0, -pc_y], [0, 1, pc_x], [0, 0, 1]] */
    F[0] = d0, F[1] = 0.0, F[2] = -pc[1] * d2;
    F[3] = 0.0, F[4] = d0, F[5] = pc[0] * d2;
    F[6] = 0.0, F[7] = 0.0, F[8] = d2;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double w = 0.0;
            for (int k = 0; k < 3; k++) w += F[3 * i + k] * F[3 * j + k];
            p->W[3 * i + j] = w;
        }
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) {
            p->K[3 * i + j] = e[i] * p->W[3 * i + j] * e[j];
            B[i][j] = F[3 * j + i] * e[j];   /* B = F^T E */
        }
        p->e[i] = e[i];
    }
    for (sweep = 0; sweep < 40; sweep++) {
        int rotated = 0;
        for (int a = 0; a < 2; a++)
            for (int b = a + 1; b < 3; b++) {
                double al = 0.0, be = 0.0, ga = 0.0, z, t, c, s;
                for (int k = 0; k < 3; k++) {
                    al += B[k][a] * B[k][a];
                    be += B[k][b] * B[k][b];
                    ga += B[k][a] * B[k][b];
                }
                if (!(fabs(ga) > 4e-16 * sqrt(al * be))) continue;
                rotated = 1;
                z = (be - al) / (2.0 * ga);
                t = (z >= 0.0 ? 1.0 : -1.0) / (fabs(z) + sqrt(1.0 + z * z));
                c = 1.0 / sqrt(1.0 + t * t);
                s = c * t;
                for (int k = 0; k < 3; k++) {
                    double x = B[k][a], y = B[k][b];
                    B[k][a] = c * x - s * y;
                    B[k][b] = s * x + c * y;
                    x = V[k][a], y = V[k][b];
                    V[k][a] = c * x - s * y;
                    V[k][b] = s * x + c * y;
                }
            }
        if (!rotated) break;
    }
    if (sweep == 40) return EXDEX_EINVAL;
    for (int j = 0; j < 3; j++) lam[j] = B[0][j] * B[0][j] + B[1][j] * B[1][j] + B[2][j] * B[2][j];
    /* ascending */
    for (int i = 0; i < 2; i++)
        for (int j = 0; j < 2 - i; j++)
            if (lam[order[j]] > lam[order[j + 1]]) {
                int x = order[j];
                order[j] = order[j + 1];
                order[j + 1] = x;
            }
    for (int j = 0; j < 3; j++) {
        p->lam[j] = lam[order[j]];
        for (int k = 0; k < 3; k++) p->Q[3 * k + j] = V[k][order[j]];
    }
    if (!(p->lam[0] >= DBL_MIN) || !isfinite(p->lam[2])) return EXDEX_EINVAL;
    return EXDEX_OK;
}

/* A point c of B in C relative to the centre of mass at r turned by th. */
static void pads_local_center(const double c[2], const double r[2], double th, double pc[2])
{
    double d[2] = {c[0] - r[0], c[1] - r[1]};
    rot2(pc, -th, d);
}

/* 1 if every vertex of the ccw polygon a (n) lies in the ccw polygon b (k). */
static int poly_in_poly(const double (*a)[2], int n, const double (*b)[2], int k)
{
    for (int e = 0; e < k; e++) {
        const double *p = b[e], *q = b[e + 1 == k ? 0 : e + 1];
        double ex = q[0] - p[0], ey = q[1] - p[1];
        for (int i = 0; i < n; i++)
            if (ex * (a[i][1] - p[1]) - ey * (a[i][0] - p[0]) < 0.0) return 0;
    }
    return 1;
}

/* 1 if the disc (c, r) lies in the ccw polygon b (k). */
static int disc_in_poly(const double c[2], double r, const double (*b)[2], int k)
{
    for (int e = 0; e < k; e++) {
        const double *p = b[e], *q = b[e + 1 == k ? 0 : e + 1];
        double ex = q[0] - p[0], ey = q[1] - p[1];
        if (ex * (c[1] - p[1]) - ey * (c[0] - p[0]) < r * hypot(ex, ey)) return 0;
    }
    return 1;
}

/* The region r (B) of the planar pose q as a region.c region in patch
 * coordinates (C, about the region's centroid, which goes to pc: C,
 * relative to the centre of mass). EXDEX_EINVAL for an empty region. */
static int pads_patch_region(const exdex_model *m, const pads_region *r, const double q[3], region *rg, double pc[2])
{
    double cs = cos(q[2]), sn = sin(q[2]);
    (void)m;
    if (!(r->area > 0.0)) return EXDEX_EINVAL;
    pc[0] = cs * (r->c[0] - q[0]) + sn * (r->c[1] - q[1]);
    pc[1] = -sn * (r->c[0] - q[0]) + cs * (r->c[1] - q[1]);
    memset(rg, 0, sizeof *rg);
    if (r->disc) {
        rg->kind = REGION_DISC;
        rg->r = r->r;
        return EXDEX_OK;
    }
    if (r->n > REGION_MAX_VERTICES) return EXDEX_EINVAL;
    rg->kind = REGION_POLYGON;
    rg->n = r->n;
    for (int i = 0; i < r->n; i++) {
        double x = r->v[i][0] - r->c[0], y = r->v[i][1] - r->c[1];
        rg->v[i][0] = cs * x + sn * y;
        rg->v[i][1] = -sn * x + cs * y;
    }
    return region_check(rg);
}

/* The face at the pose (r, th) in B. */
static void face_at(const exdex_model *m, const double r[2], double th, pads_shape *f)
{
    double cs = cos(th), sn = sin(th);
    f->n = m->face.n;
    for (int i = 0; i < f->n; i++) {
        const double *v = m->face.v[i];
        f->v[i][0] = r[0] + cs * v[0] - sn * v[1];
        f->v[i][1] = r[1] + sn * v[0] + cs * v[1];
    }
    f->r = m->face.r;
    f->c[0] = r[0] + cs * m->face.c[0] - sn * m->face.c[1];
    f->c[1] = r[1] + sn * m->face.c[0] + cs * m->face.c[1];
}

/* Which shape contains the other at the face pose f: 1 the pad lies in the
 * face, 2 the face in the pad, 0 neither (or not decided here). */
static int pads_containment(const exdex_model *m, const pads_shape *f)
{
    const pads_shape *p = &m->pad;
    if (p->n && f->n) {
        if (poly_in_poly((const double (*)[2])p->v, p->n, (const double (*)[2])f->v, f->n)) return 1;
        if (poly_in_poly((const double (*)[2])f->v, f->n, (const double (*)[2])p->v, p->n)) return 2;
        return 0;
    }
    if (!p->n && f->n) return disc_in_poly(p->c, p->r, (const double (*)[2])f->v, f->n) ? 1 : 0;
    if (p->n && !f->n) return disc_in_poly(f->c, f->r, (const double (*)[2])p->v, p->n) ? 2 : 0;
    return 0;   /* two discs: pads_intersect decides */
}

void model_pads_region(const exdex_model *m, const double r[2], double th, pads_region *out)
{
    pads_shape f;
    double cs = cos(th), sn = sin(th);
    f.n = m->face.n;
    for (int i = 0; i < f.n; i++) {
        const double *v = m->face.v[i];
        f.v[i][0] = r[0] + cs * v[0] - sn * v[1];
        f.v[i][1] = r[1] + sn * v[0] + cs * v[1];
    }
    f.r = m->face.r;
    f.c[0] = r[0] + cs * m->face.c[0] - sn * m->face.c[1];
    f.c[1] = r[1] + sn * m->face.c[0] + cs * m->face.c[1];
    pads_intersect(&m->pad, &f, out);
}

void model_pads_set(exdex_model *mc, const double q[3])
{
    pads_region rg;
    pads_shape f;
    double pc[2], cs, sn;
    int in;
    if (!mc->pads || mc->ndof != 3) return;
    if (q[0] == mc->pad_q[0] && q[1] == mc->pad_q[1] && q[2] == mc->pad_q[2]) return;
    face_at(mc, q, q[2], &f);
    in = pads_containment(mc, &f);
    cs = cos(q[2]);
    sn = sin(q[2]);
    if (in == 2 && mc->face_prep_ok && (!mc->ls_exact || mc->face_ls.type)) {
        /* the face inside the pad: the region is the face, fixed on the object */
        mc->pc[0] = mc->face_in_c[0];
        mc->pc[1] = mc->face_in_c[1];
        mc->e[2] = mc->face_in_er;
        mc->prep = mc->face_prep;
        mc->prep_stale = 0;
        if (mc->ls_exact) {
            mc->ls = mc->face_ls;
            mc->e[2] = mc->ls.e[2];
        }
        memcpy(mc->pad_q, q, sizeof mc->pad_q);
        return;
    }
    if (in == 1) {
        /* the pad inside the face: the region is the pad, fixed on the finger */
        rg.area = mc->pad_in_area;
        rg.c[0] = mc->pad_in_c[0];
        rg.c[1] = mc->pad_in_c[1];
        rg.er = mc->pad_in_er;
        if (mc->ls_exact) {
            /* its outline for the exact surface */
            rg.n = mc->pad.n;
            memcpy(rg.v, mc->pad.v, sizeof rg.v);
            rg.disc = mc->pad.n == 0;
            rg.r = mc->pad.r;
        }
    } else {
        pads_intersect(&mc->pad, &f, &rg);
    }
    if (!(rg.area > EXDEX_PAD_LOST * mc->pad_area0 && rg.er > 0.0)) return;
    if (mc->ls_exact) {
        /* the exact surface of the region about its centroid (pc), the
         * bounds of the pad's where the region is the pad */
        region prg;
        limitsurf ls;
        if (pads_patch_region(mc, &rg, q, &prg, pc) != EXDEX_OK || limitsurf_set_exact(&ls, &prg) != EXDEX_OK)
            return;
        if (in == 1) {
            ls.kmin = mc->pad_kmin;
            ls.kmax = mc->pad_kmax;
        } else {
            limitsurf_quick_bounds(&ls);
        }
        mc->pc[0] = pc[0];
        mc->pc[1] = pc[1];
        mc->e[2] = ls.e[2];
        mc->ls = ls;
        mc->prep_stale = 1;   /* prepared when read (model_prep) */
        memcpy(mc->pad_q, q, sizeof mc->pad_q);
        return;
    }
    /* the centroid in C: Rz(-theta) (c - r) */
    pc[0] = cs * (rg.c[0] - q[0]) + sn * (rg.c[1] - q[1]);
    pc[1] = -sn * (rg.c[0] - q[0]) + cs * (rg.c[1] - q[1]);
    mc->pc[0] = pc[0];
    mc->pc[1] = pc[1];
    mc->e[2] = rg.er;
    mc->prep_stale = 1;   /* prepared when read (model_prep) */
    memcpy(mc->pad_q, q, sizeof mc->pad_q);
}

void model_prep_refresh(exdex_model *mc)
{
    exdex_friction_prep prep;
    double e[3] = {1.0, 1.0, mc->e[2]};
    /* a problem the prepare refuses (not seen with a valid inertia) keeps
     * the last pose's */
    if (model_pads_prepare(mc, mc->pc, e, &prep) == EXDEX_OK) mc->prep = prep;
    mc->prep_stale = 0;
}

/* The regions of the two containments (the pad in the face, the face in
 * the pad) and the friction problem of the face inside the pad. */
static void pads_precompute(exdex_model *m)
{
    const double zero[2] = {0.0, 0.0};
    pads_shape f;
    /* the pad inside a face large enough: the pad itself */
    if (m->pad.n) {
        pads_poly_props((const double (*)[2])m->pad.v, m->pad.n, &m->pad_in_area, m->pad_in_c, &m->pad_in_er);
    } else {
        m->pad_in_area = EXDEX_PI * m->pad.r * m->pad.r;
        m->pad_in_c[0] = m->pad.c[0];
        m->pad_in_c[1] = m->pad.c[1];
        m->pad_in_er = exdex_er_disc(m->pad.r);
    }
    /* the face at the identity pose, intersected with itself: the face */
    face_at(m, zero, 0.0, &f);
    if (f.n) {
        pads_poly_props((const double (*)[2])f.v, f.n, &m->face_in_area, m->face_in_c, &m->face_in_er);
    } else {
        m->face_in_area = EXDEX_PI * f.r * f.r;
        m->face_in_c[0] = f.c[0];
        m->face_in_c[1] = f.c[1];
        m->face_in_er = exdex_er_disc(f.r);
    }
    if (m->ls_exact) {
        /* the exact surfaces of the two containments, each about its
         * centroid: the face's (in C) and the pad's bounds (in B) */
        region rg;
        limitsurf ls;
        for (int k = 0; k < 2; k++) {
            const pads_shape *s = k ? &m->pad : &f;
            const double *c = k ? m->pad_in_c : m->face_in_c;
            memset(&rg, 0, sizeof rg);
            if (s->n) {
                rg.kind = REGION_POLYGON;
                rg.n = s->n;
                for (int i = 0; i < s->n; i++) {
                    rg.v[i][0] = s->v[i][0] - c[0];
                    rg.v[i][1] = s->v[i][1] - c[1];
                }
            } else {
                region_set_disc(&rg, s->c[0] - c[0], s->c[1] - c[1], s->r);
            }
            if (limitsurf_set_exact(&ls, &rg) != EXDEX_OK) {
                /* not a region.c region (none that check_pads passes): no
                 * bounds, and the face's containment path is not taken */
                memset(&ls, 0, sizeof ls);
                ls.kmax = INFINITY;
            } else {
                limitsurf_prepare_bounds(&ls);
            }
            if (k) {
                m->pad_kmin = ls.kmin;
                m->pad_kmax = ls.kmax;
            } else {
                m->face_ls = ls;
            }
        }
    }
    m->face_prep_ok = 0;
    if (m->ndof == 3 && m->face_in_area > 0.0 && m->face_in_er > 0.0) {
        exdex_model t = *m;
        double W[9], e[3] = {1.0, 1.0, m->face_in_er};
        t.pc[0] = m->face_in_c[0];
        t.pc[1] = m->face_in_c[1];
        patch_delassus(&t, W);
        m->face_prep_ok = exdex_friction_prepare(&m->face_prep, W, e) == EXDEX_OK;
    }
}

const exdex_model *model_pads_follow(const exdex_model *m, exdex_model *copy)
{
    if (!m->pads || m == copy) return m;
    if (copy->pad_src == m && copy->pads) {
        /* a model is read-only but for a stepper's copy, which sets only its
         * grip (grip_n, capF, capS, def.grip_force) and motion between
         * steps: those are refreshed, the contact fields kept */
        copy->grip_n = m->grip_n;
        copy->capF = m->capF;
        copy->capS = m->capS;
        copy->def.grip_force = m->def.grip_force;
        copy->motion = m->motion;
    } else {
        *copy = *m;
    }
    copy->pad_src = m;
    return copy;
}

int model_pads_patch_region(const exdex_model *m, const double q[3], struct region *rg, double pc[2])
{
    pads_region r;
    if (!m->pads) return EXDEX_EINVAL;
    model_pads_region(m, q, q[2], &r);
    return pads_patch_region(m, &r, q, rg, pc);
}

int model_pads_lost(const exdex_model *m, const double *q)
{
    pads_region rg;
    pads_shape f;
    double r[3], th;
    if (!m->pads) return 0;
    pose_com(m, q, r, &th);
    face_at(m, r, th, &f);
    if (pads_containment(m, &f)) return 0;   /* the pad or the face whole */
    pads_intersect(&m->pad, &f, &rg);
    return !(rg.area > EXDEX_PAD_LOST * m->pad_area0);
}

int exdex_pad_region(const exdex_scene_def *def, const double q[3], double *area, double c[2], double *er,
                     double *radius, double (*verts)[2], int nmax, int *nv)
{
    exdex_model m;
    pads_region rg;
    if (!def || !q || !ex_finite_n(q, 3) || !(def->pad_n > 0 || def->pad_radius > 0.0)) return EXDEX_EINVAL;
    memset(&m, 0, sizeof m);
    if (check_pads(def, &m.pad, &m.face, NULL)) return EXDEX_EINVAL;
    model_pads_region(&m, q, q[2], &rg);
    if (area) *area = rg.area;
    if (c) {
        c[0] = rg.c[0];
        c[1] = rg.c[1];
    }
    if (er) *er = rg.er;
    if (radius) *radius = rg.disc ? rg.r : 0.0;
    if (nv) {
        int n = rg.n < nmax ? rg.n : nmax;
        *nv = verts ? n : 0;
        for (int i = 0; verts && i < n; i++) {
            verts[i][0] = rg.v[i][0];
            verts[i][1] = rg.v[i][1];
        }
    }
    return EXDEX_OK;
}

/* ------------------------------------------------------------ scales */

/* The relative factors of the thresholds (model_tols): tolerances.h. */

static void model_set_scales(exdex_model *m)
{
    model_scales *s = &m->scale;
    double A = fmax(sqrt(ex_dot3(m->g, m->g)), m->capF / m->m), v0 = hypot(m->def.v0[0], m->def.v0[1]);
    s->L = m->e[2];
    s->L = fmax(s->L, hypot(m->pc[0], m->pc[1]));
    for (int j = 0; j < m->n_vert; j++) s->L = fmax(s->L, hypot(m->vert[j][0], m->vert[j][1]) + m->disc_r);
    if (A > 0.0 && isfinite(A))
        s->T = sqrt(s->L / A);
    else if (m->def.motion.kind != EXDEX_MOTION_REST)
        s->T = m->def.motion.duration;
    else if (v0 > 0.0)
        s->T = s->L / v0;
    else if (m->def.v0[2] != 0.0)
        s->T = 1.0 / fabs(m->def.v0[2]);
    else
        s->T = 1.0;
    if (!(s->T > 0.0 && isfinite(s->T))) s->T = 1.0;
    s->V = s->L / s->T;
    s->F = m->m * s->L / (s->T * s->T);
    s->q = m->ndof == 1 && m->def.dof == EXDEX_DOF_ROTATION ? 1.0 : s->L;
    m->tol.touch = TOUCH_REL * s->L;
    m->tol.pen = PEN_REL * s->L;
    m->tol.start_gap = START_GAP_REL * s->L;
    m->tol.rest_gap = REST_GAP_REL * s->L;
    m->tol.rate = RATE_REL * s->V;
    m->tol.vzero = VZERO_REL * s->q / s->T;
    m->tol.fq_min = FQ_MIN_REL * s->L / s->q;
    m->tol.root = ROOT_REL * s->T;
    m->tol.h0 = H0_REL * s->T;
}

/* ------------------------------------------------------------ model */

void exdex_model_free(exdex_model *m)
{
    if (!m) return;
    exdex_motion_free(m->motion);
    if (m->grip_interp) gsl_interp_free(m->grip_interp);
    free(m->grip_t);
    free(m->grip_f);
    free(m->sw_t);
    free(m);
}

/* ------------------------------------------------- grip-force schedule */

/* The schedule of def (validated) into m: a schedule whose forces are all
 * equal (one point included) is that constant force; else owned copies of
 * the points with the forces scaled by grip_force, and the GSL interpolant
 * (linear; cubic: Steffen through 3 or more points, linear through 2). */
static int grip_setup(exdex_model *m, const exdex_scene_def *def)
{
    size_t n = def->grip_n;
    int flat = 1;
    double fmax = 0.0;
    m->def.grip_times = m->def.grip_forces = NULL;
    m->capk = def->mu * def->fingers;
    if (!n) return EXDEX_OK;
    for (size_t i = 1; i < n; i++)
        if (def->grip_forces[i] != def->grip_forces[0]) flat = 0;
    if (flat) {
        m->def.grip_force = def->grip_force * def->grip_forces[0];
        m->def.grip_n = 0;
        m->capF = def->mu * def->fingers * m->def.grip_force;
        return EXDEX_OK;
    }
    m->grip_t = malloc(n * sizeof *m->grip_t);
    m->grip_f = malloc(n * sizeof *m->grip_f);
    if (!m->grip_t || !m->grip_f) return EXDEX_ENOMEM;
    for (size_t i = 0; i < n; i++) {
        m->grip_t[i] = def->grip_times[i];
        m->grip_f[i] = def->grip_force * def->grip_forces[i];
        fmax = fmax > m->grip_f[i] ? fmax : m->grip_f[i];
    }
    m->grip_n = n;
    m->grip_kind = def->grip_kind;
    if (def->grip_kind != EXDEX_GRIP_STEP) {
        const gsl_interp_type *T = def->grip_kind == EXDEX_GRIP_CUBIC && n >= 3 ? gsl_interp_steffen : gsl_interp_linear;
        m->grip_interp = gsl_interp_alloc(T, n);
        if (!m->grip_interp) return EXDEX_ENOMEM;
        if (gsl_interp_init(m->grip_interp, m->grip_t, m->grip_f, n) != GSL_SUCCESS) return EXDEX_EINVAL;
    }
    m->capF = m->capk * fmax;
    return EXDEX_OK;
}

/* m->sw_t: the motion's switching and jump times and the schedule's
 * breakpoints, sorted (repeats kept: the whole-step test only asks whether
 * one lies in an interval). */
static int switch_list(exdex_model *m)
{
    double sw[EXDEX_MOTION_MAX_SWITCHES], tj[EXDEX_MOTION_MAX_JUMPS];
    int ns = exdex_motion_switches(m->motion, sw), nj = exdex_motion_jumps(m->motion, tj, NULL, NULL);
    size_t n = (size_t)ns + (size_t)nj + m->grip_n, k = 0;
    m->sw_motion = m->motion;
    m->sw_n = 0;
    if (!n) return EXDEX_OK;
    m->sw_t = malloc(n * sizeof *m->sw_t);
    if (!m->sw_t) return EXDEX_ENOMEM;
    for (int i = 0; i < ns; i++) m->sw_t[k++] = sw[i];
    for (int i = 0; i < nj; i++) m->sw_t[k++] = tj[i];
    for (size_t i = 0; i < m->grip_n; i++) m->sw_t[k++] = m->grip_t[i];
    gsl_sort(m->sw_t, 1, n);
    m->sw_n = n;
    return EXDEX_OK;
}

/* Index i of the piece [t_i, t_{i+1}) holding t, t inside [t_0, t_{n-1})
 * (bisection, as gsl_interp_bsearch, inlined: every step of a
 * time-stepping method calls it). */
static size_t grip_piece(const exdex_model *m, double t)
{
    size_t lo = 0, hi = m->grip_n - 1;
    const double *x = m->grip_t;
    while (hi > lo + 1) {
        size_t k = (lo + hi) / 2;
        if (x[k] > t)
            hi = k;
        else
            lo = k;
    }
    return lo;
}

/* F at t inside piece i of the linear kind: a convex combination of the
 * piece's end values (between them whatever the spacing). */
static double grip_linear(const exdex_model *m, size_t i, double t)
{
    double a = m->grip_f[i], b = m->grip_f[i + 1];
    return a + (b - a) * ((t - m->grip_t[i]) / (m->grip_t[i + 1] - m->grip_t[i]));
}

double model_grip_sched(const exdex_model *m, double t)
{
    size_t n = m->grip_n;
    if (!(t > m->grip_t[0])) return m->grip_f[0];
    if (t >= m->grip_t[n - 1]) return m->grip_f[n - 1];
    {
        size_t i = grip_piece(m, t);
        double a = m->grip_f[i], b = m->grip_f[i + 1], F;
        if (m->grip_kind == EXDEX_GRIP_STEP) return a;
        if (m->grip_kind == EXDEX_GRIP_LINEAR || !m->grip_interp) return grip_linear(m, i, t);
        F = gsl_interp_eval(m->grip_interp, m->grip_t, m->grip_f, t, NULL);
        /* Steffen's cubic is monotone on each piece: between a and b up to rounding */
        return fmin(fmax(F, fmin(a, b)), fmax(a, b));
    }
}

double model_grip_sched_rate(const exdex_model *m, double t)
{
    size_t n = m->grip_n;
    if (!(t >= m->grip_t[0]) || t >= m->grip_t[n - 1] || !m->grip_interp) return 0.0;
    return gsl_interp_eval_deriv(m->grip_interp, m->grip_t, m->grip_f, t, NULL);
}

/* Integral of F over [a, b] (a <= b) inside [t_0, t_{n-1}]. */
static double grip_integral_in(const exdex_model *m, double a, double b)
{
    double s = 0.0;
    size_t i;
    if (!(b > a)) return 0.0;
    if (m->grip_interp) return gsl_interp_eval_integ(m->grip_interp, m->grip_t, m->grip_f, a, b, NULL);
    for (i = grip_piece(m, a); i + 1 < m->grip_n && m->grip_t[i] < b; i++)
        s += m->grip_f[i] * (fmin(b, m->grip_t[i + 1]) - fmax(a, m->grip_t[i]));
    return s;
}

double model_grip_sched_mean(const exdex_model *m, double t0, double t1)
{
    size_t n = m->grip_n;
    double lo = m->grip_t[0], hi = m->grip_t[n - 1], s;
    if (t1 <= lo) return m->grip_f[0];
    if (t0 >= hi) return m->grip_f[n - 1];
    if (t0 >= lo && t1 <= hi && m->grip_kind != EXDEX_GRIP_CUBIC) {
        size_t i = grip_piece(m, t0);
        /* inside one linear or constant piece: the midpoint value is the mean */
        if (t1 <= m->grip_t[i + 1])
            return m->grip_kind == EXDEX_GRIP_STEP || !m->grip_interp ? m->grip_f[i]
                                                                      : grip_linear(m, i, 0.5 * (t0 + t1));
    }
    s = 0.0;
    if (t0 < lo) s += m->grip_f[0] * (lo - t0);
    if (t1 > hi) s += m->grip_f[n - 1] * (t1 - hi);
    s += grip_integral_in(m, fmax(t0, lo), fmin(t1, hi));
    return s / (t1 - t0);
}

size_t model_grip_breaks(const exdex_model *m, double t_end, double *ts)
{
    size_t k = 0;
    for (size_t i = 0; i < m->grip_n; i++)
        if (m->grip_t[i] > 0.0 && m->grip_t[i] <= t_end) ts[k++] = m->grip_t[i];
    return k;
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
    st = grip_setup(m, def);
    if (st) {
        exdex_model_free(m);
        *status = st;
        if (bad_param && st == EXDEX_EINVAL) *bad_param = "grip_times";
        return NULL;
    }
    st = switch_list(m);
    if (st) {
        exdex_model_free(m);
        *status = st;
        return NULL;
    }
    /* static capacity: the kinetic one times mu_static / mu (per unit grip
     * force capks, so that it follows a grip schedule as the kinetic one
     * does); with mu = 0 the ratio is undefined and mu_static fingers is
     * stored itself */
    m->cap_ratio = 1.0;
    m->capks = m->capk;
    m->capS = m->capF;
    if (def->mu_static != 0.0 && def->mu_static != def->mu) {
        if (def->mu > 0.0) {
            m->cap_ratio = def->mu_static / def->mu;
            m->capks = m->capk * m->cap_ratio;
            m->capS = m->capF * m->cap_ratio;
        } else {
            double fmax = m->def.grip_force;
            if (m->grip_n) {
                fmax = 0.0;
                for (size_t i = 0; i < m->grip_n; i++) fmax = fmax > m->grip_f[i] ? fmax : m->grip_f[i];
            }
            m->capks = def->mu_static * def->fingers;
            m->capS = m->capks * fmax;
        }
    }
    m->e[0] = m->e[1] = 1.0;
    m->e[2] = def->e_r;
    if (def->limit_surface == EXDEX_LS_EXACT && !(def->pad_n > 0 || def->pad_radius > 0.0)) {
        region rg;
        model_region(def, &rg);  /* checked by check_fields */
        limitsurf_set_exact(&m->ls, &rg);
        limitsurf_prepare_bounds(&m->ls);
        m->ls_exact = 1;
        m->e[2] = m->ls.e[2];
    } else {
        limitsurf_set_ellipsoid(&m->ls, def->e_r);
    }
    m->pc[0] = def->patch_center[0];
    m->pc[1] = def->patch_center[1];
    if (def->pad_n > 0 || def->pad_radius > 0.0) {
        /* pads on the fingers: the region at the start in place of the patch */
        pads_region rg;
        check_pads(def, &m->pad, &m->face, NULL);
        m->pads = 1;
        model_pads_region(m, def->q0, def->q0[2], &rg);
        if (!(rg.area > 0.0 && rg.er > 0.0)) {
            exdex_model_free(m);
            *status = EXDEX_EINVAL;
            if (bad_param) *bad_param = "pad";
            return NULL;
        }
        m->pad_area0 = rg.area;
        pads_local_center(rg.c, def->q0, def->q0[2], m->pc);
        m->e[2] = rg.er;
        memcpy(m->pad_q, def->q0, sizeof m->pad_q);
        if (def->limit_surface == EXDEX_LS_EXACT) {
            /* the exact surface of the region at the start, about its centroid */
            region prg;
            double pc[2];
            if (pads_patch_region(m, &rg, def->q0, &prg, pc) != EXDEX_OK ||
                limitsurf_set_exact(&m->ls, &prg) != EXDEX_OK) {
                exdex_model_free(m);
                *status = EXDEX_EINVAL;
                if (bad_param) *bad_param = "pad";
                return NULL;
            }
            limitsurf_prepare_bounds(&m->ls);
            m->ls_exact = 1;
            m->e[2] = m->ls.e[2];
        }
    }
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
        double W[9];
        patch_delassus(m, W);
        st = exdex_friction_prepare(&m->prep, W, m->e);
        if (st) {
            exdex_model_free(m);
            *status = st;
            if (bad_param) *bad_param = "inertia";
            return NULL;
        }
    }
    if (m->pads) pads_precompute(m);
    m->n_stops = def->n_stops;
    for (int k = 0; k < def->n_stops; k++) {
        memcpy(m->sp[k], def->stop_point[k], sizeof m->sp[k]);
        memcpy(m->sn[k], def->stop_normal[k], sizeof m->sn[k]);
        m->smu[k] = def->stop_mu[k];
        m->stop_friction |= def->stop_mu[k] > 0.0;
    }
    m->n_vert = def->n_vertices;
    memcpy(m->vert, def->vertices, sizeof m->vert);
    if (def->disc_radius > 0.0) {
        /* the disc's centre is its one vertex; contact.c adds the radius */
        m->n_vert = 1;
        m->vert[0][0] = def->disc_center[0];
        m->vert[0][1] = def->disc_center[1];
        m->disc_r = def->disc_radius;
    }
    m->n_obst = def->n_obstacles;
    m->n_src = m->n_stops + m->n_obst;
    for (int o = 0; o < m->n_obst; o++) m->stop_friction |= def->obstacles[o].mu > 0.0;
    m->n_hull = contact_hull((const double (*)[2])m->vert, m->n_vert, m->hull);
    if (m->n_obst && m->n_stops * contact_nv(m) + contact_obstacle_max_rows(m) > MAX_ROWS) {
        exdex_model_free(m);
        *status = EXDEX_EINVAL;
        if (bad_param) *bad_param = "obstacles (more contact rows than the core holds)";
        return NULL;
    }
    model_set_scales(m);
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
                if (contact_vertex_gap(m, &kin, k, q, j, NULL) < -m->tol.start_gap) st = EXDEX_EINVAL;
        if (st) {
            exdex_model_free(m);
            *status = st;
            if (bad_param) *bad_param = "q0 (the object starts beyond a stop)";
            return NULL;
        }
    }
    /* nor inside an obstacle */
    if (m->n_obst) {
        exdex_kinematics kin;
        double q[3], G[MAX_ROWS][3], g[MAX_ROWS], rnd[MAX_ROWS];
        if (m->ndof == 3) {
            memcpy(q, def->q0, sizeof q);
        } else {
            q[0] = def->dof == EXDEX_DOF_TRANSLATION ? m->s0 : m->th0;
        }
        st = exdex_motion_eval(m->motion, 0.0, &kin);
        if (!st) {
            int no = contact_obstacle_rows(m, &kin, q, G, g, rnd, NULL, NULL);
            for (int i = 0; i < no; i++)
                if (g[i] < -m->tol.start_gap) st = EXDEX_EINVAL;
        }
        if (st) {
            exdex_model_free(m);
            *status = st;
            if (bad_param) *bad_param = "q0 (the object starts inside an obstacle)";
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
int exdex_model_nstops(const exdex_model *m) { return m ? m->n_src : 0; }

int exdex_model_grip(const exdex_model *m, double t, double *force, double *rate)
{
    if (!m || isnan(t)) return EXDEX_EINVAL;
    if (force) *force = model_grip_force(m, t);
    if (rate) *rate = m->grip_n ? model_grip_sched_rate(m, t) : 0.0;
    return EXDEX_OK;
}

/* The plate friction wrench that holds the object at rest relative to the
 * gripper at time t and coordinates q, in B at the centre of pressure (the
 * output's wrench rows): the static balance -F of gravity and the inertial
 * forces at zero relative velocity, where it lies inside the static limit
 * surface. Returns 1 with w set where it does, 0 where the object slips at
 * once, or where the scene has stops or obstacles (their share of the load
 * is not unique), w then zero. */
int model_holding_wrench(const exdex_model *m, double t, const double *q, double w[3])
{
    frame f;
    exdex_kinematics kin;
    double Cs;
    w[0] = w[1] = w[2] = 0.0;
    if (m->n_src || model_frame_at(m, t, &f, &kin)) return 0;
    Cs = model_capacity_static(m, t);
    if (m->ndof == 1) {
        int tr = m->def.dof == EXDEX_DOF_TRANSLATION;
        double Q = model_force_1dof(m, &f, q[0], 0.0);
        /* the capacity along the coordinate: Cs for a slide, Cs e_r for a
         * spin at the centre of pressure (as the implicit step's) */
        if (!(fabs(Q) <= (tr ? Cs : Cs * m->e[2]))) return 0;
        if (tr) {
            w[0] = -Q * m->d[0];
            w[1] = -Q * m->d[1];
        } else {
            w[2] = -Q;
        }
        return 1;
    } else {
        double F[3], P[3], b[3], v0[3] = {0.0, 0.0, 0.0};
        model_force_planar(m, &f, q, v0, F);
        for (int i = 0; i < 3; i++) P[i] = -F[i];
        model_patch_of_gen(m, MODEL_CS(q[2]), P, b);
        if (!(model_ls_gauge(m, b) <= Cs)) return 0;
        model_to_b(MODEL_CS(q[2]), b, w);
        return 1;
    }
}
