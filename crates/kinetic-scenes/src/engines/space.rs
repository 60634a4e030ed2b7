//! A space of engine scenes, drawn at random from a seed along the axes in which games differ:
//! the layout (stacks, voxel heaps, piles, rains, gases, sparse debris, a few large fixed
//! boxes or a triangle-mesh ground under many small bodies), how close resting bodies sit
//! (touching, gaps of 1% to 10% of their size, loose), the share asleep (0 to 99%), fast
//! bodies (0 to 5% at 100 to 500 units per second), kinematic bodies, the spread of sizes
//! (1 to 1000), the shapes (balls, boxes, convex hulls) and the number of bodies (100 to
//! 50,000). The engine benches run their draws side by side with each engine's own broad
//! phase, so that their figures are those of scenes nobody tuned for.

use super::{EngineScene, Piece, PieceShape, closed_box, draw3, ground, scene};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::fmt;

/// How a draw's bodies are laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Columns of boxes stacked on a ground, a few bodies dropped onto them.
    Stack,
    /// A heap of cubes on a lattice in all three axes, a few balls rolling over the top.
    Voxels,
    /// Bodies dropped in a narrow column onto a ground, heaping up.
    Pile,
    /// Bodies dropped in wide layers onto a ground.
    Rain,
    /// Elastic balls and shapes flying in a closed box, no gravity.
    Gas,
    /// Sparse drifting debris in free fall, no ground.
    Debris,
    /// A few large fixed boxes on a ground, small bodies falling among them.
    Boulders,
    /// A bumpy triangle-mesh ground, small bodies falling onto it.
    Mesh,
}

/// The layouts, in the order a draw picks from.
pub const LAYOUTS: [Layout; 8] = [
    Layout::Stack,
    Layout::Voxels,
    Layout::Pile,
    Layout::Rain,
    Layout::Gas,
    Layout::Debris,
    Layout::Boulders,
    Layout::Mesh,
];

/// One draw from the space: where it lies on each axis, and its scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Draw {
    /// The seed it was drawn from.
    pub seed: u64,
    /// Its layout.
    pub layout: Layout,
    /// Moving bodies (the fixed ground, walls and boulders not counted).
    pub bodies: usize,
    /// The gap between resting neighbours, in units of their size (0: touching).
    pub gap: f32,
    /// The share of bodies created asleep.
    pub asleep: f32,
    /// The share of fast bodies (100 to 500 units per second).
    pub fast: f32,
    /// The share of kinematic bodies.
    pub kinematic: f32,
    /// The largest body's size over the smallest's.
    pub spread: f32,
    /// The shares of balls, boxes and convex hulls among the bodies.
    pub shapes: [f32; 3],
    /// The scene.
    pub scene: EngineScene,
}

impl fmt::Display for Draw {
    /// One line: `stack n=1234 gap=0.03 asleep=0.80 fast=0.010 kin=0.00 spread=12
    /// shapes=0.3/0.5/0.2`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} n={} gap={:.3} asleep={:.2} fast={:.3} kin={:.3} spread={:.0} shapes={:.2}/{:.2}/{:.2}",
            format!("{:?}", self.layout).to_lowercase(),
            self.bodies,
            self.gap,
            self.asleep,
            self.fast,
            self.kinematic,
            self.spread,
            self.shapes[0],
            self.shapes[1],
            self.shapes[2]
        )
    }
}

/// A number log-uniform in `lo..hi`.
fn log_uniform(rng: &mut ChaCha8Rng, lo: f32, hi: f32) -> f32 {
    (rng.random_range(lo.ln()..hi.ln())).exp()
}

/// What a draw's axes say, besides its layout: the dice every layout rolls.
struct Axes {
    gap: f32,
    asleep: f32,
    spread: f32,
    shapes: [f32; 3],
    /// The smallest body's radius.
    r0: f32,
}

