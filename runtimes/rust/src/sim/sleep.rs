//! Sleeping islands (docs/simulator.md, "Contact model: sleeping
//! islands"): when a body falls asleep.  The reference's `grounded`,
//! `at_rest`, `can_sleep`; the handlers (`handle_sleep`, `handle_wake`,
//! `predict_woken`) are the world's (handlers.rs).

use super::motion::point_at;
use super::scene::Body;
use super::support::{flat, is_static, support_frame};
use super::world::Space;
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
    let (m_, g_) = (&bodies[m], &bodies[g]);
    if m_.fixed || m_.asleep || !grounded(g_) {
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
    if m_.polygon {
        if m_.om.abs() * m_.bound >= rest || ev.feature != PE || ev.i < 0 {
            return false;
        }
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
