/* test_fimpact.c -- impacts on frictional stops in the event and
 * regularised methods (hybrid.c: sf_impact for planar scenes,
 * impact_impulse_1dof for 1-DoF scenes) against the closed form of the
 * impulse-level law: plastic, Coulomb friction at the stop, no plate
 * impulse (the plates' friction is bounded; its impulse over an impact is
 * 0):
 *     M (v+ - v-) = G Pn + T Pt,  G v+ = b,  |Pt| <= mu Pn,
 *     Pt = -mu Pn sign(T v+ + tb) where that slip is not 0. */
#include "check.h"
#include "sim_run.h"
#include "../exdex.h"

#include <math.h>
#include <string.h>

#define G 9.81

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
    double v0[3] = {0.15, -0.2, 2.0}, c = cos(th0), s = sin(th0), r[2] = {0.0, INFINITY};
    double loc[4][2] = {{a / 2, b / 2}, {-a / 2, b / 2}, {-a / 2, -b / 2}, {a / 2, -b / 2}};
    for (int k = 0; k < 4; k++) {
        double y = s * loc[k][0] + c * loc[k][1];
        if (y < r[1]) {
            r[0] = c * loc[k][0] - s * loc[k][1];
            r[1] = y;
        }
    }
    for (int method = EXDEX_METHOD_EVENT; method <= EXDEX_METHOD_REGULARISED; method++)
        for (int im = 0; im < 3; im++) {
            double mu = im == 0 ? 0.1 : im == 1 ? 0.3 : 2.0, W[3] = {1.0 / m, 1.0 / m, 1.0 / I};
            double Gr[3] = {0.0, 1.0, r[0]}, Tr[3] = {1.0, 0.0, -r[1]}, gg = 0, gt = 0, tt = 0, gv = 0, tv = 0;
            double det, pn, pt, vp[3];
            exdex_scene_def d = exdex_default_scene_def();
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
            memcpy(d.vertices, loc, sizeof loc);
            d.mu = 0.0;
            d.grip_force = 1.0;
            d.gravity[0] = d.gravity[1] = d.gravity[2] = 0.0;
            memset(d.R0, 0, sizeof d.R0);
            d.R0[0] = d.R0[4] = d.R0[8] = 1.0;
            d.q0[0] = d.q0[1] = 0.0;
            d.q0[2] = th0;
            memcpy(d.v0, v0, sizeof v0);
            d.n_stops = 1;
            memset(d.stop_point[0], 0, sizeof d.stop_point[0]);
            memset(d.stop_normal[0], 0, sizeof d.stop_normal[0]);
            d.stop_point[0][1] = r[1];
            d.stop_normal[0][1] = 1.0;
            d.stop_mu[0] = mu;
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
