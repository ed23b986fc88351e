/* Reading the flat scene (docs/simulator.md, written by max2code/sim/scene.py)
 * and checking it as it is read ("Flat scene checks"): whitespace-separated
 * words; the numbers are shortest round-trip decimals, which strtod reads
 * exactly.  The first fault stops the reading with its message, the same
 * in every runtime.  The limits are m2c_sim.h's. */
#include <errno.h>
#include <math.h>
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

/* Space, tab, newline or carriage return: what separates words (the text
 * check refuses the other control bytes first). */
static inline int is_space(char c)
{
    return c == ' ' || (unsigned char)(c - '\t') <= (unsigned char)('\r' - '\t');     /* \t \n \v \f \r */
}

static void fail(reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

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

/* A word as messages show it: its first 32 characters, then "..." when
 * it is longer (printf "%.*s%s" with WORD_ARGS). */
#define WORD_SHOWN 32
#define WORD_ARGS(w, n) (int)((n) > WORD_SHOWN ? WORD_SHOWN : (n)), (w), ((n) > WORD_SHOWN ? "..." : "")

int m2c_sim_text_check(const char *text, size_t n, const char *what, char *err, size_t errlen)
{
    if (n > TEXT_MAX) {
        snprintf(err, errlen, "%s: longer than %d bytes", what, TEXT_MAX);
        return -1;
    }
    for (size_t k = 0; k < n; k++) {
        unsigned char c = (unsigned char)text[k];
        if (!((c >= 0x21 && c <= 0x7e) || c == ' ' || c == '\t' || c == '\n' || c == '\r')) {
            snprintf(err, errlen, "%s: byte %zu: not printable ASCII", what, k);
            return -1;
        }
    }
    return 0;
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
    if (r->failed)
        return;
    size_t n;
    const char *w = token(r, &n, expect);
    if (r->failed)
        return;
    if (n != strlen(expect) || memcmp(w, expect, n) != 0)
        fail(r, "expected '%s', found '%.*s%s'", expect, WORD_ARGS(w, n));
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

/* w[0..n-1] is a number's text: [+-](digits[.digits]|.digits)[(e|E)[+-]digits],
 * at most 64 characters (no inf, nan, hex, '_'). */
static int number_text(const char *w, size_t n)
{
    if (n > 64)
        return 0;
    size_t k = 0, d = 0;
    if (k < n && (w[k] == '+' || w[k] == '-'))
        k++;
    while (k < n && (unsigned)(w[k] - '0') < 10u)
        k++, d++;
    if (k < n && w[k] == '.') {
        k++;
        while (k < n && (unsigned)(w[k] - '0') < 10u)
            k++, d++;
    }
    if (d == 0)
        return 0;
    if (k < n && (w[k] == 'e' || w[k] == 'E')) {
        k++;
        if (k < n && (w[k] == '+' || w[k] == '-'))
            k++;
        size_t e = 0;
        while (k < n && (unsigned)(w[k] - '0') < 10u)
            k++, e++;
        if (e == 0)
            return 0;
    }
    return k == n;
}

/* A number token that scan_decimal does not read: checked, then strtod
 * (correctly rounded), or the message. */
static __attribute__((noinline)) double num_slow(reader *r)
{
    if (r->failed)
        return 0.0;
    size_t n;
    const char *w = token(r, &n, NULL);
    if (r->failed)
        return 0.0;
    if (!number_text(w, n)) {
        fail(r, "expected a number, found '%.*s%s'", WORD_ARGS(w, n));
        return 0.0;
    }
    char buf[66];
    memcpy(buf, w, n);
    buf[n] = '\0';
    double x = strtod(buf, NULL);
    if (!isfinite(x)) {
        fail(r, "number '%.*s%s' is beyond a double's range", WORD_ARGS(w, n));
        return 0.0;
    }
    return x;
}

/* The next token as a number (inlined into the reader: a scene is mostly
 * numbers); what scan_decimal reads is a number of that form, finite. */
static inline __attribute__((always_inline)) double num(reader *r)
{
    if (!r->failed) {
        skip_spaces(r);
        double x;
        const char *e = scan_decimal(r->p, &x);
        if (e != NULL && (*e == '\0' || is_space(*e)) && e - r->p <= 64) {     /* longer: num_slow's message */
            r->p = e;
            return x;
        }
    }
    return num_slow(r);
}

/* An integer token that integer does not read: the message. */
static __attribute__((noinline)) long long integer_slow(reader *r)
{
    if (r->failed)
        return 0;
    size_t n;
    const char *w = token(r, &n, NULL);
    if (!r->failed)
        fail(r, "expected an integer, found '%.*s%s'", WORD_ARGS(w, n));
    return 0;
}

/* The next token as an integer: -?[0-9]{1,18} (no overflow). */
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

void m2c_sim_scene_free(m2c_sim_scene *s)
{
    if (s == NULL)
        return;
    free(s->bodies);
    free(s->verts);
    free(s->inputs);
    free(s);
}

/* What a body's checks need of its scene: the tolerance (m), the end
 * time (s) and the number of bodies an edge's cover may name. */
typedef struct body_context {
    double tol, end;
    long long nbodies;
} body_context;

/* The reach of a body by the end time T (docs/simulator.md, "Flat scene
 * checks", rule 8): (|px| + |py|) + (|vx| + |vy|) T + (|ax| + |ay|) T T / 2
 * + bound, left to right in doubles (no contraction: -ffp-contract=off). */
static double reach(const m2c_sim_body *b, double T)
{
    double r = fabs(b->px) + fabs(b->py);
    r = r + (fabs(b->vx) + fabs(b->vy)) * T;
    r = r + (fabs(b->ax) + fabs(b->ay)) * T * T / 2.0;
    return r + b->bound;
}

/* The rules of a body line (1 to 8) on b, its POLY, FIXED and LARGE as
 * read, body k. */
static void check_body(reader *r, const m2c_sim_body *b, long long poly, long long fixed, long long large,
                       long long nverts, int32_t k, const body_context *c)
{
    char v[M2C_SIM_NUMBER_MAX + 1];
    if (poly != 0 && poly != 1)
        fail(r, "body %d: poly must be 0 or 1", (int)k);
    else if (fixed != 0 && fixed != 1)
        fail(r, "body %d: fixed must be 0 or 1", (int)k);
    else if (large != 0 && large != 1)
        fail(r, "body %d: large must be 0 or 1", (int)k);
    else if (fixed && !(b->inv_m == 0.0 && b->inv_i == 0.0))
        fail(r, "body %d: a fixed body has inverse mass 0", (int)k);
    else if (!fixed && !(b->inv_m > 0.0))
        fail(r, "body %d: inverse mass %s must be positive", (int)k, m2c_sim_text(v, b->inv_m));
    else if (!fixed && poly && !(b->inv_i > 0.0))
        fail(r, "body %d: inverse inertia %s must be positive", (int)k, m2c_sim_text(v, b->inv_i));
    else if (!fixed && !poly && b->inv_i != 0.0)
        fail(r, "body %d: a circle has inverse inertia 0", (int)k);
    else if (!(b->e >= 0.0 && b->e <= 1.0))
        fail(r, "body %d: restitution %s outside [0, 1]", (int)k, m2c_sim_text(v, b->e));
    else if (!(b->mu >= 0.0))
        fail(r, "body %d: friction %s is negative", (int)k, m2c_sim_text(v, b->mu));
    if (r->failed)
        return;
    if (!poly) {
        if (!(b->r >= c->tol && b->r <= LENGTH_MAX))
            fail(r, "body %d: radius %s outside [tolerance, 1e150]", (int)k, m2c_sim_text(v, b->r));
        else if (nverts != 0)
            fail(r, "body %d: a circle has no vertices", (int)k);
        else if (b->orbit != 0.0 && !(b->orbit >= c->tol && b->orbit <= LENGTH_MAX))
            fail(r, "body %d: orbit radius %s outside [tolerance, 1e150]", (int)k, m2c_sim_text(v, b->orbit));
        else if (b->orbit != 0.0 && !fixed)
            fail(r, "body %d: an orbiting circle must be fixed", (int)k);
        else if (b->om != 0.0 && !(b->orbit > 0.0))
            fail(r, "body %d: a circle turns only about an orbit", (int)k);
    } else {
        if (b->r != 0.0 || b->orbit != 0.0)
            fail(r, "body %d: a polygon has no radius or orbit", (int)k);
        else if (nverts < 3 || nverts > MAX_VERTICES)
            fail(r, "body %d: %lld vertices (3 to %d)", (int)k, nverts, MAX_VERTICES);
    }
    if (r->failed)
        return;
    if (!(b->window >= 0.0 && b->window <= 0.5))
        fail(r, "body %d: window %s outside [0, 0.5]", (int)k, m2c_sim_text(v, b->window));
    /* a polygon's radius and orbit are 0 here: its bound is at least 0 */
    else if (!(b->bound >= b->r + b->orbit && b->bound <= LENGTH_MAX))
        fail(r, "body %d: bound %s is too small or too large", (int)k, m2c_sim_text(v, b->bound));
    else if (!(reach(b, c->end) <= 2.0 * LENGTH_MAX))
        fail(r, "body %d: reaches more than 2e150 m from the origin by the end", (int)k);
}

/* The rules of a whole polygon (12 to 15) on its n vertices v, body k. */
static void check_polygon(reader *r, const m2c_sim_vertex *v, int32_t n, int32_t k, double tol)
{
#define EX(j) (v[((j) + 1) % n].lx - v[(j)].lx)
#define EY(j) (v[((j) + 1) % n].ly - v[(j)].ly)
    for (int32_t j = 0; j < n; j++)
        if (!(fabs(EX(j)) + fabs(EY(j)) >= tol)) {
            fail(r, "body %d vertex %d: edge shorter than the tolerance", (int)k, (int)j);
            return;
        }
    for (int32_t j = 0; j < n; j++) {
        int32_t i = (j + n - 1) % n;
        if (!(EX(i) * EY(j) - EY(i) * EX(j) > 0.0)) {
            fail(r, "body %d vertex %d: not strictly convex (counter-clockwise)", (int)k, (int)j);
            return;
        }
    }
    int first = 0, last = 0, changes = 0;
    for (int32_t j = 0; j < n; j++) {
        double ey = EY(j);
        int sign = ey > 0.0 ? 1 : ey < 0.0 ? -1 : 0;
        if (sign == 0)
            continue;
        if (first == 0)
            first = sign;
        else if (sign != last)
            changes++;
        last = sign;
    }
    if (first != 0 && last != first)
        changes++;          /* cyclic: the last sign against the first */
    if (changes != 2) {
        fail(r, "body %d: the polygon winds %d times", (int)k, changes / 2);
        return;
    }
    for (int32_t j = 0; j < n; j++)
        if (!(v[j].nx * EY(j) - v[j].ny * EX(j) > 0.0)) {
            fail(r, "body %d vertex %d: the normal does not point outward", (int)k, (int)j);
            return;
        }
#undef EX
#undef EY
}

/* A `body ...` line and its `v` lines into b (body k; b->verts is left
 * NULL), checked; the vertices appended to *verts (*n of them, room for
 * *cap). */
static void read_body(reader *r, m2c_sim_body *b, int32_t k, const body_context *c, m2c_sim_vertex **verts,
                      size_t *n, size_t *cap)
{
    word(r, "body");
    b->idx = k;
    long long poly = integer(r);
    long long fixed = integer(r);
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
    long long large = integer(r);
    long long nverts = integer(r);
    if (r->failed)
        return;
    check_body(r, b, poly, fixed, large, nverts, k, c);
    if (r->failed)
        return;
    b->polygon = (unsigned char)poly;
    b->fixed = (unsigned char)fixed;
    b->large = (unsigned char)large;
    b->nverts = (int32_t)nverts;        /* at most MAX_VERTICES */
    b->tb = 0.0;
    b->cx = b->cy = 0;
    b->slot = -1;
    b->gone = 0;
    b->asleep = 0;
    b->island = -1;
    b->non = 0;
    b->carry = 0;
    b->rest = -1;
    b->verts = NULL;
    if (*cap - *n < (size_t)b->nverts) {
        size_t want = *cap ? 2 * *cap : 64;
        if (want < *n + (size_t)b->nverts)
            want = *n + (size_t)b->nverts;
        m2c_sim_vertex *more = realloc(*verts, want * sizeof *more);
        if (more == NULL) {
            fail(r, "out of memory");
            return;
        }
        *verts = more;
        *cap = want;
    }
    m2c_sim_vertex *v0 = *verts + *n;
    for (int32_t j = 0; j < b->nverts && !r->failed; j++) {
        m2c_sim_vertex *v = &v0[j];
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
        if (r->failed)
            return;
        /* lx, ly and rho (the vertex), h, s1 and s2 (its edge's line and extent: each at most a vertex's
           distance, twice the bound leaving room for their rounding) */
        if (!(fabs(v->lx) <= b->bound && fabs(v->ly) <= b->bound && 0.0 <= v->rho && v->rho <= b->bound
              && fabs(v->h) <= 2.0 * b->bound && fabs(v->s1) <= 2.0 * b->bound && fabs(v->s2) <= 2.0 * b->bound))
            fail(r, "body %d vertex %d: outside the bound", (int)k, (int)j);
        else if (!(fabs(v->nx * v->nx + v->ny * v->ny - 1.0) <= 1e-9))
            fail(r, "body %d vertex %d: the normal is not a unit vector", (int)k, (int)j);
        else if (!(cover == -1 || (cover >= 0 && cover < c->nbodies && cover != k)))
            fail(r, "body %d vertex %d: cover %lld is not a body", (int)k, (int)j, cover);
        v->cover = (int32_t)cover;
    }
    if (r->failed)
        return;
    if (b->polygon)
        check_polygon(r, v0, b->nverts, k, c->tol);
    *n += (size_t)b->nverts;
}

/* After the body (add_body) or the scene's final `end`: nothing more. */
static void nothing_after(reader *r, const char *after)
{
    if (r->failed)
        return;
    const char *p = r->p;
    while (*p && is_space(*p))
        p++;
    if (*p) {
        const char *e = p;
        while (*e && !is_space(*e))
            e++;
        size_t n = (size_t)(e - p);
        fail(r, "unexpected '%.*s%s' after the %s", WORD_ARGS(p, n), after);
    }
}

int m2c_sim_body_read(const char *text, m2c_sim_body *b, int32_t idx, double tol, double end, m2c_sim_vertex **verts,
                      char *err, size_t errlen)
{
    reader rd = { text, "add_body", err, errlen, 0 };
    size_t n = 0, cap = 0;
    *verts = NULL;
    if (m2c_sim_text_check(text, strlen(text), "add_body", err, errlen) != 0)
        return -1;
    body_context c = { tol, end, idx };
    read_body(&rd, b, idx, &c, verts, &n, &cap);
    nothing_after(&rd, "body");
    if (rd.failed) {
        free(*verts);
        *verts = NULL;
        return -1;
    }
    return 0;
}

m2c_sim_scene *m2c_sim_scene_read(const char *text, char *err, size_t errlen)
{
    if (m2c_sim_text_check(text, strlen(text), "scene", err, errlen) != 0)
        return NULL;
    reader rd = { text, "scene", err, errlen, 0 };
    reader *r = &rd;
    m2c_sim_scene *s = calloc(1, sizeof *s);
    if (s == NULL) {
        snprintf(err, errlen, "out of memory");
        return NULL;
    }
    char v[M2C_SIM_NUMBER_MAX + 1];
    size_t *first = NULL;               /* each body's first vertex in s->verts */
    int32_t *removed = NULL;            /* per body: the input that removed it, -1 none */
    size_t nverts = 0, capverts = 0;
    word(r, "m2c-scene");
    long long version = integer(r);
    if (!r->failed && version != 1)
        fail(r, "unknown version %lld", version);
    word(r, "end");
    s->end = num(r);
    if (!r->failed && !(s->end > 0.0 && s->end <= LENGTH_MAX))
        fail(r, "end %s outside (0, 1e150]", m2c_sim_text(v, s->end));
    word(r, "frame");
    s->frame_dt = num(r);
    if (!r->failed && !(s->frame_dt == 0.0 || (s->frame_dt > 0.0 && s->end / s->frame_dt <= 1e12))) {
        if (s->frame_dt > 0.0)
            fail(r, "frame %s gives more than 1e12 frames", m2c_sim_text(v, s->frame_dt));
        else
            fail(r, "frame %s is negative", m2c_sim_text(v, s->frame_dt));
    }
    word(r, "tolerance");
    s->tol = num(r);
    if (!r->failed && !(s->tol >= LENGTH_MIN && s->tol <= LENGTH_MAX))
        fail(r, "tolerance %s outside [1e-150, 1e150]", m2c_sim_text(v, s->tol));
    word(r, "rest_speed");
    s->rest_speed = num(r);
    if (!r->failed && !(s->rest_speed >= 0.0))
        fail(r, "rest_speed %s is negative", m2c_sim_text(v, s->rest_speed));
    else if (!r->failed && !(s->rest_speed <= LENGTH_MAX))     /* its square must not overflow */
        fail(r, "rest_speed %s beyond 1e150", m2c_sim_text(v, s->rest_speed));
    word(r, "window_angle");
    s->alpha = num(r);
    if (!r->failed && !(s->alpha > 0.0 && s->alpha <= 0.5))
        fail(r, "window_angle %s outside (0, 0.5]", m2c_sim_text(v, s->alpha));
    word(r, "max_same_time");
    s->max_same = integer(r);
    if (!r->failed && s->max_same < 1)
        fail(r, "max_same_time %lld is less than 1", s->max_same);
    word(r, "max_events");
    s->max_events = integer(r);
    if (!r->failed && s->max_events < 1)
        fail(r, "max_events %lld is less than 1", s->max_events);
    word(r, "grid");
    /* each pair checked once read, as the words come (docs/simulator.md, "Flat scene checks", Header) */
    s->x0 = num(r);
    s->y0 = num(r);
    if (!r->failed && !(fabs(s->x0) <= LENGTH_MAX && fabs(s->y0) <= LENGTH_MAX))
        fail(r, "grid origin beyond 1e150");
    s->cw = num(r);
    s->ch = num(r);
    if (!r->failed && !(s->cw >= LENGTH_MIN && s->cw <= LENGTH_MAX))
        fail(r, "grid cell %s outside [1e-150, 1e150]", m2c_sim_text(v, s->cw));
    else if (!r->failed && !(s->ch >= LENGTH_MIN && s->ch <= LENGTH_MAX))
        fail(r, "grid cell %s outside [1e-150, 1e150]", m2c_sim_text(v, s->ch));
    long long gnx = integer(r), gny = integer(r);
    if (!r->failed && (gnx < 1 || gny < 1))
        fail(r, "grid of %lld x %lld cells", gnx, gny);
    s->margin = num(r);
    s->half_cell = 0.5 * (s->ch < s->cw ? s->ch : s->cw);
    if (!r->failed && !(0.0 <= s->margin && s->margin < s->half_cell))
        fail(r, "grid margin %s m outside [0, half a cell)", m2c_sim_text(v, s->margin));
    word(r, "bodies");
    long long nb = integer(r);
    if (!r->failed && (nb < 1 || nb > MAX_BODIES))
        fail(r, "%lld bodies (1 to %d)", nb, MAX_BODIES);
    if (!r->failed) {
        long long cells = 4 * nb > 16 ? 4 * nb : 16;      /* NX NY <= cells, without overflow */
        if (gnx > cells || gny > cells / gnx)
            fail(r, "grid of %lld x %lld cells for %lld bodies (at most max(16, 4 x bodies) cells)", gnx, gny, nb);
    }
    if (!r->failed) {
        s->nx = (int32_t)gnx;
        s->ny = (int32_t)gny;
        s->nbodies = (int32_t)nb;
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
    body_context c = { s->tol, s->end, s->nbodies };
    for (int32_t i = 0; i < s->nbodies && !r->failed; i++) {
        first[i] = nverts;
        memset(&s->bodies[i], 0, sizeof *s->bodies);
        read_body(r, &s->bodies[i], i, &c, &s->verts, &nverts, &capverts);
    }
    /* an edge's cover is a fixed body (known once every body is read) */
    for (int32_t i = 0; i < s->nbodies && !r->failed; i++) {
        const m2c_sim_body *b = &s->bodies[i];
        for (int32_t j = 0; j < b->nverts && !r->failed; j++) {
            int32_t cv = s->verts[first[i] + (size_t)j].cover;
            if (cv >= 0 && !s->bodies[cv].fixed)
                fail(r, "body %d vertex %d: cover %d is not a fixed body", (int)i, (int)j, (int)cv);
        }
    }
    word(r, "inputs");
    long long ni = integer(r);
    if (!r->failed && (ni < 0 || ni > MAX_INPUTS))
        fail(r, "%lld inputs (0 to %d)", ni, MAX_INPUTS);
    if (!r->failed) {
        s->ninputs = (int32_t)ni;
        s->inputs_cap = s->ninputs + 1;
        s->inputs = calloc((size_t)s->inputs_cap, sizeof *s->inputs);
        removed = malloc((size_t)s->nbodies * sizeof *removed);
        if (s->inputs == NULL || removed == NULL)
            fail(r, "out of memory");
        else
            for (int32_t i = 0; i < s->nbodies; i++)
                removed[i] = -1;
    }
    for (int32_t k = 0; k < s->ninputs && !r->failed; k++) {
        m2c_sim_input *in = &s->inputs[k];
        word(r, "input");
        in->t = num(r);
        long long body = integer(r);
        long long mode = integer(r);
        in->vx = num(r);
        in->vy = num(r);
        if (r->failed)
            break;
        if (!(in->t >= 0.0 && in->t <= s->end))
            fail(r, "input %d: time %s outside [0, end]", (int)k, m2c_sim_text(v, in->t));
        else if (body < 0 || body >= s->nbodies)
            fail(r, "input on body %lld, which does not exist", body);
        else if (mode < 0 || mode > 4)
            fail(r, "unknown input mode %lld", mode);
        else if (!m2c_sim_drivable(&s->bodies[body], (int32_t)mode))
            fail(r, "input %d on fixed body %lld: only set_velocity (on a polygon that does not turn) or remove",
                 (int)k, body);
        else if (removed[body] >= 0)
            fail(r, "input %d: body %lld was removed by input %d", (int)k, body, (int)removed[body]);
        else if (mode == M2C_SIM_REMOVE && !(in->vx == 0.0 && in->vy == 0.0))
            fail(r, "input %d: a removal has no vector", (int)k);
        else if (mode == M2C_SIM_TELEPORT && !(fabs(in->vx) + fabs(in->vy) <= LENGTH_MAX))
            fail(r, "input %d: teleport beyond 1e150 m", (int)k);
        if (r->failed)
            break;
        in->body = (int32_t)body;
        in->mode = (int32_t)mode;
        if (mode == M2C_SIM_REMOVE)
            removed[body] = k;
    }
    word(r, "end");
    nothing_after(r, "end");
    free(removed);
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
