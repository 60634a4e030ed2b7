//! The grid on its own, driven event by event with its audit after each: its candidates
//! against a brute force over box pairs at sampled times, with sparse levels (wider cells),
//! fast and accelerated bodies crossing many cells, re-plans, a re-plan that moves a body
//! to another level, and removals.

mod common;

use kinetic_core::kds::Bodies;
use kinetic_core::{Body, CandidateStructure, FlightPlan, Quat, Shape, Vec3};
use kinetic_flight::{ConvexShape, Grid};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::{BTreeMap, BTreeSet};

type Driven = common::Driven<Grid>;

/// A ball's box at `t`, as the structures make it (inflated by 1e-9 of the radius).
fn ball_box(body: &Body, t: f64) -> (Vec3, Vec3) {
    let r = body.shape.outer_radius() * (1.0 + 1e-9);
    let c = body.plan.position_at(t);
    (c - Vec3::splat(r), c + Vec3::splat(r))
}

/// Every pair of balls whose boxes overlap at `t` by more than `margin` on every axis (must
/// be candidates), and every pair within `margin` (may be).
fn overlapping(bodies: &Bodies, t: f64, margin: f64) -> BTreeSet<(u32, u32)> {
    let mut out = BTreeSet::new();
    for (i, a) in bodies.iter().enumerate() {
        let Some(a) = a else { continue };
        for (j, b) in bodies.iter().enumerate().skip(i + 1) {
            let Some(b) = b else { continue };
            let ((alo, ahi), (blo, bhi)) = (ball_box(a, t), ball_box(b, t));
            if (0..3).all(|k| alo[k] <= bhi[k] - margin && blo[k] <= ahi[k] - margin) {
                out.insert((i as u32, j as u32));
            }
        }
    }
    out
}

fn check_against_boxes(d: &Driven, bodies: &Bodies, t: f64) {
    let have = d.candidates();
    let must = overlapping(bodies, t, 1e-9);
    let may = overlapping(bodies, t, -1e-5);
    if let Some(missing) = must.difference(&have).next() {
        panic!("t = {t}: pair {missing:?} overlaps but is not a candidate");
    }
    if let Some(extra) = have.difference(&may).next() {
        panic!("t = {t}: pair {extra:?} is a candidate but its boxes are apart");
    }
}

#[test]
fn sparse_small_balls_and_a_few_large_ones_match_the_box_pairs_through_replans_and_removals() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut bodies: Vec<Option<Body>> = Vec::new();
    // 300 small balls spread thin (their level's cells are widened), 8 large ones, a few fast
    // accelerated ones that cross many cells.
    for k in 0..320 {
        let r = if k < 300 {
            rng.random_range(0.05..0.1)
        } else if k < 308 {
            rng.random_range(2.0..4.0)
        } else {
            rng.random_range(0.2..0.3)
        };
        let p = Vec3::new(
            rng.random_range(-20.0..20.0),
            rng.random_range(-20.0..20.0),
            rng.random_range(-20.0..20.0),
        );
        let v = Vec3::new(
            rng.random_range(-3.0..3.0),
            rng.random_range(-3.0..3.0),
            rng.random_range(-3.0..3.0),
        );
        let a = if k >= 308 {
            Vec3::new(0.0, -9.81, 1.0)
        } else {
            Vec3::ZERO
        };
        bodies.push(Some(Body {
            shape: Shape::Ball { radius: r },
            plan: FlightPlan::accelerated(p, v * if k >= 308 { 5.0 } else { 1.0 }, a),
        }));
    }
    let mut d = Driven::new(Grid::new());
    let ids: Vec<u32> = (0..bodies.len() as u32).collect();
    d.grid.insert_many(&ids, &bodies, 0.0, &mut d.changes);
    d.absorb();
    d.grid.validate(&bodies, 0.0).unwrap();
    check_against_boxes(&d, &bodies, 0.0);
    let mut events = 0;
    for step in 1..=40 {
        let t = step as f64 * 0.05;
        events += d.advance(&bodies, t);
        check_against_boxes(&d, &bodies, t);
        // Every few steps: turn some balls around (re-plans) and drop one.
        if step % 5 == 0 {
            for _ in 0..10 {
                let id = rng.random_range(0..bodies.len());
                let Some(body) = bodies[id].as_mut() else {
                    continue;
                };
                let v = Vec3::new(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                );
                body.plan = body.plan.replanned(t, v);
                d.replan(&bodies, id, t);
            }
            let gone = rng.random_range(0..bodies.len());
            d.remove(&mut bodies, gone, t);
            check_against_boxes(&d, &bodies, t);
        }
    }
    let counters: BTreeMap<&str, f64> = d.grid.counters().into_iter().collect();
    assert!(counters["crossings"] > 1000.0, "{counters:?}");
    // Pairs apart watch one axis (their witness), so box events are few.
    assert!(counters["box_events"] > 20.0, "{counters:?}");
    assert!(counters["levels"] >= 3.0, "{counters:?}");
    // The small balls' footprints at the large ones' levels follow their own (no
    // certificates), and validate() above checked them against their boxes after every event.
    assert!(counters["derived_tracks"] >= 200.0, "{counters:?}");
    assert!(
        counters["derived_tracks"] < counters["tracks"],
        "{counters:?}"
    );
    assert!(events > 1000, "{events}");
}

