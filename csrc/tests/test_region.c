/* test_region.c -- integrals over a uniform contact region (region.c).
 *
 * References, test by test:
 *   closed forms    the disc's F(centre) = 2 pi R^3 / 3, Phi(centre) = 2 pi R,
 *                   G near the centre -pi R rho (Taylor: grad^2 F = 2 pi R);
 *                   the rectangle's mean distance from its centre (Howe and
 *                   Cutkosky's closed form, exdex_er_rectangle) and the
 *                   square's (sqrt2 + asinh 1)/3 a = 0.76520 a; the disc's
 *                   value at its rim (F = 32 R^3 / 9, a classic).
 *   grid            brute-force midpoint quadrature on a fine grid (every
 *                   cell centre tested for inclusion) of F, G at points
 *                   inside, on the boundary and outside random convex
 *                   polygons and discs; Phi and H at points outside (smooth
 *                   integrand there).
 *   identities      trace H = Phi; grad_c G = H - Phi I against central
 *                   differences of G; G = -grad_c F against differences of F
 *                   (polygons and the disc, across its two branches).
 *   polygon -> disc regular n-gons inscribed in the disc converge to the
 *                   disc's values (error O(1/n^2)).
 */
#include "check.h"
#include "../exdex.h"
#include "../region.h"

#include <math.h>
#include <string.h>

#include <gsl/gsl_sf_ellint.h>

static const double PI = 3.14159265358979323846;

/* tiny deterministic generator (the cases do not depend on a library) */
static unsigned long long rs, rs_seed; /* restarted at each test from its seed */
static double urand(void)
{
    if (rs_seed != check_seed()) rs = rs_seed = check_seed();
    rs ^= rs << 13, rs ^= rs >> 7, rs ^= rs << 17;
    return (double)(rs >> 11) / 9007199254740992.0;
}

/* a random convex polygon: n points on an ellipse at sorted random angles,
 * rotated and shifted */
static void random_polygon(region *rg, int n)
{
    double ang[REGION_MAX_VERTICES];
    for (int i = 0; i < n; i++) ang[i] = 2.0 * PI * urand();
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && ang[j - 1] > ang[j]; j--) {
            double t = ang[j];
            ang[j] = ang[j - 1], ang[j - 1] = t;
        }
    double a = 0.5 + urand(), b = 0.2 + urand(), rot = 2.0 * PI * urand(), cx = urand() - 0.5, cy = urand() - 0.5;
    memset(rg, 0, sizeof *rg);
    rg->kind = REGION_POLYGON;
    rg->n = n;
    for (int i = 0; i < n; i++) {
        double x = a * cos(ang[i]), y = b * sin(ang[i]);
        rg->v[i][0] = cx + cos(rot) * x - sin(rot) * y;
        rg->v[i][1] = cy + sin(rot) * x + cos(rot) * y;
    }
}

static int inside(const region *rg, double x, double y)
{
    if (rg->kind == REGION_DISC) return hypot(x - rg->c[0], y - rg->c[1]) <= rg->r;
    for (int i = 0; i < rg->n; i++) {
        const double *p = rg->v[i], *q = rg->v[(i + 1) % rg->n];
        if ((q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]) < 0.0) return 0;
    }
    return 1;
}

/* midpoint rule on an N x N grid over the bounding rectangle of least area
 * (a disc: its square; a convex polygon: the least of the rectangles with a
 * side along an edge, which holds the least one and is at most twice the
 * polygon's area). The rule errs only in the cells the boundary crosses,
 * about 4 N of them, so its error is O(1 / N) of the integrals whatever the
 * polygon's shape; over the axis-aligned box a thin sliver at an angle
 * would fill a small part of the cells and leave the boundary's share large
 * (1 % of the area at N = 1200). */
