/* Contact time of the exact motion: the generic driver of
 * docs/exact-motion.md ("Algorithm"), operation for operation the same as
 * the Rust, Python and Modula-2 runtimes. */
#include <math.h>
#include "m2c_exact.h"
#include "m2c_roots.h"

#define FLOOR 0x1p-46        /* 64 eps: the rounding floor is FLOOR * scale */
#define MAX_DEPTH 40         /* subdivision levels */
#define MAX_STEPS 200        /* zones visited per level */
#define POLISH_STEPS 4       /* Newton steps on the exact gap */
#define SAFE (1.0 + 0x1p-40) /* covers the rounding of reach() */

typedef struct {
    const m2c_motion *m;
    const double *p;
    int (*solver)(const double *c, int degree, double lo, double hi, double *t);
    double zero_tol;
} ctx;

void m2c_exact_defaults(m2c_exact_options *o)
{
    o->window_angle = M2C_EXACT_ANGLE;
    o->refine = 1;
    o->zero_tol = 0.0;
    o->solver = m2c_smallest_root;
}

static double value(const double *c, int n, double x)
{
    double v = c[n];
    for (int i = n - 1; i >= 0; i--)
        v = v * x + c[i];
    return v;
}

static double slope(const double *c, int n, double x)
{
    if (n < 1)
        return 0.0;
    double d = (double)n * c[n];
    for (int i = n - 1; i >= 1; i--)
        d = d * x + (double)i * c[i];
    return d;
}

/* A bound on |p(s) - p(0)| for 0 <= s <= L, a little above the rounded sum. */
static double reach(const double *c, int n, double L)
{
    if (n < 1)
        return 0.0;
    double b = fabs(c[n]);
    for (int i = n - 1; i >= 1; i--)
        b = b * L + fabs(c[i]);
    return b * L * SAFE;
}

static double floor_at(const ctx *k, double t)
{
    return FLOOR * k->m->scale(k->p, t);
}

/* The first root of the exact gap in [t0, t0 + L] (closed: t0 counts) or
 * (t0, t0 + L]: 1 with *r and the bracket [*a, *b] it was found in, 0 for
 * none, -1 on an error. */
static int first_root(const ctx *k, double t0, double L, int closed, int depth, double *r, double *a, double *b)
{
    double pp[M2C_EXACT_MAX_PARAMS], c[M2C_MAX_DEGREE + 1], q[M2C_MAX_DEGREE + 1];
    k->m->shift(k->p, t0, pp);
    int n = k->m->coefficients(pp, c);
    if (n < 0 || n > M2C_MAX_DEGREE)
        return -1;
    double e = k->m->truncation(pp, L);
    double f = floor_at(k, t0 + L);
    double s;
    *a = t0;
    *b = t0 + L;
    if (closed && fabs(c[0]) <= f) {
        *r = t0;
        return 1;
    }
    if (e <= f || depth >= MAX_DEPTH) {
        if (k->solver(c, n, 0.0, L, &s) != 1)
            return 0;
        *r = t0 + s;
        return 1;
    }
    double mg = e + f;
    if (fabs(c[0]) - reach(c, n, L) > mg)   /* |P| > mg on the whole window: no zone */
        return 0;
    double x = 0.0;
    for (int step = 0; step < MAX_STEPS; step++) {
        double z;
        double v = value(c, n, x);
        if (fabs(v) <= mg) {
            z = x;
        } else {
            for (int i = 0; i <= n; i++)
                q[i] = c[i];
            q[0] = v > 0.0 ? c[0] - mg : c[0] + mg;
            if (k->solver(q, n, x, L, &z) != 1)
                return 0;
        }
        double d = slope(c, n, z);
        double w = 0.5 * (L - z);
        if (d != 0.0) {
            double we = 8.0 * mg / fabs(d);
            if (we < w)
                w = we;
        }
        if (!(w > 0.0))
            return 0;
        int st = first_root(k, t0 + z, w, closed || z > 0.0, depth + 1, r, a, b);
        if (st != 0)
            return st;
        x = z + w;
        if (!(x < L))
            return 0;
    }
    /* too many zones: this level's polynomial decides the rest */
    if (k->solver(c, n, x, L, &s) != 1)
        return 0;
    *a = t0 + x;
    *b = t0 + L;
    *r = t0 + s;
    return 1;
}

/* Newton steps on the exact gap, kept while |gap| decreases inside
 * [a, b] and (lo, hi]. */
static double polish(const ctx *k, double x, double a, double b, double lo, double hi)
{
    double g = k->m->gap(k->p, x);
    for (int i = 0; i < POLISH_STEPS; i++) {
        if (g == 0.0)
            break;
        double d = k->m->gap_dt(k->p, x);
        if (!(d != 0.0))
            break;
        double xn = x - g / d;
        if (!(xn >= a && xn <= b && xn > lo && xn <= hi))
            break;
        double gn = k->m->gap(k->p, xn);
        if (!(fabs(gn) < fabs(g)))
            break;
        x = xn;
        g = gn;
    }
    return x;
}

