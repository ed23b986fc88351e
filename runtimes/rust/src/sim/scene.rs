//! The compiled scene: the flat text of docs/simulator.md, read as
//! `Scene` in runtimes/python/max2code_rt/sim/ reads it.  Numbers are
//! shortest round-trip decimals; Rust's parser reads them exactly.

use super::g17::g17;
use std::cell::Cell;

/// One vertex of a polygon and the edge that starts at it (to the next
/// vertex), in the body's frame: all precomputed by the scene compiler.
#[derive(Clone, Debug)]
pub struct Vertex {
    /// m: the vertex about the centre of mass
    pub lx: f64,
    pub ly: f64,
    /// m, rad: its polar form
    pub rho: f64,
    pub beta: f64,
    /// rad: angle of the edge's outward normal
    pub psi: f64,
    /// m: offset of the edge's line, n . v
    pub h: f64,
    /// m: the edge's extent along its tangent (-ny, nx)
    pub s1: f64,
    pub s2: f64,
    /// the edge's outward unit normal (cos psi, sin psi, but exact where
    /// the compiler's quotient is: (0, 1) for a level top face)
    pub nx: f64,
    pub ny: f64,
    /// the fixed body that covers the edge (no body can touch it while that
    /// one is there), -1: none
    pub cover: i64,
    /// cos and sin of the vertex's angle (body angle + beta) and of its
    /// edge's normal (body angle + psi), for the last argument asked
    pub at: CosSin,
    pub normal: CosSin,
}

/// cos and sin of the last argument asked, kept: a fixed polygon asks the
/// same angles again and again.  The same argument gives the same libm
/// answer, so the cache changes no bit.
#[derive(Clone, Debug)]
pub struct CosSin(Cell<(u64, f64, f64)>);

impl CosSin {
    pub(crate) fn new() -> CosSin {
        CosSin(Cell::new((f64::NAN.to_bits(), f64::NAN, f64::NAN)))
    }

    /// (cos x, sin x).
    #[inline(always)]
    pub fn of(&self, x: f64) -> (f64, f64) {
        let (bits, c, s) = self.0.get();
        if bits == x.to_bits() {
            return (c, s);
        }
        let (c, s) = (x.cos(), x.sin());
        self.0.set((x.to_bits(), c, s));
        (c, s)
    }
}

/// A body's state at its own last update time `tb`, and its constants.
/// Units: s, m, m/s, m/s^2, rad, rad/s, kg.  Laid out by use: the first
/// cache line holds all that a pair of circles that do not orbit needs
/// (motion at tb, radius), the second the rest of what every pair
/// prediction and cell crossing reads (angle, orbit, index, cell,
/// support, the flags, how many it carries), the third the rest of what
/// a collision's handler reads; polygons, support and sleep read the
/// others.  At 10^5 bodies the records do not fit the cache, and a pair
/// prediction reads at most two lines of each partner (docs/throughput.md).
/// (Its stamp, bumped when the motion changes, is in `Space::stamps`.)
#[derive(Clone, Debug)]
#[repr(C, align(64))]
pub struct Body {
    // line 0: motion at tb, radius
    /// m: centre (of rotation) at tb
    pub px: f64,
    pub py: f64,
    /// m/s: velocity at tb
    pub vx: f64,
    pub vy: f64,
    /// m/s^2: acceleration now (gravity included; while supported, only
    /// its part along the support's edge, less friction)
    pub ax: f64,
    pub ay: f64,
    /// s: the time of this state
    pub tb: f64,
    /// m: circle radius (0 for polygons)
    pub r: f64,
    // line 1: turning, index, cell, support, flags
    /// rad: angle at tb
    pub ang: f64,
    /// rad/s: angular velocity
    pub om: f64,
    /// m, rad: orbit radius and phase (circles)
    pub orbit: f64,
    pub ophase: f64,
    /// index in the scene
    pub idx: u32,
    /// index of the body supporting it (fixed), or carrying it (movable),
    /// -1: free
    pub sup: i32,
    /// grid cell (small bodies)
    pub cx: i32,
    pub cy: i32,
    pub polygon: bool,
    pub fixed: bool,
    /// not in the grid: in the large list every body checks
    pub large: bool,
    /// frozen in a sleeping island (v = a = w = 0, no events of its own)
    pub asleep: bool,
    /// removed from the world (remove_body, input MODE 4): frozen, out of the grid
    pub gone: bool,
    /// the supporting edge (index into sup's vertices), -1: free
    pub sup_edge: i32,
    /// how many bodies it carries (their sup is this movable body): read
    /// by every collision's handler with an impulse (`release`), so here in
    /// line 1 (in line 4 it would cost a cache miss per body and collision
    /// at 10^5 disks)
    pub carry: i32,
    // line 2: what a collision's handler reads besides (contact impulse,
    // support and sleep tests)
    /// 1/kg, 1/(kg m^2); 0 for fixed bodies
    pub inv_m: f64,
    pub inv_i: f64,
    /// restitution, 0..1
    pub e: f64,
    /// friction coefficient (Coulomb), >= 0
    pub mu: f64,
    /// m/s^2: free acceleration (gravity and the body's own), from the scene
    pub fax: f64,
    pub fay: f64,
    /// m: radius of the bounding circle about the centre
    pub bound: f64,
    /// rad: its window angle when it turns and its partner does not (0: it never turns)
    pub window: f64,
    // the other lines: polygons, support, sleep
    /// the body's vertices are `Scene::verts[v0 .. v0 + nv]`
    pub v0: u32,
    pub nv: u32,
    /// unit tangent of the supporting edge (along increasing S1..S2)
    pub tx: f64,
    pub ty: f64,
    /// m/s^2: free acceleration pressing onto the support, > 0
    pub load: f64,
    /// m/s^2: free acceleration along the tangent
    pub at: f64,
    /// the island's number (the index of its first sleeper), -1: awake
    /// (32 bits, as body indices: the record is then 4 lines, 256 bytes)
    pub island: i32,
    /// a large body placed in the grid: the cells its box covers (x_lo,
    /// x_hi, y_lo, y_hi), else None (in the grid's `large` list)
    pub wcells: Option<[i32; 4]>,
}

