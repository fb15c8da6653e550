/* test_cone.c -- twist cones and their volumes (cone.c, paper Section 3).
 * Expected values are closed forms worked out in the comments, symmetry
 * identities, or an independent method (QMC, brute-force scans). */
#include "check.h"
#include "../exdex.h"

#include <float.h>
#include <stdlib.h>

static const double PI = 3.14159265358979323846;
static const double R2 = 1.41421356237309504880;

/* the paper's Eq. 13 box, centred: [-dVx/2, dVx/2] x [-dVy/2, dVy/2] x [-dwz/2, dwz/2] */
static void eq13_box(double lo[3], double hi[3])
{
    double d[3] = {1.0 / R2, 1.0 / R2, 2.0};
    for (int j = 0; j < 3; j++) { lo[j] = -d[j] / 2; hi[j] = d[j] / 2; }
}

static double vol(const double *rows, int m, const double lo[3], const double hi[3])
{
    double v = NAN;
    ENSURE(exdex_cone_volume_exact(rows, m, lo, hi, &v) == EXDEX_OK);
    return v;
}

EXDEX_TEST(cone_contact_row)
{
    // r = (-1/2, -1/2), n = (0, 1): row (0, 1, r_x n_y - r_y n_x) = (0, 1, -1/2)
    double row[3], r[2] = {-0.5, -0.5}, n[2] = {0.0, 1.0};
    exdex_contact_row(row, r, n);
    ENSURE_CLOSE(row[0], 0.0, 0.0);
    ENSURE_CLOSE(row[1], 1.0, 0.0);
    ENSURE_CLOSE(row[2], -0.5, 0.0);
}

EXDEX_TEST(cone_paper_rows)
{
    // Eqs. 10-11 at phi = 30 deg, theta = 90 deg, by hand:
    // (1/2, sqrt3/2, -1/4) and (-sin 60, cos 60, -(1 - sin 60)/2)
    double rows[6], d = PI / 180.0, s3 = sqrt(3.0);
    exdex_cone_rows_paper(rows, 30 * d, 90 * d);
    ENSURE_CLOSE(rows[0], 0.5, 1e-15);
    ENSURE_CLOSE(rows[1], s3 / 2, 1e-15);
    ENSURE_CLOSE(rows[2], -0.25, 1e-15);
    ENSURE_CLOSE(rows[3], -s3 / 2, 1e-15);
    ENSURE_CLOSE(rows[4], 0.5, 1e-15);
    ENSURE_CLOSE(rows[5], -0.5 * (1 - s3 / 2), 1e-15);
}

EXDEX_TEST(cone_exact_half_space)
{
    // Closed form: a half-space through the centre of a centred box cuts it
    // in half (central symmetry), whatever its normal.
    double lo[3], hi[3];
    eq13_box(lo, hi);
    double normals[][3] = {{1, 0, 0}, {0, 0, -1}, {0.3, -0.7, 0.2}, {1e-3, 2.0, -5.0},
                           {-0.9, 0.1, 0.45}};
    for (int i = 0; i < 5; i++) ENSURE_CLOSE(vol(normals[i], 1, lo, hi), 0.5, 1e-12);
    // non-cubic, non-unit centred box: half of 2 * 6 * 0.5
    double lo2[3] = {-1, -3, -0.25}, hi2[3] = {1, 3, 0.25};
    ENSURE_CLOSE(vol(normals[2], 1, lo2, hi2), 3.0, 1e-12);
}

