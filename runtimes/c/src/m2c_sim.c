/* The discrete-event simulator (docs/simulator.md): a line-by-line port of
 * runtimes/python/max2code_rt/sim.py, the reference.  Every floating-point
 * expression is written as Python evaluates it (left to right, the same
 * parentheses), compiled with -ffp-contract=off, so the trace has the same
 * bytes.  Units: s, m, m/s, m/s^2, rad, rad/s. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_roots.h"
#include "m2c_sim_equations.h"
#include "m2c_sim_internal.h"

#define HALF_PI 1.5707963267948966      /* rad: pi/2 rounded to double (cos x = sin(x + pi/2)) */

enum { CC = 0, PE = 1 };                /* contact features: circle-circle (or -vertex), point-edge */
/* the most stages (a meeting of the bounds, a clear stretch, a Taylor window)
 * one prediction of a pair goes through before it leaves the rest to a horizon */
enum { CHAIN = 8 };

typedef m2c_sim_stats stats;
typedef struct m2c_world sim;

/* The N lines, in their order: each counter's name and place in stats. */
static const struct {
    const char *name;
    size_t offset;
} stat_lines[] = {
    { "collisions", offsetof(stats, collisions) }, { "inputs", offsetof(stats, inputs) },
    { "frames", offsetof(stats, frames) },         { "cells", offsetof(stats, cells) },
    { "horizons", offsetof(stats, horizons) },     { "stale", offsetof(stats, stale) },
    { "pairs", offsetof(stats, pairs) },           { "features", offsetof(stats, features) },
    { "supports", offsetof(stats, supports) },     { "stops", offsetof(stats, stops) },
    { "leaves", offsetof(stats, leaves) },         { "sleeps", offsetof(stats, sleeps) },
    { "wakes", offsetof(stats, wakes) },
};

/* The reference's SimError: the message, then back to the entry that
 * set m->fail; the world is unusable from then on. */
static _Noreturn void die(sim *m, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(m->err, sizeof m->err, fmt, ap);
    va_end(ap);
    m->broken = 1;
    longjmp(m->fail, 1);
}

static void report(sim *m, double t, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                   int32_t j, double cx, double cy, double nx, double ny, double imp, int support);

/* %.17g of x (as the reference's _fmt) into buf, NUL-terminated. */
static const char *fmt(char *buf, double x)
{
    buf[m2c_sim_format_number(buf, x)] = '\0';
    return buf;
}

/* cos(a) and sin(a), from the cache when a is the angle (to the bit) it
 * last held: libm's answer for the same argument, without the call.  A
 * polygon that does not turn asks for the same angles again and again. */
static inline void trig(m2c_sim_trig *k, double a, double *c, double *s)
{
    if (k->valid && memcmp(&k->angle, &a, sizeof a) == 0) {
        *c = k->c;
        *s = k->s;
        return;
    }
    *c = cos(a);
    *s = sin(a);
    k->angle = a;
    k->c = *c;
    k->s = *s;
    k->valid = 1;
}

/* Python's max(a, b) and min(a, b): the first unless the second is larger
 * (smaller). */
static inline double py_max(double a, double b)
{
    return b > a ? b : a;
}

static inline double py_min(double a, double b)
{
    return b < a ? b : a;
}

#define VTRIG(m, v) (&(m)->vtrig[(v) - (m)->s->verts])
#define ETRIG(m, v) (&(m)->etrig[(v) - (m)->s->verts])

/* ---- motion ---------------------------------------------------------------- */

/* Centre (m), velocity (m/s) and angle (rad) of a body at some time. */
typedef struct motion {
    double x, y, vx, vy, ang;
} motion;

static void advance(m2c_sim_body *b, double t)
{
    double dt = t - b->tb;
    b->px = b->px + (b->vx + 0.5 * b->ax * dt) * dt;
    b->py = b->py + (b->vy + 0.5 * b->ay * dt) * dt;
    b->vx = b->vx + b->ax * dt;
    b->vy = b->vy + b->ay * dt;
    b->ang = b->ang + b->om * dt;
    b->tb = t;
}

/* The body's state at t (the body is not changed). */
static inline motion state_at(const m2c_sim_body *b, double t)
{
    double dt = t - b->tb;
    motion q;
    q.x = b->px + (b->vx + 0.5 * b->ax * dt) * dt;
    q.y = b->py + (b->vy + 0.5 * b->ay * dt) * dt;
    q.vx = b->vx + b->ax * dt;
    q.vy = b->vy + b->ay * dt;
    q.ang = b->ang + b->om * dt;
    return q;
}

void m2c_sim_body_state(const m2c_sim_body *b, double t, m2c_body_state *s)
{
    motion q = state_at(b, t);
    s->x = q.x;
    s->y = q.y;
    s->vx = q.vx;
    s->vy = q.vy;
    s->angle = q.ang;
    s->omega = b->om;
}

/* rad/s: how fast the body's contact features turn. */
static inline double turn_rate(const m2c_sim_body *b)
{
    if (b->polygon || b->orbit > 0.0)
        return fabs(b->om);
    return 0.0;
}

/* World position (m) of a circle's centre (v NULL) or of a vertex, at t. */
static inline void point_at(sim *m, const m2c_sim_body *b, const m2c_sim_vertex *v, double t, double *x, double *y)
{
    motion q = state_at(b, t);
    double d = v == NULL ? b->orbit : v->rho;
    double beta = v == NULL ? b->ophase : v->beta;
    if (d == 0.0) {
        *x = q.x;
        *y = q.y;
        return;
    }
    double c, sn;
    if (v != NULL) {
        trig(VTRIG(m, v), q.ang + beta, &c, &sn);
    } else {
        c = cos(q.ang + beta);
        sn = sin(q.ang + beta);
    }
    *x = q.x + d * c;
    *y = q.y + d * sn;
}

/* ---- the event queue --------------------------------------------------------- */

/* Whether a body of e changed its motion since e was scheduled.  Inputs
 * are scripted, not predicted, and frames have no bodies: never. */
static int is_stale(const sim *m, const m2c_sim_event *e)
{
    switch (e->kind) {
    case M2C_SIM_COLLISION:
        return m->stamp[e->u.collision.a] != e->u.collision.stamp_a || m->stamp[e->u.collision.b] != e->u.collision.stamp_b;
    case M2C_SIM_HORIZON:
        return m->stamp[e->u.horizon.a] != e->u.horizon.stamp_a || m->stamp[e->u.horizon.b] != e->u.horizon.stamp_b;
    case M2C_SIM_CELL:
        return m->stamp[e->u.cell.body] != e->u.cell.stamp;
    case M2C_SIM_STOP:
        return m->stamp[e->u.stop.body] != e->u.stop.stamp;
    case M2C_SIM_LEAVE:
        return m->stamp[e->u.leave.body] != e->u.leave.stamp;
    default:
        return 0;
    }
}

/* The reference pops a stale event and counts it when its time comes (if
 * it is not after the end).  A stale event stays stale (stamps only grow),
 * so the queue may drop it earlier and count it then: the same count, and
 * a queue that holds mostly live events. */
static int drop_stale(void *ctx, const m2c_sim_event *e)
{
    sim *m = ctx;
    if (!is_stale(m, e))
        return 0;
    if (e->t <= m->s->end)
        m->stats.stale++;
    return 1;
}

/* Drops the stale events once the queue has doubled since the last sweep. */
static void sweep(sim *m)
{
    m2c_sim_heap_sweep(&m->heap, drop_stale, m);
    size_t live = m->heap.n;
    m->sweep_at = 2 * live > 4096 ? 2 * live : 4096;
}

/* Queues an event record (its t and kind set, and the fields of its kind). */
static void push(sim *m, const m2c_sim_event *e)
{
    if (!(e->t >= 0.0))     /* never: every time is now or later, and now >= 0 */
        die(m, "an event at a time that is not a number or negative");
    if (m2c_sim_heap_push(&m->heap, e) != 0)
        die(m, "out of memory (event queue of %zu events)", m->heap.n);
    if (m->heap.n >= m->sweep_at)
        sweep(m);
}

static void push_collision(sim *m, double t, int32_t feature, const m2c_sim_body *A, const m2c_sim_body *B,
                           int32_t i, int32_t j)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_COLLISION };
    e.u.collision.a = A->idx;
    e.u.collision.b = B->idx;
    e.u.collision.feature = feature;
    e.u.collision.i = i;
    e.u.collision.j = j;
    e.u.collision.stamp_a = m->stamp[A->idx];
    e.u.collision.stamp_b = m->stamp[B->idx];
    push(m, &e);
}

static void push_horizon(sim *m, double t, const m2c_sim_body *A, const m2c_sim_body *B)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_HORIZON };
    e.u.horizon.a = A->idx;
    e.u.horizon.b = B->idx;
    e.u.horizon.stamp_a = m->stamp[A->idx];
    e.u.horizon.stamp_b = m->stamp[B->idx];
    push(m, &e);
}

static void push_cell(sim *m, double t, const m2c_sim_body *b, int32_t axis, int32_t direction)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_CELL };
    e.u.cell.body = b->idx;
    e.u.cell.axis = axis;
    e.u.cell.direction = direction;
    e.u.cell.stamp = m->stamp[b->idx];
    e.u.cell.cx = b->cx;
    e.u.cell.cy = b->cy;
    push(m, &e);
}

static void push_stop(sim *m, double t, const m2c_sim_body *b)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_STOP };
    e.u.stop.body = b->idx;
    e.u.stop.stamp = m->stamp[b->idx];
    push(m, &e);
}

static void push_leave(sim *m, double t, const m2c_sim_body *b)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_LEAVE };
    e.u.leave.body = b->idx;
    e.u.leave.stamp = m->stamp[b->idx];
    push(m, &e);
}

static void push_input(sim *m, double t, int32_t k)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_INPUT };
    e.u.input.k = k;
    push(m, &e);
}

static void push_frame(sim *m, double t, int32_t k)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_FRAME };
    e.u.frame.k = k;
    push(m, &e);
}

/* The fetch-ahead helpers below only prefetch, which GCC counts as no side
 * effect: a function of prefetches alone is then "const" and its calls are
 * deleted as dead code before they can be inlined (so fetch_next did
 * nothing from session 3 to 9).  always_inline puts them in their callers
 * first. */
#define FETCH static inline __attribute__((always_inline))

/* Fetching ahead pays where the bodies and cells miss the cache: at 10^4
 * and 10^5 disks (3.5 and 42 MB) it takes 26 % and 30 % off the CPU
 * time; where they stay in a core's second-level cache (10^3 disks: 0.4
 * MB) it is only its instructions, 7 % more per event.  So the helpers
 * below (but the queue's and predict_cells' own few prefetches) work only
 * above this many bytes of bodies and cells: about a core's second-level
 * cache on the machine measured (docs/throughput.md, "Session 11, C"). */
#ifndef M2C_SIM_FETCH_BYTES
#define M2C_SIM_FETCH_BYTES ((size_t)1 << 20)
#endif

/* Whether to fetch ahead, from the bodies' and cells' bytes now (the scene
 * opened, or a body added). */
static void choose_fetch(sim *m)
{
    size_t bytes = ((size_t)m->s->nbodies + 1) * sizeof *m->bodies
                   + (size_t)m->s->nx * (size_t)m->s->ny * sizeof *m->grid.cells;
    m->fetch = bytes > M2C_SIM_FETCH_BYTES;
}

/* Fetches from memory the lines a body's own event reads: its prediction's
 * two and its handler's (cell, impulse). */
FETCH void fetch_body(const sim *m, int32_t idx)
{
    if (!m->fetch)
        return;
    const m2c_sim_body *b = &m->bodies[idx];
    __builtin_prefetch(&b->px);
    __builtin_prefetch(&b->ang);
    __builtin_prefetch(&b->inv_m);
}

/* Fetches the cells from xa to xb (either order) of row y, clamped to
 * the grid (no more than three: two lines at most). */
FETCH void fetch_row(const sim *m, int32_t xa, int32_t xb, int32_t y)
{
    const m2c_sim_scene *s = m->s;
    int32_t lo = xa < xb ? xa : xb, hi = xa < xb ? xb : xa;
    lo = lo > 0 ? lo : 0;
    hi = hi < s->nx - 1 ? hi : s->nx - 1;
    if (y < 0 || y >= s->ny || lo > hi)
        return;
    __builtin_prefetch(&m->grid.cells[(size_t)y * (size_t)s->nx + (size_t)lo]);
    __builtin_prefetch(&m->grid.cells[(size_t)y * (size_t)s->nx + (size_t)hi]);
}

/* Fetches the cell a small body's position falls in (cell_of's, without
 * its checks: a hint). */
FETCH void fetch_cell_at(const sim *m, const m2c_sim_body *b)
{
    if (!m->fetch)
        return;
    const m2c_sim_scene *s = m->s;
    double ix = floor((b->px - s->x0) / s->cw), iy = floor((b->py - s->y0) / s->ch);
    if (b->large || !(ix >= 0.0 && ix <= (double)(s->nx - 1) && iy >= 0.0 && iy <= (double)(s->ny - 1)))
        return;
    __builtin_prefetch(&m->grid.cells[(size_t)iy * (size_t)s->nx + (size_t)ix]);
}

/* Fetches the 3x3 cells around a small body and its count of walls near
 * (what predict_body reads of the grid). */
FETCH void fetch_block(const sim *m, const m2c_sim_body *b)
{
    if (!m->fetch)
        return;
    if (b->large)
        return;
    for (int32_t y = b->cy - 1; y <= b->cy + 1; y++)
        fetch_row(m, b->cx - 1, b->cx + 1, y);
    __builtin_prefetch(&m->wnear[(size_t)b->cy * (size_t)m->s->nx + (size_t)b->cx]);
}

/* Appends the indices of cell c to ids[*ni] when the cell keeps its list
 * inline and room is left: all M2C_SIM_CELL_INLINE slots are copied at
 * once (a loop over the count mispredicts its exit at nearly every cell;
 * the slots past the count are overwritten by the next cell's or never
 * read).  1 when done, 0 when the caller walks the list itself. */
static inline __attribute__((always_inline)) int gather_inline(const m2c_sim_cell *c, int32_t *ids, int *ni, int room)
{
    if (c->cap != 0 || *ni + M2C_SIM_CELL_INLINE > room)
        return 0;
    memcpy(&ids[*ni], c->u.in, sizeof c->u.in);
    *ni += c->n;
    return 1;
}

/* Fetches the two prediction lines of the bodies listed in the cells
 * x_lo..x_hi, y_lo..y_hi (clamped to the grid; the first 8 of each), whose
 * lists were fetched a while before. */
FETCH void fetch_bodies_in(const sim *m, int32_t x_lo, int32_t x_hi, int32_t y_lo, int32_t y_hi)
{
    if (!m->fetch)
        return;
    const m2c_sim_scene *s = m->s;
    int32_t y0 = y_lo > 0 ? y_lo : 0, y1 = y_hi < s->ny - 1 ? y_hi : s->ny - 1;
    int32_t x0 = x_lo > 0 ? x_lo : 0, x1 = x_hi < s->nx - 1 ? x_hi : s->nx - 1;
    /* the indices of inline lists gathered first (gather_inline), then
     * fetched in one loop */
    enum { ROOM = 9 * M2C_SIM_CELL_INLINE };
    int32_t ids[ROOM];
    int ni = 0;
    for (int32_t jy = y0; jy <= y1; jy++) {
        for (int32_t jx = x0; jx <= x1; jx++) {
            const m2c_sim_cell *c = &m->grid.cells[(size_t)jy * (size_t)s->nx + (size_t)jx];
            if (gather_inline(c, ids, &ni, ROOM))
                continue;
            const int32_t *items = m2c_sim_cell_items(c);
            for (int32_t k = 0; k < c->n && k < 8; k++) {
                const m2c_sim_body *o = &m->bodies[items[k]];
                __builtin_prefetch(&o->px);
                __builtin_prefetch(&o->ang);
            }
        }
    }
    for (int q = 0; q < ni; q++) {
        const m2c_sim_body *o = &m->bodies[ids[q]];
        __builtin_prefetch(&o->px);
        __builtin_prefetch(&o->ang);
    }
}

/* The same for the 3x3 cells around a small body (fetched by fetch_block),
 * for predict_body. */
FETCH void fetch_neighbours(const sim *m, const m2c_sim_body *b)
{
    if (!b->large)
        fetch_bodies_in(m, b->cx - 1, b->cx + 1, b->cy - 1, b->cy + 1);
}

/* Fetches the stamps of the event that is next for now (the queue fetched
 * its record when it found it): whether it is stale is the first question
 * asked of it. */
FETCH void fetch_stamps(const sim *m)
{
    if (!m->fetch)
        return;
    const m2c_sim_event *e = m2c_sim_heap_peek(&m->heap);
    if (e == NULL)
        return;
    if (e->kind == M2C_SIM_COLLISION) {
        __builtin_prefetch(&m->stamp[e->u.collision.a]);
        __builtin_prefetch(&m->stamp[e->u.collision.b]);
    } else if (e->kind == M2C_SIM_CELL) {
        __builtin_prefetch(&m->stamp[e->u.cell.body]);
    }
}

/* Fetches the stamps and bodies of the event that is next for now (the
 * queue fetched the event itself when it found it), while this one is
 * handled; for a cell crossing also the cells it will read (from where the
 * record says the body is: a hint, checked by nothing).  Stale events at
 * the head (a few) are dropped first and counted, as the sweep does (a
 * stale event stays stale: the same count), so that what is fetched is the
 * event handled next; events this handler schedules later may still come
 * before it (then the fetch was only early).  Not inlined: four handlers
 * call it (it pops, so its calls are not dead code). */
