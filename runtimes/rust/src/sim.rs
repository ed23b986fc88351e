//! The discrete-event simulator (docs/simulator.md), a port of the
//! reference runtimes/python/max2code_rt/sim/ that performs the same IEEE
//! double operations in the same order, so that it writes the same bytes.
//!
//! The crate cannot depend on generated code: the simulator is generic over
//! [`Equations`], which a small binary implements with the generated entries
//! of equations/circle-circle.mxm and equations/point-edge.mxm
//! ([`sim_main!`](crate::sim_main) writes that binary's `main`).  Every
//! prediction goes through those entries and through the runtime's root
//! solver [`smallest_root`](crate::roots::smallest_root).
//!
//! The simulator is a live [`World`] (docs/engine-api.md): made from a
//! scene, driven by `advance(t)`, asked `next_event_time()` and
//! `state(body, t)`; the batch simulator program is a thin user of it.
//!
//! One module per concept, as the C runtime's m2c_sim_*.c: `scene` (the
//! flat scene), `queue` (event records and the priority queue), `grid`
//! (broad phase), `huge` (huge pages for the large arrays), `motion`,
//! `predict` (pairs, features, cell crossings), `contact` (contact frame
//! and impulse), `cluster` (simultaneous contacts solved together),
//! `support` (resting and sliding, when a body is carried), `sleep` (when
//! a body falls asleep), `overlap` (a teleport's or an added body's
//! check), `world` (what a prediction reads and writes), `live` (the
//! world's API), `handlers` (one handler per event kind and their
//! dispatch, carried bodies leaving), `out` and `g17`
//! (the trace and its numbers).
//!
//! Operation order: each expression is written as Python evaluates it (left
//! to right, the same parentheses); Python's `min(a, b)` is `b < a ? b : a`
//! and `max(a, b)` is `b > a ? b : a`; sin, cos come from libm as Python's
//! math module takes them (LLVM may fuse the sin and cos of one argument
//! into glibc's sincos, which returns the same bits; a vertex keeps cos and
//! sin of the last argument asked); Rust never contracts to FMA.

// written as the Python reference reads: `x = x + y` (the same operation as
// `x += y`), `!(w > 0.0)` (true for NaN, as `not (w > 0.0)` in Python)
#![allow(clippy::assign_op_pattern, clippy::neg_cmp_op_on_partial_ord)]

use std::io::{self, Read, Write};

use crate::roots::MAX_DEGREE;

mod cluster;
pub(crate) mod contact;
mod g17;
mod grid;
mod handlers;
mod huge;
mod live;
pub(crate) mod motion;
mod out;
pub(crate) mod overlap;
pub(crate) mod predict;
mod queue;
pub(crate) mod scene;
mod sleep;
mod support;
mod world;

pub use g17::{g17, push_g17};
pub use live::{BodyState, Contact, World};
pub use out::SimError;
pub use scene::{
    Body, CosSin, Input, Scene, Vertex, ADD_VELOCITY, IMPULSE, LENGTH_MAX, LENGTH_MIN, MAX_BODIES, MAX_INPUTS,
    MAX_TEXT, MAX_VERTICES, REMOVE, SET_VELOCITY, TELEPORT,
};

/// pi/2 rounded to double (cos x = sin(x + pi/2)).
pub const HALF_PI: f64 = std::f64::consts::FRAC_PI_2;

/// Room for the coefficients of any generated variant.
pub const MAX_COEF: usize = MAX_DEGREE + 1;

/// The generated entries the simulator predicts with (see [`sim_main!`](crate::sim_main)).
pub trait Equations {
    /// Number of variants `cc_variant` counts (`CIRCLE_CIRCLE_VARIANT_NAMES.len()`).
    const CC_VARIANTS: usize;
    /// Number of variants `pe_variant` counts (`POINT_EDGE_VARIANT_NAMES.len()`).
    const PE_VARIANTS: usize;
    /// `circle_circle_variant` of the 24 parameters in their generated order.
    fn cc_variant(p: &[f64; 24]) -> i32;
    /// `circle_circle_coefficients`: the degree, coefficients in `c[..=degree]`.
    fn cc_coefficients(p: &[f64; 24], c: &mut [f64; MAX_COEF]) -> Option<usize>;
    /// `point_edge_variant` of the 12 parameters in their generated order.
    fn pe_variant(p: &[f64; 12]) -> i32;
    /// `point_edge_coefficients`: the degree, coefficients in `c[..=degree]`.
    fn pe_coefficients(p: &[f64; 12], c: &mut [f64; MAX_COEF]) -> Option<usize>;
}

