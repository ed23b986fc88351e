/* The handlers: one per event kind (input, collision, stop, leave, cell,
 * horizon, frame), their dispatch in the queue's (t, kind, seq) order, the
 * start (every pair predicted once) and the fetching ahead of what the
 * next event will read.  A handler moves the bodies of its event on to its
 * time, writes their trace lines, bumps their stamps (their queued events
 * go stale) and predicts them again.  Times in s. */
#include <math.h>
#include <stdlib.h>

#include "m2c_sim_internal.h"

/* ---- fetching ahead --------------------------------------------------------------- */

/* The helpers below only prefetch, which GCC counts as no side effect: a
 * function of prefetches alone is then "const", and its calls are deleted
 * as dead code before they can be inlined.  always_inline puts them in
 * their callers first. */
#define FETCH static inline __attribute__((always_inline))

/* Fetches from memory the lines a body's own event reads: its prediction's
 * two and its handler's (cell, impulse). */
FETCH void fetch_body(const m2c_world *m, int32_t idx)
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
FETCH void fetch_row(const m2c_world *m, int32_t xa, int32_t xb, int32_t y)
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
FETCH void fetch_cell_at(const m2c_world *m, const m2c_sim_body *b)
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
FETCH void fetch_block(const m2c_world *m, const m2c_sim_body *b)
{
    if (!m->fetch)
        return;
    if (b->large)
        return;
    for (int32_t y = b->cy - 1; y <= b->cy + 1; y++)
        fetch_row(m, b->cx - 1, b->cx + 1, y);
    __builtin_prefetch(&m->wnear[(size_t)b->cy * (size_t)m->s->nx + (size_t)b->cx]);
}

/* Fetches the two prediction lines of the bodies listed in the cells
 * x_lo..x_hi, y_lo..y_hi (clamped to the grid; the first 8 of each), whose
 * lists were fetched a while before. */
FETCH void fetch_bodies_in(const m2c_world *m, int32_t x_lo, int32_t x_hi, int32_t y_lo, int32_t y_hi)
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
            if (m2c_sim_gather_inline(c, ids, &ni, ROOM))
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
FETCH void fetch_neighbours(const m2c_world *m, const m2c_sim_body *b)
{
    if (!b->large)
        fetch_bodies_in(m, b->cx - 1, b->cx + 1, b->cy - 1, b->cy + 1);
}

/* Fetches the stamps of the event that is next for now (the queue fetched
 * its record when it found it): whether it is stale is the first question
 * asked of it. */
