//! The cell grid against the simulator's brute force on seeded random hard-sphere systems in
//! walls: equal balls and mixtures (several grid levels), audited after every event; the log
//! must be the world's bit for bit.

use kinetic_core::{BruteForce, FlightPlan, Response, Simulator, Vec3, Walls, WorldKind};
use kinetic_spheres::ElasticCells;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `n` balls of radii in `radii` placed without overlap inside a box of side `side`.
fn system(seed: u64, n: usize, radii: (f64, f64), side: f64) -> (Walls, Vec<(f64, FlightPlan)>) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let walls = Walls {
        min: Vec3::ZERO,
        max: Vec3::splat(side),
    };
    let mut balls: Vec<(f64, FlightPlan)> = Vec::new();
    while balls.len() < n {
        let r = rng.random_range(radii.0..=radii.1);
        let p = Vec3::new(
            rng.random_range(r..side - r),
            rng.random_range(r..side - r),
            rng.random_range(r..side - r),
        );
        if balls
            .iter()
            .all(|(q, plan)| (plan.position_at(0.0) - p).length() > r + q + 1e-6)
        {
            let v = Vec3::new(
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(-2.0..2.0),
            );
            balls.push((r, FlightPlan::linear(p, v)));
        }
    }
    (walls, balls)
}

#[test]
fn the_cell_grid_gives_the_worlds_log_bit_for_bit() {
    for (seed, radii) in [
        (1, (0.5, 0.5)),
        (2, (0.5, 0.5)),
        (3, (0.1, 1.2)),
        (4, (0.05, 1.0)),
    ] {
        let (walls, balls) = system(seed, 50, radii, 9.0);
        let mut cells = ElasticCells::new(walls, &balls).expect("a valid system");
        let mut world = Simulator::with_structure(
            WorldKind::Free,
            Response::Elastic,
            Some(walls),
            Box::new(BruteForce::new()),
        )
        .expect("a world");
        world.add_balls(balls).expect("balls");
        cells.validate().expect("valid at the start");
        while cells.step(4.0).expect("step") {
            cells.validate().expect("valid after every event");
        }
        cells.advance_to(4.0).expect("advance");
        world.advance_to(4.0).expect("advance");
        let (got, want) = (cells.drain_events(), world.drain_events());
        assert!(
            want.len() > 50,
            "seed {seed}: a run with collisions ({})",
            want.len()
        );
        assert_eq!(got.len(), want.len(), "seed {seed}");
        for (x, y) in got.iter().zip(&want) {
            assert_eq!(
                (x.a, x.b, x.kind, x.time.to_bits()),
                (y.a, y.b, y.kind, y.time.to_bits()),
                "seed {seed}"
            );
        }
    }
}
