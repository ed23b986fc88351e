/* The live world (m2c_world.h, docs/engine-api.md): a scene made into a
 * world that a caller drives with m2c_world_advance(t), asks for the next
 * event's time and the bodies' states, and gives live inputs and bodies;
 * the batch simulator is advance(end) + finish.  Below the API, the
 * engine's entries it calls, each catching the errors of what it runs.
 * Built with the generated equations and the numbers of variants their
 * NAME_variant functions index:  -DM2C_SIM_CC_VARIANTS=N
 * -DM2C_SIM_PE_VARIANTS=M.  Times in s, lengths in m. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_sim_internal.h"

#ifndef M2C_SIM_CC_VARIANTS
#error "build with -DM2C_SIM_CC_VARIANTS=N (the variants circle_circle_variant indexes)"
#endif
#ifndef M2C_SIM_PE_VARIANTS
#error "build with -DM2C_SIM_PE_VARIANTS=N (the variants point_edge_variant indexes)"
#endif

/* The message of the last failed m2c_world_new or m2c_world_load: per
 * thread, since no world exists to hold it. */
static _Thread_local char last_error[M2C_WORLD_ERROR_MAX];

const char *m2c_world_last_error(void)
{
    return last_error;
}

m2c_world *m2c_world_new(const char *scene_text, FILE *trace)
{
    last_error[0] = '\0';
    if (scene_text == NULL) {
        snprintf(last_error, sizeof last_error, "no scene text");
        return NULL;
    }
    m2c_sim_scene *scene = m2c_sim_scene_read(scene_text, last_error, sizeof last_error);
    if (scene == NULL)
        return NULL;
    m2c_world *w = calloc(1, sizeof *w);
    if (w == NULL) {
        m2c_sim_scene_free(scene);
        snprintf(last_error, sizeof last_error, "out of memory");
        return NULL;
    }
    if (m2c_sim_open(w, scene, M2C_SIM_CC_VARIANTS, M2C_SIM_PE_VARIANTS, trace) != 0) {
        snprintf(last_error, sizeof last_error, "%s", w->err);
        m2c_world_free(w);
        return NULL;
    }
    return w;
}

m2c_world *m2c_world_load(const char *path, FILE *trace)
{
    last_error[0] = '\0';
    FILE *f = fopen(path, "rb");
    if (f == NULL) {
        snprintf(last_error, sizeof last_error, "%s: %s", path, strerror(errno));
        return NULL;
    }
    size_t n = 0, cap = 1 << 16;
    char *buf = malloc(cap);
    while (buf != NULL) {
        if (cap - n < 2) {
            char *b = realloc(buf, 2 * cap);
            if (b == NULL) {
                free(buf);
                buf = NULL;
                break;
            }
            buf = b;
            cap *= 2;
        }
        size_t got = fread(buf + n, 1, cap - n - 1, f);
        n += got;
        if (got == 0)
            break;
    }
    int bad = ferror(f);
    fclose(f);
    if (buf == NULL || bad) {
        free(buf);
        snprintf(last_error, sizeof last_error, "%s: %s", path, buf == NULL ? "out of memory" : "cannot read");
        return NULL;
    }
    buf[n] = '\0';
    m2c_world *w = m2c_world_new(buf, trace);
    free(buf);
    return w;
}

void m2c_world_free(m2c_world *w)
{
    if (w == NULL)
        return;
    m2c_sim_close(w);
    free(w);
}

double m2c_world_time(const m2c_world *w)
{
    return w->now;
}

double m2c_world_end_time(const m2c_world *w)
{
    return w->s->end;
}

int m2c_world_body_count(const m2c_world *w)
{
    return (int)w->s->nbodies;
}

const char *m2c_world_error(const m2c_world *w)
{
    return w->err;
}

int m2c_world_advance(m2c_world *w, double t, m2c_contact_fn fn, void *user)
{
    if (w->broken)
        return -1;
    if (!(t >= w->now && t <= w->s->end)) {
        /* the world is unchanged: the caller may go on */
        char a[M2C_SIM_NUMBER_MAX + 1], b[M2C_SIM_NUMBER_MAX + 1], c[M2C_SIM_NUMBER_MAX + 1];
        snprintf(w->err, sizeof w->err, "advance: t = %s is outside [%s, %s] (the world's time .. the scene's end)",
                 m2c_sim_text(a, t), m2c_sim_text(b, w->now), m2c_sim_text(c, w->s->end));
        return -1;
    }
    w->fn = fn;
    w->user = user;
    int status = m2c_sim_advance(w, t);
    w->fn = NULL;
    w->user = NULL;
    return status;
}

double m2c_world_next_event_time(m2c_world *w)
{
    double t;
    if (m2c_sim_next_time(w, &t) != 0)
        return INFINITY;
    return t;
}

