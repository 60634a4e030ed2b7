//! The engine's own pairs: of the pairs the broad phase holds (its proxies can meet within the
//! step), the engine gets those whose boxes, as the engine grows them ([`Engine::bounds`]),
//! meet within the step, each swept along its body's velocity over the step as far as the
//! engine looks ahead ([`Engine::ahead`]: rapier, at its poses now). A proxy is a
//! ball about a body that holds its collider at every orientation, a fat box, or a region of
//! a grid: filters inside the broad phase, never pairs of the engine. A pair held but not
//! handed is looked at again when one of its colliders moves; a resting world costs nothing.
//!
//! Every contact the engine can make is between colliders whose boxes, grown by its margins,
//! overlap: so the engine keeps every contact its own broad phase would give it. A stepped
//! world's pairs are already the engine's: they pass as they are.

use super::BroadPhaseCore;
use crate::Aabb;
use crate::{Bound, Engine, Key, PairEvent};
use kinetic_core::{Real, Vec3};
use rustc_hash::FxHashMap;
use smallvec::SmallVec;

/// A collider with more links than this (a ground under thousands of bodies) has them
/// indexed by the other end, so that finding one does not pass over them all.
const LONG: usize = 32;

/// One end of a held pair, kept by the other collider: this collider's index and key, and
/// whether the engine has the pair.
#[derive(Clone, Copy, Debug)]
struct Link {
    other: u32,
    key: Key,
    handed: bool,
}

/// The pairs the broad phase holds, as links per collider (both ends), and which of them the
/// engine has.
#[derive(Debug, Default)]
pub(super) struct Handed {
    links: Vec<SmallVec<[Link; 6]>>,
    /// Per collider with more than [`LONG`] links, each link's place by its other end.
    places: Vec<Option<Box<FxHashMap<u32, u32>>>>,
    /// Pairs held, and those of them the engine has.
    held: usize,
    handed: usize,
    /// The call's number, and per collider the call whose swept box `boxes` holds and the
    /// call that looked at its pairs.
    call: u32,
    boxes: Vec<(u32, Aabb)>,
    looked: Vec<u32>,
}

impl Handed {
    /// The pairs the engine has.
    pub(super) fn handed(&self) -> usize {
        self.handed
    }

    /// The engine's pairs as links, handed, where a stepped world that kept them sorted
    /// (`pairs`) goes kinetic; `key` gives each collider's key.
    pub(super) fn linked(pairs: &[(u32, u32)], key: impl Fn(u32) -> Option<Key>) -> Handed {
        let mut h = Handed::default();
        for &(a, b) in pairs {
            if let (Some(ka), Some(kb)) = (key(a), key(b)) {
                h.hold(ka, kb, true);
            }
        }
        h
    }

    /// The engine's pairs (each `(a, b)` with `a < b`, sorted), where a kinetic world goes
    /// stepped: from there the stepped world keeps them, and the links go.
    pub(super) fn into_pairs(self) -> Vec<(u32, u32)> {
        let mut pairs: Vec<(u32, u32)> = self
            .links
            .iter()
            .enumerate()
            .flat_map(|(a, list)| {
                let a = a as u32;
                list.iter()
                    .filter(move |l| l.handed && a < l.other)
                    .map(move |l| (a, l.other))
            })
            .collect();
        pairs.sort_unstable();
        pairs
    }

    /// Where collider `b` is among `a`'s links.
    fn find(&self, a: u32, b: u32) -> Option<usize> {
        if let Some(Some(places)) = self.places.get(a as usize) {
            return places.get(&b).map(|&at| at as usize);
        }
        self.links
            .get(a as usize)?
            .iter()
            .position(|l| l.other == b)
    }

    /// Adds `link` to collider `x`'s links.
    fn push_link(&mut self, x: u32, link: Link) {
        let (list, places) = (&mut self.links[x as usize], &mut self.places[x as usize]);
        list.push(link);
        match places {
            Some(places) => {
                places.insert(link.other, list.len() as u32 - 1);
            }
            None if list.len() > LONG => {
                let at = list.iter().enumerate().map(|(k, l)| (l.other, k as u32));
                *places = Some(Box::new(at.collect()));
            }
            None => {}
        }
    }

