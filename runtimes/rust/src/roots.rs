//! Smallest real root of `c[0] + c[1] t + ... + c[n] t^n` with `lo < t <= hi`.
//! Contract and algorithm: docs/roots.md. `t` is in the caller's time unit.

// `!(x < y)` is true for NaN, as `not (x < y)` in the other runtimes
#![allow(clippy::neg_cmp_op_on_partial_ord)]

/// Largest supported degree.
pub const MAX_DEGREE: usize = 16;

const N1: usize = MAX_DEGREE + 1;
const EPS: f64 = 2.220446049250313e-16; // 2^-52, spacing of doubles at 1
const SPLITTER: f64 = 134217729.0; // 2^27 + 1, Veltkamp splitting constant
const TINY: f64 = 9.332636185032189e-302; // 2^-1000, floor of the touching bound
const SIXTEENTH: f64 = 1.52587890625e-05; // 2^-16, bisection step from an end at 0
const NEWTON_TOL: f64 = 9.313225746154785e-10; // 2^-30: an accepted Newton step this small (relative) has converged
const HALLEY_TOL: f64 = 0.00390625; // 2^-8: an accepted Halley step this small: the polish finishes it (Bernstein's single root)
const HALLEY_MIN: f64 = 4.008336720017946e-292; // 2^-968: Halley's products below this lose precision to underflow
const HANDOFF_TOL: f64 = 6.103515625e-05; // 2^-14: ... or an accepted Newton step (Halley refused) this small
const POLISH_TOL: f64 = 2.384185791015625e-07; // 2^-22: a polishing Halley step this small ends the polish
const MAXIT: usize = 100; // bracketed Newton step limit
const BERN_DEPTH: usize = 12; // Bernstein subdivision depth limit
const QUAD_SPREAD: i32 = 900; // degree 2: one scale when coefficient exponents span at most this
const ONE_SCALE_SPAN: i32 = 800; // degree n >= 3: one scale when all roots lie in 2^(+-800/n)
const BAND_SPAN: i32 = 800; // otherwise bands of magnitude 2^(800/n)
/// i! for 0 <= i <= 16 (exact).
#[rustfmt::skip]
const FACT: [f64; N1] = [
    1.0, 1.0, 2.0, 6.0, 24.0, 120.0, 720.0, 5040.0, 40320.0, 362880.0, 3628800.0, 39916800.0,
    479001600.0, 6227020800.0, 87178291200.0, 1307674368000.0, 20922789888000.0,
];

/// 2^k for -1022 <= k <= 1023 (exact).
fn pow2(k: i32) -> f64 {
    f64::from_bits(((k + 1023) as u64) << 52)
}

/// Binary exponent e of a finite nonzero x with x = f 2^e, 0.5 <= |f| < 1 (C frexp).
fn frexp_exp(x: f64) -> i32 {
    let bits = x.to_bits();
    let field = ((bits >> 52) & 0x7ff) as i32;
    if field == 0 {
        // subnormal: scale into the normal range first
        return frexp_exp(x * pow2(64)) - 64;
    }
    field - 1022
}

/// Error-free product a*b = p + e (Dekker, no FMA).
#[inline(always)]
fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    let t = SPLITTER * a;
    let ah = t - (t - a);
    let al = a - ah;
    let t = SPLITTER * b;
    let bh = t - (t - b);
    let bl = b - bh;
    (p, ((ah * bh - p) + ah * bl + al * bh) + al * bl)
}

/// p(x) by compensated Horner.
fn comp_horner(a: &[f64], n: usize, x: f64) -> f64 {
    let mut s = a[n];
    let mut c = 0.0;
    for i in (0..n).rev() {
        let (p, pe) = two_prod(s, x);
        let ai = a[i];
        s = p + ai;
        let z = s - p;
        let se = (p - (s - z)) + (ai - z);
        c = c * x + (pe + se);
    }
    s + c
}

/// Sign of p(x): -1, 0 (zero within the compensated bound), +1.
fn sign_top(a: &[f64], n: usize, x: f64) -> i32 {
    let ax = x.abs();
    let mut v = a[n];
    let mut pt = v.abs();
    for i in (0..n).rev() {
        v = v * x + a[i];
        pt = pt * ax + a[i].abs();
    }
    let nf = n as f64;
    if v.abs() > 2.0 * nf * EPS * pt {
        return if v > 0.0 { 1 } else { -1 };
    }
    let r = comp_horner(a, n, x);
    let bound = (2.0 * nf * EPS) * (2.0 * nf * EPS) * pt + TINY;
    if r.abs() <= bound {
        0
    } else if r > 0.0 {
        1
    } else {
        -1
    }
}

