/*
 * exdex.h -- the one public header of the exdex numerical core.
 *
 * In-hand manipulation by extrinsic dexterity: an object held between the two
 * parallel plates of a gripper that moves along a prescribed trajectory, with
 * gravity, inertial forces of the moving frame, plate friction (friction
 * ellipsoid, maximum dissipation, paper Eq. 6) and external stops.
 *
 * Python-free C99. Every function returns a status code (enum exdex_status) or
 * a plain value; nothing here aborts, prints or exits. Call exdex_init() once
 * per process before anything else: it switches GSL's abort handler off.
 *
 * Units are SI throughout (m, kg, s, rad, N, N m). Matrices are row-major.
 *
 * Frames (paper Section 2.1):
 *   A  world frame, fixed; gravity is given in A.
 *   B  gripper frame: origin on the plates' mid-plane, x and y span the plate
 *      plane, z is the plate normal (the closing direction of the fingers).
 *   C  object frame: origin at the object's centre of mass, z parallel to B's z
 *      (the plates keep the object in the plane); theta is the rotation of C
 *      about z relative to B.
 */
#ifndef EXDEX_H
#define EXDEX_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------ status */

enum exdex_status {
    EXDEX_OK = 0,
    EXDEX_EINVAL = 1,     /* an argument is out of its allowed range */
    EXDEX_ENOMEM = 2,     /* allocation failed */
    EXDEX_ENOCONV = 3,    /* an iterative solver did not converge */
    EXDEX_ENONFINITE = 4  /* a non-finite number appeared in the state */
};

/* Static, human-readable text for a status code. */
const char *exdex_strerror(int status);

/* Switch GSL's abort-on-error handler off (idempotent, call once per process). */
void exdex_init(void);

/* ---------------------------------------------------------------- friction
 * plate_friction.c -- the friction ellipsoid and its maximum-dissipation solve.
 *
 * Limit surface over the plate friction wrench w = (f_x, f_y, m_z) at the
 * patch's centre of pressure:  w^T E^-2 w <= (mu N)^2,  E = diag(e_t, e_t, e_r).
 * e_t = 1 (force), e_r [m] = m_max / (mu N) from the pressure distribution
 * (Howe & Cutkosky). With two fingers pressing with grip force F_g each,
 * N = 2 F_g: the two identical ellipsoids add to one of capacity 2 mu F_g.
 */

/* e_r of a uniform pressure disc of radius R [m]: 2R/3. Returns NaN if
 * R <= 0 or R is not finite; else a finite positive value. */
double exdex_er_disc(double radius);
/* e_r of a uniform pressure rectangle with half-sides a, b [m]
 * (mean distance from the centre). Returns NaN if a <= 0, b <= 0 or either
 * is not finite; else a finite positive value (no overflow or underflow for
 * any sizes or aspect ratio; between max(a, b)/2 and hypot(a, b)). */
double exdex_er_rectangle(double half_a, double half_b);

enum exdex_friction_solver {
    EXDEX_SOLVER_SCALAR = 0,    /* secular equation, safeguarded Newton in a bracket */
    EXDEX_SOLVER_BRENT = 1,     /* the same monotone scalar equation with GSL Brent */
    EXDEX_SOLVER_MULTIROOT = 2  /* paper: four quadratic equations, GSL hybridsj */
};

/*
 * One implicit friction step at a patch, velocity level (Moreau-Jean):
 *     u+ = b + W p
 * u+ the patch slip twist after the step (u_x, u_y, u_r) [m/s, m/s, rad/s],
 * b the slip twist without friction, W (3x3, SPD) the patch Delassus matrix
 * (slip per unit patch impulse), p the friction impulse (p_x, p_y, p_r)
 * [N s, N s, N m s]. p minimises p . u+ over the ellipsoid
 *     p^T E^-2 p <= cap^2,   cap = h mu N.
 * Stick iff p_stick = -W^-1 b lies inside; then u+ = 0 exactly.
 *
 * exdex_friction_prepare does the per-(W, e) work once (K = E W E, its
 * eigen-decomposition); a scene whose W is constant prepares once.
 */
typedef struct exdex_friction_prep {
    double W[9];     /* Delassus matrix, row-major */
    double e[3];     /* (e_t, e_t, e_r): semi-axes per unit capacity */
    double K[9];     /* E W E */
    double Q[9];     /* eigenvectors of K, columns, row-major storage */
    double lam[3];   /* eigenvalues of K, > 0 */
} exdex_friction_prep;

typedef struct exdex_friction_result {
    double p[3];     /* friction impulse */
    double u[3];     /* slip twist after the step, b + W p (exactly 0 at stick) */
    double sigma;    /* |E u+|, the Fritz-John multiplier (0 at stick) */
    int stick;       /* 1 if the stick solution was taken */
    int iterations;  /* solver iterations used (0 at stick) */
} exdex_friction_result;

/* GSL workspaces for the BRENT and MULTIROOT solvers (SCALAR needs none). */
typedef struct exdex_friction_ws exdex_friction_ws;
exdex_friction_ws *exdex_friction_ws_alloc(void);
void exdex_friction_ws_free(exdex_friction_ws *ws);  /* NULL is harmless */

/* EXDEX_EINVAL if W is not symmetric positive definite (also when it is
 * singular to working precision: scaled condition number above 1e12), any
 * e_i <= 0, any entry non-finite, or K's eigenvalues fall below the normal
 * floating-point range. Never allocates. */
int exdex_friction_prepare(exdex_friction_prep *prep, const double W[9],
                           const double e[3]);

/* Solve one step. ws may be NULL for EXDEX_SOLVER_SCALAR. warm (may be NULL)
 * is a guess of p used by MULTIROOT (e.g. the previous step's impulse).
 * Returns EXDEX_EINVAL for cap < 0 or non-finite input, EXDEX_ENOCONV if the
 * solver fails (every iteration is capped: no solve runs unbounded),
 * EXDEX_ENONFINITE when a result overflows the double range. On any error the
 * result fields are NaN. b, cap, W and e may span the whole double range (the
 * solve runs at unit scale after exact power-of-two rescalings). A sliding p
 * lies on the ellipsoid to rounding, |E^-1 p| = cap. MULTIROOT's iteration
 * count includes its restarts and Newton polish; when GSL's solver fails from
 * all of its independent starts, MULTIROOT restarts it from the secular
 * (SCALAR) solution and, should that fail too, returns the secular solution
 * (so no ENOCONV on valid input; the fallback counts the SCALAR
 * iterations). */
int exdex_friction_solve(const exdex_friction_prep *prep, const double b[3],
                         double cap, int solver, exdex_friction_ws *ws,
                         const double *warm, exdex_friction_result *res);

/* ------------------------------------------------------------------ motion
 * motion.c -- prescribed gripper trajectories.
 *
 * A motion moves the gripper frame B from its initial pose (R0, p0) in A.
 *   translation: p(t) = p0 + s(t) axis,            R(t) = R0
 *   rotation:    R(t) = Rot(axis, s(t)) R0,        p(t) = c + Rot(axis, s(t)) (p0 - c)
 * with s(t) a scalar profile [m or rad] and c = center, a point on the axis.
 *
 * A sampled motion (a robot log) interpolates poses given at increasing
 * times with C2 cubic splines of the position and of the quaternion
 * components (renormalised), which gives continuous accelerations. Outside
 * the sampled interval the gripper holds the end pose at rest. The spline's
 * end slopes are clamped:
 *   - end_given[e] = 1 (e = 0 the first sample, 1 the last): the logged
 *     frame's velocity end_velocity[e] [m/s] and angular velocity
 *     end_omega[e] [rad/s] there, in the coordinates of the poses;
 *   - end_given[e] = 0: from the data, separately for the position and the
 *     orientation: zero where the log starts or ends at rest, else the
 *     velocity of the quadratic through the three end samples. An end is at
 *     rest when that estimated velocity, along the first displacement D1
 *     away from the end, is at most half the mean velocity over the first
 *     interval h1:  v0 . D1 <= |D1|^2 / (2 h1)  (scale-free: it compares two
 *     velocities of the same data). A held pose (D1 = 0) or a uniformly
 *     accelerated start (v0 = 0) is at rest; a constant speed is not.
 * A log that starts or ends at speed makes the gripper's velocity jump there
 * (from or to rest): exdex_motion_jumps reports it, and every method applies
 * it as the same velocity jump of the object (exdex_simulate) when it falls
 * in (0, t_end] (at t = 0 the scene's v0 is the velocity after it).
 * The poses are those of a logged frame L (e.g. a robot flange); the gripper
 * frame is B(t) = P L(t) X, with X = tool_pose (the pose of B in L; identity
 * unless tool = 1) and P = identity (absolute poses, relative = 0) or
 * P = (R0, p0) (L(t_0) X)^-1 (relative = 1: the log's motion of B replayed
 * from the initial gripper pose (R0, p0); with L(t_0) X = I the poses are
 * displacements of it). Velocities and accelerations compose exactly.
 *
 * Every motion is right-continuous in time: at a switching time the value of
 * the next phase is returned (a sampled motion is at rest from its last
 * sample time on).
 */
