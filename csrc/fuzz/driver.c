/* driver.c -- plain-C fuzz driver of the exdex core (no clang or libFuzzer
 * needed; see fuzz.h for what is checked and how to run it).
 *
 *   fuzz_driver [--target NAME] [--n N] [--seed S] [--timeout SEC] [--out DIR]
 *               [--corpus DIR] [--write-seeds DIR] [--quiet] [--trace] [--strict]
 *               [--replay FILE...]
 * --trace prints every decoded value (use with --replay to see an input).
 * --strict makes findings on extreme input (FZ_EXTREME in fuzz.h, and hangs
 * on inputs with wild values) failures too.
 *
 * For each target: N deterministic inputs (from --seed), a mix of
 *   - random slot strings with a per-input rate of wild values (0 to 30 %),
 *   - systematic edge cases: a tame random input with one slot replaced by
 *     each special value in turn (NaN, +-inf, +-0, denormals, +-DBL_MAX, ...),
 *   - raw random bytes of random length (truncated and odd-sized inputs),
 * then every file of DIR/<target>/ when --corpus is given. Each input runs
 * under a CPU-time budget (--timeout, default 5 s of the process's CPU time,
 * so a busy machine does not turn a slow input into a hang): exceeding it prints the
 * target and input, writes it to OUT/fuzz-hang-<target>-<index>.bin, counts a
 * failed check and goes on with the next input (siglongjmp out of the call). A failed check prints where and writes the input to
 * OUT/fuzz-fail-<target>-<k>.bin (first 10 per target; OUT is --out, default
 * .); the exit status is 1 if any check failed. */
#ifndef _POSIX_C_SOURCE
#define _POSIX_C_SOURCE 200809L
#endif
#include "fuzz.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

#define MAX_INPUT 4096
#define N_SLOTS 200
#define MAX_SITES 64
#define MAX_NOTES 32

typedef struct target {
    const char *name;
    int (*fn)(const uint8_t *, size_t);
} target;

#define FUZZ_ENTRY(name) {#name, fuzz_##name},
static const target targets[] = {FUZZ_TARGETS(FUZZ_ENTRY)};
#undef FUZZ_ENTRY
#define N_TARGETS ((int)(sizeof targets / sizeof targets[0]))

/* ------------------------------------------------------------ bookkeeping */

static struct {
    unsigned long long inputs, status[6], failures, failed_inputs;
    double seconds, max_seconds;
} stats[N_TARGETS];

static struct { const char *file, *what; int line, target, extreme; unsigned long long count; } sites[MAX_SITES];
static int n_sites;
static struct { const char *key; int target, is_min; unsigned long long count; double min; } notes[MAX_NOTES];
static int n_notes;

static int cur_target = -1, cur_failed, quiet, no_save;
static const char *out_dir = ".";
static unsigned long long cur_index;
static const uint8_t *cur_data;
static size_t cur_size;

static void save_input(const char *path, const uint8_t *data, size_t size)
{
    FILE *fp = fopen(path, "wb");
    if (!fp) return;
    if (size) fwrite(data, 1, size, fp);
    fclose(fp);
}

static int strict;
static unsigned long long extremes[N_TARGETS];

/* Record a failed check (extreme = 0) or a finding on extreme input (1). */
static void record(const char *file, int line, const char *what, int extreme)
{
    int i;
    if (cur_target < 0) return;
    if (extreme && !strict) {
        extremes[cur_target]++;
    } else {
        stats[cur_target].failures++;
        if (!cur_failed) {
            cur_failed = 1;
            stats[cur_target].failed_inputs++;
        }
    }
    for (i = 0; i < n_sites; i++)
        if (sites[i].line == line && sites[i].target == cur_target && strcmp(sites[i].file, file) == 0) break;
    if (i == MAX_SITES) return;
    if (i == n_sites) {
        sites[i].file = file;
        sites[i].line = line;
        sites[i].what = what;
        sites[i].target = cur_target;
        sites[i].extreme = extreme && !strict;
        n_sites++;
        if (!quiet || !sites[i].extreme)
            fprintf(stderr, "%s %s input %llu: %s:%d: %s\n", sites[i].extreme ? "EXTREME" : "FAIL",
                    targets[cur_target].name, cur_index, file, line, what);
        if (!no_save) {
            /* the first input failing at each check is kept */
            char path[1024];
            snprintf(path, sizeof path, "%s/fuzz-%s-%s-line%d.bin", out_dir, sites[i].extreme ? "extreme" : "fail",
                     targets[cur_target].name, line);
            save_input(path, cur_data, cur_size);
            if (!quiet || !sites[i].extreme)
                fprintf(stderr, "     saved to %s (replay: fuzz_driver --target %s --trace --replay %s)\n", path,
                        targets[cur_target].name, path);
        }
    }
    sites[i].count++;
}

