//! Sort and sweep: the pairs of a few boxes whose boxes overlap, found by sorting the boxes
//! along one axis and testing each against those that start before it ends. A world of a
//! few hundred boxes pays the stepped grid's fixed costs (cells, a counting sort, thirteen
//! neighbouring cells a box) for few tests; the sweep pays a sort.
//!
//! The axis is the one along which the boxes' centres spread most (a column of bodies
//! dropped on a ground: the vertical), so that a box overlaps few others along it. The
//! order of the last call is sorted again: where the boxes moved little it is nearly
//! sorted, and an insertion sort takes it in a pass.

use crate::aabb::{AabbF32, overlap};

/// The sweep's reused buffers.
#[derive(Clone, Debug, Default)]
pub(crate) struct SortAndSweep {
    /// The boxes' places by their lower ends along the axis, as last sorted.
    order: Vec<u32>,
    /// Each place's lower end along the last call's axis (a NaN end taken as infinite: such
    /// a box meets none, and sorts last).
    lows: Vec<f32>,
    /// The last call's axis, and the longest box along it.
    axis: usize,
    longest: f32,
}

impl SortAndSweep {
    /// Calls `hit(i, j)` for each pair of places `i`, `j` in `boxes` whose boxes overlap
    /// (touching counts; a box with a NaN side meets none), each pair once; returns `false`
    /// as soon as it has tested more than `budget` pairs (some pairs then not given).
    pub(crate) fn pairs(
        &mut self,
        boxes: &[AabbF32],
        budget: usize,
        mut hit: impl FnMut(u32, u32),
    ) -> bool {
        let n = boxes.len();
        let axis = spread_axis(boxes);
        self.axis = axis;
        // The lower ends and the longest box (NaN lengths left out), in one pass.
        self.lows.clear();
        let mut longest = 0.0f32;
        for b in boxes {
            self.lows.push(low(b, axis));
            let length = b[1][axis] - b[0][axis];
            if length > longest {
                longest = length;
            }
        }
        self.longest = longest;
        let lows = &self.lows;
        let key = |i: u32| lows[i as usize];
        // The last order, unless the boxes are not as many (then sorted afresh), or it takes
        // more than a few moves a box to sort (boxes of another kind).
        let again = self.order.len() == n && insertion_sort(&mut self.order, key, 4 * n);
        if !again {
            self.order.clear();
            self.order.extend(0..n as u32);
            self.order
                .sort_unstable_by(|&i, &j| key(i).total_cmp(&key(j)));
        }
        let mut tested = 0;
        for (k, &i) in self.order.iter().enumerate() {
            let a = &boxes[i as usize];
            let end = a[1][axis];
            for &j in &self.order[k + 1..] {
                // Sorted by lower ends: none after this one starts before `a` ends. (A NaN
                // end never stops the scan; such a box overlaps none.)
                if key(j) > end {
                    break;
                }
                if overlap(a, &boxes[j as usize]) {
                    hit(i, j);
                }
                tested += 1;
            }
            if tested > budget {
                return false;
            }
        }
        true
    }

    /// Calls `hit` with the place of each of the last call's `boxes` that overlaps `q`.
    pub(crate) fn query(&self, boxes: &[AabbF32], q: &AabbF32, mut hit: impl FnMut(u32)) {
        let axis = self.axis;
        // A box that overlaps `q` starts at most the longest box's length before it.
        let from = q[0][axis] - self.longest;
        let lows = &self.lows;
        let first = self.order.partition_point(|&i| lows[i as usize] < from);
        for &j in &self.order[first..] {
            if lows[j as usize] > q[1][axis] {
                break;
            }
            if overlap(q, &boxes[j as usize]) {
                hit(j);
            }
        }
    }
}

/// Box `b`'s lower end along `axis`, infinite for NaN.
fn low(b: &AabbF32, axis: usize) -> f32 {
    let x = b[0][axis];
    if x.is_nan() { f32::INFINITY } else { x }
}

/// The axis along which the boxes' centres spread most.
fn spread_axis(boxes: &[AabbF32]) -> usize {
    let (mut lo, mut hi) = (glam::Vec3A::INFINITY, glam::Vec3A::NEG_INFINITY);
    for b in boxes {
        // Twice the centre: the spread's order is the same.
        let c = b[0] + b[1];
        lo = lo.min(c);
        hi = hi.max(c);
    }
    let spread = hi - lo;
    if spread.y >= spread.x && spread.y >= spread.z {
        1
    } else if spread.z >= spread.x {
        2
    } else {
        0
    }
}

/// Sorts `order` by `key` (as `f32::total_cmp` orders), in place and in one pass where it
/// is nearly sorted; gives up (`false`, the order left a permutation) after `budget` moves.
fn insertion_sort(order: &mut [u32], key: impl Fn(u32) -> f32, budget: usize) -> bool {
    let mut moves = 0;
    for k in 1..order.len() {
        let x = order[k];
        let kx = key(x);
        let mut m = k;
        while m > 0 && key(order[m - 1]).total_cmp(&kx).is_gt() {
            order[m] = order[m - 1];
            m -= 1;
        }
        order[m] = x;
        moves += k - m;
        if moves > budget {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aabb::{next, next_vec};
    use glam::Vec3A;

    fn to_f32(lo: glam::DVec3, hi: glam::DVec3) -> AabbF32 {
        [lo.as_vec3().into(), hi.as_vec3().into()]
    }

    /// Boxes in a column and scattered about it, moved a little each call (the order of the
    /// last call nearly sorted), with a ground under them and a box with NaN sides: the
    /// sweep's pairs are the brute force's at every call.
    #[test]
    fn the_sweep_finds_exactly_the_overlapping_pairs() {
        let mut s = 21;
        let n = 150;
        let mut at: Vec<glam::DVec3> = (0..n)
            .map(|k| {
                let column = next_vec(&mut s) * glam::DVec3::new(2.0, 30.0, 2.0);
                if k % 3 == 0 {
                    next_vec(&mut s) * 20.0
                } else {
                    column
                }
            })
            .collect();
        let mut sweep = SortAndSweep::default();
        let mut found = 0;
        for call in 0..20 {
            let mut boxes: Vec<AabbF32> = at
                .iter()
                .enumerate()
                .map(|(k, &c)| {
                    let h = glam::DVec3::splat(0.3 + 0.4 * next(&mut s)) * (1 + k % 2) as f64;
                    to_f32(c - h, c + h)
                })
                .collect();
            boxes.push(to_f32(
                glam::DVec3::new(-50.0, -1.0, -50.0),
                glam::DVec3::new(50.0, 0.1, 50.0),
            ));
            boxes.push([Vec3A::NAN, Vec3A::NAN]);
            let mut got = Vec::new();
            assert!(sweep.pairs(&boxes, usize::MAX, |i, j| got.push((i.min(j), i.max(j)))));
            got.sort_unstable();
            let mut want = Vec::new();
            for i in 0..boxes.len() {
                for j in i + 1..boxes.len() {
                    if overlap(&boxes[i], &boxes[j]) {
                        want.push((i as u32, j as u32));
                    }
                }
            }
            assert_eq!(got, want, "call {call}");
            found += want.len();
            for c in &mut at {
                *c += (next_vec(&mut s) - 0.5) * 0.2;
            }
        }
        assert!(found > 100, "{found} pairs");
    }
}
