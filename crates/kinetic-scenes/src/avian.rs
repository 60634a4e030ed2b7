//! The engine scenes ([`crate::engines`]) in avian3d (feature `avian`).

use crate::engines::{EngineScene, PieceShape};
use avian3d::prelude::*;
use bevy::prelude::*;

/// Spawns `scene`'s pieces into `world` (one entity each: a body with its collider) and sets
/// avian's gravity; returns the entities in the scene's order.
pub fn spawn(scene: &EngineScene, world: &mut World) -> Vec<Entity> {
    world.insert_resource(Gravity(Vec3::from(scene.gravity)));
    scene
        .pieces
        .iter()
        .map(|p| {
            let collider = match p.shape {
                PieceShape::Ball(r) => Collider::sphere(r),
                PieceShape::Cuboid([x, y, z]) => Collider::cuboid(2.0 * x, 2.0 * y, 2.0 * z),
            };
            let at = Transform::from_translation(Vec3::from(p.position));
            if p.fixed {
                return world.spawn((RigidBody::Static, collider, at)).id();
            }
            let body = if p.kinematic {
                RigidBody::Kinematic
            } else {
                RigidBody::Dynamic
            };
            let mut e = world.spawn((
                body,
                collider,
                at,
                ColliderDensity(p.density),
                LinearVelocity(Vec3::from(p.velocity)),
                AngularVelocity(Vec3::from(p.spin)),
            ));
            if !p.can_sleep {
                e.insert(SleepingDisabled);
            }
            if p.asleep {
                e.insert(Sleeping);
            }
            if let Some(r) = p.restitution {
                e.insert(Restitution::new(r).with_combine_rule(CoefficientCombine::Max));
            }
            if let Some(f) = p.friction {
                e.insert(Friction::new(f).with_combine_rule(CoefficientCombine::Min));
            }
            e.id()
        })
        .collect()
}
