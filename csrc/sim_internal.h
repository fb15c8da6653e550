/* sim_internal.h -- private to the exdex core: the immutable model and the
 * dynamics terms shared by the time-stepping methods (sim.c: implicit;
 * other methods may live in their own files). Not installed, no Python. */
#ifndef EXDEX_SIM_INTERNAL_H
#define EXDEX_SIM_INTERNAL_H

#include <math.h>

#include "exdex.h"

#define MAX_ROWS (EXDEX_MAX_STOPS * EXDEX_MAX_VERTICES)
#define TOUCH 1e-10   /* a stop gap below this counts as contact [m] */

struct exdex_model {
    exdex_scene_def def;    /* copy of the definition (sampled arrays owned by motion) */
    exdex_motion *motion;
    int ndof;
    double m;               /* mass */
    double I[9];            /* inertia in C */
    double izz;
    double capF;            /* friction capacity mu * fingers * grip_force [N] */
    double e[3];            /* (1, 1, e_r) */
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
};


/* Per-step quantities of the moving frame, in B coordinates: gravity g_B,
 * acceleration of B's origin a0, angular velocity w, angular acceleration dw. */
typedef struct frame {
    double gB[3], a0[3], w[3], dw[3];
} frame;

/* Rotation by angle th about z applied to a plane vector. */
static inline void rot2(double out[2], double th, const double v[2])
{
    double c = cos(th), s = sin(th);
    double x = c * v[0] - s * v[1], y = s * v[0] + c * v[1];
    out[0] = x;
    out[1] = y;
}

/* Centre of mass position r in B (z = 0) and orientation th for coordinates q. */
void sim_com_pose(const exdex_model *m, const double *q, double r[3], double *th);
/* Motion kinematics k at time t and the frame terms f in B coordinates. */
int sim_frame_at(const exdex_model *m, double t, frame *f, exdex_kinematics *k);
/* Frame terms for the step from t (kinematics kin0) to t1 = t + h: the
 * kinematics and frame f at t_eval (position-dependent terms), kin_end at
 * t1, and the linear and angular accelerations replaced by their means over
 * the step, (v(t1) - v(t)) / h: exact in the mean when a motion switches
 * acceleration inside a step (Eq. 7 has jumps). */
int sim_frame_step(const exdex_model *m, const exdex_kinematics *kin0, double t_eval, double t1, double h,
                   frame *f, exdex_kinematics *kin, exdex_kinematics *kin_end);
/* Gravity + inertial force on the centre of mass at r moving at rd (Eq. 5), B coordinates. */
void sim_force_lin(const exdex_model *m, const frame *f, const double r[3], const double rd[3], double F[3]);
/* Inertial torque about the plate normal on the body at angle th turning at thd relative to B. */
double sim_torque_z(const exdex_model *m, const frame *f, double th, double thd);
/* Gap of outline vertex j against stop k at coordinates q and gripper pose kin;
 * G (may be NULL) gets d gap / d qdot (ndof entries). */
double sim_vertex_gap(const exdex_model *m, const exdex_kinematics *kin, int k, const double *q, int j,
                      double G[3]);

/* methods.c: the event-driven, regularised and explicit methods (exdex.h
 * enum exdex_method), same contract as exdex_simulate, which dispatches here
 * for every method but EXDEX_METHOD_IMPLICIT. */
int sim_simulate_method(const exdex_model *m, double t_end, double dt, exdex_trajectory *out,
                        exdex_stats *stats);

#endif
