/* fuzz_cone.c -- the twist-cone rows and volumes of the tool-design section:
 * exdex_contact_row, exdex_contact_rows_friction, exdex_cone_rows_paper,
 * exdex_cone_volume_exact and exdex_cone_volumes (exact, grid, QMC).
 *
 * Checks: non-finite rows or box, hi <= lo, a row count outside
 * 0..EXDEX_CONE_MAX_ROWS give EXDEX_EINVAL; EXDEX_OK gives a finite volume
 * in [0, box volume]; with no rows the volume is the box volume; adding a row
 * never increases the volume; a half-space and its complement fill the box;
 * scaling the rows by a positive factor leaves the volume unchanged (all to
 * the stated accuracy 16 (1 + m) eps box, for every box; a scaling that
 * rounds the rows adds the bound round_tol on the change of the exact
 * volume); the
 * vectorised exact method matches the single call bit for bit. */
#include "fuzz.h"

#include <math.h>
#include <string.h>

#define T "cone"
#define NR EXDEX_CONE_MAX_ROWS

static double boxvol(const double lo[3], const double hi[3])
{
    return (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
}

/* The stated accuracy of the exact volume (exdex.h): |v - V| <= 16 (1 + m)
 * eps times the box volume, whatever the box's size, aspect or distance from
 * the origin, plus a few of the smallest subnormals (a subnormal box volume
 * has no relative precision to give). */
static double vol_tol(const double lo[3], const double hi[3], int m)
{
    return 16.0 * (1 + m) * 2.220446049250313e-16 * boxvol(lo, hi) + 4 * 4.9406564584124654e-324;
}

/* Bound on the change of the exact volume when every row coefficient is
 * perturbed by a relative u = eps/2 (rounding of c a_j; the cone of c a is
 * that of a, so fl(c a_j) = c a_j (1 + d_j) acts as a_j (1 + d_j)). For
 * x in the box the row's value changes by |sum_j d_j a_j x_j| <= E =
 * u sum_j |a_j| X_j, X_j = max(|lo_j|, |hi_j|), so the sign can change only
 * in the slab |a . x| <= E, whose part in the box is at most 2 E / |a_j| wide
 * along any x_j with a_j != 0: volume <= box * min(1, 2 E / max_j |a_j| w_j).
 * The cones differ only where some row changes sign: sum over the rows. (The
 * bound is evaluated in floating point; its own rounding is a relative few
 * eps of a bound that is itself not tight.) */
static double round_tol(const double *rows, int m, const double lo[3], const double hi[3])
{
    double bv = boxvol(lo, hi), t = 0.0;
    for (int r = 0; r < m; r++) {
        const double *a = rows + 3 * r;
        double E = 0.0, den = 0.0;
        for (int j = 0; j < 3; j++) {
            double X = fmax(fabs(lo[j]), fabs(hi[j])), aw = fabs(a[j]) * (hi[j] - lo[j]);
            E += fabs(a[j]) * X;
            if (aw > den) den = aw;
        }
        E *= 0.5 * 2.220446049250313e-16;
        if (E == 0.0) continue;  /* all-zero row: no constraint */
        t += bv * fmin(1.0, 2.0 * E / den);  /* den 0 (underflow): 1 */
    }
    return t;
}

int fuzz_cone(const uint8_t *data, size_t size)
{
    fz f;
    static double rows[3 * (NR + 4)], rows2[3 * (NR + 4)];
    double lo[3], hi[3], v = NAN, v2 = NAN, bv, vol[4], err[4];
    int m, md, st, finite_in;
    exdex_volume_opts o;

    fz_init(&f, data, size);
    m = fz_int(&f, 0, 8);
    md = m < 0 ? 0 : m > NR ? NR : m;
    memset(rows, 0, sizeof rows);
    for (int k = 0; k < md; k++) {
        int kind = fz_pick(&f, 0, 7);
        double *a = rows + 3 * k;
        if (kind == 0) {
            /* all-zero padding row */
        } else if (kind == 1 && k + 1 < md) {
            double r[2] = {fz_num(&f, -1, 1), fz_num(&f, -1, 1)}, th = fz_num(&f, 0, 6.283185307179586);
            double n[2] = {cos(th), sin(th)}, mu = fz_num(&f, 0.0, 2.0);
            st = exdex_contact_rows_friction(a, r, n, mu);
            FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL || st == EXDEX_ENONFINITE);
            if (!isfinite(mu) || mu < 0 || !fz_all_finite(r, 2) || !fz_all_finite(n, 2))
                FZ_CHECK(T, st == EXDEX_EINVAL);
            /* r x e overflows only for |r| near DBL_MAX */
            if (st == EXDEX_ENONFINITE) FZ_CHECK(T, f.wild > 0);
            if (st == EXDEX_OK) {
                FZ_CHECK(T, fz_all_finite(a, 6));
                k++;
            } else {
                a[0] = a[1] = a[2] = 0.0;
            }
        } else if (kind == 2 && k + 1 < md) {
            exdex_cone_rows_paper(a, fz_num(&f, -3.2, 3.2), fz_num(&f, 0.0, 3.2));
            k++;
        } else if (kind == 3) {
            double r[2] = {fz_num(&f, -1, 1), fz_num(&f, -1, 1)}, th = fz_num(&f, 0, 6.283185307179586);
            double n[2] = {cos(th), sin(th)};
            exdex_contact_row(a, r, n);
        } else {
            for (int j = 0; j < 3; j++) a[j] = fz_num(&f, -2.0, 2.0);
        }
    }
    for (int j = 0; j < 3; j++) {
        if (fz_pick(&f, 0, 1)) {
            hi[j] = fz_log(&f, 1e-3, 4.0);
            lo[j] = -hi[j];
        } else {
            lo[j] = fz_num(&f, -3.0, 1.0);
            hi[j] = lo[j] + fz_log(&f, 1e-3, 6.0);
        }
    }
    finite_in = fz_all_finite(lo, 3) && fz_all_finite(hi, 3) && fz_all_finite(rows, 3 * (size_t)md);
    bv = boxvol(lo, hi);

    st = exdex_cone_volume_exact(rows, m, lo, hi, &v);
    fuzz_count_status(T, st);
    FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL);
    FZ_CHECK(T, exdex_cone_volume_exact(rows, m, lo, hi, NULL) == EXDEX_EINVAL);
    if (m < 0 || m > NR || !finite_in || !(hi[0] > lo[0] && hi[1] > lo[1] && hi[2] > lo[2]))
        FZ_CHECK(T, st == EXDEX_EINVAL);
    if (st == EXDEX_OK) {
        /* the stated accuracy holds for every valid box and finite rows
         * (thin boxes far from the origin, wild magnitudes) */
        double tol = vol_tol(lo, hi, md), tol1 = vol_tol(lo, hi, 1);
        FZ_CHECK(T, isfinite(v));
        FZ_CHECK(T, v >= 0 && v <= bv);
        if (m == 0) FZ_CHECK(T, v == bv);
#define CONE_INV(cond) FZ_CHECK(T, cond)
        if (isfinite(bv) && bv > 0) {
            /* one row fewer: never smaller */
            if (m > 0) {
                st = exdex_cone_volume_exact(rows, m - 1, lo, hi, &v2);
                CONE_INV(st == EXDEX_OK && v2 >= v - 2 * tol);
            }
            /* positive scaling of the rows changes nothing: by 4 the rows
             * stay exact (the cone is the same), so the two volumes differ by
             * the tolerances of both; 4 a_j may overflow (EINVAL) */
            for (int i = 0; i < 3 * m; i++) rows2[i] = 4.0 * rows[i];
            st = exdex_cone_volume_exact(rows2, m, lo, hi, &v2);
            if (fz_all_finite(rows2, 3 * (size_t)m)) CONE_INV(st == EXDEX_OK && fabs(v2 - v) <= 2 * tol);
            /* by 3 the rows round, which changes the exact volume itself
             * (round_tol: a relative eps/2 in a row far from its box moves the
             * plane by much more than the box size times eps) */
            for (int i = 0; i < 3 * m; i++) rows2[i] = 3.0 * rows[i];
            st = exdex_cone_volume_exact(rows2, m, lo, hi, &v2);
            if (fz_all_finite(rows2, 3 * (size_t)m))
                CONE_INV(st == EXDEX_OK && fabs(v2 - v) <= 2 * tol + round_tol(rows, m, lo, hi));
            /* a half-space and its complement fill the box */
            if (m > 0) {
                double va, vb;
                for (int j = 0; j < 3; j++) rows2[j] = -rows[j];
                FZ_CHECK(T, exdex_cone_volume_exact(rows, 1, lo, hi, &va) == EXDEX_OK);
                FZ_CHECK(T, exdex_cone_volume_exact(rows2, 1, lo, hi, &vb) == EXDEX_OK);
                if (rows[0] != 0 || rows[1] != 0 || rows[2] != 0)
                    CONE_INV(fabs(va + vb - bv) <= 2 * tol1);
            }
        }
    }
