//! The library's default world (`World::new`: the adaptive structure raced against its
//! shortlist as the world is advanced) against the adaptive structure alone
//! (`World::without_racing`) and every box structure and the brute force by name, on draws
//! of the scene space (`kinetic_scenes::space`), driven as a game drives a world: the objects
//! added, then `advance_to` called at `--calls` even times over the horizon. Writes each
//! draw's seconds and ratios, the worst and the median, to `docs/results/world.csv`.
//!
//! `cargo bench -p kinetic-collide --bench world -- [--draws K] [--seed S] [--max-objects N]
//! [--calls C] [--out FILE]` (defaults: 30 draws from seed 1, at most 5,000 objects, 600
//! calls). Each side builds its world and runs it in this process, three times, the sides
//! interleaved; the median counts (times under a millisecond count as one in the ratios). A
//! structure past four times the fastest so far (at
//! least a second) is stopped there and counts as that. Periodic draws are left out (they
//! run on the periodic structure, not in a world), as is the brute force above 3,000
//! objects. With `WORLD_RACE` set, the default's race is printed for each run.

use kinetic_collide::run::shapes_of;
use kinetic_collide::scene::Scene;
use kinetic_collide::{Structure, World};
use kinetic_scenes::space;
use std::time::Instant;

/// Each side runs this many times, interleaved; the median counts.
const ROUNDS: usize = 3;
/// A side past this many times the fastest so far stops.
const STOP: f64 = 4.0;
/// Timings under this many seconds count as this in ratios (noise and the fixed cost of the
/// calls below it), as in the choice bench.
const FLOOR: f64 = 1e-3;

/// The sides: the raced default, the adaptive structure alone, then each structure by name.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Side {
    Raced,
    Adaptive,
    Named(Structure),
}

impl Side {
    fn name(self) -> &'static str {
        match self {
            Side::Raced => "default",
            Side::Adaptive => "adaptive",
            Side::Named(s) => s.name(),
        }
    }
}

