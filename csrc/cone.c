/* cone.c -- twist cones of a pushed planar object, their volumes inside a
 * box, and the assistive-tool optimisation (paper Section 3, Eqs. 10-13).
 *
 * The feasible twist set of a rigid planar object touching fixed surfaces
 * without friction is the polyhedral cone {x : A x >= 0}; the paper measures
 * it by its volume inside a cuboid of twists (Eq. 13) and picks the tool
 * angle minimising the volume summed over attack angles (Eq. 12).
 */
#include "exdex.h"
#include "util.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_min.h>
#include <gsl/gsl_multimin.h>
#include <gsl/gsl_qrng.h>
#include <gsl/gsl_rng.h>
#include <gsl/gsl_vector.h>
#include <math.h>
#include <stdlib.h>

/* ------------------------------------------------------------------ rows */

void exdex_contact_row(double row[3], const double r[2], const double n[2])
{
    // velocity of the material point r: v + w x r = (Vx - wz r_y, Vy + wz r_x);
    // n . that = n_x Vx + n_y Vy + (r_x n_y - r_y n_x) wz
    row[0] = n[0];
    row[1] = n[1];
    row[2] = r[0] * n[1] - r[1] * n[0];
}

int exdex_contact_rows_friction(double rows[6], const double r[2], const double n[2],
                                double mu)
{
    if (!(mu >= 0.0) || !isfinite(mu) || !isfinite(r[0]) || !isfinite(r[1]) ||
        !isfinite(n[0]) || !isfinite(n[1]))
        return EXDEX_EINVAL;
    // Friction cone edges (paper Fig. 10), normalised so a large mu keeps
    // the rows of order one.
    double t[2] = {-n[1], n[0]};
    double c = 1.0 / sqrt(1.0 + mu * mu);
    for (int k = 0; k < 2; k++) {
        double sg = k == 0 ? 1.0 : -1.0;
        double e[2] = {c * (n[0] + sg * mu * t[0]), c * (n[1] + sg * mu * t[1])};
        exdex_contact_row(rows + 3 * k, r, e);
    }
    return EXDEX_OK;
}

void exdex_cone_rows_paper(double rows[6], double phi, double theta)
{
    // Eq. 10: Vx sin(phi) + Vy cos(phi) - 1/2 (1 - sin(phi)) wz >= 0
    rows[0] = sin(phi);
    rows[1] = cos(phi);
    rows[2] = -0.5 * (1.0 - sin(phi));
    // Eq. 11: -Vx sin(theta - phi) + Vy cos(theta - phi) - 1/2 (1 - sin(theta - phi)) wz >= 0
    double p = theta - phi;
    rows[3] = -sin(p);
    rows[4] = cos(p);
    rows[5] = -0.5 * (1.0 - sin(p));
}

/* --------------------------------------------------------- exact volume */

static int box_ok(const double lo[3], const double hi[3])
{
    double vol = 1.0;
    for (int j = 0; j < 3; j++) {
        if (!isfinite(lo[j]) || !isfinite(hi[j]) || !(hi[j] > lo[j]) || !isfinite(hi[j] - lo[j])) return 0;
        vol *= hi[j] - lo[j];
    }
    return isfinite(vol) && vol > 0.0; /* the box volume must be representable (fuzzing) */
}

static int rows_ok(const double *rows, int m)
{
    if (m < 0 || m > EXDEX_CONE_MAX_ROWS) return 0;
    if (m > 0 && !rows) return 0;
    return ex_finite_n(rows, 3 * m);
}

/* Area of the rectangle [u0,u1] x [v0,v1] (coordinates iu, iv of x, with the
 * coordinate j fixed at c) clipped by every half-plane rows x >= 0. */
