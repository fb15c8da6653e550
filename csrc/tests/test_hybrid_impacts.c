/* test_hybrid_impacts.c -- hybrid_impacts.c: the 1-DoF impact impulse, on
 * the state of a begun event run, against the momentum balance. */
#include "check.h"
#include "../hybrid.h"

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
