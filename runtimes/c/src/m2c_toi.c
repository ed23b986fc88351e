/* The first contact of two bodies: the computation of one pair, shared by
 * the simulator's predictions (m2c_sim_predict.c, with its world) and the
 * TOI library (m2c_toi.h, without one).  Every prediction goes through the
 * generated entries of equations/circle-circle.mxm and
 * equations/point-edge.mxm (m2c_sim_equations.h) and through
 * m2c_smallest_root.  Every floating-point expression is written as the
 * Python reference (runtimes/python/max2code_rt) evaluates it, left to
 * right with the same parentheses, compiled with -ffp-contract=off, so the
 * four runtimes give the same bits.  Units: s, m, m/s, m/s^2, rad, rad/s. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_roots.h"
#include "m2c_sim_equations.h"
#include "m2c_sim_internal.h"
#include "m2c_toi.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif
#define HALF_PI 1.5707963267948966      /* rad: pi/2 rounded to double (cos x = sin(x + pi/2)) */
#define M2C_TOI_STRAIGHT 4.0            /* windows: a shorter clear stretch of two turning polygons leads to its
                                           window (m2c_toi_pair, the library only) */

/* cos and sin of body b's angle a (rad): without a world, the values of
 * each body's last angle are kept (a clear stretch and the Taylor window at
 * the same time take the same angles), bit for bit what cos and sin give. */
static void toi_cos_sin(m2c_toi_ctx *ctx, const m2c_sim_body *b, double a, double *c, double *s)
{
    if (ctx->m != NULL) {
        *c = cos(a);
        *s = sin(a);
        return;
    }
    double *e = ctx->trig[b->idx & 1];          /* the library's bodies are 0 and 1 */
    if ((ctx->trig_n >> (b->idx & 1) & 1) && memcmp(&e[0], &a, sizeof a) == 0) {
        *c = e[1];
        *s = e[2];
        return;
    }
    *c = cos(a);
    *s = sin(a);
    e[0] = a;
    e[1] = *c;
    e[2] = *s;
    ctx->trig_n |= 1 << (b->idx & 1);
}

/* ---- first valid root of one feature ---------------------------------------- */

