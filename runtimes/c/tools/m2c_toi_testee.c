/* The TOI library's conformance testee and timer (docs/conformance.md,
 * op "toi"; docs/toi.md).  Reads lines
 *   toi SEQ HORIZON TOL BODY_A BODY_B
 * where a body is N (0: a circle, then its radius; else N vertices x y),
 * then its motion x y vx vy ax ay angle omega orbit orbit_phase; every
 * number a hex double (16 hex digits of its bits) but N and SEQ.  Answers
 *   SEQ hit T FEATURE FIRST I J PX PY NX NY | SEQ none | SEQ overlapped | SEQ error
 * With a first argument REPS > 0 it answers each case REPS times and
 * prints, after the answers, one line `ns MEDIAN` per case (ns per query,
 * the median of REPS timed batches).  Units: s, m, rad. */
#define _POSIX_C_SOURCE 199309L
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "m2c_toi.h"

static int hexd(const char *s, double *x)
{
    char *end;
    unsigned long long u = strtoull(s, &end, 16);
    if (end == s || *end != '\0')
        return 0;
    uint64_t b = (uint64_t)u;
    memcpy(x, &b, sizeof *x);
    return 1;
}

static void puthex(double x)
{
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    printf(" %016llx", (unsigned long long)b);
}

typedef struct tcase {
    long seq;
    double horizon;
    m2c_toi_options o;
    m2c_toi_shape s[2];
    m2c_toi_motion q[2];
    int ok;
} tcase;

static char *next(char **p)
{
    return strtok_r(NULL, " \t\r\n", p);
}

static int body(char **save, m2c_toi_shape *s, m2c_toi_motion *q)
{
    char *w = next(save);
    if (w == NULL)
        return 0;
    int n = atoi(w);
    if (n == 0) {
        double r;
        if ((w = next(save)) == NULL || !hexd(w, &r) || m2c_toi_circle(s, r) != 0)
            return 0;
    } else {
        if (n < 0 || n > M2C_TOI_MAX_VERTICES)
            return 0;
        double xy[2 * M2C_TOI_MAX_VERTICES];
        for (int k = 0; k < 2 * n; k++)
            if ((w = next(save)) == NULL || !hexd(w, &xy[k]))
                return 0;
        if (m2c_toi_polygon(s, xy, n) != 0)
            return 0;
    }
    double v[10];
    for (int k = 0; k < 10; k++)
        if ((w = next(save)) == NULL || !hexd(w, &v[k]))
            return 0;
    q->x = v[0];
    q->y = v[1];
    q->vx = v[2];
    q->vy = v[3];
    q->ax = v[4];
    q->ay = v[5];
    q->angle = v[6];
    q->omega = v[7];
    q->orbit = v[8];
    q->orbit_phase = v[9];
    return 1;
}

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    long reps = argc > 1 ? atol(argv[1]) : 0;
    size_t cap = 64, n = 0;
    tcase *cs = malloc(cap * sizeof *cs);
    static char line[1 << 16];
    while (cs != NULL && fgets(line, sizeof line, stdin) != NULL) {
        char *save = NULL;
        char *w = strtok_r(line, " \t\r\n", &save);
        if (w == NULL)
            continue;
        if (n == cap) {
            cap *= 2;
            cs = realloc(cs, cap * sizeof *cs);
            if (cs == NULL)
                break;
        }
        tcase *c = &cs[n++];
        memset(c, 0, sizeof *c);
        m2c_toi_defaults(&c->o);
        char *sq = next(&save);
        c->seq = sq != NULL ? atol(sq) : -1;
        char *h = next(&save), *tl = next(&save);
        c->ok = strcmp(w, "toi") == 0 && h != NULL && tl != NULL && hexd(h, &c->horizon) && hexd(tl, &c->o.tol)
                && body(&save, &c->s[0], &c->q[0]) && body(&save, &c->s[1], &c->q[1]);
    }
    if (cs == NULL) {
        fprintf(stderr, "m2c_toi_testee: out of memory\n");
        return 1;
    }
    for (size_t k = 0; k < n; k++) {
        tcase *c = &cs[k];
        if (!c->ok) {
            printf("%ld error malformed\n", c->seq);
            continue;
        }
        m2c_toi_result r;
        int st = m2c_toi(&c->s[0], &c->q[0], &c->s[1], &c->q[1], c->horizon, &c->o, &r);
        printf("%ld", c->seq);
        if (st == M2C_TOI_HIT) {
            printf(" hit");
            puthex(r.t);
            printf(" %d %d %d %d", r.feature, r.first, (int)r.i, (int)r.j);
            puthex(r.px);
            puthex(r.py);
            puthex(r.nx);
            puthex(r.ny);
        } else if (st == M2C_TOI_NONE) {
            printf(" none");
        } else if (st == M2C_TOI_OVERLAPPED) {
            printf(" overlapped");
        } else {
            printf(" error refused");
        }
        printf("\n");
    }
    if (reps > 0) {
        enum { BATCHES = 15 };
        for (size_t k = 0; k < n; k++) {
            tcase *c = &cs[k];
            if (!c->ok)
                continue;
            double ns[BATCHES];
            volatile double sink = 0.0;
            for (int b = 0; b < BATCHES; b++) {
                double t0 = now_ns();
                for (long r = 0; r < reps; r++) {
                    m2c_toi_result res;
                    m2c_toi(&c->s[0], &c->q[0], &c->s[1], &c->q[1], c->horizon, &c->o, &res);
                    sink += res.t;
                }
                ns[b] = (now_ns() - t0) / (double)reps;
            }
            qsort(ns, BATCHES, sizeof ns[0], cmp);
            printf("ns %ld %.1f\n", c->seq, ns[BATCHES / 2]);
            (void)sink;
        }
    }
    free(cs);
    return 0;
}
