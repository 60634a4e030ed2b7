//! Every flight structure, and the world's default one, against the brute force: objects
//! come in batches while the world runs, their sizes spread past the rule's bounds (for
//! the default: the brute force for the first few dozen, then the grid, the sweep), new
//! plans teleport objects and objects leave; the log must be the brute force's
//! bit for bit, and the world and structure invariants hold after every event. The default
//! with its race (trials of other structures as the world is advanced) keeps the same log.

use kinetic_collide::{FlightPlan, ObjectId, Response, Structure, Vec3, World, WorldKind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Runs both worlds to `t`, validating the audited one after every event.
fn run_to(audited: &mut World, reference: &mut World, t: f64) {
    while audited.step(t).expect("step").is_some() {
        audited.validate().expect("valid after every event");
    }
    audited.advance_to(t).expect("advance");
    reference.advance_to(t).expect("advance");
}

fn random_ball(rng: &mut ChaCha8Rng, radius: f64, now: f64) -> (f64, FlightPlan) {
    let p = Vec3::new(
        rng.random_range(-12.0..12.0),
        rng.random_range(-12.0..12.0),
        rng.random_range(-12.0..12.0),
    );
    let v = Vec3::new(
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
        rng.random_range(-1.0..1.0),
    );
    (radius, FlightPlan::linear(p, v).starting_at(now))
}

/// The world's default holds the brute force up to this many objects (the registry's bound
/// for elastic scenes, where the brute force stops paying).
const BRUTE_FORCE_UP_TO: usize = 32;

/// A world with the structure under test, by name ("auto": the default's adaptive structure,
/// without the race, whose trials depend on the clock).
fn world_with(name: &str, kind: WorldKind) -> World {
    match name {
        "auto" => World::new(kind).without_racing(),
        "raced" => World::new(kind),
        _ => {
            let s = Structure::from_name(name).expect("a structure of this test");
            World::with_structure(kind, Response::None, None, s).expect("a world")
        }
    }
}

fn scenario(seed: u64, kind: WorldKind, name: &str) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut auto = world_with(name, kind);
    let mut brute = world_with("brute-force", kind);
    let mut ids: Vec<ObjectId> = Vec::new();
    // Radii of each batch: alike (grid), then a spread of 80x to 120x (grid still), then
    // over 10^5x (sweep).
    let batches: [(usize, f64, f64, Structure); 3] = [
        (40, 0.2, 0.25, Structure::Grid),
        (3, 20.0, 24.0, Structure::Grid),
        (2, 25_000.0, 27_500.0, Structure::Sweep),
    ];
    let mut t = 0.0;
    for (k, &(count, lo, hi, want)) in batches.iter().enumerate() {
        let balls: Vec<(f64, FlightPlan)> = (0..count)
            .map(|_| {
                let r = rng.random_range(lo..hi);
                random_ball(&mut rng, r, t)
            })
            .collect();
        // The first batch comes one by one, the others together.
        if k == 0 {
            for &(r, plan) in &balls {
                let a = auto.add_ball(r, plan).expect("add");
                let b = brute.add_ball(r, plan).expect("add");
                assert_eq!(a, b);
                ids.push(a);
                if name == "auto" {
                    // The brute force for a few dozen objects, then the rule's structure.
                    let want = if ids.len() <= BRUTE_FORCE_UP_TO {
                        "brute-force"
                    } else {
                        want.name()
                    };
                    assert_eq!(auto.structure_name(), want, "{} objects", ids.len());
                }
            }
        } else {
            let a = auto.add_balls(balls.iter().copied()).expect("add");
            let b = brute.add_balls(balls.iter().copied()).expect("add");
            assert_eq!(a, b);
            ids.extend(a);
        }
        auto.validate().expect("valid after adding");
        if name == "auto" {
            assert_eq!(auto.structure_name(), want.name(), "batch {k}");
        }
        for _ in 0..4 {
            t += 2.5;
            run_to(&mut auto, &mut brute, t);
            // A few new plans and a removal.
            for _ in 0..3 {
                let id = ids[rng.random_range(0..ids.len())];
                if let Some(body) = auto.body(id) {
                    let (_, plan) = random_ball(&mut rng, body.shape.outer_radius(), t);
                    auto.set_plan(id, plan).expect("replan");
                    brute.set_plan(id, plan).expect("replan");
                }
            }
            let id = ids.swap_remove(rng.random_range(0..ids.len()));
            auto.remove(id).expect("remove");
            brute.remove(id).expect("remove");
            // A new plan may teleport: what it starts is processed at once, at `t`.
            run_to(&mut auto, &mut brute, t);
            auto.validate()
                .expect("valid after new plans and a removal");
        }
    }
    if name == "auto" {
        let counters = auto.structure_counters();
        let switches = counters.iter().find(|(n, _)| *n == "switches");
        // Brute force, grid, sweep.
        assert_eq!(switches.map(|s| s.1), Some(2.0), "{kind:?}");
    }
    let (a, b) = (auto.drain_events(), brute.drain_events());
    assert!(a.len() > 20, "a run with contacts: {}", a.len());
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(
            (x.a, x.b, x.kind, x.time.to_bits()),
            (y.a, y.b, y.kind, y.time.to_bits()),
            "{name}, seed {seed}"
        );
    }
}

