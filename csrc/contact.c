/* contact.c -- contact geometry of the object's outline against the stops
 * (contact.h): gaps, their derivatives with respect to the free coordinates
 * and time, and the rounding bound of a gap. */
#include "exdex.h"
#include "contact.h"
#include "util.h"

#include <float.h>

int contact_vertices(const exdex_model *m, const double *q, double xb[][3], double vx[][3])
{
    double r[3], th, c, s;
    int nv = m->n_vert ? m->n_vert : 1;
    model_com_pose(m, q, r, &th);
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

double contact_gap(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3],
                   const double vx[3], double G[3])
{
    double xa[3], nB[3];
    ex_mulmv3(xa, kin->R, xb);
    for (int i = 0; i < 3; i++) xa[i] += kin->p[i] - m->sp[k][i];
    if (G) {
        ex_mulmtv3(nB, kin->R, m->sn[k]);
        if (m->ndof == 3) {
            /* columns: d xb / dx, dy, dtheta = e_z x vx */
            G[0] = nB[0];
            G[1] = nB[1];
            G[2] = -nB[0] * vx[1] + nB[1] * vx[0];
        } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
            G[0] = nB[0] * m->d[0] + nB[1] * m->d[1];
        } else {
            /* rotation about the pivot: d xb / dtheta = e_z x (xb - pivot) */
            double ax = xb[0] - m->pivot[0], ay = xb[1] - m->pivot[1];
            G[0] = -nB[0] * ay + nB[1] * ax;
        }
    }
    return ex_dot3(xa, m->sn[k]);
}

double contact_vertex_gap(const exdex_model *m, const exdex_kinematics *kin, int k, const double *q, int j,
                          double G[3])
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3];
    contact_vertices(m, q, xb, vx);
    return contact_gap(m, kin, k, xb[j], vx[j], G);
}

/* A gap within its own rounding of zero counts as exactly 0 where a method
 * decides on its sign: the sign of a rounding-level gap depends on the world
 * frame the data is given in (contact_gap works in A), not on the scene.
 * The bound is 8 rounding units of the sum of the magnitudes contact_gap
 * adds (|x_B|, |p|, |stop point|; R is orthonormal). */
#define GAP_ROUND (8.0 * DBL_EPSILON)

double contact_gap_round(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3])
{
    return GAP_ROUND * (sqrt(ex_dot3(xb, xb)) + sqrt(ex_dot3(kin->p, kin->p)) + sqrt(ex_dot3(m->sp[k], m->sp[k])));
}

double contact_min_gap(const exdex_model *m, const exdex_kinematics *kin, const double *q)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], gmin = INFINITY;
    int nv;
    if (!m->n_stops) return INFINITY;
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
    double xB[3] = {0, 0, 0}, x1[3] = {0, 0, 0}, x2[3] = {0, 0, 0};
    double Rx[3], R1[3], R2[3], wx[3], wwx[3], dwx[3], w1[3];
    const double *n = m->sn[ks];
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
    c->F = n[0] * (Rx[0] + k->p[0] - m->sp[ks][0]) + n[1] * (Rx[1] + k->p[1] - m->sp[ks][1]) +
           n[2] * (Rx[2] + k->p[2] - m->sp[ks][2]);
    c->Fq = ex_dot3(n, R1);
    c->Fqq = ex_dot3(n, R2);
    ex_cross3(wx, k->w, Rx);
    ex_cross3(wwx, k->w, wx);
    ex_cross3(dwx, k->dw, Rx);
    ex_cross3(w1, k->w, R1);
    c->Ft = ex_dot3(n, wx) + ex_dot3(n, k->v);
    c->Ftq = ex_dot3(n, w1);
    c->Ftt = ex_dot3(n, dwx) + ex_dot3(n, wwx) + ex_dot3(n, k->a);
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
    double rv[2] = {0.0, 0.0}, xB[3], xd[3], xdd[3], Rx[3], Rxd[3], Rxdd[3], nB[3], a[3], b[3], c[3];
    const double *n = m->sn[ks];
    double gap;
    if (m->n_vert) rot2(rv, q[2], m->vert[j]);
    xB[0] = q[0] + rv[0];
    xB[1] = q[1] + rv[1];
    xB[2] = 0.0;
    ex_mulmv3(Rx, k->R, xB);
    gap = n[0] * (Rx[0] + k->p[0] - m->sp[ks][0]) + n[1] * (Rx[1] + k->p[1] - m->sp[ks][1]) +
          n[2] * (Rx[2] + k->p[2] - m->sp[ks][2]);
    ex_mulmtv3(nB, k->R, n);
    G[0] = nB[0];
    G[1] = nB[1];
    G[2] = -nB[0] * rv[1] + nB[1] * rv[0];
    if (gd || gdd0) {
        xd[0] = v[0] - rv[1] * v[2];
        xd[1] = v[1] + rv[0] * v[2];
        xd[2] = 0.0;
        xdd[0] = -rv[0] * v[2] * v[2];
        xdd[1] = -rv[1] * v[2] * v[2];
        xdd[2] = 0.0;
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
    if (m->ndof == 3) {
        T[0] = t[0];
        T[1] = t[1];
        T[2] = -t[0] * vx[1] + t[1] * vx[0];
    } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        T[0] = t[0] * m->d[0] + t[1] * m->d[1];
    } else {
        double ax = xb[0] - m->pivot[0], ay = xb[1] - m->pivot[1];
        T[0] = -t[0] * ay + t[1] * ax;
    }
    ex_mulmv3(tA, kin->R, t);
    ex_mulmv3(Rx, kin->R, xb);
    ex_cross3(wx, kin->w, Rx);
    *tb = tA[0] * (kin->v[0] + wx[0]) + tA[1] * (kin->v[1] + wx[1]) + tA[2] * (kin->v[2] + wx[2]);
}

void contact_stop_tangent(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3],
                          const double vx[3], double T[3], double *tb)
{
    double nB[3];
    ex_mulmtv3(nB, kin->R, m->sn[k]);
    contact_tangent(m, kin, xb, vx, nB, T, tb);
}
