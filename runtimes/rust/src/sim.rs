//! The discrete-event simulator (docs/simulator.md), a port of the
//! reference runtimes/python/max2code_rt/sim.py that performs the same IEEE
//! double operations in the same order, so that it writes the same bytes.
//!
//! The crate cannot depend on generated code: the simulator is generic over
//! [`Equations`], which a small binary implements with the generated entries
//! of equations/circle-circle.mxm and equations/point-edge.mxm
//! ([`sim_main!`](crate::sim_main) writes that binary's `main`).  Every
//! prediction goes through those entries and through the runtime's root
//! solver [`smallest_root`].
//!
//! Operation order: each expression is written as Python evaluates it (left
//! to right, the same parentheses); Python's `min(a, b)` is `b < a ? b : a`
//! and `max(a, b)` is `b > a ? b : a`; sin, cos come from libm as Python's
//! math module takes them (LLVM may fuse the sin and cos of one argument
//! into glibc's sincos, which returns the same bits; a vertex keeps cos and
//! sin of the last argument asked); Rust never contracts to FMA.

// written as the Python reference reads: `x = x + y` (the same operation as
// `x += y`), `!(w > 0.0)` (true for NaN, as `not (w > 0.0)` in Python)
#![allow(clippy::assign_op_pattern, clippy::neg_cmp_op_on_partial_ord)]

use std::io::{self, Read, Write};

use crate::roots::{smallest_root, MAX_DEGREE};

mod g17;
mod scene;

pub use g17::{g17, push_g17};
pub use scene::{Body, CosSin, Input, Scene, Vertex};

/// pi/2 rounded to double (cos x = sin(x + pi/2)).
pub const HALF_PI: f64 = std::f64::consts::FRAC_PI_2;

/// Room for the coefficients of any generated variant.
pub const MAX_COEF: usize = MAX_DEGREE + 1;

/// The generated entries the simulator predicts with (see [`sim_main!`](crate::sim_main)).
pub trait Equations {
    /// Number of variants `cc_variant` counts (`CIRCLE_CIRCLE_VARIANT_NAMES.len()`).
    const CC_VARIANTS: usize;
    /// Number of variants `pe_variant` counts (`POINT_EDGE_VARIANT_NAMES.len()`).
    const PE_VARIANTS: usize;
    /// `circle_circle_variant` of the 24 parameters in their generated order.
    fn cc_variant(p: &[f64; 24]) -> i32;
    /// `circle_circle_coefficients`: the degree, coefficients in `c[..=degree]`.
    fn cc_coefficients(p: &[f64; 24], c: &mut [f64; MAX_COEF]) -> Option<usize>;
    /// `point_edge_variant` of the 12 parameters in their generated order.
    fn pe_variant(p: &[f64; 12]) -> i32;
    /// `point_edge_coefficients`: the degree, coefficients in `c[..=degree]`.
    fn pe_coefficients(p: &[f64; 12], c: &mut [f64; MAX_COEF]) -> Option<usize>;
}

// event kinds, in the order they are handled at equal times
const INPUT: u64 = 0;
const COLLISION: u64 = 1;
const CELL: u64 = 2;
const HORIZON: u64 = 3;
const FRAME: u64 = 4;
// contact features
const CC: i32 = 0;
const PE: i32 = 1;
const STAT_NAMES: [&str; 8] = ["collisions", "inputs", "frames", "cells", "horizons", "stale", "pairs", "features"];
const ST_COLLISIONS: usize = 0;
const ST_INPUTS: usize = 1;
const ST_FRAMES: usize = 2;
const ST_CELLS: usize = 3;
const ST_HORIZONS: usize = 4;
const ST_STALE: usize = 5;
const ST_PAIRS: usize = 6;
const ST_FEATURES: usize = 7;
const SEQ_BITS: u32 = 60;

/// A scheduled event: `key` is kind << 60 | seq, so that (t, key) orders
/// as Python's (t, kind, seq) tuples.
#[derive(Clone, Copy, Debug)]
struct Entry {
    t: f64,
    key: u64,
    p: Payload,
}

impl Entry {
    /// Python's tuple `<` on (t, kind, seq, ...): seq is unique, so the
    /// rest is never reached and the order is total (times are never NaN).
    #[inline(always)]
    fn lt(&self, o: &Entry) -> bool {
        if self.t == o.t {
            self.key < o.key
        } else {
            self.t < o.t
        }
    }
}

/// The rest of a scheduled event: bodies (-1: none) and their stamps when
/// it was scheduled, feature and indices (or input or frame number, axis,
/// direction).
#[derive(Clone, Copy, Debug)]
struct Payload {
    a: i32,
    b: i32,
    feat: i32,
    j: i32,
    i: i64,
    sa: u64,
    sb: u64,
}

/// A 4-ary min-heap of entries, ordered by (t, key).
struct Near {
    v: Vec<Entry>,
}

const ARITY: usize = 4;

impl Near {
    #[inline]
    fn push(&mut self, item: Entry) {
        let mut pos = self.v.len();
        self.v.push(item);
        while pos > 0 {
            let parent = (pos - 1) / ARITY;
            if item.lt(&self.v[parent]) {
                self.v[pos] = self.v[parent];
                pos = parent;
            } else {
                break;
            }
        }
        self.v[pos] = item;
    }

    #[inline]
    fn pop(&mut self) -> Option<Entry> {
        let last = self.v.pop()?;
        if self.v.is_empty() {
            return Some(last);
        }
        let top = self.v[0];
        let n = self.v.len();
        let mut pos = 0;
        loop {
            let first = ARITY * pos + 1;
            if first >= n {
                break;
            }
            let mut best = first;
            for c in first + 1..(first + ARITY).min(n) {
                if self.v[c].lt(&self.v[best]) {
                    best = c;
                }
            }
            if self.v[best].lt(&last) {
                self.v[pos] = self.v[best];
                pos = best;
            } else {
                break;
            }
        }
        self.v[pos] = last;
        Some(top)
    }
}

