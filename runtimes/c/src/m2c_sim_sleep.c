/* Sleeping islands (docs/simulator.md, "Contact model: sleeping islands"):
 * a slow body pressed onto a grounded one (asleep, or fixed and unmoving)
 * falls asleep in its island, frozen (v = a = w = 0, no events of its
 * own); an impulse that would move it, or a body removed or driven next to
 * it, wakes the whole island.  Speeds in m/s. */
#include <math.h>

#include "m2c_sim_internal.h"

/* A body supported by an unmoving body, slower than rest_speed along its
 * edge, that static friction would hold there (|at| <= mu load, as in
 * slide_accel at u = 0; on a level frictionless edge at = 0): it stays
 * where it is.  On a moving support: never (it does not sleep); nor on a
 * movable one (carried: grounded is false while it carries). */
int m2c_sim_at_rest(const m2c_world *m, const m2c_sim_body *A)
{
    const m2c_sim_body *B = &m->bodies[A->sup];
    if (!m2c_sim_grounded(B))
        return 0;
    double u = A->vx * A->tx + A->vy * A->ty;
    double rest = m->s->rest_speed;
    if (!(u * u < rest * rest))
        return 0;
    double f = A->mu * B->mu * A->load;
    return !(A->at > f) && !(A->at < -f);
}

/* M's centre of mass projects inside the support segment of the contact of
 * V's vertex i on E's edge j, shrunk by the tolerance: along the edge's
 * tangent t, the overlap of the edge [s1, s2] with V's face (vertex i and
 * each neighbour on the edge's line within the face tolerance of `flat`),
 * all relative to E's centre.  A polygon whose centre lies past its
 * support's end would tip: it does not sleep. */
static int over_face(m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *V, const m2c_sim_body *E, int32_t i,
                     int32_t j, double load)
{
    double tx, ty, ox, oy;
    m2c_sim_support_frame(E, j, &tx, &ty, &ox, &oy);
    double tol = m->s->tol, rest = m->s->rest_speed;
    double r = rest * rest / load;
    double ftol = r > tol ? r : tol;                                /* Python's max(tol, r) */
    const m2c_sim_vertex *ed = &E->verts[j];
    double h = ed->h;
    double px, py;
    m2c_sim_point_at(m, V, &V->verts[i], V->tb, &px, &py);
    double lo = (px - E->px) * tx + (py - E->py) * ty;
    double hi = lo;
    int32_t n = V->nverts;
    const int32_t ks[2] = { (i + n - 1) % n, (i + 1) % n };
    for (int l = 0; l < 2; l++) {
        m2c_sim_point_at(m, V, &V->verts[ks[l]], V->tb, &px, &py);
        if ((px - E->px) * ox + (py - E->py) * oy - h <= ftol) {
            double q = (px - E->px) * tx + (py - E->py) * ty;
            if (q < lo)
                lo = q;
            if (q > hi)
                hi = q;
        }
    }
    if (ed->s1 > lo)
        lo = ed->s1;
    if (ed->s2 < hi)
        hi = ed->s2;
    double c = (M->px - E->px) * tx + (M->py - E->py) * ty;
    return !(c < lo + tol) && !(c > hi - tol);
}

/* Awake movable M, one body of the collision ev with grounded G (both
 * advanced; (nx, ny) the contact's unit normal from a to b, vn its normal
 * speed), falls asleep on G: M's free acceleration presses it onto G, the
 * contact is slow, M's speed across the normal is below rest_speed, and a
 * polygon M turns slowly and lies on a face (docs/simulator.md). */
int m2c_sim_can_sleep(m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev, double nx,
                      double ny, double vn)
{
    if (!m2c_sim_grounded(G) || !m2c_sim_slow_press(m, M, G, ev, nx, ny, vn))
        return 0;
    if (M->polygon) {
        if (ev->u.collision.feature != M2C_SIM_PE || ev->u.collision.i < 0)
            return 0;
        double load = M->idx == ev->u.collision.a ? M->fax * nx + M->fay * ny : M->fax * -nx + M->fay * -ny;
        const m2c_sim_body *V = &m->bodies[ev->u.collision.a];
        const m2c_sim_body *E = &m->bodies[ev->u.collision.b];
        return m2c_sim_flat(m, V, E, ev->u.collision.i, ev->u.collision.j, -nx, -ny, load)
               && over_face(m, M, V, E, ev->u.collision.i, ev->u.collision.j, load);
    }
    return 1;
}