#[test]
fn auto_switches_as_sizes_spread_and_matches_the_brute_force_bit_for_bit() {
    for seed in 0..4 {
        scenario(seed, WorldKind::Free, "auto");
    }
}

#[test]
fn auto_on_the_plane_matches_the_brute_force_bit_for_bit() {
    for seed in 10..12 {
        scenario(seed, WorldKind::Plane, "auto");
    }
}

#[test]
fn the_raced_default_takes_batches_teleports_and_removals_bit_for_bit() {
    for seed in 1..=2 {
        scenario(seed, WorldKind::Free, "raced");
        scenario(seed, WorldKind::Plane, "raced");
    }
}

#[test]
fn every_flight_structure_takes_teleports_and_spread_sizes_bit_for_bit() {
    for name in ["sweep", "grid", "loose-grid", "guards"] {
        for seed in 20..22 {
            scenario(seed, WorldKind::Free, name);
        }
    }
    for name in ["sweep", "grid", "loose-grid"] {
        scenario(30, WorldKind::Plane, name);
    }
}

/// `World::new` chooses by measuring: advanced call by call as a game would, it tries other
/// structures on slices of its own time (each trial a hand-over and back, or a move to the
/// faster), and its log is still that of a world on a named structure, bit for bit.
#[test]
fn the_default_world_races_and_keeps_the_log() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut raced = World::new(WorldKind::Free);
    let mut named = world_with("grid", WorldKind::Free);
    for k in 0..1500 {
        // Dust of radii 0.05 to 2, and three giants.
        let radius = if k % 500 == 0 {
            8.0
        } else {
            0.05 * 40f64.powf(rng.random::<f64>())
        };
        let (r, plan) = random_ball(&mut rng, radius, 0.0);
        raced.add_ball(r, plan).unwrap();
        named.add_ball(r, plan).unwrap();
    }
    // Long enough for the trials' builds to fit a tenth of the run so far.
    for step in 1..=800 {
        let t = step as f64 * 0.05;
        raced.advance_to(t).unwrap();
        named.advance_to(t).unwrap();
    }
    raced.validate().unwrap();
    let race = raced.race();
    assert!(!race.is_empty());
    assert_eq!(race[0].from, 0.0);
    assert!(race.windows(2).all(|w| w[0].to == w[1].from), "{race:?}");
    assert_eq!(race.last().unwrap().to, 40.0);
    let tried: std::collections::BTreeSet<&str> = race.iter().map(|s| s.structure.name()).collect();
    assert!(tried.len() >= 2, "nothing tried: {race:?}");
    let (a, b) = (raced.drain_events(), named.drain_events());
    assert!(a.len() > 1000, "{} events", a.len());
    assert!(a == b, "the raced world's log differs from the grid's");
}
