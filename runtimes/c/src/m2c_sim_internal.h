/* The simulator's parts, shared by its source files (not an API): the
 * types of every concept and the functions one concept's file calls in
 * another's, in the order of CONCEPTS.md (small hot functions are static
 * inline here).  One file per concept:
 *   m2c_sim_scene.c     the flat scene read from text
 *   m2c_sim_queue.c     event records, the priority queue
 *   m2c_sim_grid.c      broad phase: cells, walls, large bodies
 *   m2c_sim_motion.c    motion between events
 *   m2c_sim_predict.c   predictions: pairs, features, first valid root, cell crossings, horizons
 *   m2c_sim_contact.c   contact frame and impulse
 *   m2c_sim_cluster.c   simultaneous contacts solved together
 *   m2c_sim_support.c   resting and sliding on a fixed body, carried bodies
 *   m2c_sim_sleep.c     sleeping islands
 *   m2c_sim_overlap.c   overlap check of a teleport or an added body
 *   m2c_sim_world.c     the state a prediction reads and writes: allocation, stamps, scheduling
 *   m2c_sim_live.c      the live world's API (m2c_world.h) and the engine's entries
 *   m2c_sim_handlers.c  one handler per event kind and their dispatch
 *   m2c_sim_out.c       the trace writer (numbers: m2c_sim_format.c)
 *   m2c_sim_pages.c     huge pages for the large arrays
 * Units: s, m, rad, kg. */
#ifndef M2C_SIM_INTERNAL_H
#define M2C_SIM_INTERNAL_H

#include <math.h>
#include <setjmp.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "m2c_sim.h"
#include "m2c_toi.h"
#include "m2c_world.h"

/* Nothing declared here is exported from the shared library of the world
 * API (only m2c_world.h's functions are): calls between the files may be
 * inlined there too. */
#pragma GCC visibility push(hidden)

/* Advises the kernel to map the whole 2 MB pages inside [p, p + bytes) as
 * huge pages (m2c_sim_pages.c): call it on a large array before it is first
 * written.  A hint only. */
void m2c_sim_huge_pages(void *p, size_t bytes);

/* ---- scene ---------------------------------------------------------------- */

/* One vertex of a polygon and the edge from it to the next vertex, in the
 * body's frame: all precomputed by the scene compiler (about the centre of
 * mass; nx, ny are cos psi, sin psi, but exact where the compiler's
 * quotient is: (0, 1) for a level top face; cover: the fixed body that
 * covers the edge, so that no body can touch it while that one is there,
 * -1: none).  The TOI library's vertex (m2c_toi.h), field for field. */
typedef m2c_toi_vertex m2c_sim_vertex;

/* A body, laid out for the predictions: a pair's prediction reads only
 * the first two cache lines (its motion, then its shape and the flags and
 * indices every pair checks), so a neighbour predicted against costs two
 * lines; what only the handling of its own events reads (impulses, cell,
 * support, islands, walls) follows.  _Alignas on px alone (on a
 * declaration of several fields it would align each one).  (Its stamp, for
 * lazy invalidation, is in an array of its own: the world's stamp.) */
typedef struct m2c_sim_body {
    /* line 0: the motion */
    _Alignas(64) double px;         /* m: centre (of rotation) at time tb */
    double py;
    double vx, vy;          /* m/s: velocity at tb */
    double ax, ay;          /* m/s^2: acceleration now (gravity included; while supported, the
                               support's acceleration plus the relative one along its edge, less
                               friction) */
    double tb;              /* s: the time of this state */
    double om;              /* rad/s: angular velocity */
    /* line 1: the rest of what predict_pair reads of both bodies */
    double ang;             /* rad: angle at tb */
    double r;               /* m: circle radius (0 for polygons) */
    double orbit, ophase;   /* m, rad: orbit radius and phase (circles) */
    double bound;           /* m: radius of the bounding circle about the centre */
    double window;          /* rad: its window angle when it turns and its partner does not (0: it never turns) */
    int32_t idx;            /* index in the scene */
    int32_t sup;            /* index of the body supporting it (fixed), or carrying it (movable), -1: free */
    unsigned char polygon, fixed, large;
    unsigned char asleep;   /* frozen in a sleeping island (v = a = w = 0, no events of its own) */
    unsigned char gone;     /* removed from the world (remove_body, input MODE 4): frozen, out of the grid */
    unsigned char placed;   /* a large body listed in the grid's walls (cells wcells), not in the large list */
    /* then what the handlers of its own events read */
    double inv_m, inv_i;    /* 1/kg, 1/(kg m^2); 0 for fixed bodies */
    double e;               /* restitution, 0..1 */
    double mu;              /* friction coefficient (Coulomb), >= 0 */
    int32_t cx, cy;         /* grid cell (small bodies) */
    int32_t slot;           /* index in its cell's list */
    int32_t nverts;
    m2c_sim_vertex *verts;  /* nverts vertices (polygons), else NULL */
    int32_t sup_edge;       /* the supporting edge (index into sup's vertices) */
    int32_t carry;          /* how many bodies it carries (their sup is this movable body) */
    double fax, fay;        /* m/s^2: free acceleration (gravity and the body's own), from the scene */
    double tx, ty;          /* unit tangent of the supporting edge (along increasing S1..S2) */
    double load;            /* m/s^2: free acceleration relative to the support's pressing onto it, > 0 */
    double at;              /* m/s^2: free acceleration relative to the support's, along the tangent */
    int32_t island;         /* the island's number (the index of its first sleeper), -1: awake */
    int32_t non;            /* asleep: how many bodies it rests on (in on) */
    int32_t on[5];          /* asleep: the bodies it rests on, its support first (1 + M2C_SIM_REST_SLOTS) */
    int32_t rest;           /* asleep: the fixed body it fell asleep supported on (its edge frame kept in tx, ty), else -1 */
    int32_t wcells[4];      /* the cells its box covers: x_lo, x_hi, y_lo, y_hi */
    unsigned long long seen;    /* the mark of the last large_near (walls_in) that listed it */
} m2c_sim_body;

/* the two lines a pair's prediction reads */
_Static_assert(offsetof(m2c_sim_body, placed) < 128, "predict_pair's fields in the first two lines");
_Static_assert(sizeof(m2c_sim_body) % 64 == 0, "bodies on whole cache lines");

