/* Reading the flat scene (docs/simulator.md, written by max2code/sim/scene.py):
 * whitespace-separated tokens; the numbers are shortest round-trip decimals,
 * which strtod reads exactly.  The messages are the reference's. */
#include <errno.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_sim_internal.h"

typedef struct reader {
    const char *p;
    const char *what;       /* the messages' prefix: "scene", "add_body" */
    char *err;
    size_t errlen;
    int failed;
} reader;

static inline int is_space(char c)
{
    return c == ' ' || (unsigned char)(c - '\t') <= (unsigned char)('\r' - '\t');     /* \t \n \v \f \r */
}

static void fail(reader *r, const char *fmt, ...)
{
    if (!r->failed) {
        va_list ap;
        va_start(ap, fmt);
        int n = snprintf(r->err, r->errlen, "%s: ", r->what);
        if (n > 0 && (size_t)n < r->errlen)
            vsnprintf(r->err + n, r->errlen - (size_t)n, fmt, ap);
        va_end(ap);
    }
    r->failed = 1;
}

/* The next token: *len characters at the returned pointer (0: none left;
 * expect: the word wanted, for the message). */
static const char *token(reader *r, size_t *len, const char *expect)
{
    const char *p = r->p;
    while (*p && is_space(*p))
        p++;
    const char *start = p;
    while ((unsigned char)*p > ' ' || (*p && !is_space(*p)))     /* above ' ': neither NUL nor a space */
        p++;
    r->p = p;
    *len = (size_t)(p - start);
    if (*len == 0) {
        if (expect != NULL)
            fail(r, "ends early (expected '%s')", expect);
        else
            fail(r, "ends early");
    }
    return start;
}

static void word(reader *r, const char *expect)
{
    size_t n;
    const char *w = token(r, &n, expect);
    if (r->failed)
        return;
    if (n != strlen(expect) || memcmp(w, expect, n) != 0)
        fail(r, "expected '%s', found '%.*s'", expect, (int)(n > 40 ? 40 : n), w);
}

__extension__ typedef unsigned __int128 u128;

/* 10^0 .. 10^22 as exact integers */
#define M2C_E19 ((u128)UINT64_C(10000000000000000000))
static const u128 pow10_exact[23] = {
    1u, 10u, 100u, 1000u, 10000u, 100000u, 1000000u, 10000000u, 100000000u, 1000000000u,
    UINT64_C(10000000000), UINT64_C(100000000000), UINT64_C(1000000000000), UINT64_C(10000000000000),
    UINT64_C(100000000000000), UINT64_C(1000000000000000), UINT64_C(10000000000000000),
    UINT64_C(100000000000000000), UINT64_C(1000000000000000000), M2C_E19, M2C_E19 * 10u, M2C_E19 * 100u,
    M2C_E19 * 1000u,
};

/* m 10^q (m >= 2^53 or q < -22, with q >= -22) as the nearest double:
 * 1 with *x, or 0 (strtod then reads it); out of line, since few numbers
 * come here. */
static __attribute__((noinline)) int exact_quotient(uint64_t m, int q, double *x)
{
    u128 pw = pow10_exact[-q];
    int bits_w = 64 - __builtin_clzll(m);
    int bits_p = (pw >> 64) != 0 ? 128 - __builtin_clzll((uint64_t)(pw >> 64))
                                 : 64 - __builtin_clzll((uint64_t)pw);
    int sh = 53 + bits_p - bits_w;          /* w 2^sh / 10^-q in (2^52, 2^54) */
    if (sh < 1)
        return 0;                           /* w >= 2^57 with a small 10^-q */
    u128 num = (u128)m << sh;
    u128 mq = num / pw;
    if (mq >> 53) {
        sh--;
        num >>= 1;                          /* exact: num had sh >= 1 zero bits at the bottom */
        mq = num / pw;
    }
    u128 rem = num - mq * pw;
    uint64_t mant = (uint64_t)mq;
    if (2u * rem > pw || (2u * rem == pw && (mant & 1u)))
        mant++;
    if (mant >> 53) {                       /* rounded up to 2^53 */
        mant >>= 1;
        sh--;
    }
    /* mant 2^-sh, with 2^-sh a normal double (sh <= 128) */
    uint64_t scale_bits = (uint64_t)(1023 - sh) << 52;
    double scale;
    memcpy(&scale, &scale_bits, sizeof scale);
    *x = (double)mant * scale;
    return 1;
}

