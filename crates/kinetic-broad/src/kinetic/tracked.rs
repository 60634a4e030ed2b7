//! A stepped world's reads of the boxes that moved: each position update marks the
//! colliders the engine moved and reads their boxes once, in index order, reading ahead
//! on large worlds.

use super::Stepped;
use crate::{Aabb, Engine, Key};
use kinetic_core::Vec3;

/// A position update that moved at least this many colliders asks the engine for the
/// collider [`PREFETCH_AHEAD`] on while it reads a box ([`Engine::prefetch_collider`]):
/// rapier's colliders and their shapes then pass a core's second-level cache (1 MB here, a
/// few hundred bytes a collider), and their reads wait on memory; below, asking costs more
/// than it saves (chosen from the cache size, not fitted: debris of 1e3 bodies in rapier
/// spent 40% more in the broad phase asking, a rain of 19,743 28% less).
const PREFETCH_FROM: usize = 2048;
/// The collider a position update asks for is this many ahead of the one whose box it
/// reads: about the loads a core keeps in flight while it works out a box (chosen, not
/// fitted).
const PREFETCH_AHEAD: usize = 4;
/// Takes the marks off `marked` and calls `each` with the key of each marked collider that
/// moves with a body (`movers`), in index order.
#[inline(always)]
fn take_marked(marked: &mut [u64], movers: &[Option<(u32, u32)>], mut each: impl FnMut(Key)) {
    for (word, bits) in marked.iter_mut().enumerate() {
        let mut bits = std::mem::take(bits);
        while bits != 0 {
            let i = (word * 64) as u32 + bits.trailing_zeros();
            bits &= bits - 1;
            if let Some(&Some((generation, _))) = movers.get(i as usize) {
                each(Key {
                    index: i,
                    generation,
                });
            }
        }
    }
}

impl Stepped {
    /// Marks collider `i` as moved in this position update: its box is read in
    /// [`Stepped::track_marked`].
    pub(in crate::kinetic) fn mark(&mut self, i: u32) {
        let word = i as usize / 64;
        if self.marked.len() <= word {
            self.marked.resize(word + 1, 0);
        }
        self.marked[word] |= 1 << (i % 64);
    }

    /// Reads the boxes of the colliders marked as moved, in index order: an engine lists
    /// them in its own (rapier: its islands'), and read in order both its colliders and
    /// these tables are walked front to back.
    pub(in crate::kinetic) fn track_marked(
        &mut self,
        engine: &impl Engine,
        movers: &[Option<(u32, u32)>],
    ) {
        let mut marked = std::mem::take(&mut self.marked);
        if self.enlarged.is_none() {
            let count: u32 = marked.iter().map(|w| w.count_ones()).sum();
            if count as usize >= PREFETCH_FROM {
                self.track_marked_ahead(engine, movers, &mut marked);
                self.marked = marked;
                return;
            }
        }
        take_marked(&mut marked, movers, |k| match engine.enlarged(k) {
            Some(b) => self.keep_enlarged(k.index, b),
            None => self.track(k.index, engine.bounds(k)),
        });
        self.marked = marked;
    }

    /// [`Stepped::track_marked`] for many colliders: their keys first, then their boxes,
    /// each read while the engine is asked for the collider [`PREFETCH_AHEAD`] on
    /// ([`Engine::prefetch_collider`]). Apart, so that the plain loop stays as it compiles
    /// alone (its box read inline).
    #[inline(never)]
    fn track_marked_ahead(
        &mut self,
        engine: &impl Engine,
        movers: &[Option<(u32, u32)>],
        marked: &mut [u64],
    ) {
        let mut keys = std::mem::take(&mut self.marked_keys);
        keys.clear();
        take_marked(marked, movers, |k| keys.push(k));
        for (n, &k) in keys.iter().enumerate() {
            if let Some(&next) = keys.get(n + PREFETCH_AHEAD) {
                engine.prefetch_collider(next);
            }
            self.track(k.index, engine.bounds(k));
        }
        self.marked_keys = keys;
    }

    /// Collider `i` moved to box `b` (`None`: the engine gives none): how far it moves over
    /// the coming step is taken from how far it moved over the last two, as a semi-implicit
    /// Euler step under a steady acceleration does (`2 d1 - d0`).
    #[inline(always)]
    pub(in crate::kinetic) fn track(&mut self, i: u32, b: Option<Aabb>) {
        let i = i as usize;
        if self.boxes.len() <= i {
            self.boxes.resize(i + 1, None);
            self.history.resize(i + 1, None);
        }
        self.changed_now(i);
        let Some(b) = b else {
            self.boxes[i] = None;
            self.history[i] = None;
            self.pending.push(i as u32);
            return;
        };
        let c = b.centre();
        match self.history[i] {
            Some((last, d0)) => {
                let d1 = c - last;
                let ahead = d0.map_or(d1, |d0| 2.0 * d1 - d0);
                self.boxes[i] = Some((b, ahead));
                self.history[i] = Some((c, Some(d1)));
            }
            // ColliderStatus for the first time: worked out from its body's velocity.
            None => {
                self.boxes[i] = None;
                self.pending.push(i as u32);
            }
        }
    }

    /// Collider `i`'s enlarged box is `b` ([`Engine::enlarged`]): filed as it is, and
    /// changed only if the engine moved it.
    #[inline(always)]
    fn keep_enlarged(&mut self, i: u32, b: Aabb) {
        let i = i as usize;
        if self.boxes.len() <= i {
            self.boxes.resize(i + 1, None);
            self.history.resize(i + 1, None);
        }
        if self.boxes[i] == Some((b, Vec3::ZERO)) {
            return;
        }
        self.changed_now(i);
        self.boxes[i] = Some((b, Vec3::ZERO));
        self.history[i] = Some((b.centre(), None));
    }

    /// Notes that collider `i`'s box changes in this call.
    #[inline(always)]
    pub(super) fn changed_now(&mut self, i: usize) {
        if self.changed.len() <= i {
            self.changed.resize(i + 1, 0);
        }
        self.last_change = self.calls + 1;
        if self.changed[i] != self.calls + 1 {
            self.changed[i] = self.calls + 1;
            if self.enlarged.is_some() {
                self.touched.push(i as u32);
            }
        }
    }
}