static __attribute__((noinline)) void fetch_next(sim *m)
{
    if (!m->fetch)
        return;
    const m2c_sim_event *e = m2c_sim_heap_peek(&m->heap);
    for (int k = 0; e != NULL && k < 8 && is_stale(m, e); k++) {
        m2c_sim_event drop;
        if (m2c_sim_heap_pop(&m->heap, &drop) != 0)
            die(m, "out of memory (event queue of %zu events)", m->heap.n);
        if (drop.t <= m->s->end)
            m->stats.stale++;
        e = m2c_sim_heap_peek(&m->heap);
    }
    if (e == NULL)
        return;
    if (e->kind == M2C_SIM_COLLISION) {
        __builtin_prefetch(&m->stamp[e->u.collision.a]);
        __builtin_prefetch(&m->stamp[e->u.collision.b]);
        fetch_body(m, e->u.collision.a);
        fetch_body(m, e->u.collision.b);
    } else if (e->kind == M2C_SIM_HORIZON) {
        __builtin_prefetch(&m->stamp[e->u.horizon.a]);
        __builtin_prefetch(&m->stamp[e->u.horizon.b]);
    } else if (e->kind == M2C_SIM_CELL) {
        __builtin_prefetch(&m->stamp[e->u.cell.body]);
        fetch_body(m, e->u.cell.body);
        int32_t cx = e->u.cell.cx, cy = e->u.cell.cy, d = e->u.cell.direction;
        if (cx >= 0 && cx < m->s->nx && cy >= 0 && cy < m->s->ny) {
            /* the cell it leaves, the one it enters and the row or column beyond */
            int32_t nx_ = cx, ny_ = cy;
            if (e->u.cell.axis == 0) {
                nx_ = cx + d;
                fetch_row(m, cx, cx + 2 * d, cy);
                fetch_row(m, cx + 2 * d, cx + 2 * d, cy - 1);
                fetch_row(m, cx + 2 * d, cx + 2 * d, cy + 1);
            } else {
                ny_ = cy + d;
                fetch_row(m, cx, cx, cy);
                fetch_row(m, cx, cx, cy + d);
                fetch_row(m, cx - 1, cx + 1, cy + 2 * d);
            }
            if (nx_ >= 0 && nx_ < m->s->nx && ny_ >= 0 && ny_ < m->s->ny)
                __builtin_prefetch(&m->wnear[(size_t)ny_ * (size_t)m->s->nx + (size_t)nx_]);
        }
    } else if (e->kind == M2C_SIM_STOP) {
        __builtin_prefetch(&m->stamp[e->u.stop.body]);
    } else if (e->kind == M2C_SIM_LEAVE) {
        __builtin_prefetch(&m->stamp[e->u.leave.body]);
    }
}

/* ---- grid ---------------------------------------------------------------------- */

static void cell_of(sim *m, double x, double y, int32_t *cx, int32_t *cy)
{
    const m2c_sim_scene *s = m->s;
    double ix = floor((x - s->x0) / s->cw);
    double iy = floor((y - s->y0) / s->ch);
    if (ix != ix || iy != iy)
        die(m, "a body's position is not a number");
    ix = ix < 0.0 ? 0.0 : (ix > (double)(s->nx - 1) ? (double)(s->nx - 1) : ix);
    iy = iy < 0.0 ? 0.0 : (iy > (double)(s->ny - 1) ? (double)(s->ny - 1) : iy);
    *cx = (int32_t)ix;
    *cy = (int32_t)iy;
}

static void cell_add(sim *m, m2c_sim_body *b)
{
    if (m2c_sim_grid_add(&m->grid, m->bodies, b) != 0)
        die(m, "out of memory (grid cell)");
}

/* Appends idx to a wall list (cell); dies when out of memory. */
/* Adds dn to the count of walls near each cell whose 3x3 block holds
 * cell (jx, jy) (the cells around it, clamped to the grid). */
static void wnear_add(sim *m, int32_t jx, int32_t jy, int32_t dn)
{
    const m2c_sim_scene *s = m->s;
    int32_t y0 = jy > 0 ? jy - 1 : 0, y1 = jy < s->ny - 1 ? jy + 1 : s->ny - 1;
    int32_t x0 = jx > 0 ? jx - 1 : 0, x1 = jx < s->nx - 1 ? jx + 1 : s->nx - 1;
    for (int32_t y = y0; y <= y1; y++)
        for (int32_t x = x0; x <= x1; x++)
            m->wnear[(size_t)y * (size_t)s->nx + (size_t)x] += dn;
}

static void wall_push(sim *m, m2c_sim_wall *c, int32_t idx)
{
    if (c->n == c->cap) {
        int32_t cap = c->cap ? 2 * c->cap : 4;
        int32_t *more = realloc(c->items, (size_t)cap * sizeof *more);
        if (more == NULL)
            die(m, "out of memory (grid walls)");
        c->items = more;
        c->cap = cap;
    }
    c->items[c->n++] = idx;
}

static inline void point_at(sim *m, const m2c_sim_body *b, const m2c_sim_vertex *v, double t, double *x, double *y);

/* A large body into the grid's walls when it is fixed and does not move
 * (v = a = 0): its box (a polygon that does not turn: its vertices at its
 * time; else its centre +- bound) in cells, every cell from cell_of(the
 * box's low corner) to cell_of(its high corner); else into the large list. */
static void place_large(sim *m, m2c_sim_body *b)
{
    if (!(b->fixed && b->vx == 0.0 && b->vy == 0.0 && b->ax == 0.0 && b->ay == 0.0)) {
        m->large[m->nlarge++] = b->idx;
        b->placed = 0;
        return;
    }
    double x0, y0, x1, y1;
    if (b->polygon && b->om == 0.0) {
        point_at(m, b, &b->verts[0], b->tb, &x0, &y0);
        x1 = x0;
        y1 = y0;
        for (int32_t k = 0; k < b->nverts; k++) {
            double x, y;
            point_at(m, b, &b->verts[k], b->tb, &x, &y);
            x0 = py_min(x0, x);
            x1 = py_max(x1, x);
            y0 = py_min(y0, y);
            y1 = py_max(y1, y);
        }
    } else {
        x0 = b->px - b->bound;
        x1 = b->px + b->bound;
        y0 = b->py - b->bound;
        y1 = b->py + b->bound;
    }
    int32_t i0, j0, i1, j1;
    cell_of(m, x0, y0, &i0, &j0);
    cell_of(m, x1, y1, &i1, &j1);
    b->placed = 1;
    b->wcells[0] = i0;
    b->wcells[1] = i1;
    b->wcells[2] = j0;
    b->wcells[3] = j1;
    int32_t nx = m->s->nx;
    for (int32_t jy = j0; jy <= j1; jy++)
        for (int32_t jx = i0; jx <= i1; jx++) {
            wall_push(m, &m->walls[(size_t)jy * (size_t)nx + (size_t)jx], b->idx);
            wnear_add(m, jx, jy, 1);
        }
}

/* idx (which is listed) out of items[0 .. *n - 1], the others keeping their order. */
static void remove_listed(int32_t *items, int32_t *n, int32_t idx)
{
    int32_t q = 0;
    while (items[q] != idx)
        q++;
    for (; q + 1 < *n; q++)
        items[q] = items[q + 1];
    (*n)--;
}

/* A large body out of the walls' cells or the large list (the others keep their order). */
static void unplace_large(sim *m, m2c_sim_body *b)
{
    if (!b->placed) {
        remove_listed(m->large, &m->nlarge, b->idx);
        return;
    }
    int32_t nx = m->s->nx;
    for (int32_t jy = b->wcells[2]; jy <= b->wcells[3]; jy++) {
        for (int32_t jx = b->wcells[0]; jx <= b->wcells[1]; jx++) {
            m2c_sim_wall *c = &m->walls[(size_t)jy * (size_t)nx + (size_t)jx];
            remove_listed(c->items, &c->n, b->idx);
            wnear_add(m, jx, jy, -1);
        }
    }
    b->placed = 0;
}

/* Room for n more indices in m->near. */
static void near_room(sim *m, int32_t n)
{
    if ((size_t)m->nnear + (size_t)n > m->near_cap) {
        size_t cap = 2 * ((size_t)m->nnear + (size_t)n) + 16;
        int32_t *more = realloc(m->near, cap * sizeof *more);
        if (more == NULL)
            die(m, "out of memory (large bodies near)");
        m->near = more;
        m->near_cap = cap;
    }
}

/* Appends to m->near (when keep) the placed large bodies listed in the cells
 * x_lo..x_hi, y_lo..y_hi (clamped to the grid, rows then columns), but b and
 * those already carrying the current mark, and marks them. */
static void walls_in(sim *m, const m2c_sim_body *b, int32_t x_lo, int32_t x_hi, int32_t y_lo, int32_t y_hi,
                     int keep)
{
    const m2c_sim_scene *s = m->s;
    int32_t y0 = y_lo > 0 ? y_lo : 0, y1 = y_hi < s->ny - 1 ? y_hi : s->ny - 1;
    int32_t x0 = x_lo > 0 ? x_lo : 0, x1 = x_hi < s->nx - 1 ? x_hi : s->nx - 1;
    for (int32_t jy = y0; jy <= y1; jy++) {
        for (int32_t jx = x0; jx <= x1; jx++) {
            const m2c_sim_wall *c = &m->walls[(size_t)jy * (size_t)s->nx + (size_t)jx];
            for (int32_t k = 0; k < c->n; k++) {
                m2c_sim_body *o = &m->bodies[c->items[k]];
                if (o->seen != m->mark && o != b) {
                    o->seen = m->mark;
                    if (keep) {
                        near_room(m, 1);
                        m->near[m->nnear++] = o->idx;
                    }
                }
            }
        }
    }
}

static int by_index(const void *a, const void *b)
{
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return (x > y) - (x < y);
}

/* The large bodies b predicts against, into m->near (m->nnear of them):
 * those placed in its 3x3 cells and every one in the large list, each
 * once, but b, in index order. */
static void large_near(sim *m, const m2c_sim_body *b)
{
    m->nnear = 0;
    if (m->wnear[(size_t)b->cy * (size_t)m->s->nx + (size_t)b->cx] != 0) {     /* else no wall near */
        m->mark++;
        walls_in(m, b, b->cx - 1, b->cx + 1, b->cy - 1, b->cy + 1, 1);
    }
    near_room(m, m->nlarge);
    for (int32_t k = 0; k < m->nlarge; k++)
        if (m->large[k] != b->idx)
            m->near[m->nnear++] = m->large[k];
    if (m->nnear > 1)
        qsort(m->near, (size_t)m->nnear, sizeof *m->near, by_index);
}

/* ---- first valid root of one feature ----------------------------------------- */

