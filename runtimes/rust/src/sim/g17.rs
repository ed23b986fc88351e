//! `%.17g` as C's printf and Python's `"%.17g" % x` write it, byte for byte.
//!
//! The 17 significant digits are the correctly rounded ones (ties to even,
//! as glibc's printf and Python's dtoa): for most magnitudes exactly from
//! integer arithmetic (`digits_fast`: x 10^p = m 5^p 2^(e+p), one 64 x 64
//! bit product and a shift where 5^p fits 64 bits, else 128-bit
//! arithmetic), otherwise from Rust's exact float formatting (`{:.16e}`).
//! They are laid out as `%g` does: exponent form when the decimal exponent
//! X is below -4 or at least 17 (with a sign and at least two exponent
//! digits), fixed form otherwise, trailing zeros and a trailing point
//! removed.  The fixed form is built with copies of constant size (no loop
//! per digit) and appended as 32 bytes cut back to its length, so that no
//! copy of variable length (a call of memcpy) is made per number.

use std::fmt::Write;

/// A fixed buffer that `write!` can fill (no allocation).
struct Small {
    buf: [u8; 40],
    len: usize,
}

impl Write for Small {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        let b = s.as_bytes();
        let end = self.len + b.len();
        if end > self.buf.len() {
            return Err(std::fmt::Error);
        }
        self.buf[self.len..end].copy_from_slice(b);
        self.len = end;
        Ok(())
    }
}

/// 10^k for 0 <= k <= 38 (exact in u128).
const fn pow10_table() -> [u128; 39] {
    let mut t = [1u128; 39];
    let mut k = 1;
    while k < 39 {
        t[k] = t[k - 1] * 10;
        k += 1;
    }
    t
}
const POW10: [u128; 39] = pow10_table();

/// 5^k shifted left until its top bit is set, and that shift, for
/// 0 <= k <= 27 (5^27 < 2^63).
const fn pow5_table() -> ([u64; 28], [u32; 28]) {
    let (mut f, mut z) = ([0u64; 28], [0u32; 28]);
    let mut p = 1u64;
    let mut k = 0;
    while k < 28 {
        if k > 0 {
            p *= 5; // 5^k, at most 5^27: no overflow
        }
        z[k] = p.leading_zeros();
        f[k] = p << z[k];
        k += 1;
    }
    (f, z)
}
const POW5: ([u64; 28], [u32; 28]) = pow5_table();
const D16: u64 = 10_000_000_000_000_000; // 10^16
const D17: u64 = 100_000_000_000_000_000; // 10^17

/// 10^k for -60 <= k <= 60, correctly rounded (for a first guess of the
/// decimal exponent only).
const POW10F_MIN: i32 = 60;
#[rustfmt::skip]
const POW10F: [f64; 121] = [1e-60, 1e-59, 1e-58, 1e-57, 1e-56, 1e-55, 1e-54, 1e-53, 1e-52, 1e-51, 1e-50, 1e-49, 1e-48, 1e-47, 1e-46, 1e-45, 1e-44, 1e-43, 1e-42, 1e-41, 1e-40, 1e-39, 1e-38, 1e-37, 1e-36, 1e-35, 1e-34, 1e-33, 1e-32, 1e-31, 1e-30, 1e-29, 1e-28, 1e-27, 1e-26, 1e-25, 1e-24, 1e-23, 1e-22, 1e-21, 1e-20, 1e-19, 1e-18, 1e-17, 1e-16, 1e-15, 1e-14, 1e-13, 1e-12, 1e-11, 1e-10, 1e-9, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22, 1e23, 1e24, 1e25, 1e26, 1e27, 1e28, 1e29, 1e30, 1e31, 1e32, 1e33, 1e34, 1e35, 1e36, 1e37, 1e38, 1e39, 1e40, 1e41, 1e42, 1e43, 1e44, 1e45, 1e46, 1e47, 1e48, 1e49, 1e50, 1e51, 1e52, 1e53, 1e54, 1e55, 1e56, 1e57, 1e58, 1e59, 1e60];

