//! The event queue: event records, one per kind with the fields that kind
//! needs (the reference's `InputEvent`, `CollisionEvent`, ...), and the
//! priority queue that pops them in the order of Python's heapq on
//! (t, kind, seq), seq the scheduling counter.

/// Event kinds, in the order they are handled at equal times.
pub const INPUT: u64 = 0;
pub const COLLISION: u64 = 1;
pub const STOP: u64 = 2;
pub const LEAVE: u64 = 3;
pub const CELL: u64 = 4;
pub const HORIZON: u64 = 5;
pub const FRAME: u64 = 6;

/// An item's key (`Item`): the kind in its top bits, then SEQ_BITS of
/// the scheduling counter, then SLOT_BITS of the record's slot.
const SLOT_BITS: u32 = 28;
const SEQ_BITS: u32 = 33;
const KIND_SHIFT: u32 = SLOT_BITS + SEQ_BITS;
const SLOT_MASK: u64 = (1 << SLOT_BITS) - 1;
/// Slots: events queued at once.
const SLOTS: usize = 1 << SLOT_BITS;
const _: () = assert!(KIND_SHIFT + 3 <= 64, "kind, seq and slot must fit 64 bits");
const _: () = assert!(std::mem::size_of::<Item>() == 16);

/// What happens at a scheduled time.  Bodies are scene indices; a stamp is
/// the body's stamp when the event was scheduled (the event is stale when
/// the body's motion changed since).  Stamps are 32 bits, as the C
/// runtime's: a record 8 bytes smaller (a collision's 32, its `Entry` 40)
/// and the stamps 4 bytes a body, which the stale check reads at random.
#[derive(Clone, Copy, Debug)]
pub enum Event {
    /// Scripted input `k` of the scene (never stale).
    Input { k: u32 },
    /// Feature CC: the circle of `a` against the circle of `b` (j < 0) or
    /// vertex j of `b`; feature PE: the circle of `a` (i < 0) or vertex i of
    /// `a` against edge j of `b`.
    Collision { a: u32, b: u32, feature: i32, i: i32, j: i32, stamp_a: u32, stamp_b: u32 },
    /// A sliding supported body's tangential speed reaches zero.
    Stop { body: u32, stamp: u32 },
    /// A supported body's centre, projected on the support's edge, reaches its end.
    Leave { body: u32, stamp: u32 },
    /// The body's centre crosses into the neighbouring cell along `axis`
    /// (0: x, 1: y) in `direction` (+1 or -1).  (cx, cy): the cell it
    /// leaves (the body's own while the record is live), only a hint of
    /// which cells to fetch ahead, never read otherwise (in bytes that
    /// would be padding: a collision's record is the largest).
    Cell { body: u32, axis: i32, direction: i32, cx: i32, cy: i32, stamp: u32 },
    /// Predict the pair again (bounding circles meet, or a Taylor window ends).
    Horizon { a: u32, b: u32, stamp_a: u32, stamp_b: u32 },
    /// Frame `k`, at k * frame_dt (never stale).
    Frame { k: i64 },
}

impl Event {
    /// The first body of the event (a collision's or horizon's `a`), or
    /// u32::MAX for an input or a frame.
    #[inline(always)]
    pub fn body(&self) -> u32 {
        match *self {
            Event::Collision { a, .. } | Event::Horizon { a, .. } => a,
            Event::Cell { body, .. } | Event::Stop { body, .. } | Event::Leave { body, .. } => body,
            Event::Input { .. } | Event::Frame { .. } => u32::MAX,
        }
    }

    /// The kind: the order of events at equal times.
    #[inline(always)]
    pub fn kind(&self) -> u64 {
        match self {
            Event::Input { .. } => INPUT,
            Event::Collision { .. } => COLLISION,
            Event::Stop { .. } => STOP,
            Event::Leave { .. } => LEAVE,
            Event::Cell { .. } => CELL,
            Event::Horizon { .. } => HORIZON,
            Event::Frame { .. } => FRAME,
        }
    }
}

