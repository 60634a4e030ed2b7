//! `sweep` (Section 3.1, Theorem 6): three kinetic sorted lists of the endpoints of the boxes
//! of the objects' outer balls, and the set of box pairs that overlap, each a candidate pair.
//!
//! Item `2 id` is the lower end of object `id`'s box on that axis, `2 id + 1` its upper end.
//! Two boxes overlap on an axis when each one's lower end is before the other's upper end in
//! that axis's list; they overlap when they do on all three. A swap of a lower end with an
//! upper end of another object is the only way that can change, so the set is kept exactly by
//! the swaps, and the audit reads it from the same three orders.
//!
//! Boxes are those of B+ (centre +/- outer radius), whose faces stay polynomials however the
//! object spins; an object that does not spin keeps its own axis-aligned box, which is
//! tighter (a ground slab, a wall). Every box is inflated by a relative 1e-9 so that two
//! objects that touch have boxes that overlap strictly: the pair is a candidate before its
//! contact begins, even at a tie.

use crate::axes::{AxisItems, AxisLists};
use crate::cell_math::{Ends, box_ends};
use kinetic_core::kds::{Bodies, PairChange, ScalarKey, ordered_pair};
use kinetic_core::{CandidateStructure, Real, Vec3};
use rustc_hash::FxHashSet;

/// The sweep over boxes: candidate pairs are the objects whose outer balls' boxes overlap.
#[derive(Debug, Default)]
pub struct Sweep {
    lists: AxisLists,
    /// Each object's box, as offsets (min, max) from its centre (`None` for ids not in the
    /// structure).
    ends: Vec<Option<Ends>>,
    /// The objects whose boxes overlap each object's box.
    partners: Vec<Vec<u32>>,
    pairs: usize,
}

fn lower(id: u32) -> u32 {
    2 * id
}

fn upper(id: u32) -> u32 {
    2 * id + 1
}

/// The two ends of object `id`'s box.
fn items(bodies: &Bodies, id: u32, (lo, hi): Ends) -> AxisItems {
    let plan = &bodies[id as usize].as_ref().expect("a live object").plan;
    vec![
        std::array::from_fn(|axis| (lower(id), ScalarKey::from_plan(plan, axis, lo[axis]))),
        std::array::from_fn(|axis| (upper(id), ScalarKey::from_plan(plan, axis, hi[axis]))),
    ]
}

impl Sweep {
    /// An empty sweep.
    pub fn new() -> Sweep {
        Sweep::default()
    }

    /// Number of overlapping box pairs.
    pub fn box_pairs(&self) -> usize {
        self.pairs
    }

    /// Swaps processed so far, over the three lists.
    pub fn swaps(&self) -> u64 {
        self.lists.swaps()
    }

    fn present(&self, id: u32) -> bool {
        self.ends.get(id as usize).is_some_and(Option::is_some)
    }

    /// Whether the boxes of `a` and `b` overlap on `axis`, read from that list's order.
    fn overlap_on(&self, axis: usize, a: u32, b: u32) -> bool {
        let p = |item| self.lists.position(axis, item);
        p(lower(a)) < p(upper(b)) && p(lower(b)) < p(upper(a))
    }

    /// Links the pair of `a` and `b`, reported in order ([`ordered_pair`]).
    fn link(&mut self, a: u32, b: u32, changes: &mut Vec<PairChange>) {
        let (a, b) = ordered_pair(a, b);
        self.partners[a as usize].push(b);
        self.partners[b as usize].push(a);
        self.pairs += 1;
        changes.push(PairChange { a, b, delta: 1 });
    }

    /// Unlinks the pair of `a` and `b`, reported in order ([`ordered_pair`]).
    fn unlink(&mut self, a: u32, b: u32, changes: &mut Vec<PairChange>) {
        let (a, b) = ordered_pair(a, b);
        for (x, y) in [(a, b), (b, a)] {
            let list = &mut self.partners[x as usize];
            let i = list.iter().position(|&p| p == y).expect("a linked pair");
            list.swap_remove(i);
        }
        self.pairs -= 1;
        changes.push(PairChange { a, b, delta: -1 });
    }

    fn grow(&mut self, id: u32) {
        let need = id as usize + 1;
        if self.ends.len() < need {
            self.ends.resize(need, None);
            self.partners.resize(need, Vec::new());
        }
    }

    /// The objects whose boxes overlap `id`'s, read from the lists' orders: those whose
    /// lower x end is before its upper x end and whose upper x end is after its lower x end,
    /// and that overlap it on y and z.
    fn overlapping(&self, id: u32) -> Vec<u32> {
        let x = self.lists.list(0);
        let (lo_x, hi_x) = (
            self.lists.position(0, lower(id)),
            self.lists.position(0, upper(id)),
        );
        x.order()[..hi_x]
            .iter()
            .filter(|&&item| item % 2 == 0 && item / 2 != id)
            .map(|&item| item / 2)
            .filter(|&o| self.lists.position(0, upper(o)) > lo_x)
            .filter(|&o| self.overlap_on(1, id, o) && self.overlap_on(2, id, o))
            .collect()
    }