FETCH void fetch_stamps(const m2c_world *m)
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
static __attribute__((noinline)) void fetch_next(m2c_world *m)
{
    if (!m->fetch)
        return;
    const m2c_sim_event *e = m2c_sim_heap_peek(&m->heap);
    for (int k = 0; e != NULL && k < 8 && m2c_sim_is_stale(m, e); k++) {
        m2c_sim_event drop;
        if (m2c_sim_heap_pop(&m->heap, &drop) != 0)
            m2c_sim_die(m, "out of memory (event queue of %zu events)", m->heap.n);
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

/* ---- the handlers, one per event kind ----------------------------------------- */

/* A collision that ends in support (called by handle_collision). */
static void handle_support(m2c_world *m, const m2c_sim_event *ev, m2c_sim_body *A, m2c_sim_body *B, double cx,
                           double cy, double nx, double ny, double vn)
{
    m->stats.supports++;
    double imp = -vn / A->inv_m;
    if (B->fixed || B->asleep)
        m2c_sim_enter_support(m, A, B, ev->u.collision.j);
    else
        m2c_sim_enter_carried(A, B, ev->u.collision.j);
    m2c_sim_emit_contact(m, "E support ", ev->t, A, B, ev->u.collision.feature, ev->u.collision.i,
                         ev->u.collision.j, cx, cy, nx, ny, imp);
    m2c_sim_report(m, ev->t, A, B, ev->u.collision.feature, ev->u.collision.i, ev->u.collision.j, cx, cy, nx, ny,
                   imp, 1);
    m2c_sim_count_touch(m, ev->t, A->idx, B->idx, ev->u.collision.feature, ev->u.collision.i, ev->u.collision.j);
    if (m2c_sim_at_rest(m, A)) {
        m2c_sim_handle_sleep(m, A, B, ev->t);
        return;
    }
    m->stamp[A->idx]++;
    m2c_sim_emit_state(m, A);
    fetch_next(m);
    m2c_sim_left left = { 0 };
    m2c_sim_release(m, A, ev->t, &left);
    m2c_sim_predict_body(m, A, ev->t, NULL);
    m2c_sim_predict_released(m, &left, ev->t);
}

/* A collision of a and b on a feature: support, or the impulse, the new
 * states, and the two bodies' pairs predicted again. */
static void handle_collision(m2c_world *m, const m2c_sim_event *ev)
{
    double t = ev->t;
    int32_t feature = ev->u.collision.feature, i = ev->u.collision.i, j = ev->u.collision.j;
    m2c_sim_body *A = &m->bodies[ev->u.collision.a], *B = &m->bodies[ev->u.collision.b];
    if (m2c_sim_repeated(m, ev)) {
        m2c_sim_handle_cluster(m, ev);
        return;
    }
    fetch_block(m, A);      /* for predict_body, after the impulse and the trace lines */
    fetch_block(m, B);
    m2c_sim_rebase(A, t);
    m2c_sim_rebase(B, t);
    double cx, cy, nx, ny;
    m2c_sim_contact_frame(m, t, feature, A, B, i, j, &cx, &cy, &nx, &ny);
    double vn = m2c_sim_normal_speed(A, B, cx, cy, nx, ny);
    if (m2c_sim_can_support(m, A, B, feature, i, j, vn) || m2c_sim_can_carry(m, A, B, feature, i, j, vn)) {
        handle_support(m, ev, A, B, cx, cy, nx, ny, vn);
        return;
    }
    if (m2c_sim_can_sleep(m, A, B, ev, nx, ny, vn)) {
        m2c_sim_handle_sleep(m, A, B, t);
        return;
    }
    if (m2c_sim_can_sleep(m, B, A, ev, nx, ny, vn)) {
        m2c_sim_handle_sleep(m, B, A, t);
        return;
    }
    if (m2c_sim_can_sleep_many(m, A, B, ev, cx, cy, nx, ny, vn)) {
        m2c_sim_handle_sleep_many(m, A, B, ev, t);
        return;
    }
    if (m2c_sim_can_sleep_many(m, B, A, ev, cx, cy, nx, ny, vn)) {
        m2c_sim_handle_sleep_many(m, B, A, ev, t);
        return;
    }
    if (m2c_sim_can_ride(m, A, B, feature, i, j, vn)) {
        handle_support(m, ev, A, B, cx, cy, nx, ny, vn);
        return;
    }
    int press_a = m2c_sim_slow_touch(m, A, B, ev, nx, ny, vn), press_b = m2c_sim_slow_touch(m, B, A, ev, nx, ny, vn);
    m->stats.collisions++;
    /* a sleeper takes the impulse frozen (a = 0: pressed by whatever lands
     * on it); a gentle touch leaves it asleep, a real impulse wakes its
     * island; a slow contact of bodies held on their supports keeps them there */
    int hold = m2c_sim_held(m, A, B, nx, ny, vn);
    double imp;
    if (hold)
        imp = m2c_sim_held_impulse(m, A, B, nx, ny, vn);
    else if (A->asleep || B->asleep)
        imp = m2c_sim_sleeper_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
    else
        imp = m2c_sim_contact_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
    if (imp != 0.0 && !hold) {
        if (A->asleep && m2c_sim_jolted(A))
            m2c_sim_handle_wake(m, A, t);
        if (B->asleep && m2c_sim_jolted(B))
            m2c_sim_handle_wake(m, B, t);
        if (A->sup >= 0)
            m2c_sim_end_support(m, A);
        if (B->sup >= 0)
            m2c_sim_end_support(m, B);
    }
    m2c_sim_emit_contact(m, "E collision ", t, A, B, feature, i, j, cx, cy, nx, ny, imp);
    fetch_neighbours(m, A);     /* their cells have come by now; the state lines take a while */
    fetch_neighbours(m, B);
    m2c_sim_report(m, t, A, B, feature, i, j, cx, cy, nx, ny, imp, 0);
    m2c_sim_count_touch(m, t, A->idx, B->idx, feature, i, j);
    /* a sleeper still asleep (zero impulse: the bodies graze, the other not
     * pressed onto it) is unchanged; the other is predicted again without
     * it (so the graze is not found again at once): only a later change of
     * the other's motion predicts the pair again */
    m2c_sim_body *both[2] = { A, B };
    for (int k = 0; k < 2; k++) {
        if (!both[k]->fixed && !both[k]->asleep) {
            m->stamp[both[k]->idx]++;
            m2c_sim_emit_state(m, both[k]);
        }
    }
    if (press_a && !A->asleep)
        m2c_sim_note_rest(m, A, B, ev, cx, cy, nx, ny);
    if (press_b && !B->asleep)
        m2c_sim_note_rest(m, B, A, ev, cx, cy, nx, ny);
    /* an impulse changes the motion of what it hit: what they carried leaves
     * (a sleeper a gentle touch left asleep has not moved: what slides on it stays) */
    m2c_sim_left left = { 0 };
    if (imp != 0.0) {
        for (int k = 0; k < 2; k++)
            if (!both[k]->fixed && !both[k]->asleep)
                m2c_sim_release(m, both[k], t, &left);
    }
    fetch_next(m);
    if (!A->fixed && !A->asleep)
        m2c_sim_predict_body(m, A, t, (B->asleep && imp == 0.0) ? B : NULL);
    if (!B->fixed && !B->asleep)
        m2c_sim_predict_body(m, B, t, ((!A->fixed && !A->asleep) || (A->asleep && imp == 0.0)) ? A : NULL);
    m2c_sim_predict_released(m, &left, t);
}

/* Sliding stops: velocity exactly the support's (zero when it does not
 * move), then rest or slide back. */
static void handle_stop(m2c_world *m, const m2c_sim_event *ev)
{
    m->stats.stops++;
    m2c_sim_body *A = &m->bodies[ev->u.stop.body];
    m2c_sim_rebase(A, ev->t);
    const m2c_sim_body *B = &m->bodies[A->sup];
    if (m2c_sim_is_static(B)) {
        A->vx = 0.0;
        A->vy = 0.0;
    } else {
        m2c_sim_motion sb = m2c_sim_state_at(B, ev->t);
        A->vx = sb.vx;
        A->vy = sb.vy;
    }
    m2c_sim_slide_accel(m, A, 0.0);
    m2c_sim_emit_support_change(m, "E stop ", ev->t, A, A->sup, A->sup_edge);
    if (m2c_sim_at_rest(m, A)) {
        m2c_sim_handle_sleep(m, A, &m->bodies[A->sup], ev->t);
        return;
    }
    if (B->asleep && !m2c_sim_base_holds(m, B, 0.0, 0.0)) {
        /* sliding back, its friction turned: the sleeping base no longer holds it */
        m2c_sim_left gone = { 0 };
        m2c_sim_leave(m, A, ev->t, NULL, &gone);
        m2c_sim_predict_released(m, &gone, ev->t);
        return;
    }
    m->stamp[A->idx]++;
    m2c_sim_emit_state(m, A);
    fetch_next(m);
    m2c_sim_left left = { 0 };
    m2c_sim_release(m, A, ev->t, &left);
    m2c_sim_predict_body(m, A, ev->t, NULL);
    m2c_sim_predict_released(m, &left, ev->t);
}

/* The support's edge ends under the body: free motion again (and for what
 * it carries). */
static void handle_leave(m2c_world *m, const m2c_sim_event *ev)
{
    m2c_sim_left left = { 0 };
    m2c_sim_leave(m, &m->bodies[ev->u.leave.body], ev->t, NULL, &left);
    fetch_next(m);
    m2c_sim_predict_released(m, &left, ev->t);
}

/* Input k removes the body (based at t): it stops where it is (v, a, w
 * zero), leaves the grid (or the large list), its stamp changes (its
 * queued events go stale) and it is never predicted again; bodies it
 * supported leave. */
static void remove_body(m2c_world *m, m2c_sim_body *body, int32_t k, double t)
{
    body->vx = body->vy = body->ax = body->ay = body->fax = body->fay = body->om = 0.0;
    if (body->sup >= 0)
        m2c_sim_end_support(m, body);
    body->gone = 1;
    m->stamp[body->idx]++;
    if (body->large) {
        m2c_sim_unplace_large(m, body);
    } else {
        m2c_sim_grid_remove(&m->grid, m->bodies, body);
    }
    m2c_sim_emit_input(m, t, body, k);
    for (int32_t q = 0; q < m->s->nbodies; q++) {
        m2c_sim_body *A = &m->bodies[q];
        if (A->sup != body->idx)
            continue;
        m2c_sim_left left = { 0 };
        m2c_sim_leave(m, A, t, NULL, &left);
        m2c_sim_predict_released(m, &left, t);
    }
    m2c_sim_wake_touching(m, body, t);
}

/* Input k sets the velocity of fixed polygon B (based at t, it does not
 * turn): a large one placed in grid cells moves to the large list for good;
 * every body it supported leaves (E leave, free motion: it meets B again at
 * once and is supported again relative to B's new motion, or bounces, or
 * falls); B is predicted against every body again (a large B: each small
 * one that is not fixed or removed, in index order; a small one:
 * predict_body), the bodies that left against the others; last the islands
 * touching B wake (wake_touching). */
static void drive(m2c_world *m, m2c_sim_body *B, int32_t k, double t, double vx, double vy)
{
    B->vx = vx;
    B->vy = vy;
    m->stamp[B->idx]++;
    if (B->placed) {
        m2c_sim_unplace_large(m, B);
        m->large[m->nlarge++] = B->idx;
    }
    m2c_sim_emit_input(m, t, B, k);
    m2c_sim_emit_state(m, B);
    int32_t n = m->s->nbodies;
    m2c_sim_left left = { 0 };
    for (int32_t q = 0; q < n; q++) {
        m2c_sim_body *A = &m->bodies[q];
        if (A->sup == B->idx)
            m2c_sim_leave(m, A, t, B, &left);
    }
    if (B->large) {
        for (int32_t q = 0; q < n; q++) {
            const m2c_sim_body *o = &m->bodies[q];
            if (!o->large && !o->gone && !o->fixed)
                m2c_sim_predict_pair(m, o, B, t);
        }
    } else {
        m2c_sim_predict_body(m, B, t, NULL);
    }
    m2c_sim_predict_released(m, &left, t);
    m2c_sim_wake_touching(m, B, t);
}

/* Input k (not a removal) on the body, based at t: stops the run when the
 * body's motion after it would reach more than 2 LENGTH_MAX from the origin
 * by the end (the live inputs' rule, from the state at t: (|px| + |py|) +
 * (|vx| + |vy|) T + (|ax| + |ay|) T T / 2 + bound, left to right in
 * doubles; a velocity or position that is not finite fails it too). */
static void check_reach(m2c_world *m, const m2c_sim_body *b, int32_t k, double t, int mode, double x, double y)
{
    double px = b->px, py = b->py, vx = b->vx, vy = b->vy;
    if (mode == M2C_SIM_SET_VELOCITY) {
        vx = x;
        vy = y;
    } else if (mode == M2C_SIM_ADD_VELOCITY) {
        vx = b->vx + x;
        vy = b->vy + y;
    } else if (mode == M2C_SIM_IMPULSE) {
        vx = b->vx + x * b->inv_m;
        vy = b->vy + y * b->inv_m;
    } else {
        px = x;
        py = y;
    }
    double T = m->s->end;
    double r = fabs(px) + fabs(py);
    r = r + (fabs(vx) + fabs(vy)) * T;
    r = r + (fabs(b->ax) + fabs(b->ay)) * T * T / 2.0;
    r = r + b->bound;
    if (!(r <= 2.0 * LENGTH_MAX)) {
        char a[M2C_SIM_NUMBER_MAX + 1];
        m2c_sim_die(m, "input %d: body %d at t = %s: reaches more than 2e150 m from the origin by the end", (int)k,
            (int)b->idx, m2c_sim_text(a, t));
    }
}

/* Scripted or live input number k: its body's velocity set or added to,
 * an impulse through its centre, or its centre moved; on a fixed body
 * (set_velocity), drive. */
static void handle_input(m2c_world *m, const m2c_sim_event *ev)
{
    m->stats.inputs++;
    double t = ev->t;
    int32_t k = ev->u.input.k;
    const m2c_sim_input *in = &m->s->inputs[k];
    m2c_sim_body *body = &m->bodies[in->body];
    if (body->gone) {
        char a[M2C_SIM_NUMBER_MAX + 1];
        m2c_sim_die(m, "input %d: body %d was removed before t = %s", (int)k, (int)body->idx, m2c_sim_text(a, t));
    }
    if (body->asleep)
        m2c_sim_handle_wake(m, body, t);
    m2c_sim_rebase(body, t);
    if (in->mode != M2C_SIM_REMOVE)
        check_reach(m, body, k, t, in->mode, in->vx, in->vy);
    if (in->mode == M2C_SIM_REMOVE) {
        remove_body(m, body, k, t);
        return;
    }
    if (body->fixed) {
        drive(m, body, k, t, in->vx, in->vy);
        return;
    }
    if (in->mode == M2C_SIM_TELEPORT) {
        int32_t o = m2c_sim_overlapping(m, body, in->vx, in->vy, t);
        if (o >= 0) {
            char a[M2C_SIM_NUMBER_MAX + 1], b[M2C_SIM_NUMBER_MAX + 1], c[M2C_SIM_NUMBER_MAX + 1];
            m2c_sim_die(m, "input %d: body %d teleported to (%s, %s) at t = %s would overlap body %d", (int)k,
                (int)body->idx, m2c_sim_text(a, in->vx), m2c_sim_text(b, in->vy), m2c_sim_text(c, t), (int)o);
        }
    }
    if (body->sup >= 0)
        m2c_sim_end_support(m, body);
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
            m2c_sim_cell_of(m, body->px, body->py, &body->cx, &body->cy);
            m2c_sim_cell_add(m, body);
        }
    }
    m->stamp[body->idx]++;
    m2c_sim_emit_input(m, t, body, k);
    m2c_sim_emit_state(m, body);
    m2c_sim_left left = { 0 };
    m2c_sim_release(m, body, t, &left);
    m2c_sim_predict_body(m, body, t, NULL);
    m2c_sim_predict_released(m, &left, t);
}

