//! Which live pairs to look for in avian's contact graph in a step.
//!
//! avian's own broad phase looks up every pair of a collider whose enlarged box moved in the
//! contact graph (a hash look-up a pair). Stepping on avian's enlarged boxes, the live pairs
//! are exactly those whose enlarged boxes overlap, and a pair that is in the graph stays
//! there while they overlap: avian's narrow phase drops a pair once the boxes part (the
//! live pair is then deleted in the same step) or on the changes the plugin observes
//! (layers, sensors, disabled colliders and bodies, body types, joints). So once every live
//! pair of a collider has been found in the graph, its box moving changes nothing there: only
//! its new pairs are looked at, and those left out of the graph (filtered by layers, joints
//! or the `filter_pairs` hook, or static), which avian asks again each time a box moves.

use kinetic_broad::{BroadPhaseCore, Key, PairEvent};
use std::collections::HashSet;

/// The pairs to check, and what is known of those checked.
#[derive(Default)]
pub(crate) struct Checks {
    /// Pairs the core handed over since the last check.
    fresh: Vec<(Key, Key)>,
    /// Per collider index, the last call that checked every pair of it, and the last that
    /// took its pairs (scratch).
    marks: Vec<(u32, u32)>,
    call: u32,
    /// Per collider index, the epoch in which every live pair of it was last found in the
    /// graph or held back; an epoch ends with a change that may take pairs out of the graph
    /// unseen.
    settled: Vec<u32>,
    epoch: u32,
    /// Whether the last call trusted the settled colliders.
    trusted: bool,
    /// The live pairs last left out of the graph, and per collider index how many of them
    /// it has.
    held_back: HashSet<(Key, Key)>,
    held_count: Vec<u32>,
}

/// A pair in one order.
fn ordered(a: Key, b: Key) -> (Key, Key) {
    (a.min(b), a.max(b))
}

impl Checks {
    /// Notes the pairs the core handed over (to check) and those it deleted.
    pub(crate) fn note(&mut self, events: &[PairEvent]) {
        for e in events {
            match *e {
                PairEvent::Add(a, b) => self.fresh.push((a, b)),
                PairEvent::Delete(a, b) => self.release(ordered(a, b)),
            }
        }
    }

    /// Forgets removed colliders' pairs (the core drops them without a word).
    pub(crate) fn forget(&mut self, removed: &[Key]) {
        if removed.is_empty() || self.held_back.is_empty() {
            return;
        }
        let gone: HashSet<Key> = removed.iter().copied().collect();
        let dropped: Vec<(Key, Key)> = self
            .held_back
            .iter()
            .filter(|(a, b)| gone.contains(a) || gone.contains(b))
            .copied()
            .collect();
        for p in dropped {
            self.release(p);
        }
    }

    /// Ends the epoch: every collider's pairs are checked again when it next moves.
    pub(crate) fn recheck_all(&mut self) {
        self.epoch = self.epoch.wrapping_add(1);
    }

    /// The live pairs to check this step, each once: every pair of the colliders `modified`
    /// and of those in `moved` not settled (every pair of them with `trust` false: live pairs
    /// are then not exactly those whose enlarged boxes overlap), and the new pairs. In the
    /// order of those colliders, then of the new pairs, so that the graph is built the same
    /// way every run.
    pub(crate) fn pairs(
        &mut self,
        core: &BroadPhaseCore,
        modified: &[Key],
        moved: &[Key],
        trust: bool,
    ) -> Vec<(Key, Key)> {
        if trust != std::mem::replace(&mut self.trusted, trust) {
            self.recheck_all();
        }
        self.call = self.call.wrapping_add(1).max(1);
        let (call, epoch) = (self.call, self.epoch);
        let settled = |k: &Key| {
            let i = k.index as usize;
            trust
                && self.settled.get(i) == Some(&epoch)
                && self.held_count.get(i).is_none_or(|&c| c == 0)
        };
        let mut every: Vec<Key> = modified.to_vec();
        every.extend(moved.iter().filter(|k| !settled(k)));
        if let Some(last) = every.iter().map(|k| k.index as usize).max()
            && self.marks.len() <= last
        {
            self.marks.resize(last + 1, (0, 0));
            self.settled.resize(last + 1, epoch.wrapping_sub(1));
        }
        for a in &every {
            self.marks[a.index as usize].0 = call;
        }
        let is_every =
            |marks: &[(u32, u32)], k: Key| marks.get(k.index as usize).is_some_and(|m| m.0 == call);
        let mut pairs = Vec::new();
        for &a in &every {
            let taken = &mut self.marks[a.index as usize].1;
            if std::mem::replace(taken, call) == call {
                continue;
            }
            self.settled[a.index as usize] = epoch;
            // A pair of two such colliders is taken from its lower end.
            let marks = &self.marks;
            let others = core.partners(a);
            let others = others.filter(|&b| !(b.index < a.index && is_every(marks, b)));
            pairs.extend(others.map(|b| (a, b)));
        }
        for (a, b) in std::mem::take(&mut self.fresh) {
            let covered = is_every(&self.marks, a) || is_every(&self.marks, b);
            if !covered && core.has_pair(a, b) {
                pairs.push((a, b));
            }
        }
        pairs
    }

    /// What the check found: `in_graph[k]`, whether pair `pairs[k]` is in the graph now.
    pub(crate) fn settle(&mut self, pairs: &[(Key, Key)], in_graph: &[bool]) {
        for (&(a, b), &there) in pairs.iter().zip(in_graph) {
            let p = ordered(a, b);
            if there {
                self.release(p);
            } else if self.held_back.insert(p) {
                for k in [a, b] {
                    let i = k.index as usize;
                    if self.held_count.len() <= i {
                        self.held_count.resize(i + 1, 0);
                    }
                    self.held_count[i] += 1;
                }
            }
        }
    }

    /// Pair `p` is no longer held back (in the graph, or gone).
    fn release(&mut self, p: (Key, Key)) {
        if self.held_back.remove(&p) {
            for k in [p.0, p.1] {
                self.held_count[k.index as usize] -= 1;
            }
        }
    }
}
