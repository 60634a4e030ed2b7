//! The loose grid on its own, driven event by event with its audit after each (regions,
//! cells, exit times, and partners against a brute force over all regions): its candidates
//! must hold every pair of overlapping boxes at sampled times, through fast and accelerated
//! bodies, re-plans that keep or leave their regions, sizes over two orders of magnitude,
//! and removals.

mod common;

use kinetic_core::kds::Bodies;
use kinetic_core::{Body, CandidateStructure, FlightPlan, Shape, Vec3};
use kinetic_flight::{ConvexShape, LooseGrid};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::{BTreeMap, BTreeSet};

type Driven = common::Driven<LooseGrid>;

/// Every pair whose boxes (the outer balls', or a resting cuboid's own) overlap at `t`.
fn overlapping(bodies: &Bodies, t: f64) -> BTreeSet<(u32, u32)> {
    let bx = |b: &Body| {
        let c = b.plan.position_at(t);
        let r = b.shape.outer_radius();
        let own = match &b.shape {
            Shape::Convex(g) => g.local_aabb(b.plan.orientation),
            _ => None,
        };
        let (lo, hi) = own.unwrap_or((Vec3::splat(-r), Vec3::splat(r)));
        (c + lo, c + hi)
    };
    let mut out = BTreeSet::new();
    for (i, a) in bodies.iter().enumerate() {
        let Some(a) = a else { continue };
        for (j, b) in bodies.iter().enumerate().skip(i + 1) {
            let Some(b) = b else { continue };
            let ((alo, ahi), (blo, bhi)) = (bx(a), bx(b));
            if (0..3).all(|k| alo[k] <= bhi[k] && blo[k] <= ahi[k]) {
                out.insert((i as u32, j as u32));
            }
        }
    }
    out
}

fn check(d: &Driven, bodies: &Bodies, t: f64) {
    let have = d.candidates();
    if let Some(missing) = overlapping(bodies, t).difference(&have).next() {
        panic!("t = {t}: pair {missing:?} overlaps but is not a candidate");
    }
}

#[test]
fn a_crowd_with_fast_falling_and_resting_bodies_keeps_every_overlapping_pair() {
    crowd(LooseGrid::new());
}

#[test]
fn a_crowd_filed_with_staggered_regions_keeps_every_overlapping_pair() {
    crowd(LooseGrid::new().staggered());
}

/// Drives a crowd of drifting, resting, fast falling and large bodies over a resting slab
/// through `grid`, with re-plans and removals, checking its candidates at each step.
fn crowd(grid: LooseGrid) {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut bodies: Vec<Option<Body>> = Vec::new();
    // 250 drifting balls, 40 at rest, 20 falling fast, 6 large, in a 20-unit cube.
    for k in 0..316 {
        let r = match k {
            0..250 => rng.random_range(0.1..0.3),
            250..290 => rng.random_range(0.1..0.3),
            290..310 => rng.random_range(0.05..0.1),
            _ => rng.random_range(2.0..5.0),
        };
        let p = Vec3::new(
            rng.random_range(-10.0..10.0),
            rng.random_range(-10.0..10.0),
            rng.random_range(-10.0..10.0),
        );
        let v = Vec3::new(
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
        );
        let plan = match k {
            250..290 => FlightPlan::at_rest(p),
            290..310 => FlightPlan::accelerated(p, v * 4.0, Vec3::new(0.0, -9.81, 0.0)),
            _ => FlightPlan::linear(p, v),
        };
        bodies.push(Some(Body {
            shape: Shape::Ball { radius: r },
            plan,
        }));
    }
    // A resting slab, as rapier's ground.
    bodies.push(Some(Body {
        shape: ConvexShape::cuboid(Vec3::new(12.0, 0.5, 12.0))
            .unwrap()
            .into_shape(),
        plan: FlightPlan::at_rest(Vec3::new(0.0, -10.5, 0.0)),
    }));
    let mut d = Driven::new(grid);
    let ids: Vec<u32> = (0..bodies.len() as u32).collect();
    d.grid.insert_many(&ids, &bodies, 0.0, &mut d.changes);
    d.absorb();
    d.grid.validate(&bodies, 0.0).unwrap();
    check(&d, &bodies, 0.0);
    let mut events = 0;
    for step in 1..=60 {
        let t = step as f64 * 0.05;
        events += d.advance(&bodies, t);
        check(&d, &bodies, t);
        // Every few steps: nudge some bodies (small changes keep their regions, large ones
        // leave them) and drop one.
        if step % 4 == 0 {
            for _ in 0..12 {
                let id = rng.random_range(0..316);
                let Some(body) = bodies[id].as_mut() else {
                    continue;
                };
                let v = body.plan.velocity_at(t);
                let nudge = if rng.random_bool(0.5) { 0.05 } else { 3.0 };
                let v = v + Vec3::new(
                    rng.random_range(-nudge..nudge),
                    rng.random_range(-nudge..nudge),
                    rng.random_range(-nudge..nudge),
                );
                body.plan = body.plan.replanned(t, v);
                d.replan(&bodies, id, t);
            }
            let gone = rng.random_range(0..316);
            d.remove(&mut bodies, gone, t);
            check(&d, &bodies, t);
        }
    }
    let counters: BTreeMap<&str, f64> = d.grid.counters().into_iter().collect();
    assert!(counters["anchors"] > 1000.0, "{counters:?}");
    assert!(counters["regions_kept"] > 20.0, "{counters:?}");
    // The slab's region is big: the balls' regions meet it through the big list.
    assert!(counters["big"] >= 1.0, "{counters:?}");
    assert!(events > 500, "{events}");
    // Superset, but not wildly so: regions reach a few box widths.
    let overlapping = overlapping(&bodies, 3.0).len();
    assert!(
        d.candidates().len() < 20 * overlapping.max(10),
        "{} candidates for {overlapping} overlapping boxes",
        d.candidates().len()
    );
}

