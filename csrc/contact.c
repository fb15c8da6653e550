/* contact.c -- contact geometry of the object's outline against the stops
 * (contact.h): gaps, their derivatives with respect to the free coordinates
 * and time, and the rounding bound of a gap. */
#include "exdex.h"
#include "contact.h"
#include "pose.h"
#include "util.h"
#include "tolerances.h"

#include <float.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_poly.h>

int contact_vertices(const exdex_model *m, const double *q, double xb[][3], double vx[][3])
{
    double r[3], th, c, s;
    int nv = m->n_vert ? m->n_vert : 1;
    pose_com(m, q, r, &th);
    c = cos(th);
    s = sin(th);
    for (int j = 0; j < nv; j++) {
        double px = m->n_vert ? m->vert[j][0] : 0.0, py = m->n_vert ? m->vert[j][1] : 0.0;
        vx[j][0] = c * px - s * py;
        vx[j][1] = s * px + c * py;
        vx[j][2] = 0.0;
        xb[j][0] = r[0] + vx[j][0];
        xb[j][1] = r[1] + vx[j][1];
        xb[j][2] = 0.0;
    }
    return nv;
}

/* ------------------------------------------------------ disc outline
 * A disc of radius r about the centre x_c (the model's one vertex) against
 * the plane with unit normal n (A): its support point is x_c - r u, u =
 * n_B,xy / s the unit in-plane direction of n_B = R^T n, s = |n_B,xy|, so
 * the gap is the centre's plane gap less r s. The support point's
 * d gap / d qdot is the centre's (a turn about the centre moves the
 * support point along the rim, along the plane: u x u = 0), and s depends
 * on time only through the gripper's orientation:
 *     d n_B / dt = -R^T (w x n),  d^2 n_B / dt^2 = R^T (w x (w x n)) - R^T (dw x n),
 *     s' = u . n_B'_xy,  s'' = (|n_B'_xy|^2 + n_B,xy . n_B''_xy) / s - s'^2 / s.
 * A plane with s <= FQ_MIN faces the plate normal: no support point (shift 0). */
static void disc_shift(const exdex_kinematics *kin, const double n[3], double *s0, double *s1, double *s2)
{
    double nB[3], wn[3], wwn[3], dwn[3], d1[3], d2[3], a[3], s;
    ex_mulmtv3(nB, kin->R, n);
    s = hypot(nB[0], nB[1]);
    *s0 = *s1 = 0.0;
    if (s2) *s2 = 0.0;
    if (!(s > FQ_MIN)) return;
    *s0 = s;
    ex_cross3(wn, kin->w, n);
    ex_mulmtv3(d1, kin->R, wn);
    for (int i = 0; i < 3; i++) d1[i] = -d1[i];
    *s1 = (nB[0] * d1[0] + nB[1] * d1[1]) / s;
    if (!s2) return;
    ex_cross3(wwn, kin->w, wn);
    ex_cross3(dwn, kin->dw, n);
    for (int i = 0; i < 3; i++) a[i] = wwn[i] - dwn[i];
    ex_mulmtv3(d2, kin->R, a);
    *s2 = (d1[0] * d1[0] + d1[1] * d1[1] + nB[0] * d2[0] + nB[1] * d2[1]) / s - *s1 * *s1 / s;
}

/* The disc's support point against the plane of unit normal n (A) at pose
 * kin, from its centre xc (B) and the centre's offset vc from the centre of
 * mass: x_s = xc - r u, vs = vc - r u (unchanged when the plane faces the
 * plate normal). */
static void disc_support(const exdex_model *m, const exdex_kinematics *kin, const double n[3], const double xc[3],
                         const double vc[3], double xs[3], double vs[3])
{
    double nB[3], s;
    ex_mulmtv3(nB, kin->R, n);
    s = hypot(nB[0], nB[1]);
    memcpy(xs, xc, 3 * sizeof *xs);
    memcpy(vs, vc, 3 * sizeof *vs);
    if (!(s > FQ_MIN)) return;
    for (int i = 0; i < 2; i++) {
        xs[i] -= m->disc_r * nB[i] / s;
        vs[i] -= m->disc_r * nB[i] / s;
    }
}

/* Velocity xd and acceleration less the part in qdd, xdd, in B of the
 * material point at offset rv (B) from the centre of mass of a planar
 * object moving at v = (xd, yd, thd): xd = (vx, vy) + thd e_z x rv,
 * xdd = -thd^2 rv. */
static void point_rates(const double rv[2], const double v[3], double xd[3], double xdd[3])
{
    xd[0] = v[0] - rv[1] * v[2];
    xd[1] = v[1] + rv[0] * v[2];
    xd[2] = 0.0;
    xdd[0] = -rv[0] * v[2] * v[2];
    xdd[1] = -rv[1] * v[2] * v[2];
    xdd[2] = 0.0;
}

/* The generalised row of an in-plane direction d (B) at the material point
 * xb of the object (offset vx from the centre of mass): d . (d xb / d qdot).
 * Planar, columns d xb / dx, dy, dtheta = e_z x vx; translation, d along
 * the slide axis; rotation about the pivot, d xb / dtheta = e_z x (xb -
 * pivot). */
static void dir_row(const exdex_model *m, const double d[2], const double xb[3], const double vx[3], double out[3])
{
    if (m->ndof == 3) {
        out[0] = d[0];
        out[1] = d[1];
        out[2] = -d[0] * vx[1] + d[1] * vx[0];
    } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        out[0] = d[0] * m->d[0] + d[1] * m->d[1];
    } else {
        double ax = xb[0] - m->pivot[0], ay = xb[1] - m->pivot[1];
        out[0] = -d[0] * ay + d[1] * ax;
    }
}

/* Gap n.(R xb + p - sp) of the vertex at xb (offset vx from the centre of
 * mass) against the plane through sp with unit normal sn, both in A: a stop,
 * or an obstacle's face seen from outside. G as contact_gap. A disc outline:
 * xb is its centre and the gap its support point's (disc_shift). */
double contact_plane_gap(const exdex_model *m, const exdex_kinematics *kin, const double sp[3], const double sn[3],
                         const double xb[3], const double vx[3], double G[3])
{
    double xa[3], nB[3];
    ex_mulmv3(xa, kin->R, xb);
    for (int i = 0; i < 3; i++) xa[i] += kin->p[i] - sp[i];
    if (G) {
        ex_mulmtv3(nB, kin->R, sn);
        dir_row(m, nB, xb, vx, G);
    }
    if (m->disc_r > 0.0) {
        /* the disc's centre is the vertex xb: its support point's gap */
        double s0, s1;
        disc_shift(kin, sn, &s0, &s1, NULL);
        return ex_dot3(xa, sn) - m->disc_r * s0;
    }
    return ex_dot3(xa, sn);
}

double contact_gap(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3],
                   const double vx[3], double G[3])
{
    return contact_plane_gap(m, kin, m->sp[k], m->sn[k], xb, vx, G);
}

double contact_vertex_gap(const exdex_model *m, const exdex_kinematics *kin, int k, const double *q, int j,
                          double G[3])
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
    contact_vertices(m, q, xb, vx);
    return contact_gap(m, kin, k, xb[j], vx[j], G);
}

/* A gap within its own rounding of zero counts as exactly 0 (GAP_ROUND,
 * tolerances.h). */
double contact_gap_round(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3])
{
    return GAP_ROUND * (sqrt(ex_dot3(xb, xb)) + m->disc_r + sqrt(ex_dot3(kin->p, kin->p)) +
                        sqrt(ex_dot3(m->sp[k], m->sp[k])));
}

