/* A contact's response (docs/simulator.md, "Impulse"): where and along
 * which normal two bodies touch, and the impulse that never adds kinetic
 * energy: frictionless and restituted when fast, a hop at about
 * rest_speed when slow and pressed, along the supports' edges for bodies
 * held on them, and with a sleeper held as fixed first.  Units: m, m/s,
 * kg m/s (impulses). */
#include <math.h>

#include "m2c_roots.h"
#include "m2c_sim_internal.h"

/* Contact point (cx, cy) (m) and unit normal (nx, ny) from A to B of a
 * feature at t (both bodies advanced to t): the TOI library's frame. */
void m2c_sim_contact_frame(m2c_world *m, double t, int32_t feature, const m2c_sim_body *A, const m2c_sim_body *B,
                           int32_t i, int32_t j, double *cx, double *cy, double *nx, double *ny)
{
    m2c_toi_frame(m, t, feature, A, B, i, j, B->ang, cx, cy, nx, ny);
}

/* The gap polynomial of the contact's feature (feature, i, j as in a
 * collision record: the one that predicted it), taken again at the contact
 * (A's time: both advanced), predicts this contact now (touching_now:
 * approaching, c1 < 0, or c2 < 0 and closing again before the gap exceeds
 * its kappa).  Its second derivative has the centripetal terms of a turn,
 * which `pressed` leaves out. */
int m2c_sim_closing(m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, int32_t feature, int32_t i, int32_t j)
{
    double now = A->tb;
    double c[M2C_MAX_DEGREE + 1] = { 0.0 };
    int deg;
    double kappa;
    if (feature == M2C_SIM_CC) {
        const m2c_sim_vertex *vb = j >= 0 ? &B->verts[j] : NULL;
        double rb = vb == NULL ? B->r : 0.0;
        double p1[11], p2[11];
        m2c_sim_circle_params(m, A, now, NULL, p1);
        m2c_sim_circle_params(m, B, now, vb, p2);
        deg = m2c_sim_circles_gap(m, p1, A->r, p2, rb, c);
        double tol = m->s->tol;
        kappa = tol * (2.0 * (A->r + rb) + tol);
    } else {
        if (i >= 0) {
            const m2c_sim_vertex *v = &A->verts[i];
            deg = m2c_sim_pe_coefficients(m, A, B, v->rho, v->beta, 0.0, j, now, c);
        } else {
            deg = m2c_sim_pe_coefficients(m, A, B, A->orbit, A->ophase, A->r, j, now, c);
        }
        kappa = m->s->tol;
    }
    return m2c_sim_touching_now(c, deg, kappa);
}

/* A hop at the floor speed adds dE = need / 2 to the pair's energy (need =
 * (floor^2 - cap) / kn): it is paid from the pair's common motion, the
 * velocity V of its centre of mass (mass M), which an equal change of both
 * velocities scales by f = sqrt(1 - need / (M V^2)), leaving their relative
 * motion, hence the hop, untouched.  Not when a body of the pair is held
 * (fixed, or a sleeper held as fixed) or the common motion cannot pay it
 * (M V^2 <= need): 0, the hop then adds dE (unpaid); else 1. */
static int pay_floor(m2c_sim_body *A, m2c_sim_body *B, double need)
{
    if (A->inv_m == 0.0 || B->inv_m == 0.0)
        return 0;
    double ma = 1.0 / A->inv_m;
    double mb = 1.0 / B->inv_m;
    double mass = ma + mb;
    double vx = (ma * A->vx + mb * B->vx) / mass;
    double vy = (ma * A->vy + mb * B->vy) / mass;
    double e2 = mass * (vx * vx + vy * vy);
    if (!(e2 > need))
        return 0;
    double f = sqrt(1.0 - need / e2);
    double dx = vx * f - vx;
    double dy = vy * f - vy;
    A->vx = A->vx + dx;
    A->vy = A->vy + dy;
    B->vx = B->vx + dx;
    B->vy = B->vy + dy;
    return 1;
}

/* A slow pressed contact (pressed, -vn < rest_speed): the bodies separate
 * at hop along n, paid from their relative motion at the contact, so the
 * pair's energy stays what it was: hop = rest_speed when kn Q pays it, else
 * sqrt(kn Q), but at least rest_speed / 32 (the energy that adds is paid
 * from the pair's common motion, pay_floor, else the hop sets unpaid).
 * u = (vn, vt) the relative velocity of the material points in the frame
 * (n, t), t = (-ny, nx), K the contact's 2x2 inverse mass matrix (kn, knt;
 * knt, kt), Q = u . K^-1 u; the new relative velocity is (hop, x) with the
 * same Q, through the impulse P = K^-1 (u' - u).  Returns its normal part
 * jn (kg m/s). */
