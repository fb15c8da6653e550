/* region.c -- integrals over a uniform contact region (region.h).
 *
 * Polygon, one edge P0 -> P1 (counter-clockwise, outward unit normal n,
 * unit direction t, length L). For the point c, x = r - c on the edge is
 * h n + s t with h = (P0 - c) . n constant and s from s0 = (P0 - c) . t to
 * s1 = s0 + L. The three edge integrals
 *   I = Int |x| ds    = [s sqrt(h^2 + s^2) + h^2 asinh(s / |h|)] / 2,
 *   J = Int ds / |x|  = asinh(s1 / |h|) - asinh(s0 / |h|) (one logarithm),
 *   S = Int s / |x| ds = |x1| - |x0|
 * (between s0 and s1; h^2 asinh and h J vanish with h) give
 *   F   = (1/3) sum h I          (div(x |x|) = 3 |x|),
 *   G   = sum n I                (gradient theorem on grad |x| = x / |x|),
 *   Phi = sum h J                (div(x / |x|) = 1 / |x|),
 *   grad_c G = -sum n (Int x/|x| ds)^T = -sum (h J n n^T + S n t^T),
 *   H = grad_c G + Phi I.
 *
 * Disc of radius R, centre o, d = c - o, rho = |d|: on the circle
 * |x|^2 = R^2 + rho^2 - 2 R rho cos(theta) = (R + rho)^2 (1 - k^2 sin^2 phi)
 * with theta = pi - 2 phi and k^2 = 4 R rho / (R + rho)^2. With s = R + rho,
 * the complete integrals K(k), E(k) and
 *   T(k) = Int_0^{pi/2} sin^2 cos^2 / sqrt(1 - k^2 sin^2) dphi
 *        = [(2 - k^2) E - 2 (1 - k^2) K] / (3 k^4),
 * the boundary forms of F, G and Phi over the circle are
 *   F   = (R/3) (4 R s E + 16 R rho^2 T / s),
 *   G   = -(16 R^2 T / s) d,
 *   Phi = 2 (s E + (R - rho) K),
 *   H   = grad_c G + Phi I  (G's derivative with dT/dm from those of K, E).
 * (G by parts: Int |x| cos(theta) dtheta = -R rho Int sin^2 / |x| dtheta.)
 * For k^2 < 1/2 (rho < 0.17 R or rho > 5.8 R) K, E and T come from their
 * hypergeometric series (the closed form of T cancels there), with
 * a_n = (2n-1)!!/(2n)!!:
 *   K = (pi/2) sum a_n^2 k^2n,  E = (pi/2) sum a_n^2 k^2n / (1 - 2n),
 *   T = (pi/2) sum a_n a_(n+1) k^2n / (2n + 4);
 * otherwise from the arithmetic-geometric mean of 1 and k' = |R - rho| / s
 * (formed without cancellation), the classical alternative to the Carlson
 * forms R_F, R_D that GSL's gsl_sf_ellint_Kcomp and _Ecomp use (the C
 * tests check the two against each other; the AGM is a few square roots).
 * At rho = R (k' = 0): E = 1, T = 1/3 and (R - rho) K = 0.
 */
#include "region.h"

#include "exdex.h"

#include <math.h>
#include <string.h>


static const double PI = 3.14159265358979323846;

/* ------------------------------------------------------------ set-up */

void region_set_rectangle(region *rg, double cx, double cy, double half_a, double half_b)
{
    memset(rg, 0, sizeof *rg);
    rg->kind = REGION_POLYGON;
    rg->n = 4;
    rg->v[0][0] = cx - half_a, rg->v[0][1] = cy - half_b;
    rg->v[1][0] = cx + half_a, rg->v[1][1] = cy - half_b;
    rg->v[2][0] = cx + half_a, rg->v[2][1] = cy + half_b;
    rg->v[3][0] = cx - half_a, rg->v[3][1] = cy + half_b;
}