/* A cache of cos and sin of one angle (rad). */
typedef struct m2c_sim_trig {
    double angle, c, s;
    int valid;
} m2c_sim_trig;

/* input modes (the flat scene's MODE; docs/simulator.md) */
enum { M2C_SIM_SET_VELOCITY = 0, M2C_SIM_ADD_VELOCITY = 1, M2C_SIM_IMPULSE = 2, M2C_SIM_TELEPORT = 3,
       M2C_SIM_REMOVE = 4 };

/* An input of this mode may act on b: any on a movable body; on a fixed
 * one, removal, or set_velocity when it is a polygon that does not turn
 * (its edges then translate: docs/simulator.md, Contact model). */
static inline int m2c_sim_drivable(const m2c_sim_body *b, int32_t mode)
{
    if (!b->fixed || mode == M2C_SIM_REMOVE)
        return 1;
    return mode == M2C_SIM_SET_VELOCITY && b->polygon && b->om == 0.0;
}

/* A scripted or live input. */
typedef struct m2c_sim_input {
    double t;               /* s */
    int32_t body;
    int32_t mode;           /* M2C_SIM_SET_VELOCITY, M2C_SIM_ADD_VELOCITY (vx, vy m/s), M2C_SIM_IMPULSE
                               (vx, vy: the impulse, N s, through the centre), M2C_SIM_TELEPORT (vx, vy:
                               the new centre, m), M2C_SIM_REMOVE (vx, vy unused, 0) */
    double vx, vy;
} m2c_sim_input;

struct m2c_sim_scene {
    double end;             /* s: end time */
    double frame_dt;        /* s: frame period (0: no frames) */
    double tol;             /* m: distance tolerance */
    double rest_speed;      /* m/s: smallest separation speed of a contact */
    double alpha;           /* rad: Taylor window angle */
    long long max_same;     /* events at one instant before "stuck" */
    long long max_events;   /* events handled in a run (every kind but stale ones) */
    double x0, y0, cw, ch;  /* m: grid origin and cell size */
    int32_t nx, ny;         /* grid cells per axis */
    double margin;          /* m: a moving centre changes cell this far past the edge */
    double half_cell;       /* m: half of min(cw, ch) */
    int32_t nbodies, ninputs;
    int32_t inputs_cap;     /* room in inputs (live inputs are appended: the recording) */
    int32_t bodies_cap;     /* room in bodies (add_body appends) */
    size_t nverts_all, verts_cap;   /* vertices in verts, and room */
    m2c_sim_body *bodies;
    m2c_sim_vertex *verts;  /* every polygon's vertices, one block */
    m2c_sim_input *inputs;
};

/* A `body ...` line and its `v` lines (the whole text) into b, index idx,
 * checked as a scene's body (docs/simulator.md, "Flat scene checks") with
 * the scene's tolerance tol (m) and end time (s), an edge's cover one of
 * the idx bodies before it; its vertices into a new *verts (b->verts left
 * NULL): 0, or -1 with the message ("add_body: ..."). */
int m2c_sim_body_read(const char *text, m2c_sim_body *b, int32_t idx, double tol, double end, m2c_sim_vertex **verts,
                      char *err, size_t errlen);

/* ---- event queue: ordered by (t, kind, seq) ---------------------------------- */

enum {
    M2C_SIM_INPUT = 0, M2C_SIM_COLLISION = 1, M2C_SIM_STOP = 2, M2C_SIM_LEAVE = 3, M2C_SIM_CELL = 4,
    M2C_SIM_HORIZON = 5, M2C_SIM_FRAME = 6, M2C_SIM_KINDS = 7
};

/* An event record: t, kind, and the fields of its kind (docs/simulator.md,
 * "The reference's structure").  stamp_*: the bodies' stamps when the
 * record was scheduled (a collision, horizon or cell record is stale when
 * one differs from its body's stamp now). */
typedef struct m2c_sim_event {
    double t;               /* s, not negative */
    int32_t kind;
    union {
        struct {
            int32_t k;      /* index in the scene's inputs */
        } input;
        struct {
            int32_t a, b;
            int32_t feature;    /* 0 circle_circle: circle of a against the circle of b (j < 0) or vertex j of b;
                                   1 point_edge: circle of a (i < 0) or vertex i of a against edge j of b */
            int32_t i, j;
            uint32_t stamp_a, stamp_b;
        } collision;
        struct {
            int32_t body;
            uint32_t stamp;
        } stop;             /* a sliding supported body's tangential speed reaches zero */
        struct {
            int32_t body;
            uint32_t stamp;
        } leave;            /* a supported body's centre, projected on the edge, reaches its end */
        struct {
            int32_t body;
            int32_t axis;       /* 0: x, 1: y */
            int32_t direction;  /* +1 or -1: the neighbouring cell entered */
            uint32_t stamp;
            int32_t cx, cy;     /* the cell it leaves (the body's own when the record is live): only
                                   a hint of which cells to fetch ahead, never read otherwise */
        } cell;
        struct {
            int32_t a, b;
            uint32_t stamp_a, stamp_b;
        } horizon;
        struct {
            int32_t k;      /* frame k is at k * frame_dt */
        } frame;
    } u;
} m2c_sim_event;

/* What the queue orders: 16 bytes.  tb: the bits of t + 0.0 (t >= 0, so
 * they order as t does); key: kind, then seq (the scheduling counter),
 * then the slot of `rest` where the event waits. */
typedef struct m2c_sim_entry {
    uint64_t tb;
    uint64_t key;
} m2c_sim_entry;

typedef struct m2c_sim_bucket {
    m2c_sim_entry *e;
    size_t n, cap;
} m2c_sim_bucket;

#ifndef M2C_SIM_SLOT_BITS
#define M2C_SIM_SLOT_BITS 28        /* events in the queue at once: 2^28 */
#endif
#ifndef M2C_SIM_SEQ_BITS
#define M2C_SIM_SEQ_BITS 33         /* then seq is renumbered (keeping the order) */
#endif

