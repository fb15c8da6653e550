/* test_status.c -- status.c: the status texts and the GSL set-up. */
#include "check.h"
#include "../exdex.h"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_sf_log.h>
#include <string.h>

/* Every status code of enum exdex_status has its own text, none of them the
 * text of an unknown code. */
EXDEX_TEST(status_every_code_has_its_own_text)
{
    const int codes[] = {EXDEX_OK, EXDEX_EINVAL, EXDEX_ENOMEM, EXDEX_ENOCONV, EXDEX_ENONFINITE};
    const int n = (int)(sizeof codes / sizeof codes[0]);
    const char *unknown = exdex_strerror(-1);
    for (int i = 0; i < n; i++) {
        const char *s = exdex_strerror(codes[i]);
        ENSURE(s != NULL && s[0] != '\0');
        ENSURE(strcmp(s, unknown) != 0);
        for (int j = 0; j < i; j++) ENSURE(strcmp(s, exdex_strerror(codes[j])) != 0);
    }
    ENSURE(strcmp(exdex_strerror(EXDEX_OK), "success") == 0);
    ENSURE(strcmp(exdex_strerror(EXDEX_EINVAL), "invalid argument") == 0);
}

/* Codes outside the enum (either side, and far away) all read as unknown. */
EXDEX_TEST(status_unknown_code_is_named_unknown)
{
    const int codes[] = {-1, EXDEX_ENONFINITE + 1, 99, -2147483647 - 1, 2147483647};
    for (int i = 0; i < 5; i++) ENSURE(strcmp(exdex_strerror(codes[i]), "unknown status") == 0);
}

/* After exdex_init (the runner calls it; once more is harmless) a GSL
 * domain error is a returned status, not an abort: log(-1) is GSL_EDOM. */
EXDEX_TEST(status_init_turns_gsl_aborts_into_statuses)
{
    gsl_sf_result r;
    exdex_init();
    exdex_init();
    ENSURE(gsl_sf_log_e(-1.0, &r) == GSL_EDOM);
    ENSURE(gsl_sf_log_e(1.0, &r) == GSL_SUCCESS);
    ENSURE_SMALL(r.val, 0.0);
}
