/* Support (docs/simulator.md, "Contact model: supported, sliding,
 * friction"): a movable body resting and sliding on an edge of a fixed
 * polygon, with Coulomb friction, or carried at rest on a movable polygon
 * that does not turn ("Contact model: carried bodies"); their stop and
 * leave events, and leaving.  A supported or carried body's motion stays
 * p + v dt + a dt^2/2, so every generated equation predicts it unchanged.
 * Units: m, m/s, m/s^2. */
#include <math.h>
#include <stdlib.h>

#include "m2c_roots.h"
#include "m2c_sim_internal.h"

/* ---- support: resting and sliding on a fixed body ---------------------------- */

/* Unit tangent (tx, ty) and outward unit normal (ox, oy) of edge j of B in
 * the world (B does not turn). */
void m2c_sim_support_frame(const m2c_sim_body *B, int32_t j, double *tx, double *ty, double *ox, double *oy)
{
    const m2c_sim_vertex *ed = &B->verts[j];
    double c = cos(B->ang);
    double s = sin(B->ang);
    *ox = c * ed->nx - s * ed->ny;
    *oy = s * ed->nx + c * ed->ny;
    *tx = -*oy;
    *ty = *ox;
}

/* A neighbour of A's vertex i lies on edge j's line within the face
 * tolerance max(tol, rest_speed^2 / load): A rests on a face. */
int m2c_sim_flat(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t i, int32_t j, double ox,
                 double oy, double load)
{
    double tol = m->s->tol, rest = m->s->rest_speed;
    double q = rest * rest / load;
    double ftol = q > tol ? q : tol;                                /* Python's max(tol, q) */
    int32_t n = A->nverts;
    double h = B->verts[j].h;
    const int32_t ks[2] = { (i + n - 1) % n, (i + 1) % n };
    for (int l = 0; l < 2; l++) {
        double px, py;
        m2c_sim_point_at(m, A, &A->verts[ks[l]], A->tb, &px, &py);
        if ((px - B->px) * ox + (py - B->py) * oy - h <= ftol)
            return 1;
    }
    return 0;
}

static int supportable(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t i, int32_t j,
                       double vn);

/* A point-edge contact of movable A on edge j of a fixed polygon B that
 * does not turn (it may translate) becomes support, everything relative to
 * B (docs/simulator.md, Contact model); both advanced. */
int m2c_sim_can_support(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                        int32_t j, double vn)
{
    if (feature != M2C_SIM_PE || A->fixed || !B->fixed || B->om != 0.0)
        return 0;
    return supportable(m, A, B, i, j, vn);
}

/* Acceleration along an edge of a body sliding at u relative to it: the
 * free part at less Coulomb friction f (mu times the load) against the
 * motion; at relative rest none while static friction holds. */
static double friction_accel(double at, double f, double u)
{
    if (u > 0.0)
        return at - f;
    if (u < 0.0)
        return at + f;
    if (at > f)
        return at - f;
    if (at < -f)
        return at + f;
    return 0.0;
}

/* Sleeping base B (at rest on edge frame (B.tx, B.ty) of fixed body B.rest)
 * stays at rest under its free acceleration, the force (px, py) and the
 * force of each body supported on it (by index, its reaction -m (a - fa)):
 * the resting contact's normal force n = -(mB faB + P) . o is positive and
 * its tangential force t = -(mB faB + P) . t lies within static friction,
 * |t| <= mu n. */
int m2c_sim_base_holds(const m2c_world *m, const m2c_sim_body *B, double px, double py)
{
    if (B->carry > 0)
        for (int32_t k = 0; k < m->s->nbodies; k++) {
            const m2c_sim_body *R = &m->bodies[k];
            if (R->sup == B->idx) {
                px = px - (R->ax - R->fax) / R->inv_m;
                py = py - (R->ay - R->fay) / R->inv_m;
            }
        }
    double mB = 1.0 / B->inv_m;
    double fx = mB * B->fax + px;
    double fy = mB * B->fay + py;
    double n = -(fx * B->ty - fy * B->tx);
    double t = -(fx * B->tx + fy * B->ty);
    double f = B->mu * m->bodies[B->rest].mu * n;
    return n > 0.0 && !(t > f) && !(t < -f);
}

