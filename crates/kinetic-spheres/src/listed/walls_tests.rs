//! The listed spheres inside walls against the world's brute force with the same walls, event
//! by event and bit for bit, with `validate()` after every event.

use super::tests::{lattice, run, spheres_within};
use super::*;
use kinetic_core::{BruteForce, FlightPlan, Response, Simulator, WorldKind};

/// `n` non-overlapping balls of radii in `radii`, inside `walls`, speeds up to `speed`.
fn balls_inside(
    seed: u64,
    n: usize,
    radii: (Real, Real),
    walls: &Walls,
    speed: Real,
) -> Vec<(Real, FlightPlan)> {
    spheres_within(seed, n, radii, (walls.min, walls.max), 1.0, speed)
}

/// The world's log of `balls` inside `walls` to `until`, and its wall contacts.
fn world_log(walls: Walls, balls: &[(Real, FlightPlan)], until: Real) -> (Vec<ContactEvent>, u64) {
    let mut world = Simulator::with_structure(
        WorldKind::Free,
        Response::Elastic,
        Some(walls),
        Box::new(BruteForce::new()),
    )
    .unwrap();
    for (r, plan) in balls {
        world.add_ball(*r, *plan).unwrap();
    }
    world.advance_to(until).unwrap();
    (world.drain_events(), world.stats().bounces)
}

#[test]
fn balls_inside_walls_give_the_worlds_log_bit_for_bit() {
    // Boxes from a few diameters wide (one cell per axis, every ball near a wall) to wide
    // ones, one of them far from the origin, sizes equal and within a factor of two.
    let cases = [
        (Vec3::ZERO, Vec3::new(3.0, 4.0, 2.5), 12, (0.3, 0.3)),
        (Vec3::splat(-5.0), Vec3::splat(5.0), 150, (0.25, 0.5)),
        (
            Vec3::new(1e4, -3.0, 0.0),
            Vec3::new(1e4 + 9.0, 6.0, 7.0),
            120,
            (0.4, 0.4),
        ),
        (Vec3::ZERO, Vec3::new(20.0, 3.0, 3.0), 90, (0.2, 0.4)),
    ];
    for (seed, &(min, max, n, radii)) in cases.iter().enumerate() {
        let walls = Walls { min, max };
        let balls = balls_inside(seed as u64, n, radii, &walls, 2.0);
        let (expected, bounces) = world_log(walls, &balls, 15.0);
        let mut gas = ListedSpheres::in_walls(walls, &balls).unwrap();
        let got = run(&mut gas, 15.0);
        assert!(
            expected.len() > 40,
            "case {seed}: {} events",
            expected.len()
        );
        assert!(bounces > 40, "case {seed}: {bounces} wall contacts");
        assert_eq!(got, expected, "case {seed}");
        assert_eq!(gas.stats().bounces, bounces, "case {seed}");
        assert_eq!(gas.stats().events_by_kind.get("bounce"), Some(&bounces));
    }
}

#[test]
fn a_dense_fluid_in_walls_keeps_its_energy_and_presses_on_the_walls() {
    // A cubic lattice at packing 0.4 that melts, against the walls on every side.
    let (side, balls) = lattice(7, 0.4, 3);
    let walls = Walls {
        min: Vec3::ZERO,
        max: Vec3::splat(side),
    };
    let mut gas = ListedSpheres::in_walls(walls, &balls).unwrap();
    let energy =
        |g: &ListedSpheres| -> Real { g.motion.iter().map(|m| m.velocity.length_squared()).sum() };
    let e0 = energy(&gas);
    let events = run(&mut gas, 4.0);
    assert!(events.len() > 5000, "{} collisions", events.len());
    assert!((energy(&gas) - e0).abs() < 1e-9 * e0);
    assert!(gas.stats().bounces > 500, "{:?}", gas.stats());
    // The walls feel a dense fluid's pressure: well above the ideal gas's N kT / V.
    let bulk = gas.bulk();
    assert!(bulk.compressibility > 2.0, "{bulk:?}");
    assert!(bulk.compressibility < 20.0, "{bulk:?}");
}

#[test]
fn a_dilute_gas_in_walls_presses_as_an_ideal_gas() {
    let walls = Walls {
        min: Vec3::ZERO,
        max: Vec3::splat(40.0),
    };
    let balls = balls_inside(11, 400, (0.05, 0.05), &walls, 1.0);
    let mut gas = ListedSpheres::in_walls(walls, &balls).unwrap();
    gas.advance_to(400.0).unwrap();
    gas.validate().unwrap();
    let z = gas.bulk().compressibility;
    assert!((z - 1.0).abs() < 0.05, "Z = {z}");
}

#[test]
fn balls_through_the_walls_are_refused() {
    let walls = Walls {
        min: Vec3::ZERO,
        max: Vec3::splat(4.0),
    };
    let through = [(0.5, FlightPlan::at_rest(Vec3::new(0.2, 2.0, 2.0)))];
    let e = ListedSpheres::in_walls(walls, &through)
        .unwrap_err()
        .to_string();
    assert!(e.contains("not inside the walls"), "{e}");
    let flat = Walls {
        min: Vec3::ZERO,
        max: Vec3::new(4.0, 0.0, 4.0),
    };
    assert!(ListedSpheres::in_walls(flat, &[]).is_err());
    let falling = [(
        0.5,
        FlightPlan::accelerated(Vec3::splat(2.0), Vec3::ZERO, Vec3::new(0.0, 0.0, -9.8)),
    )];
    assert!(ListedSpheres::in_walls(walls, &falling).is_err());
}