/// x < 10^8 as its eight decimal digits' values, the first in the lowest
/// byte: split into two 4-digit lanes of 32 bits, each into two 2-digit
/// lanes of 16 bits, each into two digits, every lane at once (the
/// divisions by 100 and 10 as products: floor(v 10486 / 2^20) = v / 100
/// for v < 10^4, floor(v 103 / 2^10) = v / 10 for v < 100, and no lane's
/// product reaches the next lane).
#[inline(always)]
pub(super) fn eight_digit_values(x: u32) -> u64 {
    let v = u64::from(x / 10_000) | (u64::from(x % 10_000) << 32);
    let h = ((v * 10_486) >> 20) & 0x0000_007f_0000_007f;
    let v = h | ((v - h * 100) << 16);
    let t = ((v * 103) >> 10) & 0x000f_000f_000f_000f;
    t | ((v - t * 10) << 8)
}

/// '0' in every byte.
pub(super) const ZEROS: u64 = 0x3030_3030_3030_3030;

/// floor(m 2^e 10^p) and whether rounding to nearest (ties to even) goes
/// up, exactly; None when the intermediate values would not fit 128 bits.
#[inline]
fn scaled(m: u64, e: i32, p: i32) -> Option<(u128, bool)> {
    let m = u128::from(m);
    let (q, round_up) = if p >= 0 {
        if p > 22 {
            return None;
        }
        let n = m * POW10[p as usize];
        if e >= 0 {
            if e > 20 {
                return None;
            }
            (n << e, false)
        } else {
            let sh = -e;
            if sh > 127 {
                return None;
            }
            let q = n >> sh;
            let r = n - (q << sh);
            let half = 1u128 << (sh - 1);
            (q, r > half || (r == half && q & 1 == 1))
        }
    } else {
        if !(0..=74).contains(&e) || -p > 38 {
            return None;
        }
        let n = m << e;
        let den = POW10[(-p) as usize];
        let q = n / den;
        let r = n - q * den;
        (q, 2 * r > den || (2 * r == den && q & 1 == 1))
    };
    Some((q, round_up))
}

/// `scaled` for the few numbers `scaled5` does not cover, kept out of
/// line: inlined, its 128-bit shifts would be prepared (about 25
/// instructions) before every number, also those that never need them.  A floor of
/// 10^17 or more is given as 10^17 (the caller only compares it with
/// 10^16 and 10^17), so that the caller's loop compares 64-bit words.
#[cold]
#[inline(never)]
fn scaled_slow(m: u64, e: i32, p: i32) -> Option<(u64, bool)> {
    let (q, up) = scaled(m, e, p)?;
    Some((q.min(u128::from(D17)) as u64, up))
}

/// floor(m 5^p 2^s) and whether rounding to nearest (ties to even) goes
/// up, for 0 <= p <= 27, from one 64 x 64 bit product: m 5^p 2^s =
/// (m 2^11)(5^p 2^z) 2^(s - 11 - z) with both factors' top bits set, so the
/// product has 127 or 128 bits and the digits (under 2^57) are its high
/// word shifted right by k = 11 + z - s - 64; None when k is not in 1..=63
/// (x too large or too small for p).
#[inline(always)]
fn scaled5(m: u64, p: usize, s: i32) -> Option<(u64, bool)> {
    let (f, z) = (POW5.0[p], POW5.1[p]);
    let k = 11 + z as i32 - s - 64;
    if !(1..=63).contains(&k) {
        return None;
    }
    let n = u128::from(m << 11) * u128::from(f);
    let (hi, lo) = ((n >> 64) as u64, n as u64);
    let q = hi >> k;
    let r = hi & ((1u64 << k) - 1);
    let half = 1u64 << (k - 1);
    Some((q, r > half || (r == half && (lo != 0 || q & 1 == 1))))
}

