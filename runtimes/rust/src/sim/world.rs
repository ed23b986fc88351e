//! What the simulator holds: the world a prediction reads (scene, bodies'
//! stamps, grid) and the queue a prediction writes (events, counters).
//! Two values, so that a prediction borrows the world and the queue apart.

use super::grid::{place_large, Grid, INLINE_IDS};
use super::queue::{prefetch, Event, Heap};
use super::scene::{Body, Scene};

/// The counters written as the trace's N lines (in [`Stats::lines`] order).
#[derive(Clone, Copy, Default)]
pub struct Stats {
    pub collisions: u64,
    pub inputs: u64,
    pub frames: u64,
    pub cells: u64,
    pub horizons: u64,
    pub stale: u64,
    /// pairs predicted
    pub pairs: u64,
    /// generated entries called (every variant of both equations)
    pub features: u64,
    /// collisions that ended in support
    pub supports: u64,
    pub stops: u64,
    pub leaves: u64,
    pub sleeps: u64,
    pub wakes: u64,
}

impl Stats {
    /// (name, count) in the order of the trace's N lines (STAT_NAMES).
    pub fn lines(&self) -> [(&'static str, u64); 13] {
        [
            ("collisions", self.collisions),
            ("inputs", self.inputs),
            ("frames", self.frames),
            ("cells", self.cells),
            ("horizons", self.horizons),
            ("stale", self.stale),
            ("pairs", self.pairs),
            ("features", self.features),
            ("supports", self.supports),
            ("stops", self.stops),
            ("leaves", self.leaves),
            ("sleeps", self.sleeps),
            ("wakes", self.wakes),
        ]
    }
}

/// The scene, the bodies' states, the grid.
pub struct Space {
    pub s: Scene,
    /// per body, bumped whenever its motion changes (lazy invalidation;
    /// [`Space::bump`]: wraps after 2^32 changes, so a record would be
    /// taken for live only if its body changed exactly a multiple of 2^32
    /// times since it was scheduled)
    pub stamps: Vec<u32>,
    pub grid: Grid,
    /// whether to fetch the next event's bodies and cells ahead ([`Space::choose_fetch`])
    pub fetch: bool,
    /// per body: asleep, the fixed body it fell asleep supported on (its
    /// edge's tangent kept in `tx`, `ty`), else -1 (the body record is full)
    pub rest: Vec<i32>,
    /// per body: its last [`REST_SLOTS`] slow contacts, the last first
    /// (sleeping on several contacts, [`super::sleep::can_sleep_many`])
    pub restc: Vec<[RestContact; REST_SLOTS]>,
    /// per body: asleep, the bodies it rests on, its support first, -1
    /// after the last (a jolt on any of them wakes it)
    pub on: Vec<[i32; 1 + REST_SLOTS]>,
}

/// Slow contacts kept per body ([`super::sleep::note_rest`]).
pub const REST_SLOTS: usize = 4;

/// A movable body's slow contact with another (a hop), for sleeping on
/// several contacts (docs/simulator.md, "Several contacts").
#[derive(Clone, Copy, Default)]
pub struct RestContact {
    /// m: the contact point
    pub px: f64,
    pub py: f64,
    /// unit normal from the body to the other
    pub mx: f64,
    pub my: f64,
    /// m, m, rad: the other body's position and angle then
    pub gx: f64,
    pub gy: f64,
    pub gang: f64,
    /// m, m, rad: the body's own position and angle then
    pub bx: f64,
    pub by: f64,
    pub bang: f64,
    /// the other body's index + 1; 0: no contact
    pub other1: i32,
    /// the collision's feature and its i, j
    pub feature: i32,
    pub i: i32,
    pub j: i32,
    /// whether the body was the collision's a
    pub side: bool,
}

/// Fetching ahead pays where the bodies and cells miss the cache (the
/// gas's are 2.9 MB at 10^4 disks, 29 MB at 10^5); where they stay in a core's
/// second-level cache it is only its instructions.  So the fetches of
/// [`Space::prefetch_block`], [`Space::prefetch_neighbours`] and
/// `World::fetch_next` are made only above this many bytes of bodies and
/// cells (the C runtime's M2C_SIM_FETCH_BYTES, about a core's L2 on the
/// machine measured).
const FETCH_BYTES: usize = 1 << 20;

impl Space {
    pub fn new(mut s: Scene) -> Space {
        let stamps = vec![0; s.bodies.len()];
        let rest = vec![-1; s.bodies.len()];
        let mut grid = Grid::new(&s);
        for b in 0..s.bodies.len() {
            if s.bodies[b].large {
                place_large(&mut grid, &mut s, b);
            }
        }
        let restc = vec![[RestContact::default(); REST_SLOTS]; s.bodies.len()];
        let on = vec![[-1; 1 + REST_SLOTS]; s.bodies.len()];
        let mut w = Space { s, stamps, grid, fetch: false, rest, restc, on };
        w.choose_fetch();
        w
    }