/* What point_edge's contact must satisfy: the point lies on the segment. */
typedef struct pe_check {
    sim *m;
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
static int behind(sim *m, const m2c_sim_body *X, int32_t i, double t, double qx, double qy, double c, double sn,
                  double h)
{
    int32_t n = X->nverts;
    motion p = state_at(X, t);
    double lim = -m->s->tol;
    const int32_t ks[2] = { (i + n - 1) % n, (i + 1) % n };
    for (int l = 0; l < 2; l++) {
        const m2c_sim_vertex *v = &X->verts[ks[l]];
        double vc, vs;
        trig(VTRIG(m, v), p.ang + v->beta, &vc, &vs);
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
    motion p = state_at(k->X, t);
    double px = p.x, py = p.y;
    if (k->rho != 0.0) {
        double pc, ps;
        if (k->vx != NULL) {
            trig(VTRIG(k->m, k->vx), p.ang + k->beta, &pc, &ps);
        } else {
            pc = cos(p.ang + k->beta);
            ps = sin(p.ang + k->beta);
        }
        px = px + k->rho * pc;
        py = py + k->rho * ps;
    }
    motion q = state_at(k->Y, t);
    double c, sn;
    trig(ETRIG(k->m, k->ed), q.ang + k->ed->psi, &c, &sn);
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
static int touching_now(const double *c, int deg, double kappa)
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
    if (deg >= 1 && fabs(c[0]) <= kappa && touching_now(c, deg, kappa) && inside(chk, 0.0)) {
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

/* ---- features -------------------------------------------------------------------- */

/* Counts a circle_circle prediction of these 24 parameters: its variant
 * and the features counter. */
static inline __attribute__((always_inline)) void cc_count(sim *m, const double *g)
{
    int idx = circle_circle_variant(g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], g[9], g[10], g[11],
                                    g[12], g[13], g[14], g[15], g[16], g[17], g[18], g[19], g[20], g[21], g[22],
                                    g[23]);
    if (idx < 0)
        die(m, "circle_circle: the scene uses an effect the generated code leaves out");
    if (idx >= m->n_cc)
        die(m, "circle_circle: variant %d, but the build counts %d variants", idx, m->n_cc);
    m->cc_counts[idx]++;
    m->stats.features++;
}

/* circle_circle's coefficients for these 24 parameters; counts the variant. */
static int cc_coefficients(sim *m, const double *g, double *coef)
{
    cc_count(m, g);
    return circle_circle_coefficients(g[0], g[1], g[2], g[3], g[4], g[5], g[6], g[7], g[8], g[9], g[10], g[11],
                                      g[12], g[13], g[14], g[15], g[16], g[17], g[18], g[19], g[20], g[21],
                                      g[22], g[23], coef);
}

/* circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
 * circle's centre (v NULL) or of a polygon's vertex, at time now. */
static void circle_params(sim *m, const m2c_sim_body *b, double now, const m2c_sim_vertex *v, double *o)
{
    motion q = state_at(b, now);
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
            trig(VTRIG(m, v), phase, &c, &sn);
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
    motion q = state_at(b, now);
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
static int circles_gap(sim *m, const double *p1, double ra, const double *p2, double rb, double *coef)
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
static inline __attribute__((always_inline)) int circles_first_args(sim *m, const double *g, double w, double *out)
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

static int circles_first(sim *m, const double *p1, double ra, const double *p2, double rb, double w, double *out)
{
    double g[24];
    cc_args(p1, ra, p2, rb, g);
    return circles_first_args(m, g, w, out);
}

/* predict_cc of two circles that do not orbit (orbit 0: neither turns),
 * with circle_params' values written out: the same 24 parameters, bit for
 * bit (d = 0 sets the turn and the phase to 0), without its branches and
 * copies.  Most pairs of a gas are such. */
static int circles_plain(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, double *out)
{
    motion qa = state_at(A, now), qb = state_at(B, now);
    const double g[24] = { qa.x - qb.x, qa.vx - qb.vx, A->ax - B->ax, A->orbit, 0.0, HALF_PI,
                           qa.y - qb.y, qa.vy - qb.vy, A->ay - B->ay, 0.0, 0.0,
                           0.0, 0.0, 0.0, B->orbit, 0.0, HALF_PI, 0.0, 0.0, 0.0, 0.0, 0.0,
                           A->r, B->r };
    return circles_first_args(m, g, w, out);
}

/* Circle of A against circle of B (vb NULL, radius rb) or vertex vb of B (rb 0). */
static int predict_cc(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, const m2c_sim_vertex *vb, double rb,
                      double now, double w, double *out)
{
    double p1[11], p2[11];
    circle_params(m, A, now, NULL, p1);
    circle_params(m, B, now, vb, p2);
    return circles_first(m, p1, A->r, p2, rb, w, out);
}

/* The point_edge polynomial (its degree; coef[0]: the gap now) of a circle
 * of radius rad whose centre orbits X's centre at rho (phase beta in X's
 * frame) against the line of edge j of Y, in s = t - now. */
static int pe_coefficients(sim *m, const m2c_sim_body *X, const m2c_sim_body *Y, double rho, double beta,
                           double rad, int32_t j, double now, double *coef)
{
    const m2c_sim_vertex *ed = &Y->verts[j];
    motion q1 = state_at(X, now);
    motion q2 = state_at(Y, now);
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
        die(m, "point_edge: the scene uses an effect the generated code leaves out");
    if (idx >= m->n_pe)
        die(m, "point_edge: variant %d, but the build counts %d variants", idx, m->n_pe);
    m->pe_counts[idx]++;
    m->stats.features++;
    return point_edge_coefficients(px, u, ax, py, v, ay, rho, wr, phr, Y->om, phn, h, coef);
}

/* The first contact within [0, w] (1 with *out, else 0) of pe_coefficients'
 * polynomial whose point (X's centre, or rho, beta about it; vx: X's vertex
 * for its cos, sin cache, else NULL) lies on edge j's segment. */
static int pe_first(sim *m, const double *coef, int deg, const m2c_sim_body *X, const m2c_sim_body *Y,
                    const m2c_sim_vertex *vx, double rho, double beta, int32_t j, double now, double w, double *out)
{
    pe_check chk = { m, X, Y, vx, rho, beta, &Y->verts[j], now, m->s->tol };
    return first_contact(coef, deg, w, m->s->tol, &chk, out);
}

/* Point of X (circle centre with its radius, or vertex vx) against the line
 * of edge j of Y (none while a fixed body covers the edge: its cover is not
 * gone). */
static int predict_pe(sim *m, const m2c_sim_body *X, const m2c_sim_body *Y, const m2c_sim_vertex *vx, int32_t j,
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
    int deg = pe_coefficients(m, X, Y, rho, beta, rad, j, now, coef);
    return pe_first(m, coef, deg, X, Y, vx, rho, beta, j, now, w, out);
}

/* ---- pairs -------------------------------------------------------------------------- */

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
static int bounds_meet(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, double *meet)
{
    motion q1 = state_at(A, now);
    motion q2 = state_at(B, now);
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
static int bound_polygon(sim *m, const m2c_sim_body *T, const m2c_sim_body *P, double now, double w, double *meet)
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
            die(m, "out of memory (bound_polygon)");
        m->scratch_cap = (size_t)n;
    }
    double *coefs = m->scratch;
    int *deg = m->scratch_deg;
    int apart = 0;
    for (int32_t j = 0; j < n; j++) {
        deg[j] = pe_coefficients(m, T, P, 0.0, 0.0, T->bound, j, now, &coefs[(size_t)j * ROW]);
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
        circle_params(m, P, now, &P->verts[k], pv);
        if (circles_first(m, pt, T->bound, pv, 0.0, w, &t) && (!have || t < best)) {
            have = 1;
            best = t;
        }
    }
    *meet = best;
    return have;
}

static void circle_polygon(sim *m, const m2c_sim_body *C, const m2c_sim_body *P, double now, double w, best *bs)
{
    double t = 0.0;
    for (int32_t j = 0; j < P->nverts; j++) {
        int found = predict_pe(m, C, P, NULL, j, now, w, &t);
        better(bs, found, t, PE, C->idx, P->idx, -1, j);
    }
    for (int32_t k = 0; k < P->nverts; k++) {
        int found = predict_cc(m, C, P, &P->verts[k], 0.0, now, w, &t);
        better(bs, found, t, CC, C->idx, P->idx, -1, k);
    }
}

static void vertices_edges(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, best *bs)
{
    double t = 0.0;
    for (int32_t i = 0; i < A->nverts; i++) {
        for (int32_t j = 0; j < B->nverts; j++) {
            int found = predict_pe(m, A, B, &A->verts[i], j, now, w, &t);
            better(bs, found, t, PE, A->idx, B->idx, i, j);
        }
    }
}

static inline int grounded(const m2c_sim_body *G);

static void edge_line(const m2c_sim_body *P, int32_t j, double t, double *ox, double *oy, double *off);
static double separation(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double t);

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
static double reach(sim *m, const m2c_sim_body *b, double nx, double ny, double now)
{
    double px, py;
    if (!b->polygon) {
        point_at(m, b, NULL, now, &px, &py);
        return nx * px + ny * py + b->r;
    }
    double best = -INFINITY;
    for (int32_t k = 0; k < b->nverts; k++) {
        point_at(m, b, &b->verts[k], now, &px, &py);
        best = py_max(best, nx * px + ny * py);
    }
    return best;
}

/* clear_time along each edge normal of P (P does not turn, T does). */
static double clear_axes(sim *m, const m2c_sim_body *T, const m2c_sim_body *P, double now)
{
    motion q1 = state_at(T, now);
    motion q2 = state_at(P, now);
    double du = q1.vx - q2.vx, dv = q1.vy - q2.vy, dax = T->ax - P->ax, day = T->ay - P->ay;
    double spin = T->bound * turn_rate(T);
    double best = 0.0;
    for (int32_t j = 0; j < P->nverts; j++) {
        double ox, oy, off;
        edge_line(P, j, now, &ox, &oy, &off);
        double c = clear_root(-reach(m, T, -ox, -oy, now) - off - m->s->tol, spin - (ox * du + oy * dv),
                              fabs(ox * dax + oy * day));
        best = py_max(best, c);
    }
    return best;
}

/* How long (s) A and B surely stay more than the tolerance apart, from
 * their gap along a fixed unit axis now (0 when not apart now): each edge
 * normal of a polygon that does not turn against a body that does
 * (clear_axes), else the line of the centres and, with the norms |x| + |y|,
 * the best separating axis (docs/simulator.md, "Clear stretches"). */
static double clear_time(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double now)
{
    if (B->polygon && B->om == 0.0 && turn_rate(A) > 0.0)
        return clear_axes(m, A, B, now);
    if (A->polygon && A->om == 0.0 && turn_rate(B) > 0.0)
        return clear_axes(m, B, A, now);
    motion q1 = state_at(A, now);
    motion q2 = state_at(B, now);
    double dx = q2.x - q1.x, dy = q2.y - q1.y;
    double d = sqrt(dx * dx + dy * dy);
    if (!(d > 0.0))
        return 0.0;
    double nx = dx / d, ny = dy / d;
    double hi = reach(m, A, nx, ny, now);
    double lo = -reach(m, B, -nx, -ny, now);
    double spin = A->bound * turn_rate(A) + B->bound * turn_rate(B);
    double tol = m->s->tol;
    double along = clear_root(lo - hi - tol, spin - (nx * (q2.vx - q1.vx) + ny * (q2.vy - q1.vy)),
                              fabs(nx * (B->ax - A->ax) + ny * (B->ay - A->ay)));
    /* and along the best separating axis, which may turn: the norms, |x| + |y| */
    double anyway = clear_root(separation(m, A, B, now) - tol, spin + fabs(q2.vx - q1.vx) + fabs(q2.vy - q1.vy),
                               fabs(B->ax - A->ax) + fabs(B->ay - A->ay));
    return py_max(along, anyway);
}

/* The earliest contact of A's and B's features within [0, w] after now, into bs. */
static void features(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double now, double w, best *bs)
{
    if (!A->polygon && !B->polygon) {
        double t = 0.0;
        int found = predict_cc(m, A, B, NULL, B->r, now, w, &t);
        better(bs, found, t, CC, A->idx, B->idx, -1, -1);
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
static void predict_pair(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double now)
{
    const m2c_sim_scene *s = m->s;
    if (A->sup == B->idx || B->sup == A->idx)
        return;     /* the support's edge line separates them (both convex): only leaving ends it */
    if ((A->asleep && grounded(B)) || (B->asleep && grounded(A)))
        return;     /* a sleeper against a sleeper or an unmoving fixed body: nothing moves */
    m->stats.pairs++;
    if (!A->polygon && !B->polygon && A->orbit == 0.0 && B->orbit == 0.0) {
        /* two circles that do not turn (turn_rate 0): the loop below takes
         * one stage, features' predict_cc */
        double w = s->end - now, t = 0.0;
        if (w > 0.0 && circles_plain(m, A, B, now, w, &t))
            push_collision(m, now + t, CC, A, B, -1, -1);
        return;
    }
    double ta = turn_rate(A), tb = turn_rate(B);
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
            push_collision(m, now + bs.s, bs.feat, &m->bodies[bs.a], &m->bodies[bs.b], bs.i, bs.j);
            return;
        }
        if (ta == 0.0 && tb == 0.0)
            return;         /* nothing turns: the window was the whole run */
        now = now + w;
        windowed = 1;
    }
    if (now < s->end)
        push_horizon(m, now, A, B);
}

/* ---- per body ------------------------------------------------------------------------ */

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
static void schedule_cell(sim *m, const m2c_sim_body *b, double now)
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
            push_cell(m, b->tb + uy, b, 1, dy);
        else if (hx)
            push_cell(m, b->tb + ux, b, 0, dx);
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
        push_cell(m, b->tb + bu, b, baxis, bdir);
}

static int among(m2c_sim_body *const *xs, int32_t n, const m2c_sim_body *x)
{
    for (int32_t k = 0; k < n; k++)
        if (xs[k] == x)
            return 1;
    return 0;
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

static inline int keeps(const sim *m, const pair_filter *f, const m2c_sim_body *b, const m2c_sim_body *o)
{
    if (b->fixed && o->fixed)
        return 0;
    switch (f->only) {
    case PAIRS_AFTER:
        return o->idx > b->idx;
    case PAIRS_ISLAND:
        return !(o->island == f->island && o->idx < b->idx);
    case PAIRS_APART:
        return !among(m->clu.done, m->clu.ndone, o);
    default:
        return 1;
    }
}

/* predict_cells' second step: the pairs of b with the bodies of the n
 * gathered indices but b and skip that f keeps, in order (their two lines
 * fetched from memory first, so that the misses overlap). */
static inline __attribute__((always_inline)) void predict_gathered(sim *m, const m2c_sim_body *b,
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
            predict_pair(m, b, cand[q], now);
}

/* Predicts the pairs of b with every body in the cells x_lo..x_hi,
 * y_lo..y_hi (clamped to the grid) that f keeps, in the reference's order:
 * rows, then columns, then each cell's list.  The candidates are gathered
 * first, their bodies fetched from memory together, then predicted in that
 * order.  Inlined (with predict_near) where it is called with a filter
 * known there, so that the filter costs no test per candidate. */
static inline __attribute__((always_inline)) void predict_cells(sim *m, const m2c_sim_body *b, int32_t x_lo,
                                                                 int32_t x_hi, int32_t y_lo, int32_t y_hi,
                                                                 double now, const pair_filter *f)
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
            if (gather_inline(c, ids, &ni, CHUNK))
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

/* The first u in [lo, hi] (s) where p + v u + a u^2 / 2 crosses zero
 * moving in the direction (+1 up, -1 down): 1 with *out, or 0. */
static int first_crossing(double p, double v, double a, int direction, double lo, double hi, double *out)
{
    double c[3] = { p, v, 0.5 * a };
    for (int it = 0; it < 3; it++) {
        double u;
        if (m2c_smallest_root(c, 2, lo, hi, &u) != 1)
            return 0;
        if ((v + a * u) * (double)direction > 0.0) {
            *out = u;
            return 1;
        }
        lo = u;
    }
    return 0;
}

/* Supported b's motion relative to its support B along the edge, at b's
 * time: q (m) the centre's coordinate along the tangent from B's centre,
 * u (m/s), a (m/s^2) its speed and acceleration. */
static void support_relative(const sim *m, const m2c_sim_body *b, double *q, double *u, double *a)
{
    const m2c_sim_body *B = &m->bodies[b->sup];
    motion sb = state_at(B, b->tb);
    *q = (b->px - sb.x) * b->tx + (b->py - sb.y) * b->ty;
    *u = (b->vx - sb.vx) * b->tx + (b->vy - sb.vy) * b->ty;
    *a = (b->ax - B->ax) * b->tx + (b->ay - B->ay) * b->ty;
}

/* A supported body's stop (its tangential speed relative to the support
 * reaches zero) and leave (its centre, projected on the edge, reaches an
 * end) events. */
static void schedule_support(sim *m, const m2c_sim_body *b)
{
    double q, u, a;
    support_relative(m, b, &q, &u, &a);
    if (u != 0.0 && a != 0.0 && (u > 0.0) != (a > 0.0))
        push_stop(m, b->tb + -u / a, b);
    const m2c_sim_vertex *ed = &m->bodies[b->sup].verts[b->sup_edge];
    double hi = m->s->end - b->tb;
    double s1 = 0.0, s2 = 0.0;
    int h2 = first_crossing(q - ed->s2, u, a, 1, 0.0, hi, &s2);
    int h1 = first_crossing(q - ed->s1, u, a, -1, 0.0, hi, &s1);
    if (h1 && (!h2 || s1 < s2)) {
        s2 = s1;
        h2 = 1;
    }
    if (h2)
        push_leave(m, b->tb + s2, b);
}

/* A small body's pairs with its neighbours that f keeps (the bodies in
 * its 3x3 cells, then the large ones near), and its next cell crossing. */
static inline __attribute__((always_inline)) void predict_near(sim *m, const m2c_sim_body *b, double now,
                                                                const pair_filter *f)
{
    predict_cells(m, b, b->cx - 1, b->cx + 1, b->cy - 1, b->cy + 1, now, f);
    large_near(m, b);
    for (int32_t k = 0; k < m->nnear; k++) {
        const m2c_sim_body *o = &m->bodies[m->near[k]];
        if (o != f->skip && keeps(m, f, b, o))
            predict_pair(m, b, o, now);
    }
    schedule_cell(m, b, now);
}

/* Everything of b's future: its pairs with every neighbour but skip, its
 * cell crossing, its stop and leave on a fixed support. */
static void predict_body(sim *m, const m2c_sim_body *b, double now, const m2c_sim_body *skip)
{
    const pair_filter f = { PAIRS_ALL, skip, -1 };
    predict_near(m, b, now, &f);
    if (b->sup >= 0 && m->bodies[b->sup].fixed)
        schedule_support(m, b);     /* a carried body moves with its base: no stop, no leave of its own */
}

/* ---- handling events: trace lines and contacts ---------------------------------------- */

/* A time as m2c_sim_put_num writes it.  A collision's E line and its two
 * S lines write the same time (the bodies' tb is the event's t): the text
 * of the last one is kept and copied while the bits are the same. */
static inline char *put_time(sim *m, char *p, double t)
{
    uint64_t bits;
    memcpy(&bits, &t, sizeof bits);
    if (m->time_len == 0 || bits != m->time_bits) {
        m->time_len = m2c_sim_format_number(m->time_text, t);
        m->time_bits = bits;
    }
    memcpy(p, m->time_text, M2C_SIM_NUMBER_MAX);      /* a line has room for whole numbers */
    return p + m->time_len;
}

static void emit_state(sim *m, const m2c_sim_body *b)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, "S ");
    p = m2c_sim_put_int(p, b->idx);
    *p++ = ' ';
    p = put_time(m, p, b->tb);
    const double v[8] = { b->px, b->py, b->vx, b->vy, b->ang, b->om, b->ax, b->ay };
    for (int k = 0; k < 8; k++) {
        *p++ = ' ';
        p = m2c_sim_put_num(p, v[k]);
    }
    *p++ = '\n';
    m->out.n += (size_t)(p - start);
}

/* Contact point (cx, cy) and unit normal (nx, ny) from A to B of a feature
 * at t (both bodies advanced to t). */
static void contact_frame(sim *m, double t, int32_t feature, const m2c_sim_body *A, const m2c_sim_body *B,
                          int32_t i, int32_t j, double *cx, double *cy, double *nx, double *ny)
{
    const m2c_sim_vertex *vA = i >= 0 ? &A->verts[i] : NULL;
    if (feature == CC) {
        double ax_, ay_, bx_, by_;
        point_at(m, A, NULL, t, &ax_, &ay_);
        point_at(m, B, j >= 0 ? &B->verts[j] : NULL, t, &bx_, &by_);
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
        point_at(m, A, vA, t, &px, &py);
        double c, sn;
        trig(ETRIG(m, &B->verts[j]), B->ang + B->verts[j].psi, &c, &sn);
        *nx = -c;                       /* from A to B: against the edge's outward normal */
        *ny = -sn;
        double rad = vA == NULL ? A->r : 0.0;
        *cx = px + rad * *nx;
        *cy = py + rad * *ny;
    }
}

/* Normal relative velocity (m/s; B's against A's, along n from A to B) of
 * the material points at the contact: negative when approaching. */
static inline double normal_speed(const m2c_sim_body *A, const m2c_sim_body *B, double cx, double cy, double nx,
                                  double ny)
{
    double uax = A->vx - A->om * (cy - A->py);
    double uay = A->vy + A->om * (cx - A->px);
    double ubx = B->vx - B->om * (cy - B->py);
    double uby = B->vy + B->om * (cx - B->px);
    return (ubx - uax) * nx + (uby - uay) * ny;
}

/* ---- support: resting and sliding on a fixed body ----------------------------------------- */

/* Unit tangent (tx, ty) and outward unit normal (ox, oy) of edge j of B in
 * the world (B does not turn). */
static void support_frame(const m2c_sim_body *B, int32_t j, double *tx, double *ty, double *ox, double *oy)
{
    const m2c_sim_vertex *ed = &B->verts[j];
    double c = cos(B->ang);
    double s = sin(B->ang);
    *ox = c * ed->nx - s * ed->ny;
    *oy = s * ed->nx + c * ed->ny;
    *tx = -*oy;
    *ty = *ox;
}

static inline int is_static(const m2c_sim_body *B)
{
    return B->vx == 0.0 && B->vy == 0.0 && B->ax == 0.0 && B->ay == 0.0 && B->om == 0.0;
}

/* A neighbour of A's vertex i lies on edge j's line within the face
 * tolerance max(tol, rest_speed^2 / load): A rests on a face. */
static int flat(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t i, int32_t j, double ox, double oy,
                double load)
{
    double tol = m->s->tol, rest = m->s->rest_speed;
    double q = rest * rest / load;
    double ftol = q > tol ? q : tol;                                /* Python's max(tol, q) */
    int32_t n = A->nverts;
    double h = B->verts[j].h;
    const int32_t ks[2] = { (i + n - 1) % n, (i + 1) % n };
    for (int l = 0; l < 2; l++) {
        double px, py;
        point_at(m, A, &A->verts[ks[l]], A->tb, &px, &py);
        if ((px - B->px) * ox + (py - B->py) * oy - h <= ftol)
            return 1;
    }
    return 0;
}

/* A point-edge contact of movable A on edge j of a fixed polygon B that
 * does not turn (it may translate) becomes support, everything relative to
 * B (docs/simulator.md, Contact model); both advanced. */
static int can_support(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i, int32_t j,
                       double vn)
{
    if (feature != PE || A->fixed || !B->fixed || B->om != 0.0)
        return 0;
    double tx, ty, ox, oy;
    support_frame(B, j, &tx, &ty, &ox, &oy);
    double load = -((A->fax - B->ax) * ox + (A->fay - B->ay) * oy);
    double rest = m->s->rest_speed;
    if (!(load > 0.0) || vn >= rest || A->e * B->e * -vn >= rest)
        return 0;
    const m2c_sim_vertex *ed = &B->verts[j];
    double q = (A->px - B->px) * tx + (A->py - B->py) * ty;
    if (q < ed->s1 || q > ed->s2)
        return 0;
    /* at an end of the edge (within the tolerance) and moving past it: it
     * is leaving (a support would end at once, again and again) */
    double u = (A->vx - B->vx) * tx + (A->vy - B->vy) * ty;
    double tol = m->s->tol;
    if ((u > 0.0 && q >= ed->s2 - tol) || (u < 0.0 && q <= ed->s1 + tol))
        return 0;
    if (A->polygon) {
        if (fabs(A->om) * A->bound >= rest)
            return 0;
        return flat(m, A, B, i, j, ox, oy, load);
    }
    return 1;
}

/* Acceleration of supported A with tangential speed u relative to its
 * support B: the relative free acceleration along the edge less Coulomb
 * friction mu |a_n| against the relative motion; at relative rest, none
 * while friction can hold it; plus B's acceleration when B moves. */
static void slide_accel(const sim *m, m2c_sim_body *A, double u)
{
    const m2c_sim_body *B = &m->bodies[A->sup];
    double f = A->mu * B->mu * A->load;
    double a;
    if (u > 0.0)
        a = A->at - f;
    else if (u < 0.0)
        a = A->at + f;
    else if (A->at > f)
        a = A->at - f;
    else if (A->at < -f)
        a = A->at + f;
    else
        a = 0.0;
    if (is_static(B)) {
        A->ax = a * A->tx;
        A->ay = a * A->ty;
    } else {
        A->ax = B->ax + a * A->tx;
        A->ay = B->ay + a * A->ty;
    }
}

/* A (advanced to now, as B) keeps only its velocity relative to B along
 * the edge, stops turning, and from now on accelerates relative to B along
 * the edge only. */
static void enter_support(const sim *m, m2c_sim_body *A, const m2c_sim_body *B, int32_t j)
{
    double tx, ty, ox, oy;
    support_frame(B, j, &tx, &ty, &ox, &oy);
    double u = (A->vx - B->vx) * tx + (A->vy - B->vy) * ty;
    if (is_static(B)) {
        A->vx = u * tx;
        A->vy = u * ty;
    } else {
        A->vx = B->vx + u * tx;
        A->vy = B->vy + u * ty;
    }
    if (A->polygon)
        A->om = 0.0;
    A->sup = B->idx;
    A->sup_edge = j;
    A->tx = tx;
    A->ty = ty;
    A->load = -((A->fax - B->ax) * ox + (A->fay - B->ay) * oy);
    A->at = (A->fax - B->ax) * tx + (A->fay - B->ay) * ty;
    slide_accel(m, A, u);
}

/* A's support (or carrier) ends: its free acceleration again. */
static void end_support(sim *m, m2c_sim_body *A)
{
    m2c_sim_body *B = &m->bodies[A->sup];
    if (!B->fixed)
        B->carry--;
    A->ax = A->fax;
    A->ay = A->fay;
    A->sup = -1;
    A->sup_edge = -1;
}

/* Whether the bodies' accelerations push them together along the normal
 * (n from A to B): the relative normal acceleration of the centres is
 * negative.  (Centripetal terms of turning bodies are left out.) */
static inline int pressed(const m2c_sim_body *A, const m2c_sim_body *B, double nx, double ny)
{
    return (B->ax - A->ax) * nx + (B->ay - A->ay) * ny < 0.0;
}

/* The gap polynomial of the contact's feature (feature, i, j as in a
 * collision record: the one that predicted it), taken again at the contact
 * (A's time: both advanced), predicts this contact now (touching_now:
 * approaching, c1 < 0, or c2 < 0 and closing again before the gap exceeds
 * its kappa).  Its second derivative has the centripetal terms of a turn,
 * which `pressed` leaves out. */
static int closing(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i, int32_t j)
{
    double now = A->tb;
    double c[M2C_MAX_DEGREE + 1] = { 0.0 };
    int deg;
    double kappa;
    if (feature == CC) {
        const m2c_sim_vertex *vb = j >= 0 ? &B->verts[j] : NULL;
        double rb = vb == NULL ? B->r : 0.0;
        double p1[11], p2[11];
        circle_params(m, A, now, NULL, p1);
        circle_params(m, B, now, vb, p2);
        deg = circles_gap(m, p1, A->r, p2, rb, c);
        double tol = m->s->tol;
        kappa = tol * (2.0 * (A->r + rb) + tol);
    } else {
        if (i >= 0) {
            const m2c_sim_vertex *v = &A->verts[i];
            deg = pe_coefficients(m, A, B, v->rho, v->beta, 0.0, j, now, c);
        } else {
            deg = pe_coefficients(m, A, B, A->orbit, A->ophase, A->r, j, now, c);
        }
        kappa = m->s->tol;
    }
    return touching_now(c, deg, kappa);
}

/* A slow pressed contact (pressed, -vn < rest_speed): the bodies separate
 * at hop along n, paid from their relative motion at the contact, so the
 * pair's energy stays what it was: hop = rest_speed when kn Q pays it, else
 * sqrt(kn Q), but at least rest_speed / 32 (the energy that adds is paid
 * from the pair's common motion, pay_floor, else the hop sets unpaid).  u = (vn, vt) the relative
 * velocity of the material points in the frame (n, t), t = (-ny, nx), K the
 * contact's 2x2 inverse mass matrix (kn, knt; knt, kt), Q = u . K^-1 u; the
 * new relative velocity is (hop, x) with the same Q, through the impulse
 * P = K^-1 (u' - u).  Returns its normal part jn (kg m/s). */
/* A hop at the floor speed adds dE = need / 2 to the pair's energy (need =
 * (floor^2 - cap) / kn): it is paid from the pair's common motion, the
 * velocity V of its centre of mass (mass M), which an equal change of both
 * velocities scales by f = sqrt(1 - need / (M V^2)), leaving their relative
 * motion, hence the hop, untouched.  Not when a body of the pair is held
 * (fixed, or a sleeper held as fixed) or the common motion cannot pay it
 * (M V^2 <= need): 0, the hop then adds dE (unpaid); else 1. */
static int pay_floor(m2c_sim_body *A, m2c_sim_body *B, double need)
{
    if (A->inv_m == 0.0 || B->inv_m == 0.0)
        return 0;
    double ma = 1.0 / A->inv_m;
    double mb = 1.0 / B->inv_m;
    double mass = ma + mb;
    double vx = (ma * A->vx + mb * B->vx) / mass;
    double vy = (ma * A->vy + mb * B->vy) / mass;
    double e2 = mass * (vx * vx + vy * vy);
    if (!(e2 > need))
        return 0;
    double f = sqrt(1.0 - need / e2);
    double dx = vx * f - vx;
    double dy = vy * f - vy;
    A->vx = A->vx + dx;
    A->vy = A->vy + dy;
    B->vx = B->vx + dx;
    B->vy = B->vy + dy;
    return 1;
}

static double hop(sim *m, m2c_sim_body *A, m2c_sim_body *B, double cx, double cy, double nx, double ny,
                  double vn)
{
    double tx = -ny, ty = nx;
    double uax = A->vx - A->om * (cy - A->py);
    double uay = A->vy + A->om * (cx - A->px);
    double ubx = B->vx - B->om * (cy - B->py);
    double uby = B->vy + B->om * (cx - B->px);
    double vt = (ubx - uax) * tx + (uby - uay) * ty;
    double ran = (cx - A->px) * ny - (cy - A->py) * nx;
    double rbn = (cx - B->px) * ny - (cy - B->py) * nx;
    double rat = (cx - A->px) * ty - (cy - A->py) * tx;
    double rbt = (cx - B->px) * ty - (cy - B->py) * tx;
    double im = A->inv_m + B->inv_m;
    double kn = im + A->inv_i * ran * ran + B->inv_i * rbn * rbn;
    double kt = im + A->inv_i * rat * rat + B->inv_i * rbt * rbt;
    double knt = A->inv_i * ran * rat + B->inv_i * rbn * rbt;
    double det = kn * kt - knt * knt;
    double q = (kt * vn * vn - 2.0 * knt * vn * vt + kn * vt * vt) / det;
    double cap = kn * q;
    double rest = m->s->rest_speed;
    double floor_ = 0.03125 * rest;
    double h;
    if (cap >= rest * rest)
        h = rest;
    else if (cap >= floor_ * floor_)
        h = sqrt(cap);
    else
        h = floor_;
    double d = det * (cap - h * h);
    double root = d > 0.0 ? sqrt(d) : 0.0;
    double mid = knt * h;
    double x;
    if (vt * kn >= mid)
        x = (mid + root) / kn;
    else
        x = (mid - root) / kn;
    double dn = h - vn;
    double dt = x - vt;
    double jn = (kt * dn - knt * dt) / det;
    double jt = (kn * dt - knt * dn) / det;
    double px = jn * nx + jt * tx;
    double py = jn * ny + jt * ty;
    A->vx = A->vx - px * A->inv_m;
    A->vy = A->vy - py * A->inv_m;
    A->om = A->om - (jn * ran + jt * rat) * A->inv_i;
    B->vx = B->vx + px * B->inv_m;
    B->vy = B->vy + py * B->inv_m;
    B->om = B->om + (jn * rbn + jt * rbt) * B->inv_i;
    if (cap < floor_ * floor_ && !pay_floor(A, B, (floor_ * floor_ - cap) / kn))
        m->unpaid = 1;
    return jn;
}

/* The impulse (kg m/s) of a contact of the feature (feature, i, j) at
 * (cx, cy) with normal (nx, ny) from A to B (both advanced to the contact
 * time): 0 when the material points do not approach and are not pressed
 * together, else the normal impulse j (velocities changed).  A fast contact
 * is frictionless and leaves at sep = max(e |vn|, min(|vn|, rest_speed)); a
 * slow pressed one hops (hop).  When the material points do not approach,
 * the centres' accelerations do not press them and a body of the pair
 * turns, the feature's gap polynomial decides whether they are pressed
 * (closing: the turn closes the gap, which would otherwise predict the same
 * contact again at once).  Never adds energy (docs/simulator.md, Impulse). */
static double contact_impulse(sim *m, m2c_sim_body *A, m2c_sim_body *B, double cx, double cy, double nx, double ny,
                              int32_t feature, int32_t i, int32_t j)
{
    double vn = normal_speed(A, B, cx, cy, nx, ny);
    double rest = m->s->rest_speed;
    int press = pressed(A, B, nx, ny);
    if (!press && !(vn < 0.0) && (turn_rate(A) > 0.0 || turn_rate(B) > 0.0))
        press = closing(m, A, B, feature, i, j);
    if (press && -vn < rest)
        return hop(m, A, B, cx, cy, nx, ny, vn);
    double imp = 0.0;
    if (vn < 0.0) {
        double ran = (cx - A->px) * ny - (cy - A->py) * nx;
        double rbn = (cx - B->px) * ny - (cy - B->py) * nx;
        double k = A->inv_m + B->inv_m + A->inv_i * ran * ran + B->inv_i * rbn * rbn;
        double e = A->e * B->e;
        double evn = e * -vn;
        double nvn = -vn;
        double lim = rest < nvn ? rest : nvn;                               /* Python's min(-vn, rest) */
        double sep = lim > evn ? lim : evn;                                 /* Python's max(e * -vn, lim) */
        imp = (sep - vn) / k;
        A->vx = A->vx - imp * A->inv_m * nx;
        A->vy = A->vy - imp * A->inv_m * ny;
        A->om = A->om - imp * A->inv_i * ran;
        B->vx = B->vx + imp * B->inv_m * nx;
        B->vy = B->vy + imp * B->inv_m * ny;
        B->om = B->om + imp * B->inv_i * rbn;
    }
    return imp;
}

/* n . t of a supported body's edge tangent t (0 for a fixed body). */
static inline double along(const m2c_sim_body *b, double nx, double ny)
{
    if (b->sup < 0)
        return 0.0;
    return nx * b->tx + ny * b->ty;
}

/* A slow contact of bodies held on their supports: each supported (on a
 * fixed body: a carried body is not) or fixed, approaching (vn < 0) slower
 * than rest_speed, not pressed, and an impulse along their edges can change
 * vn (kh > 0). */
static int held(const sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double nx, double ny, double vn)
{
    const m2c_sim_body *bodies = m->bodies;
    if (!((A->fixed || (A->sup >= 0 && bodies[A->sup].fixed))
          && (B->fixed || (B->sup >= 0 && bodies[B->sup].fixed))))
        return 0;
    if (!(vn < 0.0) || !(-vn < m->s->rest_speed) || pressed(A, B, nx, ny))
        return 0;
    double ka = along(A, nx, ny);
    double kb = along(B, nx, ny);
    return A->inv_m * ka * ka + B->inv_m * kb * kb > 0.0;
}

/* The normal impulse j of a held contact (held): each supported body takes
 * only its part along its support's edge, dv = -+ j (n . t) t / m, and
 * keeps its support; the normal speed leaves at sep = max(e |vn|,
 * min(|vn|, rest_speed)) through kh = (n . tA)^2 / mA + (n . tB)^2 / mB.
 * The friction of each is set again for its new speed relative to its
 * support (slide_accel; support_relative: the support may move). */
static double held_impulse(const sim *m, m2c_sim_body *A, m2c_sim_body *B, double nx, double ny, double vn)
{
    double ka = along(A, nx, ny);
    double kb = along(B, nx, ny);
    double k = A->inv_m * ka * ka + B->inv_m * kb * kb;
    double e = A->e * B->e;
    double evn = e * -vn;
    double nvn = -vn;
    double lim = m->s->rest_speed < nvn ? m->s->rest_speed : nvn;      /* Python's min(-vn, rest) */
    double sep = lim > evn ? lim : evn;                                 /* Python's max(e * -vn, lim) */
    double imp = (sep - vn) / k;
    if (A->sup >= 0) {
        double d = imp * A->inv_m * ka;
        A->vx = A->vx - d * A->tx;
        A->vy = A->vy - d * A->ty;
        double q, u, a;
        support_relative(m, A, &q, &u, &a);
        slide_accel(m, A, u);
    }
    if (B->sup >= 0) {
        double d = imp * B->inv_m * kb;
        B->vx = B->vx + d * B->tx;
        B->vy = B->vy + d * B->ty;
        double q, u, a;
        support_relative(m, B, &q, &u, &a);
        slide_accel(m, B, u);
    }
    return imp;
}

/* ---- event handlers: one per kind ------------------------------------------------------ */

/* An E line of a contact: collision or support. */
static void emit_contact(sim *m, const char *kind, double t, const m2c_sim_body *A, const m2c_sim_body *B,
                         int32_t feature, int32_t i, int32_t j, double cx, double cy, double nx, double ny,
                         double imp)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, kind);
    p = put_time(m, p, t);
    const long long ints[5] = { A->idx, B->idx, feature, i, j };
    for (int k = 0; k < 5; k++) {
        *p++ = ' ';
        p = m2c_sim_put_int(p, ints[k]);
    }
    const double nums[5] = { cx, cy, nx, ny, imp };
    for (int k = 0; k < 5; k++) {
        *p++ = ' ';
        p = m2c_sim_put_num(p, nums[k]);
    }
    *p++ = '\n';
    m->out.n += (size_t)(p - start);
}