static void grid(const region *rg, const double c[2], int N, region_moments *m, double *area)
{
    double lo[2] = {0, 0}, hi[2] = {0, 0}, ax[2][2] = {{1, 0}, {0, 1}};
    if (rg->kind == REGION_DISC) {
        for (int k = 0; k < 2; k++) lo[k] = rg->c[k] - rg->r, hi[k] = rg->c[k] + rg->r;
    } else {
        double best = INFINITY;
        for (int e = 0; e < rg->n; e++) {
            const double *p = rg->v[e], *q = rg->v[(e + 1) % rg->n];
            double len = hypot(q[0] - p[0], q[1] - p[1]), u[2][2], l[2] = {INFINITY, INFINITY}, h[2] = {-INFINITY, -INFINITY};
            u[0][0] = (q[0] - p[0]) / len, u[0][1] = (q[1] - p[1]) / len;
            u[1][0] = -u[0][1], u[1][1] = u[0][0];
            for (int i = 0; i < rg->n; i++)
                for (int k = 0; k < 2; k++) {
                    double t = u[k][0] * rg->v[i][0] + u[k][1] * rg->v[i][1];
                    l[k] = fmin(l[k], t), h[k] = fmax(h[k], t);
                }
            if ((h[0] - l[0]) * (h[1] - l[1]) < best) {
                best = (h[0] - l[0]) * (h[1] - l[1]);
                memcpy(ax, u, sizeof ax), memcpy(lo, l, sizeof lo), memcpy(hi, h, sizeof hi);
            }
        }
    }
    double hx = (hi[0] - lo[0]) / N, hy = (hi[1] - lo[1]) / N, dA = hx * hy;
    double F = 0, Gx = 0, Gy = 0, Phi = 0, Hxx = 0, Hxy = 0, Hyy = 0, A = 0;
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            double s = lo[0] + (i + 0.5) * hx, t = lo[1] + (j + 0.5) * hy;
            double x = s * ax[0][0] + t * ax[1][0], y = s * ax[0][1] + t * ax[1][1];
            if (!inside(rg, x, y)) continue;
            double dx = x - c[0], dy = y - c[1], r = hypot(dx, dy);
            A += dA;
            F += r * dA;
            if (r == 0.0) continue;
            Gx += dx / r * dA, Gy += dy / r * dA;
            Phi += dA / r;
            Hxx += dx * dx / (r * r * r) * dA, Hxy += dx * dy / (r * r * r) * dA, Hyy += dy * dy / (r * r * r) * dA;
        }
    m->dist = F, m->dir[0] = Gx, m->dir[1] = Gy, m->inv = Phi, m->dyad[0] = Hxx, m->dyad[1] = Hxy, m->dyad[2] = Hyy;
    *area = A;
}

EXDEX_TEST(region_check_rejects)
{
    region rg;
    region_set_rectangle(&rg, 0, 0, 1, 2);
    ENSURE(region_check(&rg) == EXDEX_OK);
    /* clockwise */
    double t[2];
    memcpy(t, rg.v[1], sizeof t), memcpy(rg.v[1], rg.v[3], sizeof t), memcpy(rg.v[3], t, sizeof t);
    ENSURE(region_check(&rg) == EXDEX_EINVAL);
    /* non-convex: a dent */
    region_set_rectangle(&rg, 0, 0, 1, 1);
    rg.n = 5;
    rg.v[4][0] = -0.5, rg.v[4][1] = 0.0; /* after (-1, 1): a right turn */
    ENSURE(region_check(&rg) == EXDEX_EINVAL);
    region_set_rectangle(&rg, 0, 0, 1, NAN);
    ENSURE(region_check(&rg) == EXDEX_EINVAL);
    region_set_rectangle(&rg, 0, 0, 1, 0);
    ENSURE(region_check(&rg) == EXDEX_EINVAL);
    region_set_disc(&rg, 0, 0, 0);
    ENSURE(region_check(&rg) == EXDEX_EINVAL);
    region_set_disc(&rg, 0, INFINITY, 1);
    ENSURE(region_check(&rg) == EXDEX_EINVAL);
    rg.kind = REGION_NONE;
    ENSURE(region_check(&rg) == EXDEX_EINVAL);
    ENSURE(region_check(NULL) == EXDEX_EINVAL);
    region_set_disc(&rg, 0, 0, 1);
    double c[2] = {NAN, 0};
    region_moments mo;
    ENSURE(region_moments_at(&rg, c, &mo) == EXDEX_EINVAL);
}

