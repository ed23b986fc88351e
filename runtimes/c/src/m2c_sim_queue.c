/* The event queue, ordered by (t, kind, seq) with seq the unique scheduling
 * counter: the pop order of the reference's heapq of (t, kind, seq, ...),
 * whatever the structure.  Times in s.
 *
 * A radix heap on the hex digits of t's bits (which order as t does,
 * t >= 0): events at or before `last`, the time last reached, wait in
 * `near`, a small 4-ary heap of 16-byte entries (bits of t; kind, seq and
 * slot in one word) compared as 128-bit integers; a later event waits
 * unsorted in bucket 16 i + j, i the highest hex digit where its time's
 * bits differ from last's and j its digit there (so bucket order is time
 * order).  When `near` runs empty, the lowest non-empty bucket gives the
 * next `last` (its smallest time) and is split: its events at that time go
 * to `near`, the others to buckets of lower digits; a lowest bucket of
 * POUR events or fewer goes to `near` whole instead, `last` then the
 * highest time that bucket can hold (a few events would otherwise go down
 * the digits one advance at a time).  An event moves at most
 * once per digit (with one bucket per bit it would move about 26 times on
 * the 10^4-disk gas; per hex digit the queue's splits take 27 % fewer
 * instructions).  So the simulator's queue, thousands of future events per
 * body, is only ever scanned in order, never sifted through at random (a
 * binary heap's pop misses the cache at every level).  An event
 * scheduled before `last` (a cell crossing rounded an ulp early) goes to
 * `near`, which orders it first, as heapq would.  For the same reason the
 * next `last` may be found right after a pop, so that the next event can be
 * fetched from memory while this one is handled.
 *
 * The events themselves wait in slots of `rest`, reused once popped.  seq
 * has M2C_SIM_SEQ_BITS bits: when they run out, the queued events are
 * renumbered 0, 1, ... in their order, which changes no comparison.  The
 * arrays grow by doubling: no allocation per event; a bucket's array of
 * more than KEEP entries is given back when the bucket empties (release),
 * so that the memory does not grow with the run's length. */
#include <stdlib.h>
#include <string.h>

#include "m2c_sim_internal.h"

__extension__ typedef unsigned __int128 u128;

#define SLOT_MASK ((UINT64_C(1) << M2C_SIM_SLOT_BITS) - 1u)
#define SEQ_SHIFT M2C_SIM_SLOT_BITS
#define SEQ_LIMIT (UINT64_C(1) << M2C_SIM_SEQ_BITS)
#define KIND_SHIFT (M2C_SIM_SLOT_BITS + M2C_SIM_SEQ_BITS)
#define AHEAD 32            /* the most records advance fetches at once */
#define POUR 16             /* a lowest bucket of this many events or fewer goes to near whole */

_Static_assert(KIND_SHIFT + 3 <= 64, "kind, seq and slot must fit 64 bits");
_Static_assert(M2C_SIM_KINDS <= 8, "the kind has 3 bits");
_Static_assert(M2C_SIM_SLOT_BITS < M2C_SIM_SEQ_BITS && M2C_SIM_SLOT_BITS <= 32, "room to renumber");

static inline u128 order(const m2c_sim_entry *x)
{
    return ((u128)x->tb << 64) | x->key;
}

static int append(m2c_sim_bucket *b, m2c_sim_entry x)
{
    if (b->n == b->cap) {
        size_t cap = b->cap ? 2 * b->cap : 64;
        m2c_sim_entry *e = realloc(b->e, cap * sizeof *e);
        if (e == NULL)
            return -1;
        m2c_sim_huge_pages(e + b->cap, (cap - b->cap) * sizeof *e);    /* the new half, not yet written */
        b->e = e;
        b->cap = cap;
    }
    b->e[b->n++] = x;
    return 0;
}

