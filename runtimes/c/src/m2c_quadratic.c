/* Quadratic roots with an error-free discriminant (roots in x units). */
#include <math.h>
#include "m2c_internal.h"

int m2c_quadratic(double a, double b, double c, double r[2])
{
    double p, pe, q, qe;
    m2c_two_prod(b, b, &p, &pe);
    double a4 = 4.0 * a;
    m2c_two_prod(a4, c, &q, &qe);
    double disc = (p - q) + (pe - qe);
    double bound = M2C_EPS * M2C_EPS * (p + fabs(q));
    if (disc < -bound)
        return 0;
    if (disc <= bound) {
        r[0] = -b / (2.0 * a);
        return 1;
    }
    double s = sqrt(disc);
    if (b < 0.0)
        s = -s;
    double qq = -0.5 * (b + s);
    double r1 = qq / a;
    double r2 = c / qq;
    if (r1 <= r2) {
        r[0] = r1;
        r[1] = r2;
    } else {
        r[0] = r2;
        r[1] = r1;
    }
    return 2;
}
