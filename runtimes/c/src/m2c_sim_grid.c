/* The broad phase's cells: one list of body indices per cell, in the
 * reference's order (append at the end; remove by moving the last element
 * into the hole, as sim.py's cell_remove).  Each body knows its slot, so a
 * removal costs O(1).  Up to M2C_SIM_CELL_INLINE bodies live in the cell
 * itself (no pointer to follow); a fuller cell moves them, in order, to an
 * array that grows by doubling and never shrinks: no allocation once every
 * cell has held its most bodies. */
#include <stdlib.h>
#include <string.h>

#include "m2c_sim_internal.h"

int m2c_sim_grid_init(m2c_sim_grid *g, int32_t nx, int32_t ny)
{
    g->nx = nx;
    g->ny = ny;
    g->cells = calloc((size_t)nx * (size_t)ny, sizeof *g->cells);
    m2c_sim_huge_pages(g->cells, (size_t)nx * (size_t)ny * sizeof *g->cells);
    return g->cells == NULL ? -1 : 0;
}

void m2c_sim_grid_free(m2c_sim_grid *g)
{
    if (g->cells != NULL) {
        size_t n = (size_t)g->nx * (size_t)g->ny;
        for (size_t k = 0; k < n; k++)
            if (g->cells[k].cap != 0)
                free(g->cells[k].u.items);
        free(g->cells);
    }
    g->cells = NULL;
}

int m2c_sim_grid_add(m2c_sim_grid *g, m2c_sim_body *bodies, m2c_sim_body *b)
{
    (void)bodies;
    m2c_sim_cell *c = &g->cells[(size_t)b->cy * (size_t)g->nx + (size_t)b->cx];
    int32_t *items;
    if (c->cap == 0) {
        if (c->n < M2C_SIM_CELL_INLINE) {
            items = c->u.in;
        } else {
            int32_t cap = 2 * M2C_SIM_CELL_INLINE;
            items = malloc((size_t)cap * sizeof *items);
            if (items == NULL)
                return -1;
            memcpy(items, c->u.in, sizeof c->u.in);
            c->u.items = items;
            c->cap = cap;
        }
    } else {
        if (c->n == c->cap) {
            int32_t cap = 2 * c->cap;
            items = realloc(c->u.items, (size_t)cap * sizeof *items);
            if (items == NULL)
                return -1;
            c->u.items = items;
            c->cap = cap;
        }
        items = c->u.items;
    }
    b->slot = c->n;
    items[c->n++] = b->idx;
    return 0;
}

void m2c_sim_grid_remove(m2c_sim_grid *g, m2c_sim_body *bodies, m2c_sim_body *b)
{
    m2c_sim_cell *c = &g->cells[(size_t)b->cy * (size_t)g->nx + (size_t)b->cx];
    int32_t *items = c->cap != 0 ? c->u.items : c->u.in;
    int32_t k = b->slot;
    int32_t last = items[--c->n];
    if (k < c->n) {
        items[k] = last;
        bodies[last].slot = k;
    }
    b->slot = -1;
}
