//! Tests of the fat boxes: the kept pairs against the grid's found afresh.

use super::*;
use crate::aabb::{next, next_vec};

/// Place `k` of a cubic lattice `side` places a side, one unit apart.
fn lattice(side: usize, k: usize) -> Vec3 {
    Vec3::new(
        (k % side) as Real,
        (k / side % side) as Real,
        (k / (side * side)) as Real,
    )
}

/// A cube of half-side `half` now at `at`, with how far it moved since it was at `last`,
/// which becomes `at`.
fn moved_to(at: Vec3, last: &mut Vec3, half: Real) -> Option<(Aabb, Vec3)> {
    let d = at - std::mem::replace(last, at);
    let h = Vec3::splat(half);
    Some((Aabb::new(at - h, at + h), d))
}

/// One call of `kept` against the pairs the grid finds afresh from the same boxes swept
/// in `frame`: the same pairs, of which it returns how many.
fn same_as_fresh(
    kept: &mut FatPairs,
    fresh: &mut SteppedGrid,
    boxes: &[Option<(Aabb, Vec3)>],
    frame: Vec3,
    keep: &dyn Fn(u32, u32) -> bool,
    call: usize,
) -> usize {
    let (mut got, mut want) = (Vec::new(), Vec::new());
    kept.pairs(boxes, frame, keep, &mut got);
    let swept = Swept { boxes, frame };
    let items = swept
        .iter()
        .enumerate()
        .filter_map(|(i, b)| Some((i as u32, b?.0)));
    fresh.pairs(items, keep, &mut want);
    assert_eq!(got, want, "call {call}");
    want.len()
}

/// `calls` calls of fat pairs on the boxes `boxes_at(call)` gives, each against the
/// grid's pairs found afresh (no frame, every pair kept): the fat pairs after them and
/// the pairs found in all.
fn run_calls(
    calls: usize,
    mut boxes_at: impl FnMut(usize) -> Vec<Option<(Aabb, Vec3)>>,
) -> (FatPairs, usize) {
    let (mut kept, mut fresh, mut met) = (FatPairs::default(), SteppedGrid::default(), 0);
    for call in 0..calls {
        let boxes = boxes_at(call);
        let keep = |_, _| true;
        met += same_as_fresh(&mut kept, &mut fresh, &boxes, Vec3::ZERO, &keep, call);
    }
    (kept, met)
}

/// Boxes flying apart and boxes jostling in a heap, over many calls, with boxes coming
/// and going and one that turns about: the kept pairs are the grid's own every call,
/// and the fat boxes are found afresh far fewer times than there are calls.
#[test]
fn kept_pairs_are_the_grids_own_at_every_call() {
    let mut s = 3;
    let n = 300;
    let mut at: Vec<Vec3> = (0..n).map(|_| next_vec(&mut s) * 12.0).collect();
    let v: Vec<Vec3> = (0..n)
        .map(|k| {
            let out = at[k] - Vec3::splat(6.0);
            // Most fly out, one in twenty jostles about where it is.
            if k % 20 != 0 { out * 0.02 } else { Vec3::ZERO }
        })
        .collect();
    let mut kept = FatPairs::default();
    let mut fresh = SteppedGrid::default();
    for call in 0..200 {
        let boxes: Vec<Option<(Aabb, Vec3)>> = (0..n)
            .map(|k| {
                if (k + call / 50) % 37 == 0 {
                    return None; // gone for a while
                }
                let jitter = next_vec(&mut s) - 0.5;
                let shake = if k % 20 == 0 { 0.004 } else { 0.0 };
                let mut d = v[k] + jitter * shake;
                if k == 11 && call >= 100 {
                    d = -d * 5.0; // turns about, faster
                }
                at[k] += d;
                let h = Vec3::splat(0.2 + 0.1 * (k % 3) as Real);
                Some((Aabb::new(at[k] - h, at[k] + h), d))
            })
            .collect();
        let keep = |a: u32, b: u32| !(a + b).is_multiple_of(5);
        // The boxes are swept in a frame drifting a little.
        let frame = Vec3::new(0.01, -0.005, 0.0);
        let found = same_as_fresh(&mut kept, &mut fresh, &boxes, frame, &keep, call);
        assert!(found > 0 || call > 20, "call {call}: no pairs to find");
    }
    assert!(
        kept.rebuilds * 4 < kept.calls && kept.refattened > 0,
        "{} rebuilds, {} re-fattened in {} calls",
        kept.rebuilds,
        kept.refattened,
        kept.calls
    );
}

