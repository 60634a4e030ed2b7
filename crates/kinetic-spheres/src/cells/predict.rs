//! Predicting a ball's next event: its pairs (closed forms, or the world's root walk), its
//! wall contact and its cell event, the earliest of which is scheduled.

use super::{ElasticCells, Event, Next, TIE_WALL};
use kinetic_core::Real;
use kinetic_core::elastic::{Due, Walk, ball_gap, canonical_base};
use kinetic_core::elastic::{WallHit, wall_hit};
use kinetic_core::kds::pair_key;
use kinetic_core::kds::roots::quadratic_roots;
use kinetic_core::{Response, WorldKind};

/// Keeps the two earliest of `top` and `event` in `top`, in order (an event already first is
/// not taken again).
#[inline]
fn keep_earliest(top: &mut [Next; 2], event: Next) {
    if event.before(&top[0]) {
        top[1] = top[0];
        top[0] = event;
    } else if event.before(&top[1]) && (event.time, event.tie) != (top[0].time, top[0].tie) {
        top[1] = event;
    }
}

impl ElasticCells {
    /// The next event of the pair `(a, b)`: its time, and whether it is a graze.
    pub(super) fn pair_due(&self, a: u32, b: u32) -> Option<(Real, bool)> {
        // Apart now and never approaching (linear motion: the gap grows from its value at
        // the pair's base time), or approaching but clearly missing: no event, as the walk
        // would find. Decided from the compact motions; the gap polynomial is made only for
        // the pairs that need the walk.
        let (ma, mb) = (&self.motion[a as usize], &self.motion[b as usize]);
        let base = ma.t0.max(mb.t0).min(self.now);
        let reach = ma.radius + mb.radius;
        let threshold2 = reach * reach;
        let db = ma.at(base) - mb.at(base);
        let c0 = db.dot(db) - threshold2;
        let v = ma.velocity - mb.velocity;
        let c1 = 2.0 * db.dot(v);
        if c0 <= 0.0 && c1 > 0.0 && base == self.now {
            // In contact now (just met, within rounding) and moving apart: the walk starts
            // inside or at zero, and the gap only grows.
            return None;
        }
        if c0 > 0.0 {
            let gap_now = if base == self.now {
                c0
            } else {
                let d = ma.at(self.now) - mb.at(self.now);
                d.dot(d) - threshold2
            };
            if gap_now > 0.0 {
                if c1 >= 0.0 {
                    return None;
                }
                let c2 = v.dot(v);
                let (p, q) = (4.0 * c2 * c0, c1 * c1);
                if p - q > 1e-6 * (p + q) {
                    return None;
                }
                // A clear first contact: the gap (the same coefficients as the gap polynomial
                // at `base`) has two roots ahead, and the walk would report the first as a
                // begin. It is taken directly, bit for bit the walk's, unless the pair has
                // events consumed (a graze) or the root is not clearly after now.
                let mut roots = [(0.0, false); 4];
                if q - p > 1e-6 * (p + q)
                    && quadratic_roots(c0, c1, c2, &mut roots) == 2
                    && base + roots[0].0 > self.now
                    && !self.skips[a as usize].iter().any(|s| s.0 == b)
                {
                    return Some((base + roots[0].0, false));
                }
            }
        }
        let (pa, pb) = (&self.plans[a as usize], &self.plans[b as usize]);
        let (ra, rb) = (self.radius[a as usize], self.radius[b as usize]);
        debug_assert_eq!(base, canonical_base(pa, pb, self.now));
        let fb = ball_gap(WorldKind::Free, pa, ra, pb, rb, base);
        let f = if base == self.now {
            fb
        } else {
            ball_gap(WorldKind::Free, pa, ra, pb, rb, self.now)
        };
        let mut walk = Walk::elastic(&fb, base, self.now, &f);
        if let Some(&(_, _, until)) = self.skips[a as usize]
            .iter()
            .find(|&&(o, c, _)| o == b && c == self.counter[b as usize])
        {
            while walk.due.is_some_and(|(t, _, _)| t <= until) {
                walk.consume(Response::Elastic);
            }
        }
        walk.due.map(|(t, _, due)| (t, due == Due::Graze))
    }

    /// Ball `id`'s next wall contact, found (as the world finds it) from the state at the
    /// start of its plan, so that it does not depend on when it is asked for.
    pub(super) fn wall_from_plan(&self, id: u32) -> Option<WallHit> {
        let plan = &self.plans[id as usize];
        let made = plan.t0.min(self.now);
        wall_hit(plan, self.radius[id as usize], &self.walls, 3, made)
    }

