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

/// Bits of an entry's key below the kind: the scheduling counter.
const SEQ_BITS: u32 = 60;

/// What happens at a scheduled time.  Bodies are scene indices; a stamp is
/// the body's stamp when the event was scheduled (the event is stale when
/// the body's motion changed since).
#[derive(Clone, Copy, Debug)]
pub enum Event {
    /// Scripted input `k` of the scene (never stale).
    Input { k: u32 },
    /// Feature CC: the circle of `a` against the circle of `b` (j < 0) or
    /// vertex j of `b`; feature PE: the circle of `a` (i < 0) or vertex i of
    /// `a` against edge j of `b`.
    Collision { a: u32, b: u32, feature: i32, i: i32, j: i32, stamp_a: u64, stamp_b: u64 },
    /// A sliding supported body's tangential speed reaches zero.
    Stop { body: u32, stamp: u64 },
    /// A supported body's centre, projected on the support's edge, reaches its end.
    Leave { body: u32, stamp: u64 },
    /// The body's centre crosses into the neighbouring cell along `axis`
    /// (0: x, 1: y) in `direction` (+1 or -1).
    Cell { body: u32, axis: i32, direction: i32, stamp: u64 },
    /// Predict the pair again (bounding circles meet, or a Taylor window ends).
    Horizon { a: u32, b: u32, stamp_a: u64, stamp_b: u64 },
    /// Frame `k`, at k * frame_dt (never stale).
    Frame { k: i64 },
}

impl Event {
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

/// A scheduled event: `key` is kind << 60 | seq, so that (t, key) orders
/// as Python's (t, kind, seq) tuples.
#[derive(Clone, Copy, Debug)]
pub struct Entry {
    pub t: f64,
    key: u64,
    pub ev: Event,
}

impl Entry {
    /// Python's tuple `<` on (t, kind, seq, ...): seq is unique, so the
    /// rest is never reached and the order is total (times are never NaN).
    #[inline(always)]
    fn lt(&self, o: &Entry) -> bool {
        if self.t == o.t {
            self.key < o.key
        } else {
            self.t < o.t
        }
    }
}

/// A 4-ary min-heap of entries, ordered by (t, key).
struct Near {
    v: Vec<Entry>,
}

const ARITY: usize = 4;

impl Near {
    #[inline]
    fn push(&mut self, item: Entry) {
        let mut pos = self.v.len();
        self.v.push(item);
        while pos > 0 {
            let parent = (pos - 1) / ARITY;
            if item.lt(&self.v[parent]) {
                self.v[pos] = self.v[parent];
                pos = parent;
            } else {
                break;
            }
        }
        self.v[pos] = item;
    }