    /// Body b's motion changed: its queued events are stale.
    #[inline(always)]
    pub fn bump(&mut self, b: usize) {
        self.stamps[b] = self.stamps[b].wrapping_add(1);
    }

    /// Whether to fetch ahead, from the bodies' and cells' bytes now (the
    /// scene read, or a body added).
    pub fn choose_fetch(&mut self) {
        let bytes = (self.s.bodies.len() + 1) * std::mem::size_of::<Body>() + self.grid.cell_bytes();
        self.fetch = bytes > FETCH_BYTES;
    }

    /// An event whose bodies' motion changed since it was scheduled.
    /// Inputs are scripted, not predicted, and frames have no bodies: never.
    #[inline(always)]
    pub fn is_stale(&self, ev: &Event) -> bool {
        match *ev {
            Event::Collision { a, b, stamp_a, stamp_b, .. } | Event::Horizon { a, b, stamp_a, stamp_b } => {
                self.stamps[a as usize] != stamp_a || self.stamps[b as usize] != stamp_b
            }
            Event::Cell { body, stamp, .. } | Event::Stop { body, stamp } | Event::Leave { body, stamp } => {
                self.stamps[body as usize] != stamp
            }
            Event::Input { .. } | Event::Frame { .. } => false,
        }
    }
}

impl Space {
    /// Have the cache lines of the event's bodies that its handler reads
    /// fetched while the stale check waits for their stamps (at 10^5
    /// bodies they are rarely still in the cache when their event comes):
    /// a collision's three (docs of [`Body`]), a cell crossing's or a
    /// horizon's two.  A hint only: nothing is read.
    #[inline(always)]
    pub fn prefetch_bodies(&self, ev: &Event) {
        let bodies = self.s.bodies.as_ptr();
        let lines = |b: u32, n: usize| {
            // wrapping: the address of a hint, never dereferenced
            let p = bodies.wrapping_add(b as usize).cast::<u8>();
            for k in 0..n {
                prefetch(p.wrapping_add(64 * k));
            }
        };
        match *ev {
            Event::Collision { a, b, .. } => {
                lines(a, 3);
                lines(b, 3);
            }
            Event::Horizon { a, b, .. } => {
                lines(a, 2);
                lines(b, 2);
            }
            Event::Cell { body, .. } => lines(body, 2),
            _ => {}
        }
    }

    /// Have the 3x3 cells around small body b fetched (what predicting it
    /// reads of the grid), when fetching pays.  A hint only.
    #[inline(always)]
    pub fn prefetch_block(&self, b: usize) {
        let body = &self.s.bodies[b];
        if self.fetch && !body.large {
            self.grid.prefetch_block(i64::from(body.cx), i64::from(body.cy));
        }
    }

    /// Have the two prediction lines of the bodies listed (inline) in the
    /// 3x3 cells around small body b fetched, when fetching pays: to be
    /// asked a while after [`Space::prefetch_block`], when those cells have
    /// come (reading them is real).  A hint only for the bodies.
    #[inline(always)]
    pub fn prefetch_neighbours(&self, b: usize) {
        let body = &self.s.bodies[b];
        if self.fetch && !body.large {
            let (cx, cy) = (i64::from(body.cx), i64::from(body.cy));
            self.prefetch_listed(cx - 1, cx + 1, cy - 1, cy + 1);
        }
    }

