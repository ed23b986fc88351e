/* The flat trace of a simulator (docs/simulator.md) as the JSON lines of
   `max2code simulate`, for the lines a run writes by the million: states,
   collisions, supports and frames.  Loaded by max2code/sim/trace_json.py
   through ctypes; max2code/sim/simulate.py (TraceConverter) is the
   specification and does everything else.

   tj_convert takes whole events (a chunk that ends where a line other than
   a state begins) and writes them, or returns -1 when the chunk holds
   anything else: another line tag or event kind, a number that is not
   plainly finite, a body or vertex index not written as %d writes it, a
   blank or other space.  Python then converts that chunk itself, with the
   same bytes or the precise error; so a number goes through here only in
   the two forms `_num` passes on unchanged or gives '.0'. */
#include <stdlib.h>
#include <string.h>

typedef struct {
    long count;          /* bodies */
    long most;           /* largest vertex or body index of a feature */
    const char **name;   /* the JSON text of each body's name */
    long *len;
    char *text;
} tj_names;

void *tj_new(const char *names, long size, long count, long most)
{
    /* names: the JSON text of every name, each followed by a newline */
    tj_names *h = calloc(1, sizeof *h);
    if (!h)
        return NULL;
    h->text = malloc((size_t)size + 1);
    h->name = malloc(sizeof *h->name * (size_t)(count + 1));
    h->len = malloc(sizeof *h->len * (size_t)(count + 1));
    if (!h->text || !h->name || !h->len) {
        free(h->text);
        free(h->name);
        free(h->len);
        free(h);
        return NULL;
    }
    memcpy(h->text, names, (size_t)size);
    h->count = count;
    h->most = most;
    long k = 0, start = 0;
    for (long p = 0; p < size && k < count; p++) {
        if (h->text[p] == '\n') {
            h->name[k] = h->text + start;
            h->len[k] = p - start;
            k++;
            start = p + 1;
        }
    }
    h->count = k;
    return h;
}

void tj_free(void *p)
{
    tj_names *h = p;
    if (h) {
        free(h->text);
        free(h->name);
        free(h->len);
        free(h);
    }
}

typedef struct {
    char *p, *end;
    int full;
} out_t;

static void put(out_t *o, const char *s, long n)
{
    if (o->full || o->end - o->p < n) {
        o->full = 1;
        return;
    }
    memcpy(o->p, s, (size_t)n);
    o->p += n;
}

#define PUTS(o, lit) put((o), (lit), (long)sizeof(lit) - 1)

typedef struct {
    const char *s;
    long n;
} tok_t;

/* the characters of a number: 1 a digit or a sign, 3 '.' or 'e' (bit 1:
   allowed, bit 2: the number passes unchanged); 0 any other */
static const unsigned char NUM_CLASS[256] = {
    ['0'] = 1, ['1'] = 1, ['2'] = 1, ['3'] = 1, ['4'] = 1, ['5'] = 1, ['6'] = 1, ['7'] = 1, ['8'] = 1, ['9'] = 1,
    ['-'] = 1, ['+'] = 1, ['.'] = 3, ['e'] = 3};

/* -?[0-9]+ */
static int whole(const char *s, long n)
{
    long i = s[0] == '-' ? 1 : 0;
    if (i == n)
        return 0;
    for (; i < n; i++)
        if (s[i] < '0' || s[i] > '9')
            return 0;
    return 1;
}

/* a number as _num writes it: unchanged when it has a '.' or an 'e' and is
   made of digits, '.', 'e', '+' and '-' only; -?[0-9]+ with '.0'; 0 else.
   Checked while copied (one pass, no call): most of the trace's bytes. */