EXDEX_TEST(cone_exact_octant)
{
    // Closed form: the octant x, y, z >= 0 of a centred box is 1/8 of it
    double lo[3], hi[3];
    eq13_box(lo, hi);
    double rows[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    ENSURE_CLOSE(vol(rows, 3, lo, hi), 0.125, 1e-12);
    // quadrant Vx >= 0, wz >= 0 -> 1/4; three rows with a redundant one -> 1/4
    double q[9] = {1, 0, 0, 0, 0, 1, 2, 0, 1};
    ENSURE_CLOSE(vol(q, 2, lo, hi), 0.25, 1e-12);
    ENSURE_CLOSE(vol(q, 3, lo, hi), 0.25, 1e-12);
}

EXDEX_TEST(cone_exact_wedges)
{
    // Closed form: in |Vx| <= a, |Vy| <= b, |wz| <= c the wedge
    // Vy >= k |Vx| (rows (-k, 1, 0), (k, 1, 0)) has cross-section area
    //   2 ab - k a^2        if k a <= b
    //   b^2 / k             if k a >= b
    // times the height 2c.
    double a = 0.4, b = 0.7, c = 1.3;
    double lo[3] = {-a, -b, -c}, hi[3] = {a, b, c};
    double ks[] = {0.0, 0.5, 1.75, 2.0, 10.0};
    for (int i = 0; i < 5; i++) {
        double k = ks[i];
        double rows[6] = {-k, 1, 0, k, 1, 0};
        double area = k * a <= b ? 2 * a * b - k * a * a : b * b / k;
        ENSURE_CLOSE(vol(rows, 2, lo, hi), area * 2 * c, 1e-12);
    }
    // Closed form: the square's floor edge (contacts (+-1/2, -1/2), n = (0, 1))
    // gives Vy >= |wz| / 2; in the Eq. 13 box b = 1/(2 sqrt2), c = 1, k c > b:
    // area b^2 / k = 1/4 in (wz, Vy), times dVx = 1/sqrt2.
    double lo13[3], hi13[3];
    eq13_box(lo13, hi13);
    double floor_rows[6] = {0, 1, -0.5, 0, 1, 0.5};
    ENSURE_CLOSE(vol(floor_rows, 2, lo13, hi13), 0.25 / R2, 1e-12);
    ENSURE_CLOSE(vol(floor_rows, 2, lo13, hi13), ref("tool_floor_edge_eq13"), 1e-12);
    // Closed form: the square in a square corner, phi = 0 (edge on the floor,
    // edge on the wall): Vy >= |wz|/2 and -Vx >= |wz|/2, with a = b = 1/(2 sqrt2),
    // 2a < c = 1: V = 2 int_0^{2a} (a - w/2)^2 dw = 4 a^3 / 3 = 1 / (12 sqrt2).
    double corner[12] = {0, 1, -0.5, 0, 1, 0.5, -1, 0, -0.5, -1, 0, 0.5};
    ENSURE_CLOSE(vol(corner, 4, lo13, hi13), 1.0 / (12.0 * R2), 1e-12);
    ENSURE_CLOSE(vol(corner, 4, lo13, hi13), ref("tool_corner_square_eq13"), 1e-12);
}

EXDEX_TEST(cone_exact_symmetry_identity)
{
    // Closed form: for a centred box, V(a1, a2) + V(a1, -a2) = V(a1) = box/2.
    double lo[3] = {-0.3, -1.1, -0.8}, hi[3] = {0.3, 1.1, 0.8};
    double box = 0.6 * 2.2 * 1.6;
    double rows[6] = {0.2, -0.9, 0.35, -0.4, 0.25, 1.7};
    double neg[6] = {0.2, -0.9, 0.35, 0.4, -0.25, -1.7};
    ENSURE_CLOSE(vol(rows, 2, lo, hi) + vol(neg, 2, lo, hi), box / 2, 1e-12);
}

EXDEX_TEST(cone_exact_empty_and_whole)
{
    double lo[3], hi[3];
    eq13_box(lo, hi);
    // Closed form: 0 = (1,0,0) + 2 (-1/2, 1, 0)/2 ... rows whose positive
    // combination vanishes leave only a null set: volume 0.
    double empty[9] = {1, 0, 0, -0.5, 1, 0, -0.5, -1, 0};
    ENSURE_CLOSE(vol(empty, 3, lo, hi), 0.0, 1e-12);
    double plane[6] = {0.3, 0.2, -1, -0.3, -0.2, 1};
    ENSURE_CLOSE(vol(plane, 2, lo, hi), 0.0, 1e-12);
    // no rows, or all-zero rows (padding): the whole box
    double zero[6] = {0, 0, 0, 0, 0, 0};
    ENSURE_CLOSE(vol(NULL, 0, lo, hi), 1.0, 1e-12);
    ENSURE_CLOSE(vol(zero, 2, lo, hi), 1.0, 1e-12);
}

EXDEX_TEST(cone_exact_offset_box)
{
    // Closed forms for a box not centred at the apex:
    // [-1,3] x [0,2] x [-1,1] (volume 16): x >= 0 keeps 3/4 -> 12;
    // y >= 0 keeps all -> 16; x >= 0, z >= 0 -> 6.
    double lo[3] = {-1, 0, -1}, hi[3] = {3, 2, 1};
    double rx[3] = {1, 0, 0}, ry[3] = {0, 1, 0}, rxz[6] = {1, 0, 0, 0, 0, 1};
    ENSURE_CLOSE(vol(rx, 1, lo, hi), 12.0, 1e-12);
    ENSURE_CLOSE(vol(ry, 1, lo, hi), 16.0, 1e-12);
    ENSURE_CLOSE(vol(rxz, 2, lo, hi), 6.0, 1e-12);
    // a box strictly inside the half-space x + y >= 0: all of it (volume 1)
    double lo2[3] = {1, 1, -5}, hi2[3] = {2, 2, -4}, rs[3] = {1, 1, 0};
    ENSURE_CLOSE(vol(rs, 1, lo2, hi2), 1.0, 1e-12);
    // positive-orthant box [0,1]^3 and the plane x >= y: half (reflection x<->y)
    double lo3[3] = {0, 0, 0}, hi3[3] = {1, 1, 1}, rd[3] = {1, -1, 0};
    ENSURE_CLOSE(vol(rd, 1, lo3, hi3), 0.5, 1e-12);
}

EXDEX_TEST(cone_exact_invalid)
{
    double lo[3] = {0, 0, 0}, hi[3] = {1, 1, 0}, rows[3] = {1, 0, 0}, v;
    ENSURE(exdex_cone_volume_exact(rows, 1, lo, hi, &v) == EXDEX_EINVAL);
    double hi2[3] = {1, 1, 1}, bad[3] = {NAN, 0, 0};
    ENSURE(exdex_cone_volume_exact(bad, 1, lo, hi2, &v) == EXDEX_EINVAL);
    ENSURE(exdex_cone_volume_exact(rows, EXDEX_CONE_MAX_ROWS + 1, lo, hi2, &v) ==
           EXDEX_EINVAL);
}

/* a generic cone for the QMC and grid checks: the paper's rows at
 * phi = 20 deg, theta = 75 deg plus a third contact-like row */
static const double GENERIC[9] = {0.34202014332566873, 0.93969262078590843, -0.32898992833716567,
                                  -0.8191520442889918, 0.57357643635104605, -0.090423977855495,
                                  0.2, 0.1, 0.6};

EXDEX_TEST(cone_qmc_matches_exact)
{
    // Independent method: randomised QMC with 10^7 points (16 shifts of
    // 625000 Sobol points) must agree with the exact volume within 5 standard
    // errors (t with 15 dof: P(|t| > 5) < 2e-4), and the error must be small.
    double lo[3], hi[3];
    eq13_box(lo, hi);
    exdex_volume_opts o = exdex_default_volume_opts();
    o.qmc_points = 625000;
    o.qmc_shifts = 16;
    o.seed = 7;
    double cases[2][9];
    for (int i = 0; i < 9; i++) cases[0][i] = GENERIC[i];
    double corner[9] = {0, 1, -0.5, -1, 0, 0.5, -1, 0, -0.5};
    for (int i = 0; i < 9; i++) cases[1][i] = corner[i];
    double vq[2], eq[2];
    ENSURE(exdex_cone_volumes(EXDEX_VOLUME_QMC, 2, 3, &cases[0][0], lo, hi, &o, vq, eq) ==
           EXDEX_OK);
    for (int c = 0; c < 2; c++) {
        double ve = vol(cases[c], 3, lo, hi);
        ENSURE(eq[c] > 0.0 && eq[c] < 2e-5);
        ENSURE(fabs(vq[c] - ve) <= 5.0 * eq[c]);
        report(c == 0 ? "tool_qmc_generic_err" : "tool_qmc_corner_err", eq[c]);
    }
}

EXDEX_TEST(cone_grid_converges)
{
    // Bound (independent of the code): box faces are cell faces, so only the
    // cone facets cut cells; a cell whose count differs from its share of P
    // has its centre within diag/2 of a facet plane, so these cells lie in a
    // slab of half-width diag around each plane, whose volume inside the box
    // is at most 2 diag S, S <= sqrt(A_xy^2 + A_yz^2 + A_zx^2) the largest
    // planar section of the box (hence the volume cut from the box by the
    // slab); each such cell errs by at most its volume:
    //   |grid - exact| <= m * 2 * S * diag   (diag: the cell diagonal).
    double lo[3], hi[3];
    eq13_box(lo, hi);
    double d[3] = {hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]};
    double S = sqrt(pow(d[0] * d[1], 2) + pow(d[1] * d[2], 2) + pow(d[2] * d[0], 2));
    double ve = vol(GENERIC, 3, lo, hi);
    exdex_volume_opts o = exdex_default_volume_opts();
    long ns[] = {8, 32, 128};
    double errs[3];
    for (int i = 0; i < 3; i++) {
        o.grid_n = ns[i];
        double vg;
        ENSURE(exdex_cone_volumes(EXDEX_VOLUME_GRID, 1, 3, GENERIC, lo, hi, &o, &vg, NULL) ==
               EXDEX_OK);
        double diag = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) / (double)ns[i];
        errs[i] = fabs(vg - ve);
        ENSURE(errs[i] <= 3 * 2 * S * diag);
    }
    ENSURE(errs[2] < errs[0]);
    // whole box: every centre counts, exactly
    o.grid_n = 5;
    double vw;
    ENSURE(exdex_cone_volumes(EXDEX_VOLUME_GRID, 1, 0, NULL, lo, hi, &o, &vw, NULL) == EXDEX_OK);
    ENSURE_CLOSE(vw, 1.0, 1e-14);
}

