//! Simultaneous contacts (docs/simulator.md, "Contact model: simultaneous
//! contacts"): a contact met again at the instant it was handled is solved
//! together with the contacts handled at that instant that reach it, by
//! sequential impulses that never add kinetic energy.  The reference's
//! `touch`, `repeated`, `cluster`, `part`, `give`, `nudge`, `sweeps`,
//! `kinetic`, `mix`, `pressing_contact`, `solve_cluster`,
//! `jolted_sleeper`, `wedged`, `holds`, `handle_cluster`, `settle`,
//! `predict_apart`.

use super::contact::{closing, contact_frame, normal_speed, pressed};
use super::live::{Contact, World};
use super::motion::{rebase, turn_rate};
use super::out::Res;
use super::predict::predict_near;
use super::scene::{Body, Vertex};
use super::sleep::grounded;
use super::support::{end_support, schedule_support, slide_accel, support_frame, support_relative};
use super::world::Queue;
use super::Equations;

/// How many times one contact is handled at one instant before it and the
/// contacts that reach it are solved together; the most sweeps of the
/// cluster's sequential impulses, and the sweep that ends them: no impulse
/// in it changed a normal speed by more than CLUSTER_TOL rest_speed.
const CLUSTER_REPEATS: u32 = 64;
/// A contact met CLUSTER_REPEATS + CLUSTER_JAM times at one instant (its
/// cluster solved CLUSTER_JAM times there and met again) jams its cluster:
/// the movers come to rest and fall asleep, held until the instant ends.
const CLUSTER_JAM: u32 = 4;
const CLUSTER_SWEEPS: usize = 100;
const CLUSTER_TOL: f64 = 1e-9;
/// The separation speed (times rest_speed) of a cluster's contact that
/// nothing presses: above the rounding of a normal speed, so that it is not
/// met again at once (2^-20).
const CLUSTER_APART: f64 = 1.0 / 1048576.0;
/// The angle (rad) within which one push holds a free acceleration (wedged).
const HOLD_TOL: f64 = 1e-9;

/// A body's part in a cluster's solve.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Part {
    /// fixed, or asleep: infinite mass
    Held,
    Free,
    /// sliding on a fixed body's edge: moves along the edge only
    Slider,
}

/// Which contact: (a, b, feature, i, j) of its collision record.
pub type ContactId = (usize, usize, i32, i32, i32);

/// A contact handled at one instant and how many times it was.
#[derive(Clone, Copy)]
pub struct Touched {
    pub c: ContactId,
    pub times: u32,
}

/// A contact of a cluster in its frame: bodies a, b, contact point, unit
/// normal from a to b, each body's arm across n, and kn, how much a unit
/// normal impulse changes the normal speed.
#[derive(Clone, Copy)]
struct Row {
    a: usize,
    b: usize,
    cx: f64,
    cy: f64,
    nx: f64,
    ny: f64,
    ran: f64,
    rbn: f64,
    kn: f64,
}

/// A body that links a cluster's contacts: movable and awake (fixed bodies
/// and sleepers are held: the cluster ends at them).
#[inline(always)]
fn joins(b_: &Body) -> bool {
    !b_.fixed && !b_.asleep
}

/// The contacts handled at this instant (`touched`, in the order first
/// handled) that reach the collision's bodies (ev) through bodies that join.
fn cluster(bodies: &[Body], touched: &[Touched], ev: ContactId) -> Vec<ContactId> {
    let mut inside: Vec<usize> = Vec::new();
    for x in [ev.0, ev.1] {
        if joins(&bodies[x]) {
            inside.push(x);
        }
    }
    let mut grow = true;
    while grow {
        grow = false;
        for &Touched { c, .. } in touched {
            if inside.contains(&c.0) || inside.contains(&c.1) {
                for x in [c.0, c.1] {
                    if !inside.contains(&x) && joins(&bodies[x]) {
                        inside.push(x);
                        grow = true;
                    }
                }
            }
        }
    }
    touched.iter().map(|x| x.c).filter(|c| inside.contains(&c.0) || inside.contains(&c.1)).collect()
}

