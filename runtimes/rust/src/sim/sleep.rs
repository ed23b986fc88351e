//! Sleeping islands (docs/simulator.md, "Contact model: sleeping
//! islands"): when a body falls asleep.  The reference's `grounded`,
//! `at_rest`, `can_sleep`; the handlers (`handle_sleep`, `handle_wake`,
//! `predict_woken`) are the world's (handlers.rs).

use super::motion::point_at;
use super::scene::Body;
use super::support::{flat, is_static, support_frame};
use super::world::{RestContact, Space, REST_SLOTS};
use super::PE;

/// A body others can fall asleep on: asleep, or fixed and unmoving.
#[inline(always)]
pub fn grounded(g_: &Body) -> bool {
    g_.asleep || (g_.fixed && is_static(g_))
}

/// A body supported by an unmoving body (`sup`), slower than rest_speed
/// along its edge, that static friction would hold there (|at| <= mu load,
/// as in slide_accel at u = 0; on a level frictionless edge at = 0): it
/// stays where it is.  On a moving support: never (it does not sleep); nor
/// on a movable one (carried: grounded is false while it carries).
pub fn at_rest(a_: &Body, sup: &Body, rest_speed: f64) -> bool {
    if !grounded(sup) {
        return false;
    }
    let u = a_.vx * a_.tx + a_.vy * a_.ty;
    if !(u * u < rest_speed * rest_speed) {
        return false;
    }
    let f = a_.mu * sup.mu * a_.load;
    !(a_.at > f) && !(a_.at < -f)
}

/// A sleeper an impulse has set moving.
#[inline(always)]
pub fn jolted(s_: &Body) -> bool {
    s_.vx != 0.0 || s_.vy != 0.0 || s_.om != 0.0
}

/// The collision a sleep is judged on: bodies a, b, feature, vertex i, edge j.
#[derive(Clone, Copy)]
pub struct Touch {
    pub a: usize,
    pub b: usize,
    pub feature: i32,
    pub i: i32,
    pub j: i32,
}

/// Awake movable M (body m), one body of the collision ev with grounded G
/// (body g; both advanced; (nx, ny) the contact's unit normal from ev.a to
/// ev.b, vn its normal speed), falls asleep on G: M's free acceleration
/// presses it onto G (load > 0), the contact is slow (vn < rest_speed and
/// eM eG (-vn) < rest_speed), M's speed across the normal is below
/// rest_speed, and a polygon M turns slower than rest_speed / bound and
/// lies on a face: a vertex-edge contact with a neighbour of the vertex on
/// the edge's line (`flat`, whichever body has the vertex).
#[allow(clippy::too_many_arguments)]
pub fn can_sleep(w: &Space, m: usize, g: usize, ev: Touch, nx: f64, ny: f64, vn: f64) -> bool {
    let bodies = &w.s.bodies;
    let m_ = &bodies[m];
    if !grounded(&bodies[g]) || !slow_press(w, m, g, ev, nx, ny, vn) {
        return false;
    }
    if m_.polygon {
        if ev.feature != PE || ev.i < 0 {
            return false;
        }
        let (mx, my) = if m == ev.a { (nx, ny) } else { (-nx, -ny) };
        let load = m_.fax * mx + m_.fay * my;
        let (v_, e_) = (&bodies[ev.a], &bodies[ev.b]);
        return flat(w, v_, e_, ev.i, ev.j, -nx, -ny, load) && over_face(w, m_, v_, e_, ev.i, ev.j, load);
    }
    true
}

