/* The world: the state a prediction reads and writes (struct m2c_world in
 * m2c_sim_internal.h: bodies, stamps, grid, queue, counters), its
 * allocation and freeing, the error exit (m2c_sim_die) and the scheduling
 * of event records, each stamped with its bodies' stamps now (lazy
 * invalidation: a record whose stamps differ from its bodies' is stale).
 * Times in s. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "m2c_sim_internal.h"

_Noreturn void m2c_sim_die(m2c_world *m, const char *format, ...)
{
    va_list ap;
    va_start(ap, format);
    vsnprintf(m->err, sizeof m->err, format, ap);
    va_end(ap);
    m->broken = 1;
    longjmp(m->fail, 1);
}

/* The reference pops a stale event and counts it when its time comes (if
 * it is not after the end).  A stale event stays stale (stamps only grow),
 * so the queue may drop it earlier and count it then: the same count, and
 * a queue that holds mostly live events. */
static int drop_stale(void *ctx, const m2c_sim_event *e)
{
    m2c_world *m = ctx;
    if (!m2c_sim_is_stale(m, e))
        return 0;
    if (e->t <= m->s->end)
        m->stats.stale++;
    return 1;
}

/* Drops the stale events once the queue has doubled since the last sweep. */
static void sweep(m2c_world *m)
{
    m2c_sim_heap_sweep(&m->heap, drop_stale, m);
    size_t live = m->heap.n;
    m->sweep_at = 2 * live > 4096 ? 2 * live : 4096;
}

/* Queues an event record (its t and kind set, and the fields of its kind);
 * sweeps the stale ones out when the queue has doubled. */
void m2c_sim_push(m2c_world *m, const m2c_sim_event *e)
{
    if (!(e->t >= 0.0))     /* never: every time is now or later, and now >= 0 */
        m2c_sim_die(m, "an event at a time that is not a number or negative");
    if (m2c_sim_heap_push(&m->heap, e) != 0)
        m2c_sim_die(m, "out of memory (event queue of %zu events)", m->heap.n);
    if (m->heap.n >= m->sweep_at)
        sweep(m);
}

void m2c_sim_push_collision(m2c_world *m, double t, int32_t feature, const m2c_sim_body *A, const m2c_sim_body *B,
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
    m2c_sim_push(m, &e);
}

void m2c_sim_push_horizon(m2c_world *m, double t, const m2c_sim_body *A, const m2c_sim_body *B)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_HORIZON };
    e.u.horizon.a = A->idx;
    e.u.horizon.b = B->idx;
    e.u.horizon.stamp_a = m->stamp[A->idx];
    e.u.horizon.stamp_b = m->stamp[B->idx];
    m2c_sim_push(m, &e);
}

void m2c_sim_push_cell(m2c_world *m, double t, const m2c_sim_body *b, int32_t axis, int32_t direction)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_CELL };
    e.u.cell.body = b->idx;
    e.u.cell.axis = axis;
    e.u.cell.direction = direction;
    e.u.cell.stamp = m->stamp[b->idx];
    e.u.cell.cx = b->cx;
    e.u.cell.cy = b->cy;
    m2c_sim_push(m, &e);
}

void m2c_sim_push_stop(m2c_world *m, double t, const m2c_sim_body *b)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_STOP };
    e.u.stop.body = b->idx;
    e.u.stop.stamp = m->stamp[b->idx];
    m2c_sim_push(m, &e);
}

void m2c_sim_push_leave(m2c_world *m, double t, const m2c_sim_body *b)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_LEAVE };
    e.u.leave.body = b->idx;
    e.u.leave.stamp = m->stamp[b->idx];
    m2c_sim_push(m, &e);
}

void m2c_sim_push_input(m2c_world *m, double t, int32_t k)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_INPUT };
    e.u.input.k = k;
    m2c_sim_push(m, &e);
}

void m2c_sim_push_frame(m2c_world *m, double t, int32_t k)
{
    m2c_sim_event e = { .t = t, .kind = M2C_SIM_FRAME };
    e.u.frame.k = k;
    m2c_sim_push(m, &e);
}