/// Balls filed together all leave their regions a flight after the build; staggered, they
/// leave them through that flight, about evenly.
#[test]
fn staggered_regions_end_through_the_first_flight() {
    // 400 balls of width 1 at speed 1 along x: a region covers 2 widths of travel, so the
    // first re-anchors come 2 time units and a margin after the build.
    let bodies: Vec<Option<Body>> = (0..400)
        .map(|k| {
            let p = Vec3::new(0.0, 3.0 * (k % 20) as f64, 3.0 * (k / 20) as f64);
            Some(Body {
                shape: Shape::Ball { radius: 0.5 },
                plan: FlightPlan::linear(p, Vec3::X),
            })
        })
        .collect();
    let anchors_by = |grid: LooseGrid, t: f64| {
        let mut d = Driven::new(grid);
        let ids: Vec<u32> = (0..bodies.len() as u32).collect();
        d.grid.insert_many(&ids, &bodies, 0.0, &mut d.changes);
        d.absorb();
        d.advance(&bodies, t);
        d.grid.validate(&bodies, t).unwrap();
        let counters: BTreeMap<&str, f64> = d.grid.counters().into_iter().collect();
        counters["anchors"] - 400.0
    };
    assert_eq!(anchors_by(LooseGrid::new(), 1.0), 0.0);
    let first = anchors_by(LooseGrid::new().staggered(), 1.0);
    let both = anchors_by(LooseGrid::new().staggered(), 2.0);
    assert!(
        (120.0..=280.0).contains(&first),
        "{first} re-anchors by t = 1"
    );
    assert!(
        both > first + 120.0,
        "{first} then {both} re-anchors by t = 2"
    );
}

#[test]
fn a_body_at_rest_keeps_its_region_and_a_fast_one_moves_on() {
    let ball = |r: f64| Shape::Ball { radius: r };
    let mut bodies: Vec<Option<Body>> = vec![
        Some(Body {
            shape: ball(1.0),
            plan: FlightPlan::at_rest(Vec3::ZERO),
        }),
        Some(Body {
            shape: ball(1.0),
            plan: FlightPlan::linear(Vec3::new(-20.0, 0.0, 0.0), Vec3::new(4.0, 0.0, 0.0)),
        }),
    ];
    let mut d = Driven::new(LooseGrid::new());
    d.grid.insert_many(&[0, 1], &bodies, 0.0, &mut d.changes);
    d.absorb();
    assert!(d.candidates().is_empty());
    // The resting ball never leaves its region: no event of its own.
    let events = d.advance(&bodies, 3.0);
    assert!(
        events >= 2,
        "the moving ball re-anchors every 2 widths: {events}"
    );
    // Boxes touch at t = 4.5 (x = -2): the pair is a candidate by then, and until they part.
    d.advance(&bodies, 4.5);
    assert_eq!(d.candidates(), BTreeSet::from([(0, 1)]));
    d.advance(&bodies, 5.5);
    assert_eq!(d.candidates(), BTreeSet::from([(0, 1)]));
    d.advance(&bodies, 9.0);
    assert!(d.candidates().is_empty());
    // A small re-plan of the resting ball keeps its region.
    let kept = |d: &Driven| {
        d.grid
            .counters()
            .into_iter()
            .find(|c| c.0 == "regions_kept")
            .unwrap()
            .1
    };
    // (The other ball stops, far off, so that the only event left is the first one's.)
    bodies[1].as_mut().unwrap().plan = FlightPlan::at_rest(Vec3::new(16.0, 0.0, 0.0));
    d.grid.replan(1, &bodies, 9.0, &mut d.changes);
    bodies[0].as_mut().unwrap().plan =
        FlightPlan::linear(Vec3::ZERO, Vec3::new(0.0, 0.01, 0.0)).starting_at(9.0);
    d.grid.replan(0, &bodies, 9.0, &mut d.changes);
    assert_eq!(kept(&d), 2.0);
    d.grid.validate(&bodies, 9.0).unwrap();
    // Its box leaves the region (margin 0.5) after 0.5 / 0.01 = 50.
    let next = d.grid.next_event_time();
    assert!(next > 9.0 + 49.0, "{next}");
}

