/* contact.h -- private to the exdex core: the contact geometry of the
 * object's outline against the stops (half-spaces of the world frame A),
 * shared by every method. A row is one (stop k, outline vertex j) pair: its
 * gap n_k . (x_A - p_k) >= 0 allowed, and the derivatives of the gap with
 * respect to the free coordinates and time. An object without an outline
 * counts its centre of mass as its one vertex; a disc outline (disc_r > 0)
 * its centre, every gap being its support point's (the centre's less the
 * radius along the row's in-plane normal) and every friction row acting at
 * that support point. */
#ifndef EXDEX_CONTACT_H
#define EXDEX_CONTACT_H

#include "model.h"

/* A planar stop row G = (n_x, n_y, r x n) (n the stop normal in B, r the
 * vertex offset) with |G_x| + |G_y| + |G_theta| below this cannot act: the
 * stop faces the plate normal (G_theta is then 0 too). The 1-DoF rows and
 * every gap compare with the model's thresholds (model_tols). */
#define FQ_MIN 1e-12

/* Number of outline vertices the stops see (at least 1). */
static inline int contact_nv(const exdex_model *m) { return m->n_vert ? m->n_vert : 1; }

/* Outline vertices in B at coordinates q: xb[j] (position) and vx[j] (offset
 * from the centre of mass), one cos/sin for all of them. Returns the count. */
int contact_vertices(const exdex_model *m, const double *q, double xb[][3], double vx[][3]);
/* Gap of the vertex at xb (offset vx from the centre of mass) against stop k
 * for the gripper pose kin; G (may be NULL) gets d gap / d qdot (ndof entries). */
double contact_gap(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3],
                   const double vx[3], double G[3]);
/* Gap of outline vertex j against stop k at coordinates q and pose kin. */
double contact_vertex_gap(const exdex_model *m, const exdex_kinematics *kin, int k, const double *q, int j,
                          double G[3]);
/* Rounding bound of contact_gap for the vertex at xb against stop k at pose
 * kin: a gap within it of 0 has no determined sign. */
double contact_gap_round(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3]);
/* Smallest gap over every (stop, vertex) pair at coordinates q and pose kin
 * (INFINITY without stops). */
double contact_min_gap(const exdex_model *m, const exdex_kinematics *kin, const double *q);
/* Every (stop, vertex) row at q and pose kin: G_i = d gap_i / d qdot, gap_i,
 * stop index; rows ordered r = k nv + j. Returns the count. */
int contact_rows(const exdex_model *m, const exdex_kinematics *kin, const double *q, double (*G)[3],
                 double *gap, int *stop);

/* 1-DoF row of vertex j against stop k as a function of (q, t), with the
 * derivatives a held constraint needs: F = n.(R x_B(q) + p - p_stop),
 * x_B the vertex in B (translation: linear in q; rotation: about the pivot). */
typedef struct crow {
    double F, Fq, Fqq, Ft, Ftq, Ftt;
} crow;
void contact_row_1dof(const exdex_model *m, const exdex_kinematics *k, int ks, int j, double q, crow *c);
/* The same rows against any plane of A through sp with unit normal n (a
 * stop's, or an obstacle's face seen from outside): contact_row_1dof,
 * contact_row_planar and contact_gap are these with the stop's plane. */
void contact_plane_row_1dof(const exdex_model *m, const exdex_kinematics *k, const double sp[3], const double n[3],
                            int j, double q, crow *c);
double contact_plane_row_planar(const exdex_model *m, const exdex_kinematics *k, const double sp[3],
                                const double n[3], int j, const double *q, const double *v, double G[3], double *gd,
                                double *gdd0);
double contact_plane_gap(const exdex_model *m, const exdex_kinematics *kin, const double sp[3], const double sn[3],
                         const double xb[3], const double vx[3], double G[3]);
/* Smallest gap of stop ks over the outline at the 1-DoF coordinate q, and
 * its vertex (jmin may be NULL). */
double contact_stop_gap(const exdex_model *m, const exdex_kinematics *k, int ks, double q, int *jmin);
/* Planar row of vertex j against stop ks at coordinates q, velocity v and
 * gripper kinematics k: returns the gap; G = d gap / d qdot; gd (may be NULL)
 * the gap rate; gdd0 (may be NULL) the gap acceleration less G qdd. */
