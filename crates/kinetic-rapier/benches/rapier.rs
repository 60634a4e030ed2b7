//! rapier 0.27's step with its default broad phase and with the kinetic one, side by side in
//! one run, on the standard scenes (`kinetic_scenes::engines::standard`: pile, rain, gas,
//! debris, drift, burst, asleep, kinematic): whole step, broad-phase time (rapier's own
//! counters) and pairs handed to the narrow phase.
//!
//! `cargo bench -p kinetic-rapier --bench rapier -- [N...] [--steps S] [--scenes pile,rain]
//! [--repeat K] [--split P] [--csv PATH]` (default N = 1000 10000 50000, S = 120, every scene,
//! K = 1). Each side runs K times, the two interleaved, and shows its run of median
//! broad-phase time (timings on a shared machine drift by tens of percent between runs).
//! Prints a markdown table and writes it as CSV (default `docs/results/rapier.csv`); "after
//! step 1" is the broad phase's mean over the steps after the first, which builds each side's
//! structure from scratch. `--split P` adds a table of each side's broad-phase time in all over
//! the steps before step P and from step P on (the rain: while it falls, and once it piles up).
//!
//! `-- --space K [--from F] [--steps S] [--repeat R]` runs draws F to F + K - 1 of the engine
//! scene space (`kinetic_scenes::engines::space`) instead (default S = 60, R = 3), each side
//! R times interleaved, and writes each draw's ratios and the worst and median over the draws
//! as the `rapier` rows of `docs/results/engines.csv` (or `--csv PATH`). Each draw also runs
//! rapier's own broad phase a second time with the pairs of each update handed over in
//! reverse order (interleaved with the others): its step over the own step is how far the
//! step moves with the order of the pairs alone, the step ratio's reference. With `--first`
//! it times the first step alone, which takes every collider in (each side builds its
//! structure), and writes the rows to `docs/results/engines-first-step.csv` (`steps` 1).

use kinetic_rapier::KineticBroadPhase;
use kinetic_scenes::engines::results::{self, DrawRow};
use kinetic_scenes::engines::{STANDARD, space};
use kinetic_scenes::rapier::{RapierScene, standard};
use rapier3d::prelude::*;
use std::time::Instant;

#[derive(Default)]
struct Row {
    step_ms: f64,
    bp_ms: f64,
    /// Broad-phase ms per step after the first (which builds the structure from scratch).
    bp_after_ms: f64,
    np_ms: f64,
    pairs: f64,
    touching: f64,
    /// Broad-phase ms in all over the steps before the split and from it on.
    bp_parts: [f64; 2],
}

fn run(scene: RapierScene, bp: &mut dyn BroadPhase, steps: usize, split: usize) -> Row {
    let RapierScene {
        mut bodies,
        mut colliders,
        gravity,
    } = scene;
    let mut pipeline = PhysicsPipeline::new();
    pipeline.counters.enable();
    let params = IntegrationParameters::default();
    let (mut islands, mut narrow) = (IslandManager::new(), NarrowPhase::new());
    let (mut joints, mut multibody) = (ImpulseJointSet::new(), MultibodyJointSet::new());
    let mut ccd = CCDSolver::new();
    let mut row = Row::default();
    let start = Instant::now();
    for k in 0..steps {
        pipeline.step(
            &gravity,
            &params,
            &mut islands,
            bp,
            &mut narrow,
            &mut bodies,
            &mut colliders,
            &mut joints,
            &mut multibody,
            &mut ccd,
            &(),
            &(),
        );
        let bp = pipeline.counters.broad_phase_time_ms();
        row.bp_ms += bp;
        row.bp_parts[usize::from(k >= split)] += bp;
        if k > 0 {
            row.bp_after_ms += bp;
        }
        row.np_ms += pipeline.counters.narrow_phase_time_ms();
        row.pairs += narrow.contact_pairs().count() as f64;
        row.touching += narrow
            .contact_pairs()
            .filter(|p| p.has_any_active_contact)
            .count() as f64;
    }
    row.step_ms = start.elapsed().as_secs_f64() * 1e3;
    let s = steps as f64;
    Row {
        step_ms: row.step_ms / s,
        bp_ms: row.bp_ms / s,
        bp_after_ms: row.bp_after_ms / (s - 1.0).max(1.0),
        np_ms: row.np_ms / s,
        pairs: row.pairs / s,
        touching: row.touching / s,
        bp_parts: row.bp_parts,
    }
}

/// rapier's own broad phase handing each update's pair events over in reverse order: the
/// same pairs, in another order.
#[derive(Default)]
struct Reversed(DefaultBroadPhase);

impl BroadPhase for Reversed {
    fn update(
        &mut self,
        params: &IntegrationParameters,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        modified: &[ColliderHandle],
        removed: &[ColliderHandle],
        events: &mut Vec<BroadPhasePairEvent>,
    ) {
        let from = events.len();
        self.0
            .update(params, colliders, bodies, modified, removed, events);
        events[from..].reverse();
    }
}

