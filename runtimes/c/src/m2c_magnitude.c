/* Any magnitude: bounds on the root exponents (Fujiwara) and the band
 * method for roots spread too widely for one power-of-two scale of the
 * coefficients (docs/roots.md step 7).  t in the caller's time unit. */
#include <math.h>
#include "m2c_internal.h"

/* ceil(a / k) for k > 0, with nonnegative operands only. */
static int ceil_div(int a, int k)
{
    if (a >= 0)
        return (a + k - 1) / k;
    return -((-a) / k);
}

void m2c_root_exponents(const double *c, int n, int j, int *ue, int *le)
{
    int en = m2c_frexp_exp(c[n]);
    int ej = m2c_frexp_exp(c[j]);
    int u = -(1 << 30), lx = -(1 << 30);
    for (int i = j; i < n; i++) {
        if (c[i] != 0.0) {
            int v = ceil_div(m2c_frexp_exp(c[i]) - en + 1, n - i);
            if (v > u)
                u = v;
        }
    }
    for (int i = j + 1; i <= n; i++) {
        if (c[i] != 0.0) {
            int v = ceil_div(m2c_frexp_exp(c[i]) - ej + 1, i - j);
            if (v > lx)
                lx = v;
        }
    }
    *ue = u + 1;
    *le = -(lx + 1);
}

/* 2^e, or infinity beyond the largest double (a band edge). */
static double edge(int e)
{
    if (e > 1023)
        return INFINITY;
    return ldexp(1.0, e);
}

/* The smallest root in (xl, xr], where 2^(s - w) <= |x| <= 2^s: solved in
 * u = t 2^-s with the coefficients c_i 2^(s i) scaled together so that the
 * largest lies in [1, 2) (those far below underflow; their terms are
 * negligible in the band). */
static int band(const double *c, int n, int s, double xl, double xr, double *t)
{
    int m = -(1 << 30);
    for (int i = 0; i <= n; i++) {
        if (c[i] != 0.0) {
            int f = m2c_frexp_exp(c[i]) + s * i;
            if (f > m)
                m = f;
        }
    }
    double a[M2C_MAX_DEGREE + 1];
    for (int i = 0; i <= n; i++)
        a[i] = ldexp(c[i], s * i + 1 - m);
    while (n >= 0 && a[n] == 0.0)
        n--;
    if (n <= 0)
        return 0;
    double u;
    if (!m2c_scaled_any(a, n, ldexp(xl, -s), ldexp(xr, -s), &u))
        return 0;
    double x = ldexp(u, s);
    if (!(xl < x && x <= xr))
        return 0;
    *t = x;
    return 1;
}

int m2c_banded(const double *c, int n, int j, int ue, int le, double lo, double hi, double *t)
{
    int w = M2C_BAND_SPAN / n;
    int nb = ceil_div(ue - le, w);
    for (int k = nb - 1; k >= 0; k--) {
        int s = le + (k + 1) * w;
        double xl = -edge(s), xr = -edge(s - w);
        if (lo > xl)
            xl = lo;
        if (hi < xr)
            xr = hi;
        if (xl < xr && band(c, n, s, xl, xr, t))
            return 1;
    }
    if (j > 0 && lo < 0.0 && 0.0 <= hi) {
        *t = 0.0;
        return 1;
    }
    for (int k = 0; k < nb; k++) {
        int s = le + (k + 1) * w;
        double xl = edge(s - w), xr = edge(s);
        if (lo > xl)
            xl = lo;
        if (hi < xr)
            xr = hi;
        if (xl < xr && band(c, n, s, xl, xr, t))
            return 1;
    }
    return 0;
}