/* An emptied bucket gives back an array of more than KEEP entries.  Each
 * bucket's array grows to the most events it ever held at once, and over a
 * long run most of the 256 buckets fill up in turn to about the whole
 * queue: kept, the arrays' sum grows with the run (the 10^4-disk gas: 0.16
 * M entries after 95 k events, 0.90 M after 2.8 M), given back, it stays
 * under the queue's peak plus KEEP per bucket, whatever the run's length. */
#define KEEP 1024

static void release(m2c_sim_bucket *b)
{
    if (b->n == 0 && b->cap > KEEP) {
        free(b->e);
        b->e = NULL;
        b->cap = 0;
    }
}

/* ---- near: a 4-ary min-heap --------------------------------------------------- */

static int near_push(m2c_sim_bucket *hp, m2c_sim_entry x)
{
    if (append(hp, x) != 0)
        return -1;
    m2c_sim_entry *ev = hp->e;
    u128 xo = order(&x);
    size_t k = hp->n - 1;
    while (k > 0) {
        size_t parent = (k - 1) / 4;
        if (!(xo < order(&ev[parent])))
            break;
        ev[k] = ev[parent];
        k = parent;
    }
    ev[k] = x;
    return 0;
}

/* Moves ev[k] down to its place among its descendants (n entries). */
static void sift_down(m2c_sim_entry *ev, size_t n, size_t k)
{
    m2c_sim_entry x = ev[k];
    u128 xo = order(&x);
    for (;;) {
        size_t c = 4 * k + 1;
        if (c >= n)
            break;
        size_t best = c;
        u128 bo = order(&ev[c]);
        size_t end = c + 4 < n ? c + 4 : n;
        for (size_t q = c + 1; q < end; q++) {
            u128 qo = order(&ev[q]);
            if (qo < bo) {
                best = q;
                bo = qo;
            }
        }
        if (!(bo < xo))
            break;
        ev[k] = ev[best];
        k = best;
    }
    ev[k] = x;
}

static m2c_sim_entry near_pop(m2c_sim_bucket *hp)
{
    m2c_sim_entry top = hp->e[0];
    size_t n = --hp->n;
    if (n > 0) {
        hp->e[0] = hp->e[n];
        sift_down(hp->e, n, 0);
    }
    return top;
}

static void near_heapify(m2c_sim_bucket *hp)
{
    if (hp->n > 1)
        for (size_t k = (hp->n - 2) / 4 + 1; k-- > 0;)
            sift_down(hp->e, hp->n, k);
}

/* ---- the radix levels ------------------------------------------------------------ */

/* The bucket of tb > last: 16 i + j, i the highest hex digit where tb
 * differs from last, j tb's digit there. */
static inline int bucket_of(uint64_t tb, uint64_t last)
{
    int i = (63 - __builtin_clzll(tb ^ last)) >> 2;
    return 16 * i + (int)((tb >> (4 * i)) & 15u);
}

/* Files x under last: near, or its bucket. */
static int place(m2c_sim_heap *h, m2c_sim_entry x)
{
    if (x.tb <= h->last)
        return near_push(&h->near, x);
    int k = bucket_of(x.tb, h->last);
    if (append(&h->bucket[k], x) != 0)
        return -1;
    h->full[k >> 6] |= UINT64_C(1) << (k & 63);
    return 0;
}

/* near is empty and some bucket is not: the lowest one's smallest time
 * becomes `last`, and its events move to near or to lower buckets (their
 * highest digit that differs from the new last is a lower one). */