static double face_area(const double *rows, int m, int j, double c, double u0, double u1,
                        double v0, double v1)
{
    enum { CAP = EXDEX_CONE_MAX_ROWS + 8 };
    double pa[CAP][2], pb[CAP][2];
    double (*in)[2] = pa, (*out)[2] = pb;
    int iu = (j + 1) % 3, iv = (j + 2) % 3;
    int n = 4;
    in[0][0] = u0; in[0][1] = v0;
    in[1][0] = u1; in[1][1] = v0;
    in[2][0] = u1; in[2][1] = v1;
    in[3][0] = u0; in[3][1] = v1;
    for (int k = 0; k < m && n > 0; k++) {
        const double *a = rows + 3 * k;
        double au = a[iu], av = a[iv], a0 = a[j] * c;
        if (au == 0.0 && av == 0.0) {
            if (a0 < 0.0) return 0.0;  // the whole face is cut away
            continue;                  // a0 >= 0: no constraint on this face
        }
        // Sutherland-Hodgman against au u + av v + a0 >= 0
        int no = 0;
        for (int i = 0; i < n; i++) {
            const double *p = in[i], *q = in[(i + 1) % n];
            double dp = au * p[0] + av * p[1] + a0;
            double dq = au * q[0] + av * q[1] + a0;
            if (dp >= 0.0) {
                out[no][0] = p[0]; out[no][1] = p[1]; no++;
                if (dq < 0.0) {
                    double t = dp / (dp - dq);
                    out[no][0] = p[0] + t * (q[0] - p[0]);
                    out[no][1] = p[1] + t * (q[1] - p[1]);
                    no++;
                }
            } else if (dq >= 0.0) {
                double t = dp / (dp - dq);
                out[no][0] = p[0] + t * (q[0] - p[0]);
                out[no][1] = p[1] + t * (q[1] - p[1]);
                no++;
            }
        }
        double (*tmp)[2] = in; in = out; out = tmp;
        n = no;
    }
    if (n < 3) return 0.0;
    // Shoelace about the first vertex (less cancellation than about 0);
    // clipping keeps the rectangle's counter-clockwise order, so the sign
    // is known, but only the magnitude is used: the face's orientation
    // (outward normal) comes from the bound, not from the winding.
    double s = 0.0;
    for (int i = 1; i + 1 < n; i++)
        s += (in[i][0] - in[0][0]) * (in[i + 1][1] - in[0][1]) -
             (in[i + 1][0] - in[0][0]) * (in[i][1] - in[0][1]);
    return 0.5 * fabs(s);
}

int exdex_cone_volume_exact(const double *rows, int m, const double lo[3],
                            const double hi[3], double *volume)
{
    if (!volume || !box_ok(lo, hi) || !rows_ok(rows, m)) return EXDEX_EINVAL;
    // Divergence theorem with F(x) = x / 3 (div F = 1) over P = box cap cone:
    // on a cone facet a . x = 0, so x . n = 0 and the facet adds nothing;
    // on the face x_j = hi_j the outward normal is +e_j (x . n = hi_j), on
    // x_j = lo_j it is -e_j (x . n = -lo_j). (DESIGN.md section 4.)
    double v = 0.0;
    for (int j = 0; j < 3; j++) {
        int iu = (j + 1) % 3, iv = (j + 2) % 3;
        if (hi[j] != 0.0)
            v += hi[j] * face_area(rows, m, j, hi[j], lo[iu], hi[iu], lo[iv], hi[iv]);
        if (lo[j] != 0.0)
            v -= lo[j] * face_area(rows, m, j, lo[j], lo[iu], hi[iu], lo[iv], hi[iv]);
    }
    *volume = v / 3.0;
    return EXDEX_OK;
}

/* ------------------------------------------------------------------ grid */

static double volume_grid(const double *rows, int m, const double lo[3], const double hi[3],
                          long n)
{
    // Paper Section 3.1: discretise the cuboid, count the cells whose centre
    // satisfies every row. Partial sums per axis keep the inner loop at m
    // multiply-adds per cell.
    double h[3];
    for (int j = 0; j < 3; j++) h[j] = (hi[j] - lo[j]) / (double)n;
    double part[EXDEX_CONE_MAX_ROWS];
    long count = 0;
    for (long i = 0; i < n; i++) {
        double x = lo[0] + (i + 0.5) * h[0];
        for (long k = 0; k < n; k++) {
            double y = lo[1] + (k + 0.5) * h[1];
            for (int r = 0; r < m; r++) part[r] = rows[3 * r] * x + rows[3 * r + 1] * y;
            for (long l = 0; l < n; l++) {
                double z = lo[2] + (l + 0.5) * h[2];
                int in = 1;
                for (int r = 0; r < m; r++)
                    if (part[r] + rows[3 * r + 2] * z < 0.0) { in = 0; break; }
                count += in;
            }
        }
    }
    double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    return box * (double)count / ((double)n * (double)n * (double)n);
}

