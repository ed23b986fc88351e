//! Conformance testee: wire lines on stdin (docs/roots.md, "Conformance
//! suite"), answers on stdout.
use std::io::{self, BufRead, Write};

use max2code_rt::{smallest_root, MAX_DEGREE};

fn f(h: &str) -> Option<f64> {
    u64::from_str_radix(h, 16).ok().map(f64::from_bits)
}

fn answer(parts: &[&str]) -> String {
    let seq = parts[1];
    if parts[0] != "roots" {
        return format!("{seq} error unknown-op");
    }
    let parsed = (|| {
        let lo = f(parts.get(2)?)?;
        let hi = f(parts.get(3)?)?;
        let count: usize = parts.get(4)?.parse().ok()?;
        let c: Option<Vec<f64>> = (0..count).map(|i| parts.get(5 + i).and_then(|h| f(h))).collect();
        Some((lo, hi, c?))
    })();
    match parsed {
        None => format!("{seq} error malformed"),
        Some((_, _, c)) if c.len() > MAX_DEGREE + 1 => format!("{seq} error degree"),
        Some((lo, hi, c)) => match smallest_root(&c, lo, hi) {
            Some(t) => format!("{seq} {:016x}", t.to_bits()),
            None => format!("{seq} none"),
        },
    }
}

fn main() {
    let stdin = io::stdin();
    let stdout = io::stdout();
    let mut out = io::BufWriter::new(stdout.lock());
    for line in stdin.lock().lines() {
        let line = line.expect("read stdin");
        let parts: Vec<&str> = line.split_whitespace().collect();
        if parts.len() < 2 {
            continue;
        }
        writeln!(out, "{}", answer(&parts)).expect("write stdout");
    }
}
