//! The brute-force reference at n = 1000: a gas of free balls run to its horizon, with no
//! response (pure detection) and with the elastic response (each collision re-plans two
//! balls and reschedules their n - 1 pairs each).
//!
//! `cargo bench --bench brute_force`.

use criterion::{Criterion, criterion_group, criterion_main};
use kinetic_collide::Response;
use kinetic_collide::Structure;
use kinetic_collide::run::run_scene;
use kinetic_scenes::BallScene;

fn brute_force(c: &mut Criterion) {
    let mut group = c.benchmark_group("brute_force");
    group.sample_size(10);
    for (name, response) in [("none", Response::None), ("elastic", Response::Elastic)] {
        let scene = BallScene {
            response,
            walls: response == Response::Elastic,
            allow_overlap: false,
            ..BallScene::gas(1000, 1)
        }
        .build();
        let out = run_scene(&scene, Some(Structure::BruteForce)).expect("scene runs");
        eprintln!(
            "brute_force/{name}: n = 1000, {} events, {} contacts, {} certificates",
            out.stats.events_total(),
            out.stats.begins,
            out.stats.certificates_max
        );
        group.bench_function(format!("gas_n1000_{name}"), |b| {
            b.iter(|| run_scene(&scene, Some(Structure::BruteForce)).expect("scene runs"))
        });
    }
    group.finish();
}

criterion_group!(benches, brute_force);
criterion_main!(benches);
