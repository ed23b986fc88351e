/* The live world API (m2c_world.h, docs/engine-api.md): creation, time,
 * queries and inputs, on the engine of m2c_sim.c.  Built with the
 * generated equations and the numbers of variants their NAME_variant
 * functions index:  -DM2C_SIM_CC_VARIANTS=N -DM2C_SIM_PE_VARIANTS=M. */
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_sim_internal.h"
#include "m2c_world.h"

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

/* %.17g of x, as the reference writes numbers in its messages. */
static const char *num(char *buf, double x)
{
    buf[m2c_sim_format_number(buf, x)] = '\0';
    return buf;
}

int m2c_world_advance(m2c_world *w, double t, m2c_contact_fn fn, void *user)
{
    if (w->broken)
        return -1;
    if (!(t >= w->now && t <= w->s->end)) {
        /* the world is unchanged: the caller may go on */
        char a[M2C_SIM_NUMBER_MAX + 1], b[M2C_SIM_NUMBER_MAX + 1], c[M2C_SIM_NUMBER_MAX + 1];
        snprintf(w->err, sizeof w->err, "advance: t = %s is outside [%s, %s] (the world's time .. the scene's end)",
                 num(a, t), num(b, w->now), num(c, w->s->end));
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
                 num(a, t), num(b, w->now), num(c, nxt));
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