impl Axes {
    /// A radius between `r0` and `r0 * spread`, the number of bodies of radius at least r
    /// falling as 1 / r.
    fn radius(&self, rng: &mut ChaCha8Rng) -> f32 {
        let (lo, hi) = (self.r0, self.r0 * self.spread);
        if hi <= lo {
            return lo;
        }
        let u: f32 = rng.random_range(0.0..1.0);
        (1.0 / (1.0 / lo - u * (1.0 / lo - 1.0 / hi))).min(hi)
    }

    /// A ball, box or hull of radius `r`, by the draw's shares.
    fn shape(&self, rng: &mut ChaCha8Rng, r: f32) -> PieceShape {
        let u: f32 = rng.random_range(0.0..1.0);
        if u < self.shapes[0] {
            PieceShape::Ball(r)
        } else if u < self.shapes[0] + self.shapes[1] {
            PieceShape::Cuboid([r, 0.8 * r, 0.9 * r])
        } else {
            PieceShape::Hull(r)
        }
    }

    /// Whether a resting body is created asleep.
    fn sleeps(&self, rng: &mut ChaCha8Rng) -> bool {
        rng.random_range(0.0..1.0) < self.asleep
    }
}

/// The draw of `seed`.
pub fn draw(seed: u64) -> Draw {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed_e461_e5u64);
    let layout = LAYOUTS[rng.random_range(0..LAYOUTS.len())];
    let bodies = log_uniform(&mut rng, 100.0, 50_000.0).round() as usize;
    let gap = match rng.random_range(0..3) {
        0 => 0.0,
        1 => log_uniform(&mut rng, 0.01, 0.1),
        _ => rng.random_range(0.5..2.0),
    };
    let asleep = if rng.random_bool(0.3) {
        0.0
    } else {
        rng.random_range(0.0..0.99)
    };
    let fast = if rng.random_bool(0.4) {
        0.0
    } else {
        rng.random_range(0.0..0.05)
    };
    let kinematic = if rng.random_bool(0.5) {
        0.0
    } else {
        rng.random_range(0.0..0.05)
    };
    let spread = if rng.random_bool(0.3) {
        1.0
    } else {
        log_uniform(&mut rng, 1.0, 1000.0)
    };
    let w = [
        rng.random_range(0.0..1.0f32),
        rng.random_range(0.0..1.0f32),
        rng.random_range(0.0..1.0f32),
    ];
    let total: f32 = w.iter().sum::<f32>().max(1e-6);
    let shapes = w.map(|x| x / total);
    let axes = Axes {
        gap,
        asleep,
        spread,
        shapes,
        r0: rng.random_range(0.1..0.5),
    };
    let n_fast = (bodies as f32 * fast).round() as usize;
    let n_kinematic = (bodies as f32 * kinematic).round() as usize;
    let n_main = bodies.saturating_sub(n_fast + n_kinematic).max(1);
    let (mut pieces, gravity, extent) = match layout {
        Layout::Stack => stack(&mut rng, &axes, n_main),
        Layout::Voxels => voxels(&mut rng, &axes, n_main),
        Layout::Pile => dropped(&mut rng, &axes, n_main, 10),
        Layout::Rain => dropped(&mut rng, &axes, n_main, 0),
        Layout::Gas => gas(&mut rng, &axes, n_main),
        Layout::Debris => debris(&mut rng, &axes, n_main),
        Layout::Boulders => boulders(&mut rng, &axes, n_main),
        Layout::Mesh => mesh(&mut rng, &axes, n_main),
    };
    // Kinematic bodies cross the scene's box at 1 to 3 units per second; fast ones fly
    // through it at 100 to 500.
    let ([lo, hi], r0) = (extent, axes.r0);
    let inside = |rng: &mut ChaCha8Rng| -> [f32; 3] {
        std::array::from_fn(|a| rng.random_range(lo[a]..hi[a].max(lo[a] + 1e-3)))
    };
    for _ in 0..n_kinematic {
        let position = inside(&mut rng);
        let v = draw3(&mut rng, 1.0);
        let speed = rng.random_range(1.0..3.0) / norm(v).max(1e-3);
        pieces.push(Piece {
            velocity: v.map(|x| x * speed),
            kinematic: true,
            ..Piece::dynamic(axes.shape(&mut rng, r0 * 2.0), position)
        });
    }
    for _ in 0..n_fast {
        let position = inside(&mut rng);
        let v = draw3(&mut rng, 1.0);
        let speed = rng.random_range(100.0..500.0) / norm(v).max(1e-3);
        pieces.push(Piece {
            velocity: v.map(|x| x * speed),
            can_sleep: false,
            ..Piece::dynamic(PieceShape::Ball(r0 * 0.5), position)
        });
    }
    let moving = pieces.iter().filter(|p| !p.fixed).count();
    Draw {
        seed,
        layout,
        bodies: moving,
        gap,
        asleep: if moving == 0 {
            0.0
        } else {
            pieces.iter().filter(|p| p.asleep).count() as f32 / moving as f32
        },
        fast: n_fast as f32 / moving.max(1) as f32,
        kinematic: n_kinematic as f32 / moving.max(1) as f32,
        spread,
        shapes,
        scene: scene(fixed_first(pieces), gravity),
    }
}

