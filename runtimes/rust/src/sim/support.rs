//! Support: a movable body resting and sliding on an edge of a fixed
//! polygon, with Coulomb friction (docs/simulator.md, "Contact model:
//! supported, sliding, friction"), or carried at rest on a movable polygon
//! that does not turn ("Carried bodies").  A supported or carried body's
//! motion stays `p + v dt + a dt^2/2`, so every generated equation predicts
//! it unchanged.

use super::motion::{point_at, state_at};
use super::queue::Event;
use super::scene::{Body, Vertex};
use super::world::{Queue, Space};
use super::PE;
use crate::roots::smallest_root;

/// Unit tangent (tx, ty) and outward unit normal (ox, oy) of edge j of B in
/// the world (B does not turn).
#[inline]
pub fn support_frame(verts: &[Vertex], b_: &Body, j: i32) -> (f64, f64, f64, f64) {
    let ed = &verts[b_.vert(j as usize)];
    let c = b_.ang.cos();
    let s = b_.ang.sin();
    let ox = c * ed.nx - s * ed.ny;
    let oy = s * ed.nx + c * ed.ny;
    (-oy, ox, ox, oy)
}

/// The body does not move (the reference's `static`).
#[inline]
pub fn is_static(b_: &Body) -> bool {
    b_.vx == 0.0 && b_.vy == 0.0 && b_.ax == 0.0 && b_.ay == 0.0 && b_.om == 0.0
}

/// A point-edge contact of movable A on edge j of a fixed polygon B that
/// does not turn (it may translate) becomes support, everything relative to
/// B (both advanced to now; vn from `normal_speed`).
#[allow(clippy::too_many_arguments)]
pub fn can_support(w: &Space, a_: &Body, b_: &Body, feature: i32, i: i32, j: i32, vn: f64) -> bool {
    if feature != PE || a_.fixed || !b_.fixed || b_.om != 0.0 {
        return false;
    }
    supportable(w, a_, b_, i, j, vn)
}

/// Acceleration along an edge of a body sliding at u relative to it: the
/// free part `at` less Coulomb friction f (mu times the load) against the
/// motion; at relative rest none while static friction holds.
#[inline]
fn friction_accel(at: f64, f: f64, u: f64) -> f64 {
    if u > 0.0 {
        at - f
    } else if u < 0.0 {
        at + f
    } else if at > f {
        at - f
    } else if at < -f {
        at + f
    } else {
        0.0
    }
}

/// Sleeping base B (at rest on edge frame (B.tx, B.ty) of fixed body
/// `w.rest[B]`) stays at rest under its free acceleration, the force
/// (px, py) and the force of each body supported on it (by index, its
/// reaction -m (a - fa)): the resting contact's normal force
/// n = -(mB faB + P) . o is positive and its tangential force
/// t = -(mB faB + P) . t lies within static friction, |t| <= mu n.
pub fn base_holds(w: &Space, b_: &Body, mut px: f64, mut py: f64) -> bool {
    let bodies = &w.s.bodies;
    if b_.carry > 0 {
        for r_ in bodies.iter() {
            if r_.sup == b_.idx as i32 {
                px -= (r_.ax - r_.fax) / r_.inv_m;
                py -= (r_.ay - r_.fay) / r_.inv_m;
            }
        }
    }
    let mb = 1.0 / b_.inv_m;
    let fx = mb * b_.fax + px;
    let fy = mb * b_.fay + py;
    let n = -(fx * b_.ty - fy * b_.tx);
    let t = -(fx * b_.tx + fy * b_.ty);
    let f = b_.mu * bodies[w.rest[b_.idx as usize] as usize].mu * n;
    n > 0.0 && !(t > f) && !(t < -f)
}

