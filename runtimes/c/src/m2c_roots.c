/* m2c_smallest_root: validation and degree reduction; m2c_solve
 * (m2c_general.c) scales and dispatches (t in the caller's time unit). */
#include <float.h>
#include <math.h>
#include "m2c_internal.h"
#include "m2c_roots.h"

int m2c_scale(const double *c, int n, double *a)
{
    return m2c_scale_impl(c, n, a);
}

/* Everything after the entry's first steps (m2c_x_entry, m2c_roots.h),
 * out of line so that those need no stack frame. */
int m2c_x_general(const double *c, int degree, double lo, double hi, double *t)
{
    /* the contract's input rules (m2c_check_input), with the finiteness of
     * the coefficients tested by m2c_solve in the same pass as their spread */
    if (c == 0 || t == 0 || degree < 0 || degree > M2C_MAX_DEGREE)
        return -1;
    if (!((fabs(lo) <= DBL_MAX) & (fabs(hi) <= DBL_MAX)) || !(lo < hi))
        return 0;
    int n = degree;
    while (n >= 0 && c[n] == 0.0) /* a NaN or infinity stops this: it stays in c[0..n] */
        n--;
    if (n <= 0)
        return 0;
    double x;
    if (n == 1) {
        if (!((fabs(c[0]) <= DBL_MAX) & (fabs(c[1]) <= DBL_MAX)))
            return 0;
        x = -c[0] / c[1]; /* one correctly rounded division: no scaling needed */
        if (!(lo < x && x <= hi))
            return 0;
    } else if (!m2c_solve(c, n, lo, hi, &x)) {
        return 0;
    }
    *t = x + 0.0;
    return 1;
}

/* The degree-2 fast path where the discriminant may cancel: the whole of
 * m2c_quadratic_in (its error-free branch). */
int m2c_x_quadratic_exact(double a, double b, double c, double lo, double hi, double *t)
{
    double x;
    if (!m2c_quadratic_in(a, b, c, lo, hi, &x))
        return 0;
    *t = x + 0.0;
    return 1;
}

/* The entry itself (with GNU C and optimisation, callers inline the same
 * steps from m2c_roots.h). */
int m2c_smallest_root(const double *c, int degree, double lo, double hi, double *t)
{
    return m2c_x_entry(c, degree, lo, hi, t);
}
