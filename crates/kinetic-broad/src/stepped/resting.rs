//! Boxes at rest kept filed between calls, so that a stepped world's sleeping and fixed
//! colliders cost next to nothing: only the boxes that moved are filed each call.
//!
//! A box *rests* when it did not change in this call (its collider did not move: a sleeping
//! body's, a fixed one's); it moves nothing over the coming step. The resting boxes are
//! filed once in a grid of their own, with the pairs among them. A call then files only the
//! other boxes (in a second grid, for their pairs among themselves), looks each of them up in
//! the resting grid, and keeps the resting pairs whose boxes have not changed since they
//! were filed. The pairs are exactly those the plain grid finds from all the boxes. The
//! resting boxes are filed afresh once more than one in [`STALE_SHARE`] (plus
//! [`STALE_MIN`]) of them has changed or come to rest since.
//!
//! The split is used while at least one box in [`REST_SHARE`] rests (stacks and heaps where
//! most bodies sleep, a world of fixed colliders); the caller finds the pairs as before
//! otherwise.

use super::SteppedGrid;
use super::sorted::merge;
use crate::aabb::Aabb;
use kinetic_core::Vec3;

/// The split is used while at least one box in this many rests (a world of a few fixed
/// colliders among moving bodies files them with the others).
const REST_SHARE: usize = 3;
/// ... this many (a look-up in the resting grid costs about what filing a box does, so the
/// split pays once most boxes rest).
const REST_OF: usize = 2;
/// The resting boxes are filed afresh once more than one in this many of them...
const STALE_SHARE: usize = 8;
/// ... plus this many has changed or come to rest since they were filed.
const STALE_MIN: usize = 16;
/// Each box and pair a call passes over (to find the moving boxes, to keep the resting
/// pairs) costs about this share of a box filed and looked up (measured in rapier on a
/// world of 8,000 sleeping bodies with 8,000 pairs: 0.14 ms a call with hardly a box
/// moving, where a pile's boxes are filed at about 0.27 µs each).
const PASSED_OVER: f64 = 1.0 / 32.0;
/// A call's work is averaged over about this many calls (a filing of the resting boxes
/// spread over the calls after it).
const SMOOTHING: f64 = 8.0;

/// The resting boxes' grid and pairs, and scratch for a call.
#[derive(Clone, Debug)]
pub(crate) struct Resting {
    /// The resting boxes as they were filed (never sorted and swept: the grid is looked up
    /// by every moving box), and the pairs among them, sorted.
    grid: SteppedGrid,
    pairs: Vec<(u32, u32)>,
    /// Per index, whether it was filed in `grid`, and the call at which it was.
    filed: Vec<bool>,
    filed_at: u64,
    /// Whether the grid holds anything.
    ready: bool,
    /// The grid of the moving boxes, filed each call.
    moving_grid: SteppedGrid,
    /// Scratch: the moving boxes' indices, the ids one looks up, and the pairs by kind.
    moving: Vec<u32>,
    found: Vec<u32>,
    own: Vec<(u32, u32)>,
    cross: Vec<(u32, u32)>,
    merged: Vec<(u32, u32)>,
    /// How many times the resting boxes were filed.
    pub(crate) filings: u64,
    /// The work of a split call, averaged, in boxes filed: each moving box filed and looked
    /// up, the resting boxes when they are filed afresh, and the boxes and pairs passed over
    /// (`None`: not split).
    work: Option<f64>,
}

impl Default for Resting {
    fn default() -> Self {
        Resting {
            grid: SteppedGrid::for_lookups(),
            pairs: Vec::new(),
            filed: Vec::new(),
            filed_at: 0,
            ready: false,
            moving_grid: SteppedGrid::default(),
            moving: Vec::new(),
            found: Vec::new(),
            own: Vec::new(),
            cross: Vec::new(),
            merged: Vec::new(),
            filings: 0,
            work: None,
        }
    }
}

