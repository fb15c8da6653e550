/* test_wedge_stops.c -- event method, planar: an object between two nearly
 * opposed stops (a fuzz input, csrc/fuzz/corpus/simulate/wedge-two-stops,
 * with its exact doubles).
 *
 * Two outline vertices touch two stops whose in-plane rows are nearly
 * opposed; vertex 1 lifts off stop 1 at a gap rate of a few um/s, below the
 * Zeno hold threshold. Holding both rows at rate 0 would pull on both
 * stops, which no stop can do. A stop pushes only, so the separating stop
 * carries no force and the motion is the one with that stop removed:
 *     stop_force[., 1] == 0, stop_force[., 0] == the one-stop scene's force,
 * and the same trajectory.
 * twin: tests/scenarios/test_wedge_stops.py (the same subject through the Python API)
 */
#include "../check.h"
#include "../sim_run.h"
#include "../../exdex.h"

#include <math.h>

static exdex_scene_def wedge(int n_stops)
{
    static const double I[9] = {0.055122824092677013, -0.0087811566424874643, 0.0,
                                -0.0087811566424874643, 0.069133000374239806, 0.0,
                                0.0, 0.0, 0.044410478815152199};
    static const double R0[9] = {-0.52499513320740521, -0.767850183872129, 0.36713240831623251,
                                 -0.21733486374369038, -0.29611189486558587, -0.93009854462880648,
                                 0.82288861160551419, -0.56808788127071497, -0.011423311398161662};
    static const double pt[2][3] = {{-0.8001788821141842, 0.42082754812831502, 0.42591935813058623},
                                    {0.73381198196706499, 1.2576907430518904, -0.86388019631132007}};
    static const double nr[2][3] = {{-0.80066368331536042, 0.42108251324346729, 0.42617740820044103},
                                    {0.43341571842420701, 0.74283733483623493, -0.51023867845962823}};
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = 9.132626770902311;
    for (int i = 0; i < 9; i++) {
        d.inertia[i] = I[i];
        d.R0[i] = R0[i];
    }
    d.n_vertices = 2;
    d.vertices[0][0] = 0.0072280840539597074;
    d.vertices[0][1] = 0.040473816424790421;
    d.vertices[1][0] = -0.020529784645506224;
    d.vertices[1][1] = 0.0083102875743806121;
    d.mu = 0.74916603304280549;
    d.grip_force = 0.0026310180267177284;
    d.fingers = 1;
    d.e_r = 0.0023690718916116191;
    d.patch_center[0] = 0.019753055743108462;
    d.patch_center[1] = 0.025916396096897644;
    d.gravity[0] = d.gravity[1] = 0.0;
    d.gravity[2] = -9.81;
    d.dof = EXDEX_DOF_PLANAR;
    d.slide_axis[0] = 0.50519507687289711;
    d.slide_axis[1] = -0.86300517629003104;
    d.q0[0] = -0.0061257966646439815;
    d.q0[1] = 0.024607908938051454;
    d.q0[2] = -0.34758493929062562;
    d.v0[0] = d.v0[1] = d.v0[2] = 0.0;
    d.p0[0] = -1.0187268427095364;
    d.p0[1] = 1.9156756370298962;
    d.p0[2] = -1.448551316323214;
    d.motion.kind = EXDEX_MOTION_REST;
    d.n_stops = n_stops;
    for (int k = 0; k < n_stops; k++)
        for (int c = 0; c < 3; c++) {
            d.stop_point[k][c] = pt[k][c];
            d.stop_normal[k][c] = nr[k][c];
        }
    d.method = EXDEX_METHOD_EVENT;
    d.friction_solver = EXDEX_SOLVER_BRENT;
    d.eps = 0.0026218094842571744;
    d.rtol = 8.3498963157401866e-08;
    d.atol = 1.4648260118039653e-07;
    return d;
}

EXDEX_TEST(wedge_two_stops_event_forces_nonnegative_and_one_stop_total)
{
    const double t_end = 0.004452489262315929;
    exdex_scene_def d2 = wedge(2), d1 = wedge(1);
    sim_run r2, r1;
    ENSURE(sim_run_def(&d2, t_end, t_end, &r2) == EXDEX_OK);
    ENSURE(sim_run_def(&d1, t_end, t_end, &r1) == EXDEX_OK);
    if (r2.status == EXDEX_OK && r1.status == EXDEX_OK) {
        size_t n = r2.tr.n;
        ENSURE(r1.tr.n == n);
        ENSURE(r1.tr.stop_force[n - 1] > 0.0);
        for (size_t i = 0; i < n; i++) {
            ENSURE(isfinite(r2.tr.stop_force[2 * i]) && r2.tr.stop_force[2 * i] >= 0.0);
            ENSURE(r2.tr.stop_force[2 * i + 1] == 0.0);
            ENSURE_CLOSE(r2.tr.stop_force[2 * i] + r2.tr.stop_force[2 * i + 1], r1.tr.stop_force[i],
                         1e-12 * fabs(r1.tr.stop_force[i]));
            for (int c = 0; c < 3; c++) ENSURE_CLOSE(r2.tr.v[3 * i + c], r1.tr.v[3 * i + c], 1e-12);
        }
    }
    sim_run_free(&r2);
    sim_run_free(&r1);
}