#undef CONE_INV

    /* vectorised: up to 3 cases of m rows each, consecutive in rows[] */
    {
        int method = fz_int(&f, 0, 2), ncases = fz_pick(&f, 0, 3), mm = md > 2 ? 2 : md;
        int use_opts = fz_pick(&f, 0, 3) != 0;
        o = exdex_default_volume_opts();
        o.grid_n = fz_int(&f, 1, 6);
        o.qmc_points = fz_int(&f, 1, 200);
        o.qmc_shifts = fz_int(&f, 1, 4);
        /* the library accepts up to 10^5 grid cells per axis and 2^30 x 4096
         * QMC points (valid, but minutes); keep each input short */
        if (o.grid_n > 16) o.grid_n = 16;
        if (o.qmc_points > 1000) o.qmc_points = 1000;
        if (o.qmc_shifts > 8) o.qmc_shifts = 8;
        o.seed = (unsigned long)fz_pick(&f, 0, 1000);
        if (!use_opts && method != EXDEX_VOLUME_EXACT) use_opts = 1;  /* defaults are slow */
        st = exdex_cone_volumes(method, (size_t)ncases, mm, rows, lo, hi, use_opts ? &o : NULL, vol, err);
        fuzz_count_status(T, st);
        FZ_CHECK(T, st == EXDEX_OK || st == EXDEX_EINVAL || st == EXDEX_ENOMEM);
        if (method < 0 || method > 2 || !fz_all_finite(lo, 3) || !fz_all_finite(hi, 3))
            FZ_CHECK(T, st == EXDEX_EINVAL);
        if (st == EXDEX_OK)
            for (int c = 0; c < ncases; c++) {
                FZ_CHECK(T, isfinite(vol[c]) && vol[c] >= 0 && vol[c] <= bv);
                if (method == EXDEX_VOLUME_EXACT) {
                    double ve;
                    FZ_CHECK(T, exdex_cone_volume_exact(rows + 3 * mm * c, mm, lo, hi, &ve) == EXDEX_OK);
                    FZ_CHECK(T, (ve == vol[c] || (isnan(ve) && isnan(vol[c]))) && isnan(err[c]));
                } else if (method == EXDEX_VOLUME_GRID) {
                    FZ_CHECK(T, isnan(err[c]));
                } else if (o.qmc_shifts > 1) {
                    FZ_CHECK(T, isfinite(err[c]) && err[c] >= 0);
                }
            }
        FZ_CHECK(T, exdex_cone_volumes(method, 1, mm, rows, lo, hi, &o, NULL, NULL) == EXDEX_EINVAL);
    }
    return 0;
}
