/* Box2D v3's b2TimeOfImpact for two balls on rigid motions, as driven by
 * bench/toi.py: the horizon is cut into 60 Hz steps (Box2D's sweep
 * interpolates one step's rotation), each step swept from the poses at its
 * ends, the first hit answers.
 *
 * stdin: "REPS" then rows of 17 numbers: per body (1 then 2) the rotation
 * centre's x, y at t = 0, its velocity, the angular velocity, the ball's
 * offset from the centre at t = 0 and its radius; then the horizon.
 * stdout: "b2 T" per row (T the time of impact, "none" when there is none)
 * and, when REPS > 0, "ns b2 X": the median over REPS passes of ns per
 * query. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "box2d/collision.h"
#include "box2d/math_functions.h"

#define FIELDS 17
#define STEP (1.0 / 60.0)

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* body k's sweep over [t0, t1]: the centre moves on its line, the ball's
 * frame turns about it */
static b2Sweep sweep(const double *b, double t0, double t1)
{
    b2Sweep s;
    s.localCenter = (b2Vec2){(float)-b[5], (float)-b[6]};
    s.c1 = (b2Vec2){(float)(b[0] + b[2] * t0), (float)(b[1] + b[3] * t0)};
    s.c2 = (b2Vec2){(float)(b[0] + b[2] * t1), (float)(b[1] + b[3] * t1)};
    s.q1 = b2MakeRot((float)(b[4] * t0));
    s.q2 = b2MakeRot((float)(b[4] * t1));
    return s;
}

/* 1 and *t at the first hit, 0 none */
static int toi(const double *r, double *t)
{
    b2Vec2 origin = {0.0f, 0.0f};
    b2TOIInput in;
    in.proxyA = b2MakeProxy(&origin, 1, (float)r[7]);
    in.proxyB = b2MakeProxy(&origin, 1, (float)r[15]);
    in.maxFraction = 1.0f;
    double horizon = r[16];
    for (double t0 = 0.0; t0 < horizon; t0 += STEP) {
        double t1 = t0 + STEP < horizon ? t0 + STEP : horizon;
        in.sweepA = sweep(r, t0, t1);
        in.sweepB = sweep(r + 8, t0, t1);
        b2TOIOutput out = b2TimeOfImpact(&in);
        if (out.state == b2_toiStateHit || out.state == b2_toiStateOverlapped) {
            *t = t0 + (double)out.fraction * (t1 - t0);
            return 1;
        }
    }
    return 0;
}

int main(void)
{
    int reps = 0;
    if (scanf("%d", &reps) != 1)
        return 1;
    size_t cap = 1024, n = 0;
    double *v = malloc(cap * sizeof *v), x;
    while (v && scanf("%lf", &x) == 1) {
        if (n == cap) {
            cap *= 2;
            v = realloc(v, cap * sizeof *v);
        }
        if (v)
            v[n++] = x;
    }
    if (!v)
        return 1;
    size_t rows = n / FIELDS;
    for (size_t i = 0; i < rows; i++) {
        double t = 0.0;
        if (toi(v + i * FIELDS, &t))
            printf("b2 %.17g\n", t);
        else
            printf("b2 none\n");
    }
    if (reps > 0 && rows > 0) {
        double *times = malloc((size_t)reps * sizeof *times), sink = 0.0;
        if (!times)
            return 1;
        for (int k = 0; k < reps; k++) {
            double t0 = now_ns();
            for (size_t i = 0; i < rows; i++) {
                double t = 0.0;
                sink += toi(v + i * FIELDS, &t) + t;
            }
            times[k] = (now_ns() - t0) / (double)rows;
        }
        qsort(times, (size_t)reps, sizeof *times, cmpd);
        printf("ns b2 %.3f\n", times[reps / 2]);
        fprintf(stderr, "checksum %g\n", sink);
        free(times);
    }
    free(v);
    return 0;
}
