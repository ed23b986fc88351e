//! The live world (docs/engine-api.md): a scene made into a world that a
//! caller drives with `advance(t)`, asks `next_event_time()` and
//! `state(body, t)`; the batch simulator is `advance(end)` + `finish()`.
//! The reference is `World` in runtimes/python/max2code_rt/sim/.

use std::io::Write;
use std::marker::PhantomData;

use super::cluster::Touched;
use super::g17::g17;
use super::grid::{cell_of, place_large};
use super::motion::state_at;
use super::out::{Out, SimError};
use super::overlap::overlapping;
use super::predict::{predict_body, predict_pair};
use super::queue::{Event, INPUT};
use super::scene::{
    check_text, drivable, read_body, shown, Body, BodyLimits, Input, Scene, Tokens, ADD_VELOCITY, IMPULSE, LENGTH_MAX,
    MAX_BODIES, REMOVE, SET_VELOCITY, TELEPORT,
};
use super::world::{Queue, Space};
use super::Equations;

/// A collision or support as `advance` reports it: the fields of the
/// trace's `E collision` / `E support` line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Contact {
    /// s
    pub t: f64,
    /// the bodies (scene indices)
    pub a: usize,
    pub b: usize,
    /// 0: circle-circle (or circle-vertex), 1: point-edge
    pub feature: i32,
    /// a's vertex (-1: its circle), b's vertex or edge (-1: its circle)
    pub i: i32,
    pub j: i32,
    /// m: the contact point
    pub px: f64,
    pub py: f64,
    /// the unit normal from a to b
    pub nx: f64,
    pub ny: f64,
    /// kg m/s, >= 0
    pub impulse: f64,
    /// true: the contact ended in support (`E support`), else a collision
    pub support: bool,
}

/// A body's exact state at one time (`World::state`).  Units: m, m/s, rad, rad/s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    pub px: f64,
    pub py: f64,
    pub vx: f64,
    pub vy: f64,
    pub angle: f64,
    pub omega: f64,
}

/// The contacts handled since the last `advance`, for its caller: a batch
/// run (`World::run`) has none and keeps none (it kept every contact of the
/// run to drop them at its end: at 10^5 disks about 15 MB written, the
/// 88-byte records and the list's copies as it grew).
pub(super) struct Reported {
    list: Vec<Contact>,
    keep: bool,
}

impl Reported {
    #[inline]
    pub(super) fn push(&mut self, c: Contact) {
        if self.keep {
            self.list.push(c);
        }
    }
}

/// A live world over the generated equations `E` (see [`sim_main!`](crate::sim_main)).
pub struct World<E: Equations> {
    /// the scene, the bodies' states and stamps, the grid
    pub(super) w: Space,
    /// the events and the counters
    pub(super) q: Queue,
    pub(super) out: Out,
    /// s: the world's current time
    time: f64,
    /// the instant of the last event handled, and how many came at it
    pub(super) last_t: f64,
    pub(super) same: i64,
    /// events handled (stale ones not): at most the scene's max_events
    pub(super) handled: i64,
    /// the contacts the next `advance` reports
    pub(super) contacts: Reported,
    /// bodies added by add_body (a recording refuses them)
    added: usize,
    /// `finish` wrote the trace's final lines: no input or body may follow
    finished: bool,
    /// the instant of the contacts in `touched`
    pub(super) touched_t: f64,
    /// the contacts (a, b, feature, i, j) handled at `touched_t` (cluster.rs)
    pub(super) touched: Vec<Touched>,
    /// the instant of the bodies in `jammed`
    pub(super) jammed_t: f64,
    /// the bodies a jam put to sleep at `jammed_t` (held_now, cluster.rs)
    pub(super) jammed: Vec<usize>,
    eq: PhantomData<E>,
}