    /// Takes the link at place `at` out of collider `x`'s links.
    fn remove_link(&mut self, x: u32, at: usize) -> Link {
        let (list, places) = (&mut self.links[x as usize], &mut self.places[x as usize]);
        let gone = list.swap_remove(at);
        if let Some(places) = places {
            places.remove(&gone.other);
            if let Some(moved) = list.get(at) {
                places.insert(moved.other, at as u32);
            }
        }
        gone
    }

    /// The other ends of the pairs of collider `i` that the engine has, as held.
    pub(super) fn partners(&self, i: u32) -> impl Iterator<Item = Key> + '_ {
        let links = self.links.get(i as usize).map_or(&[][..], |l| &l[..]);
        links.iter().filter(|l| l.handed).map(|l| l.key)
    }

    /// Whether the engine has the pair of colliders `a` and `b`.
    pub(super) fn has(&self, a: u32, b: u32) -> bool {
        self.find(a, b)
            .is_some_and(|at| self.links[a as usize][at].handed)
    }

    /// Makes room for collider index `i`.
    fn reach(&mut self, i: u32) {
        let need = i as usize + 1;
        if self.links.len() < need {
            self.links.resize(need, SmallVec::new());
            self.places.resize(need, None);
            self.boxes
                .resize(need, (0, Aabb::new(Vec3::ZERO, Vec3::ZERO)));
            self.looked.resize(need, 0);
        }
    }

    /// Holds the pair `a`, `b` (not handed, or handed with `hand`); a pair already held
    /// takes the new keys (and is handed with `hand`). Returns whether the engine had it.
    fn hold(&mut self, a: Key, b: Key, hand: bool) -> bool {
        self.reach(a.index.max(b.index));
        let mut had = false;
        for (x, y) in [(a, b), (b, a)] {
            match self.find(x.index, y.index) {
                Some(at) => {
                    let l = &mut self.links[x.index as usize][at];
                    l.key = y;
                    had = l.handed;
                    l.handed |= hand;
                }
                None => {
                    let link = Link {
                        other: y.index,
                        key: y,
                        handed: hand,
                    };
                    self.push_link(x.index, link);
                    self.held += usize::from(x.index < y.index);
                }
            }
        }
        if hand && !had {
            self.handed += 1;
        }
        had
    }

    /// Lets the pair `a`, `b` go; returns whether the engine had it.
    fn let_go(&mut self, a: u32, b: u32) -> bool {
        let mut had = false;
        for (x, y) in [(a, b), (b, a)] {
            if let Some(at) = self.find(x, y) {
                had = self.remove_link(x, at).handed;
                self.held -= usize::from(x < y);
            }
        }
        self.handed -= usize::from(had);
        had
    }

    /// Marks whether the engine has the pair `a`, `b`, at both ends.
    fn set(&mut self, a: u32, b: u32, handed: bool) {
        for (x, y) in [(a, b), (b, a)] {
            if let Some(at) = self.find(x, y) {
                self.links[x as usize][at].handed = handed;
            }
        }
        if handed {
            self.handed += 1;
        } else {
            self.handed -= 1;
        }
    }

    /// Forgets every pair of collider `i` without events (it was removed: the engine drops
    /// its pairs itself).
    fn forget(&mut self, i: u32) {
        let Some(list) = self.links.get_mut(i as usize) else {
            return;
        };
        let list = std::mem::take(list);
        self.places[i as usize] = None;
        for l in list {
            self.handed -= usize::from(l.handed);
            self.held -= 1;
            if let Some(at) = self.find(l.other, i) {
                self.remove_link(l.other, at);
            }
        }
    }
}

