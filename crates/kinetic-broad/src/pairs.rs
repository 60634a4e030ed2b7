//! The pairs handed to the engine: the structure's candidate pairs, counted as the structure
//! adds and drops them, turned into add and delete events.
//!
//! A candidate is handed to the engine (added) in a call whose window (the positions' time to
//! the end of the step the structure has looked ahead over) it is a candidate in at any
//! moment, if the two proxies can meet within that window ([`crate::gate`]). It is deleted in
//! a later call whose whole window it is absent from: it stopped being a candidate before the
//! positions' time and has not come back by the window's end, or its proxies stay apart over
//! the whole window.
//!
//! A call looks only at the pairs that may have changed: new ones, dropped ones, those of
//! proxies whose plans changed, and those whose last answer from the gate runs out (kept in
//! two queues by that time). Pairs at rest, asleep or far apart cost nothing per call.

use crate::gate::Gate;
use kinetic_core::Real;
use kinetic_core::kds::{PairChange, ordered_pair};
use rustc_hash::FxHashMap;
use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;

/// One pair's state.
#[derive(Clone, Copy, Debug)]
struct PairState {
    /// How many reasons the structure has to keep the pair (0: none now).
    count: i32,
    /// Whether the engine has it (an add went out and no delete since).
    reported: bool,
    /// When its count last fell to 0.
    dropped_at: Real,
    /// When to ask the gate again while the plans are still those of versions `plans`: for
    /// a pair not reported, a time before which its proxies cannot meet (asked again once a
    /// window ends past it); for a reported one, a time before which they surely still
    /// overlap (asked again once a window starts at or past it).
    wake: Real,
    plans: (u32, u32),
}

/// What the pair book asks the engine to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum PairOut {
    Add(u32, u32),
    Delete(u32, u32),
}

/// A pair's wake time in a queue (entries go stale when the pair is asked again; a stale
/// one costs a look when it comes due).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Wake(Real, (u32, u32));

impl Eq for Wake {}

impl PartialOrd for Wake {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Wake {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0).then(self.1.cmp(&other.1))
    }
}

/// The candidate pairs by collider index `(a, b)`, `a < b`.
#[derive(Debug, Default)]
pub(crate) struct PairBook {
    pairs: FxHashMap<(u32, u32), PairState>,
    /// Pairs whose count fell to 0 and that the engine may still have.
    dropped: Vec<(u32, u32)>,
    /// Pairs new since the last call, or whose count changed.
    touched: Vec<(u32, u32)>,
    /// Proxies whose plans changed since the last call.
    replanned: Vec<u32>,
    /// Per proxy, the other ends of its pairs.
    neighbours: Vec<Vec<u32>>,
    /// Reported pairs by the time from which a window may find them apart, and the others by
    /// the time before which they cannot meet.
    wake_reported: BinaryHeap<Reverse<Wake>>,
    wake_apart: BinaryHeap<Reverse<Wake>>,
    reported: usize,
    /// Whether the structure changed a pair since [`PairBook::take_changed`].
    changed: bool,
}

impl PairBook {
    /// Counts the structure's changes, made at time `t`.
    pub(crate) fn apply(&mut self, changes: &mut Vec<PairChange>, t: Real) {
        self.changed |= !changes.is_empty();
        for c in changes.drain(..) {
            let key = (c.a.min(c.b), c.a.max(c.b));
            let e = self.pairs.entry(key).or_insert_with(|| {
                for (i, j) in [(key.0, key.1), (key.1, key.0)] {
                    let i = i as usize;
                    if self.neighbours.len() <= i {
                        self.neighbours.resize_with(i + 1, Vec::new);
                    }
                    self.neighbours[i].push(j);
                }
                PairState {
                    count: 0,
                    reported: false,
                    dropped_at: Real::NEG_INFINITY,
                    wake: Real::NEG_INFINITY,
                    plans: (u32::MAX, u32::MAX),
                }
            });
            let before = e.count;
            e.count += c.delta;
            if before > 0 && e.count <= 0 {
                e.dropped_at = t;
                self.dropped.push(key);
            }
            self.touched.push(key);
        }
    }

