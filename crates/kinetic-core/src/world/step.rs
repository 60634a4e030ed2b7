//! The event loop: structure events, pair certificate failures and wall contacts, processed in
//! time order; the elastic response re-plans the two balls and reschedules only their
//! certificates.

use super::pairs::Due;
use super::{ContactKind, Response, Simulator, WorldError};
use crate::math::{Real, Vec3};
use crate::plan::FlightPlan;

/// What one call to [`Simulator::step`] processed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StepKind {
    /// An event of the candidate structure (its kind, e.g. `"swap"`).
    Structure(&'static str),
    /// A pair certificate failed (contact begin, end, graze or collision) between `a < b`.
    Pair(u32, u32),
    /// A ball bounced off a wall.
    Wall(u32),
}

/// Events allowed at one instant, per live object, before the run is declared Zeno.
const ZENO_PER_OBJECT: u64 = 1000;

/// Counts the events at one instant: a run with more than [`ZENO_PER_OBJECT`] per object at
/// the same time is a Zeno configuration.
#[derive(Clone, Copy, Debug)]
pub struct ZenoGuard {
    at: Real,
    count: u64,
}

impl Default for ZenoGuard {
    fn default() -> ZenoGuard {
        ZenoGuard {
            at: Real::NEG_INFINITY,
            count: 0,
        }
    }
}

impl ZenoGuard {
    /// One more event at `now` among `objects` objects, the last between `a` and `b`.
    pub fn count(&mut self, now: Real, objects: usize, a: u32, b: u32) -> Result<(), WorldError> {
        if self.at == now {
            self.count += 1;
        } else {
            (self.at, self.count) = (now, 1);
        }
        let limit = ZENO_PER_OBJECT * (objects as u64 + 1);
        if self.count > limit {
            return Err(WorldError::Zeno {
                time: now,
                limit,
                a: a.min(b),
                b: a.max(b),
            });
        }
        Ok(())
    }
}

impl Simulator {
    /// The time of the next event (+infinity for none).
    pub fn next_event_time(&self) -> Real {
        self.structure
            .next_event_time()
            .min(self.pair_queue.next_time())
            .min(self.wall_queue.next_time())
    }

    /// Processes every event up to time `t` in time order, then moves the clock to `t`.
    pub fn advance_to(&mut self, t: Real) -> Result<(), WorldError> {
        if t.is_nan() || t < self.now {
            return Err(WorldError::Backwards {
                now: self.now,
                to: t,
            });
        }
        if self.stats.samples == 0 {
            self.sample();
        }
        while self.step(t)?.is_some() {}
        self.now = t;
        Ok(())
    }

    /// Processes the next event if it happens at or before `until`; returns what it was.
    /// Tests call [`Simulator::validate`] between steps.
    pub fn step(&mut self, until: Real) -> Result<Option<StepKind>, WorldError> {
        let ts = self.structure.next_event_time();
        let tp = self.pair_queue.next_time();
        let tw = self.wall_queue.next_time();
        let next = ts.min(tp).min(tw);
        if next > until || next.is_nan() {
            return Ok(None);
        }
        if next > self.now {
            self.now = next;
        }
        // At equal times: structure events first (they may add the pair that is due), then
        // pairs by (a, b), then walls by object.
        let kind = if ts <= tp && ts <= tw {
            let mut changes = std::mem::take(&mut self.changes);
            let kind = self
                .structure
                .process_next_event(&self.bodies, &mut changes);
            self.apply_changes(&mut changes);
            self.changes = changes;
            StepKind::Structure(kind)
        } else if tp <= tw {
            let (slot, _) = self.pair_queue.pop().expect("a pair is due");
            let (a, b) = self.fire_pair(slot);
            StepKind::Pair(a, b)
        } else {
            let (id, _) = self.wall_queue.pop().expect("a wall contact is due");
            self.bounce(id);
            StepKind::Wall(id)
        };
        let name = match kind {
            StepKind::Structure(k) => k,
            StepKind::Pair(..) => "collision",
            StepKind::Wall(_) => "bounce",
        };
        *self.stats.events_by_kind.entry(name).or_insert(0) += 1;
        self.sample();
        self.count_instant(kind)?;
        Ok(Some(kind))
    }

    /// Guards against Zeno configurations: a bounded number of events per instant.
    fn count_instant(&mut self, kind: StepKind) -> Result<(), WorldError> {
        let (a, b) = match kind {
            StepKind::Pair(a, b) => (a, b),
            StepKind::Wall(a) => (a, a),
            StepKind::Structure(_) => (0, 0),
        };
        self.zeno.count(self.now, self.len(), a, b)
    }