double contact_min_gap(const exdex_model *m, const exdex_kinematics *kin, const double *q)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], gmin = INFINITY;
    int nv;
    if (m->n_obst) {
        double G[MAX_ROWS][3], g[MAX_ROWS], rnd[MAX_ROWS];
        int no = contact_obstacle_rows(m, kin, q, G, g, rnd, NULL, NULL);
        for (int i = 0; i < no; i++)
            if (g[i] < gmin) gmin = g[i];
    }
    if (!m->n_stops) return gmin;
    nv = contact_vertices(m, q, xb, vx);
    for (int k = 0; k < m->n_stops; k++)
        for (int j = 0; j < nv; j++) {
            double gap = contact_gap(m, kin, k, xb[j], vx[j], NULL);
            if (gap < gmin) gmin = gap;
        }
    return gmin;
}

int contact_rows(const exdex_model *m, const exdex_kinematics *kin, const double *q, double (*G)[3],
                 double *gap, int *stop)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
    int nv = contact_vertices(m, q, xb, vx), nr = 0;
    for (int k = 0; k < m->n_stops; k++)
        for (int j = 0; j < nv; j++) {
            gap[nr] = contact_gap(m, kin, k, xb[j], vx[j], G[nr]);
            if (stop) stop[nr] = k;
            nr++;
        }
    return nr;
}

void contact_row_1dof(const exdex_model *m, const exdex_kinematics *k, int ks, int j, double q, crow *c)
{
    contact_plane_row_1dof(m, k, m->sp[ks], m->sn[ks], j, q, c);
}

void contact_plane_row_1dof(const exdex_model *m, const exdex_kinematics *k, const double sp[3], const double n[3],
                            int j, double q, crow *c)
{
    double xB[3] = {0, 0, 0}, x1[3] = {0, 0, 0}, x2[3] = {0, 0, 0};
    double Rx[3], R1[3], R2[3], wx[3], wwx[3], dwx[3], w1[3];
    double vert[2] = {0.0, 0.0};
    if (m->n_vert) {
        vert[0] = m->vert[j][0];
        vert[1] = m->vert[j][1];
    }
    if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        double vx[2];
        rot2(vx, m->th0, vert);
        xB[0] = m->r0[0] + (q - m->s0) * m->d[0] + vx[0];
        xB[1] = m->r0[1] + (q - m->s0) * m->d[1] + vx[1];
        x1[0] = m->d[0];
        x1[1] = m->d[1];
    } else {
        double rho[2] = {m->c[0] + vert[0], m->c[1] + vert[1]}, xr[2];
        rot2(xr, q, rho);
        xB[0] = m->pivot[0] + xr[0];
        xB[1] = m->pivot[1] + xr[1];
        x1[0] = -xr[1];
        x1[1] = xr[0];
        x2[0] = -xr[0];
        x2[1] = -xr[1];
    }
    ex_mulmv3(Rx, k->R, xB);
    ex_mulmv3(R1, k->R, x1);
    ex_mulmv3(R2, k->R, x2);
    c->F = n[0] * (Rx[0] + k->p[0] - sp[0]) + n[1] * (Rx[1] + k->p[1] - sp[1]) +
           n[2] * (Rx[2] + k->p[2] - sp[2]);
    c->Fq = ex_dot3(n, R1);
    c->Fqq = ex_dot3(n, R2);
    ex_cross3(wx, k->w, Rx);
    ex_cross3(wwx, k->w, wx);
    ex_cross3(dwx, k->dw, Rx);
    ex_cross3(w1, k->w, R1);
    c->Ft = ex_dot3(n, wx) + ex_dot3(n, k->v);
    c->Ftq = ex_dot3(n, w1);
    c->Ftt = ex_dot3(n, dwx) + ex_dot3(n, wwx) + ex_dot3(n, k->a);
    if (m->disc_r > 0.0) {
        /* the disc's support point: the centre's row less r s(t) */
        double s0, s1, s2;
        disc_shift(k, n, &s0, &s1, &s2);
        c->F -= m->disc_r * s0;
        c->Ft -= m->disc_r * s1;
        c->Ftt -= m->disc_r * s2;
    }
}

/* Smallest gap of stop k over the outline, and its vertex. */
double contact_stop_gap(const exdex_model *m, const exdex_kinematics *k, int ks, double q, int *jmin)
{
    int nv = m->n_vert ? m->n_vert : 1;
    double best = INFINITY;
    for (int j = 0; j < nv; j++) {
        double g = contact_vertex_gap(m, k, ks, &q, j, NULL);
        if (g < best) {
            best = g;
            if (jmin) *jmin = j;
        }
    }
    return best;
}

/* ------------------------------------------------ planar stop kinematics */

/* Row of vertex j against stop ks at planar coordinates q, velocity v and
 * gripper kinematics k (A coordinates): gap = n.(R x_B + p - p_stop), x_B =
 * (q_x, q_y) + Rz(q_th) rho_j; G = d gap / d qdot = (R^T n).J, J = [I, e_z x
 * Rz rho]; gd = d gap / dt = G v + n.(w x R x_B + pdot); and the
 * acceleration bias gdd0 = d^2 gap / dt^2 - G qdd
 *   = n.(R xdd0 + 2 w x R xd + dw x R x_B + w x (w x R x_B) + pddot),
 * xd = J v the vertex velocity in B, xdd0 = -Rz rho thd^2 (centripetal).
 * Returns the gap. */
double contact_row_planar(const exdex_model *m, const exdex_kinematics *k, int ks, int j, const double *q,
                          const double *v, double G[3], double *gd, double *gdd0)
{
    return contact_plane_row_planar_cs(m, k, m->sp[ks], m->sn[ks], j, q, NULL, v, G, gd, gdd0);
}

double contact_row_planar_cs(const exdex_model *m, const exdex_kinematics *k, int ks, int j, const double *q,
                             const double *cs, const double *v, double G[3], double *gd, double *gdd0)
{
    return contact_plane_row_planar_cs(m, k, m->sp[ks], m->sn[ks], j, q, cs, v, G, gd, gdd0);
}

double contact_plane_row_planar(const exdex_model *m, const exdex_kinematics *k, const double sp[3],
                                const double n[3], int j, const double *q, const double *v, double G[3], double *gd,
                                double *gdd0)
{
    return contact_plane_row_planar_cs(m, k, sp, n, j, q, NULL, v, G, gd, gdd0);
}

double contact_plane_row_planar_cs(const exdex_model *m, const exdex_kinematics *k, const double sp[3],
                                   const double n[3], int j, const double *q, const double *cs, const double *v,
                                   double G[3], double *gd, double *gdd0)
{
    double rv[2] = {0.0, 0.0}, xB[3], xd[3], xdd[3], Rx[3], Rxd[3], Rxdd[3], nB[3], a[3], b[3], c[3];
    double gap;
    if (m->n_vert) {
        if (cs) rot2_cs(rv, cs, m->vert[j]);
        else rot2(rv, q[2], m->vert[j]);
    }
    xB[0] = q[0] + rv[0];
    xB[1] = q[1] + rv[1];
    xB[2] = 0.0;
    ex_mulmv3(Rx, k->R, xB);
    gap = n[0] * (Rx[0] + k->p[0] - sp[0]) + n[1] * (Rx[1] + k->p[1] - sp[1]) +
          n[2] * (Rx[2] + k->p[2] - sp[2]);
    ex_mulmtv3(nB, k->R, n);
    G[0] = nB[0];
    G[1] = nB[1];
    G[2] = -nB[0] * rv[1] + nB[1] * rv[0];
    if (gd || gdd0) {
        point_rates(rv, v, xd, xdd);
        ex_mulmv3(Rxd, k->R, xd);
        ex_mulmv3(Rxdd, k->R, xdd);
        ex_cross3(a, k->w, Rx);
        if (gd) *gd = ex_dot3(G, v) + ex_dot3(n, a) + ex_dot3(n, k->v);
        if (gdd0) {
            double s = ex_dot3(n, Rxdd) + ex_dot3(n, k->a);
            ex_cross3(b, k->w, Rxd);
            s += 2.0 * ex_dot3(n, b);
            ex_cross3(c, k->dw, Rx);
            s += ex_dot3(n, c);
            ex_cross3(b, k->w, a);
            s += ex_dot3(n, b);
            *gdd0 = s;
        }
    }
    if (m->disc_r > 0.0) {
        /* the disc's support point: the centre's row less r s(t) */
        double s0, s1, s2;
        disc_shift(k, n, &s0, &s1, &s2);
        gap -= m->disc_r * s0;
        if (gd) *gd -= m->disc_r * s1;
        if (gdd0) *gdd0 -= m->disc_r * s2;
    }
    return gap;
}