void fuzz_fail(const char *target_name, const char *file, int line, const char *what)
{
    (void)target_name;
    record(file, line, what, 0);
}

void fuzz_extreme(const char *target_name, const char *file, int line, const char *what)
{
    (void)target_name;
    record(file, line, what, 1);
}

void fuzz_count_status(const char *target_name, int status)
{
    (void)target_name;
    if (cur_target < 0) return;
    stats[cur_target].status[status >= 0 && status <= 4 ? status : 5]++;
}

static int note_index(const char *key, int is_min)
{
    for (int i = 0; i < n_notes; i++)
        if (notes[i].target == cur_target && strcmp(notes[i].key, key) == 0) return i;
    if (n_notes == MAX_NOTES) return -1;
    notes[n_notes].key = key;
    notes[n_notes].target = cur_target;
    notes[n_notes].is_min = is_min;
    notes[n_notes].count = 0;
    notes[n_notes].min = INFINITY;
    return n_notes++;
}

void fuzz_note_count(const char *target_name, const char *key)
{
    int i;
    (void)target_name;
    if (cur_target < 0) return;
    i = note_index(key, 0);
    if (i >= 0) notes[i].count++;
}

void fuzz_note_keep(const char *target_name, const char *key)
{
    int i;
    (void)target_name;
    if (cur_target < 0) return;
    i = note_index(key, 0);
    if (i < 0) return;
    if (notes[i].count++ == 0 && !no_save) {
        char path[1024];
        snprintf(path, sizeof path, "%s/fuzz-note-%s-%d.bin", out_dir, targets[cur_target].name, i);
        save_input(path, cur_data, cur_size);
        if (!quiet) fprintf(stderr, "NOTE %s input %llu: %s: saved to %s\n", targets[cur_target].name, cur_index, key, path);
    }
}

void fuzz_note_min(const char *target_name, const char *key, double value)
{
    int i;
    (void)target_name;
    if (cur_target < 0) return;
    i = note_index(key, 1);
    if (i >= 0) {
        notes[i].count++;
        if (value < notes[i].min) notes[i].min = value;
    }
}

/* ------------------------------------------------------------ time budget */

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* CPU time of this (single-threaded) process: the per-input cost and budget */
static double cpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static char hang_path[1200];
static sigjmp_buf hang_jump;
static volatile sig_atomic_t in_input;
static unsigned long long hangs[N_TARGETS];

static void on_alarm(int sig)
{
    /* async-signal-safe: write() and _exit() only */
    static const char msg[] = "HANG: an input exceeded the time budget; written to ";
    int fd;
    (void)sig;
    if (cur_target >= 0) {
        fd = open(hang_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0) {
            ssize_t w = write(fd, cur_data, cur_size);
            (void)w;
            close(fd);
        }
    }
    {
        ssize_t w = write(2, msg, sizeof msg - 1);
        w = write(2, hang_path, strlen(hang_path));
        w = write(2, "\n", 1);
        (void)w;
    }
    /* Leave the input and go on with the next one (memory the hung call had
     * allocated is lost; the hang is counted as a failure). */
    if (in_input) siglongjmp(hang_jump, 1);
    _exit(2);
}

static double budget = 5.0;

static void arm(void)
{
    struct itimerval it;
    memset(&it, 0, sizeof it);
    it.it_value.tv_sec = (time_t)budget;
    it.it_value.tv_usec = (suseconds_t)((budget - floor(budget)) * 1e6);
    setitimer(ITIMER_PROF, &it, NULL);
}

static void disarm(void)
{
    struct itimerval it;
    memset(&it, 0, sizeof it);
    setitimer(ITIMER_PROF, &it, NULL);
}

static void run_one(int t, unsigned long long index, const uint8_t *data, size_t size)
{
    double t0, dt;
    cur_target = t;
    cur_index = index;
    cur_data = data;
    cur_size = size;
    cur_failed = 0;
    snprintf(hang_path, sizeof hang_path, "%s/fuzz-hang-%s-%llu.bin", out_dir, targets[t].name, index);
    t0 = cpu_now();
    if (sigsetjmp(hang_jump, 1) == 0) {
        in_input = 1;
        arm();
        targets[t].fn(data, size);
        disarm();
        in_input = 0;
    } else {
        in_input = 0;
        hangs[t]++;
        record("(time budget)", 0, "the input ran longer than --timeout", fz_current_wild > 0);
    }
    dt = cpu_now() - t0;
    stats[t].inputs++;
    stats[t].seconds += dt;
    if (dt > stats[t].max_seconds) stats[t].max_seconds = dt;
}

/* ------------------------------------------------------------ generation */

/* splitmix64: a small deterministic generator */
static uint64_t rng_next(uint64_t *s)
{
    uint64_t z = (*s += 0x9E3779B97F4A7C15ULL);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
}

