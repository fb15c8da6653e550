/* libfuzzer_main.c -- libFuzzer entry point for one target of fuzz.h.
 * Built by `make -C csrc fuzz` with clang -fsanitize=fuzzer,address,undefined
 * and -DFUZZ_TARGET=<name>; a failed check aborts, so libFuzzer saves the
 * input (crash-<sha1>) and prints how to reproduce it. */
#include "fuzz.h"

#include <stdio.h>
#include <stdlib.h>

#ifndef FUZZ_TARGET
#error "build with -DFUZZ_TARGET=<name> (one of FUZZ_TARGETS in fuzz.h)"
#endif
#define FUZZ_CAT2(a, b) a##b
#define FUZZ_CAT(a, b) FUZZ_CAT2(a, b)

void fuzz_fail(const char *target, const char *file, int line, const char *what)
{
    fprintf(stderr, "FAIL %s: %s:%d: %s\n", target, file, line, what);
    abort();
}

void fuzz_extreme(const char *target, const char *file, int line, const char *what)
{
    const char *strict = getenv("FUZZ_STRICT");
    if (strict && strict[0] == '1') fuzz_fail(target, file, line, what);
}

void fuzz_count_status(const char *target, int status) { (void)target; (void)status; }
void fuzz_note_count(const char *target, const char *key) { (void)target; (void)key; }
void fuzz_note_keep(const char *target, const char *key) { (void)target; (void)key; }
void fuzz_note_min(const char *target, const char *key, double value)
{
    (void)target;
    (void)key;
    (void)value;
}

int LLVMFuzzerInitialize(int *argc, char ***argv)
{
    (void)argc;
    (void)argv;
    exdex_init();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    return FUZZ_CAT(fuzz_, FUZZ_TARGET)(data, size);
}