/// The 17 correctly rounded significant digits of finite nonzero |x| as an
/// integer in [10^16, 10^17), and the decimal exponent X of the first
/// digit; None when outside the range the 128-bit arithmetic covers.
/// Always inlined: as a call of its own it would cost about 20 instructions
/// per number (saved registers, the result through memory).
#[inline(always)]
fn digits_fast(x: f64) -> Option<(u64, i32)> {
    let bits = x.to_bits();
    let field = ((bits >> 52) & 0x7ff) as i32;
    let frac = bits & ((1u64 << 52) - 1);
    let (m, e) = if field == 0 { (frac, -1074) } else { (frac | (1u64 << 52), field - 1075) };
    if m == 0 {
        return None;
    }
    // floor(log2 |x|), then a decimal exponent estimate that is X or X + 1
    let l2 = 63 - m.leading_zeros() as i32 + e;
    let mut xe = (((i64::from(l2) + 1) * 78913) >> 18) as i32; // floor((l2 + 1) log10 2)

    // which of the two: a guess from the powers of ten (the digits decide exactly)
    if (-POW10F_MIN + 1..=POW10F_MIN).contains(&xe) && x.abs() < POW10F[(xe + POW10F_MIN) as usize] {
        xe -= 1;
    }
    for _ in 0..3 {
        let p = 16 - xe;
        let s = e + p; // x 10^p = m 5^p 2^s
        let fast = if (0..=27).contains(&p) { scaled5(m, p as usize, s) } else { None };
        let (q, up) = match fast {
            Some(v) => v,
            None => scaled_slow(m, e, p)?,
        };
        if q >= D17 {
            xe += 1;
        } else if q < D16 {
            xe -= 1;
        } else {
            let d = q + u64::from(up);
            // rounding up to 10^17 is 1.0000000000000000 10^(X + 1)
            return Some(if d == D17 { (D16, xe + 1) } else { (d, xe) });
        }
    }
    None
}

/// The 17 digits as an integer in [10^16, 10^17) and the decimal exponent,
/// from Rust's exact formatting (any finite nonzero x).
fn digits_fmt(x: f64) -> (u64, i32) {
    let mut s = Small { buf: [0; 40], len: 0 };
    write!(s, "{:.16e}", x.abs()).expect("17 digits fit");
    let body = &s.buf[..s.len];
    // body: D.DDDDDDDDDDDDDDDDe[-]X
    debug_assert_eq!(body[18], b'e');
    let mut d = u64::from(body[0] - b'0');
    for &c in &body[2..18] {
        d = d * 10 + u64::from(c - b'0');
    }
    let mut exp: i32 = 0;
    let mut exp_neg = false;
    for &c in &body[19..] {
        if c == b'-' {
            exp_neg = true;
        } else {
            exp = exp * 10 + i32::from(c - b'0');
        }
    }
    (d, if exp_neg { -exp } else { exp })
}

/// Append `x` formatted as `%.17g` to `out`.
pub fn push_g17(out: &mut Vec<u8>, x: f64) {
    push_g17_at(out, x, true, false);
}

/// Append a space and `x` formatted as `%.17g` to `out` (a trace's number
/// field): one copy of constant size for both, where pushing the space
/// and then the number would each check the capacity and move the length.
/// A zero (a third of a gas's numbers: the accelerations) is written here,
/// inlined into the caller, as 4 constant bytes cut back to " 0" or " -0";
/// through the whole writer it would take about 45 instructions.
#[inline(always)]
pub fn push_spaced_g17(out: &mut Vec<u8>, x: f64) {
    if x == 0.0 {
        let neg = x.is_sign_negative();
        let at = out.len();
        out.extend_from_slice(if neg { b" -0 " } else { b" 0  " });
        out.truncate(at + 2 + usize::from(neg));
    } else {
        push_spaced_g17_written(out, x);
    }
}

#[inline(never)]
fn push_spaced_g17_written(out: &mut Vec<u8>, x: f64) {
    push_g17_at(out, x, true, true);
}

/// A space and `x` formatted as `%.17g` in `line` (at most 26 bytes); the
/// length.
#[inline(never)]
pub fn spaced_g17(line: &mut [u8; 48], x: f64) -> usize {
    line[0] = b' ';
    write_g17(line, 1, x, true)
}

#[cfg(test)]
fn push_g17_with(out: &mut Vec<u8>, x: f64, fast: bool) {
    push_g17_at(out, x, fast, false);
}

