//! Building a broad phase and asking it about itself.

use super::{BroadPhaseStats, Clock, KineticBroadPhase, StepStats};
use crate::motions::ByBody;
use crate::pairs::PairBook;
use kinetic_core::Real;
use kinetic_flight::Choice;
use rapier3d::prelude::*;

impl KineticBroadPhase {
    /// A broad phase that picks its structure from the first colliders it is given.
    pub fn new() -> KineticBroadPhase {
        KineticBroadPhase {
            choice: None,
            slack_fraction: 0.05,
            min_slack: 1e-3,
            structure: None,
            bodies: Vec::new(),
            plans: Vec::new(),
            proxies: Vec::new(),
            movers: Vec::new(),
            moved_bits: Vec::new(),
            motions: ByBody::default(),
            moving: Vec::new(),
            grown: Vec::new(),
            lag_reach: None,
            book: PairBook::default(),
            clock: Clock::default(),
            emitted: (Real::NAN, Real::NAN),
            changes: Vec::new(),
            out: Vec::new(),
            stats: BroadPhaseStats::default(),
            step: StepStats::default(),
            audit: false,
            audit_error: None,
        }
    }

    /// The same broad phase with the structure chosen by the caller.
    pub fn with_structure(mut self, choice: Choice) -> KineticBroadPhase {
        self.choice = Some(choice);
        self
    }

    /// The same broad phase with another slack: a moving body may stray `fraction` of its
    /// size (at least `min` length units) from its plan before it is re-planned. More slack,
    /// fewer re-plans and more pairs. Default 0.05 and 0.001.
    pub fn with_slack(mut self, fraction: f32, min: f32) -> KineticBroadPhase {
        self.slack_fraction = fraction.max(0.0) as Real;
        self.min_slack = min.max(1e-9) as Real;
        self
    }

    /// The same broad phase, auditing itself after every event of its structure (slow; for
    /// tests). The first failure is kept: see [`KineticBroadPhase::audit_error`].
    pub fn with_audit(mut self) -> KineticBroadPhase {
        self.audit = true;
        self
    }

    /// The first failure of the audit, if any.
    pub fn audit_error(&self) -> Option<&str> {
        self.audit_error.as_deref()
    }

    /// The structure in use: `"grid"`, `"sweep"`, `"guards"`, or `"none"` before the first
    /// collider.
    pub fn structure_name(&self) -> &'static str {
        self.structure.as_ref().map_or("none", |s| s.name())
    }

    /// Figures over the whole run.
    pub fn stats(&self) -> BroadPhaseStats {
        BroadPhaseStats {
            pairs: self.book.reported(),
            candidates: self.book.candidates(),
            ..self.stats
        }
    }

    /// Figures over the last physics step.
    pub fn last_step(&self) -> StepStats {
        self.step
    }

    /// The structure's own figures (e.g. the sweep's box pairs, the guards' watches).
    pub fn structure_counters(&self) -> Vec<(&'static str, f64)> {
        self.structure.as_ref().map_or(Vec::new(), |s| s.counters())
    }

    /// Whether rapier has the pair of these two colliders by this broad phase.
    pub fn has_pair(&self, a: ColliderHandle, b: ColliderHandle) -> bool {
        let (ia, ib) = (a.into_raw_parts().0, b.into_raw_parts().0);
        self.known(a) && self.known(b) && self.book.has(ia, ib)
    }
}
