/* hybrid.c -- the event-driven and regularised methods (exdex.h, enum
 * exdex_method), one hybrid ODE / event machine on the model of model.h,
 * with the output contract of method.h: samples on the fixed dt grid with
 * t_end exact, q, v, the mean plate wrench and mean stop forces over the
 * interval ending at each sample, the stick flag, and exdex_stats.
 *
 * Equations of motion (paper Eqs. 3-5, model.c): M qdd = Q(t, q, qd) +
 * friction + stops, with Q the gravity and inertial forces of the moving
 * frame. Friction at the patch (paper Eq. 6, maximum dissipation): slip twist
 * u = J' Rz(-theta) qd (object frame, at the centre of pressure), wrench
 *     sliding:  w = -mu N E^2 u / |E u|,   sticking: any w with |E^-1 w| <= mu N.
 * For 1-DoF scenes this is f = -C sign(qd) with C = mu N (translation) or
 * mu N e_r (rotation about the centre of pressure).
 *
 * EXDEX_METHOD_EVENT (event-driven, exact Coulomb):
 *   Modes: slip (smooth ODE with the sliding law, integrated by GSL odeiv2
 *   rk8pd under a standard error control with the scene's rtol, atol), stick
 *   (q, qd held exactly; the friction is the wrench that holds) and, for
 *   1-DoF scenes with stops, contact (the object follows a stop: the gap is
 *   held at 0 and the stop force comes from the constraint acceleration).
 *   Each mode has guard functions that are >= 0 while it holds:
 *     slip -> stop:   1-DoF s qd (s the slip direction); planar, see below;
 *     stick -> slip:  C (1 + 1e-12) - |required friction| (the wrench that
 *                     would hold leaves the ellipsoid; the 1e-12 band keeps
 *                     loads sitting on the limit from toggling);
 *     free -> contact: the gap of every (stop, vertex) pair; contact -> free:
 *                     the stop force; in contact also the gaps of the
 *                     contact stop's other vertices (a turning gripper or
 *                     object hands the contact over to another corner).
 *                     A gap that dips below 0 and recovers within one
 *                     step (a corner grazing a stop), and at rest any
 *                     guard that does (a load leaving the friction limit
 *                     for a moment), is found from its rates at the
 *                     step's ends (gap_dips).
 *   Planar slip (|E u| compared with zsw = SLIP_FLOOR V, V the scene's
 *   velocity scale: below it the sliding law is stiff: its
 *   direction relaxes at the rate C |K| / |E u| <~ A / |E u| (A = V / T the
 *   acceleration scale), where an explicit stepper is stable only for steps
 *   below ~5 |E u| / (C |K|). With zsw = SLIP_FLOOR V a slip lingering at
 *   a small speed (a load crossing the friction limit at a grazing rate, a
 *   slip dying out) costs at most ~1 / (5 SLIP_FLOOR) steps per T, where
 *   with zsw tied to a small atol alone the step collapsed as |E u| -> 0.
 *   zsw does not depend on rtol, atol: a band that grew with a loose atol
 *   would exceed real speeds of the scene (a stop moving in B pushes a
 *   resting object at its own speed; an impact leaving it below zsw would
 *   be taken as a rest, which the stop ends again after tol.rest_gap of
 *   its travel, over and over), so a loose tolerance would fail instead of
 *   giving a less accurate answer.
 *   What a stop drops, |E u| <= zsw of speed, moves the object by
 *   zsw^2 / (2 a) ~ SLIP_FLOOR^2 L / 2 at a deceleration a ~ A: 5e-13 L,
 *   scale-free and below any tolerance of the stepper):
 *     small slip (it grows from rest): the friction is the maximum-
 *       dissipation wrench of the current load for an infinitesimal step
 *       (against stops: the fixed point of that law on the constrained
 *       acceleration). The sliding law's direction E u / |E u| relaxes onto
 *       it at the rate C |K| / |E u| (K = E W E), infinitely stiff at the
 *       start of a slip; the slip follows it to |E u| |dn/dt| / (C |K|) (n
 *       that direction). Guards: the load leaves the ellipsoid's outside
 *       (|E^-1 w_stick| - C (1 + TOLF): it stops), SLIP_UP zsw - |E u| (it
 *       becomes a slip, no state change; SLIP_UP > 1 is the hysteresis that
 *       keeps a slip hovering near zsw from switching at every step);
 *     slip: the sliding law. Guards: (E u).(E u_0), u_0 the slip at the
 *       start of the step (it reverses: a stop if |E u| <= zsw there, else
 *       a turn of the slip direction, which only renews u_0), and
 *       |E u| - zsw (it dies out, also against stops, without reversing):
 *       where the load can be held at rest (the stick test) a stop sets
 *       qd = 0, so a slip's last zsw of speed is dropped; else it slips on
 *       as a small slip with its velocity kept (a dropped speed would
 *       persist where friction cannot take it back: with mu = 0 a spin of
 *       zsw would last to t_end). A slip that lingers below SLIP_STIFF zsw
 *       (STIFF_AFTER consecutive steps) is integrated by a linearly
 *       implicit stepper instead of rk8pd, the same law under the same
 *       error control (stiff_track): a load just beyond the friction limit
 *       grows a slip at a small rate, or holds it at a small steady speed,
 *       and the explicit stepper's stable step ~5 (|E u| / V) T would make
 *       the cost (and the step budget below) grow without bound.
 *   After every accepted step the guards are checked; the earliest sign change
 *   is located by GSL Brent on the stepper's own one-step map tau -> y(t0 +
 *   tau) (an interpolant of the stepper's order) at the first point where the
 *   guard is violated (g < 0, not an exact zero that would decide the same
 *   mode again), and the mode is decided again there (slip stops with qd = 0
 *   exactly; it sticks iff the required friction lies in the ellipsoid, else
 *   it slips on in the direction that the maximum-dissipation solve gives
 *   for an infinitesimal step). A guard can change sign and back within one
 *   step: a 1-DoF slip that stops and restarts the same way (s qd falling
 *   then rising over the step: its minimum is searched, golden section on
 *   the one-step map), and a guard violated at the step start that first
 *   recovers (a corner lifted off a stop falling back: its maximum is
 *   searched, and the crossing after it located); at rest every guard is
 *   a function of t alone and a step can be long (the state is constant), so
 *   a load that leaves the ellipsoid and comes back within one step is
 *   found from the guards' rates at the step's ends (gap_dips). In a 1-DoF
 *   scene a stop's gap guard is the least gap over the outline, whose end
 *   rates need not show one corner's dip (a corner of a turning object
 *   sweeping past a stop that cuts its path a little while another corner
 *   is the nearest at both step ends): each free (stop, vertex) row is
 *   checked too (row_dip). The
 *   motion's own switching times (Eq. 7, trapezoid kinks, end of a sampled
 *   motion) and the breakpoints of a grip schedule are stepped onto, never
 *   over, and velocity jumps of the gripper
 *   there are applied as inertial impulses. A sampled motion's knots (its
 *   sample times, exdex_motion_next_knot) end steps too, with no decision
 *   (the kinematics are C2 there): the gripper's jerk jumps at a knot, and
 *   rk8pd's step across one has a local error set by where the knot falls
 *   in it (the order lost), so the global error summed over a log's
 *   hundreds of knots scatters by 10x from one rtol or last bit of the
 *   data to the next instead of falling with rtol (zoo_inputs 795, 335
 *   knots: 6.9e-9 .. 1.2e-7 L at rtol 1e-9 over logs a few ulps apart;
 *   2.6e-11 .. 3.3e-11 L with the steps ending at knots, in 377 steps
 *   instead of 923). Fails by Zeno-like toggling: a
 *   load that crosses the friction limit N times costs 2N events, and more
 *   than EVENTS_MAX events within one output interval return EXDEX_ENOCONV.
 *
 * EXDEX_METHOD_REGULARISED (smooth friction):
 *   w = -mu N E^2 u / sqrt(|E u|^2 + eps^2), eps a slip speed [m/s]; the same
 *   adaptive rk8pd integration, no stick mode (no true stick: under a load w
 *   inside the ellipsoid the object creeps at E u = eps E^-1 w /
 *   sqrt((mu N)^2 - |E^-1 w|^2)). Stiff when eps is small: the explicit
 *   stepper's step collapses to ~ M eps / C.
 *
 * Static and kinetic friction (capacities C_s = mu_static N >= C = mu N,
 * two ellipsoids of the same shape):
 *   event: every test of a stick (the stick -> slip guard, a rest against
 *     stops, the decision after a slip stops or at a segment start) uses
 *     C_s; every slip (the sliding law, the direction a slip starts in, the
 *     small-slip law, sliding along a 1-DoF stop) uses C. A small slip
 *     (planar, growing from rest) stops when its load falls back inside the
 *     kinetic ellipsoid, where the slip decelerates; the decision there
 *     sticks (the load is inside the static one too).
 *   regularised: a stick band of slip speeds |E u| <= eps, viscous up to
 *     the static capacity, and Coulomb against the kinetic one beyond,
 *         w = -C_s E^2 u / eps     (|E u| <= eps),
 *         w = -C E^2 u / |E u|     (|E u| > eps).
 *     First order in eps: a load w_h inside the static ellipsoid is held at
 *     the creep E u = eps E^-1 w_h / C_s (|E u| < eps: a drift of at most
 *     eps per unit time, reached after the band's relaxation time M eps /
 *     C_s); a load leaving it (|E^-1 w_h| > C_s) pushes the slip out of the
 *     band, where the kinetic law is exact, so the slip starts at |E u| =
 *     eps, at most a relaxation time after the exact breakaway, instead of
 *     0: its speed differs from the exact one by at most eps (eps C / C_s
 *     under a slowly rising load, as the exact slip has gained (C_s - C) /
 *     M times the relaxation time by then), and s by eps times the slip's
 *     duration; a slip that decelerates enters the band and is
 *     caught there at its creep speed (the viscous rate C_s / (M eps) is
 *     that of the one-coefficient law, as stiff and no stiffer). Why a band
 *     that reaches C_s: a smooth capacity falling from C_s to C over a speed
 *     v_s (a Stribeck curve C + (C_s - C) exp(-(|E u| / v_s)^2) under the
 *     one-coefficient regularisation) holds at most C_s (1 - O(eps / v_s))
 *     before it accelerates away, and past the static limit the slip lags
 *     the exact one by the time it takes to cross v_s against a capacity
 *     still near C_s, (v_s^2 M^2 / ((C_s - C) Q'))^(1/3) under a load rising
 *     at Q'; both vanish only if eps / v_s -> 0 and v_s -> 0, so no choice of
 *     v_s is first order (v_s = sqrt(eps V): O(eps^(1/2)) and O(eps^(1/3)),
 *     v_s proportional to eps: an O(1) deficit of the static limit). The
 *     band has no such deficit (its force reaches C_s at |E u| = eps) and no
 *     speed range with the static capacity beyond eps. The switch at |E u| =
 *     eps is a jump of the right-hand side that the error control steps
 *     across (it is crossed once per stick -> slip or slip -> stick: below
 *     it the flow goes to the creep point, above it away from the band or
 *     into it, never along it, as C < C_s). In a 1-DoF rotation scene the
 *     band is eps / e_r in |thd|, as eps is. With C_s = C it is the one-
 *     coefficient law above (its creep eps |w_h| / sqrt(C^2 - |w_h|^2)).
 *     Planar: a held regime. In the band z = E u relaxes as z' = -(C_s /
 *     eps) S (z - z*) with S = E J M^-1 J^T E (J: qd -> u) symmetric, z* the
 *     creep of the current load; each eigencomponent of S moves
 *     monotonically from the old creep to the new one, so after a load that
 *     jumps and turns (a motion's acceleration jump, a grip step) |z| can
 *     pass max(|z_0|, |z*|), up to sqrt(|z_0|^2 + |z*|^2): beyond eps for a
 *     load still inside the static ellipsoid, where the kinetic law would
 *     let it break away at every eps (the excursion is scale-free in z /
 *     eps). So the object is held (hyb.held) from the band on, and a held
 *     slip beyond it meets Coulomb at C_s (w = -C_s E^2 u / |E u|,
 *     continuous with the band), under which its kinetic energy relative to
 *     the plates falls while the load is inside C_s (power |E u| (|E^-1
 *     w_h| - C_s) <= 0), so it comes back into the band; it breaks away
 *     (kinetic beyond the band) where the slip is beyond the band and the
 *     object could not rest in B: the load at rest (the event method's
 *     stick test, against the contact set its least-friction split) leaves
 *     the static ellipsoid, or a contact-set row's stop moves into it (a
 *     slip the stop forces). A guard locates either switch: held, fmax(eps -
 *     |E u|, that test); not held, |E u| - eps (held again in the band). A
 *     velocity changed by an impact or a gripper jump is a slip (not held
 *     unless in the band). Under a slowly rising load the creep reaches eps
 *     as the load reaches C_s, so the break-away is where it was (first
 *     order). A 1-DoF band needs no such regime: its one component relaxes
 *     monotonically, and at |v| = eps the band pushes inward while |Q| <=
 *     C_s.
 *
 * Stops: every scene with every method. Planar scenes in the hybrid
 * (event, regularised) integrator carry a contact set of (stop, vertex) rows
 * besides the friction mode:
 *   free row -> impact: its gap reaches 0 (located by Brent); the impact is
 *     plastic, with no plate impulse (the grip force is finite): v is
 *     projected onto G v >= -dgap/dt|_q (no approach) of the touching rows
 *     in the M metric (ldp_project), with Coulomb friction at frictional
 *     rows at every approach speed (sf_impact), the impulses counted in the
 *     stop force integrals; the rows left touching at rate ~0 that push
 *     join the contact set; event, frictional rows touching a rest: a stop
 *     whose path turns back within tol.rest_gap of the held pose is a
 *     contact of the rest, not an impact (sf_graze);
 *   in contact: qdd = M^-1 (F + friction + G^T lam), lam >= 0 the LCP
 *     G M^-1 G^T lam = -(G M^-1 (F + friction) + Gdot v) with complementarity
 *     (the M-metric projection of the free acceleration, ldp_project); after each
 *     step the penetration and approach speed of the set rows are projected
 *     out; a row leaves when lam reaches 0 (guard lam G M^-1 G^T - gap
 *     acceleration, negative once it separates);
 *   an impact whose lift-off rates are all below zsw holds the touching
 *     rows at rate 0 (a face landing flat: plastic impacts alternating
 *     between its corners with rates shrinking by a constant factor would
 *     accumulate at a finite time);
 *   event, slip against stops: where it stops, a stop moving in B would
 *     push it on (the plastic impact on v = 0), and if that slip is below
 *     SLIP_PUSH zsw it is a rest on the touching rows instead (a restart
 *     there would stop again at once, Zeno-like: a gripper's rotation
 *     reversing with the object against a stop), and so is a stop of a
 *     slip below zsw that a set row held while its stop recedes in B at
 *     SLIP_PUSH zsw or faster and friction alone cannot hold the load (the
 *     object followed the stop: at rest the row separates and the load
 *     drives it back, an impact every few hundred ns; the rest lags the
 *     stop by at most tol.rest_gap, see decide); stick against
 *     stops: rest iff the least-friction split (planar_rest: least
 *     combination over the stop forces lam >= 0, ldp_min_combination, as the
 *     implicit method) has |E^-1 w| <= mu N
 *     (1 + TOLF); the rest ends when that fails or a set row's gap leaves
 *     +-tol.rest_gap (stops moving in B). During the rest q is held
 *     exactly (no projection after its steps, which would move it by the
 *     stops' travel over each step and make the rest's end depend on where
 *     steps end); the samples and the smallest gap report it pushed out of
 *     the stops (reported_pose), as the decision at the rest's end does.
 *
 * Frictional stops (stop_mu > 0), 1-DoF scenes: in contact the vertex
 *   slips along its stop at s = T qd + tb (contact_tangent), and the stop's
 *   Coulomb force -mu lam sign(s) along the tangent adds -mu lam sign(s) T
 *   to the generalized force: M qdd = Q + f + lam D, D = Fq - mu sign(s) T,
 *   the constraint fixing qdd, so lam = (M qdd - Q - f) / D. The slip's sign
 *   is a mode (hyb.ss) with its guard ss s >= 0, located like every guard;
 *   at a reversal the mode is decided again with the new sign. Where D Fq
 *   <= 0 the friction turns the normal force's generalized direction
 *   around and the acceleration-level contact has no solution (Painleve):
 *   the contact is taken frictionless there and a warning counted (the
 *   implicit method, at the velocity level, reports the same jam); a jam
 *   reached in contact (D / Fq falling to 0, lam without bound) is located
 *   by a guard at D / Fq = JAM_DIR. Impacts
 *   are plastic with Coulomb friction at the impulse level
 *   (impact_impulse_1dof: the velocity after one is the frictionless one,
 *   the impulse the stop takes is not). Planar scenes: a friction mode per
 *   stop (stick, slide +-), exact at the acceleration level, in both
 *   methods (the regularised one smooths the plate friction only), and
 *   impacts with Coulomb friction at the impulse level: see "planar
 *   frictional stops" and "frictional impacts" below (sf_*, stop_friction.h).
 *
 * Obstacles (Obstacle.mu > 0 as a frictional stop: the row's tangent at its
 *   point, orow_point; planar scenes: the stop friction below, one friction
 *   group per line of contact): their rows (obstacle_rows.h: an outline vertex
 *   against a polytope's faces, a section vertex against the outline's
 *   hull, a rod against the hull; a disc outline: one row per obstacle, its
 *   support point against a face, its centre against a section vertex, its
 *   rim against a rod) go through the stops' code path: the same gap guards,
 *   impacts, contact sets (planar) and single-row contact (1-DoF), their
 *   forces in source n_stops + o. Each row is a largest (or, for a rod,
 *   smallest) distance over features; a row in contact holds its feature
 *   (a smooth function with exact rates and gap accelerations), and a
 *   guard, >= 0 while that feature stays the active one, locates the switch
 *   as a root like every other guard: the mode is decided again there with
 *   the new feature. Free rows' guards are the gaps themselves, which are
 *   continuous across feature switches (planar: one per outline vertex and
 *   per polytope the smallest gap of its section vertices, whose number
 *   changes with the gripper's pose, a disc's one row per obstacle; 1-DoF:
 *   the smallest gap per obstacle).
 *
 * Penetration: event and regularised keep every stop to rounding and event
 *   location (|gap rate| tol.root; planar decisions also project positions
 *   back). A gap below -tol.pen after a step counts a warning in
 *   exdex_stats, as in every method:
 *   only a scene that drives the object through a stop gets there (a
 *   prescribed motion pushing a pinned pivot or the slide line through it,
 *   stops that pinch the object, a stop the free coordinates cannot act on).
 *
 * Budgets (every loop is bounded; a run that would grind returns
 * EXDEX_ENOCONV, with stats.warnings incremented):
 *   - event, regularised: at most STEPS_MAX (10^5) ODE steps, accepted plus
 *     rejected, plus Brent iterations (each one stepper application),
 *     per output interval (dt is the output grid and also the unit
 *     of the budget: a finer grid gives a long stiff run more steps), and the
 *     step the controller suggests must stay >= H_FLOOR_ULPS (16) ulps of t
 *     (h >= 16 DBL_EPSILON |t|) while t is short of the next stop time;
 *     GSL's own controller fails below 1 ulp, and the rejections inside one
 *     gsl_odeiv2_evolve_apply call are bounded by its step-size decrease
 *     (each at least x0.89 per rejection, floor at 1 ulp);
 *   - event: at most EVENTS_MAX (1000) events per output interval, each
 *     located by at most BRENT_MAX (200) Brent iterations (and a guard's
 *     extremum inside a step by at most 60 golden-section iterations);
 *   - every failure records its time and cause in exdex_stats (fail_time,
 *     fail_cause: events, step budget, step floor, stepper);
 *   - decisions, projections, impacts: fixed small iteration counts;
 *   - explicit: one step per output sample, nothing else iterates.
 * Why the regularised step collapses: near u = 0 the friction slope is
 * k = C / (M eps) [1/s] (1-DoF; C (1 - (Q/C)^2)^(3/2) / (M eps) at the creep
 * speed under a load Q), and rk8pd is stable only for h k below its real
 * stability interval, ~5.17. So the steps per output interval are about
 * dt k / 5.17: the budget is reached once eps < dt C / (5.17 M 10^5).
 */
#include "exdex.h"
#include "contact.h"
#include "stop_impulse.h"
#include "ldp.h"
#include "method.h"
#include "model.h"
#include "obstacle_rows.h"
#include "stop_friction.h"
#include "util.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_roots.h>

#define TOLF 1e-12        /* relative band at the friction limit (stick while |f| <= C (1 + TOLF)) */
#define EVENTS_MAX 1000   /* events within one output interval before EXDEX_ENOCONV */
#define STEPS_MAX 100000  /* ODE steps (accepted + rejected) per output interval before EXDEX_ENOCONV */
#define H_FLOOR_ULPS 16.0 /* a suggested step below this many ulps of t is a collapse: EXDEX_ENOCONV */
#define BRENT_MAX 200     /* Brent iterations per located event */
#define DOUBLING_EXACT 10 /* locate: a forward search past 2^10 of its first increment is bisected back */
#define NY_MAX (9 + EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES)
#define NG_MAX (3 + 3 * MAX_ROWS + 1 + SF_MAX_STOPS + EXDEX_MAX_OBSTACLES)  /* guards (planar: 2 friction, the rows, stop friction, obstacle features) */
#define NSRC_MAX (EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES)
/* 1-DoF frictional contact (see "Frictional stops" above): its normal force
 * is lam = R / D, D = Fq - mu ss T, i.e. the frictionless force R / Fq times
 * Fq / D. Where D / Fq falls to 0 (a jam: the friction turns the normal
 * force's generalized direction around) lam grows as 1 / (t_jam - t) and its
 * integral as -log(t_jam - t): no step reaches t_jam. The contact is taken
 * frictionless (warning counted) once D / Fq <= JAM_DIR, a guard located
 * like every guard: the normal force is then 1 / JAM_DIR times the
 * frictionless one, and the impulse given up, the integral of lam beyond,
 * grows as log(1 / JAM_DIR) only. Friction returns where D / Fq of the slip's
 * sign exceeds JAM_DIR again, or the slip reverses (decided again there). */
#define JAM_DIR 1e-6
#define SLIP_FLOOR 1e-6  /* planar slip: below SLIP_FLOOR V of |E u| the slip is "small" (see the header comment) */
#define SLIP_UP 2.0      /* a small slip becomes a slip at SLIP_UP zsw (hysteresis against zsw) */
#define SLIP_PUSH 4.0    /* a stop pushing a stopped planar slip on below SLIP_PUSH zsw: a rest instead */
#define SLIP_STIFF 100.0 /* a planar slip below SLIP_STIFF zsw for STIFF_AFTER steps: the stiff stepper */
#define STIFF_AFTER 1000

enum { LAW_COULOMB = 0, LAW_SMOOTH = 1 };
enum { MODE_SLIP = 0, MODE_STICK = 1, MODE_CONTACT = 2, MODE_FREE = 3 };

