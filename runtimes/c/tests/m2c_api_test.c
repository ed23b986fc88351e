/* API edge cases of libm2c (degrees, NULL, the GSL baseline's contract). */
#include <math.h>
#include <stdio.h>
#include "m2c_roots.h"

static int failures;

#define CHECK(cond)                                                        \
    do {                                                                   \
        if (!(cond)) {                                                     \
            printf("FAIL %s:%d: %s\n", __FILE__, __LINE__, #cond);         \
            failures++;                                                    \
        }                                                                  \
    } while (0)

int main(void)
{
    double t = -1.0;
    const double lin[2] = {-0.5, 1.0};
    const double dbl[3] = {0.25, -1.0, 1.0};
    const double cub[4] = {-0.375, 0.0, 0.0, 1.0};
    double big[18] = {0};
    CHECK(m2c_smallest_root(lin, 1, 0.0, 1.0, &t) == 1 && t == 0.5);
    CHECK(m2c_smallest_root(lin, -1, 0.0, 1.0, &t) == -1);
    CHECK(m2c_smallest_root(big, 17, 0.0, 1.0, &t) == -1);
    CHECK(m2c_smallest_root(0, 1, 0.0, 1.0, &t) == -1);
    CHECK(m2c_smallest_root(lin, 1, 0.0, 1.0, 0) == -1);
    CHECK(m2c_smallest_root(lin, 1, 0.5, 1.0, &t) == 0);
    CHECK(m2c_smallest_root(lin, 1, 0.0, INFINITY, &t) == 0);
    CHECK(m2c_smallest_root(lin, 1, NAN, 1.0, &t) == 0);
    CHECK(m2c_smallest_root(dbl, 2, 0.0, 1.0, &t) == 1 && t == 0.5);
    CHECK(m2c_smallest_root(cub, 3, 0.0, 1.0, &t) == 1 && fabs(t - cbrt(0.375)) < 1e-15);
    CHECK(m2c_smallest_root(big, 16, 0.0, 1.0, &t) == 0);
    CHECK(m2c_smallest_root_gsl(lin, 1, 0.0, 1.0, &t) == 1 && fabs(t - 0.5) < 1e-15);
    CHECK(m2c_smallest_root_gsl(cub, 3, 0.0, 1.0, &t) == 1 && fabs(t - cbrt(0.375)) < 1e-12);
    CHECK(m2c_smallest_root_gsl(big, 16, 0.0, 1.0, &t) == 0);
    CHECK(m2c_smallest_root_gsl(lin, 17, 0.0, 1.0, &t) == -1);
    printf("%d passed, %d failed\n", 15 - failures, failures);
    return failures != 0;
}
