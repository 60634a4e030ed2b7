//! Criterion bench over the comparison's scene families (`kinetic_collide::families`): the
//! kinetic structure the tool chooses, time-stepped detection at 1/60 and rapier at 1/60,
//! each running the whole scene. `cargo bench --bench families`; the accuracy of each is in
//! `kinetic-collide compare`.

use criterion::{Criterion, criterion_group, criterion_main};
use kinetic_collide::run::run_scene;
use kinetic_collide_cli::rapier_run::{Broad, run_rapier};
use kinetic_collide_cli::time_stepped::run_stepped;
use kinetic_scenes::families::Family;
use std::hint::black_box;

fn families(c: &mut Criterion) {
    for family in Family::ALL {
        let scene = family.scene(family.default_size(), 1);
        let mut group = c.benchmark_group(format!("families/{}", family.name()));
        group.sample_size(10);
        group.bench_function("kinetic", |b| {
            b.iter(|| black_box(run_scene(&scene, None).map(|o| o.events.len()).ok()))
        });
        group.bench_function("stepped 1/60", |b| {
            b.iter(|| black_box(run_stepped(&scene, 1.0 / 60.0).map(|o| o.events.len()).ok()))
        });
        group.bench_function("rapier 1/60", |b| {
            b.iter(|| {
                black_box(
                    run_rapier(&scene, 1.0 / 60.0, Broad::Default, false)
                        .map(|o| o.events.len())
                        .ok(),
                )
            })
        });
        group.finish();
    }
}

criterion_group!(benches, families);
criterion_main!(benches);
