/* test_limitsurf.c -- the limit surface interface (limitsurf.c).
 *
 * References, test by test:
 *   largest moment    closed forms: a uniform disc's 2/3 mu N R, a square's
 *                     (sqrt2 + asinh 1)/3 = 0.76520 mu N a (half-side a).
 *   centres           the force and moment of rotations about given centres
 *                     (inside, on an edge, outside, far: both branches of the
 *                     exact surface) against a brute-force grid sum of
 *                     -s/|s| over the region.
 *   asymptotes        derived by hand for a disc: near pure translation the
 *                     exact moment is omega R^2 / (4 |v|) (the ellipsoid's
 *                     (2R/3)^2 omega / |v|: 16/9 of it), near pure rotation
 *                     the exact force is |v| / (omega R) (the ellipsoid's 1.5x).
 *   inside            the exact surface lies inside the ellipsoid of the same
 *                     largest moment (disc, square, rectangles): every exact
 *                     wrench has ellipsoid gauge <= 1; the largest gap is
 *                     reported (the literature's 6.6 % for a disc is a check).
 *   identities        D(u) = -w(u) . u (degree-1 homogeneity), w = -grad D and
 *                     the Hessian against central differences, continuity
 *                     across the closed-form / quadrature switch, the gauge of
 *                     a slip's wrench is 1 and its slip direction is the slip.
 *   step              limitsurf_step: for the ellipsoid exdex_friction_solve
 *                     itself (bit for bit); for the exact surface the stick
 *                     test by the gauge, u+ = b + W p, p = cap w(u+), and
 *                     optimality against random points of the surface (brute
 *                     force), no kinetic energy added.
 */
#include "check.h"
#include "../exdex.h"
#include "../limitsurf.h"

#include <math.h>
#include <string.h>

static const double PI = 3.14159265358979323846;

/* xorshift64, restarted at each test from its seed */
static unsigned long long rs, rs_seed;
static double urand(void)
{
    if (rs_seed != check_seed()) rs = rs_seed = check_seed();
    rs ^= rs << 13, rs ^= rs >> 7, rs ^= rs << 17;
    return (double)(rs >> 11) / 9007199254740992.0;
}
static double srand1(void) { return 2.0 * urand() - 1.0; }

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

static int inside(const region *rg, double x, double y)
{
    if (rg->kind == REGION_DISC) return hypot(x - rg->c[0], y - rg->c[1]) <= rg->r;
    for (int i = 0; i < rg->n; i++) {
        const double *p = rg->v[i], *q = rg->v[(i + 1) % rg->n];
        if ((q[0] - p[0]) * (y - p[1]) - (q[1] - p[1]) * (x - p[0]) < 0.0) return 0;
    }
    return 1;
}

/* grid sum of the friction wrench per unit capacity, -(1/A) Int (s/|s|, r x s/|s|) dA */
static void grid_wrench(const region *rg, const double u[3], int N, double w[3], double *D)
{
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    if (rg->kind == REGION_DISC) {
        for (int k = 0; k < 2; k++) lo[k] = rg->c[k] - rg->r, hi[k] = rg->c[k] + rg->r;
    } else {
        for (int i = 0; i < rg->n; i++)
            for (int k = 0; k < 2; k++) lo[k] = fmin(lo[k], rg->v[i][k]), hi[k] = fmax(hi[k], rg->v[i][k]);
    }
    double hx = (hi[0] - lo[0]) / N, hy = (hi[1] - lo[1]) / N, A = 0, s0 = 0, s1 = 0, s2 = 0, sd = 0;
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            double x = lo[0] + (i + 0.5) * hx, y = lo[1] + (j + 0.5) * hy;
            if (!inside(rg, x, y)) continue;
            double sx = u[0] - u[2] * y, sy = u[1] + u[2] * x, s = hypot(sx, sy);
            A += 1;
            sd += s;
            if (s == 0.0) continue;
            s0 -= sx / s, s1 -= sy / s, s2 -= (x * sy - y * sx) / s;
        }
    w[0] = s0 / A, w[1] = s1 / A, w[2] = s2 / A;
    *D = sd / A;
}

static void set_square(region *rg, double a) { region_set_rectangle(rg, 0, 0, a, a); }

