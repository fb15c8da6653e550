/* fuzz_limitsurf.c -- the limit surfaces (limitsurf.h, a private header of
 * the core): the ellipsoid or the exact surface of a decoded disc or convex
 * polygon, a decoded slip twist, load and step problem.
 *
 * Checks: no crash, no hang (every Newton loop is capped); on finite
 * input: D(u) >= 0 and D(u) = -w(u) . u (homogeneity) to rounding, the
 * gauge of w(u) is 1 and the stick test agrees with it, the step returns
 * OK (ENOCONV is counted) with an impulse inside the surface of its
 * capacity, u+ = 0 at stick, and no kinetic energy added. */
#include "fuzz.h"
#include "../limitsurf.h"

#include <math.h>
#include <string.h>

#define T "limitsurf"

static double dot3(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

int fuzz_limitsurf(const uint8_t *data, size_t size)
{
    fz f;
    region rg;
    limitsurf ls;
    fz_init(&f, data, size);
    int kind = fz_pick(&f, 0, 2);
    double L = fz_log(&f, 1e-3, 1.0);
    memset(&rg, 0, sizeof rg);
    if (kind == 0) {
        if (limitsurf_set_ellipsoid(&ls, L) != EXDEX_OK) return 0;
    } else {
        if (kind == 1) {
            region_set_disc(&rg, L * fz_num(&f, -1.0, 1.0), L * fz_num(&f, -1.0, 1.0), L);
        } else {
            rg.kind = REGION_POLYGON;
            rg.n = fz_pick(&f, 3, 8);
            double cx = L * fz_num(&f, -1.0, 1.0), cy = L * fz_num(&f, -1.0, 1.0), ax = fz_num(&f, 0.1, 1.0);
            for (int i = 0; i < rg.n; i++) {
                double a = 6.283185307179586 * (i + fz_num(&f, 0.0, 0.9)) / rg.n;
                rg.v[i][0] = cx + L * cos(a), rg.v[i][1] = cy + ax * L * sin(a);
            }
        }
        int st = limitsurf_set_exact(&ls, &rg);
        fuzz_count_status(T, st);
        if (st != EXDEX_OK) return 0;
    }
    double u[3], w[3], H[9], load[3], Wm[9], b[3], cap;
    for (int i = 0; i < 3; i++) u[i] = fz_num(&f, -1.0, 1.0) / (i < 2 ? 1.0 : L);
    for (int i = 0; i < 3; i++) load[i] = fz_num(&f, -1.0, 1.0) * (i < 2 ? 1.0 : L);
    {
        double B[9];
        for (int i = 0; i < 9; i++) B[i] = fz_num(&f, -1.0, 1.0);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) {
                double s = i == j ? 0.3 : 0.0;
                for (int k = 0; k < 3; k++) s += B[3 * i + k] * B[3 * j + k];
                Wm[3 * i + j] = s * (i < 2 ? 1.0 : 1.0 / L) * (j < 2 ? 1.0 : 1.0 / L);
            }
    }
    for (int i = 0; i < 3; i++) b[i] = fz_num(&f, -1.0, 1.0) / (i < 2 ? 1.0 : L);
    cap = fz_num(&f, 0.0, 2.0);
    int finite = f.nonfinite == 0 && fz_all_finite(u, 3) && fz_all_finite(load, 3) && fz_all_finite(Wm, 9)
                 && fz_all_finite(b, 3);
    double nu = sqrt(dot3(u, u));
    if (finite && nu > 0.0) {
        double D = limitsurf_wrench(&ls, u, w, H);
        FZ_EXTREME(T, &f, isfinite(D) && D >= 0.0 && fz_all_finite(w, 3) && fz_all_finite(H, 9));
        FZ_EXTREME(T, &f, fabs(D + dot3(w, u)) <= 1e-10 * (fabs(u[0]) + fabs(u[1]) + fabs(u[2]) * L * 2));
        double g;
        int st = limitsurf_gauge(&ls, w, &g, NULL);
        if (st == EXDEX_ENOCONV) fuzz_note_keep(T, f.wild ? "gauge ENOCONV (extreme input)" : "gauge ENOCONV");
        else {
            FZ_EXTREME(T, &f, st == EXDEX_OK);
            FZ_EXTREME(T, &f, fabs(g - 1.0) <= 1e-8);
        }
    }
    if (finite) {
        double g;
        int st = limitsurf_gauge(&ls, load, &g, NULL);
        if (st == EXDEX_OK) {
            int s1 = limitsurf_sticks(&ls, load, g * (1.0 + 1e-9)), s2 = limitsurf_sticks(&ls, load, g * (1.0 - 1e-9));
            FZ_EXTREME(T, &f, s1 == 1 || s1 < 0);
            FZ_EXTREME(T, &f, s2 == 0 || s2 < 0 || g == 0.0);
        } else {
            FZ_EXTREME(T, &f, st == EXDEX_ENOCONV);
            fuzz_note_keep(T, f.wild ? "load gauge ENOCONV (extreme input)" : "load gauge ENOCONV");
        }
    } else {
        double g;
        FZ_CHECK(T, limitsurf_gauge(&ls, load, &g, NULL) == EXDEX_EINVAL || fz_all_finite(load, 3));
    }
    exdex_friction_prep prep;
    if (exdex_friction_prepare(&prep, Wm, ls.e) != EXDEX_OK) return 0;
    exdex_friction_result r;
    int st = limitsurf_step(&ls, &prep, b, cap, EXDEX_SOLVER_SCALAR, NULL, NULL, &r);
    fuzz_count_status(T, st);
    if (!finite) return 0;
    if (st == EXDEX_ENOCONV) {
        fuzz_note_keep(T, f.wild ? "step ENOCONV (extreme input)" : "step ENOCONV");
        return 0;
    }
    FZ_EXTREME(T, &f, st == EXDEX_OK);
    if (st != EXDEX_OK) return 0;
    FZ_EXTREME(T, &f, fz_all_finite(r.p, 3) && fz_all_finite(r.u, 3));
    if (r.stick) FZ_CHECK(T, r.u[0] == 0.0 && r.u[1] == 0.0 && r.u[2] == 0.0);
    double g, Wp[3];
    if (limitsurf_gauge(&ls, r.p, &g, NULL) == EXDEX_OK) FZ_EXTREME(T, &f, g <= cap * (1.0 + 1e-8) + 1e-300);
    for (int i = 0; i < 3; i++) Wp[i] = Wm[3 * i] * r.p[0] + Wm[3 * i + 1] * r.p[1] + Wm[3 * i + 2] * r.p[2];
    FZ_EXTREME(T, &f, dot3(r.p, b) + 0.5 * dot3(r.p, Wp) <= 1e-12 * (fabs(dot3(r.p, b)) + dot3(r.p, Wp)));
    return 0;
}
