//! The handlers of the live world: one per event kind (the reference's
//! `handle_input`, `handle_collision` (and `handle_support`),
//! `handle_stop`, `handle_leave`, `handle_cell`, `handle_horizon`,
//! `handle_frame`), the dispatch over them, the first predictions and the
//! end of the trace.

use super::contact::{
    contact_frame, contact_impulse, held, held_impulse, normal_speed, sleeper_impulse, two_mut, ImpulseCtx,
};
use super::g17::g17;
use super::grid::cell_of;
use super::live::{Contact, World};
use super::motion::{rebase, state_at};
use super::out::{Res, SimError};
use super::overlap::overlapping;
use super::predict::{predict_body, predict_cells, predict_near, predict_pair, schedule_cell};
use super::queue::{prefetch, Event};
use super::scene::{ADD_VELOCITY, IMPULSE, LENGTH_MAX, REMOVE, SET_VELOCITY, TELEPORT};
use super::sleep::{at_rest, can_sleep, can_sleep_many, holding_bodies, jolted, note_rest, slow_touch, Touch};
use super::support::{
    base_holds, can_carry, can_ride, can_support, end_support, enter_carried, enter_support, is_static, slide_accel,
};
use super::world::{REST_SLOTS, SWEEP_FIRST};

/// The island of the sleepers handle_wake is waking.
const WAKING: i32 = -2;
use super::Equations;

impl<E: Equations> World<E> {
    // ---- event handlers: one per kind -------------------------------------

