/* Bracketed Newton on a monotone piece, and the compensated polish
 * (x, brackets in the caller's time unit). */
#include <math.h>
#include "m2c_internal.h"

/* Bisection point of [xa, xb]; half = (xb - xa)/2. */
static double midpoint(double xa, double xb, double half)
{
    if (xa < 0.0 && 0.0 < xb)
        return 0.0;
    if (xa > 0.0 && xb > 8.0 * xa)
        return sqrt(xa) * sqrt(xb);
    if (xb < 0.0 && xa < 8.0 * xb)
        return -(sqrt(-xa) * sqrt(-xb));
    if (xa == 0.0 && xb > 0.0)
        return xb * M2C_SIXTEENTH;
    if (xb == 0.0 && xa < 0.0)
        return xa * M2C_SIXTEENTH;
    return xa + half;
}

double m2c_newton(const double *a, int n, double lo, double hi, int slo,
                  double *xa_out, double *xb_out)
{
    double xa = lo, xb = hi;
    double x = 0.5 * (xa + xb);
    double dx = xb - xa;
    double dxold = dx;
    int neg = slo < 0;
    double tol = M2C_EPS;
    for (int it = 0; it < M2C_MAXIT; it++) {
        double v = a[n];
        double d = 0.0;
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
                tol = M2C_NEWTON_TOL;
            } else {
                dxold = dx;
                dx = 0.5 * (xb - xa);
                xn = midpoint(xa, xb, dx);
                tol = M2C_EPS;
            }
        } else {
            dxold = dx;
            dx = 0.5 * (xb - xa);
            xn = midpoint(xa, xb, dx);
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
    *xa_out = xa;
    *xb_out = xb;
    return x;
}

double m2c_polish(const double *a, int n, double x, double xa, double xb)
{
    for (int k = 0; k < 2; k++) {
        double ax = fabs(x);
        double v = a[n];
        double d = 0.0;
        double pt = fabs(v);
        for (int i = n - 1; i >= 0; i--) {
            d = d * x + v;
            v = v * x + a[i];
            pt = pt * ax + fabs(a[i]);
        }
        if (d == 0.0)
            return x;
        if (n * pt <= 8.0 * fabs(x * d)) {
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