enum exdex_motion_kind {
    EXDEX_MOTION_REST = 0,        /* the gripper stays at (R0, p0) */
    EXDEX_MOTION_ASYMMETRIC = 1,  /* paper Eq. 7: a_H, a_L from Eq. 9; round trip over 2T */
    EXDEX_MOTION_TRAPEZOID = 2,   /* trapezoidal velocity: distance X1 in time T, peak v_max */
    EXDEX_MOTION_SAMPLED = 3,     /* poses at times, interpolated */
    EXDEX_MOTION_SHAKE = 4,       /* oscillation s(t) = A (1 - cos 2 pi f t) for a duration D */
    EXDEX_MOTION_CHAIN = 5        /* pieces played one after the other (below) */
};

/* Shake: s(t) = A (1 - cos(2 pi f t)) on [0, D), A = amplitude, f =
 * frequency, D = duration; it starts at rest with s = 0 (acceleration
 * A (2 pi f)^2: an acceleration switch at 0) and holds s(D) from D on. Whole
 * or half cycles (f D an integer or half-integer) end at rest; otherwise the
 * velocity jumps to rest at D (exdex_motion_jumps). A phase 2 pi f D within
 * 16 rounding units of a multiple of pi counts as a whole or half cycle.
 *
 * Chain: pieces[0 .. n_pieces-1] (no chains among them) played one after
 * the other. Piece i occupies [T_i, T_i+1), T_0 = 0, T_i+1 = T_i + its
 * length: exdex_motion_end of the piece, except a REST piece (a pause),
 * which lasts its duration (> 0); every length must be > 0. Piece i runs on
 * local time t - T_i from the pose where piece i-1 ends (piece 0 from
 * (R0, p0)): its R0, p0 are that pose. A sampled piece with absolute poses
 * ignores them and must start there: its first pose may differ from the end
 * pose of the piece before by at most 1e-9 (|p_end| + |p_start|) + 1e-12 m
 * in position and 1e-9 in each rotation-matrix entry, else EXDEX_EINVAL
 * naming the piece ("motion.pieces[i]"). Velocity: where piece i-1 ends and
 * piece i starts the frame's velocity jumps by the sum of their own jumps
 * there (exdex_motion_jumps); a jump with |dv| or |dw| above 1e-9 times the
 * speeds on either side is EXDEX_EINVAL naming piece i unless allow_jump = 1
 * (then it is a velocity jump of the chain, applied by every method like
 * a sampled log's); a smaller one is rounding and dropped. Jumps inside a
 * piece and at the chain's start and end are the pieces' own. The chain's
 * switching times are the pieces' (shifted) and every T_i; a time exactly
 * at a shifted switch belongs to the phase after it, as in the piece. */
#define EXDEX_MOTION_MAX_PIECES 16

typedef struct exdex_motion_def {
    int kind;               /* enum exdex_motion_kind */
    int rotation;           /* 0: translate along axis; 1: rotate about axis through center */
    double axis[3];         /* direction in A, any finite non-zero vector (normalised) */
    double center[3];       /* a point of the rotation axis in A [m] */
    double amplitude;       /* X1 [m] or theta1 [rad]; any sign (sign gives direction) */
    double duration;        /* T [s] > 0 */
    double beta;            /* Eq. 7 ratio, 0 < beta < 1 */
    double v_max;           /* trapezoid peak speed [m/s or rad/s] > 0 with
                               |X1|/T <= v_max <= 2|X1|/T */
    size_t n_samples;       /* sampled: number of poses (>= 4) */
    const double *times;    /* sampled: (n_samples,) strictly increasing [s] */
    const double *poses;    /* sampled: (n_samples, 7) rows x y z qw qx qy qz of the
                               logged frame (R_AB without tool and relative);
                               quaternions need not be normalised */
    int end_given[2];       /* sampled: 0 end slopes from the data, 1 given (above) */
    double end_velocity[2][3];  /* sampled: given velocity at the first, last sample [m/s] */
    double end_omega[2][3];     /* sampled: given angular velocity there [rad/s] */
    int relative;           /* sampled: 1 replays the log from (R0, p0) (above) */
    int tool;               /* sampled: 1 applies tool_pose */
    double tool_pose[7];    /* sampled: pose of B in the logged frame, x y z qw qx qy qz
                               (quaternion non-zero, normalised) */
    double frequency;       /* shake: f [Hz] > 0, with f D <= 1e9 cycles */
    size_t n_pieces;        /* chain: 1 .. EXDEX_MOTION_MAX_PIECES */
    const struct exdex_motion_def *pieces;  /* chain: (n_pieces,) piece definitions (copied) */
    int allow_jump;         /* chain: 1 accepts velocity jumps between pieces (0 or 1) */
    double time_shift;      /* >= 0 [s]: the motion defined by the other fields, played from
                               its time time_shift on (t = 0 is its time_shift; its
                               switching times and jumps at or before it are dropped); 0: as
                               defined. A run that continues another from a later time. */
} exdex_motion_def;

/* Kinematics of B in A at one time, all vectors expressed in A. */
typedef struct exdex_kinematics {
    double R[9];   /* R_AB: columns are B's axes in A */
    double p[3];   /* position of B's origin [m] */
    double v[3];   /* its velocity [m/s] */
    double a[3];   /* its acceleration [m/s^2] */
    double w[3];   /* angular velocity of B [rad/s] */
    double dw[3];  /* angular acceleration of B [rad/s^2] */
} exdex_kinematics;

typedef struct exdex_motion exdex_motion;  /* opaque, immutable after alloc */

/* Validates def (EXDEX_EINVAL, *bad_param names the field when not NULL:
 * "motion.times", "motion.poses", "motion.end_given", "motion.end_velocity",
 * "motion.end_omega", "motion.relative", "motion.tool", "motion.tool_pose",
 * ...), copies sampled arrays. R0 must be a rotation matrix (orthonormal, det +1,
 * to 1e-9). Returns NULL on error with *status set. */
exdex_motion *exdex_motion_alloc(const exdex_motion_def *def, const double R0[9],
                                 const double p0[3], int *status,
                                 const char **bad_param);
void exdex_motion_free(exdex_motion *m);  /* NULL is harmless */

/* Thread-safe (no hidden mutable state). */
int exdex_motion_eval(const exdex_motion *m, double t, exdex_kinematics *k);
/* End of the motion: after it the gripper is at rest [s]. */
double exdex_motion_end(const exdex_motion *m);

/* Velocity jumps of the gripper frame B: times t[j] [s] (increasing) where
 * its velocity is discontinuous, with the jumps (right limit minus left
 * limit) of the velocity of B's origin dv[j] [m/s] and of its angular
 * velocity dw[j] [rad/s], in A; the pose is continuous there. A sampled
 * motion jumps at its first sample when it starts at speed and at its last
 * when it ends at speed; a trapezoid without ramps (v_max = |X1|/T) at 0 and
 * T; a shake that ends mid-cycle at D; a chain where its pieces do (above).
 * Returns their number (0 .. EXDEX_MOTION_MAX_JUMPS); any output may be
 * NULL. */
