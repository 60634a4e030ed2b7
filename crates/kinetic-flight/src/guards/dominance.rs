//! Cones and dominance (Lemma 9): the cone every guard of an object sees another's centre
//! in, and the closer object of the same cone that proves a box holds no guard.

use super::Guards;
use kinetic_core::kds::certificates::ball_ball_gap;
use kinetic_core::kds::roots::first_sign_change;
use kinetic_core::kds::{Bodies, EventQueue, PairChange, Poly};
use kinetic_core::{Real, Vec3};

/// The first time after `now` at which `p` (in local time) changes sign, never `now` itself.
fn due(p: &Poly, now: Real) -> Real {
    first_sign_change(p).map_or(Real::INFINITY, |tau| {
        let t = now + tau;
        if t > now { t } else { now.next_up() }
    })
}

/// Puts watch `slot` in `queue` at `due`, or out of it when it is never due.
pub(super) fn reschedule(queue: &mut EventQueue, slot: u32, due: Real) {
    if due.is_finite() {
        queue.schedule(slot, due, u64::from(slot));
    } else {
        queue.remove(slot);
    }
}

/// `n . d(tau) - shift` for a relative centre `d` given as local coefficients.
fn along(n: Vec3, d: &[Vec3; 3], shift: Real) -> Poly {
    Poly::new(&[n.dot(d[0]) - shift, n.dot(d[1]), n.dot(d[2])])
}

