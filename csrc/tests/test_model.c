/* test_model.c -- model.c: the checks of exdex_model_alloc (status and
 * field name) and the grip force (the centre-of-mass pose: test_pose.c). */
#include "check.h"
#include "sim_run.h"
#include "../model.h"

#include <math.h>
#include <string.h>

/* Each bad field alone: NULL, EXDEX_EINVAL, bad_param naming that field,
 * and exdex_scene_check says the same. */
EXDEX_TEST(model_alloc_rejects_each_bad_field_by_name)
{
    struct { const char *field; exdex_scene_def d; } cases[16];
    int n = 0;
    const exdex_scene_def good = scene_vertical(0.2, 2.0);
#define CASE(name, stmt) do { cases[n].field = name; cases[n].d = good; { exdex_scene_def *d = &cases[n].d; stmt; } n++; } while (0)
    CASE("mass", d->mass = 0.0);
    CASE("mass", d->mass = NAN);
    CASE("inertia", d->inertia[4] = INFINITY);
    CASE("mu", d->mu = -0.1);
    CASE("grip_force", d->grip_force = -1.0);
    CASE("fingers", d->fingers = 3);
    CASE("e_r", d->e_r = 0.0);
    CASE("gravity", d->gravity[1] = NAN);
    CASE("dof", d->dof = 4);
    CASE("slide_axis", (d->slide_axis[0] = 0.6, d->slide_axis[1] = 0.6));
    CASE("n_stops", d->n_stops = EXDEX_MAX_STOPS + 1);
    CASE("method", d->method = 7);
    CASE("eps", d->eps = 0.0);
    CASE("rtol", d->rtol = -1e-8);
    CASE("atol", d->atol = NAN);
#undef CASE
    for (int i = 0; i < n; i++) {
        int status = -1;
        const char *bad = NULL, *bad_check = NULL;
        exdex_model *m = exdex_model_alloc(&cases[i].d, &status, &bad);
        ENSURE(m == NULL);
        ENSURE(status == EXDEX_EINVAL);
        ENSURE(bad != NULL && strcmp(bad, cases[i].field) == 0);
        if (!(bad != NULL && strcmp(bad, cases[i].field) == 0))
            printf("    case %d: expected '%s', got '%s'\n", i, cases[i].field, bad ? bad : "(null)");
        ENSURE(exdex_scene_check(&cases[i].d, &bad_check) == EXDEX_EINVAL);
        ENSURE(bad_check != NULL && strcmp(bad_check, cases[i].field) == 0);
        exdex_model_free(m);
    }
    {
        int status = -1;
        const char *bad = NULL;
        ENSURE(exdex_model_alloc(NULL, &status, &bad) == NULL && status == EXDEX_EINVAL);
        ENSURE(bad != NULL && strcmp(bad, "scene") == 0);
        exdex_model *m = exdex_model_alloc(&good, &status, &bad);
        ENSURE(m != NULL && status == EXDEX_OK && exdex_model_ndof(m) == 1 && exdex_model_nstops(m) == 0);
        ENSURE(exdex_scene_check(&good, NULL) == EXDEX_OK);
        exdex_model_free(m);
        exdex_model_free(NULL);
    }
}

/* Constant grip: F = grip_force, rate 0; a linear schedule (0, 1) -> (1, 3)
 * scaled by 2: F(0.25) = 2 (1 + 2 0.25) = 3, rate 4, held after its end;
 * NULL model or NaN t: EXDEX_EINVAL. */
EXDEX_TEST(model_grip_constant_and_linear_schedule)
{
    exdex_scene_def d = scene_vertical(0.2, 2.0);
    const double ts[2] = {0.0, 1.0}, fs[2] = {1.0, 3.0};
    double F, dF;
    int status;
    exdex_model *m = exdex_model_alloc(&d, &status, NULL);
    ENSURE(m != NULL);
    ENSURE(exdex_model_grip(m, 0.4, &F, &dF) == EXDEX_OK);
    ENSURE(F == d.grip_force && dF == 0.0);
    ENSURE(exdex_model_grip(m, NAN, &F, &dF) == EXDEX_EINVAL);
    ENSURE(exdex_model_grip(NULL, 0.0, &F, &dF) == EXDEX_EINVAL);
    exdex_model_free(m);

    d.grip_force = 2.0;
    d.grip_n = 2;
    d.grip_times = ts;
    d.grip_forces = fs;
    d.grip_kind = EXDEX_GRIP_LINEAR;
    m = exdex_model_alloc(&d, &status, NULL);
    ENSURE(m != NULL);
    ENSURE(exdex_model_grip(m, 0.25, &F, &dF) == EXDEX_OK);
    ENSURE_CLOSE(F, 3.0, 1e-15);
    ENSURE_CLOSE(dF, 4.0, 1e-14);
    ENSURE(exdex_model_grip(m, 2.0, &F, NULL) == EXDEX_OK);
    ENSURE_CLOSE(F, 6.0, 1e-15);
    exdex_model_free(m);
}

/* model_torque_z (Euler's equation about the plate normal) against the
 * generic matrix route: I_B = Rz I Rz^T by full 3x3 products, v = dw +
 * thd (w x e_z), W = w + thd e_z, torque -(I_B v)_z - (W x I_B W)_z; a
 * full symmetric inertia, at angles on and off the axes. The (cos, sin)
 * form gives the same number as the angle form. */
EXDEX_TEST(model_torque_z_matches_generic_euler_torque)
{
    exdex_model m;
    frame f = {{0, 0, 0}, {0, 0, 0}, {0.7, -1.3, 2.1}, {-0.4, 0.9, 1.7}};
    const double I[9] = {0.031, 0.004, -0.006, 0.004, 0.027, 0.003, -0.006, 0.003, 0.045};
    const double ths[5] = {0.0, 1.5707963267948966, -2.3, 0.37, 4.1}, thd = -0.8;
    memset(&m, 0, sizeof m);
    memcpy(m.I, I, sizeof I);
    for (int n = 0; n < 5; n++) {
        double c = cos(ths[n]), s = sin(ths[n]), cs[2] = {c, s};
        double Rz[9] = {c, -s, 0, s, c, 0, 0, 0, 1}, T[9], IB[9], v[3], W[3], Iv[3], IW[3], ref_t;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                T[3 * i + j] = 0.0;
                for (int k = 0; k < 3; k++) T[3 * i + j] += Rz[3 * i + k] * I[3 * k + j];
            }
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                IB[3 * i + j] = 0.0;
                for (int k = 0; k < 3; k++) IB[3 * i + j] += T[3 * i + k] * Rz[3 * j + k];
            }
        v[0] = f.dw[0] + thd * f.w[1];
        v[1] = f.dw[1] - thd * f.w[0];
        v[2] = f.dw[2];
        W[0] = f.w[0];
        W[1] = f.w[1];
        W[2] = f.w[2] + thd;
        for (int i = 0; i < 3; i++) {
            Iv[i] = IB[3 * i] * v[0] + IB[3 * i + 1] * v[1] + IB[3 * i + 2] * v[2];
            IW[i] = IB[3 * i] * W[0] + IB[3 * i + 1] * W[1] + IB[3 * i + 2] * W[2];
        }
        ref_t = -Iv[2] - (W[0] * IW[1] - W[1] * IW[0]);
        ENSURE(fabs(ref_t) > 1e-3);
        ENSURE_CLOSE(model_torque_z(&m, &f, ths[n], thd), ref_t, 1e-14);
        ENSURE(model_torque_z_cs(&m, &f, cs, thd) == model_torque_z(&m, &f, ths[n], thd));
    }
}
