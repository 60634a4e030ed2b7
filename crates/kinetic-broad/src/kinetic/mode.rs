//! Kinetic or stepped: the broad phase follows what the world's bodies do (the design and
//! its figures: `docs/structures.md`).
//!
//! Plans pay where they hold. In a pile, a settling rain or a dense gas nearly every body is
//! pushed off its plan every few steps, and each re-plan costs the kinetic structure far more
//! than filing the body's box again. There the broad phase *steps*: the kinetic structure is
//! dropped and each position update files every collider's box, swept over the coming step,
//! into the stepped grid ([`crate::stepped`]) and hands over the pairs whose boxes meet
//! within the step. A box's sweep is its own last two moves extrapolated (`2 d1 - d0`);
//! between pricing windows an update reads only the moved colliders' boxes.
//!
//! The choice is made from counts, never from clocks, so a run is the same every time:
//!
//! - kinetic, a step costs its re-plans and events, [`OP_COST`] each, averaged over about
//!   [`SMOOTHING`] steps;
//! - stepped, a step costs [`BOX_COST`] per collider held, or, while the resting boxes stay
//!   filed ([`Resting`]) or fat boxes hold the pairs ([`FatPairs`]), the work they count in
//!   the same units; a kinetic world keeps the price its last stepped stretch measured;
//! - stepped, the bodies' plans are kept on three position updates in [`PRICE_EVERY`]
//!   ([`FAT_PRICE_SPACING`] times as many while fat boxes hold the pairs) (no
//!   structure to tell), and the third prices a kinetic step: the last kinetic stretch's
//!   cost scaled by its re-plans to the re-plans now; before any kinetic stretch, an event
//!   for each re-plan and the loose grid's re-anchors for the boxes' moves.
//!
//! Every world starts stepped: its first step files the boxes, far less than building the
//! kinetic structure (a sleeping world's resting boxes then stay filed). The world steps
//! once the kinetic cost is above the stepped one, and goes back after [`CALM_COUNTS`]
//! prices running below [`BACK`] of it (more after kinetic stretches that did not last), at
//! least [`DWELL`] steps after the last switch, and once what kinetic steps would have saved
//! since the last switch pays for building the structure ([`OP_COST`] a collider): rent or
//! buy, so a long calm run goes kinetic and a short one never pays for a build. A world
//! steps only when the broad phase picked the structure itself: a caller's choice
//! ([`BroadPhaseCore::with_loose_grid`]) stays kinetic.
//!
//! An engine that keeps enlarged boxes of its own ([`Engine::enlarged`], avian's) steps for
//! good, on those boxes: it moves a box only when its collider leaves it and lists those
//! colliders, so a stepped call costs in proportion to the boxes it moved, while a kinetic
//! step reads every awake body to hold it to its plan. Its pairs are then exactly those its
//! own broad phase would find. Where the engine also keeps an index of those boxes for its
//! own queries ([`Engine::enlarged_near`], avian's collider trees), each moved box is looked
//! up there rather than in a grid of the broad phase's own.
//!
//! The pairs the engine has are carried over at a switch: to the stepped grid's, with adds
//! and deletes for the difference, and back to the kinetic book, which adopts those it holds
//! and deletes the others.

use super::{BroadPhaseCore, Proxy, REGION_MARGIN, REGION_STEPS};
use crate::Aabb;
use crate::stepped::{
    EnlargedPairs, FatPairs, Resting, meet_ahead, sorted_difference, typical_move,
};
use crate::{Bound, Engine, Key, PairEvent};
use kinetic_core::{Real, Vec3};
use kinetic_flight::LOOSE_TRAVEL;

#[path = "tracked.rs"]
mod tracked;

/// The kinetic cost of a re-plan or an event, in units of one collider filed by the stepped
/// grid (measured on the rapier bench's pile, rain and gas at 1e3 and 1e4 bodies).
const OP_COST: Real = 40.0;
/// The stepped cost of a collider.
const BOX_COST: Real = 1.0;
/// Costs are averaged over about this many steps.
const SMOOTHING: Real = 2.0;
/// A stepped world goes back to kinetic once a kinetic step is priced below this share of a
/// stepped one.
const BACK: Real = 0.5;
/// A stepped world passes over its bodies' plans on three position updates running in
/// this many (in 12, those passes cost piles, rains and gases of 100 to 1e3 bodies about 4%
/// of their broad phase)...
const PRICE_EVERY: u64 = 24;
/// ... or this many times as many while fat boxes hold its pairs: a world flying apart,
/// where reading every body's state is most of a step's work and plans would seldom be
/// cheaper.
const FAT_PRICE_SPACING: u64 = 4;
/// A stepped world goes back to kinetic after this many counts running priced it cheaper...
const CALM_COUNTS: u32 = 2;
/// ... or up to this many, after kinetic stretches that did not last...
const MOST_CALM_COUNTS: u32 = 16;
/// ... this many steps.
const SHORT_STRETCH: u64 = 120;
/// The typical move is taken again on one position update in this many (it changes
/// little from step to step, and any frame that moves steadily sweeps the boxes right).
const TYPICAL_EVERY: u64 = 4;
/// Steps between two switches at least.
const DWELL: u64 = 8;