// contact features: circle-circle (also circle-vertex), point-edge
const CC: i32 = 0;
const PE: i32 = 1;

/// Run a compiled scene (the flat text), writing the flat trace to `sink`.
/// Returns the exit status: 0, or 1 after an `X message` line for a stuck
/// or bad scene (the trace so far stays written, as the Python runtime's).
pub fn simulate<E: Equations>(scene_text: &str, sink: Box<dyn Write>) -> io::Result<i32> {
    simulate_parsed::<E>(Scene::parse(scene_text), sink)
}

/// `simulate` of a scene already read (or the message of why it could not
/// be), so that its text need not outlive the reading: the program's
/// `main` lets it go before the run (at 10^5 disks 14 MB of text, 16 MB
/// of buffer).
fn simulate_parsed<E: Equations>(parsed: Result<Scene, String>, sink: Box<dyn Write>) -> io::Result<i32> {
    // read first: a bad scene's X line goes to the sink, which the world
    // would otherwise own (and drop unwritten) when its making fails
    match parsed {
        Err(msg) => stop_status::<E>(Err((None, SimError::Msg(msg))), Some(sink)),
        Ok(scene) => {
            let mut world = World::<E>::unstarted(scene, Some(sink));
            match world.start().and_then(|()| world.run()) {
                Ok(()) => {
                    // the trace is written and flushed (finish), and the
                    // program ends with this world: the system takes its
                    // memory back whole, where dropping it freed the grid's
                    // two lists per cell one by one (at 10^5 disks 0.3 M
                    // cells, 15 MB walked after the last line)
                    std::mem::forget(world);
                    Ok(0)
                }
                Err(e) => stop_status(Err((Some(world), e)), None),
            }
        }
    }
}

/// 0 after a run, or 1 after the `X message` line of a stuck or bad scene
/// (written to the world's trace, or to `sink` when no world was made).
fn stop_status<E: Equations>(
    res: Result<(), (Option<World<E>>, SimError)>,
    sink: Option<Box<dyn Write>>,
) -> io::Result<i32> {
    match res {
        Ok(()) => Ok(0),
        Err((_, SimError::Io(e))) => Err(e),
        Err((Some(mut world), SimError::Msg(msg))) => match world.stop_trace(&msg) {
            Err(SimError::Io(e)) => Err(e),
            _ => Ok(1),
        },
        Err((None, SimError::Msg(msg))) => {
            if let Some(mut sink) = sink {
                writeln!(sink, "X {msg}")?;
                sink.flush()?;
            }
            Ok(1)
        }
    }
}

/// The flat scene with its input lines taken out (`inputs 0`), and those
/// lines' fields (T BODY MODE X Y) in order (the reference's `split_inputs`).
fn split_inputs(text: &str) -> Result<(String, Vec<Input>), SimError> {
    let bad = || SimError::Msg("scene: expected 'inputs'".to_string());
    let at = text.find("\ninputs ").ok_or_else(bad)?;
    let (head, tail) = (&text[..at], &text[at + "\ninputs ".len()..]);
    let lines: Vec<&str> = tail.split('\n').collect();
    let k: usize = lines[0].trim().parse().map_err(|_| bad())?;
    if k > scene::MAX_INPUTS as usize {
        return Err(SimError::Msg(format!("scene: {k} inputs (0 to {})", scene::MAX_INPUTS)));
    }
    // one line each: no more than the text has
    let mut inputs = Vec::with_capacity(k.min(lines.len()));
    for i in 0..k {
        let f: Vec<&str> = lines.get(1 + i).ok_or_else(bad)?.split_ascii_whitespace().skip(1).collect();
        let num = |n: usize| f.get(n).and_then(|w| w.parse::<f64>().ok()).ok_or_else(bad);
        let int = |n: usize| f.get(n).and_then(|w| w.parse::<i64>().ok()).ok_or_else(bad);
        inputs.push(Input { t: num(0)?, body: int(1)?, mode: int(2)?, vx: num(3)?, vy: num(4)? });
    }
    Ok((format!("{head}\ninputs 0\nend\n"), inputs))
}

