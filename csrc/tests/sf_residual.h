/* sf_residual.h -- test helper: the residuals of the contact conditions of a
 * planar object in a small slip against frictional stops (stop_friction.h's
 * problem with the plate's friction, sf_plate), at a candidate solution
 * (qdd, the rows' normal forces lam, the stops' tangential forces beta, the
 * plate's patch wrench w). Each condition is evaluated from the problem's
 * data by the arithmetic below alone (no stop_friction.c, no ldp.c): it
 * checks a solution, however it was found.
 *
 * The conditions (stop_friction.h's model, M = diag(1 / minv), F = M a the
 * force without stops and plate friction):
 *   ne     Newton-Euler, M qdd = F + A w + sum_i lam_i G_i + sum_k beta_k T_k,
 *          per component relative to the sum of its terms' magnitudes;
 *   gauge, mdp  the plate's friction law for the patch slip u = A^T qdd:
 *          slipping, the wrench on the limit surface (gauge | |E^-1 w| -
 *          cap | / cap) with maximum dissipation, E u antiparallel to the
 *          unit n = E^-1 w / |E^-1 w| (mdp: the part of E u off -n, |E u - (E u
 *          . n) n| + max(0, E u . n), over us, the size of the terms E u is
 *          formed from: |E| |A^T| (|qdd| + |a| + M^-1 |A| |w|) componentwise; a backward
 *          error, which stays well defined where the slip vanishes and
 *          its direction does not); or sticking, u = 0 (|E u| / us) with
 *          the wrench inside (max(0, |E^-1 w| - cap) / cap). The smaller
 *          of the two readings counts (its two parts are written);
 *   compl  each row's complementarity 0 <= lam_i _|_ G_i qdd + gdd0_i >= 0,
 *          |min(lam_i / fs, acc_i / as_i)| (fs the force scale: cap + the
 *          sum of |lam| and |beta| + |F| in the plane; as_i the sum of the
 *          magnitudes of acc_i's terms at qdd and at a);
 *   coul   each stop's Coulomb law in its mode (st[k].fm), its rows' normal
 *          force sum L, its slip acceleration acct = T qdd + sdd0 (as the
 *          sum of the magnitudes of its terms): sliding with sign sigma
 *          (SF_SLIDE_P: +1, SF_SLIDE_M: -1), beta = -sigma mu L; sticking,
 *          acct = 0; rolling (SF_ROLL: stick or slide, not given), |beta| <=
 *          mu L and, where acct is not 0, beta = -sign(acct) mu L, the
 *          residual min(|acct| / as, |beta + sign(acct) mu L| / fs); a
 *          frictionless stop (mu 0, SF_NONE), or one whose rows carry no
 *          force (L = 0), beta = 0. Force residuals / fs;
 *   guard  the inequalities that hold while a given mode lasts (the
 *          guards that end it): a sticking stop's force in its cone,
 *          max(0, |beta| - mu L) / fs; a sliding stop's slip of the sign
 *          sigma, against its slip velocity s where |s| > zsw (1 when s has
 *          the other sign), else max(0, -sigma acct) / as. A state past a
 *          guard (a trial point of a step that event location rejects)
 *          has guard > 0 whatever the solution: sf_residual's value leaves
 *          it out.
 * sf_residual returns the largest residual but guard and writes each (part
 * may be NULL). */
#ifndef EXDEX_TEST_SF_RESIDUAL_H
#define EXDEX_TEST_SF_RESIDUAL_H

#include "../stop_friction.h"

#include <math.h>

enum { SFR_NE, SFR_GAUGE, SFR_MDP, SFR_COMPL, SFR_COUL, SFR_GUARD, SFR_N };

/* A state's problem: the rows and stops (their slip velocity s and the
 * slide threshold zsw), M^-1, the acceleration a without stops and plate
 * friction, the plate. */
typedef struct sfr_problem {
    int nr, ns;
    const sf_row *rows;
    const sf_stop *st;
    const double *s;
    double zsw;
    const double *minv, *a;
    const sf_plate *pl;
} sfr_problem;

static inline double sfr_max(double x, double y) { return x > y ? x : y; }