EXDEX_TEST(limitsurf_set_rejects)
{
    limitsurf ls;
    region rg;
    ENSURE(limitsurf_set_ellipsoid(&ls, 0.0) == EXDEX_EINVAL);
    ENSURE(limitsurf_set_ellipsoid(&ls, NAN) == EXDEX_EINVAL);
    ENSURE(limitsurf_set_ellipsoid(&ls, 0.01) == EXDEX_OK);
    rg.kind = REGION_NONE;
    ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_EINVAL);
    ENSURE(ls.type == &limitsurf_ellipsoid);
    region_set_disc(&rg, 0, 0, -1);
    ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_EINVAL);
    region_set_disc(&rg, 0, 0, 1);
    ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
    double g, w[3] = {NAN, 0, 0};
    ENSURE(limitsurf_gauge(&ls, w, &g, NULL) == EXDEX_EINVAL);
    ENSURE(limitsurf_sticks(&ls, w, 1.0) == -EXDEX_EINVAL);
}

EXDEX_TEST(limitsurf_largest_moment)
{
    limitsurf ls;
    region rg;
    double w[3], u[3] = {0, 0, 1};
    for (int k = 0; k < 3; k++) {
        double R = k == 0 ? 1.0 : k == 1 ? 0.01 : 3.0;
        region_set_disc(&rg, 0, 0, R);
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        limitsurf_wrench(&ls, u, w, NULL);
        ENSURE_CLOSE(w[2], -2.0 * R / 3.0, 1e-15 * R);
        ENSURE_SMALL(w[0], 1e-16);
        ENSURE_SMALL(w[1], 1e-16);
        /* the largest moment the surface carries: gauge of a pure moment */
        double m[3] = {0, 0, 1}, g;
        ENSURE(limitsurf_gauge(&ls, m, &g, NULL) == EXDEX_OK);
        ENSURE_CLOSE(1.0 / g, 2.0 * R / 3.0, 1e-12 * R);
        report(k == 0 ? "limitsurf disc largest moment / (mu N R)" : k == 1 ? "limitsurf disc R=0.01" : "limitsurf disc R=3",
               1.0 / (g * R));
        double a = R;
        set_square(&rg, a);
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        limitsurf_wrench(&ls, u, w, NULL);
        ENSURE_CLOSE(-w[2] / a, (sqrt(2.0) + asinh(1.0)) / 3.0, 1e-15);
        ENSURE_CLOSE(-w[2] / a, 0.76520, 5e-6);
        ENSURE(limitsurf_gauge(&ls, m, &g, NULL) == EXDEX_OK);
        ENSURE_CLOSE(1.0 / (g * a), 0.76520, 5e-6);
        if (k == 0) report("limitsurf square largest moment / (mu N a)", 1.0 / (g * a));
    }
}

EXDEX_TEST(limitsurf_centres_against_grid)
{
    limitsurf ls;
    region rg;
    for (int shape = 0; shape < 3; shape++) {
        if (shape == 0) region_set_disc(&rg, 0.003, -0.002, 0.01);
        else if (shape == 1) region_set_rectangle(&rg, -0.002, 0.001, 0.01, 0.006);
        else {
            /* a convex pentagon, reference point off its centroid */
            double v[5][2] = {{-0.01, -0.008}, {0.012, -0.006}, {0.015, 0.004}, {0.002, 0.011}, {-0.011, 0.006}};
            memset(&rg, 0, sizeof rg);
            rg.kind = REGION_POLYGON, rg.n = 5;
            memcpy(rg.v, v, sizeof v);
        }
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        /* centres of rotation at 0, 0.3, 0.9, 1.0 (rim / near edge), 2, 10 region sizes
         * (the last is on the quadrature branch), and a pure translation */
        const double fr[7] = {0.0, 0.3, 0.9, 1.0, 2.0, 10.0, -1.0};
        for (int k = 0; k < 7; k++) {
            double ang = 2 * PI * urand(), d = fr[k] * 0.01, c[2] = {ls.g[0] + d * cos(ang), ls.g[1] + d * sin(ang)};
            double om = urand() < 0.5 ? -3.0 : 2.0, u[3];
            if (fr[k] < 0) {
                u[0] = cos(ang), u[1] = sin(ang), u[2] = 0.0;
            } else {
                /* v + om z x c = 0 */
                u[0] = om * c[1], u[1] = -om * c[0], u[2] = om;
            }
            double w[3], wg[3], D, Dg;
            D = limitsurf_wrench(&ls, u, w, NULL);
            grid_wrench(&rg, u, 1500, wg, &Dg);
            ENSURE_CLOSE(w[0], wg[0], 3e-3);
            ENSURE_CLOSE(w[1], wg[1], 3e-3);
            ENSURE_CLOSE(w[2], wg[2], 3e-3 * 0.01);
            ENSURE_CLOSE(D, Dg, 3e-3 * sqrt(dot3(u, u)) * (1 + 0.02 * fabs(u[2])));
            ENSURE_CLOSE(D, limitsurf_dissipation(&ls, u), 1e-15 * D);
        }
    }
}

