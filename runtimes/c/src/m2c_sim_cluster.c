/* Simultaneous contacts (docs/simulator.md, "Contact model: simultaneous
 * contacts"): a contact met again at the instant it was handled is solved
 * together with the contacts handled at that instant that reach it, by
 * sequential impulses that never add kinetic energy; sleepers the solve
 * would jolt wake, and bodies slow enough after it fall asleep.  Units:
 * m/s, kg m/s (impulses), J (energies). */
#include <math.h>
#include <stdlib.h>

#include "m2c_sim_internal.h"

/* how many times one contact is handled at one instant before it and the
 * contacts it touches are solved together; the most sweeps of the cluster's
 * sequential impulses, and the sweep that ends them: no impulse in it
 * changed a normal speed by more than CLUSTER_TOL rest_speed */
#define CLUSTER_REPEATS 64
/* a contact met CLUSTER_REPEATS + CLUSTER_JAM times at one instant (its
 * cluster solved CLUSTER_JAM times there and met again) jams its cluster: the
 * movers come to rest and fall asleep, held until the instant ends */
#define CLUSTER_JAM 4
#define CLUSTER_SWEEPS 100
#define CLUSTER_TOL 1e-9
/* the separation speed (times rest_speed) of a cluster's contact that nothing
 * presses: above the rounding of a normal speed, so that it is not met again at once */
#define CLUSTER_APART 0x1p-20
/* the angle (rad) within which one push holds a free acceleration (wedged) */
#define HOLD_TOL 1e-9
/* a body's part in a cluster's solve: held (fixed, or asleep: infinite mass),
 * free, or sliding on a fixed body's edge (moves along the edge only) */
enum { HELD = 0, FREE = 1, SLIDER = 2 };

/* Count a contact handled at t (an E collision or E support line). */
void m2c_sim_count_touch(m2c_world *m, double t, int32_t a, int32_t b, int32_t feature, int32_t i, int32_t j)
{
    if (t != m->touched_t) {
        m->touched_t = t;
        m->ntouched = 0;
    }
    for (int32_t k = 0; k < m->ntouched; k++) {
        m2c_sim_touch *c = &m->touched[k];
        if (c->a == a && c->b == b && c->feature == feature && c->i == i && c->j == j) {
            c->times++;
            return;
        }
    }
    if (m->ntouched == m->touched_cap) {
        int32_t cap = m->touched_cap ? 2 * m->touched_cap : 16;
        m2c_sim_touch *more = realloc(m->touched, (size_t)cap * sizeof *more);
        if (more == NULL)
            m2c_sim_die(m, "out of memory");
        m->touched = more;
        m->touched_cap = cap;
    }
    m->touched[m->ntouched++] = (m2c_sim_touch){ a, b, feature, i, j, 1 };
}

/* How many times the collision's contact was handled at this instant. */
static long long jam_count(const m2c_world *m, const m2c_sim_event *ev)
{
    if (ev->t != m->touched_t)
        return 0;
    for (int32_t k = 0; k < m->ntouched; k++) {
        const m2c_sim_touch *c = &m->touched[k];
        if (c->a == ev->u.collision.a && c->b == ev->u.collision.b && c->feature == ev->u.collision.feature
            && c->i == ev->u.collision.i && c->j == ev->u.collision.j)
            return c->times;
    }
    return 0;
}

/* A sleeper a jam put to sleep at the current instant: no touch wakes it
 * before the instant ends. */
int m2c_sim_held_now(const m2c_world *m, const m2c_sim_body *S)
{
    if (m->jammed_t != m->last_t)
        return 0;
    for (int32_t k = 0; k < m->njammed; k++)
        if (m->jammed[k] == S->idx)
            return 1;
    return 0;
}

/* The collision's contact (a, b, feature, i, j) was handled
 * CLUSTER_REPEATS times already at this instant: other contacts keep
 * undoing its impulse (a settling pile meets one contact up to 32 times at
 * one instant and goes on: ball-pit.json). */
