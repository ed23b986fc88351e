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
    int n = 0;
    int ok = m2c_check_input(c, degree, lo, hi, t, &n);
    if (ok != 1)
        return ok;
    double x;
    if (!m2c_solve(c, n, lo, hi, &x))
        return 0;
    *t = x + 0.0;
    return 1;
}
