/* Predictions (docs/simulator.md): the first contact of a pair after now
 * (the pair's computation is the TOI library's, m2c_toi.c), or a horizon
 * event where the Taylor polynomials of its turns stop being good, and a
 * body's next cell crossing (through m2c_smallest_root).  Every floating-point expression is written as the
 * Python reference (runtimes/python/max2code_rt) evaluates it, left
 * to right with the same parentheses, compiled with -ffp-contract=off, so
 * the trace has the same bytes.  Units: s, m, m/s, m/s^2, rad, rad/s. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_roots.h"
#include "m2c_sim_internal.h"

/* the most stages (a meeting of the bounds, a clear stretch, a Taylor window)
 * one prediction of a pair goes through before it leaves the rest to a horizon */
enum { CHAIN = 8 };

/* ---- pairs: the TOI library's computation (m2c_toi.c) with the world --------- */

void m2c_sim_circle_params(m2c_world *m, const m2c_sim_body *b, double now, const m2c_sim_vertex *v, double *o)
{
    m2c_toi_ctx ctx = m2c_sim_ctx(m);
    m2c_toi_circle_params(&ctx, b, now, v, o);
}

int m2c_sim_circles_gap(m2c_world *m, const double *p1, double ra, const double *p2, double rb, double *coef)
{
    m2c_toi_ctx ctx = m2c_sim_ctx(m);
    return m2c_toi_circles_gap(&ctx, p1, ra, p2, rb, coef);
}

int m2c_sim_pe_coefficients(m2c_world *m, const m2c_sim_body *X, const m2c_sim_body *Y, double rho, double beta,
                            double rad, int32_t j, double now, double *coef)
{
    m2c_toi_ctx ctx = m2c_sim_ctx(m);
    return m2c_toi_pe_coefficients(&ctx, X, Y, rho, beta, rad, j, now, coef);
}

/* Schedules the first contact of A and B after now, or a horizon event
 * where the Taylor polynomials of their turns stop being good.  Cheap
 * steps chain: a later meeting of the bounds or a clear stretch moves now
 * on (up to CHAIN stages, at most one Taylor window: m2c_toi_pair). */
void m2c_sim_predict_pair(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double now)
{
    if (A->sup == B->idx || B->sup == A->idx)
        return;     /* the support's edge line separates them (both convex): only leaving ends it */
    if ((A->asleep && m2c_sim_grounded(B)) || (B->asleep && m2c_sim_grounded(A)))
        return;     /* a sleeper against a sleeper or an unmoving fixed body: nothing moves */
    m->stats.pairs++;
    m2c_toi_ctx ctx = m2c_sim_ctx(m);
    m2c_toi_best bs;
    double at = now;
    int found = m2c_toi_pair(&ctx, A, B, now, m->s->end, CHAIN, 1, &bs, &at);
    if (found == 1)
        m2c_sim_push_collision(m, at + bs.s, bs.feat, bs.a, bs.b, bs.i, bs.j);
    else if (found == 2 && at < m->s->end)
        m2c_sim_push_horizon(m, at, A, B);
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
