// rapier 0.27's `BroadPhase` over the engine-agnostic core: rapier's sets seen as an `Engine`,
// its handles as `Key`s, the core's pairs as rapier's pair events. Included by `f32.rs` and
// `f64.rs`, each with its own `rapier` (rapier3d or rapier3d-f64).

use kinetic_broad::{
    Aabb,    BodyState, BroadPhaseCore, BroadPhaseStats, Engine, Bound, Key, PairEvent, ColliderStatus, Slack,
    EngineStep, StepStats,
};
use kinetic_core::{Real, Vec3, prefetch};
use rapier::prelude::*;

/// rapier's scalar.
type RReal = rapier::math::Real;

/// The kinetic broad phase for rapier 0.27: implements its [`BroadPhase`].
#[derive(Debug, Default)]
pub struct KineticBroadPhase {
    core: BroadPhaseCore,
    /// The parameters of the last step, for [`KineticBroadPhase::validate`].
    params: Option<IntegrationParameters>,
    /// Buffers reused from call to call.
    modified: Vec<Key>,
    removed: Vec<Key>,
    events: Vec<PairEvent>,
}

/// rapier's sets as the core sees them.
struct Rapier<'a> {
    colliders: &'a ColliderSet,
    bodies: &'a RigidBodySet,
    params: &'a IntegrationParameters,
}

/// A collider handle as a key.
fn key(h: ColliderHandle) -> Key {
    let (index, generation) = h.into_raw_parts();
    Key::new(index, generation)
}

/// A rigid-body handle as a key.
fn body_key(h: RigidBodyHandle) -> Key {
    let (index, generation) = h.into_raw_parts();
    Key::new(index, generation)
}

/// Converts a rapier vector.
fn dvec(v: &Vector<RReal>) -> Vec3 {
    Vec3::new(v.x as Real, v.y as Real, v.z as Real)
}

/// Converts a rapier point.
fn dpoint(p: &Point<RReal>) -> Vec3 {
    Vec3::new(p.x as Real, p.y as Real, p.z as Real)
}

/// Converts a rapier point just written to memory by code that is not inlined (parry's
/// shapes, called through a trait object), one coordinate at a time: a load of two
/// coordinates at once cannot take them from two separate stores still in flight and waits
/// for both to reach the cache (with the box tracked inline, debris of 1e3 bodies spent
/// about 5% less in the broad phase).
fn just_stored(p: &Point<RReal>) -> Vec3 {
    // Each coordinate's address passes through `black_box`, so each is loaded on its own.
    let read = |x: &RReal| *std::hint::black_box(x) as Real;
    Vec3::new(read(&p.x), read(&p.y), read(&p.z))
}

/// A rigid body's centre of mass in world space, from its current pose (rapier refreshes its
/// own world centre of mass only at the end of a step, after the broad phase has run).
fn centre_of_mass(rb: &RigidBody) -> Vec3 {
    dpoint(&(rb.position() * rb.local_center_of_mass()))
}

/// The contact margins `co`'s boxes and balls are grown by under `params`: half the
/// prediction distance and the contact skin.
fn margin_of(co: &Collider, params: &IntegrationParameters) -> Real {
    params.prediction_distance() as Real / 2.0 + co.contact_skin() as Real
}

/// How `co` is held under `params`: a ball about its body's centre of mass when the body
/// moves, its own box otherwise, both grown by half the prediction distance and the contact
/// skin. The least slack is in rapier's length unit.
fn hold_of(
    co: &Collider,
    bodies: &RigidBodySet,
    params: &IntegrationParameters,
    slack: Slack,
) -> Bound {
    let margin = margin_of(co, params);
    let moving = co
        .parent()
        .and_then(|h| bodies.get(h).map(|rb| (h, rb)))
        .filter(|(_, rb)| !rb.is_fixed());
    match moving {
        None => {
            let aabb = co.compute_aabb();
            Bound::fixed(dpoint(&aabb.mins), dpoint(&aabb.maxs), margin)
        }
        Some((h, rb)) => {
            let sphere = co.shape().compute_bounding_sphere(co.position());
            let reach =
                (dpoint(sphere.center()) - centre_of_mass(rb)).length() + sphere.radius() as Real;
            let slack = Slack {
                min: slack.min * params.length_unit as Real,
                ..slack
            };
            Bound::moving(body_key(h), reach, margin, slack)
        }
    }
}

