/* The bisection point of the bracketed Newton method (x in the caller's
 * time unit); the method itself is m2c_newton_impl in m2c_internal.h. */
#include <math.h>
#include "m2c_internal.h"

double m2c_midpoint(double xa, double xb, double half)
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