fn norm(v: [f32; 3]) -> f32 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// The pieces with the fixed ones first, each side in its order.
fn fixed_first(pieces: Vec<Piece>) -> Vec<Piece> {
    let (mut fixed, moving): (Vec<Piece>, Vec<Piece>) = pieces.into_iter().partition(|p| p.fixed);
    fixed.extend(moving);
    fixed
}

/// A layout's pieces, its gravity along y and the box `[lo, hi]` its bodies fill.
type Laid = (Vec<Piece>, f32, [[f32; 3]; 2]);

/// Columns of boxes of one size (`2 r0` high), 2 to 10 high, `gap` apart side by side and
/// resting on each other, on a ground; one body in 100 dropped from above (sizes by the
/// spread).
fn stack(rng: &mut ChaCha8Rng, axes: &Axes, n: usize) -> Laid {
    let r = axes.r0;
    let high = rng.random_range(2..=10usize);
    let dropped = n / 100;
    let stacked = n - dropped;
    let columns = stacked.div_ceil(high);
    let side = (columns as f64).sqrt().ceil() as usize;
    let pitch = 2.0 * r * (1.0 + axes.gap);
    let half = side as f32 * pitch / 2.0;
    let mut pieces = vec![ground(half + 4.0 * r * axes.spread.min(50.0))];
    let at = |c: usize| {
        (
            (c % side) as f32 * pitch - half + pitch / 2.0,
            (c / side) as f32 * pitch - half + pitch / 2.0,
        )
    };
    for k in 0..stacked {
        let (x, z) = at(k / high);
        let y = r + (k % high) as f32 * 2.0 * r;
        pieces.push(Piece {
            asleep: axes.sleeps(rng),
            ..Piece::dynamic(PieceShape::Cuboid([r; 3]), [x, y, z])
        });
    }
    let top = high as f32 * 2.0 * r;
    for _ in 0..dropped {
        let (x, z) = at(rng.random_range(0..columns.max(1)));
        let s = axes.radius(rng);
        let y = top + s + rng.random_range(1.0..4.0);
        pieces.push(Piece::dynamic(axes.shape(rng, s), [x, y, z]));
    }
    (
        pieces,
        -9.81,
        [[-half, 0.0, -half], [half, top + 4.0, half]],
    )
}