/* ------------------------------------------------------------------- QMC */

typedef struct qmc_ws {
    gsl_qrng *q;
    gsl_rng *rng;
    double *shift;   /* (shifts, 3) */
    long *count;     /* (shifts,) */
} qmc_ws;

static void qmc_free(qmc_ws *w)
{
    if (w->q) gsl_qrng_free(w->q);
    if (w->rng) gsl_rng_free(w->rng);
    free(w->shift);
    free(w->count);
    w->q = NULL; w->rng = NULL; w->shift = NULL; w->count = NULL;
}

static int qmc_alloc(qmc_ws *w, int shifts)
{
    w->q = gsl_qrng_alloc(gsl_qrng_sobol, 3);
    w->rng = gsl_rng_alloc(gsl_rng_mt19937);
    w->shift = malloc(sizeof(double) * 3 * (size_t)shifts);
    w->count = malloc(sizeof(long) * (size_t)shifts);
    if (!w->q || !w->rng || !w->shift || !w->count) {
        qmc_free(w);
        return EXDEX_ENOMEM;
    }
    return EXDEX_OK;
}

static int volume_qmc(qmc_ws *w, const double *rows, int m, const double lo[3],
                      const double hi[3], const exdex_volume_opts *o, double *vol,
                      double *err)
{
    int K = o->qmc_shifts;
    double h[3];
    for (int j = 0; j < 3; j++) h[j] = hi[j] - lo[j];
    gsl_qrng_init(w->q);
    gsl_rng_set(w->rng, o->seed);
    // Cranley-Patterson rotations: the same Sobol points shifted mod 1 by K
    // independent uniform vectors give K unbiased, independent estimates.
    for (int k = 0; k < K; k++) {
        for (int j = 0; j < 3; j++)
            w->shift[3 * k + j] = K > 1 ? gsl_rng_uniform(w->rng) : 0.0;
        w->count[k] = 0;
    }
    double u[3];
    for (long i = 0; i < o->qmc_points; i++) {
        if (gsl_qrng_get(w->q, u) != GSL_SUCCESS) return EXDEX_EINVAL;
        for (int k = 0; k < K; k++) {
            double x[3];
            for (int j = 0; j < 3; j++) {
                double t = u[j] + w->shift[3 * k + j];
                if (t >= 1.0) t -= 1.0;
                x[j] = lo[j] + t * h[j];
            }
            int in = 1;
            for (int r = 0; r < m; r++) {
                const double *a = rows + 3 * r;
                if (a[0] * x[0] + a[1] * x[1] + a[2] * x[2] < 0.0) { in = 0; break; }
            }
            w->count[k] += in;
        }
    }
    double box = h[0] * h[1] * h[2];
    double mean = 0.0;
    for (int k = 0; k < K; k++) mean += (double)w->count[k];
    mean /= (double)K;
    double var = 0.0;
    for (int k = 0; k < K; k++) {
        double d = (double)w->count[k] - mean;
        var += d * d;
    }
    double scale = box / (double)o->qmc_points;
    *vol = mean * scale;
    *err = K > 1 ? sqrt(var / (double)(K - 1) / (double)K) * scale : NAN;
    return EXDEX_OK;
}

/* ------------------------------------------------------------ vectorised */

exdex_volume_opts exdex_default_volume_opts(void)
{
    exdex_volume_opts o;
    o.grid_n = 64;
    o.qmc_points = 1L << 16;
    o.qmc_shifts = 16;
    o.seed = 1;
    return o;
}

