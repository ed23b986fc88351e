/* The general method (degree >= 3): clip to the root bound, cheap exit,
 * derivative roots bottom up, first root at the top (t in x units). */
#include <math.h>
#include "m2c_internal.h"
#include "m2c_roots.h"

int m2c_roots_between(const double *a, int n, const double *crit, int m,
                      double lo, double hi, double *out)
{
    int k = 0;
    double xl = lo;
    int sl = m2c_sign_plain(a, n, lo);
    for (int i = 0; i <= m; i++) {
        double xr = i < m ? crit[i] : hi;
        int sr = m2c_sign_plain(a, n, xr);
        if (sl == 0 && i > 0) {
            out[k++] = xl;
        } else if (sl * sr < 0) {
            double xa, xb;
            out[k++] = m2c_newton(a, n, xl, xr, sl, &xa, &xb);
        }
        xl = xr;
        sl = sr;
    }
    return k;
}

int m2c_general(const double *a, int n, double lo, double hi, double *t)
{
    /* 1. clip to the root bound */
    double an = fabs(a[n]);
    double mx = 0.0;
    for (int i = 0; i < n; i++) {
        double v = fabs(a[i]) / an;
        if (v > mx)
            mx = v;
    }
    double r = 2.0 * (1.0 + mx);
    double cap = ldexp(1.0, 900 / n);
    if (r > cap)
        r = cap;
    if (lo < -r)
        lo = -r;
    if (hi > r)
        hi = r;
    if (!(lo < hi))
        return 0;
    /* 2. cheap exit: Taylor shift at the midpoint */
    double mid = 0.5 * (lo + hi);
    double rad = hi - mid;
    if (mid - lo > rad)
        rad = mid - lo;
    rad = rad * (1.0 + 4.0 * M2C_EPS);
    double q[M2C_MAX_DEGREE + 1] = {0};
    for (int i = 0; i <= n; i++)
        q[i] = a[i];
    for (int i = 0; i < n; i++)
        for (int j = n - 1; j >= i; j--)
            q[j] = q[j] + mid * q[j + 1];
    double s = fabs(q[n]);
    for (int k = n - 1; k > 0; k--)
        s = s * rad + fabs(q[k]);
    s = s * rad;
    double y = fabs(mid) + rad;
    double pt = fabs(a[n]);
    for (int i = n - 1; i >= 0; i--)
        pt = pt * y + fabs(a[i]);
    if (fabs(q[0]) - s * (1.0 + 4.0 * (n + 1) * M2C_EPS) > 8.0 * (n + 1) * M2C_EPS * pt)
        return 0;
    /* 3. derivative tables and their roots, bottom up */
    double ders[M2C_MAX_DEGREE - 1][M2C_MAX_DEGREE + 1];
    for (int i = 0; i <= n; i++)
        ders[0][i] = a[i];
    for (int k = 1; k < n - 1; k++)
        for (int i = 0; i <= n - k; i++)
            ders[k][i] = ders[k - 1][i + 1] * (double)(i + 1);
    double crit[M2C_MAX_DEGREE], next[M2C_MAX_DEGREE], qr[2];
    const double *d2 = ders[n - 2];
    int nq = m2c_quadratic(d2[2], d2[1], d2[0], qr);
    int m = 0;
    for (int i = 0; i < nq; i++)
        if (lo < qr[i] && qr[i] < hi)
            crit[m++] = qr[i];
    for (int k = n - 3; k > 0; k--) {
        int m2 = m2c_roots_between(ders[k], n - k, crit, m, lo, hi, next);
        for (int i = 0; i < m2; i++)
            crit[i] = next[i];
        m = m2;
    }
    /* 4. top level: first root, careful signs */
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
            double xa, xb;
            double x = m2c_newton(a, n, xl, xr, sl, &xa, &xb);
            x = m2c_polish(a, n, x, xl, xr); /* the monotone piece bounds the polish */
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
