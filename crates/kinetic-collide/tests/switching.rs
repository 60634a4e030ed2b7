//! Handing a running world from one structure to another (`World::switch_structure`, what the
//! race of the default does) changes nothing in the log: on seeded random scenes, a run that
//! switches every few events through every structure of its world gives the brute force's
//! contacts, with `validate()` after every event; and a run without a named structure gives
//! the log of one with it, bit for bit.

use kinetic_collide::Structure;
use kinetic_collide::run::{build_world, run_scene};
use kinetic_collide::scene::Scene;
use kinetic_scenes::audit::{assert_same_contacts, run_audited};
use kinetic_scenes::{BallScene, FlightScene, ShapeMix};

/// Runs `scene` switching structure every `every` events, cycling through every structure
/// that runs in its world, with the audit after every event.
fn run_switching(scene: &Scene, every: usize) -> Vec<kinetic_collide::ContactEvent> {
    let cycle: Vec<Structure> = Structure::ALL
        .into_iter()
        .filter(|s| s.runs_in_a_world() && s.applies_to(scene))
        .collect();
    assert!(cycle.len() >= 4, "{cycle:?}");
    let (mut world, _) = build_world(scene, Some(cycle[0])).unwrap();
    world.validate().unwrap();
    let mut steps = 0;
    let mut next = 1;
    while world.step(scene.horizon).unwrap().is_some() {
        world.validate().unwrap();
        steps += 1;
        if steps % every == 0 {
            let s = cycle[next % cycle.len()];
            world.switch_structure(s, scene.horizon / 1000.0).unwrap();
            assert_eq!(world.structure_name(), s.name());
            world
                .validate()
                .unwrap_or_else(|e| panic!("after switching to {s:?}: {e}"));
            next += 1;
        }
    }
    assert!(next > cycle.len(), "only {next} switches");
    world.advance_to(scene.horizon).unwrap();
    world.drain_events()
}

#[test]
fn switching_mid_run_keeps_the_brute_force_log() {
    for seed in 1..=3 {
        let balls = BallScene {
            n: 120,
            horizon: 4.0,
            ..BallScene::gas(120, seed)
        }
        .build();
        let shapes = FlightScene {
            n: 80,
            shapes: ShapeMix::Mixed,
            fill: 0.08,
            horizon: 3.0,
            ..FlightScene::asteroids(80, 1.0, seed)
        }
        .build();
        let elastic = BallScene {
            n: 80,
            horizon: 30.0,
            ..BallScene::marbles_on_a_table()
        };
        let elastic = BallScene { seed, ..elastic }.build();
        for (what, scene) in [("gas", &balls), ("shapes", &shapes), ("marbles", &elastic)] {
            let reference = run_audited(scene, Structure::BruteForce);
            assert!(reference.len() > 10, "{what}: {} events", reference.len());
            let got = run_switching(scene, 7);
            assert_same_contacts(&reference, &got, &format!("{what} seed {seed}"));
            if what != "shapes" {
                // Balls: the same log bit for bit.
                assert_eq!(got, reference, "{what} seed {seed}");
            }
        }
    }
}

#[test]
fn the_raced_default_gives_the_named_structures_log() {
    // Long enough to race: the default measures its shortlist and may switch.
    let scene = BallScene {
        n: 1500,
        horizon: 20.0,
        ..BallScene::gas(1500, 7)
    }
    .build();
    let raced = run_scene(&scene, None).unwrap();
    let named = run_scene(&scene, Some(Structure::Sweep)).unwrap();
    assert_eq!(raced.events, named.events);
    assert!(named.race.is_empty());
    // The race covers the run, slice after slice.
    if !raced.race.is_empty() {
        assert_eq!(raced.race[0].from, 0.0);
        assert_eq!(raced.race.last().unwrap().to, scene.horizon);
        for w in raced.race.windows(2) {
            assert_eq!(w[0].to, w[1].from);
        }
    }
}
