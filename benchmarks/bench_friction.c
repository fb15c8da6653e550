/* bench_friction.c -- nanoseconds per friction solve (csrc/friction.c) for the
 * SCALAR, BRENT and MULTIROOT solvers, and per exdex_friction_prepare.
 *
 * Build and run by hand from the repository root:
 *
 *   cc -O2 -std=c99 -D_POSIX_C_SOURCE=200809L -Icsrc $(gsl-config --cflags) \
 *      benchmarks/bench_friction.c csrc/friction.c csrc/status.c \
 *      $(gsl-config --libs) -lm -o bench_friction && ./bench_friction
 *
 * Cases: the random set of the C test (csrc/tests/test_friction.c, same
 * generator, seed 20240611): SPD W with condition numbers up to 1e6,
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

#define N_CASES 12000
#define RUNS 9

typedef struct rcase { double W[9], e[3], b[3], cap; } rcase;

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static void matvec(double r[3], const double W[9], const double v[3])
{
    for (int i = 0; i < 3; i++) r[i] = W[3 * i] * v[0] + W[3 * i + 1] * v[1] + W[3 * i + 2] * v[2];
}

static void lu_solve(double x[3], const double W[9], const double v[3])
{
    double A[9];
    size_t perm_d[3];
    gsl_permutation perm = {3, perm_d};
    int sign;
    memcpy(A, W, sizeof A);
    gsl_matrix_view Am = gsl_matrix_view_array(A, 3, 3);
    gsl_vector_const_view vv = gsl_vector_const_view_array(v, 3);
    gsl_vector_view xv = gsl_vector_view_array(x, 3);
    gsl_linalg_LU_decomp(&Am.matrix, &perm, &sign);
    gsl_linalg_LU_solve(&Am.matrix, &perm, &vv.vector, &xv.vector);
}

/* The generator of csrc/tests/test_friction.c (random_case). */
static void random_case(gsl_rng *rng, int k, rcase *c)
{
    double R[9] = {0}, d[3], q[4], n = 0.0, scale, kap;
    scale = pow(10.0, gsl_ran_flat(rng, -2.0, 2.0));
    kap = pow(10.0, gsl_ran_flat(rng, 0.0, 6.0));
    d[0] = scale;
    d[1] = scale * pow(kap, gsl_rng_uniform(rng));
    d[2] = scale * kap;
    if (k % 5 == 0) {
        int sh = (int)gsl_rng_uniform_int(rng, 3);
        for (int i = 0; i < 3; i++) R[3 * i + (i + sh) % 3] = 1.0;
    } else {
        for (int i = 0; i < 4; i++) {
            q[i] = gsl_ran_gaussian(rng, 1.0);
            n += q[i] * q[i];
        }
        n = sqrt(n);
        for (int i = 0; i < 4; i++) q[i] /= n;
        R[0] = 1 - 2 * (q[2] * q[2] + q[3] * q[3]);
        R[1] = 2 * (q[1] * q[2] - q[3] * q[0]);
        R[2] = 2 * (q[1] * q[3] + q[2] * q[0]);
        R[3] = 2 * (q[1] * q[2] + q[3] * q[0]);
        R[4] = 1 - 2 * (q[1] * q[1] + q[3] * q[3]);
        R[5] = 2 * (q[2] * q[3] - q[1] * q[0]);
        R[6] = 2 * (q[1] * q[3] - q[2] * q[0]);
        R[7] = 2 * (q[2] * q[3] + q[1] * q[0]);
        R[8] = 1 - 2 * (q[1] * q[1] + q[2] * q[2]);
    }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j <= i; j++) {
            double s = 0.0;
            for (int l = 0; l < 3; l++) s += R[3 * i + l] * d[l] * R[3 * j + l];
            c->W[3 * i + j] = c->W[3 * j + i] = s;
        }
    c->e[0] = c->e[1] = 1.0;
    c->e[2] = pow(10.0, gsl_ran_flat(rng, -3.0, 0.0));
    if ((k % 10) >= 6) {
        double y[3], m = pow(10.0, gsl_ran_flat(rng, -2.0, 2.0)), p_st[3];
        int kk = 3 + (int)gsl_rng_uniform_int(rng, 7);
        double sg = gsl_rng_uniform(rng) < 0.5 ? -1.0 : 1.0;
        for (int i = 0; i < 3; i++) y[i] = gsl_ran_gaussian(rng, 1.0);
        n = sqrt(y[0] * y[0] + y[1] * y[1] + y[2] * y[2]);
        for (int i = 0; i < 3; i++) p_st[i] = c->e[i] * y[i] / n * m;
        matvec(c->b, c->W, p_st);
        for (int i = 0; i < 3; i++) c->b[i] = -c->b[i];
        c->cap = m / (1.0 + sg * pow(10.0, -kk));
    } else {
        double m = pow(10.0, gsl_ran_flat(rng, -2.0, 2.0)), p_st[3], en = 0.0;
        for (int i = 0; i < 3; i++) c->b[i] = m * gsl_ran_gaussian(rng, 1.0);
        lu_solve(p_st, c->W, c->b);
        for (int i = 0; i < 3; i++) en += (p_st[i] / c->e[i]) * (p_st[i] / c->e[i]);
        c->cap = sqrt(en) * pow(10.0, gsl_ran_flat(rng, -2.0, 1.0));
    }
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