/// A scheduled event as the queue gives it back: its time (as pushed, so
/// -0.0 stays -0.0) and its record.
#[derive(Clone, Copy, Debug)]
pub struct Entry {
    pub t: f64,
    pub ev: Event,
}
const _: () = assert!(std::mem::size_of::<Entry>() == 40);

/// What the queue orders and moves: 16 bytes (as the C runtime's) instead
/// of a whole `Entry`, which waits in `Heap::slab` meanwhile.  `tb`: the
/// bits of t (`time_bits`); `key`: kind, seq and slot (where the record
/// waits), highest first, so that (tb, key) orders as Python's (t, kind,
/// seq) tuples (seq is unique, so the order is total and the slot never
/// decides).  At 10^5 disks the queue holds millions of items; with
/// 24-byte items its splits and appends would be half the simulated
/// last-level misses per event.
#[derive(Clone, Copy, Debug)]
struct Item {
    tb: u64,
    key: u64,
}

impl Item {
    /// (tb, key) as one number: one wide comparison instead of two branches.
    #[inline(always)]
    fn order(&self) -> u128 {
        (u128::from(self.tb) << 64) | u128::from(self.key)
    }

    /// Where the record waits in the slab.
    #[inline(always)]
    fn slot(&self) -> usize {
        (self.key & SLOT_MASK) as usize
    }
}

const ARITY: usize = 4;

/// Moves v[pos] down to its place among its descendants (a 4-ary min-heap
/// on `order`).
// indexed: every iterator form of the children's loop compiles to more instructions in Heap::pop
#[allow(clippy::needless_range_loop)]
#[inline]
fn sift_down(v: &mut [Item], mut pos: usize) {
    let n = v.len();
    let x = v[pos];
    let xo = x.order();
    loop {
        let first = ARITY * pos + 1;
        if first >= n {
            break;
        }
        let mut best = first;
        let mut bo = v[first].order();
        for c in first + 1..(first + ARITY).min(n) {
            let co = v[c].order();
            if co < bo {
                best = c;
                bo = co;
            }
        }
        if bo < xo {
            v[pos] = v[best];
            pos = best;
        } else {
            break;
        }
    }
    v[pos] = x;
}

/// A 4-ary min-heap of items, ordered by (tb, key).
struct Near {
    v: Vec<Item>,
}

impl Near {
    #[inline]
    fn push(&mut self, item: Item) {
        let mut pos = self.v.len();
        self.v.push(item);
        let o = item.order();
        while pos > 0 {
            let parent = (pos - 1) / ARITY;
            if o < self.v[parent].order() {
                self.v[pos] = self.v[parent];
                pos = parent;
            } else {
                break;
            }
        }
        self.v[pos] = item;
    }

    #[inline]
    fn pop(&mut self) -> Option<Item> {
        let last = self.v.pop()?;
        if self.v.is_empty() {
            return Some(last);
        }
        let top = self.v[0];
        self.v[0] = last;
        sift_down(&mut self.v, 0);
        Some(top)
    }

    /// The heap order again after items were taken out (`Heap::sweep`).
    fn heapify(&mut self) {
        let n = self.v.len();
        if n > 1 {
            for pos in (0..=(n - 2) / ARITY).rev() {
                sift_down(&mut self.v, pos);
            }
        }
    }
}

/// The bits of a time as an unsigned integer with the order of the times
/// (-0 counts as +0, as it compares equal).
#[inline(always)]
fn time_bits(t: f64) -> u64 {
    let b = (t + 0.0).to_bits();
    if b >> 63 == 1 {
        !b
    } else {
        b | (1 << 63)
    }
}