/// The layout above: motion and radius in the first line, what every
/// prediction reads in the first two.
const _: () = {
    assert!(std::mem::offset_of!(Body, r) + 8 <= 64);
    assert!(std::mem::offset_of!(Body, sup_edge) + 4 <= 128);
    assert!(std::mem::offset_of!(Body, carry) + 4 <= 128);
    assert!(std::mem::offset_of!(Body, gone) < 128);
    assert!(std::mem::offset_of!(Body, inv_m) == 128 && std::mem::offset_of!(Body, window) + 8 <= 192);
    assert!(std::mem::size_of::<Body>() == 256);
};

impl Body {
    /// Index of the body in the scene.
    #[inline(always)]
    pub fn index(&self) -> usize {
        self.idx as usize
    }

    /// Index in `Scene::verts` of vertex k (and the edge from it).
    #[inline(always)]
    pub fn vert(&self, k: usize) -> usize {
        self.v0 as usize + k
    }

    /// Number of vertices.
    #[inline(always)]
    pub fn nverts(&self) -> usize {
        self.nv as usize
    }
}

/// The limits of a flat text (docs/simulator.md, "Flat scene checks"), the
/// same names and values in every runtime: bodies in a scene, vertices of a
/// polygon, inputs in a scene.
pub const MAX_BODIES: i64 = 1_000_000;
pub const MAX_VERTICES: i64 = 1024;
pub const MAX_INPUTS: i64 = 10_000_000;
/// m: the largest length (and coordinate) a flat text may give, and the
/// smallest tolerance or grid cell
pub const LENGTH_MAX: f64 = 1e150;
pub const LENGTH_MIN: f64 = 1e-150;
/// bytes: the longest flat text
pub const MAX_TEXT: usize = 1 << 30;
/// characters of a number's word, digits of an integer's
const MAX_NUMBER_CHARS: usize = 64;
const MAX_INTEGER_DIGITS: usize = 18;

/// A word as a message shows it: its first 32 characters, then `...` when
/// it is longer.
pub(super) fn shown(w: &str) -> String {
    match w.char_indices().nth(32) {
        Some((at, _)) => format!("{}...", &w[..at]),
        None => w.to_string(),
    }
}

/// The text as a whole: at most MAX_TEXT bytes, each printable ASCII or
/// whitespace (space, tab, newline, carriage return); `what` names it in
/// the message ("scene", "add_body").
pub fn check_text(text: &[u8], what: &str) -> Result<(), String> {
    if text.len() > MAX_TEXT {
        return Err(format!("{what}: longer than {MAX_TEXT} bytes"));
    }
    match text.iter().position(|&c| !(c.is_ascii_graphic() || matches!(c, b' ' | b'\t' | b'\n' | b'\r'))) {
        Some(n) => Err(format!("{what}: byte {n}: not printable ASCII")),
        None => Ok(()),
    }
}

/// `w` is a number's word: `[+-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+-]?[0-9]+)?`,
/// at most MAX_NUMBER_CHARS characters (no `inf`, `nan`, hex, `_`).
fn is_number_word(w: &[u8]) -> bool {
    let n = w.len();
    let digits = |mut p: usize| {
        while p < n && w[p].is_ascii_digit() {
            p += 1;
        }
        p
    };
    if n > MAX_NUMBER_CHARS {
        return false;
    }
    let mut p = usize::from(n > 0 && (w[0] == b'+' || w[0] == b'-'));
    let q = digits(p);
    let mut any = q > p;
    p = q;
    if p < n && w[p] == b'.' {
        let q = digits(p + 1);
        any |= q > p + 1;
        p = q;
    }
    if !any {
        return false;
    }
    if p < n && (w[p] == b'e' || w[p] == b'E') {
        p += 1;
        if p < n && (w[p] == b'+' || w[p] == b'-') {
            p += 1;
        }
        let q = digits(p);
        if q == p {
            return false;
        }
        p = q;
    }
    p == n
}

/// Input modes (the flat scene's MODE).
pub const SET_VELOCITY: i64 = 0;
pub const ADD_VELOCITY: i64 = 1;
pub const IMPULSE: i64 = 2;
pub const TELEPORT: i64 = 3;
pub const REMOVE: i64 = 4;

/// An input of this mode may act on b: any on a movable body; on a fixed
/// one, removal, or set_velocity when it is a polygon that does not turn
/// (its edges then translate: docs/simulator.md, Contact model).
pub fn drivable(b: &Body, mode: i64) -> bool {
    if !b.fixed || mode == REMOVE {
        return true;
    }
    mode == SET_VELOCITY && b.polygon && b.om == 0.0
}

/// A scripted or live input.
#[derive(Clone, Copy, Debug)]
pub struct Input {
    /// s
    pub t: f64,
    /// index in the scene
    pub body: i64,
    /// SET_VELOCITY, ADD_VELOCITY (vx, vy in m/s), IMPULSE (vx, vy: the
    /// impulse, N s, through the centre), TELEPORT (vx, vy: the new centre,
    /// m), REMOVE (vx, vy unused, 0)
    pub mode: i64,
    pub vx: f64,
    pub vy: f64,
}

#[derive(Clone, Debug)]
pub struct Scene {
    pub end: f64,
    pub frame_dt: f64,
    pub tol: f64,
    pub rest_speed: f64,
    pub alpha: f64,
    pub max_same: i64,
    /// events handled in a run (every kind but stale ones)
    pub max_events: i64,
    pub x0: f64,
    pub y0: f64,
    pub cw: f64,
    pub ch: f64,
    pub nx: i64,
    pub ny: i64,
    /// m: a moving centre changes cell this far past the cell's edge
    pub margin: f64,
    /// m: half of min(cw, ch)
    pub half_cell: f64,
    pub bodies: Vec<Body>,
    /// all polygons' vertices, body after body
    pub verts: Vec<Vertex>,
    pub inputs: Vec<Input>,
}

