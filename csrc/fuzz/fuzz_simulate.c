/* fuzz_simulate.c -- exdex_scene_check, exdex_model_alloc and a short
 * exdex_simulate (<= 40 steps; one output interval for the adaptive event
 * and regularised methods) on fuzzed scene definitions: every method, every dof, every
 * motion kind, 0-3 stops placed just outside the object's initial outline,
 * 0-2 convex obstacles (boxes, rods) near it, all friction solvers.
 *
 * Checks: a non-finite value in a validated field gives EXDEX_EINVAL with
 * bad_param set; a scene is rejected as bad input (EXDEX_EINVAL) by both
 * exdex_scene_check and exdex_model_alloc or by neither, with the same bad_param;
 * exdex_simulate rejects a wrong trajectory size or missing arrays with
 * EXDEX_EINVAL; EXDEX_OK gives finite t, q, v, wrench, stop_force >= 0, stick
 * in {0, 1}, stats.steps = n - 1, t[n-1] = t_end; the same model run twice
 * gives bit-identical trajectories (unless the first run spent its budget,
 * EXDEX_ENOCONV, or was a long adaptive one); a 1-DoF run certified as it
 * goes (exdex_simulate_certified) finds the whole run's certificate and
 * repeats its samples up to the failure. The smallest stop gap is recorded (the
 * driver prints the most negative one seen), and tame runs that penetrate a
 * stop beyond the method's bound (penetration_bound) without a warning are
 * noted by method and dof ("silent stop penetration beyond the bound"). */
#include "fuzz.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define T "simulate"
#define MAX_STEPS 40

/* note keys of tame runs that penetrate a stop beyond the method's bound
 * (penetration_bound) without a warning, by method (exdex.h enum
 * exdex_method) and dof */
static const char *const silent_key[4][3] = {
    {"silent stop penetration beyond the bound: implicit, translation", "silent stop penetration beyond the bound: implicit, rotation",
     "silent stop penetration beyond the bound: implicit, planar"},
    {"silent stop penetration beyond the bound: event, translation", "silent stop penetration beyond the bound: event, rotation",
     "silent stop penetration beyond the bound: event, planar"},
    {"silent stop penetration beyond the bound: regularised, translation", "silent stop penetration beyond the bound: regularised, rotation",
     "silent stop penetration beyond the bound: regularised, planar"},
    {"silent stop penetration beyond the bound: explicit, translation", "silent stop penetration beyond the bound: explicit, rotation",
     "silent stop penetration beyond the bound: explicit, planar"}};


typedef struct traj {
    exdex_trajectory tr;
    double *buf;
} traj;

static int traj_alloc(traj *t, size_t n, int ndof, int nstops)
{
    size_t per = 1 + 2 * (size_t)ndof + 3 + (size_t)nstops;
    memset(t, 0, sizeof *t);
    t->buf = calloc(n * per, sizeof(double));
    t->tr.stick = calloc(n, 1);
    if (!t->buf || !t->tr.stick) {
        free(t->buf);
        free(t->tr.stick);
        return 0;
    }
    t->tr.n = n;
    t->tr.t = t->buf;
    t->tr.q = t->tr.t + n;
    t->tr.v = t->tr.q + n * (size_t)ndof;
    t->tr.wrench = t->tr.v + n * (size_t)ndof;
    t->tr.stop_force = nstops ? t->tr.wrench + 3 * n : NULL;
    return 1;
}

static void traj_free(traj *t)
{
    free(t->buf);
    free(t->tr.stick);
}

/* The penetration a method may leave at a sample without a warning: 1e-9 m
 * (rounding and located events), and for the explicit method also the
 * curvature of a rotating vertex's path over one step: its rows are linear
 * in v+ while the vertex moves on a circle of radius r, so gap(q + h v+) >=
 * gap(q) + h G v+ - 1/2 h^2 thd^2 r (r the vertex's distance from the
 * rotation centre: the centre of mass for planar scenes, the pivot (the
 * centre of pressure) for rotation; thd the output velocity v+); planar
 * with obstacles also the cross term of a section vertex against an edge. */
