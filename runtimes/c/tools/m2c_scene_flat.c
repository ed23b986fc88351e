/* The common case of `max2code simulate`'s scene, read, checked and
   compiled to the flat scene (docs/simulator.md) in C: a JSON scene of
   circles without orbit and of fixed polygons, with no inputs.  Loaded by
   max2code/sim/scene_c.py through ctypes (as a PyDLL: it runs in the
   Python process, holding the interpreter's lock); max2code/sim/scene.py is
   the specification and does everything else.

   This code only accelerates: it never reports a fault.  A scene it does
   not take whole ("not mine": any key, value or spelling outside the case
   below, any fault, any check whose outcome is not certain with a wide
   margin) goes, whole, to the Python reader, which gives the same bytes or
   the precise error.  Taken:
   - a JSON object of ASCII text whose keys are the scene keys, each at most
     once; "inputs" absent or []; "name" a string; numbers as the Python
     reader reads them (an integer of up to 18 digits made a double, any
     other number the double json.loads makes: see quick_double, and the
     interpreter's own PyOS_string_to_double for the rest);
   - bodies: circles whose keys are the circle's (no orbit, no vertices),
     each at most once, with a name of printable ASCII without escapes (its
     JSON is then the name in quotes), every field in range (a radius at least
     the tolerance); polygons are left for Python to read (sf_polygon gives
     each one's text), and must be fixed and not turning (scene_c.py
     checks), so that no body turns and the window angles are 0.5 and 0;
   - checks: names unique; a circle's magnitudes (hypot here is libm's, not
     Python's math.hypot, so each bound must hold with a relative margin of
     1e-6); overlaps at t = 0 of a movable circle with any circle (grid of
     cells) and with each polygon's box (given by Python), each clear of the
     tolerance with a margin.
   Numbers are written as the interpreter's repr writes them (quick_repr,
   and PyOS_double_to_string, 'r' mode, '.0' added, for the rest): the flat
   text is the Python compiler's byte for byte, and tests/simulator/test_scene_c.py
   compares the two.  The JSON text is not kept: after sf_compile the state
   holds the bodies' numbers and names only (sf_part writes from them). */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* the interpreter's own number conversions (exported by every CPython) */
extern double PyOS_string_to_double(const char *s, char **endptr, void *overflow_exception);
extern char *PyOS_double_to_string(double val, char format_code, int precision, int flags, int *type);
extern void PyMem_Free(void *p);
#define PY_DTSF_ADD_DOT_0 0x02

#define LENGTH_MAX 1e150
#define LENGTH_MIN 1e-150
#define MARGIN 1e-6            /* relative margin of every check made here with other rounding than Python's */
#define MAX_DEPTH 200          /* nesting of a skipped value (Python's json stops near 1000) */
#define MAX_LARGE 64           /* large circles and polygons, each tested against every movable circle */
#define SF_CELL_FACTOR 1.15    /* cells this many times the largest movable body (max2code/sim/scene.py CELL_FACTOR) */

enum { MINE = 0, NOT_MINE = 1, NO_MEMORY = 2 };

typedef struct {
    char *s;
    size_t n, cap;
} sf_buf;

typedef struct {
    const char *text;          /* the scene's JSON (ASCII, NUL after its end) */
    const char *p, *end;       /* where parsing is */
    /* the scene's fields */
    double end_time, frame_rate, gx, gy, tolerance, rest_speed, order, max_same, max_events, max_frame_rate;
    /* bodies: kind 0 a circle (its fields below), 1 a polygon (its text's span, for Python) */
    long n, cap;
    unsigned char *kind, *fixed;
    double *mass, *restitution, *friction, *px, *py, *vx, *vy, *ax, *ay, *angle, *omega, *radius;
    long *name_at, *name_len;  /* a name's characters in text (name_at < 0: body{k}) */
    long npoly, *poly;         /* the polygons' body indices */
    long *poly_start, *poly_end;
    unsigned char *large;      /* per body, from the grid */
    sf_buf out, names;
    int accelerates;           /* a circle's acceleration (gravity included) is not (0, 0) */
} sf_scene;

/* ------------------------------------------------------------ buffers */
static int put(sf_buf *b, const char *s, size_t n)
{
    if (b->n + n + 1 > b->cap) {
        size_t cap = b->cap ? b->cap : 1 << 16;
        while (b->n + n + 1 > cap)
            cap *= 2;
        char *s2 = realloc(b->s, cap);
        if (!s2)
            return -1;
        b->s = s2;
        b->cap = cap;
    }
    memcpy(b->s + b->n, s, n);
    b->n += n;
    b->s[b->n] = 0;
    return 0;
}

static int puts_(sf_buf *b, const char *s) { return put(b, s, strlen(s)); }

/* ------------------------------------------------------------ numbers
   Most numbers go neither through the interpreter's strtod nor its dtoa
   (each a few hundred ns: bignum arithmetic, and the x87 control word set
   and restored): two exact shortcuts take the common ones and leave the
   rest to the interpreter.  tests/simulator/test_scene_c.py compares both with
   float() and repr() on random and edge values. */
typedef unsigned __int128 u128;
static u128 pow10_128[40];       /* 10^0 .. 10^38 */
static int x87_extended = -1;    /* the x87 rounds to 64 bits (the shortcut of quick_double needs it) */

static void numbers_init(void)
{
    if (!pow10_128[0]) {
        pow10_128[0] = 1;
        for (int k = 1; k < 40; k++)
            pow10_128[k] = pow10_128[k - 1] * 10;
    }
#if defined(__x86_64__) && LDBL_MANT_DIG == 64
    unsigned short cw;
    __asm__ volatile("fnstcw %0" : "=m"(cw));
    x87_extended = (cw & 0x300) == 0x300;
#else
    x87_extended = 0;
#endif
}

/* The double nearest w * 10^p (w < 2^64), when one rounding of the exact
   value to the x87's 64-bit mantissa tells it: that rounding is within half
   a unit of 64 bits of the exact value, so when its 11 bits below the
   double's 53 are not at (or next to) the half-way pattern 0x400, the exact
   value rounds to the same double as it does.  0: the interpreter decides. */