/* An E line of a supported body's event: stop or leave (edge of sup). */
static void emit_support_change(sim *m, const char *kind, double t, const m2c_sim_body *A, int32_t sup,
                                int32_t edge)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, kind);
    p = m2c_sim_put_num(p, t);
    *p++ = ' ';
    p = m2c_sim_put_int(p, A->idx);
    *p++ = ' ';
    p = m2c_sim_put_int(p, sup);
    p = m2c_sim_put_str(p, " -1 -1 ");
    p = m2c_sim_put_int(p, edge);
    p = m2c_sim_put_str(p, " 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
}

/* ---- carried: at rest on a movable body that does not turn ------------------------------------ */

/* A point-edge contact of movable A on edge j of a movable polygon B that
 * does not turn and is itself supported or carried (its motion a
 * polynomial: constant acceleration) becomes carrying (docs/simulator.md,
 * "Carried bodies"); both advanced.  As can_support, everything relative
 * to B: load = -((fa - aB) . o) > 0, slow (vn < rest_speed, eA eB (-vn) <
 * rest_speed), A's centre over the edge; and A at relative rest along it
 * (u = (vA - vB) . t, u^2 < rest_speed^2) where static friction holds it
 * (|at| <= muA muB load, at = (fa - aB) . t), B not carried by A (no loop),
 * and |vB|^2 <= |vA|^2: taking B's velocity never raises A's kinetic
 * energy.  A polygon also turns slower than rest_speed / bound and lies on
 * a face (flat). */
static int can_carry(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i, int32_t j,
                     double vn)
{
    if (feature != PE || A->fixed || B->fixed || !B->polygon || B->om != 0.0 || B->sup < 0)
        return 0;
    for (int32_t k = B->sup; k >= 0; k = m->bodies[k].sup)
        if (k == A->idx)
            return 0;
    double tx, ty, ox, oy;
    support_frame(B, j, &tx, &ty, &ox, &oy);
    double load = -((A->fax - B->ax) * ox + (A->fay - B->ay) * oy);
    double rest = m->s->rest_speed;
    if (!(load > 0.0) || vn >= rest || A->e * B->e * -vn >= rest)
        return 0;
    const m2c_sim_vertex *ed = &B->verts[j];
    double q = (A->px - B->px) * tx + (A->py - B->py) * ty;
    if (q < ed->s1 || q > ed->s2)
        return 0;
    double u = (A->vx - B->vx) * tx + (A->vy - B->vy) * ty;
    if (!(u * u < rest * rest))
        return 0;
    double at = (A->fax - B->ax) * tx + (A->fay - B->ay) * ty;
    double f = A->mu * B->mu * load;
    if (at > f || at < -f)
        return 0;
    if (B->vx * B->vx + B->vy * B->vy > A->vx * A->vx + A->vy * A->vy)
        return 0;
    if (A->polygon) {
        if (fabs(A->om) * A->bound >= rest)
            return 0;
        return flat(m, A, B, i, j, ox, oy, load);
    }
    return 1;
}

/* A (advanced to now, as B) moves with B from now on: B's velocity and
 * acceleration exactly (its offset from B constant), no turn. */
static void enter_carried(m2c_sim_body *A, m2c_sim_body *B, int32_t j)
{
    double tx, ty, ox, oy;
    support_frame(B, j, &tx, &ty, &ox, &oy);
    A->vx = B->vx;
    A->vy = B->vy;
    if (A->polygon)
        A->om = 0.0;
    A->sup = B->idx;
    A->sup_edge = j;
    A->tx = tx;
    A->ty = ty;
    A->load = -((A->fax - B->ax) * ox + (A->fay - B->ay) * oy);
    A->at = (A->fax - B->ax) * tx + (A->fay - B->ay) * ty;
    A->ax = B->ax;
    A->ay = B->ay;
    B->carry++;
}

/* The bodies that left their support or carrier at one instant (leave), in
 * the order they left, each with the body its prediction skips (-1: none). */
typedef struct left_list {
    int32_t n, cap;
    int32_t *body, *skip;
} left_list;

static void left_push(sim *m, left_list *l, int32_t body, int32_t skip)
{
    if (l->n == l->cap) {
        int32_t cap = l->cap ? 2 * l->cap : 8;
        int32_t *b = realloc(l->body, (size_t)cap * sizeof *b);
        if (b == NULL)
            die(m, "out of memory");
        l->body = b;
        int32_t *k = realloc(l->skip, (size_t)cap * sizeof *k);
        if (k == NULL)
            die(m, "out of memory");
        l->skip = k;
        l->cap = cap;
    }
    l->body[l->n] = body;
    l->skip[l->n] = skip;
    l->n++;
}

static void release(sim *m, const m2c_sim_body *B, double t, left_list *left);

/* A leaves its support or carrier at t (E leave, its state: world velocity
 * kept, free acceleration), then what A carries, depth-first (release);
 * each appended to left with the body its prediction skips
 * (predict_released). */
static void leave(sim *m, m2c_sim_body *A, double t, const m2c_sim_body *skip, left_list *left)
{
    m->stats.leaves++;
    advance(A, t);
    int32_t sup = A->sup, edge = A->sup_edge;
    end_support(m, A);
    m->stamp[A->idx]++;
    emit_support_change(m, "E leave ", t, A, sup, edge);
    emit_state(m, A);
    left_push(m, left, A->idx, skip == NULL ? -1 : skip->idx);
    release(m, A, t, left);
}

/* B's motion changes at t: every body B carries leaves (by index, each with
 * what it carries: leave), skipping B in its prediction. */
