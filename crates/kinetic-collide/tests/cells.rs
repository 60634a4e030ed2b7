//! The cell grid for elastic balls in walls (`cells`): against the event-driven brute force,
//! audited after every event, and over a million collisions of a hard-sphere gas.

use kinetic_collide::Structure;
use kinetic_collide::run::run_scene;
use kinetic_collide::scene::{Scene, outer_radius};
use kinetic_collide::spheres::ElasticCells;
use kinetic_collide::{ContactEvent, Response, WorldKind};
use kinetic_scenes::BallScene;
use kinetic_scenes::hard_spheres::HardSpheres;
use std::collections::BTreeMap;

/// The scene's balls on the cell grid.
fn cells_of(scene: &Scene) -> ElasticCells {
    let balls: Vec<_> = scene
        .objects
        .iter()
        .map(|o| (outer_radius(&o.shape), o.plan()))
        .collect();
    ElasticCells::new(scene.walls.unwrap(), &balls).unwrap()
}

/// Runs the scene on the cell grid, auditing it after every event.
/// The scene's contact log on the cell grid, audited after every event, and its events by kind.
fn cells_audited(scene: &Scene) -> (Vec<ContactEvent>, BTreeMap<&'static str, u64>) {
    let mut cells = cells_of(scene);
    cells.validate().unwrap();
    while cells.step(scene.horizon).unwrap() {
        cells
            .validate()
            .unwrap_or_else(|e| panic!("at t = {}: {e}", cells.now()));
    }
    cells.advance_to(scene.horizon).unwrap();
    (cells.drain_events(), cells.stats().events_by_kind.clone())
}

/// Small hard-sphere systems: a gas and mixtures (one to a few large balls among small ones).
fn small_systems() -> Vec<(String, Scene)> {
    let mut out = Vec::new();
    for (ratio, n) in [(1.0, 40), (0.5, 45), (0.3, 60), (0.2, 50)] {
        for seed in 1..=2 {
            let h = HardSpheres {
                n,
                ratio,
                packing: 0.2,
                collisions: 400.0,
                seed,
                periodic: false,
            };
            out.push((format!("ratio {ratio} seed {seed}"), h.build().unwrap()));
        }
    }
    // Radii spread over a factor 20: several levels, blocks at each finer one.
    let spread = BallScene {
        n: 40,
        r_min: 0.05,
        r_max: 1.0,
        side: 8.0,
        speed: 3.0,
        world: WorldKind::Free,
        response: Response::Elastic,
        walls: true,
        allow_overlap: false,
        horizon: 40.0,
        seed: 5,
        ..BallScene::gas(40, 5)
    }
    .build();
    out.push(("radii 0.05 to 1".to_string(), spread));
    out
}

#[test]
fn cells_give_the_brute_force_log_bit_for_bit() {
    let mut kinds: BTreeMap<&'static str, u64> = BTreeMap::new();
    for (name, scene) in small_systems() {
        assert!(
            matches!(
                kinetic_collide::Structure::for_scene(&scene),
                Structure::Cells | Structure::Lists
            ),
            "{name}"
        );
        let reference = kinetic_scenes::audit::run_audited(&scene, Structure::BruteForce);
        let (got, by_kind) = cells_audited(&scene);
        for (kind, n) in by_kind {
            *kinds.entry(kind).or_default() += n;
        }
        // At least the first 200 collisions are compared, pairs, order and times.
        assert!(
            reference.len() >= 200,
            "{name}: {} collisions",
            reference.len()
        );
        assert_eq!(got.len(), reference.len(), "{name}");
        for (k, (g, r)) in got.iter().zip(&reference).enumerate() {
            assert_eq!(g, r, "{name}: collision {k}");
        }
    }
    // Every way an event is handled was met: stale first events replaced by the second,
    // full re-predictions, crossings, bounces and collisions.
    for kind in ["stale", "recheck", "crossing", "bounce", "collision"] {
        assert!(
            kinds.get(kind).is_some_and(|&n| n > 0),
            "no {kind}: {kinds:?}"
        );
    }
}

