//! The free-flight structures against the brute-force reference on seeded random scenes of
//! balls, cuboids and convex hulls: the same contacts (pairs and kinds in order, times within
//! 1e-7 relative), with `Simulator::validate` (the structure's audit and the check that no
//! overlapping pair is missing) after every event.

use glam::{DQuat, DVec3};
use kinetic_collide::Structure;
use kinetic_collide::run::run_scene;
use kinetic_collide::scene::{Scene, SceneObject, ShapeSpec};
use kinetic_collide::{ContactKind, Response, WorldKind};
use kinetic_scenes::{FlightScene, NestScene, ShapeMix};

use kinetic_scenes::audit::{assert_same_contacts, by_pair, run_audited};

/// Runs `params` with the brute force and `structure`; returns the number of contacts.
fn check(params: FlightScene, structure: Structure) -> usize {
    check_scene(&params.build(), structure, &format!("{params:?}"))
}

/// Runs `scene` with the brute force and `structure`; returns the number of contacts.
fn check_scene(scene: &Scene, structure: Structure, what: &str) -> usize {
    let reference = run_audited(scene, Structure::BruteForce);
    let got = run_audited(scene, structure);
    assert_same_contacts(&reference, &got, &format!("{structure:?} {what}"));
    reference.len()
}

fn object(shape: ShapeSpec, position: DVec3, velocity: DVec3) -> SceneObject {
    SceneObject {
        shape,
        position,
        velocity,
        acceleration: DVec3::ZERO,
        orientation: DQuat::IDENTITY,
        angular_velocity: DVec3::ZERO,
    }
}

fn free(objects: Vec<SceneObject>, horizon: f64) -> Scene {
    Scene {
        world: WorldKind::Free,
        horizon,
        response: Response::None,
        walls: None,
        periodic: None,
        objects,
    }
}

/// Every free-flight structure.
const FREE: [Structure; 3] = [Structure::Sweep, Structure::Guards, Structure::Grid];

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
        Structure::Sweep,
    );
    assert!(contacts > 20, "{contacts}");
}

#[test]
fn grid_balls_similar_sizes_and_accelerated_mixed_shapes() {
    let contacts = check(
        FlightScene {
            spin: 0.0,
            ..scene(150, 1.0, ShapeMix::Balls, 1)
        },
        Structure::Grid,
    );
    assert!(contacts > 20, "{contacts}");
    for (shapes, seed) in [(ShapeMix::Cuboids, 2), (ShapeMix::Mixed, 3)] {
        let contacts = check(
            FlightScene {
                acceleration: 2.0,
                ..scene(100, 3.0, shapes, seed)
            },
            Structure::Grid,
        );
        assert!(contacts > 10, "{shapes:?}: {contacts}");
    }
}

#[test]
fn sweep_spinning_cuboids() {
    let contacts = check(scene(100, 2.0, ShapeMix::Cuboids, 2), Structure::Sweep);
    assert!(contacts > 20, "{contacts}");
}

#[test]
fn sweep_accelerated_hulls() {
    let contacts = check(
        FlightScene {
            acceleration: 0.3,
            ..scene(100, 3.0, ShapeMix::Hulls, 3)
        },
        Structure::Sweep,
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
        Structure::Guards,
    );
    assert!(contacts > 20, "{contacts}");
}

#[test]
fn both_structures_mixed_shapes_sigma_100() {
    for structure in FREE {
        let contacts = check(scene(150, 100.0, ShapeMix::Mixed, 5), structure);
        assert!(contacts > 10, "{contacts}");
    }
}

#[test]
fn both_structures_mixed_shapes_sigma_1e4_accelerated() {
    for structure in FREE {
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
        let contacts = check(scene(100, 30.0, shapes, seed), Structure::Guards);
        assert!(contacts > 5, "{contacts}");
    }
}

#[test]
fn lattice_sharing_coordinates_with_simultaneous_contacts() {
    // Cubes and balls on a 4 x 4 x 4 lattice of spacing 1: every box end shares its
    // coordinate with a row of others; alternate layers move along +x and -x at the same
    // speed, so contacts begin and end many at a time.
    let mut objects = Vec::new();
    for i in 0..4 {
        for j in 0..4 {
            for k in 0..4 {
                let shape = if (i + j + k) % 2 == 0 {
                    ShapeSpec::Cuboid {
                        half_extents: DVec3::splat(0.3),
                    }
                } else {
                    ShapeSpec::Ball { radius: 0.3 }
                };
                let v = if k % 2 == 0 { 0.5 } else { -0.5 };
                let p = DVec3::new(f64::from(i), f64::from(j), f64::from(k) * 0.5);
                objects.push(object(shape, p, DVec3::new(v, 0.0, 0.0)));
            }
        }
    }
    let scene = free(objects, 4.0);
    for structure in FREE {
        let contacts = check_scene(&scene, structure, "lattice");
        assert!(contacts > 50, "{contacts}");
    }
}

#[test]
fn objects_starting_in_contact() {
    // Pairs touching exactly, overlapping, and nested, at t = 0, then flying apart or on.
    let ball = |r| ShapeSpec::Ball { radius: r };
    let cube = |h| ShapeSpec::Cuboid {
        half_extents: DVec3::splat(h),
    };
    let x = |v: f64| DVec3::new(v, 0.0, 0.0);
    let row = |k: f64| DVec3::new(0.0, 20.0 * k, 0.0);
    let objects = vec![
        // Balls touching, parting.
        object(ball(1.0), row(0.0), x(-1.0)),
        object(ball(2.0), row(0.0) + x(3.0), x(1.0)),
        // Cubes face to face, one at rest.
        object(cube(1.0), row(1.0), DVec3::ZERO),
        object(cube(0.5), row(1.0) + x(1.5), x(0.5)),
        // A small ball deep inside a large cube, passing through it.
        object(cube(3.0), row(2.0), DVec3::ZERO),
        object(ball(0.5), row(2.0), x(1.0)),
        // Touching and moving together: in contact the whole time.
        object(ball(1.0), row(3.0), x(1.0)),
        object(cube(1.0), row(3.0) + x(2.0), x(1.0)),
    ];
    let scene = free(objects, 6.0);
    for structure in FREE {
        let contacts = check_scene(&scene, structure, "start in contact");
        assert!(contacts >= 6, "{contacts}");
    }
}

