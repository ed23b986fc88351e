//! Sleeping islands (docs/simulator.md, "Contact model: sleeping
//! islands"): when a body falls asleep.  The reference's `grounded`,
//! `at_rest`, `can_sleep`; the handlers (`handle_sleep`, `handle_wake`,
//! `predict_woken`) are the world's (handlers.rs).

use super::motion::point_at;
use super::scene::Body;
use super::support::{flat, is_static, support_frame};
use super::world::{RestContact, Space};
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
    let bodies = &w.s.bodies;
    let (m_, g_) = (&bodies[m], &bodies[g]);
    if m_.fixed || m_.asleep {
        return false;
    }
    let (mx, my) = if m == ev.a { (nx, ny) } else { (-nx, -ny) };
    let rest = w.s.rest_speed;
    let load = m_.fax * mx + m_.fay * my;
    if !(load > 0.0) || vn >= rest || m_.e * g_.e * -vn >= rest {
        return false;
    }
    let ut = m_.vy * mx - m_.vx * my;
    if ut * ut >= rest * rest {
        return false;
    }
    !m_.polygon || m_.om.abs() * m_.bound < rest
}

/// Keeps the contact of ev at (cx, cy) as M's last slow pressing contact,
/// with G's and M's positions and angles now; the one before, when it was
/// with another body, is kept too.
#[allow(clippy::too_many_arguments)]
pub fn note_rest(w: &mut Space, m: usize, g: usize, ev: Touch, cx: f64, cy: f64, nx: f64, ny: f64) {
    let (m_, g_) = (&w.s.bodies[m], &w.s.bodies[g]);
    let (mx, my) = if m == ev.a { (nx, ny) } else { (-nx, -ny) };
    let r = RestContact {
        px: cx,
        py: cy,
        mx,
        my,
        load: m_.fax * mx + m_.fay * my,
        gx: g_.px,
        gy: g_.py,
        gang: g_.ang,
        bx: m_.px,
        by: m_.py,
        bang: m_.ang,
        other1: g as i32 + 1,
    };
    let slots = &mut w.restc[m];
    if slots[0].other1 != g as i32 + 1 {
        slots[1] = slots[0];
    }
    slots[0] = r;
}

/// M's last slow pressing contact with a body other than G, if any.
pub fn rest_other(w: &Space, m: usize, g: usize) -> Option<RestContact> {
    let slots = &w.restc[m];
    let r = if slots[0].other1 - 1 == g as i32 { slots[1] } else { slots[0] };
    (r.other1 != 0 && r.other1 - 1 != g as i32).then_some(r)
}

/// A contact force along (gx, gy) at a contact of unit normal (mx, my) lies
/// in the friction cone: c > 0 and |m x g| <= mu c.
fn in_cone(mx: f64, my: f64, gx: f64, gy: f64, mu: f64) -> bool {
    let c = mx * gx + my * gy;
    let s = (mx * gy - my * gx).abs();
    c > 0.0 && !(s > mu * c)
}

/// Awake movable M, in the slow pressing contact of ev with grounded G at
/// (cx, cy), falls asleep on two supports (docs/simulator.md, "Two
/// supports"): its last slow pressing contact with another body G1 that is
/// grounded and has not moved since; M has moved less than the face
/// tolerance since (its centre, and its angle times its bound); both
/// contacts can push along M's free acceleration within their friction
/// cones, and M's centre lies strictly between the two contact points
/// across that direction (by more than the tolerance).
#[allow(clippy::too_many_arguments)]
pub fn can_sleep_two(w: &Space, m: usize, g: usize, ev: Touch, cx: f64, cy: f64, nx: f64, ny: f64, vn: f64) -> bool {
    let bodies = &w.s.bodies;
    if !grounded(&bodies[g]) || !slow_press(w, m, g, ev, nx, ny, vn) {
        return false;
    }
    let Some(r) = rest_other(w, m, g) else {
        return false;
    };
    let (m_, g_, g1) = (&bodies[m], &bodies[g], &bodies[(r.other1 - 1) as usize]);
    if g1.gone || !grounded(g1) || g1.px != r.gx || g1.py != r.gy || g1.ang != r.gang {
        return false;
    }
    let (tol, r2) = (w.s.tol, w.s.rest_speed * w.s.rest_speed / r.load);
    let ftol = if r2 > tol { r2 } else { tol }; // C's fmax(tol, r2)
    let (dx, dy) = (m_.px - r.bx, m_.py - r.by);
    if dx * dx + dy * dy > ftol * ftol || (m_.ang - r.bang).abs() * m_.bound > ftol {
        return false;
    }
    let fa = (m_.fax * m_.fax + m_.fay * m_.fay).sqrt();
    let (gx, gy) = (m_.fax / fa, m_.fay / fa);
    let (mx, my) = if m == ev.a { (nx, ny) } else { (-nx, -ny) };
    if !in_cone(r.mx, r.my, gx, gy, m_.mu * g1.mu) || !in_cone(mx, my, gx, gy, m_.mu * g_.mu) {
        return false;
    }
    let x1 = (r.px - m_.px) * -gy + (r.py - m_.py) * gx;
    let x2 = (cx - m_.px) * -gy + (cy - m_.py) * gx;
    (x1 < -tol && x2 > tol) || (x1 > tol && x2 < -tol)
}
