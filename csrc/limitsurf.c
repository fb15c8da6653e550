/* limitsurf.c -- the limit surface interface and its two implementations
 * (limitsurf.h).
 *
 * Exact surface, closed form. For a slip twist u = (v, omega) with omega
 * != 0 the slip v + omega z x r vanishes at the instantaneous centre
 * c = z x v / omega = (-v_y, v_x) / omega, and s(r) = omega z x (r - c), so
 * with the region integrals at c (region.h: F, G, H) and sgn = sign(omega):
 *   D(u)   = |omega| F / A,
 *   f      = -(sgn / A) z x G,
 *   m      = -(sgn / A) Int r . (r - c) / |r - c| dA = -(sgn / A) (F + c . G),
 *   Hess D = (1 / (A |omega|)) M H M^T,  M = [[1, 0], [0, 1], [-c_y, c_x]]
 * (the slip's unit tangent x/|x| carries the twist J_r^T x/|x| = M x/|x|,
 * and Hess D = (1/A) Int J_r^T (I - s s^T/|s|^2) J_r / |s| dA).
 *
 * Exact surface, nearly translating slips. When the instantaneous centre
 * lies far from the region (the slip at the centroid exceeds LS_FAR_RATIO
 * times |omega| times the region's reach, which includes omega = 0), the
 * closed forms cancel (their terms grow like |c|^2 while the moment about
 * the centroid shrinks like 1 / |c|: at LS_FAR_RATIO = 16 they lose about
 * 16^2 rounding units), but the integrand s / |s| is smooth over the
 * region: a fixed product Gauss rule (6 x 6 Gauss-Legendre points on each
 * triangle of the fan from the first vertex, collapsed; a disc 6 Gauss points
 * in the radius times 12 in the angle, trapezoidal) integrates it to
 * rounding: the integrand is analytic in a neighbourhood LS_FAR_RATIO - 1
 * region sizes wide, so 6-point Gauss converges like (2 LS_FAR_RATIO)^-12 <
 * 1e-18 and the periodic trapezoid like LS_FAR_RATIO^-12 < 4e-15.
 *
 * Exact gauge. g(w) = 1 / min { D(u) : w . u = 1 } (the polar of the
 * support function), a smooth strictly convex problem in the plane
 * w . u = 1: Newton on its two coordinates with a backtracking line search,
 * from the ellipsoid's minimiser E^-2 w / (w^T E^-2 w). The minimiser is
 * the outward normal at w / g(w); the slip direction is its opposite.
 *
 * Exact step. The slip u minimises the strictly convex 0.5 (u - b)^T W^-1
 * (u - b) + cap D(u) (stick iff the minimum is u = 0, i.e. g(W^-1 b) <=
 * cap). Newton on u itself stalls: the objective is a cone near u = 0 and
 * its Hessian (that of D, degree -1) blows up there, so Newton's radial
 * steps overshoot through 0 when the slip is small. With u = t d the
 * optimal t for a direction d is (d . y - cap D(d)) / (d^T W^-1 d), y =
 * W^-1 b, leaving a smooth problem in the direction alone (see reduced),
 * solved by Newton on the unit sphere from the gauge's normal at y (the
 * gauge is warm-started from the ellipsoid of the surface's largest
 * moment).
 */
#include "limitsurf.h"

#include "util.h"
#include "ldp.h"
#include "tolerances.h"

#include <float.h>
#include <math.h>
#include <string.h>


/* The tolerances and budgets of the quadrature, the Newton iterations and
 * the gauge's bounds (LS_*) are entries of tolerances.h. */
#define NGL 6
#define NTH 12

static const double PI = 3.14159265358979323846;

/* 6-point Gauss-Legendre on [-1, 1]: nodes +-x_i, weights w_i */
static const double GLX[3] = {0.2386191860831969, 0.66120938646626448, 0.93246951420315194};
static const double GLW[3] = {0.46791393457269104, 0.36076157304813872, 0.17132449237917027};

/* the disc's NTH = 12 angles (j + 1/2) 30 degrees */
#define C15 0.96592582628906831
#define S15 0.25881904510252074
#define C45 0.70710678118654757
static const double TH_COS[NTH] = {C15, C45, S15, -S15, -C45, -C15, -C15, -C45, -S15, S15, C45, C15};
static const double TH_SIN[NTH] = {S15, C45, C15, C15, C45, S15, -S15, -C45, -C15, -C15, -C45, -S15};

/* node k (0 .. NGL-1) on [0, 1] and its weight */
static void gl01(int k, double *x, double *w)
{
    int i = k < 3 ? 2 - k : k - 3;
    double t = k < 3 ? -GLX[i] : GLX[i];
    *x = 0.5 * (1.0 + t);
    *w = 0.5 * GLW[i];
}

static void plane_basis(const double n[3], double N[2][3]);

/* ------------------------------------------------------------ ellipsoid */

static double ell_dissipation(const limitsurf *ls, const double u[3])
{
    double a = ls->e[0] * u[0], b = ls->e[1] * u[1], c = ls->e[2] * u[2];
    return sqrt(a * a + b * b + c * c);
}

static double ell_wrench(const limitsurf *ls, const double u[3], double w[3], double hess[9])
{
    const double *e = ls->e;
    double eu[3], sig;
    for (int i = 0; i < 3; i++) eu[i] = e[i] * u[i];
    sig = sqrt(ex_dot3(eu, eu));
    for (int i = 0; i < 3; i++) w[i] = -e[i] * eu[i] / sig;
    if (hess)
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                hess[3 * i + j] = ((i == j ? e[i] * e[i] : 0.0) - (e[i] * eu[i]) * (e[j] * eu[j]) / (sig * sig)) / sig;
    return sig;
}

