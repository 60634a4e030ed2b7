//! The broad phase's figures: over the whole run and over the last step.

/// Figures over the whole run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BroadPhaseStats {
    /// Physics steps seen.
    pub steps: u64,
    /// Pairs the engine has now.
    pub pairs: usize,
    /// Pairs the kinetic structure holds now (the engine also keeps, for up to a step,
    /// pairs that have just dropped out).
    pub candidates: usize,
    /// Events of the kinetic structure processed.
    pub events: u64,
    /// Bodies re-planned because they left their plan's slack (or came to rest).
    pub replans: u64,
    /// Colliders put into the structure (new ones, changed ones, and proxies grown or shrunk
    /// around a change between steps).
    pub inserts: u64,
    /// Pairs added.
    pub added: u64,
    /// Pairs deleted.
    pub deleted: u64,
    /// Times a body that kept re-planning had its slack doubled.
    pub slack_growths: u64,
    /// Times a body with grown slack that then kept its plan had it halved.
    pub slack_shrinks: u64,
    /// Times a body at rest was held by fresh fat boxes (it came to rest, or left its boxes
    /// and came to rest again).
    pub boxed: u64,
    /// Switches between kinetic and stepped ([`crate::BroadPhaseCore`]'s mode).
    pub switches: u64,
    /// Stepped: times the colliders' fat boxes were filed afresh (see `docs/structures.md`).
    pub fat_filings: u64,
    /// Stepped: colliders that left their fat boxes and were given new ones on their own.
    pub refattened: u64,
    /// Stepped: times the resting colliders (sleeping, fixed) were filed afresh, where most
    /// rest and only the moving ones are filed each step; on an engine's enlarged boxes, times
    /// all its boxes were.
    pub rest_filings: u64,
    /// Stepped on an engine's enlarged boxes: boxes looked up in the engine's own index of
    /// them ([`crate::Engine::enlarged_near`]) rather than filed.
    pub engine_lookups: u64,
}

/// Figures over the last physics step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Events of the kinetic structure processed.
    pub events: u64,
    /// Bodies re-planned.
    pub replans: u64,
    /// Colliders put into the structure.
    pub inserts: u64,
    /// Pairs added.
    pub added: u64,
    /// Pairs deleted.
    pub deleted: u64,
}