/* Mutable state of one hybrid (event / regularised) run. The ODE state y is
 *   1-DoF:  (q, qd, I_f, I_lambda[n_stops])   (I: time integrals of the
 *           generalized friction and of each stop's normal force)
 *   planar: (x, y, theta, xd, yd, thetad, I_w[3])  (I_w: integral of the
 *           plate wrench (f_x, f_y, m_z) in B) */
typedef struct hyb {
    const exdex_model *m;
    exdex_model *mc;   /* pads on the fingers: m itself, the run's own copy whose contact
                          fields follow the state (hyb_pads); NULL without pads */
    int law, ndof, ns, ny;
    int mode;
    double s;          /* 1-DoF slip / friction direction (contact: 0 = at rest) */
    int ck, cj;        /* contact: stop and vertex */
    int nv, ncs;       /* planar: outline vertices; rows in the contact set */
    int cs[MAX_ROWS];  /* planar contact set: rows r = k nv + j (stop k, vertex j) */
    double uref[3];    /* planar slip: E u at the start of the step */
    int small;         /* planar Coulomb slip: 1 while |E u| < zsw (the slip grows from rest) */
    double zsw;        /* planar: slip speed |E u| below which a slip is small: SLIP_FLOOR V */
    double lo, hi;     /* motion segment [lo, hi) */
    double M, cap, eps;
    double capk;       /* capacity per unit model_capacity: 1, or e_r for a 1-DoF rotation */
    double caps;       /* static capacity (force, or torque in a 1-DoF rotation), >= cap */
    int err;           /* first failure inside a right-hand side */
    exdex_stats *st;
    double ss;         /* 1-DoF contact with a frictional stop: sign of the contact vertex's
                          slip along the stop (its Coulomb force opposes it); 0: none */
    int gap0, gap1;    /* guards() entries [gap0, gap1): free gaps, functions of (t, q) only */
    int sfric;         /* planar with a frictional stop: the stop friction below (sf_*) */
    int fm[SF_MAX_STOPS];  /* planar: friction mode of each friction group with contact-set rows (SF_*) */
    int no;            /* obstacles (their rows follow the stops', see hrow_src) */
    int stiff;         /* event, planar slip: 1 while the stiff stepper integrates it (stiff_track) */
    int nlow;          /* consecutive steps of that slip below SLIP_STIFF zsw (up to STIFF_AFTER) */
    double jam;        /* 1-DoF contact with a frictional stop taken frictionless at a jam (its
                          friction would turn the normal force around, see JAM_DIR): the sign of
                          the slip there; 0: none */
    int sgn;           /* planar friction groups of the contact set fixed at the decision (sf_groups):
                          their count, 0 while a decision builds the set (then found afresh) */
    int sg[MAX_ROWS];  /* the group of each contact-set row while sgn > 0 */
    int held;          /* regularised, planar, C_s > C: 1 while the object is held (in the
                          stick band, or beyond it with the load inside the static ellipsoid),
                          0 once it broke away (until it slows into the band again); see the top */
} hyb;

/* Pads on the fingers: the model's contact fields set to the region at the
 * planar state y (model_pads_set; nothing when they hold it already). Every
 * function below that reads the contact (pc, e, prep) at a state calls it
 * first. */
static inline void hyb_pads(const hyb *H, const double *y)
{
    if (H->mc && H->ndof == 3) model_pads_set(H->mc, y);
}

/* ---------------------------------------------------------- contact rows
 * The stops' rows and the obstacles' (obstacle_rows.h) in one numbering: planar row
 * r < ns nv is stop r / nv against outline vertex r % nv, r >= ns nv the
 * obstacle row of code r - ns nv (its feature held); the 1-DoF contact
 * (ck, cj) is a stop and a vertex, or ck = ns + o and cj an obstacle row
 * code. Obstacle rows take the stops' code path everywhere: gaps, rates,
 * impacts, contact forces, rests; their force is source ns + o's. */

/* Source (stop_force column) of planar row r. */
static int hrow_src(const hyb *H, int r)
{
    int base = H->ns * H->nv;
    return r < base ? r / H->nv : H->ns + orow_obst(r - base);
}

/* Planar row r at (q, v): contact_row_planar's contract. */
static double hrow_planar(const hyb *H, const exdex_kinematics *kin, int r, const double *q, const double *v,
                          double G[3], double *gd, double *gdd0)
{
    int base = H->ns * H->nv;
    if (r < base) return contact_row_planar(H->m, kin, r / H->nv, r % H->nv, q, v, G, gd, gdd0);
    return orow_planar(H->m, kin, r - base, q, v, G, gd, gdd0);
}

/* Every planar row at (kin, y), an obstacle's with its active feature:
 * rows, G, gaps and (gd may be NULL) gap rates. Returns the count. */
static int hrow_all_planar(const hyb *H, const exdex_kinematics *kin, const double *y, int *rows, double (*G)[3],
                           double *gap, double *gd)
{
    int n = 0;
    for (int k = 0; k < H->ns; k++)
        for (int j = 0; j < H->nv; j++) {
            gap[n] = contact_row_planar(H->m, kin, k, j, y, y + 3, G[n], gd ? &gd[n] : NULL, NULL);
            rows[n++] = k * H->nv + j;
        }
    if (H->no) {
        int code[MAX_ROWS], no = orow_all(H->m, kin, y, y + 3, 1, code, NULL);
        for (int i = 0; i < no && n < MAX_ROWS; i++) {
            rows[n] = H->ns * H->nv + code[i];
            gap[n] = orow_planar(H->m, kin, code[i], y, y + 3, G[n], gd ? &gd[n] : NULL, NULL);
            n++;
        }
    }
    return n;
}

/* 1-DoF row (k, j) (a stop and vertex, or an obstacle and row code) at q. */
static void hrow_1dof(const hyb *H, const exdex_kinematics *kin, int k, int j, double q, crow *c)
{
    if (k < H->ns)
        contact_row_1dof(H->m, kin, k, j, q, c);
    else
        orow_1dof(H->m, kin, j, q, c);
}

/* Every 1-DoF row at (kin, q, v): sources k and rows j (vertex or code),
 * the stops' first (r = k nv + j). Returns the count. */
static int hrow_all_1dof(const hyb *H, const exdex_kinematics *kin, double q, const double *v, int *k, int *j)
{
    int n = 0;
    for (int s = 0; s < H->ns; s++)
        for (int v = 0; v < H->nv; v++) {
            k[n] = s;
            j[n++] = v;
        }
    if (H->no) {
        int code[MAX_ROWS], no = orow_all(H->m, kin, &q, v, 0, code, NULL);
        for (int i = 0; i < no && n < MAX_ROWS; i++) {
            k[n] = H->ns + orow_obst(code[i]);
            j[n++] = code[i];
        }
    }
    return n;
}

/* ---------------------------------------------------------- shared terms */

/* t clamped into the current segment: right-continuous at its start, left
 * limit (a few ulps before) at its end, so an RK stage on the segment end
 * never sees the next phase's acceleration or grip force. */
static double seg_time(const hyb *H, double t)
{
    double lo = H->lo, hi = H->hi;
    if (isfinite(hi)) hi -= 4.0 * DBL_EPSILON * fmax(1.0, fabs(hi));
    if (t > hi) t = hi;
    if (t < lo) t = lo;
    return t;
}

/* Frame terms at t inside the current motion segment (seg_time); with a
 * grip schedule also the friction capacities H->cap, H->caps at that time (segments end
 * at the schedule's breakpoints too), which every friction law, guard and
 * decision below reads: the stick guard C(t) (1 + TOLF) - |load|_E is
 * located on the stepper's dense map like every other guard. */
static int frame_seg(hyb *H, double t, frame *f, exdex_kinematics *k)
{
    t = seg_time(H, t);
    if (H->m->grip_n) {
        H->cap = H->capk * model_capacity(H->m, t);
        H->caps = H->capk * model_capacity_static(H->m, t);
    }
    return model_frame_at(H->m, t, f, k);
}

/* Regularised friction per unit slip at slip speed sig = |E u| (same
 * units as eps): the wrench is -smooth_gain E^2 u (1-DoF: -smooth_gain v).
 * One coefficient: C / sqrt(sig^2 + eps^2). Static and kinetic (caps >
 * cap): the stick band C_s / eps for sig <= eps, Coulomb C / sig beyond
 * (see the top). */
static double smooth_gain(const hyb *H, double sig)
{
    if (H->caps == H->cap) return H->cap / sqrt(sig * sig + H->eps * H->eps);
    return sig <= H->eps ? H->caps / H->eps : (H->held ? H->caps : H->cap) / sig;
}

/* Constraint acceleration of q along the row (F(q(t), t) = 0 held). */
static double contact_qdd(const crow *c, double v)
{
    return -(c->Ftt + 2.0 * c->Ftq * v + c->Fqq * v * v) / c->Fq;
}

/* Slip of the 1-DoF row (k, j) (a stop and vertex, or an obstacle and row
 * code) along its stop at (q, v) and pose kin: s = T v + tb
 * (contact_stop_tangent; an obstacle row: contact_tangent at its point,
 * orow_point); T (may be NULL) gets d s / d qdot. contact_slip_1dof: of the
 * contact row (H->ck, H->cj). */
static double row_slip_1dof(const hyb *H, const exdex_kinematics *kin, int k, int j, double q, double v, double *T)
{
    double xb[EXDEX_MAX_VERTICES][3], vx[EXDEX_MAX_VERTICES][3], Tv[3], tb;
    if (k >= H->ns) {
        contact_point cp;
        orow_point(H->m, kin, j, &q, &cp);
        contact_tangent(H->m, kin, cp.x, cp.vx, cp.nB, Tv, &tb);
        if (T) *T = Tv[0];
        return Tv[0] * v + tb;
    }
    contact_vertices(H->m, &q, xb, vx);
    contact_stop_tangent(H->m, kin, k, xb[j], vx[j], Tv, &tb);
    if (T) *T = Tv[0];
    return Tv[0] * v + tb;
}

static double contact_slip_1dof(const hyb *H, const exdex_kinematics *kin, double q, double v, double *T)
{
    return row_slip_1dof(H, kin, H->ck, H->cj, q, v, T);
}

/* The stop's generalized force per unit normal force in contact: Fq, less
 * mu ss T with a frictional stop (its Coulomb force -mu lam ss along the
 * tangent, generalized force -mu lam ss T). */
static double contact_dir(const hyb *H, const crow *c, double T)
{
    double mu = model_source_mu(H->m, H->ck);
    return mu > 0.0 && H->ss != 0.0 ? c->Fq - mu * H->ss * T : c->Fq;
}

/* Friction f and stop force lam in contact (M qdd = Q + f + lam D, D =
 * contact_dir: Fq for a frictionless stop); T the tangent row of the
 * contact vertex (contact_slip_1dof). */
static void contact_forces(const hyb *H, const crow *c, double T, double R, double v, double *f, double *lam)
{
    double D = contact_dir(H, c, T);
    if (H->law == LAW_SMOOTH) {
        *f = H->caps == H->cap ? -H->cap * v / sqrt(v * v + H->eps * H->eps) : -smooth_gain(H, fabs(v)) * v;
        *lam = (R - *f) / D;
    } else if (H->s != 0.0) {
        *f = -H->s * H->cap;
        *lam = (R - *f) / D;
    } else {
        /* at rest against the stop: the stop carries what it can (as the implicit method) */
        double l = R / D;
        *lam = l > 0.0 ? l : 0.0;
        *f = R - *lam * D;
    }
}

/* Normal impulse of a 1-DoF impact on row (k, j) (c its row at q): the
 * velocity v goes to vn = -Ft / Fq (no approach), plastic. With a
 * frictional stop the impact is Coulomb's at the impulse level (stop_impulse.h's
 * problem with no plate impulse: the plates' friction is bounded, its
 * impulse over the impact 0; the implicit step's impulse as the step
 * vanishes): M (vn - v) = lam Fq + beta T, beta = -mu lam sigma, sigma the
 * sign of the row's slip s = T vn + tb after the impact, so lam = M (vn -
 * v) / D with D = Fq - mu sigma T (contact_dir's). The velocity after the
 * impact is vn either way (one free coordinate); the friction changes the
 * impulse the stop takes. Where D Fq <= 0 no lam >= 0 is consistent (the
 * friction turns the impulse's generalized direction around: a jam, as
 * for the contact mode): the frictionless impulse and a warning. */
static double impact_impulse_1dof(hyb *H, const exdex_kinematics *kin, int k, int j, double q, const crow *c,
                                  double v, double vn)
{
    double mu = model_source_mu(H->m, k), T = 0.0, sl, D = c->Fq;
    if (mu > 0.0) {
        sl = row_slip_1dof(H, kin, k, j, q, vn, &T);
        if (sl != 0.0) D = c->Fq - mu * (sl > 0.0 ? 1.0 : -1.0) * T;
        if (!(D * c->Fq > 0.0)) {
            H->st->warnings++;
            D = c->Fq;
        }
    }
    return H->M * (vn - v) / D;
}

/* ------------------------------------------------ planar frictional stops
 * Coulomb friction between a stop with stop_mu > 0 (or an obstacle with mu
 * > 0) and the points of a planar object touching it, exact (not
 * regularised, also in the regularised method, which smooths the plate
 * friction only): the acceleration-level problem of stop_friction.h on the
 * contact-set rows. The rows fall into friction groups, lines of contact
 * (sf_groups: a stop's rows, an obstacle face's vertex rows, the section
 * vertices on one edge of the object, a rod's row), fixed at each decision
 * (sf_fix_groups) and held with the contact set. Each group with
 * contact-set rows has a friction mode H->fm (one per group: its touching
 * points lie on its line and slip together): sliding with the sign of its
 * slip s (along the tangent of contact_slip_planar, or orow_slip for an
 * obstacle row, whose contact point may move over the object) or
 * sticking. The modes are decided at every decision (decide: sf_decide)
 * and held between decisions, where their guards (sf_guards) say when they
 * end: a sliding stop's slip reaching 0 (sigma s), a sticking stop's force
 * reaching its cone (mu sum lam (1 + SF_BAND) - |beta|). A slip with |s| <=
 * zsw is decided as rolling (stick or slide, the acceleration-level mode
 * enumeration: a slip located at its reversal is within rounding of 0
 * there), and a sticking stop's slip is projected to 0 at the decision and
 * after every step (sf_project_stick), like the gap of a contact row.
 * Normal forces and separations stay as without friction (the contact set,
 * its separation guards); impacts are frictional at the impulse level
 * (sf_impact, below).
 * At rest (stick) the least-friction split of planar_rest takes each
 * stop's force in its friction cone, {lam (G + mu c T) : -1 <= c <= 1},
 * generated by G + mu T and G - mu T (ldp_min_combination over the
 * generators), while the stop's slip past the resting object |tb| <= zsw;
 * a stop moving past it faster slides: G - mu sign(tb) T. That choice is
 * the stop's mode, decided with the rest and held through it (the rest's
 * load is then smooth in time), its guards |tb| leaving or entering the
 * band. A stop whose mode is not decided (inside a decision) is classified
 * by its tb as it stands.
 * Painleve: where no mode of the acceleration-level problem is consistent
 * (a sliding stop whose friction turns the normal force's effect around:
 * a jam, or more rows than sf_solve reduces to its enumeration), the stops
 * of the contact set are taken frictionless until the next decision, and a
 * warning is counted, as for a 1-DoF jam; the loss of consistency is a
 * located guard (+1 / -1). The velocity-level (impulse) solution would
 * exist there (stop_impulse.h), but it is a jump of the velocity that the
 * acceleration-level machine would have to apply as an impact at a time it
 * cannot locate from a smooth guard; the implicit method, which is that
 * velocity-level step, reports the same scenes with its own warning. */

/* every contact-set row and friction group fits stop_friction.h's problem */
_Static_assert(MAX_ROWS <= SF_MAX_ROWS, "stop_friction.h holds every contact-set row");
_Static_assert(EXDEX_MAX_STOPS + MAX_ROWS <= SF_MAX_STOPS, "stop_friction.h holds every friction group");

#define SF_TOL 1e-10  /* sign slack of the mode checks: x the scene's acceleration V / T and force F */
#define SF_SAME_LINE 1e-6  /* obstacle rows whose unit in-plane normals differ by at most this share a group */

/* The contact set as stop_friction.h's problem at (kin, y): its rows, their
 * friction groups (stop_friction.h's "stops") and each group's slip. */
typedef struct sf_set {
    sf_row rows[SF_MAX_ROWS];
    sf_stop st[SF_MAX_STOPS];
    double s[SF_MAX_STOPS], tb[SF_MAX_STOPS];  /* a group's slip and its slip at v = 0 */
    int has[SF_MAX_STOPS];                     /* the group has contact-set rows */
    int grp[MAX_ROWS];                         /* the group of each contact-set row */
    int ng;                                    /* groups */
} sf_set;

/* The unit in-plane normal (B) of planar row r at (kin, y): the direction
 * its gap grows in when the object's point moves (a stop's, an obstacle
 * face's, or orow_point's). */
static void sf_row_normal(const hyb *H, const exdex_kinematics *kin, int r, const double *y, double n[2])
{
    int base = H->ns * H->nv;
    double nB[3], nn;
    if (r < base) {
        ex_mulmtv3(nB, kin->R, H->m->sn[r / H->nv]);
    } else {
        contact_point cp;
        orow_point(H->m, kin, r - base, y, &cp);
        memcpy(nB, cp.nB, sizeof nB);
    }
    nn = hypot(nB[0], nB[1]);
    n[0] = nn > 0.0 ? nB[0] / nn : 0.0;
    n[1] = nn > 0.0 ? nB[1] / nn : 0.0;
}

/* Friction groups of the contact-set rows at (kin, y) into grp: a group is
 * a line of contact, whose rows slip together (one slip, one tangent row:
 * two points on one line have the same arm of the tangent about the centre
 * of mass and the same frame slip along it). Stop k's rows are group k;
 * an obstacle's rows join the first group of the same obstacle whose
 * normal agrees to SF_SAME_LINE (the vertices on one face; the section
 * vertices on one edge of the object; both, where a face lies flush on an
 * edge), else start one, numbered from ns. Returns the count, -1 beyond
 * SF_MAX_STOPS. */
static int sf_groups(const hyb *H, const exdex_kinematics *kin, const double *y, int *grp)
{
    double gn[SF_MAX_STOPS][2];
    int gsrc[SF_MAX_STOPS], ng = H->ns, base = H->ns * H->nv;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i], src, g;
        double n[2];
        if (r < base) {
            grp[i] = r / H->nv;
            continue;
        }
        src = hrow_src(H, r);
        sf_row_normal(H, kin, r, y, n);
        for (g = H->ns; g < ng; g++)
            if (gsrc[g] == src && fabs(n[0] - gn[g][0]) <= SF_SAME_LINE && fabs(n[1] - gn[g][1]) <= SF_SAME_LINE) break;
        if (g == ng) {
            if (ng == SF_MAX_STOPS) return -1;
            gsrc[ng] = src;
            gn[ng][0] = n[0];
            gn[ng][1] = n[1];
            ng++;
        }
        grp[i] = g;
    }
    return ng;
}

/* The contact-set rows at (kin, y) as stop_friction.h's problem into S (groups:
 * those fixed at the decision, else sf_groups); a group's slip is its first
 * set row's (contact_slip_planar, orow_slip). A group in SF_ROLL with |s| >
 * zsw is given the slide of its sign. Returns the row count, or -1 when it
 * exceeds SF_MAX_ROWS or the groups SF_MAX_STOPS (rows then hold only the
 * first SF_MAX_ROWS; with the groups found, grp, has, s, tb, st are
 * complete). */
static int sf_build(hyb *H, const exdex_kinematics *kin, const double *y, sf_set *S)
{
    const exdex_model *m = H->m;
    int base = H->ns * H->nv;
    if (H->sgn > 0) {
        memcpy(S->grp, H->sg, (size_t)H->ncs * sizeof *S->grp);
        S->ng = H->sgn;
    } else {
        S->ng = sf_groups(H, kin, y, S->grp);
        if (S->ng < 0) {
            S->ng = 0;
            return -1;
        }
    }
    for (int k = 0; k < S->ng; k++) {
        S->has[k] = 0;
        S->s[k] = S->tb[k] = 0.0;
        S->st[k].mu = k < H->ns ? model_source_mu(m, k) : 0.0;
        S->st[k].fm = H->fm[k];
        S->st[k].sdd0 = 0.0;
        S->st[k].T[0] = S->st[k].T[1] = S->st[k].T[2] = 0.0;
    }
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i], k = S->grp[i];
        sf_stop *st = &S->st[k];
        if (i < SF_MAX_ROWS) {
            hrow_planar(H, kin, r, y, y + 3, S->rows[i].G, NULL, &S->rows[i].gdd0);
            S->rows[i].stop = k;
        }
        if (S->has[k]) continue;
        S->has[k] = 1;
        if (r < base) {
            S->s[k] = contact_slip_planar(m, kin, k, r % H->nv, y, y + 3, st->T, &S->tb[k], &st->sdd0);
        } else {
            st->mu = model_source_mu(m, hrow_src(H, r));
            S->s[k] = orow_slip(m, kin, r - base, y, y + 3, st->T, &S->tb[k], &st->sdd0);
        }
        if (st->fm == SF_ROLL && fabs(S->s[k]) > H->zsw) st->fm = S->s[k] > 0.0 ? SF_SLIDE_P : SF_SLIDE_M;
    }
    return H->ncs > SF_MAX_ROWS ? -1 : H->ncs;
}

/* The groups of the contact set fixed for the mode after a decision at
 * (t, y), so that between decisions (the contact set held) every guard and
 * mode keeps its group. */
static void sf_fix_groups(hyb *H, double t, const double *y)
{
    frame f;
    exdex_kinematics kin;
    int ng;
    H->sgn = 0;
    if (!H->ncs || frame_seg(H, t, &f, &kin)) return;
    ng = sf_groups(H, &kin, y, H->sg);
    H->sgn = ng > 0 ? ng : 0;
}

/* The problem solved at (kin, y) with the acceleration a without stops
 * (sf_solve); res (may be NULL) gets the solution. Returns 0 when no mode is
 * consistent (then nothing is written but res). */
static int sf_solve_at(hyb *H, const exdex_kinematics *kin, const double *y, const double a[3], sf_result *res)
{
    sf_set S;
    int ok;
    const model_scales *sc = &H->m->scale;
    if (sf_build(H, kin, y, &S) < 0) return 0;
    ok = sf_solve(H->ncs, S.rows, S.ng, S.st, H->m->minv, a, SF_TOL * sc->V / sc->T, SF_TOL * sc->F, res);
    H->st->stop_iterations += (size_t)res->tried;
    return ok;
}

/* contact_acc_planar with frictional stops: 1 with qdd, lam, acc as it
 * defines them (2: the mode is a lock, stop_friction.h: lam is one split of
 * indeterminate forces, lock_rows (may be NULL) the set rows it holds, bit
 * i for H->cs[i]), 0 when no mode is consistent (the caller then takes the
 * stops frictionless). */
static int sf_acc(hyb *H, const exdex_kinematics *kin, const double *y, const double afree[3], double qdd[3],
                  double *lam, double *acc, unsigned *lock_rows)
{
    sf_result res;
    if (!sf_solve_at(H, kin, y, afree, &res)) return 0;
    if (lock_rows) *lock_rows = res.lock ? res.mask : 0u;
    memcpy(qdd, res.qdd, sizeof res.qdd);
    for (int i = 0; i < H->ncs; i++) {
        lam[i] = res.lam[i];
        if (acc) acc[i] = res.acc[i];
    }
    return 1 + res.lock;
}