/// A point-edge contact of movable A on edge j of a sleeping polygon B that
/// fell asleep supported on a fixed body (`w.rest`) becomes support on B,
/// as on a fixed body that does not move (docs/simulator.md, "Sliding on a
/// sleeping base"), when B's resting contact holds the force A's sliding
/// puts on B besides B's other riders (`base_holds`).
#[allow(clippy::too_many_arguments)]
pub fn can_ride(w: &Space, a_: &Body, b_: &Body, feature: i32, i: i32, j: i32, vn: f64) -> bool {
    if feature != PE || a_.fixed || !b_.asleep || w.rest[b_.idx as usize] < 0 || !b_.polygon {
        return false;
    }
    if !supportable(w, a_, b_, i, j, vn) {
        return false;
    }
    let (tx, ty, ox, oy) = support_frame(&w.s.verts, b_, j);
    let u = a_.vx * tx + a_.vy * ty;
    let a = friction_accel(a_.fax * tx + a_.fay * ty, a_.mu * b_.mu * -(a_.fax * ox + a_.fay * oy), u);
    base_holds(w, b_, -(a * tx - a_.fax) / a_.inv_m, -(a * ty - a_.fay) / a_.inv_m)
}

/// The checks of can_support after the bodies' kinds: pressed onto edge j,
/// slow, over the edge and not leaving it, a polygon flat on it.
fn supportable(w: &Space, a_: &Body, b_: &Body, i: i32, j: i32, vn: f64) -> bool {
    let s = &w.s;
    let (tx, ty, ox, oy) = support_frame(&s.verts, b_, j);
    let load = -((a_.fax - b_.ax) * ox + (a_.fay - b_.ay) * oy);
    let rest = s.rest_speed;
    if !(load > 0.0) || vn >= rest || a_.e * b_.e * -vn >= rest {
        return false;
    }
    let ed = &s.verts[b_.vert(j as usize)];
    let q = (a_.px - b_.px) * tx + (a_.py - b_.py) * ty;
    if q < ed.s1 || q > ed.s2 {
        return false;
    }
    // at an end of the edge (within the tolerance) and moving past it: it
    // is leaving (a support would end at once, again and again)
    let u = (a_.vx - b_.vx) * tx + (a_.vy - b_.vy) * ty;
    let tol = s.tol;
    if (u > 0.0 && q >= ed.s2 - tol) || (u < 0.0 && q <= ed.s1 + tol) {
        return false;
    }
    if a_.polygon {
        if a_.om.abs() * a_.bound >= rest {
            return false;
        }
        return flat(w, a_, b_, i, j, ox, oy, load);
    }
    true
}

/// A neighbour of A's vertex i lies on edge j's line within the face
/// tolerance max(tol, rest_speed^2 / load): A rests on a face.
#[allow(clippy::too_many_arguments)]
pub(super) fn flat(w: &Space, a_: &Body, b_: &Body, i: i32, j: i32, ox: f64, oy: f64, load: f64) -> bool {
    let s = &w.s;
    let (tol, r2) = (s.tol, s.rest_speed * s.rest_speed / load);
    // Python's max(tol, r2)
    let ftol = if r2 > tol { r2 } else { tol };
    let n = a_.nverts();
    let h = s.verts[b_.vert(j as usize)].h;
    let i = i as usize;
    for k in [(i + n - 1) % n, (i + 1) % n] {
        let (px, py) = point_at(a_, Some(&s.verts[a_.vert(k)]), a_.tb);
        if (px - b_.px) * ox + (py - b_.py) * oy - h <= ftol {
            return true;
        }
    }
    false
}

