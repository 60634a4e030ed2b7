//! # kinetic-avian
//!
//! A kinetic broad phase for avian3d 0.8: [`KineticBroadPhasePlugin`] replaces avian's BVH
//! broad phase with the engine-agnostic core of `kinetic-broad` (which `kinetic-rapier`
//! shares). Swap it in with one line:
//!
//! ```no_run
//! use avian3d::prelude::*;
//! use bevy::prelude::*;
//! use kinetic_avian::KineticBroadPhasePlugin;
//!
//! App::new()
//!     .add_plugins((MinimalPlugins, TransformPlugin))
//!     .add_plugins(
//!         PhysicsPlugins::default()
//!             .build()
//!             .disable::<BvhBroadPhasePlugin>()
//!             .add(KineticBroadPhasePlugin::new()),
//!     )
//!     .run();
//! ```
//!
//! ## What it does
//!
//! Each collider is a proxy of the engine-agnostic core. avian keeps an enlarged box
//! (`EnlargedAabb`) about every collider and moves it only when the collider's box leaves
//! it; its narrow phase keeps a pair while the two enlarged boxes overlap. The core reads
//! those boxes ([`kinetic_broad::Engine::enlarged`]) and steps on them for good: each step
//! it looks only at the colliders whose enlarged boxes avian moved (avian's
//! `MovedProxies`), keeps each collider's pairs, and adds or deletes those that changed.
//! Each moved box is looked up in avian's own collider trees, which avian keeps up to date
//! for its queries whichever broad phase runs ([`kinetic_broad::Engine::enlarged_near`]), so
//! the plugin keeps no index of its own beside them (a step that moves so many boxes that
//! filing them all costs less files them in the core's grid instead).
//! A heap of bodies jostling inside their boxes, or asleep, costs next to nothing, whatever
//! the pairs it holds. Once a step, before avian's narrow phase, the pairs whose boxes
//! overlap are *live*.
//!
//! The plugin adds to the [`ContactGraph`](avian3d::prelude::ContactGraph) every live pair
//! whose enlarged boxes overlap and that the graph does not hold, filtered as avian's own
//! broad phase filters: collision layers, colliders of one body, static pairs, joints with
//! collisions disabled, and the `filter_pairs` hook of `H`
//! ([`CollisionHooks`](avian3d::prelude::CollisionHooks)). The graph then gets the pairs
//! avian's own broad phase would give it.
//! avian's own broad phase looks up in the graph every pair of every collider whose box
//! moved; the plugin looks a live pair up only where it may be missing: a new pair, a pair
//! of a changed collider, or one it left out before (filtered, as avian asks again each time
//! a box moves). avian's changes that take pairs out of the graph (a joint, a body disabled,
//! enabled or made no body, a sensor made a plain collider) make it look at those pairs
//! again as their colliders move; so does [`KineticBroadPhase::recheck_pairs`], for pairs
//! taken out of the graph by hand.
//!
//! With [`KineticBroadPhasePlugin::with_loose_grid`] the caller picks a kinetic structure
//! instead: every collider is then a ball about its body's centre of mass (grown by avian's
//! contact tolerance, the collision margin and a slack) on a flight plan fitted to avian's
//! substepped integrator, and the structure is advanced over each step through its own
//! events in time order.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod checks;
mod graph;
mod view;

use avian3d::collision::CollisionDiagnostics;
use avian3d::prelude::*;
use bevy::ecs::system::{StaticSystemParam, SystemParamItem};
use bevy::prelude::*;
use core::marker::PhantomData;
use kinetic_broad::BroadPhaseCore;

pub use kinetic_broad::{BroadPhaseStats, StepStats};

/// The avian plugin: add it with avian's `BvhBroadPhasePlugin` disabled (the crate docs show
/// how). `H`: the collision hooks whose `filter_pairs` applies, as with avian's own broad
/// phase.
pub struct KineticBroadPhasePlugin<H: CollisionHooks = ()> {
    loose_grid: Option<bool>,
    audit: bool,
    hooks: PhantomData<H>,
}

