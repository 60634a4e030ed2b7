//! The brute-force reference: every pair of objects is a candidate, with one certificate per
//! pair. It is the oracle that every other structure is tested against, and the baseline of
//! the benchmarks.

use crate::math::Real;
use crate::structure::{Bodies, CandidateStructure, PairChange};

/// Every pair is a candidate pair.
#[derive(Clone, Debug, Default)]
pub struct BruteForce {
    live: Vec<u32>,
}

impl BruteForce {
    /// An empty brute-force structure.
    pub fn new() -> BruteForce {
        BruteForce::default()
    }
}

impl CandidateStructure for BruteForce {
    fn name(&self) -> &'static str {
        "brute-force"
    }

    fn insert(&mut self, id: u32, _: &Bodies, _: Real, changes: &mut Vec<PairChange>) {
        changes.extend(self.live.iter().map(|&b| PairChange {
            a: b,
            b: id,
            delta: 1,
        }));
        self.live.push(id);
    }

    fn remove(&mut self, id: u32, _: &Bodies, _: Real, changes: &mut Vec<PairChange>) {
        self.live.retain(|&x| x != id);
        changes.extend(self.live.iter().map(|&b| PairChange {
            a: b,
            b: id,
            delta: -1,
        }));
    }

    fn replan(&mut self, _: u32, _: &Bodies, _: Real, _: &mut Vec<PairChange>) {}

    fn next_event_time(&self) -> Real {
        Real::INFINITY
    }

    fn process_next_event(&mut self, _: &Bodies, _: &mut Vec<PairChange>) -> &'static str {
        "none" // never called: the brute force schedules no events of its own
    }

    fn certificates(&self) -> usize {
        0
    }

    fn validate(&self, bodies: &Bodies, _: Real) -> Result<(), String> {
        let live = bodies.iter().filter(|b| b.is_some()).count();
        if live != self.live.len() {
            return Err(format!(
                "brute force knows {} objects, the world has {live}",
                self.live.len()
            ));
        }
        match self
            .live
            .iter()
            .find(|&&id| bodies.get(id as usize).is_none_or(Option::is_none))
        {
            Some(id) => Err(format!("brute force holds removed object {id}")),
            None => Ok(()),
        }
    }
}
