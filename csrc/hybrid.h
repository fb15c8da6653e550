/* hybrid.h -- private to the exdex core: the event-driven and regularised
 * methods (exdex.h, enum exdex_method), one hybrid ODE / event machine on
 * the model of model.h,
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
 *                     step's ends (hyb_gap_dips).
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
 *       (against stops: that law on the constrained acceleration, the plate
 *       one more contact of the stops' problem, stop_friction.h's sf_plate,
 *       with frictional stops and the ellipsoid; else the fixed point of
 *       the law). The sliding law's direction E u / |E u| relaxes onto
 *       it at the rate C |K| / |E u| (K = E W E), infinitely stiff at the
 *       start of a slip; the slip follows it to |E u| |dn/dt| / (C |K|) (n
 *       that direction). Guards: the load leaves the ellipsoid's outside
 *       (|E^-1 w_stick| - C (1 + FRICTION_BAND): it stops), SLIP_UP zsw - |E u| (it
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
 *   found from the guards' rates at the step's ends (hyb_gap_dips). In a 1-DoF
 *   scene a stop's gap guard is the least gap over the outline, whose end
 *   rates need not show one corner's dip (a corner of a turning object
 *   sweeping past a stop that cuts its path a little while another corner
 *   is the nearest at both step ends): each free (stop, vertex) row is
 *   checked too (hyb_row_dip). The
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
 *     stops: rest iff the least-friction split (hyb_planar_rest: least
 *     combination over the stop forces lam >= 0, ldp_min_combination, as the
 *     implicit method; the exact surface: its least gauge,
 *     limitsurf_min_combination; with frictional rows on the ellipsoid: the
 *     split of a plate creeping under the load, hybrid_laws.c's
 *     sf_rest_creep) has |E^-1 w| (the gauge) <= mu N
 *     (1 + FRICTION_BAND); the rest ends when that fails or a set row's gap leaves
 *     +-tol.rest_gap (stops moving in B). During the rest q is held
 *     exactly (no projection after its steps, which would move it by the
 *     stops' travel over each step and make the rest's end depend on where
 *     steps end); the samples and the smallest gap report it pushed out of
 *     the stops (hyb_reported_pose), as the decision at the rest's end does.
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
 *   (hyb_impact_impulse_1dof: the velocity after one is the frictionless one,
 *   the impulse the stop takes is not). Planar scenes: a friction mode per
 *   stop (stick, slide +-), exact at the acceleration level, in both
 *   methods (the regularised one smooths the plate friction only), and
 *   impacts with Coulomb friction at the impulse level: see "planar
 *   frictional stops" and "frictional impacts" below (sf_*, stop_friction.h).
 *   A planar sliding mode whose friction jams it (its determinant ratio
 *   D / D_0, the counterpart of D / Fq, falling to 0 with the stop forces
 *   growing without bound) is located at |D / D_0| = JAM_DIR (G_SF_JAM),
 *   where an impulse arrests the slip (the impact without collision,
 *   hyb_planar_jam_impulse) and the mode is decided again.
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
 *     rejected, plus the location's work: its Brent iterations, and every
 *     one-step map it applies (Brent, golden section, forward search, the
 *     cut at an event; each one stepper application) if more,
 *     per output interval (dt is the output grid and also the unit
 *     of the budget: a finer grid gives a long stiff run more steps), and the
 *     step the controller suggests must stay >= H_FLOOR_ULPS (16) ulps of t
 *     (h >= 16 DBL_EPSILON |t|) while t is short of the next stop time;
 *     GSL's own controller fails below 1 ulp, and the rejections inside one
 *     gsl_odeiv2_evolve_apply call are bounded by its step-size decrease
 *     (each at least x0.89 per rejection, floor at 1 ulp);
 *   - event: at most EVENTS_MAX (1000) events per output interval, each
 *     located by at most BRENT_MAX (200) Brent iterations (and a guard's
 *     extremum inside a step by at most GOLDEN_MAX (60) golden-section iterations);
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
#ifndef EXDEX_HYBRID_H
#define EXDEX_HYBRID_H

/* The methods' files, by concern (each includes this header; calls go
 * downwards only: hybrid.c -> hybrid_decide.c, hybrid_events.c ->
 * hybrid_impacts.c (decide only) -> hybrid_laws.c):
 *   hybrid_laws.c     the slip laws, the contact rows, the ODE right-hand side;
 *   hybrid_impacts.c  impacts and velocity jumps;
 *   hybrid_decide.c   the decision at an event and at a segment start (hyb_decide_event,
 *                     hyb_decide: the modes, the contact set, the stop friction; its
 *                     policy for ties and hysteresis, T1 .. T9) and the row states;
 *   hybrid_events.c   guards and event location;
 *   hybrid.c          the driver (workspace, start, advance, method tables). */

