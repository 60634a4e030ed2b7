//! The event queue: an indexed 4-ary min-heap of certificate failure times.
//!
//! Certificates are named by dense `u32` ids chosen by the owner of the queue (an item of a
//! sorted list, a pair slot, ...). Each id is scheduled at most once; scheduling it again
//! moves it. Keys are `(time, tie, id)`, compared with `f64::total_cmp`, so equal times pop
//! in an order fixed by the owner's tie-break and then the id: same input, same order.

const ABSENT: u32 = u32::MAX;

#[derive(Clone, Copy, Debug)]
struct Entry {
    time: f64,
    tie: u64,
    id: u32,
}

impl Entry {
    #[inline]
    fn before(&self, other: &Entry) -> bool {
        match self.time.total_cmp(&other.time) {
            std::cmp::Ordering::Less => true,
            std::cmp::Ordering::Greater => false,
            std::cmp::Ordering::Equal => (self.tie, self.id) < (other.tie, other.id),
        }
    }
}

/// An indexed priority queue of `(time, tie-break)` keys: O(log n) schedule, reschedule and
/// remove, O(1) peek.
///
/// ```
/// # use kinetic_core::kds::EventQueue;
/// let mut q = EventQueue::new();
/// q.schedule(7, 2.0, 0);
/// q.schedule(3, 1.0, 0);
/// q.schedule(7, 0.5, 0); // moves id 7
/// assert_eq!(q.pop(), Some((7, 0.5)));
/// assert_eq!(q.pop(), Some((3, 1.0)));
/// assert_eq!(q.pop(), None);
/// ```
#[derive(Clone, Debug, Default)]
pub struct EventQueue {
    heap: Vec<Entry>,
    /// Heap position of each id, `ABSENT` when it is not scheduled.
    slot: Vec<u32>,
}

impl EventQueue {
    /// An empty queue.
    pub fn new() -> EventQueue {
        EventQueue::default()
    }

    /// An empty queue with room for ids below `ids`.
    pub fn with_capacity(ids: usize) -> EventQueue {
        EventQueue {
            heap: Vec::with_capacity(ids),
            slot: Vec::with_capacity(ids),
        }
    }

    /// The number of scheduled events.
    pub fn len(&self) -> usize {
        self.heap.len()
    }

    /// Whether nothing is scheduled.
    pub fn is_empty(&self) -> bool {
        self.heap.is_empty()
    }

    /// Schedules `id` at `time` (moving it if it was already scheduled). A NaN time is a
    /// programming error; it sorts after every number and so never fires before real events.
    pub fn schedule(&mut self, id: u32, time: f64, tie: u64) {
        debug_assert!(!time.is_nan(), "event time is NaN");
        let i = id as usize;
        if i >= self.slot.len() {
            self.slot.resize(i + 1, ABSENT);
        }
        let entry = Entry { time, tie, id };
        match self.slot[i] {
            ABSENT => {
                self.heap.push(entry);
                self.sift_up(self.heap.len() - 1);
            }
            pos => {
                let pos = pos as usize;
                let earlier = entry.before(&self.heap[pos]);
                self.heap[pos] = entry;
                if earlier {
                    self.sift_up(pos);
                } else {
                    self.sift_down(pos);
                }
            }
        }
    }

    /// Removes `id` if it is scheduled; returns its time.
    pub fn remove(&mut self, id: u32) -> Option<f64> {
        let pos = *self.slot.get(id as usize)?;
        if pos == ABSENT {
            return None;
        }
        let pos = pos as usize;
        let time = self.heap[pos].time;
        self.slot[id as usize] = ABSENT;
        let last = self.heap.pop().expect("a scheduled id has an entry");
        if pos < self.heap.len() {
            let earlier = last.before(&self.heap[pos]);
            self.heap[pos] = last;
            self.slot[last.id as usize] = pos as u32;
            if earlier {
                self.sift_up(pos);
            } else {
                self.sift_down(pos);
            }
        }
        Some(time)
    }

    /// The time at which `id` is scheduled, if it is.
    pub fn time_of(&self, id: u32) -> Option<f64> {
        match self.slot.get(id as usize) {
            Some(&pos) if pos != ABSENT => Some(self.heap[pos as usize].time),
            _ => None,
        }
    }

    /// The earliest event, without removing it.
    #[inline]
    pub fn peek(&self) -> Option<(u32, f64)> {
        self.heap.first().map(|e| (e.id, e.time))
    }

    /// The earliest time, or +infinity when nothing is scheduled.
    #[inline]
    pub fn next_time(&self) -> f64 {
        self.heap.first().map_or(f64::INFINITY, |e| e.time)
    }

    /// Removes and returns the earliest event.
    pub fn pop(&mut self) -> Option<(u32, f64)> {
        let (id, time) = self.peek()?;
        self.remove(id);
        Some((id, time))
    }

    /// Checks the heap order and the index: for `validate()` of the structures above.
    pub fn validate(&self) -> Result<(), String> {
        for (pos, e) in self.heap.iter().enumerate() {
            if self.slot.get(e.id as usize) != Some(&(pos as u32)) {
                return Err(format!(
                    "queue: id {} at heap position {pos} is not indexed there",
                    e.id
                ));
            }
            if pos > 0 && e.before(&self.heap[(pos - 1) / 4]) {
                return Err(format!("queue: heap order broken at position {pos}"));
            }
        }
        let indexed = self.slot.iter().filter(|&&s| s != ABSENT).count();
        if indexed != self.heap.len() {
            return Err(format!(
                "queue: {indexed} ids indexed, {} scheduled",
                self.heap.len()
            ));
        }
        Ok(())
    }

    fn sift_up(&mut self, mut pos: usize) {
        let entry = self.heap[pos];
        while pos > 0 {
            let parent = (pos - 1) / 4;
            if !entry.before(&self.heap[parent]) {
                break;
            }
            self.heap[pos] = self.heap[parent];
            self.slot[self.heap[pos].id as usize] = pos as u32;
            pos = parent;
        }
        self.heap[pos] = entry;
        self.slot[entry.id as usize] = pos as u32;
    }

    fn sift_down(&mut self, mut pos: usize) {
        let entry = self.heap[pos];
        let n = self.heap.len();
        loop {
            let first = 4 * pos + 1;
            if first >= n {
                break;
            }
            let mut best = first;
            for child in first + 1..(first + 4).min(n) {
                if self.heap[child].before(&self.heap[best]) {
                    best = child;
                }
            }
            if !self.heap[best].before(&entry) {
                break;
            }
            self.heap[pos] = self.heap[best];
            self.slot[self.heap[pos].id as usize] = pos as u32;
            pos = best;
        }
        self.heap[pos] = entry;
        self.slot[entry.id as usize] = pos as u32;
    }
}
