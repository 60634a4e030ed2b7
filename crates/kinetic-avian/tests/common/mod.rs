//! A headless avian app with either broad phase, and the checks the tests share.

#![allow(dead_code)]

use avian3d::collision::collider::contact_query;
use avian3d::prelude::*;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use kinetic_avian::{KineticBroadPhase, KineticBroadPhasePlugin};
use std::collections::BTreeSet;
use std::time::Duration;

/// Which broad phase an app runs: avian's, the plugin as it comes, or the plugin held to a
/// kinetic structure (it then never steps).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Broad {
    Default,
    Kinetic,
    /// The kinetic plugin with its proxies in the loose grid (`true`) or the grid.
    LooseGrid(bool),
}

pub const HZ: f64 = 64.0;

/// A headless app stepping avian at 64 Hz, one physics step per update; the kinetic broad
/// phase audits itself after every event and every step.
pub fn app(broad: Broad) -> App {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin));
    let physics = PhysicsPlugins::default().build();
    match broad {
        Broad::Default => app.add_plugins(physics),
        Broad::Kinetic => app.add_plugins(
            physics
                .disable::<BvhBroadPhasePlugin>()
                .add(KineticBroadPhasePlugin::new().with_audit()),
        ),
        Broad::LooseGrid(loose) => app.add_plugins(
            physics.disable::<BvhBroadPhasePlugin>().add(
                KineticBroadPhasePlugin::new()
                    .with_loose_grid(loose)
                    .with_audit(),
            ),
        ),
    };
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        1.0 / HZ,
    )));
    app.insert_resource(Time::<Fixed>::from_hz(HZ));
    app.finish();
    app
}

/// One update, and the kinetic broad phase's audit.
pub fn step(app: &mut App) {
    app.update();
    if let Some(e) = audit(app) {
        panic!("audit: {e}");
    }
}

/// The order in which a test spawned an entity: the same in two apps built alike, where the
/// entities' indices may differ.
#[derive(Component, Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub struct Tag(pub u32);

pub fn spawn(app: &mut App, bundle: impl Bundle) -> Entity {
    let mut q = app.world_mut().query::<&Tag>();
    let n = q.iter(app.world()).count() as u32;
    app.world_mut().spawn((bundle, Tag(n))).id()
}

/// The tags of two entities, in order.
pub fn tags(app: &App, a: Entity, b: Entity) -> (u32, u32) {
    let tag = |e: Entity| app.world().get::<Tag>(e).map_or(u32::MAX, |t| t.0);
    (tag(a).min(tag(b)), tag(a).max(tag(b)))
}

pub fn ball(at: Vec3, radius: f32) -> impl Bundle {
    (
        RigidBody::Dynamic,
        Collider::sphere(radius),
        Transform::from_translation(at),
    )
}

pub fn cuboid(at: Vec3, size: Vec3) -> impl Bundle {
    (
        RigidBody::Dynamic,
        Collider::cuboid(size.x, size.y, size.z),
        Transform::from_translation(at),
    )
}

/// A ground 80 wide, its top at 0.
pub fn ground(app: &mut App) -> Entity {
    spawn(
        app,
        (
            RigidBody::Static,
            Collider::cuboid(80.0, 1.0, 80.0),
            Transform::from_xyz(0.0, -0.5, 0.0),
        ),
    )
}

/// A body's position, in f32 whatever avian's precision.
pub fn position(app: &App, e: Entity) -> Vec3 {
    let p = app.world().get::<Position>(e).expect("a body").0;
    Vec3::new(p.x as f32, p.y as f32, p.z as f32)
}

/// The kinetic broad phase's audit failure, if any.
pub fn audit(app: &App) -> Option<String> {
    app.world()
        .get_resource::<KineticBroadPhase>()
        .and_then(|k| k.audit_error().map(str::to_string))
}

pub fn kinetic(app: &App) -> &KineticBroadPhase {
    app.world().resource::<KineticBroadPhase>()
}

/// The touching pairs of the contact graph, by tag.
pub fn touching(app: &App) -> BTreeSet<(u32, u32)> {
    let graph = app.world().resource::<ContactGraph>();
    graph
        .iter_active_touching()
        .chain(graph.iter_sleeping_touching())
        .map(|p| tags(app, p.collider1, p.collider2))
        .collect()
}

/// One step, checked: every pair of colliders within `gap` of each other before it (not both
/// static, not on one body, on layers that interact, enabled) is in the contact graph after
/// its broad and narrow phases. Returns those that are not.
pub fn step_missing(app: &mut App, gap: f32) -> Vec<String> {
    if app.world().resource::<Time<Physics>>().elapsed_secs_f64() == 0.0 {
        // Before the first step the bodies' positions are not set.
        step(app);
        return Vec::new();
    }
    let near = near_pairs(app, gap);
    step(app);
    let graph = app.world().resource::<ContactGraph>();
    near.into_iter()
        .filter(|(a, b, _)| !graph.contains(*a, *b))
        .map(|(a, b, d)| format!("{a:?} and {b:?} at {d}"))
        .collect()
}

/// Pairs of colliders within `gap` of each other (not both static, not on one body, on layers
/// that interact, enabled).
pub fn near_pairs(app: &mut App, gap: f32) -> Vec<(Entity, Entity, f32)> {
    let mut q = app.world_mut().query_filtered::<(
        Entity,
        &Collider,
        &Position,
        &Rotation,
        Option<&ColliderOf>,
        Option<&CollisionLayers>,
    ), Without<ColliderDisabled>>();
    let world = app.world();
    let colliders: Vec<_> = q.iter(world).collect();
    let is_static = |of: Option<&ColliderOf>| {
        of.and_then(|of| world.get::<RigidBody>(of.body))
            .is_none_or(|rb| rb.is_static())
    };
    let mut near = Vec::new();
    for (i, a) in colliders.iter().enumerate() {
        for b in &colliders[i + 1..] {
            if is_static(a.4) && is_static(b.4) {
                continue;
            }
            if a.4.is_some() && a.4.map(|o| o.body) == b.4.map(|o| o.body) {
                continue;
            }
            let (la, lb) = (
                a.5.copied().unwrap_or_default(),
                b.5.copied().unwrap_or_default(),
            );
            if !la.interacts_with(lb) {
                continue;
            }
            let d =
                contact_query::distance(a.1, a.2.0, *a.3, b.1, b.2.0, *b.3).expect("a distance");
            if d <= gap {
                near.push((a.0, b.0, d));
            }
        }
    }
    near
}