EXDEX_TEST(limitsurf_disc_asymptotes)
{
    limitsurf ls, le;
    region rg;
    double R = 0.02, w[3], we[3];
    region_set_disc(&rg, 0, 0, R);
    ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
    ENSURE(limitsurf_set_ellipsoid(&le, 2.0 * R / 3.0) == EXDEX_OK);
    /* near pure translation: moment -omega R^2 / (4 |v|) (1 + O(omega^2 R^2 / v^2)) */
    double u[3] = {0.3, -0.4, 1e-3};
    limitsurf_wrench(&ls, u, w, NULL);
    limitsurf_wrench(&le, u, we, NULL);
    ENSURE_CLOSE(w[2] / (-u[2] * R * R / (4 * 0.5)), 1.0, 1e-8);
    ENSURE_CLOSE(we[2] / w[2], 16.0 / 9.0, 1e-8);
    /* near pure rotation: |f| = |v| / (|omega| R) (1 + O(rho^2 / R^2)) */
    double u2[3] = {1e-6, 0, 1.0};
    report("limitsurf disc ellipsoid/exact moment near translation", we[2] / w[2]);
    limitsurf_wrench(&ls, u2, w, NULL);
    limitsurf_wrench(&le, u2, we, NULL);
    ENSURE_CLOSE(-w[0] / (1e-6 / R), 1.0, 1e-6);
    ENSURE_CLOSE(we[0] / w[0], 1.5, 1e-6);
    report("limitsurf disc ellipsoid/exact force near rotation", we[0] / w[0]);
}

EXDEX_TEST(limitsurf_exact_inside_ellipsoid)
{
    /* disc, square, 2:1 rectangle; a 10:1 strip is not inside (reported) */
    for (int shape = 0; shape < 4; shape++) {
        region rg;
        limitsurf ls, le;
        if (shape == 0) region_set_disc(&rg, 0, 0, 1.0);
        else region_set_rectangle(&rg, 0, 0, 1.0, shape == 1 ? 1.0 : shape == 2 ? 0.5 : 0.1);
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        /* the ellipsoid of the same largest moment: e_r = mean distance from the centre */
        ENSURE(limitsurf_set_ellipsoid(&le, ls.e[2]) == EXDEX_OK);
        double gmin = INFINITY, gmax = 0.0;
        for (int k = 0; k < 4000; k++) {
            double u[3] = {srand1(), srand1(), srand1() * 3.0}, w[3], g;
            /* include centres of rotation on the region's rim */
            if (k % 4 == 0) {
                double a = 2 * PI * urand(), rr = 0.8 + 0.4 * urand();
                u[0] = rr * sin(a), u[1] = -rr * cos(a), u[2] = 1.0;
            }
            limitsurf_wrench(&ls, u, w, NULL);
            ENSURE(limitsurf_gauge(&le, w, &g, NULL) == EXDEX_OK);
            gmin = fmin(gmin, g), gmax = fmax(gmax, g);
        }
        if (shape < 3) ENSURE(gmax <= 1.0 + 1e-12);
        else report("limitsurf 10:1 strip exact/ellipsoid largest radial ratio", gmax);
        /* the surfaces touch at the pure moment and the pure force */
        double uf[3] = {1, 0, 0}, um[3] = {0, 0, 1}, w[3], g;
        limitsurf_wrench(&ls, uf, w, NULL);
        ENSURE(limitsurf_gauge(&le, w, &g, NULL) == EXDEX_OK);
        ENSURE_CLOSE(g, 1.0, 1e-12);
        limitsurf_wrench(&ls, um, w, NULL);
        ENSURE(limitsurf_gauge(&le, w, &g, NULL) == EXDEX_OK);
        ENSURE_CLOSE(g, 1.0, 1e-12);
        /* and the exact surface is well inside elsewhere (a few per cent) */
        ENSURE(gmin < 0.97);
        if (shape == 0) report("limitsurf disc exact/ellipsoid smallest radial ratio", gmin);
        if (shape == 1) report("limitsurf square exact/ellipsoid smallest radial ratio", gmin);
    }
}

