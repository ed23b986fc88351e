/* Predictions (docs/simulator.md): the first contact of a pair after now,
 * or a horizon event where the Taylor polynomials of its turns stop being
 * good, and a body's next cell crossing.  Every prediction goes through
 * the generated entries of equations/circle-circle.mxm and
 * equations/point-edge.mxm (m2c_sim_equations.h) and through
 * m2c_smallest_root.  Every floating-point expression is written as the
 * Python reference (runtimes/python/max2code_rt) evaluates it, left
 * to right with the same parentheses, compiled with -ffp-contract=off, so
 * the trace has the same bytes.  Units: s, m, m/s, m/s^2, rad, rad/s. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_roots.h"
#include "m2c_sim_equations.h"
#include "m2c_sim_internal.h"

#define HALF_PI 1.5707963267948966      /* rad: pi/2 rounded to double (cos x = sin(x + pi/2)) */

/* the most stages (a meeting of the bounds, a clear stretch, a Taylor window)
 * one prediction of a pair goes through before it leaves the rest to a horizon */
enum { CHAIN = 8 };

/* ---- first valid root of one feature ---------------------------------------- */

/* What point_edge's contact must satisfy: the point lies on the segment. */
typedef struct pe_check {
    m2c_world *m;
    const m2c_sim_body *X, *Y;
    const m2c_sim_vertex *vx;           /* X's vertex (its cos, sin cache), else NULL */
    double rho, beta;                   /* m, rad: the point about X's centre (0: the centre) */
    const m2c_sim_vertex *ed;           /* the edge of Y */
    double now, tol;                    /* s, m */
} pe_check;

/* A neighbour of X's vertex i at t lies more than the tolerance behind the
 * line (c, sn) . (p - (qx, qy)) = h (an edge's line: its outward unit normal
 * (c, sn), its body's centre (qx, qy)), previous neighbour first
 * (docs/simulator.md, "Corners"). */
static int behind(m2c_world *m, const m2c_sim_body *X, int32_t i, double t, double qx, double qy, double c, double sn,
                  double h)
{
    int32_t n = X->nverts;
    m2c_sim_motion p = m2c_sim_state_at(X, t);
    double lim = -m->s->tol;
    const int32_t ks[2] = { (i + n - 1) % n, (i + 1) % n };
    for (int l = 0; l < 2; l++) {
        const m2c_sim_vertex *v = &X->verts[ks[l]];
        double vc, vs;
        m2c_sim_cos_sin(M2C_SIM_VTRIG(m, v), p.ang + v->beta, &vc, &vs);
        double kx = p.x + v->rho * vc;
        double ky = p.y + v->rho * vs;
        if ((kx - qx) * c + (ky - qy) * sn - h < lim)
            return 1;
    }
    return 0;
}

/* The point lies on the edge's segment at now + s; when it is X's vertex
 * (vx), neither neighbour of that vertex lies behind the edge's line
 * (behind: else a corner meets a corner, another feature pair's contact). */
static int inside(const pe_check *k, double s)
{
    if (k == NULL)
        return 1;
    double t = k->now + s;
    m2c_sim_motion p = m2c_sim_state_at(k->X, t);
    double px = p.x, py = p.y;
    if (k->rho != 0.0) {
        double pc, ps;
        if (k->vx != NULL) {
            m2c_sim_cos_sin(M2C_SIM_VTRIG(k->m, k->vx), p.ang + k->beta, &pc, &ps);
        } else {
            pc = cos(p.ang + k->beta);
            ps = sin(p.ang + k->beta);
        }
        px = px + k->rho * pc;
        py = py + k->rho * ps;
    }
    m2c_sim_motion q = m2c_sim_state_at(k->Y, t);
    double c, sn;
    m2c_sim_cos_sin(M2C_SIM_ETRIG(k->m, k->ed), q.ang + k->ed->psi, &c, &sn);
    double along = (px - q.x) * -sn + (py - q.y) * c;
    if (!(k->ed->s1 - k->tol <= along && along <= k->ed->s2 + k->tol))
        return 0;
    if (k->vx == NULL)
        return 1;
    return !behind(k->m, k->X, (int32_t)(k->vx - k->X->verts), t, q.x, q.y, c, sn, k->ed->h);
}

/* At a zero s of the gap c whose first derivative there is d: approaching
 * (d < 0), or resting and pressed together (d == 0, second derivative < 0). */
static int pressing(const double *c, int deg, double d, double s)
{
    if (d < 0.0)
        return 1;
    if (d != 0.0 || deg < 2)
        return 0;
    double dd = 0.0;
    for (int k = deg; k > 1; k--)
        dd = dd * s + (double)(k * (k - 1)) * c[k];
    return dd < 0.0;
}

/* At s = 0, with the gap zero within kappa: approaching (c1 < 0), or
 * pressed together (c2 < 0) so that the gap closes again before it ever
 * exceeds kappa: its largest value c0 + c1^2 / (4 |c2|) <= kappa.  (A
 * resting body's c1 is zero up to rounding: cos(pi/2) is 6e-17.) */
int m2c_sim_touching_now(const double *c, int deg, double kappa)
{
    if (c[1] < 0.0)
        return 1;
    if (deg < 2 || !(c[2] < 0.0))
        return 0;
    return c[0] + c[1] * c[1] / (4.0 * -c[2]) <= kappa;
}

/* The smallest s in [0, w] (s) where the gap c(s) reaches zero while
 * decreasing, or touches zero with zero slope while pressed together
 * (resting contact), and the check holds.  At s = 0 the gap counts as zero
 * within kappa: approaching or pressed (touching_now) means contact now,
 * separating or merely touching never. */