int exdex_cone_volumes(int method, size_t n_cases, int m, const double *rows,
                       const double lo[3], const double hi[3],
                       const exdex_volume_opts *opts, double *volume, double *err)
{
    exdex_volume_opts o = opts ? *opts : exdex_default_volume_opts();
    if (!volume || !box_ok(lo, hi) || m < 0 || m > EXDEX_CONE_MAX_ROWS ||
        (n_cases > 0 && m > 0 && !rows))
        return EXDEX_EINVAL;
    if (method == EXDEX_VOLUME_GRID && !(o.grid_n >= 1 && o.grid_n <= 100000))
        return EXDEX_EINVAL;
    if (method == EXDEX_VOLUME_QMC &&
        !(o.qmc_points >= 1 && o.qmc_points <= (1L << 30) && o.qmc_shifts >= 1 &&
          o.qmc_shifts <= 4096))
        return EXDEX_EINVAL;
    if (method < EXDEX_VOLUME_EXACT || method > EXDEX_VOLUME_QMC) return EXDEX_EINVAL;
    for (size_t c = 0; c < n_cases; c++)
        if (!rows_ok(rows + 3 * (size_t)m * c, m)) return EXDEX_EINVAL;

    qmc_ws w = {NULL, NULL, NULL, NULL};
    if (method == EXDEX_VOLUME_QMC) {
        int st = qmc_alloc(&w, o.qmc_shifts);
        if (st) return st;
    }
    int status = EXDEX_OK;
    for (size_t c = 0; c < n_cases && status == EXDEX_OK; c++) {
        const double *a = rows + 3 * (size_t)m * c;
        double e = NAN;
        switch (method) {
        case EXDEX_VOLUME_EXACT:
            status = exdex_cone_volume_exact(a, m, lo, hi, &volume[c]);
            break;
        case EXDEX_VOLUME_GRID:
            volume[c] = volume_grid(a, m, lo, hi, o.grid_n);
            break;
        default:
            status = volume_qmc(&w, a, m, lo, hi, &o, &volume[c], &e);
            break;
        }
        if (err) err[c] = e;
    }
    qmc_free(&w);
    return status;
}

/* ------------------------------------------------------------ tool rows */

int exdex_tool_problem_check(const exdex_tool_problem *p, const char **bad_param)
{
    const char *bad = NULL;
    if (!p) bad = "problem";
    else if (p->model != EXDEX_TOOL_CONTACT && p->model != EXDEX_TOOL_PAPER) bad = "model";
    else if (p->n_phi < 1 || !p->phi || !ex_finite_n(p->phi, p->n_phi)) bad = "phi";
    else if (!box_ok(p->lo, p->hi)) bad = "box";
    else if (!(p->mu >= 0.0) || !isfinite(p->mu)) bad = "mu";
    else if (p->has_push && !ex_finite_n(p->push, 3)) bad = "push";
    else if (p->model == EXDEX_TOOL_CONTACT) {
        if (p->n_shapes < 1 || !p->n_vertices || !p->vertices) bad = "shapes";
        else {
            size_t off = 0;
            for (int s = 0; s < p->n_shapes && !bad; s++) {
                int nv = p->n_vertices[s];
                if (nv < 3 || nv > EXDEX_MAX_VERTICES) { bad = "shapes"; break; }
                const double *v = p->vertices + 2 * off;
                if (!ex_finite_n(v, 2 * nv)) bad = "shapes";
                double area = 0.0;
                for (int i = 0; i < nv; i++) {
                    int k = (i + 1) % nv;
                    area += v[2 * i] * v[2 * k + 1] - v[2 * k] * v[2 * i + 1];
                }
                if (!(fabs(area) > 0.0)) bad = "shapes";
                off += (size_t)nv;
            }
        }
    }
    if (bad_param) *bad_param = bad;
    return bad ? EXDEX_EINVAL : EXDEX_OK;
}

