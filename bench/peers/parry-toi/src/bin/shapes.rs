//! parry2d's `cast_shapes_nonlinear` for two bodies, each a ball or a convex
//! polygon, moving with constant velocity and angular velocity, in f64 and
//! f32, as driven by bench/toi_shapes.py.
//!
//! stdin: "REPS" then one case per line: the horizon (s), then per body (A
//! then B): kind (0 ball, 1 polygon), the number of vertices n (0 for a
//! ball), the centre of rotation x, y (m) at t = 0, its velocity vx, vy
//! (m/s), the angle (rad) at t = 0, the angular velocity (rad/s), the
//! ball's radius (m; 0 for a polygon), then the n vertices x y (m, about
//! the centre of rotation, counter-clockwise).
//! stdout per case: "f64 A" and "f32 A", A the time of impact, "none" or
//! "overlapped" (parry reports the bodies penetrating at the start); when
//! REPS > 0 also "ns f64 X" and "ns f32 X": the median of 15 batches of
//! REPS queries, ns per query.
use std::io::Read;
use std::time::Instant;

struct Body {
    polygon: bool,
    x: f64,
    y: f64,
    vx: f64,
    vy: f64,
    angle: f64,
    omega: f64,
    radius: f64,
    vertices: Vec<(f64, f64)>,
}

struct Case {
    horizon: f64,
    a: Body,
    b: Body,
}

#[derive(Clone, Copy)]
enum Answer {
    Hit(f64),
    None,
    Overlapped,
    Refused,
}

macro_rules! caster {
    ($name:ident, $krate:ident, $real:ty) => {
        fn $name(c: &Case) -> Answer {
            use $krate::math::{Isometry, Point, Vector};
            use $krate::query::{cast_shapes_nonlinear, NonlinearRigidMotion, ShapeCastStatus};
            use $krate::shape::{Ball, ConvexPolygon, Shape};
            let motion = |b: &Body| {
                // the body's frame is its centre of rotation: it moves on its line and turns about itself
                let start = Isometry::new(Vector::new(b.x as $real, b.y as $real), b.angle as $real);
                NonlinearRigidMotion::new(start, Point::origin(), Vector::new(b.vx as $real, b.vy as $real),
                                          b.omega as $real)
            };
            let shape = |b: &Body| -> Option<Box<dyn Shape>> {
                if b.polygon {
                    let pts = b.vertices.iter().map(|&(x, y)| Point::new(x as $real, y as $real)).collect();
                    ConvexPolygon::from_convex_polyline(pts).map(|p| Box::new(p) as Box<dyn Shape>)
                } else {
                    Some(Box::new(Ball::new(b.radius as $real)))
                }
            };
            let (Some(s1), Some(s2)) = (shape(&c.a), shape(&c.b)) else { return Answer::Refused };
            match cast_shapes_nonlinear(&motion(&c.a), &*s1, &motion(&c.b), &*s2, 0.0, c.horizon as $real, true) {
                Ok(Some(hit)) if hit.status == ShapeCastStatus::PenetratingOrWithinTargetDist
                    && hit.time_of_impact == 0.0 => Answer::Overlapped,
                Ok(Some(hit)) => Answer::Hit(hit.time_of_impact as f64),
                Ok(None) => Answer::None,
                Err(_) => Answer::Refused,
            }
        }
    };
}

caster!(toi64, parry2d_f64, f64);
caster!(toi32, parry2d, f32);

fn median_ns(c: &Case, reps: usize, f: fn(&Case) -> Answer) -> f64 {
    let mut times = Vec::with_capacity(15);
    let mut sink = 0.0;
    for _ in 0..15 {
        let t0 = Instant::now();
        for _ in 0..reps {
            if let Answer::Hit(t) = f(std::hint::black_box(c)) {
                sink += t;
            }
        }
        times.push(t0.elapsed().as_nanos() as f64 / reps as f64);
    }
    std::hint::black_box(sink);
    times.sort_by(|a, b| a.partial_cmp(b).unwrap());
    times[times.len() / 2]
}

fn body(v: &mut impl Iterator<Item = f64>) -> Option<Body> {
    let kind = v.next()?;
    let n = v.next()? as usize;
    let mut b = Body { polygon: kind == 1.0, x: v.next()?, y: v.next()?, vx: v.next()?, vy: v.next()?,
                       angle: v.next()?, omega: v.next()?, radius: v.next()?, vertices: Vec::with_capacity(n) };
    for _ in 0..n {
        b.vertices.push((v.next()?, v.next()?));
    }
    Some(b)
}

fn main() {
    let mut text = String::new();
    std::io::stdin().read_to_string(&mut text).expect("stdin");
    let mut lines = text.lines();
    let reps: usize = lines.next().and_then(|s| s.trim().parse().ok()).unwrap_or(0);
    let show = |a: Answer| match a {
        Answer::Hit(t) => format!("{t:e}"),
        Answer::None => "none".to_string(),
        Answer::Overlapped => "overlapped".to_string(),
        Answer::Refused => "refused".to_string(),
    };
    for line in lines.filter(|l| !l.trim().is_empty()) {
        let mut v = line.split_whitespace().map(|s| s.parse::<f64>().expect("a number"));
        let horizon = v.next().expect("a horizon");
        let (Some(a), Some(b)) = (body(&mut v), body(&mut v)) else { panic!("a short case line") };
        let c = Case { horizon, a, b };
        println!("f64 {}", show(toi64(&c)));
        println!("f32 {}", show(toi32(&c)));
        if reps > 0 {
            println!("ns f64 {:.3}", median_ns(&c, reps, toi64));
            println!("ns f32 {:.3}", median_ns(&c, reps, toi32));
        }
    }
}
