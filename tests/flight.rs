//! The free-flight structures against the brute-force reference on seeded random scenes of
//! balls, cuboids and convex hulls: the same contacts (pairs and kinds in order, times within
//! 1e-7 relative), with `World::validate` (the structure's audit and the check that no
//! overlapping pair is missing) after every event.

use kinetic_collide::run::{StructureName, build_world};
use kinetic_collide::scene::Scene;
use kinetic_collide::scenes::{FlightScene, ShapeMix};
use kinetic_collide::{ContactEvent, ContactKind};
use std::collections::BTreeMap;

/// Runs `scene` with `structure`, auditing the world after every event.
fn run_audited(scene: &Scene, structure: StructureName) -> Vec<ContactEvent> {
    let (mut world, _) = build_world(scene, Some(structure)).unwrap();
    world.validate().unwrap();
    while world.step(scene.horizon).unwrap().is_some() {
        world
            .validate()
            .unwrap_or_else(|e| panic!("{structure:?} at t = {}: {e}", world.now()));
    }
    world.advance_to(scene.horizon).unwrap();
    world.drain_events()
}

/// The contacts of each pair, in order.
fn by_pair(events: &[ContactEvent]) -> BTreeMap<(u32, u32), Vec<(ContactKind, f64)>> {
    let mut out: BTreeMap<_, Vec<_>> = BTreeMap::new();
    for e in events {
        out.entry((e.a.0, e.b.0))
            .or_default()
            .push((e.kind, e.time));
    }
    out
}

/// Same pairs, same kinds in the same order per pair, times within 1e-7 relative.
fn assert_same_contacts(reference: &[ContactEvent], got: &[ContactEvent], what: &str) {
    let (r, g) = (by_pair(reference), by_pair(got));
    for (pair, want) in &r {
        let have = g
            .get(pair)
            .unwrap_or_else(|| panic!("{what}: pair {pair:?} missing: {want:?}"));
        assert_eq!(
            have.iter().map(|x| x.0).collect::<Vec<_>>(),
            want.iter().map(|x| x.0).collect::<Vec<_>>(),
            "{what}: pair {pair:?}: {have:?} vs {want:?}"
        );
        for (h, w) in have.iter().zip(want) {
            assert!(
                (h.1 - w.1).abs() <= 1e-7 * w.1.abs().max(1.0),
                "{what}: pair {pair:?}: {have:?} vs {want:?}"
            );
        }
    }
    if let Some(extra) = g.keys().find(|p| !r.contains_key(p)) {
        panic!("{what}: extra pair {extra:?}: {:?}", g[extra]);
    }
}

/// Runs `params` with the brute force and `structure`; returns the number of contacts.
fn check(params: FlightScene, structure: StructureName) -> usize {
    let scene = params.build();
    let reference = run_audited(&scene, StructureName::BruteForce);
    let got = run_audited(&scene, structure);
    assert_same_contacts(&reference, &got, &format!("{structure:?} {params:?}"));
    reference.len()
}

fn scene(n: usize, sigma: f64, shapes: ShapeMix, seed: u64) -> FlightScene {
    FlightScene {
        n,
        sigma,
        shapes,
        fill: 0.08,
        ..FlightScene::asteroids(n, sigma, seed)
    }
}

#[test]
fn sweep_balls_similar_sizes() {
    let contacts = check(
        FlightScene {
            spin: 0.0,
            ..scene(150, 1.0, ShapeMix::Balls, 1)
        },
        StructureName::Sweep,
    );
    assert!(contacts > 20, "{contacts}");
}

#[test]
fn sweep_spinning_cuboids() {
    let contacts = check(scene(100, 2.0, ShapeMix::Cuboids, 2), StructureName::Sweep);
    assert!(contacts > 20, "{contacts}");
}

#[test]
fn sweep_accelerated_hulls() {
    let contacts = check(
        FlightScene {
            acceleration: 0.3,
            ..scene(100, 3.0, ShapeMix::Hulls, 3)
        },
        StructureName::Sweep,
    );
    assert!(contacts > 20, "{contacts}");
}

#[test]
fn guards_balls_similar_sizes() {
    let contacts = check(
        FlightScene {
            spin: 0.0,
            ..scene(150, 1.0, ShapeMix::Balls, 4)
        },
        StructureName::Guards,
    );
    assert!(contacts > 20, "{contacts}");
}

#[test]
fn both_structures_mixed_shapes_sigma_100() {
    for structure in [StructureName::Sweep, StructureName::Guards] {
        let contacts = check(scene(150, 100.0, ShapeMix::Mixed, 5), structure);
        assert!(contacts > 10, "{contacts}");
    }
}

#[test]
fn both_structures_mixed_shapes_sigma_1e4_accelerated() {
    for structure in [StructureName::Sweep, StructureName::Guards] {
        let contacts = check(
            FlightScene {
                acceleration: 0.2,
                ..scene(150, 1e4, ShapeMix::Mixed, 6)
            },
            structure,
        );
        assert!(contacts > 5, "{contacts}");
    }
}

#[test]
fn guards_spinning_hulls_and_cuboids() {
    for (shapes, seed) in [(ShapeMix::Hulls, 7), (ShapeMix::Cuboids, 8)] {
        let contacts = check(scene(100, 30.0, shapes, seed), StructureName::Guards);
        assert!(contacts > 5, "{contacts}");
    }
}
