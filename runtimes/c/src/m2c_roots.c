/* m2c_smallest_root: validation and degree reduction; m2c_solve
 * (m2c_general.c) scales and dispatches (t in the caller's time unit). */
#include <math.h>
#include "m2c_internal.h"
#include "m2c_roots.h"

int m2c_scale(const double *c, int n, double *a)
{
    return m2c_scale_impl(c, n, a);
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
    double x;
    if (!m2c_solve(c, n, lo, hi, &x))
        return 0;
    *t = x + 0.0;
    return 1;
}
