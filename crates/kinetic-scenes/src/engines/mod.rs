//! Scenes for physics engines (rapier, avian), engine-neutral, built from a seed: the kinds
//! the engines' own benches use (a pile, a rain, a ball gas in a box, drifting debris of
//! spread sizes and of alike ones, a burst flying apart, a mostly sleeping world, many
//! kinematic bodies). The `rapier` and
//! `avian` modules put them into each engine, so both adapters' benches and examples run the
//! very same scenes.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

pub mod results;
pub mod space;

/// A piece's shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PieceShape {
    /// A ball of this radius.
    Ball(f32),
    /// A box of these half-extents.
    Cuboid([f32; 3]),
    /// A convex hull of this radius: the points of [`hull_points`].
    Hull(f32),
    /// A fixed triangle-mesh ground: the mesh of [`terrain_mesh`] with these arguments.
    Terrain {
        /// Half its width along x and z.
        half: f32,
        /// Cells along each side (two triangles each).
        cells: u32,
        /// The height of its bumps.
        height: f32,
    },
}

/// The points of a [`PieceShape::Hull`] of radius `r`: an icosahedron squashed to
/// `(1, 0.8, 0.9)` times `r` on the axes, so that it rolls unevenly.
pub fn hull_points(r: f32) -> Vec<[f32; 3]> {
    let g = (1.0 + 5f32.sqrt()) / 2.0;
    let scale = r / (1.0 + g * g).sqrt();
    let mut points = Vec::with_capacity(12);
    for a in [-1.0, 1.0] {
        for b in [-g, g] {
            for p in [[0.0, a, b], [a, b, 0.0], [b, 0.0, a]] {
                points.push([p[0] * scale, p[1] * scale * 0.8, p[2] * scale * 0.9]);
            }
        }
    }
    points
}

/// The vertices and triangles of a [`PieceShape::Terrain`]: a square grid of `cells` by
/// `cells` cells over `-half..half` along x and z, its height `height` times a product of
/// two sines (bumps about 8 cells wide), its top between `-height` and `height` about y = 0.
pub fn terrain_mesh(half: f32, cells: u32, height: f32) -> (Vec<[f32; 3]>, Vec<[u32; 3]>) {
    let cells = cells.max(1);
    let step = 2.0 * half / cells as f32;
    let at = |i: u32| -half + i as f32 * step;
    let mut vertices = Vec::with_capacity(((cells + 1) * (cells + 1)) as usize);
    for i in 0..=cells {
        for j in 0..=cells {
            let (x, z) = (at(i), at(j));
            let y = height * (x / step * 0.8).sin() * (z / step * 0.8).sin();
            vertices.push([x, y, z]);
        }
    }
    let mut triangles = Vec::with_capacity((2 * cells * cells) as usize);
    let v = |i: u32, j: u32| i * (cells + 1) + j;
    for i in 0..cells {
        for j in 0..cells {
            triangles.push([v(i, j), v(i, j + 1), v(i + 1, j)]);
            triangles.push([v(i + 1, j), v(i, j + 1), v(i + 1, j + 1)]);
        }
    }
    (vertices, triangles)
}

/// One body with one collider.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Piece {
    /// Its shape.
    pub shape: PieceShape,
    /// Where its centre starts.
    pub position: [f32; 3],
    /// Its velocity and spin at the start.
    pub velocity: [f32; 3],
    /// Its angular velocity at the start.
    pub spin: [f32; 3],
    /// Fixed (the ground, walls), not dynamic.
    pub fixed: bool,
    /// Kinematic: moved by its velocity alone, pushed by nothing.
    pub kinematic: bool,
    /// Its density (1 for most).
    pub density: f32,
    /// Whether the engine may put it to sleep.
    pub can_sleep: bool,
    /// Created asleep.
    pub asleep: bool,
    /// Its restitution (0: no bounce) and friction, where not the engine's default.
    pub restitution: Option<f32>,
    /// Its friction, where not the engine's default.
    pub friction: Option<f32>,
}

