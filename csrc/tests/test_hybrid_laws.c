/* test_hybrid_laws.c -- hybrid_laws.c: the constraint acceleration of a held
 * 1-DoF row against an independent method. */
#include "check.h"
#include "../hybrid.h"

#include <math.h>

/* The row F(q, t) = sin q + t^2 q - 0.3 (its partials by hand); q(t) the
 * root near 0.3 found by Newton at t - h, t, t + h, and its second
 * difference (q(t+h) - 2 q(t) + q(t-h)) / h^2 against hyb_contact_qdd with
 * v the central difference: d^2 F / dt^2 = 0 along q(t). */
static double row_root(double t)
{
    double q = 0.3;
    for (int i = 0; i < 60; i++) q -= (sin(q) + t * t * q - 0.3) / (cos(q) + t * t);
    return q;
}

EXDEX_TEST(hybrid_laws_contact_qdd_holds_the_row)
{
    const double t = 0.7, h = 1e-4;
    double qm = row_root(t - h), q0 = row_root(t), qp = row_root(t + h);
    double v = (qp - qm) / (2 * h), a_fd = (qp - 2 * q0 + qm) / (h * h);
    crow c;
    c.F = sin(q0) + t * t * q0 - 0.3;
    c.Fq = cos(q0) + t * t;
    c.Fqq = -sin(q0);
    c.Ft = 2 * t * q0;
    c.Ftq = 2 * t;
    c.Ftt = 2 * q0;
    ENSURE_SMALL(c.F, 1e-15);
    /* the second difference's truncation error ~ h^2 q'''' / 12 and its
     * rounding ~ 4 eps / h^2 ~ 1e-7 */
    ENSURE_CLOSE(hyb_contact_qdd(&c, v), a_fd, 1e-6);
    /* a row moving with constant acceleration a: F = q - a t^2 / 2 gives qdd = a */
    crow lin = {0.0, 1.0, 0.0, 0.0, 0.0, -2.5};
    ENSURE(hyb_contact_qdd(&lin, 123.0) == 2.5);
}
