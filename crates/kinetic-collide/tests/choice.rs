//! The default choice on the choice family: it always names a structure that applies to the
//! scene, follows the documented rule, and gives the brute force's contacts.

use kinetic_collide::kds::{
    GRID_SPREAD, LOOSE_SPREAD, RESTING_CROSSINGS, RESTING_GRID_MAX, brute_force_pays,
    grid_crossing_share, loose_spread, sweep_crossings,
};
use kinetic_collide::run::{StructureName, choose_structure, run_scene};
use kinetic_collide::structures::{contacts, crossings, heavy_pairs, passes, radii};
use kinetic_collide::{Response, WorldKind};
use kinetic_scenes::audit::assert_same_contacts;
use kinetic_scenes::choice::{KINDS, choice_family};

#[test]
fn the_default_applies_follows_the_rule_and_matches_the_brute_force() {
    let cases = choice_family(&[60, 250], 7);
    assert_eq!(cases.len(), 2 * KINDS.len());
    let mut picked = std::collections::BTreeSet::new();
    for case in &cases {
        let scene = &case.scene;
        let pick = choose_structure(scene);
        assert!(pick.applies_to(scene), "{}: {pick:?}", case.kind);
        let spread = scene.size_ratio();
        let heavy = heavy_pairs(scene);
        let elastic = scene.response == Response::Elastic;
        let n = scene.objects.len();
        let boxes = if crossings(scene) <= RESTING_CROSSINGS * n as f64
            && n <= RESTING_GRID_MAX
            && spread <= GRID_SPREAD
        {
            StructureName::Grid
        } else if spread <= LOOSE_SPREAD
            && (scene.world == WorldKind::Plane || spread <= loose_spread(n))
        {
            StructureName::LooseGrid
        } else if spread <= GRID_SPREAD && scene.world == WorldKind::Free {
            StructureName::Grid
        } else {
            StructureName::Sweep
        };
        // The grid's crossings are of its cells, wider than its objects where sizes spread.
        let cells = match boxes {
            StructureName::Grid => crossings(scene) * grid_crossing_share(radii(scene)),
            // The sweep's swaps: box ends passed, whatever the objects' sizes.
            StructureName::Sweep => sweep_crossings(passes(scene)),
            _ => crossings(scene),
        };
        let want = if StructureName::Cells.applies_to(scene) {
            StructureName::Cells
        } else if brute_force_pays(n, cells, contacts(scene), heavy, elastic) {
            StructureName::BruteForce
        } else {
            boxes
        };
        assert_eq!(pick, want, "{} at {n} (spread {spread})", case.kind);
        picked.insert(pick.as_str());
        let reference = run_scene(scene, Some(StructureName::BruteForce)).unwrap();
        let got = run_scene(scene, None).unwrap();
        assert_eq!(got.structure, pick);
        assert_same_contacts(&reference.events, &got.events, case.kind);
    }
    // The family exercises every branch of the rule.
    assert_eq!(
        picked.into_iter().collect::<Vec<_>>(),
        ["brute-force", "cells", "grid", "loose-grid", "sweep"]
    );
}

#[test]
fn the_sweep_pays_for_box_ends_passed_whatever_the_sizes() {
    use kinetic_collide::glam::DVec3;
    use kinetic_collide::scene::{Scene, SceneObject};
    // Ten balls of diameter 1 a unit apart along x: their starts and a mean diameter span 10,
    // so 2 ends a unit. One crosses 3 units along x in the horizon: 6 ends passed.
    let line = |radius: f64| Scene {
        world: WorldKind::Free,
        horizon: 1.0,
        response: Response::None,
        walls: None,
        periodic: None,
        objects: (0..10)
            .map(|i| {
                let v = if i == 0 { 3.0 } else { 0.0 };
                SceneObject::ball(
                    radius,
                    DVec3::new(i as f64, 0.0, 0.0),
                    DVec3::new(v, 0.0, 0.0),
                )
            })
            .collect(),
    };
    let scene = line(0.5);
    assert_eq!(passes(&scene), 3.0 * 20.0 / 10.0);
    // Balls a thousandth the size cross their own size hundreds of times more often (to a cap
    // of 1000 for each), but pass about as many box ends.
    let tiny = line(0.0005);
    assert!(crossings(&tiny) > 300.0 * crossings(&scene));
    assert!(passes(&tiny) < 1.2 * passes(&scene));
}
