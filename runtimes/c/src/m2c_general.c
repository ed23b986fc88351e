/* Degree >= 1 after stripping: exact scaling, degrees 1 and 2, and the
 * general method for degree >= 3 (docs/roots.md step 6): clip to the root
 * bound, Bernstein coefficients on the interval, subdivision left to right
 * (no root / one simple root / split), and the derivative method where the
 * Bernstein signs are unsure.  One copy per degree (a constant n, unrolled);
 * t in the caller's time unit. */
#include <math.h>
#include "m2c_internal.h"
#include "m2c_roots.h"

/* i! for 0 <= i <= 16 (exact in a double). */
static const double FACT[M2C_MAX_DEGREE + 1] = {
    1.0, 1.0, 2.0, 6.0, 24.0, 120.0, 720.0, 5040.0, 40320.0, 362880.0,
    3628800.0, 39916800.0, 479001600.0, 6227020800.0, 87178291200.0,
    1307674368000.0, 20922789888000.0};

/* All roots of p (degree n) in the open (lo, hi), ascending, given the m
 * ascending roots crit of p' there; returns the count written to out. */
static int roots_between(const double *a, int n, const double *crit, int m,
                         double lo, double hi, double *out)
{
    int k = 0;
    double xl = lo;
    int sl = m2c_sign_plain(a, n, lo);
    for (int i = 0; i <= m; i++) {
        double xr = i < m ? crit[i] : hi;
        int sr = m2c_sign_plain(a, n, xr);
        if (sl == 0 && i > 0)
            out[k++] = xl;
        else if (sl * sr < 0)
            out[k++] = m2c_newton_impl(a, n, xl, xr, sl, 0.5 * (xl + xr), M2C_NEWTON_TOL);
        xl = xr;
        sl = sr;
    }
    return k;
}

/* floor(d / 2) for any int d (C's / truncates). */
static int floor_half(int d)
{
    return d >= 0 ? d / 2 : -((1 - d) / 2);
}

/* m2c_quadratic in x = 2^s u (docs/roots.md step 7.4): s balances a 2^(2s)
 * against c (or b 2^s when c = 0), a common power of two puts the largest
 * coefficient in [1, 2), the roots u come back as ldexp(u, s).  The same
 * bits as m2c_quadratic where its products stay normal; where they
 * underflow (roots far from 1 with tiny coefficients) the roots are kept. */
static int quadratic_scaled(double a, double b, double c, double r[2])
{
    int ea = m2c_frexp_exp(a);
    int eb = b != 0.0 ? m2c_frexp_exp(b) : 0, ec = c != 0.0 ? m2c_frexp_exp(c) : 0;
    int s = c != 0.0 ? floor_half(ec - ea) : b != 0.0 ? eb - ea : 0;
    int m = ea + 2 * s;
    if (b != 0.0 && eb + s > m)
        m = eb + s;
    if (c != 0.0 && ec > m)
        m = ec;
    int k = 1 - m;
    int nr = m2c_quadratic(ldexp(a, 2 * s + k), ldexp(b, s + k), ldexp(c, k), r);
    for (int i = 0; i < nr; i++)
        r[i] = ldexp(r[i], s);
    return nr;
}

/* The derivative method on [lo, hi] (answers in (lo, hi]): roots of the
 * derivatives bottom up, then the first root of p with careful signs. */
