//! The periodic structure against the world's brute force (where no image is in reach) and
//! against an exhaustive periodic reference (every pair, every nearby image), event by event,
//! with `validate()` after every event.

use super::event::{exchange, wrapped};
use super::predict::pair_due;
use super::*;
use kinetic_core::{BruteForce, ContactKind, FlightPlan, ObjectId, Response, Simulator, WorldKind};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// `n` non-overlapping spheres of radius in `radii` with centres in `[lo, hi]^3`, speeds up to
/// about `speed`.
fn random_spheres(
    seed: u64,
    n: usize,
    radii: (Real, Real),
    lo: Real,
    hi: Real,
    speed: Real,
) -> Vec<(Real, FlightPlan)> {
    spheres_within(
        seed,
        n,
        radii,
        (Vec3::splat(lo), Vec3::splat(hi)),
        0.0,
        speed,
    )
}

/// `n` non-overlapping spheres of radius in `radii` whose centres lie in the box from `lo` to
/// `hi` shrunk by `inset` times their radius, speeds up to about `speed`.
pub(super) fn spheres_within(
    seed: u64,
    n: usize,
    radii: (Real, Real),
    (lo, hi): (Vec3, Vec3),
    inset: Real,
    speed: Real,
) -> Vec<(Real, FlightPlan)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out: Vec<(Real, FlightPlan)> = Vec::new();
    while out.len() < n {
        let r = rng.random_range(radii.0..=radii.1);
        let m = inset * r;
        let p = Vec3::new(
            rng.random_range(lo.x + m..hi.x - m),
            rng.random_range(lo.y + m..hi.y - m),
            rng.random_range(lo.z + m..hi.z - m),
        );
        let v = Vec3::new(
            rng.random_range(-speed..speed),
            rng.random_range(-speed..speed),
            rng.random_range(-speed..speed),
        );
        if out
            .iter()
            .all(|(q, plan)| (plan.position - p).length() > r + q + 1e-3)
        {
            out.push((r, FlightPlan::linear(p, v)));
        }
    }
    out
}

/// The sum of squared speeds: twice the kinetic energy, for spheres of equal mass.
fn energy(gas: &ListedSpheres) -> Real {
    gas.motion.iter().map(|m| m.velocity.length_squared()).sum()
}

/// Runs `gas` to `t`, validating after every event.
pub(super) fn run(gas: &mut ListedSpheres, t: Real) -> Vec<ContactEvent> {
    gas.validate().unwrap();
    while gas.step(t).unwrap() {
        gas.validate()
            .unwrap_or_else(|e| panic!("at {}: {e}", gas.now()));
    }
    gas.advance_to(t).unwrap();
    gas.drain_events()
}

#[test]
fn a_box_too_wide_to_wrap_gives_the_worlds_log() {
    for seed in 0..4 {
        let spheres = random_spheres(seed, 80, (0.3, 0.6), 0.0, 7.0, 1.0);
        let cell = PeriodicBox {
            min: Vec3::splat(-100.0),
            max: Vec3::splat(100.0),
        };
        let mut gas = ListedSpheres::periodic(cell, &spheres).unwrap();
        let mut world = Simulator::with_structure(
            WorldKind::Free,
            Response::Elastic,
            None,
            Box::new(BruteForce::new()),
        )
        .unwrap();
        for (r, plan) in &spheres {
            world.add_ball(*r, *plan).unwrap();
        }
        world.advance_to(20.0).unwrap();
        let expected = world.drain_events();
        let got = run(&mut gas, 20.0);
        assert!(
            expected.len() > 30,
            "seed {seed}: {} events",
            expected.len()
        );
        assert_eq!(got, expected, "seed {seed}");
    }
}