EXDEX_TEST(region_disc_closed_forms)
{
    for (int k = 0; k < 3; k++) {
        double R = k == 0 ? 1.0 : k == 1 ? 0.013 : 7.5;
        region rg;
        region_set_disc(&rg, 0.3 * R, -0.2 * R, R);
        ENSURE(region_check(&rg) == EXDEX_OK);
        region_moments mo;
        ENSURE(region_moments_at(&rg, rg.c, &mo) == EXDEX_OK);
        ENSURE_CLOSE(mo.dist, 2.0 * PI * R * R * R / 3.0, 1e-15 * R * R * R);
        ENSURE_CLOSE(mo.inv, 2.0 * PI * R, 1e-15 * R);
        ENSURE_CLOSE(region_mean_distance(&rg, rg.c), 2.0 * R / 3.0, 1e-15 * R);
        ENSURE_CLOSE(region_mean_distance(&rg, rg.c), exdex_er_disc(R), 1e-15 * R);
        ENSURE(mo.dir[0] == 0.0 && mo.dir[1] == 0.0);
        /* near the centre: G = -pi R rho (1 + O(rho^2 / R^2)) */
        double c[2] = {rg.c[0] + 1e-4 * R, rg.c[1]};
        ENSURE(region_moments_at(&rg, c, &mo) == EXDEX_OK);
        ENSURE_CLOSE(mo.dir[0], -PI * R * 1e-4 * R, 1e-9 * R * R);
        ENSURE_CLOSE(mo.dir[1], 0.0, 1e-20 * R * R);
        /* on the rim: mean distance of a disc from a point of its rim 32 R / (9 pi) */
        c[0] = rg.c[0], c[1] = rg.c[1] + R;
        ENSURE(region_moments_at(&rg, c, &mo) == EXDEX_OK);
        ENSURE_CLOSE(mo.dist, 32.0 * R * R * R / 9.0, 1e-14 * R * R * R);
        /* on the rim Phi = 4R (from the boundary form: 2 (2R E(1))) */
        ENSURE_CLOSE(mo.inv, 4.0 * R, 1e-14 * R);
        /* far away: the mean distance is rho + R^2 / (8 rho) + O(R^4 / rho^3) */
        c[0] = rg.c[0] + 1e3 * R, c[1] = rg.c[1];
        ENSURE(region_moments_at(&rg, c, &mo) == EXDEX_OK);
        ENSURE_CLOSE(mo.dist / (PI * R * R * 1e3 * R), 1.0 + 0.125e-6, 1e-11);
        ENSURE_CLOSE(mo.dir[0] / (PI * R * R), -1.0, 1e-6);
    }
}

EXDEX_TEST(region_rectangle_closed_forms)
{
    region rg;
    double a = 0.02, b = 0.013;
    region_set_rectangle(&rg, 0.1, -0.05, a, b);
    double g[2];
    region_centroid(&rg, g);
    ENSURE_CLOSE(g[0], 0.1, 1e-16);
    ENSURE_CLOSE(g[1], -0.05, 1e-16);
    ENSURE_CLOSE(region_area(&rg), 4 * a * b, 1e-18);
    ENSURE_CLOSE(region_mean_distance(&rg, g), exdex_er_rectangle(a, b), 1e-15);
    region_set_rectangle(&rg, 0, 0, a, a);
    double o[2] = {0, 0};
    ENSURE_CLOSE(region_mean_distance(&rg, o) / a, (sqrt(2.0) + asinh(1.0)) / 3.0, 1e-15);
    ENSURE_CLOSE(region_mean_distance(&rg, o) / a, 0.76520, 5e-6);
    region_moments mo;
    ENSURE(region_moments_at(&rg, o, &mo) == EXDEX_OK);
    ENSURE_SMALL(mo.dir[0], 1e-18);
    ENSURE_SMALL(mo.dir[1], 1e-18);
    /* Phi at the centre of a square: 8 a asinh(1) (four triangles, each 2 a asinh 1) */
    ENSURE_CLOSE(mo.inv, 8.0 * a * asinh(1.0), 1e-16);
    ENSURE_CLOSE(mo.dyad[0], mo.inv / 2.0, 1e-16);
    ENSURE_SMALL(mo.dyad[1], 1e-17);
}

static void check_grid(const region *rg, const double c[2], int smooth, const char *what)
{
    region_moments mo, gr;
    double A;
    (void)what;
    ENSURE(region_moments_at(rg, c, &mo) == EXDEX_OK);
    grid(rg, c, 1200, &gr, &A);
    double L = sqrt(region_area(rg)), reach = region_reach(rg, c);
    ENSURE_CLOSE(A / region_area(rg), 1.0, 5e-3);
    /* the grid's error is dominated by the boundary cells: O(h / L) of the integral's scale */
    ENSURE_CLOSE(mo.dist / (A * reach), gr.dist / (A * reach), 5e-3);
    ENSURE_CLOSE(mo.dir[0] / A, gr.dir[0] / A, 5e-3);
    ENSURE_CLOSE(mo.dir[1] / A, gr.dir[1] / A, 5e-3);
    if (smooth) {
        ENSURE_CLOSE(mo.inv * L / A, gr.inv * L / A, 5e-3);
        for (int k = 0; k < 3; k++) ENSURE_CLOSE(mo.dyad[k] * L / A, gr.dyad[k] * L / A, 5e-3);
    }
}

