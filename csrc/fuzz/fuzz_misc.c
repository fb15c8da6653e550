/* fuzz_misc.c -- the small scalar entry points: exdex_er_disc,
 * exdex_er_rectangle, exdex_n_samples, exdex_strerror, the default
 * definitions.
 *
 * Checks: e_r is NaN for invalid sizes; otherwise finite and positive for
 * every finite positive size, 2R/3 for the disc, and for the rectangle
 * between max(a, b)/2 (the mean |x| along the long side, a lower bound of
 * the mean distance) and hypot(a, b) (the farthest point), symmetric and
 * equal to the value of the problem rescaled to unit size; n_samples is 0 for invalid (t_end, dt) and else
 * the step count of the documented rule; strerror never returns NULL; the
 * default scene passes exdex_scene_check. */
#include "fuzz.h"

#include <float.h>
#include <math.h>

#ifndef DBL_TRUE_MIN /* C11 */
#define DBL_TRUE_MIN 4.9406564584124654e-324
#endif

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
        /* 2R/3 to rounding (reference in long double); a subnormal result
         * is exact only to its absolute spacing DBL_TRUE_MIN */
        double ref = (double)((long double)r * 2.0L / 3.0L);
        FZ_CHECK(T, isfinite(e) && e > 0);
        FZ_CHECK(T, fabs(e - ref) <= 1e-15 * ref + DBL_TRUE_MIN);
    }

    a = fz_log(&f, 1e-6, 1.0);
    b = fz_pick(&f, 0, 3) ? fz_log(&f, 1e-6, 1.0) : a;
    e = exdex_er_rectangle(a, b);
    if (!(a > 0) || !(b > 0) || !isfinite(a) || !isfinite(b)) {
        FZ_CHECK(T, isnan(e));
    } else {
        /* finite and positive for every finite positive size; between
         * max(a, b)/2 (the mean |x| along the long side, a lower bound of
         * the mean distance) and hypot(a, b) (the farthest point), up to
         * rounding and, for a subnormal result, its absolute spacing */
        double m = fmax(a, b);
        int k;
        FZ_CHECK(T, isfinite(e) && e > 0);
        FZ_CHECK(T, e >= 0.5 * m * (1 - 1e-12) - DBL_TRUE_MIN && e <= hypot(a, b) * (1 + 1e-12) + DBL_TRUE_MIN);
        /* symmetric, and homogeneous of degree 1: the same value from the
         * problem rescaled (exactly, by a power of two) to max(a, b) ~ 1,
         * when both sizes stay normal numbers */
        FZ_CHECK(T, exdex_er_rectangle(b, a) == e);
        frexp(m, &k);
        if (fmin(a, b) >= DBL_MIN && ldexp(fmin(a, b), -k) >= DBL_MIN && e >= DBL_MIN) {
            double es = ldexp(exdex_er_rectangle(ldexp(a, -k), ldexp(b, -k)), k);
            FZ_CHECK(T, fabs(e - es) <= 1e-15 * es);
        }
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