    fn handle_collision(&mut self, t: f64, a: u32, b: u32, feature: i32, i: i32, j: i32) -> Res<()> {
        let (ai, bi) = (a as usize, b as usize);
        if self.repeated(t, (ai, bi, feature, i, j)) {
            return self.handle_cluster(t, (ai, bi, feature, i, j));
        }
        // for predict_body, after the impulse and the trace lines
        self.w.prefetch_block(ai);
        self.w.prefetch_block(bi);
        {
            let (a_, b_) = two_mut(&mut self.w.s.bodies, ai, bi);
            rebase(a_, t);
            rebase(b_, t);
        }
        let (cx, cy, nx, ny, vn, support) = {
            let s = &self.w.s;
            let (a_, b_) = (&s.bodies[ai], &s.bodies[bi]);
            let (cx, cy, nx, ny) = contact_frame(&s.verts, t, feature, a_, b_, i, j, b_.ang);
            let vn = normal_speed(a_, b_, cx, cy, nx, ny);
            let support =
                can_support(&self.w, a_, b_, feature, i, j, vn) || can_carry(&self.w, a_, b_, feature, i, j, vn);
            (cx, cy, nx, ny, vn, support)
        };
        if support {
            return self.handle_support(t, (a, b, feature, i, j), (cx, cy), (nx, ny), vn);
        }
        let touch = Touch { a: ai, b: bi, feature, i, j };
        if can_sleep(&self.w, ai, bi, touch, nx, ny, vn) {
            return self.handle_sleep(ai, bi, t);
        }
        if can_sleep(&self.w, bi, ai, touch, nx, ny, vn) {
            return self.handle_sleep(bi, ai, t);
        }
        if can_sleep_many(&self.w, ai, bi, touch, cx, cy, nx, ny, vn) {
            return self.handle_sleep_many(ai, bi, touch, t);
        }
        if can_sleep_many(&self.w, bi, ai, touch, cx, cy, nx, ny, vn) {
            return self.handle_sleep_many(bi, ai, touch, t);
        }
        if can_ride(&self.w, &self.w.s.bodies[ai], &self.w.s.bodies[bi], feature, i, j, vn) {
            return self.handle_support(t, (a, b, feature, i, j), (cx, cy), (nx, ny), vn);
        }
        let (press_a, press_b) =
            (slow_touch(&self.w, ai, bi, touch, nx, ny, vn), slow_touch(&self.w, bi, ai, touch, nx, ny, vn));
        self.q.stats.collisions += 1;
        let rest_speed = self.w.s.rest_speed;
        // a sleeper takes the impulse frozen (a = 0: pressed by whatever lands
        // on it); a gentle touch leaves it asleep, a real impulse wakes it and what rests on it;
        // a slow contact of bodies held on their supports keeps them there
        let bodies = &self.w.s.bodies;
        let is_held = held(bodies, &bodies[ai], &bodies[bi], nx, ny, vn, rest_speed);
        let imp = if is_held {
            // the supports (fixed bodies, unchanged here), for slide_accel
            let support = |k: usize| {
                let sup = self.w.s.bodies[k].sup;
                (sup >= 0).then(|| self.w.s.bodies[sup as usize].clone())
            };
            let (sup_a, sup_b) = (support(ai), support(bi));
            let (a_, b_) = two_mut(&mut self.w.s.bodies, ai, bi);
            held_impulse(a_, b_, sup_a.as_ref(), sup_b.as_ref(), nx, ny, vn, rest_speed)
        } else {
            let held_now = self.held_now(if self.w.s.bodies[ai].asleep { ai } else { bi });
            let s = &mut self.w.s;
            let mut ctx = ImpulseCtx {
                verts: &s.verts,
                tol: s.tol,
                rest_speed,
                q: &mut self.q,
                feature,
                i,
                j,
                unpaid: false,
                held_now,
            };
            let (a_, b_) = two_mut(&mut s.bodies, ai, bi);
            if a_.asleep || b_.asleep {
                sleeper_impulse::<E>(&mut ctx, a_, b_, cx, cy, nx, ny)?
            } else {
                contact_impulse::<E>(&mut ctx, a_, b_, cx, cy, nx, ny)?
            }
        };
        if imp != 0.0 && !is_held {
            if self.w.s.bodies[ai].asleep && jolted(&self.w.s.bodies[ai]) {
                self.handle_wake(ai, t)?;
            }
            if self.w.s.bodies[bi].asleep && jolted(&self.w.s.bodies[bi]) {
                self.handle_wake(bi, t)?;
            }
            for k in [ai, bi] {
                if self.w.s.bodies[k].sup >= 0 {
                    end_support(&mut self.w.s.bodies, k);
                }
            }
        }
        let (a_fixed, b_fixed, a_asleep, b_asleep);
        {
            self.out.contact("collision", t, a, b, feature, i, j, (cx, cy), (nx, ny), imp)?;
            // their cells have come by now; the state lines take a while
            self.w.prefetch_neighbours(ai);
            self.w.prefetch_neighbours(bi);
            let w = &mut self.w;
            let (a_, b_) = two_mut(&mut w.s.bodies, ai, bi);
            self.contacts.push(Contact {
                t,
                a: a as usize,
                b: b as usize,
                feature,
                i,
                j,
                px: cx,
                py: cy,
                nx,
                ny,
                impulse: imp,
                support: false,
            });
            // a sleeper still asleep (zero impulse: the bodies graze, the other
            // not pressed onto it) is unchanged; the other is predicted again
            // without it (so the graze is not found again at once): only a
            // later change of the other's motion predicts the pair again
            a_fixed = a_.fixed;
            b_fixed = b_.fixed;
            a_asleep = a_.asleep;
            b_asleep = b_.asleep;
            for body in [a_, b_] {
                if !body.fixed && !body.asleep {
                    let k = body.index();
                    w.stamps[k] = w.stamps[k].wrapping_add(1); // Space::bump, the bodies borrowed
                    self.out.state(body)?;
                }
            }
        }
        if press_a && !self.w.s.bodies[ai].asleep {
            note_rest(&mut self.w, ai, bi, touch, cx, cy, nx, ny);
        }
        if press_b && !self.w.s.bodies[bi].asleep {
            note_rest(&mut self.w, bi, ai, touch, cx, cy, nx, ny);
        }
        self.touch(t, (ai, bi, feature, i, j));
        // an impulse changes the motion of what it hit: what they carried leaves
        // (a sleeper a gentle touch left asleep has not moved: what slides on it stays)
        let mut left = Vec::new();
        if imp != 0.0 {
            for k in [ai, bi] {
                if !self.w.s.bodies[k].fixed && !self.w.s.bodies[k].asleep {
                    self.release(k, t, &mut left)?;
                }
            }
        }
        self.fetch_next();
        if !a_fixed && !a_asleep {
            predict_body::<E>(&self.w, &mut self.q, ai, t, if b_asleep && imp == 0.0 { Some(bi) } else { None })?;
        }
        if !b_fixed && !b_asleep {
            let skip_a = (!a_fixed && !a_asleep) || (a_asleep && imp == 0.0);
            predict_body::<E>(&self.w, &mut self.q, bi, t, if skip_a { Some(ai) } else { None })?;
        }
        self.predict_released(&left, t)
    }