#define EXDEX_MOTION_MAX_JUMPS (2 * EXDEX_MOTION_MAX_PIECES)
int exdex_motion_jumps(const exdex_motion *m, double t[EXDEX_MOTION_MAX_JUMPS],
                       double dv[EXDEX_MOTION_MAX_JUMPS][3], double dw[EXDEX_MOTION_MAX_JUMPS][3]);

/* Switching times [s] of the motion, increasing: where its acceleration or
 * velocity may be discontinuous (Eq. 7: beta T, (2 - beta) T, 2T; trapezoid:
 * the ramp ends and T; sampled: the first and last sample times; shake: D;
 * chain: above; rest: none). Between two of them the kinematics are smooth,
 * except at a sampled log's knots (exdex_motion_next_knot). Returns their
 * number (0 .. EXDEX_MOTION_MAX_SWITCHES). */
#define EXDEX_MOTION_MAX_SWITCHES (4 * EXDEX_MOTION_MAX_PIECES)
int exdex_motion_switches(const exdex_motion *m, double ts[EXDEX_MOTION_MAX_SWITCHES]);
/* The first of exdex_motion_switches' times above lo, INFINITY if none:
 * the same time, found without building the list. */
double exdex_motion_next_switch(const exdex_motion *m, double lo);
/* The first knot of the motion above t, INFINITY if none: a sampled log's
 * sample times (inside a chain: those of the sampled piece holding t, at
 * their chain times; with a time_shift, on the shifted time). Its clamped
 * cubic splines are C2 there, and their third derivative jumps, so the
 * kinematics are smooth between two knots (and the switching times), not
 * across one: an adaptive integrator's step that straddles a knot loses its
 * order there. */
double exdex_motion_next_knot(const exdex_motion *m, double t);

/* Scalar profiles: position s, velocity sd, acceleration sdd at time t.
 * Before 0: s = sd = sdd = 0; after the end: at rest at the end value. */
void exdex_profile_asymmetric(double amplitude, double T, double beta, double t,
                              double *s, double *sd, double *sdd);
void exdex_profile_trapezoid(double amplitude, double T, double v_max, double t,
                             double *s, double *sd, double *sdd);

/* --------------------------------------------------------------- simulate
 * model.c -- the scene compiled to an immutable model, the relative
 * dynamics of the object in B (paper Eqs. 3-5); simulate.c -- one run of a
 * method (implicit.c, hybrid.c: event and regularised, explicit.c).
 *
 * Free coordinates (the scene chooses; the step works in that reduced space):
 *   EXDEX_DOF_TRANSLATION  q = s: the centre of mass moves along slide_axis
 *                          (a unit vector of the plate plane, B frame),
 *                          position (x0, y0) + (s - s0) slide_axis,
 *                          s0 = slide_axis . (x0, y0); theta fixed.
 *   EXDEX_DOF_ROTATION     q = theta: the object turns about a pivot fixed in
 *                          B at the patch's centre of pressure (paper 2.3),
 *                          an ideal pin; the plates' friction torque resists.
 *   EXDEX_DOF_PLANAR       q = (x, y, theta).
 */
enum exdex_dof { EXDEX_DOF_TRANSLATION = 1, EXDEX_DOF_ROTATION = 2, EXDEX_DOF_PLANAR = 3 };

/* All four share the model and the output contract, stops included in
 * every scene. EVENT and REGULARISED return EXDEX_ENOCONV
 * past 1e5 ODE steps plus event-location (Brent) iterations per output
 * interval, or a step below 16 ulps of t. */
enum exdex_method {
    EXDEX_METHOD_IMPLICIT = 0,     /* Moreau midpoint, maximum-dissipation solve (default);
                                      steps of dt, exact stick */
    EXDEX_METHOD_EVENT = 1,        /* event-driven exact stick/slip: GSL odeiv2 rk8pd to
                                      rtol/atol, switches located by Brent; dt is only the
                                      output grid; EXDEX_ENOCONV past 1000 events per
                                      output interval (Zeno-like toggling) */
    EXDEX_METHOD_REGULARISED = 2,  /* smooth friction |u| -> sqrt(|u|^2 + eps^2), rk8pd to
                                      rtol/atol; no true stick (creeps) */
    EXDEX_METHOD_EXPLICIT = 3,     /* explicit Coulomb with sign(), symplectic Euler steps
                                      of dt, naive baseline; chatters at stick */
    EXDEX_METHOD_ANALYTIC = 4      /* exact phase-by-phase solution of 1-DoF scenes with a
                                      piecewise-constant drive (exdex_analytic_unsupported
                                      says which scenes); dt is only the output grid */
};

#define EXDEX_MAX_STOPS 8
#define EXDEX_MAX_VERTICES 32
#define EXDEX_REGION_MAX_VERTICES 32  /* vertices of a contact region (exdex_scene_def) */
#define EXDEX_MAX_OBSTACLES 4
#define EXDEX_MAX_FACES 12
#define EXDEX_MAX_PAD_VERTICES 32

/* A convex obstacle fixed in the world frame A; the object's outline may not
 * enter it.
 *   EXDEX_OBSTACLE_POLYTOPE  the intersection of n_faces half-spaces
 *                            (x - face_point[f]) . face_normal[f] <= 0, the
 *                            normals unit and pointing out of the solid; it
 *                            may be unbounded (one face is a plane stop seen
 *                            from its other side: Stop(point, normal) keeps
 *                            the object where a one-face obstacle with the
 *                            same point and normal does).
 *   EXDEX_OBSTACLE_CYLINDER  the points within radius of the line through
 *                            center along axis (unit): an infinite rod.
 * The plate plane (z = 0 of the moving gripper frame B) cuts a polytope in a
 * convex polygon (each half-space a half-plane of B) and a rod in a disc
 * (axis along the plate normal) or an ellipse. Contacts: an outline vertex
 * against the obstacle (gap: the largest of its face distances; for a rod
 * its distance from the axis less the radius), a polygon vertex of the
 * section against the convex hull of the outline (gap: its largest
 * distance outside the hull's edge lines) and, for a rod, the hull against
 * the section (gap: the smallest distance of a hull point from the axis less
 * the radius, negative inside). A disc outline (disc_radius) touches each
 * obstacle with one row: its distance from the section less its radius (a
 * face's plane row, the nearest section vertex, or the rim point nearest the
 * rod's axis). */
enum exdex_obstacle_kind { EXDEX_OBSTACLE_POLYTOPE = 0, EXDEX_OBSTACLE_CYLINDER = 1 };

typedef struct exdex_obstacle_def {
    int kind;                               /* enum exdex_obstacle_kind */
    int n_faces;                            /* polytope: 1..EXDEX_MAX_FACES */
    double face_point[EXDEX_MAX_FACES][3];  /* a point of each face plane, in A [m] */
    double face_normal[EXDEX_MAX_FACES][3]; /* outward unit normals, in A */
    double center[3];                       /* cylinder: a point of the axis, in A [m] */
    double axis[3];                         /* cylinder: unit direction, in A */
    double radius;                          /* cylinder: > 0 [m] */
    double mu;                              /* Coulomb coefficient against the object (>= 0,
                                               finite; 0: frictionless), as a stop's stop_mu:
                                               along the tangent e_z x n_B of each row */
} exdex_obstacle_def;

/* Section of obstacle o by the plate plane of the gripper pose (R = R_AB, p):
 * the vertices (x, y) in B of the polygon, counter-clockwise, at most
 * EXDEX_MAX_FACES (a vertex is where two face lines meet inside every other
 * half-plane; an unbounded section lists its finite vertices only, a
 * section without vertices gives 0). A cylinder gives its ellipse: centre
 * xy[0] (the axis meets the plane there), semi-axes ab[0] >= ab[1] = radius
 * and the angle ab[2] of the major axis [rad]; returns 1, or 0 when the axis
 * lies in the plane (the section is a strip). EXDEX_EINVAL (as a negative
 * count, -EXDEX_EINVAL) for an invalid obstacle or pose. ab may be NULL for
 * polytopes. */
int exdex_obstacle_section(const exdex_obstacle_def *o, const double R[9], const double p[3],
                           double xy[EXDEX_MAX_FACES][2], double ab[3]);

