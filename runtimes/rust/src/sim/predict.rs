//! Predictions: the first contact of a pair after now ([`pair_search`],
//! which the TOI library [`crate::toi`] calls too; or a horizon event where
//! the Taylor polynomials of its turns stop being good), and a body's next
//! cell crossing.  Every prediction goes through the generated
//! entries ([`Equations`]) and the root solver [`smallest_root`].

use super::motion::{point_at, state_at, turn_rate};
use super::out::{Res, SimError};
use super::overlap::{edge_line, polygons_separation, separation, vertices};
use super::queue::prefetch;
use super::scene::{Body, Vertex};
use super::sleep::grounded;
use super::support::schedule_support;
use super::world::{Queue, Space};
use super::{Equations, CC, HALF_PI, MAX_COEF, PE};
use crate::roots::smallest_root;

/// The most stages (a meeting of the bounds, a clear stretch, a Taylor
/// window) one prediction of a pair goes through before it leaves the rest
/// to a horizon.
const CHAIN: usize = 8;
/// A clear stretch of two turning polygons shorter than this many Taylor
/// windows leads straight to the window at its end (the TOI library only).
const STRAIGHT: f64 = 4.0;

/// What a pair's computation reads besides the two bodies: the simulator's
/// [`Space`], or the TOI library's pair ([`crate::toi`]).
pub trait PairEnv {
    /// m: the distance tolerance
    fn tol(&self) -> f64;
    /// rad: the window angle of a pair in which both bodies turn
    fn alpha(&self) -> f64;
    /// every vertex, indexed by [`Body::vert`]
    fn verts(&self) -> &[Vertex];
    /// whether the fixed body `cover` (>= 0) still covers its edge
    fn covered(&self, cover: i64) -> bool;
    /// true for the TOI library, which has no world: its own clear stretch
    /// of two polygons ([`clear_polygons`]) and its overlap test of the
    /// bounds without a polynomial ([`bounds_meet`]); the simulator keeps
    /// the values whose bits its traces pin
    #[inline(always)]
    fn library(&self) -> bool {
        false
    }
}

impl PairEnv for Space {
    #[inline(always)]
    fn tol(&self) -> f64 {
        self.s.tol
    }
    #[inline(always)]
    fn alpha(&self) -> f64 {
        self.s.alpha
    }
    #[inline(always)]
    fn verts(&self) -> &[Vertex] {
        &self.s.verts
    }
    #[inline(always)]
    fn covered(&self, cover: i64) -> bool {
        !self.s.bodies[cover as usize].gone
    }
}

/// Where a pair's computation counts the generated entries' variants it
/// serves: the simulator's [`Queue`] (and its features counter); the TOI
/// library counts nothing.
pub trait Counter {
    fn count_cc(&mut self, idx: usize);
    fn count_pe(&mut self, idx: usize);
}

impl Counter for Queue {
    #[inline(always)]
    fn count_cc(&mut self, idx: usize) {
        self.cc_counts[idx] += 1;
        self.stats.features += 1;
    }
    #[inline(always)]
    fn count_pe(&mut self, idx: usize) {
        self.pe_counts[idx] += 1;
        self.stats.features += 1;
    }
}

/// At a zero of the gap c: approaching (first derivative d < 0), or
/// resting and pressed together (d == 0, second derivative < 0).
#[inline(always)]
pub fn pressing(c: &[f64; MAX_COEF], deg: usize, d: f64, s: f64) -> bool {
    if d < 0.0 {
        return true;
    }
    if d != 0.0 || deg < 2 {
        return false;
    }
    let mut dd = 0.0;
    for k in (2..=deg).rev() {
        dd = dd * s + (k * (k - 1)) as f64 * c[k];
    }
    dd < 0.0
}

/// At s = 0, with the gap zero within kappa: approaching (c1 < 0), or
/// pressed together (c2 < 0) so that the gap closes again before it ever
/// exceeds kappa: its largest value c0 + c1^2 / (4 |c2|) <= kappa.  (A
/// resting body's c1 is zero up to rounding: cos(pi/2) is 6e-17.)
#[inline(always)]
pub fn touching_now(c: &[f64; MAX_COEF], deg: usize, kappa: f64) -> bool {
    if c[1] < 0.0 {
        return true;
    }
    if deg < 2 || !(c[2] < 0.0) {
        return false;
    }
    c[0] + c[1] * c[1] / (4.0 * -c[2]) <= kappa
}

/// The smallest s in [0, w] where the gap c(s) reaches zero while
/// decreasing, or touches zero with zero slope while pressed together
/// (resting contact), and check(s) holds.  At s = 0 the gap counts as zero
/// within kappa: approaching or pressed (touching_now) means contact now,
/// separating or merely touching never.
///
/// before: the earliest contact of the pair's other features found so far
/// (+inf for none); a contact at or after it is never kept (the earliest
/// one, first found on a tie, wins), so the search may answer None instead
/// (docs/simulator.md, "Features that cannot come first"): at once when
/// before is 0, and when a Bernstein test shows no root in [0, before (1 +
/// 2^-10)] (degrees 3 and 4: the root solver's entry's; 5 to 8:
/// no_root_high), so that a root found in [0, w] lies beyond before by far
/// more than the solver's error.
#[inline(always)]
pub fn first_contact<F: FnMut(f64) -> bool>(
    c: &[f64; MAX_COEF],
    deg: usize,
    w: f64,
    kappa: f64,
    before: f64,
    mut check: F,
) -> Option<f64> {
    if !(before > 0.0) {
        return None;
    }
    if deg >= 1 && c[0].abs() <= kappa && touching_now(c, deg, kappa) && check(0.0) {
        return Some(0.0);
    }
    if before < w && (3..=8).contains(&deg) {
        let h = before + before * TWO_M10;
        let clear = |h: f64| {
            if deg <= 4 {
                h >= TWO_M250 && if deg == 3 { crate::roots::no_root3(c, h) } else { crate::roots::no_root4(c, h) }
            } else {
                h >= TWO_M100 && no_root_high(c, deg, h)
            }
        };
        if h < w && clear(h) {
            return None;
        }
    }
    let mut lo = 0.0;
    for _ in 0..deg + 2 {
        let s = smallest_root(&c[..deg + 1], lo, w)?;
        let mut d = 0.0;
        for k in (1..=deg).rev() {
            d = d * s + k as f64 * c[k];
        }
        if pressing(c, deg, d, s) && check(s) {
            return Some(s);
        }
        lo = s;
    }
    None
}

/// 2^-10 and 2^-250 (first_contact's margin and the Bernstein test's least interval).
const TWO_M10: f64 = 1.0 / 1024.0;
const TWO_M250: f64 = two_to(-250);

const TWO_M100: f64 = two_to(-100);
const TWO_M46: f64 = two_to(-46);

/// Binomial coefficients C(j, i), j <= 8 (exact in an f64).
const BINOMIAL: [[f64; 9]; 9] = [
    [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 2.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 3.0, 3.0, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 4.0, 6.0, 4.0, 1.0, 0.0, 0.0, 0.0, 0.0],
    [1.0, 5.0, 10.0, 10.0, 5.0, 1.0, 0.0, 0.0, 0.0],
    [1.0, 6.0, 15.0, 20.0, 15.0, 6.0, 1.0, 0.0, 0.0],
    [1.0, 7.0, 21.0, 35.0, 35.0, 21.0, 7.0, 1.0, 0.0],
    [1.0, 8.0, 28.0, 56.0, 70.0, 56.0, 28.0, 8.0, 1.0],
];

/// The polynomial c of degree n (5 to 8) surely has no root in [0, hi]
/// (hi >= 2^-100, so that hi^8 stays normal): its Bernstein coefficients
/// there, b_j = sum_{i <= j} C(j, i) u_i with t_i = c_i hi^i and u_i = t_i /
/// C(n, i), are all beyond m = 2^-46 S + 2^-900 (S = sum |t_i|) with t_0's
/// sign (the root solver's test for degrees 3 and 4, for higher degrees:
/// docs/simulator.md, "Features that cannot come first").
fn no_root_high(c: &[f64; MAX_COEF], n: usize, hi: f64) -> bool {
    let mut u = [0.0; 9];
    let (mut p, mut sum) = (1.0, 0.0);
    for (i, (ui, ci)) in u.iter_mut().zip(c).take(n + 1).enumerate() {
        let t = ci * p;
        p = p * hi;
        sum = sum + t.abs();
        *ui = t / BINOMIAL[n][i];
    }
    let m = TWO_M46 * sum + TWO_M900;
    let neg = u[0] < 0.0;
    for (j, row) in BINOMIAL.iter().enumerate().take(n + 1) {
        let mut b = 0.0;
        for (w, ui) in row[..=j].iter().zip(&u) {
            b = b + w * ui;
        }
        if !(if neg { b < -m } else { b > m }) {
            return false;
        }
    }
    true
}