/// b's part in a cluster's solve.
fn part(bodies: &[Body], b: usize) -> Part {
    let b_ = &bodies[b];
    if b_.fixed || b_.asleep {
        return Part::Held;
    }
    if b_.sup >= 0 && bodies[b_.sup as usize].fixed {
        return Part::Slider;
    }
    Part::Free
}

/// How much a unit impulse along n at the contact (rn: the contact's arm
/// across n) changes b's normal speed there.
fn give(bodies: &[Body], b: usize, nx: f64, ny: f64, rn: f64) -> f64 {
    let b_ = &bodies[b];
    match part(bodies, b) {
        Part::Held => 0.0,
        Part::Slider => {
            let k = nx * b_.tx + ny * b_.ty;
            b_.inv_m * k * k
        }
        Part::Free => b_.inv_m + b_.inv_i * rn * rn,
    }
}

/// An impulse j along n on b at the contact (rn its arm across n).
fn nudge(bodies: &mut [Body], b: usize, j: f64, nx: f64, ny: f64, rn: f64) {
    let p = part(bodies, b);
    let b_ = &mut bodies[b];
    match p {
        Part::Held => {}
        Part::Slider => {
            let d = j * b_.inv_m * (nx * b_.tx + ny * b_.ty);
            b_.vx = b_.vx + d * b_.tx;
            b_.vy = b_.vy + d * b_.ty;
        }
        Part::Free => {
            b_.vx = b_.vx + j * b_.inv_m * nx;
            b_.vy = b_.vy + j * b_.inv_m * ny;
            b_.om = b_.om + j * b_.inv_i * rn;
        }
    }
}

/// Sequential impulses over the cluster's contacts (rows, in order): each
/// contact's accumulated normal impulse acc[k] moves so that its normal
/// speed becomes target[k], but never below zero (a contact only pushes);
/// sweep after sweep until no impulse of a sweep changed a normal speed by
/// more than CLUSTER_TOL rest_speed, at most CLUSTER_SWEEPS sweeps.
fn sweeps(bodies: &mut [Body], rows: &[Row], acc: &mut [f64], target: &[f64], rest_speed: f64) {
    let tol = CLUSTER_TOL * rest_speed;
    for _ in 0..CLUSTER_SWEEPS {
        let mut big = 0.0;
        for (k, r) in rows.iter().enumerate() {
            if !(r.kn > 0.0) {
                continue;
            }
            let vn = normal_speed(&bodies[r.a], &bodies[r.b], r.cx, r.cy, r.nx, r.ny);
            let mut new = acc[k] + (target[k] - vn) / r.kn;
            if new < 0.0 {
                new = 0.0;
            }
            let dj = new - acc[k];
            acc[k] = new;
            nudge(bodies, r.a, -dj, r.nx, r.ny, r.ran);
            nudge(bodies, r.b, dj, r.nx, r.ny, r.rbn);
            let ch = dj.abs() * r.kn;
            if ch > big {
                big = ch;
            }
        }
        if big <= tol {
            return;
        }
    }
}

/// The kinetic energy of the bodies (linear, and turning where 1/I > 0).
fn kinetic(bodies: &[Body], movers: &[usize]) -> f64 {
    let mut e = 0.0;
    for &m in movers {
        let b_ = &bodies[m];
        e = e + 0.5 * (b_.vx * b_.vx + b_.vy * b_.vy) / b_.inv_m;
        if b_.inv_i > 0.0 {
            e = e + 0.5 * b_.om * b_.om / b_.inv_i;
        }
    }
    e
}

fn velocities(bodies: &[Body], movers: &[usize]) -> Vec<(f64, f64, f64)> {
    movers.iter().map(|&m| (bodies[m].vx, bodies[m].vy, bodies[m].om)).collect()
}

fn set_velocities(bodies: &mut [Body], movers: &[usize], vs: &[(f64, f64, f64)]) {
    for (k, &m) in movers.iter().enumerate() {
        let b_ = &mut bodies[m];
        (b_.vx, b_.vy, b_.om) = vs[k];
    }
}

