/* fuzz_misc.c -- the small scalar entry points: exdex_er_disc,
 * exdex_er_rectangle, exdex_n_samples, exdex_strerror, the default
 * definitions.
 *
 * Checks: e_r is NaN for invalid sizes; otherwise 2R/3 for the disc, and for
 * the rectangle finite and between max(a, b)/2 (the mean |x| along the long
 * side, a lower bound of the mean distance) and hypot(a, b) (the farthest
 * point); n_samples is 0 for invalid (t_end, dt) and else
 * the step count of the documented rule; strerror never returns NULL; the
 * default scene passes exdex_scene_check. */
#include "fuzz.h"

#include <math.h>

#define T "misc"

int fuzz_misc(const uint8_t *data, size_t size)
{
    fz f;
    double r, a, b, e, t_end, dt;
    size_t n;
    fz_init(&f, data, size);

    r = fz_log(&f, 1e-6, 1.0);
    e = exdex_er_disc(r);
    if (!(r > 0) || !isfinite(r)) {
        FZ_CHECK(T, isnan(e));
    } else {
        FZ_EXTREME(T, &f, isfinite(e) && e > 0);
        FZ_EXTREME(T, &f, fabs(e - 2.0 * (r / 3.0)) <= 1e-15 * e);
    }

    a = fz_log(&f, 1e-6, 1.0);
    b = fz_pick(&f, 0, 3) ? fz_log(&f, 1e-6, 1.0) : a;
    e = exdex_er_rectangle(a, b);
    if (!(a > 0) || !(b > 0) || !isfinite(a) || !isfinite(b)) {
        FZ_CHECK(T, isnan(e));
    } else {
        /* the mean distance from the centre lies between half the shorter
         * side's... bounds: >= max(a, b) / 2 (the mean |x| along the long
         * side) and <= hypot(a, b) (the farthest point) */
        FZ_EXTREME(T, &f, isfinite(e) && e > 0);
        FZ_EXTREME(T, &f, e >= 0.5 * fmax(a, b) * (1 - 1e-12) && e <= hypot(a, b) * (1 + 1e-12));
    }

    dt = fz_log(&f, 1e-6, 1.0);
    t_end = dt * fz_log(&f, 0.5, 1e4);
    n = exdex_n_samples(t_end, dt);
    if (!(isfinite(t_end) && isfinite(dt) && dt > 0 && t_end > 0 && dt <= t_end)) {
        FZ_CHECK(T, n == 0);
    } else if (n > 0) {
        /* steps of dt, the last shortened: (n - 2) dt < t_end <= (n - 1) dt,
         * up to the documented 1e-9 relative rounding allowance */
        double steps = (double)(n - 1), ratio = t_end / dt;
        FZ_CHECK(T, n >= 2);
        FZ_CHECK(T, ratio <= steps * (1 + 1e-9) + 1e-9 && ratio > (steps - 1) * (1 - 1e-9) - 1e-9);
    } else {
        FZ_CHECK(T, t_end / dt > 1e9 * (1 - 1e-9));
    }

    FZ_CHECK(T, exdex_strerror(fz_int(&f, 0, 5)) != NULL);
    {
        exdex_scene_def d = exdex_default_scene_def();
        exdex_volume_opts o = exdex_default_volume_opts();
        FZ_CHECK(T, exdex_scene_check(&d, NULL) == EXDEX_OK);
        FZ_CHECK(T, o.grid_n >= 1 && o.qmc_points >= 1 && o.qmc_shifts >= 1);
    }
    fuzz_count_status(T, EXDEX_OK);
    return 0;
}
