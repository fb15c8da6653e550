/* status.c -- status texts and process-wide GSL set-up. */
#include "exdex.h"

#include <gsl/gsl_errno.h>

const char *exdex_strerror(int status)
{
    switch (status) {
    case EXDEX_OK: return "success";
    case EXDEX_EINVAL: return "invalid argument";
    case EXDEX_ENOMEM: return "out of memory";
    case EXDEX_ENOCONV: return "solver did not converge";
    case EXDEX_ENONFINITE: return "non-finite value in the state";
    default: return "unknown status";
    }
}

void exdex_init(void)
{
    /* GSL would otherwise abort the process on errors; every call site in
     * exdex checks the returned status instead. */
    gsl_set_error_handler_off();
}
