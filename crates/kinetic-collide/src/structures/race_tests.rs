//! The race's tests: its choices on worlds whose structures run at set paces.

use super::*;
use crate::scene::SceneObject;
use glam::DVec3;
use kinetic_core::WorldKind;

/// `n` balls in a row, for a horizon of 100.
fn scene(n: usize) -> Scene {
    let ball = |i: usize| SceneObject::ball(0.5, DVec3::new(2.0 * i as f64, 0.0, 0.0), DVec3::X);
    Scene {
        world: WorldKind::Free,
        horizon: 100.0,
        response: Response::None,
        walls: None,
        periodic: None,
        objects: (0..n).map(ball).collect(),
    }
}

/// Runs a race in which each structure costs `pace` wall seconds per unit of simulated
/// time and each build `build` seconds; returns its slices.
fn run(race: &mut Race, pace: impl Fn(Structure) -> f64, build: f64) -> Vec<Slice> {
    run_with(race, |s, from, to, _| pace(s) * (to - from), build)
}

/// [`run`] with the wall seconds of each slice given by `wall(structure, from, to,
/// built)`, `built` the simulated time the structure was built at.
fn run_with(
    race: &mut Race,
    wall: impl Fn(Structure, f64, f64, f64) -> f64,
    build: f64,
) -> Vec<Slice> {
    let mut now = 0.0;
    let mut built = 0.0;
    while now < 100.0 {
        let mut to = race.slice_end(now);
        assert!(to > now, "the race stalls at {now}");
        let mut wall = wall(race.current(), now, to, built);
        // A slice past its wall-clock limit stops there, as a run's does (taken here at the
        // slice's mean pace).
        if let Some(limit) = race.wall_limit(to)
            && wall > limit
        {
            to = now + (to - now) * limit / wall;
            wall = limit;
        }
        if race
            .slice_done(now, to, wall, &mut |s, _| {
                // The brute force's 2,000 objects at 0.1 us a pair.
                if s == Structure::BruteForce {
                    0.2
                } else {
                    build
                }
            })
            .is_some()
        {
            race.switched(build);
            built = to;
        }
        now = to;
    }
    std::mem::replace(race, Race::new(&scene(2), Structure::Grid, 0.0)).into_slices()
}

fn paces(s: Structure) -> f64 {
    match s {
        Structure::Grid => 0.01,
        Structure::Sweep => 0.05,
        Structure::LooseGrid => 0.2,
        _ => 1.0,
    }
}

#[test]
fn the_race_ends_on_the_fastest_within_its_share() {
    let mut race = Race::new(&scene(2000), Structure::Sweep, 0.001);
    let slices = run(&mut race, paces, 0.001);
    assert_eq!(slices.last().unwrap().structure, Structure::Grid);
    // The slices cover the run, in order.
    assert_eq!(slices[0].from, 0.0);
    assert_eq!(slices.last().unwrap().to, 100.0);
    assert!(slices.windows(2).all(|w| w[0].to == w[1].from));
    // What the run cost beyond the grid's own run: the sweep measured, the trials and
    // their builds, within the share of the grid's run and the measurement before it.
    let total: f64 = slices.iter().map(|s| s.wall_seconds).sum();
    let grid_alone = paces(Structure::Grid) * 100.0;
    assert!(
        total < grid_alone * (1.0 + SHARE) + 4.0 * LEAST_WALL,
        "{total} {slices:?}"
    );
}

#[test]
fn a_slow_trial_is_cut_short_and_the_leader_kept() {
    // The grid leads from the start; every other structure is slower.
    let mut race = Race::new(&scene(2000), Structure::Grid, 0.001);
    let slices = run(&mut race, paces, 0.0);
    assert_eq!(slices.last().unwrap().structure, Structure::Grid);
    // What the trials cost beyond the grid's pace on their slices.
    let grid = paces(Structure::Grid);
    let trials: f64 = slices
        .iter()
        .filter(|s| s.structure != Structure::Grid)
        .map(|s| s.wall_seconds - grid * (s.to - s.from))
        .sum();
    assert!(trials > 0.0, "nothing was tried: {slices:?}");
    assert!(trials < SHARE * grid * 100.0, "{trials} {slices:?}");
}