/* The decimal at p ([-]digits[.digits][e[+-]digits], at most 19
 * significant digits) as the nearest double, ties to even, as strtod
 * rounds it: the end of its text (the first character that cannot continue
 * it: the caller checks that it ends the token) with *out, or NULL when it
 * is not of that form or not in the range below (strtod then reads it).
 * The text must end in a character that is none of "0-9.eE+-" (a space or
 * the NUL), which stops every loop.  With w the digits as an integer and
 * x = w 10^q: when w < 2^53 and |q| <= 22, x is one correctly rounded
 * product or quotient of two exact doubles; when q < 0 and 10^-q < 2^75
 * (q >= -22), m = floor(w 2^s / 10^-q) in [2^52, 2^53) and its remainder
 * are exact in 128 bits and give the rounding.  The scene's numbers are
 * shortest round-trip decimals (up to 17 digits): nearly all take one of
 * the two paths, about ten times faster than strtod.  Reading the token
 * and its number in one pass halves the scene reader's work per number. */
static inline __attribute__((always_inline)) const char *scan_decimal(const char *p, double *out)
{
    static const double p10[23] = { 1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12,
                                    1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22 };
    int neg = 0;
    if (*p == '-') {
        neg = 1;
        p++;
    }
    uint64_t m = 0;
    int q = 0;
    const char *first = p;
    /* leading zeros, then the whole part's digits, then the fraction's
     * (its zeros before any other digit only move the point) */
    while (*p == '0')
        p++;
    const char *sig = p;
    while ((unsigned)(*p - '0') < 10u)
        m = 10u * m + (uint64_t)(*p++ - '0');
    int digits = (int)(p - first), nsig = (int)(p - sig);
    if (*p == '.') {
        p++;
        const char *f = p;
        if (m == 0) {
            while (*p == '0')
                p++;
            q -= (int)(p - f);
        }
        const char *g = p;
        while ((unsigned)(*p - '0') < 10u)
            m = 10u * m + (uint64_t)(*p++ - '0');
        q -= (int)(p - g);
        digits += (int)(p - f);
        nsig += (int)(p - g);
    }
    if (digits == 0 || nsig > 19)
        return NULL;        /* no digits, or m may have overflowed */
    if (*p == 'e' || *p == 'E') {
        p++;
        int eneg = 0, ed = 0, e = 0;
        if (*p == '+' || *p == '-') {
            eneg = *p == '-';
            p++;
        }
        for (; *p >= '0' && *p <= '9'; p++) {
            if (++ed > 4)
                return NULL;
            e = 10 * e + (*p - '0');
        }
        if (ed == 0)
            return NULL;
        q += eneg ? -e : e;
    }
    double x;
    if (m == 0) {
        x = 0.0;
    } else if (m < (UINT64_C(1) << 53) && q >= -22 && q <= 22) {
        x = q >= 0 ? (double)m * p10[q] : (double)m / p10[-q];
    } else if (q < 0 && q >= -22) {
        if (!exact_quotient(m, q, &x))
            return NULL;
    } else {
        return NULL;
    }
    *out = neg ? -x : x;
    return p;
}

/* The decimal w[0..n-1] (no NUL needed): scan_decimal on a terminated
 * copy; texts of 64 characters or more go to strtod. */
int m2c_sim_parse_number(const char *w, size_t n, double *out)
{
    char buf[64];
    if (n >= sizeof buf)
        return 0;
    memcpy(buf, w, n);
    buf[n] = '\0';
    double x;
    const char *e = scan_decimal(buf, &x);
    if (e != buf + n)
        return 0;
    *out = x;
    return 1;
}

/* Past the spaces before the next token. */
static inline void skip_spaces(reader *r)
{
    const char *p = r->p;
    while ((unsigned char)(*p - 1) < ' ' && is_space(*p))     /* 1 .. ' ': one test for the digit after */
        p++;
    r->p = p;
}

/* A number token that scan_decimal does not read: strtod, or the message. */
static __attribute__((noinline)) double num_slow(reader *r)
{
    double x;
    size_t n;
    const char *w = token(r, &n, NULL);
    if (r->failed)
        return 0.0;
    char buf[64];
    if (n >= sizeof buf) {
        fail(r, "expected a number, found '%.*s'", 40, w);
        return 0.0;
    }
    memcpy(buf, w, n);
    buf[n] = '\0';
    char *end;
    errno = 0;
    x = strtod(buf, &end);
    if (end != buf + n) {
        fail(r, "expected a number, found '%.*s'", (int)n, w);
        return 0.0;
    }
    return x;
}

/* The next token as a number (inlined into the reader: a scene is mostly numbers). */
static inline __attribute__((always_inline)) double num(reader *r)
{
    if (!r->failed) {
        skip_spaces(r);
        double x;
        const char *e = scan_decimal(r->p, &x);
        if (e != NULL && (*e == '\0' || is_space(*e)) && e - r->p < 64) {     /* longer: num_slow's message */
            r->p = e;
            return x;
        }
    }
    return num_slow(r);
}

