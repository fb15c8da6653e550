/* stop_friction.h -- private to the exdex core: the acceleration-level contact
 * problem of a planar object against stops with Coulomb friction, for the
 * event-driven and regularised methods (hybrid.c). A "stop" here is a
 * friction group: a line of contact whose rows slip together (a stop, or
 * an obstacle's contact line: hybrid.c, sf_groups). Pure numerics on ldp.h:
 * no model, no allocation, every loop bounded.
 *
 * The problem (3 free coordinates, M = diag(1 / minv)):
 *     M (qdd - a) = sum_i lam_i G_i + sum_k beta_k T_k,
 *     normal, each row i:  0 <= lam_i  _|_  G_i qdd + gdd0_i >= 0,
 *     friction, each stop k with rows carrying force: one tangential force
 *       beta_k along T_k, the Coulomb law of the stop's slip s_k:
 *         sliding (s_k != 0, sign sigma):  beta_k = -mu_k sigma sum_i lam_i,
 *         rolling (s_k = 0):  T_k qdd + sdd0_k = 0 and |beta_k| <=
 *           mu_k sum_i lam_i (stick), or sliding at the limit with the
 *           slip acceleration T_k qdd + sdd0_k of the sign sigma
 *           (beta_k = -mu_k sigma sum_i lam_i).
 * a is the acceleration without the stops (applied forces and the plate
 * friction, which does not depend on the stop forces: the grip force is
 * given). The rows of one stop are outline vertices on the stop's line, so
 * while their gaps are held they slip together: one slip s_k, one tangent
 * row T_k (the same for every such vertex: the arm of the tangent about the
 * centre of mass is the line's) and one friction force, which the stop's
 * rows share in proportion to their normal forces (each then at the same
 * fraction of its cone). Counting one tangential unknown per stop, not per
 * vertex, keeps a face lying flat on a stop from giving a singular system
 * (two sticking corners of a face have dependent tangent rows).
 *
 * Contact modes: each row carries force (its gap acceleration 0) or not (its
 * lam 0); each stop with rows carrying force sticks or slides with a sign.
 * A mode is solved exactly (at most 3 independent constraint rows in the
 * plane, ldp_solve_small; a mode with more, or a singular one, is a lock
 * (below) or skipped) and
 * accepted when its signs hold: lam >= -tol_f, the gap accelerations of the
 * rows without force >= -tol_a and, for a rolling stop (SF_ROLL), the mode
 * chosen for it: sticking inside its cone (|beta| <= mu sum lam (1 +
 * FRICTION_BAND)), or sliding with its slip acceleration of the sign of the slide
 * (>= -tol_a). A stop given a mode (SF_STICK, SF_SLIDE_*) keeps it without
 * these checks: its equations stay smooth in time, and the caller's guards
 * (the cone margin, the slip's sign) say when it ends.
 * A mode with more than 3 constraint rows, or 3 whose system is singular,
 * is a lock when the rows carrying force (and the sticking stops' slip
 * rows) fix qdd by themselves (rank 3, the others consistent with them): an
 * object wedged between stops, e.g. a block pressed into a corner, whose
 * slips are then 0 at every instant while the lock holds. Its motion is
 * determined, its forces are not (any split over the stops' cones that
 * gives the required M (qdd - a)): the lock is consistent iff that force
 * lies in the cone of the mode's generators (the rows' G_i +- mu T_k in
 * the friction cones, G_i - mu sigma T_k for a sliding stop, G_i for a
 * frictionless one), with the margin (res.margin, the least signed distance
 * of the force to the cone's facets plus the band FRICTION_BAND of its size) as
 * the caller's guard of it; res.lam, res.beta get one such split (the
 * combination nearest the required force). A lock whose stops all have
 * given modes is kept whatever its margin, like any given mode (the guard
 * ends it). Where a rolling stop is to be decided, locks are tried only
 * after every other mode has failed: a lock's forces include wedge forces
 * that a less constrained consistent mode (a row separating, a stop
 * sliding) does without, so where both are consistent (Coulomb friction's
 * acceleration-level ambiguity) the less constrained one is taken (the
 * Python tests check the choice against the implicit method's velocity-
 * level step on random corner scenes). And in a mode whose
 * three constraints fix qdd, a rolling stop's slip acceleration is the
 * kinematics': one within tol_a of 0 is no slide in either direction (the
 * stop is held, which its stick mode, a lock, describes); a slide of it is
 * accepted only with sigma acct > tol_a. Without the lock such a mode
 * would be skipped as singular and a sticking stop of a wedged object
 * could only be described as sliding with a slip of 0, whose sign is
 * rounding.
 * The modes are enumerated in a fixed order (per stop the given mode, or
 * for a rolling stop: stick, slide +, slide -; the rows: every row carrying
 * force first, then the subsets by a binary count down), the first
 * consistent one is returned. Beyond SF_ENUM_ROWS rows a stop with more
 * than two rows (points on its line) enters the enumeration with its two
 * extreme rows only: every other row's G and gap acceleration is a convex
 * combination of theirs, so a force on the others is one on the extremes;
 * the others carry none and keep their sign check (gap acceleration >=
 * -tol_a). With friction the acceleration-level problem
 * can have no consistent mode (Painleve: a sliding stop whose friction turns
 * the normal force's effect around) or several; the caller decides what to
 * do when none is found. */
