/* tolerances.h -- private to the exdex core: the one table of the
 * thresholds and budgets of the core's contact and friction decisions, of
 * the solvers of the plates' friction law (the ellipsoid and the exact limit
 * surface) and of the hybrid (event, regularised) methods' iterations.
 * Every entry is scale-free: a pure number, a fraction of one of the
 * scene's scales (model_scales: L, T, V = L / T, F, q; model_set_scales
 * turns the *_REL factors into model_tols), a multiple of a named speed
 * (zsw, the small-slip band of hybrid.h), a count of ulps, or an iteration
 * count. A threshold is spelled here once and read by name everywhere it is
 * used. */
#ifndef EXDEX_TOLERANCES_H
#define EXDEX_TOLERANCES_H

/* ------------------------------------------------ the rounding band
 * Relative band of every friction-limit and mode-sign check of a solved
 * quantity against its bound (the rounding of the solve, far below any
 * physical margin): a load sticks while |f| <= C (1 + FRICTION_BAND) (the
 * event method's stick tests, implicit.c's rest split, analytic.c's closed
 * forms), a stop's friction sticks while |beta| <= mu sum lam (1 +
 * FRICTION_BAND) (stop_friction.h), and stop_impulse.c's sign checks of an
 * impulse-level mode allow FRICTION_BAND of the quantities' size. */
#define FRICTION_BAND 1e-12

/* ------------------------------------------------ the certificate (certify.c)
 * A slip's unbalanced wrench counts as zero below this fraction of the
 * scene's force scale plus the load's size and the capacity (rounding of
 * the load is ~1e-16 of them). */
#define CERT_SLIP_TOL 1e-9
/* A piece's (or a block's) far end, where a motion switches, is evaluated
 * this fraction of its length inside it (the left limit there), and a
 * grip schedule's capacities at its ends are widened by as much of their
 * change. */
#define CERT_PIECE_INSIDE 1e-9
/* Relative widening of a computed bound, enclosure or band test beyond the
 * rounding of its evaluation (some hundred operations on numbers of the
 * terms' size). */
#define CERT_ROUND 1e-12
/* A stuck output interval that no proof covers is halved this many times
 * at most (its enclosure proven over each part, the middle of a part that
 * is not proven evaluated): an excursion of the load between two stuck
 * samples is seen to 2^-CERT_BETWEEN_DEPTH of the interval where the
 * enclosures cannot prove it absent. */
#define CERT_BETWEEN_DEPTH 4
/* logs (sampled motions) whose whole-knot-interval frame boxes one certificate caches (motion.c,
   motion_frame_box_cached); a further log's boxes are computed anew each time */
#define FRAME_BOX_CACHE_LOGS 8

/* ------------------------------------------------ model_tols (model.c)
 * For a typical paper scene (L ~ 1 cm, T ~ 30 ms, V ~ 0.3 m/s) they give
 * thresholds near 1e-10 m, 1e-12 m/s and 1e-13 s, far below the accuracy
 * of any method and far above the rounding of the quantities they compare. */
#define TOUCH_REL 1e-8       /* tol.touch: a stop gap below it counts as contact, x L */
#define PEN_REL 1e-7         /* tol.pen: a gap below -pen after a step counts a warning, x L */
#define START_GAP_REL 1e-7   /* tol.start_gap: a vertex starting below -start_gap is beyond its stop, x L */
#define REST_GAP_REL 1e-7    /* tol.rest_gap: a planar rest ends when a set row's |gap| exceeds it, x L */
#define RATE_REL 3e-12       /* tol.rate: a gap rate below it counts as 0, x V */
#define VZERO_REL 3e-12      /* tol.vzero: a 1-DoF |qd| below it counts as 0, x q / T */
#define FQ_MIN_REL 1e-12     /* tol.fq_min: a 1-DoF stop row with |d gap / dq| below it cannot act, x L / q */
#define ROOT_REL 3e-12       /* tol.root: event time resolution, x T */
#define H0_REL 0.03          /* tol.h0: first step of the adaptive integrators, x T */