static int first_contact(const double *c, int deg, double w, double kappa, const pe_check *chk, double *out)
{
    if (deg >= 1 && fabs(c[0]) <= kappa && m2c_sim_touching_now(c, deg, kappa) && inside(chk, 0.0)) {
        *out = 0.0;
        return 1;
    }
    double lo = 0.0;
    for (int it = 0; it < deg + 2; it++) {
        double s;
        if (m2c_smallest_root(c, deg, lo, w, &s) != 1)
            return 0;
        double d = 0.0;
        for (int k = deg; k > 0; k--)
            d = d * s + (double)k * c[k];
        if (pressing(c, deg, d, s) && inside(chk, s)) {
            *out = s;
            return 1;
        }
        lo = s;
    }
    return 0;
}

/* ---- features --------------------------------------------------------------- */

/* Counts a circle_circle prediction of these 24 parameters: its variant
 * and the features counter. */
static inline __attribute__((always_inline)) void cc_count(m2c_world *m, const double *g)
{
    int idx = circle_circle_variant(g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], g[9], g[10], g[11],
                                    g[12], g[13], g[14], g[15], g[16], g[17], g[18], g[19], g[20], g[21], g[22],
                                    g[23]);
    if (idx < 0)
        m2c_sim_die(m, "circle_circle: the scene uses an effect the generated code leaves out");
    if (idx >= m->n_cc)
        m2c_sim_die(m, "circle_circle: variant %d, but the build counts %d variants", idx, m->n_cc);
    m->cc_counts[idx]++;
    m->stats.features++;
}

/* circle_circle's coefficients for these 24 parameters; counts the variant. */
static int cc_coefficients(m2c_world *m, const double *g, double *coef)
{
    cc_count(m, g);
    return circle_circle_coefficients(g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], g[9], g[10], g[11],
                                      g[12], g[13], g[14], g[15], g[16], g[17], g[18], g[19], g[20], g[21],
                                      g[22], g[23], coef);
}

/* circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
 * circle's centre (v NULL) or of a polygon's vertex, at time now. */
void m2c_sim_circle_params(m2c_world *m, const m2c_sim_body *b, double now, const m2c_sim_vertex *v, double *o)
{
    m2c_sim_motion q = m2c_sim_state_at(b, now);
    double x = q.x, y = q.y, d, phase;
    if (v == NULL) {
        d = b->orbit;
        phase = q.ang + b->ophase;
    } else {
        d = v->rho;
        phase = q.ang + v->beta;
    }
    double om = b->om;
    if (om == 0.0 && d != 0.0) {
        /* an orbit that does not turn is a fixed offset: fold it in */
        double c, sn;
        if (v != NULL) {
            m2c_sim_cos_sin(M2C_SIM_VTRIG(m, v), phase, &c, &sn);
        } else {
            c = cos(phase);
            sn = sin(phase);
        }
        x = x + d * c;
        y = y + d * sn;
        d = 0.0;
    }
    if (d == 0.0) {
        om = 0.0;
        phase = 0.0;
    }
    o[0] = x;
    o[1] = q.vx;
    o[2] = b->ax;
    o[3] = d;
    o[4] = om;
    o[5] = phase + HALF_PI;
    o[6] = y;
    o[7] = q.vy;
    o[8] = b->ay;
    o[9] = om;
    o[10] = phase;
}

/* circle_circle parameters of b's centre of rotation at time now, no
 * orbit: the centre of a bounding circle (circle_params of a polygon). */
static void centre_params(const m2c_sim_body *b, double now, double *o)
{
    m2c_sim_motion q = m2c_sim_state_at(b, now);
    o[0] = q.x;
    o[1] = q.vx;
    o[2] = b->ax;
    o[3] = 0.0;
    o[4] = 0.0;
    o[5] = HALF_PI;
    o[6] = q.y;
    o[7] = q.vy;
    o[8] = b->ay;
    o[9] = 0.0;
    o[10] = 0.0;
}

/* circle_circle's 24 parameters (g) of a circle of radius ra moving as p1
 * (circle_params) and one of radius rb moving as p2: only differences of
 * the centres' motions matter, circle 1 moves relative to circle 2's
 * centre of rotation. */
static void cc_args(const double *p1, double ra, const double *p2, double rb, double *g)
{
    g[0] = p1[0] - p2[0];
    g[1] = p1[1] - p2[1];
    g[2] = p1[2] - p2[2];
    g[3] = p1[3];
    g[4] = p1[4];
    g[5] = p1[5];
    g[6] = p1[6] - p2[6];
    g[7] = p1[7] - p2[7];
    g[8] = p1[8] - p2[8];
    g[9] = p1[9];
    g[10] = p1[10];
    g[11] = 0.0;
    g[12] = 0.0;
    g[13] = 0.0;
    g[14] = p2[3];
    g[15] = p2[4];
    g[16] = p2[5];
    g[17] = 0.0;
    g[18] = 0.0;
    g[19] = 0.0;
    g[20] = p2[9];
    g[21] = p2[10];
    g[22] = ra;
    g[23] = rb;
}

/* The circle_circle polynomial (its degree; the squared distance of the
 * centres less (ra + rb)^2, in s from the parameters' time) of a circle of
 * radius ra moving as p1 (circle_params) and one of radius rb moving as p2. */
int m2c_sim_circles_gap(m2c_world *m, const double *p1, double ra, const double *p2, double rb, double *coef)
{
    double g[24];
    cc_args(p1, ra, p2, rb, g);
    return cc_coefficients(m, g, coef);
}

