//! The rolling-ball benchmark: the collision tree, its global-lists variant and the
//! brute force on `BallScene::rolling(n)` (radii 0.01 to 10, linear motion, no response), one
//! timed run each, with the figures the README table shows. The brute force runs up to
//! n = 1e4 and its event log is compared with the tree's.
//!
//! `cargo bench --bench rolling` (add `-- --quick` for n = 1e3 and 1e4 only).

use kinetic_collide::Structure;
use kinetic_collide::run::{RunOutput, run_scene};
use kinetic_scenes::BallScene;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    // Horizons: about 1e6 structure events at n = 1e5 for the tree.
    let sizes: &[(usize, f64)] = if quick {
        &[(1_000, 20.0), (10_000, 4.0)]
    } else {
        &[(1_000, 20.0), (10_000, 4.0), (100_000, 1.0)]
    };
    println!(
        "| n | horizon | structure | wall s | events | swaps | collisions | contacts | certificates max | certs / (n log2 n) | candidate pairs mean | events / contact | brute / this |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for &(n, horizon) in sizes {
        let scene = BallScene::rolling(n, horizon, 1).build();
        let brute = (n <= 10_000).then(|| run_scene(&scene, Some(Structure::BruteForce)));
        let brute = brute.map(|r| r.expect("the brute force runs"));
        if let Some(b) = &brute {
            row(n, horizon, b, None);
        }
        // The global lists make some fifty times the tree's events (every point passes every
        // box of every level); at n = 1e5 that is hours here, so they stop at 1e4.
        let variants: &[Structure] = if n <= 10_000 {
            &[Structure::RollingTree, Structure::RollingGlobalLists]
        } else {
            &[Structure::RollingTree]
        };
        for &s in variants {
            let out = run_scene(&scene, Some(s)).expect("the rolling tree runs");
            if let Some(b) = &brute {
                let same = b.events.len() == out.events.len()
                    && b.events.iter().zip(&out.events).all(|(x, y)| {
                        (x.a, x.b, x.kind) == (y.a, y.b, y.kind)
                            && (x.time - y.time).abs() <= 1e-7 * x.time.abs().max(1.0)
                    });
                assert!(
                    same,
                    "{} and the brute force logged different events at n = {n}",
                    s.name()
                );
            }
            row(n, horizon, &out, brute.as_ref());
        }
    }
}

fn row(n: usize, horizon: f64, out: &RunOutput, brute: Option<&RunOutput>) {
    let s = &out.stats;
    let kind = |k: &str| s.events_by_kind.get(k).copied().unwrap_or(0);
    let nlogn = n as f64 * (n as f64).log2();
    println!(
        "| {n} | {horizon} | {} | {:.3} | {} | {} | {} | {} | {} | {:.2} | {:.0} | {:.1} | {} |",
        out.structure.name(),
        out.wall_seconds,
        s.events_total(),
        kind("swap"),
        kind("collision"),
        s.begins,
        s.certificates_max,
        s.certificates_max as f64 / nlogn,
        s.candidate_pairs_mean(),
        s.events_total() as f64 / s.begins.max(1) as f64,
        brute.map_or("-".to_string(), |b| format!(
            "{:.0}x",
            b.wall_seconds / out.wall_seconds
        )),
    );
}