/// The largest mu in [0, 1] for which the bodies' velocities v1 + mu (v -
/// v1) (v: theirs now, v1 as given; the kinetic energy at v1 at most
/// budget) have a kinetic energy at most budget: with a the energy of the
/// change, b the cross term and e1 the energy at v1, a mu^2 + b mu <=
/// budget - e1.
fn mix(bodies: &[Body], movers: &[usize], v1: &[(f64, f64, f64)], budget: f64) -> f64 {
    let mut a = 0.0;
    let mut b = 0.0;
    let mut e1 = 0.0;
    for (k, &mi) in movers.iter().enumerate() {
        let m = &bodies[mi];
        let (vx, vy, om) = v1[k];
        let dx = m.vx - vx;
        let dy = m.vy - vy;
        a = a + 0.5 * (dx * dx + dy * dy) / m.inv_m;
        b = b + (vx * dx + vy * dy) / m.inv_m;
        e1 = e1 + 0.5 * (vx * vx + vy * vy) / m.inv_m;
        if m.inv_i > 0.0 {
            let dw = m.om - om;
            a = a + 0.5 * dw * dw / m.inv_i;
            b = b + om * dw / m.inv_i;
            e1 = e1 + 0.5 * om * om / m.inv_i;
        }
    }
    if !(a > 0.0) {
        return 1.0;
    }
    let mut spare = budget - e1;
    if spare < 0.0 {
        spare = 0.0;
    }
    let root = (b * b + 4.0 * a * spare).sqrt();
    let mu = if b > 0.0 { 2.0 * spare / (b + root) } else { (root - b) / (2.0 * a) };
    if mu < 1.0 {
        mu
    } else {
        1.0
    }
}

/// What a cluster's solve reads besides the bodies: the scene's vertices,
/// tolerance and rest speed, and the queue's counters (`closing`).
struct Solve<'a> {
    verts: &'a [Vertex],
    tol: f64,
    rest_speed: f64,
    q: &'a mut Queue,
}

/// A contact of the cluster that must separate: its bodies' accelerations
/// press them together (pressed) or, a body turning, its gap closes now
/// (closing), as contact_impulse decides.
fn pressing_contact<E: Equations>(sv: &mut Solve, bodies: &[Body], r: &Row, c: &ContactId) -> Res<bool> {
    let (a_, b_) = (&bodies[r.a], &bodies[r.b]);
    if pressed(a_, b_, r.nx, r.ny) {
        return Ok(true);
    }
    if turn_rate(a_) > 0.0 || turn_rate(b_) > 0.0 {
        return closing::<E>(sv.verts, sv.tol, sv.q, a_, b_, c.2, c.3, c.4);
    }
    Ok(false)
}

/// What solve_cluster leaves: each contact's frame and its normal impulse,
/// the bodies that move and their velocities before.
struct Solved {
    rows: Vec<Row>,
    acc: Vec<f64>,
    movers: Vec<usize>,
    saved: Vec<(f64, f64, f64)>,
}

