//! The pairs of boxes that an engine moves one at a time: its enlarged boxes (avian's
//! `EnlargedAabb`), each moved only when its collider leaves it. A call looks only at the
//! boxes that changed in it, so a world whose bodies jostle inside their boxes costs next to
//! nothing, however many pairs it holds.
//!
//! Where the engine keeps an index of these boxes for its own queries
//! ([`crate::Engine::enlarged_near`]: avian's collider trees, kept up to date whichever broad
//! phase runs), each changed box is looked up there, and nothing is filed, unless so many
//! changed in one call that filing every box (below) costs less. Otherwise:
//!
//! The boxes are filed in a grid once ([`SteppedGrid`], for look-ups); a box that changes
//! leaves the grid for a short list of *loose* boxes. Each changed box is looked up among
//! the filed boxes that have not changed since and among the loose ones, and its pairs
//! (kept per box) are brought to what it overlaps now, with an add or a delete for each
//! difference. All the boxes are filed afresh, the pairs found from the grid and compared
//! with those held, both sorted, in one pass, when that costs less, counted in boxes filed
//! and pairs found (the same counts, so the same choices, on every run):
//! - a call whose look-ups would cost more than filing every box (the last filing's count);
//! - once the loose boxes, filed or scanned again at each call, have cost as much as one
//!   filing since the last (a renter buys once the rent has come to the price: at most
//!   twice the cheaper of the two, whatever the calls to come).

use super::SteppedGrid;
use super::sorted::sorted_difference;
use crate::aabb::{Aabb, AabbF32, overlap, to_f32};

/// A changed box's look-up (the filed and loose boxes near it, its partners sorted and
/// compared) costs about this many boxes filed or pairs found in a filing of every box
/// (measured on two draws of the engine scene space in avian: a gas of 11,517 bodies with a
/// third moving each step, whose broad phase took 2.8x avian's at 4 and 1.25x at 8, and a
/// stack of 326 with a quarter moving, 0.2 ms at either).
const LOOKUP_WORK: usize = 8;
/// The loose boxes are filed in a grid of their own for a call's look-ups once the tests a
/// scan would make are more than this many per box filed and looked up (chosen, not
/// fitted: a box test costs a few nanoseconds, a filing and a look-up some hundreds).
pub(super) const SCAN_MOST: usize = 32;
/// The place of a box that is not loose.
const NOT_LOOSE: u32 = u32::MAX;

/// The boxes, their pairs, and the grid they are filed in.
#[derive(Clone, Debug)]
pub(crate) struct EnlargedPairs {
    /// Per index, its box now.
    boxes: Vec<Option<Aabb>>,
    /// Per index, the indices it is paired with (both ends hold each pair), and the pairs.
    partners: Vec<Vec<u32>>,
    count: usize,
    /// The grid of the filed boxes, and per index whether its box is filed there (it has
    /// not changed since).
    grid: SteppedGrid,
    filed: Vec<bool>,
    filed_count: usize,
    /// The boxes changed since they were filed, and per index its place among them
    /// ([`NOT_LOOSE`]: not among them).
    loose: Vec<u32>,
    loose_at: Vec<u32>,
    /// A call's loose boxes side by side, rounded out to single precision (scanned, with
    /// their indices beside them), or in a grid of their own, and scratch.
    loose_boxes: Vec<AabbF32>,
    loose_ids: Vec<u32>,
    loose_grid: SteppedGrid,
    found: Vec<u32>,
    near: Vec<u32>,
    all: Vec<(u32, u32)>,
    old: Vec<(u32, u32)>,
    gone: Vec<u32>,
    came: Vec<u32>,
    /// The last filing of every box, in boxes filed and pairs found, and the loose boxes
    /// filed or scanned since, in boxes.
    filing_work: usize,
    loose_work: usize,
    /// How many times every box was filed afresh.
    pub(crate) filings: u64,
    /// Whether the engine keeps an index of the boxes that look-ups use instead of the grid
    /// (not known before the first look-up).
    engine_index: Option<bool>,
    /// On the engine's index: what a look-up and a unit of filing cost on this world.
    paces: Paces,
    /// Boxes looked up in the engine's index.
    pub(crate) engine_lookups: u64,
}