/// Builds `scene`'s world for `side` and advances it in `calls` even steps to the horizon;
/// the wall seconds (build included), whether it was stopped at `budget`, and the structure
/// it ended on.
fn timed(scene: &Scene, side: Side, calls: usize, budget: f64) -> (f64, bool, String) {
    let shapes = shapes_of(scene).expect("shapes");
    let plans = scene.objects.iter().map(|o| o.plan());
    let start = Instant::now();
    let mut world = match side {
        Side::Raced | Side::Adaptive => {
            let world =
                World::with_response(scene.world, scene.response, scene.walls).expect("a world");
            if side == Side::Adaptive {
                world.without_racing()
            } else {
                world
            }
        }
        Side::Named(s) => {
            World::with_structure(scene.world, scene.response, scene.walls, s).expect("a world")
        }
    };
    world
        .add_objects(shapes.into_iter().zip(plans))
        .expect("objects");
    for k in 1..=calls {
        let t = scene.horizon * k as f64 / calls as f64;
        world.advance_to(t).expect("advance");
        if start.elapsed().as_secs_f64() > budget {
            return (budget, true, world.structure_name().to_string());
        }
    }
    if side == Side::Raced && std::env::var_os("WORLD_RACE").is_some() {
        for s in world.race() {
            eprintln!(
                "  {:<12} {:>10.4} .. {:>10.4} {:>9.5}s (build {:.5}s)",
                s.structure.name(),
                s.from,
                s.to,
                s.wall_seconds,
                s.build_seconds
            );
        }
    }
    (
        start.elapsed().as_secs_f64(),
        false,
        world.structure_name().to_string(),
    )
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let value = |flag: &str| -> Option<String> {
        let at = args.iter().position(|a| a == flag)?;
        args.get(at + 1).cloned()
    };
    let number = |flag: &str, default: u64| -> u64 {
        value(flag).map_or(default, |v| {
            v.parse()
                .unwrap_or_else(|_| panic!("{flag}: a number, not {v}"))
        })
    };
    let draws = number("--draws", 30);
    let seed = number("--seed", 1);
    let max_objects = number("--max-objects", 5000) as usize;
    let calls = number("--calls", 600).max(1) as usize;
    let out = value("--out").unwrap_or_else(|| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/results/world.csv").to_string()
    });
    let mut csv = String::from(
        "seed,draw,objects,default_s,adaptive_s,fastest,fastest_s,default_over_fastest,\
         adaptive_over_fastest,default_over_adaptive,default_ends_on\n",
    );
    let mut ratios: Vec<(f64, f64, f64)> = Vec::new();
    for s in seed..seed + draws {
        let draw = space::draw(s, max_objects);
        let scene = &draw.scene;
        if scene.periodic.is_some() {
            continue;
        }
        let mut sides = vec![Side::Raced, Side::Adaptive];
        for st in [
            Structure::Grid,
            Structure::LooseGrid,
            Structure::Sweep,
            Structure::BruteForce,
        ] {
            if st != Structure::BruteForce || scene.objects.len() <= 3000 {
                sides.push(Side::Named(st));
            }
        }
        let mut times: Vec<Vec<f64>> = vec![Vec::new(); sides.len()];
        let mut ends = String::new();
        for _ in 0..ROUNDS {
            for (i, &side) in sides.iter().enumerate() {
                let fastest = times
                    .iter()
                    .filter(|t| !t.is_empty())
                    .map(|t| median(t.clone()))
                    .fold(f64::INFINITY, f64::min);
                let budget = (STOP * fastest).max(1.0);
                let (seconds, _, end) = timed(scene, side, calls, budget);
                times[i].push(seconds);
                if side == Side::Raced {
                    ends = end;
                }
            }
        }
        let med: Vec<f64> = times.into_iter().map(median).collect();
        let (best, best_s) = sides
            .iter()
            .zip(&med)
            .skip(2)
            .min_by(|a, b| a.1.total_cmp(b.1))
            .map(|(s, &t)| (s.name(), t))
            .expect("a structure");
        let (raced, adaptive) = (med[0], med[1]);
        let (fr, fa, fb) = (raced.max(FLOOR), adaptive.max(FLOOR), best_s.max(FLOOR));
        let r = (fr / fb, fa / fb, fr / fa);
        ratios.push(r);
        println!(
            "{s:>3} {:<70} default {raced:.4}s adaptive {adaptive:.4}s {best} {best_s:.4}s: \
             {:.2}x {:.2}x (default/adaptive {:.2}x) ends on {ends}",
            draw.label, r.0, r.1, r.2
        );
        csv.push_str(&format!(
            "{s},\"{}\",{},{raced:.6},{adaptive:.6},{best},{best_s:.6},{:.3},{:.3},{:.3},{ends}\n",
            draw.label,
            scene.objects.len(),
            r.0,
            r.1,
            r.2
        ));
    }
    let column = |f: fn(&(f64, f64, f64)) -> f64| -> (f64, f64) {
        let v: Vec<f64> = ratios.iter().map(f).collect();
        (v.iter().copied().fold(0.0, f64::max), median(v.clone()))
    };
    if !ratios.is_empty() {
        let (dw, dm) = column(|r| r.0);
        let (aw, am) = column(|r| r.1);
        let (rw, rm) = column(|r| r.2);
        println!(
            "{} draws: default/fastest worst {dw:.2}x median {dm:.2}x; adaptive/fastest worst \
             {aw:.2}x median {am:.2}x; default/adaptive worst {rw:.2}x median {rm:.2}x",
            ratios.len()
        );
        csv.push_str(&format!(
            "worst,,,,,,,{dw:.3},{aw:.3},{rw:.3},\nmedian,,,,,,,{dm:.3},{am:.3},{rm:.3},\n"
        ));
    }
    std::fs::write(&out, csv).unwrap_or_else(|e| panic!("{out}: {e}"));
    println!("wrote {out}");
}