/* planar_rest with frictional stops (the same contract): the least plate
 * friction over the stop forces in their cones (above). Returns -1 when
 * the generators exceed ldp_min_combination's rows (planar_rest then
 * takes the stops frictionless). */
static double sf_rest(hyb *H, const exdex_kinematics *kin, const double *y, const double F[3], double w[3],
                      double *lam)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    double D[LDP_MAX_ROWS][3], B[LDP_MAX_ROWS][3], c[LDP_MAX_ROWS], a[3], mF[3], P[3];
    int own[LDP_MAX_ROWS], ng = 0, it = 0;
    sf_set S;
    if (2 * H->ncs > LDP_MAX_ROWS) return -1.0;
    sf_build(H, kin, y, &S);
    if (H->ncs && S.ng == 0) return -1.0;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i], k = S.grp[i], fm;
        double G[3], mu = S.st[k].mu;
        const double *T = S.st[k].T, tb = S.tb[k];
        hrow_planar(H, kin, r, y, y + 3, G, NULL, NULL);
        fm = H->fm[k] == SF_ROLL ? (fabs(tb) <= H->zsw ? SF_STICK : tb > 0.0 ? SF_SLIDE_P : SF_SLIDE_M) : H->fm[k];
        if (!(mu > 0.0) || fm == SF_NONE) {
            memcpy(D[ng], G, sizeof G);
            own[ng++] = i;
        } else if (fm == SF_STICK) {
            for (int c2 = 0; c2 < 3; c2++) {
                D[ng][c2] = G[c2] + mu * T[c2];
                D[ng + 1][c2] = G[c2] - mu * T[c2];
            }
            own[ng++] = i;
            own[ng++] = i;
        } else {
            double sg = fm == SF_SLIDE_P ? 1.0 : -1.0;
            for (int c2 = 0; c2 < 3; c2++) D[ng][c2] = G[c2] - mu * sg * T[c2];
            own[ng++] = i;
        }
    }
    for (int c2 = 0; c2 < 3; c2++) mF[c2] = -F[c2];
    model_patch_of_gen(m, MODEL_CS(y[2]), mF, a);
    for (int c2 = 0; c2 < 3; c2++) a[c2] /= m->e[c2];
    for (int g = 0; g < ng; g++) {
        double mD[3] = {-D[g][0], -D[g][1], -D[g][2]};
        model_patch_of_gen(m, MODEL_CS(y[2]), mD, B[g]);
        for (int c2 = 0; c2 < 3; c2++) B[g][c2] /= m->e[c2];
    }
    ldp_min_combination(ng, a, (const double (*)[3])B, c, &it);
    H->st->stop_iterations += (size_t)it;
    for (int i = 0; i < H->ncs; i++) lam[i] = 0.0;
    for (int c2 = 0; c2 < 3; c2++) P[c2] = -F[c2];
    for (int g = 0; g < ng; g++) {
        lam[own[g]] += c[g];
        for (int c2 = 0; c2 < 3; c2++) P[c2] -= c[g] * D[g][c2];
    }
    model_patch_of_gen(m, MODEL_CS(y[2]), P, w);
    return model_ell_norm(m, w);
}

/* Accelerations in planar contact: qdd = M^-1 (F + P + G_A^T lam), lam >= 0
 * the stop forces of the contact-set rows, complementary to their gap
 * accelerations G_i qdd + gdd0_i >= 0 (the small LCP G M^-1 G^T lam =
 * -(G M^-1 (F + P) + gdd0) with complementarity): the M-metric projection
 * of the free acceleration (ldp_project). The plate friction does not depend on
 * the stop forces (the grip force is given). acc_i (may be NULL) gets the
 * gap acceleration of every contact-set row. Returns 1 when the stop
 * friction's mode is a lock (sf_acc; lock_rows, may be NULL, gets its rows),
 * else 0. */
static int contact_acc_planar(hyb *H, const exdex_kinematics *kin, const double *y, const double afree[3],
                              double qdd[3], double *lam, double *acc, unsigned *lock_rows)
{
    double Gr[MAX_ROWS][3], b[MAX_ROWS];
    int lk = H->sfric ? sf_acc(H, kin, y, afree, qdd, lam, acc, lock_rows) : 0;
    if (lock_rows && lk != 2) *lock_rows = 0u;
    if (lk) return lk - 1;
    b[0] = 0.0;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double gdd0 = 0.0;
        hrow_planar(H, kin, r, y, y + 3, Gr[i], NULL, &gdd0);
        b[i] = -gdd0;
    }
    ldp_project(H->m->minv, H->ncs, (const double (*)[3])Gr, b, afree, FQ_MIN, qdd, lam, &H->st->stop_iterations, &H->st->warnings);
    if (acc)
        for (int i = 0; i < H->ncs; i++) acc[i] = ex_dot3(Gr[i], qdd) - b[i];
    return 0;
}

/* ------------------------------------------------- frictional impacts
 * An impact on frictional rows is plastic with Coulomb friction at the
 * rows: the impulse-level problem of stop_impulse.h (Stewart-Trinkle velocity
 * level, exact mode enumeration) over the vanishing duration of the impact,
 *     M (v+ - v) = sum_i (lam_i G_i + beta_i T_i),
 *     0 <= lam_i  _|_  G_i v+ - b_i >= 0    (b_i = -(gd_i - G_i v): no approach),
 *     |beta_i| <= mu_i lam_i, beta_i = -mu_i lam_i sign(s_i) where the
 *     post-impact slip s_i = T_i v+ + tb_i != 0,
 * with no plate impulse: the plates' friction force is bounded by the grip
 * force (cap = 0 in stop_impulse.h), so its impulse over the impact is 0. This
 * is the implicit step's impulse (stop_impulse.h with the plate term cap h) in
 * the limit of a vanishing step h, and the explicit method's (cap = 0 as
 * here). Frictionless rows make it the plastic M-metric projection
 * (ldp_project), which is solved first: where no frictional row carries an
 * impulse there, that projection is the answer, and the arithmetic is that
 * of frictionless stops bit for bit.
 * Friction applies at every approach speed: the impulses scale with the
 * approach, the law does not. The one touch that is not an impact is a
 * stop grazing a resting object within the rest's own tolerance
 * (sf_graze): there the rows join the rest as contacts, at the
 * acceleration level. */

/* Coulomb coefficient of planar row r at (kin, y) and, when > 0, its slip
 * row: s = T v + tb along the tangent in the plate plane (stop rows:
 * contact_slip_planar; obstacle rows: orow_slip, the tangent at the row's
 * point). */
static double hrow_friction_planar(const hyb *H, const exdex_kinematics *kin, int r, const double *y, double T[3],
                                   double *tb)
{
    double mu;
    int base = H->ns * H->nv;
    T[0] = T[1] = T[2] = 0.0;
    *tb = 0.0;
    mu = model_source_mu(H->m, hrow_src(H, r));
    if (!(mu > 0.0)) return mu;
    if (r < base)
        contact_slip_planar(H->m, kin, r / H->nv, r % H->nv, y, y + 3, T, tb, NULL);
    else
        orow_slip(H->m, kin, r - base, y, y + 3, T, tb, NULL);
    return mu;
}

/* A stop touching a resting object at a tangency of its path (event
 * method, v = 0 held exactly by a rest): is every row that the touching
 * stops drive into the object (approach b_i > tol.rate at v = 0) a graze
 * the rest already tolerates? At the held pose the gap is a function of t
 * alone, gap(t) = -b_i (t - t0) + gdd0_i (t - t0)^2 / 2 + ..., gdd0_i its
 * acceleration at v = 0: with gdd0_i > 0 the stop's path turns back after
 * reaching at most b_i^2 / (2 gdd0_i) into the held pose. Where that is
 * within tol.rest_gap for every such row, the touch is a contact of the
 * rest (the rows join its contact set, the rest split with the stops'
 * friction decides whether it holds, and the rest ends where a row's gap
 * leaves +-tol.rest_gap), not an impact: a rest against stops moving in B
 * holds q exactly while their gaps stay within +-tol.rest_gap, so a dip
 * below that is below the resolution of the held pose (an exact tangency,
 * rate 0, arrives at a rate up to sqrt(2 gdd0 tol.rest_gap) from the held
 * pose's offset). An impulse there would be the Coulomb impulse of an
 * approach that the held pose does not determine: near a Painleve
 * configuration of the stop's friction (the friction nearly cancelling the
 * normal impulse's effect on the gap) it moves the object at many times
 * the approach, where the exact motion stays at rest. A stop whose path
 * keeps approaching (gdd0_i <= 0: a stop moving at a constant or growing
 * rate into the object), or dips deeper, strikes it: the impact with
 * Coulomb friction, at every approach speed. Returns 1 for a graze. */
static int sf_graze(const hyb *H, const exdex_kinematics *kin, const double *y, int n, const int *rows, const double *b)
{
    const exdex_model *m = H->m;
    double zero[3] = {0.0, 0.0, 0.0};
    int any = 0;
    if (H->law != LAW_COULOMB || y[3] != 0.0 || y[4] != 0.0 || y[5] != 0.0) return 0;
    for (int i = 0; i < n; i++) {
        double G[3], gd = 0.0, gdd0 = 0.0;
        if (!(b[i] > m->tol.rate)) continue;
        hrow_planar(H, kin, rows[i], y, zero, G, &gd, &gdd0);
        if (!(gdd0 > 0.0 && b[i] * b[i] <= 2.0 * gdd0 * m->tol.rest_gap)) return 0;
        any = 1;
    }
    return any;
}

/* The planar impact with friction at (kin, y): rows (their G, bounds b as
 * planar_impact_and_set builds them: the touching rows), v and lam the
 * frictionless impact (ldp_project), replaced by the frictional one when a
 * frictional row carries an impulse in it and some row is approached
 * (b_i - G_i v > tol.rate: below that a row's rate is 0 to the method, as
 * for the contact set and the impact count, and the projection only
 * removes rounding). Where stop_impulse.h finds no consistent mode (none
 * among its candidates: fc_solve) the frictionless impact stands and a
 * warning is counted. Returns 1 if v and lam were replaced, 2 for a graze
 * of a rest (sf_graze: no impulse, v and lam untouched), else 0. */
static int sf_impact(hyb *H, const exdex_kinematics *kin, const double *y, int n, const int *rows,
                     const double (*Gr)[3], const double *b, double v[3], double *lam)
{
    const exdex_model *m = H->m;
    fc_row fr[MAX_ROWS];
    fc_problem p;
    fc_result res;
    unsigned char hint[MAX_ROWS];
    double lf[MAX_ROWS], bf[MAX_ROWS], T[3], tb;
    int fric = 0, approach = 0;
    for (int i = 0; i < n; i++) {
        if (lam[i] > 0.0 && hrow_friction_planar(H, kin, rows[i], y, T, &tb) > 0.0) fric = 1;
        if (b[i] - ex_dot3(Gr[i], y + 3) > m->tol.rate) approach = 1;
    }
    if (!fric || !approach) return 0;
    if (sf_graze(H, kin, y, n, rows, b)) return 2;
    if (n > LDP_MAX_ROWS / 2) {
        H->st->warnings++;
        return 0;
    }
    for (int i = 0; i < n; i++) {
        fc_row *r = &fr[i];
        memcpy(r->G, Gr[i], sizeof r->G);
        r->mu = hrow_friction_planar(H, kin, rows[i], y, r->T, &r->tb);
        r->rhs = b[i];
        /* at v = 0 a row can carry an impulse only where its bound is 0
         * (a stop at rest in B, or moving along its face): one the gripper
         * drives into the object excludes rest, one it leaves behind
         * carries nothing (as the implicit step's rows) */
        r->rest = b[i] > m->tol.rate ? -1 : b[i] >= -m->tol.rate ? 1 : 0;
        hint[i] = lam[i] > 0.0;
    }
    memset(&p, 0, sizeof p);
    p.n = 3;
    for (int c = 0; c < 3; c++) {
        p.Md[c] = 1.0 / m->minv[c];
        p.vs[c] = y[3 + c];
        p.A[c][c] = 1.0;
    }
    p.cap = p.cap_rest = 0.0;
    p.vscale = m->scale.V;
    p.vrest = m->tol.rate;
    p.nr = n;
    p.rows = fr;
    if (!fc_solve(&p, hint, v, NULL, lf, bf, &res)) {
        H->st->warnings++;
        return 0;
    }
    H->st->stop_iterations += (size_t)res.iters;
    memcpy(v, res.v, 3 * sizeof *v);
    for (int i = 0; i < n; i++) lam[i] = lf[i];
    return 1;
}

/* The hold of a face landing flat (planar_impact_and_set) on frictional
 * stops: the held rows' normal rates are taken as 0 below zsw; a held
 * frictional stop whose slip along it is below zsw there too is decided
 * sticking (sf_decide) and its slip projected to 0 on the contact set with
 * inequality rows (sf_project_stick), which can lift a corner of the face
 * just held flat again (the tangential impulse's torque) and restart the
 * cascade the hold ends. Both are the same band: the hold takes the slip
 * to 0 with the normal rates, in one M-metric projection (the held rows as
 * equality pairs G2 v = b2 and, per held frictional stop with |T v2 + tb|
 * <= zsw, T v = -tb at its first held row). v2 and lam2 (the normal pairs'
 * multipliers, first n2 entries) are replaced when that projection
 * succeeds with finite multipliers. */
static void sf_hold_stick(hyb *H, const exdex_kinematics *kin, const double *y, int n, const int *rows,
                          const double (*Gr)[3], const double *b, int n2, double (*G2)[3], double *b2, double *v2,
                          double *lam2)
{
    double G3[2 * MAX_ROWS + 2 * NSRC_MAX][3], b3[2 * MAX_ROWS + 2 * NSRC_MAX], lam3[2 * MAX_ROWS + 2 * NSRC_MAX], v3[3];
    int done[NSRC_MAX] = {0}, n3 = n2, add = 0;
    memcpy(G3, G2, (size_t)n2 * sizeof *G3);
    memcpy(b3, b2, (size_t)n2 * sizeof *b3);
    for (int i = 0; i < n; i++) {
        double T[3], tb, rate = ex_dot3(Gr[i], y + 3) - b[i];
        int src = hrow_src(H, rows[i]);
        if (rate > H->zsw || done[src]) continue;
        done[src] = 1;
        if (!(hrow_friction_planar(H, kin, rows[i], y, T, &tb) > 0.0)) continue;
        if (!(fabs(ex_dot3(T, v2) + tb) <= H->zsw)) continue;
        for (int c = 0; c < 3; c++) {
            G3[n3][c] = T[c];
            G3[n3 + 1][c] = -T[c];
        }
        b3[n3] = -tb;
        b3[n3 + 1] = tb;
        n3 += 2;
        add = 1;
    }
    if (!add || !ldp_project(H->m->minv, n3, (const double (*)[3])G3, b3, y + 3, FQ_MIN, v3, lam3,
                             &H->st->stop_iterations, &H->st->warnings))
        return;
    for (int i = 0; i < n3; i++)
        if (!isfinite(lam3[i])) return;
    memcpy(v2, v3, sizeof v3);
    memcpy(lam2, lam3, (size_t)n2 * sizeof *lam2);
}

/* Impacts of a planar object on the touching rows (gap <= tol.touch) at
 * (t, y): the plastic impact projects v onto G v >= -(gd - G v) (no
 * approach) in the M metric; with frictional rows carrying an impulse
 * there, the impact with Coulomb friction replaces it (sf_impact); the
 * impulses go into the stops' force integrals. Then the contact set: the
 * touching rows whose rate is ~0 and which push (lam > 0) under the
 * accelerations of the mode. */
static void planar_impact_and_set(hyb *H, double t, const exdex_kinematics *kin, double *y)
{
    const exdex_model *m = H->m;
    double Gr[MAX_ROWS][3], b[MAX_ROWS], lam[MAX_ROWS], v[3], ga[MAX_ROWS], gda[MAX_ROWS];
    int rows[MAX_ROWS], n = 0, na = hrow_all_planar(H, kin, y, rows, Gr, ga, gda), graze = 0;
    for (int i = 0; i < na; i++) {
        if (ga[i] > m->tol.touch) continue;
        memcpy(Gr[n], Gr[i], sizeof Gr[n]);
        b[n] = -(gda[i] - ex_dot3(Gr[n], y + 3));
        rows[n++] = rows[i];
    }
    H->ncs = 0;
    if (!n) return;
    if (ldp_project(m->minv, n, (const double (*)[3])Gr, b, y + 3, FQ_MIN, v, lam, &H->st->stop_iterations, &H->st->warnings)) {
        double G2[2 * MAX_ROWS][3], b2[2 * MAX_ROWS], lam2[2 * MAX_ROWS], v2[3];
        if (H->sfric) graze = sf_impact(H, kin, y, n, rows, (const double (*)[3])Gr, b, v, lam) == 2;
        if (graze) {
            /* a graze of a rest (sf_graze): no impulse, the rows join the
             * rest's contact set */
            memcpy(v, y + 3, sizeof v);
            for (int i = 0; i < n; i++) lam[i] = 0.0;
        }
        double per_stop[NSRC_MAX] = {0};
        int n2 = 0, lift = 0;
        for (int i = 0; i < n; i++) {
            y[9 + hrow_src(H, rows[i])] += lam[i];
            /* an approached row (gap rate below -tol.rate) takes an impact */
            if (lam[i] > 0 && ex_dot3(Gr[i], y + 3) - b[i] < -m->tol.rate)
                per_stop[hrow_src(H, rows[i])] += lam[i];
        }
        for (int k = 0; k < H->ns + H->no; k++) method_note_impact(H->st, t, k, per_stop[k]);
        memcpy(y + 3, v, sizeof v);
        /* A plastic impact at one corner of a face that lands flat lifts
         * the other corner off, which falls back, impacts, lifts the first:
         * rates shrinking geometrically, events accumulating at a finite
         * time (Zeno). Once the lift-off rates are below zsw the touching
         * rows that would separate that slowly are held at rate 0 instead
         * (equality rows, an M-metric projection again): the face rests. */
        for (int i = 0; i < n; i++) {
            double rate = ex_dot3(Gr[i], y + 3) - b[i];
            if (rate > m->tol.rate && rate <= H->zsw) lift = 1;
        }
        for (int i = 0; lift && i < n; i++) {
            double rate = ex_dot3(Gr[i], y + 3) - b[i];
            if (rate > H->zsw) continue;
            for (int c = 0; c < 3; c++) {
                G2[n2][c] = Gr[i][c];
                G2[n2 + 1][c] = -Gr[i][c];
            }
            b2[n2] = b[i];
            b2[n2 + 1] = -b[i];
            n2 += 2;
        }
        if (lift && ldp_project(m->minv, n2, (const double (*)[3])G2, b2, y + 3, FQ_MIN, v2, lam2,
                                &H->st->stop_iterations, &H->st->warnings)) {
            /* The hold may pull a stop (the lifting corner of a face held
             * flat, or an object held between two stops while the other
             * stop pushes), but a hold that pushes nowhere is no contact
             * reaction: when no stop of this event gets a positive net
             * impulse (impact + hold), e.g. an object between two nearly
             * opposed stops both pulled, or a non-finite hold, the hold is
             * not applied: the plastic impact velocity stands and the
             * rows separate. */
            double net[NSRC_MAX] = {0};
            int pull = 1;
            for (int i = 0, r = 0; i < n; i++) {
                double rate = ex_dot3(Gr[i], y + 3) - b[i];
                net[hrow_src(H, rows[i])] += lam[i];
                if (rate > H->zsw) continue;
                net[hrow_src(H, rows[i])] += lam2[r] - lam2[r + 1];
                r += 2;
            }
            for (int k = 0; k < H->ns + H->no; k++)
                if (net[k] > 0.0) pull = 0;
            for (int k = 0; k < H->ns + H->no; k++)
                if (!isfinite(net[k])) pull = 1;
            if (!pull && H->sfric) sf_hold_stick(H, kin, y, n, rows, (const double (*)[3])Gr, b, n2, G2, b2, v2, lam2);
            for (int i = 0, r = 0; !pull && i < n; i++) {
                double rate = ex_dot3(Gr[i], y + 3) - b[i];
                if (rate > H->zsw) continue;
                y[9 + hrow_src(H, rows[i])] += lam2[r] - lam2[r + 1];
                r += 2;
            }
            if (!pull) memcpy(y + 3, v2, sizeof v2);
        }
    }
    for (int i = 0; i < n; i++) {
        double rate = ex_dot3(Gr[i], y + 3) - b[i];
        if (fabs(rate) <= m->tol.rate || (graze && rate < 0.0)) H->cs[H->ncs++] = rows[i];
    }
}

/* Positions back onto the stops at (t, y), when a row penetrates: the
 * M-metric projection of q onto G dq >= -gap of every row (a located impact
 * lies up to |gap rate| ROOT_TOL beyond its stop, a rest against a stop
 * moving in B up to REST_GAP). The rows that do not penetrate are
 * constraints too: projecting only the penetrating ones can turn the object
 * into a touching neighbour (a rotation about one corner pushes the next
 * corner in), by as much as it removes. */
static void planar_unpenetrate(hyb *H, const exdex_kinematics *kin, double *y)
{
    double Gr[MAX_ROWS][3], b[MAX_ROWS], lam[MAX_ROWS], zero[3] = {0, 0, 0}, dq[3];
    int rows[MAX_ROWS], n = hrow_all_planar(H, kin, y, rows, Gr, b, NULL), pen = 0;
    for (int i = 0; i < n; i++) {
        if (b[i] < 0.0) pen = 1;
        b[i] = -b[i];
    }
    if (pen && ldp_project(H->m->minv, n, (const double (*)[3])Gr, b, zero, FQ_MIN, dq, lam, &H->st->stop_iterations, &H->st->warnings))
        for (int c = 0; c < 3; c++) y[c] += dq[c];
}

/* The pose reported at (t, y) (an output sample, the smallest gap): a
 * planar rest holds q exactly, also while a stop or an obstacle moving in B
 * (an obstacle is fixed in the world, so it moves in B with the gripper)
 * closes in on it (up to tol.rest_gap, where the rest ends); reported is
 * the held pose pushed out of the stops and obstacles (planar_unpenetrate,
 * the projection the decision at the rest's end makes), a function of q
 * and t alone. Projecting the
 * held q itself after every step would move it by the stop's travel over
 * each step: the rest's end, and the answer, would depend on where steps
 * end (the output grid among them). Any other mode: y as it is. */
static const double *reported_pose(hyb *H, double t, const double *y, double *buf)
{
    frame f;
    exdex_kinematics kin;
    if (H->ndof != 3 || !(H->ns || H->no) || H->law != LAW_COULOMB || H->mode != MODE_STICK) return y;
    memcpy(buf, y, (size_t)H->ny * sizeof *y);
    if (!frame_seg(H, t, &f, &kin)) planar_unpenetrate(H, &kin, buf);
    return buf;
}

