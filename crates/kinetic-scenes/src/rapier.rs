//! The engine scenes ([`crate::engines`]) in rapier (feature `rapier`).

use crate::engines::{self, EngineScene, PieceShape, hull_points, terrain_mesh};
use rapier3d::prelude::*;

/// A rapier scene: its bodies and colliders, and the gravity it runs under.
pub struct RapierScene {
    /// The bodies.
    pub bodies: RigidBodySet,
    /// The colliders.
    pub colliders: ColliderSet,
    /// Gravity.
    pub gravity: Vector<f32>,
}

impl From<EngineScene> for RapierScene {
    fn from(scene: EngineScene) -> RapierScene {
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        for p in scene.pieces {
            let mut co = match p.shape {
                PieceShape::Ball(r) => ColliderBuilder::ball(r),
                PieceShape::Cuboid([x, y, z]) => ColliderBuilder::cuboid(x, y, z),
                PieceShape::Hull(r) => {
                    let points: Vec<Point<f32>> =
                        hull_points(r).into_iter().map(Point::from).collect();
                    ColliderBuilder::convex_hull(&points).expect("an icosahedron's hull")
                }
                PieceShape::Terrain {
                    half,
                    cells,
                    height,
                } => {
                    let (vertices, triangles) = terrain_mesh(half, cells, height);
                    let vertices = vertices.into_iter().map(Point::from).collect();
                    ColliderBuilder::trimesh(vertices, triangles).expect("a grid's triangles")
                }
            }
            .density(p.density);
            if let Some(e) = p.restitution {
                co = co
                    .restitution(e)
                    .restitution_combine_rule(CoefficientCombineRule::Max);
            }
            if let Some(f) = p.friction {
                co = co
                    .friction(f)
                    .friction_combine_rule(CoefficientCombineRule::Min);
            }
            let at = Vector::from(p.position);
            if p.fixed {
                colliders.insert(co.translation(at).build());
                continue;
            }
            let builder = if p.kinematic {
                RigidBodyBuilder::kinematic_velocity_based()
            } else {
                RigidBodyBuilder::dynamic()
            };
            let h = bodies.insert(
                builder
                    .translation(at)
                    .linvel(Vector::from(p.velocity))
                    .angvel(Vector::from(p.spin))
                    .can_sleep(p.can_sleep)
                    .sleeping(p.asleep),
            );
            colliders.insert_with_parent(co, h, &mut bodies);
        }
        RapierScene {
            bodies,
            colliders,
            gravity: Vector::from(scene.gravity),
        }
    }
}

/// The rain ([`engines::rain`]) in rapier.
pub fn rain(n: usize, rocks: usize, seed: u64) -> RapierScene {
    engines::rain(n, rocks, seed).into()
}

/// The debris field ([`engines::debris`]) in rapier.
pub fn debris(n: usize, seed: u64) -> RapierScene {
    engines::debris(n, seed).into()
}

/// The standard scene of `kind` ([`engines::standard`]) in rapier.
pub fn standard(kind: &str, n: usize) -> Option<RapierScene> {
    engines::standard(kind, n).map(RapierScene::from)
}