impl<E: Equations> World<E> {
    /// A world from a compiled scene (the flat text of docs/simulator.md),
    /// writing its flat trace to `trace` (None: no trace); every pair's
    /// first prediction is made.
    pub fn from_scene(text: &str, trace: Option<Box<dyn Write>>) -> Result<World<E>, SimError> {
        let scene = Scene::parse(text).map_err(SimError::Msg)?;
        let mut world = World::unstarted(scene, trace);
        world.start()?;
        Ok(world)
    }

    /// A world from a scene already read, before its first predictions
    /// (`start`): the batch programs make it so that a failing start still
    /// writes its `X` line to the world's trace.
    pub(crate) fn unstarted(scene: Scene, trace: Option<Box<dyn Write>>) -> World<E> {
        World {
            w: Space::new(scene),
            q: Queue::new(E::CC_VARIANTS, E::PE_VARIANTS),
            out: Out::new(trace),
            time: 0.0,
            last_t: -1.0,
            same: 0,
            handled: 0,
            contacts: Reported { list: Vec::new(), keep: true },
            added: 0,
            finished: false,
            touched_t: -1.0,
            touched: Vec::new(),
            jammed_t: -1.0,
            jammed: Vec::new(),
            eq: PhantomData,
        }
    }

    /// A world from a compiled scene file.
    pub fn from_file(path: &str, trace: Option<Box<dyn Write>>) -> Result<World<E>, SimError> {
        let bytes = std::fs::read(path).map_err(|e| SimError::Msg(format!("{path}: {e}")))?;
        check_text(&bytes, "scene").map_err(SimError::Msg)?;
        // printable ASCII: UTF-8
        let text = String::from_utf8(bytes).map_err(|e| SimError::Msg(format!("{path}: {e}")))?;
        World::from_scene(&text, trace)
    }

    /// s: the world's current time.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// s: the scene's end time.
    pub fn end(&self) -> f64 {
        self.w.s.end
    }

    /// Number of bodies.
    pub fn bodies(&self) -> usize {
        self.w.s.bodies.len()
    }

    /// Handle every event at a time before t, move the world's time to t
    /// and return the contacts handled since the last call.  Events at
    /// exactly t stay queued: an input made at t comes before them, as a
    /// scripted input at t does.  No body is re-based but by its events.
    pub fn advance(&mut self, t: f64) -> Result<Vec<Contact>, SimError> {
        if !(t >= self.time && t <= self.w.s.end) {
            return Err(SimError::Msg(format!(
                "advance: t = {} is outside [{}, {}] (the world's time .. the scene's end)",
                g17(t),
                g17(self.time),
                g17(self.w.s.end)
            )));
        }
        self.process(t, false)?;
        self.time = t;
        Ok(self.take_contacts())
    }

    fn take_contacts(&mut self) -> Vec<Contact> {
        std::mem::take(&mut self.contacts.list)
    }

    /// The time of the next event that is not stale (stale ones at the top
    /// of the queue are dropped and counted as the run would); infinity
    /// when none comes before the end.
    pub fn next_event_time(&mut self) -> f64 {
        let end = self.w.s.end;
        while let Some(top) = self.q.heap.peek() {
            if top.t > end {
                break;
            }
            if !self.w.is_stale(&top.ev) {
                return top.t;
            }
            self.q.heap.pop();
            self.q.stats.stale += 1;
        }
        f64::INFINITY
    }

    /// The exact state of a body at t, for t from the world's time to the
    /// next event's.
    pub fn state(&mut self, body: usize, t: f64) -> Result<BodyState, SimError> {
        self.body(body)?;
        let nxt = self.next_event_time();
        if !(t >= self.time && t <= nxt && t <= self.w.s.end) {
            return Err(SimError::Msg(format!(
                "state: t = {} is outside [{}, {}] (the world's time .. the next event)",
                g17(t),
                g17(self.time),
                g17(nxt)
            )));
        }
        let b = &self.w.s.bodies[body];
        let (px, py, vx, vy, angle) = state_at(b, t);
        Ok(BodyState { px, py, vx, vy, angle, omega: b.om })
    }