int m2c_sim_repeated(const m2c_world *m, const m2c_sim_event *ev)
{
    if (ev->t != m->touched_t)
        return 0;
    for (int32_t k = 0; k < m->ntouched; k++) {
        const m2c_sim_touch *c = &m->touched[k];
        if (c->a == ev->u.collision.a && c->b == ev->u.collision.b && c->feature == ev->u.collision.feature
            && c->i == ev->u.collision.i && c->j == ev->u.collision.j)
            return c->times >= CLUSTER_REPEATS;
    }
    return 0;
}

/* A body that links a cluster's contacts: movable and awake (fixed bodies
 * and sleepers are held: the cluster ends at them). */
static inline int joins(const m2c_sim_body *b)
{
    return !b->fixed && !b->asleep;
}

/* Room in the cluster's scratch for n contacts and nb bodies. */
static void cluster_room(m2c_world *m, int32_t n, int32_t nb)
{
    m2c_sim_cluster *c = &m->clu;
    if (n > c->cap) {
        int32_t cap = c->cap ? c->cap : 8;
        while (cap < n)
            cap *= 2;
        m2c_sim_row *rows = realloc(c->rows, (size_t)cap * sizeof *rows);
        if (rows != NULL)
            c->rows = rows;
        double *acc = realloc(c->acc, (size_t)cap * sizeof *acc);
        if (acc != NULL)
            c->acc = acc;
        double *acc2 = realloc(c->acc2, (size_t)cap * sizeof *acc2);
        if (acc2 != NULL)
            c->acc2 = acc2;
        double *target = realloc(c->target, (size_t)cap * sizeof *target);
        if (target != NULL)
            c->target = target;
        double *pushes = realloc(c->pushes, (size_t)(cap + 1) * 4 * sizeof *pushes);
        if (pushes != NULL)
            c->pushes = pushes;
        if (rows == NULL || acc == NULL || acc2 == NULL || target == NULL || pushes == NULL)
            m2c_sim_die(m, "out of memory");
        c->cap = cap;
    }
    if (nb > c->bcap) {
        int32_t cap = c->bcap ? c->bcap : 16;
        while (cap < nb)
            cap *= 2;
        int32_t *inside = realloc(c->inside, (size_t)cap * sizeof *inside);
        if (inside != NULL)
            c->inside = inside;
        m2c_sim_body **movers = realloc(c->movers, (size_t)cap * sizeof *movers);
        if (movers != NULL)
            c->movers = movers;
        m2c_sim_body **done = realloc(c->done, (size_t)cap * sizeof *done);
        if (done != NULL)
            c->done = done;
        double *saved = realloc(c->saved, (size_t)cap * 3 * sizeof *saved);
        if (saved != NULL)
            c->saved = saved;
        double *v2 = realloc(c->v2, (size_t)cap * 3 * sizeof *v2);
        if (v2 != NULL)
            c->v2 = v2;
        double *vs = realloc(c->vs, (size_t)cap * 3 * sizeof *vs);
        if (vs != NULL)
            c->vs = vs;
        if (inside == NULL || movers == NULL || done == NULL || saved == NULL || v2 == NULL || vs == NULL)
            m2c_sim_die(m, "out of memory");
        c->bcap = cap;
    }
}

void m2c_sim_cluster_free(m2c_sim_cluster *c)
{
    free(c->rows);
    free(c->acc);
    free(c->acc2);
    free(c->target);
    free(c->pushes);
    free(c->inside);
    free(c->movers);
    free(c->done);
    free(c->saved);
    free(c->v2);
    free(c->vs);
}

static int listed(const int32_t *xs, int32_t n, int32_t x)
{
    for (int32_t k = 0; k < n; k++)
        if (xs[k] == x)
            return 1;
    return 0;
}

/* The contacts handled at this instant (touched, in the order first
 * handled) that reach the collision's bodies through bodies that join, into
 * the scratch's rows (bodies and feature only; clu.n of them). */
