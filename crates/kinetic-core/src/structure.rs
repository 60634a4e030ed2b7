//! What a kinetic collision structure provides to the simulator: a set of candidate pairs
//! that always contains every pair in contact, kept up to date by its own events.
//!
//! The simulator ([`crate::Simulator`]) keeps a disjointness certificate for each candidate pair
//! and reports contacts; a structure only decides which pairs are candidates. The brute force
//! ([`crate::BruteForce`]) makes every pair a candidate and has no events of its own.

use crate::body::Body;
use crate::math::{Real, Vec3};

/// A change to the candidate set: `delta` is +1 (the structure now needs the pair certified)
/// or -1 (it no longer does). A pair may be needed for several reasons; the simulator counts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PairChange {
    /// One object.
    pub a: u32,
    /// The other object.
    pub b: u32,
    /// +1 or -1.
    pub delta: i32,
}

/// Orders `changes` so that every addition comes before every removal, each kind in the
/// order it was made: a structure that re-files objects in one go (a teleport, a switch to
/// another structure) reports its new pairs before it lets the old ones go, so that a pair
/// both need, in contact perhaps, never drops to no holder for an instant.
pub fn additions_first(changes: &mut [PairChange]) {
    changes.sort_by_key(|c| std::cmp::Reverse(c.delta));
}

/// The live objects, by id: `bodies[id]` is `None` for ids not (or no longer) in the world.
pub type Bodies = [Option<Body>];

/// A kinetic structure that maintains candidate pairs.
pub trait CandidateStructure: std::fmt::Debug + Send + Sync {
    /// The name used in statistics and on the command line.
    fn name(&self) -> &'static str;
    /// Object `id` (already in `bodies`) joins at time `now`.
    fn insert(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>);
    /// Objects `ids` (already in `bodies`) join at time `now` together: a structure that can
    /// build in bulk does so here (the default inserts them one by one).
    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        for &id in ids {
            self.insert(id, bodies, now, changes);
        }
    }
    /// Object `id` (still in `bodies`) leaves at time `now`.
    fn remove(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>);
    /// Object `id` has a new flight plan from `now` on.
    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>);
    /// The time of the structure's next own event (+infinity for none).
    fn next_event_time(&self) -> Real;
    /// Processes the next own event; returns its kind for the statistics (e.g. `"swap"`).
    fn process_next_event(
        &mut self,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) -> &'static str;
    /// The number of certificates the structure itself holds (pair certificates excluded).
    fn certificates(&self) -> usize;
    /// The structure's own figures for the statistics, by name (none by default).
    fn counters(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
    /// The boxes the structure keeps at time `now`, as (min, max) corners, for pictures:
    /// threshold boxes, object boxes (none by default).
    fn boxes(&self, _bodies: &Bodies, _now: Real) -> Vec<(Vec3, Vec3)> {
        Vec::new()
    }
    /// Recomputes the structure's invariants from scratch at time `now`.
    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String>;
}
