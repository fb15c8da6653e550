/* sim_run.h -- test helpers shared by the C test files: run a scene
 * definition through the public API into freshly allocated trajectory
 * arrays, and build the scene definitions the files have in common. */
#ifndef EXDEX_TEST_SIM_RUN_H
#define EXDEX_TEST_SIM_RUN_H

#include "../exdex.h"

typedef struct sim_run {
    exdex_trajectory tr;
    exdex_stats st;
    int ndof, nstops, status;
} sim_run;

/* Simulate def from 0 to t_end with step dt; returns the status (also in
 * r->status). The arrays are allocated even when the run fails. */
int sim_run_def(const exdex_scene_def *def, double t_end, double dt, sim_run *r);
void sim_run_free(sim_run *r);

/* Closed form of the 1-DoF vertical problem (gravity g down, up positive)
 * under the piecewise-constant gripper accelerations acc[k] on
 * [t_sw[k], t_sw[k + 1]), friction capacity cap_acc per unit mass: the
 * final displacement; *t_stick (may be NULL) the last slip -> stick time
 * (NaN if none). Written independently of the core. */
double vertical_closed_form(double g, double cap_acc, const double *t_sw, const double *acc, int n_phase,
                            double *t_stick);

/* Scene builders. scene_vertical returns a 1-DoF vertical scene (B y up,
 * default pose), gripper at rest, gravity 9.81 m/s^2 down A z, mu 0.5 on
 * two fingers, friction capacity ratio x m g. The others set the fields
 * they name and leave the rest of d as it is:
 *   scene_eq7        the motion: Eq. 7 (asymmetric) along (rotation 0) or
 *                    about (rotation 1) the axis (ax, ay, az), amplitude,
 *                    duration, ratio beta;
 *   scene_trapezoid  the same for the trapezoid of peak speed v_max;
 *   scene_rect       the outline (-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy);
 *   scene_stop       stop k's point p and normal n (A), n_stops at least
 *                    k + 1. */
exdex_scene_def scene_vertical(double mass, double ratio);
void scene_eq7(exdex_scene_def *d, int rotation, double ax, double ay, double az, double amplitude, double duration,
               double beta);
void scene_trapezoid(exdex_scene_def *d, int rotation, double ax, double ay, double az, double amplitude,
                     double duration, double v_max);
void scene_rect(exdex_scene_def *d, double hx, double hy);
void scene_stop(exdex_scene_def *d, int k, double px, double py, double pz, double nx, double ny, double nz);

#endif