/* Is some stop out of the object's reach at (t, q), its gap below -tol.pen
 * for every value of the free coordinates? Translation and planar: a row
 * that the free coordinates cannot move (|d gap / dq| <= tol.fq_min: the stop is
 * parallel to the slide line or faces the plate normal); rotation: the
 * vertex moves on a circle about the pivot, gap(q') = F + Fqq + Fq sin(q' -
 * q) - Fqq cos(q' - q) (contact_row's derivatives at q), whose maximum F +
 * Fqq + hypot(Fq, Fqq) is below -tol.pen (the stop has passed the pivot's
 * reach). Such a penetration is the scene's, not the method's. */
int contact_unreachable(const exdex_model *m, const exdex_kinematics *k, const double *q)
{
    int nv = m->n_vert ? m->n_vert : 1;
    if (!m->n_stops) return 0;
    for (int s = 0; s < m->n_stops; s++)
        for (int j = 0; j < nv; j++) {
            if (m->ndof == 3) {
                double G[3], g = contact_vertex_gap(m, k, s, q, j, G);
                if (g < -m->tol.pen && !(fabs(G[0]) + fabs(G[1]) + fabs(G[2]) > FQ_MIN)) return 1;
            } else {
                crow c;
                contact_row_1dof(m, k, s, j, q[0], &c);
                if (m->def.dof == EXDEX_DOF_TRANSLATION) {
                    if (c.F < -m->tol.pen && !(fabs(c.Fq) > m->tol.fq_min)) return 1;
                } else if (c.F + c.Fqq + hypot(c.Fq, c.Fqq) < -m->tol.pen) {
                    return 1;
                }
            }
        }
    return 0;
}

/* Largest distance of an outline vertex from the rotation centre (the
 * centre of mass for planar scenes, the pivot for rotation; 0 for
 * translation): bounds |d^2 gap / d theta^2|. */
double contact_rot_radius(const exdex_model *m)
{
    int nv = m->n_vert ? m->n_vert : 1;
    double r = 0.0;
    if (m->def.dof == EXDEX_DOF_TRANSLATION) return 0.0;
    for (int j = 0; j < nv; j++) {
        double x = m->n_vert ? m->vert[j][0] : 0.0, y = m->n_vert ? m->vert[j][1] : 0.0;
        if (m->def.dof == EXDEX_DOF_ROTATION) {
            x += m->c[0];
            y += m->c[1];
        }
        r = fmax(r, sqrt(x * x + y * y));
    }
    return r;
}

void contact_tangent(const exdex_model *m, const exdex_kinematics *kin, const double xb[3], const double vx[3],
                     const double nB_inplane[2], double T[3], double *tb)
{
    double nn = hypot(nB_inplane[0], nB_inplane[1]), t[3], tA[3], Rx[3], wx[3];
    T[0] = T[1] = T[2] = 0.0;
    *tb = 0.0;
    if (!(nn > FQ_MIN)) return;
    t[0] = -nB_inplane[1] / nn;
    t[1] = nB_inplane[0] / nn;
    t[2] = 0.0;
    dir_row(m, t, xb, vx, T);
    ex_mulmv3(tA, kin->R, t);
    ex_mulmv3(Rx, kin->R, xb);
    ex_cross3(wx, kin->w, Rx);
    *tb = tA[0] * (kin->v[0] + wx[0]) + tA[1] * (kin->v[1] + wx[1]) + tA[2] * (kin->v[2] + wx[2]);
}

void contact_stop_tangent(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3],
                          const double vx[3], double T[3], double *tb)
{
    contact_plane_tangent(m, kin, m->sn[k], xb, vx, T, tb);
}

void contact_plane_tangent(const exdex_model *m, const exdex_kinematics *kin, const double n[3], const double xb[3],
                           const double vx[3], double T[3], double *tb)
{
    double nB[3];
    ex_mulmtv3(nB, kin->R, n);
    if (m->disc_r > 0.0) {
        /* a disc (xb its centre) slips at its support point */
        double xs[3], vs[3];
        disc_support(m, kin, n, xb, vx, xs, vs);
        contact_tangent(m, kin, xs, vs, nB, T, tb);
        return;
    }
    contact_tangent(m, kin, xb, vx, nB, T, tb);
}

/* ------------------------------------------------------ convex obstacles */

/* d gap / d qdot of a row whose gap changes by nB . dx when the object's
 * material point at x (B) moves by dx (nB in B, its z ignored): the columns
 * of dx / dqdot as in contact_plane_gap. */
static void row_G(const exdex_model *m, const double *q, const double x[3], const double nB[3], double G[3])
{
    if (m->ndof == 3) {
        double rx = x[0] - q[0], ry = x[1] - q[1];
        G[0] = nB[0];
        G[1] = nB[1];
        G[2] = -nB[0] * ry + nB[1] * rx;
    } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        G[0] = nB[0] * m->d[0] + nB[1] * m->d[1];
    } else {
        double ax = x[0] - m->pivot[0], ay = x[1] - m->pivot[1];
        G[0] = -nB[0] * ay + nB[1] * ax;
    }
}

int contact_hull(const double (*v)[2], int n, double (*hull)[2])
{
    /* Andrew's monotone chain on the points sorted by (x, y); at most
     * EXDEX_MAX_VERTICES points, insertion sort. */
    double p[EXDEX_MAX_VERTICES][2];
    int k = 0;
    if (n <= 0) {
        hull[0][0] = hull[0][1] = 0.0;
        return 1;
    }
    for (int i = 0; i < n; i++) {
        int j = i;
        while (j > 0 && (p[j - 1][0] > v[i][0] || (p[j - 1][0] == v[i][0] && p[j - 1][1] > v[i][1]))) {
            p[j][0] = p[j - 1][0];
            p[j][1] = p[j - 1][1];
            j--;
        }
        p[j][0] = v[i][0];
        p[j][1] = v[i][1];
    }
    for (int pass = 0; pass < 2; pass++) {
        int start = k;
        for (int ii = 0; ii < n; ii++) {
            int i = pass ? n - 1 - ii : ii;
            while (k >= start + 2) {
                double ax = hull[k - 1][0] - hull[k - 2][0], ay = hull[k - 1][1] - hull[k - 2][1];
                double bx = p[i][0] - hull[k - 2][0], by = p[i][1] - hull[k - 2][1];
                if (ax * by - ay * bx > 0.0) break;
                k--;
            }
            hull[k][0] = p[i][0];
            hull[k][1] = p[i][1];
            k++;
        }
        k--;  /* the last point of each chain starts the other */
    }
    if (k < 1) k = 1;
    /* all points equal: one point; collinear: the two ends */
    if (k == 2 && hull[0][0] == hull[1][0] && hull[0][1] == hull[1][1]) k = 1;
    return k;
}