    /// A collision that ends in support (called by handle_collision):
    /// `contact` is (a, b, feature, i, j) of the collision record.  When
    /// the support leaves the body at rest, it falls asleep.
    fn handle_support(
        &mut self,
        t: f64,
        contact: (u32, u32, i32, i32, i32),
        c: (f64, f64),
        n: (f64, f64),
        vn: f64,
    ) -> Res<()> {
        self.q.stats.supports += 1;
        let (a, b, feature, i, j) = contact;
        let (ai, bi) = (a as usize, b as usize);
        {
            let w = &mut self.w;
            let (a_, b_) = two_mut(&mut w.s.bodies, ai, bi);
            let imp = -vn / a_.inv_m;
            if b_.fixed {
                enter_support(&w.s.verts, a_, b_, j);
            } else if b_.asleep {
                enter_support(&w.s.verts, a_, b_, j);
                b_.carry += 1; // a sleeping base counts what it supports
            } else {
                enter_carried(&w.s.verts, a_, b_, j);
            }
            self.out.contact("support", t, a, b, feature, i, j, c, n, imp)?;
            let (px, py, nx, ny) = (c.0, c.1, n.0, n.1);
            self.contacts.push(Contact {
                t,
                a: a as usize,
                b: b as usize,
                feature,
                i,
                j,
                px,
                py,
                nx,
                ny,
                impulse: imp,
                support: true,
            });
        }
        self.touch(t, (ai, bi, feature, i, j));
        if at_rest(&self.w.s.bodies[ai], &self.w.s.bodies[bi], self.w.s.rest_speed) {
            return self.handle_sleep(ai, bi, t);
        }
        self.w.bump(ai);
        self.out.state(&self.w.s.bodies[ai])?;
        self.predict_changed(ai, t)
    }

    /// Sliding stops: velocity exactly the support's (zero when it does
    /// not move), then rest (asleep when at rest) or slide back.
    fn handle_stop(&mut self, t: f64, body: u32) -> Res<()> {
        self.q.stats.stops += 1;
        let ai = body as usize;
        let sup = self.w.s.bodies[ai].sup as usize;
        let (a_, b_) = two_mut(&mut self.w.s.bodies, ai, sup);
        rebase(a_, t);
        if is_static(b_) {
            a_.vx = 0.0;
            a_.vy = 0.0;
        } else {
            let (_, _, bvx, bvy, _) = state_at(b_, t);
            a_.vx = bvx;
            a_.vy = bvy;
        }
        slide_accel(a_, b_, 0.0);
        self.out.support_end("stop", t, a_.idx, a_.sup, a_.sup_edge)?;
        if at_rest(a_, b_, self.w.s.rest_speed) {
            return self.handle_sleep(ai, sup, t);
        }
        if self.w.s.bodies[sup].asleep && !base_holds(&self.w, &self.w.s.bodies[sup], 0.0, 0.0) {
            // sliding back, its friction turned: the sleeping base no longer holds it
            let mut left = Vec::new();
            self.leave(ai, t, None, &mut left)?;
            return self.predict_released(&left, t);
        }
        self.w.bump(ai);
        self.out.state(&self.w.s.bodies[ai])?;
        self.predict_changed(ai, t)
    }

    // ---- sleeping islands -------------------------------------------------

    /// Body a (advanced to t) falls asleep resting on g: frozen (v = a = w
    /// = 0) in g's island, or in a new one numbered a's index when g is
    /// fixed.  Its awake neighbours are predicted against it again.
    pub(super) fn handle_sleep(&mut self, a: usize, g: usize, t: f64) -> Res<()> {
        self.q.stats.sleeps += 1;
        let g_island = if self.w.s.bodies[g].asleep { self.w.s.bodies[g].island } else { a as i32 };
        let sup = self.w.s.bodies[a].sup;
        self.w.rest[a] = if sup >= 0 && self.w.s.bodies[sup as usize].fixed { sup } else { -1 };
        if self.w.s.bodies[a].sup >= 0 {
            end_support(&mut self.w.s.bodies, a);
        }
        let a_ = &mut self.w.s.bodies[a];
        a_.vx = 0.0;
        a_.vy = 0.0;
        a_.om = 0.0;
        a_.ax = 0.0;
        a_.ay = 0.0;
        a_.asleep = true;
        a_.island = g_island;
        self.w.on[a] = [-1; 1 + REST_SLOTS];
        self.w.on[a][0] = g as i32;
        self.w.bump(a);
        self.out.sleep(t, a as u32, g as u32, g_island)?;
        self.out.state(&self.w.s.bodies[a])?;
        self.predict_changed(a, t)
    }

    /// Body a falls asleep on g (handle_sleep); then the body of each noted
    /// contact that still holds (in slot order) is added to what a rests on,
    /// so a jolt on any of them wakes a.
    pub(super) fn handle_sleep_many(&mut self, a: usize, g: usize, touch: Touch, t: f64) -> Res<()> {
        let (others, nh) = holding_bodies(&self.w, a, touch);
        self.handle_sleep(a, g, t)?;
        for (h, &o) in others[..nh].iter().enumerate() {
            self.w.on[a][1 + h] = o as i32;
        }
        Ok(())
    }

    // ---- carried bodies: leaving depth-first -------------------------------