#include "exdex.h"
#include "contact.h"
#include "stop_impulse.h"
#include "ldp.h"
#include "method.h"
#include "model.h"
#include "obstacle_rows.h"
#include "stop_friction.h"
#include "tolerances.h"
#include "util.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <gsl/gsl_roots.h>

#define NY_MAX (9 + EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES)
#define NG_MAX (3 + 3 * MAX_ROWS + 2 + SF_MAX_STOPS + EXDEX_MAX_OBSTACLES)  /* guards (planar: 2 friction, the rows, stop friction, obstacle features) */
#define NSRC_MAX (EXDEX_MAX_STOPS + EXDEX_MAX_OBSTACLES)

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
    int sfric;         /* planar with a frictional stop: the stop friction below (sf_*) */
    int fm[SF_MAX_STOPS];  /* planar: friction mode of each friction group with contact-set rows (SF_*) */
    int no;            /* obstacles (their rows follow the stops', see hyb_hrow_src) */
    int stiff;         /* event, planar slip: 1 while the stiff stepper integrates it (stiff_track) */
    int nlow;          /* consecutive steps of that slip below SLIP_STIFF zsw (up to STIFF_AFTER) */
    int cheb;          /* event, planar slip: 1 while the Chebyshev stepper integrates it (cheb_track) */
    int ncheb;         /* consecutive rk8pd steps of that slip near rk8pd's stability limit (up to CHEB_AFTER) */
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

/* The mode as one array of row states (hyb_row_states, hybrid_decide.c): a
 * record per row of the contact state, the plate's friction first, then
 * each row in contact (planar: the contact set in its order; 1-DoF: the
 * contact row), then each friction group of the set (planar, stop
 * friction). The records are read from hyb's mode fields (mode, small,
 * stiff, held, s, ck, cj, ss, jam, cs, sgn, sg, fm), which the slip laws
 * and guards read. */
enum { ROW_PLATE, ROW_STOP, ROW_OBSTACLE, ROW_GROUP };
enum {
    /* the plate (dir: 1-DoF the slip sign s) */
    RS_STICK,      /* held exactly (against rows: a rest on them) */
    RS_SLIP,       /* the sliding law (rk8pd) */
    RS_SMALL_SLIP, /* planar: a slip growing from rest, below SLIP_UP zsw */
    RS_STIFF_SLIP, /* planar: a slip lingering slow, on the stiff stepper */
    RS_SMOOTH,     /* regularised: the smooth law */
    RS_HELD,       /* regularised, two coefficients: the held regime */
    /* a row in contact (dir: 1-DoF the stop friction's sign ss, or the jam's) */
    RS_CONTACT,
    RS_JAM,        /* 1-DoF, frictional: taken frictionless at a jam */
    /* a friction group (its stop_friction.h mode SF_*; dir: a slide's sign) */
    RS_ROLL,
    RS_GROUP_STICK,
    RS_SLIDE,
    RS_FRICTIONLESS
};

typedef struct hyb_row_state {
    int kind;     /* ROW_* */
    int row;      /* plate -1; planar row r = k nv + j or ns nv + obstacle code; 1-DoF the vertex or
                     obstacle row code (cj); a group its index */
    int src;      /* a row's stop or obstacle source (k, or ns + obstacle); else -1 */
    int group;    /* a planar row's friction group while the groups are fixed (sgn > 0); else -1 */
    int mode;     /* RS_* */
    double dir;
} hyb_row_state;