EXDEX_TEST(region_grid_polygons)
{
    for (int trial = 0; trial < 12; trial++) {
        region rg;
        random_polygon(&rg, 3 + trial % 6);
        ENSURE(region_check(&rg) == EXDEX_OK);
        double g[2], c[2];
        region_centroid(&rg, g);
        /* inside (the centroid), a vertex, an edge midpoint, outside near and far */
        check_grid(&rg, g, 0, "centroid");
        check_grid(&rg, rg.v[0], 0, "vertex");
        c[0] = 0.5 * (rg.v[1][0] + rg.v[2][0]), c[1] = 0.5 * (rg.v[1][1] + rg.v[2][1]);
        check_grid(&rg, c, 0, "edge");
        double rr = region_reach(&rg, g), ang = 2.0 * PI * urand();
        c[0] = g[0] + 1.5 * rr * cos(ang), c[1] = g[1] + 1.5 * rr * sin(ang);
        check_grid(&rg, c, 1, "outside");
        c[0] = g[0] + 6.0 * rr * cos(ang), c[1] = g[1] + 6.0 * rr * sin(ang);
        check_grid(&rg, c, 1, "far");
    }
}

EXDEX_TEST(region_grid_discs)
{
    for (int trial = 0; trial < 6; trial++) {
        region rg;
        region_set_disc(&rg, urand() - 0.5, urand() - 0.5, 0.3 + urand());
        /* distances from the centre across both branches (series k^2 < 1/2, Carlson) */
        const double fr[7] = {0.0, 0.1, 0.3, 0.9, 1.0, 2.0, 8.0};
        for (int k = 0; k < 7; k++) {
            double ang = 2.0 * PI * urand(), c[2] = {rg.c[0] + fr[k] * rg.r * cos(ang), rg.c[1] + fr[k] * rg.r * sin(ang)};
            check_grid(&rg, c, fr[k] > 1.0, "disc");
        }
    }
}

EXDEX_TEST(region_identities)
{
    for (int trial = 0; trial < 20; trial++) {
        region rg;
        random_polygon(&rg, 3 + trial % 8);
        double g[2], c[2];
        region_centroid(&rg, g);
        double rr = region_reach(&rg, g), f = 3.0 * urand(), ang = 2.0 * PI * urand();
        c[0] = g[0] + f * rr * cos(ang), c[1] = g[1] + f * rr * sin(ang);
        region_moments mo, mp, mm;
        ENSURE(region_moments_at(&rg, c, &mo) == EXDEX_OK);
        /* trace H = Phi: the edge sums cancel to it from terms as large as
         * the edges (|r1 - r0| <= L each), so to rounding of Phi + perimeter
         * (a sliver's Phi can be 1e-5 of its perimeter) */
        double per = 0.0;
        for (int i = 0; i < rg.n; i++)
            per += hypot(rg.v[(i + 1) % rg.n][0] - rg.v[i][0], rg.v[(i + 1) % rg.n][1] - rg.v[i][1]);
        ENSURE_CLOSE(mo.dyad[0] + mo.dyad[2], mo.inv, 1e-13 * (mo.inv + per));
        double hstep = 1e-5 * rr;
        for (int k = 0; k < 2; k++) {
            double cp[2] = {c[0], c[1]}, cm[2] = {c[0], c[1]};
            cp[k] += hstep, cm[k] -= hstep;
            ENSURE(region_moments_at(&rg, cp, &mp) == EXDEX_OK);
            ENSURE(region_moments_at(&rg, cm, &mm) == EXDEX_OK);
            /* G = -grad F */
            ENSURE_CLOSE(-(mp.dist - mm.dist) / (2 * hstep), mo.dir[k], 1e-7 * mo.inv * rr);
            /* d G_j / d c_k = H_jk - Phi delta_jk */
            double dG0 = (mp.dir[0] - mm.dir[0]) / (2 * hstep), dG1 = (mp.dir[1] - mm.dir[1]) / (2 * hstep);
            double H0k = k == 0 ? mo.dyad[0] - mo.inv : mo.dyad[1], H1k = k == 0 ? mo.dyad[1] : mo.dyad[2] - mo.inv;
            ENSURE_CLOSE(dG0, H0k, 1e-6 * mo.inv);
            ENSURE_CLOSE(dG1, H1k, 1e-6 * mo.inv);
        }
    }
    /* the disc: G = -grad F by differences, across the branch switch */
    region rg;
    region_set_disc(&rg, 0.2, -0.1, 0.7);
    for (int k = 0; k < 40; k++) {
        double rho = 0.05 * k * rg.r + 0.01, c[2] = {rg.c[0] + rho * 0.6, rg.c[1] + rho * 0.8}, h = 1e-6;
        double cp[2] = {c[0] + h, c[1]}, cm[2] = {c[0] - h, c[1]};
        region_moments mo, mp, mm;
        ENSURE(region_moments_at(&rg, c, &mo) == EXDEX_OK);
        ENSURE(region_moments_at(&rg, cp, &mp) == EXDEX_OK);
        ENSURE(region_moments_at(&rg, cm, &mm) == EXDEX_OK);
        ENSURE_CLOSE(-(mp.dist - mm.dist) / (2 * h), mo.dir[0], 1e-8);
        /* trace H = Phi: the edge sums cancel to it from terms as large as
         * the edges (|r1 - r0| <= L each), so to rounding of Phi + perimeter
         * (a sliver's Phi can be 1e-5 of its perimeter) */
        double per = 0.0;
        for (int i = 0; i < rg.n; i++)
            per += hypot(rg.v[(i + 1) % rg.n][0] - rg.v[i][0], rg.v[(i + 1) % rg.n][1] - rg.v[i][1]);
        ENSURE_CLOSE(mo.dyad[0] + mo.dyad[2], mo.inv, 1e-13 * (mo.inv + per));
        /* d G / d c_x = (H_xx - Phi, H_xy) */
        ENSURE_CLOSE((mp.dir[0] - mm.dir[0]) / (2 * h), mo.dyad[0] - mo.inv, 1e-6 * mo.inv);
        ENSURE_CLOSE((mp.dir[1] - mm.dir[1]) / (2 * h), mo.dyad[1], 1e-6 * mo.inv);
    }
}

