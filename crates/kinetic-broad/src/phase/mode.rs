//! Kinetic or stepped: the broad phase follows what the world's bodies do.
//!
//! Plans pay where they hold. In a pile, a settling rain or a dense gas nearly every body is
//! pushed off its plan every few steps, and each re-plan costs the kinetic structure far more
//! than filing the body's box again. There the broad phase *steps*: the kinetic structure is
//! dropped and each call files every collider's box, swept over the coming step, into the
//! stepped grid ([`crate::stepped`]) and hands over the pairs whose boxes overlap.
//!
//! The choice is made from counts, never from clocks, so a run is the same every time:
//!
//! - kinetic, a step costs its re-plans and events, [`OP_COST`] each;
//! - stepped, a step costs [`BOX_COST`] per collider held;
//! - while stepped, the plans are still kept (re-fitted as they fail, at no cost to any
//!   structure), and a kinetic step is priced as the last kinetic stretch's cost scaled by
//!   how many re-plans there are now to how many there were then.
//!
//! Both costs are averaged over about [`SMOOTHING`] steps. The world steps once the kinetic
//! cost is above the stepped one and goes back once it is below [`BACK`] of it, at least
//! [`DWELL`] steps after the last switch. Only the structure the broad phase picks for
//! itself switches: a caller's choice ([`BroadPhaseCore::with_structure`]) stays kinetic.
//!
//! The pairs the engine has are carried over at a switch: to the stepped grid's, with adds
//! and deletes for the difference, and back to the kinetic book, which adopts those it holds
//! and deletes the others.

use super::BroadPhaseCore;
use crate::stepped::{Aabb, SteppedGrid};
use crate::{Engine, Hold, PairEvent};
use kinetic_core::{Real, Vec3};
use kinetic_flight::Choice;

/// The kinetic cost of a re-plan or an event, in units of one collider filed by the stepped
/// grid (measured on the rapier bench's pile, rain and gas at 1e3 and 1e4 bodies).
const OP_COST: Real = 40.0;
/// The stepped cost of a collider.
const BOX_COST: Real = 1.0;
/// Costs are averaged over about this many steps.
const SMOOTHING: Real = 4.0;
/// A stepped world goes back to kinetic once a kinetic step is priced below this share of a
/// stepped one.
const BACK: Real = 0.5;
/// Steps between two switches at least.
const DWELL: u64 = 8;

/// The stepped mode's state.
#[derive(Debug, Default)]
pub(super) struct Stepped {
    grid: SteppedGrid,
    /// Per collider index, its box for this call (`None`: to be worked out).
    boxes: Vec<Option<Aabb>>,
    /// The pairs the engine has, sorted.
    pub(super) reported: Vec<(u32, u32)>,
    /// This call's pairs.
    found: Vec<(u32, u32)>,
}

/// What decides the mode.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct Meter {
    /// Averaged costs of a kinetic step (measured or priced) and of a stepped one.
    kinetic: Real,
    stepped: Real,
    /// Averaged re-plans a step.
    replans: Real,
    /// The last kinetic stretch's averaged cost and re-plans, when it ended.
    last_cost: Real,
    last_replans: Real,
    /// The step of the last switch.
    switched: u64,
    /// Whether the next position update switches.
    switch: bool,
}

impl Stepped {
    /// Forgets collider `i`'s box and (`silent`) its pairs: the engine drops a removed
    /// collider's pairs itself.
    pub(super) fn forget(&mut self, i: u32, silent: bool) {
        if let Some(b) = self.boxes.get_mut(i as usize) {
            *b = None;
        }
        if silent {
            self.reported.retain(|&(a, b)| a != i && b != i);
        }
    }

    /// Marks collider `i`'s box to be worked out again.
    pub(super) fn moved(&mut self, i: u32) {
        if let Some(b) = self.boxes.get_mut(i as usize) {
            *b = None;
        }
    }
}

impl BroadPhaseCore {
    /// Whether the world may step: the structure is the broad phase's own pick, and the loose
    /// grid (alike sizes: a spread of sizes would make the stepped grid test its big boxes
    /// against every other).
    pub(super) fn may_step(&self) -> bool {
        !self.choice_given && self.choice == Some(Choice::Loose)
    }

    /// Whether the world is stepped now.
    pub(super) fn is_stepped(&self) -> bool {
        self.stepped.is_some()
    }

    /// At the end of a step: prices it both ways, and calls for a switch if the other way
    /// is cheaper.
    pub(super) fn weigh(&mut self) {
        if !self.may_step() {
            return;
        }
        let held = self.proxies.iter().flatten().count() as Real;
        let replans = self.step.replans as Real;
        let m = &mut self.meter;
        let w = 1.0 / SMOOTHING;
        let kinetic = if self.stepped.is_some() {
            if m.last_cost > 0.0 {
                m.last_cost * (replans + 1.0) / (m.last_replans + 1.0)
            } else {
                // No kinetic stretch yet: an event for each re-plan.
                2.0 * OP_COST * replans
            }
        } else {
            OP_COST * (self.step.replans + self.step.events) as Real
        };
        m.kinetic += w * (kinetic - m.kinetic);
        m.stepped += w * (BOX_COST * held - m.stepped);
        m.replans += w * (replans - m.replans);
        let steps = self.stats.steps;
        if steps < m.switched + DWELL {
            return;
        }
        if self.stepped.is_none() && m.kinetic > m.stepped {
            m.last_cost = m.kinetic;
            m.last_replans = m.replans;
            m.switched = steps;
            m.switch = true;
        } else if self.stepped.is_some() && m.kinetic < BACK * m.stepped {
            m.switched = steps;
            m.switch = true;
        }
    }

