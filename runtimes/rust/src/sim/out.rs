//! The flat trace (docs/simulator.md, "Flat trace"), buffered: one method
//! per kind of line, numbers written as `%.17g` ([`push_spaced_g17`]).  A world
//! without a trace has no sink: every method does nothing.

use std::fmt;
use std::io::{self, Write};

use super::g17::{eight_digit_values, push_spaced_g17, spaced_g17, ZEROS};
use super::scene::Body;

/// Why the simulator stopped or refused a call: a stuck or bad scene, or a
/// call outside what the world allows (the message of an `X` line), or a
/// trace that could not be written.
#[derive(Debug)]
pub enum SimError {
    Msg(String),
    Io(io::Error),
}

impl From<io::Error> for SimError {
    fn from(e: io::Error) -> SimError {
        SimError::Io(e)
    }
}

impl fmt::Display for SimError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SimError::Msg(msg) => f.write_str(msg),
            SimError::Io(e) => write!(f, "cannot write the trace: {e}"),
        }
    }
}

impl std::error::Error for SimError {}

pub type Res<T> = Result<T, SimError>;

/// Buffered trace output (none without a sink).
pub struct Out {
    buf: Vec<u8>,
    sink: Option<Box<dyn Write>>,
    /// The last time written by `time` (its bits), as ` %.17g` in
    /// `time_text[..time_len]` (`time_len` 0: none yet).
    time_bits: u64,
    time_len: usize,
    time_text: [u8; 48],
}

impl Out {
    pub fn new(sink: Option<Box<dyn Write>>) -> Out {
        let cap = if sink.is_some() { 1 << 17 } else { 0 };
        Out { buf: Vec::with_capacity(cap), sink, time_bits: 0, time_len: 0, time_text: [0; 48] }
    }

    /// No sink: nothing is written.
    #[inline(always)]
    fn off(&self) -> bool {
        self.sink.is_none()
    }

    #[inline]
    fn s(&mut self, text: &str) {
        self.buf.extend_from_slice(text.as_bytes());
    }

    #[inline]
    fn num(&mut self, x: f64) {
        push_spaced_g17(&mut self.buf, x);
    }

    /// ` T`, a time as `num` writes it.  A collision's E line and its two S
    /// lines write the same time (the bodies' tb is the event's t): the
    /// text of the last one is kept and copied while the bits are the same.
    #[inline]
    fn time(&mut self, t: f64) {
        let bits = t.to_bits();
        if self.time_len == 0 || bits != self.time_bits {
            self.time_len = spaced_g17(&mut self.time_text, t);
            self.time_bits = bits;
        }
        let at = self.buf.len();
        self.buf.extend_from_slice(&self.time_text[..32]);
        self.buf.truncate(at + self.time_len);
    }

    /// ` K` (an integer as `%d` writes it), built in a fixed buffer and
    /// appended as 24 bytes cut back to its length: a copy of variable
    /// length would be a call of memcpy (five per collision line).  From
    /// -9 to 9 (a collision's feature and vertices, -1 without) as 4
    /// constant bytes cut back, without the digit loop.
    #[inline(always)]
    fn int(&mut self, k: i64) {
        if (-9..=9).contains(&k) {
            let neg = k < 0;
            let digit = b'0' + k.unsigned_abs() as u8;
            let at = self.buf.len();
            self.buf.extend_from_slice(&if neg { [b' ', b'-', digit, b' '] } else { [b' ', digit, b' ', b' '] });
            self.buf.truncate(at + 2 + usize::from(neg));
        } else if k.unsigned_abs() < 100_000_000 {
            // the eight digits in one word, the first in its lowest byte:
            // the leading zeros shifted out, the rest cut off
            let neg = k < 0;
            let v = eight_digit_values(k.unsigned_abs() as u32);
            let lead = (v.trailing_zeros() / 8) as usize;
            let mut d = [b' '; 16];
            d[1] = b'-';
            let s = 1 + usize::from(neg);
            d[s..s + 8].copy_from_slice(&((v >> (8 * lead)) + ZEROS).to_le_bytes());
            let at = self.buf.len();
            self.buf.extend_from_slice(&d);
            self.buf.truncate(at + s + 8 - lead);
        } else {
            self.int_digits(k);
        }
    }