#[test]
fn cells_sized_by_a_lone_first_object_are_sized_afresh_when_most_regions_outgrow_them() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    // A speck first: the cells are sized by its region.
    let mut bodies: Vec<Option<Body>> = vec![Some(Body {
        shape: Shape::Ball { radius: 0.001 },
        plan: FlightPlan::at_rest(Vec3::ZERO),
    })];
    let mut d = Driven::new(LooseGrid::new());
    d.grid.insert(0, &bodies, 0.0, &mut d.changes);
    d.absorb();
    // Then 200 drifting balls a thousand times larger: each covers far more than the cells
    // allow, so is big, until the big ones are many and the cells are sized afresh.
    for id in 1..=200u32 {
        let p = Vec3::new(
            rng.random_range(-20.0..20.0),
            rng.random_range(-20.0..20.0),
            rng.random_range(-20.0..20.0),
        );
        let v = Vec3::new(
            rng.random_range(-1.0..1.0),
            0.0,
            rng.random_range(-1.0..1.0),
        );
        bodies.push(Some(Body {
            shape: Shape::Ball {
                radius: rng.random_range(0.5..1.5),
            },
            plan: FlightPlan::linear(p, v),
        }));
        d.grid.insert(id, &bodies, 0.0, &mut d.changes);
        d.absorb();
        d.grid.validate(&bodies, 0.0).unwrap();
    }
    let counters: BTreeMap<&str, f64> = d.grid.counters().into_iter().collect();
    assert!(counters["refiles"] >= 1.0, "{counters:?}");
    assert!(counters["cell_size"] > 1.0, "{counters:?}");
    assert!(counters["big"] < 32.0, "{counters:?}");
    check(&d, &bodies, 0.0);
    for step in 1..=40 {
        let t = step as f64 * 0.25;
        d.advance(&bodies, t);
        check(&d, &bodies, t);
    }
}

#[test]
fn a_horizon_keeps_a_slow_bodys_region_close_to_its_box() {
    let slow = |grid: LooseGrid| {
        let bodies: Vec<Option<Body>> = vec![Some(Body {
            shape: Shape::Ball { radius: 1.0 },
            plan: FlightPlan::linear(Vec3::ZERO, Vec3::new(0.01, 0.0, 0.0)),
        })];
        let mut d = Driven::new(grid);
        d.grid.insert(0, &bodies, 0.0, &mut d.changes);
        d.grid.validate(&bodies, 0.0).unwrap();
        let (lo, hi) = d.grid.boxes(&bodies, 0.0)[0];
        (hi - lo).x
    };
    // Box 2 wide, margin 0.5 a side: 3, plus the travel of 2 widths (4) without a horizon,
    // or of 10 time units (0.1) with one.
    let w = slow(LooseGrid::new());
    assert!((w - 7.0).abs() < 1e-6, "{w}");
    let w = slow(LooseGrid::new().with_horizon(10.0));
    assert!((w - 3.1).abs() < 1e-6, "{w}");
}

#[test]
fn a_shot_far_faster_than_its_width_is_reanchored_once_per_least_flight() {
    // A ball of radius 0.5 at 1e4 units per time unit along a row of 20 resting balls
    // 3 apart (x = 0 to 57): it crosses its own width 1e4 times per time unit.
    let shot = |grid: LooseGrid| {
        let mut bodies = common::resting_row(20, 3.0, 0.5);
        bodies.push(common::shot_along_x());
        let ids: Vec<u32> = (0..21).collect();
        let mut d = Driven::new(grid);
        d.grid.insert_many(&ids, &bodies, 0.0, &mut d.changes);
        d.absorb();
        // Steps of 0.01 (100 units of flight each); within the second, where the shot
        // passes the row, the candidates are checked every 0.1 units of its flight.
        d.fly_past_the_row(&bodies, |d, t, _| check(d, &bodies, t))
    };
    let bounded = shot(LooseGrid::new().with_horizon(0.04).with_least_flight(0.01));
    assert!(
        bounded.iter().all(|&e| e <= 2),
        "events per step {bounded:?}"
    );
    // Without the floor the shot is re-anchored every 2 widths of its flight, grown by the
    // margins: 44 or 45 times in each step of 100 units.
    let unbounded = shot(LooseGrid::new().with_horizon(0.04));
    println!("events per step: {bounded:?} with the floor, {unbounded:?} without");
    assert!(
        unbounded.iter().skip(2).all(|&e| e >= 40),
        "events per step {unbounded:?}"
    );
}
