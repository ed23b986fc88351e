/* Benchmark driver: m2c_bench SOLVER REPS < wire lines (as the testee reads).
 * SOLVER is m2c or gsl.  Polynomials are grouped by degree; each group is
 * solved REPS times in-process, each pass timed with CLOCK_MONOTONIC.
 * Prints per degree: "DEGREE MEDIAN_NS_PER_SOLVE FOUND CHECKSUM". */
#define _POSIX_C_SOURCE 199309L
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "m2c_roots.h"

#define MAXP 100000

static double from_hex(const char *s)
{
    uint64_t u = strtoull(s, 0, 16);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e9 + ts.tv_nsec;
}

typedef struct {
    double lo, hi, c[M2C_MAX_DEGREE + 1];
} poly;

static poly polys[M2C_MAX_DEGREE + 1][MAXP / 8];
static int counts[M2C_MAX_DEGREE + 1];

/* One timed pass over the np polynomials of one degree: ns per solve; the
 * number found and the sum of the roots into *found and *sum.  A function of
 * its own: GCC compiles main, run once, for size (a library call for each
 * inlined sqrt, say), which is not how a caller's hot loop is compiled.  The
 * solver is a constant in each copy (pass_m2c, pass_gsl): with it a variable,
 * the loop tested it on every solve and, short of registers, kept its count
 * of roots in memory. */
__attribute__((always_inline)) static inline double pass(int gsl, int deg, int np, int *found, double *sum)
{
    int nf = 0;
    double s = 0.0;
    double t0 = now_ns();
    for (int i = 0; i < np; i++) {
        double t;
        const poly *p = &polys[deg][i];
        int k = gsl ? m2c_smallest_root_gsl(p->c, deg, p->lo, p->hi, &t)
                    : m2c_smallest_root(p->c, deg, p->lo, p->hi, &t);
        if (k == 1) {
            nf++;
            s += t;
        }
    }
    double t1 = now_ns();
    *found = nf;
    *sum = s;
    return (t1 - t0) / np;
}

__attribute__((noinline)) static double pass_m2c(int deg, int np, int *found, double *sum)
{
    return pass(0, deg, np, found, sum);
}

__attribute__((noinline)) static double pass_gsl(int deg, int np, int *found, double *sum)
{
    return pass(1, deg, np, found, sum);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: m2c_bench m2c|gsl REPS < cases\n");
        return 2;
    }
    int gsl = strcmp(argv[1], "gsl") == 0;
    int reps = atoi(argv[2]);
    if (reps < 1 || reps > 10000)
        return 2;
    char op[32], seq[64], tok[32];
    while (scanf("%31s %63s", op, seq) == 2) {
        double lo, hi;
        int count;
        if (scanf("%31s", tok) != 1)
            return 2;
        lo = from_hex(tok);
        if (scanf("%31s", tok) != 1)
            return 2;
        hi = from_hex(tok);
        if (scanf("%d", &count) != 1 || count < 1 || count > M2C_MAX_DEGREE + 1)
            return 2;
        int deg = count - 1;
        if (counts[deg] >= MAXP / 8)
            return 2;
        poly *p = &polys[deg][counts[deg]++];
        p->lo = lo;
        p->hi = hi;
        for (int i = 0; i < count; i++) {
            if (scanf("%31s", tok) != 1)
                return 2;
            p->c[i] = from_hex(tok);
        }
    }
    static double times[10000];
    for (int deg = 0; deg <= M2C_MAX_DEGREE; deg++) {
        int np = counts[deg];
        if (np == 0)
            continue;
        int found = 0;
        double sum = 0.0;
        for (int r = -1; r < reps; r++) {
            double ns = gsl ? pass_gsl(deg, np, &found, &sum) : pass_m2c(deg, np, &found, &sum);
            if (r >= 0)
                times[r] = ns;
        }
        qsort(times, (size_t)reps, sizeof times[0], cmp);
        printf("%d %.3f %d %.17g\n", deg, times[reps / 2], found, sum);
    }
    return 0;
}