/// The cluster's joint impulses: inelastic sequential impulses (target
/// normal speed 0: kinetic energy e1); then the pressed contacts separate
/// at rest_speed (the others at CLUSTER_APART rest_speed): sequential
/// impulses from v1 (v2), taken when they cost no more than e1; else the
/// same from the movers at rest (vs, energy es), mixed towards v2 as far as
/// e1 pays (mix) when es <= e1, else vs scaled to energy e1.
fn solve_cluster<E: Equations>(sv: &mut Solve, bodies: &mut [Body], cs: &[ContactId], t: f64) -> Res<Solved> {
    let mut rows = Vec::with_capacity(cs.len());
    for &(a, b, feature, i, j) in cs {
        let (a_, b_) = (&bodies[a], &bodies[b]);
        let (cx, cy, nx, ny) = contact_frame(sv.verts, t, feature, a_, b_, i, j, b_.ang);
        let ran = (cx - a_.px) * ny - (cy - a_.py) * nx;
        let rbn = (cx - b_.px) * ny - (cy - b_.py) * nx;
        let kn = give(bodies, a, nx, ny, ran) + give(bodies, b, nx, ny, rbn);
        rows.push(Row { a, b, cx, cy, nx, ny, ran, rbn, kn });
    }
    let mut movers: Vec<usize> = Vec::new();
    for c in cs {
        for x in [c.0, c.1] {
            if part(bodies, x) != Part::Held && !movers.contains(&x) {
                movers.push(x);
            }
        }
    }
    let saved = velocities(bodies, &movers);
    let n = rows.len();
    let rest = sv.rest_speed;
    let mut acc = vec![0.0; n];
    sweeps(bodies, &rows, &mut acc, &vec![0.0; n], rest);
    let e1 = kinetic(bodies, &movers);
    let mut target = vec![0.0; n];
    for k in 0..n {
        target[k] = if pressing_contact::<E>(sv, bodies, &rows[k], &cs[k])? { rest } else { CLUSTER_APART * rest };
    }
    sweeps(bodies, &rows, &mut acc, &target, rest);
    if kinetic(bodies, &movers) <= e1 {
        return Ok(Solved { rows, acc, movers, saved });
    }
    let v2 = velocities(bodies, &movers);
    let acc2 = acc;
    for &m in &movers {
        let sup = bodies[m].sup;
        if sup >= 0 && bodies[sup as usize].fixed {
            let (_, u, _) = support_relative(&bodies[m], &bodies[sup as usize]);
            let b_ = &mut bodies[m];
            b_.vx = b_.vx - u * b_.tx;
            b_.vy = b_.vy - u * b_.ty;
        } else {
            let b_ = &mut bodies[m];
            b_.vx = 0.0;
            b_.vy = 0.0;
        }
        bodies[m].om = 0.0;
    }
    let mut acc = vec![0.0; n];
    sweeps(bodies, &rows, &mut acc, &target, rest);
    let es = kinetic(bodies, &movers);
    if es <= e1 {
        let vs = velocities(bodies, &movers);
        set_velocities(bodies, &movers, &v2);
        let mu = mix(bodies, &movers, &vs, e1);
        for (k, &m) in movers.iter().enumerate() {
            let b_ = &mut bodies[m];
            let (vx, vy, om) = vs[k];
            b_.vx = vx + mu * (b_.vx - vx);
            b_.vy = vy + mu * (b_.vy - vy);
            b_.om = om + mu * (b_.om - om);
        }
        for k in 0..n {
            acc[k] = acc[k] + mu * (acc2[k] - acc[k]);
        }
        return Ok(Solved { rows, acc, movers, saved });
    }
    let f = (e1 / es).sqrt();
    for &m in &movers {
        let b_ = &mut bodies[m];
        b_.vx = f * b_.vx;
        b_.vy = f * b_.vy;
        b_.om = f * b_.om;
    }
    for a in acc.iter_mut() {
        *a = f * *a;
    }
    Ok(Solved { rows, acc, movers, saved })
}

/// The first sleeper (in the contacts' order) whose held impulses, summed,
/// would change its material points' normal speed by at least rest_speed
/// (as a touch that is not gentle, sleeper_impulse); None.
fn jolted_sleeper(bodies: &[Body], rows: &[Row], acc: &[f64], rest_speed: f64, held: &[usize]) -> Option<usize> {
    for r in rows {
        for s in [r.a, r.b] {
            let s_ = &bodies[s];
            if !s_.asleep || held.contains(&s) {
                continue;
            }
            let mut total = 0.0;
            for (q, o) in rows.iter().enumerate() {
                if o.a == s || o.b == s {
                    let rsn = if o.a == s { o.ran } else { o.rbn };
                    total = total + acc[q] * (s_.inv_m + s_.inv_i * rsn * rsn);
                }
            }
            if total >= rest_speed {
                return Some(s);
            }
        }
    }
    None
}