    /// Ball `id`'s next wall contact, not before now.
    pub(super) fn wall_next(&self, id: u32) -> Option<WallHit> {
        let mut hit = self.wall[id as usize]?;
        hit.time = hit.time.max(self.now);
        Some(hit)
    }

    /// Recomputes ball `id`'s next event from all its certificates; with `offer`, each pair's
    /// failure time is offered to the partner too (after a change of plan, or of neighbours).
    pub(super) fn predict(&mut self, id: u32, offer: bool) {
        let mut others = std::mem::take(&mut self.neighbour_buffer);
        self.neighbours(id, &mut others);
        self.pair_next[id as usize] = [Next::IDLE; 2];
        self.predict_with(id, &others, offer);
        others.clear();
        self.neighbour_buffer = others;
    }

    /// Ball `id` crossed into new cells (its home cell moved along `axis`, or with `block`,
    /// that block's end grew along `axis`): its pairs with the balls of the cells entered
    /// are predicted and offered, and its two earliest pair events known are kept. The balls
    /// it left behind are still reached by those events or by a later full prediction.
    pub(super) fn predict_entered(&mut self, id: u32, block: Option<u8>, axis: usize, up: bool) {
        let mut others = std::mem::take(&mut self.neighbour_buffer);
        let i = id as usize;
        match block {
            None => {
                let l = &self.levels[self.level[i] as usize];
                let home = self.home[i];
                let (mut lo, mut hi) = Self::around(l, home);
                let far = if up {
                    home[axis] + 1
                } else {
                    home[axis].wrapping_sub(1)
                };
                if far < l.n[axis] {
                    (lo[axis], hi[axis]) = (far, far);
                    self.members(l, lo, hi, id, &mut others);
                }
                if let Some(v) = l.visitors.get(&l.index(home)) {
                    others.extend_from_slice(v);
                }
            }
            Some(level) => {
                if let Some(b) = self.blocks[i].iter().find(|b| b.level == level) {
                    let (mut lo, mut hi) = (b.lo, b.hi);
                    let at = if up { b.hi[axis] } else { b.lo[axis] };
                    (lo[axis], hi[axis]) = (at, at);
                    self.members(&self.levels[level as usize], lo, hi, id, &mut others);
                }
            }
        }
        self.predict_with(id, &others, true);
        others.clear();
        self.neighbour_buffer = others;
    }

    /// Ball `id`'s next event: the earliest of its wall contact, its cell event, its two
    /// earliest pair events known, and its pairs with `others` (offered to them with `offer`).
    fn predict_with(&mut self, id: u32, others: &[u32], offer: bool) {
        let i = id as usize;
        let mut top = self.pair_next[i];
        for &other in others {
            let Some((time, graze)) = self.pair_due(id, other) else {
                continue;
            };
            let tie = pair_key(self.ext[i], self.ext[other as usize]);
            let mine = Next {
                time,
                tie,
                event: Event::Pair {
                    other,
                    counter: self.counter[other as usize],
                    graze,
                },
            };
            keep_earliest(&mut top, mine);
            if offer {
                let theirs = Next {
                    time,
                    tie,
                    event: Event::Pair {
                        other: id,
                        counter: self.counter[i],
                        graze,
                    },
                };
                let o = other as usize;
                keep_earliest(&mut self.pair_next[o], theirs);
                if theirs.before(&self.next[o]) {
                    self.next[o] = theirs;
                    self.queue.schedule(other, time, tie);
                }
            }
        }
        self.pair_next[i] = top;
        self.settle(id);
    }

    /// Schedules ball `id`'s next event: the earliest of its wall contact, its cell event and
    /// its two earliest pair events known (the first of them on a tie).
    pub(super) fn settle(&mut self, id: u32) {
        let i = id as usize;
        let mut best = Next::IDLE;
        if let Some(hit) = self.wall_next(id) {
            best = Next {
                time: hit.time,
                tie: TIE_WALL | u64::from(self.ext[id as usize]),
                event: Event::Wall(hit),
            };
        }
        let cell = self.cell_event(id);
        if cell.before(&best) {
            best = cell;
        }
        for pair in self.pair_next[i] {
            if pair.before(&best) {
                best = pair;
            }
        }
        self.next[i] = best;
        if best.time.is_finite() {
            self.queue.schedule(id, best.time, best.tie);
        } else {
            self.queue.remove(id);
        }
    }
}