#[test]
fn an_open_race_ends_on_the_fastest_within_its_share_of_the_run_so_far() {
    // A world of 2,000 objects advanced by 1/60 at a time, starting on the sweep.
    let mut race = Race::open(Structure::Sweep, 2000, 1.0, true, 1.0 / 60.0);
    let mut now = 0.0;
    for k in 1..=6000 {
        let t = k as f64 / 60.0;
        loop {
            let planned = race.slice_end(now);
            assert!(planned > now, "the race stalls at {now}");
            if planned > t {
                // The slice goes on at the next call.
                break;
            }
            // A slice past its wall-clock limit stops there, as a world's does.
            let pace = paces(race.current());
            let limit = race.wall_limit(planned).unwrap_or(f64::INFINITY);
            let to = planned.min(now + limit / pace);
            let wall = pace * (to - now);
            if race.slice_done(now, to, wall, &mut |_, _| 0.001).is_some() {
                race.switched(0.001);
            }
            now = to;
        }
    }
    let all = race.into_slices();
    // Most of the run on the grid, from early on.
    let on = |s: Structure| -> f64 {
        all.iter()
            .filter(|x| x.structure == s)
            .map(|x| x.to - x.from)
            .sum()
    };
    let end = all.last().unwrap().to;
    assert!(on(Structure::Grid) > 0.95 * end, "{all:?}");
    // Left within the first 60 calls.
    assert!(on(Structure::Sweep) < 1.0, "{all:?}");
    assert!(all.windows(2).all(|w| w[0].to == w[1].from));
    // What the race cost beyond the grid's pace: within twice the share of the grid's
    // run (the budget is a share of twice the run so far).
    let total: f64 = all.iter().map(|s| s.wall_seconds).sum();
    let grid_alone = paces(Structure::Grid) * end;
    assert!(
        total < paces(Structure::Sweep) * end.min(1.0) + grid_alone * (1.0 + 2.0 * SHARE),
        "{total} against {grid_alone}: {all:?}"
    );
}

#[test]
fn the_leaders_pace_is_measured_no_longer_than_its_build_took() {
    let mut race = Race::new(&scene(5000), Structure::Sweep, 0.01);
    let planned = race.slice_end(0.0);
    assert_eq!(race.wall_limit(planned), Some(0.01));
    // Cut at its limit halfway, the slice ends the measurement: the trials begin.
    let next = race.slice_done(0.0, planned / 2.0, 0.01, &mut |_, _| 0.001);
    assert_eq!(next, Some(Structure::Grid));
}

#[test]
fn a_runner_up_far_slower_than_the_leader_is_not_tried_again() {
    // On the grid, the sweep runs at 5 times its pace and the others slower still.
    let mut race = Race::new(&scene(5000), Structure::Grid, 0.001);
    let slices = run_with(&mut race, |s, from, to, _| paces(s) * (to - from), 0.001);
    let trials = |s: Structure| {
        let on = slices.iter().filter(|x| x.structure == s);
        on.filter(|x| x.build_seconds > 0.0).count()
    };
    assert_eq!(trials(Structure::Sweep), 1, "{slices:?}");
    assert_eq!(slices.last().unwrap().structure, Structure::Grid);
}

#[test]
fn a_structure_whose_work_comes_in_bursts_is_measured_over_one() {
    // The loose grid re-files every object 10 units after it was built: nothing before,
    // then a burst of 2 s (0.2 a unit on the whole, four times the sweep's 0.05). A trial
    // of a few units would see it free.
    let bursts = |s: Structure, from: f64, to: f64, built: f64| match s {
        Structure::LooseGrid => {
            let done = |t: f64| ((t - built) / 10.0).floor();
            2.0 * (done(to) - done(from))
        }
        _ => paces(s) * (to - from),
    };
    let mut race = Race::new(&scene(5000), Structure::Sweep, 0.001);
    let slices = run_with(&mut race, bursts, 0.001);
    assert_eq!(
        slices.last().unwrap().structure,
        Structure::Grid,
        "{slices:?}"
    );
    let loose: f64 = slices
        .iter()
        .filter(|s| s.structure == Structure::LooseGrid)
        .map(|s| s.to - s.from)
        .sum();
    assert!(loose < 25.0, "{slices:?}");
}