impl Piece {
    fn dynamic(shape: PieceShape, position: [f32; 3]) -> Piece {
        Piece {
            shape,
            position,
            velocity: [0.0; 3],
            spin: [0.0; 3],
            fixed: false,
            kinematic: false,
            density: 1.0,
            can_sleep: true,
            asleep: false,
            restitution: None,
            friction: None,
        }
    }

    fn fixed(shape: PieceShape, position: [f32; 3]) -> Piece {
        Piece {
            fixed: true,
            ..Piece::dynamic(shape, position)
        }
    }
}

/// Three draws in `-h..h`: a position or a velocity.
fn draw3(rng: &mut ChaCha8Rng, h: f32) -> [f32; 3] {
    [
        rng.random_range(-h..h),
        rng.random_range(-h..h),
        rng.random_range(-h..h),
    ]
}

/// A ball of radius `r`, or (every `every`-th piece, from the last of each run) a box of
/// half-extents `r` times `box_shape`.
fn ball_or_box(k: usize, every: usize, r: f32, box_shape: [f32; 3]) -> PieceShape {
    if k % every == every - 1 {
        PieceShape::Cuboid(box_shape.map(|f| f * r))
    } else {
        PieceShape::Ball(r)
    }
}

/// Piece `k` of a free-flying scene: a ball of radius `r` or (every second one) a box, set
/// moving and spinning, never asleep.
fn spinning(k: usize, r: f32, position: [f32; 3], velocity: [f32; 3], spin: [f32; 3]) -> Piece {
    Piece {
        velocity,
        spin,
        can_sleep: false,
        ..Piece::dynamic(ball_or_box(k, 2, r, [1.0, 0.7, 0.8]), position)
    }
}

/// The scene of `pieces` under gravity `gy` along the y axis.
fn scene(pieces: Vec<Piece>, gy: f32) -> EngineScene {
    EngineScene {
        pieces,
        gravity: [0.0, gy, 0.0],
    }
}

/// A ground slab of half-width `half`, its top at 0.
fn ground(half: f32) -> Piece {
    Piece::fixed(PieceShape::Cuboid([half, 0.5, half]), [0.0, -0.5, 0.0])
}

/// Six fixed slabs `t` thick closing the cube of half-width `half` about the origin.
fn closed_box(half: f32, t: f32) -> Vec<Piece> {
    let w = half + t;
    let wall = |at: [f32; 3], h: [f32; 3]| Piece::fixed(PieceShape::Cuboid(h), at);
    vec![
        wall([0.0, -half - t, 0.0], [w, t, w]),
        wall([0.0, half + t, 0.0], [w, t, w]),
        wall([-half - t, 0.0, 0.0], [t, w, w]),
        wall([half + t, 0.0, 0.0], [t, w, w]),
        wall([0.0, 0.0, -half - t], [w, w, t]),
        wall([0.0, 0.0, half + t], [w, w, t]),
    ]
}

/// A scene: its pieces and the gravity it runs under.
#[derive(Clone, Debug, PartialEq)]
pub struct EngineScene {
    /// The pieces, the fixed ones first.
    pub pieces: Vec<Piece>,
    /// Gravity.
    pub gravity: [f32; 3],
}