/// M's centre of mass projects inside the support segment of the contact of
/// V's vertex i on E's edge j, shrunk by the tolerance: along the edge's
/// tangent t, the overlap of the edge [s1, s2] with V's face (vertex i and
/// each neighbour on the edge's line within the face tolerance of `flat`),
/// all relative to E's centre.  A polygon whose centre lies past its
/// support's end would tip: it does not sleep.
#[allow(clippy::too_many_arguments)]
fn over_face(w: &Space, m_: &Body, v_: &Body, e_: &Body, i: i32, j: i32, load: f64) -> bool {
    let s = &w.s;
    let (tx, ty, ox, oy) = support_frame(&s.verts, e_, j);
    let (tol, r2) = (s.tol, s.rest_speed * s.rest_speed / load);
    // Python's max(tol, r2)
    let ftol = if r2 > tol { r2 } else { tol };
    let ed = &s.verts[e_.vert(j as usize)];
    let h = ed.h;
    let i = i as usize;
    let (px, py) = point_at(v_, Some(&s.verts[v_.vert(i)]), v_.tb);
    let mut lo = (px - e_.px) * tx + (py - e_.py) * ty;
    let mut hi = lo;
    let n = v_.nverts();
    for k in [(i + n - 1) % n, (i + 1) % n] {
        let (px, py) = point_at(v_, Some(&s.verts[v_.vert(k)]), v_.tb);
        if (px - e_.px) * ox + (py - e_.py) * oy - h <= ftol {
            let q = (px - e_.px) * tx + (py - e_.py) * ty;
            if q < lo {
                lo = q;
            }
            if q > hi {
                hi = q;
            }
        }
    }
    if ed.s1 > lo {
        lo = ed.s1;
    }
    if ed.s2 < hi {
        hi = ed.s2;
    }
    let c = (m_.px - e_.px) * tx + (m_.py - e_.py) * ty;
    !(c < lo + tol) && !(c > hi - tol)
}

/// The contact of ev of awake movable M (body m) with G (body g) is slow and
/// presses M onto G: M's free acceleration has a positive load along the
/// normal from M to G, vn < rest_speed and eM eG (-vn) < rest_speed, M's
/// speed across the normal is below rest_speed, and a polygon M turns
/// slower than rest_speed / bound.
pub fn slow_press(w: &Space, m: usize, g: usize, ev: Touch, nx: f64, ny: f64, vn: f64) -> bool {
    let m_ = &w.s.bodies[m];
    if m_.fixed || m_.asleep {
        return false;
    }
    let (mx, my) = if m == ev.a { (nx, ny) } else { (-nx, -ny) };
    let load = m_.fax * mx + m_.fay * my;
    load > 0.0 && slow_touch(w, m, g, ev, nx, ny, vn)
}

/// The contact of ev of awake movable M with G is slow: [`slow_press`]
/// without the load (a contact across M's free acceleration, a wall a box
/// leans on, counts).
pub fn slow_touch(w: &Space, m: usize, g: usize, ev: Touch, nx: f64, ny: f64, vn: f64) -> bool {
    let bodies = &w.s.bodies;
    let (m_, g_) = (&bodies[m], &bodies[g]);
    if m_.fixed || m_.asleep {
        return false;
    }
    let (mx, my) = if m == ev.a { (nx, ny) } else { (-nx, -ny) };
    let rest = w.s.rest_speed;
    if vn >= rest || m_.e * g_.e * -vn >= rest {
        return false;
    }
    let ut = m_.vy * mx - m_.vx * my;
    if ut * ut >= rest * rest {
        return false;
    }
    !m_.polygon || m_.om.abs() * m_.bound < rest
}

fn same_key(r: &RestContact, q: &RestContact) -> bool {
    r.other1 == q.other1 && r.feature == q.feature && r.i == q.i && r.j == q.j && r.side == q.side
}

