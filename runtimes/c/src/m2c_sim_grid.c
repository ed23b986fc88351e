/* The broad phase's cells: one list of body indices per cell, in the
 * reference's order (append at the end; remove by moving the last element
 * into the hole, as sim.py's cell_remove).  Each body knows its slot, so a
 * removal costs O(1).  A list grows by doubling and never shrinks: no
 * allocation once every cell has held its most bodies. */
#include <stdlib.h>

#include "m2c_sim_internal.h"

int m2c_sim_grid_init(m2c_sim_grid *g, int32_t nx, int32_t ny)
{
    g->nx = nx;
    g->ny = ny;
    g->cells = calloc((size_t)nx * (size_t)ny, sizeof *g->cells);
    return g->cells == NULL ? -1 : 0;
}

void m2c_sim_grid_free(m2c_sim_grid *g)
{
    if (g->cells != NULL) {
        size_t n = (size_t)g->nx * (size_t)g->ny;
        for (size_t k = 0; k < n; k++)
            free(g->cells[k].items);
        free(g->cells);
    }
    g->cells = NULL;
}

int m2c_sim_grid_add(m2c_sim_grid *g, m2c_sim_body *bodies, m2c_sim_body *b)
{
    (void)bodies;
    m2c_sim_cell *c = &g->cells[(size_t)b->cy * (size_t)g->nx + (size_t)b->cx];
    if (c->n == c->cap) {
        int32_t cap = c->cap ? 2 * c->cap : 4;
        int32_t *items = realloc(c->items, (size_t)cap * sizeof *items);
        if (items == NULL)
            return -1;
        c->items = items;
        c->cap = cap;
    }
    b->slot = c->n;
    c->items[c->n++] = b->idx;
    return 0;
}

void m2c_sim_grid_remove(m2c_sim_grid *g, m2c_sim_body *bodies, m2c_sim_body *b)
{
    m2c_sim_cell *c = &g->cells[(size_t)b->cy * (size_t)g->nx + (size_t)b->cx];
    int32_t k = b->slot;
    int32_t last = c->items[--c->n];
    if (k < c->n) {
        c->items[k] = last;
        bodies[last].slot = k;
    }
    b->slot = -1;
}
