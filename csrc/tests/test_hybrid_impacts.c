/* test_hybrid_impacts.c -- hybrid_impacts.c: the 1-DoF impact impulse, on
 * the state of a begun event run, against the momentum balance; a stop
 * grazing a rest (sf_graze) against the closed form of its depth; a planar
 * slide into a Painleve jam: its jam ratio and arrest impulse
 * (hyb_planar_jam_impulse) against their closed forms, and the run through
 * it against the implicit method. */
#include "check.h"
#include "../hybrid.h"
#include "hybrid_scene.h"
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

/* ------------------------------------------------- a jam (Painleve)
 * A rod-like box a x b = 0.1 x 0.01 m (mass 0.1 kg, I = m (a^2 + b^2) / 12,
 * frictionless plates) in the plate plane (B = A) under gravity -9.81 m/s^2
 * along A y, its corner 3 (-a/2, -b/2) on a floor stop y >= y_s (normal +y)
 * at the angle phi, sliding to -x (slip sigma = -1). With r = R(phi) (-a/2,
 * -b/2) the corner's arm, its rows are G = (0, 1, r_x) and T = (1, 0, -r_y),
 * and the sliding mode's jam ratio is, in closed form,
 *     D / D_0 = 1 - mu sigma (G M^-1 T) / (G M^-1 G)
 *             = 1 + mu sigma r_x r_y / (I / m + r_x^2),
 * 0 at phi* = 0.5 rad for mu = (I / m + r_x^2) / (r_x r_y) there (2.18).
 * The scene starts at phi* - dphi, the corner at rest in y, turning at 15
 * rad/s towards phi* and sliding at -3 m/s. */
static exdex_scene_def jam_rod(double dphi, double *mu, double *ratio, double r[2])
{
    const double a = 0.1, b = 0.01, m = 0.1, om = 15.0;
    exdex_scene_def d = scene_plate_box(a, b, 0.01, m);
    double I = d.inertia[8], c = cos(0.5), s = sin(0.5), rx = -a / 2 * c + b / 2 * s, ry = -a / 2 * s - b / 2 * c;
    *mu = (I / m + rx * rx) / (rx * ry);
    c = cos(0.5 - dphi);
    s = sin(0.5 - dphi);
    r[0] = rx = -a / 2 * c + b / 2 * s;
    r[1] = ry = -a / 2 * s - b / 2 * c;
    *ratio = 1.0 - *mu * rx * ry / (I / m + rx * rx);
    d.gravity[0] = d.gravity[2] = 0.0;
    d.gravity[1] = -9.81;
    d.q0[0] = d.q0[1] = 0.0;
    d.q0[2] = 0.5 - dphi;
    d.v0[0] = -3.0;
    d.v0[1] = -om * rx;   /* the corner's rate along the normal: v_y + om r_x = 0 */
    d.v0[2] = om;
    scene_stop(&d, 0, 0.0, ry, 0.0, 0.0, 1.0, 0.0);
    d.stop_mu[0] = *mu;
    d.method = EXDEX_METHOD_EVENT;
    d.rtol = 1e-9;
    d.atol = 1e-12;
    return d;
}