typedef struct exdex_scene_def {
    /* object */
    double mass;              /* [kg] > 0 */
    double inertia[9];        /* about the centre of mass, in C [kg m^2], SPD */
    int n_vertices;           /* outline used against stops (0..EXDEX_MAX_VERTICES) */
    double vertices[EXDEX_MAX_VERTICES][2];  /* in C, relative to the centre of mass [m] */
    /* grasp */
    double mu;                /* plate friction coefficient >= 0 */
    double grip_force;        /* normal force per finger [N] >= 0 */
    int fingers;              /* 1 or 2 pressing patches (N = fingers * grip_force) */
    double e_r;               /* torsional semi-axis of the ellipsoid [m] > 0 */
    double patch_center[2];   /* centre of pressure in C, relative to the centre of mass [m] */
    /* world */
    double gravity[3];        /* in A [m/s^2] */
    /* coordinates */
    int dof;                  /* enum exdex_dof */
    double slide_axis[2];     /* translation: unit vector in B's plate plane */
    double q0[3];             /* initial (x, y, theta) of C in B [m, m, rad] */
    double v0[3];             /* initial relative velocity [m/s, m/s, rad/s] */
    /* gripper */
    double R0[9];             /* initial R_AB */
    double p0[3];             /* initial position of B in A [m] */
    exdex_motion_def motion;
    /* external stops: half-spaces of A, (x - point) . normal >= 0 allowed */
    int n_stops;
    double stop_point[EXDEX_MAX_STOPS][3];
    double stop_normal[EXDEX_MAX_STOPS][3];  /* unit */
    /* numerics */
    int method;               /* enum exdex_method */
    int friction_solver;      /* enum exdex_friction_solver */
    double eps;               /* regularised method: smoothing slip speed |E u| [m/s] > 0
                                 (a rotation scene: e_r |omega|) */
    double rtol, atol;        /* event/regularised methods: GSL odeiv2 tolerances, rtol
                                 relative to each state component, atol relative to its
                                 scale (positions L, angles 1 rad, velocities L/T, 1/T,
                                 force integrals m L/T, with the scene's length L and
                                 time T scales): both dimensionless */
    /* grip-force schedule (grip_n = 0: the constant grip_force). With a
     * schedule the normal force of each finger is F(t) = grip_force S(t)
     * (grip_force a scale, 1 for the schedule as given), S the schedule
     * through the points (grip_times[i], grip_forces[i]) by grip_kind, held
     * at its first and last value outside [grip_times[0],
     * grip_times[grip_n - 1]]; the friction capacity is mu fingers F(t).
     * The points are copied by exdex_model_alloc. */
    size_t grip_n;              /* 0 or 1 .. EXDEX_MAX_GRIP_POINTS */
    const double *grip_times;   /* (grip_n,) finite, strictly increasing [s] */
    const double *grip_forces;  /* (grip_n,) finite, >= 0 [N] */
    int grip_kind;              /* enum exdex_grip_kind */
    /* static friction: the plates hold the object while the wrench that
     * holds it lies in the static ellipsoid, of capacity mu_static N, and a
     * slip slides against the kinetic one, mu N (same shape, E); a slip
     * sticks again where its slip twist reaches 0 with the holding wrench
     * inside the static ellipsoid. mu_static >= mu, or 0: equal to mu (a
     * zero-initialised field keeps the one-coefficient law). The static
     * capacity is the kinetic one times mu_static / mu, so it follows a grip
     * schedule too. Each method states its use of it at the top of its file
     * (implicit.c: stick with the static capacity first, else slide with the
     * kinetic one; hybrid.c: event, and the regularised law's capacity
     * falling from static to kinetic with the slip speed; explicit.c: the
     * static rule at rest only; analytic.c). */
    double mu_static;
    /* convex obstacles fixed in A (above); their stop forces follow the
     * stops' in exdex_trajectory.stop_force. Every method but analytic
     * solves scenes with obstacles (frictional ones and disc outlines
     * too). */
    int n_obstacles;          /* 0..EXDEX_MAX_OBSTACLES */
    exdex_obstacle_def obstacles[EXDEX_MAX_OBSTACLES];
    /* Coulomb friction coefficient of each stop against the outline vertices
     * touching it (>= 0, finite; 0: frictionless). The friction acts along the
     * tangent t = e_z x n_B of the plate plane (n_B the in-plane part of the
     * stop normal in B), bounded by stop_mu times the stop's normal force.
     * Every method but analytic: exact in the implicit and explicit methods
     * (velocity level) and in the event and regularised methods (acceleration
     * level, hybrid.c; the regularised method smooths the plate friction
     * only). Impacts on a frictional stop, in every method: plastic with
     * Coulomb friction at the impulse level and no plate impulse (the
     * implicit step's law as the step vanishes). */
    double stop_mu[EXDEX_MAX_STOPS];
    /* A disc outline: disc_radius > 0 [m] makes the object's outline in the
     * plate plane the disc of that radius about disc_center (C, relative to
     * the centre of mass [m]) instead of the polygon of vertices (n_vertices
     * must then be 0; EXDEX_EINVAL, bad_param "disc_radius"); 0 keeps the
     * polygon. Against a stop the disc touches at its support point, the
     * rim point farthest along -n_B (n_B the stop normal in B): gap =
     * n . (centre in A - stop point) - disc_radius |n_B,xy|, a single row
     * per stop whose contact point moves along the rim as the object turns
     * (its friction acts there, so a disc rolls on a frictional stop).
     * Against an obstacle: the disc's distance from the section less the
     * radius (a face, a section vertex, or a rod's axis). Every method
     * solves it where it solves the stops and obstacles. */
    double disc_radius;
    double disc_center[2];
    /* Pads on the fingers: pad_n > 0 (a convex polygon, either orientation,
     * at pad_center + s pad[i] in B [m], s = pad_scale, 0 taken as 1) or
     * pad_radius > 0 (a disc of that radius about pad_center in B) fixes the
     * contact on the finger. The object's contact
     * face is then face_n > 0 (a convex polygon in C, relative to the centre
     * of mass [m]) or face_radius > 0 (a disc about face_center in C). At each
     * instant the contact region is the pad intersected with the face (in
     * B, the face at the object's pose; a disc against a polygon as stated
     * in pads.h), under uniform pressure N / area: the friction acts at the
     * region's centroid (in place of patch_center) with the ellipsoid's e_r
     * the region's mean distance from its centroid (in place of e_r), both
     * following the object's pose. The capacity stays mu N while the region
     * is non-empty. A 1-DoF translation is unaffected but for that; a 1-DoF
     * rotation pivots at the centroid of the region at the start and keeps
     * its e_r. The region must be non-empty at the start (EXDEX_EINVAL,
     * bad_param "pad"). When it vanishes (area below EXDEX_PAD_LOST times
     * the region's at the start) at an output sample, the grasp is lost:
     * the run records that sample, stops there, and exdex_stats.lost_t
     * and lost_sample say where (the samples after it are not written).
     * The adaptive methods (event, regularised) end their integration at
     * the end of the step in which it vanished: that sample holds the
     * pose there, not one integrated on past the loss.
     * pad_n = 0 and pad_radius = 0 (zero-initialised) keep the patch fixed
     * on the object (patch_center, e_r), bit for bit. */
    int pad_n;
    double pad[EXDEX_MAX_PAD_VERTICES][2];
    double pad_radius;
    double pad_center[2];
    double pad_scale;
    int face_n;
    double face[EXDEX_MAX_PAD_VERTICES][2];
    double face_radius;
    double face_center[2];
    /* The limit surface of the plate friction (enum exdex_limit_surface):
     * EXDEX_LS_ELLIPSOID (0, a zero-initialised field) the paper's Eq. 6
     * with e_r; EXDEX_LS_EXACT uniform-pressure Coulomb friction over the
     * contact region below with maximum dissipation (e_r is then not used:
     * the region's mean distance from patch_center takes its place where a
     * method needs a torsional length, the 1-DoF rotation's capacity and
     * the scene's length scale). The exact surface needs a region
     * (EXDEX_EINVAL, bad_param "region_kind" without one); planar scenes
     * with it run the implicit and event methods, with frictionless stops
     * and obstacles (EXDEX_EINVAL, bad_param "limit_surface", for another
     * method or a frictional stop or obstacle);
     * 1-DoF scenes run every method (a translation's friction is the
     * capacity whatever the shape; a rotation's torque capacity is the
     * region's). */
    int limit_surface;
    /* The contact region of each finger in C relative to patch_center (the
     * reference point of the friction wrench) [m]: region_kind 0 none,
     * 1 a convex polygon of region_n (3 .. EXDEX_REGION_MAX_VERTICES)
     * vertices region_vertices, counter-clockwise, 2 a disc of radius
     * region_radius centred on patch_center. Used by the exact surface
     * only (a region with the ellipsoid is checked and otherwise ignored). */
    int region_kind;
    int region_n;
    double region_vertices[EXDEX_REGION_MAX_VERTICES][2];
    double region_radius;
} exdex_scene_def;