/// A (advanced to now, as B) keeps only its velocity relative to B along
/// edge j of B, stops turning, and from now on accelerates relative to B
/// along the edge only.
pub fn enter_support(verts: &[Vertex], a_: &mut Body, b_: &Body, j: i32) {
    let (tx, ty, ox, oy) = support_frame(verts, b_, j);
    let u = (a_.vx - b_.vx) * tx + (a_.vy - b_.vy) * ty;
    if is_static(b_) {
        a_.vx = u * tx;
        a_.vy = u * ty;
    } else {
        a_.vx = b_.vx + u * tx;
        a_.vy = b_.vy + u * ty;
    }
    if a_.polygon {
        a_.om = 0.0;
    }
    a_.sup = b_.idx as i32;
    a_.sup_edge = j;
    a_.tx = tx;
    a_.ty = ty;
    a_.load = -((a_.fax - b_.ax) * ox + (a_.fay - b_.ay) * oy);
    a_.at = (a_.fax - b_.ax) * tx + (a_.fay - b_.ay) * ty;
    slide_accel(a_, b_, u);
}

/// Acceleration of supported A with tangential speed u relative to its
/// support B (`sup`): the relative free acceleration along the edge less
/// Coulomb friction mu |a_n| against the relative motion; at relative
/// rest, none while friction can hold it; plus B's acceleration when B
/// moves.
pub fn slide_accel(a_: &mut Body, sup: &Body, u: f64) {
    let a = friction_accel(a_.at, a_.mu * sup.mu * a_.load, u);
    if is_static(sup) {
        a_.ax = a * a_.tx;
        a_.ay = a * a_.ty;
    } else {
        a_.ax = sup.ax + a * a_.tx;
        a_.ay = sup.ay + a * a_.ty;
    }
}

/// Body a's support (or carrier) ends: its free acceleration again (a
/// carrier counts one body less); `bodies` is the scene's.
pub fn end_support(bodies: &mut [Body], a: usize) {
    let sup = bodies[a].sup as usize;
    if !bodies[sup].fixed {
        bodies[sup].carry -= 1;
    }
    let a_ = &mut bodies[a];
    a_.ax = a_.fax;
    a_.ay = a_.fay;
    a_.sup = -1;
    a_.sup_edge = -1;
}

// ---- carried: at rest on a movable body that does not turn -----------------------

/// A point-edge contact of movable A on edge j of a movable polygon B that
/// does not turn and is itself supported or carried (its motion a
/// polynomial: constant acceleration) becomes carrying (docs/simulator.md,
/// "Carried bodies"); both advanced.  As can_support, everything relative
/// to B: load = -((fa - aB) . o) > 0, slow (vn < rest_speed, eA eB (-vn) <
/// rest_speed), A's centre over the edge; and A at relative rest along it
/// (u = (vA - vB) . t, u^2 < rest_speed^2) where static friction holds it
/// (|at| <= muA muB load, at = (fa - aB) . t), B not carried by A (no
/// loop), and |vB|^2 <= |vA|^2: taking B's velocity never raises A's
/// kinetic energy.  A polygon also turns slower than rest_speed / bound
/// and lies on a face (`flat`).
#[allow(clippy::too_many_arguments)]
pub fn can_carry(w: &Space, a_: &Body, b_: &Body, feature: i32, i: i32, j: i32, vn: f64) -> bool {
    if feature != PE || a_.fixed || b_.fixed || !b_.polygon || b_.om != 0.0 || b_.sup < 0 {
        return false;
    }
    let s = &w.s;
    let mut k = b_.sup;
    while k >= 0 {
        if k == a_.idx as i32 {
            return false;
        }
        k = s.bodies[k as usize].sup;
    }
    let (tx, ty, ox, oy) = support_frame(&s.verts, b_, j);
    let load = -((a_.fax - b_.ax) * ox + (a_.fay - b_.ay) * oy);
    let rest = s.rest_speed;
    if !(load > 0.0) || vn >= rest || a_.e * b_.e * -vn >= rest {
        return false;
    }
    let ed = &s.verts[b_.vert(j as usize)];
    let q = (a_.px - b_.px) * tx + (a_.py - b_.py) * ty;
    if q < ed.s1 || q > ed.s2 {
        return false;
    }
    let u = (a_.vx - b_.vx) * tx + (a_.vy - b_.vy) * ty;
    if !(u * u < rest * rest) {
        return false;
    }
    let at = (a_.fax - b_.ax) * tx + (a_.fay - b_.ay) * ty;
    let f = a_.mu * b_.mu * load;
    if at > f || at < -f {
        return false;
    }
    if b_.vx * b_.vx + b_.vy * b_.vy > a_.vx * a_.vx + a_.vy * a_.vy {
        return false;
    }
    if a_.polygon {
        if a_.om.abs() * a_.bound >= rest {
            return false;
        }
        return flat(w, a_, b_, i, j, ox, oy, load);
    }
    true
}