static const double *shape_vertices(const exdex_tool_problem *p, int shape, int *nv)
{
    size_t off = 0;
    for (int s = 0; s < shape; s++) off += (size_t)p->n_vertices[s];
    *nv = p->n_vertices[shape];
    return p->vertices + 2 * off;
}

/* Append the row(s) of one contact (object frame), with friction if mu > 0. */
static int add_contact(double *rows, int *nrows, const double r[2], const double n[2],
                       double mu)
{
    int need = mu > 0.0 ? 2 : 1;
    if (*nrows + need > EXDEX_CONE_MAX_ROWS) return EXDEX_EINVAL;
    if (mu > 0.0) {
        int st = exdex_contact_rows_friction(rows + 3 * *nrows, r, n, mu);
        if (st) return st;
    } else {
        exdex_contact_row(rows + 3 * *nrows, r, n);
    }
    *nrows += need;
    return EXDEX_OK;
}

int exdex_tool_rows(const exdex_tool_problem *p, const exdex_tool_def *tool, int shape,
                    double phi, double *rows, int *nrows)
{
    if (!p || !tool || !rows || !nrows || !isfinite(phi) || !isfinite(tool->alpha1) ||
        !isfinite(tool->alpha2) || (tool->plunger && !isfinite(tool->s)))
        return EXDEX_EINVAL;
    *nrows = 0;
    double cp = cos(phi), sp = sin(phi);
    if (p->model == EXDEX_TOOL_PAPER) {
        exdex_cone_rows_paper(rows, phi - tool->alpha1, tool->alpha2 - tool->alpha1);
        *nrows = 2;
    } else {
        if (shape < 0 || shape >= p->n_shapes) return EXDEX_EINVAL;
        int nv;
        const double *v = shape_vertices(p, shape, &nv);
        double radius = 0.0;
        for (int i = 0; i < nv; i++)
            radius = fmax(radius, hypot(v[2 * i], v[2 * i + 1]));
        double tol = 1e-9 * radius;
        double alpha[2] = {tool->alpha1, tool->alpha2};
        double nw[2][2], h[2];  // world normals, support offsets
        for (int s = 0; s < 2; s++) {
            nw[s][0] = -sin(alpha[s]);
            nw[s][1] = cos(alpha[s]);
            // the surface normal in the object frame: R(-phi) n
            double n[2] = {cp * nw[s][0] + sp * nw[s][1], -sp * nw[s][0] + cp * nw[s][1]};
            double dmin = INFINITY;
            for (int i = 0; i < nv; i++)
                dmin = fmin(dmin, n[0] * v[2 * i] + n[1] * v[2 * i + 1]);
            h[s] = -dmin;
            for (int i = 0; i < nv; i++) {
                if (n[0] * v[2 * i] + n[1] * v[2 * i + 1] <= dmin + tol) {
                    int st = add_contact(rows, nrows, v + 2 * i, n, p->mu);
                    if (st) return st;
                }
            }
        }
        double det = nw[0][0] * nw[1][1] - nw[0][1] * nw[1][0];
        if (tool->plunger && fabs(det) > 1e-9) {
            // Wedged position c of the reference point: n_s . (c + R v) >= 0
            // with equality at the support vertices, n_s . c = h_s.
            double c[2] = {(h[0] * nw[1][1] - h[1] * nw[0][1]) / det,
                           (nw[0][0] * h[1] - nw[1][0] * h[0]) / det};
            double area = 0.0;
            for (int i = 0; i < nv; i++) {
                int k = (i + 1) % nv;
                area += v[2 * i] * v[2 * k + 1] - v[2 * k] * v[2 * i + 1];
            }
            double best = -INFINITY, bx = 0.0, by = 0.0, bnx = 0.0, bny = 0.0;
            for (int i = 0; i < nv; i++) {
                int k = (i + 1) % nv;
                double ax = c[0] + cp * v[2 * i] - sp * v[2 * i + 1];
                double ay = c[1] + sp * v[2 * i] + cp * v[2 * i + 1];
                double qx = c[0] + cp * v[2 * k] - sp * v[2 * k + 1];
                double qy = c[1] + sp * v[2 * k] + cp * v[2 * k + 1];
                double x0 = fmin(ax, qx), x1 = fmax(ax, qx);
                if (!(tool->s >= x0 && tool->s <= x1) || x1 - x0 <= 0.0) continue;
                double y = ay + (tool->s - ax) / (qx - ax) * (qy - ay);
                if (y > best) {
                    // inward normal of the edge: left of the edge direction for
                    // a counter-clockwise polygon, right for a clockwise one
                    double dx = qx - ax, dy = qy - ay, len = hypot(dx, dy);
                    double sg = area > 0.0 ? 1.0 : -1.0;
                    best = y; bx = tool->s; by = y;
                    bnx = -sg * dy / len; bny = sg * dx / len;
                }
            }
            if (best > -INFINITY) {
                // to the object frame: r = R(-phi) (p - c), n = R(-phi) n_w
                double px = bx - c[0], py = by - c[1];
                double r[2] = {cp * px + sp * py, -sp * px + cp * py};
                double n[2] = {cp * bnx + sp * bny, -sp * bnx + cp * bny};
                int st = add_contact(rows, nrows, r, n, p->mu);
                if (st) return st;
            }
        }
    }
    if (p->has_push) {
        // push . x >= 0: quasi-static motion must be driven by the push
        // (the contacts only dissipate). Force to the object frame.
        if (*nrows + 1 > EXDEX_CONE_MAX_ROWS) return EXDEX_EINVAL;
        double *a = rows + 3 * *nrows;
        a[0] = cp * p->push[0] + sp * p->push[1];
        a[1] = -sp * p->push[0] + cp * p->push[1];
        a[2] = p->push[2];
        *nrows += 1;
    }
    return EXDEX_OK;
}