/// The stepped mode's state.
#[derive(Debug, Default)]
pub(super) struct Stepped {
    grid: FatPairs,
    /// Per collider index, its box now and how far it moves over the coming step (`None`:
    /// to be worked out).
    boxes: Vec<Option<(Aabb, Vec3)>>,
    /// The pairs the engine has, sorted (on the engine's enlarged boxes: in `enlarged`).
    reported: Vec<(u32, u32)>,
    /// On the engine's enlarged boxes ([`Engine::enlarged`]): their pairs, kept per box.
    enlarged: Option<Box<EnlargedPairs>>,
    /// On the engine's enlarged boxes: the colliders whose boxes changed in this call.
    touched: Vec<u32>,
    /// This call's pairs.
    found: Vec<(u32, u32)>,
    /// Per collider index, its box's centre at the last call and how far it had moved
    /// since the call before, if seen.
    history: Vec<Option<(Vec3, Option<Vec3>)>>,
    /// Position updates since the world stepped.
    updates: u64,
    /// Colliders whose boxes are to be worked out from their bodies (new ones, those
    /// without a history), or (`all`) every collider.
    pub(super) pending: Vec<u32>,
    all: bool,
    /// The typical move of the boxes, taken again on one update in [`TYPICAL_EVERY`], and
    /// scratch for it.
    typical: Vec3,
    sample: Vec<Real>,
    /// The colliders moved in this position update, a bit per index, and scratch for their
    /// keys.
    marked: Vec<u64>,
    marked_keys: Vec<Key>,
    /// The pairs gone and new in this call.
    gone: Vec<(u32, u32)>,
    new: Vec<(u32, u32)>,
    /// The loose grid's re-anchors an update would take for the boxes' moves, as last
    /// worked out (on the updates that count re-plans).
    anchors: Real,
    /// The boxes at rest, filed between calls; per collider index, the last call in which
    /// its box changed; and the calls, counted from 1.
    resting: Resting,
    changed: Vec<u64>,
    calls: u64,
    /// The last call in which some box changed, and whether this call's pairs were those
    /// of the last (no box changed in it or in the one before: nothing to look at).
    last_change: u64,
    quiet: bool,
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
    /// While stepped, what kinetic steps would have saved since the last switch (a step's
    /// stepped cost above its kinetic price, summed): the world goes kinetic only once this
    /// pays for building the structure, [`OP_COST`] a collider.
    saved: Real,
    /// Counts running that priced a kinetic step below [`BACK`] of a stepped one, and how
    /// many it takes to go back: [`CALM_COUNTS`], doubled (up to [`MOST_CALM_COUNTS`]) each
    /// time a kinetic stretch ends within [`SHORT_STRETCH`] steps.
    calm: u32,
    need: u32,
}

impl Stepped {
    /// A stepped world's state: on the engine's enlarged boxes (`engine_boxes`), or on
    /// boxes swept over each step.
    pub(super) fn new(engine_boxes: bool) -> Stepped {
        Stepped {
            enlarged: engine_boxes.then(Default::default),
            ..Stepped::default()
        }
    }

    /// Whether this position update passes over the moved bodies' plans (three running
    /// every [`PRICE_EVERY`], the third counting the re-plans) rather than only over the
    /// moved colliders' boxes; never on the engine's enlarged boxes (the world steps for
    /// good).
    pub(super) fn full(&self) -> bool {
        self.enlarged.is_none() && self.updates % self.price_every() < 3
    }

    /// Whether it steps on the engine's enlarged boxes.
    pub(super) fn on_engine_boxes(&self) -> bool {
        self.enlarged.is_some()
    }