static void random_region(region *rg, int k)
{
    if (k % 3 == 0) {
        region_set_disc(rg, 0.01 * srand1(), 0.01 * srand1(), 0.005 + 0.02 * urand());
    } else {
        int n = 3 + k % 7;
        double ang[REGION_MAX_VERTICES];
        for (int i = 0; i < n; i++) ang[i] = 2 * PI * (i + 0.8 * urand()) / n;
        double a = 0.005 + 0.02 * urand(), b = 0.005 + 0.02 * urand(), cx = 0.01 * srand1(), cy = 0.01 * srand1();
        memset(rg, 0, sizeof *rg);
        rg->kind = REGION_POLYGON, rg->n = n;
        for (int i = 0; i < n; i++) rg->v[i][0] = cx + a * cos(ang[i]), rg->v[i][1] = cy + b * sin(ang[i]);
    }
}

EXDEX_TEST(limitsurf_identities)
{
    for (int k = 0; k < 60; k++) {
        region rg;
        limitsurf ls;
        random_region(&rg, k);
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        for (int j = 0; j < 8; j++) {
            double u[3] = {srand1(), srand1(), srand1() * (j % 4 == 0 ? 1e-3 : 100.0)}, w[3], H[9], D;
            D = limitsurf_wrench(&ls, u, w, H);
            double nu = sqrt(dot3(u, u));
            ENSURE_CLOSE(D, -dot3(w, u), 1e-13 * nu);
            /* H u = 0 (the gradient is homogeneous of degree 0) */
            for (int i = 0; i < 3; i++) {
                double sc = fabs(H[3 * i] * u[0]) + fabs(H[3 * i + 1] * u[1]) + fabs(H[3 * i + 2] * u[2]);
                ENSURE_SMALL(H[3 * i] * u[0] + H[3 * i + 1] * u[1] + H[3 * i + 2] * u[2], 1e-9 * sc);
            }
            /* central differences, a step relative to each component's scale */
            for (int c = 0; c < 3; c++) {
                double h = 1e-6 * (c < 2 ? 1.0 : 100.0), up[3], um[3], wp[3], wm[3];
                memcpy(up, u, sizeof up), memcpy(um, u, sizeof um);
                up[c] += h, um[c] -= h;
                double Dp = limitsurf_wrench(&ls, up, wp, NULL), Dm = limitsurf_wrench(&ls, um, wm, NULL);
                double sc = c < 2 ? 1.0 : 0.03;
                ENSURE_CLOSE(-(Dp - Dm) / (2 * h), w[c], 1e-6 * sc);
                /* H is positive semi-definite: |H_ic| <= sqrt(H_ii H_cc) sets each entry's scale */
                /* (plus the two branches' 1e-11 difference, should the pair straddle the switch) */
                for (int i = 0; i < 3; i++)
                    ENSURE_CLOSE(-(wp[i] - wm[i]) / (2 * h), H[3 * i + c],
                                 1e-5 * sqrt(H[4 * i] * H[4 * c]) + 1e-11 * (i < 2 ? 1.0 : ls.reach) / h);
            }
            /* gauge of the wrench 1; its slip direction the slip */
            double g, dir[3];
            int gst = limitsurf_gauge(&ls, w, &g, dir);
            ENSURE(gst == EXDEX_OK);
            ENSURE_CLOSE(g, 1.0, 1e-10);
            for (int i = 0; i < 3; i++) ENSURE_CLOSE(dir[i], u[i] / nu, 1e-6);
            ENSURE(limitsurf_sticks(&ls, w, 1.0 + 1e-9) == 1);
            ENSURE(limitsurf_sticks(&ls, w, 1.0 - 1e-9) == 0);
        }
        /* continuity across the switch to quadrature: |slip at the centroid| = 4 reach |omega| */
        double ang = 2 * PI * urand(), uu[2][3];
        for (int s = 0; s < 2; s++) {
            double f = 4.0 * (s ? 1.0 + 1e-12 : 1.0 - 1e-12), om = 1.0;
            double sx = f * ls.reach * cos(ang), sy = f * ls.reach * sin(ang);
            /* slip at the centroid s = v + om z x g */
            uu[s][0] = sx + om * ls.g[1], uu[s][1] = sy - om * ls.g[0], uu[s][2] = om;
        }
        double w0[3], w1[3];
        double D0 = limitsurf_wrench(&ls, uu[0], w0, NULL), D1 = limitsurf_wrench(&ls, uu[1], w1, NULL);
        /* (the closed form's edge sums lose about 1e3 rounding units there) */
        ENSURE_CLOSE(D0, D1, 1e-11 * D0);
        ENSURE_CLOSE(w0[0], w1[0], 1e-11);
        ENSURE_CLOSE(w0[1], w1[1], 1e-11);
        ENSURE_CLOSE(w0[2], w1[2], 1e-11 * ls.reach);
    }
}