/* Fetching ahead pays where the bodies and cells miss the cache: at 10^4
 * and 10^5 disks (3.5 and 42 MB) it takes 26 % and 30 % off the CPU
 * time; where they stay in a core's second-level cache (10^3 disks: 0.4
 * MB) it is only its instructions, 7 % more per event.  So the fetch-ahead
 * helpers of m2c_sim_handlers.c (but the queue's and predict_cells' own
 * few prefetches) work only above this many bytes of bodies and cells: about a core's second-level
 * cache on the machine measured (docs/throughput.md). */
#ifndef M2C_SIM_FETCH_BYTES
#define M2C_SIM_FETCH_BYTES ((size_t)1 << 20)
#endif

/* Whether to fetch ahead, from the bodies' and cells' bytes now (the scene
 * opened, or a body added). */
void m2c_sim_choose_fetch(m2c_world *m)
{
    size_t bytes = ((size_t)m->s->nbodies + 1) * sizeof *m->bodies
                   + (size_t)m->s->nx * (size_t)m->s->ny * sizeof *m->grid.cells;
    m->fetch = bytes > M2C_SIM_FETCH_BYTES;
}

/* Takes scene, allocates the world's state, places the large bodies and
 * starts (m2c_sim_start). */
int m2c_sim_open(m2c_world *m, m2c_sim_scene *scene, int cc_variants, int pe_variants, FILE *trace)
{
    m->s = scene;
    m->bodies = scene->bodies;
    m->n_cc = cc_variants;
    m->n_pe = pe_variants;
    m->sweep_at = 4096;
    m->last_t = -1.0;
    m->unpaid = 0;
    m->touched_t = -1.0;
    m->jammed_t = -1.0;
    M2C_SIM_CATCH(m);
    if (m2c_sim_out_init(&m->out, trace) != 0)
        m2c_sim_die(m, "out of memory");
    if (cc_variants < 1 || pe_variants < 1)
        m2c_sim_die(m, "no variants to count (circle_circle %d, point_edge %d)", cc_variants, pe_variants);
    m->cc_counts = calloc((size_t)cc_variants, sizeof *m->cc_counts);
    m->pe_counts = calloc((size_t)pe_variants, sizeof *m->pe_counts);
    m->large = calloc((size_t)scene->nbodies + 1, sizeof *m->large);
    m->stamp = calloc((size_t)scene->nbodies + 1, sizeof *m->stamp);
    m->restc = calloc(M2C_SIM_REST_SLOTS * ((size_t)scene->nbodies + 1), sizeof *m->restc);
    size_t nv = scene->verts_cap + 1;
    m->trig_cap = nv;
    m->vtrig = calloc(nv, sizeof *m->vtrig);
    m->etrig = calloc(nv, sizeof *m->etrig);
    if (m->stamp == NULL || m->restc == NULL || m->vtrig == NULL || m->etrig == NULL || m->cc_counts == NULL || m->pe_counts == NULL
        || m->large == NULL || m2c_sim_grid_init(&m->grid, scene->nx, scene->ny) != 0)
        m2c_sim_die(m, "out of memory");
    m2c_sim_choose_fetch(m);
    m->walls = calloc((size_t)scene->nx * (size_t)scene->ny, sizeof *m->walls);
    m->wnear = calloc((size_t)scene->nx * (size_t)scene->ny, sizeof *m->wnear);
    if (m->walls == NULL || m->wnear == NULL)
        m2c_sim_die(m, "out of memory");
    m2c_sim_huge_pages(m->walls, (size_t)scene->nx * (size_t)scene->ny * sizeof *m->walls);
    m2c_sim_huge_pages(m->wnear, (size_t)scene->nx * (size_t)scene->ny * sizeof *m->wnear);
    for (int32_t k = 0; k < scene->nbodies; k++)
        if (scene->bodies[k].large)
            m2c_sim_place_large(m, &scene->bodies[k]);
    m2c_sim_start(m);
    return 0;
}

/* Frees everything the world holds, the scene too. */
void m2c_sim_close(m2c_world *m)
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
    free(m->restc);
    free(m->vtrig);
    free(m->etrig);
    free(m->scratch);
    free(m->scratch_deg);
    free(m->touched);
    free(m->jammed);
    m2c_sim_cluster_free(&m->clu);
    m2c_sim_scene_free(m->s);
    m->s = NULL;
}