static int quick_double(uint64_t w, int p, double *out)
{
#if defined(__x86_64__) && LDBL_MANT_DIG == 64
    static const long double tens[] = {1e0L, 1e1L, 1e2L, 1e3L, 1e4L, 1e5L, 1e6L, 1e7L, 1e8L, 1e9L, 1e10L,
                                       1e11L, 1e12L, 1e13L, 1e14L, 1e15L, 1e16L, 1e17L, 1e18L, 1e19L, 1e20L,
                                       1e21L, 1e22L, 1e23L, 1e24L, 1e25L, 1e26L, 1e27L};     /* exact: 5^27 < 2^64 */
    if (!x87_extended || p < -27 || p > 27)
        return 0;
    if (w == 0) {
        *out = 0.0;
        return 1;
    }
    long double v = p < 0 ? (long double)w / tens[-p] : (long double)w * tens[p];
    /* its 64-bit significand: the x87 format stores it whole, leading 1 included, in its first 8 bytes (v is
       normal here: 1 <= w < 2^64 and 10^-27 <= 10^p <= 10^27); it is what ldexpl(frexpl(v), 64) gives,
       without two library calls per number */
    uint64_t bits;
    memcpy(&bits, &v, sizeof bits);
    unsigned low = (unsigned)(bits & 0x7FF);
    if (low >= 0x3FF && low <= 0x401)
        return 0;
    *out = (double)v;
    return fabs(*out) >= DBL_MIN && isfinite(*out);
#else
    (void)w;
    (void)p;
    (void)out;
    return 0;
#endif
}

/* Python's repr of x (the shortest decimal that reads back as x, the
   nearest of those) for 1e-4 <= |x| < 1e15 and x not a power of two (whose
   rounding interval is lopsided): its length in buf, 0 when the interpreter
   must write it.  x = m 2^-S exactly; N = m 10^k, with k chosen so that
   x 10^k has 17 digits before the point; each candidate D (15, 16, 17
   digits, correctly rounded from x) reads back as x when it lies within half
   a unit of m of it: |D 10^(17-q) 2^(S+1) - 2N| < 10^k (<= when m is even:
   a tie rounds to even).  Fewer than 15 digits: when the 15-digit one reads
   back, no other 15-digit decimal does (the interval is narrower than their
   spacing), so any shorter one is it without its trailing zeros.  Written
   as repr writes these: no exponent, at least one digit after the point. */
static int quick_repr(double x, char *buf)
{
    double a = fabs(x);
    if (!(a >= 1e-4 && a < 1e15))
        return 0;
    int e2;
    double f = frexp(a, &e2);                       /* a = f 2^e2, f in [0.5, 1) */
    uint64_t m = (uint64_t)ldexp(f, 53);
    int S = 53 - e2;                                /* a = m 2^-S, 0 < S <= 67 */
    if (m == (1ull << 52))
        return 0;
    int k = 16 - (int)floor(log10(a));
    u128 N = 0;
    uint64_t T = 0;                                 /* floor(x 10^k) */
    for (int tries = 0; tries < 3; tries++) {
        if (k < 0 || k > 22)
            return 0;
        N = (u128)m * pow10_128[k];
        T = (uint64_t)(N >> S);
        if (T < 10000000000000000ull)
            k++;
        else if (T >= 100000000000000000ull)
            k--;
        else
            break;
    }
    if (T < 10000000000000000ull || T >= 100000000000000000ull)
        return 0;
    u128 twoN = N << 1, lim = pow10_128[k];
    uint64_t digits = 0;
    int q;
    for (q = 15; q <= 17; q++) {
        int j = 17 - q;
        uint64_t unit = (uint64_t)pow10_128[j];
        uint64_t D = T / unit;
        u128 M = (u128)unit << S;
        u128 R = N - (u128)D * M;                   /* N = D M + R, R < M */
        if (2 * R > M || (2 * R == M && (D & 1)))
            D++;
        if (D >= (uint64_t)pow10_128[q])
            return 0;                               /* rounded up to a new digit: the interpreter's */
        u128 C = ((u128)D * unit) << (S + 1);
        u128 diff = C > twoN ? C - twoN : twoN - C;
        if (diff < lim || (diff == lim && !(m & 1))) {
            digits = D;
            break;
        }
    }
    if (q > 17)
        return 0;
    int decpt = 17 - k;                             /* x = 0.d1d2... 10^decpt */
    char d[24];
    int n = 0;
    while (digits % 10 == 0)
        digits /= 10;
    for (uint64_t v = digits; v; v /= 10)
        d[n++] = (char)('0' + v % 10);              /* reversed */
    char *o = buf;
    if (x < 0.0)
        *o++ = '-';
    if (decpt <= 0) {
        *o++ = '0';
        *o++ = '.';
        for (int i = 0; i < -decpt; i++)
            *o++ = '0';
        for (int i = n - 1; i >= 0; i--)
            *o++ = d[i];
    } else if (decpt >= n) {
        for (int i = n - 1; i >= 0; i--)
            *o++ = d[i];
        for (int i = n; i < decpt; i++)
            *o++ = '0';
        *o++ = '.';
        *o++ = '0';
    } else {
        for (int i = n - 1; i >= 0; i--) {
            *o++ = d[i];
            if (n - i == decpt)
                *o++ = '.';
        }
    }
    *o = 0;
    return (int)(o - buf);
}

/* repr of a double, through a small cache (a gas repeats its radius, mass, zeros) */
#define CACHE 1024
typedef struct {
    uint64_t bits;
    char text[32];
    int len;                   /* 0: empty */
} sf_cached;
static sf_cached cache[CACHE];

