//! parry2d's `cast_shapes_nonlinear` for two balls on rigid motions, in f32
//! and f64, as driven by bench/toi.py.
//!
//! stdin: "REPS" then rows of FIELDS numbers: for each body (1 then 2) the
//! rotation centre's x, y at t = 0, its velocity vx, vy, the angular
//! velocity, the ball's offset from the centre ox, oy at t = 0 and the
//! ball's radius; then the horizon.  stdout per row: "f64 T" and "f32 T"
//! (T the time of impact, "none" when there is none); then, when REPS > 0,
//! "ns f64 X" and "ns f32 X": the median over REPS passes of ns per query.
use std::io::Read;
use std::time::Instant;

/// Numbers per row: 2 bodies x (cx, cy, vx, vy, w, ox, oy, radius) + horizon.
const FIELDS: usize = 17;

macro_rules! caster {
    ($name:ident, $krate:ident, $real:ty) => {
        fn $name(r: &[f64]) -> Option<f64> {
            use $krate::math::{Isometry, Point, Vector};
            use $krate::query::{cast_shapes_nonlinear, NonlinearRigidMotion};
            use $krate::shape::Ball;
            let body = |k: usize| {
                let b = &r[8 * k..8 * k + 8];
                // the ball sits at centre + offset at t = 0 and turns about the centre
                let start = Isometry::translation((b[0] + b[5]) as $real, (b[1] + b[6]) as $real);
                let local_center = Point::new(-b[5] as $real, -b[6] as $real);
                let m = NonlinearRigidMotion::new(start, local_center, Vector::new(b[2] as $real, b[3] as $real), b[4] as $real);
                (m, Ball::new(b[7] as $real))
            };
            let (m1, s1) = body(0);
            let (m2, s2) = body(1);
            match cast_shapes_nonlinear(&m1, &s1, &m2, &s2, 0.0, r[16] as $real, true) {
                Ok(Some(hit)) => Some(hit.time_of_impact as f64),
                _ => None,
            }
        }
    };
}

caster!(toi64, parry2d_f64, f64);
caster!(toi32, parry2d, f32);

fn median_ns(rows: &[&[f64]], reps: usize, f: fn(&[f64]) -> Option<f64>) -> f64 {
    let mut times = Vec::with_capacity(reps);
    let mut sink = 0.0;
    for _ in 0..reps {
        let t0 = Instant::now();
        for r in rows {
            sink += std::hint::black_box(f(std::hint::black_box(r))).unwrap_or(0.0);
        }
        times.push(t0.elapsed().as_nanos() as f64 / rows.len() as f64);
    }
    eprintln!("checksum {sink}");
    times.sort_by(|a, b| a.partial_cmp(b).unwrap());
    times[reps / 2]
}

fn main() {
    let mut text = String::new();
    std::io::stdin().read_to_string(&mut text).expect("stdin");
    let mut it = text.split_whitespace();
    let reps: usize = it.next().and_then(|s| s.parse().ok()).unwrap_or(0);
    let v: Vec<f64> = it.map(|s| s.parse().expect("a number")).collect();
    let rows: Vec<&[f64]> = v.chunks_exact(FIELDS).collect();
    let show = |t: Option<f64>| t.map_or("none".to_string(), |t| format!("{t:e}"));
    for r in &rows {
        println!("f64 {}", show(toi64(r)));
        println!("f32 {}", show(toi32(r)));
    }
    if reps > 0 && !rows.is_empty() {
        println!("ns f64 {:.3}", median_ns(&rows, reps, toi64));
        println!("ns f32 {:.3}", median_ns(&rows, reps, toi32));
    }
}
