/* Internal pieces of the root solver, shared by the files in src/.
 * Every function follows docs/roots.md operation for operation, so that the
 * C, Rust, Python and Modula-2 runtimes compute the same bits. */
#ifndef M2C_INTERNAL_H
#define M2C_INTERNAL_H

#define M2C_EPS 0x1p-52          /* spacing of doubles at 1 (2 u) */
#define M2C_SPLITTER 134217729.0 /* 2^27 + 1, Veltkamp splitting constant */
#define M2C_TINY 0x1p-1000       /* absolute floor of the touching bound */
#define M2C_SIXTEENTH 0x1p-16    /* bisection step from a bracket end at 0 */
#define M2C_NEWTON_TOL 0x1p-30   /* an accepted Newton step this small (relative) has converged */
#define M2C_MAXIT 100            /* bracketed Newton step limit */

/* Error-free product a*b = *p + *e (Dekker, no FMA). */
static inline void m2c_two_prod(double a, double b, double *p, double *e)
{
    double q = a * b;
    double t = M2C_SPLITTER * a;
    double ah = t - (t - a);
    double al = a - ah;
    t = M2C_SPLITTER * b;
    double bh = t - (t - b);
    double bl = b - bh;
    *p = q;
    *e = ((ah * bh - q) + ah * bl + al * bh) + al * bl;
}

/* p(x) by compensated Horner; a[0..n] ascending, n >= 1. */
double m2c_comp_horner(const double *a, int n, double x);

/* Sign of p(x): -1, 0 (zero within the compensated bound), +1. */
int m2c_sign_top(const double *a, int n, double x);

/* Sign of the plain Horner value of p(x): -1, 0 (exactly zero), +1. */
int m2c_sign_plain(const double *a, int n, double x);

/* Root of p in (lo, hi), p(lo) of sign slo (nonzero), p(hi) of the other;
 * *xa, *xb receive the final bracket. */
double m2c_newton(const double *a, int n, double lo, double hi, int slo,
                  double *xa, double *xb);

/* A last Newton step inside [xa, xb]: plain when Horner is accurate enough
 * at x, else up to two steps with compensated Horner. */
double m2c_polish(const double *a, int n, double x, double xa, double xb);

/* Real roots of a x^2 + b x + c (a != 0), ascending, into r; returns count. */
int m2c_quadratic(double a, double b, double c, double r[2]);

/* All roots of p (degree n) in the open (lo, hi), ascending, given the
 * m ascending roots crit of p' there; returns the count written to out. */
int m2c_roots_between(const double *a, int n, const double *crit, int m,
                      double lo, double hi, double *out);

/* a[0..] = c[0..n] times the power of two that puts max |c_i| in [1, 2);
 * returns the degree left after dropping top coefficients that underflowed. */
int m2c_scale(const double *c, int n, double *a);

/* The general method for degree n >= 3 (a scaled); 1 and *t when found. */
int m2c_general(const double *a, int n, double lo, double hi, double *t);

#endif