double contact_row_planar(const exdex_model *m, const exdex_kinematics *k, int ks, int j, const double *q,
                          const double *v, double G[3], double *gd, double *gdd0);
/* contact_plane_row_planar and contact_row_planar with cs = (cos q[2], sin q[2])
 * given (NULL: computed). */
double contact_plane_row_planar_cs(const exdex_model *m, const exdex_kinematics *k, const double sp[3],
                                   const double n[3], int j, const double *q, const double *cs, const double *v,
                                   double G[3], double *gd, double *gdd0);
double contact_row_planar_cs(const exdex_model *m, const exdex_kinematics *k, int ks, int j, const double *q,
                             const double *cs, const double *v, double G[3], double *gd, double *gdd0);

/* Coulomb friction of a contact row (a point of the object against a
 * contact fixed in A: a stop, or any other row with an in-plane normal).
 * The tangent is t_B = e_z x n_B, n_B the unit in-plane part of the row's
 * normal in B (the plates hold the object in the plate plane, so the
 * friction acts in it). The slip of the contact point along t is
 *     s = T . qdot + tb,
 * T = d s / d qdot (the formula of G with t_B for n_B: planar (t_x, t_y,
 * -t_x vx_y + t_y vx_x), translation t . slide axis, rotation t . (e_z x
 * (x_B - pivot))), and tb = t_A . (pdot + w x R x_B) the slip of the point
 * with the object at rest in B (the gripper's motion past the contact;
 * exactly 0 for a gripper at rest). The friction force on the object is
 * beta t, |beta| <= mu lambda (lambda the normal force), opposing s when
 * s != 0; its generalized force is beta T. nB_inplane (x, y of n_B, not
 * normalised) with |n_B| below FQ_MIN gives T = 0, tb = 0 (the row cannot
 * act). */
void contact_tangent(const exdex_model *m, const exdex_kinematics *kin, const double xb[3], const double vx[3],
                     const double nB_inplane[2], double T[3], double *tb);
/* The friction rows of stop k at the vertex xb (offset vx): contact_tangent
 * with n_B = R^T n_k. */
void contact_stop_tangent(const exdex_model *m, const exdex_kinematics *kin, int k, const double xb[3],
                          const double vx[3], double T[3], double *tb);

/* The same against any plane of A with unit normal n (a stop's, or an
 * obstacle's face seen from outside): contact_stop_tangent is this with the
 * stop's normal. */
void contact_plane_tangent(const exdex_model *m, const exdex_kinematics *kin, const double n[3], const double xb[3],
                           const double vx[3], double T[3], double *tb);

/* Is some stop out of the object's reach at pose k and coordinates q, its
 * gap below -tol.pen for every value of the free coordinates? */
int contact_unreachable(const exdex_model *m, const exdex_kinematics *k, const double *q);
/* Largest distance of an outline vertex from the rotation centre (the
 * centre of mass for planar scenes, the pivot for rotation; 0 for
 * translation): bounds |d^2 gap / d theta^2|. */
double contact_rot_radius(const exdex_model *m);

/* ------------------------------------------------ convex obstacles
 * Rows of the obstacles (exdex.h, exdex_obstacle_def) after the stops' rows,
 * in the same form: gap_i >= 0 allowed, G_i = d gap_i / d qdot. Per
 * polytope: one row per outline vertex (its largest face distance: the
 * row of that face, a plane row as a stop's) and, with a hull of at least 3
 * vertices, one per vertex of the section polygon in the order of
 * contact_section_vertices (its largest distance outside the hull's edge
 * lines, acting at the section vertex with the edge's inward normal); per
 * rod: one row, the hull point nearest the axis (its distance from the axis
 * less the radius, negative when the axis meets the plane inside the hull).
 * A disc outline: one row per obstacle (its distance from the section less
 * its radius: disc_obstacle_row in contact.c). contact_obstacle_build
 * decides every row; contact_obstacle_rows, contact_obstacle_rows_pred and
 * obstacle_rows.h's orow_all are views of it. */

/* Where a row acts, for friction along it (contact_tangent): the object's
 * material point x (B), its offset vx from the centre of mass (planar) and
 * the row's normal nB (B; its in-plane part is the direction the gap grows
 * in when the point moves). */
typedef struct contact_point {
    double x[3], vx[3], nB[3];
} contact_point;