/// With G grounded, keeps the slow contact of ev at (cx, cy) first among M's last
/// [`REST_SLOTS`] slow contacts (distinct by the other body, ev's feature,
/// i, j and which side M is), with G's and M's positions and angles now:
/// an earlier one with the same key leaves its place, the others move down
/// one, the oldest beyond the slots is dropped.
#[allow(clippy::too_many_arguments)]
pub fn note_rest(w: &mut Space, m: usize, g: usize, ev: Touch, cx: f64, cy: f64, nx: f64, ny: f64) {
    let (m_, g_) = (&w.s.bodies[m], &w.s.bodies[g]);
    if !grounded(g_) {
        return; // an awake body moves: a contact with it would not hold
    }
    let side = m == ev.a;
    let (mx, my) = if side { (nx, ny) } else { (-nx, -ny) };
    let r = RestContact {
        px: cx,
        py: cy,
        mx,
        my,
        gx: g_.px,
        gy: g_.py,
        gang: g_.ang,
        bx: m_.px,
        by: m_.py,
        bang: m_.ang,
        other1: g as i32 + 1,
        feature: ev.feature,
        i: ev.i,
        j: ev.j,
        side,
    };
    let slots = &mut w.restc[m];
    let mut k = 0;
    while k < REST_SLOTS - 1 && slots[k].other1 != 0 && !same_key(&slots[k], &r) {
        k += 1;
    }
    while k > 0 {
        slots[k] = slots[k - 1];
        k -= 1;
    }
    slots[0] = r;
}

/// M's noted slow contacts that still hold, in slot order, but the one with
/// ev's key: the other body is not removed, grounded, at the position and
/// angle noted (bit for bit), and M has moved less than ftol since (its
/// centre, and its angle times its bound).  Their slot numbers go to held;
/// returns how many.
fn holding(w: &Space, m: usize, ev: Touch, ftol: f64, held: &mut [usize; REST_SLOTS]) -> usize {
    let bodies = &w.s.bodies;
    let m_ = &bodies[m];
    let side = m == ev.a;
    let other1 = (if side { ev.b } else { ev.a }) as i32 + 1;
    let mut n = 0;
    for (k, r) in w.restc[m].iter().enumerate() {
        if r.other1 == 0 {
            break;
        }
        if r.other1 == other1 && r.feature == ev.feature && r.i == ev.i && r.j == ev.j && r.side == side {
            continue;
        }
        let o = &bodies[(r.other1 - 1) as usize];
        if o.gone || !grounded(o) || o.px != r.gx || o.py != r.gy || o.ang != r.gang {
            continue;
        }
        let (dx, dy) = (m_.px - r.bx, m_.py - r.by);
        if dx * dx + dy * dy > ftol * ftol || (m_.ang - r.bang).abs() * m_.bound > ftol {
            continue;
        }
        held[n] = k;
        n += 1;
    }
    n
}