    /// Body a, whose motion changed at t (state written), is predicted again
    /// after what it carried leaves: release, predict_body, predict_released.
    fn predict_changed(&mut self, a: usize, t: f64) -> Res<()> {
        let mut left = Vec::new();
        self.release(a, t, &mut left)?;
        predict_body::<E>(&self.w, &mut self.q, a, t, None)?;
        self.predict_released(&left, t)
    }

    /// Body a leaves its support or carrier at t (E leave, its state: world
    /// velocity kept, free acceleration), then what a carries, depth-first
    /// (release); each appended to `left` with the body its prediction
    /// skips (predict_released).
    fn leave(&mut self, a: usize, t: f64, skip: Option<usize>, left: &mut Vec<(usize, Option<usize>)>) -> Res<()> {
        self.q.stats.leaves += 1;
        rebase(&mut self.w.s.bodies[a], t);
        let (sup, edge) = (self.w.s.bodies[a].sup, self.w.s.bodies[a].sup_edge);
        end_support(&mut self.w.s.bodies, a);
        self.w.bump(a);
        let a_ = &self.w.s.bodies[a];
        self.out.support_end("leave", t, a_.idx, sup, edge)?;
        self.out.state(a_)?;
        left.push((a, skip));
        self.release(a, t, left)
    }

    /// Body b's motion changes at t: every body b carries leaves (by index,
    /// each with what it carries: leave), skipping b in its prediction.
    pub(super) fn release(&mut self, b: usize, t: f64, left: &mut Vec<(usize, Option<usize>)>) -> Res<()> {
        if self.w.s.bodies[b].carry == 0 {
            return Ok(());
        }
        for o in 0..self.w.s.bodies.len() {
            if self.w.s.bodies[o].sup == b as i32 {
                self.leave(o, t, Some(b), left)?;
            }
        }
        Ok(())
    }

    /// Predict the bodies that left (leave), in the order they left, each
    /// but against the body it skips (already predicted with it).
    pub(super) fn predict_released(&mut self, left: &[(usize, Option<usize>)], t: f64) -> Res<()> {
        for &(a, skip) in left {
            predict_body::<E>(&self.w, &mut self.q, a, t, skip)?;
        }
        Ok(())
    }

    /// Sleeper s wakes at t, and with it every sleeper that rests on a
    /// woken body (the upward closure, marked island WAKING): each (by
    /// index) gets its free acceleration back, then fresh predictions (a
    /// pair of woken bodies once).
    pub(super) fn handle_wake(&mut self, s: usize, t: f64) -> Res<()> {
        self.q.stats.wakes += 1;
        self.out.wake(t, s as u32, self.w.s.bodies[s].island)?;
        let n = self.w.s.bodies.len();
        let island = WAKING;
        self.w.s.bodies[s].island = island;
        let mut grown = true;
        while grown {
            grown = false;
            for k in 0..n {
                let b_ = &self.w.s.bodies[k];
                if b_.asleep
                    && b_.island != island
                    && self.w.on[k]
                        .iter()
                        .take_while(|&&g| g >= 0)
                        .any(|&g| self.w.s.bodies[g as usize].island == island)
                {
                    self.w.s.bodies[k].island = island;
                    grown = true;
                }
            }
        }
        for k in 0..n {
            let b_ = &mut self.w.s.bodies[k];
            if b_.asleep && b_.island == island {
                rebase(b_, t);
                b_.asleep = false;
                b_.ax = b_.fax;
                b_.ay = b_.fay;
                self.w.rest[k] = -1;
                self.w.bump(k);
                self.out.state(&self.w.s.bodies[k])?;
            }
        }
        let mut left = Vec::new();
        for k in 0..n {
            if self.w.s.bodies[k].island == island {
                self.release(k, t, &mut left)?; // bodies sliding on a member leave it: it may move
            }
        }
        for k in 0..n {
            if self.w.s.bodies[k].island == island {
                self.predict_woken(k, t, island)?;
            }
        }
        self.predict_released(&left, t)?;
        for b_ in self.w.s.bodies.iter_mut() {
            if b_.island == island {
                b_.island = -1;
            }
        }
        Ok(())
    }

    /// predict_body for a member of a waking island: a pair of two members
    /// is predicted by the one with the smaller index.
    fn predict_woken(&mut self, b: usize, now: f64, island: i32) -> Res<()> {
        let (w, q) = (&self.w, &mut self.q);
        let bodies = &w.s.bodies;
        predict_near::<E>(w, q, b, now, |o| !(bodies[o].island == island && o < b))
    }

    /// The support's edge ends under the body: free motion again.
    fn handle_leave(&mut self, t: f64, body: u32) -> Res<()> {
        let mut left = Vec::new();
        self.leave(body as usize, t, None, &mut left)?;
        self.predict_released(&left, t)
    }