/// What a look-up in the engine's index and a unit of a filing of every box (a box filed or a
/// pair found) cost on this world, as measured: the two ways differ tenfold from one world
/// to another (against a filing, a look-up in avian's trees costs about one unit in a pile of
/// 488 bodies and about nine in a gas of 11,517).
#[derive(Clone, Debug)]
struct Paces {
    /// Nanoseconds a look-up and a unit of filing; before a way is measured, a guess.
    lookup: f64,
    unit: f64,
    calls: u64,
    /// The call at which the way not taken is next tried, the calls between tries, and
    /// while a try runs, what the way not tried was priced at.
    next_try: u64,
    wait: u64,
    trying: Option<f64>,
}

/// After this many calls, the way not taken is taken if it is not priced at more than
/// [`TRY_AT_MOST`] times the other, so that its pace is measured again as the world changes;
/// a try that costs more than the other way would have waits twice as long for the next,
/// up to [`LAST_TRY_WAIT`] calls (chosen, not fitted: a try costs at most three times the
/// cheaper way, on one call in 16 at first; a stack of 625 bodies in avian lost 8% of its
/// broad phase to tries costing twice the look-ups, one call in 16).
const TRY_EVERY: u64 = 16;
const TRY_AT_MOST: f64 = 3.0;
const LAST_TRY_WAIT: u64 = 256;

impl Default for Paces {
    fn default() -> Self {
        // Guesses: a unit of filing about 30 ns, a look-up `LOOKUP_WORK` units.
        Paces {
            lookup: 30.0 * LOOKUP_WORK as f64,
            unit: 30.0,
            calls: 0,
            next_try: TRY_EVERY,
            wait: TRY_EVERY,
            trying: None,
        }
    }
}

impl Paces {
    /// Whether to file every box (`filing` units) rather than look up `lookups` boxes.
    fn file(&mut self, lookups: usize, filing: usize) -> bool {
        let (look, file) = (lookups as f64 * self.lookup, filing as f64 * self.unit);
        self.calls += 1;
        let (cheaper, dearer) = (look.min(file), look.max(file));
        let try_other = self.calls >= self.next_try && dearer <= TRY_AT_MOST * cheaper;
        if try_other {
            self.trying = Some(cheaper);
        }
        (file < look) != try_other
    }

    /// A way was taken (`filed`) and took `took` for `work` look-ups or units.
    fn measured(&mut self, filed: bool, took: std::time::Duration, work: usize) {
        if let Some(other) = self.trying.take() {
            // A try that lost waits longer for the next; one that won, not.
            self.wait = if took.as_nanos() as f64 > other {
                (2 * self.wait).min(LAST_TRY_WAIT)
            } else {
                TRY_EVERY
            };
            self.next_try = self.calls + self.wait;
        }
        if work == 0 {
            return;
        }
        let pace = took.as_nanos() as f64 / work as f64;
        let p = if filed {
            &mut self.unit
        } else {
            &mut self.lookup
        };
        *p = 0.5 * *p + 0.5 * pace;
    }
}

impl Default for EnlargedPairs {
    fn default() -> Self {
        EnlargedPairs {
            boxes: Vec::new(),
            partners: Vec::new(),
            count: 0,
            grid: SteppedGrid::for_lookups(),
            filed: Vec::new(),
            filed_count: 0,
            loose: Vec::new(),
            loose_at: Vec::new(),
            loose_boxes: Vec::new(),
            loose_ids: Vec::new(),
            loose_grid: SteppedGrid::for_lookups(),
            found: Vec::new(),
            near: Vec::new(),
            all: Vec::new(),
            old: Vec::new(),
            gone: Vec::new(),
            came: Vec::new(),
            filing_work: 0,
            loose_work: 0,
            filings: 0,
            engine_index: None,
            paces: Paces::default(),
            engine_lookups: 0,
        }
    }
}

impl EnlargedPairs {
    /// The pairs held.
    pub(crate) fn count(&self) -> usize {
        self.count
    }

