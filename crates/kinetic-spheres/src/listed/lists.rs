//! Neighbour lists: a fixed stride per sphere, grown when a list overflows.

use kinetic_core::prefetch;

/// Every sphere's neighbours, in a row of `stride` slots each: the row's first slot holds the
/// list's length, the others its neighbours, so that a list is one or two cache lines.
#[derive(Clone, Debug)]
pub(super) struct Lists {
    stride: usize,
    slots: Vec<u32>,
    total: usize,
    /// Per sphere, the last stamp a relist gave it (see [`Lists::stamps`]), and the next
    /// stamp to give.
    stamp: Vec<u32>,
    next_stamp: u32,
    /// The row being relisted, as it was.
    old: Vec<u32>,
}

impl Lists {
    pub(super) fn new(spheres: usize, stride: usize) -> Lists {
        let stride = stride.clamp(4, u16::MAX as usize);
        Lists {
            stride,
            slots: vec![0; spheres * stride],
            total: 0,
            stamp: vec![0; spheres],
            next_stamp: 1,
            old: Vec::new(),
        }
    }

    /// Slots per row (one more than a list can hold before the rows grow).
    pub(super) fn stride(&self) -> usize {
        self.stride
    }

    /// Entries over all lists (each pair twice).
    pub(super) fn total(&self) -> usize {
        self.total
    }

    #[inline]
    pub(super) fn of(&self, i: u32) -> &[u32] {
        let at = i as usize * self.stride;
        let len = self.slots[at] as usize;
        &self.slots[at + 1..at + 1 + len]
    }

    /// Asks for `i`'s row to be fetched (its first two cache lines).
    #[inline]
    pub(super) fn prefetch(&self, i: u32) {
        let at = i as usize * self.stride;
        prefetch(&self.slots[at]);
        if let Some(later) = self.slots.get(at + 16) {
            prefetch(later);
        }
    }

    pub(super) fn push(&mut self, i: u32, n: u32) {
        let mut at = i as usize * self.stride;
        if self.slots[at] as usize + 1 == self.stride {
            self.grow();
            at = i as usize * self.stride;
        }
        let len = self.slots[at] as usize;
        self.slots[at + 1 + len] = n;
        self.slots[at] += 1;
        self.total += 1;
    }

    /// Removes `other` from `i`'s list (order is not kept).
    pub(super) fn remove(&mut self, i: u32, other: u32) {
        let at = i as usize * self.stride;
        let len = self.slots[at] as usize;
        let row = &mut self.slots[at + 1..at + 1 + len];
        if let Some(k) = row.iter().position(|&n| n == other) {
            row[k] = row[len - 1];
            self.slots[at] -= 1;
            self.total -= 1;
        }
    }

    /// Starts relisting `i`: keeps its row as it was and stamps each sphere on it `was`;
    /// [`Lists::restamp`] then stamps those found again `kept`. Returns `(was, kept)`.
    pub(super) fn stamps(&mut self, i: u32) -> (u32, u32) {
        if self.next_stamp >= u32::MAX - 2 {
            self.stamp.fill(0);
            self.next_stamp = 1;
        }
        let (was, kept) = (self.next_stamp, self.next_stamp + 1);
        self.next_stamp += 2;
        let mut old = std::mem::take(&mut self.old);
        old.clear();
        old.extend_from_slice(self.of(i));
        for &k in &old {
            self.stamp[k as usize] = was;
            // Its row is written below if it leaves.
            self.prefetch(k);
        }
        self.old = old;
        (was, kept)
    }

    /// Whether `other` was on the row being relisted (stamped `was`): if so, it is stamped
    /// `kept` and its own row stays as it is.
    #[inline]
    pub(super) fn restamp(&mut self, other: u32, was: u32, kept: u32) -> bool {
        let s = &mut self.stamp[other as usize];
        if *s == was {
            *s = kept;
            true
        } else {
            false
        }
    }

    /// Ends relisting `i`: the spheres on its old row that were not found again (still
    /// stamped `was`) lose it from their rows.
    pub(super) fn drop_left(&mut self, i: u32, was: u32) {
        let old = std::mem::take(&mut self.old);
        for &k in &old {
            if self.stamp[k as usize] == was {
                self.remove(k, i);
            }
        }
        self.old = old;
    }

    pub(super) fn clear(&mut self, i: u32) {
        let at = i as usize * self.stride;
        self.total -= self.slots[at] as usize;
        self.slots[at] = 0;
    }

    /// Widens every row (a list is full) by a quarter, at least 8 slots, so that rows stay
    /// close to the longest list: every row moves to its new place.
    fn grow(&mut self) {
        let stride = (self.stride + (self.stride / 4).max(8)).min(u16::MAX as usize);
        assert!(
            stride > self.stride,
            "a neighbour list holds at most 65534 spheres"
        );
        let spheres = self.slots.len() / self.stride;
        let mut slots = vec![0; spheres * stride];
        for i in 0..spheres {
            let from = i * self.stride;
            let used = self.slots[from] as usize + 1;
            slots[i * stride..i * stride + used].copy_from_slice(&self.slots[from..from + used]);
        }
        self.slots = slots;
        self.stride = stride;
    }
}