#ifndef EXDEX_STOP_FRICTION_H
#define EXDEX_STOP_FRICTION_H

#include "tolerances.h"

#define SF_ENUM_ROWS 8  /* up to this many rows every row's normal modes are enumerated (above: sf_solve) */
#define SF_MAX_ROWS 256 /* rows: every contact row of a planar object (model.h's MAX_ROWS) */
#define SF_MAX_STOPS (SF_MAX_ROWS + 8) /* friction groups ("stops"): the stops (EXDEX_MAX_STOPS) and the
                                          obstacles' contact lines (at most one per row) */

/* Friction mode of a stop (sf_solve's fm). */
enum { SF_ROLL = 0, SF_STICK = 1, SF_SLIDE_P = 2, SF_SLIDE_M = 3, SF_NONE = 4 };

typedef struct sf_row {
    double G[3];    /* d gap / d qdot */
    double gdd0;    /* gap acceleration less G qdd */
    int stop;       /* its stop, 0 .. SF_MAX_STOPS - 1 */
} sf_row;

typedef struct sf_stop {
    double T[3];    /* d slip / d qdot (of the stop's rows) */
    double sdd0;    /* slip acceleration less T qdd */
    double mu;      /* Coulomb coefficient >= 0 (0: frictionless) */
    int fm;         /* SF_ROLL (stick or slide, enumerated), SF_STICK, SF_SLIDE_P (slip > 0, beta =
                       -mu sum lam), SF_SLIDE_M, SF_NONE (frictionless) */
} sf_stop;

typedef struct sf_result {
    double qdd[3];
    double lam[SF_MAX_ROWS];    /* normal force of each row */
    double acc[SF_MAX_ROWS];    /* gap acceleration of each row */
    double beta[SF_MAX_STOPS];  /* tangential force of each stop */
    double lsum[SF_MAX_STOPS];  /* sum of its rows' lam */
    double acct[SF_MAX_STOPS];  /* slip acceleration T qdd + sdd0 of each stop */
    double w[3];                /* the plate's wrench (sf_solve_plate), else 0 */
    int fm[SF_MAX_STOPS];       /* mode found: SF_STICK, SF_SLIDE_P, SF_SLIDE_M, or the given one for a
                                   stop without force (SF_ROLL stays SF_ROLL) */
    int tried;                  /* modes solved */
    int lock;                   /* 1: the mode found is a lock (above) */
    double margin;              /* a lock's margin (>= 0 while consistent), else 0 */
    unsigned mask;              /* a lock's rows (bit i: row i carries force in it), else 0 */
} sf_result;