void region_set_disc(region *rg, double cx, double cy, double radius)
{
    memset(rg, 0, sizeof *rg);
    rg->kind = REGION_DISC;
    rg->c[0] = cx, rg->c[1] = cy;
    rg->r = radius;
}

/* twice the signed area of the polygon */
static double poly_area2(const region *rg)
{
    double a = 0.0;
    for (int i = 0; i < rg->n; i++) {
        const double *p = rg->v[i], *q = rg->v[(i + 1) % rg->n];
        a += p[0] * q[1] - p[1] * q[0];
    }
    return a;
}

int region_check(const region *rg)
{
    if (!rg) return EXDEX_EINVAL;
    if (rg->kind == REGION_DISC)
        return isfinite(rg->c[0]) && isfinite(rg->c[1]) && isfinite(rg->r) && rg->r > 0.0 ? EXDEX_OK : EXDEX_EINVAL;
    if (rg->kind != REGION_POLYGON || rg->n < 3 || rg->n > REGION_MAX_VERTICES) return EXDEX_EINVAL;
    double size2 = 0.0;
    for (int i = 0; i < rg->n; i++) {
        if (!isfinite(rg->v[i][0]) || !isfinite(rg->v[i][1])) return EXDEX_EINVAL;
        for (int j = 0; j < i; j++) {
            double dx = rg->v[i][0] - rg->v[j][0], dy = rg->v[i][1] - rg->v[j][1];
            double d2 = dx * dx + dy * dy;
            if (d2 > size2) size2 = d2;
        }
    }
    if (!isfinite(size2) || !(poly_area2(rg) > 0.0)) return EXDEX_EINVAL;
    /* every vertex on the left of (or on) every edge's line: convex and
     * counter-clockwise, winding once (left turns alone allow a star) */
    for (int i = 0; i < rg->n; i++) {
        const double *p = rg->v[i], *q = rg->v[(i + 1) % rg->n];
        for (int j = 0; j < rg->n; j++) {
            const double *r = rg->v[j];
            double cr = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
            if (cr < -1e-12 * size2) return EXDEX_EINVAL;
        }
    }
    return EXDEX_OK;
}

double region_area(const region *rg)
{
    if (rg->kind == REGION_DISC) return PI * rg->r * rg->r;
    return 0.5 * poly_area2(rg);
}

void region_centroid(const region *rg, double g[2])
{
    if (rg->kind == REGION_DISC) {
        g[0] = rg->c[0], g[1] = rg->c[1];
        return;
    }
    /* fan from vertex 0, in coordinates relative to it (no cancellation
     * for a small polygon far from the origin) */
    const double *o = rg->v[0];
    double a = 0.0, gx = 0.0, gy = 0.0;
    for (int i = 1; i + 1 < rg->n; i++) {
        double px = rg->v[i][0] - o[0], py = rg->v[i][1] - o[1];
        double qx = rg->v[i + 1][0] - o[0], qy = rg->v[i + 1][1] - o[1];
        double t = px * qy - py * qx;
        a += t;
        gx += t * (px + qx);
        gy += t * (py + qy);
    }
    g[0] = o[0] + gx / (3.0 * a);
    g[1] = o[1] + gy / (3.0 * a);
}

double region_reach(const region *rg, const double c[2])
{
    if (rg->kind == REGION_DISC) return hypot(c[0] - rg->c[0], c[1] - rg->c[1]) + rg->r;
    double m = 0.0;
    for (int i = 0; i < rg->n; i++) {
        double d = hypot(rg->v[i][0] - c[0], rg->v[i][1] - c[1]);
        if (d > m) m = d;
    }
    return m;
}

/* ------------------------------------------------------------ polygon */