impl Resting {
    /// The pairs `(a, b)`, `a < b`, of `boxes` (per index: the box and how far it moves over
    /// the coming step, swept by it) whose swept boxes overlap and that `keep(a, b)` keeps,
    /// into `out`, sorted, in call `call` (calls counted from 1); `changed[i]` is the last
    /// call in which box `i` changed (came, moved or went). A resting box (one that did not
    /// change in this call) is taken as not moving. Returns `false`, with `out` untouched,
    /// when too few boxes rest for the split to pay.
    pub(crate) fn pairs(
        &mut self,
        boxes: &[Option<(Aabb, Vec3)>],
        changed: &[u64],
        call: u64,
        keep: &dyn Fn(u32, u32) -> bool,
        out: &mut Vec<(u32, u32)>,
    ) -> bool {
        let n = boxes.len();
        let rests = |i: usize| boxes[i].is_some() && changed[i] < call;
        if self.filed.len() < n {
            self.filed.resize(n, false);
        }
        // One pass: the boxes resting, and those whose standing changed since the filing
        // (members no longer resting as filed, resting ones not filed).
        let filed_at = self.filed_at;
        let (mut resting, mut members, mut stale, mut lost) = (0, 0, 0, 0);
        for (i, &filed) in self.filed[..n].iter().enumerate() {
            let rest = rests(i);
            let still = rest && (!filed || changed[i] < filed_at);
            resting += usize::from(rest);
            members += usize::from(filed);
            stale += usize::from(filed != still);
            lost += usize::from(filed && !still);
        }
        if resting * REST_SHARE < REST_OF * n {
            self.ready = false;
            self.work = None;
            return false;
        }
        if self.ready && stale > members / STALE_SHARE + STALE_MIN {
            self.ready = false;
        }
        let refiled = !self.ready;
        if refiled {
            self.file(boxes, &rests, call, keep);
        }
        let filed_at = self.filed_at;
        let filed = &self.filed;
        let member = |i: usize| i < filed.len() && filed[i] && changed[i] < filed_at && rests(i);
        // The others: filed among themselves, and looked up among the members.
        self.moving.clear();
        self.moving
            .extend((0..n as u32).filter(|&i| boxes[i as usize].is_some() && !member(i as usize)));
        let swept = |i: u32| {
            let (b, d) = boxes[i as usize].expect("a box");
            if changed[i as usize] < call {
                b
            } else {
                b.swept(d)
            }
        };
        self.moving_grid.pairs(
            self.moving.iter().map(|&i| (i, swept(i))),
            keep,
            &mut self.own,
        );
        self.cross.clear();
        for &m in &self.moving {
            self.found.clear();
            self.grid.overlapping_with(&swept(m), &mut self.found);
            for &r in &self.found {
                if member(r as usize) && keep(m.min(r), m.max(r)) {
                    self.cross.push((m.min(r), m.max(r)));
                }
            }
        }
        self.cross.sort_unstable();
        self.cross.dedup();
        let filed = 2 * self.moving.len() + if refiled { resting } else { 0 };
        let work = filed as f64 + PASSED_OVER * (n + self.pairs.len()) as f64;
        self.work = Some(match self.work {
            Some(w) => w + (work - w) / SMOOTHING,
            None => work,
        });
        // The members' own pairs, those of both still members.
        out.clear();
        merge(&self.own, &self.cross, &mut self.merged);
        if refiled || lost == 0 {
            // Every box filed is (still) a member: all their pairs stand.
            merge(&self.pairs, &self.merged, out);
            return true;
        }
        let kept = self
            .pairs
            .iter()
            .copied()
            .filter(|&(a, b)| member(a as usize) && member(b as usize));
        let mut left = self.merged.iter().copied().peekable();
        for p in kept {
            while let Some(&q) = left.peek().filter(|&&q| q < p) {
                out.push(q);
                left.next();
            }
            out.push(p);
        }
        out.extend(left);
        true
    }

    /// The work of a call while the resting boxes are kept filed, averaged over the last
    /// few (in boxes filed): `None` while too few rest for that.
    pub(crate) fn work(&self) -> Option<f64> {
        self.work
    }

    /// Files every resting box afresh, unswept, with the pairs among them that `keep` keeps.
    fn file(
        &mut self,
        boxes: &[Option<(Aabb, Vec3)>],
        rests: &dyn Fn(usize) -> bool,
        call: u64,
        keep: &dyn Fn(u32, u32) -> bool,
    ) {
        self.filings += 1;
        self.filed_at = call;
        self.ready = true;
        for (i, f) in self.filed.iter_mut().enumerate() {
            *f = i < boxes.len() && rests(i);
        }
        let items = (0..boxes.len())
            .filter(|&i| self.filed[i])
            .map(|i| (i as u32, boxes[i].expect("a resting box").0));
        self.grid.remeasure();
        self.grid.pairs(items, keep, &mut self.pairs);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aabb::{next, next_vec, overlapping};

    /// Boxes at random in a cube, a share of them resting; over calls some wake and move,
    /// some fall asleep, some go and come: the pairs are always those of every box.
    #[test]
    fn the_pairs_are_those_of_every_box_as_boxes_wake_sleep_come_and_go() {
        let mut s = 7u64;
        let n = 600;
        let mut boxes: Vec<Option<(Aabb, Vec3)>> = (0..n)
            .map(|_| {
                let c = next_vec(&mut s) * 20.0;
                let h = Vec3::splat(0.2 + next(&mut s) * 0.6);
                Some((Aabb::about(c, h), (next_vec(&mut s) - 0.5) * 0.4))
            })
            .collect();
        let mut changed = vec![1u64; n];
        let mut resting = Resting::default();
        let (mut out, mut used) = (Vec::new(), 0);
        for call in 2..40u64 {
            for i in 0..n {
                let u = next(&mut s);
                // Most rest; a few move, a few go, a few come back.
                if u < 0.02 {
                    if let Some((b, d)) = boxes[i] {
                        boxes[i] = Some((Aabb::new(b.min + d, b.max + d), d));
                    }
                    changed[i] = call;
                } else if u < 0.023 {
                    boxes[i] = None;
                    changed[i] = call;
                } else if u < 0.03 && boxes[i].is_none() {
                    let c = next_vec(&mut s) * 20.0;
                    boxes[i] = Some((Aabb::about(c, Vec3::splat(0.4)), Vec3::ZERO));
                    changed[i] = call;
                }
            }
            let eff =
                |i: usize| boxes[i].map(|(b, d)| if changed[i] < call { b } else { b.swept(d) });
            let mut want = Vec::new();
            for a in 0..n {
                for b in a + 1..n {
                    if let (Some(x), Some(y)) = (eff(a), eff(b))
                        && overlapping(&x, &y)
                    {
                        want.push((a as u32, b as u32));
                    }
                }
            }
            if resting.pairs(&boxes, &changed, call, &|_, _| true, &mut out) {
                used += 1;
                assert_eq!(out, want, "call {call}");
            }
        }
        assert!(used > 30, "the split was used in {used} calls");
        assert!(
            resting.filings >= 2 && resting.filings < 20,
            "{}",
            resting.filings
        );
        // Too few resting: not used.
        let moved = vec![100u64; n];
        assert!(!resting.pairs(&boxes, &moved, 100, &|_, _| true, &mut out));
    }
}