/// A rain of `n` mixed balls and boxes (radii 0.1 to 0.2) dropped from rest over a ground
/// slab, in layers 1 unit apart of cells 0.5 apart (a layer holds about n / 10), with `rocks`
/// large boulders (radius 1 to 2) resting on the ground among them.
pub fn rain(n: usize, rocks: usize, seed: u64) -> EngineScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut pieces = Vec::with_capacity(n + rocks + 1);
    // Drops in layers of side*side cells 0.5 apart, 1 unit between layers.
    let side = ((n as f64 / 10.0).sqrt().ceil() as usize).max(2);
    let half = side as f32 * 0.25 + 4.0;
    pieces.push(ground(half));
    for _ in 0..rocks {
        let r = rng.random_range(1.0..2.0);
        let p = [
            rng.random_range(-half + 2.0..half - 2.0),
            r,
            rng.random_range(-half + 2.0..half - 2.0),
        ];
        pieces.push(Piece {
            density: 3.0,
            ..Piece::dynamic(PieceShape::Ball(r), p)
        });
    }
    let per_layer = side * side;
    for k in 0..n {
        let (layer, cell) = (k / per_layer, k % per_layer);
        let p = [
            (cell % side) as f32 * 0.5 - side as f32 * 0.25 + rng.random_range(-0.05..0.05),
            5.0 + layer as f32 + rng.random_range(0.0..0.3),
            (cell / side) as f32 * 0.5 - side as f32 * 0.25 + rng.random_range(-0.05..0.05),
        ];
        let r = rng.random_range(0.1..0.2);
        pieces.push(Piece::dynamic(ball_or_box(k, 3, r, [1.0; 3]), p));
    }
    scene(pieces, -9.81)
}

/// A debris field in free fall (no gravity, no ground): `n` spinning balls and boxes whose
/// radii run from 0.01 to 10 (three orders of magnitude; the number of pieces of radius at
/// least r falls as 1 / r), drifting at up to 1 unit per second in a cube sized for a volume
/// fraction of about 2%. None sleeps.
pub fn debris(n: usize, seed: u64) -> EngineScene {
    drifting(n, seed, (0.01, 10.0))
}

/// Drifting debris of alike sizes: the [`debris`] field with radii from 0.1 to 0.5 (the
/// number of pieces of radius at least r still falling as 1 / r).
pub fn drift(n: usize, seed: u64) -> EngineScene {
    drifting(n, seed, (0.1, 0.5))
}

/// `n` spinning balls and boxes with radii from `lo` to `hi` (the number of pieces of radius
/// at least r falling as 1 / r, the first piece the largest), drifting at up to 1 unit per
/// second in a cube sized for a volume fraction of about 2%.
fn drifting(n: usize, seed: u64, (lo, hi): (f32, f32)) -> EngineScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let radii: Vec<f32> = (0..n)
        .map(|k| {
            // P(R >= r) ~ 1/r between lo and hi; the first piece is the largest.
            if k == 0 {
                hi
            } else {
                let u: f32 = rng.random_range(0.0..1.0);
                (1.0 / (1.0 / lo - u * (1.0 / lo - 1.0 / hi))).min(hi)
            }
        })
        .collect();
    let volume: f32 = radii.iter().map(|r| 4.2 * r * r * r).sum();
    let half = (volume / 0.02).cbrt() / 2.0;
    let pieces = radii
        .iter()
        .enumerate()
        .map(|(k, &r)| {
            let position = draw3(&mut rng, half);
            let velocity = draw3(&mut rng, 1.0);
            let spin = draw3(&mut rng, 1.0);
            spinning(k, r, position, velocity, spin)
        })
        .collect();
    scene(pieces, 0.0)
}

/// A pile: `n` balls and boxes (radii 0.2 to 0.25) dropped in a column of 10 by 10 cells 0.5
/// apart, layers 0.5 apart, onto a ground: they land on each other and heap up.
pub fn pile(n: usize, seed: u64) -> EngineScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut pieces = vec![ground(20.0)];
    for k in 0..n {
        let (layer, cell) = (k / 100, k % 100);
        let p = [
            (cell % 10) as f32 * 0.5 - 2.25 + rng.random_range(-0.02..0.02),
            0.5 + layer as f32 * 0.5,
            (cell / 10) as f32 * 0.5 - 2.25 + rng.random_range(-0.02..0.02),
        ];
        let r = rng.random_range(0.2..0.25);
        pieces.push(Piece::dynamic(ball_or_box(k, 2, r, [0.9; 3]), p));
    }
    scene(pieces, -9.81)
}