impl BroadPhaseCore {
    /// Turns the structure's pair events of this call (`held`: the pairs its proxies can
    /// meet within the step) into the engine's: the pairs whose engine boxes meet within the
    /// step. `moved`: the colliders added, changed or moved (at the start of a step,
    /// `starts`, those the update dropped, being disabled, lose their pairs without events);
    /// `removed`: those removed.
    pub(super) fn hand_over(
        &mut self,
        engine: &impl Engine,
        held: &[PairEvent],
        (moved, removed): (&[Key], &[Key]),
        starts: bool,
        events: &mut Vec<PairEvent>,
    ) {
        if self.is_stepped() {
            // A stepped world's pairs are the engine's (those of the swept boxes, or of the
            // engine's enlarged ones), kept sorted there: each passes as it is, and the
            // links below stay empty until the world goes kinetic again.
            for &e in held {
                self.count_event(matches!(e, PairEvent::Add(..)));
            }
            events.extend_from_slice(held);
            events.sort_unstable();
            return;
        }
        let mut h = std::mem::take(&mut self.handed);
        h.call = h.call.wrapping_add(1).max(1);
        // Removed colliders, and those the update dropped (disabled): their pairs go as
        // the structure's went, without events.
        let dropped = moved.iter().filter(|&&c| starts && !self.knows(c));
        for &c in removed.iter().chain(dropped) {
            h.forget(c.index);
        }
        for &e in held {
            match e {
                PairEvent::Add(a, b) => {
                    let had = h.hold(a, b, false);
                    self.look_at(&mut h, engine, a, b, had, events);
                }
                PairEvent::Delete(a, b) => {
                    if h.let_go(a.index, b.index) {
                        self.count_event(false);
                        events.push(PairEvent::Delete(a, b));
                    }
                }
            }
        }
        // The held pairs of each moved collider, each pair once.
        let call = h.call;
        for &c in moved {
            if (c.index as usize) < h.looked.len() {
                h.looked[c.index as usize] = call;
            }
        }
        for &c in moved {
            let i = c.index as usize;
            if i >= h.links.len() || !self.knows(c) {
                continue;
            }
            let mut k = 0;
            while k < h.links[i].len() {
                let l = h.links[i][k];
                k += 1;
                // A pair of two moved colliders is looked at from its lower end.
                if h.looked[l.other as usize] == call && l.other < c.index {
                    continue;
                }
                self.look_at(&mut h, engine, c, l.key, l.handed, events);
            }
        }
        events.sort_unstable();
        self.handed = h;
    }

    /// Hands the held pair `a`, `b` (which the engine has if `had`) to the engine, or takes
    /// it back, as their swept boxes meet or not.
    fn look_at(
        &mut self,
        h: &mut Handed,
        engine: &impl Engine,
        a: Key,
        b: Key,
        had: bool,
        events: &mut Vec<PairEvent>,
    ) {
        let (x, y) = (self.box_of(h, engine, a), self.box_of(h, engine, b));
        let meet = x.overlaps(&y);
        if meet != had {
            h.set(a.index, b.index, meet);
            self.count_event(meet);
            let (a, b) = if a.index < b.index { (a, b) } else { (b, a) };
            events.push(if meet {
                PairEvent::Add(a, b)
            } else {
                PairEvent::Delete(a, b)
            });
        }
    }

    /// Collider `c`'s swept box in this call, worked out once.
    fn box_of(&self, h: &mut Handed, engine: &impl Engine, c: Key) -> Aabb {
        let i = c.index as usize;
        if h.boxes[i].0 != h.call {
            h.boxes[i] = (h.call, self.swept_bounds(engine, c, self.clock.dt));
        }
        h.boxes[i].1
    }

    /// Collider `c`'s box as the engine grows it (for an engine that gives no boxes, the
    /// ball of its hold about its body's centre, or a fixed collider's own box), swept along
    /// its body's velocity over `dt` as far as the engine looks ahead ([`Engine::ahead`]; a
    /// sleeping body's as it is); everywhere when unknown.
    fn swept_bounds(&self, engine: &impl Engine, c: Key, dt: Real) -> Aabb {
        let everywhere = Aabb::EVERYWHERE;
        let hold = self.proxies.get(c.index as usize).copied().flatten();
        let (state, own) = match hold.map(|p| p.hold) {
            Some(Bound::Moving { body, radius, .. }) => {
                let state = engine.body(body).map(|s| (body, s));
                let own = engine.bounds(c).or_else(|| {
                    let r = Vec3::splat(radius);
                    state.map(|(_, s)| Aabb::about(s.centre, r))
                });
                (state, own)
            }
            Some(Bound::Fixed { min, max }) => {
                (None, Some(engine.bounds(c).unwrap_or(Aabb::new(min, max))))
            }
            None => (None, engine.bounds(c)),
        };
        let Some(own) = own else {
            return everywhere;
        };
        let d = match state.filter(|(_, s)| !s.sleeping) {
            Some((body, s)) if s.velocity != Vec3::ZERO => engine.ahead(body, s.velocity * dt),
            _ => Vec3::ZERO,
        };
        if !d.is_finite() {
            return everywhere;
        }
        own.swept(d)
    }

