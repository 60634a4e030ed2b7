//! The event loop: each ball's scheduled event in time order, and the responses.

use super::{ElasticCells, Event, Next};
use crate::bulk::mass;
use kinetic_core::FlightPlan;
use kinetic_core::Real;
use kinetic_core::elastic::Motion;
use kinetic_core::elastic::bounced;
use kinetic_core::elastic::elastic_exchange;
use kinetic_core::{ContactEvent, ContactKind, ObjectId, WorldError};

impl ElasticCells {
    /// Processes every event up to time `t` in time order, then moves the clock to `t`.
    pub fn advance_to(&mut self, t: Real) -> Result<(), WorldError> {
        if t.is_nan() || t < self.now {
            return Err(WorldError::Backwards {
                now: self.now,
                to: t,
            });
        }
        while self.step(t)? {}
        self.now = t;
        Ok(())
    }

    /// Processes the next event if it happens at or before `until`; returns whether there
    /// was one. Tests call [`ElasticCells::validate`] between steps.
    pub fn step(&mut self, until: Real) -> Result<bool, WorldError> {
        let Some((id, time)) = self.queue.peek() else {
            return Ok(false);
        };
        if time > until || time.is_nan() {
            return Ok(false);
        }
        // The ball stays at the head of the queue while its event is processed: every branch
        // below schedules its next event, which moves it down once.
        if time > self.now {
            self.now = time;
        }
        let next = self.next[id as usize];
        self.next[id as usize] = Next::IDLE;
        let (kind, pair) = match next.event {
            Event::Idle => {
                self.queue.remove(id);
                ("recheck", (id, id))
            }
            Event::Recheck => {
                self.predict(id, false);
                ("recheck", (id, id))
            }
            Event::Pair {
                other,
                counter,
                graze,
            } => {
                if self.counter[other as usize] != counter {
                    let second = self.pair_next[id as usize][1];
                    if matches!(second.event, Event::Pair { .. }) {
                        let rest = Next {
                            event: Event::Recheck,
                            ..second
                        };
                        self.pair_next[id as usize] = [second, rest];
                        self.settle(id);
                        ("stale", (id, other))
                    } else {
                        self.predict(id, false);
                        ("recheck", (id, other))
                    }
                } else {
                    self.fire_pair(id, other, graze);
                    ("collision", (id, other))
                }
            }
            Event::Wall(hit) => {
                let old = self.plans[id as usize].velocity_at(self.now)[hit.axis];
                let plan = bounced(&self.plans[id as usize], hit, self.now);
                let dv = plan.velocity_at(self.now)[hit.axis] - old;
                self.sums.wall_impulse += mass(self.radius[id as usize]) * dv.abs();
                self.stats.bounces += 1;
                self.replan(id, plan);
                self.predict(id, true);
                ("bounce", (id, id))
            }
            Event::Home { axis, up } => {
                self.link_out(id);
                let c = &mut self.home[id as usize][axis as usize];
                *c = if up { *c + 1 } else { *c - 1 };
                self.link_in(id);
                self.predict_entered(id, None, axis as usize, up);
                ("crossing", (id, id))
            }
            Event::Block {
                level,
                axis,
                hi,
                up,
            } => {
                self.move_block(id, level, axis as usize, hi, up);
                if hi == up {
                    self.predict_entered(id, Some(level), axis as usize, up);
                } else {
                    // The block only left cells: the remembered pair events still stand.
                    self.settle(id);
                }
                ("crossing", (id, id))
            }
        };
        *self.stats.events_by_kind.entry(kind).or_insert(0) += 1;
        self.sample();
        let (a, b) = (self.ext[pair.0 as usize], self.ext[pair.1 as usize]);
        self.zeno.count(self.now, self.len(), a, b)?;
        Ok(true)
    }

    pub(super) fn sample(&mut self) {
        let c = self.queue.len();
        let s = &mut self.stats;
        s.certificates_max = s.certificates_max.max(c);
        s.certificates_sum += c as f64;
        s.samples += 1;
    }

    /// A pair certificate fails: report the contact and respond. Balls whose plans do not
    /// change (a graze, or balls that are not approaching) skip that event of the pair.
    fn fire_pair(&mut self, a: u32, b: u32, graze: bool) {
        self.log(a, b);
        if !graze {
            let (ra, rb) = (self.radius[a as usize], self.radius[b as usize]);
            let (pa, pb) = (self.plans[a as usize], self.plans[b as usize]);
            if let Some((na, nb)) = elastic_exchange(&pa, ra, &pb, rb, self.now) {
                self.sums.collisions += 1;
                self.replan(a, na);
                self.replan(b, nb);
                self.predict(a, true);
                self.predict(b, true);
                return;
            }
        }
        let (ca, cb) = (self.counter[a as usize], self.counter[b as usize]);
        self.skips[a as usize].push((b, cb, self.now));
        self.skips[b as usize].push((a, ca, self.now));
        self.predict(a, false);
        self.predict(b, false);
    }

    fn log(&mut self, a: u32, b: u32) {
        let (a, b) = (self.ext[a as usize], self.ext[b as usize]);
        self.stats.begins += 1;
        self.events.push(ContactEvent {
            time: self.now,
            a: ObjectId(a.min(b)),
            b: ObjectId(a.max(b)),
            kind: ContactKind::Begin,
        });
    }

    /// Installs a new plan: the ball's old predictions are stale from now on.
    fn replan(&mut self, id: u32, plan: FlightPlan) {
        self.plans[id as usize] = plan;
        self.motion[id as usize] = Motion::of(&plan, self.radius[id as usize]);
        self.counter[id as usize] = self.counter[id as usize].wrapping_add(1);
        self.skips[id as usize].clear();
        self.wall[id as usize] = self.wall_from_plan(id);
    }
}