/* An integer token that integer does not read: strtoll, or the message. */
static __attribute__((noinline)) long long integer_slow(reader *r)
{
    size_t n;
    const char *w = token(r, &n, NULL);
    if (r->failed)
        return 0;
    char buf[32];
    if (n >= sizeof buf) {
        fail(r, "expected an integer, found '%.*s'", 20, w);
        return 0;
    }
    memcpy(buf, w, n);
    buf[n] = '\0';
    char *end;
    errno = 0;
    long long v = strtoll(buf, &end, 10);
    if (end != buf + n || errno != 0) {
        fail(r, "expected an integer, found '%.*s'", (int)n, w);
        return 0;
    }
    return v;
}

/* The next token as an integer: [-]digits (up to 18: no overflow) without strtoll. */
static inline __attribute__((always_inline)) long long integer(reader *r)
{
    if (!r->failed) {
        skip_spaces(r);
        const char *p = r->p;
        int neg = *p == '-';
        p += neg;
        const char *d = p;
        long long v = 0;
        while ((unsigned)(*p - '0') < 10u && p - d < 18)
            v = 10 * v + (*p++ - '0');
        if (p > d && (*p == '\0' || is_space(*p))) {
            r->p = p;
            return neg ? -v : v;
        }
    }
    return integer_slow(r);
}

static int32_t count(reader *r, long long limit)
{
    long long v = integer(r);
    if (!r->failed && (v < 0 || v > limit))
        fail(r, "a count out of range");
    return r->failed ? 0 : (int32_t)v;
}

void m2c_sim_scene_free(m2c_sim_scene *s)
{
    if (s == NULL)
        return;
    free(s->bodies);
    free(s->verts);
    free(s->inputs);
    free(s);
}

/* A `body ...` line and its `v` lines into b (index i; b->verts is left
 * NULL), the vertices appended to *verts (*n of them, room for *cap); an
 * edge's COVER is -1 or a body index below nbodies. */
static void read_body(reader *r, m2c_sim_body *b, int32_t i, int32_t nbodies, m2c_sim_vertex **verts, size_t *n,
                      size_t *cap)
{
    word(r, "body");
    b->idx = i;
    b->polygon = integer(r) == 1;
    b->fixed = integer(r) == 1;
    b->inv_m = num(r);
    b->inv_i = num(r);
    b->e = num(r);
    b->mu = num(r);
    b->px = num(r);
    b->py = num(r);
    b->vx = num(r);
    b->vy = num(r);
    b->ax = num(r);
    b->ay = num(r);
    b->fax = b->ax;
    b->fay = b->ay;
    b->sup = -1;
    b->sup_edge = -1;
    b->ang = num(r);
    b->om = num(r);
    b->r = num(r);
    b->orbit = num(r);
    b->ophase = num(r);
    b->bound = num(r);
    b->window = num(r);
    b->large = integer(r) == 1;
    b->nverts = count(r, 1 << 20);
    b->tb = 0.0;
    b->cx = b->cy = 0;
    b->slot = -1;
    b->gone = 0;
    b->asleep = 0;
    b->island = -1;
    b->carry = 0;
    b->verts = NULL;
    for (int32_t k = 0; k < b->nverts && !r->failed; k++) {
        if (*n == *cap) {
            size_t c = *cap ? 2 * *cap : 64;
            m2c_sim_vertex *v = realloc(*verts, c * sizeof *v);
            if (v == NULL) {
                fail(r, "out of memory");
                break;
            }
            *verts = v;
            *cap = c;
        }
        m2c_sim_vertex *v = &(*verts)[(*n)++];
        word(r, "v");
        v->lx = num(r);
        v->ly = num(r);
        v->rho = num(r);
        v->beta = num(r);
        v->psi = num(r);
        v->h = num(r);
        v->s1 = num(r);
        v->s2 = num(r);
        v->nx = num(r);
        v->ny = num(r);
        long long cover = integer(r);
        if (!r->failed && (cover < -1 || cover >= nbodies))
            fail(r, "an edge's cover names no body");
        v->cover = (int32_t)cover;
    }
}

