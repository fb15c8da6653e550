/* obstacle_rows.c -- the obstacles' rows with their feature held (obstacle_rows.h).
 *
 * Derivatives. A vertex row is a plane row (contact_plane_row_*, the
 * stops' formulas). A section or rod row is evaluated in truncated Taylor
 * arithmetic: every quantity is a jet (c0, c1, c2), its value and first two
 * Taylor coefficients along a line s -> (q + dq s, t + dt s) of coordinates
 * and time, the gripper's pose along it R(s) = R + s dt Rdot + s^2 dt^2
 * Rddot / 2 (Rdot = [w]x R, Rddot = [dw]x R + [w]x [w]x R) and p(s) = p +
 * s dt v + s^2 dt^2 a / 2, exact to second order. Sums, products,
 * quotients and square roots of jets are exact to second order, so c1 is
 * the gap's directional derivative and 2 c2 its second one:
 *   planar: G_i = c1 along (e_i, 0); gd = c1 and gdd0 = 2 c2 along (v, 1)
 *     (d^2 gap / dt^2 along q + v s + qdd s^2 / 2 is 2 c2 + G qdd);
 *   1-DoF: Fq, Fqq along (1, 0); Ft, Ftt along (0, 1); Ftq from (1, 1).
 * The geometry is that of contact_obstacle_rows: the section vertex of
 * faces f, g solves (R^T n_f)_xy . y = n_f . (p_f - p) (and for g) by
 * Cramer's rule; its gap against the hull edge (u, w) is the edge's outward
 * normal times y - u; a rod's gap is the distance of the hull vertex x from
 * the axis, |(x - c) - ((x - c) . a) a| - r, or for an edge's interior the
 * distance of the edge's line from the axis, |(u - c) . m| / |m| - r with
 * m = (w - u) x a (all in B: c, a the axis's point and direction). */
#include "exdex.h"
#include "obstacle_rows.h"
#include "pose.h"
#include "util.h"

#include <float.h>
#include <string.h>

typedef struct jet {
    double c[3];
} jet;

static jet jk(double x)
{
    jet r = {{x, 0.0, 0.0}};
    return r;
}
static jet jadd(jet a, jet b)
{
    jet r = {{a.c[0] + b.c[0], a.c[1] + b.c[1], a.c[2] + b.c[2]}};
    return r;
}
static jet jsub(jet a, jet b)
{
    jet r = {{a.c[0] - b.c[0], a.c[1] - b.c[1], a.c[2] - b.c[2]}};
    return r;
}
static jet jmul(jet a, jet b)
{
    jet r = {{a.c[0] * b.c[0], a.c[0] * b.c[1] + a.c[1] * b.c[0], a.c[0] * b.c[2] + a.c[1] * b.c[1] + a.c[2] * b.c[0]}};
    return r;
}
static jet jdiv(jet a, jet b)
{
    jet r;
    r.c[0] = a.c[0] / b.c[0];
    r.c[1] = (a.c[1] - r.c[0] * b.c[1]) / b.c[0];
    r.c[2] = (a.c[2] - r.c[0] * b.c[2] - r.c[1] * b.c[1]) / b.c[0];
    return r;
}
static jet jsqrt(jet a)
{
    jet r;
    r.c[0] = sqrt(a.c[0]);
    r.c[1] = a.c[1] / (2.0 * r.c[0]);
    r.c[2] = (a.c[2] - r.c[1] * r.c[1]) / (2.0 * r.c[0]);
    return r;
}

/* The pose along the line: gripper R(s), p(s); the object's centre of mass
 * r(s) in B and cos, sin of its angle. */
typedef struct ojet {
    jet R[9], p[3], r[2], ct, st;
} ojet;

static void ojet_init(const exdex_model *m, const exdex_kinematics *k, const double *q, const double *dq, double dt,
                      ojet *J)
{
    double r0[3], th;
    for (int j = 0; j < 3; j++) {
        double col[3] = {k->R[j], k->R[3 + j], k->R[6 + j]}, d1[3], w1[3], d2[3];
        ex_cross3(d1, k->w, col);
        ex_cross3(w1, k->w, d1);
        ex_cross3(d2, k->dw, col);
        for (int i = 0; i < 3; i++) {
            J->R[3 * i + j].c[0] = col[i];
            J->R[3 * i + j].c[1] = dt * d1[i];
            J->R[3 * i + j].c[2] = 0.5 * dt * dt * (d2[i] + w1[i]);
        }
    }
    for (int i = 0; i < 3; i++) {
        J->p[i].c[0] = k->p[i];
        J->p[i].c[1] = dt * k->v[i];
        J->p[i].c[2] = 0.5 * dt * dt * k->a[i];
    }
    pose_com(m, q, r0, &th);
    if (m->ndof == 3) {
        double w = dq[2], c = cos(th), s = sin(th);
        J->r[0] = jk(r0[0]);
        J->r[0].c[1] = dq[0];
        J->r[1] = jk(r0[1]);
        J->r[1].c[1] = dq[1];
        J->ct = (jet){{c, -s * w, -0.5 * c * w * w}};
        J->st = (jet){{s, c * w, -0.5 * s * w * w}};
    } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        J->r[0] = (jet){{r0[0], dq[0] * m->d[0], 0.0}};
        J->r[1] = (jet){{r0[1], dq[0] * m->d[1], 0.0}};
        J->ct = jk(cos(th));
        J->st = jk(sin(th));
    } else {
        double w = dq[0], c = cos(th), s = sin(th);
        J->ct = (jet){{c, -s * w, -0.5 * c * w * w}};
        J->st = (jet){{s, c * w, -0.5 * s * w * w}};
        J->r[0] = jadd(jk(m->pivot[0]), jsub(jmul(J->ct, jk(m->c[0])), jmul(J->st, jk(m->c[1]))));
        J->r[1] = jadd(jk(m->pivot[1]), jadd(jmul(J->st, jk(m->c[0])), jmul(J->ct, jk(m->c[1]))));
    }
}

