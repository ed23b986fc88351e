/* max2code C runtime: time of impact of two bodies (a circle or a convex
 * polygon each), with no world: the first contact within a horizon of two
 * bodies moving as the simulator moves them (docs/toi.md).  The pair
 * computation is the simulator's own (its predictions call this code):
 * bounding circles that do not turn first, clear stretches, then Taylor
 * windows of the generated circle_circle and point_edge polynomials.
 *
 * Units: s, m, m/s, m/s^2, rad, rad/s.  Angles count counter-clockwise.
 *
 *   m2c_toi_shape a, b;
 *   m2c_toi_circle(&a, 0.5);
 *   const double box[8] = { -1, -1, 1, -1, 1, 1, -1, 1 };
 *   m2c_toi_polygon(&b, box, 4);
 *   m2c_toi_motion ma = { .x = -3, .vx = 2 }, mb = { .omega = 1 };
 *   m2c_toi_result r;
 *   if (m2c_toi(&a, &ma, &b, &mb, 5.0, NULL, &r) == M2C_TOI_HIT) ... r.t, r.px, r.py, r.nx, r.ny
 *
 * The library calls the generated circle_circle and point_edge entries
 * (with every effect: acceleration and orbit) and is built with them: the
 * simulator's shared library of those effects exports m2c_toi
 * (max2code/toolchain/toi.py, c_library; docs/toi.md). */
#ifndef M2C_TOI_H
#define M2C_TOI_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Most vertices of a polygon shape. */
#define M2C_TOI_MAX_VERTICES 64

/* One vertex of a polygon and the edge from it to the next vertex, in the
 * body's frame (about its centre of rotation), made by m2c_toi_polygon. */
typedef struct m2c_toi_vertex {
    double lx, ly;          /* m: the vertex about the centre of rotation */
    double rho, beta;       /* m, rad: its polar form */
    double psi;             /* rad: angle of the edge's outward normal */
    double h;               /* m: offset of the edge's line, n . v */
    double s1, s2;          /* m: the edge's extent along its tangent (-ny, nx) */
    double nx, ny;          /* the edge's outward unit normal */
    int32_t cover;          /* the simulator's covering body of the edge, -1: none (always -1 here) */
} m2c_toi_vertex;

/* A body's shape: a circle (nverts 0) or a convex polygon. */
typedef struct m2c_toi_shape {
    int32_t nverts;         /* 0: circle */
    double radius;          /* m: circle radius (0 for a polygon) */
    double bound;           /* m: radius of the bounding circle about the centre of rotation */
    m2c_toi_vertex verts[M2C_TOI_MAX_VERTICES];
} m2c_toi_shape;

/* A body's motion, at time 0 of the query: its centre (of rotation) moves
 * as p + v t + a t^2/2, its angle as angle + omega t.  A circle may orbit
 * its centre: its own centre is then p + orbit (cos(angle + orbit_phase),
 * sin(angle + orbit_phase)), turning with omega. */
typedef struct m2c_toi_motion {
    double x, y;            /* m: centre of rotation */
    double vx, vy;          /* m/s */
    double ax, ay;          /* m/s^2 */
    double angle;           /* rad */
    double omega;           /* rad/s */
    double orbit;           /* m: orbit radius of a circle's centre (0: none; polygons: 0) */
    double orbit_phase;     /* rad: the orbit's phase relative to angle */
} m2c_toi_motion;

/* Options; m2c_toi_defaults fills the defaults. */
typedef struct m2c_toi_options {
    double tol;             /* m: distance tolerance of contacts (default 1e-9) */
    int taylor_order;       /* the Taylor order the generated polynomials were made with (default 4) */
} m2c_toi_options;

void m2c_toi_defaults(m2c_toi_options *o);

/* status of m2c_toi */
enum { M2C_TOI_ERROR = -1, M2C_TOI_NONE = 0, M2C_TOI_HIT = 1, M2C_TOI_OVERLAPPED = 2 };

/* feature of a contact */
enum {
    M2C_TOI_CC = 0,         /* circle (or circle's centre) against a circle or a vertex: i -1, j the vertex or -1 */
    M2C_TOI_PE = 1          /* a circle (i -1) or vertex i of one body against edge j of the other */
};

/* The answer of m2c_toi. */
typedef struct m2c_toi_result {
    int status;             /* M2C_TOI_HIT, M2C_TOI_NONE, M2C_TOI_OVERLAPPED, M2C_TOI_ERROR */
    double t;               /* s: contact time (0 when overlapped) */
    int feature;            /* M2C_TOI_CC or M2C_TOI_PE */
    int first;              /* 0: i is body A's feature and j body B's; 1: i is B's and j A's */
    int32_t i, j;           /* vertex i (-1: the circle) against edge or vertex j (-1: the circle) */
    double px, py;          /* m: contact point at t */
    double nx, ny;          /* unit normal at t, from the body holding i to the other */
} m2c_toi_result;

/* The first contact of bodies A and B within [0, horizon] s: M2C_TOI_HIT
 * with *r filled, M2C_TOI_NONE, M2C_TOI_OVERLAPPED when they overlap at
 * t = 0 by more than the tolerance (r->t 0), or M2C_TOI_ERROR (a non-finite
 * number, a negative horizon, an orbit on a polygon, bad options, more
 * than 10^7 steps).  Contacts are found to within the tolerance (docs/toi.md). */
int m2c_toi(const m2c_toi_shape *a, const m2c_toi_motion *ma, const m2c_toi_shape *b, const m2c_toi_motion *mb,
            double horizon, const m2c_toi_options *o, m2c_toi_result *r);

/* A circle of radius m (> 0): 0, or -1 when the radius is not positive and finite. */
int m2c_toi_circle(m2c_toi_shape *s, double radius);

/* A convex polygon of n (3..M2C_TOI_MAX_VERTICES) vertices xy[2k], xy[2k+1]
 * (m, about the centre of rotation, counter-clockwise): 0, or -1 when the
 * count is out of range, a number is not finite or an edge has length 0. */
int m2c_toi_polygon(m2c_toi_shape *s, const double *xy, int n);

#ifdef __cplusplus
}
#endif

#endif