#[test]
fn a_replan_that_starts_a_spin_moves_a_cuboid_to_a_larger_level() {
    // A cube at rest keeps its own box (2 wide); spinning, it needs its outer ball's (3.46
    // wide): another level, so it is placed afresh.
    let slab = ConvexShape::cuboid(Vec3::splat(1.0)).unwrap().into_shape();
    let mut bodies: Vec<Option<Body>> = vec![
        Some(Body {
            shape: slab,
            plan: FlightPlan::at_rest(Vec3::ZERO),
        }),
        // Within the spinning slab's outer ball, outside its own box.
        Some(Body {
            shape: Shape::Ball { radius: 0.1 },
            plan: FlightPlan::at_rest(Vec3::new(0.0, 1.5, 0.0)),
        }),
        Some(Body {
            shape: Shape::Ball { radius: 0.1 },
            plan: FlightPlan::linear(Vec3::new(5.0, 0.0, 0.0), Vec3::new(-1.0, 0.0, 0.0)),
        }),
    ];
    let mut d = Driven::new(Grid::new());
    d.grid.insert_many(&[0, 1, 2], &bodies, 0.0, &mut d.changes);
    d.absorb();
    assert!(d.candidates().is_empty(), "{:?}", d.candidates());
    let levels = |d: &Driven| {
        d.grid
            .counters()
            .into_iter()
            .find(|c| c.0 == "levels")
            .unwrap()
            .1
    };
    assert_eq!(levels(&d), 2.0);
    // The moving ball's box reaches the cube's own box (x = 1) at t = 3.9.
    d.advance(&bodies, 3.85);
    assert!(d.candidates().is_empty());
    d.advance(&bodies, 3.95);
    assert_eq!(d.candidates(), BTreeSet::from([(0, 2)]));
    // Start the spin: the box becomes the outer ball's and holds the resting ball too.
    bodies[0].as_mut().unwrap().plan =
        FlightPlan::at_rest(Vec3::ZERO).with_spin(Quat::IDENTITY, Vec3::new(0.0, 0.0, 1.0));
    d.grid.replan(0, &bodies, 3.95, &mut d.changes);
    d.absorb();
    d.grid.validate(&bodies, 3.95).unwrap();
    assert_eq!(levels(&d), 3.0);
    assert_eq!(d.candidates(), BTreeSet::from([(0, 1), (0, 2)]));
    d.advance(&bodies, 10.0);
    // The moving ball has gone through and out the other side.
    assert_eq!(d.candidates(), BTreeSet::from([(0, 1)]));
}

#[test]
fn a_pair_apart_on_one_axis_watches_that_axis_alone() {
    // A small ball passes along x over a large resting one. At height 1.5 it is apart on y
    // for ever, so its box entering and leaving the large one's on x is no event: only the
    // witness axis (y) is watched. At height 0.5 the two boxes overlap on y and z, and x
    // makes the pair a candidate and then drops it.
    let box_events = |height: f64| {
        let bodies: Vec<Option<Body>> = vec![
            Some(Body {
                shape: Shape::Ball { radius: 1.0 },
                plan: FlightPlan::at_rest(Vec3::ZERO),
            }),
            Some(Body {
                shape: Shape::Ball { radius: 0.1 },
                plan: FlightPlan::linear(Vec3::new(-3.0, height, 0.0), Vec3::new(2.0, 0.0, 0.0)),
            }),
        ];
        let mut d = Driven::new(Grid::new());
        d.grid.insert_many(&[0, 1], &bodies, 0.0, &mut d.changes);
        d.absorb();
        d.grid.validate(&bodies, 0.0).unwrap();
        let mut seen = BTreeSet::new();
        for k in 1..=30 {
            let t = k as f64 * 0.1;
            d.advance(&bodies, t);
            check_against_boxes(&d, &bodies, t);
            seen.extend(d.candidates());
        }
        let counters: BTreeMap<&str, f64> = d.grid.counters().into_iter().collect();
        assert_eq!(counters["grid_pairs"], 1.0, "{counters:?}");
        (counters["box_events"], seen)
    };
    let (apart, seen) = box_events(1.5);
    assert_eq!(apart, 0.0);
    assert!(seen.is_empty(), "{seen:?}");
    // Overlapping on y and z: x's two changes are events (in, then out), and the pair was a
    // candidate between them.
    let (crossing, seen) = box_events(0.5);
    assert_eq!(crossing, 2.0);
    assert_eq!(seen, BTreeSet::from([(0, 1)]));
}