int contact_halfplanes(const exdex_obstacle_def *o, const double R[9], const double p[3], double a[][2], double *b,
                       int *idx, int *empty)
{
    int k = 0;
    *empty = 0;
    for (int f = 0; f < o->n_faces; f++) {
        double nB[3], d[3];
        ex_mulmtv3(nB, R, o->face_normal[f]);
        for (int i = 0; i < 3; i++) d[i] = o->face_point[f][i] - p[i];
        double bf = ex_dot3(o->face_normal[f], d), na = hypot(nB[0], nB[1]);
        if (!(na > 1e-12)) {
            if (bf < 0.0) *empty = 1;
            continue;
        }
        a[k][0] = nB[0];
        a[k][1] = nB[1];
        b[k] = bf;
        if (idx) idx[k] = f;
        k++;
    }
    return k;
}

int contact_farthest_line(int n, const double (*a)[2], const double *b, const double xc[3], double *db, int *on)
{
    int fb = -1;
    *db = -INFINITY;
    for (int k = 0; k < n; k++) {
        double dd = (a[k][0] * xc[0] + a[k][1] * xc[1] - b[k]) / hypot(a[k][0], a[k][1]);
        if (dd > *db) {
            *db = dd;
            fb = k;
        }
    }
    *on = 1;
    if (fb >= 0 && *db > 0.0) {
        double na = hypot(a[fb][0], a[fb][1]), y[2] = {xc[0] - *db * a[fb][0] / na, xc[1] - *db * a[fb][1] / na};
        double sc = hypot(y[0], y[1]);
        for (int h = 0; h < n; h++) {
            if (h == fb) continue;
            if (a[h][0] * y[0] + a[h][1] * y[1] - b[h] > 1e-12 * (hypot(a[h][0], a[h][1]) * sc + fabs(b[h])))
                *on = 0;
        }
    }
    return fb;
}

void contact_rod_axis(const exdex_obstacle_def *o, const double R[9], const double p[3], double cB[3], double aB[3])
{
    double d[3];
    for (int i = 0; i < 3; i++) d[i] = o->center[i] - p[i];
    ex_mulmtv3(cB, R, d);
    ex_mulmtv3(aB, R, o->axis);
}

int contact_section_vertices(int n, const double (*a)[2], const double *b, double ys[][2], int fg[][2])
{
    int ny = 0;
    for (int f = 0; f < n; f++)
        for (int g = f + 1; g < n; g++) {
            double det = a[f][0] * a[g][1] - a[f][1] * a[g][0], y[2], sc;
            int ok = 1;
            if (!(fabs(det) > 1e-12 * hypot(a[f][0], a[f][1]) * hypot(a[g][0], a[g][1]))) continue;
            y[0] = (b[f] * a[g][1] - b[g] * a[f][1]) / det;
            y[1] = (a[f][0] * b[g] - a[g][0] * b[f]) / det;
            sc = hypot(y[0], y[1]);
            for (int h = 0; ok && h < n; h++) {
                if (h == f || h == g) continue;
                if (a[h][0] * y[0] + a[h][1] * y[1] - b[h] > 1e-12 * (hypot(a[h][0], a[h][1]) * sc + fabs(b[h])))
                    ok = 0;
            }
            for (int i = 0; ok && i < ny; i++)
                if (hypot(ys[i][0] - y[0], ys[i][1] - y[1]) <= 1e-10 * (sc + hypot(ys[i][0], ys[i][1]))) ok = 0;
            if (!ok || ny >= EXDEX_MAX_FACES) continue;
            ys[ny][0] = y[0];
            ys[ny][1] = y[1];
            if (fg) {
                fg[ny][0] = f;
                fg[ny][1] = g;
            }
            ny++;
        }
    return ny;
}

/* The n points xy in counter-clockwise order about their mean (insertion
 * by angle, equal angles kept in their order). */
static void sort_ccw(int n, double xy[][2])
{
    double ang[EXDEX_MAX_FACES], cx = 0.0, cy = 0.0;
    for (int i = 0; i < n; i++) {
        cx += xy[i][0] / n;
        cy += xy[i][1] / n;
    }
    for (int i = 0; i < n; i++) {
        double x0 = xy[i][0], y0 = xy[i][1], t = atan2(y0 - cy, x0 - cx);
        int j = i;
        while (j > 0 && ang[j - 1] > t) {
            ang[j] = ang[j - 1];
            xy[j][0] = xy[j - 1][0];
            xy[j][1] = xy[j - 1][1];
            j--;
        }
        ang[j] = t;
        xy[j][0] = x0;
        xy[j][1] = y0;
    }
}

int contact_obstacle_valid(const exdex_obstacle_def *o)
{
    if (!o || !(isfinite(o->mu) && o->mu >= 0.0)) return 0;
    if (o->kind == EXDEX_OBSTACLE_POLYTOPE) {
        if (o->n_faces < 1 || o->n_faces > EXDEX_MAX_FACES) return 0;
        for (int f = 0; f < o->n_faces; f++)
            if (!ex_finite_n(o->face_point[f], 3) || !ex_finite_n(o->face_normal[f], 3) ||
                fabs(sqrt(ex_dot3(o->face_normal[f], o->face_normal[f])) - 1.0) > 1e-9)
                return 0;
        return 1;
    }
    if (o->kind == EXDEX_OBSTACLE_CYLINDER)
        return ex_finite_n(o->center, 3) && ex_finite_n(o->axis, 3) &&
               fabs(sqrt(ex_dot3(o->axis, o->axis)) - 1.0) <= 1e-9 && isfinite(o->radius) && o->radius > 0.0;
    return 0;
}

int exdex_obstacle_section(const exdex_obstacle_def *o, const double R[9], const double p[3],
                           double xy[EXDEX_MAX_FACES][2], double ab[3])
{
    if (!contact_obstacle_valid(o) || !R || !p || !xy || !ex_finite_n(R, 9) || !ex_finite_n(p, 3))
        return -EXDEX_EINVAL;
    if (o->kind == EXDEX_OBSTACLE_POLYTOPE) {
        double a[EXDEX_MAX_FACES][2], b[EXDEX_MAX_FACES];
        int empty, nh = contact_halfplanes(o, R, p, a, b, NULL, &empty);
        int ny = empty ? 0 : contact_section_vertices(nh, (const double (*)[2])a, b, xy, NULL);
        sort_ccw(ny, xy);
        return ny;
    } else {
        double cB[3], aB[3];
        if (!ab) return -EXDEX_EINVAL;
        contact_rod_axis(o, R, p, cB, aB);
        if (!(fabs(aB[2]) > 1e-12)) return 0;
        xy[0][0] = cB[0] - cB[2] / aB[2] * aB[0];
        xy[0][1] = cB[1] - cB[2] / aB[2] * aB[1];
        /* points y of the plane at distance r from the axis: |y|^2 - (y.a)^2
         * = r^2 (y from the centre), semi-axes r / |a_z| along a_xy, r across */
        ab[0] = o->radius / fabs(aB[2]);
        ab[1] = o->radius;
        ab[2] = (aB[0] == 0.0 && aB[1] == 0.0) ? 0.0 : atan2(aB[1], aB[0]);
        return 1;
    }
}

int contact_axis_in_hull(int nh, const double hb[][3], const double cB[3], const double aB[3])
{
    double c0[2] = {cB[0] - cB[2] / aB[2] * aB[0], cB[1] - cB[2] / aB[2] * aB[1]};
    for (int e = 0; e < nh; e++) {
        const double *u = hb[e], *v = hb[(e + 1) % nh];
        if ((v[0] - u[0]) * (c0[1] - u[1]) - (v[1] - u[1]) * (c0[0] - u[0]) <= 0.0) return 0;
    }
    return 1;
}