    /// The pairs the engine has, sorted.
    pub(super) fn pairs(&self) -> std::borrow::Cow<'_, [(u32, u32)]> {
        match &self.enlarged {
            Some(e) => e.sorted().into(),
            None => (&self.reported[..]).into(),
        }
    }

    /// How many pairs the engine has.
    pub(super) fn pair_count(&self) -> usize {
        self.enlarged
            .as_ref()
            .map_or(self.reported.len(), |e| e.count())
    }

    /// The colliders paired with collider `i`: kept per box on the engine's enlarged boxes,
    /// else read off the sorted pairs (a pass over them all).
    pub(super) fn partners_of(&self, i: u32) -> impl Iterator<Item = u32> + '_ {
        let (kept, sorted) = match &self.enlarged {
            Some(e) => (e.partners(i), &[][..]),
            None => (&[][..], &self.reported[..]),
        };
        let other = move |&(a, b): &(u32, u32)| {
            if a == i {
                Some(b)
            } else if b == i {
                Some(a)
            } else {
                None
            }
        };
        kept.iter().copied().chain(sorted.iter().filter_map(other))
    }

    /// Outside the engine's enlarged boxes, the box collider `i` is kept in, if known.
    pub(super) fn kept_box(&self, i: u32) -> Option<Aabb> {
        let kept = self.boxes.get(i as usize).copied().flatten();
        kept.filter(|_| self.enlarged.is_none()).map(|(b, _)| b)
    }

    /// Whether the engine has the pair of colliders `a` and `b`.
    pub(super) fn holds(&self, a: u32, b: u32) -> bool {
        match &self.enlarged {
            Some(e) => e.has(a, b),
            None => self.reported.binary_search(&(a.min(b), a.max(b))).is_ok(),
        }
    }

    /// The pairs the engine has, taken over by the kinetic book at a switch.
    pub(super) fn into_pairs(self) -> Vec<(u32, u32)> {
        match &self.enlarged {
            Some(e) => e.sorted(),
            None => self.reported,
        }
    }

    /// Position updates from one pricing to the next: [`PRICE_EVERY`], spaced by
    /// [`FAT_PRICE_SPACING`] while fat boxes hold the pairs (the spacings' windows line up).
    fn price_every(&self) -> u64 {
        if self.grid.holds() {
            PRICE_EVERY * FAT_PRICE_SPACING
        } else {
            PRICE_EVERY
        }
    }

    /// Times its fat boxes were filed afresh, and boxes re-fattened on their own.
    pub(super) fn fat_counts(&self) -> (u64, u64) {
        (self.grid.rebuilds, self.grid.refattened)
    }

    /// The work of a call, averaged, in boxes filed, where it keeps some boxes filed
    /// between calls (resting boxes, or fat boxes holding the pairs; none in a quiet call);
    /// `None`: every box is filed each call.
    fn work(&self) -> Option<Real> {
        if self.quiet {
            return Some(0.0);
        }
        self.resting.work().or_else(|| self.grid.work())
    }

    /// Whether the last call found nothing to do.
    #[cfg(test)]
    pub(super) fn quiet(&self) -> bool {
        self.quiet
    }

    /// Times the resting boxes (or the enlarged ones) were filed.
    pub(super) fn rest_filings(&self) -> u64 {
        self.resting.filings + self.enlarged.as_ref().map_or(0, |e| e.filings)
    }

    /// Enlarged boxes looked up in the engine's own index.
    pub(super) fn engine_lookups(&self) -> u64 {
        self.enlarged.as_ref().map_or(0, |e| e.engine_lookups)
    }

    /// Whether this position update's re-plans price a kinetic step.
    fn counting(&self) -> bool {
        self.updates % self.price_every() == 2
    }

    /// Forgets collider `i`'s box and (`silent`) its pairs: the engine drops a removed
    /// collider's pairs itself.
    pub(super) fn forget(&mut self, i: u32, silent: bool) {
        self.changed_now(i as usize);
        if let Some(b) = self.boxes.get_mut(i as usize) {
            *b = None;
        }
        if let Some(h) = self.history.get_mut(i as usize) {
            *h = None;
        }
        if silent {
            match self.enlarged.as_mut() {
                Some(e) => e.forget(i),
                None => self.reported.retain(|&(a, b)| a != i && b != i),
            }
        }
    }
}

impl BroadPhaseCore {
    /// Whether the world may step: the structure is the broad phase's own pick (made once
    /// the first colliders come).
    pub(super) fn may_step(&self) -> bool {
        !self.choice_given && self.loose_grid.is_some()
    }