    /// Every body's state at `t` at once (what a frame draws): entry k is
    /// body k's, as `state` gives it; an error as `state`'s when `t` is outside.
    pub fn states(&mut self, t: f64) -> Result<Vec<BodyState>, SimError> {
        if self.w.s.bodies.is_empty() {
            return Ok(Vec::new());
        }
        let first = self.state(0, t)?;
        let mut out = Vec::with_capacity(self.w.s.bodies.len());
        out.push(first);
        for b in &self.w.s.bodies[1..] {
            let (px, py, vx, vy, angle) = state_at(b, t);
            out.push(BodyState { px, py, vx, vy, angle, omega: b.om });
        }
        Ok(out)
    }

    fn body(&self, k: usize) -> Result<&Body, SimError> {
        let n = self.w.s.bodies.len();
        if k >= n {
            return Err(SimError::Msg(format!("no body {k} (the world has {n})")));
        }
        Ok(&self.w.s.bodies[k])
    }

    // ---- live inputs: at the world's time, recorded in the input list --------

    /// Set the body's velocity (m/s) now.
    pub fn set_velocity(&mut self, body: usize, vx: f64, vy: f64) -> Result<(), SimError> {
        self.live_input(body, SET_VELOCITY, vx, vy).map(|_| ())
    }

    /// Add (dvx, dvy) m/s to the body's velocity now.
    pub fn add_velocity(&mut self, body: usize, dvx: f64, dvy: f64) -> Result<(), SimError> {
        self.live_input(body, ADD_VELOCITY, dvx, dvy).map(|_| ())
    }

    /// An impulse (N s) through the centre now: dv = J inv_mass.
    pub fn apply_impulse(&mut self, body: usize, jx: f64, jy: f64) -> Result<(), SimError> {
        self.live_input(body, IMPULSE, jx, jy).map(|_| ())
    }

    /// Move the body's centre to (x, y) now, keeping its velocity; false
    /// (the world unchanged) when it would overlap another body by more
    /// than the tolerance there.
    pub fn teleport(&mut self, body: usize, x: f64, y: f64) -> Result<bool, SimError> {
        self.live_input(body, TELEPORT, x, y)
    }

    /// An input at the world's time T, handled as the same input scripted
    /// at T and listed after the scene's would be: the scene's inputs at T
    /// are handled first, then this one, before any other event at T
    /// (docs/engine-api.md, "Live inputs").  It is appended to the input
    /// list, which is the recording.
    /// Refused before it changes anything: after `finish`, on a body that
    /// does not exist or was removed, one an input of this mode may not
    /// drive, or when the velocity or position it gives would not be finite
    /// (a teleport: beyond LENGTH_MAX).
    fn live_input(&mut self, body: usize, mode: i64, x: f64, y: f64) -> Result<bool, SimError> {
        self.not_finished()?;
        if body >= self.w.s.bodies.len() {
            return Err(SimError::Msg(format!("live input: body {body} does not exist")));
        }
        if self.body(body)?.gone {
            return Err(SimError::Msg(format!("body {body} was removed")));
        }
        if !drivable(self.body(body)?, mode) {
            return Err(SimError::Msg(format!(
                "body {body} is fixed: inputs move movable bodies only (or set the velocity of a fixed polygon that does not turn, or remove a fixed body)"
            )));
        }
        let t = self.time;
        self.inputs_now()?;
        // the scene's inputs at t are handled: the body's velocity now is
        // the one this input changes (as handle_input re-bases it)
        let b = self.body(body)?;
        if b.gone {
            return Err(SimError::Msg(format!("body {body} was removed")));
        }
        let (px, py, vx, vy, _) = state_at(b, t);
        let (rx, ry, what) = match mode {
            SET_VELOCITY => (x, y, "velocity"),
            ADD_VELOCITY => (vx + x, vy + y, "velocity"),
            IMPULSE => (vx + x * b.inv_m, vy + y * b.inv_m, "velocity"),
            _ => (x, y, "position"),
        };
        if !(rx.is_finite() && ry.is_finite()) {
            return Err(SimError::Msg(format!("live input: body {body}: {what} would not be finite")));
        }
        if mode == TELEPORT && !(x.abs() + y.abs() <= LENGTH_MAX) {
            return Err(SimError::Msg(format!("live input: body {body}: teleport beyond 1e150 m")));
        }
        // the motion after the input stays within the scene's reach by the end (rule 8, left to right)
        let (qx, qy, ux, uy) = if mode == TELEPORT { (x, y, vx, vy) } else { (px, py, rx, ry) };
        let end = self.w.s.end;
        let reach =
            (qx.abs() + qy.abs()) + (ux.abs() + uy.abs()) * end + (b.ax.abs() + b.ay.abs()) * end * end / 2.0 + b.bound;
        if mode != REMOVE && !(reach <= 2.0 * LENGTH_MAX) {
            return Err(SimError::Msg(format!(
                "live input: body {body}: reaches more than 2e150 m from the origin by the end"
            )));
        }
        if mode == TELEPORT {
            let s = &self.w.s;
            if overlapping(&s.bodies, &s.verts, s.tol, &s.bodies[body], Some(body), x, y, t).is_some() {
                return Ok(false);
            }
        }
        self.w.s.inputs.push(Input { t, body: body as i64, mode, vx: x, vy: y });
        let k = (self.w.s.inputs.len() - 1) as u32;
        self.q.heap.push(t, Event::Input { k });
        self.inputs_now()?;
        Ok(true)
    }