/// first_contact's before for the earliest contact found so far.
#[inline(always)]
fn before_of(best: Option<Best>) -> f64 {
    best.map_or(f64::INFINITY, |b| b.s)
}

// ---- features -----------------------------------------------------------------

/// circle_circle parameters (x, vx, ax, d, e, f; y, vy, ay, p, q) of a
/// circle's centre (v None) or of a polygon's vertex, at time now.
#[inline(always)]
pub(super) fn circle_params(b: &Body, now: f64, v: Option<&Vertex>) -> [f64; 11] {
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

/// Counts a circle_circle prediction of these 24 parameters: its variant
/// and the features counter.
#[inline(always)]
fn cc_count<E: Equations, C: Counter>(q: &mut C, args: &[f64; 24]) -> Res<()> {
    let idx = E::cc_variant(args);
    if idx < 0 {
        return Err(SimError::Msg("circle_circle: the scene uses an effect the generated code leaves out".into()));
    }
    q.count_cc(idx as usize);
    Ok(())
}

#[inline(always)]
fn cc_coefficients<E: Equations, C: Counter>(q: &mut C, args: &[f64; 24], coef: &mut [f64; MAX_COEF]) -> Res<usize> {
    cc_count::<E, _>(q, args)?;
    E::cc_coefficients(args, coef)
        .ok_or_else(|| SimError::Msg("circle_circle: the scene uses an effect the generated code leaves out".into()))
}

/// circle_circle parameters of b's centre of rotation at time now, no
/// orbit: the centre of a bounding circle (circle_params of a polygon).
#[inline(always)]
fn centre_params(b: &Body, now: f64) -> [f64; 11] {
    let (x, y, vx, vy, _) = state_at(b, now);
    [x, vx, b.ax, 0.0, 0.0, HALF_PI, y, vy, b.ay, 0.0, 0.0]
}

/// Circle of A against circle of B (vb None) or vertex vb of B (radius 0).
#[allow(clippy::too_many_arguments)]
fn predict_cc<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    a_: &Body,
    b_: &Body,
    vb: Option<&Vertex>,
    rb: f64,
    now: f64,
    win: f64,
    before: f64,
) -> Res<Option<f64>> {
    circles_first::<E, _, _>(w, q, &circle_params(a_, now, None), a_.r, &circle_params(b_, now, vb), rb, win, before)
}

/// circle_circle's 24 parameters for two bodies that do not turn:
/// circle_params' values written out (d = 0 sets the turn and the phase to
/// 0), with (oa, ob) in the orbit-radius slots (the bodies' orbits, or 0.0
/// for bounding circles) and (ra, rb) the circles' radii.
#[inline(always)]
fn plain_args(a_: &Body, b_: &Body, now: f64, (oa, ob): (f64, f64), (ra, rb): (f64, f64)) -> [f64; 24] {
    let (xa, ya, vxa, vya, _) = state_at(a_, now);
    let (xb, yb, vxb, vyb, _) = state_at(b_, now);
    [
        xa - xb,
        vxa - vxb,
        a_.ax - b_.ax,
        oa,
        0.0,
        HALF_PI,
        ya - yb,
        vya - vyb,
        a_.ay - b_.ay,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        ob,
        0.0,
        HALF_PI,
        0.0,
        0.0,
        0.0,
        0.0,
        0.0,
        ra,
        rb,
    ]
}

/// predict_cc of two circles that do not orbit (orbit 0: neither turns),
/// with circle_params' values written out: the same 24 parameters, bit for
/// bit (d = 0 sets the turn and the phase to 0), without its branches and
/// copies.  Most pairs of a gas are such.
#[inline(always)]
fn circles_plain<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    a_: &Body,
    b_: &Body,
    now: f64,
    win: f64,
) -> Res<Option<f64>> {
    let args = plain_args(a_, b_, now, (a_.orbit, b_.orbit), (a_.r, b_.r));
    circles_first_args::<E, _, _>(w, q, &args, win, f64::INFINITY)
}

/// The first contact within [0, win] of a circle of radius ra moving as pa
/// (circle_params) and one of radius rb moving as pb.
#[allow(clippy::too_many_arguments)]
fn circles_first<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    pa: &[f64; 11],
    ra: f64,
    pb: &[f64; 11],
    rb: f64,
    win: f64,
    before: f64,
) -> Res<Option<f64>> {
    circles_first_args::<E, _, _>(w, q, &cc_args(pa, ra, pb, rb), win, before)
}

/// circles_first of circle_circle's 24 parameters (cc_args).
#[inline(always)]
fn circles_first_args<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    args: &[f64; 24],
    win: f64,
    before: f64,
) -> Res<Option<f64>> {
    let (ra, rb) = (args[22], args[23]);
    let tol = w.tol();
    let kappa = tol * (2.0 * (ra + rb) + tol);
    if circles_apart(args, kappa) {
        cc_count::<E, _>(q, args)?;
        return Ok(None);
    }
    let mut coef = [0.0; MAX_COEF];
    let deg = cc_coefficients::<E, _>(q, args, &mut coef)?;
    Ok(first_contact(&coef, deg, win, kappa, before, |_| true))
}

/// The pair of circles_gap's parameters g surely has no contact, decided
/// without the polynomial (docs/simulator.md, "Pairs that stay apart"):
/// neither circle orbits and their relative acceleration is zero, so the
/// gap is |p + v s|^2 - R^2 (p, v: the relative position and velocity, R =
/// ra + rb), and either the centres separate (p . v > 0 by more than its
/// rounding: the generated c1 = 2 p.v is then positive, c2 = |v|^2 is never
/// negative, and first_contact finds no approach), or they approach on a
/// line that passes farther than R from each other: (p x v)^2 > (R^2 +
/// kappa) |v|^2 by more than the rounding (then the gap now exceeds kappa
/// and its discriminant is clearly negative: no root).  The margins (2^-40
/// and 2^-30 of the terms' size) are far above the few units of 2^-53 by
/// which the coefficients can be off, and the sizes are bounded so that
/// nothing underflows (where rounding is no longer relative: a speed of
/// 1e-162 m/s squares to 0) or overflows.  The prediction is still counted.
// the bounds as comparisons: `contains` compiles to more instructions per prediction here
#[allow(clippy::manual_range_contains)]
#[inline(always)]
fn circles_apart(g: &[f64; 24], kappa: f64) -> bool {
    if g[2] != 0.0 || g[8] != 0.0 || g[3] != 0.0 || g[14] != 0.0 {
        return false;
    }
    let (x, vx, y, vy) = (g[0], g[1], g[6], g[7]);
    let (px, py) = (x * vx, y * vy);
    let size = px.abs() + py.abs();
    if size >= TWO_M900 && px + py > TWO_M40 * size {
        return true;
    }
    let r = g[22] + g[23];
    let (v2, p2) = (vx * vx + vy * vy, x * x + y * y);
    if !(v2 >= TWO_M450 && v2 <= TWO_P450 && p2 >= TWO_M450 && p2 <= TWO_P450) {
        return false;
    }
    let cross = x * vy - y * vx;
    cross * cross - (r * r + kappa) * v2 > TWO_M30 * p2 * v2
}

/// 2^e (a normal double) from its bits.
const fn two_to(e: i64) -> f64 {
    f64::from_bits(((1023 + e) as u64) << 52)
}
const TWO_M40: f64 = two_to(-40);
const TWO_M30: f64 = two_to(-30);
const TWO_M900: f64 = two_to(-900);
const TWO_M450: f64 = two_to(-450);
const TWO_P450: f64 = two_to(450);

/// The circle_circle polynomial (squared distance of the centres less
/// (ra + rb)^2, in s from the parameters' time) of a circle of radius ra
/// moving as pa (circle_params) and one of radius rb moving as pb, in
/// `coef`; returns its degree.
#[inline(always)]
pub(super) fn circles_gap<E: Equations, C: Counter>(
    q: &mut C,
    pa: &[f64; 11],
    ra: f64,
    pb: &[f64; 11],
    rb: f64,
    coef: &mut [f64; MAX_COEF],
) -> Res<usize> {
    cc_coefficients::<E, _>(q, &cc_args(pa, ra, pb, rb), coef)
}

