/* test_hybrid_decide.c -- rules of the hybrid methods' decision
 * (hybrid_decide.c), called directly on the state of a begun event run,
 * against closed forms.
 *
 * hyb_hold_set_rows: at a decision the contact set's obstacle rows are put
 * back onto their features, positions and velocities, by the M-metric
 * projection onto the set rows as equalities. The scene: a box (a x b,
 * mass m) sliding freely (mu = 0, gravity along the plate normal, B = A) on
 * the top face y = -b/2 of an obstacle box, its two lower corners (x_j =
 * +-a/2, -b/2) in the contact set. Each corner's row against the face has
 * G_j = (0, 1, x_j) (d gap / d(x, y, theta) at theta = 0) and gap y (a
 * translation). Lifted by delta and moving up at w (a drift the decision
 * must remove), the projection solves G_j dq = -delta for both rows with
 * dq = M^-1 G^T lam: by the symmetry x_1 = -x_2, lam_1 = lam_2, so dq =
 * (0, -delta, 0); and G_j v = 0 with v = v0 + M^-1 G^T mu: (vx, 0, 0), vx
 * untouched (G has no x component). Rows left on their face are left
 * alone (bit for bit). */
#include "check.h"
#include "hybrid_scene.h"
#include "sim_run.h"

#include <math.h>
#include <string.h>

#define BOX_A 0.04
#define BOX_B 0.02

static exdex_scene_def slide_def(double vx)
{
    double a = BOX_A, b = BOX_B, top = -b / 2, h = 0.05;
    exdex_scene_def d = scene_plate_box(a, b, 0.01, 0.1);
    d.grip_force = 1.0;
    d.fingers = 2;
    d.e_r = 0.0033;
    d.v0[0] = vx;
    /* the obstacle: a box 0.2 x h x 0.1 below the object, top face y = -b/2 */
    scene_obstacle_box(&d, 0, (const double[3]){0.0, top - h / 2, 0.0}, (const double[3]){0.1, h / 2, 0.05});
    d.obstacles[0].mu = 0.0;
    d.method = EXDEX_METHOD_EVENT;
    d.rtol = 1e-10;
    d.atol = 1e-10;
    return d;
}

EXDEX_TEST(hold_set_rows_puts_drifted_obstacle_rows_back_on_their_face)
{
    const double vx = 0.01, delta = 1e-5, w = 0.003;
    exdex_scene_def d = slide_def(vx);
    begun b;
    exdex_kinematics kin;
    frame f;
    int code[MAX_ROWS], n, ncs = 0;
    double gap[MAX_ROWS], y[NY_MAX], y_on[NY_MAX];
    ENSURE(begin_run(&d, 1.0, &b) == EXDEX_OK);
    const exdex_model *m = b.m;
    ode *O = b.O;
    hyb *H = &O->S.H;
    ENSURE(H->law == LAW_COULOMB && H->mode == MODE_SLIP && H->no == 1 && H->ns == 0);
    memcpy(y, O->S.y, sizeof y);
    ENSURE(hyb_frame_seg(H, 0.0, &f, &kin) == EXDEX_OK);
    /* the lower corners' rows against the top face: the contact set */
    n = orow_all(m, &kin, y, y + 3, 1, code, gap);
    for (int i = 0; i < n; i++)
        if (orow_kind(code[i]) == OROW_VERTEX && fabs(gap[i]) <= 1e-15) H->cs[ncs++] = code[i];
    ENSURE(ncs == 2);
    H->ncs = ncs;
    H->sgn = 0;
    /* on the face: left alone */
    memcpy(y_on, y, sizeof y_on);
    hyb_hold_set_rows(H, 0.0, y);
    ENSURE(memcmp(y, y_on, (size_t)H->ny * sizeof *y) == 0);
    /* lifted by delta, moving up at w */
    y[1] = delta;
    y[4] = w;
    hyb_hold_set_rows(H, 0.0, y);
    /* to rounding: 1e-12 of the drift removed (delta in position, w in rate;
     * theta's part relative to them over the half-width a / 2) */
    ENSURE(y[0] == 0.0);
    ENSURE_SMALL(y[1], 1e-12 * delta);
    ENSURE_SMALL(y[2], 1e-12 * delta / (BOX_A / 2));
    ENSURE(y[3] == vx);
    ENSURE_SMALL(y[4], 1e-12 * w);
    ENSURE_SMALL(y[5], 1e-12 * w / (BOX_A / 2));
    for (int i = 0; i < ncs; i++) {
        double G[3], gd;
        ENSURE_SMALL(orow_planar(m, &kin, H->cs[i], y, y + 3, G, &gd, NULL), 1e-12 * delta);
        ENSURE_SMALL(gd, 1e-12 * w);
    }
    end_run(&b);
}

/* ------------------------------------------------ the decision's rules
 * Each test below names the rule of hybrid_decide.c's policy (T1 .. T9) it
 * checks, on the state of a begun event run, the decision called directly
 * (hyb_decide at a segment start, hyb_decide_event at a located event). */

/* An event run begun for 1 s (hybrid_scene.h's begin_run), its hybrid state. */
static hyb *begin_event(const exdex_scene_def *d, begun *b)
{
    int status = begin_run(d, 1.0, b);
    ENSURE(status == EXDEX_OK);
    return status == EXDEX_OK ? &b->O->S.H : NULL;
}

static void end_event(begun *b) { end_run(b); }

/* The 1-DoF vertical scene (mass m, B y up, gravity g down), mu 0.5 on two
 * fingers, capacity ratio x m g, stops none. */
static exdex_scene_def vertical_def(double ratio)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = 0.3;
    d.grip_force = ratio * d.mass * 9.81 / (2 * d.mu);
    d.method = EXDEX_METHOD_EVENT;
    return d;
}

/* T1, 1-DoF: at rest the load is the weight, Q0 = -m g (closed form); the
 * object sticks iff |Q0| <= C_s (1 + FRICTION_BAND), a load on the limit
 * sticks, one just beyond the band slips in the load's sign (down). */