/* Hull vertex k in B. */
static void ojet_hull(const exdex_model *m, const ojet *J, int k, jet x[2])
{
    double hx = m->hull[k][0], hy = m->hull[k][1];
    x[0] = jadd(J->r[0], jsub(jmul(J->ct, jk(hx)), jmul(J->st, jk(hy))));
    x[1] = jadd(J->r[1], jadd(jmul(J->st, jk(hx)), jmul(J->ct, jk(hy))));
}

/* R(s)^T u for a fixed vector u of A. */
static void ojet_rt(const ojet *J, const double u[3], jet out[3])
{
    for (int i = 0; i < 3; i++) {
        out[i] = jk(0.0);
        for (int k = 0; k < 3; k++) out[i] = jadd(out[i], jmul(J->R[3 * k + i], jk(u[k])));
    }
}

/* ------------------------------------------------ disc outlines
 * A disc outline (disc_r > 0, its centre the one vertex) has one row per
 * obstacle, the same kinds with their own meaning: OROW_VERTEX (a = 0) the
 * support point against face feat (a plane row, as a stop's); OROW_SECTION
 * (faces a < b, feat 0) the centre's distance from the section vertex of
 * faces a, b less the radius; OROW_ROD (feat 0) the rim point nearest the
 * axis, its distance from the axis less the rod's radius. That last is a
 * minimum over the rim angle phi of f(phi; q, t): with phi* the minimiser
 * (contact_circle_min), the gap's first derivatives are f's at phi* and its
 * second ones f_ab - f_a,phi f_b,phi / f_phi,phi (the envelope), from jets
 * along lines that also move phi. */

/* The disc's centre in B along the line. */
static void ojet_disc(const exdex_model *m, const ojet *J, jet x[2])
{
    double hx = m->vert[0][0], hy = m->vert[0][1];
    x[0] = jadd(J->r[0], jsub(jmul(J->ct, jk(hx)), jmul(J->st, jk(hy))));
    x[1] = jadd(J->r[1], jadd(jmul(J->st, jk(hx)), jmul(J->ct, jk(hy))));
}

/* The section vertex of faces f, g along the line (Cramer's rule). */
static void ojet_section_vertex(const exdex_obstacle_def *ob, const ojet *J, int f, int g, jet y[2])
{
    jet af[3], ag[3], bf = jk(ex_dot3(ob->face_normal[f], ob->face_point[f]));
    jet bg = jk(ex_dot3(ob->face_normal[g], ob->face_point[g])), det;
    ojet_rt(J, ob->face_normal[f], af);
    ojet_rt(J, ob->face_normal[g], ag);
    for (int k = 0; k < 3; k++) {
        bf = jsub(bf, jmul(jk(ob->face_normal[f][k]), J->p[k]));
        bg = jsub(bg, jmul(jk(ob->face_normal[g][k]), J->p[k]));
    }
    det = jsub(jmul(af[0], ag[1]), jmul(af[1], ag[0]));
    y[0] = jdiv(jsub(jmul(bf, ag[1]), jmul(bg, af[1])), det);
    y[1] = jdiv(jsub(jmul(af[0], bg), jmul(ag[0], bf)), det);
}

/* The rod's axis in B along the line: point cB, direction aB. */
static void ojet_axis(const exdex_obstacle_def *ob, const ojet *J, jet cB[3], jet aB[3])
{
    ojet_rt(J, ob->axis, aB);
    ojet_rt(J, ob->center, cB);
    for (int i = 0; i < 3; i++) {
        jet t = jk(0.0);
        for (int k = 0; k < 3; k++) t = jadd(t, jmul(J->R[3 * k + i], J->p[k]));
        cB[i] = jsub(cB[i], t);
    }
}

/* The hull edge e along the line: its start u, its direction (ex, ey) to
 * the next hull vertex; returns its length. */
static jet ojet_edge(const exdex_model *m, const ojet *J, int e, jet u[2], jet *ex, jet *ey)
{
    jet w[2];
    ojet_hull(m, J, e, u);
    ojet_hull(m, J, (e + 1) % m->n_hull, w);
    *ex = jsub(w[0], u[0]);
    *ey = jsub(w[1], u[1]);
    return jsqrt(jadd(jmul(*ex, *ex), jmul(*ey, *ey)));
}

/* The rim point at the unit u0 (cos phi0, sin phi0) turned by dphi s, and
 * distance |w|) along the line (q + dq s, t + dt s). */