int contact_hull_b(const exdex_model *m, const double *q, double hb[][3])
{
    double r[3], th, c, s;
    pose_com(m, q, r, &th);
    c = cos(th);
    s = sin(th);
    for (int i = 0; i < m->n_hull; i++) {
        hb[i][0] = r[0] + c * m->hull[i][0] - s * m->hull[i][1];
        hb[i][1] = r[1] + s * m->hull[i][0] + c * m->hull[i][1];
        hb[i][2] = 0.0;
    }
    return m->n_hull;
}

/* Squared distance from the rod's axis (through cB along unit aB, in B) of
 * the point x of the plate plane, and that offset w (perpendicular to the
 * axis). */
static double axis_dist2(const double cB[3], const double aB[3], const double x[3], double w[3])
{
    double d[3] = {x[0] - cB[0], x[1] - cB[1], x[2] - cB[2]}, t = ex_dot3(d, aB);
    for (int i = 0; i < 3; i++) w[i] = d[i] - t * aB[i];
    return ex_dot3(w, w);
}

void contact_set_point(contact_point *cp, const double x[3], const double r[3], const double nB[3])
{
    if (!cp) return;
    for (int i = 0; i < 3; i++) {
        cp->x[i] = x[i];
        cp->vx[i] = x[i] - r[i];
        cp->nB[i] = nB[i];
    }
    cp->x[2] = cp->vx[2] = 0.0;
}

/* The unit vector u minimising g(u) = 2 r b . u - r^2 (u . a)^2 over the
 * unit circle (a, b plane vectors, r > 0). In the frame of e1 = a / |a|
 * (alpha = |a|), u = (cos phi, sin phi), b = (b1, b2): g' = 0 is
 *     -b1 sin phi + b2 cos phi + r alpha^2 sin phi cos phi = 0,
 * with t = tan(phi / 2) the quartic
 *     -b2 t^4 - 2 (b1 + r alpha^2) t^3 + 2 (r alpha^2 - b1) t + b2 = 0
 * (GSL gsl_poly_complex_solve); phi = pi (t infinite) is a candidate too.
 * The global minimum is one of the stationary points, so the candidate with
 * the least g is it (the real parts of complex roots are extra candidates
 * that can only lose); two guarded Newton steps on g' polish it. */
static void circle_min(const double a[2], const double b[2], double r, double u[2])
{
    double alpha = hypot(a[0], a[1]), e1[2], b1, b2, k, c[5], z[8], best_phi = EXDEX_PI, best;
    int deg = 4;
    if (alpha > 0.0) {
        e1[0] = a[0] / alpha;
        e1[1] = a[1] / alpha;
    } else {
        e1[0] = 1.0;
        e1[1] = 0.0;
    }
    b1 = b[0] * e1[0] + b[1] * e1[1];
    b2 = -b[0] * e1[1] + b[1] * e1[0];
    k = r * alpha * alpha;
#define GPHI(ph) (2.0 * (b1 * cos(ph) + b2 * sin(ph)) - k * cos(ph) * cos(ph))
    best = GPHI(EXDEX_PI);
    c[0] = b2;
    c[1] = 2.0 * (k - b1);
    c[2] = 0.0;
    c[3] = -2.0 * (b1 + k);
    c[4] = -b2;
    {
        double sc = fabs(b1) + fabs(b2) + fabs(k);
        while (deg > 0 && !(fabs(c[deg]) > 1e-14 * sc)) deg--;
    }
    if (deg >= 1) {
        gsl_poly_complex_workspace *ws = gsl_poly_complex_workspace_alloc((size_t)deg + 1);
        int ok = ws && gsl_poly_complex_solve(c, (size_t)deg + 1, ws, z) == GSL_SUCCESS;
        if (ws) gsl_poly_complex_workspace_free(ws);
        for (int i = 0; ok && i < deg; i++) {
            double ph = 2.0 * atan(z[2 * i]), g = GPHI(ph);
            if (g < best) {
                best = g;
                best_phi = ph;
            }
        }
        if (!ok) {
            /* no roots: the candidates of a coarse scan */
            for (int i = 0; i < 64; i++) {
                double ph = -EXDEX_PI + 2.0 * EXDEX_PI * i / 64.0, g = GPHI(ph);
                if (g < best) {
                    best = g;
                    best_phi = ph;
                }
            }
        }
    }
    for (int it = 0; it < 2; it++) {
        double sn = sin(best_phi), cs = cos(best_phi);
        double d1 = 2.0 * (-b1 * sn + b2 * cs) + 2.0 * k * cs * sn;
        double d2 = 2.0 * (-b1 * cs - b2 * sn) + 2.0 * k * (cs * cs - sn * sn);
        double ph, g;
        if (!(d2 > 0.0)) break;
        ph = best_phi - d1 / d2;
        g = GPHI(ph);
        if (!(g <= best)) break;
        best = g;
        best_phi = ph;
    }
#undef GPHI
    u[0] = cos(best_phi) * e1[0] - sin(best_phi) * e1[1];
    u[1] = cos(best_phi) * e1[1] + sin(best_phi) * e1[0];
}

void contact_circle_min(const double a[2], const double b[2], double r, double u[2])
{
    circle_min(a, b, r, u);
}

/* The largest distance of a polytope's face points from the origin of A
 * (a term of the rounding bounds). */
static double face_point_max(const exdex_obstacle_def *ob)
{
    double fmax = 0.0;
    for (int f = 0; f < ob->n_faces; f++)
        fmax = fmax > sqrt(ex_dot3(ob->face_point[f], ob->face_point[f]))
                   ? fmax : sqrt(ex_dot3(ob->face_point[f], ob->face_point[f]));
    return fmax;
}

/* The tie rule of contact_obstacle_build among the n pieces of one row:
 * distances g_i, rows Gi_i (read by the step rule only), features ft_i
 * (read by the rate rule only); best is the first piece of the largest
 * distance. */
static int tie_pick(const exdex_model *m, const exdex_kinematics *kin, const double *q, const contact_obuild *opt,
                    int n, const double *g, const double (*Gi)[3], const contact_feature *ft, int best)
{
    if (!opt) return best;
    if (opt->vp) {
        /* step rule: the largest predicted distance g_i + h Gi_i . vp, the first of equal ones */
        double pb = -INFINITY;
        int pick = best;
        for (int i = 0; i < n; i++) {
            double pr = g[i];
            for (int d = 0; d < m->ndof; d++) pr += opt->h * Gi[i][d] * opt->vp[d];
            if (pr > pb) {
                pb = pr;
                pick = i;
            }
        }
        return pick;
    }
    if (opt->rate && opt->v) {
        /* rate rule: among the pieces within tol.touch of the largest, the
         * one of the largest rate (the first of equal ones) */
        double rb = -INFINITY;
        int pick = best, ties = 0;
        for (int i = 0; i < n; i++) ties += g[i] >= g[best] - m->tol.touch;
        if (ties < 2) return best;
        for (int i = 0; i < n; i++) {
            double r;
            if (!(g[i] >= g[best] - m->tol.touch)) continue;
            r = opt->rate(m, kin, &ft[i], q, opt->v);
            if (r > rb) {
                rb = r;
                pick = i;
            }
        }
        return pick;
    }
    return best;
}

static contact_feature feature(int o, int kind, int a, int b, int feat)
{
    contact_feature f = {o, kind, a, b, feat};
    return f;
}

