//! The default choice of structure against every structure, on the choice family
//! (`kinetic_scenes::choice`): each structure's wall time on each scene (stopped at a budget
//! once it is far behind the fastest), the default's pick and its time over the fastest's.
//! Writes `docs/results/choice.csv`.
//!
//! `cargo bench --bench choice -- [SIZES...] [--budget SECONDS] [--kinds a,b,...]
//! [--structures a,b,...] [--out FILE]` (sizes default to 100 1000 10000; `--structures`
//! times only those beside the default's pick, for runs at 1e6 where a slow build alone
//! would take minutes). The brute force is left out above 3,000 objects: its
//! build alone makes n^2 / 2 certificates, and a budget stops runs only between events.
//! Runs under 20 ms are the best of five.

use kinetic_collide::Structure;
use kinetic_collide::run::{Stream, run_scene_streamed};
use kinetic_scenes::choice::{ChoiceCase, KINDS, choice_scene, response_name, world_name};
use std::ops::ControlFlow;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// Runs shorter than this many seconds...
const SHORT: f64 = 0.02;
/// ... are timed this many times, and the best counts.
const SHORT_RUNS: usize = 5;

/// One structure's run of one scene.
struct Timing {
    seconds: f64,
    /// Stopped at the budget before the horizon.
    stopped: bool,
    events: u64,
    contacts: u64,
}

fn timed(scene: &kinetic_collide::scene::Scene, s: Structure, budget: f64) -> Option<Timing> {
    let stop = Arc::new(AtomicBool::new(false));
    let done = Arc::new(AtomicBool::new(false));
    let timer = {
        let (stop, done) = (stop.clone(), done.clone());
        std::thread::spawn(move || {
            let start = std::time::Instant::now();
            while !done.load(Ordering::Relaxed) {
                if start.elapsed().as_secs_f64() > budget {
                    stop.store(true, Ordering::Relaxed);
                    return;
                }
                std::thread::sleep(Duration::from_millis(5));
            }
        })
    };
    let mut sink = |_: &[kinetic_collide::ContactEvent]| ControlFlow::Continue(());
    let mut stream = Stream {
        sink: &mut sink,
        stop: Some(&stop),
    };
    let out = run_scene_streamed(scene, Some(s), &[], &mut |_, _| {}, &mut stream);
    done.store(true, Ordering::Relaxed);
    let _ = timer.join();
    let out = out.ok()?;
    Some(Timing {
        seconds: out.wall_seconds,
        stopped: out.interrupted.is_some(),
        events: out.stats.events_total(),
        contacts: out.stats.begins,
    })
}

fn main() {
    let mut sizes = Vec::new();
    let mut budget: f64 = 20.0;
    let mut out = String::from("docs/results/choice.csv");
    let mut kinds: Option<Vec<String>> = None;
    let mut only: Option<Vec<String>> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--budget" => budget = args.next().and_then(|v| v.parse().ok()).unwrap_or(budget),
            "--out" => out = args.next().unwrap_or(out),
            "--kinds" => {
                kinds = args
                    .next()
                    .map(|k| k.split(',').map(String::from).collect())
            }
            "--structures" => {
                only = args
                    .next()
                    .map(|k| k.split(',').map(String::from).collect())
            }
            "--bench" => {}
            _ => sizes.extend(a.parse::<usize>().ok()),
        }
    }
    if sizes.is_empty() {
        sizes = vec![100, 1000, 10000];
    }
    let mut csv = String::from(
        "kind,n,world,response,structure,seconds,stopped,events,contacts,events_per_contact,default\n",
    );
    println!("| scene | n | default | default / fastest | fastest | times (s) |");
    println!("|---|---|---|---|---|---|");
    let mut worst: f64 = 1.0;
    // Scenes are built one at a time, and only those of the kinds asked for: at 1e6 objects
    // the kinds that place balls apart take minutes to build.
    let cases = sizes
        .iter()
        .flat_map(|&n| KINDS.iter().map(move |&kind| (kind, n)));
    for (kind, n) in cases {
        if kinds.as_ref().is_some_and(|k| !k.iter().any(|k| k == kind)) {
            continue;
        }
        let Some(scene) = choice_scene(kind, n, 1) else {
            continue;
        };
        let case = ChoiceCase { kind, n, scene };
        let scene = &case.scene;
        let pick = Structure::for_scene(scene);
        let mut rows: Vec<(Structure, Timing)> = Vec::new();
        // The default's pick first: the others are then stopped at a few times its time.
        let order = std::iter::once(pick).chain(Structure::ALL.into_iter().filter(|&s| s != pick));
        for s in order {
            let named = only
                .as_ref()
                .is_none_or(|o| s == pick || o.iter().any(|n| n == s.name()));
            if !named
                || !s.applies_to(scene)
                || (s == Structure::BruteForce && scene.objects.len() > 3000)
            {
                continue;
            }
            // Once a structure is far behind, stop it at a few times the fastest.
            let best = rows
                .iter()
                .filter(|(_, t)| !t.stopped)
                .map(|(_, t)| t.seconds)
                .fold(f64::INFINITY, f64::min);
            let cap = budget.min((best * 4.0).max(0.5));
            if let Some(mut t) = timed(scene, s, cap) {
                // Runs of a few milliseconds vary by 2x from one to the next (the first
                // structure timed on a scene pays for fresh memory): the best of five.
                for _ in 1..SHORT_RUNS {
                    if t.stopped || t.seconds >= SHORT {
                        break;
                    }
                    if let Some(again) = timed(scene, s, cap)
                        && !again.stopped
                        && again.seconds < t.seconds
                    {
                        t = again;
                    }
                }
                rows.push((s, t));
            }
        }
        rows.sort_by_key(|(s, _)| Structure::ALL.iter().position(|x| x == s));
        let (fast, best) = rows
            .iter()
            .filter(|(_, t)| !t.stopped)
            .map(|(s, t)| (*s, t.seconds))
            .fold((pick, f64::INFINITY), |a, b| if b.1 < a.1 { b } else { a });
        let mine = rows
            .iter()
            .find(|(s, _)| *s == pick)
            .map_or(f64::INFINITY, |(_, t)| {
                if t.stopped { f64::INFINITY } else { t.seconds }
            });
        // Timings under a millisecond are noise: compare from there.
        let ratio = mine.max(1e-3) / best.max(1e-3);
        worst = worst.max(ratio);
        let times: Vec<String> = rows
            .iter()
            .map(|(s, t)| {
                format!(
                    "{} {}{:.3}",
                    s.name(),
                    if t.stopped { ">" } else { "" },
                    t.seconds
                )
            })
            .collect();
        println!(
            "| {} | {} | {} | {:.2} | {} | {} |",
            case.kind,
            scene.objects.len(),
            pick.name(),
            ratio,
            fast.name(),
            times.join(", ")
        );
        for (s, t) in &rows {
            csv.push_str(&format!(
                "{},{},{},{},{},{:.6},{},{},{},{:.2},{}\n",
                case.kind,
                scene.objects.len(),
                world_name(scene),
                response_name(scene),
                s.name(),
                t.seconds,
                t.stopped,
                t.events,
                t.contacts,
                t.events as f64 / t.contacts.max(1) as f64,
                *s == pick
            ));
        }
    }
    println!("\nworst default / fastest: {worst:.2}");
    if let Some(dir) = std::path::Path::new(&out).parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    match std::fs::write(&out, csv) {
        Ok(()) => println!("wrote {out}"),
        Err(e) => eprintln!("{out}: {e}"),
    }
}
