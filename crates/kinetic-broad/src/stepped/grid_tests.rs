//! The grid's pairs against every pair's, in piles, clusters, spreads of sizes and
//! degenerate boxes, filed and swept.

use super::*;
use crate::aabb::{next, next_vec, overlapping};
use kinetic_core::{Real, Vec3};

/// Checks `grid`'s pairs of `items` against every pair's, and those of a copy that is
/// swept where `grid` is not and the other way round.
fn check(grid: &mut SteppedGrid, items: &[(u32, Aabb)], what: &str) {
    let mut other = grid.clone();
    other.no_sweep = !grid.no_sweep;
    check_one(&mut other, items, &format!("{what}, other way"));
    check_one(grid, items, what);
}

fn check_one(grid: &mut SteppedGrid, items: &[(u32, Aabb)], what: &str) {
    let mut out = Vec::new();
    grid.pairs(items.iter().copied(), &|_, _| true, &mut out);
    let mut want = Vec::new();
    for (k, a) in items.iter().enumerate() {
        for b in &items[k + 1..] {
            if a.1.overlaps(&b.1) {
                want.push(ordered(a.0, b.0));
            }
        }
    }
    want.sort_unstable();
    assert!(!want.is_empty(), "{what}: no pairs to find");
    let missing: Vec<_> = want
        .iter()
        .filter(|p| out.binary_search(p).is_err())
        .collect();
    // Boxes are rounded outwards to single precision: a pair apart by less than that
    // may be given too.
    let near = |a: u32, b: u32| {
        let find = |id: u32| items.iter().find(|(i, _)| *i == id).expect("an item").1;
        let (a, b) = (find(a), find(b));
        let grow = |x: Aabb| {
            let out = (x.min.abs() + x.max.abs()) * (2.0 * f32::EPSILON as Real);
            Aabb::new(x.min - out, x.max + out)
        };
        grow(a).overlaps(&grow(b))
    };
    let extra: Vec<_> = out
        .iter()
        .filter(|p| want.binary_search(p).is_err() && !near(p.0, p.1))
        .collect();
    assert!(
        missing.is_empty() && extra.is_empty(),
        "{what}: missing {missing:?}, extra {extra:?}"
    );
}

#[test]
fn scattered_boxes_with_a_few_wide_ones_give_exactly_the_overlapping_pairs() {
    let mut s = 7;
    let mut grid = SteppedGrid::default();
    for round in 0..4 {
        let mut items = Vec::new();
        for id in 0..400u32 {
            let c = next_vec(&mut s) * 20.0;
            // Mostly small boxes, a few wide ones (a ground) and one with a NaN.
            let h = if id % 97 == 0 {
                Vec3::new(15.0, 0.5, 15.0)
            } else {
                Vec3::splat(0.2 + next(&mut s) * (round as Real + 1.0))
            };
            let b = if id == 5 && round == 2 {
                Aabb::new(Vec3::NAN, Vec3::NAN)
            } else {
                Aabb::new(c - h, c + h)
            };
            items.push((id * 3 + round, b));
        }
        check(&mut grid, &items, &format!("round {round}"));
    }
}

/// Clusters of boxes scattered over a space far wider than they fill: the cells are
/// hashed, each box is filed in every cell it overlaps, and boxes that overlap across
/// cell lines are found once each.
#[test]
fn clusters_far_apart_in_hashed_cells_give_exactly_the_overlapping_pairs() {
    let mut s = 13;
    let mut grid = SteppedGrid::default();
    for round in 0..4 {
        let mut items = Vec::new();
        let mut centre = Vec3::ZERO;
        for id in 0..600u32 {
            if id % 6 == 0 {
                centre = next_vec(&mut s) * 5000.0;
            }
            let c = centre + next_vec(&mut s) * 2.0;
            // Mostly small boxes, a few wide ones and one with a NaN.
            let h = if id % 151 == 0 {
                Vec3::new(40.0, 0.5, 40.0)
            } else {
                Vec3::splat(0.3 + next(&mut s) * 0.5)
            };
            let b = if id == 7 && round == 1 {
                Aabb::new(Vec3::NAN, Vec3::NAN)
            } else {
                Aabb::new(c - h, c + h)
            };
            items.push((id * 5 + round, b));
        }
        check(&mut grid, &items, &format!("round {round}"));
        assert!(
            grid.dense.is_none(),
            "round {round}: the cells were not hashed"
        );
    }
}

