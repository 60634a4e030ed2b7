//! A scene run through rapier 0.27's own pipeline, for comparison: every object is a dynamic
//! body that follows its flight plan (no gravity; a constant force gives the plan's
//! acceleration) with a sensor collider, so objects pass through each other as in the scene.
//! Contacts are the narrow phase's intersecting pairs after each step. With CCD on, rapier
//! also reports a sensor pair that met and parted within one step (a "pseudo-intersection"
//! found by its time-of-impact sweep) as a started and a stopped collision event; such a
//! contact is logged as beginning and ending at the end of that step. (rapier's CCD ignores
//! such pairs between non-sensor colliders whose contacts are not solved: see its
//! `ccd_solver.rs`, "For now we just ignore this special case".)

use crate::time_stepped::log_changes;
use kinetic_collide::scene::{Scene, ShapeSpec};
use kinetic_core::{ContactEvent, ContactKind, ObjectId, Real};
use kinetic_rapier::KineticBroadPhase;
use rapier3d::prelude::*;
use rustc_hash::FxHashSet;
use std::sync::Mutex;
use std::time::Instant;

/// Which broad phase rapier runs with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Broad {
    /// rapier's default (its BVH).
    Default,
    /// This workspace's kinetic broad phase.
    Kinetic,
}

/// What an engine's run found (rapier's here, avian's in `avian_run`).
#[derive(Clone, Debug)]
pub struct EngineOutput {
    /// Contact begins and ends at step times, in log order.
    pub events: Vec<ContactEvent>,
    /// Steps taken.
    pub steps: u64,
    /// Wall-clock seconds (building the world and stepping).
    pub wall_seconds: f64,
}

/// Why the engine could not take the scene.
#[derive(Debug, thiserror::Error)]
#[error("objects[{index}]: {message}")]
pub struct EngineError {
    /// The object at fault.
    pub index: usize,
    /// What the engine refused.
    pub message: String,
}