/* The plate's friction as one more contact of the problem (sf_solve_plate),
 * in a small slip from rest: the ellipsoidal limit surface |E^-1 w| <= cap
 * of the patch wrench w (E = diag(e)), whose generalized force is A w and
 * whose slip is the patch slip u = A^T qdd of the acceleration (the slip's
 * direction is its acceleration's), with maximum dissipation: w = -cap E^2
 * u / |E u|, u != 0. In each mode of the enumeration the constraints make
 * qdd, and so u, affine in w: u = b + W w. With z = E u and the multiplier
 * lam = cap / |z| the plate's condition is (I + lam K) z = E b, K = E W E,
 * and the one scalar equation lam |z(lam)| = cap. Where every stop of the
 * mode carrying force is frictionless or sticks, W is A^T M^-1/2 P M^-1/2 A
 * with P the projection off the mode's constraints: K is symmetric
 * positive semidefinite, lam |z(lam)| increases strictly from 0, and the
 * root is unique; it is bracketed by doubling lam (at most
 * PLATE_BRACKET_MAX trial points) and found by false position (Illinois), to
 * PLATE_ROOT_TOL of cap (at most PLATE_ROOT_MAX steps). With a sliding stop
 * K need not be symmetric and the equation may have several roots: the
 * first (the least lam: the fastest slip, the largest dissipation cap |E
 * u|) is taken, where lam |z| increases (K + I / lam with a positive
 * definite symmetric part) by the bracket below that region's end, else
 * from every root of the equation as the sign changes of a polynomial of
 * degree 6 in 1 / lam (stop_friction.c, plate_root); the bracket is kept
 * before any pole of z (I + lam K singular), next to which lam |z| exceeds
 * cap. In a mode
 * without rows carrying force the plate may hold the object alone: qdd = 0
 * with w = -A^-1 M a where that lies inside the ellipsoid (to
 * FRICTION_BAND; as a friction step sticks), else the root. A mode with
 * rows carrying force and no root (the plate would hold the object, qdd =
 * 0, at rows whose constraints then fix it at rest: a rest on them, not a
 * small slip) is not consistent. A lock's qdd is fixed by its constraints: the plate's
 * wrench is then that of u = A^T qdd (none for u = 0), and its stop forces
 * the lock's. The mode's signs are checked as in sf_solve, at the joint
 * solution; res->w gets the plate's wrench. */
typedef struct sf_plate {
    double A[3][3]; /* A[c][j]: generalized force component c of the unit patch wrench e_j */
    double e[3];    /* the ellipsoid's semi-axes, E = diag(e) */
    double cap;     /* its capacity >= 0 (0: no plate friction, w = 0) */
} sf_plate;

/* Solve the problem of nr rows (<= SF_MAX_ROWS) on ns stops (<= SF_MAX_STOPS;
 * a row's stop indexes st). Returns 1 with a consistent mode in res, 0 when
 * no mode is consistent, nr or ns are out of range, or more than
 * SF_ENUM_ROWS rows remain after the reduction above (res then holds no
 * solution). */
int sf_solve(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3], const double a[3],
             double tol_a, double tol_f, sf_result *res);

/* sf_solve with the plate's friction as one more contact (sf_plate): a the
 * acceleration without the stops and without the plate's friction; the
 * same order of modes, the first consistent one at its own plate wrench
 * (res->w). Returns as sf_solve. */
int sf_solve_plate(int nr, const sf_row *rows, int ns, const sf_stop *st, const double minv[3], const double a[3],
                   const sf_plate *pl, double tol_a, double tol_f, sf_result *res);

/* x with C_l x = rhs_l for all k rows (3 <= k <= SF_MAX_ROWS + SF_MAX_STOPS):
 * solved on the three rows of largest volume (unit rows in the metric
 * diag(minv)^1/2, above SF_LOCK_RANK), every row then checked to |C_l x -
 * rhs_l| <= tol. Returns 0 if the rows have rank below 3 or are
 * inconsistent beyond tol. A lock's acceleration, and its velocity (every
 * row's rate held). */
int sf_lock_solve(int k, const double (*C)[3], const double *rhs, const double minv[3], double tol, double x[3]);

#endif