/* Rest against the contact-set rows (event method, stick): can the object
 * stay at rest with stop forces lam >= 0 and a plate wrench inside the
 * ellipsoid? The wrench needed is w(lam) = patch(-(F + G^T lam)); minimise
 * |E^-1 w(lam)| over lam >= 0 (ldp_min_combination; the
 * minimiser is the split with the least friction, as in the implicit method).
 * Returns the minimum (rest holds iff <= cap (1 + TOLF)); w, lam the split. */
static double planar_rest(hyb *H, const exdex_kinematics *kin, const double *y, const double F[3], double w[3],
                          double *lam)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    double B[MAX_ROWS][3], a[3], mF[3], P[3];
    int it = 0;
    if (H->sfric) {
        double r = sf_rest(H, kin, y, F, w, lam);
        if (r >= 0.0) return r;
    }
    for (int c = 0; c < 3; c++) mF[c] = -F[c];
    model_patch_of_gen(m, MODEL_CS(y[2]), mF, a);
    for (int c = 0; c < 3; c++) a[c] /= m->e[c];
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double G[3], mG[3];
        hrow_planar(H, kin, r, y, y + 3, G, NULL, NULL);
        for (int c = 0; c < 3; c++) mG[c] = -G[c];
        model_patch_of_gen(m, MODEL_CS(y[2]), mG, B[i]);
        for (int c = 0; c < 3; c++) B[i][c] /= m->e[c];
    }
    ldp_min_combination(H->ncs, a, (const double (*)[3])B, lam, &it);
    H->st->stop_iterations += (size_t)it;
    for (int c = 0; c < 3; c++) P[c] = -F[c];
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double G[3];
        hrow_planar(H, kin, r, y, y + 3, G, NULL, NULL);
        for (int c = 0; c < 3; c++) P[c] -= lam[i] * G[c];
    }
    model_patch_of_gen(m, MODEL_CS(y[2]), P, w);
    return model_ell_norm(m, w);
}

/* The load at (t, y) (f, kin its frame terms): the ellipsoid norm |E^-1 w|
 * of the plate wrench w that holds the object at zero velocity (against
 * the contact-set rows: the least-friction split of planar_rest).
 * planar_load_held: would the object stay at rest there (the stick test of
 * decide): that load inside the static ellipsoid? */
static double planar_load(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    double F[3], w[3], zero[3] = {0, 0, 0}, lam[MAX_ROWS];
    model_force_planar(m, f, y, zero, F);
    if (H->ncs) return planar_rest(H, kin, y, F, w, lam);
    for (int i = 0; i < 3; i++) F[i] = -F[i];
    model_patch_of_gen(m, MODEL_CS(y[2]), F, w);
    return model_ls_gauge(m, w);
}

static int planar_load_held(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    return planar_load(H, f, kin, y) <= H->caps * (1.0 + TOLF);
}

/* Regularised, planar, C_s > C: whether the held regime applies (see the
 * top), and the slip speed |E u| at y. */
static int smooth_two(const hyb *H)
{
    return H->law == LAW_SMOOTH && H->ndof == 3 && H->m->capks > H->m->capk;
}

static double planar_slip_speed(const hyb *H, const double *y)
{
    hyb_pads(H, y);
    double u[3], eu[3];
    model_patch_slip(H->m, MODEL_CS(y[2]), y + 3, u);
    for (int i = 0; i < 3; i++) eu[i] = H->m->e[i] * u[i];
    return sqrt(ex_dot3(eu, eu));
}

/* Does a contact-set row's stop recede in B, at zero velocity, at SLIP_PUSH
 * zsw or faster, while friction alone cannot hold the load at rest (see
 * decide)? f, kin the frame terms at (t, y). */
static int planar_set_recedes(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    hyb_pads(H, y);
    double zero[3] = {0, 0, 0}, F[3], w[3];
    if (!H->ncs) return 0;
    model_force_planar(H->m, f, y, zero, F);
    for (int i = 0; i < 3; i++) F[i] = -F[i];
    model_patch_of_gen(H->m, MODEL_CS(y[2]), F, w);
    if (model_ell_norm(H->m, w) <= H->caps * (1.0 + TOLF)) return 0;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double G[3], gd;
        hrow_planar(H, kin, r, y, zero, G, &gd, NULL);
        if (gd >= SLIP_PUSH * H->zsw) return 1;
    }
    return 0;
}

/* Planar applied force F (B, generalized) and plate friction wrench w
 * (patch) of the current mode at (t, y): stick holds everything (w = -F as
 * a patch wrench; the stop forces of a rest against stops are not part of
 * it), slip the sliding law (the maximum-dissipation direction from rest),
 * regularised the smooth law. */
static int planar_friction(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, double F[3],
                           double w[3])
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    double th = y[2];
    const double *v = y + 3;
    model_force_planar(m, f, y, v, F);
    if (H->mode == MODE_STICK) {
        double mF[3] = {-F[0], -F[1], -F[2]};
        model_patch_of_gen(m, MODEL_CS(th), mF, w);
    } else {
        double u[3], eu[3], sig;
        model_patch_slip(m, MODEL_CS(th), v, u);
        for (int i = 0; i < 3; i++) eu[i] = m->e[i] * u[i];
        sig = sqrt(ex_dot3(eu, eu));
        if (H->law == LAW_SMOOTH) {
            if (H->caps == H->cap) {
                double den = sqrt(sig * sig + H->eps * H->eps);
                for (int i = 0; i < 3; i++) w[i] = -H->cap * m->e[i] * eu[i] / den;
            } else {
                double gn = smooth_gain(H, sig);
                for (int i = 0; i < 3; i++) w[i] = -gn * m->e[i] * eu[i];
            }
        } else if (sig > 0.0 && !H->small) {
            if (m->ls_exact) {
                /* the exact surface's maximum-dissipation wrench of the slip */
                limitsurf_wrench(&m->ls, u, w, NULL);
                for (int i = 0; i < 3; i++) w[i] *= H->cap;
            } else {
                for (int i = 0; i < 3; i++) w[i] = -H->cap * m->e[i] * eu[i] / sig;
            }
        } else {
            /* slip starting from rest, and a small slip growing from rest:
             * the maximum-dissipation wrench for an infinitesimal step,
             * u' = b + W w (paper Eq. 6). While |E u| is small the sliding
             * law's direction E u / |E u| relaxes onto this one at the rate
             * C |K| / |E u| (K = E W E): infinitely stiff as the slip starts,
             * and below the error control's resolution (atol) E u carries no
             * direction at all. The slip follows this direction to within
             * |E u| |d(direction)/dt| / (C |K|) (quasi-static relaxation) */
            double wF[3], b[3];
            exdex_friction_result res;
            int st;
            model_patch_of_gen(m, MODEL_CS(th), F, wF);
            ex_mulmv3(b, m->prep.W, wF);
            st = limitsurf_step(&m->ls, &m->prep, b, H->cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &res);
            if (st) return st;
            memcpy(w, res.p, 3 * sizeof *w);
            if (H->ncs && kin) {
                /* against stops the slip starts along the constrained
                 * acceleration: the friction and the stop forces are
                 * found together, by the fixed point w = -C E^2 E u'/|E u'|
                 * of u' the patch slip of the M-metric projection of the
                 * free acceleration (bounded; the last iterate is kept) */
                for (int it = 0; it < 16; it++) {
                    double P[3], a[3], qdd[3], lam[MAX_ROWS], ua[3], ea[3], sa, wn[3], d = 0.0;
                    model_gen_of_patch(m, MODEL_CS(th), w, P);
                    for (int i = 0; i < 3; i++) a[i] = m->minv[i] * (F[i] + P[i]);
                    contact_acc_planar(H, kin, y, a, qdd, lam, NULL, NULL);
                    model_patch_slip(m, MODEL_CS(th), qdd, ua);
                    for (int i = 0; i < 3; i++) ea[i] = m->e[i] * ua[i];
                    sa = sqrt(ex_dot3(ea, ea));
                    if (!(sa > 0.0)) break;
                    for (int i = 0; i < 3; i++) {
                        wn[i] = -H->cap * m->e[i] * ea[i] / sa;
                        d = fmax(d, fabs(wn[i] - w[i]) / m->e[i]);
                        w[i] = wn[i];
                    }
                    H->st->stop_iterations++;
                    if (d <= 1e-12 * H->cap) break;
                }
            }
        }
    }
    return EXDEX_OK;
}

/* A contact-set row whose separation was located at t and that the
 * decision there put back into the set, twice at the same time: at the
 * separation instant its force and gap acceleration both vanish, and the
 * complementarity solve at the decided state may return a force of
 * rounding size (lam > 0) with the guard lam G M^-1 G^T - gap acceleration
 * of rounding size below 0, which the next step then finds falling (the row
 * separates with the row still in the set: the step would be taken with a
 * violated guard and the row's gap unwatched, its stop no longer able to
 * act as an impact). The event's own answer stands: the row leaves the set
 * (its free gap guard watches it again; a row that still pushes comes back
 * by an impact at rate ~0); with frictional rows the friction groups and
 * modes of the rows left are decided again (sf_redecide). */
static void set_tie_leaves(hyb *H, int r)
{
    int n = 0;
    for (int i = 0; i < H->ncs; i++)
        if (H->cs[i] != r) H->cs[n++] = H->cs[i];
    H->ncs = n;
}

static void planar_prune_set(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y);

/* The other tie: a free stop row whose gap crossing was located at t, twice
 * at the same time, with the decision leaving it free: a corner (or a face,
 * two corners) arriving at its stop tangentially (normal rate ~0, the
 * object sliding along it) and pressed into it, whose rate at the located
 * point is positive by up to the gap acceleration times the location
 * tolerance, above tol.rate, so that it neither takes an impact nor joins
 * the contact set, and the next step drives it into the stop. The event's
 * answer stands: every touching stop row (gap <= tol.touch) whose rate is
 * below zsw joins the set, where the complementarity solve keeps the rows
 * that push (planar_prune_set). */
static void set_tie_joins(hyb *H, const double *y, double t)
{
    frame f;
    exdex_kinematics kin;
    unsigned char in[MAX_ROWS];
    if (frame_seg(H, t, &f, &kin)) return;
    memset(in, 0, (size_t)(H->ns * H->nv));
    for (int i = 0; i < H->ncs; i++)
        if (H->cs[i] < H->ns * H->nv) in[H->cs[i]] = 1;
    for (int r = 0; r < H->ns * H->nv && H->ncs < MAX_ROWS; r++) {
        double G[3], gd;
        if (in[r]) continue;
        if (contact_row_planar(H->m, &kin, r / H->nv, r % H->nv, y, y + 3, G, &gd, NULL) <= H->m->tol.touch &&
            fabs(gd) <= H->zsw)
            H->cs[H->ncs++] = r;
    }
    planar_prune_set(H, &f, &kin, y);
}

/* Keep in the planar contact set only the rows that push (lam > 0) under
 * the accelerations of the current (non-stick) mode at (t, y); in a lock
 * (stop_friction.h) the rows it holds: their forces are indeterminate, a row
 * without force in one split carries it in another, and they all hold (gap
 * acceleration 0) while the lock lasts. */
static void planar_prune_set(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y)
{
    hyb_pads(H, y);
    double F[3], w[3], P[3], a[3], qdd[3], lam[MAX_ROWS];
    int n = 0;
    if (!H->ncs || H->mode == MODE_STICK) return;
    if (planar_friction(H, f, kin, y, F, w)) return;
    model_gen_of_patch(H->m, MODEL_CS(y[2]), w, P);
    for (int i = 0; i < 3; i++) a[i] = H->m->minv[i] * (F[i] + P[i]);
    unsigned lk = 0u;
    contact_acc_planar(H, kin, y, a, qdd, lam, NULL, &lk);
    for (int i = 0; i < H->ncs; i++)
        if (lam[i] > 0.0 || (lk >> i & 1u)) H->cs[n++] = H->cs[i];
    H->ncs = n;
}

/* ------------------------------------ planar frictional stops: modes */

static int sf_free_acc(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, double a[3]);

/* In a lock of the current modes at (t, y) (S its problem): y's velocity
 * replaced by the one holding the lock's rows at rate 0 and its sticking
 * stops' slips at 0 (sf_lock_solve to tol.rate), provided the set's other
 * rows do not approach at it. Returns 1 if replaced. */
static int sf_lock_velocity(hyb *H, const frame *f, const exdex_kinematics *kin, double *y, const sf_set *S)
{
    double a[3], qdd[3], lamc[MAX_ROWS], C[SF_MAX_ROWS + SF_MAX_STOPS][3], rhs[SF_MAX_ROWS + SF_MAX_STOPS], v[3],
        Go[SF_MAX_ROWS][3], bo[SF_MAX_ROWS];
    unsigned lk = 0u;
    int k = 0, no = 0;
    if (sf_free_acc(H, f, kin, y, a) != EXDEX_OK) return 0;
    contact_acc_planar(H, kin, y, a, qdd, lamc, NULL, &lk);
    if (!lk) return 0;
    for (int i = 0; i < H->ncs && i < SF_MAX_ROWS; i++) {
        double G[3], gd;
        hrow_planar(H, kin, H->cs[i], y, y + 3, G, &gd, NULL);
        if (lk >> i & 1u) {
            memcpy(C[k], G, sizeof G);
            rhs[k++] = -(gd - ex_dot3(G, y + 3));
        } else {
            memcpy(Go[no], G, sizeof G);
            bo[no++] = -(gd - ex_dot3(G, y + 3));
        }
    }
    for (int j = 0; j < S->ng; j++) {
        if (!(S->has[j] && S->st[j].mu > 0.0 && H->fm[j] == SF_STICK)) continue;
        memcpy(C[k], S->st[j].T, sizeof C[k]);
        rhs[k++] = -S->tb[j];
    }
    if (!sf_lock_solve(k, (const double (*)[3])C, rhs, H->m->minv, H->m->tol.rate, v)) return 0;
    for (int i = 0; i < no; i++)
        if (!(ex_dot3(Go[i], v) >= bo[i] - H->m->tol.rate)) return 0;
    memcpy(y + 3, v, sizeof v);
    return 1;
}

/* The velocity of a planar object with sticking stops (H->fm SF_STICK,
 * not at rest) projected in the M metric onto their slips 0 (T v = -tb)
 * and the contact-set rows' no-approach G v >= -(gd - G v). In a lock
 * (stop_friction.h: more such rows than coordinates, dependent) the velocity is
 * the one that holds the lock's rows at rate 0 and its stops' slips at 0
 * (sf_lock_solve, to tol.rate), the set's other rows not approaching; the
 * projection of the dependent rows as inequality pairs would be
 * inconsistent by rounding. */
static void sf_project_stick(hyb *H, const frame *f, const exdex_kinematics *kin, double *y)
{
    sf_set S;
    double Gr[SF_MAX_ROWS + 2 * SF_MAX_STOPS][3], b[SF_MAX_ROWS + 2 * SF_MAX_STOPS],
        lam[SF_MAX_ROWS + 2 * SF_MAX_STOPS], v[3];
    int n = 0, stick = 0;
    if (H->mode == MODE_STICK || !H->ncs || sf_build(H, kin, y, &S) < 0) return;
    for (int k = 0; k < S.ng; k++) stick += S.has[k] && S.st[k].mu > 0.0 && H->fm[k] == SF_STICK;
    if (!stick) return;
    if (H->ncs + stick > 3 && sf_lock_velocity(H, f, kin, y, &S)) return;
    for (int i = 0; i < H->ncs; i++) {
        int r = H->cs[i];
        double gd;
        hrow_planar(H, kin, r, y, y + 3, Gr[n], &gd, NULL);
        b[n] = -(gd - ex_dot3(Gr[n], y + 3));
        n++;
    }
    for (int k = 0; k < S.ng; k++) {
        if (!(S.has[k] && S.st[k].mu > 0.0 && H->fm[k] == SF_STICK)) continue;
        for (int c = 0; c < 3; c++) {
            Gr[n][c] = S.st[k].T[c];
            Gr[n + 1][c] = -S.st[k].T[c];
        }
        b[n] = -S.tb[k];
        b[n + 1] = S.tb[k];
        n += 2;
    }
    if (ldp_project(H->m->minv, n, (const double (*)[3])Gr, b, y + 3, FQ_MIN, v, lam, &H->st->stop_iterations,
                    &H->st->warnings))
        memcpy(y + 3, v, sizeof v);
}

/* The acceleration without stops of the current (non-stick) mode at y. */
static int sf_free_acc(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, double a[3])
{
    hyb_pads(H, y);
    double F[3], w[3], P[3];
    int st = planar_friction(H, f, kin, y, F, w);
    if (st) return st;
    model_gen_of_patch(H->m, MODEL_CS(y[2]), w, P);
    for (int i = 0; i < 3; i++) a[i] = H->m->minv[i] * (F[i] + P[i]);
    return EXDEX_OK;
}

/* Guards of the stops' friction modes at (t, y) (planar, contact set not
 * empty) into g; returns their count. At rest, per frictional stop with
 * set rows: zsw - |tb| (static) or sigma tb - zsw (sliding past). Else +1
 * / -1 (a consistent mode exists or not), and per frictional stop with set
 * rows: sliding, sigma s; sticking, mu sum lam (1 + SF_BAND) - |beta|, or
 * in a lock (stop_friction.h) its margin. */
static int sf_guards(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, double *g)
{
    sf_set S;
    sf_result res;
    double a[3];
    int n = 0, ok = 0;
    int nr = sf_build(H, kin, y, &S);
    if (H->mode == MODE_STICK) {
        for (int k = 0; k < S.ng; k++) {
            if (!(S.has[k] && S.st[k].mu > 0.0)) continue;
            g[n++] = H->fm[k] == SF_STICK     ? H->zsw - fabs(S.tb[k])
                     : H->fm[k] == SF_SLIDE_P ? S.tb[k] - H->zsw
                     : H->fm[k] == SF_SLIDE_M ? -S.tb[k] - H->zsw
                                              : 1.0;
        }
        return n;
    }
    memset(&res, 0, sizeof res);
    if (nr >= 0 && sf_free_acc(H, f, kin, y, a) == EXDEX_OK) ok = sf_solve_at(H, kin, y, a, &res);
    g[n++] = ok ? 1.0 : -1.0;
    for (int k = 0; k < S.ng; k++) {
        if (!(S.has[k] && S.st[k].mu > 0.0)) continue;
        if (H->fm[k] == SF_SLIDE_P)
            g[n++] = S.s[k];
        else if (H->fm[k] == SF_SLIDE_M)
            g[n++] = -S.s[k];
        else if (H->fm[k] == SF_STICK && ok && res.lock)
            g[n++] = res.margin;
        else if (H->fm[k] == SF_STICK && ok)
            g[n++] = S.st[k].mu * res.lsum[k] * (1.0 + SF_BAND) - fabs(res.beta[k]);
        else
            g[n++] = 1.0;
    }
    return n;
}

/* The stops' friction modes after decide_modes at (t, y) (every H->fm was
 * SF_ROLL during it): at rest from each stop's tb (above); else the mode
 * that the acceleration-level problem finds, the stops sliding where |s| >
 * zsw, and a sticking stop's slip projected to 0. In a small slip the
 * plate friction depends on the stops' modes (below): a mode is kept only
 * if the problem decides it again on its own plate friction. No
 * consistent mode (Painleve, or a small slip whose coupled problem has
 * none, or more than 3 rolling stops in a small slip): the stops
 * frictionless, a warning. */
static void sf_decide(hyb *H, double t, double *y)
{
    frame f;
    exdex_kinematics kin;
    sf_set S;
    sf_result res;
    double a[3];
    int nr, ok = 0, fs;
    if (!H->ncs) return;
    fs = frame_seg(H, t, &f, &kin);
    if (fs) {
        H->err = H->err ? H->err : fs;
        return;
    }
    nr = sf_build(H, &kin, y, &S);
    if (H->mode == MODE_STICK) {
        for (int k = 0; k < S.ng; k++)
            if (S.has[k] && S.st[k].mu > 0.0)
                H->fm[k] = fabs(S.tb[k]) <= H->zsw ? SF_STICK : S.tb[k] > 0.0 ? SF_SLIDE_P : SF_SLIDE_M;
        return;
    }
    if (H->mode == MODE_SLIP && H->small && nr >= 0) {
        /* a small slip's plate friction is found together with the stop
         * forces (planar_friction's fixed point), so it depends on the
         * stops' modes: each mode of the rolling stops (|s| <= zsw) is
         * tried with its own plate friction, and the first that the
         * problem decides again from that friction is kept (the guards
         * then start from a consistent mode) */
        int roll[SF_MAX_STOPS], pick[SF_MAX_STOPS] = {0}, nroll = 0, found = 0;
        static const int cand[3] = {SF_STICK, SF_SLIDE_P, SF_SLIDE_M};
        for (int k = 0; k < S.ng; k++)
            if (S.has[k] && S.st[k].mu > 0.0 && S.st[k].fm == SF_ROLL) roll[nroll++] = k;
        for (int combo = 0; nroll <= 3 && !found; combo++) {
            int c = combo, same = 1;
            if (combo >= (nroll == 0 ? 1 : nroll == 1 ? 3 : nroll == 2 ? 9 : 27)) break;
            for (int i = 0; i < nroll; i++) {
                pick[i] = cand[c % 3];
                c /= 3;
            }
            for (int k = 0; k < S.ng; k++) H->fm[k] = SF_ROLL;
            for (int i = 0; i < nroll; i++) H->fm[roll[i]] = pick[i];
            fs = sf_free_acc(H, &f, &kin, y, a);
            if (fs) {
                H->err = H->err ? H->err : fs;
                return;
            }
            for (int k = 0; k < S.ng; k++) H->fm[k] = SF_ROLL;
            if (!sf_solve_at(H, &kin, y, a, &res)) continue;
            for (int i = 0; i < nroll; i++) same &= res.fm[roll[i]] == pick[i];
            found = ok = same;
        }
        if (!found && nroll) {
            /* no combination is decided again on its own plate friction
             * (a lock's plate friction, with its stops given, against the
             * roll decision that tries locks last, stop_friction.h): the modes
             * the problem finds with every rolling stop left to it, on the
             * plate friction of that same problem (the fixed point of
             * planar_friction with the stops rolling) */
            for (int k = 0; k < S.ng; k++) H->fm[k] = SF_ROLL;
            fs = sf_free_acc(H, &f, &kin, y, a);
            if (fs) {
                H->err = H->err ? H->err : fs;
                return;
            }
            ok = sf_solve_at(H, &kin, y, a, &res);
        }
    } else if (nr >= 0) {
        fs = sf_free_acc(H, &f, &kin, y, a);
        if (fs) {
            H->err = H->err ? H->err : fs;
            return;
        }
        ok = sf_solve_at(H, &kin, y, a, &res);
    }
    for (int k = 0; k < S.ng; k++) {
        if (!(S.has[k] && S.st[k].mu > 0.0)) continue;
        H->fm[k] = ok ? res.fm[k] : SF_NONE;
    }
    if (!ok) {
        H->st->warnings++;
        return;
    }
    sf_project_stick(H, &f, &kin, y);
}

/* ------------------------------------------------------- right-hand side */

