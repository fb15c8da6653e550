/* model.h -- private to the exdex core: the immutable model a scene
 * definition compiles to, the kinematics of the moving gripper frame, the
 * paper's Eqs. 3-5 (gravity and inertial force and torque on the object in
 * B) and the maps between the generalised coordinates and the friction
 * patch. Everything here is read-only after exdex_model_alloc: every method
 * keeps its mutable state in its own workspace. Not installed, no Python. */
#ifndef EXDEX_MODEL_H
#define EXDEX_MODEL_H

#include <math.h>

#include <gsl/gsl_interp.h>

#include "exdex.h"
#include "limitsurf.h"
#include "pads.h"
#include "tolerances.h"
#include "util.h"

#define MAX_ROWS (EXDEX_MAX_STOPS * EXDEX_MAX_VERTICES)

/* The scene's own scales. Every threshold of a contact or rounding decision
 * is a fixed fraction of one of them (model_tols), so a scene whose
 * lengths, times or masses are all scaled by the same factors gives results
 * scaled by those factors (the physics has no length, time or mass of its
 * own). */
typedef struct model_scales {
    double L;   /* length [m]: the largest of e_r, |patch centre| and |outline vertex| (> 0) */
    double T;   /* time [s]: sqrt(L / A) with the acceleration scale A = max(|g|, mu N / m);
                   without one, the motion's duration, else L / |v0|, else 1 */
    double V;   /* velocity L / T [m/s] */
    double F;   /* force m L / T^2 [N] */
    double q;   /* unit of the 1-DoF coordinate: L (translation) or 1 (rotation, rad) */
} model_scales;

/* Thresholds of the decisions, in the scene's units (model_alloc sets them
 * from the scales with the relative factors in model.c). */
typedef struct model_tols {
    double touch;      /* a stop gap below this counts as contact [m] */
    double pen;        /* a stop gap below -pen after a step counts a warning [m] */
    double start_gap;  /* an outline vertex starting below -start_gap is beyond its stop [m] */
    double rest_gap;   /* planar rest against stops ends when a set row's |gap| exceeds this [m] */
    double rate;       /* a gap rate below this counts as 0 [m/s] */
    double vzero;      /* a 1-DoF |qd| below this counts as 0 [m/s or rad/s] */
    double fq_min;     /* a 1-DoF stop row with |d gap / dq| below this cannot act [1 or m] */
    double root;       /* event time resolution [s] */
    double h0;         /* first step of the adaptive integrators [s] */
} model_tols;

