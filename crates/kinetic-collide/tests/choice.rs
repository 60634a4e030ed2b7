//! The default choice on the choice family (and a spread of sizes wider than the family's): it
//! always names a structure that applies to the scene, every branch of the rule is taken, and
//! it gives the brute force's contacts.

use kinetic_collide::Structure;
use kinetic_collide::run::run_scene;
use kinetic_scenes::BallScene;
use kinetic_scenes::audit::assert_same_contacts;
use kinetic_scenes::choice::{KINDS, choice_family};

#[test]
fn the_default_applies_takes_every_branch_and_matches_the_brute_force() {
    let cases = choice_family(&[60, 250], 7);
    assert_eq!(cases.len(), 2 * KINDS.len());
    // Sizes spread wider than the family's (1:10^6), drifting, for the sweep.
    let wide = BallScene {
        r_min: 5e-5,
        r_max: 50.0,
        side: 12.0 * 250f64.cbrt(),
        speed: 0.01,
        horizon: 10.0,
        ..BallScene::gas(250, 7)
    }
    .build();
    let mut picked = std::collections::BTreeSet::new();
    for (kind, scene) in cases
        .iter()
        .map(|c| (c.kind, &c.scene))
        .chain([("sizes-1e6", &wide)])
    {
        let pick = Structure::for_scene(scene);
        assert!(pick.applies_to(scene), "{kind}: {pick:?}");
        picked.insert(pick.name());
        let reference = run_scene(scene, Some(Structure::BruteForce)).unwrap();
        let got = run_scene(scene, None).unwrap();
        // The run starts on the pick (and may race on from there).
        let first = got.race.first().map_or(got.structure, |leg| leg.structure);
        assert_eq!(first, pick, "{kind}");
        assert_same_contacts(&reference.events, &got.events, kind);
    }
    // The family exercises every branch of the rule but the loose grid's (named above 200,000
    // objects of alike sizes; the race tries it below).
    assert_eq!(
        picked.into_iter().collect::<Vec<_>>(),
        ["brute-force", "cells", "grid", "lists", "sweep"]
    );
}

/// Above 96 objects the model never names the brute force: the run starts on a box structure
/// and the race brings the brute force in where it measures that its build pays back. Either
/// way the log is the brute force's own, bit for bit, on the family's long flights and
/// crowds.
#[test]
fn above_96_objects_the_race_weighs_the_brute_force_and_the_log_is_its_own() {
    let mut checked = Vec::new();
    for case in choice_family(&[100, 250], 3) {
        let scene = &case.scene;
        if scene.periodic.is_some() || scene.walls.is_some() {
            continue;
        }
        let pick = Structure::for_scene(scene);
        assert_ne!(pick, Structure::BruteForce, "{}", case.kind);
        if !matches!(case.kind, "long-horizon" | "dense-gas" | "gas" | "rolling") {
            continue;
        }
        checked.push(case.kind);
        let reference = run_scene(scene, Some(Structure::BruteForce)).unwrap();
        let got = run_scene(scene, None).unwrap();
        assert!(!reference.events.is_empty(), "{}: no contacts", case.kind);
        assert_eq!(got.events, reference.events, "{}", case.kind);
    }
    assert!(checked.len() >= 4, "{checked:?}");
}
