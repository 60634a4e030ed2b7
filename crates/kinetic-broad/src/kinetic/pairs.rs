//! The pairs the broad phase holds: the structure's candidate pairs, counted as the structure
//! adds and drops them, turned into add and delete events for the engine's own pairs (see
//! `phase/handed.rs`, which hands the engine those whose boxes meet).
//!
//! A candidate is held from the call whose window (the positions' time to the end of the step
//! the structure has looked ahead over) it is a candidate in at any moment, and let go in a
//! later call whose whole window it is absent from: it stopped being a candidate before the
//! positions' time and has not come back. A call costs in proportion to the pairs the
//! structure changed since the last one: a resting world costs nothing.

use kinetic_core::Real;
use kinetic_core::kds::{PairChange, ordered_pair};
use rustc_hash::FxHashMap;

/// One pair's state.
#[derive(Clone, Copy, Debug)]
struct PairState {
    /// How many reasons the structure has to keep the pair (0: none now).
    count: i32,
    /// Whether it is held (an add went out and no delete since).
    reported: bool,
    /// When its count last fell to 0.
    dropped_at: Real,
}

/// What the pair book asks the engine to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub(crate) enum PairOut {
    Add(u32, u32),
    Delete(u32, u32),
}

/// The candidate pairs by collider index `(a, b)`, `a < b`.
#[derive(Debug, Default)]
pub(crate) struct PairBook {
    pairs: FxHashMap<(u32, u32), PairState>,
    /// Pairs whose count fell to 0 and that may still be held.
    dropped: Vec<(u32, u32)>,
    /// Pairs whose count changed since the last call.
    dirty: Vec<(u32, u32)>,
    reported: usize,
}

impl PairBook {
    /// Counts the structure's changes, made at time `t`.
    pub(crate) fn apply(&mut self, changes: &mut Vec<PairChange>, t: Real) {
        for c in changes.drain(..) {
            let key = (c.a.min(c.b), c.a.max(c.b));
            let e = self.pairs.entry(key).or_insert(PairState {
                count: 0,
                reported: false,
                dropped_at: Real::NEG_INFINITY,
            });
            let before = e.count;
            e.count += c.delta;
            if before > 0 && e.count <= 0 {
                e.dropped_at = t;
                self.dropped.push(key);
            }
            if before <= 0 && e.count > 0 {
                self.dirty.push(key);
            }
        }
    }

    /// Forgets every pair of collider `id` without events (it was removed: the engine drops its
    /// pairs itself). `changes` holds the structure's drops for its removal.
    pub(crate) fn forget(&mut self, id: u32, changes: &mut Vec<PairChange>) {
        for c in changes.drain(..) {
            let key = (c.a.min(c.b), c.a.max(c.b));
            if let Some(e) = self.pairs.remove(&key) {
                self.reported -= usize::from(e.reported);
            }
        }
        // Pairs that had already dropped out and wait for their delete.
        let mut gone = Vec::new();
        self.dropped.retain(|&(a, b)| {
            let mine = a == id || b == id;
            if mine {
                gone.push((a, b));
            }
            !mine
        });
        for key in gone {
            if let Some(e) = self.pairs.remove(&key) {
                self.reported -= usize::from(e.reported);
            }
        }
    }

    /// Emits the events of one call whose window starts at the positions' time `t_pos`: a
    /// pair that became a candidate since the last call is added, and one that dropped out
    /// before `t_pos` and is still out is deleted. Only the pairs changed since the last call
    /// are looked at.
    pub(crate) fn emit(&mut self, t_pos: Real, out: &mut Vec<PairOut>) {
        let mut dirty = std::mem::take(&mut self.dirty);
        for key in dirty.drain(..) {
            if let Some(e) = self.pairs.get_mut(&key)
                && !e.reported
                && (e.count > 0 || e.dropped_at >= t_pos)
            {
                e.reported = true;
                self.reported += 1;
                out.push(PairOut::Add(key.0, key.1));
            }
        }
        self.dirty = dirty;
        let mut dropped = std::mem::take(&mut self.dropped);
        dropped.retain(|key| {
            let Some(e) = self.pairs.get(key) else {
                return false;
            };
            if e.count > 0 {
                return false; // back in, and held
            }
            if e.dropped_at >= t_pos {
                return true; // out since a time within this window: held a call longer
            }
            if e.reported {
                self.reported -= 1;
                out.push(PairOut::Delete(key.0, key.1));
            }
            self.pairs.remove(key);
            false
        });
        dropped.sort_unstable();
        dropped.dedup();
        self.dropped = dropped;
        // The map's order is not the pairs' order: events go out sorted.
        out.sort_unstable();
        out.dedup();
    }

