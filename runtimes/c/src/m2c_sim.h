/* max2code C runtime: the discrete-event 2D collision simulator
 * (docs/simulator.md), a port of the Python reference
 * (runtimes/python/max2code_rt) that performs the same IEEE double
 * operations in the same order and so writes the same bytes.  This header
 * is what the simulator's program (tools/m2c_sim_main.c) uses besides the
 * world API: the scene reader and the trace's number writer.  Programs of
 * one's own include m2c_world.h (include/) instead.
 *
 * It reads a compiled scene (the flat text of max2code/sim/scene.py) and writes
 * the flat trace.  Every prediction goes through the generated entries of
 * equations/circle-circle.mxm and equations/point-edge.mxm (declared in
 * m2c_sim_equations.h, linked in from the generated .c files) and through
 * m2c_smallest_root.  Times in seconds, lengths in metres, angles in
 * radians. */
#ifndef M2C_SIM_H
#define M2C_SIM_H

#include <stddef.h>
#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

/* The limits of flat text (docs/simulator.md, "Flat scene checks"), the
 * same names and values in every runtime: bodies in a scene, vertices of
 * one polygon, scripted inputs, the largest and smallest length (m) and
 * the longest text (bytes).  Every count is checked against its limit
 * before anything is allocated for it. */
#define MAX_BODIES 1000000
#define MAX_VERTICES 1024
#define MAX_INPUTS 10000000
#define LENGTH_MAX 1e150
#define LENGTH_MIN 1e-150
#define TEXT_MAX 1073741824

/* A compiled scene: the bodies' state at t = 0 and the settings. */
typedef struct m2c_sim_scene m2c_sim_scene;

/* Reads the flat scene in `text` (NUL-terminated).  Returns the scene, or
 * NULL with a message in err (as the reference words it) on a bad scene
 * or when out of memory. */
m2c_sim_scene *m2c_sim_scene_read(const char *text, char *err, size_t errlen);

void m2c_sim_scene_free(m2c_sim_scene *scene);

/* The check of flat text's bytes (n of them at text): 0, or -1 with
 * "WHAT: longer than 1073741824 bytes" or "WHAT: byte N: not printable
 * ASCII" in err (what: "scene", "add_body").  The scene reader runs it on
 * its NUL-terminated text; a program that read n bytes (a NUL among them)
 * runs it on all n. */
int m2c_sim_text_check(const char *text, size_t n, const char *what, char *err, size_t errlen);

/* Running a scene: the world API of m2c_world.h. */

/* Writes x into buf exactly as C's printf("%.17g", x) and Python's
 * "%.17g" % x do (a NaN of either sign as "nan", like Python); returns the
 * length.  buf holds at least M2C_SIM_NUMBER_MAX bytes, all of which it may
 * write (past the length: scratch); no NUL is written. */
#define M2C_SIM_NUMBER_MAX 32
int m2c_sim_format_number(char *buf, double x);

/* A decimal number (w[0..n-1], no NUL needed) as strtod reads it: 1 with
 * *out, or 0 when it is one that strtod itself must read (the scene
 * reader's fast path, m2c_sim_scene.c). */
int m2c_sim_parse_number(const char *w, size_t n, double *out);

#ifdef __cplusplus
}
#endif

#endif