static int num(out_t *o, tok_t t)
{
    const unsigned char *s = (const unsigned char *)t.s;
    unsigned all = 1, mark = 0;
    if (!o->full && o->end - o->p >= t.n + 2) {
        char *d = o->p;
        for (long i = 0; i < t.n; i++) {
            unsigned c = NUM_CLASS[s[i]];
            all &= c;
            mark |= c;
            d[i] = (char)s[i];
        }
        if (!all)
            return 0;
        if (mark & 2) {
            o->p = d + t.n;
            return 1;
        }
        if (!whole(t.s, t.n))
            return 0;
        d[t.n] = '.';
        d[t.n + 1] = '0';
        o->p = d + t.n + 2;
        return 1;
    }
    for (long i = 0; i < t.n; i++) {        /* no room: checked only (the caller grows the buffer) */
        unsigned c = NUM_CLASS[s[i]];
        all &= c;
        mark |= c;
    }
    o->full = 1;
    return all && ((mark & 2) || whole(t.s, t.n));
}

/* a whole number as %d writes it, from -1 to `most`; -2 else */
static long index_of(tok_t t, long most)
{
    if (t.n == 2 && t.s[0] == '-' && t.s[1] == '1')
        return -1;
    if (t.n < 1 || t.n > 18 || (t.s[0] == '0' && t.n > 1))
        return -2;
    long v = 0;
    for (long i = 0; i < t.n; i++) {
        if (t.s[i] < '0' || t.s[i] > '9')
            return -2;
        v = v * 10 + (t.s[i] - '0');
    }
    return v <= most ? v : -2;
}

static int same(tok_t t, const char *lit)
{
    size_t n = strlen(lit);
    return (size_t)t.n == n && memcmp(t.s, lit, n) == 0;
}

/* The space-separated fields of the line [p, nl) into t (at most `most`):
   their count, or -1 for a blank field or line, or too many fields. */
static int split_line(const char *p, const char *nl, tok_t *t, int most)
{
    int n = 0;
    const char *q = p;
    for (;;) {
        const char *sp = q;
        while (sp < nl && *sp != ' ')
            sp++;
        if (sp == q || n == most)
            return -1;
        t[n].s = q;
        t[n].n = sp - q;
        n++;
        if (sp == nl)
            return n;
        q = sp + 1;
    }
}

/* Returns the bytes written to out, -1 when Python must convert this chunk,
   -2 when out is too small; *events: the E lines of the chunk, *lines: its lines. */
