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