/// circle_circle's 24 parameters of a circle of radius ra moving as pa
/// (circle_params) and one of radius rb moving as pb.
#[inline(always)]
fn cc_args(pa: &[f64; 11], ra: f64, pb: &[f64; 11], rb: f64) -> [f64; 24] {
    let [a, b, c, d, e, f, m, n, o, p, qq] = *pa;
    let [g, h, i, j, k, l, r, s, u, v, ww] = *pb;
    // only differences of the centres' motions matter: circle 1 moves
    // relative to circle 2's centre of rotation
    [a - g, b - h, c - i, d, e, f, m - r, n - s, o - u, p, qq, 0.0, 0.0, 0.0, j, k, l, 0.0, 0.0, 0.0, v, ww, ra, rb]
}

/// Point of X (circle centre with radius, or vertex vx_, X's vertex i;
/// -1: a circle) against the line of edge j of Y (none while a fixed body
/// covers the edge: its cover is not gone).
#[allow(clippy::too_many_arguments)]
fn predict_pe<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    x_: &Body,
    y_: &Body,
    vx_: Option<&Vertex>,
    j: usize,
    now: f64,
    win: f64,
    i: i32,
    before: f64,
) -> Res<Option<f64>> {
    let cover = w.verts()[y_.vert(j)].cover;
    if cover >= 0 && w.covered(cover) {
        return Ok(None);
    }
    let (rho, beta, rad) = match vx_ {
        None => (x_.orbit, x_.ophase, x_.r),
        Some(v) => (v.rho, v.beta, 0.0),
    };
    let mut coef = [0.0; MAX_COEF];
    let deg = pe_coefficients::<E, _>(w.verts(), q, x_, y_, rho, beta, rad, j, now, &mut coef)?;
    Ok(pe_first(w, &coef, deg, x_, y_, (rho, beta, vx_), j, now, win, i, before))
}

/// The point_edge polynomial of a circle of radius rad whose centre orbits
/// X's centre at rho (phase beta in X's frame) against the line of edge j
/// of Y, in s = t - now (its c[0]: the gap now); returns its degree.
#[allow(clippy::too_many_arguments)]
pub(super) fn pe_coefficients<E: Equations, C: Counter>(
    verts: &[Vertex],
    q: &mut C,
    x_: &Body,
    y_: &Body,
    rho: f64,
    beta: f64,
    rad: f64,
    j: usize,
    now: f64,
    coef: &mut [f64; MAX_COEF],
) -> Res<usize> {
    let ed = &verts[y_.vert(j)];
    let (x1, y1, u1, v1, ang1) = state_at(x_, now);
    let (x2, y2, u2, v2, ang2) = state_at(y_, now);
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
        return Err(SimError::Msg("point_edge: the scene uses an effect the generated code leaves out".into()));
    }
    q.count_pe(idx as usize);
    E::pe_coefficients(&args, coef)
        .ok_or_else(|| SimError::Msg("point_edge: the scene uses an effect the generated code leaves out".into()))
}

/// The first contact within [0, win] of pe_coefficients' polynomial whose
/// point (X's centre, or rho, beta about it; `pt.2` the vertex, whose cos
/// and sin are cached) lies on edge j's segment; when the point is X's
/// vertex i (i >= 0), both neighbours of that vertex must also lie no more
/// than the tolerance behind edge j's line (`behind`: else that line does
/// not separate the bodies there, a corner meeting a corner: another
/// feature pair is the contact).
#[allow(clippy::too_many_arguments)]
fn pe_first<W: PairEnv>(
    w: &W,
    coef: &[f64; MAX_COEF],
    deg: usize,
    x_: &Body,
    y_: &Body,
    pt: (f64, f64, Option<&Vertex>),
    j: usize,
    now: f64,
    win: f64,
    i: i32,
    before: f64,
) -> Option<f64> {
    let ed = &w.verts()[y_.vert(j)];
    let tol = w.tol();
    let (rho, beta, vx_) = pt;
    let inside = |s: f64| -> bool {
        let t = now + s;
        let (mut px, mut py, _, _, pa) = state_at(x_, t);
        if rho != 0.0 {
            let (c, s) = match vx_ {
                Some(v) => v.at.of(pa + beta),
                None => ((pa + beta).cos(), (pa + beta).sin()),
            };
            px = px + rho * c;
            py = py + rho * s;
        }
        let (qx, qy, _, _, qa) = state_at(y_, t);
        let th = qa + ed.psi;
        let (c, sn) = ed.normal.of(th);
        let along = (px - qx) * -sn + (py - qy) * c;
        if !(ed.s1 - tol <= along && along <= ed.s2 + tol) {
            return false;
        }
        if i < 0 {
            return true;
        }
        !behind(w, x_, i as usize, t, (qx, qy), (c, sn), ed.h)
    };
    first_contact(coef, deg, win, tol, before, inside)
}

/// A neighbour of X's vertex i at t lies more than the tolerance behind the
/// line (c, sn) . (p - q) = h (an edge's line: its outward unit normal
/// `n` = (c, sn), its body's centre `q`), previous neighbour first
/// (docs/simulator.md, "Corners").
#[inline]
fn behind<W: PairEnv>(w: &W, x_: &Body, i: usize, t: f64, q: (f64, f64), n: (f64, f64), h: f64) -> bool {
    let nv = x_.nverts();
    let (px, py, _, _, pa) = state_at(x_, t);
    let (qx, qy) = q;
    let (c, sn) = n;
    let lim = -w.tol();
    for k in [(i + nv - 1) % nv, (i + 1) % nv] {
        let v = &w.verts()[x_.vert(k)];
        let (vc, vs) = v.at.of(pa + v.beta);
        let kx = px + v.rho * vc;
        let ky = py + v.rho * vs;
        if (kx - qx) * c + (ky - qy) * sn - h < lim {
            return true;
        }
    }
    false
}

/// A candidate contact: s after its time, feature feat of body a's point
/// (i: its vertex, -1 the circle) against body b's edge, vertex or circle j.
#[derive(Clone, Copy)]
pub struct Best {
    pub s: f64,
    pub feat: i32,
    pub a: usize,
    pub b: usize,
    pub i: i32,
    pub j: i32,
}

#[inline(always)]
fn better(best: Option<Best>, t: Option<f64>, feat: i32, a: usize, b: usize, i: i32, j: i32) -> Option<Best> {
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
fn bounds_meet<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    a_: &Body,
    b_: &Body,
    now: f64,
    win: f64,
) -> Res<Option<f64>> {
    let tol = w.tol();
    if w.library() {
        // bounds that overlap now need no polynomial (a test that says
        // overlap only goes on to the next step)
        let (x1, y1, _, _, _) = state_at(a_, now);
        let (x2, y2, _, _, _) = state_at(b_, now);
        let (dx, dy, r) = (x1 - x2, y1 - y2, a_.bound + b_.bound);
        if dx * dx + dy * dy - r * r <= tol * (2.0 * r + tol) {
            return Ok(Some(0.0));
        }
    }
    let args = plain_args(a_, b_, now, (0.0, 0.0), (a_.bound, b_.bound));
    let mut coef = [0.0; MAX_COEF];
    let deg = cc_coefficients::<E, _>(q, &args, &mut coef)?;
    if coef[0] <= tol * (2.0 * (a_.bound + b_.bound) + tol) {
        return Ok(Some(0.0));
    }
    Ok(smallest_root(&coef[..deg + 1], 0.0, win))
}

/// T turns, polygon P does not: when T's bounding circle (radius T.bound
/// about T's centre of rotation, which does not turn) first touches P
/// itself (its edges, then its vertices) within (0, win]; 0.0 when no edge
/// line of P has the circle beyond it by more than the tolerance now
/// (overlapping, or near a corner); None when they do not meet.  Exact:
/// neither the circle nor P turns.
fn bound_polygon<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    t_: &Body,
    p_: &Body,
    now: f64,
    win: f64,
) -> Res<Option<f64>> {
    let tol = w.tol();
    let n = p_.nverts();
    let mut coefs: Vec<([f64; MAX_COEF], usize)> = Vec::with_capacity(n);
    let mut apart = false;
    for j in 0..n {
        let mut c = [0.0; MAX_COEF];
        let deg = pe_coefficients::<E, _>(w.verts(), q, t_, p_, 0.0, 0.0, t_.bound, j, now, &mut c)?;
        if c[0] > tol {
            apart = true;
        }
        coefs.push((c, deg));
    }
    if !apart {
        return Ok(Some(0.0));
    }
    let mut meet: Option<f64> = None;
    for (j, (c, deg)) in coefs.iter().enumerate() {
        if let Some(t) = pe_first(w, c, *deg, t_, p_, (0.0, 0.0, None), j, now, win, -1, meet.unwrap_or(f64::INFINITY))
        {
            if meet.is_none_or(|m| t < m) {
                meet = Some(t);
            }
        }
    }
    let pt = centre_params(t_, now);
    for k in 0..n {
        let v = &w.verts()[p_.vert(k)];
        let before = meet.unwrap_or(f64::INFINITY);
        let t = circles_first::<E, _, _>(w, q, &pt, t_.bound, &circle_params(p_, now, Some(v)), 0.0, win, before)?;
        if let Some(t) = t {
            if meet.is_none_or(|m| t < m) {
                meet = Some(t);
            }
        }
    }
    Ok(meet)
}