long tj_convert(void *handle, const char *in, long size, char *out, long cap, int frames, long *events,
                long *lines)
{
    const tj_names *h = handle;
    out_t o = {out, out + cap, 0};
    int open = 0;        /* 0: no event; 1: an event's head written; 2: and states */
    long n_events = 0, n_lines = 0;
    const char *p = in, *end = in + size;
    if (size == 0 || in[size - 1] != '\n')
        return -1;
    while (p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        tok_t t[13];
        int n = split_line(p, nl, t, 13);
        if (n < 0)
            return -1;
        p = nl + 1;
        n_lines++;
        if (n == 11 && same(t[0], "S")) {
            long b = index_of(t[1], h->count - 1);
            if (open == 0 || b < 0)
                return -1;
            if (open == 1)
                PUTS(&o, ",\"states\":[");
            else
                PUTS(&o, ",");
            open = 2;
            PUTS(&o, "{\"body\":");
            put(&o, h->name[b], h->len[b]);
            PUTS(&o, ",\"position\":[");
            if (!num(&o, t[3])) return -1;
            PUTS(&o, ",");
            if (!num(&o, t[4])) return -1;
            PUTS(&o, "],\"velocity\":[");
            if (!num(&o, t[5])) return -1;
            PUTS(&o, ",");
            if (!num(&o, t[6])) return -1;
            PUTS(&o, "],\"angle\":");
            if (!num(&o, t[7])) return -1;
            PUTS(&o, ",\"angular_velocity\":");
            if (!num(&o, t[8])) return -1;
            PUTS(&o, ",\"acceleration\":[");
            if (!num(&o, t[9])) return -1;
            PUTS(&o, ",");
            if (!num(&o, t[10])) return -1;
            PUTS(&o, "]}");
            continue;
        }
        if (n != 13 || !same(t[0], "E"))
            return -1;
        if (open == 2)
            PUTS(&o, "]}\n");
        else if (open == 1)
            PUTS(&o, "}\n");
        open = 0;
        n_events++;
        int collision = same(t[1], "collision");
        if (collision || same(t[1], "support")) {
            long a = index_of(t[3], h->count - 1), b = index_of(t[4], h->count - 1);
            long i = index_of(t[6], h->most), j = index_of(t[7], h->most);
            int feat = same(t[5], "0") ? 0 : same(t[5], "1") ? 1 : -1;
            if (a < 0 || b < 0 || i < -1 || j < -1 || feat < 0)
                return -1;
            const char *feature = feat == 0 ? (j >= 0 ? "circle-vertex" : "circle-circle")
                                            : (i >= 0 ? "vertex-edge" : "circle-edge");
            PUTS(&o, "{\"t\":");
            if (!num(&o, t[2])) return -1;
            PUTS(&o, ",\"kind\":\"");
            put(&o, t[1].s, t[1].n);
            PUTS(&o, "\",\"bodies\":[");
            put(&o, h->name[a], h->len[a]);
            PUTS(&o, ",");
            put(&o, h->name[b], h->len[b]);
            PUTS(&o, "],\"feature\":\"");
            put(&o, feature, (long)strlen(feature));
            PUTS(&o, "\",\"features\":[");
            put(&o, t[6].s, t[6].n);
            PUTS(&o, ",");
            put(&o, t[7].s, t[7].n);
            PUTS(&o, "],\"point\":[");
            if (!num(&o, t[8])) return -1;
            PUTS(&o, ",");
            if (!num(&o, t[9])) return -1;
            PUTS(&o, "],\"normal\":[");
            if (!num(&o, t[10])) return -1;
            PUTS(&o, ",");
            if (!num(&o, t[11])) return -1;
            PUTS(&o, "],\"impulse\":");
            if (!num(&o, t[12])) return -1;
            open = 1;
        } else if (same(t[1], "frame")) {
            if (frames) {
                PUTS(&o, "{\"t\":");
                if (!num(&o, t[2])) return -1;
                PUTS(&o, ",\"kind\":\"frame\"");
                open = 1;
            } else {
                tok_t time = t[2];   /* checked as the Python path checks it, then left out */
                out_t none = {NULL, NULL, 1};
                if (!num(&none, time))
                    return -1;
            }
        } else {
            return -1;
        }
    }
    if (open == 2)
        PUTS(&o, "]}\n");
    else if (open == 1)
        PUTS(&o, "}\n");
    if (o.full)
        return -2;
    *events = n_events;
    *lines = n_lines;
    return o.p - out;
}

/* F lines only (the final states, one per body) as _finals writes them: each
   `{"body":NAME,"position":[PX,PY],"velocity":[VX,VY],"angle":A,"angular_velocity":W}`,
   separated by commas.  Returns the bytes written, -1 when Python must convert
   the block (another line, a number or index not in its plain form), -2 when
   out is too small. */
long tj_finals(void *handle, const char *in, long size, char *out, long cap)
{
    const tj_names *h = handle;
    out_t o = {out, out + cap, 0};
    const char *p = in, *end = in + size;
    if (size == 0 || in[size - 1] != '\n')
        return -1;
    while (p < end) {
        const char *nl = memchr(p, '\n', (size_t)(end - p));
        tok_t t[8];
        int n = split_line(p, nl, t, 8);
        if (n < 0)
            return -1;
        long b = n == 8 && same(t[0], "F") ? index_of(t[1], h->count - 1) : -2;
        if (b < 0)
            return -1;
        if (p != in)
            PUTS(&o, ",");
        p = nl + 1;
        PUTS(&o, "{\"body\":");
        put(&o, h->name[b], h->len[b]);
        PUTS(&o, ",\"position\":[");
        if (!num(&o, t[2])) return -1;
        PUTS(&o, ",");
        if (!num(&o, t[3])) return -1;
        PUTS(&o, "],\"velocity\":[");
        if (!num(&o, t[4])) return -1;
        PUTS(&o, ",");
        if (!num(&o, t[5])) return -1;
        PUTS(&o, "],\"angle\":");
        if (!num(&o, t[6])) return -1;
        PUTS(&o, ",\"angular_velocity\":");
        if (!num(&o, t[7])) return -1;
        PUTS(&o, "}");
    }
    return o.full ? -2 : o.p - out;
}
