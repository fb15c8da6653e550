/* test_frictional_impacts.c -- impacts on frictional stops in the event and
 * regularised methods (hybrid.c: sf_impact for planar scenes,
 * impact_impulse_1dof for 1-DoF scenes) against the closed form of the
 * impulse-level law: plastic, Coulomb friction at the stop, no plate
 * impulse (the plates' friction is bounded; its impulse over an impact is
 * 0):
 *     M (v+ - v-) = G Pn + T Pt,  G v+ = b,  |Pt| <= mu Pn,
 *     Pt = -mu Pn sign(T v+ + tb) where that slip is not 0.
 * twin: tests/scenarios/test_frictional_impacts.py (the same subject through the Python API)
 */
#include "../check.h"
#include "../sim_run.h"
#include "../../exdex.h"

#include <math.h>
#include <string.h>

#define G 9.81

/* The box of the corner strikes: a x b, mass m, Izz = I, outline loc, in a
 * planar grasp whose plates have no friction, no gravity, B = A, turned by
 * th0 and moving at v0 (x, y, theta rates); a floor stop (normal +y, its
 * friction mu) through y = y_stop; the method at rtol 1e-12, atol 1e-14. */
static exdex_scene_def strike_def(int method, double a, double b, double m, double I, double loc[4][2],
                                  double th0, const double v0[3], double y_stop, double mu)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.dof = EXDEX_DOF_PLANAR;
    d.method = method;
    d.rtol = 1e-12;
    d.atol = 1e-14;
    d.mass = m;
    memset(d.inertia, 0, sizeof d.inertia);
    d.inertia[0] = m * b * b / 12.0;
    d.inertia[4] = m * a * a / 12.0;
    d.inertia[8] = I;
    d.n_vertices = 4;
    memcpy(d.vertices, loc, sizeof d.vertices[0] * 4);
    d.mu = 0.0;
    d.grip_force = 1.0;
    d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
    memset(d.R0, 0, sizeof d.R0);
    d.R0[0] = d.R0[4] = d.R0[8] = 1.0;
    d.q0[0] = d.q0[1] = 0.0;
    d.q0[2] = th0;
    memcpy(d.v0, v0, sizeof d.v0);
    d.n_stops = 1;
    memset(d.stop_point[0], 0, sizeof d.stop_point[0]);
    memset(d.stop_normal[0], 0, sizeof d.stop_normal[0]);
    d.stop_point[0][1] = y_stop;
    d.stop_normal[0][1] = 1.0;
    d.stop_mu[0] = mu;
    return d;
}

/* The corner r (from C, in A) of the outline loc turned by th0 that is
 * lowest (least y). */
static void lowest_corner(double loc[4][2], double th0, double r[2])
{
    double c = cos(th0), s = sin(th0);
    r[0] = 0.0;
    r[1] = INFINITY;
    for (int k = 0; k < 4; k++) {
        double y = s * loc[k][0] + c * loc[k][1];
        if (y < r[1]) {
            r[0] = c * loc[k][0] - s * loc[k][1];
            r[1] = y;
        }
    }
}

/* A box a x b (mass m, Izz = m (a^2 + b^2) / 12) turned by th0, moving at
 * v0 = (0.15, -0.2) m/s and spinning at 2 rad/s in a planar grasp whose
 * plates have no friction, no gravity, B = A; its lowest corner r (from
 * C) touches a floor stop (normal +y) at t = 0 and approaches it: the
 * impact is at t = 0, the box flies freely after it. Closed form with
 * rows G = (0, 1, r_x), T = (1, 0, -r_y) (the corner's normal and
 * tangential velocities): sticking solves the 2 x 2 system
 *     [G W G, G W T; T W G, T W T] (Pn, Pt) = -(G v, T v),  W = M^-1,
 * kept if |Pt| <= mu Pn; else sliding against the slip before the impact,
 * s = sign(T v): Pt = -mu s Pn, Pn = -G v / (G W (G - mu s T)). */
