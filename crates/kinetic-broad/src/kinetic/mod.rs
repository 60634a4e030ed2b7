//! The kinetic half of the broad phase, and its front door: colliders as proxies in a
//! kinetic structure, bodies on flight plans fitted to the engine's integrator, the pairs the
//! structure holds, and of those the engine's own handed to it (see the crate docs). Where
//! plans do not hold, the core steps instead (`mode.rs`), with the other half
//! ([`crate::stepped`]).
//!
//! Split by operation: `api.rs` (building and asking), `bound.rs` (how a collider is held),
//! `motions.rs` (per-body state), `proxies.rs` (colliders in and out of the structure),
//! `plans.rs` (bodies' plans and slack), `update.rs` (the engine's call and the structure's
//! events), `pairs.rs` (the book of held pairs), `handed.rs` (the pairs handed to the
//! engine), `fat.rs` (bodies at rest held by fat boxes), `mode.rs` (kinetic or stepped),
//! `stats.rs`, `validate.rs`.

mod api;
mod bound;
mod fat;
mod handed;
mod mode;
mod motions;
mod pairs;
mod plans;
mod proxies;
mod stats;
#[cfg(test)]
mod tests;
mod update;
mod validate;

pub use bound::{Bound, Slack, fit_plan};
pub use stats::{BroadPhaseStats, StepStats};

use crate::Aabb;
use crate::Key;
use kinetic_core::kds::PairChange;
use kinetic_core::{Body, CandidateStructure, FlightPlan, Real, Vec3};
use motions::ByBody;
use pairs::{PairBook, PairOut};
use smallvec::SmallVec;

/// Steps over which a body must stay within half its slack to be planned at rest.
const REST_STEPS: Real = 30.0;
/// A body whose last [`RESTLESS_RUN`] re-plans each came within this many position updates of
/// the one before has its slack doubled...
const RESTLESS_UPDATES: u64 = 2;
/// ... (four, so five re-plans in all: not a body that starts to fall, which takes up to three
/// to learn its acceleration)...
const RESTLESS_RUN: u32 = 4;
/// ... up to this many times (a slack 8 times the base)...
const MAX_GROWTH: u32 = 3;
/// ... and halved at a re-plan that comes at least this many updates after the last.
const CALM_UPDATES: u64 = 60;

/// The loose grid's regions cover at most this many steps of a body's flight: a body
/// coasting slowly in a pile holds a region hugging its box, not one stretched over two box
/// widths of its drift (at the end of the rain at 1e4: 23 candidates per body, not 62).
const REGION_STEPS: Real = 4.0;
/// The loose grid's regions are wider than the boxes they hold by this share of a box width
/// on every side: bodies jostled in a pile or a rain keep far fewer candidates than with the
/// grid's default (a quarter width), for a few more re-anchors (at 1e4 bodies, the pile's
/// broad phase 28% faster and the rain's 18%; `docs/results/rapier.md`).
const REGION_MARGIN: Real = 0.1;

/// A candidate structure the broad phase can hold across threads.
type Structure = Box<dyn CandidateStructure + Send + Sync>;

/// A collider as the broad phase holds it.
#[derive(Clone, Copy, Debug)]
struct Proxy {
    key: Key,
    hold: Bound,
    /// Grown to cover the time between its change and the structure's clock, until the
    /// positions reach this time.
    grown_until: Option<Real>,
    /// The fat box `(min, max)` it is held by while its body is at rest (`None`: the ball
    /// of its hold, on the body's plan).
    fat: Option<Aabb>,
}

/// A moving body's plan and what the broad phase has seen of it.
#[derive(Clone, Debug)]
struct Motion {
    plan: FlightPlan,
    /// The least base slack of its colliders.
    slack: Real,
    /// The slack is the base times `2^growth`: doubled for a body that keeps re-planning
    /// (one jostled in a pile), halved back once it keeps its plans.
    growth: u32,
    /// The position update of its last re-plan, and how many re-plans running came within
    /// [`RESTLESS_UPDATES`] of the one before.
    replanned: u64,
    restless: u32,
    /// Its colliders (one or two most often: held in place, not on the heap).
    colliders: SmallVec<[u32; 2]>,
    /// Its velocity at the last position update that moved it, and which update that was.
    last_v: Vec3,
    seen: u64,
    /// The acceleration it showed over the last update (if seen on the one before).
    last_a: Option<Vec3>,
    /// The acceleration it showed over two updates running: what its plan assumes.
    steady_a: Vec3,
    /// Whether it is in `BroadPhaseCore::moving`.
    listed: bool,
    /// Whether its colliders are held by fat boxes (a body at rest) rather than on its plan.
    fat: bool,
}