/// A ball gas: `n` elastic, frictionless balls (radius 0.1 to 0.2) at up to 2 units per
/// second in zero gravity, closed in a box of six slabs sized for a volume fraction of about
/// 5%; none sleeps.
pub fn gas(n: usize, seed: u64) -> EngineScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let half = (n as f32 * 4.2 * 0.15f32.powi(3) / 0.05).cbrt() / 2.0;
    let mut pieces = closed_box(half, 0.5);
    let inner = half - 0.25;
    for _ in 0..n {
        let position = draw3(&mut rng, inner);
        let velocity = draw3(&mut rng, 2.0);
        let r = rng.random_range(0.1..0.2);
        pieces.push(Piece {
            velocity,
            can_sleep: false,
            restitution: Some(1.0),
            friction: Some(0.0),
            ..Piece::dynamic(PieceShape::Ball(r), position)
        });
    }
    scene(pieces, 0.0)
}

/// A mostly sleeping world: `n` unit boxes created asleep on a ground in a grid 1.5 apart,
/// and one body in 200 (balls of radius 0.3) falling onto them from 3 to 8 units up.
pub fn asleep(n: usize, seed: u64) -> EngineScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let side = (n as f64).sqrt().ceil() as usize;
    let half = side as f32 * 0.75 + 2.0;
    let mut pieces = vec![ground(half)];
    let at = |k: usize| {
        (
            (k % side) as f32 * 1.5 - side as f32 * 0.75,
            (k / side) as f32 * 1.5 - side as f32 * 0.75,
        )
    };
    for k in 0..n {
        let (x, z) = at(k);
        pieces.push(Piece {
            asleep: true,
            ..Piece::dynamic(PieceShape::Cuboid([0.5; 3]), [x, 0.5, z])
        });
    }
    for k in (0..n).step_by(200) {
        let (x, z) = at(k);
        let y = rng.random_range(3.0..8.0);
        pieces.push(Piece::dynamic(PieceShape::Ball(0.3), [x, y, z]));
    }
    scene(pieces, -9.81)
}

/// Crates: `n` unit boxes stacked 8 high in square columns 0.1 apart, created asleep, and
/// one body in 200 (a box or a ball of radius 0.5) dropped onto them from 3 to 6 units above.
/// A resting world whose boxes nearly touch on every side.
pub fn crates(n: usize, seed: u64) -> EngineScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let columns = n.div_ceil(8);
    let side = (columns as f64).sqrt().ceil() as usize;
    let pitch = 1.1;
    let half = side as f32 * pitch / 2.0;
    let mut pieces = vec![ground(half + 2.0)];
    let at = |c: usize| {
        (
            (c % side) as f32 * pitch - half + 0.55,
            (c / side) as f32 * pitch - half + 0.55,
        )
    };
    for k in 0..n {
        let (x, z) = at(k / 8);
        let y = 0.5 + (k % 8) as f32;
        pieces.push(Piece {
            asleep: true,
            ..Piece::dynamic(PieceShape::Cuboid([0.5; 3]), [x, y, z])
        });
    }
    for k in (0..n).step_by(200) {
        let (x, z) = at(k / 8);
        let y = 8.0 + rng.random_range(3.0..6.0);
        let shape = if k % 400 == 0 {
            PieceShape::Cuboid([0.5; 3])
        } else {
            PieceShape::Ball(0.5)
        };
        pieces.push(Piece::dynamic(shape, [x, y, z]));
    }
    scene(pieces, -9.81)
}

/// Many kinematic bodies: `n` balls and boxes (radii 0.2 to 0.5) moved by their velocities
/// (up to 3 units per second) and spins through a cube sized for a volume fraction of about
/// 3%, passing through each other; no gravity.
pub fn kinematic(n: usize, seed: u64) -> EngineScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let half = (n as f32 * 4.2 * 0.35f32.powi(3) / 0.03).cbrt() / 2.0;
    let pieces = (0..n)
        .map(|k| {
            let position = draw3(&mut rng, half);
            let velocity = draw3(&mut rng, 3.0);
            let spin = draw3(&mut rng, 1.0);
            let r = rng.random_range(0.2..0.5);
            Piece {
                velocity,
                spin,
                kinematic: true,
                ..Piece::dynamic(ball_or_box(k, 2, r, [1.0, 0.8, 0.6]), position)
            }
        })
        .collect();
    scene(pieces, 0.0)
}