    /// A pair certificate fails: report it, respond, and find the pair's next event.
    fn fire_pair(&mut self, slot: u32) -> (u32, u32) {
        let cert = *self.pairs.get(slot);
        let (a, b) = (cert.a, cert.b);
        let Some((_, due)) = cert.walk.due() else {
            return (a, b);
        };
        match (self.response, due) {
            (_, Due::Recheck) => {}
            (Response::None, Due::Begin) => {
                self.log(a, b, ContactKind::Begin);
                self.pairs.get_mut(slot).touching = true;
            }
            (Response::None, Due::End) => {
                self.log(a, b, ContactKind::End);
                self.pairs.get_mut(slot).touching = false;
            }
            (_, Due::Graze) => {
                self.log(a, b, ContactKind::Begin);
                if self.response == Response::None {
                    self.log(a, b, ContactKind::End);
                }
            }
            (Response::Elastic, _) => {
                self.log(a, b, ContactKind::Begin);
                if self.collide(a, b) {
                    return (a, b); // both re-planned: every pair of theirs is fresh
                }
            }
        }
        self.consume_pair(slot);
        (a, b)
    }

    /// The elastic response: momentum exchanged along the line between the centres (between
    /// tangency points on a plane), masses proportional to radius cubed. Returns whether the
    /// velocities changed (they do not for balls that are not approaching).
    fn collide(&mut self, a: u32, b: u32) -> bool {
        let (pa, pb) = (self.plan_of(a), self.plan_of(b));
        match elastic_exchange(&pa, self.radius(a), &pb, self.radius(b), self.now) {
            Some((na, nb)) => {
                self.replan(a, na);
                self.replan(b, nb);
                true
            }
            None => false,
        }
    }

    /// Installs a new plan for `id` and reschedules exactly its certificates.
    pub(crate) fn replan(&mut self, id: u32, plan: FlightPlan) {
        if let Some(body) = self.bodies[id as usize].as_mut() {
            body.plan = plan;
        }
        let mut changes = std::mem::take(&mut self.changes);
        self.structure
            .replan(id, &self.bodies, self.now, &mut changes);
        self.apply_changes(&mut changes);
        self.changes = changes;
        for slot in self.pairs.slots_of(id) {
            self.refresh_pair(slot);
        }
        self.refresh_walls(id);
    }
}

/// The plans of two balls after an elastic collision at `now`: momentum exchanged along the
/// line between the centres (between tangency points on a plane), masses proportional to
/// radius cubed; `None` for balls that are not approaching (their velocities do not change).
pub fn elastic_exchange(
    pa: &FlightPlan,
    ra: Real,
    pb: &FlightPlan,
    rb: Real,
    now: Real,
) -> Option<(FlightPlan, FlightPlan)> {
    let d = pa.position_at(now) - pb.position_at(now);
    let e = Exchange::of(d, pa.velocity_at(now), pb.velocity_at(now), ra, rb)?;
    Some((pa.replanned(now, e.va), pb.replanned(now, e.vb)))
}

/// An elastic exchange between two balls: their new velocities, and what the collision
/// virial needs.
pub struct Exchange {
    /// Ball a's new velocity.
    pub va: Vec3,
    /// Ball b's new velocity.
    pub vb: Vec3,
    /// The distance between the centres.
    pub distance: Real,
    /// a's change of velocity along the line from b to a (positive): a's impulse is its
    /// mass times this.
    pub dv_a: Real,
}

impl Exchange {
    /// Balls of radii `ra`, `rb` moving at `va`, `vb`, a's centre `d` from b's: momentum
    /// exchanged along `d`, masses proportional to radius cubed; `None` unless approaching.
    #[inline]
    pub fn of(d: Vec3, va: Vec3, vb: Vec3, ra: Real, rb: Real) -> Option<Exchange> {
        let len = d.length();
        if len == 0.0 || !len.is_finite() {
            return None;
        }
        let n = d / len;
        let u = (va - vb).dot(n);
        if u >= 0.0 {
            return None;
        }
        let (ma, mb) = (ra * ra * ra, rb * rb * rb);
        // Written with mass ratios so that radii 1e-6 next to 1e6 do not overflow.
        let (wa, wb) = (2.0 / (1.0 + ma / mb), 2.0 / (1.0 + mb / ma));
        Some(Exchange {
            va: va - n * (wa * u),
            vb: vb + n * (wb * u),
            distance: len,
            dv_a: -(wa * u),
        })
    }
}