static int ell_gauge(const limitsurf *ls, const double w[3], double *g, double dir[3])
{
    const double *e = ls->e;
    if (!ex_finite_n(w, 3)) return EXDEX_EINVAL;
    double a = w[0] / e[0], b = w[1] / e[1], c = w[2] / e[2];
    *g = sqrt(a * a + b * b + c * c);
    if (dir) {
        /* outward normal at w: E^-2 w; the slip opposes it */
        double n[3] = {a / e[0], b / e[1], c / e[2]}, nn = sqrt(ex_dot3(n, n));
        for (int i = 0; i < 3; i++) dir[i] = nn > 0.0 ? -n[i] / nn : NAN;
    }
    return EXDEX_OK;
}

const limitsurf_type limitsurf_ellipsoid = {"ellipsoid", ell_dissipation, ell_wrench, ell_gauge};

/* ------------------------------------------------------------ exact */

/* Quadrature of the smooth integrand (far instantaneous centre): D, w and
 * the Hessian. */
static void quad_add(const double r[2], double wt, const double u[3], double *D, double w[3], double *hess)
{
    double sx = u[0] - u[2] * r[1], sy = u[1] + u[2] * r[0], s = sqrt(sx * sx + sy * sy);
    double hx = sx / s, hy = sy / s;
    *D += wt * s;
    w[0] -= wt * hx;
    w[1] -= wt * hy;
    w[2] -= wt * (r[0] * hy - r[1] * hx);
    if (hess) {
        /* J_r^T t, t = (-hy, hx) the unit tangent */
        double a[3] = {-hy, hx, -r[1] * -hy + r[0] * hx}, k = wt / s;
        for (int i = 0; i < 3; i++)
            for (int j = i; j < 3; j++) hess[3 * i + j] += k * a[i] * a[j];
    }
}

static double exact_quad(const limitsurf *ls, const double u[3], double w[3], double hess[9])
{
    const region *rg = &ls->rg;
    double D = 0.0;
    w[0] = w[1] = w[2] = 0.0;
    if (hess)
        for (int i = 0; i < 9; i++) hess[i] = 0.0;
    if (rg->kind == REGION_DISC) {
        double R = rg->r;
        for (int a = 0; a < NGL; a++) {
            double x, wx;
            gl01(a, &x, &wx);
            double rho = R * x, wr = R * wx * rho * (2.0 * PI / NTH);
            for (int j = 0; j < NTH; j++) {
                double r[2] = {rg->c[0] + rho * TH_COS[j], rg->c[1] + rho * TH_SIN[j]};
                quad_add(r, wr, u, &D, w, hess);
            }
        }
    } else {
        /* the fan from vertex 0 (n - 2 triangles: the integrand is smooth
         * over the whole region, no point of it is special) */
        const double *g = rg->v[0];
        for (int i = 1; i + 1 < rg->n; i++) {
            const double *p = rg->v[i], *q = rg->v[i + 1];
            double ax = p[0] - g[0], ay = p[1] - g[1], ex = q[0] - p[0], ey = q[1] - p[1];
            double at2 = ax * ey - ay * ex; /* twice the triangle's area */
            if (!(at2 > 0.0)) continue;
            for (int a = 0; a < NGL; a++) {
                double xi, wxi;
                gl01(a, &xi, &wxi);
                for (int b = 0; b < NGL; b++) {
                    double eta, weta;
                    gl01(b, &eta, &weta);
                    double r[2] = {g[0] + xi * (ax + eta * ex), g[1] + xi * (ay + eta * ey)};
                    quad_add(r, wxi * weta * at2 * xi, u, &D, w, hess);
                }
            }
        }
    }
    double inv = 1.0 / ls->area;
    for (int i = 0; i < 3; i++) w[i] *= inv;
    if (hess)
        for (int i = 0; i < 3; i++)
            for (int j = i; j < 3; j++) hess[3 * j + i] = hess[3 * i + j] *= inv;  /* upper, mirrored */
    return D * inv;
}

static int exact_far(const limitsurf *ls, const double u[3])
{
    double sx = u[0] - u[2] * ls->g[1], sy = u[1] + u[2] * ls->g[0];
    return hypot(sx, sy) > LS_FAR_RATIO * ls->reach * fabs(u[2]);
}

static double exact_wrench(const limitsurf *ls, const double u[3], double w[3], double hess[9])
{
    if (u[0] == 0.0 && u[1] == 0.0 && u[2] == 0.0) {
        w[0] = w[1] = w[2] = NAN;
        if (hess)
            for (int i = 0; i < 9; i++) hess[i] = NAN;
        return 0.0;
    }
    if (exact_far(ls, u)) return exact_quad(ls, u, w, hess);
    double om = u[2], c[2] = {-u[1] / om, u[0] / om}, A = ls->area, sg = om > 0.0 ? 1.0 : -1.0;
    region_moments mo;
    if (region_moments_at(&ls->rg, c, &mo) != EXDEX_OK) {
        w[0] = w[1] = w[2] = NAN;
        return NAN;
    }
    w[0] = sg * mo.dir[1] / A;
    w[1] = -sg * mo.dir[0] / A;
    w[2] = -sg * (mo.dist + c[0] * mo.dir[0] + c[1] * mo.dir[1]) / A;
    if (hess) {
        double M[3][2] = {{1, 0}, {0, 1}, {-c[1], c[0]}}, H[2][2] = {{mo.dyad[0], mo.dyad[1]}, {mo.dyad[1], mo.dyad[2]}};
        double k = 1.0 / (A * fabs(om));
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double s = 0.0;
                for (int a = 0; a < 2; a++)
                    for (int b = 0; b < 2; b++) s += M[i][a] * H[a][b] * M[j][b];
                hess[3 * i + j] = k * s;
            }
    }
    return fabs(om) * mo.dist / A;
}

static double exact_dissipation(const limitsurf *ls, const double u[3])
{
    double w[3];
    if (u[0] == 0.0 && u[1] == 0.0 && u[2] == 0.0) return 0.0;
    return exact_wrench(ls, u, w, NULL);
}

/* Solve the symmetric positive definite n x n system A x = r (n <= 3) by
 * Cholesky; 0 if A is not positive definite to working precision. */
