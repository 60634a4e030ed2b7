//! The kinetic sorted list against sorting at random times, `validate()` after every event.

use kinetic_core::kds::{KineticSortedList, ScalarKey};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn random_keys(n: usize, seed: u64, quadratic: bool, grid: bool) -> Vec<(u32, ScalarKey)> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n as u32)
        .map(|i| {
            let (mut x, mut v) = (rng.random_range(-10.0..10.0), rng.random_range(-1.0..1.0));
            if grid {
                // Shared coordinates and speeds: many simultaneous swaps.
                x = f64::from(rng.random_range(-3..3i32));
                v = f64::from(rng.random_range(-2..3i32)) * 0.5;
            }
            let a = if quadratic {
                rng.random_range(-0.2..0.2)
            } else {
                0.0
            };
            (i, ScalarKey::new(0.0, x, v, a))
        })
        .collect()
}

/// Runs to `horizon`, validating after every swap and checking the order at sample times.
fn check_against_sorting(keys: &[(u32, ScalarKey)], horizon: f64, samples: usize) -> u64 {
    let mut list = KineticSortedList::from_items(0.0, keys.iter().copied()).unwrap();
    list.validate().unwrap();
    for s in 1..=samples {
        let t = horizon * s as f64 / samples as f64;
        while let Some(_swap) = list.process_next_event(t) {
            list.validate()
                .unwrap_or_else(|e| panic!("after a swap at {}: {e}", list.now()));
        }
        list.advance_to(t, |_| {}).unwrap();
        list.validate().unwrap();
        let values: Vec<f64> = list
            .order()
            .iter()
            .map(|&i| keys[i as usize].1.value_at(t))
            .collect();
        for w in values.windows(2) {
            assert!(
                w[0] <= w[1] + 1e-9 * w[1].abs().max(1.0),
                "not sorted at {t}: {} > {}",
                w[0],
                w[1]
            );
        }
    }
    list.swap_count()
}

#[test]
fn linear_keys_stay_sorted() {
    for seed in 0..5 {
        let swaps = check_against_sorting(&random_keys(200, seed, false, false), 20.0, 50);
        assert!(swaps > 100, "seed {seed}: only {swaps} swaps");
    }
}

#[test]
fn quadratic_keys_stay_sorted() {
    for seed in 10..14 {
        check_against_sorting(&random_keys(150, seed, true, false), 20.0, 40);
    }
}

#[test]
fn simultaneous_swaps_on_a_grid() {
    for seed in 20..24 {
        let swaps = check_against_sorting(&random_keys(120, seed, false, true), 10.0, 40);
        assert!(swaps > 0);
    }
}

#[test]
fn three_items_crossing_at_one_point() {
    // All at x = 0 at t = 1 with speeds 1, 0, -1: the order reverses in three swaps.
    let keys = [
        (0, ScalarKey::linear(-1.0, 1.0)),
        (1, ScalarKey::linear(0.0, 0.0)),
        (2, ScalarKey::linear(1.0, -1.0)),
    ];
    let mut list = KineticSortedList::from_items(0.0, keys).unwrap();
    let mut swaps = Vec::new();
    while let Some(s) = list.process_next_event(2.0) {
        swaps.push(s);
        list.validate().unwrap();
    }
    assert_eq!(list.order(), &[2, 1, 0]);
    assert_eq!(swaps.len(), 3);
    assert!(swaps.iter().all(|s| s.time == 1.0));
}

#[test]
fn insert_remove_and_rekey_while_running() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let keys = random_keys(100, 3, false, false);
    let mut list = KineticSortedList::from_items(0.0, keys.iter().copied()).unwrap();
    let mut live: Vec<(u32, ScalarKey)> = keys.clone();
    let mut next_id = 100u32;
    for step in 1..=60 {
        let t = step as f64 * 0.25;
        while list.process_next_event(t).is_some() {
            list.validate().unwrap();
        }
        list.advance_to(t, |_| {}).unwrap();
        match step % 3 {
            0 => {
                let k = ScalarKey::new(
                    t,
                    rng.random_range(-10.0..10.0),
                    rng.random_range(-1.0..1.0),
                    0.0,
                );
                list.insert(next_id, k).unwrap();
                live.push((next_id, k));
                next_id += 1;
            }
            1 => {
                let i = rng.random_range(0..live.len());
                let (id, _) = live.swap_remove(i);
                list.remove(id).unwrap();
            }
            _ => {
                let i = rng.random_range(0..live.len());
                let k = ScalarKey::new(t, live[i].1.value_at(t), rng.random_range(-2.0..2.0), 0.0);
                live[i].1 = k;
                list.set_key(live[i].0, k).unwrap();
            }
        }
        list.validate().unwrap();
        // Re-keyed items may be out of place until their swaps at t run.
        while list.process_next_event(t).is_some() {
            list.validate().unwrap();
        }
        let mut want: Vec<f64> = live.iter().map(|(_, k)| k.value_at(t)).collect();
        want.sort_by(f64::total_cmp);
        let got: Vec<f64> = list
            .order()
            .iter()
            .map(|&i| list.key(i).unwrap().value_at(t))
            .collect();
        assert_eq!(got.len(), want.len());
        for (g, w) in got.iter().zip(&want) {
            assert!((g - w).abs() < 1e-9, "at {t}: {g} vs {w}");
        }
    }
    assert_eq!(
        list.insert(5000, ScalarKey::linear(f64::NAN, 0.0)),
        Err(kinetic_core::kds::SortedListError::NonFinite(5000))
    );
    assert!(list.remove(99_999).is_err());
}
