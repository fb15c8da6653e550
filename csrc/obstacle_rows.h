/* obstacle_rows.h -- private to the exdex core: the obstacles' contact rows as the
 * hybrid (event, regularised) machine holds them. A row of
 * contact_obstacle_build is a largest (or smallest) distance over the
 * features of a pair: an outline vertex against the faces of a polytope
 * (the largest face distance), a section vertex against the outline's hull
 * edges (the largest edge distance), a rod's axis against the hull (the
 * nearest vertex or edge). Its gap is continuous but only piecewise smooth:
 * where the active feature changes, its rate jumps. Here a row is its code:
 * the pair and the feature held, a smooth function of (q, t) with exact
 * first and second derivatives; a guard (orow_feature_guard) changes sign
 * where the held feature stops being the active one, so the machine decides
 * again there.
 *
 * Codes (>= 0): (((o 3 + kind) 32 + a) 32 + b) 64 + feat, o the obstacle,
 * kind, a, b and feat those of the row's contact_feature (contact.h).
 * contact_obstacle_build decides the rows: orow_all is its view with the
 * rate tie rule. */
#ifndef EXDEX_OBSTACLE_ROWS_H
#define EXDEX_OBSTACLE_ROWS_H

#include "contact.h"

static inline int orow_code(int o, int kind, int a, int b, int feat)
{
    return (((o * 3 + kind) * 32 + a) * 32 + b) * 64 + feat;
}
static inline int orow_obst(int c) { return c / (64 * 32 * 32 * 3); }
static inline int orow_kind(int c) { return (c / (64 * 32 * 32)) % 3; }
static inline int orow_a(int c) { return (c / (64 * 32)) % 32; }
static inline int orow_b(int c) { return (c / 64) % 32; }
static inline int orow_feat(int c) { return c % 64; }
/* the pair without its feature (two codes of the same row compare equal) */
static inline int orow_pair(int c) { return c / 64; }

/* 1 if code is a valid row code for model m (the obstacle, kind, indices
 * and feature in range). */
int orow_valid(const exdex_model *m, int code);

/* Every obstacle row at pose kin and coordinates q with its active feature:
 * codes and gaps (gap may be NULL), in the order obstacle, outline vertices,
 * then section vertices (or the rod's row): contact_obstacle_build's rows,
 * with the rate tie rule (orow_rate) when the velocities v are given (v may
 * be NULL: no tie rule) and its planar option. Returns the count (<=
 * contact_obstacle_max_rows). */
int orow_all(const exdex_model *m, const exdex_kinematics *kin, const double *q, const double *v, int planar,
             int *code, double *gap);

/* Planar row `code` (feature held) at q, v: returns the gap; G = d gap /
 * d qdot; gd (may be NULL) its rate; gdd0 (may be NULL) its acceleration
 * less G qdd (contact_row_planar's contract). */
double orow_planar(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q, const double *v,
                   double G[3], double *gd, double *gdd0);
/* 1-DoF row `code` (feature held) at q: contact_row_1dof's contract. */
void orow_1dof(const exdex_model *m, const exdex_kinematics *kin, int code, double q, crow *c);
/* >= 0 while the feature held in code is the row's active one (and a
 * section vertex is a vertex of the section): a length. */
double orow_feature_guard(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q);
/* Where the row `code` (feature held) acts at (kin, q), for its friction
 * (contact_tangent): the object's material point, its offset from the
 * centre of mass and the row's normal in B (the direction the gap grows in
 * when that point moves), as contact_obstacle_rows gives them. */
void orow_point(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q, contact_point *cp);

/* Planar slip along row `code` (feature held) at (kin, q, v): s = T . v +
 * tb with T, tb of contact_tangent at the row's point (orow_point; a vertex
 * row: contact_plane_slip_planar with the face's normal, as a stop's);
 * sdd0 (may be NULL) the slip acceleration less T qdd, exact also where the
 * contact point moves over the object (section and rod rows). Returns s. */
double orow_slip(const exdex_model *m, const exdex_kinematics *kin, int code, const double *q, const double *v,
                 double T[3], double *tb, double *sdd0);

#endif
