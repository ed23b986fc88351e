/* Internal pieces of the root solver, shared by the files in src/.
 * Every function follows docs/roots.md operation for operation, so that the
 * C, Rust, Python and Modula-2 runtimes compute the same bits.  The hot
 * pieces are static inline (always inlined) so that the per-degree copies of
 * the general method (m2c_general.c) run with a constant degree: fully
 * unrolled loops with the coefficients in registers, the same operations. */
#ifndef M2C_INTERNAL_H
#define M2C_INTERNAL_H

#include <math.h>
#include "m2c_roots.h"
#include <stdint.h>
#include <string.h>

#define M2C_EPS 0x1p-52          /* spacing of doubles at 1 (2 u) */
#define M2C_SPLITTER 134217729.0 /* 2^27 + 1, Veltkamp splitting constant */
#define M2C_TINY 0x1p-1000       /* absolute floor of the touching and Bernstein bounds */
#define M2C_SIXTEENTH 0x1p-16    /* bisection step from a bracket end at 0 */
#define M2C_NEWTON_TOL 0x1p-30   /* an accepted Newton step this small (relative) has converged */
#define M2C_HALLEY_TOL 0x1p-8    /* an accepted Halley step this small: the polish finishes it */
#define M2C_HALLEY_MIN 0x1p-968  /* Halley's products below this lose precision to underflow */
#define M2C_HANDOFF_TOL 0x1p-14  /* ... or an accepted Newton step (Halley refused) this small */
#define M2C_POLISH_TOL 0x1p-22   /* a polishing Halley step this small ends the polish */
#define M2C_MAXIT 100            /* bracketed Newton step limit */
#define M2C_BERN_DEPTH 12        /* Bernstein subdivision depth limit */
#define M2C_QUAD_SPREAD 900      /* degree 2: one scale when coefficient exponents span at most this */
#define M2C_ONE_SCALE_SPAN 800   /* degree n >= 3: one scale when all roots lie in 2^(+-800/n) */
#define M2C_BAND_SPAN 800        /* otherwise bands of magnitude 2^(800/n) */

#define M2C_INLINE static inline __attribute__((always_inline))
#define M2C_UNROLL _Pragma("GCC unroll 17")

