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

/* Everything but the degree-2 fast path (kept out of line so that the fast
 * path needs no stack frame). */
__attribute__((noinline)) static int smallest_root_general(const double *c, int degree, double lo, double hi,
                                                           double *t)
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

int m2c_smallest_root(const double *c, int degree, double lo, double hi, double *t)
{
    if (degree == 2 && c != 0 && t != 0) {
        /* fast path: moderate coefficients give the same bits unscaled */
        double c0 = c[0], c1 = c[1], c2 = c[2];
        /* lo < hi, both finite: hi - lo is positive and finite (an overflow
         * only sends the call to the general path) */
        double w = hi - lo;
        if ((c2 != 0.0) & m2c_moderate3(c0, c1, c2) & (w > 0.0) & (w <= DBL_MAX)) {
            double x;
            if (!m2c_quadratic_in(c2, c1, c0, lo, hi, &x))
                return 0;
            *t = x + 0.0;
            return 1;
        }
    }
    if (degree >= 3 && degree <= 8 && c != 0 && t != 0 && c[degree] != 0.0) {
        /* nothing to strip, and lo < hi with both finite (as above): one
         * per-degree copy of the general method, called directly */
        double w = hi - lo;
        if ((w > 0.0) & (w <= DBL_MAX))
            return m2c_solve_entry(c, degree, lo, hi, t);
    }
    return smallest_root_general(c, degree, lo, hi, t);
}