static int rhs(double t, const double y[], double dy[], void *params)
{
    hyb *H = params;
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    int st = frame_seg(H, t, &f, &kin);
    if (st) {
        if (!H->err) H->err = st;
        return GSL_EBADFUNC;
    }
    for (int i = 0; i < H->ny; i++) dy[i] = 0.0;
    if (H->ndof == 1) {
        double q = y[0], v = y[1];
        if (H->mode == MODE_STICK) {
            dy[2] = -model_force_1dof(m, &f, q, 0.0);
        } else if (H->mode == MODE_CONTACT) {
            crow c;
            double qdd, R, fr, lam;
            double T = 0.0;
            hrow_1dof(H, &kin, H->ck, H->cj, q, &c);
            if (H->ss != 0.0) contact_slip_1dof(H, &kin, q, v, &T);
            qdd = contact_qdd(&c, v);
            R = H->M * qdd - model_force_1dof(m, &f, q, v);
            contact_forces(H, &c, T, R, v, &fr, &lam);
            dy[0] = v;
            dy[1] = qdd;
            dy[2] = fr;
            dy[3 + H->ck] = lam;
        } else {
            double Q = model_force_1dof(m, &f, q, v), fr;
            if (H->law == LAW_SMOOTH)
                fr = H->caps == H->cap ? -H->cap * v / sqrt(v * v + H->eps * H->eps) : -smooth_gain(H, fabs(v)) * v;
            else
                fr = -H->s * H->cap;
            dy[0] = v;
            dy[1] = (Q + fr) / H->M;
            dy[2] = fr;
        }
    } else {
        double F[3], w[3], P[3], th = y[2];
        const double *v = y + 3;
        st = planar_friction(H, &f, &kin, y, F, w);
        if (st) {
            if (!H->err) H->err = st;
            return GSL_EBADFUNC;
        }
        if (H->mode == MODE_STICK && H->ncs) {
            double lam[MAX_ROWS];
            planar_rest(H, &kin, y, F, w, lam);
            for (int i = 0; i < H->ncs; i++) dy[9 + hrow_src(H, H->cs[i])] += lam[i];
        }
        if (H->mode != MODE_STICK) {
            double a[3];
            model_gen_of_patch(m, MODEL_CS(th), w, P);
            for (int i = 0; i < 3; i++) {
                dy[i] = v[i];
                a[i] = m->minv[i] * (F[i] + P[i]);
                dy[3 + i] = a[i];
            }
            if (H->ncs) {
                double lam[MAX_ROWS];
                contact_acc_planar(H, &kin, y, a, dy + 3, lam, NULL, NULL);
                for (int i = 0; i < H->ncs; i++) dy[9 + hrow_src(H, H->cs[i])] += lam[i];
            }
        }
        {
            double c = cos(th), s = sin(th);
            dy[6] = c * w[0] - s * w[1];
            dy[7] = s * w[0] + c * w[1];
            dy[8] = w[2];
        }
    }
    for (int i = 0; i < H->ny; i++)
        if (!isfinite(dy[i])) {
            if (!H->err) H->err = EXDEX_ENONFINITE;
            return GSL_EBADFUNC;
        }
    return GSL_SUCCESS;
}

/* ---------------------------------------------------------------- guards */

/* Planar guards of the obstacles' free rows at (kin, y), as the stops':
 * per polytope the gap of each outline vertex's row not in the contact set
 * and the smallest gap of its section rows not in the set (a length of the
 * scene when there are none: the count stays fixed between events), per
 * rod its row's gap unless in the set. Returns how many. */
static int obst_guards(const hyb *H, const exdex_kinematics *kin, const double *y, double *g)
{
    const exdex_model *m = H->m;
    int code[MAX_ROWS], n = 0, base = H->ns * H->nv, no = 0;
    double gap[MAX_ROWS];
    no = orow_all(m, kin, y, NULL, 1, code, gap);
    if (m->disc_r > 0.0) {
        /* a disc: one row per obstacle, whose kind changes with its
         * feature: its gap while out of the contact set */
        for (int o = 0; o < no; o++) {
            int in = 0;
            for (int c = 0; c < H->ncs && !in; c++) in = H->cs[c] >= base && orow_obst(H->cs[c] - base) == o;
            g[n++] = in ? m->scale.L : gap[o];
        }
        return n;
    }
    for (int o = 0, i = 0; o < H->no; o++) {
        int poly = m->def.obstacles[o].kind == EXDEX_OBSTACLE_POLYTOPE;
        double smin = m->scale.L;
        for (; i < no && orow_obst(code[i]) == o; i++) {
            int in = 0;
            for (int c = 0; c < H->ncs && !in; c++)
                in = H->cs[c] >= base && orow_pair(H->cs[c] - base) == orow_pair(code[i]);
            if (orow_kind(code[i]) == OROW_SECTION) {
                if (!in) smin = fmin(smin, gap[i]);
            } else if (!in) {
                g[n++] = gap[i];
            }
        }
        if (poly) g[n++] = smin;
    }
    return n;
}

/* 1-DoF guards of the obstacles at (kin, q): per obstacle the smallest gap
 * of its rows (in contact with it: of its other rows, a length of the scene
 * when there are none). Returns how many. */
static int obst_guards_1dof(const hyb *H, const exdex_kinematics *kin, double q, double *g)
{
    const exdex_model *m = H->m;
    int code[MAX_ROWS], n = 0, no, contact = H->mode == MODE_CONTACT;
    double gap[MAX_ROWS];
    no = orow_all(m, kin, &q, NULL, 0, code, gap);
    for (int o = 0, i = 0; o < H->no; o++) {
        int own = contact && H->ck == H->ns + o;
        double gmin = own ? m->scale.L : INFINITY;
        for (; i < no && orow_obst(code[i]) == o; i++)
            if (!(own && (m->disc_r > 0.0 || orow_pair(code[i]) == orow_pair(H->cj))) && gap[i] < gmin) gmin = gap[i];
        g[n++] = gmin;
    }
    return n;
}

/* Guard values of the current mode at (t, y); each is >= 0 while the mode
 * holds. Returns how many (<= 2 + n_stops). */
/* The free gaps among the guards, in guards()'s order: planar, the gap of
 * every (stop, vertex) row outside the contact set; 1-DoF, each stop's
 * smallest vertex gap (the contact stop: its other vertices'). Functions of
 * (t, q) alone, so their rates along the motion are those of q' = qd. */
static int gap_guards(const hyb *H, const exdex_kinematics *kin, const double *y, double *g)
{
    const exdex_model *m = H->m;
    int n = 0;
    if (H->ndof == 3) {
        unsigned char in[MAX_ROWS];
        memset(in, 0, (size_t)(H->ns * H->nv));
        for (int i = 0; i < H->ncs; i++)
            if (H->cs[i] < H->ns * H->nv) in[H->cs[i]] = 1;
        for (int k = 0; k < H->ns; k++)
            for (int j = 0; j < H->nv; j++) {
                double G[3];
                if (!in[k * H->nv + j]) g[n++] = contact_row_planar(m, kin, k, j, y, y + 3, G, NULL, NULL);
            }
        if (H->no) n += obst_guards(H, kin, y, g + n);
        return n;
    }
    for (int k = 0; k < H->ns; k++) {
        double q = y[0];
        if (H->mode == MODE_CONTACT && k == H->ck) {
            /* the other vertices of the contact stop: the gripper's
             * rotation (or the object's) can bring one of them onto
             * the stop while the contact vertex is held at 0 */
            double gmin = INFINITY;
            for (int j = 0; j < H->nv; j++)
                if (j != H->cj) gmin = fmin(gmin, contact_vertex_gap(m, kin, k, &q, j, NULL));
            if (H->nv > 1) g[n++] = gmin;
            continue;
        }
        g[n++] = contact_stop_gap(m, kin, k, q, NULL);
    }
    if (H->no) n += obst_guards_1dof(H, kin, y[0], g + n);
    return n;
}

static int guards(hyb *H, double t, const double *y, double *g)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    int n = 0, fs = frame_seg(H, t, &f, &kin);
    H->gap0 = H->gap1 = 0;
    if (fs) {
        H->err = H->err ? H->err : fs;
        return 0;
    }
    if (H->ndof == 3) {
        if (H->law == LAW_SMOOTH) {
            /* one coefficient: no friction guard. Two: the held regime's
             * (see the top), its first guard: held, it breaks away where
             * the slip is beyond the band and the object could not rest
             * in B (the load at rest leaves the static ellipsoid, or a
             * contact-set row's stop moves into it: a forced slip); not
             * held, it is held again where the slip slows into the band */
            if (smooth_two(H)) {
                double sig = planar_slip_speed(H, y);
                if (H->held) {
                    double gh = H->caps * (1.0 + TOLF) - planar_load(H, &f, &kin, y), zero[3] = {0, 0, 0};
                    for (int i = 0; i < H->ncs; i++) {
                        double G[3], gd;
                        hrow_planar(H, &kin, H->cs[i], y, zero, G, &gd, NULL);
                        gh = fmin(gh, H->caps * (gd + m->tol.rate) / m->scale.V);
                    }
                    g[n++] = fmax(H->eps - sig, gh);
                } else {
                    g[n++] = sig - H->eps;
                }
            }
        } else if (H->mode == MODE_SLIP) {
            double u[3], eu[3], sig;
            model_patch_slip(m, MODEL_CS(y[2]), y + 3, u);
            for (int i = 0; i < 3; i++) eu[i] = m->e[i] * u[i];
            sig = sqrt(ex_dot3(eu, eu));
            if (H->small) {
                /* small slip growing from rest: it stops when the load
                 * falls back inside the ellipsoid (the stick guard with the
                 * sign reversed) and becomes a (large) slip at |E u| =
                 * SLIP_UP zsw */
                double F[3], w[3], zero[3] = {0, 0, 0}, lam[MAX_ROWS];
                model_force_planar(m, &f, y, zero, F);
                if (H->ncs) {
                    g[n++] = planar_rest(H, &kin, y, F, w, lam) - H->cap * (1.0 + TOLF);
                } else {
                    for (int i = 0; i < 3; i++) F[i] = -F[i];
                    model_patch_of_gen(m, MODEL_CS(y[2]), F, w);
                    g[n++] = model_ls_gauge(m, w) - H->cap * (1.0 + TOLF);
                }
                g[n++] = SLIP_UP * H->zsw - sig;
            } else {
                /* the slip reverses (E u turns against its direction at
                 * the start of the step: a stop, or a turn when |E u| is
                 * large there) or decays below zsw (a slip dying out,
                 * against stops too, without reversing) */
                g[n++] = ex_dot3(eu, H->uref);
                g[n++] = sig - H->zsw;
            }
        } else {
            double F[3], w[3], zero[3] = {0, 0, 0}, lam[MAX_ROWS];
            model_force_planar(m, &f, y, zero, F);
            if (H->ncs) {
                g[n++] = H->caps * (1.0 + TOLF) - planar_rest(H, &kin, y, F, w, lam);
            } else {
                for (int i = 0; i < 3; i++) F[i] = -F[i];
                model_patch_of_gen(m, MODEL_CS(y[2]), F, w);
                g[n++] = H->caps * (1.0 + TOLF) - model_ls_gauge(m, w);
            }
        }
        if (H->ns || H->no) {
            /* stops: free rows, their gap (impact when it reaches 0); rows of
             * the contact set, lam_i G_i M^-1 G_i^T - gap acceleration_i (> 0
             * while the row pushes, < 0 once it separates) */
            H->gap0 = n;
            n += gap_guards(H, &kin, y, g + n);
            H->gap1 = n;
            if (H->ncs && H->mode == MODE_STICK) {
                /* at rest against stops that move in B the contact ends
                 * once a set row's gap leaves +-tol.rest_gap */
                for (int i = 0; i < H->ncs; i++) {
                    int r = H->cs[i];
                    double G[3];
                    g[n++] = m->tol.rest_gap - fabs(hrow_planar(H, &kin, r, y, y + 3, G, NULL, NULL));
                }
            } else if (H->ncs) {
                double F[3], w[3], P[3], a[3], qdd[3], lam[MAX_ROWS], acc[MAX_ROWS];
                int st = planar_friction(H, &f, &kin, y, F, w);
                if (st) {
                    H->err = H->err ? H->err : st;
                    return 0;
                }
                model_gen_of_patch(m, MODEL_CS(y[2]), w, P);
                for (int i = 0; i < 3; i++) a[i] = m->minv[i] * (F[i] + P[i]);
                /* in a lock (stop_friction.h) the rows' forces are one split of
                 * indeterminate ones: the lock's margin (sf_guards) says
                 * when a row must separate or a stop slide */
                unsigned lk = 0u;
                contact_acc_planar(H, &kin, y, a, qdd, lam, acc, &lk);
                for (int i = 0; i < H->ncs; i++) {
                    int r = H->cs[i];
                    double G[3], d = 0.0;
                    hrow_planar(H, &kin, r, y, y + 3, G, NULL, NULL);
                    for (int c = 0; c < 3; c++) d += G[c] * G[c] * m->minv[c];
                    g[n++] = (lk >> i & 1u) ? 1.0 : lam[i] * d - acc[i];
                }
            }
            /* an obstacle row of the set: its feature stays the active one */
            for (int i = 0; i < H->ncs; i++)
                if (H->cs[i] >= H->ns * H->nv) g[n++] = orow_feature_guard(m, &kin, H->cs[i] - H->ns * H->nv, y);
            if (H->sfric && H->ncs) n += sf_guards(H, &f, &kin, y, g + n);
        }
        return n;
    }
    {
        double q = y[0], v = y[1];
        if (H->mode == MODE_SLIP) {
            g[n++] = H->s * v;
        } else if (H->mode == MODE_STICK) {
            g[n++] = H->caps * (1.0 + TOLF) - fabs(model_force_1dof(m, &f, q, 0.0));
        } else if (H->mode == MODE_CONTACT) {
            crow c;
            double R, fr, lam, T = 0.0;
            hrow_1dof(H, &kin, H->ck, H->cj, q, &c);
            if (H->ss != 0.0) contact_slip_1dof(H, &kin, q, v, &T);
            R = H->M * contact_qdd(&c, v) - model_force_1dof(m, &f, q, v);
            if (H->law == LAW_COULOMB && H->s == 0.0) {
                /* at rest against the stop (q and the stop at rest in B,
                 * |qd| <= tol.vzero): the load at rest, R = -Q(q, 0), the
                 * same number that the decision at its end tests against
                 * C_s (decide_modes), so a rest that ends there is not
                 * taken up again as a stick and left by the stick guard at
                 * once */
                R = -model_force_1dof(m, &f, q, 0.0);
                g[n++] = fmax(R / contact_dir(H, &c, T), H->caps * (1.0 + TOLF) - fabs(R));
                g[n++] = m->tol.vzero - fabs(v);
            } else {
                contact_forces(H, &c, T, R, v, &fr, &lam);
                g[n++] = lam;
                if (H->law == LAW_COULOMB) g[n++] = H->s * v;
            }
        }
        H->gap0 = n;
        n += gap_guards(H, &kin, y, g + n);
        H->gap1 = n;
        /* a frictional contact: its vertex keeps slipping the same way
         * along the stop (at a reversal the friction turns: decided again) */
        if (H->mode == MODE_CONTACT && H->ss != 0.0) {
            double T = 0.0;
            crow c;
            g[n++] = H->ss * contact_slip_1dof(H, &kin, q, v, &T);
            /* ... and its friction does not jam the contact (JAM_DIR) */
            hrow_1dof(H, &kin, H->ck, H->cj, q, &c);
            g[n++] = contact_dir(H, &c, T) / c.Fq - JAM_DIR;
        }
        if (H->mode == MODE_CONTACT && H->jam != 0.0) {
            /* taken frictionless at a jam: until the slip reverses or its
             * friction would no longer jam the contact */
            double T = 0.0;
            crow c;
            g[n++] = H->jam * contact_slip_1dof(H, &kin, q, v, &T);
            hrow_1dof(H, &kin, H->ck, H->cj, q, &c);
            g[n++] = JAM_DIR - (c.Fq - model_source_mu(m, H->ck) * H->jam * T) / c.Fq;
        }
        /* in contact with an obstacle row: its feature stays the active one */
        if (H->mode == MODE_CONTACT && H->ck >= H->ns) g[n++] = orow_feature_guard(m, &kin, H->cj, &q);
    }
    return n;
}

/* ------------------------------------------------------------- decisions */

/* Choose the mode at (t, y) (after an event, at a segment start, at t = 0).
 * vzero: qd is known to be 0 (a slip just stopped). May change y (impacts,
 * projection onto a stop). */
static void decide_modes(hyb *H, double t, double *y, int vzero)
{
    hyb_pads(H, y);
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    int fs = frame_seg(H, t, &f, &kin);
    if (fs) {
        H->err = H->err ? H->err : fs;
        return;
    }
    if (H->ndof == 3) {
        double F[3], w[3], u[3], zero[3] = {0, 0, 0};
        if (H->ns || H->no) {
            planar_unpenetrate(H, &kin, y);
            planar_impact_and_set(H, t, &kin, y);
        }
        if (H->law == LAW_SMOOTH) {
            H->mode = MODE_FREE;
            planar_prune_set(H, &f, &kin, y);
            return;
        }
        if (!vzero && (y[3] != 0.0 || y[4] != 0.0 || y[5] != 0.0)) {
            /* a slip below zsw (left by an impact or a jump of the
             * gripper): it stops where the load can be held, else it
             * slips on as a small slip (below) */
            /* a small slip stays small up to SLIP_UP zsw (its guard's
             * hysteresis): an event of another guard (a stop row) within
             * that band must not turn it into a large slip, whose decay
             * guard at zsw would fire at once and stop it again */
            double band = H->mode == MODE_SLIP && H->small ? SLIP_UP * H->zsw : H->zsw;
            model_patch_slip(m, MODEL_CS(y[2]), y + 3, u);
            for (int i = 0; i < 3; i++) u[i] *= m->e[i];
            if (!(sqrt(ex_dot3(u, u)) >= band)) {
                if (planar_load_held(H, &f, &kin, y)) {
                    vzero = 1;
                } else {
                    H->mode = MODE_SLIP;
                    H->small = 1;
                    planar_prune_set(H, &f, &kin, y);
                    return;
                }
            }
        }
        if (vzero) {
            y[3] = y[4] = y[5] = 0.0;
            if (H->ns || H->no) {
                /* a slip that stopped against stops moving in B: the stops
                 * push it on at their own speed. If that slip is below
                 * SLIP_PUSH zsw it would soon count as stopped again
                 * (Zeno-like restarts); it is a rest instead, on
                 * every touching row, which the tol.rest_gap guard ends once the
                 * stops have moved (a drift below tol.rest_gap). The same
                 * for a touching stop that recedes in B at a rate below
                 * SLIP_PUSH zsw (the slip that followed it stopped): left
                 * out of the set, the load would push the object back onto
                 * it at once, an impact at the same time, and so on. And
                 * for a slip that stopped (below zsw) while a contact-set
                 * row held it, when that row's stop recedes faster and
                 * friction alone cannot hold the load (planar_set_recedes:
                 * the object followed the stop, pushing on it): at rest the
                 * row would separate at once and the load drive the object
                 * back onto it, an impact every few hundred ns; the rest on
                 * the touching rows lags the stop by at most tol.rest_gap
                 * before its guard ends it, as for a slow recession */
                double ysv[NSRC_MAX], u[3], eu[3], Ga[MAX_ROWS][3], ga[MAX_ROWS], gda[MAX_ROWS];
                int recede = planar_set_recedes(H, &f, &kin, y), ra[MAX_ROWS], na;
                memcpy(ysv, y + 9, (size_t)(H->ns + H->no) * sizeof *ysv);
                planar_impact_and_set(H, t, &kin, y);
                model_patch_slip(m, MODEL_CS(y[2]), y + 3, u);
                for (int i = 0; i < 3; i++) eu[i] = m->e[i] * u[i];
                na = hrow_all_planar(H, &kin, y, ra, Ga, ga, gda);
                if (y[3] == 0.0 && y[4] == 0.0 && y[5] == 0.0)
                    for (int i = 0; i < na && !recede; i++)
                        if (ga[i] <= m->tol.touch && gda[i] > m->tol.rate && gda[i] < SLIP_PUSH * H->zsw) recede = 1;
                if (recede || ((y[3] != 0.0 || y[4] != 0.0 || y[5] != 0.0) && sqrt(ex_dot3(eu, eu)) < SLIP_PUSH * H->zsw)) {
                    memcpy(y + 9, ysv, (size_t)(H->ns + H->no) * sizeof *ysv);
                    y[3] = y[4] = y[5] = 0.0;
                    H->ncs = 0;
                    na = hrow_all_planar(H, &kin, y, ra, Ga, ga, NULL);
                    for (int i = 0; i < na; i++)
                        if (ga[i] <= m->tol.touch) H->cs[H->ncs++] = ra[i];
                }
            }
        }
        H->small = 0;
        if (y[3] != 0.0 || y[4] != 0.0 || y[5] != 0.0) {
            H->mode = MODE_SLIP;
            model_patch_slip(m, MODEL_CS(y[2]), y + 3, u);
            for (int i = 0; i < 3; i++) H->uref[i] = m->e[i] * u[i];
            planar_prune_set(H, &f, &kin, y);
            return;
        }
        model_force_planar(m, &f, y, zero, F);
        if (H->ncs) {
            double lam[MAX_ROWS];
            if (planar_rest(H, &kin, y, F, w, lam) <= H->caps * (1.0 + TOLF)) {
                H->mode = MODE_STICK;
                return;
            }
        } else {
            double mF[3] = {-F[0], -F[1], -F[2]};
            model_patch_of_gen(m, MODEL_CS(y[2]), mF, w);
        }
        if (!H->ncs && model_ls_gauge(m, w) <= H->caps * (1.0 + TOLF)) {
            H->mode = MODE_STICK;
        } else {
            /* starts to slip: the direction of the slip acceleration */
            double wF[3], b[3];
            exdex_friction_result res;
            int st;
            model_patch_of_gen(m, MODEL_CS(y[2]), F, wF);
            ex_mulmv3(b, m->prep.W, wF);
            st = limitsurf_step(&m->ls, &m->prep, b, H->cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &res);
            if (st) {
                H->err = H->err ? H->err : st;
                return;
            }
            H->mode = MODE_SLIP;
            H->small = 1;
            for (int i = 0; i < 3; i++) H->uref[i] = m->e[i] * res.u[i];
            if (H->ncs) {
                /* against stops: the slip starts along the constrained
                 * acceleration of the friction just found */
                double P[3], a[3], qdd[3], lam[MAX_ROWS], ua[3];
                model_gen_of_patch(m, MODEL_CS(y[2]), res.p, P);
                for (int i = 0; i < 3; i++) a[i] = m->minv[i] * (F[i] + P[i]);
                contact_acc_planar(H, &kin, y, a, qdd, lam, NULL, NULL);
                model_patch_slip(m, MODEL_CS(y[2]), qdd, ua);
                for (int i = 0; i < 3; i++) H->uref[i] = m->e[i] * ua[i];
                planar_prune_set(H, &f, &kin, y);
            }
        }
        return;
    }
    {
        double q = y[0];
        if (vzero && H->mode != MODE_CONTACT) y[1] = 0.0;
        /* impacts: a touching stop approached by the object stops it
         * (plastic, like the implicit step); the normal impulse is counted
         * in the stop's force integral */
        int rk[MAX_ROWS], rj[MAX_ROWS], nr = (H->ns || H->no) ? hrow_all_1dof(H, &kin, q, y + 1, rk, rj) : 0;
        for (int pass = 0; pass < 3 && nr; pass++) {
            int kb = -1, jb = -1;
            double worst = -m->tol.rate;
            crow cb;
            for (int r = 0; r < nr; r++) {
                double rate;
                crow c;
                hrow_1dof(H, &kin, rk[r], rj[r], q, &c);
                if (c.F > m->tol.touch || !(fabs(c.Fq) > m->tol.fq_min)) continue;
                rate = c.Fq * y[1] + c.Ft;
                if (rate < worst) {
                    worst = rate;
                    kb = rk[r];
                    jb = rj[r];
                    cb = c;
                }
            }
            if (kb < 0) break;
            {
                double vn = -cb.Ft / cb.Fq, ln = impact_impulse_1dof(H, &kin, kb, jb, q, &cb, y[1], vn);
                y[3 + kb] += ln;
                method_note_impact(H->st, t, kb, ln);
                y[1] = vn;
                vzero = 0;
                if (pass == 2) H->st->warnings++; /* stops pinch the object */
            }
        }
        /* contact with a touching stop */
        for (int r = 0; r < nr; r++) {
            int k = rk[r], j = rj[r];
            double rate, v, Q, R, fr, lam, s_old = H->s;
            crow c;
            hrow_1dof(H, &kin, k, j, q, &c);
            if (c.F > m->tol.touch || !(fabs(c.Fq) > m->tol.fq_min)) continue;
            rate = c.Fq * y[1] + c.Ft;
            if (fabs(rate) > m->tol.rate) continue;
            v = -c.Ft / c.Fq;
            if (H->law == LAW_COULOMB) {
                if (fabs(v) > m->tol.vzero && !vzero) {
                    H->s = v > 0 ? 1.0 : -1.0;
                } else {
                    /* the stop at rest in B: the object slides with it in
                     * the direction of its acceleration, or rests against
                     * it (s = 0: static friction, the stick test at C_s)
                     * where that acceleration is 0. An acceleration that
                     * gains less than tol.vzero of speed over the time
                     * scale T counts as 0: a stop fixed in B (a gripper
                     * moving along it) has Ftt of a few ulps, whose sign
                     * must not choose a sliding contact (kinetic friction
                     * of a sign set by rounding, the rest ending at C
                     * instead of C_s); a real acceleration that small
                     * reaches tol.vzero, where the rest's guard decides
                     * again, after at least T */
                    double a = contact_qdd(&c, 0.0), a0 = m->tol.vzero / m->scale.T;
                    H->s = a > a0 ? 1.0 : a < -a0 ? -1.0 : 0.0;
                    v = 0.0;
                }
            }
            Q = model_force_1dof(m, &f, q, v);
            /* a rest (s = 0): the stop's acceleration counts as 0 (above),
             * the load is the one at rest that the stick test below and the
             * rest's guard use */
            R = H->law == LAW_COULOMB && H->s == 0.0 ? -Q : H->M * contact_qdd(&c, v) - Q;
            {
                /* a frictional stop: the friction opposes the vertex's slip
                 * along it (located guards put a reversal just past its
                 * zero: the new sign). With mu ss T turning the normal
                 * force's generalized direction around (D Fq <= 0) the
                 * acceleration-level contact has no solution (Painleve):
                 * the contact is taken frictionless there, counted as a
                 * warning */
                double sl, T = 0.0;
                H->ck = k;
                H->cj = j;
                H->ss = 0.0;
                H->jam = 0.0;
                if (model_source_mu(m, k) > 0.0) {
                    sl = contact_slip_1dof(H, &kin, q, v, &T);
                    H->ss = sl > 0.0 ? 1.0 : sl < 0.0 ? -1.0 : 0.0;
                    if (H->ss != 0.0 && !(contact_dir(H, &c, T) / c.Fq > JAM_DIR)) {
                        H->jam = H->ss;
                        H->ss = 0.0;
                        H->st->warnings++;
                    }
                }
                contact_forces(H, &c, T, R, v, &fr, &lam);
            }
            /* a stop force exactly 0 keeps no contact: it is about to
             * separate (or needs none) */
            if (lam > 0.0 && (H->law == LAW_SMOOTH || H->s != 0.0 || fabs(fr) <= H->caps * (1.0 + TOLF))) {
                H->mode = MODE_CONTACT;
                H->ck = k;
                H->cj = j;
                /* onto the constraint: Newton on F(q, t) = 0 */
                for (int it = 0; it < 8 && fabs(c.F) > 0.0; it++) {
                    double dq = c.F / c.Fq;
                    q -= dq;
                    hrow_1dof(H, &kin, k, j, q, &c);
                    H->st->stop_iterations++;
                    if (fabs(dq) <= 1e-16 * (m->scale.q + fabs(q))) break;
                }
                y[0] = q;
                y[1] = (H->law == LAW_COULOMB && H->s == 0.0) ? 0.0 : -c.Ft / c.Fq;
                return;
            }
            H->s = s_old;
            H->ss = 0.0;
            H->jam = 0.0;
        }
        if (H->law == LAW_SMOOTH) {
            H->mode = MODE_FREE;
        } else if (y[1] != 0.0 && !vzero) {
            H->mode = MODE_SLIP;
            H->s = y[1] > 0 ? 1.0 : -1.0;
        } else {
            double Q0 = model_force_1dof(m, &f, q, 0.0);
            y[1] = 0.0;
            if (fabs(Q0) <= H->caps * (1.0 + TOLF)) {
                H->mode = MODE_STICK;
                H->s = 0.0;
            } else {
                H->mode = MODE_SLIP;
                H->s = Q0 > 0 ? 1.0 : -1.0;
            }
        }
    }
}

