//! Building a broad phase and asking it about itself.

use super::motions::ByBody;
use super::pairs::PairBook;
use super::{BroadPhaseCore, BroadPhaseStats, Clock, StepStats};
use crate::{Key, Slack};
use kinetic_core::Real;

impl BroadPhaseCore {
    /// A broad phase that picks its structure from the first colliders it is given.
    pub fn new() -> BroadPhaseCore {
        BroadPhaseCore {
            loose_grid: None,
            choice_given: false,
            engine_boxes: false,
            stepped: None,
            meter: Default::default(),
            adopting: None,
            slack: Slack {
                fraction: 0.05,
                min: 1e-3,
            },
            structure: None,
            bodies: Vec::new(),
            plans: Vec::new(),
            proxies: Vec::new(),
            held: 0,
            movers: Vec::new(),
            moved_bits: Vec::new(),
            states: Vec::new(),
            motions: ByBody::default(),
            moving: Vec::new(),
            grown: Vec::new(),
            lag_reach: None,
            book: PairBook::default(),
            clock: Clock::default(),
            changes: Vec::new(),
            out: Vec::new(),
            held_events: Vec::new(),
            handed: Default::default(),
            stats: BroadPhaseStats::default(),
            step: StepStats::default(),
            audit: false,
            audit_error: None,
        }
    }

    /// The same broad phase with its proxies in the structure the caller chose: the loose
    /// grid (`loose`) or the hierarchical grid. It then stays kinetic.
    pub fn with_loose_grid(mut self, loose: bool) -> BroadPhaseCore {
        self.loose_grid = Some(loose);
        self.choice_given = true;
        self
    }

    /// The same broad phase with another slack: a moving body may stray `fraction` of its
    /// size (at least `min` length units; the engine may scale it to its own unit) from its plan before it is re-planned. More slack,
    /// fewer re-plans and more pairs. Default 0.05 and 0.001.
    pub fn with_slack(mut self, fraction: Real, min: Real) -> BroadPhaseCore {
        self.slack = Slack {
            fraction: fraction.max(0.0),
            min: min.max(1e-9),
        };
        self
    }

    /// The same broad phase, auditing itself after every event of its structure (slow; for
    /// tests). The first failure is kept: see [`BroadPhaseCore::audit_error`].
    pub fn with_audit(mut self) -> BroadPhaseCore {
        self.audit = true;
        self
    }

    /// The first failure of the audit, if any.
    pub fn audit_error(&self) -> Option<&str> {
        self.audit_error.as_deref()
    }

    /// The structure in use: `"grid"`, `"loose-grid"`, `"sweep"`, `"guards"`, `"stepped"`
    /// while the world is stepped, or `"none"` before the first collider.
    pub fn structure_name(&self) -> &'static str {
        if self.is_stepped() {
            return "stepped";
        }
        self.structure.as_ref().map_or("none", |s| s.name())
    }

    /// Figures over the whole run.
    pub fn stats(&self) -> BroadPhaseStats {
        if let Some(st) = &self.stepped {
            let (filings, refattened) = st.fat_counts();
            return BroadPhaseStats {
                pairs: self.handed_count(),
                candidates: st.pair_count(),
                fat_filings: self.stats.fat_filings + filings,
                refattened: self.stats.refattened + refattened,
                rest_filings: self.stats.rest_filings + st.rest_filings(),
                engine_lookups: self.stats.engine_lookups + st.engine_lookups(),
                ..self.stats
            };
        }
        BroadPhaseStats {
            pairs: self.handed.handed(),
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

    /// The slack a moving body is given ([`BroadPhaseCore::with_slack`]).
    pub fn slack(&self) -> Slack {
        self.slack
    }

    /// Whether the engine has the pair of these two colliders by this broad phase.
    pub fn has_pair(&self, a: Key, b: Key) -> bool {
        // A stepped world's pairs are the engine's, kept there.
        let has = match &self.stepped {
            Some(st) => st.holds(a.index, b.index),
            None => self.handed.has(a.index, b.index),
        };
        self.knows(a) && self.knows(b) && has
    }

    /// The colliders with which the engine has a pair with collider `c` by this broad
    /// phase, in the order they are held (the same on every run): an engine that keeps its
    /// own pair list need not keep another beside it. A world stepped on boxes swept over
    /// the step keeps its pairs sorted, not per collider: there this takes a pass over
    /// them all.
    pub fn partners(&self, c: Key) -> impl Iterator<Item = Key> + '_ {
        let known = self.knows(c);
        // A stepped world keeps the engine's pairs itself; a kinetic one, as links.
        let st = self.stepped.as_ref();
        let linked = st.is_none().then(|| self.handed.partners(c.index));
        let paired = st.into_iter().flat_map(move |st| st.partners_of(c.index));
        let paired = paired.filter_map(|j| self.proxies.get(j as usize).copied().flatten());
        linked
            .into_iter()
            .flatten()
            .chain(paired.map(|p| p.key))
            .filter(move |_| known)
    }

    /// How many pairs the engine has by this broad phase.
    pub(super) fn handed_count(&self) -> usize {
        match &self.stepped {
            Some(st) => st.pair_count(),
            None => self.handed.handed(),
        }
    }

    /// Whether the world steps on the engine's enlarged boxes (for good).
    pub(super) fn on_engine_boxes(&self) -> bool {
        self.stepped.as_ref().is_some_and(|st| st.on_engine_boxes())
    }

    /// Whether the broad phase holds the pair of these two colliders: their proxies can
    /// meet within the step (the engine has those of them whose boxes meet too).
    pub fn holds_pair(&self, a: Key, b: Key) -> bool {
        if !(self.knows(a) && self.knows(b)) {
            return false;
        }
        match &self.stepped {
            Some(st) => st.holds(a.index, b.index),
            None => self.book.has(a.index, b.index),
        }
    }

    /// Whether the next position update needs every moved collider listed: always, except in
    /// a world stepped on the engine's enlarged boxes ([`crate::Engine::enlarged`]), where
    /// the engine need list only the colliders whose enlarged boxes it moved.
    pub fn reads_every_move(&self) -> bool {
        !self.on_engine_boxes()
    }

    /// Whether collider `c` is held on a moving body (its moves come with its body's).
    pub fn on_moving_body(&self, c: Key) -> bool {
        self.movers
            .get(c.index as usize)
            .copied()
            .flatten()
            .is_some_and(|(g, body)| g == c.generation && body != u32::MAX)
    }

    /// Whether collider `c` is held.
    pub fn knows(&self, c: Key) -> bool {
        self.proxies
            .get(c.index as usize)
            .and_then(|p| p.as_ref())
            .is_some_and(|p| p.key == c)
    }

    /// The number of colliders held.
    pub fn held(&self) -> usize {
        self.held
    }
}