/* A radix heap on the hex digits of t's bits (m2c_sim_queue.c): near[]
 * holds, as a 4-ary heap, the events at or before `last` (the time last
 * reached); bucket 16 i + j the later ones whose bits first differ from
 * last's in hex digit i, where theirs is j. */
#define M2C_SIM_BUCKETS 256
typedef struct m2c_sim_heap {
    size_t n;                   /* events queued */
    uint64_t last;              /* bits of the time last reached */
    m2c_sim_bucket near;        /* a 4-ary heap */
    m2c_sim_bucket bucket[M2C_SIM_BUCKETS];
    uint64_t full[M2C_SIM_BUCKETS / 64];    /* bit k set: bucket k is not empty */
    m2c_sim_event *rest;        /* the events, by slot (cap of them) */
    size_t cap;
    uint32_t *free;             /* unused slots (a stack) */
    size_t nfree, used;         /* slots never used start at `used` */
    uint64_t seq;               /* the next scheduling counter */
} m2c_sim_heap;

/* Schedules e (its time must not be negative): 0, or -1 when out of memory
 * or too many events at once (the queue is unchanged). */
int m2c_sim_heap_push(m2c_sim_heap *h, const m2c_sim_event *e);
/* Removes the first event into *e (the queue must not be empty): 0, or -1
 * when out of memory (an event may then be lost: give up). */
int m2c_sim_heap_pop(m2c_sim_heap *h, m2c_sim_event *e);
/* Removes every event for which drop(ctx, e) is true; the others keep their
 * order (their keys are unchanged). */
void m2c_sim_heap_sweep(m2c_sim_heap *h, int (*drop)(void *ctx, const m2c_sim_event *e), void *ctx);
void m2c_sim_heap_free(m2c_sim_heap *h);
/* The event first in the queue (moving `last` on when near is empty), or
 * NULL when the queue is empty; it stays queued.  -1 out of memory. */
int m2c_sim_heap_top(m2c_sim_heap *h, const m2c_sim_event **e);

/* The event first in the queue now, or NULL: a hint for fetching what it
 * will need (the queue may change before it is popped). */
static inline const m2c_sim_event *m2c_sim_heap_peek(const m2c_sim_heap *h)
{
    if (h->near.n == 0)
        return NULL;
    return &h->rest[h->near.e[0].key & ((UINT64_C(1) << M2C_SIM_SLOT_BITS) - 1u)];
}

/* ---- grid: one list of body indices per cell ------------------------------- */

#define M2C_SIM_CELL_INLINE 6      /* bodies a cell holds without an allocation */
typedef struct m2c_sim_cell {
    int32_t n;              /* bodies in the cell */
    int32_t cap;            /* 0: they are in u.in, else u.items holds cap of them */
    union {
        int32_t in[M2C_SIM_CELL_INLINE];
        int32_t *items;
    } u;
} m2c_sim_cell;

static inline const int32_t *m2c_sim_cell_items(const m2c_sim_cell *c)
{
    return c->cap != 0 ? c->u.items : c->u.in;
}

/* The large bodies listed in one cell (the walls), by index. */
typedef struct m2c_sim_wall {
    int32_t n, cap;
    int32_t *items;
} m2c_sim_wall;

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

/* Appends the indices of cell c to ids[*ni] when the cell keeps its list
 * inline and room is left: all M2C_SIM_CELL_INLINE slots are copied at
 * once (a loop over the count mispredicts its exit at nearly every cell;
 * the slots past the count are overwritten by the next cell's or never
 * read).  1 when done, 0 when the caller walks the list itself. */
static inline __attribute__((always_inline)) int m2c_sim_gather_inline(const m2c_sim_cell *c, int32_t *ids, int *ni,
                                                                       int room)
{
    if (c->cap != 0 || *ni + M2C_SIM_CELL_INLINE > room)
        return 0;
    memcpy(&ids[*ni], c->u.in, sizeof c->u.in);
    *ni += c->n;
    return 1;
}

/* The cell (cx, cy) of a point (m), clamped to the grid; dies on a NaN. */
void m2c_sim_cell_of(m2c_world *m, double x, double y, int32_t *cx, int32_t *cy);
/* Appends b to its cell's list; dies when out of memory. */
void m2c_sim_cell_add(m2c_world *m, m2c_sim_body *b);
/* A large body into the walls' cells (fixed and unmoving) or the large list. */
void m2c_sim_place_large(m2c_world *m, m2c_sim_body *b);
/* A large body out of the walls' cells or the large list. */
void m2c_sim_unplace_large(m2c_world *m, m2c_sim_body *b);
/* Appends to m->near (when keep) the walls listed in the cells x_lo..x_hi,
 * y_lo..y_hi not marked yet, but b, and marks them. */
void m2c_sim_walls_in(m2c_world *m, const m2c_sim_body *b, int32_t x_lo, int32_t x_hi, int32_t y_lo, int32_t y_hi,
                      int keep);
/* Sorts m->near by index. */
void m2c_sim_sort_near(m2c_world *m);
/* The large bodies b predicts against, into m->near, by index. */
void m2c_sim_large_near(m2c_world *m, const m2c_sim_body *b);

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

/* A number as m2c_sim_format_number writes it; +0 (a third of a gas's
 * numbers: angles, spins, accelerations) written here without the call. */
static inline char *m2c_sim_put_num(char *p, double x)
{
    uint64_t bits;
    memcpy(&bits, &x, sizeof bits);
    if (bits == 0) {
        *p = '0';
        return p + 1;
    }
    return p + m2c_sim_format_number(p, x);
}

char *m2c_sim_put_int(char *p, long long v);

/* The trace's lines (docs/simulator.md, "Flat trace"); nothing without a trace. */
/* S: b's state at its time tb. */
void m2c_sim_emit_state(m2c_world *m, const m2c_sim_body *b);
/* E collision / E support (kind: "E collision ", "E support "). */
void m2c_sim_emit_contact(m2c_world *m, const char *kind, double t, const m2c_sim_body *A, const m2c_sim_body *B,
                          int32_t feature, int32_t i, int32_t j, double cx, double cy, double nx, double ny,
                          double imp);
/* E stop / E leave of a supported body (edge of sup). */
void m2c_sim_emit_support_change(m2c_world *m, const char *kind, double t, const m2c_sim_body *A, int32_t sup,
                                 int32_t edge);