EXDEX_TEST(cone_volumes_vectorised)
{
    // the batch call gives the single-case values
    double lo[3], hi[3];
    eq13_box(lo, hi);
    double rows[2][9] = {{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0}};
    for (int i = 0; i < 9; i++) rows[1][i] = GENERIC[i];
    double v[2], e[2];
    ENSURE(exdex_cone_volumes(EXDEX_VOLUME_EXACT, 2, 3, &rows[0][0], lo, hi, NULL, v, e) ==
           EXDEX_OK);
    ENSURE_CLOSE(v[0], 0.125, 1e-12);
    ENSURE_CLOSE(v[1], vol(GENERIC, 3, lo, hi), 0.0);
    ENSURE(isnan(e[0]));
    exdex_volume_opts o = exdex_default_volume_opts();
    o.grid_n = 0;
    ENSURE(exdex_cone_volumes(EXDEX_VOLUME_GRID, 2, 3, &rows[0][0], lo, hi, &o, v, NULL) ==
           EXDEX_EINVAL);
    ENSURE(exdex_cone_volumes(7, 2, 3, &rows[0][0], lo, hi, NULL, v, NULL) == EXDEX_EINVAL);
}

static const double SQUARE[8] = {-0.5, -0.5, 0.5, -0.5, 0.5, 0.5, -0.5, 0.5};

