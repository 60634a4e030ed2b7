//! Built-in scenes, defined once and shared by the command-line tool, the tests and the
//! benches. Each is seeded: the same parameters give the same scene, bit for bit.

use glam::DVec3;
use kinetic_collide::scene::{Scene, SceneObject};
use kinetic_collide::{Response, Walls, WorldKind};
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
    /// The default scene: marbles on a table, 300 balls of radii 1:50 rolling and bouncing
    /// elastically inside the table's rim.
    pub fn marbles_on_a_table() -> BallScene {
        BallScene {
            n: 300,
            r_min: 0.02,
            r_max: 1.0,
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
                let kinetic_collide::scene::ShapeSpec::Ball { radius } = o.shape else {
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
            periodic: None,
            objects,
        }
    }
}

/// A random direction (zero, rarely).
pub(crate) fn random_unit(rng: &mut ChaCha8Rng) -> DVec3 {
    DVec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    )
    .normalize_or_zero()
}

/// Which shapes a free-flight scene holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShapeMix {
    /// Balls only.
    Balls,
    /// Cuboids only.
    Cuboids,
    /// Convex hulls only.
    Hulls,
    /// Balls, cuboids and hulls in turn.
    Mixed,
}

/// Parameters of a random scene of convex objects flying freely through each other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightScene {
    /// Number of objects.
    pub n: usize,
    /// Smallest inner radius.
    pub r_min: f64,
    /// Scale factor: largest over smallest inner radius (sizes log-uniform between).
    pub sigma: f64,
    /// The shapes.
    pub shapes: ShapeMix,
    /// Largest initial speed.
    pub speed: f64,
    /// Largest angular speed (0 for no spin).
    pub spin: f64,
    /// Constant acceleration magnitude (0 for linear motion), random direction per object.
    pub acceleration: f64,
    /// Fraction of the start cube's volume that the outer balls fill; sets its side.
    pub fill: f64,
    /// The horizon.
    pub horizon: f64,
    /// The random seed.
    pub seed: u64,
}

impl FlightScene {
    /// An asteroid field: `n` mixed objects whose sizes span a factor `sigma`, spinning, with
    /// linear motion and no response.
    pub fn asteroids(n: usize, sigma: f64, seed: u64) -> FlightScene {
        FlightScene {
            n,
            r_min: 0.5,
            sigma,
            shapes: ShapeMix::Mixed,
            speed: 1.0,
            spin: 1.0,
            acceleration: 0.0,
            fill: 0.05,
            horizon: 10.0,
            seed,
        }
    }

    /// The scene itself.
    pub fn build(&self) -> Scene {
        use kinetic_collide::scene::ShapeSpec;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let (ln_lo, ln_hi) = (self.r_min.ln(), (self.r_min * self.sigma).ln());
        let mut shapes = Vec::with_capacity(self.n);
        let mut volume = 0.0;
        for i in 0..self.n {
            let r = if ln_hi > ln_lo {
                rng.random_range(ln_lo..ln_hi).exp()
            } else {
                self.r_min
            };
            let kind = match self.shapes {
                ShapeMix::Balls => 0,
                ShapeMix::Cuboids => 1,
                ShapeMix::Hulls => 2,
                ShapeMix::Mixed => i % 3,
            };
            let shape = match kind {
                0 => ShapeSpec::Ball { radius: r },
                // Inner radius r (the smallest half extent), fatness at most 3.
                1 => ShapeSpec::Cuboid {
                    half_extents: DVec3::new(
                        r,
                        r * rng.random_range(1.0..2.0),
                        r * rng.random_range(1.0..2.0),
                    ),
                },
                // The six axis points at distances from r to 1.5 r hold a ball of radius
                // r / sqrt 3 about the origin; six more random points make it irregular.
                _ => {
                    let mut points = Vec::with_capacity(12);
                    for k in 0..3 {
                        for s in [-1.0, 1.0] {
                            let mut p = DVec3::ZERO;
                            p[k] = s * r * rng.random_range(1.0..1.5);
                            points.push(p);
                        }
                    }
                    for _ in 0..6 {
                        let d = DVec3::new(
                            rng.random_range(-1.0..1.0),
                            rng.random_range(-1.0..1.0),
                            rng.random_range(-1.0..1.0),
                        );
                        points.push(d.normalize_or(DVec3::X) * r * rng.random_range(1.0..1.5));
                    }
                    ShapeSpec::ConvexHull { points }
                }
            };
            let outer = kinetic_collide::scene::outer_radius(&shape);
            volume += 4.0 / 3.0 * std::f64::consts::PI * outer.powi(3);
            shapes.push(shape);
        }
        let side = (volume / self.fill).cbrt();
        let objects = shapes
            .into_iter()
            .map(|shape| {
                let position = DVec3::new(
                    rng.random_range(0.0..side),
                    rng.random_range(0.0..side),
                    rng.random_range(0.0..side),
                );
                let velocity =
                    random_unit(&mut rng) * self.speed * rng.random_range(0.0..1.0f64).sqrt();
                let acceleration = random_unit(&mut rng) * self.acceleration;
                let angular_velocity =
                    random_unit(&mut rng) * self.spin * rng.random_range(0.0..1.0);
                let axis = random_unit(&mut rng);
                let orientation = if axis == DVec3::ZERO {
                    glam::DQuat::IDENTITY
                } else {
                    glam::DQuat::from_axis_angle(axis, rng.random_range(0.0..std::f64::consts::TAU))
                };
                SceneObject {
                    shape,
                    position,
                    velocity,
                    acceleration,
                    orientation,
                    angular_velocity,
                }
            })
            .collect();
        Scene {
            world: WorldKind::Free,
            horizon: self.horizon,
            response: Response::None,
            walls: None,
            periodic: None,
            objects,
        }
    }
}