static int advance(m2c_sim_heap *h)
{
    int w = 0;
    while (h->full[w] == 0)
        w++;
    int k = 64 * w + __builtin_ctzll(h->full[w]);
    m2c_sim_bucket *b = &h->bucket[k];
    if (b->n <= POUR) {
        /* few events: all of them to near, and `last` to the highest time the
         * bucket can hold (last's digits above i, then j, then all ones):
         * every other bucket's events are later than that and stay where
         * they are (their highest digit that differs from it, and their
         * digit there, are those they had) */
        int i = k >> 4;
        uint64_t below = (UINT64_C(1) << (4 * i)) - 1u;     /* digits under i */
        uint64_t above = i == 15 ? 0u : ~((UINT64_C(16) << (4 * i)) - 1u);
        h->last = (h->last & above) | ((uint64_t)(k & 15) << (4 * i)) | below;
        h->full[w] &= ~(UINT64_C(1) << (k & 63));
        for (size_t q = 0; q < b->n; q++) {
            __builtin_prefetch(&h->rest[b->e[q].key & SLOT_MASK]);
            if (near_push(&h->near, b->e[q]) != 0)
                return -1;
        }
        b->n = 0;
        release(b);
        return 0;
    }
    uint64_t low = b->e[0].tb;
    for (size_t q = 1; q < b->n; q++)
        if (b->e[q].tb < low)
            low = b->e[q].tb;
    /* the lowest bucket holds the next events (but those pushed later): when
     * they are few, fetch their records now, so that the pops that follow
     * (many of stale events, which are only looked at) do not wait for each */
    if (b->n <= AHEAD)
        for (size_t q = 0; q < b->n; q++)
            __builtin_prefetch(&h->rest[b->e[q].key & SLOT_MASK]);
    h->last = low;
    h->full[w] &= ~(UINT64_C(1) << (k & 63));
    size_t n = b->n;
    b->n = 0;
    for (size_t q = 0; q < n; q++) {
        m2c_sim_entry x = b->e[q];
        if (x.tb == low) {
            if (near_push(&h->near, x) != 0)
                return -1;
        } else {
            int j = bucket_of(x.tb, low);       /* j < k */
            if (append(&h->bucket[j], x) != 0)
                return -1;
            h->full[j >> 6] |= UINT64_C(1) << (j & 63);
        }
    }
    release(b);
    return 0;
}

static inline int any_full(const m2c_sim_heap *h)
{
    return (h->full[0] | h->full[1] | h->full[2] | h->full[3]) != 0;
}

/* ---- slots and seq ---------------------------------------------------------------- */

static int grow(m2c_sim_heap *h)
{
    size_t cap = h->cap ? 2 * h->cap : 1024;
    if (cap > SLOT_MASK + 1u)
        return -1;
    m2c_sim_event *rest = realloc(h->rest, cap * sizeof *rest);
    if (rest == NULL)
        return -1;
    m2c_sim_huge_pages(rest + h->cap, (cap - h->cap) * sizeof *rest);     /* the new half, not yet written */
    h->rest = rest;
    uint32_t *fr = realloc(h->free, cap * sizeof *fr);
    if (fr == NULL)
        return -1;
    h->free = fr;
    h->cap = cap;
    return 0;
}

static int by_value(const void *x, const void *y)
{
    uint64_t a = *(const uint64_t *)x, b = *(const uint64_t *)y;
    return (a > b) - (a < b);
}

static m2c_sim_entry *entry_at(m2c_sim_heap *h, size_t k)
{
    if (k < h->near.n)
        return &h->near.e[k];
    k -= h->near.n;
    for (int b = 0; b < M2C_SIM_BUCKETS; b++) {
        if (k < h->bucket[b].n)
            return &h->bucket[b].e[k];
        k -= h->bucket[b].n;
    }
    return NULL;
}

/* Renumbers the queued events' seq 0 .. n-1 in the order of their seq. */
static int renumber(m2c_sim_heap *h)
{
    if (h->n >= SEQ_LIMIT / 2 || h->n > UINT32_MAX)  /* never with the default sizes: n < 2^28 */
        return -1;
    /* (seq << 32 | position) sorts by seq */
    uint64_t *tmp = malloc((h->n + 1) * sizeof *tmp);
    if (tmp == NULL)
        return -1;
    for (size_t k = 0; k < h->n; k++)
        tmp[k] = (((entry_at(h, k)->key >> SEQ_SHIFT) & (SEQ_LIMIT - 1u)) << 32) | k;
    qsort(tmp, h->n, sizeof *tmp, by_value);
    for (size_t r = 0; r < h->n; r++) {
        m2c_sim_entry *x = entry_at(h, tmp[r] & 0xffffffffu);
        uint64_t kind = x->key >> KIND_SHIFT, slot = x->key & SLOT_MASK;
        x->key = (kind << KIND_SHIFT) | ((uint64_t)r << SEQ_SHIFT) | slot;
    }
    free(tmp);
    h->seq = h->n;
    return 0;
}

