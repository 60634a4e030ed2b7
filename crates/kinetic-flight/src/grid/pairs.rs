//! Grid pairs and their box certificates: a candidate watches its three axes, a pair apart
//! its witness axis alone.

use super::{Grid, HYSTERESIS, HYSTERESIS_ABS, NO_WITNESS, Slot};
use crate::cell_math::{Local, crossing, sign_after};
use kinetic_core::Real;
use kinetic_core::kds::{PairChange, ordered_pair};

fn minus(a: Local, b: Local) -> Local {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

impl Grid {
    /// The per-axis states of the boxes of `a` and `b` just after `now` (looked at afresh on
    /// the axes `fresh`, kept on the others), and their certificates: for a candidate, when
    /// each axis parts; for a pair that is not, when its witness closes (the apart axis that
    /// closes last), with no certificate on the other two, since the boxes cannot overlap
    /// before then whatever those do.
    pub(super) fn certify_pair(&self, slot: &mut Slot, now: Real, fresh: [bool; 3]) {
        let (ma, mb) = (self.member(slot.a), self.member(slot.b));
        let slack_rel = HYSTERESIS * ma.width.min(mb.width);
        let mut ends = [[[0.0; 3]; 2]; 3];
        for k in 0..3 {
            // p1: b's upper end above a's lower end; p2: a's upper end above b's lower end.
            let p1 = minus(mb.hi[k].local(now), ma.lo[k].local(now));
            let p2 = minus(ma.hi[k].local(now), mb.lo[k].local(now));
            if fresh[k] {
                slot.inside[k] = sign_after(p1) >= 0 && sign_after(p2) >= 0;
            }
            ends[k] = [p1, p2];
        }
        slot.due = [Real::INFINITY; 3];
        if slot.inside.iter().all(|&x| x) {
            slot.witness = NO_WITNESS;
            for (k, [p1, p2]) in ends.into_iter().enumerate() {
                let e = slack_rel + HYSTERESIS_ABS * (ma.lo[k].k0.abs() + mb.lo[k].k0.abs());
                slot.due[k] = crossing(p1, -e, -1, now).min(crossing(p2, -e, -1, now));
            }
            return;
        }
        let mut witness: Option<(usize, Real)> = None;
        for (k, [p1, p2]) in ends.into_iter().enumerate() {
            if slot.inside[k] {
                continue;
            }
            // Apart on this axis: the one of p1, p2 that is below zero (their sum, the two
            // widths, is positive) comes back up.
            let low = if p1[0] <= p2[0] { p1 } else { p2 };
            let close = crossing(low, 0.0, 1, now);
            if witness.is_none_or(|(_, t)| close > t) {
                witness = Some((k, close));
            }
        }
        let (k, close) = witness.expect("an axis apart");
        slot.witness = k as u8;
        slot.due[k] = close;
    }

    pub(super) fn schedule_slot(&mut self, i: u32) {
        let slot = self.slots[i as usize].as_ref().expect("a slot");
        let t = slot.due.iter().fold(Real::INFINITY, |x, &y| x.min(y));
        if t.is_finite() {
            self.pairs_queue.schedule(i, t, 0);
        } else {
            self.pairs_queue.remove(i);
        }
    }

    /// Reports a change of slot `i`'s candidacy.
    pub(super) fn report(&mut self, i: u32, changes: &mut Vec<PairChange>) {
        let slot = self.slots[i as usize].as_mut().expect("a slot");
        let now_in = slot.inside.iter().all(|&x| x);
        if now_in != slot.reported {
            slot.reported = now_in;
            let delta = if now_in { 1 } else { -1 };
            changes.push(PairChange {
                a: slot.a,
                b: slot.b,
                delta,
            });
            if now_in {
                self.box_pairs += 1;
            } else {
                self.box_pairs -= 1;
            }
        }
    }

    pub(super) fn pair_up(&mut self, x: u32, y: u32, now: Real, changes: &mut Vec<PairChange>) {
        let key = ordered_pair(x, y);
        if let Some(&i) = self.pair_of.get(&key) {
            self.slots[i as usize].as_mut().expect("a slot").count += 1;
            return;
        }
        let mut slot = Slot {
            a: key.0,
            b: key.1,
            count: 1,
            inside: [false; 3],
            due: [Real::INFINITY; 3],
            witness: NO_WITNESS,
            reported: false,
        };
        self.certify_pair(&mut slot, now, [true; 3]);
        let i = match self.free.pop() {
            Some(i) => {
                self.slots[i as usize] = Some(slot);
                i
            }
            None => {
                self.slots.push(Some(slot));
                (self.slots.len() - 1) as u32
            }
        };
        self.pair_of.insert(key, i);
        for m in [key.0, key.1] {
            self.members[m as usize]
                .as_mut()
                .expect("a member")
                .pairs
                .push(i);
        }
        self.schedule_slot(i);
        self.report(i, changes);
    }

    pub(super) fn pair_down(&mut self, x: u32, y: u32, changes: &mut Vec<PairChange>) {
        let key = ordered_pair(x, y);
        let Some(&i) = self.pair_of.get(&key) else {
            return;
        };
        let slot = self.slots[i as usize].as_mut().expect("a slot");
        slot.count -= 1;
        if slot.count > 0 {
            return;
        }
        if slot.reported {
            slot.inside = [false; 3];
            self.report(i, changes);
        }
        self.slots[i as usize] = None;
        self.free.push(i);
        self.pair_of.remove(&key);
        self.pairs_queue.remove(i);
        for m in [key.0, key.1] {
            let pairs = &mut self.members[m as usize].as_mut().expect("a member").pairs;
            if let Some(j) = pairs.iter().position(|&p| p == i) {
                pairs.swap_remove(j);
            }
        }
    }

    /// Certifies every grid pair of member `id` afresh (after its plan changed).
    pub(super) fn recertify_pairs(&mut self, id: u32, now: Real, changes: &mut Vec<PairChange>) {
        for i in self.member(id).pairs.clone() {
            let mut slot = self.slots[i as usize].take().expect("a slot");
            self.certify_pair(&mut slot, now, [true; 3]);
            self.slots[i as usize] = Some(slot);
            self.schedule_slot(i);
            self.report(i, changes);
        }
    }
}