/// Cubes of one size on a lattice `gap` apart on every axis, 2 to 8 layers on a ground; one
/// body in 150 rolled over the top at 1 to 4 units per second (sizes by the spread).
fn voxels(rng: &mut ChaCha8Rng, axes: &Axes, n: usize) -> Laid {
    let r = axes.r0;
    let layers = rng.random_range(2..=8usize);
    let rolling = n / 150;
    let cubes = n - rolling;
    let per_layer = cubes.div_ceil(layers);
    let side = (per_layer as f64).sqrt().ceil() as usize;
    let pitch = 2.0 * r * (1.0 + axes.gap);
    let half = side as f32 * pitch / 2.0;
    let mut pieces = vec![ground(half + 4.0 * r * axes.spread.min(50.0))];
    for k in 0..cubes {
        let (layer, cell) = (k / per_layer, k % per_layer);
        let x = (cell % side) as f32 * pitch - half + pitch / 2.0;
        let z = (cell / side) as f32 * pitch - half + pitch / 2.0;
        let y = r + layer as f32 * pitch;
        pieces.push(Piece {
            asleep: axes.sleeps(rng),
            ..Piece::dynamic(PieceShape::Cuboid([r; 3]), [x, y, z])
        });
    }
    let top = layers as f32 * pitch;
    for _ in 0..rolling {
        let s = axes.radius(rng);
        let p = [
            rng.random_range(-half..half.max(-half + 1e-3)),
            top + s,
            rng.random_range(-half..half.max(-half + 1e-3)),
        ];
        let v = [
            rng.random_range(-4.0..4.0),
            0.0,
            rng.random_range(-4.0..4.0),
        ];
        pieces.push(Piece {
            velocity: v,
            ..Piece::dynamic(PieceShape::Ball(s), p)
        });
    }
    (
        pieces,
        -9.81,
        [[-half, 0.0, -half], [half, top + 2.0, half]],
    )
}

/// Bodies (sizes by the spread) dropped from rest in layers onto a ground, cells the largest
/// body plus the gap apart: `width` cells to a side (a pile), or a tenth of them in each layer
/// when `width` is 0 (a rain).
fn dropped(rng: &mut ChaCha8Rng, axes: &Axes, n: usize, width: usize) -> Laid {
    let radii: Vec<f32> = (0..n).map(|_| axes.radius(rng)).collect();
    // Cells fit the bodies of the 99th percentile; the few larger are giants laid apart.
    let mut sorted = radii.clone();
    sorted.sort_by(f32::total_cmp);
    let cell_r = sorted[(sorted.len() * 99 / 100).min(sorted.len() - 1)];
    let pitch = 2.0 * cell_r * (1.0 + axes.gap.max(0.02));
    let side = if width > 0 {
        width
    } else {
        ((n as f64 / 10.0).sqrt().ceil() as usize).max(2)
    };
    let per_layer = side * side;
    let half = side as f32 * pitch / 2.0;
    let giant = radii.iter().fold(0.0f32, |m, &r| m.max(r));
    let mut pieces = vec![ground(half + 2.0 * giant + 2.0)];
    let mut k = 0;
    let mut high = 0.0f32;
    for &r in &radii {
        let p = if r > cell_r {
            // A giant rests on the ground beside the layers.
            let a: f32 = rng.random_range(0.0..std::f32::consts::TAU);
            [(half + r) * a.cos(), r, (half + r) * a.sin()]
        } else {
            let (layer, cell) = (k / per_layer, k % per_layer);
            k += 1;
            let y = 2.0 * cell_r + layer as f32 * pitch;
            high = high.max(y);
            [
                (cell % side) as f32 * pitch - half + pitch / 2.0,
                y,
                (cell / side) as f32 * pitch - half + pitch / 2.0,
            ]
        };
        pieces.push(Piece::dynamic(axes.shape(rng, r), p));
    }
    (
        pieces,
        -9.81,
        [[-half, 0.0, -half], [half, high + 1.0, half]],
    )
}