    /// The boxes paired with box `i`.
    pub(crate) fn partners(&self, i: u32) -> &[u32] {
        self.partners.get(i as usize).map_or(&[], |p| &p[..])
    }

    /// Whether boxes `a` and `b` are paired.
    pub(crate) fn has(&self, a: u32, b: u32) -> bool {
        self.partners
            .get(a as usize)
            .is_some_and(|p| p.contains(&b))
    }

    /// Every pair `(a, b)`, `a < b`, sorted.
    pub(crate) fn sorted(&self) -> Vec<(u32, u32)> {
        let mut out: Vec<(u32, u32)> = (0..self.partners.len() as u32)
            .flat_map(|a| {
                self.partners[a as usize]
                    .iter()
                    .filter(move |&&b| a < b)
                    .map(move |&b| (a, b))
            })
            .collect();
        out.sort_unstable();
        out
    }

    /// Makes room for index `i`.
    fn reach(&mut self, i: usize) {
        if self.boxes.len() <= i {
            let n = i + 1;
            self.boxes.resize(n, None);
            self.partners.resize(n, Vec::new());
            self.filed.resize(n, false);
            self.loose_at.resize(n, NOT_LOOSE);
        }
    }

    /// Drops box `i` and its pairs without a word (the engine drops a removed collider's
    /// pairs itself).
    pub(crate) fn forget(&mut self, i: u32) {
        let i = i as usize;
        self.reach(i);
        self.unfile(i);
        self.boxes[i] = None;
        for j in std::mem::take(&mut self.partners[i]) {
            self.partners[j as usize].retain(|&x| x as usize != i);
            self.count -= 1;
        }
    }

    /// Takes box `i` out of the grid (it changed) and out of the loose list.
    fn unfile(&mut self, i: usize) {
        if std::mem::take(&mut self.filed[i]) {
            self.filed_count -= 1;
        }
        let at = std::mem::replace(&mut self.loose_at[i], NOT_LOOSE);
        if at != NOT_LOOSE {
            self.loose.swap_remove(at as usize);
            if let Some(&moved) = self.loose.get(at as usize) {
                self.loose_at[moved as usize] = at;
            }
        }
    }

    /// One call: the boxes of `changed` (indices, each once) are now `boxes_now(i)`; every
    /// pair added is pushed onto `adds` and every pair gone onto `deletes`, as `(a, b)`,
    /// `a < b`.
    pub(crate) fn update(
        &mut self,
        changed: &[u32],
        boxes_now: &dyn Fn(u32) -> Option<Aabb>,
        engine_near: &dyn Fn(u32, &Aabb, &mut Vec<u32>) -> bool,
        adds: &mut Vec<(u32, u32)>,
        deletes: &mut Vec<(u32, u32)>,
    ) {
        if let Some(&last) = changed.iter().max() {
            self.reach(last as usize);
        }
        if self.engine_index != Some(false) {
            for &i in changed {
                self.boxes[i as usize] = boxes_now(i);
            }
            if self.engine_index.is_none() {
                // Whether the engine keeps an index, asked once of a box there (the first call
                // then files every box: a look-up each would cost several times more).
                let first = changed
                    .iter()
                    .find_map(|&i| Some((i, self.boxes[i as usize]?)));
                if let Some((i, b)) = first {
                    self.found.clear();
                    self.engine_index = Some(engine_near(i, &b, &mut self.found));
                }
            }
            if self.engine_index == Some(true) {
                // Look the changed boxes up, or file every box, whichever this world's
                // measured paces say costs less; the same pairs and events either way.
                let file = self.paces.file(changed.len(), self.filing_work);
                let start = std::time::Instant::now();
                if file {
                    self.file_all_and_diff(adds, deletes);
                } else {
                    self.look_up_in_engine(changed, engine_near, adds, deletes);
                }
                let work = if file {
                    self.filing_work
                } else {
                    changed.len()
                };
                self.paces.measured(file, start.elapsed(), work);
                return;
            }
        }
        for &i in changed {
            self.unfile(i as usize);
            let b = boxes_now(i);
            self.boxes[i as usize] = b;
            if b.is_some() {
                self.loose_at[i as usize] = self.loose.len() as u32;
                self.loose.push(i);
            }
        }
        let loose = self.loose.len();
        if changed.len() * LOOKUP_WORK + loose > self.filing_work
            || self.loose_work + loose > self.filing_work
        {
            // Filing every box finds every pair: those are taken as they are.
            self.file_all_and_diff(adds, deletes);
        } else {
            self.loose_work += loose;
            self.look_up(changed, adds, deletes);
        }
    }