/* the ellipsoid through the table: the paper's Eq. 6 */
EXDEX_TEST(limitsurf_ellipsoid_table)
{
    limitsurf le;
    ENSURE(limitsurf_set_ellipsoid(&le, 0.013) == EXDEX_OK);
    for (int k = 0; k < 100; k++) {
        double u[3] = {srand1(), srand1(), 50 * srand1()}, w[3], eu[3], s = 0, g, dir[3];
        for (int i = 0; i < 3; i++) eu[i] = le.e[i] * u[i], s += eu[i] * eu[i];
        s = sqrt(s);
        double D = limitsurf_wrench(&le, u, w, NULL);
        ENSURE_CLOSE(D, s, 1e-15 * s);
        for (int i = 0; i < 3; i++) ENSURE_CLOSE(w[i], -le.e[i] * le.e[i] * u[i] / s, 1e-15);
        ENSURE(limitsurf_gauge(&le, w, &g, dir) == EXDEX_OK);
        ENSURE_CLOSE(g, 1.0, 1e-14);
        double nu = sqrt(dot3(u, u));
        for (int i = 0; i < 3; i++) ENSURE_CLOSE(dir[i], u[i] / nu, 1e-12);
    }
}

static void random_spd(double W[9])
{
    double B[9];
    for (int i = 0; i < 9; i++) B[i] = srand1();
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double s = i == j ? 0.5 : 0.0;
            for (int k = 0; k < 3; k++) s += B[3 * i + k] * B[3 * j + k];
            W[3 * i + j] = s;
        }
}

EXDEX_TEST(limitsurf_step_ellipsoid_is_friction_solve)
{
    limitsurf le;
    ENSURE(limitsurf_set_ellipsoid(&le, 0.02) == EXDEX_OK);
    for (int k = 0; k < 200; k++) {
        double W[9], b[3] = {srand1(), srand1(), 30 * srand1()}, cap = 2 * urand();
        random_spd(W);
        for (int i = 0; i < 3; i++) W[3 * i + 2] *= 2500, W[6 + i] *= 2500; /* rotation rows ~ 1/r^2 */
        exdex_friction_prep prep;
        ENSURE(exdex_friction_prepare(&prep, W, le.e) == EXDEX_OK);
        exdex_friction_result a, b2;
        ENSURE(limitsurf_step(&le, &prep, b, cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &a) == EXDEX_OK);
        ENSURE(exdex_friction_solve(&prep, b, cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &b2) == EXDEX_OK);
        ENSURE(memcmp(&a, &b2, sizeof a) == 0);
    }
}