static void cluster(m2c_world *m, const m2c_sim_event *ev)
{
    m2c_sim_cluster *c = &m->clu;
    cluster_room(m, m->ntouched, 2 * m->ntouched + 2);
    int32_t first[2] = { ev->u.collision.a, ev->u.collision.b };
    c->ninside = 0;
    for (int q = 0; q < 2; q++)
        if (joins(&m->bodies[first[q]]))
            c->inside[c->ninside++] = first[q];
    int grow = 1;
    while (grow) {
        grow = 0;
        for (int32_t k = 0; k < m->ntouched; k++) {
            const m2c_sim_touch *t = &m->touched[k];
            if (listed(c->inside, c->ninside, t->a) || listed(c->inside, c->ninside, t->b)) {
                int32_t both[2] = { t->a, t->b };
                for (int q = 0; q < 2; q++) {
                    if (!listed(c->inside, c->ninside, both[q]) && joins(&m->bodies[both[q]])) {
                        c->inside[c->ninside++] = both[q];
                        grow = 1;
                    }
                }
            }
        }
    }
    c->n = 0;
    for (int32_t k = 0; k < m->ntouched; k++) {
        const m2c_sim_touch *t = &m->touched[k];
        if (listed(c->inside, c->ninside, t->a) || listed(c->inside, c->ninside, t->b)) {
            m2c_sim_row *r = &c->rows[c->n++];
            r->A = &m->bodies[t->a];
            r->B = &m->bodies[t->b];
            r->feature = t->feature;
            r->i = t->i;
            r->j = t->j;
        }
    }
}

/* b's part in a cluster's solve: HELD (fixed or asleep), SLIDER (supported
 * on a fixed body: it moves along the edge only, as in held_impulse) or
 * FREE. */
static int part(const m2c_world *m, const m2c_sim_body *b)
{
    if (b->fixed || b->asleep)
        return HELD;
    if (b->sup >= 0 && m->bodies[b->sup].fixed)
        return SLIDER;
    return FREE;
}

/* How much a unit impulse along n at the contact (rn: the contact's arm
 * across n) changes b's normal speed there. */
static double give(const m2c_world *m, const m2c_sim_body *b, double nx, double ny, double rn)
{
    int p = part(m, b);
    if (p == HELD)
        return 0.0;
    if (p == SLIDER) {
        double k = nx * b->tx + ny * b->ty;
        return b->inv_m * k * k;
    }
    return b->inv_m + b->inv_i * rn * rn;
}

/* An impulse j along n on b at the contact (rn its arm across n). */
static void nudge(const m2c_world *m, m2c_sim_body *b, double j, double nx, double ny, double rn)
{
    int p = part(m, b);
    if (p == HELD)
        return;
    if (p == SLIDER) {
        double d = j * b->inv_m * (nx * b->tx + ny * b->ty);
        b->vx = b->vx + d * b->tx;
        b->vy = b->vy + d * b->ty;
        return;
    }
    b->vx = b->vx + j * b->inv_m * nx;
    b->vy = b->vy + j * b->inv_m * ny;
    b->om = b->om + j * b->inv_i * rn;
}

/* Sequential impulses over the cluster's contacts (in order): each
 * contact's accumulated normal impulse acc[k] moves so that its normal
 * speed becomes target[k], but never below zero (a contact only pushes);
 * sweep after sweep until no impulse of a sweep changed a normal speed by
 * more than CLUSTER_TOL rest_speed, at most CLUSTER_SWEEPS sweeps. */
static void sweeps(m2c_world *m, double *acc, const double *target)
{
    const m2c_sim_cluster *c = &m->clu;
    double tol = CLUSTER_TOL * m->s->rest_speed;
    for (int s = 0; s < CLUSTER_SWEEPS; s++) {
        double big = 0.0;
        for (int32_t k = 0; k < c->n; k++) {
            const m2c_sim_row *r = &c->rows[k];
            if (!(r->kn > 0.0))
                continue;
            double vn = m2c_sim_normal_speed(r->A, r->B, r->cx, r->cy, r->nx, r->ny);
            double nw = acc[k] + (target[k] - vn) / r->kn;
            if (nw < 0.0)
                nw = 0.0;
            double dj = nw - acc[k];
            acc[k] = nw;
            nudge(m, r->A, -dj, r->nx, r->ny, r->ran);
            nudge(m, r->B, dj, r->nx, r->ny, r->rbn);
            double ch = fabs(dj) * r->kn;
            if (ch > big)
                big = ch;
        }
        if (big <= tol)
            return;
    }
}