static int spd_solve(int n, const double *A, const double *r, double *x)
{
    double L[9] = {0};
    for (int i = 0; i < n; i++)
        for (int j = 0; j <= i; j++) {
            double s = A[n * i + j];
            for (int k = 0; k < j; k++) s -= L[3 * i + k] * L[3 * j + k];
            if (i == j) {
                if (!(s > 0.0)) return 0;
                L[3 * i + i] = sqrt(s);
            } else {
                L[3 * i + j] = s / L[3 * j + j];
            }
        }
    double y[3];
    for (int i = 0; i < n; i++) {
        double s = r[i];
        for (int k = 0; k < i; k++) s -= L[3 * i + k] * y[k];
        y[i] = s / L[3 * i + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = y[i];
        for (int k = i + 1; k < n; k++) s -= L[3 * k + i] * x[k];
        x[i] = s / L[3 * i + i];
    }
    return 1;
}

/* Backtracking (Armijo) along a damped Newton step of squared decrement
 * lam2 > 0: the first t = 2^-k, k < 40, with phi(t) <= phi0 - t lam2 / 4
 * (2^-40 if none), or t = 1 without a search (search 0: the quadratic
 * range, where the decrease is below the rounding of phi). phi(t) is the
 * objective minimised, at the step t. */
static double armijo(double (*phi)(void *ctx, double t), void *ctx, double phi0, double lam2, int search)
{
    double t = 1.0;
    for (int k = 0; k < LS_ARMIJO_MAX && search; k++) {
        if (phi(ctx, t) <= phi0 - LS_ARMIJO_DECREASE * t * lam2) break;
        t *= 0.5;
    }
    return t;
}

/* The gauge's line: D at u0 + (z + t dz) in the plane's basis N. */
typedef struct gauge_line {
    const limitsurf *ls;
    const double *u0, *z, *dz;
    const double (*N)[3];
} gauge_line;

static double gauge_line_at(void *ctx, double t)
{
    const gauge_line *g = ctx;
    double ut[3];
    for (int i = 0; i < 3; i++)
        ut[i] = g->u0[i] + (g->z[0] + t * g->dz[0]) * g->N[0][i] + (g->z[1] + t * g->dz[1]) * g->N[1][i];
    return exact_dissipation(g->ls, ut);
}

static int exact_gauge(const limitsurf *ls, const double w[3], double *g, double dir[3])
{
    if (!ex_finite_n(w, 3)) return EXDEX_EINVAL;
    double nw = sqrt(ex_dot3(w, w));
    if (!(nw > 0.0)) {
        *g = 0.0;
        if (dir) dir[0] = dir[1] = dir[2] = NAN;
        return EXDEX_OK;
    }
    /* scale: w / |w| (the gauge is homogeneous) */
    double n[3] = {w[0] / nw, w[1] / nw, w[2] / nw}, N[2][3], z[2], u0[3], u[3];
    /* an orthonormal basis of the plane n . u = 0 */
    {
        int k = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0 : fabs(n[1]) <= fabs(n[2]) ? 1 : 2;
        double a[3] = {0, 0, 0}, d;
        a[k] = 1.0;
        d = a[0] * n[0] + a[1] * n[1] + a[2] * n[2];
        for (int i = 0; i < 3; i++) N[0][i] = a[i] - d * n[i];
        d = sqrt(ex_dot3(N[0], N[0]));
        for (int i = 0; i < 3; i++) N[0][i] /= d;
        N[1][0] = n[1] * N[0][2] - n[2] * N[0][1];
        N[1][1] = n[2] * N[0][0] - n[0] * N[0][2];
        N[1][2] = n[0] * N[0][1] - n[1] * N[0][0];
    }
    /* start: the ellipsoid's minimiser E^-2 n / (n^T E^-2 n) */
    {
        double en[3], s;
        for (int i = 0; i < 3; i++) en[i] = n[i] / (ls->e[i] * ls->e[i]);
        s = ex_dot3(en, n);
        for (int i = 0; i < 3; i++) en[i] /= s;
        z[0] = ex_dot3(N[0], en);
        z[1] = ex_dot3(N[1], en);
        for (int i = 0; i < 3; i++) u0[i] = n[i];
    }
    double D = 0.0, wu[3], Hu[9], lam2_prev = INFINITY;
    int ok = 0;
    for (int it = 0; it < LIMITSURF_MAX_ITER; it++) {
        for (int i = 0; i < 3; i++) u[i] = u0[i] + z[0] * N[0][i] + z[1] * N[1][i];
        D = exact_wrench(ls, u, wu, Hu);
        if (!isfinite(D)) return EXDEX_ENOCONV;
        /* grad D = -w */
        double gz[2], Hz[4], dz[2], t, lam2;
        for (int a = 0; a < 2; a++) {
            gz[a] = -ex_dot3(N[a], wu);
            for (int b = 0; b < 2; b++) {
                double s = 0.0;
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) s += N[a][i] * Hu[3 * i + j] * N[b][j];
                Hz[2 * a + b] = s;
            }
        }
        double mg[2] = {-gz[0], -gz[1]};
        if (!spd_solve(2, Hz, mg, dz)) return EXDEX_ENOCONV;
        lam2 = -(gz[0] * dz[0] + gz[1] * dz[1]);
        if (lam2 <= LS_NEWTON_DONE * D || (lam2 <= LS_NEWTON_FULL * D && lam2 > LS_NEWTON_QUADRATIC * lam2_prev)) {
            ok = 1;
            break;
        }
        lam2_prev = lam2;
        /* backtracking (Armijo), except in the quadratic range where the
         * decrease is below the rounding of D */
        {
            gauge_line gl = {ls, u0, z, dz, (const double (*)[3])N};
            t = armijo(gauge_line_at, &gl, D, lam2, lam2 > LS_NEWTON_FULL * D);
        }
        z[0] += t * dz[0];
        z[1] += t * dz[1];
        if (t < LS_LINE_STEP_MIN) {
            /* no decrease to rounding: at the minimum to working precision */
            for (int i = 0; i < 3; i++) u[i] = u0[i] + z[0] * N[0][i] + z[1] * N[1][i];
            D = exact_dissipation(ls, u);
            ok = lam2 <= LS_NEWTON_ACCEPT * D;
            break;
        }
    }
    if (!ok || !(D > 0.0)) return EXDEX_ENOCONV;
    *g = nw / D;
    if (dir) {
        double nu = sqrt(ex_dot3(u, u));
        for (int i = 0; i < 3; i++) dir[i] = -u[i] / nu;
    }
    return EXDEX_OK;
}

