//! The benchmark family behind the default choice of structure: scenes that span the number
//! of objects, the spread of sizes and of speeds, the shapes, the density, the horizon, free
//! and plane worlds, with and without elastic response. The `choice` bench runs every
//! structure on each and the default's pick, and the tests check the pick on the small ones.

use crate::generators::{BallScene, FlightScene, ShapeMix};
use crate::hard_spheres::HardSpheres;
use glam::DVec3;
use kinetic_collide::scene::Scene;
use kinetic_collide::{Response, WorldKind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// One scene of the family.
#[derive(Clone, Debug)]
pub struct ChoiceCase {
    /// What kind of scene, e.g. `gas`, `sizes-1e4`, `bullets`.
    pub kind: &'static str,
    /// The number of objects asked for.
    pub n: usize,
    /// The scene.
    pub scene: Scene,
}

/// The kinds of scene in the family.
pub const KINDS: [&str; 16] = [
    "gas",
    "dense-gas",
    "sizes-1e2",
    "sizes-250",
    "sizes-1e3",
    "sizes-1e4",
    "bullets",
    "asteroids",
    "cuboids",
    "accelerating",
    "long-horizon",
    "at-rest",
    "hard-spheres",
    "mixture",
    "rolling",
    "marbles",
];

/// The scene of `kind` with about `n` objects, or None for an unknown kind.
pub fn choice_scene(kind: &str, n: usize, seed: u64) -> Option<Scene> {
    let gas = BallScene {
        horizon: 10.0,
        ..BallScene::gas(n, seed)
    };
    Some(match kind {
        // Equal balls flying through each other, about 2% of space filled.
        "gas" => gas.build(),
        // The same, about 15% filled.
        "dense-gas" => BallScene {
            side: 1.6 * (n as f64).cbrt(),
            ..gas
        }
        .build(),
        // Balls of radii spanning 1:100 to 1:10^4, log-uniform, similar fill.
        "sizes-1e2" => BallScene {
            r_min: 0.05,
            r_max: 5.0,
            side: 6.0 * (n as f64).cbrt(),
            ..gas
        }
        .build(),
        // Spreads on either side of the loose grid's bound (500x).
        "sizes-250" => BallScene {
            r_min: 0.02,
            r_max: 5.0,
            side: 6.0 * (n as f64).cbrt(),
            ..gas
        }
        .build(),
        "sizes-1e3" => BallScene {
            r_min: 0.005,
            r_max: 5.0,
            side: 6.0 * (n as f64).cbrt(),
            ..gas
        }
        .build(),
        "sizes-1e4" => BallScene {
            r_min: 0.005,
            r_max: 50.0,
            side: 12.0 * (n as f64).cbrt(),
            ..gas
        }
        .build(),
        // A gas with one ball in a hundred a hundred times faster.
        "bullets" => {
            let mut scene = gas.build();
            let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0xb0b);
            for o in scene.objects.iter_mut().step_by(100) {
                let d = DVec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                o.velocity = d.normalize_or(DVec3::X) * 100.0;
            }
            scene
        }
        // Spinning balls, boxes and hulls of sizes spanning 1:60.
        "asteroids" => FlightScene::asteroids(n, 60.0, seed).build(),
        "cuboids" => FlightScene {
            shapes: ShapeMix::Cuboids,
            spin: 0.0,
            ..FlightScene::asteroids(n, 60.0, seed)
        }
        .build(),
        // Balls under constant accelerations of random directions.
        "accelerating" => BallScene {
            acceleration: 0.5,
            ..gas
        }
        .build(),
        // The gas over ten times the horizon.
        "long-horizon" => BallScene {
            horizon: 100.0,
            ..gas
        }
        .build(),
        // Balls at rest, a few touching.
        "at-rest" => BallScene { speed: 0.0, ..gas }.build(),
        // Elastic equal spheres in walls at packing 0.26, about 10 collisions per sphere.
        "hard-spheres" => HardSpheres {
            collisions: 10.0 * n as f64,
            seed,
            ..HardSpheres::gas(n)
        }
        .build()
        .ok()?,
        // Elastic spheres in walls, diameters 1:4 with equal volumes.
        "mixture" => HardSpheres {
            collisions: 10.0 * n as f64,
            seed,
            ..HardSpheres::mixture(n, 0.25)
        }
        .build()
        .ok()?,
        // Balls of radii 1:1000 rolling through each other on a plane.
        "rolling" => BallScene::rolling(n, 10.0, seed).build(),
        // Marbles of radii 1:50 bouncing elastically on a table in its rim.
        "marbles" => BallScene {
            n,
            side: 30.0 * (n as f64 / 300.0).sqrt(),
            seed,
            ..BallScene::marbles_on_a_table()
        }
        .build(),
        _ => return None,
    })
}

/// Every kind at each of `sizes`, seeded by `seed`.
pub fn choice_family(sizes: &[usize], seed: u64) -> Vec<ChoiceCase> {
    let mut cases = Vec::new();
    for &n in sizes {
        for kind in KINDS {
            if let Some(scene) = choice_scene(kind, n, seed) {
                cases.push(ChoiceCase { kind, n, scene });
            }
        }
    }
    cases
}

/// Whether a scene is in a plane world (for tables).
pub fn world_name(scene: &Scene) -> &'static str {
    match scene.world {
        WorldKind::Free => "free",
        WorldKind::Plane => "plane",
    }
}

/// The response's name (for tables).
pub fn response_name(scene: &Scene) -> &'static str {
    match scene.response {
        Response::None => "none",
        Response::Elastic => "elastic",
    }
}
