//! Helpers the tests share: runs audited after every event, and contact comparisons.

use kinetic_collide::Structure;
use kinetic_collide::run::build_world;
use kinetic_collide::scene::Scene;
use kinetic_collide::{ContactEvent, ContactKind};
use std::collections::BTreeMap;

/// Runs `scene` with `structure`, auditing the world after every event.
pub fn run_audited(scene: &Scene, structure: Structure) -> Vec<ContactEvent> {
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
pub fn by_pair(events: &[ContactEvent]) -> BTreeMap<(u32, u32), Vec<(ContactKind, f64)>> {
    let mut out: BTreeMap<_, Vec<_>> = BTreeMap::new();
    for e in events {
        out.entry((e.a.0, e.b.0))
            .or_default()
            .push((e.kind, e.time));
    }
    out
}

/// Same pairs, same kinds in the same order per pair, times within 1e-7 relative.
pub fn assert_same_contacts(reference: &[ContactEvent], got: &[ContactEvent], what: &str) {
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