impl<H: CollisionHooks> Default for KineticBroadPhasePlugin<H> {
    fn default() -> Self {
        KineticBroadPhasePlugin {
            loose_grid: None,
            audit: false,
            hooks: PhantomData,
        }
    }
}

impl KineticBroadPhasePlugin {
    /// The plugin with no collision hooks: `KineticBroadPhasePlugin::<H>::default()` takes
    /// those of `H`.
    pub fn new() -> Self {
        KineticBroadPhasePlugin::default()
    }
}

impl<H: CollisionHooks> KineticBroadPhasePlugin<H> {
    /// The same plugin with its proxies in the kinetic structure the caller chose, the loose
    /// grid (`loose`) or the hierarchical grid, on flight plans (by default the broad phase
    /// steps on avian's enlarged boxes).
    pub fn with_loose_grid(mut self, loose: bool) -> Self {
        self.loose_grid = Some(loose);
        self
    }

    /// The same plugin, auditing the broad phase after every event of its structure and
    /// every step (slow; for tests): see [`KineticBroadPhase::audit_error`].
    pub fn with_audit(mut self) -> Self {
        self.audit = true;
        self
    }
}

impl<H: CollisionHooks + 'static> Plugin for KineticBroadPhasePlugin<H>
where
    for<'w, 's> SystemParamItem<'w, 's, H>: CollisionHooks,
{
    fn build(&self, app: &mut App) {
        let mut core = BroadPhaseCore::new();
        if let Some(loose) = self.loose_grid {
            core = core.with_loose_grid(loose);
        }
        if self.audit {
            core = core.with_audit();
        }
        app.insert_resource(KineticBroadPhase {
            core,
            audit: self.audit,
            ..KineticBroadPhase::default()
        });
        view::observe_insertions(app);
        app.add_systems(
            PhysicsSchedule,
            collect_pairs::<H>.in_set(BroadPhaseSystems::CollectCollisions),
        );
    }
}

/// The broad phase's state, a resource: ask it for figures, or whether a pair is live.
#[derive(Resource, Default)]
pub struct KineticBroadPhase {
    core: BroadPhaseCore,
    /// Which live pairs to look for in the contact graph (the pairs themselves are kept in
    /// the core alone: [`BroadPhaseCore::partners`]).
    checks: checks::Checks,
    /// Whether the first step has been seen.
    started: bool,
    audit: bool,
    audit_error: Option<String>,
    /// Pairs added to the contact graph, over the run and in the last step.
    added: u64,
    last_added: u64,
    /// Time spent in the last step.
    last_time: std::time::Duration,
}

impl KineticBroadPhase {
    /// Figures over the whole run.
    pub fn stats(&self) -> BroadPhaseStats {
        self.core.stats()
    }

    /// Figures over the last step's position update.
    pub fn last_step(&self) -> StepStats {
        self.core.last_step()
    }

    /// The structure in use (its registry name), `"stepped"` while the broad phase steps, or
    /// `"none"` before the first collider.
    pub fn structure_name(&self) -> &'static str {
        self.core.structure_name()
    }

    /// The pairs whose proxies can meet within the step.
    pub fn live_pairs(&self) -> usize {
        self.core.stats().pairs
    }

    /// Whether the proxies of colliders `a` and `b` can meet within the step.
    pub fn is_live(&self, a: Entity, b: Entity) -> bool {
        self.core.has_pair(view::key(a), view::key(b))
    }

    /// Pairs added to avian's contact graph, over the whole run.
    pub fn added(&self) -> u64 {
        self.added
    }

    /// Pairs added to the contact graph in the last step, and the time the step took.
    pub fn last_added(&self) -> (u64, std::time::Duration) {
        (self.last_added, self.last_time)
    }

    /// The first failure of the audit, if any ([`KineticBroadPhasePlugin::with_audit`]).
    pub fn audit_error(&self) -> Option<&str> {
        self.core.audit_error().or(self.audit_error.as_deref())
    }

    /// The engine-agnostic core it runs on.
    pub fn core(&self) -> &BroadPhaseCore {
        &self.core
    }

    /// In audit mode, validates the core against avian's world and keeps the first failure,
    /// saying `when` it came.
    fn audit_now(&mut self, world: &view::AvianWorld, when: &str) {
        if self.audit && self.audit_error.is_none() {
            let all = world.collider_keys();
            if let Err(e) = self.core.validate(world, all) {
                self.audit_error = Some(format!("{when}: {e}"));
            }
        }
    }

    /// Checks every live pair again when its colliders next move: call it after taking
    /// pairs out of avian's contact graph by hand (the plugin itself observes every change
    /// of avian's that takes pairs out).
    pub fn recheck_pairs(&mut self) {
        self.checks.recheck_all();
    }
}

