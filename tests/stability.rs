//! The stability suite: one named test per case where collision detection methods break
//! (`kinetic_scenes::families::Case`). Each runs every free-flight structure with
//! `World::validate` after every event against the brute force, and checks the case's own
//! claim; where it shows how a time-stepped method fails, it asserts that too.

use kinetic_collide::Structure;
use kinetic_collide::run::{build_world, run_scene};
use kinetic_collide::scene::Scene;
use kinetic_collide::{ContactEvent, ContactKind, World, WorldError};
use kinetic_collide_cli::compare::score;
use kinetic_collide_cli::time_stepped::run_stepped;
use kinetic_scenes::families::{Case, Family};

use kinetic_scenes::audit::{assert_same_contacts, run_audited as audited};

const FREE: [Structure; 4] = [
    Structure::Sweep,
    Structure::Guards,
    Structure::Grid,
    Structure::LooseGrid,
];

/// Every structure gives the brute force's contacts (per pair the same kinds in the same
/// order, times within the scene format's 1e-7 * max(1, |t|)); returns the brute force's log.
fn same_log_everywhere(scene: &Scene) -> Vec<ContactEvent> {
    let reference = audited(scene, Structure::BruteForce);
    for s in FREE {
        assert_same_contacts(&reference, &audited(scene, s), &format!("{s:?}"));
    }
    reference
}

#[test]
fn simultaneous_events_on_a_lattice() {
    let scene = Case::Lattice.scene();
    let log = same_log_everywhere(&scene);
    // Integer positions and speeds: every structure gives the very same log.
    for s in FREE {
        assert_eq!(audited(&scene, s), log, "{s:?}");
    }
    // 125 pairs touch at exactly t = 1 and part at exactly t = 3, logged by (a, b).
    assert_eq!(log.len(), 250);
    for (half, (t, kind)) in [(1.0, ContactKind::Begin), (3.0, ContactKind::End)]
        .into_iter()
        .enumerate()
    {
        let part = &log[125 * half..125 * (half + 1)];
        assert!(part.iter().all(|e| e.time == t && e.kind == kind));
        assert!(part.windows(2).all(|w| (w[0].a, w[0].b) < (w[1].a, w[1].b)));
    }
}

#[test]
fn grazes() {
    let scene = Case::Grazes.scene();
    let log = same_log_everywhere(&scene);
    // Objects 0..40 graze exactly, 40..80 miss by 1e-9, 80..120 overlap by 1e-9.
    let of = |lo: u32, hi: u32| -> Vec<&ContactEvent> {
        log.iter().filter(|e| e.a.0 >= lo && e.b.0 < hi).collect()
    };
    // Each pair's events, in order.
    let pairs = |events: Vec<&ContactEvent>| {
        let mut by: std::collections::BTreeMap<(u32, u32), Vec<(ContactKind, f64)>> =
            Default::default();
        for e in events {
            by.entry((e.a.0, e.b.0)).or_default().push((e.kind, e.time));
        }
        by
    };
    let exact = pairs(of(0, 40));
    assert_eq!(exact.len(), 20, "{exact:?}");
    for (pair, ev) in &exact {
        // A begin and an end at the same instant, at 2.0123 within the format's accuracy.
        assert_eq!(ev.len(), 2, "{pair:?}: {ev:?}");
        assert_eq!((ev[0].0, ev[1].0), (ContactKind::Begin, ContactKind::End));
        assert_eq!(ev[0].1, ev[1].1);
        assert!((ev[0].1 - 2.0123).abs() < 1e-7, "{pair:?}: {ev:?}");
    }
    assert!(of(40, 80).is_empty(), "a miss by 1e-9 touched");
    let near = pairs(of(80, 120));
    assert_eq!(near.len(), 20);
    for (pair, ev) in &near {
        // Overlapping by 1e-9 for 2 sqrt(2e-9) = 8.94e-5 around t = 2.0123.
        assert_eq!(ev.len(), 2, "{pair:?}: {ev:?}");
        let length = ev[1].1 - ev[0].1;
        assert!(
            (length - 2.0 * 2e-9f64.sqrt()).abs() < 1e-3 * length,
            "{pair:?}: {ev:?}"
        );
    }
    // Time steps of 1/1000 are too coarse to see the 9e-5-long contacts: all are missed.
    let stepped = run_stepped(&scene, 1e-3).unwrap();
    let acc = score(&log, &stepped.events, scene.horizon, 1e-3);
    assert_eq!(acc.missed(), 40, "{acc:?}");
}

