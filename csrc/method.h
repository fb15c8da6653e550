/* method.h -- private to the exdex core: the table through which
 * exdex_simulate (simulate.c) runs an integration method, one file per
 * method (implicit.c, hybrid.c for event and regularised, explicit.c).
 *
 * Contract of run: the model and the output arrays are valid (simulate.c
 * checked them), sample 0 holds the initial state, *st is zeroed with
 * min_gap = INFINITY, first_warning_t = max_impulse_t = NaN and
 * max_impulse_stop = -1. run records each sample with method_record (which
 * also notes the time of the first warning); an event method counts impacts
 * with method_note_impact where it applies one (time-stepping methods leave
 * that to simulate.c). run fills samples 1 .. n-1 on the grid t_i = i dt
 * (the last one t_end), adds to *st, and returns EXDEX_OK, EXDEX_ENOCONV,
 * EXDEX_ENONFINITE, EXDEX_ENOMEM, or EXDEX_EINVAL from a solver whose input
 * left the finite range (simulate.c reports that as EXDEX_ENONFINITE). */
#ifndef EXDEX_METHOD_H
#define EXDEX_METHOD_H

#include "model.h"

typedef struct method_impl {
    const char *name;
    /* The run's mutable workspace, or NULL with *status EXDEX_ENOMEM. */
    void *(*alloc)(const exdex_model *m, int *status);
    /* NULL: the run is begin and advance (below) over the output grid */
    int (*run)(const exdex_model *m, void *ws, double t_end, double dt, exdex_trajectory *out, exdex_stats *st);
    void (*free)(void *ws);  /* NULL is harmless */
    /* 1: a time-stepping method whose per-step stop impulses (stop_force
     * times the step) simulate.c reads to count impacts; 0: run counts them
     * itself with method_note_impact */
    int impacts_from_steps;
    int checks_finite;       /* 1: run returns EXDEX_OK only with finite output (it checks
                                every step), so simulate.c need not scan it again */
    /* A run is begin followed by advance for the samples 1 .. n-1 (t_i = i
     * dt, the last one t_end; simulate.c where run is NULL); the stepper
     * (stepper.c) calls them one interval at a time. begin puts the initial state into ws for a run to t_end
     * (INFINITY: not known) whose first output step is dt. advance runs from
     * the time reached to t1 (> it) and records the interval as sample i of
     * out (method_record); regrip = 1 says that the model's friction
     * capacity changed since the last interval (the stepper's grip force):
     * a method that caches modes or capacities decides them again. A failed
     * advance leaves ws unusable until begin or restore. */
    int (*begin)(const exdex_model *m, void *ws, double t_end, double dt, exdex_stats *st);
    int (*advance)(const exdex_model *m, void *ws, double t1, int regrip, exdex_trajectory *out, size_t i,
                   exdex_stats *st);
    /* The run's state between two intervals as state_size bytes (save), and
     * back (restore, into a workspace of the same model on which begin ran):
     * advancing from a restored state repeats the saved run bit for bit.
     * restore returns EXDEX_EINVAL, leaving ws as begin left it, when an
     * index or count of the state is out of its range for this model
     * (numbers are not checked: a non-finite one fails the next advance). */
    size_t state_size;
    void (*save)(const void *ws, void *buf);
    int (*restore)(void *ws, const void *buf);
    /* NULL, or advance over the grid's samples i0 .. i1 (t_i = i dt, the
     * last one of out t_end) in one call, as that many advance calls would
     * run them (bit for bit), without a call per sample: what simulate.c's
     * run certified as it goes calls for a window (where run does the rest) */
    int (*advance_samples)(const exdex_model *m, void *ws, double t_end, double dt, exdex_trajectory *out,
                           size_t i0, size_t i1, exdex_stats *st);
} method_impl;

/* A sub-step's share of its output interval's means (the time-stepping
 * methods split an output step at switching times): the sub-step's plate
 * wrench wr and source forces sfs (n_src of them) weighted by its fraction
 * wt of the interval, added to wrench and sf, or starting them (first). */
static inline void method_add_sub(int first, double wt, const double wr[3], const double *sfs, int n_src,
                                  double wrench[3], double *sf)
{
    for (int c = 0; c < 3; c++) wrench[c] = first ? wr[c] * wt : wrench[c] + wr[c] * wt;
    for (int k = 0; k < n_src; k++) sf[k] = first ? sfs[k] * wt : sf[k] + sfs[k] * wt;
}

/* Count an impact of `impulse` (> 0) [N s] on stop `k` at time t. */
static inline void method_note_impact(exdex_stats *st, double t, int k, double impulse)
{
    if (!(impulse > 0.0)) return;
    st->impacts++;
    if (impulse > st->max_impulse) {
        st->max_impulse = impulse;
        st->max_impulse_t = t;
        st->max_impulse_stop = k;
    }
}

/* Note the time of the first warning: call after each step or output
 * interval ending at t. */
static inline void method_note_warning_time(exdex_stats *st, double t)
{
    if (st->warnings && st->first_warning_t != st->first_warning_t) st->first_warning_t = t;
}

/* Record sample i: time t, coordinates q and velocities v (ndof each), the
 * mean plate wrench over the interval ending there (B, at the centre of
 * pressure), the stick flag and the mean force of each stop; the stick
 * flag also counts in st->stick_steps. */
static inline void method_record(const exdex_model *m, exdex_trajectory *out, exdex_stats *st, size_t i, double t,
                                 const double *q, const double *v, const double wrench[3], int stick,
                                 const double *stop_force)
{
    int nd = m->ndof, ns = m->n_src;
    out->t[i] = t;
    for (int c = 0; c < nd; c++) {
        out->q[i * (size_t)nd + c] = q[c];
        out->v[i * (size_t)nd + c] = v[c];
    }
    for (int c = 0; c < 3; c++) out->wrench[3 * i + c] = wrench[c];
    out->stick[i] = (unsigned char)stick;
    st->stick_steps += (size_t)(stick != 0);
    for (int k = 0; k < ns; k++) out->stop_force[i * (size_t)ns + k] = stop_force[k];
    method_note_warning_time(st, t);
}

/* The stop impulses of a time-stepping run (impacts.c): impulse(ctx, k, i)
 * is P_i = stop_force_i h_i of source k for step i >= 1 and 0 for i = 0,
 * time(ctx, i) the end of step i; samples 0 .. n-1 exist. */
#define IMPACT_STEPS 4
typedef struct impact_steps {
    double (*impulse)(const void *ctx, int k, size_t i);
    double (*time)(const void *ctx, size_t i);
    const void *ctx;
    size_t n;
} impact_steps;

/* Count the impacts of source k (impacts.c) whose bursts start at step i
 * (>= 1) or later into st (impacts, max_impulse and its time and stop):
 * final = 0 to the end of the samples, as a whole run's scan; final = 1 only
 * those whose decision no later step can change (it reads P_{i-1} ..
 * P_{i+2 IMPACT_STEPS}). Returns the first step not yet scanned, where a
 * later final or whole scan of the same source goes on to the same count. */
size_t impact_scan(const impact_steps *s, int k, size_t i, int final, exdex_stats *st);

/* The method table (simulate.c): NULL for an unknown method. */
const method_impl *method_get(int method);

extern const method_impl method_implicit;     /* implicit.c */
extern const method_impl method_event;        /* hybrid.c */
extern const method_impl method_regularised;  /* hybrid.c */
extern const method_impl method_explicit;     /* explicit.c */
extern const method_impl method_analytic;     /* analytic.c */

#endif
