/* max2code C runtime: the live world API (docs/engine-api.md), a port of
 * the Python reference's World (runtimes/python/max2code_rt/sim/).
 *
 * A world is a scene being simulated: advance it to any time, read the
 * exact state of any body between events, change velocities at the current
 * time.  It is built with the generated contact equations of its scene's
 * effects (max2code.sim.simulate.world_library builds it as libm2c_world.so
 * beside the simulator program).  Worlds share nothing: two may run at once (not one
 * from two threads at once).  Times in s, lengths in m, angles in rad,
 * velocities in m/s, impulses in kg m/s. */
#ifndef M2C_WORLD_H
#define M2C_WORLD_H

#include <stdio.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct m2c_world m2c_world;

/* One contact reported by m2c_world_advance: the fields of the trace's
 * E collision / E support line: bodies a and b (scene indices), the
 * feature (0 circle-circle: circle of a against the circle of b, j < 0, or
 * vertex j of b; 1 point-edge: circle of a, i < 0, or vertex i of a against
 * edge j of b), the contact point, the unit normal from a to b, the
 * impulse; support: 1 when the contact ended in support (a resting or
 * sliding body, E support), 0 for a collision. */
typedef struct m2c_contact {
    double t;
    int a, b, feature, i, j;
    double px, py, nx, ny, impulse;
    int support;
} m2c_contact;

typedef void (*m2c_contact_fn)(const m2c_contact *c, void *user);

/* A body's exact state at some time. */
typedef struct m2c_body_state {
    double x, y, vx, vy, angle, omega;
} m2c_body_state;

/* A world from a compiled scene (the flat text of max2code/sim/scene.py,
 * NUL-terminated) at t = 0; trace NULL: no trace, else the flat trace is
 * written there as events happen.  NULL on a bad scene or out of memory:
 * the message is then m2c_world_last_error()'s.  The text is checked as it
 * is read (docs/simulator.md, "Flat scene checks"): the first fault gives
 * "scene: ...", the same message as every runtime's. */
m2c_world *m2c_world_new(const char *scene_text, FILE *trace);
/* The same from a file holding the compiled scene. */
m2c_world *m2c_world_load(const char *path, FILE *trace);
/* The message of the last m2c_world_new or m2c_world_load that failed in
 * this thread. */
const char *m2c_world_last_error(void);
void m2c_world_free(m2c_world *w);

/* s: the time the world has reached. */
double m2c_world_time(const m2c_world *w);
int m2c_world_body_count(const m2c_world *w);
/* s: the scene's end time (no event after it). */
double m2c_world_end_time(const m2c_world *w);

/* Handles every event before time t, calling fn (when not NULL) for each
 * contact in order, and moves the world's time to t.  Events at exactly t
 * stay queued: an input made at t comes before them, as a scripted input
 * at t does.  0; -1 with the message in m2c_world_error(w) when t is
 * outside [the world's time, the scene's end] (the world is unchanged), or
 * when the scene is stuck or memory runs out (the world is then unusable
 * but for m2c_world_free). */
int m2c_world_advance(m2c_world *w, double t, m2c_contact_fn fn, void *user);

/* s: the time of the next event that is not stale (stale ones at the top
 * of the queue are dropped and counted as the run would), +inf when none
 * comes before the end. */
double m2c_world_next_event_time(m2c_world *w);

/* The exact state of body at time t, for t from the world's time to the
 * next event's: 0, or -1 with m2c_world_error(w) (no such body, t outside). */
int m2c_world_state(m2c_world *w, int body, double t, m2c_body_state *s);
/* Every body's state at time t at once (what a frame draws; one call
 * instead of one per body): s[k] for body k, k < m2c_world_body_count(w);
 * room: the entries s has.  0, or -1 with m2c_world_error(w) (room too
 * small, t outside as above). */
int m2c_world_states(m2c_world *w, double t, m2c_body_state *s, int room);

/* Handles the events at the end time (fn told of their contacts, as
 * m2c_world_advance), then writes the end of the trace: every body at the
 * end time, the counters and the predictions per variant (what the batch
 * simulator writes last).  0, or -1 with m2c_world_error(w). */
int m2c_world_finish(m2c_world *w, m2c_contact_fn fn, void *user);

/* Live inputs, at the world's time T (docs/engine-api.md, "Live inputs"):
 * handled as the same input scripted at T and listed after the scene's
 * would be (the scene's inputs at T first, then this one, before any other
 * event at T), and appended to the world's input list: the recording.
 * Movable bodies only, but set_velocity also on a fixed polygon that does
 * not turn (a moving platform: docs/engine-api.md).  0, or -1 with
 * m2c_world_error(w), the world unchanged: "live input: the world is
 * finished" (after m2c_world_finish), "live input: body N does not exist",
 * a removed body, another input on a fixed body, "live input: body N:
 * velocity would not be finite" (the body's velocity after the input),
 * "... position would not be finite" (a teleport to a point that is not
 * finite) or "... teleport beyond 1e150 m"; or -1 on a
 * failure (the world unusable).  Velocities in m/s; an impulse in N s
 * through the centre (dv = J / mass). */
int m2c_world_set_velocity(m2c_world *w, int body, double vx, double vy);
int m2c_world_add_velocity(m2c_world *w, int body, double dvx, double dvy);
int m2c_world_apply_impulse(m2c_world *w, int body, double jx, double jy);
/* Moves the body's centre to (x, y) now, keeping its velocity: 1; 0 (the
 * world unchanged) when it would overlap another body there by more than
 * the tolerance; -1 as above, and (the world unchanged) "live input: body
 * N: teleport beyond 1e150 m" when |x| + |y| > 1e150. */
int m2c_world_teleport(m2c_world *w, int body, double x, double y);

/* Takes a body (movable or fixed) out of the world now: an input (MODE 4)
 * like the others, so recorded.  It stops where it is, is never predicted
 * again, and bodies resting on it leave.  0, or -1 as above. */
int m2c_world_remove_body(m2c_world *w, int body);
/* Adds a body given as its flat lines (max2code/sim/scene.py body_lines:
 * `body ...` and its `v` lines, the state at the world's time) now.  Its
 * index (the next one); -1 when it would overlap a body by more than the
 * tolerance (the world unchanged); -2 with m2c_world_error(w) on a bad text
 * (the world unchanged: the scene's checks of a body, "add_body: ...",
 * with the scene's tolerance and end time, an edge's cover one of the
 * world's bodies), after m2c_world_finish ("live input: the world is
 * finished", the world unchanged) or on a failure.  Not an input: a
 * recording refuses a session that added bodies. */
int m2c_world_add_body(m2c_world *w, const char *body_text);

/* Recordings (docs/engine-api.md): the world's input log, the scene's
 * inputs then the live ones in the order they were made (what
 * max2code/sim/recording.py writes as a scene); mode 0 set velocity, 1 add
 * velocity, 2 impulse, 3 teleport, 4 remove (x, y 0). */
typedef struct m2c_input {
    double t;
    int body, mode;
    double x, y;
} m2c_input;

int m2c_world_input_count(const m2c_world *w);
/* Input k of the log: 0, or -1 when there is no input k. */
int m2c_world_input(const m2c_world *w, int k, m2c_input *in);
/* How many bodies add_body added (a recording refuses such a session). */
long long m2c_world_added(const m2c_world *w);

/* The last error of this world ("" when none). */
const char *m2c_world_error(const m2c_world *w);

#ifdef __cplusplus
}
#endif

#endif
