/* Contact time of the exact motion: the generic driver of
 * docs/exact-motion.md ("Algorithm"), operation for operation the same as
 * the Rust, Python and Modula-2 runtimes. */
#include <float.h>
#include <math.h>
#include "m2c_exact.h"
#include "m2c_roots.h"

#define FLOOR 0x1p-46        /* 64 eps: the rounding floor is FLOOR * scale */
#define MAX_DEPTH 40         /* subdivision levels */
#define MAX_STEPS 200        /* zones visited per level */
#define POLISH_STEPS 4       /* Newton steps on the exact gap */
#define SAFE (1.0 + 0x1p-40) /* covers the rounding of reach() */
#define SHARP 0x1p-42        /* a root known to this relative width is not polished */
#define SETTLED 0x1p-50      /* a Newton step this small (relative, 4 ulps) ends the polish */

typedef struct {
    const m2c_motion *m;
    const double *p;
    int (*solver)(const double *c, int degree, double lo, double hi, double *t);
    double zero_tol;
    const double *pd;   /* two circles without orbits: the centres' difference (x0, x1, x2, y0, y1, y2) and
                           the sum of radii; the gap is then this polynomial and its scale the layout's
                           magnitude sum (NULL: the motion's gap and scale) */
    const int *ix;      /* with pd: the motion's circles table */
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

/* Two circles without orbits: the magnitude sum of the gap's terms at
 * time t, (|r1| + |r2|)^2 + Y^2 + X^2 with X = |x1| + |x2| + (|vx1| +
 * |vx2|) |t| + (|ax1| + |ax2|) t^2/2 (the value the generated scale gives
 * at t = 0 when the orbit radii are zero). */
static double still_scale(const ctx *k, double t)
{
    const int *ix = k->ix, *jx = ix + 12;
    const double *p = k->p;
    double sr = fabs(p[ix[11]]) + fabs(p[jx[11]]);
    if (t == 0.0) {            /* the same value, the terms in t being zero */
        double ax = fabs(p[ix[0]]) + fabs(p[jx[0]]), ay = fabs(p[ix[1]]) + fabs(p[jx[1]]);
        return sr * sr + ay * ay + ax * ax;
    }
    double u = fabs(t), u2 = 0.5 * u * u;
    double sx = fabs(p[ix[0]]) + fabs(p[jx[0]]) + (fabs(p[ix[2]]) + fabs(p[jx[2]])) * u +
                (fabs(p[ix[4]]) + fabs(p[jx[4]])) * u2;
    double sy = fabs(p[ix[1]]) + fabs(p[jx[1]]) + (fabs(p[ix[3]]) + fabs(p[jx[3]])) * u +
                (fabs(p[ix[5]]) + fabs(p[jx[5]])) * u2;
    return sr * sr + sy * sy + sx * sx;
}

static double floor_at(const ctx *k, double t)
{
    if (k->pd)
        return FLOOR * still_scale(k, t);
    return FLOOR * k->m->scale(k->p, t);
}

/* Two circles without orbits: the centres' distance squared minus the
 * radii's sum squared and its derivative, from the differences d (ctx.pd). */
static double still_gap(const double *d, double t)
{
    double x = (d[2] * t + d[1]) * t + d[0];
    double y = (d[5] * t + d[4]) * t + d[3];
    return y * y - d[6] * d[6] + x * x;
}

static double still_gap_dt(const double *d, double t)
{
    double x = (d[2] * t + d[1]) * t + d[0];
    double y = (d[5] * t + d[4]) * t + d[3];
    return 2.0 * (x * (2.0 * d[2] * t + d[1]) + y * (2.0 * d[5] * t + d[4]));
}

/* The exact gap and its derivative: the motion's, or for two circles
 * without orbits still_gap (k->pd). */
static double gap_at(const ctx *k, double t)
{
    return k->pd ? still_gap(k->pd, t) : k->m->gap(k->p, t);
}

static double gap_dt_at(const ctx *k, double t)
{
    return k->pd ? still_gap_dt(k->pd, t) : k->m->gap_dt(k->p, t);
}

/* ---- Two circles: the whole-horizon bound (docs/exact-motion.md) ----
 * Without its orbit a centre moves on a parabola; the orbit term moves it
 * by at most rho from there.  So the gap is positive wherever the
 * parabolas' distance exceeds the sum of radii plus both rho:
 * H(t) = |D(t)|^2 - (R + rho1 + rho2)^2 > 0, a polynomial of degree <= 4. */

/* A bound on |(sin(wx t + phx), sin(wy t + phy))| times |radius|: with
 * wx = wy the squared length is 1 - cos(A + B) cos(phx - phy) <= 1 +
 * |cos(phx - phy)| (1 for a circular orbit), else at most 2. */
static double orbit_reach(double radius, double wx, double phx, double wy, double phy)
{
    if (radius == 0.0)
        return 0.0;
    double k2 = 2.0;
    if (wx == wy)
        k2 = 1.0 + (fabs(cos(phx - phy)) + 0x1p-50 * (1.0 + fabs(phx) + fabs(phy)));
    return fabs(radius) * sqrt(k2) * SAFE;
}

/* H's coefficients h[0..4] from the circles' parameters (ix: the motion's
 * circles table), d[0..6] the differences of gap_at, *margin a bound on the
 * rounding of H on [0, T]; returns rho1 + rho2.  Without orbits (rho1 =
 * rho2 = 0) H is the exact gap, differences first. */
static double circles_bound(const int *ix, const double *p, double T, double *h, double *d, double *margin)
{
    const int *jx = ix + 12;
    double x0 = p[ix[0]] - p[jx[0]], y0 = p[ix[1]] - p[jx[1]];
    double x1 = p[ix[2]] - p[jx[2]], y1 = p[ix[3]] - p[jx[3]];
    double x2 = 0.5 * (p[ix[4]] - p[jx[4]]), y2 = 0.5 * (p[ix[5]] - p[jx[5]]);
    double rho = orbit_reach(p[ix[6]], p[ix[7]], p[ix[8]], p[ix[9]], p[ix[10]]) +
                 orbit_reach(p[jx[6]], p[jx[7]], p[jx[8]], p[jx[9]], p[jx[10]]);
    double r = fabs(p[ix[11]] + p[jx[11]]);
    double R = rho == 0.0 ? r : (r + rho) * SAFE;   /* no orbit: H is the exact gap */
    h[0] = x0 * x0 + y0 * y0 - R * R;
    h[1] = 2.0 * (x0 * x1 + y0 * y1);
    h[2] = x1 * x1 + y1 * y1 + 2.0 * (x0 * x2 + y0 * y2);
    h[3] = 2.0 * (x1 * x2 + y1 * y2);
    h[4] = x2 * x2 + y2 * y2;
    double sx = fabs(x0) + (fabs(x1) + fabs(x2) * T) * T;
    double sy = fabs(y0) + (fabs(y1) + fabs(y2) * T) * T;
    *margin = FLOOR * (sx * sx + sy * sy + R * R);
    d[0] = x0, d[1] = x1, d[2] = x2, d[3] = y0, d[4] = y1, d[5] = y2, d[6] = r;
    return rho;
}

/* Two circles: the window rate, the largest |angular velocity| of the
 * orbit terms of the bodies that orbit (radius not zero).  It is what the
 * generated rate gives for this layout (each approximation's error term is
 * its body's orbit radius times a factor, and the radius squared is one of
 * them), without its sines. */
static double circles_rate(const int *ix, const double *p)
{
    double rate = 0.0;
    for (int b = 0; b < 2; b++, ix += 12) {
        if (p[ix[6]] == 0.0)
            continue;
        double wx = fabs(p[ix[7]]), wy = fabs(p[ix[9]]);
        if (wx > rate)
            rate = wx;
        if (wy > rate)
            rate = wy;
    }
    return rate;
}

/* The first t in [lo, T] where H(t) <= 2 margin (H > margin, so the gap
 * > 0, before it), or 2 T + 1 when there is none. */
static double entry(const double *h, int n, double margin, double lo, double T)
{
    if (value(h, n, lo) <= 2.0 * margin)
        return lo;
    double q[5], r;
    for (int i = 0; i <= n; i++)
        q[i] = h[i];
    q[0] = h[0] - 2.0 * margin;
    if (m2c_smallest_root(q, n, lo, T, &r) == 1)
        return r;
    return 2.0 * T + 1.0;
}

/* How far the exact gap's root may lie from the root s of the polynomial c
 * of degree n that is within err of the gap: err / |c'(s)| (infinite where
 * c' is zero). */
static double width(const double *c, int n, double s, double err)
{
    double d = fabs(slope(c, n, s));
    return d > 0.0 ? err / d : INFINITY;
}

/* The first root of the exact gap in [t0, t0 + L] (closed: t0 counts) or
 * (t0, t0 + L]: 1 with *r, the bracket [*a, *b] it was found in and *wd
 * how far the gap's root may lie from *r, 0 for none, -1 on an error. */
static int first_root(const ctx *k, double t0, double L, int closed, int depth, double *r, double *a, double *b,
                      double *wd)
{
    double c[M2C_MAX_DEGREE + 1], q[M2C_MAX_DEGREE + 1], e = 0.0;
    int n;
    if (k->m->window) {
        n = k->m->window(k->p, t0, L, c, &e);
    } else {
        double pp[M2C_EXACT_MAX_PARAMS];
        k->m->shift(k->p, t0, pp);
        n = k->m->coefficients(pp, c);
        if (n >= 0 && n <= M2C_MAX_DEGREE)
            e = k->m->truncation(pp, L);
    }
    if (n < 0 || n > M2C_MAX_DEGREE)
        return -1;
    double f = floor_at(k, t0 + L);
    double s;
    *a = t0;
    *b = t0 + L;
    if (closed && fabs(c[0]) <= f) {
        *r = t0;
        *wd = INFINITY;
        return 1;
    }
    if (e <= f || depth >= MAX_DEPTH) {
        if (k->solver(c, n, 0.0, L, &s) != 1)
            return 0;
        *r = t0 + s;
        *wd = width(c, n, s, e + f);
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
        double w = L - z;      /* to the window's end, at most half the window */
        if (w > 0.5 * L)
            w = 0.5 * L;
        if (d != 0.0) {
            double we = 8.0 * mg / fabs(d);
            if (we < w)
                w = we;
        }
        if (!(w > 0.0))
            return 0;
        int st = first_root(k, t0 + z, w, closed || z > 0.0, depth + 1, r, a, b, wd);
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
    *wd = width(c, n, s, mg);
    return 1;
}

/* Newton steps on the exact gap, kept while |gap| decreases inside
 * [a, b] and (lo, hi]; a step of at most SETTLED times the root is taken
 * without evaluating the gap there, and ends the polish.  The driver polishes a root only when it may lie
 * more than SHARP r from the gap's (near a double root, or where the
 * rounding or truncation of its polynomial is large). */
static double polish(const ctx *k, double x, double a, double b, double lo, double hi)
{
    double g = gap_at(k, x);
    for (int i = 0; i < POLISH_STEPS; i++) {
        if (g == 0.0)
            break;
        double d = gap_dt_at(k, x);
        if (!(d != 0.0))
            break;
        double xn = x - g / d;
        if (!(xn >= a && xn <= b && xn > lo && xn <= hi))
            break;
        if (fabs(xn - x) <= SETTLED * fabs(xn)) {
            x = xn;            /* converged to rounding: the next step would be noise */
            break;
        }
        double gn = gap_at(k, xn);
        if (!(fabs(gn) < fabs(g)))
            break;
        x = xn;
        g = gn;
    }
    return x;
}

/* polish for two circles without orbits over [a, b] = [lo, hi]: the same
 * steps on still_gap, called directly. */
static double still_polish(const double *d, double x, double lo, double hi)
{
    double g = still_gap(d, x);
    for (int i = 0; i < POLISH_STEPS; i++) {
        if (g == 0.0)
            break;
        double dg = still_gap_dt(d, x);
        if (!(dg != 0.0))
            break;
        double xn = x - g / dg;
        if (!(xn > lo && xn <= hi))
            break;
        if (fabs(xn - x) <= SETTLED * fabs(xn)) {
            x = xn;
            break;
        }
        double gn = still_gap(d, xn);
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
        if (fabs(gap_at(k, tau)) > 2.0 * band)
            return tau;
        tau = 2.0 * tau;
    }
    return horizon;
}

/* No parameter is an infinity or a NaN.  Their sum is finite only then,
 * unless finite parameters overflow it: then each is tested (x * 0 is 0
 * for every finite x, else NaN). */
static int all_finite(const double *p, int n)
{
    double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
    int i = 0;
    for (; i + 3 < n; i += 4) {
        s0 += p[i];
        s1 += p[i + 1];
        s2 += p[i + 2];
        s3 += p[i + 3];
    }
    for (; i < n; i++)
        s0 += p[i];
    if (isfinite((s0 + s1) + (s2 + s3)))
        return 1;
    for (i = 0; i < n; i++)
        if (!(p[i] * 0.0 == 0.0))
            return 0;
    return 1;
}

/* The checks and the rules at t = 0 shared by m2c_exact_toc and
 * m2c_exact_poly_toc: -1 an error, 0 none, 1 a contact at 0,
 * M2C_EXACT_OVERLAPPED, or 3 with *start (0, or where a separating contact
 * at 0 has left the zero band): search (*start, horizon].  clear0 is a
 * lower bound on the exact gap at t = 0 (-INFINITY when none is known):
 * above twice the band the computed gap, within the floor (at most the
 * band) of the exact one, is above the band, so the rules answer search
 * from 0 without evaluating it. */
#define SEARCH 3
static int begin(const ctx *k, const m2c_exact_options *o, double horizon, double clear0, double *start, double *t)
{
    const m2c_motion *m = k->m;
    if (!(o->window_angle > 0.0 && o->window_angle <= DBL_MAX) || !o->solver || !(o->zero_tol >= 0.0))
        return -1;
    if (!(horizon > 0.0 && horizon <= DBL_MAX))
        return 0;
    if (!all_finite(k->p, m->nparams))
        return 0;
    *start = 0.0;
    double band0 = floor_at(k, 0.0);
    if (o->zero_tol > band0)
        band0 = o->zero_tol;
    if (clear0 > 2.0 * band0)
        return SEARCH;
    double g0 = gap_at(k, 0.0);
    if (g0 < -band0) {          /* inside each other at t = 0: not a contact, its own answer */
        *t = 0.0;
        return M2C_EXACT_OVERLAPPED;
    }
    if (fabs(g0) <= band0) {
        double d0 = gap_dt_at(k, 0.0);
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

/* The polynomial c of degree n is the exact gap: its smallest root in
 * (start, horizon], polished (PolyContact). */
static int poly_search(const ctx *k, const double *c, int n, double start, double horizon, int refine, double *t)
{
    double r;
    if (k->solver(c, n, start, horizon, &r) != 1)
        return 0;
    if (refine)
        r = polish(k, r, start, horizon, start, horizon);
    if (r > horizon)
        r = horizon;
    *t = r + 0.0;
    return 1;
}

/* Two circles without orbits: their gap is the polynomial H of
 * circles_bound (rho1 = rho2 = 0: exact up to its margin), solved once
 * over (start, horizon]; the root is polished on the gap only when its
 * width under that margin exceeds SHARP r.  The checks and rules at t = 0
 * are begin's, with the gap and the scale at 0 read from the differences
 * directly (the values gap_at and floor_at give: at t = 0 the terms in t
 * are zero); begin itself answers only a touch at 0.  The parameters'
 * finiteness decides only an answer other than none (a non-finite one
 * makes every answer none), so it is tested only before such an answer;
 * the margin is computed only for a root. */
static int still_circles(const m2c_motion *m, const double *p, double horizon, const m2c_exact_options *o,
                         double *t)
{
    if (!(o->window_angle > 0.0 && o->window_angle <= DBL_MAX) || !o->solver || !(o->zero_tol >= 0.0))
        return -1;
    if (!(horizon > 0.0 && horizon <= DBL_MAX))
        return 0;
    const int *ix = m->circles, *jx = ix + 12;
    double x0 = p[ix[0]] - p[jx[0]], y0 = p[ix[1]] - p[jx[1]];
    double x1 = p[ix[2]] - p[jx[2]], y1 = p[ix[3]] - p[jx[3]];
    double x2 = 0.5 * (p[ix[4]] - p[jx[4]]), y2 = 0.5 * (p[ix[5]] - p[jx[5]]);
    double r = fabs(p[ix[11]] + p[jx[11]]);
    double h[5], d[7], start = 0.0, s;
    h[0] = x0 * x0 + y0 * y0 - r * r;
    h[1] = 2.0 * (x0 * x1 + y0 * y1);
    h[2] = x1 * x1 + y1 * y1 + 2.0 * (x0 * x2 + y0 * y2);
    h[3] = 2.0 * (x1 * x2 + y1 * y2);
    h[4] = x2 * x2 + y2 * y2;
    double sr = fabs(p[ix[11]]) + fabs(p[jx[11]]);
    double ax = fabs(p[ix[0]]) + fabs(p[jx[0]]), ay = fabs(p[ix[1]]) + fabs(p[jx[1]]);
    double band0 = FLOOR * (sr * sr + ay * ay + ax * ax);
    if (o->zero_tol > band0)
        band0 = o->zero_tol;
    double g0 = y0 * y0 - r * r + x0 * x0;
    if (g0 < -band0) {          /* inside each other at t = 0: not a contact, its own answer */
        if (!all_finite(p, m->nparams))
            return 0;
        *t = 0.0;
        return M2C_EXACT_OVERLAPPED;
    }
    if (fabs(g0) <= band0) {    /* touching at t = 0 */
        d[0] = x0, d[1] = x1, d[2] = x2, d[3] = y0, d[4] = y1, d[5] = y2, d[6] = r;
        ctx k = {m, p, o->solver, o->zero_tol, d, ix};
        int st0 = begin(&k, o, horizon, -INFINITY, &start, t);
        if (st0 != SEARCH)
            return st0;
    }
    int n = h[4] != 0.0 ? 4 : h[3] != 0.0 ? 3 : h[2] != 0.0 ? 2 : h[1] != 0.0 ? 1 : 0;
    int found = o->solver == m2c_smallest_root ? m2c_smallest_root(h, n, start, horizon, &s)
                                               : o->solver(h, n, start, horizon, &s);
    if (found != 1 || !all_finite(p, m->nparams))
        return 0;
    if (o->refine) {
        double sx = fabs(x0) + (fabs(x1) + fabs(x2) * horizon) * horizon;
        double sy = fabs(y0) + (fabs(y1) + fabs(y2) * horizon) * horizon;
        double margin = FLOOR * (sx * sx + sy * sy + r * r);
        if (!(width(h, n, s, margin) <= SHARP * s)) {
            d[0] = x0, d[1] = x1, d[2] = x2, d[3] = y0, d[4] = y1, d[5] = y2, d[6] = r;
            s = still_polish(d, s, start, horizon);
        }
    }
    if (s > horizon)
        s = horizon;
    *t = s + 0.0;
    return 1;
}

static const m2c_exact_options DEFAULTS = {M2C_EXACT_ANGLE, 1, 0.0, m2c_smallest_root};

int m2c_exact_toc(const m2c_motion *m, const double *p, double horizon, const m2c_exact_options *options,
                  double *t)
{
    if (!m || !p || !t || m->nparams < 0 || m->nparams > M2C_EXACT_MAX_PARAMS || m->max_degree > M2C_MAX_DEGREE)
        return -1;
    if (m->circles && p[m->circles[6]] == 0.0 && p[m->circles[18]] == 0.0)
        return still_circles(m, p, horizon, options ? options : &DEFAULTS, t);    /* no orbit: no windows */
    m2c_exact_options o = options ? *options : DEFAULTS;
    ctx k = {m, p, o.solver, o.zero_tol, 0, 0};
    double hb[5], pd[7], mb = 0.0, clear0 = -INFINITY;
    int nb = 0, bound = 0;
    if (m->circles) {          /* (non-finite parameters or horizon: begin answers before any use) */
        bound = 1;
        double rho = circles_bound(m->circles, p, horizon, hb, pd, &mb);
        nb = 4;
        while (nb > 0 && hb[nb] == 0.0)
            nb--;
        /* at t = 0 the centres are |D| apart without their orbits, each orbit
         * offset at most its rho: the gap is at least (|D| - rho)^2 - R^2,
         * |D| rounded down and the square and R^2 by 2^-40 against the
         * roundings */
        double dist = sqrt(pd[0] * pd[0] + pd[3] * pd[3]) * (1.0 - 0x1p-40);
        if (dist > rho) {
            double s = dist - rho;
            clear0 = s * s * (1.0 - 0x1p-40) - pd[6] * pd[6] * (1.0 + 0x1p-40);
        }
    }
    double start;
    int st0 = begin(&k, &o, horizon, clear0, &start, t);
    if (st0 != SEARCH)
        return st0;
    double e = bound ? entry(hb, nb, mb, start, horizon) : start;
    if (!(e <= horizon))
        return 0;              /* the bound keeps the circles apart over the whole horizon */
    double span = horizon - start;
    double h = span;
    double rate = bound ? circles_rate(m->circles, p) : m->rate(p);
    if (rate > 0.0 && o.window_angle / rate < span)
        h = o.window_angle / rate;
    if (span / h > M2C_EXACT_MAX_WINDOWS)
        return -1;
    double w = 0.0, t0 = start;
    for (;;) {
        if (e > t0) {          /* skip the windows that end before the bound's zone */
            double wj = floor((e - start) / h);
            if (wj > 0.0 && start + wj * h > e)
                wj -= 1.0;
            if (wj > w) {
                w = wj;
                t0 = start + w * h;
            }
        }
        if (!(t0 < horizon))
            return 0;
        double t1 = start + (w + 1.0) * h;
        if (!(t1 < horizon))
            t1 = horizon;
        double L = t1 - t0;
        double r, a, b, wd;
        int st;
        if (o.refine) {
            st = first_root(&k, t0, L, w > 0.0, 0, &r, &a, &b, &wd);
            if (st == 1 && !(wd <= SHARP * r))
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
        w += 1.0;
        if (bound && t0 < horizon) {
            e = entry(hb, nb, mb, t0, horizon);
            if (!(e <= horizon))
                return 0;
        }
    }
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
    m2c_motion m = {pm->nparams, pm->max_degree, pm->coefficients, 0, pm->gap, pm->gap_dt, pm->scale, 0, 0, 0, 0};
    ctx k = {&m, p, o.solver, o.zero_tol, 0, 0};
    double start;
    int st0 = begin(&k, &o, horizon, -INFINITY, &start, t);
    if (st0 != SEARCH)
        return st0;
    double c[M2C_MAX_DEGREE + 1];
    int n = m.coefficients(p, c);
    if (n < 0 || n > M2C_MAX_DEGREE)
        return -1;
    return poly_search(&k, c, n, start, horizon, o.refine, t);
}