/* 2^k for -1022 <= k <= 1023 (exact). */
M2C_INLINE double m2c_pow2(int k)
{
    uint64_t u = (uint64_t)(k + 1023) << 52;
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

/* Error-free product a*b = *p + *e (Dekker, no FMA). */
M2C_INLINE void m2c_two_prod(double a, double b, double *p, double *e)
{
    double q = a * b;
    double t = M2C_SPLITTER * a;
    double ah = t - (t - a);
    double al = a - ah;
    t = M2C_SPLITTER * b;
    double bh = t - (t - b);
    double bl = b - bh;
    *p = q;
    *e = ((ah * bh - q) + ah * bl + al * bh) + al * bl;
}

/* p(x) by compensated Horner; a[0..n] ascending, n >= 1. */
double m2c_comp_horner(const double *a, int n, double x);

/* Sign of p(x): -1, 0 (zero within the compensated bound), +1. */
int m2c_sign_top(const double *a, int n, double x);

/* Sign of the plain Horner value of p(x): -1, 0 (exactly zero), +1. */
int m2c_sign_plain(const double *a, int n, double x);

/* Bisection point of [xa, xb]; half = (xb - xa)/2. */
double m2c_midpoint(double xa, double xb, double half);

/* Root of p in (lo, hi), p(lo) of sign slo (nonzero), p(hi) of the other,
 * starting at x0 (lo < x0 < hi); an accepted Newton step of at most
 * tol*|x| ends it. */
M2C_INLINE double m2c_newton_impl(const double *a, int n, double lo, double hi, int slo,
                                  double x0, double tolnewton)
{
    double xa = lo, xb = hi;
    double x = x0;
    double dx = xb - xa;
    double dxold = dx;
    int neg = slo < 0;
    double tol = M2C_EPS;
    for (int it = 0; it < M2C_MAXIT; it++) {
        double v = a[n];
        double d = 0.0;
        M2C_UNROLL
        for (int i = n - 1; i >= 0; i--) {
            d = d * x + v;
            v = v * x + a[i];
        }
        if (v == 0.0)
            break;
        if ((v < 0.0) == neg)
            xa = x;
        else
            xb = x;
        double xn;
        if (d != 0.0 && fabs(4.0 * v) < fabs(dxold * d)) {
            double step = v / d;
            xn = x - step;
            if (xa < xn && xn < xb) {
                dxold = dx;
                dx = step;
                tol = tolnewton;
            } else {
                dxold = dx;
                dx = 0.5 * (xb - xa);
                xn = m2c_midpoint(xa, xb, dx);
                tol = M2C_EPS;
            }
        } else {
            dxold = dx;
            dx = 0.5 * (xb - xa);
            xn = m2c_midpoint(xa, xb, dx);
            tol = M2C_EPS;
        }
        if (!(xa < xn && xn < xb))
            break;
        if (fabs(dx) <= tol * fabs(xn)) {
            x = xn;
            break;
        }
        x = xn;
    }
    return x;
}

/* The step from p(x) = v, p'(x) = d (nonzero), p''(x)/2 = h: Halley's
 * v d / (d^2 - v h) when d^2 - v h > d^2 / 2 (at most twice the Newton step,
 * same direction; false for an overflow or NaN) and both v d and d^2 are at
 * least 2^-968 (no precision lost to underflow: in a band of tiny values
 * they can underflow), else Newton's v / d.  1 when Halley's. */
M2C_INLINE int m2c_halley_step(double v, double d, double h, double *step)
{
    double dd = d * d;
    double vd = v * d;
    double den = dd - v * h;
    if (den > 0.5 * dd && fabs(vd) >= M2C_HALLEY_MIN && dd >= M2C_HALLEY_MIN) {
        *step = vd / den;
        return 1;
    }
    *step = v / d;
    return 0;
}

/* c[0] + c[1] x + ... + c[m] x^m by Estrin's scheme (docs/roots.md step
 * 7.3): pairs q_i = q_2i + q_2i+1 * p with p = x, then x^2, x^4, ... until
 * one value is left; an odd last entry is carried up unchanged.  About
 * log2(m + 1) multiply-adds deep where Horner is m (m <= 16). */
M2C_INLINE double m2c_estrin(const double *c, int m, double x)
{
    double q[M2C_MAX_DEGREE + 1];
    int k = m + 1;
    M2C_UNROLL
    for (int i = 0; i < k; i++)
        q[i] = c[i];
    double p = x;
    M2C_UNROLL
    for (int level = 0; level < 5 && k > 1; level++) {
        int k2 = (k + 1) / 2;
        M2C_UNROLL
        for (int i = 0; i < k2; i++)
            q[i] = 2 * i + 1 < k ? q[2 * i] + q[2 * i + 1] * p : q[2 * i];
        k = k2;
        p = p * p;
    }
    return q[0];
}

/* Bernstein's single simple root in (lo, hi): the bracketed method of
 * m2c_newton_impl with Halley's step (cubic convergence) where it is safe:
 * p, p' and p''/2 by Estrin's scheme (shorter chains than Horner's: this
 * loop is latency-bound, and its accuracy only needs to bring x within
 * 2^-8; the polish evaluates by Horner with its error bound),
 * m2c_halley_step chooses the step.  An accepted Halley step of at most tolhalley |x| ends it, a Newton
 * step of at most 2^-14 |x|. */
M2C_INLINE double m2c_halley_impl(const double *a, int n, double lo, double hi, int slo,
                                  double x0, double tolhalley)
{
    double xa = lo, xb = hi;
    double x = x0;
    double dx = xb - xa;
    double dxold = dx;
    int neg = slo < 0;
    double tol = M2C_EPS;
    /* the coefficients of p' and p''/2 (docs/roots.md step 7.3) */
    double da[M2C_MAX_DEGREE], ha[M2C_MAX_DEGREE];
    M2C_UNROLL
    for (int i = 0; i < n; i++)
        da[i] = (double)(i + 1) * a[i + 1];
    M2C_UNROLL
    for (int i = 0; i < n - 1; i++)
        ha[i] = (double)((i + 1) * (i + 2) / 2) * a[i + 2];
    for (int it = 0; it < M2C_MAXIT; it++) {
        double v = m2c_estrin(a, n, x);
        double d = m2c_estrin(da, n - 1, x);
        double h = m2c_estrin(ha, n - 2, x);
        if (v == 0.0)
            break;
        if ((v < 0.0) == neg)
            xa = x;
        else
            xb = x;
        double xn;
        if (d != 0.0 && fabs(4.0 * v) < fabs(dxold * d)) {
            double step;
            int halley = m2c_halley_step(v, d, h, &step);
            xn = x - step;
            if (xa < xn && xn < xb) {
                dxold = dx;
                dx = step;
                tol = halley ? tolhalley : M2C_HANDOFF_TOL;
            } else {
                dxold = dx;
                dx = 0.5 * (xb - xa);
                xn = m2c_midpoint(xa, xb, dx);
                tol = M2C_EPS;
            }
        } else {
            dxold = dx;
            dx = 0.5 * (xb - xa);
            xn = m2c_midpoint(xa, xb, dx);
            tol = M2C_EPS;
        }
        if (!(xa < xn && xn < xb))
            break;
        if (fabs(dx) <= tol * fabs(xn)) {
            x = xn;
            break;
        }
        x = xn;
    }
    return x;
}

/* A last Newton step inside (xa, xb]: plain when Horner is accurate enough
 * at x, else up to two steps with compensated Horner. */
M2C_INLINE double m2c_polish_impl(const double *a, int n, double x, double xa, double xb)
{
    for (int k = 0; k < 2; k++) {
        double ax = fabs(x);
        double v = a[n];
        double d = 0.0;
        double mu = 0.5 * fabs(v);
        M2C_UNROLL
        for (int i = n - 1; i >= 0; i--) {
            d = d * x + v;
            v = v * x + a[i];
            mu = mu * ax + fabs(v);
        }
        if (d == 0.0)
            return x;
        /* running error bound of Horner (Higham, Alg. 5.1): |v - p(x)| <= eps (mu - |v|/2) */
        if (mu <= 2.0 * fabs(x * d)) {
            /* Horner is accurate enough here: one plain Newton step */
            double xn = x - v / d;
            if (xa < xn && xn <= xb)
                return xn;
            return x;
        }
        double vc = m2c_comp_horner(a, n, x);
        if (vc == 0.0)
            return x;
        double xn = x - vc / d;
        if (!(xa < xn && xn <= xb) || xn == x)
            return x;
        x = xn;
    }
    return x;
}

/* p(x) by compensated Horner (Graillat, Langlois, Louvet): as accurate as
 * Horner in twice the precision; n >= 1.  Inlined in the polish,
 * m2c_comp_horner out of line elsewhere. */
M2C_INLINE double m2c_comp_horner_impl(const double *a, int n, double x)
{
    double s = a[n];
    double c = 0.0;
    M2C_UNROLL
    for (int i = n - 1; i >= 0; i--) {
        double p, pe;
        m2c_two_prod(s, x, &p, &pe);
        double ai = a[i];
        s = p + ai;
        double z = s - p;
        double se = (p - (s - z)) + (ai - z);
        c = c * x + (pe + se);
    }
    return s + c;
}

/* The polish after Bernstein's Halley iteration (docs/roots.md step 7.3):
 * the step of m2c_halley_step from p(x) (plain Horner where its running
 * error bound allows, else compensated), p'(x) and p''(x)/2, kept only
 * inside (xa, xb]; a Halley step of at most 2^-22 |x| (a Newton step: 2^-30)
 * ends it, else another round, at most three. */
M2C_INLINE double m2c_polish_halley_impl(const double *a, int n, double x, double xa, double xb)
{
    for (int k = 0; k < 3; k++) {
        double ax = fabs(x);
        double v = a[n];
        double d = 0.0;
        double h = 0.0;
        double mu = 0.5 * fabs(v);
        M2C_UNROLL
        for (int i = n - 1; i >= 0; i--) {
            h = h * x + d;
            d = d * x + v;
            v = v * x + a[i];
            mu = mu * ax + fabs(v);
        }
        if (d == 0.0)
            return x;
        if (mu > 2.0 * fabs(x * d)) /* plain Horner not accurate enough: compensated */
            v = m2c_comp_horner_impl(a, n, x);
        double step;
        /* Newton where Halley is refused converges only quadratically */
        double tol = m2c_halley_step(v, d, h, &step) ? M2C_POLISH_TOL : M2C_NEWTON_TOL;
        double xn = x - step;
        if (!(xa < xn && xn <= xb))
            return x;
        if (fabs(step) <= tol * fabs(xn))
            return xn;
        x = xn;
    }
    return x;
}

/* Real roots of a x^2 + b x + c (a != 0), ascending, into r; returns count.
 * The plain discriminant when it cannot cancel (4ac <= b*b/2), none when it
 * is clearly negative, error-free products only in between. */
M2C_INLINE int m2c_quadratic(double a, double b, double c, double r[2])
{
    double p = b * b;
    double q = (4.0 * a) * c;
    double disc = p - q;
    if (q <= 0.5 * p) {
        if (disc == 0.0) { /* b == 0 and ac == 0 */
            r[0] = -b / (2.0 * a);
            return 1;
        }
    } else if (disc < -M2C_EPS * (p + q)) {
        return 0;
    } else {
        double pe, qe;
        m2c_two_prod(b, b, &p, &pe);
        double a4 = 4.0 * a;
        m2c_two_prod(a4, c, &q, &qe);
        disc = (p - q) + (pe - qe);
        double bound = M2C_EPS * M2C_EPS * (p + fabs(q));
        if (disc < -bound)
            return 0;
        if (disc <= bound) {
            r[0] = -b / (2.0 * a);
            return 1;
        }
    }
    m2c_x_quadratic_two(a, b, c, disc, r);
    return 2;
}

/* The first root of a x^2 + b x + c (a != 0) in (lo, hi]: 1 and *t, or 0. */
M2C_INLINE int m2c_quadratic_in(double a, double b, double c, double lo, double hi, double *t)
{
    double r[2];
    int nr = m2c_quadratic(a, b, c, r);
    if (nr > 0 && lo < r[0] && r[0] <= hi) {
        *t = r[0];
        return 1;
    }
    if (nr > 1 && lo < r[1] && r[1] <= hi) {
        *t = r[1];
        return 1;
    }
    return 0;
}

/* Binary exponent e of a finite nonzero x = f 2^e, 0.5 <= |f| < 1 (frexp). */
M2C_INLINE int m2c_frexp_exp(double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    int field = (int)((u >> 52) & 0x7ff);
    if (field == 0) { /* subnormal: scale into the normal range first */
        x = x * m2c_pow2(64);
        memcpy(&u, &x, sizeof u);
        return (int)((u >> 52) & 0x7ff) - 1022 - 64;
    }
    return field - 1022;
}

/* a[0..n] = c[0..n] times the power of two that puts m = max |c_i| in
 * [1, 2) (exact while the products stay normal). */
M2C_INLINE void m2c_scale_pow2(const double *c, int n, double m, double *a)
{
    int k = 1 - m2c_frexp_exp(m);
    if (k > 1000) {
        double f = m2c_pow2(600);
        M2C_UNROLL
        for (int i = 0; i <= n; i++)
            a[i] = c[i] * f;
        k -= 600;
    } else {
        M2C_UNROLL
        for (int i = 0; i <= n; i++)
            a[i] = c[i];
    }
    /* 2^-1023 is subnormal: 2^-1022 / 2 (exact) */
    double f = k < -1022 ? m2c_pow2(-1022) * 0.5 : m2c_pow2(k);
    M2C_UNROLL
    for (int i = 0; i <= n; i++)
        a[i] = a[i] * f;
}

/* m2c_scale_pow2; returns the degree left after dropping top coefficients
 * that underflowed. */
M2C_INLINE int m2c_scale_max(const double *c, int n, double m, double *a)
{
    m2c_scale_pow2(c, n, m, a);
    while (n >= 0 && a[n] == 0.0) /* underflowed to zero in the scaling */
        n--;
    return n;
}

/* m2c_scale_max with the maximum computed here. */
M2C_INLINE int m2c_scale_impl(const double *c, int n, double *a)
{
    double m = 0.0;
    M2C_UNROLL
    for (int i = 0; i <= n; i++) {
        double v = fabs(c[i]);
        if (v > m)
            m = v;
    }
    return m2c_scale_max(c, n, m, a);
}

/* m2c_scale_impl, not inlined (the GSL baseline). */
int m2c_scale(const double *c, int n, double *a);

/* Degree n >= 2 of c (c[n] != 0; a NaN or infinity answers none), lo < hi finite: one scale
 * or bands (docs/roots.md steps 3-7); 1 and *t when found. */
int m2c_solve(const double *c, int n, double lo, double hi, double *t);

/* Degree 3 <= n <= 8 from the entry: c[n] != 0, lo < hi and hi - lo finite
 * (a NaN or infinite coefficient answers none); 1 and *t (never -0.0) when
 * found. */
int m2c_solve_entry(const double *c, int n, double lo, double hi, double *t);

/* Coefficients a[0..n] already scaled (max |a_i| in [1, 2), a[n] != 0,
 * n >= 1): the first root in (lo, hi] by the closed forms or the general
 * method; 1 and *t when found. */
int m2c_scaled_any(const double *a, int n, double lo, double hi, double *t);

/* Exponents (ue, le): every root of c (degree n, c[n] != 0, j < n the lowest
 * index with c[j] != 0) has |t| < 2^ue, every nonzero root |t| > 2^le. */
void m2c_root_exponents(const double *c, int n, int j, int *ue, int *le);

/* Roots too spread for one scale: bands of magnitude, each with its own
 * power-of-two scale of t (docs/roots.md step 7); 1 and *t when found. */
int m2c_banded(const double *c, int n, int j, int ue, int le, double lo, double hi, double *t);

/* The contract's input rules, shared by the solver and the GSL baseline:
 * -1 for a bad degree or NULL pointer, 0 when the answer is "none" (NaN/inf,
 * lo >= hi, all-zero or constant polynomial), else 1 with *n the degree left
 * after dropping exactly-zero top coefficients. */
static inline int m2c_check_input(const double *c, int degree, double lo, double hi, const double *t, int *n)
{
    if (c == 0 || t == 0 || degree < 0 || degree > M2C_MAX_DEGREE)
        return -1;
    if (!(isfinite(lo) && isfinite(hi)) || !(lo < hi))
        return 0;
    for (int i = 0; i <= degree; i++)
        if (!isfinite(c[i]))
            return 0;
    int m = degree;
    while (m >= 0 && c[m] == 0.0)
        m--;
    if (m <= 0)
        return 0;
    *n = m;
    return 1;
}

#endif
