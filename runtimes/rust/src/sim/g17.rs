//! `%.17g` as C's printf and Python's `"%.17g" % x` write it, byte for byte.
//!
//! The 17 significant digits come from Rust's exact float formatting
//! (`{:.16e}`: correctly rounded, ties to even, as glibc and Python's dtoa);
//! this module only lays them out as `%g` does: exponent form when the
//! decimal exponent X is below -4 or at least 17 (with a sign and at least
//! two exponent digits), fixed form otherwise, trailing zeros and a trailing
//! point removed.

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

/// Append `x` formatted as `%.17g` to `out`.
pub fn push_g17(out: &mut Vec<u8>, x: f64) {
    if x.is_nan() {
        out.extend_from_slice(b"nan");
        return;
    }
    if x.is_infinite() {
        out.extend_from_slice(if x < 0.0 { b"-inf" } else { b"inf" });
        return;
    }
    let mut s = Small { buf: [0; 40], len: 0 };
    write!(s, "{:.16e}", x).expect("17 digits fit");
    let text = &s.buf[..s.len];
    // text: [-]D.DDDDDDDDDDDDDDDDe[-]X
    let (neg, body) = if text[0] == b'-' { (true, &text[1..]) } else { (false, text) };
    let mut digits = [0u8; 17];
    digits[0] = body[0];
    digits[1..].copy_from_slice(&body[2..18]);
    debug_assert_eq!(body[18], b'e');
    let mut exp: i32 = 0;
    let mut exp_neg = false;
    for &c in &body[19..] {
        if c == b'-' {
            exp_neg = true;
        } else {
            exp = exp * 10 + i32::from(c - b'0');
        }
    }
    if exp_neg {
        exp = -exp;
    }
    let mut nd = 17;
    while nd > 1 && digits[nd - 1] == b'0' {
        nd -= 1;
    }
    if neg {
        out.push(b'-');
    }
    if !(-4..17).contains(&exp) {
        out.push(digits[0]);
        if nd > 1 {
            out.push(b'.');
            out.extend_from_slice(&digits[1..nd]);
        }
        out.push(b'e');
        out.push(if exp < 0 { b'-' } else { b'+' });
        let a = exp.unsigned_abs();
        if a >= 100 {
            out.push(b'0' + (a / 100) as u8);
        }
        out.push(b'0' + (a / 10 % 10) as u8);
        out.push(b'0' + (a % 10) as u8);
    } else if exp >= 0 {
        let ip = exp as usize + 1;
        out.extend_from_slice(&digits[..ip]);
        if nd > ip {
            out.push(b'.');
            out.extend_from_slice(&digits[ip..nd]);
        }
    } else {
        out.extend_from_slice(b"0.");
        for _ in 0..(-exp - 1) {
            out.push(b'0');
        }
        out.extend_from_slice(&digits[..nd]);
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
    use super::g17;

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
            (9.999999999999999e22, "9.9999999999999992e+22"),
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