/* ------------------------------------------------ stop friction (stop_friction.h) */
#define SF_LOCK_RANK 1e-9  /* a lock's constraints (unit rows, M^-1/2 metric) and generators span R^3 above this volume */

#define PLATE_BRACKET_MAX 128 /* sf_solve_plate: trial points (doublings, halvings back from a pole) of the
                                 plate's multiplier to bracket its root ... */
#define PLATE_ROOT_MAX 100    /* ... false-position steps on the bracket ... */
#define PLATE_ROOT_TOL 1e-13  /* ... until lam |z(lam)| is within this x cap of cap, or lam within this of itself */
#define PLATE_POLY_BISECT 200 /* ... bisection steps per root of the polynomial that counts every root ... */
#define PLATE_ROOT_SEP 1e-6  /* ... whose least lam replaces the doubling's root when below it by this factor */

/* ------------------------------------------------ hybrid methods: budgets
 * (hybrid.h, "Budgets": a run that would exceed one returns EXDEX_ENOCONV) */
#define EVENTS_MAX 1000   /* events within one output interval */
#define STEPS_MAX 100000  /* ODE steps (accepted + rejected) and event location work per output interval */
#define H_FLOOR_ULPS 16.0 /* a suggested step below this many ulps of t is a collapse */
#define BRENT_MAX 200     /* Brent iterations per located event */
#define GOLDEN_MAX 60     /* golden-section iterations per guard extremum inside a step */
#define DOUBLING_MAX 64   /* locate: forward doublings from Brent's point to a violated guard */
#define DOUBLING_EXACT 10 /* locate: a forward search past 2^10 of its first increment is bisected back */
#define ROW_NEWTON_MAX 8  /* 1-DoF contact: Newton steps of q onto its constraint F(q, t) = 0 ... */
#define ROW_NEWTON_TOL 1e-16 /* ... until |dq| <= this x (q + |q|), q the coordinate's scale */
#define SMALL_SLIP_FIX_MAX 16  /* planar small slip against stops: fixed-point iterations of its friction ... */
#define SMALL_SLIP_FIX_TOL 1e-12 /* ... until the wrench moves by at most this x C (E-scaled components) */

/* ------------------------------------------------ hybrid methods: thresholds */
/* 1-DoF frictional contact (hybrid.h, "Frictional stops"): its normal force
 * is lam = R / D, D = Fq - mu ss T, i.e. the frictionless force R / Fq times
 * Fq / D. Where D / Fq falls to 0 (a jam: the friction turns the normal
 * force's generalized direction around) lam grows as 1 / (t_jam - t) and its
 * integral as -log(t_jam - t): no step reaches t_jam. The contact is taken
 * frictionless (warning counted) once D / Fq <= JAM_DIR, a guard located
 * like every guard: the normal force is then 1 / JAM_DIR times the
 * frictionless one, and the impulse given up, the integral of lam beyond,
 * grows as log(1 / JAM_DIR) only. Friction returns where D / Fq of the slip's
 * sign exceeds JAM_DIR again, or the slip reverses (decided again there).
 * Planar frictional stops: the same threshold on a sliding mode's
 * determinant ratio |D / D_0| (hyb_sf_jam_ratio, hybrid_laws.c), located by
 * the guard G_SF_JAM; there the slip is arrested by the impact without
 * collision (hyb_planar_jam_impulse, hybrid_impacts.c), whose tangential
 * impulse lies within JAM_DIR of its cone (|beta| = mu lam / (1 - D / D_0)
 * for one row). */
