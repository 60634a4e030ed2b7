//! A calendar queue with one entry per sphere: a small binary heap for the current stretch
//! of time, unordered lists for the stretches after it, and an overflow list beyond them
//! (Paul's scheme, as event-driven MD codes use it). Scheduling and removal are O(1) outside
//! the heap, and the heap holds only the events of the next few dozen.
//!
//! Order is by `(time, tie, id)`, exactly as [`kinetic_core::kds::EventQueue`] orders, so runs are the same
//! whichever queue holds the events.

use kinetic_core::Real;
use kinetic_core::prefetch;

/// Not scheduled.
const ABSENT: u32 = u32::MAX;
/// A place at or above this is a list (the rest: the bucket's index, `buckets` for the
/// overflow); below it, a heap position.
const LISTED: u32 = 1 << 31;
/// No entry in a list.
const END: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct Slot<P> {
    time: Real,
    tie: u64,
    place: u32,
    prev: u32,
    next: u32,
    payload: P,
}

/// A heap entry: the key and the payload inline, so that sifting and popping read the heap
/// alone.
#[derive(Clone, Copy, Debug)]
struct Entry<P> {
    time: Real,
    tie: u64,
    id: u32,
    payload: P,
}

impl<P> Entry<P> {
    /// Whether this entry comes first: earlier, or at the same time with a lower tie and
    /// id. Times are seldom equal, so the one branch, on equal times, is well predicted, and
    /// a heap picks a child by the times' comparison alone.
    #[inline]
    fn before(&self, other: &Entry<P>) -> bool {
        if self.time == other.time {
            (self.tie, self.id) < (other.tie, other.id)
        } else {
            self.time < other.time
        }
    }
}

/// The queue: each id's entry carries a payload `P` that the queue hands back with it.
#[derive(Clone, Debug)]
pub(super) struct Calendar<P> {
    slots: Vec<Slot<P>>,
    heap: Vec<Entry<P>>,
    /// Heads of the bucket lists, then the overflow list's.
    heads: Vec<u32>,
    /// The inverse of the bucket width, and the time of bucket 0.
    inv_width: Real,
    origin: Real,
    /// The current bucket (absolute number): the heap holds every event of buckets up to it;
    /// and its place in the ring of `buckets` lists.
    current: u64,
    current_slot: u64,
    buckets: u64,
    len: usize,
    listed: usize,
}

impl<P: Copy + Default> Calendar<P> {
    /// An empty queue for ids below `ids`, with buckets `width` wide, `buckets` of them
    /// after the current one, starting at time `origin`.
    pub(super) fn new(ids: usize, width: Real, buckets: usize, origin: Real) -> Calendar<P> {
        let width = if width.is_finite() && width > 0.0 {
            width
        } else {
            1.0
        };
        let buckets = buckets.clamp(1, (LISTED - 2) as usize);
        Calendar {
            slots: vec![
                Slot {
                    time: Real::INFINITY,
                    tie: u64::MAX,
                    place: ABSENT,
                    prev: END,
                    next: END,
                    payload: P::default(),
                };
                ids
            ],
            heap: Vec::new(),
            heads: vec![END; buckets + 1],
            inv_width: 1.0 / width,
            origin,
            current: 0,
            current_slot: 0,
            buckets: buckets as u64,
            len: 0,
            listed: 0,
        }
    }

    fn buckets(&self) -> u64 {
        self.buckets
    }

    fn entry(&self, id: u32) -> Entry<P> {
        let s = &self.slots[id as usize];
        Entry {
            time: s.time,
            tie: s.tie,
            id,
            payload: s.payload,
        }
    }

    /// The time of the earliest event, or infinity.
    pub(super) fn next_time(&self) -> Real {
        self.heap.first().map_or(Real::INFINITY, |e| e.time)
    }

    /// The time, tie and payload `id` is scheduled with, if it is.
    pub(super) fn get(&self, id: u32) -> Option<(Real, u64, P)> {
        let s = &self.slots[id as usize];
        (s.place != ABSENT).then_some((s.time, s.tie, s.payload))
    }

    /// The earliest event: its id, time and payload.
    pub(super) fn peek(&self) -> Option<(u32, Real, P)> {
        self.heap.first().map(|e| (e.id, e.time, e.payload))
    }

    /// Asks for `id`'s entry to be fetched.
    #[inline]
    pub(super) fn prefetch(&self, id: u32) {
        prefetch(&self.slots[id as usize]);
    }