/// The whitespace-separated words of a flat text, read in order; `what`
/// names the text in messages ("scene", "add_body").
/// The decimal at the start of `w` ([-]digits[.digits][e[+-]digits], at
/// most 19 significant digits, read as far as that grammar goes) as the
/// nearest double, ties to even, as `parse` reads it, and where it stops
/// (the caller checks that a space or the end follows); None when it has
/// no digits, more than 19 significant ones, an exponent mark without
/// digits or with more than 4, or is not in the range below (`parse` then
/// reads the word).  With m the digits as an integer and x = m 10^q:
/// when m < 2^53 and |q| <= 22, x is one correctly rounded product or
/// quotient of two exact doubles; when -22 <= q < 0, the 53-bit quotient
/// floor(m 2^s / 10^-q) and its remainder are exact in 128 bits and give
/// the rounding.  The scene's numbers are shortest round-trip decimals (up
/// to 17 digits): nearly all take one of the two paths.  The C runtime's
/// m2c_sim_parse_number, step for step, and like it in one pass (the
/// number's end found by its grammar, not by finding the word's end first
/// and reading the word again: read twice, the numbers would be half of
/// the start's instructions at 10^5 disks).
#[inline(always)]
fn parse_decimal_prefix(w: &[u8]) -> Option<(f64, usize)> {
    const P10: [f64; 23] = [
        1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19,
        1e20, 1e21, 1e22,
    ];
    let n = w.len();
    let mut p = 0;
    let neg = n > 0 && w[0] == b'-';
    if neg {
        p = 1;
    }
    let first = p;
    // leading zeros, then the whole part's digits, then the fraction's (its
    // zeros before any other digit only move the point)
    while p < n && w[p] == b'0' {
        p += 1;
    }
    let sig = p;
    let mut m: u64 = 0;
    while p < n && w[p].is_ascii_digit() {
        m = m.wrapping_mul(10).wrapping_add(u64::from(w[p] - b'0'));
        p += 1;
    }
    let (mut digits, mut nsig) = (p - first, p - sig);
    let mut q: i32 = 0;
    if p < n && w[p] == b'.' {
        p += 1;
        let f = p;
        if m == 0 {
            while p < n && w[p] == b'0' {
                p += 1;
            }
            q -= (p - f) as i32;
        }
        let g = p;
        while p < n && w[p].is_ascii_digit() {
            m = m.wrapping_mul(10).wrapping_add(u64::from(w[p] - b'0'));
            p += 1;
        }
        q -= (p - g) as i32;
        digits += p - f;
        nsig += p - g;
    }
    if digits == 0 || nsig > 19 {
        return None; // no digits, or m may have wrapped
    }
    if p < n && (w[p] == b'e' || w[p] == b'E') {
        p += 1;
        let mut eneg = false;
        if p < n && (w[p] == b'+' || w[p] == b'-') {
            eneg = w[p] == b'-';
            p += 1;
        }
        let (mut ed, mut e) = (0, 0i32);
        while p < n && w[p].is_ascii_digit() {
            ed += 1;
            if ed > 4 {
                return None;
            }
            e = 10 * e + i32::from(w[p] - b'0');
            p += 1;
        }
        if ed == 0 {
            return None;
        }
        q += if eneg { -e } else { e };
    }
    let x = if m == 0 {
        0.0
    } else if m < (1u64 << 53) && (-22..=22).contains(&q) {
        if q >= 0 {
            m as f64 * P10[q as usize]
        } else {
            m as f64 / P10[(-q) as usize]
        }
    } else if (-22..0).contains(&q) {
        let pw = 10u128.pow((-q) as u32);
        let bits_w = 64 - m.leading_zeros() as i32;
        let bits_p = 128 - pw.leading_zeros() as i32;
        let mut sh = 53 + bits_p - bits_w; // m 2^sh / 10^-q in (2^52, 2^54)
        if sh < 1 {
            return None; // m >= 2^57 with a small 10^-q
        }
        let mut num = u128::from(m) << sh;
        let mut mq = num / pw;
        if mq >> 53 != 0 {
            sh -= 1;
            num >>= 1; // exact: num had sh >= 1 zero bits at the bottom
            mq = num / pw;
        }
        let rem = num - mq * pw;
        let mut mant = mq as u64;
        if 2 * rem > pw || (2 * rem == pw && mant & 1 == 1) {
            mant += 1;
        }
        if mant >> 53 != 0 {
            mant >>= 1; // rounded up to 2^53
            sh -= 1;
        }
        // mant 2^-sh, with 2^-sh a normal double (sh <= 128)
        mant as f64 * f64::from_bits(((1023 - sh) as u64) << 52)
    } else {
        return None;
    };
    Some((if neg { -x } else { x }, p))
}

/// The words of `text` separated by ASCII whitespace (what
/// `str::split_ascii_whitespace` splits on), read from the start.
pub struct Tokens<'a> {
    text: &'a str,
    /// where the next word (or the whitespace before it) starts
    pos: usize,
    what: &'static str,
}