static void disc_rim_jet(const exdex_model *m, const exdex_kinematics *kin, const exdex_obstacle_def *ob,
                         const double *q, const double *dq, double dt, const double u0[2], double dphi, jet x[2],
                         jet w[3])
{
    ojet J;
    jet cB[3], aB[3], d[3], t, c = {{u0[0], -u0[1] * dphi, -0.5 * u0[0] * dphi * dphi}};
    jet sn = {{u0[1], u0[0] * dphi, -0.5 * u0[1] * dphi * dphi}};
    ojet_init(m, kin, q, dq, dt, &J);
    ojet_axis(ob, &J, cB, aB);
    ojet_disc(m, &J, x);
    x[0] = jadd(x[0], jmul(jk(m->disc_r), c));
    x[1] = jadd(x[1], jmul(jk(m->disc_r), sn));
    d[0] = jsub(x[0], cB[0]);
    d[1] = jsub(x[1], cB[1]);
    d[2] = jsub(jk(0.0), cB[2]);
    t = jadd(jadd(jmul(d[0], aB[0]), jmul(d[1], aB[1])), jmul(d[2], aB[2]));
    for (int i = 0; i < 3; i++) w[i] = jsub(d[i], jmul(t, aB[i]));
}

/* The distance of that rim point from the axis less the rod's radius. */
static jet disc_rod_jet(const exdex_model *m, const exdex_kinematics *kin, const exdex_obstacle_def *ob,
                        const double *q, const double *dq, double dt, const double u0[2], double dphi)
{
    jet x[2], w[3];
    disc_rim_jet(m, kin, ob, q, dq, dt, u0, dphi, x, w);
    return jsub(jsqrt(jadd(jadd(jmul(w[0], w[0]), jmul(w[1], w[1])), jmul(w[2], w[2]))), jk(ob->radius));
}

/* The rim point nearest the rod's axis at (kin, q): the unit u of
 * contact_circle_min (the rim point xc + r u, as contact_obstacle_build
 * takes it). */
static void disc_rod_u(const exdex_model *m, const exdex_kinematics *kin, const exdex_obstacle_def *ob,
                       const double *q, double u[2])
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], cB[3], aB[3], d[3], t, b[2];
    contact_vertices(m, q, xb, vx);
    contact_rod_axis(ob, kin->R, kin->p, cB, aB);
    for (int i = 0; i < 3; i++) d[i] = xb[0][i] - cB[i];
    t = ex_dot3(d, aB);
    b[0] = d[0] - t * aB[0];
    b[1] = d[1] - t * aB[1];
    contact_circle_min(aB, b, m->disc_r, u);
}

/* Along the line (q + dq s, t + dt s) from the minimiser u: the rod row's
 * first derivative (*g1), its second (*g2, the envelope's) and the rate of
 * the minimiser (returned). */
static double disc_rod_env(const exdex_model *m, const exdex_kinematics *kin, const exdex_obstacle_def *ob,
                           const double *q, const double *dq, double dt, const double u[2], double *g0, double *g1,
                           double *g2)
{
    double zero[3] = {0, 0, 0}, fss, fpp, fsp;
    jet a = disc_rod_jet(m, kin, ob, q, dq, dt, u, 0.0), b = disc_rod_jet(m, kin, ob, q, zero, 0.0, u, 1.0);
    jet c = disc_rod_jet(m, kin, ob, q, dq, dt, u, 1.0);
    fss = 2.0 * a.c[2];
    fpp = 2.0 * b.c[2];
    fsp = 0.5 * (2.0 * c.c[2] - fss - fpp);
    if (g0) *g0 = a.c[0];
    if (g1) *g1 = a.c[1];
    if (!(fpp > 0.0)) {
        if (g2) *g2 = fss;
        return 0.0;
    }
    if (g2) *g2 = fss - fsp * fsp / fpp;
    return -fsp / fpp;
}

/* The gap of a section or rod row along the line (see the header). */
static jet orow_jet(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q, const double *dq,
                    double dt)
{
    const exdex_obstacle_def *ob = &m->def.obstacles[orow_obst(code)];
    int feat = orow_feat(code);
    ojet J;
    ojet_init(m, kin, q, dq, dt, &J);
    if (m->disc_r > 0.0) {
        /* the centre's distance from the section vertex (a rod: disc_rod_jet) */
        jet y[2], xc[2], dx, dy;
        ojet_section_vertex(ob, &J, orow_a(code), orow_b(code), y);
        ojet_disc(m, &J, xc);
        dx = jsub(xc[0], y[0]);
        dy = jsub(xc[1], y[1]);
        return jsub(jsqrt(jadd(jmul(dx, dx), jmul(dy, dy))), jk(m->disc_r));
    }
    if (orow_kind(code) == OROW_SECTION) {
        jet y[2], u[2], ex, ey, len;
        ojet_section_vertex(ob, &J, orow_a(code), orow_b(code), y);
        len = ojet_edge(m, &J, feat, u, &ex, &ey);
        return jdiv(jsub(jmul(ey, jsub(y[0], u[0])), jmul(ex, jsub(y[1], u[1]))), len);
    } else {
        jet cB[3], aB[3], d[3];
        ojet_axis(ob, &J, cB, aB);
        if (feat < 32) {
            jet x[2], t, w2 = jk(0.0);
            ojet_hull(m, &J, feat, x);
            d[0] = jsub(x[0], cB[0]);
            d[1] = jsub(x[1], cB[1]);
            d[2] = jsub(jk(0.0), cB[2]);
            t = jadd(jadd(jmul(d[0], aB[0]), jmul(d[1], aB[1])), jmul(d[2], aB[2]));
            for (int i = 0; i < 3; i++) {
                jet wi = jsub(d[i], jmul(t, aB[i]));
                w2 = jadd(w2, jmul(wi, wi));
            }
            return jsub(jsqrt(w2), jk(ob->radius));
        } else {
            int e = feat - 32;
            jet u[2], du[2], mv[3], num, mm;
            ojet_edge(m, &J, e, u, &du[0], &du[1]);
            mv[0] = jmul(du[1], aB[2]);
            mv[1] = jsub(jk(0.0), jmul(du[0], aB[2]));
            mv[2] = jsub(jmul(du[0], aB[1]), jmul(du[1], aB[0]));
            d[0] = jsub(u[0], cB[0]);
            d[1] = jsub(u[1], cB[1]);
            d[2] = jsub(jk(0.0), cB[2]);
            num = jadd(jadd(jmul(d[0], mv[0]), jmul(d[1], mv[1])), jmul(d[2], mv[2]));
            mm = jsqrt(jadd(jadd(jmul(mv[0], mv[0]), jmul(mv[1], mv[1])), jmul(mv[2], mv[2])));
            if (num.c[0] < 0.0) num = jsub(jk(0.0), num);
            return jsub(jdiv(num, mm), jk(ob->radius));
        }
    }
}

