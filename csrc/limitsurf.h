/* limitsurf.h -- private to the exdex core: the limit surface of a plate
 * contact behind one interface (a method table, as GSL's solver types), with
 * two implementations:
 *
 *   limitsurf_ellipsoid  the paper's Eq. 6: w^T E^-2 w <= C^2, E = diag(1,
 *                        1, e_r); the support function |E u|.
 *   limitsurf_exact      Coulomb friction of uniform pressure over the
 *                        contact region with maximum dissipation: the
 *                        friction wrench of a slip twist u is the integral
 *                        of -(C / A) s / |s| over the region, s(r) = v +
 *                        omega z x r the slip at r; closed forms from
 *                        region.h (edge integrals for polygons, elliptic
 *                        integrals for discs).
 *
 * Conventions. Wrenches w = (f_x, f_y, m_z) [N, N, N m] and slip twists
 * u = (v_x, v_y, omega) [m/s, m/s, rad/s] are taken at the reference point,
 * the origin of the frame the region is given in (for a patch fixed on the
 * object: the centre of pressure, axes of the object frame C). The surface
 * is stored per unit capacity: the set L1 of wrenches one newton of
 * capacity C = mu N can carry; at capacity C it is C L1 (static and kinetic
 * friction are two capacities of one shape). Everything below is per unit
 * capacity unless it takes C.
 *
 *   D(u)      dissipation (support function of L1): max over w in L1 of
 *             w . u, >= 0, positively homogeneous of degree 1, convex;
 *             C D(u) is the power friction dissipates in the slip u
 *             (ellipsoid |E u|; exact (1/A) Int |s(r)| dA).
 *   w(u)      friction wrench of the slip u != 0: -grad D(u), on the
 *             boundary of L1, opposing the slip (w . u = -D(u)); C w(u) at
 *             capacity C. Its Hessian is that of D (degree -1 homogeneous).
 *   g(w)      gauge of a load: the least t >= 0 with w in t L1. The
 *             contact carries the wrench w at capacity C (stick) iff
 *             g(w) <= C: the stick test. g(w) = max over u != 0 of
 *             w . u / D(u).
 *   slip direction of a wrench at the limit: the slip twist u (unit
 *             length) whose friction wrench is w / g(w), i.e. the
 *             direction in which an object slides when the friction it
 *             must supply is w and that reaches the limit. u = -n, n the
 *             outward normal of L1 at w / g(w) (the maximiser of w . u /
 *             D(u)).
 *
 * No allocation, no model: a surface is a small value (limitsurf_set_*),
 * and every loop is bounded (Newton iterations capped at
 * LIMITSURF_MAX_ITER; quadrature of fixed size).
 */
#ifndef EXDEX_LIMITSURF_H
#define EXDEX_LIMITSURF_H

#include "exdex.h"
#include "region.h"

#define LIMITSURF_MAX_ITER 60

struct limitsurf;

typedef struct limitsurf_type {
    const char *name;  /* "ellipsoid", "exact" */
    /* D(u) */
    double (*dissipation)(const struct limitsurf *ls, const double u[3]);
    /* w(u) = -grad D(u) for u != 0 (NaN for u = 0), and hess (NULL: not
     * wanted) the Hessian of D at u, row-major 3x3; returns D(u). */
    double (*wrench)(const struct limitsurf *ls, const double u[3], double w[3], double hess[9]);
    /* g(w); dir (NULL: not wanted) the unit slip direction of w at the limit
     * (NaN for w = 0). Returns EXDEX_OK, EXDEX_EINVAL for non-finite w,
     * EXDEX_ENOCONV if the exact surface's search fails (capped). */
    int (*gauge)(const struct limitsurf *ls, const double w[3], double *g, double dir[3]);
} limitsurf_type;

typedef struct limitsurf {
    const limitsurf_type *type;
    double e[3];      /* ellipsoid: (1, 1, e_r); exact: the ellipsoid of its largest moment
                         about the reference point (e_r = F(0) / A), its warm start */
    region rg;        /* exact: the region (kind REGION_NONE for the ellipsoid) */
    double area;      /* exact: area of the region */
    double g[2];      /* exact: centroid */
    double reach;     /* exact: largest distance of the region from its centroid */
    /* bounds kmin |E u| <= D(u) <= kmax |E u| (E of e; the ellipsoid: 1, 1;
     * the exact surface: 0 and INFINITY until limitsurf_prepare_bounds): the
     * step decides stick or slip from |E^-1 y| alone outside the band they
     * leave, without the gauge's search */
    double kmin, kmax;
} limitsurf;

extern const limitsurf_type limitsurf_ellipsoid;
extern const limitsurf_type limitsurf_exact;

/* The ellipsoid of semi-axis e_r > 0 (finite), or the exact surface of a
 * valid region (region_check). EXDEX_EINVAL otherwise (ls unchanged). */
