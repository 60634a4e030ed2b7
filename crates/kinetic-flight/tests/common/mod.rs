//! Driving a candidate structure event by event, with the candidate set its changes describe.

use kinetic_core::kds::{Bodies, PairChange};
use kinetic_core::{Body, CandidateStructure, FlightPlan, Shape, Vec3};
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

    /// Tells the structure that object `id`'s plan changed at `t`, auditing after.
    pub fn replan(&mut self, bodies: &Bodies, id: usize, t: f64) {
        self.grid.replan(id as u32, bodies, t, &mut self.changes);
        self.absorb();
        self.grid
            .validate(bodies, t)
            .unwrap_or_else(|e| panic!("after a re-plan at {t}: {e}"));
    }

    /// Takes object `id`, if it is live, out of the structure and of `bodies`, auditing after.
    pub fn remove(&mut self, bodies: &mut Bodies, id: usize, t: f64) {
        if bodies[id].is_none() {
            return;
        }
        self.grid.remove(id as u32, bodies, t, &mut self.changes);
        self.absorb();
        bodies[id] = None;
        self.grid
            .validate(bodies, t)
            .unwrap_or_else(|e| panic!("after a removal at {t}: {e}"));
    }

    /// Runs 20 steps of 0.01 (a shot's flight past a row, see [`shot_along_x`]), the second
    /// (where it passes the row) sampled 1,000 times. `at(self, t, sampled)` looks at the
    /// structure at each sample and each step's end. Returns the events of each step.
    pub fn fly_past_the_row(
        &mut self,
        bodies: &Bodies,
        mut at: impl FnMut(&Self, f64, bool),
    ) -> Vec<usize> {
        let mut per_step = Vec::new();
        for step in 1..=20 {
            let end = step as f64 * 0.01;
            let mut events = 0;
            if step == 2 {
                for k in 1..=1000 {
                    let t = 0.01 + k as f64 * 1e-5;
                    events += self.advance(bodies, t);
                    at(self, t, true);
                }
            }
            events += self.advance(bodies, end);
            at(self, end, false);
            per_step.push(events);
        }
        per_step
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

/// `n` balls of radius `radius` resting along the x axis, `spacing` apart from the origin.
pub fn resting_row(n: usize, spacing: f64, radius: f64) -> Vec<Option<Body>> {
    (0..n)
        .map(|i| {
            Some(Body {
                shape: Shape::Ball { radius },
                plan: FlightPlan::at_rest(Vec3::new(spacing * i as f64, 0.0, 0.0)),
            })
        })
        .collect()
}

/// A ball of radius 0.5 at x = -100 flying along x at 1e4 units per time unit: it reaches a
/// [`resting_row`] from the origin during the second step of [`Driven::fly_past_the_row`].
pub fn shot_along_x() -> Option<Body> {
    Some(Body {
        shape: Shape::Ball { radius: 0.5 },
        plan: FlightPlan::linear(Vec3::new(-100.0, 0.0, 0.0), Vec3::new(1e4, 0.0, 0.0)),
    })
}