/// Parameters of a scene of the paper's Fig. 6: clusters of small balls, each watched by
/// chains of ever larger balls whose boxes all hold the cluster while the balls stay apart.
///
/// Each cluster has four chains along the tetrahedron's directions (each moved to the middle
/// of the guard cone it points into, so that the guards see a chain inside one cone). A
/// chain's balls grow by a factor `growth`, each centred 1.5 radii from the cluster: its box
/// reaches past the cluster, the ball stops half a radius short, and the next ball starts
/// beyond it; chains in different directions stay apart at any sizes. Everything in a
/// cluster drifts together, the small balls jiggle, and nothing responds to contact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NestScene {
    /// Number of clusters.
    pub clusters: usize,
    /// Small balls per cluster.
    pub small: usize,
    /// Radius of the small balls.
    pub r_min: f64,
    /// Radius of the first ball of each chain.
    pub r_first: f64,
    /// Largest over smallest radius: the chains stop before exceeding it.
    pub sigma: f64,
    /// Factor between consecutive balls of a chain (at least 5 keeps them apart).
    pub growth: f64,
    /// Speed of the small balls relative to their cluster.
    pub jiggle: f64,
    /// The horizon.
    pub horizon: f64,
    /// The random seed.
    pub seed: u64,
}

impl NestScene {
    /// Chains per cluster.
    pub const CHAINS: usize = 4;

    /// Nests of 100 small balls of radius 0.5 under chains up to `sigma` times larger, in
    /// enough clusters to make about `n` objects.
    pub fn new(n: usize, sigma: f64, seed: u64) -> NestScene {
        let mut scene = NestScene {
            clusters: 1,
            small: 100,
            r_min: 0.5,
            r_first: 20.0,
            sigma,
            growth: 5.2,
            jiggle: 0.2,
            horizon: 2.0,
            seed,
        };
        scene.clusters = n
            .div_ceil(scene.small + Self::CHAINS * scene.levels())
            .max(1);
        scene
    }

    /// Balls per chain.
    pub fn levels(&self) -> usize {
        let mut r = self.r_first;
        let mut k = 0;
        while r <= self.r_min * self.sigma * (1.0 + 1e-12) {
            k += 1;
            r *= self.growth;
        }
        k
    }

    /// The scene itself.
    pub fn build(&self) -> Scene {
        use kinetic_collide::scene::ShapeSpec;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let levels = self.levels();
        let largest = self.r_first * self.growth.powi(levels.saturating_sub(1) as i32);
        let spacing = 6.0 * largest.max(self.r_first);
        let per_side = (self.clusters as f64).cbrt().ceil() as usize;
        let cones = kinetic_collide::kds::ConeSet::new(1.0);
        let chains: Vec<DVec3> = [
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
            DVec3::new(-1.0, -1.0, 1.0),
        ]
        .iter()
        .map(|&t| {
            // Slightly off the diagonal, which lies on cone facets.
            let cone = cones.cone(cones.locate(t + DVec3::new(0.0, 0.05, 0.1) * t));
            cone.rays.iter().sum::<DVec3>().normalize()
        })
        .collect();
        let mut objects = Vec::new();
        let ball = |radius: f64, position: DVec3, velocity: DVec3| SceneObject {
            shape: ShapeSpec::Ball { radius },
            position,
            velocity,
            acceleration: DVec3::ZERO,
            orientation: glam::DQuat::IDENTITY,
            angular_velocity: DVec3::ZERO,
        };
        for c in 0..self.clusters {
            let cell = DVec3::new(
                (c % per_side) as f64,
                ((c / per_side) % per_side) as f64,
                (c / (per_side * per_side)) as f64,
            );
            let centre = cell * spacing;
            let drift = random_unit(&mut rng) * 0.1;
            for dir in &chains {
                let mut r = self.r_first;
                for _ in 0..levels {
                    objects.push(ball(r, centre + *dir * (1.5 * r), drift));
                    r *= self.growth;
                }
            }
            // The small balls start within 0.4 r_first of the cluster's centre, clear of
            // the first balls of the chains (half a radius away).
            let reach = (0.4 * self.r_first - self.r_min) / 3f64.sqrt();
            for _ in 0..self.small {
                let offset = DVec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                ) * reach;
                let velocity = drift + random_unit(&mut rng) * self.jiggle;
                objects.push(ball(self.r_min, centre + offset, velocity));
            }
        }
        Scene {
            world: WorldKind::Free,
            horizon: self.horizon,
            response: Response::None,
            walls: None,
            periodic: None,
            objects,
        }
    }
}
