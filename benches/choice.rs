//! The default (no structure named: the model's pick, raced against its shortlist as the run
//! goes) against every structure, on draws of the scene space (`kinetic_scenes::space`) or on
//! the choice family (`kinetic_scenes::choice`): each structure's wall time (stopped at a
//! budget once it is far behind the fastest), the default's, and the default's time over the
//! fastest structure's, per draw, with the worst and the median. Writes
//! `docs/results/choice.csv`.
//!
//! `cargo bench --bench choice -- [--draws K] [--seed S] [--max-objects N] [--budget SECONDS]
//! [--out FILE]` draws K scenes (default 40) from seed S (default 1) with at most N objects
//! (default 100,000); `-- --family [SIZES...] [--kinds a,b,...]` runs the family instead;
//! `--scenes DIR` also writes each scene there (`draw-SEED.json`) for `kinetic-collide run`.
//! Every run is a fresh process of the tool (`run --events none --stats`, timed by its own
//! `wall_seconds`), as a user's would be, killed at its budget. A screen times the default
//! and every structure once (a structure far behind the fastest is stopped at four times
//! its time); then the default and the fastest structure run three times each, interleaved
//! (twice where the fastest takes over 3 s), and each side's median counts: the screen's
//! runs are left out, as the fastest was picked for its screen time. Runs under 0.1 s are the median of five. The
//! brute force is left out above 3,000 objects (its build alone makes n^2 / 2
//! certificates).

use kinetic_collide::Structure;
use kinetic_collide::scene::Scene;
use kinetic_scenes::choice::{KINDS, choice_scene, response_name, world_name};
use kinetic_scenes::space;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// Runs shorter than this many seconds...
const SHORT: f64 = 0.1;
/// ... are timed this many times, and the median counts.
const SHORT_RUNS: usize = 5;
/// The default and the fastest structure are then timed this many times each, interleaved,
/// and each side's median counts...
const DUELS: usize = 3;
/// ... or this many times where the fastest takes longer than [`DUEL_LONG`] seconds (the
/// median of two: their mean).
const DUELS_LONG: usize = 2;
/// See [`DUELS_LONG`].
const DUEL_LONG: f64 = 3.0;
/// Timings under this many seconds count as this in ratios (noise below it).
const FLOOR: f64 = 1e-3;

/// One run of one scene.
#[derive(Clone)]
struct Timing {
    seconds: f64,
    /// Stopped at the budget before the horizon.
    stopped: bool,
    /// The structure that ended the run.
    structure: Structure,
}

/// Runs `scene` (written at `path`) on `s` (None: the default) in a fresh process of the
/// tool, as a user would (`run --events none --stats`), killed after `budget` seconds; the
/// time is the run's own `wall_seconds` (the detection, without reading the scene).
fn timed_once(path: &Path, s: Option<Structure>, budget: f64) -> Option<Timing> {
    let stats = path.with_extension("stats.json");
    let _ = std::fs::remove_file(&stats);
    let mut command = Command::new(env!("CARGO_BIN_EXE_kinetic-collide"));
    command
        .arg("run")
        .arg(path)
        .args(["--events", "none", "--stats"])
        .arg(&stats)
        .stdout(Stdio::null())
        .stderr(Stdio::null());
    if let Some(s) = s {
        command.args(["--structure", s.name()]);
    }
    let mut child = command.spawn().ok()?;
    let start = Instant::now();
    loop {
        if child.try_wait().ok()?.is_some() {
            break;
        }
        if start.elapsed().as_secs_f64() > budget {
            let _ = child.kill();
            let _ = child.wait();
            return Some(Timing {
                seconds: budget,
                stopped: true,
                structure: s.unwrap_or(Structure::BruteForce),
            });
        }
        std::thread::sleep(Duration::from_millis(1));
    }
    let text = std::fs::read_to_string(&stats).ok()?;
    let v: serde_json::Value = serde_json::from_str(&text).ok()?;
    Some(Timing {
        seconds: v["wall_seconds"].as_f64()?,
        stopped: false,
        structure: Structure::from_name(v["structure"].as_str()?)?,
    })
}