static double penetration_bound(const exdex_scene_def *d, const exdex_trajectory *tr)
{
    double hmax = 0.0, wmax = 0.0, rmax = 0.0;
    int nv = d->n_vertices > 0 ? d->n_vertices : 1, nd = d->dof == EXDEX_DOF_PLANAR ? 3 : 1;
    if (d->method != EXDEX_METHOD_EXPLICIT || d->dof == EXDEX_DOF_TRANSLATION) return 1e-9;
    for (size_t i = 1; i < tr->n; i++) hmax = fmax(hmax, tr->t[i] - tr->t[i - 1]);
    for (size_t i = 0; i < tr->n; i++) wmax = fmax(wmax, fabs(tr->v[i * (size_t)nd + (size_t)nd - 1]));
    for (int j = 0; j < nv; j++) {
        double x = d->n_vertices > 0 ? d->vertices[j][0] : 0.0, y = d->n_vertices > 0 ? d->vertices[j][1] : 0.0;
        if (d->disc_radius > 0.0) {
            /* a disc: its centre's path (the gap is the centre's less a constant in theta) */
            x = d->disc_center[0];
            y = d->disc_center[1];
        }
        if (d->dof == EXDEX_DOF_ROTATION) {
            x -= d->patch_center[0];
            y -= d->patch_center[1];
        }
        rmax = fmax(rmax, sqrt(x * x + y * y));
    }
    if (nd == 3 && d->n_obstacles > 0) {
        /* an obstacle's section vertex against an object edge (the bound
         * derived in explicit.c): 1/2 h^2 thd^2 (r + h |v|) + h^2 |thd| |v|,
         * v the centre of mass's velocity in v+ */
        double pmax = 0.0;
        for (size_t i = 1; i < tr->n; i++) {
            const double *vi = tr->v + i * 3;
            double h = tr->t[i] - tr->t[i - 1], w = fabs(vi[2]), sp = hypot(vi[0], vi[1]);
            pmax = fmax(pmax, 0.5 * h * h * w * w * (rmax + h * sp) + h * h * w * sp);
        }
        return 1e-9 + pmax * (1.0 + 1e-9);
    }
    return 1e-9 + 0.5 * hmax * hmax * wmax * wmax * rmax * (1.0 + 1e-9);
}

static void rot2(double out[2], double th, const double v[2])
{
    out[0] = cos(th) * v[0] - sin(th) * v[1];
    out[1] = sin(th) * v[0] + cos(th) * v[1];
}

