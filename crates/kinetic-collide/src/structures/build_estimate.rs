//! What a structure's build would cost in a world, estimated by building it on samples of
//! the world's objects: the race's price of a trial before it is run.

use super::Structure;
use crate::World;
use kinetic_core::{FlightPlan, Response, Shape};
use std::time::Instant;

/// The most objects in the sample [`pair_cost`] times.
const PROBE_OBJECTS: usize = 64;

/// The wall seconds one pair certificate of this world costs to make: the brute force's build
/// timed on a sample of a quarter of its objects (at least 16, at most [`PROBE_OBJECTS`], so
/// that the probe costs at most a sixteenth of the whole build), spread over the ids (so over
/// its sizes and shapes), with their plans at the world's time.
///
/// The sample is built in two batches, the first of [`PROBE_FIRST`] objects. Where that
/// batch's cost per pair, over the world's `n (n - 1) / 2` pairs, passes `worth` seconds
/// [`ROUGH`] times over, the probe stops there with that cost: a build that dear is not tried
/// (see [`super::Race`]), and the whole probe could cost more than the rest of a short run.
pub(crate) fn pair_cost(world: &World, worth: f64) -> f64 {
    let sample = sample(world, PROBE_OBJECTS);
    if sample.len() < 2 {
        return 0.0;
    }
    let n = world.len() as f64;
    let pairs = |k: usize| (k * k.saturating_sub(1) / 2) as f64;
    let first = PROBE_FIRST.min(sample.len());
    let k = sample.len();
    let start = Instant::now();
    // Passing through each other: the certificates, without walls or bounces.
    let mut probe = kinetic_core::Simulator::new(world.kind());
    let mut batch = sample;
    let tail = batch.split_off(first);
    if probe.add_objects(batch).is_err() {
        return 0.0;
    }
    let per_pair = start.elapsed().as_secs_f64() / pairs(first);
    if first == k || per_pair * n * (n - 1.0) / 2.0 > ROUGH * worth {
        return per_pair;
    }
    if probe.add_objects(tail).is_err() {
        return 0.0;
    }
    start.elapsed().as_secs_f64() / pairs(k)
}

/// The objects in the first batch of [`pair_cost`]'s probe (120 pairs).
const PROBE_FIRST: usize = 16;

/// How far over what a build may cost the first batch of [`pair_cost`]'s probe must project
/// it before the probe stops: that batch also pays the probe's first allocations, so its cost
/// per pair can be a few times the whole sample's.
const ROUGH: f64 = 4.0;

/// The most objects in the sample [`build_cost`] builds.
const BUILD_SAMPLE: usize = 256;

/// The wall seconds a whole build of `structure` would cost in this world: for the brute
/// force its pairs at [`pair_cost`] (whose probe stops early where the build would cost more
/// than `worth` several times over); for a box structure its build timed on two samples of a
/// quarter of the objects (at least 16, at most [`BUILD_SAMPLE`]) and scaled to all of them,
/// the larger of the two: one spread over the ids (so over their sizes and shapes), one the
/// objects nearest a middle one (so at the world's own density, where a structure's pairs
/// per object grow with it: 8,000 cubes drifting on a lattice, sampled over the ids at a
/// quarter of their density, gave the loose grid's build a quarter of its 1.0 s). A box
/// structure's build grows about as its objects; a small sample's fixed costs make it an
/// overestimate, which keeps trials within their budget. `least_flight` sizes the grids as
/// the run's.
pub(crate) fn build_cost(
    world: &World,
    structure: Structure,
    least_flight: f64,
    worth: f64,
) -> f64 {
    let n = world.len() as f64;
    if structure == Structure::BruteForce {
        return pair_cost(world, worth) * n * (n - 1.0) / 2.0;
    }
    [sample(world, BUILD_SAMPLE), cluster(world, BUILD_SAMPLE)]
        .into_iter()
        .map(|objects| {
            let k = objects.len() as f64;
            sample_build(world, structure, least_flight, objects).map_or(0.0, |s| s * n / k)
        })
        .fold(0.0, f64::max)
}