/// A (advanced to now, as B) moves with B from now on: B's velocity and
/// acceleration exactly (its offset from B constant), no turn; B counts it
/// (`carry`).
pub fn enter_carried(verts: &[Vertex], a_: &mut Body, b_: &mut Body, j: i32) {
    let (tx, ty, ox, oy) = support_frame(verts, b_, j);
    a_.vx = b_.vx;
    a_.vy = b_.vy;
    if a_.polygon {
        a_.om = 0.0;
    }
    a_.sup = b_.idx as i32;
    a_.sup_edge = j;
    a_.tx = tx;
    a_.ty = ty;
    a_.load = -((a_.fax - b_.ax) * ox + (a_.fay - b_.ay) * oy);
    a_.at = (a_.fax - b_.ax) * tx + (a_.fay - b_.ay) * ty;
    a_.ax = b_.ax;
    a_.ay = b_.ay;
    b_.carry += 1;
}

/// Supported b's motion relative to its support `sup` along the edge, at
/// b's time: (q, u, a), q the centre's coordinate along the tangent from
/// the support's centre, u, a its speed and acceleration.
#[inline]
pub fn support_relative(b: &Body, sup: &Body) -> (f64, f64, f64) {
    let (bx, by, bvx, bvy, _) = state_at(sup, b.tb);
    let q = (b.px - bx) * b.tx + (b.py - by) * b.ty;
    let u = (b.vx - bvx) * b.tx + (b.vy - bvy) * b.ty;
    let a = (b.ax - sup.ax) * b.tx + (b.ay - sup.ay) * b.ty;
    (q, u, a)
}

/// A supported body's stop (its tangential speed relative to the support
/// reaches zero) and leave (its centre, projected on the edge, reaches an
/// end) events.
pub fn schedule_support(w: &Space, q: &mut Queue, bi: usize) {
    let s = &w.s;
    let b = &s.bodies[bi];
    let stamp = w.stamps[bi];
    let sup = &s.bodies[b.sup as usize];
    let (p, u, a) = support_relative(b, sup);
    if u != 0.0 && a != 0.0 && (u > 0.0) != (a > 0.0) {
        q.heap.push(b.tb + -u / a, Event::Stop { body: b.idx, stamp });
    }
    let ed = &s.verts[sup.vert(b.sup_edge as usize)];
    let hi = s.end - b.tb;
    let mut s2 = first_crossing(p - ed.s2, u, a, 1, 0.0, hi);
    let s1 = first_crossing(p - ed.s1, u, a, -1, 0.0, hi);
    if let Some(x) = s1 {
        if s2.is_none_or(|y| x < y) {
            s2 = s1;
        }
    }
    if let Some(x) = s2 {
        q.heap.push(b.tb + x, Event::Leave { body: b.idx, stamp });
    }
}

/// The first u in [lo, hi] where p + v u + a u^2 / 2 crosses zero moving
/// in the direction (+1 up, -1 down).
fn first_crossing(p: f64, v: f64, a: f64, direction: i32, lo: f64, hi: f64) -> Option<f64> {
    let c = [p, v, 0.5 * a];
    let mut lo = lo;
    for _ in 0..3 {
        let u = smallest_root(&c, lo, hi)?;
        if (v + a * u) * f64::from(direction) > 0.0 {
            return Some(u);
        }
        lo = u;
    }
    None
}