static double rng_unit(uint64_t *s) { return (double)(rng_next(s) >> 11) * 0x1.0p-53; }

static void random_slot(uint8_t *p, uint64_t *s, double wild_rate)
{
    uint64_t v = rng_next(s);
    if (rng_unit(s) < wild_rate)
        p[0] = (uint8_t)(FZ_WILD_FIRST + (v & 3));
    else
        p[0] = (uint8_t)(v % FZ_WILD_FIRST);
    v = rng_next(s);
    for (int i = 0; i < 8; i++) p[1 + i] = (uint8_t)(v >> (8 * i));
}

/* Input number i of target t: fills buf, returns its size. */
static size_t make_input(uint8_t *buf, int t, unsigned long long i, uint64_t seed)
{
    static const double rates[] = {0.0, 0.0, 0.002, 0.01, 0.05, 0.3};
    uint64_t s = seed ^ (0xA24BAED4963EE407ULL * (uint64_t)(t + 1)) ^ (i * 0xD1B54A32D192ED03ULL);
    unsigned kind = (unsigned)(i % 8);
    rng_next(&s);
    if (kind <= 1) {
        /* edge case: one slot takes one special value, the rest tame */
        int ns = fz_n_special();
        unsigned long long j = i / 8;
        int which = (int)(j % (unsigned long long)ns);
        size_t k = (size_t)((j / (unsigned long long)ns) % N_SLOTS);
        for (size_t q = 0; q < N_SLOTS; q++) random_slot(buf + FZ_SLOT * q, &s, 0.0);
        fz_put_special(buf, FZ_SLOT * k, MAX_INPUT, which);
        return FZ_SLOT * N_SLOTS;
    }
    if (kind == 2) {
        /* raw bytes of random length */
        size_t n = (size_t)(rng_next(&s) % (FZ_SLOT * N_SLOTS + 1));
        for (size_t q = 0; q < n; q++) buf[q] = (uint8_t)rng_next(&s);
        return n;
    }
    {
        double rate = rates[(i / 8) % (sizeof rates / sizeof rates[0])];
        for (size_t q = 0; q < N_SLOTS; q++) random_slot(buf + FZ_SLOT * q, &s, rate);
        return FZ_SLOT * N_SLOTS;
    }
}

/* ------------------------------------------------------------ files */

static size_t read_file(const char *path, uint8_t *buf, size_t cap, int *ok)
{
    FILE *fp = fopen(path, "rb");
    size_t n;
    *ok = 0;
    if (!fp) return 0;
    n = fread(buf, 1, cap, fp);
    fclose(fp);
    *ok = 1;
    return n;
}

static int run_corpus(int t, const char *dir)
{
    char path[1024];
    DIR *d;
    struct dirent *e;
    static uint8_t buf[MAX_INPUT];
    int count = 0;
    snprintf(path, sizeof path, "%s/%s", dir, targets[t].name);
    d = opendir(path);
    if (!d) return 0;
    while ((e = readdir(d))) {
        char file[2048];
        int ok;
        size_t n;
        if (e->d_name[0] == '.') continue;
        snprintf(file, sizeof file, "%s/%s", path, e->d_name);
        n = read_file(file, buf, sizeof buf, &ok);
        if (!ok) continue;
        run_one(t, (unsigned long long)count, buf, n);
        count++;
    }
    closedir(d);
    return count;
}

/* Seeds: tame random inputs (every slot reasonable), 16 per target. */
static int write_seeds(const char *dir)
{
    static uint8_t buf[MAX_INPUT];
    mkdir(dir, 0755);
    for (int t = 0; t < N_TARGETS; t++) {
        char path[1024];
        uint64_t s = 0x5EED0000ULL + (uint64_t)t;
        snprintf(path, sizeof path, "%s/%s", dir, targets[t].name);
        mkdir(path, 0755);
        for (int k = 0; k < 16; k++) {
            char file[2048];
            size_t n = FZ_SLOT * N_SLOTS;
            for (size_t q = 0; q < N_SLOTS; q++) random_slot(buf + FZ_SLOT * q, &s, 0.0);
            snprintf(file, sizeof file, "%s/seed-%02d", path, k);
            save_input(file, buf, n);
        }
        /* one all-zero input: the low end of every range */
        {
            char file[2048];
            memset(buf, 0, FZ_SLOT * N_SLOTS);
            snprintf(file, sizeof file, "%s/seed-zeros", path);
            save_input(file, buf, FZ_SLOT * N_SLOTS);
        }
    }
    return 0;
}

/* ------------------------------------------------------------ main */

static void usage(void)
{
    printf("usage: fuzz_driver [--target NAME] [--n N] [--seed S] [--timeout SEC] [--out DIR]\n"
           "                   [--corpus DIR] [--write-seeds DIR] [--quiet] [--trace] [--strict]\n"
           "                   [--replay FILE...]\n"
           "targets:");
    for (int t = 0; t < N_TARGETS; t++) printf(" %s", targets[t].name);
    printf("\n");
}

