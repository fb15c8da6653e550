/* run_tests.c -- runner of the exdex C suite.
 *
 *   run_tests [--data FILE] [--values] [--times] [--skip NAME] [--shard K/N]
 *             [--salt N] [NAME-FILTER]
 *
 * Runs every registered test whose name contains NAME-FILTER and not the
 * --skip text, prints one line per test (with --times, the test's CPU seconds
 * after it) and a closing "N passed, N failed" line, and exits 1 on failure
 * (2 on a bad argument). --shard K/N (1 <= K <= N) runs the K-th of N parts
 * of those tests, every N-th from the K-th: the N parts together run each
 * selected test once, so a slow runner (valgrind) can run them in parallel.
 * A test's random inputs come from its seed (check_seed, a hash of its name);
 * --salt N (N > 0) mixes N into every seed, so the suite draws other inputs
 * (the long run's sweep of the random tests). */
#include "check.h"
#include "../exdex.h"

#include <stdlib.h>
#include <string.h>
#include <time.h>

#define MAX_TESTS 512
#define MAX_REFS 1024

static struct { const char *name, *file; check_fn fn; } tests[MAX_TESTS];
static int n_tests;
static int current_failed;
static int print_values;
static int print_times;
static struct { char key[96]; double value; } refs[MAX_REFS];
static int n_refs;
static const char *data_path = "../tests/data/reference.dat";
static unsigned long long current_seed = 1;

unsigned long long check_seed(void) { return current_seed; }

static unsigned long long seed_salt;

/* FNV-1a of the name, then of the salt's 8 bytes where one is given; never 0 */
static unsigned long long name_seed(const char *name)
{
    unsigned long long h = 1469598103934665603ULL;
    for (; *name; name++) h = (h ^ (unsigned char)*name) * 1099511628211ULL;
    if (seed_salt)
        for (int b = 0; b < 8; b++) h = (h ^ ((seed_salt >> (8 * b)) & 0xff)) * 1099511628211ULL;
    return h ? h : 1;
}

void check_register(const char *name, const char *file, check_fn fn)
{
    if (n_tests < MAX_TESTS) {
        tests[n_tests].name = name;
        tests[n_tests].file = file;
        tests[n_tests].fn = fn;
        n_tests++;
    }
}

void check_fail(const char *file, int line, const char *msg)
{
    if (current_failed < 5) printf("    %s:%d: ENSURE(%s) failed\n", file, line, msg);
    current_failed++;
}

void check_fail_close(const char *file, int line, const char *a, const char *b,
                      double va, double vb, double tol)
{
    if (current_failed < 5)
        printf("    %s:%d: |%s - %s| = |%.17g - %.17g| = %.3g > %.3g\n", file, line, a, b,
               va, vb, fabs(va - vb), tol);
    current_failed++;
}

static void load_refs(void)
{
    FILE *f = fopen(data_path, "r");
    char line[512];
    if (!f) {
        printf("cannot open reference data %s\n", data_path);
        return;
    }
    while (fgets(line, sizeof line, f)) {
        char key[96];
        double v;
        char *hash = strchr(line, '#');
        if (hash) *hash = '\0';
        if (sscanf(line, "%95s %lf", key, &v) == 2 && n_refs < MAX_REFS) {
            strcpy(refs[n_refs].key, key);
            refs[n_refs].value = v;
            n_refs++;
        }
    }
    fclose(f);
}

double ref(const char *key)
{
    for (int i = 0; i < n_refs; i++)
        if (strcmp(refs[i].key, key) == 0) return refs[i].value;
    printf("    missing reference value '%s' in %s\n", key, data_path);
    current_failed++;
    return NAN;
}

void report(const char *key, double value)
{
    if (print_values) printf("VALUE %s %.17g\n", key, value);
}

int main(int argc, char **argv)
{
    const char *filter = NULL, *skip = NULL;
    int passed = 0, failed = 0, shard_k = 1, shard_n = 1, selected = 0;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--data") == 0 && i + 1 < argc)
            data_path = argv[++i];
        else if (strcmp(argv[i], "--values") == 0)
            print_values = 1;
        else if (strcmp(argv[i], "--times") == 0)
            print_times = 1;
        else if (strcmp(argv[i], "--skip") == 0 && i + 1 < argc)
            skip = argv[++i];
        else if (strcmp(argv[i], "--shard") == 0 && i + 1 < argc) {
            char tail;
            if (sscanf(argv[++i], "%d/%d%c", &shard_k, &shard_n, &tail) != 2 || shard_n < 1 ||
                shard_k < 1 || shard_k > shard_n) {
                printf("--shard must be K/N with 1 <= K <= N, got '%s'\n", argv[i]);
                return 2;
            }
        } else if (strcmp(argv[i], "--salt") == 0 && i + 1 < argc) {
            char tail;
            if (sscanf(argv[++i], "%llu%c", &seed_salt, &tail) != 1 || seed_salt == 0) {
                printf("--salt must be a whole number > 0, got '%s'\n", argv[i]);
                return 2;
            }
        } else
            filter = argv[i];
    }
    exdex_init();
    load_refs();
    for (int i = 0; i < n_tests; i++) {
        if (filter && !strstr(tests[i].name, filter)) continue;
        if (skip && strstr(tests[i].name, skip)) continue;
        if (selected++ % shard_n != shard_k - 1) continue;
        current_failed = 0;
        current_seed = name_seed(tests[i].name);
        clock_t c0 = clock();
        tests[i].fn();
        double sec = (double)(clock() - c0) / CLOCKS_PER_SEC;
        if (current_failed) {
            printf("FAIL %s (%s)", tests[i].name, tests[i].file);
            failed++;
        } else {
            printf("ok   %s", tests[i].name);
            passed++;
        }
        if (print_times) printf("  %.3f s", sec);
        printf("\n");
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