/// Runs `scene` in rapier with steps of `dt` to the horizon.
pub fn run_rapier(
    scene: &Scene,
    dt: Real,
    broad: Broad,
    ccd: bool,
) -> Result<EngineOutput, EngineError> {
    let start = Instant::now();
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    for (index, o) in scene.objects.iter().enumerate() {
        let v32 = |v: glam::DVec3| vector![v.x as f32, v.y as f32, v.z as f32];
        let plan = o.centre_plan(scene.world);
        let (position, velocity, acceleration) = (plan.position, plan.velocity, plan.acceleration);
        let q = plan.orientation;
        let rotation = rapier3d::na::UnitQuaternion::from_quaternion(
            rapier3d::na::Quaternion::new(q.w as f32, q.x as f32, q.y as f32, q.z as f32),
        );
        let body = RigidBodyBuilder::dynamic()
            .position(Isometry::from_parts(
                Translation::from(v32(position)),
                rotation,
            ))
            .linvel(v32(velocity))
            .angvel(v32(plan.angular_velocity))
            .can_sleep(false)
            .ccd_enabled(ccd)
            .build();
        let handle = bodies.insert(body);
        let builder = match &o.shape {
            ShapeSpec::Ball { radius } => ColliderBuilder::ball(*radius as f32),
            ShapeSpec::Cuboid { half_extents: h } => {
                ColliderBuilder::cuboid(h.x as f32, h.y as f32, h.z as f32)
            }
            ShapeSpec::ConvexHull { points } => {
                let pts: Vec<Point<f32>> = points
                    .iter()
                    .map(|p| point![p.x as f32, p.y as f32, p.z as f32])
                    .collect();
                ColliderBuilder::convex_hull(&pts).ok_or_else(|| EngineError {
                    index,
                    message: "rapier cannot build this convex hull in f32".into(),
                })?
            }
        };
        // Sensors: intersections are found for every pair, nothing pushes back.
        let collider = builder
            .sensor(true)
            .active_collision_types(ActiveCollisionTypes::all())
            .active_events(ActiveEvents::COLLISION_EVENTS)
            .build();
        colliders.insert_with_parent(collider, handle, &mut bodies);
        if acceleration != glam::DVec3::ZERO {
            let body = &mut bodies[handle];
            let force = v32(acceleration) * body.mass();
            body.add_force(force, true);
        }
    }
    let mut islands = IslandManager::new();
    let mut narrow = NarrowPhase::new();
    let mut joints = ImpulseJointSet::new();
    let mut multibody = MultibodyJointSet::new();
    let mut ccd_solver = CCDSolver::new();
    let mut pipeline = PhysicsPipeline::new();
    let params = IntegrationParameters {
        dt: dt as f32,
        ..IntegrationParameters::default()
    };
    let mut bp: Box<dyn BroadPhase> = match broad {
        Broad::Default => Box::new(DefaultBroadPhase::new()),
        Broad::Kinetic => Box::new(KineticBroadPhase::new()),
    };
    let gravity = vector![0.0, 0.0, 0.0];
    let steps = (scene.horizon / dt).floor() as u64;
    let mut touching: FxHashSet<(u32, u32)> = FxHashSet::default();
    let mut now_touching: FxHashSet<(u32, u32)> = FxHashSet::default();
    let mut events = Vec::new();
    let collector = Collector::default();
    // Colliders were inserted in object order into an empty set: slot i is object i.
    let object = |h: ColliderHandle| h.into_raw_parts().0;
    for k in 1..=steps {
        pipeline.step(
            &gravity,
            &params,
            &mut islands,
            bp.as_mut(),
            &mut narrow,
            &mut bodies,
            &mut colliders,
            &mut joints,
            &mut multibody,
            &mut ccd_solver,
            &(),
            &collector,
        );
        let pair = |h1, h2| {
            let (a, b) = (object(h1), object(h2));
            (a.min(b), a.max(b))
        };
        now_touching.clear();
        now_touching.extend(
            narrow
                .intersection_pairs()
                .filter(|p| p.2)
                .map(|(h1, h2, _)| pair(h1, h2)),
        );
        let t = k as Real * dt;
        // Pairs CCD saw meet and part within the step: a begin and an end at its end.
        let mut passed: Vec<(u32, u32)> = collector
            .take()
            .into_iter()
            .map(|(h1, h2)| pair(h1, h2))
            .filter(|p| !now_touching.contains(p) && !touching.contains(p))
            .collect();
        passed.sort_unstable();
        passed.dedup();
        for &(a, b) in &passed {
            for kind in [ContactKind::Begin, ContactKind::End] {
                events.push(ContactEvent {
                    time: t,
                    a: ObjectId(a),
                    b: ObjectId(b),
                    kind,
                });
            }
        }
        log_changes(&touching, &now_touching, t, &mut events);
        std::mem::swap(&mut touching, &mut now_touching);
    }
    Ok(EngineOutput {
        events,
        steps,
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}

/// Collects the collider pairs of the collision events rapier sends during a step that start
/// a contact (the narrow phase's own changes are read from its pairs; this catches CCD's
/// pseudo-intersections, which never show there).
#[derive(Default)]
struct Collector(Mutex<Vec<(ColliderHandle, ColliderHandle)>>);

impl Collector {
    fn take(&self) -> Vec<(ColliderHandle, ColliderHandle)> {
        self.0
            .lock()
            .map(|mut v| std::mem::take(&mut *v))
            .unwrap_or_default()
    }
}

impl EventHandler for Collector {
    fn handle_collision_event(
        &self,
        _bodies: &RigidBodySet,
        _colliders: &ColliderSet,
        event: CollisionEvent,
        _contact_pair: Option<&ContactPair>,
    ) {
        if let CollisionEvent::Started(h1, h2, _) = event
            && let Ok(mut v) = self.0.lock()
        {
            v.push((h1, h2));
        }
    }

    fn handle_contact_force_event(
        &self,
        _dt: f32,
        _bodies: &RigidBodySet,
        _colliders: &ColliderSet,
        _contact_pair: &ContactPair,
        _total_force_magnitude: f32,
    ) {
    }
}