EXDEX_TEST(decide_1dof_sticks_iff_the_load_is_within_the_static_band)
{
    exdex_scene_def d = vertical_def(2.0);
    begun b;
    frame f;
    exdex_kinematics kin;
    hyb *H = begin_event(&d, &b);
    double y[NY_MAX], Q0;
    if (!H) {
        end_event(&b);
        return;
    }
    ENSURE(H->mode == MODE_STICK && H->s == 0.0);   /* capacity 2 m g */
    memcpy(y, b.O->S.y, sizeof y);
    ENSURE(hyb_frame_seg(H, 0.0, &f, &kin) == EXDEX_OK);
    Q0 = model_force_1dof(b.m, &f, y[0], 0.0);
    ENSURE_CLOSE(Q0, -0.3 * 9.81, 1e-15);
    H->caps = fabs(Q0);                                  /* on the limit */
    hyb_decide(H, 0.0, y, 1);
    ENSURE(H->mode == MODE_STICK && y[1] == 0.0);
    H->caps = fabs(Q0) / (1.0 + 0.5 * FRICTION_BAND);    /* inside the band */
    hyb_decide(H, 0.0, y, 1);
    ENSURE(H->mode == MODE_STICK);
    H->caps = fabs(Q0) / (1.0 + 4.0 * FRICTION_BAND);    /* beyond it */
    hyb_decide(H, 0.0, y, 1);
    ENSURE(H->mode == MODE_SLIP && H->s == -1.0 && y[1] == 0.0);
    end_event(&b);
}

/* T4, T5, 1-DoF: the object's point on a stop fixed in B (gap 0, rate 0).
 * A stop below it (normal up) carries what it can at rest, the whole
 * weight (lam = m g / Fq > 0, the friction 0): a contact at rest (s = 0, y
 * at rate 0), whether the friction could hold the weight (capacity 2 m g)
 * or not (0.5 m g). A stop above it (normal down): the weight pulls the
 * point away, the stop force of that rest is 0, which keeps no contact
 * (T5): a stick under 2 m g, a slip down (away) under 0.5 m g. */
EXDEX_TEST(decide_1dof_rest_on_a_stop_is_a_contact_only_where_the_stop_pushes)
{
    const double ratios[2] = {0.5, 2.0};
    for (int up = 0; up < 2; up++)
        for (int i = 0; i < 2; i++) {
            exdex_scene_def d = vertical_def(ratios[i]);
            begun b;
            hyb *H;
            d.n_stops = 1;
            d.stop_normal[0][2] = up ? -1.0 : 1.0;   /* through the object's point */
            H = begin_event(&d, &b);
            if (H && !up) ENSURE(H->mode == MODE_CONTACT && H->s == 0.0 && H->ck == 0 && b.O->S.y[1] == 0.0);
            if (H && up && i == 1) ENSURE(H->mode == MODE_STICK && H->s == 0.0);
            if (H && up && i == 0) ENSURE(H->mode == MODE_SLIP && H->s == -1.0);
            end_event(&b);
        }
}

/* T1, T5, 1-DoF, a released grip: the object's point on a stop below it,
 * fixed in B, its normal tilted from the slide axis by a (n = (sin a, 0,
 * cos a) in A, so d gap / dq = Fq = cos a), capacity 0. The closed form of
 * the rest: one coordinate and one constraint, M qdd = Q + f + lam Fq with
 * qdd = 0, so the stop carries the whole load R = -Q0 = m g, lam = R / Fq >
 * 0, and the plates nothing, f = 0 exactly: a contact at rest at every
 * capacity, 0 included. Over the tilts the rounding residual R - (R / Fq)
 * Fq is an ulp of R at some of them; taken as the plates' friction it
 * exceeds a capacity of 0, and the decision slipped into the stop. */
EXDEX_TEST(decide_1dof_rest_on_a_pushing_stop_holds_with_the_grip_released)
{
    for (int k = 0; k < 60; k++) {
        const double a = 0.02 * k;
        exdex_scene_def d = vertical_def(0.5);
        begun b;
        frame f;
        exdex_kinematics kin;
        hyb *H;
        double y[NY_MAX], R, fr, lam;
        crow c;
        d.mass = 0.3 + 0.01 * k;
        d.grip_force = 0.5 * d.mass * 9.81 / (2 * d.mu);
        d.n_stops = 1;
        d.stop_normal[0][0] = sin(a);
        d.stop_normal[0][2] = cos(a);
        H = begin_event(&d, &b);
        if (!H) {
            end_event(&b);
            continue;
        }
        ENSURE(H->mode == MODE_CONTACT && H->s == 0.0 && H->ck == 0);
        memcpy(y, b.O->S.y, sizeof y);
        ENSURE(hyb_frame_seg(H, 0.0, &f, &kin) == EXDEX_OK);
        hyb_hrow_1dof(H, &kin, 0, 0, y[0], &c);
        ENSURE(c.Fq > 0.0);
        R = -model_force_1dof(b.m, &f, y[0], 0.0);
        ENSURE(R > 0.0);
        hyb_contact_forces(H, &c, 0.0, R, 0.0, &fr, &lam);
        ENSURE(fr == 0.0 && lam == R / c.Fq);
        H->cap = H->caps = 0.0;   /* the grip released */
        hyb_decide(H, 0.0, y, 0);
        ENSURE(H->mode == MODE_CONTACT && H->s == 0.0 && H->ck == 0 && y[1] == 0.0);
        end_event(&b);
    }
}

/* T1, T5, 1-DoF, through a run: decide_1dof_rest_on_a_pushing_stop_holds_
 * with_the_grip_released's rest (the point on a stop below it, fixed in B,
 * its normal tilted by a), the grip a cubic schedule from the capacity
 * 0.5 m g at t = 0 to 0 at t = 0.5 s, the run to 1 s at output steps 1/8,
 * 1/7, 1/9 s. The closed form: nothing moves the object (the stop fixed in
 * B carries the whole load m g along q), so at every sample q = q0, qd = 0
 * exactly, the step stuck and the plates' mean wrench is exactly 0 (their
 * share of the rest, f = 0, hyb_contact_forces), the stop's mean force > 0.
 * These hold exactly: the gripper at rest gives the stop's rates 0, the
 * stop through the object's point its gap 0, and the plates' share is set
 * to 0. The grip's breakpoint at 0.5 s ends a step with a decision at
 * capacity 0: a rounding residual R - (R / Fq) Fq taken there as the
 * plates' friction fails the stick test and slips the object along the
 * stop, at the tilts where that residual is not 0, an answer that depends
 * on where the run's steps end (the 1-DoF rest of
 * tests/scenarios/test_zoo_inputs.py's seed 1126 at its grip's release). */