const limitsurf_type limitsurf_exact = {"exact", exact_dissipation, exact_wrench, exact_gauge};

/* ------------------------------------------------------------ set-up */

int limitsurf_set_ellipsoid(limitsurf *ls, double e_r)
{
    if (!(e_r > 0.0) || !isfinite(e_r)) return EXDEX_EINVAL;
    memset(ls, 0, sizeof *ls);
    ls->type = &limitsurf_ellipsoid;
    ls->e[0] = ls->e[1] = 1.0;
    ls->e[2] = e_r;
    ls->rg.kind = REGION_NONE;
    ls->kmin = ls->kmax = 1.0;
    return EXDEX_OK;
}

int limitsurf_set_exact(limitsurf *ls, const region *rg)
{
    if (region_check(rg) != EXDEX_OK) return EXDEX_EINVAL;
    double o[2] = {0.0, 0.0}, er = region_mean_distance(rg, o);
    if (!(er > 0.0) || !isfinite(er)) return EXDEX_EINVAL;
    memset(ls, 0, sizeof *ls);
    ls->type = &limitsurf_exact;
    ls->rg = *rg;
    ls->area = region_area(rg);
    region_centroid(rg, ls->g);
    ls->reach = region_reach(rg, ls->g);
    ls->e[0] = ls->e[1] = 1.0;
    ls->e[2] = er;
    ls->kmin = 0.0;
    ls->kmax = INFINITY;
    return EXDEX_OK;
}

/* D(E^-1 s) for the unit E-space direction s */
static double kratio(const limitsurf *ls, const double s[3])
{
    double d[3] = {s[0] / ls->e[0], s[1] / ls->e[1], s[2] / ls->e[2]}, n = sqrt(ex_dot3(s, s));
    return exact_dissipation(ls, d) / n;
}

/* local search on the sphere from s for the minimum (sign 1) or maximum (-1) */
static double krefine(const limitsurf *ls, double s[3], int sign)
{
    double best = sign * kratio(ls, s), h = LS_REFINE_STEP;
    for (int it = 0; it < LS_REFINE_MAX && h > LS_REFINE_STEP_MIN; it++) {
        double N[2][3], ns = sqrt(ex_dot3(s, s)), n[3] = {s[0] / ns, s[1] / ns, s[2] / ns};
        int moved = 0;
        plane_basis(n, N);
        for (int k = 0; k < 4 && !moved; k++) {
            double t[3], a = k < 2 ? 1.0 : -1.0;
            for (int i = 0; i < 3; i++) t[i] = n[i] + a * h * N[k % 2][i];
            double v = sign * kratio(ls, t);
            if (v < best) {
                best = v;
                for (int i = 0; i < 3; i++) s[i] = t[i];
                moved = 1;
            }
        }
        if (!moved) h *= 0.5;
    }
    return sign * best;
}

void limitsurf_prepare_bounds(limitsurf *ls)
{
    if (ls->type != &limitsurf_exact) return;
    double lo = INFINITY, hi = 0.0, slo[3] = {1, 0, 0}, shi[3] = {1, 0, 0};
    const int n = LS_BOUND_LATTICE;
    for (int i = 0; i < n; i++) {
        /* a Fibonacci lattice on the unit sphere */
        double z = 1.0 - (2.0 * i + 1.0) / n, r = sqrt(1.0 - z * z), ph = 2.399963229728653 * i;
        double s[3] = {r * cos(ph), r * sin(ph), z}, v = kratio(ls, s);
        if (v < lo) lo = v, slo[0] = s[0], slo[1] = s[1], slo[2] = s[2];
        if (v > hi) hi = v, shi[0] = s[0], shi[1] = s[1], shi[2] = s[2];
    }
    lo = fmin(lo, krefine(ls, slo, 1));
    hi = fmax(hi, krefine(ls, shi, -1));
    if (!(lo > 0.0) || !isfinite(hi)) return; /* keep the gauge for every decision */
    ls->kmin = lo * (1.0 - LS_SAMPLED_BOUND_MARGIN);
    ls->kmax = hi * (1.0 + LS_SAMPLED_BOUND_MARGIN);
}