/* Limit surfaces of the plate friction (exdex_scene_def.limit_surface). */
enum exdex_limit_surface {
    EXDEX_LS_ELLIPSOID = 0,  /* paper Eq. 6: w^T E^-2 w <= (mu N)^2 */
    EXDEX_LS_EXACT = 1       /* uniform pressure over the region, maximum dissipation */
};
enum exdex_region_kind { EXDEX_REGION_NONE = 0, EXDEX_REGION_POLYGON = 1, EXDEX_REGION_DISC = 2 };

/* A contact's limit surface per unit capacity (mu N = 1), at the reference
 * point of the region (limitsurf.c): surface an enum exdex_limit_surface,
 * e_r [m] > 0 for the ellipsoid, the region (region_kind, region_n,
 * region_vertices, region_radius, as in exdex_scene_def) for the exact
 * surface. what = 0: in is a slip twist u = (v_x, v_y, omega) != 0, out
 * its friction wrench (f_x, f_y, m_z) and *scalar its dissipation D(u)
 * (out . u = -D(u)); what = 1: in is a wrench the contact must supply,
 * *scalar its gauge (it is carried at capacity C iff gauge <= C: the stick
 * test) and out the unit slip twist it drives at the limit. Returns
 * EXDEX_OK, EXDEX_EINVAL (bad surface, e_r or region, non-finite or zero u,
 * what not 0 or 1), EXDEX_ENOCONV (the exact gauge's search, capped). */
int exdex_limit_surface_eval(int surface, double e_r, int region_kind, int region_n,
                             const double (*region_vertices)[2], double region_radius, int what, const double in[3],
                             double out[3], double *scalar);

/* The area ratio below which the pads' contact region counts as vanished. */
#define EXDEX_PAD_LOST 1e-6

/* The pads' contact region of def (pads on the fingers) with the object at
 * the pose q = (x, y, theta) of C in B: its area [m^2] (0: empty), centroid
 * c in B, e_r (mean distance from the centroid [m]) and, when verts is not
 * NULL, up to nmax of its polygon vertices (B, ccw) with their count in
 * *nv (0 for a region that is a disc exactly: then *radius > 0, else 0).
 * EXDEX_EINVAL for a def without pads or with an invalid pad or face. */
int exdex_pad_region(const exdex_scene_def *def, const double q[3], double *area, double c[2], double *er,
                     double *radius, double (*verts)[2], int nmax, int *nv);

/* Interpolation of a grip-force schedule between its points. */
enum exdex_grip_kind {
    EXDEX_GRIP_LINEAR = 0,  /* piecewise linear */
    EXDEX_GRIP_CUBIC = 1,   /* Steffen's monotone cubic (GSL gsl_interp_steffen): C1, no
                               overshoot (between two points it stays between their values,
                               so F >= 0); linear through two points, constant through one */
    EXDEX_GRIP_STEP = 2     /* piecewise constant, right-continuous: forces[i] on
                               [times[i], times[i + 1]) (a release or re-grip as a step) */
};
#define EXDEX_MAX_GRIP_POINTS 1000000

/* NULL if EXDEX_METHOD_ANALYTIC solves the scene, else a static sentence
 * saying why not: it needs a 1-DoF scene without stops whose drive is
 * piecewise constant: a translation scene whose gripper translates (Eq. 7,
 * a trapezoid with ramps, or rest), or a rotation scene about the centre of
 * mass (patch centre 0) whose gripper turns about the plate normal (to
 * 1e-12) or rests; the grip force constant, or a piecewise-linear or step
 * schedule (not a cubic one, unless its forces are all equal). */
const char *exdex_analytic_unsupported(const exdex_scene_def *def);

/* Defaults: unit mass, unit inertia, mu 0.5, grip force 1 N, 2 fingers,
 * e_r 0.01 m, gravity (0, 0, -9.81), R0 with B's y up (B x = A x, B y = A z,
 * B z = -A y), translation along B's y, gripper at rest, implicit method,
 * scalar friction solver, eps 1e-4, rtol 1e-8, atol 1e-10. */
exdex_scene_def exdex_default_scene_def(void);

/* EXDEX_OK or EXDEX_EINVAL with *bad_param (if not NULL) naming the field.
 * Rejects exactly what exdex_model_alloc rejects with EXDEX_EINVAL (R0, the
 * motion, a singular planar friction problem, an object starting beyond a
 * stop included), with the same bad_param; it builds the model and frees it
 * again, so it may also return EXDEX_ENOMEM. A motion that overflows at
 * t = 0 (model_alloc: EXDEX_ENONFINITE) passes the check. */
int exdex_scene_check(const exdex_scene_def *def, const char **bad_param);

typedef struct exdex_model exdex_model;  /* immutable after alloc */
/* NULL on error with *status EXDEX_EINVAL (bad_param names the field),
 * EXDEX_ENOMEM, or EXDEX_ENONFINITE (the motion overflows at t = 0). */
exdex_model *exdex_model_alloc(const exdex_scene_def *def, int *status,
                               const char **bad_param);
void exdex_model_free(exdex_model *m);   /* NULL is harmless */
int exdex_model_ndof(const exdex_model *m);
int exdex_model_nstops(const exdex_model *m);  /* stops + obstacles: stop_force columns */
/* Normal force of each finger at time t, *force [N], and its rate dF/dt,
 * *rate [N/s] (the right derivative at a breakpoint; either may be NULL):
 * the constant grip_force or the scene's grip schedule scaled by it.
 * EXDEX_EINVAL for a NULL model or a NaN t. */
int exdex_model_grip(const exdex_model *m, double t, double *force, double *rate);

/* Number of recorded samples for (t_end, dt): steps of dt, the last one
 * shortened to end exactly at t_end; samples = steps + 1. 0 if invalid:
 * non-finite, dt <= 0, dt > t_end, or more than EXDEX_MAX_STEPS steps.
 * The limit bounds the run time of one call (the implicit method takes one
 * step per sample, each with capped inner iterations) and the caller's
 * arrays (>= 8 doubles a sample, 64 GB at the limit); exdex_simulate
 * rejects (t_end, dt) beyond it with EXDEX_EINVAL. */
#define EXDEX_MAX_STEPS 1000000000.0
size_t exdex_n_samples(double t_end, double dt);

/* Caller-allocated output arrays, n = exdex_n_samples(t_end, dt) rows. */
typedef struct exdex_trajectory {
    size_t n;
    double *t;            /* (n,) [s] */
    double *q;            /* (n, ndof) coordinates */
    double *v;            /* (n, ndof) relative velocities */
    double *wrench;       /* (n, 3) plate friction (f_x, f_y, m_z) on the object,
                             in B at the centre of pressure, mean over the step
                             that ends at this sample [N, N, N m]; row 0: the
                             wrench holding the object at t = 0 where it starts
                             at rest inside the static limit surface in a
                             scene without stops or obstacles (the static
                             balance of gravity and the inertial forces), else
                             0 (it starts moving or slipping, or stops and
                             obstacles share the load) */
    unsigned char *stick; /* (n,) 1 where the step ending here stuck */
    double *stop_force;   /* (n, n_stops + n_obstacles) mean normal force of each
                             stop, then of each obstacle [N]; may be NULL when
                             there are neither (exdex_model_nstops counts both) */
} exdex_trajectory;

