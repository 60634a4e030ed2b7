//! The space of scenes the default structure is measured on: a seeded generator whose draws
//! vary along the axes in which users' scenes differ, rather than a list of scenes to tune
//! on.
//!
//! Axes, each drawn independently:
//! - the world: free flight (half the draws), balls rolling on a plane, elastic balls inside
//!   walls, elastic spheres in a periodic box;
//! - the number of objects, log-uniform from 10 to the largest asked for (1e6 in the space);
//! - the spread of sizes, log-uniform from 1 to 1e5, and in a quarter of the draws a few
//!   giants among dust (dust spread at most 10, one to three giants at the full spread);
//! - the shapes in free flight: balls, cuboids, convex hulls or all three, spinning or not;
//! - the density: the share of space the objects fill, log-uniform from 0.1% to 20% (elastic
//!   systems: packings 1% to 45%);
//! - the speeds: drifting (the horizon a hundredth of a box crossing) to a box crossing and a
//!   half, and in a third of the draws bullets: up to 5% of the objects 30 to 300 times as
//!   fast (elastic systems: 0.1 to 20 collisions per sphere, at the thermal speeds of kT = 1).

use crate::generators::{BallScene, FlightScene, ShapeMix, random_unit};
use crate::hard_spheres::HardSpheres;
use glam::DVec3;
use kinetic_collide::scene::{Scene, SceneObject};
use kinetic_collide::{Response, WorldKind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// The most objects a draw of the space may have.
pub const MAX_OBJECTS: usize = 1_000_000;

/// One draw of the space.
#[derive(Clone, Debug)]
pub struct Draw {
    /// The seed that drew it.
    pub seed: u64,
    /// What was drawn, for tables: world, objects, spread, shapes, fill, bullets, travel.
    pub label: String,
    /// The scene.
    pub scene: Scene,
}

/// Log-uniform in `[lo, hi]`.
fn log_uniform(rng: &mut ChaCha8Rng, lo: f64, hi: f64) -> f64 {
    if hi > lo {
        rng.random_range(lo.ln()..hi.ln()).exp()
    } else {
        lo
    }
}

/// The draw of `seed`, with at most `max_objects` objects (at least 10, at most
/// [`MAX_OBJECTS`]).
pub fn draw(seed: u64, max_objects: usize) -> Draw {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5ce9e_5ace);
    let top = max_objects.clamp(10, MAX_OBJECTS) as f64;
    let n = log_uniform(&mut rng, 10.0, top).round() as usize;
    let world = rng.random_range(0..20u32);
    let travel = log_uniform(&mut rng, 0.01, 1.5);
    let bullets = if rng.random_bool(1.0 / 3.0) {
        log_uniform(&mut rng, 0.002, 0.05)
    } else {
        0.0
    };
    let (mut scene, label) = match world {
        // Elastic systems: the hard-sphere generator places them apart.
        0..=3 => {
            let periodic = world == 3;
            let packing = log_uniform(&mut rng, 0.01, 0.45);
            let ratio = if rng.random_bool(0.5) {
                1.0
            } else {
                log_uniform(&mut rng, 0.05, 1.0)
            };
            // The horizon: 0.1 to 20 collisions per sphere.
            let per_sphere = log_uniform(&mut rng, 0.1, 20.0);
            let spheres = HardSpheres {
                n,
                ratio,
                packing,
                collisions: per_sphere * n as f64,
                seed,
                periodic,
            };
            let Ok(scene) = spheres.build() else {
                // Too dense to start: the draw of the next seed.
                return draw(seed.wrapping_add(1 << 32), max_objects);
            };
            let label = format!(
                "{} n={n} ratio={ratio:.3} packing={packing:.3} collisions/sphere={per_sphere:.2}",
                if periodic { "periodic" } else { "walls" }
            );
            (scene, label)
        }
        // Balls rolling through each other on a plane.
        4..=7 => {
            let spread = log_uniform(&mut rng, 1.0, 1e4);
            let fill = log_uniform(&mut rng, 0.001, 0.2);
            let (r_min, r_max) = (0.5, 0.5 * spread);
            let mean_area = if spread > 1.0 {
                std::f64::consts::PI * (r_max * r_max - r_min * r_min) / (2.0 * spread.ln())
            } else {
                std::f64::consts::PI * r_min * r_min
            };
            let side = (n as f64 * mean_area / fill).sqrt().max(4.0 * r_max);
            let scene = BallScene {
                n,
                r_min,
                r_max,
                side,
                speed: 1.0,
                acceleration: 0.0,
                world: WorldKind::Plane,
                response: Response::None,
                walls: false,
                allow_overlap: true,
                horizon: 1.0,
                seed,
            }
            .build();
            let label = format!("plane n={n} spread={spread:.0} fill={fill:.4}");
            (scene, label)
        }
        // Free flight, through each other.
        _ => {
            let giants = rng.random_bool(0.25);
            let spread = log_uniform(&mut rng, 1.0, 1e5);
            let fill = log_uniform(&mut rng, 0.001, 0.2);
            let shapes = match rng.random_range(0..4u32) {
                0 | 1 => ShapeMix::Balls,
                2 => ShapeMix::Cuboids,
                _ => [ShapeMix::Hulls, ShapeMix::Mixed][rng.random_range(0..2usize)],
            };
            let spin = if rng.random_bool(0.5) { 1.0 } else { 0.0 };
            let dust = if giants { spread.min(10.0) } else { spread };
            let mut scene = FlightScene {
                n,
                r_min: 0.5,
                sigma: dust,
                shapes,
                speed: 1.0,
                spin,
                acceleration: 0.0,
                fill,
                horizon: 1.0,
                seed,
            }
            .build();
            let mut label =
                format!("free n={n} spread={spread:.0} {shapes:?} fill={fill:.4} spin={spin}");
            if giants {
                let count = rng.random_range(1..=3usize);
                let side = box_side(&scene);
                for k in 0..count {
                    let r = 0.5 * spread / (k as f64 + 1.0);
                    let p = DVec3::new(
                        rng.random_range(0.0..side),
                        rng.random_range(0.0..side),
                        rng.random_range(0.0..side),
                    );
                    let v = random_unit(&mut rng) * rng.random_range(0.0..0.1);
                    scene.objects.push(SceneObject::ball(r, p, v));
                }
                label.push_str(&format!(" giants={count}"));
            }
            (scene, label)
        }
    };
    if scene.response == Response::Elastic {
        return Draw { seed, label, scene };
    }
    // Bullets: a share of the objects much faster than the rest.
    if bullets > 0.0 {
        let every = (1.0 / bullets).round().max(1.0) as usize;
        for o in scene.objects.iter_mut().step_by(every) {
            let speed = o.velocity.length().max(0.5) * rng.random_range(30.0..300.0);
            let mut d = random_unit(&mut rng);
            if scene.world == WorldKind::Plane {
                d.z = 0.0;
            }
            o.velocity = d.normalize_or(DVec3::X) * speed;
        }
    }
    // The horizon: `travel` box crossings at the typical speed.
    let speeds: f64 = scene.objects.iter().map(|o| o.velocity.length()).sum();
    let typical = (speeds / scene.objects.len().max(1) as f64).max(1e-9);
    scene.horizon = travel * box_side(&scene) / typical;
    let label = format!(
        "{label} bullets={bullets:.3} travel={travel:.3} objects={}",
        scene.objects.len()
    );
    Draw { seed, label, scene }
}

