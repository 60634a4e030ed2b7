//! avian3d 0.8's step with its own broad phase (BVH) and with the kinetic plugin, side by side
//! in one run, on the rapier bench's standard scenes (`kinetic_scenes::engines::standard`:
//! pile, rain, gas, debris, drift, burst, asleep, kinematic): whole step, broad-phase time
//! (avian's `CollisionDiagnostics::broad_phase`, which avian resets at the start of every
//! step), avian's collider-tree upkeep beside it (`ColliderTreeDiagnostics`: AABB and BVH
//! updates and optimisation, paid on both sides, since spatial queries use the trees) and
//! pairs in the contact graph. Each run makes one physics step first, then puts the scene's
//! resting pieces to sleep as avian keeps them asleep (their islands), then times `S` steps.
//!
//! `cargo bench -p kinetic-avian --bench avian -- [N...] [--steps S] [--scenes pile,rain]
//! [--repeat K] [--csv PATH]` (default N = 1000 10000, S = 120, every scene, K = 3). The two
//! sides run K times, interleaved; each figure is the median of the K runs. Prints a markdown
//! table and writes it as CSV (default `docs/results/avian.csv`).
//!
//! `-- --space K [--from F] [--steps S] [--repeat R]` runs draws F to F + K - 1 of the engine
//! scene space (`kinetic_scenes::engines::space`) instead (default S = 60), and writes each
//! draw's ratios and the worst and median over the draws as the `avian` rows of
//! `docs/results/engines.csv` (or `--csv PATH`). With `--first` it times the first physics
//! step alone, which takes every collider in (each side builds its structure), and writes
//! the rows to `docs/results/engines-first-step.csv` (`steps` 1).

use avian3d::collider_tree::ColliderTreeDiagnostics;
use avian3d::collision::CollisionDiagnostics;
use avian3d::prelude::*;
use bevy::prelude::*;
use bevy::time::TimeUpdateStrategy;
use kinetic_avian::KineticBroadPhasePlugin;
use kinetic_scenes::engines::results::{self, DrawRow};
use kinetic_scenes::engines::{self, EngineScene, space};
use std::time::{Duration, Instant};

#[derive(Clone, Copy, Debug, PartialEq)]
enum Side {
    Avian,
    Kinetic,
}

/// One run's figures, per step.
#[derive(Clone, Copy, Default)]
struct Row {
    step_ms: f64,
    bp_ms: f64,
    tree_ms: f64,
    pairs: f64,
    touching: f64,
}