/* The pair of circles_gap's parameters g surely has no contact, decided
 * without the polynomial (docs/simulator.md, "Pairs that stay apart"):
 * neither circle orbits and their relative acceleration is zero, so the gap
 * is |p + v s|^2 - R^2 (p, v: the relative position and velocity, R = ra +
 * rb), and either the centres separate (p . v > 0 by more than its
 * rounding: the generated c1 = 2 p.v is then positive, c2 = |v|^2 is never
 * negative, and first_contact finds no approach), or they approach on a
 * line that passes farther than R from each other: (p x v)^2 > (R^2 +
 * kappa) |v|^2 by more than the rounding (then the gap now exceeds kappa and
 * its discriminant is clearly negative: no root).  The margins (2^-40 and
 * 2^-30 of the terms' size) are far above the few units of 2^-53 by which
 * the coefficients can be off, and the sizes are bounded so that nothing
 * underflows (where rounding is no longer relative: a speed of 1e-162 m/s
 * squares to 0) or overflows.  The prediction is still counted. */
static int circles_apart(const double *g, double kappa)
{
    if (g[2] != 0.0 || g[8] != 0.0 || g[3] != 0.0 || g[14] != 0.0)
        return 0;
    double x = g[0], vx = g[1], y = g[6], vy = g[7];
    double px = x * vx, py = y * vy;
    double size = fabs(px) + fabs(py);
    if (size >= 0x1p-900 && px + py > 0x1p-40 * size)
        return 1;
    double r = g[22] + g[23];
    double v2 = vx * vx + vy * vy, p2 = x * x + y * y;
    if (!(v2 >= 0x1p-450 && v2 <= 0x1p450 && p2 >= 0x1p-450 && p2 <= 0x1p450))
        return 0;
    double cross = x * vy - y * vx;
    return cross * cross - (r * r + kappa) * v2 > 0x1p-30 * p2 * v2;
}

/* The first contact within [0, w] (1 with *out, else 0) of a circle of
 * radius ra moving as p1 (circle_params) and one of radius rb moving as p2. */
static inline __attribute__((always_inline)) int circles_first_args(m2c_world *m, const double *g, double w,
                                                                    double *out)
{
    double tol = m->s->tol;
    double kappa = tol * (2.0 * (g[22] + g[23]) + tol);
    if (circles_apart(g, kappa)) {
        cc_count(m, g);
        return 0;
    }
    double coef[M2C_MAX_DEGREE + 1];
    int deg = cc_coefficients(m, g, coef);
    return first_contact(coef, deg, w, kappa, NULL, out);
}

static int circles_first(m2c_world *m, const double *p1, double ra, const double *p2, double rb, double w,
                         double *out)
{
    double g[24];
    cc_args(p1, ra, p2, rb, g);
    return circles_first_args(m, g, w, out);
}

/* predict_cc of two circles that do not orbit (orbit 0: neither turns),
 * with circle_params' values written out: the same 24 parameters, bit for
 * bit (d = 0 sets the turn and the phase to 0), without its branches and
 * copies.  Most pairs of a gas are such. */
static int circles_plain(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w,
                         double *out)
{
    m2c_sim_motion qa = m2c_sim_state_at(A, now), qb = m2c_sim_state_at(B, now);
    const double g[24] = { qa.x - qb.x, qa.vx - qb.vx, A->ax - B->ax, A->orbit, 0.0, HALF_PI,
                           qa.y - qb.y, qa.vy - qb.vy, A->ay - B->ay, 0.0, 0.0,
                           0.0, 0.0, 0.0, B->orbit, 0.0, HALF_PI, 0.0, 0.0, 0.0, 0.0, 0.0,
                           A->r, B->r };
    return circles_first_args(m, g, w, out);
}

/* Circle of A against circle of B (vb NULL, radius rb) or vertex vb of B (rb 0). */
static int predict_cc(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, const m2c_sim_vertex *vb, double rb,
                      double now, double w, double *out)
{
    double p1[11], p2[11];
    m2c_sim_circle_params(m, A, now, NULL, p1);
    m2c_sim_circle_params(m, B, now, vb, p2);
    return circles_first(m, p1, A->r, p2, rb, w, out);
}

/* The point_edge polynomial (its degree; coef[0]: the gap now) of a circle
 * of radius rad whose centre orbits X's centre at rho (phase beta in X's
 * frame) against the line of edge j of Y, in s = t - now. */
int m2c_sim_pe_coefficients(m2c_world *m, const m2c_sim_body *X, const m2c_sim_body *Y, double rho, double beta,
                            double rad, int32_t j, double now, double *coef)
{
    const m2c_sim_vertex *ed = &Y->verts[j];
    m2c_sim_motion q1 = m2c_sim_state_at(X, now);
    m2c_sim_motion q2 = m2c_sim_state_at(Y, now);
    double phn = q2.ang + ed->psi;
    double wr = X->om - Y->om;
    double phr = (q1.ang + beta) - phn;
    double h = ed->h + rad;
    if (wr == 0.0 && rho != 0.0) {
        /* the point does not turn relative to the edge: its offset along
         * the normal is a constant, folded into the line's offset */
        h = h - rho * cos(phr);
        rho = 0.0;
    }
    double px = q1.x - q2.x, u = q1.vx - q2.vx, ax = X->ax - Y->ax;
    double py = q1.y - q2.y, v = q1.vy - q2.vy, ay = X->ay - Y->ay;
    int idx = point_edge_variant(px, u, ax, py, v, ay, rho, wr, phr, Y->om, phn, h);
    if (idx < 0)
        m2c_sim_die(m, "point_edge: the scene uses an effect the generated code leaves out");
    if (idx >= m->n_pe)
        m2c_sim_die(m, "point_edge: variant %d, but the build counts %d variants", idx, m->n_pe);
    m->pe_counts[idx]++;
    m->stats.features++;
    return point_edge_coefficients(px, u, ax, py, v, ay, rho, wr, phr, Y->om, phn, h, coef);
}

/* The first contact within [0, w] (1 with *out, else 0) of pe_coefficients'
 * polynomial whose point (X's centre, or rho, beta about it; vx: X's vertex
 * for its cos, sin cache, else NULL) lies on edge j's segment. */
