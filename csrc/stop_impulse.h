/* stop_impulse.h -- private to the exdex core: the velocity-level (impulse)
 * contact step with Coulomb friction at the contact rows, besides the plate
 * friction with its prescribed normal force. Pure numerics on ldp.h: no
 * model, no allocation, every loop bounded.
 *
 * The problem of one step (n = 1 or 3 free coordinates, M = diag(Md)):
 *     M (v - vs) = P + sum_i (lam_i G_i + beta_i T_i),
 *     plate:   P = -cap A^T A v / |A v| if v != 0, else any P with
 *              |A^-T P| <= cap_rest (maximum dissipation over the ellipsoid,
 *              static capacity cap_rest >= cap at rest;
 *              A = E J_f maps v to the scaled patch slip, so |A^-T P| is
 *              the ellipsoid norm of the plate impulse; or any limit
 *              surface ls: P = cap A^T w(A v), A = J_f, at rest its gauge
 *              g(A^-T P) <= cap_rest),
 *     normal:  0 <= lam_i  _|_  G_i v - rhs_i >= 0,
 *     Coulomb: |beta_i| <= mu_i lam_i, beta_i = -mu_i lam_i sign(s_i) when
 *              the slip s_i = T_i v + tb_i != 0.
 * This is the Stewart-Trinkle / Anitescu-Potra velocity-level form of
 * Coulomb friction with unknown normal forces. At the acceleration level the
 * same contacts can have no solution or several (Painleve's paradoxes: a
 * sliding contact whose friction torque turns the normal force's effect
 * around); at the impulse level a finite impulse over a step always exists
 * for the linear complementarity problem of the stop rows, and the plate
 * term, convex in v, does not change that. Complementarity is exact: the
 * solution is found by enumerating the contact modes (each row separate,
 * sliding +, sliding -, or sticking; the plate at rest or sliding), solving
 * each mode's equations exactly (the sliding plate by Newton's method on its
 * smooth sliding law) and accepting the first mode whose signs all hold: the
 * impulses lam >= 0, the slip directions, the sticking rows inside their
 * cones, the separating rows not penetrating. Nothing is regularised. Where
 * several modes are consistent (non-uniqueness) the order of the
 * enumeration decides: plate rest first (the least plate friction split;
 * in the plane on the ellipsoid with frictional rows, the split of a plate
 * creeping under the load, stop_impulse.c's creep_rest),
 * then the mode guessed from the hint, then the others in a fixed order
 * (per row: the guess, stick, the other slide, separate).
 * The candidates: the hint's rows (at most FC_MAX_CAND), joined by a row a
 * consistent mode violates. Where those give no consistent mode (a row
 * outside the hint must carry an impulse, or the hint has more rows), the
 * wide candidates: every row that may carry an impulse (the hint's, the
 * touching ones, those v0 violates), the rows of one frictional line of
 * contact (points with one normal and one tangent row) by its two extreme
 * rows, at most FC_MAX_WIDE. In the plane at most 3 rows are independent,
 * and on one line G_i = (n, r_i x n) is affine in the point's place: an
 * impulse on an inner point is one on the two extremes. */
#ifndef EXDEX_STOP_IMPULSE_H
#define EXDEX_STOP_IMPULSE_H

#include "ldp.h"
#include "limitsurf.h"

#define FC_MAX_CAND 4  /* rows whose modes are enumerated from the hint (4^4 modes at most) */
#define FC_MAX_WIDE 6  /* rows whose modes are enumerated when those do not suffice (4^6 modes at most) */

typedef struct fc_row {
    double G[3];   /* d gap / d qdot (n entries) */
    double T[3];   /* d slip / d qdot along the row's tangent (n entries) */
    double rhs;    /* the row holds when G v >= rhs */
    double tb;     /* slip at v = 0 */
    double mu;     /* Coulomb coefficient >= 0 */
    int rest;      /* at v = 0: 1 may carry force (touching), 0 carries none, -1 is violated */
} fc_row;

typedef struct fc_problem {
    int n;               /* 1 or 3 */
    double Md[3];        /* diagonal of M, > 0 */
    double vs[3];        /* velocity without plate friction and contacts */
    double A[3][3];      /* plate slip map (n x n, invertible when cap > 0) */
    const limitsurf *ls; /* NULL: the ellipsoid above (A = E J_f, the scaled slip);
                            else the plate's limit surface (limitsurf.h) with A = J_f,
                            the unscaled slip: P = cap J_f^T w(J_f v) sliding, and at
                            rest g(J_f^-T P) <= cap_rest in place of |A^-T P| */
    double cap;          /* plate capacity of the step (an impulse) >= 0: sliding */
    double cap_rest;     /* capacity of the plates' rest test (static friction), >= cap;
                            0: cap */
    double vscale;       /* velocity scale of the tolerances, > 0 */
    double vrest;        /* at rest a row with |tb| <= vrest has a static cone */
    int nr;              /* rows, <= LDP_MAX_ROWS / 2 */
    const fc_row *rows;
} fc_problem;

/* Contact modes of a row (fc_solve's modes array). */
enum { FC_OFF = 0, FC_SLIDE_P = 1, FC_SLIDE_M = 2, FC_STICK = 3 };

typedef struct fc_result {
    double v[3];   /* velocity after the step */
    double P[3];   /* plate friction impulse (generalized) */
    int rest;      /* 1: the plate stuck, v = 0 exactly */
    int iters;     /* Newton iterations and modes tried */
} fc_result;

/* Solve the step. hint (nr flags, may be NULL): rows active in an
 * approximate solution (e.g. the frictionless one), tried first, and v0 a
 * velocity near the solution (the start of Newton's method and of the slip
 * signs of the first guess). modes (nr entries, may be NULL): on entry a
 * row's mode in a previous solution (e.g. the last step), the first guess
 * of an active row whose entry is not FC_OFF (a mode changes rarely from
 * one step to the next: one mode solve instead of an enumeration); on a
 * successful return each row's mode (FC_STICK for a row carrying force at
 * plate rest). lam, beta (nr each) get the impulses. Returns
 * 1 when a consistent mode was found, 0 otherwise (then lam, beta and res
 * hold no solution): no mode of the candidates is consistent (e.g. a jam:
 * friction turning a row's normal impulse around), or the wide candidates
 * exceed FC_MAX_WIDE. */
int fc_solve(const fc_problem *p, const unsigned char *hint, const double v0[3], int *modes, double *lam,
             double *beta, fc_result *res);

#endif
