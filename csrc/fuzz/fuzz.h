/* fuzz.h -- fuzz harnesses of the exdex C core.
 *
 * Every public entry point of csrc/exdex.h is driven with decoded, structured
 * inputs: extreme magnitudes, zeros, denormals, NaN and infinity mixed into
 * otherwise reasonable values. Checks on every input:
 *   - no crash (run under ASan/UBSan or valgrind to see memory errors),
 *   - no hang (a time budget per input: the driver's --timeout, libFuzzer's
 *     -timeout),
 *   - EXDEX_OK implies finite outputs (no NaN or infinity out of finite,
 *     valid input), plus cheap physical/contract invariants per target,
 *   - invalid input (a non-finite or out-of-range field that must be
 *     validated) gives a non-OK status code.
 *
 * Two drivers run the same targets (fuzz_<name>.c):
 *
 *   1. driver.c: plain C99, builds with gcc, no extra tools. Deterministic
 *      random + systematic edge-case inputs, then the seed corpus. Part of the
 *      normal test suite (tests/scenarios/test_hardening.py runs `make -C csrc fuzz-quick`):
 *         make -C csrc fuzz-quick                  # 10^5 inputs in total
 *         make -C csrc fuzz-long FUZZ_N=1000000    # 10^6 inputs per target
 *         make -C csrc fuzz-asan                   # the quick run under ASan+UBSan
 *         build/fuzz_driver --help                 # all options (target, seed, replay)
 *      A failing input is written to fuzz-fail-<target>-<n>.bin; replay it with
 *         build/fuzz_driver --target NAME --replay FILE
 *
 *   2. libfuzzer_main.c: coverage-guided libFuzzer, needs clang
 *      (Debian/Ubuntu: apt-get install -y clang). One binary per target:
 *         make -C csrc fuzz FUZZ_TIME=60           # each target 60 s
 *         make -C csrc fuzz FUZZ_RUNS=1000000      # or a number of inputs
 *      New corpus entries go to csrc/build-fuzz/corpus/<target>/; the seed
 *      corpus csrc/fuzz/corpus/<target>/ is read, never written.
 *      Regenerate the seed corpus: build/fuzz_driver --write-seeds fuzz/corpus
 *
 * Adding an entry point: write `int fuzz_<name>(const uint8_t *, size_t)`
 * in a new csrc/fuzz/fuzz_<name>.c (decode with the fz_* readers below,
 * check with FZ_CHECK) and add X(<name>) to FUZZ_TARGETS below. The
 * Makefile builds every fuzz_<name>.c of this folder (and a libFuzzer binary
 * per such file); the driver and the seed writer find the target through
 * the list. input.c is the decoder, driver.c and libfuzzer_main.c the mains.
 *
 * Input format: a sequence of 9-byte slots, each read by one fz_* call; the
 * slot's first byte selects how the value is made:
 *   0..251  a reasonable value in the range the target asks for, from the
 *           little-endian 64-bit number in bytes 1..8 (u = bits 63..11 / 2^53);
 *   252,253 "wild": a special value, byte 1 indexes the table (NaN, +-inf,
 *           +-0, denormals, +-DBL_MIN, +-DBL_MAX, 1e+-300, eps, ...);
 *   254     wild: the raw IEEE bits of bytes 1..8;
 *   255     wild: a log-uniform magnitude 1e-300..1e300 of either sign.
 * Missing bytes read as 0, so every byte string is an input and reading past
 * the end gives the low end of each range. A wild slot is recorded (fz->wild), so a target knows when its
 * input was extreme and can demand a status code for non-finite values.
 */
#ifndef EXDEX_FUZZ_H
#define EXDEX_FUZZ_H

#include <stddef.h>
#include <stdint.h>

#include "../exdex.h"

#define FZ_SLOT 9
#define FZ_WILD_FIRST 252  /* selectors 252..255 are wild */

typedef struct fz {
    const uint8_t *p;
    size_t n, pos;
    int wild;       /* number of wild slots read so far */
    int nonfinite;  /* number of non-finite doubles handed out */
} fz;

void fz_init(fz *f, const uint8_t *data, size_t size);
extern int fz_trace;  /* 1: print every decoded value to stderr (driver --trace) */