static exdex_tool_problem square_problem(const double *phi, int n_phi, const int *nv)
{
    exdex_tool_problem p;
    p.model = EXDEX_TOOL_CONTACT;
    p.n_shapes = 1;
    p.n_vertices = nv;
    p.vertices = SQUARE;
    p.n_phi = n_phi;
    p.phi = phi;
    eq13_box(p.lo, p.hi);
    p.mu = 0.0;
    p.has_push = 0;
    p.push[0] = p.push[1] = p.push[2] = 0.0;
    return p;
}

EXDEX_TEST(cone_tool_rows_square_corner)
{
    // By hand: unit square, phi = 0, theta = 90 deg (floor + wall on its
    // right): floor edge -> (0,1,-1/2), (0,1,1/2); wall edge (n = (-1,0)) at
    // (1/2,-1/2), (1/2,1/2) -> (-1,0,-1/2), (-1,0,1/2).
    int nv = 4;
    double phi = 0.0;
    exdex_tool_problem p = square_problem(&phi, 1, &nv);
    exdex_tool_def t = {0.0, PI / 2, 0, 0.0};
    double rows[3 * EXDEX_CONE_MAX_ROWS];
    int m;
    ENSURE(exdex_tool_rows(&p, &t, 0, 0.0, rows, &m) == EXDEX_OK);
    ENSURE(m == 4);
    double expect[12] = {0, 1, -0.5, 0, 1, 0.5, -1, 0, -0.5, -1, 0, 0.5};
    for (int i = 0; i < 12 && m == 4; i++) ENSURE_CLOSE(rows[i], expect[i], 1e-15);
    double v;
    ENSURE(exdex_tool_objective(&p, &t, &v) == EXDEX_OK);
    ENSURE_CLOSE(v, 1.0 / (12.0 * R2), 1e-12);

    // By hand: phi = 30 deg: floor normal in the square's frame (1/2, sqrt3/2)
    // touches vertex (-1/2,-1/2): row (1/2, sqrt3/2, -(sqrt3 - 1)/4);
    // wall normal (-sin 60, cos 60) touches (1/2,-1/2): (-sqrt3/2, 1/2, (1 - sqrt3)/4)... r x n =
    // r_x n_y - r_y n_x = 1/4 - (sqrt3/4) = (1 - sqrt3)/4.
    double s3 = sqrt(3.0);
    ENSURE(exdex_tool_rows(&p, &t, 0, PI / 6, rows, &m) == EXDEX_OK);
    ENSURE(m == 2);
    double e2[6] = {0.5, s3 / 2, -(s3 - 1) / 4, -s3 / 2, 0.5, (1 - s3) / 4};
    for (int i = 0; i < 6 && m == 2; i++) ENSURE_CLOSE(rows[i], e2[i], 1e-15);
}

EXDEX_TEST(cone_tool_rows_plunger)
{
    // By hand: square wedged in the corner (floor y = 0, wall x = 0, object at
    // x <= 0): centre (-1/2, 1/2). Plunger at x = -0.25 touches the top edge at
    // (-0.25, 1): r = (0.25, 0.5), inward normal (0, -1): row (0, -1, -0.25).
    int nv = 4;
    double phi = 0.0;
    exdex_tool_problem p = square_problem(&phi, 1, &nv);
    exdex_tool_def t = {0.0, PI / 2, 1, -0.25};
    double rows[3 * EXDEX_CONE_MAX_ROWS];
    int m;
    ENSURE(exdex_tool_rows(&p, &t, 0, 0.0, rows, &m) == EXDEX_OK);
    ENSURE(m == 5);
    ENSURE_CLOSE(rows[12], 0.0, 1e-15);
    ENSURE_CLOSE(rows[13], -1.0, 1e-15);
    ENSURE_CLOSE(rows[14], -0.25, 1e-15);
    // clockwise vertex order: the same row
    double cw[8] = {-0.5, 0.5, 0.5, 0.5, 0.5, -0.5, -0.5, -0.5};
    p.vertices = cw;
    ENSURE(exdex_tool_rows(&p, &t, 0, 0.0, rows, &m) == EXDEX_OK);
    ENSURE(m == 5);
    ENSURE_CLOSE(rows[13], -1.0, 1e-15);
    ENSURE_CLOSE(rows[14], -0.25, 1e-15);
    // plunger beyond the object: no contact
    t.s = 0.5;
    ENSURE(exdex_tool_rows(&p, &t, 0, 0.0, rows, &m) == EXDEX_OK);
    ENSURE(m == 4);
}