/* The kinetic energy (J) of the movers (linear, and turning where 1/I > 0). */
static double kinetic(const m2c_world *m)
{
    const m2c_sim_cluster *c = &m->clu;
    double e = 0.0;
    for (int32_t k = 0; k < c->nmovers; k++) {
        const m2c_sim_body *b = c->movers[k];
        e = e + 0.5 * (b->vx * b->vx + b->vy * b->vy) / b->inv_m;
        if (b->inv_i > 0.0)
            e = e + 0.5 * b->om * b->om / b->inv_i;
    }
    return e;
}

static void velocities(const m2c_world *m, double *vs)
{
    const m2c_sim_cluster *c = &m->clu;
    for (int32_t k = 0; k < c->nmovers; k++) {
        vs[3 * k] = c->movers[k]->vx;
        vs[3 * k + 1] = c->movers[k]->vy;
        vs[3 * k + 2] = c->movers[k]->om;
    }
}

static void set_velocities(m2c_world *m, const double *vs)
{
    const m2c_sim_cluster *c = &m->clu;
    for (int32_t k = 0; k < c->nmovers; k++) {
        c->movers[k]->vx = vs[3 * k];
        c->movers[k]->vy = vs[3 * k + 1];
        c->movers[k]->om = vs[3 * k + 2];
    }
}

/* The largest mu in [0, 1] for which the movers' velocities
 * v1 + mu (v - v1) (v: theirs now, v1 as given; the kinetic energy at v1
 * at most budget) have a kinetic energy at most budget: with a the energy
 * of the change, b the cross term and e1 the energy at v1,
 * a mu^2 + b mu <= budget - e1. */
static double mix(const m2c_world *m, const double *v1, double budget)
{
    const m2c_sim_cluster *c = &m->clu;
    double a = 0.0, b = 0.0, e1 = 0.0;
    for (int32_t k = 0; k < c->nmovers; k++) {
        const m2c_sim_body *q = c->movers[k];
        double vx = v1[3 * k], vy = v1[3 * k + 1], om = v1[3 * k + 2];
        double dx = q->vx - vx;
        double dy = q->vy - vy;
        a = a + 0.5 * (dx * dx + dy * dy) / q->inv_m;
        b = b + (vx * dx + vy * dy) / q->inv_m;
        e1 = e1 + 0.5 * (vx * vx + vy * vy) / q->inv_m;
        if (q->inv_i > 0.0) {
            double dw = q->om - om;
            a = a + 0.5 * dw * dw / q->inv_i;
            b = b + om * dw / q->inv_i;
            e1 = e1 + 0.5 * om * om / q->inv_i;
        }
    }
    if (!(a > 0.0))
        return 1.0;
    double spare = budget - e1;
    if (spare < 0.0)
        spare = 0.0;
    double root = sqrt(b * b + 4.0 * a * spare);
    double mu;
    if (b > 0.0)
        mu = 2.0 * spare / (b + root);
    else
        mu = (root - b) / (2.0 * a);
    return mu < 1.0 ? mu : 1.0;
}

/* A contact of the cluster that must separate: its bodies' accelerations
 * press them together (pressed) or, a body turning, its gap closes now
 * (closing), as contact_impulse decides. */
static int pressing_contact(m2c_world *m, const m2c_sim_row *r)
{
    if (m2c_sim_pressed(r->A, r->B, r->nx, r->ny))
        return 1;
    if (m2c_sim_turn_rate(r->A) > 0.0 || m2c_sim_turn_rate(r->B) > 0.0)
        return m2c_sim_closing(m, r->A, r->B, r->feature, r->i, r->j);
    return 0;
}