/* What point_edge's contact must satisfy: the point lies on the segment. */
typedef struct pe_check {
    m2c_toi_ctx *ctx;
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
static int behind(m2c_toi_ctx *ctx, const m2c_sim_body *X, int32_t i, double t, double qx, double qy, double c, double sn,
                  double h)
{
    int32_t n = X->nverts;
    m2c_sim_motion p = m2c_sim_state_at(X, t);
    double lim = -ctx->tol;
    const int32_t ks[2] = { (i + n - 1) % n, (i + 1) % n };
    for (int l = 0; l < 2; l++) {
        const m2c_sim_vertex *v = &X->verts[ks[l]];
        double vc, vs;
        m2c_sim_vcos_sin(ctx->m, v, p.ang + v->beta, &vc, &vs);
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
            m2c_sim_vcos_sin(k->ctx->m, k->vx, p.ang + k->beta, &pc, &ps);
        } else {
            pc = cos(p.ang + k->beta);
            ps = sin(p.ang + k->beta);
        }
        px = px + k->rho * pc;
        py = py + k->rho * ps;
    }
    m2c_sim_motion q = m2c_sim_state_at(k->Y, t);
    double c, sn;
    m2c_sim_ecos_sin(k->ctx->m, k->ed, q.ang + k->ed->psi, &c, &sn);
    double along = (px - q.x) * -sn + (py - q.y) * c;
    if (!(k->ed->s1 - k->tol <= along && along <= k->ed->s2 + k->tol))
        return 0;
    if (k->vx == NULL)
        return 1;
    return !behind(k->ctx, k->X, (int32_t)(k->vx - k->X->verts), t, q.x, q.y, c, sn, k->ed->h);
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
int m2c_toi_touching_now(const double *c, int deg, double kappa)
{
    if (c[1] < 0.0)
        return 1;
    if (deg < 2 || !(c[2] < 0.0))
        return 0;
    return c[0] + c[1] * c[1] / (4.0 * -c[2]) <= kappa;
}

/* Binomial coefficients C(j, i), j <= 8 (exact in a double). */
static const double BINOMIAL[9][9] = {
    { 1 }, { 1, 1 }, { 1, 2, 1 }, { 1, 3, 3, 1 }, { 1, 4, 6, 4, 1 }, { 1, 5, 10, 10, 5, 1 },
    { 1, 6, 15, 20, 15, 6, 1 }, { 1, 7, 21, 35, 35, 21, 7, 1 }, { 1, 8, 28, 56, 70, 56, 28, 8, 1 },
};

/* The polynomial c of degree n (5 to 8) surely has no root in [0, hi]
 * (hi >= 2^-100, so that hi^8 stays normal): its Bernstein coefficients
 * there, b_j = sum_{i <= j} C(j, i) u_i with t_i = c_i hi^i and u_i = t_i /
 * C(n, i), are all beyond m = 2^-46 S + 2^-900 (S = sum |t_i|) with t_0's
 * sign.  The root solver's test for degrees 3 and 4 (docs/roots.md, step 1,
 * "lo >= 0" (c)) for higher degrees: each t_i is within 8 roundings of c_i
 * hi^i, each term C(j, i) u_i within 2 more, each sum within 8 more, so b_j
 * is within 18 2^-53 S < 2^-48 S of the exact coefficient and m is 7 times
 * that (docs/simulator.md, "Features that cannot come first"). */
static int no_root_high(const double *c, int n, double hi)
{
    double u[9], p = 1.0, S = 0.0;
    for (int i = 0; i <= n; i++) {
        double t = c[i] * p;
        p = p * hi;
        S = S + fabs(t);
        u[i] = t / BINOMIAL[n][i];
    }
    double m = 0x1p-46 * S + 0x1p-900;
    int neg = u[0] < 0.0;
    for (int j = 0; j <= n; j++) {
        double b = 0.0;
        for (int i = 0; i <= j; i++)
            b = b + BINOMIAL[j][i] * u[i];
        if (!(neg ? b < -m : b > m))
            return 0;
    }
    return 1;
}

/* The smallest s in [0, w] (s) where the gap c(s) reaches zero while
 * decreasing, or touches zero with zero slope while pressed together
 * (resting contact), and the check holds.  At s = 0 the gap counts as zero
 * within kappa: approaching or pressed (touching_now) means contact now,
 * separating or merely touching never.
 *
 * before: the earliest contact of the pair's other features found so far
 * (+inf for none); a contact at or after it is never kept (the earliest
 * one, first found on a tie, wins), so the search may answer none instead
 * (docs/simulator.md, "Features that cannot come first"): at once when
 * before is 0, and when a Bernstein test shows no root in [0, before (1 +
 * 2^-10)] (degrees 3 and 4: the root solver's entry's; 5 to 8:
 * no_root_high), so that a root found in [0, w] lies beyond before by far
 * more than the solver's error. */
static int first_contact(const double *c, int deg, double w, double kappa, const pe_check *chk, double before,
                         double *out)
{
    if (!(before > 0.0))
        return 0;
    if (deg >= 1 && fabs(c[0]) <= kappa && m2c_toi_touching_now(c, deg, kappa) && inside(chk, 0.0)) {
        *out = 0.0;
        return 1;
    }
    if (before < w && deg >= 3 && deg <= 8) {
        double h = before + before * 0x1p-10;
        if (h < w && (deg <= 4 ? h >= 0x1p-250 && (deg == 3 ? m2c_x_no_root3(c, h) : m2c_x_no_root4(c, h))
                               : h >= 0x1p-100 && no_root_high(c, deg, h)))
            return 0;
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
static inline __attribute__((always_inline)) void cc_count(m2c_toi_ctx *ctx, const double *g)
{
    int idx = circle_circle_variant(g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], g[9], g[10], g[11],
                                    g[12], g[13], g[14], g[15], g[16], g[17], g[18], g[19], g[20], g[21], g[22],
                                    g[23]);
    m2c_world *m = ctx->m;
    if (m == NULL) {
        ctx->error |= idx < 0;
        return;
    }
    if (idx < 0)
        ctx->die(m, "circle_circle: the scene uses an effect the generated code leaves out");
    if (idx >= m->n_cc)
        ctx->die(m, "circle_circle: variant %d, but the build counts %d variants", idx, m->n_cc);
    m->cc_counts[idx]++;
    m->stats.features++;
}

/* circle_circle's coefficients for these 24 parameters; counts the variant. */
static int cc_coefficients(m2c_toi_ctx *ctx, const double *g, double *coef)
{
    cc_count(ctx, g);
    return circle_circle_coefficients(g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], g[9], g[10], g[11],
                                      g[12], g[13], g[14], g[15], g[16], g[17], g[18], g[19], g[20], g[21],
                                      g[22], g[23], coef);
}

/* circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
 * circle's centre (v NULL) or of a polygon's vertex, at time now. */
void m2c_toi_circle_params(m2c_toi_ctx *ctx, const m2c_sim_body *b, double now, const m2c_sim_vertex *v, double *o)
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
            m2c_sim_vcos_sin(ctx->m, v, phase, &c, &sn);
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
int m2c_toi_circles_gap(m2c_toi_ctx *ctx, const double *p1, double ra, const double *p2, double rb, double *coef)
{
    double g[24];
    cc_args(p1, ra, p2, rb, g);
    return cc_coefficients(ctx, g, coef);
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
static inline __attribute__((always_inline)) int circles_first_args(m2c_toi_ctx *ctx, const double *g, double w,
                                                                    double before, double *out)
{
    double tol = ctx->tol;
    double kappa = tol * (2.0 * (g[22] + g[23]) + tol);
    if (circles_apart(g, kappa)) {
        cc_count(ctx, g);
        return 0;
    }
    double coef[M2C_MAX_DEGREE + 1];
    int deg = cc_coefficients(ctx, g, coef);
    return first_contact(coef, deg, w, kappa, NULL, before, out);
}

static int circles_first(m2c_toi_ctx *ctx, const double *p1, double ra, const double *p2, double rb, double w,
                         double before, double *out)
{
    double g[24];
    cc_args(p1, ra, p2, rb, g);
    return circles_first_args(ctx, g, w, before, out);
}

/* predict_cc of two circles that do not orbit (orbit 0: neither turns),
 * with circle_params' values written out: the same 24 parameters, bit for
 * bit (d = 0 sets the turn and the phase to 0), without its branches and
 * copies.  Most pairs of a gas are such. */
static int circles_plain(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w,
                         double *out)
{
    m2c_sim_motion qa = m2c_sim_state_at(A, now), qb = m2c_sim_state_at(B, now);
    const double g[24] = { qa.x - qb.x, qa.vx - qb.vx, A->ax - B->ax, A->orbit, 0.0, HALF_PI,
                           qa.y - qb.y, qa.vy - qb.vy, A->ay - B->ay, 0.0, 0.0,
                           0.0, 0.0, 0.0, B->orbit, 0.0, HALF_PI, 0.0, 0.0, 0.0, 0.0, 0.0,
                           A->r, B->r };
    return circles_first_args(ctx, g, w, HUGE_VAL, out);
}

/* Circle of A against circle of B (vb NULL, radius rb) or vertex vb of B (rb
 * 0); before: first_contact's. */
static int predict_cc(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, const m2c_sim_vertex *vb, double rb,
                      double now, double w, double before, double *out)
{
    double p1[11], p2[11];
    m2c_toi_circle_params(ctx, A, now, NULL, p1);
    m2c_toi_circle_params(ctx, B, now, vb, p2);
    return circles_first(ctx, p1, A->r, p2, rb, w, before, out);
}

/* Counts a point_edge prediction of variant idx (point_edge_variant): its
 * variant and the features counter; without a world, a variant of an
 * effect the generated code leaves out (idx < 0) is an error. */
static void pe_count(m2c_toi_ctx *ctx, int idx)
{
    m2c_world *m = ctx->m;
    if (m == NULL) {
        ctx->error |= idx < 0;
        return;
    }
    if (idx < 0)
        ctx->die(m, "point_edge: the scene uses an effect the generated code leaves out");
    if (idx >= m->n_pe)
        ctx->die(m, "point_edge: variant %d, but the build counts %d variants", idx, m->n_pe);
    m->pe_counts[idx]++;
    m->stats.features++;
}

/* The point_edge polynomial (its degree; coef[0]: the gap now) of a circle
 * of radius rad whose centre orbits X's centre at rho (phase beta in X's
 * frame) against the line of edge j of Y, in s = t - now. */
int m2c_toi_pe_coefficients(m2c_toi_ctx *ctx, const m2c_sim_body *X, const m2c_sim_body *Y, double rho, double beta,
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
    pe_count(ctx, point_edge_variant(px, u, ax, py, v, ay, rho, wr, phr, Y->om, phn, h));
    return point_edge_coefficients(px, u, ax, py, v, ay, rho, wr, phr, Y->om, phn, h, coef);
}

/* The first contact within [0, w] (1 with *out, else 0) of pe_coefficients'
 * polynomial whose point (X's centre, or rho, beta about it; vx: X's vertex
 * for its cos, sin cache, else NULL) lies on edge j's segment. */
static int pe_first(m2c_toi_ctx *ctx, const double *coef, int deg, const m2c_sim_body *X, const m2c_sim_body *Y,
                    const m2c_sim_vertex *vx, double rho, double beta, int32_t j, double now, double w, double before,
                    double *out)
{
    pe_check chk = { ctx, X, Y, vx, rho, beta, &Y->verts[j], now, ctx->tol };
    return first_contact(coef, deg, w, ctx->tol, &chk, before, out);
}

/* Point of X (circle centre with its radius, or vertex vx) against the line
 * of edge j of Y (none while a fixed body covers the edge: its cover is not
 * gone); before: first_contact's. */
static int predict_pe(m2c_toi_ctx *ctx, const m2c_sim_body *X, const m2c_sim_body *Y, const m2c_sim_vertex *vx, int32_t j,
                      double now, double w, double before, double *out)
{
    int32_t cover = Y->verts[j].cover;
    if (cover >= 0 && ctx->m != NULL && !ctx->m->bodies[cover].gone)
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
    int deg = m2c_toi_pe_coefficients(ctx, X, Y, rho, beta, rad, j, now, coef);
    return pe_first(ctx, coef, deg, X, Y, vx, rho, beta, j, now, w, before, out);
}

/* ---- pairs ------------------------------------------------------------------ */

/* The earliest contact found so far in one pair. */
typedef m2c_toi_best best;

static inline void better(best *bs, int found, double t, int32_t feat, const m2c_sim_body *a, const m2c_sim_body *b,
                          int32_t i, int32_t j)
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
static int bounds_meet(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, double *meet)
{
    m2c_sim_motion q1 = m2c_sim_state_at(A, now);
    m2c_sim_motion q2 = m2c_sim_state_at(B, now);
    double tol = ctx->tol;
    if (ctx->m == NULL) {
        /* the library: bounds that overlap now need no polynomial (the
         * simulator keeps the polynomial's own value, whose bits its traces
         * pin; a test that says overlap only goes on to the next step) */
        double dx = q1.x - q2.x, dy = q1.y - q2.y, r = A->bound + B->bound;
        if (dx * dx + dy * dy - r * r <= tol * (2.0 * r + tol)) {
            *meet = 0.0;
            return 1;
        }
    }
    double g[24] = { q1.x - q2.x, q1.vx - q2.vx, A->ax - B->ax, 0.0, 0.0, HALF_PI,
                     q1.y - q2.y, q1.vy - q2.vy, A->ay - B->ay, 0.0, 0.0,
                     0.0, 0.0, 0.0, 0.0, 0.0, HALF_PI, 0.0, 0.0, 0.0, 0.0, 0.0, A->bound, B->bound };
    double coef[M2C_MAX_DEGREE + 1];
    int deg = cc_coefficients(ctx, g, coef);
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
static int bound_polygon(m2c_toi_ctx *ctx, const m2c_sim_body *T, const m2c_sim_body *P, double now, double w,
                         double *meet)
{
    enum { ROW = M2C_MAX_DEGREE + 1 };
    double tol = ctx->tol;
    int32_t n = P->nverts;
    m2c_world *m = ctx->m;
    if (m != NULL && (size_t)n > m->scratch_cap) {
        /* every edge's polynomial is kept until the overlap test has seen them all */
        double *more = realloc(m->scratch, (size_t)n * ROW * sizeof *more);
        if (more != NULL)
            m->scratch = more;
        int *degs = realloc(m->scratch_deg, (size_t)n * sizeof *degs);
        if (degs != NULL)
            m->scratch_deg = degs;
        if (more == NULL || degs == NULL)
            ctx->die(m, "out of memory (bound_polygon)");
        m->scratch_cap = (size_t)n;
    }
    /* the library's polygons have at most M2C_TOI_MAX_VERTICES vertices */
    double *coefs = m != NULL ? m->scratch : ctx->scratch;
    int *deg = m != NULL ? m->scratch_deg : ctx->scratch_deg;
    int apart = 0;
    for (int32_t j = 0; j < n; j++) {
        deg[j] = m2c_toi_pe_coefficients(ctx, T, P, 0.0, 0.0, T->bound, j, now, &coefs[(size_t)j * ROW]);
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
        if (pe_first(ctx, &coefs[(size_t)j * ROW], deg[j], T, P, NULL, 0.0, 0.0, j, now, w, have ? best : HUGE_VAL, &t)
            && (!have || t < best)) {
            have = 1;
            best = t;
        }
    }
    double pt[11], pv[11];
    centre_params(T, now, pt);
    for (int32_t k = 0; k < n; k++) {
        m2c_toi_circle_params(ctx, P, now, &P->verts[k], pv);
        if (circles_first(ctx, pt, T->bound, pv, 0.0, w, have ? best : HUGE_VAL, &t) && (!have || t < best)) {
            have = 1;
            best = t;
        }
    }
    *meet = best;
    return have;
}

static void circle_polygon(m2c_toi_ctx *ctx, const m2c_sim_body *C, const m2c_sim_body *P, double now, double w, best *bs)
{
    double t = 0.0;
    for (int32_t j = 0; j < P->nverts; j++) {
        int found = predict_pe(ctx, C, P, NULL, j, now, w, bs->have ? bs->s : HUGE_VAL, &t);
        better(bs, found, t, M2C_SIM_PE, C, P, -1, j);
    }
    for (int32_t k = 0; k < P->nverts; k++) {
        int found = predict_cc(ctx, C, P, &P->verts[k], 0.0, now, w, bs->have ? bs->s : HUGE_VAL, &t);
        better(bs, found, t, M2C_SIM_CC, C, P, -1, k);
    }
}

/* What every vertex-edge pair of a window shares (window_bound).  X holds
 * the vertices, Y the edges. */
typedef struct pe_window {
    int on;                     /* the bound holds (both turns stay within 1 rad over the window) and Y's
                                   edges fit the arrays */
    double ca, sa;              /* cos, sin of X's angle now */
    double base;                /* m: the bound on a gap's change, its part common to every pair */
    double per_rho;             /* its part per metre of the vertex's radius */
    double abase, aper_rho;     /* m, and m per metre of radius: the same for the place along an edge */
    double ex[M2C_TOI_MAX_VERTICES], ey[M2C_TOI_MAX_VERTICES];  /* each edge's outward unit normal now */
    double off[M2C_TOI_MAX_VERTICES];   /* m: the gap of X's centre beyond each edge's line now */
    double slack[M2C_TOI_MAX_VERTICES]; /* m: the margin of each line's offset */
    double along[M2C_TOI_MAX_VERTICES]; /* m: X's centre along each edge (its tangent (-ey, ex)) now */
    double lo[M2C_TOI_MAX_VERTICES], hi[M2C_TOI_MAX_VERTICES];  /* m: the edge's extent, widened by the
                                                                   tolerance and the margins */
} pe_window;

/* The gap g(s) = n(s) . (d(s) + r(s)) - h of a vertex (r: its offset from
 * X's centre, |r| = rho, turning at wx) from the line of an edge of Y (n:
 * its unit normal, turning at wy; d: X's centre less Y's) changes over
 * [0, w] by at most w (|wy| D + V + |wx - wy| rho), since
 * |g'| <= |wy| |d| + |d'| + |wx - wy| rho (D >= |d|, V >= |d'| over the
 * window); point_edge's polynomial is g with the sin and cos of both turns
 * replaced by their Taylor polynomials of order n >= 1, each off by at most
 * x^2/2 for a turn x <= 1 rad, so it is within (xn^2 D + xr^2 rho) of g (xn =
 * |wy| w, xr = |wx - wy| w).  When |g(0)| exceeds both plus the tolerance
 * (first_contact's contact now) and a margin of 2^-30 of the sizes and of
 * the angles' lever for every rounding, the polynomial keeps the sign of
 * g(0) all through the window: no root, no contact (docs/toi.md, "Cost").
 * Likewise the place a(s) = t(s) . (d(s) + r(s)) of the vertex along the
 * edge (t: the edge's unit tangent) changes by at most
 * w (|wy| (D + rho) + V + |wx| rho): when a(0) lies farther than that
 * beyond the edge's extent widened by the tolerance, inside (evaluated on
 * the exact motion) refuses every root of the window. */
static void window_bound(m2c_toi_ctx *ctx, const m2c_sim_body *X, const m2c_sim_body *Y, double now, double w,
                         pe_window *k)
{
    m2c_sim_motion q1 = m2c_sim_state_at(X, now);
    m2c_sim_motion q2 = m2c_sim_state_at(Y, now);
    double dx = q1.x - q2.x, dy = q1.y - q2.y;
    double u = q1.vx - q2.vx, v = q1.vy - q2.vy, ax = X->ax - Y->ax, ay = X->ay - Y->ay;
    double speed = sqrt(u * u + v * v), acc = sqrt(ax * ax + ay * ay);
    double d = sqrt(dx * dx + dy * dy) + (speed + 0.5 * acc * w) * w;
    double vel = speed + acc * w;
    double wy = fabs(Y->om), wr = fabs(X->om - Y->om);
    double xn = wy * w, xr = wr * w;
    double lever = fabs(q1.ang) + fabs(q2.ang) + 8.0;
    k->base = w * (wy * d + vel) + xn * xn * d + ctx->tol + 0x1p-30 * (1.0 + lever) * d;
    k->per_rho = w * wr + xr * xr + 0x1p-30 * (1.0 + lever);
    k->abase = w * (wy * d + vel) + ctx->tol + 0x1p-30 * (1.0 + lever) * d;
    k->aper_rho = w * (wy + fabs(X->om)) + 0x1p-30 * (1.0 + lever);
    k->on = xn <= 1.0 && xr <= 1.0 && k->base <= DBL_MAX && k->per_rho <= DBL_MAX
            && Y->nverts <= M2C_TOI_MAX_VERTICES;
    if (!k->on)
        return;
    toi_cos_sin(ctx, X, q1.ang, &k->ca, &k->sa);
    double cb, sb;
    toi_cos_sin(ctx, Y, q2.ang, &cb, &sb);
    for (int32_t j = 0; j < Y->nverts; j++) {
        const m2c_sim_vertex *ed = &Y->verts[j];
        double nx = cb * ed->nx - sb * ed->ny;
        double ny = sb * ed->nx + cb * ed->ny;
        k->ex[j] = nx;
        k->ey[j] = ny;
        k->off[j] = nx * dx + ny * dy - ed->h;
        k->slack[j] = 0x1p-30 * fabs(ed->h);
        k->along[j] = -ny * dx + nx * dy;
        double margin = 0x1p-30 * (fabs(ed->s1) + fabs(ed->s2));
        k->lo[j] = ed->s1 - margin;
        k->hi[j] = ed->s2 + margin;
    }
}

/* The point_edge variants m2c_toi_pe_coefficients picks for X's vertices
 * against Y's edges now: *turning for a vertex off X's centre that turns
 * relative to the edge, *fixed for the others (rho 0 after the fold).  A
 * variant reads only which effects are zero (orbit, acceleration, the two
 * turns), never the positions, phases or the line's offset. */
static void pe_variants(const m2c_sim_body *X, const m2c_sim_body *Y, double now, int *turning, int *fixed)
{
    m2c_sim_motion q1 = m2c_sim_state_at(X, now);
    m2c_sim_motion q2 = m2c_sim_state_at(Y, now);
    double px = q1.x - q2.x, u = q1.vx - q2.vx, ax = X->ax - Y->ax;
    double py = q1.y - q2.y, v = q1.vy - q2.vy, ay = X->ay - Y->ay;
    double wr = X->om - Y->om;
    *turning = point_edge_variant(px, u, ax, py, v, ay, wr == 0.0 ? 0.0 : 1.0, wr, 0.0, Y->om, 0.0, 0.0);
    *fixed = point_edge_variant(px, u, ax, py, v, ay, 0.0, wr, 0.0, Y->om, 0.0, 0.0);
}

/* Every vertex of A against every edge of B within [0, w] after now; the
 * pairs far_from_line proves apart are counted, not solved. */
static void vertices_edges(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, best *bs)
{
    pe_window k;
    window_bound(ctx, A, B, now, w, &k);
    int turning = -1, fixed = -1;
    if (k.on)
        pe_variants(A, B, now, &turning, &fixed);
    double t = 0.0;
    for (int32_t i = 0; i < A->nverts; i++) {
        const m2c_sim_vertex *v = &A->verts[i];
        double rx = 0.0, ry = 0.0, lim = 0.0, alim = 0.0;
        int spared = v->rho == 0.0 ? fixed : turning;
        if (k.on) {
            rx = k.ca * v->lx - k.sa * v->ly;
            ry = k.sa * v->lx + k.ca * v->ly;
            lim = k.base + k.per_rho * v->rho;
            alim = k.abase + k.aper_rho * v->rho;
        }
        for (int32_t j = 0; j < B->nverts; j++) {
            double a = 0.0;
            if (k.on && (fabs(k.off[j] + k.ex[j] * rx + k.ey[j] * ry) > lim + k.slack[j]
                         || (a = k.along[j] - k.ey[j] * rx + k.ex[j] * ry) < k.lo[j] - alim
                         || a > k.hi[j] + alim)) {
                /* far from the line, or beside the edge, all through the window (window_bound):
                 * counted, not solved (without a world the count is only pe_count's check) */
                if (ctx->m == NULL) {
                    ctx->error |= spared < 0;
                    continue;
                }
                int32_t cover = B->verts[j].cover;
                if (!(cover >= 0 && !ctx->m->bodies[cover].gone))
                    pe_count(ctx, spared);
                continue;
            }
            int found = predict_pe(ctx, A, B, v, j, now, w, bs->have ? bs->s : HUGE_VAL, &t);
            better(bs, found, t, M2C_SIM_PE, A, B, i, j);
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
static double reach(m2c_toi_ctx *ctx, const m2c_sim_body *b, double nx, double ny, double now)
{
    double px, py;
    if (!b->polygon) {
        m2c_sim_point_at(ctx->m, b, NULL, now, &px, &py);
        return nx * px + ny * py + b->r;
    }
    double best = -INFINITY;
    for (int32_t k = 0; k < b->nverts; k++) {
        m2c_sim_point_at(ctx->m, b, &b->verts[k], now, &px, &py);
        best = m2c_sim_max(best, nx * px + ny * py);
    }
    return best;
}

/* The vertices (xs[k], ys[k]) of polygon b at t (m). */
static void vertex_points(m2c_world *m, const m2c_sim_body *b, double t, double *xs, double *ys)
{
    if (m != NULL) {
        for (int32_t k = 0; k < b->nverts; k++)
            m2c_sim_point_at(m, b, &b->verts[k], t, &xs[k], &ys[k]);
        return;
    }
    /* no world, no cache: m2c_sim_point_at's values, cos and sin of each angle in one go */
    m2c_sim_motion q = m2c_sim_state_at(b, t);
    for (int32_t k = 0; k < b->nverts; k++) {
        const m2c_sim_vertex *v = &b->verts[k];
        if (v->rho == 0.0) {
            xs[k] = q.x;
            ys[k] = q.y;
            continue;
        }
        double a = q.ang + v->beta;
        double c = cos(a), sn = sin(a);
        xs[k] = q.x + v->rho * c;
        ys[k] = q.y + v->rho * sn;
    }
}

/* reach of a polygon whose vertices now are (xs[k], ys[k]), k < n. */
static double reach_points(double nx, double ny, const double *xs, const double *ys, int32_t n)
{
    double best = -INFINITY;
    for (int32_t k = 0; k < n; k++)
        best = m2c_sim_max(best, nx * xs[k] + ny * ys[k]);
    return best;
}

static double polygons_separation(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double t,
                                  const double *ax, const double *ay, const double *bx, const double *by);

/* clear_time along each edge normal of P (P does not turn, T does). */
static double clear_axes(m2c_toi_ctx *ctx, const m2c_sim_body *T, const m2c_sim_body *P, double now)
{
    m2c_sim_motion q1 = m2c_sim_state_at(T, now);
    m2c_sim_motion q2 = m2c_sim_state_at(P, now);
    double du = q1.vx - q2.vx, dv = q1.vy - q2.vy, dax = T->ax - P->ax, day = T->ay - P->ay;
    double spin = T->bound * m2c_sim_turn_rate(T);
    double best = 0.0;
    for (int32_t j = 0; j < P->nverts; j++) {
        double ox, oy, off;
        m2c_sim_edge_line(P, j, now, &ox, &oy, &off);
        double c = clear_root(-reach(ctx, T, -ox, -oy, now) - off - ctx->tol, spin - (ox * du + oy * dv),
                              fabs(ox * dax + oy * day));
        best = m2c_sim_max(best, c);
    }
    return best;
}

/* The vertices (xs[k], ys[k]) of polygon b whose state now is q, from one
 * cosine c and sine s of its angle: the rotation of each vertex's place
 * (lx, ly) in the body's frame (m). */
static void rotated_points(const m2c_sim_body *b, m2c_sim_motion q, double c, double s, double *xs, double *ys)
{
    for (int32_t k = 0; k < b->nverts; k++) {
        const m2c_sim_vertex *v = &b->verts[k];
        xs[k] = q.x + (c * v->lx - s * v->ly);
        ys[k] = q.y + (s * v->lx + c * v->ly);
    }
}

/* The velocity (wx[k], wy[k]) (m/s) of each vertex of polygon b about its
 * centre from its turn: its offset from the centre (the rotation of its
 * place (lx, ly) by the cosine c and sine s of b's angle) turned a quarter
 * and times the turn rate. */
static void spin_velocities(const m2c_sim_body *b, double c, double s, double *wx, double *wy)
{
    for (int32_t k = 0; k < b->nverts; k++) {
        const m2c_sim_vertex *v = &b->verts[k];
        wx[k] = -(b->om * (s * v->lx + c * v->ly));
        wy[k] = b->om * (c * v->lx - s * v->ly);
    }
}

/* The larger of best and the time the other polygon Q (its centre (qx, qy))
 * stays beyond some edge line of P (state q, cos c and sin s of its angle)
 * by more than tol (s).  Q's n vertices (xs, ys) and their velocities from
 * the turn (qwx, qwy) (spin_velocities); (du, dv) and (dax, day): Q's
 * velocity and acceleration less P's; spin: the bounds times the turn
 * rates; span: the time of one radian of the two turns together (s), the
 * reach of the turning bound.
 *
 * Along the edge's outward normal o held fixed, every vertex of Q stays
 * beyond P's support until the root of the rate bound e - (spin - o . (du,
 * dv)) s - |o . (dax, day)| s^2/2 of the nearest vertex's gap e (each point
 * of a body moves along o at most its bound times its turn rate faster than
 * the centre).  Along the normal n(s) turning with P, P's support is the
 * edge's own line, and vertex k's gap g(s) = n(s) . (d(s) + r_k(s)) - h (d:
 * Q's centre less P's, r_k: the vertex about Q's centre) has, with the turn
 * rates wp and wq, the derivatives g1 = wp n_ . u + n . (dv + w_k) and g2 =
 * -wp^2 n . u + 2 wp n_ . (dv + w_k) + n . da - wq^2 n . r_k at 0 (u = d +
 * r_k, n_ the normal turned a quarter, w_k the vertex's velocity from the
 * turn); over [0, span] the third derivative is at most J = |wp|^3 D + 3
 * wp^2 V + 3 |wp| |da| + bound_Q |wq - wp|^3 and the first at most |wp| D +
 * V + bound_Q |wq - wp| (D, V: bounds of |d| and |d'| over the span), so g
 * stays above g(0) + g1 s + (g2 - J span/3) s^2/2 until that bound's root
 * (at most span).  The axis holds until the later of the two; the turning
 * normal is taken only where it can raise the axis and best, nearest vertex
 * first, and a vertex whose first-derivative bound already lasts past the
 * time so far is not solved. */
static double edges_clear(const m2c_sim_body *P, m2c_sim_motion q, double c, double s, const m2c_sim_body *Q,
                          double qx, double qy, const double *xs, const double *ys, const double *qwx,
                          const double *qwy, int32_t n, double best, double spin, double span, double du, double dv,
                          double dax, double day, double tol)
{
    double wp = P->om, wr = Q->om;
    double vel = sqrt(du * du + dv * dv);
    double acc = sqrt(dax * dax + day * day);
    double cx = qx - q.x, cy = qy - q.y;
    double dist = sqrt(cx * cx + cy * cy) + (vel + 0.5 * acc * span) * span;
    double vmax = vel + acc * span;
    double aw = fabs(wp), dw = fabs(wr - wp);
    double jerk = (aw * aw * aw * dist + 3.0 * aw * aw * vmax + 3.0 * aw * acc + Q->bound * dw * dw * dw) * span / 3.0;
    double rate = aw * dist + vmax + Q->bound * dw;
    int turning = span > 0.0 && span <= DBL_MAX && jerk <= DBL_MAX && rate <= DBL_MAX;
    double gaps[M2C_TOI_MAX_VERTICES];
    for (int32_t j = 0; j < P->nverts; j++) {
        const m2c_sim_vertex *ed = &P->verts[j];
        double ox = c * ed->nx - s * ed->ny;
        double oy = s * ed->nx + c * ed->ny;
        double off = ox * q.x + oy * q.y + ed->h;
        double g = INFINITY;
        int32_t near = 0, k = 0;
        for (; k < n; k++) {
            double e = ox * xs[k] + oy * ys[k] - off;
            if (e - tol <= 0.0)
                break;                  /* then g - tol <= 0 too: x - tol rises with x */
            gaps[k] = e;
            if (e < g) {
                g = e;
                near = k;
            }
        }
        if (k < n || !(g - tol > 0.0))
            continue;                   /* not apart along this axis: 0, never above best */
        double m = clear_root(g - tol, spin - (ox * du + oy * dv), fabs(ox * dax + oy * day));
        if (turning && span > m && span > best) {
            double mt = span;
            for (int32_t i = 0; i < n; i++) {
                k = i == 0 ? near : (i <= near ? i - 1 : i);
                double e = gaps[k] - tol;
                if (e - mt * rate >= 0.0)
                    continue;           /* its first-derivative bound alone lasts past mt */
                double ux = xs[k] - q.x, uy = ys[k] - q.y;
                double vx = du + qwx[k], vy = dv + qwy[k];
                double g1 = wp * (ox * uy - oy * ux) + (ox * vx + oy * vy);
                double g2 = -(wp * wp) * (ox * ux + oy * uy) + 2.0 * wp * (ox * vy - oy * vx) + (ox * dax + oy * day)
                            - wr * wr * (ox * (xs[k] - qx) + oy * (ys[k] - qy));
                double qq = jerk - g2;
                if (!(qq > 0.0))
                    qq = 0.0;
                double t = clear_root(e, -g1, qq);
                if (!(t >= 0.0))
                    t = 0.0;
                if (t < mt) {
                    mt = t;
                    if (!(mt > m && mt > best))
                        break;
                }
            }
            if (mt > m)
                m = mt;
        }
        if (m > best)
            best = m;
    }
    return best;
}

/* The library's clear_time of two polygons (no world; the simulator keeps
 * clear_time's own, whose bits its traces pin): every vertex from one
 * cosine and sine of its body's angle (rotated_points), and the gap along
 * each edge normal of either polygon, held fixed and turning with its
 * polygon (edges_clear), as well as along the line of the centres.  Along
 * a fixed axis the gap closes at most as fast as the centres' relative
 * motion along it plus each bound times its turn rate (clear_time), along a
 * turning edge normal each vertex's gap stays above its Taylor polynomial
 * of order 2 less the bound of its third derivative (edges_clear), and the
 * gap of the best separating axis now is the separation, so this is never
 * shorter than a bound through the norms |x| + |y| and never longer than
 * the bodies stay apart. */
static double clear_polygons(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, double now)
{
    m2c_sim_motion q1 = m2c_sim_state_at(A, now);
    m2c_sim_motion q2 = m2c_sim_state_at(B, now);
    double dx = q2.x - q1.x, dy = q2.y - q1.y;
    double d = sqrt(dx * dx + dy * dy);
    if (!(d > 0.0))
        return 0.0;
    double nx = dx / d, ny = dy / d;
    double ca, sa, cb, sb;
    toi_cos_sin(ctx, A, q1.ang, &ca, &sa);
    toi_cos_sin(ctx, B, q2.ang, &cb, &sb);
    double ax[M2C_TOI_MAX_VERTICES], ay[M2C_TOI_MAX_VERTICES], bx[M2C_TOI_MAX_VERTICES], by[M2C_TOI_MAX_VERTICES];
    rotated_points(A, q1, ca, sa, ax, ay);
    rotated_points(B, q2, cb, sb, bx, by);
    double awx[M2C_TOI_MAX_VERTICES], awy[M2C_TOI_MAX_VERTICES], bwx[M2C_TOI_MAX_VERTICES], bwy[M2C_TOI_MAX_VERTICES];
    spin_velocities(A, ca, sa, awx, awy);
    spin_velocities(B, cb, sb, bwx, bwy);
    double hi = reach_points(nx, ny, ax, ay, A->nverts);
    double lo = -reach_points(-nx, -ny, bx, by, B->nverts);
    double spin = A->bound * m2c_sim_turn_rate(A) + B->bound * m2c_sim_turn_rate(B);
    double span = 1.0 / (fabs(A->om) + fabs(B->om));
    double tol = ctx->tol;
    double du = q2.vx - q1.vx, dv = q2.vy - q1.vy, dax = B->ax - A->ax, day = B->ay - A->ay;
    double best = clear_root(lo - hi - tol, spin - (nx * du + ny * dv), fabs(nx * dax + ny * day));
    best = edges_clear(A, q1, ca, sa, B, q2.x, q2.y, bx, by, bwx, bwy, B->nverts, best, spin, span, du, dv, dax, day,
                       tol);
    return edges_clear(B, q2, cb, sb, A, q1.x, q1.y, ax, ay, awx, awy, A->nverts, best, spin, span, q1.vx - q2.vx,
                       q1.vy - q2.vy, A->ax - B->ax, A->ay - B->ay, tol);
}

/* How long (s) A and B surely stay more than the tolerance apart, from
 * their gap along a fixed unit axis now (0 when not apart now): each edge
 * normal of a polygon that does not turn against a body that does
 * (clear_axes), else the line of the centres and, with the norms |x| + |y|,
 * the best separating axis (docs/simulator.md, "Clear stretches"). */
static double clear_time(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, double now)
{
    if (B->polygon && B->om == 0.0 && m2c_sim_turn_rate(A) > 0.0)
        return clear_axes(ctx, A, B, now);
    if (A->polygon && A->om == 0.0 && m2c_sim_turn_rate(B) > 0.0)
        return clear_axes(ctx, B, A, now);
    if (ctx->m == NULL && A->polygon && B->polygon && A->nverts <= M2C_TOI_MAX_VERTICES
        && B->nverts <= M2C_TOI_MAX_VERTICES)
        return clear_polygons(ctx, A, B, now);
    m2c_sim_motion q1 = m2c_sim_state_at(A, now);
    m2c_sim_motion q2 = m2c_sim_state_at(B, now);
    double dx = q2.x - q1.x, dy = q2.y - q1.y;
    double d = sqrt(dx * dx + dy * dy);
    if (!(d > 0.0))
        return 0.0;
    double nx = dx / d, ny = dy / d;
    /* two polygons: their vertices now, once for reach and the separation */
    double ax[M2C_TOI_MAX_VERTICES], ay[M2C_TOI_MAX_VERTICES], bx[M2C_TOI_MAX_VERTICES], by[M2C_TOI_MAX_VERTICES];
    int shared = A->polygon && B->polygon && A->nverts <= M2C_TOI_MAX_VERTICES && B->nverts <= M2C_TOI_MAX_VERTICES;
    double hi, lo, sep;
    if (shared) {
        vertex_points(ctx->m, A, now, ax, ay);
        vertex_points(ctx->m, B, now, bx, by);
        hi = reach_points(nx, ny, ax, ay, A->nverts);
        lo = -reach_points(-nx, -ny, bx, by, B->nverts);
    } else {
        hi = reach(ctx, A, nx, ny, now);
        lo = -reach(ctx, B, -nx, -ny, now);
    }
    double spin = A->bound * m2c_sim_turn_rate(A) + B->bound * m2c_sim_turn_rate(B);
    double tol = ctx->tol;
    double along = clear_root(lo - hi - tol, spin - (nx * (q2.vx - q1.vx) + ny * (q2.vy - q1.vy)),
                              fabs(nx * (B->ax - A->ax) + ny * (B->ay - A->ay)));
    /* and along the best separating axis, which may turn: the norms, |x| + |y| */
    if (shared)
        sep = polygons_separation(ctx->m, A, B, now, ax, ay, bx, by);
    else
        sep = m2c_sim_separation(ctx->m, A, B, now);
    double anyway = clear_root(sep - tol, spin + fabs(q2.vx - q1.vx) + fabs(q2.vy - q1.vy),
                               fabs(B->ax - A->ax) + fabs(B->ay - A->ay));
    return m2c_sim_max(along, anyway);
}

/* The earliest contact of A's and B's features within [0, w] after now, into bs. */
static void features(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, best *bs)
{
    if (!A->polygon && !B->polygon) {
        double t = 0.0;
        int found = predict_cc(ctx, A, B, NULL, B->r, now, w, HUGE_VAL, &t);
        better(bs, found, t, M2C_SIM_CC, A, B, -1, -1);
    } else if (!A->polygon) {
        circle_polygon(ctx, A, B, now, w, bs);
    } else if (!B->polygon) {
        circle_polygon(ctx, B, A, now, w, bs);
    } else {
        vertices_edges(ctx, A, B, now, w, bs);
        vertices_edges(ctx, B, A, now, w, bs);
    }
}

/* ---- separation along fixed axes, contact frame ----------------------------- */

/* Outward unit normal (ox, oy) of edge j of P at t and the offset (m) of
 * its line, (ox, oy) . point = off. */
void m2c_sim_edge_line(const m2c_sim_body *P, int32_t j, double t, double *ox, double *oy, double *off)
{
    const m2c_sim_vertex *ed = &P->verts[j];
    m2c_sim_motion q = m2c_sim_state_at(P, t);
    double c = cos(q.ang);
    double s = sin(q.ang);
    *ox = c * ed->nx - s * ed->ny;
    *oy = s * ed->nx + c * ed->ny;
    *off = *ox * q.x + *oy * q.y + ed->h;
}

/* Along the edge normals of P: the largest over P's edges of the smallest
 * distance of Q's vertices beyond the edge's line; Q's vertices at t from
 * (qx, qy) when given, else computed (a polygon of more vertices than the
 * buffers hold).  P's lines are m2c_sim_edge_line's, with the cos and sin
 * of P's angle taken once. */
static double edges_separation(m2c_world *m, const m2c_sim_body *P, const m2c_sim_body *Q, double t, const double *qx,
                               const double *qy)
{
    m2c_sim_motion q = m2c_sim_state_at(P, t);
    double c = cos(q.ang);
    double s = sin(q.ang);
    double best = -INFINITY;
    for (int32_t j = 0; j < P->nverts; j++) {
        const m2c_sim_vertex *ed = &P->verts[j];
        double ox = c * ed->nx - s * ed->ny;
        double oy = s * ed->nx + c * ed->ny;
        double off = ox * q.x + oy * q.y + ed->h;
        double lo = INFINITY;
        for (int32_t k = 0; k < Q->nverts; k++) {
            double px, py;
            if (qx != NULL) {
                px = qx[k];
                py = qy[k];
            } else {
                m2c_sim_point_at(m, Q, &Q->verts[k], t, &px, &py);
            }
            lo = m2c_sim_min(lo, ox * px + oy * py - off);
        }
        best = m2c_sim_max(best, lo);
    }
    return best;
}

/* m2c_sim_separation of two polygons whose vertices at t are (ax, ay) and
 * (bx, by), or NULL: computed on the way. */
static double polygons_separation(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double t,
                                  const double *ax, const double *ay, const double *bx, const double *by)
{
    return m2c_sim_max(edges_separation(m, A, B, t, bx, by), edges_separation(m, B, A, t, ax, ay));
}

/* A circle against a polygon: along P's edge normals, and along the line
 * from P's nearest vertex (the first of the nearest) to the circle's centre. */
static double circle_separation(m2c_world *m, const m2c_sim_body *C, const m2c_sim_body *P, double t)
{
    double cx, cy;
    m2c_sim_point_at(m, C, NULL, t, &cx, &cy);
    double best = -INFINITY;
    for (int32_t j = 0; j < P->nverts; j++) {
        double ox, oy, off;
        m2c_sim_edge_line(P, j, t, &ox, &oy, &off);
        best = m2c_sim_max(best, ox * cx + oy * cy - off - C->r);
    }
    double d2 = INFINITY, nearx = 0.0, neary = 0.0;
    for (int32_t k = 0; k < P->nverts; k++) {
        double qx, qy;
        m2c_sim_point_at(m, P, &P->verts[k], t, &qx, &qy);
        double e2 = (cx - qx) * (cx - qx) + (cy - qy) * (cy - qy);
        if (e2 < d2) {
            d2 = e2;
            nearx = qx;
            neary = qy;
        }
    }
    if (d2 > 0.0) {
        double d = sqrt(d2);
        double ux = (cx - nearx) / d, uy = (cy - neary) / d;
        double hi = -INFINITY;
        for (int32_t k = 0; k < P->nverts; k++) {
            double qx, qy;
            m2c_sim_point_at(m, P, &P->verts[k], t, &qx, &qy);
            hi = m2c_sim_max(hi, ux * qx + uy * qy);
        }
        best = m2c_sim_max(best, ux * cx + uy * cy - C->r - hi);
    }
    return best;
}

/* The largest gap between A and B at t along a separating axis: negative
 * by the depth they overlap (edge normals of either polygon, and for a
 * circle the line from the nearest vertex; circles: the distance of the
 * centres less the radii). */
double m2c_sim_separation(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double t)
{
    if (!A->polygon && !B->polygon) {
        double ax, ay, bx, by;
        m2c_sim_point_at(m, A, NULL, t, &ax, &ay);
        m2c_sim_point_at(m, B, NULL, t, &bx, &by);
        return sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay)) - (A->r + B->r);
    }
    if (!A->polygon)
        return circle_separation(m, A, B, t);
    if (!B->polygon)
        return circle_separation(m, B, A, t);
    if (A->nverts > M2C_TOI_MAX_VERTICES || B->nverts > M2C_TOI_MAX_VERTICES)
        return polygons_separation(m, A, B, t, NULL, NULL, NULL, NULL);
    double ax[M2C_TOI_MAX_VERTICES], ay[M2C_TOI_MAX_VERTICES], bx[M2C_TOI_MAX_VERTICES], by[M2C_TOI_MAX_VERTICES];
    vertex_points(m, A, t, ax, ay);
    vertex_points(m, B, t, bx, by);
    return polygons_separation(m, A, B, t, ax, ay, bx, by);
}

/* Contact point (cx, cy) (m) and unit normal (nx, ny) from A to B of a
 * feature at t, B's angle at t being bang (rad). */
void m2c_toi_frame(m2c_world *m, double t, int32_t feature, const m2c_sim_body *A, const m2c_sim_body *B, int32_t i,
                   int32_t j, double bang, double *cx, double *cy, double *nx, double *ny)
{
    const m2c_sim_vertex *vA = i >= 0 ? &A->verts[i] : NULL;
    if (feature == M2C_SIM_CC) {
        double ax_, ay_, bx_, by_;
        m2c_sim_point_at(m, A, NULL, t, &ax_, &ay_);
        m2c_sim_point_at(m, B, j >= 0 ? &B->verts[j] : NULL, t, &bx_, &by_);
        double dx = bx_ - ax_, dy = by_ - ay_;
        double dist = sqrt(dx * dx + dy * dy);
        if (dist > 0.0) {
            *nx = dx / dist;
            *ny = dy / dist;
        } else {
            *nx = 1.0;
            *ny = 0.0;
        }
        *cx = ax_ + A->r * *nx;
        *cy = ay_ + A->r * *ny;
    } else {
        double px, py;
        m2c_sim_point_at(m, A, vA, t, &px, &py);
        double c, sn;
        m2c_sim_ecos_sin(m, &B->verts[j], bang + B->verts[j].psi, &c, &sn);
        *nx = -c;                       /* from A to B: against the edge's outward normal */
        *ny = -sn;
        double rad = vA == NULL ? A->r : 0.0;
        *cx = px + rad * *nx;
        *cy = py + rad * *ny;
    }
}

/* ---- one pair: the chain of cheap steps and Taylor windows ------------------- */

/* The first contact of A and B after now (docs/simulator.md, "One
 * prediction chains its cheap steps"): a later meeting of the bounds or a
 * clear stretch moves now on, a Taylor window solves the features, at most
 * `stages` steps of which at most `windows` windows.  1 with *bs (its s
 * after *at), 0 when there is none before end, 2 when the steps ran out at
 * *at (the simulator schedules a horizon there when it is before the end). */
int m2c_toi_pair(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, double now, double end, long stages,
                 long windows, m2c_toi_best *bs, double *at)
{
    bs->have = 0;
    if (!A->polygon && !B->polygon && A->orbit == 0.0 && B->orbit == 0.0) {
        /* two circles that do not turn (turn_rate 0): the loop below takes
         * one stage, features' predict_cc */
        double w = end - now, t = 0.0;
        if (w > 0.0 && circles_plain(ctx, A, B, now, w, &t)) {
            better(bs, 1, t, M2C_SIM_CC, A, B, -1, -1);
            *at = now;
            return 1;
        }
        return 0;
    }
    double ta = m2c_sim_turn_rate(A), tb = m2c_sim_turn_rate(B);
    /* the library: a clear stretch of two turning polygons shorter than
     * M2C_TOI_STRAIGHT windows leads straight to the window at its end,
     * without another bound or clear-stretch test (the simulator: never) */
    double lead = ctx->m == NULL && A->polygon && B->polygon && ta > 0.0 && tb > 0.0 ? M2C_TOI_STRAIGHT : 0.0;
    int straight = 0;
    long solved = 0;
    for (long stage = 0; stage < stages; stage++) {
        double w = end - now;
        if (!(w > 0.0))
            return 0;
        if ((A->polygon || B->polygon) && !straight) {
            /* bounds that do not turn: until they touch, nothing can */
            double meet = 0.0;
            int met;
            if (B->polygon && ta > 0.0 && B->om == 0.0)
                met = bound_polygon(ctx, A, B, now, w, &meet);
            else if (A->polygon && tb > 0.0 && A->om == 0.0)
                met = bound_polygon(ctx, B, A, now, w, &meet);
            else
                met = bounds_meet(ctx, A, B, now, w, &meet);
            if (!met)
                return 0;
            if (meet > 0.0) {
                now = now + meet;
                continue;
            }
        }
        if (ta > 0.0 || tb > 0.0) {
            double x;
            if (ta > 0.0 && tb > 0.0)
                x = ctx->alpha / (ta + tb);
            else if (ta > 0.0)
                x = A->window / ta;         /* only A turns: its own lever */
            else
                x = B->window / tb;
            if (x < w)                      /* Python's min(w, x) */
                w = x;
            if (!straight) {
                double clear = clear_time(ctx, A, B, now);
                if (clear >= w) {
                    /* apart all through the window, whatever the turns do: no
                     * roots to solve until they may come within the tolerance */
                    now = now + clear;
                    straight = clear < lead * w;
                    continue;
                }
            }
        }
        straight = 0;
        if (solved >= windows)
            break;          /* the simulator: one Taylor window per prediction, the next at a horizon */
        features(ctx, A, B, now, w, bs);
        if (bs->have) {
            *at = now;
            return 1;
        }
        if (ta == 0.0 && tb == 0.0)
            return 0;       /* nothing turns: the window was the whole run */
        now = now + w;
        solved++;
    }
    *at = now;
    return 2;
}

/* ---- the library: m2c_toi.h ------------------------------------------------- */

void m2c_toi_defaults(m2c_toi_options *o)
{
    o->tol = 1e-9;
    o->taylor_order = 4;
}

int m2c_toi_circle(m2c_toi_shape *s, double radius)
{
    if (!(radius > 0.0 && radius <= DBL_MAX))
        return -1;
    s->nverts = 0;
    s->radius = radius;
    s->bound = radius;
    return 0;
}

int m2c_toi_polygon(m2c_toi_shape *s, const double *xy, int n)
{
    if (n < 3 || n > M2C_TOI_MAX_VERTICES)
        return -1;
    for (int k = 0; k < 2 * n; k++)
        if (!(fabs(xy[k]) <= DBL_MAX))
            return -1;
    double bound = 0.0;
    for (int k = 0; k < n; k++) {
        double x0 = xy[2 * k], y0 = xy[2 * k + 1];
        double x1 = xy[2 * ((k + 1) % n)], y1 = xy[2 * ((k + 1) % n) + 1];
        double x2 = xy[2 * ((k + 2) % n)], y2 = xy[2 * ((k + 2) % n) + 1];
        double ex = x1 - x0, ey = y1 - y0;
        /* strictly convex, counter-clockwise: every turn left */
        if (!(ex * (y2 - y1) - ey * (x2 - x1) > 0.0))
            return -1;
        double ln = sqrt(ex * ex + ey * ey);
        double nx = ey / ln, ny = -ex / ln;     /* outward: the polygon is counter-clockwise */
        double tx = ex / ln, ty = ey / ln;
        m2c_toi_vertex *v = &s->verts[k];
        v->lx = x0;
        v->ly = y0;
        v->rho = sqrt(x0 * x0 + y0 * y0);
        v->beta = atan2(y0, x0);
        v->psi = atan2(ny, nx);
        v->h = nx * x0 + ny * y0;
        v->s1 = tx * x0 + ty * y0;
        v->s2 = tx * x1 + ty * y1;
        v->nx = nx;
        v->ny = ny;
        v->cover = -1;
        if (v->rho > bound)
            bound = v->rho;
    }
    /* the edges wind once around the centre of rotation's side: the turns sum to 2 pi */
    double turn = 0.0;
    for (int k = 0; k < n; k++) {
        const m2c_toi_vertex *v = &s->verts[k], *u = &s->verts[(k + 1) % n];
        double d = u->psi - v->psi;
        while (d <= 0.0)
            d += 2.0 * M_PI;
        turn += d;
    }
    if (!(turn < 3.0 * M_PI))
        return -1;
    s->nverts = n;
    s->radius = 0.0;
    s->bound = bound;
    return 0;
}

/* m2c_sim_separation of A and B at 0; of two polygons with every vertex
 * from one cosine and sine of its body's angle (rotated_points), the
 * library's own values (the simulator keeps m2c_sim_separation's). */
static double library_separation(const m2c_sim_body *A, const m2c_sim_body *B)
{
    if (!A->polygon || !B->polygon)
        return m2c_sim_separation(NULL, A, B, 0.0);
    m2c_sim_motion q1 = m2c_sim_state_at(A, 0.0);
    m2c_sim_motion q2 = m2c_sim_state_at(B, 0.0);
    double ax[M2C_TOI_MAX_VERTICES], ay[M2C_TOI_MAX_VERTICES], bx[M2C_TOI_MAX_VERTICES], by[M2C_TOI_MAX_VERTICES];
    rotated_points(A, q1, cos(q1.ang), sin(q1.ang), ax, ay);
    rotated_points(B, q2, cos(q2.ang), sin(q2.ang), bx, by);
    return polygons_separation(NULL, A, B, 0.0, ax, ay, bx, by);
}

/* A and B at 0 are farther apart than their bounds and the tolerance, so
 * that their separation exceeds the tolerance (each body lies within its
 * bound about its centre of rotation) and the overlap test can be spared:
 * the centres' distance less the bounds, with a margin of 2^-30 of the
 * sizes for every rounding. */
static int bounds_apart(const m2c_sim_body *A, const m2c_sim_body *B, double tol)
{
    double dx = B->px - A->px, dy = B->py - A->py, r = A->bound + B->bound;
    double d = sqrt(dx * dx + dy * dy);
    return d - r > tol + 0x1p-30 * (d + r + fabs(A->px) + fabs(A->py) + fabs(B->px) + fabs(B->py));
}

/* The largest angle (at most 0.5 rad) whose order-n Taylor remainder of sin
 * and cos, a^(n+1)/(n+1)!, times the lever (m) stays below the tolerance. */
static double angle_for(double lever, int n, double tol)
{
    double f = 1.0;
    for (int k = 2; k <= n + 1; k++)
        f = f * (double)k;
    double a = pow(f * tol / lever, 1.0 / (double)(n + 1));
    return a < 0.5 ? a : 0.5;
}

static int finite_motion(const m2c_toi_motion *q)
{
    const double v[10] = { q->x, q->y, q->vx, q->vy, q->ax, q->ay, q->angle, q->omega, q->orbit, q->orbit_phase };
    for (int k = 0; k < 10; k++)
        if (!(fabs(v[k]) <= DBL_MAX))
            return 0;
    return q->orbit >= 0.0;
}

/* The simulator's body of a shape moving as q (its clock at 0). */
static void body_of(const m2c_toi_shape *s, const m2c_toi_motion *q, int32_t idx, m2c_sim_body *b)
{
    memset(b, 0, sizeof *b);
    b->px = q->x;
    b->py = q->y;
    b->vx = q->vx;
    b->vy = q->vy;
    b->ax = q->ax;
    b->ay = q->ay;
    b->tb = 0.0;
    b->om = q->omega;
    b->ang = q->angle;
    b->polygon = s->nverts > 0;
    b->r = b->polygon ? 0.0 : s->radius;
    b->orbit = b->polygon ? 0.0 : q->orbit;
    b->ophase = b->polygon ? 0.0 : q->orbit_phase;
    b->bound = b->polygon ? s->bound : b->orbit + b->r;
    b->idx = idx;
    b->sup = -1;
    b->island = -1;
    b->non = 0;
    b->nverts = s->nverts;
    b->verts = b->polygon ? (m2c_sim_vertex *)s->verts : NULL;
}

int m2c_toi(const m2c_toi_shape *a, const m2c_toi_motion *ma, const m2c_toi_shape *b, const m2c_toi_motion *mb,
            double horizon, const m2c_toi_options *o, m2c_toi_result *r)
{
    m2c_toi_options def;
    if (o == NULL) {
        m2c_toi_defaults(&def);
        o = &def;
    }
    memset(r, 0, sizeof *r);
    r->status = M2C_TOI_ERROR;
    r->i = r->j = -1;
    if (!(o->tol > 0.0 && o->tol <= DBL_MAX) || o->taylor_order < 1 || o->taylor_order > 7)
        return M2C_TOI_ERROR;
    if (!(horizon >= 0.0 && horizon <= DBL_MAX) || !finite_motion(ma) || !finite_motion(mb))
        return M2C_TOI_ERROR;
    if ((a->nverts > 0 && ma->orbit != 0.0) || (b->nverts > 0 && mb->orbit != 0.0))
        return M2C_TOI_ERROR;
    m2c_sim_body A, B;
    body_of(a, ma, 0, &A);
    body_of(b, mb, 1, &B);
    double tol = o->tol;
    if (!bounds_apart(&A, &B, tol) && library_separation(&A, &B) < -tol) {
        r->status = M2C_TOI_OVERLAPPED;
        return M2C_TOI_OVERLAPPED;
    }
    /* the windows (docs/simulator.md, "Taylor windows"): both turn, a lever
     * of twice the larger bound plus the larger bound; one turns, its bound
     * plus a circle partner's radius */
    double ta = m2c_sim_turn_rate(&A), tb = m2c_sim_turn_rate(&B);
    double big = A.bound > B.bound ? A.bound : B.bound;
    double alpha = 0.5;
    if (ta > 0.0 && tb > 0.0)
        alpha = angle_for(2.0 * big + big, o->taylor_order, tol);
    else if (ta > 0.0)
        A.window = angle_for(A.bound + B.r, o->taylor_order, tol);
    else if (tb > 0.0)
        B.window = angle_for(B.bound + A.r, o->taylor_order, tol);
    double scratch[M2C_TOI_MAX_VERTICES * (M2C_MAX_DEGREE + 1)];
    int scratch_deg[M2C_TOI_MAX_VERTICES];
    m2c_toi_ctx ctx = { tol, alpha, NULL, NULL, 0, scratch, scratch_deg, 0, { { 0.0 } } };
    m2c_toi_best bs;
    double at = 0.0;
    int found = m2c_toi_pair(&ctx, &A, &B, 0.0, horizon, 10000000L, 10000000L, &bs, &at);
    if (ctx.error || found == 2)
        return M2C_TOI_ERROR;
    if (found == 0) {
        r->status = M2C_TOI_NONE;
        return M2C_TOI_NONE;
    }
    double t = at + bs.s;
    r->status = M2C_TOI_HIT;
    r->t = t;
    r->feature = bs.feat;
    r->first = bs.a == &B;
    r->i = bs.i;
    r->j = bs.j;
    m2c_sim_motion qb = m2c_sim_state_at(bs.b, t);
    m2c_toi_frame(NULL, t, bs.feat, bs.a, bs.b, bs.i, bs.j, qb.ang, &r->px, &r->py, &r->nx, &r->ny);
    return M2C_TOI_HIT;
}