static int by_derivatives(const double *a, int n, double lo, double hi, double *t)
{
    double ders[M2C_MAX_DEGREE - 1][M2C_MAX_DEGREE + 1];
    if (n < 3 || n > M2C_MAX_DEGREE) /* never: callers pass 3 <= n <= 16 */
        return 0;
    for (int i = 0; i <= n; i++)
        ders[0][i] = a[i];
    for (int k = 1; k < n - 1; k++)
        for (int i = 0; i <= n - k; i++)
            ders[k][i] = ders[k - 1][i + 1] * (double)(i + 1);
    double crit[M2C_MAX_DEGREE], next[M2C_MAX_DEGREE], qr[2];
    const double *d2 = ders[n - 2];
    int nq = quadratic_scaled(d2[2], d2[1], d2[0], qr);
    int m = 0;
    for (int i = 0; i < nq; i++)
        if (lo < qr[i] && qr[i] < hi)
            crit[m++] = qr[i];
    for (int k = n - 3; k > 0; k--) {
        int m2 = roots_between(ders[k], n - k, crit, m, lo, hi, next);
        for (int i = 0; i < m2; i++)
            crit[i] = next[i];
        m = m2;
    }
    double xl = lo;
    int sl = m2c_sign_top(a, n, lo);
    for (int i = 0; i <= m; i++) {
        if (sl == 0 && i > 0) {
            *t = xl;
            return 1;
        }
        double xr = i < m ? crit[i] : hi;
        int sr = m2c_sign_top(a, n, xr);
        if (sl * sr < 0) {
            double x = m2c_newton_impl(a, n, xl, xr, sl, 0.5 * (xl + xr), M2C_NEWTON_TOL);
            x = m2c_polish_impl(a, n, x, xl, xr); /* the monotone piece bounds the polish */
            if (!(x > xl))
                x = xr;
            if (x > xr)
                x = xr;
            *t = x;
            return 1;
        }
        xl = xr;
        sl = sr;
    }
    if (sl == 0) {
        *t = hi;
        return 1;
    }
    return 0;
}

/* Sign variations of b[0..n], or -1 when one of them is within e of zero;
 * *mx receives max |b_i|. */
M2C_INLINE int variations(const double *b, int n, double e, double *mx)
{
    double m = fabs(b[0]);
    int unsure = m <= e;
    int v = 0;
    M2C_UNROLL
    for (int i = 1; i <= n; i++) {
        double ab = fabs(b[i]);
        m = ab > m ? ab : m;
        unsure |= ab <= e;
        v += (b[i] < 0.0) != (b[i - 1] < 0.0);
    }
    *mx = m;
    return unsure ? -1 : v;
}