int m2c_sim_body_read(const char *text, m2c_sim_body *b, int32_t idx, m2c_sim_vertex **verts, char *err,
                      size_t errlen)
{
    reader rd = { text, "add_body", err, errlen, 0 };
    size_t n = 0, cap = 0;
    *verts = NULL;
    read_body(&rd, b, idx, idx, verts, &n, &cap);
    if (!rd.failed) {
        const char *p = rd.p;
        while (*p && is_space(*p))
            p++;
        if (*p) {
            const char *e = p;
            while (*e && !is_space(*e))
                e++;
            fail(&rd, "unexpected '%.*s' after the body", (int)(e - p > 40 ? 40 : e - p), p);
        }
    }
    if (rd.failed) {
        free(*verts);
        *verts = NULL;
        return -1;
    }
    return 0;
}

m2c_sim_scene *m2c_sim_scene_read(const char *text, char *err, size_t errlen)
{
    reader rd = { text, "scene", err, errlen, 0 };
    reader *r = &rd;
    m2c_sim_scene *s = calloc(1, sizeof *s);
    if (s == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    size_t *first = NULL;               /* each body's first vertex in s->verts */
    size_t nverts = 0, capverts = 0;
    word(r, "m2c-scene");
    if (!r->failed && integer(r) != 1 && !r->failed)
        fail(r, "unknown version");
    word(r, "end");
    s->end = num(r);
    word(r, "frame");
    s->frame_dt = num(r);
    word(r, "tolerance");
    s->tol = num(r);
    word(r, "rest_speed");
    s->rest_speed = num(r);
    word(r, "window_angle");
    s->alpha = num(r);
    word(r, "max_same_time");
    s->max_same = integer(r);
    word(r, "grid");
    s->x0 = num(r);
    s->y0 = num(r);
    s->cw = num(r);
    s->ch = num(r);
    s->nx = count(r, 1 << 30);
    s->ny = count(r, 1 << 30);
    s->margin = num(r);
    if (!r->failed && (s->nx < 1 || s->ny < 1 || (long long)s->nx * s->ny > (1ll << 31)))
        fail(r, "bad grid");
    s->half_cell = 0.5 * (s->ch < s->cw ? s->ch : s->cw);
    if (!r->failed && !(0.0 <= s->margin && s->margin < s->half_cell))
        fail(r, "grid margin outside [0, half a cell)");
    word(r, "bodies");
    s->nbodies = count(r, 1 << 28);
    if (!r->failed) {
        s->bodies_cap = s->nbodies + 1;
        size_t bytes = ((size_t)s->nbodies + 1) * sizeof *s->bodies;      /* a multiple of 64 */
        s->bodies = aligned_alloc(64, bytes);
        if (s->bodies != NULL) {
            /* zeroed one body at a time as it is read (below): one pass
             * over the 32 MB of 10^5 bodies, not two */
            m2c_sim_huge_pages(s->bodies, bytes);
            memset(&s->bodies[s->nbodies], 0, sizeof *s->bodies);
        }
        first = calloc((size_t)s->nbodies + 1, sizeof *first);
        if (s->bodies == NULL || first == NULL)
            fail(r, "out of memory");
    }
    for (int32_t i = 0; i < s->nbodies && !r->failed; i++) {
        first[i] = nverts;
        memset(&s->bodies[i], 0, sizeof *s->bodies);
        read_body(r, &s->bodies[i], i, s->nbodies, &s->verts, &nverts, &capverts);
    }
    word(r, "inputs");
    s->ninputs = count(r, 1 << 28);
    if (!r->failed) {
        s->inputs_cap = s->ninputs + 1;
        s->inputs = calloc((size_t)s->inputs_cap, sizeof *s->inputs);
        if (s->inputs == NULL)
            fail(r, "out of memory");
    }
    for (int32_t k = 0; k < s->ninputs && !r->failed; k++) {
        m2c_sim_input *in = &s->inputs[k];
        word(r, "input");
        in->t = num(r);
        long long body = integer(r);
        in->mode = (int32_t)integer(r);
        in->vx = num(r);
        in->vy = num(r);
        if (!r->failed && (body < 0 || body >= s->nbodies))
            fail(r, "input on body %lld, which does not exist", body);
        else if (!r->failed && (in->mode < 0 || in->mode > 4))
            fail(r, "unknown input mode %d", (int)in->mode);
        else if (!r->failed && !m2c_sim_drivable(&s->bodies[body], in->mode))
            fail(r, "input %d on fixed body %lld: only set_velocity (on a polygon that does not turn) or remove",
                 (int)k, body);
        in->body = (int32_t)body;
    }
    word(r, "end");
    if (r->failed) {
        free(first);
        m2c_sim_scene_free(s);
        return NULL;
    }
    for (int32_t i = 0; i < s->nbodies; i++)
        s->bodies[i].verts = s->bodies[i].nverts > 0 ? s->verts + first[i] : NULL;
    s->nverts_all = nverts;
    s->verts_cap = capverts;
    free(first);
    return s;
}