int m2c_world_state(m2c_world *w, int body, double t, m2c_body_state *s)
{
    if (w->broken)
        return -1;
    if (body < 0 || body >= w->s->nbodies) {
        snprintf(w->err, sizeof w->err, "no body %d (the world has %d)", body, (int)w->s->nbodies);
        return -1;
    }
    double nxt = m2c_world_next_event_time(w);
    if (w->broken)
        return -1;
    if (!(t >= w->now && t <= nxt && t <= w->s->end)) {
        char a[M2C_SIM_NUMBER_MAX + 1], b[M2C_SIM_NUMBER_MAX + 1], c[M2C_SIM_NUMBER_MAX + 1];
        snprintf(w->err, sizeof w->err, "state: t = %s is outside [%s, %s] (the world's time .. the next event)",
                 m2c_sim_text(a, t), m2c_sim_text(b, w->now), m2c_sim_text(c, nxt));
        return -1;
    }
    m2c_sim_body_state(&w->bodies[body], t, s);
    return 0;
}

int m2c_world_states(m2c_world *w, double t, m2c_body_state *s, int room)
{
    if (w->broken)
        return -1;
    int n = (int)w->s->nbodies;
    if (room < n) {
        snprintf(w->err, sizeof w->err, "states: room for %d bodies, the world has %d", room, n);
        return -1;
    }
    if (n == 0)
        return 0;
    if (m2c_world_state(w, 0, t, &s[0]) != 0)
        return -1;          /* t outside: the message is state's */
    for (int k = 1; k < n; k++)
        m2c_sim_body_state(&w->bodies[k], t, &s[k]);
    return 0;
}

int m2c_world_finish(m2c_world *w, m2c_contact_fn fn, void *user)
{
    if (w->broken)
        return -1;
    w->fn = fn;
    w->user = user;
    int status = m2c_sim_finish(w);
    w->fn = NULL;
    w->user = NULL;
    return status;
}

/* A live input: 0, or -1 with the message (a refused teleport is 0 with
 * *done 0). */
static int live(m2c_world *w, int body, int mode, double x, double y, int *done)
{
    return m2c_sim_live_input(w, body, mode, x, y, done);
}

int m2c_world_set_velocity(m2c_world *w, int body, double vx, double vy)
{
    int done;
    return live(w, body, M2C_SIM_SET_VELOCITY, vx, vy, &done);
}

int m2c_world_add_velocity(m2c_world *w, int body, double dvx, double dvy)
{
    int done;
    return live(w, body, M2C_SIM_ADD_VELOCITY, dvx, dvy, &done);
}

int m2c_world_apply_impulse(m2c_world *w, int body, double jx, double jy)
{
    int done;
    return live(w, body, M2C_SIM_IMPULSE, jx, jy, &done);
}

int m2c_world_teleport(m2c_world *w, int body, double x, double y)
{
    int done;
    if (live(w, body, M2C_SIM_TELEPORT, x, y, &done) != 0)
        return -1;
    return done;
}

int m2c_world_remove_body(m2c_world *w, int body)
{
    int done;
    return live(w, body, M2C_SIM_REMOVE, 0.0, 0.0, &done);
}

int m2c_world_add_body(m2c_world *w, const char *body_text)
{
    int idx;
    if (body_text == NULL) {
        snprintf(w->err, sizeof w->err, "add_body: no text");
        return -2;
    }
    if (m2c_sim_add_body(w, body_text, &idx) != 0)
        return -2;
    return idx;
}

int m2c_world_input_count(const m2c_world *w)
{
    return (int)w->s->ninputs;
}

int m2c_world_input(const m2c_world *w, int k, m2c_input *in)
{
    if (k < 0 || k >= w->s->ninputs)
        return -1;
    const m2c_sim_input *e = &w->s->inputs[k];
    in->t = e->t;
    in->body = (int)e->body;
    in->mode = (int)e->mode;
    in->x = e->vx;
    in->y = e->vy;
    return 0;
}

long long m2c_world_added(const m2c_world *w)
{
    return w->added;
}

/* ---- the engine's entries ---------------------------------------------------- */

/* Handles the input events queued at exactly the world's time. */
static void inputs_now(m2c_world *m)
{
    m2c_sim_event ev;
    for (;;) {
        const m2c_sim_event *top;
        if (m2c_sim_heap_top(&m->heap, &top) != 0)
            m2c_sim_die(m, "out of memory (event queue of %zu events)", m->heap.n);
        if (top == NULL || top->t != m->now || top->kind != M2C_SIM_INPUT)
            break;
        if (m2c_sim_heap_pop(&m->heap, &ev) != 0)
            m2c_sim_die(m, "out of memory (event queue of %zu events)", m->heap.n);
        m2c_sim_dispatch(m, &ev);
    }
}

