//! Motion between events: every body moves exactly, `p + (v + a dt/2) dt`,
//! `v + a dt`, `angle + w dt`, from its state at its own update time `tb`.

use super::scene::{Body, Vertex};

/// Carry the body's state to time t (only events do this: re-basing rounds).
#[inline(always)]
pub fn rebase(b: &mut Body, t: f64) {
    let dt = t - b.tb;
    b.px = b.px + (b.vx + 0.5 * b.ax * dt) * dt;
    b.py = b.py + (b.vy + 0.5 * b.ay * dt) * dt;
    b.vx = b.vx + b.ax * dt;
    b.vy = b.vy + b.ay * dt;
    b.ang = b.ang + b.om * dt;
    b.tb = t;
}

/// Centre, velocity and angle at time t (the body is not changed).
#[inline(always)]
pub fn state_at(b: &Body, t: f64) -> (f64, f64, f64, f64, f64) {
    let dt = t - b.tb;
    (
        b.px + (b.vx + 0.5 * b.ax * dt) * dt,
        b.py + (b.vy + 0.5 * b.ay * dt) * dt,
        b.vx + b.ax * dt,
        b.vy + b.ay * dt,
        b.ang + b.om * dt,
    )
}

/// rad/s: how fast the body's features turn (0 for a circle that does not orbit).
#[inline(always)]
pub fn turn_rate(b: &Body) -> f64 {
    if b.polygon || b.orbit > 0.0 {
        return b.om.abs();
    }
    0.0
}

/// World position of a circle's centre (v None) or of a vertex, at t.
#[inline(always)]
pub fn point_at(b: &Body, v: Option<&Vertex>, t: f64) -> (f64, f64) {
    let (x, y, _, _, ang) = state_at(b, t);
    match v {
        None => {
            let d = b.orbit;
            if d == 0.0 {
                return (x, y);
            }
            (x + d * (ang + b.ophase).cos(), y + d * (ang + b.ophase).sin())
        }
        Some(v) => {
            let d = v.rho;
            if d == 0.0 {
                return (x, y);
            }
            let (c, s) = v.at.of(ang + v.beta);
            (x + d * c, y + d * s)
        }
    }
}