/* The body's centre went the grid's margin past its cell's edge along an axis: it moves
 * to the next cell and is predicted against the row or column it now neighbours. */
static void handle_cell(m2c_world *m, const m2c_sim_event *ev)
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
    m2c_sim_cell_add(m, body);
    fetch_next(m);
    m2c_sim_predict_cells(m, body, x_lo, x_hi, y_lo, y_hi, ev->t);
    /* the walls of the new row or column but those also listed in the two
     * it shares with the old neighbourhood (predicted at its last change):
     * none when no wall is listed in the new 3x3 block */
    m->nnear = 0;
    if (m->wnear[(size_t)body->cy * (size_t)m->s->nx + (size_t)body->cx] == 0) {
        m2c_sim_schedule_cell(m, body, ev->t);
        return;
    }
    m->mark++;
    if (ev->u.cell.axis == 0) {
        int32_t lo = d > 0 ? body->cx - 1 : body->cx;
        m2c_sim_walls_in(m, body, lo, lo + 1, body->cy - 1, body->cy + 1, 0);
    } else {
        int32_t lo = d > 0 ? body->cy - 1 : body->cy;
        m2c_sim_walls_in(m, body, body->cx - 1, body->cx + 1, lo, lo + 1, 0);
    }
    m2c_sim_walls_in(m, body, x_lo, x_hi, y_lo, y_hi, 1);
    m2c_sim_sort_near(m);
    if (!body->fixed)
        for (int32_t k = 0; k < m->nnear; k++)
            m2c_sim_predict_pair(m, body, &m->bodies[m->near[k]], ev->t);
    m2c_sim_schedule_cell(m, body, ev->t);
}