    /// A scripted or live input (scene input k): a velocity set or added,
    /// an impulse through the centre, or a teleport (refused with an error
    /// when the body would overlap another there).
    fn handle_input(&mut self, t: f64, k: u32) -> Res<()> {
        self.q.stats.inputs += 1;
        let inp = self.w.s.inputs[k as usize];
        let a = inp.body as usize;
        if self.w.s.bodies[a].gone {
            return Err(SimError::Msg(format!("input {k}: body {a} was removed before t = {}", g17(t))));
        }
        if self.w.s.bodies[a].asleep {
            self.handle_wake(a, t)?;
        }
        rebase(&mut self.w.s.bodies[a], t);
        if inp.mode != REMOVE {
            self.check_reach(a, k, t, inp.mode, inp.vx, inp.vy)?;
        }
        if inp.mode == REMOVE {
            return self.remove(a, k, t);
        }
        if self.w.s.bodies[a].fixed {
            return self.drive(a, k, t, inp.vx, inp.vy);
        }
        if inp.mode == TELEPORT {
            let s = &self.w.s;
            if let Some(o) = overlapping(&s.bodies, &s.verts, s.tol, &s.bodies[a], Some(a), inp.vx, inp.vy, t) {
                return Err(SimError::Msg(format!(
                    "input {k}: body {a} teleported to ({}, {}) at t = {} would overlap body {o}",
                    g17(inp.vx),
                    g17(inp.vy),
                    g17(t)
                )));
            }
        }
        if self.w.s.bodies[a].sup >= 0 {
            end_support(&mut self.w.s.bodies, a);
        }
        let body = &mut self.w.s.bodies[a];
        if inp.mode == SET_VELOCITY {
            body.vx = inp.vx;
            body.vy = inp.vy;
        } else if inp.mode == ADD_VELOCITY {
            body.vx = body.vx + inp.vx;
            body.vy = body.vy + inp.vy;
        } else if inp.mode == IMPULSE {
            body.vx = body.vx + inp.vx * body.inv_m;
            body.vy = body.vy + inp.vy * body.inv_m;
        } else {
            body.px = inp.vx;
            body.py = inp.vy;
            if !body.large {
                // a large body is in no cell: every body checks it
                let (cx0, cy0) = (body.cx, body.cy);
                let (cx, cy) = cell_of(&self.w.s, inp.vx, inp.vy);
                self.w.grid.remove(a as u32, cx0, cy0);
                let body = &mut self.w.s.bodies[a];
                body.cx = cx;
                body.cy = cy;
                self.w.grid.add(a as u32, cx, cy);
            }
        }
        self.w.bump(a);
        let body = &self.w.s.bodies[a];
        self.out.input(t, body.idx, k)?;
        self.out.state(body)?;
        self.predict_changed(a, t)
    }

    /// Input k (not a removal) on body a, based at t: refused when the
    /// body's motion after it would reach more than 2e150 m from the origin
    /// by the end (the live inputs' rule, from the state at t, left to
    /// right in doubles; a velocity or position that is not finite is
    /// refused by it too).
    fn check_reach(&self, a: usize, k: u32, t: f64, mode: i64, x: f64, y: f64) -> Res<()> {
        let b = &self.w.s.bodies[a];
        let (px, py, vx, vy) = match mode {
            SET_VELOCITY => (b.px, b.py, x, y),
            ADD_VELOCITY => (b.px, b.py, b.vx + x, b.vy + y),
            IMPULSE => (b.px, b.py, b.vx + x * b.inv_m, b.vy + y * b.inv_m),
            _ => (x, y, b.vx, b.vy),
        };
        let end = self.w.s.end;
        let reach =
            (px.abs() + py.abs()) + (vx.abs() + vy.abs()) * end + (b.ax.abs() + b.ay.abs()) * end * end / 2.0 + b.bound;
        if reach <= 2.0 * LENGTH_MAX {
            return Ok(());
        }
        Err(SimError::Msg(format!(
            "input {k}: body {a} at t = {}: reaches more than 2e150 m from the origin by the end",
            g17(t)
        )))
    }

    /// Input k removes body a (based at t): it stops where it is (v, a, w
    /// zero), leaves the grid, its stamp changes (its queued events go
    /// stale) and it is never predicted again; bodies it supported leave.
    fn remove(&mut self, a: usize, k: u32, t: f64) -> Res<()> {
        let body = &mut self.w.s.bodies[a];
        body.vx = 0.0;
        body.vy = 0.0;
        body.ax = 0.0;
        body.ay = 0.0;
        body.fax = 0.0;
        body.fay = 0.0;
        body.om = 0.0;
        if body.sup >= 0 {
            end_support(&mut self.w.s.bodies, a);
        }
        let body = &mut self.w.s.bodies[a];
        body.gone = true;
        let (large, cx, cy, wcells) = (body.large, body.cx, body.cy, body.wcells);
        self.w.bump(a);
        if large {
            self.w.grid.unplace_large(a as u32, wcells);
        } else {
            self.w.grid.remove(a as u32, cx, cy);
        }
        self.out.input(t, a as u32, k)?;
        for o in 0..self.w.s.bodies.len() {
            if self.w.s.bodies[o].sup != a as i32 {
                continue;
            }
            let mut left = Vec::new();
            self.leave(o, t, None, &mut left)?;
            self.predict_released(&left, t)?;
        }
        self.wake_touching(a, t)
    }