/* GCC -O3 (with some -march) reports b[] below as maybe uninitialised: b[0..n]
 * are all set in step 2 and the crossing scan stops before b[n + 1] (variations
 * counted exactly one sign change in b[0..n]); the warning is a false positive. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
M2C_INLINE int general_impl(const double *a, int n, double lo, double hi, double *t)
{
    /* 1. clip to the root bound (r >= 2: nothing to clip in [-2, 2], and no
     * division on the way) */
    if (!(-2.0 <= lo && hi <= 2.0)) {
        double mx = 0.0;
        M2C_UNROLL
        for (int i = 0; i < n; i++) {
            double v = fabs(a[i]);
            if (v > mx)
                mx = v;
        }
        mx = mx / fabs(a[n]); /* = max |a_i|/|a_n| (rounding is monotone) */
        double r = 2.0 * (1.0 + mx);
        double cap = m2c_pow2(900 / n);
        if (r > cap)
            r = cap;
        if (lo < -r)
            lo = -r;
        if (hi > r)
            hi = r;
        if (!(lo < hi))
            return 0;
    }
    /* 2. n! times the Bernstein coefficients of p on [lo, hi], error bound e */
    double b[M2C_MAX_DEGREE + 1];
    M2C_UNROLL
    for (int i = 0; i <= n; i++)
        b[i] = a[i];
    if (lo != 0.0) {
        M2C_UNROLL
        for (int i = 0; i < n; i++) {
            M2C_UNROLL
            for (int j = n - 1; j >= i; j--)
                b[j] = b[j] + lo * b[j + 1];
        }
    }
    double w = hi - lo;
    double f = 1.0;
    M2C_UNROLL
    for (int j = 0; j <= n; j++) {
        b[j] = b[j] * f * (FACT[j] * FACT[n - j]);
        f = f * w;
    }
    M2C_UNROLL
    for (int k = 1; k <= n; k++) {
        M2C_UNROLL
        for (int j = n; j >= k; j--)
            b[j] = b[j] + b[j - 1];
    }
    double y = fabs(lo) + w;
    double pt = fabs(a[n]);
    M2C_UNROLL
    for (int i = n - 1; i >= 0; i--)
        pt = pt * y + fabs(a[i]);
    double e = 8.0 * (n + 1) * M2C_EPS * pt * FACT[n] + M2C_TINY;
    /* 3. subdivision, left to right */
    double stb[M2C_BERN_DEPTH][M2C_MAX_DEGREE + 1];
    double ste[M2C_BERN_DEPTH], stl[M2C_BERN_DEPTH], stu[M2C_BERN_DEPTH];
    int std[M2C_BERN_DEPTH];
    int sp = 0;
    int depth = 0;
    double xl = lo, xr = hi;
    for (;;) {
        double bm;
        int v = variations(b, n, e, &bm);
        if (v == 1) {
            /* one simple root in (xl, xr): start where the control polygon crosses */
            double x0, wn = (xr - xl) / (double)n;
            if (n == 3) {
                /* the same sums with b in registers: the segment by branches */
                if ((b[1] < 0.0) != (b[0] < 0.0))
                    x0 = xl + wn * (0.0 + b[0] / (b[0] - b[1]));
                else if ((b[2] < 0.0) != (b[1] < 0.0))
                    x0 = xl + wn * (1.0 + b[1] / (b[1] - b[2]));
                else
                    x0 = xl + wn * (2.0 + b[2] / (b[2] - b[3]));
            } else {
                int i = 0;
                while ((b[i + 1] < 0.0) == (b[i] < 0.0))
                    i++;
                x0 = xl + wn * ((double)i + b[i] / (b[i] - b[i + 1]));
            }
            if (!(xl < x0 && x0 < xr))
                x0 = 0.5 * (xl + xr);
            double x = m2c_halley_impl(a, n, xl, xr, b[0] < 0.0 ? -1 : 1, x0, M2C_HALLEY_TOL);
            x = m2c_polish_halley_impl(a, n, x, xl, xr);
            if (!(x > xl))
                x = xr;
            if (x > xr)
                x = xr;
            *t = x;
            return 1;
        }
        if (v != 0) {
            if (depth == M2C_BERN_DEPTH || (v < 0 && (fabs(b[0]) <= e || fabs(b[n]) <= e))) {
                if (by_derivatives(a, n, xl, xr, t))
                    return 1;
            } else {
                /* de Casteljau at 1/2: left half in b, right half pushed */
                double c[M2C_MAX_DEGREE + 1];
                double *rb = stb[sp];
                M2C_UNROLL
                for (int i = 0; i <= n; i++)
                    c[i] = b[i];
                rb[n] = c[n];
                M2C_UNROLL
                for (int k = 1; k <= n; k++) {
                    M2C_UNROLL
                    for (int i = 0; i <= n - k; i++)
                        c[i] = 0.5 * (c[i] + c[i + 1]);
                    b[k] = c[0];
                    rb[n - k] = c[n - k];
                }
                double xm = 0.5 * (xl + xr);
                e = e + n * M2C_EPS * bm;
                depth++;
                ste[sp] = e;
                stl[sp] = xm;
                stu[sp] = xr;
                std[sp] = depth;
                sp++;
                xr = xm;
                continue;
            }
        }
        /* no root in (xl, xr]: the next pending interval */
        if (sp == 0)
            return 0;
        sp--;
        M2C_UNROLL
        for (int i = 0; i <= n; i++)
            b[i] = stb[sp][i];
        e = ste[sp];
        xl = stl[sp];
        xr = stu[sp];
        depth = std[sp];
    }
}

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

/* Scaled coefficients (max |a_i| in [1, 2), a[n] != 0): closed forms for
 * degrees 1 and 2, the general method above. */
M2C_INLINE int scaled_impl(const double *a, int n, double lo, double hi, double *t)
{
    if (n == 1) {
        double x = -a[0] / a[1];
        if (!(lo < x && x <= hi))
            return 0;
        *t = x;
        return 1;
    }
    if (n == 2)
        return m2c_quadratic_in(a[2], a[1], a[0], lo, hi, t);
    return general_impl(a, n, lo, hi, t);
}

/* Degree n >= 2 (c[n] != 0): none for a NaN or infinite coefficient, else
 * one power-of-two scale of the coefficients when the roots
 * allow it (the exponents of the nonzero coefficients span little, or
 * Fujiwara's bounds put every root within 2^(+-800/n)), else bands. */
