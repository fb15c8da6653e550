/* sim_run.c -- see sim_run.h. */
#include "sim_run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void sim_run_free(sim_run *r)
{
    free(r->tr.t);
    free(r->tr.q);
    free(r->tr.v);
    free(r->tr.wrench);
    free(r->tr.stick);
    free(r->tr.stop_force);
    memset(r, 0, sizeof *r);
}

int sim_run_def(const exdex_scene_def *def, double t_end, double dt, sim_run *r)
{
    const char *bad = NULL;
    int status;
    exdex_model *m = exdex_model_alloc(def, &status, &bad);
    size_t n = exdex_n_samples(t_end, dt);
    memset(r, 0, sizeof *r);
    if (!m) return r->status = status;
    r->ndof = exdex_model_ndof(m);
    r->nstops = exdex_model_nstops(m);
    r->tr.n = n;
    r->tr.t = calloc(n, sizeof(double));
    r->tr.q = calloc(n * 3, sizeof(double));
    r->tr.v = calloc(n * 3, sizeof(double));
    r->tr.wrench = calloc(n * 3, sizeof(double));
    r->tr.stick = calloc(n, 1);
    r->tr.stop_force = calloc(n * (r->nstops + 1), sizeof(double));
    r->status = exdex_simulate(m, t_end, dt, &r->tr, &r->st);
    exdex_model_free(m);
    return r->status;
}

exdex_scene_def scene_vertical(double mass, double ratio)
{
    exdex_scene_def d = exdex_default_scene_def();
    d.mass = mass;
    d.mu = 0.5;
    d.fingers = 2;
    d.grip_force = ratio * mass * 9.81 / (2 * d.mu);
    d.gravity[2] = -9.81;
    return d;
}

static void motion_line(exdex_scene_def *d, int kind, int rotation, double ax, double ay, double az,
                        double amplitude, double duration)
{
    d->motion.kind = kind;
    d->motion.rotation = rotation;
    d->motion.axis[0] = ax;
    d->motion.axis[1] = ay;
    d->motion.axis[2] = az;
    d->motion.amplitude = amplitude;
    d->motion.duration = duration;
}

void scene_eq7(exdex_scene_def *d, int rotation, double ax, double ay, double az, double amplitude, double duration,
               double beta)
{
    motion_line(d, EXDEX_MOTION_ASYMMETRIC, rotation, ax, ay, az, amplitude, duration);
    d->motion.beta = beta;
}

void scene_trapezoid(exdex_scene_def *d, int rotation, double ax, double ay, double az, double amplitude,
                     double duration, double v_max)
{
    motion_line(d, EXDEX_MOTION_TRAPEZOID, rotation, ax, ay, az, amplitude, duration);
    d->motion.v_max = v_max;
}

void scene_rect(exdex_scene_def *d, double hx, double hy)
{
    double v[4][2] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
    d->n_vertices = 4;
    memcpy(d->vertices, v, sizeof v);
}

void scene_stop(exdex_scene_def *d, int k, double px, double py, double pz, double nx, double ny, double nz)
{
    d->stop_point[k][0] = px;
    d->stop_point[k][1] = py;
    d->stop_point[k][2] = pz;
    d->stop_normal[k][0] = nx;
    d->stop_normal[k][1] = ny;
    d->stop_normal[k][2] = nz;
    if (d->n_stops < k + 1) d->n_stops = k + 1;
}

/* Closed form of the 1-DoF vertical problem under piecewise-constant gripper
 * acceleration (up positive), written independently of the core: exact
 * propagation with analytic stick/slip switching. */
double vertical_closed_form(double g, double cap_acc, const double *t_sw, const double *acc, int n_phase,
                            double *t_stick)
{
    double x = 0.0, v = 0.0;
    if (t_stick) *t_stick = NAN;
    for (int k = 0; k < n_phase; k++) {
        double t = t_sw[k], t_end = t_sw[k + 1];
        double need = g + acc[k]; /* acceleration friction must supply to stick */
        while (t < t_end) {
            if (v == 0.0) {
                if (fabs(need) <= cap_acc) break; /* sticks for the rest of the phase */
                {
                    double a = -need + copysign(cap_acc, need), dt = t_end - t;
                    x += 0.5 * a * dt * dt;
                    v += a * dt;
                    t = t_end;
                }
            } else {
                double a = -need - copysign(cap_acc, v), dt = t_end - t;
                double t_stop = (a * v < 0) ? -v / a : INFINITY;
                if (t_stop < dt) {
                    x += v * t_stop + 0.5 * a * t_stop * t_stop;
                    v = 0.0;
                    t += t_stop;
                    if (t_stick) *t_stick = t;
                } else {
                    x += v * dt + 0.5 * a * dt * dt;
                    v += a * dt;
                    t = t_end;
                }
            }
        }
    }
    return x;
}
