//! Filing regions in the cells they cover (or in the big list), and sizing the cells.

use super::{CellKey, LooseGrid, MAX_CELLS, MAX_SPAN};
use kinetic_core::{Real, Vec3};

/// The median of the positive finite widths `w`, if any.
pub(super) fn median(w: impl Iterator<Item = Real>) -> Option<Real> {
    let mut w: Vec<Real> = w.filter(|w| *w > 0.0 && w.is_finite()).collect();
    let mid = w.len() / 2;
    (!w.is_empty()).then(|| *w.select_nth_unstable_by(mid, Real::total_cmp).1)
}

/// The cells of footprint `f`, in order.
pub(super) fn cell_keys(f: [[i64; 2]; 3]) -> impl Iterator<Item = CellKey> {
    (f[0][0]..=f[0][1]).flat_map(move |i| {
        (f[1][0]..=f[1][1]).flat_map(move |j| (f[2][0]..=f[2][1]).map(move |k| [i, j, k]))
    })
}

impl LooseGrid {
    /// The cells the region `lo..hi` covers, per axis the first and last index; `None` when
    /// it is big (or there are no cells yet).
    pub(super) fn footprint(&self, lo: Vec3, hi: Vec3) -> Option<[[i64; 2]; 3]> {
        let s = self.cell?;
        let mut f = [[0i64; 2]; 3];
        let mut all = 1;
        for k in 0..3 {
            // Saturating casts: a region out at 1e300 is big, not wrapped.
            let a = (lo[k] / s).floor() as i64;
            let b = ((hi[k] / s).floor() as i64).max(a);
            let span = b.saturating_sub(a).saturating_add(1);
            if !(1..=MAX_SPAN).contains(&span) {
                return None;
            }
            all *= span;
            f[k] = [a, b];
        }
        (all <= MAX_CELLS).then_some(f)
    }

    /// The slot of cell `key`, made if the cell is new.
    fn slot_for(&mut self, key: CellKey) -> u32 {
        if let Some(&slot) = self.cells.get(&key) {
            return slot;
        }
        let slot = self.free.pop().unwrap_or_else(|| {
            self.occupants.push(Vec::new());
            (self.occupants.len() - 1) as u32
        });
        self.cells.insert(key, slot);
        slot
    }

    /// Files member `id`'s region: in the cells it covers, or in the big list. Returns the
    /// slots.
    pub(super) fn file(&mut self, id: u32, lo: Vec3, hi: Vec3) -> (Vec<u32>, bool) {
        let Some(f) = self.footprint(lo, hi) else {
            self.big.push(id);
            return (Vec::new(), true);
        };
        let mut slots = Vec::with_capacity(8);
        for key in cell_keys(f) {
            let slot = self.slot_for(key);
            self.occupants[slot as usize].push(id);
            slots.push(slot);
        }
        (slots, false)
    }

    /// Moves member `id`'s filing from the cells of footprint `from` (its `slots`, in
    /// [`cell_keys`] order) to those of `to`: out of the cells only `from` covers (emptied
    /// ones forgotten), into those only `to` covers. Returns the slots of `to`, in order.
    pub(super) fn shift_filing(
        &mut self,
        id: u32,
        slots: Vec<u32>,
        from: [[i64; 2]; 3],
        to: [[i64; 2]; 3],
    ) -> Vec<u32> {
        if from == to {
            self.same_cells += 1;
            return slots;
        }
        let within = |f: &[[i64; 2]; 3], key: &CellKey| {
            (0..3).all(|k| f[k][0] <= key[k] && key[k] <= f[k][1])
        };
        let mut out = Vec::with_capacity(slots.len());
        let span = |k: usize| from[k][1] - from[k][0] + 1;
        for key in cell_keys(to) {
            if within(&from, &key) {
                let at = ((key[0] - from[0][0]) * span(1) + key[1] - from[1][0]) * span(2) + key[2]
                    - from[2][0];
                out.push(slots[at as usize]);
                continue;
            }
            let slot = self.slot_for(key);
            self.occupants[slot as usize].push(id);
            out.push(slot);
        }
        for (key, &slot) in cell_keys(from).zip(&slots) {
            if within(&to, &key) {
                continue;
            }
            let list = &mut self.occupants[slot as usize];
            if let Some(i) = list.iter().position(|&x| x == id) {
                list.swap_remove(i);
            }
            if list.is_empty() {
                self.cells.remove(&key);
                self.free.push(slot);
            }
        }
        out
    }

    /// Takes member `id` out of its cells (or the big list); emptied cells are forgotten.
    pub(super) fn unfile(&mut self, id: u32) {
        let m = self.members[id as usize].as_mut().expect("a member");
        let slots = std::mem::take(&mut m.slots);
        let (lo, hi) = (m.lo, m.hi);
        if m.big {
            if let Some(i) = self.big.iter().position(|&x| x == id) {
                self.big.swap_remove(i);
            }
            return;
        }
        let mut emptied = false;
        for &slot in &slots {
            let list = &mut self.occupants[slot as usize];
            if let Some(i) = list.iter().position(|&x| x == id) {
                list.swap_remove(i);
            }
            emptied |= list.is_empty();
        }
        if emptied {
            let Some(f) = self.footprint(lo, hi) else {
                return;
            };
            for key in cell_keys(f) {
                if let Some(&slot) = self.cells.get(&key)
                    && self.occupants[slot as usize].is_empty()
                {
                    self.cells.remove(&key);
                    self.free.push(slot);
                }
            }
        }
    }

    /// Sizes the cells afresh (the median width of the regions now) and files every region
    /// again. Partners stay: they are the overlapping regions, whatever the cells.
    pub(super) fn refile(&mut self) {
        let w = median(
            self.members
                .iter()
                .flatten()
                .map(|m| (m.hi - m.lo).max_element()),
        );
        let Some(w) = w else {
            return;
        };
        self.cell = Some(w);
        self.refiles += 1;
        self.cells.clear();
        self.occupants.clear();
        self.free.clear();
        self.big.clear();
        for id in 0..self.members.len() as u32 {
            let Some(m) = self.members[id as usize].as_ref() else {
                continue;
            };
            let (lo, hi) = (m.lo, m.hi);
            let (slots, big) = self.file(id, lo, hi);
            let m = self.members[id as usize].as_mut().expect("a member");
            m.slots = slots;
            m.big = big;
        }
    }
}