int fuzz_simulate(const uint8_t *data, size_t size)
{
    fz f;
    fz_motion mm;
    exdex_scene_def d = exdex_default_scene_def();
    int imode, st_check, st_alloc = -1, required_nonfinite = 0, nv_dec, ns_dec, raw_normal[EXDEX_MAX_STOPS] = {0};
    double stop_gap[EXDEX_MAX_STOPS] = {0};
    const char *bad = NULL, *bad2 = NULL;
    exdex_model *m;
    double dt, t_end;
    size_t n;

    fz_init(&f, data, size);
    d.mass = fz_log(&f, 1e-3, 10.0);
    imode = fz_pick(&f, 0, 7);
    if (imode < 6) {
        /* R diag(I1, I2, I3) R^T */
        double q[4], R[9], Id[3];
        for (int i = 0; i < 3; i++) Id[i] = d.mass * fz_log(&f, 1e-5, 1e-2);
        for (int i = 0; i < 4; i++) q[i] = fz_num(&f, -1.0, 1.0);
        if (imode < 3) { q[0] = 1; q[1] = q[2] = 0; }
        if (q[0] == 0 && q[1] == 0 && q[2] == 0 && q[3] == 0) q[0] = 1;
        fz_quat_to_R(R, q);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double a = 0;
                for (int k = 0; k < 3; k++) a += R[3 * i + k] * Id[k] * R[3 * j + k];
                d.inertia[3 * i + j] = a;
            }
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < i; j++) d.inertia[3 * i + j] = d.inertia[3 * j + i];
    } else {
        for (int i = 0; i < 9; i++) d.inertia[i] = fz_num(&f, -1e-3, 1e-3);
    }
    d.n_vertices = fz_int(&f, 0, 6);
    nv_dec = d.n_vertices < 0 ? 0 : d.n_vertices > EXDEX_MAX_VERTICES ? EXDEX_MAX_VERTICES : d.n_vertices;
    for (int j = 0; j < nv_dec; j++) {
        d.vertices[j][0] = fz_num(&f, -0.05, 0.05);
        d.vertices[j][1] = fz_num(&f, -0.05, 0.05);
    }
    d.mu = fz_num(&f, 0.0, 1.5);
    d.grip_force = fz_pick(&f, 0, 15) == 0 ? 0.0 : fz_log(&f, 1e-3, 50.0);
    d.fingers = fz_int(&f, 1, 2);
    d.e_r = fz_log(&f, 1e-4, 0.05);
    d.patch_center[0] = fz_num(&f, -0.03, 0.03);
    d.patch_center[1] = fz_num(&f, -0.03, 0.03);
    for (int i = 0; i < 3; i++) d.gravity[i] = fz_num(&f, -12.0, 12.0);
    if (fz_pick(&f, 0, 1)) { d.gravity[0] = d.gravity[1] = 0; d.gravity[2] = -9.81; }
    d.dof = fz_int(&f, 1, 3);
    if (fz_pick(&f, 0, 15)) {
        double a = fz_num(&f, 0.0, 6.283185307179586);
        d.slide_axis[0] = cos(a);
        d.slide_axis[1] = sin(a);
    } else {
        d.slide_axis[0] = fz_num(&f, -1.0, 1.0);
        d.slide_axis[1] = fz_num(&f, -1.0, 1.0);
    }
    d.q0[0] = fz_num(&f, -0.05, 0.05);
    d.q0[1] = fz_num(&f, -0.05, 0.05);
    d.q0[2] = fz_num(&f, -3.2, 3.2);
    for (int i = 0; i < 3; i++) d.v0[i] = fz_pick(&f, 0, 1) ? 0.0 : fz_num(&f, -0.5, 0.5);
    fz_decode_motion(&f, &mm);
    d.motion = mm.def;
    if (mm.have_R0) memcpy(d.R0, mm.R0, sizeof d.R0);
    if (mm.have_p0) memcpy(d.p0, mm.p0, sizeof d.p0);
    d.n_stops = fz_int(&f, 0, 3);
    ns_dec = d.n_stops < 0 ? 0 : d.n_stops > EXDEX_MAX_STOPS ? EXDEX_MAX_STOPS : d.n_stops;
    for (int k = 0; k < ns_dec; k++) {
        double nrm[3], lo = INFINITY, gap, len;
        int nvv = nv_dec ? nv_dec : 1;
        if (fz_pick(&f, 0, 1)) {
            len = sqrt(d.gravity[0] * d.gravity[0] + d.gravity[1] * d.gravity[1] + d.gravity[2] * d.gravity[2]);
            for (int i = 0; i < 3; i++) nrm[i] = len > 0 ? -d.gravity[i] / len : (i == 2);
        } else {
            double a = fz_num(&f, 0.0, 6.283185307179586), z = fz_num(&f, -1.0, 1.0);
            double r = sqrt(fmax(0.0, 1 - z * z));
            nrm[0] = r * cos(a); nrm[1] = r * sin(a); nrm[2] = z;
        }
        /* point: just outside the lowest initial vertex along the normal */
        for (int j = 0; j < nvv; j++) {
            double vb[2] = {0, 0}, xb[3], xa[3];
            if (nv_dec) rot2(vb, d.q0[2], d.vertices[j]);
            xb[0] = d.q0[0] + vb[0]; xb[1] = d.q0[1] + vb[1]; xb[2] = 0;
            for (int i = 0; i < 3; i++)
                xa[i] = d.R0[3 * i] * xb[0] + d.R0[3 * i + 1] * xb[1] + d.R0[3 * i + 2] * xb[2] + d.p0[i];
            lo = fmin(lo, xa[0] * nrm[0] + xa[1] * nrm[1] + xa[2] * nrm[2]);
        }
        gap = fz_pick(&f, 0, 3) == 0 ? 0.0 : fz_num(&f, 0.0, 0.02);
        stop_gap[k] = gap;
        for (int i = 0; i < 3; i++) {
            d.stop_normal[k][i] = nrm[i];
            d.stop_point[k][i] = (lo - gap) * nrm[i];
        }
        if (fz_pick(&f, 0, 31) == 0) { /* occasionally a raw (wild) normal */
            for (int i = 0; i < 3; i++) d.stop_normal[k][i] = fz_num(&f, -1.0, 1.0);
            raw_normal[k] = 1;
        }
    }
    /* every method (each bounds its loops: EXDEX_ENOCONV past its step,
     * step-floor and event budgets), and invalid ids when wild */
    d.method = fz_int(&f, 0, 4);
    d.friction_solver = fz_int(&f, 0, 2);
    d.eps = fz_log(&f, 1e-6, 1e-2);
    d.rtol = fz_log(&f, 1e-10, 1e-4);
    d.atol = fz_log(&f, 1e-12, 1e-6);
    dt = fz_log(&f, 1e-4, 0.05);
    t_end = dt * (double)fz_int(&f, 1, MAX_STEPS) * fz_num(&f, 0.95, 1.05);
    /* the adaptive methods may spend their whole step budget (1e5 ODE steps,
     * hybrid.c) and event budget (1000 events of <= 200 Brent iterations)
     * in every output interval of a stiff scene: one output interval for
     * them (t_end = dt), to keep the time per input well below the driver's
     * timeout (FUZZ_TIMEOUT, also under ASan) */
    if ((d.method == EXDEX_METHOD_EVENT || d.method == EXDEX_METHOD_REGULARISED) && isfinite(t_end))
        t_end = dt;
    /* static coefficient (decoded last, so older corpus inputs keep their
     * meaning): 0 (equal to mu), above mu, or anything (below mu, wild) */
    switch (fz_pick(&f, 0, 3)) {
    case 0: d.mu_static = 0.0; break;
    case 1: d.mu_static = d.mu; break;
    case 2: d.mu_static = d.mu + fz_num(&f, 0.0, 1.5); break;
    default: d.mu_static = fz_num(&f, -0.5, 2.0);
    }
    /* 0-2 convex obstacles (decoded after the static coefficient, so inputs
     * without them keep their meaning): a box turned at random or a rod along a random axis,
     * placed at a random distance from the object's initial centre in A,
     * occasionally with a wild field (the core rejects those by name) */
    d.n_obstacles = fz_pick(&f, 0, 2) == 0 ? fz_int(&f, 0, 2) : 0;
    for (int o = 0; o < d.n_obstacles && o < EXDEX_MAX_OBSTACLES; o++) {
        exdex_obstacle_def *ob = &d.obstacles[o];
        double c[3], xb[3] = {d.q0[0], d.q0[1], 0.0}, dist = fz_num(&f, 0.0, 0.2), dir[3], len;
        for (int i = 0; i < 3; i++) dir[i] = fz_num(&f, -1.0, 1.0);
        len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        for (int i = 0; i < 3; i++) {
            c[i] = d.R0[3 * i] * xb[0] + d.R0[3 * i + 1] * xb[1] + d.p0[i];
            c[i] += len > 0 ? dist * dir[i] / len : 0.0;
        }
        ob->kind = fz_pick(&f, 0, 1);
        if (ob->kind == EXDEX_OBSTACLE_POLYTOPE) {
            double q[4], Q[9], h[3];
            for (int i = 0; i < 4; i++) q[i] = fz_num(&f, -1.0, 1.0);
            if (q[0] == 0 && q[1] == 0 && q[2] == 0 && q[3] == 0) q[0] = 1;
            fz_quat_to_R(Q, q);
            for (int i = 0; i < 3; i++) h[i] = fz_log(&f, 1e-3, 0.2);
            ob->n_faces = fz_int(&f, 1, 6);
            for (int fc = 0; fc < ob->n_faces && fc < 6; fc++) {
                int i = fc / 2;
                double sg = fc % 2 ? -1.0 : 1.0;
                for (int k = 0; k < 3; k++) {
                    ob->face_normal[fc][k] = sg * Q[3 * k + i];
                    ob->face_point[fc][k] = c[k] + sg * h[i] * Q[3 * k + i];
                }
            }
        } else {
            double a = fz_num(&f, 0.0, 6.283185307179586), z = fz_num(&f, -1.0, 1.0), r = sqrt(fmax(0.0, 1 - z * z));
            ob->kind = EXDEX_OBSTACLE_CYLINDER;
            ob->axis[0] = r * cos(a);
            ob->axis[1] = r * sin(a);
            ob->axis[2] = z;
            memcpy(ob->center, c, sizeof c);
            ob->radius = fz_log(&f, 1e-3, 0.05);
        }
        if (fz_pick(&f, 0, 31) == 0) ob->radius = fz_num(&f, -1.0, 1.0); /* occasionally wild */
        ob->mu = fz_pick(&f, 0, 1) ? 0.0 : fz_num(&f, -0.1, 1.5);     /* friction, sometimes < 0 */
    }
    /* each stop's Coulomb coefficient, decoded after the obstacles so that
     * the inputs written before it decode as before (with frictionless stops): 0, or
     * reasonable in [0, 1.5], or wild (negative and non-finite values are
     * bad input; event and regularised reject mu > 0 by name) */
    for (int k = 0; k < ns_dec; k++) d.stop_mu[k] = fz_pick(&f, 0, 1) ? fz_num(&f, 0.0, 1.5) : 0.0;
    /* a disc outline (decoded last, and only for a selector of 1, so older
     * inputs keep their polygon): radius and centre in C, the polygon
     * dropped (kept with 1 in 8: bad input, "disc_radius"), and each stop
     * (but a raw normal) moved to its gap below the disc's support point */
    if (fz_pick(&f, 0, 3) == 1) {
        d.disc_radius = fz_log(&f, 1e-3, 0.05);
        d.disc_center[0] = fz_num(&f, -0.02, 0.02);
        d.disc_center[1] = fz_num(&f, -0.02, 0.02);
        if (fz_pick(&f, 0, 7) != 0) d.n_vertices = 0;
        for (int k = 0; k < ns_dec; k++) {
            double cb[2], xa[3], nb[2], lo;
            if (raw_normal[k]) continue;
            rot2(cb, d.q0[2], d.disc_center);
            cb[0] += d.q0[0];
            cb[1] += d.q0[1];
            for (int i = 0; i < 3; i++) xa[i] = d.R0[3 * i] * cb[0] + d.R0[3 * i + 1] * cb[1] + d.p0[i];
            for (int i = 0; i < 2; i++)
                nb[i] = d.R0[i] * d.stop_normal[k][0] + d.R0[3 + i] * d.stop_normal[k][1] +
                        d.R0[6 + i] * d.stop_normal[k][2];
            lo = xa[0] * d.stop_normal[k][0] + xa[1] * d.stop_normal[k][1] + xa[2] * d.stop_normal[k][2] -
                 d.disc_radius * hypot(nb[0], nb[1]);
            for (int i = 0; i < 3; i++) d.stop_point[k][i] = (lo - stop_gap[k]) * d.stop_normal[k][i];
        }
    }

    /* pads on the fingers (decoded last, only for a selector of 1, so older
     * inputs decode as before): a square or disc pad about a decoded point
     * of B near the object, and the face a box rectangle or a disc in C
     * (a region empty at the start is bad input, "pad") */
    if (fz_pick(&f, 0, 3) == 1) {
        double a = fz_log(&f, 1e-3, 0.03), cx = fz_num(&f, -0.02, 0.02), cy = fz_num(&f, -0.02, 0.02);
        if (fz_pick(&f, 0, 1)) {
            d.pad_radius = a;
            d.pad_center[0] = cx;
            d.pad_center[1] = cy;
        } else {
            d.pad_n = 4;
            d.pad[0][0] = cx - a, d.pad[0][1] = cy - a;
            d.pad[1][0] = cx + a, d.pad[1][1] = cy - a;
            d.pad[2][0] = cx + a, d.pad[2][1] = cy + a;
            d.pad[3][0] = cx - a, d.pad[3][1] = cy + a;
        }
        if (fz_pick(&f, 0, 1)) {
            d.face_radius = fz_log(&f, 1e-3, 0.05);
        } else {
            double hx = fz_log(&f, 1e-3, 0.05), hy = fz_log(&f, 1e-3, 0.05);
            d.face_n = 4;
            d.face[0][0] = -hx, d.face[0][1] = -hy;
            d.face[1][0] = hx, d.face[1][1] = -hy;
            d.face[2][0] = hx, d.face[2][1] = hy;
            d.face[3][0] = -hx, d.face[3][1] = hy;
        }
    }

    /* fields exdex_scene_check must validate */
    required_nonfinite = !isfinite(d.mass) || !fz_all_finite(d.inertia, 9) || !isfinite(d.mu) ||
                         !isfinite(d.grip_force) || !isfinite(d.e_r) || !fz_all_finite(d.patch_center, 2) ||
                         !fz_all_finite(d.gravity, 3) || !fz_all_finite(d.slide_axis, 2) ||
                         !fz_all_finite(d.q0, 3) || !fz_all_finite(d.v0, 3) || !fz_all_finite(d.p0, 3) ||
                         !isfinite(d.eps) || !isfinite(d.rtol) ||
                         !isfinite(d.atol) || !isfinite(d.mu_static) || !isfinite(d.disc_radius) ||
                         !fz_all_finite(d.disc_center, 2);
    if (d.n_vertices >= 0 && d.n_vertices <= EXDEX_MAX_VERTICES &&
        !fz_all_finite(&d.vertices[0][0], 2 * (size_t)d.n_vertices))
        required_nonfinite = 1;
    if (d.n_stops >= 0 && d.n_stops <= EXDEX_MAX_STOPS)
        for (int k = 0; k < d.n_stops; k++)
            if (!fz_all_finite(d.stop_point[k], 3) || !fz_all_finite(d.stop_normal[k], 3) ||
                !isfinite(d.stop_mu[k]))
                required_nonfinite = 1;
    for (int o = 0; o < d.n_obstacles && o < EXDEX_MAX_OBSTACLES; o++) {
        const exdex_obstacle_def *ob = &d.obstacles[o];
        if (ob->kind == EXDEX_OBSTACLE_CYLINDER &&
            (!fz_all_finite(ob->center, 3) || !fz_all_finite(ob->axis, 3) || !isfinite(ob->radius)))
            required_nonfinite = 1;
        if (!isfinite(ob->mu)) required_nonfinite = 1;
        if (ob->kind == EXDEX_OBSTACLE_POLYTOPE)
            for (int fc = 0; fc < ob->n_faces && fc < EXDEX_MAX_FACES; fc++)
                if (!fz_all_finite(ob->face_point[fc], 3) || !fz_all_finite(ob->face_normal[fc], 3))
                    required_nonfinite = 1;
    }
    /* pads: every decoded field of a pad and face in use */
    if (d.pad_n || d.pad_radius != 0.0)
        if (!isfinite(d.pad_radius) || !fz_all_finite(d.pad_center, 2) || !fz_all_finite(&d.pad[0][0], 8) ||
            !isfinite(d.face_radius) || !fz_all_finite(&d.face[0][0], 8))
            required_nonfinite = 1;

    if (fz_trace) {
        fprintf(stderr, "scene: mass %g I %g %g %g / %g %g %g / %g %g %g nv %d mu %g grip %g fingers %d e_r %g pc %g %g\n"
                "  g %g %g %g dof %d axis %g %g q0 %g %g %g v0 %g %g %g\n"
                "  R0 %g %g %g / %g %g %g / %g %g %g p0 %g %g %g motion kind %d rot %d amp %g T %g\n"
                "  n_stops %d method %d solver %d eps %g rtol %g atol %g t_end %.17g dt %.17g\n",
                d.mass, d.inertia[0], d.inertia[1], d.inertia[2], d.inertia[3], d.inertia[4], d.inertia[5],
                d.inertia[6], d.inertia[7], d.inertia[8], d.n_vertices, d.mu, d.grip_force, d.fingers, d.e_r,
                d.patch_center[0], d.patch_center[1], d.gravity[0], d.gravity[1], d.gravity[2], d.dof,
                d.slide_axis[0], d.slide_axis[1], d.q0[0], d.q0[1], d.q0[2], d.v0[0], d.v0[1], d.v0[2],
                d.R0[0], d.R0[1], d.R0[2], d.R0[3], d.R0[4], d.R0[5], d.R0[6], d.R0[7], d.R0[8], d.p0[0],
                d.p0[1], d.p0[2], d.motion.kind, d.motion.rotation, d.motion.amplitude, d.motion.duration,
                d.n_stops, d.method, d.friction_solver, d.eps, d.rtol, d.atol, t_end, dt);
        for (int k = 0; k < ns_dec; k++)
            fprintf(stderr, "  stop %d point %g %g %g normal %g %g %g mu %g\n", k, d.stop_point[k][0],
                    d.stop_point[k][1], d.stop_point[k][2], d.stop_normal[k][0], d.stop_normal[k][1],
                    d.stop_normal[k][2], d.stop_mu[k]);
        for (int j = 0; j < nv_dec; j++) fprintf(stderr, "  vertex %d %g %g\n", j, d.vertices[j][0], d.vertices[j][1]);
        if (d.disc_radius != 0.0)
            fprintf(stderr, "  disc radius %g centre %g %g\n", d.disc_radius, d.disc_center[0], d.disc_center[1]);
        for (int o = 0; o < d.n_obstacles && o < EXDEX_MAX_OBSTACLES; o++)
            fprintf(stderr, "  obstacle %d kind %d faces %d centre %g %g %g axis %g %g %g radius %g\n", o,
                    d.obstacles[o].kind, d.obstacles[o].n_faces, d.obstacles[o].center[0], d.obstacles[o].center[1],
                    d.obstacles[o].center[2], d.obstacles[o].axis[0], d.obstacles[o].axis[1], d.obstacles[o].axis[2],
                    d.obstacles[o].radius);
    }
    st_check = exdex_scene_check(&d, &bad);
    FZ_CHECK(T, st_check == EXDEX_OK || st_check == EXDEX_EINVAL || st_check == EXDEX_ENOMEM);
    if (st_check) FZ_CHECK(T, bad != NULL);
    /* a static coefficient below mu (and not 0) is bad input */
    if (isfinite(d.mu) && d.mu >= 0 && isfinite(d.mu_static) && d.mu_static != 0.0 && d.mu_static < d.mu)
        FZ_CHECK(T, st_check == EXDEX_EINVAL);
    FZ_CHECK(T, exdex_scene_check(NULL, NULL) == EXDEX_EINVAL);
    m = exdex_model_alloc(&d, &st_alloc, &bad2);
    fuzz_count_status(T, st_alloc);
    if (required_nonfinite) FZ_CHECK(T, st_check == EXDEX_EINVAL && m == NULL && st_alloc == EXDEX_EINVAL);
    /* R0 and the motion: rejected by both */
    if (mm.used_nonfinite || !fz_all_finite(d.R0, 9))
        FZ_CHECK(T, st_check == EXDEX_EINVAL && m == NULL && st_alloc == EXDEX_EINVAL);
    /* the check rejects exactly what model_alloc rejects as bad input, with the same name */
    if (st_check == EXDEX_EINVAL || st_alloc == EXDEX_EINVAL)
        FZ_CHECK(T, st_check == EXDEX_EINVAL && m == NULL && st_alloc == EXDEX_EINVAL && bad && bad2 &&
                        strcmp(bad, bad2) == 0);
    if (!m) {
        FZ_CHECK(T, st_alloc == EXDEX_EINVAL || st_alloc == EXDEX_ENOMEM || st_alloc == EXDEX_ENONFINITE);
        if (st_alloc == EXDEX_ENONFINITE) fuzz_note_count(T, "model_alloc ENONFINITE (initial state overflows)");
        if (st_alloc == EXDEX_EINVAL) FZ_CHECK(T, bad2 != NULL);
    } else {
        FZ_CHECK(T, st_alloc == EXDEX_OK);
    }
    FZ_CHECK(T, exdex_model_ndof(NULL) == 0 && exdex_model_nstops(NULL) == 0);
    exdex_model_free(NULL);

    n = exdex_n_samples(t_end, dt);
    if (m) {
        int ndof = exdex_model_ndof(m), nstops = exdex_model_nstops(m), st;
        traj a, b;
        exdex_stats sa, sb;
        FZ_CHECK(T, ndof == (d.dof == EXDEX_DOF_PLANAR ? 3 : 1) && nstops == d.n_stops + d.n_obstacles);
        FZ_CHECK(T, exdex_simulate(m, t_end, dt, NULL, NULL) == EXDEX_EINVAL);
        if (n == 0 || n > MAX_STEPS * 2 + 2) {
            /* invalid (t_end, dt) or more steps than this harness runs */
            if (n == 0 && traj_alloc(&a, 4, ndof, nstops)) {
                FZ_CHECK(T, exdex_simulate(m, t_end, dt, &a.tr, &sa) == EXDEX_EINVAL);
                traj_free(&a);
            }
        } else if (traj_alloc(&a, n, ndof, nstops)) {
            /* wrong size and missing arrays are rejected */
            a.tr.n = n + 1;
            FZ_CHECK(T, exdex_simulate(m, t_end, dt, &a.tr, &sa) == EXDEX_EINVAL);
            a.tr.n = n;
            if (nstops) {
                double *keep = a.tr.stop_force;
                a.tr.stop_force = NULL;
                FZ_CHECK(T, exdex_simulate(m, t_end, dt, &a.tr, &sa) == EXDEX_EINVAL);
                a.tr.stop_force = keep;
            }
            st = exdex_simulate(m, t_end, dt, &a.tr, &sa);
            fuzz_count_status(T, st);
            FZ_CHECK(T, st >= EXDEX_OK && st <= EXDEX_ENONFINITE);
            /* EINVAL is for arguments; the model and trajectory are valid */
            FZ_EXTREME(T, &f, st != EXDEX_EINVAL && st != EXDEX_ENOMEM);
            if (st == EXDEX_OK) {
                /* pads: a lost grasp ends the run at sample lost_sample (nw samples written) */
                size_t nw = sa.lost_sample ? sa.lost_sample + 1 : n;
                FZ_CHECK(T, sa.lost_sample < n && (sa.lost_sample == 0) == isnan(sa.lost_t));
                FZ_CHECK(T, sa.lost_sample == 0 || d.pad_n > 0 || d.pad_radius > 0.0);
                if (sa.lost_sample) {
                    fuzz_note_count(T, "runs OK that lost the grasp");
                    FZ_CHECK(T, sa.lost_t == a.tr.t[sa.lost_sample]);
                }
                fuzz_note_count(T, "runs OK");
                FZ_EXTREME(T, &f, fz_all_finite(a.tr.t, nw) && fz_all_finite(a.tr.q, nw * (size_t)ndof) &&
                                      fz_all_finite(a.tr.v, nw * (size_t)ndof) &&
                                      fz_all_finite(a.tr.wrench, 3 * nw));
                /* the fixed-step methods take exactly one step per sample,
                 * and the analytic method counts one per sample */
                if (d.method == EXDEX_METHOD_IMPLICIT || d.method == EXDEX_METHOD_EXPLICIT ||
                    d.method == EXDEX_METHOD_ANALYTIC)
                    FZ_CHECK(T, sa.steps == nw - 1);
                FZ_CHECK(T, sa.stick_steps <= sa.steps);
                FZ_CHECK(T, a.tr.t[0] == 0.0 && (sa.lost_sample || a.tr.t[n - 1] == t_end));
                for (size_t i = 1; i < nw; i++) FZ_CHECK(T, a.tr.t[i] > a.tr.t[i - 1]);
                for (size_t i = 0; i < nw; i++) FZ_CHECK(T, a.tr.stick[i] <= 1);
                for (size_t i = 0; i < nw * (size_t)nstops; i++)
                    FZ_EXTREME(T, &f, isfinite(a.tr.stop_force[i]) && a.tr.stop_force[i] >= 0.0);
                if (nstops) {
                    FZ_CHECK(T, !isnan(sa.min_gap));
                    if (f.wild == 0) {
                        fuzz_note_count(T, "tame runs OK with stops");
                        if (d.n_obstacles) {
                            fuzz_note_count(T, "tame runs OK with obstacles");
                            fuzz_note_min(T, "min gap of tame runs with obstacles [m]", sa.min_gap);
                            if (sa.min_gap < -1e-9)
                                fuzz_note_keep(T, sa.warnings ? "tame obstacle runs with a gap < -1e-9 m, with warnings"
                                                              : "tame obstacle runs with a gap < -1e-9 m, no warning");
                        }
                        fuzz_note_min(T, "min stop gap of tame runs [m]", sa.min_gap);
                        if (sa.warnings) fuzz_note_count(T, "tame runs with stop warnings");
                        if (sa.min_gap < -1e-9) {
                            fuzz_note_keep(T, sa.warnings ? "tame runs with a stop gap < -1e-9 m, with warnings"
                                                           : "tame runs with a stop gap < -1e-9 m, no warning");
                        }
                        /* the silent ones beyond the method's bound, by method and dof
                         * (a reproducer per class) */
                        if (!sa.warnings && d.method >= 0 && d.method <= 3 && d.dof >= 1 && d.dof <= 3 &&
                            sa.min_gap < -penetration_bound(&d, &a.tr))
                            fuzz_note_keep(T, silent_key[d.method][d.dof - 1]);
                        if (!sa.warnings) fuzz_note_min(T, "min stop gap of tame runs without warnings [m]", sa.min_gap);
                    }
                }
            }
            /* determinism: the same model again, bit for bit (not after
             * EXDEX_ENOCONV or an adaptive run that used more than 10^4
             * steps and Brent iterations: the slowest runs there are, and
             * twice would double the time per input) */
            if (st != EXDEX_ENOCONV &&
                !((d.method == EXDEX_METHOD_EVENT || d.method == EXDEX_METHOD_REGULARISED) &&
                  sa.steps + sa.solver_iterations > 10000) &&
                traj_alloc(&b, n, ndof, nstops)) {
                int st2 = exdex_simulate(m, t_end, dt, &b.tr, &sb);
                FZ_CHECK(T, st2 == st);
                if (st == EXDEX_OK && st2 == EXDEX_OK) {
                    size_t per = 1 + 2 * (size_t)ndof + 3 + (size_t)nstops;
                    FZ_CHECK(T, memcmp(a.buf, b.buf, n * per * sizeof(double)) == 0);
                    FZ_CHECK(T, memcmp(a.tr.stick, b.tr.stick, n) == 0);
                    FZ_CHECK(T, memcmp(&sa, &sb, sizeof sa) == 0);
                }
                traj_free(&b);
            }
            /* certified as it goes: the whole run's certificate, and its samples
             * (all of them where the reduction holds, those before the failure where it fails) */
            if (st == EXDEX_OK && ndof == 1 && traj_alloc(&b, n, ndof, nstops)) {
                exdex_trajectory part = a.tr;
                exdex_certificate ca, cb;
                size_t nw = 0, keep;
                part.n = sa.lost_sample ? sa.lost_sample + 1 : n;
                if (exdex_certify(m, &part, &ca) == EXDEX_OK) {
                    int st3 = exdex_simulate_certified(m, t_end, dt, &b.tr, &sb, &cb, &nw);
                    FZ_CHECK(T, st3 == EXDEX_OK);
                    if (st3 == EXDEX_OK) {
                        keep = ca.holds ? part.n : ca.first_bad ? ca.first_bad : 1;
                        fuzz_note_count(T, ca.holds ? "certified as it goes: held" : "certified as it goes: failed");
                        FZ_CHECK(T, cb.holds == ca.holds && cb.first_bad == ca.first_bad && cb.stick == ca.stick);
                        FZ_CHECK(T, nw == keep || (!ca.holds && nw == keep + 1));
                        FZ_CHECK(T, b.tr.t[nw - 1] == cb.valid_until);
                        FZ_CHECK(T, cb.valid_until == ca.valid_until || (!ca.holds && nw == keep));
                        FZ_CHECK(T, memcmp(a.tr.t, b.tr.t, keep * sizeof(double)) == 0);
                        FZ_CHECK(T, memcmp(a.tr.q, b.tr.q, keep * sizeof(double)) == 0);
                        FZ_CHECK(T, memcmp(a.tr.v, b.tr.v, keep * sizeof(double)) == 0);
                        FZ_CHECK(T, memcmp(a.tr.stick, b.tr.stick, keep) == 0);
                        if (ca.holds) FZ_CHECK(T, memcmp(&sa, &sb, sizeof sa) == 0);
                    }
                }
                traj_free(&b);
            }
            traj_free(&a);
        }
    }
    exdex_model_free(m);
    return 0;
}