/// The exhaustive periodic reference: every pair, through each of the 27 images around its
/// nearest, the earliest failure (ties by pair), the same exchange, starts wrapped the same way.
fn reference(cell: PeriodicBox, spheres: &[(Real, FlightPlan)], until: Real) -> Vec<ContactEvent> {
    let side = cell.max - cell.min;
    let period = Period {
        min: cell.min,
        side,
        inv_side: Vec3::ONE / side,
        half_side: side * 0.5,
    };
    let mut m: Vec<Motion> = spheres.iter().map(|(r, p)| Motion::of(p, *r)).collect();
    let mut now = 0.0;
    let mut log = Vec::new();
    loop {
        let mut best: Option<(Real, u64, usize, usize, Vec3)> = None;
        for a in 0..m.len() {
            for b in a + 1..m.len() {
                let d = m[a].at(now) - m[b].at(now);
                let near = (d / side).round();
                for dx in -1..=1 {
                    for dy in -1..=1 {
                        for dz in -1..=1 {
                            let s = (near + Vec3::new(dx as Real, dy as Real, dz as Real)) * side;
                            let d_now = (m[a].at(now) - m[b].at(now)) - s;
                            if let Some((t, false)) =
                                pair_due(&m[a], &m[b], s, d_now, now, None, Real::INFINITY)
                            {
                                let key = ((a as u64) << 32) | b as u64;
                                if best.is_none_or(|(bt, bk, ..)| (t, key) < (bt, bk)) {
                                    best = Some((t, key, a, b, s));
                                }
                            }
                        }
                    }
                }
            }
        }
        let Some((t, _, a, b, s)) = best else { break };
        if t > until {
            break;
        }
        now = t;
        let (va, vb, _) = exchange(&m[a], &m[b], s, now).expect("approaching");
        for (i, v) in [(a, va), (b, vb)] {
            m[i].position = wrapped(&period, m[i].at(now)).0;
            m[i].t0 = now;
            m[i].velocity = v;
        }
        log.push(ContactEvent {
            time: now,
            a: ObjectId(a as u32),
            b: ObjectId(b as u32),
            kind: ContactKind::Begin,
        });
    }
    log
}

#[test]
fn images_collide_as_the_exhaustive_reference_says() {
    for (seed, n, side) in [(1, 30, 6.0), (2, 40, 7.0), (3, 20, 3.2), (4, 50, 9.0)] {
        let spheres = random_spheres(seed, n, (0.3, 0.5), 0.0, side, 2.0);
        let cell = PeriodicBox {
            min: Vec3::ZERO,
            max: Vec3::splat(side),
        };
        let mut gas = ListedSpheres::periodic(cell, &spheres).unwrap();
        let got = run(&mut gas, 12.0);
        let expected = reference(cell, &spheres, 12.0);
        assert!(
            expected.len() > 100,
            "seed {seed}: {} events",
            expected.len()
        );
        assert_eq!(got, expected, "seed {seed}");
        assert!(
            gas.stats()
                .events_by_kind
                .get("shell")
                .copied()
                .unwrap_or(0)
                > 0
        );
    }
}

/// 300 spheres of radius 0.5 in a periodic box of side 12, at random from `seed`.
fn thin_gas(seed: u64) -> ListedSpheres {
    let side = 12.0;
    let spheres = random_spheres(seed, 300, (0.5, 0.5), 0.0, side, 1.0);
    let cell = PeriodicBox {
        min: Vec3::ZERO,
        max: Vec3::splat(side),
    };
    ListedSpheres::periodic(cell, &spheres).unwrap()
}

#[test]
fn energy_and_momentum_are_kept_and_the_bulk_is_sane() {
    let mut gas = thin_gas(9);
    let momentum = |g: &ListedSpheres| -> Vec3 { g.motion.iter().map(|m| m.velocity).sum() };
    let (e0, p0) = (energy(&gas), momentum(&gas));
    gas.advance_to(30.0).unwrap();
    gas.validate().unwrap();
    assert!((energy(&gas) - e0).abs() < 1e-9 * e0);
    assert!((momentum(&gas) - p0).length() < 1e-9 * e0.sqrt());
    let bulk = gas.bulk();
    assert!(bulk.collision_rate > 0.1, "{bulk:?}");
    assert!(bulk.compressibility > 1.0, "{bulk:?}");
}

#[test]
fn bad_boxes_and_spheres_are_refused() {
    let cell = PeriodicBox {
        min: Vec3::ZERO,
        max: Vec3::splat(2.0),
    };
    let one = [(0.5, FlightPlan::at_rest(Vec3::ONE))];
    let e = ListedSpheres::periodic(cell, &one).unwrap_err().to_string();
    assert!(e.contains("at least"), "{e}");
    let cell = PeriodicBox {
        min: Vec3::ZERO,
        max: Vec3::splat(10.0),
    };
    let outside = [(0.5, FlightPlan::at_rest(Vec3::splat(11.0)))];
    assert!(ListedSpheres::periodic(cell, &outside).is_err());
    let falling = [(
        0.5,
        FlightPlan::accelerated(Vec3::ONE, Vec3::ZERO, Vec3::new(0.0, 0.0, -9.8)),
    )];
    assert!(ListedSpheres::periodic(cell, &falling).is_err());
    let empty = ListedSpheres::periodic(cell, &[]).unwrap();
    assert!(empty.is_empty());
}