/// The wall seconds `structure`'s build of `objects` takes (None where it cannot hold them).
fn sample_build(
    world: &World,
    structure: Structure,
    least_flight: f64,
    objects: Vec<(Shape, FlightPlan)>,
) -> Option<f64> {
    if objects.is_empty() {
        return None;
    }
    let shapes: Vec<Shape> = objects.iter().map(|o| o.0.clone()).collect();
    let start = Instant::now();
    let candidates = structure.build(world.kind(), &shapes, least_flight).ok()?;
    let mut probe =
        kinetic_core::Simulator::with_structure(world.kind(), Response::None, None, candidates)
            .ok()?;
    probe.add_objects(objects).ok()?;
    Some(start.elapsed().as_secs_f64())
}

/// A quarter of the world's objects (at least 16, at most `most`), spread over the ids (so
/// over their sizes and shapes), with their plans at the world's time.
fn sample(world: &World, most: usize) -> Vec<(Shape, FlightPlan)> {
    let bodies: Vec<&kinetic_core::Body> = world.bodies().iter().flatten().collect();
    let size = (bodies.len() / 4).clamp(16, most);
    let step = bodies.len().div_ceil(size).max(1);
    bodies
        .iter()
        .step_by(step)
        .map(|b| (b.shape.clone(), b.plan))
        .collect()
}

/// As many objects as [`sample`] takes, those whose centres lie nearest the middle object's
/// (by id) at the world's time: a piece of the world at its own density.
fn cluster(world: &World, most: usize) -> Vec<(Shape, FlightPlan)> {
    let now = world.now();
    let mut bodies: Vec<(f64, usize, &kinetic_core::Body)> = world
        .bodies()
        .iter()
        .flatten()
        .enumerate()
        .map(|(i, b)| (0.0, i, b))
        .collect();
    let size = (bodies.len() / 4).clamp(16, most).min(bodies.len());
    let Some(middle) = bodies.get(bodies.len() / 2) else {
        return Vec::new();
    };
    let centre = middle.2.plan.position_at(now);
    for (d, _, b) in bodies.iter_mut() {
        *d = (b.plan.position_at(now) - centre).length_squared();
    }
    if size < bodies.len() {
        bodies.select_nth_unstable_by(size, |a, b| a.0.total_cmp(&b.0));
        bodies.truncate(size);
    }
    // In id order, as the other sample.
    bodies.sort_by_key(|&(_, i, _)| i);
    bodies
        .into_iter()
        .map(|(_, _, b)| (b.shape.clone(), b.plan))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;
    use kinetic_core::WorldKind;
    /// The volume of the box about `objects`' centres at time 0, per object.
    fn room_per_object(objects: &[(Shape, FlightPlan)]) -> f64 {
        let (lo, hi) = objects.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), (_, plan)| {
                let p = plan.position_at(0.0);
                (lo.min(p), hi.max(p))
            },
        );
        let side = hi - lo + DVec3::ONE;
        side.x * side.y * side.z / objects.len() as f64
    }

    #[test]
    fn a_build_is_also_sampled_at_the_worlds_own_density() {
        // 3,375 balls on a lattice of unit spacing: the sample spread over the ids holds about
        // 250 of them over the whole lattice, the cluster as many at the lattice's density.
        let mut world =
            World::with_structure(WorldKind::Free, Response::None, None, Structure::Grid).unwrap();
        let k = 15;
        world
            .add_balls((0..k * k * k).map(|i| {
                let p = DVec3::new((i % k) as f64, (i / k % k) as f64, (i / (k * k)) as f64);
                (0.3, FlightPlan::linear(p, DVec3::X))
            }))
            .unwrap();
        let spread = sample(&world, BUILD_SAMPLE);
        let near = cluster(&world, BUILD_SAMPLE);
        assert!(
            spread.len() > BUILD_SAMPLE * 9 / 10,
            "{} spread",
            spread.len()
        );
        assert_eq!(near.len(), BUILD_SAMPLE);
        let (spread_room, near_room) = (room_per_object(&spread), room_per_object(&near));
        assert!(
            spread_room > 10.0 && near_room < 4.0,
            "room per object: spread {spread_room}, near {near_room} (the lattice's is 1)"
        );
        // The estimate builds both samples.
        let whole = build_cost(&world, Structure::LooseGrid, 0.0, f64::INFINITY);
        assert!(whole > 0.0 && whole.is_finite(), "estimate {whole}");
    }
}
