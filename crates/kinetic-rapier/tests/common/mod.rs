//! A rapier world stepped with a chosen broad phase, and the checks the tests share.

#![allow(dead_code)]

use kinetic_rapier::KineticBroadPhase;
use rapier3d::parry::query;
use rapier3d::prelude::*;
use std::collections::BTreeSet;

/// Wraps a broad phase and checks every event it sends against rapier's rules, at the
/// positions of the call that sent it.
pub struct Recorder<B: BroadPhase> {
    pub inner: B,
    /// Rule breaks seen: a pair deleted within the prediction distance, a pair out of order,
    /// an event naming a collider that is not there.
    pub faults: Vec<String>,
    pub adds: u64,
    pub deletes: u64,
}

impl<B: BroadPhase> Recorder<B> {
    pub fn new(inner: B) -> Self {
        Recorder {
            inner,
            faults: Vec::new(),
            adds: 0,
            deletes: 0,
        }
    }
}

impl<B: BroadPhase> BroadPhase for Recorder<B> {
    fn update(
        &mut self,
        params: &IntegrationParameters,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        modified: &[ColliderHandle],
        removed: &[ColliderHandle],
        events: &mut Vec<BroadPhasePairEvent>,
    ) {
        let start = events.len();
        self.inner
            .update(params, colliders, bodies, modified, removed, events);
        for e in &events[start..] {
            let (pair, delete) = match e {
                BroadPhasePairEvent::AddPair(p) => (p, false),
                BroadPhasePairEvent::DeletePair(p) => (p, true),
            };
            let (Some(c1), Some(c2)) =
                (colliders.get(pair.collider1), colliders.get(pair.collider2))
            else {
                self.faults
                    .push(format!("event for a missing collider: {pair:?}"));
                continue;
            };
            if pair.collider1.into_raw_parts().0 >= pair.collider2.into_raw_parts().0 {
                self.faults.push(format!("pair out of order: {pair:?}"));
            }
            if delete {
                self.deletes += 1;
                let d = query::distance(c1.position(), c1.shape(), c2.position(), c2.shape())
                    .unwrap_or(0.0);
                if d <= params.prediction_distance() {
                    self.faults
                        .push(format!("pair {pair:?} deleted at distance {d}"));
                }
            } else {
                self.adds += 1;
            }
        }
    }
}

/// A rapier world and its pipeline.
pub struct Sim<B: BroadPhase> {
    pub bodies: RigidBodySet,
    pub colliders: ColliderSet,
    pub islands: IslandManager,
    pub narrow: NarrowPhase,
    pub joints: ImpulseJointSet,
    pub multibody: MultibodyJointSet,
    pub ccd: CCDSolver,
    pub pipeline: PhysicsPipeline,
    pub params: IntegrationParameters,
    pub gravity: Vector<f32>,
    pub bp: Recorder<B>,
}

impl<B: BroadPhase> Sim<B> {
    pub fn new(bodies: RigidBodySet, colliders: ColliderSet, gravity: f32, bp: B) -> Self {
        Sim {
            bodies,
            colliders,
            islands: IslandManager::new(),
            narrow: NarrowPhase::new(),
            joints: ImpulseJointSet::new(),
            multibody: MultibodyJointSet::new(),
            ccd: CCDSolver::new(),
            pipeline: PhysicsPipeline::new(),
            params: IntegrationParameters::default(),
            gravity: vector![0.0, -gravity, 0.0],
            bp: Recorder::new(bp),
        }
    }

    pub fn step(&mut self) {
        self.pipeline.step(
            &self.gravity,
            &self.params,
            &mut self.islands,
            &mut self.bp,
            &mut self.narrow,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.joints,
            &mut self.multibody,
            &mut self.ccd,
            &(),
            &(),
        );
    }

    /// The pairs with an active contact in the narrow phase, by collider index.
    pub fn touching(&self) -> BTreeSet<(u32, u32)> {
        self.narrow
            .contact_pairs()
            .filter(|p| p.has_any_active_contact)
            .map(|p| key(p.collider1, p.collider2))
            .collect()
    }

    /// Whether the narrow phase holds the pair of these colliders.
    pub fn has_pair(&self, a: ColliderHandle, b: ColliderHandle) -> bool {
        self.narrow.contact_pair(a, b).is_some() || self.narrow.intersection_pair(a, b).is_some()
    }

    /// The deepest overlap among the narrow phase's contacts (0 if none).
    pub fn deepest(&self) -> f32 {
        self.narrow
            .contact_pairs()
            .flat_map(|p| p.manifolds.iter())
            .flat_map(|m| m.points.iter())
            .map(|c| -c.dist)
            .fold(0.0, f32::max)
    }

    /// Brute force: every pair of colliders that rapier would let touch (not on one body,
    /// not both fixed, groups that interact) and that is within the prediction distance.
    /// Returns those the narrow phase does not hold.
    pub fn missing_pairs(&self) -> Vec<(ColliderHandle, ColliderHandle, f32)> {
        let pd = self.params.prediction_distance();
        let all: Vec<(ColliderHandle, &Collider)> = self
            .colliders
            .iter()
            .filter(|(_, c)| c.is_enabled())
            .collect();
        let fixed = |c: &Collider| {
            c.parent()
                .is_none_or(|b| self.bodies.get(b).is_none_or(|rb| rb.is_fixed()))
        };
        let mut out = Vec::new();
        for (i, &(h1, c1)) in all.iter().enumerate() {
            for &(h2, c2) in &all[i + 1..] {
                if (c1.parent().is_some() && c1.parent() == c2.parent())
                    || (fixed(c1) && fixed(c2))
                    || !c1.collision_groups().test(c2.collision_groups())
                {
                    continue;
                }
                let d = query::distance(c1.position(), c1.shape(), c2.position(), c2.shape())
                    .unwrap_or(0.0);
                if d <= pd && !self.has_pair(h1, h2) {
                    out.push((h1, h2, d));
                }
            }
        }
        out
    }
}

impl Sim<KineticBroadPhase> {
    /// Every check of the kinetic broad phase after a step: its own audit, the brute force,
    /// the rules of the events it sent.
    pub fn check(&self, step: usize) {
        let bp = &self.bp.inner;
        if let Err(e) = bp.validate(&self.colliders, &self.bodies) {
            panic!("step {step}: validate: {e}");
        }
        if let Some(e) = bp.audit_error() {
            panic!("step {step}: audit: {e}");
        }
        let missing = self.missing_pairs();
        assert!(missing.is_empty(), "step {step}: missing pairs {missing:?}");
        assert!(
            self.bp.faults.is_empty(),
            "step {step}: {:?}",
            self.bp.faults
        );
    }
}

pub fn key(a: ColliderHandle, b: ColliderHandle) -> (u32, u32) {
    let (a, b) = (a.into_raw_parts().0, b.into_raw_parts().0);
    (a.min(b), a.max(b))
}

/// A ground slab, fixed, top face at y = 0.
pub fn ground(colliders: &mut ColliderSet, half: f32) -> ColliderHandle {
    colliders.insert(
        ColliderBuilder::cuboid(half, 0.1, half)
            .translation(vector![0.0, -0.1, 0.0])
            .build(),
    )
}
