//! Driving a candidate structure event by event, with the candidate set its changes describe.

use kinetic_core::{Bodies, CandidateStructure, PairChange};
use std::collections::{BTreeMap, BTreeSet};

/// A structure with the candidate set its changes describe.
pub struct Driven<S> {
    pub grid: S,
    pub count: BTreeMap<(u32, u32), i32>,
    pub changes: Vec<PairChange>,
}

impl<S: CandidateStructure> Driven<S> {
    pub fn new(grid: S) -> Driven<S> {
        Driven {
            grid,
            count: BTreeMap::new(),
            changes: Vec::new(),
        }
    }

    /// Counts the changes made so far: each pair once at most.
    pub fn absorb(&mut self) {
        for c in self.changes.drain(..) {
            assert!(c.a < c.b, "pair {c:?} out of order");
            let n = self.count.entry((c.a, c.b)).or_default();
            *n += c.delta;
            assert!(*n == 0 || *n == 1, "pair ({}, {}) counted {n}", c.a, c.b);
        }
        self.count.retain(|_, n| *n > 0);
    }

    pub fn candidates(&self) -> BTreeSet<(u32, u32)> {
        self.count.keys().copied().collect()
    }

    /// Runs the structure's events up to `t`, auditing after each.
    pub fn advance(&mut self, bodies: &Bodies, t: f64) -> usize {
        let mut events = 0;
        while self.grid.next_event_time() <= t {
            let at = self.grid.next_event_time();
            self.grid.process_next_event(bodies, &mut self.changes);
            self.absorb();
            events += 1;
            self.grid
                .validate(bodies, at)
                .unwrap_or_else(|e| panic!("after an event at {at}: {e}"));
        }
        events
    }
}