/// The grid's counter `name`.
fn counter(d: &Driven, name: &str) -> f64 {
    d.grid
        .counters()
        .into_iter()
        .find(|c| c.0 == name)
        .unwrap_or_else(|| panic!("no counter {name}"))
        .1
}

#[test]
fn a_shot_far_faster_than_its_cells_holds_a_region_a_step_and_meets_the_row_in_its_path() {
    // A ball of radius 0.5 at 1e4 units per time unit along a row of 20 resting balls 3 apart
    // (x = 0 to 57), with a few larger balls beside the row (a second level): in a step of
    // 0.01 it crosses 100 of its cells.
    let shot = |grid: Grid| {
        let mut bodies = common::resting_row(20, 3.0, 0.5);
        for i in 0..4 {
            bodies.push(Some(Body {
                shape: Shape::Ball { radius: 4.0 },
                plan: FlightPlan::at_rest(Vec3::new(20.0 * i as f64, 4.2, 0.0)),
            }));
        }
        bodies.push(common::shot_along_x());
        let ids: Vec<u32> = (0..bodies.len() as u32).collect();
        let mut d = Driven::new(grid);
        d.grid.insert_many(&ids, &bodies, 0.0, &mut d.changes);
        d.absorb();
        d.grid.validate(&bodies, 0.0).unwrap();
        // Within the second step, where the shot passes the row, the candidates are checked
        // every 0.1 units of its flight.
        let mut met = BTreeSet::new();
        let per_step = d.fly_past_the_row(&bodies, |d, t, sampled| {
            check_against_boxes(d, &bodies, t);
            if sampled {
                met.extend(d.candidates().into_iter().filter(|p| p.1 == 24));
            }
        });
        (per_step, met.len(), counter(&d, "crossings"))
    };
    let (bounded, met, crossings) = shot(Grid::new().with_least_flight(0.01));
    println!("with the floor: events per step {bounded:?}, {crossings} crossings");
    // The 20 row balls and the 4 large ones, whose boxes reach down to y = 0.2.
    assert_eq!(met, 24);
    // A region a step (one event), and in the step that passes the row the box events of the
    // 24 balls it meets: each in and out on x, its witness axis (at most 2 more each).
    assert!(bounded[0] <= 2, "events per step {bounded:?}");
    assert!(bounded[1] <= 2 + 4 * 24, "events per step {bounded:?}");
    assert!(bounded[2..].iter().all(|&e| e <= 2), "{bounded:?}");
    assert_eq!(crossings, 0.0);
    // Without the floor the shot crosses about 100 cells a step at its own level (and the
    // coarser level's cells).
    let (unbounded, met, crossings) = shot(Grid::new());
    println!("without: events per step {unbounded:?}, {crossings} crossings");
    assert_eq!(met, 24);
    assert!(unbounded[2..].iter().all(|&e| e >= 100), "{unbounded:?}");
}