/* The feature a row holds (obstacle_rows.h packs it into a row code):
 *   OROW_VERTEX:  a = outline vertex j, b = 0, feat = the face;
 *   OROW_SECTION: a < b the two faces whose lines meet at the section vertex,
 *                 feat = the hull edge (from hull vertex feat to feat + 1);
 *   OROW_ROD:     a = b = 0, feat = hull vertex k (k < 32) or hull edge
 *                 32 + e (its interior).
 * A disc outline: OROW_VERTEX (a = 0) its support point against face feat,
 * OROW_SECTION (faces a < b, feat 0) its centre's distance from their
 * section vertex less the radius, OROW_ROD (feat 0) its rim point nearest
 * the axis. obst is the obstacle's index. */
enum { OROW_VERTEX = 0, OROW_SECTION = 1, OROW_ROD = 2 };
typedef struct contact_feature {
    int obst, kind, a, b, feat;
} contact_feature;

/* The rate (d gap / dt at velocity v, the feature held) of the row of
 * feature f at (kin, q): supplied by the caller of the rate tie rule. */
typedef double (*contact_rate_fn)(const exdex_model *m, const exdex_kinematics *kin, const contact_feature *f,
                                  const double *q, const double *v);

/* How contact_obstacle_build decides a row whose gap is a largest
 * distance over pieces (faces for an outline vertex, hull edges for a
 * section vertex). The constraint set {max_i g_i >= 0} is not convex where
 * two pieces meet (a corner against a corner) and a row holds one piece:
 * without a rule (opt NULL, or vp and rate NULL), the first piece of the
 * largest g at q.
 *   Step rule (vp not NULL, a time step of length h with the predicted
 *   velocity vp): the piece of the largest predicted distance g_i + h G_i .
 *   vp over all pieces (the first of equal ones): the piece that is the
 *   largest at the step's end, so a corner sliding past a corner is held by
 *   the piece it moves along rather than stopped by the piece it leaves.
 *   The pick differs from the largest at q only where two pieces' order
 *   changes within the step.
 *   Rate rule (rate and v not NULL, vp NULL): where several pieces are
 *   within tol.touch of the largest, the one of them of the largest rate
 *   rate(f_i, q, v) (the first of equal ones): the piece that stays the
 *   largest at the next instant (a max of several pieces stays >= 0 while
 *   any piece does; holding a piece that decreases would block a motion the
 *   others allow).
 * planar = 1 computes a face row's gap (and G) as contact_plane_row_planar,
 * 0 as contact_plane_gap: the formulas the stops' rows use in the planar
 * methods (event, regularised) and in the steppers, so that a one-face
 * obstacle is its plane stop bit for bit in each. Rods and disc outlines
 * have one piece. */
typedef struct contact_obuild {
    const double *vp;
    double h;
    const double *v;
    contact_rate_fn rate;
    int planar;
} contact_obuild;

/* Every obstacle row at q and pose kin with the rule opt (may be NULL):
 * gap_i (gap may be NULL); G_i (G may be NULL); round_i (may be NULL)
 * bounds the rounding of gap_i; src_i = n_stops + obstacle index (may be NULL); cp_i (may be NULL)
 * where the row acts; ft_i (may be NULL) the feature it holds. Returns the
 * count, at most contact_obstacle_max_rows. */
int contact_obstacle_build(const exdex_model *m, const exdex_kinematics *kin, const double *q,
                           const contact_obuild *opt, double (*G)[3], double *gap, double *round, int *src,
                           contact_point *cp, contact_feature *ft);
/* contact_obstacle_build without a tie rule, planar = 0. */
int contact_obstacle_rows(const exdex_model *m, const exdex_kinematics *kin, const double *q, double (*G)[3],
                          double *gap, double *round, int *src, contact_point *cp);
/* contact_obstacle_build with the step rule for a step of length h (vp
 * NULL: none), planar = 0. */
int contact_obstacle_rows_pred(const exdex_model *m, const exdex_kinematics *kin, const double *q, const double *vp,
                               double h, double (*G)[3], double *gap, double *round, int *src, contact_point *cp);
int contact_obstacle_max_rows(const exdex_model *m);
/* 1 if the obstacle definition is valid (kind, face count, unit normals and
 * axis, finite points, radius > 0). */
int contact_obstacle_valid(const exdex_obstacle_def *o);
/* Fill cp (if not NULL) for a row acting at x with normal nB: x and nB,
 * vx = x less the centre of mass r, the z components of x and vx 0. */