EXDEX_TEST(cone_friction)
{
    // mu = 0: the friction rows are the frictionless row twice.
    double r[2] = {0.3, -0.5}, n[2] = {0.6, 0.8}, rows[6], row[3];
    ENSURE(exdex_contact_rows_friction(rows, r, n, 0.0) == EXDEX_OK);
    exdex_contact_row(row, r, n);
    for (int i = 0; i < 3; i++) {
        ENSURE_CLOSE(rows[i], row[i], 0.0);
        ENSURE_CLOSE(rows[3 + i], row[i], 0.0);
    }
    ENSURE(exdex_contact_rows_friction(rows, r, n, -0.1) == EXDEX_EINVAL);
    // Closed form (see cone_exact_wedges): contact at r = 0, n = (0,1), mu:
    // Vy >= mu |Vx|; a large mu pins the contact, the volume b^2/mu * 2c -> 0.
    double a = 0.4, b = 0.7, c = 1.3;
    double lo[3] = {-a, -b, -c}, hi[3] = {a, b, c};
    double r0[2] = {0, 0}, n0[2] = {0, 1};
    double mus[] = {0.0, 0.3, 5.0, 1e6};
    for (int i = 0; i < 4; i++) {
        double mu = mus[i];
        ENSURE(exdex_contact_rows_friction(rows, r0, n0, mu) == EXDEX_OK);
        double area = mu * a <= b ? 2 * a * b - mu * a * a : b * b / mu;
        ENSURE_CLOSE(vol(rows, 2, lo, hi), area * 2 * c, 1e-12);
    }
    // The tool problem with mu = 0 gives the frictionless volume.
    int nv = 4;
    double phis[3] = {0.1, 0.4, 0.7};
    exdex_tool_problem p = square_problem(phis, 3, &nv);
    exdex_tool_def t = {0.0, 1.4, 0, 0.0};
    double v0, vf, vbig;
    ENSURE(exdex_tool_objective(&p, &t, &v0) == EXDEX_OK);
    p.mu = 1e-300;  // friction rows path, numerically mu = 0
    ENSURE(exdex_tool_objective(&p, &t, &vf) == EXDEX_OK);
    ENSURE_CLOSE(vf, v0, 1e-14);
    p.mu = 1e8;
    ENSURE(exdex_tool_objective(&p, &t, &vbig) == EXDEX_OK);
    ENSURE(vbig < 1e-6 && vbig >= 0.0);
}

EXDEX_TEST(cone_push)
{
    // By hand: square in the square corner (rows as in
    // cone_tool_rows_square_corner). A push into the corner (1, -1, 0) is
    // balanced by the contact forces, -P = 1/2 (sum of the four rows' wrenches),
    // so every permitted twist has P . x <= 0: with P . x >= 0 only a null set.
    int nv = 4;
    double phi = 0.0;
    exdex_tool_problem p = square_problem(&phi, 1, &nv);
    p.has_push = 1;
    p.push[0] = 1; p.push[1] = -1; p.push[2] = 0;
    exdex_tool_def t = {0.0, PI / 2, 0, 0.0};
    double v;
    ENSURE(exdex_tool_objective(&p, &t, &v) == EXDEX_OK);
    ENSURE_CLOSE(v, 0.0, 1e-12);
    // A push away from the wall (-1, -1, 0) is not resisted: a positive volume.
    p.push[0] = -1;
    ENSURE(exdex_tool_objective(&p, &t, &v) == EXDEX_OK);
    ENSURE(v > 1e-3);
}

EXDEX_TEST(cone_optimise_theta_matches_dense_scan)
{
    // Independent method: a dense brute-force scan of the objective over
    // theta (4001 values); Brent's minimum must not be worse than the dense
    // scan's and must lie within one dense step of it.
    int nv = 4;
    double phis[4];
    for (int i = 0; i < 4; i++) phis[i] = (5.0 + 10.0 * i) * PI / 180;
    exdex_tool_problem p = square_problem(phis, 4, &nv);
    p.model = EXDEX_TOOL_PAPER;
    exdex_tool_def t = {0.0, 0.0, 0, 0.0};
    double lo = 10 * PI / 180, hi = 170 * PI / 180;
    exdex_tool_opt_result res;
    double scan[33];
    ENSURE(exdex_tool_optimise_theta(&p, &t, lo, hi, 33, 1e-10, scan, &res) == EXDEX_OK);
    int nd = 4001, best = 0;
    double fbest = INFINITY, step = (hi - lo) / (nd - 1);
    for (int i = 0; i < nd; i++) {
        exdex_tool_def u = t;
        u.alpha2 = lo + i * step;
        double f;
        ENSURE(exdex_tool_objective(&p, &u, &f) == EXDEX_OK);
        if (f < fbest) { fbest = f; best = i; }
    }
    ENSURE(res.f <= fbest + 1e-12);
    if (res.bracketed) ENSURE(fabs(res.x[1] - (lo + best * step)) <= step);
    for (int i = 0; i < 33; i++) ENSURE(res.f <= scan[i] + 1e-15);
    // the same 1-D problem through nmsimplex2 with only alpha2 free. The
    // objective is flat to rounding within ~sqrt(eps) |theta| ~ 4e-8 of its
    // minimum (quadratic there), and nmsimplex2 accepts a reflection of equal
    // value, so on that plateau the simplex need not shrink: the size
    // tolerance must lie above the plateau (1e-7), the accuracy check below
    // is on f.
    int fr[3] = {0, 1, 0};
    double st[3] = {0.1, 0.1, 0.1};
    exdex_tool_def start = {0.0, res.x[1] + 0.05, 0, 0.0};
    exdex_tool_opt_result r2;
    ENSURE(exdex_tool_optimise(&p, &start, fr, st, 500, 1e-7, &r2) == EXDEX_OK);
    ENSURE(r2.f <= fbest + 1e-9);
    ENSURE(exdex_tool_optimise_theta(&p, &t, hi, lo, 33, 1e-10, NULL, &res) == EXDEX_EINVAL);
}