int limitsurf_set_ellipsoid(limitsurf *ls, double e_r);
int limitsurf_set_exact(limitsurf *ls, const region *rg);

/* The bounds kmin, kmax of an exact surface (see limitsurf), found by
 * sampling D(E^-1 s) over 256 unit s and refining the extremes by a local
 * search, then widened by 1e-3 (the step's decisions from them are
 * certain as long as the sampled extremes are within 1e-3 of the true
 * ones; the band between falls back to the gauge). A few hundred
 * evaluations: once per model. */
void limitsurf_prepare_bounds(limitsurf *ls);

/* Bounds kmin, kmax of an exact surface from a few of its region's
 * integrals in closed form (the polar moment, the centroid, G at the
 * reference point; see limitsurf.c), valid for every region, looser than
 * limitsurf_prepare_bounds's (a uniform disc or square: about 0.71 and
 * 1.07) and about a hundred times cheaper: for a region that changes
 * every step (pads on the fingers). */
void limitsurf_quick_bounds(limitsurf *ls);

/* Shorthands for the table. */
static inline double limitsurf_dissipation(const limitsurf *ls, const double u[3])
{
    return ls->type->dissipation(ls, u);
}
static inline double limitsurf_wrench(const limitsurf *ls, const double u[3], double w[3], double hess[9])
{
    return ls->type->wrench(ls, u, w, hess);
}
static inline int limitsurf_gauge(const limitsurf *ls, const double w[3], double *g, double dir[3])
{
    return ls->type->gauge(ls, w, g, dir);
}

/* The stick test for the certification of reduced runs and the methods:
 * 1 if the load w (the wrench the contact must supply, at the reference
 * point) lies inside the surface of capacity C >= 0 (g(w) <= C), 0 if not,
 * a negative status (-EXDEX_EINVAL, -EXDEX_ENOCONV) if the gauge fails. */
int limitsurf_sticks(const limitsurf *ls, const double w[3], double C);

/* Slip direction at the limit (see above): unit u, NaN for w = 0. */
int limitsurf_slip_direction(const limitsurf *ls, const double w[3], double u[3]);

/* The gauge g(w) (w != 0), its gradient (the unit-dissipation normal u* /
 * D(u*) of the gauge's maximiser u*) and its Hessian (hess may be NULL),
 * row-major 3x3, symmetric, w its null vector. Statuses as the gauge's,
 * EXDEX_ENOCONV also where the Hessian is singular. */
int limitsurf_gauge_hessian(const limitsurf *ls, const double w[3], double *g, double grad[3], double hess[9]);

/* The least gauge of a load given up to a combination of stop forces:
 * min g(a + sum_j lam_j b_j) over lam >= 0 (k <= LDP_MAX_ROWS vectors
 * b_j), lam (k entries) its minimiser; the stick test of a rest against
 * stops is that minimum <= cap. The ellipsoid: ldp_min_combination in E^-1
 * coordinates, as the methods form it. The exact surface: from that
 * ellipsoid solution, Newton steps (the ellipsoid problems of the local
 * quadratic model of g^2 / 2) with a line search, until the decrease stops
 * or the gauge falls to cap (a combination the surface carries: the test is
 * decided); where the ellipsoid's minimum exceeds cap kmax it returns that
 * minimum / kmax (a lower bound above cap) without iterating; cap NaN
 * asks for the minimum itself (no early return). NaN if the gauge fails. iters (may be NULL) gets the NNLS iterations added. */
double limitsurf_min_combination(const limitsurf *ls, int k, const double a[3], const double (*b)[3], double cap,
                                 double *lam, int *iters);

/* One implicit friction step with this surface (the problem of
 * exdex_friction_solve): u+ = b + W p, p the friction impulse of capacity
 * cap = h C >= 0 that minimises p . u+ over cap L1. Stick iff g(W^-1 b) <=
 * cap (p = -W^-1 b, u+ = 0 exactly); otherwise u+ minimises the strictly
 * convex 0.5 (u - b)^T W^-1 (u - b) + cap D(u) (Newton with a backtracking
 * line search, warm-started from the ellipsoid's solution of prep) and
 * p = cap w(u+). prep is the ellipsoid problem of W and this surface's e
 * (exdex_friction_prepare): for the ellipsoid the step is
 * exdex_friction_solve(prep, b, cap, solver, ws, warm, res) itself (warm a
 * guess of p). For the exact surface warm (may be NULL) is a guess of the
 * slip twist's direction (e.g. the last step's u+), used when the reduced
 * problem is positive there. res as for exdex_friction_solve (sigma =
 * D(u+)); returns its statuses. */
int limitsurf_step(const limitsurf *ls, const exdex_friction_prep *prep, const double b[3], double cap, int solver,
                   exdex_friction_ws *ws, const double *warm, exdex_friction_result *res);

#endif
