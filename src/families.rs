//! Scene families for comparing methods: defined once and shared by the `compare` command,
//! the benches and the tests. Every family moves its objects along fixed flight plans with no
//! response (`"none"`), so every method (kinetic, time-stepped, rapier) follows the same
//! motion and their contacts can be matched one to one against the exact log.

use crate::scene::{Scene, SceneObject, ShapeSpec};
use crate::scenes::{BallScene, FlightScene};
use glam::DVec3;
use kinetic_core::{Response, WorldKind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A family of scenes, each built from a size and a seed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Family {
    /// Marbles rolling on a table: balls of radii 1:50 on a plane.
    Marbles,
    /// A gas of similar balls (radii 0.4 to 0.6) flying through each other.
    Gas,
    /// An asteroid field: spinning balls, boxes and hulls whose sizes span three orders of
    /// magnitude.
    Asteroids,
    /// Bullets: small fast balls (speeds 100 to 400) fired through a row of thin plates.
    Bullets,
    /// A resting pile: a lattice of slightly overlapping balls, jiggling slowly, so most
    /// contacts start at t = 0 and last.
    Pile,
}

impl Family {
    /// Every family, in the order tables and charts show them.
    pub const ALL: [Family; 5] = [
        Family::Marbles,
        Family::Gas,
        Family::Asteroids,
        Family::Bullets,
        Family::Pile,
    ];

    /// Its name on the command line and in tables.
    pub fn name(self) -> &'static str {
        match self {
            Family::Marbles => "marbles",
            Family::Gas => "gas",
            Family::Asteroids => "asteroids",
            Family::Bullets => "bullets",
            Family::Pile => "pile",
        }
    }

    /// The family of that name, if any.
    pub fn parse(name: &str) -> Option<Family> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }

    /// The number of objects the `compare` command uses by default.
    pub fn default_size(self) -> usize {
        match self {
            Family::Marbles => 300,
            Family::Gas => 400,
            Family::Asteroids => 300,
            Family::Bullets => 200,
            Family::Pile => 343,
        }
    }

    /// The scene with about `n` objects (exactly `n` except for the pile, which rounds to a
    /// cube, and the bullets, which add their plates).
    pub fn scene(self, n: usize, seed: u64) -> Scene {
        match self {
            Family::Marbles => BallScene {
                n,
                response: Response::None,
                walls: false,
                horizon: 10.0,
                seed,
                ..BallScene::marbles_on_a_table()
            }
            .build(),
            Family::Gas => BallScene {
                r_min: 0.4,
                r_max: 0.6,
                seed,
                ..BallScene::gas(n, seed)
            }
            .build(),
            Family::Asteroids => FlightScene::asteroids(n, 1000.0, seed).build(),
            Family::Bullets => bullets(n, seed),
            Family::Pile => pile(n, seed),
        }
    }
}

/// Plates in the bullets' path.
const PLATES: usize = 8;

/// `n` bullets of radius 0.05 starting left of a row of plates (0.02 thick, 4 by 4, 2 apart
/// along x) and flying through all of them at speeds 100 to 400 within a few degrees of +x.
fn bullets(n: usize, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut objects = Vec::with_capacity(n + PLATES);
    for k in 0..PLATES {
        objects.push(SceneObject {
            shape: ShapeSpec::Cuboid {
                half_extents: DVec3::new(0.01, 2.0, 2.0),
            },
            ..SceneObject::ball(1.0, DVec3::new(2.0 * k as f64, 0.0, 0.0), DVec3::ZERO)
        });
    }
    for _ in 0..n {
        let start = DVec3::new(
            rng.random_range(-100.0..-2.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        let dir = DVec3::new(
            1.0,
            rng.random_range(-0.05..0.05),
            rng.random_range(-0.05..0.05),
        )
        .normalize();
        let speed = rng.random_range(100.0..400.0);
        objects.push(SceneObject::ball(0.05, start, dir * speed));
    }
    Scene {
        world: WorldKind::Free,
        horizon: 1.0,
        response: Response::None,
        walls: None,
        objects,
    }
}

/// About `n` balls of radius 0.5 on a cubic lattice 0.99 apart (each overlaps its six
/// neighbours by 0.01), each jiggling at up to 0.002, so that contacts begin at t = 0 and most
/// last the whole run while a few end and begin again.
fn pile(n: usize, seed: u64) -> Scene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let side = ((n as f64).cbrt().round() as usize).max(2);
    let mut objects = Vec::with_capacity(side * side * side);
    for i in 0..side * side * side {
        let cell = DVec3::new(
            (i % side) as f64,
            ((i / side) % side) as f64,
            (i / (side * side)) as f64,
        );
        let v = DVec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        ) * 0.002;
        objects.push(SceneObject::ball(0.5, cell * 0.99, v));
    }
    Scene {
        world: WorldKind::Free,
        horizon: 10.0,
        response: Response::None,
        walls: None,
        objects,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_are_seeded_named_and_motion_only() {
        for f in Family::ALL {
            assert_eq!(Family::parse(f.name()), Some(f));
            let a = f.scene(50, 3);
            assert_eq!(a, f.scene(50, 3), "{} is not reproducible", f.name());
            assert_ne!(a, f.scene(50, 4), "{} ignores its seed", f.name());
            assert_eq!(a.response, Response::None, "{}", f.name());
            assert!(a.objects.len() >= 27, "{}: {}", f.name(), a.objects.len());
        }
        assert_eq!(Family::parse("plasma"), None);
    }
}