/// Asks the processor to bring the cache line at `p` in ahead of its use
/// (a hint only: nothing is read, and nothing changes if it is ignored).
#[inline(always)]
pub(super) fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: PREFETCHT0 reads no memory that a program can observe and
    // cannot fault, whatever the address; SSE, which it needs, is part of
    // every x86-64 processor.
    unsafe {
        std::arch::x86_64::_mm_prefetch::<{ std::arch::x86_64::_MM_HINT_T0 }>(p.cast::<i8>());
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// The event queue: a radix heap on the hex digits of the times' bits.
/// Events at or before the time reached (`reached`, the last time taken
/// from the buckets) wait in a small 4-ary heap ordered by (t, kind, seq);
/// later ones wait unsorted in bucket 16 i + j, i the highest hex digit in
/// which their time differs from the time reached and j their digit there.
/// When the small heap runs empty, the lowest bucket's earliest time
/// becomes the time reached and its events move to the small heap (that
/// time) or to lower buckets (an event moves at most once per digit: 16
/// times, against 64 with a bucket per bit).  So events are
/// appended and scanned in order instead of sifted at random, and the pop
/// order is Python's heapq order on (t, kind, seq) (unique keys: any
/// correct priority queue gives it), also for an event scheduled a rounding
/// error before the time reached.  What moves is a 16-byte `Item`; the
/// record waits in a slot of `slab`, reused once popped (the C runtime's
/// queue has the same structure).  `sweep` drops the stale events.
pub struct Heap {
    near: Near,
    reached: u64,
    buckets: Box<[Vec<Item>; BUCKETS]>,
    /// bit k % 64 of word k / 64 set: bucket k is not empty
    mask: [u64; BUCKETS / 64],
    /// the scheduling counter (below `seq_limit`: then renumbered)
    seq: u64,
    seq_limit: u64,
    /// the records, by slot
    slab: Vec<Entry>,
    /// slots not in use (a stack: the last freed is reused first, while
    /// it is likely still in the cache)
    free: Vec<u32>,
    /// events queued
    len: usize,
    /// times `renumber` ran (the tests check that theirs ran)
    #[cfg(test)]
    renumbered: usize,
}

/// Buckets: 16 hex digits of 16 values.
const BUCKETS: usize = 256;

/// The most records a split fetches ahead at once.
const SPLIT_AHEAD: usize = 32;

/// A lowest bucket of this many events or fewer goes to the small heap
/// whole (as the C runtime's queue): a few events would otherwise go down
/// the digits one split at a time.
const POUR: usize = 16;

/// An emptied bucket keeps its array only up to this many items (as the C
/// runtime's queue).  Each bucket's array grows to the most items it ever
/// held at once, and over a long run most of the 256 fill up in turn to
/// about the whole queue: kept, the arrays' sum grows with the run's
/// length; given back, it stays under the queue's peak plus KEEP a bucket.
const KEEP: usize = 1024;

/// The bucket of time bits o above `reached`: 16 i + o's hex digit i, i
/// the highest digit where they differ.  That is at most 255 already; the
/// mask tells the compiler so, and the buckets (a fixed array) are then
/// indexed without a bounds check.
#[inline(always)]
fn bucket_of(o: u64, reached: u64) -> usize {
    let i = (63 - (o ^ reached).leading_zeros()) / 4;
    (16 * i as usize + ((o >> (4 * i)) & 15) as usize) & (BUCKETS - 1)
}

impl Heap {
    pub fn new() -> Heap {
        Heap {
            near: Near { v: Vec::with_capacity(64) },
            reached: 0,
            buckets: Box::new(std::array::from_fn(|_| Vec::new())),
            mask: [0; BUCKETS / 64],
            seq: 0,
            seq_limit: 1 << SEQ_BITS,
            slab: Vec::new(),
            free: Vec::new(),
            len: 0,
            #[cfg(test)]
            renumbered: 0,
        }
    }

    /// Events queued (stale ones included until they are popped or swept).
    #[inline]
    pub fn len(&self) -> usize {
        self.len
    }

    #[inline(always)]
    fn place(&mut self, x: Item) {
        if x.tb <= self.reached {
            self.near.push(x);
        } else {
            let k = bucket_of(x.tb, self.reached);
            self.buckets[k].push(x);
            self.mask[k / 64] |= 1 << (k % 64);
        }
    }

    /// Schedule an event at t (after every event already scheduled at the
    /// same time and of the same kind).
    #[inline]
    pub fn push(&mut self, t: f64, ev: Event) {
        let e = Entry { t, ev };
        let slot = match self.free.pop() {
            Some(s) => {
                self.slab[s as usize] = e;
                s
            }
            None => {
                assert!(self.slab.len() < SLOTS, "more than 2^28 events queued at once");
                let s = self.slab.len() as u32;
                let grows = self.slab.len() == self.slab.capacity();
                self.slab.push(e);
                if grows {
                    super::huge::advise(&self.slab);
                }
                s
            }
        };
        if self.seq == self.seq_limit {
            self.renumber();
        }
        let key = (ev.kind() << KIND_SHIFT) | (self.seq << SLOT_BITS) | u64::from(slot);
        self.seq += 1;
        self.len += 1;
        self.place(Item { tb: time_bits(t), key });
    }

    /// The scheduling counter has run out of its bits: number the queued
    /// events 0, 1, ... in their order (tb, key).  Two items of the same
    /// time and kind keep their seq order, and no comparison of time or
    /// kind changes, so the pop order is the same; the small heap stays a
    /// heap and each item stays in its bucket (both depend on the order
    /// and the time only).  Once in 2^33 events.
    #[cold]
    #[inline(never)]
    fn renumber(&mut self) {
        #[cfg(test)]
        {
            self.renumbered += 1;
        }
        let mut all: Vec<(u128, u32, u32)> = Vec::with_capacity(self.len);
        for (k, x) in self.near.v.iter().enumerate() {
            all.push((x.order(), BUCKETS as u32, k as u32));
        }
        for (b, v) in self.buckets.iter().enumerate() {
            for (k, x) in v.iter().enumerate() {
                all.push((x.order(), b as u32, k as u32));
            }
        }
        all.sort_unstable_by_key(|e| e.0);
        for (seq, &(_, b, k)) in all.iter().enumerate() {
            let x = if b as usize == BUCKETS {
                &mut self.near.v[k as usize]
            } else {
                &mut self.buckets[b as usize][k as usize]
            };
            let kind = x.key >> KIND_SHIFT;
            x.key = (kind << KIND_SHIFT) | ((seq as u64) << SLOT_BITS) | (x.key & SLOT_MASK);
        }
        self.seq = all.len() as u64;
        assert!(self.seq < self.seq_limit, "fewer events queued than seq numbers");
    }

    /// The earliest event: smallest t, then kind, then scheduling order.
    #[inline]
    pub fn pop(&mut self) -> Option<Entry> {
        self.refill();
        let x = self.near.pop()?;
        let e = self.slab[x.slot()];
        self.free.push(x.slot() as u32);
        self.len -= 1;
        // find the next event now (events scheduled meanwhile before it go
        // to the small heap, which orders them first) and have its record
        // fetched from memory while this one is handled
        self.refill();
        if let Some(next) = self.near.v.first() {
            prefetch(&self.slab[next.slot()]);
        }
        Some(e)
    }

    /// The earliest event, left queued.
    #[inline]
    pub fn peek(&mut self) -> Option<&Entry> {
        self.refill();
        let x = self.near.v.first()?;
        Some(&self.slab[x.slot()])
    }

    /// When the small heap is empty, move the lowest bucket's events there
    /// (its earliest time) or to lower buckets.  The test inline, the move
    /// out of line: a pop asks twice, and most times the small heap has
    /// events (the call's saved registers cost more than the test).
    #[inline(always)]
    fn refill(&mut self) {
        if self.near.v.is_empty() {
            self.split_lowest();
        }
    }

    #[inline(never)]
    fn split_lowest(&mut self) {
        let Some(w) = self.mask.iter().position(|&m| m != 0) else {
            return;
        };
        let k = 64 * w + self.mask[w].trailing_zeros() as usize;
        self.mask[w] &= !(1u64 << (k % 64));
        let mut items = std::mem::take(&mut self.buckets[k]);
        if items.len() <= POUR {
            // few events: all of them to the small heap, and the time
            // reached to the highest time the bucket can hold (its digits
            // above i, then j, then all ones): every other bucket's events
            // are later than that and stay where they are (their highest
            // digit that differs from it, and their digit there, are those
            // they had)
            let i = k >> 4;
            let below = (1u64 << (4 * i)) - 1;
            let above = if i == 15 { 0 } else { !((16u64 << (4 * i)) - 1) };
            self.reached = (self.reached & above) | (((k & 15) as u64) << (4 * i)) | below;
            for &x in &items {
                prefetch(self.slab.as_ptr().wrapping_add(x.slot()));
                self.near.push(x);
            }
        } else {
            self.reached = items.iter().map(|x| x.tb).min().expect("a bucket in the mask has events");
            self.split(&items);
        }
        if items.capacity() <= KEEP {
            items.clear();
            self.buckets[k] = items;
        }
    }

    /// split_lowest's move of the lowest bucket's items (more than POUR),
    /// `reached` their earliest time: to the small heap or lower buckets.
    #[inline(always)]
    fn split(&mut self, items: &[Item]) {
        // the lowest bucket holds the next events (but those pushed later):
        // when they are few, have their records fetched now, so that the pops
        // and peeks that follow (many of stale events, only looked at) do
        // not wait for each in turn (the C runtime's `advance`)
        if items.len() <= SPLIT_AHEAD {
            for x in items {
                // wrapping: the address of a hint, never dereferenced
                prefetch(self.slab.as_ptr().wrapping_add(x.slot()));
            }
        }
        // all of them now differ from the time reached in a lower digit
        for &x in items {
            self.place(x);
        }
    }

    /// Remove every queued event for which `drop` is true (the stale ones:
    /// with lazy invalidation they would otherwise wait until their time,
    /// and outnumber the live ones).  The others keep their keys, so the
    /// pop order of what stays is unchanged.  `ahead` is told the first
    /// body of the event `drop` is asked about some items later (to fetch
    /// what `drop` will read; the record itself is fetched here).
    pub fn sweep(&mut self, mut ahead: impl FnMut(u32), mut drop: impl FnMut(&Entry) -> bool) {
        let (slab, free) = (&self.slab, &mut self.free);
        let mut removed = 0;
        let mut keep = |x: &Item| {
            if drop(&slab[x.slot()]) {
                free.push(x.slot() as u32);
                removed += 1;
                false
            } else {
                true
            }
        };
        retain_ahead(&mut self.near.v, slab, &mut ahead, &mut keep);
        for (k, b) in self.buckets.iter_mut().enumerate() {
            if !b.is_empty() {
                retain_ahead(b, slab, &mut ahead, &mut keep);
                if b.is_empty() {
                    self.mask[k / 64] &= !(1u64 << (k % 64));
                    if b.capacity() > KEEP {
                        *b = Vec::new();
                    }
                }
            }
        }
        self.near.heapify();
        self.len -= removed;
    }
}

/// Vec::retain of the items (`keep` asked about each in order, the kept
/// ones in their order), with the record of the item 2 AHEAD places on
/// prefetched and the first body of the record AHEAD places on (fetched
/// AHEAD items before) told to `ahead`: the items' records lie anywhere
/// in the slab, and at 10^5 bodies a sweep otherwise waits for each in turn.
fn retain_ahead(v: &mut Vec<Item>, slab: &[Entry], ahead: &mut impl FnMut(u32), keep: &mut impl FnMut(&Item) -> bool) {
    const AHEAD: usize = 8;
    let n = v.len();
    let mut kept = 0;
    for r in 0..n {
        if r + 2 * AHEAD < n {
            prefetch(slab.as_ptr().wrapping_add(v[r + 2 * AHEAD].slot()));
        }
        if r + AHEAD < n {
            ahead(slab[v[r + AHEAD].slot()].ev.body());
        }
        let x = v[r];
        if keep(&x) {
            v[kept] = x;
            kept += 1;
        }
    }
    v.truncate(kept);
}

impl Default for Heap {
    fn default() -> Heap {
        Heap::new()
    }
}

#[cfg(test)]
mod tests {
    use super::{Event, Heap};

    /// xorshift64*: reproducible numbers without a dependency.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
    }

    /// An event of kind `kind` (0..7) that carries `k`.
    fn event(kind: u64, k: u64) -> Event {
        let e = match kind {
            0 => Event::Input { k: k as u32 },
            1 => Event::Collision { a: k as u32, b: 0, feature: 0, i: -1, j: -1, stamp_a: k as u32, stamp_b: 0 },
            2 => Event::Stop { body: k as u32, stamp: 0 },
            3 => Event::Leave { body: k as u32, stamp: 0 },
            4 => Event::Cell { body: k as u32, axis: 0, direction: 1, cx: 0, cy: 0, stamp: k as u32 },
            5 => Event::Horizon { a: k as u32, b: 0, stamp_a: k as u32, stamp_b: 0 },
            _ => Event::Frame { k: k as i64 },
        };
        assert_eq!(e.kind(), kind);
        e
    }

    /// The number an event carries.
    fn carried(ev: &Event) -> u64 {
        match *ev {
            Event::Input { k } => u64::from(k),
            Event::Collision { a, .. } => u64::from(a),
            Event::Stop { body, .. } | Event::Leave { body, .. } => u64::from(body),
            Event::Cell { body, .. } => u64::from(body),
            Event::Horizon { a, .. } => u64::from(a),
            Event::Frame { k } => k as u64,
        }
    }

    /// A queue whose scheduling counter runs out after `limit` events (its
    /// own: 2^33), so that the tests renumber it many times.
    fn new_heap(limit: Option<u64>) -> Heap {
        let mut h = Heap::new();
        if let Some(l) = limit {
            h.seq_limit = l;
        }
        h
    }

    #[test]
    fn heap_pops_in_time_then_kind_then_seq_order() {
        pops_in_time_then_kind_then_seq_order(None);
    }

    #[test]
    fn renumbered_heap_pops_in_time_then_kind_then_seq_order() {
        // the counter runs out after 8192 pushes, and again after each
        // renumbering (of up to about 7000 events queued)
        pops_in_time_then_kind_then_seq_order(Some(1 << 13));
    }

    fn pops_in_time_then_kind_then_seq_order(limit: Option<u64>) {
        let mut rng = Rng(12345);
        let mut heap = new_heap(limit);
        // (t, kind, seq)
        let mut all: Vec<(f64, u64, u64)> = Vec::new();
        let mut pending: Vec<(f64, u64, u64)> = Vec::new();
        let first = |v: &Vec<(f64, u64, u64)>| -> usize {
            let mut m = 0;
            for k in 1..v.len() {
                if (v[k].0, v[k].1, v[k].2) < (v[m].0, v[m].1, v[m].2) {
                    m = k;
                }
            }
            m
        };
        let mut now = 0.0;
        let mut count = 0;
        for seq in 0..20_000u64 {
            // few distinct times, so that equal times are ordered by kind and
            // seq; some before the time reached (as a rounding error can put
            // them), some -0.0 (equal to 0.0)
            let t = match rng.next() % 8 {
                0 => now - (rng.next() % 4) as f64 * 0.125,
                1 => -0.0,
                _ => now + (rng.next() % 50) as f64 * 0.125,
            };
            let kind = rng.next() % 7;
            heap.push(t, event(kind, seq));
            all.push((t, kind, seq));
            pending.push((t, kind, seq));
            if !rng.next().is_multiple_of(3) {
                // peek leaves the earliest queued: the pop that follows takes it
                let peeked = heap.peek().map(|e| (e.t.to_bits(), e.ev.kind(), carried(&e.ev))).expect("not empty");
                let e = heap.pop().expect("not empty");
                assert_eq!(peeked, (e.t.to_bits(), e.ev.kind(), carried(&e.ev)));
                let m = first(&pending);
                assert_eq!(
                    (e.t.to_bits(), e.ev.kind(), carried(&e.ev)),
                    (pending[m].0.to_bits(), pending[m].1, pending[m].2)
                );
                pending.swap_remove(m);
                now = e.t;
                count += 1;
            }
        }
        while let Some(e) = heap.pop() {
            let m = first(&pending);
            assert_eq!(
                (e.t.to_bits(), e.ev.kind(), carried(&e.ev)),
                (pending[m].0.to_bits(), pending[m].1, pending[m].2)
            );
            pending.swap_remove(m);
            count += 1;
        }
        assert_eq!(count, all.len());
        if limit.is_some() {
            assert!(heap.renumbered >= 2, "renumbered {} times", heap.renumbered);
        }
        // with everything pushed first, the pops are the sorted order (all
        // 20,000 queued at once: a counter of 2^15 then, never renumbered)
        let mut heap = new_heap(limit.map(|_| 1 << 15));
        for &(t, kind, seq) in &all {
            heap.push(t, event(kind, seq));
        }
        let widest = |h: &Heap| h.buckets.iter().map(Vec::capacity).max().expect("256 buckets");
        assert!(widest(&heap) > super::KEEP, "a bucket holds more than KEEP items");
        let mut sorted = all.clone();
        sorted.sort_by(|x, y| x.0.partial_cmp(&y.0).unwrap().then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
        for &(t, kind, seq) in &sorted {
            let e = heap.pop().expect("not empty");
            assert_eq!((e.t, e.ev.kind(), carried(&e.ev)), (t, kind, seq));
        }
        assert!(heap.pop().is_none());
        // the emptied buckets gave back their arrays of more than KEEP items
        assert!(widest(&heap) <= super::KEEP, "a bucket keeps {} items' room", widest(&heap));
    }

    #[test]
    fn sweep_drops_what_it_is_told_and_keeps_the_order_of_the_rest() {
        sweep_drops_and_keeps_the_order(None);
    }

    #[test]
    fn renumbered_sweep_drops_what_it_is_told_and_keeps_the_order_of_the_rest() {
        sweep_drops_and_keeps_the_order(Some(1 << 14));
    }

    fn sweep_drops_and_keeps_the_order(limit: Option<u64>) {
        let mut rng = Rng(777);
        let mut heap = new_heap(limit);
        let mut pending: Vec<(f64, u64, u64)> = Vec::new();
        let mut now = 0.0;
        let mut swept = 0;
        for seq in 0..30_000u64 {
            let t = now + (rng.next() % 300) as f64 * 0.0625;
            let kind = rng.next() % 7;
            heap.push(t, event(kind, seq));
            pending.push((t, kind, seq));
            match rng.next() % 100 {
                0..=1 => {
                    // drop the events carrying a multiple of a random divisor
                    let d = 2 + rng.next() % 5;
                    let before = heap.len();
                    heap.sweep(|_| {}, |e| carried(&e.ev).is_multiple_of(d));
                    pending.retain(|p| p.2 % d != 0);
                    assert_eq!(heap.len(), pending.len());
                    swept += before - heap.len();
                }
                2..=60 => {
                    let e = heap.pop().expect("not empty");
                    let m = (0..pending.len())
                        .min_by(|&x, &y| {
                            let (a, b) = (pending[x], pending[y]);
                            a.0.partial_cmp(&b.0).unwrap().then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2))
                        })
                        .expect("not empty");
                    assert_eq!(
                        (e.t.to_bits(), e.ev.kind(), carried(&e.ev)),
                        (pending[m].0.to_bits(), pending[m].1, pending[m].2)
                    );
                    pending.swap_remove(m);
                    now = e.t;
                }
                _ => {}
            }
        }
        assert!(swept > 1000, "the sweeps dropped {swept} events");
        if limit.is_some() {
            assert!(heap.renumbered >= 1, "renumbered {} times", heap.renumbered);
        }
        pending.sort_by(|x, y| x.0.partial_cmp(&y.0).unwrap().then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
        for &(t, kind, seq) in &pending {
            let e = heap.pop().expect("not empty");
            assert_eq!((e.t, e.ev.kind(), carried(&e.ev)), (t, kind, seq));
        }
        assert!(heap.pop().is_none() && heap.len() == 0);
    }
}
