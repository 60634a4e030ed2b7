//! The pairs handed to rapier: the structure's candidate pairs, counted as the structure adds
//! and drops them, turned into `AddPair` and `DeletePair` events by rapier's rules.
//!
//! A pair is reported (`AddPair`) in the call during which it becomes a candidate at any
//! moment of the window the call looks ahead over, and deleted (`DeletePair`) only in a
//! later call whose whole window it is absent from: it stopped being a candidate before the
//! positions' time and has not come back by the window's end.

use kinetic_core::{PairChange, Real};
use rustc_hash::FxHashMap;

/// One pair's state.
#[derive(Clone, Copy, Debug)]
struct PairState {
    /// How many reasons the structure has to keep the pair (0: none now).
    count: i32,
    /// Whether rapier has it (an `AddPair` went out and no `DeletePair` since).
    reported: bool,
    /// When its count last fell to 0.
    dropped_at: Real,
}

/// What the pair book asks rapier to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PairOut {
    Add(u32, u32),
    Delete(u32, u32),
}

/// The candidate pairs by collider index `(a, b)`, `a < b`.
#[derive(Debug, Default)]
pub(crate) struct PairBook {
    pairs: FxHashMap<(u32, u32), PairState>,
    /// Pairs whose count rose from 0 since the last emit.
    added: Vec<(u32, u32)>,
    /// Pairs whose count fell to 0 and that rapier may still have.
    dropped: Vec<(u32, u32)>,
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
            if before <= 0 && e.count > 0 {
                self.added.push(key);
            } else if before > 0 && e.count <= 0 {
                e.dropped_at = t;
                self.dropped.push(key);
            }
        }
    }

    /// Forgets every pair of collider `id` without events (it was removed: rapier drops its
    /// pairs itself). `changes` holds the structure's drops for its removal.
    pub(crate) fn forget(&mut self, id: u32, changes: &mut Vec<PairChange>) {
        for c in changes.drain(..) {
            let key = (c.a.min(c.b), c.a.max(c.b));
            if let Some(e) = self.pairs.remove(&key) {
                self.reported -= usize::from(e.reported);
            }
        }
        // Pairs that had already dropped out and wait for their `DeletePair`.
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

    /// Emits the events of one call whose positions are at time `t_pos`: every pair that
    /// became a candidate is added; a pair that dropped out before `t_pos` and is still out
    /// is deleted.
    pub(crate) fn emit(&mut self, t_pos: Real, out: &mut Vec<PairOut>) {
        let mut keep = Vec::new();
        for key in std::mem::take(&mut self.dropped) {
            let Some(e) = self.pairs.get(&key).copied() else {
                continue;
            };
            if e.count > 0 {
                continue; // back in: it is dropped again when it next falls out
            }
            if e.dropped_at < t_pos {
                if e.reported {
                    out.push(PairOut::Delete(key.0, key.1));
                    self.reported -= 1;
                }
                self.pairs.remove(&key);
            } else {
                keep.push(key);
            }
        }
        self.dropped = keep;
        for key in std::mem::take(&mut self.added) {
            if let Some(e) = self.pairs.get_mut(&key)
                && !e.reported
            {
                e.reported = true;
                self.reported += 1;
                out.push(PairOut::Add(key.0, key.1));
            }
        }
    }

    /// Pairs rapier has.
    pub(crate) fn reported(&self) -> usize {
        self.reported
    }

    /// Pairs the structure holds now.
    pub(crate) fn candidates(&self) -> usize {
        self.pairs.values().filter(|e| e.count > 0).count()
    }

    /// Checks the book against itself: counts are never negative, the reported count is
    /// right and (`settled`, between calls) every candidate is reported.
    pub(crate) fn audit(&self, settled: bool) -> Result<(), String> {
        let mut reported = 0;
        for (&(a, b), e) in &self.pairs {
            if e.count < 0 {
                return Err(format!("pair ({a}, {b}): count {}", e.count));
            }
            if settled && e.count > 0 && !e.reported {
                return Err(format!(
                    "pair ({a}, {b}) is a candidate rapier does not have"
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

    /// Whether rapier has pair `(a, b)` by this book.
    pub(crate) fn has(&self, a: u32, b: u32) -> bool {
        self.pairs
            .get(&(a.min(b), a.max(b)))
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
        assert_eq!(book.reported(), 0);
        book.audit(true).unwrap();
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
        book.apply(&mut vec![change(0, 2, -1)], 1.5);
        book.emit(2.0, &mut out);
        assert_eq!(out, vec![PairOut::Add(0, 2), PairOut::Delete(0, 2)]);
    }

    #[test]
    fn a_removed_colliders_pairs_go_silently() {
        let mut book = PairBook::default();
        let mut out = Vec::new();
        book.apply(&mut vec![change(0, 1, 1), change(1, 2, 1)], 0.0);
        book.emit(0.0, &mut out);
        book.apply(&mut vec![change(1, 2, -1)], 0.5);
        book.forget(1, &mut vec![change(0, 1, -1)]);
        out.clear();
        book.emit(2.0, &mut out);
        assert!(out.is_empty(), "{out:?}");
        assert_eq!(book.reported(), 0);
        book.audit(true).unwrap();
    }
}