/* Why a run returned EXDEX_ENOCONV or EXDEX_ENONFINITE (exdex_stats.fail_cause). */
enum exdex_fail_cause {
    EXDEX_FAIL_NONE = 0,         /* the run succeeded */
    EXDEX_FAIL_EVENTS = 1,       /* event: more than 1000 mode switches within one output
                                    interval (Zeno-like accumulation of events) */
    EXDEX_FAIL_STEP_BUDGET = 2,  /* event, regularised: more than 1e5 ODE steps plus event
                                    location iterations within one output interval (stiff) */
    EXDEX_FAIL_STEP_FLOOR = 3,   /* event, regularised: the adaptive step fell below 16 ulps
                                    of t (a step-size collapse) */
    EXDEX_FAIL_STEPPER = 4,      /* the ODE stepper or the event location failed */
    EXDEX_FAIL_SOLVER = 5,       /* an inner solver (friction, constraints) failed */
    EXDEX_FAIL_NONFINITE = 6     /* the state left the finite range */
};

typedef struct exdex_stats {
    size_t steps;
    size_t stick_steps;
    size_t solver_iterations;   /* friction solver iterations, summed */
    size_t stop_iterations;     /* stop/friction block iterations, summed */
    size_t warnings;            /* soft problems (e.g. stop iteration limit) */
    double min_gap;             /* smallest stop gap seen after a step [m] */
    double first_warning_t;     /* end of the first step or output interval
                                 * that counted a warning [s]; NaN: none */
    size_t impacts;             /* impacts on stops: a stop starts pushing an
                                 * object that approaches it (a velocity jump) */
    double max_impulse;         /* largest impact impulse of one stop [N s]
                                 * (generalized: N m s on a rotation pin); 0: none */
    double max_impulse_t;       /* its time [s] (the step's end for
                                 * time-stepping methods); NaN: none */
    int max_impulse_stop;       /* its stop index; -1: none */
    double fail_time;           /* where a failed run stopped: the time it had reached
                                   (event, regularised: the start of the failing step
                                   or event) [s]; NaN after success or when unknown */
    int fail_cause;             /* enum exdex_fail_cause; EXDEX_FAIL_NONE after success */
    double lost_t;              /* pads on the fingers: the time of the output sample at which
                                   the contact region vanished and the run stopped (the grasp
                                   is lost); NaN: held to the end */
    size_t lost_sample;         /* its sample index (the last one written); 0: none */
} exdex_stats;

/* Run the whole trajectory. Thread-safe for distinct out/stats. Returns
 * EXDEX_EINVAL only for bad arguments (model, t_end, dt beyond
 * EXDEX_MAX_STEPS, out arrays); a state, wrench or stop force that leaves the
 * finite range during the run gives EXDEX_ENONFINITE (EXDEX_OK guarantees
 * finite output), and a solver failure EXDEX_ENOCONV. */
int exdex_simulate(const exdex_model *m, double t_end, double dt,
                   exdex_trajectory *out, exdex_stats *stats);


/* ------------------------------------------------------------ certificate
 * certify.c -- does the planar model admit a reduced run's motion? For a
 * translation or rotation model, along the trajectory out of a successful
 * exdex_simulate: the plate friction wrench the neglected in-plane
 * coordinates need to stay still (gravity, the frame's inertial terms and
 * the reduced coordinate's motion through the planar equations), with the
 * stops and obstacles that touch the object pushing as needed (and their
 * friction), is checked against the friction limit surface (the ellipsoid,
 * or the exact surface of limit_surface EXDEX_LS_EXACT): inside the static surface while the reduced
 * coordinate sticks; while it slips, maximum dissipation fixes the
 * friction of the slip (a pure translation slip has no moment, a pure
 * rotation about the centre of pressure no force), and what it cannot give
 * must be zero to 1e-9 of the scene's force scale plus the load. Checked
 * at every sample and switching time; a failure is located between
 * samples (certify.c says where this is exact). A slip the samples do not
 * show (the coordinate moved between two stuck samples of an exact-stick
 * method) is checked at both ends of its interval with the interval's
 * mean rate; where that fails the reduction holds up to the interval's
 * start. Between two stuck samples the load is proven inside the surface
 * over the interval's enclosure or, where that cannot be shown, the
 * interval is halved (four times at most) and the middles evaluated: an
 * excursion shorter than a sixteenth of an output interval is seen only
 * where a proof rules it out, and not where stops carry the stuck load. */
typedef struct exdex_certificate {
    int reduced;          /* 1: a 1-DoF run was checked; 0: planar (nothing neglected) */
    int holds;            /* 1: the reduction held up to the last sample */
    double valid_until;   /* [s] the last sample's time when it holds, else the last
                             time at which it is known to hold (the failure is after it) */
    size_t first_bad;     /* first sample whose check fails (n when none) */
    int stick;            /* mode of the reduced coordinate there: 1 stuck, 0 slipping */
    double load[3];       /* the wrench needed there (f_x, f_y, m_z) in B at the
                             centre of pressure [N, N, N m] (before stop forces) */
    double capacity;      /* friction capacity there (the static one when stuck) [N] */
    double gauge;         /* stuck: gauge of the load in the limit surface (> 1 fails);
                             slipping: the part the slip's friction cannot give, |E^-1 r| / C */
    int coordinate;       /* the neglected coordinate that needs most of it: translation
                             runs 1 (across the slide axis) or 2 (theta); rotation runs 0
                             (the pivot's translation x, y); -1 none */
} exdex_certificate;

/* EXDEX_OK (c filled: planar runs have reduced = 0 and hold), EXDEX_EINVAL
 * for NULL arguments or an empty trajectory, or the motion's status. */
int exdex_certify(const exdex_model *m, const exdex_trajectory *out, exdex_certificate *c);
/* The same certificate with every sample evaluated: exdex_certify skips the
 * samples of a piece between switching times whose mode it has proven to
 * hold there for every state the run visits (certify.c); this is the
 * reference the C suite checks it against, the same result. */
int exdex_certify_samples(const exdex_model *m, const exdex_trajectory *out, exdex_certificate *c);
/* The check of a run's newest sample, for a run advanced a sample at a time
 * (the stepper): out holds the run's last out->n samples (3, or all of them
 * while the run has fewer), n_before the run's samples before out->t[0].
 * Checks the newest one (and, when it is the run's sample 1, sample 0 first)
 * as exdex_certify_samples does within the whole run: c->holds = 1 if it
 * holds (valid_until its time, first_bad its index + 1), else c as
 * exdex_certify's at that failure (first_bad the run's index). The run's
 * sample 0 alone holds (it is decided with sample 1). EXDEX_EINVAL for NULL
 * arguments or a window that is not the run's last samples. */
int exdex_certify_last(const exdex_model *m, const exdex_trajectory *out, size_t n_before, exdex_certificate *c);
/* exdex_simulate with the certificate checked as the run goes, a window of
 * samples at a time: a 1-DoF run whose reduction fails stops there, its
 * last sample at the failure's time (c->valid_until: the run's grid up to
 * the sample before it, then one step to it; just the grid's sample 0
 * where it fails at t = 0). Where it holds, out, the stats and c are
 * exdex_simulate's and exdex_certify's (bit for bit); where it fails, the
 * samples before the failure are exdex_simulate's, c exdex_certify's of
 * the whole run (first_bad on the run's grid) and the stats those of the
 * samples written. *n_out: the samples written (also where the pads'
 * grasp is lost). A planar model runs exdex_simulate. A solver failure
 * after the reduction failed does not count (the run ends before it);
 * other statuses as exdex_simulate's, c then not filled. */
int exdex_simulate_certified(const exdex_model *m, double t_end, double dt, exdex_trajectory *out,
                             exdex_stats *stats, exdex_certificate *c, size_t *n_out);