static void release(sim *m, const m2c_sim_body *B, double t, left_list *left)
{
    if (B->carry == 0)
        return;
    for (int32_t k = 0; k < m->s->nbodies; k++) {
        m2c_sim_body *A = &m->bodies[k];
        if (A->sup == B->idx)
            leave(m, A, t, B, left);
    }
}

/* Predict the bodies that left (leave), in the order they left, each but
 * against the body it skips (already predicted with it); frees the list. */
static void predict_released(sim *m, left_list *left, double t)
{
    for (int32_t k = 0; k < left->n; k++)
        predict_body(m, &m->bodies[left->body[k]], t, left->skip[k] < 0 ? NULL : &m->bodies[left->skip[k]]);
    free(left->body);
    free(left->skip);
    left->body = left->skip = NULL;
    left->n = left->cap = 0;
}

/* ---- sleeping islands ------------------------------------------------------------------------ */

/* A body others can fall asleep on: asleep, or fixed and unmoving. */
static inline int grounded(const m2c_sim_body *G)
{
    return G->asleep || (G->fixed && is_static(G));
}

/* A body supported by an unmoving body, slower than rest_speed along its
 * edge, that static friction would hold there (|at| <= mu load, as in
 * slide_accel at u = 0; on a level frictionless edge at = 0): it stays
 * where it is.  On a moving support: never (it does not sleep); nor on a
 * movable one (carried: grounded is false while it carries). */
static int at_rest(const sim *m, const m2c_sim_body *A)
{
    const m2c_sim_body *B = &m->bodies[A->sup];
    if (!grounded(B))
        return 0;
    double u = A->vx * A->tx + A->vy * A->ty;
    double rest = m->s->rest_speed;
    if (!(u * u < rest * rest))
        return 0;
    double f = A->mu * B->mu * A->load;
    return !(A->at > f) && !(A->at < -f);
}

/* Awake movable M, one body of the collision ev with grounded G (both
 * advanced; (nx, ny) the contact's unit normal from a to b, vn its normal
 * speed), falls asleep on G: M's free acceleration presses it onto G, the
 * contact is slow, M's speed across the normal is below rest_speed, and a
 * polygon M turns slowly and lies on a face (docs/simulator.md). */
static int can_sleep(sim *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev, double nx,
                     double ny, double vn)
{
    if (M->fixed || M->asleep || !grounded(G))
        return 0;
    double mx, my;
    if (M->idx == ev->u.collision.a) {
        mx = nx;
        my = ny;
    } else {
        mx = -nx;
        my = -ny;
    }
    double rest = m->s->rest_speed;
    double load = M->fax * mx + M->fay * my;
    if (!(load > 0.0) || vn >= rest || M->e * G->e * -vn >= rest)
        return 0;
    double ut = M->vy * mx - M->vx * my;
    if (ut * ut >= rest * rest)
        return 0;
    if (M->polygon) {
        if (fabs(M->om) * M->bound >= rest || ev->u.collision.feature != PE || ev->u.collision.i < 0)
            return 0;
        return flat(m, &m->bodies[ev->u.collision.a], &m->bodies[ev->u.collision.b], ev->u.collision.i,
                    ev->u.collision.j, -nx, -ny, load);
    }
    return 1;
}

/* The impulse of a contact of A and B, one of them (S) asleep: first with
 * S held as if fixed (its 1/m and 1/I zero); when that impulse would change
 * the normal speed of S's material point by less than rest_speed and no
 * hop of it was unpaid, it
 * stands (S stays asleep, unchanged: a gentle touch); else the other
 * body's velocity is restored and the full impulse is applied (S moves:
 * jolted, its island wakes).  When the other body is fixed (it moves or
 * turns: a sleeper is never predicted against an unmoving one) S cannot be
 * held (the pair would have no mass): the full impulse at once.  Returns
 * the impulse applied. */
static double sleeper_impulse(sim *m, m2c_sim_body *A, m2c_sim_body *B, double cx, double cy, double nx,
                              double ny, int32_t feature, int32_t i, int32_t j)
{
    m2c_sim_body *S = A->asleep ? A : B;
    m2c_sim_body *M = A->asleep ? B : A;
    if (M->fixed)
        return contact_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
    double vx = M->vx, vy = M->vy, om = M->om;
    double inv_m = S->inv_m, inv_i = S->inv_i;
    S->inv_m = 0.0;
    S->inv_i = 0.0;
    m->unpaid = 0;
    double imp = contact_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
    S->inv_m = inv_m;
    S->inv_i = inv_i;
    double rsn = (cx - S->px) * ny - (cy - S->py) * nx;
    if (imp * (S->inv_m + S->inv_i * rsn * rsn) < m->s->rest_speed && !m->unpaid)
        return imp;
    M->vx = vx;
    M->vy = vy;
    M->om = om;
    return contact_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
}

/* A sleeper an impulse has set moving. */
static inline int jolted(const m2c_sim_body *S)
{
    return S->vx != 0.0 || S->vy != 0.0 || S->om != 0.0;
}

/* An E line of a sleep or wake: body a, body b (-1 for a wake), island. */
static void emit_island(sim *m, const char *kind, double t, int32_t a, int32_t b, int32_t island)
{
    if (m->out.f == NULL)
        return;
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, kind);
    p = m2c_sim_put_num(p, t);
    *p++ = ' ';
    p = m2c_sim_put_int(p, a);
    *p++ = ' ';
    p = m2c_sim_put_int(p, b);
    p = m2c_sim_put_str(p, " -1 -1 ");
    p = m2c_sim_put_int(p, island);
    p = m2c_sim_put_str(p, " 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
}

/* A (advanced to t) falls asleep resting on G: frozen (v = a = w = 0) in
 * G's island, or in a new one numbered A's index when G is fixed.  Its
 * awake neighbours are predicted against it again. */
static void handle_sleep(sim *m, m2c_sim_body *A, const m2c_sim_body *G, double t)
{
    m->stats.sleeps++;
    if (A->sup >= 0)
        end_support(m, A);
    A->vx = 0.0;
    A->vy = 0.0;
    A->om = 0.0;
    A->ax = 0.0;
    A->ay = 0.0;
    A->asleep = 1;
    A->island = G->asleep ? G->island : A->idx;
    m->stamp[A->idx]++;
    emit_island(m, "E sleep ", t, A->idx, G->idx, A->island);
    emit_state(m, A);
    left_list left = { 0 };
    release(m, A, t, &left);
    predict_body(m, A, t, NULL);
    predict_released(m, &left, t);
}

/* predict_body for a member of a waking island: a pair of two members is
 * predicted by the one with the smaller index.  (A member moves, since no
 * fixed body sleeps, so keeps' test of two fixed bodies never drops its
 * pair with a large body.)  No stop or leave events here. */
static void predict_woken(sim *m, const m2c_sim_body *b, double now, int32_t island)
{
    const pair_filter f = { PAIRS_ISLAND, NULL, island };
    predict_near(m, b, now, &f);
}

/* S's island wakes at t: every member (by index) gets its free
 * acceleration back, then fresh predictions (a pair of members once). */
static void handle_wake(sim *m, const m2c_sim_body *S, double t)
{
    m->stats.wakes++;
    int32_t island = S->island;
    emit_island(m, "E wake ", t, S->idx, -1, island);
    int32_t n = m->s->nbodies;
    for (int32_t k = 0; k < n; k++) {
        m2c_sim_body *b = &m->bodies[k];
        if (b->asleep && b->island == island) {
            advance(b, t);
            b->asleep = 0;
            b->ax = b->fax;
            b->ay = b->fay;
            m->stamp[b->idx]++;
            emit_state(m, b);
        }
    }
    for (int32_t k = 0; k < n; k++)
        if (m->bodies[k].island == island)
            predict_woken(m, &m->bodies[k], t, island);
    for (int32_t k = 0; k < n; k++)
        if (m->bodies[k].island == island)
            m->bodies[k].island = -1;
}

/* ---- simultaneous contacts: a contact met again at one instant ------------------------------ */

/* how many times one contact is handled at one instant before it and the
 * contacts it touches are solved together; the most sweeps of the cluster's
 * sequential impulses, and the sweep that ends them: no impulse in it
 * changed a normal speed by more than CLUSTER_TOL rest_speed */
#define CLUSTER_REPEATS 64
#define CLUSTER_SWEEPS 100
#define CLUSTER_TOL 1e-9
/* the separation speed (times rest_speed) of a cluster's contact that nothing
 * presses: above the rounding of a normal speed, so that it is not met again at once */
#define CLUSTER_APART 0x1p-20
/* the angle (rad) within which one push holds a free acceleration (wedged) */
#define HOLD_TOL 1e-9
/* a body's part in a cluster's solve: held (fixed, or asleep: infinite mass),
 * free, or sliding on a fixed body's edge (moves along the edge only) */
enum { HELD = 0, FREE = 1, SLIDER = 2 };

/* Count a contact handled at t (an E collision or E support line). */
static void touch(sim *m, double t, int32_t a, int32_t b, int32_t feature, int32_t i, int32_t j)
{
    if (t != m->touched_t) {
        m->touched_t = t;
        m->ntouched = 0;
    }
    for (int32_t k = 0; k < m->ntouched; k++) {
        m2c_sim_touch *c = &m->touched[k];
        if (c->a == a && c->b == b && c->feature == feature && c->i == i && c->j == j) {
            c->times++;
            return;
        }
    }
    if (m->ntouched == m->touched_cap) {
        int32_t cap = m->touched_cap ? 2 * m->touched_cap : 16;
        m2c_sim_touch *more = realloc(m->touched, (size_t)cap * sizeof *more);
        if (more == NULL)
            die(m, "out of memory");
        m->touched = more;
        m->touched_cap = cap;
    }
    m->touched[m->ntouched++] = (m2c_sim_touch){ a, b, feature, i, j, 1 };
}

/* The collision's contact (a, b, feature, i, j) was handled
 * CLUSTER_REPEATS times already at this instant: other contacts keep
 * undoing its impulse (a settling pile meets one contact up to 32 times at
 * one instant and goes on: ball-pit.json). */
static int repeated(const sim *m, const m2c_sim_event *ev)
{
    if (ev->t != m->touched_t)
        return 0;
    for (int32_t k = 0; k < m->ntouched; k++) {
        const m2c_sim_touch *c = &m->touched[k];
        if (c->a == ev->u.collision.a && c->b == ev->u.collision.b && c->feature == ev->u.collision.feature
            && c->i == ev->u.collision.i && c->j == ev->u.collision.j)
            return c->times >= CLUSTER_REPEATS;
    }
    return 0;
}

/* A body that links a cluster's contacts: movable and awake (fixed bodies
 * and sleepers are held: the cluster ends at them). */
static inline int joins(const m2c_sim_body *b)
{
    return !b->fixed && !b->asleep;
}

/* Room in the cluster's scratch for n contacts and nb bodies. */
static void cluster_room(sim *m, int32_t n, int32_t nb)
{
    m2c_sim_cluster *c = &m->clu;
    if (n > c->cap) {
        int32_t cap = c->cap ? c->cap : 8;
        while (cap < n)
            cap *= 2;
        m2c_sim_row *rows = realloc(c->rows, (size_t)cap * sizeof *rows);
        if (rows != NULL)
            c->rows = rows;
        double *acc = realloc(c->acc, (size_t)cap * sizeof *acc);
        if (acc != NULL)
            c->acc = acc;
        double *acc2 = realloc(c->acc2, (size_t)cap * sizeof *acc2);
        if (acc2 != NULL)
            c->acc2 = acc2;
        double *target = realloc(c->target, (size_t)cap * sizeof *target);
        if (target != NULL)
            c->target = target;
        double *pushes = realloc(c->pushes, (size_t)(cap + 1) * 4 * sizeof *pushes);
        if (pushes != NULL)
            c->pushes = pushes;
        if (rows == NULL || acc == NULL || acc2 == NULL || target == NULL || pushes == NULL)
            die(m, "out of memory");
        c->cap = cap;
    }
    if (nb > c->bcap) {
        int32_t cap = c->bcap ? c->bcap : 16;
        while (cap < nb)
            cap *= 2;
        int32_t *inside = realloc(c->inside, (size_t)cap * sizeof *inside);
        if (inside != NULL)
            c->inside = inside;
        m2c_sim_body **movers = realloc(c->movers, (size_t)cap * sizeof *movers);
        if (movers != NULL)
            c->movers = movers;
        m2c_sim_body **done = realloc(c->done, (size_t)cap * sizeof *done);
        if (done != NULL)
            c->done = done;
        double *saved = realloc(c->saved, (size_t)cap * 3 * sizeof *saved);
        if (saved != NULL)
            c->saved = saved;
        double *v2 = realloc(c->v2, (size_t)cap * 3 * sizeof *v2);
        if (v2 != NULL)
            c->v2 = v2;
        double *vs = realloc(c->vs, (size_t)cap * 3 * sizeof *vs);
        if (vs != NULL)
            c->vs = vs;
        if (inside == NULL || movers == NULL || done == NULL || saved == NULL || v2 == NULL || vs == NULL)
            die(m, "out of memory");
        c->bcap = cap;
    }
}

static void cluster_free(m2c_sim_cluster *c)
{
    free(c->rows);
    free(c->acc);
    free(c->acc2);
    free(c->target);
    free(c->pushes);
    free(c->inside);
    free(c->movers);
    free(c->done);
    free(c->saved);
    free(c->v2);
    free(c->vs);
}

static int listed(const int32_t *xs, int32_t n, int32_t x)
{
    for (int32_t k = 0; k < n; k++)
        if (xs[k] == x)
            return 1;
    return 0;
}

/* The contacts handled at this instant (touched, in the order first
 * handled) that reach the collision's bodies through bodies that join, into
 * the scratch's rows (bodies and feature only; clu.n of them). */
static void cluster(sim *m, const m2c_sim_event *ev)
{
    m2c_sim_cluster *c = &m->clu;
    cluster_room(m, m->ntouched, 2 * m->ntouched + 2);
    int32_t first[2] = { ev->u.collision.a, ev->u.collision.b };
    c->ninside = 0;
    for (int q = 0; q < 2; q++)
        if (joins(&m->bodies[first[q]]))
            c->inside[c->ninside++] = first[q];
    int grow = 1;
    while (grow) {
        grow = 0;
        for (int32_t k = 0; k < m->ntouched; k++) {
            const m2c_sim_touch *t = &m->touched[k];
            if (listed(c->inside, c->ninside, t->a) || listed(c->inside, c->ninside, t->b)) {
                int32_t both[2] = { t->a, t->b };
                for (int q = 0; q < 2; q++) {
                    if (!listed(c->inside, c->ninside, both[q]) && joins(&m->bodies[both[q]])) {
                        c->inside[c->ninside++] = both[q];
                        grow = 1;
                    }
                }
            }
        }
    }
    c->n = 0;
    for (int32_t k = 0; k < m->ntouched; k++) {
        const m2c_sim_touch *t = &m->touched[k];
        if (listed(c->inside, c->ninside, t->a) || listed(c->inside, c->ninside, t->b)) {
            m2c_sim_row *r = &c->rows[c->n++];
            r->A = &m->bodies[t->a];
            r->B = &m->bodies[t->b];
            r->feature = t->feature;
            r->i = t->i;
            r->j = t->j;
        }
    }
}

/* b's part in a cluster's solve: HELD (fixed or asleep), SLIDER (supported
 * on a fixed body: it moves along the edge only, as in held_impulse) or
 * FREE. */
static int part(const sim *m, const m2c_sim_body *b)
{
    if (b->fixed || b->asleep)
        return HELD;
    if (b->sup >= 0 && m->bodies[b->sup].fixed)
        return SLIDER;
    return FREE;
}

/* How much a unit impulse along n at the contact (rn: the contact's arm
 * across n) changes b's normal speed there. */
static double give(const sim *m, const m2c_sim_body *b, double nx, double ny, double rn)
{
    int p = part(m, b);
    if (p == HELD)
        return 0.0;
    if (p == SLIDER) {
        double k = nx * b->tx + ny * b->ty;
        return b->inv_m * k * k;
    }
    return b->inv_m + b->inv_i * rn * rn;
}

/* An impulse j along n on b at the contact (rn its arm across n). */
static void nudge(const sim *m, m2c_sim_body *b, double j, double nx, double ny, double rn)
{
    int p = part(m, b);
    if (p == HELD)
        return;
    if (p == SLIDER) {
        double d = j * b->inv_m * (nx * b->tx + ny * b->ty);
        b->vx = b->vx + d * b->tx;
        b->vy = b->vy + d * b->ty;
        return;
    }
    b->vx = b->vx + j * b->inv_m * nx;
    b->vy = b->vy + j * b->inv_m * ny;
    b->om = b->om + j * b->inv_i * rn;
}

/* Sequential impulses over the cluster's contacts (in order): each
 * contact's accumulated normal impulse acc[k] moves so that its normal
 * speed becomes target[k], but never below zero (a contact only pushes);
 * sweep after sweep until no impulse of a sweep changed a normal speed by
 * more than CLUSTER_TOL rest_speed, at most CLUSTER_SWEEPS sweeps. */
static void sweeps(sim *m, double *acc, const double *target)
{
    const m2c_sim_cluster *c = &m->clu;
    double tol = CLUSTER_TOL * m->s->rest_speed;
    for (int s = 0; s < CLUSTER_SWEEPS; s++) {
        double big = 0.0;
        for (int32_t k = 0; k < c->n; k++) {
            const m2c_sim_row *r = &c->rows[k];
            if (!(r->kn > 0.0))
                continue;
            double vn = normal_speed(r->A, r->B, r->cx, r->cy, r->nx, r->ny);
            double nw = acc[k] + (target[k] - vn) / r->kn;
            if (nw < 0.0)
                nw = 0.0;
            double dj = nw - acc[k];
            acc[k] = nw;
            nudge(m, r->A, -dj, r->nx, r->ny, r->ran);
            nudge(m, r->B, dj, r->nx, r->ny, r->rbn);
            double ch = fabs(dj) * r->kn;
            if (ch > big)
                big = ch;
        }
        if (big <= tol)
            return;
    }
}

