/* Baseline: the same contract answered by GSL's companion-matrix solver
 * (t in the caller's time unit). */
#include <math.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_poly.h>
#include "m2c_internal.h"
#include "m2c_roots.h"

/* One cached workspace per degree (GSL allocates per call otherwise). */
static gsl_poly_complex_workspace *workspaces[M2C_MAX_DEGREE + 1];

int m2c_smallest_root_gsl(const double *c, int degree, double lo, double hi, double *t)
{
    int n = 0;
    int ok = m2c_check_input(c, degree, lo, hi, t, &n);
    if (ok != 1)
        return ok;
    double a[M2C_MAX_DEGREE + 1];
    n = m2c_scale(c, n, a); /* same exact scaling; keeps GSL's balancing finite */
    if (n <= 0)
        return 0;
    gsl_set_error_handler_off();
    if (workspaces[n] == 0) {
        workspaces[n] = gsl_poly_complex_workspace_alloc((size_t)n + 1);
        if (workspaces[n] == 0)
            return 0;
    }
    double z[2 * M2C_MAX_DEGREE];
    if (gsl_poly_complex_solve(a, (size_t)n + 1, workspaces[n], z) != GSL_SUCCESS)
        return 0;
    int found = 0;
    double best = 0.0;
    for (int i = 0; i < n; i++) {
        double re = z[2 * i], im = z[2 * i + 1];
        double scale = fabs(re) > 1.0 ? fabs(re) : 1.0;
        if (fabs(im) <= 1e-7 * scale && lo < re && re <= hi && (!found || re < best)) {
            best = re;
            found = 1;
        }
    }
    if (found)
        *t = best + 0.0;
    return found;
}
