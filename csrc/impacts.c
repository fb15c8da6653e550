/* impacts.c -- the impacts of a time-stepping run (implicit, explicit), read
 * from its per-step stop impulses: the scan exdex_simulate runs over a whole
 * run and the stepper runs over its last steps (method.h).
 *
 * With P_i = stop_force_i h_i the impulse of step i on one stop (P_0 = 0): a
 * stop force bounded by the loads gives impulses of order h that change
 * little from step to step; an impact (a velocity jump) gives impulses of
 * order M v, independent of h, in one step or spread over a few (the
 * velocity-level rows of the explicit method let the object cover the last
 * gap in the first of them). With base_j = min(P_j .. P_j+W), the load level
 * just after step j (W = IMPACT_STEPS), an impact of the stop is a burst:
 * steps i .. j-1 (at most W of them) where P_i > IMPACT_RATIO P_{i-1} and
 * every P_l > IMPACT_RATIO base_l, whose largest impulse exceeds
 * IMPACT_RATIO base_j. Its impulse is the burst's sum, its time the end of
 * its largest step. This resolves approach speeds above about IMPACT_RATIO
 * h times the loading acceleration; slower touch-downs are not
 * distinguishable from a contact that starts to carry a load, and a burst
 * that the end of the run cuts off is not counted.
 *
 * The decision on a burst starting at step i reads P_{i-1} .. P_{i+2W}
 * (the burst ends at j <= i+W, and base_j looks W steps on): once those
 * steps exist it is final, and a scan that stops at the first undecided candidate
 * (final = 1) can go on later over more steps to the same result. */
#include "method.h"

#include <math.h>

#define IMPACT_RATIO 4.0

static double base_after(const impact_steps *s, int k, size_t j)
{
    double b = s->impulse(s->ctx, k, j);
    for (size_t l = j + 1; l < s->n && l <= j + IMPACT_STEPS; l++) {
        double P = s->impulse(s->ctx, k, l);
        if (P < b) b = P;
    }
    return b;
}

/* As method_note_impact; the largest impulse, on a tie, is that of the
 * lowest stop (a scan of the whole run takes one stop after the other, the
 * stepper's all stops step by step: both keep the same one). */
static void note(exdex_stats *st, double t, int k, double impulse)
{
    if (!(impulse > 0.0)) return;
    st->impacts++;
    if (impulse > st->max_impulse || (impulse == st->max_impulse && k < st->max_impulse_stop)) {
        st->max_impulse = impulse;
        st->max_impulse_t = t;
        st->max_impulse_stop = k;
    }
}

size_t impact_scan(const impact_steps *s, int k, size_t i, int final, exdex_stats *st)
{
    size_t n = s->n;
    for (; i < n; i++) {
        double P, peak, sum;
        size_t ipk = i, j;
        if (final && i + 2 * IMPACT_STEPS >= n) break;   /* P_{i+2W} not there yet */
        P = s->impulse(s->ctx, k, i);
        peak = sum = P;
        if (!(P > 0.0 && P > IMPACT_RATIO * s->impulse(s->ctx, k, i - 1))) continue;
        for (j = i + 1; j < n && j < i + IMPACT_STEPS; j++) {
            double Pj = s->impulse(s->ctx, k, j);
            if (!(Pj > IMPACT_RATIO * base_after(s, k, j))) break;   /* the burst is over */
            sum += Pj;
            if (Pj > peak) {
                peak = Pj;
                ipk = j;
            }
        }
        if (j < n && peak > IMPACT_RATIO * base_after(s, k, j)) {
            note(st, s->time(s->ctx, ipk), k, sum);
            i = j - 1;   /* continue after the burst */
        }
    }
    return i;
}