#define HYB_ROWS_MAX (1 + MAX_ROWS + SF_MAX_STOPS)

/* Pads on the fingers: the model's contact fields set to the region at the
 * planar state y (model_pads_set; nothing when they hold it already). Every
 * function below that reads the contact (pc, e, prep) at a state calls it
 * first. */
static inline void hyb_pads(const hyb *H, const double *y)
{
    if (H->mc && H->ndof == 3) model_pads_set(H->mc, y);
}

/* every contact-set row and friction group fits stop_friction.h's problem */
_Static_assert(MAX_ROWS <= SF_MAX_ROWS, "stop_friction.h holds every contact-set row");
_Static_assert(EXDEX_MAX_STOPS + MAX_ROWS <= SF_MAX_STOPS, "stop_friction.h holds every friction group");

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

/* Group k's slip held at its value at v = 0 as an equality pair of a
 * velocity projection (rows G v >= b): rows n and n + 1 get +T_k, -T_k with
 * b = -tb_k, +tb_k; returns n + 2. */
static inline int hyb_sf_slip_pair(const sf_set *S, int k, double (*G)[3], double *b, int n)
{
    for (int c = 0; c < 3; c++) {
        G[n][c] = S->st[k].T[c];
        G[n + 1][c] = -S->st[k].T[c];
    }
    b[n] = -S->tb[k];
    b[n + 1] = S->tb[k];
    return n + 2;
}

/* ------------------------------------------------------------- guards
 * A guard of the current mode (hybrid_events.c, hyb_guards): value >= 0
 * while the mode holds, an event where it falls below 0 (located on the
 * stepper's map). kind says what ends there; row is the contact row it
 * watches (a (stop, vertex) row r = k nv + j or ns nv + obstacle code, a
 * friction group, a stop or an obstacle, by kind; -1 for none); dir is the
 * sign of the motion it follows (the slip direction s, ss or jam, the slide
 * of a friction group; 0 for a force, a gap or a speed). The guards of a
 * mode come in a fixed order: the plate friction's, the free gaps (one
 * block: G_GAP or G_STOP_GAP, then G_OBST_GAP), the contact set's, the
 * 1-DoF contact's, the stop friction's. */
enum {
    /* plate friction, planar */
    G_HELD,          /* regularised, two coefficients: the held regime breaks away / is held again */
    G_SMALL_STOPS,   /* small slip: the load falls back inside the limit (a stop) */
    G_SMALL_GROWS,   /* small slip: |E u| reaches SLIP_UP zsw (a slip) */
    G_SLIP_TURNS,    /* slip: E u turns against its direction at the step start */
    G_SLIP_DECAYS,   /* slip: |E u| falls below zsw */
    G_STICK_LEAVES,  /* stick (planar or 1-DoF): the load at rest leaves the static limit */
    /* 1-DoF modes */
    G_SLIP_STOPS,    /* slip: s qd reaches 0 */
    G_REST_LEAVES,   /* rest against a stop: the stop no longer pushes and the load leaves C_s */
    G_REST_MOVES,    /* rest against a stop: |qd| leaves tol.vzero */
    G_CONTACT_PUSH,  /* contact: the stop force reaches 0 */
    G_CONTACT_STOPS, /* contact, sliding along the stop: s qd reaches 0 */
    G_CONTACT_SLIP,  /* frictional contact: the vertex's slip along the stop reverses */
    G_CONTACT_JAM,   /* frictional contact: D / Fq falls to JAM_DIR (a jam) */
    G_JAM_SLIP,      /* taken frictionless at a jam: the slip reverses */
    G_JAM_ENDS,      /* taken frictionless at a jam: the friction would no longer jam */
    /* rows */
    G_GAP,           /* planar: a free (stop, vertex) row's gap (row r) */
    G_STOP_GAP,      /* 1-DoF: a stop's least vertex gap (row: the stop) */
    G_OBST_GAP,      /* an obstacle's free gap (row: the obstacle) */
    G_REST_GAP,      /* planar rest: a set row's |gap| leaves tol.rest_gap (row r) */
    G_SEPARATES,     /* a contact-set row's separation (row r) */
    G_FEATURE,       /* an obstacle row in contact keeps its feature (row r, or the 1-DoF row code) */
    /* stop friction, planar (row: the friction group) */
    G_SF_REST,       /* at rest: a stop's slip past the object leaves / enters the band */
    G_SF_CONSISTENT, /* +1 / -1: a consistent mode of the acceleration-level problem exists */
    G_SF_JAM,        /* a sliding group's friction jams its mode: |D / D_0| reaches JAM_DIR (hyb_sf_jam_ratio) */
    G_SF_SLIDES,     /* a sliding group's slip reaches 0 */
    G_SF_CONE,       /* a sticking group's force reaches its cone */
    G_SF_LOCK,       /* a lock's margin */
    G_SF_IDLE        /* a group without a guard of its own (+1) */
};

