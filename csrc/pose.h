/* pose.h -- private to the exdex core: the object's pose from its
 * coordinates, read by the model, the contact geometry and the methods
 * alike (it calls nothing). */
#ifndef EXDEX_POSE_H
#define EXDEX_POSE_H

#include <math.h>

#include "model.h"

/* Rotation by angle th about z applied to a plane vector. */
static inline void rot2(double out[2], double th, const double v[2])
{
    double c = cos(th), s = sin(th);
    double x = c * v[0] - s * v[1], y = s * v[0] + c * v[1];
    out[0] = x;
    out[1] = y;
}

/* rot2 with cs = (cos th, sin th) given. */
static inline void rot2_cs(double out[2], const double cs[2], const double v[2])
{
    double c = cs[0], s = cs[1];
    double x = c * v[0] - s * v[1], y = s * v[0] + c * v[1];
    out[0] = x;
    out[1] = y;
}

/* Centre of mass position r in B (z = 0) and orientation th for coordinates q:
 * translation r = r0 + (s - s0) d; rotation r = pivot + Rz(theta) c;
 * planar r = (x, y). */
static inline void pose_com(const exdex_model *m, const double *q, double r[3], double *th)
{
    r[2] = 0.0;
    switch (m->ndof == 3 ? EXDEX_DOF_PLANAR : m->def.dof) {
    case EXDEX_DOF_TRANSLATION:
        r[0] = m->r0[0] + (q[0] - m->s0) * m->d[0];
        r[1] = m->r0[1] + (q[0] - m->s0) * m->d[1];
        *th = m->th0;
        break;
    case EXDEX_DOF_ROTATION: {
        double rho[2];
        rot2(rho, q[0], m->c);
        r[0] = m->pivot[0] + rho[0];
        r[1] = m->pivot[1] + rho[1];
        *th = q[0];
        break;
    }
    default:
        r[0] = q[0];
        r[1] = q[1];
        *th = q[2];
    }
}

#endif