/* The kinetic energy (J) of the movers (linear, and turning where 1/I > 0). */
static double kinetic(const sim *m)
{
    const m2c_sim_cluster *c = &m->clu;
    double e = 0.0;
    for (int32_t k = 0; k < c->nmovers; k++) {
        const m2c_sim_body *b = c->movers[k];
        e = e + 0.5 * (b->vx * b->vx + b->vy * b->vy) / b->inv_m;
        if (b->inv_i > 0.0)
            e = e + 0.5 * b->om * b->om / b->inv_i;
    }
    return e;
}

static void velocities(const sim *m, double *vs)
{
    const m2c_sim_cluster *c = &m->clu;
    for (int32_t k = 0; k < c->nmovers; k++) {
        vs[3 * k] = c->movers[k]->vx;
        vs[3 * k + 1] = c->movers[k]->vy;
        vs[3 * k + 2] = c->movers[k]->om;
    }
}

static void set_velocities(sim *m, const double *vs)
{
    const m2c_sim_cluster *c = &m->clu;
    for (int32_t k = 0; k < c->nmovers; k++) {
        c->movers[k]->vx = vs[3 * k];
        c->movers[k]->vy = vs[3 * k + 1];
        c->movers[k]->om = vs[3 * k + 2];
    }
}

/* The largest mu in [0, 1] for which the movers' velocities
 * v1 + mu (v - v1) (v: theirs now, v1 as given; the kinetic energy at v1
 * at most budget) have a kinetic energy at most budget: with a the energy
 * of the change, b the cross term and e1 the energy at v1,
 * a mu^2 + b mu <= budget - e1. */
static double mix(const sim *m, const double *v1, double budget)
{
    const m2c_sim_cluster *c = &m->clu;
    double a = 0.0, b = 0.0, e1 = 0.0;
    for (int32_t k = 0; k < c->nmovers; k++) {
        const m2c_sim_body *q = c->movers[k];
        double vx = v1[3 * k], vy = v1[3 * k + 1], om = v1[3 * k + 2];
        double dx = q->vx - vx;
        double dy = q->vy - vy;
        a = a + 0.5 * (dx * dx + dy * dy) / q->inv_m;
        b = b + (vx * dx + vy * dy) / q->inv_m;
        e1 = e1 + 0.5 * (vx * vx + vy * vy) / q->inv_m;
        if (q->inv_i > 0.0) {
            double dw = q->om - om;
            a = a + 0.5 * dw * dw / q->inv_i;
            b = b + om * dw / q->inv_i;
            e1 = e1 + 0.5 * om * om / q->inv_i;
        }
    }
    if (!(a > 0.0))
        return 1.0;
    double spare = budget - e1;
    if (spare < 0.0)
        spare = 0.0;
    double root = sqrt(b * b + 4.0 * a * spare);
    double mu;
    if (b > 0.0)
        mu = 2.0 * spare / (b + root);
    else
        mu = (root - b) / (2.0 * a);
    return mu < 1.0 ? mu : 1.0;
}

/* A contact of the cluster that must separate: its bodies' accelerations
 * press them together (pressed) or, a body turning, its gap closes now
 * (closing), as contact_impulse decides. */
static int pressing_contact(sim *m, const m2c_sim_row *r)
{
    if (pressed(r->A, r->B, r->nx, r->ny))
        return 1;
    if (turn_rate(r->A) > 0.0 || turn_rate(r->B) > 0.0)
        return closing(m, r->A, r->B, r->feature, r->i, r->j);
    return 0;
}

/* The cluster's joint impulses (docs/simulator.md, "Contact model:
 * simultaneous contacts") into clu.acc, the movers and their velocities
 * before into clu.movers and clu.saved: inelastic sequential impulses
 * (target normal speed 0: kinetic energy e1); then the pressed contacts
 * separate at rest_speed (the others at CLUSTER_APART rest_speed):
 * sequential impulses from v1 (v2), taken when they cost no more than e1;
 * else the same from the movers at rest (vs, energy es), mixed towards v2
 * as far as e1 pays (mix) when es <= e1, else vs scaled to energy e1. */
static void solve_cluster(sim *m, double t)
{
    m2c_sim_cluster *c = &m->clu;
    int32_t n = c->n;
    for (int32_t k = 0; k < n; k++) {
        m2c_sim_row *r = &c->rows[k];
        contact_frame(m, t, r->feature, r->A, r->B, r->i, r->j, &r->cx, &r->cy, &r->nx, &r->ny);
        r->ran = (r->cx - r->A->px) * r->ny - (r->cy - r->A->py) * r->nx;
        r->rbn = (r->cx - r->B->px) * r->ny - (r->cy - r->B->py) * r->nx;
        r->kn = give(m, r->A, r->nx, r->ny, r->ran) + give(m, r->B, r->nx, r->ny, r->rbn);
    }
    c->nmovers = 0;
    for (int32_t k = 0; k < n; k++) {
        m2c_sim_body *both[2] = { c->rows[k].A, c->rows[k].B };
        for (int q = 0; q < 2; q++)
            if (part(m, both[q]) != HELD && !among(c->movers, c->nmovers, both[q]))
                c->movers[c->nmovers++] = both[q];
    }
    velocities(m, c->saved);
    double *acc = c->acc, *target = c->target;
    for (int32_t k = 0; k < n; k++) {
        acc[k] = 0.0;
        target[k] = 0.0;
    }
    sweeps(m, acc, target);
    double e1 = kinetic(m);
    for (int32_t k = 0; k < n; k++)
        target[k] = pressing_contact(m, &c->rows[k]) ? m->s->rest_speed : CLUSTER_APART * m->s->rest_speed;
    sweeps(m, acc, target);
    if (kinetic(m) <= e1)
        return;
    velocities(m, c->v2);
    double *acc2 = c->acc2;
    for (int32_t k = 0; k < n; k++)
        acc2[k] = acc[k];
    for (int32_t k = 0; k < c->nmovers; k++) {
        m2c_sim_body *b = c->movers[k];
        if (b->sup >= 0 && m->bodies[b->sup].fixed) {
            double q, u, a;
            support_relative(m, b, &q, &u, &a);
            b->vx = b->vx - u * b->tx;
            b->vy = b->vy - u * b->ty;
        } else {
            b->vx = 0.0;
            b->vy = 0.0;
        }
        b->om = 0.0;
    }
    for (int32_t k = 0; k < n; k++)
        acc[k] = 0.0;
    sweeps(m, acc, target);
    double es = kinetic(m);
    if (es <= e1) {
        velocities(m, c->vs);
        set_velocities(m, c->v2);
        double mu = mix(m, c->vs, e1);
        for (int32_t k = 0; k < c->nmovers; k++) {
            m2c_sim_body *b = c->movers[k];
            double vx = c->vs[3 * k], vy = c->vs[3 * k + 1], om = c->vs[3 * k + 2];
            b->vx = vx + mu * (b->vx - vx);
            b->vy = vy + mu * (b->vy - vy);
            b->om = om + mu * (b->om - om);
        }
        for (int32_t k = 0; k < n; k++)
            acc[k] = acc[k] + mu * (acc2[k] - acc[k]);
        return;
    }
    double f = sqrt(e1 / es);
    for (int32_t k = 0; k < c->nmovers; k++) {
        m2c_sim_body *b = c->movers[k];
        b->vx = f * b->vx;
        b->vy = f * b->vy;
        b->om = f * b->om;
    }
    for (int32_t k = 0; k < n; k++)
        acc[k] = f * acc[k];
}

/* The first sleeper (in the contacts' order) whose held impulses, summed,
 * would change its material points' normal speed by at least rest_speed
 * (as a touch that is not gentle, sleeper_impulse); NULL. */
static m2c_sim_body *jolted_sleeper(const sim *m)
{
    const m2c_sim_cluster *c = &m->clu;
    for (int32_t k = 0; k < c->n; k++) {
        m2c_sim_body *both[2] = { c->rows[k].A, c->rows[k].B };
        for (int p = 0; p < 2; p++) {
            m2c_sim_body *S = both[p];
            if (!S->asleep)
                continue;
            double total = 0.0;
            for (int32_t q = 0; q < c->n; q++) {
                const m2c_sim_row *r = &c->rows[q];
                if (r->A == S || r->B == S) {
                    double rsn = r->A == S ? r->ran : r->rbn;
                    total = total + c->acc[q] * (S->inv_m + S->inv_i * rsn * rsn);
                }
            }
            if (total >= m->s->rest_speed)
                return S;
        }
    }
    return NULL;
}

/* The pushes (unit directions, npush of them, x then y) can make (dx, dy)
 * with non-negative weights through one push (its direction within
 * HOLD_TOL rad of d) or two: d = a p + b q, a >= 0, b >= 0 (Cramer,
 * p x q != 0), pairs in order.  (dx, dy) = (0, 0) needs nothing. */
static int holds(const double *pushes, int32_t npush, double dx, double dy)
{
    if (dx == 0.0 && dy == 0.0)
        return 1;
    for (int32_t k = 0; k < npush; k++) {
        double px = pushes[2 * k], py = pushes[2 * k + 1];
        double dot = px * dx + py * dy;
        if (dot > 0.0 && fabs(px * dy - py * dx) <= HOLD_TOL * dot)
            return 1;
    }
    for (int32_t k = 0; k < npush; k++) {
        double px = pushes[2 * k], py = pushes[2 * k + 1];
        for (int32_t q = k + 1; q < npush; q++) {
            double qx = pushes[2 * q], qy = pushes[2 * q + 1];
            double det = px * qy - py * qx;
            if (det == 0.0)
                continue;
            double a = (dx * qy - dy * qx) / det;
            double b = (px * dy - py * dx) / det;
            if (a >= 0.0 && b >= 0.0)
                return 1;
        }
    }
    return 0;
}

/* The grounded body awake M falls asleep on after its cluster's solve, or
 * NULL: M slower than rest_speed (a polygon also turning slower than
 * rest_speed / bound) and its free acceleration held by what it rests on
 * (holds): the outward normal of its support when it is supported on an
 * unmoving fixed body, and each contact of the cluster with a grounded body
 * (pushing M along -m, m the contact's normal from M).  It falls asleep on
 * its support, else on the first grounded body of those contacts. */
static m2c_sim_body *wedged(sim *m, const m2c_sim_body *M)
{
    const m2c_sim_cluster *c = &m->clu;
    double rest = m->s->rest_speed;
    if (!(M->vx * M->vx + M->vy * M->vy < rest * rest))
        return NULL;
    if (M->polygon && !(fabs(M->om) * M->bound < rest))
        return NULL;
    double *pushes = c->pushes;
    int32_t npush = 0;
    m2c_sim_body *G = NULL;
    if (M->sup >= 0) {
        m2c_sim_body *S = &m->bodies[M->sup];
        if (!(S->fixed && grounded(S)))
            return NULL;
        double tx, ty, ox, oy;
        support_frame(S, M->sup_edge, &tx, &ty, &ox, &oy);
        pushes[2 * npush] = ox;
        pushes[2 * npush + 1] = oy;
        npush++;
        G = S;
    }
    for (int32_t k = 0; k < c->n; k++) {
        const m2c_sim_row *r = &c->rows[k];
        if (r->A == M && grounded(r->B)) {
            pushes[2 * npush] = -r->nx;
            pushes[2 * npush + 1] = -r->ny;
            npush++;
            if (G == NULL)
                G = r->B;
        }
        if (r->B == M && grounded(r->A)) {
            pushes[2 * npush] = r->nx;
            pushes[2 * npush + 1] = r->ny;
            npush++;
            if (G == NULL)
                G = r->A;
        }
    }
    if (G == NULL || !holds(pushes, npush, -M->fax, -M->fay))
        return NULL;
    return G;
}

/* A body of a solved cluster after its impulses: one sliding on a fixed
 * body gets its friction again for its new speed (as held_impulse), a
 * carried one leaves its base's motion (end_support: it is not held); a
 * new stamp, its state. */
static void settle(sim *m, m2c_sim_body *b)
{
    if (b->sup >= 0) {
        if (m->bodies[b->sup].fixed) {
            double q, u, a;
            support_relative(m, b, &q, &u, &a);
            slide_accel(m, b, u);
        } else {
            end_support(m, b);
        }
    }
    m->stamp[b->idx]++;
    emit_state(m, b);
}

/* predict_body for a body of a solved cluster, but against the bodies in
 * done (predicted already, or fallen asleep and predicted against it by
 * handle_sleep). */
static void predict_apart(sim *m, const m2c_sim_body *b, double now)
{
    const pair_filter f = { PAIRS_APART, NULL, -1 };
    predict_near(m, b, now, &f);
    if (b->sup >= 0 && m->bodies[b->sup].fixed)
        schedule_support(m, b);
}

/* A contact met again at the instant it was handled (repeated): the
 * contacts handled at this instant that reach it (cluster) are solved
 * together (solve_cluster); a sleeper the solve would jolt wakes and the
 * solve is made again with it moving.  Then an E collision line per contact
 * (its normal impulse), each followed by the states of its moving bodies
 * not written yet (settle); what a body whose velocity changed carries
 * leaves; those slow enough fall asleep (wedged), and the others are
 * predicted again. */
static void handle_cluster(sim *m, const m2c_sim_event *ev)
{
    m2c_sim_cluster *c = &m->clu;
    double t = ev->t;
    touch(m, t, ev->u.collision.a, ev->u.collision.b, ev->u.collision.feature, ev->u.collision.i,
          ev->u.collision.j);
    for (;;) {
        cluster(m, ev);
        for (int32_t k = 0; k < c->n; k++) {
            advance(c->rows[k].A, t);
            advance(c->rows[k].B, t);
        }
        solve_cluster(m, t);
        m2c_sim_body *S = jolted_sleeper(m);
        if (S == NULL)
            break;
        set_velocities(m, c->saved);
        handle_wake(m, S, t);
    }
    /* written: the movers whose state is out (the first ndone of done serve) */
    c->ndone = 0;
    for (int32_t k = 0; k < c->n; k++) {
        const m2c_sim_row *r = &c->rows[k];
        m->stats.collisions++;
        emit_contact(m, "E collision ", t, r->A, r->B, r->feature, r->i, r->j, r->cx, r->cy, r->nx, r->ny,
                     c->acc[k]);
        report(m, t, r->A, r->B, r->feature, r->i, r->j, r->cx, r->cy, r->nx, r->ny, c->acc[k], 0);
        m2c_sim_body *both[2] = { r->A, r->B };
        for (int q = 0; q < 2; q++) {
            if (among(c->movers, c->nmovers, both[q]) && !among(c->done, c->ndone, both[q])) {
                c->done[c->ndone++] = both[q];
                settle(m, both[q]);
            }
        }
    }
    left_list left = { 0 };
    for (int32_t k = 0; k < c->nmovers; k++) {
        const m2c_sim_body *b = c->movers[k];
        if (b->vx != c->saved[3 * k] || b->vy != c->saved[3 * k + 1] || b->om != c->saved[3 * k + 2])
            release(m, b, t, &left);
    }
    c->ndone = 0;
    int grow = 1;
    while (grow) {
        grow = 0;
        for (int32_t k = 0; k < c->nmovers; k++) {
            m2c_sim_body *b = c->movers[k];
            if (!b->asleep) {
                m2c_sim_body *G = wedged(m, b);
                if (G != NULL) {
                    handle_sleep(m, b, G, t);
                    c->done[c->ndone++] = b;
                    grow = 1;
                }
            }
        }
    }
    for (int32_t k = 0; k < c->nmovers; k++) {
        m2c_sim_body *b = c->movers[k];
        if (!b->asleep) {
            predict_apart(m, b, t);
            c->done[c->ndone++] = b;
        }
    }
    predict_released(m, &left, t);
}

/* A collision that ends in support (called by handle_collision). */
static void handle_support(sim *m, const m2c_sim_event *ev, m2c_sim_body *A, m2c_sim_body *B, double cx,
                           double cy, double nx, double ny, double vn)
{
    m->stats.supports++;
    double imp = -vn / A->inv_m;
    if (B->fixed)
        enter_support(m, A, B, ev->u.collision.j);
    else
        enter_carried(A, B, ev->u.collision.j);
    emit_contact(m, "E support ", ev->t, A, B, ev->u.collision.feature, ev->u.collision.i, ev->u.collision.j, cx,
                 cy, nx, ny, imp);
    report(m, ev->t, A, B, ev->u.collision.feature, ev->u.collision.i, ev->u.collision.j, cx, cy, nx, ny, imp, 1);
    touch(m, ev->t, A->idx, B->idx, ev->u.collision.feature, ev->u.collision.i, ev->u.collision.j);
    if (at_rest(m, A)) {
        handle_sleep(m, A, B, ev->t);
        return;
    }
    m->stamp[A->idx]++;
    emit_state(m, A);
    fetch_next(m);
    left_list left = { 0 };
    release(m, A, ev->t, &left);
    predict_body(m, A, ev->t, NULL);
    predict_released(m, &left, ev->t);
}

/* A collision of a and b on a feature: support, or the impulse, the new
 * states, and the two bodies' pairs predicted again. */