    /// Whether the world is stepped now.
    pub(super) fn is_stepped(&self) -> bool {
        self.stepped.is_some()
    }

    /// At the end of a step: prices it both ways, and calls for a switch if the other way
    /// is cheaper.
    pub(super) fn weigh(&mut self) {
        if !self.may_step() || (self.engine_boxes && self.is_stepped()) {
            return;
        }
        let held = self.held as Real;
        let replans = self.step.replans as Real;
        // A stepped world counts its re-plans only now and then.
        let counted = self.stepped.as_ref().is_none_or(Stepped::counting);
        if let Some(st) = self.stepped.as_mut() {
            st.updates += 1;
        }
        let m = &mut self.meter;
        // A count now and then is taken as it is; a kinetic step's own costs are averaged.
        let w = if self.stepped.is_some() {
            1.0
        } else {
            1.0 / SMOOTHING
        };
        let kinetic = if !counted {
            m.kinetic
        } else if self.stepped.is_some() {
            if m.last_cost > 0.0 {
                m.last_cost * (replans + 1.0) / (m.last_replans + 1.0)
            } else {
                // No kinetic stretch yet: an event for each re-plan, and the re-anchors of
                // the bodies' flight.
                let anchors = self.stepped.as_ref().map_or(0.0, |st| st.anchors);
                OP_COST * (2.0 * replans + anchors)
            }
        } else {
            OP_COST * (self.step.replans + self.step.events) as Real
        };
        m.kinetic += w * (kinetic - m.kinetic);
        match self.stepped.as_ref() {
            Some(st) => {
                let all = BOX_COST * held;
                m.stepped = st.work().map_or(all, |work| work.min(all));
            }
            // A kinetic world is priced against its last stepped stretch, as measured
            // there (every world starts stepped).
            None if m.stepped > 0.0 => {}
            None => m.stepped = BOX_COST * held,
        }
        if counted {
            m.replans += w * (replans - m.replans);
        }
        let steps = self.stats.steps;
        if self.stepped.is_some() {
            m.saved += (m.stepped - m.kinetic).max(0.0);
            if counted {
                m.calm = if m.kinetic < BACK * m.stepped {
                    m.calm + 1
                } else {
                    0
                };
            }
        }
        let need = m.need.max(CALM_COUNTS);
        if steps < m.switched + DWELL {
            return;
        }
        if self.stepped.is_none() && m.kinetic > m.stepped {
            // A kinetic stretch that did not last: the next must wait for longer calm.
            m.need = if steps < m.switched + SHORT_STRETCH {
                (need * 2).min(MOST_CALM_COUNTS)
            } else {
                CALM_COUNTS
            };
            m.last_cost = m.kinetic;
            m.last_replans = m.replans;
            m.saved = 0.0;
            m.switched = steps;
            m.switch = true;
        } else if self.stepped.is_some() && m.calm >= need && m.saved >= OP_COST * held {
            // Rent or buy: a build is paid for by what the stepped steps since the last
            // switch cost above kinetic ones, so a run pays at most about twice the cheaper.
            m.calm = 0;
            m.saved = 0.0;
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

    /// Drops the kinetic structure; this call's stepped pairs take over from the engine's
    /// (the stepped world keeps them from here, sorted).
    fn go_stepped(&mut self) {
        let had = std::mem::take(&mut self.handed).into_pairs();
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
            all: true,
            ..Stepped::default()
        });
    }