static void poly_moments(const region *rg, const double c[2], region_moments *out)
{
    double F = 0.0, Gx = 0.0, Gy = 0.0, Phi = 0.0, dxx = 0.0, dxy = 0.0, dyx = 0.0, dyy = 0.0;
    /* c relative to the first vertex: the integrals depend on r - c only,
     * and a small region far from the frame's origin keeps its digits */
    const double *o = rg->v[0];
    double cx = c[0] - o[0], cy = c[1] - o[1];
    for (int i = 0; i < rg->n; i++) {
        const double *p = rg->v[i], *q = rg->v[(i + 1) % rg->n];
        double ex = q[0] - p[0], ey = q[1] - p[1], L = sqrt(ex * ex + ey * ey);
        if (!(L > 0.0)) continue; /* a repeated vertex: no edge */
        double tx = ex / L, ty = ey / L, nx = ty, ny = -tx;
        double x0 = (p[0] - o[0]) - cx, y0 = (p[1] - o[1]) - cy;
        double h = x0 * nx + y0 * ny, s0 = x0 * tx + y0 * ty, s1 = s0 + L;
        double ah = fabs(h);
        double r0 = sqrt(h * h + s0 * s0), r1 = sqrt(h * h + s1 * s1);
        double I = 0.5 * (s1 * r1 - s0 * r0), hJ = 0.0, J = 0.0;
        if (ah > 0.0) {
            /* asinh(s1/|h|) - asinh(s0/|h|) as one logarithm, each form free
             * of cancellation on its side of the foot of the perpendicular */
            if (s0 >= 0.0) J = log((s1 + r1) / (s0 + r0));
            else if (s1 <= 0.0) J = log((r0 - s0) / (r1 - s1));
            else J = log((s1 + r1) / ah) + log((r0 - s0) / ah);
            I += 0.5 * h * h * J;
            hJ = h * J;
        }
        double S = r1 - r0;
        F += h * I;
        Gx += nx * I, Gy += ny * I;
        Phi += hJ;
        /* grad_c G = -sum (h J n n^T + S n t^T) */
        dxx -= hJ * nx * nx + S * nx * tx;
        dxy -= hJ * nx * ny + S * nx * ty;
        dyx -= hJ * ny * nx + S * ny * tx;
        dyy -= hJ * ny * ny + S * ny * ty;
    }
    out->dist = F / 3.0;
    out->dir[0] = Gx, out->dir[1] = Gy;
    out->inv = Phi;
    out->dyad[0] = dxx + Phi;
    out->dyad[1] = 0.5 * (dxy + dyx);
    out->dyad[2] = dyy + Phi;
}

/* ------------------------------------------------------------ disc */

/* K, E, T and dT = dT/dm (m = k^2; NaN at m = 1, where it diverges like
 * K) of k^2 = k2, 1 - k^2 = kp2 (given separately). */