EXDEX_TEST(fimpact_planar_spinning_corner_on_frictional_floor_closed_form)
{
    double a = 0.04, b = 0.02, m = 0.1, I = m * (a * a + b * b) / 12.0, th0 = 0.3;
    double v0[3] = {0.15, -0.2, 2.0}, r[2];
    double loc[4][2] = {{a / 2, b / 2}, {-a / 2, b / 2}, {-a / 2, -b / 2}, {a / 2, -b / 2}};
    lowest_corner(loc, th0, r);
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_REGULARISED; method++)
        for (int im = 0; im < 3; im++) {
            double mu = im == 0 ? 0.1 : im == 1 ? 0.3 : 2.0, W[3] = {1.0 / m, 1.0 / m, 1.0 / I};
            double Gr[3] = {0.0, 1.0, r[0]}, Tr[3] = {1.0, 0.0, -r[1]}, gg = 0, gt = 0, tt = 0, gv = 0, tv = 0;
            double det, pn, pt, vp[3];
            exdex_scene_def d = strike_def(method, a, b, m, I, loc, th0, v0, r[1], mu);
            sim_run run;
            for (int i = 0; i < 3; i++) {
                gg += Gr[i] * W[i] * Gr[i];
                gt += Gr[i] * W[i] * Tr[i];
                tt += Tr[i] * W[i] * Tr[i];
                gv += Gr[i] * v0[i];
                tv += Tr[i] * v0[i];
            }
            det = gg * tt - gt * gt;
            pn = (-gv * tt + tv * gt) / det;
            pt = (-tv * gg + gv * gt) / det;
            ENSURE((im == 2) == (fabs(pt) <= mu * pn));  /* mu 2 sticks, 0.1 and 0.3 slide */
            if (fabs(pt) > mu * pn) {
                double sg = copysign(1.0, tv), den = 0.0;
                for (int i = 0; i < 3; i++) den += Gr[i] * W[i] * (Gr[i] - mu * sg * Tr[i]);
                pn = -gv / den;
                pt = -mu * sg * pn;
            }
            for (int i = 0; i < 3; i++) vp[i] = v0[i] + W[i] * (Gr[i] * pn + Tr[i] * pt);
            ENSURE(sim_run_def(&d, 0.002, 1e-4, &run) == EXDEX_OK);
            ENSURE(run.st.warnings == 0 && run.st.impacts == 1);
            ENSURE_CLOSE(run.st.max_impulse, pn, 1e-12 * pn);
            for (int i = 0; i < 3; i++) ENSURE_CLOSE(run.tr.v[3 * (run.tr.n - 1) + i], vp[i], 1e-12);
            sim_run_free(&run);
        }
}

/* 1-DoF: the centre of mass slides along B's y (vertical) against an
 * incline fixed in A with in-plane normal n = (sin al, cos al), touching it
 * at rest at t = 0, the gripper moving at the speed V = -0.05 m/s along x
 * from t = 0 (a trapezoid without ramps), the object at rest in B: the
 * incline moves at -V in B, into the object (n_x V < 0), and strikes it at
 * t = 0. The plastic impact makes the gap rate n . (V x + v y) = 0, v =
 * -tan(al) V, and the point then slips along t = (-cos al, sin al) at s =
 * -V / cos(al) > 0; the incline's friction impulse is -mu Pn t, so m v =
 * Pn (cos al - mu sin al) = Pn D. D > 0 at mu 0.4 and 1 (with al = 0.5);
 * at mu 2.5 D < 0: no Pn >= 0 is consistent (a jam), the impact is
 * frictionless (Pn = m v / cos al) with a warning. */
EXDEX_TEST(fimpact_1dof_incline_strike_closed_form)
{
    double al = 0.5, m = 0.1;
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_REGULARISED; method++)
        for (int c = 0; c < 3; c++) {
            double mu = c == 0 ? 0.4 : c == 1 ? 1.0 : 2.5, V = -0.05, v = -tan(al) * V, s = -V / cos(al);
            double D = cos(al) - copysign(1.0, s) * mu * sin(al);
            double pn = D > 0.0 ? m * fabs(v) / D : m * fabs(v) / cos(al);
            exdex_scene_def d = exdex_default_scene_def();
            sim_run r;
            d.mass = m;
            d.mu = 0.5;
            d.grip_force = 0.5;
            d.gravity[2] = -G;
            d.method = method;
            d.motion.kind = EXDEX_MOTION_TRAPEZOID;
            d.motion.axis[0] = 1.0;
            d.motion.axis[1] = d.motion.axis[2] = 0.0;
            d.motion.amplitude = V;
            d.motion.duration = 1.0;
            d.motion.v_max = fabs(V);
            d.n_stops = 1;
            d.stop_normal[0][0] = sin(al);
            d.stop_normal[0][2] = cos(al);
            d.stop_mu[0] = mu;
            d.rtol = 1e-12;
            d.atol = 1e-14;
            ENSURE((c == 2) == (D < 0.0));
            ENSURE(sim_run_def(&d, 0.01, 1e-3, &r) == EXDEX_OK);
            ENSURE(c == 2 ? r.st.warnings > 0 : r.st.warnings == 0);
            ENSURE(r.st.impacts >= 1 && r.st.max_impulse_t == 0.0);
            ENSURE_CLOSE(r.st.max_impulse, pn, 1e-12 * pn);
            sim_run_free(&r);
        }
}