int orow_valid(const exdex_model *m, int code)
{
    int o, kind, a, b, f;
    const exdex_obstacle_def *ob;
    if (code < 0) return 0;
    o = orow_obst(code);
    kind = orow_kind(code);
    a = orow_a(code);
    b = orow_b(code);
    f = orow_feat(code);
    if (o >= m->n_obst) return 0;
    ob = &m->def.obstacles[o];
    if (m->disc_r > 0.0) {
        if (ob->kind == EXDEX_OBSTACLE_POLYTOPE)
            return (kind == OROW_VERTEX && a == 0 && b == 0 && f < ob->n_faces) ||
                   (kind == OROW_SECTION && a < b && b < ob->n_faces && f == 0);
        return kind == OROW_ROD && a == 0 && b == 0 && f == 0;
    }
    if (ob->kind == EXDEX_OBSTACLE_POLYTOPE) {
        if (kind == OROW_VERTEX) return a < contact_nv(m) && b == 0 && f < ob->n_faces;
        return kind == OROW_SECTION && m->n_hull >= 3 && a < b && b < ob->n_faces && f < m->n_hull;
    }
    return kind == OROW_ROD && a == 0 && b == 0 && (f < 32 ? f < m->n_hull : f - 32 < m->n_hull && m->n_hull > 1);
}

/* ------------------------------------------------ plain geometry at t */

/* Half-plane a . y <= b of face f in B's plate plane; returns |a|. */
static double face_line(const exdex_obstacle_def *ob, const exdex_kinematics *kin, int f, double a[2], double *b)
{
    double nB[3], d[3];
    ex_mulmtv3(nB, kin->R, ob->face_normal[f]);
    for (int i = 0; i < 3; i++) d[i] = ob->face_point[f][i] - kin->p[i];
    a[0] = nB[0];
    a[1] = nB[1];
    *b = ex_dot3(ob->face_normal[f], d);
    return hypot(nB[0], nB[1]);
}

/* min(res, the least distance of the point y inside the plate-plane lines of
 * the obstacle's faces other than f and g): a point of the section stays
 * inside the other faces' half-planes. */
static double inside_other_faces(const exdex_obstacle_def *ob, const exdex_kinematics *kin, int f, int g,
                                 const double y[2], double res)
{
    for (int h = 0; h < ob->n_faces; h++) {
        double ah[2], bh, na;
        if (h == f || h == g) continue;
        na = face_line(ob, kin, h, ah, &bh);
        if (na > 1e-12) res = fmin(res, (bh - ah[0] * y[0] - ah[1] * y[1]) / na);
    }
    return res;
}

/* The rod's contact normal at the point x (B): the offset of x from the
 * axis (cB, aB), d - (d . aB) aB with d = x - cB, normalised (zero when x is
 * on the axis) into nb. Returns the distance |d - (d . aB) aB|. */
static double rod_normal(const double cB[3], const double aB[3], const double x[3], double nb[3])
{
    double d[3], t, dist;
    for (int i = 0; i < 3; i++) d[i] = x[i] - cB[i];
    t = ex_dot3(d, aB);
    for (int i = 0; i < 3; i++) nb[i] = d[i] - t * aB[i];
    dist = sqrt(ex_dot3(nb, nb));
    for (int i = 0; i < 3; i++) nb[i] = dist > 0.0 ? nb[i] / dist : 0.0;
    return dist;
}

/* Rate of the row code (feature held) at (q, v) (the gap's first Taylor
 * coefficient along (v, 1)). */
static double orow_rate(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q, const double *v)
{
    const exdex_obstacle_def *ob = &m->def.obstacles[orow_obst(code)];
    if (orow_kind(code) == OROW_VERTEX) {
        int f = orow_feat(code);
        if (m->ndof == 3) {
            double G[3], gd;
            contact_plane_row_planar(m, kin, ob->face_point[f], ob->face_normal[f], orow_a(code), q, v, G, &gd, NULL);
            return gd;
        } else {
            crow c;
            contact_plane_row_1dof(m, kin, ob->face_point[f], ob->face_normal[f], orow_a(code), q[0], &c);
            return c.Fq * v[0] + c.Ft;
        }
    }
    return orow_jet(m, kin, code, q, v, 1.0).c[1];
}