static double hop(m2c_world *m, m2c_sim_body *A, m2c_sim_body *B, double cx, double cy, double nx, double ny,
                  double vn)
{
    double tx = -ny, ty = nx;
    double uax = A->vx - A->om * (cy - A->py);
    double uay = A->vy + A->om * (cx - A->px);
    double ubx = B->vx - B->om * (cy - B->py);
    double uby = B->vy + B->om * (cx - B->px);
    double vt = (ubx - uax) * tx + (uby - uay) * ty;
    double ran = (cx - A->px) * ny - (cy - A->py) * nx;
    double rbn = (cx - B->px) * ny - (cy - B->py) * nx;
    double rat = (cx - A->px) * ty - (cy - A->py) * tx;
    double rbt = (cx - B->px) * ty - (cy - B->py) * tx;
    double im = A->inv_m + B->inv_m;
    double kn = im + A->inv_i * ran * ran + B->inv_i * rbn * rbn;
    double kt = im + A->inv_i * rat * rat + B->inv_i * rbt * rbt;
    double knt = A->inv_i * ran * rat + B->inv_i * rbn * rbt;
    double det = kn * kt - knt * knt;
    double q = (kt * vn * vn - 2.0 * knt * vn * vt + kn * vt * vt) / det;
    double cap = kn * q;
    double rest = m->s->rest_speed;
    double floor_ = 0.03125 * rest;
    double h;
    if (cap >= rest * rest)
        h = rest;
    else if (cap >= floor_ * floor_)
        h = sqrt(cap);
    else
        h = floor_;
    double d = det * (cap - h * h);
    double root = d > 0.0 ? sqrt(d) : 0.0;
    double mid = knt * h;
    double x;
    if (vt * kn >= mid)
        x = (mid + root) / kn;
    else
        x = (mid - root) / kn;
    double dn = h - vn;
    double dt = x - vt;
    double jn = (kt * dn - knt * dt) / det;
    double jt = (kn * dt - knt * dn) / det;
    double px = jn * nx + jt * tx;
    double py = jn * ny + jt * ty;
    A->vx = A->vx - px * A->inv_m;
    A->vy = A->vy - py * A->inv_m;
    A->om = A->om - (jn * ran + jt * rat) * A->inv_i;
    B->vx = B->vx + px * B->inv_m;
    B->vy = B->vy + py * B->inv_m;
    B->om = B->om + (jn * rbn + jt * rbt) * B->inv_i;
    if (cap < floor_ * floor_ && !pay_floor(A, B, (floor_ * floor_ - cap) / kn))
        m->unpaid = 1;
    return jn;
}

/* The impulse (kg m/s) of a contact of the feature (feature, i, j) at
 * (cx, cy) with normal (nx, ny) from A to B (both advanced to the contact
 * time): 0 when the material points do not approach and are not pressed
 * together, else the normal impulse j (velocities changed).  A fast contact
 * is frictionless and leaves at sep = max(e |vn|, min(|vn|, rest_speed)); a
 * slow pressed one hops (hop).  When the material points do not approach,
 * the centres' accelerations do not press them and a body of the pair
 * turns, the feature's gap polynomial decides whether they are pressed
 * (closing: the turn closes the gap, which would otherwise predict the same
 * contact again at once).  Never adds energy (docs/simulator.md, Impulse). */
double m2c_sim_contact_impulse(m2c_world *m, m2c_sim_body *A, m2c_sim_body *B, double cx, double cy, double nx,
                               double ny, int32_t feature, int32_t i, int32_t j)
{
    double vn = m2c_sim_normal_speed(A, B, cx, cy, nx, ny);
    double rest = m->s->rest_speed;
    int press = m2c_sim_pressed(A, B, nx, ny);
    if (!press && !(vn < 0.0) && (m2c_sim_turn_rate(A) > 0.0 || m2c_sim_turn_rate(B) > 0.0))
        press = m2c_sim_closing(m, A, B, feature, i, j);
    if (press && -vn < rest)
        return hop(m, A, B, cx, cy, nx, ny, vn);
    double imp = 0.0;
    if (vn < 0.0) {
        double ran = (cx - A->px) * ny - (cy - A->py) * nx;
        double rbn = (cx - B->px) * ny - (cy - B->py) * nx;
        double k = A->inv_m + B->inv_m + A->inv_i * ran * ran + B->inv_i * rbn * rbn;
        double e = A->e * B->e;
        double evn = e * -vn;
        double nvn = -vn;
        double lim = rest < nvn ? rest : nvn;                               /* Python's min(-vn, rest) */
        double sep = lim > evn ? lim : evn;                                 /* Python's max(e * -vn, lim) */
        imp = (sep - vn) / k;
        A->vx = A->vx - imp * A->inv_m * nx;
        A->vy = A->vy - imp * A->inv_m * ny;
        A->om = A->om - imp * A->inv_i * ran;
        B->vx = B->vx + imp * B->inv_m * nx;
        B->vy = B->vy + imp * B->inv_m * ny;
        B->om = B->om + imp * B->inv_i * rbn;
    }
    return imp;
}