/// [`timed_once`]; for short runs the median of five.
fn timed(scene: &Path, s: Option<Structure>, budget: f64) -> Option<Timing> {
    let t = timed_once(scene, s, budget)?;
    if t.stopped || t.seconds >= SHORT {
        return Some(t);
    }
    let mut runs = vec![t];
    for _ in 1..SHORT_RUNS {
        runs.extend(timed_once(scene, s, budget));
    }
    Some(middle(runs))
}

/// The run of median time.
fn middle(mut runs: Vec<Timing>) -> Timing {
    runs.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    runs.swap_remove(runs.len() / 2)
}

/// The default and every structure on one scene.
struct Row {
    default: Timing,
    structures: Vec<(Structure, Timing)>,
}

impl Row {
    /// The fastest structure that finished, and its time.
    fn fastest(&self) -> (Structure, f64) {
        self.structures
            .iter()
            .filter(|(_, t)| !t.stopped)
            .map(|(s, t)| (*s, t.seconds))
            .fold((self.default.structure, f64::INFINITY), |a, b| {
                if b.1 < a.1 { b } else { a }
            })
    }

    /// The default's time over the fastest structure's.
    fn ratio(&self) -> f64 {
        let mine = if self.default.stopped {
            f64::INFINITY
        } else {
            self.default.seconds
        };
        mine.max(FLOOR) / self.fastest().1.max(FLOOR)
    }

    fn times(&self) -> String {
        let t: Vec<String> = self
            .structures
            .iter()
            .map(|(s, t)| {
                let over = if t.stopped { ">" } else { "" };
                format!("{}:{over}{:.4}", s.name(), t.seconds)
            })
            .collect();
        t.join(" ")
    }
}

fn measure(scene: &Scene, budget: f64) -> Option<Row> {
    let path = std::env::temp_dir().join(format!(
        "kinetic-collide-choice-{}.json",
        std::process::id()
    ));
    std::fs::write(&path, scene.to_json()).ok()?;
    // The screen: the default, then every structure, each stopped once far behind.
    let mut defaults = vec![timed(&path, None, budget)?];
    let mut structures: Vec<(Structure, Timing)> = Vec::new();
    for s in Structure::ALL {
        if !s.applies_to(scene) || (s == Structure::BruteForce && scene.objects.len() > 3000) {
            continue;
        }
        let best = structures
            .iter()
            .filter(|(_, t)| !t.stopped)
            .map(|(_, t)| t.seconds)
            .fold(defaults[0].seconds, f64::min);
        let cap = budget.min((best * 4.0).max(0.5));
        if let Some(t) = timed(&path, Some(s), cap) {
            structures.push((s, t));
        }
    }
    // The duel: the default and the fastest structure of the screen, interleaved, DUELS
    // times each (DUELS_LONG where the fastest takes over DUEL_LONG seconds); each side's
    // median run counts. The screen's runs are left out: the fastest was picked for being
    // the quickest of its screen, which would count in its favour.
    let fastest = structures
        .iter()
        .filter(|(_, t)| !t.stopped)
        .min_by(|a, b| a.1.seconds.total_cmp(&b.1.seconds))
        .map(|(s, t)| (*s, t.clone()));
    if let Some((fast, first)) = fastest {
        let rounds = if first.seconds > DUEL_LONG {
            DUELS_LONG
        } else {
            DUELS
        };
        let (mut mine, mut runs) = (Vec::new(), Vec::new());
        for _ in 0..rounds {
            mine.extend(timed(&path, None, budget));
            runs.extend(timed(&path, Some(fast), budget));
        }
        if !mine.is_empty() {
            defaults = mine;
        }
        if !runs.is_empty() {
            let kept = middle(runs);
            for (s, t) in structures.iter_mut() {
                if *s == fast {
                    *t = kept.clone();
                }
            }
        }
    }
    let _ = std::fs::remove_file(&path);
    Some(Row {
        default: middle(defaults),
        structures,
    })
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return f64::NAN;
    }
    let m = v.len() / 2;
    if v.len() % 2 == 1 {
        v[m]
    } else {
        (v[m - 1] + v[m]) / 2.0
    }
}