/* A point-edge contact of movable A on edge j of a sleeping polygon B that
 * fell asleep supported on a fixed body (B.rest) becomes support on B, as
 * on a fixed body that does not move (docs/simulator.md, "Sliding on a
 * sleeping base"), when B's resting contact holds the force A's sliding
 * puts on B besides B's other riders (base_holds). */
int m2c_sim_can_ride(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                     int32_t j, double vn)
{
    if (feature != M2C_SIM_PE || A->fixed || !B->asleep || B->rest < 0 || !B->polygon)
        return 0;
    if (!supportable(m, A, B, i, j, vn))
        return 0;
    double tx, ty, ox, oy;
    m2c_sim_support_frame(B, j, &tx, &ty, &ox, &oy);
    double u = A->vx * tx + A->vy * ty;
    double a = friction_accel(A->fax * tx + A->fay * ty, A->mu * B->mu * -(A->fax * ox + A->fay * oy), u);
    return m2c_sim_base_holds(m, B, -(a * tx - A->fax) / A->inv_m, -(a * ty - A->fay) / A->inv_m);
}

/* The checks of can_support after the bodies' kinds: pressed onto edge j,
 * slow, over the edge and not leaving it, a polygon flat on it. */
static int supportable(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t i, int32_t j, double vn)
{
    double tx, ty, ox, oy;
    m2c_sim_support_frame(B, j, &tx, &ty, &ox, &oy);
    double load = -((A->fax - B->ax) * ox + (A->fay - B->ay) * oy);
    double rest = m->s->rest_speed;
    if (!(load > 0.0) || vn >= rest || A->e * B->e * -vn >= rest)
        return 0;
    const m2c_sim_vertex *ed = &B->verts[j];
    double q = (A->px - B->px) * tx + (A->py - B->py) * ty;
    if (q < ed->s1 || q > ed->s2)
        return 0;
    /* at an end of the edge (within the tolerance) and moving past it: it
     * is leaving (a support would end at once, again and again) */
    double u = (A->vx - B->vx) * tx + (A->vy - B->vy) * ty;
    double tol = m->s->tol;
    if ((u > 0.0 && q >= ed->s2 - tol) || (u < 0.0 && q <= ed->s1 + tol))
        return 0;
    if (A->polygon) {
        if (fabs(A->om) * A->bound >= rest)
            return 0;
        return m2c_sim_flat(m, A, B, i, j, ox, oy, load);
    }
    return 1;
}

/* Acceleration of supported A with tangential speed u relative to its
 * support B: the relative free acceleration along the edge less Coulomb
 * friction mu |a_n| against the relative motion; at relative rest, none
 * while friction can hold it; plus B's acceleration when B moves. */
void m2c_sim_slide_accel(const m2c_world *m, m2c_sim_body *A, double u)
{
    const m2c_sim_body *B = &m->bodies[A->sup];
    double a = friction_accel(A->at, A->mu * B->mu * A->load, u);
    if (m2c_sim_is_static(B)) {
        A->ax = a * A->tx;
        A->ay = a * A->ty;
    } else {
        A->ax = B->ax + a * A->tx;
        A->ay = B->ay + a * A->ty;
    }
}

/* A (advanced to now, as B) keeps only its velocity relative to B along
 * the edge, stops turning, and from now on accelerates relative to B along
 * the edge only. */
void m2c_sim_enter_support(const m2c_world *m, m2c_sim_body *A, const m2c_sim_body *B, int32_t j)
{
    double tx, ty, ox, oy;
    m2c_sim_support_frame(B, j, &tx, &ty, &ox, &oy);
    double u = (A->vx - B->vx) * tx + (A->vy - B->vy) * ty;
    if (m2c_sim_is_static(B)) {
        A->vx = u * tx;
        A->vy = u * ty;
    } else {
        A->vx = B->vx + u * tx;
        A->vy = B->vy + u * ty;
    }
    if (A->polygon)
        A->om = 0.0;
    A->sup = B->idx;
    A->sup_edge = j;
    A->tx = tx;
    A->ty = ty;
    A->load = -((A->fax - B->ax) * ox + (A->fay - B->ay) * oy);
    A->at = (A->fax - B->ax) * tx + (A->fay - B->ay) * ty;
    if (!B->fixed)
        m->bodies[B->idx].carry++;      /* a sleeping base counts what it supports */
    m2c_sim_slide_accel(m, A, u);
}