/// `steps` steps of `scene` on `side`, timed after the first physics step; with `first`, the
/// first physics step alone.
fn run(scene: &EngineScene, side: Side, steps: usize, first: bool) -> (Row, String) {
    let mut app = App::new();
    app.add_plugins((MinimalPlugins, TransformPlugin));
    let physics = PhysicsPlugins::default().build();
    match side {
        Side::Avian => app.add_plugins(physics),
        Side::Kinetic => app.add_plugins(
            physics
                .disable::<BvhBroadPhasePlugin>()
                .add(KineticBroadPhasePlugin::new()),
        ),
    };
    app.insert_resource(TimeUpdateStrategy::ManualDuration(Duration::from_secs_f64(
        1.0 / 64.0,
    )));
    app.finish();
    let entities = kinetic_scenes::avian::spawn(scene, app.world_mut());
    // The first update sets the clocks: no physics step yet. The second is a step, which
    // makes the islands the resting pieces then sleep in.
    app.update();
    if first {
        let start = Instant::now();
        app.update();
        let row = Row {
            step_ms: start.elapsed().as_secs_f64() * 1e3,
            bp_ms: app
                .world()
                .resource::<CollisionDiagnostics>()
                .broad_phase
                .as_secs_f64()
                * 1e3,
            pairs: app.world().resource::<ContactGraph>().iter_active().count() as f64,
            ..Row::default()
        };
        return (row, structure(&app));
    }
    app.update();
    kinetic_scenes::avian::put_to_sleep(scene, app.world_mut(), &entities);
    let mut row = Row::default();
    let (mut bp, mut tree) = (Duration::ZERO, Duration::ZERO);
    let start = Instant::now();
    for _ in 0..steps {
        app.update();
        // Avian resets its diagnostics at the start of each step: these are this step's.
        bp += app.world().resource::<CollisionDiagnostics>().broad_phase;
        let t = app.world().resource::<ColliderTreeDiagnostics>();
        tree += t.update + t.optimize;
        let graph = app.world().resource::<ContactGraph>();
        row.pairs += graph.iter_active().count() as f64;
        row.touching += graph.iter_active_touching().count() as f64;
    }
    let n = steps as f64;
    row.step_ms = start.elapsed().as_secs_f64() * 1e3 / n;
    row.bp_ms = bp.as_secs_f64() * 1e3 / n;
    row.tree_ms = tree.as_secs_f64() * 1e3 / n;
    row.pairs /= n;
    row.touching /= n;
    (row, structure(&app))
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// The kinetic plugin's mode at the end of a run, as its diagnostics name it.
fn structure(app: &App) -> String {
    app.world()
        .get_resource::<kinetic_avian::KineticBroadPhase>()
        .map_or_else(|| "bvh".to_string(), |k| k.structure_name().to_string())
}

/// Runs draws `from..from + count` of the scene space and writes the `avian` rows of `csv`
/// (with `first`, of the first physics step alone).
fn space_draws(from: u64, count: u64, steps: usize, repeat: usize, first: bool, csv: &str) {
    let steps = if first { 1 } else { steps };
    let timed = if first {
        "the first physics step".to_string()
    } else {
        format!("{steps} steps at 64 Hz")
    };
    println!("avian3d 0.8, {timed}, medians of {repeat} interleaved runs\n");
    println!("| seed | draw | step | broad phase | pairs | kinetic as |");
    println!("|---|---|---|---|---|---|");
    let mut rows = Vec::new();
    for seed in from..from + count {
        let d = space::draw(seed);
        let mut runs: [Vec<Row>; 2] = [Vec::new(), Vec::new()];
        let mut name = String::new();
        for _ in 0..repeat {
            runs[0].push(run(&d.scene, Side::Avian, steps, first).0);
            let (row, s) = run(&d.scene, Side::Kinetic, steps, first);
            runs[1].push(row);
            name = s;
        }
        let side = |k: usize| {
            let med = |f: fn(&Row) -> f64| median(runs[k].iter().map(f).collect());
            results::Side {
                step_ms: med(|r| r.step_ms),
                broad_phase_ms: med(|r| r.bp_ms),
                pairs: med(|r| r.pairs),
            }
        };
        let row = DrawRow::new(&d, steps, side(0), side(1), &name);
        let [s, b, p] = row.ratios();
        println!("| {seed} | {d} | {s:.2}x | {b:.2}x | {p:.2}x | {name} |");
        rows.push(row);
    }
    results::report("avian", &rows, csv);
}

fn main() {
    let mut ns = Vec::new();
    let (mut steps, mut repeat) = (120, 3);
    let mut scenes: Vec<String> = engines::STANDARD.iter().map(|s| s.to_string()).collect();
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let mut csv = None;
    let (mut draws, mut from, mut steps_given, mut first) = (None, 0u64, false, false);
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = |name: &str| {
            args.next()
                .unwrap_or_else(|| panic!("{name} needs a value"))
        };
        match a.as_str() {
            "--steps" => {
                steps = value("--steps").parse().expect("--steps: a number");
                steps_given = true;
            }
            "--space" => draws = Some(value("--space").parse().expect("--space: a number")),
            "--from" => from = value("--from").parse().expect("--from: a seed"),
            "--repeat" => repeat = value("--repeat").parse().expect("--repeat: a number"),
            "--scenes" => scenes = value("--scenes").split(',').map(str::to_string).collect(),
            "--csv" => csv = Some(value("--csv")),
            "--first" => first = true,
            "--bench" => {}
            n => ns.push(n.parse::<usize>().expect("N: a number of bodies")),
        }
    }
    if let Some(count) = draws {
        let file = if first {
            "engines-first-step"
        } else {
            "engines"
        };
        let csv = csv.unwrap_or(format!("{root}/docs/results/{file}.csv"));
        space_draws(
            from,
            count,
            if steps_given { steps } else { 60 },
            repeat,
            first,
            &csv,
        );
        return;
    }
    let csv = csv.unwrap_or(format!("{root}/docs/results/avian.csv"));
    if ns.is_empty() {
        ns = vec![1000, 10000];
    }
    println!("avian3d 0.8, {steps} steps at 64 Hz, median of {repeat} interleaved runs\n");
    println!(
        "| scene | bodies | side | step (ms) | broad phase (ms) | collider trees (ms) | pairs | touching | broad phase kinetic/avian | step kinetic/avian |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut lines = vec![
        "scene,bodies,steps,side,step_ms,broad_phase_ms,collider_tree_ms,pairs,touching"
            .to_string(),
    ];
    for scene_name in &scenes {
        for &n in &ns {
            let scene = engines::standard(scene_name, n).unwrap_or_else(|| {
                panic!("unknown scene {scene_name}: one of {:?}", engines::STANDARD)
            });
            let mut runs: [Vec<Row>; 2] = [Vec::new(), Vec::new()];
            for _ in 0..repeat {
                runs[0].push(run(&scene, Side::Avian, steps, false).0);
                runs[1].push(run(&scene, Side::Kinetic, steps, false).0);
            }
            let med = |side: usize, f: fn(&Row) -> f64| median(runs[side].iter().map(f).collect());
            let rows: Vec<Row> = (0..2)
                .map(|s| Row {
                    step_ms: med(s, |r| r.step_ms),
                    bp_ms: med(s, |r| r.bp_ms),
                    tree_ms: med(s, |r| r.tree_ms),
                    pairs: med(s, |r| r.pairs),
                    touching: med(s, |r| r.touching),
                })
                .collect();
            for (s, side) in [Side::Avian, Side::Kinetic].into_iter().enumerate() {
                let r = rows[s];
                let ratio = if side == Side::Kinetic {
                    format!(
                        "{:.2} | {:.2}",
                        r.bp_ms / rows[0].bp_ms,
                        r.step_ms / rows[0].step_ms
                    )
                } else {
                    " | ".to_string()
                };
                println!(
                    "| {scene_name} | {n} | {side:?} | {:.2} | {:.3} | {:.3} | {:.0} | {:.0} | {ratio} |",
                    r.step_ms, r.bp_ms, r.tree_ms, r.pairs, r.touching
                );
                lines.push(format!(
                    "{scene_name},{n},{steps},{},{:.3},{:.4},{:.4},{:.0},{:.0}",
                    format!("{side:?}").to_lowercase(),
                    r.step_ms,
                    r.bp_ms,
                    r.tree_ms,
                    r.pairs,
                    r.touching
                ));
            }
        }
    }
    match std::fs::write(&csv, lines.join("\n") + "\n") {
        Ok(()) => println!("\nwrote {csv}"),
        Err(e) => eprintln!("could not write {csv}: {e}"),
    }
}