/* The contact of ev of awake movable M with G (both advanced; (nx, ny) from
 * a to b, vn its normal speed) is slow and presses M onto G: M's free
 * acceleration has a positive load along the normal from M to G, vn <
 * rest_speed and eM eG (-vn) < rest_speed, M's speed across the normal is
 * below rest_speed, and a polygon M turns slower than rest_speed / bound. */
int m2c_sim_slow_press(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev,
                       double nx, double ny, double vn)
{
    if (M->fixed || M->asleep)
        return 0;
    double mx = M->idx == ev->u.collision.a ? nx : -nx;
    double my = M->idx == ev->u.collision.a ? ny : -ny;
    double rest = m->s->rest_speed;
    double load = M->fax * mx + M->fay * my;
    if (!(load > 0.0) || vn >= rest || M->e * G->e * -vn >= rest)
        return 0;
    double ut = M->vy * mx - M->vx * my;
    if (ut * ut >= rest * rest)
        return 0;
    return !M->polygon || fabs(M->om) * M->bound < rest;
}

/* Keeps the contact of ev at (cx, cy) as M's last slow pressing contact,
 * with G's and M's positions and angles now. */
void m2c_sim_note_rest(m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev, double cx,
                       double cy, double nx, double ny)
{
    m2c_sim_rest_contact *r = &m->restc[2 * (size_t)M->idx];
    if (r[0].other1 != G->idx + 1)
        r[1] = r[0];                    /* the last contact with another body is kept */
    r->px = cx;
    r->py = cy;
    r->mx = M->idx == ev->u.collision.a ? nx : -nx;
    r->my = M->idx == ev->u.collision.a ? ny : -ny;
    r->load = M->fax * r->mx + M->fay * r->my;
    r->gx = G->px;
    r->gy = G->py;
    r->gang = G->ang;
    r->bx = M->px;
    r->by = M->py;
    r->bang = M->ang;
    r->other1 = G->idx + 1;
}

/* M's last slow pressing contact with a body other than G, or NULL. */
static const m2c_sim_rest_contact *rest_other(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G)
{
    const m2c_sim_rest_contact *r = &m->restc[2 * (size_t)M->idx];
    if (r->other1 - 1 == G->idx)
        r++;
    return r->other1 == 0 || r->other1 - 1 == G->idx ? NULL : r;
}

/* A contact force along the direction of M's free acceleration (gx, gy)
 * (unit) at a contact with unit normal (mx, my) from M to G lies in the
 * friction cone: the normal presses (c > 0) and |m x g| <= mu c. */
static int in_cone(double mx, double my, double gx, double gy, double mu)
{
    double c = mx * gx + my * gy;
    double s = fabs(mx * gy - my * gx);
    return c > 0.0 && !(s > mu * c);
}

/* Awake movable M, in the slow pressing contact of ev with grounded G at
 * (cx, cy), falls asleep on two supports: its last slow pressing contact
 * (restc) was with another grounded body G1 that has not moved since, and M
 * has moved less than the face tolerance of `flat` since (its centre, and
 * its angle times its bound: it still touches G1 within a hop's height); both
 * contacts can push along M's free acceleration within their friction
 * cones, and M's centre lies strictly between the two contact points across
 * that direction (by more than the tolerance): two vertical forces then
 * hold M's weight with no torque (docs/simulator.md, "Two supports"). */
int m2c_sim_can_sleep_two(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev,
                          double cx, double cy, double nx, double ny, double vn)
{
    if (!m2c_sim_grounded(G) || !m2c_sim_slow_press(m, M, G, ev, nx, ny, vn))
        return 0;
    const m2c_sim_rest_contact *r = rest_other(m, M, G);
    if (r == NULL)
        return 0;
    const m2c_sim_body *G1 = &m->bodies[r->other1 - 1];
    if (G1->gone || !m2c_sim_grounded(G1) || G1->px != r->gx || G1->py != r->gy || G1->ang != r->gang)
        return 0;
    /* M has stayed within a hop's height of where it touched G1 (the face tolerance of `flat`) */
    double ftol = fmax(m->s->tol, m->s->rest_speed * m->s->rest_speed / r->load);
    double dx = M->px - r->bx, dy = M->py - r->by;
    if (dx * dx + dy * dy > ftol * ftol || fabs(M->ang - r->bang) * M->bound > ftol)
        return 0;
    double fa = sqrt(M->fax * M->fax + M->fay * M->fay);
    double gx = M->fax / fa, gy = M->fay / fa;
    double mx = M->idx == ev->u.collision.a ? nx : -nx;
    double my = M->idx == ev->u.collision.a ? ny : -ny;
    if (!in_cone(r->mx, r->my, gx, gy, M->mu * G1->mu) || !in_cone(mx, my, gx, gy, M->mu * G->mu))
        return 0;
    double x1 = (r->px - M->px) * -gy + (r->py - M->py) * gx;
    double x2 = (cx - M->px) * -gy + (cy - M->py) * gx;
    double tol = m->s->tol;
    return (x1 < -tol && x2 > tol) || (x1 > tol && x2 < -tol);
}

