//! Scene families for comparing methods: defined once and shared by the `compare` command,
//! the benches and the tests. Every family moves its objects along fixed flight plans with no
//! response (`"none"`), so every method (kinetic, time-stepped, rapier) follows the same
//! motion and their contacts can be matched one to one against the exact log.

use crate::generators::{BallScene, FlightScene};
use glam::DVec3;
use kinetic_collide::scene::{Scene, SceneObject, ShapeSpec};
use kinetic_collide::{Response, WorldKind};
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
        periodic: None,
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
        periodic: None,
        objects,
    }
}

/// The stability cases: scenes where methods break, each built to show one way.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Case {
    /// 125 pairs on a lattice that all touch at t = 1 and part at t = 3, exactly.
    Lattice,
    /// Pairs that touch at one instant (exact grazes), miss by 1e-9, or overlap by 1e-9.
    Grazes,
    /// Pairs touching, overlapping and nested at t = 0, moving apart or along.
    StartInContact,
    /// The gas family moved 1e6 along each axis.
    Offset1e6,
    /// The gas family moved 1e9 along each axis.
    Offset1e9,
    /// A ball of radius 1e6 with balls of radius 1e-6 flying at and along its surface.
    Radii,
    /// Balls at speeds of 1e6 through rows of balls at rest.
    Speed1e6,
    /// A small elastic ball between two huge ones closing in: a Zeno configuration.
    Zeno,
}

