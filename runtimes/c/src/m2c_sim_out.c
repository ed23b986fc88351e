/* The trace writer (docs/simulator.md, "Flat trace"): one function per
 * kind of line, numbers written as %.17g (m2c_sim_format.c).  Lines are
 * formatted straight into one buffer that is written out when less than a
 * line's room is left (and at the end).  A world without a trace (out.f
 * NULL) formats no event lines.  Times in s. */
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "m2c_sim_internal.h"

enum { OUT_BUFFER = 1 << 16 };

int m2c_sim_out_init(m2c_sim_out *o, FILE *f)
{
    o->f = f;
    o->n = 0;
    o->failed = 0;
    o->cap = OUT_BUFFER;
    o->buf = malloc(o->cap);
    return o->buf == NULL ? -1 : 0;
}

void m2c_sim_out_flush(m2c_sim_out *o)
{
    if (o->f == NULL) {         /* no trace: the lines are dropped */
        o->n = 0;
        return;
    }
    if (o->n > 0 && fwrite(o->buf, 1, o->n, o->f) != o->n)
        o->failed = 1;
    o->n = 0;
    if (fflush(o->f) != 0)
        o->failed = 1;
}

void m2c_sim_out_free(m2c_sim_out *o)
{
    free(o->buf);
    o->buf = NULL;
}

char *m2c_sim_put_int(char *p, long long v)
{
    /* a collision line's feature and vertex indices are 0, 1 or -1 */
    if (v >= -9 && v <= 9) {
        if (v < 0) {
            *p++ = '-';
            v = -v;
        }
        *p++ = (char)('0' + v);
        return p;
    }
    char tmp[24];
    int n = 0;
    unsigned long long u = v < 0 ? 0ull - (unsigned long long)v : (unsigned long long)v;
    do {
        tmp[n++] = (char)('0' + u % 10u);
        u /= 10u;
    } while (u != 0);
    if (v < 0)
        *p++ = '-';
    while (n > 0)
        *p++ = tmp[--n];
    return p;
}

/* ---- the lines ------------------------------------------------------------------ */

/* The N lines, in their order: each counter's name and place in m2c_sim_stats. */
static const struct {
    const char *name;
    size_t offset;
} stat_lines[] = {
    { "collisions", offsetof(m2c_sim_stats, collisions) }, { "inputs", offsetof(m2c_sim_stats, inputs) },
    { "frames", offsetof(m2c_sim_stats, frames) },         { "cells", offsetof(m2c_sim_stats, cells) },
    { "horizons", offsetof(m2c_sim_stats, horizons) },     { "stale", offsetof(m2c_sim_stats, stale) },
    { "pairs", offsetof(m2c_sim_stats, pairs) },           { "features", offsetof(m2c_sim_stats, features) },
    { "supports", offsetof(m2c_sim_stats, supports) },     { "stops", offsetof(m2c_sim_stats, stops) },
    { "leaves", offsetof(m2c_sim_stats, leaves) },         { "sleeps", offsetof(m2c_sim_stats, sleeps) },
    { "wakes", offsetof(m2c_sim_stats, wakes) },
};

/* A time as m2c_sim_put_num writes it.  A collision's E line and its two
 * S lines write the same time (the bodies' tb is the event's t): the text
 * of the last one is kept and copied while the bits are the same. */
static inline char *put_time(m2c_world *m, char *p, double t)
{
    uint64_t bits;
    memcpy(&bits, &t, sizeof bits);
    if (m->time_len == 0 || bits != m->time_bits) {
        m->time_len = m2c_sim_format_number(m->time_text, t);
        m->time_bits = bits;
    }
    memcpy(p, m->time_text, M2C_SIM_NUMBER_MAX);      /* a line has room for whole numbers */
    return p + m->time_len;
}

void m2c_sim_emit_state(m2c_world *m, const m2c_sim_body *b)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, "S ");
    p = m2c_sim_put_int(p, b->idx);
    *p++ = ' ';
    p = put_time(m, p, b->tb);
    const double v[8] = { b->px, b->py, b->vx, b->vy, b->ang, b->om, b->ax, b->ay };
    for (int k = 0; k < 8; k++) {
        *p++ = ' ';
        p = m2c_sim_put_num(p, v[k]);
    }
    *p++ = '\n';
    m->out.n += (size_t)(p - start);
}

/* An E line of a contact: collision or support (kind "E collision ", "E support "). */
void m2c_sim_emit_contact(m2c_world *m, const char *kind, double t, const m2c_sim_body *A, const m2c_sim_body *B,
                          int32_t feature, int32_t i, int32_t j, double cx, double cy, double nx, double ny,
                          double imp)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, kind);
    p = put_time(m, p, t);
    const long long ints[5] = { A->idx, B->idx, feature, i, j };
    for (int k = 0; k < 5; k++) {
        *p++ = ' ';
        p = m2c_sim_put_int(p, ints[k]);
    }
    const double nums[5] = { cx, cy, nx, ny, imp };
    for (int k = 0; k < 5; k++) {
        *p++ = ' ';
        p = m2c_sim_put_num(p, nums[k]);
    }
    *p++ = '\n';
    m->out.n += (size_t)(p - start);
}