    /// Input k sets the velocity of fixed polygon b (based at t, it does not
    /// turn): a large one placed in grid cells moves to the large list for
    /// good; every body it supported leaves (E leave, free motion: it meets
    /// b again at once and is supported again relative to b's new motion,
    /// or bounces, or falls); b is predicted against every body again (a
    /// large b: each small one that is not fixed or removed, in index
    /// order; a small one: predict_body), the bodies that left against the
    /// others; last the sleepers touching b wake (wake_touching: b may have
    /// held them, or carries them into others).
    fn drive(&mut self, b: usize, k: u32, t: f64, vx: f64, vy: f64) -> Res<()> {
        let body = &mut self.w.s.bodies[b];
        body.vx = vx;
        body.vy = vy;
        self.w.stamps[b] = self.w.stamps[b].wrapping_add(1); // Space::bump, the body borrowed
        if let Some(cells) = body.wcells {
            self.w.grid.unplace_large(b as u32, Some(cells));
            body.wcells = None;
            self.w.grid.large.push(b as u32);
        }
        self.out.input(t, b as u32, k)?;
        self.out.state(&self.w.s.bodies[b])?;
        let n = self.w.s.bodies.len();
        let mut left = Vec::new();
        for o in 0..n {
            if self.w.s.bodies[o].sup != b as i32 {
                continue;
            }
            self.leave(o, t, Some(b), &mut left)?;
        }
        if self.w.s.bodies[b].large {
            for o in 0..n {
                let ob = &self.w.s.bodies[o];
                if !ob.large && !ob.gone && !ob.fixed {
                    predict_pair::<E>(&self.w, &mut self.q, o, b, t)?;
                }
            }
        } else {
            predict_body::<E>(&self.w, &mut self.q, b, t, None)?;
        }
        self.predict_released(&left, t)?;
        self.wake_touching(b, t)
    }

    /// The sleepers whose bounding circles reach the body's (within the
    /// tolerance; a body removed, or a fixed one whose velocity an input
    /// set) wake, each with what rests on it: it may have held them (by
    /// index; one woken with an earlier one is awake already).
    fn wake_touching(&mut self, body: usize, t: f64) -> Res<()> {
        let tol = self.w.s.tol;
        let (bx, by, bound) = {
            let b_ = &self.w.s.bodies[body];
            (b_.px, b_.py, b_.bound)
        };
        for o in 0..self.w.s.bodies.len() {
            let o_ = &self.w.s.bodies[o];
            if o_.asleep {
                let dx = o_.px - bx;
                let dy = o_.py - by;
                let reach = o_.bound + bound + tol;
                if dx * dx + dy * dy <= reach * reach {
                    self.handle_wake(o, t)?;
                }
            }
        }
        Ok(())
    }