int exdex_tool_volumes(const exdex_tool_problem *p, size_t n_tools,
                       const exdex_tool_def *tools, double *volume)
{
    if (exdex_tool_problem_check(p, NULL) || (n_tools > 0 && (!tools || !volume)))
        return EXDEX_EINVAL;
    int ns = p->model == EXDEX_TOOL_PAPER ? 1 : p->n_shapes;
    double rows[3 * EXDEX_CONE_MAX_ROWS];
    size_t idx = 0;
    for (size_t t = 0; t < n_tools; t++)
        for (int s = 0; s < ns; s++)
            for (int k = 0; k < p->n_phi; k++) {
                int m, st = exdex_tool_rows(p, &tools[t], s, p->phi[k], rows, &m);
                if (!st) st = exdex_cone_volume_exact(rows, m, p->lo, p->hi, &volume[idx]);
                if (st) return st;
                idx++;
            }
    return EXDEX_OK;
}

int exdex_tool_objective(const exdex_tool_problem *p, const exdex_tool_def *tool,
                         double *sum)
{
    if (!sum || !tool || exdex_tool_problem_check(p, NULL)) return EXDEX_EINVAL;
    int ns = p->model == EXDEX_TOOL_PAPER ? 1 : p->n_shapes;
    double rows[3 * EXDEX_CONE_MAX_ROWS];
    double acc = 0.0;
    for (int s = 0; s < ns; s++)
        for (int k = 0; k < p->n_phi; k++) {
            int m;
            double v;
            int st = exdex_tool_rows(p, tool, s, p->phi[k], rows, &m);
            if (!st) st = exdex_cone_volume_exact(rows, m, p->lo, p->hi, &v);
            if (st) return st;
            acc += v;
        }
    *sum = acc;
    return EXDEX_OK;
}

/* ------------------------------------------------------- optimisation */

typedef struct theta_ctx {
    const exdex_tool_problem *p;
    exdex_tool_def tool;
    int status;
    int evals;
} theta_ctx;

static double theta_f(double theta, void *params)
{
    theta_ctx *c = params;
    exdex_tool_def t = c->tool;
    t.alpha2 = t.alpha1 + theta;
    double f = NAN;
    int st = exdex_tool_objective(c->p, &t, &f);
    if (st && !c->status) c->status = st;
    c->evals++;
    return f;
}