/// `k^3` spheres of diameter 1 on a cubic lattice at `packing` in a cube from the origin, with
/// random velocities from `seed`: the cube's side and the spheres.
pub(super) fn lattice(k: usize, packing: Real, seed: u64) -> (Real, Vec<(Real, FlightPlan)>) {
    let spacing = (std::f64::consts::PI / 6.0 / packing).cbrt();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut spheres = Vec::new();
    for x in 0..k {
        for y in 0..k {
            for z in 0..k {
                let p = (Vec3::new(x as Real, y as Real, z as Real) + 0.5) * spacing;
                let v = Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                spheres.push((0.5, FlightPlan::linear(p, v)));
            }
        }
    }
    (spacing * k as Real, spheres)
}

/// [`lattice`] at packing 0.45 in a periodic box: a dense fluid once the lattice melts.
fn dense_lattice(k: usize, seed: u64) -> ListedSpheres {
    let (side, spheres) = lattice(k, 0.45, seed);
    let cell = PeriodicBox {
        min: Vec3::ZERO,
        max: Vec3::splat(side),
    };
    ListedSpheres::periodic(cell, &spheres).unwrap()
}

/// A dense fluid (a lattice at packing 0.45 that melts): tens of thousands of collisions,
/// stale events and shell crossings, every prediction checked against every pair's (the
/// unit-test build checks each one) and the structure validated along the way.
#[test]
fn a_dense_fluid_keeps_its_invariants_and_its_energy() {
    let mut gas = dense_lattice(6, 5);
    let e0 = energy(&gas);
    for step in 1..=40 {
        gas.advance_to(step as Real * 0.5).unwrap();
        gas.validate().unwrap();
    }
    let stats = gas.stats();
    let count = |kind: &str| stats.events_by_kind.get(kind).copied().unwrap_or(0);
    assert!(count("collision") > 20_000, "{:?}", stats.events_by_kind);
    assert!(count("stale") > 1_000, "{:?}", stats.events_by_kind);
    assert!(count("shell") > 1_000, "{:?}", stats.events_by_kind);
    assert!((energy(&gas) - e0).abs() < 1e-9 * e0);
}

/// Dense fluids with every listed pair's cover checked after every event (and the whole
/// structure every hundred): stale events take runners-up, and once those are spent the
/// shell crossing only where no pair before it was left out.
#[test]
fn stale_events_take_runners_up_and_every_pair_stays_covered() {
    let mut taken = [0.0; 2];
    for seed in 0..6 {
        let mut gas = dense_lattice(6, seed);
        let mut events = 0u64;
        while gas.step(8.0).unwrap() {
            gas.validate_cover()
                .unwrap_or_else(|e| panic!("seed {seed} at {}: {e}", gas.now()));
            events += 1;
            if events.is_multiple_of(100) {
                gas.validate().unwrap();
            }
        }
        let counters = gas.counters();
        for (j, name) in ["stale_to_runner_up", "stale_to_shell"].iter().enumerate() {
            taken[j] += counters.iter().find(|c| c.0 == *name).unwrap().1;
        }
    }
    assert!(taken[0] > 1000.0 && taken[1] > 10.0, "{taken:?}");
}

/// A sphere that crosses its shell re-centres ahead of itself along its flight, no further
/// than half its shell, once the fluid has a mean free time; the run stays whole.
#[test]
fn shell_crossings_re_centre_ahead_along_the_flight() {
    let mut gas = thin_gas(4);
    // Before any collision there is no free time: the centre is where the sphere is.
    assert_eq!(gas.new_centre(0), gas.motion[0].at(gas.now()));
    run(&mut gas, 5.0);
    let mut ahead = 0;
    for id in 0..gas.len() as u32 {
        let m = gas.motion[id as usize];
        let here = m.at(gas.now());
        let offset = gas.new_centre(id) - here;
        let shell = gas.centre[id as usize].shell;
        assert!(
            offset.length() <= 0.5 * shell * (1.0 + 1e-12),
            "{id}: {offset}"
        );
        if m.velocity != Vec3::ZERO {
            // Along the velocity, forwards.
            let along = offset.dot(m.velocity) / m.velocity.length();
            assert!((along - offset.length()).abs() <= 1e-9, "{id}: {offset}");
            ahead += usize::from(along > 0.0);
        }
    }
    assert!(ahead > 250, "{ahead} of 300 re-centre ahead");
    run(&mut gas, 10.0);
    assert!(gas.stats().events_by_kind["shell"] > 100);
}
