//! Re-plans: an object's footprints and grid pairs certified on its new plan.

use super::Grid;
use super::{FAST_SPAN, SLOW_SPAN};
use kinetic_core::Real;
use kinetic_core::kds::{Bodies, PairChange};

impl Grid {
    /// Object `id` has a new plan from `now` ([`kinetic_core::CandidateStructure::replan`]):
    /// its footprints and pairs afresh, or placed anew when its level or speed class changed.
    pub(super) fn replan_member(
        &mut self,
        id: u32,
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if !self.present(id) {
            return;
        }
        let new = self.make_member(bodies, id);
        let was_fast = self.member(id).region.is_some();
        let fast = self.is_fast(&new, now, if was_fast { SLOW_SPAN } else { FAST_SPAN });
        if was_fast && fast {
            // Still fast: a new region, and its pairs certified on the new plan.
            let m = self.members[id as usize].as_mut().expect("a member");
            (m.lo, m.hi, m.width, m.level) = (new.lo, new.hi, new.width, new.level);
            self.anchor_fast(id, now, changes);
            self.recertify_pairs(id, now, changes);
            return;
        }
        if was_fast || fast || new.level != self.member(id).level {
            // A new box size, or into or out of the cells: placed afresh.
            self.unplace(id, changes);
            let pairs = self.members[id as usize]
                .replace(new)
                .expect("a member")
                .pairs;
            debug_assert!(pairs.is_empty(), "unplaced with pairs left");
            self.settle(id, now, changes);
            return;
        }
        let m = self.members[id as usize].as_mut().expect("a member");
        (m.lo, m.hi, m.width) = (new.lo, new.hi, new.width);
        // Enter the new cells before leaving the old, so that shared cells keep their pairs.
        let old = m.tracks.clone();
        let level = m.level;
        let (mut before, mut after) = (
            std::mem::take(&mut self.old_keys),
            std::mem::take(&mut self.keys),
        );
        for (ti, old_track) in old.iter().enumerate() {
            let m = self.member(id);
            let track = if ti == 0 {
                self.footprint(m, old_track.level, now)
            } else {
                self.track_at(m, &m.tracks[0], old_track.level, now)
            };
            Self::cells_of(old_track, None, &mut before);
            Self::cells_of(&track, None, &mut after);
            let owner = old_track.level == level;
            for &key in &after {
                if !before.contains(&key) {
                    self.enter(id, key, owner, now, changes);
                }
            }
            for &key in &before {
                if !after.contains(&key) {
                    self.leave(id, key, owner, changes);
                }
            }
            self.members[id as usize].as_mut().expect("a member").tracks[ti] = track;
        }
        (self.old_keys, self.keys) = (before, after);
        self.schedule_member(id);
        self.fast_links(id, now, changes);
        self.recertify_pairs(id, now, changes);
    }
}