static void handle_collision(sim *m, const m2c_sim_event *ev)
{
    double t = ev->t;
    int32_t feature = ev->u.collision.feature, i = ev->u.collision.i, j = ev->u.collision.j;
    m2c_sim_body *A = &m->bodies[ev->u.collision.a], *B = &m->bodies[ev->u.collision.b];
    if (repeated(m, ev)) {
        handle_cluster(m, ev);
        return;
    }
    fetch_block(m, A);      /* for predict_body, after the impulse and the trace lines */
    fetch_block(m, B);
    advance(A, t);
    advance(B, t);
    double cx, cy, nx, ny;
    contact_frame(m, t, feature, A, B, i, j, &cx, &cy, &nx, &ny);
    double vn = normal_speed(A, B, cx, cy, nx, ny);
    if (can_support(m, A, B, feature, i, j, vn) || can_carry(m, A, B, feature, i, j, vn)) {
        handle_support(m, ev, A, B, cx, cy, nx, ny, vn);
        return;
    }
    if (can_sleep(m, A, B, ev, nx, ny, vn)) {
        handle_sleep(m, A, B, t);
        return;
    }
    if (can_sleep(m, B, A, ev, nx, ny, vn)) {
        handle_sleep(m, B, A, t);
        return;
    }
    m->stats.collisions++;
    /* a sleeper takes the impulse frozen (a = 0: pressed by whatever lands
     * on it); a gentle touch leaves it asleep, a real impulse wakes its
     * island; a slow contact of bodies held on their supports keeps them there */
    int hold = held(m, A, B, nx, ny, vn);
    double imp;
    if (hold)
        imp = held_impulse(m, A, B, nx, ny, vn);
    else if (A->asleep || B->asleep)
        imp = sleeper_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
    else
        imp = contact_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
    if (imp != 0.0 && !hold) {
        if (A->asleep && jolted(A))
            handle_wake(m, A, t);
        if (B->asleep && jolted(B))
            handle_wake(m, B, t);
        if (A->sup >= 0)
            end_support(m, A);
        if (B->sup >= 0)
            end_support(m, B);
    }
    emit_contact(m, "E collision ", t, A, B, feature, i, j, cx, cy, nx, ny, imp);
    fetch_neighbours(m, A);     /* their cells have come by now; the state lines take a while */
    fetch_neighbours(m, B);
    report(m, t, A, B, feature, i, j, cx, cy, nx, ny, imp, 0);
    touch(m, t, A->idx, B->idx, feature, i, j);
    /* a sleeper still asleep (zero impulse: the bodies graze, the other not
     * pressed onto it) is unchanged; the other is predicted again without
     * it (so the graze is not found again at once): only a later change of
     * the other's motion predicts the pair again */
    m2c_sim_body *both[2] = { A, B };
    for (int k = 0; k < 2; k++) {
        if (!both[k]->fixed && !both[k]->asleep) {
            m->stamp[both[k]->idx]++;
            emit_state(m, both[k]);
        }
    }
    /* an impulse changes the motion of what it hit: what they carried leaves */
    left_list left = { 0 };
    if (imp != 0.0) {
        for (int k = 0; k < 2; k++)
            if (!both[k]->fixed)
                release(m, both[k], t, &left);
    }
    fetch_next(m);
    if (!A->fixed && !A->asleep)
        predict_body(m, A, t, (B->asleep && imp == 0.0) ? B : NULL);
    if (!B->fixed && !B->asleep)
        predict_body(m, B, t, ((!A->fixed && !A->asleep) || (A->asleep && imp == 0.0)) ? A : NULL);
    predict_released(m, &left, t);
}

/* Sliding stops: velocity exactly the support's (zero when it does not
 * move), then rest or slide back. */
static void handle_stop(sim *m, const m2c_sim_event *ev)
{
    m->stats.stops++;
    m2c_sim_body *A = &m->bodies[ev->u.stop.body];
    advance(A, ev->t);
    const m2c_sim_body *B = &m->bodies[A->sup];
    if (is_static(B)) {
        A->vx = 0.0;
        A->vy = 0.0;
    } else {
        motion sb = state_at(B, ev->t);
        A->vx = sb.vx;
        A->vy = sb.vy;
    }
    slide_accel(m, A, 0.0);
    emit_support_change(m, "E stop ", ev->t, A, A->sup, A->sup_edge);
    if (at_rest(m, A)) {
        handle_sleep(m, A, &m->bodies[A->sup], ev->t);
        return;
    }
    m->stamp[A->idx]++;
    emit_state(m, A);
    fetch_next(m);
    left_list left = { 0 };
    release(m, A, ev->t, &left);
    predict_body(m, A, ev->t, NULL);
    predict_released(m, &left, ev->t);
}

/* The support's edge ends under the body: free motion again (and for what
 * it carries). */
static void handle_leave(sim *m, const m2c_sim_event *ev)
{
    left_list left = { 0 };
    leave(m, &m->bodies[ev->u.leave.body], ev->t, NULL, &left);
    fetch_next(m);
    predict_released(m, &left, ev->t);
}

/* ---- overlap (a teleport's check) ------------------------------------------------------------ */

/* Outward unit normal (ox, oy) of edge j of P at t and the offset of its
 * line, (ox, oy) . point = off. */
static void edge_line(const m2c_sim_body *P, int32_t j, double t, double *ox, double *oy, double *off)
{
    const m2c_sim_vertex *ed = &P->verts[j];
    motion q = state_at(P, t);
    double c = cos(q.ang);
    double s = sin(q.ang);
    *ox = c * ed->nx - s * ed->ny;
    *oy = s * ed->nx + c * ed->ny;
    *off = *ox * q.x + *oy * q.y + ed->h;
}

/* Along the edge normals of P: the largest over P's edges of the smallest
 * distance of Q's vertices beyond the edge's line. */
static double edges_separation(sim *m, const m2c_sim_body *P, const m2c_sim_body *Q, double t)
{
    double best = -INFINITY;
    for (int32_t j = 0; j < P->nverts; j++) {
        double ox, oy, off;
        edge_line(P, j, t, &ox, &oy, &off);
        double lo = INFINITY;
        for (int32_t k = 0; k < Q->nverts; k++) {
            double qx, qy;
            point_at(m, Q, &Q->verts[k], t, &qx, &qy);
            lo = py_min(lo, ox * qx + oy * qy - off);
        }
        best = py_max(best, lo);
    }
    return best;
}

/* A circle against a polygon: along P's edge normals, and along the line
 * from P's nearest vertex (the first of the nearest) to the circle's centre. */
static double circle_separation(sim *m, const m2c_sim_body *C, const m2c_sim_body *P, double t)
{
    double cx, cy;
    point_at(m, C, NULL, t, &cx, &cy);
    double best = -INFINITY;
    for (int32_t j = 0; j < P->nverts; j++) {
        double ox, oy, off;
        edge_line(P, j, t, &ox, &oy, &off);
        best = py_max(best, ox * cx + oy * cy - off - C->r);
    }
    double d2 = INFINITY, nearx = 0.0, neary = 0.0;
    for (int32_t k = 0; k < P->nverts; k++) {
        double qx, qy;
        point_at(m, P, &P->verts[k], t, &qx, &qy);
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
            point_at(m, P, &P->verts[k], t, &qx, &qy);
            hi = py_max(hi, ux * qx + uy * qy);
        }
        best = py_max(best, ux * cx + uy * cy - C->r - hi);
    }
    return best;
}

/* The largest gap between A and B at t along a separating axis: negative
 * by the depth they overlap (edge normals of either polygon, and for a
 * circle the line from the nearest vertex; circles: the distance of the
 * centres less the radii). */
static double separation(sim *m, const m2c_sim_body *A, const m2c_sim_body *B, double t)
{
    if (!A->polygon && !B->polygon) {
        double ax, ay, bx, by;
        point_at(m, A, NULL, t, &ax, &ay);
        point_at(m, B, NULL, t, &bx, &by);
        return sqrt((bx - ax) * (bx - ax) + (by - ay) * (by - ay)) - (A->r + B->r);
    }
    if (!A->polygon)
        return circle_separation(m, A, B, t);
    if (!B->polygon)
        return circle_separation(m, B, A, t);
    return py_max(edges_separation(m, A, B, t), edges_separation(m, B, A, t));
}

/* The first body (by index) that A, with its centre moved to (x, y) at
 * time t, would overlap by more than the tolerance; -1 when none. */
static int32_t overlapping(sim *m, m2c_sim_body *A, double x, double y, double t)
{
    double tol = m->s->tol;
    double spx = A->px, spy = A->py, svx = A->vx, svy = A->vy, sang = A->ang, stb = A->tb;
    motion q = state_at(A, t);
    A->px = x;                          /* A at t, moved (restored below) */
    A->py = y;
    A->vx = q.vx;
    A->vy = q.vy;
    A->ang = q.ang;
    A->tb = t;
    int32_t found = -1;
    for (int32_t k = 0; k < m->s->nbodies; k++) {
        const m2c_sim_body *B = &m->bodies[k];
        if (B == A || B->gone)
            continue;
        motion qb = state_at(B, t);
        double dx = qb.x - x, dy = qb.y - y;
        double reach = A->bound + B->bound + tol;
        if (dx * dx + dy * dy > reach * reach)
            continue;
        if (separation(m, A, B, t) < -tol) {
            found = B->idx;
            break;
        }
    }
    A->px = spx;
    A->py = spy;
    A->vx = svx;
    A->vy = svy;
    A->ang = sang;
    A->tb = stb;
    return found;
}

/* An E line of an input (k: its index in the input list). */
static void emit_input(sim *m, double t, const m2c_sim_body *body, int32_t k)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, "E input ");
    p = m2c_sim_put_num(p, t);
    *p++ = ' ';
    p = m2c_sim_put_int(p, body->idx);
    p = m2c_sim_put_str(p, " -1 -1 ");
    p = m2c_sim_put_int(p, k);
    p = m2c_sim_put_str(p, " -1 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
}

/* The islands of the sleepers whose bounding circles reach the removed
 * body's (within the tolerance) wake: it may have held them (by index; a
 * woken island's other members are awake already). */
static void wake_touching(sim *m, const m2c_sim_body *body, double t)
{
    double tol = m->s->tol;
    for (int32_t k = 0; k < m->s->nbodies; k++) {
        const m2c_sim_body *o = &m->bodies[k];
        if (o->asleep) {
            double dx = o->px - body->px;
            double dy = o->py - body->py;
            double reach = o->bound + body->bound + tol;
            if (dx * dx + dy * dy <= reach * reach)
                handle_wake(m, o, t);
        }
    }
}

/* Input k removes the body (based at t): it stops where it is (v, a, w
 * zero), leaves the grid (or the large list), its stamp changes (its
 * queued events go stale) and it is never predicted again; bodies it
 * supported leave. */
static void remove_body(sim *m, m2c_sim_body *body, int32_t k, double t)
{
    body->vx = body->vy = body->ax = body->ay = body->fax = body->fay = body->om = 0.0;
    if (body->sup >= 0)
        end_support(m, body);
    body->gone = 1;
    m->stamp[body->idx]++;
    if (body->large) {
        unplace_large(m, body);
    } else {
        m2c_sim_grid_remove(&m->grid, m->bodies, body);
    }
    emit_input(m, t, body, k);
    for (int32_t q = 0; q < m->s->nbodies; q++) {
        m2c_sim_body *A = &m->bodies[q];
        if (A->sup != body->idx)
            continue;
        left_list left = { 0 };
        leave(m, A, t, NULL, &left);
        predict_released(m, &left, t);
    }
    wake_touching(m, body, t);
}

/* Input k sets the velocity of fixed polygon B (based at t, it does not
 * turn): a large one placed in grid cells moves to the large list for good;
 * every body it supported leaves (E leave, free motion: it meets B again at
 * once and is supported again relative to B's new motion, or bounces, or
 * falls); B is predicted against every body again (a large B: each small
 * one that is not fixed or removed, in index order; a small one:
 * predict_body), the bodies that left against the others; last the islands
 * touching B wake (wake_touching). */
static void drive(sim *m, m2c_sim_body *B, int32_t k, double t, double vx, double vy)
{
    B->vx = vx;
    B->vy = vy;
    m->stamp[B->idx]++;
    if (B->placed) {
        unplace_large(m, B);
        m->large[m->nlarge++] = B->idx;
    }
    emit_input(m, t, B, k);
    emit_state(m, B);
    int32_t n = m->s->nbodies;
    left_list left = { 0 };
    for (int32_t q = 0; q < n; q++) {
        m2c_sim_body *A = &m->bodies[q];
        if (A->sup == B->idx)
            leave(m, A, t, B, &left);
    }
    if (B->large) {
        for (int32_t q = 0; q < n; q++) {
            const m2c_sim_body *o = &m->bodies[q];
            if (!o->large && !o->gone && !o->fixed)
                predict_pair(m, o, B, t);
        }
    } else {
        predict_body(m, B, t, NULL);
    }
    predict_released(m, &left, t);
    wake_touching(m, B, t);
}

/* Scripted or live input number k: its body's velocity set or added to,
 * an impulse through its centre, or its centre moved; on a fixed body
 * (set_velocity), drive. */
static void handle_input(sim *m, const m2c_sim_event *ev)
{
    m->stats.inputs++;
    double t = ev->t;
    int32_t k = ev->u.input.k;
    const m2c_sim_input *in = &m->s->inputs[k];
    m2c_sim_body *body = &m->bodies[in->body];
    if (body->gone) {
        char a[M2C_SIM_NUMBER_MAX + 1];
        die(m, "input %d: body %d was removed before t = %s", (int)k, (int)body->idx, fmt(a, t));
    }
    if (body->asleep)
        handle_wake(m, body, t);
    advance(body, t);
    if (in->mode == M2C_SIM_REMOVE) {
        remove_body(m, body, k, t);
        return;
    }
    if (body->fixed) {
        drive(m, body, k, t, in->vx, in->vy);
        return;
    }
    if (in->mode == M2C_SIM_TELEPORT) {
        int32_t o = overlapping(m, body, in->vx, in->vy, t);
        if (o >= 0) {
            char a[M2C_SIM_NUMBER_MAX + 1], b[M2C_SIM_NUMBER_MAX + 1], c[M2C_SIM_NUMBER_MAX + 1];
            die(m, "input %d: body %d teleported to (%s, %s) at t = %s would overlap body %d", (int)k,
                (int)body->idx, fmt(a, in->vx), fmt(b, in->vy), fmt(c, t), (int)o);
        }
    }
    if (body->sup >= 0)
        end_support(m, body);
    if (in->mode == M2C_SIM_SET_VELOCITY) {
        body->vx = in->vx;
        body->vy = in->vy;
    } else if (in->mode == M2C_SIM_ADD_VELOCITY) {
        body->vx = body->vx + in->vx;
        body->vy = body->vy + in->vy;
    } else if (in->mode == M2C_SIM_IMPULSE) {
        body->vx = body->vx + in->vx * body->inv_m;
        body->vy = body->vy + in->vy * body->inv_m;
    } else {
        body->px = in->vx;
        body->py = in->vy;
        if (!body->large) {     /* a large body is in no cell: every body checks it */
            m2c_sim_grid_remove(&m->grid, m->bodies, body);
            cell_of(m, body->px, body->py, &body->cx, &body->cy);
            cell_add(m, body);
        }
    }
    m->stamp[body->idx]++;
    emit_input(m, t, body, k);
    emit_state(m, body);
    left_list left = { 0 };
    release(m, body, t, &left);
    predict_body(m, body, t, NULL);
    predict_released(m, &left, t);
}

/* The body's centre went the grid's margin past its cell's edge along an axis: it moves
 * to the next cell and is predicted against the row or column it now neighbours. */
static void handle_cell(sim *m, const m2c_sim_event *ev)
{
    m->stats.cells++;
    m2c_sim_body *body = &m->bodies[ev->u.cell.body];
    int32_t d = ev->u.cell.direction;
    /* the row or column it will predict against (fetch_next fetched its
     * cells): their bodies are fetched while it changes cells */
    int32_t x_lo, x_hi, y_lo, y_hi;
    if (ev->u.cell.axis == 0) {
        x_lo = x_hi = body->cx + 2 * d;
        y_lo = body->cy - 1;
        y_hi = body->cy + 1;
    } else {
        x_lo = body->cx - 1;
        x_hi = body->cx + 1;
        y_lo = y_hi = body->cy + 2 * d;
    }
    fetch_bodies_in(m, x_lo, x_hi, y_lo, y_hi);
    m2c_sim_grid_remove(&m->grid, m->bodies, body);
    if (ev->u.cell.axis == 0)
        body->cx += d;
    else
        body->cy += d;
    cell_add(m, body);
    fetch_next(m);
    const pair_filter all = { PAIRS_ALL, NULL, -1 };
    predict_cells(m, body, x_lo, x_hi, y_lo, y_hi, ev->t, &all);
    /* the walls of the new row or column but those also listed in the two
     * it shares with the old neighbourhood (predicted at its last change):
     * none when no wall is listed in the new 3x3 block */
    m->nnear = 0;
    if (m->wnear[(size_t)body->cy * (size_t)m->s->nx + (size_t)body->cx] == 0) {
        schedule_cell(m, body, ev->t);
        return;
    }
    m->mark++;
    if (ev->u.cell.axis == 0) {
        int32_t lo = d > 0 ? body->cx - 1 : body->cx;
        walls_in(m, body, lo, lo + 1, body->cy - 1, body->cy + 1, 0);
    } else {
        int32_t lo = d > 0 ? body->cy - 1 : body->cy;
        walls_in(m, body, body->cx - 1, body->cx + 1, lo, lo + 1, 0);
    }
    walls_in(m, body, x_lo, x_hi, y_lo, y_hi, 1);
    if (m->nnear > 1)
        qsort(m->near, (size_t)m->nnear, sizeof *m->near, by_index);
    if (!body->fixed)
        for (int32_t k = 0; k < m->nnear; k++)
            predict_pair(m, body, &m->bodies[m->near[k]], ev->t);
    schedule_cell(m, body, ev->t);
}

/* The pair reached the end of its Taylor window, or its bounding circles
 * met: predicted again from now. */
static void handle_horizon(sim *m, const m2c_sim_event *ev)
{
    m->stats.horizons++;
    predict_pair(m, &m->bodies[ev->u.horizon.a], &m->bodies[ev->u.horizon.b], ev->t);
}

/* Draw frame number k: written, and the next one scheduled. */
static void handle_frame(sim *m, const m2c_sim_event *ev)
{
    m->stats.frames++;
    const m2c_sim_scene *s = m->s;
    if (m->out.f != NULL) {
        char *start = m2c_sim_out_reserve(&m->out), *p = start;
        p = m2c_sim_put_str(p, "E frame ");
        p = m2c_sim_put_num(p, ev->t);
        p = m2c_sim_put_str(p, " -1 -1 -1 -1 -1 0 0 0 0 0\n");
        m->out.n += (size_t)(p - start);
    }
    double nxt = (double)(ev->u.frame.k + 1) * s->frame_dt;
    if (nxt <= s->end)
        push_frame(m, nxt, ev->u.frame.k + 1);
}

/* The handler of each event kind, by kind. */
static void (*const handlers[M2C_SIM_KINDS])(sim *, const m2c_sim_event *) = {
    [M2C_SIM_INPUT] = handle_input, [M2C_SIM_COLLISION] = handle_collision, [M2C_SIM_STOP] = handle_stop,
    [M2C_SIM_LEAVE] = handle_leave, [M2C_SIM_CELL] = handle_cell,           [M2C_SIM_HORIZON] = handle_horizon,
    [M2C_SIM_FRAME] = handle_frame,
};

/* Places the bodies in the grid, schedules the inputs and the first frame,
 * and predicts every pair once. */