/* decide_modes, and with frictional stops in a planar scene the stops'
 * friction modes after it (decided afresh at every decision: sf_decide). */
static void decide(hyb *H, double t, double *y, int vzero)
{
    double v0[3] = {0, 0, 0};
    if (H->sfric)
        for (int k = 0; k < SF_MAX_STOPS; k++) H->fm[k] = SF_ROLL;
    H->sgn = 0;
    if (H->ndof == 3) memcpy(v0, y + 3, sizeof v0);
    decide_modes(H, t, y, vzero);
    if (smooth_two(H)) {
        /* the held regime: held in the band; a velocity changed by an
         * impact is a slip (kinetic beyond the band); else as it was */
        if (planar_slip_speed(H, y) <= H->eps)
            H->held = 1;
        else if (y[3] != v0[0] || y[4] != v0[1] || y[5] != v0[2])
            H->held = 0;
    }
    if (H->sfric && !H->err) {
        sf_fix_groups(H, t, y);
        sf_decide(H, t, y);
    }
}

/* The stops' friction groups and modes of the contact set decided again at
 * (t, y) after the set changed outside decide (set_tie_leaves), as decide
 * makes them after decide_modes: groups afresh, every mode from SF_ROLL. */
static void sf_redecide(hyb *H, double t, double *y)
{
    for (int k = 0; k < SF_MAX_STOPS; k++) H->fm[k] = SF_ROLL;
    sf_fix_groups(H, t, y);
    if (!H->err) sf_decide(H, t, y);
}

/* The rows of the planar contact set held as equalities (hold_set_rows):
 * given the n set rows G_i x >= b_i (in the set's order), appends
 * -G_i x >= -b_i for each row whose G_i is independent of the set rows
 * before it (in the M^-1 metric, a residual above 1e-6 of its norm; a row
 * within that of their span is implied by them to rounding, and its
 * mirror would make the rows inconsistent by rounding). Returns the new
 * count (n when the mirrors would exceed LDP_MAX_ROWS). */
static int set_row_equalities(const hyb *H, int n, double (*Gr)[3], double *b)
{
    double basis[3][3];
    int nb = 0, m = n;
    if (n + 3 > LDP_MAX_ROWS) return n;
    for (int i = 0; i < n && nb < 3; i++) {
        double u[3], n0, nn;
        for (int c = 0; c < 3; c++) u[c] = Gr[i][c] * sqrt(H->m->minv[c]);
        n0 = ex_dot3(u, u);
        for (int k = 0; k < nb; k++) {
            double p = ex_dot3(u, basis[k]);
            for (int c = 0; c < 3; c++) u[c] -= p * basis[k][c];
        }
        nn = ex_dot3(u, u);
        if (!(nn > 1e-12 * n0)) continue;
        for (int c = 0; c < 3; c++) basis[nb][c] = u[c] / sqrt(nn);
        nb++;
        for (int c = 0; c < 3; c++) Gr[m][c] = -Gr[i][c];
        b[m++] = -b[i];
    }
    return m;
}

/* The planar contact set at a decision (t, y) (an event, a switching time
 * of the motion or the grip before its jump, a regrip), outside a rest: a
 * set row pushes (lam > 0) until its separation, the located root of its
 * guard, so its exact gap and rate are 0 over the whole contact, up to and
 * at that root. The integrated state leaves them off by the integrator's
 * error (project_contact after each step removes only penetration and
 * approach), up to its tolerance, far above tol.touch and tol.rate, the
 * bands in which the decision takes a row as touching at rate 0
 * (planar_impact_and_set): it would find a pushing row separating and drop
 * it from the set, a free flight of that row with its friction lost until
 * an impact brings it back. Where a set row is beyond either band, q and
 * then v are projected (M metric) onto every set row at gap 0 and rate 0
 * (equalities; the rows implied by others one-sided); within both bands the
 * decision takes them so already and y is left as it is. The event method
 * in scenes with obstacles; a scene of stops alone, and the regularised
 * method, keep their state as integrated. */
static void hold_set_rows(hyb *H, double t, double *y)
{
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    double Gr[MAX_ROWS + 3][3], b[MAX_ROWS + 3], lam[MAX_ROWS + 3], zero[3] = {0, 0, 0}, dq[3], v[3];
    int off = 0, n;
    if (H->law != LAW_COULOMB || H->ndof != 3 || !H->no || !H->ncs || H->mode == MODE_STICK) return;
    if (frame_seg(H, t, &f, &kin)) return;
    for (int i = 0; i < H->ncs && !off; i++) {
        double gd, g = hrow_planar(H, &kin, H->cs[i], y, y + 3, Gr[i], &gd, NULL);
        off = g > m->tol.touch || gd > m->tol.rate;
    }
    if (!off) return;
    for (int i = 0; i < H->ncs; i++) b[i] = -hrow_planar(H, &kin, H->cs[i], y, y + 3, Gr[i], NULL, NULL);
    n = set_row_equalities(H, H->ncs, Gr, b);
    if (ldp_project(m->minv, n, (const double (*)[3])Gr, b, zero, FQ_MIN, dq, lam, &H->st->stop_iterations, &H->st->warnings))
        for (int c = 0; c < 3; c++) y[c] += dq[c];
    if (contact_min_gap(m, &kin, y) < 0.0) planar_unpenetrate(H, &kin, y);
    for (int i = 0; i < H->ncs; i++) {
        double gd;
        hrow_planar(H, &kin, H->cs[i], y, y + 3, Gr[i], &gd, NULL);
        b[i] = -(gd - ex_dot3(Gr[i], y + 3));
    }
    n = set_row_equalities(H, H->ncs, Gr, b);
    if (ldp_project(m->minv, n, (const double (*)[3])Gr, b, y + 3, FQ_MIN, v, lam, &H->st->stop_iterations, &H->st->warnings))
        memcpy(y + 3, v, sizeof v);
}

/* After an accepted step in contact: back onto the constraint (the
 * integrated q drifts off it at the tolerance level). */
static void project_contact(hyb *H, double t, double *y)
{
    frame f;
    exdex_kinematics kin;
    crow c;
    if (H->ndof == 3 && H->ncs) {
        /* planar: remove the penetration and the approach speed of the
         * contact-set rows (M-metric projections; a row drifting off its
         * stop is left to the accelerations) */
        double Gr[MAX_ROWS][3], b[MAX_ROWS], lam[MAX_ROWS], zero[3] = {0, 0, 0}, dq[3], v[3];
        if (frame_seg(H, t, &f, &kin)) return;
        for (int i = 0; i < H->ncs; i++) {
            int r = H->cs[i];
            b[i] = -hrow_planar(H, &kin, r, y, y + 3, Gr[i], NULL, NULL);
        }
        if (ldp_project(H->m->minv, H->ncs, (const double (*)[3])Gr, b, zero, FQ_MIN, dq, lam, &H->st->stop_iterations, &H->st->warnings))
            for (int c2 = 0; c2 < 3; c2++) y[c2] += dq[c2];
        /* the projection (a rotation about a set row) can push a row off
         * the set into its stop: then onto every row */
        if (contact_min_gap(H->m, &kin, y) < 0.0) planar_unpenetrate(H, &kin, y);
        for (int i = 0; i < H->ncs; i++) {
            int r = H->cs[i];
            double gd;
            hrow_planar(H, &kin, r, y, y + 3, Gr[i], &gd, NULL);
            b[i] = -(gd - ex_dot3(Gr[i], y + 3));
        }
        if (ldp_project(H->m->minv, H->ncs, (const double (*)[3])Gr, b, y + 3, FQ_MIN, v, lam, &H->st->stop_iterations, &H->st->warnings))
            memcpy(y + 3, v, sizeof v);
        if (H->sfric) sf_project_stick(H, &f, &kin, y);
        return;
    }
    if (H->ndof != 1 || H->mode != MODE_CONTACT) return;
    if (frame_seg(H, t, &f, &kin)) return;
    hrow_1dof(H, &kin, H->ck, H->cj, y[0], &c);
    for (int it = 0; it < 8 && fabs(c.F) > 0.0; it++) {
        double dq = c.F / c.Fq;
        y[0] -= dq;
        hrow_1dof(H, &kin, H->ck, H->cj, y[0], &c);
        H->st->stop_iterations++;
        if (fabs(dq) <= 1e-16 * (H->m->scale.q + fabs(y[0]))) break;
    }
    if (!(H->law == LAW_COULOMB && H->s == 0.0)) y[1] = -c.Ft / c.Fq;
}

/* A gripper velocity jump at a switching time ts (exdex_motion_jumps: a
 * trapezoid without ramps, a sampled motion starting or ending at speed):
 * the object's relative velocity jumps as model_velocity_jump derives
 * (friction cannot oppose an impulse: the grip force is finite). */
static int apply_jump(hyb *H, double ts, double *y)
{
    const exdex_model *m = H->m;
    exdex_kinematics k;
    double tj[EXDEX_MOTION_MAX_JUMPS], dv[EXDEX_MOTION_MAX_JUMPS][3], dw[EXDEX_MOTION_MAX_JUMPS][3];
    int nj = exdex_motion_jumps(m->motion, tj, dv, dw), st;
    for (int j = 0; j < nj; j++) {
        if (tj[j] != ts) continue;
        st = exdex_motion_eval(m->motion, ts, &k);
        if (st) return st;
        model_velocity_jump(m, k.R, y, dv[j], dw[j], y + (H->ndof == 1 ? 1 : 3));
        H->held = 0;  /* a slip (regularised, planar): held again by the decision if in the band */
    }
    return EXDEX_OK;
}

/* ------------------------------------------------------ the hybrid loop */

/* Stiff planar slip. The sliding law's direction E u / |E u| relaxes onto
 * the one where the friction balances the load at the rate C |K| / |E u|
 * (see the top), and rk8pd is stable only for steps below ~5 |E u| / (C
 * |K|): a slip that lingers at a small speed (a load just beyond the
 * friction limit, growing it slowly) holds the explicit stepper to steps
 * ~5 (|E u| / V) T whatever the tolerance. Such a slip, below SLIP_STIFF
 * zsw for STIFF_AFTER consecutive accepted steps (a slip passing through
 * that band on its way up or down at an acceleration of the scene's scale
 * A takes a few steps; a brief lingering costs at most STIFF_AFTER explicit
 * steps and keeps rk8pd's answer), is integrated by GSL's bsimp (Bader-Deuflhard
 * semi-implicit extrapolation, stable on the relaxing direction), whose
 * steps are set by the same error control alone; it goes back to rk8pd
 * above 2 SLIP_STIFF zsw and at every event (the mode decided again). The
 * same ODE under the same rtol, atol: the answer differs from an rk8pd run
 * by the tolerance, not by the output grid or the step budget. */
static void stiff_track(hyb *H, const double *y, int reset)
{
    hyb_pads(H, y);
    double u[3], eu[3], s;
    if (reset || H->ndof != 3 || H->law != LAW_COULOMB || H->mode != MODE_SLIP || H->small) {
        H->stiff = 0;
        H->nlow = 0;
        return;
    }
    model_patch_slip(H->m, MODEL_CS(y[2]), y + 3, u);
    for (int c = 0; c < 3; c++) eu[c] = H->m->e[c] * u[c];
    s = sqrt(ex_dot3(eu, eu));
    if (s < SLIP_STIFF * H->zsw) {
        if (H->nlow < STIFF_AFTER) H->nlow++;
        if (H->nlow >= STIFF_AFTER) H->stiff = 1;
    } else if (!H->stiff || !(s <= 2.0 * SLIP_STIFF * H->zsw)) {
        H->stiff = 0;
        H->nlow = 0;
    }
}

/* The Jacobian of rhs for bsimp, by forward differences: the columns of
 * the configuration and velocity (planar: 6; the force integrals do not
 * enter rhs, their columns are 0), each perturbed by sqrt(DBL_EPSILON)
 * times the larger of its size and its scale (L, 1 rad, V, 1 / T), and
 * d/dt likewise over sqrt(DBL_EPSILON) max(|t|, T), backwards at the end
 * of the motion segment (rhs clamps t into it). */
static int slip_jac(double t, const double y[], double *dfdy, double dfdt[], void *params)
{
    hyb *H = params;
    const model_scales *sc = &H->m->scale;
    int ny = H->ny, nq = H->ndof == 3 ? 6 : 2;
    double f0[NY_MAX], f1[NY_MAX], yp[NY_MAX], dt;
    double scale[6] = {sc->L, sc->L, 1.0, sc->V, sc->V, 1.0 / sc->T};
    if (H->ndof == 1) {
        scale[0] = sc->q;
        scale[1] = sc->q / sc->T;
    }
    if (rhs(t, y, f0, H) != GSL_SUCCESS) return GSL_EBADFUNC;
    memset(dfdy, 0, (size_t)(ny * ny) * sizeof *dfdy);
    memcpy(yp, y, (size_t)ny * sizeof *yp);
    for (int j = 0; j < nq; j++) {
        double d = sqrt(DBL_EPSILON) * fmax(fabs(y[j]), scale[j]);
        yp[j] = y[j] + d;
        d = yp[j] - y[j];
        if (rhs(t, yp, f1, H) != GSL_SUCCESS) return GSL_EBADFUNC;
        for (int i = 0; i < ny; i++) dfdy[i * ny + j] = (f1[i] - f0[i]) / d;
        yp[j] = y[j];
    }
    dt = sqrt(DBL_EPSILON) * fmax(fabs(t), sc->T);
    if (seg_time(H, t + dt) < t + dt) dt = -dt;
    dt = (t + dt) - t;
    if (rhs(t + dt, y, f1, H) != GSL_SUCCESS) return GSL_EBADFUNC;
    for (int i = 0; i < ny; i++) dfdt[i] = (f1[i] - f0[i]) / dt;
    return GSL_SUCCESS;
}


typedef struct ode {
    gsl_odeiv2_step *step;         /* the stepper in use: rk, or bs while H.stiff */
    gsl_odeiv2_step *rk, *bs;      /* rk8pd (explicit), bsimp (linearly implicit, stiff_track) */
    gsl_odeiv2_control *con;
    gsl_odeiv2_evolve *evo;
    gsl_root_fsolver *root;
    gsl_odeiv2_system sys;
    double yerr[NY_MAX], ytmp[NY_MAX];
    double *ts, *gb;   /* switching times, grip breakpoints (EXDEX_MOTION_MAX_SWITCHES + grip_n each) */
    exdex_model *mc;   /* pads on the fingers: the run's own copy of the model (hyb.mc) */
    /* the run's state between output intervals (hybrid_begin, _advance) */
    struct hyb_state {
        hyb H;
        double y[NY_MAX];
        double t, h, t_rec;   /* time reached, the stepper's next step, last recorded time */
        size_t nsw;           /* number of switching times in ts */
        /* GSL's evolve object (its public fields): it keeps state between
         * two applications (GSL 2.7 starts a step from the last step's
         * dydt_out while count > 0), so its counts, last step and work
         * vectors are saved with the state (hybrid_save) and a restored run
         * repeats the saved one bit for bit */
        unsigned long count, failed_steps;
        double last_step;
        double e_y0[NY_MAX], e_yerr[NY_MAX], e_dydt_in[NY_MAX], e_dydt_out[NY_MAX];
    } S;
} ode;

static void ode_free(ode *O)
{
    if (!O) return;
    free(O->mc);
    if (O->root) gsl_root_fsolver_free(O->root);
    if (O->evo) gsl_odeiv2_evolve_free(O->evo);
    if (O->con) gsl_odeiv2_control_free(O->con);
    if (O->rk) gsl_odeiv2_step_free(O->rk);
    if (O->bs) gsl_odeiv2_step_free(O->bs);
    free(O->ts);
    free(O->gb);
    free(O);
}

/* The GSL workspaces of one run (the method table's alloc); the system's
 * parameters are set by the run. */
static void *hybrid_alloc(const exdex_model *m, int *status)
{
    size_t ny = (size_t)(m->ndof == 3 ? 9 + m->n_src : 3 + m->n_src);
    ode *O = calloc(1, sizeof *O);
    if (!O) {
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    O->rk = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk8pd, ny);
    O->bs = gsl_odeiv2_step_alloc(gsl_odeiv2_step_bsimp, ny);
    O->step = O->rk;
    {
        /* atol is relative to the scene's scales: each state component's
         * absolute tolerance is atol times its own scale (positions L,
         * angles 1 rad, velocities L / T and 1 / T, force integrals F T,
         * torque integrals F L T), so the error control (and with it every
         * step) is the same in any units */
        const model_scales *s = &m->scale;
        double sc[NY_MAX];
        size_t k = 0;
        if (m->ndof == 3) {
            double row[9] = {s->L, s->L, 1.0, s->V, s->V, 1.0 / s->T, s->F * s->T, s->F * s->T, s->F * s->L * s->T};
            for (; k < 9; k++) sc[k] = row[k];
        } else {
            sc[k++] = s->q;
            sc[k++] = s->q / s->T;
            sc[k++] = s->F * s->T * s->L / s->q;
        }
        for (; k < ny; k++) sc[k] = s->F * s->T;
        O->con = gsl_odeiv2_control_scaled_new(m->def.atol, m->def.rtol, 1.0, 0.0, sc, ny);
    }
    O->evo = gsl_odeiv2_evolve_alloc(ny);
    O->root = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
    O->ts = malloc((EXDEX_MOTION_MAX_SWITCHES + m->grip_n) * sizeof *O->ts);
    O->gb = malloc((EXDEX_MOTION_MAX_SWITCHES + m->grip_n) * sizeof *O->gb);
    if (m->pads) O->mc = calloc(1, sizeof *O->mc);
    if (!O->rk || !O->bs || !O->con || !O->evo || !O->root || !O->ts || !O->gb || (m->pads && !O->mc)) {
        ode_free(O);
        *status = EXDEX_ENOMEM;
        return NULL;
    }
    /* the evolve object's vectors go into a saved state (hybrid_save) also
     * before its first step writes them (a run stuck from the start): they
     * start at 0, not as malloc left them */
    memset(O->evo->y0, 0, ny * sizeof(double));
    memset(O->evo->yerr, 0, ny * sizeof(double));
    memset(O->evo->dydt_in, 0, ny * sizeof(double));
    memset(O->evo->dydt_out, 0, ny * sizeof(double));
    O->sys.function = rhs;
    O->sys.jacobian = slip_jac;
    O->sys.dimension = ny;
    O->sys.params = NULL;
    return O;
}

