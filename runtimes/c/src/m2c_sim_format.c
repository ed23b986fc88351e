/* m2c_sim_format_number: a double as printf("%.17g") writes it, without
 * printf's cost (glibc formats a %.17g in about half a microsecond; a
 * collision writes 20 numbers).
 *
 * Exact and correctly rounded like printf: for a normal x = f 2^e2 the
 * 17 significant digits are D = round-half-even(x 10^p) with p = 16 - X,
 * computed in integers, with X chosen so that 10^16 <= floor(x 10^p) <
 * 10^17.  For 0 <= p <= 27 (X from -11 to 16, nearly every number of a
 * trace) x 10^p = (f 2^11)(5^p 2^z) 2^(e2 + p - 11 - z) with both factors'
 * top bits set: one 64 x 64-bit product whose high word, shifted, gives D;
 * otherwise f 5^p in 192 bits and shifted, or f 2^e2 / 10^-p in 128 bits.
 * Values outside that exact range (below about 1e-39, above 2^128,
 * subnormals) go to snprintf itself.  The digits are made eight at a time
 * in one 64-bit word (see eight_digit_values).  Then %g's rules: fixed
 * notation when -4 <= X < 17, else d.ddde+XX; trailing zeros and a bare
 * point dropped. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_sim.h"

__extension__ typedef unsigned __int128 m2c_u128;

#define POW5_MAX 55             /* 5^55 < 2^128 */
#define POW10_MAX 22            /* 10^22 < 2^74 */

#define POW10_GUESS 60            /* 10^-60 .. 10^60 as doubles, for a first guess */

static m2c_u128 pow5[POW5_MAX + 1];
static double pow10d[2 * POW10_GUESS + 2];
static m2c_u128 pow10[POW10_MAX + 1];
#define POW5N_MAX 27            /* 5^27 < 2^63 */
static uint64_t pow5n[POW5N_MAX + 1];  /* 5^k shifted left until its top bit is set */
static int pow5z[POW5N_MAX + 1];       /* by that many bits */
static int tables_ready;

static void make_tables(void)
{
    pow5[0] = 1;
    for (int k = 1; k <= POW5_MAX; k++)
        pow5[k] = pow5[k - 1] * 5u;
    for (int k = 0; k <= POW5N_MAX; k++) {
        uint64_t v = (uint64_t)pow5[k];
        pow5z[k] = __builtin_clzll(v);
        pow5n[k] = v << pow5z[k];
    }
    pow10[0] = 1;
    for (int k = 1; k <= POW10_MAX; k++)
        pow10[k] = pow10[k - 1] * 10u;
    for (int k = -POW10_GUESS; k <= POW10_GUESS + 1; k++) {
        char text[16];
        snprintf(text, sizeof text, "1e%d", k);
        pow10d[k + POW10_GUESS] = strtod(text, NULL);
    }
    tables_ready = 1;
}

/* Bit k of the 192-bit m (limbs little-endian). */
static int bit_at(const uint64_t m[3], int k)
{
    return (int)((m[k / 64] >> (k % 64)) & 1u);
}

/* Whether any of the bits 0 .. k-1 of m is set (k < 192). */
static int any_below(const uint64_t m[3], int k)
{
    int limb = k / 64, b = k % 64;
    for (int i = 0; i < limb; i++)
        if (m[i] != 0)
            return 1;
    return b != 0 && (m[limb] & ((UINT64_C(1) << b) - 1u)) != 0;
}

/* floor(m / 2^sh) when it fits 64 bits (0 < sh < 192); -1 if it does not. */
static int shift_down(const uint64_t m[3], int sh, uint64_t *q)
{
    uint64_t r[3];
    int limb = sh / 64, b = sh % 64;
    for (int k = 0; k < 3; k++) {
        int src = k + limb;
        uint64_t lo = src < 3 ? m[src] : 0u;
        uint64_t hi = src + 1 < 3 ? m[src + 1] : 0u;
        r[k] = b != 0 ? (lo >> b) | (hi << (64 - b)) : lo;
    }
    if (r[1] != 0 || r[2] != 0)
        return -1;
    *q = r[0];
    return 0;
}

enum { TOO_SMALL = 1, TOO_LARGE = 2, NO_FAST_PATH = -1 };

/* With p = 16 - x10: *d = floor(f 2^e2 10^p) and *up = whether rounding to
 * nearest-even adds one.  0, TOO_SMALL (floor < 10^16), TOO_LARGE (floor >=
 * 10^17) or NO_FAST_PATH. */