static int put_real(sf_buf *b, double x)
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    sf_cached *e = &cache[(bits ^ (bits >> 29) ^ (bits >> 47)) & (CACHE - 1)];
    if (e->len && e->bits == bits)
        return put(b, e->text, (size_t)e->len);
    char quick[40];
    int len = quick_repr(x, quick);
    if (len)
        return put(b, quick, (size_t)len);
    char *s = PyOS_double_to_string(x, 'r', 0, PY_DTSF_ADD_DOT_0, NULL);
    if (!s)
        return -1;
    size_t n = strlen(s);
    int rc = put(b, s, n);
    if (n < sizeof e->text) {
        memcpy(e->text, s, n);
        e->len = (int)n;
        e->bits = bits;
    }
    PyMem_Free(s);
    return rc;
}

/* ------------------------------------------------------------ JSON */
static void space(sf_scene *s)
{
    while (s->p < s->end && (*s->p == ' ' || *s->p == '\n' || *s->p == '\t' || *s->p == '\r'))
        s->p++;
}

static int eat(sf_scene *s, char c)
{
    space(s);
    if (s->p < s->end && *s->p == c) {
        s->p++;
        return 1;
    }
    return 0;
}

/* a string: its characters' span, *plain when it has no escape; 0 when not a valid JSON string */
static int string(sf_scene *s, const char **at, long *len, int *plain)
{
    space(s);
    if (s->p >= s->end || *s->p != '"')
        return 0;
    const char *q = ++s->p;
    *plain = 1;
    while (q < s->end && *q != '"') {
        unsigned char c = (unsigned char)*q;
        if (c < 0x20)
            return 0;
        if (c == '\\') {
            *plain = 0;
            q++;
            if (q >= s->end)
                return 0;
            if (*q == 'u') {
                for (int k = 1; k <= 4; k++) {
                    char h = q + k < s->end ? q[k] : 0;
                    if (!((h >= '0' && h <= '9') || (h >= 'a' && h <= 'f') || (h >= 'A' && h <= 'F')))
                        return 0;
                }
                q += 4;
            } else if (!strchr("\"\\/bfnrt", *q) || !*q) {
                return 0;
            }
        }
        q++;
    }
    if (q >= s->end)
        return 0;
    *at = s->p;
    *len = q - s->p;
    s->p = q + 1;
    return 1;
}

/* a key and its colon: 1 with its span, 0 at a malformed one */
static int key(sf_scene *s, const char **at, long *len)
{
    int plain;
    if (!string(s, at, len, &plain) || !plain)
        return 0;
    return eat(s, ':');
}

static int is(const char *at, long len, const char *word)
{
    return (long)strlen(word) == len && memcmp(at, word, (size_t)len) == 0;
}

/* a JSON number as Python's json and float() read it: 1 and the double (out NULL: the grammar only, any
   number json reads), 0 when not a number or not plainly a finite double */
static int number(sf_scene *s, double *out)
{
    space(s);
    const char *q = s->p, *start = q;
    int whole = 1;
    if (q < s->end && *q == '-')
        q++;
    if (q >= s->end || *q < '0' || *q > '9')
        return 0;
    if (*q == '0')
        q++;
    else
        while (q < s->end && *q >= '0' && *q <= '9')
            q++;
    if (q < s->end && *q == '.') {
        whole = 0;
        q++;
        if (q >= s->end || *q < '0' || *q > '9')
            return 0;
        while (q < s->end && *q >= '0' && *q <= '9')
            q++;
    }
    if (q < s->end && (*q == 'e' || *q == 'E')) {
        whole = 0;
        q++;
        if (q < s->end && (*q == '+' || *q == '-'))
            q++;
        if (q >= s->end || *q < '0' || *q > '9')
            return 0;
        while (q < s->end && *q >= '0' && *q <= '9')
            q++;
    }
    if (!out) {
        s->p = q;
        return 1;
    }
    if (whole) {
        /* an int, which the reader makes a float: exact up to 18 digits in 64 bits, then rounded once */
        const char *d = start + (*start == '-');
        if (q - d > 18)
            return 0;
        int64_t v = 0;
        for (; d < q; d++)
            v = v * 10 + (*d - '0');
        *out = (double)(*start == '-' ? -v : v);
    } else {
        /* up to 19 significant digits and a small exponent: the quick way, when it can tell */
        uint64_t w = 0;
        int digits = 0, p = 0, exp_sign = 1, exp = 0, after = 0;
        const char *d = start + (*start == '-');
        for (; d < q && *d != 'e' && *d != 'E'; d++) {
            if (*d == '.') {
                after = 1;
                continue;
            }
            if (digits || *d != '0') {
                if (++digits > 19)
                    break;
                w = w * 10 + (uint64_t)(*d - '0');
            }
            p -= after;                             /* a digit after the point */
        }
        if (digits <= 19 && d < q) {
            d++;
            if (*d == '+' || *d == '-')
                exp_sign = *d++ == '-' ? -1 : 1;
            for (; d < q && exp < 1000; d++)
                exp = exp * 10 + (*d - '0');
        }
        if (digits <= 19 && exp < 1000 && quick_double(w, p + exp_sign * exp, out)) {
            if (*start == '-')
                *out = -*out;
            s->p = q;
            return 1;
        }
        char *stop = NULL;
        *out = PyOS_string_to_double(start, &stop, NULL);
        if (stop != q || !isfinite(*out))
            return 0;
    }
    s->p = q;
    return 1;
}

/* [x, y] */
static int pair(sf_scene *s, double *x, double *y)
{
    return eat(s, '[') && number(s, x) && eat(s, ',') && number(s, y) && eat(s, ']');
}

/* any JSON value, checked and passed over */
static int skip(sf_scene *s, int depth)
{
    space(s);
    if (s->p >= s->end || depth > MAX_DEPTH)
        return 0;
    char c = *s->p;
    if (c == '{') {
        s->p++;
        if (eat(s, '}'))
            return 1;
        do {
            const char *at;
            long len;
            int plain;
            if (!string(s, &at, &len, &plain) || !eat(s, ':') || !skip(s, depth + 1))
                return 0;
        } while (eat(s, ','));
        return eat(s, '}');
    }
    if (c == '[') {
        s->p++;
        if (eat(s, ']'))
            return 1;
        do {
            if (!skip(s, depth + 1))
                return 0;
        } while (eat(s, ','));
        return eat(s, ']');
    }
    if (c == '"') {
        const char *at;
        long len;
        int plain;
        return string(s, &at, &len, &plain);
    }
    if (c == '-' || (c >= '0' && c <= '9'))
        return number(s, NULL);         /* (NaN and the infinities, which json reads too, are not mine) */
    for (const char *const *w = (const char *const[]){"true", "false", "null", NULL}; *w; w++) {
        size_t n = strlen(*w);
        if ((size_t)(s->end - s->p) >= n && memcmp(s->p, *w, n) == 0) {
            s->p += n;
            return 1;
        }
    }
    return 0;
}

