//! Anchors: an object given a fresh region, and its pairs found again.

use super::{BIG_SHARE, LooseGrid, MANY_BIG, Member};
use kinetic_core::Real;
use kinetic_core::kds::{Bodies, PairChange, ordered_pair};

fn pair_change(x: u32, y: u32, delta: i32) -> PairChange {
    let (a, b) = ordered_pair(x, y);
    PairChange { a, b, delta }
}

impl LooseGrid {
    /// Gives member `id` a fresh region from its plan at `now`, as if anchored `age` of its
    /// flight ago (see [`LooseGrid::region`]), finds its partners again and reports the pairs
    /// that change.
    pub(super) fn anchor(
        &mut self,
        id: u32,
        bodies: &Bodies,
        now: Real,
        age: Real,
        changes: &mut Vec<PairChange>,
    ) {
        self.anchors += 1;
        let (lo, hi) = self.region(bodies, id, now, age);
        // A region that still covers some of the same cells stays filed there: it leaves
        // only the cells it no longer covers and enters only the new ones.
        let mut kept_slots = None;
        let mut old = if self.present(id) {
            let m = self.member(id);
            let moved = match (m.big, self.footprint(m.lo, m.hi), self.footprint(lo, hi)) {
                (false, Some(from), Some(to)) => Some((from, to)),
                _ => None,
            };
            if moved.is_none() {
                self.unfile(id);
            }
            let m = self.members[id as usize].take().expect("a member");
            if let Some((from, to)) = moved {
                kept_slots = Some(self.shift_filing(id, m.slots, from, to));
            }
            m.partners
        } else {
            self.live += 1;
            Vec::new()
        };
        self.epoch += 1;
        let epoch = self.epoch;
        if self.mark.len() < self.members.len() {
            self.mark.resize(self.members.len(), 0);
        }
        self.mark[id as usize] = epoch;
        let mut found = std::mem::take(&mut self.scratch);
        found.clear();
        let (slots, big) = match kept_slots {
            Some(slots) => (slots, false),
            None => self.file(id, lo, hi),
        };
        let (members, mark) = (&self.members, &mut self.mark);
        let mut meet = |p: u32, found: &mut Vec<u32>| {
            if mark[p as usize] != epoch {
                mark[p as usize] = epoch;
                let q = members[p as usize].as_ref().expect("a member");
                if q.lo.cmple(hi).all() && lo.cmple(q.hi).all() {
                    found.push(p);
                }
            }
        };
        if big {
            // A big region meets any other: it looks at them all.
            for (p, q) in self.members.iter().enumerate() {
                if q.is_some() {
                    meet(p as u32, &mut found);
                }
            }
        } else {
            for &slot in &slots {
                for &p in &self.occupants[slot as usize] {
                    meet(p, &mut found);
                }
            }
            for &p in &self.big {
                meet(p, &mut found);
            }
        }
        found.sort_unstable();
        old.sort_unstable();
        // Pairs that end, then pairs that begin.
        for &p in &old {
            if found.binary_search(&p).is_err() {
                self.part(id, p, changes);
            }
        }
        for &p in &found {
            if old.binary_search(&p).is_err() {
                let q = self.members[p as usize].as_mut().expect("a member");
                q.partners.push(id);
                self.pairs += 1;
                changes.push(pair_change(id, p, 1));
            }
        }
        let exit = Self::exit_time(bodies, id, lo, hi, now);
        self.members[id as usize] = Some(Member {
            lo,
            hi,
            slots,
            big,
            partners: found,
            exit,
        });
        self.scratch = old;
        self.schedule(id, exit);
        if self.big.len() > self.refile_above && self.big.len() * BIG_SHARE > self.live {
            self.refile();
            self.refile_above = MANY_BIG.max(2 * self.big.len());
        }
    }

    /// Ends the pair of `id` and its partner `p`: off `p`'s partners, and reported.
    pub(super) fn part(&mut self, id: u32, p: u32, changes: &mut Vec<PairChange>) {
        let q = self.members[p as usize].as_mut().expect("a member");
        if let Some(i) = q.partners.iter().position(|&x| x == id) {
            q.partners.swap_remove(i);
        }
        self.pairs -= 1;
        changes.push(pair_change(id, p, -1));
    }

    pub(super) fn schedule(&mut self, id: u32, exit: Real) {
        if exit.is_finite() {
            self.exits.schedule(id, exit, 0);
        } else {
            self.exits.remove(id);
        }
    }
}
