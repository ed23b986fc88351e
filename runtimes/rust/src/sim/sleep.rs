//! Sleeping islands (docs/simulator.md, "Contact model: sleeping
//! islands"): when a body falls asleep.  The reference's `grounded`,
//! `at_rest`, `can_sleep`; the handlers (`handle_sleep`, `handle_wake`,
//! `predict_woken`) are the world's (handlers.rs).

use super::scene::Body;
use super::support::{flat, is_static};
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
        return flat(w, &bodies[ev.a], &bodies[ev.b], ev.i, ev.j, -nx, -ny, load);
    }
    true
}