/* Slow slanted strikes: a box a x b (plates without friction, no gravity,
 * B = A) turned by th0 touches a floor stop (normal +y) with its lowest
 * corner r at t = 0, that corner's velocity (ct, -vn): approach vn from
 * 1e-9 to 1e-3 m/s (log-uniform), the slant ct / vn = tan(phi), phi
 * uniform in (-1.4, 1.4) rad, while the box spins at w about it (|w| 1 to
 * 5 rad/s, so the box itself moves at ~w |r|, far above the slow approach:
 * v_C = (ct, -vn) - w (-r_y, r_x)), mu 0.05 to 2.5; 40 scenes of a fixed
 * stream. The law is that of the touching test above at every approach
 * speed (stick iff the 2 x 2 system's |Pt| <= mu Pn, else sliding with
 * the sign that the slip after the impact has, corner_law); the box flies
 * freely after it. The friction's
 * share of the velocity change, |v+ - v+(mu = 0)|, is ~mu vn: the check
 * holds the error to 1e-6 of it (plus rounding of v), so an impact taken
 * frictionless fails by a factor 1e6. */
static double lcg_uniform(unsigned long long *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0;
}

static int corner_law(const double W[3], const double Gr[3], const double Tr[3], const double v0[3], double mu,
                      double vp[3], double *pn_out)
{
    double gg = 0, gt = 0, tt = 0, gv = 0, tv = 0, det, pn, pt;
    int n = 0;
    for (int i = 0; i < 3; i++) {
        gg += Gr[i] * W[i] * Gr[i];
        gt += Gr[i] * W[i] * Tr[i];
        tt += Tr[i] * W[i] * Tr[i];
        gv += Gr[i] * v0[i];
        tv += Tr[i] * v0[i];
    }
    det = gg * tt - gt * gt;
    pn = (-gv * tt + tv * gt) / det;
    pt = (-tv * gg + gv * gt) / det;
    if (fabs(pt) <= mu * pn) {
        for (int i = 0; i < 3; i++) vp[i] = v0[i] + W[i] * (Gr[i] * pn + Tr[i] * pt);
        *pn_out = pn;
        return 1;
    }
    /* sliding: Pt = -mu sg Pn with sg the sign of the slip after the
     * impact, T v+ = tv + Pn (gt - mu sg tt); G v+ = 0 fixes Pn = -gv /
     * (gg - mu sg gt). Each sign is tried; the consistent one (Pn >= 0,
     * sg T v+ > 0) is the law (not always the slip's sign before the
     * impact: the normal impulse's coupling gt can reverse the slip) */
    for (int k = 0; k < 2; k++) {
        double sg = k ? -1.0 : 1.0, p = -gv / (gg - mu * sg * gt), tvp = tv + p * (gt - mu * sg * tt);
        if (!(p >= 0.0 && sg * tvp > 0.0)) continue;
        for (int i = 0; i < 3; i++) vp[i] = v0[i] + W[i] * (Gr[i] * p - mu * sg * Tr[i] * p);
        *pn_out = p;
        n++;
    }
    return n;
}