struct exdex_model {
    exdex_scene_def def;    /* copy of the definition (sampled arrays owned by motion) */
    exdex_motion *motion;
    int ndof;
    double m;               /* mass */
    double I[9];            /* inertia in C */
    double izz;
    double capF;            /* friction capacity mu * fingers * grip_force [N] (a schedule: its
                               largest value; read the capacity with model_capacity) */
    double e[3];            /* (1, 1, e_r); the exact surface: e_r its mean distance (limitsurf.h) */
    limitsurf ls;           /* the limit surface per unit capacity (the ellipsoid of e, or the
                               exact surface of the region in patch coordinates) */
    int ls_exact;           /* 1: ls is the exact surface */
    double pc[2];           /* centre of pressure in C */
    double g[3];            /* gravity in A */
    /* translation */
    double d[2];            /* unit slide axis in B */
    double r0[2];           /* initial centre of mass in B */
    double s0;              /* d . r0 */
    double th0;
    /* rotation about the pivot (centre of pressure, fixed in B) */
    double pivot[2];
    double c[2];            /* centre of mass relative to the pivot, in C */
    double mrot;            /* generalized mass izz + m |c|^2 */
    /* planar: friction problem in object-frame patch coordinates (constant) */
    exdex_friction_prep prep;
    double minv[3];         /* diagonal of M^-1 */
    /* stops */
    int n_stops;
    double sp[EXDEX_MAX_STOPS][3], sn[EXDEX_MAX_STOPS][3];
    int n_vert;
    double vert[EXDEX_MAX_VERTICES][2];
    model_scales scale;
    model_tols tol;
    /* grip-force schedule (exdex_scene_def.grip_n): read it only through
     * model_grip_force / model_capacity and friends below. grip_n = 0 for a
     * constant grip force, also for a schedule whose forces are all equal
     * (it is that constant: def.grip_force is then the scaled force and
     * capF its capacity). Otherwise grip_t, grip_f are owned copies of the
     * points, the forces scaled by def.grip_force, and capF is the largest
     * capacity of the schedule (the scales use it). */
    size_t grip_n;
    int grip_kind;          /* enum exdex_grip_kind */
    double *grip_t, *grip_f;
    gsl_interp *grip_interp;  /* linear and cubic kinds (NULL for step); evaluated without an
                                 accelerator, so concurrent reads are safe */
    double capk;            /* mu * fingers: capacity per unit grip force */
    /* static friction (exdex_scene_def.mu_static): the static capacity is
     * the kinetic one times cap_ratio = mu_static / mu (exactly 1, and the
     * static capacity the kinetic one bit for bit, when they are equal):
     * capks = capk cap_ratio per unit grip force, capS = capF cap_ratio the
     * largest. With mu = 0 the ratio is undefined (1) and capks = mu_static
     * fingers is set itself. Read it with model_capacity_static. */
    double cap_ratio;
    double capks;
    double capS;
    /* convex obstacles (def.obstacles): their rows follow the stops' */
    int n_obst;
    int n_src;              /* n_stops + n_obst: the stop_force columns */
    int n_hull;             /* convex hull of the outline (C, counter-clockwise) */
    double hull[EXDEX_MAX_VERTICES][2];
    double smu[EXDEX_MAX_STOPS];  /* Coulomb coefficient of each stop */
    int stop_friction;            /* 1 if some stop has smu > 0 */
    /* disc outline (def.disc_radius > 0): n_vert = 1 with vert[0] the disc
     * centre, and disc_r its radius; 0 for a polygon outline */
    double disc_r;
    /* every time at which the scene's motion (the one allocated for the
     * model, sw_motion) switches or jumps, and the grip schedule's
     * breakpoints: increasing, owned (model_substep's whole-step test) */
    const exdex_motion *sw_motion;
    size_t sw_n;
    double *sw_t;
    /* pads on the fingers (def.pad_n > 0 or def.pad_radius > 0): pad (in
     * B) and face (in C, a ccw polygon or a disc); pc, e[2] and prep then
     * hold the contact region at the pose pad_q (planar) or at the start
     * (1-DoF). A model is read-only: a method that follows the region keeps
     * its own copy of the model (model_pads_follow) and sets it with
     * model_pads_set. */
    int pads;
    pads_shape pad, face;
    double pad_q[3];
    double pad_area0;   /* the region's area at the start */
    const exdex_model *pad_src;  /* a copy (model_pads_follow): the model it copies */
    /* the regions of the two containments, computed once: the pad inside the
     * face (pad_in: its area, centroid in B, e_r) and the face inside the pad
     * (face_in: centroid in C, and face_prep the friction problem there) */
    double pad_in_area, pad_in_c[2], pad_in_er;
    double face_in_area, face_in_c[2], face_in_er;
    exdex_friction_prep face_prep;
    int face_prep_ok;
    /* the exact surface with pads (ls_exact): ls follows the region
     * (model_pads_set); face_ls is the face's (the face inside the pad), and
     * pad_kmin, pad_kmax the bounds of the pad's (the pad inside the face;
     * a turn of the region leaves them) */
    limitsurf face_ls;
    double pad_kmin, pad_kmax;
    /* prep is not yet that of pc and e (model_pads_set defers it: most of a
     * run's poses never read it); read prep through model_prep */
    int prep_stale;
};

/* ------------------------------------------------ grip force, capacity
 * The friction capacity C(t) = mu fingers F(t) [N], F the normal force of
 * each finger: constant (capF) or the schedule. Every method reads the
 * capacity through these; with a constant grip force they return capF
 * itself, bit for bit. */