/* The pair reached the end of its Taylor window, or its bounding circles
 * met: predicted again from now. */
static void handle_horizon(m2c_world *m, const m2c_sim_event *ev)
{
    m->stats.horizons++;
    m2c_sim_predict_pair(m, &m->bodies[ev->u.horizon.a], &m->bodies[ev->u.horizon.b], ev->t);
}

/* Draw frame number k: written, and the next one scheduled. */
static void handle_frame(m2c_world *m, const m2c_sim_event *ev)
{
    m->stats.frames++;
    const m2c_sim_scene *s = m->s;
    m2c_sim_emit_frame(m, ev->t);
    double nxt = (double)(ev->u.frame.k + 1) * s->frame_dt;
    if (nxt <= s->end)
        m2c_sim_push_frame(m, nxt, ev->u.frame.k + 1);
}

/* ---- dispatch ------------------------------------------------------------------ */

/* The handler of each event kind, by kind. */
static void (*const handlers[M2C_SIM_KINDS])(m2c_world *, const m2c_sim_event *) = {
    [M2C_SIM_INPUT] = handle_input, [M2C_SIM_COLLISION] = handle_collision, [M2C_SIM_STOP] = handle_stop,
    [M2C_SIM_LEAVE] = handle_leave, [M2C_SIM_CELL] = handle_cell,           [M2C_SIM_HORIZON] = handle_horizon,
    [M2C_SIM_FRAME] = handle_frame,
};