void limitsurf_quick_bounds(limitsurf *ls)
{
    if (ls->type != &limitsurf_exact) return;
    const region *rg = &ls->rg;
    const double o[2] = {0.0, 0.0};
    double A = ls->area, er = ls->e[2], J, gn, gam, a, b, kmin, kmax;
    region_moments mo;
    /* J: the polar moment of the region about the reference point */
    if (rg->kind == REGION_DISC) {
        J = 0.5 * PI * rg->r * rg->r * rg->r * rg->r + A * (rg->c[0] * rg->c[0] + rg->c[1] * rg->c[1]);
    } else {
        double s = 0.0;
        for (int i = 0; i < rg->n; i++) {
            const double *p = rg->v[i], *q = rg->v[i + 1 == rg->n ? 0 : i + 1];
            double cr = p[0] * q[1] - q[0] * p[1];
            s += cr * (p[0] * p[0] + p[0] * q[0] + q[0] * q[0] + p[1] * p[1] + p[1] * q[1] + q[1] * q[1]);
        }
        J = s / 12.0;
    }
    if (region_moments_at(rg, o, &mo) != EXDEX_OK) return;
    gn = hypot(ls->g[0], ls->g[1]);
    gam = fmin(1.0, hypot(mo.dir[0], mo.dir[1]) / A);
    if (!(gam >= 0.0) || !isfinite(J) || !(J > 0.0) || !isfinite(gn)) return;
    /* u = (v, omega) at the reference point, x = |v|, y = e_r |omega|
     * (|E u|^2 = x^2 + y^2), g the centroid, s(r) = v + omega z x r:
     *   above: D <= x + y (|s| <= |v| + |omega| |r|), and D^2 <= mean |s|^2
     *   = |v|^2 + 2 omega v . (z x g) + omega^2 J / A (Jensen) <= the form
     *   [[1, a], [a, b]] of (x, y), a = |g| / e_r, b = J / (A e_r^2);
     *   below: D >= |mean s| >= x - a y, and D = |omega| F(c) / A >= y -
     *   gam x (F convex: F(c) >= F(0) - G(0) . c, |c| = |v| / |omega|,
     *   gam = |G(0)| / A), whose larger is least where they cross. */
    a = gn / er;
    b = J / (A * er * er);
    kmax = fmin(sqrt(2.0), sqrt(0.5 * ((1.0 + b) + sqrt((1.0 - b) * (1.0 - b) + 4.0 * a * a))));
    kmin = (1.0 - a * gam) / sqrt((1.0 + a) * (1.0 + a) + (1.0 + gam) * (1.0 + gam));
    if (!(kmin > 0.0) || !isfinite(kmax)) return;
    ls->kmin = kmin * (1.0 - LS_CLOSED_BOUND_MARGIN);
    ls->kmax = kmax * (1.0 + LS_CLOSED_BOUND_MARGIN);
}

int limitsurf_sticks(const limitsurf *ls, const double w[3], double C)
{
    double g;
    int st = limitsurf_gauge(ls, w, &g, NULL);
    if (st != EXDEX_OK) return -st;
    return g <= C;
}

int limitsurf_slip_direction(const limitsurf *ls, const double w[3], double u[3])
{
    double g;
    return limitsurf_gauge(ls, w, &g, u);
}

/* limitsurf_gauge_hessian from the gauge g of w and its slip direction dir
 * (limitsurf_gauge's outputs at w) */
static int gauge_hessian_at(const limitsurf *ls, const double w[3], const double *g, const double dir[3],
                            double grad[3], double hess[9])
{
    double u[3], wu[3], HD[9], Ds, n[3], wh[3], nw, nn, Z[2][3], Y[2][3], M2[4], R2[4], S[4], det;
    if (!(*g > 0.0) || !isfinite(*g)) return EXDEX_ENOCONV;
    for (int i = 0; i < 3; i++) u[i] = -dir[i];
    Ds = limitsurf_wrench(ls, u, wu, HD);
    if (!(Ds > 0.0) || !isfinite(Ds)) return EXDEX_ENOCONV;
    /* grad g = n = u* / D(u*) (the gauge's maximiser u*); with w^ = w / g on
     * the surface, grad D(grad g(w)) = w / g(w) differentiated gives
     * Hess D(n) Hess g(w^) = I - w^ n^T, Hess D(n) = D(u*) Hess D(u*);
     * Hess g is symmetric with null vector w^: Hess g = Z S Z^T (Z a basis
     * of the plane orthogonal to w^), S from that equation's Y^T (.) Z part
     * (Y a basis of the plane orthogonal to n, where Hess D(n) acts), and
     * Hess g(w) = Hess g(w^) / g (degree -1) */
    for (int i = 0; i < 3; i++) {
        n[i] = u[i] / Ds;
        wh[i] = w[i] / *g;
        grad[i] = n[i];
    }
    if (!hess) return EXDEX_OK;
    nw = sqrt(ex_dot3(wh, wh));
    nn = sqrt(ex_dot3(n, n));
    {
        double a[3] = {wh[0] / nw, wh[1] / nw, wh[2] / nw}, b[3] = {n[0] / nn, n[1] / nn, n[2] / nn};
        plane_basis(a, Z);
        plane_basis(b, Y);
    }
    for (int r = 0; r < 2; r++)
        for (int c = 0; c < 2; c++) {
            double hz[3], yw = ex_dot3(Y[r], wh), nz = ex_dot3(n, Z[c]);
            for (int i = 0; i < 3; i++) hz[i] = Ds * (HD[3 * i] * Z[c][0] + HD[3 * i + 1] * Z[c][1] + HD[3 * i + 2] * Z[c][2]);
            M2[2 * r + c] = ex_dot3(Y[r], hz);
            R2[2 * r + c] = ex_dot3(Y[r], Z[c]) - yw * nz;
        }
    det = M2[0] * M2[3] - M2[1] * M2[2];
    if (!(fabs(det) > 0.0) || !isfinite(det)) return EXDEX_ENOCONV;
    S[0] = (M2[3] * R2[0] - M2[1] * R2[2]) / det;
    S[1] = (M2[3] * R2[1] - M2[1] * R2[3]) / det;
    S[2] = (-M2[2] * R2[0] + M2[0] * R2[2]) / det;
    S[3] = (-M2[2] * R2[1] + M2[0] * R2[3]) / det;
    S[1] = S[2] = 0.5 * (S[1] + S[2]);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double h = 0.0;
            for (int a = 0; a < 2; a++)
                for (int b = 0; b < 2; b++) h += Z[a][i] * S[2 * a + b] * Z[b][j];
            hess[3 * i + j] = h / *g;
        }
    return EXDEX_OK;
}

int limitsurf_gauge_hessian(const limitsurf *ls, const double w[3], double *g, double grad[3], double hess[9])
{
    double dir[3];
    int st = limitsurf_gauge(ls, w, g, dir);
    if (st != EXDEX_OK) return st;
    return gauge_hessian_at(ls, w, g, dir, grad, hess);
}