static int disc_kernels(double k2, double kp2, double *K, double *E, double *T, double *dT)
{
    if (k2 < 0.5) {
        /* series: a_n = (2n-1)!!/(2n)!!, a_(n+1) = a_n (2n+1)/(2n+2) */
        double a = 1.0, p = 1.0, pm = 0.0, sk = 0.0, se = 0.0, st = 0.0, sd = 0.0;
        for (int n = 0; n < REGION_SERIES_MAX; n++) {
            double an1 = a * (2.0 * n + 1.0) / (2.0 * n + 2.0);
            double tk = a * a * p;
            sk += tk;
            se += tk / (1.0 - 2.0 * n);
            st += a * an1 * p / (2.0 * n + 4.0);
            sd += n * a * an1 * pm / (2.0 * n + 4.0);
            if (tk < 1e-18 * sk) break;
            a = an1;
            pm = p;
            p *= k2;
        }
        *K = 0.5 * PI * sk;
        *E = 0.5 * PI * se;
        *T = 0.5 * PI * st;
        *dT = 0.5 * PI * sd;
        return EXDEX_OK;
    }
    if (!(kp2 > 1e-300)) {
        *K = INFINITY;
        *E = 1.0;
        *T = 1.0 / 3.0;
        *dT = NAN;
        return EXDEX_OK;
    }
    /* K and E by the arithmetic-geometric mean of 1 and k' (quadratic
     * convergence: 5 or 6 rounds for k' > 1e-150): K = pi / (2 M),
     * E = K (1 - sum 2^(n-1) c_n^2), c_0 = k, c_n = (a_(n-1) - b_(n-1)) / 2.
     * test_region.c checks them against GSL's Carlson forms
     * (gsl_sf_ellint_Kcomp, _Ecomp) to rounding. */
    {
        double a = 1.0, b = sqrt(kp2), sum = 0.5 * k2, pw = 0.5;
        for (int n = 0; n < REGION_AGM_MAX && a - b > 1e-16 * a; n++) {
            double an = 0.5 * (a + b), c = 0.5 * (a - b);
            pw *= 2.0;
            sum += pw * c * c;
            b = sqrt(a * b);
            a = an;
        }
        *K = PI / (2.0 * a);
        *E = *K * (1.0 - sum);
    }
    *T = ((2.0 - k2) * *E - 2.0 * kp2 * *K) / (3.0 * k2 * k2);
    /* dT/dm from dE/dm = (E - K) / (2m), 2 (1 - m) dK/dm = (E - (1 - m) K) / m */
    {
        double m = k2, N = -*E + (2.0 - m) * (*E - *K) / (2.0 * m) + 2.0 * *K - (*E - kp2 * *K) / m;
        *dT = N / (3.0 * m * m) - 2.0 * *T / m;
    }
    return EXDEX_OK;
}

static int disc_moments(const region *rg, const double c[2], region_moments *out)
{
    double R = rg->r, dx = c[0] - rg->c[0], dy = c[1] - rg->c[1], rho = hypot(dx, dy);
    double s = R + rho, q = (R - rho) / s;
    double k2 = 4.0 * (R / s) * (rho / s), kp2 = q * q, K, E, T, dT;
    int st = disc_kernels(k2, kp2, &K, &E, &T, &dT);
    if (st != EXDEX_OK) return st;
    out->dist = (R / 3.0) * (4.0 * R * s * E + 16.0 * R * (rho / s) * rho * T);
    /* G = -gam d, gam(rho) = 16 R^2 T / s; grad_c G = -gam I - gam' d d^T / rho,
     * gam' = 16 R^2 (T'(m) m'(rho) / s - T / s^2), m' = 4 R (R - rho) / s^3
     * (T' grows like K near the rim, where m' vanishes: the product -> 0) */
    double gam = 16.0 * R * (R / s) * T;
    out->dir[0] = -gam * dx, out->dir[1] = -gam * dy;
    out->inv = 2.0 * (s * E + (rho == R ? 0.0 : (R - rho) * K));
    double dgam = -16.0 * R * (R / s) * T / s;
    if (rho != R && isfinite(dT)) dgam += 16.0 * R * R * dT * 4.0 * R * (R - rho) / (s * s * s * s);
    double gx = rho > 0.0 ? dx / rho : 0.0, gy = rho > 0.0 ? dy / rho : 0.0;
    out->dyad[0] = -gam - dgam * rho * gx * gx + out->inv;
    out->dyad[1] = -dgam * rho * gx * gy;
    out->dyad[2] = -gam - dgam * rho * gy * gy + out->inv;
    return EXDEX_OK;
}

int region_moments_at(const region *rg, const double c[2], region_moments *out)
{
    if (!isfinite(c[0]) || !isfinite(c[1])) return EXDEX_EINVAL;
    if (rg->kind == REGION_DISC) return disc_moments(rg, c, out);
    poly_moments(rg, c, out);
    return EXDEX_OK;
}

double region_mean_distance(const region *rg, const double c[2])
{
    region_moments mo;
    if (region_moments_at(rg, c, &mo) != EXDEX_OK) return NAN;
    return mo.dist / region_area(rg);
}