/// The grounded body awake M falls asleep on after its cluster's solve, or
/// None: M slower than rest_speed (a polygon also turning slower than
/// rest_speed / bound) and its free acceleration held by what it rests on
/// (holds): the outward normal of its support when it is supported on an
/// unmoving fixed body, and each contact of the cluster with a grounded
/// body (pushing M along -m, m the contact's normal from M).  It falls
/// asleep on its support, else on the first grounded body of those
/// contacts.
fn wedged(verts: &[Vertex], bodies: &[Body], m: usize, rows: &[Row], rest_speed: f64) -> Option<usize> {
    let rest = rest_speed;
    let m_ = &bodies[m];
    if !(m_.vx * m_.vx + m_.vy * m_.vy < rest * rest) {
        return None;
    }
    if m_.polygon && !(m_.om.abs() * m_.bound < rest) {
        return None;
    }
    let mut pushes: Vec<(f64, f64)> = Vec::new();
    let mut g = None;
    if m_.sup >= 0 {
        let s_ = &bodies[m_.sup as usize];
        if !(s_.fixed && grounded(s_)) {
            return None;
        }
        let (_, _, ox, oy) = support_frame(verts, s_, m_.sup_edge);
        pushes.push((ox, oy));
        g = Some(m_.sup as usize);
    }
    for r in rows {
        if r.a == m && grounded(&bodies[r.b]) {
            pushes.push((-r.nx, -r.ny));
            if g.is_none() {
                g = Some(r.b);
            }
        }
        if r.b == m && grounded(&bodies[r.a]) {
            pushes.push((r.nx, r.ny));
            if g.is_none() {
                g = Some(r.a);
            }
        }
    }
    if g.is_none() || !holds(&pushes, -m_.fax, -m_.fay) {
        return None;
    }
    g
}

/// The pushes (unit directions) can make (dx, dy) with non-negative weights
/// through one push (its direction within HOLD_TOL rad of d) or two: d = a
/// p + b q, a >= 0, b >= 0 (Cramer, p x q != 0), pairs in order.  (dx, dy)
/// = (0, 0) needs nothing.
fn holds(pushes: &[(f64, f64)], dx: f64, dy: f64) -> bool {
    if dx == 0.0 && dy == 0.0 {
        return true;
    }
    for &(px, py) in pushes {
        let dot = px * dx + py * dy;
        if dot > 0.0 && (px * dy - py * dx).abs() <= HOLD_TOL * dot {
            return true;
        }
    }
    let n = pushes.len();
    for k in 0..n {
        let (px, py) = pushes[k];
        for &(qx, qy) in &pushes[k + 1..n] {
            let det = px * qy - py * qx;
            if det == 0.0 {
                continue;
            }
            let a = (dx * qy - dy * qx) / det;
            let b = (px * dy - py * dx) / det;
            if a >= 0.0 && b >= 0.0 {
                return true;
            }
        }
    }
    false
}

impl<E: Equations> World<E> {
    /// Count a contact handled at t (an E collision or E support line).
    pub(super) fn touch(&mut self, t: f64, c: ContactId) {
        if t != self.touched_t {
            self.touched_t = t;
            self.touched.clear();
        }
        for x in self.touched.iter_mut() {
            if x.c == c {
                x.times += 1;
                return;
            }
        }
        self.touched.push(Touched { c, times: 1 });
    }

    /// How many times the collision's contact was handled at this instant.
    fn jam_count(&self, t: f64, c: ContactId) -> u32 {
        if t != self.touched_t {
            return 0;
        }
        self.touched.iter().find(|x| x.c == c).map_or(0, |x| x.times)
    }

    /// A sleeper a jam put to sleep at the current instant: no touch wakes it
    /// before the instant ends.
    pub(super) fn held_now(&self, s: usize) -> bool {
        self.jammed_t == self.last_t && self.jammed.contains(&s)
    }

