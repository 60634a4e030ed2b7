//! The balls of a scene that the hard-sphere simulators take.

use crate::scene::{Scene, ShapeSpec};
use kinetic_core::{FlightPlan, Response, Walls, WorldKind};
use kinetic_spheres::{ElasticCells, PeriodicBox};

/// The walls and balls of a scene that the cell grid holds: elastic, free, walls, balls only,
/// no accelerations, and sizes for which the grid is small.
pub(crate) fn cell_balls(scene: &Scene) -> Option<(Walls, Vec<(f64, FlightPlan)>)> {
    let walls = scene.walls?;
    if scene.world != WorldKind::Free || scene.response != Response::Elastic {
        return None;
    }
    let mut balls = Vec::with_capacity(scene.objects.len());
    for o in &scene.objects {
        match o.shape {
            ShapeSpec::Ball { radius } if o.acceleration == glam::DVec3::ZERO => {
                balls.push((radius, o.plan()));
            }
            _ => return None,
        }
    }
    let radii: Vec<f64> = balls.iter().map(|b| b.0).collect();
    ElasticCells::supports(&walls, &radii).then_some((walls, balls))
}

/// The periodic box and balls of a periodic scene (its objects are elastic balls moving
/// linearly: the scene format checks that).
pub(crate) fn periodic_balls(scene: &Scene) -> Option<(PeriodicBox, Vec<(f64, FlightPlan)>)> {
    let cell = scene.periodic?;
    let balls = scene
        .objects
        .iter()
        .map(|o| match o.shape {
            ShapeSpec::Ball { radius } => Some((radius, o.plan())),
            _ => None,
        })
        .collect::<Option<Vec<_>>>()?;
    Some((cell, balls))
}
