/* check.h -- the tiny test framework of the exdex C suite (Box2D style).
 *
 *   EXDEX_TEST(name) { ENSURE(x > 0); ENSURE_CLOSE(a, b, 1e-12); }
 *
 * Each test registers itself (no shared list to edit). ref("key") reads a
 * reference number from the data file shared with pytest
 * (tests/data/reference.dat); report("key", value) records a computed number
 * that `run_tests --values` prints as "VALUE key value" so pytest can
 * cross-check it through the Python API. */
#ifndef EXDEX_CHECK_H
#define EXDEX_CHECK_H

#include <math.h>
#include <stdio.h>

typedef void (*check_fn)(void);
void check_register(const char *name, const char *file, check_fn fn);
void check_fail(const char *file, int line, const char *msg);
void check_fail_close(const char *file, int line, const char *a, const char *b,
                      double va, double vb, double tol);
double ref(const char *key);
void report(const char *key, double value);
/* A seed of the running test (a hash of its name, never 0): a test file's
 * random generator restarts from it at each test, so that a test draws the
 * same inputs whichever tests ran before it (a name filter, run_tests
 * --shard). */
unsigned long long check_seed(void);

#define EXDEX_TEST(name)                                                     \
    static void name(void);                                                  \
    __attribute__((constructor)) static void check_register_##name(void)     \
    {                                                                        \
        check_register(#name, __FILE__, name);                               \
    }                                                                        \
    static void name(void)

#define ENSURE(expr)                                                         \
    do {                                                                     \
        if (!(expr)) check_fail(__FILE__, __LINE__, #expr);                  \
    } while (0)

/* |a - b| <= tol, and neither is NaN */
#define ENSURE_CLOSE(a, b, tol)                                              \
    do {                                                                     \
        double check_a_ = (a), check_b_ = (b);                               \
        if (!(fabs(check_a_ - check_b_) <= (tol)))                           \
            check_fail_close(__FILE__, __LINE__, #a, #b, check_a_, check_b_, \
                             (tol));                                         \
    } while (0)

#define ENSURE_SMALL(a, tol) ENSURE_CLOSE(a, 0.0, tol)

#endif