    /// A cluster its solves do not settle (met again after CLUSTER_JAM
    /// solves at one instant): inelastic collapse, resolved as in Luding's
    /// TC model with a contact time of zero: contacts met again at once lose
    /// all restitution and all sliding.  An E collision line per contact of
    /// the cluster (impulse 0), then each mover (a body of the cluster that
    /// is not held, in the contacts' order) falls asleep, at rest, on its
    /// support when that is fixed, else on the first body it touches in the
    /// cluster that is fixed or asleep, else on the other body of its first
    /// contact; it is held until the instant ends (held_now).  Kinetic
    /// energy only falls.
    fn jam(&mut self, t: f64, c: ContactId) -> Res<()> {
        self.touch(t, c);
        let cs = cluster(&self.w.s.bodies, &self.touched, c);
        for &(a, b, ..) in &cs {
            rebase(&mut self.w.s.bodies[a], t);
            rebase(&mut self.w.s.bodies[b], t);
        }
        let mut movers: Vec<usize> = Vec::new();
        for x in &cs {
            for y in [x.0, x.1] {
                if part(&self.w.s.bodies, y) != Part::Held && !movers.contains(&y) {
                    movers.push(y);
                }
            }
        }
        for &(a, b, feature, i, j) in &cs {
            let s = &self.w.s;
            let (cx, cy, nx, ny) = contact_frame(&s.verts, t, feature, &s.bodies[a], &s.bodies[b], i, j, s.bodies[b].ang);
            self.q.stats.collisions += 1;
            self.out.contact("collision", t, a as u32, b as u32, feature, i, j, (cx, cy), (nx, ny), 0.0)?;
            self.contacts.push(Contact {
                t,
                a,
                b,
                feature,
                i,
                j,
                px: cx,
                py: cy,
                nx,
                ny,
                impulse: 0.0,
                support: false,
            });
        }
        if self.jammed_t != t {
            self.jammed_t = t;
            self.jammed.clear();
        }
        for &m in &movers {
            if self.w.s.bodies[m].asleep {
                continue;
            }
            let bodies = &self.w.s.bodies;
            let sup = bodies[m].sup;
            let mut g: Option<usize> = None;
            if sup >= 0 && bodies[sup as usize].fixed {
                g = Some(sup as usize);
            } else {
                for &(a, b, ..) in &cs {
                    let o = if a == m {
                        Some(b)
                    } else if b == m {
                        Some(a)
                    } else {
                        None
                    };
                    if let Some(o) = o {
                        if bodies[o].fixed || bodies[o].asleep {
                            g = Some(o);
                            break;
                        }
                    }
                }
                if g.is_none() {
                    g = cs.iter().find(|x| x.0 == m || x.1 == m).map(|x| if x.0 == m { x.1 } else { x.0 });
                }
            }
            let g = g.expect("a mover of a cluster has a contact");
            self.jammed.push(m);
            self.handle_sleep(m, g, t)?;
        }
        Ok(())
    }

    /// The collision's contact (a, b, feature, i, j) was handled
    /// CLUSTER_REPEATS times already at this instant: other contacts keep
    /// undoing its impulse (a settling pile meets one contact up to 32 times
    /// at one instant and goes on: ball-pit.json).
    pub(super) fn repeated(&self, t: f64, c: ContactId) -> bool {
        if t != self.touched_t {
            return false;
        }
        match self.touched.iter().find(|x| x.c == c) {
            Some(x) => x.times >= CLUSTER_REPEATS,
            None => false,
        }
    }