/* E sleep / E wake: body a, body b (-1 for a wake), island. */
void m2c_sim_emit_island(m2c_world *m, const char *kind, double t, int32_t a, int32_t b, int32_t island);
/* E input k on body. */
void m2c_sim_emit_input(m2c_world *m, double t, const m2c_sim_body *body, int32_t k);
/* E frame at t. */
void m2c_sim_emit_frame(m2c_world *m, double t);
/* E add of body idx at t. */
void m2c_sim_emit_add(m2c_world *m, double t, int32_t idx);
/* The end of the trace: every body (F, at its time), the counters (N),
 * the predictions served per variant (V). */
void m2c_sim_emit_final(m2c_world *m);

/* ---- world: the simulation's whole state (m2c_sim_world.c) ------------------ */

/* The counters written as the trace's N lines (the reference's Stats). */
typedef struct m2c_sim_stats {
    long long collisions, inputs, frames, cells, horizons, stale, pairs, features, supports, stops, leaves, sleeps,
        wakes;
} m2c_sim_stats;

#define M2C_WORLD_ERROR_MAX 512

/* A contact handled at one instant (an E collision or E support line): the
 * collision record's bodies and feature, and a count. */
typedef struct m2c_sim_touch {
    int32_t a, b, feature, i, j;
    int32_t times;          /* how many times it was handled at that instant */
} m2c_sim_touch;

/* One contact of a cluster being solved (docs/simulator.md, "Contact model:
 * simultaneous contacts"): its bodies and feature, contact point, unit
 * normal from A to B, the arms across n and kn, the change of its normal
 * speed per unit normal impulse. */
typedef struct m2c_sim_row {
    m2c_sim_body *A, *B;
    int32_t feature, i, j;
    double cx, cy, nx, ny, ran, rbn, kn;
} m2c_sim_row;

/* The scratch of a cluster's solve (handle_cluster), kept between calls. */
typedef struct m2c_sim_cluster {
    m2c_sim_row *rows;                  /* the contacts (n of them, room for cap) */
    double *acc, *acc2, *target;        /* per contact: normal impulses, targets (N s, m/s) */
    double *pushes;                     /* wedged: directions (x, y), up to cap + 1 of them */
    int32_t n, cap;
    int32_t *inside;                    /* body indices reached (cluster) */
    int32_t ninside;
    m2c_sim_body **movers;              /* the bodies that move (nmovers, room for bcap) */
    double *saved, *v2, *vs;            /* per mover: vx, vy, om */
    m2c_sim_body **done;                /* predicted already, or fallen asleep (predict_apart) */
    int32_t nmovers, ndone, bcap;
} m2c_sim_cluster;

/* A movable body's slow contact with another (a hop), for sleeping on
 * several contacts (docs/simulator.md, "Several contacts"). */
#define M2C_SIM_REST_SLOTS 4   /* slow contacts kept per body, the last first */
typedef struct m2c_sim_rest_contact {
    double px, py;          /* m: the contact point */
    double mx, my;          /* unit normal from the body to the other */
    double gx, gy, gang;    /* m, m, rad: the other body's position and angle then */
    double bx, by, bang;    /* m, m, rad: the body's own position and angle then */
    int32_t other1;         /* the other body's index + 1; 0: no contact */
    int32_t feature, i, j;  /* the collision's feature and its i, j */
    int32_t side;           /* 1: the body was the collision's a, 0: its b */
} m2c_sim_rest_contact;

struct m2c_world {
    m2c_sim_scene *s;                   /* owned */
    m2c_sim_body *bodies;               /* s->bodies */
    uint32_t *stamp;                    /* per body: bumped when its motion changes (lazy invalidation) */
    m2c_sim_rest_contact *restc;        /* per body, M2C_SIM_REST_SLOTS: its last slow contacts, the last first */
    m2c_sim_heap heap;
    m2c_sim_stats stats;
    long long *cc_counts, *pe_counts;   /* predictions served per variant */
    int n_cc, n_pe;
    m2c_sim_grid grid;
    int32_t *large;                     /* the large bodies not placed in the walls' cells, by index */
    int32_t nlarge;
    m2c_sim_wall *walls;                /* nx * ny: the large fixed unmoving bodies listed per cell it covers */
    int32_t *wnear;                     /* nx * ny: entries of the walls' lists in the cell's 3x3 block (0: none near) */
    unsigned long long mark;            /* the current large_near / walls_in mark */
    int32_t *near;                      /* large_near's answer: nnear body indices (room for near_cap) */
    int32_t nnear;
    size_t near_cap;
    size_t sweep_at;                    /* queue size that triggers a sweep of stale events */
    int fetch;                          /* fetch ahead: the bodies and cells outgrow a core's cache (choose_fetch) */
    m2c_sim_trig *vtrig;                /* per vertex: cos, sin of its phase ang + beta */
    m2c_sim_trig *etrig;                /* per edge: cos, sin of its normal's angle ang + psi */
    m2c_sim_out out;                    /* the trace (out.f NULL: none) */
    uint64_t time_bits;                 /* the last event time written (put_time), as bits */
    int time_len;                       /* and its text's length (0: none yet) */
    char time_text[M2C_SIM_NUMBER_MAX]; /* and its text */
    double now;                         /* s: the time reached */
    double last_t;                      /* s: time of the last event handled (-1 before any) */
    long long same;                     /* events handled at last_t after the first */
    long long handled;                  /* events handled (stale ones not): at most s->max_events */
    m2c_contact_fn fn;                  /* during m2c_world_advance: told of each contact */
    void *user;
    size_t trig_cap;                    /* entries of vtrig and etrig */
    long long added;                    /* bodies added by add_body (a recording refuses them) */
    int unpaid;                         /* a hop since sleeper_impulse cleared it added energy (pay_floor could not pay) */
    double touched_t;                   /* s: the instant of the contacts in touched */
    m2c_sim_touch *touched;             /* the contacts handled at touched_t, in order, each once */
    double jammed_t;                    /* s: the instant of the bodies in jammed */
    int32_t *jammed;                    /* the bodies a jam put to sleep at jammed_t (m2c_sim_held_now) */
    int32_t njammed, jammed_cap;
    int32_t ntouched, touched_cap;
    m2c_sim_cluster clu;                /* handle_cluster's scratch */
    double *scratch;                    /* bound_polygon: scratch_cap polynomials of M2C_MAX_DEGREE + 1 */
    int *scratch_deg;                   /* and their degrees */
    size_t scratch_cap;
    int broken;                         /* an error stopped the world */
    int finished;                       /* m2c_world_finish ran: no more inputs or bodies */
    jmp_buf fail;                       /* where the current API call catches an error */
    char err[M2C_WORLD_ERROR_MAX];
};

