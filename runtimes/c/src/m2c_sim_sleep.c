/* Sleeping islands (docs/simulator.md, "Contact model: sleeping islands"):
 * a slow body pressed onto a grounded one (asleep, or fixed and unmoving)
 * falls asleep resting on it, frozen (v = a = w = 0, no events of its
 * own); an impulse that would move it, or a body removed or driven next to
 * it, wakes it and the sleepers resting on it, going up.  Speeds in m/s. */
#include <math.h>

#include "m2c_sim_internal.h"

#define WAKING (-2)     /* island of the sleepers handle_wake is waking */

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
    double load = M->fax * mx + M->fay * my;
    return load > 0.0 && m2c_sim_slow_touch(m, M, G, ev, nx, ny, vn);
}

/* The contact of ev of awake movable M with G is slow: slow_press without
 * the load (a contact across M's free acceleration, a wall a box leans on,
 * counts). */
int m2c_sim_slow_touch(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev,
                       double nx, double ny, double vn)
{
    if (M->fixed || M->asleep)
        return 0;
    double mx = M->idx == ev->u.collision.a ? nx : -nx;
    double my = M->idx == ev->u.collision.a ? ny : -ny;
    double rest = m->s->rest_speed;
    if (vn >= rest || M->e * G->e * -vn >= rest)
        return 0;
    double ut = M->vy * mx - M->vx * my;
    if (ut * ut >= rest * rest)
        return 0;
    return !M->polygon || fabs(M->om) * M->bound < rest;
}

/* The key of a noted contact: the other body, ev's feature, i and j, and
 * which side of ev M is. */
static int same_key(const m2c_sim_rest_contact *r, const m2c_sim_rest_contact *q)
{
    return r->other1 == q->other1 && r->feature == q->feature && r->i == q->i && r->j == q->j && r->side == q->side;
}

/* With G grounded, keeps the slow contact of ev at (cx, cy) first among M's last
 * M2C_SIM_REST_SLOTS slow contacts (distinct by key), with G's and M's
 * positions and angles now: an earlier one with the same key leaves its
 * place, the others move down one, the oldest beyond the slots is
 * dropped. */
void m2c_sim_note_rest(m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev, double cx,
                       double cy, double nx, double ny)
{
    if (!m2c_sim_grounded(G))
        return;                         /* an awake body moves: a contact with it would not hold */
    m2c_sim_rest_contact *slots = &m->restc[M2C_SIM_REST_SLOTS * (size_t)M->idx];
    m2c_sim_rest_contact r;
    int side = M->idx == ev->u.collision.a;
    r.other1 = G->idx + 1;
    r.feature = ev->u.collision.feature;
    r.i = ev->u.collision.i;
    r.j = ev->u.collision.j;
    r.side = side;
    r.px = cx;
    r.py = cy;
    r.mx = side ? nx : -nx;
    r.my = side ? ny : -ny;
    r.gx = G->px;
    r.gy = G->py;
    r.gang = G->ang;
    r.bx = M->px;
    r.by = M->py;
    r.bang = M->ang;
    int k = 0;
    while (k < M2C_SIM_REST_SLOTS - 1 && slots[k].other1 != 0 && !same_key(&slots[k], &r))
        k++;
    for (; k > 0; k--)
        slots[k] = slots[k - 1];
    slots[0] = r;
}

/* M's noted slow contacts that still hold, in slot order, but the one with
 * ev's key: the other body is not removed, grounded, at the position and
 * angle noted (bit for bit), and M has moved less than ftol since (its
 * centre, and its angle times its bound).  Their slot numbers go to held;
 * returns how many. */
static int holding(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_event *ev, double ftol,
                   int held[M2C_SIM_REST_SLOTS])
{
    const m2c_sim_rest_contact *slots = &m->restc[M2C_SIM_REST_SLOTS * (size_t)M->idx];
    int side = M->idx == ev->u.collision.a;
    int32_t other1 = (side ? ev->u.collision.b : ev->u.collision.a) + 1;
    int n = 0;
    for (int k = 0; k < M2C_SIM_REST_SLOTS; k++) {
        const m2c_sim_rest_contact *r = &slots[k];
        if (r->other1 == 0)
            break;
        if (r->other1 == other1 && r->feature == ev->u.collision.feature && r->i == ev->u.collision.i
            && r->j == ev->u.collision.j && r->side == side)
            continue;
        const m2c_sim_body *O = &m->bodies[r->other1 - 1];
        if (O->gone || !m2c_sim_grounded(O) || O->px != r->gx || O->py != r->gy || O->ang != r->gang)
            continue;
        double dx = M->px - r->bx, dy = M->py - r->by;
        if (dx * dx + dy * dy > ftol * ftol || fabs(M->ang - r->bang) * M->bound > ftol)
            continue;
        held[n++] = k;
    }
    return n;
}