int m2c_sim_advance(m2c_world *m, double t)
{
    M2C_SIM_CATCH(m);
    m2c_sim_run_until(m, t, 0);
    m->now = t;
    return 0;
}

int m2c_sim_next_time(m2c_world *m, double *t)
{
    M2C_SIM_CATCH(m);
    for (;;) {
        const m2c_sim_event *top;
        if (m2c_sim_heap_top(&m->heap, &top) != 0)
            m2c_sim_die(m, "out of memory (event queue of %zu events)", m->heap.n);
        if (top == NULL || top->t > m->s->end) {
            *t = INFINITY;
            return 0;
        }
        if (!m2c_sim_is_stale(m, top)) {
            *t = top->t;
            return 0;
        }
        m2c_sim_event ev;
        if (m2c_sim_heap_pop(&m->heap, &ev) != 0)
            m2c_sim_die(m, "out of memory (event queue of %zu events)", m->heap.n);
        m->stats.stale++;
    }
}

/* A live input whose result would not be finite (docs/simulator.md,
 * "Flat scene checks", Live API): the body's velocity at the world's time
 * after a set, an added velocity or an impulse; a teleport to a point that
 * is not finite or beyond LENGTH_MAX (|x| + |y|); or a motion after it
 * that reaches more than 2 LENGTH_MAX from the origin by the end (the
 * scene's rule 8 from the body's position and velocity after the input,
 * its acceleration and bound, with T the end time; left to right in
 * doubles).  1 with the message (nothing changed), else 0. */
static int refused_as_not_finite(m2c_world *m, const m2c_sim_body *b, int mode, double x, double y)
{
    int body = (int)b->idx;
    if (mode == M2C_SIM_REMOVE)
        return 0;
    m2c_body_state st;
    m2c_sim_body_state(b, m->now, &st);
    double px = st.x, py = st.y, vx = st.vx, vy = st.vy;
    if (mode == M2C_SIM_TELEPORT) {
        if (!isfinite(x) || !isfinite(y)) {
            snprintf(m->err, sizeof m->err, "live input: body %d: position would not be finite", body);
            return 1;
        }
        if (!(fabs(x) + fabs(y) <= LENGTH_MAX)) {
            snprintf(m->err, sizeof m->err, "live input: body %d: teleport beyond 1e150 m", body);
            return 1;
        }
        px = x;
        py = y;
    } else {
        if (mode == M2C_SIM_SET_VELOCITY) {
            vx = x;
            vy = y;
        } else if (mode == M2C_SIM_ADD_VELOCITY) {
            vx = st.vx + x;
            vy = st.vy + y;
        } else {
            vx = st.vx + x * b->inv_m;
            vy = st.vy + y * b->inv_m;
        }
        if (!b->fixed && !(isfinite(vx) && isfinite(vy))) {
            snprintf(m->err, sizeof m->err, "live input: body %d: velocity would not be finite", body);
            return 1;
        }
    }
    double T = m->s->end;
    double r = fabs(px) + fabs(py);
    r = r + (fabs(vx) + fabs(vy)) * T;
    r = r + (fabs(b->ax) + fabs(b->ay)) * T * T / 2.0;
    r = r + b->bound;
    if (r <= 2.0 * LENGTH_MAX)
        return 0;
    snprintf(m->err, sizeof m->err, "live input: body %d: reaches more than 2e150 m from the origin by the end", body);
    return 1;
}