EXDEX_TEST(limitsurf_step_exact)
{
    int n_stick = 0, n_slip = 0;
    for (int k = 0; k < 150; k++) {
        region rg;
        limitsurf ls, le;
        random_region(&rg, k);
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        ENSURE(limitsurf_set_ellipsoid(&le, ls.e[2]) == EXDEX_OK);
        double W[9], b[3], cap;
        random_spd(W);
        /* a body-like Delassus matrix: translation 1/m, rotation 1/I ~ 1/(m r^2) */
        double r2 = 1.0 / (ls.e[2] * ls.e[2]);
        for (int i = 0; i < 3; i++) W[3 * i + 2] *= sqrt(r2), W[6 + i] *= sqrt(r2);
        for (int i = 0; i < 3; i++) b[i] = srand1() * (i < 2 ? 1.0 : sqrt(r2));
        cap = 3 * urand();
        exdex_friction_prep prep;
        ENSURE(exdex_friction_prepare(&prep, W, ls.e) == EXDEX_OK);
        exdex_friction_result r;
        int st = limitsurf_step(&ls, &prep, b, cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &r);
        ENSURE(st == EXDEX_OK);
        if (st != EXDEX_OK) continue;
        /* u+ = b + W p */
        double Wp[3];
        for (int i = 0; i < 3; i++) Wp[i] = W[3 * i] * r.p[0] + W[3 * i + 1] * r.p[1] + W[3 * i + 2] * r.p[2];
        for (int i = 0; i < 3; i++) ENSURE_CLOSE(r.u[i], r.stick ? 0.0 : b[i] + Wp[i], 1e-12 * (fabs(b[i]) + fabs(Wp[i])));
        /* p inside cap L (gauge <= cap) */
        double g;
        ENSURE(limitsurf_gauge(&ls, r.p, &g, NULL) == EXDEX_OK);
        ENSURE(g <= cap * (1 + 1e-9) + 1e-300);
        /* objective f(p) = 0.5 p W p + b p no larger than at random points of the surface */
        double f = 0.5 * dot3(r.p, Wp) + dot3(b, r.p);
        for (int j = 0; j < 300; j++) {
            double uq[3] = {srand1(), srand1(), srand1() * sqrt(r2)}, wq[3], Wq[3];
            limitsurf_wrench(&ls, uq, wq, NULL);
            double t = urand();
            for (int i = 0; i < 3; i++) wq[i] *= cap * t;
            for (int i = 0; i < 3; i++) Wq[i] = W[3 * i] * wq[0] + W[3 * i + 1] * wq[1] + W[3 * i + 2] * wq[2];
            double fq = 0.5 * dot3(wq, Wq) + dot3(b, wq);
            ENSURE(f <= fq + 1e-12 * (fabs(f) + fabs(fq)));
        }
        /* friction adds no kinetic energy: |u+|_W^-1 <= |b|_W^-1, i.e. p . (b + W p / 2) <= 0 */
        ENSURE(dot3(r.p, b) + 0.5 * dot3(r.p, Wp) <= 1e-14 * fabs(dot3(r.p, b)));
        {
            /* with the bounds prepared: the same decision and the same impulse */
            limitsurf lb = ls;
            exdex_friction_result rb;
            limitsurf_prepare_bounds(&lb);
            ENSURE(lb.kmin > 0.0 && lb.kmax < INFINITY);
            ENSURE(limitsurf_step(&lb, &prep, b, cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &rb) == EXDEX_OK);
            ENSURE(rb.stick == r.stick);
            for (int i = 0; i < 3; i++) ENSURE_CLOSE(rb.p[i], r.p[i], 1e-9 * cap * (i < 2 ? 1 : ls.e[2]));
        }
        if (r.stick) {
            n_stick++;
            ENSURE(r.sigma == 0.0);
        } else {
            n_slip++;
            /* maximum dissipation: p = cap w(u+), i.e. p on the surface cap L
             * and u+ along the surface's normal n(p). Checked as a backward
             * error: u+'s part across n(p) (E-scaled) against the size of
             * u+'s terms b and W p. A forward check of p against cap w(u+)
             * is not posed at this accuracy: near a stick u+ is a small
             * difference of those terms, and W's condition enters it (2e-11
             * off where p is 6e-3 in one of these draws) */
            double w[3], gn, n[3], En[3], Eu[3], nn = 0.0, un = 0.0, sz = 0.0, across = 0.0;
            double D = limitsurf_wrench(&ls, r.u, w, NULL);
            ENSURE_CLOSE(D, r.sigma, 1e-12 * D);
            ENSURE_CLOSE(g, cap, 1e-9 * cap);
            ENSURE(limitsurf_gauge(&ls, r.p, &gn, n) == EXDEX_OK);
            for (int i = 0; i < 3; i++) {
                En[i] = n[i] * ls.e[i];
                Eu[i] = r.u[i] * ls.e[i];
                nn += En[i] * En[i];
                un += Eu[i] * En[i];
                sz += pow((fabs(b[i]) + fabs(Wp[i])) * ls.e[i], 2);
            }
            ENSURE(un > 0.0); /* outward: the slip dissipates */
            for (int i = 0; i < 3; i++) across += pow(Eu[i] - un / nn * En[i], 2);
            ENSURE(sqrt(across) <= 1e-10 * sqrt(sz));
        }
    }
    ENSURE(n_stick > 10 && n_slip > 10);
}

/* kmin |E u| <= D(u) <= kmax |E u| on 2000 random slips, the first n of
 * them of translation and rotation alike, the rest nearly rotations */
