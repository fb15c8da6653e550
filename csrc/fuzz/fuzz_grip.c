/* fuzz_grip.c -- grip-force schedules (exdex_scene_def.grip_n, grip_times,
 * grip_forces, grip_kind) through exdex_scene_check, exdex_model_alloc,
 * exdex_model_grip and a short exdex_simulate of a simple scene (every
 * method and dof, gripper at rest or on a trapezoid).
 *
 * Checks: a non-finite time or force, times not strictly increasing, a
 * negative force, an unknown kind or a missing array give EXDEX_EINVAL from
 * both exdex_scene_check and exdex_model_alloc with the same bad_param
 * ("grip_times", "grip_forces", "grip_kind", "grip_n"); a valid schedule is
 * accepted. For a built model, F(t) = exdex_model_grip at fuzzed times
 * (wild ones included) is finite, >= 0 and at most grip_force times the
 * largest force (every kind interpolates without overshoot: linear and step
 * by construction, the cubic is Steffen's monotone one), its rate finite;
 * F is held at the end values outside the points. EXDEX_OK from
 * exdex_simulate gives finite output, and a second run is bit-identical. */
#include "fuzz.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define T "grip"
#define MAX_PTS 8
#define MAX_STEPS 20

int fuzz_grip(const uint8_t *data, size_t size)
{
    fz f;
    exdex_scene_def d = exdex_default_scene_def();
    double times[MAX_PTS], forces[MAX_PTS], fmax_ = 0.0, dt, t_end;
    int n, bad_in = 0, st_check, st_alloc = -1;
    const char *bad = NULL, *bad2 = NULL;
    exdex_model *m;

    fz_init(&f, data, size);
    n = fz_pick(&f, 0, MAX_PTS);
    {
        double t = fz_num(&f, -0.1, 0.1);
        for (int i = 0; i < n; i++) {
            times[i] = t;
            forces[i] = fz_pick(&f, 0, 5) == 0 ? 0.0 : fz_num(&f, -0.2, 5.0);
            t += fz_pick(&f, 0, 15) == 0 ? 0.0 : fz_log(&f, 1e-6, 0.2);
        }
    }
    d.grip_n = (size_t)n;
    d.grip_times = fz_pick(&f, 0, 31) == 0 ? NULL : times;
    d.grip_forces = fz_pick(&f, 0, 31) == 0 ? NULL : forces;
    d.grip_kind = fz_int(&f, 0, 2);
    d.grip_force = fz_pick(&f, 0, 7) == 0 ? 0.0 : fz_log(&f, 1e-3, 10.0);
    d.mass = fz_log(&f, 1e-2, 1.0);
    d.mu = fz_num(&f, 0.0, 1.0);
    d.dof = fz_pick(&f, 1, 3);
    d.patch_center[0] = fz_pick(&f, 0, 1) ? 0.0 : fz_num(&f, -0.01, 0.01);
    d.v0[0] = fz_num(&f, -0.3, 0.3);
    d.v0[1] = fz_num(&f, -0.3, 0.3);
    d.v0[2] = fz_num(&f, -5.0, 5.0);
    if (fz_pick(&f, 0, 1)) {
        d.motion.kind = EXDEX_MOTION_TRAPEZOID;
        d.motion.axis[0] = 0.0;
        d.motion.axis[1] = 0.0;
        d.motion.axis[2] = 1.0;
        d.motion.amplitude = fz_num(&f, -0.05, 0.05);
        d.motion.duration = 0.2;
        d.motion.v_max = 1.5 * fabs(d.motion.amplitude) / 0.2 + 1e-9;
    }
    d.method = fz_pick(&f, 0, 4);
    d.rtol = 1e-8;
    d.atol = 1e-10;
    dt = fz_log(&f, 1e-3, 0.05);
    t_end = dt * (double)fz_pick(&f, 1, MAX_STEPS);
    if (d.method == EXDEX_METHOD_EVENT || d.method == EXDEX_METHOD_REGULARISED) t_end = dt;

    /* which input is bad, in the order the core checks it */
    if (d.grip_n > 0) {
        if (d.grip_kind < EXDEX_GRIP_LINEAR || d.grip_kind > EXDEX_GRIP_STEP) bad_in = 1;
        if (!d.grip_times || !d.grip_forces) bad_in = 1;
        for (int i = 0; i < n && d.grip_times && d.grip_forces; i++) {
            if (!isfinite(times[i]) || (i && !(times[i] > times[i - 1]))) bad_in = 1;
            if (!isfinite(forces[i]) || forces[i] < 0 || !isfinite(d.grip_force * forces[i])) bad_in = 1;
            else if (forces[i] > fmax_) fmax_ = forces[i];
        }
    }
    if (!isfinite(d.grip_force) || !isfinite(d.mass) || !isfinite(d.mu) ||
        !fz_all_finite(d.patch_center, 2) || !fz_all_finite(d.v0, 3) || !isfinite(d.motion.amplitude))
        bad_in = 2; /* some other field: rejected too, not necessarily as a grip field */

    st_check = exdex_scene_check(&d, &bad);
    m = exdex_model_alloc(&d, &st_alloc, &bad2);
    fuzz_count_status(T, st_alloc);
    FZ_CHECK(T, (st_check == EXDEX_EINVAL) == (st_alloc == EXDEX_EINVAL));
    if (st_check == EXDEX_EINVAL) FZ_CHECK(T, bad && bad2 && strcmp(bad, bad2) == 0);
    if (bad_in == 1) {
        FZ_CHECK(T, st_check == EXDEX_EINVAL && m == NULL);
        if (bad && d.mass > 0 && isfinite(d.mass) && isfinite(d.grip_force) && d.grip_force >= 0 && isfinite(d.mu) &&
            d.mu >= 0)
            FZ_CHECK(T, strncmp(bad, "grip_", 5) == 0);
    }
    if (!m) return 0;
    FZ_CHECK(T, bad_in == 0);
    fuzz_note_count(T, "models built");
    FZ_CHECK(T, exdex_model_grip(NULL, 0.0, NULL, NULL) == EXDEX_EINVAL);
    FZ_CHECK(T, exdex_model_grip(m, NAN, NULL, NULL) == EXDEX_EINVAL);
    for (int k = 0; k < 6; k++) {
        double t = fz_num(&f, -0.2, 1.0), F = NAN, R = NAN, cap;
        if (isnan(t)) continue;
        FZ_CHECK(T, exdex_model_grip(m, t, &F, &R) == EXDEX_OK);
        cap = d.grip_n ? d.grip_force * fmax_ : d.grip_force;
        FZ_CHECK(T, isfinite(F) && F >= 0.0 && F <= cap * (1.0 + 1e-12));
        FZ_EXTREME(T, &f, isfinite(R));
        if (n > 0 && d.grip_times) {
            double F0 = NAN, F1 = NAN;
            exdex_model_grip(m, times[0] - 1.0, &F0, NULL);
            exdex_model_grip(m, times[n - 1] + 1.0, &F1, NULL);
            if (isfinite(times[0] - 1.0)) FZ_CHECK(T, F0 == d.grip_force * forces[0] || F0 == F1);
        }
    }
    {
        size_t ns = exdex_n_samples(t_end, dt);
        int nd = exdex_model_ndof(m);
        if (ns >= 2 && ns <= MAX_STEPS + 2) {
            double *buf = calloc(ns * (size_t)(1 + 2 * nd + 3) * 2, sizeof(double));
            unsigned char *stick = calloc(2 * ns, 1);
            if (buf && stick) {
                exdex_trajectory a = {ns, buf, buf + ns, buf + ns + ns * (size_t)nd, buf + ns + 2 * ns * (size_t)nd,
                                      stick, NULL};
                double *b0 = buf + ns * (size_t)(1 + 2 * nd + 3);
                exdex_trajectory b = {ns, b0, b0 + ns, b0 + ns + ns * (size_t)nd, b0 + ns + 2 * ns * (size_t)nd,
                                      stick + ns, NULL};
                exdex_stats sa, sb;
                int st = exdex_simulate(m, t_end, dt, &a, &sa);
                fuzz_count_status(T, st);
                FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_ENOCONV || st == EXDEX_ENONFINITE);
                if (st == EXDEX_OK) {
                    fuzz_note_count(T, "runs OK");
                    FZ_CHECK(T, fz_all_finite(a.q, ns * (size_t)nd) && fz_all_finite(a.v, ns * (size_t)nd) &&
                                    fz_all_finite(a.wrench, 3 * ns));
                    FZ_CHECK(T, exdex_simulate(m, t_end, dt, &b, &sb) == EXDEX_OK);
                    FZ_CHECK(T, memcmp(a.q, b.q, ns * (size_t)nd * sizeof(double)) == 0 &&
                                    memcmp(a.v, b.v, ns * (size_t)nd * sizeof(double)) == 0);
                }
            }
            free(buf);
            free(stick);
        }
    }
    exdex_model_free(m);
    return 0;
}