static int pe_first(m2c_world *m, const double *coef, int deg, const m2c_sim_body *X, const m2c_sim_body *Y,
                    const m2c_sim_vertex *vx, double rho, double beta, int32_t j, double now, double w, double *out)
{
    pe_check chk = { m, X, Y, vx, rho, beta, &Y->verts[j], now, m->s->tol };
    return first_contact(coef, deg, w, m->s->tol, &chk, out);
}

/* Point of X (circle centre with its radius, or vertex vx) against the line
 * of edge j of Y (none while a fixed body covers the edge: its cover is not
 * gone). */
static int predict_pe(m2c_world *m, const m2c_sim_body *X, const m2c_sim_body *Y, const m2c_sim_vertex *vx, int32_t j,
                      double now, double w, double *out)
{
    int32_t cover = Y->verts[j].cover;
    if (cover >= 0 && !m->bodies[cover].gone)
        return 0;
    double rho, beta, rad;
    if (vx == NULL) {
        rho = X->orbit;
        beta = X->ophase;
        rad = X->r;
    } else {
        rho = vx->rho;
        beta = vx->beta;
        rad = 0.0;
    }
    double coef[M2C_MAX_DEGREE + 1];
    int deg = m2c_sim_pe_coefficients(m, X, Y, rho, beta, rad, j, now, coef);
    return pe_first(m, coef, deg, X, Y, vx, rho, beta, j, now, w, out);
}

/* ---- pairs ------------------------------------------------------------------ */

/* The earliest contact found so far in one pair. */
typedef struct best {
    int have;
    double s;                           /* s after now */
    int32_t feat, a, b, i, j;
} best;

static inline void better(best *bs, int found, double t, int32_t feat, int32_t a, int32_t b, int32_t i, int32_t j)
{
    if (found && (!bs->have || t < bs->s)) {
        bs->have = 1;
        bs->s = t;
        bs->feat = feat;
        bs->a = a;
        bs->b = b;
        bs->i = i;
        bs->j = j;
    }
}

/* When the bounding circles first touch within (0, w] (s after now): 1 with
 * *meet = 0 when they overlap or touch now (within the tolerance), 1 with
 * the time when they touch later, 0 when they do not meet (exact: bounding
 * circles do not turn). */
static int bounds_meet(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, double *meet)
{
    m2c_sim_motion q1 = m2c_sim_state_at(A, now);
    m2c_sim_motion q2 = m2c_sim_state_at(B, now);
    double g[24] = { q1.x - q2.x, q1.vx - q2.vx, A->ax - B->ax, 0.0, 0.0, HALF_PI,
                     q1.y - q2.y, q1.vy - q2.vy, A->ay - B->ay, 0.0, 0.0,
                     0.0, 0.0, 0.0, 0.0, 0.0, HALF_PI, 0.0, 0.0, 0.0, 0.0, 0.0, A->bound, B->bound };
    double coef[M2C_MAX_DEGREE + 1];
    int deg = cc_coefficients(m, g, coef);
    double tol = m->s->tol;
    if (coef[0] <= tol * (2.0 * (A->bound + B->bound) + tol)) {
        *meet = 0.0;
        return 1;
    }
    return m2c_smallest_root(coef, deg, 0.0, w, meet) == 1;
}

/* T turns, polygon P does not: when T's bounding circle (radius T->bound
 * about T's centre of rotation, which does not turn) first touches P itself
 * (its edges, then its vertices) within (0, w]: 1 with *meet = 0 when no
 * edge line of P has the circle beyond it by more than the tolerance now
 * (overlapping, or near a corner), 1 with the time when it touches later,
 * 0 when they do not meet.  Exact: neither the circle nor P turns. */
static int bound_polygon(m2c_world *m, const m2c_sim_body *T, const m2c_sim_body *P, double now, double w,
                         double *meet)
{
    enum { ROW = M2C_MAX_DEGREE + 1 };
    double tol = m->s->tol;
    int32_t n = P->nverts;
    if ((size_t)n > m->scratch_cap) {
        /* every edge's polynomial is kept until the overlap test has seen them all */
        double *more = realloc(m->scratch, (size_t)n * ROW * sizeof *more);
        if (more != NULL)
            m->scratch = more;
        int *degs = realloc(m->scratch_deg, (size_t)n * sizeof *degs);
        if (degs != NULL)
            m->scratch_deg = degs;
        if (more == NULL || degs == NULL)
            m2c_sim_die(m, "out of memory (bound_polygon)");
        m->scratch_cap = (size_t)n;
    }
    double *coefs = m->scratch;
    int *deg = m->scratch_deg;
    int apart = 0;
    for (int32_t j = 0; j < n; j++) {
        deg[j] = m2c_sim_pe_coefficients(m, T, P, 0.0, 0.0, T->bound, j, now, &coefs[(size_t)j * ROW]);
        if (coefs[(size_t)j * ROW] > tol)
            apart = 1;
    }
    if (!apart) {
        *meet = 0.0;
        return 1;
    }
    int have = 0;
    double best = 0.0, t = 0.0;
    for (int32_t j = 0; j < n; j++) {
        if (pe_first(m, &coefs[(size_t)j * ROW], deg[j], T, P, NULL, 0.0, 0.0, j, now, w, &t)
            && (!have || t < best)) {
            have = 1;
            best = t;
        }
    }
    double pt[11], pv[11];
    centre_params(T, now, pt);
    for (int32_t k = 0; k < n; k++) {
        m2c_sim_circle_params(m, P, now, &P->verts[k], pv);
        if (circles_first(m, pt, T->bound, pv, 0.0, w, &t) && (!have || t < best)) {
            have = 1;
            best = t;
        }
    }
    *meet = best;
    return have;
}