    /// Notes that proxy `id`'s plan changed: its pairs are asked again at the next call.
    pub(crate) fn replanned(&mut self, id: u32) {
        self.replanned.push(id);
    }

    /// Removes pair `key` from the book (its neighbours' lists too); returns its state.
    fn remove(&mut self, key: (u32, u32)) -> Option<PairState> {
        let e = self.pairs.remove(&key)?;
        for (i, j) in [(key.0, key.1), (key.1, key.0)] {
            if let Some(list) = self.neighbours.get_mut(i as usize)
                && let Some(at) = list.iter().position(|&x| x == j)
            {
                list.swap_remove(at);
            }
        }
        self.reported -= usize::from(e.reported);
        Some(e)
    }

    /// Forgets every pair of collider `id` without events (it was removed: the engine drops
    /// its pairs itself). `changes` holds the structure's drops for its removal.
    pub(crate) fn forget(&mut self, id: u32, changes: &mut Vec<PairChange>) {
        self.changed = true;
        changes.clear();
        let others = self
            .neighbours
            .get_mut(id as usize)
            .map(std::mem::take)
            .unwrap_or_default();
        for j in others {
            if let Some(e) = self.pairs.remove(&ordered_pair(id, j)) {
                self.reported -= usize::from(e.reported);
            }
            if let Some(list) = self.neighbours.get_mut(j as usize)
                && let Some(at) = list.iter().position(|&x| x == id)
            {
                list.swap_remove(at);
            }
        }
        self.dropped.retain(|&(a, b)| a != id && b != id);
    }

    /// Emits the events of one call whose window runs from the positions' time `t_pos` to
    /// `t_end`: a pair that dropped out before `t_pos` and is still out is deleted; every
    /// other pair is added or deleted as the gate (`gate(a, b)`) says. The gate is asked
    /// again only once its last answer runs out ([`Gate`]) or a proxy's plan changed
    /// ([`PairBook::replanned`]; `plan(i)` is its plan's version).
    pub(crate) fn emit(
        &mut self,
        t_pos: Real,
        t_end: Real,
        gate: impl Fn(u32, u32) -> Gate,
        plan: impl Fn(u32) -> u32,
        out: &mut Vec<PairOut>,
    ) {
        let mut look = std::mem::take(&mut self.touched);
        look.extend_from_slice(&self.dropped);
        for i in std::mem::take(&mut self.replanned) {
            if let Some(others) = self.neighbours.get(i as usize) {
                look.extend(others.iter().map(|&j| ordered_pair(i, j)));
            }
        }
        while let Some(&Reverse(Wake(t, key))) = self.wake_reported.peek()
            && t <= t_pos
        {
            self.wake_reported.pop();
            look.push(key);
        }
        while let Some(&Reverse(Wake(t, key))) = self.wake_apart.peek()
            && t < t_end
        {
            self.wake_apart.pop();
            look.push(key);
        }
        look.sort_unstable();
        look.dedup();
        for key in look {
            let Some(e) = self.pairs.get_mut(&key) else {
                continue;
            };
            let (a, b) = key;
            if e.count <= 0 && e.dropped_at < t_pos {
                if e.reported {
                    out.push(PairOut::Delete(a, b));
                }
                self.remove(key);
                continue;
            }
            let plans = (plan(a), plan(b));
            let due = if e.reported {
                e.wake <= t_pos
            } else {
                e.wake < t_end
            };
            if plans == e.plans && !due {
                continue;
            }
            let g = gate(a, b);
            e.plans = plans;
            e.wake = g.wake;
            if g.meet != e.reported {
                e.reported = g.meet;
                if g.meet {
                    self.reported += 1;
                    out.push(PairOut::Add(a, b));
                } else {
                    self.reported -= 1;
                    out.push(PairOut::Delete(a, b));
                }
            }
            if g.wake < Real::INFINITY {
                let queue = if g.meet {
                    &mut self.wake_reported
                } else {
                    &mut self.wake_apart
                };
                queue.push(Reverse(Wake(g.wake, key)));
            }
        }
        let pairs = &self.pairs;
        self.dropped
            .retain(|key| pairs.get(key).is_some_and(|e| e.count <= 0));
        // Stale queue entries pile up while pairs are asked again far ahead of their wake:
        // rebuilt from the book once they outnumber the pairs twice.
        if self.wake_reported.len() + self.wake_apart.len() > 2 * self.pairs.len() + 64 {
            self.rebuild_queues();
        }
        // Events go out sorted.
        out.sort_unstable();
    }

