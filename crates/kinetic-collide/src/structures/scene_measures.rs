//! What the cost model reads of a scene before it runs: sizes, how far the objects travel
//! against their sizes, how many box ends they pass, how many contacts they make.

use crate::scene::{Scene, ShapeSpec};
use kinetic_core::WorldKind;

/// The outer radii of a scene's objects.
pub(crate) fn radii(scene: &Scene) -> impl Iterator<Item = f64> + '_ {
    scene
        .objects
        .iter()
        .map(|o| crate::scene::outer_radius(&o.shape))
}

/// How many times the objects cross their own size over the horizon, summed: each object's
/// travel (speed times horizon, plus half its acceleration times the horizon squared) over
/// its diameter, at most [`super::registry::FLIGHT_PARTS`] (the grids' least flight). What a box structure
/// pays for in events, where the brute force pays for every pair once.
pub(crate) fn crossings(scene: &Scene) -> f64 {
    let h = scene.horizon;
    scene
        .objects
        .iter()
        .map(|o| {
            let travel = o.velocity.length() * h + 0.5 * o.acceleration.length() * h * h;
            let size = 2.0 * crate::scene::outer_radius(&o.shape);
            if size > 0.0 && travel.is_finite() {
                (travel / size).min(super::registry::FLIGHT_PARTS)
            } else {
                super::registry::FLIGHT_PARTS
            }
        })
        .sum()
}

/// About how many box ends the objects pass along the axes over the horizon (three in a free
/// world, two on a plane): each object's travel along an axis times the density of box ends
/// there, `2 n` over the extent of the objects' starts grown by their mean diameter. What the
/// sweep pays for in swaps of its sorted lists, whatever the objects' sizes (measured 1.1 to
/// 1.5 swaps a pass on the choice family). Zero where it cannot be told (starts and sizes
/// that leave no extent): the cost model then takes a box structure, which never costs
/// quadratic memory.
pub(crate) fn passes(scene: &Scene) -> f64 {
    let n = scene.objects.len();
    if n == 0 {
        return 0.0;
    }
    let h = scene.horizon;
    let mean = radii(scene).sum::<f64>() / n as f64;
    let (lo, hi) = starts_box(scene);
    let extent = (hi - lo) + glam::DVec3::splat(2.0 * mean);
    let axes = if scene.world == WorldKind::Plane {
        2
    } else {
        3
    };
    let density = |k: usize| 2.0 * n as f64 / extent[k];
    let p: f64 = scene
        .objects
        .iter()
        .map(|o| {
            let travel = o.velocity * h + 0.5 * o.acceleration * h * h;
            (0..axes).map(|k| travel[k].abs() * density(k)).sum::<f64>()
        })
        .sum();
    if p.is_finite() { p } else { 0.0 }
}

/// The box of the objects' starts (their positions at t = 0).
fn starts_box(scene: &Scene) -> (glam::DVec3, glam::DVec3) {
    scene.objects.iter().fold(
        (glam::DVec3::INFINITY, glam::DVec3::NEG_INFINITY),
        |(lo, hi), o| (lo.min(o.position), hi.max(o.position)),
    )
}

/// About how many contacts the objects make over the horizon: each object's travel through
/// the others as if they stood still, `pi (r_i + r_j)^2` of space swept per unit of travel for
/// each other object `j` (in a plane world the discs' `2 (r_i + r_j)` of area), over the
/// space they share: the walls' box, or else the box of the objects' starts grown by the
/// largest outer radius. For n equal balls filling a share phi of space this is 6 phi
/// contacts per [`crossings`]; what a box structure pays for in new candidate pairs where
/// objects crowd.
pub(crate) fn contacts(scene: &Scene) -> f64 {
    let h = scene.horizon;
    let radius = |o: &crate::scene::SceneObject| crate::scene::outer_radius(&o.shape);
    let (lo, hi) = match scene.walls {
        Some(w) => (w.min, w.max),
        None => {
            let r = radii(scene).fold(0.0, f64::max);
            let (lo, hi) = starts_box(scene);
            (lo - glam::DVec3::splat(r), hi + glam::DVec3::splat(r))
        }
    };
    let d = hi - lo;
    let plane = scene.world == WorldKind::Plane;
    let space = if plane { d.x * d.y } else { d.x * d.y * d.z };
    let n = scene.objects.len() as f64;
    let s1: f64 = scene.objects.iter().map(radius).sum();
    let s2: f64 = scene.objects.iter().map(|o| radius(o).powi(2)).sum();
    let swept: f64 = scene
        .objects
        .iter()
        .map(|o| {
            let travel = o.velocity.length() * h + 0.5 * o.acceleration.length() * h * h;
            let r = radius(o);
            let reach = if plane {
                2.0 * (n * r + s1)
            } else {
                std::f64::consts::PI * (n * r * r + 2.0 * r * s1 + s2)
            };
            travel * reach
        })
        .sum();
    let c = swept / space;
    if c.is_finite() && c > 0.0 { c } else { 0.0 }
}

/// Whether some objects are cuboids or hulls, or accelerate: pairs whose certificates cost
/// the brute force about twice a linear ball pair's.
pub(crate) fn heavy_pairs(scene: &Scene) -> bool {
    scene
        .objects
        .iter()
        .any(|o| !matches!(o.shape, ShapeSpec::Ball { .. }) || o.acceleration != glam::DVec3::ZERO)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::SceneObject;
    use kinetic_core::{Response, Vec3 as DVec3};

    #[test]
    fn the_sweep_pays_for_box_ends_passed_whatever_the_sizes() {
        // Ten balls of diameter 1 a unit apart along x: their starts and a mean diameter span 10,
        // so 2 ends a unit. One crosses 3 units along x in the horizon: 6 ends passed.
        let line = |radius: f64| Scene {
            world: WorldKind::Free,
            horizon: 1.0,
            response: Response::None,
            walls: None,
            periodic: None,
            objects: (0..10)
                .map(|i| {
                    let v = if i == 0 { 3.0 } else { 0.0 };
                    SceneObject::ball(
                        radius,
                        DVec3::new(i as f64, 0.0, 0.0),
                        DVec3::new(v, 0.0, 0.0),
                    )
                })
                .collect(),
        };
        let scene = line(0.5);
        assert_eq!(passes(&scene), 3.0 * 20.0 / 10.0);
        // Balls a thousandth the size cross their own size hundreds of times more often (to a cap
        // of 1000 for each), but pass about as many box ends.
        let tiny = line(0.0005);
        assert!(crossings(&tiny) > 300.0 * crossings(&scene));
        assert!(passes(&tiny) < 1.2 * passes(&scene));
    }
}
