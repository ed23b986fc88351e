/* The simulator's parts, shared by its source files (not an API):
 * scene (m2c_sim_scene.c), event heap (m2c_sim_heap.c), grid cells
 * (m2c_sim_grid.c), trace writer (m2c_sim_out.c, m2c_sim_format.c) and the
 * simulation itself (m2c_sim.c).  Units: s, m, rad, kg. */
#ifndef M2C_SIM_INTERNAL_H
#define M2C_SIM_INTERNAL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "m2c_sim.h"

/* ---- scene ---------------------------------------------------------------- */

/* One vertex of a polygon and the edge from it to the next vertex, in the
 * body's frame: all precomputed by the scene compiler. */
typedef struct m2c_sim_vertex {
    double lx, ly;          /* m: the vertex about the centre of mass */
    double rho, beta;       /* m, rad: its polar form */
    double psi;             /* rad: angle of the edge's outward normal */
    double h;               /* m: offset of the edge's line, n . v */
    double s1, s2;          /* m: the edge's extent along its tangent */
} m2c_sim_vertex;

typedef struct m2c_sim_body {
    double px, py;          /* m: centre (of rotation) at time tb */
    double vx, vy;          /* m/s: velocity at tb */
    double ax, ay;          /* m/s^2: acceleration (gravity included) */
    double ang, om;         /* rad, rad/s: angle at tb, angular velocity */
    double tb;              /* s: the time of this state */
    double inv_m, inv_i;    /* 1/kg, 1/(kg m^2); 0 for fixed bodies */
    double e;               /* restitution, 0..1 */
    double r;               /* m: circle radius (0 for polygons) */
    double orbit, ophase;   /* m, rad: orbit radius and phase (circles) */
    double bound;           /* m: radius of the bounding circle about the centre */
    m2c_sim_vertex *verts;  /* nverts vertices (polygons), else NULL */
    int32_t nverts;
    int32_t idx;            /* index in the scene */
    uint32_t stamp;         /* bumped when the motion changes (lazy invalidation) */
    int32_t cx, cy;         /* grid cell (small bodies) */
    int32_t slot;           /* index in its cell's list */
    unsigned char polygon, fixed, large;
} m2c_sim_body;

typedef struct m2c_sim_input {
    double t;               /* s */
    int32_t body;
    int32_t mode;           /* 0: set velocity, 1: add velocity */
    double vx, vy;          /* m/s */
} m2c_sim_input;

struct m2c_sim_scene {
    double end;             /* s: end time */
    double frame_dt;        /* s: frame period (0: no frames) */
    double tol;             /* m: distance tolerance */
    double rest_speed;      /* m/s: smallest separation speed of a contact */
    double alpha;           /* rad: Taylor window angle */
    long long max_same;     /* events at one instant before "stuck" */
    double x0, y0, cw, ch;  /* m: grid origin and cell size */
    int32_t nx, ny;         /* grid cells per axis */
    int32_t nbodies, ninputs;
    m2c_sim_body *bodies;
    m2c_sim_vertex *verts;  /* every polygon's vertices, one block */
    m2c_sim_input *inputs;
};

/* ---- event heap: a binary min-heap ordered by (t, kind, seq) --------------- */

enum { M2C_SIM_INPUT = 0, M2C_SIM_COLLISION = 1, M2C_SIM_CELL = 2, M2C_SIM_HORIZON = 3, M2C_SIM_FRAME = 4 };
#define M2C_SIM_KIND_SHIFT 56   /* key = kind << 56 | seq: seq is unique, below 2^56 */

typedef struct m2c_sim_event {
    double t;               /* s */
    uint64_t key;           /* kind and scheduling counter */
    int32_t a, b;           /* bodies (-1: none) */
    uint32_t sa, sb;        /* their stamps when scheduled */
    int32_t feat, i, j;     /* feature and its indices (or input / frame number, axis, direction) */
} m2c_sim_event;

typedef struct m2c_sim_heap {
    m2c_sim_event *ev;
    size_t n, cap;
} m2c_sim_heap;

/* 0, or -1 when out of memory (the heap is unchanged). */
int m2c_sim_heap_push(m2c_sim_heap *h, const m2c_sim_event *e);
/* Removes the first event into *e; the heap must not be empty. */
void m2c_sim_heap_pop(m2c_sim_heap *h, m2c_sim_event *e);
void m2c_sim_heap_free(m2c_sim_heap *h);

/* ---- grid: one list of body indices per cell ------------------------------- */

typedef struct m2c_sim_cell {
    int32_t *items;
    int32_t n, cap;
} m2c_sim_cell;

typedef struct m2c_sim_grid {
    m2c_sim_cell *cells;    /* nx * ny, row-major (cy * nx + cx) */
    int32_t nx, ny;
} m2c_sim_grid;

int m2c_sim_grid_init(m2c_sim_grid *g, int32_t nx, int32_t ny);
void m2c_sim_grid_free(m2c_sim_grid *g);
/* Appends b to the list of its cell (b->cx, b->cy); 0, or -1 when out of memory. */
int m2c_sim_grid_add(m2c_sim_grid *g, m2c_sim_body *bodies, m2c_sim_body *b);
/* Removes b from its cell's list: the last element moves into its place. */
void m2c_sim_grid_remove(m2c_sim_grid *g, m2c_sim_body *bodies, m2c_sim_body *b);

/* ---- trace writer: a buffer flushed to a FILE ------------------------------ */

typedef struct m2c_sim_out {
    FILE *f;
    char *buf;
    size_t n, cap;
    int failed;             /* a write failed */
} m2c_sim_out;

int m2c_sim_out_init(m2c_sim_out *o, FILE *f);
void m2c_sim_out_flush(m2c_sim_out *o);
void m2c_sim_out_free(m2c_sim_out *o);

/* Room for one trace line (the longest is a collision: 11 fields). */
#define M2C_SIM_LINE_MAX 512
static inline char *m2c_sim_out_reserve(m2c_sim_out *o)
{
    if (o->cap - o->n < M2C_SIM_LINE_MAX)
        m2c_sim_out_flush(o);
    return o->buf + o->n;
}

static inline char *m2c_sim_put_str(char *p, const char *s)
{
    while (*s)
        *p++ = *s++;
    return p;
}

static inline char *m2c_sim_put_num(char *p, double x)
{
    return p + m2c_sim_format_number(p, x);
}

char *m2c_sim_put_int(char *p, long long v);

#endif