/* The schedule's force F(t) (grip_n > 0), its rate dF/dt (right derivative
 * at a breakpoint; 0 outside the points and for the step kind) and its mean
 * over [t0, t1] (t0 < t1): the exact integral over the interval divided by
 * its length, or, inside one linear or constant piece, the value at the
 * midpoint (the same mean, and a flat piece gives its value exactly). */
double model_grip_sched(const exdex_model *m, double t);
double model_grip_sched_rate(const exdex_model *m, double t);
double model_grip_sched_mean(const exdex_model *m, double t0, double t1);

/* Normal force of each finger at t [N]. */
static inline double model_grip_force(const exdex_model *m, double t)
{
    return m->grip_n ? model_grip_sched(m, t) : m->def.grip_force;
}
/* Friction capacity C(t) = mu fingers F(t) [N]. */
static inline double model_capacity(const exdex_model *m, double t)
{
    return m->grip_n ? m->capk * model_grip_sched(m, t) : m->capF;
}
/* dC/dt [N/s] (0 for a constant grip force). */
static inline double model_capacity_rate(const exdex_model *m, double t)
{
    return m->grip_n ? m->capk * model_grip_sched_rate(m, t) : 0.0;
}
/* Mean capacity over the step [t0, t1] (t0 < t1) [N]: h times it is the
 * largest friction impulse the plates can carry over the step (the bound of
 * the time-stepping methods). capF for a constant grip force. */
static inline double model_capacity_mean(const exdex_model *m, double t0, double t1)
{
    return m->grip_n ? m->capk * model_grip_sched_mean(m, t0, t1) : m->capF;
}
/* Static friction capacity C_s(t) = mu_static fingers F(t) >= C(t) [N]
 * (model_capacity itself, bit for bit, when mu_static = mu). */
static inline double model_capacity_static(const exdex_model *m, double t)
{
    return m->grip_n ? m->capks * model_grip_sched(m, t) : m->capS;
}
/* Its mean over the step [t0, t1] (t0 < t1) [N], as model_capacity_mean. */
static inline double model_capacity_static_mean(const exdex_model *m, double t0, double t1)
{
    return m->grip_n ? m->capks * model_grip_sched_mean(m, t0, t1) : m->capS;
}
/* The schedule's breakpoints in (0, t_end] (where F or its derivatives may
 * be discontinuous), increasing, into ts (up to m->grip_n of them); returns
 * their number (0 for a constant grip force). The event and regularised
 * methods step onto them as onto the motion's switching times. */
size_t model_grip_breaks(const exdex_model *m, double t_end, double *ts);

/* Per-step quantities of the moving frame, in B coordinates: gravity g_B,
 * acceleration of B's origin a0, angular velocity w, angular acceleration dw. */
typedef struct frame {
    double gB[3], a0[3], w[3], dw[3];
} frame;

/* Coulomb coefficient of the contact rows of source k (a stop index, or
 * n_stops + an obstacle index; 0 for a source without friction data). */
static inline double model_source_mu(const exdex_model *m, int k)
{
    if (k >= m->n_stops && k < m->n_src) return m->def.obstacles[k - m->n_stops].mu;
    return k >= 0 && k < m->n_stops ? m->smu[k] : 0.0;
}

/* Initial coordinates q and velocities v of the scene (ndof entries each):
 * translation s0 = d . (x0, y0) and the velocity component along d; rotation
 * theta0 and omega0; planar the definition's q0, v0. */
void model_initial_state(const exdex_model *m, double *q, double *v);

/* ------------------------------------------------- frame kinematics */

/* Motion kinematics k at time t and the frame terms f in B coordinates. */
int model_frame_at(const exdex_model *m, double t, frame *f, exdex_kinematics *k);
/* Frame terms for the step from t (kinematics kin0) to t1 = t + h: the
 * kinematics and frame f at t_eval (position-dependent terms), kin_end at
 * t1, and the linear and angular accelerations replaced by their means over
 * the step, (v(t1) - v(t)) / h: exact in the mean when a motion switches
 * acceleration inside a step (Eq. 7 has jumps). */