/* ------------------------------------------------------------ bodies */
static int grow(sf_scene *s)
{
    long cap = s->cap ? 2 * s->cap : 1024;
#define GROW(f)                                                    \
    do {                                                           \
        void *q = realloc(s->f, sizeof *s->f * (size_t)cap);       \
        if (!q)                                                    \
            return -1;                                             \
        s->f = q;                                                  \
    } while (0)
    GROW(kind); GROW(fixed); GROW(mass); GROW(restitution); GROW(friction); GROW(px); GROW(py); GROW(vx);
    GROW(vy); GROW(ax); GROW(ay); GROW(angle); GROW(omega); GROW(radius); GROW(name_at); GROW(name_len);
#undef GROW
    s->cap = cap;
    return 0;
}

/* bits of the body keys seen */
enum { K_NAME = 1, K_SHAPE = 2, K_RADIUS = 4, K_MASS = 8, K_FIXED = 16, K_POSITION = 32, K_VELOCITY = 64,
       K_ACCELERATION = 128, K_ANGLE = 256, K_OMEGA = 512, K_RESTITUTION = 1024, K_FRICTION = 2048,
       K_COMMENT = 4096, K_VERTICES = 8192, K_ORBIT = 16384 };

/* bodies[k]: MINE, NOT_MINE or NO_MEMORY */
static int body(sf_scene *s, long k)
{
    if (k >= s->cap && grow(s))
        return NO_MEMORY;
    space(s);
    const char *start = s->p;
    if (!eat(s, '{'))
        return NOT_MINE;
    unsigned seen = 0;
    int shape = -1, fixed = 0;          /* shape 0 circle, 1 polygon */
    double mass = 0, restitution = 1.0, friction = 0.0, radius = 0, px = 0, py = 0, vx = 0.0, vy = 0.0, ax = 0.0,
           ay = 0.0, angle = 0.0, omega = 0.0;
    const char *name = NULL;
    long name_len = 0;
    if (!eat(s, '}')) {
        do {
            const char *at, *vat;
            long len, vlen;
            int plain;
            unsigned bit;
            if (!key(s, &at, &len))
                return NOT_MINE;
            int ok;
            if (is(at, len, "name")) {
                bit = K_NAME;
                ok = string(s, &vat, &vlen, &plain) && plain && vlen > 0;
                for (long i = 0; ok && i < vlen; i++)
                    ok = vat[i] >= 0x20 && vat[i] < 0x7f;
                name = vat;
                name_len = vlen;
            } else if (is(at, len, "shape")) {
                bit = K_SHAPE;
                ok = string(s, &vat, &vlen, &plain) && plain;
                shape = ok && is(vat, vlen, "circle") ? 0 : ok && is(vat, vlen, "polygon") ? 1 : -1;
                ok = ok && shape >= 0;
            } else if (is(at, len, "fixed")) {
                bit = K_FIXED;
                space(s);
                if ((size_t)(s->end - s->p) >= 4 && memcmp(s->p, "true", 4) == 0) {
                    fixed = 1;
                    s->p += 4;
                    ok = 1;
                } else if ((size_t)(s->end - s->p) >= 5 && memcmp(s->p, "false", 5) == 0) {
                    fixed = 0;
                    s->p += 5;
                    ok = 1;
                } else {
                    ok = 0;
                }
            } else if (is(at, len, "radius")) {
                bit = K_RADIUS;
                ok = number(s, &radius);
            } else if (is(at, len, "mass")) {
                bit = K_MASS;
                ok = number(s, &mass);
            } else if (is(at, len, "restitution")) {
                bit = K_RESTITUTION;
                ok = number(s, &restitution);
            } else if (is(at, len, "friction")) {
                bit = K_FRICTION;
                ok = number(s, &friction);
            } else if (is(at, len, "angle")) {
                bit = K_ANGLE;
                ok = number(s, &angle);
            } else if (is(at, len, "angular_velocity")) {
                bit = K_OMEGA;
                ok = number(s, &omega);
            } else if (is(at, len, "position")) {
                bit = K_POSITION;
                ok = pair(s, &px, &py);
            } else if (is(at, len, "velocity")) {
                bit = K_VELOCITY;
                ok = pair(s, &vx, &vy);
            } else if (is(at, len, "acceleration")) {
                bit = K_ACCELERATION;
                ok = pair(s, &ax, &ay);
            } else if (is(at, len, "comment")) {
                bit = K_COMMENT;
                ok = skip(s, 1);
            } else if (is(at, len, "vertices")) {
                bit = K_VERTICES;
                ok = skip(s, 1);
            } else if (is(at, len, "orbit")) {
                bit = K_ORBIT;
                ok = skip(s, 1);
            } else {
                return NOT_MINE;            /* an unknown key: Python names it */
            }
            /* a key given twice (json keeps the last) or a value not as above (a polygon's too) */
            if (!ok || (seen & bit))
                return NOT_MINE;
            seen |= bit;
        } while (eat(s, ','));
        if (!eat(s, '}'))
            return NOT_MINE;
    }
    s->name_at[k] = name ? name - s->text : -1;
    s->name_len[k] = name_len;
    if (shape == 1) {
        s->kind[k] = 1;
        s->poly_start[s->npoly] = start - s->text;
        s->poly_end[s->npoly] = s->p - s->text;
        s->poly[s->npoly++] = k;
        return MINE;
    }
    if (shape != 0 || !(seen & K_POSITION) || !(seen & K_RADIUS) || (seen & (K_VERTICES | K_ORBIT)))
        return NOT_MINE;
    if (fixed ? (seen & K_MASS) != 0 : !((seen & K_MASS) && mass > 0.0))
        return NOT_MINE;
    if (!(restitution >= 0.0 && restitution <= 1.0) || !(friction >= 0.0) || !(radius >= s->tolerance)
        || omega != 0.0)
        return NOT_MINE;
    if (!fixed) {
        ax = ax + s->gx;
        ay = ay + s->gy;
    }
    if (ax != 0.0 || ay != 0.0)
        s->accelerates = 1;
    s->kind[k] = 0;
    s->fixed[k] = (unsigned char)fixed;
    s->mass[k] = fixed ? INFINITY : mass;
    s->restitution[k] = restitution;
    s->friction[k] = friction;
    s->px[k] = px;
    s->py[k] = py;
    s->vx[k] = vx;
    s->vy[k] = vy;
    s->ax[k] = ax;
    s->ay[k] = ay;
    s->angle[k] = angle;
    s->omega[k] = omega;
    s->radius[k] = radius;
    return MINE;
}