impl Rapier<'_> {
    /// The rigid body of key `b`, if rapier has it.
    fn rigid_body(&self, b: Key) -> Option<&RigidBody> {
        self.bodies
            .get(RigidBodyHandle::from_raw_parts(b.index, b.generation))
    }
}

impl Engine for Rapier<'_> {
    fn collider(&self, c: Key, slack: Slack) -> ColliderStatus {
        let h = ColliderHandle::from_raw_parts(c.index, c.generation);
        match self.colliders.get(h) {
            None => ColliderStatus::Missing,
            Some(co) if !co.is_enabled() => ColliderStatus::Disabled,
            Some(co) => ColliderStatus::Held(hold_of(co, self.bodies, self.params, slack)),
        }
    }

    fn bounds(&self, c: Key) -> Option<Aabb> {
        let co = self
            .colliders
            .get(ColliderHandle::from_raw_parts(c.index, c.generation))?;
        let aabb = co.compute_aabb();
        let margin = margin_of(co, self.params);
        let m = Vec3::splat(margin);
        Some(Aabb::new(just_stored(&aabb.mins), just_stored(&aabb.maxs)).grown(m))
    }

    /// A collider's shape lies in memory of its own, away from rapier's arena: asked for
    /// ahead of its box.
    fn prefetch_collider(&self, c: Key) {
        if let Some(co) = self
            .colliders
            .get(ColliderHandle::from_raw_parts(c.index, c.generation))
        {
            prefetch(co.shape());
        }
    }

    fn motion(&self, b: Key) -> Option<(Vec3, Vec3)> {
        let rb = self.rigid_body(b)?;
        Some((centre_of_mass(rb), dvec(rb.linvel())))
    }

    fn motions(&self, bodies: &[Key], out: &mut Vec<Option<(Vec3, Vec3)>>) {
        // Bodies lie hundreds of bytes apart in rapier's arena. The body `AHEAD` on is looked
        // up (its arena entry read) and the lines its centre and velocity lie in asked for,
        // so that they are on their way when it is read.
        const AHEAD: usize = 8;
        for (k, &b) in bodies.iter().enumerate() {
            if let Some(rb) = bodies.get(k + AHEAD).and_then(|&next| self.rigid_body(next)) {
                prefetch(rb.position());
                prefetch(rb.local_center_of_mass());
                prefetch(rb.linvel());
            }
            out.push(self.motion(b));
        }
    }

    /// rapier's own broad phase takes each box where it is, and sweeps it ahead only for a
    /// body with soft CCD, to where its velocity and forces take it over the step, by at
    /// most its soft-CCD distance: so does this one (by the move of its centre of mass).
    fn ahead(&self, b: Key, _d: Vec3) -> Vec3 {
        let Some(rb) = self.rigid_body(b) else {
            return Vec3::ZERO;
        };
        let soft = rb.soft_ccd_prediction() as Real;
        if soft <= 0.0 {
            return Vec3::ZERO;
        }
        let next = rb.predict_position_using_velocity_and_forces(self.params.dt);
        let to = dpoint(&(next * rb.local_center_of_mass()));
        (to - centre_of_mass(rb)).clamp_length_max(soft)
    }

    fn body(&self, b: Key) -> Option<BodyState> {
        let rb = self.rigid_body(b)?;
        Some(BodyState {
            centre: centre_of_mass(rb),
            velocity: dvec(rb.linvel()),
            sleeping: rb.is_sleeping(),
        })
    }
}