/* An E line of a supported body's event: stop or leave (edge of sup). */
void m2c_sim_emit_support_change(m2c_world *m, const char *kind, double t, const m2c_sim_body *A, int32_t sup,
                                 int32_t edge)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, kind);
    p = m2c_sim_put_num(p, t);
    *p++ = ' ';
    p = m2c_sim_put_int(p, A->idx);
    *p++ = ' ';
    p = m2c_sim_put_int(p, sup);
    p = m2c_sim_put_str(p, " -1 -1 ");
    p = m2c_sim_put_int(p, edge);
    p = m2c_sim_put_str(p, " 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
}

/* An E line of a sleep or wake: body a, body b (-1 for a wake), island. */
void m2c_sim_emit_island(m2c_world *m, const char *kind, double t, int32_t a, int32_t b, int32_t island)
{
    if (m->out.f == NULL)
        return;
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, kind);
    p = m2c_sim_put_num(p, t);
    *p++ = ' ';
    p = m2c_sim_put_int(p, a);
    *p++ = ' ';
    p = m2c_sim_put_int(p, b);
    p = m2c_sim_put_str(p, " -1 -1 ");
    p = m2c_sim_put_int(p, island);
    p = m2c_sim_put_str(p, " 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
}

/* An E line of an input (k: its index in the input list). */
void m2c_sim_emit_input(m2c_world *m, double t, const m2c_sim_body *body, int32_t k)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, "E input ");
    p = m2c_sim_put_num(p, t);
    *p++ = ' ';
    p = m2c_sim_put_int(p, body->idx);
    p = m2c_sim_put_str(p, " -1 -1 ");
    p = m2c_sim_put_int(p, k);
    p = m2c_sim_put_str(p, " -1 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
}

/* An E line of a frame at t. */
void m2c_sim_emit_frame(m2c_world *m, double t)
{
    if (m->out.f == NULL)
        return;     /* no trace: nothing to format */
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, "E frame ");
    p = m2c_sim_put_num(p, t);
    p = m2c_sim_put_str(p, " -1 -1 -1 -1 -1 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
}

/* An E line of a body added at t (add_body). */
void m2c_sim_emit_add(m2c_world *m, double t, int32_t idx)
{
    char *start = m2c_sim_out_reserve(&m->out), *p = start;
    p = m2c_sim_put_str(p, "E add ");
    p = m2c_sim_put_num(p, t);
    *p++ = ' ';
    p = m2c_sim_put_int(p, idx);
    p = m2c_sim_put_str(p, " -1 -1 -1 -1 0 0 0 0 0\n");
    m->out.n += (size_t)(p - start);
}

/* The trace's end: an F line per body (its state at its time: the end
 * time, where m2c_sim_finish moved every body), the N lines of the
 * counters, the V lines of the predictions served per variant. */
void m2c_sim_emit_final(m2c_world *m)
{
    const m2c_sim_scene *s = m->s;
    const m2c_sim_body *bodies = m->bodies;
    for (int32_t k = 0; k < s->nbodies; k++) {
        const m2c_sim_body *b = &bodies[k];
        char *start = m2c_sim_out_reserve(&m->out), *p = start;
        p = m2c_sim_put_str(p, "F ");
        p = m2c_sim_put_int(p, b->idx);
        const double v[6] = { b->px, b->py, b->vx, b->vy, b->ang, b->om };
        for (int l = 0; l < 6; l++) {
            *p++ = ' ';
            p = m2c_sim_put_num(p, v[l]);
        }
        *p++ = '\n';
        m->out.n += (size_t)(p - start);
    }
    for (size_t k = 0; k < sizeof stat_lines / sizeof stat_lines[0]; k++) {
        char *start = m2c_sim_out_reserve(&m->out), *p = start;
        p = m2c_sim_put_str(p, "N ");
        p = m2c_sim_put_str(p, stat_lines[k].name);
        *p++ = ' ';
        p = m2c_sim_put_int(p, *(const long long *)((const char *)&m->stats + stat_lines[k].offset));
        *p++ = '\n';
        m->out.n += (size_t)(p - start);
    }
    for (int e = 0; e < 2; e++) {
        int n = e == 0 ? m->n_cc : m->n_pe;
        const long long *counts = e == 0 ? m->cc_counts : m->pe_counts;
        for (int k = 0; k < n; k++) {
            char *start = m2c_sim_out_reserve(&m->out), *p = start;
            p = m2c_sim_put_str(p, e == 0 ? "V circle_circle " : "V point_edge ");
            p = m2c_sim_put_int(p, k);
            *p++ = ' ';
            p = m2c_sim_put_int(p, counts[k]);
            *p++ = '\n';
            m->out.n += (size_t)(p - start);
        }
    }
}
