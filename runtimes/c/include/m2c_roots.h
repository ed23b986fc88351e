/* max2code C runtime: smallest real root of a polynomial in (lo, hi].
 * Contract and algorithm: docs/roots.md.  Times are in the caller's units. */
#ifndef M2C_ROOTS_H
#define M2C_ROOTS_H

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Largest supported degree. */
#define M2C_MAX_DEGREE 16

/* Smallest real root t of c[0] + c[1] t + ... + c[degree] t^degree with
 * lo < t <= hi.  Returns 1 and stores *t when found, 0 when there is none
 * (including NaN/inf input, lo >= hi, all-zero or constant polynomials),
 * -1 when degree is outside 0..M2C_MAX_DEGREE or c/t is NULL. */
int m2c_smallest_root(const double *c, int degree, double lo, double hi, double *t);

/* The same contract answered by GSL's companion-matrix solver
 * (gsl_poly_complex_solve), the paper's baseline: a complex root counts as
 * real when |Im z| <= 1e-7 * max(1, |Re z|).  Not thread-safe (it caches one
 * GSL workspace per degree). */
int m2c_smallest_root_gsl(const double *c, int degree, double lo, double hi, double *t);

#ifndef __cplusplus /* C++ callers call the library (hex floats, memcpy on doubles) */
/* ---- The entry's first steps, shared by the library and (GNU C, with
 * optimisation) inlined into callers.  Not part of the API: the m2c_x_
 * names may change with any version. ---- */

/* GNU C with optimisation: the helpers below are only inlined (gnu_inline),
 * never emitted, so that the inline m2c_smallest_root may call them. */
#if defined(__GNUC__) && defined(__OPTIMIZE__) && !defined(M2C_NO_INLINE_ENTRY)
#define M2C_X_INLINE extern __inline__ __attribute__((gnu_inline, always_inline))
#else
#define M2C_X_INLINE static inline
#endif

/* Degrees 3 to 8 after the entry's checks; the rest of the entry; the
 * degree-2 fast path's error-free discriminant (m2c_quadratic_in). */
int m2c_solve_entry(const double *c, int n, double lo, double hi, double *t);
int m2c_x_general(const double *c, int degree, double lo, double hi, double *t);
int m2c_x_quadratic_exact(double a, double b, double c, double lo, double hi, double *t);

/* The degree-2 fast path's admission (docs/roots.md step 1): c2 != 0, each
 * coefficient zero or |c_i| >= 2^-200, |c0| + |c1| + |c2| < 2^200 (false
 * for NaN and infinities), and w = hi - lo positive and finite.  The lower
 * bounds read the exponent fields: (u << 1) - 1 wraps a zero (either sign)
 * to the top, so one unsigned comparison accepts zero and |v| >= 2^-200;
 * for c2, (u << 1) > k rejects zero as well.  w > 0 and finite is one
 * unsigned comparison of its bits.  The tests are branches taken in turn
 * (&&), the sum first, as Rust's admit2 compiles: the fast path's calls
 * pass them all, so each is predicted, and GCC needs fewer instructions
 * than for all five combined with & (m2c_bench's degree-2 pass: 94.6 ->
 * 91.2 per solve). */
M2C_X_INLINE int m2c_x_admit2(double c0, double c1, double c2, double w)
{
    uint64_t u0, u1, u2, uw;
    memcpy(&u0, &c0, sizeof u0);
    memcpy(&u1, &c1, sizeof u1);
    memcpy(&u2, &c2, sizeof u2);
    memcpy(&uw, &w, sizeof uw);
    const uint64_t k = ((uint64_t)823 << 53) - 1; /* exponent field 823: 2^-200 */
    return fabs(c0) + fabs(c1) + fabs(c2) < 0x1p200 &&
           uw - 1 < 0x7fefffffffffffffu && /* 0 < w <= DBL_MAX */
           (u2 << 1) > k && (u0 << 1) - 1 >= k && (u1 << 1) - 1 >= k;
}

/* The roots of a x^2 + b x + c from d > 0, the discriminant computed so
 * that it is accurate (docs/roots.md step 6), ascending into r. */
M2C_X_INLINE void m2c_x_quadratic_two(double a, double b, double c, double d, double r[2])
{
    double s = sqrt(d);
    if (b < 0.0)
        s = -s;
    double qq = -0.5 * (b + s);
    double r1 = qq / a;
    double r2 = c / qq;
    if (r1 <= r2) {
        r[0] = r1;
        r[1] = r2;
    } else {
        r[0] = r2;
        r[1] = r1;
    }
}