/// The text (after a space when `space`) is built in a fixed buffer and
/// appended as 32 bytes cut back to its length, so that no copy of
/// variable length (a call of memcpy) is made per number.
#[inline(always)]
fn push_g17_at(out: &mut Vec<u8>, x: f64, fast: bool, space: bool) {
    // at most 26 bytes: the space, the sign, then "0.000" and 17 digits or
    // d.16 digits e-XXX; room up to 48 for the copies of constant size
    let mut line = [0u8; 48];
    line[0] = b' ';
    let n = write_g17(&mut line, usize::from(space), x, fast);
    let at = out.len();
    out.extend_from_slice(&line[..32]);
    out.truncate(at + n);
}

/// Write `x` as `%.17g` into `line` from `start` (at most 2); the end.
#[inline(always)]
fn write_g17(line: &mut [u8; 48], start: usize, x: f64, fast: bool) -> usize {
    let neg = x.is_sign_negative();
    line[start] = b'-';
    let s = start + usize::from(neg);
    if x == 0.0 {
        // zeros are a third of a gas's numbers (the accelerations)
        line[s] = b'0';
        return s + 1;
    }
    if !x.is_finite() {
        if x.is_nan() {
            // no sign on a NaN, as Python writes it
            line[start..start + 3].copy_from_slice(b"nan");
            return start + 3;
        }
        line[s..s + 3].copy_from_slice(b"inf");
        return s + 3;
    }
    let (d, exp) = match if fast { digits_fast(x) } else { None } {
        Some(v) => v,
        None => digits_fmt(x),
    };
    // the 17 digits (the first, then two words of eight), then room for the
    // copies of constant size below
    let hi = (d / 100_000_000) as u32; // 9 digits
    let (w1, w2) = (eight_digit_values(hi % 100_000_000), eight_digit_values((d % 100_000_000) as u32));
    let mut dg = [0u8; 40];
    dg[0] = b'0' + (hi / 100_000_000) as u8;
    dg[1..9].copy_from_slice(&(w1 + ZEROS).to_le_bytes());
    dg[9..17].copy_from_slice(&(w2 + ZEROS).to_le_bytes());
    // the last digit that is not a trailing zero: the highest byte that is
    // not 0 (d >= 10^16: the first digit is not)
    let last = if w2 != 0 {
        9 + (63 - w2.leading_zeros()) as usize / 8
    } else if w1 != 0 {
        1 + (63 - w1.leading_zeros()) as usize / 8
    } else {
        0
    };
    if (0..17).contains(&exp) {
        // the whole part (digits 0..=X), the point, the fraction (digits X+1..=last)
        let xe = exp as usize;
        line[s..s + 17].copy_from_slice(&dg[..17]);
        line[s + xe + 1] = b'.';
        line[s + xe + 2..s + xe + 18].copy_from_slice(&dg[xe + 1..xe + 17]);
        s + if last > xe { last + 2 } else { xe + 1 }
    } else if (-4..0).contains(&exp) {
        // "0." and -X-1 zeros, then the digits
        let zeros = (-exp) as usize;
        line[s..s + 6].copy_from_slice(b"0.0000");
        line[s + 1 + zeros..s + 18 + zeros].copy_from_slice(&dg[..17]);
        s + 2 + zeros + last
    } else {
        let mut n = s;
        let mut put = |bytes: &[u8]| {
            line[n..n + bytes.len()].copy_from_slice(bytes);
            n += bytes.len();
        };
        put(&dg[..1]);
        if last > 0 {
            put(b".");
            put(&dg[1..=last]);
        }
        put(if exp < 0 { b"e-" } else { b"e+" });
        let a = exp.unsigned_abs();
        if a >= 100 {
            put(&[b'0' + (a / 100) as u8]);
        }
        put(&[b'0' + (a / 10 % 10) as u8, b'0' + (a % 10) as u8]);
        n
    }
}

/// `x` formatted as `%.17g`.
pub fn g17(x: f64) -> String {
    let mut v = Vec::with_capacity(32);
    push_g17(&mut v, x);
    String::from_utf8(v).expect("ASCII")
}