/* The cluster's joint impulses (docs/simulator.md, "Contact model:
 * simultaneous contacts") into clu.acc, the movers and their velocities
 * before into clu.movers and clu.saved: inelastic sequential impulses
 * (target normal speed 0: kinetic energy e1); then the pressed contacts
 * separate at rest_speed (the others at CLUSTER_APART rest_speed):
 * sequential impulses from v1 (v2), taken when they cost no more than e1;
 * else the same from the movers at rest (vs, energy es), mixed towards v2
 * as far as e1 pays (mix) when es <= e1, else vs scaled to energy e1. */
static void solve_cluster(m2c_world *m, double t)
{
    m2c_sim_cluster *c = &m->clu;
    int32_t n = c->n;
    for (int32_t k = 0; k < n; k++) {
        m2c_sim_row *r = &c->rows[k];
        m2c_sim_contact_frame(m, t, r->feature, r->A, r->B, r->i, r->j, &r->cx, &r->cy, &r->nx, &r->ny);
        r->ran = (r->cx - r->A->px) * r->ny - (r->cy - r->A->py) * r->nx;
        r->rbn = (r->cx - r->B->px) * r->ny - (r->cy - r->B->py) * r->nx;
        r->kn = give(m, r->A, r->nx, r->ny, r->ran) + give(m, r->B, r->nx, r->ny, r->rbn);
    }
    c->nmovers = 0;
    for (int32_t k = 0; k < n; k++) {
        m2c_sim_body *both[2] = { c->rows[k].A, c->rows[k].B };
        for (int q = 0; q < 2; q++)
            if (part(m, both[q]) != HELD && !m2c_sim_among(c->movers, c->nmovers, both[q]))
                c->movers[c->nmovers++] = both[q];
    }
    velocities(m, c->saved);
    double *acc = c->acc, *target = c->target;
    for (int32_t k = 0; k < n; k++) {
        acc[k] = 0.0;
        target[k] = 0.0;
    }
    sweeps(m, acc, target);
    double e1 = kinetic(m);
    for (int32_t k = 0; k < n; k++)
        target[k] = pressing_contact(m, &c->rows[k]) ? m->s->rest_speed : CLUSTER_APART * m->s->rest_speed;
    sweeps(m, acc, target);
    if (kinetic(m) <= e1)
        return;
    velocities(m, c->v2);
    double *acc2 = c->acc2;
    for (int32_t k = 0; k < n; k++)
        acc2[k] = acc[k];
    for (int32_t k = 0; k < c->nmovers; k++) {
        m2c_sim_body *b = c->movers[k];
        if (b->sup >= 0 && m->bodies[b->sup].fixed) {
            double q, u, a;
            m2c_sim_support_relative(m, b, &q, &u, &a);
            b->vx = b->vx - u * b->tx;
            b->vy = b->vy - u * b->ty;
        } else {
            b->vx = 0.0;
            b->vy = 0.0;
        }
        b->om = 0.0;
    }
    for (int32_t k = 0; k < n; k++)
        acc[k] = 0.0;
    sweeps(m, acc, target);
    double es = kinetic(m);
    if (es <= e1) {
        velocities(m, c->vs);
        set_velocities(m, c->v2);
        double mu = mix(m, c->vs, e1);
        for (int32_t k = 0; k < c->nmovers; k++) {
            m2c_sim_body *b = c->movers[k];
            double vx = c->vs[3 * k], vy = c->vs[3 * k + 1], om = c->vs[3 * k + 2];
            b->vx = vx + mu * (b->vx - vx);
            b->vy = vy + mu * (b->vy - vy);
            b->om = om + mu * (b->om - om);
        }
        for (int32_t k = 0; k < n; k++)
            acc[k] = acc[k] + mu * (acc2[k] - acc[k]);
        return;
    }
    double f = sqrt(e1 / es);
    for (int32_t k = 0; k < c->nmovers; k++) {
        m2c_sim_body *b = c->movers[k];
        b->vx = f * b->vx;
        b->vy = f * b->vy;
        b->om = f * b->om;
    }
    for (int32_t k = 0; k < n; k++)
        acc[k] = f * acc[k];
}

/* The first sleeper (in the contacts' order) whose held impulses, summed,
 * would change its material points' normal speed by at least rest_speed
 * (as a touch that is not gentle, sleeper_impulse); NULL. */