impl<'a> Tokens<'a> {
    pub fn new(text: &'a str, what: &'static str) -> Tokens<'a> {
        Tokens { text, pos: 0, what }
    }

    #[inline(always)]
    fn skip_space(&mut self) {
        let b = self.text.as_bytes();
        while self.pos < b.len() && b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
    }

    /// The next word, None at the end.
    #[inline]
    fn word(&mut self) -> Option<&'a str> {
        self.skip_space();
        let b = self.text.as_bytes();
        let start = self.pos;
        while self.pos < b.len() && !b[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        // ASCII bytes bound the word: char boundaries of the text
        (self.pos > start).then(|| &self.text[start..self.pos])
    }

    fn next_word(&mut self, expect: Option<&str>) -> Result<&'a str, String> {
        self.word().ok_or_else(|| match expect {
            Some(w) => format!("{}: ends early (expected '{w}')", self.what),
            None => format!("{}: ends early", self.what),
        })
    }

    fn expect(&mut self, w: &str) -> Result<(), String> {
        let got = self.next_word(Some(w))?;
        if got != w {
            return Err(format!("{}: expected '{w}', found '{}'", self.what, shown(got)));
        }
        Ok(())
    }

    /// Bytes not read yet (a bound on how many lines can follow).
    fn remaining(&self) -> usize {
        self.text.len() - self.pos
    }

    fn num(&mut self) -> Result<f64, String> {
        self.skip_space();
        let b = &self.text.as_bytes()[self.pos..];
        if let Some((x, p)) = parse_decimal_prefix(b) {
            // the grammar's words are a subset of a number's; finite
            if p <= MAX_NUMBER_CHARS && (p == b.len() || b[p].is_ascii_whitespace()) {
                self.pos += p;
                return Ok(x);
            }
        }
        // not a decimal that parse_decimal reads (nor is the whole word,
        // which starts as the number did and goes on): `parse` reads it
        // when it is a number's word (`parse` also takes inf, nan, infinity)
        let w = self.next_word(None)?;
        let bad = || format!("{}: expected a number, found '{}'", self.what, shown(w));
        if !is_number_word(w.as_bytes()) {
            return Err(bad());
        }
        let x = w.parse::<f64>().map_err(|_| bad())?;
        if !x.is_finite() {
            return Err(format!("{}: number '{}' is beyond a double's range", self.what, shown(w)));
        }
        Ok(x)
    }

    /// An integer's word: `-?[0-9]{1,18}`.
    fn int(&mut self) -> Result<i64, String> {
        let w = self.next_word(None)?;
        let bad = || format!("{}: expected an integer, found '{}'", self.what, shown(w));
        let d = w.strip_prefix('-').unwrap_or(w);
        if d.is_empty() || d.len() > MAX_INTEGER_DIGITS || !d.bytes().all(|c| c.is_ascii_digit()) {
            return Err(bad());
        }
        w.parse::<i64>().map_err(|_| bad())
    }

    /// The next word, if any (a text that should have ended).
    pub fn rest(&mut self) -> Option<&'a str> {
        self.word()
    }
}

/// What a body's checks compare with: the scene's end time (s) and
/// tolerance (m), and how many bodies there are (a cover names one of them).
#[derive(Clone, Copy, Debug)]
pub struct BodyLimits {
    pub end: f64,
    pub tol: f64,
    pub bodies: i64,
}

/// A `body ...` line and its `v` lines (docs/simulator.md, Flat scene):
/// body number `idx`, its vertices appended to `verts`, each field checked
/// ("Flat scene checks"): the body line once read whole, each `v` line once
/// read, the polygon once its last `v` line is.
pub fn read_body(tk: &mut Tokens, idx: u32, verts: &mut Vec<Vertex>, lim: &BodyLimits) -> Result<Body, String> {
    tk.expect("body")?;
    let poly = tk.int()?;
    let fixed = tk.int()?;
    let (inv_m, inv_i, e, mu) = (tk.num()?, tk.num()?, tk.num()?, tk.num()?);
    let (px, py, vx, vy, ax, ay) = (tk.num()?, tk.num()?, tk.num()?, tk.num()?, tk.num()?, tk.num()?);
    let (ang, om) = (tk.num()?, tk.num()?);
    let (r, orbit, ophase, bound, window) = (tk.num()?, tk.num()?, tk.num()?, tk.num()?, tk.num()?);
    let large = tk.int()?;
    let nverts = tk.int()?;
    let what = tk.what;
    let fail = |m: String| Err(format!("{what}: body {idx}: {m}"));
    for (name, x) in [("poly", poly), ("fixed", fixed), ("large", large)] {
        if x != 0 && x != 1 {
            return fail(format!("{name} must be 0 or 1"));
        }
    }
    let (polygon, fixed, large) = (poly == 1, fixed == 1, large == 1);
    if fixed {
        if !(inv_m == 0.0 && inv_i == 0.0) {
            return fail("a fixed body has inverse mass 0".to_string());
        }
    } else if !(inv_m > 0.0) {
        return fail(format!("inverse mass {} must be positive", g17(inv_m)));
    } else if polygon && !(inv_i > 0.0) {
        return fail(format!("inverse inertia {} must be positive", g17(inv_i)));
    } else if !polygon && inv_i != 0.0 {
        return fail("a circle has inverse inertia 0".to_string());
    }
    if !((0.0..=1.0).contains(&e)) {
        return fail(format!("restitution {} outside [0, 1]", g17(e)));
    }
    if !(mu >= 0.0) {
        return fail(format!("friction {} is negative", g17(mu)));
    }
    let tol = lim.tol;
    if !polygon {
        if !(tol <= r && r <= LENGTH_MAX) {
            return fail(format!("radius {} outside [tolerance, 1e150]", g17(r)));
        }
        if nverts != 0 {
            return fail("a circle has no vertices".to_string());
        }
        if orbit != 0.0 {
            if !(tol <= orbit && orbit <= LENGTH_MAX) {
                return fail(format!("orbit radius {} outside [tolerance, 1e150]", g17(orbit)));
            }
            if !fixed {
                return fail("an orbiting circle must be fixed".to_string());
            }
        }
        if om != 0.0 && !(orbit > 0.0) {
            return fail("a circle turns only about an orbit".to_string());
        }
    } else {
        if r != 0.0 || orbit != 0.0 {
            return fail("a polygon has no radius or orbit".to_string());
        }
        if !(3..=MAX_VERTICES).contains(&nverts) {
            return fail(format!("{nverts} vertices (3 to {MAX_VERTICES})"));
        }
    }
    if !((0.0..=0.5).contains(&window)) {
        return fail(format!("window {} outside [0, 0.5]", g17(window)));
    }
    // a polygon's radius and orbit are 0 here: its bound is at least 0
    if !(bound >= r + orbit && bound <= LENGTH_MAX) {
        return fail(format!("bound {} is too small or too large", g17(bound)));
    }
    let t = lim.end;
    // left to right, as every runtime computes it
    let reach = (px.abs() + py.abs()) + (vx.abs() + vy.abs()) * t + (ax.abs() + ay.abs()) * t * t / 2.0 + bound;
    if !(reach <= 2.0 * LENGTH_MAX) {
        return fail("reaches more than 2e150 m from the origin by the end".to_string());
    }
    // nverts is 0 or in 3..=MAX_VERTICES
    let nv = nverts as u32;
    let v0 = verts.len() as u32;
    for j in 0..nv {
        tk.expect("v")?;
        let mut v = [0.0f64; 10];
        for x in v.iter_mut() {
            *x = tk.num()?;
        }
        let cover = tk.int()?;
        let fail = |m: String| Err(format!("{what}: body {idx} vertex {j}: {m}"));
        // lx, ly and rho (the vertex), h, s1 and s2 (its edge's line and extent: each at most a vertex's
        // distance, twice the bound leaving room for their rounding)
        if !(v[0].abs() <= bound
            && v[1].abs() <= bound
            && 0.0 <= v[2]
            && v[2] <= bound
            && v[5].abs() <= 2.0 * bound
            && v[6].abs() <= 2.0 * bound
            && v[7].abs() <= 2.0 * bound)
        {
            return fail("outside the bound".to_string());
        }
        if !((v[8] * v[8] + v[9] * v[9] - 1.0).abs() <= 1e-9) {
            return fail("the normal is not a unit vector".to_string());
        }
        if !(cover == -1 || (0 <= cover && cover < lim.bodies && cover != i64::from(idx))) {
            return fail(format!("cover {cover} is not a body"));
        }
        verts.push(Vertex {
            lx: v[0],
            ly: v[1],
            rho: v[2],
            beta: v[3],
            psi: v[4],
            h: v[5],
            s1: v[6],
            s2: v[7],
            nx: v[8],
            ny: v[9],
            cover,
            at: CosSin::new(),
            normal: CosSin::new(),
        });
    }
    if polygon {
        check_polygon(&verts[v0 as usize..], tol).map_err(|m| format!("{what}: body {idx}{m}"))?;
    }
    Ok(Body {
        idx,
        polygon,
        fixed,
        large,
        inv_m,
        inv_i,
        e,
        mu,
        fax: ax,
        fay: ay,
        sup: -1,
        sup_edge: -1,
        carry: 0,
        tx: 0.0,
        ty: 0.0,
        load: 0.0,
        at: 0.0,
        px,
        py,
        vx,
        vy,
        ax,
        ay,
        ang,
        om,
        tb: 0.0,
        r,
        orbit,
        ophase,
        bound,
        window,
        v0,
        nv,
        cx: 0,
        cy: 0,
        gone: false,
        asleep: false,
        island: -1,
        wcells: None,
    })
}