fn circle_polygon<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    c_: &Body,
    p_: &Body,
    now: f64,
    win: f64,
    mut best: Option<Best>,
) -> Res<Option<Best>> {
    for j in 0..p_.nverts() {
        let t = predict_pe::<E, _, _>(w, q, c_, p_, None, j, now, win, -1, before_of(best))?;
        best = better(best, t, PE, c_.index(), p_.index(), -1, j as i32);
    }
    for k in 0..p_.nverts() {
        let v = &w.verts()[p_.vert(k)];
        let t = predict_cc::<E, _, _>(w, q, c_, p_, Some(v), 0.0, now, win, before_of(best))?;
        best = better(best, t, CC, c_.index(), p_.index(), -1, k as i32);
    }
    Ok(best)
}

/// The most edges a window's bound keeps per edge (window_bound): the TOI
/// library's polygons have at most 64 vertices; a larger polygon of a
/// scene is solved pair by pair without it.
const WINDOW_EDGES: usize = 64;

/// What every vertex-edge pair of a window shares ([`window_bound`]).  X
/// holds the vertices, Y the edges.
struct PeWindow {
    /// the bound holds (both turns stay within 1 rad over the window) and
    /// Y's edges fit the arrays
    on: bool,
    /// cos, sin of X's angle now
    ca: f64,
    sa: f64,
    /// m: the bound on a gap's change, its part common to every pair
    base: f64,
    /// its part per metre of the vertex's radius
    per_rho: f64,
    /// m, and m per metre of radius: the same for the place along an edge
    abase: f64,
    aper_rho: f64,
    /// each edge's outward unit normal now
    ex: [f64; WINDOW_EDGES],
    ey: [f64; WINDOW_EDGES],
    /// m: the gap of X's centre beyond each edge's line now
    off: [f64; WINDOW_EDGES],
    /// m: the margin of each line's offset
    slack: [f64; WINDOW_EDGES],
    /// m: X's centre along each edge (its tangent (-ey, ex)) now
    along: [f64; WINDOW_EDGES],
    /// m: the edge's extent, widened by the margins
    lo: [f64; WINDOW_EDGES],
    hi: [f64; WINDOW_EDGES],
}

/// The gap g(s) = n(s) . (d(s) + r(s)) - h of a vertex (r: its offset from
/// X's centre, |r| = rho, turning at wx) from the line of an edge of Y (n:
/// its unit normal, turning at wy; d: X's centre less Y's) changes over
/// [0, win] by at most win (|wy| D + V + |wx - wy| rho), since
/// |g'| <= |wy| |d| + |d'| + |wx - wy| rho (D >= |d|, V >= |d'| over the
/// window); point_edge's polynomial is g with the sin and cos of both turns
/// replaced by their Taylor polynomials of order n >= 1, each off by at
/// most x^2/2 for a turn x <= 1 rad, so it is within (xn^2 D + xr^2 rho) of
/// g (xn = |wy| win, xr = |wx - wy| win).  When |g(0)| exceeds both plus
/// the tolerance (first_contact's contact now) and a margin of 2^-30 of
/// the sizes and of the angles' lever for every rounding, the polynomial
/// keeps the sign of g(0) all through the window: no root, no contact
/// (docs/toi.md, "Cost").  Likewise the place a(s) = t(s) . (d(s) + r(s))
/// of the vertex along the edge (t: the edge's unit tangent) changes by at
/// most win (|wy| (D + rho) + V + |wx| rho): when a(0) lies farther than
/// that beyond the edge's extent widened by the tolerance, inside
/// (evaluated on the exact motion) refuses every root of the window.
fn window_bound(verts: &[Vertex], tol: f64, x_: &Body, y_: &Body, now: f64, win: f64) -> PeWindow {
    let (x1, y1, u1, v1, ang1) = state_at(x_, now);
    let (x2, y2, u2, v2, ang2) = state_at(y_, now);
    let (dx, dy) = (x1 - x2, y1 - y2);
    let (u, v, ax, ay) = (u1 - u2, v1 - v2, x_.ax - y_.ax, x_.ay - y_.ay);
    let speed = (u * u + v * v).sqrt();
    let acc = (ax * ax + ay * ay).sqrt();
    let d = (dx * dx + dy * dy).sqrt() + (speed + 0.5 * acc * win) * win;
    let vel = speed + acc * win;
    let wy = y_.om.abs();
    let wr = (x_.om - y_.om).abs();
    let (xn, xr) = (wy * win, wr * win);
    let lever = ang1.abs() + ang2.abs() + 8.0;
    let base = win * (wy * d + vel) + xn * xn * d + tol + TWO_M30 * (1.0 + lever) * d;
    let per_rho = win * wr + xr * xr + TWO_M30 * (1.0 + lever);
    let abase = win * (wy * d + vel) + tol + TWO_M30 * (1.0 + lever) * d;
    let aper_rho = win * (wy + x_.om.abs()) + TWO_M30 * (1.0 + lever);
    let on = xn <= 1.0 && xr <= 1.0 && base <= f64::MAX && per_rho <= f64::MAX && y_.nverts() <= WINDOW_EDGES;
    let mut k = PeWindow {
        on,
        ca: 0.0,
        sa: 0.0,
        base,
        per_rho,
        abase,
        aper_rho,
        ex: [0.0; WINDOW_EDGES],
        ey: [0.0; WINDOW_EDGES],
        off: [0.0; WINDOW_EDGES],
        slack: [0.0; WINDOW_EDGES],
        along: [0.0; WINDOW_EDGES],
        lo: [0.0; WINDOW_EDGES],
        hi: [0.0; WINDOW_EDGES],
    };
    if !on {
        return k;
    }
    k.ca = ang1.cos();
    k.sa = ang1.sin();
    let (cb, sb) = (ang2.cos(), ang2.sin());
    for j in 0..y_.nverts() {
        let ed = &verts[y_.vert(j)];
        let nx = cb * ed.nx - sb * ed.ny;
        let ny = sb * ed.nx + cb * ed.ny;
        k.ex[j] = nx;
        k.ey[j] = ny;
        k.off[j] = nx * dx + ny * dy - ed.h;
        k.slack[j] = TWO_M30 * ed.h.abs();
        k.along[j] = -ny * dx + nx * dy;
        let margin = TWO_M30 * (ed.s1.abs() + ed.s2.abs());
        k.lo[j] = ed.s1 - margin;
        k.hi[j] = ed.s2 + margin;
    }
    k
}

/// The point_edge variants pe_coefficients picks for X's vertices against
/// Y's edges now: (a vertex off X's centre that turns relative to the
/// edge, the others: rho 0 after the fold).  A variant reads only which
/// effects are zero (orbit, acceleration, the two turns), never the
/// positions, phases or the line's offset.
fn pe_variants<E: Equations>(x_: &Body, y_: &Body, now: f64) -> (i32, i32) {
    let (x1, y1, u1, v1, _) = state_at(x_, now);
    let (x2, y2, u2, v2, _) = state_at(y_, now);
    let wr = x_.om - y_.om;
    let mut args = [x1 - x2, u1 - u2, x_.ax - y_.ax, y1 - y2, v1 - v2, x_.ay - y_.ay, 0.0, wr, 0.0, y_.om, 0.0, 0.0];
    let fixed = E::pe_variant(&args);
    args[6] = if wr == 0.0 { 0.0 } else { 1.0 };
    (E::pe_variant(&args), fixed)
}