/* The degree-2 fast path (step 1; c2 != 0, moderate coefficients, lo < hi
 * with hi - lo finite): the first root in (lo, hi] as m2c_quadratic_in
 * finds it (step 6), 1 and *t (never -0.0) or 0.  With lo >= 0 and
 * c0 c2 < 0 only the positive root is computed, which is sure by the signs
 * alone (docs/roots.md step 1, "lo >= 0"; the entry has already answered
 * none when c0, c1, c2 have no sign change). */
M2C_X_INLINE int m2c_x_quadratic_fast(double c0, double c1, double c2, double lo, double hi, double *t)
{
    const double a = c2, b = c1, c = c0;
    int from0 = lo >= 0.0;
    double p = b * b;
    double q = (4.0 * a) * c;
    double d = p - q;
    double x;
    if (q <= 0.5 * p) {
        if (d == 0.0) { /* b == 0 and ac == 0: the double root */
            x = -b / (2.0 * a);
            goto one;
        }
    } else if (d < -0x1p-52 * (p + q)) {
        return 0;
    } else {
        return m2c_x_quadratic_exact(a, b, c, lo, hi, t); /* cancellation possible */
    }
    if (from0 & (q < 0.0)) {
        /* a c < 0: one root of each sign, and only the positive one can lie
         * in (lo, hi]; it is qq/a when b and a differ in sign, else c/qq */
        double s = sqrt(d);
        if (b < 0.0)
            s = -s;
        double qq = -0.5 * (b + s);
        x = (b < 0.0) != (a < 0.0) ? qq / a : c / qq;
        goto one;
    } else {
        double r[2];
        m2c_x_quadratic_two(a, b, c, d, r);
        if (lo < r[0] && r[0] <= hi) {
            *t = r[0] + 0.0;
            return 1;
        }
        x = r[1];
    }
one:
    if (!(lo < x && x <= hi))
        return 0;
    *t = x + 0.0;
    return 1;
}

/* GCC 12 (-O3 with LTO) warns that c[1..4] may be uninitialised when a
 * caller fills c up to a degree it computes (m2c_sim_predict.c's
 * bounds_meet), and a diagnostic pragma does not reach LTO's inlining: the
 * empty asm hides where c points (no instruction; the entry reads only
 * c[0..degree], which the contract requires set). */
#if defined(__GNUC__)
#define M2C_X_OPAQUE(p) __asm__("" : "+r"(p))
#else
#define M2C_X_OPAQUE(p) ((void)0)
#endif

/* Whether the sign bits of x and y differ.  In the no-root tests this
 * stands for (x < 0) != (y < 0): the two differ only when x or y is zero or
 * NaN, and then the test answers 0 either way. */
M2C_X_INLINE int m2c_x_signs_differ(double x, double y)
{
    uint64_t u, v;
    memcpy(&u, &x, 8);
    memcpy(&v, &y, 8);
    return (int64_t)(u ^ v) < 0;
}

/* b with its sign bit flipped when s's is set: flip(b, s) > m for m > 0 is
 * b > m when s >= +0 and b < -m when s <= -0 (0 for NaN either way).  In
 * the no-root tests, s = t0: "all b_i > m or all b_i < -m" (t0 among them)
 * is "all flip(b_i, t0) > m" (t0 = +-0 fails both). */
M2C_X_INLINE double m2c_x_flip(double b, double s)
{
    uint64_t u, v;
    memcpy(&u, &b, 8);
    memcpy(&v, &s, 8);
    u ^= v & 0x8000000000000000u;
    memcpy(&b, &u, 8);
    return b;
}

/* Degrees 3 and 4 with lo >= 0 and hi >= 2^-250 (docs/roots.md step 1,
 * "lo >= 0" (c)): 1 when p has no root in [0, hi], shown by its Bernstein
 * coefficients there (weighted sums of t_i = c_i hi^i) all beyond
 * m = 2^-46 (|t_0| + ... + |t_n|) + 2^-900 with one sign: m is 16 times
 * their rounding error, so the exact ones share that sign (hi >= 2^-250
 * keeps hi^n normal: an underflowed power would lose c_i hi^n whole).
 * Steps 2-8 answer none for each such p; this answers it sooner (half the
 * benchmark's cubics: 36 -> 15 cycles).  0 when not shown (also for a NaN,
 * an infinity or an overflow: a comparison with NaN or with an infinite m
 * is false).  p(0) and p(hi) of opposite signs, the usual case when there
 * is a root, are tested first, so that those calls pay little. */