static void cross3(const double a[3], const double b[3], double c[3])
{
    c[0] = a[1] * b[2] - a[2] * b[1];
    c[1] = a[2] * b[0] - a[0] * b[2];
    c[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* The contacts (px, py, mx, my, mu) of M, np of them (unit normal m from M
 * to the other body), admit a static equilibrium with a margin: each of
 * four targets T is a combination with coefficients >= 0 of the contact
 * rays (per contact -m + mu t and -m - mu t, t = (-my, mx); -m alone when
 * mu = 0), each ray written (dx, dy, (p - pM) x d).  By Caratheodory a
 * target in the cone of the rays lies in the cone of three independent
 * ones: the triples i < j < k are tried with Cramer's rule until every
 * target is found in one (docs/simulator.md, "Several contacts"). */
static int balanced(const m2c_sim_body *M, const double (*pts)[5], int np, double fa, double tol)
{
    double rays[2 * (M2C_SIM_REST_SLOTS + 1)][3];
    int n = 0;
    for (int c = 0; c < np; c++) {
        double rx = pts[c][0] - M->px, ry = pts[c][1] - M->py;
        double mx = pts[c][2], my = pts[c][3], mu = pts[c][4];
        if (mu > 0.0) {
            double dx = -mx - mu * my, dy = -my + mu * mx;
            rays[n][0] = dx;
            rays[n][1] = dy;
            rays[n][2] = rx * dy - ry * dx;
            n++;
            dx = -mx + mu * my;
            dy = -my - mu * mx;
            rays[n][0] = dx;
            rays[n][1] = dy;
            rays[n][2] = rx * dy - ry * dx;
            n++;
        } else {
            double dx = -mx, dy = -my;
            rays[n][0] = dx;
            rays[n][1] = dy;
            rays[n][2] = rx * dy - ry * dx;
            n++;
        }
    }
    if (n < 3)
        return 0;
    double e = tol / M->bound;
    double wx = -e * M->fay, wy = e * M->fax;
    double tq = fa * tol;
    const double targets[4][3] = { { -M->fax + wx, -M->fay + wy, 0.0 },
                                   { -M->fax - wx, -M->fay - wy, 0.0 },
                                   { -M->fax, -M->fay, tq },
                                   { -M->fax, -M->fay, -tq } };
    int found[4] = { 0, 0, 0, 0 };
    int left = 4;
    for (int i = 0; i < n - 2; i++)
        for (int j = i + 1; j < n - 1; j++) {
            double cij[3];
            cross3(rays[i], rays[j], cij);
            for (int k = j + 1; k < n; k++) {
                double cjk[3], cki[3];
                cross3(rays[j], rays[k], cjk);
                cross3(rays[k], rays[i], cki);
                double d = dot3(rays[i], cjk);
                if (!(d > 0.0) && !(d < 0.0))
                    continue;
                for (int q = 0; q < 4; q++) {
                    if (found[q])
                        continue;
                    double li = dot3(targets[q], cjk), lj = dot3(targets[q], cki), lk = dot3(targets[q], cij);
                    if (d > 0.0 ? (li < 0.0 || lj < 0.0 || lk < 0.0) : (li > 0.0 || lj > 0.0 || lk > 0.0))
                        continue;
                    found[q] = 1;
                    if (--left == 0)
                        return 1;
                }
            }
        }
    return 0;
}

/* Awake movable M, in the slow pressing contact of ev with grounded G at
 * (cx, cy), falls asleep resting on several contacts (docs/simulator.md,
 * "Several contacts"): this contact and M's noted ones that still hold
 * (holding) admit a static equilibrium with a margin (balanced). */
int m2c_sim_can_sleep_many(const m2c_world *m, const m2c_sim_body *M, const m2c_sim_body *G, const m2c_sim_event *ev,
                           double cx, double cy, double nx, double ny, double vn)
{
    if (!m2c_sim_grounded(G) || !m2c_sim_slow_press(m, M, G, ev, nx, ny, vn))
        return 0;
    double fa = sqrt(M->fax * M->fax + M->fay * M->fay);
    double rest = m->s->rest_speed;
    double ftol = fmax(m->s->tol, rest * rest / fa);
    int held[M2C_SIM_REST_SLOTS];
    int nh = holding(m, M, ev, ftol, held);
    if (nh == 0)
        return 0;
    double pts[M2C_SIM_REST_SLOTS + 1][5];
    int side = M->idx == ev->u.collision.a;
    pts[0][0] = cx;
    pts[0][1] = cy;
    pts[0][2] = side ? nx : -nx;
    pts[0][3] = side ? ny : -ny;
    pts[0][4] = M->mu * G->mu;
    const m2c_sim_rest_contact *slots = &m->restc[M2C_SIM_REST_SLOTS * (size_t)M->idx];
    for (int h = 0; h < nh; h++) {
        const m2c_sim_rest_contact *r = &slots[held[h]];
        pts[h + 1][0] = r->px;
        pts[h + 1][1] = r->py;
        pts[h + 1][2] = r->mx;
        pts[h + 1][3] = r->my;
        pts[h + 1][4] = M->mu * m->bodies[r->other1 - 1].mu;
    }
    return balanced(M, (const double (*)[5])pts, nh + 1, fa, m->s->tol);
}

/* A falls asleep on G (handle_sleep); then the body of each noted contact
 * that still holds (in slot order) is added to what A rests on, so a jolt
 * on any of them wakes A. */
void m2c_sim_handle_sleep_many(m2c_world *m, m2c_sim_body *A, const m2c_sim_body *G, const m2c_sim_event *ev, double t)
{
    double fa = sqrt(A->fax * A->fax + A->fay * A->fay);
    double rest = m->s->rest_speed;
    int held[M2C_SIM_REST_SLOTS];
    int nh = holding(m, A, ev, fmax(m->s->tol, rest * rest / fa), held);
    int32_t others[M2C_SIM_REST_SLOTS];
    for (int h = 0; h < nh; h++)
        others[h] = m->restc[M2C_SIM_REST_SLOTS * (size_t)A->idx + (size_t)held[h]].other1 - 1;
    m2c_sim_handle_sleep(m, A, G, t);
    for (int h = 0; h < nh; h++)
        A->on[A->non++] = others[h];
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
    A->on[0] = G->idx;
    A->non = 1;
    m->stamp[A->idx]++;
    m2c_sim_emit_island(m, "E sleep ", t, A->idx, G->idx, A->island);
    m2c_sim_emit_state(m, A);
    m2c_sim_left left = { 0 };
    m2c_sim_release(m, A, t, &left);
    m2c_sim_predict_body(m, A, t, NULL);
    m2c_sim_predict_released(m, &left, t);
}

/* Sleeper S wakes at t, and with it every sleeper that rests on a woken
 * body (the upward closure, marked island WAKING): each (by index) gets its
 * free acceleration back, then fresh predictions (a pair of woken bodies
 * once). */
void m2c_sim_handle_wake(m2c_world *m, const m2c_sim_body *S, double t)
{
    m->stats.wakes++;
    m2c_sim_emit_island(m, "E wake ", t, S->idx, -1, S->island);
    int32_t n = m->s->nbodies;
    const int32_t island = WAKING;
    m->bodies[S->idx].island = island;
    int grown = 1;
    while (grown) {
        grown = 0;
        for (int32_t k = 0; k < n; k++) {
            m2c_sim_body *b = &m->bodies[k];
            if (b->asleep && b->island != island)
                for (int32_t g = 0; g < b->non; g++)
                    if (m->bodies[b->on[g]].island == island) {
                        b->island = island;
                        grown = 1;
                        break;
                    }
        }
    }
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

/* The sleepers whose bounding circles reach the removed body's (within the
 * tolerance) wake, each with what rests on it: it may have held them (by
 * index; one woken with an earlier one is awake already). */
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