    /// Counts a pair added to or deleted from the engine.
    fn count_event(&mut self, add: bool) {
        if add {
            self.stats.added += 1;
            self.step.added += 1;
        } else {
            self.stats.deleted += 1;
            self.step.deleted += 1;
        }
    }

    /// Checks the engine's pairs against themselves (for tests): links at both ends, with
    /// the same answer, and the count of pairs handed.
    pub(super) fn validate_handed(&self) -> Result<(), String> {
        let h = &self.handed;
        let mut handed = 0;
        for (a, list) in h.links.iter().enumerate() {
            for l in list {
                let back = h
                    .find(l.other, a as u32)
                    .map(|at| h.links[l.other as usize][at]);
                match back {
                    Some(m) if m.handed == l.handed => {}
                    _ => return Err(format!("handed: pair ({a}, {}) not linked back", l.other)),
                }
                handed += usize::from(l.handed && (a as u32) < l.other);
            }
        }
        if handed != h.handed {
            return Err(format!(
                "handed: {handed} pairs handed, {} counted",
                h.handed
            ));
        }
        for (a, (list, places)) in h.links.iter().zip(&h.places).enumerate() {
            let Some(places) = places else { continue };
            let placed = list
                .iter()
                .enumerate()
                .all(|(k, l)| places.get(&l.other) == Some(&(k as u32)));
            if !placed || places.len() != list.len() {
                return Err(format!("handed: collider {a}'s links misplaced"));
            }
        }
        let held = h.links.iter().map(|l| l.len()).sum::<usize>() / 2;
        if held != h.held {
            return Err(format!("handed: {held} pairs held, {} counted", h.held));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    /// Pairs held, handed, let go and forgotten at random, most of them on one collider (a
    /// ground whose links are indexed): the links agree with a plain map after every change.
    #[test]
    fn a_collider_with_many_links_finds_each_as_a_plain_map_does() {
        let mut core = BroadPhaseCore::new();
        let mut want: BTreeMap<(u32, u32), bool> = BTreeMap::new();
        let mut s = 7u64;
        let mut next = |n: u64| {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            (s % n) as u32
        };
        let key = |i: u32| Key::new(i, 1);
        for round in 0..4000 {
            // One end is the ground (collider 0) three times in four.
            let a = if next(4) > 0 { 0 } else { 1 + next(150) };
            let b = 1 + next(150);
            if a == b {
                continue;
            }
            let p = (a.min(b), a.max(b));
            let h = &mut core.handed;
            match next(10) {
                0..=4 => {
                    // Held, and handed at once one time in three (as a stepped world's).
                    let hand = next(3) == 0;
                    let had = h.hold(key(a), key(b), hand);
                    assert_eq!(had, want.get(&p).copied().unwrap_or(false));
                    *want.entry(p).or_insert(false) |= hand;
                }
                5 | 6 => {
                    if let Some(handed) = want.get_mut(&p) {
                        let now = !*handed;
                        h.set(a, b, now);
                        *handed = now;
                    }
                }
                7 | 8 => {
                    let had = h.let_go(a, b);
                    assert_eq!(Some(had), want.remove(&p).or(Some(false)));
                }
                _ if round % 50 == 0 => {
                    h.forget(b);
                    want.retain(|&(x, y), _| x != b && y != b);
                }
                _ => {}
            }
            core.validate_handed().unwrap();
            for (&(x, y), &handed) in &want {
                assert_eq!(core.handed.has(x, y), handed);
                assert_eq!(core.handed.has(y, x), handed);
            }
        }
        assert!(
            core.handed.places[0].is_some(),
            "the ground's links were never indexed"
        );
    }
}
