//! rapier2d (f64) driver of the side-by-side benchmark (max2code/reports/peers.py).
//!
//! Reads a scene in the peer format on stdin (written by `peer_text` in
//! peers.py: the step, gravity, every body and the scripted inputs), steps it
//! at the given step with rapier's default integration parameters, and writes
//! after each step one line `s T CPU` (the time reached and the CPU seconds of
//! that step alone, CLOCK_PROCESS_CPUTIME_ID around the step call) and one
//! line per body `x y angle vx vy omega`.  Circles never turn (rotations
//! locked), as in the scene model; polygons get the scene's mass and moment
//! of inertia; restitution and friction combine by product; fixed bodies
//! that move or turn are kinematic (velocity based).
use rapier2d_f64::prelude::*;
use std::io::{self, BufWriter, Read, Write};

fn cpu_seconds() -> f64 {
    let mut ts = libc::timespec { tv_sec: 0, tv_nsec: 0 };
    unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

struct Words<'a>(std::str::SplitAsciiWhitespace<'a>);

impl<'a> Words<'a> {
    fn word(&mut self) -> &'a str {
        self.0.next().expect("peer scene: unexpected end")
    }
    fn f(&mut self) -> f64 {
        let w = self.word();
        w.parse().unwrap_or_else(|_| panic!("peer scene: not a number: {w}"))
    }
    fn n(&mut self) -> usize {
        let w = self.word();
        w.parse().unwrap_or_else(|_| panic!("peer scene: not a count: {w}"))
    }
    fn expect(&mut self, key: &str) {
        let w = self.word();
        assert!(w == key, "peer scene: expected {key}, got {w}");
    }
}

struct Input {
    time: f64,
    body: usize,
    mode: usize,
    x: f64,
    y: f64,
}

fn main() {
    let mut text = String::new();
    io::stdin().read_to_string(&mut text).expect("stdin");
    let mut w = Words(text.split_ascii_whitespace());
    w.expect("peer-scene");
    w.expect("end");
    let end = w.f();
    w.expect("dt");
    let dt = w.f();
    w.expect("substeps");
    let _substeps = w.n(); // Box2D's; rapier runs its own defaults
    w.expect("gravity");
    let gravity = Vector::new(w.f(), w.f());
    w.expect("bodies");
    let n = w.n();

    let mut world = PhysicsWorld::default();
    world.gravity = gravity;
    world.integration_parameters.dt = dt;
    let mut handles = Vec::with_capacity(n);
    let mut own_force: Vec<Option<Vector>> = Vec::with_capacity(n);
    let mut removed = vec![false; n];
    for _ in 0..n {
        let kind = w.word();
        let role = w.n(); // 0 movable, 1 fixed and still, 2 fixed and moving (kinematic)
        let fixed = role > 0;
        let mass = w.f();
        let inertia = w.f();
        let (px, py, vx, vy, ang, om) = (w.f(), w.f(), w.f(), w.f(), w.f(), w.f());
        let (e, mu, ax, ay) = (w.f(), w.f(), w.f(), w.f());
        let collider = match kind {
            "c" => {
                let (r, orad, oang) = (w.f(), w.f(), w.f());
                ColliderBuilder::ball(r).translation(Vector::new(orad * oang.cos(), orad * oang.sin()))
            }
            "p" => {
                let k = w.n();
                let pts: Vec<Vector> = (0..k).map(|_| Vector::new(w.f(), w.f())).collect();
                ColliderBuilder::convex_hull(&pts).expect("peer scene: polygon is not convex")
            }
            other => panic!("peer scene: unknown shape {other}"),
        };
        let collider = collider
            .density(0.0)
            .restitution(e)
            .friction(mu)
            .restitution_combine_rule(CoefficientCombineRule::Multiply)
            .friction_combine_rule(CoefficientCombineRule::Multiply);
        let builder = if fixed {
            if role == 2 {
                RigidBodyBuilder::kinematic_velocity_based()
            } else {
                RigidBodyBuilder::fixed()
            }
        } else if kind == "c" {
            RigidBodyBuilder::dynamic()
                .additional_mass_properties(MassProperties::new(Vector::ZERO, mass, 1.0))
                .lock_rotations()
        } else {
            RigidBodyBuilder::dynamic().additional_mass_properties(MassProperties::new(Vector::ZERO, mass, inertia))
        };
        let body = builder.translation(Vector::new(px, py)).rotation(ang).linvel(Vector::new(vx, vy)).angvel(om);
        let (h, _) = world.insert(body, collider);
        let g = gravity;
        own_force.push(if !fixed && (ax != g.x || ay != g.y) {
            Some(Vector::new((ax - g.x) * mass, (ay - g.y) * mass))
        } else {
            None
        });
        handles.push(h);
    }
    for (i, f) in own_force.iter().enumerate() {
        if let Some(f) = f {
            world.bodies[handles[i]].add_force(*f, true); // persistent until reset: the body's own acceleration
        }
    }
    w.expect("inputs");
    let m = w.n();
    let mut inputs: Vec<Input> = (0..m)
        .map(|_| Input { time: w.f(), body: w.n(), mode: w.n(), x: w.f(), y: w.f() })
        .collect();
    inputs.sort_by(|a, b| a.time.partial_cmp(&b.time).unwrap());

    let out = io::stdout();
    let mut out = BufWriter::with_capacity(1 << 20, out.lock());
    let steps = ((end / dt) - 1e-9).ceil().max(0.0) as usize;
    let mut next = 0;
    for k in 0..steps {
        let now = k as f64 * dt;
        while next < inputs.len() && inputs[next].time <= now + 1e-12 * dt {
            let inp = &inputs[next];
            next += 1;
            let h = handles[inp.body];
            if removed[inp.body] {
                continue;
            }
            match inp.mode {
                0 => world.bodies[h].set_linvel(Vector::new(inp.x, inp.y), true),
                1 => {
                    let v = world.bodies[h].linvel();
                    world.bodies[h].set_linvel(v + Vector::new(inp.x, inp.y), true)
                }
                2 => world.bodies[h].apply_impulse(Vector::new(inp.x, inp.y), true),
                3 => world.bodies[h].set_translation(Vector::new(inp.x, inp.y), true),
                _ => {
                    removed[inp.body] = true;
                    let pw = &mut world;
                    pw.bodies.remove(
                        h,
                        &mut pw.islands,
                        &mut pw.colliders,
                        &mut pw.impulse_joints,
                        &mut pw.multibody_joints,
                        &mut pw.soft_bodies,
                        true,
                    );
                }
            }
        }
        let c0 = cpu_seconds();
        world.step();
        let c1 = cpu_seconds();
        writeln!(out, "s {} {}", (k + 1) as f64 * dt, c1 - c0).unwrap();
        for (i, h) in handles.iter().enumerate() {
            if removed[i] {
                writeln!(out, "- - - - - -").unwrap();
                continue;
            }
            let b = &world.bodies[*h];
            let p = b.translation();
            let v = b.linvel();
            writeln!(out, "{} {} {} {} {} {}", p.x, p.y, b.rotation().angle(), v.x, v.y, b.angvel()).unwrap();
        }
    }
    out.flush().unwrap();
}
