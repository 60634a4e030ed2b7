//! Bench command for the free-flight structures: candidate pairs, certificates, events and
//! wall time against n, sweep against guards against the grid against the brute force, for
//! - asteroid fields of mixed spinning balls, cuboids and hulls at scale factors 1, 100 and
//!   1e4;
//! - nests (the paper's Fig. 6): clusters of small balls under chains of ever larger balls
//!   whose boxes all hold the cluster, at scale factors 100 and 1e4.
//!
//! `cargo bench --bench flight` prints a markdown table; `-- --quick` stops at n = 1000.
//! The brute force runs up to n = 1000 (it keeps n^2 / 2 certificates).

use kinetic_collide::Structure;
use kinetic_collide::run::run_scene;
use kinetic_collide::scene::Scene;
use kinetic_scenes::{FlightScene, NestScene};

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let sizes: &[usize] = if quick {
        &[100, 1000]
    } else {
        &[100, 1000, 10_000]
    };
    println!(
        "| scene | sigma | n | structure | pairs/object (mean) | pairs (max) | certificates (mean) | events | contacts | seconds |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut scenes: Vec<(&str, f64, usize, Scene)> = Vec::new();
    for sigma in [1.0, 100.0, 1e4] {
        for &n in sizes {
            let scene = FlightScene {
                horizon: 2.0,
                ..FlightScene::asteroids(n, sigma, 1)
            };
            scenes.push(("asteroids", sigma, n, scene.build()));
        }
    }
    for sigma in [100.0, 1e4] {
        for &n in sizes {
            scenes.push(("nests", sigma, n, NestScene::new(n, sigma, 1).build()));
        }
    }
    for (name, sigma, _, scene) in scenes {
        let n = scene.objects.len();
        {
            let mut contacts = None;
            for s in [
                Structure::Sweep,
                Structure::Guards,
                Structure::Grid,
                Structure::BruteForce,
            ] {
                if s == Structure::BruteForce && n > 1000 {
                    continue;
                }
                let out = run_scene(&scene, Some(s)).expect("the scene runs");
                let c = out.stats.begins + out.stats.ends;
                assert_eq!(*contacts.get_or_insert(c), c, "{s:?} disagrees on contacts");
                println!(
                    "| {name} | {sigma} | {n} | {} | {:.2} | {} | {:.0} | {} | {} | {:.3} |",
                    s.name(),
                    out.stats.candidate_pairs_mean() / n as f64,
                    out.stats.candidate_pairs_max,
                    out.stats.certificates_mean(),
                    out.stats.events_total(),
                    c,
                    out.wall_seconds
                );
            }
        }
    }
}
