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

/* A compiled scene: the bodies' state at t = 0 and the settings. */
typedef struct m2c_sim_scene m2c_sim_scene;

/* Reads the flat scene in `text` (NUL-terminated).  Returns the scene, or
 * NULL with a message in err (as the reference words it) on a bad scene
 * or when out of memory. */
m2c_sim_scene *m2c_sim_scene_read(const char *text, char *err, size_t errlen);

void m2c_sim_scene_free(m2c_sim_scene *scene);

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