    /// Pairs the structure holds now.
    pub(crate) fn candidates(&self) -> usize {
        self.pairs.values().filter(|e| e.count > 0).count()
    }

    /// Checks the book against itself: counts are never negative, the reported count is
    /// right and (`settled`, between calls) every candidate is held.
    pub(crate) fn audit(&self, settled: bool) -> Result<(), String> {
        let mut reported = 0;
        for (&(a, b), e) in &self.pairs {
            if e.count < 0 {
                return Err(format!("pair ({a}, {b}): count {}", e.count));
            }
            if settled && e.count > 0 && !e.reported {
                return Err(format!(
                    "pair ({a}, {b}) is a candidate the book does not hold"
                ));
            }
            reported += usize::from(e.reported);
        }
        if reported != self.reported {
            return Err(format!(
                "{} pairs reported, {reported} marked so",
                self.reported
            ));
        }
        Ok(())
    }

    /// The pairs held by this book, in no order.
    pub(crate) fn reported_pairs(&self) -> Vec<(u32, u32)> {
        self.pairs
            .iter()
            .filter(|(_, e)| e.reported)
            .map(|(k, _)| *k)
            .collect()
    }

    /// Takes the engine's pairs `had` (each `(a, b)` with `a < b`) as held: those the book
    /// holds are marked so; the others go to `gone`, to be deleted. The book's candidates not
    /// among them are added at the next call.
    pub(crate) fn adopt(&mut self, had: &[(u32, u32)], gone: &mut Vec<(u32, u32)>) {
        for key in had {
            match self.pairs.get_mut(key) {
                Some(e) if !e.reported => {
                    e.reported = true;
                    self.reported += 1;
                }
                Some(_) => {}
                None => gone.push(*key),
            }
        }
        for (key, e) in &self.pairs {
            if !e.reported {
                self.dirty.push(*key);
            }
            if e.count <= 0 {
                self.dropped.push(*key);
            }
        }
    }

    /// Whether pair `(a, b)` is held by this book.
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

    #[test]
    fn a_pair_that_comes_and_goes_within_a_window_is_added_then_deleted_later() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        // Window [0, 1]: the pair appears at 0.4 and leaves at 0.6.
        book.apply(&mut vec![change(3, 1, 1)], 0.4);
        book.apply(&mut vec![change(1, 3, -1)], 0.6);
        book.emit(0.0, &mut out);
        assert_eq!(out, vec![PairOut::Add(1, 3)]);
        assert!(book.has(1, 3));
        // Next call, positions at 0.5: it left at 0.6, within that call's window: kept.
        out.clear();
        book.emit(0.5, &mut out);
        assert!(out.is_empty());
        // Positions at 1.0: it has been out since 0.6: deleted.
        book.emit(1.0, &mut out);
        assert_eq!(out, vec![PairOut::Delete(1, 3)]);
        assert!(!book.has(1, 3));
        book.audit(true).unwrap();
        // Nothing changed since: a call looks at nothing and says nothing.
        out.clear();
        book.emit(2.0, &mut out);
        assert!(out.is_empty());
    }

    #[test]
    fn a_pair_needed_twice_stays_until_both_reasons_go() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 2, 1), change(0, 2, 1)], 0.0);
        book.emit(0.0, &mut out);
        book.apply(&mut vec![change(0, 2, -1)], 0.5);
        book.emit(1.0, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 2)]);
        book.audit(true).unwrap();
        book.apply(&mut vec![change(0, 2, -1)], 1.5);
        book.emit(2.0, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 2), PairOut::Delete(0, 2)]);
        assert_eq!(book.candidates(), 0);
    }

    #[test]
    fn a_removed_colliders_pairs_go_silently() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 1, 1), change(1, 2, 1)], 0.0);
        book.emit(0.0, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 1), PairOut::Add(1, 2)]);
        book.apply(&mut vec![change(1, 2, -1)], 0.5);
        book.forget(1, &mut vec![change(0, 1, -1)]);
        out.clear();
        book.emit(2.0, &mut out);
        assert!(out.is_empty(), "{out:?}");
        assert!(book.reported_pairs().is_empty());
        book.audit(true).unwrap();
    }
}