/* A falls asleep on G (handle_sleep) and on its other support, the body of
 * its last slow pressing contact: when that one sleeps in another island,
 * the two islands become one (A's), so that waking either wakes both. */
void m2c_sim_handle_sleep_two(m2c_world *m, m2c_sim_body *A, const m2c_sim_body *G, double t)
{
    const m2c_sim_body *G1 = &m->bodies[rest_other(m, A, G)->other1 - 1];
    m2c_sim_handle_sleep(m, A, G, t);
    if (G1->asleep && G1->island != A->island) {
        int32_t old = G1->island;
        for (int32_t k = 0; k < m->s->nbodies; k++)
            if (m->bodies[k].asleep && m->bodies[k].island == old)
                m->bodies[k].island = A->island;
    }
}

/* A (advanced to t) falls asleep resting on G: frozen (v = a = w = 0) in
 * G's island, or in a new one numbered A's index when G is fixed.  Its
 * awake neighbours are predicted against it again. */
void m2c_sim_handle_sleep(m2c_world *m, m2c_sim_body *A, const m2c_sim_body *G, double t)
{
    m->stats.sleeps++;
    A->rest = A->sup >= 0 && m->bodies[A->sup].fixed ? A->sup : -1;
    if (A->sup >= 0)
        m2c_sim_end_support(m, A);
    A->vx = 0.0;
    A->vy = 0.0;
    A->om = 0.0;
    A->ax = 0.0;
    A->ay = 0.0;
    A->asleep = 1;
    A->island = G->asleep ? G->island : A->idx;
    m->stamp[A->idx]++;
    m2c_sim_emit_island(m, "E sleep ", t, A->idx, G->idx, A->island);
    m2c_sim_emit_state(m, A);
    m2c_sim_left left = { 0 };
    m2c_sim_release(m, A, t, &left);
    m2c_sim_predict_body(m, A, t, NULL);
    m2c_sim_predict_released(m, &left, t);
}

/* S's island wakes at t: every member (by index) gets its free
 * acceleration back, then fresh predictions (a pair of members once). */
void m2c_sim_handle_wake(m2c_world *m, const m2c_sim_body *S, double t)
{
    m->stats.wakes++;
    int32_t island = S->island;
    m2c_sim_emit_island(m, "E wake ", t, S->idx, -1, island);
    int32_t n = m->s->nbodies;
    for (int32_t k = 0; k < n; k++) {
        m2c_sim_body *b = &m->bodies[k];
        if (b->asleep && b->island == island) {
            m2c_sim_rebase(b, t);
            b->asleep = 0;
            b->rest = -1;
            b->ax = b->fax;
            b->ay = b->fay;
            m->stamp[b->idx]++;
            m2c_sim_emit_state(m, b);
        }
    }
    m2c_sim_left left = { 0 };
    for (int32_t k = 0; k < n; k++)
        if (m->bodies[k].island == island)
            m2c_sim_release(m, &m->bodies[k], t, &left);    /* bodies sliding on a member leave it: it may move */
    for (int32_t k = 0; k < n; k++)
        if (m->bodies[k].island == island)
            m2c_sim_predict_woken(m, &m->bodies[k], t, island);
    m2c_sim_predict_released(m, &left, t);
    for (int32_t k = 0; k < n; k++)
        if (m->bodies[k].island == island)
            m->bodies[k].island = -1;
}

/* The islands of the sleepers whose bounding circles reach the removed
 * body's (within the tolerance) wake: it may have held them (by index; a
 * woken island's other members are awake already). */
void m2c_sim_wake_touching(m2c_world *m, const m2c_sim_body *body, double t)
{
    double tol = m->s->tol;
    for (int32_t k = 0; k < m->s->nbodies; k++) {
        const m2c_sim_body *o = &m->bodies[k];
        if (o->asleep) {
            double dx = o->px - body->px;
            double dy = o->py - body->py;
            double reach = o->bound + body->bound + tol;
            if (dx * dx + dy * dy <= reach * reach)
                m2c_sim_handle_wake(m, o, t);
        }
    }
}