EXDEX_TEST(hybrid_impacts_jam_arrests_the_slip_as_the_rigid_limit)
{
    /* At the jam (the ratio 2e-7 < JAM_DIR: dphi = 1.2e-7 rad) the guard
     * G_SF_JAM reads |D / D_0| - JAM_DIR of the closed form, and the
     * impulse hyb_planar_jam_impulse gives keeps the corner's normal rate
     * (0), takes its slip to 0, and is lam G + beta T with lam > 0 the
     * normal impulse the stop's force integral gets and beta = -mu sigma
     * lam / (1 - D / D_0), the Coulomb cone's edge to D / D_0 (the
     * closed form of the 2 x 2 system: G-row a0 lam + aT beta = 0). */
    double mu, ratio, r[2], y[NY_MAX], v0[3], G[3], T[3], dv[3], lam, beta, ng = 0;
    exdex_scene_def d = jam_rod(1.2e-7, &mu, &ratio, r);
    begun b;
    hyb_guard g[NG_MAX];
    int found = 0;
    ENSURE(ratio > 0.0 && ratio < JAM_DIR);
    ENSURE(begin_run(&d, 1e-3, &b) == EXDEX_OK);
    if (b.O) {
        hyb *H = &b.O->S.H;
        memcpy(y, b.O->S.y, sizeof y);
        /* sliding on the stop (the sign of contact_slip_planar's tangent
         * is its own: the closed forms take sigma T, which is not) */
        ENSURE(H->mode == MODE_SLIP && H->ncs == 1 && H->cs[0] == 3 && (H->fm[0] == SF_SLIDE_P || H->fm[0] == SF_SLIDE_M));
        ng = hyb_guards(H, 0.0, y, g);
        for (int e = 0; e < ng; e++)
            if (g[e].kind == G_SF_JAM) {
                found++;
                ENSURE_CLOSE(g[e].value, fabs(ratio) - JAM_DIR, 1e-12);
            }
        ENSURE(found == 1);
        memcpy(v0, y + 3, sizeof v0);
        G[0] = 0.0, G[1] = 1.0, G[2] = r[0];
        T[0] = 1.0, T[1] = 0.0, T[2] = -r[1];
        ENSURE(hyb_planar_jam_impulse(H, 0.0, y) == 1);
        ENSURE(b.st.warnings == 0 && b.st.impacts == 1);
        ENSURE_CLOSE(ex_dot3(G, y + 3), ex_dot3(G, v0), 1e-12);   /* normal rate kept: 0 */
        ENSURE_SMALL(ex_dot3(T, y + 3), 1e-12);                    /* slip arrested (the stop is at rest) */
        /* M dv = lam G + beta T: lam from the y row, beta from the x row */
        for (int c = 0; c < 3; c++) dv[c] = (y[3 + c] - v0[c]) / b.m->minv[c];
        lam = dv[1];
        beta = dv[0];
        ENSURE(lam > 0.0);
        ENSURE_CLOSE(y[9], lam, 1e-12 * lam);
        ENSURE_CLOSE(dv[2], lam * G[2] + beta * T[2], 1e-9 * fabs(dv[2]));
        ENSURE_CLOSE(beta, mu * lam / (1.0 - ratio), 1e-9 * fabs(beta));
    }
    end_run(&b);
}

EXDEX_TEST(hybrid_impacts_jam_run_returns_with_the_implicit_methods_limit)
{
    /* From dphi = 1e-3 (ratio 1.7e-3) the slide runs into the jam within
     * ~0.1 ms, its stop force growing without bound. The event run takes
     * the arrest impulse there (one impact, no warning) and then flies
     * free (stop force 0): at t = 0.25 ms its velocity is the implicit
     * method's at dt = 1e-7 s, an independent method (the velocity-level
     * step, whose impulse at the jam is that arrest at dt = 1e-7, 5e-9,
     * 2.5e-9 and 5e-10 s: v = (-1.0403, 1.5199, 36.684), the event run
     * within 5e-6 of each relative; at dt = 3.3e-7, 5e-8, 2e-8 and 1e-9 s
     * the step lands on the jam with a partial impulse, theta rate 26.5,
     * 18.7, 20.1, 19.2 rad/s, scattered with dt). Taken frictionless at
     * the jam (no located jam: the mode inconsistent one step past it, a
     * warning) the run ends at (-2.67, 0.77, 18.6). */
    double mu, ratio, r[2];
    exdex_scene_def d = jam_rod(1e-3, &mu, &ratio, r);
    sim_run e, im;
    int se = sim_run_def(&d, 1e-3, 2.5e-4, &e), si;
    d.method = EXDEX_METHOD_IMPLICIT;
    si = sim_run_def(&d, 1e-3, 1e-7, &im);
    ENSURE(se == EXDEX_OK && si == EXDEX_OK);
    if (se == EXDEX_OK && si == EXDEX_OK) {
        ENSURE(e.st.warnings == 0 && e.st.impacts == 1);
        ENSURE(e.tr.stop_force[2] == 0.0 && e.tr.stop_force[4] == 0.0);
        for (int c = 0; c < 3; c++) ENSURE_CLOSE(e.tr.v[3 + c], im.tr.v[3 * 2500 + c], 1e-5 * fabs(im.tr.v[3 * 2500 + c]));
    }
    sim_run_free(&e);
    sim_run_free(&im);
}
