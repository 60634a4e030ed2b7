//! Watches: where the ends of a box lie among the grid planes of a smaller object, the box
//! events when an end crosses a plane, and the candidate pairs they make.

use super::dominance::reschedule;
use super::{EndWatch, Guards, Watch};
use kinetic_core::Real;
use kinetic_core::kds::certificates::above_just_after;
use kinetic_core::kds::{Bodies, OrderCertificate, PairChange, ScalarKey};

impl Guards {
    /// Where end `upper` of the box of `boxer` lies among the grid planes of `guarded` on
    /// `axis`, now.
    fn end_watch(
        &self,
        bodies: &Bodies,
        guarded: u32,
        boxer: u32,
        axis: usize,
        upper: bool,
        now: Real,
    ) -> EndWatch {
        let half = self.half[boxer as usize];
        let end = ScalarKey::from_plan(
            Self::plan(bodies, boxer),
            axis,
            if upper { half } else { -half },
        )
        .local(now);
        let plane = |i| self.plane(bodies, guarded, axis, i).local(now);
        let m = self.grid.m;
        let j = (0..m)
            .take_while(|&i| above_just_after(&end, &plane(i)))
            .count() as u32;
        EndWatch {
            j,
            lo: (j > 0).then(|| OrderCertificate::new(&plane(j - 1), &end, now)),
            hi: (j < m).then(|| OrderCertificate::new(&end, &plane(j), now)),
        }
    }

    pub(super) fn plane(&self, bodies: &Bodies, guarded: u32, axis: usize, i: u32) -> ScalarKey {
        let off = self.grid.offset(self.inner[guarded as usize], i);
        ScalarKey::from_plan(Self::plan(bodies, guarded), axis, off)
    }

    pub(super) fn make_watch(&self, bodies: &Bodies, guarded: u32, boxer: u32, now: Real) -> Watch {
        Watch {
            guarded,
            boxer,
            ends: std::array::from_fn(|axis| {
                [false, true].map(|upper| self.end_watch(bodies, guarded, boxer, axis, upper, now))
            }),
            cone: None,
            cone_due: Real::INFINITY,
            dominator: None,
            dominator_due: Real::INFINITY,
        }
    }

    pub(super) fn link(&mut self, a: u32, b: u32, delta: i32, changes: &mut Vec<PairChange>) {
        if delta > 0 {
            self.links[a as usize].push(b);
            self.links[b as usize].push(a);
        } else {
            for (x, y) in [(a, b), (b, a)] {
                let list = &mut self.links[x as usize];
                let i = list.iter().position(|&p| p == y).expect("a linked pair");
                list.swap_remove(i);
            }
        }
        changes.push(PairChange { a, b, delta });
    }

    /// Sets the directed pair (guarded, boxer) to `on`.
    pub(super) fn set_pair(
        &mut self,
        guarded: u32,
        boxer: u32,
        on: bool,
        changes: &mut Vec<PairChange>,
    ) {
        let had = self.pairs.contains(&(guarded, boxer));
        if on && !had {
            self.pairs.insert((guarded, boxer));
            self.link(guarded, boxer, 1, changes);
        } else if !on && had {
            self.pairs.remove(&(guarded, boxer));
            self.link(guarded, boxer, -1, changes);
        }
    }

    /// Stores a watch (or clears its slot), keeping the count of watch certificates.
    pub(super) fn put_watch(&mut self, slot: u32, w: Option<Watch>) {
        let certs = |w: &Option<Watch>| w.as_ref().map_or(0, Watch::certificates);
        self.watch_certs -= certs(&self.watches[slot as usize]);
        self.watch_certs += certs(&w);
        self.watches[slot as usize] = w;
    }

    pub(super) fn schedule(&mut self, slot: u32) {
        let w = self.watches[slot as usize].as_ref().expect("a live watch");
        reschedule(&mut self.watch_queue, slot, w.due());
    }

    /// Starts watching (guarded, boxer) now.
    pub(super) fn open_watch(
        &mut self,
        bodies: &Bodies,
        guarded: u32,
        boxer: u32,
        changes: &mut Vec<PairChange>,
    ) {
        if self.watch_index.contains_key(&(guarded, boxer)) {
            return;
        }
        let w = self.make_watch(bodies, guarded, boxer, self.now);
        let slot = match self.free.pop() {
            Some(s) => s,
            None => {
                self.watches.push(None);
                (self.watches.len() - 1) as u32
            }
        };
        self.put_watch(slot, Some(w));
        self.watch_index.insert((guarded, boxer), slot);
        self.watches_of[guarded as usize].push(slot);
        self.watches_of[boxer as usize].push(slot);
        if self.dominatees.len() <= slot as usize {
            self.dominatees.resize(slot as usize + 1, Vec::new());
        }
        self.schedule(slot);
        self.recone(bodies, &[slot], changes);
    }

    /// Stops watching (guarded, boxer).
    pub(super) fn close_watch(
        &mut self,
        bodies: &Bodies,
        guarded: u32,
        boxer: u32,
        changes: &mut Vec<PairChange>,
    ) {
        let Some(slot) = self.watch_index.remove(&(guarded, boxer)) else {
            return;
        };
        let mut redo = Vec::new();
        self.detach(slot, &mut redo);
        self.put_watch(slot, None);
        self.watch_queue.remove(slot);
        self.cone_queue.remove(slot);
        for o in [guarded, boxer] {
            let list = &mut self.watches_of[o as usize];
            let i = list
                .iter()
                .position(|&s| s == slot)
                .expect("a listed watch");
            list.swap_remove(i);
        }
        self.free.push(slot);
        self.set_pair(guarded, boxer, false, changes);
        for d in redo {
            self.redominate(bodies, d, changes);
        }
    }

    /// A watch's certificate failed: an end of the box crossed a grid plane.
    pub(super) fn on_watch(&mut self, slot: u32, bodies: &Bodies, changes: &mut Vec<PairChange>) {
        let mut w = self.watches[slot as usize].expect("a live watch");
        let due = w.due();
        let now = self.now;
        let (axis, e) = (0..6)
            .map(|k| (k / 2, k % 2))
            .find(|&(a, e)| w.ends[a][e].due() <= due)
            .expect("the due end");
        let ew = &mut w.ends[axis][e];
        let lo_due = ew.lo.map_or(Real::INFINITY, |c| c.failure_time());
        let end = ScalarKey::from_plan(
            Self::plan(bodies, w.boxer),
            axis,
            if e == 1 {
                self.half[w.boxer as usize]
            } else {
                -self.half[w.boxer as usize]
            },
        )
        .local(now);
        let m = self.grid.m;
        if lo_due <= due {
            // The end went below plane j - 1.
            ew.hi = ew.lo.map(|c| c.swapped());
            ew.j -= 1;
            ew.lo = (ew.j > 0).then(|| {
                let p = self.plane(bodies, w.guarded, axis, ew.j - 1).local(now);
                OrderCertificate::new(&p, &end, now)
            });
        } else {
            // The end went above plane j.
            ew.lo = ew.hi.map(|c| c.swapped());
            ew.j += 1;
            ew.hi = (ew.j < m).then(|| {
                let p = self.plane(bodies, w.guarded, axis, ew.j).local(now);
                OrderCertificate::new(&end, &p, now)
            });
        }
        self.put_watch(slot, Some(w));
        self.schedule(slot);
        self.box_events += 1;
        self.set_pair(w.guarded, w.boxer, w.wanted(), changes);
    }
}