EXDEX_TEST(event_run_rest_on_a_pushing_stop_holds_through_a_grip_released_at_a_breakpoint)
{
    static const double ts[2] = {0.0, 0.5};
    static const int n_out[3] = {8, 7, 9};
    for (int k = 0; k < 60; k++)
        for (int g = 0; g < 3; g++) {
            const double a = 0.02 * k;
            exdex_scene_def d = vertical_def(0.5);
            double fs[2];
            sim_run r;
            d.mass = 0.3 + 0.01 * k;
            fs[0] = 0.5 * d.mass * 9.81 / (2 * d.mu);
            fs[1] = 0.0;
            d.grip_force = 1.0;
            d.grip_n = 2;
            d.grip_times = ts;
            d.grip_forces = fs;
            d.grip_kind = EXDEX_GRIP_CUBIC;
            d.n_stops = 1;
            d.stop_normal[0][0] = sin(a);
            d.stop_normal[0][2] = cos(a);
            ENSURE(sim_run_def(&d, 1.0, 1.0 / n_out[g], &r) == EXDEX_OK);
            for (size_t i = 1; i < r.tr.n && r.status == EXDEX_OK; i++) {
                ENSURE(r.tr.q[i] == r.tr.q[0] && r.tr.v[i] == 0.0 && r.tr.stick[i]);
                ENSURE(r.tr.wrench[3 * i] == 0.0 && r.tr.wrench[3 * i + 1] == 0.0 && r.tr.wrench[3 * i + 2] == 0.0);
                ENSURE(r.tr.stop_force[i] > 0.0);
            }
            sim_run_free(&r);
        }
}

/* The mean of max(1 + 2 cos w t, 0) over [t0, t1]: the antiderivative
 * t + 2 sin(w t) / w over the parts of [t0, t1] in the intervals
 * [k P - P / 3, k P + P / 3] (P = 2 pi / w) where cos w t >= -1/2. */
static double unload_mean(double w, double t0, double t1)
{
    const double P = 2.0 * M_PI / w;
    double s = 0.0;
    for (int k = 0; k <= (int)(t1 / P) + 1; k++) {
        double a = fmax(t0, k * P - P / 3.0), b = fmin(t1, k * P + P / 3.0);
        if (b > a) s += (b + 2.0 * sin(w * b) / w) - (a + 2.0 * sin(w * a) / w);
    }
    return s / (t1 - t0);
}

/* T1, T5, 1-DoF, through a run: a rest on a stop that unloads inside a
 * step while the plates hold. The point on a stop below it (normal n =
 * (sin a, 0, cos a), a = 0.5, so Fq = cos a), the gripper shaken along the
 * stop (axis (cos a, 0, -sin a): the stop stays fixed in B), s(t) = A (1 -
 * cos w t), f = 5 Hz, for 0.4 s, A w^2 sin a = -2 g. The load along q at
 * rest is Q = -m g + m s'' sin a = -m g (1 + 2 cos w t): the stop pushes
 * (lam = -Q / Fq) while cos w t > -1/2 and unloads inside the steps over
 * (1/3, 2/3) of each period, where the plates hold a pull up to m g. Two
 * graspings: capacity 2 m g (mu_static = mu), and kinetic 0.8 m g with
 * mu_static = 1.5 mu (static 1.2 m g: the pull is held only by the static
 * capacity, which the rest's guard uses). The closed form: the object
 * stays at q0 with qd = 0, and each step's mean stop force is (m g / Fq)
 * unload_mean over it (m g / Fq after the shake), at output steps 0.5 / n
 * for n = 4, 7, 8, 9, 16, 64, rtol 1e-10: q and qd within 1e-15 m and
 * 1e-14 m/s (rounding of the stop's rates in B, ~1e-17 m and 1e-16 m/s),
 * the stop force within 1e-7 of m g / Fq (the integration of its mean,
 * ~1e-9). A slip would move q by millimetres, a stop force carried through
 * the unload (negative) or a plate share of a pushing stop's load would
 * move the means by a fraction of m g / Fq. */
EXDEX_TEST(event_run_rest_on_a_stop_unloading_inside_a_step_is_held_by_the_plates)
{
    static const int n_out[6] = {4, 7, 8, 9, 16, 64};
    const double al = 0.5, f = 5.0, w = 2.0 * M_PI * f, g = 9.81, mass = 0.3, t_shake = 0.4;
    for (int ms = 0; ms < 2; ms++)
        for (int io = 0; io < 6; io++) {
            exdex_scene_def d = scene_vertical(mass, ms ? 0.8 : 2.0);
            const double lam0 = mass * g / cos(al);
            sim_run r;
            d.n_stops = 1;
            d.stop_normal[0][0] = sin(al);
            d.stop_normal[0][2] = cos(al);
            if (ms) d.mu_static = 1.5 * d.mu;
            d.motion.kind = EXDEX_MOTION_SHAKE;
            d.motion.axis[0] = cos(al);
            d.motion.axis[2] = -sin(al);
            d.motion.amplitude = -2.0 * g / sin(al) / (w * w);
            d.motion.frequency = f;
            d.motion.duration = t_shake;
            d.method = EXDEX_METHOD_EVENT;
            d.rtol = 1e-10;
            d.atol = 1e-10;
            ENSURE(sim_run_def(&d, 0.5, 0.5 / n_out[io], &r) == EXDEX_OK);
            ENSURE(r.st.warnings == 0);
            for (size_t i = 1; i < r.tr.n && r.status == EXDEX_OK; i++) {
                double t0 = r.tr.t[i - 1], t1 = r.tr.t[i];
                ENSURE_SMALL(r.tr.q[i] - r.tr.q[0], 1e-15);
                ENSURE_SMALL(r.tr.v[i], 1e-14);
                if (t1 <= t_shake) ENSURE_SMALL(r.tr.stop_force[i] - lam0 * unload_mean(w, t0, t1), 1e-7 * lam0);
                if (t0 >= t_shake) ENSURE_SMALL(r.tr.stop_force[i] - lam0, 1e-7 * lam0);
            }
            sim_run_free(&r);
        }
}