M2C_INLINE int solve_impl(const double *c, int n, double lo, double hi, double *t)
{
    /* max and smallest nonzero |c_i| from their bit patterns (ordered like
     * the values); a NaN or infinity shows as the largest: answer none */
    uint64_t umax = 0, umin = UINT64_MAX;
    M2C_UNROLL
    for (int i = 0; i <= n; i++) {
        uint64_t u;
        memcpy(&u, &c[i], sizeof u);
        u &= 0x7fffffffffffffffu;
        uint64_t uz = u - 1; /* a zero wraps to the top: the minimum skips it */
        umax = u > umax ? u : umax;
        umin = uz < umin ? uz : umin;
    }
    umin += 1; /* c[n] != 0: some u is nonzero */
    if (umax >= 0x7ff0000000000000u)
        return 0;
    double mx, mn;
    memcpy(&mx, &umax, sizeof mx);
    memcpy(&mn, &umin, sizeof mn);
    int spread = m2c_frexp_exp(mx) - m2c_frexp_exp(mn);
    if (__builtin_expect(n == 2 ? spread > M2C_QUAD_SPREAD : spread > M2C_ONE_SCALE_SPAN / n - 2, 0)) {
        int j = 0;
        while (c[j] == 0.0)
            j++;
        int ue, le;
        m2c_root_exponents(c, n, j, &ue, &le);
        int lim = M2C_ONE_SCALE_SPAN / n;
        if (n == 2 || !(ue <= lim && le >= -lim))
            return m2c_banded(c, n, j, ue, le, lo, hi, t);
        /* one scale for a wide spread: top coefficients may underflow */
        double a[M2C_MAX_DEGREE + 1];
        int n2 = m2c_scale_max(c, n, mx, a);
        if (n2 != n)
            return n2 > 0 && m2c_scaled_any(a, n2, lo, hi, t);
        return scaled_impl(a, n, lo, hi, t);
    }
    /* the spread bounds every nonzero |a_i| below by 2^-(spread + 1) >= 2^-901:
     * nothing underflows */
    double a[M2C_MAX_DEGREE + 1];
    m2c_scale_pow2(c, n, mx, a);
    return scaled_impl(a, n, lo, hi, t);
}

#define M2C_CASE(N) \
    case N:         \
        return solve_impl(c, N, lo, hi, t);

int m2c_solve(const double *c, int n, double lo, double hi, double *t)
{
    switch (n) {
        M2C_CASE(2) M2C_CASE(3) M2C_CASE(4) M2C_CASE(5) M2C_CASE(6)
        M2C_CASE(7) M2C_CASE(8) M2C_CASE(9) M2C_CASE(10) M2C_CASE(11) M2C_CASE(12)
        M2C_CASE(13) M2C_CASE(14) M2C_CASE(15) M2C_CASE(16)
    default:
        return 0;
    }
}

/* Degrees 3 to 8 straight from the entry (m2c_smallest_root): c[n] != 0,
 * lo < hi with hi - lo finite; the answer's -0.0 made +0.0.  The same
 * computation as m2c_solve's, with one copy per degree called directly: no
 * general validation, no stripping (about 2 ns of a 35 ns cubic, 5 of an
 * 88 ns octic).  Degrees 9-16 (rare) take the general path. */
int m2c_solve_entry(const double *c, int n, double lo, double hi, double *t)
{
    double x;
    int k;
    switch (n) {
    case 3: k = solve_impl(c, 3, lo, hi, &x); break;
    case 4: k = solve_impl(c, 4, lo, hi, &x); break;
    case 5: k = solve_impl(c, 5, lo, hi, &x); break;
    case 6: k = solve_impl(c, 6, lo, hi, &x); break;
    case 7: k = solve_impl(c, 7, lo, hi, &x); break;
    case 8: k = solve_impl(c, 8, lo, hi, &x); break;
    default: return m2c_solve(c, n, lo, hi, t); /* never: the entry passes 3 <= n <= 8 */
    }
    if (!k)
        return 0;
    *t = x + 0.0;
    return 1;
}

#undef M2C_CASE
#define M2C_CASE(N) \
    case N:         \
        return scaled_impl(a, N, lo, hi, t);

int m2c_scaled_any(const double *a, int n, double lo, double hi, double *t)
{
    switch (n) {
        M2C_CASE(1) M2C_CASE(2) M2C_CASE(3) M2C_CASE(4) M2C_CASE(5) M2C_CASE(6)
        M2C_CASE(7) M2C_CASE(8) M2C_CASE(9) M2C_CASE(10) M2C_CASE(11) M2C_CASE(12)
        M2C_CASE(13) M2C_CASE(14) M2C_CASE(15) M2C_CASE(16)
    default:
        return 0;
    }
}