    /// Every input: the scene's, then the live ones in the order they were
    /// made (what a recording writes).
    pub fn input_log(&self) -> &[Input] {
        &self.w.s.inputs
    }

    /// How many bodies add_body added.
    pub fn added(&self) -> usize {
        self.added
    }

    /// Take a body (movable or fixed) out of the world now: input MODE 4.
    pub fn remove_body(&mut self, body: usize) -> Result<(), SimError> {
        self.live_input(body, REMOVE, 0.0, 0.0).map(|_| ())
    }

    /// A body from its flat lines (`body ...` and its `v` lines, the state
    /// at the world's time) added now; its index, or None (the world
    /// unchanged) when it would overlap a body by more than the tolerance.
    /// Not an input: a recording refuses a session that added bodies.
    pub fn add_body(&mut self, text: &str) -> Result<Option<usize>, SimError> {
        self.not_finished()?;
        let n = self.w.s.bodies.len();
        if n as i64 >= MAX_BODIES {
            // a scene's limit holds for a world too
            return Err(SimError::Msg(format!("add_body: the world has {n} bodies (at most {MAX_BODIES})")));
        }
        let v0 = self.w.s.verts.len();
        let res = self.add_body_at(text, v0);
        if !matches!(res, Ok(Some(_))) {
            // not added: its vertices go too
            self.w.s.verts.truncate(v0);
        }
        res
    }