/* A planar scene (B = A, the plate plane A's x-y plane) with gravity g
 * along -y in it: a square 4 x 4 cm, mass 0.2, the patch at its centre of
 * mass, capacity ratio x m g; no stops. */
static exdex_scene_def planar_def(double ratio)
{
    double a = 0.04, m = 0.2;
    exdex_scene_def d = scene_plate_box(a, a, 0.0, m);
    d.mu = 0.5;
    d.grip_force = ratio * m * 9.81 / (2 * d.mu);
    d.e_r = 0.005;
    d.gravity[1] = -9.81;
    d.gravity[2] = 0.0;
    d.method = EXDEX_METHOD_EVENT;
    return d;
}

/* planar_def(ratio)'s square standing on a stop along its lower face
 * (y >= -a/2), the stop's friction mu_s, gravity tilted in the plate plane
 * from -y toward +x by beta, tan beta = tb. */
static exdex_scene_def planar_on_stop_def(double ratio, double mu_s, double tb)
{
    exdex_scene_def d = planar_def(ratio);
    double c = sqrt(1.0 + tb * tb);
    d.gravity[0] = 9.81 * (tb / c);
    d.gravity[1] = -9.81 * (1.0 / c);
    scene_stop(&d, 0, 0.0, -0.02, 0.0, 0.0, 1.0, 0.0);
    d.stop_mu[0] = mu_s;
    return d;
}

/* T1 planar and the slip's start: at rest the load is the weight, a pure
 * force (0, -m g) at the patch (no moment: the patch at the centre of
 * mass); capacity 2 m g holds it (a stick), capacity 0.5 m g does not: a
 * small slip whose reference direction is the slip acceleration's, by the
 * symmetry of the ellipsoid about its force axes straight down (E u along
 * -y, no x, no spin). */
EXDEX_TEST(decide_planar_rest_sticks_inside_the_limit_and_slips_along_the_load_outside)
{
    const double ratios[2] = {2.0, 0.5};
    for (int i = 0; i < 2; i++) {
        exdex_scene_def d = planar_def(ratios[i]);
        begun b;
        hyb *H = begin_event(&d, &b);
        if (!H) {
            end_event(&b);
            continue;
        }
        ENSURE(H->law == LAW_COULOMB && H->ndof == 3 && H->ncs == 0);
        if (i == 0) ENSURE(H->mode == MODE_STICK);
        if (i == 1) {
            ENSURE(H->mode == MODE_SLIP && H->small == 1);
            ENSURE(H->uref[1] < 0.0);
            ENSURE_SMALL(H->uref[0], 1e-15 * fabs(H->uref[1]));
            ENSURE_SMALL(H->uref[2], 1e-15 * fabs(H->uref[1]));
        }
        end_event(&b);
    }
}

/* b's run in a slip (small: a small slip), its planar state y with the
 * velocity (0, vy, 0) (a slide along -y at |E u| = |vy|: e = (1, 1, e_r),
 * the patch at the centre of mass). */
static void planar_slipping_down(begun *b, double *y, double vy, int small)
{
    memcpy(y, b->O->S.y, NY_MAX * sizeof *y);
    y[3] = 0.0;
    y[4] = vy;
    y[5] = 0.0;
    b->O->S.H.mode = MODE_SLIP;
    b->O->S.H.small = small;
}

/* T2, the small slip's band and its hysteresis: a slide at 1.5 zsw whose
 * load the friction cannot hold (capacity 0.5 m g) stays a small slip if
 * it was one (band SLIP_UP zsw = 2 zsw), and is a slip (its reference E u,
 * the velocity kept) if it was not (band zsw); at 0.5 zsw it is a small
 * slip either way, velocity kept; at 0.5 zsw under capacity 2 m g it stops
 * (qd = 0) and sticks. */
EXDEX_TEST(decide_planar_small_slip_band_and_its_hysteresis)
{
    for (int held = 0; held < 2; held++) {
        exdex_scene_def d = planar_def(held ? 2.0 : 0.5);
        begun b;
        hyb *H = begin_event(&d, &b);
        double y[NY_MAX], z;
        if (!H) {
            end_event(&b);
            continue;
        }
        ENSURE(b.m->e[0] == 1.0 && b.m->e[1] == 1.0);
        ENSURE(SLIP_UP == 2.0);
        z = H->zsw;
        ENSURE(z > 0.0);
        if (!held) {
            for (int small = 0; small < 2; small++) {
                planar_slipping_down(&b, y, -1.5 * z, small);
                hyb_decide(H, 0.0, y, 0);
                ENSURE(H->mode == MODE_SLIP && H->small == small && y[4] == -1.5 * z && y[3] == 0.0);
                if (!small) ENSURE(H->uref[1] == -1.5 * z && H->uref[0] == 0.0 && H->uref[2] == 0.0);
                planar_slipping_down(&b, y, -0.5 * z, small);
                hyb_decide(H, 0.0, y, 0);
                ENSURE(H->mode == MODE_SLIP && H->small == 1 && y[4] == -0.5 * z);
            }
        } else {
            planar_slipping_down(&b, y, -0.5 * z, 0);
            hyb_decide(H, 0.0, y, 0);
            ENSURE(H->mode == MODE_STICK && y[3] == 0.0 && y[4] == 0.0 && y[5] == 0.0);
        }
        end_event(&b);
    }
}

/* T8 at an event: a slip whose decay guard fell (|E u| below zsw) stops
 * where the load can be held (a stick, qd = 0) and else slips on as a small
 * slip with its velocity kept; a slip whose E u turned against its
 * reference above zsw only renews the reference (on as a slip), below zsw
 * it is a stop like a decay. */
