/* The simulator's parts, shared by its source files (not an API):
 * scene (m2c_sim_scene.c), event queue (m2c_sim_queue.c), grid cells
 * (m2c_sim_grid.c), trace writer (m2c_sim_out.c, m2c_sim_format.c) and the
 * simulation itself (m2c_sim.c).  Units: s, m, rad, kg. */
#ifndef M2C_SIM_INTERNAL_H
#define M2C_SIM_INTERNAL_H

#include <setjmp.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "m2c_sim.h"
#include "m2c_world.h"

/* Advises the kernel to map the whole 2 MB pages inside [p, p + bytes) as
 * huge pages (m2c_sim_pages.c): call it on a large array before it is first
 * written.  A hint only. */
void m2c_sim_huge_pages(void *p, size_t bytes);

/* ---- scene ---------------------------------------------------------------- */

/* One vertex of a polygon and the edge from it to the next vertex, in the
 * body's frame: all precomputed by the scene compiler. */
typedef struct m2c_sim_vertex {
    double lx, ly;          /* m: the vertex about the centre of mass */
    double rho, beta;       /* m, rad: its polar form */
    double psi;             /* rad: angle of the edge's outward normal */
    double h;               /* m: offset of the edge's line, n . v */
    double s1, s2;          /* m: the edge's extent along its tangent (-ny, nx) */
    double nx, ny;          /* the edge's outward unit normal (cos psi, sin psi, but exact where the
                               compiler's quotient is: (0, 1) for a level top face) */
    int32_t cover;          /* the fixed body that covers the edge (no body can touch it while that one
                               is there), -1: none */
} m2c_sim_vertex;

/* A body, laid out for the predictions: a pair's prediction reads only
 * the first two cache lines (its motion, then its shape and the flags and
 * indices every pair checks), so a neighbour predicted against costs two
 * lines; what only the handling of its own events reads (impulses, cell,
 * support, islands, walls) follows.  _Alignas on px alone (on a
 * declaration of several fields it would align each one).  (Its stamp, for
 * lazy invalidation, is in an array of its own, m2c_sim.c.) */
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

/* ---- the world: the simulation's whole state (m2c_sim.c runs it, m2c_sim_world.c is its API) ---- */

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

struct m2c_world {
    m2c_sim_scene *s;                   /* owned */
    m2c_sim_body *bodies;               /* s->bodies */
    uint32_t *stamp;                    /* per body: bumped when its motion changes (lazy invalidation) */
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
    m2c_contact_fn fn;                  /* during m2c_world_advance: told of each contact */
    void *user;
    size_t trig_cap;                    /* entries of vtrig and etrig */
    long long added;                    /* bodies added by add_body (a recording refuses them) */
    int unpaid;                         /* a hop since sleeper_impulse cleared it added energy (pay_floor could not pay) */
    double touched_t;                   /* s: the instant of the contacts in touched */
    m2c_sim_touch *touched;             /* the contacts handled at touched_t, in order, each once */
    int32_t ntouched, touched_cap;
    m2c_sim_cluster clu;                /* handle_cluster's scratch */
    double *scratch;                    /* bound_polygon: scratch_cap polynomials of M2C_MAX_DEGREE + 1 */
    int *scratch_deg;                   /* and their degrees */
    size_t scratch_cap;
    int broken;                         /* an error stopped the world */
    jmp_buf fail;                       /* where the current API call catches an error */
    char err[M2C_WORLD_ERROR_MAX];
};

/* The engine's entries (m2c_sim.c); each returns 0, or -1 with the message
 * in w->err. */
/* Takes scene (freed by m2c_sim_close even on failure), allocates and
 * predicts every pair at t = 0. */
int m2c_sim_open(m2c_world *w, m2c_sim_scene *scene, int cc_variants, int pe_variants, FILE *trace);
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
/* A `body ...` line and its `v` lines (the whole text) into b, index idx,
 * its vertices into a new *verts (b->verts left NULL): 0, or -1 with the
 * message ("add_body: ..."). */
int m2c_sim_body_read(const char *text, m2c_sim_body *b, int32_t idx, m2c_sim_vertex **verts, char *err,
                      size_t errlen);
/* Handles the events at the end time too, then writes every body at the
 * end time, the counters, the variants served; flushed. */
int m2c_sim_finish(m2c_world *w);
void m2c_sim_close(m2c_world *w);
/* Body b's exact state at t (from its state at b->tb). */
void m2c_sim_body_state(const m2c_sim_body *b, double t, m2c_body_state *s);

/* The event first in the queue (moving `last` on when near is empty), or
 * NULL when the queue is empty; it stays queued.  -1 out of memory. */
int m2c_sim_heap_top(m2c_sim_heap *h, const m2c_sim_event **e);

#endif