    /// The entries that come next after the earliest when nothing is scheduled meanwhile:
    /// the heap's second and third (either may be the next).
    pub(super) fn following(&self) -> impl Iterator<Item = (u32, P)> + '_ {
        self.heap.iter().skip(1).take(2).map(|e| (e.id, e.payload))
    }

    /// Schedules `id` at `(time, tie)` with `payload`, replacing its entry.
    pub(super) fn schedule(&mut self, id: u32, time: Real, tie: u64, payload: P) {
        let place = self.slots[id as usize].place;
        let bucket = (time - self.origin) * self.inv_width;
        if place < LISTED && bucket < (self.current + 1) as Real {
            // In the heap, and staying there: move it in place.
            let s = &mut self.slots[id as usize];
            (s.time, s.tie, s.payload) = (time, tie, payload);
            let pos = place as usize;
            self.heap[pos] = Entry {
                time,
                tie,
                id,
                payload,
            };
            let e = self.heap[pos];
            if pos > 0 && e.before(&self.heap[(pos - 1) / 2]) {
                self.sift_up(pos);
            } else {
                self.sift_down(pos);
            }
            return;
        }
        self.remove(id);
        let s = &mut self.slots[id as usize];
        s.time = time;
        s.tie = tie;
        s.payload = payload;
        self.len += 1;
        if bucket < (self.current + 1) as Real || time.is_nan() {
            self.heap_push(id);
        } else if bucket < (self.current + 1 + self.buckets) as Real {
            // The ring's place of that bucket, from the current one's without a division.
            let mut b = self.current_slot + (bucket as u64 - self.current);
            if b >= self.buckets {
                b -= self.buckets;
            }
            self.link(id, b as u32);
        } else {
            let overflow = self.buckets() as u32;
            self.link(id, overflow);
        }
        if self.heap.is_empty() {
            self.refill();
        }
    }

    /// Removes `id`'s entry, if any; returns its time.
    pub(super) fn remove(&mut self, id: u32) -> Option<Real> {
        let place = self.slots[id as usize].place;
        if place == ABSENT {
            return None;
        }
        self.len -= 1;
        if place >= LISTED {
            self.unlink(id, place - LISTED);
        } else {
            self.heap_remove(place as usize);
        }
        self.slots[id as usize].place = ABSENT;
        if self.heap.is_empty() && self.len > 0 {
            self.refill();
        }
        Some(self.slots[id as usize].time)
    }

    fn link(&mut self, id: u32, bucket: u32) {
        let head = self.heads[bucket as usize];
        let s = &mut self.slots[id as usize];
        s.place = LISTED + bucket;
        s.prev = END;
        s.next = head;
        if head != END {
            self.slots[head as usize].prev = id;
        }
        self.heads[bucket as usize] = id;
        self.listed += 1;
    }

    fn unlink(&mut self, id: u32, bucket: u32) {
        let Slot { prev, next, .. } = self.slots[id as usize];
        if prev == END {
            self.heads[bucket as usize] = next;
        } else {
            self.slots[prev as usize].next = next;
        }
        if next != END {
            self.slots[next as usize].prev = prev;
        }
        self.listed -= 1;
    }

    /// Moves on, bucket by bucket, until the heap holds an event (or nothing is left); the
    /// overflow is sorted out again each time the buckets come round.
    fn refill(&mut self) {
        while self.heap.is_empty() && self.listed > 0 {
            self.current += 1;
            self.current_slot += 1;
            let n = self.buckets();
            if self.current_slot == n {
                self.current_slot = 0;
                self.spill_overflow();
            }
            let b = self.current_slot as usize;
            let mut id = std::mem::replace(&mut self.heads[b], END);
            while id != END {
                let next = self.slots[id as usize].next;
                self.listed -= 1;
                self.heap_push(id);
                id = next;
            }
            if self.heap.is_empty()
                && self.listed > 0
                && self.heads[..n as usize].iter().all(|&h| h == END)
            {
                // Only the overflow holds events: jump to its earliest bucket.
                let mut earliest = Real::INFINITY;
                let mut id = self.heads[n as usize];
                while id != END {
                    earliest = earliest.min(self.slots[id as usize].time);
                    id = self.slots[id as usize].next;
                }
                let at = ((earliest - self.origin) * self.inv_width).floor();
                if at.is_finite() && at > self.current as Real {
                    // Land on the round's start below it, so the spill sees it.
                    let at = at as u64;
                    self.current = (at - at % n).max(self.current) - 1;
                    self.current_slot = self.current % n;
                } else {
                    self.spill_all();
                }
            }
        }
    }

    /// Re-files the overflow list's events that now fall within the buckets.
    fn spill_overflow(&mut self) {
        let n = self.buckets();
        let mut id = std::mem::replace(&mut self.heads[n as usize], END);
        while id != END {
            let next = self.slots[id as usize].next;
            self.listed -= 1;
            let time = self.slots[id as usize].time;
            let bucket = (time - self.origin) * self.inv_width;
            if bucket < (self.current + 1) as Real {
                self.heap_push(id);
            } else if bucket < (self.current + n) as Real {
                self.link(id, (bucket as u64 % n) as u32);
            } else {
                self.link(id, n as u32);
            }
            id = next;
        }
    }

    /// Puts every listed event in the heap (events whose times do not map to buckets).
    fn spill_all(&mut self) {
        for b in 0..self.heads.len() {
            let mut id = std::mem::replace(&mut self.heads[b], END);
            while id != END {
                let next = self.slots[id as usize].next;
                self.listed -= 1;
                self.heap_push(id);
                id = next;
            }
        }
    }

    fn heap_push(&mut self, id: u32) {
        let pos = self.heap.len();
        self.heap.push(self.entry(id));
        self.slots[id as usize].place = pos as u32;
        self.sift_up(pos);
    }

    fn heap_remove(&mut self, pos: usize) {
        let last = self.heap.pop().expect("a heap position");
        if pos < self.heap.len() {
            self.heap[pos] = last;
            self.slots[last.id as usize].place = pos as u32;
            if pos > 0 && last.before(&self.heap[(pos - 1) / 2]) {
                self.sift_up(pos);
            } else {
                self.sift_down(pos);
            }
        }
    }

    fn sift_up(&mut self, mut pos: usize) {
        let e = self.heap[pos];
        while pos > 0 {
            let parent = (pos - 1) / 2;
            let p = self.heap[parent];
            if !e.before(&p) {
                break;
            }
            self.heap[pos] = p;
            self.slots[p.id as usize].place = pos as u32;
            pos = parent;
        }
        self.heap[pos] = e;
        self.slots[e.id as usize].place = pos as u32;
    }

    /// Moves the entry at `pos` down to its place. The hole goes down to a leaf, each time
    /// to the earlier child (chosen without a branch), and the entry then rises from there:
    /// an entry moved down mostly belongs near the leaves, so the rise is short and the
    /// descent costs no mispredicted comparison.
    fn sift_down(&mut self, mut pos: usize) {
        let e = self.heap[pos];
        let n = self.heap.len();
        let mut child = 2 * pos + 1;
        while child + 1 < n {
            child += usize::from(self.heap[child + 1].before(&self.heap[child]));
            let c = self.heap[child];
            self.heap[pos] = c;
            self.slots[c.id as usize].place = pos as u32;
            pos = child;
            child = 2 * pos + 1;
        }
        if child < n {
            let c = self.heap[child];
            self.heap[pos] = c;
            self.slots[c.id as usize].place = pos as u32;
            pos = child;
        }
        self.heap[pos] = e;
        self.sift_up(pos);
    }

    /// Checks the heap order, the places and the counts.
    pub(super) fn validate(&self) -> Result<(), String> {
        for (pos, e) in self.heap.iter().enumerate() {
            let s = &self.slots[e.id as usize];
            if s.place != pos as u32 || (s.time, s.tie) != (e.time, e.tie) {
                return Err(format!("calendar: heap entry {} is out of step", e.id));
            }
            if pos > 0 && e.before(&self.heap[(pos - 1) / 2]) {
                return Err(format!("calendar: heap out of order at {pos}"));
            }
        }
        let mut listed = 0;
        for (b, &head) in self.heads.iter().enumerate() {
            let mut id = head;
            while id != END {
                let s = &self.slots[id as usize];
                if s.place != LISTED + b as u32 {
                    return Err(format!("calendar: listed entry {id} has the wrong place"));
                }
                if let Some(top) = self.heap.first()
                    && self.entry(id).before(top)
                {
                    return Err(format!(
                        "calendar: listed entry {id} before the heap's first"
                    ));
                }
                listed += 1;
                id = s.next;
            }
        }
        if listed != self.listed || listed + self.heap.len() != self.len {
            return Err("calendar: counts disagree".into());
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Random schedules and removals agree with a sorted reference on every pop.
    #[test]
    fn pops_in_order_like_a_sorted_list() {
        let mut state = 12345u64;
        let mut rand = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let ids = 200;
        let mut q = Calendar::<()>::new(ids, 0.01, 50, 0.0);
        let mut reference: Vec<Option<(Real, u64)>> = vec![None; ids];
        let mut now = 0.0;
        for _ in 0..20_000 {
            let id = (rand() % ids as u64) as u32;
            match rand() % 4 {
                0 => {
                    q.remove(id);
                    reference[id as usize] = None;
                }
                1 | 2 => {
                    // Mostly near, sometimes far (overflow), sometimes at now.
                    let r = rand() % 100;
                    let dt = if r < 5 {
                        0.0
                    } else if r < 10 {
                        (rand() % 1000) as Real * 0.1
                    } else {
                        (rand() % 1000) as Real * 1e-4
                    };
                    let tie = rand() % 3;
                    q.schedule(id, now + dt, tie, ());
                    reference[id as usize] = Some((now + dt, tie));
                }
                _ => {
                    let expected = reference
                        .iter()
                        .enumerate()
                        .filter_map(|(i, e)| e.map(|(t, tie)| (t, tie, i as u32)))
                        .min_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
                    let got = q.peek();
                    assert_eq!(got.map(|g| (g.1, g.0)), expected.map(|e| (e.0, e.2)));
                    if let Some((id, t, ())) = got {
                        now = t;
                        q.remove(id);
                        reference[id as usize] = None;
                    }
                }
            }
            q.validate().unwrap();
        }
    }
}