/* The one row of a disc outline (centre xc in B, offset vc from the centre
 * of mass rc) against obstacle o (contact.h). Polytope: the disc's
 * distance from the section less the radius: while the centre's nearest
 * point of the section lies on a face line (or the centre is inside), that
 * face's plane row (plane_gap, the support point's gap; planar: as
 * contact_plane_row_planar); else the nearest section vertex y (the first
 * of equal distances in contact_section_vertices' order): |xc - y| - r
 * along (xc - y) / |xc - y|. Rod: the rim point xc + r u nearest the axis
 * (u the minimiser of circle_min in the metric of the distance from the
 * axis), its distance from the axis less the rod's radius, negative when
 * the axis meets the plane inside the disc. Returns the gap; need = 0 (no
 * gap, G, round or cp wanted) decides the feature alone (and returns 0). */
static double disc_obstacle_row(const exdex_model *m, const exdex_kinematics *kin, const double *q, int o,
                                int planar, int need, const double xc[3], const double vc[3], const double rc[3],
                                double G[3], double *round, contact_point *cp, contact_feature *ft)
{
    const exdex_obstacle_def *ob = &m->def.obstacles[o];
    double pn = sqrt(ex_dot3(kin->p, kin->p)), r = m->disc_r, gap;
    if (ob->kind == EXDEX_OBSTACLE_POLYTOPE) {
        double a[EXDEX_MAX_FACES][2], b[EXDEX_MAX_FACES], db;
        int face[EXDEX_MAX_FACES], empty, on, nh = contact_halfplanes(ob, kin->R, kin->p, a, b, face, &empty), best;
        int fb = contact_farthest_line(nh, (const double (*)[2])a, b, xc, &db, &on);
        if (!(empty || on)) {
            /* the nearest section vertex */
            double y[EXDEX_MAX_FACES][2], dmin = INFINITY;
            int fg[EXDEX_MAX_FACES][2], ny = contact_section_vertices(nh, (const double (*)[2])a, b, y, fg), ib = 0;
            for (int i = 0; i < ny; i++) {
                double dd = hypot(xc[0] - y[i][0], xc[1] - y[i][1]);
                if (dd < dmin) {
                    dmin = dd;
                    ib = i;
                }
            }
            if (ny > 0) {
                double nb[3] = {0, 0, 0}, x[3];
                *ft = feature(o, OROW_SECTION, face[fg[ib][0]], face[fg[ib][1]], 0);
                if (!need) return 0.0;
                if (dmin > 0.0) {
                    nb[0] = (xc[0] - y[ib][0]) / dmin;
                    nb[1] = (xc[1] - y[ib][1]) / dmin;
                } else {
                    double na = hypot(a[fb][0], a[fb][1]);
                    nb[0] = a[fb][0] / na;
                    nb[1] = a[fb][1] / na;
                }
                gap = dmin - r;
                x[0] = xc[0] - r * nb[0];
                x[1] = xc[1] - r * nb[1];
                x[2] = 0.0;
                if (G) row_G(m, q, x, nb, G);
                contact_set_point(cp, x, rc, nb);
                *round = 64.0 * DBL_EPSILON * (hypot(xc[0], xc[1]) + r + pn + face_point_max(ob));
                return gap;
            }
        }
        /* a face row: the face of the farthest line, or the largest face
         * distance (as an outline vertex's) when the centre is inside */
        if (!empty && fb >= 0 && db > 0.0) {
            best = face[fb];
        } else {
            double gb = -INFINITY;
            best = 0;
            for (int f = 0; f < ob->n_faces; f++) {
                double g = contact_plane_gap(m, kin, ob->face_point[f], ob->face_normal[f], xc, vc, NULL);
                if (g > gb) {
                    gb = g;
                    best = f;
                }
            }
        }
        *ft = feature(o, OROW_VERTEX, 0, 0, best);
        if (!need) return 0.0;
        if (planar) {
            double zero[3] = {0, 0, 0}, Gp[3];
            gap = contact_plane_row_planar(m, kin, ob->face_point[best], ob->face_normal[best], 0, q, zero, Gp, NULL,
                                           NULL);
            if (G) memcpy(G, Gp, sizeof Gp);
        } else {
            gap = contact_plane_gap(m, kin, ob->face_point[best], ob->face_normal[best], xc, vc, G);
        }
        *round = GAP_ROUND * (sqrt(ex_dot3(xc, xc)) + r + pn +
                              sqrt(ex_dot3(ob->face_point[best], ob->face_point[best])));
        if (cp) {
            double xs[3], vs[3];
            disc_support(m, kin, ob->face_normal[best], xc, vc, xs, vs);
            memcpy(cp->x, xs, sizeof cp->x);
            memcpy(cp->vx, vs, sizeof cp->vx);
            ex_mulmtv3(cp->nB, kin->R, ob->face_normal[best]);
        }
        return gap;
    } else {
        double cB[3], aB[3], w[3], bvec[2], u[2], x[3], nb[3], dist;
        int inside = 0;
        *ft = feature(o, OROW_ROD, 0, 0, 0);
        if (!need) return 0.0;
        contact_rod_axis(ob, kin->R, kin->p, cB, aB);
        if (fabs(aB[2]) > 1e-12) {
            double c0[2] = {cB[0] - cB[2] / aB[2] * aB[0], cB[1] - cB[2] / aB[2] * aB[1]};
            inside = hypot(xc[0] - c0[0], xc[1] - c0[1]) < r;
        }
        /* |P (x - cB)|^2 over the rim x = xc + r u: P z0 the centre's offset
         * from the axis, b its in-plane part */
        axis_dist2(cB, aB, xc, w);
        bvec[0] = w[0];
        bvec[1] = w[1];
        circle_min(aB, bvec, r, u);
        x[0] = xc[0] + r * u[0];
        x[1] = xc[1] + r * u[1];
        x[2] = 0.0;
        dist = sqrt(axis_dist2(cB, aB, x, w));
        if (dist > 0.0) {
            for (int i = 0; i < 3; i++) nb[i] = (inside ? -w[i] : w[i]) / dist;
        } else {
            nb[0] = -u[0];
            nb[1] = -u[1];
            nb[2] = 0.0;
        }
        gap = (inside ? -dist : dist) - ob->radius;
        if (G) row_G(m, q, x, nb, G);
        contact_set_point(cp, x, rc, nb);
        *round = 64.0 * DBL_EPSILON * (hypot(x[0], x[1]) + r + pn + sqrt(ex_dot3(ob->center, ob->center)) +
                                       ob->radius);
        return gap;
    }
}

static inline double rod_foot(int nh, const double hb[][3], const double cB[3], const double aB[3], int e,
                              double *len)
{
    const double *u = hb[e], *v = hb[(e + 1) % nh];
    double du[3] = {v[0] - u[0], v[1] - u[1], 0.0}, d[3] = {u[0] - cB[0], u[1] - cB[1], -cB[2]}, w[3], dd[3];
    double t = ex_dot3(d, aB), ta = ex_dot3(du, aB);
    for (int i = 0; i < 3; i++) {
        w[i] = d[i] - t * aB[i];
        dd[i] = du[i] - ta * aB[i];
    }
    *len = sqrt(ex_dot3(dd, dd));
    return *len > 0.0 ? -ex_dot3(w, dd) / ex_dot3(dd, dd) : 0.0;
}

double contact_rod_foot(int nh, const double hb[][3], const double cB[3], const double aB[3], int e, double *len)
{
    return rod_foot(nh, hb, cB, aB, e, len);
}

