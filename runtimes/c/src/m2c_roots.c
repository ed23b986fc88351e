/* m2c_smallest_root: validation, degree reduction, exact power-of-two
 * scaling and dispatch (t in the caller's time unit). */
#include <math.h>
#include "m2c_internal.h"
#include "m2c_roots.h"

int m2c_scale(const double *c, int n, double *a)
{
    /* scale so that max |a_i| lies in [1, 2) */
    double m = 0.0;
    for (int i = 0; i <= n; i++) {
        double v = fabs(c[i]);
        if (v > m)
            m = v;
    }
    int e;
    frexp(m, &e);
    int k = 1 - e;
    for (int i = 0; i <= n; i++)
        a[i] = c[i];
    if (k > 1000) {
        double f = ldexp(1.0, 600);
        for (int i = 0; i <= n; i++)
            a[i] = a[i] * f;
        k -= 600;
    }
    double f = ldexp(1.0, k);
    for (int i = 0; i <= n; i++)
        a[i] = a[i] * f;
    while (n >= 0 && a[n] == 0.0) /* underflowed to zero in the scaling */
        n--;
    return n;
}

int m2c_smallest_root(const double *c, int degree, double lo, double hi, double *t)
{
    if (c == 0 || t == 0 || degree < 0 || degree > M2C_MAX_DEGREE)
        return -1;
    if (!(isfinite(lo) && isfinite(hi)) || !(lo < hi))
        return 0;
    for (int i = 0; i <= degree; i++)
        if (!isfinite(c[i]))
            return 0;
    int n = degree;
    while (n >= 0 && c[n] == 0.0)
        n--;
    if (n <= 0)
        return 0;
    double a[M2C_MAX_DEGREE + 1];
    n = m2c_scale(c, n, a);
    if (n <= 0)
        return 0;
    double x;
    if (n == 1) {
        x = -a[0] / a[1];
        if (!(lo < x && x <= hi))
            return 0;
    } else if (n == 2) {
        double r[2];
        int nr = m2c_quadratic(a[2], a[1], a[0], r);
        int found = 0;
        for (int i = 0; i < nr && !found; i++) {
            if (lo < r[i] && r[i] <= hi) {
                x = r[i];
                found = 1;
            }
        }
        if (!found)
            return 0;
    } else if (!m2c_general(a, n, lo, hi, &x)) {
        return 0;
    }
    *t = x + 0.0;
    return 1;
}