#[test]
fn balls_starting_in_contact_overlapping_or_grazing() {
    use kinetic_collide::{FlightPlan, Vec3, Walls};
    let walls = Walls {
        min: Vec3::ZERO,
        max: Vec3::splat(10.0),
    };
    let balls = [
        // Touching and approaching at t = 0: a collision at once.
        (0.5, FlightPlan::linear(Vec3::new(2.0, 2.0, 2.0), Vec3::X)),
        (0.5, FlightPlan::at_rest(Vec3::new(3.0, 2.0, 2.0))),
        // Overlapping and moving apart: no collision.
        (0.5, FlightPlan::linear(Vec3::new(2.0, 6.0, 2.0), -Vec3::X)),
        (0.5, FlightPlan::linear(Vec3::new(2.8, 6.0, 2.0), Vec3::X)),
        // A graze, passing at exactly the sum of the radii (measure zero: whatever the world
        // reports, the grid reports too).
        (0.5, FlightPlan::linear(Vec3::new(1.0, 2.0, 7.0), Vec3::X)),
        (0.5, FlightPlan::at_rest(Vec3::new(5.0, 3.0, 7.0))),
    ];
    let mut cells = ElasticCells::new(walls, &balls).unwrap();
    let mut world = kinetic_collide::World::with_structure(
        WorldKind::Free,
        Response::Elastic,
        Some(walls),
        kinetic_collide::Structure::BruteForce,
    )
    .unwrap();
    world.add_balls(balls).unwrap();
    while cells.step(3.5).unwrap() {
        cells.validate().unwrap();
    }
    world.advance_to(3.5).unwrap();
    let (got, want) = (cells.drain_events(), world.drain_events());
    assert_eq!(got, want);
    let pairs: Vec<(u32, u32, f64)> = got.iter().map(|e| (e.a.0, e.b.0, e.time)).collect();
    assert_eq!(pairs[0], (0, 1, 0.0));
    assert!(pairs.iter().all(|p| (p.0, p.1) != (2, 3)), "{pairs:?}");
}

#[test]
fn cells_refuse_what_they_do_not_hold() {
    use kinetic_collide::{FlightPlan, Vec3, Walls, WorldError};
    let walls = Walls {
        min: Vec3::ZERO,
        max: Vec3::splat(10.0),
    };
    let falling = FlightPlan::accelerated(Vec3::splat(5.0), Vec3::ZERO, -Vec3::Z);
    assert!(matches!(
        ElasticCells::new(walls, &[(0.5, falling)]),
        Err(WorldError::UnsupportedShape { object: 0, .. })
    ));
    let outside = FlightPlan::at_rest(Vec3::new(9.8, 5.0, 5.0));
    assert!(matches!(
        ElasticCells::new(walls, &[(0.5, outside)]),
        Err(WorldError::OutsideWalls { object: 0 })
    ));
    // Tiny balls in a huge box: too many cells, so a scene like it goes to the world.
    assert!(!ElasticCells::supports(
        &Walls {
            min: Vec3::ZERO,
            max: Vec3::splat(1e6),
        },
        &[1e-3, 1e-3]
    ));
}

/// The gas over a million collisions: energy, walls and overlaps at sampled times.
#[test]
fn a_million_collisions_conserve_energy_inside_the_walls() {
    for (ratio, n, collisions) in [(1.0, 4000, 1.0e6), (0.1, 4000, 2.0e5)] {
        let h = HardSpheres {
            collisions,
            ..HardSpheres::mixture(n, ratio)
        };
        let scene = h.build().unwrap();
        let mut cells = cells_of(&scene);
        let e0 = cells.kinetic_energy();
        let side = h.side();
        let samples = 50;
        let mut begun = 0;
        for k in 1..=samples {
            let t = scene.horizon * k as f64 / samples as f64;
            cells.advance_to(t).unwrap();
            begun += cells.drain_events().len();
            let e = cells.kinetic_energy();
            assert!(
                ((e - e0) / e0).abs() < 1e-9,
                "ratio {ratio}: energy {e} against {e0} at t = {t}"
            );
            for id in 0..cells.len() as u32 {
                let p = cells.plan(id).position_at(t);
                let r = cells.radius(id);
                assert!(
                    (0..3).all(|k| p[k] - r >= -1e-9 && p[k] + r <= side + 1e-9),
                    "ratio {ratio}: ball {id} at {p} left the walls at t = {t}"
                );
            }
            // Contact times are exact to about 1e-12 here; speeds are at most about 100.
            let overlap = cells.max_overlap();
            assert!(
                overlap < 1e-9,
                "ratio {ratio}: overlap {overlap} at t = {t}"
            );
        }
        assert!(
            begun as f64 > 0.8 * collisions,
            "ratio {ratio}: {begun} collisions"
        );
    }
}

