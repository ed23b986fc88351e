//! Time of impact of two bodies (a circle or a convex polygon each), with
//! no world: the first contact within a horizon of two bodies moving as the
//! simulator moves them (docs/toi.md).  The computation is the simulator's
//! own pair prediction ([`crate::sim`]'s `pair_search`, which its
//! predictions call), over the generated contact equations `E` (the
//! [`crate::sim_equations!`] of circle_circle and point_edge generated with
//! every effect).  The same bits as the C and Python libraries.
//!
//! Units: s, m, m/s, m/s^2, rad, rad/s.  Angles count counter-clockwise.
//!
//! ```ignore
//! let ball = toi::circle(0.5).unwrap();
//! let bx = toi::polygon(&[(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]).unwrap();
//! let r = toi::toi::<GeneratedEquations>(&ball, &Motion { x: -4.0, vx: 2.0, ..Motion::default() },
//!                                        &bx, &Motion { omega: 1.0, ..Motion::default() }, 5.0, &Options::default());
//! if r.status == toi::HIT { println!("{} {:?} {:?}", r.t, (r.px, r.py), (r.nx, r.ny)); }
//! ```

// `!(x > 0.0)` is also true for NaN, on purpose (the other runtimes' tests
// read the same way); the arithmetic is written as the other runtimes write it
#![allow(clippy::neg_cmp_op_on_partial_ord, clippy::assign_op_pattern)]

use crate::sim::contact::contact_frame;
use crate::sim::motion::{state_at, turn_rate};
use crate::sim::predict::{library_separation, pair_search, Counter, Found, PairEnv};
use crate::sim::scene::{Body, CosSin, Vertex};
use crate::sim::Equations;

/// Status of an answer (the C library's numbers).
pub const ERROR: i32 = -1;
pub const NONE: i32 = 0;
pub const HIT: i32 = 1;
pub const OVERLAPPED: i32 = 2;
/// Most vertices of a polygon shape.
pub const MAX_VERTICES: usize = 64;
/// Most steps (bounds, clear stretches, windows) of one query.
const MAX_STEPS: usize = 10_000_000;

/// A circle (no vertices, radius > 0) or a convex polygon (its vertices
/// about the centre of rotation); `bound`: m, the radius of the bounding
/// circle about the centre of rotation.
#[derive(Clone, Debug)]
pub struct Shape {
    pub radius: f64,
    pub bound: f64,
    pub verts: Vec<Vertex>,
}

/// A circle of `radius` m (> 0, finite).
pub fn circle(radius: f64) -> Option<Shape> {
    if !(radius > 0.0 && radius <= f64::MAX) {
        return None;
    }
    Some(Shape { radius, bound: radius, verts: Vec::new() })
}

/// A strictly convex polygon of 3..=MAX_VERTICES vertices (m, about the
/// centre of rotation, counter-clockwise).
pub fn polygon(points: &[(f64, f64)]) -> Option<Shape> {
    let n = points.len();
    if !(3..=MAX_VERTICES).contains(&n) || !points.iter().all(|&(x, y)| x.abs() <= f64::MAX && y.abs() <= f64::MAX) {
        return None;
    }
    let mut verts = Vec::with_capacity(n);
    let mut bound = 0.0;
    for k in 0..n {
        let ((x0, y0), (x1, y1), (x2, y2)) = (points[k], points[(k + 1) % n], points[(k + 2) % n]);
        let (ex, ey) = (x1 - x0, y1 - y0);
        // strictly convex, counter-clockwise: every turn left
        if !(ex * (y2 - y1) - ey * (x2 - x1) > 0.0) {
            return None;
        }
        let ln = (ex * ex + ey * ey).sqrt();
        // outward: the polygon is counter-clockwise
        let (nx, ny) = (ey / ln, -ex / ln);
        let (tx, ty) = (ex / ln, ey / ln);
        let rho = (x0 * x0 + y0 * y0).sqrt();
        verts.push(Vertex {
            lx: x0,
            ly: y0,
            rho,
            beta: y0.atan2(x0),
            psi: ny.atan2(nx),
            h: nx * x0 + ny * y0,
            s1: tx * x0 + ty * y0,
            s2: tx * x1 + ty * y1,
            nx,
            ny,
            cover: -1,
            at: CosSin::new(),
            normal: CosSin::new(),
        });
        if rho > bound {
            bound = rho;
        }
    }
    // the edges wind once around: the turns of the normal sum to 2 pi
    let mut turn = 0.0;
    for k in 0..n {
        let mut d = verts[(k + 1) % n].psi - verts[k].psi;
        while d <= 0.0 {
            d += 2.0 * std::f64::consts::PI;
        }
        turn += d;
    }
    if !(turn < 3.0 * std::f64::consts::PI) {
        return None;
    }
    Some(Shape { radius: 0.0, bound, verts })
}