/* ------------------------------------------------------------ names */
static uint64_t hash_bytes(const char *p, long n)
{
    uint64_t h = 1469598103934665603ull;
    for (long i = 0; i < n; i++)
        h = (h ^ (unsigned char)p[i]) * 1099511628211ull;
    return h;
}

/* the names' JSON text (each followed by a newline); NOT_MINE when two are alike */
static int names(sf_scene *s)
{
    size_t slots = 16;
    while (slots < 2 * (size_t)s->n)
        slots *= 2;
    long *slot = malloc(sizeof *slot * slots);      /* body index + 1, 0: empty */
    long *at = malloc(sizeof *at * (size_t)s->n);
    if (!slot || !at) {
        free(slot);
        free(at);
        return NO_MEMORY;
    }
    memset(slot, 0, sizeof *slot * slots);
    int rc = MINE;
    char own[32];
    for (long k = 0; k < s->n && rc == MINE; k++) {
        const char *name;
        long len;
        at[k] = (long)s->names.n + 1;
        if (s->name_at[k] >= 0) {
            name = s->text + s->name_at[k];
            len = s->name_len[k];
        } else {
            len = snprintf(own, sizeof own, "body%ld", k);
            name = own;
        }
        if (put(&s->names, "\"", 1) || put(&s->names, name, (size_t)len) || put(&s->names, "\"\n", 2)) {
            rc = NO_MEMORY;
            break;
        }
        const char *mine = s->names.s + at[k];
        size_t h = (size_t)hash_bytes(mine, len) & (slots - 1);
        for (;; h = (h + 1) & (slots - 1)) {
            if (!slot[h]) {
                slot[h] = k + 1;
                break;
            }
            long j = slot[h] - 1;
            /* names as written: the other's may have moved with the buffer, so by offset */
            if (s->names.s[at[j] + len] == '"' && memcmp(s->names.s + at[j], s->names.s + at[k], (size_t)len) == 0) {
                rc = NOT_MINE;
                break;
            }
        }
    }
    free(slot);
    free(at);
    return rc;
}

/* ------------------------------------------------------------ the scene */
enum { S_NAME = 1, S_END = 2, S_FRAME = 4, S_GRAVITY = 8, S_TOL = 16, S_REST = 32, S_ORDER = 64, S_BODIES = 128,
       S_INPUTS = 256, S_SAME = 512, S_EVENTS = 1024, S_FPS = 2048, S_COMMENT = 4096 };

void sf_free(void *h)
{
    sf_scene *s = h;
    if (!s)
        return;
    free(s->kind); free(s->fixed); free(s->mass); free(s->restitution); free(s->friction); free(s->px);
    free(s->py); free(s->vx); free(s->vy); free(s->ax); free(s->ay); free(s->angle); free(s->omega);
    free(s->radius); free(s->name_at); free(s->name_len); free(s->poly); free(s->poly_start); free(s->poly_end);
    free(s->large); free(s->out.s); free(s->names.s);
    free(s);
}

/* the numbers of a scene, checked as _parse_scene checks them; NOT_MINE when one is not plainly right */
static int scene_numbers(sf_scene *s)
{
    double e = s->end_time;
    if (!(e > 0.0) || !(s->frame_rate >= 0.0) || !(s->tolerance > 0.0) || !(s->rest_speed >= 0.0)
        || !(s->order > 0.0) || s->order != floor(s->order) || s->order > 7.0 || !(s->max_same > 0.0)
        || s->max_same != floor(s->max_same) || s->max_same >= 9223372036854775808.0 || !(s->max_events > 0.0)
        || s->max_events != floor(s->max_events) || s->max_events >= 9223372036854775808.0
        || !(s->max_frame_rate > 0.0) || s->frame_rate > s->max_frame_rate
        || s->frame_rate * e > s->max_events || e > LENGTH_MAX || s->tolerance < LENGTH_MIN
        || s->tolerance > LENGTH_MAX)
        return NOT_MINE;
    return MINE;
}

/* Read the scene: MINE when it is the case above (then sf_polygon, sf_facts and sf_names tell what Python
   needs, and sf_compile finishes), NOT_MINE, or NO_MEMORY. */