/// Elastic, frictionless bodies (sizes by the spread) at up to 2 units per second in a box
/// of six fixed slabs sized for a volume fraction of 5% to 20% (less with a wider gap).
fn gas(rng: &mut ChaCha8Rng, axes: &Axes, n: usize) -> Laid {
    let radii: Vec<f32> = (0..n).map(|_| axes.radius(rng)).collect();
    let volume: f32 = radii.iter().map(|r| 4.2 * r * r * r).sum();
    let fraction = 0.2 / (1.0 + 3.0 * axes.gap);
    let giant = radii.iter().fold(0.0f32, |m, &r| m.max(r));
    let half = ((volume / fraction).cbrt() / 2.0).max(2.0 * giant);
    let mut pieces = closed_box(half, 1.0);
    for &r in &radii {
        let inner = (half - r).max(0.0);
        pieces.push(Piece {
            velocity: draw3(rng, 2.0),
            spin: draw3(rng, 1.0),
            can_sleep: false,
            restitution: Some(1.0),
            friction: Some(0.0),
            ..Piece::dynamic(axes.shape(rng, r), draw3(rng, inner))
        });
    }
    (pieces, 0.0, [[-half; 3], [half; 3]])
}

/// Spinning bodies (sizes by the spread) drifting at up to 1 unit per second in free fall, in
/// a cube sized for a volume fraction of 0.5% to 2%.
fn debris(rng: &mut ChaCha8Rng, axes: &Axes, n: usize) -> Laid {
    let radii: Vec<f32> = (0..n).map(|_| axes.radius(rng)).collect();
    let volume: f32 = radii.iter().map(|r| 4.2 * r * r * r).sum();
    let half = (volume / (0.02 / (1.0 + 1.5 * axes.gap))).cbrt() / 2.0;
    let pieces = radii
        .iter()
        .map(|&r| Piece {
            velocity: draw3(rng, 1.0),
            spin: draw3(rng, 1.0),
            can_sleep: false,
            ..Piece::dynamic(axes.shape(rng, r), draw3(rng, half))
        })
        .collect();
    (pieces, 0.0, [[-half; 3], [half; 3]])
}

/// Three to eight large fixed boxes (20 to 80 times the smallest body) on a ground, and the
/// bodies (sizes by the spread) dropped among and onto them from up to a box's height.
fn boulders(rng: &mut ChaCha8Rng, axes: &Axes, n: usize) -> Laid {
    let big = 20.0 * axes.r0;
    let half = (n as f32).sqrt() * 4.0 * axes.r0 * (1.0 + axes.gap) + 4.0 * big;
    let mut pieces = vec![ground(half + axes.r0 * axes.spread)];
    for _ in 0..rng.random_range(3..=8) {
        let h = [
            rng.random_range(big..4.0 * big),
            rng.random_range(big..4.0 * big),
            rng.random_range(big..4.0 * big),
        ];
        let at = [
            rng.random_range(-half..half),
            h[1],
            rng.random_range(-half..half),
        ];
        pieces.push(Piece::fixed(PieceShape::Cuboid(h), at));
    }
    let high = 8.0 * big;
    for _ in 0..n {
        let r = axes.radius(rng);
        let p = [
            rng.random_range(-half..half),
            rng.random_range(r..high + r),
            rng.random_range(-half..half),
        ];
        pieces.push(Piece::dynamic(axes.shape(rng, r), p));
    }
    (pieces, -9.81, [[-half, 0.0, -half], [half, high, half]])
}

