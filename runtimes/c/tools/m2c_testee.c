/* Conformance testee: reads wire lines on stdin, answers on stdout.
 *   in:  roots SEQ LO HI COUNT C0 ... C(COUNT-1)   (doubles as 16 hex digits
 *        of their IEEE-754 bits)
 *   out: SEQ HEX | SEQ none | SEQ error MESSAGE
 * Argument --gsl answers with the GSL baseline instead. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "m2c_roots.h"

static double from_hex(const char *s)
{
    uint64_t u = strtoull(s, 0, 16);
    double d;
    memcpy(&d, &u, sizeof d);
    return d;
}

int main(int argc, char **argv)
{
    int gsl = argc > 1 && strcmp(argv[1], "--gsl") == 0;
    char op[32], seq[64], tok[32];
    while (scanf("%31s %63s", op, seq) == 2) {
        if (strcmp(op, "roots") != 0) {
            int ch;
            while ((ch = getchar()) != '\n' && ch != EOF) {
            }
            printf("%s error unknown-op\n", seq);
            continue;
        }
        double lo, hi, c[M2C_MAX_DEGREE + 1];
        int count;
        if (scanf("%31s", tok) != 1)
            return 2;
        lo = from_hex(tok);
        if (scanf("%31s", tok) != 1)
            return 2;
        hi = from_hex(tok);
        if (scanf("%d", &count) != 1)
            return 2;
        if (count < 0 || count > M2C_MAX_DEGREE + 1) {
            int ch;
            while ((ch = getchar()) != '\n' && ch != EOF) {
            }
            printf("%s error degree\n", seq);
            continue;
        }
        for (int i = 0; i < count; i++) {
            if (scanf("%31s", tok) != 1)
                return 2;
            c[i] = from_hex(tok);
        }
        double t = 0.0;
        int r;
        if (count == 0)
            r = 0;
        else
            r = gsl ? m2c_smallest_root_gsl(c, count - 1, lo, hi, &t)
                    : m2c_smallest_root(c, count - 1, lo, hi, &t);
        if (r == 1) {
            uint64_t u;
            memcpy(&u, &t, sizeof u);
            printf("%s %016" PRIx64 "\n", seq, u);
        } else if (r == 0) {
            printf("%s none\n", seq);
        } else {
            printf("%s error degree\n", seq);
        }
    }
    return 0;
}