/* g(a + sum_j lam_j b_j), dir its slip direction (limitsurf_gauge) */
static int comb_gauge(const limitsurf *ls, int k, const double a[3], const double (*b)[3], const double *lam,
                      double w[3], double *g, double dir[3])
{
    for (int i = 0; i < 3; i++) {
        w[i] = a[i];
        for (int j = 0; j < k; j++) w[i] += lam[j] * b[j][i];
    }
    return limitsurf_gauge(ls, w, g, dir);
}

double limitsurf_min_combination(const limitsurf *ls, int k, const double a[3], const double (*b)[3], double cap,
                                 double *lam, int *iters)
{
    double ta[3], tb[LDP_MAX_ROWS][3], lnew[LDP_MAX_ROWS], w[3], dir[3], g, ge;
    int it = 0;
    if (k > LDP_MAX_ROWS) return NAN;
    /* the ellipsoid of e first: min |E^-1 (a + B^T lam)| */
    for (int i = 0; i < 3; i++) {
        ta[i] = a[i] / ls->e[i];
        for (int j = 0; j < k; j++) tb[j][i] = b[j][i] / ls->e[i];
    }
    ge = ldp_min_combination(k, ta, (const double (*)[3])tb, lam, &it);
    if (iters) *iters += it;
    if (ls->type != &limitsurf_exact) return ge;
    /* the gauge lies in [|E^-1 w| / kmax, |E^-1 w| / kmin]: no combination
     * is carried where the ellipsoid's least one exceeds cap kmax */
    if (!isnan(cap) && !(ge <= cap * ls->kmax)) return ge / ls->kmax;
    if (comb_gauge(ls, k, a, b, lam, w, &g, dir) != EXDEX_OK) return NAN;
    /* SQP on g^2 / 2, degree-2 homogeneous: its second-order model at w is
     * the quadratic form w'^T Q w' / 2 exactly, Q = grad g grad g^T + g Hess
     * g (positive definite: Hess g's null vector w has grad g . w = g > 0),
     * so each step is the ellipsoid problem of Q (ldp_min_combination after
     * a Cholesky factor), damped along the segment to it */
    for (int round = 0; round < 30 && !(g <= cap); round++) {
        double gr[3], H[9], Q[9], L[9] = {0}, gt = g, wt[3], dt[3], gm;
        /* g and dir are the gauge's at w (no second gauge solve) */
        if (gauge_hessian_at(ls, w, &g, dir, gr, H) != EXDEX_OK) break;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) Q[3 * i + j] = gr[i] * gr[j] + g * H[3 * i + j];
        /* Q = L L^T; the model's norm is |L^T w'| */
        {
            int ok = 1;
            for (int i = 0; i < 3 && ok; i++)
                for (int j = 0; j <= i; j++) {
                    double sum = Q[3 * i + j];
                    for (int c = 0; c < j; c++) sum -= L[3 * i + c] * L[3 * j + c];
                    if (i == j) {
                        if (!(sum > 0.0)) ok = 0;
                        else L[3 * i + i] = sqrt(sum);
                    } else {
                        L[3 * i + j] = sum / L[3 * j + j];
                    }
                }
            if (!ok) break;
        }
        for (int i = 0; i < 3; i++) {
            ta[i] = 0.0;
            for (int c = i; c < 3; c++) ta[i] += L[3 * c + i] * a[c];
            for (int j = 0; j < k; j++) {
                tb[j][i] = 0.0;
                for (int c = i; c < 3; c++) tb[j][i] += L[3 * c + i] * b[j][c];
            }
        }
        it = 0;
        gm = ldp_min_combination(k, ta, (const double (*)[3])tb, lnew, &it);
        if (iters) *iters += it;
        /* the model's least value: no decrease beyond rounding predicted,
         * the minimum to working precision (no line search to fail) */
        if (!(gm < g * (1.0 - LS_COMB_PREDICTED))) break;
        {
            double t = 1.0, lt[LDP_MAX_ROWS];
            int moved = 0;
            for (int ls_it = 0; ls_it < LS_COMB_HALVINGS; ls_it++) {
                for (int j = 0; j < k; j++) lt[j] = lam[j] + t * (lnew[j] - lam[j]);
                if (comb_gauge(ls, k, a, b, lt, wt, &gt, dt) != EXDEX_OK) break;
                if (gt < g) {
                    moved = 1;
                    break;
                }
                t *= 0.5;
            }
            if (!moved) break;
            memcpy(lam, lt, (size_t)k * sizeof *lam);
            memcpy(w, wt, sizeof w);
            memcpy(dir, dt, sizeof dir);
            if (!(g - gt > LS_COMB_DECREASE * g)) {
                g = gt;
                break;
            }
            g = gt;
        }
    }
    return g;
}

/* ------------------------------------------------------------ the step */

static void mulmv(double out[3], const double A[9], const double x[3])
{
    for (int i = 0; i < 3; i++) out[i] = A[3 * i] * x[0] + A[3 * i + 1] * x[1] + A[3 * i + 2] * x[2];
}

/* The reduced objective of a slip direction d (u = t d, t >= 0 optimal
 * for d): psi(d) = f(d) / sqrt(q(d)), f = d . y - cap D(d), q = d^T W^-1 d
 * (y = W^-1 b); its gradient and Hessian when wanted. Homogeneous of degree
 * 0 in d. */
static double reduced(const limitsurf *ls, const double Winv[9], const double y[3], double cap, const double d[3],
                      double gr[3], double hs[9], double *f_out, double *q_out, double *D_out, double w_out[3])
{
    double w[3], HD[9], Wd[3], f, q, gf[3], gq[3];
    double D = limitsurf_wrench(ls, d, w, gr ? HD : NULL);
    mulmv(Wd, Winv, d);
    f = ex_dot3(d, y) - cap * D;
    q = ex_dot3(d, Wd);
    if (f_out) *f_out = f;
    if (q_out) *q_out = q;
    if (D_out) *D_out = D;
    if (w_out) memcpy(w_out, w, sizeof w);
    double sq = sqrt(q), psi = f / sq;
    if (gr) {
        for (int i = 0; i < 3; i++) {
            gf[i] = y[i] + cap * w[i];
            gq[i] = 2.0 * Wd[i];
            gr[i] = gf[i] / sq - 0.5 * f * gq[i] / (q * sq);
        }
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                hs[3 * i + j] = -cap * HD[3 * i + j] / sq - 0.5 * (gf[i] * gq[j] + gq[i] * gf[j]) / (q * sq)
                                - f * Winv[3 * i + j] / (q * sq) + 0.75 * f * gq[i] * gq[j] / (q * q * sq);
    }
    return psi;
}