#[test]
fn objects_starting_in_contact() {
    let scene = Case::StartInContact.scene();
    let log = same_log_everywhere(&scene);
    let begins: Vec<_> = log
        .iter()
        .filter(|e| e.kind == ContactKind::Begin)
        .collect();
    // Every one of the 40 pairs begins at t = 0 (the scene format's rule), once.
    assert_eq!(begins.len(), 40);
    assert!(begins.iter().all(|e| e.time == 0.0));
    // Those touching exactly and parting end at once; those overlapping, or nested, end
    // later; those moving together never end.
    let ends_at_zero = log
        .iter()
        .filter(|e| e.kind == ContactKind::End && e.time == 0.0)
        .count();
    assert_eq!(ends_at_zero, 10);
    let ends = log.iter().filter(|e| e.kind == ContactKind::End).count();
    assert_eq!(ends, 30);
}

/// The log of `scene` and of the same scene moved back by `shift`: same pairs and kinds,
/// times within `tolerance`.
fn offset_case(case: Case, shift: f64, tolerance: f64) {
    let shifted = case.scene();
    let log = same_log_everywhere(&shifted);
    let mut plain = shifted.clone();
    for o in &mut plain.objects {
        o.position -= glam::DVec3::splat(shift);
    }
    let want = run_scene(&plain, Some(Structure::BruteForce))
        .unwrap()
        .events;
    assert_eq!(log.len(), want.len());
    let key = |e: &ContactEvent| (e.a, e.b, e.kind);
    let mut got: Vec<_> = log.iter().map(|e| (key(e), e.time)).collect();
    let mut exp: Vec<_> = want.iter().map(|e| (key(e), e.time)).collect();
    got.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    exp.sort_by(|x, y| x.0.cmp(&y.0).then(x.1.total_cmp(&y.1)));
    for (g, e) in got.iter().zip(&exp) {
        assert_eq!(g.0, e.0);
        assert!((g.1 - e.1).abs() <= tolerance, "{g:?} vs {e:?}");
    }
}

#[test]
fn coordinates_offset_by_1e6() {
    // Positions keep 1e-10 absolute there: times agree to 1e-7 (the format's accuracy).
    offset_case(Case::Offset1e6, 1e6, 1e-7);
}

#[test]
fn coordinates_offset_by_1e9() {
    // Positions keep only 1.2e-7 absolute at 1e9, and contact times no better than that
    // over the relative speed: every contact is still found, in the same order per pair.
    offset_case(Case::Offset1e9, 1e9, 1e-4);
}

#[test]
fn radii_1e_minus_6_next_to_1e6() {
    let scene = Case::Radii.scene();
    let log = same_log_everywhere(&scene);
    // 20 tiny balls land on the giant at t = 1; 20 tiny pairs meet each other at t = 2.
    let begins: Vec<_> = log
        .iter()
        .filter(|e| e.kind == ContactKind::Begin)
        .collect();
    assert_eq!(begins.len(), 40, "{log:?}");
    let on_giant = begins.iter().filter(|e| e.a.0 == 0).count();
    assert_eq!(on_giant, 20);
    for e in begins {
        let when = if e.a.0 == 0 { 1.0 } else { 2.0 };
        assert!((e.time - when).abs() < 1e-3, "{e:?}");
    }
}

#[test]
fn speeds_of_1e6() {
    let scene = Case::Speed1e6.scene();
    let log = same_log_everywhere(&scene);
    // Each of 5 bullets passes 40 balls: 200 contacts, each 1e-6 long.
    let begins = log.iter().filter(|e| e.kind == ContactKind::Begin).count();
    assert_eq!(begins, 200);
    // Sampling every 1e-3 (the time between two balls) sees none of them.
    let stepped = run_stepped(&scene, 1e-3).unwrap();
    let acc = score(&log, &stepped.events, scene.horizon, 1e-3);
    assert_eq!(acc.missed(), 200, "{acc:?}");
}