/// Clusters of boxes far apart, each box swinging about its place at its own pace, so
/// that boxes leave their fat boxes one by one next to boxes that left theirs before:
/// the kept pairs are the grid's own every call, mostly from boxes re-fattened alone.
#[test]
fn boxes_leaving_their_fat_boxes_one_by_one_keep_every_pair() {
    let mut s = 5;
    let n = 400;
    // Twos that meet now and then, and boxes alone: few pairs, as in debris.
    let base: Vec<Vec3> = (0..n / 4)
        .flat_map(|_| {
            let c = next_vec(&mut s) * 200.0;
            let far = next_vec(&mut s) * 200.0;
            [
                c,
                c + Vec3::new(0.6, 0.1, 0.0),
                far,
                far + Vec3::splat(50.0),
            ]
        })
        .collect();
    let pace: Vec<(Vec3, Real)> = (0..n)
        .map(|_| {
            let axis = next_vec(&mut s) - 0.5;
            (axis, 0.005 + 0.015 * next(&mut s))
        })
        .collect();
    let at = |k: usize, t: Real| base[k] + pace[k].0 * (pace[k].1 * t).sin();
    let (kept, met) = run_calls(400, |call| {
        let t = call as Real;
        (0..n)
            .map(|k| {
                let (c, d) = (at(k, t), at(k, t + 1.0) - at(k, t));
                let h = Vec3::splat(0.3);
                Some((Aabb::new(c - h, c + h), d))
            })
            .collect()
    });
    assert!(met > 0, "no pairs to find");
    assert!(
        kept.refattened > 10 * kept.rebuilds && kept.rebuilds > 0,
        "{} rebuilds, {} re-fattened in {} calls",
        kept.rebuilds,
        kept.refattened,
        kept.calls
    );
}

/// Small boxes flying apart with few pairs among them: after a filing that found few
/// candidates, fat boxes cover more steps (fewer filings), and the kept pairs are still
/// the grid's own every call.
#[test]
fn few_candidates_give_fat_boxes_covering_more_steps() {
    let mut s = 7;
    let n = 500;
    let mut at: Vec<Vec3> = (0..n).map(|_| next_vec(&mut s) * 40.0).collect();
    let v: Vec<Vec3> = (0..n).map(|_| (next_vec(&mut s) - 0.5) * 0.05).collect();
    let (kept, met) = run_calls(300, |_| {
        (0..n)
            .map(|k| {
                at[k] += v[k];
                let h = Vec3::splat(0.05 + 0.1 * (k % 4) as Real);
                Some((Aabb::new(at[k] - h, at[k] + h), v[k]))
            })
            .collect()
    });
    assert!(met > 0, "no pairs to find");
    assert!(kept.rebuilds >= 2, "{} rebuilds", kept.rebuilds);
    assert!(
        kept.ahead > AHEAD && kept.ahead <= MOST_AHEAD,
        "fat boxes cover {} steps",
        kept.ahead
    );
}

/// A lattice of boxes falling together, faster each call, some overlapping their
/// neighbours: in the world's frame every box changes its move each call by enough to
/// leave a fat box within a few calls; in the frame falling with them the boxes do not
/// move, and fat boxes riding with it hold them from the second call on. The kept pairs
/// are the grid's own every call (the pairs of boxes that meet within the step: the same
/// in any frame the boxes are swept in).
#[test]
fn boxes_falling_together_are_held_by_fat_boxes_riding_with_them() {
    use crate::stepped::moves::meet_within_step;
    let side = 10;
    let n = side * side * side;
    let g = Vec3::new(0.0, -0.003, 0.0);
    let place = |k: usize| lattice(side, k) * 0.75;
    // Apart at 0.3, one in seven at 0.5 overlapping its neighbours.
    let half = |k: usize| Vec3::splat(if k.is_multiple_of(7) { 0.5 } else { 0.3 });
    let (mut kept, mut fresh, mut met) = (FatPairs::default(), SteppedGrid::default(), 0);
    for call in 0..150 {
        let t = call as Real;
        // After t semi-implicit Euler steps from rest, and the move over the next.
        let (fall, d) = (g * (t * (t + 1.0) / 2.0), g * (t + 1.0));
        let boxes: Vec<Option<(Aabb, Vec3)>> = (0..n)
            .map(|k| {
                let c = place(k) + fall;
                Some((Aabb::new(c - half(k), c + half(k)), d))
            })
            .collect();
        let at = |i: u32| boxes[i as usize].expect("a box");
        let keep = |a: u32, b: u32| meet_within_step(at(a), at(b));
        met += same_as_fresh(&mut kept, &mut fresh, &boxes, Vec3::ZERO, &keep, call);
    }
    assert!(met > 0, "no pairs to find");
    assert!(
        kept.ready && kept.ride && kept.rebuilds == 1,
        "held: {}, riding: {}, {} rebuilds",
        kept.ready,
        kept.ride,
        kept.rebuilds
    );
}