#[test]
fn the_leader_is_paced_once_warm() {
    // The grid runs its first 0.03 units at ten times its pace (cold caches, a queue
    // still growing), a tenth as long as its build; the sweep, twice the grid's warm
    // pace, is faster than that.
    let cold = |s: Structure, from: f64, to: f64, _| match s {
        Structure::Grid => {
            let cold = (to.min(0.03) - from.min(0.03)).max(0.0);
            0.01 * (to - from) + 0.09 * cold
        }
        Structure::Sweep => 0.02 * (to - from),
        _ => (to - from),
    };
    let mut race = Race::new(&scene(5000), Structure::Grid, 0.01);
    let slices = run_with(&mut race, cold, 0.01);
    let on_grid: f64 = slices
        .iter()
        .filter(|s| s.structure == Structure::Grid)
        .map(|s| s.to - s.from)
        .sum();
    assert!(on_grid > 90.0, "{slices:?}");
    assert_eq!(slices.last().unwrap().structure, Structure::Grid);
}

#[test]
fn one_structure_makes_no_race() {
    let mut periodic = scene(10);
    periodic.periodic = Some(kinetic_spheres::PeriodicBox {
        min: DVec3::ZERO,
        max: DVec3::splat(100.0),
    });
    let race = Race::new(&periodic, Structure::Periodic, 0.0);
    assert_eq!(race.slice_end(0.0), 100.0);
}

#[test]
fn a_runner_up_faster_than_the_leader_has_become_is_tried_outside_the_budget() {
    // The loose grid runs at 0.01 a unit until 10, then at 0.03; the grid at 0.02 throughout.
    // The loose grid's rebuild (0.2) spends the budget, so only the paces can pay for a
    // trial of the grid once the loose grid has slowed.
    let pace = |s: Structure, t: f64| match s {
        Structure::LooseGrid if t < 10.0 => 0.01,
        Structure::LooseGrid => 0.03,
        Structure::Grid => 0.02,
        Structure::Sweep => 0.05,
        _ => 1.0,
    };
    let build = |s: Structure| if s == Structure::Grid { 0.01 } else { 0.2 };
    let mut race = Race::new(&scene(5000), Structure::LooseGrid, 0.001);
    let mut now = 0.0;
    while now < 100.0 {
        let to = race.slice_end(now);
        assert!(to > now, "the race stalls at {now}");
        // Paces change at 10 only: the slices are cut there.
        let s = race.current();
        let wall = if now < 10.0 && to > 10.0 {
            pace(s, now) * (10.0 - now) + pace(s, 10.0) * (to - 10.0)
        } else {
            pace(s, now) * (to - now)
        };
        if let Some(next) = race.slice_done(now, to, wall, &mut |s, _| build(s)) {
            race.switched(build(next));
        }
        now = to;
    }
    let slices = race.into_slices();
    let on_grid: f64 = slices
        .iter()
        .filter(|x| x.structure == Structure::Grid && x.from >= 10.0)
        .map(|x| x.to - x.from)
        .sum();
    assert!(on_grid > 50.0, "{slices:?}");
    assert_eq!(slices.last().unwrap().structure, Structure::Grid);
}

/// A check that falls a rounding after a trial ended times a sliver of simulated time, whose
/// wall time is the timer's own cost: no pace is taken from it (it would be millions of
/// times the leader's, and any structure would then beat the leader), and the check waits
/// for a slice long enough to time.
#[test]
fn a_check_on_a_sliver_of_time_keeps_the_leaders_pace() {
    let mut race = Race::new(&scene(2000), Structure::Grid, 0.001);
    race.phase = Phase::Settled;
    race.pace = 0.01;
    race.slice = 1.0;
    race.measured_from = 10.0;
    race.measured_wall = 0.0;
    race.paces = vec![(Structure::Sweep, 0.05)];
    let sliver = 10.0 + 2.0 * f64::EPSILON * 10.0;
    race.next_check = sliver;
    let mut build = |_, _| 0.001;
    assert_eq!(race.slice_done(10.0, sliver, 1e-6, &mut build), None);
    assert_eq!(race.pace, 0.01);
    assert_eq!(race.current(), Structure::Grid);
    let next = race.slice_end(sliver);
    assert!(next >= sliver + race.slice, "{next}");
    // The check then times the leader over the longer slice.
    assert_eq!(race.slice_done(sliver, next, 0.012, &mut build), None);
    let want = (1e-6 + 0.012) / (next - 10.0);
    assert!((race.pace - want).abs() < 1e-12, "{} {want}", race.pace);
}

