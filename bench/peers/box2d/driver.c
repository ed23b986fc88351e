/* Box2D v3 driver of the side-by-side benchmark (max2code/reports/peers.py).
 *
 * Reads a scene in the peer format on stdin (written by peer_text in
 * peers.py: the step, the sub-steps, gravity, every body and the scripted
 * inputs), steps it with b2World_Step(dt, substeps) and writes after each
 * step one line "s T CPU" (the time reached and the CPU seconds of that step
 * alone, CLOCK_PROCESS_CPUTIME_ID around the call) and one line per body
 * "x y angle vx vy omega".  Circles never turn (angular motion locked), as in
 * the scene model; polygons get the scene's mass and moment of inertia;
 * restitution and friction combine by product (the world's mixing
 * callbacks); fixed bodies that move or turn are kinematic.  Everything else
 * is Box2D's default world (sleeping on, restitution threshold, contact
 * softness).  Compiled by the benchmark against the Box2D source it is given. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "box2d/box2d.h"

static double cpu_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

static void expect(const char *key) {
    char w[64];
    if (scanf("%63s", w) != 1 || strcmp(w, key) != 0) {
        fprintf(stderr, "peer scene: expected %s\n", key);
        exit(2);
    }
}

static double num(void) {
    double x;
    if (scanf("%lf", &x) != 1) {
        fprintf(stderr, "peer scene: expected a number\n");
        exit(2);
    }
    return x;
}

static long count(void) {
    long n;
    if (scanf("%ld", &n) != 1 || n < 0) {
        fprintf(stderr, "peer scene: expected a count\n");
        exit(2);
    }
    return n;
}

static float product(float a, uint64_t ida, float b, uint64_t idb) {
    (void)ida;
    (void)idb;
    return a * b;
}

typedef struct {
    double time, x, y;
    long body, mode;
} Input;

static int by_time(const void *a, const void *b) {
    double ta = ((const Input *)a)->time, tb = ((const Input *)b)->time;
    return (ta > tb) - (ta < tb);
}

int main(void) {
    expect("peer-scene");
    expect("end");
    double end = num();
    expect("dt");
    double dt = num();
    expect("substeps");
    int substeps = (int)count();
    expect("gravity");
    double gx = num(), gy = num();
    expect("bodies");
    long n = count();

    b2WorldDef wd = b2DefaultWorldDef();
    wd.gravity = (b2Vec2){(float)gx, (float)gy};
    wd.frictionCallback = product;
    wd.restitutionCallback = product;
    b2WorldId world = b2CreateWorld(&wd);
    b2BodyId *ids = calloc((size_t)n + 1, sizeof *ids);
    b2Vec2 *force = calloc((size_t)n + 1, sizeof *force);
    char *has_force = calloc((size_t)n + 1, 1), *removed = calloc((size_t)n + 1, 1);
    for (long i = 0; i < n; i++) {
        char kind[8];
        if (scanf("%7s", kind) != 1) exit(2);
        long role = count();            /* 0 movable, 1 fixed and still, 2 fixed and moving */
        double mass = num(), inertia = num();
        double px = num(), py = num(), vx = num(), vy = num(), ang = num(), om = num();
        double e = num(), mu = num(), ax = num(), ay = num();
        b2BodyDef bd = b2DefaultBodyDef();
        bd.type = role == 0 ? b2_dynamicBody : role == 1 ? b2_staticBody : b2_kinematicBody;
        bd.position = (b2Pos){px, py};
        bd.rotation = b2MakeRot((float)ang);
        bd.linearVelocity = (b2Vec2){(float)vx, (float)vy};
        bd.angularVelocity = (float)om;
        if (kind[0] == 'c') bd.motionLocks.angularZ = true;
        b2BodyId id = b2CreateBody(world, &bd);
        b2ShapeDef sd = b2DefaultShapeDef();
        sd.density = 0.0f;
        sd.updateBodyMass = false;
        sd.material.friction = (float)mu;
        sd.material.restitution = (float)e;
        if (kind[0] == 'c') {
            double r = num(), orad = num(), oang = num();
            b2Circle c = {{(float)(orad * cos(oang)), (float)(orad * sin(oang))}, (float)r};
            b2CreateCircleShape(id, &sd, &c);
        } else {
            long k = count();
            if (k > B2_MAX_POLYGON_VERTICES) {
                printf("X a polygon of %ld vertices (Box2D takes at most %d)\n", k, B2_MAX_POLYGON_VERTICES);
                return 3;
            }
            b2Vec2 pts[B2_MAX_POLYGON_VERTICES];
            for (long j = 0; j < k; j++) pts[j] = (b2Vec2){(float)num(), (float)num()};
            b2Hull hull = b2ComputeHull(pts, (int)k);
            if (hull.count == 0) {
                printf("X a polygon Box2D's hull refuses\n");
                return 3;
            }
            b2Polygon poly = b2MakePolygon(&hull, 0.0f);
            b2CreatePolygonShape(id, &sd, &poly);
        }
        if (role == 0) {
            b2MassData md = {(float)mass, {0.0f, 0.0f}, kind[0] == 'c' ? 1.0f : (float)inertia};
            b2Body_SetMassData(id, md);
            if (ax != gx || ay != gy) {
                has_force[i] = 1;
                force[i] = (b2Vec2){(float)((ax - gx) * mass), (float)((ay - gy) * mass)};
            }
        }
        ids[i] = id;
    }
    expect("inputs");
    long m = count();
    Input *in = calloc((size_t)m + 1, sizeof *in);
    for (long j = 0; j < m; j++) {
        in[j].time = num();
        in[j].body = count();
        in[j].mode = count();
        in[j].x = num();
        in[j].y = num();
    }
    qsort(in, (size_t)m, sizeof *in, by_time);

    static char buf[1 << 20];
    setvbuf(stdout, buf, _IOFBF, sizeof buf);
    long steps = (long)ceil(end / dt - 1e-9);
    long next = 0;
    for (long k = 0; k < steps; k++) {
        double now = (double)k * dt;
        while (next < m && in[next].time <= now + 1e-12 * dt) {
            Input *p = &in[next++];
            if (removed[p->body]) continue;
            b2BodyId id = ids[p->body];
            b2Vec2 v = {(float)p->x, (float)p->y};
            if (p->mode == 0) {
                b2Body_SetLinearVelocity(id, v);
            } else if (p->mode == 1) {
                b2Body_SetLinearVelocity(id, b2Add(b2Body_GetLinearVelocity(id), v));
            } else if (p->mode == 2) {
                b2Body_ApplyLinearImpulseToCenter(id, v, true);
            } else if (p->mode == 3) {
                b2Body_SetTransform(id, (b2Pos){p->x, p->y}, b2Body_GetRotation(id));
            } else {
                removed[p->body] = 1;
                b2DestroyBody(id);
            }
        }
        double c0 = cpu_seconds();
        for (long i = 0; i < n; i++)
            if (has_force[i] && !removed[i]) b2Body_ApplyForceToCenter(ids[i], force[i], false);
        b2World_Step(world, (float)dt, substeps);
        double c1 = cpu_seconds();
        printf("s %.17g %.17g\n", (double)(k + 1) * dt, c1 - c0);
        for (long i = 0; i < n; i++) {
            if (removed[i]) {
                puts("- - - - - -");
                continue;
            }
            b2Pos p = b2Body_GetPosition(ids[i]);
            b2Vec2 v = b2Body_GetLinearVelocity(ids[i]);
            printf("%.9g %.9g %.9g %.9g %.9g %.9g\n", (double)p.x, (double)p.y,
                   (double)b2Rot_GetAngle(b2Body_GetRotation(ids[i])), (double)v.x, (double)v.y,
                   (double)b2Body_GetAngularVelocity(ids[i]));
        }
    }
    fflush(stdout);
    b2DestroyWorld(world);
    return 0;
}