/// The live operation of an input's mode (set or add velocity, impulse,
/// teleport) on the world at its time; false: a teleport refused.
fn live_op<E: Equations>(world: &mut World<E>, inp: &Input) -> Result<bool, SimError> {
    let body = usize::try_from(inp.body)
        .map_err(|_| SimError::Msg(format!("live input: body {} does not exist", inp.body)))?;
    match inp.mode {
        scene::SET_VELOCITY => world.set_velocity(body, inp.vx, inp.vy).map(|_| true),
        scene::ADD_VELOCITY => world.add_velocity(body, inp.vx, inp.vy).map(|_| true),
        scene::IMPULSE => world.apply_impulse(body, inp.vx, inp.vy).map(|_| true),
        scene::TELEPORT => world.teleport(body, inp.vx, inp.vy),
        scene::REMOVE => world.remove_body(body).map(|_| true),
        m => Err(SimError::Msg(format!("scene: unknown input mode {m}"))),
    }
}

/// The scene through the live API in steps of dt: advance(k dt) for k = 1,
/// 2, ... below the end, then finish(); after each advance, every body's
/// `P T BODY PX PY VX VY ANGLE OMEGA` (state(body, T)) and `C T COUNT`
/// (the contacts advance returned) on `probe` (the reference's `stepped`).
/// With `live`, the scene's inputs are taken out of it and made as live
/// inputs instead: advance to each input's time, then its operation.
pub fn stepped<E: Equations>(
    scene_text: &str,
    sink: Box<dyn Write>,
    probe: &mut dyn Write,
    dt: f64,
    live: bool,
) -> io::Result<i32> {
    let mut sink = Some(sink);
    let (text, inputs) = if live {
        match split_inputs(scene_text) {
            Ok(split) => split,
            Err(e) => return stop_status::<E>(Err((None, e)), sink),
        }
    } else {
        (scene_text.to_string(), Vec::new())
    };
    let mut world = match Scene::parse(&text) {
        Err(msg) => return stop_status::<E>(Err((None, SimError::Msg(msg))), sink),
        Ok(scene) => World::<E>::unstarted(scene, sink.take()),
    };
    if let Err(e) = world.start() {
        return stop_status(Err((Some(world), e)), None);
    }
    let res = (|| -> Result<(), SimError> {
        let end = world.end();
        let mut nxt = 0; // the next live input
        let mut k: i64 = 1;
        loop {
            let t = (k as f64) * dt;
            while nxt < inputs.len() && (!(t < end) || inputs[nxt].t <= t) {
                world.advance(inputs[nxt].t)?;
                if !live_op(&mut world, &inputs[nxt])? {
                    return Err(SimError::Msg(format!(
                        "live input {nxt}: teleport refused (the body would overlap another)"
                    )));
                }
                nxt += 1;
            }
            if !(t < end) {
                break;
            }
            let got = world.advance(t)?;
            let every = world.states(t)?; // every body at once, checked against one by one
            if every.len() != world.bodies() {
                return Err(SimError::Msg(format!(
                    "states(t) gives {} states for {} bodies",
                    every.len(),
                    world.bodies()
                )));
            }
            for (b, want) in every.iter().enumerate() {
                let s = world.state(b, t)?;
                if s != *want {
                    return Err(SimError::Msg(format!("states(t) gives body {b} another state than state({b}, t)")));
                }
                writeln!(
                    probe,
                    "P {} {b} {} {} {} {} {} {}",
                    g17(t),
                    g17(s.px),
                    g17(s.py),
                    g17(s.vx),
                    g17(s.vy),
                    g17(s.angle),
                    g17(s.omega)
                )?;
            }
            writeln!(probe, "C {} {}", g17(t), got.len())?;
            k += 1;
        }
        world.finish()?;
        Ok(())
    })();
    probe.flush()?;
    stop_status(res.map_err(|e| (Some(world), e)), sink)
}