    fn add_body_at(&mut self, text: &str, v0: usize) -> Result<Option<usize>, SimError> {
        check_text(text.as_bytes(), "add_body").map_err(SimError::Msg)?;
        let mut tk = Tokens::new(text, "add_body");
        let idx = self.w.s.bodies.len();
        let s = &self.w.s;
        let lim = BodyLimits { end: s.end, tol: s.tol, bodies: idx as i64 };
        let mut b = read_body(&mut tk, idx as u32, &mut self.w.s.verts, &lim).map_err(SimError::Msg)?;
        debug_assert_eq!(b.v0 as usize, v0);
        if let Some(w) = tk.rest() {
            return Err(SimError::Msg(format!("add_body: unexpected '{}' after the body", shown(w))));
        }
        let s = &self.w.s;
        // Python's min(cw, ch)
        let cell = if s.ch < s.cw { s.ch } else { s.cw };
        b.large = 2.0 * b.bound > cell;
        if b.large && !b.fixed {
            return Err(SimError::Msg(format!(
                "add_body: a movable body of bound {} m does not fit the grid's cells ({} x {} m): put such a body in the scene",
                g17(b.bound),
                g17(s.cw),
                g17(s.ch)
            )));
        }
        let t = self.time;
        b.tb = t;
        self.inputs_now()?;
        let s = &self.w.s;
        if overlapping(&s.bodies, &s.verts, s.tol, &b, None, b.px, b.py, t).is_some() {
            return Ok(None);
        }
        let (large, fixed) = (b.large, b.fixed);
        self.w.s.bodies.push(b);
        self.w.stamps.push(0);
        self.w.rest.push(-1);
        self.w.restc.push([super::world::RestContact::default(); super::world::REST_SLOTS]);
        self.w.on.push([-1; 1 + super::world::REST_SLOTS]);
        self.w.choose_fetch();
        self.added += 1;
        self.out.add(t, idx as u32)?;
        if large {
            place_large(&mut self.w.grid, &mut self.w.s, idx);
            for o in 0..self.w.s.bodies.len() {
                let ob = &self.w.s.bodies[o];
                if !(ob.large || ob.gone || (ob.fixed && fixed)) {
                    predict_pair::<E>(&self.w, &mut self.q, o, idx, t)?;
                }
            }
        } else {
            let (px, py) = (self.w.s.bodies[idx].px, self.w.s.bodies[idx].py);
            let (cx, cy) = cell_of(&self.w.s, px, py);
            let body = &mut self.w.s.bodies[idx];
            body.cx = cx;
            body.cy = cy;
            self.w.grid.add(idx as u32, cx, cy);
            if !fixed {
                self.out.state(&self.w.s.bodies[idx])?;
            }
            predict_body::<E>(&self.w, &mut self.q, idx, t, None)?;
        }
        Ok(Some(idx))
    }

    /// Inputs and bodies are refused once `finish` wrote the final lines.
    fn not_finished(&self) -> Result<(), SimError> {
        if self.finished {
            return Err(SimError::Msg("live input: the world is finished".to_string()));
        }
        Ok(())
    }

    /// Handle the input events queued at exactly the world's time.
    fn inputs_now(&mut self) -> Result<(), SimError> {
        while let Some(top) = self.q.heap.peek() {
            if !(top.t == self.time && top.ev.kind() == INPUT) {
                break;
            }
            let e = self.q.heap.pop().expect("peeked");
            self.dispatch(e.t, e.ev)?;
            self.sweep_if_due();
        }
        Ok(())
    }

    /// Handle the events at the end time, then write every body at the end,
    /// the counters and the variants served; returns the contacts handled
    /// since the last advance.  The trace is flushed.
    pub fn finish(&mut self) -> Result<Vec<Contact>, SimError> {
        let end = self.w.s.end;
        self.process(end, true)?;
        self.time = end;
        self.finished = true;
        self.write_final()?;
        self.out.flush()?;
        Ok(self.take_contacts())
    }

    /// The batch simulator: every event to the end, then the final lines.
    pub fn run(&mut self) -> Result<(), SimError> {
        self.contacts.keep = false; // no caller to report them to
        self.advance(self.w.s.end)?;
        self.finish()?;
        Ok(())
    }

    /// Write what the trace holds so far to its sink.
    pub fn flush(&mut self) -> Result<(), SimError> {
        Ok(self.out.flush()?)
    }