/* an orthonormal basis N of the plane orthogonal to the unit vector n */
static void plane_basis(const double n[3], double N[2][3])
{
    int k = fabs(n[0]) <= fabs(n[1]) && fabs(n[0]) <= fabs(n[2]) ? 0 : fabs(n[1]) <= fabs(n[2]) ? 1 : 2;
    double a[3] = {0, 0, 0}, d;
    a[k] = 1.0;
    d = ex_dot3(a, n);
    for (int i = 0; i < 3; i++) N[0][i] = a[i] - d * n[i];
    d = sqrt(ex_dot3(N[0], N[0]));
    for (int i = 0; i < 3; i++) N[0][i] /= d;
    N[1][0] = n[1] * N[0][2] - n[2] * N[0][1];
    N[1][1] = n[2] * N[0][0] - n[0] * N[0][2];
    N[1][2] = n[0] * N[0][1] - n[1] * N[0][0];
}

/* The step's line: -psi at d + t (dz in the tangent basis N). */
typedef struct step_line {
    const limitsurf *ls;
    const double *Winv, *y;
    double cap;
    const double *d, *dz;
    const double (*N)[3];
} step_line;

static double step_line_at(void *ctx, double t)
{
    const step_line *s = ctx;
    double dt[3];
    for (int i = 0; i < 3; i++) dt[i] = s->d[i] + t * (s->dz[0] * s->N[0][i] + s->dz[1] * s->N[1][i]);
    return -reduced(s->ls, s->Winv, s->y, s->cap, dt, NULL, NULL, NULL, NULL, NULL, NULL);
}

