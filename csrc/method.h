/* method.h -- private to the exdex core: the table through which
 * exdex_simulate (simulate.c) runs an integration method, one file per
 * method (implicit.c, hybrid.c for event and regularised, explicit.c).
 *
 * Contract of run: the model and the output arrays are valid (simulate.c
 * checked them), sample 0 holds the initial state, *st is zeroed with
 * min_gap = INFINITY. run fills samples 1 .. n-1 on the grid t_i = i dt
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
    int (*run)(const exdex_model *m, void *ws, double t_end, double dt, exdex_trajectory *out, exdex_stats *st);
    void (*free)(void *ws);  /* NULL is harmless */
} method_impl;

extern const method_impl method_implicit;     /* implicit.c */
extern const method_impl method_event;        /* hybrid.c */
extern const method_impl method_regularised;  /* hybrid.c */
extern const method_impl method_explicit;     /* explicit.c */

#endif