int exdex_tool_optimise_theta(const exdex_tool_problem *p, const exdex_tool_def *tool,
                              double theta_lo, double theta_hi, int n_scan, double xtol,
                              double *scan_f, exdex_tool_opt_result *res)
{
    if (!tool || !res || exdex_tool_problem_check(p, NULL) || !isfinite(theta_lo) ||
        !isfinite(theta_hi) || !(theta_hi > theta_lo) || n_scan < 3 || !(xtol > 0.0))
        return EXDEX_EINVAL;
    theta_ctx ctx = {p, *tool, EXDEX_OK, 0};
    // Coarse scan (Eq. 12 over a grid of theta); keep the first best value.
    int best = 0;
    double fbest = INFINITY, dth = (theta_hi - theta_lo) / (n_scan - 1);
    double fprev = NAN, fnext = NAN;
    double *f = scan_f ? scan_f : malloc(sizeof(double) * (size_t)n_scan);
    if (!f) return EXDEX_ENOMEM;
    for (int i = 0; i < n_scan; i++) {
        f[i] = theta_f(theta_lo + i * dth, &ctx);
        if (ctx.status) break;
        if (f[i] < fbest) { fbest = f[i]; best = i; }
    }
    if (!ctx.status && best > 0 && best < n_scan - 1) {
        fprev = f[best - 1];
        fnext = f[best + 1];
    }
    if (!scan_f) free(f);
    if (ctx.status) return ctx.status;
    res->x[0] = tool->alpha1;
    res->x[1] = tool->alpha1 + theta_lo + best * dth;
    res->x[2] = tool->s;
    res->f = fbest;
    res->iterations = 0;
    res->bracketed = 0;
    if (!(best > 0 && best < n_scan - 1 && fbest < fprev && fbest < fnext)) {
        res->evaluations = ctx.evals;
        return EXDEX_OK;  // minimum at a bound or on a plateau: no bracket
    }
    // Brent on the two cells around the scan minimum (gsl_min_fminimizer_brent).
    gsl_min_fminimizer *s = gsl_min_fminimizer_alloc(gsl_min_fminimizer_brent);
    if (!s) return EXDEX_ENOMEM;
    gsl_function F = {theta_f, &ctx};
    double a = theta_lo + (best - 1) * dth, b = theta_lo + (best + 1) * dth;
    double xm = theta_lo + best * dth;
    int status = EXDEX_OK;
    int gs = gsl_min_fminimizer_set_with_values(s, &F, xm, fbest, a, fprev, b, fnext);
    if (gs != GSL_SUCCESS) status = EXDEX_ENOCONV;
    int it = 0;
    while (!status && it < 200) {
        it++;
        gs = gsl_min_fminimizer_iterate(s);
        if (ctx.status) { status = ctx.status; break; }
        if (gs != GSL_SUCCESS) { status = EXDEX_ENOCONV; break; }
        double lo = gsl_min_fminimizer_x_lower(s), hi = gsl_min_fminimizer_x_upper(s);
        // Brent cannot resolve a minimum below ~sqrt(DBL_EPSILON) relative
        // (the objective is flat to rounding there): clamp the tolerance.
        double xm_now = gsl_min_fminimizer_x_minimum(s);
        if (hi - lo <= fmax(xtol, 3e-8 * fmax(1.0, fabs(xm_now)))) break;
    }
    if (!status && it >= 200) status = EXDEX_ENOCONV;
    if (!status) {
        double xb = gsl_min_fminimizer_x_minimum(s), fb = gsl_min_fminimizer_f_minimum(s);
        if (fb <= fbest) {
            res->x[1] = tool->alpha1 + xb;
            res->f = fb;
        }
        res->bracketed = 1;
        res->iterations = it;
    }
    res->evaluations = ctx.evals;
    gsl_min_fminimizer_free(s);
    return status;
}

typedef struct multi_ctx {
    const exdex_tool_problem *p;
    exdex_tool_def base;
    int idx[3];  /* free parameter -> index into (alpha1, alpha2, s) */
    int nfree;
    int status;
    int evals;
} multi_ctx;