/// A trial that beat the leader on a slice of lighter work for the leader's structure too
/// (the leader ran its first slices where the work was heaviest) leaves the leader a
/// runner-up: a later check tries it again, and the run ends on it.
#[test]
fn a_leader_beaten_on_a_lighter_slice_is_tried_again() {
    let mut race = Race::new(&scene(2000), Structure::Grid, 0.001);
    // The grid at 0.03 a unit over the first 5 units and 0.01 after; the loose grid at 0.02
    // throughout; the sweep and the brute force far slower.
    let wall = |s: Structure, from: f64, to: f64, _: f64| match s {
        Structure::Grid => {
            0.03 * (to.min(5.0) - from.min(5.0)) + 0.01 * (to.max(5.0) - from.max(5.0))
        }
        Structure::LooseGrid => 0.02 * (to - from),
        _ => 1.0 * (to - from),
    };
    let slices = run_with(&mut race, wall, 0.001);
    assert!(
        slices.iter().any(|s| s.structure == Structure::LooseGrid),
        "the loose grid's trial: {slices:?}"
    );
    assert_eq!(
        slices.last().unwrap().structure,
        Structure::Grid,
        "{slices:?}"
    );
}

/// A trial whose structure does little right after its build (fresh certificates that last:
/// a loose grid's regions) is measured until its pace is steady: the loose grid's pace
/// grows from nothing to three times the grid's over the 4 units after each build, then
/// stays there.
#[test]
fn a_trial_quiet_after_its_build_is_measured_until_steady() {
    // The wall seconds from `built` to `t`: the ramp's integral, then 0.03 a unit.
    let ramp = 4.0;
    let upto = |t: f64| {
        let r = t.min(ramp);
        0.03 * r * r / (2.0 * ramp) + 0.03 * (t - r).max(0.0)
    };
    let quiet = |s: Structure, from: f64, to: f64, built: f64| match s {
        Structure::LooseGrid => upto(to - built) - upto(from - built),
        Structure::Grid => 0.01 * (to - from),
        _ => to - from,
    };
    let mut race = Race::new(&scene(2000), Structure::Grid, 0.001);
    let slices = run_with(&mut race, quiet, 0.001);
    // Within the share of the grid's own run.
    let total: f64 = slices.iter().map(|s| s.wall_seconds).sum();
    assert!(total < 0.01 * 100.0 * (1.0 + SHARE), "{total} {slices:?}");
    assert_eq!(
        slices.last().unwrap().structure,
        Structure::Grid,
        "{slices:?}"
    );
}

/// Builds estimated on a sample are scaled by how far the start's own estimate fell short of
/// its measured build: every box structure's whole build here costs four times its sample's
/// estimate (0.04 s against 0.01 s), so a trial would cost its build and the leader's
/// rebuild, 0.08 s, most of the 0.1 s budget, and none is tried. Where the start's build is
/// its estimate, the same trials are tried.
#[test]
fn sampled_builds_are_scaled_by_the_starts_measured_one() {
    let trials = |start_build: f64, sampled: f64| {
        let mut race = Race::new(&scene(2000), Structure::Grid, start_build);
        let mut now = 0.0;
        while now < 100.0 {
            let to = race.slice_end(now);
            assert!(to > now, "the race stalls at {now}");
            let wall = paces(race.current()) * (to - now);
            // (The brute force's pairs far too dear to try.)
            let mut estimate = |s, _| {
                if s == Structure::BruteForce {
                    10.0
                } else {
                    sampled
                }
            };
            if race.slice_done(now, to, wall, &mut estimate).is_some() {
                race.switched(start_build);
            }
            now = to;
        }
        let slices = race.into_slices();
        assert_eq!(slices.last().unwrap().structure, Structure::Grid);
        slices
            .iter()
            .filter(|s| s.structure != Structure::Grid)
            .count()
    };
    // Estimated at 0.01: tried where the start's build took what its estimate said, not
    // where it took four times as long.
    assert_eq!(trials(0.04, 0.01), 0);
    assert!(trials(0.01, 0.01) > 0);
    // Estimated at 0.04, too dear to try, unless the start's build took a quarter of its
    // estimate (a sample's fixed costs, scaled up to all the objects).
    assert_eq!(trials(0.04, 0.04), 0);
    assert!(trials(0.01, 0.04) > 0);
}
