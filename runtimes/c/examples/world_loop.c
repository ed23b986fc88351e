/* A game loop on the live world (docs/engine-api.md, C): the compiled scene
 * in argv[1] is advanced frame by frame at 60 frames per second; each
 * contact is printed as it is handled, and body argv[2]'s exact state at
 * every 30th frame.  Build it against the libm2c_world.so that
 * max2code.sim.simulate.world_library(scene) makes beside the simulator of
 * the scene's effects:
 *
 *   cc -std=c11 -Iruntimes/c/include world_loop.c DIR/libm2c_world.so -Wl,-rpath,DIR -o world_loop
 *   ./world_loop scene.txt 0
 *
 * (scene.txt: the compiled scene, the text of
 * max2code.sim.scene.compile_scene(load_scene("SCENE.json")).) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "m2c_world.h"

static void on_contact(const m2c_contact *c, void *user)
{
    long *n = user;
    ++*n;
    printf("contact t=%.9f bodies %d %d feature %d impulse %.6g\n", c->t, c->a, c->b, c->feature, c->impulse);
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: %s COMPILED_SCENE BODY\n", argv[0]);
        return 2;
    }
    m2c_world *w = m2c_world_load(argv[1], NULL);   /* no trace */
    if (w == NULL) {
        fprintf(stderr, "%s\n", m2c_world_last_error());
        return 1;
    }
    int body = atoi(argv[2]);
    double end = m2c_world_end_time(w), dt = 1.0 / 60.0;
    long contacts = 0, idle = 0;
    for (long frame = 1;; frame++) {
        double t = fmin(frame * dt, end);
        /* a game would sleep until min(t, next event) here; count the frames it could idle through */
        if (m2c_world_next_event_time(w) >= t)
            idle++;
        if (m2c_world_advance(w, t, on_contact, &contacts) != 0) {
            fprintf(stderr, "%s\n", m2c_world_error(w));
            m2c_world_free(w);
            return 1;
        }
        m2c_body_state s;
        if (frame % 30 == 0 && m2c_world_state(w, body, t, &s) == 0)
            printf("frame %ld t=%.6f body %d at (%.9f, %.9f) v (%.9f, %.9f)\n", frame, t, body, s.x, s.y, s.vx, s.vy);
        if (t >= end)
            break;
    }
    if (m2c_world_finish(w, on_contact, &contacts) != 0) {
        fprintf(stderr, "%s\n", m2c_world_error(w));
        m2c_world_free(w);
        return 1;
    }
    printf("%ld contacts, %ld frames without an event\n", contacts, idle);
    m2c_world_free(w);
    return 0;
}