/// A body's motion at time 0 of the query: its centre of rotation moves as
/// p + v t + a t^2/2, its angle as angle + omega t; a circle's own centre
/// may orbit it at `orbit` m, at angle + orbit_phase.
#[derive(Clone, Copy, Debug, Default)]
pub struct Motion {
    pub x: f64,
    pub y: f64,
    pub vx: f64,
    pub vy: f64,
    pub ax: f64,
    pub ay: f64,
    pub angle: f64,
    pub omega: f64,
    pub orbit: f64,
    pub orbit_phase: f64,
}

impl Motion {
    fn values(&self) -> [f64; 10] {
        [self.x, self.y, self.vx, self.vy, self.ax, self.ay, self.angle, self.omega, self.orbit, self.orbit_phase]
    }
}

/// Options: the distance tolerance (m, default 1e-9) and the Taylor order
/// the generated polynomials were made with (default 4).
#[derive(Clone, Copy, Debug)]
pub struct Options {
    pub tol: f64,
    pub taylor_order: i32,
}

impl Default for Options {
    fn default() -> Options {
        Options { tol: 1e-9, taylor_order: 4 }
    }
}

/// The answer: status (HIT, NONE, OVERLAPPED, ERROR); t (s); feature (0:
/// circle against circle or vertex, 1: point against edge); first: false
/// when i is A's feature and j B's, true when i is B's and j A's; i the
/// vertex (-1: the circle) against j, edge or vertex (-1: the circle);
/// (px, py) the contact point (m) and (nx, ny) the unit normal from the
/// body holding i to the other, at t.
#[derive(Clone, Copy, Debug, Default)]
pub struct ToiResult {
    pub status: i32,
    pub t: f64,
    pub feature: i32,
    pub first: bool,
    pub i: i32,
    pub j: i32,
    pub px: f64,
    pub py: f64,
    pub nx: f64,
    pub ny: f64,
}

impl ToiResult {
    fn of(status: i32) -> ToiResult {
        ToiResult { status, i: -1, j: -1, ..ToiResult::default() }
    }
}

/// The pair's surroundings without a world: the two bodies' vertices, no
/// covered edges, no counters.
struct Pair {
    tol: f64,
    alpha: f64,
    verts: Vec<Vertex>,
}

impl PairEnv for Pair {
    fn tol(&self) -> f64 {
        self.tol
    }
    fn alpha(&self) -> f64 {
        self.alpha
    }
    fn verts(&self) -> &[Vertex] {
        &self.verts
    }
    fn covered(&self, _cover: i64) -> bool {
        false
    }
    fn library(&self) -> bool {
        true
    }
}

struct Uncounted;

impl Counter for Uncounted {
    fn count_cc(&mut self, _idx: usize) {}
    fn count_pe(&mut self, _idx: usize) {}
}

/// The largest angle (at most 0.5 rad) whose order-n Taylor remainder of
/// sin and cos, a^(n+1)/(n+1)!, times the lever (m) stays below tol.
fn angle_for(lever: f64, n: i32, tol: f64) -> f64 {
    let mut f = 1.0;
    for k in 2..=n + 1 {
        f *= k as f64;
    }
    let a = (f * tol / lever).powf(1.0 / (n + 1) as f64);
    if a < 0.5 {
        a
    } else {
        0.5
    }
}

