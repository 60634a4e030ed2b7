//! The balls of a scene that the hard-sphere simulators take.

use crate::scene::{Scene, ShapeSpec};
use kinetic_core::{FlightPlan, Response, Walls, WorldKind};
use kinetic_spheres::{ElasticCells, PeriodicBox};

/// The walls and balls of a scene that the cell grid holds: elastic balls in walls (see
/// [`wall_balls`]) of sizes for which the grid is small.
pub(crate) fn cell_balls(scene: &Scene) -> Option<(Walls, Vec<(f64, FlightPlan)>)> {
    let (walls, balls) = wall_balls(scene)?;
    let radii: Vec<f64> = balls.iter().map(|b| b.0).collect();
    ElasticCells::supports(&walls, &radii).then_some((walls, balls))
}

/// The largest radius the neighbour lists take in walls, relative to the smallest: the cell
/// grid groups sizes within this factor on one level of cells, so below it the two hold the
/// balls alike and the lists' cheaper events decide.
pub(crate) const LISTED_SPREAD: f64 = 2.0;

/// The walls and balls of a scene that the neighbour lists hold: elastic balls in walls (see
/// [`wall_balls`]), the largest at most [`LISTED_SPREAD`] times the smallest.
pub(crate) fn listed_balls(scene: &Scene) -> Option<(Walls, Vec<(f64, FlightPlan)>)> {
    let (walls, balls) = wall_balls(scene)?;
    let (lo, hi) = balls.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), b| {
        (lo.min(b.0), hi.max(b.0))
    });
    (hi <= LISTED_SPREAD * lo).then_some((walls, balls))
}

/// The walls and balls of an elastic scene of balls moving linearly inside walls in a free
/// world (at least one ball).
fn wall_balls(scene: &Scene) -> Option<(Walls, Vec<(f64, FlightPlan)>)> {
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
    (!balls.is_empty()).then_some((walls, balls))
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