/// A polygon's vertices (at least 3) as the flat text's checks 12-15 ask:
/// edges of at least `tol` (|x| + |y|), every turn strictly
/// counter-clockwise, one winding, every normal outward; the message after
/// `body K` (" vertex J: ..." or ": ...").
fn check_polygon(vs: &[Vertex], tol: f64) -> Result<(), String> {
    let n = vs.len();
    let edge = |j: usize| {
        let (a, b) = (&vs[j], &vs[(j + 1) % n]);
        (b.lx - a.lx, b.ly - a.ly)
    };
    for j in 0..n {
        let (ex, ey) = edge(j);
        if !(ex.abs() + ey.abs() >= tol) {
            return Err(format!(" vertex {j}: edge shorter than the tolerance"));
        }
    }
    for j in 0..n {
        let ((px, py), (ex, ey)) = (edge((j + n - 1) % n), edge(j));
        if !(px * ey - py * ex > 0.0) {
            return Err(format!(" vertex {j}: not strictly convex (counter-clockwise)"));
        }
    }
    let signs: Vec<bool> = (0..n).map(|j| edge(j).1).filter(|&y| y != 0.0).map(|y| y > 0.0).collect();
    let changes = (0..signs.len()).filter(|&i| signs[i] != signs[(i + 1) % signs.len()]).count();
    if changes != 2 {
        return Err(format!(": the polygon winds {} times", changes / 2));
    }
    for (j, v) in vs.iter().enumerate() {
        let (ex, ey) = edge(j);
        if !(v.nx * ey - v.ny * ex > 0.0) {
            return Err(format!(" vertex {j}: the normal does not point outward"));
        }
    }
    Ok(())
}

