/* sim_run.h -- test helper: run a scene definition through the public API
 * into freshly allocated trajectory arrays (shared by the C test files). */
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

#endif