#[inline(always)]
fn cross3(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

#[inline(always)]
fn dot3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The contacts (px, py, mx, my, mu) of M (unit normal m from M to the
/// other body) admit a static equilibrium with a margin: each of four
/// targets T is a combination with coefficients >= 0 of the contact rays
/// (per contact -m + mu t and -m - mu t, t = (-my, mx); -m alone when
/// mu = 0), each ray written (dx, dy, (p - pM) x d).  By Caratheodory a
/// target in the cone of the rays lies in the cone of three independent
/// ones: the triples i < j < k are tried with Cramer's rule until every
/// target is found in one (docs/simulator.md, "Several contacts").
fn balanced(m_: &Body, pts: &[[f64; 5]], fa: f64, tol: f64) -> bool {
    let mut rays = [[0.0f64; 3]; 2 * (REST_SLOTS + 1)];
    let mut n = 0;
    for p in pts {
        let (rx, ry) = (p[0] - m_.px, p[1] - m_.py);
        let (mx, my, mu) = (p[2], p[3], p[4]);
        if mu > 0.0 {
            let (dx, dy) = (-mx - mu * my, -my + mu * mx);
            rays[n] = [dx, dy, rx * dy - ry * dx];
            n += 1;
            let (dx, dy) = (-mx + mu * my, -my - mu * mx);
            rays[n] = [dx, dy, rx * dy - ry * dx];
            n += 1;
        } else {
            let (dx, dy) = (-mx, -my);
            rays[n] = [dx, dy, rx * dy - ry * dx];
            n += 1;
        }
    }
    if n < 3 {
        return false;
    }
    let e = tol / m_.bound;
    let (wx, wy) = (-e * m_.fay, e * m_.fax);
    let tq = fa * tol;
    let targets = [
        [-m_.fax + wx, -m_.fay + wy, 0.0],
        [-m_.fax - wx, -m_.fay - wy, 0.0],
        [-m_.fax, -m_.fay, tq],
        [-m_.fax, -m_.fay, -tq],
    ];
    let mut found = [false; 4];
    let mut left = 4;
    for i in 0..n - 2 {
        for j in i + 1..n - 1 {
            let cij = cross3(&rays[i], &rays[j]);
            for k in j + 1..n {
                let cjk = cross3(&rays[j], &rays[k]);
                let cki = cross3(&rays[k], &rays[i]);
                let d = dot3(&rays[i], &cjk);
                if !(d > 0.0) && !(d < 0.0) {
                    continue;
                }
                for q in 0..4 {
                    if found[q] {
                        continue;
                    }
                    let t = &targets[q];
                    let (li, lj, lk) = (dot3(t, &cjk), dot3(t, &cki), dot3(t, &cij));
                    let out = if d > 0.0 { li < 0.0 || lj < 0.0 || lk < 0.0 } else { li > 0.0 || lj > 0.0 || lk > 0.0 };
                    if out {
                        continue;
                    }
                    found[q] = true;
                    left -= 1;
                    if left == 0 {
                        return true;
                    }
                }
            }
        }
    }
    false
}

/// The face tolerance of the noted contacts: max(tol, rest_speed^2 / |faM|).
fn rest_ftol(w: &Space, m_: &Body) -> (f64, f64) {
    let fa = (m_.fax * m_.fax + m_.fay * m_.fay).sqrt();
    let (tol, r2) = (w.s.tol, w.s.rest_speed * w.s.rest_speed / fa);
    (fa, if r2 > tol { r2 } else { tol }) // C's fmax(tol, r2)
}

/// Awake movable M, in the slow pressing contact of ev with grounded G at
/// (cx, cy), falls asleep resting on several contacts (docs/simulator.md,
/// "Several contacts"): this contact and M's noted ones that still hold
/// ([`holding`]) admit a static equilibrium with a margin ([`balanced`]).
#[allow(clippy::too_many_arguments)]
pub fn can_sleep_many(w: &Space, m: usize, g: usize, ev: Touch, cx: f64, cy: f64, nx: f64, ny: f64, vn: f64) -> bool {
    let bodies = &w.s.bodies;
    if !grounded(&bodies[g]) || !slow_press(w, m, g, ev, nx, ny, vn) {
        return false;
    }
    let m_ = &bodies[m];
    let (fa, ftol) = rest_ftol(w, m_);
    let mut held = [0usize; REST_SLOTS];
    let nh = holding(w, m, ev, ftol, &mut held);
    if nh == 0 {
        return false;
    }
    let (mx, my) = if m == ev.a { (nx, ny) } else { (-nx, -ny) };
    let mut pts = [[0.0f64; 5]; REST_SLOTS + 1];
    pts[0] = [cx, cy, mx, my, m_.mu * bodies[g].mu];
    let slots = &w.restc[m];
    for h in 0..nh {
        let r = &slots[held[h]];
        pts[h + 1] = [r.px, r.py, r.mx, r.my, m_.mu * bodies[(r.other1 - 1) as usize].mu];
    }
    balanced(m_, &pts[..nh + 1], fa, w.s.tol)
}

/// The bodies of M's noted contacts that still hold (in slot order), for
/// what M rests on when it falls asleep on several contacts.
pub fn holding_bodies(w: &Space, m: usize, ev: Touch) -> ([usize; REST_SLOTS], usize) {
    let (_, ftol) = rest_ftol(w, &w.s.bodies[m]);
    let mut held = [0usize; REST_SLOTS];
    let nh = holding(w, m, ev, ftol, &mut held);
    let mut others = [0usize; REST_SLOTS];
    for h in 0..nh {
        others[h] = (w.restc[m][held[h]].other1 - 1) as usize;
    }
    (others, nh)
}