int m2c_sim_live_input(m2c_world *m, int body, int mode, double x, double y, int *done)
{
    *done = 0;
    if (m->broken)
        return -1;
    if (m->finished) {
        snprintf(m->err, sizeof m->err, "live input: the world is finished");
        return -1;
    }
    if (body < 0 || body >= m->s->nbodies) {
        snprintf(m->err, sizeof m->err, "live input: body %d does not exist", body);
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
    if (!isfinite(x) || !isfinite(y)) {          /* also on a fixed body: its velocity or position */
        snprintf(m->err, sizeof m->err, "live input: body %d: %s would not be finite", body,
                 mode == M2C_SIM_TELEPORT ? "position" : "velocity");
        return -1;
    }
    if (refused_as_not_finite(m, b, mode, x, y))
        return -1;
    M2C_SIM_CATCH(m);
    double t = m->now;
    inputs_now(m);
    if (mode == M2C_SIM_TELEPORT && m2c_sim_overlapping(m, b, x, y, t) >= 0)
        return 0;
    m2c_sim_scene *s = m->s;
    if (s->ninputs == s->inputs_cap) {
        if (s->inputs_cap > (1 << 28))
            m2c_sim_die(m, "too many inputs");
        m2c_sim_input *more = realloc(s->inputs, 2 * (size_t)s->inputs_cap * sizeof *more);
        if (more == NULL)
            m2c_sim_die(m, "out of memory (inputs)");
        s->inputs = more;
        s->inputs_cap *= 2;
    }
    m2c_sim_input *in = &s->inputs[s->ninputs++];
    in->t = t;
    in->body = body;
    in->mode = mode;
    in->vx = x;
    in->vy = y;
    m2c_sim_push_input(m, t, s->ninputs - 1);
    inputs_now(m);
    *done = 1;
    return 0;
}

/* Room for one more body with nverts vertices: 0, or -1 (out of memory;
 * what was grown stays grown, nothing else changes). */
static int reserve_body(m2c_world *m, int32_t nverts)
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
        m2c_sim_rest_contact *rc = realloc(m->restc, M2C_SIM_REST_SLOTS * (size_t)cap * sizeof *rc);
        if (rc != NULL)
            m->restc = rc;
        if (b == NULL || st == NULL || lg == NULL || rc == NULL) {
            free(b);
            return -1;
        }
        m2c_sim_huge_pages(b, (size_t)cap * sizeof *b);
        memset(b, 0, (size_t)cap * sizeof *b);
        memcpy(b, s->bodies, (size_t)s->nbodies * sizeof *b);
        memset(st + s->bodies_cap, 0, (size_t)(cap - s->bodies_cap) * sizeof *st);
        memset(rc + M2C_SIM_REST_SLOTS * (size_t)s->bodies_cap, 0, M2C_SIM_REST_SLOTS * (size_t)(cap - s->bodies_cap) * sizeof *rc);
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

int m2c_sim_add_body(m2c_world *m, const char *text, int *idx)
{
    *idx = -1;
    if (m->broken)
        return -1;
    if (m->finished) {
        snprintf(m->err, sizeof m->err, "live input: the world is finished");
        return -1;
    }
    if (m->s->nbodies >= MAX_BODIES) {      /* a scene's limit holds for a world too */
        snprintf(m->err, sizeof m->err, "add_body: the world has %d bodies (at most %d)", (int)m->s->nbodies,
                 MAX_BODIES);
        return -1;
    }
    m2c_sim_scene *s = m->s;
    m2c_sim_body nb;
    memset(&nb, 0, sizeof nb);
    m2c_sim_vertex *nv = NULL;
    if (m2c_sim_body_read(text, &nb, s->nbodies, s->tol, s->end, &nv, m->err, sizeof m->err) != 0)
        return -1;
    nb.large = 2.0 * nb.bound > m2c_sim_min(s->cw, s->ch);
    if (nb.large && !nb.fixed) {
        char a[M2C_SIM_NUMBER_MAX + 1], b[M2C_SIM_NUMBER_MAX + 1], c[M2C_SIM_NUMBER_MAX + 1];
        snprintf(m->err, sizeof m->err, "add_body: a movable body of bound %s m does not fit the grid's cells "
                 "(%s x %s m): put such a body in the scene", m2c_sim_text(a, nb.bound), m2c_sim_text(b, s->cw),
                 m2c_sim_text(c, s->ch));
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
    M2C_SIM_CATCH(m);
    double t = m->now;
    b->tb = t;
    inputs_now(m);
    if (m2c_sim_overlapping(m, b, b->px, b->py, t) >= 0)
        return 0;
    s->nbodies++;
    s->nverts_all += (size_t)b->nverts;
    m->added++;
    m2c_sim_choose_fetch(m);
    m2c_sim_emit_add(m, t, b->idx);
    if (b->large) {
        m2c_sim_place_large(m, b);
        for (int32_t k = 0; k < s->nbodies; k++) {
            const m2c_sim_body *o = &m->bodies[k];
            if (!o->large && !o->gone && !(o->fixed && b->fixed))
                m2c_sim_predict_pair(m, o, b, t);
        }
    } else {
        m2c_sim_cell_of(m, b->px, b->py, &b->cx, &b->cy);
        m2c_sim_cell_add(m, b);
        if (!b->fixed)
            m2c_sim_emit_state(m, b);
        m2c_sim_predict_body(m, b, t, NULL);
    }
    *idx = b->idx;
    return 0;
}

int m2c_sim_finish(m2c_world *m)
{
    M2C_SIM_CATCH(m);
    m->finished = 1;
    m2c_sim_run_until(m, m->s->end, 1);
    m->now = m->s->end;
    for (int32_t k = 0; k < m->s->nbodies; k++)
        m2c_sim_rebase(&m->bodies[k], m->s->end);
    m2c_sim_emit_final(m);
    m2c_sim_out_flush(&m->out);
    if (m->out.failed)
        m2c_sim_die(m, "cannot write the trace");
    return 0;
}