    /// At the start of a position update: makes the switch the last step's costs called for.
    pub(super) fn switch_if_due(&mut self, engine: &impl Engine) {
        if !std::mem::take(&mut self.meter.switch) {
            return;
        }
        self.stats.switches += 1;
        if self.stepped.is_none() {
            self.go_stepped();
        } else {
            self.go_kinetic(engine);
        }
    }

    /// Drops the kinetic structure; this call's stepped pairs take over from the book's.
    fn go_stepped(&mut self) {
        let mut had = self.book.reported_pairs();
        had.sort_unstable();
        self.book = Default::default();
        self.structure = None;
        self.grown.clear();
        for p in self.proxies.iter_mut().flatten() {
            p.grown_until = None;
            p.fat = None;
        }
        let keys: Vec<_> = self.motions.iter().map(|(k, _)| k).collect();
        for k in keys {
            self.motions.get_mut(k).expect("listed").fat = false;
        }
        self.stepped = Some(Stepped {
            reported: had,
            ..Stepped::default()
        });
    }

    /// Builds the kinetic structure again from the proxies and their plans, at the positions'
    /// time; the book adopts the engine's pairs once this call's events have run
    /// ([`BroadPhaseCore::adopt`]).
    fn go_kinetic(&mut self, engine: &impl Engine) {
        let st = self.stepped.take().expect("stepped");
        self.adopting = Some(st.reported);
        self.clock.kds = self.clock.pos;
        // Bodies at rest are held by fat boxes again.
        let resting: Vec<_> = self
            .motions
            .iter()
            .filter(|(_, m)| m.at_rest())
            .map(|(k, _)| k)
            .collect();
        for b in resting {
            self.box_in(engine, b);
        }
        self.build_structure();
    }

    /// After a switch back to kinetic, once the structure has looked ahead: the book takes the
    /// pairs the engine has that it holds as handed over, and the others are deleted.
    pub(super) fn adopt(&mut self, events: &mut Vec<PairEvent>) {
        let Some(had) = self.adopting.take() else {
            return;
        };
        let mut gone = Vec::new();
        self.book.adopt(&had, &mut gone);
        for (a, b) in gone {
            self.out_event(a, b, false, events);
        }
    }

    /// The stepped call: every collider's box, the pairs whose boxes overlap, and the adds
    /// and deletes that take the engine's pairs to them.
    pub(super) fn step_pairs(&mut self, engine: &impl Engine, events: &mut Vec<PairEvent>) {
        let mut st = self.stepped.take().expect("stepped");
        self.stepped_pairs(&mut st, engine, events);
        self.stepped = Some(st);
    }

    fn stepped_pairs(
        &mut self,
        st: &mut Stepped,
        engine: &impl Engine,
        events: &mut Vec<PairEvent>,
    ) {
        if st.boxes.len() < self.proxies.len() {
            st.boxes.resize(self.proxies.len(), None);
        }
        let dt = self.clock.dt;
        for (i, p) in self.proxies.iter().enumerate() {
            let Some(p) = p else {
                st.boxes[i] = None;
                continue;
            };
            if st.boxes[i].is_some() {
                continue;
            }
            st.boxes[i] = Some(match p.hold {
                Hold::Fixed { min, max } => (min, max),
                Hold::Moving { body, radius, .. } => {
                    let v = engine.body(body).map_or(Vec3::ZERO, |rb| rb.velocity);
                    let (lo, hi) = engine.bounds(p.key).unwrap_or_else(|| {
                        let c = self
                            .motions
                            .get(body)
                            .map_or(Vec3::ZERO, |m| m.plan.position_at(self.clock.pos));
                        (c - Vec3::splat(radius), c + Vec3::splat(radius))
                    });
                    let d = v * dt;
                    (lo + d.min(Vec3::ZERO), hi + d.max(Vec3::ZERO))
                }
            });
        }
        let boxes = &st.boxes;
        st.grid.pairs(
            boxes
                .iter()
                .enumerate()
                .filter_map(|(i, b)| Some((i as u32, (*b)?))),
            &mut st.found,
        );
        // The difference, in order: deletes of pairs gone, adds of pairs new.
        let (old, new) = (&st.reported, &st.found);
        let (mut i, mut j) = (0, 0);
        let (mut adds, mut deletes) = (Vec::new(), Vec::new());
        while i < old.len() || j < new.len() {
            match (old.get(i), new.get(j)) {
                (Some(a), Some(b)) if a == b => {
                    i += 1;
                    j += 1;
                }
                (Some(a), b) if b.is_none_or(|b| a < b) => {
                    deletes.push(*a);
                    i += 1;
                }
                (_, Some(b)) => {
                    adds.push(*b);
                    j += 1;
                }
                _ => break,
            }
        }
        std::mem::swap(&mut st.reported, &mut st.found);
        for (a, b) in adds {
            self.out_event(a, b, true, events);
        }
        for (a, b) in deletes {
            self.out_event(a, b, false, events);
        }
    }

    /// Hands pair `(a, b)` of collider indices to the engine: added or deleted.
    pub(super) fn out_event(&mut self, a: u32, b: u32, add: bool, events: &mut Vec<PairEvent>) {
        let (Some(pa), Some(pb)) = (self.proxies[a as usize], self.proxies[b as usize]) else {
            return;
        };
        if add {
            self.stats.added += 1;
            self.step.added += 1;
            events.push(PairEvent::Add(pa.key, pb.key));
        } else {
            self.stats.deleted += 1;
            self.step.deleted += 1;
            events.push(PairEvent::Delete(pa.key, pb.key));
        }
    }
}