int limitsurf_step(const limitsurf *ls, const exdex_friction_prep *prep, const double b[3], double cap, int solver,
                   exdex_friction_ws *ws, const double *warm, exdex_friction_result *res)
{
    if (ls->type != &limitsurf_exact) return exdex_friction_solve(prep, b, cap, solver, ws, warm, res);
    for (int i = 0; i < 3; i++) res->p[i] = res->u[i] = NAN;
    res->sigma = NAN;
    res->stick = 0;
    res->iterations = 0;
    if (!(cap >= 0.0) || !isfinite(cap) || !ex_finite_n(b, 3)) return EXDEX_EINVAL;
    const double *W = prep->W;
    double Winv[9], y[3], g, e3[3], col[3];
    /* W^-1 column by column (W is SPD: exdex_friction_prepare checked it) */
    for (int j = 0; j < 3; j++) {
        for (int i = 0; i < 3; i++) e3[i] = i == j ? 1.0 : 0.0;
        if (!spd_solve(3, W, e3, col)) return EXDEX_EINVAL;
        for (int i = 0; i < 3; i++) Winv[3 * i + j] = col[i];
    }
    if (!spd_solve(3, W, b, y)) return EXDEX_EINVAL;
    /* one refinement of y = W^-1 b */
    {
        double r[3], dy[3];
        mulmv(r, W, y);
        for (int i = 0; i < 3; i++) r[i] = b[i] - r[i];
        if (spd_solve(3, W, r, dy))
            for (int i = 0; i < 3; i++) y[i] += dy[i];
    }
    double d[3], dir[3], ge;
    int st = EXDEX_OK, decided = 0;
    /* from the bounds alone where they decide: g(y) lies in
     * [|E^-1 y| / kmax, |E^-1 y| / kmin] (D >= kmin |E u| bounds the gauge's
     * maximum above; the ellipsoid's maximiser E^-2 y bounds it below) */
    {
        double a = y[0] / ls->e[0], b2 = y[1] / ls->e[1], c = y[2] / ls->e[2];
        ge = sqrt(a * a + b2 * b2 + c * c);
    }
    if (ge <= cap * ls->kmin) {
        g = 0.0; /* stick, certain */
        decided = 1;
    } else if (ge > cap * ls->kmax) {
        /* slip, certain; E^-2 y starts it with f >= |E^-1 y| |E d| - cap kmax |E d| > 0 */
        double nd = 0.0;
        for (int i = 0; i < 3; i++) {
            d[i] = y[i] / (ls->e[i] * ls->e[i]);
            nd += d[i] * d[i];
        }
        nd = sqrt(nd);
        for (int i = 0; i < 3; i++) d[i] /= nd;
        g = INFINITY;
        decided = 2;
    }
    if (!decided) {
        st = limitsurf_gauge(ls, y, &g, dir);
        if (st != EXDEX_OK) return st;
        for (int i = 0; i < 3; i++) d[i] = -dir[i];
    }
    if (g > cap && warm && ex_finite_n(warm, 3) && (warm[0] != 0.0 || warm[1] != 0.0 || warm[2] != 0.0)) {
        /* a warm slip direction (the last step's slip) where psi is positive there */
        double f, q, nw = sqrt(ex_dot3(warm, warm)), dw[3] = {warm[0] / nw, warm[1] / nw, warm[2] / nw};
        reduced(ls, Winv, y, cap, dw, NULL, NULL, &f, &q, NULL, NULL);
        if (f > 0.0) memcpy(d, dw, sizeof d);
    }
    if (g <= cap) {
        for (int i = 0; i < 3; i++) {
            res->p[i] = -y[i];
            res->u[i] = 0.0;
        }
        res->sigma = 0.0;
        res->stick = 1;
        return EXDEX_OK;
    }
    /* sliding: the direction d of the slip maximises psi (see reduced);
     * its magnitude is then t = f / q. psi has one local maximum where it is
     * positive (a local maximum is a local minimum of the convex objective
     * over a cone around u), and the outward normal of the surface at y
     * (the gauge's maximiser) is a start where f = D (g - cap) > 0. Newton
     * in the plane tangent to the unit sphere at d, with a backtracking line
     * search (and a Levenberg shift where psi's Hessian is not negative
     * definite). */
    int ok = 0, it;
    /* f, q, D and w at the current d (kept for the end: the loop ends at a
     * d it has evaluated) */
    double lam2_prev = INFINITY, f = NAN, q = NAN, Dd = NAN, wd[3] = {NAN, NAN, NAN};
    for (it = 0; it < LIMITSURF_MAX_ITER; it++) {
        double gr[3], hs[9], N[2][3], gz[2], Hz[4], dz[2], lam2, t, P0;
        P0 = reduced(ls, Winv, y, cap, d, gr, hs, &f, &q, &Dd, wd);
        if (!isfinite(P0) || !(f > 0.0)) return EXDEX_ENOCONV;
        plane_basis(d, N);
        for (int a = 0; a < 2; a++) {
            gz[a] = ex_dot3(N[a], gr);
            for (int c = 0; c < 2; c++) {
                double sum = 0.0;
                for (int i = 0; i < 3; i++)
                    for (int j = 0; j < 3; j++) sum += N[a][i] * hs[3 * i + j] * N[c][j];
                Hz[2 * a + c] = -sum; /* minus: the maximum's Hessian is negative definite */
            }
        }
        {
            double mu = 0.0, tr = fabs(Hz[0]) + fabs(Hz[3]);
            int solved = 0;
            for (int k = 0; k < LS_SHIFT_TRIES && !solved; k++) {
                double Hm[4] = {Hz[0] + mu, Hz[1], Hz[2], Hz[3] + mu};
                solved = spd_solve(2, Hm, gz, dz);
                mu = mu == 0.0 ? LS_SHIFT_START * tr + 1e-300 : LS_SHIFT_GROWTH * mu;
            }
            if (!solved) return EXDEX_ENOCONV;
        }
        lam2 = gz[0] * dz[0] + gz[1] * dz[1];
        /* psi's scale: its terms before they cancel (near the stick
         * boundary f = d . y - cap D is a small difference) */
        double psc = (fabs(ex_dot3(d, y)) + cap * Dd) / sqrt(q);
        if (lam2 <= LS_NEWTON_DONE * psc) {
            ok = 1;
            break;
        }
        if (lam2 <= LS_NEWTON_FULL * psc && lam2 > LS_NEWTON_QUADRATIC * lam2_prev) {
            /* full steps no longer decrease the decrement quadratically: the
             * rounding floor of psi's gradient */
            ok = 1;
            break;
        }
        lam2_prev = lam2;
        {
            /* psi is maximised: Armijo on -psi */
            step_line sl = {ls, Winv, y, cap, d, dz, (const double (*)[3])N};
            t = armijo(step_line_at, &sl, -P0, lam2, lam2 > LS_NEWTON_FULL * psc);
        }
        if (t < LS_LINE_STEP_MIN) {
            ok = lam2 <= LS_NEWTON_ACCEPT * psc;
            break;
        }
        {
            double nd;
            for (int i = 0; i < 3; i++) d[i] += t * (dz[0] * N[0][i] + dz[1] * N[1][i]);
            nd = sqrt(ex_dot3(d, d));
            for (int i = 0; i < 3; i++) d[i] /= nd;
        }
    }
    res->iterations = it + 1;
    if (!ok) return EXDEX_ENOCONV;
    {
        double Wp[3];
        if (!(f > 0.0)) return EXDEX_ENOCONV;
        /* p = cap w(d) on the surface; u+ = b + W p (= (f / q) d at the optimum) */
        for (int i = 0; i < 3; i++) res->p[i] = cap * wd[i];
        mulmv(Wp, W, res->p);
        for (int i = 0; i < 3; i++) res->u[i] = b[i] + Wp[i];
        res->sigma = limitsurf_dissipation(ls, res->u);
    }
    if (!ex_finite_n(res->p, 3)) return EXDEX_ENONFINITE;
    return EXDEX_OK;
}

/* ------------------------------------------------------------ public */

int exdex_limit_surface_eval(int surface, double e_r, int region_kind, int region_n,
                             const double (*region_vertices)[2], double region_radius, int what, const double in[3],
                             double out[3], double *scalar)
{
    limitsurf ls;
    region rg;
    if (!in || !out || !scalar || (what != 0 && what != 1) || !ex_finite_n(in, 3)) return EXDEX_EINVAL;
    if (surface == EXDEX_LS_ELLIPSOID) {
        if (limitsurf_set_ellipsoid(&ls, e_r) != EXDEX_OK) return EXDEX_EINVAL;
    } else if (surface == EXDEX_LS_EXACT) {
        memset(&rg, 0, sizeof rg);
        if (region_kind == EXDEX_REGION_DISC) {
            region_set_disc(&rg, 0.0, 0.0, region_radius);
        } else if (region_kind == EXDEX_REGION_POLYGON && region_vertices && region_n >= 3 &&
                   region_n <= EXDEX_REGION_MAX_VERTICES) {
            rg.kind = REGION_POLYGON;
            rg.n = region_n;
            memcpy(rg.v, region_vertices, (size_t)region_n * sizeof rg.v[0]);
        } else {
            return EXDEX_EINVAL;
        }
        if (limitsurf_set_exact(&ls, &rg) != EXDEX_OK) return EXDEX_EINVAL;
    } else {
        return EXDEX_EINVAL;
    }
    if (what == 0) {
        if (in[0] == 0.0 && in[1] == 0.0 && in[2] == 0.0) return EXDEX_EINVAL;
        *scalar = limitsurf_wrench(&ls, in, out, NULL);
        return ex_finite_n(out, 3) && isfinite(*scalar) ? EXDEX_OK : EXDEX_ENONFINITE;
    }
    return limitsurf_gauge(&ls, in, scalar, out);
}