static void circle_polygon(m2c_world *m, const m2c_sim_body *C, const m2c_sim_body *P, double now, double w, best *bs)
{
    double t = 0.0;
    for (int32_t j = 0; j < P->nverts; j++) {
        int found = predict_pe(m, C, P, NULL, j, now, w, &t);
        better(bs, found, t, M2C_SIM_PE, C->idx, P->idx, -1, j);
    }
    for (int32_t k = 0; k < P->nverts; k++) {
        int found = predict_cc(m, C, P, &P->verts[k], 0.0, now, w, &t);
        better(bs, found, t, M2C_SIM_CC, C->idx, P->idx, -1, k);
    }
}

static void vertices_edges(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, best *bs)
{
    double t = 0.0;
    for (int32_t i = 0; i < A->nverts; i++) {
        for (int32_t j = 0; j < B->nverts; j++) {
            int found = predict_pe(m, A, B, &A->verts[i], j, now, w, &t);
            better(bs, found, t, M2C_SIM_PE, A->idx, B->idx, i, j);
        }
    }
}

/* The positive root of q/2 s^2 + r s - g (q >= 0), for g > 0, else 0;
 * +inf when it has none (r <= 0 and q = 0). */
static double clear_root(double g, double r, double q)
{
    if (!(g > 0.0))
        return 0.0;
    if (r > 0.0)
        return 2.0 * g / (r + sqrt(r * r + 2.0 * q * g));
    if (q > 0.0)
        return (sqrt(r * r + 2.0 * q * g) - r) / q;
    return INFINITY;
}

/* The largest projection of b on the unit axis (nx, ny) at now (m). */
static double reach(m2c_world *m, const m2c_sim_body *b, double nx, double ny, double now)
{
    double px, py;
    if (!b->polygon) {
        m2c_sim_point_at(m, b, NULL, now, &px, &py);
        return nx * px + ny * py + b->r;
    }
    double best = -INFINITY;
    for (int32_t k = 0; k < b->nverts; k++) {
        m2c_sim_point_at(m, b, &b->verts[k], now, &px, &py);
        best = m2c_sim_max(best, nx * px + ny * py);
    }
    return best;
}

/* clear_time along each edge normal of P (P does not turn, T does). */
static double clear_axes(m2c_world *m, const m2c_sim_body *T, const m2c_sim_body *P, double now)
{
    m2c_sim_motion q1 = m2c_sim_state_at(T, now);
    m2c_sim_motion q2 = m2c_sim_state_at(P, now);
    double du = q1.vx - q2.vx, dv = q1.vy - q2.vy, dax = T->ax - P->ax, day = T->ay - P->ay;
    double spin = T->bound * m2c_sim_turn_rate(T);
    double best = 0.0;
    for (int32_t j = 0; j < P->nverts; j++) {
        double ox, oy, off;
        m2c_sim_edge_line(P, j, now, &ox, &oy, &off);
        double c = clear_root(-reach(m, T, -ox, -oy, now) - off - m->s->tol, spin - (ox * du + oy * dv),
                              fabs(ox * dax + oy * day));
        best = m2c_sim_max(best, c);
    }
    return best;
}

/* How long (s) A and B surely stay more than the tolerance apart, from
 * their gap along a fixed unit axis now (0 when not apart now): each edge
 * normal of a polygon that does not turn against a body that does
 * (clear_axes), else the line of the centres and, with the norms |x| + |y|,
 * the best separating axis (docs/simulator.md, "Clear stretches"). */
static double clear_time(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double now)
{
    if (B->polygon && B->om == 0.0 && m2c_sim_turn_rate(A) > 0.0)
        return clear_axes(m, A, B, now);
    if (A->polygon && A->om == 0.0 && m2c_sim_turn_rate(B) > 0.0)
        return clear_axes(m, B, A, now);
    m2c_sim_motion q1 = m2c_sim_state_at(A, now);
    m2c_sim_motion q2 = m2c_sim_state_at(B, now);
    double dx = q2.x - q1.x, dy = q2.y - q1.y;
    double d = sqrt(dx * dx + dy * dy);
    if (!(d > 0.0))
        return 0.0;
    double nx = dx / d, ny = dy / d;
    double hi = reach(m, A, nx, ny, now);
    double lo = -reach(m, B, -nx, -ny, now);
    double spin = A->bound * m2c_sim_turn_rate(A) + B->bound * m2c_sim_turn_rate(B);
    double tol = m->s->tol;
    double along = clear_root(lo - hi - tol, spin - (nx * (q2.vx - q1.vx) + ny * (q2.vy - q1.vy)),
                              fabs(nx * (B->ax - A->ax) + ny * (B->ay - A->ay)));
    /* and along the best separating axis, which may turn: the norms, |x| + |y| */
    double anyway = clear_root(m2c_sim_separation(m, A, B, now) - tol,
                               spin + fabs(q2.vx - q1.vx) + fabs(q2.vy - q1.vy),
                               fabs(B->ax - A->ax) + fabs(B->ay - A->ay));
    return m2c_sim_max(along, anyway);
}

/* The earliest contact of A's and B's features within [0, w] after now, into bs. */
static void features(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, best *bs)
{
    if (!A->polygon && !B->polygon) {
        double t = 0.0;
        int found = predict_cc(m, A, B, NULL, B->r, now, w, &t);
        better(bs, found, t, M2C_SIM_CC, A->idx, B->idx, -1, -1);
    } else if (!A->polygon) {
        circle_polygon(m, A, B, now, w, bs);
    } else if (!B->polygon) {
        circle_polygon(m, B, A, now, w, bs);
    } else {
        vertices_edges(m, A, B, now, w, bs);
        vertices_edges(m, B, A, now, w, bs);
    }
}

/* Schedules the first contact of A and B after now, or a horizon event
 * where the Taylor polynomials of their turns stop being good.  Cheap
 * steps chain: a later meeting of the bounds or a clear stretch moves now
 * on (up to CHAIN stages, at most one Taylor window). */