/* contact features of a collision record: circle-circle (or circle-vertex), point-edge */
enum { M2C_SIM_CC = 0, M2C_SIM_PE = 1 };

/* The reference's SimError: the message, then back to the entry that set
 * m->fail; the world is unusable from then on. */
_Noreturn void m2c_sim_die(m2c_world *m, const char *format, ...) __attribute__((format(printf, 2, 3)));

/* Entries: each catches the errors of what it calls (m2c_sim_die) here. */
#define M2C_SIM_CATCH(m)                                                                                    \
    do {                                                                                                    \
        if ((m)->broken)                                                                                    \
            return -1;                                                                                      \
        if (setjmp((m)->fail) != 0)                                                                         \
            return -1;                                                                                      \
    } while (0)

/* %.17g of x (as the reference's _fmt) into buf (M2C_SIM_NUMBER_MAX + 1
 * bytes), NUL-terminated: numbers in messages. */
static inline const char *m2c_sim_text(char *buf, double x)
{
    buf[m2c_sim_format_number(buf, x)] = '\0';
    return buf;
}

/* Takes scene (freed by m2c_sim_close even on failure), allocates and
 * predicts every pair at t = 0: 0, or -1 with the message in w->err. */
int m2c_sim_open(m2c_world *w, m2c_sim_scene *scene, int cc_variants, int pe_variants, FILE *trace);
void m2c_sim_close(m2c_world *w);
/* Whether to fetch ahead, from the bodies' and cells' bytes now. */
void m2c_sim_choose_fetch(m2c_world *m);

/* Whether a body of e changed its motion since e was scheduled.  Inputs
 * are scripted, not predicted, and frames have no bodies: never. */