EXDEX_TEST(cone_tool_problem_check)
{
    int nv = 2;
    double phi = 0.0;
    exdex_tool_problem p = square_problem(&phi, 1, &nv);
    const char *bad = NULL;
    ENSURE(exdex_tool_problem_check(&p, &bad) == EXDEX_EINVAL);
    ENSURE(bad && bad[0] == 's');
    nv = 4;
    p.mu = -1;
    ENSURE(exdex_tool_problem_check(&p, &bad) == EXDEX_EINVAL);
    ENSURE(bad && bad[0] == 'm');
    p.mu = 0;
    ENSURE(exdex_tool_problem_check(&p, &bad) == EXDEX_OK);
    ENSURE(bad == NULL);
}

/* ---------------------------------------------- thin boxes far from the apex
 * (the volume must keep its relative accuracy, stated in exdex.h as
 * 16 (1 + m) eps times the box volume, whatever the box's size, aspect ratio
 * or distance from the origin). */

static const double EPS = 2.220446049250313e-16;

EXDEX_TEST(cone_exact_far_box_symmetric_closed_forms)
{
    // Closed forms by symmetry: the rows (1,-1,0), (0,1,-1) vanish along
    // (1,1,1), so on a cube [L, L+w]^3 the cone x >= y >= z is one of the 6
    // congruent orderings of the coordinates: 1/6 of the cube; x >= y alone
    // is half of it (reflection x <-> y). The apex is 10^12 cube sizes away.
    double L = 1e9, w = 1e-3;
    double lo[3] = {L, L, L}, hi[3] = {L + w, L + w, L + w};
    double bv = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    double rows[6] = {1, -1, 0, 0, 1, -1};
    ENSURE_CLOSE(vol(rows, 1, lo, hi) / bv, 0.5, 32 * EPS);
    ENSURE_CLOSE(vol(rows, 2, lo, hi) / bv, 1.0 / 6.0, 48 * EPS);
    // the same on the far negative side, and a thin box (aspect 1e-12 in z)
    // for x >= y: the z extent does not matter
    double lo2[3] = {-L - w, -L - w, 3.0}, hi2[3] = {-L, -L, 3.0 + 1e-12};
    double bv2 = (hi2[0] - lo2[0]) * (hi2[1] - lo2[1]) * (hi2[2] - lo2[2]);
    ENSURE_CLOSE(vol(rows, 1, lo2, hi2) / bv2, 0.5, 32 * EPS);
}

EXDEX_TEST(cone_exact_far_thin_box_tetrahedron_closed_form)
{
    // Closed form: box [L, L+w]^2 x [1, 1+d] with L = 2^30, w = 2^-10,
    // d = 2^-41 (aspect d/w = 2^-31, apex 2^40 box widths away) and the row
    // (1, 1, -(2L + w)): with u = (x - L) + (y - L), the section at z is
    // {u >= g(z)}, g = w + (2L + w)(z - 1), of area (2w - g)^2 / 2 for
    // w <= g <= 2w and 0 beyond (g(1 + d) > 2w). Integrating over z:
    //   V = w^3 / (6 (2L + w)),  the box volume being w^2 d.
    double L = 0x1p30, w = 0x1p-10, d = 0x1p-41;
    double lo[3] = {L, L, 1.0}, hi[3] = {L + w, L + w, 1.0 + d};
    double row[3] = {1, 1, -(2 * L + w)};
    double ref_v = w * w * w / (6 * (2 * L + w)), bv = w * w * d;
    ENSURE_CLOSE(vol(row, 1, lo, hi) / bv, ref_v / bv, 32 * EPS);
    // the complement fills the box
    double neg[3] = {-1, -1, 2 * L + w};
    ENSURE_CLOSE((vol(row, 1, lo, hi) + vol(neg, 1, lo, hi)) / bv, 1.0, 32 * EPS);
}