    /// Brings the pairs of each box of `changed` to those it overlaps now, looked up in the
    /// engine's own index of the boxes ([`crate::Engine::enlarged_near`]).
    fn look_up_in_engine(
        &mut self,
        changed: &[u32],
        engine_near: &dyn Fn(u32, &Aabb, &mut Vec<u32>) -> bool,
        adds: &mut Vec<(u32, u32)>,
        deletes: &mut Vec<(u32, u32)>,
    ) {
        for &i in changed {
            let mut near = std::mem::take(&mut self.near);
            near.clear();
            if let Some(b) = self.boxes[i as usize] {
                self.found.clear();
                engine_near(i, &b, &mut self.found);
                let boxes = &self.boxes;
                let meets = |&j: &u32| j != i && boxes[j as usize].is_some_and(|c| c.overlaps(&b));
                let found = self
                    .found
                    .iter()
                    .copied()
                    .filter(|&j| (j as usize) < boxes.len());
                near.extend(found.filter(meets));
                near.sort_unstable();
                near.dedup();
            }
            self.set_partners(i, &near, adds, deletes);
            self.near = near;
        }
        // What filing every box would cost now (its slots, for its boxes).
        self.filing_work = self.boxes.len() + self.count;
        self.engine_lookups += changed.len() as u64;
        // In order, as a filing gives them: the same events whichever way they were found.
        adds.sort_unstable();
        deletes.sort_unstable();
    }

    /// Brings the pairs of each box of `changed` to those it overlaps now.
    fn look_up(
        &mut self,
        changed: &[u32],
        adds: &mut Vec<(u32, u32)>,
        deletes: &mut Vec<(u32, u32)>,
    ) {
        let scan =
            changed.len() * self.loose.len() <= SCAN_MOST * (changed.len() + self.loose.len());
        // The loose boxes side by side, scanned in order, or filed in a grid of their own.
        let boxes = &self.boxes;
        let loose = self
            .loose
            .iter()
            .map(|&i| (i, boxes[i as usize].expect("loose")));
        self.loose_boxes.clear();
        self.loose_ids.clear();
        if scan {
            for (i, b) in loose {
                self.loose_boxes.push(to_f32(&b));
                self.loose_ids.push(i);
            }
        } else {
            self.loose_grid.file_for_lookups(loose);
        }
        for &i in changed {
            let mut near = std::mem::take(&mut self.near);
            near.clear();
            if let Some(b) = self.boxes[i as usize] {
                // The filed boxes that have not changed since, then the loose ones.
                self.found.clear();
                self.grid.overlapping_with(&b, &mut self.found);
                let (filed, boxes) = (&self.filed, &self.boxes);
                let exact = |j: u32| j != i && boxes[j as usize].is_some_and(|c| c.overlaps(&b));
                near.extend(
                    self.found
                        .iter()
                        .copied()
                        .filter(|&j| filed[j as usize] && exact(j)),
                );
                if scan {
                    // Rounded out, a test passes every pair that meets: the few that pass
                    // are tested exactly.
                    let q = to_f32(&b);
                    let meets = self.loose_boxes.iter().zip(&self.loose_ids);
                    let meets = meets.filter(|(c, _)| overlap(c, &q));
                    near.extend(meets.map(|(_, &j)| j).filter(|&j| exact(j)));
                } else {
                    self.found.clear();
                    self.loose_grid.overlapping_with(&b, &mut self.found);
                    near.extend(self.found.iter().copied().filter(|&j| exact(j)));
                }
                near.sort_unstable();
                near.dedup();
            }
            self.set_partners(i, &near, adds, deletes);
            self.near = near;
        }
    }

