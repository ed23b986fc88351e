//! Benchmark driver: `max2code_rt_bench REPS < wire lines`.  Polynomials are
//! grouped by degree; each group is solved REPS times in-process, each pass
//! timed with `Instant`.  Prints per degree:
//! "DEGREE MEDIAN_NS_PER_SOLVE FOUND CHECKSUM".
use std::collections::BTreeMap;
use std::hint::black_box;
use std::io::{self, BufRead};
use std::time::Instant;

use max2code_rt::smallest_root;

fn f(h: &str) -> f64 {
    f64::from_bits(u64::from_str_radix(h, 16).expect("hex double"))
}

fn main() {
    let reps: usize = std::env::args().nth(1).and_then(|s| s.parse().ok()).unwrap_or(21);
    let mut groups: BTreeMap<usize, Vec<(Vec<f64>, f64, f64)>> = BTreeMap::new();
    for line in io::stdin().lock().lines() {
        let line = line.expect("read stdin");
        let p: Vec<&str> = line.split_whitespace().collect();
        if p.len() < 5 {
            continue;
        }
        let count: usize = p[4].parse().expect("count");
        let c: Vec<f64> = (0..count).map(|i| f(p[5 + i])).collect();
        groups.entry(count - 1).or_default().push((c, f(p[2]), f(p[3])));
    }
    for (deg, polys) in &groups {
        let mut times = Vec::with_capacity(reps);
        let mut found = 0;
        let mut sum = 0.0;
        for r in 0..=reps {
            found = 0;
            sum = 0.0;
            let t0 = Instant::now();
            for (c, lo, hi) in polys {
                if let Some(t) = smallest_root(black_box(c), *lo, *hi) {
                    found += 1;
                    sum += t;
                }
            }
            let ns = t0.elapsed().as_nanos() as f64 / polys.len() as f64;
            if r > 0 {
                times.push(ns);
            }
        }
        times.sort_by(|a, b| a.partial_cmp(b).unwrap());
        println!("{} {:.3} {} {:e}", deg, times[times.len() / 2], found, sum);
    }
}