fn body(s: &Shape, q: &Motion, idx: u32, v0: u32) -> Body {
    let polygon = !s.verts.is_empty();
    let (r, orbit, ophase) = if polygon { (0.0, 0.0, 0.0) } else { (s.radius, q.orbit, q.orbit_phase) };
    Body {
        idx,
        polygon,
        fixed: false,
        large: false,
        inv_m: 0.0,
        inv_i: 0.0,
        e: 0.0,
        mu: 0.0,
        fax: q.ax,
        fay: q.ay,
        sup: -1,
        sup_edge: -1,
        carry: 0,
        tx: 0.0,
        ty: 0.0,
        load: 0.0,
        at: 0.0,
        px: q.x,
        py: q.y,
        vx: q.vx,
        vy: q.vy,
        ax: q.ax,
        ay: q.ay,
        ang: q.angle,
        om: q.omega,
        tb: 0.0,
        r,
        orbit,
        ophase,
        bound: if polygon { s.bound } else { orbit + r },
        window: 0.0,
        v0,
        nv: s.verts.len() as u32,
        cx: 0,
        cy: 0,
        gone: false,
        asleep: false,
        island: -1,
        wcells: None,
    }
}

/// The first contact of A and B within [0, horizon] s (docs/toi.md).
/// A and B at 0 are farther apart than their bounds and the tolerance, so
/// that their separation exceeds the tolerance (each body lies within its
/// bound about its centre of rotation) and the overlap test can be spared:
/// the centres' distance less the bounds, with a margin of 2^-30 of the
/// sizes for every rounding.
fn bounds_apart(a: &Body, b: &Body, tol: f64) -> bool {
    let (dx, dy, r) = (b.px - a.px, b.py - a.py, a.bound + b.bound);
    let d = (dx * dx + dy * dy).sqrt();
    d - r > tol + 1.0 / 1_073_741_824.0 * (d + r + a.px.abs() + a.py.abs() + b.px.abs() + b.py.abs())
}

pub fn toi<E: Equations>(a: &Shape, ma: &Motion, b: &Shape, mb: &Motion, horizon: f64, o: &Options) -> ToiResult {
    let (tol, order) = (o.tol, o.taylor_order);
    if !(tol > 0.0 && tol <= f64::MAX && (1..=7).contains(&order)) {
        return ToiResult::of(ERROR);
    }
    if !(0.0..=f64::MAX).contains(&horizon) {
        return ToiResult::of(ERROR);
    }
    for q in [ma, mb] {
        if !q.values().iter().all(|v| v.abs() <= f64::MAX) || !(q.orbit >= 0.0) {
            return ToiResult::of(ERROR);
        }
    }
    if (!a.verts.is_empty() && ma.orbit != 0.0) || (!b.verts.is_empty() && mb.orbit != 0.0) {
        return ToiResult::of(ERROR);
    }
    let mut bodies = [body(a, ma, 0, 0), body(b, mb, 1, a.verts.len() as u32)];
    let mut verts = a.verts.clone();
    verts.extend(b.verts.iter().cloned());
    let mut pair = Pair { tol, alpha: 0.5, verts };
    if !bounds_apart(&bodies[0], &bodies[1], tol) && library_separation(&pair.verts, &bodies[0], &bodies[1]) < -tol {
        return ToiResult::of(OVERLAPPED);
    }
    // the windows (docs/simulator.md, "Taylor windows"): both turn, a lever
    // of twice the larger bound plus the larger bound; one turns, its bound
    // plus a circle partner's radius
    let (ta, tb) = (turn_rate(&bodies[0]), turn_rate(&bodies[1]));
    let big = if bodies[0].bound > bodies[1].bound { bodies[0].bound } else { bodies[1].bound };
    if ta > 0.0 && tb > 0.0 {
        pair.alpha = angle_for(2.0 * big + big, order, tol);
    } else if ta > 0.0 {
        bodies[0].window = angle_for(bodies[0].bound + bodies[1].r, order, tol);
    } else if tb > 0.0 {
        bodies[1].window = angle_for(bodies[1].bound + bodies[0].r, order, tol);
    }
    let found =
        pair_search::<E, _, _>(&pair, &mut Uncounted, &bodies[0], &bodies[1], 0.0, horizon, MAX_STEPS, MAX_STEPS);
    let (at, bb) = match found {
        Ok(Found::Contact(at, bb)) => (at, bb),
        Ok(Found::None) => return ToiResult::of(NONE),
        _ => return ToiResult::of(ERROR),
    };
    let t = at + bb.s;
    let (x, y) = (&bodies[bb.a], &bodies[bb.b]);
    let bang = state_at(y, t).4;
    let (px, py, nx, ny) = contact_frame(&pair.verts, t, bb.feat, x, y, bb.i, bb.j, bang);
    ToiResult { status: HIT, t, feature: bb.feat, first: bb.a == 1, i: bb.i, j: bb.j, px, py, nx, ny }
}