/* ---- the API ------------------------------------------------------------------------ */

int m2c_sim_heap_push(m2c_sim_heap *h, const m2c_sim_event *e)
{
    if (h->n == h->cap && grow(h) != 0)
        return -1;
    if (h->seq == SEQ_LIMIT && renumber(h) != 0)
        return -1;
    /* a slot: the last freed, else a new one (n < cap, so one is there) */
    uint32_t slot = h->nfree > 0 ? h->free[h->nfree - 1] : (uint32_t)h->used;
    double t = e->t + 0.0;          /* -0.0 orders as 0.0, as in the reference */
    m2c_sim_entry x;
    memcpy(&x.tb, &t, sizeof t);
    x.key = ((uint64_t)e->kind << KIND_SHIFT) | (h->seq << SEQ_SHIFT) | slot;
    if (place(h, x) != 0)
        return -1;
    if (h->nfree > 0)
        h->nfree--;
    else
        h->used++;
    h->rest[slot] = *e;
    h->seq++;
    h->n++;
    return 0;
}

int m2c_sim_heap_pop(m2c_sim_heap *h, m2c_sim_event *e)
{
    if (h->near.n == 0 && advance(h) != 0)
        return -1;
    m2c_sim_entry x = near_pop(&h->near);
    uint32_t slot = (uint32_t)(x.key & SLOT_MASK);
    *e = h->rest[slot];
    h->free[h->nfree++] = slot;
    h->n--;
    /* Find the next event now (events scheduled meanwhile before it go to
     * near, which orders them first) and fetch it while this one is handled. */
    if (h->near.n == 0 && any_full(h) && advance(h) != 0)
        return -1;
    if (h->near.n > 0)
        __builtin_prefetch(&h->rest[h->near.e[0].key & SLOT_MASK]);
    return 0;
}

int m2c_sim_heap_top(m2c_sim_heap *h, const m2c_sim_event **e)
{
    *e = NULL;
    if (h->n == 0)
        return 0;
    if (h->near.n == 0 && advance(h) != 0)
        return -1;
    *e = &h->rest[h->near.e[0].key & SLOT_MASK];
    return 0;
}

void m2c_sim_heap_sweep(m2c_sim_heap *h, int (*drop)(void *ctx, const m2c_sim_event *e), void *ctx)
{
    for (int b = -1; b < M2C_SIM_BUCKETS; b++) {
        m2c_sim_bucket *bk = b < 0 ? &h->near : &h->bucket[b];
        size_t w = 0;
        for (size_t k = 0; k < bk->n; k++) {
            uint32_t slot = (uint32_t)(bk->e[k].key & SLOT_MASK);
            if (drop(ctx, &h->rest[slot])) {
                h->free[h->nfree++] = slot;
                h->n--;
            } else {
                bk->e[w++] = bk->e[k];
            }
        }
        bk->n = w;
        if (b >= 0 && w == 0) {
            h->full[b >> 6] &= ~(UINT64_C(1) << (b & 63));
            release(bk);
        }
    }
    near_heapify(&h->near);
}

void m2c_sim_heap_free(m2c_sim_heap *h)
{
    free(h->near.e);
    for (int b = 0; b < M2C_SIM_BUCKETS; b++)
        free(h->bucket[b].e);
    free(h->rest);
    free(h->free);
    memset(h, 0, sizeof *h);
}