/* Places the bodies in the grid, schedules the inputs and the first frame,
 * and predicts every pair once. */
void m2c_sim_start(m2c_world *m)
{
    enum { AHEAD = 4 };     /* bodies: the grid reads of body k + AHEAD are fetched while k is placed or predicted */
    m2c_sim_scene *s = m->s;
    m2c_sim_body *bodies = m->bodies;
    for (int32_t k = 0; k < s->nbodies; k++) {
        m2c_sim_body *b = &bodies[k];
        if (k + AHEAD < s->nbodies)
            fetch_cell_at(m, &bodies[k + AHEAD]);
        if (!b->large) {
            m2c_sim_cell_of(m, b->px, b->py, &b->cx, &b->cy);
            m2c_sim_cell_add(m, b);
        }
    }
    for (int32_t k = 0; k < s->ninputs; k++)
        m2c_sim_push_input(m, s->inputs[k].t, k);
    if (s->frame_dt > 0.0 && s->frame_dt <= s->end)
        m2c_sim_push_frame(m, s->frame_dt, 1);
    for (int32_t k = 0; k < s->nbodies; k++) {
        const m2c_sim_body *b = &bodies[k];
        if (k + AHEAD < s->nbodies)
            fetch_block(m, &bodies[k + AHEAD]);
        if (!b->large)
            m2c_sim_predict_first(m, b);
    }
}