    /// Builds the kinetic structure again from the proxies and their plans, at the positions'
    /// time; the book adopts the engine's pairs once this call's events have run
    /// ([`BroadPhaseCore::adopt`]).
    fn go_kinetic(&mut self, engine: &impl Engine) {
        let st = self.stepped.take().expect("stepped");
        let (filings, refattened) = st.fat_counts();
        self.stats.fat_filings += filings;
        self.stats.refattened += refattened;
        self.stats.rest_filings += st.rest_filings();
        self.stats.engine_lookups += st.engine_lookups();
        let had = st.into_pairs();
        let proxies = &self.proxies;
        let key = |i: u32| proxies.get(i as usize).copied().flatten().map(|p| p.key);
        self.handed = super::handed::Handed::linked(&had, key);
        self.adopting = Some(had);
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
            st.history.resize(self.proxies.len(), None);
        }
        st.changed.resize(st.boxes.len(), 0);
        let dt = self.clock.dt;
        let pending = if std::mem::take(&mut st.all) {
            st.pending.clear();
            (0..self.proxies.len() as u32).collect()
        } else {
            std::mem::take(&mut st.pending)
        };
        for &i in &pending {
            let i = i as usize;
            st.changed_now(i);
            let Some(p) = self.proxies.get(i).copied().flatten() else {
                st.boxes[i] = None;
                st.history[i] = None;
                continue;
            };
            if st.boxes[i].is_some() {
                continue;
            }
            st.boxes[i] = Some(match p.hold {
                Bound::Fixed { min, max } => (Aabb::new(min, max), Vec3::ZERO),
                Bound::Moving { body, radius, .. } => {
                    if let Some(b) = engine.enlarged(p.key) {
                        st.history[i] = Some((b.centre(), None));
                        st.boxes[i] = Some((b, Vec3::ZERO));
                        continue;
                    }
                    let rb = engine.body(body);
                    let v = rb.map_or(Vec3::ZERO, |rb| rb.velocity);
                    let m = self.motions.get(body);
                    // An engine that gives no boxes: the ball of the hold about the body's
                    // centre now (a stepped world keeps its plans only now and then).
                    let b = engine.bounds(p.key).unwrap_or_else(|| {
                        let c = rb.map_or_else(
                            || m.map_or(Vec3::ZERO, |m| m.plan.position_at(self.clock.pos)),
                            |rb| rb.centre,
                        );
                        Aabb::about(c, Vec3::splat(radius))
                    });
                    // Where a semi-implicit Euler step takes it under the acceleration it
                    // has shown.
                    let a = m.map_or(Vec3::ZERO, |m| m.steady_a);
                    st.history[i] = Some((b.centre(), None));
                    (b, (v + a * dt) * dt)
                }
            });
        }
        st.pending = pending;
        st.pending.clear();
        if st.counting() {
            st.anchors = anchors(&st.boxes);
        }
        st.calls += 1;
        if let Some(mut enlarged) = st.enlarged.take() {
            // The engine's enlarged boxes: the pairs of those it moved looked at again.
            let boxes = &st.boxes;
            let now = |i: u32| boxes.get(i as usize).copied().flatten().map(|(b, _)| b);
            let proxies = &self.proxies;
            let near = |i: u32, b: &Aabb, out: &mut Vec<u32>| {
                let key = proxies.get(i as usize).copied().flatten().map(|p| p.key);
                key.is_some_and(|k| engine.enlarged_near(k, b, out))
            };
            st.new.clear();
            st.gone.clear();
            enlarged.update(&st.touched, &now, &near, &mut st.new, &mut st.gone);
            st.enlarged = Some(enlarged);
            st.touched.clear();
            for &(a, b) in &st.new {
                self.out_event(a, b, true, events);
            }
            for &(a, b) in &st.gone {
                self.out_event(a, b, false, events);
            }
            return;
        }
        // No box changed in this call or the last: every box is still, as in the last
        // call, whose pairs stand (a sleeping world costs nothing a step).
        st.quiet = st.calls > 1 && st.last_change + 1 < st.calls;
        if st.quiet {
            return;
        }
        // Where many boxes rest, only those that moved are filed: a resting box moves
        // nothing over the step.
        let (boxes, changed, call) = (&st.boxes, &st.changed, st.calls);
        let still = |i: u32| {
            boxes[i as usize].map(|(b, d)| {
                (
                    b,
                    if changed[i as usize] < call {
                        Vec3::ZERO
                    } else {
                        d
                    },
                )
            })
        };
        // How far ahead the engine looks for the body a moving box rides.
        let proxies = &self.proxies;
        let ahead = |i: u32, d: Vec3| match proxies.get(i as usize).copied().flatten() {
            Some(Proxy {
                hold: Bound::Moving { body, .. },
                ..
            }) if d != Vec3::ZERO => engine.ahead(body, d),
            _ => d,
        };
        let keep_still = |a: u32, b: u32| match (still(a), still(b)) {
            (Some(x), Some(y)) => meet_ahead((a, x), (b, y), &ahead),
            _ => true,
        };
        let split = st
            .resting
            .pairs(boxes, changed, call, &keep_still, &mut st.found);
        if !split {
            Self::plain_pairs(st, &ahead);
        }
        self.hand_difference(st, events);
    }

    /// The stepped pairs of every box, from the fat boxes or the grid, each box looking as
    /// far ahead as `ahead` says ([`meet_ahead`]).
    fn plain_pairs(st: &mut Stepped, ahead: &impl Fn(u32, Vec3) -> Vec3) {
        // Of the pairs whose swept boxes overlap, those whose boxes meet as they move: two
        // bodies falling side by side are not a pair.
        // Two boxes meet as they move in any frame that moves steadily: the boxes are swept
        // in the frame of the typical box (a falling heap's boxes then hardly sweep at all),
        // or while fat boxes hold the pairs, the one they were filed in.
        let frame = match st.grid.frame() {
            Some(frame) => frame,
            None => {
                if st.updates.is_multiple_of(TYPICAL_EVERY) {
                    st.typical = typical_move(&st.boxes, &mut st.sample);
                }
                st.typical
            }
        };
        let boxes = &st.boxes;
        let keep = |a: u32, b: u32| match (boxes[a as usize], boxes[b as usize]) {
            (Some(x), Some(y)) => meet_ahead((a, x), (b, y), ahead),
            _ => true,
        };
        st.grid.pairs(boxes, frame, &keep, &mut st.found);
    }

    /// Hands the engine the difference between the pairs it has and this call's.
    fn hand_difference(&mut self, st: &mut Stepped, events: &mut Vec<PairEvent>) {
        // The difference, in order: deletes of pairs gone, adds of pairs new.
        let (adds, deletes) = (&mut st.new, &mut st.gone);
        adds.clear();
        deletes.clear();
        sorted_difference(
            &st.reported,
            &st.found,
            |p| deletes.push(p),
            |p| adds.push(p),
        );
        std::mem::swap(&mut st.reported, &mut st.found);
        for &(a, b) in &st.new {
            self.out_event(a, b, true, events);
        }
        for &(a, b) in &st.gone {
            self.out_event(a, b, false, events);
        }
    }

    /// Hands pair `(a, b)` of collider indices to the engine: added or deleted.
    pub(super) fn out_event(&mut self, a: u32, b: u32, add: bool, events: &mut Vec<PairEvent>) {
        let (Some(pa), Some(pb)) = (self.proxies[a as usize], self.proxies[b as usize]) else {
            return;
        };
        events.push(if add {
            PairEvent::Add(pa.key, pb.key)
        } else {
            PairEvent::Delete(pa.key, pb.key)
        });
    }
}