/// The bits of a time as an unsigned integer with the order of the times
/// (-0 counts as +0, as it compares equal).
#[inline(always)]
fn time_bits(t: f64) -> u64 {
    let b = (t + 0.0).to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | (1 << 63)
    }
}

/// The event queue: a radix heap on the bits of the times.  Events at or
/// before the time reached (`reached`, the last time taken from the
/// buckets) wait in a small 4-ary heap ordered by (t, kind, seq); later
/// ones wait unsorted in bucket k, k the highest bit in which their time
/// differs from the time reached.  When the small heap runs empty, the
/// lowest bucket's earliest time becomes the time reached and its events
/// move to the small heap (that time) or to lower buckets.  So events are
/// appended and scanned in order instead of sifted at random, and the pop
/// order is Python's heapq order on (t, kind, seq) (unique keys: any
/// correct priority queue gives it), also for an event scheduled a rounding
/// error before the time reached.  The memory is that of the most events
/// pending at once.
struct Heap {
    near: Near,
    reached: u64,
    buckets: Vec<Vec<Entry>>,
    /// bit k set: bucket k is not empty
    mask: u64,
}

impl Heap {
    fn new() -> Heap {
        Heap {
            near: Near { v: Vec::with_capacity(64) },
            reached: 0,
            buckets: vec![Vec::new(); 64],
            mask: 0,
        }
    }

    #[inline(always)]
    fn place(&mut self, e: Entry) {
        let o = time_bits(e.t);
        if o <= self.reached {
            self.near.push(e);
        } else {
            let k = 63 - (o ^ self.reached).leading_zeros() as usize;
            self.buckets[k].push(e);
            self.mask |= 1 << k;
        }
    }

    #[inline]
    fn push(&mut self, t: f64, key: u64, p: Payload) {
        self.place(Entry { t, key, p });
    }

    #[inline]
    fn pop(&mut self) -> Option<Entry> {
        if self.near.v.is_empty() {
            if self.mask == 0 {
                return None;
            }
            let k = self.mask.trailing_zeros() as usize;
            self.mask &= !(1u64 << k);
            let mut items = std::mem::take(&mut self.buckets[k]);
            self.reached = items.iter().map(|e| time_bits(e.t)).min().expect("a bucket in the mask has events");
            // all of them now differ from the time reached below bit k
            for &e in &items {
                self.place(e);
            }
            items.clear();
            self.buckets[k] = items;
        }
        self.near.pop()
    }
}

/// The event queue and the counters (everything a prediction changes).
struct Queue {
    heap: Heap,
    seq: u64,
    stats: [u64; 8],
    cc_counts: Vec<u64>,
    pe_counts: Vec<u64>,
}

impl Queue {
    #[allow(clippy::too_many_arguments)]
    #[inline]
    fn push(&mut self, stamps: &[u64], t: f64, kind: u64, a: i32, b: i32, feat: i32, i: i64, j: i32) {
        let sa = if a >= 0 { stamps[a as usize] } else { 0 };
        let sb = if b >= 0 { stamps[b as usize] } else { 0 };
        self.heap.push(t, (kind << SEQ_BITS) | self.seq, Payload { a, b, feat, j, i, sa, sb });
        self.seq += 1;
    }
}

/// The world: the scene, the bodies' states, the grid.
struct World {
    s: Scene,
    /// per body, bumped whenever its motion changes (lazy invalidation)
    stamps: Vec<u64>,
    cells: Vec<CellList>,
    large: Vec<u32>,
}

const CELL_INLINE: usize = 4;

/// One grid cell's list of bodies: the first few inline (a cell rarely
/// holds more), the rest in a vector.  Python's list operations: append at
/// the end, remove by moving the last element into the hole.
#[derive(Clone, Default)]
struct CellList {
    n: u32,
    inline: [u32; CELL_INLINE],
    more: Vec<u32>,
}

impl CellList {
    #[inline(always)]
    fn get(&self, k: usize) -> u32 {
        if k < CELL_INLINE {
            self.inline[k]
        } else {
            self.more[k - CELL_INLINE]
        }
    }

    #[inline]
    fn push(&mut self, x: u32) {
        let n = self.n as usize;
        if n < CELL_INLINE {
            self.inline[n] = x;
        } else {
            self.more.push(x);
        }
        self.n += 1;
    }

    /// Python's cell_remove: the last element moves into the hole.
    #[inline]
    fn remove(&mut self, x: u32) {
        let n = self.n as usize;
        let k = (0..n).position(|k| self.get(k) == x).expect("a body is in its cell");
        let last = if n > CELL_INLINE { self.more.pop().expect("n > inline") } else { self.inline[n - 1] };
        if k < n - 1 {
            if k < CELL_INLINE {
                self.inline[k] = last;
            } else {
                self.more[k - CELL_INLINE] = last;
            }
        }
        self.n -= 1;
    }
}

/// Buffered trace output.
struct Out<W: Write> {
    buf: Vec<u8>,
    sink: W,
}

impl<W: Write> Out<W> {
    #[inline]
    fn s(&mut self, text: &str) {
        self.buf.extend_from_slice(text.as_bytes());
    }

    #[inline]
    fn num(&mut self, x: f64) {
        self.buf.push(b' ');
        push_g17(&mut self.buf, x);
    }

    #[inline]
    fn int(&mut self, k: i64) {
        self.buf.push(b' ');
        let mut d = [0u8; 20];
        let mut n = d.len();
        let mut u = k.unsigned_abs();
        loop {
            n -= 1;
            d[n] = b'0' + (u % 10) as u8;
            u /= 10;
            if u == 0 {
                break;
            }
        }
        if k < 0 {
            self.buf.push(b'-');
        }
        self.buf.extend_from_slice(&d[n..]);
    }

    #[inline]
    fn end_line(&mut self) -> io::Result<()> {
        self.buf.push(b'\n');
        if self.buf.len() >= 1 << 16 {
            self.flush()?;
        }
        Ok(())
    }

    fn flush(&mut self) -> io::Result<()> {
        self.sink.write_all(&self.buf)?;
        self.buf.clear();
        self.sink.flush()
    }
}

