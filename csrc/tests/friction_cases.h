/* friction_cases.h -- the random friction-step problems shared by the C test
 * (csrc/tests/test_plate_friction.c) and the solver benchmark
 * (benchmarks/bench_friction.c): SPD W with condition numbers up to 1e6,
 * e = (1, 1, e_r), e_r in [1e-3, 1], 60% generic (stick or slip), 40% within
 * 1e-3..1e-9 of the stick/slip boundary (`near`). Header-only (static
 * functions); the includer provides <math.h>, <string.h> and GSL's linalg,
 * randist and rng headers. */
#ifndef EXDEX_FRICTION_CASES_H
#define EXDEX_FRICTION_CASES_H

static double fc_norm3(const double v[3]) { return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/* |E^-1 p| */
static double fc_ell_norm(const double p[3], const double e[3])
{
    double n = 0.0;
    for (int i = 0; i < 3; i++) n += (p[i] / e[i]) * (p[i] / e[i]);
    return sqrt(n);
}

static void matvec(double r[3], const double W[9], const double v[3])
{
    for (int i = 0; i < 3; i++) r[i] = W[3 * i] * v[0] + W[3 * i + 1] * v[1] + W[3 * i + 2] * v[2];
}

/* x = W^-1 v by GSL LU with partial pivoting (independent of plate_friction.c). */
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

typedef struct rcase { double W[9], e[3], b[3], cap, cond; int near; } rcase;

static void random_case(gsl_rng *rng, int k, rcase *c)
{
    double R[9] = {0}, d[3], q[4], n = 0.0, scale, kap;
    scale = pow(10.0, gsl_ran_flat(rng, -2.0, 2.0));
    kap = pow(10.0, gsl_ran_flat(rng, 0.0, 6.0));
    d[0] = scale;
    d[1] = scale * pow(kap, gsl_rng_uniform(rng));
    d[2] = scale * kap;
    c->cond = kap;
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
    c->near = (k % 10) >= 6;
    if (c->near) {
        double y[3], m = pow(10.0, gsl_ran_flat(rng, -2.0, 2.0)), p_st[3];
        int kk = 3 + (int)gsl_rng_uniform_int(rng, 7);
        double sg = gsl_rng_uniform(rng) < 0.5 ? -1.0 : 1.0;
        for (int i = 0; i < 3; i++) y[i] = gsl_ran_gaussian(rng, 1.0);
        n = fc_norm3(y);
        for (int i = 0; i < 3; i++) p_st[i] = c->e[i] * y[i] / n * m;
        matvec(c->b, c->W, p_st);
        for (int i = 0; i < 3; i++) c->b[i] = -c->b[i];
        c->cap = m / (1.0 + sg * pow(10.0, -kk));
    } else {
        double m = pow(10.0, gsl_ran_flat(rng, -2.0, 2.0)), p_st[3];
        for (int i = 0; i < 3; i++) c->b[i] = m * gsl_ran_gaussian(rng, 1.0);
        lu_solve(p_st, c->W, c->b);
        c->cap = fc_ell_norm(p_st, c->e) * pow(10.0, gsl_ran_flat(rng, -2.0, 1.0));
    }
}

#endif