    /// Every overlapping pair among `ids`' boxes and the others, by a sweep along x.
    fn overlapping_pairs(&self) -> Vec<(u32, u32)> {
        let mut out = Vec::new();
        let mut active: Vec<u32> = Vec::new();
        let mut slot: Vec<u32> = vec![u32::MAX; self.ends.len()];
        for &item in self.lists.list(0).order() {
            let id = item / 2;
            if item % 2 == 0 {
                for &other in &active {
                    if self.overlap_on(1, id, other) && self.overlap_on(2, id, other) {
                        out.push(ordered_pair(id, other));
                    }
                }
                slot[id as usize] = active.len() as u32;
                active.push(id);
            } else {
                let i = slot[id as usize] as usize;
                active.swap_remove(i);
                if let Some(&moved) = active.get(i) {
                    slot[moved as usize] = i as u32;
                }
            }
        }
        out
    }
}

impl CandidateStructure for Sweep {
    fn name(&self) -> &'static str {
        "sweep"
    }

    fn insert(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        self.lists.sync(now);
        self.grow(id);
        let ends = box_ends(bodies, id);
        self.ends[id as usize] = Some(ends);
        self.lists.insert(items(bodies, id, ends));
        for o in self.overlapping(id) {
            self.link(id, o, changes);
        }
    }

    fn insert_many(
        &mut self,
        ids: &[u32],
        bodies: &Bodies,
        now: Real,
        changes: &mut Vec<PairChange>,
    ) {
        if !self.lists.is_empty() || ids.len() < 2 {
            for &id in ids {
                self.insert(id, bodies, now, changes);
            }
            return;
        }
        // An empty sweep: build the lists in one go and sweep for the overlapping boxes.
        let mut all = Vec::with_capacity(2 * ids.len());
        for &id in ids {
            self.grow(id);
            let ends = box_ends(bodies, id);
            self.ends[id as usize] = Some(ends);
            all.extend(items(bodies, id, ends));
        }
        self.lists = AxisLists::build(now, all);
        for (a, b) in self.overlapping_pairs() {
            self.link(a, b, changes);
        }
    }

    fn remove(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.lists.sync(now);
        for o in self.partners[id as usize].clone() {
            self.unlink(id, o, changes);
        }
        let ends = self.ends[id as usize].take().expect("present");
        self.lists.remove(items(bodies, id, ends));
    }

    fn replan(&mut self, id: u32, bodies: &Bodies, now: Real, changes: &mut Vec<PairChange>) {
        if !self.present(id) {
            return;
        }
        self.lists.sync(now);
        // A new plan may start or stop a spin, which changes the box.
        let ends = box_ends(bodies, id);
        self.ends[id as usize] = Some(ends);
        let new = items(bodies, id, ends);
        if self.lists.keeps_order(&new, now) {
            self.lists.set_keys(new);
            return;
        }
        // The box jumped: it is filed afresh where it is now, and its pairs change at once
        // (the new ones first, so that a pair in contact never drops to no holder).
        let old = self.partners[id as usize].clone();
        self.lists.remove(new.clone());
        self.lists.insert(new);
        let now_overlapping = self.overlapping(id);
        for &o in &now_overlapping {
            if !old.contains(&o) {
                self.link(id, o, changes);
            }
        }
        for o in old {
            if !now_overlapping.contains(&o) {
                self.unlink(id, o, changes);
            }
        }
    }

    fn next_event_time(&self) -> Real {
        self.lists.next_event_time()
    }

    fn process_next_event(&mut self, _: &Bodies, changes: &mut Vec<PairChange>) -> &'static str {
        let Some((axis, swap)) = self.lists.next_swap() else {
            return "swap";
        };
        let (a, b) = (swap.left / 2, swap.right / 2);
        // An upper end passing a lower end of another box (they meet on this axis) or a lower
        // end passing an upper end (they part) changes the pair iff the other axes overlap.
        let meets = (swap.left % 2, swap.right % 2) == (1, 0);
        let parts = (swap.left % 2, swap.right % 2) == (0, 1);
        if a != b
            && (meets || parts)
            && (0..3)
                .filter(|&k| k != axis)
                .all(|k| self.overlap_on(k, a, b))
        {
            if meets {
                self.link(a, b, changes);
            } else {
                self.unlink(a, b, changes);
            }
        }
        "swap"
    }

    fn certificates(&self) -> usize {
        self.lists.certificates()
    }

    fn counters(&self) -> Vec<(&'static str, f64)> {
        vec![("box_pairs", self.pairs as f64)]
    }

    fn boxes(&self, bodies: &Bodies, now: Real) -> Vec<(Vec3, Vec3)> {
        let centre = |id: usize| bodies.get(id)?.as_ref().map(|b| b.plan.position_at(now));
        (0..self.ends.len())
            .filter_map(|id| Some((centre(id)?, self.ends[id]?)))
            .map(|(c, (lo, hi))| (c + lo, c + hi))
            .collect()
    }

    fn validate(&self, bodies: &Bodies, now: Real) -> Result<(), String> {
        self.lists.validate(
            "sweep",
            bodies,
            now,
            |id| self.present(id),
            |id| items(bodies, id, box_ends(bodies, id)),
        )?;
        let want: FxHashSet<(u32, u32)> = self.overlapping_pairs().into_iter().collect();
        let mut have = FxHashSet::default();
        for (a, ps) in self.partners.iter().enumerate() {
            for &b in ps {
                let a = a as u32;
                if a < b {
                    have.insert((a, b));
                }
            }
        }
        if want != have || have.len() != self.pairs {
            let missing = want.difference(&have).next();
            let extra = have.difference(&want).next();
            return Err(format!(
                "sweep pairs: {} kept, {} overlap (missing {missing:?}, extra {extra:?})",
                self.pairs,
                want.len()
            ));
        }
        Ok(())
    }
}