/* Stops the run when more than max_same events happen at one instant. */
static void count_same_time(m2c_world *m, double t, double *last_t, long long *same)
{
    if (t == *last_t) {
        (*same)++;
        if (*same > m->s->max_same) {
            char num[M2C_SIM_NUMBER_MAX + 1];
            num[m2c_sim_format_number(num, t)] = '\0';
            m2c_sim_die(m, "more than %lld events at t = %s: the scene is stuck", m->s->max_same, num);
        }
    } else {
        *last_t = t;
        *same = 0;
    }
}

/* Handles one event popped from the queue: dropped when stale, counted
 * against max_events (every kind: cell crossings and horizons too) and
 * among the events at one instant (max_same_time), to its kind's handler. */
void m2c_sim_dispatch(m2c_world *m, const m2c_sim_event *ev)
{
    if (m2c_sim_is_stale(m, ev)) {
        m->stats.stale++;
        return;
    }
    if (++m->handled > m->s->max_events) {
        char num[M2C_SIM_NUMBER_MAX + 1];
        num[m2c_sim_format_number(num, ev->t)] = '\0';
        m2c_sim_die(m, "more than %lld events (collisions, inputs, frames, cell crossings, horizons) at t = %s: "
                    "the run was stopped; raise max_events in the scene or --max-events, or shorten end_time",
                    m->s->max_events, num);
    }
    count_same_time(m, ev->t, &m->last_t, &m->same);
    handlers[ev->kind](m, ev);
}

/* The queued events before limit (s; inclusive: at limit too) in
 * (t, kind, seq) order, each to its kind's handler, the events that
 * handling schedules included. */
void m2c_sim_run_until(m2c_world *m, double limit, int inclusive)
{
    m2c_sim_event ev;
    for (;;) {
        const m2c_sim_event *top;
        if (m2c_sim_heap_top(&m->heap, &top) != 0)
            m2c_sim_die(m, "out of memory (event queue of %zu events)", m->heap.n);
        if (top == NULL || top->t > limit || (top->t == limit && !inclusive))
            break;
        if (m2c_sim_heap_pop(&m->heap, &ev) != 0)
            m2c_sim_die(m, "out of memory (event queue of %zu events)", m->heap.n);
        fetch_stamps(m);
        m2c_sim_dispatch(m, &ev);
    }
}