    /// End the trace with `X message` (a run stopped on a stuck or bad
    /// scene) and flush it.
    pub fn stop_trace(&mut self, msg: &str) -> Result<(), SimError> {
        self.out.message(msg);
        self.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::World;
    use crate::sim::{Equations, SimError, MAX_COEF};

    /// Equations under which no pair ever meets (every gap polynomial is
    /// the constant 1): a world whose live API alone is tested.
    struct Apart;

    impl Equations for Apart {
        const CC_VARIANTS: usize = 1;
        const PE_VARIANTS: usize = 1;
        fn cc_variant(_: &[f64; 24]) -> i32 {
            0
        }
        fn cc_coefficients(_: &[f64; 24], c: &mut [f64; MAX_COEF]) -> Option<usize> {
            c[0] = 1.0;
            Some(0)
        }
        fn pe_variant(_: &[f64; 12]) -> i32 {
            0
        }
        fn pe_coefficients(_: &[f64; 12], c: &mut [f64; MAX_COEF]) -> Option<usize> {
            c[0] = 1.0;
            Some(0)
        }
    }

    const SCENE: &str = "m2c-scene 1\nend 2\nframe 0\ntolerance 1e-9\nrest_speed 0.01\nwindow_angle 0.5\n\
        max_same_time 100\nmax_events 1000\ngrid -2 -2 1 1 4 4 0.1\nbodies 1\n\
        body 0 0 1 0 0.5 0.2 0 0 0 0 0 0 0 0 0.1 0 0 0.1 0 0 0\ninputs 0\nend\n";

    const BALL: &str = "body 0 0 1 0 0.5 0.2 1 1 0 0 0 0 0 0 0.1 0 0 0.1 0 0 0";

    #[track_caller]
    fn msg<T: std::fmt::Debug>(r: Result<T, SimError>) -> String {
        match r {
            Err(SimError::Msg(m)) => m,
            other => panic!("expected a refusal, got {other:?}"),
        }
    }

    /// The live API refuses, before it changes anything, bodies that do not
    /// exist, results that would not be finite, far teleports, add_body text
    /// that fails a body's checks, and everything after finish().
    #[test]
    fn live_refusals() {
        let mut w = World::<Apart>::from_scene(SCENE, None).expect("a valid scene");
        assert_eq!(msg(w.set_velocity(5, 1.0, 0.0)), "live input: body 5 does not exist");
        assert_eq!(msg(w.state(1, 0.0)), "no body 1 (the world has 1)");
        w.add_velocity(0, 1e140, 0.0).expect("within the reach");
        let far = "live input: body 0: reaches more than 2e150 m from the origin by the end";
        assert_eq!(msg(w.add_velocity(0, 1e308, 0.0)), far);
        assert_eq!(msg(w.set_velocity(0, 0.0, 2e150)), far);
        assert_eq!(msg(w.apply_impulse(0, f64::MAX, 0.0)), far);
        assert_eq!(msg(w.set_velocity(0, f64::NAN, 0.0)), "live input: body 0: velocity would not be finite");
        assert_eq!(msg(w.teleport(0, f64::INFINITY, 0.0)), "live input: body 0: position would not be finite");
        assert_eq!(msg(w.teleport(0, 1e150, 1e150)), "live input: body 0: teleport beyond 1e150 m");
        assert_eq!(w.state(0, 0.0).expect("a body").vx, 1e140); // the refused inputs changed nothing
        assert_eq!(w.input_log().len(), 1);
        w.set_velocity(0, 0.0, 0.0).expect("finite");
        assert_eq!(
            msg(w.add_body(&BALL.replace(" 0.5 0.2 ", " 5 0.2 "))),
            "add_body: body 1: restitution 5 outside [0, 1]"
        );
        assert_eq!(msg(w.add_body(&format!("{BALL} x"))), "add_body: unexpected 'x' after the body");
        assert_eq!(msg(w.add_body(&BALL.replace("body", "b\u{e9}dy"))), "add_body: byte 1: not printable ASCII");
        assert_eq!(msg(w.add_body("body 1")), "add_body: ends early");
        assert_eq!(w.bodies(), 1);
        assert_eq!(w.add_body(BALL).expect("a valid body"), Some(1));
        w.finish().expect("the end");
        let finished = "live input: the world is finished";
        assert_eq!(msg(w.set_velocity(0, 1.0, 0.0)), finished);
        assert_eq!(msg(w.remove_body(1)), finished);
        assert_eq!(msg(w.add_body(BALL)), finished);
    }
}
