/* test_hybrid_impacts.c -- hybrid_impacts.c: the 1-DoF impact impulse, on
 * the state of a begun event run, against the momentum balance; a stop
 * grazing a rest (sf_graze) against the closed form of its depth. */
#include "check.h"
#include "../hybrid.h"
#include "sim_run.h"

#include <math.h>
#include <string.h>

/* The 1-DoF vertical scene (mass m, coordinate along B y = A z) over a stop
 * y >= -0.05 (normal along the free coordinate): a plastic impact from v to
 * vn changes the momentum by lam Fq, lam = m (vn - v) / Fq; the stop's
 * tangent is normal to the motion (no slip along it), so a frictional stop
 * (mu 0.8) takes the same impulse. */
static double impulse(double mu, double v, double vn, double *Fq)
{
    exdex_scene_def d = exdex_default_scene_def();
    exdex_model *m;
    exdex_stats st;
    exdex_kinematics kin;
    frame f;
    crow c;
    int status = 0;
    double lam = NAN, y[NY_MAX];
    ode *O;
    d.mass = 0.25;
    d.mu = 0.5;
    d.grip_force = 0.25 * 9.81 / (2 * 0.5) * 2.0;   /* capacity 2 m g: held */
    d.method = EXDEX_METHOD_EVENT;
    d.n_stops = 1;
    d.stop_point[0][2] = -0.05;
    d.stop_normal[0][2] = 1.0;
    d.stop_mu[0] = mu;
    memset(&st, 0, sizeof st);
    m = exdex_model_alloc(&d, &status, NULL);
    ENSURE(m != NULL);
    if (!m) return NAN;
    O = method_event.alloc(m, &status);
    ENSURE(O != NULL);
    if (O && method_event.begin(m, O, 1.0, 1.0, &st) == EXDEX_OK) {
        hyb *H = &O->S.H;
        memcpy(y, O->S.y, sizeof y);
        ENSURE(hyb_frame_seg(H, 0.0, &f, &kin) == EXDEX_OK);
        hyb_hrow_1dof(H, &kin, 0, 0, y[0], &c);
        *Fq = c.Fq;
        lam = hyb_impact_impulse_1dof(H, &kin, 0, 0, y[0], &c, v, vn);
        ENSURE(st.warnings == 0);
    }
    method_event.free(O);
    exdex_model_free(m);
    return lam;
}

EXDEX_TEST(hybrid_impacts_impulse_1dof_balances_momentum)
{
    double Fq = NAN, lam = impulse(0.0, -0.4, 0.0, &Fq);
    ENSURE_CLOSE(Fq, 1.0, 1e-15);   /* the gap grows with y one for one */
    ENSURE_CLOSE(lam * Fq, 0.25 * (0.0 - -0.4), 1e-15);
    ENSURE(lam > 0.0);
    ENSURE_CLOSE(impulse(0.0, -0.4, 0.1, &Fq), 0.25 * 0.5 / Fq, 1e-15);
    ENSURE(impulse(0.8, -0.4, 0.0, &Fq) == impulse(0.0, -0.4, 0.0, &Fq));
}

/* A stop that grazes a resting object (sf_graze). The square of side
 * 0.04 m (mass 0.2 kg, plates mu 0.5, capacity 10 m g, gravity along the
 * plate normal: no in-plane load) is held at rest in a gripper that moves
 * +x by X = 0.01 m in a trapezoid (duration 0.2 s, peak 0.075 m/s: it
 * decelerates at a = 0.075 / (0.2 - 0.01 / 0.075) = 1.125 m/s^2 over its
 * last ramp). A frictional stop (mu 0.5) fixed in A faces the square's
 * right face (normal -x) at x = 0.02 + X - d. Closed form in B: the gap is
 * X - d - x(t), which closes during the deceleration at the rate
 * b = sqrt(2 a d) (gap acceleration +a, turning back) and reaches its
 * deepest, -d, as the gripper stops: a graze of depth b^2 / (2 a) = d. With
 * d = rest_gap / 2 the touch is a contact of the rest: no impact, the
 * object is still at rest in B at t_end with q bit for bit its start.
 * With d = 4 rest_gap it is an impact (the rest cannot hold q within its
 * band): one impact. Either way the square ends at rest in B with its
 * right face on the stop, q = (-d, 0, 0). */
static int graze_run(double depth_in_rest_gaps, sim_run *r, double *rest_gap)
{
    const double X = 0.01, m = 0.2, side = 0.04;
    exdex_scene_def d = exdex_default_scene_def();
    int status = 0;
    exdex_model *mod;
    d.mass = m;
    d.mu = 0.5;
    d.grip_force = 10.0 * m * 9.81 / (2 * d.mu);
    d.method = EXDEX_METHOD_EVENT;
    d.dof = EXDEX_DOF_PLANAR;
    d.gravity[0] = d.gravity[1] = 0.0;
    d.gravity[2] = -9.81;
    scene_rect(&d, side / 2, side / 2);
    scene_trapezoid(&d, 0, 1.0, 0.0, 0.0, X, 0.2, 0.075);
    mod = exdex_model_alloc(&d, &status, NULL);
    ENSURE(mod != NULL);
    if (!mod) return -1;
    *rest_gap = mod->tol.rest_gap;
    exdex_model_free(mod);
    scene_stop(&d, 0, side / 2 + X - depth_in_rest_gaps * *rest_gap, 0.0, 0.0, -1.0, 0.0, 0.0);
    d.stop_mu[0] = 0.5;
    return sim_run_def(&d, 0.3, 0.01, r);
}

EXDEX_TEST(hybrid_impacts_a_graze_of_a_rest_within_its_band_is_no_impact)
{
    /* depth d in units of rest_gap: a graze up to 1, an impact above (10 %
     * either side of the threshold, and far from it) */
    const double depths[4] = {0.5, 0.9, 1.1, 4.0};
    for (int k = 0; k < 4; k++) {
        sim_run r;
        double rg = NAN;
        int st = graze_run(depths[k], &r, &rg);
        ENSURE(st == EXDEX_OK);
        if (st == EXDEX_OK) {
            const double d = depths[k] * rg, a = 0.075 / (0.2 - 0.01 / 0.075), t0 = 0.2 - sqrt(2.0 * d / a);
            size_t n = r.tr.n - 1;
            ENSURE(r.st.warnings == 0);
            ENSURE(r.st.impacts == (depths[k] > 1.0 ? 1u : 0u));
            for (size_t i = 0; i <= n && r.tr.t[i] < t0; i++)   /* held exactly before the touch */
                ENSURE(r.tr.q[3 * i] == 0.0 && r.tr.q[3 * i + 1] == 0.0 && r.tr.q[3 * i + 2] == 0.0);
            /* at rest in B at the end, the right face on the stop: x = -d */
            ENSURE(r.tr.v[3 * n] == 0.0 && r.tr.v[3 * n + 1] == 0.0 && r.tr.v[3 * n + 2] == 0.0);
            ENSURE_CLOSE(r.tr.q[3 * n], -d, 1e-3 * d);
            ENSURE_SMALL(r.tr.q[3 * n + 1], 1e-6 * d);
            ENSURE_SMALL(0.02 * r.tr.q[3 * n + 2], 1e-6 * d);
        }
        sim_run_free(&r);
    }
}
