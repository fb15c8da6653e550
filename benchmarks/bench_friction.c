/* bench_friction.c -- nanoseconds per friction solve (csrc/plate_friction.c) for the
 * SCALAR, BRENT and MULTIROOT solvers, and per exdex_friction_prepare.
 *
 * Build and run by hand from the repository root:
 *
 *   cc -O2 -std=c99 -D_POSIX_C_SOURCE=200809L -Icsrc $(gsl-config --cflags) \
 *      benchmarks/bench_friction.c csrc/plate_friction.c csrc/status.c \
 *      $(gsl-config --libs) -lm -o bench_friction && ./bench_friction
 *
 * Cases: the random set of the C test (csrc/tests/friction_cases.h, seed
 * 20240611): SPD W with condition numbers up to 1e6,
 * e = (1, 1, e_r), e_r in [1e-3, 1], 60% generic (stick or slip), 40% within
 * 1e-3..1e-9 of the stick/slip boundary. Each solver runs over all cases
 * (and, separately, over the sliding ones only: the stick test alone is the
 * same for all three), 9 runs, and the median time per solve is printed
 * together with the fastest and slowest run. The workspace is allocated
 * once; nothing is allocated in the timed loops.
 */
#include "exdex.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <gsl/gsl_linalg.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>

#include "tests/friction_cases.h"

#define N_CASES 12000
#define RUNS 9

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static volatile double sink;

/* ns per solve over the cases idx[0..n), median/min/max of RUNS runs */
static void time_solver(const char *name, int solver, const exdex_friction_prep *prep,
                        const rcase *cases, const int *idx, int n, exdex_friction_ws *ws)
{
    double t[RUNS];
    long iters = 0;
    for (int r = 0; r < RUNS; r++) {
        double t0 = now(), acc = 0.0;
        for (int k = 0; k < n; k++) {
            exdex_friction_result res;
            const rcase *c = &cases[idx[k]];
            exdex_friction_solve(&prep[idx[k]], c->b, c->cap, solver, ws, NULL, &res);
            acc += res.p[0];
            if (r == 0) iters += res.iterations;
        }
        t[r] = (now() - t0) / n * 1e9;
        sink = acc;
    }
    qsort(t, RUNS, sizeof t[0], cmp_double);
    printf("  %-10s %8.1f ns/solve (min %.1f, max %.1f), %.2f iterations/solve\n", name,
           t[RUNS / 2], t[0], t[RUNS - 1], (double)iters / n);
}

int main(void)
{
    static rcase cases[N_CASES];
    static exdex_friction_prep prep[N_CASES];
    static int all[N_CASES], slip[N_CASES];
    int n_slip = 0;
    double tp[RUNS];
    gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
    exdex_friction_ws *ws = exdex_friction_ws_alloc();

    exdex_init();
    gsl_rng_set(rng, 20240611UL);
    for (int k = 0; k < N_CASES; k++) {
        exdex_friction_result res;
        random_case(rng, k, &cases[k]);
        if (exdex_friction_prepare(&prep[k], cases[k].W, cases[k].e) != EXDEX_OK) {
            fprintf(stderr, "prepare failed on case %d\n", k);
            return 1;
        }
        all[k] = k;
        exdex_friction_solve(&prep[k], cases[k].b, cases[k].cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &res);
        if (!res.stick) slip[n_slip++] = k;
    }
    for (int r = 0; r < RUNS; r++) {
        double t0 = now();
        for (int k = 0; k < N_CASES; k++) exdex_friction_prepare(&prep[k], cases[k].W, cases[k].e);
        tp[r] = (now() - t0) / N_CASES * 1e9;
    }
    qsort(tp, RUNS, sizeof tp[0], cmp_double);
    printf("friction benchmark: %d random cases (%d sliding), median of %d runs\n", N_CASES, n_slip,
           RUNS);
    printf("  prepare    %8.1f ns/call (min %.1f, max %.1f)\n", tp[RUNS / 2], tp[0], tp[RUNS - 1]);
    printf("all cases (stick and slip):\n");
    time_solver("SCALAR", EXDEX_SOLVER_SCALAR, prep, cases, all, N_CASES, ws);
    time_solver("BRENT", EXDEX_SOLVER_BRENT, prep, cases, all, N_CASES, ws);
    time_solver("MULTIROOT", EXDEX_SOLVER_MULTIROOT, prep, cases, all, N_CASES, ws);
    printf("sliding cases only:\n");
    time_solver("SCALAR", EXDEX_SOLVER_SCALAR, prep, cases, slip, n_slip, ws);
    time_solver("BRENT", EXDEX_SOLVER_BRENT, prep, cases, slip, n_slip, ws);
    time_solver("MULTIROOT", EXDEX_SOLVER_MULTIROOT, prep, cases, slip, n_slip, ws);
    exdex_friction_ws_free(ws);
    gsl_rng_free(rng);
    return 0;
}