EXDEX_TEST(decide_event_decayed_and_turned_slips)
{
    for (int held = 0; held < 2; held++) {
        exdex_scene_def d = planar_def(held ? 2.0 : 0.5);
        begun b;
        hyb *H = begin_event(&d, &b);
        double y[NY_MAX], z;
        if (!H) {
            end_event(&b);
            continue;
        }
        z = H->zsw;
        /* decayed to 0.9 zsw */
        planar_slipping_down(&b, y, -0.9 * z, 0);
        ENSURE(hyb_decide_event(H, 0.0, y, hg(G_SLIP_DECAYS, -1, 0.0, -1e-3 * z), 0) == EXDEX_OK);
        if (held) ENSURE(H->mode == MODE_STICK && y[4] == 0.0);
        if (!held) ENSURE(H->mode == MODE_SLIP && H->small == 1 && y[4] == -0.9 * z);
        /* turned: the reference was up, the slide is down at 3 zsw */
        planar_slipping_down(&b, y, -3.0 * z, 0);
        H->uref[0] = H->uref[2] = 0.0;
        H->uref[1] = 3.0 * z;
        ENSURE(hyb_decide_event(H, 0.0, y, hg(G_SLIP_TURNS, -1, 0.0, -1e-3 * z), 0) == EXDEX_OK);
        ENSURE(H->mode == MODE_SLIP && H->small == 0 && y[4] == -3.0 * z && H->uref[1] == -3.0 * z);
        /* turned below zsw: a stop (held: a stick; else a small slip from rest, down) */
        planar_slipping_down(&b, y, -0.5 * z, 0);
        ENSURE(hyb_decide_event(H, 0.0, y, hg(G_SLIP_TURNS, -1, 0.0, -1e-3 * z), 0) == EXDEX_OK);
        ENSURE(y[4] == 0.0);
        if (held) ENSURE(H->mode == MODE_STICK);
        if (!held) ENSURE(H->mode == MODE_SLIP && H->small == 1 && H->uref[1] < 0.0);
        end_event(&b);
    }
}

/* T2 at the small slip's band edge, against set rows: the square of
 * planar_def on a frictionless stop along its lower face (y >= -a/2),
 * plate capacity 0.5 m g, gravity tilted in the plate plane by beta from
 * -y, a small slip along +x grown to SLIP_UP zsw (G_SMALL_GROWS) with both
 * lower corners in the set. At rest the stop carries the weight's normal
 * part, the plate the part along the stop, m g sin beta (closed form): for
 * beta = 0 that is 0 <= C, so the object stops (qd = 0, a stick); for tan
 * beta = 0.8, sin beta = 0.625 > 0.5 (1 + FRICTION_BAND), it cannot be
 * held and slips on as a slip, velocity kept. */
EXDEX_TEST(decide_event_small_slip_grown_against_set_rows_stops_where_held)
{
    for (int tilt = 0; tilt < 2; tilt++) {
        exdex_scene_def d = planar_on_stop_def(0.5, 0.0, tilt ? 0.8 : 0.0);
        begun b;
        hyb *H = begin_event(&d, &b);
        double y[NY_MAX], z;
        if (!H) {
            end_event(&b);
            continue;
        }
        ENSURE(H->ncs == 2 && !H->sfric);
        z = H->zsw;
        memcpy(y, b.O->S.y, sizeof y);
        y[3] = SLIP_UP * z;
        y[4] = y[5] = 0.0;
        H->mode = MODE_SLIP;
        H->small = 1;
        ENSURE(hyb_decide_event(H, 0.0, y, hg(G_SMALL_GROWS, -1, 0.0, -1e-3 * z), 0) == EXDEX_OK);
        if (!tilt) ENSURE(H->mode == MODE_STICK && y[3] == 0.0 && y[4] == 0.0 && y[5] == 0.0);
        if (tilt) ENSURE(H->mode == MODE_SLIP && H->small == 0 && y[3] == SLIP_UP * z && y[4] == 0.0);
        end_event(&b);
    }
}

/* The decision as one array of row states (hyb_row_states). 1-DoF: the
 * object's point on a stop below it at rest (above: a contact at rest) is
 * the plate at rest and the stop's row in contact, its friction sign 0.
 * Planar: the square of planar_def at rest on a frictional stop along its
 * lower face (y >= -a/2, mu 0.5) under capacity 2 m g: the least-friction
 * split of the rest puts the weight on the stop, so the plate sticks; the
 * rows in contact are the two lower corners (vertices 0 and 3, rows k nv +
 * j = 0 and 3), one friction group (the stop's line) that sticks, as its
 * slip at rest is 0. */
EXDEX_TEST(decide_row_states_of_a_rest_on_a_stop)
{
    hyb_row_state rs[HYB_ROWS_MAX];
    for (int planar = 0; planar < 2; planar++) {
        exdex_scene_def d = planar ? planar_on_stop_def(2.0, 0.5, 0.0) : vertical_def(2.0);
        begun b;
        hyb *H;
        int n;
        if (!planar) {
            d.n_stops = 1;
            d.stop_normal[0][2] = 1.0;
        }
        H = begin_event(&d, &b);
        if (!H) {
            end_event(&b);
            continue;
        }
        n = hyb_row_states(H, rs);
        ENSURE(rs[0].kind == ROW_PLATE && rs[0].mode == RS_STICK && rs[0].dir == 0.0);
        if (!planar) {
            ENSURE(n == 2);
            ENSURE(n == 2 && rs[1].kind == ROW_STOP && rs[1].src == 0 && rs[1].row == 0 && rs[1].mode == RS_CONTACT &&
                   rs[1].dir == 0.0);
        } else {
            ENSURE(n == 4);
            ENSURE(n == 4 && rs[1].kind == ROW_STOP && rs[2].kind == ROW_STOP && rs[1].src == 0 && rs[2].src == 0);
            ENSURE(n == 4 && ((rs[1].row == 0 && rs[2].row == 3) || (rs[1].row == 3 && rs[2].row == 0)));
            ENSURE(n == 4 && rs[1].mode == RS_CONTACT && rs[2].mode == RS_CONTACT && rs[1].group == rs[2].group &&
                   rs[1].group >= 0);
            ENSURE(n == 4 && rs[3].kind == ROW_GROUP && rs[3].row == rs[1].group && rs[3].mode == RS_GROUP_STICK);
        }
        end_event(&b);
    }
}

