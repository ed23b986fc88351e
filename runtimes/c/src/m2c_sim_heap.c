/* The event queue: a binary min-heap of events ordered by (t, kind, seq),
 * seq being the unique scheduling counter, so the pop order is the
 * reference's (heapq on the tuple (t, kind, seq, ...)).  Times in s.
 * Stale events stay until popped (lazy invalidation); the array only grows,
 * by doubling, so there is no allocation per event. */
#include <stdlib.h>

#include "m2c_sim_internal.h"

static inline int earlier(const m2c_sim_event *x, const m2c_sim_event *y)
{
    return x->t < y->t || (x->t == y->t && x->key < y->key);
}

int m2c_sim_heap_push(m2c_sim_heap *h, const m2c_sim_event *e)
{
    if (h->n == h->cap) {
        size_t cap = h->cap ? 2 * h->cap : 1024;
        m2c_sim_event *ev = realloc(h->ev, cap * sizeof *ev);
        if (ev == NULL)
            return -1;
        h->ev = ev;
        h->cap = cap;
    }
    m2c_sim_event *ev = h->ev;
    size_t k = h->n++;
    while (k > 0) {
        size_t parent = (k - 1) / 2;
        if (!earlier(e, &ev[parent]))
            break;
        ev[k] = ev[parent];
        k = parent;
    }
    ev[k] = *e;
    return 0;
}

void m2c_sim_heap_pop(m2c_sim_heap *h, m2c_sim_event *e)
{
    m2c_sim_event *ev = h->ev;
    *e = ev[0];
    size_t n = --h->n;
    if (n == 0)
        return;
    m2c_sim_event last = ev[n];
    size_t k = 0;
    for (;;) {
        size_t c = 2 * k + 1;
        if (c >= n)
            break;
        if (c + 1 < n && earlier(&ev[c + 1], &ev[c]))
            c++;
        if (!earlier(&ev[c], &last))
            break;
        ev[k] = ev[c];
        k = c;
    }
    ev[k] = last;
}

void m2c_sim_heap_free(m2c_sim_heap *h)
{
    free(h->ev);
    h->ev = NULL;
    h->n = h->cap = 0;
}