/// The simulator program: compiled scene on stdin, flat trace on stdout;
/// `--step DT` drives the live world in steps ([`stepped`], probe lines on
/// stderr), `--step DT --live` with the scene's inputs made live.  Returns the exit status.
pub fn main<E: Equations>() -> i32 {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let live = args.iter().any(|a| a == "--live");
    args.retain(|a| a != "--live");
    let step = match args.as_slice() {
        [] if !live => None,
        [flag, dt] if flag == "--step" && dt.parse::<f64>().is_ok_and(|dt| dt > 0.0) => dt.parse::<f64>().ok(),
        _ => {
            eprintln!("usage: sim [--step DT [--live]] < scene");
            return 2;
        }
    };
    // bytes (at most one past the longest text): checked before they are
    // taken as text, so that a byte that is no ASCII gets its X line
    let mut bytes = Vec::new();
    if let Err(e) = io::stdin().take(scene::MAX_TEXT as u64 + 1).read_to_end(&mut bytes) {
        eprintln!("max2code simulator: cannot read the scene: {e}");
        return 2;
    }
    let mut stdout = Box::new(io::stdout().lock());
    let text = match scene::check_text(&bytes, "scene").map(|()| String::from_utf8(bytes)) {
        Ok(Ok(text)) => text,
        Err(msg) => {
            return match writeln!(stdout, "X {msg}").and_then(|()| stdout.flush()) {
                Ok(()) => 1,
                Err(e) => {
                    eprintln!("max2code simulator: cannot write the trace: {e}");
                    2
                }
            };
        }
        Ok(Err(e)) => unreachable!("printable ASCII is UTF-8: {e}"),
    };
    let res = match step {
        None => {
            let parsed = Scene::parse(&text);
            drop(text);
            simulate_parsed::<E>(parsed, stdout)
        }
        Some(dt) => stepped::<E>(&text, stdout, &mut io::stderr().lock(), dt, live),
    };
    match res {
        Ok(code) => code,
        Err(e) => {
            eprintln!("max2code simulator: cannot write the trace: {e}");
            2
        }
    }
}

/// `sim_equations!(circle_circle, point_edge)`, with the two generated
/// modules (equations/circle-circle.mxm and equations/point-edge.mxm) in
/// scope, defines `struct GeneratedEquations` implementing [`Equations`]
/// with their entries: the type parameter of a [`World`].
#[macro_export]
macro_rules! sim_equations {
    ($cc:ident, $pe:ident) => {
        /// The generated entries of this program's contact equations.
        struct GeneratedEquations;

        impl $crate::sim::Equations for GeneratedEquations {
            const CC_VARIANTS: usize = $cc::CIRCLE_CIRCLE_VARIANT_NAMES.len();
            const PE_VARIANTS: usize = $pe::POINT_EDGE_VARIANT_NAMES.len();

            #[inline(always)]
            fn cc_variant(p: &[f64; 24]) -> i32 {
                $cc::circle_circle_variant(
                    p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13], p[14],
                    p[15], p[16], p[17], p[18], p[19], p[20], p[21], p[22], p[23],
                )
            }

            #[inline(always)]
            fn cc_coefficients(p: &[f64; 24], c: &mut [f64; $crate::sim::MAX_COEF]) -> Option<usize> {
                let (degree, k) = $cc::circle_circle_coefficients(
                    p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13], p[14],
                    p[15], p[16], p[17], p[18], p[19], p[20], p[21], p[22], p[23],
                )?;
                c[..k.len()].copy_from_slice(&k);
                Some(degree)
            }

            #[inline]
            fn pe_variant(p: &[f64; 12]) -> i32 {
                $pe::point_edge_variant(p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11])
            }

            #[inline]
            fn pe_coefficients(p: &[f64; 12], c: &mut [f64; $crate::sim::MAX_COEF]) -> Option<usize> {
                let (degree, k) = $pe::point_edge_coefficients(
                    p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11],
                )?;
                c[..k.len()].copy_from_slice(&k);
                Some(degree)
            }
        }
    };
}

/// The `main` of a simulator binary: `sim_main!(circle_circle, point_edge)`
/// with the two generated modules in scope defines their
/// [`sim_equations!`](crate::sim_equations) and runs [`main`].
#[macro_export]
macro_rules! sim_main {
    ($cc:ident, $pe:ident) => {
        $crate::sim_equations!($cc, $pe);

        fn main() {
            ::std::process::exit($crate::sim::main::<GeneratedEquations>());
        }
    };
}