/// Sign of the plain Horner value: -1, 0 (exactly zero), +1.
fn sign_plain(a: &[f64], n: usize, x: f64) -> i32 {
    let mut v = a[n];
    for i in (0..n).rev() {
        v = v * x + a[i];
    }
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

/// Bisection point of [xa, xb]; half = (xb - xa)/2.
fn midpoint(xa: f64, xb: f64, half: f64) -> f64 {
    if xa < 0.0 && 0.0 < xb {
        return 0.0;
    }
    if xa > 0.0 && xb > 8.0 * xa {
        return xa.sqrt() * xb.sqrt();
    }
    if xb < 0.0 && xa < 8.0 * xb {
        return -((-xa).sqrt() * (-xb).sqrt());
    }
    if xa == 0.0 && xb > 0.0 {
        return xb * SIXTEENTH;
    }
    if xb == 0.0 && xa < 0.0 {
        return xa * SIXTEENTH;
    }
    xa + half
}

/// Root of p in (lo, hi), p(lo) of sign slo (nonzero), p(hi) of the other,
/// starting at x0 (lo < x0 < hi).
#[inline(always)]
fn newton(a: &[f64], n: usize, lo: f64, hi: f64, slo: i32, x0: f64, tolnewton: f64) -> f64 {
    let mut xa = lo;
    let mut xb = hi;
    let mut x = x0;
    let mut dx = xb - xa;
    let mut dxold = dx;
    let neg = slo < 0;
    let mut tol: f64;
    for _ in 0..MAXIT {
        let mut v = a[n];
        let mut d = 0.0;
        for i in (0..n).rev() {
            d = d * x + v;
            v = v * x + a[i];
        }
        if v == 0.0 {
            break;
        }
        if (v < 0.0) == neg {
            xa = x;
        } else {
            xb = x;
        }
        let mut xn;
        if d != 0.0 && (4.0 * v).abs() < (dxold * d).abs() {
            let step = v / d;
            xn = x - step;
            if xa < xn && xn < xb {
                dxold = dx;
                dx = step;
                tol = tolnewton;
            } else {
                dxold = dx;
                dx = 0.5 * (xb - xa);
                xn = midpoint(xa, xb, dx);
                tol = EPS;
            }
        } else {
            dxold = dx;
            dx = 0.5 * (xb - xa);
            xn = midpoint(xa, xb, dx);
            tol = EPS;
        }
        if !(xa < xn && xn < xb) {
            break;
        }
        if dx.abs() <= tol * xn.abs() {
            x = xn;
            break;
        }
        x = xn;
    }
    x
}

/// The step from p(x) = v, p'(x) = d (nonzero), p''(x)/2 = h: Halley's
/// v d / (d^2 - v h) when d^2 - v h > d^2 / 2 (at most twice the Newton step,
/// same direction; false for an overflow or NaN) and both v d and d^2 are at
/// least HALLEY_MIN (no precision lost to underflow), else Newton's v / d;
/// and whether it is Halley's.
#[inline(always)]
fn halley_step(v: f64, d: f64, h: f64) -> (f64, bool) {
    let dd = d * d;
    let vd = v * d;
    let den = dd - v * h;
    if den > 0.5 * dd && vd.abs() >= HALLEY_MIN && dd >= HALLEY_MIN {
        (vd / den, true)
    } else {
        (v / d, false)
    }
}

/// c[0] + c[1] x + ... + c[m] x^m by Estrin's scheme (docs/roots.md step
/// 7.3): pairs q_i = q_2i + q_2i+1 * p with p = x, then x^2, x^4, ... until
/// one value is left; an odd last entry is carried up unchanged.  About
/// log2(m + 1) multiply-adds deep where Horner is m (m <= 16).
#[inline(always)]
fn estrin(c: &[f64], m: usize, x: f64) -> f64 {
    let mut q = [0.0f64; N1];
    let mut k = m + 1;
    q[..k].copy_from_slice(&c[..k]);
    let mut p = x;
    while k > 1 {
        let k2 = k.div_ceil(2);
        for i in 0..k2 {
            q[i] = if 2 * i + 1 < k { q[2 * i] + q[2 * i + 1] * p } else { q[2 * i] };
        }
        k = k2;
        p = p * p;
    }
    q[0]
}

/// Bernstein's single simple root in (lo, hi): `newton` with the step of
/// `halley_step`, h = p''/2, and p, p', p''/2 by Estrin's scheme (shorter
/// chains than Horner's: this loop is latency-bound, and it only brings x
/// within 2^-8; the polish evaluates by Horner with its error bound); an accepted Halley step of at most HALLEY_TOL
/// |x| ends it, a Newton step of at most HANDOFF_TOL |x|.
#[inline(always)]
fn halley(a: &[f64], n: usize, lo: f64, hi: f64, slo: i32, x0: f64) -> f64 {
    let mut xa = lo;
    let mut xb = hi;
    let mut x = x0;
    let mut dx = xb - xa;
    let mut dxold = dx;
    let neg = slo < 0;
    let mut tol: f64;
    // the coefficients of p' and p''/2
    let mut da = [0.0f64; MAX_DEGREE];
    let mut ha = [0.0f64; MAX_DEGREE];
    for i in 0..n {
        da[i] = (i + 1) as f64 * a[i + 1];
    }
    for i in 0..n - 1 {
        ha[i] = ((i + 1) * (i + 2) / 2) as f64 * a[i + 2];
    }
    for _ in 0..MAXIT {
        let v = estrin(a, n, x);
        let d = estrin(&da, n - 1, x);
        let h = estrin(&ha, n - 2, x);
        if v == 0.0 {
            break;
        }
        if (v < 0.0) == neg {
            xa = x;
        } else {
            xb = x;
        }
        let mut xn;
        if d != 0.0 && (4.0 * v).abs() < (dxold * d).abs() {
            let (step, is_halley) = halley_step(v, d, h);
            xn = x - step;
            if xa < xn && xn < xb {
                dxold = dx;
                dx = step;
                tol = if is_halley { HALLEY_TOL } else { HANDOFF_TOL };
            } else {
                dxold = dx;
                dx = 0.5 * (xb - xa);
                xn = midpoint(xa, xb, dx);
                tol = EPS;
            }
        } else {
            dxold = dx;
            dx = 0.5 * (xb - xa);
            xn = midpoint(xa, xb, dx);
            tol = EPS;
        }
        if !(xa < xn && xn < xb) {
            break;
        }
        if dx.abs() <= tol * xn.abs() {
            x = xn;
            break;
        }
        x = xn;
    }
    x
}

/// A last Newton step inside (xa, xb]: plain when the running error bound
/// of Horner at x is within a few ulps of x, else up to two steps with
/// compensated Horner.
#[inline(always)]
fn polish(a: &[f64], n: usize, mut x: f64, xa: f64, xb: f64) -> f64 {
    for _ in 0..2 {
        let ax = x.abs();
        let mut v = a[n];
        let mut d = 0.0;
        let mut mu = 0.5 * v.abs();
        for i in (0..n).rev() {
            d = d * x + v;
            v = v * x + a[i];
            mu = mu * ax + v.abs();
        }
        if d == 0.0 {
            return x;
        }
        // running error bound of Horner (Higham, Alg. 5.1): |v - p(x)| <= eps (mu - |v|/2)
        if mu <= 2.0 * (x * d).abs() {
            // Horner is accurate enough here: one plain Newton step
            let xn = x - v / d;
            if xa < xn && xn <= xb {
                return xn;
            }
            return x;
        }
        let vc = comp_horner(a, n, x);
        if vc == 0.0 {
            return x;
        }
        let xn = x - vc / d;
        if !(xa < xn && xn <= xb) || xn == x {
            return x;
        }
        x = xn;
    }
    x
}

/// The polish after Bernstein's Halley iteration: the step of `halley_step`
/// from p(x) (plain Horner where its running error bound allows, else
/// compensated), p'(x) and p''(x)/2, kept only inside (xa, xb]; a Halley step
/// of at most POLISH_TOL |x| (a Newton step: NEWTON_TOL) ends it, else
/// another round, at most three.
#[inline(always)]
fn polish_halley(a: &[f64], n: usize, mut x: f64, xa: f64, xb: f64) -> f64 {
    for _ in 0..3 {
        let ax = x.abs();
        let mut v = a[n];
        let mut d = 0.0;
        let mut h = 0.0;
        let mut mu = 0.5 * v.abs();
        for i in (0..n).rev() {
            h = h * x + d;
            d = d * x + v;
            v = v * x + a[i];
            mu = mu * ax + v.abs();
        }
        if d == 0.0 {
            return x;
        }
        if mu > 2.0 * (x * d).abs() {
            // plain Horner not accurate enough: compensated
            v = comp_horner(a, n, x);
        }
        let (step, is_halley) = halley_step(v, d, h);
        let xn = x - step;
        if !(xa < xn && xn <= xb) {
            return x;
        }
        if step.abs() <= (if is_halley { POLISH_TOL } else { NEWTON_TOL }) * xn.abs() {
            return xn;
        }
        x = xn;
    }
    x
}

/// `quadratic` in x = 2^s u (docs/roots.md step 7.4): s balances a 2^(2s)
/// against c (or b 2^s when c = 0), a common power of two puts the largest
/// coefficient in [1, 2), the roots u come back as ldexp(u, s).  The same
/// bits as `quadratic` where its products stay normal; where they underflow
/// (roots far from 1 with tiny coefficients) the roots are kept.
fn quadratic_scaled(a: f64, b: f64, c: f64, r: &mut [f64; 2]) -> usize {
    let ea = frexp_exp(a);
    let eb = if b != 0.0 { frexp_exp(b) } else { 0 };
    let ec = if c != 0.0 { frexp_exp(c) } else { 0 };
    let s = if c != 0.0 {
        (ec - ea).div_euclid(2)
    } else if b != 0.0 {
        eb - ea
    } else {
        0
    };
    let mut m = ea + 2 * s;
    if b != 0.0 {
        m = m.max(eb + s);
    }
    if c != 0.0 {
        m = m.max(ec);
    }
    let k = 1 - m;
    let nr = quadratic(ldexp(a, 2 * s + k), ldexp(b, s + k), ldexp(c, k), r);
    for x in r.iter_mut().take(nr) {
        *x = ldexp(*x, s);
    }
    nr
}

/// Real roots of a x^2 + b x + c (a != 0), ascending, into r; returns the
/// count. The plain discriminant when it cannot cancel (4ac <= b*b/2), none
/// when it is clearly negative, error-free products only in between.
#[inline(always)]
fn quadratic(a: f64, b: f64, c: f64, r: &mut [f64; 2]) -> usize {
    let mut p = b * b;
    let mut q = (4.0 * a) * c;
    let mut disc = p - q;
    if q <= 0.5 * p {
        if disc == 0.0 {
            // b == 0 and ac == 0
            r[0] = -b / (2.0 * a);
            return 1;
        }
    } else if disc < -EPS * (p + q) {
        return 0;
    } else {
        let (p2, pe) = two_prod(b, b);
        let a4 = 4.0 * a;
        let (q2, qe) = two_prod(a4, c);
        p = p2;
        q = q2;
        disc = (p - q) + (pe - qe);
        let bound = EPS * EPS * (p + q.abs());
        if disc < -bound {
            return 0;
        }
        if disc <= bound {
            r[0] = -b / (2.0 * a);
            return 1;
        }
    }
    let mut s = disc.sqrt();
    if b < 0.0 {
        s = -s;
    }
    let qq = -0.5 * (b + s);
    let r1 = qq / a;
    let r2 = c / qq;
    if r1 <= r2 {
        r[0] = r1;
        r[1] = r2;
    } else {
        r[0] = r2;
        r[1] = r1;
    }
    2
}

/// The first root of a x^2 + b x + c (a != 0) in (lo, hi].
#[inline(always)]
fn quadratic_in(a: f64, b: f64, c: f64, lo: f64, hi: f64) -> Option<f64> {
    let mut r = [0.0f64; 2];
    let nr = quadratic(a, b, c, &mut r);
    if nr > 0 && lo < r[0] && r[0] <= hi {
        return Some(r[0]);
    }
    if nr > 1 && lo < r[1] && r[1] <= hi {
        return Some(r[1]);
    }
    None
}

/// The degree-2 fast path's admission (docs/roots.md step 1): c2 != 0, each
/// coefficient zero or |c_i| >= 2^-200, |c0| + |c1| + |c2| < 2^200 (false for
/// NaN and infinities), and w = hi - lo positive and finite.  The lower bounds
/// read the exponent fields: (u << 1) - 1 wraps a zero (either sign) to the
/// top, so one unsigned comparison accepts zero and |v| >= 2^-200; for c2,
/// (u << 1) > K rejects zero as well.  w > 0 and finite is one unsigned
/// comparison of its bits.
#[inline(always)]
fn admit2(c0: f64, c1: f64, c2: f64, w: f64) -> bool {
    const K: u64 = (823u64 << 53) - 1; // exponent field 823: 2^-200
    const TWO_200: f64 = 1.6069380442589903e60; // 2^200 exactly
    let small = |v: f64| (v.to_bits() << 1).wrapping_sub(1) >= K;
    let ok = small(c0) & small(c1) & ((c2.to_bits() << 1) > K) & (w.to_bits().wrapping_sub(1) < 0x7fef_ffff_ffff_ffff);
    ok & (c0.abs() + c1.abs() + c2.abs() < TWO_200)
}

/// Degrees 3 and 4 with lo >= 0 and hi >= 2^-250 (docs/roots.md step 1,
/// "lo >= 0" (c)): true when p has no root in [0, hi], shown by its Bernstein
/// coefficients there (weighted sums of t_i = c_i hi^i) all beyond
/// m = 2^-46 (|t_0| + ... + |t_n|) + 2^-900 with one sign: m is 16 times their
/// rounding error, so the exact ones share that sign (hi >= 2^-250 keeps hi^n
/// normal: an underflowed power would lose c_i hi^n whole).  Steps 2-8 answer
/// none for each such p; this answers it sooner.  False when not shown (also
/// for a NaN, an infinity or an overflow: a comparison with NaN or with an
/// infinite m is false).  p(0) and p(hi) of opposite signs, the usual case
/// when there is a root, are tested first, so that those calls pay little.
#[inline(always)]
pub(crate) fn no_root3(c: &[f64], hi: f64) -> bool {
    let h2 = hi * hi;
    let (t0, t1, t2, t3) = (c[0], c[1] * hi, c[2] * h2, c[3] * (h2 * hi));
    let b3 = (t0 + t1) + (t2 + t3);
    if signs_differ(t0, b3) {
        return false;
    }
    let m = TWO_M46 * ((t0.abs() + t1.abs()) + (t2.abs() + t3.abs())) + TWO_M900;
    let b1 = t0 + t1 * (1.0 / 3.0);
    let b2 = (t0 + t1 * (2.0 / 3.0)) + t2 * (1.0 / 3.0);
    let f = |b: f64| flip(b, t0) > m;
    f(t0) & f(b1) & f(b2) & f(b3)
}

/// Whether the sign bits of x and y differ.  In `no_root3` and `no_root4`
/// this stands for (x < 0) != (y < 0): the two differ only when x or y is
/// zero or NaN, and then the test answers false either way.
#[inline(always)]
fn signs_differ(x: f64, y: f64) -> bool {
    ((x.to_bits() ^ y.to_bits()) as i64) < 0
}

/// b with its sign bit flipped when s's is set: flip(b, s) > m for m > 0 is
/// b > m when s >= +0 and b < -m when s <= -0 (false for NaN either way).
/// In `no_root3` and `no_root4`, s = t0: "all b_i > m or all b_i < -m"
/// (t0 among them) is "all flip(b_i, t0) > m" (t0 = +-0 fails both).
#[inline(always)]
fn flip(b: f64, s: f64) -> f64 {
    f64::from_bits(b.to_bits() ^ (s.to_bits() & 0x8000_0000_0000_0000))
}

/// `no_root3` for degree 4.
#[inline(always)]
pub(crate) fn no_root4(c: &[f64], hi: f64) -> bool {
    let h2 = hi * hi;
    let (t0, t1, t2, t3, t4) = (c[0], c[1] * hi, c[2] * h2, c[3] * (h2 * hi), c[4] * (h2 * h2));
    let b4 = ((t0 + t1) + (t2 + t3)) + t4;
    if signs_differ(t0, b4) {
        return false;
    }
    let m = TWO_M46 * (((t0.abs() + t1.abs()) + (t2.abs() + t3.abs())) + t4.abs()) + TWO_M900;
    let b1 = t0 + t1 * 0.25;
    let b2 = (t0 + t1 * 0.5) + t2 * (1.0 / 6.0);
    let b3 = (t0 + t1 * 0.75) + (t2 * 0.5 + t3 * 0.25);
    let f = |b: f64| flip(b, t0) > m;
    f(t0) & f(b1) & f(b2) & f(b3) & f(b4)
}

const TWO_M46: f64 = 1.4210854715202004e-14; // 2^-46 exactly
const TWO_M250: f64 = 5.527147875260445e-76; // 2^-250 exactly
const TWO_M900: f64 = 1.1830521861667747e-271; // 2^-900 exactly

/// The degree-2 fast path (step 1; admitted by `admit2`): the first root in
/// (lo, hi] as `quadratic_in` finds it (step 6), never -0.0.  With lo >= 0
/// (docs/roots.md step 1, "lo >= 0"; the entry has already answered none
/// when c0, c1, c2 have no sign change), when c0 c2 < 0 only the positive
/// root is computed.
#[inline(always)]
fn quadratic_fast(c0: f64, c1: f64, c2: f64, lo: f64, hi: f64) -> Option<f64> {
    let (a, b, c) = (c2, c1, c0);
    let from0 = lo >= 0.0;
    let p = b * b;
    let q = (4.0 * a) * c;
    let d = p - q;
    let x;
    if q <= 0.5 * p {
        if d == 0.0 {
            // b == 0 and ac == 0: the double root
            x = -b / (2.0 * a);
            return if lo < x && x <= hi { Some(x + 0.0) } else { None };
        }
    } else if d < -EPS * (p + q) {
        return None;
    } else {
        return quadratic_exact(a, b, c, lo, hi); // cancellation possible
    }
    let mut s = d.sqrt();
    if b < 0.0 {
        s = -s;
    }
    let qq = -0.5 * (b + s);
    if from0 & (q < 0.0) {
        // a c < 0: one root of each sign, and only the positive one can lie
        // in (lo, hi]; it is qq/a when b and a differ in sign, else c/qq
        x = if (b < 0.0) != (a < 0.0) { qq / a } else { c / qq };
    } else {
        let r1 = qq / a;
        let r2 = c / qq;
        let (r0, r1) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
        if lo < r0 && r0 <= hi {
            return Some(r0 + 0.0);
        }
        x = r1;
    }
    if lo < x && x <= hi {
        Some(x + 0.0)
    } else {
        None
    }
}

/// The degree-2 fast path where the discriminant may cancel: the whole of
/// `quadratic_in` (its error-free branch), out of line.
#[inline(never)]
fn quadratic_exact(a: f64, b: f64, c: f64, lo: f64, hi: f64) -> Option<f64> {
    let x = quadratic_in(a, b, c, lo, hi)?;
    Some(x + 0.0)
}

/// x 2^k rounded once (C's ldexp; x finite): exact unless the result is
/// subnormal, zero or infinite.
fn ldexp(x: f64, k: i32) -> f64 {
    if x == 0.0 {
        return x;
    }
    let e = frexp_exp(x);
    // f = x 2^-e in [0.5, 1), exact (2^-1023 and 2^-1024 are not normal powers)
    let f = if e < -1000 {
        (x * pow2(600)) * pow2(-(e + 600))
    } else if e == 1024 {
        x * pow2(-1022) * 0.25
    } else if e == 1023 {
        x * pow2(-1022) * 0.5
    } else {
        x * pow2(-e)
    };
    let m = e as i64 + k as i64;
    if m > 1024 {
        return f * pow2(1023) * 4.0; // overflows to infinity
    }
    if m == 1024 {
        return (f * 2.0) * pow2(1023);
    }
    if m >= -1021 {
        return f * pow2(m as i32);
    }
    let m = if m < -1100 { -1100 } else { m as i32 };
    (f * pow2(m + 1022)) * pow2(-1022)
}

/// ceil(a / k) for k > 0, with nonnegative operands only.
fn ceil_div(a: i32, k: i32) -> i32 {
    if a >= 0 {
        (a + k - 1) / k
    } else {
        -((-a) / k)
    }
}

/// (ue, le): every root of c (degree n, c[n] != 0, j < n the lowest index
/// with c[j] != 0) has |t| < 2^ue, every nonzero root |t| > 2^le.
fn root_exponents(c: &[f64], n: usize, j: usize) -> (i32, i32) {
    let en = frexp_exp(c[n]);
    let ej = frexp_exp(c[j]);
    let mut u = -(1 << 30);
    let mut lx = -(1 << 30);
    for (i, &ci) in c[..n].iter().enumerate().skip(j) {
        if ci != 0.0 {
            let v = ceil_div(frexp_exp(ci) - en + 1, (n - i) as i32);
            if v > u {
                u = v;
            }
        }
    }
    for (i, &ci) in c[..=n].iter().enumerate().skip(j + 1) {
        if ci != 0.0 {
            let v = ceil_div(frexp_exp(ci) - ej + 1, (i - j) as i32);
            if v > lx {
                lx = v;
            }
        }
    }
    (u + 1, -(lx + 1))
}

/// 2^e, or infinity beyond the largest double (a band edge).
fn edge(e: i32) -> f64 {
    if e > 1023 {
        return f64::INFINITY;
    }
    ldexp(1.0, e)
}

/// The smallest root in (xl, xr], where 2^(s - w) <= |x| <= 2^s: solved in
/// u = t 2^-s with the coefficients c_i 2^(s i) scaled together so that the
/// largest lies in [1, 2) (those far below underflow: negligible in the band).
fn band(c: &[f64], n: usize, s: i32, xl: f64, xr: f64) -> Option<f64> {
    let mut m = -(1 << 30);
    for (i, &ci) in c[..=n].iter().enumerate() {
        if ci != 0.0 {
            let f = frexp_exp(ci) + s * i as i32;
            if f > m {
                m = f;
            }
        }
    }
    let mut a = [0.0f64; N1];
    for i in 0..n + 1 {
        a[i] = ldexp(c[i], s * i as i32 + 1 - m);
    }
    let mut n = n;
    while a[n] == 0.0 {
        if n == 0 {
            return None;
        }
        n -= 1;
    }
    if n == 0 {
        return None;
    }
    let u = scaled_any(&a, n, ldexp(xl, -s), ldexp(xr, -s))?;
    let x = ldexp(u, s);
    if xl < x && x <= xr {
        Some(x)
    } else {
        None
    }
}

/// Roots too spread for one scale: bands of magnitude, each with its own
/// power-of-two scale of t, in the order of t (docs/roots.md step 7).
fn banded(c: &[f64], n: usize, j: usize, ue: i32, le: i32, lo: f64, hi: f64) -> Option<f64> {
    let w = BAND_SPAN / n as i32;
    let nb = ceil_div(ue - le, w);
    for k in (0..nb).rev() {
        let s = le + (k + 1) * w;
        let mut xl = -edge(s);
        let mut xr = -edge(s - w);
        if lo > xl {
            xl = lo;
        }
        if hi < xr {
            xr = hi;
        }
        if xl < xr {
            if let Some(t) = band(c, n, s, xl, xr) {
                return Some(t);
            }
        }
    }
    if j > 0 && lo < 0.0 && 0.0 <= hi {
        return Some(0.0);
    }
    for k in 0..nb {
        let s = le + (k + 1) * w;
        let mut xl = edge(s - w);
        let mut xr = edge(s);
        if lo > xl {
            xl = lo;
        }
        if hi < xr {
            xr = hi;
        }
        if xl < xr {
            if let Some(t) = band(c, n, s, xl, xr) {
                return Some(t);
            }
        }
    }
    None
}

/// All roots of p (degree n) in the open (lo, hi), ascending, given the
/// ascending roots `crit` of p' there; returns the count written to `out`.
fn roots_between(a: &[f64], n: usize, crit: &[f64], lo: f64, hi: f64, out: &mut [f64]) -> usize {
    let mut k = 0;
    let mut xl = lo;
    let mut sl = sign_plain(a, n, lo);
    let m = crit.len();
    for i in 0..=m {
        let xr = crit.get(i).copied().unwrap_or(hi); // the critical points, then hi
        let sr = sign_plain(a, n, xr);
        if sl == 0 && i > 0 {
            out[k] = xl;
            k += 1;
        } else if sl * sr < 0 {
            out[k] = newton(a, n, xl, xr, sl, 0.5 * (xl + xr), NEWTON_TOL);
            k += 1;
        }
        xl = xr;
        sl = sr;
    }
    k
}

/// The derivative method on [lo, hi] (answers in (lo, hi]): roots of the
/// derivatives bottom up, then the first root of p with careful signs.
// `crit[i]` indexed: its `get` forms compile to more instructions (the simulator calls this often)
#[allow(clippy::needless_range_loop)]
fn by_derivatives(a: &[f64], n: usize, lo: f64, hi: f64) -> Option<f64> {
    let mut ders = [[0.0f64; N1]; MAX_DEGREE - 1];
    ders[0][..=n].copy_from_slice(&a[..=n]);
    for k in 1..n - 1 {
        for i in 0..=n - k {
            ders[k][i] = ders[k - 1][i + 1] * (i + 1) as f64;
        }
    }
    let mut crit = [0.0f64; MAX_DEGREE];
    let mut next = [0.0f64; MAX_DEGREE];
    let mut qr = [0.0f64; 2];
    let d2 = &ders[n - 2];
    let nq = quadratic_scaled(d2[2], d2[1], d2[0], &mut qr);
    let mut m = 0;
    for &x in &qr[..nq] {
        if lo < x && x < hi {
            crit[m] = x;
            m += 1;
        }
    }
    for k in (1..n - 2).rev() {
        let m2 = roots_between(&ders[k], n - k, &crit[..m], lo, hi, &mut next);
        crit[..m2].copy_from_slice(&next[..m2]);
        m = m2;
    }
    let mut xl = lo;
    let mut sl = sign_top(a, n, lo);
    for i in 0..=m {
        if sl == 0 && i > 0 {
            return Some(xl);
        }
        let xr = if i < m { crit[i] } else { hi };
        let sr = sign_top(a, n, xr);
        if sl * sr < 0 {
            let x0 = newton(a, n, xl, xr, sl, 0.5 * (xl + xr), NEWTON_TOL);
            let mut x = polish(a, n, x0, xl, xr); // the monotone piece bounds the polish
            if !(x > xl) {
                x = xr;
            }
            if x > xr {
                x = xr;
            }
            return Some(x);
        }
        xl = xr;
        sl = sr;
    }
    if sl == 0 {
        return Some(hi);
    }
    None
}

/// Sign variations of b[0..=n], or -1 when one of them is within e of zero;
/// also max |b_i|.
#[inline(always)]
fn variations(b: &[f64], n: usize, e: f64) -> (i32, f64) {
    let mut m = b[0].abs();
    let mut unsure = m <= e;
    let mut v = 0;
    for i in 1..n + 1 {
        let ab = b[i].abs();
        m = if ab > m { ab } else { m };
        unsure |= ab <= e;
        v += ((b[i] < 0.0) != (b[i - 1] < 0.0)) as i32;
    }
    (if unsure { -1 } else { v }, m)
}

/// The general method for degree n = N >= 3 (a scaled; one copy per degree,
/// so the loops unroll): clip to the root bound, Bernstein subdivision left
/// to right, the derivative method where the Bernstein signs are unsure.
// `b[j] = b[j] + x`: `+=` evaluates x before the place, which reorders the bounds checks (other code)
#[allow(clippy::assign_op_pattern)]
#[inline(always)]
fn general<const N: usize, const M: usize>(a: &[f64; M], mut lo: f64, mut hi: f64) -> Option<f64> {
    let n = N;
    // 1. clip to the root bound (r >= 2: nothing to clip in [-2, 2], and no
    // division on the way)
    if !(-2.0 <= lo && hi <= 2.0) {
        let mut mx = 0.0;
        for &ai in &a[..n] {
            let v = ai.abs();
            if v > mx {
                mx = v;
            }
        }
        mx /= a[n].abs(); // = max |a_i|/|a_n| (rounding is monotone)
        let mut r = 2.0 * (1.0 + mx);
        let cap = pow2(900 / n as i32);
        if r > cap {
            r = cap;
        }
        if lo < -r {
            lo = -r;
        }
        if hi > r {
            hi = r;
        }
        if !(lo < hi) {
            return None;
        }
    }
    // 2. n! times the Bernstein coefficients of p on [lo, hi], error bound e
    let mut b = *a;
    if lo != 0.0 {
        for i in 0..n {
            for j in (i..n).rev() {
                b[j] = b[j] + lo * b[j + 1];
            }
        }
    }
    let w = hi - lo;
    let mut f = 1.0;
    for j in 0..n + 1 {
        b[j] = b[j] * f * (FACT[j] * FACT[n - j]);
        f *= w;
    }
    for k in 1..n + 1 {
        for j in (k..n + 1).rev() {
            b[j] = b[j] + b[j - 1];
        }
    }
    let y = lo.abs() + w;
    let mut pt = a[n].abs();
    for i in (0..n).rev() {
        pt = pt * y + a[i].abs();
    }
    let nf = n as f64;
    let e = 8.0 * (nf + 1.0) * EPS * pt * FACT[n] + TINY;
    // 3. subdivision, left to right
    subdivide_impl::<N, M>(a, &b, e, lo, hi, 0)
}

/// `subdivide_impl` out of line, for the halves.
#[inline(never)]
fn subdivide<const N: usize, const M: usize>(
    a: &[f64; M],
    b: &[f64; M],
    e: f64,
    xl: f64,
    xr: f64,
    depth: usize,
) -> Option<f64> {
    subdivide_impl::<N, M>(a, b, e, xl, xr, depth)
}

/// Step 3 on [xl, xr] with the n!-scaled Bernstein coefficients b and their
/// error bound e: the root in (xl, xr], or None (the caller goes on right).
#[inline(always)]
fn subdivide_impl<const N: usize, const M: usize>(
    a: &[f64; M],
    b: &[f64; M],
    e: f64,
    xl: f64,
    xr: f64,
    depth: usize,
) -> Option<f64> {
    let n = N;
    let nf = n as f64;
    let (v, bm) = variations(b, n, e);
    if v == 1 {
        // one simple root in (xl, xr): start where the control polygon crosses
        let wn = (xr - xl) / nf;
        let mut x0 = if N == 3 {
            // the same sums with b in registers: the segment by branches
            if (b[1] < 0.0) != (b[0] < 0.0) {
                xl + wn * (0.0 + b[0] / (b[0] - b[1]))
            } else if (b[2] < 0.0) != (b[1] < 0.0) {
                xl + wn * (1.0 + b[1] / (b[1] - b[2]))
            } else {
                xl + wn * (2.0 + b[2] / (b[2] - b[3]))
            }
        } else {
            let mut i = 0;
            while (b[i + 1] < 0.0) == (b[i] < 0.0) {
                i += 1;
            }
            xl + wn * (i as f64 + b[i] / (b[i] - b[i + 1]))
        };
        if !(xl < x0 && x0 < xr) {
            x0 = 0.5 * (xl + xr);
        }
        let x1 = halley(a, n, xl, xr, if b[0] < 0.0 { -1 } else { 1 }, x0);
        let mut x = polish_halley(a, n, x1, xl, xr);
        if !(x > xl) {
            x = xr;
        }
        if x > xr {
            x = xr;
        }
        return Some(x);
    }
    if v == 0 {
        return None;
    }
    if depth == BERN_DEPTH || (v < 0 && (b[0].abs() <= e || b[n].abs() <= e)) {
        return by_derivatives(a, n, xl, xr);
    }
    // de Casteljau at 1/2: left half, then right half
    let mut c = *b;
    let mut lb = [0.0f64; M];
    let mut rb = [0.0f64; M];
    lb[0] = c[0];
    rb[n] = c[n];
    for k in 1..n + 1 {
        for i in 0..n - k + 1 {
            c[i] = 0.5 * (c[i] + c[i + 1]);
        }
        lb[k] = c[0];
        rb[n - k] = c[n - k];
    }
    let xm = 0.5 * (xl + xr);
    let e2 = e + nf * EPS * bm;
    if let Some(t) = subdivide::<N, M>(a, &lb, e2, xl, xm, depth + 1) {
        return Some(t);
    }
    subdivide::<N, M>(a, &rb, e2, xm, xr, depth + 1)
}

/// Scaled coefficients (max |a_i| in [1, 2), a[N] != 0): closed forms for
/// degrees 1 and 2, the general method (one copy per degree).
#[inline(always)]
fn scaled<const N: usize, const M: usize>(a: &[f64; M], lo: f64, hi: f64) -> Option<f64> {
    if N == 1 {
        let x = -a[0] / a[1];
        if !(lo < x && x <= hi) {
            return None;
        }
        Some(x)
    } else if N == 2 {
        quadratic_in(a[2], a[1], a[0], lo, hi)
    } else {
        general::<N, M>(a, lo, hi)
    }
}

/// Degree n = N >= 2 (c[N] != 0; a NaN or infinity answers none): one power-of-two scale of the coefficients
/// when the roots allow it, else bands (one copy per degree).  M = N + 1 (a
/// const generic cannot be N + 1 on stable Rust): the arrays of this copy
/// hold exactly its coefficients, so there are no unused entries to zero.
fn solve<const N: usize, const M: usize>(c: &[f64; M], lo: f64, hi: f64) -> Option<f64> {
    const { assert!(M == N + 1) };
    let n = N;
    // max and smallest nonzero |c_i| from their bit patterns (ordered like the
    // values); a NaN or infinity shows as the largest: answer none
    let mut umax = 0u64;
    let mut umin = u64::MAX;
    for ci in c {
        let u = ci.to_bits() & 0x7fff_ffff_ffff_ffff;
        let uz = u.wrapping_sub(1); // a zero wraps to the top: the minimum skips it
        umax = if u > umax { u } else { umax };
        umin = if uz < umin { uz } else { umin };
    }
    let umin = umin.wrapping_add(1); // c[N] != 0: some u is nonzero
    if umax >= 0x7ff0_0000_0000_0000 {
        return None;
    }
    // frexp exponents of the largest and smallest: of normal numbers, their
    // exponent fields less 1022 (the smallest normal: so is the largest)
    let (ex, en) = if umin >= 1 << 52 {
        ((umax >> 52) as i32 - 1022, (umin >> 52) as i32 - 1022)
    } else {
        (frexp_exp(f64::from_bits(umax)), frexp_exp(f64::from_bits(umin)))
    };
    let spread = ex - en;
    let lim = ONE_SCALE_SPAN / n as i32;
    if if n == 2 { spread > QUAD_SPREAD } else { spread > lim - 2 } {
        let mut j = 0;
        while c[j] == 0.0 {
            j += 1;
        }
        let (ue, le) = root_exponents(c, n, j);
        if n == 2 || !(ue <= lim && le >= -lim) {
            return banded(c, n, j, ue, le, lo, hi);
        }
        // one scale for a wide spread: top coefficients may underflow
        let mut a = [0.0f64; M];
        let n2 = scale_max(c, N, ex, &mut a)?;
        if n2 != N {
            return scaled_any(&a, n2, lo, hi);
        }
        return scaled::<N, M>(&a, lo, hi);
    }
    // the spread bounds every nonzero |a_i| below by 2^-(spread + 1) >= 2^-901:
    // nothing underflows
    let mut a = [0.0f64; M];
    scale_pow2(c, N, ex, &mut a);
    scaled::<N, M>(&a, lo, hi)
}

fn dispatch(c: &[f64], n: usize, lo: f64, hi: f64) -> Option<f64> {
    match n {
        2 => solve::<2, 3>(head(c), lo, hi),
        3 => solve::<3, 4>(head(c), lo, hi),
        4 => solve::<4, 5>(head(c), lo, hi),
        5 => solve::<5, 6>(head(c), lo, hi),
        6 => solve::<6, 7>(head(c), lo, hi),
        7 => solve::<7, 8>(head(c), lo, hi),
        8 => solve::<8, 9>(head(c), lo, hi),
        9 => solve::<9, 10>(head(c), lo, hi),
        10 => solve::<10, 11>(head(c), lo, hi),
        11 => solve::<11, 12>(head(c), lo, hi),
        12 => solve::<12, 13>(head(c), lo, hi),
        13 => solve::<13, 14>(head(c), lo, hi),
        14 => solve::<14, 15>(head(c), lo, hi),
        15 => solve::<15, 16>(head(c), lo, hi),
        16 => solve::<16, 17>(head(c), lo, hi),
        _ => None,
    }
}

/// The first K entries of `a` as an array (K <= a.len()).
#[inline(always)]
fn head<const K: usize>(a: &[f64]) -> &[f64; K] {
    a[..K].try_into().expect("K <= a.len()")
}

/// Scaled coefficients a[0..=n], n >= 1: the first root in (lo, hi].
fn scaled_any(a: &[f64], n: usize, lo: f64, hi: f64) -> Option<f64> {
    match n {
        1 => scaled::<1, 2>(head(a), lo, hi),
        2 => scaled::<2, 3>(head(a), lo, hi),
        3 => scaled::<3, 4>(head(a), lo, hi),
        4 => scaled::<4, 5>(head(a), lo, hi),
        5 => scaled::<5, 6>(head(a), lo, hi),
        6 => scaled::<6, 7>(head(a), lo, hi),
        7 => scaled::<7, 8>(head(a), lo, hi),
        8 => scaled::<8, 9>(head(a), lo, hi),
        9 => scaled::<9, 10>(head(a), lo, hi),
        10 => scaled::<10, 11>(head(a), lo, hi),
        11 => scaled::<11, 12>(head(a), lo, hi),
        12 => scaled::<12, 13>(head(a), lo, hi),
        13 => scaled::<13, 14>(head(a), lo, hi),
        14 => scaled::<14, 15>(head(a), lo, hi),
        15 => scaled::<15, 16>(head(a), lo, hi),
        16 => scaled::<16, 17>(head(a), lo, hi),
        _ => None,
    }
}

/// `a[0..=n]` = `c[0..=n]` times the power of two putting m = max |c_i| in
/// [1, 2), given e = frexp_exp(m) (exact while the products stay normal).
#[inline(always)]
fn scale_pow2(c: &[f64], n: usize, e: i32, a: &mut [f64]) {
    let c = &c[..n + 1];
    let a = &mut a[..n + 1];
    let k = 1 - e;
    if k > 1000 {
        // two steps (2^k would overflow); k - 600 > 400 is normal
        let (g, f) = (pow2(600), pow2(k - 600));
        for i in 0..c.len() {
            a[i] = (c[i] * g) * f;
        }
    } else {
        // 2^k for k = -1023 is subnormal: build it as 2^-1022 / 2 (exact)
        let f = if k < -1022 { pow2(-1022) * 0.5 } else { pow2(k) };
        for i in 0..c.len() {
            a[i] = c[i] * f;
        }
    }
}

/// `scale_pow2`; returns the degree left after dropping top coefficients
/// that underflowed.
#[inline(always)]
fn scale_max(c: &[f64], mut n: usize, e: i32, a: &mut [f64]) -> Option<usize> {
    scale_pow2(c, n, e, a);
    loop {
        if a[n] != 0.0 {
            return Some(n);
        }
        if n == 0 {
            return None;
        }
        n -= 1;
    }
}

/// Smallest real root `t` of `c[0] + c[1] t + ... + c[n] t^n` with
/// `lo < t <= hi`, or `None` (also for NaN/inf input, `lo >= hi`, all-zero or
/// constant polynomials, and more than `MAX_DEGREE + 1` coefficients).
///
/// Inlined into the caller (also across crates: the simulator, generated
/// code, the benchmark) as far as the degree-2 fast path and the no-root test
/// of degrees 3 and 4; the rest is one out-of-line call.
#[inline]
pub fn smallest_root(c: &[f64], lo: f64, hi: f64) -> Option<f64> {
    if c.len() == 3 && (lo >= 0.0) & (c[0] * c[1] > 0.0) & (c[1] * c[2] > 0.0) {
        return None; // no sign change, at any magnitude (docs/roots.md step 1)
    }
    if c.len() == 3 && admit2(c[0], c[1], c[2], hi - lo) {
        // fast path: moderate coefficients give the same bits unscaled; lo < hi,
        // both finite, exactly when hi - lo is positive and finite (an overflow
        // only sends the call to the general path)
        return quadratic_fast(c[0], c[1], c[2], lo, hi);
    }
    if c.len() == 4 && (lo >= 0.0) & (hi >= TWO_M250) && no_root3(c, hi) {
        return None; // no root in [0, hi] (docs/roots.md step 1, "lo >= 0" (c))
    }
    if c.len() == 5 && (lo >= 0.0) & (hi >= TWO_M250) && no_root4(c, hi) {
        return None;
    }
    smallest_root_general(c, lo, hi)
}

/// Everything but the degree-2 fast path (out of line).
#[inline(never)]
fn smallest_root_general(c: &[f64], lo: f64, hi: f64) -> Option<f64> {
    let len = c.len();
    // hi - lo positive and finite: one unsigned comparison of its bits
    if (4..=9).contains(&len) && c[len - 1] != 0.0 && (hi - lo).to_bits().wrapping_sub(1) < 0x7fef_ffff_ffff_ffff {
        // degrees 3 to 8 (docs/roots.md step 1): nothing to strip, lo < hi
        // with both finite; that degree's copy of steps 4-7 at once (a NaN or
        // infinite coefficient answers none there)
        let x = match len {
            4 => solve::<3, 4>(head(c), lo, hi),
            5 => solve::<4, 5>(head(c), lo, hi),
            6 => solve::<5, 6>(head(c), lo, hi),
            7 => solve::<6, 7>(head(c), lo, hi),
            8 => solve::<7, 8>(head(c), lo, hi),
            _ => solve::<8, 9>(head(c), lo, hi),
        }?;
        return Some(x + 0.0);
    }
    if c.len() > N1 {
        return None;
    }
    if !(lo.is_finite() && hi.is_finite() && lo < hi) {
        return None;
    }
    // a NaN or infinity stops the search for the top nonzero coefficient, so it
    // stays in c[0..=n], whose finiteness the spread pass of `solve` tests
    let n = c.iter().rposition(|&v| v != 0.0)?;
    if n == 0 {
        return None;
    }
    let x = if n == 1 {
        if !(c[0].is_finite() && c[1].is_finite()) {
            return None;
        }
        // one correctly rounded division: no scaling needed
        let x = -c[0] / c[1];
        if !(lo < x && x <= hi) {
            return None;
        }
        x
    } else {
        dispatch(c, n, lo, hi)?
    };
    Some(x + 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_roots(roots: &[f64]) -> Vec<f64> {
        let mut c = vec![1.0];
        for &r in roots {
            let mut nxt = vec![0.0; c.len() + 1];
            for (i, &v) in c.iter().enumerate() {
                nxt[i + 1] += v;
                nxt[i] -= r * v;
            }
            c = nxt;
        }
        c
    }

    #[test]
    fn contract_edges() {
        assert_eq!(smallest_root(&[-0.5, 1.0], 0.0, 1.0), Some(0.5));
        assert_eq!(smallest_root(&[-1.0, 1.0], 0.0, 1.0), Some(1.0));
        assert_eq!(smallest_root(&[0.0, 1.0], 0.0, 1.0), None);
        assert_eq!(smallest_root(&[0.0, 0.0, 0.0], 0.0, 1.0), None);
        assert_eq!(smallest_root(&[], 0.0, 1.0), None);
        assert_eq!(smallest_root(&[2.0], 0.0, 1.0), None);
        assert_eq!(smallest_root(&[-0.5, 1.0, 0.0, -0.0], 0.0, 1.0), Some(0.5));
        assert_eq!(smallest_root(&[-0.5, 1.0], 1.0, 0.0), None);
        assert_eq!(smallest_root(&[-0.5, f64::NAN], 0.0, 1.0), None);
        assert_eq!(smallest_root(&[-0.5, 1.0], 0.0, f64::INFINITY), None);
        assert_eq!(smallest_root(&[1.0; 18], 0.0, 1.0), None);
    }

    #[test]
    fn touching_and_complex() {
        assert_eq!(smallest_root(&from_roots(&[0.5, 0.5]), 0.0, 1.0), Some(0.5));
        assert_eq!(smallest_root(&from_roots(&[0.5, 0.5, -3.0]), 0.0, 2.0), Some(0.5));
        assert_eq!(smallest_root(&from_roots(&[0.5, 0.5, 0.5, 5.0]), 0.0, 2.0), Some(0.5));
        let a = 2f64.powi(-10);
        assert_eq!(smallest_root(&[a * a + 1e-18, -2.0 * a, 1.0], 0.0, 1.0), None);
    }

    #[test]
    fn zero_is_positive() {
        let t = smallest_root(&[0.0, 1.0], -1.0, 1.0).unwrap();
        assert_eq!(t.to_bits(), 0);
    }

    #[test]
    fn scaling_is_exact() {
        let c = from_roots(&[0.2, 0.45, 0.9, 3.0]);
        let base = smallest_root(&c, 0.0, 1.0).unwrap();
        assert!((base - 0.2).abs() < 1e-15);
        for s in [2f64.powi(-1000), 2f64.powi(1000), 0.125, -8.0] {
            let cs: Vec<f64> = c.iter().map(|v| v * s).collect();
            assert_eq!(smallest_root(&cs, 0.0, 1.0), Some(base));
        }
    }

    #[test]
    fn spread_and_degree_16() {
        let c = from_roots(&[1e-6, 1e-3, 1.0, 1e3, 1e6]);
        let t = smallest_root(&c, 0.0, 1e7).unwrap();
        assert!((t - 1e-6).abs() < 1e-18);
        let rs: Vec<f64> = (1..=16).map(|k| 0.05 * k as f64).collect();
        let t = smallest_root(&from_roots(&rs), 0.0, 1.0).unwrap();
        assert!((t - 0.05).abs() < 1e-12);
    }

    #[test]
    fn ldexp_rounds_once() {
        assert_eq!(ldexp(1.0, -1074), 5e-324);
        assert_eq!(ldexp(1.5, -1075), 5e-324); // 0.75 of the smallest subnormal
        assert_eq!(ldexp(1.0, -1075), 0.0); // half of it: ties to even
        assert_eq!(ldexp(3.0, -1075).to_bits(), 2); // 1.5 ulp: ties to even
        assert_eq!(ldexp(5e-324, 1074), 1.0);
        assert_eq!(ldexp(f64::MAX, -2046).to_bits(), 4503599627370496); // rounds up to 2^-1022
        assert_eq!(ldexp(0.7500000000000001, -1073).to_bits(), 2); // values from C's ldexp
        assert_eq!(ldexp(1.0, 1023), 8.98846567431158e307);
        assert_eq!(ldexp(1.0, 1024), f64::INFINITY);
        assert_eq!(ldexp(-0.75, 3), -6.0);
        assert_eq!(ldexp(f64::MAX, -1023).to_bits(), 4611686018427387903);
    }

    #[test]
    fn any_magnitude() {
        // the classic scaled quartic: coefficients 1e-307 .. 1e1, roots 1e75 .. 1e80
        let c = from_roots(&[1e80, 1e77, 1e76, 1e75]).iter().map(|v| v * 1e-307).collect::<Vec<_>>();
        let t = smallest_root(&c, 0.0, 1e300).unwrap();
        assert!((t - 1e75).abs() < 1e63);
        let t = smallest_root(&c, 2e77, 1e300).unwrap();
        assert!((t - 1e80).abs() < 1e68);
        // roots +-1e-300 of 1e300 t^2 - 1e-300
        assert_eq!(smallest_root(&[-1e-300, 0.0, 1e300], 0.0, 1.0), Some(1e-300));
        assert_eq!(smallest_root(&[-1e-300, 0.0, 1e300], -1.0, 1.0), Some(-1e-300));
    }

    #[test]
    fn frexp_matches_c() {
        assert_eq!(frexp_exp(1.0), 1);
        assert_eq!(frexp_exp(0.75), 0);
        assert_eq!(frexp_exp(f64::MAX), 1024);
        assert_eq!(frexp_exp(5e-324), -1073);
        assert_eq!(frexp_exp(2.2250738585072014e-308), -1021);
    }
}