fn main() {
    let mut draws = 40usize;
    let mut seed = 1u64;
    let mut max_objects = 100_000usize;
    let mut budget: f64 = 20.0;
    let mut out = String::from("docs/results/choice.csv");
    let mut family = false;
    let mut sizes = Vec::new();
    let mut kinds: Option<Vec<String>> = None;
    let mut scenes_dir: Option<String> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut value = || args.next().unwrap_or_default();
        match a.as_str() {
            "--draws" => draws = value().parse().unwrap_or(draws),
            "--seed" => seed = value().parse().unwrap_or(seed),
            "--max-objects" => max_objects = value().parse().unwrap_or(max_objects),
            "--budget" => budget = value().parse().unwrap_or(budget),
            "--out" => out = value(),
            "--family" => family = true,
            "--scenes" => scenes_dir = Some(value()),
            "--kinds" => kinds = Some(value().split(',').map(String::from).collect()),
            "--bench" => {}
            _ => sizes.extend(a.parse::<usize>().ok()),
        }
    }
    let scenes: Vec<(String, String, Scene)> = if family {
        if sizes.is_empty() {
            sizes = vec![100, 1000, 10000];
        }
        let mut v = Vec::new();
        for &n in &sizes {
            for kind in KINDS {
                if kinds.as_ref().is_some_and(|k| !k.iter().any(|k| k == kind)) {
                    continue;
                }
                if let Some(scene) = choice_scene(kind, n, 1) {
                    v.push((format!("{kind}-{n}"), kind.to_string(), scene));
                }
            }
        }
        v
    } else {
        (seed..seed + draws as u64)
            .map(|s| {
                let d = space::draw(s, max_objects);
                (s.to_string(), d.label, d.scene)
            })
            .collect()
    };
    let mut csv = String::from(
        "draw,scene,objects,world,response,default_structure,default_seconds,fastest,fastest_seconds,ratio,times\n",
    );
    println!("| draw | scene | default | fastest | default / fastest |");
    println!("|---|---|---|---|---|");
    let mut ratios = Vec::new();
    for (id, label, scene) in &scenes {
        if let Some(dir) = &scenes_dir {
            let _ = std::fs::create_dir_all(dir);
            let path = std::path::Path::new(dir).join(format!("draw-{id}.json"));
            if let Err(e) = std::fs::write(&path, scene.to_json()) {
                eprintln!("{}: {e}", path.display());
            }
        }
        let Some(row) = measure(scene, budget) else {
            eprintln!("{id}: {label}: the default did not run");
            continue;
        };
        let (fast, best) = row.fastest();
        let ratio = row.ratio();
        ratios.push(ratio);
        println!(
            "| {id} | {label} | {} {:.4} s | {} {:.4} s | {ratio:.2} |",
            row.default.structure.name(),
            row.default.seconds,
            fast.name(),
            best
        );
        csv.push_str(&format!(
            "{id},{label},{},{},{},{},{:.6},{},{:.6},{ratio:.3},{}\n",
            scene.objects.len(),
            world_name(scene),
            if scene.periodic.is_some() {
                "periodic"
            } else {
                response_name(scene)
            },
            row.default.structure.name(),
            row.default.seconds,
            fast.name(),
            best,
            row.times()
        ));
    }
    // A draw on which every run passed the budget has no ratio: it is counted apart.
    let over = ratios.iter().filter(|r| r.is_nan()).count();
    ratios.retain(|r| !r.is_nan());
    let worst = ratios.iter().copied().fold(f64::NAN, f64::max);
    let mid = median(ratios.clone());
    println!(
        "\n{} scenes: worst default / fastest {worst:.2}, median {mid:.2}; {over} with every \
         run over the {budget} s budget",
        ratios.len()
    );
    csv.push_str(&format!(
        "worst,,,,,,,,,{worst:.3},\nmedian,,,,,,,,,{mid:.3},\n"
    ));
    if let Some(dir) = std::path::Path::new(&out).parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    match std::fs::write(&out, csv) {
        Ok(()) => println!("wrote {out}"),
        Err(e) => eprintln!("{out}: {e}"),
    }
}