    /// The body's centre went the grid's margin past its cell's edge along an axis:
    /// move it to the next cell and predict it against the row or column it now neighbours.
    fn handle_cell(&mut self, t: f64, body: u32, axis: i32, direction: i32) -> Res<()> {
        self.q.stats.cells += 1;
        let a = body as usize;
        let d = i64::from(direction);
        let (cx0, cy0) = (self.w.s.bodies[a].cx, self.w.s.bodies[a].cy);
        let (mut cx, mut cy) = (i64::from(cx0), i64::from(cy0));
        let (x_lo, x_hi, y_lo, y_hi);
        if axis == 0 {
            cx += d;
            let col = cx + d;
            (x_lo, x_hi, y_lo, y_hi) = (col, col, cy - 1, cy + 1);
        } else {
            cy += d;
            let row = cy + d;
            (x_lo, x_hi, y_lo, y_hi) = (cx - 1, cx + 1, row, row);
        }
        // the bodies of the row or column it will predict against (their
        // cells were fetched with this event): fetched while it changes cells
        self.w.prefetch_listed(x_lo, x_hi, y_lo, y_hi);
        self.w.grid.remove(body, cx0, cy0);
        // a cell event moves to a neighbouring cell of the grid
        let b_ = &mut self.w.s.bodies[a];
        b_.cx = cx as i32;
        b_.cy = cy as i32;
        self.w.grid.add(body, cx as i32, cy as i32);
        self.fetch_next();
        predict_cells::<E>(&self.w, &mut self.q, a, x_lo, x_hi, y_lo, y_hi, t, None, false)?;
        // the walls of the new row or column but those also listed in the
        // two it shares with the old neighbourhood (predicted at its last
        // change): none when no wall is listed in the new 3x3 block
        let grid = &self.w.grid;
        if !grid.walls_near(cx, cy) {
            schedule_cell(&self.w, &mut self.q, a, t);
            return Ok(());
        }
        let mut shared = Vec::new();
        if axis == 0 {
            let lo = if d > 0 { cx - 1 } else { cx };
            grid.walls_in(a, lo, lo + 1, cy - 1, cy + 1, &mut shared);
        } else {
            let lo = if d > 0 { cy - 1 } else { cy };
            grid.walls_in(a, cx - 1, cx + 1, lo, lo + 1, &mut shared);
        }
        let mut news = Vec::new();
        grid.walls_in(a, x_lo, x_hi, y_lo, y_hi, &mut news);
        news.retain(|o| !shared.contains(o));
        news.sort_unstable();
        news.dedup();
        if !self.w.s.bodies[a].fixed {
            for o in news {
                predict_pair::<E>(&self.w, &mut self.q, a, o as usize, t)?;
            }
        }
        schedule_cell(&self.w, &mut self.q, a, t);
        Ok(())
    }

    fn handle_horizon(&mut self, t: f64, a: u32, b: u32) -> Res<()> {
        self.q.stats.horizons += 1;
        predict_pair::<E>(&self.w, &mut self.q, a as usize, b as usize, t)
    }

    fn handle_frame(&mut self, t: f64, k: i64) -> Res<()> {
        self.q.stats.frames += 1;
        self.out.frame(t)?;
        let nxt = (k + 1) as f64 * self.w.s.frame_dt;
        if nxt <= self.w.s.end {
            self.q.heap.push(nxt, Event::Frame { k: k + 1 });
        }
        Ok(())
    }

    // ---- the run ------------------------------------------------------------

    /// Cells, inputs, the first frame and every pair's first prediction.
    pub(super) fn start(&mut self) -> Res<()> {
        let (w, q) = (&mut self.w, &mut self.q);
        let n = w.s.bodies.len();
        // the cells that body b + AHEAD will be added to, and then predicted
        // against, are fetched while body b is (at 10^5 disks the bodies
        // are read in order, the cells at random); hints only
        const AHEAD: usize = 4;
        for b in 0..n {
            if w.fetch && b + AHEAD < n {
                let ahead = &w.s.bodies[b + AHEAD];
                let (cx, cy) = cell_of(&w.s, ahead.px, ahead.py);
                w.grid.prefetch_cells(i64::from(cx), i64::from(cx), i64::from(cy), i64::from(cy));
            }
            if !w.s.bodies[b].large {
                let (cx, cy) = cell_of(&w.s, w.s.bodies[b].px, w.s.bodies[b].py);
                let body = &mut w.s.bodies[b];
                body.cx = cx;
                body.cy = cy;
                w.grid.add(body.idx, cx, cy);
            }
        }
        for (k, inp) in w.s.inputs.iter().enumerate() {
            q.heap.push(inp.t, Event::Input { k: k as u32 });
        }
        if w.s.frame_dt > 0.0 && w.s.frame_dt <= w.s.end {
            q.heap.push(w.s.frame_dt, Event::Frame { k: 1 });
        }
        for b in 0..n {
            if b + AHEAD < n {
                w.prefetch_block(b + AHEAD);
            }
            let body = &w.s.bodies[b];
            if body.large {
                continue;
            }
            let (cx, cy, fixed) = (i64::from(body.cx), i64::from(body.cy), body.fixed);
            predict_cells::<E>(w, q, b, cx - 1, cx + 1, cy - 1, cy + 1, 0.0, None, true)?;
            for o in w.grid.large_near(b, body.cx, body.cy) {
                let o = o as usize;
                if !(fixed && w.s.bodies[o].fixed) {
                    predict_pair::<E>(w, q, b, o, 0.0)?;
                }
            }
            schedule_cell(w, q, b, 0.0);
        }
        Ok(())
    }

    /// Every body at the end time, the counters and the variants served
    /// (the trace's F, N and V lines; the reference's `finish` after its
    /// last events).
    pub(super) fn write_final(&mut self) -> Res<()> {
        let end = self.w.s.end;
        for b in self.w.s.bodies.iter_mut() {
            rebase(b, end);
        }
        for b in &self.w.s.bodies {
            self.out.final_state(b)?;
        }
        for (name, count) in self.q.stats.lines() {
            self.out.stat(name, count)?;
        }
        for (k, &c) in self.q.cc_counts.iter().enumerate() {
            self.out.variant("circle_circle", k, c)?;
        }
        for (k, &c) in self.q.pe_counts.iter().enumerate() {
            self.out.variant("point_edge", k, c)?;
        }
        Ok(())
    }

