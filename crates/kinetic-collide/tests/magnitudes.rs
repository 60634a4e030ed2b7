//! Properties over random input: the scene parser never panics, whatever the text; small
//! random scenes give the brute force's log with every structure, balls at any scale of
//! lengths from 1e-100 to 1e100, cuboids from 1e-3 to 1e6; a scene beyond the range the tool
//! computes exactly is refused.

use kinetic_collide::Structure;
use kinetic_collide::run::run_scene;
use kinetic_collide::scene::{MAX_REACH, Scene, SceneObject, ShapeSpec};
use kinetic_collide::{ContactEvent, Response, WorldKind};
use kinetic_scenes::audit::assert_same_contacts;
use proptest::prelude::*;

/// A small random scene of balls and cuboids flying through each other, lengths scaled by
/// `scale` (speeds too, so times do not change).
fn scene(seeds: &[(u8, [i8; 3], [i8; 3])], scale: f64, world: WorldKind, boxes: bool) -> Scene {
    let objects = seeds
        .iter()
        .enumerate()
        .map(|(i, &(size, p, v))| {
            let r = (1.0 + f64::from(size % 8) * 0.25) * scale;
            // Off the lattice, so that no two objects graze (a graze is measure zero, and
            // rounding may make it a touch or a miss).
            let jitter = glam::DVec3::new(0.0123, 0.0071, 0.0037) * (1.0 + i as f64 * 0.618);
            let position = (glam::DVec3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
                * 0.5
                + jitter)
                * scale;
            let velocity =
                glam::DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2])) * 0.05 * scale;
            let shape = if boxes && size >= 128 && world == WorldKind::Free {
                ShapeSpec::Cuboid {
                    half_extents: glam::DVec3::new(r, r * 1.5, r * 0.75),
                }
            } else {
                ShapeSpec::Ball { radius: r }
            };
            SceneObject {
                shape,
                ..SceneObject::ball(r, position, velocity)
            }
        })
        .collect();
    Scene {
        world,
        horizon: 20.0,
        response: Response::None,
        walls: None,
        periodic: None,
        objects,
    }
}

/// The scales (powers of ten) over which cuboids and hulls are checked: their distances come
/// from parry's queries, whose tolerances are absolute.
const CUBOID_SCALES: std::ops::RangeInclusive<i32> = -3..=6;

/// Every structure on the scene of `seeds` scaled by `10^exponent` gives the brute force's
/// log of the unscaled scene.
fn same_logs_at_scale(
    seeds: &[(u8, [i8; 3], [i8; 3])],
    exponent: i32,
    world: WorldKind,
    boxes: bool,
) {
    let unit = scene(seeds, 1.0, world, boxes);
    let reference = log(&unit, Structure::BruteForce);
    let scaled = scene(seeds, 10f64.powi(exponent), world, boxes);
    // The scaled scene reads back through the parser: it is in range.
    let read = Scene::from_json(&scaled.to_json()).unwrap();
    for s in applicable(&read) {
        let got = log(&read, s);
        assert_same_contacts(&reference, &got, &format!("{s:?} at 1e{exponent}"));
    }
}

fn applicable(scene: &Scene) -> Vec<Structure> {
    Structure::ALL
        .into_iter()
        .filter(|s| s.applies_to(scene))
        .collect()
}

fn log(scene: &Scene, s: Structure) -> Vec<ContactEvent> {
    run_scene(scene, Some(s))
        .unwrap_or_else(|e| panic!("{s:?}: {e}"))
        .events
}

proptest! {
    // A fixed seed: the same cases on every run.
    #![proptest_config(ProptestConfig {
        cases: 24,
        rng_seed: proptest::test_runner::RngSeed::Fixed(20261124),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn every_structure_gives_the_brute_force_log_for_balls_at_any_scale(
        seeds in prop::collection::vec((any::<u8>(), any::<[i8; 3]>(), any::<[i8; 3]>()), 2..14),
        exponent in -100i32..=100,
        plane in any::<bool>(),
    ) {
        let world = if plane { WorldKind::Plane } else { WorldKind::Free };
        same_logs_at_scale(&seeds, exponent, world, false);
    }

    #[test]
    fn every_structure_gives_the_brute_force_log_for_cuboids_over_a_range_of_scales(
        seeds in prop::collection::vec((any::<u8>(), any::<[i8; 3]>(), any::<[i8; 3]>()), 2..10),
        exponent in CUBOID_SCALES,
    ) {
        same_logs_at_scale(&seeds, exponent, WorldKind::Free, true);
    }

    #[test]
    fn the_parser_never_panics_on_any_text(text in ".{0,200}") {
        let _ = Scene::from_json(&text);
    }

    #[test]
    fn the_parser_never_panics_on_mangled_scenes(
        cut in 0usize..400,
        byte in any::<u8>(),
        seeds in prop::collection::vec((any::<u8>(), any::<[i8; 3]>(), any::<[i8; 3]>()), 1..4),
    ) {
        let text = scene(&seeds, 1.0, WorldKind::Free, true).to_json();
        let mut bytes = text.into_bytes();
        let at = cut.min(bytes.len().saturating_sub(1));
        bytes[at] = byte;
        if let Ok(text) = String::from_utf8(bytes.clone()) {
            let _ = Scene::from_json(&text);
        }
        bytes.truncate(at);
        if let Ok(text) = String::from_utf8(bytes) {
            let _ = Scene::from_json(&text);
        }
    }

    #[test]
    fn a_scene_beyond_the_range_is_refused(exponent in 151i32..=307, which in 0usize..3) {
        let big = 10f64.powi(exponent);
        let mut s = scene(&[(1, [0, 0, 0], [1, 0, 0]), (2, [4, 0, 0], [0, 0, 0])], 1.0, WorldKind::Free, false);
        match which {
            0 => s.objects[1].position.x = big,
            1 => s.objects[0].velocity.x = big,
            _ => s.objects[0].shape = ShapeSpec::Ball { radius: big },
        }
        let err = Scene::from_json(&s.to_json()).unwrap_err();
        prop_assert!(err.path.starts_with("objects["), "{err}");
        prop_assert!(err.message.contains("beyond"), "{err}");
        prop_assert!(big > MAX_REACH);
    }
}