/// The conformance testee of op "toi" over the equations E (docs/conformance.md):
/// reads `toi SEQ HORIZON TOL BODY_A BODY_B` lines from standard input, writes
/// `SEQ hit T FEATURE FIRST I J PX PY NX NY`, `SEQ none`, `SEQ overlapped` or
/// `SEQ error ...`; every number a hex double but N and SEQ.
pub fn testee_main<E: Equations>() -> i32 {
    use std::io::{BufRead, Write};
    let stdin = std::io::stdin();
    let stdout = std::io::stdout();
    let mut out = std::io::BufWriter::new(stdout.lock());
    fn hexd(w: Option<&str>) -> Option<f64> {
        u64::from_str_radix(w?, 16).ok().map(f64::from_bits)
    }
    fn read_body<'a, I: Iterator<Item = &'a str>>(it: &mut I) -> Option<(Shape, Motion)> {
        let n: usize = it.next()?.parse().ok()?;
        let shape = if n == 0 {
            circle(hexd(it.next())?)?
        } else {
            let mut pts = Vec::with_capacity(n);
            for _ in 0..n {
                pts.push((hexd(it.next())?, hexd(it.next())?));
            }
            polygon(&pts)?
        };
        let mut v = [0.0; 10];
        for x in v.iter_mut() {
            *x = hexd(it.next())?;
        }
        let m = Motion {
            x: v[0],
            y: v[1],
            vx: v[2],
            vy: v[3],
            ax: v[4],
            ay: v[5],
            angle: v[6],
            omega: v[7],
            orbit: v[8],
            orbit_phase: v[9],
        };
        Some((shape, m))
    }
    for line in stdin.lock().lines() {
        let Ok(line) = line else { break };
        let mut it = line.split_whitespace();
        if it.next() != Some("toi") {
            continue;
        }
        let seq = it.next().unwrap_or("-1").to_string();
        let parsed = (|| {
            let h = hexd(it.next())?;
            let tol = hexd(it.next())?;
            let (sa, ma) = read_body(&mut it)?;
            let (sb, mb) = read_body(&mut it)?;
            Some((h, tol, sa, ma, sb, mb))
        })();
        let Some((h, tol, sa, ma, sb, mb)) = parsed else {
            let _ = writeln!(out, "{seq} error malformed");
            continue;
        };
        let r = toi::<E>(&sa, &ma, &sb, &mb, h, &Options { tol, taylor_order: 4 });
        let _ = match r.status {
            HIT => writeln!(
                out,
                "{seq} hit {:016x} {} {} {} {} {:016x} {:016x} {:016x} {:016x}",
                r.t.to_bits(),
                r.feature,
                r.first as i32,
                r.i,
                r.j,
                r.px.to_bits(),
                r.py.to_bits(),
                r.nx.to_bits(),
                r.ny.to_bits()
            ),
            NONE => writeln!(out, "{seq} none"),
            OVERLAPPED => writeln!(out, "{seq} overlapped"),
            _ => writeln!(out, "{seq} error refused"),
        };
    }
    0
}