/// Every vertex of A against every edge of B within [0, win] after now;
/// the pairs window_bound proves apart are counted, not solved.
fn vertices_edges<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    a_: &Body,
    b_: &Body,
    now: f64,
    win: f64,
    mut best: Option<Best>,
) -> Res<Option<Best>> {
    let k = window_bound(w.verts(), w.tol(), a_, b_, now, win);
    let (turning, fixed) = if k.on { pe_variants::<E>(a_, b_, now) } else { (-1, -1) };
    for i in 0..a_.nverts() {
        let v = &w.verts()[a_.vert(i)];
        let (mut rx, mut ry, mut lim, mut alim) = (0.0, 0.0, 0.0, 0.0);
        let spared = if v.rho == 0.0 { fixed } else { turning };
        if k.on {
            rx = k.ca * v.lx - k.sa * v.ly;
            ry = k.sa * v.lx + k.ca * v.ly;
            lim = k.base + k.per_rho * v.rho;
            alim = k.abase + k.aper_rho * v.rho;
        }
        for j in 0..b_.nverts() {
            let spare = k.on && {
                let a = k.along[j] - k.ey[j] * rx + k.ex[j] * ry;
                (k.off[j] + k.ex[j] * rx + k.ey[j] * ry).abs() > lim + k.slack[j]
                    || a < k.lo[j] - alim
                    || a > k.hi[j] + alim
            };
            if spare {
                // far from the line, or beside the edge, all through the window (window_bound):
                // counted, not solved
                let cover = w.verts()[b_.vert(j)].cover;
                if !(cover >= 0 && w.covered(cover)) {
                    if spared < 0 {
                        return Err(SimError::Msg(
                            "point_edge: the scene uses an effect the generated code leaves out".into(),
                        ));
                    }
                    q.count_pe(spared as usize);
                }
                continue;
            }
            let t = predict_pe::<E, _, _>(w, q, a_, b_, Some(v), j, now, win, i as i32, before_of(best))?;
            best = better(best, t, PE, a_.index(), b_.index(), i as i32, j as i32);
        }
    }
    Ok(best)
}

// ---- pairs --------------------------------------------------------------------

/// Schedule the first contact of A and B after now, or a horizon event
/// where the Taylor polynomials of their turns stop being good.  Cheap
/// steps chain: a later meeting of the bounds or a clear stretch moves
/// `now` on (up to CHAIN stages, at most one Taylor window: [`pair_search`],
/// the TOI library's computation).
pub fn predict_pair<E: Equations>(w: &Space, q: &mut Queue, ai: usize, bi: usize, now: f64) -> Res<()> {
    let s = &w.s;
    let a_ = &s.bodies[ai];
    let b_ = &s.bodies[bi];
    if a_.sup == b_.idx as i32 || b_.sup == a_.idx as i32 {
        // the support's edge line separates them (both convex): only leaving ends it
        return Ok(());
    }
    if (a_.asleep && grounded(b_)) || (b_.asleep && grounded(a_)) {
        // a sleeper against a sleeper or an unmoving fixed body: nothing moves
        return Ok(());
    }
    q.stats.pairs += 1;
    match pair_search::<E, _, _>(w, q, a_, b_, now, s.end, CHAIN, 1)? {
        Found::Contact(at, bb) => q.push_collision(w, at + bb.s, bb.feat, &s.bodies[bb.a], &s.bodies[bb.b], bb.i, bb.j),
        Found::Stopped(at) if at < s.end => q.push_horizon(w, at, a_, b_),
        _ => {}
    }
    Ok(())
}

/// What [`pair_search`] found.
#[derive(Clone, Copy)]
pub enum Found {
    /// no contact before the end
    None,
    /// a contact: its s after the time given, its features
    Contact(f64, Best),
    /// the steps ran out at this time (the simulator schedules a horizon there)
    Stopped(f64),
}

/// The first contact of A and B after now (docs/simulator.md, "One
/// prediction chains its cheap steps"): a later meeting of the bounds or a
/// clear stretch moves now on, a Taylor window solves the features, at most
/// `stages` steps of which at most `windows` windows.
#[allow(clippy::too_many_arguments)]
pub fn pair_search<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    a_: &Body,
    b_: &Body,
    now: f64,
    end: f64,
    stages: usize,
    windows: usize,
) -> Res<Found> {
    if !a_.polygon && !b_.polygon && a_.orbit == 0.0 && b_.orbit == 0.0 {
        // two circles that do not turn (turn_rate 0): the loop below takes
        // one stage, features' predict_cc
        let win = end - now;
        if win > 0.0 {
            if let Some(t) = circles_plain::<E, _, _>(w, q, a_, b_, now, win)? {
                return Ok(Found::Contact(now, Best { s: t, feat: CC, a: a_.index(), b: b_.index(), i: -1, j: -1 }));
            }
        }
        return Ok(Found::None);
    }
    let (ta, tb) = (turn_rate(a_), turn_rate(b_));
    // the library: a clear stretch of two turning polygons shorter than
    // STRAIGHT windows leads straight to the window at its end, without
    // another bound or clear-stretch test (the simulator: never)
    let lead = if w.library() && a_.polygon && b_.polygon && ta > 0.0 && tb > 0.0 { STRAIGHT } else { 0.0 };
    let mut straight = false;
    let mut now = now;
    let mut solved = 0;
    for _ in 0..stages {
        let mut win = end - now;
        if !(win > 0.0) {
            return Ok(Found::None);
        }
        if (a_.polygon || b_.polygon) && !straight {
            // bounds that do not turn: until they touch, nothing can
            let meet = if b_.polygon && ta > 0.0 && b_.om == 0.0 {
                bound_polygon::<E, _, _>(w, q, a_, b_, now, win)?
            } else if a_.polygon && tb > 0.0 && a_.om == 0.0 {
                bound_polygon::<E, _, _>(w, q, b_, a_, now, win)?
            } else {
                bounds_meet::<E, _, _>(w, q, a_, b_, now, win)?
            };
            match meet {
                None => return Ok(Found::None),
                Some(meet) if meet > 0.0 => {
                    now = now + meet;
                    continue;
                }
                Some(_) => {}
            }
        }
        let x = if ta > 0.0 && tb > 0.0 {
            w.alpha() / (ta + tb)
        } else if ta > 0.0 {
            a_.window / ta
        } else if tb > 0.0 {
            b_.window / tb
        } else {
            win
        };
        // Python's min(w, x)
        if x < win {
            win = x;
        }
        if (ta > 0.0 || tb > 0.0) && !straight {
            let clear = clear_time(w, a_, b_, now);
            if clear >= win {
                // apart all through the window, whatever the turns do: no
                // roots to solve until they may come within the tolerance
                now = now + clear;
                straight = clear < lead * win;
                continue;
            }
        }
        straight = false;
        if solved >= windows {
            // the simulator: one Taylor window per prediction, the next at a horizon
            break;
        }
        if let Some(bb) = features::<E, _, _>(w, q, a_, b_, now, win)? {
            return Ok(Found::Contact(now, bb));
        }
        if ta == 0.0 && tb == 0.0 {
            // nothing turns: the window was the whole run
            return Ok(Found::None);
        }
        now = now + win;
        solved += 1;
    }
    Ok(Found::Stopped(now))
}

/// The earliest contact of A's and B's features within [0, win] after now.
fn features<E: Equations, W: PairEnv, C: Counter>(
    w: &W,
    q: &mut C,
    a_: &Body,
    b_: &Body,
    now: f64,
    win: f64,
) -> Res<Option<Best>> {
    let mut best = None;
    if !a_.polygon && !b_.polygon {
        let t = predict_cc::<E, _, _>(w, q, a_, b_, None, b_.r, now, win, f64::INFINITY)?;
        if let Some(t) = t {
            best = Some(Best { s: t, feat: CC, a: a_.index(), b: b_.index(), i: -1, j: -1 });
        }
    } else if !a_.polygon {
        best = circle_polygon::<E, _, _>(w, q, a_, b_, now, win, None)?;
    } else if !b_.polygon {
        best = circle_polygon::<E, _, _>(w, q, b_, a_, now, win, None)?;
    } else {
        best = vertices_edges::<E, _, _>(w, q, a_, b_, now, win, None)?;
        best = vertices_edges::<E, _, _>(w, q, b_, a_, now, win, best)?;
    }
    Ok(best)
}

// ---- clear stretches: how long a pair surely stays apart ---------------------------