/// The broad phase's clock: the time of the colliders' positions and of the structure.
#[derive(Clone, Copy, Debug, Default)]
struct Clock {
    /// The positions' time: the sum of the steps integrated so far.
    pos: Real,
    /// The structure's time: the end of the window it has looked ahead to.
    kds: Real,
    /// The length of the current step, and how much of it is still to be integrated.
    dt: Real,
    left: Real,
    /// Whether the next call is the start of a step (the user's changes).
    in_step: bool,
    /// Position updates seen.
    updates: u64,
}

/// The kinetic broad phase, for any engine: an adapter implements [`crate::Engine`] over its
/// colliders and bodies and calls [`BroadPhaseCore::update`].
pub struct BroadPhaseCore {
    /// Whether the proxies live in the loose grid (else the hierarchical grid); `None` until
    /// the first colliders decide.
    loose_grid: Option<bool>,
    /// Whether the caller chose the structure (it then stays kinetic).
    choice_given: bool,
    /// Whether the engine keeps enlarged boxes of its own ([`crate::Engine::enlarged`]),
    /// found from the first colliders: the world then steps for good, on those boxes, and
    /// keeps no plans (a collider is read with [`crate::Engine::collider_on_boxes`]).
    engine_boxes: bool,
    /// The stepped mode's state while the world is stepped ([`mode`]).
    stepped: Option<mode::Stepped>,
    meter: mode::Meter,
    /// After a switch back to kinetic, the pairs the engine had, for the book to adopt.
    adopting: Option<Vec<(u32, u32)>>,
    slack: Slack,
    structure: Option<Structure>,
    bodies: Vec<Option<Body>>,
    /// Per collider, the version of its proxy's plan (bumped at every change), for the pair
    /// book's gate to know when to ask again.
    plans: Vec<u32>,
    proxies: Vec<Option<Proxy>>,
    /// How many colliders are held (`proxies` that are `Some`).
    held: usize,
    /// Per collider index, the generation of the collider held there and the index of its
    /// moving body (`u32::MAX` for a fixed one): all a position update reads of each moved
    /// collider, kept compact because an engine lists them in its own order (rapier: its islands').
    movers: Vec<Option<(u32, u32)>>,
    /// The bodies moved in this position update, a bit per body index: they are looked at
    /// in index order, each once, whatever order the engine lists their colliders in.
    moved_bits: Vec<u64>,
    /// The moved bodies' centres and velocities as the engine gave them in the last update
    /// (a buffer).
    states: Vec<Option<(Vec3, Vec3)>>,
    motions: ByBody<Motion>,
    /// Bodies whose plans are not at rest, in the order they started moving.
    moving: Vec<Key>,
    /// Colliders whose proxies may be grown (checked when the positions move on).
    grown: Vec<u32>,
    /// This call's [`BroadPhaseCore::lag_growth`], once worked out.
    lag_reach: Option<Real>,
    book: PairBook,
    clock: Clock,
    changes: Vec<PairChange>,
    out: Vec<PairOut>,
    /// The held pairs' events of the current call (a buffer), and which held pairs the
    /// engine has.
    held_events: Vec<crate::PairEvent>,
    handed: handed::Handed,
    stats: BroadPhaseStats,
    step: StepStats,
    audit: bool,
    audit_error: Option<String>,
}

impl Proxy {
    /// Its entry in [`BroadPhaseCore::movers`]: the collider's generation and the index
    /// of its moving body (`u32::MAX` when fixed).
    fn mover(&self) -> (u32, u32) {
        let body = match self.hold {
            Bound::Moving { body, .. } => body.index,
            Bound::Fixed { .. } => u32::MAX,
        };
        (self.key.generation, body)
    }
}

impl Default for BroadPhaseCore {
    fn default() -> Self {
        BroadPhaseCore::new()
    }
}

impl std::fmt::Debug for BroadPhaseCore {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("BroadPhaseCore")
            .field("structure", &self.structure_name())
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}
