//! Built-in scenes, defined once and shared by the command-line tool, the tests and the
//! benches. Each is seeded: the same parameters give the same scene, bit for bit.

use crate::scene::{Scene, SceneObject};
use glam::DVec3;
use kinetic_core::{Response, Walls, WorldKind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Parameters of a random scene of balls.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BallScene {
    /// Number of balls.
    pub n: usize,
    /// Smallest radius.
    pub r_min: f64,
    /// Largest radius (radii are log-uniform between the two).
    pub r_max: f64,
    /// Side of the square (plane) or cube (free) the balls start in.
    pub side: f64,
    /// Largest initial speed.
    pub speed: f64,
    /// Constant acceleration magnitude (0 for linear motion); each ball gets its own
    /// random direction.
    pub acceleration: f64,
    /// Plane or free.
    pub world: WorldKind,
    /// Contact response.
    pub response: Response,
    /// Whether the start square/cube is also a box of walls.
    pub walls: bool,
    /// Whether balls may overlap at the start (otherwise they are placed apart).
    pub allow_overlap: bool,
    /// The horizon.
    pub horizon: f64,
    /// The random seed.
    pub seed: u64,
}

impl BallScene {
    /// The default scene: marbles on a table, 300 balls of radii 1:10 rolling and bouncing
    /// elastically inside the table's rim.
    pub fn marbles_on_a_table() -> BallScene {
        BallScene {
            n: 300,
            r_min: 0.05,
            r_max: 0.5,
            side: 30.0,
            speed: 2.0,
            acceleration: 0.0,
            world: WorldKind::Plane,
            response: Response::Elastic,
            walls: true,
            allow_overlap: false,
            horizon: 20.0,
            seed: 1,
        }
    }

    /// The rolling benchmark: `n` balls on a plane with radii from 0.01 to 10 (log-uniform,
    /// ratio 1000), moving linearly at speeds up to 1 through each other (no response), at a
    /// density that does not change with `n` (side 10 sqrt(n)).
    pub fn rolling(n: usize, horizon: f64, seed: u64) -> BallScene {
        BallScene {
            n,
            r_min: 0.01,
            r_max: 10.0,
            side: 10.0 * (n as f64).sqrt(),
            speed: 1.0,
            acceleration: 0.0,
            world: WorldKind::Plane,
            response: Response::None,
            walls: false,
            allow_overlap: true,
            horizon,
            seed,
        }
    }

    /// A gas of `n` equal balls (radius 0.5) flying freely through each other in 3-space.
    pub fn gas(n: usize, seed: u64) -> BallScene {
        BallScene {
            n,
            r_min: 0.5,
            r_max: 0.5,
            side: 3.0 * (n as f64).cbrt(),
            speed: 1.0,
            acceleration: 0.0,
            world: WorldKind::Free,
            response: Response::None,
            walls: false,
            allow_overlap: true,
            horizon: 10.0,
            seed,
        }
    }

    /// The scene itself.
    pub fn build(&self) -> Scene {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let dims = if self.world == WorldKind::Plane { 2 } else { 3 };
        let mut objects: Vec<SceneObject> = Vec::with_capacity(self.n);
        let (ln_lo, ln_hi) = (self.r_min.ln(), self.r_max.ln());
        let mut attempts = 0usize;
        while objects.len() < self.n {
            attempts += 1;
            let r = if ln_hi > ln_lo {
                rng.random_range(ln_lo..ln_hi).exp()
            } else {
                self.r_min
            };
            let mut p = DVec3::ZERO;
            for k in 0..dims {
                p[k] = rng.random_range(r..(self.side - r).max(r * 1.000001));
            }
            let mut v = DVec3::ZERO;
            let mut a = DVec3::ZERO;
            for k in 0..dims {
                v[k] = rng.random_range(-1.0..1.0);
                a[k] = rng.random_range(-1.0..1.0);
            }
            let v = v.normalize_or_zero() * self.speed * rng.random_range(0.0..1.0f64).sqrt();
            let a = a.normalize_or_zero() * self.acceleration;
            let apart = |o: &SceneObject| {
                let crate::scene::ShapeSpec::Ball { radius } = o.shape else {
                    return true;
                };
                let d2 = (o.position - p).length_squared();
                match self.world {
                    WorldKind::Plane => d2 > 4.0 * radius * r,
                    WorldKind::Free => d2 > (radius + r) * (radius + r),
                }
            };
            if self.allow_overlap || attempts > 1000 * self.n || objects.iter().all(apart) {
                let mut o = SceneObject::ball(r, p, v);
                o.acceleration = a;
                objects.push(o);
            }
        }
        let walls = self.walls.then(|| Walls {
            min: DVec3::new(0.0, 0.0, if dims == 2 { -1.0 } else { 0.0 }),
            max: DVec3::splat(self.side).with_z(if dims == 2 { 1.0 } else { self.side }),
        });
        Scene {
            world: self.world,
            horizon: self.horizon,
            response: self.response,
            walls,
            objects,
        }
    }
}