static m2c_sim_body *jolted_sleeper(const m2c_world *m)
{
    const m2c_sim_cluster *c = &m->clu;
    for (int32_t k = 0; k < c->n; k++) {
        m2c_sim_body *both[2] = { c->rows[k].A, c->rows[k].B };
        for (int p = 0; p < 2; p++) {
            m2c_sim_body *S = both[p];
            if (!S->asleep || m2c_sim_held_now(m, S))
                continue;
            double total = 0.0;
            for (int32_t q = 0; q < c->n; q++) {
                const m2c_sim_row *r = &c->rows[q];
                if (r->A == S || r->B == S) {
                    double rsn = r->A == S ? r->ran : r->rbn;
                    total = total + c->acc[q] * (S->inv_m + S->inv_i * rsn * rsn);
                }
            }
            if (total >= m->s->rest_speed)
                return S;
        }
    }
    return NULL;
}

/* The pushes (unit directions, npush of them, x then y) can make (dx, dy)
 * with non-negative weights through one push (its direction within
 * HOLD_TOL rad of d) or two: d = a p + b q, a >= 0, b >= 0 (Cramer,
 * p x q != 0), pairs in order.  (dx, dy) = (0, 0) needs nothing. */
static int holds(const double *pushes, int32_t npush, double dx, double dy)
{
    if (dx == 0.0 && dy == 0.0)
        return 1;
    for (int32_t k = 0; k < npush; k++) {
        double px = pushes[2 * k], py = pushes[2 * k + 1];
        double dot = px * dx + py * dy;
        if (dot > 0.0 && fabs(px * dy - py * dx) <= HOLD_TOL * dot)
            return 1;
    }
    for (int32_t k = 0; k < npush; k++) {
        double px = pushes[2 * k], py = pushes[2 * k + 1];
        for (int32_t q = k + 1; q < npush; q++) {
            double qx = pushes[2 * q], qy = pushes[2 * q + 1];
            double det = px * qy - py * qx;
            if (det == 0.0)
                continue;
            double a = (dx * qy - dy * qx) / det;
            double b = (px * dy - py * dx) / det;
            if (a >= 0.0 && b >= 0.0)
                return 1;
        }
    }
    return 0;
}

/* The grounded body awake M falls asleep on after its cluster's solve, or
 * NULL: M slower than rest_speed (a polygon also turning slower than
 * rest_speed / bound) and its free acceleration held by what it rests on
 * (holds): the outward normal of its support when it is supported on an
 * unmoving fixed body, and each contact of the cluster with a grounded body
 * (pushing M along -m, m the contact's normal from M).  It falls asleep on
 * its support, else on the first grounded body of those contacts. */
static m2c_sim_body *wedged(m2c_world *m, const m2c_sim_body *M)
{
    const m2c_sim_cluster *c = &m->clu;
    double rest = m->s->rest_speed;
    if (!(M->vx * M->vx + M->vy * M->vy < rest * rest))
        return NULL;
    if (M->polygon && !(fabs(M->om) * M->bound < rest))
        return NULL;
    double *pushes = c->pushes;
    int32_t npush = 0;
    m2c_sim_body *G = NULL;
    if (M->sup >= 0) {
        m2c_sim_body *S = &m->bodies[M->sup];
        if (!(S->fixed && m2c_sim_grounded(S)))
            return NULL;
        double tx, ty, ox, oy;
        m2c_sim_support_frame(S, M->sup_edge, &tx, &ty, &ox, &oy);
        pushes[2 * npush] = ox;
        pushes[2 * npush + 1] = oy;
        npush++;
        G = S;
    }
    for (int32_t k = 0; k < c->n; k++) {
        const m2c_sim_row *r = &c->rows[k];
        if (r->A == M && m2c_sim_grounded(r->B)) {
            pushes[2 * npush] = -r->nx;
            pushes[2 * npush + 1] = -r->ny;
            npush++;
            if (G == NULL)
                G = r->B;
        }
        if (r->B == M && m2c_sim_grounded(r->A)) {
            pushes[2 * npush] = r->nx;
            pushes[2 * npush + 1] = r->ny;
            npush++;
            if (G == NULL)
                G = r->A;
        }
    }
    if (G == NULL || !holds(pushes, npush, -M->fax, -M->fay))
        return NULL;
    return G;
}