/* A's support (or carrier) ends: its free acceleration again. */
void m2c_sim_end_support(m2c_world *m, m2c_sim_body *A)
{
    m2c_sim_body *B = &m->bodies[A->sup];
    if (!B->fixed)
        B->carry--;
    A->ax = A->fax;
    A->ay = A->fay;
    A->sup = -1;
    A->sup_edge = -1;
}

/* ---- carried: at rest on a movable body that does not turn ------------------- */

/* A point-edge contact of movable A on edge j of a movable polygon B that
 * does not turn and is itself supported or carried (its motion a
 * polynomial: constant acceleration) becomes carrying (docs/simulator.md,
 * "Carried bodies"); both advanced.  As can_support, everything relative
 * to B: load = -((fa - aB) . o) > 0, slow (vn < rest_speed, eA eB (-vn) <
 * rest_speed), A's centre over the edge; and A at relative rest along it
 * (u = (vA - vB) . t, u^2 < rest_speed^2) where static friction holds it
 * (|at| <= muA muB load, at = (fa - aB) . t), B not carried by A (no loop),
 * and |vB|^2 <= |vA|^2: taking B's velocity never raises A's kinetic
 * energy.  A polygon also turns slower than rest_speed / bound and lies on
 * a face (flat). */
int m2c_sim_can_carry(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i,
                      int32_t j, double vn)
{
    if (feature != M2C_SIM_PE || A->fixed || B->fixed || !B->polygon || B->om != 0.0 || B->sup < 0)
        return 0;
    for (int32_t k = B->sup; k >= 0; k = m->bodies[k].sup)
        if (k == A->idx)
            return 0;
    double tx, ty, ox, oy;
    m2c_sim_support_frame(B, j, &tx, &ty, &ox, &oy);
    double load = -((A->fax - B->ax) * ox + (A->fay - B->ay) * oy);
    double rest = m->s->rest_speed;
    if (!(load > 0.0) || vn >= rest || A->e * B->e * -vn >= rest)
        return 0;
    const m2c_sim_vertex *ed = &B->verts[j];
    double q = (A->px - B->px) * tx + (A->py - B->py) * ty;
    if (q < ed->s1 || q > ed->s2)
        return 0;
    double u = (A->vx - B->vx) * tx + (A->vy - B->vy) * ty;
    if (!(u * u < rest * rest))
        return 0;
    double at = (A->fax - B->ax) * tx + (A->fay - B->ay) * ty;
    double f = A->mu * B->mu * load;
    if (at > f || at < -f)
        return 0;
    if (B->vx * B->vx + B->vy * B->vy > A->vx * A->vx + A->vy * A->vy)
        return 0;
    if (A->polygon) {
        if (fabs(A->om) * A->bound >= rest)
            return 0;
        return m2c_sim_flat(m, A, B, i, j, ox, oy, load);
    }
    return 1;
}

/* A (advanced to now, as B) moves with B from now on: B's velocity and
 * acceleration exactly (its offset from B constant), no turn. */
void m2c_sim_enter_carried(m2c_sim_body *A, m2c_sim_body *B, int32_t j)
{
    double tx, ty, ox, oy;
    m2c_sim_support_frame(B, j, &tx, &ty, &ox, &oy);
    A->vx = B->vx;
    A->vy = B->vy;
    if (A->polygon)
        A->om = 0.0;
    A->sup = B->idx;
    A->sup_edge = j;
    A->tx = tx;
    A->ty = ty;
    A->load = -((A->fax - B->ax) * ox + (A->fay - B->ay) * oy);
    A->at = (A->fax - B->ax) * tx + (A->fay - B->ay) * ty;
    A->ax = B->ax;
    A->ay = B->ay;
    B->carry++;
}

/* ---- a supported body's stop and leave events --------------------------------- */

/* The first u in [lo, hi] (s) where p + v u + a u^2 / 2 crosses zero
 * moving in the direction (+1 up, -1 down): 1 with *out, or 0. */
static int first_crossing(double p, double v, double a, int direction, double lo, double hi, double *out)
{
    double c[3] = { p, v, 0.5 * a };
    for (int it = 0; it < 3; it++) {
        double u;
        if (m2c_smallest_root(c, 2, lo, hi, &u) != 1)
            return 0;
        if ((v + a * u) * (double)direction > 0.0) {
            *out = u;
            return 1;
        }
        lo = u;
    }
    return 0;
}

/* Supported b's motion relative to its support B along the edge, at b's
 * time: q (m) the centre's coordinate along the tangent from B's centre,
 * u (m/s), a (m/s^2) its speed and acceleration. */
