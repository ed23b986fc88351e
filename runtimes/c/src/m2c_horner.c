/* Polynomial evaluation: compensated Horner and the sign tests (values are
 * in the units of the coefficients; x in the caller's time unit). */
#include <math.h>
#include "m2c_internal.h"

double m2c_comp_horner(const double *a, int n, double x)
{
    return m2c_comp_horner_impl(a, n, x);
}

int m2c_sign_top(const double *a, int n, double x)
{
    double ax = fabs(x);
    double v = a[n];
    double pt = fabs(v);
    for (int i = n - 1; i >= 0; i--) {
        v = v * x + a[i];
        pt = pt * ax + fabs(a[i]);
    }
    if (fabs(v) > 2.0 * n * M2C_EPS * pt)
        return v > 0.0 ? 1 : -1;
    double r = m2c_comp_horner(a, n, x);
    double bound = (2.0 * n * M2C_EPS) * (2.0 * n * M2C_EPS) * pt + M2C_TINY;
    if (fabs(r) <= bound)
        return 0;
    return r > 0.0 ? 1 : -1;
}

int m2c_sign_plain(const double *a, int n, double x)
{
    double v = a[n];
    for (int i = n - 1; i >= 0; i--)
        v = v * x + a[i];
    if (v > 0.0)
        return 1;
    if (v < 0.0)
        return -1;
    return 0;
}