/* A body of a solved cluster after its impulses: one sliding on a fixed
 * body gets its friction again for its new speed (as held_impulse), a
 * carried one leaves its base's motion (end_support: it is not held); a
 * new stamp, its state. */
static void settle(m2c_world *m, m2c_sim_body *b)
{
    if (b->sup >= 0) {
        if (m->bodies[b->sup].fixed) {
            double q, u, a;
            m2c_sim_support_relative(m, b, &q, &u, &a);
            m2c_sim_slide_accel(m, b, u);
        } else {
            m2c_sim_end_support(m, b);
        }
    }
    m->stamp[b->idx]++;
    m2c_sim_emit_state(m, b);
}

/* A contact met again at the instant it was handled (repeated): the
 * contacts handled at this instant that reach it (cluster) are solved
 * together (solve_cluster); a sleeper the solve would jolt wakes and the
 * solve is made again with it moving.  Then an E collision line per contact
 * (its normal impulse), each followed by the states of its moving bodies
 * not written yet (settle); what a body whose velocity changed carries
 * leaves; those slow enough fall asleep (wedged), and the others are
 * predicted again. */
/* A cluster its solves do not settle (met again after CLUSTER_JAM solves
 * at one instant): inelastic collapse, resolved as in Luding's TC model
 * with a contact time of zero: contacts met again at once lose all
 * restitution and all sliding.  An E collision line per contact of the
 * cluster (impulse 0), then each mover (a body of the cluster that is not
 * held, in the contacts' order) falls asleep, at rest, on its support when
 * that is fixed, else on the first body it touches in the cluster that is
 * fixed or asleep, else on the other body of its first contact; it is held
 * until the instant ends (m2c_sim_held_now).  Kinetic energy only falls. */
static void jam(m2c_world *m, const m2c_sim_event *ev)
{
    m2c_sim_cluster *c = &m->clu;
    double t = ev->t;
    m2c_sim_count_touch(m, t, ev->u.collision.a, ev->u.collision.b, ev->u.collision.feature, ev->u.collision.i,
                        ev->u.collision.j);
    cluster(m, ev);
    for (int32_t k = 0; k < c->n; k++) {
        m2c_sim_rebase(c->rows[k].A, t);
        m2c_sim_rebase(c->rows[k].B, t);
    }
    c->nmovers = 0;
    for (int32_t k = 0; k < c->n; k++) {
        m2c_sim_body *both[2] = { c->rows[k].A, c->rows[k].B };
        for (int q = 0; q < 2; q++)
            if (part(m, both[q]) != HELD && !m2c_sim_among(c->movers, c->nmovers, both[q]))
                c->movers[c->nmovers++] = both[q];
    }
    for (int32_t k = 0; k < c->n; k++) {
        m2c_sim_row *r = &c->rows[k];
        m2c_sim_contact_frame(m, t, r->feature, r->A, r->B, r->i, r->j, &r->cx, &r->cy, &r->nx, &r->ny);
        m->stats.collisions++;
        m2c_sim_emit_contact(m, "E collision ", t, r->A, r->B, r->feature, r->i, r->j, r->cx, r->cy, r->nx, r->ny,
                             0.0);
        m2c_sim_report(m, t, r->A, r->B, r->feature, r->i, r->j, r->cx, r->cy, r->nx, r->ny, 0.0, 0);
    }
    if (m->jammed_t != t) {
        m->jammed_t = t;
        m->njammed = 0;
    }
    for (int32_t k = 0; k < c->nmovers; k++) {
        m2c_sim_body *b = c->movers[k];
        if (b->asleep)
            continue;
        m2c_sim_body *G = NULL;
        if (b->sup >= 0 && m->bodies[b->sup].fixed) {
            G = &m->bodies[b->sup];
        } else {
            for (int32_t q = 0; q < c->n && G == NULL; q++) {
                m2c_sim_body *o = c->rows[q].A == b ? c->rows[q].B : (c->rows[q].B == b ? c->rows[q].A : NULL);
                if (o != NULL && (o->fixed || o->asleep))
                    G = o;
            }
            for (int32_t q = 0; q < c->n && G == NULL; q++)
                if (c->rows[q].A == b || c->rows[q].B == b)
                    G = c->rows[q].A == b ? c->rows[q].B : c->rows[q].A;
        }
        if (m->njammed == m->jammed_cap) {
            int32_t cap = m->jammed_cap ? 2 * m->jammed_cap : 16;
            int32_t *more = realloc(m->jammed, (size_t)cap * sizeof *more);
            if (more == NULL)
                m2c_sim_die(m, "out of memory");
            m->jammed = more;
            m->jammed_cap = cap;
        }
        m->jammed[m->njammed++] = b->idx;
        m2c_sim_handle_sleep(m, b, G, t);
    }
}

