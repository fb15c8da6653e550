/* test_impacts.c -- impacts.c: impact_scan on impulse sequences written by
 * hand, against the rule of method.h / impacts.c: a burst of steps whose
 * impulses jump above IMPACT_RATIO (4) times the load level around them is
 * one impact, its impulse the burst's sum, its time the end of its largest
 * step; a steady load is none, and a burst the run's end cuts off is none. */
#include "check.h"
#include "../method.h"

#include <math.h>
#include <string.h>

#define NSTEPS 40

typedef struct seq { double P[2][NSTEPS]; } seq;

static double seq_impulse(const void *ctx, int k, size_t i) { return ((const seq *)ctx)->P[k][i]; }
static double seq_time(const void *ctx, size_t i) { (void)ctx; return 0.01 * (double)i; }

static void load(seq *s, int k, double level)
{
    s->P[k][0] = 0.0;   /* P_0 = 0 */
    for (int i = 1; i < NSTEPS; i++) s->P[k][i] = level;
}

static exdex_stats fresh_stats(void)
{
    exdex_stats st;
    memset(&st, 0, sizeof st);
    st.max_impulse_t = NAN;
    st.max_impulse_stop = -1;
    return st;
}

static exdex_stats scan_all(const seq *s, int n_src)
{
    impact_steps is = {seq_impulse, seq_time, s, NSTEPS};
    exdex_stats st = fresh_stats();
    for (int k = 0; k < n_src; k++) impact_scan(&is, k, 1, 0, &st);
    return st;
}

/* A stop that starts carrying a steady load at step 1 (P_1 > 4 P_0 = 0, but
 * not above 4 times the level after it): no impact. */
EXDEX_TEST(impacts_steady_load_is_no_impact)
{
    seq s;
    load(&s, 0, 1e-3);
    exdex_stats st = scan_all(&s, 1);
    ENSURE(st.impacts == 0 && st.max_impulse == 0.0 && st.max_impulse_stop == -1 && isnan(st.max_impulse_t));
}

/* One step of 0.1 N s on a load of 1e-3 N s at step 10: one impact, 0.1, at
 * t(10); spread over steps 10, 11 (0.04, 0.06): one impact of 0.1 at the
 * larger step's end t(11). */
EXDEX_TEST(impacts_burst_is_one_impact_of_its_sum)
{
    seq s;
    exdex_stats st;
    load(&s, 0, 1e-3);
    s.P[0][10] = 0.1;
    st = scan_all(&s, 1);
    ENSURE(st.impacts == 1);
    ENSURE_CLOSE(st.max_impulse, 0.1, 1e-17);
    ENSURE_CLOSE(st.max_impulse_t, 0.10, 1e-17);
    ENSURE(st.max_impulse_stop == 0);

    load(&s, 0, 1e-3);
    s.P[0][10] = 0.04;
    s.P[0][11] = 0.06;
    st = scan_all(&s, 1);
    ENSURE(st.impacts == 1);
    ENSURE_CLOSE(st.max_impulse, 0.1, 1e-17);
    ENSURE_CLOSE(st.max_impulse_t, 0.11, 1e-17);
}

/* Two separate bursts on stop 0 (0.02 at step 8, 0.05 at step 25) and one
 * of 0.05 on stop 1 at step 15: three impacts; the largest 0.05, on a tie
 * the lowest stop's (stop 0, t(25)). */
EXDEX_TEST(impacts_counts_bursts_and_keeps_the_largest)
{
    seq s;
    load(&s, 0, 1e-3);
    load(&s, 1, 2e-3);
    s.P[0][8] = 0.02;
    s.P[0][25] = 0.05;
    s.P[1][15] = 0.05;
    exdex_stats st = scan_all(&s, 2);
    ENSURE(st.impacts == 3);
    ENSURE(st.max_impulse == 0.05 && st.max_impulse_stop == 0);
    ENSURE_CLOSE(st.max_impulse_t, 0.25, 1e-17);
}

/* A spike at the last step is cut off by the run's end: none. A final scan
 * stops before the last 2 IMPACT_STEPS steps and a whole scan from where it
 * stopped finds the same impacts as one whole scan. */
EXDEX_TEST(impacts_end_of_run_and_final_scan)
{
    seq s;
    impact_steps is = {seq_impulse, seq_time, &s, NSTEPS};
    exdex_stats st, st2;
    size_t next;
    load(&s, 0, 1e-3);
    s.P[0][NSTEPS - 1] = 0.1;
    st = scan_all(&s, 1);
    ENSURE(st.impacts == 0);

    load(&s, 0, 1e-3);
    s.P[0][12] = 0.1;
    s.P[0][NSTEPS - 5] = 0.07;   /* within the last 2 W steps */
    st = scan_all(&s, 1);
    ENSURE(st.impacts == 2);
    st2 = fresh_stats();
    next = impact_scan(&is, 0, 1, 1, &st2);
    ENSURE(next == NSTEPS - 2 * IMPACT_STEPS);
    ENSURE(st2.impacts == 1 && st2.max_impulse == 0.1);
    impact_scan(&is, 0, next, 0, &st2);
    ENSURE(st2.impacts == st.impacts && st2.max_impulse == st.max_impulse && st2.max_impulse_t == st.max_impulse_t);
}