    /// The wake queues afresh from the pairs' own wake times.
    fn rebuild_queues(&mut self) {
        let (mut reported, mut apart) = (Vec::new(), Vec::new());
        for (&key, e) in &self.pairs {
            if e.wake < Real::INFINITY {
                let w = Reverse(Wake(e.wake, key));
                if e.reported {
                    reported.push(w);
                } else {
                    apart.push(w);
                }
            }
        }
        self.wake_reported = BinaryHeap::from(reported);
        self.wake_apart = BinaryHeap::from(apart);
    }

    /// Whether the structure changed a pair since the last call; clears the flag.
    pub(crate) fn take_changed(&mut self) -> bool {
        std::mem::take(&mut self.changed)
    }

    /// Pairs the engine has.
    pub(crate) fn reported(&self) -> usize {
        self.reported
    }

    /// Pairs the structure holds now.
    pub(crate) fn candidates(&self) -> usize {
        self.pairs.values().filter(|e| e.count > 0).count()
    }

    /// Checks the book against itself: counts are never negative, the reported count is
    /// right, every pair is in both its proxies' lists and (`settled`, between calls) every
    /// candidate whose proxies can meet in the window (`meet`) is reported.
    pub(crate) fn audit(
        &self,
        settled: bool,
        meet: impl Fn(u32, u32) -> bool,
    ) -> Result<(), String> {
        let mut reported = 0;
        for (&(a, b), e) in &self.pairs {
            if e.count < 0 {
                return Err(format!("pair ({a}, {b}): count {}", e.count));
            }
            if settled && e.count > 0 && !e.reported && meet(a, b) {
                return Err(format!(
                    "pair ({a}, {b}) is a candidate the engine does not have (asked again at \
                     {}, plans {:?})",
                    e.wake, e.plans
                ));
            }
            let listed = |i: u32, j: u32| {
                self.neighbours
                    .get(i as usize)
                    .is_some_and(|l| l.contains(&j))
            };
            if !listed(a, b) || !listed(b, a) {
                return Err(format!(
                    "pair ({a}, {b}) is missing from its proxies' lists"
                ));
            }
            reported += usize::from(e.reported);
        }
        let listed: usize = self.neighbours.iter().map(Vec::len).sum();
        if listed != 2 * self.pairs.len() {
            return Err(format!(
                "{listed} entries in the proxies' lists for {} pairs",
                self.pairs.len()
            ));
        }
        if reported != self.reported {
            return Err(format!(
                "{} pairs reported, {reported} marked so",
                self.reported
            ));
        }
        Ok(())
    }