/* ---------------------------------------------------------------- stepper
 * stepper.c -- a run advanced one step at a time, for feedback control: the
 * caller chooses each step's length and grip force from the state it reads.
 *
 * A stepper owns a copy of the model's numbers (the model itself must
 * outlive it and is not changed) and one workspace of the scene's method.
 * Step k ends at t_base + k dt while dt stays the same (t_base: where dt
 * last changed), so stepping n times with dt reproduces exdex_simulate(m,
 * n dt, dt) bit for bit (the same samples, stats and status), whatever the
 * method, when every step takes the scene's own grip force (NaN below).
 * The impacts of the time-stepping methods (implicit, explicit), which
 * exdex_simulate finds from the stop impulses of a few steps around each,
 * the end of the run cutting off an undecided one, are the stepper's stats
 * over the steps taken in the same way.
 * The first step's dt is the run's: the event and regularised methods start
 * their adaptive step from it, as exdex_simulate from its dt.
 *
 * Grip force: a finite grip_force >= 0 [N per finger] holds over the step
 * (a constant capacity mu fingers grip_force replaces the scene's grip force
 * or schedule for that step); NaN takes the scene's own (constant or
 * schedule). A change of the capacity between two steps is a jump at the
 * step boundary; the event method decides stick or slip again there. The
 * model's scales and tolerances stay those of the scene's grip. The
 * analytic method takes a new grip force as a new segment from the step's
 * start.
 *
 * save / restore copy the whole state (time, grid, method state, last
 * sample, stats): stepping on from a restored state repeats what the saved
 * stepper did, bit for bit. A snapshot restores into any stepper of the same
 * model. After a failed step (a status other than EXDEX_OK and EXDEX_EINVAL)
 * the stepper only accepts restore or free. Not thread-safe per stepper;
 * distinct steppers of one model may run in parallel. */
typedef struct exdex_stepper exdex_stepper;

typedef struct exdex_stepper_sample {
    double t;                            /* time reached [s] */
    double q[3], v[3];                   /* coordinates and rates (ndof of them) */
    double wrench[3];                    /* plate friction, mean over the last step (B, centre
                                            of pressure) [N, N, N m]; 0 before the first step */
    int stick;                           /* 1 if the last step ended exactly at rest (before the
                                            first: the initial velocity is 0) */
    double stop_force[EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES];  /* mean normal force of each stop, then
                                            of each obstacle, over the last step [N] */
    double grip_force;                   /* the last step's grip force [N] (NaN: the scene's) */
    size_t steps;                        /* steps taken */
} exdex_stepper_sample;

/* NULL with *status EXDEX_EINVAL (no model, or an unknown method),
 * EXDEX_ENOMEM, or the status of the method's set-up (EXDEX_ENONFINITE: the
 * analytic method's drive overflows, as exdex_simulate reports it). */
exdex_stepper *exdex_stepper_alloc(const exdex_model *m, int *status);
void exdex_stepper_free(exdex_stepper *s);   /* NULL is harmless */

/* Advance by dt [s] (finite, > 0, with t + dt > t and at most
 * EXDEX_MAX_STEPS steps of this dt from t_base) with grip force grip_force
 * (above). EXDEX_EINVAL for bad arguments (the stepper unchanged), else the
 * status exdex_simulate would return for the step (EXDEX_ENOCONV,
 * EXDEX_ENONFINITE; stats give the cause and time). */
int exdex_stepper_step(exdex_stepper *s, double dt, double grip_force);

/* A prescribed gripper pose (exdex_stepper_step_gripper): the pose of B in
 * A at the end of the step, R = R_AB (a rotation matrix to 1e-9) and p [m],
 * and its twist there, the velocity v [m/s] of B's origin and the angular
 * velocity w [rad/s] (A), each used when given_v / given_w is 1 and
 * otherwise the step's secant: the mean velocity (p - p0) / dt and the
 * constant angular velocity turning R0 into R over dt (the shorter way),
 * with (R0, p0) the pose at the step's start. */
typedef struct exdex_gripper_pose {
    double R[9], p[3], v[3], w[3];
    int given_v, given_w;
} exdex_gripper_pose;

/* As exdex_stepper_step, the gripper following a prescribed pose over the
 * step (pose NULL: the scene's motion, exdex_stepper_step itself). From the
 * gripper's pose and twist at the step's start (the last step's given end,
 * or the scene's motion at t for the first step with a pose) to the given
 * end, its position and the quaternion of its rotation are each the cubic
 * with those end values and rates (Hermite interpolation, the quaternion
 * normalised): position, velocity, orientation and angular velocity
 * continuous from step to step, the accelerations of the cubic inside each
 * step (the position's linear in time). Sampling a smooth motion at the
 * step ends with its twist, this interpolates it with errors O(dt^4) in
 * the pose, O(dt^3) in the twist and O(dt^2) in the accelerations. The
 * scene's switching times and velocity jumps no longer apply: once a step
 * gives a pose, every later step must (EXDEX_EINVAL otherwise, the stepper
 * unchanged), and so after a restore of a snapshot saved after such a step.
 * EXDEX_EINVAL also for a pose with the analytic method (its phases are the
 * scene's motion) and for a non-finite pose or an R that is not a
 * rotation. */
int exdex_stepper_step_gripper(exdex_stepper *s, double dt, double grip_force, const exdex_gripper_pose *pose);

/* The state after the last step (or the initial state); stats (may be
 * NULL) as exdex_simulate's over the steps taken. */
int exdex_stepper_get(const exdex_stepper *s, exdex_stepper_sample *out, exdex_stats *stats);
/* The certificate of a translation or rotation stepper's steps so far
 * (exdex_certify_last after each step, with that step's grip force and
 * gripper motion): as exdex_certify's over the same samples, fixed at the
 * first failure; reduced = 0 for a planar one. */
int exdex_stepper_certificate(const exdex_stepper *s, exdex_certificate *c);

/* Bytes of a snapshot of this stepper's state. */
size_t exdex_stepper_state_size(const exdex_stepper *s);
/* EXDEX_EINVAL if size differs from exdex_stepper_state_size or buf is
 * NULL; restore also (the stepper unchanged) if the snapshot is not one
 * saved by a stepper of the same model, or was changed after save (a
 * checksum and the ranges of its indices are checked); EXDEX_ENOMEM. */
int exdex_stepper_save(const exdex_stepper *s, void *buf, size_t size);
int exdex_stepper_restore(exdex_stepper *s, const void *buf, size_t size);

/* ------------------------------------------------------------ tool design
 * cone.c -- twist cones of a pushed planar object and their volumes
 * (paper Section 3). Declarations are added below by that module.
 */

/* Twist x = (Vx, Vy, wz) of a planar object, in the object's own frame at its
 * reference point (the origin of its vertex coordinates) [m/s, m/s, rad/s].
 * A contact at r (object frame, about the reference point) whose normal n
 * (unit) points from the tool into the object's free side gives the
 * unilateral row  n . (v + w x r) >= 0,  i.e.  row = (n_x, n_y, r_x n_y - r_y n_x).
 * A cone is {x : rows x >= 0}; an all-zero row is no constraint (padding).
 * Wrenches (F_x, F_y, M_z) pair with twists by power F_x Vx + F_y Vy + M_z wz. */
#define EXDEX_CONE_MAX_ROWS 136

/* row = (n, r x n) */
void exdex_contact_row(double row[3], const double r[2], const double n[2]);

/* Frictional contact (paper Section 3.2, Fig. 10): the two friction-cone edge
 * directions e+- = (n +- mu t) / sqrt(1 + mu^2), t = (-n_y, n_x), each as a
 * row (e, r x e). The twists satisfying both are those no contact force
 * inside the friction cone can oppose (the contact point's velocity lies in
 * the dual of the friction cone). mu = 0 gives two copies of the frictionless
 * row. rows: (2, 3). EXDEX_EINVAL if mu < 0 or input non-finite;
 * EXDEX_ENONFINITE if a row overflows (|r| near DBL_MAX). */
int exdex_contact_rows_friction(double rows[6], const double r[2], const double n[2],
                                double mu);

/* The paper's Eqs. 10-11, literally: rows (2, 3) for the unit square at
 * attack angle phi against two surfaces at angle theta [rad]. */
void exdex_cone_rows_paper(double rows[6], double phi, double theta);