/* Where a contact at t = 0 that separates has left the zero band. */
static double depart(const ctx *k, double horizon, double band0, double d0)
{
    double tau = d0 > 0.0 ? 2.0 * band0 / d0 : horizon * 0x1p-30;
    if (!(tau > 0.0))
        tau = horizon * 0x1p-30;
    for (int i = 0; i < 200; i++) {
        if (!(tau < horizon))
            return horizon;
        double band = floor_at(k, tau);
        if (k->zero_tol > band)
            band = k->zero_tol;
        if (fabs(k->m->gap(k->p, tau)) > 2.0 * band)
            return tau;
        tau = 2.0 * tau;
    }
    return horizon;
}

/* The checks and the rules at t = 0 shared by m2c_exact_toc and
 * m2c_exact_poly_toc: -1 an error, 0 none, 1 a contact at 0,
 * M2C_EXACT_OVERLAPPED, or 3 with *start (0, or where a separating contact
 * at 0 has left the zero band): search (*start, horizon]. */
#define SEARCH 3
static int begin(const ctx *k, const m2c_exact_options *o, double horizon, double *start, double *t)
{
    const m2c_motion *m = k->m;
    const double *p = k->p;
    if (!(o->window_angle > 0.0) || !isfinite(o->window_angle) || !o->solver || !(o->zero_tol >= 0.0))
        return -1;
    if (!isfinite(horizon) || !(horizon > 0.0))
        return 0;
    for (int i = 0; i < m->nparams; i++)
        if (!isfinite(p[i]))
            return 0;
    *start = 0.0;
    double band0 = floor_at(k, 0.0);
    if (o->zero_tol > band0)
        band0 = o->zero_tol;
    double g0 = m->gap(p, 0.0);
    if (g0 < -band0) {          /* inside each other at t = 0: not a contact, its own answer */
        *t = 0.0;
        return M2C_EXACT_OVERLAPPED;
    }
    if (fabs(g0) <= band0) {
        double d0 = m->gap_dt(p, 0.0);
        if (d0 < 0.0) {
            *t = 0.0;
            return 1;
        }
        *start = depart(k, horizon, band0, d0);
        if (!(*start < horizon))
            return 0;
    }
    return SEARCH;
}

int m2c_exact_toc(const m2c_motion *m, const double *p, double horizon, const m2c_exact_options *options,
                  double *t)
{
    m2c_exact_options o;
    if (options)
        o = *options;
    else
        m2c_exact_defaults(&o);
    if (!m || !p || !t || m->nparams < 0 || m->nparams > M2C_EXACT_MAX_PARAMS || m->max_degree > M2C_MAX_DEGREE)
        return -1;
    ctx k = {m, p, o.solver, o.zero_tol};
    double start;
    int st0 = begin(&k, &o, horizon, &start, t);
    if (st0 != SEARCH)
        return st0;
    double span = horizon - start;
    double h = span;
    double rate = m->rate(p);
    if (rate > 0.0 && o.window_angle / rate < span)
        h = o.window_angle / rate;
    if (span / h > M2C_EXACT_MAX_WINDOWS)
        return -1;
    double t0 = start;
    for (double w = 0.0; t0 < horizon; w += 1.0) {
        double t1 = start + (w + 1.0) * h;
        if (!(t1 < horizon))
            t1 = horizon;
        double L = t1 - t0;
        double r, a, b;
        int st;
        if (o.refine) {
            st = first_root(&k, t0, L, w > 0.0, 0, &r, &a, &b);
            if (st == 1)
                r = polish(&k, r, a, b, start, horizon);
        } else {
            double pp[M2C_EXACT_MAX_PARAMS], c[M2C_MAX_DEGREE + 1], s = 0.0;
            m->shift(p, t0, pp);
            int n = m->coefficients(pp, c);
            if (n < 0 || n > M2C_MAX_DEGREE)
                st = -1;
            else if (fabs(c[0]) - reach(c, n, L) > 0.0)
                st = 0;
            else
                st = o.solver(c, n, 0.0, L, &s) == 1;
            r = t0 + s;
        }
        if (st < 0)
            return -1;
        if (st == 1) {
            if (r > horizon)
                r = horizon;
            *t = r + 0.0;
            return 1;
        }
        t0 = t1;
    }
    return 0;
}

int m2c_exact_poly_toc(const m2c_poly_motion *pm, const double *p, double horizon,
                       const m2c_exact_options *options, double *t)
{
    m2c_exact_options o;
    if (options)
        o = *options;
    else
        m2c_exact_defaults(&o);
    if (!pm || !p || !t || pm->nparams < 0 || pm->nparams > M2C_EXACT_MAX_PARAMS || pm->max_degree > M2C_MAX_DEGREE)
        return -1;
    /* the windowed driver's motion without shift, truncation and rate, which this path never calls */
    m2c_motion m = {pm->nparams, pm->max_degree, pm->coefficients, 0, pm->gap, pm->gap_dt, pm->scale, 0, 0};
    ctx k = {&m, p, o.solver, o.zero_tol};
    double start;
    int st0 = begin(&k, &o, horizon, &start, t);
    if (st0 != SEARCH)
        return st0;
    double c[M2C_MAX_DEGREE + 1], r;
    int n = m.coefficients(p, c);
    if (n < 0 || n > M2C_MAX_DEGREE)
        return -1;
    if (o.solver(c, n, start, horizon, &r) != 1)
        return 0;
    if (o.refine)
        r = polish(&k, r, start, horizon, start, horizon);
    if (r > horizon)
        r = horizon;
    *t = r + 0.0;
    return 1;
}