static void bounds_hold(const limitsurf *ls, int n)
{
    for (int j = 0; j < 2000; j++) {
        double s = j < n ? 1.0 : 1e-3;
        double u[3] = {s * srand1(), s * srand1(), srand1() / ls->e[2]}, eu = 0.0;
        for (int i = 0; i < 3; i++) eu += (ls->e[i] * u[i]) * (ls->e[i] * u[i]);
        double D = limitsurf_dissipation(ls, u);
        ENSURE(D >= ls->kmin * sqrt(eu) && D <= ls->kmax * sqrt(eu));
    }
}

EXDEX_TEST(limitsurf_bounds)
{
    /* kmin |E u| <= D(u) <= kmax |E u| on random slips; the disc's are the
     * ratios of the exact surface to its ellipsoid (0.934 and 1, widened 1e-3) */
    for (int k = 0; k < 12; k++) {
        region rg;
        limitsurf ls;
        random_region(&rg, k);
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        limitsurf_prepare_bounds(&ls);
        bounds_hold(&ls, 2000);
    }
    region rg;
    limitsurf ls;
    region_set_disc(&rg, 0, 0, 0.01);
    ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
    limitsurf_prepare_bounds(&ls);
    ENSURE_CLOSE(ls.kmin, 0.9342051836507127 * (1 - 1e-3), 2e-6);
    ENSURE_CLOSE(ls.kmax, 1.0 + 1e-3, 1e-6);
}

EXDEX_TEST(limitsurf_quick_bounds_hold)
{
    /* limitsurf_quick_bounds: kmin |E u| <= D(u) <= kmax |E u| on random
     * slips of random regions, centred or not on the reference point (the
     * bounds are proven, not sampled), and no tighter than the sampled ones;
     * a centred disc's from the closed forms: kmin = 1 / sqrt(2), kmax =
     * sqrt(J / (A e_r^2)) = sqrt(9 / 8) */
    for (int k = 0; k < 30; k++) {
        region rg;
        limitsurf ls, lp;
        random_region(&rg, k);
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        lp = ls;
        limitsurf_quick_bounds(&ls);
        limitsurf_prepare_bounds(&lp);
        ENSURE(ls.kmin > 0.0 && ls.kmax < INFINITY);
        ENSURE(ls.kmin <= lp.kmin / (1 - 1e-3) && ls.kmax >= lp.kmax / (1 + 1e-3));
        bounds_hold(&ls, 1000);
    }
    region rg;
    limitsurf ls;
    region_set_disc(&rg, 0, 0, 0.01);
    ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
    limitsurf_quick_bounds(&ls);
    ENSURE_CLOSE(ls.kmin, sqrt(0.5) * (1 - 1e-6), 1e-12);
    ENSURE_CLOSE(ls.kmax, sqrt(9.0 / 8.0) * (1 + 1e-6), 1e-12);
}

EXDEX_TEST(limitsurf_gauge_hessian_against_differences)
{
    /* the gauge's gradient and Hessian against central differences of the
     * gauge and of the gradient; Hess g w = 0 and grad g . w = g (degrees 0
     * and 1); both surfaces */
    for (int k = 0; k < 24; k++) {
        region rg;
        limitsurf ls;
        random_region(&rg, k);
        if (k % 4 == 3) {
            ENSURE(limitsurf_set_ellipsoid(&ls, 0.004 + 0.01 * urand()) == EXDEX_OK);
        } else {
            ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        }
        for (int j = 0; j < 6; j++) {
            double w[3] = {srand1(), srand1(), srand1() * ls.e[2]}, g, gr[3], H[9], hstep = 1e-5;
            ENSURE(limitsurf_gauge_hessian(&ls, w, &g, gr, H) == EXDEX_OK);
            ENSURE_CLOSE(dot3(gr, w), g, 1e-10 * g);
            for (int i = 0; i < 3; i++) {
                double hw = H[3 * i] * w[0] + H[3 * i + 1] * w[1] + H[3 * i + 2] * w[2];
                ENSURE_SMALL(hw, 1e-8 * (fabs(H[3 * i]) + fabs(H[3 * i + 1]) + fabs(H[3 * i + 2])) * sqrt(dot3(w, w)));
            }
            for (int c = 0; c < 3; c++) {
                double wp[3], wm[3], gp, gm, grp[3], grm[3], sc = c < 2 ? 1.0 : ls.e[2];
                memcpy(wp, w, sizeof wp);
                memcpy(wm, w, sizeof wm);
                wp[c] += hstep * sc;
                wm[c] -= hstep * sc;
                ENSURE(limitsurf_gauge_hessian(&ls, wp, &gp, grp, NULL) == EXDEX_OK);
                ENSURE(limitsurf_gauge_hessian(&ls, wm, &gm, grm, NULL) == EXDEX_OK);
                ENSURE_CLOSE(gr[c], (gp - gm) / (2 * hstep * sc), 1e-6 * sqrt(dot3(gr, gr)) * (c < 2 ? 1 : 1 / ls.e[2]));
                for (int i = 0; i < 3; i++) {
                    double fd = (grp[i] - grm[i]) / (2 * hstep * sc), si = i < 2 ? 1.0 : ls.e[2];
                    ENSURE_CLOSE(H[3 * i + c], fd, 1e-5 / (g * sc * si));
                }
            }
        }
    }
}

