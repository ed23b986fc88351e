/* max2code C runtime: smallest real root of a polynomial in (lo, hi].
 * Contract and algorithm: docs/roots.md.  Times are in the caller's units. */
#ifndef M2C_ROOTS_H
#define M2C_ROOTS_H

#ifdef __cplusplus
extern "C" {
#endif

/* Largest supported degree. */
#define M2C_MAX_DEGREE 16

/* Smallest real root t of c[0] + c[1] t + ... + c[degree] t^degree with
 * lo < t <= hi.  Returns 1 and stores *t when found, 0 when there is none
 * (including NaN/inf input, lo >= hi, all-zero or constant polynomials),
 * -1 when degree is outside 0..M2C_MAX_DEGREE or c/t is NULL. */
int m2c_smallest_root(const double *c, int degree, double lo, double hi, double *t);

/* The same contract answered by GSL's companion-matrix solver
 * (gsl_poly_complex_solve), the paper's baseline: a complex root counts as
 * real when |Im z| <= 1e-7 * max(1, |Re z|).  Not thread-safe (it caches one
 * GSL workspace per degree). */
int m2c_smallest_root_gsl(const double *c, int degree, double lo, double hi, double *t);

#ifdef __cplusplus
}
#endif

#endif