int contact_obstacle_build(const exdex_model *m, const exdex_kinematics *kin, const double *q,
                           const contact_obuild *opt, double (*G)[3], double *gap, double *round, int *src,
                           contact_point *cp, contact_feature *ft)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], hb[EXDEX_MAX_VERTICES][3];
    double pn = round ? sqrt(ex_dot3(kin->p, kin->p)) : 0.0, rc[3] = {0, 0, 0}, thc;
    int nv = contact_vertices(m, q, xb, vx), nh = contact_hull_b(m, q, hb), nr = 0;
    int step = opt && opt->vp, planar = opt && opt->planar, rate = opt && !opt->vp && opt->rate && opt->v;
    int need = gap || G || round || cp;
    if (cp) pose_com(m, q, rc, &thc);
    for (int o = 0; o < m->n_obst; o++) {
        const exdex_obstacle_def *ob = &m->def.obstacles[o];
        double rnd = 0.0;
        contact_feature f0;
        if (m->disc_r > 0.0) {
            double gv = disc_obstacle_row(m, kin, q, o, planar, need, xb[0], vx[0], rc, G ? G[nr] : NULL, &rnd,
                                          cp ? &cp[nr] : NULL, &f0);
            if (gap) gap[nr] = gv;
            if (round) round[nr] = rnd;
            if (ft) ft[nr] = f0;
            if (src) src[nr] = m->n_stops + o;
            nr++;
            continue;
        }
        if (ob->kind == EXDEX_OBSTACLE_POLYTOPE) {
            double a[EXDEX_MAX_FACES][2], b[EXDEX_MAX_FACES], y[EXDEX_MAX_FACES][2];
            double fmax = round ? face_point_max(ob) : 0.0;
            int idx[EXDEX_MAX_FACES], fg[EXDEX_MAX_FACES][2], empty, nhp, ny;
            /* outline vertex j against the solid: its largest face distance */
            for (int j = 0; j < nv; j++) {
                int best = 0;
                double gb = -INFINITY, gf[EXDEX_MAX_FACES], Gf[EXDEX_MAX_FACES][3];
                contact_feature cf[EXDEX_MAX_FACES];
                for (int f = 0; f < ob->n_faces; f++) {
                    double g = contact_plane_gap(m, kin, ob->face_point[f], ob->face_normal[f], xb[j], vx[j],
                                                 step ? Gf[f] : NULL);
                    gf[f] = g;
                    if (rate) cf[f] = feature(o, OROW_VERTEX, j, 0, f);
                    if (g > gb) {
                        gb = g;
                        best = f;
                    }
                }
                best = tie_pick(m, kin, q, opt, ob->n_faces, gf, (const double (*)[3])Gf, cf, best);
                if (planar && (gap || G)) {
                    double zero[3] = {0, 0, 0}, Gp[3];
                    double gv = contact_plane_row_planar(m, kin, ob->face_point[best], ob->face_normal[best], j, q,
                                                         zero, Gp, NULL, NULL);
                    if (gap) gap[nr] = gv;
                    if (G) memcpy(G[nr], Gp, sizeof Gp);
                } else if (G) {
                    double gv = contact_plane_gap(m, kin, ob->face_point[best], ob->face_normal[best], xb[j], vx[j],
                                                  G[nr]);
                    if (gap) gap[nr] = gv;
                } else if (gap) {
                    gap[nr] = gf[best];
                }
                if (round)
                    round[nr] = GAP_ROUND * (sqrt(ex_dot3(xb[j], xb[j])) + pn +
                                             sqrt(ex_dot3(ob->face_point[best], ob->face_point[best])));
                if (cp) {
                    /* as a stop's row: the vertex and its offset as contact_vertices gives them */
                    memcpy(cp[nr].x, xb[j], sizeof cp[nr].x);
                    memcpy(cp[nr].vx, vx[j], sizeof cp[nr].vx);
                    ex_mulmtv3(cp[nr].nB, kin->R, ob->face_normal[best]);
                }
                if (ft) ft[nr] = feature(o, OROW_VERTEX, j, 0, best);
                if (src) src[nr] = m->n_stops + o;
                nr++;
            }
            /* section vertex i against the outline's hull: its largest
             * distance outside the hull's edge lines */
            if (nh < 3) continue;
            nhp = contact_halfplanes(ob, kin->R, kin->p, a, b, idx, &empty);
            if (empty) continue;
            ny = contact_section_vertices(nhp, (const double (*)[2])a, b, y, fg);
            for (int i = 0; i < ny; i++) {
                double gb = -INFINITY, nb[3] = {0, 0, 0}, x[3] = {y[i][0], y[i][1], 0.0};
                double ge[EXDEX_MAX_VERTICES], Ge[EXDEX_MAX_VERTICES][3];
                contact_feature ce[EXDEX_MAX_VERTICES];
                int eb = -1, ne_n = 0, fa = idx[fg[i][0]], fc = idx[fg[i][1]], eidx[EXDEX_MAX_VERTICES];
                for (int e = 0; e < nh; e++) {
                    const double *u = hb[e], *v = hb[(e + 1) % nh];
                    double ex = v[0] - u[0], ey = v[1] - u[1], len = hypot(ex, ey), n0, n1, g;
                    if (!(len > 0.0)) continue;
                    n0 = ey / len; /* outward normal of a counter-clockwise edge */
                    n1 = -ex / len;
                    g = n0 * (x[0] - u[0]) + n1 * (x[1] - u[1]);
                    ge[ne_n] = g;
                    eidx[ne_n] = e;
                    if (rate) ce[ne_n] = feature(o, OROW_SECTION, fa, fc, e);
                    if (step) {
                        double ni[3] = {-n0, -n1, 0.0};
                        row_G(m, q, x, ni, Ge[ne_n]);
                    }
                    if (g > gb) {
                        gb = g;
                        eb = ne_n;
                    }
                    ne_n++;
                }
                f0 = feature(o, OROW_SECTION, fa, fc, 0);
                if (eb >= 0) {
                    eb = tie_pick(m, kin, q, opt, ne_n, ge, (const double (*)[3])Ge, ce, eb);
                    gb = ge[eb];
                    f0.feat = eidx[eb];
                    if (G || cp) {
                        /* the picked edge's inward normal, as in the loop */
                        const double *u = hb[f0.feat], *v = hb[(f0.feat + 1) % nh];
                        double ex = v[0] - u[0], ey = v[1] - u[1], len = hypot(ex, ey);
                        nb[0] = -(ey / len);
                        nb[1] = -(-ex / len);
                    }
                }
                if (gap) gap[nr] = gb;
                if (G) row_G(m, q, x, nb, G[nr]);
                contact_set_point(cp ? &cp[nr] : NULL, x, rc, nb);
                if (round) round[nr] = 64.0 * DBL_EPSILON * (hypot(x[0], x[1]) + hypot(hb[0][0], hb[0][1]) + pn + fmax);
                if (ft) ft[nr] = f0;
                if (src) src[nr] = m->n_stops + o;
                nr++;
            }
        } else {
            /* the rod against the hull: the hull point nearest the axis */
            double cB[3], aB[3], best = INFINITY, xs[3] = {0, 0, 0}, ws[3] = {0, 0, 0}, nb[3], dist;
            int inside = nh >= 3, ebest = 0, feat = 0;
            contact_rod_axis(ob, kin->R, kin->p, cB, aB);
            for (int e = 0; e < nh; e++) {
                const double *u = hb[e], *v = hb[(e + 1) % nh];
                double w[3], du[3] = {v[0] - u[0], v[1] - u[1], 0.0}, len, t = 0.0, x[3], d2;
                if (nh > 1) {
                    t = rod_foot(nh, (const double (*)[3])hb, cB, aB, e, &len);
                    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
                }
                for (int i = 0; i < 3; i++) x[i] = u[i] + t * du[i];
                d2 = axis_dist2(cB, aB, x, w);
                if (d2 < best) {
                    best = d2;
                    ebest = e;
                    feat = t == 0.0 ? e : t == 1.0 ? (e + 1) % nh : 32 + e;
                    memcpy(xs, x, sizeof xs);
                    memcpy(ws, w, sizeof ws);
                }
            }
            if (feat < 32 && nh > 1) {
                /* at a vertex: an adjacent edge whose foot lies inside it is
                 * the feature (the distances differ there only at second
                 * order, the feet at first: the choice agrees with
                 * orow_feature_guard's sign); the point stays the vertex */
                int k = feat, ep = (k + nh - 1) % nh;
                double lp, ln, tp = rod_foot(nh, (const double (*)[3])hb, cB, aB, ep, &lp);
                double tn = rod_foot(nh, (const double (*)[3])hb, cB, aB, k, &ln);
                if (lp > 0.0 && tp < 1.0)
                    feat = 32 + ep;
                else if (ln > 0.0 && tn > 0.0)
                    feat = 32 + k;
            }
            if (ft) ft[nr] = feature(o, OROW_ROD, 0, 0, feat);
            if (src) src[nr] = m->n_stops + o;
            if (!need) {
                nr++;
                continue;
            }
            if (inside && fabs(aB[2]) > 1e-12) {
                /* the axis meets the plane at c0: inside the hull? */
                inside = contact_axis_in_hull(nh, (const double (*)[3])hb, cB, aB);
            } else {
                inside = 0;
            }
            dist = sqrt(best);
            if (dist > 0.0) {
                for (int i = 0; i < 3; i++) nb[i] = (inside ? -ws[i] : ws[i]) / dist;
            } else {
                /* on the axis: the edge's outward normal, reversed */
                const double *u = hb[ebest], *v = hb[(ebest + 1) % nh];
                double ex = v[0] - u[0], ey = v[1] - u[1], len = hypot(ex, ey);
                nb[0] = len > 0.0 ? -ey / len : 0.0;
                nb[1] = len > 0.0 ? ex / len : 0.0;
                nb[2] = 0.0;
            }
            if (gap) gap[nr] = (inside ? -dist : dist) - ob->radius;
            if (G) row_G(m, q, xs, nb, G[nr]);
            contact_set_point(cp ? &cp[nr] : NULL, xs, rc, nb);
            if (round)
                round[nr] = 64.0 * DBL_EPSILON * (hypot(xs[0], xs[1]) + pn + sqrt(ex_dot3(ob->center, ob->center)) +
                                                  ob->radius);
            nr++;
        }
    }
    return nr;
}