#define JAM_DIR 1e-6
#define SLIP_FLOOR 1e-6  /* planar slip: below zsw = SLIP_FLOOR V of |E u| the slip is "small" (hybrid.h) */
#define SLIP_UP 2.0      /* a small slip becomes a slip at SLIP_UP zsw (hysteresis against zsw) */
#define SLIP_PUSH 4.0    /* a stop pushing a stopped planar slip on below SLIP_PUSH zsw: a rest instead */
#define SLIP_STIFF 100.0 /* a planar slip below SLIP_STIFF zsw for STIFF_AFTER steps: the stiff stepper */
#define STIFF_AFTER 1000
/* planar slip (without rows in contact: slower than CHEB_SLOW V) whose rk8pd steps sit near their stability limit
   (h rho >= CHEB_ON, rho a bound on the direction's relaxation rate, CHEB_AFTER steps in a row): the Chebyshev
   stepper, back to rk8pd below CHEB_OFF (hybrid.c, cheb_track); its rate bound is CHEB_RHO_SAFETY times that bound
   at a step's start, and a step needing more than CHEB_STAGES_MAX stages is refused (the error control shrinks it) */
#define CHEB_SLOW 1e-3
#define CHEB_ON 6.0
#define CHEB_OFF 4.0
#define CHEB_AFTER 2
#define CHEB_RHO_SAFETY 2.0
#define CHEB_STAGES_MAX 64
#define SF_TOL 1e-10     /* sign slack of the stop-friction mode checks: x the scene's acceleration V / T and force F */
#define SF_SAME_LINE 1e-6  /* obstacle rows whose unit in-plane normals differ by at most this share a friction group */
#define DIP_DELTA 1e-3   /* dip searches: one-sided differences over this fraction of the step (hybrid_events.c) */
#define DIP_MARGIN 0.5   /* dip searches: a minimum estimated below this fraction of the smaller end value is searched */
#define FEW_ULPS 4.0     /* a few ulps of t: a segment's end as its left limit (seg_time), locate's first forward step */
#define HERMITE_FLAT 1e-14 /* hermite_min: a cubic coefficient below this share of the quadratic's is taken as 0 */
#define SET_ROW_DEPENDENT 1e-12 /* set_row_equalities: a row whose M-metric component off the earlier rows is below
                                   this share of its norm (squared) is dependent on them; hyb_sf_jam_ratio: a
                                   mode's constraints whose M-metric Gram determinant is below this share of the
                                   product of its diagonal are dependent */