EXDEX_TEST(region_polygon_to_disc)
{
    region dk, pg;
    double R = 0.4;
    region_set_disc(&dk, 0.1, 0.2, R);
    double err_prev = INFINITY;
    for (int n = 8; n <= 64; n *= 2) {
        memset(&pg, 0, sizeof pg);
        pg.kind = REGION_POLYGON;
        pg.n = n;
        for (int i = 0; i < n; i++)
            pg.v[i][0] = 0.1 + R * cos(2 * PI * i / n), pg.v[i][1] = 0.2 + R * sin(2 * PI * i / n);
        double c[2] = {0.1 + 0.55 * R, 0.2 - 0.3 * R};
        region_moments a, b;
        ENSURE(region_moments_at(&dk, c, &a) == EXDEX_OK);
        ENSURE(region_moments_at(&pg, c, &b) == EXDEX_OK);
        double err = fabs(a.dist - b.dist) / a.dist + fabs(a.dir[0] - b.dir[0]) / fabs(a.dir[0]) + fabs(a.inv - b.inv) / a.inv;
        /* inscribed n-gon: area deficit 1 - sin(2 pi/n) n / (2 pi) ~ (2 pi^2/3) / n^2 */
        ENSURE(err < 8.0 * PI * PI / ((double)n * n));
        ENSURE(err < err_prev / 3.0);
        err_prev = err;
    }
}

EXDEX_TEST(region_disc_against_gsl_elliptic)
{
    /* the disc's F and Phi from GSL's complete elliptic integrals directly
     * (gsl_sf_ellint_Kcomp, _Ecomp: Carlson's forms), on the branch where the
     * region module uses the AGM: F = (R/3)(4 R s E + 16 R rho^2 T / s),
     * Phi = 2 (s E + (R - rho) K), T = [(2 - k^2) E - 2 (1 - k^2) K] / (3 k^4) */
    double R = 0.7;
    region rg;
    region_set_disc(&rg, 0.0, 0.0, R);
    for (int i = 1; i < 60; i++) {
        double rho = R * (0.18 + 0.09 * i); /* k^2 >= 1/2 for rho/R in (0.17, 5.8) */
        if (fabs(rho - R) < 1e-9) continue;
        double s = R + rho, k2 = 4.0 * R * rho / (s * s), kp2 = ((R - rho) / s) * ((R - rho) / s);
        if (k2 < 0.5) continue;
        double k = sqrt(k2), K = gsl_sf_ellint_Kcomp(k, GSL_PREC_DOUBLE), E = gsl_sf_ellint_Ecomp(k, GSL_PREC_DOUBLE);
        double T = ((2.0 - k2) * E - 2.0 * kp2 * K) / (3.0 * k2 * k2);
        double c[2] = {rho, 0.0};
        region_moments mo;
        ENSURE(region_moments_at(&rg, c, &mo) == EXDEX_OK);
        ENSURE_CLOSE(mo.dist, (R / 3.0) * (4.0 * R * s * E + 16.0 * R * rho * rho * T / s), 1e-13 * R * R * R);
        ENSURE_CLOSE(mo.inv, 2.0 * (s * E + (R - rho) * K), 1e-13 * R);
    }
}