/* T9 in a small slip, on the square of planar_def standing on a frictional
 * stop along its lower face (y >= -a/2, stop mu 0.5), gravity tilted in
 * the plate plane by beta from -y (tan beta 0.8 > mu), plate capacity 0.1 m
 * g: the load along the stop, m g sin beta - 0.1 m g at least (0.525 m g),
 * exceeds what the stop's friction can take, mu m g cos beta (0.39 m g),
 * so the object starts to slide along the stop, downhill (+x). The
 * decision's stop friction modes are a fixed point (the rule): the problem
 * solved on the plate friction of the decided modes, every group left to
 * it, decides them again; its solution slides the object along +x (the
 * sign of gravity's part along the stop) with no acceleration normal to
 * the stop. */
EXDEX_TEST(decide_small_slip_stop_friction_modes_are_a_fixed_point)
{
    exdex_scene_def d = planar_on_stop_def(0.1, 0.5, 0.8);
    begun b;
    hyb *H = begin_event(&d, &b);
    frame f;
    exdex_kinematics kin;
    sf_result res;
    double a[3], y[NY_MAX];
    int fm[SF_MAX_STOPS], ng;
    if (!H) {
        end_event(&b);
        return;
    }
    ENSURE(H->mode == MODE_SLIP && H->small == 1 && H->ncs == 2 && H->sgn == 1);
    ENSURE(H->fm[0] == SF_SLIDE_P || H->fm[0] == SF_SLIDE_M);
    ng = H->sgn;
    memcpy(fm, H->fm, sizeof fm);
    memcpy(y, b.O->S.y, sizeof y);
    ENSURE(hyb_frame_seg(H, 0.0, &f, &kin) == EXDEX_OK);
    ENSURE(hyb_sf_free_acc(H, &f, &kin, y, a) == EXDEX_OK);
    for (int k = 0; k < ng; k++) H->fm[k] = SF_ROLL;
    ENSURE(hyb_sf_solve_at(H, &kin, y, a, &res) == 1);
    for (int k = 0; k < ng; k++) ENSURE(res.fm[k] == fm[k]);
    ENSURE(res.qdd[0] > 0.0);
    ENSURE_SMALL(res.qdd[1], 1e-12 * res.qdd[0]);
    ENSURE_SMALL(res.qdd[2], 1e-12 * res.qdd[0] / 0.02);
    end_event(&b);
}

/* T9 in a small slip with two consistent modes: the square of planar_def
 * standing on a stop along its lower face (stop mu 1.0), gravity tilted by
 * beta from -y toward +x (tan beta 3), plate capacity 0.5 m g, the patch 1
 * cm to the right of the centre of mass. The object starts to turn about
 * its lower right corner (vertex 0, r = (a/2, -a/2) from the centre of
 * mass, the set's one row). Two modes are consistent at their own plate
 * wrench (the plate solved with the stops as one more contact on the given
 * modes, hyb_sf_free_acc, then the problem from rolling decides them
 * again): the corner sticking, and the corner sliding back (-x). The rule
 * keeps the first in stop_friction.h's order, stick before slide: the
 * decision sticks, and the plate's friction with the group rolling is the
 * stick's. A decision that took the slide (a search ending on a later
 * candidate, a fallback) fails the test. At the sticking mode the corner
 * does not accelerate (closed form of a pivot at rest: a_x = thdd r_y, a_y
 * = -thdd r_x) and its friction is inside the cone by more than 5 %
 * (|beta| <= 0.95 mu sum lam). */
EXDEX_TEST(decide_small_slip_stop_friction_keeps_the_first_fixed_point_in_order)
{
    const double mu_s = 1.0, r[2] = {0.02, -0.02};
    exdex_scene_def d = planar_on_stop_def(0.5, mu_s, 3.0);
    begun b;
    hyb *H;
    frame f;
    exdex_kinematics kin;
    sf_result res;
    double a[3], y[NY_MAX], s;
    d.patch_center[0] = 0.01;
    H = begin_event(&d, &b);
    if (!H) {
        end_event(&b);
        return;
    }
    ENSURE(H->mode == MODE_SLIP && H->small == 1 && H->ncs == 1 && H->cs[0] == 0 && H->sgn == 1);
    ENSURE(H->fm[0] == SF_STICK);
    memcpy(y, b.O->S.y, sizeof y);
    ENSURE(hyb_frame_seg(H, 0.0, &f, &kin) == EXDEX_OK);
    /* the stick: a fixed point, a pivot about the corner, inside the cone */
    H->fm[0] = SF_STICK;
    ENSURE(hyb_sf_free_acc(H, &f, &kin, y, a) == EXDEX_OK);
    H->fm[0] = SF_ROLL;
    ENSURE(hyb_sf_solve_at(H, &kin, y, a, &res) == 1);
    ENSURE(res.fm[0] == SF_STICK && !res.lock);
    s = fabs(res.qdd[2]) * 0.02;
    ENSURE(s > 0.0);
    ENSURE_CLOSE(res.qdd[0], res.qdd[2] * r[1], 1e-12 * s);
    ENSURE_CLOSE(res.qdd[1], -res.qdd[2] * r[0], 1e-12 * s);
    ENSURE(res.lsum[0] > 0.0 && fabs(res.beta[0]) <= 0.95 * mu_s * res.lsum[0]);
    /* the slide back: a fixed point too, later in the order */
    H->fm[0] = SF_SLIDE_M;
    ENSURE(hyb_sf_free_acc(H, &f, &kin, y, a) == EXDEX_OK);
    H->fm[0] = SF_ROLL;
    ENSURE(hyb_sf_solve_at(H, &kin, y, a, &res) == 1);
    ENSURE(res.fm[0] == SF_SLIDE_M);
    /* every group rolling: the plate's friction is the stick's, which the
     * problem decides again */
    H->fm[0] = SF_ROLL;
    ENSURE(hyb_sf_free_acc(H, &f, &kin, y, a) == EXDEX_OK);
    ENSURE(hyb_sf_solve_at(H, &kin, y, a, &res) == 1);
    ENSURE(res.fm[0] == SF_STICK);
    end_event(&b);
}

/* T7, a separation located twice at one instant: the square of planar_def
 * sliding at 1 cm/s along a frictionless stop under its lower face, the
 * weight (-y, capacity 0.1 m g) pressing both lower corners (rows 0 and 3)
 * onto it. At a first event of row 0's separation guard (same = 0) the
 * decision's answer stands: both rows push, both stay in the set. At a
 * repeated one (same = 1) the event's answer stands: row 0 leaves, row 3
 * stays (the set's order kept). */
