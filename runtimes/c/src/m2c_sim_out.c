/* The trace writer: lines are formatted straight into one buffer that is
 * written out when less than a line's room is left (and at the end). */
#include <stdlib.h>

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
