//! rapier scenes for the example, the tests and the benchmark, built from a seed (feature
//! `rapier`).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rapier3d::prelude::*;

/// A rapier scene: its bodies and colliders, and the gravity it runs under.
pub struct RapierScene {
    /// The bodies.
    pub bodies: RigidBodySet,
    /// The colliders.
    pub colliders: ColliderSet,
    /// Gravity.
    pub gravity: Vector<f32>,
}

/// A rain of `n` mixed balls and boxes (radii 0.1 to 0.2) dropped from rest over a ground
/// slab, in layers 1 unit apart of cells 0.5 apart (a layer holds about n / 10), with `rocks`
/// large boulders (radius 1 to 2) resting on the ground among them.
pub fn rain(n: usize, rocks: usize, seed: u64) -> RapierScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    // Drops in layers of side*side cells 0.5 apart, 1 unit between layers.
    let side = ((n as f64 / 10.0).sqrt().ceil() as usize).max(2);
    let half = side as f32 * 0.25 + 4.0;
    colliders.insert(
        ColliderBuilder::cuboid(half, 0.5, half)
            .translation(vector![0.0, -0.5, 0.0])
            .build(),
    );
    for _ in 0..rocks {
        let r = rng.random_range(1.0..2.0);
        let p = vector![
            rng.random_range(-half + 2.0..half - 2.0),
            r,
            rng.random_range(-half + 2.0..half - 2.0)
        ];
        let h = bodies.insert(RigidBodyBuilder::dynamic().translation(p));
        colliders.insert_with_parent(ColliderBuilder::ball(r).density(3.0), h, &mut bodies);
    }
    let per_layer = side * side;
    for k in 0..n {
        let (layer, cell) = (k / per_layer, k % per_layer);
        let p = vector![
            (cell % side) as f32 * 0.5 - side as f32 * 0.25 + rng.random_range(-0.05..0.05),
            5.0 + layer as f32 + rng.random_range(0.0..0.3),
            (cell / side) as f32 * 0.5 - side as f32 * 0.25 + rng.random_range(-0.05..0.05)
        ];
        let h = bodies.insert(RigidBodyBuilder::dynamic().translation(p));
        let r = rng.random_range(0.1..0.2);
        let co = if k % 3 == 2 {
            ColliderBuilder::cuboid(r, r, r)
        } else {
            ColliderBuilder::ball(r)
        };
        colliders.insert_with_parent(co, h, &mut bodies);
    }
    RapierScene {
        bodies,
        colliders,
        gravity: vector![0.0, -9.81, 0.0],
    }
}

/// A debris field in free fall (no gravity, no ground): `n` spinning balls and boxes whose
/// radii run from 0.01 to 10 (three orders of magnitude; the number of pieces of radius at
/// least r falls as 1 / r), drifting at up to 1 unit per second in a cube sized for a volume
/// fraction of about 2%.
pub fn debris(n: usize, seed: u64) -> RapierScene {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut bodies = RigidBodySet::new();
    let mut colliders = ColliderSet::new();
    let (lo, hi) = (0.01f32, 10.0f32);
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
    for (k, &r) in radii.iter().enumerate() {
        let p = vector![
            rng.random_range(-half..half),
            rng.random_range(-half..half),
            rng.random_range(-half..half)
        ];
        let v = vector![
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0)
        ];
        let w = vector![
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0)
        ];
        let h = bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(p)
                .linvel(v)
                .angvel(w)
                .can_sleep(false),
        );
        let co = if k % 2 == 1 {
            ColliderBuilder::cuboid(r, 0.7 * r, 0.8 * r)
        } else {
            ColliderBuilder::ball(r)
        };
        colliders.insert_with_parent(co, h, &mut bodies);
    }
    RapierScene {
        bodies,
        colliders,
        gravity: vector![0.0, 0.0, 0.0],
    }
}
