//! The loose grid as the simulator's candidate structure.

use super::LooseGrid;
use super::cells::median;
use crate::cell_math::box_width;
use kinetic_core::kds::{Bodies, PairChange};
use kinetic_core::{CandidateStructure, Real, Vec3};

/// A share of a flight in `[0, 1)` for object `id`, spread evenly over the ids (the
/// fractional parts of multiples of the golden ratio).
fn stagger(id: u32) -> Real {
    (Real::from(id) * 0.618_033_988_749_894_9).fract()
}

impl CandidateStructure for LooseGrid {
    fn name(&self) -> &'static str {
        "loose-grid"
    }

    fn insert(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.insert_many(&[id], bodies, now, changes);
    }

    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if self.cell.is_none() {
            if let Some(w) = median(ids.iter().map(|&id| box_width(bodies, id))) {
                self.typical = w;
            }
            // Cells as wide as the first regions' median.
            self.cell = median(ids.iter().map(|&id| {
                let (lo, hi) = self.region(bodies, id, now, 0.0);
                (hi - lo).max_element()
            }));
        }
        if let Some(&top) = ids.iter().max()
            && self.members.len() <= top as usize
        {
            self.members.resize(top as usize + 1, None);
        }
        // Filed together, regions are staggered when asked: else they would all end a
        // flight from now, in one wave.
        let staggered = self.staggered && ids.len() > 1;
        for &id in ids {
            if !self.present(id) {
                let age = if staggered { stagger(id) } else { 0.0 };
                self.anchor(id, bodies, now, age, changes);
            }
        }
    }

    fn remove(&mut self, id: u32, _: &Bodies, _: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.unfile(id);
        self.live -= 1;
        let m = self.members[id as usize].take().expect("a member");
        for p in m.partners {
            self.part(id, p, changes);
        }
        self.exits.remove(id);
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        let m = self.member(id);
        let exit = Self::exit_time(bodies, id, m.lo, m.hi, now);
        if exit > now {
            // Still inside its region on the new plan: it keeps the region.
            self.kept += 1;
            self.members[id as usize].as_mut().expect("a member").exit = exit;
            self.schedule(id, exit);
        } else {
            self.anchor(id, bodies, now, 0.0, changes);
        }
    }

    fn next_event_time(&self) -> Real {
        self.exits.next_time()
    }

    fn process_next_event(
        &mut self,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) -> &'static str {
        if let Some((id, t)) = self.exits.peek() {
            self.anchor(id, bodies, t, 0.0, changes);
        }
        "anchor"
    }

    fn certificates(&self) -> usize {
        self.exits.len()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        vec![
            ("region_pairs", self.pairs as f64),
            ("cells", self.cells.len() as f64),
            ("big", self.big.len() as f64),
            ("cell_size", self.cell.unwrap_or(0.0)),
            ("refiles", self.refiles as f64),
            ("anchors", self.anchors as f64),
            ("anchors_same_cells", self.same_cells as f64),
            ("regions_kept", self.kept as f64),
        ]
    }

    fn boxes(&self, _: &Bodies, _: Real) -> Vec<(Vec3, Vec3)> {
        self.members
            .iter()
            .flatten()
            .map(|m| (m.lo, m.hi))
            .collect()
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.check(bodies, now)
    }
}