/* orow_rate for the rate tie rule of contact_obstacle_build. */
static double feature_rate(const exdex_model *m, const exdex_kinematics *kin, const contact_feature *f,
                           const double *q, const double *v)
{
    return orow_rate(m, kin, orow_code(f->obst, f->kind, f->a, f->b, f->feat), q, v);
}

int orow_all(const exdex_model *m, const exdex_kinematics *kin, const double *q, const double *v, int planar,
             int *code, double *gap)
{
    contact_obuild opt = {NULL, 0.0, v, v ? feature_rate : NULL, planar};
    contact_feature ft[MAX_ROWS];
    int n = contact_obstacle_build(m, kin, q, &opt, NULL, gap, NULL, NULL, NULL, ft);
    for (int i = 0; i < n; i++) code[i] = orow_code(ft[i].obst, ft[i].kind, ft[i].a, ft[i].b, ft[i].feat);
    return n;
}

double orow_planar(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q, const double *v,
                   double G[3], double *gd, double *gdd0)
{
    const exdex_obstacle_def *ob = &m->def.obstacles[orow_obst(code)];
    jet g;
    if (orow_kind(code) == OROW_VERTEX) {
        int f = orow_feat(code);
        return contact_plane_row_planar(m, kin, ob->face_point[f], ob->face_normal[f], orow_a(code), q, v, G, gd,
                                        gdd0);
    }
    if (m->disc_r > 0.0 && orow_kind(code) == OROW_ROD) {
        double ur[2], g0, g1, g2;
        disc_rod_u(m, kin, ob, q, ur);
        for (int i = 0; i < 3; i++) {
            double e[3] = {0, 0, 0};
            e[i] = 1.0;
            G[i] = disc_rod_jet(m, kin, ob, q, e, 0.0, ur, 0.0).c[1];
        }
        disc_rod_env(m, kin, ob, q, v, 1.0, ur, &g0, &g1, &g2);
        if (gd) *gd = g1;
        if (gdd0) *gdd0 = g2;
        return g0;
    }
    for (int i = 0; i < 3; i++) {
        double e[3] = {0, 0, 0};
        e[i] = 1.0;
        G[i] = orow_jet(m, kin, code, q, e, 0.0).c[1];
    }
    g = orow_jet(m, kin, code, q, v, 1.0);
    if (gd) *gd = g.c[1];
    if (gdd0) *gdd0 = 2.0 * g.c[2];
    return g.c[0];
}

void orow_1dof(const exdex_model *m, const exdex_kinematics *kin, int code, double q, crow *c)
{
    const exdex_obstacle_def *ob = &m->def.obstacles[orow_obst(code)];
    double one = 1.0, zero = 0.0;
    jet gq, gt, gb;
    if (orow_kind(code) == OROW_VERTEX) {
        int f = orow_feat(code);
        contact_plane_row_1dof(m, kin, ob->face_point[f], ob->face_normal[f], orow_a(code), q, c);
        return;
    }
    if (m->disc_r > 0.0 && orow_kind(code) == OROW_ROD) {
        /* the envelope: f_ab - f_a,phi f_b,phi / f_phi,phi */
        double ur[2], fqp, ftp, fpp, dq, dt;
        jet jp;
        disc_rod_u(m, kin, ob, &q, ur);
        jp = disc_rod_jet(m, kin, ob, &q, &zero, 0.0, ur, 1.0);
        gq = disc_rod_jet(m, kin, ob, &q, &one, 0.0, ur, 0.0);
        gt = disc_rod_jet(m, kin, ob, &q, &zero, 1.0, ur, 0.0);
        gb = disc_rod_jet(m, kin, ob, &q, &one, 1.0, ur, 0.0);
        fpp = 2.0 * jp.c[2];
        fqp = disc_rod_jet(m, kin, ob, &q, &one, 0.0, ur, 1.0).c[2] - gq.c[2] - jp.c[2];
        ftp = disc_rod_jet(m, kin, ob, &q, &zero, 1.0, ur, 1.0).c[2] - gt.c[2] - jp.c[2];
        dq = fpp > 0.0 ? fqp / fpp : 0.0;
        dt = fpp > 0.0 ? ftp / fpp : 0.0;
        c->F = gq.c[0];
        c->Fq = gq.c[1];
        c->Fqq = 2.0 * gq.c[2] - fqp * dq;
        c->Ft = gt.c[1];
        c->Ftt = 2.0 * gt.c[2] - ftp * dt;
        c->Ftq = gb.c[2] - gq.c[2] - gt.c[2] - fqp * dt;
        return;
    }
    gq = orow_jet(m, kin, code, &q, &one, 0.0);
    gt = orow_jet(m, kin, code, &q, &zero, 1.0);
    gb = orow_jet(m, kin, code, &q, &one, 1.0);
    c->F = gq.c[0];
    c->Fq = gq.c[1];
    c->Fqq = 2.0 * gq.c[2];
    c->Ft = gt.c[1];
    c->Ftt = 2.0 * gt.c[2];
    c->Ftq = gb.c[2] - gq.c[2] - gt.c[2];
}