/// Why a run stopped early: a stuck or bad scene (an `X` line), or output
/// that could not be written.
enum Stop {
    Scene(String),
    Io(io::Error),
}

impl From<io::Error> for Stop {
    fn from(e: io::Error) -> Stop {
        Stop::Io(e)
    }
}

type Res<T> = Result<T, Stop>;

// ---- motion -------------------------------------------------------------

#[inline(always)]
fn advance(b: &mut Body, t: f64) {
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
fn state_at(b: &Body, t: f64) -> (f64, f64, f64, f64, f64) {
    let dt = t - b.tb;
    (
        b.px + (b.vx + 0.5 * b.ax * dt) * dt,
        b.py + (b.vy + 0.5 * b.ay * dt) * dt,
        b.vx + b.ax * dt,
        b.vy + b.ay * dt,
        b.ang + b.om * dt,
    )
}

#[inline(always)]
fn turn_rate(b: &Body) -> f64 {
    if b.polygon || b.orbit > 0.0 {
        return b.om.abs();
    }
    0.0
}

/// World position of a circle's centre (v None) or of a vertex, at t.
#[inline(always)]
fn point_at(b: &Body, v: Option<&Vertex>, t: f64) -> (f64, f64) {
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

// ---- grid -----------------------------------------------------------------

fn cell_of(s: &Scene, x: f64, y: f64) -> (i32, i32) {
    let fx = ((x - s.x0) / s.cw).floor();
    let fy = ((y - s.y0) / s.ch).floor();
    let ix = if fx < 0.0 { 0 } else if fx > (s.nx - 1) as f64 { s.nx - 1 } else { fx as i64 };
    let iy = if fy < 0.0 { 0 } else if fy > (s.ny - 1) as f64 { s.ny - 1 } else { fy as i64 };
    (ix as i32, iy as i32)
}

impl World {
    fn cell_index(&self, b: usize) -> usize {
        let body = &self.s.bodies[b];
        (i64::from(body.cy) * self.s.nx + i64::from(body.cx)) as usize
    }

    fn cell_remove(&mut self, b: usize) {
        let c = self.cell_index(b);
        self.cells[c].remove(b as u32);
    }

    fn cell_add(&mut self, b: usize) {
        let c = self.cell_index(b);
        self.cells[c].push(b as u32);
    }
}

// ---- first valid root of one feature ----------------------------------------

/// The smallest s in [0, w] where the gap c(s) reaches zero while
/// decreasing and check(s) holds.  At s = 0 the gap counts as zero within
/// kappa: approaching means contact now, separating never.
#[inline(always)]
fn first_contact<F: FnMut(f64) -> bool>(c: &[f64; MAX_COEF], deg: usize, w: f64, kappa: f64, mut check: F) -> Option<f64> {
    if deg >= 1 && c[0].abs() <= kappa && c[1] < 0.0 && check(0.0) {
        return Some(0.0);
    }
    let mut lo = 0.0;
    for _ in 0..deg + 2 {
        let s = smallest_root(&c[..deg + 1], lo, w)?;
        let mut d = 0.0;
        for k in (1..=deg).rev() {
            d = d * s + k as f64 * c[k];
        }
        if d < 0.0 && check(s) {
            return Some(s);
        }
        lo = s;
    }
    None
}

// ---- features -----------------------------------------------------------------

/// circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
/// circle's centre (v None) or of a polygon's vertex, at time now.
#[inline(always)]
fn circle_params(b: &Body, now: f64, v: Option<&Vertex>) -> [f64; 11] {
    let (mut x, mut y, vx, vy, ang) = state_at(b, now);
    let (mut d, mut phase) = match v {
        None => (b.orbit, ang + b.ophase),
        Some(v) => (v.rho, ang + v.beta),
    };
    let mut om = b.om;
    if om == 0.0 && d != 0.0 {
        // an orbit that does not turn is a fixed offset: fold it in
        let (c, s) = match v {
            None => (phase.cos(), phase.sin()),
            Some(v) => v.at.of(phase),
        };
        x = x + d * c;
        y = y + d * s;
        d = 0.0;
    }
    if d == 0.0 {
        om = 0.0;
        phase = 0.0;
    }
    [x, vx, b.ax, d, om, phase + HALF_PI, y, vy, b.ay, om, phase]
}

#[inline(always)]
fn cc_coefficients<E: Equations>(q: &mut Queue, args: &[f64; 24], coef: &mut [f64; MAX_COEF]) -> Res<usize> {
    let idx = E::cc_variant(args);
    if idx < 0 {
        return Err(Stop::Scene("circle_circle: the scene uses an effect the generated code leaves out".into()));
    }
    q.cc_counts[idx as usize] += 1;
    q.stats[ST_FEATURES] += 1;
    E::cc_coefficients(args, coef)
        .ok_or_else(|| Stop::Scene("circle_circle: the scene uses an effect the generated code leaves out".into()))
}

/// Circle of A against circle of B (vb None) or vertex vb of B (radius 0).
#[allow(clippy::too_many_arguments)]
fn predict_cc<E: Equations>(
    w: &World,
    q: &mut Queue,
    a_: &Body,
    b_: &Body,
    vb: Option<&Vertex>,
    rb: f64,
    now: f64,
    win: f64,
) -> Res<Option<f64>> {
    let [a, b, c, d, e, f, m, n, o, p, qq] = circle_params(a_, now, None);
    let [g, h, i, j, k, l, r, s, u, v, ww] = circle_params(b_, now, vb);
    // only differences of the centres' motions matter: circle 1 moves
    // relative to circle 2's centre of rotation
    let args = [
        a - g,
        b - h,
        c - i,
        d,
        e,
        f,
        m - r,
        n - s,
        o - u,
        p,
        qq,
        0.0,
        0.0,
        0.0,
        j,
        k,
        l,
        0.0,
        0.0,
        0.0,
        v,
        ww,
        a_.r,
        rb,
    ];
    let mut coef = [0.0; MAX_COEF];
    let deg = cc_coefficients::<E>(q, &args, &mut coef)?;
    let tol = w.s.tol;
    let kappa = tol * (2.0 * (a_.r + rb) + tol);
    Ok(first_contact(&coef, deg, win, kappa, |_| true))
}

/// Point of X (circle centre with radius, or vertex vx_) against the line of edge j of Y.
#[allow(clippy::too_many_arguments)]
fn predict_pe<E: Equations>(
    w: &World,
    q: &mut Queue,
    x_: &Body,
    y_: &Body,
    vx_: Option<&Vertex>,
    j: usize,
    now: f64,
    win: f64,
) -> Res<Option<f64>> {
    let ed = &w.s.verts[y_.vert(j)];
    let (x1, y1, u1, v1, ang1) = state_at(x_, now);
    let (x2, y2, u2, v2, ang2) = state_at(y_, now);
    let (rho, beta, rad) = match vx_ {
        None => (x_.orbit, x_.ophase, x_.r),
        Some(v) => (v.rho, v.beta, 0.0),
    };
    let phn = ang2 + ed.psi;
    let wr = x_.om - y_.om;
    let phr = (ang1 + beta) - phn;
    let mut h = ed.h + rad;
    let mut rho = rho;
    if wr == 0.0 && rho != 0.0 {
        // the point does not turn relative to the edge: its offset along
        // the normal is a constant, folded into the line's offset
        h = h - rho * phr.cos();
        rho = 0.0;
    }
    let args = [x1 - x2, u1 - u2, x_.ax - y_.ax, y1 - y2, v1 - v2, x_.ay - y_.ay, rho, wr, phr, y_.om, phn, h];
    let idx = E::pe_variant(&args);
    if idx < 0 {
        return Err(Stop::Scene("point_edge: the scene uses an effect the generated code leaves out".into()));
    }
    q.pe_counts[idx as usize] += 1;
    q.stats[ST_FEATURES] += 1;
    let mut coef = [0.0; MAX_COEF];
    let deg = E::pe_coefficients(&args, &mut coef)
        .ok_or_else(|| Stop::Scene("point_edge: the scene uses an effect the generated code leaves out".into()))?;
    let tol = w.s.tol;
    let inside = |s: f64| -> bool {
        let t = now + s;
        let (px, py) = point_at(x_, vx_, t);
        let (qx, qy, _, _, qa) = state_at(y_, t);
        let th = qa + ed.psi;
        let (c, s) = ed.normal.of(th);
        let along = (px - qx) * -s + (py - qy) * c;
        ed.s1 - tol <= along && along <= ed.s2 + tol
    };
    Ok(first_contact(&coef, deg, win, tol, inside))
}

/// A candidate contact: (s, feature, a, b, i, j).
#[derive(Clone, Copy)]
struct Best {
    s: f64,
    feat: i32,
    a: usize,
    b: usize,
    i: i64,
    j: i64,
}

#[inline(always)]
fn better(best: Option<Best>, t: Option<f64>, feat: i32, a: usize, b: usize, i: i64, j: i64) -> Option<Best> {
    if let Some(s) = t {
        if best.is_none_or(|bb| s < bb.s) {
            return Some(Best { s, feat, a, b, i, j });
        }
    }
    best
}

/// When the bounding circles first touch within (0, w]: 0.0 when they
/// overlap or touch now (within the tolerance), None when they do not meet
/// (exact: bounding circles do not turn).
fn bounds_meet<E: Equations>(w: &World, q: &mut Queue, a_: &Body, b_: &Body, now: f64, win: f64) -> Res<Option<f64>> {
    let (x1, y1, u1, v1, _) = state_at(a_, now);
    let (x2, y2, u2, v2, _) = state_at(b_, now);
    let args = [
        x1 - x2,
        u1 - u2,
        a_.ax - b_.ax,
        0.0,
        0.0,
        HALF_PI,
        y1 - y2,
        v1 - v2,
        a_.ay - b_.ay,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        HALF_PI,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        a_.bound,
        b_.bound,
    ];
    let mut coef = [0.0; MAX_COEF];
    let deg = cc_coefficients::<E>(q, &args, &mut coef)?;
    let tol = w.s.tol;
    if coef[0] <= tol * (2.0 * (a_.bound + b_.bound) + tol) {
        return Ok(Some(0.0));
    }
    Ok(smallest_root(&coef[..deg + 1], 0.0, win))
}

fn circle_polygon<E: Equations>(
    w: &World,
    q: &mut Queue,
    c_: &Body,
    p_: &Body,
    now: f64,
    win: f64,
    mut best: Option<Best>,
) -> Res<Option<Best>> {
    for j in 0..p_.nverts() {
        let t = predict_pe::<E>(w, q, c_, p_, None, j, now, win)?;
        best = better(best, t, PE, c_.index(), p_.index(), -1, j as i64);
    }
    for k in 0..p_.nverts() {
        let v = &w.s.verts[p_.vert(k)];
        let t = predict_cc::<E>(w, q, c_, p_, Some(v), 0.0, now, win)?;
        best = better(best, t, CC, c_.index(), p_.index(), -1, k as i64);
    }
    Ok(best)
}

fn vertices_edges<E: Equations>(
    w: &World,
    q: &mut Queue,
    a_: &Body,
    b_: &Body,
    now: f64,
    win: f64,
    mut best: Option<Best>,
) -> Res<Option<Best>> {
    for i in 0..a_.nverts() {
        let v = &w.s.verts[a_.vert(i)];
        for j in 0..b_.nverts() {
            let t = predict_pe::<E>(w, q, a_, b_, Some(v), j, now, win)?;
            best = better(best, t, PE, a_.index(), b_.index(), i as i64, j as i64);
        }
    }
    Ok(best)
}

// ---- pairs --------------------------------------------------------------------

/// Schedule the first contact of A and B after now, or a horizon event
/// where the Taylor polynomials of their turns stop being good.
fn predict_pair<E: Equations>(w: &World, q: &mut Queue, ai: usize, bi: usize, now: f64) -> Res<()> {
    let s = &w.s;
    let a_ = &s.bodies[ai];
    let b_ = &s.bodies[bi];
    q.stats[ST_PAIRS] += 1;
    let mut win = s.end - now;
    if !(win > 0.0) {
        return Ok(());
    }
    if a_.polygon || b_.polygon {
        // the bounding circles do not turn: until they touch, nothing can
        match bounds_meet::<E>(w, q, a_, b_, now, win)? {
            None => return Ok(()),
            Some(meet) if meet > 0.0 => {
                q.push(&w.stamps, now + meet, HORIZON, a_.idx as i32, b_.idx as i32, -1, -1, -1);
                return Ok(());
            }
            Some(_) => {}
        }
    }
    let turn = turn_rate(a_) + turn_rate(b_);
    if turn > 0.0 {
        let x = s.alpha / turn;
        if x < win {
            win = x;
        }
    }
    let mut best = None;
    if !a_.polygon && !b_.polygon {
        let t = predict_cc::<E>(w, q, a_, b_, None, b_.r, now, win)?;
        if let Some(t) = t {
            best = Some(Best { s: t, feat: CC, a: a_.index(), b: b_.index(), i: -1, j: -1 });
        }
    } else if !a_.polygon {
        best = circle_polygon::<E>(w, q, a_, b_, now, win, None)?;
    } else if !b_.polygon {
        best = circle_polygon::<E>(w, q, b_, a_, now, win, None)?;
    } else {
        best = vertices_edges::<E>(w, q, a_, b_, now, win, None)?;
        best = vertices_edges::<E>(w, q, b_, a_, now, win, best)?;
    }
    if let Some(bb) = best {
        q.push(&w.stamps, now + bb.s, COLLISION, bb.a as i32, bb.b as i32, bb.feat, bb.i, bb.j as i32);
    } else if now + win < s.end {
        q.push(&w.stamps, now + win, HORIZON, a_.idx as i32, b_.idx as i32, -1, -1, -1);
    }
    Ok(())
}

// ---- per body -------------------------------------------------------------------

/// Predict body b against the bodies of the cells x_lo..=x_hi, y_lo..=y_hi
/// (b itself, `skip` and fixed pairs left out).
#[allow(clippy::too_many_arguments)]
fn predict_cells<E: Equations>(
    w: &World,
    q: &mut Queue,
    b: usize,
    x_lo: i64,
    x_hi: i64,
    y_lo: i64,
    y_hi: i64,
    now: f64,
    skip: Option<usize>,
    only_after: bool,
) -> Res<()> {
    let s = &w.s;
    let fixed = s.bodies[b].fixed;
    for jy in y_lo.max(0)..=y_hi.min(s.ny - 1) {
        for jx in x_lo.max(0)..=x_hi.min(s.nx - 1) {
            let cell = &w.cells[(jy * s.nx + jx) as usize];
            for k in 0..cell.n as usize {
                let o = cell.get(k) as usize;
                if o == b || Some(o) == skip || (only_after && o <= b) {
                    continue;
                }
                if !(fixed && s.bodies[o].fixed) {
                    predict_pair::<E>(w, q, b, o, now)?;
                }
            }
        }
    }
    Ok(())
}

fn predict_body<E: Equations>(w: &World, q: &mut Queue, b: usize, now: f64, skip: Option<usize>) -> Res<()> {
    let body = &w.s.bodies[b];
    let (cx, cy) = (i64::from(body.cx), i64::from(body.cy));
    predict_cells::<E>(w, q, b, cx - 1, cx + 1, cy - 1, cy + 1, now, skip, false)?;
    for &o in &w.large {
        let o = o as usize;
        if o != b && Some(o) != skip && !(body.fixed && w.s.bodies[o].fixed) {
            predict_pair::<E>(w, q, b, o, now)?;
        }
    }
    schedule_cell(w, q, b, now);
    Ok(())
}

fn schedule_cell(w: &World, q: &mut Queue, bi: usize, now: f64) {
    let s = &w.s;
    let b = &s.bodies[bi];
    if b.large || (b.vx == 0.0 && b.vy == 0.0 && b.ax == 0.0 && b.ay == 0.0) {
        return;
    }
    let ulo = now - b.tb;
    let uhi = s.end - b.tb;
    let mut best: Option<(f64, i64, i32)> = None;
    for axis in 0..2 {
        let (p, v, a, i, n, origin, size) =
            if axis == 0 { (b.px, b.vx, b.ax, i64::from(b.cx), s.nx, s.x0, s.cw) } else { (b.py, b.vy, b.ay, i64::from(b.cy), s.ny, s.y0, s.ch) };
        for direction in [1i32, -1] {
            let bound = if direction == 1 {
                if i >= n - 1 {
                    continue;
                }
                origin + (i + 1) as f64 * size
            } else {
                if i <= 0 {
                    continue;
                }
                origin + i as f64 * size
            };
            let c = [p - bound, v, 0.5 * a];
            let mut lo = ulo;
            for _ in 0..3 {
                let Some(u) = smallest_root(&c, lo, uhi) else {
                    break;
                };
                if (v + a * u) * f64::from(direction) > 0.0 {
                    if best.is_none_or(|bb| u < bb.0) {
                        best = Some((u, axis, direction));
                    }
                    break;
                }
                lo = u;
            }
        }
    }
    if let Some((u, axis, direction)) = best {
        q.push(&w.stamps, b.tb + u, CELL, bi as i32, -1, -1, axis, direction);
    }
}

// ---- handling events --------------------------------------------------------------

fn emit_state<W: Write>(out: &mut Out<W>, b: &Body) -> io::Result<()> {
    out.s("S");
    out.int(i64::from(b.idx));
    out.num(b.tb);
    out.num(b.px);
    out.num(b.py);
    out.num(b.vx);
    out.num(b.vy);
    out.num(b.ang);
    out.num(b.om);
    out.end_line()
}

/// Two distinct bodies of the slice, mutably.
fn two_mut(v: &mut [Body], a: usize, b: usize) -> (&mut Body, &mut Body) {
    assert!(a != b, "a collision needs two bodies");
    if a < b {
        let (lo, hi) = v.split_at_mut(b);
        (&mut lo[a], &mut hi[0])
    } else {
        let (lo, hi) = v.split_at_mut(a);
        (&mut hi[0], &mut lo[b])
    }
}

#[allow(clippy::too_many_arguments)]
fn collide<E: Equations, W: Write>(
    w: &mut World,
    q: &mut Queue,
    out: &mut Out<W>,
    t: f64,
    feat: i32,
    ai: usize,
    bi: usize,
    i: i64,
    j: i32,
) -> Res<()> {
    let rest_speed = w.s.rest_speed;
    let (a_fixed, b_fixed);
    {
        let verts = &w.s.verts;
        let (a_, b_) = two_mut(&mut w.s.bodies, ai, bi);
        advance(a_, t);
        advance(b_, t);
        let va = if i >= 0 { Some(&verts[a_.vert(i as usize)]) } else { None };
        let (nx, ny, cx, cy);
        if feat == CC {
            let (ax_, ay_) = point_at(a_, None, t);
            let vb = if j >= 0 { Some(&verts[b_.vert(j as usize)]) } else { None };
            let (bx_, by_) = point_at(b_, vb, t);
            let (dx, dy) = (bx_ - ax_, by_ - ay_);
            let dist = (dx * dx + dy * dy).sqrt();
            if dist > 0.0 {
                nx = dx / dist;
                ny = dy / dist;
            } else {
                nx = 1.0;
                ny = 0.0;
            }
            cx = ax_ + a_.r * nx;
            cy = ay_ + a_.r * ny;
        } else {
            let (px, py) = point_at(a_, va, t);
            let ed = &verts[b_.vert(j as usize)];
            let th = b_.ang + ed.psi;
            let (c, s) = ed.normal.of(th);
            // from A to B: against the edge's outward normal
            nx = -c;
            ny = -s;
            let rad = if va.is_none() { a_.r } else { 0.0 };
            cx = px + rad * nx;
            cy = py + rad * ny;
        }
        // velocities of the material points at the contact
        let uax = a_.vx - a_.om * (cy - a_.py);
        let uay = a_.vy + a_.om * (cx - a_.px);
        let ubx = b_.vx - b_.om * (cy - b_.py);
        let uby = b_.vy + b_.om * (cx - b_.px);
        let vn = (ubx - uax) * nx + (uby - uay) * ny;
        let mut imp = 0.0;
        if vn < 0.0 {
            let ran = (cx - a_.px) * ny - (cy - a_.py) * nx;
            let rbn = (cx - b_.px) * ny - (cy - b_.py) * nx;
            let k = a_.inv_m + b_.inv_m + a_.inv_i * ran * ran + b_.inv_i * rbn * rbn;
            let e = a_.e * b_.e;
            let lo = if rest_speed < -vn { rest_speed } else { -vn };
            let first = e * -vn;
            let sep = if lo > first { lo } else { first };
            imp = (sep - vn) / k;
            a_.vx = a_.vx - imp * a_.inv_m * nx;
            a_.vy = a_.vy - imp * a_.inv_m * ny;
            a_.om = a_.om - imp * a_.inv_i * ran;
            b_.vx = b_.vx + imp * b_.inv_m * nx;
            b_.vy = b_.vy + imp * b_.inv_m * ny;
            b_.om = b_.om + imp * b_.inv_i * rbn;
        }
        out.s("E collision");
        out.num(t);
        out.int(ai as i64);
        out.int(bi as i64);
        out.int(i64::from(feat));
        out.int(i);
        out.int(i64::from(j));
        out.num(cx);
        out.num(cy);
        out.num(nx);
        out.num(ny);
        out.num(imp);
        out.end_line()?;
        a_fixed = a_.fixed;
        b_fixed = b_.fixed;
        for b in [a_, b_] {
            if !b.fixed {
                w.stamps[b.index()] += 1;
                emit_state(out, b)?;
            }
        }
    }
    if !a_fixed {
        predict_body::<E>(w, q, ai, t, None)?;
    }
    if !b_fixed {
        predict_body::<E>(w, q, bi, t, if !a_fixed { Some(ai) } else { None })?;
    }
    Ok(())
}

fn run<E: Equations, W: Write>(scene: Scene, out: &mut Out<W>) -> Res<()> {
    let ncells = (scene.nx * scene.ny) as usize;
    let large = scene.bodies.iter().filter(|b| b.large).map(|b| b.idx).collect();
    let stamps = vec![0; scene.bodies.len()];
    let mut w = World { s: scene, stamps, cells: vec![CellList::default(); ncells], large };
    let mut q = Queue {
        heap: Heap::new(),
        seq: 0,
        stats: [0; 8],
        cc_counts: vec![0; E::CC_VARIANTS],
        pe_counts: vec![0; E::PE_VARIANTS],
    };
    let n = w.s.bodies.len();
    for b in 0..n {
        if !w.s.bodies[b].large {
            let (cx, cy) = cell_of(&w.s, w.s.bodies[b].px, w.s.bodies[b].py);
            w.s.bodies[b].cx = cx;
            w.s.bodies[b].cy = cy;
            w.cell_add(b);
        }
    }
    for k in 0..w.s.inputs.len() {
        let inp = w.s.inputs[k];
        q.push(&w.stamps, inp.t, INPUT, inp.body as i32, -1, -1, k as i64, inp.mode as i32);
    }
    if w.s.frame_dt > 0.0 && w.s.frame_dt <= w.s.end {
        q.push(&w.stamps, w.s.frame_dt, FRAME, -1, -1, -1, 1, -1);
    }
    for b in 0..n {
        let body = &w.s.bodies[b];
        if body.large {
            continue;
        }
        let (cx, cy, fixed) = (i64::from(body.cx), i64::from(body.cy), body.fixed);
        predict_cells::<E>(&w, &mut q, b, cx - 1, cx + 1, cy - 1, cy + 1, 0.0, None, true)?;
        for &o in &w.large {
            let o = o as usize;
            if !(fixed && w.s.bodies[o].fixed) {
                predict_pair::<E>(&w, &mut q, b, o, 0.0)?;
            }
        }
        schedule_cell(&w, &mut q, b, 0.0);
    }
    let mut last_t = -1.0;
    let mut same: i64 = 0;
    while let Some(popped) = q.heap.pop() {
        let t = popped.t;
        let ev = popped.p;
        if t > w.s.end {
            break;
        }
        let kind = popped.key >> SEQ_BITS;
        // an input is scripted, not predicted: it happens whatever the body did before
        if kind != INPUT
            && ((ev.a >= 0 && w.stamps[ev.a as usize] != ev.sa) || (ev.b >= 0 && w.stamps[ev.b as usize] != ev.sb))
        {
            q.stats[ST_STALE] += 1;
            continue;
        }
        if t == last_t {
            same += 1;
            if same > w.s.max_same {
                return Err(Stop::Scene(format!(
                    "more than {} events at t = {}: the scene is stuck",
                    w.s.max_same,
                    g17(t)
                )));
            }
        } else {
            last_t = t;
            same = 0;
        }
        match kind {
            COLLISION => {
                q.stats[ST_COLLISIONS] += 1;
                collide::<E, W>(&mut w, &mut q, out, t, ev.feat, ev.a as usize, ev.b as usize, ev.i, ev.j)?;
            }
            INPUT => {
                q.stats[ST_INPUTS] += 1;
                let inp = w.s.inputs[ev.i as usize];
                let a = ev.a as usize;
                let body = &mut w.s.bodies[a];
                advance(body, t);
                if inp.mode == 0 {
                    body.vx = inp.vx;
                    body.vy = inp.vy;
                } else {
                    body.vx = body.vx + inp.vx;
                    body.vy = body.vy + inp.vy;
                }
                w.stamps[a] += 1;
                out.s("E input");
                out.num(t);
                out.int(a as i64);
                out.s(" -1 -1");
                out.int(ev.i);
                out.s(" -1 0 0 0 0 0");
                out.end_line()?;
                emit_state(out, &w.s.bodies[a])?;
                predict_body::<E>(&w, &mut q, a, t, None)?;
            }
            CELL => {
                q.stats[ST_CELLS] += 1;
                let a = ev.a as usize;
                w.cell_remove(a);
                let dir = i64::from(ev.j);
                let news;
                {
                    let body = &mut w.s.bodies[a];
                    let (mut cx, mut cy) = (i64::from(body.cx), i64::from(body.cy));
                    if ev.i == 0 {
                        cx += dir;
                        let col = cx + dir;
                        news = (col, col, cy - 1, cy + 1);
                    } else {
                        cy += dir;
                        let row = cy + dir;
                        news = (cx - 1, cx + 1, row, row);
                    }
                    // a cell event moves to a neighbouring cell of the grid
                    body.cx = cx as i32;
                    body.cy = cy as i32;
                }
                w.cell_add(a);
                predict_cells::<E>(&w, &mut q, a, news.0, news.1, news.2, news.3, t, None, false)?;
                schedule_cell(&w, &mut q, a, t);
            }
            HORIZON => {
                q.stats[ST_HORIZONS] += 1;
                predict_pair::<E>(&w, &mut q, ev.a as usize, ev.b as usize, t)?;
            }
            _ => {
                debug_assert_eq!(kind, FRAME);
                q.stats[ST_FRAMES] += 1;
                out.s("E frame");
                out.num(t);
                out.s(" -1 -1 -1 -1 -1 0 0 0 0 0");
                out.end_line()?;
                let nxt = (ev.i + 1) as f64 * w.s.frame_dt;
                if nxt <= w.s.end {
                    q.push(&w.stamps, nxt, FRAME, -1, -1, -1, ev.i + 1, -1);
                }
            }
        }
    }
    let end = w.s.end;
    for b in w.s.bodies.iter_mut() {
        advance(b, end);
    }
    for b in &w.s.bodies {
        out.s("F");
        out.int(i64::from(b.idx));
        out.num(b.px);
        out.num(b.py);
        out.num(b.vx);
        out.num(b.vy);
        out.num(b.ang);
        out.num(b.om);
        out.end_line()?;
    }
    for (k, name) in STAT_NAMES.iter().enumerate() {
        out.s("N ");
        out.s(name);
        out.int(q.stats[k] as i64);
        out.end_line()?;
    }
    for (k, &c) in q.cc_counts.iter().enumerate() {
        out.s("V circle_circle");
        out.int(k as i64);
        out.int(c as i64);
        out.end_line()?;
    }
    for (k, &c) in q.pe_counts.iter().enumerate() {
        out.s("V point_edge");
        out.int(k as i64);
        out.int(c as i64);
        out.end_line()?;
    }
    Ok(())
}

/// Run a compiled scene (the flat text), writing the flat trace to `sink`.
/// Returns the exit status: 0, or 1 after an `X message` line for a stuck
/// or bad scene (the trace so far stays written, as the Python runtime's).
pub fn simulate<E: Equations, W: Write>(scene_text: &str, sink: W) -> io::Result<i32> {
    let mut out = Out { buf: Vec::with_capacity(1 << 17), sink };
    let res = match Scene::parse(scene_text) {
        Ok(scene) => run::<E, W>(scene, &mut out),
        Err(msg) => Err(Stop::Scene(msg)),
    };
    match res {
        Ok(()) => {
            out.flush()?;
            Ok(0)
        }
        Err(Stop::Scene(msg)) => {
            out.s("X ");
            out.s(&msg);
            out.buf.push(b'\n');
            out.flush()?;
            Ok(1)
        }
        Err(Stop::Io(e)) => Err(e),
    }
}

/// The simulator program: compiled scene on stdin, flat trace on stdout;
/// returns the exit status.
pub fn main<E: Equations>() -> i32 {
    let mut text = String::new();
    if let Err(e) = io::stdin().read_to_string(&mut text) {
        eprintln!("max2code simulator: cannot read the scene: {e}");
        return 2;
    }
    let stdout = io::stdout();
    match simulate::<E, _>(&text, stdout.lock()) {
        Ok(code) => code,
        Err(e) => {
            eprintln!("max2code simulator: cannot write the trace: {e}");
            2
        }
    }
}

/// The `main` of a simulator binary: `sim_main!(circle_circle, point_edge)`
/// with the two generated modules (equations/circle-circle.mxm and
/// equations/point-edge.mxm) in scope implements [`Equations`] with their
/// entries and runs [`main`].
#[macro_export]
macro_rules! sim_main {
    ($cc:ident, $pe:ident) => {
        struct GeneratedEquations;

        impl $crate::sim::Equations for GeneratedEquations {
            const CC_VARIANTS: usize = $cc::CIRCLE_CIRCLE_VARIANT_NAMES.len();
            const PE_VARIANTS: usize = $pe::POINT_EDGE_VARIANT_NAMES.len();

            #[inline]
            fn cc_variant(p: &[f64; 24]) -> i32 {
                $cc::circle_circle_variant(
                    p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13], p[14],
                    p[15], p[16], p[17], p[18], p[19], p[20], p[21], p[22], p[23],
                )
            }

            #[inline]
            fn cc_coefficients(p: &[f64; 24], c: &mut [f64; $crate::sim::MAX_COEF]) -> Option<usize> {
                let (degree, k) = $cc::circle_circle_coefficients(
                    p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13], p[14],
                    p[15], p[16], p[17], p[18], p[19], p[20], p[21], p[22], p[23],
                )?;
                c[..k.len()].copy_from_slice(&k);
                Some(degree)
            }

            #[inline]
            fn pe_variant(p: &[f64; 12]) -> i32 {
                $pe::point_edge_variant(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11])
            }

            #[inline]
            fn pe_coefficients(p: &[f64; 12], c: &mut [f64; $crate::sim::MAX_COEF]) -> Option<usize> {
                let (degree, k) =
                    $pe::point_edge_coefficients(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11])?;
                c[..k.len()].copy_from_slice(&k);
                Some(degree)
            }
        }

        fn main() {
            ::std::process::exit($crate::sim::main::<GeneratedEquations>());
        }
    };
}