impl Guards {
    /// The centre of `boxer` relative to that of `guarded`, in local time from `now`.
    fn relative(bodies: &Bodies, guarded: u32, boxer: u32, now: Real) -> [Vec3; 3] {
        let (a, b) = (
            Self::plan(bodies, boxer).local_coefficients(now),
            Self::plan(bodies, guarded).local_coefficients(now),
        );
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    /// Half the side of the guard cube of `guarded`, a relative 1e-9 wider.
    pub(super) fn cube_half(&self, guarded: u32) -> Real {
        self.grid
            .offset(self.inner[guarded as usize], self.grid.m - 1)
            * (1.0 + 1e-9)
    }

    /// The cone that every guard of `guarded` sees the centre of `boxer` in, with the time to
    /// look again: when the centre leaves it (a centre event) or, with no such cone, when
    /// the cube might come to lie inside one.
    ///
    /// With hysteresis, so that rounding at a crossing cannot bring the same crossing back
    /// an instant later: the cube enters a cone only with every margin at least `slack` (a
    /// relative 1e-9 of the distance), and leaves it when a margin reaches 0; outside, it
    /// looks again when a margin below `slack` reaches `2 slack`, or when the centre is
    /// `slack` past a facet of its cone.
    fn cone_state(&self, bodies: &Bodies, guarded: u32, boxer: u32) -> (Option<u32>, Real) {
        let now = self.now;
        let d = Self::relative(bodies, guarded, boxer, now);
        let i = self.cones.locate(d[0]);
        let cone = self.cones.cone(i);
        // The cube lies in the cone when its farthest corner from each facet plane does:
        // n . d >= a |n|_1 for the cube's half side a.
        let half = self.cube_half(guarded);
        let slack = 1e-9 * (d[0].length() + half);
        let margins = cone
            .normals
            .map(|n| along(n, &d, half * n.abs().element_sum()));
        let first = |ps: &mut dyn Iterator<Item = Poly>| {
            ps.map(|p| due(&p, now)).fold(Real::INFINITY, Real::min)
        };
        if margins
            .iter()
            .all(|p| p.c[0] >= slack && p.sign_just_after_zero() > 0)
        {
            (Some(i), first(&mut margins.into_iter()))
        } else {
            let rising = margins.into_iter().filter(|p| p.c[0] < slack).map(|p| {
                let mut p = p;
                p.c[0] -= 2.0 * slack;
                p
            });
            let leaving = cone.normals.map(|n| along(n, &d, -slack));
            (None, first(&mut rising.chain(leaving)))
        }
    }

    /// The watch of the same guarded object and cone that proves `slot`'s boxer holds no
    /// guard, with the time the proof lasts: its centre is closer along the representative
    /// edge, and the outer balls are apart (Lemma 9: a centre between a guard and the
    /// triangle of the cone through the other centre lies inside that other object, had it
    /// held the guard). Of several, the one whose proof lasts longest.
    fn find_dominator(&self, bodies: &Bodies, slot: u32) -> (Option<u32>, Real) {
        let w = self.watches[slot as usize].expect("a live watch");
        let Some(cone) = w.cone else {
            return (None, Real::INFINITY);
        };
        let Some(list) = self.by_cone.get(&(w.guarded, cone)) else {
            return (None, Real::INFINITY);
        };
        let now = self.now;
        let edge = self.cones.cone(cone).edge();
        let me = Self::plan(bodies, w.boxer).local_coefficients(now);
        let mut best: (Option<u32>, Real) = (None, Real::NEG_INFINITY);
        for &o in list {
            if o == slot {
                continue;
            }
            let other = self.watches[o as usize].expect("a live watch").boxer;
            let them = Self::plan(bodies, other).local_coefficients(now);
            let farther = Poly::new(&[
                edge.dot(me[0] - them[0]),
                edge.dot(me[1] - them[1]),
                edge.dot(me[2] - them[2]),
            ]);
            // Hysteresis as for the cones: a dominance starts only with a relative 1e-9 to
            // spare, so rounding where one ends cannot restart it an instant later.
            let reach = self.half[w.boxer as usize] + self.half[other as usize];
            let slack = 1e-9 * ((me[0] - them[0]).length() + reach);
            if farther.c[0] < slack || farther.sign_just_after_zero() <= 0 {
                continue;
            }
            let apart = ball_ball_gap(&me, &them, reach * reach);
            if apart.c[0] < slack * reach || apart.sign_just_after_zero() <= 0 {
                continue;
            }
            let until = due(&farther, now).min(due(&apart, now));
            if until > best.1 {
                best = (Some(o), until);
            }
        }
        match best.0 {
            Some(_) => best,
            None => (None, Real::INFINITY),
        }
    }

    fn schedule_cone(&mut self, slot: u32) {
        let w = self.watches[slot as usize].as_ref().expect("a live watch");
        reschedule(&mut self.cone_queue, slot, w.cone_event_time());
    }

    /// Takes `slot` out of its cone's list and drops its dominance links; the watches it
    /// dominated are pushed to `redo`.
    pub(super) fn detach(&mut self, slot: u32, redo: &mut Vec<u32>) {
        let mut w = self.watches[slot as usize].expect("a live watch");
        if let Some(c) = w.cone.take() {
            let key = (w.guarded, c);
            let list = self.by_cone.get_mut(&key).expect("a listed cone");
            let i = list
                .iter()
                .position(|&s| s == slot)
                .expect("a listed watch");
            list.swap_remove(i);
            if list.is_empty() {
                self.by_cone.remove(&key);
            }
        }
        if let Some(d) = w.dominator.take() {
            let list = &mut self.dominatees[d as usize];
            let i = list.iter().position(|&s| s == slot).expect("a dominatee");
            list.swap_remove(i);
        }
        w.cone_due = Real::INFINITY;
        w.dominator_due = Real::INFINITY;
        self.put_watch(slot, Some(w));
        for d in std::mem::take(&mut self.dominatees[slot as usize]) {
            let mut x = self.watches[d as usize].expect("a live watch");
            x.dominator = None;
            x.dominator_due = Real::INFINITY;
            self.put_watch(d, Some(x));
            redo.push(d);
        }
    }

    /// Looks again for a dominator of `slot` and updates its pair.
    pub(super) fn redominate(&mut self, bodies: &Bodies, slot: u32, changes: &mut Vec<PairChange>) {
        let Some(mut w) = self.watches[slot as usize] else {
            return;
        };
        if let Some(d) = w.dominator.take() {
            let list = &mut self.dominatees[d as usize];
            let i = list.iter().position(|&s| s == slot).expect("a dominatee");
            list.swap_remove(i);
        }
        // The search reads only the watch's cone and boxer, which stay as stored.
        let (dominator, until) = self.find_dominator(bodies, slot);
        w.dominator = dominator;
        w.dominator_due = until;
        if let Some(d) = dominator {
            self.dominatees[d as usize].push(slot);
        }
        self.put_watch(slot, Some(w));
        self.schedule_cone(slot);
        self.set_pair(w.guarded, w.boxer, w.wanted(), changes);
    }

    /// Places the watches `slots` in their cones afresh (they are new, or their plans
    /// changed, or a centre crossed a facet) and settles every dominance that this touches.
    pub(super) fn recone(&mut self, bodies: &Bodies, slots: &[u32], changes: &mut Vec<PairChange>) {
        let mut redo = Vec::new();
        for &s in slots {
            self.detach(s, &mut redo);
        }
        for &s in slots {
            let mut w = self.watches[s as usize].expect("a live watch");
            let (cone, until) = self.cone_state(bodies, w.guarded, w.boxer);
            w.cone = cone;
            w.cone_due = until;
            self.put_watch(s, Some(w));
            redo.push(s);
            if let Some(c) = cone {
                let list = self.by_cone.entry((w.guarded, c)).or_default();
                // Undominated watches of this cone may now be dominated by this one.
                redo.extend(
                    list.iter().copied().filter(|&o| {
                        self.watches[o as usize].is_some_and(|x| x.dominator.is_none())
                    }),
                );
                list.push(s);
            }
        }
        redo.sort_unstable();
        redo.dedup();
        for s in redo {
            self.redominate(bodies, s, changes);
        }
    }

    /// A cone event of watch `slot`: its centre crossed a facet ("centre"), or its dominance
    /// ended ("dominance"). Returns the kind.
    pub(super) fn on_cone(
        &mut self,
        slot: u32,
        bodies: &Bodies,
        changes: &mut Vec<PairChange>,
    ) -> &'static str {
        let w = self.watches[slot as usize].expect("a live watch");
        if w.cone_due <= w.dominator_due {
            self.centre_events += 1;
            self.recone(bodies, &[slot], changes);
            "centre"
        } else {
            self.dominance_events += 1;
            self.redominate(bodies, slot, changes);
            "dominance"
        }
    }
}