/* n . t of a supported body's edge tangent t (0 for a fixed body). */
static inline double along(const m2c_sim_body *b, double nx, double ny)
{
    if (b->sup < 0)
        return 0.0;
    return nx * b->tx + ny * b->ty;
}

/* A slow contact of bodies held on their supports: each supported (on a
 * fixed body: a carried body is not) or fixed, approaching (vn < 0) slower
 * than rest_speed, not pressed, and an impulse along their edges can change
 * vn (kh > 0). */
int m2c_sim_held(const m2c_world *m, const m2c_sim_body *A, const m2c_sim_body *B, double nx, double ny, double vn)
{
    const m2c_sim_body *bodies = m->bodies;
    if (!((A->fixed || (A->sup >= 0 && bodies[A->sup].fixed))
          && (B->fixed || (B->sup >= 0 && bodies[B->sup].fixed))))
        return 0;
    if (!(vn < 0.0) || !(-vn < m->s->rest_speed) || m2c_sim_pressed(A, B, nx, ny))
        return 0;
    double ka = along(A, nx, ny);
    double kb = along(B, nx, ny);
    return A->inv_m * ka * ka + B->inv_m * kb * kb > 0.0;
}

/* The normal impulse j of a held contact (held): each supported body takes
 * only its part along its support's edge, dv = -+ j (n . t) t / m, and
 * keeps its support; the normal speed leaves at sep = max(e |vn|,
 * min(|vn|, rest_speed)) through kh = (n . tA)^2 / mA + (n . tB)^2 / mB.
 * The friction of each is set again for its new speed relative to its
 * support (slide_accel; support_relative: the support may move). */
double m2c_sim_held_impulse(const m2c_world *m, m2c_sim_body *A, m2c_sim_body *B, double nx, double ny, double vn)
{
    double ka = along(A, nx, ny);
    double kb = along(B, nx, ny);
    double k = A->inv_m * ka * ka + B->inv_m * kb * kb;
    double e = A->e * B->e;
    double evn = e * -vn;
    double nvn = -vn;
    double lim = m->s->rest_speed < nvn ? m->s->rest_speed : nvn;      /* Python's min(-vn, rest) */
    double sep = lim > evn ? lim : evn;                                 /* Python's max(e * -vn, lim) */
    double imp = (sep - vn) / k;
    if (A->sup >= 0) {
        double d = imp * A->inv_m * ka;
        A->vx = A->vx - d * A->tx;
        A->vy = A->vy - d * A->ty;
        double q, u, a;
        m2c_sim_support_relative(m, A, &q, &u, &a);
        m2c_sim_slide_accel(m, A, u);
    }
    if (B->sup >= 0) {
        double d = imp * B->inv_m * kb;
        B->vx = B->vx + d * B->tx;
        B->vy = B->vy + d * B->ty;
        double q, u, a;
        m2c_sim_support_relative(m, B, &q, &u, &a);
        m2c_sim_slide_accel(m, B, u);
    }
    return imp;
}

/* The impulse (kg m/s) of a contact of A and B, one of them (S) asleep:
 * first with S held as if fixed (its 1/m and 1/I zero); when that impulse
 * would change the normal speed of S's material point by less than
 * rest_speed and no hop of it was unpaid, it stands (S stays asleep,
 * unchanged: a gentle touch); else the other body's velocity is restored
 * and the full impulse is applied (S moves: jolted, it wakes with what rests on it).
 * When the other body is fixed (it moves or turns: a sleeper is never
 * predicted against an unmoving one) S cannot be held (the pair would have
 * no mass): the full impulse at once.  Returns the impulse applied. */
double m2c_sim_sleeper_impulse(m2c_world *m, m2c_sim_body *A, m2c_sim_body *B, double cx, double cy, double nx,
                               double ny, int32_t feature, int32_t i, int32_t j)
{
    m2c_sim_body *S = A->asleep ? A : B;
    m2c_sim_body *M = A->asleep ? B : A;
    if (M->fixed)
        return m2c_sim_contact_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
    double vx = M->vx, vy = M->vy, om = M->om;
    double inv_m = S->inv_m, inv_i = S->inv_i;
    S->inv_m = 0.0;
    S->inv_i = 0.0;
    m->unpaid = 0;
    double imp = m2c_sim_contact_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
    S->inv_m = inv_m;
    S->inv_i = inv_i;
    double rsn = (cx - S->px) * ny - (cy - S->py) * nx;
    if ((imp * (S->inv_m + S->inv_i * rsn * rsn) < m->s->rest_speed && !m->unpaid) || m2c_sim_held_now(m, S))
        return imp;
    M->vx = vx;
    M->vy = vy;
    M->om = om;
    return m2c_sim_contact_impulse(m, A, B, cx, cy, nx, ny, feature, i, j);
}