static int scaled(uint64_t f, int e2, int x10, uint64_t *d, int *up)
{
    const uint64_t lo17 = UINT64_C(10000000000000000), hi17 = UINT64_C(100000000000000000);
    int p = 16 - x10;
    uint64_t q;
    int k = p >= 0 && p <= POW5N_MAX ? 11 + pow5z[p] - (e2 + p) - 64 : 0;
    if (k >= 1 && k <= 63) {
        /* the common case: the product of (f 2^11) and (5^p 2^z) has 127 or
         * 128 bits, and the digits (under 2^57) are its high word >> k */
        m2c_u128 n = (m2c_u128)(f << 11) * pow5n[p];
        uint64_t hi = (uint64_t)(n >> 64), lo = (uint64_t)n;
        q = hi >> k;
        uint64_t r = hi & ((UINT64_C(1) << k) - 1u), half = UINT64_C(1) << (k - 1);
        *up = r > half || (r == half && (lo != 0 || (q & 1u) != 0));
    } else if (p >= 0) {
        if (p > POW5_MAX)
            return NO_FAST_PATH;
        /* m = f 5^p, exactly, in 192 bits */
        m2c_u128 pw = pow5[p];
        m2c_u128 lo = (m2c_u128)f * (uint64_t)pw;
        m2c_u128 hi = (m2c_u128)f * (uint64_t)(pw >> 64) + (lo >> 64);
        uint64_t m[3] = { (uint64_t)lo, (uint64_t)hi, (uint64_t)(hi >> 64) };
        int s = e2 + p;         /* x 10^p = m 2^s */
        if (s >= 0) {
            if (m[1] != 0 || m[2] != 0 || s >= 64 || (s > 0 && (m[0] >> (64 - s)) != 0))
                return NO_FAST_PATH;
            q = m[0] << s;
            *up = 0;
        } else {
            int sh = -s;
            if (sh >= 192 || shift_down(m, sh, &q) != 0)
                return NO_FAST_PATH;
            if (!bit_at(m, sh - 1))
                *up = 0;
            else if (any_below(m, sh - 1))
                *up = 1;
            else
                *up = (int)(q & 1u);     /* a tie: to even */
        }
    } else {
        int k = -p;
        if (k > POW10_MAX || e2 < 0 || e2 + 53 > 127)
            return NO_FAST_PATH;
        m2c_u128 n = (m2c_u128)f << e2;
        m2c_u128 pw = pow10[k];
        m2c_u128 qq = n / pw, rr = n % pw;
        if ((qq >> 64) != 0)
            return NO_FAST_PATH;
        q = (uint64_t)qq;
        m2c_u128 twice = rr * 2u;
        *up = twice > pw ? 1 : (twice == pw ? (int)(q & 1u) : 0);
    }
    if (q < lo17)
        return TOO_SMALL;
    if (q >= hi17)
        return TOO_LARGE;
    *d = q;
    return 0;
}

/* The 17 digits of a normal double f 2^e2: *d in [10^16, 10^17) and the
 * decimal exponent *x10 of the first digit.  0, or -1 for no fast path. */
static int decimal17(double ax, uint64_t f, int e2, int *x10, uint64_t *d)
{
    if (!tables_ready)
        make_tables();
    /* floor(log10 x) is this or one more: 2^(e2+52) <= x < 2^(e2+53) */
    int x = ((e2 + 52) * 78913) >> 18;      /* floor((e2 + 52) log10(2)) for |e2| < 1100 */
    /* a guess of which (scaled() decides exactly) */
    if (x >= -POW10_GUESS && x < POW10_GUESS && ax >= pow10d[x + 1 + POW10_GUESS])
        x++;
    for (int tries = 0; tries < 3; tries++) {
        uint64_t q = 0;
        int up = 0;
        int r = scaled(f, e2, x, &q, &up);
        if (r == TOO_SMALL) {
            x--;
            continue;
        }
        if (r == TOO_LARGE) {
            x++;
            continue;
        }
        if (r != 0)
            return -1;
        q += (uint64_t)up;
        if (q == UINT64_C(100000000000000000)) {
            q = UINT64_C(10000000000000000);
            x++;
        }
        *d = q;
        *x10 = x;
        return 0;
    }
    return -1;
}

/* x < 10^8 as its eight decimal digits' values, the first in the lowest
 * byte: split into two 4-digit lanes of 32 bits, each into two 2-digit
 * lanes of 16 bits, each into two digits, every lane at once (the
 * divisions by 100 and 10 as products: floor(v 10486 / 2^20) = v / 100 for
 * v < 10^4, floor(v 103 / 2^10) = v / 10 for v < 100, and no lane's product
 * reaches the next lane). */