void m2c_sim_predict_pair(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double now)
{
    const m2c_sim_scene *s = m->s;
    if (A->sup == B->idx || B->sup == A->idx)
        return;     /* the support's edge line separates them (both convex): only leaving ends it */
    if ((A->asleep && m2c_sim_grounded(B)) || (B->asleep && m2c_sim_grounded(A)))
        return;     /* a sleeper against a sleeper or an unmoving fixed body: nothing moves */
    m->stats.pairs++;
    if (!A->polygon && !B->polygon && A->orbit == 0.0 && B->orbit == 0.0) {
        /* two circles that do not turn (turn_rate 0): the loop below takes
         * one stage, features' predict_cc */
        double w = s->end - now, t = 0.0;
        if (w > 0.0 && circles_plain(m, A, B, now, w, &t))
            m2c_sim_push_collision(m, now + t, M2C_SIM_CC, A, B, -1, -1);
        return;
    }
    double ta = m2c_sim_turn_rate(A), tb = m2c_sim_turn_rate(B);
    int windowed = 0;
    for (int stage = 0; stage < CHAIN; stage++) {
        double w = s->end - now;
        if (!(w > 0.0))
            return;
        if (A->polygon || B->polygon) {
            /* bounds that do not turn: until they touch, nothing can */
            double meet = 0.0;
            int met;
            if (B->polygon && ta > 0.0 && B->om == 0.0)
                met = bound_polygon(m, A, B, now, w, &meet);
            else if (A->polygon && tb > 0.0 && A->om == 0.0)
                met = bound_polygon(m, B, A, now, w, &meet);
            else
                met = bounds_meet(m, A, B, now, w, &meet);
            if (!met)
                return;
            if (meet > 0.0) {
                now = now + meet;
                continue;
            }
        }
        if (ta > 0.0 || tb > 0.0) {
            double x;
            if (ta > 0.0 && tb > 0.0)
                x = s->alpha / (ta + tb);
            else if (ta > 0.0)
                x = A->window / ta;         /* only A turns: its own lever */
            else
                x = B->window / tb;
            if (x < w)                      /* Python's min(w, x) */
                w = x;
            double clear = clear_time(m, A, B, now);
            if (clear >= w) {
                /* apart all through the window, whatever the turns do: no
                 * roots to solve until they may come within the tolerance */
                now = now + clear;
                continue;
            }
        }
        if (windowed)
            break;          /* one Taylor window per prediction: the next at a horizon */
        best bs = { 0, 0.0, 0, 0, 0, 0, 0 };
        features(m, A, B, now, w, &bs);
        if (bs.have) {
            m2c_sim_push_collision(m, now + bs.s, bs.feat, &m->bodies[bs.a], &m->bodies[bs.b], bs.i, bs.j);
            return;
        }
        if (ta == 0.0 && tb == 0.0)
            return;         /* nothing turns: the window was the whole run */
        now = now + w;
        windowed = 1;
    }
    if (now < s->end)
        m2c_sim_push_horizon(m, now, A, B);
}

/* ---- per body: cell crossings and neighbours --------------------------------- */

/* schedule_cell's crossing along one axis of a body without acceleration
 * there (p, v: its coordinate and speed at tb; i: its cell, of n; the
 * cells from origin, size wide; h: the margin; u in (ulo, uhi]): only the
 * boundary ahead in v's direction can be crossed, so it is chosen by
 * selects rather than by trying both (v's sign is a coin toss for the
 * branch predictor).  1 with *u and *dir, or 0; the same values as the
 * loop of schedule_cell. */
static inline __attribute__((always_inline)) int plain_crossing(double p, double v, int32_t i, int32_t n,
                                                                double origin, double size, double h, double ulo,
                                                                double uhi, double *u, int *dir)
{
    int up = v > 0.0;
    int ok = (up & (i < n - 1)) | ((v < 0.0) & (i > 0));
    /* origin + (i + 1) size + h upward, origin + i size - h downward (x - h is x + -h) */
    double bound = origin + (double)(i + up) * size + (up ? h : -h);
    double c0 = p - bound;
    *dir = up ? 1 : -1;
    if (ulo == 0.0 && c0 * (double)*dir >= 0.0) {
        *u = 0.0;       /* on the boundary or past it, moving across: at once */
        return ok;
    }
    double r = -c0 / v;
    *u = r + 0.0;
    return ok & (fabs(ulo) <= DBL_MAX) & (fabs(uhi) <= DBL_MAX) & (fabs(c0) <= DBL_MAX) & (fabs(v) <= DBL_MAX)
           & (ulo < r) & (r <= uhi);
}

/* Schedules b's next crossing of a cell boundary (a root of a quadratic in
 * the body's own time since tb). */