    /// Handle one event taken from the queue: drop it when stale, count it
    /// against max_events (every kind: cell crossings and horizons too) and
    /// among the events at one instant (max_same_time), call its kind's handler.
    pub(super) fn dispatch(&mut self, t: f64, ev: Event) -> Res<()> {
        if self.w.is_stale(&ev) {
            self.q.stats.stale += 1;
            return Ok(());
        }
        self.handled += 1;
        if self.handled > self.w.s.max_events {
            let msg = format!(
                "more than {} events (collisions, inputs, frames, cell crossings, horizons) at t = {}: the run was \
                 stopped; raise max_events in the scene or --max-events, or shorten end_time",
                self.w.s.max_events,
                g17(t)
            );
            return Err(SimError::Msg(msg));
        }
        if t == self.last_t {
            self.same += 1;
            if self.same > self.w.s.max_same {
                let msg = format!("more than {} events at t = {}: the scene is stuck", self.w.s.max_same, g17(t));
                return Err(SimError::Msg(msg));
            }
        } else {
            self.last_t = t;
            self.same = 0;
        }
        match ev {
            Event::Input { k } => self.handle_input(t, k),
            Event::Collision { a, b, feature, i, j, .. } => self.handle_collision(t, a, b, feature, i, j),
            Event::Stop { body, .. } => self.handle_stop(t, body),
            Event::Leave { body, .. } => self.handle_leave(t, body),
            Event::Cell { body, axis, direction, .. } => self.handle_cell(t, body, axis, direction),
            Event::Horizon { a, b, .. } => self.handle_horizon(t, a, b),
            Event::Frame { k } => self.handle_frame(t, k),
        }
    }

    /// Have the next event's stamps, bodies and (a cell crossing's) cells
    /// fetched while this one is handled ([`Space::prefetch_event`]), when
    /// fetching pays.  Stale events at the head (up to 8) are dropped
    /// first and counted, as the sweep does (a stale event stays stale:
    /// the same count, the same order of what stays), so that what is
    /// fetched is the event handled next; events this handler schedules
    /// later may still come before it (then the fetch was only early).
    #[inline(never)]
    pub(super) fn fetch_next(&mut self) {
        if !self.w.fetch {
            return;
        }
        let end = self.w.s.end;
        for _ in 0..8 {
            match self.q.heap.peek() {
                Some(e) if self.w.is_stale(&e.ev) => {}
                _ => break,
            }
            let e = self.q.heap.pop().expect("peeked");
            if e.t <= end {
                self.q.stats.stale += 1;
            }
        }
        if let Some(e) = self.q.heap.peek() {
            self.w.prefetch_event(&e.ev);
        }
    }

    /// Handle every queued event before t (inclusive: at t too), in
    /// (t, kind, seq) order, events that handling schedules included.
    pub(super) fn process(&mut self, t: f64, inclusive: bool) -> Res<()> {
        while let Some(top) = self.q.heap.peek() {
            if top.t > t || (top.t == t && !inclusive) {
                return Ok(());
            }
            let e = self.q.heap.pop().expect("peeked");
            self.w.prefetch_bodies(&e.ev);
            self.dispatch(e.t, e.ev)?;
            self.sweep_if_due();
        }
        Ok(())
    }

    /// Drop the stale events once the queue has doubled since the last
    /// sweep.  The reference pops a stale event and counts it when its time
    /// comes (if it is not after the end); a stale event stays stale (stamps
    /// only grow), so it may go earlier and be counted then: the same count,
    /// the same order of what stays, and a queue that holds mostly live
    /// events (at 10^5 disks it held several stale ones per live one).
    #[inline]
    pub(super) fn sweep_if_due(&mut self) {
        if self.q.heap.len() < self.q.sweep_at {
            return;
        }
        let (w, stats, end) = (&self.w, &mut self.q.stats, self.w.s.end);
        let stamps = w.stamps.as_ptr();
        let ahead = |b: u32| {
            if b != u32::MAX {
                // the stamp the stale check reads (a hint: wrapping, never read here)
                prefetch(stamps.wrapping_add(b as usize));
            }
        };
        self.q.heap.sweep(ahead, |e| {
            if !w.is_stale(&e.ev) {
                return false;
            }
            if e.t <= end {
                stats.stale += 1;
            }
            true
        });
        self.q.sweep_at = (2 * self.q.heap.len()).max(SWEEP_FIRST);
    }
}