/// A heap of boxes trembling in their contacts, each move unlike the last (far too
/// unsteady for the moves to promise fat boxes), with two bullets through it: the boxes
/// stay in place, the trial fat boxes show it, and fat boxes are tried and hold the pairs,
/// refiled only now and then for the bullets; the kept pairs are the grid's own every call.
#[test]
fn a_trembling_heap_with_bullets_through_it_is_held_by_fat_boxes() {
    let mut s = 13;
    let side = 8;
    let n = side * side * side;
    let place = |k: usize| lattice(side, k);
    let mut last: Vec<Vec3> = (0..n + 2).map(place).collect();
    let (kept, met) = run_calls(200, |call| {
        (0..n + 2)
            .map(|k| {
                let at = if k < n {
                    place(k) + (next_vec(&mut s) - 0.5) * 0.02
                } else {
                    // Through the heap along a row, and round again.
                    let x = -4.0 + 0.5 * (call % 32) as Real;
                    Vec3::new(x, 2.5 + (k - n) as Real * 3.0, 3.5)
                };
                moved_to(at, &mut last[k], if k < n { 0.5 } else { 0.1 })
            })
            .collect()
    });
    assert!(met > 0, "no pairs to find");
    // (Whether they are still held at the end is the clock's call: a test sharing the
    // machine can be preempted in a call.)
    assert!(
        kept.rebuilds > 0 && kept.rebuilds * 4 < kept.calls && kept.refattened > 0,
        "held: {}, {} rebuilds, {} re-fattened in {} calls",
        kept.ready,
        kept.rebuilds,
        kept.refattened,
        kept.calls
    );
}

/// A heap trembling in place, a twentieth of whose boxes jump to another place each call:
/// the boxes re-fattened since the filing come to be filed in a grid of their own for the
/// look-ups, and the kept pairs are the grid's own every call.
#[test]
fn boxes_leaving_their_fat_boxes_by_the_score_keep_every_pair() {
    let mut s = 17;
    let side = 12;
    let n = side * side * side;
    let place = |k: usize| lattice(side, k) * 1.1;
    let mut home: Vec<Vec3> = (0..n).map(place).collect();
    let mut last = home.clone();
    let (kept, met) = run_calls(120, |call| {
        // From the 40th call, some boxes trade places each call.
        if call >= 40 {
            for _ in 0..n / 40 {
                let (a, b) = (
                    (next(&mut s) * n as Real) as usize % n,
                    (next(&mut s) * n as Real) as usize % n,
                );
                home.swap(a, b);
            }
        }
        (0..n)
            .map(|k| {
                let at = home[k] + (next_vec(&mut s) - 0.5) * 0.01;
                moved_to(at, &mut last[k], 0.5)
            })
            .collect()
    });
    assert!(met > 0, "no pairs to find");
    assert!(
        kept.refat_filings > 0 && kept.refattened > 0,
        "{} filings of the re-fattened boxes, {} re-fattened, {} rebuilds in {} calls",
        kept.refat_filings,
        kept.refattened,
        kept.rebuilds,
        kept.calls
    );
}

/// A settled heap: boxes packed side by side, each trembling about its place. Fat boxes
/// hold its pairs, with candidates at least half as many as the boxes (each box rounded
/// once a call), and the kept pairs are the grid's own every call.
#[test]
fn a_settled_heap_is_held_by_fat_boxes_with_many_candidates() {
    let mut s = 11;
    let side = 8;
    let n = side * side * side;
    let place = |k: usize| lattice(side, k);
    let mut last: Vec<Vec3> = (0..n).map(place).collect();
    let (kept, met) = run_calls(200, |_| {
        (0..n)
            .map(|k| {
                let at = place(k) + (next_vec(&mut s) - 0.5) * 1e-4;
                moved_to(at, &mut last[k], 0.5)
            })
            .collect()
    });
    assert!(met > 0, "no pairs to find");
    assert!(kept.rebuilds >= 1, "fat boxes never filed");
    assert!(
        kept.ready && kept.candidates.len() * 2 >= n,
        "{} candidates for {n} boxes, held: {}",
        kept.candidates.len(),
        kept.ready
    );
}