#[cfg(test)]
mod tests {
    use super::{g17, push_g17_with, push_spaced_g17};
    use std::os::raw::{c_char, c_int};

    fn both(x: f64) -> (Vec<u8>, Vec<u8>) {
        let (mut a, mut b) = (Vec::new(), Vec::new());
        push_g17_with(&mut a, x, true);
        push_g17_with(&mut b, x, false);
        (a, b)
    }

    /// xorshift64*: reproducible bits without a dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
    }

    #[test]
    fn fast_digits_agree_with_exact_formatting() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let check = |x: f64| {
            let (a, b) = both(x);
            assert_eq!(a, b, "{x:e} ({:#x})", x.to_bits());
        };
        for _ in 0..300_000 {
            // any bits, and magnitudes a trace holds (1e-9 .. 1e9)
            check(f64::from_bits(rng.next()));
            let u = (rng.next() >> 11) as f64 / (1u64 << 53) as f64;
            check((u * 41.4 - 20.7).exp() * if rng.next() & 1 == 1 { 1.0 } else { -1.0 });
        }
        // ties at the 17th digit (small odd multiples of powers of two),
        // powers of ten and their neighbours, integers
        for k in 0..120 {
            for m in [1u64, 3, 5, 7, 9, 11, 13, 25, 99, 12345] {
                check(m as f64 * 2f64.powi(-k));
                check(m as f64 * 2f64.powi(k));
            }
        }
        for k in -30..40 {
            let p = 10f64.powi(k);
            check(p);
            check(f64::from_bits(p.to_bits() + 1));
            check(f64::from_bits(p.to_bits() - 1));
        }
        for i in 0..100_000u64 {
            check(i as f64);
            check((1u64 << 53) as f64 - i as f64);
            check(1e17 + (i * 16) as f64);
        }
    }

    extern "C" {
        /// The C library's snprintf: the definition of the bytes `push_g17` writes.
        fn snprintf(buf: *mut c_char, n: usize, fmt: *const c_char, ...) -> c_int;
    }

    /// printf("%.17g", x), but "nan" for every NaN (as Python and the
    /// simulators write it; glibc writes "-nan" for a negative one).
    fn printf_g17(x: f64) -> Vec<u8> {
        if x.is_nan() {
            return b"nan".to_vec();
        }
        let mut buf = [0u8; 64];
        // SAFETY: buf has 64 bytes and snprintf writes at most that many, its
        // NUL included; the format is a NUL-terminated literal taking one double.
        let n = unsafe { snprintf(buf.as_mut_ptr().cast(), buf.len(), c"%.17g".as_ptr(), x) };
        buf[..usize::try_from(n).expect("snprintf formats a double")].to_vec()
    }

    /// The k-th number of the check: every class by turns.
    fn sample(rng: &mut Rng, k: u64) -> f64 {
        let u = rng.next();
        let sign = if u & 1 == 1 { -1.0 } else { 1.0 };
        match k % 8 {
            // any bit pattern (NaNs and infinities included)
            0 => f64::from_bits(u),
            // decimals with few digits
            1 => (u % 2_000_001) as f64 / 1000.0 - 1000.0,
            // 53-bit mantissas, exponents -253..+46
            2 => (u >> 11) as f64 * 2f64.powi((rng.next() % 300) as i32 - 253),
            // integers
            3 => (u >> 12) as f64 * sign,
            // the magnitudes of a simulation, 1e-20 .. 1e20
            4 => ((u >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 10f64.powi((rng.next() % 40) as i32 - 20),
            // subnormals
            5 => f64::from_bits((u & ((1u64 << 52) - 1)) | (u & (1u64 << 63))),
            // powers of ten and their neighbours, 1e-323 .. 1e308
            6 => {
                let p: f64 = format!("1e{}", (rng.next() % 632) as i32 - 323).parse().expect("a power of ten");
                f64::from_bits((p.to_bits() + (u >> 1) % 5).saturating_sub(2)) * sign
            }
            // zeros, ties at the 17th digit (small odd multiples of powers of two), the extremes
            _ => match u % 6 {
                0 => 0.0 * sign,
                1 => (((u >> 8) % 4096) * 2 + 1) as f64 * 2f64.powi(((u >> 20) % 240) as i32 - 120),
                2 => f64::MAX * sign,
                3 => f64::MIN_POSITIVE * sign,
                4 => 5e-324 * sign,
                _ => f64::EPSILON * sign,
            },
        }
    }

    /// The written bytes are printf's on random doubles of every class;
    /// `M2C_G17_CHECK=N` checks N numbers instead of the default 10^6
    /// (docs/throughput.md names runs of 2 10^7).
    #[test]
    fn writes_what_printf_writes() {
        let n: u64 = std::env::var("M2C_G17_CHECK").ok().and_then(|v| v.parse().ok()).unwrap_or(1_000_000);
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        let (mut bad, mut mine) = (0u64, Vec::with_capacity(64));
        for k in 0..n {
            let x = sample(&mut rng, k);
            mine.clear();
            push_g17_with(&mut mine, x, true);
            let want = printf_g17(x);
            if mine != want {
                if bad < 10 {
                    eprintln!(
                        "{x:e} ({:#x}): {} printf {}",
                        x.to_bits(),
                        String::from_utf8_lossy(&mine),
                        String::from_utf8_lossy(&want)
                    );
                }
                bad += 1;
            }
        }
        eprintln!("{bad} of {n} numbers differ from printf(\"%.17g\")");
        assert_eq!(bad, 0);
    }

    /// A trace's field is a space and then the same bytes.
    #[test]
    fn spaced_is_a_space_and_the_number() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let (mut spaced, mut plain) = (Vec::new(), Vec::new());
        for k in 0..200_000 {
            let x = sample(&mut rng, k);
            spaced.clear();
            plain.clear();
            push_spaced_g17(&mut spaced, x);
            push_g17_with(&mut plain, x, true);
            assert_eq!(spaced[0], b' ', "{x:e}");
            assert_eq!(&spaced[1..], &plain[..], "{x:e}");
        }
    }

    #[test]
    fn eight_digit_values_are_the_digits() {
        for x in (0..100_000u32).chain((0..100_000_000).step_by(997)).chain(99_990_000..100_000_000) {
            let mut want = x;
            let w = super::eight_digit_values(x);
            for k in (0..8).rev() {
                assert_eq!((w >> (8 * k)) & 0xff, u64::from(want % 10), "{x}");
                want /= 10;
            }
        }
    }

    #[test]
    fn python_vectors() {
        // expected strings from Python 3: "%.17g" % x
        let cases: &[(f64, &str)] = &[
            (0.0, "0"),
            (-0.0, "-0"),
            (3.0, "3"),
            (-3.0, "-3"),
            (0.1, "0.10000000000000001"),
            (1e-5, "1.0000000000000001e-05"),
            (1e-4, "0.0001"),
            (0.00012345, "0.00012344999999999999"),
            (1e16, "10000000000000000"),
            (1e17, "1e+17"),
            (123456789012345678.0, "1.2345678901234568e+17"),
            (1.5, "1.5"),
            (2.5e-300, "2.5e-300"),
            (1e300, "1.0000000000000001e+300"),
            (f64::MAX, "1.7976931348623157e+308"),
            (f64::MIN_POSITIVE, "2.2250738585072014e-308"),
            (5e-324, "4.9406564584124654e-324"),
            (2f64.powi(-25), "2.9802322387695312e-08"),
            (3.0 * 2f64.powi(-25), "8.9406967163085938e-08"),
            (1e23, "9.9999999999999992e+22"),
            (0.5, "0.5"),
            (100.0, "100"),
            (-1.0 / 3.0, "-0.33333333333333331"),
            (f64::INFINITY, "inf"),
            (f64::NEG_INFINITY, "-inf"),
            (f64::NAN, "nan"),
        ];
        for &(x, want) in cases {
            assert_eq!(g17(x), want, "{x:e}");
        }
    }
}
