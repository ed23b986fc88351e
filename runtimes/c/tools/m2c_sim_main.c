/* The C simulator's program (docs/simulator.md): reads a compiled scene on
 * stdin and writes the flat trace on stdout; on a stuck or bad scene it
 * writes `X message` and exits 1.  Built by `max2code simulate --lang c`
 * (max2code/toolchain/c.py) with the generated circle_circle.c and
 * point_edge.c, the simulator's sources (src/m2c_sim*.c; -Iinclude for
 * m2c_world.h, -Isrc for m2c_sim.h) and the numbers of variants their
 * NAME_variant functions index:
 *
 *   -DM2C_SIM_CC_VARIANTS=N -DM2C_SIM_PE_VARIANTS=M
 *
 * `m2c_sim --step DT [--live]` drives the world in steps of DT instead (as
 * the reference's sim_main --step: every body's state after each step on
 * stderr; --live: the scene's inputs made as live inputs at their times);
 * the trace must be the same bytes.
 *
 * `m2c_sim --check-format N` instead compares the trace's number writer with
 * printf("%.17g") on N pseudo-random doubles of eight classes by turns (any
 * bits, few-digit decimals, 53-bit mantissas, integers, simulation-like
 * magnitudes, subnormals, powers of ten and their neighbours, zeros, ties and
 * extremes; exit 1 on any difference). */
#include <float.h>
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

/* All of f (at most TEXT_MAX + 1 bytes: a longer text is refused by its
 * length) with a NUL after it, its length in *len; NULL when it cannot be
 * read. */