M2C_X_INLINE int m2c_x_no_root3(const double *c, double hi)
{
    M2C_X_OPAQUE(c);
    double h2 = hi * hi;
    double t0 = c[0], t1 = c[1] * hi, t2 = c[2] * h2, t3 = c[3] * (h2 * hi);
    double b3 = (t0 + t1) + (t2 + t3);
    if (m2c_x_signs_differ(t0, b3))
        return 0;
    double m = 0x1p-46 * ((fabs(t0) + fabs(t1)) + (fabs(t2) + fabs(t3))) + 0x1p-900;
    double b1 = t0 + t1 * (1.0 / 3.0);
    double b2 = (t0 + t1 * (2.0 / 3.0)) + t2 * (1.0 / 3.0);
    return (m2c_x_flip(t0, t0) > m) & (m2c_x_flip(b1, t0) > m) & (m2c_x_flip(b2, t0) > m) & (m2c_x_flip(b3, t0) > m);
}

M2C_X_INLINE int m2c_x_no_root4(const double *c, double hi)
{
    M2C_X_OPAQUE(c);
    double h2 = hi * hi;
    double t0 = c[0], t1 = c[1] * hi, t2 = c[2] * h2, t3 = c[3] * (h2 * hi), t4 = c[4] * (h2 * h2);
    double b4 = ((t0 + t1) + (t2 + t3)) + t4;
    if (m2c_x_signs_differ(t0, b4))
        return 0;
    double m = 0x1p-46 * (((fabs(t0) + fabs(t1)) + (fabs(t2) + fabs(t3))) + fabs(t4)) + 0x1p-900;
    double b1 = t0 + t1 * 0.25;
    double b2 = (t0 + t1 * 0.5) + t2 * (1.0 / 6.0);
    double b3 = (t0 + t1 * 0.75) + (t2 * 0.5 + t3 * 0.25);
    return (m2c_x_flip(t0, t0) > m) & (m2c_x_flip(b1, t0) > m) & (m2c_x_flip(b2, t0) > m) &
           (m2c_x_flip(b3, t0) > m) & (m2c_x_flip(b4, t0) > m);
}

/* m2c_smallest_root up to its first call: the degree-2 fast path, degrees
 * 3 and 4 with lo >= 0 and no root in [0, hi] answered at once, degrees 3
 * to 8 with nothing to strip straight to their copy of the general method,
 * the rest to m2c_x_general. */
M2C_X_INLINE int m2c_x_entry(const double *c, int degree, double lo, double hi, double *t)
{
    if (degree == 2 && c != 0 && t != 0) {
        double c0 = c[0], c1 = c[1], c2 = c[2];
        /* lo < hi, both finite: hi - lo is positive and finite (an overflow
         * only sends the call to the general path) */
        double w = hi - lo;
        if ((lo >= 0.0) & (c0 * c1 > 0.0) & (c1 * c2 > 0.0))
            return 0; /* no sign change, at any magnitude (docs/roots.md step 1) */
        if (m2c_x_admit2(c0, c1, c2, w))
            return m2c_x_quadratic_fast(c0, c1, c2, lo, hi, t);
    }
    if (degree == 3 && c != 0 && t != 0 && lo >= 0.0 && hi >= 0x1p-250 && m2c_x_no_root3(c, hi))
        return 0;
    if (degree == 4 && c != 0 && t != 0 && lo >= 0.0 && hi >= 0x1p-250 && m2c_x_no_root4(c, hi))
        return 0;
    if (degree >= 3 && degree <= 8 && c != 0 && t != 0 && c[degree] != 0.0) {
        double w = hi - lo;
        if ((w > 0.0) & (w <= DBL_MAX))
            return m2c_solve_entry(c, degree, lo, hi, t);
    }
    return m2c_x_general(c, degree, lo, hi, t);
}

#if defined(__GNUC__) && defined(__OPTIMIZE__) && !defined(M2C_NO_INLINE_ENTRY)
/* GNU C: this definition is only inlined (gnu_inline); the library's
 * m2c_smallest_root is the same function out of line. */
extern __inline__ __attribute__((gnu_inline, always_inline)) int
m2c_smallest_root(const double *c, int degree, double lo, double hi, double *t)
{
    return m2c_x_entry(c, degree, lo, hi, t);
}
#endif
#endif /* __cplusplus */

#ifdef __cplusplus
}
#endif

#endif