int contact_obstacle_rows(const exdex_model *m, const exdex_kinematics *kin, const double *q, double (*G)[3],
                          double *gap, double *round, int *src, contact_point *cp)
{
    return contact_obstacle_build(m, kin, q, NULL, G, gap, round, src, cp, NULL);
}

int contact_obstacle_rows_pred(const exdex_model *m, const exdex_kinematics *kin, const double *q, const double *vp,
                               double h, double (*G)[3], double *gap, double *round, int *src, contact_point *cp)
{
    contact_obuild opt = {vp, h, NULL, NULL, 0};
    return contact_obstacle_build(m, kin, q, &opt, G, gap, round, src, cp, NULL);
}

int contact_obstacle_max_rows(const exdex_model *m)
{
    int n = 0, nv = contact_nv(m);
    if (m->disc_r > 0.0) return m->n_obst;  /* one row per obstacle */
    for (int o = 0; o < m->n_obst; o++)
        n += m->def.obstacles[o].kind == EXDEX_OBSTACLE_POLYTOPE
                 ? nv + (m->n_hull >= 3 ? m->def.obstacles[o].n_faces : 0)
                 : 1;
    return n;
}

/* ------------------------------------------- planar slip along a stop */

double contact_slip_planar(const exdex_model *m, const exdex_kinematics *k, int ks, int j, const double *q,
                           const double *v, double T[3], double *tb, double *sdd0)
{
    return contact_plane_slip_planar(m, k, m->sn[ks], j, q, v, T, tb, sdd0);
}

double contact_plane_slip_planar(const exdex_model *m, const exdex_kinematics *k, const double n[3], int j,
                                 const double *q, const double *v, double T[3], double *tb, double *sdd0)
{
    double rv[3] = {0.0, 0.0, 0.0}, xB[3], xd[3], xdd[3], Rx[3], Rxd[3], Rxdd[3], nB[3], tB[3], tA[3];
    double VP[3], AP[3], wB[3], dnB[3], dtB[3], dtA[3], tmp[3], tmp2[3], nn, udu;
    if (m->n_vert) rot2(rv, q[2], m->vert[j]);
    xB[0] = q[0] + rv[0];
    xB[1] = q[1] + rv[1];
    xB[2] = 0.0;
    contact_plane_tangent(m, k, n, xB, rv, T, tb);
    if (sdd0 && m->disc_r > 0.0) {
        /* a disc slips at its support point x_s = x_c - r u (u = n_B,xy / |n_B,xy|):
         * below, the material point there. The contact moves along the rim (d x_s /
         * dt = xd_c - r du/dt, not the material point's xd_c - r thd e_z x u), which
         * changes A_P by R (-thd^2 r u - r thd e_z x du/dt) + w x R (r thd e_z x u -
         * r du/dt); with du/dt along t (u is unit) the first is along u and the
         * second is w x (a vector along t_A): both are normal to t_A, so t_A . A_P
         * and the slip acceleration are the material point's */
        double xs[3], vs[3];
        disc_support(m, k, n, xB, rv, xs, vs);
        memcpy(xB, xs, sizeof xs);
        memcpy(rv, vs, sizeof vs);
    }
    if (sdd0) {
        *sdd0 = 0.0;
        ex_mulmtv3(nB, k->R, n);
        nn = hypot(nB[0], nB[1]);
        if (nn > FQ_MIN) {
            /* s = t_A . V_P, V_P the velocity of the material point in A,
             * t_A = R t_B, t_B = e_z x n_B / |n_B| (in-plane part):
             * ds/dt = t_A . A_P + (w x t_A + R dt_B/dt) . V_P, with
             * dn_B/dt = -(w_B x n_B), w_B = R^T w */
            point_rates(rv, v, xd, xdd);
            ex_mulmv3(Rx, k->R, xB);
            ex_mulmv3(Rxd, k->R, xd);
            ex_mulmv3(Rxdd, k->R, xdd);
            ex_cross3(tmp, k->w, Rx);
            for (int c = 0; c < 3; c++) VP[c] = k->v[c] + tmp[c] + Rxd[c];
            for (int c = 0; c < 3; c++) AP[c] = k->a[c] + Rxdd[c];
            ex_cross3(tmp2, k->w, tmp);
            for (int c = 0; c < 3; c++) AP[c] += tmp2[c];
            ex_cross3(tmp, k->dw, Rx);
            for (int c = 0; c < 3; c++) AP[c] += tmp[c];
            ex_cross3(tmp, k->w, Rxd);
            for (int c = 0; c < 3; c++) AP[c] += 2.0 * tmp[c];
            tB[0] = -nB[1] / nn;
            tB[1] = nB[0] / nn;
            tB[2] = 0.0;
            ex_mulmv3(tA, k->R, tB);
            ex_mulmtv3(wB, k->R, k->w);
            ex_cross3(dnB, wB, nB);
            for (int c = 0; c < 3; c++) dnB[c] = -dnB[c];
            udu = nB[0] * dnB[0] + nB[1] * dnB[1];
            dtB[0] = -dnB[1] / nn + nB[1] * udu / (nn * nn * nn);
            dtB[1] = dnB[0] / nn - nB[0] * udu / (nn * nn * nn);
            dtB[2] = 0.0;
            ex_mulmv3(tmp, k->R, dtB);
            ex_cross3(dtA, k->w, tA);
            for (int c = 0; c < 3; c++) dtA[c] += tmp[c];
            *sdd0 = ex_dot3(tA, AP) + ex_dot3(dtA, VP);
        }
    }
    return ex_dot3(T, v) + *tb;
}