/// A burst in free fall (no gravity, no ground): `n` spinning balls and boxes of radius 0.1
/// to 0.3 packed in a cube (about one per 1.7 cubic units) and flying apart, each outwards
/// by where it starts, at up to 2 units per second on each axis, give or take 0.2. None
/// sleeps.
pub fn burst(n: usize, seed: u64) -> EngineScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let half = (n as f32).cbrt() * 0.6;
    let pieces = (0..n)
        .map(|k| {
            let r = rng.random_range(0.1f32..0.3);
            let position = draw3(&mut rng, half);
            let jitter = draw3(&mut rng, 0.2);
            let velocity = std::array::from_fn(|a| 2.0 * position[a] / half + jitter[a]);
            let spin = draw3(&mut rng, 2.0);
            spinning(k, r, position, velocity, spin)
        })
        .collect();
    scene(pieces, 0.0)
}

/// The scene of `kind` (`pile`, `rain`, `gas`, `debris`, `drift`, `burst`, `asleep`,
/// `kinematic`, `crates`) with
/// `n` bodies, from the seed each bench uses.
pub fn standard(kind: &str, n: usize) -> Option<EngineScene> {
    Some(match kind {
        "pile" => pile(n, 5),
        "rain" => rain(n, (n / 400).max(3), 7),
        "gas" => gas(n, 3),
        "debris" => debris(n, 1),
        "drift" => drift(n, 19),
        "burst" => burst(n, 17),
        "asleep" => asleep(n, 11),
        "kinematic" => kinematic(n, 13),
        "crates" => crates(n, 23),
        _ => return None,
    })
}

/// The standard scenes' kinds, in the benches' order.
pub const STANDARD: [&str; 9] = [
    "pile",
    "rain",
    "gas",
    "debris",
    "drift",
    "burst",
    "asleep",
    "kinematic",
    "crates",
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rain_has_its_ground_rocks_and_drops_and_a_debris_field_spans_three_orders() {
        let s = rain(100, 3, 7);
        assert_eq!(s.pieces.len(), 104);
        assert!(s.pieces[0].fixed && s.pieces[1..].iter().all(|p| !p.fixed));
        assert_eq!(rain(100, 3, 7), s);
        let d = debris(1000, 1);
        let radius = |p: &Piece| match p.shape {
            PieceShape::Ball(r) | PieceShape::Hull(r) => r,
            PieceShape::Cuboid(h) => h[0],
            PieceShape::Terrain { half, .. } => half,
        };
        let (lo, hi) = d
            .pieces
            .iter()
            .map(radius)
            .fold((f32::MAX, 0.0f32), |(l, h), r| (l.min(r), h.max(r)));
        assert!(lo < 0.02 && hi == 10.0, "{lo} {hi}");
        assert!(
            d.pieces
                .iter()
                .all(|p| !p.can_sleep && p.velocity != [0.0; 3])
        );
    }

    #[test]
    fn every_standard_scene_has_its_bodies_and_the_fixed_ones_first() {
        for kind in STANDARD {
            let s = standard(kind, 1000).expect("a standard scene");
            let moving = s.pieces.iter().filter(|p| !p.fixed).count();
            assert!((1000..=1010).contains(&moving), "{kind}: {moving}");
            let first_moving = s.pieces.iter().position(|p| !p.fixed).unwrap_or(0);
            assert!(s.pieces[first_moving..].iter().all(|p| !p.fixed), "{kind}");
        }
        assert!(standard("nothing", 10).is_none());
        let a = asleep(1000, 1);
        assert_eq!(a.pieces.iter().filter(|p| p.asleep).count(), 1000);
        assert!(kinematic(10, 1).pieces.iter().all(|p| p.kinematic));
    }
}