    /// Box `i`'s partners become `near` (sorted): the pairs gone and new are noted at both
    /// ends.
    fn set_partners(
        &mut self,
        i: u32,
        near: &[u32],
        adds: &mut Vec<(u32, u32)>,
        deletes: &mut Vec<(u32, u32)>,
    ) {
        let mut old = std::mem::take(&mut self.partners[i as usize]);
        old.sort_unstable();
        let pair = |j: u32| (i.min(j), i.max(j));
        let (mut gone, mut came) = (
            std::mem::take(&mut self.gone),
            std::mem::take(&mut self.came),
        );
        gone.clear();
        came.clear();
        sorted_difference(&old, near, |x| gone.push(x), |y| came.push(y));
        for &x in &gone {
            self.partners[x as usize].retain(|&k| k != i);
            self.count -= 1;
            deletes.push(pair(x));
        }
        for &y in &came {
            self.partners[y as usize].push(i);
            self.count += 1;
            adds.push(pair(y));
        }
        (self.gone, self.came) = (gone, came);
        old.clear();
        old.extend_from_slice(near);
        self.partners[i as usize] = old;
    }

    /// Files every box afresh; its pairs, found from the grid, go to `all`.
    fn file_all(&mut self) {
        self.filings += 1;
        for &i in &self.loose {
            self.loose_at[i as usize] = NOT_LOOSE;
        }
        self.loose.clear();
        self.filed_count = 0;
        for (f, b) in self.filed.iter_mut().zip(&self.boxes) {
            *f = b.is_some();
            self.filed_count += usize::from(*f);
        }
        let boxes = &self.boxes;
        let items = (0..boxes.len() as u32).filter_map(|i| boxes[i as usize].map(|b| (i, b)));
        let keep = |a: u32, b: u32| match (boxes[a as usize], boxes[b as usize]) {
            (Some(x), Some(y)) => x.overlaps(&y),
            _ => false,
        };
        self.grid.remeasure();
        self.grid.pairs(items, &keep, &mut self.all);
    }