static char *read_all(FILE *f, size_t *len)
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
        size_t want = cap - n - 1;
        if (want > (size_t)TEXT_MAX + 1 - n)
            want = (size_t)TEXT_MAX + 1 - n;
        size_t got = fread(buf + n, 1, want, f);
        n += got;
        if (got == 0 || n > (size_t)TEXT_MAX)
            break;
    }
    if (ferror(f)) {
        free(buf);
        return NULL;
    }
    buf[n] = '\0';
    *len = n;
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
        switch (k % 8) {
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
        case 4:                                     /* simulation-like magnitudes */
            x = ((double)(u >> 11) / 9007199254740992.0 - 0.5) * pow(10.0, (double)(int)(next_random() % 40u) - 20);
            break;
        case 5: {                                   /* subnormals */
            uint64_t b = (u & ((UINT64_C(1) << 52) - 1u)) | (u & (UINT64_C(1) << 63));
            memcpy(&x, &b, sizeof x);
            break;
        }
        case 6: {                                   /* powers of ten and their neighbours, 1e-323 .. 1e308 */
            char text[16];
            snprintf(text, sizeof text, "1e%d", (int)(next_random() % 632u) - 323);
            double pw = strtod(text, NULL);
            uint64_t b;
            memcpy(&b, &pw, sizeof b);
            b = b + (u >> 1) % 5u >= 2u ? b + (u >> 1) % 5u - 2u : 0u;
            memcpy(&x, &b, sizeof x);
            x = (u & 1u) ? -x : x;
            break;
        }
        default: {                                  /* zeros, ties at the 17th digit, extremes */
            double sign = (u & 1u) ? -1.0 : 1.0;
            switch (u % 6u) {
            case 0: x = 0.0 * sign; break;
            case 1: x = ldexp((double)(((u >> 8) % 4096u) * 2u + 1u), (int)((u >> 20) % 240u) - 120); break;
            case 2: x = DBL_MAX * sign; break;
            case 3: x = DBL_MIN * sign; break;
            case 4: x = 4.9406564584124654e-324 * sign; break;
            default: x = DBL_EPSILON * sign; break;
            }
            break;
        }
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

/* m2c_sim_parse_number against strtod on n decimals: shortest round-trip
 * and %.15g .. %.17g forms of random doubles, and random digit strings. */
static int check_parse(long long n)
{
    long long bad = 0, fast = 0;
    char text[64];
    for (long long k = 0; k < n; k++) {
        uint64_t u = next_random();
        double x;
        switch (k % 4) {
        case 0:                                     /* any finite bit pattern */
            memcpy(&x, &u, sizeof x);
            if (!isfinite(x))
                x = 1.0;
            break;
        case 1:                                     /* simulation-like magnitudes */
            x = ((double)(u >> 11) / 9007199254740992.0 - 0.5) * pow(10.0, (double)(int)(next_random() % 40u) - 20);
            break;
        case 2:                                     /* 53-bit mantissas, exponents -80..+80 */
            x = ldexp((double)(u >> 11), (int)(next_random() % 160u) - 133);
            break;
        default:                                    /* few digits */
            x = (double)(int64_t)(u % 2000001u) / 1000.0 - 1000.0;
            break;
        }
        int prec = (int)(next_random() % 4u);       /* 0: shortest, else 14 + prec digits */
        if (prec == 0) {
            for (int d = 1; d <= 17; d++) {
                snprintf(text, sizeof text, "%.*g", d, x);
                if (strtod(text, NULL) == x)
                    break;
            }
        } else {
            snprintf(text, sizeof text, "%.*g", 14 + prec, x);
        }
        if (k % 7 == 6) {                           /* random digits, point and exponent */
            int nd = 1 + (int)(next_random() % 20u), at = (int)(next_random() % 21u), q = 0;
            for (int d = 0; d < nd; d++) {
                if (d == at)
                    text[q++] = '.';
                text[q++] = (char)('0' + next_random() % 10u);
            }
            q += snprintf(text + q, sizeof text - (size_t)q, "e%d", (int)(next_random() % 60u) - 40);
        }
        double mine, ref = strtod(text, NULL);
        if (m2c_sim_parse_number(text, strlen(text), &mine)) {
            fast++;
            if (memcmp(&mine, &ref, sizeof mine) != 0 && bad++ < 10)
                printf("%s: %a, strtod %a\n", text, mine, ref);
        }
    }
    printf("%lld of %lld decimals (%lld read without strtod) differ from strtod\n", bad, n, fast);
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

/* One input line of the flat scene: T BODY MODE X Y. */
typedef struct live_input {
    double t, x, y;
    int body, mode;
} live_input;

/* The reference's split_inputs: the flat scene in text with its input
 * lines taken out (`inputs 0`), and those inputs in order into *inputs
 * (*n of them; malloc'ed).  0, or -1 with err. */
static int split_inputs(char *text, live_input **inputs, long *n, char *err, size_t errlen)
{
    *inputs = NULL;
    *n = 0;
    char *at = strstr(text, "\ninputs ");
    if (at == NULL) {
        snprintf(err, errlen, "scene: expected 'inputs'");
        return -1;
    }
    char *p = at + 8, *q;
    long k = strtol(p, &q, 10);
    if (q == p) {
        snprintf(err, errlen, "scene: expected an integer after 'inputs'");
        return -1;
    }
    if (k < 0 || k > MAX_INPUTS) {      /* before the allocation */
        snprintf(err, errlen, "scene: %ld inputs (0 to %d)", k, MAX_INPUTS);
        return -1;
    }
    p = q;
    *inputs = calloc((size_t)k + 1, sizeof **inputs);
    if (*inputs == NULL) {
        snprintf(err, errlen, "out of memory");
        return -1;
    }
    for (long i = 0; i < k; i++) {
        while (*p == ' ' || *p == '\n')
            p++;
        if (strncmp(p, "input ", 6) != 0) {
            snprintf(err, errlen, "scene: expected 'input'");
            return -1;
        }
        live_input *in = &(*inputs)[i];
        in->t = strtod(p + 6, &p);
        in->body = (int)strtol(p, &p, 10);
        in->mode = (int)strtol(p, &p, 10);
        in->x = strtod(p, &p);
        in->y = strtod(p, &p);
    }
    *n = k;
    strcpy(at, "\ninputs 0\nend\n");
    return 0;
}

/* The live operation of an input's mode (as the reference's ops, by MODE):
 * 0 done, 1 a teleport refused, -1 an error. */
static int live_op(m2c_world *w, const live_input *in)
{
    switch (in->mode) {
    case 0:
        return m2c_world_set_velocity(w, in->body, in->x, in->y);
    case 1:
        return m2c_world_add_velocity(w, in->body, in->x, in->y);
    case 2:
        return m2c_world_apply_impulse(w, in->body, in->x, in->y);
    case 3: {
        int r = m2c_world_teleport(w, in->body, in->x, in->y);
        return r < 0 ? -1 : r == 0;
    }
    default:
        return m2c_world_remove_body(w, in->body);
    }
}

/* The scene through the live API in steps of dt (the reference's
 * sim_main --step): advance(k dt) for k = 1, 2, ... below the end, each
 * followed by every body's state at k dt (P lines) and the number of
 * contacts (C line) on probe, then finish.  With inputs (--live: the
 * scene's inputs taken out of it), before each step the world advances to
 * each input's time due by then and makes it live.  0, or -1 with err. */
static int stepped(m2c_world *w, double end, double dt, FILE *probe, const live_input *inputs, long ninputs,
                   char *err, size_t errlen)
{
    int n = m2c_world_body_count(w);
    long nxt = 0;
    /* every body at once (m2c_world_states), checked against one by one */
    m2c_body_state *all = malloc(sizeof *all * (size_t)(n > 0 ? n : 1));
    if (all == NULL) {
        snprintf(err, errlen, "out of memory (states)");
        return -1;
    }
    for (long long k = 1;; k++) {
        double t = (double)k * dt;
        while (nxt < ninputs && (!(t < end) || inputs[nxt].t <= t)) {
            if (m2c_world_advance(w, inputs[nxt].t, NULL, NULL) != 0)
                goto failed;
            int r = live_op(w, &inputs[nxt]);
            if (r < 0)
                goto failed;
            if (r > 0) {
                snprintf(err, errlen, "live input %ld: teleport refused (the body would overlap another)", nxt);
                free(all);
                return -1;
            }
            nxt++;
        }
        if (!(t < end))
            break;
        long long got = 0;
        if (m2c_world_advance(w, t, count_contact, &got) != 0)
            goto failed;
        if (m2c_world_states(w, t, all, n) != 0)
            goto failed;
        for (int b = 0; b < n; b++) {
            m2c_body_state st;
            if (m2c_world_state(w, b, t, &st) != 0)
                goto failed;
            if (memcmp(&st, &all[b], sizeof st) != 0) {
                snprintf(err, errlen, "states(t) gives body %d another state than state(%d, t)", b, b);
                free(all);
                return -1;
            }
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
    if (m2c_world_finish(w, NULL, NULL) == 0) {
        free(all);
        return 0;
    }
failed:
    free(all);
    snprintf(err, errlen, "%s", m2c_world_error(w));
    return -1;
}

int main(int argc, char **argv)
{
    if (argc == 3 && strcmp(argv[1], "--check-format") == 0)
        return check_format(atoll(argv[2]));
    if (argc == 3 && strcmp(argv[1], "--check-parse") == 0)
        return check_parse(atoll(argv[2]));
    double dt = 0.0;
    int live = 0, nargs = 0;
    const char *args[3] = { NULL, NULL, NULL };
    for (int k = 1; k < argc; k++) {
        if (strcmp(argv[k], "--live") == 0)
            live = 1;
        else if (nargs < 3)
            args[nargs++] = argv[k];
        else
            nargs = 3;
    }
    if (nargs == 2 && strcmp(args[0], "--step") == 0) {
        char *rest;
        dt = strtod(args[1], &rest);
        if (*rest != '\0' || !(dt > 0.0)) {
            fprintf(stderr, "%s: --step wants a positive number of seconds\n", argv[0]);
            return 2;
        }
    } else if (nargs != 0 || live) {
        fprintf(stderr, "usage: %s [--step DT [--live]] < SCENE   (or --check-format N, --check-parse N)\n", argv[0]);
        return 2;
    }
    char err[M2C_WORLD_ERROR_MAX_COPY];
    size_t len = 0;
    char *text = read_all(stdin, &len);
    if (text == NULL) {
        printf("X cannot read the scene\n");
        return 1;
    }
    /* the bytes the scene reader cannot see: a NUL, or past TEXT_MAX; with --live, the whole text before its
     * input lines are taken out */
    if ((live || strlen(text) != len) && m2c_sim_text_check(text, len, "scene", err, sizeof err) != 0) {
        free(text);
        printf("X %s\n", err);
        return 1;
    }
    live_input *inputs = NULL;
    long ninputs = 0;
    if (live && split_inputs(text, &inputs, &ninputs, err, sizeof err) != 0) {
        free(text);
        free(inputs);
        printf("X %s\n", err);
        return 1;
    }
    m2c_world *w = m2c_world_new(text, stdout);
    free(text);
    if (w == NULL) {
        free(inputs);
        printf("X %s\n", m2c_world_last_error());
        return 1;
    }
    int status;
    if (dt > 0.0) {
        status = stepped(w, m2c_world_end_time(w), dt, stderr, inputs, ninputs, err, sizeof err);
    } else {
        status = m2c_world_advance(w, m2c_world_end_time(w), NULL, NULL);
        if (status == 0)
            status = m2c_world_finish(w, NULL, NULL);
        if (status != 0)
            snprintf(err, sizeof err, "%s", m2c_world_error(w));
    }
    free(inputs);
    m2c_world_free(w);              /* flushes the trace written so far */
    if (status != 0) {
        printf("X %s\n", err);
        fflush(stdout);
        return 1;
    }
    return fflush(stdout) == 0 ? 0 : 1;
}
