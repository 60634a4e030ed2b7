//! Kinetic sorted list: swap events per second on random linear motions.
//!
//! `cargo bench --bench sorted_list`. Each iteration processes a fixed number of swaps from a
//! list built once; criterion's throughput line gives swaps per second.

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use kinetic_collide::kds::{KineticSortedList, ScalarKey};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_list(n: usize) -> KineticSortedList {
    let mut rng = ChaCha8Rng::seed_from_u64(n as u64);
    let keys = (0..n as u32).map(|i| {
        (
            i,
            ScalarKey::linear(rng.random_range(0.0..n as f64), rng.random_range(-1.0..1.0)),
        )
    });
    KineticSortedList::from_items(0.0, keys).expect("finite keys")
}

fn swaps(c: &mut Criterion) {
    let mut group = c.benchmark_group("sorted_list_swaps");
    group.sample_size(10);
    const SWAPS: u64 = 200_000;
    group.throughput(Throughput::Elements(SWAPS));
    for n in [10_000usize, 100_000, 1_000_000] {
        // Warm the list past its start so events are spread as in a long run.
        let mut base = random_list(n);
        for _ in 0..SWAPS {
            base.process_next_event(f64::INFINITY);
        }
        group.bench_function(format!("n={n}"), |b| {
            b.iter_batched_ref(
                || base.clone(),
                |list| {
                    for _ in 0..SWAPS {
                        list.process_next_event(f64::INFINITY);
                    }
                },
                BatchSize::LargeInput,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, swaps);
criterion_main!(benches);
