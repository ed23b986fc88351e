/* Box2D v3's b2TimeOfImpact for two bodies, each a ball or a convex polygon
 * moving with constant velocity and angular velocity, as driven by
 * bench/toi_shapes.py: the horizon is cut into 60 Hz steps (Box2D's sweep
 * interpolates one step's rotation), each step swept from the poses at its
 * ends; the first hit answers.
 *
 * stdin: "REPS" then one case per line: the horizon (s), then per body (A
 * then B): kind (0 ball, 1 polygon), the number of vertices n (0 for a
 * ball), the centre of rotation x, y (m) at t = 0, its velocity vx, vy
 * (m/s), the angle (rad) at t = 0, the angular velocity (rad/s), the ball's
 * radius (m; 0 for a polygon), then the n vertices x y (m, about the centre
 * of rotation, counter-clockwise).
 * stdout per case: "b2 A", A the time of impact, "none", "overlapped" (in
 * the first step) or "refused" (more than B2_MAX_POLYGON_VERTICES); when
 * REPS > 0 also "ns b2 X": the median of 15 batches of REPS queries, ns per
 * query. */
#define _POSIX_C_SOURCE 199309L
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "box2d/collision.h"
#include "box2d/math_functions.h"

#define STEP (1.0 / 60.0)       /* s */

typedef struct {
    double x, y, vx, vy, angle, omega;      /* m, m/s, rad, rad/s */
    b2ShapeProxy proxy;
} body;

static double now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e9 + (double)ts.tv_nsec;
}

static int cmpd(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* the body's sweep over [t0, t1] (s): its frame is its centre of rotation */
static b2Sweep sweep(const body *b, double t0, double t1)
{
    b2Sweep s;
    s.localCenter = (b2Vec2){0.0f, 0.0f};
    s.c1 = (b2Vec2){(float)(b->x + b->vx * t0), (float)(b->y + b->vy * t0)};
    s.c2 = (b2Vec2){(float)(b->x + b->vx * t1), (float)(b->y + b->vy * t1)};
    s.q1 = b2MakeRot((float)(b->angle + b->omega * t0));
    s.q2 = b2MakeRot((float)(b->angle + b->omega * t1));
    return s;
}

/* 1 and *t at the first hit, 2 overlapped in the first step, 0 none */
static int toi(const body *a, const body *b, double horizon, double *t)
{
    b2TOIInput in;
    in.proxyA = a->proxy;
    in.proxyB = b->proxy;
    in.maxFraction = 1.0f;
    for (double t0 = 0.0; t0 < horizon; t0 += STEP) {
        double t1 = t0 + STEP < horizon ? t0 + STEP : horizon;
        in.sweepA = sweep(a, t0, t1);
        in.sweepB = sweep(b, t0, t1);
        b2TOIOutput out = b2TimeOfImpact(&in);
        if (out.state == b2_toiStateOverlapped && t0 == 0.0)
            return 2;
        if (out.state == b2_toiStateHit || out.state == b2_toiStateOverlapped) {
            *t = t0 + (double)out.fraction * (t1 - t0);
            return 1;
        }
    }
    return 0;
}

/* one body from the case line; 0 when the line ends early or the polygon is too large */
static int read_body(body *b, int *refused)
{
    double kind, n, radius;
    if (scanf("%lf %lf %lf %lf %lf %lf %lf %lf %lf", &kind, &n, &b->x, &b->y, &b->vx, &b->vy, &b->angle,
              &b->omega, &radius) != 9)
        return 0;
    b2Vec2 pts[B2_MAX_POLYGON_VERTICES];
    int count = 0;
    for (int k = 0; k < (int)n; k++) {
        double x, y;
        if (scanf("%lf %lf", &x, &y) != 2)
            return 0;
        if (count < B2_MAX_POLYGON_VERTICES)
            pts[count++] = (b2Vec2){(float)x, (float)y};
        else
            *refused = 1;
    }
    if (kind == 0.0) {
        b2Vec2 origin = {0.0f, 0.0f};
        b->proxy = b2MakeProxy(&origin, 1, (float)radius);
    } else {
        b->proxy = b2MakeProxy(pts, count, 0.0f);
    }
    return 1;
}

int main(void)
{
    int reps = 0;
    double horizon;
    if (scanf("%d", &reps) != 1)
        return 1;
    while (scanf("%lf", &horizon) == 1) {
        body a, b;
        int refused = 0;
        if (!read_body(&a, &refused) || !read_body(&b, &refused))
            return 1;
        double t = 0.0;
        if (refused) {
            printf("b2 refused\n");
            continue;
        }
        int r = toi(&a, &b, horizon, &t);
        if (r == 1)
            printf("b2 %.17g\n", t);
        else
            printf("b2 %s\n", r == 2 ? "overlapped" : "none");
        if (reps > 0) {
            double ns[15], sink = 0.0;
            for (int k = 0; k < 15; k++) {
                double t0 = now_ns();
                for (int i = 0; i < reps; i++) {
                    double u = 0.0;
                    if (toi(&a, &b, horizon, &u) == 1)
                        sink += u;
                }
                ns[k] = (now_ns() - t0) / reps;
            }
            qsort(ns, 15, sizeof ns[0], cmpd);
            printf("ns b2 %.3f\n", ns[7]);
            if (sink == -1.0)
                fprintf(stderr, "checksum %g\n", sink);
        }
    }
    return 0;
}