static void hybrid_free(void *ws) { ode_free(ws); }

/* Forget the last accepted step. GSL's evolve object starts a step from
 * the previous step's end derivative (dydt_out, at the state it returned)
 * while its step count is > 0, for steppers that take an input derivative
 * (rk8pd does): after any change of y or of the right-hand side between two
 * gsl_odeiv2_evolve_apply calls (an event, a projection, a velocity jump, a
 * new motion or grip segment, a new mode) the next step must evaluate it
 * afresh. */
static void ode_restart(ode *O)
{
    gsl_odeiv2_evolve_reset(O->evo);
    gsl_odeiv2_step_reset(O->step);
}

/* The stepper's one-step map from (t0, y0) over tau, into out. */
static int one_step(ode *O, double t0, const double *y0, double tau, double *out)
{
    size_t ny = O->sys.dimension;
    memcpy(out, y0, ny * sizeof *out);
    if (tau <= 0.0) return GSL_SUCCESS;
    return gsl_odeiv2_step_apply(O->step, t0, tau, out, O->yerr, NULL, NULL, &O->sys);
}

typedef struct rootctx {
    hyb *H;
    ode *O;
    double t0;
    const double *y0;
    int e;
    int fail;
    double off;   /* added to the function's value (a row's gap or guard e) */
} rootctx;

/* Gap of the (stop, vertex) row r = k nv + j at (t, y) (the value its stop
 * guard takes for that vertex); rate (may be NULL) gets d gap / dt. */
static double row_gap(hyb *H, double t, const double *y, int r, double *rate)
{
    const exdex_model *m = H->m;
    frame f;
    exdex_kinematics kin;
    int k = r / H->nv, j = r % H->nv, fs = frame_seg(H, t, &f, &kin);
    if (fs) {
        H->err = H->err ? H->err : fs;
        return 0.0;
    }
    if (H->ndof == 3) {
        double G[3], gd;
        double g = contact_row_planar(m, &kin, k, j, y, y + 3, G, &gd, NULL);
        if (rate) *rate = gd;
        return g;
    }
    if (rate) {
        crow c;
        contact_row_1dof(m, &kin, k, j, y[0], &c);
        *rate = c.Fq * y[1] + c.Ft;
    }
    return contact_vertex_gap(m, &kin, k, y, j, NULL);
}

/* e >= 0: guard e; e < 0: the gap of row -1 - e (row_gap). */
static double root_fn(double tau, void *p)
{
    rootctx *c = p;
    double g[NG_MAX];
    if (one_step(c->O, c->t0, c->y0, tau, c->O->ytmp) != GSL_SUCCESS) {
        c->fail = 1;
        return 0.0;
    }
    if (c->e < 0) return row_gap(c->H, c->t0 + tau, c->O->ytmp, -1 - c->e, NULL) + c->off;
    guards(c->H, c->t0 + tau, c->O->ytmp, g);
    return g[c->e] + c->off;
}

/* Golden-section search for the extremum of guard e over [0, tau1] on the
 * stepper's map (dir +1: the minimum, -1: the maximum), at most 60
 * iterations, stopping early once the guard has the sign sought (dir +1:
 * g < 0, -1: g > 0). *tau, *g: the best point found. EXDEX_ENOCONV if the
 * stepper fails. */
static int extremum(rootctx *cp, double tau1, double dir, double *tau, double *g);

static int guard_extremum(hyb *H, ode *O, double t0, const double *y0, double tau1, int e, double dir,
                          double *tau, double *g)
{
    rootctx c = {H, O, t0, y0, e, 0, 0.0};
    return extremum(&c, tau1, dir, tau, g);
}

/* guard_extremum on the function of c (a guard, or a row's gap plus c.off) */
static int extremum(rootctx *cp, double tau1, double dir, double *tau, double *g)
{
    rootctx c = *cp;
    hyb *H = c.H;
    double a = 0.0, b = tau1, r = 0.5 * (3.0 - sqrt(5.0));
    double x1 = a + r * (b - a), x2 = b - r * (b - a), f1 = dir * root_fn(x1, &c), f2 = dir * root_fn(x2, &c);
    for (int it = 0; it < 60 && f1 >= 0.0 && f2 >= 0.0 && !c.fail && b - a > H->m->tol.root; it++) {
        if (f1 < f2) {
            b = x2;
            x2 = x1;
            f2 = f1;
            x1 = a + r * (b - a);
            f1 = dir * root_fn(x1, &c);
        } else {
            a = x1;
            x1 = x2;
            f1 = f2;
            x2 = b - r * (b - a);
            f2 = dir * root_fn(x2, &c);
        }
        H->st->solver_iterations++;
    }
    if (c.fail || H->err) return H->err ? H->err : EXDEX_ENOCONV;
    *tau = f1 < f2 ? x1 : x2;
    *g = dir * (f1 < f2 ? f1 : f2);
    return EXDEX_OK;
}

/* A free gap can dip below 0 and recover within one accepted step (a corner
 * of a turning outline grazing a stop): both end values are positive and
 * the impact would be missed. The gaps are functions of (t, q), so their
 * rates at the step's ends follow from q' = qd (one-sided differences over
 * DIP_DELTA of the step). A gap falling at the start and rising at the end
 * has an interior minimum; the cubic Hermite interpolant of the end values
 * and rates estimates it with an error O(h^4 max |g^(4)|), far below its end
 * values for a step the error control accepted, so a minimum estimated
 * below DIP_MARGIN of the smaller end value is searched for on the
 * stepper's map (guard_extremum) and, if negative, its crossing located
 * (the event is the first crossing, in [0, the minimum]). Candidates
 * improve *tau_best, *e_best. */
#define DIP_DELTA 1e-3
#define DIP_MARGIN 0.5

static int locate(hyb *H, ode *O, double t0, const double *y0, double tau0, double tau1, int e, double *tau);

/* Smallest value on [0, h] of the cubic with values g0, g1 and slopes r0, r1
 * at the ends. */
static double hermite_min(double g0, double g1, double r0, double r1, double h)
{
    /* p(s) = g0 + r0 s + c2 s^2 + c3 s^3; p'(s) = r0 + 2 c2 s + 3 c3 s^2 */
    double c2 = (3.0 * (g1 - g0) / h - 2.0 * r0 - r1) / h, c3 = (r0 + r1 - 2.0 * (g1 - g0) / h) / (h * h);
    double a = 3.0 * c3, b = 2.0 * c2, c = r0, pmin = fmin(g0, g1), roots[2];
    int nr = 0;
    if (fabs(a) * h <= 1e-14 * fabs(b)) {
        if (b != 0.0) roots[nr++] = -c / b;
    } else {
        double disc = b * b - 4.0 * a * c;
        if (disc >= 0.0) {
            double sq = sqrt(disc), qq = -0.5 * (b + (b >= 0.0 ? sq : -sq));
            if (qq != 0.0) {
                roots[nr++] = qq / a;
                roots[nr++] = c / qq;
            }
        }
    }
    for (int i = 0; i < nr; i++)
        if (roots[i] > 0.0 && roots[i] < h) {
            double x = roots[i];
            pmin = fmin(pmin, g0 + x * (r0 + x * (c2 + x * c3)));
        }
    return pmin;
}

static int gap_dips(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, int ng,
                    const double *g0, const double *g1, double *tau_best, int *e_best)
{
    /* at rest (Coulomb stick) q and qd are held, so every guard is a
     * function of t alone (the load, the stops' motion in B): all of them */
    int stick = H->law == LAW_COULOMB && H->mode == MODE_STICK;
    int a = stick ? 0 : H->gap0, b = stick ? ng : H->gap1, nd = H->ndof, want = 0, fs = 0;
    double h = t1 - t0, d = DIP_DELTA * h, ya[NY_MAX], yb[NY_MAX], ga[NG_MAX], gb[2 * NG_MAX];
    double cap = H->cap, caps = H->caps;
    exdex_kinematics ka, kb;
    frame fa, fb;
    if (b <= a || !(h > 0.0)) return EXDEX_OK;
    for (int e = a; e < b; e++) want |= g0[e] > 0.0 && g1[e] >= 0.0;
    if (!want) return EXDEX_OK;
    memcpy(ya, y0, (size_t)H->ny * sizeof *ya);
    memcpy(yb, y1, (size_t)H->ny * sizeof *yb);
    for (int c = 0; c < nd; c++) {
        ya[c] += d * y0[nd + c];
        yb[c] -= d * y1[nd + c];
    }
    if (stick) {
        int na = guards(H, t0 + d, ya, ga), nb = guards(H, t1 - d, yb, gb);
        guards(H, t1, y1, gb + ng); /* H as after the step's own evaluation */
        if (H->err) return H->err;
        if (na != ng || nb != ng) return EXDEX_OK;
    } else {
        fs = frame_seg(H, t0 + d, &fa, &ka);
        if (!fs) fs = frame_seg(H, t1 - d, &fb, &kb);
        H->cap = cap; /* frame_seg reads the capacities at its time: keep t1's */
        H->caps = caps;
        if (fs) return fs;
        if (gap_guards(H, &ka, ya, ga + a) != b - a || gap_guards(H, &kb, yb, gb + a) != b - a) return EXDEX_OK;
    }
    for (int e = a; e < b; e++) {
        double r0 = (ga[e] - g0[e]) / d, r1 = (g1[e] - gb[e]) / d, tm, gm, tau;
        int st;
        if (!(g0[e] > 0.0 && g1[e] >= 0.0 && r0 < 0.0 && r1 > 0.0)) continue;
        if (!(hermite_min(g0[e], g1[e], r0, r1, h) < DIP_MARGIN * fmin(g0[e], g1[e]))) continue;
        st = guard_extremum(H, O, t0, y0, h, e, 1.0, &tm, &gm);
        if (st) return st;
        if (!(gm < 0.0)) continue;
        st = locate(H, O, t0, y0, 0.0, tm, e, &tau);
        if (st) return st;
        if (tau < *tau_best) {
            *tau_best = tau;
            *e_best = e;
        }
    }
    return EXDEX_OK;
}

/* A free obstacle row's gap is a largest distance over features (obstacle_rows.h):
 * continuous, but its rate jumps where the active feature changes. Within
 * one step an outline vertex can cross a face close to the section's corner
 * and leave the polytope again past the next face (it cuts through the
 * corner), or a section vertex an outline edge near its end: the gap falls
 * below 0 and is back above it at a feature switch, with no turn of a smooth
 * rate for gap_dips to see; from a touching start (a row the decision left
 * free at gap 0 with a small rate, which the load turns back) the end
 * values even look like a recovery. So where an obstacle row's active
 * feature differs at the step's ends, each obstacle guard that is not
 * violated at the end is searched for a value below -tol.touch (beyond the
 * touching band) on the stepper's map (golden section towards its minimum,
 * extremum); found, the first crossing of 0 before it is located, from the
 * step start if the guard is positive there, else from a point after it
 * where the guard is positive (searched towards its largest value); a guard
 * that stays <= 0 from the start up to that point is the decision's at t0,
 * not an event. Candidates improve *tau_best, *e_best. */
static int obst_dips(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, const double *g0,
                     const double *g1, double *tau_best, int *e_best)
{
    const exdex_model *m = H->m;
    int c0[MAX_ROWS], c1[MAX_ROWS], n0, n1, changed, fs, a, b = H->gap1, nin = 0;
    double h = t1 - t0, cap = H->cap, caps = H->caps;
    exdex_kinematics k0, k1;
    frame f0, f1;
    if (!H->no || H->ndof != 3 || !(h > 0.0)) return EXDEX_OK;
    fs = frame_seg(H, t0, &f0, &k0);
    if (!fs) fs = frame_seg(H, t1, &f1, &k1);
    H->cap = cap; /* frame_seg reads the capacities at its time: keep t1's */
    H->caps = caps;
    if (fs) return fs;
    n0 = orow_all(m, &k0, y0, NULL, 1, c0, NULL);
    n1 = orow_all(m, &k1, y1, NULL, 1, c1, NULL);
    changed = n0 != n1;
    for (int i = 0; i < n0 && !changed; i++) changed = c0[i] != c1[i];
    if (!changed) return EXDEX_OK;
    /* the obstacles' guards follow the free (stop, vertex) rows' (gap_guards) */
    for (int i = 0; i < H->ncs; i++) nin += H->cs[i] < H->ns * H->nv;
    a = H->gap0 + H->ns * H->nv - nin;
    for (int e = a; e < b; e++) {
        rootctx c = {H, O, t0, y0, e, 0, m->tol.touch};
        double tm, gm, lo = 0.0, tau;
        int st;
        if (!(g1[e] >= 0.0)) continue; /* violated at the end: the main loop's */
        st = extremum(&c, h, 1.0, &tm, &gm);
        if (st) return st;
        if (!(gm < 0.0)) continue;
        if (!(g0[e] > 0.0)) {
            double tx, gx;
            st = guard_extremum(H, O, t0, y0, tm, e, -1.0, &tx, &gx);
            if (st) return st;
            if (!(gx > 0.0)) continue;
            lo = tx;
        }
        st = locate(H, O, t0, y0, lo, tm, e, &tau);
        if (st) return st;
        if (tau < *tau_best) {
            *tau_best = tau;
            *e_best = e;
        }
    }
    return EXDEX_OK;
}

/* Locate the root of guard e in [tau0, tau1] (g(tau0) > 0 > g(tau1)) with Brent;
 * returns the upper end of the final bracket (the guard is just violated). */
static int locate(hyb *H, ode *O, double t0, const double *y0, double tau0, double tau1, int e, double *tau)
{
    rootctx c = {H, O, t0, y0, e, 0, 0.0};
    gsl_function F = {root_fn, &c};
    double lo = tau0, hi = tau1;
    int st = gsl_root_fsolver_set(O->root, &F, lo, hi);
    if (st) {
        /* no bracket: the one-step map does not reproduce at tau1 the
         * violated sign that the accepted step found there (the guard
         * within rounding of 0, the step's map and the evolved state
         * differing in the last bits): the event is at the step's end */
        if (c.fail) return EXDEX_ENOCONV;
        *tau = tau1;
        return EXDEX_OK;
    }
    for (int it = 0; it < BRENT_MAX; it++) {
        st = gsl_root_fsolver_iterate(O->root);
        if (st || c.fail) return EXDEX_ENOCONV;
        H->st->solver_iterations++;
        lo = gsl_root_fsolver_x_lower(O->root);
        hi = gsl_root_fsolver_x_upper(O->root);
        if (hi - lo <= H->m->tol.root) break;
    }
    /* The event is the first point where the guard is violated (g < 0):
     * Brent may stop on a point with g >= 0 (an exact zero included, where
     * the mode would be decided again unchanged and the switch be missed
     * until the next step). Step forward from it, doubling, to a point with
     * g < 0 (g(tau1) < 0 bounds the search). */
    {
        double d = fmax(H->m->tol.root, 4.0 * DBL_EPSILON * fabs(t0 + hi)), d0 = d, lo2 = hi;
        for (int k = 0; k < 64 && hi < tau1 && !(root_fn(hi, &c) < 0.0) && !c.fail; k++) {
            lo2 = hi;
            hi = fmin(tau1, hi + d);
            d *= 2.0;
        }
        /* Brent can stop on a zero that is no crossing: a gap lifted off
         * by an impact at the step start is 0 to rounding just after it
         * (g >= 0 there, and the crossing sought where it comes back down
         * later in the step). The doubling then passes over the crossing
         * by up to its last increment, a good part of the step: an
         * increment beyond 2^DOUBLING_EXACT d0 is bisected (g >= 0 at lo2,
         * < 0 at hi) to tol.root (a search that ends sooner leaves the
         * event at most 2^(DOUBLING_EXACT + 1) tol.root, ~6e-9 T, late). */
        if (hi - lo2 > ldexp(d0, DOUBLING_EXACT) && !c.fail && root_fn(hi, &c) < 0.0) {
            for (int it = 0; it < 2 * BRENT_MAX && hi - lo2 > H->m->tol.root && !c.fail; it++) {
                double mid = lo2 + 0.5 * (hi - lo2);
                if (!(mid > lo2 && mid < hi)) break;
                H->st->solver_iterations++;
                if (root_fn(mid, &c) < 0.0)
                    hi = mid;
                else
                    lo2 = mid;
            }
        }
    }
    if (c.fail) return EXDEX_ENOCONV;
    *tau = hi;
    return EXDEX_OK;
}

/* A free (stop, vertex) row of a 1-DoF scene can meet its stop and leave it
 * again within one step (planar rows are guards of their own, gap_dips; a
 * 1-DoF stop's guard is its least gap over the outline, whose end rates can
 * belong to another corner): a vertex sweeping past a stop that cuts its path only a little (a
 * turning object, a corner passing a stop at a shallow angle) has a gap that
 * is positive at both ends of the step and negative in between, which the
 * guards' end values do not show; the exact motion has an impact there.
 * Where a free row's gap is positive at both ends and its rate turns from
 * approaching (< 0) at t0 to receding (> 0) at t1, the gap has an interior
 * minimum. It is searched (golden section on the stepper's one-step map,
 * extremum) unless the cubic Hermite interpolant of the end values and
 * rates keeps its minimum above the touching band by at least its own depth
 * below the ends (the interpolant's error is of fourth order in the step,
 * the depth of second: a step that resolves the motion resolves the dip
 * to well within its depth); where the minimum falls below -tol.touch (a
 * penetration beyond the touching band: rows touching at either end, gap <=
 * tol.touch, are the impact and contact-set logic's, and a rounding-level
 * dip of a row left at 0 is no impact) the first crossing of 0 is located
 * (Brent, locate). A gap without such a turn over one step (two turns
 * within one step) is beyond the stepper's resolution of the motion and
 * not searched. *tau: the earliest crossing, INFINITY if none. Rows in the
 * contact set, and the 1-DoF contact row, are not free. */
static int row_dip(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, double *tau)
{
    int nr = H->ns * H->nv;
    double touch = H->m->tol.touch;
    unsigned char in[MAX_ROWS];
    *tau = INFINITY;
    if (!H->ns || !(t1 > t0)) return EXDEX_OK;
    memset(in, 0, (size_t)nr);
    if (H->ndof == 3)
        for (int i = 0; i < H->ncs; i++) in[H->cs[i]] = 1;
    else if (H->mode == MODE_CONTACT && H->ck < H->ns)   /* an obstacle's contact row is not a stop row */
        in[H->ck * H->nv + H->cj] = 1;
    for (int r = 0; r < nr; r++) {
        double ga, gb, ra, rb, tm, gm, tr;
        int st;
        if (in[r]) continue;
        ga = row_gap(H, t0, y0, r, &ra);
        gb = row_gap(H, t1, y1, r, &rb);
        if (H->err) return H->err;
        if (!(ga > touch && gb > touch && ra < 0.0 && rb > 0.0)) continue;
        {
            /* screen: the cubic Hermite interpolant of (ga, ra, gb, rb)
             * has its minimum pm at least its own depth below the ends
             * (min(ga, gb) - pm) above the touching band: no search */
            double pm = hermite_min(ga, gb, ra, rb, t1 - t0);
            if (pm - touch >= fmin(ga, gb) - pm) continue;
        }
        {
            rootctx c = {H, O, t0, y0, -1 - r, 0, touch};
            st = extremum(&c, t1 - t0, 1.0, &tm, &gm);
        }
        if (st) return st;
        if (!(gm < 0.0)) continue;
        st = locate(H, O, t0, y0, 0.0, tm, -1 - r, &tr);
        if (st) return st;
        if (tr < *tau) *tau = tr;
    }
    return EXDEX_OK;
}

/* The switching times in (0, t_end], increasing: the motion's
 * (exdex_motion_switches: its acceleration switches and velocity jumps) and
 * the grip schedule's breakpoints (model_grip_breaks: the capacity or its
 * derivatives jump there), merged; gb is scratch for the breakpoints. A
 * jump at t_end is applied too, so the state recorded there is its right
 * limit, as at every other time. */
static size_t switch_times(const exdex_model *m, double t_end, double *ts, double *gb)
{
    double c[EXDEX_MOTION_MAX_SWITCHES];
    int n = exdex_motion_switches(m->motion, c);
    size_t k = 0, ng = model_grip_breaks(m, t_end, gb), i = 0, j = 0;
    while (i < (size_t)n || j < ng) {
        double x;
        if (j >= ng || (i < (size_t)n && c[i] <= gb[j]))
            x = c[i++];
        else
            x = gb[j++];
        if (x > 0.0 && x <= t_end && (k == 0 || x > ts[k - 1])) ts[k++] = x;
    }
    return k;
}

static int is_still(const hyb *H, const double *y)
{
    if (H->ndof == 1) return y[1] == 0.0;
    return y[3] == 0.0 && y[4] == 0.0 && y[5] == 0.0;
}

/* The failure record of a run that stopped at t with status. */
static void hybrid_failed(const hyb *H, int status, double t, exdex_stats *st)
{
    /* the stepper and event location fail with ENOCONV, the inner
     * solvers with their own status (simulate.c names those) */
    if (status == EXDEX_ENOCONV && st->fail_cause == EXDEX_FAIL_NONE && !H->err)
        st->fail_cause = EXDEX_FAIL_STEPPER;
    st->fail_time = t;
}

/* The initial state and mode; the switching times in (0, t_end]. */
static int hybrid_begin(const exdex_model *m, ode *O, int law, double t_end, double dt, exdex_stats *st)
{
    hyb H;
    double y[NY_MAX], *ts = O->ts, h;
    size_t nsw;
    int nd, ns;
    if (O->mc) m = model_pads_follow(m, O->mc);
    nd = m->ndof;
    ns = m->n_stops;
    memset(&H, 0, sizeof H);
    H.m = m;
    H.mc = O->mc;
    H.law = law;
    H.ndof = nd;
    H.ns = ns;
    H.no = m->n_obst;
    H.ny = nd == 3 ? 9 + m->n_src : 3 + m->n_src;
    H.nv = m->n_vert ? m->n_vert : 1;
    H.st = st;
    for (int k = 0; nd == 3 && k < ns + m->n_obst; k++) H.sfric |= model_source_mu(m, k) > 0.0;
    /* eps is a slip speed |E u| [m/s]; a 1-DoF rotation slips at
     * |E u| = e_r |thd|, so its smoothing rate is eps / e_r [rad/s] */
    H.eps = m->ndof == 1 && m->def.dof == EXDEX_DOF_ROTATION ? m->def.eps / m->e[2] : m->def.eps;
    if (nd == 3) {
        H.M = 1.0;
        H.capk = 1.0;
        H.cap = m->capF;
        H.caps = m->capS;
        H.zsw = SLIP_FLOOR * m->scale.V;  /* a slip speed |E u| */
    } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
        H.M = m->m;
        H.capk = 1.0;
        H.cap = m->capF;
        H.caps = m->capS;
    } else {
        H.M = m->mrot;
        H.capk = m->e[2];
        H.cap = m->capF * m->e[2];
        H.caps = m->capS * m->e[2];
    }
    O->sys.params = &H;
    nsw = switch_times(m, t_end, ts, O->gb);
    memset(y, 0, sizeof y);
    if (nd == 3) {
        model_initial_state(m, y, y + 3);
    } else {
        model_initial_state(m, y, y + 1);
    }
    H.lo = 0.0;
    H.hi = nsw ? ts[0] : INFINITY;
    decide(&H, 0.0, y, 0);
    h = fmin(dt, m->tol.h0);
    O->S.H = H;
    memcpy(O->S.y, y, sizeof y);
    O->S.t = O->S.t_rec = 0.0;
    O->S.h = h;
    O->S.nsw = nsw;
    O->sys.params = &O->S.H;
    O->step = O->rk;
    /* GSL's objects as allocated: a begin after a run starts afresh */
    gsl_odeiv2_evolve_reset(O->evo);
    gsl_odeiv2_step_reset(O->step);
    /* a failure in the decision at t = 0 stops the run before it starts */
    if (H.err) hybrid_failed(&H, H.err, 0.0, st);
    return H.err;
}

