//! The grid as the simulator's candidate structure.

use super::Grid;
use kinetic_core::kds::{Bodies, PairChange};
use kinetic_core::{CandidateStructure, Real, Vec3};

impl CandidateStructure for Grid {
    fn name(&self) -> &'static str {
        "grid"
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
        self.insert_bulk(ids, bodies, now, changes);
    }

    fn remove(&mut self, id: u32, _: &Bodies, _: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.unplace(id, changes);
        self.members[id as usize] = None;
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.replan_member(id, bodies, now, changes);
    }

    fn next_event_time(&self) -> Real {
        self.crossings_queue
            .next_time()
            .min(self.pairs_queue.next_time())
    }

    fn process_next_event(&mut self, _: &Bodies, changes: &mut Vec<PairChange>) -> &'static str {
        let (c, p) = (self.crossings_queue.peek(), self.pairs_queue.peek());
        match (c, p) {
            (Some((id, t)), p) if p.is_none_or(|(_, tp)| t <= tp) => {
                self.process_crossing(id, t, changes);
                "crossing"
            }
            (_, Some((i, t))) => {
                self.process_pair(i, t, changes);
                "box"
            }
            _ => "crossing",
        }
    }

    fn certificates(&self) -> usize {
        // A fast member's certificate is its box inside its region: a face each.
        4 * 3 * self.own_tracks + 6 * self.fast.len() + 3 * self.pair_of.len()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        let tracks = self
            .members
            .iter()
            .flatten()
            .flat_map(|m| &m.tracks)
            .fold((0, 0), |(n, d), t| (n + 1, d + t.shift.is_some() as usize));
        vec![
            ("box_pairs", self.box_pairs as f64),
            ("grid_pairs", self.pair_of.len() as f64),
            ("cells", self.cells.len() as f64),
            ("levels", self.occupied.len() as f64),
            ("tracks", tracks.0 as f64),
            ("derived_tracks", tracks.1 as f64),
            ("level_ratio", self.ratio()),
            ("crossings", self.crossings as f64),
            ("box_events", self.pair_events as f64),
            ("fast", self.fast.len() as f64),
            ("fast_anchors", self.fast_anchors as f64),
        ]
    }

    fn boxes(&self, _: &Bodies, now: Real) -> Vec<(Vec3, Vec3)> {
        self.members
            .iter()
            .flatten()
            .map(|m| {
                let lo = Vec3::from_array(std::array::from_fn(|k| m.lo[k].value_at(now)));
                let hi = Vec3::from_array(std::array::from_fn(|k| m.hi[k].value_at(now)));
                (lo, hi)
            })
            .collect()
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.check(bodies, now)
    }
}