static inline int m2c_sim_is_stale(const m2c_world *m, const m2c_sim_event *e)
{
    switch (e->kind) {
    case M2C_SIM_COLLISION:
        return m->stamp[e->u.collision.a] != e->u.collision.stamp_a
               || m->stamp[e->u.collision.b] != e->u.collision.stamp_b;
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

/* Schedules an event record (its t and kind set, and the fields of its
 * kind); the records of bodies carry their stamps now. */
void m2c_sim_push(m2c_world *m, const m2c_sim_event *e);
void m2c_sim_push_collision(m2c_world *m, double t, int32_t feature, const m2c_sim_body *A, const m2c_sim_body *B,
                            int32_t i, int32_t j);
void m2c_sim_push_horizon(m2c_world *m, double t, const m2c_sim_body *A, const m2c_sim_body *B);
void m2c_sim_push_cell(m2c_world *m, double t, const m2c_sim_body *b, int32_t axis, int32_t direction);
void m2c_sim_push_stop(m2c_world *m, double t, const m2c_sim_body *b);
void m2c_sim_push_leave(m2c_world *m, double t, const m2c_sim_body *b);
void m2c_sim_push_input(m2c_world *m, double t, int32_t k);
void m2c_sim_push_frame(m2c_world *m, double t, int32_t k);

/* ---- motion: between events (m2c_sim_motion.c) ------------------------------ */

/* Centre (m), velocity (m/s) and angle (rad) of a body at some time. */
typedef struct m2c_sim_motion {
    double x, y, vx, vy, ang;
} m2c_sim_motion;

/* Python's max(a, b) and min(a, b): the first unless the second is larger
 * (smaller). */
static inline double m2c_sim_max(double a, double b)
{
    return b > a ? b : a;
}

static inline double m2c_sim_min(double a, double b)
{
    return b < a ? b : a;
}

/* cos(a) and sin(a), from the cache when a is the angle (to the bit) it
 * last held: libm's answer for the same argument, without the call.  A
 * polygon that does not turn asks for the same angles again and again. */
static inline void m2c_sim_cos_sin(m2c_sim_trig *k, double a, double *c, double *s)
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

/* The cos, sin cache of vertex v's phase (VTRIG) or of its edge's normal (ETRIG). */
#define M2C_SIM_VTRIG(m, v) (&(m)->vtrig[(v) - (m)->s->verts])
#define M2C_SIM_ETRIG(m, v) (&(m)->etrig[(v) - (m)->s->verts])

/* cos(a) and sin(a) of vertex v's phase (vcos_sin) or of its edge's
 * normal (ecos_sin): from the world's cache, or computed when m is NULL
 * (the TOI library, m2c_toi.c, has no world): the same bits either way. */
static inline void m2c_sim_vcos_sin(m2c_world *m, const m2c_sim_vertex *v, double a, double *c, double *s)
{
    if (m != NULL) {
        m2c_sim_cos_sin(M2C_SIM_VTRIG(m, v), a, c, s);
        return;
    }
    *c = cos(a);
    *s = sin(a);
}

static inline void m2c_sim_ecos_sin(m2c_world *m, const m2c_sim_vertex *v, double a, double *c, double *s)
{
    if (m != NULL) {
        m2c_sim_cos_sin(M2C_SIM_ETRIG(m, v), a, c, s);
        return;
    }
    *c = cos(a);
    *s = sin(a);
}

/* Moves b's state on to time t (s). */
static inline void m2c_sim_rebase(m2c_sim_body *b, double t)
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
static inline m2c_sim_motion m2c_sim_state_at(const m2c_sim_body *b, double t)
{
    double dt = t - b->tb;
    m2c_sim_motion q;
    q.x = b->px + (b->vx + 0.5 * b->ax * dt) * dt;
    q.y = b->py + (b->vy + 0.5 * b->ay * dt) * dt;
    q.vx = b->vx + b->ax * dt;
    q.vy = b->vy + b->ay * dt;
    q.ang = b->ang + b->om * dt;
    return q;
}

/* rad/s: how fast the body's contact features turn. */
static inline double m2c_sim_turn_rate(const m2c_sim_body *b)
{
    if (b->polygon || b->orbit > 0.0)
        return fabs(b->om);
    return 0.0;
}

/* World position (m) of a circle's centre (v NULL) or of a vertex, at t
 * (m NULL: no world, vcos_sin). */
static inline void m2c_sim_point_at(m2c_world *m, const m2c_sim_body *b, const m2c_sim_vertex *v, double t, double *x,
                                    double *y)
{
    m2c_sim_motion q = m2c_sim_state_at(b, t);
    double d = v == NULL ? b->orbit : v->rho;
    double beta = v == NULL ? b->ophase : v->beta;
    if (d == 0.0) {
        *x = q.x;
        *y = q.y;
        return;
    }
    double c, sn;
    if (v != NULL) {
        m2c_sim_vcos_sin(m, v, q.ang + beta, &c, &sn);
    } else {
        c = cos(q.ang + beta);
        sn = sin(q.ang + beta);
    }
    *x = q.x + d * c;
    *y = q.y + d * sn;
}

/* Body b's exact state at t (from its state at b->tb). */
void m2c_sim_body_state(const m2c_sim_body *b, double t, m2c_body_state *s);

/* ---- predict: pairs, features, first valid root, cells, horizons (m2c_sim_predict.c) ---- */

/* ---- the pair computation, shared with the TOI library (m2c_toi.c) ----------- */

/* What a pair's computation reads besides the two bodies. */
typedef struct m2c_toi_ctx {
    double tol;                 /* m: the distance tolerance */
    double alpha;               /* rad: the window angle of a pair in which both bodies turn */
    m2c_world *m;               /* the simulator's world (its variant counts, cos/sin caches, covered edges,
                                   scratch, errors), or NULL: the library, which has none of them */
    void (*die)(m2c_world *m, const char *format, ...);     /* with a world: its error exit */
    int error;                  /* without a world: a generated entry refused its parameters */
    double *scratch;            /* without a world: bound_polygon's M2C_TOI_MAX_VERTICES polynomials */
    int *scratch_deg;           /* and their degrees */
    int trig_n;                 /* without a world: bit k set when trig[k] holds body k's last angle (rad), */
    double trig[2][3];          /* its cos and sin (toi_cos_sin: a clear stretch and the window after it
                                   share them) */
} m2c_toi_ctx;

/* The simulator's context of a pair's computation. */
static inline m2c_toi_ctx m2c_sim_ctx(m2c_world *m)
{
    m2c_toi_ctx k = { m->s->tol, m->s->alpha, m, m2c_sim_die, 0, NULL, NULL, 0, { { 0.0 } } };
    return k;
}

/* The earliest contact found in a pair: s after the time of the answer,
 * feature feat of a's point (circle centre i -1, or vertex i) against b's
 * circle, vertex or edge j. */
typedef struct m2c_toi_best {
    int have;
    double s;
    int32_t feat;
    const m2c_sim_body *a, *b;
    int32_t i, j;
} m2c_toi_best;

/* The first contact of A and B after now, through at most `stages` cheap
 * steps (bounds, clear stretches, windows) and `windows` Taylor windows:
 * 1 with *bs (its s after *at), 0 when there is none before end, 2 when the
 * steps ran out at *at (a horizon). */
int m2c_toi_pair(m2c_toi_ctx *ctx, const m2c_sim_body *A, const m2c_sim_body *B, double now, double end, long stages,
                 long windows, m2c_toi_best *bs, double *at);
/* At s = 0, with the gap polynomial c zero within kappa: approaching or pressed together. */
int m2c_toi_touching_now(const double *c, int deg, double kappa);
/* circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
 * circle's centre (v NULL) or of a polygon's vertex, at time now. */
void m2c_toi_circle_params(m2c_toi_ctx *ctx, const m2c_sim_body *b, double now, const m2c_sim_vertex *v, double *o);
/* The circle_circle polynomial of two circles moving as p1 and p2 (circle_params); its degree. */
int m2c_toi_circles_gap(m2c_toi_ctx *ctx, const double *p1, double ra, const double *p2, double rb, double *coef);
/* The point_edge polynomial of a point of X (rho, beta about its centre,
 * radius rad) against the line of edge j of Y; its degree. */
int m2c_toi_pe_coefficients(m2c_toi_ctx *ctx, const m2c_sim_body *X, const m2c_sim_body *Y, double rho, double beta,
                            double rad, int32_t j, double now, double *coef);
/* Contact point (cx, cy) (m) and unit normal (nx, ny) from A to B of a
 * feature at t, B's angle at t being bang. */
void m2c_toi_frame(m2c_world *m, double t, int32_t feature, const m2c_sim_body *A, const m2c_sim_body *B, int32_t i,
                   int32_t j, double bang, double *cx, double *cy, double *nx, double *ny);

static inline int m2c_sim_touching_now(const double *c, int deg, double kappa)
{
    return m2c_toi_touching_now(c, deg, kappa);
}
/* circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
 * circle's centre (v NULL) or of a polygon's vertex, at time now. */
void m2c_sim_circle_params(m2c_world *m, const m2c_sim_body *b, double now, const m2c_sim_vertex *v, double *o);
/* The circle_circle polynomial of two circles moving as p1 and p2 (circle_params); its degree. */
int m2c_sim_circles_gap(m2c_world *m, const double *p1, double ra, const double *p2, double rb, double *coef);
/* The point_edge polynomial of a point of X (rho, beta about its centre,
 * radius rad) against the line of edge j of Y; its degree. */
int m2c_sim_pe_coefficients(m2c_world *m, const m2c_sim_body *X, const m2c_sim_body *Y, double rho, double beta,
                            double rad, int32_t j, double now, double *coef);
/* Schedules the first contact of A and B after now, or a horizon event. */
void m2c_sim_predict_pair(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double now);
/* Schedules b's next crossing of a cell boundary. */
void m2c_sim_schedule_cell(m2c_world *m, const m2c_sim_body *b, double now);
/* Everything of b's future: its pairs with every neighbour but skip, its
 * cell crossing, its stop and leave on a fixed support. */
void m2c_sim_predict_body(m2c_world *m, const m2c_sim_body *b, double now, const m2c_sim_body *skip);
/* The pairs of b with every body in the cells x_lo..x_hi, y_lo..y_hi. */
void m2c_sim_predict_cells(m2c_world *m, const m2c_sim_body *b, int32_t x_lo, int32_t x_hi, int32_t y_lo,
                           int32_t y_hi, double now);
/* The start's predictions of small body b at t = 0: its pairs with the
 * bodies of a higher index near it, with the large ones near, its cell crossing. */
void m2c_sim_predict_first(m2c_world *m, const m2c_sim_body *b);
/* predict_body for a member of a waking island (a pair of two members once). */
void m2c_sim_predict_woken(m2c_world *m, const m2c_sim_body *b, double now, int32_t island);
/* predict_body for a body of a solved cluster, but against the bodies in clu.done. */
void m2c_sim_predict_apart(m2c_world *m, const m2c_sim_body *b, double now);

/* Whether x is among xs[0 .. n - 1]. */
static inline int m2c_sim_among(m2c_sim_body *const *xs, int32_t n, const m2c_sim_body *x)
{
    for (int32_t k = 0; k < n; k++)
        if (xs[k] == x)
            return 1;
    return 0;
}

/* ---- contact: frame and impulse (m2c_sim_contact.c) -------------------------- */

/* Normal relative velocity (m/s; B's against A's, along n from A to B) of
 * the material points at the contact: negative when approaching. */
static inline double m2c_sim_normal_speed(const m2c_sim_body *A, const m2c_sim_body *B, double cx, double cy,
                                          double nx, double ny)
{
    double uax = A->vx - A->om * (cy - A->py);
    double uay = A->vy + A->om * (cx - A->px);
    double ubx = B->vx - B->om * (cy - B->py);
    double uby = B->vy + B->om * (cx - B->px);
    return (ubx - uax) * nx + (uby - uay) * ny;
}

/* Whether the bodies' accelerations push them together along the normal
 * (n from A to B): the relative normal acceleration of the centres is
 * negative.  (Centripetal terms of turning bodies are left out.) */
static inline int m2c_sim_pressed(const m2c_sim_body *A, const m2c_sim_body *B, double nx, double ny)
{
    return (B->ax - A->ax) * nx + (B->ay - A->ay) * ny < 0.0;
}

/* Contact point (cx, cy) (m) and unit normal (nx, ny) from A to B of a
 * feature at t (both bodies advanced to t). */
void m2c_sim_contact_frame(m2c_world *m, double t, int32_t feature, const m2c_sim_body *A, const m2c_sim_body *B,
                           int32_t i, int32_t j, double *cx, double *cy, double *nx, double *ny);
/* The contact's feature polynomial, taken again at the contact, predicts it now. */
int m2c_sim_closing(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                    int32_t j);
/* The impulse (kg m/s) of a contact; velocities changed. */
double m2c_sim_contact_impulse(m2c_world *m, m2c_sim_body *A, m2c_sim_body *B, double cx, double cy, double nx,
                               double ny, int32_t feature, int32_t i, int32_t j);
/* A slow contact of bodies held on their supports. */
int m2c_sim_held(const m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double nx, double ny, double vn);
/* The normal impulse (kg m/s) of a held contact. */
double m2c_sim_held_impulse(const m2c_world *m, m2c_sim_body *A, m2c_sim_body *B, double nx, double ny, double vn);
/* The impulse (kg m/s) of a contact of A and B, one of them asleep. */
double m2c_sim_sleeper_impulse(m2c_world *m, m2c_sim_body *A, m2c_sim_body *B, double cx, double cy, double nx,
                               double ny, int32_t feature, int32_t i, int32_t j);

/* ---- support: resting, sliding and carried bodies (m2c_sim_support.c) -------- */

/* B does not move (v = a = w = 0). */
static inline int m2c_sim_is_static(const m2c_sim_body *B)
{
    return B->vx == 0.0 && B->vy == 0.0 && B->ax == 0.0 && B->ay == 0.0 && B->om == 0.0;
}

/* The bodies that left their support or carrier at one instant, in the
 * order they left, each with the body its prediction skips (-1: none). */
typedef struct m2c_sim_left {
    int32_t n, cap;
    int32_t *body, *skip;
} m2c_sim_left;

/* Unit tangent (tx, ty) and outward unit normal (ox, oy) of edge j of B in
 * the world (B does not turn). */
void m2c_sim_support_frame(const m2c_sim_body *B, int32_t j, double *tx, double *ty, double *ox, double *oy);
/* A neighbour of A's vertex i lies on edge j's line within the face tolerance. */
int m2c_sim_flat(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t i, int32_t j, double ox,
                 double oy, double load);
/* A point-edge contact that becomes support on a fixed polygon. */
int m2c_sim_can_support(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                        int32_t j, double vn);
/* Supported A's acceleration (m/s^2) for its tangential speed u (m/s) relative to its support. */
void m2c_sim_slide_accel(const m2c_world *m, m2c_sim_body *A, double u);
void m2c_sim_enter_support(const m2c_world *m, m2c_sim_body *A, const m2c_sim_body *B, int32_t j);
/* A point-edge contact that becomes support on a sleeping polygon that holds it. */
int m2c_sim_can_ride(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                     int32_t j, double vn);
/* A sleeping base stays at rest under its riders and the extra force (px, py). */
int m2c_sim_base_holds(const m2c_world *m, const m2c_sim_body *B, double px, double py);
/* A's support (or carrier) ends: its free acceleration again. */
void m2c_sim_end_support(m2c_world *m, m2c_sim_body *A);
/* A point-edge contact that becomes carrying on a movable polygon. */
int m2c_sim_can_carry(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                      int32_t j, double vn);
void m2c_sim_enter_carried(m2c_sim_body *A, m2c_sim_body *B, int32_t j);
/* Supported b's position q (m), speed u (m/s) and acceleration a (m/s^2)
 * along the edge relative to its support, at b's time. */
void m2c_sim_support_relative(const m2c_world *m, const m2c_sim_body *b, double *q, double *u, double *a);
/* A supported body's stop and leave events. */
void m2c_sim_schedule_support(m2c_world *m, const m2c_sim_body *b);
/* A leaves its support or carrier at t, then what it carries (into left). */
void m2c_sim_leave(m2c_world *m, m2c_sim_body *A, double t, const m2c_sim_body *skip, m2c_sim_left *left);
/* B's motion changes at t: every body B carries leaves (into left). */
void m2c_sim_release(m2c_world *m, const m2c_sim_body *B, double t, m2c_sim_left *left);
/* Predicts the bodies in left; frees the list. */
void m2c_sim_predict_released(m2c_world *m, m2c_sim_left *left, double t);

/* ---- sleep: sleeping islands (m2c_sim_sleep.c) -------------------------------- */

/* A body others can fall asleep on: asleep, or fixed and unmoving. */
static inline int m2c_sim_grounded(const m2c_sim_body *G)
{
    return G->asleep || (G->fixed && m2c_sim_is_static(G));
}

/* A sleeper an impulse has set moving. */
static inline int m2c_sim_jolted(const m2c_sim_body *S)
{
    return S->vx != 0.0 || S->vy != 0.0 || S->om != 0.0;
}

/* A supported body that stays where it is. */
int m2c_sim_at_rest(const m2c_world *m, const m2c_sim_body *A);
/* Awake movable M, a body of the collision ev with grounded G, falls asleep on G. */
int m2c_sim_slow_press(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev,
                       double nx, double ny, double vn);
void m2c_sim_note_rest(m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev, double cx,
                       double cy, double nx, double ny);
int m2c_sim_slow_touch(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev,
                       double nx, double ny, double vn);
int m2c_sim_can_sleep_many(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev,
                           double cx, double cy, double nx, double ny, double vn);
void m2c_sim_handle_sleep_many(m2c_world *m, m2c_sim_body *A, const m2c_sim_body *G, const m2c_sim_event *ev, double t);
int m2c_sim_can_sleep(m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev, double nx,
                      double ny, double vn);
/* A (advanced to t) falls asleep resting on G. */
void m2c_sim_handle_sleep(m2c_world *m, m2c_sim_body *A, const m2c_sim_body *G, double t);
/* Sleeper S wakes at t, with every sleeper resting on a woken body. */
void m2c_sim_handle_wake(m2c_world *m, const m2c_sim_body *S, double t);
/* The islands of the sleepers whose bounding circles reach body's wake. */
void m2c_sim_wake_touching(m2c_world *m, const m2c_sim_body *body, double t);

/* ---- cluster: simultaneous contacts (m2c_sim_cluster.c) ----------------------- */

/* Counts a contact handled at t (an E collision or E support line). */
void m2c_sim_count_touch(m2c_world *m, double t, int32_t a, int32_t b, int32_t feature, int32_t i, int32_t j);
/* The collision's contact was handled often enough at this instant to be solved with the others. */
int m2c_sim_repeated(const m2c_world *m, const m2c_sim_event *ev);
int m2c_sim_held_now(const m2c_world *m, const m2c_sim_body *S);
/* Solves the contacts met at this instant that reach ev's together. */
void m2c_sim_handle_cluster(m2c_world *m, const m2c_sim_event *ev);
void m2c_sim_cluster_free(m2c_sim_cluster *c);

/* ---- overlap: a teleport's or an added body's check (m2c_sim_overlap.c) ------- */

/* Outward unit normal (ox, oy) of edge j of P at t and the offset (m) of
 * its line, (ox, oy) . point = off. */
void m2c_sim_edge_line(const m2c_sim_body *P, int32_t j, double t, double *ox, double *oy, double *off);
/* The largest gap (m) between A and B at t along a separating axis (negative: overlap depth). */
double m2c_sim_separation(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double t);
/* The first body that A, its centre moved to (x, y) at t, would overlap; -1 when none. */
int32_t m2c_sim_overlapping(m2c_world *m, m2c_sim_body *A, double x, double y, double t);

/* ---- handlers: one per event kind, and their dispatch (m2c_sim_handlers.c) ---- */

/* Places the bodies in the grid, schedules the inputs and the first frame,
 * and predicts every pair once. */
void m2c_sim_start(m2c_world *m);
/* Handles one event popped from the queue. */
void m2c_sim_dispatch(m2c_world *m, const m2c_sim_event *ev);
/* Handles the queued events before limit (s; at limit too when inclusive). */
void m2c_sim_run_until(m2c_world *m, double limit, int inclusive);

/* ---- live: the engine's entries behind m2c_world.h (m2c_sim_live.c) ----------- */

/* Tells the caller of m2c_world_advance of a contact. */
static inline void m2c_sim_report(m2c_world *m, double t, const m2c_sim_body *A, const m2c_sim_body *B,
                                  int32_t feature, int32_t i, int32_t j, double cx, double cy, double nx, double ny,
                                  double imp, int support)
{
    if (m->fn == NULL)
        return;
    m2c_contact c = { t, A->idx, B->idx, feature, i, j, cx, cy, nx, ny, imp, support };
    m->fn(&c, m->user);
}

/* Each returns 0, or -1 with the message in w->err. */
/* Handles the events before t (<= the scene's end); the time is then t. */
int m2c_sim_advance(m2c_world *w, double t);
/* The time of the next live event (stale ones are dropped, counted), or +inf. */
int m2c_sim_next_time(m2c_world *w, double *t);
/* A live input at the world's time (docs/engine-api.md): 0 with *done 1,
 * or *done 0 when a teleport is refused (it would overlap; the world is
 * unchanged); -1 on a bad call (the world is unchanged: no such body, a
 * fixed body, a coordinate that is not finite) or a failure. */
int m2c_sim_live_input(m2c_world *w, int body, int mode, double x, double y, int *done);
/* add_body (docs/engine-api.md): a body from its flat lines, at the
 * world's time.  0 with *idx its index, or *idx -1 when it would overlap a
 * body (the world unchanged); -1 on a bad body (the world unchanged) or a
 * failure. */
int m2c_sim_add_body(m2c_world *w, const char *text, int *idx);
/* Handles the events at the end time too, then writes every body at the
 * end time, the counters, the variants served; flushed. */
int m2c_sim_finish(m2c_world *w);

#pragma GCC visibility pop
#endif