    /// A contact met again at the instant it was handled (repeated): the
    /// contacts handled at this instant that reach it (cluster) are solved
    /// together (solve_cluster); a sleeper the solve would jolt wakes and
    /// the solve is made again with it moving.  Then an E collision line per
    /// contact (its normal impulse), each followed by the states of its
    /// moving bodies not written yet (settle); what a body whose velocity
    /// changed carries leaves; those slow enough fall asleep (wedged), and
    /// the others are predicted again.
    pub(super) fn handle_cluster(&mut self, t: f64, c: ContactId) -> Res<()> {
        if self.jam_count(t, c) >= CLUSTER_REPEATS + CLUSTER_JAM {
            return self.jam(t, c);
        }
        self.touch(t, c);
        let rest = self.w.s.rest_speed;
        let (cs, solved) = loop {
            let cs = cluster(&self.w.s.bodies, &self.touched, c);
            for &(a, b, ..) in &cs {
                rebase(&mut self.w.s.bodies[a], t);
                rebase(&mut self.w.s.bodies[b], t);
            }
            let s = &mut self.w.s;
            let mut sv = Solve { verts: &s.verts, tol: s.tol, rest_speed: rest, q: &mut self.q };
            let solved = solve_cluster::<E>(&mut sv, &mut s.bodies, &cs, t)?;
            let held: &[usize] = if self.jammed_t == self.last_t { &self.jammed } else { &[] };
            match jolted_sleeper(&s.bodies, &solved.rows, &solved.acc, rest, held) {
                None => break (cs, solved),
                Some(sl) => {
                    set_velocities(&mut s.bodies, &solved.movers, &solved.saved);
                    self.handle_wake(sl, t)?;
                }
            }
        };
        let Solved { rows, acc, movers, saved } = solved;
        let mut written: Vec<usize> = Vec::new();
        for (k, r) in rows.iter().enumerate() {
            let (_, _, feature, i, j) = cs[k];
            self.q.stats.collisions += 1;
            self.out.contact(
                "collision",
                t,
                r.a as u32,
                r.b as u32,
                feature,
                i,
                j,
                (r.cx, r.cy),
                (r.nx, r.ny),
                acc[k],
            )?;
            self.contacts.push(Contact {
                t,
                a: r.a,
                b: r.b,
                feature,
                i,
                j,
                px: r.cx,
                py: r.cy,
                nx: r.nx,
                ny: r.ny,
                impulse: acc[k],
                support: false,
            });
            for x in [r.a, r.b] {
                if movers.contains(&x) && !written.contains(&x) {
                    written.push(x);
                    self.settle(x)?;
                }
            }
        }
        let mut left = Vec::new();
        for (k, &m) in movers.iter().enumerate() {
            let b_ = &self.w.s.bodies[m];
            if b_.vx != saved[k].0 || b_.vy != saved[k].1 || b_.om != saved[k].2 {
                self.release(m, t, &mut left)?;
            }
        }
        let mut done: Vec<usize> = Vec::new();
        let mut grow = true;
        while grow {
            grow = false;
            for &m in &movers {
                if !self.w.s.bodies[m].asleep {
                    if let Some(g) = wedged(&self.w.s.verts, &self.w.s.bodies, m, &rows, rest) {
                        self.handle_sleep(m, g, t)?;
                        done.push(m);
                        grow = true;
                    }
                }
            }
        }
        for &m in &movers {
            if !self.w.s.bodies[m].asleep {
                self.predict_apart(m, t, &done)?;
                done.push(m);
            }
        }
        self.predict_released(&left, t)
    }

    /// A body of a solved cluster after its impulses: one sliding on a fixed
    /// body gets its friction again for its new speed (as held_impulse), a
    /// carried one leaves its base's motion (end_support: it is not held); a
    /// new stamp, its state.
    fn settle(&mut self, b: usize) -> Res<()> {
        let sup = self.w.s.bodies[b].sup;
        if sup >= 0 {
            if self.w.s.bodies[sup as usize].fixed {
                let sup_ = self.w.s.bodies[sup as usize].clone();
                let b_ = &mut self.w.s.bodies[b];
                let (_, u, _) = support_relative(b_, &sup_);
                slide_accel(b_, &sup_, u);
            } else {
                end_support(&mut self.w.s.bodies, b);
            }
        }
        self.w.bump(b);
        self.out.state(&self.w.s.bodies[b])?;
        Ok(())
    }

    /// predict_body for a body of a solved cluster, but against the bodies
    /// in done (predicted already, or fallen asleep and predicted against it
    /// by handle_sleep).
    fn predict_apart(&mut self, b: usize, now: f64, done: &[usize]) -> Res<()> {
        let (w, q) = (&self.w, &mut self.q);
        let bodies = &w.s.bodies;
        let fixed = bodies[b].fixed;
        predict_near::<E>(w, q, b, now, |o| !(done.contains(&o) || (fixed && bodies[o].fixed)))?;
        let sup = bodies[b].sup;
        if sup >= 0 && bodies[sup as usize].fixed {
            schedule_support(w, q, b);
        }
        Ok(())
    }
}