void contact_set_point(contact_point *cp, const double x[3], const double r[3], const double nB[3]);
/* Half-planes a.y <= b of B's plate plane cut by the polytope's faces at pose
 * (R, p): a = (R^T n)_xy, b = n.(face point - p), with their face numbers in
 * idx (may be NULL). Faces parallel to the plane (|a| <= 1e-12) are left out
 * when the plane lies inside them; *empty is set when it lies outside one
 * (the plane misses the solid). Returns the number kept. */
int contact_halfplanes(const exdex_obstacle_def *o, const double R[9], const double p[3], double a[][2], double *b,
                       int *idx, int *empty);
/* The line of the n half-planes a_k . y <= b_k farthest from the point xc
 * (largest (a_k . xc - b_k) / |a_k|, the first of equal ones; -1 for n = 0),
 * that distance in *db; *on is 0 when the distance is positive and the foot
 * of xc on the line lies outside another half-plane beyond a relative 1e-12
 * (a_h . y - b_h > 1e-12 (|a_h| |y| + |b_h|)), else 1. */
int contact_farthest_line(int n, const double (*a)[2], const double *b, const double xc[3], double *db, int *on);
/* A rod's axis in B at pose (R, p): the point cB = R^T (center - p) and the
 * direction aB = R^T axis. */
void contact_rod_axis(const exdex_obstacle_def *o, const double R[9], const double p[3], double cB[3], double aB[3]);
/* The vertices of the polygon {y : a_i . y <= b_i} of n lines (|a_i| > 0):
 * each intersection of two lines f < g (not parallel: |det| > 1e-12 |a_f|
 * |a_g|) that satisfies every other half-plane to a relative 1e-12 (a_h . y
 * - b_h <= 1e-12 (|a_h| |y| + |b_h|)), once (one within 1e-10 (|y| + |y'|)
 * of an earlier y' is dropped), in the order of (f, g), with its pair in fg
 * (may be NULL). Returns their number (at most EXDEX_MAX_FACES). */
int contact_section_vertices(int n, const double (*a)[2], const double *b, double ys[][2], int fg[][2]);
/* Convex hull (counter-clockwise, 1 .. n points) of n plane points; n = 0
 * gives the origin alone. */
int contact_hull(const double (*v)[2], int n, double (*hull)[2]);

/* The rim point of a disc of radius r nearest a rod's axis: the unit u
 * minimising 2 r b . u - r^2 (u . a)^2 over the unit circle, a the in-plane
 * part of the axis direction (B), b the in-plane part of the centre's
 * offset from the axis (as contact_obstacle_build finds it). */
void contact_circle_min(const double a[2], const double b[2], double r, double u[2]);

/* Slip of vertex j of a planar object along stop ks at coordinates q,
 * velocity v and gripper kinematics k: returns s = T . v + tb with T, tb of
 * contact_stop_tangent (the vertex as the material point); sdd0 (may be
 * NULL) gets the slip acceleration less T qdd (the stop's tangent turns
 * with the gripper: its rate is part of it). */
double contact_slip_planar(const exdex_model *m, const exdex_kinematics *k, int ks, int j, const double *q,
                           const double *v, double T[3], double *tb, double *sdd0);
/* The same along the plane of A with unit normal n (an obstacle's face seen
 * from outside): contact_slip_planar is this with the stop's normal. */
double contact_plane_slip_planar(const exdex_model *m, const exdex_kinematics *k, const double n[3], int j,
                                 const double *q, const double *v, double T[3], double *tb, double *sdd0);

/* The outline's convex hull in B at coordinates q, counter-clockwise (z = 0);
 * returns its vertex count. */
int contact_hull_b(const exdex_model *m, const double *q, double hb[][3]);
/* Whether the line through cB along aB (B, aB[2] != 0) meets the plate plane
 * strictly inside the counter-clockwise hull hb (nh vertices). */
int contact_axis_in_hull(int nh, const double hb[][3], const double cB[3], const double aB[3]);
/* Foot parameter (unclamped) along the hull edge e (hb, nh vertices) of the
 * point nearest the rod's axis (cB, aB in B); *len the edge's length
 * perpendicular to the axis (0: the edge is parallel to it, and the foot 0). */
double contact_rod_foot(int nh, const double hb[][3], const double cB[3], const double aB[3], int e, double *len);

#endif