/// The re-anchors a step of the loose grid would take for boxes moving as `boxes` do. A
/// body's region covers its flight over [`LOOSE_TRAVEL`] of its widths, but at least a step
/// and at most [`REGION_STEPS`], and [`REGION_MARGIN`] of its width on every side: a box `w`
/// wide moving `d` a step covers `h = clamp(2 w / |d|, 1, REGION_STEPS)` steps and is
/// re-anchored every `h + 0.1 w / |d|` steps (a body at rest, never).
fn anchors(boxes: &[Option<(Aabb, Vec3)>]) -> Real {
    boxes
        .iter()
        .flatten()
        .map(|(Aabb { min: lo, max: hi }, d)| {
            let (d, w) = (d.length(), (*hi - *lo).max_element());
            let h = (LOOSE_TRAVEL * w / d).clamp(1.0, REGION_STEPS);
            let a = d / (h * d + REGION_MARGIN * w);
            if a.is_finite() { a } else { 0.0 }
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit(at: Vec3) -> Aabb {
        Aabb::new(at, at + Vec3::ONE)
    }

    #[test]
    fn a_box_is_re_anchored_by_how_far_it_moves_against_its_region() {
        let b = (unit(Vec3::ZERO), Vec3::ZERO);
        assert_eq!(anchors(&[Some(b), None]), 0.0);
        // Slow, moving its margin's worth a step: its region covers REGION_STEPS steps, so
        // once in REGION_STEPS + 1 steps.
        let d = Vec3::new(0.0, REGION_MARGIN, 0.0);
        let once = anchors(&[Some((unit(Vec3::ZERO), d))]);
        assert!((once - 1.0 / (REGION_STEPS + 1.0)).abs() < 1e-12, "{once}");
        // Its width a step: the region covers its travel of LOOSE_TRAVEL widths.
        let width = anchors(&[Some((unit(Vec3::ZERO), Vec3::X))]);
        let want = 1.0 / (LOOSE_TRAVEL + REGION_MARGIN);
        assert!((width - want).abs() < 1e-12, "{width}");
        // Fast: a region covers a step at least, so about once a step each; two boxes,
        // twice one.
        let fast = anchors(&[Some((unit(Vec3::ZERO), d * 1e6)); 2]);
        assert!(fast < 2.0 && fast > 1.99, "{fast}");
    }
}