/* A double: reasonable in [lo, hi], or wild. */
double fz_num(fz *f, double lo, double hi);
/* A double with a log-uniform magnitude in [lo, hi] (0 < lo < hi), or wild. */
double fz_log(fz *f, double lo, double hi);
/* An int: reasonable in [lo, hi], or wild (any int). */
int fz_int(fz *f, int lo, int hi);
/* An int in [lo, hi], never wild (for choices that only steer decoding). */
int fz_pick(fz *f, int lo, int hi);

/* Number of special values and the value of index i (for seeds and tests). */
int fz_n_special(void);
double fz_special(int i);

/* Slot writers for the seed generators and the driver: a reasonable value
 * u in [0, 1) of the range, or a wild one. */
size_t fz_put_tame(uint8_t *buf, size_t pos, size_t cap, double u);
size_t fz_put_special(uint8_t *buf, size_t pos, size_t cap, int special_index);

/* Failure report: defined by each driver (libFuzzer: abort; driver: record). */
void fuzz_fail(const char *target, const char *file, int line, const char *what);

#define FZ_CHECK(target, cond)                                              \
    do {                                                                    \
        if (!(cond)) fuzz_fail(target, __FILE__, __LINE__, #cond);          \
    } while (0)

/* A check whose failure on an input with wild slots (extreme magnitudes,
 * denormals, ...) is recorded as a finding on extreme input: listed with its
 * first reproducer, but a failure only with the driver's --strict (libFuzzer:
 * FUZZ_STRICT=1 in the environment). On a tame input it is a FZ_CHECK. Used
 * for "finite output" and accuracy checks whose known failures need data
 * beyond ~1e150 or below ~1e-150 (see the findings in the driver's output). */
void fuzz_extreme(const char *target, const char *file, int line, const char *what);
#define FZ_EXTREME(target, f, cond)                                         \
    do {                                                                    \
        if (!(cond)) {                                                      \
            if ((f)->wild) fuzz_extreme(target, __FILE__, __LINE__, #cond); \
            else fuzz_fail(target, __FILE__, __LINE__, #cond);              \
        }                                                                   \
    } while (0)

/* Wild slots read since the last fz_init (for the driver's hang report). */
extern int fz_current_wild;

/* Statistics a target reports (the driver prints them; libFuzzer ignores
 * them): every status returned by the library, and named notes: a count
 * ("multiroot ENOCONV") or the smallest value seen ("min stop gap"). */
void fuzz_count_status(const char *target, int status);
void fuzz_note_count(const char *target, const char *key);
void fuzz_note_min(const char *target, const char *key, double value);
/* A count like fuzz_note_count that also keeps the first input seen
 * (OUT/fuzz-note-<target>-<k>.bin), for cases worth a closer look. */
void fuzz_note_keep(const char *target, const char *key);

/* The targets: X(name) for each fuzz_<name>(data, size). */
#define FUZZ_TARGETS(X) \
    X(friction)         \
    X(motion)           \
    X(simulate)         \
    X(cone)             \
    X(tool)             \
    X(misc)             \
    X(ldp)              \
    X(grip)             \
    X(stepper)          \
    X(region)           \
    X(limitsurf)        \
    X(pads)

#define FUZZ_DECLARE(name) int fuzz_##name(const uint8_t *data, size_t size);
FUZZ_TARGETS(FUZZ_DECLARE)
#undef FUZZ_DECLARE

/* Helpers shared by the targets. */
int fz_all_finite(const double *x, size_t n);
void fz_quat_to_R(double R[9], const double q[4]);  /* q need not be unit */

/* A decoded gripper motion (fuzz_motion.c); arrays live in the struct, def
 * points into them. used_nonfinite: a field the kind validates is non-finite. */
#define FZ_MAX_SAMPLES 16
typedef struct fz_motion {
    exdex_motion_def def;
    double times[FZ_MAX_SAMPLES], poses[FZ_MAX_SAMPLES * 7];
    double R0[9], p0[3];
    int have_R0, have_p0;
    int used_nonfinite;
    exdex_motion_def pieces[5];   /* chain pieces */
} fz_motion;
void fz_decode_motion(fz *f, fz_motion *m);

#endif