/// Python's max(a, b): the first unless the second is larger.
#[inline(always)]
fn max(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// How long A and B surely stay more than the tolerance apart, from their
/// gap g along a fixed unit axis n now (0 when not apart now): along n the
/// gap changes by (dv . n) s + (da . n) s^2/2 from the centres' relative
/// motion and closes by at most spin s from the turns (spin: each turning
/// body's bound times its turn rate), so it stays above the tolerance for s
/// below the positive root of |da . n|/2 s^2 + r s - (g - tol), r = spin -
/// dv . n (clear_root).  The axis: when one of them is a polygon P that
/// does not turn and the other, T, turns, each of P's edge normals (the
/// largest of the times); otherwise the line of the centres, and the best
/// separating axis bounded by the norms |x| + |y|.
fn clear_time<W: PairEnv>(w: &W, a_: &Body, b_: &Body, now: f64) -> f64 {
    if b_.polygon && b_.om == 0.0 && turn_rate(a_) > 0.0 {
        return clear_axes(w, a_, b_, now);
    }
    if a_.polygon && a_.om == 0.0 && turn_rate(b_) > 0.0 {
        return clear_axes(w, b_, a_, now);
    }
    if w.library() && a_.polygon && b_.polygon {
        return clear_polygons(w, a_, b_, now);
    }
    let (x1, y1, u1, v1, _) = state_at(a_, now);
    let (x2, y2, u2, v2, _) = state_at(b_, now);
    let (dx, dy) = (x2 - x1, y2 - y1);
    let d = (dx * dx + dy * dy).sqrt();
    if !(d > 0.0) {
        return 0.0;
    }
    let (nx, ny) = (dx / d, dy / d);
    // two polygons: their vertices now, once for reach and the separation
    let pts = if a_.polygon && b_.polygon {
        Some((vertices(w.verts(), a_, now), vertices(w.verts(), b_, now)))
    } else {
        None
    };
    let (hi, lo) = match &pts {
        Some((pa, pb)) => (reach_points(nx, ny, pa), -reach_points(-nx, -ny, pb)),
        None => (reach(w, a_, nx, ny, now), -reach(w, b_, -nx, -ny, now)),
    };
    let spin = a_.bound * turn_rate(a_) + b_.bound * turn_rate(b_);
    let tol = w.tol();
    let along = clear_root(
        lo - hi - tol,
        spin - (nx * (u2 - u1) + ny * (v2 - v1)),
        (nx * (b_.ax - a_.ax) + ny * (b_.ay - a_.ay)).abs(),
    );
    // and along the best separating axis, which may turn: the norms, |x| + |y|
    let sep = match &pts {
        Some((pa, pb)) => polygons_separation(w.verts(), a_, b_, now, pa, pb),
        None => separation(w.verts(), a_, b_, now),
    };
    let anyway =
        clear_root(sep - tol, spin + (u2 - u1).abs() + (v2 - v1).abs(), (b_.ax - a_.ax).abs() + (b_.ay - a_.ay).abs());
    max(along, anyway)
}

/// The vertices of polygon b whose centre is at (x, y), from the cosine c
/// and sine s of its angle: the rotation of each vertex's place (lx, ly) in
/// the body's frame (m).
fn rotated_points(verts: &[Vertex], b: &Body, x: f64, y: f64, c: f64, s: f64) -> Vec<(f64, f64)> {
    (0..b.nverts())
        .map(|k| {
            let v = &verts[b.vert(k)];
            (x + (c * v.lx - s * v.ly), y + (s * v.lx + c * v.ly))
        })
        .collect()
}

/// [`separation`] of A and B at 0; of two polygons with every vertex from
/// one cosine and sine of its body's angle ([`rotated_points`]), the TOI
/// library's own values (the simulator keeps [`separation`]'s).
pub(crate) fn library_separation(verts: &[Vertex], a_: &Body, b_: &Body) -> f64 {
    if !(a_.polygon && b_.polygon) {
        return separation(verts, a_, b_, 0.0);
    }
    let (x1, y1, _, _, g1) = state_at(a_, 0.0);
    let (x2, y2, _, _, g2) = state_at(b_, 0.0);
    let pa = rotated_points(verts, a_, x1, y1, g1.cos(), g1.sin());
    let pb = rotated_points(verts, b_, x2, y2, g2.cos(), g2.sin());
    polygons_separation(verts, a_, b_, 0.0, &pa, &pb)
}

/// The velocity of each vertex of polygon b about its centre from its turn
/// (m/s): its offset from the centre (the rotation of its place (lx, ly) by
/// the cosine c and sine s of b's angle) turned a quarter and times the
/// turn rate.
fn spin_velocities(verts: &[Vertex], b: &Body, c: f64, s: f64) -> Vec<(f64, f64)> {
    (0..b.nverts())
        .map(|k| {
            let v = &verts[b.vert(k)];
            (-(b.om * (s * v.lx + c * v.ly)), b.om * (c * v.lx - s * v.ly))
        })
        .collect()
}

/// The later of the rate bound's root (clear_root(e, lin, qa)) and the
/// Taylor bound's (clear_root(e, r, q)) of one vertex (s).
/// The larger of best and the time the other polygon Q (its centre (qx,
/// qy)) stays beyond some edge line of P (its centre (px, py), cos c and sin
/// s of its angle) by more than tol (s).  Q's vertices pts and their
/// velocities from the turn qw ([`spin_velocities`]); (du, dv) and (dax,
/// day): Q's velocity and acceleration less P's; spin: the bounds times the
/// turn rates; span: the time of one radian of the two turns together (s),
/// the reach of the turning bound.
///
/// Along the edge's outward normal o held fixed, every vertex of Q stays
/// beyond P's support until the root of the rate bound e - (spin - o . (du,
/// dv)) s - |o . (dax, day)| s^2/2 of the nearest vertex's gap e (each point
/// of a body moves along o at most its bound times its turn rate faster
/// than the centre).  Along the normal n(s) turning with P, P's support is
/// the edge's own line, and vertex k's gap g(s) = n(s) . (d(s) + r_k(s)) - h
/// (d: Q's centre less P's, r_k: the vertex about Q's centre) has, with the
/// turn rates wp and wq, the derivatives g1 = wp n_ . u + n . (dv + w_k) and
/// g2 = -wp^2 n . u + 2 wp n_ . (dv + w_k) + n . da - wq^2 n . r_k at 0 (u =
/// d + r_k, n_ the normal turned a quarter, w_k the vertex's velocity from
/// the turn); over [0, span] the third derivative is at most J = |wp|^3 D +
/// 3 wp^2 V + 3 |wp| |da| + bound_Q |wq - wp|^3 and the first at most
/// |wp| D + V + bound_Q |wq - wp| (D, V: bounds of |d| and |d'| over the span), so
/// g stays above g(0) + g1 s + (g2 - J span/3) s^2/2 until that bound's root
/// (at most span).  The axis holds until the later of the two; the turning
/// normal is taken only where it can raise the axis and best, nearest
/// vertex first, and a vertex whose first-derivative bound already lasts
/// past the time so far is not solved.
#[allow(clippy::too_many_arguments)]
fn edges_clear(
    verts: &[Vertex],
    p_: &Body,
    (px, py, c, s): (f64, f64, f64, f64),
    q_: &Body,
    (qx, qy): (f64, f64),
    pts: &[(f64, f64)],
    qw: &[(f64, f64)],
    mut best: f64,
    (spin, span): (f64, f64),
    (du, dv, dax, day): (f64, f64, f64, f64),
    tol: f64,
) -> f64 {
    let (wp, wr) = (p_.om, q_.om);
    let vel = (du * du + dv * dv).sqrt();
    let acc = (dax * dax + day * day).sqrt();
    let (cx, cy) = (qx - px, qy - py);
    let dist = (cx * cx + cy * cy).sqrt() + (vel + 0.5 * acc * span) * span;
    let vmax = vel + acc * span;
    let (aw, dw) = (wp.abs(), (wr - wp).abs());
    let jerk = (aw * aw * aw * dist + 3.0 * aw * aw * vmax + 3.0 * aw * acc + q_.bound * dw * dw * dw) * span / 3.0;
    let rate = aw * dist + vmax + q_.bound * dw;
    let turning = span > 0.0 && span <= f64::MAX && jerk <= f64::MAX && rate <= f64::MAX;
    let n = pts.len();
    let mut gaps = vec![0.0f64; n];
    for j in 0..p_.nverts() {
        let ed = &verts[p_.vert(j)];
        let ox = c * ed.nx - s * ed.ny;
        let oy = s * ed.nx + c * ed.ny;
        let off = ox * px + oy * py + ed.h;
        let mut g = f64::INFINITY;
        let mut near = 0;
        let mut all = true;
        for (k, &(x, y)) in pts.iter().enumerate() {
            let e = ox * x + oy * y - off;
            if e - tol <= 0.0 {
                all = false; // then g - tol <= 0 too: x - tol rises with x
                break;
            }
            gaps[k] = e;
            if e < g {
                g = e;
                near = k;
            }
        }
        if !all || !(g - tol > 0.0) {
            continue; // not apart along this axis: 0, never above best
        }
        let mut m = clear_root(g - tol, spin - (ox * du + oy * dv), (ox * dax + oy * day).abs());
        if turning && span > m && span > best {
            let mut mt = span;
            for i in 0..n {
                let k = if i == 0 {
                    near
                } else if i <= near {
                    i - 1
                } else {
                    i
                };
                let e = gaps[k] - tol;
                if e - mt * rate >= 0.0 {
                    continue; // its first-derivative bound alone lasts past mt
                }
                let (x, y) = pts[k];
                let (ux, uy) = (x - px, y - py);
                let (vx, vy) = (du + qw[k].0, dv + qw[k].1);
                let g1 = wp * (ox * uy - oy * ux) + (ox * vx + oy * vy);
                let g2 = -(wp * wp) * (ox * ux + oy * uy) + 2.0 * wp * (ox * vy - oy * vx) + (ox * dax + oy * day)
                    - wr * wr * (ox * (x - qx) + oy * (y - qy));
                let mut qq = jerk - g2;
                if !(qq > 0.0) {
                    qq = 0.0;
                }
                let mut t = clear_root(e, -g1, qq);
                if !(t >= 0.0) {
                    t = 0.0;
                }
                if t < mt {
                    mt = t;
                    if !(mt > m && mt > best) {
                        break;
                    }
                }
            }
            if mt > m {
                m = mt;
            }
        }
        if m > best {
            best = m;
        }
    }
    best
}

/// The library's clear_time of two polygons (the simulator keeps
/// clear_time's own, whose bits its traces pin): every vertex from one
/// cosine and sine of its body's angle ([`rotated_points`]), and the gap
/// along each edge normal of either polygon, held fixed and turning with its
/// polygon ([`edges_clear`]), as well as along the line of the centres.
/// Along a fixed axis the gap closes at most as fast as the centres'
/// relative motion along it plus each bound times its turn rate, along a
/// turning edge normal each vertex's gap stays above its Taylor polynomial
/// of order 2 less the bound of its third derivative, and the gap of the
/// best separating axis now is the separation, so this is never shorter
/// than the bound through the norms |x| + |y| and never longer than the
/// bodies stay apart.
fn clear_polygons<W: PairEnv>(w: &W, a_: &Body, b_: &Body, now: f64) -> f64 {
    let (x1, y1, u1, v1, g1) = state_at(a_, now);
    let (x2, y2, u2, v2, g2) = state_at(b_, now);
    let (dx, dy) = (x2 - x1, y2 - y1);
    let d = (dx * dx + dy * dy).sqrt();
    if !(d > 0.0) {
        return 0.0;
    }
    let (nx, ny) = (dx / d, dy / d);
    let (ca, sa, cb, sb) = (g1.cos(), g1.sin(), g2.cos(), g2.sin());
    let pa = rotated_points(w.verts(), a_, x1, y1, ca, sa);
    let pb = rotated_points(w.verts(), b_, x2, y2, cb, sb);
    let wa = spin_velocities(w.verts(), a_, ca, sa);
    let wb = spin_velocities(w.verts(), b_, cb, sb);
    let hi = reach_points(nx, ny, &pa);
    let lo = -reach_points(-nx, -ny, &pb);
    let spin = a_.bound * turn_rate(a_) + b_.bound * turn_rate(b_);
    let span = 1.0 / (a_.om.abs() + b_.om.abs());
    let tol = w.tol();
    let (du, dv, dax, day) = (u2 - u1, v2 - v1, b_.ax - a_.ax, b_.ay - a_.ay);
    let best = clear_root(lo - hi - tol, spin - (nx * du + ny * dv), (nx * dax + ny * day).abs());
    let best = edges_clear(
        w.verts(),
        a_,
        (x1, y1, ca, sa),
        b_,
        (x2, y2),
        &pb,
        &wb,
        best,
        (spin, span),
        (du, dv, dax, day),
        tol,
    );
    edges_clear(
        w.verts(),
        b_,
        (x2, y2, cb, sb),
        a_,
        (x1, y1),
        &pa,
        &wa,
        best,
        (spin, span),
        (u1 - u2, v1 - v2, a_.ax - b_.ax, a_.ay - b_.ay),
        tol,
    )
}

/// The largest projection of b on the unit axis (nx, ny) at now.
fn reach<W: PairEnv>(w: &W, b: &Body, nx: f64, ny: f64, now: f64) -> f64 {
    if !b.polygon {
        let (px, py) = point_at(b, None, now);
        return nx * px + ny * py + b.r;
    }
    let mut best = f64::NEG_INFINITY;
    for k in 0..b.nverts() {
        let (px, py) = point_at(b, Some(&w.verts()[b.vert(k)]), now);
        best = max(best, nx * px + ny * py);
    }
    best
}

/// [`reach`] of a polygon whose vertices now are pts.
fn reach_points(nx: f64, ny: f64, pts: &[(f64, f64)]) -> f64 {
    let mut best = f64::NEG_INFINITY;
    for &(px, py) in pts {
        best = max(best, nx * px + ny * py);
    }
    best
}

/// clear_time along each edge normal of P (P does not turn, T does).
fn clear_axes<W: PairEnv>(w: &W, t_: &Body, p_: &Body, now: f64) -> f64 {
    let (_, _, u1, v1, _) = state_at(t_, now);
    let (_, _, u2, v2, _) = state_at(p_, now);
    let (du, dv, dax, day) = (u1 - u2, v1 - v2, t_.ax - p_.ax, t_.ay - p_.ay);
    let spin = t_.bound * turn_rate(t_);
    let mut best = 0.0;
    for j in 0..p_.nverts() {
        let (ox, oy, off) = edge_line(w.verts(), p_, j, now);
        let c = clear_root(
            -reach(w, t_, -ox, -oy, now) - off - w.tol(),
            spin - (ox * du + oy * dv),
            (ox * dax + oy * day).abs(),
        );
        best = max(best, c);
    }
    best
}

/// The positive root of q/2 s^2 + r s - g (q >= 0), for g > 0, else 0;
/// infinity when it has none (r <= 0 and q = 0).
#[inline]
fn clear_root(g: f64, r: f64, q: f64) -> f64 {
    if !(g > 0.0) {
        return 0.0;
    }
    if r > 0.0 {
        return 2.0 * g / (r + (r * r + 2.0 * q * g).sqrt());
    }
    if q > 0.0 {
        return ((r * r + 2.0 * q * g).sqrt() - r) / q;
    }
    f64::INFINITY
}

// ---- per body -------------------------------------------------------------------

/// Predict body b against the bodies of the cells x_lo..=x_hi, y_lo..=y_hi
/// (b itself, `skip` and fixed pairs left out).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn predict_cells<E: Equations>(
    w: &Space,
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
    let (y0, y1, x0, x1) = (y_lo.max(0), y_hi.min(s.ny - 1), x_lo.max(0), x_hi.min(s.nx - 1));
    let mut found = [0u32; GATHER];
    let Some(n) = w.grid.gather(x0, x1, y0, y1, &mut found) else {
        // more bodies than room (small bodies in large cells): cell by cell
        for jy in y0..=y1 {
            for jx in x0..=x1 {
                let cell = w.grid.cell(jx, jy);
                for k in 0..cell.len() {
                    predict_one::<E>(w, q, b, fixed, cell.get(k) as usize, now, skip, only_after)?;
                }
            }
        }
        return Ok(());
    };
    // first have every partner's two lines and its stamp (which scheduling
    // a contact with it reads) fetched: at 10^5 bodies they are rarely in
    // the cache, and so their misses overlap instead of each waiting for
    // the pair before it (a hint only, nothing is read); b, skip and, with
    // only_after, the bodies up to b are left out by the count, not by a
    // branch (the list kept in place, in order: a candidate moves only to
    // an earlier slot).  n <= GATHER (gather's room) and nc <= k: the
    // `min`s and the mask only let the compiler drop the bounds checks.
    let (bodies, stamps) = (s.bodies.as_ptr(), w.stamps.as_ptr());
    let skip_o = skip.map_or(u32::MAX, |k| k as u32);
    let (b_o, after) = (b as u32, if only_after { b as u32 } else { 0 });
    let mut nc = 0;
    for k in 0..n.min(GATHER) {
        let o = found[k];
        let p = bodies.wrapping_add(o as usize).cast::<u8>();
        prefetch(p);
        prefetch(p.wrapping_add(64));
        prefetch(stamps.wrapping_add(o as usize));
        found[nc & (GATHER - 1)] = o;
        nc += usize::from((o != b_o) & (o != skip_o) & (!only_after | (o > after)));
    }
    for &o in &found[..nc.min(GATHER)] {
        if !(fixed && s.bodies[o as usize].fixed) {
            predict_pair::<E>(w, q, b, o as usize, now)?;
        }
    }
    Ok(())
}