#[test]
fn run_chooses_cells_for_hard_spheres_and_logs_what_the_grid_logs() {
    let scene = HardSpheres {
        collisions: 3000.0,
        ..HardSpheres::mixture(600, 0.2)
    }
    .build()
    .unwrap();
    let cells = run_scene(&scene, None).unwrap();
    assert_eq!(cells.structure, Structure::Cells);
    let grid = run_scene(&scene, Some(Structure::Grid)).unwrap();
    assert_eq!(cells.event_log(), grid.event_log());
    assert_eq!(cells.stats.bounces, grid.stats.bounces);
    assert!(cells.stats.begins > 2000);
}

#[test]
fn run_measures_lists_and_cells_for_spheres_of_one_size_and_logs_what_the_grid_logs() {
    for (n, packing) in [(500, 0.1), (864, 0.4)] {
        let scene = HardSpheres {
            collisions: 4000.0,
            packing,
            ..HardSpheres::gas(n)
        }
        .build()
        .unwrap();
        // The default measures the lists, and the cell grid where that is cheap against the
        // run, from the start, then runs the faster: both log alike, and both give the bulk
        // figures.
        let default = run_scene(&scene, None).unwrap();
        let legs: Vec<_> = default.race.iter().map(|l| (l.structure, l.from)).collect();
        let tried = if legs.len() == 3 {
            vec![(Structure::Lists, 0.0), (Structure::Cells, 0.0)]
        } else {
            vec![(Structure::Lists, 0.0)]
        };
        assert_eq!(legs[..legs.len() - 1], tried[..], "{legs:?}");
        // The winner went on from where its trial stopped.
        let trial_end = default.race[..legs.len() - 1]
            .iter()
            .filter(|l| l.structure == default.structure)
            .map(|l| l.to)
            .fold(0.0, f64::max);
        assert!(trial_end > 0.0, "{legs:?}");
        assert_eq!(legs.last(), Some(&(default.structure, trial_end)));
        assert_eq!(default.race.last().unwrap().to, scene.horizon);
        let lists = run_scene(&scene, Some(Structure::Lists)).unwrap();
        assert_eq!(default.event_log(), lists.event_log());
        // The trial's sums are the first block's: the bulk figures are those of a run on
        // the winner alone, bit for bit.
        let alone = run_scene(&scene, Some(default.structure)).unwrap();
        assert_eq!(default.bulk, alone.bulk);
        let grid = run_scene(&scene, Some(Structure::Grid)).unwrap();
        assert_eq!(lists.event_log(), grid.event_log(), "packing {packing}");
        assert_eq!(lists.stats.bounces, grid.stats.bounces);
        assert!(lists.stats.bounces > 50, "{} bounces", lists.stats.bounces);
        let cells = run_scene(&scene, Some(Structure::Cells)).unwrap();
        assert_eq!(lists.event_log(), cells.event_log(), "packing {packing}");
        // The same collisions and bounces: the same figures, but for the order of the sums.
        let (a, b) = (lists.bulk.unwrap().bulk, cells.bulk.unwrap().bulk);
        assert_eq!(a.collision_rate, b.collision_rate);
        assert!((a.temperature / b.temperature - 1.0).abs() < 1e-12);
        assert!((a.pressure / b.pressure - 1.0).abs() < 1e-9, "{a:?} {b:?}");
        assert!(default.bulk.is_some());
        // The pressure on the walls is the fluid's, about Carnahan-Starling's (a small
        // system, its start included: within a fifth).
        let bulk = lists.bulk.expect("bulk figures");
        let eta = packing;
        let cs = (1.0 + eta + eta * eta - eta.powi(3)) / (1.0 - eta).powi(3);
        let z = bulk.bulk.compressibility;
        assert!(
            (z / cs - 1.0).abs() < 0.2,
            "packing {packing}: Z = {z}, CS {cs}"
        );
    }
}