static inline uint64_t eight_digit_values(uint32_t x)
{
    uint64_t v = (uint64_t)(x / 10000u) | ((uint64_t)(x % 10000u) << 32);
    uint64_t h = ((v * 10486u) >> 20) & UINT64_C(0x0000007f0000007f);
    v = h | ((v - h * 100u) << 16);
    uint64_t t = ((v * 103u) >> 10) & UINT64_C(0x000f000f000f000f);
    return t | ((v - t * 10u) << 8);
}

/* The eight digits of w (eight_digit_values) as text at out. */
static inline void put_eight(char *out, uint64_t w)
{
    w += UINT64_C(0x3030303030303030);
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    memcpy(out, &w, 8);
#else
    for (int k = 0; k < 8; k++)
        out[k] = (char)(w >> (8 * k));
#endif
}

int m2c_sim_format_number(char *buf, double x)
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    int neg = (int)(bits >> 63);
    int be = (int)((bits >> 52) & 0x7ffu);
    uint64_t frac = bits & ((UINT64_C(1) << 52) - 1u);
    char *p = buf;
    if (be == 0x7ff) {
        if (frac != 0) {
            memcpy(p, "nan", 3);        /* Python writes no sign on a NaN */
            return 3;
        }
        if (neg)
            *p++ = '-';
        memcpy(p, "inf", 3);
        return (int)(p - buf) + 3;
    }
    if (be == 0 && frac == 0) {
        if (neg)
            *p++ = '-';
        *p++ = '0';
        return (int)(p - buf);
    }
    uint64_t d = 0;
    int x10 = 0;
    if (be == 0 || decimal17(fabs(x), frac | (UINT64_C(1) << 52), be - 1075, &x10, &d) != 0) {
        char tmp[M2C_SIM_NUMBER_MAX + 8];
        int n = snprintf(tmp, sizeof tmp, "%.17g", x);
        if (n < 0 || n > M2C_SIM_NUMBER_MAX)
            n = 0;
        memcpy(buf, tmp, (size_t)n);
        return n;
    }
    /* the 17 digits, then room for the fixed-size copies below */
    char dg[40];
    uint32_t hi = (uint32_t)(d / 100000000u);  /* 9 digits */
    uint64_t w1 = eight_digit_values(hi % 100000000u), w2 = eight_digit_values((uint32_t)(d % 100000000u));
    dg[0] = (char)('0' + hi / 100000000u);
    put_eight(dg + 1, w1);
    put_eight(dg + 9, w2);
    /* the last digit that is not a trailing zero: the highest byte of w1, w2
     * that is not 0 (d >= 10^16: the first digit is not) */
    int last = w2 != 0 ? 9 + (63 - __builtin_clzll(w2)) / 8 : w1 != 0 ? 1 + (63 - __builtin_clzll(w1)) / 8 : 0;
    if (x10 >= -4 && x10 < 17) {
        /* fixed notation, built with copies of fixed size (no loop per
         * digit) in t, then copied whole: buf holds M2C_SIM_NUMBER_MAX */
        char t[64];
        int n;
        t[0] = '-';
        char *q = t + neg;
        if (x10 >= 0) {
            memcpy(q, dg, 17);                          /* the whole part: digits 0..x10 */
            q[x10 + 1] = '.';
            memcpy(q + x10 + 2, dg + x10 + 1, 16);      /* the fraction: digits x10+1..last */
            n = last > x10 ? last + 2 : x10 + 1;
        } else {
            memcpy(q, "0.0000", 6);                     /* 0. and -x10-1 zeros */
            memcpy(q + 1 - x10, dg, 17);
            n = 1 - x10 + last + 1;
        }
        memcpy(buf, t, M2C_SIM_NUMBER_MAX);
        return neg + n;
    }
    /* the exponent form */
    if (neg)
        *p++ = '-';
    *p++ = dg[0];
    if (last > 0) {
        *p++ = '.';
        for (int k = 1; k <= last; k++)
            *p++ = dg[k];
    }
    *p++ = 'e';
    int ex = x10;
    if (ex < 0) {
        *p++ = '-';
        ex = -ex;
    } else {
        *p++ = '+';
    }
    if (ex >= 100) {
        *p++ = (char)('0' + ex / 100);
        ex %= 100;
    }
    *p++ = (char)('0' + ex / 10);
    *p++ = (char)('0' + ex % 10);
    return (int)(p - buf);
}
