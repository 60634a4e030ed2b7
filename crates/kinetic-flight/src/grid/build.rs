//! Objects joining: the grid sized by the first ones, and a bulk placed at once.

use super::FAST_SPAN;
use super::Grid;
use crate::cell_math::{box_width, levels_for};
use kinetic_core::Real;
use kinetic_core::kds::{Bodies, PairChange};

impl Grid {
    /// Objects `ids` join at `now` together
    /// ([`kinetic_core::CandidateStructure::insert_many`]): the levels sized by the first ones,
    /// then the cell dwellers placed and the fast ones anchored.
    pub(super) fn insert_bulk(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if self.base.is_none() {
            // The finest cells fit the smallest box. Levels are a power of two apart, so that
            // the middle 98% of sizes span about BULK_LEVELS levels: 2 for similar sizes, wider
            // for a spread (fewer levels for each object to visit).
            let w = ids.iter().map(|&id| box_width(bodies, id));
            if let Some((base, ratio)) = levels_for(w) {
                self.base = Some(base);
                self.ratio = ratio;
            }
        }
        self.widen_for(ids, bodies, now);
        let mut fresh = Vec::with_capacity(ids.len());
        let mut fast = Vec::new();
        // The members' table grown once for the bulk, not copied over as it doubles.
        if let Some(&top) = ids.iter().max()
            && self.members.len() <= top as usize
        {
            self.members.resize(top as usize + 1, None);
        }
        for &id in ids {
            if self.present(id) {
                continue;
            }
            let m = self.make_member(bodies, id);
            if self.is_fast(&m, now, FAST_SPAN) {
                self.members[id as usize] = Some(m);
                fast.push(id);
                continue;
            }
            // Levels first, so that the visitors are in place when the owners come.
            self.occupy(m.level, now, changes);
            self.members[id as usize] = Some(m);
            fresh.push(id);
        }
        // Room for what a bulk of objects fills at once (cells, grid pairs), so that the
        // tables are not grown and copied over and over while it is placed.
        if fresh.len() > 1 {
            let n = fresh.len();
            self.cells.reserve(n);
            self.pair_of.reserve(2 * n);
            self.slots.reserve(2 * n);
        }
        for id in fresh {
            self.place(id, now, changes);
        }
        for id in fast {
            self.fast.push(id);
            self.anchor_fast(id, now, changes);
        }
    }
}