EXDEX_TEST(cone_exact_thin_box_prism_closed_form)
{
    // Closed form: x in [1/2, 1/2 + w], w = 2^-40 (aspect 2^-40 against the
    // other sides), y in [-1/2, 1/2], z in [2, 3]; the row (-1, 2, 0) keeps
    // y >= x / 2: V = 1 * int (1/2 - x/2) dx = w (1/4 - w/4).
    double w = 0x1p-40;
    double lo[3] = {0.5, -0.5, 2.0}, hi[3] = {0.5 + w, 0.5, 3.0};
    double row[3] = {-1, 2, 0};
    ENSURE_CLOSE(vol(row, 1, lo, hi) / w, 0.25 - w / 4, 32 * EPS);
    // Closed form: a 1e-12-thin slab across the apex: z in [0, 1e-12] and the
    // rows Vx >= 0, Vy >= 0 keep a quarter whatever the thickness
    double lo2[3] = {-1, -1, 0}, hi2[3] = {1, 1, 1e-12}, q[6] = {1, 0, 0, 0, 1, 0};
    ENSURE_CLOSE(vol(q, 2, lo2, hi2) / (4e-12), 0.25, 48 * EPS);
}

EXDEX_TEST(cone_exact_shift_along_null_direction)
{
    // Independent comparison: rows whose common null direction is n = (1,1,1)
    // (rows . n = 0) describe the same set after any shift of the box along n;
    // the box around the apex (terms O(1), well conditioned) is the reference
    // for the same box shifted far away along n. Dyadic boxes and shifts keep
    // every shifted coordinate exact (checked), so the boxes are congruent.
    double rows[9] = {1, -1, 0, -0.25, -0.75, 1, 0.5, 0.25, -0.75};  // dyadic: rows . n = 0 exactly
    struct { double w[3], lo[3], t[3]; } cases[2] = {
        // 2^45 is 10^13 box sizes away
        {{0.75, 1.25, 0.875}, {-0.125, -1.0, -0.5}, {0x1p20, -0x1p31, 0x1p45}},
        // thin: z width 0.875 * 2^-40 (aspect ~1e-12); 2^9 is 5e14 z widths
        {{0.75, 1.25, 0.875 * 0x1p-40}, {-0.125, -1.0, -0.25 * 0x1p-40}, {0x1p9, -0x1p5, 0x1p7}},
    };
    for (int c = 0; c < 2; c++) {
        double lo0[3], hi0[3];
        for (int j = 0; j < 3; j++) { lo0[j] = cases[c].lo[j]; hi0[j] = lo0[j] + cases[c].w[j]; }
        double bv = cases[c].w[0] * cases[c].w[1] * cases[c].w[2];
        double v0 = vol(rows, 3, lo0, hi0);
        ENSURE(v0 > 0.05 * bv && v0 < 0.95 * bv);
        for (int i = 0; i < 3; i++) {
            double t = cases[c].t[i], lo[3], hi[3];
            for (int j = 0; j < 3; j++) {
                lo[j] = lo0[j] + t;
                hi[j] = hi0[j] + t;
                ENSURE(lo[j] - t == lo0[j] && hi[j] - t == hi0[j]);  // exact shift
            }
            ENSURE_CLOSE(vol(rows, 3, lo, hi) / bv, v0 / bv, 2 * 16 * 4 * EPS);
        }
    }
}

EXDEX_TEST(cone_grid_far_box_closed_form)
{
    // Closed form: on the grid of n^3 cells of [L, L+w]^3 the centres with
    // x >= y are those with i >= k (i, k their indices): n (n + 1) / 2 of
    // the n^2 (x, y) pairs, so the grid volume is (n + 1) / (2 n) of the box
    // for any L (the centres on the diagonal count as inside).
    double L = 1e9, w = 1e-3;
    double lo[3] = {L, L, L}, hi[3] = {L + w, L + w, L + w};
    double bv = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    double row[3] = {1, -1, 0}, v;
    exdex_volume_opts o = exdex_default_volume_opts();
    o.grid_n = 9;
    ENSURE(exdex_cone_volumes(EXDEX_VOLUME_GRID, 1, 1, row, lo, hi, &o, &v, NULL) == EXDEX_OK);
    ENSURE_CLOSE(v / bv, 10.0 / 18.0, 4 * EPS);
}

EXDEX_TEST(cone_rows_overflow_status)
{
    // a contact point near DBL_MAX makes r x n overflow: a status, not inf
    double r[2] = {1.7e308, -1.7e308}, n[2] = {0.6, 0.8}, rows[6];
    ENSURE(exdex_contact_rows_friction(rows, r, n, 0.5) == EXDEX_ENONFINITE);
    // a push near DBL_MAX overflows when rotated into the object frame
    int nv = 4;
    double phi = 0.7;
    exdex_tool_problem p = square_problem(&phi, 1, &nv);
    p.has_push = 1;
    p.push[0] = 1.7e308; p.push[1] = 1.7e308; p.push[2] = 0;
    exdex_tool_def t = {0.0, PI / 2, 0, 0.0};
    double tr[3 * EXDEX_CONE_MAX_ROWS];
    int m;
    // R(-phi) push at phi = -pi/4: x' = (push_x - push_y) / sqrt2 = 0,
    // y' = (push_x + push_y) / sqrt2 = 2.4e308: inf
    ENSURE(exdex_tool_rows(&p, &t, 0, -PI / 4, tr, &m) == EXDEX_ENONFINITE);
    double f;
    p.phi = &phi;
    phi = -PI / 4;
    ENSURE(exdex_tool_objective(&p, &t, &f) == EXDEX_ENONFINITE);
}