int model_frame_step(const exdex_model *m, const exdex_kinematics *kin0, double t_eval, double t1, double h,
                     frame *f, exdex_kinematics *kin, exdex_kinematics *kin_end);

/* A motion over one step [t0, t1] given by its ends (motion.c; the
 * stepper's prescribed gripper pose): from the kinematics k0 at t0 (pose
 * R, p and twist v, w; its accelerations are not used) to the pose R1, p1
 * with the twist v1, w1 at t1 (A). The position and the quaternion of R
 * (n1 taken on n0's side, n1 . n0 >= 0) are each the cubic with these end
 * values and rates (n' = (1/2) (0, w) n), and the quaternion is normalised
 * (eval_log's kinematics): position, velocity, R and w continuous at the
 * step's ends, the accelerations of the cubic inside (linear in time for
 * the position), exact for a motion whose position is a cubic of time.
 * Evaluated outside [t0, t1] it extends the cubics. No switching times or
 * jumps. v1 = NULL takes the step's mean velocity (p1 - p0) / (t1 - t0),
 * w1 = NULL the constant angular velocity that turns R0 into R1 over the
 * step (the shorter way). k1 (may be NULL) receives R1, p1 and the end twist
 * used (accelerations 0). motion_step_alloc returns NULL when out of
 * memory; the motion starts at rest at the identity, and exdex_motion_free
 * frees it. motion_step_set returns EXDEX_EINVAL (the motion unchanged) for
 * t1 <= t0, a non-finite input or an R1 that is not a rotation matrix (to
 * 1e-9). */
exdex_motion *motion_step_alloc(void);
/* Over [ta, tb] (motion.c): 1 if B does not turn there (R constant, w = dw
 * = 0) and the acceleration of its origin (A) lies in the box [lo, hi]
 * componentwise, for rest, translating profiles and shakes, logs whose
 * orientation is constant, chains and time-shifted plays of them; 0 if not
 * known (lo, hi then not a bound). */
int motion_accel_box(const exdex_motion *m, double ta, double tb, double lo[3], double hi[3]);
/* The turning frame's quantities over [ta, tb] (motion.c): 1 if every
 * value model_frame_at gives for a time in [ta, tb] with the gravity g (A)
 * lies in fb (componentwise intervals of g_B, a0, w, dw, in B) for rest,
 * profiles and shakes (translating or turning about their axis), logs
 * (turning or not), chains and time-shifted plays of them; 0 if not known
 * (fb then not a bound). A log's box over [ta, tb] inside one knot
 * interval is that part's; across several, the hull of the whole
 * intervals it meets. */
typedef struct frame_box {
    ex_iv gB[3], a0[3], w[3], dw[3];
} frame_box;
int motion_frame_box(const exdex_motion *m, double ta, double tb, const double g[3], frame_box *fb);
/* The same box through a cache of the boxes of logs' whole knot intervals
 * (motion_frame_cache_new, for one gravity g; freed by
 * motion_frame_cache_free): each interval is enclosed once per cache, and
 * the result is motion_frame_box's, bit for bit. cache NULL, another g, or
 * no memory for it: computed directly. One cache serves one thread. */
typedef struct frame_box_cache frame_box_cache;
frame_box_cache *motion_frame_cache_new(const double g[3]);
void motion_frame_cache_free(frame_box_cache *c);
int motion_frame_box_cached(const exdex_motion *m, double ta, double tb, const double g[3], frame_box *fb,
                            frame_box_cache *cache);
int motion_step_set(exdex_motion *m, double t0, double t1, const exdex_kinematics *k0, const double R1[9],
                    const double p1[3], const double *v1, const double *w1, exdex_kinematics *k1);

/* --------------------------------------- paper Eqs. 3-5: applied forces */