int sf_parse(void *h, const char *text, long size)
{
    sf_scene *s = h;
    numbers_init();
    for (long i = 0; i < size; i++)
        if ((unsigned char)text[i] >= 0x80)
            return NOT_MINE;            /* Python reads UTF-8 and names the bad byte */
    s->text = s->p = text;
    s->end = text + size;
    s->tolerance = 1e-9;
    s->rest_speed = 0.05;
    s->order = 4.0;
    s->max_same = 100000.0;
    s->max_events = 10000000.0;
    s->max_frame_rate = 1000.0;
    if (!eat(s, '{'))
        return NOT_MINE;
    unsigned seen = 0;
    const char *bodies = NULL;
    do {
        const char *at, *vat;
        long len, vlen;
        int plain, ok;
        unsigned bit;
        if (!key(s, &at, &len))
            return NOT_MINE;
        if (is(at, len, "name")) {
            bit = S_NAME;
            ok = string(s, &vat, &vlen, &plain);
        } else if (is(at, len, "comment")) {
            bit = S_COMMENT;
            ok = skip(s, 1);
        } else if (is(at, len, "end_time")) {
            bit = S_END;
            ok = number(s, &s->end_time);
        } else if (is(at, len, "frame_rate")) {
            bit = S_FRAME;
            ok = number(s, &s->frame_rate);
        } else if (is(at, len, "gravity")) {
            bit = S_GRAVITY;
            ok = pair(s, &s->gx, &s->gy);
        } else if (is(at, len, "tolerance")) {
            bit = S_TOL;
            ok = number(s, &s->tolerance);
        } else if (is(at, len, "rest_speed")) {
            bit = S_REST;
            ok = number(s, &s->rest_speed);
        } else if (is(at, len, "taylor_order")) {
            bit = S_ORDER;
            ok = number(s, &s->order);
        } else if (is(at, len, "max_events_at_one_time")) {
            bit = S_SAME;
            ok = number(s, &s->max_same);
        } else if (is(at, len, "max_events")) {
            bit = S_EVENTS;
            ok = number(s, &s->max_events);
        } else if (is(at, len, "max_frame_rate")) {
            bit = S_FPS;
            ok = number(s, &s->max_frame_rate);
        } else if (is(at, len, "inputs")) {
            bit = S_INPUTS;
            ok = eat(s, '[') && eat(s, ']');
        } else if (is(at, len, "bodies")) {
            bit = S_BODIES;
            space(s);
            bodies = s->p;              /* read when the gravity is known */
            ok = skip(s, 1);
        } else {
            return NOT_MINE;
        }
        if (!ok || (seen & bit))
            return NOT_MINE;
        seen |= bit;
    } while (eat(s, ','));
    if (!eat(s, '}'))
        return NOT_MINE;
    space(s);
    if (s->p != s->end || !(seen & S_END) || !bodies)
        return NOT_MINE;
    if (scene_numbers(s))
        return NOT_MINE;
    /* the bodies */
    s->p = bodies;
    if (!eat(s, '['))
        return NOT_MINE;
    long npoly_cap = MAX_LARGE;
    s->poly = malloc(sizeof *s->poly * (size_t)npoly_cap);
    s->poly_start = malloc(sizeof *s->poly_start * (size_t)npoly_cap);
    s->poly_end = malloc(sizeof *s->poly_end * (size_t)npoly_cap);
    if (!s->poly || !s->poly_start || !s->poly_end)
        return NO_MEMORY;
    long k = 0;
    do {
        if (s->npoly == MAX_LARGE)
            return NOT_MINE;            /* polygons are tested against every circle */
        int rc = body(s, k);
        if (rc)
            return rc;
        k++;
    } while (eat(s, ','));
    if (!eat(s, ']'))
        return NOT_MINE;
    s->n = k;
    return names(s);
}

void *sf_new(void) { return calloc(1, sizeof(sf_scene)); }

long sf_polygons(void *h) { return ((sf_scene *)h)->npoly; }

/* polygon j: its body index and its JSON text's span */
void sf_polygon(void *h, long j, long *index, long *start, long *end)
{
    sf_scene *s = h;
    *index = s->poly[j];
    *start = s->poly_start[j];
    *end = s->poly_end[j];
}

/* facts: end_time, frame_rate, gravity x and y, tolerance, rest_speed, taylor_order, max_events_at_one_time,
   max_events, bodies, whether a circle accelerates */
void sf_facts(void *h, double *out)
{
    sf_scene *s = h;
    double v[] = {s->end_time, s->frame_rate, s->gx, s->gy, s->tolerance, s->rest_speed, s->order, s->max_same,
                  s->max_events, (double)s->n, (double)s->accelerates};
    memcpy(out, v, sizeof v);
}

/* the bodies' names as JSON, each followed by a newline */
const char *sf_names(void *h, long *size)
{
    sf_scene *s = h;
    *size = (long)s->names.n;
    return s->names.s;
}

/* ------------------------------------------------------------ checks */
/* Python's float // for finite doubles, as int: 1 when it fits in 2^52 */
static int floordiv(double a, double b, long *out)
{
    double mod = fmod(a, b), div = (a - mod) / b, f;
    if (mod != 0.0 && ((b < 0.0) != (mod < 0.0)))
        div -= 1.0;
    if (div != 0.0) {
        f = floor(div);
        if (div - f > 0.5)
            f += 1.0;
    } else {
        f = 0.0;
    }
    if (!(fabs(f) < 4503599627370496.0))
        return 0;
    *out = (long)f;
    return 1;
}

/* clear: circles i and j not overlapping by more than the tolerance, with a margin (penetration's
   r_i + r_j - hypot > tol is an overlap) */
static int circles_clear(const sf_scene *s, long i, long j, double tol)
{
    double gap = s->radius[i] + s->radius[j] - tol;
    if (!(gap > 0.0))
        return 1;                       /* r_i + r_j - hypot <= r_i + r_j <= tol, rounded alike */
    double need = gap + MARGIN * (s->radius[i] + s->radius[j] + tol);
    double dx = s->px[j] - s->px[i], dy = s->py[j] - s->py[i];
    return dx * dx + dy * dy > need * need;
}

typedef struct {
    long *head, *next;
    int64_t *kx, *ky;
    size_t mask;
    double cell;
} sf_grid;

static size_t cell_slot(const sf_grid *g, int64_t x, int64_t y)
{
    uint64_t h = (uint64_t)x * 0x9E3779B97F4A7C15ull ^ (uint64_t)y * 0xC2B2AE3D27D4EB4Full;
    return (size_t)(h ^ (h >> 31)) & g->mask;
}