EXDEX_TEST(cone_exact_far_small_box_rounded_rows_exact_rational)
{
    /* Fuzzing (fuzz_cone.c, scaling check) found v(3 a) != v(a) beyond the
     * stated accuracy for this small box (w = 1e-3) about 5 from the apex
     * with two nearly parallel rows. Not a defect of the method: 3 a_j
     * rounds, and the exact volumes of the two sets of doubles differ by
     * 1.8e-13 box volumes. References: exact rational arithmetic (Python
     * fractions: vertex enumeration of the clipped box and the divergence
     * theorem) on the very doubles below and on fl(3 a_j), each rounded once
     * to double. Both volumes are checked to 16 (1 + m) eps box. */
    const double rows[15] = {
        -0x1.d4fc9ffe14386p+0, 0x1.2eb467116df6ep+0, 0x1.4cacc45ad36ep-1,
        -0x1.39cd179f1b31ep+0, 0x1.ab5b6435bebep-4, 0x1.7a14cce53bf9p-3,
        0x1.eab842f9d4d4p+0, -0x1.377c04bb0a8bap+0, -0x1.0ac0a9eaaa426p+0,
        0x1.de33739e82d32p-5, -0x1.ff207e2b9cbb6p-1, -0x1.e21cc8c617d2dp-2,
        0x1.de33739e82d32p-5, -0x1.ff207e2b9cbb6p-1, -0x1.0ef19b9cf416ap-1};
    const double lo[3] = {-3.0, -3.0, -3.0};
    const double hi[3] = {-0x1.7fdf3b645a1cbp+1, -0x1.7fdf3b645a1cbp+1, -0x1.7fdf3b645a1cbp+1};
    const double V1 = 1.7846567860402642e-10, V3 = 1.7846567860385033e-10;
    double r3[15], v = -1.0, bv = 1.0;
    for (int j = 0; j < 3; j++) bv *= hi[j] - lo[j];
    for (int i = 0; i < 15; i++) r3[i] = 3.0 * rows[i];
    ENSURE(exdex_cone_volume_exact(rows, 5, lo, hi, &v) == EXDEX_OK);
    ENSURE(fabs(v - V1) <= 16.0 * 6 * DBL_EPSILON * bv);
    ENSURE(exdex_cone_volume_exact(r3, 5, lo, hi, &v) == EXDEX_OK);
    ENSURE(fabs(v - V3) <= 16.0 * 6 * DBL_EPSILON * bv);
    /* the premise: the rounding of 3 a alone moves the exact volume by more
     * than the method's accuracy */
    ENSURE(fabs(V1 - V3) > 2 * 16.0 * 6 * DBL_EPSILON * bv);
}

EXDEX_TEST(cone_optimise_theta_angle_bound)
{
    // alpha2 = alpha1 + theta resolves theta to eps (|alpha1| + |theta|)
    // only: angles beyond EXDEX_TOOL_ANGLE_MAX are rejected (fuzzing found
    // alpha1 ~ 1e128 returning theta = alpha2 - alpha1 = 0 outside the
    // range). At the bound, the returned theta is the one evaluated to
    // eps/2 * 2e6 = 2.3e-10 rad, so it lies in [lo, hi] to that.
    int nv = 4;
    double phis[2] = {5.0 * PI / 180, 25.0 * PI / 180};
    exdex_tool_problem p = square_problem(phis, 2, &nv);
    p.model = EXDEX_TOOL_PAPER;
    double lo = 10 * PI / 180, hi = 170 * PI / 180;
    exdex_tool_opt_result res;
    static const double bad_a1[4] = {1e16, -8.3e128, 1.0000000001e6, -DBL_MAX};
    for (int i = 0; i < 4; i++) {
        exdex_tool_def t = {bad_a1[i], 0.0, 0, 0.0};
        ENSURE(exdex_tool_optimise_theta(&p, &t, lo, hi, 9, 1e-8, NULL, &res) == EXDEX_EINVAL);
    }
    {
        exdex_tool_def t = {0.0, 0.0, 0, 0.0};
        ENSURE(exdex_tool_optimise_theta(&p, &t, lo, 2e6, 9, 1e-8, NULL, &res) == EXDEX_EINVAL);
        ENSURE(exdex_tool_optimise_theta(&p, &t, -2e6, hi, 9, 1e-8, NULL, &res) == EXDEX_EINVAL);
    }
    for (int sg = -1; sg <= 1; sg += 2) {
        exdex_tool_def t = {sg * EXDEX_TOOL_ANGLE_MAX, 0.0, 0, 0.0};
        ENSURE(exdex_tool_optimise_theta(&p, &t, lo, hi, 9, 1e-8, NULL, &res) == EXDEX_OK);
        double th = res.x[1] - res.x[0];
        ENSURE(res.x[0] == t.alpha1);
        ENSURE(th >= lo - 2.4e-10 && th <= hi + 2.4e-10);
    }
}