static void start(sim *m)
{
    enum { AHEAD = 4 };     /* bodies: the grid reads of body k + AHEAD are fetched while k is placed or predicted */
    m2c_sim_scene *s = m->s;
    m2c_sim_body *bodies = m->bodies;
    for (int32_t k = 0; k < s->nbodies; k++) {
        m2c_sim_body *b = &bodies[k];
        if (k + AHEAD < s->nbodies)
            fetch_cell_at(m, &bodies[k + AHEAD]);
        if (!b->large) {
            cell_of(m, b->px, b->py, &b->cx, &b->cy);
            cell_add(m, b);
        }
    }
    for (int32_t k = 0; k < s->ninputs; k++)
        push_input(m, s->inputs[k].t, k);
    if (s->frame_dt > 0.0 && s->frame_dt <= s->end)
        push_frame(m, s->frame_dt, 1);
    const pair_filter after = { PAIRS_AFTER, NULL, -1 };
    for (int32_t k = 0; k < s->nbodies; k++) {
        const m2c_sim_body *b = &bodies[k];
        if (k + AHEAD < s->nbodies)
            fetch_block(m, &bodies[k + AHEAD]);
        if (b->large)
            continue;
        predict_cells(m, b, b->cx - 1, b->cx + 1, b->cy - 1, b->cy + 1, 0.0, &after);
        large_near(m, b);
        for (int32_t l = 0; l < m->nnear; l++) {
            const m2c_sim_body *o = &bodies[m->near[l]];
            if (!(b->fixed && o->fixed))
                predict_pair(m, b, o, 0.0);
        }
        schedule_cell(m, b, 0.0);
    }
}

/* Every body at the end time, the statistics, the predictions per variant. */
static void finish(sim *m)
{
    m2c_sim_scene *s = m->s;
    m2c_sim_body *bodies = m->bodies;
    for (int32_t k = 0; k < s->nbodies; k++)
        advance(&bodies[k], s->end);
    for (int32_t k = 0; k < s->nbodies; k++) {
        const m2c_sim_body *b = &bodies[k];
        char *start = m2c_sim_out_reserve(&m->out), *p = start;
        p = m2c_sim_put_str(p, "F ");
        p = m2c_sim_put_int(p, b->idx);
        const double v[6] = { b->px, b->py, b->vx, b->vy, b->ang, b->om };
        for (int l = 0; l < 6; l++) {
            *p++ = ' ';
            p = m2c_sim_put_num(p, v[l]);
        }
        *p++ = '\n';
        m->out.n += (size_t)(p - start);
    }
    for (size_t k = 0; k < sizeof stat_lines / sizeof stat_lines[0]; k++) {
        char *start = m2c_sim_out_reserve(&m->out), *p = start;
        p = m2c_sim_put_str(p, "N ");
        p = m2c_sim_put_str(p, stat_lines[k].name);
        *p++ = ' ';
        p = m2c_sim_put_int(p, *(const long long *)((const char *)&m->stats + stat_lines[k].offset));
        *p++ = '\n';
        m->out.n += (size_t)(p - start);
    }
    for (int e = 0; e < 2; e++) {
        int n = e == 0 ? m->n_cc : m->n_pe;
        const long long *counts = e == 0 ? m->cc_counts : m->pe_counts;
        for (int k = 0; k < n; k++) {
            char *start = m2c_sim_out_reserve(&m->out), *p = start;
            p = m2c_sim_put_str(p, e == 0 ? "V circle_circle " : "V point_edge ");
            p = m2c_sim_put_int(p, k);
            *p++ = ' ';
            p = m2c_sim_put_int(p, counts[k]);
            *p++ = '\n';
            m->out.n += (size_t)(p - start);
        }
    }
}

/* Stops the run when more than max_same events happen at one instant. */
static void count_same_time(sim *m, double t, double *last_t, long long *same)
{
    if (t == *last_t) {
        (*same)++;
        if (*same > m->s->max_same) {
            char num[M2C_SIM_NUMBER_MAX + 1];
            num[m2c_sim_format_number(num, t)] = '\0';
            die(m, "more than %lld events at t = %s: the scene is stuck", m->s->max_same, num);
        }
    } else {
        *last_t = t;
        *same = 0;
    }
}

/* Tells the caller of m2c_world_advance of a contact. */
static void report(sim *m, double t, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                   int32_t j, double cx, double cy, double nx, double ny, double imp, int support)
{
    if (m->fn == NULL)
        return;
    m2c_contact c = { t, A->idx, B->idx, feature, i, j, cx, cy, nx, ny, imp, support };
    m->fn(&c, m->user);
}

/* Handles one event popped from the queue: dropped when stale, counted
 * among the events at one instant (max_same_time), to its kind's handler. */
static void dispatch(sim *m, const m2c_sim_event *ev)
{
    if (is_stale(m, ev)) {
        m->stats.stale++;
        return;
    }
    count_same_time(m, ev->t, &m->last_t, &m->same);
    handlers[ev->kind](m, ev);
}

/* The queued events before limit (s; inclusive: at limit too) in
 * (t, kind, seq) order, each to its kind's handler, the events that
 * handling schedules included. */
static void run_until(sim *m, double limit, int inclusive)
{
    m2c_sim_event ev;
    for (;;) {
        const m2c_sim_event *top;
        if (m2c_sim_heap_top(&m->heap, &top) != 0)
            die(m, "out of memory (event queue of %zu events)", m->heap.n);
        if (top == NULL || top->t > limit || (top->t == limit && !inclusive))
            break;
        if (m2c_sim_heap_pop(&m->heap, &ev) != 0)
            die(m, "out of memory (event queue of %zu events)", m->heap.n);
        fetch_stamps(m);
        dispatch(m, &ev);
    }
}

/* Handles the input events queued at exactly the world's time. */
static void inputs_now(sim *m)
{
    m2c_sim_event ev;
    for (;;) {
        const m2c_sim_event *top;
        if (m2c_sim_heap_top(&m->heap, &top) != 0)
            die(m, "out of memory (event queue of %zu events)", m->heap.n);
        if (top == NULL || top->t != m->now || top->kind != M2C_SIM_INPUT)
            break;
        if (m2c_sim_heap_pop(&m->heap, &ev) != 0)
            die(m, "out of memory (event queue of %zu events)", m->heap.n);
        dispatch(m, &ev);
    }
}

/* Entries: each catches the errors of what it calls (die) here. */
#define CATCH(m)                                                                                            \
    do {                                                                                                    \
        if ((m)->broken)                                                                                    \
            return -1;                                                                                      \
        if (setjmp((m)->fail) != 0)                                                                         \
            return -1;                                                                                      \
    } while (0)

int m2c_sim_open(sim *m, m2c_sim_scene *scene, int cc_variants, int pe_variants, FILE *trace)
{
    m->s = scene;
    m->bodies = scene->bodies;
    m->n_cc = cc_variants;
    m->n_pe = pe_variants;
    m->sweep_at = 4096;
    m->last_t = -1.0;
    m->unpaid = 0;
    m->touched_t = -1.0;
    CATCH(m);
    if (m2c_sim_out_init(&m->out, trace) != 0)
        die(m, "out of memory");
    if (cc_variants < 1 || pe_variants < 1)
        die(m, "no variants to count (circle_circle %d, point_edge %d)", cc_variants, pe_variants);
    m->cc_counts = calloc((size_t)cc_variants, sizeof *m->cc_counts);
    m->pe_counts = calloc((size_t)pe_variants, sizeof *m->pe_counts);
    m->large = calloc((size_t)scene->nbodies + 1, sizeof *m->large);
    m->stamp = calloc((size_t)scene->nbodies + 1, sizeof *m->stamp);
    size_t nv = scene->verts_cap + 1;
    m->trig_cap = nv;
    m->vtrig = calloc(nv, sizeof *m->vtrig);
    m->etrig = calloc(nv, sizeof *m->etrig);
    if (m->stamp == NULL || m->vtrig == NULL || m->etrig == NULL || m->cc_counts == NULL || m->pe_counts == NULL
        || m->large == NULL || m2c_sim_grid_init(&m->grid, scene->nx, scene->ny) != 0)
        die(m, "out of memory");
    choose_fetch(m);
    m->walls = calloc((size_t)scene->nx * (size_t)scene->ny, sizeof *m->walls);
    m->wnear = calloc((size_t)scene->nx * (size_t)scene->ny, sizeof *m->wnear);
    if (m->walls == NULL || m->wnear == NULL)
        die(m, "out of memory");
    m2c_sim_huge_pages(m->walls, (size_t)scene->nx * (size_t)scene->ny * sizeof *m->walls);
    m2c_sim_huge_pages(m->wnear, (size_t)scene->nx * (size_t)scene->ny * sizeof *m->wnear);
    for (int32_t k = 0; k < scene->nbodies; k++)
        if (scene->bodies[k].large)
            place_large(m, &scene->bodies[k]);
    start(m);
    return 0;
}

int m2c_sim_advance(sim *m, double t)
{
    CATCH(m);
    run_until(m, t, 0);
    m->now = t;
    return 0;
}

int m2c_sim_next_time(sim *m, double *t)
{
    CATCH(m);
    for (;;) {
        const m2c_sim_event *top;
        if (m2c_sim_heap_top(&m->heap, &top) != 0)
            die(m, "out of memory (event queue of %zu events)", m->heap.n);
        if (top == NULL || top->t > m->s->end) {
            *t = INFINITY;
            return 0;
        }
        if (!is_stale(m, top)) {
            *t = top->t;
            return 0;
        }
        m2c_sim_event ev;
        if (m2c_sim_heap_pop(&m->heap, &ev) != 0)
            die(m, "out of memory (event queue of %zu events)", m->heap.n);
        m->stats.stale++;
    }
}

int m2c_sim_live_input(sim *m, int body, int mode, double x, double y, int *done)
{
    *done = 0;
    if (m->broken)
        return -1;
    if (body < 0 || body >= m->s->nbodies) {
        snprintf(m->err, sizeof m->err, "no body %d (the world has %d)", body, (int)m->s->nbodies);
        return -1;
    }
    m2c_sim_body *b = &m->bodies[body];
    if (b->gone) {
        snprintf(m->err, sizeof m->err, "body %d was removed", body);
        return -1;
    }
    if (!m2c_sim_drivable(b, mode)) {
        snprintf(m->err, sizeof m->err, "body %d is fixed: inputs move movable bodies only (or set the velocity of a "
                 "fixed polygon that does not turn, or remove a fixed body)", body);
        return -1;
    }
    if (!isfinite(x) || !isfinite(y)) {
        char a[M2C_SIM_NUMBER_MAX + 1], c[M2C_SIM_NUMBER_MAX + 1];
        snprintf(m->err, sizeof m->err, "input on body %d: (%s, %s) is not finite", body, fmt(a, x), fmt(c, y));
        return -1;
    }
    CATCH(m);
    double t = m->now;
    inputs_now(m);
    if (mode == M2C_SIM_TELEPORT && overlapping(m, b, x, y, t) >= 0)
        return 0;
    m2c_sim_scene *s = m->s;
    if (s->ninputs == s->inputs_cap) {
        if (s->inputs_cap > (1 << 28))
            die(m, "too many inputs");
        m2c_sim_input *more = realloc(s->inputs, 2 * (size_t)s->inputs_cap * sizeof *more);
        if (more == NULL)
            die(m, "out of memory (inputs)");
        s->inputs = more;
        s->inputs_cap *= 2;
    }
    m2c_sim_input *in = &s->inputs[s->ninputs++];
    in->t = t;
    in->body = body;
    in->mode = mode;
    in->vx = x;
    in->vy = y;
    push_input(m, t, s->ninputs - 1);
    inputs_now(m);
    *done = 1;
    return 0;
}

/* Room for one more body with nverts vertices: 0, or -1 (out of memory;
 * what was grown stays grown, nothing else changes). */
static int reserve_body(sim *m, int32_t nverts)
{
    m2c_sim_scene *s = m->s;
    if (s->nbodies + 1 >= s->bodies_cap) {
        if (s->bodies_cap > (1 << 28))
            return -1;
        int32_t cap = 2 * s->bodies_cap;
        m2c_sim_body *b = aligned_alloc(64, (size_t)cap * sizeof *b);     /* a multiple of 64 */
        uint32_t *st = realloc(m->stamp, (size_t)cap * sizeof *st);
        if (st != NULL)
            m->stamp = st;
        int32_t *lg = realloc(m->large, (size_t)cap * sizeof *lg);
        if (lg != NULL)
            m->large = lg;
        if (b == NULL || st == NULL || lg == NULL) {
            free(b);
            return -1;
        }
        m2c_sim_huge_pages(b, (size_t)cap * sizeof *b);
        memset(b, 0, (size_t)cap * sizeof *b);
        memcpy(b, s->bodies, (size_t)s->nbodies * sizeof *b);
        memset(st + s->bodies_cap, 0, (size_t)(cap - s->bodies_cap) * sizeof *st);
        free(s->bodies);
        s->bodies = m->bodies = b;
        s->bodies_cap = cap;
    }
    if (s->nverts_all + (size_t)nverts > s->verts_cap) {
        size_t cap = 2 * (s->nverts_all + (size_t)nverts) + 64;
        size_t *first = malloc(((size_t)s->nbodies + 1) * sizeof *first);
        if (first == NULL)
            return -1;
        for (int32_t k = 0; k < s->nbodies; k++)
            first[k] = s->bodies[k].verts != NULL ? (size_t)(s->bodies[k].verts - s->verts) : 0;
        m2c_sim_vertex *v = realloc(s->verts, cap * sizeof *v);
        if (v == NULL) {
            free(first);
            return -1;
        }
        s->verts = v;
        s->verts_cap = cap;
        for (int32_t k = 0; k < s->nbodies; k++)
            if (s->bodies[k].verts != NULL)
                s->bodies[k].verts = v + first[k];
        free(first);
    }
    if (s->verts_cap + 1 > m->trig_cap) {
        size_t cap = s->verts_cap + 1;
        m2c_sim_trig *vt = realloc(m->vtrig, cap * sizeof *vt);
        if (vt != NULL)
            m->vtrig = vt;
        m2c_sim_trig *et = realloc(m->etrig, cap * sizeof *et);
        if (et != NULL)
            m->etrig = et;
        if (vt == NULL || et == NULL)
            return -1;
        memset(vt + m->trig_cap, 0, (cap - m->trig_cap) * sizeof *vt);
        memset(et + m->trig_cap, 0, (cap - m->trig_cap) * sizeof *et);
        m->trig_cap = cap;
    }
    return 0;
}

int m2c_sim_add_body(sim *m, const char *text, int *idx)
{
    *idx = -1;
    if (m->broken)
        return -1;
    m2c_sim_scene *s = m->s;
    m2c_sim_body nb;
    memset(&nb, 0, sizeof nb);
    m2c_sim_vertex *nv = NULL;
    if (m2c_sim_body_read(text, &nb, s->nbodies, &nv, m->err, sizeof m->err) != 0)
        return -1;
    nb.large = 2.0 * nb.bound > py_min(s->cw, s->ch);
    if (nb.large && !nb.fixed) {
        char a[M2C_SIM_NUMBER_MAX + 1], b[M2C_SIM_NUMBER_MAX + 1], c[M2C_SIM_NUMBER_MAX + 1];
        snprintf(m->err, sizeof m->err, "add_body: a movable body of bound %s m does not fit the grid's cells "
                 "(%s x %s m): put such a body in the scene", fmt(a, nb.bound), fmt(b, s->cw), fmt(c, s->ch));
        free(nv);
        return -1;
    }
    if (reserve_body(m, nb.nverts) != 0) {
        free(nv);
        snprintf(m->err, sizeof m->err, "out of memory (add_body)");
        m->broken = 1;
        return -1;
    }
    /* the body waits in the first unused place (not counted until it is added) */
    if (nb.nverts > 0) {
        memcpy(s->verts + s->nverts_all, nv, (size_t)nb.nverts * sizeof *nv);
        nb.verts = s->verts + s->nverts_all;
    }
    free(nv);
    m2c_sim_body *b = &s->bodies[s->nbodies];
    *b = nb;
    m->stamp[b->idx] = 0;
    CATCH(m);
    double t = m->now;
    b->tb = t;
    inputs_now(m);
    if (overlapping(m, b, b->px, b->py, t) >= 0)
        return 0;
    s->nbodies++;
    s->nverts_all += (size_t)b->nverts;
    m->added++;
    choose_fetch(m);
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, "E add ");
    p = m2c_sim_put_num(p, t);
    *p++ = ' ';
    p = m2c_sim_put_int(p, b->idx);
    p = m2c_sim_put_str(p, " -1 -1 -1 -1 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
    if (b->large) {
        place_large(m, b);
        for (int32_t k = 0; k < s->nbodies; k++) {
            const m2c_sim_body *o = &m->bodies[k];
            if (!o->large && !o->gone && !(o->fixed && b->fixed))
                predict_pair(m, o, b, t);
        }
    } else {
        cell_of(m, b->px, b->py, &b->cx, &b->cy);
        cell_add(m, b);
        if (!b->fixed)
            emit_state(m, b);
        predict_body(m, b, t, NULL);
    }
    *idx = b->idx;
    return 0;
}

int m2c_sim_finish(sim *m)
{
    CATCH(m);
    run_until(m, m->s->end, 1);
    m->now = m->s->end;
    finish(m);
    m2c_sim_out_flush(&m->out);
    if (m->out.failed)
        die(m, "cannot write the trace");
    return 0;
}

void m2c_sim_close(sim *m)
{
    if (m->out.buf != NULL)
        m2c_sim_out_flush(&m->out);
    m2c_sim_out_free(&m->out);
    m2c_sim_grid_free(&m->grid);
    m2c_sim_heap_free(&m->heap);
    free(m->cc_counts);
    free(m->pe_counts);
    free(m->large);
    if (m->walls != NULL && m->s != NULL)
        for (size_t k = 0; k < (size_t)m->s->nx * (size_t)m->s->ny; k++)
            free(m->walls[k].items);
    free(m->walls);
    free(m->wnear);
    free(m->near);
    free(m->stamp);
    free(m->vtrig);
    free(m->etrig);
    free(m->scratch);
    free(m->scratch_deg);
    free(m->touched);
    cluster_free(&m->clu);
    m2c_sim_scene_free(m->s);
    m->s = NULL;
}
