/* The broad phase (docs/simulator.md, "Broad phase"): a uniform grid of
 * cells holding the small bodies, the large fixed bodies that do not move
 * listed in the cells their boxes cover (walls), and the list of the other
 * large bodies, which every body checks.  Lengths in m.
 *
 * The cells: one list of body indices per cell, in the
 * reference's order (append at the end; remove by moving the last element
 * into the hole, as the reference's cell_remove).  Each body knows its slot, so a
 * removal costs O(1).  Up to M2C_SIM_CELL_INLINE bodies live in the cell
 * itself (no pointer to follow); a fuller cell moves them, in order, to an
 * array that grows by doubling and never shrinks: no allocation once every
 * cell has held its most bodies. */
#include <math.h>
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

/* ---- the world's grid: a body's cell, walls, large bodies near ---------------- */

/* The cell of point (x, y) (m), clamped to the grid. */
void m2c_sim_cell_of(m2c_world *m, double x, double y, int32_t *cx, int32_t *cy)
{
    const m2c_sim_scene *s = m->s;
    double ix = floor((x - s->x0) / s->cw);
    double iy = floor((y - s->y0) / s->ch);
    if (ix != ix || iy != iy)
        m2c_sim_die(m, "a body's position is not a number");
    ix = ix < 0.0 ? 0.0 : (ix > (double)(s->nx - 1) ? (double)(s->nx - 1) : ix);
    iy = iy < 0.0 ? 0.0 : (iy > (double)(s->ny - 1) ? (double)(s->ny - 1) : iy);
    *cx = (int32_t)ix;
    *cy = (int32_t)iy;
}

/* Appends b to the list of its cell (b->cx, b->cy). */
void m2c_sim_cell_add(m2c_world *m, m2c_sim_body *b)
{
    if (m2c_sim_grid_add(&m->grid, m->bodies, b) != 0)
        m2c_sim_die(m, "out of memory (grid cell)");
}

/* Adds dn to the count of walls near each cell whose 3x3 block holds
 * cell (jx, jy) (the cells around it, clamped to the grid). */
static void wnear_add(m2c_world *m, int32_t jx, int32_t jy, int32_t dn)
{
    const m2c_sim_scene *s = m->s;
    int32_t y0 = jy > 0 ? jy - 1 : 0, y1 = jy < s->ny - 1 ? jy + 1 : s->ny - 1;
    int32_t x0 = jx > 0 ? jx - 1 : 0, x1 = jx < s->nx - 1 ? jx + 1 : s->nx - 1;
    for (int32_t y = y0; y <= y1; y++)
        for (int32_t x = x0; x <= x1; x++)
            m->wnear[(size_t)y * (size_t)s->nx + (size_t)x] += dn;
}

/* Appends idx to a wall list (cell); dies when out of memory. */
static void wall_push(m2c_world *m, m2c_sim_wall *c, int32_t idx)
{
    if (c->n == c->cap) {
        int32_t cap = c->cap ? 2 * c->cap : 4;
        int32_t *more = realloc(c->items, (size_t)cap * sizeof *more);
        if (more == NULL)
            m2c_sim_die(m, "out of memory (grid walls)");
        c->items = more;
        c->cap = cap;
    }
    c->items[c->n++] = idx;
}

/* A large body into the grid's walls when it is fixed and does not move
 * (v = a = 0): its box (a polygon that does not turn: its vertices at its
 * time; else its centre +- bound) in cells, every cell from cell_of(the
 * box's low corner) to cell_of(its high corner); else into the large list. */
void m2c_sim_place_large(m2c_world *m, m2c_sim_body *b)
{
    if (!(b->fixed && b->vx == 0.0 && b->vy == 0.0 && b->ax == 0.0 && b->ay == 0.0)) {
        m->large[m->nlarge++] = b->idx;
        b->placed = 0;
        return;
    }
    double x0, y0, x1, y1;
    if (b->polygon && b->om == 0.0) {
        m2c_sim_point_at(m, b, &b->verts[0], b->tb, &x0, &y0);
        x1 = x0;
        y1 = y0;
        for (int32_t k = 0; k < b->nverts; k++) {
            double x, y;
            m2c_sim_point_at(m, b, &b->verts[k], b->tb, &x, &y);
            x0 = m2c_sim_min(x0, x);
            x1 = m2c_sim_max(x1, x);
            y0 = m2c_sim_min(y0, y);
            y1 = m2c_sim_max(y1, y);
        }
    } else {
        x0 = b->px - b->bound;
        x1 = b->px + b->bound;
        y0 = b->py - b->bound;
        y1 = b->py + b->bound;
    }
    int32_t i0, j0, i1, j1;
    m2c_sim_cell_of(m, x0, y0, &i0, &j0);
    m2c_sim_cell_of(m, x1, y1, &i1, &j1);
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
void m2c_sim_unplace_large(m2c_world *m, m2c_sim_body *b)
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
static void near_room(m2c_world *m, int32_t n)
{
    if ((size_t)m->nnear + (size_t)n > m->near_cap) {
        size_t cap = 2 * ((size_t)m->nnear + (size_t)n) + 16;
        int32_t *more = realloc(m->near, cap * sizeof *more);
        if (more == NULL)
            m2c_sim_die(m, "out of memory (large bodies near)");
        m->near = more;
        m->near_cap = cap;
    }
}

/* Appends to m->near (when keep) the placed large bodies listed in the cells
 * x_lo..x_hi, y_lo..y_hi (clamped to the grid, rows then columns), but b and
 * those already carrying the current mark, and marks them. */
void m2c_sim_walls_in(m2c_world *m, const m2c_sim_body *b, int32_t x_lo, int32_t x_hi, int32_t y_lo, int32_t y_hi,
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

/* m->near (the answer of walls_in, large_near) in index order. */
void m2c_sim_sort_near(m2c_world *m)
{
    if (m->nnear > 1)
        qsort(m->near, (size_t)m->nnear, sizeof *m->near, by_index);
}

/* The large bodies b predicts against, into m->near (m->nnear of them):
 * those placed in its 3x3 cells and every one in the large list, each
 * once, but b, in index order. */
void m2c_sim_large_near(m2c_world *m, const m2c_sim_body *b)
{
    m->nnear = 0;
    if (m->wnear[(size_t)b->cy * (size_t)m->s->nx + (size_t)b->cx] != 0) {     /* else no wall near */
        m->mark++;
        m2c_sim_walls_in(m, b, b->cx - 1, b->cx + 1, b->cy - 1, b->cy + 1, 1);
    }
    near_room(m, m->nlarge);
    for (int32_t k = 0; k < m->nlarge; k++)
        if (m->large[k] != b->idx)
            m->near[m->nnear++] = m->large[k];
    m2c_sim_sort_near(m);
}
