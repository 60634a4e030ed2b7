//! Events: a footprint certificate failing (a cell crossing, or a fast object reaching its
//! region's edge) and a box certificate failing.

use super::Grid;
use super::{FAST_SPAN, SLOW_SPAN};
use kinetic_core::Real;
use kinetic_core::kds::PairChange;

impl Grid {
    pub(super) fn process_crossing(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        let m = self.member(id);
        if m.region.is_some() {
            // A fast member's box reached its region's edge: a new region, or back into the
            // cells once it is slow.
            if self.is_fast(m, now, SLOW_SPAN) {
                self.anchor_fast(id, now, changes);
            } else {
                self.unplace(id, changes);
                self.settle(id, now, changes);
            }
            return;
        }
        if self.is_fast(m, now, FAST_SPAN) {
            // Sped up (an accelerated plan): out of the cells.
            self.unplace(id, changes);
            self.settle(id, now, changes);
            return;
        }
        self.crossings += 1;
        let m = self.member(id);
        // The due certificate: its track, axis and kind.
        let (mut ti, mut k, mut kind, mut best) = (0, 0, 0, Real::INFINITY);
        // Derived tracks have no certificates of their own.
        for (i, t) in m
            .tracks
            .iter()
            .enumerate()
            .filter(|(_, t)| t.shift.is_none())
        {
            for (axis, due) in t.due.iter().enumerate() {
                for (c, &d) in due.iter().enumerate() {
                    if d < best {
                        (ti, k, kind, best) = (i, axis, c, d);
                    }
                }
            }
        }
        let owner = m.tracks[ti].level == m.level;
        let mut track = m.tracks[ti].clone();
        let [a, b] = track.cells[k];
        let mut keys = std::mem::take(&mut self.keys);
        // Which end of the range moves, the slab of cells entered or left, the new end.
        let (end, slab, moved, entering) = match kind {
            0 => (0, a - 1, a - 1, true),
            1 => (0, a, a + 1, false),
            2 => (1, b + 1, b + 1, true),
            _ => (1, b, b - 1, false),
        };
        track.cells[k][end] = moved;
        // The slab spans the other axes' ranges, which this event leaves as they are.
        Self::cells_of(&track, Some((k, slab)), &mut keys);
        for &key in &keys {
            if entering {
                self.enter(id, key, owner, now, changes);
            } else {
                self.leave(id, key, owner, changes);
            }
        }
        self.certify_axis(self.member(id), &mut track, k, now);
        let m = self.members[id as usize].as_mut().expect("a member");
        m.tracks[ti] = track;
        if owner {
            // The derived tracks follow the own range on this axis: at most one end of each
            // moves, by one cell, the same way.
            for tj in 1..m.tracks.len() {
                let m = self.member(id);
                let (own, t) = (&m.tracks[0], &m.tracks[tj]);
                let Some(shift) = t.shift else { continue };
                let want = own.cells[k].map(|c| c >> shift);
                let have = t.cells[k];
                if want == have {
                    continue;
                }
                let mut t = t.clone();
                t.cells[k] = want;
                // The slab entered (from the new range) or left (from the old).
                let (slab, from) = if want[0] < have[0] {
                    (want[0], &t)
                } else if want[0] > have[0] {
                    (have[0], &m.tracks[tj])
                } else if want[1] > have[1] {
                    (want[1], &t)
                } else {
                    (have[1], &m.tracks[tj])
                };
                Self::cells_of(from, Some((k, slab)), &mut keys);
                for &key in &keys {
                    if entering {
                        self.enter(id, key, false, now, changes);
                    } else {
                        self.leave(id, key, false, changes);
                    }
                }
                self.members[id as usize].as_mut().expect("a member").tracks[tj] = t;
            }
            self.fast_links(id, now, changes);
        }
        self.keys = keys;
        self.schedule_member(id);
    }

    pub(super) fn process_pair(&mut self, i: u32, now: Real, changes: &mut Vec<PairChange>) {
        self.pair_events += 1;
        let mut slot = self.slots[i as usize].take().expect("a slot");
        let k = (0..3)
            .min_by(|&x, &y| slot.due[x].total_cmp(&slot.due[y]))
            .expect("three axes");
        slot.inside[k] = !slot.inside[k];
        // A candidate's axes are all watched. A pair apart watched its witness alone, which
        // has just closed: the other two are looked at afresh.
        let fresh = if slot.reported {
            [false; 3]
        } else {
            std::array::from_fn(|j| j != k)
        };
        self.certify_pair(&mut slot, now, fresh);
        self.slots[i as usize] = Some(slot);
        self.schedule_slot(i);
        self.report(i, changes);
    }
}
