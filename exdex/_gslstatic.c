/* Linked into the extensions only when GSL is linked statically (setup.py).
 *
 * GSL's CBLAS reports invalid arguments through cblas_xerbla, which prints to
 * stderr. Some distributions build libgslcblas.a without -fPIC, and that one
 * object cannot go into a shared library. Defining the function here keeps it
 * out of the link. The exdex core never passes invalid arguments to CBLAS
 * (GSL checks them before it calls CBLAS), and it never prints: this handler
 * does nothing. */
#include <gsl/gsl_cblas.h>

#if defined(__GNUC__)
__attribute__((visibility("hidden")))
#endif
void cblas_xerbla(int p, const char *rout, const char *form, ...)
{
    (void)p;
    (void)rout;
    (void)form;
}
