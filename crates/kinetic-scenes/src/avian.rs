//! The engine scenes ([`crate::engines`]) in avian3d (feature `avian`).

use crate::engines::{EngineScene, PieceShape, hull_points, terrain_mesh};
use avian3d::math::RVector;
use avian3d::prelude::*;
use bevy::prelude::*;

/// A point of a shape in avian's precision (f32, or f64 with `parry-f64`).
fn point([x, y, z]: [f32; 3]) -> RVector {
    RVector::new(x as _, y as _, z as _)
}

/// Spawns `scene`'s pieces into `world` (one entity each: a body with its collider) and sets
/// avian's gravity; returns the entities in the scene's order. Pieces that start asleep are
/// spawned awake: avian wakes a body spawned `Sleeping` on its first step, before its islands
/// are made; [`put_to_sleep`] puts them to sleep once a step has made them.
pub fn spawn(scene: &EngineScene, world: &mut World) -> Vec<Entity> {
    world.insert_resource(Gravity(Vec3::from(scene.gravity)));
    scene
        .pieces
        .iter()
        .map(|p| {
            let collider = match p.shape {
                PieceShape::Ball(r) => Collider::sphere(r),
                PieceShape::Cuboid([x, y, z]) => Collider::cuboid(2.0 * x, 2.0 * y, 2.0 * z),
                PieceShape::Hull(r) => {
                    let points: Vec<RVector> = hull_points(r).into_iter().map(point).collect();
                    Collider::convex_hull(&points).expect("an icosahedron's hull")
                }
                PieceShape::Terrain {
                    half,
                    cells,
                    height,
                } => {
                    let (vertices, triangles) = terrain_mesh(half, cells, height);
                    Collider::trimesh(vertices.into_iter().map(point).collect(), triangles)
                }
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

/// Puts the scene's pieces that start asleep to sleep as avian keeps bodies asleep: each one's
/// island, once a physics step has grouped the bodies into islands (`SleepBody`). `entities`
/// are [`spawn`]'s.
pub fn put_to_sleep(scene: &EngineScene, world: &mut World, entities: &[Entity]) {
    use avian3d::dynamics::solver::islands::SleepBody;
    for (p, &e) in scene.pieces.iter().zip(entities) {
        if p.asleep && !p.fixed && !p.kinematic && !world.entity(e).contains::<Sleeping>() {
            // A body without an island yet (none is made before the first step) stays awake.
            let _ = SleepBody(e).apply(world);
        }
    }
}
