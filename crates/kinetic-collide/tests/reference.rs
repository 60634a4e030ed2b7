//! The brute-force reference on seeded random scenes, against direct overlap tests at sample
//! times: the contact state implied by the event log must match the geometry.

use kinetic_collide::Structure;
use kinetic_collide::run::build_world;
use kinetic_collide::{ContactKind, ObjectId, Response, World, WorldKind};
use kinetic_scenes::BallScene;
use std::collections::BTreeSet;

fn check(params: BallScene) -> usize {
    let scene = params.build();
    let (mut world, _) = build_world(&scene, Some(Structure::BruteForce)).unwrap();
    let mut touching: BTreeSet<(u32, u32)> = BTreeSet::new();
    let samples = 40;
    let mut total = 0;
    for s in 0..=samples {
        let t = scene.horizon * s as f64 / samples as f64;
        while world.step(t).unwrap().is_some() {
            world
                .validate()
                .unwrap_or_else(|e| panic!("at {}: {e}", world.now()));
        }
        world.advance_to(t).unwrap();
        let events = world.drain_events();
        total += events.len();
        for e in events {
            match e.kind {
                ContactKind::Begin => {
                    assert!(touching.insert((e.a.0, e.b.0)), "double begin {e:?}")
                }
                ContactKind::End => {
                    assert!(touching.remove(&(e.a.0, e.b.0)), "end without begin {e:?}")
                }
            }
        }
        // Direct test at t, skipping pairs within a hair of touching (rounding at the event).
        let n = scene.objects.len() as u32;
        for a in 0..n {
            for b in a + 1..n {
                let (ba, bb) = (
                    world.body(ObjectId(a)).unwrap(),
                    world.body(ObjectId(b)).unwrap(),
                );
                let (ra, rb) = (ba.shape.outer_radius(), bb.shape.outer_radius());
                let d = (ba.plan.position_at(t) - bb.plan.position_at(t)).length();
                let reach = match scene.world {
                    WorldKind::Free => ra + rb,
                    WorldKind::Plane => 2.0 * (ra * rb).sqrt(),
                };
                if (d - reach).abs() > 1e-9 * reach.max(1.0) {
                    assert_eq!(
                        touching.contains(&(a, b)),
                        d < reach,
                        "pair ({a}, {b}) at t = {t}: distance {d}, reach {reach}"
                    );
                }
            }
        }
    }
    total
}

#[test]
fn free_linear_balls_match_direct_overlap_tests() {
    for seed in 0..4 {
        let events = check(BallScene {
            n: 60,
            ..BallScene::gas(60, seed)
        });
        assert!(events > 10, "seed {seed}: {events} events");
    }
}

#[test]
fn free_accelerated_mixed_sizes_match() {
    for seed in 10..13 {
        check(BallScene {
            r_min: 0.05,
            r_max: 2.0,
            acceleration: 0.5,
            ..BallScene::gas(50, seed)
        });
    }
}

#[test]
fn plane_balls_match() {
    for seed in 20..23 {
        let params = BallScene {
            n: 80,
            response: Response::None,
            walls: false,
            allow_overlap: true,
            side: 15.0,
            r_min: 0.01,
            r_max: 1.0,
            horizon: 10.0,
            seed,
            ..BallScene::marbles_on_a_table()
        };
        assert!(check(params) > 10);
    }
}

#[test]
fn coordinates_offset_by_a_million() {
    let base = BallScene::gas(40, 5).build();
    let mut far = base.clone();
    for o in &mut far.objects {
        o.position += kinetic_collide::Vec3::splat(1e6);
    }
    let run = |s: &kinetic_collide::scene::Scene| {
        kinetic_collide::run::run_scene(s, None).unwrap().events
    };
    let (near, off) = (run(&base), run(&far));
    assert_eq!(near.len(), off.len());
    for (x, y) in near.iter().zip(&off) {
        assert_eq!((x.a, x.b, x.kind), (y.a, y.b, y.kind));
        assert!(
            (x.time - y.time).abs() < 1e-7 * x.time.max(1.0),
            "{} vs {}",
            x.time,
            y.time
        );
    }
}

#[test]
fn elastic_gas_in_a_box_keeps_energy() {
    let scene = BallScene {
        response: Response::Elastic,
        walls: true,
        allow_overlap: false,
        ..BallScene::gas(100, 3)
    }
    .build();
    let energy = |world: &World| -> f64 {
        world
            .bodies()
            .iter()
            .flatten()
            .map(|b| {
                let r = b.shape.outer_radius();
                0.5 * r * r * r * b.plan.velocity_at(world.now()).length_squared()
            })
            .sum()
    };
    let (mut world, _) = build_world(&scene, Some(Structure::BruteForce)).unwrap();
    let e0 = energy(&world);
    while world.step(scene.horizon).unwrap().is_some() {
        world.validate().unwrap();
    }
    assert!(world.stats().begins > 20 && world.stats().bounces > 5);
    assert!((energy(&world) - e0).abs() < 1e-9 * e0);
}