/// The run of median broad-phase time (with what else the run kept).
fn median<T>(mut runs: Vec<(Row, T)>) -> (Row, T) {
    runs.sort_by(|a, b| a.0.bp_ms.total_cmp(&b.0.bp_ms));
    let mid = runs.len() / 2;
    runs.swap_remove(mid)
}

/// The kinetic broad phase, with the structure `KINETIC_STRUCTURE` names if any.
fn kinetic() -> KineticBroadPhase {
    let named = std::env::var("KINETIC_STRUCTURE").ok();
    match named.as_deref() {
        Some("loose-grid") => KineticBroadPhase::default().with_loose_grid(true),
        Some("grid") => KineticBroadPhase::default().with_loose_grid(false),
        _ => KineticBroadPhase::default(),
    }
}

/// Runs draws `from..from + count` of the scene space and writes the `rapier` rows of `csv`
/// (with `first`, of the first step alone, and no run with the pairs reversed).
fn space_draws(from: u64, count: u64, steps: usize, repeat: usize, first: bool, csv: &str) {
    let steps = if first { 1 } else { steps };
    println!("rapier 0.27, {steps} steps at 60 Hz, medians of {repeat} interleaved runs\n");
    println!("| seed | draw | step | broad phase | pairs | kinetic as | own, pairs reversed |");
    println!("|---|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for seed in from..from + count {
        let d = space::draw(seed);
        let make = || RapierScene::from(d.scene.clone());
        let (mut ds, mut ks, mut rs) = (Vec::new(), Vec::new(), Vec::new());
        for _ in 0..repeat {
            ds.push(run(make(), &mut DefaultBroadPhase::new(), steps, steps));
            if !first {
                rs.push(run(make(), &mut Reversed::default(), steps, steps).step_ms);
            }
            let mut kbp = kinetic();
            ks.push(run(make(), &mut kbp, steps, steps));
            if ks.len() == repeat {
                let side = |rs: &[Row]| {
                    let med = |f: fn(&Row) -> f64| {
                        let mut xs: Vec<f64> = rs.iter().map(f).collect();
                        xs.sort_by(f64::total_cmp);
                        xs[xs.len() / 2]
                    };
                    results::Side {
                        step_ms: med(|r| r.step_ms),
                        broad_phase_ms: med(|r| r.bp_ms),
                        pairs: med(|r| r.pairs),
                    }
                };
                if std::env::var_os("KINETIC_COUNTERS").is_some() {
                    println!("{:?}", kbp.stats());
                }
                let mut row = DrawRow::new(&d, steps, side(&ds), side(&ks), kbp.structure_name());
                rs.sort_by(f64::total_cmp);
                row.own_reversed_step_ms = rs.get(rs.len() / 2).copied();
                let [s, b, p] = row.ratios();
                println!(
                    "| {seed} | {d} | {s:.2}x | {b:.2}x | {p:.2}x | {} | {:.2}x |",
                    row.structure,
                    row.reversed_ratio().unwrap_or(f64::NAN)
                );
                rows.push(row);
            }
        }
    }
    results::report("rapier", &rows, csv);
}

