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
        // The run starts on the pick (and may race on from there), or, where the pick is the
        // brute force and its build was measured to cost more than a box structure's, on that
        // box structure.
        let first = got.race.first().map_or(got.structure, |leg| leg.structure);
        assert!(
            first == pick || pick == Structure::BruteForce,
            "{kind}: started on {first:?}, picked {pick:?}"
        );
        assert_same_contacts(&reference.events, &got.events, kind);
    }
    // The family exercises every branch of the rule.
    assert_eq!(
        picked.into_iter().collect::<Vec<_>>(),
        [
            "brute-force",
            "cells",
            "grid",
            "lists",
            "loose-grid",
            "sweep"
        ]
    );
}

/// Where the model picks the brute force for more than 64 objects, a run measures it as it
/// builds it, in batches, and may leave it for a box structure after the second: either way
/// the log is the brute force's own, bit for bit.
#[test]
fn a_brute_force_measured_as_it_is_built_gives_its_own_log() {
    let mut measured = Vec::new();
    for case in choice_family(&[100, 250], 3) {
        let scene = &case.scene;
        if Structure::for_scene(scene) != Structure::BruteForce || scene.objects.len() <= 64 {
            continue;
        }
        measured.push(case.kind);
        let reference = run_scene(scene, Some(Structure::BruteForce)).unwrap();
        let got = run_scene(scene, None).unwrap();
        assert!(!reference.events.is_empty(), "{}: no contacts", case.kind);
        assert_eq!(got.events, reference.events, "{}", case.kind);
    }
    assert!(measured.len() >= 2, "{measured:?}");
}
