//! A scene run through avian 0.8, for comparison (feature `avian`): every object is a dynamic
//! body with a sensor collider that follows its flight plan (no gravity; a constant linear
//! acceleration gives the plan's), so objects pass through each other as in the scene, in a
//! headless Bevy app stepping avian once an update at `dt`. Contacts are the touching pairs
//! of avian's contact graph after each step, logged at the time of the poses they were found
//! on: avian's narrow phase runs before its solver moves the bodies, so the graph after a
//! step holds the contacts of the poses the step started from (a game learns of a contact a
//! step after those poses; rapier's pipeline finds them on the poses it ends with).
//!
//! avian's continuous collision detection (`SweptCcd`, speculative contacts) acts on solid
//! contacts only: its sweeps skip sensors, and a sweep stops a body at its first time of
//! impact, which a body that passes through others would not do. The `ccd` runs add
//! `SweptCcd` against every kind of body, as a game would, to show what it changes here.

use crate::rapier_run::{EngineError, EngineOutput};
use crate::time_stepped::log_changes;
use avian3d::prelude::*;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use kinetic_collide::scene::{Scene, ShapeSpec};
use kinetic_core::Real;
use rustc_hash::{FxHashMap, FxHashSet};
use std::time::{Duration, Instant};

/// Runs `scene` in avian with steps of `dt` to the horizon, on avian's own broad phase or
/// (`kinetic`) the kinetic plugin, with `SweptCcd` on every body or not.
pub fn run_avian(
    scene: &Scene,
    dt: Real,
    kinetic: bool,
    ccd: bool,
) -> Result<EngineOutput, EngineError> {
    let start = Instant::now();
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin));
    let physics = PhysicsPlugins::default().build();
    if kinetic {
        app.add_plugins(
            physics
                .disable::<BvhBroadPhasePlugin>()
                .add(kinetic_avian::KineticBroadPhasePlugin::new()),
        );
    } else {
        app.add_plugins(physics);
    }
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        dt,
    )));
    app.insert_resource(Time::<Fixed>::from_seconds(dt));
    app.insert_resource(Gravity(Vec3::ZERO));
    app.finish();
    let mut object: FxHashMap<Entity, u32> = FxHashMap::default();
    for (index, o) in scene.objects.iter().enumerate() {
        let v32 = |v: glam::DVec3| Vec3::new(v.x as f32, v.y as f32, v.z as f32);
        let plan = o.centre_plan(scene.world);
        let collider = match &o.shape {
            ShapeSpec::Ball { radius } => Collider::sphere(*radius as f32),
            ShapeSpec::Cuboid { half_extents: h } => {
                Collider::cuboid(2.0 * h.x as f32, 2.0 * h.y as f32, 2.0 * h.z as f32)
            }
            ShapeSpec::ConvexHull { points } => {
                let points: Vec<Vec3> = points.iter().map(|&p| v32(p)).collect();
                Collider::convex_hull(&points).ok_or_else(|| EngineError {
                    index,
                    message: "avian cannot build this convex hull in f32".into(),
                })?
            }
        };
        let q = plan.orientation;
        let rotation = Quat::from_xyzw(q.x as f32, q.y as f32, q.z as f32, q.w as f32);
        let mut body = app.world_mut().spawn((
            RigidBody::Dynamic,
            collider,
            Sensor,
            // Sensors add no mass: the body gets one of its own, so that it moves.
            Mass(1.0),
            AngularInertia::new(Vec3::ONE),
            Transform::from_translation(v32(plan.position)).with_rotation(rotation),
            LinearVelocity(v32(plan.velocity)),
            AngularVelocity(v32(plan.angular_velocity)),
            ConstantLinearAcceleration(v32(plan.acceleration)),
            SleepingDisabled,
        ));
        if ccd {
            body.insert(SweptCcd {
                filter: CcdFilter::ALL,
                ..SweptCcd::default()
            });
        }
        object.insert(body.id(), index as u32);
    }
    let steps = (scene.horizon / dt).floor() as u64;
    let mut touching: FxHashSet<(u32, u32)> = FxHashSet::default();
    let mut now_touching: FxHashSet<(u32, u32)> = FxHashSet::default();
    let mut events = Vec::new();
    for k in 1..=steps {
        // One physics step an update; the first update may only start the clock.
        let due = k as f64 * dt - 0.5 * dt;
        for _ in 0..3 {
            app.update();
            let physics = app.world().resource::<Time<Physics>>();
            if physics.elapsed_secs_f64() >= due {
                break;
            }
        }
        now_touching.clear();
        let graph = app.world().resource::<ContactGraph>();
        now_touching.extend(graph.iter_active_touching().filter_map(|pair| {
            let a = *object.get(&pair.collider1)?;
            let b = *object.get(&pair.collider2)?;
            Some((a.min(b), a.max(b)))
        }));
        // avian's narrow phase runs before the step moves the bodies: the graph after step
        // k holds the contacts of the poses at its start.
        log_changes(&touching, &now_touching, (k - 1) as Real * dt, &mut events);
        std::mem::swap(&mut touching, &mut now_touching);
    }
    Ok(EngineOutput {
        events,
        steps,
        wall_seconds: start.elapsed().as_secs_f64(),
    })
}