/// A bumpy triangle-mesh ground, and the bodies (sizes by the spread) dropped onto it from
/// layers up to a few units high.
fn mesh(rng: &mut ChaCha8Rng, axes: &Axes, n: usize) -> Laid {
    let pitch = 2.0 * axes.r0 * (1.0 + axes.gap.max(0.05)) * 2.0;
    let side = ((n as f64 / 4.0).sqrt().ceil() as usize).max(2);
    let half = side as f32 * pitch / 2.0 + axes.r0 * axes.spread;
    let cells = ((side / 2).max(8) as u32).min(256);
    let height = axes.r0 * 2.0;
    let mut pieces = vec![Piece::fixed(
        PieceShape::Terrain {
            half,
            cells,
            height,
        },
        [0.0, 0.0, 0.0],
    )];
    let per_layer = side * side;
    let mut high = 0.0f32;
    for k in 0..n {
        let r = axes.radius(rng);
        let (layer, cell) = (k / per_layer, k % per_layer);
        let y = height + r + 0.5 + layer as f32 * pitch.max(2.0 * r);
        high = high.max(y);
        let p = [
            (cell % side) as f32 * pitch - half + rng.random_range(0.0..pitch),
            y,
            (cell / side) as f32 * pitch - half + rng.random_range(0.0..pitch),
        ];
        pieces.push(Piece::dynamic(axes.shape(rng, r), p));
    }
    (pieces, -9.81, [[-half, 0.0, -half], [half, high, half]])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn draws_are_their_seeds_and_cover_every_axis() {
        assert_eq!(draw(3), draw(3));
        assert_ne!(draw(3), draw(4));
        let draws: Vec<Draw> = (0..200).map(draw).collect();
        for layout in LAYOUTS {
            assert!(draws.iter().any(|d| d.layout == layout), "{layout:?}");
        }
        for d in &draws {
            let moving = d.scene.pieces.iter().filter(|p| !p.fixed).count();
            assert_eq!(moving, d.bodies, "{d}");
            assert!((90..=50_100).contains(&d.bodies), "{d}");
            let first = d.scene.pieces.iter().position(|p| !p.fixed).unwrap_or(0);
            assert!(d.scene.pieces[first..].iter().all(|p| !p.fixed), "{d}");
            for p in &d.scene.pieces {
                assert!(p.position.iter().all(|x| x.is_finite()), "{d}");
                assert!(p.velocity.iter().all(|x| x.is_finite()), "{d}");
            }
        }
        let any = |f: &dyn Fn(&Draw) -> bool| draws.iter().any(f);
        assert!(any(&|d| d.gap == 0.0) && any(&|d| (0.01..0.1).contains(&d.gap)));
        assert!(any(&|d| d.gap >= 0.5));
        assert!(any(&|d| d.asleep > 0.8) && any(&|d| d.asleep == 0.0));
        assert!(any(&|d| d.fast > 0.03) && any(&|d| d.fast == 0.0));
        assert!(any(&|d| d.kinematic > 0.0) && any(&|d| d.spread > 300.0));
        assert!(any(&|d| d.bodies < 200) && any(&|d| d.bodies > 20_000));
        let hulls = |d: &Draw| {
            d.scene
                .pieces
                .iter()
                .any(|p| matches!(p.shape, PieceShape::Hull(_)))
        };
        assert!(any(&hulls));
    }

    #[test]
    fn fast_bodies_fly_at_their_speeds_and_stacks_touch_when_drawn_so() {
        let d = (0..400)
            .map(draw)
            .find(|d| d.fast > 0.02)
            .expect("a draw with fast bodies");
        let fast: Vec<f32> = d
            .scene
            .pieces
            .iter()
            .map(|p| norm(p.velocity))
            .filter(|&v| v > 50.0)
            .collect();
        assert!(!fast.is_empty() && fast.iter().all(|&v| (99.0..=501.0).contains(&v)));
        let s = (0..400)
            .map(draw)
            .find(|d| d.layout == Layout::Stack && d.gap == 0.0)
            .expect("a touching stack");
        let boxes: Vec<&Piece> = s
            .scene
            .pieces
            .iter()
            .filter(|p| !p.fixed && matches!(p.shape, PieceShape::Cuboid(_)))
            .collect();
        let (a, b) = (boxes[0], boxes[1]);
        let PieceShape::Cuboid(h) = a.shape else {
            unreachable!()
        };
        // Two boxes of one column rest on each other: their centres a box's height apart.
        assert!(((b.position[1] - a.position[1]) - 2.0 * h[1]).abs() < 1e-5);
    }
}