#[test]
fn a_dense_pile_with_a_spread_of_wide_boxes_gives_exactly_the_overlapping_pairs() {
    let mut s = 11;
    let mut grid = SteppedGrid::default();
    for round in 0..3 {
        let mut items = Vec::new();
        // A lattice of boxes that touch their neighbours, jittered.
        for k in 0..1000u32 {
            let (x, y, z) = (k % 10, (k / 10) % 10, k / 100);
            let c = Vec3::new(x as Real, y as Real, z as Real) * 0.5 + next_vec(&mut s) * 0.05;
            let h = next_vec(&mut s) * 0.05 + 0.2;
            items.push((k, Aabb::new(c - h, c + h)));
        }
        // Wide boxes of many sizes, more than make a grid of their own.
        for k in 0..60u32 {
            let c = next_vec(&mut s) * 5.0;
            let h = Vec3::splat(0.6 * (1.0 + 8.0 * next(&mut s)));
            items.push((2000 + k, Aabb::new(c - h, c + h)));
        }
        // A ground, and (once) a box with NaN sides.
        items.push((
            5000,
            Aabb::new(Vec3::new(-50.0, -1.0, -50.0), Vec3::new(50.0, 0.1, 50.0)),
        ));
        if round == 1 {
            items.push((5001, Aabb::new(Vec3::NAN, Vec3::ONE)));
        }
        check(&mut grid, &items, &format!("round {round}"));
    }
}

/// Debris whose sizes span three orders: the wide boxes make grids of their own, one in
/// another, and both the pairs and a box's look-up find exactly the overlapping boxes.
#[test]
fn sizes_spread_over_three_orders_nest_grids_and_give_exactly_the_overlapping_pairs() {
    let mut s = 17;
    let mut grid = SteppedGrid {
        no_sweep: true,
        ..SteppedGrid::default()
    };
    let mut swept = SteppedGrid::default();
    let mut items = Vec::new();
    for round in 0..3u32 {
        items.clear();
        for id in 0..3000u32 {
            // The number of boxes of radius at least r falls as 1 / r, from 0.01 to 10.
            let r = 1.0 / (100.0 - next(&mut s) * 99.9);
            let c = next_vec(&mut s) * 60.0;
            let h = Vec3::new(1.0, 0.5 + next(&mut s), 1.0) * r;
            items.push((id * 3 + round, Aabb::new(c - h, c + h)));
        }
        check(&mut grid, &items, &format!("round {round}"));
        let mut depth = 0;
        let mut g = &grid;
        while let Some(inner) = g.nested() {
            depth += 1;
            g = inner;
        }
        assert!(depth >= 2, "round {round}: {depth} nested grids");
        // Look-ups in the grid, and in the sweep of as many of the boxes as are swept.
        let few = &items[..SWEEP_MOST];
        swept.pairs(few.iter().copied(), &|_, _| true, &mut Vec::new());
        assert!(swept.swept, "round {round}: debris not swept");
        for k in 0..400 {
            let (_, q) = items[(k / 2 * 13) % items.len()];
            let q = q.grown(Vec3::splat(0.05));
            let mut got = Vec::new();
            let (by, among) = if k % 2 == 0 {
                (&grid, &items[..])
            } else {
                (&swept, few)
            };
            by.overlapping_with(&q, &mut got);
            got.sort_unstable();
            got.dedup();
            let want: Vec<u32> = among
                .iter()
                .filter(|(_, b)| overlapping(&q, b))
                .map(|(id, _)| *id)
                .collect::<std::collections::BTreeSet<_>>()
                .into_iter()
                .collect();
            assert_eq!(got, want, "round {round}: look-up {k}");
        }
    }
}

#[test]
fn boxes_that_are_all_nan_or_wide_do_not_recurse_for_ever() {
    let mut grid = SteppedGrid::default();
    let mut items: Vec<(u32, Aabb)> = (0..40)
        .map(|k| (k, Aabb::new(Vec3::NAN, Vec3::NAN)))
        .collect();
    items.push((100, Aabb::new(Vec3::ZERO, Vec3::ONE)));
    items.push((101, Aabb::new(Vec3::splat(0.5), Vec3::splat(2.0))));
    check(&mut grid, &items, "NaN boxes");
}