void m2c_sim_handle_cluster(m2c_world *m, const m2c_sim_event *ev)
{
    m2c_sim_cluster *c = &m->clu;
    double t = ev->t;
    if (jam_count(m, ev) >= CLUSTER_REPEATS + CLUSTER_JAM) {
        jam(m, ev);
        return;
    }
    m2c_sim_count_touch(m, t, ev->u.collision.a, ev->u.collision.b, ev->u.collision.feature, ev->u.collision.i,
                        ev->u.collision.j);
    for (;;) {
        cluster(m, ev);
        for (int32_t k = 0; k < c->n; k++) {
            m2c_sim_rebase(c->rows[k].A, t);
            m2c_sim_rebase(c->rows[k].B, t);
        }
        solve_cluster(m, t);
        m2c_sim_body *S = jolted_sleeper(m);
        if (S == NULL)
            break;
        set_velocities(m, c->saved);
        m2c_sim_handle_wake(m, S, t);
    }
    /* written: the movers whose state is out (the first ndone of done serve) */
    c->ndone = 0;
    for (int32_t k = 0; k < c->n; k++) {
        const m2c_sim_row *r = &c->rows[k];
        m->stats.collisions++;
        m2c_sim_emit_contact(m, "E collision ", t, r->A, r->B, r->feature, r->i, r->j, r->cx, r->cy, r->nx, r->ny,
                             c->acc[k]);
        m2c_sim_report(m, t, r->A, r->B, r->feature, r->i, r->j, r->cx, r->cy, r->nx, r->ny, c->acc[k], 0);
        m2c_sim_body *both[2] = { r->A, r->B };
        for (int q = 0; q < 2; q++) {
            if (m2c_sim_among(c->movers, c->nmovers, both[q]) && !m2c_sim_among(c->done, c->ndone, both[q])) {
                c->done[c->ndone++] = both[q];
                settle(m, both[q]);
            }
        }
    }
    m2c_sim_left left = { 0 };
    for (int32_t k = 0; k < c->nmovers; k++) {
        const m2c_sim_body *b = c->movers[k];
        if (b->vx != c->saved[3 * k] || b->vy != c->saved[3 * k + 1] || b->om != c->saved[3 * k + 2])
            m2c_sim_release(m, b, t, &left);
    }
    c->ndone = 0;
    int grow = 1;
    while (grow) {
        grow = 0;
        for (int32_t k = 0; k < c->nmovers; k++) {
            m2c_sim_body *b = c->movers[k];
            if (!b->asleep) {
                m2c_sim_body *G = wedged(m, b);
                if (G != NULL) {
                    m2c_sim_handle_sleep(m, b, G, t);
                    c->done[c->ndone++] = b;
                    grow = 1;
                }
            }
        }
    }
    for (int32_t k = 0; k < c->nmovers; k++) {
        m2c_sim_body *b = c->movers[k];
        if (!b->asleep) {
            m2c_sim_predict_apart(m, b, t);
            c->done[c->ndone++] = b;
        }
    }
    m2c_sim_predict_released(m, &left, t);
}