    /// Files every box afresh and brings the pairs to those found: the old and the new,
    /// both sorted, compared in one pass, and each box's partners listed again.
    fn file_all_and_diff(&mut self, adds: &mut Vec<(u32, u32)>, deletes: &mut Vec<(u32, u32)>) {
        self.file_all();
        let mut old = std::mem::take(&mut self.old);
        old.clear();
        for (a, list) in self.partners.iter_mut().enumerate() {
            list.sort_unstable();
            let a = a as u32;
            old.extend(list.iter().filter(|&&b| a < b).map(|&b| (a, b)));
        }
        let new = &self.all;
        sorted_difference(&old, new, |x| deletes.push(x), |y| adds.push(y));
        self.old = old;
        self.filing_work = self.filed_count + new.len();
        self.loose_work = 0;
        for list in &mut self.partners {
            list.clear();
        }
        for &(a, b) in new {
            self.partners[a as usize].push(b);
            self.partners[b as usize].push(a);
        }
        self.count = new.len();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::aabb::{next, next_vec};
    use kinetic_core::Vec3;
    use std::collections::BTreeSet;

    /// With look-ups priced lower, filing is tried after 16 calls, and after twice as many
    /// each time it costs more than the look-ups would have.
    #[test]
    fn a_try_of_the_other_way_that_loses_waits_twice_as_long_for_the_next() {
        let mut paces = Paces {
            lookup: 100.0,
            unit: 10.0,
            ..Paces::default()
        };
        let mut tries = Vec::new();
        for call in 1..=200u64 {
            // 10 look-ups (1,000 ns) against a filing of 200 units (2,000 ns, then 2,500).
            let file = paces.file(10, 200);
            if file {
                tries.push(call);
            }
            let (took, work) = if file { (3000, 200) } else { (1000, 10) };
            paces.measured(file, std::time::Duration::from_nanos(took), work);
        }
        assert_eq!(tries, [16, 48, 112]);
        // A try that wins brings the next one back to 16 calls on.
        let file = (0..300).find(|_| paces.file(10, 200)).is_some();
        assert!(file);
        paces.measured(true, std::time::Duration::from_nanos(500), 200);
        let calls = paces.calls;
        let next = (1..=100)
            .find(|_| paces.file(10, 200))
            .expect("another try");
        assert_eq!(paces.calls, calls + 16, "{next}");
    }

    /// Boxes in a cube of which a few move, go and come each call, now and then many: the
    /// pairs held, and those the adds and deletes build, are always those of every box.
    #[test]
    fn the_pairs_are_those_of_every_box_as_a_few_boxes_change_each_call() {
        for engine_index in [false, true] {
            pairs_as_boxes_change(engine_index);
        }
    }

    /// With `engine_index`, the look-ups ask an index of the engine's (here: the boxes that
    /// overlap, rounded out, and every tenth box besides, as a superset).
    fn pairs_as_boxes_change(engine_index: bool) {
        let mut s = 11u64;
        let n = 500;
        let mut boxes: Vec<Option<Aabb>> = (0..n)
            .map(|_| {
                let h = Vec3::splat(0.2 + next(&mut s) * 0.6);
                Some(Aabb::about(next_vec(&mut s) * 15.0, h))
            })
            .collect();
        let mut pairs = EnlargedPairs::default();
        let mut built = BTreeSet::new();
        let (mut adds, mut deletes) = (Vec::new(), Vec::new());
        for call in 0..60 {
            let share = match call {
                0 => 1.0,
                20 | 41 => 0.6,
                _ => 0.01 + 0.02 * next(&mut s),
            };
            let mut changed = Vec::new();
            for (i, b) in boxes.iter_mut().enumerate() {
                if call > 0 && next(&mut s) >= share {
                    continue;
                }
                changed.push(i as u32);
                let u = next(&mut s);
                *b = if u < 0.1 {
                    None
                } else {
                    let h = Vec3::splat(0.2 + next(&mut s) * 0.6);
                    Some(Aabb::about(next_vec(&mut s) * 15.0, h))
                };
            }
            adds.clear();
            deletes.clear();
            let near = |i: u32, b: &Aabb, out: &mut Vec<u32>| {
                assert_eq!(
                    boxes[i as usize].as_ref(),
                    Some(b),
                    "box {i} looked up as it is"
                );
                let grown = b.grown(Vec3::splat(1e-6));
                let near = (0..n as u32).filter(|&j| {
                    j % 10 == 0 || boxes[j as usize].is_some_and(|c| c.overlaps(&grown))
                });
                out.extend(near);
                engine_index
            };
            pairs.update(
                &changed,
                &|i| boxes[i as usize],
                &near,
                &mut adds,
                &mut deletes,
            );
            for p in &deletes {
                assert!(built.remove(p), "call {call}: {p:?} deleted, not held");
            }
            for p in &adds {
                assert!(built.insert(*p), "call {call}: {p:?} added twice");
            }
            let mut want = BTreeSet::new();
            for a in 0..n {
                for b in a + 1..n {
                    if let (Some(x), Some(y)) = (boxes[a], boxes[b])
                        && x.overlaps(&y)
                    {
                        want.insert((a as u32, b as u32));
                    }
                }
            }
            assert_eq!(built, want, "call {call}");
            assert_eq!(pairs.sorted(), want.iter().copied().collect::<Vec<_>>());
            assert_eq!(pairs.count(), want.len());
            if let Some(&(a, b)) = want.iter().next() {
                assert!(pairs.has(a, b) && pairs.has(b, a));
            }
        }
        if engine_index {
            // Looked up in the engine's index (and filed where that measured cheaper).
            assert!(pairs.engine_lookups > 0);
        } else {
            assert!(
                pairs.filings >= 3 && pairs.filings < 30,
                "{}",
                pairs.filings
            );
        }
        // A box dropped without a word takes its pairs with it.
        let i = (0..n)
            .find(|&i| !pairs.partners[i].is_empty())
            .expect("a pair");
        let before = pairs.count();
        let had = pairs.partners[i].len();
        pairs.forget(i as u32);
        assert_eq!(pairs.count(), before - had);
        assert!(
            pairs
                .sorted()
                .iter()
                .all(|&(a, b)| a as usize != i && b as usize != i)
        );
    }
}