EXDEX_TEST(fimpact_planar_slow_slanted_strikes_closed_form)
{
    double a = 0.04, b = 0.02, m = 0.1, I = m * (a * a + b * b) / 12.0, W[3] = {1.0 / m, 1.0 / m, 1.0 / I};
    double loc[4][2] = {{a / 2, b / 2}, {-a / 2, b / 2}, {-a / 2, -b / 2}, {a / 2, -b / 2}};
    unsigned long long seed = 20261126ULL;
    int nstick = 0;
    for (int sc = 0; sc < 40; sc++) {
        double th0 = 0.1 + 0.5 * lcg_uniform(&seed), vn = pow(10.0, -9.0 + 6.0 * lcg_uniform(&seed));
        double phi = -1.4 + 2.8 * lcg_uniform(&seed), w = (1.0 + 4.0 * lcg_uniform(&seed));
        double mu = 0.05 + 2.45 * lcg_uniform(&seed), r[2];
        if (lcg_uniform(&seed) < 0.5) w = -w;
        lowest_corner(loc, th0, r);
        for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_REGULARISED; method++) {
            double Gr[3] = {0.0, 1.0, r[0]}, Tr[3] = {1.0, 0.0, -r[1]}, v0[3], vp[3], vf[3], pn, pn0, share = 0.0;
            exdex_scene_def d;
            sim_run run;
            v0[0] = vn * tan(phi) + w * r[1];
            v0[1] = -vn - w * r[0];
            v0[2] = w;
            d = strike_def(method, a, b, m, I, loc, th0, v0, r[1], mu);
            ENSURE(corner_law(W, Gr, Tr, v0, mu, vp, &pn) == 1);  /* one consistent mode */
            ENSURE(corner_law(W, Gr, Tr, v0, 0.0, vf, &pn0) == 1);
            for (int i = 0; i < 3; i++) share = fmax(share, fabs(vp[i] - vf[i]));
            ENSURE(share > 0.01 * mu * vn);
            if (method == EXDEX_METHOD_EVENT) {
                double tv = 0.0;
                for (int i = 0; i < 3; i++) tv += Tr[i] * vp[i];
                nstick += tv == 0.0 || fabs(tv) < 1e-12 * vn;
            }
            ENSURE(sim_run_def(&d, 0.002, 1e-4, &run) == EXDEX_OK);
            ENSURE(run.st.warnings == 0 && run.st.impacts == 1);
            ENSURE_CLOSE(run.st.max_impulse, pn, 1e-9 * pn + 1e-14 * m);
            for (int i = 0; i < 3; i++)
                ENSURE_CLOSE(run.tr.v[3 * (run.tr.n - 1) + i], vp[i], 1e-6 * share + 1e-14 * fabs(vp[i]) + 1e-15);
            sim_run_free(&run);
        }
    }
    ENSURE(nstick >= 1 && nstick <= 39);  /* the stream has sticking and sliding strikes */
}

/* A square box (side a, mass m; plate capacity 0.5 N, below its weight
 * m g = 0.98 N) tilted by th0 = 0.05 rad slides down between the plates
 * from rest under gravity g along -y in the plate plane onto a
 * frictional floor (normal +y, mu 0.8) a few mm below its lowest corner.
 * The corner strikes, the box turns about it (sticking), the other corner
 * lands, lifts the first, and so on: plastic impacts with rotation rates
 * shrinking geometrically, ended where the lift-off rates are below the
 * method's band (the face held flat, the slip along the floor held at 0
 * with it). The motion's end state is exact: the face flush on the floor
 * (theta = 0 to the band's rotation, y = a / 2), at rest (v = 0 exactly),
 * the floor carrying the weight (stop force m g), no warnings. */
EXDEX_TEST(fimpact_planar_face_landing_on_frictional_floor_rests_flush)
{
    double a = 0.03, m = 0.1, th0 = 0.05;
    double loc[4][2] = {{a / 2, a / 2}, {-a / 2, a / 2}, {-a / 2, -a / 2}, {a / 2, -a / 2}};
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_EVENT; method++) {
        exdex_scene_def d = exdex_default_scene_def();
        sim_run run;
        size_t last;
        d.dof = EXDEX_DOF_PLANAR;
        d.method = method;
        d.rtol = 1e-10;
        d.atol = 1e-13;
        d.mass = m;
        memset(d.inertia, 0, sizeof d.inertia);
        d.inertia[0] = d.inertia[4] = m * a * a / 12.0;
        d.inertia[8] = m * a * a / 6.0;
        d.n_vertices = 4;
        memcpy(d.vertices, loc, sizeof loc);
        d.mu = 0.5;
        d.grip_force = 0.5;
        d.gravity[0] = d.gravity[2] = 0.0;
        d.gravity[1] = -G;
        memset(d.R0, 0, sizeof d.R0);
        d.R0[0] = d.R0[4] = d.R0[8] = 1.0;
        d.q0[0] = d.q0[1] = 0.0;
        d.q0[2] = th0;
        d.n_stops = 1;
        memset(d.stop_point[0], 0, sizeof d.stop_point[0]);
        memset(d.stop_normal[0], 0, sizeof d.stop_normal[0]);
        d.stop_point[0][1] = -(a / 2) * (cos(th0) + sin(th0)) - 0.002;
        d.stop_normal[0][1] = 1.0;
        d.stop_mu[0] = 0.8;
        ENSURE(sim_run_def(&d, 0.2, 1e-3, &run) == EXDEX_OK);
        last = run.tr.n - 1;
        ENSURE(run.st.warnings == 0 && run.st.impacts >= 2);
        ENSURE_SMALL(run.tr.q[3 * last + 2], 1e-6);
        ENSURE_CLOSE(run.tr.q[3 * last + 1] - d.stop_point[0][1], a / 2, 1e-9);
        for (int i = 0; i < 3; i++) ENSURE(run.tr.v[3 * last + i] == 0.0);
        ENSURE_CLOSE(run.tr.stop_force[last], m * G, 1e-9 * m * G);
        sim_run_free(&run);
    }
}