    /// `int` of any k, by its digits.
    #[inline(never)]
    fn int_digits(&mut self, k: i64) {
        let mut u = k.unsigned_abs();
        let mut digits = 1;
        let mut p = 10u64;
        while digits < 20 && u >= p {
            digits += 1;
            p = p.wrapping_mul(10);
        }
        let mut d = [b' '; 24];
        let neg = usize::from(k < 0);
        d[1] = b'-';
        let mut n = 1 + neg + digits;
        loop {
            n -= 1;
            d[n] = b'0' + (u % 10) as u8;
            u /= 10;
            if u == 0 {
                break;
            }
        }
        let at = self.buf.len();
        self.buf.extend_from_slice(&d);
        self.buf.truncate(at + 1 + neg + digits);
    }

    #[inline]
    fn end_line(&mut self) -> io::Result<()> {
        self.buf.push(b'\n');
        if self.buf.len() >= 1 << 16 {
            self.flush()?;
        }
        Ok(())
    }

    pub fn flush(&mut self) -> io::Result<()> {
        if let Some(sink) = self.sink.as_mut() {
            sink.write_all(&self.buf)?;
            self.buf.clear();
            sink.flush()?;
        }
        Ok(())
    }

    /// `E collision T A B FEATURE I J CX CY NX NY IMPULSE`, or `E support ...`
    /// with the same fields (`word`: "collision" or "support").
    #[allow(clippy::too_many_arguments)]
    pub fn contact(
        &mut self,
        word: &str,
        t: f64,
        a: u32,
        b: u32,
        feature: i32,
        i: i32,
        j: i32,
        c: (f64, f64),
        n: (f64, f64),
        impulse: f64,
    ) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("E ");
        self.s(word);
        self.time(t);
        self.int(i64::from(a));
        self.int(i64::from(b));
        self.int(i64::from(feature));
        self.int(i64::from(i));
        self.int(i64::from(j));
        self.num(c.0);
        self.num(c.1);
        self.num(n.0);
        self.num(n.1);
        self.num(impulse);
        self.end_line()
    }

    /// `E stop T A B -1 -1 J 0 0 0 0 0` or `E leave ...` (`word`): body a,
    /// supported by edge j of body b, stops sliding or leaves the edge.
    pub fn support_end(&mut self, word: &str, t: f64, a: u32, b: i32, j: i32) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("E ");
        self.s(word);
        self.num(t);
        self.int(i64::from(a));
        self.int(i64::from(b));
        self.s(" -1 -1");
        self.int(i64::from(j));
        self.s(" 0 0 0 0 0");
        self.end_line()
    }

    /// `E input T BODY -1 -1 K -1 0 0 0 0 0`
    pub fn input(&mut self, t: f64, body: u32, k: u32) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("E input");
        self.num(t);
        self.int(i64::from(body));
        self.s(" -1 -1");
        self.int(i64::from(k));
        self.s(" -1 0 0 0 0 0");
        self.end_line()
    }

    /// `E sleep T A G -1 -1 ISLAND 0 0 0 0 0`: body a falls asleep on g.
    pub fn sleep(&mut self, t: f64, a: u32, g: u32, island: i32) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("E sleep");
        self.num(t);
        self.int(i64::from(a));
        self.int(i64::from(g));
        self.s(" -1 -1");
        self.int(i64::from(island));
        self.s(" 0 0 0 0 0");
        self.end_line()
    }

    /// `E wake T S -1 -1 -1 ISLAND 0 0 0 0 0`: sleeper s wakes, with what rests on it.
    pub fn wake(&mut self, t: f64, s: u32, island: i32) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("E wake");
        self.num(t);
        self.int(i64::from(s));
        self.s(" -1 -1 -1");
        self.int(i64::from(island));
        self.s(" 0 0 0 0 0");
        self.end_line()
    }

    /// `E add T BODY -1 -1 -1 -1 0 0 0 0 0`: a body added to the world.
    pub fn add(&mut self, t: f64, body: u32) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("E add");
        self.num(t);
        self.int(i64::from(body));
        self.s(" -1 -1 -1 -1 0 0 0 0 0");
        self.end_line()
    }

    /// `E frame T -1 -1 -1 -1 -1 0 0 0 0 0`
    pub fn frame(&mut self, t: f64) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("E frame");
        self.num(t);
        self.s(" -1 -1 -1 -1 -1 0 0 0 0 0");
        self.end_line()
    }

    /// `S BODY TB PX PY VX VY ANGLE OMEGA AX AY`: a body's new state, with
    /// the acceleration from then on (the reference's emit_state).
    pub fn state(&mut self, b: &Body) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("S");
        self.int(i64::from(b.idx));
        self.time(b.tb);
        self.num(b.px);
        self.num(b.py);
        self.num(b.vx);
        self.num(b.vy);
        self.num(b.ang);
        self.num(b.om);
        self.num(b.ax);
        self.num(b.ay);
        self.end_line()
    }

    /// `F BODY PX PY VX VY ANGLE OMEGA`: a body at the end time.
    pub fn final_state(&mut self, b: &Body) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("F");
        self.int(i64::from(b.idx));
        self.num(b.px);
        self.num(b.py);
        self.num(b.vx);
        self.num(b.vy);
        self.num(b.ang);
        self.num(b.om);
        self.end_line()
    }

    /// `N NAME COUNT`
    pub fn stat(&mut self, name: &str, count: u64) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("N ");
        self.s(name);
        self.int(count as i64);
        self.end_line()
    }

    /// `V EQUATION INDEX COUNT`
    pub fn variant(&mut self, equation: &str, index: usize, count: u64) -> io::Result<()> {
        if self.off() {
            return Ok(());
        }
        self.s("V ");
        self.s(equation);
        self.int(index as i64);
        self.int(count as i64);
        self.end_line()
    }

    /// `X MESSAGE`: the run stopped on a stuck or bad scene.
    pub fn message(&mut self, msg: &str) {
        if self.off() {
            return;
        }
        self.s("X ");
        self.s(msg);
        self.buf.push(b'\n');
    }
}