double orow_feature_guard(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q)
{
    const exdex_obstacle_def *ob = &m->def.obstacles[orow_obst(code)];
    double hb[EXDEX_MAX_VERTICES][3], big = m->scale.L;
    int nh = contact_hull_b(m, q, hb), feat = orow_feat(code), kind = orow_kind(code);
    if (m->disc_r > 0.0) {
        /* a face row: the centre's foot on the face line stays on the
         * face (inside the other faces' half-planes); a section vertex:
         * the centre's feet on both its face lines stay beyond it, and it
         * stays a vertex of the section; a rod: no feature */
        double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], res = big;
        contact_vertices(m, q, xb, vx);
        if (kind == OROW_VERTEX) {
            double af[2], bf, na = face_line(ob, kin, feat, af, &bf), dd, y[2];
            if (!(na > 1e-12)) return big;
            dd = (af[0] * xb[0][0] + af[1] * xb[0][1] - bf) / na;
            y[0] = xb[0][0] - dd * af[0] / na;
            y[1] = xb[0][1] - dd * af[1] / na;
            return inside_other_faces(ob, kin, feat, feat, y, res);
        }
        if (kind == OROW_SECTION) {
            int f = orow_a(code), g = orow_b(code);
            double af[2], ag[2], bf, bg, det, y[2], nf, ng, df, dg, yf[2], yg[2];
            nf = face_line(ob, kin, f, af, &bf);
            ng = face_line(ob, kin, g, ag, &bg);
            det = af[0] * ag[1] - af[1] * ag[0];
            y[0] = (bf * ag[1] - bg * af[1]) / det;
            y[1] = (af[0] * bg - ag[0] * bf) / det;
            df = (af[0] * xb[0][0] + af[1] * xb[0][1] - bf) / nf;
            dg = (ag[0] * xb[0][0] + ag[1] * xb[0][1] - bg) / ng;
            yf[0] = xb[0][0] - df * af[0] / nf;
            yf[1] = xb[0][1] - df * af[1] / nf;
            yg[0] = xb[0][0] - dg * ag[0] / ng;
            yg[1] = xb[0][1] - dg * ag[1] / ng;
            res = fmin((ag[0] * yf[0] + ag[1] * yf[1] - bg) / ng, (af[0] * yg[0] + af[1] * yg[1] - bf) / nf);
            return inside_other_faces(ob, kin, f, g, y, res);
        }
        return big;
    }
    if (kind == OROW_VERTEX) {
        double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], gf, go = -INFINITY;
        int j = orow_a(code);
        contact_vertices(m, q, xb, vx);
        gf = contact_plane_gap(m, kin, ob->face_point[feat], ob->face_normal[feat], xb[j], vx[j], NULL);
        for (int f = 0; f < ob->n_faces; f++)
            if (f != feat) go = fmax(go, contact_plane_gap(m, kin, ob->face_point[f], ob->face_normal[f], xb[j], vx[j], NULL));
        return ob->n_faces > 1 ? gf - go : big;
    }
    if (kind == OROW_SECTION) {
        int f = orow_a(code), g = orow_b(code);
        double af[2], ag[2], bf, bg, det, y[2], res = big, ge = -INFINITY, go = -INFINITY;
        face_line(ob, kin, f, af, &bf);
        face_line(ob, kin, g, ag, &bg);
        det = af[0] * ag[1] - af[1] * ag[0];
        y[0] = (bf * ag[1] - bg * af[1]) / det;
        y[1] = (af[0] * bg - ag[0] * bf) / det;
        /* the held edge stays the farthest edge line */
        for (int e = 0; e < nh; e++) {
            const double *u = hb[e], *v = hb[(e + 1) % nh];
            double ex = v[0] - u[0], ey = v[1] - u[1], len = hypot(ex, ey), gv;
            if (!(len > 0.0)) continue;
            gv = ey / len * (y[0] - u[0]) + (-ex / len) * (y[1] - u[1]);
            if (e == feat)
                ge = gv;
            else
                go = fmax(go, gv);
        }
        if (nh > 1 && isfinite(go)) res = fmin(res, ge - go);
        /* and y a vertex of the section: inside the other faces' half-planes */
        return inside_other_faces(ob, kin, f, g, y, res);
    }
    {
        double cB[3], aB[3], len, t;
        contact_rod_axis(ob, kin->R, kin->p, cB, aB);
        if (nh < 2) return big;
        if (feat >= 32) {
            t = contact_rod_foot(nh, (const double (*)[3])hb, cB, aB, feat - 32, &len);
            return fmin(t, 1.0 - t) * len;
        } else {
            int ep = (feat + nh - 1) % nh;
            double lp, tp = contact_rod_foot(nh, (const double (*)[3])hb, cB, aB, ep, &lp);
            double tn = contact_rod_foot(nh, (const double (*)[3])hb, cB, aB, feat, &len);
            return fmin((tp - 1.0) * lp, -tn * len);
        }
    }
}