/* Gravity + inertial force on the centre of mass at r moving at rd (Eq. 5),
 * B coordinates: m (g_B - a0 - dw x r - w x (w x r) - 2 w x rd). */
void model_force_lin(const exdex_model *m, const frame *f, const double r[3], const double rd[3], double F[3]);
/* Inertial torque about the plate normal on the body at angle th turning at
 * thd relative to B (Euler's equation, z-component, Eq. 4). */
double model_torque_z(const exdex_model *m, const frame *f, double th, double thd);
/* The same from cs = (cos th, sin th). */
double model_torque_z_cs(const exdex_model *m, const frame *f, const double cs[2], double thd);
/* 1-DoF generalised applied force Q(t, q, qd): Eq. 5 projected on the slide
 * axis (translation) or its moment about the pivot plus the inertial torque
 * (rotation). */
double model_force_1dof(const exdex_model *m, const frame *f, double q, double v);
/* Planar generalised applied force (B frame, (x, y, theta)). */
void model_force_planar(const exdex_model *m, const frame *f, const double *q, const double *v, double F[3]);
/* The same with cs = (cos q[2], sin q[2]) given. */
void model_force_planar_cs(const exdex_model *m, const frame *f, const double *q, const double *v,
                           const double cs[2], double F[3]);

/* A velocity jump of the gripper frame (exdex_motion_jumps: dv of B's
 * origin, dw, in A; R = R_AB, continuous there) applied to the relative
 * velocities v (ndof entries) of the object at coordinates q.
 *
 * Derivation. The object's absolute twist is V = V_B + J qd, V_B the
 * frame's twist at the object and J the twist per relative rate of the free
 * coordinates. Over the vanishing duration of the jump only impulsive forces
 * change momentum: friction is bounded by mu N (finite grip force) and
 * gravity is finite, so their impulses vanish. The ideal constraints may be
 * impulsive: the plates' normal force and tilt torques (the object stays in
 * the plate plane) and, in a rotation scene, the pin at the pivot (it moves
 * with B). Their reactions do no work on the motions the free coordinates
 * allow, J^T Lambda = 0, so the momentum balance M6 dV = Lambda projected
 * with J^T gives J^T M6 (dV_B + J dqd) = 0:
 *     dqd = -(J^T M6 J)^-1 J^T M6 dV_B,
 * minus the frame's jump at the object projected onto the free coordinates
 * in the mass metric. J^T M6 dV_B is minus the generalised inertial force of
 * Eq. 5 with the frame's accelerations replaced by its jumps (no gravity, no
 * velocity terms), which model_force_1dof / model_force_planar evaluate:
 * translation dsd = -d . (dv + dw x r) (r the centre of mass), rotation
 * dthd = -(m (e_z x rho) . (dv + dw x r) + [I_B dw]_z) / (I_zz + m |rho|^2)
 * (rho from the pivot to the centre of mass; the pin's impulse acts at the
 * pivot, which the rotation does not move), planar (dxd, dyd) = -(dv + dw x
 * r)_xy and dthd = -[I_B dw]_z / I_zz. With mu = 0 the object keeps its
 * absolute velocity along the free coordinates; with friction it then slips
 * until friction stops it.
 *
 * Every method applies this jump with this function, at the jump time
 * itself: the event and regularised methods step onto it (a switching time,
 * exdex_motion_switches), the implicit and explicit methods end a sub-step
 * there (model_substep below), so friction acts on the jumped relative
 * velocity only after it, over the following steps, and the slide the jump
 * starts carries the method's own first-order error in h. */
void model_velocity_jump(const exdex_model *m, const double R[9], const double *q, const double dv[3],
                         const double dw[3], double *v);

