/* input.c -- the slot decoder shared by every fuzz target (format in fuzz.h). */
#include "fuzz.h"

#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

static const double special[] = {
    NAN, INFINITY, -INFINITY, 0.0, -0.0,
    4.9406564584124654e-324,   /* smallest denormal */
    -4.9406564584124654e-324,
    1.1125369292536007e-308,   /* a denormal, DBL_MIN / 2 */
    -1.1125369292536007e-308,
    DBL_MIN, -DBL_MIN, DBL_MAX, -DBL_MAX,
    1e-300, -1e-300, 1e300, -1e300, 1e-150, 1e150,
    1.0, -1.0, 0.5, 2.0, DBL_EPSILON, 1.0 + DBL_EPSILON, 1.0 - DBL_EPSILON / 2,
    1e-16, 1e16, 1e-8, 1e8,
};
#define N_SPECIAL ((int)(sizeof special / sizeof special[0]))

int fz_n_special(void) { return N_SPECIAL; }
double fz_special(int i) { return special[((i % N_SPECIAL) + N_SPECIAL) % N_SPECIAL]; }

int fz_trace;
int fz_current_wild;

static double traced(double x, const char *how)
{
    if (fz_trace) fprintf(stderr, "  fz %-4s %.17g\n", how, x);
    return x;
}

void fz_init(fz *f, const uint8_t *data, size_t size)
{
    f->p = data;
    f->n = size;
    f->pos = 0;
    f->wild = 0;
    f->nonfinite = 0;
    fz_current_wild = 0;
}

/* The next slot: selector and the 8 payload bytes (missing bytes are 0). */
static uint8_t slot(fz *f, uint8_t b[8])
{
    uint8_t sel = 0;
    memset(b, 0, 8);
    if (f->pos < f->n) sel = f->p[f->pos];
    for (int i = 0; i < 8; i++)
        if (f->pos + 1 + (size_t)i < f->n) b[i] = f->p[f->pos + 1 + (size_t)i];
    f->pos += FZ_SLOT;
    return sel;
}

static uint64_t le64(const uint8_t b[8])
{
    uint64_t v = 0;
    for (int i = 7; i >= 0; i--) v = (v << 8) | b[i];
    return v;
}

static double unit(const uint8_t b[8]) { return (double)(le64(b) >> 11) * 0x1.0p-53; }

static double wild_double(fz *f, uint8_t sel, const uint8_t b[8])
{
    double x;
    f->wild++;
    fz_current_wild++;
    if (sel < 254) {
        x = special[b[0] % N_SPECIAL];
    } else if (sel == 254) {
        uint64_t bits = le64(b);
        memcpy(&x, &bits, sizeof x);
    } else {
        /* sign from bit 0 of byte 0, exponent -300..300 from bytes 1-2,
         * mantissa 1..10 from bytes 3-4 */
        int e = (int)((b[1] | (b[2] << 8)) % 601) - 300;
        double m = 1.0 + 9.0 * (double)(b[3] | (b[4] << 8)) / 65536.0;
        x = ((b[0] & 1) ? -1.0 : 1.0) * m * pow(10.0, e);
    }
    if (!isfinite(x)) f->nonfinite++;
    return x;
}

double fz_num(fz *f, double lo, double hi)
{
    uint8_t b[8], sel = slot(f, b);
    if (sel >= FZ_WILD_FIRST) return traced(wild_double(f, sel, b), "num*");
    return traced(lo + (hi - lo) * unit(b), "num");
}

double fz_log(fz *f, double lo, double hi)
{
    uint8_t b[8], sel = slot(f, b);
    if (sel >= FZ_WILD_FIRST) return traced(wild_double(f, sel, b), "log*");
    return traced(exp(log(lo) + (log(hi) - log(lo)) * unit(b)), "log");
}

int fz_int(fz *f, int lo, int hi)
{
    uint8_t b[8], sel = slot(f, b);
    if (sel >= FZ_WILD_FIRST) {
        static const int sp[] = {INT_MIN, INT_MAX, -1, 0, 1 << 30, -(1 << 30), 255, 1000};
        f->wild++;
        fz_current_wild++;
        if (sel < 254) {
            if (b[0] & 1) return (int)traced((b[0] & 2) ? lo - 1 - (b[1] & 3) : hi + 1 + (b[1] & 3), "int*");
            return (int)traced(sp[b[1] % (sizeof sp / sizeof sp[0])], "int*");
        }
        {
            uint32_t u = (uint32_t)le64(b);
            int v;
            memcpy(&v, &u, sizeof v);
            return (int)traced(v, "int*");
        }
    }
    return (int)traced(lo + (int)(le64(b) % (uint64_t)((long long)hi - lo + 1)), "int");
}

int fz_pick(fz *f, int lo, int hi)
{
    uint8_t b[8];
    (void)slot(f, b);
    return (int)traced(lo + (int)(le64(b) % (uint64_t)((long long)hi - lo + 1)), "pick");
}

size_t fz_put_tame(uint8_t *buf, size_t pos, size_t cap, double u)
{
    uint64_t v;
    if (pos + FZ_SLOT > cap) return pos;
    if (!(u >= 0.0)) u = 0.0;
    if (u >= 1.0) u = 1.0 - DBL_EPSILON;
    v = (uint64_t)(u * 0x1.0p53) << 11;
    buf[pos] = 0;
    for (int i = 0; i < 8; i++) buf[pos + 1 + (size_t)i] = (uint8_t)(v >> (8 * i));
    return pos + FZ_SLOT;
}

size_t fz_put_special(uint8_t *buf, size_t pos, size_t cap, int special_index)
{
    if (pos + FZ_SLOT > cap) return pos;
    memset(buf + pos, 0, FZ_SLOT);
    buf[pos] = FZ_WILD_FIRST;
    buf[pos + 1] = (uint8_t)(((special_index % N_SPECIAL) + N_SPECIAL) % N_SPECIAL);
    return pos + FZ_SLOT;
}

int fz_all_finite(const double *x, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!isfinite(x[i])) return 0;
    return 1;
}