/* overlaps at t = 0: MINE when every pair with a movable circle is clear */
static int overlaps(sf_scene *s, const double *poly)
{
    double tol = s->tolerance, big = 0.0;
    long movable = 0;
    for (long k = 0; k < s->n; k++)
        if (!s->kind[k] && !s->fixed[k]) {
            movable++;
            if (s->radius[k] > big)
                big = s->radius[k];
        }
    if (!movable)
        return MINE;                    /* fixed pairs are never tested */
    double cell = 2.0 * big * (1.0 + MARGIN) + tol;
    /* polygons: each box clear of each movable circle's */
    for (long j = 0; j < s->npoly; j++) {
        const double *b = poly + 7 * j + 3;
        double pad = tol + MARGIN * (fabs(b[0]) + fabs(b[1]) + fabs(b[2]) + fabs(b[3]) + 2.0 * big);
        for (long k = 0; k < s->n; k++) {
            if (s->kind[k] || s->fixed[k])
                continue;
            double r = s->radius[k];
            if (!(s->px[k] - r > b[2] + pad || s->px[k] + r + pad < b[0] || s->py[k] - r > b[3] + pad
                  || s->py[k] + r + pad < b[1]))
                return NOT_MINE;
        }
    }
    /* circles larger than a cell's half: each against every movable circle */
    long nlarge = 0, nsmall = 0;
    for (long k = 0; k < s->n; k++) {
        if (s->kind[k])
            continue;
        if (s->radius[k] > cell / 2.0) {
            if (++nlarge > MAX_LARGE)
                return NOT_MINE;
            for (long i = 0; i < s->n; i++)
                if (!s->kind[i] && !s->fixed[i] && i != k && !circles_clear(s, i, k, tol))
                    return NOT_MINE;
        } else {
            nsmall++;
        }
    }
    /* the others through a grid of cells at least as wide as two of them: neighbours can touch */
    sf_grid g = {0};
    size_t slots = 16;
    while (slots < 2 * (size_t)nsmall)
        slots *= 2;
    g.mask = slots - 1;
    g.head = malloc(sizeof *g.head * slots);
    g.next = malloc(sizeof *g.next * (size_t)s->n);
    g.kx = malloc(sizeof *g.kx * (size_t)s->n);
    g.ky = malloc(sizeof *g.ky * (size_t)s->n);
    int rc = MINE;
    if (!g.head || !g.next || !g.kx || !g.ky) {
        rc = NO_MEMORY;
        goto done;
    }
    for (size_t i = 0; i < slots; i++)
        g.head[i] = -1;
    for (long k = 0; k < s->n && rc == MINE; k++) {
        if (s->kind[k] || s->radius[k] > cell / 2.0)
            continue;
        double fx = floor(s->px[k] / cell), fy = floor(s->py[k] / cell);
        if (!(fabs(fx) < 1e15 && fabs(fy) < 1e15)) {
            rc = NOT_MINE;
            break;
        }
        int64_t x = (int64_t)fx, y = (int64_t)fy;
        g.kx[k] = x;
        g.ky[k] = y;
        /* test against the circles already in this and the eight neighbouring cells */
        for (int64_t dx = -1; dx <= 1 && rc == MINE; dx++)
            for (int64_t dy = -1; dy <= 1 && rc == MINE; dy++) {
                size_t h = cell_slot(&g, x + dx, y + dy);
                for (long j = g.head[h]; j >= 0; j = g.next[j]) {
                    if (g.kx[j] != x + dx || g.ky[j] != y + dy || (s->fixed[j] && s->fixed[k]))
                        continue;
                    if (!circles_clear(s, j, k, tol)) {
                        rc = NOT_MINE;
                        break;
                    }
                }
            }
        size_t h = cell_slot(&g, x, y);
        g.next[k] = g.head[h];
        g.head[h] = k;
    }
done:
    free(g.head);
    free(g.next);
    free(g.kx);
    free(g.ky);
    return rc;
}

/* a circle's magnitudes (_check_magnitudes without inputs): MINE when all hold with the margin */
static int magnitudes(const sf_scene *s)
{
    double T = s->end_time, lim = LENGTH_MAX * (1.0 - MARGIN);
    double lim_v = LENGTH_MAX / T * (1.0 - MARGIN), lim_a = LENGTH_MAX / T / T * (1.0 - MARGIN);
    for (long k = 0; k < s->n; k++) {
        if (s->kind[k])
            continue;
        double r = s->radius[k];
        double speed = hypot(s->vx[k], s->vy[k]), accel = hypot(s->ax[k], s->ay[k]);
        double far = hypot(s->px[k], s->py[k]);
        if (!(r <= lim) || !(r >= LENGTH_MIN * (1.0 + MARGIN)) || !(far <= lim) || !(speed <= lim_v)
            || !(accel <= lim_a) || !((far + speed * T + accel * T * T / 2.0 + r) * (1.0 + MARGIN) <= lim))
            return NOT_MINE;
        if (!s->fixed[k] && !(isfinite(1.0 / s->mass[k]) && 1.0 / s->mass[k] < 1e300))
            return NOT_MINE;
    }
    return MINE;
}

/* ------------------------------------------------------------ the flat scene */
static int line_real(sf_buf *b, const char *head, double x)
{
    return puts_(b, head) || put_real(b, x) || put(b, "\n", 1);
}

/* Check and compile: poly holds per polygon (in sf_polygon's order) its bound, position x and y, and its box
   at t = 0 (x0 y0 x1 y1); large gets per polygon whether it is large (the LARGE token).  MINE, NOT_MINE or
   NO_MEMORY; then sf_text gives the flat scene's head (up to the bodies' lines) and sf_part the rest. */