impl Scene {
    /// Read a compiled scene, checking it as docs/simulator.md's "Flat
    /// scene checks" say (the first fault); the error is the message of an
    /// `X` line.  No count taken from the text sizes an allocation before
    /// it is checked.
    pub fn parse(text: &str) -> Result<Scene, String> {
        check_text(text.as_bytes(), "scene")?;
        let mut tk = Tokens::new(text, "scene");
        tk.expect("m2c-scene")?;
        let version = tk.int()?;
        if version != 1 {
            return Err(format!("scene: unknown version {version}"));
        }
        tk.expect("end")?;
        let end = tk.num()?;
        if !(end > 0.0 && end <= LENGTH_MAX) {
            return Err(format!("scene: end {} outside (0, 1e150]", g17(end)));
        }
        tk.expect("frame")?;
        let frame_dt = tk.num()?;
        if !(frame_dt == 0.0 || (frame_dt > 0.0 && end / frame_dt <= 1e12)) {
            return Err(if frame_dt > 0.0 {
                format!("scene: frame {} gives more than 1e12 frames", g17(frame_dt))
            } else {
                format!("scene: frame {} is negative", g17(frame_dt))
            });
        }
        tk.expect("tolerance")?;
        let tol = tk.num()?;
        if !(LENGTH_MIN..=LENGTH_MAX).contains(&tol) {
            return Err(format!("scene: tolerance {} outside [1e-150, 1e150]", g17(tol)));
        }
        tk.expect("rest_speed")?;
        let rest_speed = tk.num()?;
        if !(rest_speed >= 0.0) {
            return Err(format!("scene: rest_speed {} is negative", g17(rest_speed)));
        }
        if rest_speed > LENGTH_MAX {
            // its square must not overflow
            return Err(format!("scene: rest_speed {} beyond 1e150", g17(rest_speed)));
        }
        tk.expect("window_angle")?;
        let alpha = tk.num()?;
        if !(alpha > 0.0 && alpha <= 0.5) {
            return Err(format!("scene: window_angle {} outside (0, 0.5]", g17(alpha)));
        }
        tk.expect("max_same_time")?;
        let max_same = tk.int()?;
        if max_same < 1 {
            return Err(format!("scene: max_same_time {max_same} is less than 1"));
        }
        tk.expect("max_events")?;
        let max_events = tk.int()?;
        if max_events < 1 {
            return Err(format!("scene: max_events {max_events} is less than 1"));
        }
        // the grid line read whole, then checked
        tk.expect("grid")?;
        // each pair checked once read, as the words come (docs/simulator.md, "Flat scene checks", Header)
        let (x0, y0) = (tk.num()?, tk.num()?);
        if !(x0.abs() <= LENGTH_MAX && y0.abs() <= LENGTH_MAX) {
            return Err("scene: grid origin beyond 1e150".to_string());
        }
        let (cw, ch) = (tk.num()?, tk.num()?);
        for c in [cw, ch] {
            if !(LENGTH_MIN..=LENGTH_MAX).contains(&c) {
                return Err(format!("scene: grid cell {} outside [1e-150, 1e150]", g17(c)));
            }
        }
        let (nx, ny) = (tk.int()?, tk.int()?);
        if nx < 1 || ny < 1 {
            return Err(format!("scene: grid of {nx} x {ny} cells"));
        }
        let margin = tk.num()?;
        let half_cell = 0.5 * if ch < cw { ch } else { cw };
        if !(0.0 <= margin && margin < half_cell) {
            return Err(format!("scene: grid margin {} m outside [0, half a cell)", g17(margin)));
        }
        tk.expect("bodies")?;
        let n = tk.int()?;
        if !(1..=MAX_BODIES).contains(&n) {
            return Err(format!("scene: {n} bodies (1 to {MAX_BODIES})"));
        }
        // at most 4e6 cells: nx, ny and their product fit an i32
        let cells = (4 * n).max(16);
        if !(nx <= cells && ny <= cells && nx * ny <= cells) {
            return Err(format!("scene: grid of {nx} x {ny} cells for {n} bodies (at most max(16, 4 x bodies) cells)"));
        }
        // a body line has 22 words: at least 44 bytes each
        let mut bodies = Vec::with_capacity((n as usize).min(tk.remaining() / 44 + 1));
        super::huge::advise(&bodies);
        let mut verts = Vec::new();
        let lim = BodyLimits { end, tol, bodies: n };
        for idx in 0..n as u32 {
            bodies.push(read_body(&mut tk, idx, &mut verts, &lim)?);
        }
        for b in &bodies {
            for j in 0..b.nverts() {
                let cover = verts[b.vert(j)].cover;
                if cover >= 0 && !bodies[cover as usize].fixed {
                    return Err(format!("scene: body {} vertex {j}: cover {cover} is not a fixed body", b.idx));
                }
            }
        }
        tk.expect("inputs")?;
        let k = tk.int()?;
        if !(0..=MAX_INPUTS).contains(&k) {
            return Err(format!("scene: {k} inputs (0 to {MAX_INPUTS})"));
        }
        // an input line has 6 words: at least 12 bytes each
        let mut inputs = Vec::with_capacity((k as usize).min(tk.remaining() / 12 + 1));
        // the input that removed each body, once one does
        let mut removed_by: Vec<i64> = Vec::new();
        for i in 0..k {
            tk.expect("input")?;
            let t = tk.num()?;
            let body = tk.int()?;
            let mode = tk.int()?;
            let (vx, vy) = (tk.num()?, tk.num()?);
            if !(0.0 <= t && t <= end) {
                return Err(format!("scene: input {i}: time {} outside [0, end]", g17(t)));
            }
            if body < 0 || body >= n {
                return Err(format!("scene: input on body {body}, which does not exist"));
            }
            if !(0..=4).contains(&mode) {
                return Err(format!("scene: unknown input mode {mode}"));
            }
            if !drivable(&bodies[body as usize], mode) {
                return Err(format!(
                    "scene: input {i} on fixed body {body}: only set_velocity (on a polygon that does not turn) or remove"
                ));
            }
            if let Some(&m) = removed_by.get(body as usize).filter(|&&m| m >= 0) {
                return Err(format!("scene: input {i}: body {body} was removed by input {m}"));
            }
            if mode == REMOVE {
                if !(vx == 0.0 && vy == 0.0) {
                    return Err(format!("scene: input {i}: a removal has no vector"));
                }
                if removed_by.is_empty() {
                    removed_by = vec![-1; n as usize];
                }
                removed_by[body as usize] = i;
            }
            if mode == TELEPORT && !(vx.abs() + vy.abs() <= LENGTH_MAX) {
                return Err(format!("scene: input {i}: teleport beyond 1e150 m"));
            }
            inputs.push(Input { t, body, mode, vx, vy });
        }
        tk.expect("end")?;
        if let Some(w) = tk.rest() {
            return Err(format!("scene: unexpected '{}' after the end", shown(w)));
        }
        Ok(Scene {
            end,
            frame_dt,
            tol,
            rest_speed,
            alpha,
            max_same,
            max_events,
            x0,
            y0,
            cw,
            ch,
            nx,
            ny,
            margin,
            half_cell,
            bodies,
            verts,
            inputs,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::{check_text, parse_decimal_prefix, read_body, BodyLimits, Tokens};

    /// The whole word `w` as parse_decimal_prefix reads it, or None.
    fn parse_decimal(w: &[u8]) -> Option<f64> {
        match parse_decimal_prefix(w) {
            Some((x, p)) if p == w.len() => Some(x),
            _ => None,
        }
    }

    /// xorshift64*: reproducible numbers without a dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(2685821657736338717)
        }
    }

    /// parse_decimal reads what `parse` reads, bit for bit, whenever it
    /// reads a decimal at all: shortest and 15-17 digit forms of random
    /// doubles of every magnitude, and random digit strings.
    #[test]
    fn decimals_read_as_parse_reads_them() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let (mut fast, mut total) = (0, 0);
        let mut check = |text: String| {
            let want: f64 = text.parse().expect("a number");
            if let Some(x) = parse_decimal(text.as_bytes()) {
                assert_eq!(x.to_bits(), want.to_bits(), "{text}");
                fast += 1;
            }
            total += 1;
        };
        for k in 0..200_000u64 {
            let u = rng.next();
            let x = match k % 3 {
                0 => f64::from_bits(u),
                1 => ((u >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 10f64.powi((rng.next() % 40) as i32 - 20),
                _ => (u % 2_000_001) as f64 / 1000.0 - 1000.0,
            };
            if !x.is_finite() {
                continue;
            }
            check(format!("{x:?}"));
            check(format!("{x:e}"));
            check(format!("{x:.16e}"));
            check(format!("{x:.14e}"));
            let nd = 1 + (rng.next() % 20) as usize;
            let at = (rng.next() % 21) as usize;
            let mut s = String::new();
            for d in 0..nd {
                if d == at {
                    s.push('.');
                }
                s.push(char::from(b'0' + (rng.next() % 10) as u8));
            }
            check(format!("{s}e{}", (rng.next() % 60) as i32 - 40));
        }
        assert!(fast > total / 4 && fast < total, "{fast} of {total} read without parse");
    }

    /// Tokens reads a text word by word as split_ascii_whitespace and
    /// `parse` read it: every number to the same bits, every word that is
    /// no number (or `parse`'s inf, nan, infinity) to the same error, an
    /// overflow to its own, whatever whitespace separates them (numbers
    /// followed directly by other characters included).
    #[test]
    fn tokens_read_as_split_and_parse_read() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let odd = [
            "1.5x", "1e", "1e+", "-", ".", "-.e1", "abc", "nan", "inf", "-inf", "1_0", "0x10", "1e99999", "1.5e5e",
            "+1", "1..2", "9",
        ];
        let space = [" ", "  ", "\t", "\n", "\r\n", "\x0c", " \n\t "];
        for _ in 0..2_000 {
            let mut text = String::new();
            if rng.next().is_multiple_of(2) {
                text.push_str(space[(rng.next() % space.len() as u64) as usize]);
            }
            for k in 0..(1 + rng.next() % 12) {
                if k > 0 {
                    text.push_str(space[(rng.next() % space.len() as u64) as usize]);
                }
                let u = rng.next();
                let word = match u % 5 {
                    0 => odd[(rng.next() % odd.len() as u64) as usize].to_string(),
                    1 => format!("{:e}", f64::from_bits(rng.next() >> 2)),
                    2 => format!("{}", (rng.next() % 100_000) as f64 / 64.0 - 700.0),
                    3 => "9".repeat(1 + (rng.next() % 25) as usize),
                    _ => format!("{:?}", f64::from_bits(rng.next()) * 0.0 + (rng.next() % 1000) as f64 * 1e-7),
                };
                text.push_str(&word);
            }
            if rng.next().is_multiple_of(2) {
                text.push_str(space[(rng.next() % space.len() as u64) as usize]);
            }
            let mut tk = Tokens::new(&text, "t");
            for w in text.split_ascii_whitespace() {
                let named = w.contains(['n', 'N', 'i', 'I']); // inf, nan, infinity
                let want = match w.parse::<f64>() {
                    Ok(x) if !named && x.is_finite() => Ok(x.to_bits()),
                    Ok(_) if !named => Err(format!("t: number '{w}' is beyond a double's range")),
                    _ => Err(format!("t: expected a number, found '{w}'")),
                };
                assert_eq!(tk.num().map(f64::to_bits), want, "{text:?}");
            }
            assert_eq!(tk.num(), Err("t: ends early".to_string()), "{text:?}");
            assert_eq!(tk.rest(), None);
        }
    }

    /// The number grammar's edges: signs, points, exponents, 64
    /// characters, overflow and underflow; the integer grammar's 18 digits.
    #[test]
    fn number_and_integer_words() {
        let num = |w: &str| Tokens::new(w, "t").num();
        for (w, x) in [("+1", 1.0), ("1.", 1.0), (".5", 0.5), ("-.5e+1", -5.0), ("1E-400", 0.0), ("4.9e-324", 5e-324)] {
            assert_eq!(num(w), Ok(x), "{w}");
        }
        let long = format!("0.{}1", "0".repeat(61)); // 64 characters
        assert_eq!(num(&long), Ok(1e-62));
        let longer = format!("0.{}1", "0".repeat(62));
        assert_eq!(num(&longer), Err(format!("t: expected a number, found '{}...'", &longer[..32])));
        for w in ["inf", "-infinity", "NaN", "0x10", "1_0", ".", "-", "1e", "1e+", "++1", "1.5.", "e5", "1d5"] {
            assert_eq!(num(w), Err(format!("t: expected a number, found '{w}'")), "{w}");
        }
        assert_eq!(num("-1e309"), Err("t: number '-1e309' is beyond a double's range".to_string()));
        let int = |w: &str| Tokens::new(w, "t").int();
        assert_eq!(int("-999999999999999999"), Ok(-999_999_999_999_999_999));
        for w in ["1000000000000000000", "+5", "-", "1.0", "1e3", "--1", " "] {
            assert!(int(w).is_err(), "{w}");
        }
        assert_eq!(int("+5"), Err("t: expected an integer, found '+5'".to_string()));
    }

    /// The whole text: its first byte that is neither printable ASCII nor
    /// space, tab, newline or carriage return, by its offset.
    #[test]
    fn bytes_of_the_text() {
        assert_eq!(check_text(b"a b\tc\r\nd~!", "scene"), Ok(()));
        assert_eq!(check_text(b"ab\x0cc", "scene"), Err("scene: byte 2: not printable ASCII".to_string()));
        assert_eq!(
            check_text("t\u{e9}".as_bytes(), "add_body"),
            Err("add_body: byte 1: not printable ASCII".to_string())
        );
        assert_eq!(check_text(b"\x7f", "scene"), Err("scene: byte 0: not printable ASCII".to_string()));
    }

    /// A body line of a movable circle of radius 0.1 at x, the fields
    /// changed as `change` says (name, value).
    fn circle(change: &[(&str, &str)]) -> String {
        let names = "poly fixed inv_mass inv_inertia restitution friction px py vx vy ax ay angle omega radius orbit \
                     orbit_angle bound window large nverts";
        let mut words: Vec<String> =
            "0 0 1 0 0.5 0.2 0 0 0 0 0 -9.81 0 0 0.1 0 0 0.1 0 0 0".split(' ').map(String::from).collect();
        for (name, value) in change {
            let k = names.split_whitespace().position(|n| n == *name).expect("a field");
            words[k] = value.to_string();
        }
        format!("body {}\n", words.join(" "))
    }

    /// A square polygon's body line and `v` lines (side 0.4 about its
    /// centre), its vertices as given (counter-clockwise from (-0.2, -0.2)).
    fn square(vs: &[(f64, f64, f64, f64)]) -> String {
        let mut t = format!("body 1 0 0.5 3 0.5 0.2 1 0 0 0 0 -9.81 0 0 0 0 0 0.3 0 0 {}\n", vs.len());
        for (x, y, nx, ny) in vs {
            t.push_str(&format!("v {x} {y} 0.28 0 0 0.2 -0.2 0.2 {nx} {ny} -1\n"));
        }
        t
    }

    const SQUARE: [(f64, f64, f64, f64); 4] =
        [(-0.2, -0.2, 0.0, -1.0), (0.2, -0.2, 1.0, 0.0), (0.2, 0.2, 0.0, 1.0), (-0.2, 0.2, -1.0, 0.0)];

    fn body(text: &str) -> Result<(), String> {
        let lim = BodyLimits { end: 2.0, tol: 1e-9, bodies: 3 };
        let mut tk = Tokens::new(text, "add_body");
        read_body(&mut tk, 3, &mut Vec::new(), &lim).map(|_| ())
    }

    /// A body's checks, in their order, with WHAT = add_body.
    #[test]
    fn body_checks() {
        assert_eq!(body(&circle(&[])), Ok(()));
        assert_eq!(body(&square(&SQUARE)), Ok(()));
        let at = |m: &str| Err(format!("add_body: body 3: {m}"));
        assert_eq!(body(&circle(&[("fixed", "2"), ("large", "3")])), at("fixed must be 0 or 1"));
        assert_eq!(body(&circle(&[("inv_mass", "0")])), at("inverse mass 0 must be positive"));
        assert_eq!(body(&circle(&[("fixed", "1")])), at("a fixed body has inverse mass 0"));
        assert_eq!(body(&circle(&[("restitution", "5"), ("friction", "-1")])), at("restitution 5 outside [0, 1]"));
        assert_eq!(body(&circle(&[("friction", "-1")])), at("friction -1 is negative"));
        assert_eq!(
            body(&circle(&[("radius", "1e151"), ("bound", "1e151")])),
            at("radius 1e+151 outside [tolerance, 1e150]")
        );
        assert_eq!(body(&circle(&[("window", "-0.1")])), at("window -0.10000000000000001 outside [0, 0.5]"));
        assert_eq!(body(&circle(&[("bound", "0.05")])), at("bound 0.050000000000000003 is too small or too large"));
        assert_eq!(body(&circle(&[("ay", "-1e300")])), at("reaches more than 2e150 m from the origin by the end"));
        let mut big = square(&SQUARE);
        big = big.replacen(" 4\n", " 1025\n", 1);
        assert_eq!(body(&big), at("1025 vertices (3 to 1024)"));
        let mut cw = SQUARE;
        cw.reverse();
        assert_eq!(
            body(&square(&cw)),
            Err("add_body: body 3 vertex 0: not strictly convex (counter-clockwise)".into())
        );
        let mut short = SQUARE;
        short[1].0 = -0.2 + 1e-10;
        assert_eq!(body(&square(&short)), Err("add_body: body 3 vertex 0: edge shorter than the tolerance".into()));
        let mut inward = SQUARE;
        inward[2].3 = -1.0;
        assert_eq!(body(&square(&inward)), Err("add_body: body 3 vertex 2: the normal does not point outward".into()));
        let covered = square(&SQUARE).replacen(" -1\n", " 3\n", 1);
        assert_eq!(body(&covered), Err("add_body: body 3 vertex 0: cover 3 is not a body".into()));
        let far = square(&SQUARE).replacen("v -0.2 -0.2", "v -0.5 -0.2", 1);
        assert_eq!(body(&far), Err("add_body: body 3 vertex 0: outside the bound".into()));
        let distant = square(&SQUARE).replacen(" 0.28 ", " 0.31 ", 1);
        assert_eq!(body(&distant), Err("add_body: body 3 vertex 0: outside the bound".into()));
        let line = square(&SQUARE).replacen(" 0.2 -0.2 0.2 ", " 0.61 -0.2 0.2 ", 1);
        assert_eq!(body(&line), Err("add_body: body 3 vertex 0: outside the bound".into()));
    }
}