static inline double sf_residual(const sfr_problem *p, const double qdd[3], const double *lam, const double *beta,
                                 const double w[3], double part[SFR_N])
{
    double r[SFR_N] = {0, 0, 0, 0, 0, 0}, Aw[3], u[3], eu[3], nu = 0.0, g = 0.0, fs, worst = 0.0;
    const sf_plate *pl = p->pl;
    double lsum[SF_MAX_STOPS];
    fs = pl->cap + hypot(p->a[0] / p->minv[0], p->a[1] / p->minv[1]);
    for (int i = 0; i < p->nr; i++) fs += fabs(lam[i]);
    for (int k = 0; k < p->ns; k++) {
        fs += fabs(beta[k]);
        lsum[k] = 0.0;
    }
    for (int i = 0; i < p->nr; i++) lsum[p->rows[i].stop] += lam[i];
    /* Newton-Euler */
    for (int c = 0; c < 3; c++) {
        double lhs = qdd[c] / p->minv[c], f0 = p->a[c] / p->minv[c], rhs, mag;
        Aw[c] = pl->A[c][0] * w[0] + pl->A[c][1] * w[1] + pl->A[c][2] * w[2];
        rhs = f0 + Aw[c];
        mag = fabs(lhs) + fabs(f0) + fabs(pl->A[c][0] * w[0]) + fabs(pl->A[c][1] * w[1]) + fabs(pl->A[c][2] * w[2]);
        for (int i = 0; i < p->nr; i++) {
            rhs += lam[i] * p->rows[i].G[c];
            mag += fabs(lam[i] * p->rows[i].G[c]);
        }
        for (int k = 0; k < p->ns; k++) {
            rhs += beta[k] * p->st[k].T[c];
            mag += fabs(beta[k] * p->st[k].T[c]);
        }
        if (mag > 0.0) r[SFR_NE] = sfr_max(r[SFR_NE], fabs(lhs - rhs) / mag);
    }
    /* the plate: on the limit surface, along the slip's maximum dissipation */
    for (int j = 0; j < 3; j++) {
        u[j] = pl->A[0][j] * qdd[0] + pl->A[1][j] * qdd[1] + pl->A[2][j] * qdd[2];
        eu[j] = pl->e[j] * u[j];
        nu += eu[j] * eu[j];
        g += (w[j] / pl->e[j]) * (w[j] / pl->e[j]);
    }
    nu = sqrt(nu);
    g = sqrt(g);
    if (pl->cap > 0.0) {
        double n[3], un = 0.0, perp = 0.0, us = 0.0, slip, stick, gs = fabs(g - pl->cap) / pl->cap;
        for (int j = 0; j < 3; j++) {
            double t = 0.0;
            n[j] = g > 0.0 ? w[j] / pl->e[j] / g : 0.0;
            un += eu[j] * n[j];
            for (int c = 0; c < 3; c++)
                t += fabs(pl->A[c][j]) * (fabs(qdd[c]) + fabs(p->a[c]) +
                                          p->minv[c] * (fabs(pl->A[c][0] * w[0]) + fabs(pl->A[c][1] * w[1]) + fabs(pl->A[c][2] * w[2])));
            us += (pl->e[j] * t) * (pl->e[j] * t);
        }
        us = sqrt(us);
        if (us == 0.0) us = 1.0;
        for (int j = 0; j < 3; j++) perp += (eu[j] - un * n[j]) * (eu[j] - un * n[j]);
        slip = sfr_max(gs, (sqrt(perp) + sfr_max(0.0, un)) / us);
        stick = sfr_max(sfr_max(0.0, g - pl->cap) / pl->cap, nu / us);
        if (slip <= stick) {
            r[SFR_GAUGE] = gs;
            r[SFR_MDP] = (sqrt(perp) + sfr_max(0.0, un)) / us;
        } else {
            r[SFR_GAUGE] = sfr_max(0.0, g - pl->cap) / pl->cap;
            r[SFR_MDP] = nu / us;
        }
    } else {
        r[SFR_GAUGE] = g;
    }
    /* the rows' complementarity */
    for (int i = 0; i < p->nr; i++) {
        const double *G = p->rows[i].G;
        double acc = G[0] * qdd[0] + G[1] * qdd[1] + G[2] * qdd[2] + p->rows[i].gdd0, as = fabs(p->rows[i].gdd0);
        for (int c = 0; c < 3; c++) as += fabs(G[c] * qdd[c]) + fabs(G[c] * p->a[c]);
        r[SFR_COMPL] = sfr_max(r[SFR_COMPL], fabs(fmin(lam[i] / fs, as > 0.0 ? acc / as : acc)));
    }
    /* the stops' Coulomb law */
    for (int k = 0; k < p->ns; k++) {
        const sf_stop *s = &p->st[k];
        double L = lsum[k], acct = s->T[0] * qdd[0] + s->T[1] * qdd[1] + s->T[2] * qdd[2] + s->sdd0, as = fabs(s->sdd0);
        double e = 0.0, gd = 0.0, sg = s->fm == SF_SLIDE_P ? 1.0 : -1.0;
        for (int c = 0; c < 3; c++) as += fabs(s->T[c] * qdd[c]) + fabs(s->T[c] * p->a[c]);
        if (as == 0.0) as = 1.0;
        if (!(s->mu > 0.0) || s->fm == SF_NONE || L == 0.0) {
            e = fabs(beta[k]) / fs;
        } else if (s->fm == SF_SLIDE_P || s->fm == SF_SLIDE_M) {
            e = fabs(beta[k] + sg * s->mu * L) / fs;
            gd = fabs(p->s[k]) > p->zsw ? (sg * p->s[k] < 0.0 ? 1.0 : 0.0) : sfr_max(0.0, -sg * acct) / as;
        } else if (s->fm == SF_STICK) {
            e = fabs(acct) / as;
            gd = sfr_max(0.0, fabs(beta[k]) - s->mu * L) / fs;
        } else {
            e = sfr_max(0.0, fabs(beta[k]) - s->mu * L) / fs;
            if (acct != 0.0)
                e = sfr_max(e, fmin(fabs(acct) / as, fabs(beta[k] + (acct > 0.0 ? 1.0 : -1.0) * s->mu * L) / fs));
        }
        r[SFR_COUL] = sfr_max(r[SFR_COUL], e);
        r[SFR_GUARD] = sfr_max(r[SFR_GUARD], gd);
    }
    for (int q = 0; q < SFR_N; q++) {
        if (q != SFR_GUARD) worst = sfr_max(worst, r[q]);
        if (part) part[q] = r[q];
    }
    return worst;
}

#endif