int sf_compile(void *h, const double *poly, unsigned char *large)
{
    sf_scene *s = h;
    s->text = s->p = s->end = NULL;     /* Python frees the JSON text once this returns */
    int rc = magnitudes(s);
    if (rc || (rc = overlaps(s, poly)))
        return rc;
    /* the grid (make_grid) */
    double movable = -1.0;
    for (long k = 0; k < s->n; k++)
        if (!s->kind[k] && !s->fixed[k] && (movable < 0.0 || s->radius[k] > movable))
            movable = s->radius[k];     /* a circle's bound is 0.0 + radius: the radius (polygons are fixed) */
    double size = 2.0 * (movable < 0.0 ? 1.0 : movable) * (1.0 + 1e-6);
    s->large = malloc((size_t)s->n + 1);
    if (!s->large)
        return NO_MEMORY;
    double lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
    long small = 0, j = 0;
    for (long k = 0; k < s->n; k++) {
        double bound, x, y;
        if (s->kind[k]) {
            bound = poly[7 * j];
            x = poly[7 * j + 1];
            y = poly[7 * j + 2];
            large[j++] = bound * 2.0 > size;
        } else {
            bound = 0.0 + s->radius[k];
            x = s->px[k];
            y = s->py[k];
        }
        s->large[k] = bound * 2.0 > size;
        if (!s->large[k]) {
            small++;
            lo_x = x < lo_x ? x : lo_x;
            lo_y = y < lo_y ? y : lo_y;
            hi_x = x > hi_x ? x : hi_x;
            hi_y = y > hi_y ? y : hi_y;
        }
    }
    double x0 = 0.0, y0 = 0.0, cw = size, ch = size, margin = 0.0;
    long nx = 1, ny = 1;
    if (small) {
        double cell = size * SF_CELL_FACTOR;
        x0 = lo_x - cell;
        y0 = lo_y - cell;
        double w = hi_x - lo_x + 2.0 * cell, hgt = hi_y - lo_y + 2.0 * cell;
        long limit = 4 * small > 16 ? 4 * small : 16;
        if (!floordiv(w, cell, &nx) || !floordiv(hgt, cell, &ny) || nx > (1L << 30) || ny > (1L << 30))
            return NOT_MINE;
        nx = nx > 1 ? nx : 1;
        ny = ny > 1 ? ny : 1;
        while (nx * ny > limit) {
            nx = nx / 2 > 1 ? nx / 2 : 1;
            ny = ny / 2 > 1 ? ny / 2 : 1;
        }
        cw = w / (double)nx;
        ch = hgt / (double)ny;
        margin = 0.5 * ((ch < cw ? ch : cw) - size);     /* the whole slack, as Python's max(0, ...) */
        margin = margin > 0.0 ? margin : 0.0;
    }
    /* the text */
    sf_buf *b = &s->out;
    char tmp[96];
    b->n = 0;
    if (puts_(b, "m2c-scene 1\n") || line_real(b, "end ", s->end_time)
        || line_real(b, "frame ", s->frame_rate > 0.0 ? 1.0 / s->frame_rate : 0.0)
        || line_real(b, "tolerance ", s->tolerance) || line_real(b, "rest_speed ", s->rest_speed)
        || line_real(b, "window_angle ", 0.5))
        return NO_MEMORY;
    snprintf(tmp, sizeof tmp, "max_same_time %lld\nmax_events %lld\ngrid ", (long long)s->max_same,
             (long long)s->max_events);
    if (puts_(b, tmp) || put_real(b, x0) || put(b, " ", 1) || put_real(b, y0) || put(b, " ", 1) || put_real(b, cw)
        || put(b, " ", 1) || put_real(b, ch))
        return NO_MEMORY;
    snprintf(tmp, sizeof tmp, " %ld %ld ", nx, ny);
    if (puts_(b, tmp) || put_real(b, margin))
        return NO_MEMORY;
    snprintf(tmp, sizeof tmp, "\nbodies %ld\n", s->n);
    if (puts_(b, tmp))
        return NO_MEMORY;
    return MINE;
}

/* After sf_compile: the lines of the bodies from `from` on, up to `upto` or the first polygon (whose lines
   Python writes), in place of the text before; returns the index reached, -1 when out of memory.  The flat
   scene is sf_compile's text, then the bodies' lines in order, then "inputs 0" and "end". */
long sf_part(void *h, long from, long upto)
{
    sf_scene *s = h;
    sf_buf *b = &s->out;
    b->n = 0;
    long k = from;
    for (; k < upto && k < s->n && !s->kind[k]; k++) {
        int fixed = s->fixed[k];
        /* body 0 FIXED INV_MASS 0.0 RESTITUTION FRICTION PX PY VX VY AX AY ANGLE OMEGA RADIUS 0.0 0.0 BOUND 0.0
           LARGE 0 (_circle_line) */
        if (puts_(b, fixed ? "body 0 1 " : "body 0 0 ") || put_real(b, fixed ? 0.0 : 1.0 / s->mass[k])
            || puts_(b, " 0.0 ") || put_real(b, s->restitution[k]) || put(b, " ", 1)
            || put_real(b, s->friction[k]) || put(b, " ", 1) || put_real(b, s->px[k]) || put(b, " ", 1)
            || put_real(b, s->py[k]) || put(b, " ", 1) || put_real(b, s->vx[k]) || put(b, " ", 1)
            || put_real(b, s->vy[k]) || put(b, " ", 1) || put_real(b, s->ax[k]) || put(b, " ", 1)
            || put_real(b, s->ay[k]) || put(b, " ", 1) || put_real(b, s->angle[k]) || put(b, " ", 1)
            || put_real(b, s->omega[k]) || put(b, " ", 1) || put_real(b, s->radius[k]) || puts_(b, " 0.0 0.0 ")
            || put_real(b, 0.0 + s->radius[k]) || puts_(b, s->large[k] ? " 0.0 1 0\n" : " 0.0 0 0\n"))
            return -1;
    }
    return k;
}

const char *sf_text(void *h, long *size)
{
    sf_scene *s = h;
    *size = (long)s->out.n;
    return s->out.s;
}

/* for tests/simulator/test_scene_c.py: a number read as the scene reader reads it (1 and *out, 0 when it is not one
   it takes), and a double written as the flat scene writes it (its length) */
int sf_number(const char *text, long size, double *out)
{
    sf_scene s = {0};
    numbers_init();
    s.text = s.p = text;
    s.end = text + size;
    return number(&s, out) && s.p == s.end;
}

long sf_repr(double x, char *out, long cap)
{
    sf_buf b = {0};
    numbers_init();
    if (put_real(&b, x) || (long)b.n >= cap) {
        free(b.s);
        return -1;
    }
    memcpy(out, b.s, b.n + 1);
    long n = (long)b.n;
    free(b.s);
    return n;
}