#define GUARD_RECOVER 1e-13 /* a guard violated at a step's start recovers when it rises by more than this over
                               the step (in the guard's own units, not scaled) */

/* ------------------------------------------------ contact rows (contact.c, ldp.c)
 * A gap within its own rounding of zero counts as exactly 0 where a method
 * decides on its sign: the sign of a rounding-level gap depends on the world
 * frame the data is given in (contact_gap works in A), not on the scene.
 * The bound is GAP_ROUND rounding units of the sum of the magnitudes
 * contact_gap adds (|x_B|, |p|, |stop point|; R is orthonormal;
 * DBL_EPSILON: float.h). */
#define GAP_ROUND (8.0 * DBL_EPSILON)
#define NNLS_TOL 1e-13  /* ldp.c's NNLS: converged where the multipliers outside the passive set are <= this */

/* ------------------------------------------------ plate friction (plate_friction.c)
 * exdex_friction_prepare's checks of the plate's Delassus matrix W and the
 * solvers of the ellipsoid's maximum-dissipation problem (relative
 * tolerances, ulp counts, iteration counts). */
#define FRICTION_SYM_REL 1e-12  /* W must be symmetric to this x its largest entry */
/* Limit on the scaled condition number of W, that of D^-1 W D^-1 with
 * D = diag(W)^(1/2): beyond it W is singular to working precision (the stick
 * impulse -W^-1 b would carry relative errors above 1e-4). */
#define FRICTION_MAX_COND 1e12
#define FRICTION_STICK_REFINE 1e-6 /* a stick test within this of the ellipsoid is decided on the refined impulse */
#define FRICTION_SECULAR_MAX 200   /* secular equation: Newton or Brent iterations */
#define FRICTION_ROUND_ULPS 4.0    /* a root, a norm or a step within this many ulps counts as exact */
/* The Fritz John system (the general solver): GSL's hybridsj until the
 * scaled residual is below FJ_HYBRID_DONE (at most FJ_HYBRID_MAX iterations,
 * FJ_RESETS_MAX restarts from sigma < 0), then at most FJ_NEWTON_MAX Newton
 * steps; a root is accepted at a relative residual of FJ_RELRES, and sigma
 * = 0 is admitted where it leaves at most FJ_SIGMA_ZERO (DBL_EPSILON:
 * float.h). */
#define FJ_HYBRID_MAX 100
#define FJ_HYBRID_DONE 1e-6
#define FJ_RESETS_MAX 10
#define FJ_NEWTON_MAX 10
#define FJ_RELRES (64.0 * DBL_EPSILON)
#define FJ_SIGMA_ZERO 1e-12

/* ------------------------------------------------ the exact limit surface (limitsurf.c)
 * LS_FAR_RATIO: a region whose slip at the centroid exceeds this many region
 * sizes is integrated in the far field (limitsurf.c's head: the accuracy
 * that follows from it). Newton's stopping rules, on the squared Newton
 * decrement lam2 (about twice the objective's excess over its optimum)
 * relative to the objective's scale: done below LS_NEWTON_DONE (the optimum
 * to 1e-24 relative, the optimiser to about 1e-12); full steps without a
 * line search below LS_NEWTON_FULL (the decrease is below the rounding of
 * the objective there), and done once they stop shrinking lam2
 * quadratically (by LS_NEWTON_QUADRATIC a step: the rounding floor of the
 * gradient); a line search
 * (Armijo: decrease LS_ARMIJO_DECREASE t lam2, at most LS_ARMIJO_MAX
 * halvings) that ends below LS_LINE_STEP_MIN finds no decrease and ends the
 * iteration, which counts as converged below LS_NEWTON_ACCEPT. */
#define LS_FAR_RATIO 16.0
#define LS_NEWTON_DONE 1e-24
#define LS_NEWTON_FULL 1e-8
#define LS_NEWTON_ACCEPT 1e-12
#define LS_NEWTON_QUADRATIC 0.25
#define LS_ARMIJO_DECREASE 0.25
#define LS_ARMIJO_MAX 40
#define LS_LINE_STEP_MIN 1e-9
#define LS_SHIFT_START 1e-8  /* a Newton Hessian that is not positive definite: shift by this x its trace ... */
#define LS_SHIFT_GROWTH 10.0 /* ... growing by this factor ... */
#define LS_SHIFT_TRIES 30    /* ... at most this often */
/* The bounds kmin, kmax of the gauge's ratio to |E u| (limitsurf_prepare_bounds):
 * the extremes over a Fibonacci lattice of LS_BOUND_LATTICE directions, each
 * refined by a pattern search (first step LS_REFINE_STEP, halved down to
 * LS_REFINE_STEP_MIN, at most LS_REFINE_MAX moves), widened by
 * LS_SAMPLED_BOUND_MARGIN; the closed-form bounds of the ellipsoid of a
 * region are widened by LS_CLOSED_BOUND_MARGIN (their rounding). */
#define LS_BOUND_LATTICE 256
#define LS_REFINE_STEP 0.1
#define LS_REFINE_STEP_MIN 1e-7
#define LS_REFINE_MAX 200
#define LS_SAMPLED_BOUND_MARGIN 1e-3
#define LS_CLOSED_BOUND_MARGIN 1e-6
/* The combination search of a wrench on the exact surface against contact
 * rows: it stops where its model predicts a decrease below LS_COMB_PREDICTED
 * of the gauge or the step (at most LS_COMB_HALVINGS halvings) gains less
 * than LS_COMB_DECREASE of it. */
#define LS_COMB_PREDICTED 1e-13
#define LS_COMB_HALVINGS 30
#define LS_COMB_DECREASE 1e-14

#endif