static double multi_f(const gsl_vector *x, void *params)
{
    multi_ctx *c = params;
    exdex_tool_def t = c->base;
    double *q[3] = {&t.alpha1, &t.alpha2, &t.s};
    for (int i = 0; i < c->nfree; i++) *q[c->idx[i]] = gsl_vector_get(x, (size_t)i);
    double f = NAN;
    int st = exdex_tool_objective(c->p, &t, &f);
    c->evals++;
    if (st) {
        if (!c->status) c->status = st;
        return GSL_POSINF;
    }
    return f;
}

int exdex_tool_optimise(const exdex_tool_problem *p, const exdex_tool_def *start,
                        const int free_param[3], const double step[3], int max_iter,
                        double size_tol, exdex_tool_opt_result *res)
{
    if (!start || !free_param || !step || !res || exdex_tool_problem_check(p, NULL) ||
        max_iter < 1 || !(size_tol > 0.0))
        return EXDEX_EINVAL;
    multi_ctx ctx;
    ctx.p = p;
    ctx.base = *start;
    ctx.nfree = 0;
    ctx.status = EXDEX_OK;
    ctx.evals = 0;
    double x0[3] = {start->alpha1, start->alpha2, start->s};
    for (int i = 0; i < 3; i++) {
        if (!isfinite(x0[i])) return EXDEX_EINVAL;
        if (free_param[i]) {
            if (!(step[i] > 0.0) || !isfinite(step[i])) return EXDEX_EINVAL;
            ctx.idx[ctx.nfree++] = i;
        }
    }
    if (ctx.nfree == 0) return EXDEX_EINVAL;
    res->x[0] = x0[0]; res->x[1] = x0[1]; res->x[2] = x0[2];
    res->f = NAN;
    res->bracketed = 0;
    gsl_multimin_fminimizer *s =
        gsl_multimin_fminimizer_alloc(gsl_multimin_fminimizer_nmsimplex2, (size_t)ctx.nfree);
    gsl_vector *x = gsl_vector_alloc((size_t)ctx.nfree);
    gsl_vector *ss = gsl_vector_alloc((size_t)ctx.nfree);
    int status = EXDEX_OK;
    if (!s || !x || !ss) status = EXDEX_ENOMEM;
    if (!status) {
        for (int i = 0; i < ctx.nfree; i++) {
            gsl_vector_set(x, (size_t)i, x0[ctx.idx[i]]);
            gsl_vector_set(ss, (size_t)i, step[ctx.idx[i]]);
        }
        gsl_multimin_function F = {multi_f, (size_t)ctx.nfree, &ctx};
        if (gsl_multimin_fminimizer_set(s, &F, x, ss) != GSL_SUCCESS) status = EXDEX_ENOCONV;
        if (ctx.status) status = ctx.status;
    }
    int it = 0;
    while (!status) {
        if (it >= max_iter) { status = EXDEX_ENOCONV; break; }
        it++;
        int gs = gsl_multimin_fminimizer_iterate(s);
        if (ctx.status) { status = ctx.status; break; }
        if (gs != GSL_SUCCESS) { status = EXDEX_ENOCONV; break; }
        if (gsl_multimin_test_size(gsl_multimin_fminimizer_size(s), size_tol) == GSL_SUCCESS)
            break;
    }
    if (s && (status == EXDEX_OK || status == EXDEX_ENOCONV) && it > 0) {
        // report the best point even when the iteration cap was hit
        const gsl_vector *xb = gsl_multimin_fminimizer_x(s);
        for (int i = 0; i < ctx.nfree; i++) res->x[ctx.idx[i]] = gsl_vector_get(xb, (size_t)i);
        res->f = gsl_multimin_fminimizer_minimum(s);
    }
    res->iterations = it;
    res->evaluations = ctx.evals;
    if (s) gsl_multimin_fminimizer_free(s);
    if (x) gsl_vector_free(x);
    if (ss) gsl_vector_free(ss);
    return status;
}