impl Case {
    /// Every case, in the order the README's table shows them.
    pub const ALL: [Case; 8] = [
        Case::Lattice,
        Case::Grazes,
        Case::StartInContact,
        Case::Offset1e6,
        Case::Offset1e9,
        Case::Radii,
        Case::Speed1e6,
        Case::Zeno,
    ];

    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Case::Lattice => "lattice",
            Case::Grazes => "grazes",
            Case::StartInContact => "start-in-contact",
            Case::Offset1e6 => "offset-1e6",
            Case::Offset1e9 => "offset-1e9",
            Case::Radii => "radii-1e-6-1e6",
            Case::Speed1e6 => "speed-1e6",
            Case::Zeno => "zeno",
        }
    }

    /// The case of that name, if any.
    pub fn parse(name: &str) -> Option<Case> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }

    /// The scene.
    pub fn scene(self) -> Scene {
        let ball = |r: f64, p: DVec3, v: DVec3| SceneObject::ball(r, p, v);
        let free = |objects: Vec<SceneObject>, horizon: f64| Scene {
            world: WorldKind::Free,
            horizon,
            response: Response::None,
            walls: None,
            periodic: None,
            objects,
        };
        match self {
            Case::Lattice => {
                let mut objects = Vec::new();
                for i in 0..125 {
                    let cell = DVec3::new((i % 5) as f64, ((i / 5) % 5) as f64, (i / 25) as f64);
                    let p = cell * DVec3::new(8.0, 4.0, 4.0);
                    objects.push(ball(0.5, p, DVec3::X));
                    objects.push(ball(0.5, p + DVec3::new(2.0, 0.0, 0.0), DVec3::ZERO));
                }
                free(objects, 4.0)
            }
            Case::Grazes => {
                // Centres pass at distance 1 + miss from a ball at rest; radii 0.5 each.
                let mut objects = Vec::new();
                for (k, miss) in [0.0, 1e-9, -1e-9].into_iter().enumerate() {
                    for j in 0..20 {
                        let base = DVec3::new(0.0, 10.0 * j as f64, 10.0 * k as f64);
                        objects.push(ball(0.5, base, DVec3::ZERO));
                        // Off the samples of every step: the graze is at t = 2.0123.
                        let p = base + DVec3::new(-2.0123, 1.0 + miss, 0.0);
                        objects.push(ball(0.5, p, DVec3::X));
                    }
                }
                free(objects, 4.0)
            }
            Case::StartInContact => {
                let cube = |h: f64, p: DVec3, v: DVec3| SceneObject {
                    shape: ShapeSpec::Cuboid {
                        half_extents: DVec3::splat(h),
                    },
                    ..SceneObject::ball(1.0, p, v)
                };
                let x = |v: f64| DVec3::new(v, 0.0, 0.0);
                let mut objects = Vec::new();
                for j in 0..10 {
                    let row = DVec3::new(0.0, 0.0, 30.0 * j as f64);
                    let y = |k: f64| row + DVec3::new(0.0, 20.0 * k, 0.0);
                    objects.extend([
                        // Touching exactly, parting.
                        ball(1.0, y(0.0), x(-1.0)),
                        ball(2.0, y(0.0) + x(3.0), x(1.0)),
                        // Overlapping, parting slowly.
                        ball(1.0, y(1.0), x(-0.1)),
                        ball(1.0, y(1.0) + x(1.5), x(0.1)),
                        // A small ball deep inside a cube, passing through it.
                        cube(3.0, y(2.0), DVec3::ZERO),
                        ball(0.5, y(2.0), x(1.0)),
                        // Touching and moving together: in contact the whole time.
                        ball(1.0, y(3.0), x(1.0)),
                        cube(1.0, y(3.0) + x(2.0), x(1.0)),
                    ]);
                }
                free(objects, 6.0)
            }
            Case::Offset1e6 | Case::Offset1e9 => {
                let shift = if self == Case::Offset1e6 { 1e6 } else { 1e9 };
                let mut scene = Family::Gas.scene(200, 1);
                for o in &mut scene.objects {
                    o.position += DVec3::splat(shift);
                }
                scene
            }
            Case::Radii => {
                // The big ball's top is at z = 1e6; tiny balls start 1e-5 above it, half
                // falling onto it, half sliding along in pairs that meet each other.
                let mut objects = vec![ball(1e6, DVec3::ZERO, DVec3::ZERO)];
                for k in 0..40 {
                    let x = 1e-3 * k as f64;
                    let top = (1e12 - x * x).sqrt();
                    let p = DVec3::new(x, 0.0, top + 1e-6 + 1e-5);
                    if k % 2 == 0 {
                        objects.push(ball(1e-6, p, DVec3::new(0.0, 0.0, -1e-5)));
                    } else {
                        objects.push(ball(
                            1e-6,
                            p + DVec3::new(0.0, -5e-6, 0.0),
                            DVec3::new(0.0, 2e-6, 0.0),
                        ));
                        objects.push(ball(
                            1e-6,
                            p + DVec3::new(0.0, 5e-6, 0.0),
                            DVec3::new(0.0, -2e-6, 0.0),
                        ));
                    }
                }
                free(objects, 4.0)
            }
            Case::Speed1e6 => {
                // Rows of resting balls 1000 apart; each bullet passes one every 1e-3 and
                // touches it for 1e-6.
                let mut objects = Vec::new();
                for j in 0..5 {
                    let y = 5.0 * j as f64;
                    for k in 0..40 {
                        let p = DVec3::new(1000.0 * k as f64, y, 0.0);
                        objects.push(ball(0.5, p, DVec3::ZERO));
                    }
                    let v = DVec3::new(1e6, 0.0, 0.0);
                    objects.push(ball(0.5, DVec3::new(-5.0, y + 0.1 * j as f64, 0.0), v));
                }
                free(objects, 0.05)
            }
            Case::Zeno => {
                // Gap 2 between the giants' surfaces, closing at 2 per unit time; the small
                // ball (mass 1e-10 of theirs) bounces between them ever faster.
                let v = DVec3::X;
                Scene {
                    response: Response::Elastic,
                    ..free(
                        vec![
                            ball(1e3, DVec3::new(-1e3 - 1.5, 0.0, 0.0), v),
                            ball(0.5, DVec3::ZERO, v),
                            ball(1e3, DVec3::new(1e3 + 1.5, 0.0, 0.0), -v),
                        ],
                        2.0,
                    )
                }
            }
        }
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
        for c in Case::ALL {
            assert_eq!(Case::parse(c.name()), Some(c));
            let scene = c.scene();
            assert!(scene.objects.len() >= 3, "{}", c.name());
            assert!(Scene::from_json(&scene.to_json()).is_ok(), "{}", c.name());
        }
    }
}