#[test]
fn fast_bodies_leave_the_cells_and_come_back_through_replans_and_acceleration() {
    // 200 small balls drifting, 6 large ones, 8 shots aimed through the crowd far faster than
    // their cells, and 6 balls that start at rest under a strong acceleration (fast within a
    // few steps): every event audited, the candidates checked against the box pairs 25
    // times a step, through re-plans that bring shots back slowly (into the cells) and fire
    // resting or drifting balls off (out of them), and removals.
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let mut bodies: Vec<Option<Body>> = Vec::new();
    let random_v = |rng: &mut ChaCha8Rng, speed: f64| {
        Vec3::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        ) * speed
    };
    let in_crowd = |rng: &mut ChaCha8Rng| {
        Vec3::new(
            rng.random_range(-10.0..10.0),
            rng.random_range(-10.0..10.0),
            rng.random_range(-10.0..10.0),
        )
    };
    const SHOT: f64 = 4000.0;
    for k in 0..220 {
        let r = match k {
            0..200 => rng.random_range(0.1..0.2),
            200..206 => rng.random_range(2.0..3.0),
            _ => rng.random_range(0.1..0.3),
        };
        let p = in_crowd(&mut rng);
        let plan = match k {
            0..206 => FlightPlan::linear(p, random_v(&mut rng, 1.0)),
            206..214 => {
                // From 25 to 45 units out, through a point of the crowd.
                let from = p + random_v(&mut rng, 1.0).normalize() * rng.random_range(25.0..45.0);
                FlightPlan::linear(from, (p - from).normalize() * SHOT)
            }
            _ => FlightPlan::accelerated(p, Vec3::ZERO, random_v(&mut rng, 20000.0)),
        };
        bodies.push(Some(Body {
            shape: Shape::Ball { radius: r },
            plan,
        }));
    }
    let mut d = Driven::new(Grid::new().with_least_flight(0.05));
    let ids: Vec<u32> = (0..bodies.len() as u32).collect();
    d.grid.insert_many(&ids, &bodies, 0.0, &mut d.changes);
    d.absorb();
    d.grid.validate(&bodies, 0.0).unwrap();
    check_against_boxes(&d, &bodies, 0.0);
    let fast_at_start = counter(&d, "fast");
    let (mut most_fast, mut fewest_fast) = (fast_at_start, fast_at_start);
    let mut met_fast = BTreeSet::new();
    let mut slowed = 0;
    for step in 1..=60 {
        for k in 1..=25 {
            let t = (step - 1) as f64 * 0.02 + k as f64 * 0.0008;
            d.advance(&bodies, t);
            check_against_boxes(&d, &bodies, t);
            // Pairs with a body fired off (a shot, or a ball re-planned fast).
            met_fast.extend(d.candidates().into_iter().filter(|&(a, b)| {
                [a, b].iter().any(|&x| {
                    bodies[x as usize]
                        .as_ref()
                        .is_some_and(|b| b.plan.velocity_at(t).length() > 100.0)
                })
            }));
        }
        let t = step as f64 * 0.02;
        let fast = counter(&d, "fast");
        (most_fast, fewest_fast) = (most_fast.max(fast), fewest_fast.min(fast));
        if step % 3 == 0 {
            // A body moving fast is brought back into the crowd slowly; any other is fired
            // off at the shots' speed.
            for _ in 0..8 {
                let id = rng.random_range(0..bodies.len());
                let Some(body) = bodies[id].as_mut() else {
                    continue;
                };
                body.plan = if body.plan.velocity_at(t).length() > 100.0 {
                    slowed += 1;
                    FlightPlan::linear(in_crowd(&mut rng), random_v(&mut rng, 1.0)).starting_at(t)
                } else {
                    body.plan
                        .replanned(t, random_v(&mut rng, 1.0).normalize() * SHOT)
                };
                d.replan(&bodies, id, t);
            }
            let gone = rng.random_range(0..bodies.len());
            d.remove(&mut bodies, gone, t);
            check_against_boxes(&d, &bodies, t);
        }
    }
    let anchors = counter(&d, "fast_anchors");
    println!(
        "fast: {fast_at_start} at the start, {fewest_fast} to {most_fast}; {slowed} brought \
         back; {anchors} regions; {} pairs with fast bodies met",
        met_fast.len()
    );
    // The shots start fast, the accelerated balls and the balls fired off join them, and
    // the ones brought back leave the fast ones.
    assert!(fast_at_start >= 8.0, "{fast_at_start}");
    assert!(most_fast >= 20.0, "{most_fast}");
    assert!(slowed >= 10, "{slowed}");
    assert!(anchors > 100.0, "{anchors}");
    assert!(met_fast.len() >= 10, "{met_fast:?}");
}

#[test]
fn a_sparse_layer_gets_cells_of_about_one_ball_each() {
    // 1,000 balls of radius 0.1 in a layer of 100 x 100 (on a plane: one z), about 3 apart,
    // rolling at speed 1 for 10. Cells of about one ball each (1.6 to 3.2 wide, the balls'
    // own widened by a power of two) change a footprint about 16 times a ball; cells sized
    // by the volume of the layer's box over the balls (a cube root of 3.2 times the
    // balls' own, so 0.8 to 1.6 wide) about 32 times.
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let bodies: Vec<Option<Body>> = (0..1000)
        .map(|_| {
            let p = Vec3::new(
                rng.random_range(0.0..100.0),
                rng.random_range(0.0..100.0),
                0.1,
            );
            let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            Some(Body {
                shape: Shape::Ball { radius: 0.1 },
                plan: FlightPlan::linear(p, Vec3::new(a.cos(), a.sin(), 0.0)),
            })
        })
        .collect();
    let mut d = Driven::new(Grid::new());
    let ids: Vec<u32> = (0..bodies.len() as u32).collect();
    d.grid.insert_many(&ids, &bodies, 0.0, &mut d.changes);
    d.absorb();
    d.advance(&bodies, 10.0);
    check_against_boxes(&d, &bodies, 10.0);
    let crossings = d
        .grid
        .counters()
        .into_iter()
        .find(|c| c.0 == "crossings")
        .map(|c| c.1)
        .unwrap();
    assert!(
        crossings > 0.0 && crossings < 24.0 * 1000.0,
        "{crossings} cell crossings for 1,000 balls"
    );
}