    #[inline]
    fn pop(&mut self) -> Option<Entry> {
        let last = self.v.pop()?;
        if self.v.is_empty() {
            return Some(last);
        }
        let top = self.v[0];
        let n = self.v.len();
        let mut pos = 0;
        loop {
            let first = ARITY * pos + 1;
            if first >= n {
                break;
            }
            let mut best = first;
            for c in first + 1..(first + ARITY).min(n) {
                if self.v[c].lt(&self.v[best]) {
                    best = c;
                }
            }
            if self.v[best].lt(&last) {
                self.v[pos] = self.v[best];
                pos = best;
            } else {
                break;
            }
        }
        self.v[pos] = last;
        Some(top)
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
/// error before the time reached.  The memory is that of the most events
/// pending at once.
pub struct Heap {
    near: Near,
    reached: u64,
    buckets: Vec<Vec<Entry>>,
    /// bit k % 64 of word k / 64 set: bucket k is not empty
    mask: [u64; BUCKETS / 64],
    /// the scheduling counter
    seq: u64,
}

/// Buckets: 16 hex digits of 16 values.
const BUCKETS: usize = 256;

/// The bucket of time bits o above `reached`: 16 i + o's hex digit i, i
/// the highest digit where they differ.
#[inline(always)]
fn bucket_of(o: u64, reached: u64) -> usize {
    let i = (63 - (o ^ reached).leading_zeros()) / 4;
    16 * i as usize + ((o >> (4 * i)) & 15) as usize
}

impl Heap {
    pub fn new() -> Heap {
        Heap {
            near: Near { v: Vec::with_capacity(64) },
            reached: 0,
            buckets: vec![Vec::new(); BUCKETS],
            mask: [0; BUCKETS / 64],
            seq: 0,
        }
    }

    #[inline(always)]
    fn place(&mut self, e: Entry) {
        let o = time_bits(e.t);
        if o <= self.reached {
            self.near.push(e);
        } else {
            let k = bucket_of(o, self.reached);
            self.buckets[k].push(e);
            self.mask[k / 64] |= 1 << (k % 64);
        }
    }

    /// Schedule an event at t (after every event already scheduled at the
    /// same time and of the same kind).
    #[inline]
    pub fn push(&mut self, t: f64, ev: Event) {
        let key = (ev.kind() << SEQ_BITS) | self.seq;
        self.seq += 1;
        self.place(Entry { t, key, ev });
    }

    /// The earliest event: smallest t, then kind, then scheduling order.
    #[inline]
    pub fn pop(&mut self) -> Option<Entry> {
        self.refill();
        self.near.pop()
    }

    /// The earliest event, left queued.
    #[inline]
    pub fn peek(&mut self) -> Option<&Entry> {
        self.refill();
        self.near.v.first()
    }

    /// When the small heap is empty, move the lowest bucket's events there
    /// (its earliest time) or to lower buckets.
    #[inline]
    fn refill(&mut self) {
        if self.near.v.is_empty() {
            let Some(w) = self.mask.iter().position(|&m| m != 0) else {
                return;
            };
            let k = 64 * w + self.mask[w].trailing_zeros() as usize;
            self.mask[w] &= !(1u64 << (k % 64));
            let mut items = std::mem::take(&mut self.buckets[k]);
            self.reached = items.iter().map(|e| time_bits(e.t)).min().expect("a bucket in the mask has events");
            // all of them now differ from the time reached in a lower digit
            for &e in &items {
                self.place(e);
            }
            items.clear();
            self.buckets[k] = items;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Event, Heap, SEQ_BITS};

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
            1 => Event::Collision { a: k as u32, b: 0, feature: 0, i: -1, j: -1, stamp_a: k, stamp_b: 0 },
            2 => Event::Stop { body: k as u32, stamp: 0 },
            3 => Event::Leave { body: k as u32, stamp: 0 },
            4 => Event::Cell { body: k as u32, axis: 0, direction: 1, stamp: k },
            5 => Event::Horizon { a: k as u32, b: 0, stamp_a: k, stamp_b: 0 },
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

    #[test]
    fn heap_pops_in_time_then_kind_then_seq_order() {
        let mut rng = Rng(12345);
        let mut heap = Heap::new();
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
            if rng.next() % 3 != 0 {
                // peek leaves the earliest queued: the pop that follows takes it
                let (pt, pkey) = heap.peek().map(|e| (e.t, e.key)).expect("not empty");
                let e = heap.pop().expect("not empty");
                assert_eq!((pt.to_bits(), pkey), (e.t.to_bits(), e.key));
                let m = first(&pending);
                assert_eq!((e.t.to_bits(), e.ev.kind(), carried(&e.ev)), (pending[m].0.to_bits(), pending[m].1, pending[m].2));
                assert_eq!(e.key, (pending[m].1 << SEQ_BITS) | pending[m].2);
                pending.swap_remove(m);
                now = e.t;
                count += 1;
            }
        }
        while let Some(e) = heap.pop() {
            let m = first(&pending);
            assert_eq!((e.t.to_bits(), e.ev.kind(), carried(&e.ev)), (pending[m].0.to_bits(), pending[m].1, pending[m].2));
            pending.swap_remove(m);
            count += 1;
        }
        assert_eq!(count, all.len());
        // with everything pushed first, the pops are the sorted order
        let mut heap = Heap::new();
        for &(t, kind, seq) in &all {
            heap.push(t, event(kind, seq));
        }
        let mut sorted = all.clone();
        sorted.sort_by(|x, y| x.0.partial_cmp(&y.0).unwrap().then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
        for &(t, kind, seq) in &sorted {
            let e = heap.pop().expect("not empty");
            assert_eq!((e.t, e.ev.kind(), carried(&e.ev)), (t, kind, seq));
        }
        assert!(heap.pop().is_none());
    }
}
