//! The default structure of a [`crate::World`] whose objects come one by one and whose
//! sizes are not known when it is made: the box structure the cost model picks
//! ([`for_flights`]) for the objects it holds.
//!
//! It starts as the brute force, which costs least for a few dozen objects whatever they do
//! (see [`super::cost::brute_force_pays`]), and keeps the spread of the outer radii of every object
//! it has held. Once it holds more than [`ELASTIC_BRUTE_MAX`] objects, or a newcomer widens
//! the spread past the rule's bound, it builds the structure the rule now names from every
//! object it holds and hands its pairs over: the new structure's pairs are added before the
//! old one's are let go, so no pair in contact is dropped for an instant and the log is the
//! same as the new structure's from the start. It never goes back to the brute force, and the
//! spread only grows, so this happens at most three times (brute force, loose grid, grid,
//! sweep).

use super::Structure;
use super::cost::{ELASTIC_BRUTE_MAX, for_flights};
use kinetic_core::kds::{Bodies, PairChange, additions_first};
use kinetic_core::{CandidateStructure, Real, Vec3, WorldKind};

/// The flight structure the rule picks for the objects held so far.
#[derive(Debug)]
pub(crate) struct Auto {
    /// The structure in use.
    choice: Structure,
    inner: Box<dyn CandidateStructure>,
    /// Whether each id is held, and how many are.
    held: Vec<bool>,
    live: usize,
    /// The smallest and largest outer radius of every object held so far.
    lo: Real,
    hi: Real,
    least_flight: Real,
    switches: u64,
}

impl Default for Auto {
    fn default() -> Auto {
        Auto::new()
    }
}

impl Auto {
    /// An empty structure (the brute force for a few dozen objects, then the box structure the
    /// rule names: the grid for most worlds).
    pub(crate) fn new() -> Auto {
        Auto::with_least_flight(0.0)
    }

    /// An empty structure whose grids give every region at least `flight` time units of
    /// flight (see [`LooseGrid::with_least_flight`]).
    pub(crate) fn with_least_flight(flight: Real) -> Auto {
        let least_flight = if flight.is_finite() {
            flight.max(0.0)
        } else {
            0.0
        };
        Auto {
            choice: Structure::BruteForce,
            inner: make(Structure::BruteForce, least_flight),
            held: Vec::new(),
            live: 0,
            lo: Real::INFINITY,
            hi: 0.0,
            least_flight,
            switches: 0,
        }
    }

    /// The structure the rule names for the objects held so far: the brute force while they
    /// are few and it has never held more, else the box structure for their spread.
    fn wanted(&self) -> Structure {
        if self.choice == Structure::BruteForce && self.live <= ELASTIC_BRUTE_MAX {
            Structure::BruteForce
        } else {
            // What the objects will do is not known: the sweep for its spread alone.
            for_flights(self.spread(), self.live, Real::INFINITY)
        }
    }

    /// Widens the spread by the outer radii of `ids` and moves to the structure the rule
    /// names for it, with `ids` inserted.
    fn take_in(&mut self, ids: &[u32], bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        for &id in ids {
            if let Some(b) = &bodies[id as usize] {
                let r = b.shape.outer_radius();
                if r > 0.0 {
                    self.lo = self.lo.min(r);
                    self.hi = self.hi.max(r);
                }
            }
        }
        let fresh = ids
            .iter()
            .filter(|&&id| !self.held.get(id as usize).copied().unwrap_or(false))
            .count();
        self.live += fresh;
        let want = self.wanted();
        if want == self.choice {
            self.mark(ids, true);
            self.inner.insert_many(ids, bodies, now, changes);
            return;
        }
        let old: Vec<u32> = (0..self.held.len() as u32)
            .filter(|&id| self.held[id as usize])
            .collect();
        self.mark(ids, true);
        let mut next = make(want, self.least_flight);
        let all: Vec<u32> = old.iter().chain(ids).copied().collect();
        let from = changes.len();
        next.insert_many(&all, bodies, now, changes);
        for &id in &old {
            self.inner.remove(id, bodies, now, changes);
        }
        additions_first(&mut changes[from..]);
        if !old.is_empty() {
            self.switches += 1;
        }
        self.inner = next;
        self.choice = want;
    }

    /// The spread of the outer radii of every object held so far (1 for none).
    fn spread(&self) -> Real {
        if self.hi > 0.0 {
            self.hi / self.lo
        } else {
            1.0
        }
    }

    fn mark(&mut self, ids: &[u32], held: bool) {
        if let Some(&top) = ids.iter().max()
            && self.held.len() <= top as usize
        {
            self.held.resize(top as usize + 1, false);
        }
        for &id in ids {
            self.held[id as usize] = held;
        }
    }
}

/// An empty structure of kind `choice` (one the cost model names: the brute force or a box
/// structure, each of which holds any world).
fn make(choice: Structure, least_flight: Real) -> Box<dyn CandidateStructure> {
    choice
        .build(WorldKind::Free, &[], least_flight)
        .unwrap_or_else(|_| Box::new(kinetic_core::BruteForce::new()))
}

impl CandidateStructure for Auto {
    fn name(&self) -> &'static str {
        self.inner.name()
    }

    fn insert(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.take_in(&[id], bodies, now, changes);
    }

    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        self.take_in(ids, bodies, now, changes);
    }

    fn remove(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if self.held.get(id as usize).copied().unwrap_or(false) {
            self.held[id as usize] = false;
            self.live -= 1;
            self.inner.remove(id, bodies, now, changes);
        }
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.inner.replan(id, bodies, now, changes);
    }

    fn next_event_time(&self) -> Real {
        self.inner.next_event_time()
    }

    fn process_next_event(
        &mut self,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) -> &'static str {
        self.inner.process_next_event(bodies, changes)
    }

    fn certificates(&self) -> usize {
        self.inner.certificates()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        let mut c = self.inner.counters();
        c.push(("switches", self.switches as f64));
        c
    }

    fn boxes(&self, bodies: &Bodies, now: Real) -> Vec<(Vec3, Vec3)> {
        self.inner.boxes(bodies, now)
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        for (id, b) in bodies.iter().enumerate() {
            let held = self.held.get(id).copied().unwrap_or(false);
            if held != b.is_some() {
                return Err(format!(
                    "auto: object {id} held {held}, live {}",
                    b.is_some()
                ));
            }
        }
        let live = self.held.iter().filter(|&&h| h).count();
        if live != self.live {
            return Err(format!("auto: {live} objects held, {} counted", self.live));
        }
        if self.wanted() != self.choice {
            return Err(format!(
                "auto: holds {} for {live} objects of a spread of {}",
                self.inner.name(),
                self.spread()
            ));
        }
        self.inner.validate(bodies, now)
    }
}