    /// The same for the cells x_lo..=x_hi, y_lo..=y_hi (clamped to the grid).
    #[inline(always)]
    pub fn prefetch_listed(&self, x_lo: i64, x_hi: i64, y_lo: i64, y_hi: i64) {
        if self.fetch {
            let bodies = self.s.bodies.as_ptr();
            let mut ids = [0u32; INLINE_IDS];
            let n = self.grid.inline_ids(x_lo, x_hi, y_lo, y_hi, &mut ids);
            for &o in &ids[..n] {
                // wrapping: the address of a hint, never dereferenced
                let p = bodies.wrapping_add(o as usize).cast::<u8>();
                prefetch(p);
                prefetch(p.wrapping_add(64));
            }
        }
    }

    /// Have what the event `ev` (next in the queue) will read fetched: its
    /// bodies' stamps (the stale check's), a collision's bodies' three
    /// lines, a cell crossing's body and the cells it leaves, enters and
    /// predicts against (from the cell its record says it leaves: a hint).
    #[inline(always)]
    pub fn prefetch_event(&self, ev: &Event) {
        let stamps = self.stamps.as_ptr();
        match *ev {
            Event::Collision { a, b, .. } => {
                prefetch(stamps.wrapping_add(a as usize));
                prefetch(stamps.wrapping_add(b as usize));
                self.prefetch_bodies(ev);
            }
            Event::Horizon { a, b, .. } => {
                prefetch(stamps.wrapping_add(a as usize));
                prefetch(stamps.wrapping_add(b as usize));
            }
            Event::Cell { body, axis, direction, cx, cy, .. } => {
                prefetch(stamps.wrapping_add(body as usize));
                self.prefetch_bodies(ev);
                let (cx, cy, d) = (i64::from(cx), i64::from(cy), i64::from(direction));
                let g = &self.grid;
                if axis == 0 {
                    g.prefetch_cells(cx, cx + 2 * d, cy, cy);
                    g.prefetch_cells(cx + 2 * d, cx + 2 * d, cy - 1, cy + 1);
                } else {
                    g.prefetch_cells(cx, cx, cy, cy + d);
                    g.prefetch_cells(cx - 1, cx + 1, cy + 2 * d, cy + 2 * d);
                }
            }
            Event::Stop { body, .. } | Event::Leave { body, .. } => prefetch(stamps.wrapping_add(body as usize)),
            Event::Input { .. } | Event::Frame { .. } => {}
        }
    }
}

/// The queue is first swept of stale events when it holds this many, then
/// whenever it has doubled since the last sweep (as in the C runtime).
pub const SWEEP_FIRST: usize = 4096;

/// The event queue and the counters (everything a prediction changes).
pub struct Queue {
    pub heap: Heap,
    pub stats: Stats,
    /// predictions served per variant of circle_circle and point_edge
    pub cc_counts: Vec<u64>,
    pub pe_counts: Vec<u64>,
    /// events queued at which the stale ones are swept out (`World::sweep_if_due`)
    pub sweep_at: usize,
}

impl Queue {
    pub fn new(cc_variants: usize, pe_variants: usize) -> Queue {
        Queue {
            heap: Heap::new(),
            stats: Stats::default(),
            cc_counts: vec![0; cc_variants],
            pe_counts: vec![0; pe_variants],
            sweep_at: SWEEP_FIRST,
        }
    }

    #[allow(clippy::too_many_arguments)]
    #[inline]
    pub fn push_collision(&mut self, w: &Space, t: f64, feature: i32, a: &Body, b: &Body, i: i32, j: i32) {
        let (stamp_a, stamp_b) = (w.stamps[a.index()], w.stamps[b.index()]);
        self.heap.push(t, Event::Collision { a: a.idx, b: b.idx, feature, i, j, stamp_a, stamp_b });
    }

    #[inline]
    pub fn push_horizon(&mut self, w: &Space, t: f64, a: &Body, b: &Body) {
        let (stamp_a, stamp_b) = (w.stamps[a.index()], w.stamps[b.index()]);
        self.heap.push(t, Event::Horizon { a: a.idx, b: b.idx, stamp_a, stamp_b });
    }

    #[inline]
    pub fn push_cell(&mut self, w: &Space, t: f64, b: &Body, axis: i32, direction: i32) {
        let (cx, cy) = (b.cx, b.cy);
        self.heap.push(t, Event::Cell { body: b.idx, axis, direction, cx, cy, stamp: w.stamps[b.index()] });
    }
}