#[test]
fn a_huge_object_ringed_by_tiny_ones() {
    // The paper's Fig. 6 the other way round: a ball of radius 1000 with 80 tiny objects
    // on a ring around it (sizes 1e-3 of it, a scale factor of 2000), half flying in to
    // touch it, half skimming past its box corners.
    let mut objects = vec![object(
        ShapeSpec::Ball { radius: 1000.0 },
        DVec3::ZERO,
        DVec3::ZERO,
    )];
    for k in 0..80 {
        let a = f64::from(k) * std::f64::consts::TAU / 80.0;
        let dir = DVec3::new(a.cos(), a.sin(), 0.3 * (3.0 * a).sin()).normalize();
        let shape = if k % 2 == 0 {
            ShapeSpec::Ball { radius: 0.5 }
        } else {
            ShapeSpec::Cuboid {
                half_extents: DVec3::new(0.5, 0.6, 0.7),
            }
        };
        let (position, velocity) = if k % 4 < 2 {
            (dir * 1003.0, -dir * 1.0)
        } else {
            // Near a corner of the huge ball's box, outside the ball.
            let corner = DVec3::new(a.cos().signum(), a.sin().signum(), 1.0) * 990.0;
            (corner, dir.cross(DVec3::Z) * 2.0)
        };
        objects.push(object(shape, position, velocity));
    }
    let scene = free(objects, 5.0);
    for structure in FREE {
        let contacts = check_scene(&scene, structure, "ring");
        assert!(contacts >= 40, "{contacts}");
    }
}

#[test]
fn coordinates_offset_by_1e6() {
    let mut scene = scene(100, 30.0, ShapeMix::Mixed, 9).build();
    for o in &mut scene.objects {
        o.position += DVec3::splat(1e6);
    }
    for structure in FREE {
        let contacts = check_scene(&scene, structure, "offset 1e6");
        assert!(contacts > 5, "{contacts}");
    }
}

#[test]
fn nests_of_fig_6_cones_drop_candidates_and_miss_nothing() {
    // Clusters of small balls under four chains of ever larger balls (Fig. 6): the cones
    // leave one or two balls per chain as candidates of each small ball.
    let scene = NestScene {
        horizon: 1.0,
        ..NestScene::new(100, 1e4, 10)
    }
    .build();
    for structure in FREE {
        let contacts = check_scene(&scene, structure, "nests");
        assert!(contacts > 10, "{contacts}");
    }
    let stat = |structure| {
        let out = run_scene(&scene, Some(structure)).unwrap();
        let dominated = out
            .structure_stats
            .iter()
            .find(|(k, _)| *k == "dominated_watches")
            .map_or(0.0, |&(_, v)| v);
        (out.stats.candidate_pairs_mean(), dominated)
    };
    let (sweep, _) = stat(Structure::Sweep);
    let (guards, dominated) = stat(Structure::Guards);
    assert!(dominated > 100.0, "{dominated} watches dominated");
    assert!(
        guards < 0.75 * sweep,
        "guards {guards} pairs, sweep {sweep}"
    );
}

#[test]
fn elastic_gas_with_walls_gives_the_brute_force_log_with_every_structure() {
    // Every bounce re-plans two balls: the structures' replan paths, audited after each event.
    use kinetic_scenes::BallScene;
    for (r_max, seed) in [(0.5, 4), (4.0, 5)] {
        let scene = BallScene {
            response: kinetic_collide::Response::Elastic,
            walls: true,
            allow_overlap: false,
            r_max,
            acceleration: 0.5,
            horizon: 8.0,
            ..BallScene::gas(60, seed)
        }
        .build();
        let reference = run_audited(&scene, Structure::BruteForce);
        assert!(reference.len() > 30, "{}", reference.len());
        for structure in FREE {
            let got = run_audited(&scene, structure);
            assert_eq!(got, reference, "{structure:?} r_max {r_max}");
        }
    }
}

#[test]
fn large_spinning_polytopes_touch_without_chatter() {
    // The asteroid family's boxes and hulls reach 500 units across at coordinates near 1e4;
    // there parry's GJK calls pairs within about 1e-6 "intersecting" when they are apart,
    // which once made contact ends chatter (begin/end flips 1e-9 s apart). Every pair's
    // contacts must now alternate cleanly, as in the brute force, for every structure.
    let scene = kinetic_scenes::families::Family::Asteroids.scene(300, 1);
    let reference = run_audited(&scene, Structure::BruteForce);
    for (pair, events) in by_pair(&reference) {
        for w in events.windows(2) {
            let same_instant_graze = w[0].0 == ContactKind::Begin && w[1].1 == w[0].1;
            assert!(
                same_instant_graze || w[1].1 - w[0].1 > 1e-6,
                "pair {pair:?} flips within 1e-6: {events:?}"
            );
        }
    }
    assert!(reference.len() > 30, "{}", reference.len());
    for structure in FREE {
        assert_same_contacts(&reference, &run_audited(&scene, structure), "asteroids");
    }
}