static const char *status_name[6] = {"OK", "EINVAL", "ENOMEM", "ENOCONV", "ENONFINITE", "other"};

int main(int argc, char **argv)
{
    const char *only = NULL, *corpus = NULL;
    unsigned long long n = 10000, total = 0, failures = 0;
    uint64_t seed = 1;
    int replay_from = 0;
    static uint8_t buf[MAX_INPUT];
    double t_all = now();

    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--target") == 0 && i + 1 < argc) only = argv[++i];
        else if (strcmp(argv[i], "--n") == 0 && i + 1 < argc) n = strtoull(argv[++i], NULL, 10);
        else if (strcmp(argv[i], "--seed") == 0 && i + 1 < argc) seed = strtoull(argv[++i], NULL, 10);
        else if (strcmp(argv[i], "--timeout") == 0 && i + 1 < argc) budget = atof(argv[++i]);
        else if (strcmp(argv[i], "--corpus") == 0 && i + 1 < argc) corpus = argv[++i];
        else if (strcmp(argv[i], "--write-seeds") == 0 && i + 1 < argc) return write_seeds(argv[++i]);
        else if (strcmp(argv[i], "--quiet") == 0) quiet = 1;
        else if (strcmp(argv[i], "--strict") == 0) strict = 1;
        else if (strcmp(argv[i], "--trace") == 0) fz_trace = 1;
        else if (strcmp(argv[i], "--out") == 0 && i + 1 < argc) out_dir = argv[++i];
        else if (strcmp(argv[i], "--replay") == 0) { replay_from = i + 1; no_save = 1; break; }
        else { usage(); return strcmp(argv[i], "--help") == 0 ? 0 : 64; }
    }
    if (!(budget > 0)) budget = 5.0;
    exdex_init();
    {
        /* sigaction, not signal(): under strict POSIX feature macros glibc's
         * signal() is one-shot (System V semantics) */
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_alarm;
        sigemptyset(&sa.sa_mask);
        sigaction(SIGPROF, &sa, NULL);
    }

    for (int t = 0; t < N_TARGETS; t++) {
        int from_corpus = 0;
        if (only && strcmp(only, targets[t].name) != 0) continue;
        if (replay_from) {
            for (int i = replay_from; i < argc; i++) {
                int ok;
                size_t sz = read_file(argv[i], buf, sizeof buf, &ok);
                if (!ok) {
                    fprintf(stderr, "cannot read %s\n", argv[i]);
                    return 64;
                }
                run_one(t, (unsigned long long)(i - replay_from), buf, sz);
            }
        } else {
            for (unsigned long long i = 0; i < n; i++) {
                size_t sz = make_input(buf, t, i, seed);
                run_one(t, i, buf, sz);
            }
            if (corpus) from_corpus = run_corpus(t, corpus);
        }
        total += stats[t].inputs;
        failures += stats[t].failures;
        if (!quiet || stats[t].failures) {
            printf("%-9s %9llu inputs (%d from the corpus) %7.2f s, max %.2f ms/input, %llu failed checks "
                   "in %llu inputs, %llu hangs, %llu findings on extreme input\n          statuses:",
                   targets[t].name, stats[t].inputs, from_corpus, stats[t].seconds,
                   1e3 * stats[t].max_seconds, stats[t].failures, stats[t].failed_inputs, hangs[t], extremes[t]);
            for (int s = 0; s < 6; s++)
                if (stats[t].status[s]) printf(" %s %llu", status_name[s], stats[t].status[s]);
            printf("\n");
            for (int k = 0; k < n_notes; k++)
                if (notes[k].target == t) {
                    if (notes[k].is_min)
                        printf("          %s: %.3g (over %llu)\n", notes[k].key, notes[k].min, notes[k].count);
                    else
                        printf("          %s: %llu\n", notes[k].key, notes[k].count);
                }
        }
    }
    for (int pass = 0; pass < 2; pass++) {
        int any = 0;
        for (int i = 0; i < n_sites; i++) {
            if (sites[i].extreme != pass) continue;
            if (!any++)
                printf(pass ? "findings on extreme input (failures with --strict):\n" : "failed checks:\n");
            printf("  %-9s %s:%d: %s  (%llu times)\n", targets[sites[i].target].name, sites[i].file,
                   sites[i].line, sites[i].what, sites[i].count);
        }
    }
    {
        unsigned long long ext = 0;
        for (int t = 0; t < N_TARGETS; t++) ext += extremes[t];
        printf("fuzz: %llu inputs, %llu failed checks, %llu findings on extreme input, %.1f s\n", total, failures,
               ext, now() - t_all);
    }
    return failures ? 1 : 0;
}