void m2c_sim_schedule_cell(m2c_world *m, const m2c_sim_body *b, double now)
{
    const m2c_sim_scene *s = m->s;
    if (b->large || (b->vx == 0.0 && b->vy == 0.0 && b->ax == 0.0 && b->ay == 0.0))
        return;
    double ulo = now - b->tb;
    double uhi = s->end - b->tb;
    /* the margin, or what the cell leaves a body added live that is wider
     * than the scene's widest (it must stay within half a cell of its cell) */
    double h = s->margin, room = s->half_cell - b->bound;
    if (room < h)
        h = room;
    int have = 0, baxis = 0, bdir = 0;
    double bu = 0.0;
    if (b->ax == 0.0 && b->ay == 0.0) {
        /* no acceleration (a gas): what the loop below does, one axis at a
         * time, without its branches on the direction of v */
        double ux = 0.0, uy = 0.0;
        int dx = 0, dy = 0;
        int hx = plain_crossing(b->px, b->vx, b->cx, s->nx, s->x0, s->cw, h, ulo, uhi, &ux, &dx);
        int hy = plain_crossing(b->py, b->vy, b->cy, s->ny, s->y0, s->ch, h, ulo, uhi, &uy, &dy);
        if (hy && (!hx || uy < ux))
            m2c_sim_push_cell(m, b->tb + uy, b, 1, dy);
        else if (hx)
            m2c_sim_push_cell(m, b->tb + ux, b, 0, dx);
        return;
    }
    for (int axis = 0; axis < 2; axis++) {
        double p, v, a, origin, size;
        int32_t i, n;
        if (axis == 0) {
            p = b->px; v = b->vx; a = b->ax; i = b->cx; n = s->nx; origin = s->x0; size = s->cw;
        } else {
            p = b->py; v = b->vy; a = b->ay; i = b->cy; n = s->ny; origin = s->y0; size = s->ch;
        }
        for (int dir = 1; dir >= -1; dir -= 2) {
            if (a == 0.0 && !(v * (double)dir > 0.0))
                continue;   /* no acceleration: every crossing found below moves the other way (v + a u = v) */
            double bound;
            if (dir == 1) {
                if (i >= n - 1)
                    continue;
                bound = origin + (double)(i + 1) * size + h;
            } else {
                if (i <= 0)
                    continue;
                bound = origin + (double)i * size - h;
            }
            double c[3] = { p - bound, v, 0.5 * a };
            if (ulo == 0.0 && c[0] * (double)dir >= 0.0
                && (v * (double)dir > 0.0 || (v == 0.0 && a * (double)dir > 0.0))) {
                /* on the boundary now, or past it (cell_of's quotient and
                 * the boundary's sum origin + i size can round apart), and
                 * moving or accelerating across it: cross at once (the root
                 * finder reports no root at the interval's start, and none
                 * at all for a boundary already behind) */
                if (!have || 0.0 < bu) {
                    have = 1;
                    bu = 0.0;
                    baxis = axis;
                    bdir = dir;
                }
                continue;
            }
            if (a == 0.0) {
                /* v moves across the boundary (tested above): one root, the
                 * root finder's degree-1 answer (one division, the same bits
                 * as m2c_smallest_root of c, whose c[2] is zero) without
                 * the call */
                double u = -c[0] / v;
                if ((fabs(ulo) <= DBL_MAX) & (fabs(uhi) <= DBL_MAX) & (fabs(c[0]) <= DBL_MAX) & (fabs(v) <= DBL_MAX)
                    && ulo < u && u <= uhi) {
                    u = u + 0.0;
                    if (!have || u < bu) {
                        have = 1;
                        bu = u;
                        baxis = axis;
                        bdir = dir;
                    }
                }
                continue;
            }
            double lo = ulo;
            for (int it = 0; it < 3; it++) {
                double u;
                if (m2c_smallest_root(c, 2, lo, uhi, &u) != 1)
                    break;
                if ((v + a * u) * (double)dir > 0.0) {
                    if (!have || u < bu) {
                        have = 1;
                        bu = u;
                        baxis = axis;
                        bdir = dir;
                    }
                    break;
                }
                lo = u;
            }
        }
    }
    if (have)
        m2c_sim_push_cell(m, b->tb + bu, b, baxis, bdir);
}

/* Which of a body's neighbours it is predicted against: never itself, nor
 * skip, nor a fixed one when it is fixed too; and by `only`:
 * PAIRS_ALL every other, PAIRS_AFTER those of a higher index (the start,
 * where each pair is predicted once), PAIRS_ISLAND all but the members of
 * `island` of a lower index (a waking island: a pair of two members is
 * predicted by the one with the smaller index), PAIRS_APART all but the
 * solved cluster's bodies in done (predicted already). */
enum { PAIRS_ALL, PAIRS_AFTER, PAIRS_ISLAND, PAIRS_APART };
typedef struct pair_filter {
    int only;
    const m2c_sim_body *skip;
    int32_t island;         /* PAIRS_ISLAND's */
} pair_filter;

static inline int keeps(const m2c_world *m, const pair_filter *f, const m2c_sim_body *b, const m2c_sim_body *o)
{
    if (b->fixed && o->fixed)
        return 0;
    switch (f->only) {
    case PAIRS_AFTER:
        return o->idx > b->idx;
    case PAIRS_ISLAND:
        return !(o->island == f->island && o->idx < b->idx);
    case PAIRS_APART:
        return !m2c_sim_among(m->clu.done, m->clu.ndone, o);
    default:
        return 1;
    }
}

/* predict_cells' second step: the pairs of b with the bodies of the n
 * gathered indices but b and skip that f keeps, in order (their two lines
 * fetched from memory first, so that the misses overlap). */
static inline __attribute__((always_inline)) void predict_gathered(m2c_world *m, const m2c_sim_body *b,
                                                                   const m2c_sim_body *skip, const int32_t *ids,
                                                                   int n, const m2c_sim_body **cand, double now,
                                                                   const pair_filter *f)
{
    int nc = 0;
    for (int q = 0; q < n; q++) {
        const m2c_sim_body *o = &m->bodies[ids[q]];
        __builtin_prefetch(&o->px);
        __builtin_prefetch(&o->ang);
        cand[nc] = o;
        nc += (o != b) & (o != skip);
    }
    for (int q = 0; q < nc; q++)
        if (keeps(m, f, b, cand[q]))
            m2c_sim_predict_pair(m, b, cand[q], now);
}

/* Predicts the pairs of b with every body in the cells x_lo..x_hi,
 * y_lo..y_hi (clamped to the grid) that f keeps, in the reference's order:
 * rows, then columns, then each cell's list.  The candidates are gathered
 * first, their bodies fetched from memory together, then predicted in that
 * order.  Inlined (with predict_near) where it is called with a filter
 * known there, so that the filter costs no test per candidate. */