/// The side of the box the objects start in (the largest coordinate's span).
fn box_side(scene: &Scene) -> f64 {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for o in &scene.objects {
        lo = lo.min(o.position);
        hi = hi.max(o.position);
    }
    let span = hi - lo;
    span.x.max(span.y).max(span.z).max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use kinetic_collide::Structure;

    #[test]
    fn draws_are_seeded_and_cover_the_axes() {
        let draws: Vec<Draw> = (1..=120).map(|s| draw(s, 300)).collect();
        let again = draw(7, 300);
        assert_eq!(again.label, draws[6].label);
        assert_eq!(again.scene.to_json(), draws[6].scene.to_json());
        let mut worlds = [0usize; 4];
        for d in &draws {
            let s = &d.scene;
            assert!((10..=303).contains(&s.objects.len()), "{}", d.label);
            assert!(s.horizon.is_finite() && s.horizon > 0.0, "{}", d.label);
            // Every draw reads back and runs on the structures the registry offers.
            Scene::from_json(&s.to_json()).unwrap_or_else(|e| panic!("{}: {e}", d.label));
            assert!(Structure::ALL.iter().any(|x| x.applies_to(s)));
            let k = if s.periodic.is_some() {
                3
            } else if s.response == Response::Elastic {
                2
            } else if s.world == WorldKind::Plane {
                1
            } else {
                0
            };
            worlds[k] += 1;
        }
        assert!(worlds.iter().all(|&w| w > 0), "{worlds:?}");
        let spreads: Vec<f64> = draws.iter().map(|d| d.scene.size_ratio()).collect();
        assert!(spreads.iter().any(|&s| s > 1e3), "{spreads:?}");
        assert!(spreads.iter().any(|&s| s < 3.0));
        assert!(draws.iter().any(|d| d.label.contains("giants")));
        assert!(draws.iter().any(|d| d.label.contains("Cuboids")));
        assert!(draws.iter().any(|d| !d.label.contains("bullets=0.000")));
    }
}