#[cfg(test)]
mod tests {
    use super::{CellList, Heap, Payload, CELL_INLINE};

    /// xorshift64*: reproducible numbers without a dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
    }

    fn payload(k: u64) -> Payload {
        Payload { a: k as i32, b: -1, feat: 0, j: 0, i: k as i64, sa: k, sb: 0 }
    }

    #[test]
    fn heap_pops_in_time_then_key_order() {
        let mut rng = Rng(12345);
        let mut heap = Heap::new();
        let mut all: Vec<(f64, u64)> = Vec::new();
        let mut popped: Vec<(f64, u64, i64)> = Vec::new();
        let mut pending: Vec<(f64, u64)> = Vec::new();
        let first = |v: &Vec<(f64, u64)>| -> usize {
            let mut m = 0;
            for k in 1..v.len() {
                if v[k].0 < v[m].0 || (v[k].0 == v[m].0 && v[k].1 < v[m].1) {
                    m = k;
                }
            }
            m
        };
        let mut now = 0.0;
        for seq in 0..20_000u64 {
            // few distinct times, so that equal times are ordered by key;
            // some before the time reached (as a rounding error can put
            // them), some -0.0 (equal to 0.0)
            let t = match rng.next() % 8 {
                0 => now - (rng.next() % 4) as f64 * 0.125,
                1 => -0.0,
                _ => now + (rng.next() % 50) as f64 * 0.125,
            };
            let key = ((rng.next() % 5) << 60) | seq;
            heap.push(t, key, payload(seq));
            all.push((t, key));
            pending.push((t, key));
            if rng.next() % 3 != 0 {
                let e = heap.pop().expect("not empty");
                let m = first(&pending);
                assert_eq!((e.t.to_bits(), e.key), (pending[m].0.to_bits(), pending[m].1));
                pending.swap_remove(m);
                popped.push((e.t, e.key, e.p.i));
                now = e.t;
            }
        }
        while let Some(e) = heap.pop() {
            popped.push((e.t, e.key, e.p.i));
        }
        assert_eq!(popped.len(), all.len());
        // every payload comes back with its entry
        for &(_, key, i) in &popped {
            assert_eq!(key & ((1 << 60) - 1), i as u64);
        }
        // with everything pushed first, the pops are the sorted order
        let mut heap = Heap::new();
        for (seq, &(t, key)) in all.iter().enumerate() {
            heap.push(t, key, payload(seq as u64));
        }
        let mut sorted = all.clone();
        sorted.sort_by(|x, y| x.0.partial_cmp(&y.0).unwrap().then(x.1.cmp(&y.1)));
        for &(t, key) in &sorted {
            let e = heap.pop().expect("not empty");
            assert_eq!((e.t, e.key), (t, key));
        }
        assert!(heap.pop().is_none());
    }

    #[test]
    fn cell_list_is_a_python_list_with_last_into_the_hole() {
        let mut rng = Rng(777);
        let mut cell = CellList::default();
        let mut model: Vec<u32> = Vec::new();
        let mut next = 0u32;
        for _ in 0..50_000 {
            if model.is_empty() || (model.len() < 3 * CELL_INLINE && rng.next() % 2 == 0) {
                cell.push(next);
                model.push(next);
                next += 1;
            } else {
                let x = model[(rng.next() % model.len() as u64) as usize];
                cell.remove(x);
                let k = model.iter().position(|&o| o == x).unwrap();
                let last = model.pop().unwrap();
                if k < model.len() {
                    model[k] = last;
                }
            }
            assert_eq!(cell.n as usize, model.len());
            for (k, &x) in model.iter().enumerate() {
                assert_eq!(cell.get(k), x);
            }
        }
    }
}
