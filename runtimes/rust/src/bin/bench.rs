//! Benchmark driver: `max2code_rt_bench REPS < wire lines`.  Polynomials are
//! grouped by degree; each group is solved REPS times in-process, each pass
//! timed with `Instant`.  Prints per degree:
//! "DEGREE MEDIAN_NS_PER_SOLVE FOUND CHECKSUM".
//!
//! The polynomials of a degree lie in one array, each with its coefficients
//! inline, as m2c_bench keeps them: a caller's loop over its own data, not a
//! pointer to chase per solve.
use std::collections::BTreeMap;
use std::io::{self, BufRead};
use std::time::Instant;

use max2code_rt::{smallest_root, MAX_DEGREE};

struct Poly {
    lo: f64,
    hi: f64,
    c: [f64; MAX_DEGREE + 1],
}

fn f(h: &str) -> f64 {
    f64::from_bits(u64::from_str_radix(h, 16).expect("hex double"))
}

/// One timed pass over the polynomials of degree `deg`: ns per solve, the
/// number found and the sum of the roots.  A function of its own, as in
/// m2c_bench, so that the loop is compiled as a caller's hot loop is.
#[inline(never)]
fn pass(polys: &[Poly], deg: usize) -> (f64, usize, f64) {
    let mut found = 0;
    let mut sum = 0.0;
    let t0 = Instant::now();
    for p in polys {
        if let Some(t) = smallest_root(&p.c[..deg + 1], p.lo, p.hi) {
            found += 1;
            sum += t;
        }
    }
    let ns = t0.elapsed().as_nanos() as f64 / polys.len() as f64;
    (ns, found, sum)
}

fn main() {
    let reps: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(21);
    let mut groups: BTreeMap<usize, Vec<Poly>> = BTreeMap::new();
    for line in io::stdin().lock().lines() {
        let line = line.expect("read stdin");
        let p: Vec<&str> = line.split_whitespace().collect();
        if p.len() < 5 {
            continue;
        }
        let count: usize = p[4].parse().expect("count");
        assert!((1..=MAX_DEGREE + 1).contains(&count), "coefficient count {count} outside 1..={}", MAX_DEGREE + 1);
        let mut c = [0.0f64; MAX_DEGREE + 1];
        for i in 0..count {
            c[i] = f(p[5 + i]);
        }
        groups.entry(count - 1).or_default().push(Poly { lo: f(p[2]), hi: f(p[3]), c });
    }
    for (deg, polys) in &groups {
        let mut times = Vec::with_capacity(reps);
        let mut found = 0;
        let mut sum = 0.0;
        for r in 0..=reps {
            let (ns, nf, s) = pass(polys, *deg);
            found = nf;
            sum = s;
            if r > 0 {
                times.push(ns);
            }
        }
        times.sort_by(|a, b| a.partial_cmp(b).unwrap());
        println!("{} {:.3} {} {:e}", deg, times[times.len() / 2], found, sum);
    }
}