/// Room for the bodies of a 3x3 block of cells (cells are 1.15 times the
/// largest movable body wide, docs/simulator.md "Broad phase": the block
/// is 3.45 diameters square, and equal disks, their centres in it at least
/// a diameter apart, number about 23 at the densest packing;
/// [`predict_cells`] walks the cells again when they do not fit).
const GATHER: usize = 32;
const _: () = assert!(GATHER.is_power_of_two(), "predict_cells masks with GATHER - 1");

/// predict_cells' step for a body o of the cells.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn predict_one<E: Equations>(
    w: &Space,
    q: &mut Queue,
    b: usize,
    fixed: bool,
    o: usize,
    now: f64,
    skip: Option<usize>,
    only_after: bool,
) -> Res<()> {
    if o == b || Some(o) == skip || (only_after && o <= b) {
        return Ok(());
    }
    if !(fixed && w.s.bodies[o].fixed) {
        predict_pair::<E>(w, q, b, o, now)?;
    }
    Ok(())
}

pub fn predict_body<E: Equations>(w: &Space, q: &mut Queue, b: usize, now: f64, skip: Option<usize>) -> Res<()> {
    let body = &w.s.bodies[b];
    let (cx, cy) = (i64::from(body.cx), i64::from(body.cy));
    predict_cells::<E>(w, q, b, cx - 1, cx + 1, cy - 1, cy + 1, now, skip, false)?;
    for o in w.grid.large_near(b, body.cx, body.cy) {
        let o = o as usize;
        if Some(o) != skip && !(body.fixed && w.s.bodies[o].fixed) {
            predict_pair::<E>(w, q, b, o, now)?;
        }
    }
    schedule_cell(w, q, b, now);
    if body.sup >= 0 && (w.s.bodies[body.sup as usize].fixed || w.s.bodies[body.sup as usize].asleep) {
        // a carried body moves with its base: no stop, no leave of its own
        schedule_support(w, q, b);
    }
    Ok(())
}