EXDEX_TEST(decide_event_repeated_separation_leaves_the_set)
{
    for (int same = 0; same < 2; same++) {
        exdex_scene_def d = planar_on_stop_def(0.1, 0.0, 0.0);
        begun b;
        hyb *H;
        double y[NY_MAX];
        d.v0[0] = 0.01;
        H = begin_event(&d, &b);
        if (!H) {
            end_event(&b);
            continue;
        }
        ENSURE(H->mode == MODE_SLIP && H->small == 0 && H->ncs == 2);
        memcpy(y, b.O->S.y, sizeof y);
        ENSURE(hyb_decide_event(H, 0.0, y, hg(G_SEPARATES, 0, 0.0, -1e-18), same) == EXDEX_OK);
        ENSURE(H->mode == MODE_SLIP);
        if (!same) ENSURE(H->ncs == 2 && ((H->cs[0] == 0 && H->cs[1] == 3) || (H->cs[0] == 3 && H->cs[1] == 0)));
        if (same) ENSURE(H->ncs == 1 && H->cs[0] == 3);
        end_event(&b);
    }
}

/* A decision at t inside the cruise of a trapezoid motion of duration 1 s
 * and amplitude 0.8 v_max (cruise at v_max on [0.2, 0.8]): the run's
 * current motion segment set to that cruise (the decision's frame is read
 * inside it), t = 0.5 s. */
#define CRUISE_T 0.5
static void in_cruise(hyb *H)
{
    H->lo = 0.2;
    H->hi = 0.8;
}

/* planar_on_stop_def(2.0, 0, 0) (the square on a frictionless stop along
 * its lower face, capacity 2 m g) with the gripper in a trapezoid motion
 * along A -y (approach: the stop, fixed in A, moves in B toward the object
 * at v) or +y (it recedes at v). */
static exdex_scene_def moving_stop_def(double v, int approach)
{
    exdex_scene_def d = planar_on_stop_def(2.0, 0.0, 0.0);
    scene_trapezoid(&d, 0, 0.0, approach ? -1.0 : 1.0, 0.0, 0.8 * v, 1.0, v);
    return d;
}

/* T3, rest instead of push: the square of moving_stop_def at rest in B on
 * its stop (both lower corners at gap 0) in the cruise, a slip that just
 * stopped (vzero). The stop moves in B at the gripper's speed v along its
 * normal (closed form: the corners' gap rate at rest is -v approaching, +v
 * receding; checked first). Approaching at 2 SLIP_PUSH zsw it pushes the
 * object on: the plastic impact of a translating box on a frictionless
 * line gives it the stop's velocity, v_y = v (closed form), a slip. At 0.5
 * SLIP_PUSH zsw it is a rest instead: qd = 0 with both touching corners in
 * the set, a stick (the plate holds the weight). Receding at 0.5 SLIP_PUSH
 * zsw: a rest on both touching corners as well; at 2 SLIP_PUSH zsw the
 * corners are left out (the set empty), a stick on the plate alone. zsw
 * is the scene's (SLIP_FLOOR V, V from the scene's length and
 * acceleration, not from the motion): read on the scene at rest. */
EXDEX_TEST(decide_planar_stopped_slip_rests_instead_of_a_slow_push)
{
    double z;
    {
        exdex_scene_def d0 = planar_on_stop_def(2.0, 0.0, 0.0);
        begun b0;
        hyb *H0 = begin_event(&d0, &b0);
        z = H0 ? H0->zsw : 0.0;
        end_event(&b0);
        ENSURE(z > 0.0);
        if (!(z > 0.0)) return;
    }
    for (int approach = 0; approach < 2; approach++)
        for (int fast = 0; fast < 2; fast++) {
            double v = (fast ? 2.0 : 0.5) * SLIP_PUSH * z, y[NY_MAX], Ga[MAX_ROWS][3], ga[MAX_ROWS], gda[MAX_ROWS],
                   gmin = INFINITY;
            int ra[MAX_ROWS], na, nt = 0;
            exdex_scene_def d = moving_stop_def(v, approach);
            begun b;
            frame f;
            exdex_kinematics kin;
            hyb *H = begin_event(&d, &b);
            if (!H) {
                end_event(&b);
                continue;
            }
            ENSURE(H->zsw == z && !H->sfric);
            in_cruise(H);
            memcpy(y, b.O->S.y, sizeof y);
            y[3] = y[4] = y[5] = 0.0;
            ENSURE(hyb_frame_seg(H, CRUISE_T, &f, &kin) == EXDEX_OK);
            na = hyb_hrow_all_planar(H, &kin, y, ra, Ga, ga, gda);
            for (int i = 0; i < na; i++) gmin = fmin(gmin, ga[i]);
            y[1] -= gmin; /* the lower face onto the stop (d gap / d y = 1) */
            na = hyb_hrow_all_planar(H, &kin, y, ra, Ga, ga, gda);
            for (int i = 0; i < na; i++)
                if (ga[i] <= b.m->tol.touch) {
                    nt++;
                    ENSURE_CLOSE(gda[i], approach ? -v : v, 1e-9 * v);
                }
            ENSURE(nt == 2);
            hyb_decide(H, CRUISE_T, y, 1);
            if (approach && fast) {
                ENSURE(H->mode == MODE_SLIP);
                ENSURE_CLOSE(y[4], v, 1e-9 * v);
                ENSURE_SMALL(y[3], 1e-9 * v);
                ENSURE_SMALL(y[5], 1e-9 * v / 0.02);
            } else {
                ENSURE(H->mode == MODE_STICK && y[3] == 0.0 && y[4] == 0.0 && y[5] == 0.0);
                ENSURE(H->ncs == (!approach && fast ? 0 : 2));
            }
            end_event(&b);
        }
}

/* The 1-DoF scene of vertical_def(0.5) (its point moving along A z, B y
 * up) on one stop through the point with the normal n = (sin a, 0, cos a)
 * (A), tan a = ta, stop friction mu_s, the gripper in a trapezoid motion
 * along A x at speed u (sign: direction) in its cruise. */