void orow_point(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q, contact_point *cp)
{
    const exdex_obstacle_def *ob = &m->def.obstacles[orow_obst(code)];
    double hb[EXDEX_MAX_VERTICES][3], r[3], th, x[3] = {0, 0, 0}, nb[3] = {0, 0, 0};
    int nh = contact_hull_b(m, q, hb), feat = orow_feat(code), kind = orow_kind(code);
    pose_com(m, q, r, &th);
    if (m->disc_r > 0.0) {
        /* the disc: its support point against the face, the rim point
         * toward the section vertex, the rim point nearest the axis */
        double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], rd = m->disc_r, nn;
        contact_vertices(m, q, xb, vx);
        if (kind == OROW_VERTEX) {
            ex_mulmtv3(nb, kin->R, ob->face_normal[feat]);
            nn = hypot(nb[0], nb[1]);
            x[0] = xb[0][0] - (nn > FQ_MIN ? rd * nb[0] / nn : 0.0);
            x[1] = xb[0][1] - (nn > FQ_MIN ? rd * nb[1] / nn : 0.0);
        } else if (kind == OROW_SECTION) {
            int f = orow_a(code), g = orow_b(code);
            double af[2], ag[2], bf, bg, det, y[2];
            face_line(ob, kin, f, af, &bf);
            face_line(ob, kin, g, ag, &bg);
            det = af[0] * ag[1] - af[1] * ag[0];
            y[0] = (bf * ag[1] - bg * af[1]) / det;
            y[1] = (af[0] * bg - ag[0] * bf) / det;
            nb[0] = xb[0][0] - y[0];
            nb[1] = xb[0][1] - y[1];
            nn = hypot(nb[0], nb[1]);
            nb[0] = nn > 0.0 ? nb[0] / nn : 0.0;
            nb[1] = nn > 0.0 ? nb[1] / nn : 0.0;
            x[0] = xb[0][0] - rd * nb[0];
            x[1] = xb[0][1] - rd * nb[1];
        } else {
            double cB[3], aB[3], ur[2];
            disc_rod_u(m, kin, ob, q, ur);
            contact_rod_axis(ob, kin->R, kin->p, cB, aB);
            x[0] = xb[0][0] + rd * ur[0];
            x[1] = xb[0][1] + rd * ur[1];
            rod_normal(cB, aB, x, nb);
        }
        contact_set_point(cp, x, r, nb);
        (void)nh;
        return;
    }
    if (kind == OROW_VERTEX) {
        double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
        int j = orow_a(code);
        contact_vertices(m, q, xb, vx);
        memcpy(cp->x, xb[j], sizeof cp->x);
        memcpy(cp->vx, vx[j], sizeof cp->vx);
        ex_mulmtv3(cp->nB, kin->R, ob->face_normal[feat]);
        return;
    }
    if (kind == OROW_SECTION) {
        int f = orow_a(code), g = orow_b(code);
        double af[2], ag[2], bf, bg, det;
        const double *u = hb[feat], *w = hb[(feat + 1) % nh];
        double ex = w[0] - u[0], ey = w[1] - u[1], len = hypot(ex, ey);
        face_line(ob, kin, f, af, &bf);
        face_line(ob, kin, g, ag, &bg);
        det = af[0] * ag[1] - af[1] * ag[0];
        x[0] = (bf * ag[1] - bg * af[1]) / det;
        x[1] = (af[0] * bg - ag[0] * bf) / det;
        /* the edge's inward normal: the gap grows as the object's point at
         * y moves into the object (away from the section vertex) */
        if (len > 0.0) {
            nb[0] = -ey / len;
            nb[1] = ex / len;
        }
    } else {
        double cB[3], aB[3];
        contact_rod_axis(ob, kin->R, kin->p, cB, aB);
        if (feat < 32) {
            x[0] = hb[feat][0];
            x[1] = hb[feat][1];
        } else {
            double len, tf = contact_rod_foot(nh, (const double (*)[3])hb, cB, aB, feat - 32, &len);
            const double *u = hb[feat - 32], *w = hb[(feat - 31) % nh];
            x[0] = u[0] + tf * (w[0] - u[0]);
            x[1] = u[1] + tf * (w[1] - u[1]);
        }
        rod_normal(cB, aB, x, nb);
    }
    contact_set_point(cp, x, r, nb);
}

/* ------------------------------------------------ slip along a row
 * The slip of the object's material point at the row's contact point x
 * along the tangent t = e_z x n (n the unit in-plane normal of the row, B):
 * s = t . (xdot + R^T pdot + w_B x x), xdot the material point's velocity in
 * B, w_B = R^T w (contact_tangent's T v + tb). Along the line (q + v s, t +
 * s) with v held, its first Taylor coefficient is d s / dt less T qdd: the
 * slip acceleration sdd0 (stop_friction.h) of a row whose contact point moves over
 * the object (a section vertex along the object's edge, a rod's nearest
 * point) as exactly as of a vertex row. */

/* The contact point x and the unit in-plane normal n (B) of a section or rod
 * row along the line (orow_point's, as jets). */