    /// Whether the engine has pair `(a, b)` by this book.
    pub(crate) fn has(&self, a: u32, b: u32) -> bool {
        self.pairs
            .get(&ordered_pair(a, b))
            .is_some_and(|e| e.reported)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn change(a: u32, b: u32, delta: i32) -> PairChange {
        PairChange { a, b, delta }
    }

    fn always(_: u32, _: u32) -> bool {
        true
    }

    /// A gate for which every pair can meet (asked again at every call).
    fn meets(_: u32, _: u32) -> Gate {
        Gate {
            meet: true,
            wake: Real::NEG_INFINITY,
        }
    }

    /// A gate for which every pair stays apart until `t` (the window's end).
    fn apart(t: Real) -> impl Fn(u32, u32) -> Gate {
        move |_, _| Gate {
            meet: false,
            wake: t,
        }
    }

    fn same_plans(_: u32) -> u32 {
        0
    }

    #[test]
    fn a_candidate_goes_to_the_engine_only_while_its_proxies_can_meet() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 1, 1)], 0.0);
        book.emit(0.0, 1.0, apart(1.0), same_plans, &mut out);
        assert!(out.is_empty());
        assert_eq!(book.candidates(), 1);
        book.audit(true, |_, _| false).unwrap();
        assert!(
            book.audit(true, always).is_err(),
            "a meeting candidate must be reported"
        );
        book.emit(1.0, 2.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 1)]);
        // Still a candidate, but its balls stay apart over the next window: deleted.
        out.clear();
        book.emit(2.0, 3.0, apart(3.0), same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Delete(0, 1)]);
        assert_eq!(book.reported(), 0);
        assert_eq!(book.candidates(), 1);
    }

    #[test]
    fn the_gate_is_asked_again_only_once_its_answer_runs_out_or_a_plan_changes() {
        use std::cell::Cell;
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 1, 1)], 0.0);
        let asked = Cell::new(0);
        // Apart until 3.5 on plans of version 0.
        let gate = |_, _| {
            asked.set(asked.get() + 1);
            Gate {
                meet: false,
                wake: 3.5,
            }
        };
        let version = Cell::new(0);
        let plan = |_| version.get();
        for t in [0.0, 1.0, 2.0, 2.4] {
            book.emit(t, t + 1.0, gate, plan, &mut out);
        }
        assert_eq!(asked.get(), 1, "windows ending by 3.5 reuse the answer");
        version.set(1);
        book.replanned(0);
        book.emit(2.5, 3.5, gate, plan, &mut out);
        assert_eq!(asked.get(), 2, "a new plan asks again");
        assert!(out.is_empty());
        // A window past 3.5 asks again: the proxies meet now, and surely overlap until 4.2:
        // not asked again by windows starting before 4.2.
        let meet = |_, _| {
            asked.set(asked.get() + 1);
            Gate {
                meet: true,
                wake: 4.2,
            }
        };
        book.emit(3.0, 4.0, meet, plan, &mut out);
        book.emit(3.1, 4.1, meet, plan, &mut out);
        book.emit(4.1, 5.1, meet, plan, &mut out);
        assert_eq!(asked.get(), 3);
        assert_eq!(out, vec![PairOut::Add(0, 1)]);
        let never = |_, _| Gate {
            meet: false,
            wake: Real::INFINITY,
        };
        book.emit(4.2, 5.2, never, plan, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 1), PairOut::Delete(0, 1)]);
    }

    #[test]
    fn a_pair_that_comes_and_goes_within_a_window_is_added_then_deleted_later() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        // Window [0, 1]: the pair appears at 0.4 and leaves at 0.6.
        book.apply(&mut vec![change(3, 1, 1)], 0.4);
        book.apply(&mut vec![change(1, 3, -1)], 0.6);
        book.emit(0.0, 1.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Add(1, 3)]);
        assert!(book.has(1, 3));
        // Next call, positions at 0.5: it left at 0.6, within that call's window: kept.
        out.clear();
        book.emit(0.5, 1.5, meets, same_plans, &mut out);
        assert!(out.is_empty());
        // Positions at 1.0: it has been out since 0.6: deleted.
        book.emit(1.0, 2.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Delete(1, 3)]);
        assert_eq!(book.reported(), 0);
        book.audit(true, always).unwrap();
    }

    #[test]
    fn a_pair_needed_twice_stays_until_both_reasons_go() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 2, 1), change(0, 2, 1)], 0.0);
        book.emit(0.0, 1.0, meets, same_plans, &mut out);
        book.apply(&mut vec![change(0, 2, -1)], 0.5);
        book.emit(1.0, 2.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 2)]);
        book.apply(&mut vec![change(0, 2, -1)], 1.5);
        book.emit(2.0, 3.0, meets, same_plans, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 2), PairOut::Delete(0, 2)]);
    }

    #[test]
    fn a_removed_colliders_pairs_go_silently() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 1, 1), change(1, 2, 1)], 0.0);
        book.emit(0.0, 1.0, meets, same_plans, &mut out);
        book.apply(&mut vec![change(1, 2, -1)], 0.5);
        book.forget(1, &mut vec![change(0, 1, -1)]);
        out.clear();
        book.emit(2.0, 3.0, meets, same_plans, &mut out);
        assert!(out.is_empty(), "{out:?}");
        assert_eq!(book.reported(), 0);
        book.audit(true, always).unwrap();
    }
}