impl Drop for Out {
    /// What is buffered reaches the sink (a live world's trace need not end).
    fn drop(&mut self) {
        let _ = self.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::super::g17::push_spaced_g17;
    use super::Out;

    #[test]
    fn time_writes_what_num_writes_also_when_kept() {
        let mut out = Out::new(None);
        let mut want = Vec::new();
        // repeats (kept text), a zero of either sign (the same as 0.0 in
        // ==, not in bits), lengths that shrink and grow
        for t in [0.5, 0.5, 0.0, -0.0, -0.0, 0.0, 1.0 / 3.0, 1.0 / 3.0, 2.0, 1e-300, 1e-300, 0.5] {
            out.time(t);
            push_spaced_g17(&mut want, t);
        }
        assert_eq!(String::from_utf8_lossy(&out.buf), String::from_utf8_lossy(&want));
    }

    #[test]
    fn int_writes_what_percent_d_writes() {
        let mut out = Out::new(None);
        let mut want = Vec::new();
        let mut x: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut values = vec![0i64, 1, -1, 9, 10, -10, 99, 100, 999_999, 1_000_000, i64::MAX, i64::MIN, i64::MIN + 1];
        for k in 0..19 {
            let p = 10i64.pow(k);
            values.extend([p - 1, p, p + 1, -p, -(p - 1)]);
        }
        for _ in 0..10_000 {
            x ^= x >> 12;
            x ^= x << 25;
            x ^= x >> 27;
            let v = x.wrapping_mul(0x2545_f491_4f6c_dd1d) as i64;
            values.extend([v, v >> (x % 64)]);
        }
        for &v in &values {
            out.int(v);
            want.extend_from_slice(format!(" {v}").as_bytes());
        }
        assert_eq!(String::from_utf8_lossy(&out.buf), String::from_utf8_lossy(&want));
    }
}