static void orow_point_jet(const exdex_model *m, const exdex_obstacle_def *ob, const ojet *J, int code, jet x[2],
                           jet n[2])
{
    int feat = orow_feat(code);
    if (m->disc_r > 0.0) {
        /* a disc's section row: the rim point toward the section vertex */
        jet y[2], xc[2], nn;
        ojet_section_vertex(ob, J, orow_a(code), orow_b(code), y);
        ojet_disc(m, J, xc);
        n[0] = jsub(xc[0], y[0]);
        n[1] = jsub(xc[1], y[1]);
        nn = jsqrt(jadd(jmul(n[0], n[0]), jmul(n[1], n[1])));
        n[0] = jdiv(n[0], nn);
        n[1] = jdiv(n[1], nn);
        x[0] = jsub(xc[0], jmul(jk(m->disc_r), n[0]));
        x[1] = jsub(xc[1], jmul(jk(m->disc_r), n[1]));
        return;
    }
    if (orow_kind(code) == OROW_SECTION) {
        jet u[2], ex, ey, len;
        ojet_section_vertex(ob, J, orow_a(code), orow_b(code), x);
        len = ojet_edge(m, J, feat, u, &ex, &ey);
        n[0] = jdiv(jsub(jk(0.0), ey), len);
        n[1] = jdiv(ex, len);
    } else {
        jet cB[3], aB[3], d[3], t, nn;
        ojet_axis(ob, J, cB, aB);
        if (feat < 32) {
            ojet_hull(m, J, feat, x);
        } else {
            jet u[2], du[3], dd[3], ta, tf, num = jk(0.0), den = jk(0.0);
            ojet_edge(m, J, feat - 32, u, &du[0], &du[1]);
            du[2] = jk(0.0);
            d[0] = jsub(u[0], cB[0]);
            d[1] = jsub(u[1], cB[1]);
            d[2] = jsub(jk(0.0), cB[2]);
            t = jadd(jadd(jmul(d[0], aB[0]), jmul(d[1], aB[1])), jmul(d[2], aB[2]));
            ta = jadd(jmul(du[0], aB[0]), jmul(du[1], aB[1]));
            for (int i = 0; i < 3; i++) {
                jet wi = jsub(d[i], jmul(t, aB[i]));
                dd[i] = jsub(du[i], jmul(ta, aB[i]));
                num = jadd(num, jmul(wi, dd[i]));
                den = jadd(den, jmul(dd[i], dd[i]));
            }
            tf = jdiv(jsub(jk(0.0), num), den);
            x[0] = jadd(u[0], jmul(tf, du[0]));
            x[1] = jadd(u[1], jmul(tf, du[1]));
        }
        d[0] = jsub(x[0], cB[0]);
        d[1] = jsub(x[1], cB[1]);
        d[2] = jsub(jk(0.0), cB[2]);
        t = jadd(jadd(jmul(d[0], aB[0]), jmul(d[1], aB[1])), jmul(d[2], aB[2]));
        n[0] = jsub(d[0], jmul(t, aB[0]));
        n[1] = jsub(d[1], jmul(t, aB[1]));
        nn = jsqrt(jadd(jmul(n[0], n[0]), jmul(n[1], n[1])));
        n[0] = jdiv(n[0], nn);
        n[1] = jdiv(n[1], nn);
    }
}

double orow_slip(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q, const double *v,
                 double T[3], double *tb, double *sdd0)
{
    const exdex_obstacle_def *ob = &m->def.obstacles[orow_obst(code)];
    contact_point cp;
    if (orow_kind(code) == OROW_VERTEX)
        return contact_plane_slip_planar(m, kin, ob->face_normal[orow_feat(code)], orow_a(code), q, v, T, tb, sdd0);
    orow_point(m, kin, code, q, &cp);
    contact_tangent(m, kin, cp.x, cp.vx, cp.nB, T, tb);
    if (sdd0) {
        ojet J;
        jet x[2], n[2], wB[3], vp[3], pv[3], wv[3], tx, ty, s;
        ojet_init(m, kin, q, v, 1.0, &J);
        if (m->disc_r > 0.0 && orow_kind(code) == OROW_ROD) {
            /* the rim point nearest the axis moves along the rim at the
             * minimiser's rate */
            double ur[2], dphi;
            disc_rod_u(m, kin, ob, q, ur);
            dphi = disc_rod_env(m, kin, ob, q, v, 1.0, ur, NULL, NULL, NULL);
            jet w[3], nn;
            disc_rim_jet(m, kin, ob, q, v, 1.0, ur, dphi, x, w);
            nn = jsqrt(jadd(jmul(w[0], w[0]), jmul(w[1], w[1])));
            n[0] = jdiv(w[0], nn);
            n[1] = jdiv(w[1], nn);
        } else {
            orow_point_jet(m, ob, &J, code, x, n);
        }
        for (int i = 0; i < 3; i++) {
            wv[i] = (jet){{kin->w[i], kin->dw[i], 0.0}};
            pv[i] = (jet){{kin->v[i], kin->a[i], 0.0}};
        }
        for (int i = 0; i < 3; i++) {
            wB[i] = jk(0.0);
            vp[i] = jk(0.0);
            for (int k = 0; k < 3; k++) {
                wB[i] = jadd(wB[i], jmul(J.R[3 * k + i], wv[k]));
                vp[i] = jadd(vp[i], jmul(J.R[3 * k + i], pv[k]));
            }
        }
        /* the material point's velocity in B, plus the frame's at x */
        tx = jadd(jsub(jk(v[0]), jmul(jk(v[2]), jsub(x[1], J.r[1]))), jsub(vp[0], jmul(wB[2], x[1])));
        ty = jadd(jadd(jk(v[1]), jmul(jk(v[2]), jsub(x[0], J.r[0]))), jadd(vp[1], jmul(wB[2], x[0])));
        s = jadd(jmul(jsub(jk(0.0), n[1]), tx), jmul(n[0], ty));
        *sdd0 = s.c[1];
    }
    return ex_dot3(T, v) + *tb;
}