/* Volume of {x in [lo, hi] : rows x >= 0}, m rows (m, 3), m <= EXDEX_CONE_MAX_ROWS.
 * Every method works in the unit cube of the box (centred, each axis scaled
 * by its width; each row's offset there formed exactly and rounded once), so
 * the box's size, aspect ratio and distance from the apex cost no accuracy.
 *   exact: apex within 4 box widths: divergence theorem about the apex, only
 *          the box faces contribute (each a square clipped by the rows,
 *          Sutherland-Hodgman, shoelace); apex farther: the cube clipped by
 *          each half-space as a polytope, divergence theorem about its centre.
 *          Accuracy: |V - V_true| <= 16 (1 + m) eps * box volume (+ a few
 *          subnormals when the box volume is subnormal), V in [0, box volume],
 *          V = box volume exactly without rows. (Measured: <= ~4 eps * box
 *          against a quad-precision reference; the bound has margin.)
 *   grid:  the paper's discretisation: n^3 cells, cell centres counted
 *          (a centre on a cone facet counts as inside).
 *   qmc:   GSL Sobol points (gsl_qrng_sobol), randomised by `shifts` random
 *          Cranley-Patterson shifts (gsl_rng_mt19937, seed); `points` Sobol
 *          points per shift; the estimate is the mean over shifts and *err its
 *          standard error (sample sd / sqrt(shifts)); shifts = 1 uses the
 *          unshifted sequence and sets *err = NaN. */
enum exdex_volume_method {
    EXDEX_VOLUME_EXACT = 0,
    EXDEX_VOLUME_GRID = 1,
    EXDEX_VOLUME_QMC = 2
};

typedef struct exdex_volume_opts {
    long grid_n;          /* grid cells per axis, >= 1 */
    long qmc_points;      /* Sobol points per shift, 1 .. 2^30 */
    int qmc_shifts;       /* random shifts, >= 1 */
    unsigned long seed;   /* seed of the shifts */
} exdex_volume_opts;

/* Defaults: grid_n 64, qmc_points 2^16, qmc_shifts 16, seed 1. */
exdex_volume_opts exdex_default_volume_opts(void);

int exdex_cone_volume_exact(const double *rows, int m, const double lo[3],
                            const double hi[3], double *volume);

/* Vectorised: n_cases cones of m rows each (rows (n_cases, m, 3)), one box.
 * volume (n_cases,); err (n_cases,) may be NULL (QMC standard error, NaN
 * for the other methods). Allocates the QMC workspaces once per call. */
int exdex_cone_volumes(int method, size_t n_cases, int m, const double *rows,
                       const double lo[3], const double hi[3],
                       const exdex_volume_opts *opts, double *volume, double *err);

/* Tool design (paper Section 3.1, Eq. 12, and beyond).
 *
 * World (tool) frame: the object is pushed into a V of two infinite flat
 * surfaces through the apex (origin), with inward normals
 *     n1 = (-sin alpha1, cos alpha1)   ("left" surface; alpha1 = 0 is a floor)
 *     n2 = (-sin alpha2, cos alpha2)   ("right" surface)
 * so the paper's tool angle is theta = alpha2 - alpha1 (90 deg: a square
 * corner). An object at attack angle phi is its polygon rotated by phi; it
 * touches each surface at its support vertices (every vertex within 1e-9 of
 * the polygon's radius of the minimum of n . x; an edge contact gives one
 * row per end vertex). Optionally a spring plunger presses along -y at
 * x = s in the tool frame, the object being wedged into the V (position from
 * touching both surfaces): it touches the topmost boundary point of the
 * object on the line x = s (no contact if the line misses the object or the
 * surfaces are parallel). Rows are in the object frame.
 */
enum exdex_tool_model {
    EXDEX_TOOL_CONTACT = 0,  /* rows from the contacts above (derived) */
    EXDEX_TOOL_PAPER = 1     /* Eqs. 10-11 literally (unit square only), with
                                attack phi - alpha1 and theta = alpha2 - alpha1 */
};

typedef struct exdex_tool_def {
    double alpha1, alpha2;  /* surface normal angles [rad] */
    int plunger;            /* 1: use the plunger */
    double s;               /* plunger position along x [m] */
} exdex_tool_def;

typedef struct exdex_tool_problem {
    int model;                /* enum exdex_tool_model */
    int n_shapes;             /* >= 1 (ignored by EXDEX_TOOL_PAPER) */
    const int *n_vertices;    /* (n_shapes,), each 3..EXDEX_MAX_VERTICES */
    const double *vertices;   /* (sum n_vertices, 2) object frame [m] */
    int n_phi;                /* >= 1 */
    const double *phi;        /* (n_phi,) attack angles [rad] */
    double lo[3], hi[3];      /* the twist box */
    double mu;                /* tool friction coefficient >= 0 */
    int has_push;             /* 1: add the push row push . x >= 0 */
    double push[3];           /* push wrench in the tool frame (F_x, F_y, M_z) */
} exdex_tool_problem;

/* EXDEX_OK or EXDEX_EINVAL with *bad_param naming the field. */
int exdex_tool_problem_check(const exdex_tool_problem *p, const char **bad_param);

/* Rows of one shape (index) at one attack angle; *nrows <= EXDEX_CONE_MAX_ROWS.
 * EXDEX_ENONFINITE if a row overflows (vertices or push near DBL_MAX); the
 * volume, objective and optimiser calls pass that status on. */
int exdex_tool_rows(const exdex_tool_problem *p, const exdex_tool_def *tool, int shape,
                    double phi, double *rows, int *nrows);

/* Exact volumes for n_tools tools: volume (n_tools, n_shapes, n_phi). */
int exdex_tool_volumes(const exdex_tool_problem *p, size_t n_tools,
                       const exdex_tool_def *tools, double *volume);

/* Eq. 12 objective: sum over shapes and attack angles of the exact volume
 * (EXDEX_ENONFINITE if the sum overflows, for boxes near DBL_MAX). */
int exdex_tool_objective(const exdex_tool_problem *p, const exdex_tool_def *tool,
                         double *sum);

typedef struct exdex_tool_opt_result {
    double x[3];       /* (alpha1, alpha2, s) at the optimum */
    double f;          /* objective there */
    int iterations;    /* Brent or simplex iterations */
    int evaluations;   /* objective evaluations, scan included */
    int bracketed;     /* theta: 1 if Brent refined an interior scan minimum,
                          0 if the scan minimum was at a bound or on a plateau */
} exdex_tool_opt_result;

/* Eq. 12: theta* = argmin over theta in [theta_lo, theta_hi] of the
 * objective with alpha2 = alpha1 + theta (tool->alpha1, plunger, s kept):
 * n_scan >= 3 equally spaced values, then GSL Brent on the two scan cells
 * around the best value, to |dtheta| <= max(xtol, 3e-8 max(1, |theta|)) (Brent's
 * resolution is ~sqrt(DBL_EPSILON)). scan_f (n_scan,) may be NULL.
 * EXDEX_EINVAL also for |tool->alpha1|, |theta_lo| or |theta_hi| beyond
 * EXDEX_TOOL_ANGLE_MAX [rad]: alpha1 + theta resolves theta only to
 * eps (|alpha1| + |theta|), so theta = alpha2 - alpha1 (res->x) would leave
 * [theta_lo, theta_hi] (for |alpha1| ~ 1e16 theta is lost entirely); within
 * the bound res->x[1] - res->x[0] is the theta evaluated to 2.3e-10 rad. */
#define EXDEX_TOOL_ANGLE_MAX 1e6
int exdex_tool_optimise_theta(const exdex_tool_problem *p, const exdex_tool_def *tool,
                              double theta_lo, double theta_hi, int n_scan, double xtol,
                              double *scan_f, exdex_tool_opt_result *res);

/* Several tool parameters together: GSL nmsimplex2 over the parameters
 * (alpha1, alpha2, s) whose free[i] is 1, from tool (start) with initial
 * steps step[3], until the simplex size <= size_tol or max_iter. */
int exdex_tool_optimise(const exdex_tool_problem *p, const exdex_tool_def *start,
                        const int free_param[3], const double step[3], int max_iter,
                        double size_tol, exdex_tool_opt_result *res);

#ifdef __cplusplus
}
#endif
#endif /* EXDEX_H */