EXDEX_TEST(limitsurf_min_combination_kkt)
{
    /* the least gauge over lam >= 0 of a + lam_1 b_1 + lam_2 b_2 (exact
     * surface, cap NaN: the minimum itself): the optimality conditions
     * (b_j . grad g = 0 where lam_j > 0, >= 0 where lam_j = 0) to the
     * search's resolution, which stops where its model predicts a decrease
     * below 1e-13 of g: a step along b_j would gain (b_j . grad g)^2 /
     * (2 b_j' Hess g b_j), which must be below 1e-12 of g (a raw bound on
     * b_j . grad g would ask for 1e-15 where Hess g is large along b_j: a
     * torque row on a small patch); and no grid point of lam in
     * [0, 3 |a| / |b|]^2 below it */
    int n_free = 0, n_bound = 0;
    for (int k = 0; k < 40; k++) {
        region rg;
        limitsurf ls;
        random_region(&rg, k);
        ENSURE(limitsurf_set_exact(&ls, &rg) == EXDEX_OK);
        limitsurf_prepare_bounds(&ls);
        double a[3] = {srand1(), srand1(), srand1() * ls.e[2]}, b[2][3], lam[2], g, w[3], gr[3], gg;
        for (int j = 0; j < 2; j++)
            for (int i = 0; i < 3; i++) b[j][i] = srand1() * (i < 2 ? 1.0 : ls.e[2]);
        g = limitsurf_min_combination(&ls, 2, a, (const double (*)[3])b, NAN, lam, NULL);
        ENSURE(isfinite(g) && g >= 0.0);
        for (int i = 0; i < 3; i++) w[i] = a[i] + lam[0] * b[0][i] + lam[1] * b[1][i];
        if (!(sqrt(dot3(w, w)) > 1e-9)) continue;   /* the cone reaches -a: g = 0 */
        double H[9];
        ENSURE(limitsurf_gauge_hessian(&ls, w, &gg, gr, H) == EXDEX_OK);
        ENSURE_CLOSE(gg, g, 1e-12 * g);
        for (int j = 0; j < 2; j++) {
            double d = dot3(b[j], gr), curv = 0.0;
            for (int p = 0; p < 3; p++)
                for (int q = 0; q < 3; q++) curv += b[j][p] * H[3 * p + q] * b[j][q];
            ENSURE(curv > 0.0);
            if (lam[j] > 0.0) {
                n_free++;
                ENSURE(d * d / (2.0 * curv) <= 1e-12 * g);
            } else {
                n_bound++;
                ENSURE(d >= 0.0 || d * d / (2.0 * curv) <= 1e-12 * g);
            }
        }
        double L = 3.0 * sqrt(dot3(a, a)) / fmin(sqrt(dot3(b[0], b[0])), sqrt(dot3(b[1], b[1])));
        for (int p = 0; p <= 40; p++)
            for (int q = 0; q <= 40; q++) {
                double l0 = L * p / 40, l1 = L * q / 40, wq[3], gq;
                for (int i = 0; i < 3; i++) wq[i] = a[i] + l0 * b[0][i] + l1 * b[1][i];
                if (limitsurf_gauge(&ls, wq, &gq, NULL) != EXDEX_OK) continue;
                ENSURE(gq >= g * (1 - 1e-9));
            }
    }
    ENSURE(n_free > 5 && n_bound > 5);
}