/* ------------------------------- sub-steps of the time-stepping methods
 * The implicit and explicit methods take an output step (t, t1] as
 * sub-steps ending at the scene's switching times strictly inside it: the
 * motion's (exdex_motion_switches: acceleration switches and velocity
 * jumps) and the grip schedule's breakpoints (model_grip_breaks; m's own
 * grip_n, so a stepper step with a constant grip force has none). Inside a
 * sub-step the frame's kinematics and the capacity are smooth, so its
 * step-mean accelerations and capacity carry no switch; a velocity jump is
 * applied between two sub-steps (model_velocity_jump), not spread over a
 * step as dv / h.
 *
 * "Strictly inside" is to within snap(x) = 1e-12 (|x| + T) (T the scene's
 * time scale) of a step end x: a switch that an output grid point i dt
 * meets to within rounding (dt chosen to land on it) does not split the
 * step, so such a run takes exactly the steps it takes without switches. A
 * velocity jump at tj belongs to the sub-step (tc, te] with
 * tc + snap(tc) < tj <= te + snap(te) and is applied at its end te: these
 * sets partition the time axis for any sequence of steps (the stepper's
 * steps of varying dt too), so every jump in (snap(0), t_end + snap(t_end)]
 * is applied exactly once, and one at the output time t_end is applied
 * before that sample is recorded (its right limit, as the event method
 * records). A jump at t = 0 is not applied (v0 is the velocity after it). */
typedef struct model_sub {
    double te;         /* end of the sub-step (tc < te <= t1) */
    int jumps;         /* number of velocity jumps applied at te */
    double dv[3], dw[3];    /* their sum (A coordinates) */
    double dvl[3], dwl[3];  /* the part with tj <= te, which exdex_motion_eval(te) holds */
    int split;         /* 1 if te < t1 (a switching time inside the step) */
} model_sub;
/* The sub-step from tc towards the step end t1 (tc < t1). */
void model_substep_full(const exdex_model *m, double tc, double t1, model_sub *s);
/* snap(x) above */
static inline double model_substep_snap(const exdex_model *m, double x)
{
    return 1e-12 * (fabs(x) + m->scale.T);
}
/* What model_substep has learnt of m->sw_t: none of its times lies in
 * (lo, next) (lo = INFINITY: nothing yet). A method's workspace keeps one
 * per run; it holds for the model whatever the time, so a restored state
 * may keep it. */
typedef struct model_sw_cache {
    double lo, next;
} model_sw_cache;
static inline void model_sw_cache_reset(model_sw_cache *c)
{
    c->lo = INFINITY;
    c->next = 0.0;
}
/* model_substep_full, with the common case first: the model's own motion
 * in use and none of its switching times (m->sw_t) in (tc + snap(tc),
 * t1 + snap(t1)], so the sub-step is the whole step, without jumps. */
static inline void model_substep(const exdex_model *m, model_sw_cache *c, double tc, double t1, model_sub *s)
{
    if (m->motion == m->sw_motion) {
        double lo = tc + model_substep_snap(m, tc), top = t1 + model_substep_snap(m, t1);
        if (!(lo >= c->lo && top < c->next)) {
            size_t a = 0, b = m->sw_n;
            while (a < b) {
                size_t mid = a + (b - a) / 2;
                if (m->sw_t[mid] > lo) b = mid;
                else a = mid + 1;
            }
            c->lo = lo;
            c->next = a < m->sw_n ? m->sw_t[a] : INFINITY;
        }
        if (top < c->next) {
            s->te = t1;
            s->split = 0;
            s->jumps = 0;
            return;
        }
    }
    model_substep_full(m, tc, t1, s);
}
/* model_frame_step for the sub-step from tc (kinematics kin0, the right
 * limit there) to s->te, h = s->te - tc: with jumps at te, kin_end is the
 * left limit at te (its velocities without the jumps), so the step-mean
 * accelerations are those of the smooth motion inside the sub-step.
 * Without jumps it is model_frame_step itself. */
int model_frame_substep_jumps(const exdex_model *m, const exdex_kinematics *kin0, double t_eval,
                              const model_sub *s, double h, frame *f, exdex_kinematics *kin,
                              exdex_kinematics *kin_end);