/// predict_pair of body b against every body near that `keep` lets
/// through, then b's next cell crossing: the bodies listed in its 3x3
/// cells but b itself and (for a fixed b) the fixed ones, then the large
/// bodies near (`large_near`, b not among them; the fixed test is then
/// `keep`'s to make, as the reference's callers differ there).  The walk
/// of predict_woken (handlers.rs) and predict_apart (cluster.rs), which
/// differ only in `keep`.
#[inline]
pub fn predict_near<E: Equations>(
    w: &Space,
    q: &mut Queue,
    b: usize,
    now: f64,
    mut keep: impl FnMut(usize) -> bool,
) -> Res<()> {
    let s = &w.s;
    let body = &s.bodies[b];
    let (cx, cy, fixed) = (i64::from(body.cx), i64::from(body.cy), body.fixed);
    for jy in (cy - 1).max(0)..=(cy + 1).min(s.ny - 1) {
        for jx in (cx - 1).max(0)..=(cx + 1).min(s.nx - 1) {
            let cell = w.grid.cell(jx, jy);
            for k in 0..cell.len() {
                let o = cell.get(k) as usize;
                if o != b && !(fixed && s.bodies[o].fixed) && keep(o) {
                    predict_pair::<E>(w, q, b, o, now)?;
                }
            }
        }
    }
    for o in w.grid.large_near(b, body.cx, body.cy) {
        let o = o as usize;
        if keep(o) {
            predict_pair::<E>(w, q, b, o, now)?;
        }
    }
    schedule_cell(w, q, b, now);
    Ok(())
}

pub fn schedule_cell(w: &Space, q: &mut Queue, bi: usize, now: f64) {
    let s = &w.s;
    let b = &s.bodies[bi];
    if b.large || (b.vx == 0.0 && b.vy == 0.0 && b.ax == 0.0 && b.ay == 0.0) {
        return;
    }
    let ulo = now - b.tb;
    let uhi = s.end - b.tb;
    // the margin, or what the cell leaves a body added live that is wider
    // than the scene's widest (it must stay within half a cell of its cell)
    let room = s.half_cell - b.bound;
    let h = if room < s.margin { room } else { s.margin };
    let mut best: Option<(f64, i32, i32)> = None;
    for axis in 0..2 {
        let (p, v, a, i, n, origin, size) = if axis == 0 {
            (b.px, b.vx, b.ax, i64::from(b.cx), s.nx, s.x0, s.cw)
        } else {
            (b.py, b.vy, b.ay, i64::from(b.cy), s.ny, s.y0, s.ch)
        };
        if a != 0.0 {
            cross_accelerated(&mut best, axis, [p, v, a], i, n, origin, size, h, ulo, uhi);
            continue;
        }
        // no acceleration: only the boundary ahead in v's direction can be
        // crossed (v + a u = v), once; the other direction is skipped as
        // cross_accelerated's test `v dir > 0` would skip it
        let direction = if v > 0.0 {
            1
        } else if v < 0.0 {
            -1
        } else {
            continue;
        };
        let Some(bound) = cell_bound(i, n, origin, size, h, direction) else {
            continue;
        };
        let c0 = p - bound;
        if ulo == 0.0 && c0 * f64::from(direction) >= 0.0 {
            // on the boundary now, or past it, and moving across it: at once
            // (cross_accelerated says why)
            if best.is_none_or(|bb| 0.0 < bb.0) {
                best = Some((0.0, axis, direction));
            }
            continue;
        }
        // one root, the root finder's degree-1 answer (one division, the
        // same bits as smallest_root of [c0, v, 0], whose c[2] is zero)
        // without the call
        let u = -c0 / v;
        if ulo.is_finite() && uhi.is_finite() && c0.is_finite() && v.is_finite() && ulo < u && u <= uhi {
            let u = u + 0.0;
            if best.is_none_or(|bb| u < bb.0) {
                best = Some((u, axis, direction));
            }
        }
    }
    if let Some((u, axis, direction)) = best {
        q.push_cell(w, b.tb + u, b, axis, direction);
    }
}

/// The line, a margin h past a boundary of cell i (of n, from origin, each size wide), that a body
/// moving in `direction` (+1 or -1) crosses to change cell; None at the grid's edge.
#[inline(always)]
fn cell_bound(i: i64, n: i64, origin: f64, size: f64, h: f64, direction: i32) -> Option<f64> {
    if direction == 1 {
        if i >= n - 1 {
            return None;
        }
        Some(origin + (i + 1) as f64 * size + h)
    } else {
        if i <= 0 {
            return None;
        }
        Some(origin + i as f64 * size - h)
    }
}

/// schedule_cell along one axis of an accelerated body (pva: its position,
/// speed and acceleration along the axis, a != 0): the earliest crossing
/// of either boundary of cell i into `best` if earlier than what is there.
/// Out of line: a gas has no acceleration, and this path's set-up of the
/// root finder then cost every call.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
fn cross_accelerated(
    best: &mut Option<(f64, i32, i32)>,
    axis: i32,
    pva: [f64; 3],
    i: i64,
    n: i64,
    origin: f64,
    size: f64,
    h: f64,
    ulo: f64,
    uhi: f64,
) {
    let [p, v, a] = pva;
    for direction in [1i32, -1] {
        let Some(bound) = cell_bound(i, n, origin, size, h, direction) else {
            continue;
        };
        let c = [p - bound, v, 0.5 * a];
        let dir = f64::from(direction);
        if ulo == 0.0 && c[0] * dir >= 0.0 && (v * dir > 0.0 || (v == 0.0 && a * dir > 0.0)) {
            // on the boundary now, or past it (cell_of's quotient and the
            // boundary's sum origin + i size can round apart), and moving
            // or accelerating across it: cross at once (the root finder
            // reports no root at the interval's start, and none at all
            // for a boundary already behind)
            if best.is_none_or(|bb| 0.0 < bb.0) {
                *best = Some((0.0, axis, direction));
            }
            continue;
        }
        let mut lo = ulo;
        for _ in 0..3 {
            let Some(u) = smallest_root(&c, lo, uhi) else {
                break;
            };
            if (v + a * u) * dir > 0.0 {
                if best.is_none_or(|bb| u < bb.0) {
                    *best = Some((u, axis, direction));
                }
                break;
            }
            lo = u;
        }
    }
}