/* One output interval, from the last recorded time to ti, recorded as
 * sample i. regrip: the model's capacity changed since the last interval
 * (the stepper's grip force): the mode is decided again at its start. */
static int hybrid_advance(const exdex_model *m, ode *O, double ti, int regrip, exdex_trajectory *out, size_t i,
                          exdex_stats *st)
{
    hyb H = O->S.H;
    double y[NY_MAX], y0[NY_MAX], *ts = O->ts, t = O->S.t, h = O->S.h;
    size_t nsw = O->S.nsw;
    int nd, ns, law = H.law, status = EXDEX_OK;
    if (O->mc) m = model_pads_follow(m, O->mc);
    nd = m->ndof;
    ns = m->n_stops;
    memcpy(y, O->S.y, sizeof y);
    H.m = m;
    H.mc = O->mc;
    H.st = st;
    O->sys.params = &H;
    O->step = H.stiff ? O->bs : O->rk;
    if (regrip) {
        H.cap = H.capk * model_capacity(m, t);
        H.caps = H.capk * model_capacity_static(m, t);
        hold_set_rows(&H, t, y);
        decide(&H, t, y, 0);
        stiff_track(&H, y, 1);
        O->step = O->rk;
        gsl_odeiv2_evolve_reset(O->evo);
        gsl_odeiv2_step_reset(O->step);
        status = H.err;
    }
    do {
        double hs = ti - O->S.t_rec;
        if (status) break;
        int events = 0, same = 0;
        unsigned long ode_steps = 0;
        size_t brent0 = st->solver_iterations; /* Brent iterations count in the step budget */
        double t_event = -1.0;
        while (t < ti && status == EXDEX_OK && !H.err) {
            double g0[NG_MAX], g1[NG_MAX], t0 = t, tstop, tau_best = INFINITY;
            int ng, e_best = -1, gs;
            size_t k = 0;
            while (k < nsw && ts[k] <= t) k++;
            H.lo = k ? ts[k - 1] : 0.0;
            H.hi = k < nsw ? ts[k] : INFINITY;
            tstop = fmin(ti, H.hi);
            tstop = fmin(tstop, exdex_motion_next_knot(m->motion, t));  /* a step ends at a knot: header */
            if (nd == 3 && H.mode == MODE_SLIP && law == LAW_COULOMB &&
                (y[3] != 0.0 || y[4] != 0.0 || y[5] != 0.0)) {
                double u[3];
                hyb_pads(&H, y);
                model_patch_slip(m, MODEL_CS(y[2]), y + 3, u);
                for (int c = 0; c < 3; c++) H.uref[c] = m->e[c] * u[c];
            }
            memcpy(y0, y, sizeof y);
            ng = guards(&H, t0, y0, g0);
            if (O->step != (H.stiff ? O->bs : O->rk)) {
                O->step = H.stiff ? O->bs : O->rk;
                ode_restart(O);
            }
            {
                unsigned long c0 = O->evo->count + O->evo->failed_steps;
                gs = gsl_odeiv2_evolve_apply(O->evo, O->con, O->step, &O->sys, &t, tstop, &h, y);
                ode_steps += O->evo->count + O->evo->failed_steps - c0;
            }
            if (H.err) break;
            if (gs != GSL_SUCCESS) {
                st->fail_cause = EXDEX_FAIL_STEPPER;
                status = EXDEX_ENOCONV;
                break;
            }
            st->steps++;
            /* step budget and step floor (see the header comment) */
            if (ode_steps + (st->solver_iterations - brent0) > STEPS_MAX ||
                (t < tstop && !(h >= H_FLOOR_ULPS * DBL_EPSILON * fabs(t)))) {
                st->warnings++;
                st->fail_cause = ode_steps + (st->solver_iterations - brent0) > STEPS_MAX ? EXDEX_FAIL_STEP_BUDGET
                                                                                        : EXDEX_FAIL_STEP_FLOOR;
                status = EXDEX_ENOCONV;
                break;
            }
            guards(&H, t, y, g1);
            if (nd == 1 && law == LAW_COULOMB && H.mode == MODE_SLIP && g0[0] > 0.0 && g1[0] >= 0.0) {
                /* the slip can stop and restart the same way within one
                 * step (the load falls inside the friction limit and
                 * leaves it again): s qd dips below 0 and recovers, which
                 * the end values do not show. s qd has an interior minimum
                 * when its rate turns from falling to rising over the step;
                 * then a golden-section search for it on the stepper's map
                 * (bounded), and a negative minimum bounds the root */
                double d0[NY_MAX], d1[NY_MAX];
                if (rhs(t0, y0, d0, &H) == GSL_SUCCESS && rhs(t, y, d1, &H) == GSL_SUCCESS &&
                    H.s * d0[1] < 0.0 && H.s * d1[1] > 0.0) {
                    double tm, gm;
                    status = guard_extremum(&H, O, t0, y0, t - t0, 0, 1.0, &tm, &gm);
                    if (status) break;
                    if (gm < 0.0) {
                        /* the step ends at the dip; the guard is violated there */
                        if (one_step(O, t0, y0, tm, y) != GSL_SUCCESS) {
                            status = EXDEX_ENOCONV;
                            break;
                        }
                        t = t0 + tm;
                        guards(&H, t, y, g1);
                    }
                }
            }
            for (int e = 0; e < ng; e++) {
                double tau;
                if (!(g1[e] < 0.0)) continue;
                if (g0[e] <= 0.0) {
                    /* violated from the start: an event at t0 unless the
                     * guard is recovering (a touching stop left behind), or
                     * the decision at t0 keeps being undone (a tie: let the
                     * step decide, counted as a warning) */
                    if (!(g1[e] < g0[e] - 1e-13)) continue;
                    {
                        /* it may recover first and cross later within the
                         * step (a corner lifted off a stop by an impact at
                         * t0 falls back): locate that crossing */
                        double tm, gm;
                        status = guard_extremum(&H, O, t0, y0, t - t0, e, -1.0, &tm, &gm);
                        if (status) break;
                        if (gm > 0.0) {
                            status = locate(&H, O, t0, y0, tm, t - t0, e, &tau);
                            if (status) break;
                            if (tau < tau_best) {
                                tau_best = tau;
                                e_best = e;
                            }
                            continue;
                        }
                    }
                    if (same >= 4) {
                        st->warnings++;
                        continue;
                    }
                    tau = 0.0;
                } else {
                    status = locate(&H, O, t0, y0, 0.0, t - t0, e, &tau);
                    if (status) break;
                }
                if (tau < tau_best) {
                    tau_best = tau;
                    e_best = e;
                }
            }
            /* a free gap that dipped below 0 and recovered within the step */
            if (!status) status = gap_dips(&H, O, t0, y0, t, y, ng, g0, g1, &tau_best, &e_best);
            /* ... or through an obstacle row's feature switch */
            if (!status) status = obst_dips(&H, O, t0, y0, t, y, g0, g1, &tau_best, &e_best);
            if (!status && ns && nd == 1) {
                /* 1-DoF: a corner's gap dipping below 0 within the step
                 * (row_dip): the event is its stop guard, violated at the
                 * crossing */
                double tau, gt[NG_MAX], ye[NY_MAX], t1 = t;
                const double *y1 = y;
                if (tau_best < t - t0) {
                    /* only a dip before the event found matters */
                    if (one_step(O, t0, y0, tau_best, O->ytmp) != GSL_SUCCESS || H.err) {
                        status = H.err ? H.err : EXDEX_ENOCONV;
                        break;
                    }
                    memcpy(ye, O->ytmp, (size_t)H.ny * sizeof *ye);
                    t1 = t0 + tau_best;
                    y1 = ye;
                }
                status = row_dip(&H, O, t0, y0, t1, y1, &tau);
                if (!status && tau < tau_best) {
                    if (one_step(O, t0, y0, tau, O->ytmp) != GSL_SUCCESS || H.err) {
                        status = H.err ? H.err : EXDEX_ENOCONV;
                    } else {
                        guards(&H, t0 + tau, O->ytmp, gt);
                        for (int e = 0; e < ng; e++)
                            if (g0[e] > 0.0 && gt[e] < 0.0) {
                                tau_best = tau;
                                e_best = e;
                                break;
                            }
                    }
                }
            }
            if (status) break;
            /* a guard can dip below 0 and recover within one step (its end
             * value is >= 0): the located event's point shows it; take the
             * earliest such crossing instead (at most ng passes) */
            for (int pass = 0; e_best >= 0 && tau_best > 0.0 && !status && pass < ng; pass++) {
                double gt[NG_MAX], tau_new = tau_best;
                int e_new = -1;
                if (one_step(O, t0, y0, tau_best, O->ytmp) != GSL_SUCCESS || H.err) {
                    status = H.err ? H.err : EXDEX_ENOCONV;
                    break;
                }
                guards(&H, t0 + tau_best, O->ytmp, gt);
                for (int e = 0; e < ng && !status; e++) {
                    double tau;
                    if (e == e_best || !(g0[e] > 0.0) || !(gt[e] < 0.0)) continue;
                    status = locate(&H, O, t0, y0, 0.0, tau_best, e, &tau);
                    if (!status && tau < tau_new) {
                        tau_new = tau;
                        e_new = e;
                    }
                }
                if (e_new < 0) break;
                tau_best = tau_new;
                e_best = e_new;
            }
            if (!status && ode_steps + (st->solver_iterations - brent0) > STEPS_MAX) {
                st->warnings++;
                st->fail_cause = EXDEX_FAIL_STEP_BUDGET;
                status = EXDEX_ENOCONV;
            }
            if (status) break;
            if (e_best >= 0) {
                int vz, keep = 0, sep = -1, join = 0;
                if (tau_best > 0.0 && t0 + tau_best == t0 && g0[e_best] > 0.0 && t > t0) {
                    /* a crossing within half an ulp of t0: the event time
                     * would round to t0, where the guard holds and the
                     * decision at the same state would be taken again
                     * (no progress, events piling up at one time): the
                     * event is at the next representable time */
                    tau_best = nextafter(t0, INFINITY) - t0;
                }
                if (one_step(O, t0, y0, tau_best, y) != GSL_SUCCESS || H.err) {
                    status = H.err ? H.err : EXDEX_ENOCONV;
                    break;
                }
                t = t0 + tau_best;
                same = t == t_event ? same + 1 : 0;
                t_event = t;
                /* the first guard of 1-DoF slip (and of moving contact, the
                 * second) is the slip speed: it stopped. A rest against a
                 * stop (1-DoF contact, s = 0) ends at its first guard (the
                 * stop no longer pushes and the load leaves the static
                 * capacity) from rest: the velocity it carries is the
                 * stop's, below tol.vzero (its second guard), whose sign
                 * must not choose a slip */
                vz = (nd == 1 && H.mode == MODE_SLIP && e_best == 0) ||
                     (H.mode == MODE_CONTACT && H.law == LAW_COULOMB && H.s != 0.0 && e_best == 1) ||
                     (nd == 1 && H.mode == MODE_CONTACT && H.law == LAW_COULOMB && H.s == 0.0 && e_best == 0);
                if (nd == 3 && H.mode == MODE_SLIP && law == LAW_COULOMB && e_best < 2) {
                    /* planar: a small slip stops (guard 0) or has grown
                     * (guard 1: on as a slip, no stop); a slip decays below
                     * zsw (guard 1) or reverses (guard 0): a stop, unless
                     * |E u| is still above zsw where E u turned against its
                     * direction at the step start (a turn: on as a slip
                     * with the new reference direction) */
                    double u[3], eu[3];
                    hyb_pads(&H, y);
                    model_patch_slip(m, MODEL_CS(y[2]), y + 3, u);
                    for (int c = 0; c < 3; c++) eu[c] = m->e[c] * u[c];
                    if (H.small) {
                        vz = e_best == 0;
                        /* grown to SLIP_UP zsw: decided as a (large) slip */
                        if (e_best == 1) H.small = 0;
                    } else {
                        vz = e_best == 1 || !(sqrt(ex_dot3(eu, eu)) > H.zsw);
                        if (e_best == 1) {
                            /* decayed below zsw: it stops where the load
                             * can be held; else it slips on as a small
                             * slip, velocity kept (what a stop dropped
                             * would persist where the friction cannot
                             * take it back, e.g. mu = 0) */
                            frame fk;
                            exdex_kinematics kk;
                            if (frame_seg(&H, t, &fk, &kk)) {
                                status = EXDEX_ENOCONV;
                                break;
                            }
                            keep = !planar_load_held(&H, &fk, &kk, y);
                        }
                    }
                }
                /* planar, a contact-set row separating (its guard lam G
                 * M^-1 G^T - gap acceleration, after the free gaps) */
                if (nd == 3 && law == LAW_COULOMB && H.mode != MODE_STICK && e_best >= H.gap1 &&
                    e_best < H.gap1 + H.ncs)
                    sep = H.cs[e_best - H.gap1];
                /* planar, a free stop row's gap (the first guards from gap0) */
                if (nd == 3 && law == LAW_COULOMB && H.mode == MODE_SLIP && !H.sfric && e_best >= H.gap0 &&
                    e_best < H.gap1 && e_best - H.gap0 < H.ns * H.nv - H.ncs)
                    join = 1;
                hold_set_rows(&H, t, y);
                /* regularised, planar, two coefficients: the held
                 * regime's guard (the first): it broke away, or a slip
                 * slowed into the band */
                if (smooth_two(&H) && e_best == 0) H.held = !H.held;
                if (keep)
                    H.small = 1;
                else
                    decide(&H, t, y, vz);
                if (sep >= 0 && same >= 1 && H.mode == MODE_SLIP) {
                    set_tie_leaves(&H, sep);
                    if (H.sfric) sf_redecide(&H, t, y);
                }
                if (join && same >= 1 && H.mode == MODE_SLIP) set_tie_joins(&H, y, t);
                gsl_odeiv2_evolve_reset(O->evo);
                gsl_odeiv2_step_reset(O->step);
                if (++events > EVENTS_MAX) {
                    st->warnings++;
                    st->fail_cause = EXDEX_FAIL_EVENTS;
                    status = EXDEX_ENOCONV;
                    break;
                }
            } else {
                /* the projection moves y off the evolve object's last
                 * output: the next step must not start from that output's
                 * derivative */
                double yp[NY_MAX];
                memcpy(yp, y, sizeof yp);
                /* a planar rest holds q (reported_pose) */
                if (!(nd == 3 && law == LAW_COULOMB && H.mode == MODE_STICK)) project_contact(&H, t, y);
                if (memcmp(yp, y, (size_t)H.ny * sizeof *y)) ode_restart(O);
            }
            stiff_track(&H, y, e_best >= 0);
            /* a penetration left after the step: the scene drives the
             * object through a stop (see tol.pen) */
            if (ns || m->n_obst) {
                exdex_kinematics kt;
                double yr[NY_MAX];
                const double *yq = reported_pose(&H, t, y, yr);
                double gmin = exdex_motion_eval(m->motion, t, &kt) ? INFINITY : contact_min_gap(m, &kt, yq);
                if (gmin < st->min_gap) st->min_gap = gmin;
                if (gmin < -m->tol.pen) st->warnings++;
            }
            if (t == H.hi) {
                /* a switching time of the motion: next segment */
                hold_set_rows(&H, t, y);
                H.lo = H.hi;
                k++;
                H.hi = k < nsw ? ts[k] : INFINITY;
                status = apply_jump(&H, t, y);
                if (status) break;
                decide(&H, t, y, 0);
                stiff_track(&H, y, 1);
                ode_restart(O);
            }
            if (!ex_finite_n(y, H.ny)) status = EXDEX_ENONFINITE;
        }
        if (H.err && !status) status = H.err;
        if (status) break;
        {
            /* the interval's integrals (friction, stop forces) as means
             * over it; then they restart from 0 */
            int off = nd == 1 ? 2 : 6, nw = nd == 1 ? 1 : 3;
            double wrench[3] = {0, 0, 0}, sf[NSRC_MAX], yr[NY_MAX];
            const double *yq;
            if (nd == 3) {
                for (int c = 0; c < 3; c++) wrench[c] = y[6 + c] / hs;
            } else if (m->def.dof == EXDEX_DOF_TRANSLATION) {
                wrench[0] = y[2] / hs * m->d[0];
                wrench[1] = y[2] / hs * m->d[1];
            } else {
                wrench[2] = y[2] / hs;
            }
            for (int k2 = 0; k2 < m->n_src; k2++) sf[k2] = y[off + nw + k2] / hs;
            yq = reported_pose(&H, ti, y, yr);
            method_record(m, out, st, i, ti, yq, yq + nd, wrench,
                          law == LAW_COULOMB && H.mode == MODE_STICK ? 1 : is_still(&H, y), sf);
            for (int c = off; c < H.ny; c++) y[c] = 0.0;
        }
    } while (0);
    if (!status && H.err) status = H.err;
    if (status) hybrid_failed(&H, status, t, st);
    O->S.H = H;
    memcpy(O->S.y, y, sizeof y);
    O->S.t = t;
    O->S.h = h;
    O->S.t_rec = ti;
    O->sys.params = &O->S.H;
    return status;
}

/* ------------------------------------------------------------ entry points */

static int event_begin(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st)
{
    return hybrid_begin(m, ws, LAW_COULOMB, t_end, dt, st);
}

static int regularised_begin(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st)
{
    return hybrid_begin(m, ws, LAW_SMOOTH, t_end, dt, st);
}

static int hybrid_advance_ws(const exdex_model *m, void *ws, double t1, int regrip, exdex_trajectory *out,
                             size_t i, exdex_stats *st)
{
    return hybrid_advance(m, ws, t1, regrip, out, i, st);
}

/* The state: O->S with the evolve object's fields (the switching times
 * are fixed by begin; the stepper and control objects are not saved: the
 * rk8pd and bsimp steppers recompute all their stages (bsimp also its
 * Jacobian) from y and dydt_in in each application, the one in use is
 * H.stiff's, and the scaled control has no state). */
static void hybrid_save(const void *ws, void *buf)
{
    const ode *O = ws;
    struct hyb_state S;
    size_t n = O->evo->dimension;
    memcpy(&S, &O->S, sizeof S);
    S.count = O->evo->count;
    S.failed_steps = O->evo->failed_steps;
    S.last_step = O->evo->last_step;
    memcpy(S.e_y0, O->evo->y0, n * sizeof(double));
    memcpy(S.e_yerr, O->evo->yerr, n * sizeof(double));
    memcpy(S.e_dydt_in, O->evo->dydt_in, n * sizeof(double));
    memcpy(S.e_dydt_out, O->evo->dydt_out, n * sizeof(double));
    memcpy(buf, &S, sizeof S);
}

static int hybrid_restore(void *ws, const void *buf)
{
    ode *O = ws;
    struct hyb_state S;
    const hyb *B = &O->S.H;   /* as begin set it up for this model and law */
    int nr;
    memcpy(&S, buf, sizeof S);
    nr = B->ns * B->nv;
    if (S.H.law != B->law || S.H.ndof != B->ndof || S.H.ns != B->ns || S.H.no != B->no || S.H.ny != B->ny ||
        S.H.nv != B->nv || S.nsw != O->S.nsw || S.H.mode < MODE_SLIP || S.H.mode > MODE_FREE || S.H.ncs < 0 ||
        S.H.ncs > MAX_ROWS ||
        (S.H.mode == MODE_CONTACT && !(S.H.ck >= 0 && S.H.ck < B->ns && S.H.cj >= 0 && S.H.cj < B->nv) &&
         !(S.H.ck >= B->ns && S.H.ck < B->ns + B->no && orow_valid(B->m, S.H.cj) &&
           orow_obst(S.H.cj) == S.H.ck - B->ns)))
        return EXDEX_EINVAL;
    for (int i = 0; i < S.H.ncs; i++)
        if (S.H.cs[i] < 0 || (S.H.cs[i] >= nr && !(B->no && orow_valid(B->m, S.H.cs[i] - nr)))) return EXDEX_EINVAL;
    if (S.H.sfric != B->sfric || (S.H.stiff != 0 && S.H.stiff != 1) || S.H.nlow < 0 || S.H.nlow > STIFF_AFTER ||
        (S.H.jam != 0.0 && S.H.jam != 1.0 && S.H.jam != -1.0) || (S.H.held != 0 && S.H.held != 1))
        return EXDEX_EINVAL;
    for (int k = 0; k < SF_MAX_STOPS; k++)
        if (S.H.fm[k] < SF_ROLL || S.H.fm[k] > SF_NONE) return EXDEX_EINVAL;
    if (S.H.sgn < 0 || S.H.sgn > SF_MAX_STOPS || (S.H.sgn > 0 && S.H.ndof != 3)) return EXDEX_EINVAL;
    for (int i = 0; S.H.sgn > 0 && i < S.H.ncs; i++)
        if (S.H.sg[i] < 0 || S.H.sg[i] >= S.H.sgn) return EXDEX_EINVAL;
    O->S = S;
    O->sys.params = &O->S.H;
    {
        size_t n = O->evo->dimension;
        O->evo->count = S.count;
        O->evo->failed_steps = S.failed_steps;
        O->evo->last_step = S.last_step;
        memcpy(O->evo->y0, S.e_y0, n * sizeof(double));
        memcpy(O->evo->yerr, S.e_yerr, n * sizeof(double));
        memcpy(O->evo->dydt_in, S.e_dydt_in, n * sizeof(double));
        memcpy(O->evo->dydt_out, S.e_dydt_out, n * sizeof(double));
    }
    return EXDEX_OK;
}

#define HYBRID_STATE_SIZE sizeof(((ode *)0)->S)

const method_impl method_event = {"event", hybrid_alloc, NULL, hybrid_free, 0, 0, event_begin,
                                  hybrid_advance_ws, HYBRID_STATE_SIZE, hybrid_save, hybrid_restore};
const method_impl method_regularised = {"regularised", hybrid_alloc, NULL, hybrid_free, 0, 0,
                                        regularised_begin, hybrid_advance_ws, HYBRID_STATE_SIZE, hybrid_save,
                                        hybrid_restore};