static inline int model_frame_substep(const exdex_model *m, const exdex_kinematics *kin0, double t_eval,
                                      const model_sub *s, double h, frame *f, exdex_kinematics *kin,
                                      exdex_kinematics *kin_end)
{
    if (!s->jumps) return model_frame_step(m, kin0, t_eval, s->te, h, f, kin, kin_end);
    return model_frame_substep_jumps(m, kin0, t_eval, s, h, f, kin, kin_end);
}
/* At the end of a sub-step with jumps: applies them to the relative
 * velocities v at coordinates q (model_velocity_jump, R of kin_end) and
 * turns kin_end into the right limit at te (the next sub-step's kin0). */
void model_substep_jump(const exdex_model *m, const model_sub *s, const double *q, double *v,
                        exdex_kinematics *kin_end);

/* ----------------------------------------------------- patch coordinates
 * The friction patch sits at the centre of pressure pc (object frame C). A
 * planar velocity v = (xd, yd, thd) in B has the patch slip twist
 *     u = J' Rz(-th) v,   J' = [[1, 0, -pc_y], [0, 1, pc_x], [0, 0, 1]]
 * (object frame, at the centre of pressure); a patch wrench (or impulse) w
 * has the generalised force P = Rz(th) J'^T w, and P the patch wrench
 * w = J'^-T Rz(-th) P. cs = (cos th, sin th); MODEL_CS(th) forms it. */
#define MODEL_CS(th) ((const double[2]){cos(th), sin(th)})

void model_patch_slip(const exdex_model *m, const double cs[2], const double v[3], double u[3]);
void model_gen_of_patch(const exdex_model *m, const double cs[2], const double w[3], double P[3]);
void model_patch_of_gen(const exdex_model *m, const double cs[2], const double P[3], double w[3]);
/* A plane force (f_x, f_y) of the object frame rotated into B, z kept. */
static inline void model_to_b(const double cs[2], const double w[3], double out[3])
{
    double x = cs[0] * w[0] - cs[1] * w[1], y = cs[1] * w[0] + cs[0] * w[1];
    out[0] = x;
    out[1] = y;
    out[2] = w[2];
}
/* The scene's contact region (region_kind, region_n, region_vertices,
 * region_radius) as a region in patch coordinates: EXDEX_OK if valid. */
int model_region(const exdex_scene_def *d, region *rg);

/* The gauge of a patch wrench per unit capacity (limitsurf.h): w is
 * carried at capacity C iff it is <= C. The ellipsoid's |E^-1 w|
 * (model_ell_norm itself, bit for bit), or the exact surface's (NaN if its
 * search fails: a comparison with it is then false). */
static inline double model_ell_norm(const exdex_model *m, const double w[3]);
static inline double model_ls_gauge(const exdex_model *m, const double w[3])
{
    double g;
    if (!m->ls_exact) return model_ell_norm(m, w);
    return limitsurf_gauge(&m->ls, w, &g, NULL) == EXDEX_OK ? g : NAN;
}
/* ------------------------------------------------------ pads on the fingers */

/* The contact region with the object's centre of mass at r (B) turned by th. */
void model_pads_region(const exdex_model *m, const double r[2], double th, pads_region *out);
/* The planar contact fields of a model copy mc (pads: pc, e[2], prep) set
 * to the region at the planar pose q (x, y, theta); nothing when q is the
 * pose they hold, or without pads. A region that has vanished (area at most
 * EXDEX_PAD_LOST times the start's) or whose prepare fails keeps the
 * fields of the last pose (the run stops at the next output sample, see
 * model_pads_lost). */
void model_pads_set(exdex_model *mc, const double q[3]);
/* The planar friction problem of the contact at the pose the model holds
 * (pads: prepared here on first reading after model_pads_set moved the
 * region; m is then the method's own copy). */
void model_prep_refresh(exdex_model *mc);
static inline const exdex_friction_prep *model_prep(const exdex_model *m)
{
    if (m->prep_stale) model_prep_refresh((exdex_model *)m);
    return &m->prep;
}
/* For a method's entry point: m itself without pads, else copy (a
 * method's own copy of the model, zeroed when the workspace was made)
 * refreshed from m, its contact fields kept when they came from m before
 * (they depend on the pose only). */