void m2c_sim_support_relative(const m2c_world *m, const m2c_sim_body *b, double *q, double *u, double *a)
{
    const m2c_sim_body *B = &m->bodies[b->sup];
    m2c_sim_motion sb = m2c_sim_state_at(B, b->tb);
    *q = (b->px - sb.x) * b->tx + (b->py - sb.y) * b->ty;
    *u = (b->vx - sb.vx) * b->tx + (b->vy - sb.vy) * b->ty;
    *a = (b->ax - B->ax) * b->tx + (b->ay - B->ay) * b->ty;
}

/* A supported body's stop (its tangential speed relative to the support
 * reaches zero) and leave (its centre, projected on the edge, reaches an
 * end) events. */
void m2c_sim_schedule_support(m2c_world *m, const m2c_sim_body *b)
{
    double q, u, a;
    m2c_sim_support_relative(m, b, &q, &u, &a);
    if (u != 0.0 && a != 0.0 && (u > 0.0) != (a > 0.0))
        m2c_sim_push_stop(m, b->tb + -u / a, b);
    const m2c_sim_vertex *ed = &m->bodies[b->sup].verts[b->sup_edge];
    double hi = m->s->end - b->tb;
    double s1 = 0.0, s2 = 0.0;
    int h2 = first_crossing(q - ed->s2, u, a, 1, 0.0, hi, &s2);
    int h1 = first_crossing(q - ed->s1, u, a, -1, 0.0, hi, &s1);
    if (h1 && (!h2 || s1 < s2)) {
        s2 = s1;
        h2 = 1;
    }
    if (h2)
        m2c_sim_push_leave(m, b->tb + s2, b);
}

/* ---- leaving: a support or carrier ends -------------------------------------- */

static void left_push(m2c_world *m, m2c_sim_left *l, int32_t body, int32_t skip)
{
    if (l->n == l->cap) {
        int32_t cap = l->cap ? 2 * l->cap : 8;
        int32_t *b = realloc(l->body, (size_t)cap * sizeof *b);
        if (b == NULL)
            m2c_sim_die(m, "out of memory");
        l->body = b;
        int32_t *k = realloc(l->skip, (size_t)cap * sizeof *k);
        if (k == NULL)
            m2c_sim_die(m, "out of memory");
        l->skip = k;
        l->cap = cap;
    }
    l->body[l->n] = body;
    l->skip[l->n] = skip;
    l->n++;
}

/* A leaves its support or carrier at t (E leave, its state: world velocity
 * kept, free acceleration), then what A carries, depth-first (release);
 * each appended to left with the body its prediction skips
 * (predict_released). */
void m2c_sim_leave(m2c_world *m, m2c_sim_body *A, double t, const m2c_sim_body *skip, m2c_sim_left *left)
{
    m->stats.leaves++;
    m2c_sim_rebase(A, t);
    int32_t sup = A->sup, edge = A->sup_edge;
    m2c_sim_end_support(m, A);
    m->stamp[A->idx]++;
    m2c_sim_emit_support_change(m, "E leave ", t, A, sup, edge);
    m2c_sim_emit_state(m, A);
    left_push(m, left, A->idx, skip == NULL ? -1 : skip->idx);
    m2c_sim_release(m, A, t, left);
}

/* B's motion changes at t: every body B carries leaves (by index, each with
 * what it carries: leave), skipping B in its prediction. */
void m2c_sim_release(m2c_world *m, const m2c_sim_body *B, double t, m2c_sim_left *left)
{
    if (B->carry == 0)
        return;
    for (int32_t k = 0; k < m->s->nbodies; k++) {
        m2c_sim_body *A = &m->bodies[k];
        if (A->sup == B->idx)
            m2c_sim_leave(m, A, t, B, left);
    }
}

/* Predict the bodies that left (leave), in the order they left, each but
 * against the body it skips (already predicted with it); frees the list. */
void m2c_sim_predict_released(m2c_world *m, m2c_sim_left *left, double t)
{
    for (int32_t k = 0; k < left->n; k++)
        m2c_sim_predict_body(m, &m->bodies[left->body[k]], t, left->skip[k] < 0 ? NULL : &m->bodies[left->skip[k]]);
    free(left->body);
    free(left->skip);
    left->body = left->skip = NULL;
    left->n = left->cap = 0;
}