impl BroadPhase for KineticBroadPhase {
    /// rapier 0.27 calls it once with the user's changes at the start of a step, then once
    /// after each position update, the updates together one step long.
    fn update(
        &mut self,
        params: &IntegrationParameters,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        modified_colliders: &[ColliderHandle],
        removed_colliders: &[ColliderHandle],
        events: &mut Vec<BroadPhasePairEvent>,
    ) {
        self.params = Some(*params);
        let engine = Rapier {
            colliders,
            bodies,
            params,
        };
        let step = EngineStep {
            dt: params.dt as Real,
            substeps: params.num_solver_iterations.get() as Real,
        };
        self.modified.clear();
        self.modified
            .extend(modified_colliders.iter().map(|&h| key(h)));
        self.removed.clear();
        self.removed
            .extend(removed_colliders.iter().map(|&h| key(h)));
        self.core.update(
            step,
            &engine,
            &self.modified,
            &self.removed,
            &mut self.events,
        );
        let handle = |k: Key| ColliderHandle::from_raw_parts(k.index, k.generation);
        events.extend(self.events.drain(..).map(|e| match e {
            PairEvent::Add(a, b) => {
                BroadPhasePairEvent::AddPair(ColliderPair::new(handle(a), handle(b)))
            }
            PairEvent::Delete(a, b) => {
                BroadPhasePairEvent::DeletePair(ColliderPair::new(handle(a), handle(b)))
            }
        }));
    }
}

impl KineticBroadPhase {
    /// A broad phase that picks its structure from the first colliders it is given.
    pub fn new() -> KineticBroadPhase {
        KineticBroadPhase::default()
    }

    /// The same broad phase with its proxies in the structure the caller chose, the loose
    /// grid (`loose`) or the hierarchical grid, kept kinetic throughout.
    pub fn with_loose_grid(mut self, loose: bool) -> KineticBroadPhase {
        self.core = self.core.with_loose_grid(loose);
        self
    }

    /// The same broad phase with another slack: a moving body may stray `fraction` of its
    /// size (at least `min` times rapier's length unit) from its plan before it is
    /// re-planned. More slack, fewer re-plans and more pairs. Default 0.05 and 0.001.
    pub fn with_slack(mut self, fraction: RReal, min: RReal) -> KineticBroadPhase {
        self.core = self.core.with_slack(fraction as Real, min as Real);
        self
    }

    /// The same broad phase, auditing itself after every event of its structure (slow; for
    /// tests). The first failure is kept: see [`KineticBroadPhase::audit_error`].
    pub fn with_audit(mut self) -> KineticBroadPhase {
        self.core = self.core.with_audit();
        self
    }

    /// The first failure of the audit, if any.
    pub fn audit_error(&self) -> Option<&str> {
        self.core.audit_error()
    }

    /// The structure in use (its registry name), `"stepped"` while the broad phase steps, or
    /// `"none"` before the first collider.
    pub fn structure_name(&self) -> &'static str {
        self.core.structure_name()
    }

    /// Figures over the whole run.
    pub fn stats(&self) -> BroadPhaseStats {
        self.core.stats()
    }

    /// Figures over the last physics step.
    pub fn last_step(&self) -> StepStats {
        self.core.last_step()
    }

    /// The structure's own figures (e.g. the sweep's box pairs, the guards' watches).
    pub fn structure_counters(&self) -> Vec<(&'static str, f64)> {
        self.core.structure_counters()
    }

    /// Whether rapier has the pair of these two colliders by this broad phase.
    pub fn has_pair(&self, a: ColliderHandle, b: ColliderHandle) -> bool {
        self.core.has_pair(key(a), key(b))
    }

    /// The engine-agnostic core it runs on.
    pub fn core(&self) -> &BroadPhaseCore {
        &self.core
    }

    /// Recomputes the invariants from scratch ([`BroadPhaseCore::validate`]): the
    /// structure's, the pairs', every enabled collider held, every moving body within its
    /// slack of its plan.
    pub fn validate(&self, colliders: &ColliderSet, bodies: &RigidBodySet) -> Result<(), String> {
        let params = self.params.unwrap_or_default();
        let engine = Rapier {
            colliders,
            bodies,
            params: &params,
        };
        self.core
            .validate(&engine, colliders.iter().map(|(h, _)| key(h)))
    }
}