static exdex_scene_def slanted_stop_def(double ta, double mu_s, double u)
{
    exdex_scene_def d = vertical_def(0.5);
    double c = 1.0 / sqrt(1.0 + ta * ta);
    d.n_stops = 1;
    d.stop_normal[0][0] = ta * c;
    d.stop_normal[0][1] = 0.0;
    d.stop_normal[0][2] = c;
    d.stop_mu[0] = mu_s;
    scene_trapezoid(&d, 0, u > 0 ? 1.0 : -1.0, 0.0, 0.0, 0.8 * fabs(u), 1.0, fabs(u));
    return d;
}

/* T6, the jam: the point of slanted_stop_def held on its stop (gap 0, rate
 * 0) while the gripper moves along A x at u. Closed form: the gap is sin a
 * (x_B + u t) + cos a q, so at rate 0 qd = -u tan a; the point moves in A
 * along the stop at u (1, 0, -tan a), its friction -mu lam sgn(u) (cos a,
 * 0, -sin a), whose part along the DoF (A z) adds to the normal's cos a:
 * D = lam (cos a + sgn(u) mu sin a), D / Fq = 1 + sgn(u) mu tan a. With mu
 * 0.5: u > 0, tan a = 3: 2.5; u < 0, tan a = 1: 0.5, a frictional contact
 * (ss != 0, no jam, the law's D / Fq that value); u < 0, tan a = 3: -0.5
 * <= JAM_DIR, the friction would turn the normal force around: a jam (the
 * contact frictionless: ss = 0, jam the slip's sign, one warning). Every
 * case a contact (the weight presses the point on, lam > 0). */
EXDEX_TEST(decide_1dof_contact_jams_where_friction_would_turn_the_normal_force)
{
    const double cases[3][2] = {{3.0, 0.02}, {1.0, -0.02}, {3.0, -0.02}}, mu = 0.5;
    for (int i = 0; i < 3; i++) {
        double ta = cases[i][0], u = cases[i][1], dir = 1.0 + (u > 0 ? 1.0 : -1.0) * mu * ta, y[NY_MAX], q, T;
        exdex_scene_def d = slanted_stop_def(ta, mu, u);
        begun b;
        frame f;
        exdex_kinematics kin;
        crow c;
        long w0;
        hyb *H = begin_event(&d, &b);
        int rk[MAX_ROWS], rj[MAX_ROWS], nr;
        if (!H) {
            end_event(&b);
            continue;
        }
        in_cruise(H);
        memcpy(y, b.O->S.y, sizeof y);
        ENSURE(hyb_frame_seg(H, CRUISE_T, &f, &kin) == EXDEX_OK);
        nr = hyb_hrow_all_1dof(H, &kin, y[0], y + 1, rk, rj);
        ENSURE(nr == 1 && rk[0] == 0);
        if (nr != 1) {
            end_event(&b);
            continue;
        }
        q = y[0];
        for (int it = 0; it < 3; it++) {
            hyb_hrow_1dof(H, &kin, rk[0], rj[0], q, &c);
            q -= c.F / c.Fq;
        }
        hyb_hrow_1dof(H, &kin, rk[0], rj[0], q, &c);
        ENSURE_SMALL(c.F, 1e-15);
        y[0] = q;
        y[1] = -c.Ft / c.Fq;
        ENSURE_CLOSE(y[1], -u * ta, 1e-12);
        w0 = (long)H->st->warnings;
        hyb_decide(H, CRUISE_T, y, 0);
        ENSURE(H->mode == MODE_CONTACT && H->ck == 0);
        if (dir <= JAM_DIR) {
            ENSURE(H->jam != 0.0 && H->ss == 0.0);
            ENSURE((long)H->st->warnings == w0 + 1);
        } else {
            ENSURE(H->ss != 0.0 && H->jam == 0.0);
            ENSURE((long)H->st->warnings == w0);
            hyb_contact_slip_1dof(H, &kin, y[0], y[1], &T);
            hyb_hrow_1dof(H, &kin, rk[0], rj[0], y[0], &c);
            ENSURE_CLOSE(hyb_contact_dir(H, &c, T) / c.Fq, dir, 1e-12);
        }
        end_event(&b);
    }
}

/* T7, a gap crossing located twice at one instant (hyb_set_tie_joins): the
 * square of planar_def sliding at 1 cm/s along a frictionless stop under
 * its lower face, both lower corners (rows 0 and 3) at gap 0 but left out
 * of the contact set, receding at the rate r (a located crossing's rate
 * is positive by up to the gap acceleration times the location
 * tolerance). At a first event of row 0's gap guard (same = 0) the
 * decision's answer stands: a receding row is no contact, the set stays
 * empty. At a repeated one (same = 1) every touching row with |r| <= zsw
 * joins and the rows that push stay: with the weight toward the stop (-y)
 * both corners; with it away from the stop (+y) neither (they carry no
 * force); at r = 2 zsw (a real separation) neither joins. */
EXDEX_TEST(decide_event_repeated_tangential_arrival_joins_the_set)
{
    for (int c = 0; c < 4; c++) {
        int same = c > 0, away = c == 2, fast = c == 3;
        exdex_scene_def d = planar_on_stop_def(0.1, 0.0, 0.0);
        begun b;
        hyb *H;
        double y[NY_MAX];
        d.v0[0] = 0.01;
        if (away) d.gravity[1] = 9.81;
        H = begin_event(&d, &b);
        if (!H) {
            end_event(&b);
            continue;
        }
        ENSURE(H->mode == MODE_SLIP && H->small == 0 && !H->sfric);
        memcpy(y, b.O->S.y, sizeof y);
        H->ncs = 0;
        y[4] = fast ? 2.0 * H->zsw : 10.0 * b.m->tol.rate;
        ENSURE(10.0 * b.m->tol.rate < H->zsw);
        ENSURE(hyb_decide_event(H, 0.0, y, hg(G_GAP, 0, 0.0, -1e-18), same) == EXDEX_OK);
        ENSURE(H->mode == MODE_SLIP);
        if (c == 1) ENSURE(H->ncs == 2 && H->cs[0] == 0 && H->cs[1] == 3);
        else ENSURE(H->ncs == 0);
        end_event(&b);
    }
}