static inline __attribute__((always_inline)) void predict_cells(m2c_world *m, const m2c_sim_body *b, int32_t x_lo,
                                                                int32_t x_hi, int32_t y_lo, int32_t y_hi, double now,
                                                                const pair_filter *f)
{
    const m2c_sim_body *skip = f->skip;
    enum { CHUNK = 64 };
    const m2c_sim_scene *s = m->s;
    int32_t y0 = y_lo > 0 ? y_lo : 0, y1 = y_hi < s->ny - 1 ? y_hi : s->ny - 1;
    int32_t x0 = x_lo > 0 ? x_lo : 0, x1 = x_hi < s->nx - 1 ? x_hi : s->nx - 1;
    for (int32_t jy = y0; jy <= y1; jy++) {
        __builtin_prefetch(&m->grid.cells[(size_t)jy * (size_t)s->nx + (size_t)x0]);
        __builtin_prefetch(&m->grid.cells[(size_t)jy * (size_t)s->nx + (size_t)x1]);
    }
    /* The indices of inline lists gathered by gather_inline, the others
     * one by one, then the bodies taken from the gathered indices in one
     * loop, b and skip left out by the count, not by a branch.  The same
     * candidates in the same order. */
    int32_t ids[CHUNK];
    const m2c_sim_body *cand[CHUNK];
    int ni = 0;
    for (int32_t jy = y0; jy <= y1; jy++) {
        for (int32_t jx = x0; jx <= x1; jx++) {
            const m2c_sim_cell *c = &m->grid.cells[(size_t)jy * (size_t)s->nx + (size_t)jx];
            if (m2c_sim_gather_inline(c, ids, &ni, CHUNK))
                continue;
            const int32_t *items = m2c_sim_cell_items(c);
            for (int32_t k = 0; k < c->n; k++) {
                if (ni == CHUNK) {
                    predict_gathered(m, b, skip, ids, ni, cand, now, f);
                    ni = 0;
                }
                ids[ni++] = items[k];
            }
        }
    }
    predict_gathered(m, b, skip, ids, ni, cand, now, f);
}

/* A small body's pairs with its neighbours that f keeps (the bodies in
 * its 3x3 cells, then the large ones near), and its next cell crossing. */
static inline __attribute__((always_inline)) void predict_near(m2c_world *m, const m2c_sim_body *b, double now,
                                                               const pair_filter *f)
{
    predict_cells(m, b, b->cx - 1, b->cx + 1, b->cy - 1, b->cy + 1, now, f);
    m2c_sim_large_near(m, b);
    for (int32_t k = 0; k < m->nnear; k++) {
        const m2c_sim_body *o = &m->bodies[m->near[k]];
        if (o != f->skip && keeps(m, f, b, o))
            m2c_sim_predict_pair(m, b, o, now);
    }
    m2c_sim_schedule_cell(m, b, now);
}

/* Everything of b's future: its pairs with every neighbour but skip, its
 * cell crossing, its stop and leave on a fixed or sleeping support. */
void m2c_sim_predict_body(m2c_world *m, const m2c_sim_body *b, double now, const m2c_sim_body *skip)
{
    const pair_filter f = { PAIRS_ALL, skip, -1 };
    predict_near(m, b, now, &f);
    if (b->sup >= 0 && (m->bodies[b->sup].fixed || m->bodies[b->sup].asleep))
        m2c_sim_schedule_support(m, b);     /* a carried body moves with its base: no stop, no leave of its own */
}

/* predict_body for a member of a waking island: a pair of two members is
 * predicted by the one with the smaller index.  (A member moves, since no
 * fixed body sleeps, so keeps' test of two fixed bodies never drops its
 * pair with a large body.)  No stop or leave events here. */
void m2c_sim_predict_woken(m2c_world *m, const m2c_sim_body *b, double now, int32_t island)
{
    const pair_filter f = { PAIRS_ISLAND, NULL, island };
    predict_near(m, b, now, &f);
}

/* predict_body for a body of a solved cluster, but against the bodies in
 * done (predicted already, or fallen asleep and predicted against it by
 * handle_sleep). */
void m2c_sim_predict_apart(m2c_world *m, const m2c_sim_body *b, double now)
{
    const pair_filter f = { PAIRS_APART, NULL, -1 };
    predict_near(m, b, now, &f);
    if (b->sup >= 0 && m->bodies[b->sup].fixed)
        m2c_sim_schedule_support(m, b);
}

/* The pairs of b with every body in the cells x_lo..x_hi, y_lo..y_hi (a
 * row or column entered: handle_cell). */
void m2c_sim_predict_cells(m2c_world *m, const m2c_sim_body *b, int32_t x_lo, int32_t x_hi, int32_t y_lo,
                           int32_t y_hi, double now)
{
    const pair_filter all = { PAIRS_ALL, NULL, -1 };
    predict_cells(m, b, x_lo, x_hi, y_lo, y_hi, now, &all);
}

/* The start's predictions of small body b at t = 0 (each pair once): its
 * pairs with the bodies of a higher index in its 3x3 cells, with every
 * large body near (but two fixed bodies), and its cell crossing. */
void m2c_sim_predict_first(m2c_world *m, const m2c_sim_body *b)
{
    const pair_filter after = { PAIRS_AFTER, NULL, -1 };
    predict_cells(m, b, b->cx - 1, b->cx + 1, b->cy - 1, b->cy + 1, 0.0, &after);
    m2c_sim_large_near(m, b);
    for (int32_t l = 0; l < m->nnear; l++) {
        const m2c_sim_body *o = &m->bodies[m->near[l]];
        if (!(b->fixed && o->fixed))
            m2c_sim_predict_pair(m, b, o, 0.0);
    }
    m2c_sim_schedule_cell(m, b, 0.0);
}