#[test]
fn long_run_of_1e7_events_without_drift() {
    // The marbles family's free cousin: an elastic gas in walls, run past 1e7 events. At
    // sampled times, a brute force started from the long run's state must give the same
    // collisions over the next window, so nothing has drifted.
    let mut scene = Family::Gas.scene(400, 7);
    scene.response = kinetic_collide::Response::Elastic;
    scene.walls = Some(kinetic_collide::Walls {
        min: glam::DVec3::ZERO,
        max: glam::DVec3::splat(22.0),
    });
    for (i, o) in scene.objects.iter_mut().enumerate() {
        // Lay the balls out on a lattice inside the walls, apart.
        let cell = glam::DVec3::new((i % 8) as f64, ((i / 8) % 8) as f64, (i / 64) as f64);
        o.position = cell * 2.6 + glam::DVec3::splat(1.5);
    }
    let (mut world, _) = build_world(&scene, Some(Structure::Sweep)).unwrap();
    let mut t = 0.0;
    let mut k = 0u32;
    let mut windows = 0;
    let mut total = 0u64;
    while world.stats().events_total() < 10_000_000 {
        t += 2.0;
        k += 1;
        world.advance_to(t).unwrap();
        world.drain_events();
        // A window of 0.5 after t, checked against a fresh brute force every 10 units.
        if k.is_multiple_of(5) {
            let mut fresh = World::with_structure(
                scene.world,
                scene.response,
                scene.walls,
                Structure::BruteForce,
            )
            .unwrap();
            fresh.advance_to(t).unwrap();
            fresh
                .add_objects(
                    world
                        .bodies()
                        .iter()
                        .flatten()
                        .map(|b| (b.shape.clone(), b.plan)),
                )
                .unwrap();
            world.advance_to(t + 0.5).unwrap();
            fresh.advance_to(t + 0.5).unwrap();
            let (a, b) = (world.drain_events(), fresh.drain_events());
            assert!(!a.is_empty(), "no collisions in the window at {t}");
            assert_eq!(a.len(), b.len(), "window at {t}");
            for (x, y) in a.iter().zip(&b) {
                assert_eq!((x.a, x.b), (y.a, y.b), "window at {t}");
                assert!((x.time - y.time).abs() <= 1e-7 * x.time, "{x:?} vs {y:?}");
            }
            windows += 1;
            t += 0.5;
        }
        total = world.stats().events_total();
    }
    assert!(
        total >= 10_000_000 && windows >= 3,
        "{total} events, {windows} windows"
    );
}

#[test]
fn zeno_trap_ends_with_bounded_work() {
    // A small elastic ball between two giants closing in: it bounces ever faster until it
    // has pushed them apart. Every structure gives the brute force's log, the run ends (no
    // hang) with a bounded number of collisions, and the giants leave moving apart.
    let scene = Case::Zeno.scene();
    let reference = run_scene(&scene, Some(Structure::BruteForce));
    match &reference {
        Ok(out) => {
            assert!(out.events.len() < 1_000_000, "{}", out.events.len());
            for s in FREE {
                let got = run_scene(&scene, Some(s)).unwrap();
                assert_eq!(got.events, out.events, "{s:?}");
            }
            let (mut world, _) = build_world(&scene, Some(Structure::Sweep)).unwrap();
            world.advance_to(scene.horizon).unwrap();
            let v = |i: usize| world.bodies()[i].as_ref().unwrap().plan.velocity_at(2.0).x;
            assert!(v(0) < 0.0 && v(2) > 0.0, "giants at {} and {}", v(0), v(2));
        }
        // Or a clear error naming the Zeno configuration, with the work done kept.
        Err(e) => {
            let kinetic_collide::run::RunError::Stopped {
                source, partial, ..
            } = e
            else {
                panic!("{e}");
            };
            assert!(matches!(source, WorldError::Zeno { .. }), "{source}");
            assert!(!partial.events.is_empty());
        }
    }
}
