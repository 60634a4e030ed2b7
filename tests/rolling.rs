//! The rolling-ball collision tree (both list layouts) against the brute-force reference on
//! seeded random plane scenes, with `validate()` after every event, plus named degenerate
//! cases.

use kinetic_collide::run::{StructureName, build_world};
use kinetic_collide::scene::Scene;
use kinetic_collide::scenes::BallScene;
use kinetic_collide::{ContactEvent, Response, World, WorldKind};

const LAYOUTS: [StructureName; 2] = [
    StructureName::RollingTree,
    StructureName::RollingGlobalLists,
];

/// Validating is a full audit, O(n log^2 n) each time: runs validate after each of their
/// first `AUDITED` events (the global lists make twenty times as many events as the tree).
const AUDITED: usize = 20_000;

/// Runs `world` to `horizon`, validating after each of the first `audited` events; returns
/// the log.
fn run_validated(world: &mut World, horizon: f64, audited: usize) -> Vec<ContactEvent> {
    world.validate().unwrap_or_else(|e| panic!("at start: {e}"));
    let mut events = 0;
    while world.step(horizon).unwrap().is_some() {
        events += 1;
        if events <= audited {
            world.validate().unwrap_or_else(|e| {
                panic!("{} at t = {}: {e}", world.structure_name(), world.now())
            });
        }
    }
    world.advance_to(horizon).unwrap();
    world
        .validate()
        .unwrap_or_else(|e| panic!("at the horizon: {e}"));
    world.drain_events()
}

fn run(scene: &Scene, structure: StructureName) -> Vec<ContactEvent> {
    let (mut world, _) = build_world(scene, Some(structure)).unwrap();
    world.advance_to(scene.horizon).unwrap();
    world.drain_events()
}

/// Two logs are the same: the same pairs and kinds in the same order, times within the
/// scene format's accuracy.
fn assert_same_log(reference: &[ContactEvent], got: &[ContactEvent], what: &str) {
    let first_diff = reference.iter().zip(got).position(|(r, g)| {
        (r.a, r.b, r.kind) != (g.a, g.b, g.kind)
            || (r.time - g.time).abs() > 1e-7 * r.time.abs().max(1.0)
    });
    assert!(
        first_diff.is_none() && reference.len() == got.len(),
        "{what}: logs differ at event {:?} of {} / {}: reference {:?}, got {:?}",
        first_diff,
        reference.len(),
        got.len(),
        first_diff.map(|i| reference[i]),
        first_diff.map(|i| got[i]),
    );
}

fn plane(n: usize, r_min: f64, r_max: f64, side: f64, seed: u64) -> BallScene {
    BallScene {
        n,
        r_min,
        r_max,
        side,
        speed: 1.0,
        acceleration: 0.0,
        world: WorldKind::Plane,
        response: Response::None,
        walls: false,
        allow_overlap: true,
        horizon: 10.0,
        seed,
    }
}

/// Runs `params` with the brute force and with both layouts of the collision tree: the logs
/// must match to the horizon (the tree validated as `run_validated` says).
fn check_against_brute_force(params: BallScene) -> usize {
    let scene = params.build();
    let reference = run(&scene, StructureName::BruteForce);
    for layout in LAYOUTS {
        let (mut world, _) = build_world(&scene, Some(layout)).unwrap();
        let got = run_validated(&mut world, scene.horizon, AUDITED);
        assert_same_log(
            &reference,
            &got,
            &format!("{} on {params:?}", layout.as_str()),
        );
    }
    reference.len()
}

#[test]
fn sparse_linear_three_orders_of_radii() {
    let mut events = 0;
    for seed in 0..3 {
        events += check_against_brute_force(plane(200, 0.01, 10.0, 300.0, seed));
    }
    assert!(events > 30, "too few events to test anything: {events}");
}

#[test]
fn dense_linear_three_orders_of_radii() {
    let events = check_against_brute_force(plane(500, 0.01, 10.0, 120.0, 7));
    assert!(events > 400, "{events}");
}

#[test]
fn accelerated_mixed_sizes() {
    let mut params = plane(300, 0.01, 10.0, 150.0, 3);
    params.acceleration = 0.3;
    let events = check_against_brute_force(params);
    assert!(events > 100, "{events}");
}

#[test]
fn elastic_in_a_box_with_walls() {
    let mut params = plane(300, 0.01, 10.0, 200.0, 5);
    params.response = Response::Elastic;
    params.walls = true;
    params.allow_overlap = false;
    params.speed = 3.0;
    let events = check_against_brute_force(params);
    assert!(events > 50, "{events}");
}

#[test]
fn elastic_accelerated_dense() {
    let mut params = plane(400, 0.02, 2.0, 80.0, 11);
    params.response = Response::Elastic;
    params.walls = true;
    params.allow_overlap = false;
    params.acceleration = 0.5;
    let events = check_against_brute_force(params);
    assert!(events > 100, "{events}");
}
