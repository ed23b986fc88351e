/* The C simulator's program (docs/simulator.md): reads a compiled scene on
 * stdin and writes the flat trace on stdout; on a stuck or bad scene it
 * writes `X message` and exits 1.  Built by `max2code simulate --lang c`
 * (max2code/targets/c.py) with the generated circle_circle.c and
 * point_edge.c, and with the numbers of variants their NAME_variant
 * functions index:
 *
 *   -DM2C_SIM_CC_VARIANTS=N -DM2C_SIM_PE_VARIANTS=M
 *
 * `m2c_sim --step DT` drives the world in steps of DT instead (as the
 * reference's sim_main --step: every body's state after each step on
 * stderr); the trace must be the same bytes.
 *
 * `m2c_sim --check-format N` instead compares the trace's number writer with
 * printf("%.17g") on N pseudo-random doubles (exit 1 on any difference). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_sim.h"
#include "m2c_world.h"

enum { M2C_WORLD_ERROR_MAX_COPY = 512 };

#ifndef M2C_SIM_CC_VARIANTS
#error "build with -DM2C_SIM_CC_VARIANTS=N (the variants circle_circle_variant indexes)"
#endif
#ifndef M2C_SIM_PE_VARIANTS
#error "build with -DM2C_SIM_PE_VARIANTS=N (the variants point_edge_variant indexes)"
#endif

static char *read_all(FILE *f)
{
    size_t n = 0, cap = 1 << 16;
    char *buf = malloc(cap);
    if (buf == NULL)
        return NULL;
    for (;;) {
        if (cap - n < 2) {
            char *b = realloc(buf, 2 * cap);
            if (b == NULL) {
                free(buf);
                return NULL;
            }
            buf = b;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0)
            break;
    }
    if (ferror(f)) {
        free(buf);
        return NULL;
    }
    buf[n] = '\0';
    return buf;
}

static uint64_t rng_state = UINT64_C(0x9E3779B97F4A7C15);

static uint64_t next_random(void)
{
    /* xorshift64* */
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * UINT64_C(2685821657736338717);
}

static int check_format(long long n)
{
    long long bad = 0;
    char mine[M2C_SIM_NUMBER_MAX + 1], ref[64];
    for (long long k = 0; k < n; k++) {
        uint64_t u = next_random();
        double x;
        switch (k % 5) {
        case 0:                                     /* any bit pattern */
            memcpy(&x, &u, sizeof x);
            break;
        case 1:                                     /* decimals with few digits */
            x = (double)(int64_t)(u % 2000001u) / 1000.0 - 1000.0;
            break;
        case 2:                                     /* 53-bit mantissas, exponents -200..+100 */
            x = ldexp((double)(u >> 11), (int)(next_random() % 300u) - 253);
            break;
        case 3:                                     /* integers */
            x = (double)(int64_t)(u >> 12) * ((u & 1u) ? -1.0 : 1.0);
            break;
        default:                                    /* simulation-like magnitudes */
            x = ((double)(u >> 11) / 9007199254740992.0 - 0.5) * pow(10.0, (double)(int)(next_random() % 40u) - 20);
            break;
        }
        int len = m2c_sim_format_number(mine, x);
        mine[len] = '\0';
        if (isnan(x))
            strcpy(ref, "nan");
        else
            snprintf(ref, sizeof ref, "%.17g", x);
        if (strcmp(mine, ref) != 0 && bad++ < 10)
            printf("%a: %s, printf %s\n", x, mine, ref);
    }
    printf("%lld of %lld numbers differ from printf(\"%%.17g\")\n", bad, n);
    return bad != 0;
}

static void count_contact(const m2c_contact *c, void *user)
{
    (void)c;
    (*(long long *)user)++;
}

static void put_number(FILE *f, double x)
{
    char buf[M2C_SIM_NUMBER_MAX + 1];
    buf[m2c_sim_format_number(buf, x)] = '\0';
    fputs(buf, f);
}

/* The scene through the live API in steps of dt (the reference's
 * sim_main --step): advance(k dt) for k = 1, 2, ... below the end, each
 * followed by every body's state at k dt (P lines) and the number of
 * contacts (C line) on probe, then finish.  0, or -1 (m2c_world_error). */
static int stepped(m2c_world *w, double end, double dt, FILE *probe)
{
    int n = m2c_world_body_count(w);
    for (long long k = 1; (double)k * dt < end; k++) {
        double t = (double)k * dt;
        long long got = 0;
        if (m2c_world_advance(w, t, count_contact, &got) != 0)
            return -1;
        for (int b = 0; b < n; b++) {
            m2c_body_state st;
            if (m2c_world_state(w, b, t, &st) != 0)
                return -1;
            fputs("P ", probe);
            put_number(probe, t);
            fprintf(probe, " %d", b);
            const double v[6] = { st.x, st.y, st.vx, st.vy, st.angle, st.omega };
            for (int q = 0; q < 6; q++) {
                fputc(' ', probe);
                put_number(probe, v[q]);
            }
            fputc('\n', probe);
        }
        fputs("C ", probe);
        put_number(probe, t);
        fprintf(probe, " %lld\n", got);
    }
    return m2c_world_finish(w, NULL, NULL);
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--check-format") == 0)
        return check_format(atoll(argv[2]));
    double dt = 0.0;
    if (argc == 3 && strcmp(argv[1], "--step") == 0) {
        char *rest;
        dt = strtod(argv[2], &rest);
        if (*rest != '\0' || !(dt > 0.0)) {
            fprintf(stderr, "%s: --step wants a positive number of seconds\n", argv[0]);
            return 2;
        }
    } else if (argc != 1) {
        fprintf(stderr, "usage: %s [--step DT] < SCENE   (or --check-format N)\n", argv[0]);
        return 2;
    }
    char *text = read_all(stdin);
    if (text == NULL) {
        printf("X cannot read the scene\n");
        return 1;
    }
    m2c_world *w = m2c_world_new(text, stdout);
    free(text);
    if (w == NULL) {
        printf("X %s\n", m2c_world_last_error());
        return 1;
    }
    int status;
    if (dt > 0.0) {
        status = stepped(w, m2c_world_end_time(w), dt, stderr);
    } else {
        status = m2c_world_advance(w, m2c_world_end_time(w), NULL, NULL);
        if (status == 0)
            status = m2c_world_finish(w, NULL, NULL);
    }
    if (status != 0) {
        char err[M2C_WORLD_ERROR_MAX_COPY];
        snprintf(err, sizeof err, "%s", m2c_world_error(w));
        m2c_world_free(w);          /* flushes the trace written so far */
        printf("X %s\n", err);
        fflush(stdout);
        return 1;
    }
    m2c_world_free(w);
    return fflush(stdout) == 0 ? 0 : 1;
}