const exdex_model *model_pads_follow(const exdex_model *m, exdex_model *copy);
/* The planar friction problem of the patch at pc (C) with semi-axes e, as
 * exdex_friction_prepare(W = J' M^-1 J'^T, e) makes it, from the factor
 * J' M^-1/2 by an inline 3 x 3 one-sided Jacobi SVD (model.c); EXDEX_EINVAL
 * where that would refuse K. */
int model_pads_prepare(const exdex_model *m, const double pc[2], const double e[3], exdex_friction_prep *p);
/* The pads' contact region at the planar pose q as a region.c region in
 * patch coordinates (object frame C, relative to the region's centroid,
 * which it returns in pc, in C relative to the centre of mass): the input of
 * a limit surface of the current region. EXDEX_EINVAL for an empty one. */
struct region;   /* region.h */
int model_pads_patch_region(const exdex_model *m, const double q[3], struct region *rg, double pc[2]);
/* 1 if the pads' region at the coordinates q (ndof entries) has vanished. */
int model_pads_lost(const exdex_model *m, const double *q);

/* The plate friction wrench (in B at the centre of pressure) that holds the
 * object at rest at time t and coordinates q: 1 and w where the static
 * balance of gravity and the inertial forces lies inside the static limit
 * surface of a scene without stops or obstacles, else 0 and w zero
 * (model.c). */
int model_holding_wrench(const exdex_model *m, double t, const double *q, double w[3]);

/* An enclosure of the rotations of a plane vector set (certify.c): for
 * every u, the points Rz(-theta) u, theta in [th0, th1], lie in the
 * triangle of the points sc[k] Rz(-th[k]) u, k < the count returned: 1 for
 * th1 == th0 (th[0] = th0, sc[0] = 1), else 3 (the arc's ends, with
 * sc = 1, and the meeting point of its end tangents, at the middle angle
 * with sc = 1 / cos of the half span); 0 where the half span is not in
 * [0, half_max] (half_max < pi / 2) or not finite. */
int certify_arc_triangle(double th0, double th1, double half_max, double th[3], double sc[3]);
/* The load of a rotation or translation run in a turning gripper
 * (certify.c): 1 if the patch wrench the neglected coordinates need with no
 * stop force (the certificate's load) lies in b for every time in [ta, tb]
 * (the frame of motion_frame_box), angle (rotation) or slide coordinate
 * (translation) in th and rate in v (0 for a stuck state); 0 where not
 * known (a planar run, a motion without an enclosure). */
int certify_turning_load(const exdex_model *m, double ta, double tb, ex_iv th, ex_iv v, ex_iv b[3]);

/* exdex_certify of a run's windows (certify.c). A certify_run holds what
 * the windows of one run to t_end share (the frame boxes' cache, and the
 * piece proofs where they read no state of the run); NULL: no memory. In
 * certify_window, out holds samples of the run whose first skip (0, or
 * >= 2 and < out->n) are known to hold (skip 0: out starts at the run's
 * sample 0, the first window, and all of it is checked); the samples from
 * skip on are checked as exdex_certify checks them within the whole run
 * (the same first failure: every check reads its sample and the two
 * before it, and the proofs that skip samples only skip passing ones).
 * first_bad counts from out's sample 0. */
typedef struct certify_run certify_run;
certify_run *certify_run_new(const exdex_model *m, double t_end);
void certify_run_free(certify_run *r);
int certify_window(const exdex_model *m, const exdex_trajectory *out, size_t skip, certify_run *r,
                   exdex_certificate *c);

/* |E^-1 w|, the ellipsoid norm of a patch wrench (paper Eq. 6). */
static inline double model_ell_norm(const exdex_model *m, const double w[3])
{
    double a = w[0] / m->e[0], b = w[1] / m->e[1], c = w[2] / m->e[2];
    return sqrt(a * a + b * b + c * c);
}

#endif