fn main() {
    let args: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| a != "--bench")
        .collect();
    let mut sizes = Vec::new();
    let mut steps = 120;
    let mut only: Option<Vec<String>> = None;
    let mut repeat = 1;
    let (mut steps_given, mut repeat_given) = (false, false);
    let mut split: Option<usize> = None;
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let mut csv = None;
    let (mut draws, mut from, mut first) = (None, 0u64, false);
    let mut it = args.iter();
    while let Some(a) = it.next() {
        if a == "--steps" {
            steps = it.next().and_then(|s| s.parse().ok()).expect("--steps S");
            steps_given = true;
        } else if a == "--space" {
            draws = Some(
                it.next()
                    .and_then(|s| s.parse().ok())
                    .expect("--space K (draws)"),
            );
        } else if a == "--from" {
            from = it
                .next()
                .and_then(|s| s.parse().ok())
                .expect("--from F (a seed)");
        } else if a == "--repeat" {
            repeat = it
                .next()
                .and_then(|s| s.parse().ok())
                .filter(|&k: &usize| k > 0)
                .expect("--repeat K (K > 0)");
            repeat_given = true;
        } else if a == "--split" {
            split = Some(
                it.next()
                    .and_then(|s| s.parse().ok())
                    .expect("--split P (a step)"),
            );
        } else if a == "--csv" {
            csv = Some(it.next().expect("--csv PATH").clone());
        } else if a == "--first" {
            first = true;
        } else if a == "--scenes" {
            let list = it.next().expect("--scenes pile,rain");
            only = Some(list.split(',').map(str::to_string).collect());
        } else if let Ok(n) = a.parse::<usize>() {
            sizes.push(n);
        }
    }
    if let Some(count) = draws {
        let file = if first {
            "engines-first-step"
        } else {
            "engines"
        };
        let csv = csv.unwrap_or(format!("{root}/docs/results/{file}.csv"));
        let steps = if steps_given { steps } else { 60 };
        let repeat = if repeat_given { repeat } else { 3 };
        space_draws(from, count, steps, repeat, first, &csv);
        return;
    }
    let csv = csv.unwrap_or(format!("{root}/docs/results/rapier.csv"));
    if sizes.is_empty() {
        sizes = vec![1000, 10000, 50000];
    }
    println!(
        "{steps} steps at 60 Hz; times are means per step (each side's run of median broad-phase time of {repeat}); after step 1: the broad phase's mean over the steps after the first (the first builds the structure); pairs: the narrow phase's pairs, touching: those with an active contact\n"
    );
    println!(
        "| scene | n | broad phase | step ms | broad phase ms | after step 1 | narrow phase ms | pairs | touching | kinetic: structure, events/step, re-plans/step |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut parts = Vec::new();
    let mut lines = vec![
        "scene,bodies,steps,side,step_ms,broad_phase_ms,after_first_ms,narrow_phase_ms,pairs,touching,structure,events_per_step,replans_per_step".to_string(),
    ];
    for name in STANDARD {
        if only.as_ref().is_some_and(|o| !o.iter().any(|s| s == name)) {
            continue;
        }
        let make = |n: usize| -> RapierScene { standard(name, n).expect("a standard scene") };
        for &n in &sizes {
            let (mut ds, mut ks) = (Vec::new(), Vec::new());
            for _ in 0..repeat {
                let at = split.unwrap_or(steps);
                ds.push((run(make(n), &mut DefaultBroadPhase::new(), steps, at), ()));
                let mut kbp = kinetic();
                ks.push((run(make(n), &mut kbp, steps, at), kbp));
            }
            let ((d, ()), (k, kbp)) = (median(ds), median(ks));
            let s = kbp.stats();
            for (label, r, extra) in [
                ("default (BVH)", &d, String::new()),
                (
                    "kinetic",
                    &k,
                    format!(
                        "{}, {:.0}, {:.1}{}",
                        kbp.structure_name(),
                        s.events as f64 / s.steps as f64,
                        s.replans as f64 / s.steps as f64,
                        if std::env::var_os("KINETIC_COUNTERS").is_some() {
                            format!(" {:?} {:?}", kbp.structure_counters(), s)
                        } else {
                            String::new()
                        }
                    ),
                ),
            ] {
                println!(
                    "| {name} | {n} | {label} | {:.2} | {:.3} | {:.3} | {:.2} | {:.0} | {:.0} | {extra} |",
                    r.step_ms, r.bp_ms, r.bp_after_ms, r.np_ms, r.pairs, r.touching
                );
                let (side, structure, events, replans) = if label == "kinetic" {
                    let per = |x: u64| x as f64 / s.steps.max(1) as f64;
                    (
                        "kinetic",
                        kbp.structure_name(),
                        per(s.events),
                        per(s.replans),
                    )
                } else {
                    ("default", "bvh", 0.0, 0.0)
                };
                lines.push(format!(
                    "{name},{n},{steps},{side},{:.3},{:.4},{:.4},{:.3},{:.0},{:.0},{structure},{events:.1},{replans:.2}",
                    r.step_ms, r.bp_ms, r.bp_after_ms, r.np_ms, r.pairs, r.touching
                ));
            }
            println!(
                "| {name} | {n} | kinetic / default | {:.2}x | {:.2}x | {:.2}x | {:.2}x | {:.2}x | | |",
                k.step_ms / d.step_ms,
                k.bp_ms / d.bp_ms,
                k.bp_after_ms / d.bp_after_ms,
                k.np_ms / d.np_ms,
                k.pairs / d.pairs
            );
            parts.push((name, n, d.bp_parts, k.bp_parts));
        }
    }
    match std::fs::write(&csv, lines.join("\n") + "\n") {
        Ok(()) => println!("\nwrote {csv}"),
        Err(e) => eprintln!("could not write {csv}: {e}"),
    }
    if let Some(p) = split {
        println!(
            "\nBroad-phase ms in all (the same runs), steps 0 to {} and {p} to {}:\n",
            p.saturating_sub(1),
            steps.saturating_sub(1)
        );
        println!("| scene | n | steps | default | kinetic | kinetic / default |");
        println!("|---|---|---|---|---|---|");
        for (name, n, d, k) in parts {
            for (i, range) in [
                format!("0-{}", p.saturating_sub(1)),
                format!("{p}-{}", steps.saturating_sub(1)),
            ]
            .iter()
            .enumerate()
            {
                println!(
                    "| {name} | {n} | {range} | {:.1} | {:.1} | {:.2}x |",
                    d[i],
                    k[i],
                    k[i] / d[i]
                );
            }
        }
    }
}