/// The plugin's system, in avian's `BroadPhaseSystems::CollectCollisions`.
#[allow(clippy::too_many_arguments)]
fn collect_pairs<H: CollisionHooks>(
    mut state: ResMut<KineticBroadPhase>,
    world: view::AvianWorld,
    mut changes: view::Changes,
    hooks: StaticSystemParam<H>,
    mut commands: Commands,
    mut contact_graph: ResMut<ContactGraph>,
    mut diagnostics: ResMut<CollisionDiagnostics>,
) where
    for<'w, 's> SystemParamItem<'w, 's, H>: CollisionHooks,
{
    let start = std::time::Instant::now();
    let state = &mut *state;
    let step = world.step();
    let every = !state.started || state.core.reads_every_move();
    let moves = match (state.started, every) {
        // The first call: every collider is new, none has moved.
        (false, _) => view::Moves::None,
        (true, true) => view::Moves::Every,
        (true, false) => view::Moves::Enlarged,
    };
    let (modified, removed, moved) = changes.collect(&world, &state.core, moves);
    if changes.take_recheck() || world.joints.is_changed() {
        // Pairs may have left the graph unseen: a joint, or a body disabled or retyped.
        state.checks.recheck_all();
    }
    state.checks.forget(&removed);
    let mut events = Vec::new();
    if step.dt > 0.0 {
        let removed = if state.started {
            // The positions moved on by a step since the last call: the bodies that moved,
            // after the colliders removed (whose indices new ones may take).
            state
                .core
                .update(step, &world, &moved, &removed, &mut events);
            state.checks.note(&events);
            events.clear();
            if modified.is_empty() {
                // (With changes made since, the world is already past what the core knows.)
                state.audit_now(&world, "after the position update");
            }
            &[][..]
        } else {
            &removed[..]
        };
        // The start of the step: the user's changes (on the first call, every collider).
        state.started = true;
        state
            .core
            .update(step, &world, &modified, removed, &mut events);
        state.checks.note(&events);
    }
    state.audit_now(&world, "at the start of the step");
    // Of the live pairs, those that may have to go into the graph: the new ones, those of
    // colliders changed, and those of colliders whose enlarged boxes avian moved that were
    // not all found in the graph before. A collider that only jiggles within its enlarged
    // box costs nothing here.
    // (Between reads of every moved body, `moved` is already those.)
    let moved: Vec<_> = if every {
        world.enlarged_moved(false).collect()
    } else {
        moved
    };
    let trust = !state.core.reads_every_move();
    let check = state.checks.pairs(&state.core, &modified, &moved, trust);
    let mut in_graph = Vec::with_capacity(check.len());
    let added = graph::add_overlapping(
        &check,
        &world,
        &hooks.into_inner(),
        &mut commands,
        &mut contact_graph,
        &mut in_graph,
    );
    state.checks.settle(&check, &in_graph);
    state.added += added;
    state.last_added = added;
    state.last_time = start.elapsed();
    diagnostics.broad_phase += state.last_time;
}