typedef struct hyb_guard {
    double value;
    int kind, row;
    double dir;
} hyb_guard;

/* (cos, sin) of theta = y[2] in csv for the stop rows' _cs forms, or NULL
 * where the scene has no stops (the rows then take nothing). */
static inline const double *hyb_stop_cs(const hyb *H, const double *y, double csv[2])
{
    if (!H->ns) return NULL;
    csv[0] = cos(y[2]);
    csv[1] = sin(y[2]);
    return csv;
}

static inline hyb_guard hg(int kind, int row, double dir, double value)
{
    hyb_guard g = {value, kind, row, dir};
    return g;
}

/* A free gap (functions of (t, q) alone). */
static inline int hyb_guard_is_gap(int kind) { return kind == G_GAP || kind == G_STOP_GAP || kind == G_OBST_GAP; }

/* The ODE workspace of one run (hybrid.c): the steppers, the root finder
 * and the saved state. */
typedef struct ode {
    gsl_odeiv2_step *step;         /* the stepper in use: rk, or bs while H.stiff */
    gsl_odeiv2_step *rk, *bs, *ck; /* rk8pd (explicit), bsimp (linearly implicit, stiff_track), rkc (cheb_track) */
    gsl_odeiv2_control *con;
    gsl_odeiv2_evolve *evo;
    gsl_root_fsolver *root;
    gsl_odeiv2_system sys;
    double yerr[NY_MAX], ytmp[NY_MAX];
    double *ts, *gb;   /* switching times, grip breakpoints (EXDEX_MOTION_MAX_SWITCHES + grip_n each) */
    exdex_model *mc;   /* pads on the fingers: the run's own copy of the model (hyb.mc) */
    unsigned long maps; /* one-step maps applied (hyb_one_step): event location's share of the step budget */
    /* the right-hand side at the start of the step under way, (f0_t,
     * f0_y), for its one-step maps (hyb_one_step); f0_ok = 0: not yet
     * evaluated in this step (step_start clears it) */
    double f0[NY_MAX], f0_y[NY_MAX], f0_t;
    int f0_ok;
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

/* hybrid_laws.c */
int hyb_hrow_src(const hyb *H, int r);
double hyb_hrow_planar(const hyb *H, const exdex_kinematics *kin, int r, const double *q, const double *v,
                       double G[3], double *gd, double *gdd0);
/* The same with cs = (cos q[2], sin q[2]) given (NULL: computed). */
double hyb_hrow_planar_cs(const hyb *H, const exdex_kinematics *kin, int r, const double *q, const double *cs,
                          const double *v, double G[3], double *gd, double *gdd0);
int hyb_hrow_all_planar(const hyb *H, const exdex_kinematics *kin, const double *y, int *rows, double (*G)[3],
                        double *gap, double *gd);
void hyb_hrow_1dof(const hyb *H, const exdex_kinematics *kin, int k, int j, double q, crow *c);
int hyb_hrow_all_1dof(const hyb *H, const exdex_kinematics *kin, double q, const double *v, int *k, int *j);
int hyb_frame_seg(hyb *H, double t, frame *f, exdex_kinematics *k);
double hyb_contact_qdd(const crow *c, double v);
double hyb_row_slip_1dof(const hyb *H, const exdex_kinematics *kin, int k, int j, double q, double v, double *T);
double hyb_contact_slip_1dof(const hyb *H, const exdex_kinematics *kin, double q, double v, double *T);
double hyb_contact_dir(const hyb *H, const crow *c, double T);
void hyb_contact_forces(const hyb *H, const crow *c, double T, double R, double v, double *f, double *lam);
int hyb_sf_build(hyb *H, const exdex_kinematics *kin, const double *y, sf_set *S);
void hyb_sf_fix_groups(hyb *H, double t, const double *y);
int hyb_sf_solve_at(hyb *H, const exdex_kinematics *kin, const double *y, const double a[3], sf_result *res);
double hyb_sf_jam_ratio(const hyb *H, const sf_set *S, const sf_result *res);
int hyb_sf_solve_plate(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, sf_result *res);
int hyb_contact_acc_planar(hyb *H, const exdex_kinematics *kin, const double *y, const double afree[3],
                           double qdd[3], double *lam, double *acc, unsigned *lock_rows);
double hyb_planar_rest(hyb *H, const exdex_kinematics *kin, const double *y, const double F[3], double w[3],
                       double *lam);
double hyb_planar_load(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y);
int hyb_planar_load_held(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y);
int hyb_smooth_two(const hyb *H);
double hyb_planar_slip_speed(const hyb *H, const double *y);
int hyb_planar_set_recedes(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y);
int hyb_planar_friction(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, double F[3],
                        double w[3]);
int hyb_sf_free_acc(hyb *H, const frame *f, const exdex_kinematics *kin, const double *y, double a[3]);
int hyb_rhs(double t, const double y[], double dy[], void *params);
int hyb_slip_jac(double t, const double y[], double *dfdy, double dfdt[], void *params);

/* hybrid_impacts.c */
double hyb_impact_impulse_1dof(hyb *H, const exdex_kinematics *kin, int k, int j, double q, const crow *c,
                               double v, double vn);
void hyb_planar_impact_and_set(hyb *H, double t, const exdex_kinematics *kin, double *y);
int hyb_planar_jam_impulse(hyb *H, double t, double *y);
void hyb_planar_unpenetrate(hyb *H, const exdex_kinematics *kin, double *y);
const double *hyb_reported_pose(hyb *H, double t, const double *y, double *buf);
int hyb_apply_jump(hyb *H, double ts, double *y);

/* hybrid_decide.c */
void hyb_set_tie_leaves(hyb *H, int r);
void hyb_set_tie_joins(hyb *H, const double *y, double t);
void hyb_decide(hyb *H, double t, double *y, int vzero);
int hyb_decide_event(hyb *H, double t, double *y, hyb_guard g, int same);
int hyb_row_states(const hyb *H, hyb_row_state *rs);
void hyb_sf_redecide(hyb *H, double t, double *y);
void hyb_hold_set_rows(hyb *H, double t, double *y);
void hyb_project_contact(hyb *H, double t, double *y);

/* hybrid_events.c */
int hyb_guards(hyb *H, double t, const double *y, hyb_guard *g);
int hyb_one_step(ode *O, double t0, const double *y0, double tau, double *out);
int hyb_guard_extremum(hyb *H, ode *O, double t0, const double *y0, double tau1, int e, double dir,
                       double *tau, double *g);
int hyb_gap_dips(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, int ng,
                 const hyb_guard *g0, const hyb_guard *g1, double *tau_best, int *e_best);
int hyb_obst_dips(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, int ng,
                  const hyb_guard *g0, const hyb_guard *g1, double *tau_best, int *e_best);
int hyb_locate(hyb *H, ode *O, double t0, const double *y0, double tau0, double tau1, int e, double *tau);
int hyb_row_dip(hyb *H, ode *O, double t0, const double *y0, double t1, const double *y1, double *tau);

#endif
