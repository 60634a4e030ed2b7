//! Pair certificates: one disjointness certificate per candidate pair, with the contact state
//! machine of the scene format.
//!
//! Two balls: a `ball_ball_disjoint` certificate. It caches the roots of its polynomial from
//! the moment it was made and walks them in order (CGAL style): the next event after a begin
//! is found among the same roots, so a root that rounding put a hair early or late never fires
//! twice.
//!
//! A pair with another shape: a [`ShapeWalk`]. The outer balls' polynomial walk gives the
//! windows in which the shapes can touch at all; inside a window the contact search of
//! [`crate::geometry`] finds the flips.

use super::{ContactEvent, ContactKind, ObjectId, Response, Simulator, WorldKind};
use crate::certificates::ball_ball_gap;
use crate::geometry::{Found, Mover, search};
use crate::math::Real;
use crate::pair_key::pair_key;
use crate::poly::Poly;
use crate::roots::{Root, Roots, roots_after_zero};
use crate::structure::{CandidateStructure, PairChange};
use rustc_hash::FxHashMap;

/// Where the next contact event of a polynomial gap comes from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// At the moment the walk was made.
    Now,
    /// A root of the gap `f`.
    F,
    /// A root of its derivative `f'` (overlapping objects start to approach).
    G,
}

/// What the next event of a walk is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Due {
    /// Contact begins (no response) or a collision happens (elastic).
    Begin,
    /// Contact ends.
    End,
    /// The objects touch at one instant without overlapping: begin and end together.
    Graze,
    /// Nothing to report: the certificate is renewed (a shape pair's search window moves on).
    Recheck,
}

/// The cached roots of a gap polynomial `f` (and, for the elastic response, of `f'`) made at
/// time `made`, and where the walk through them stands.
#[derive(Clone, Copy, Debug)]
pub struct Walk {
    made: Real,
    f: Roots,
    g: Roots,
    f_next: u8,
    g_next: u8,
    /// `f < 0` (overlapping) at the walk's position.
    inside: bool,
    /// No event is due before this (the time the walk was made for).
    floor: Real,
    /// The next event, if any: `(time, source, kind)`.
    pub due: Option<(Real, Source, Due)>,
}

impl Walk {
    /// The contact walk of gap `f` (local time around `made`, at or before `now`) for an
    /// object pair in state `touching` at `now` under no response: begins, ends and grazes
    /// after `now`.
    pub fn contact(f: &Poly, made: Real, now: Real, touching: bool) -> Walk {
        let mut w = Walk::empty(made, roots_after_zero(f), Roots::default(), touching);
        w.skip_to(now);
        w.advance_contact();
        w
    }

    /// The collision walk of gap `f` (local time around `made`) under the elastic response:
    /// the first time after `now` at which `f <= 0` and `f' < 0` (touching and approaching);
    /// grazes as [`Due::Graze`]. `f_now` is the same gap around `now`, for the state now.
    pub fn elastic(f: &Poly, made: Real, now: Real, f_now: &Poly) -> Walk {
        let g = f.derivative();
        let inside = f_now.sign_just_after_zero() < 0;
        let mut w = Walk::empty(made, roots_after_zero(f), roots_after_zero(&g), inside);
        w.skip_to(now);
        if (inside || f_now.c[0] == 0.0) && f_now.derivative().sign_just_after_zero() < 0 {
            w.due = Some((now, Source::Now, Due::Begin));
        } else {
            w.advance_elastic();
        }
        w
    }

    /// Skips the roots before `now` (the state now is known). Roots a hair before now (the
    /// roots come from the gap around `made`, the state from the gap around `now`, and the
    /// two round differently) are kept and fall due now if they contradict the state: a
    /// contact that begins as a structure adds its pair is not lost to rounding.
    fn skip_to(&mut self, now: Real) {
        self.floor = now;
        let before = now - 1e-9 * now.abs().max(1.0);
        let made = self.made;
        let early = |r: Root| made + r.tau < before;
        while self.f.get(self.f_next as usize).is_some_and(early) {
            self.f_next += 1;
        }
        while self.g.get(self.g_next as usize).is_some_and(early) {
            self.g_next += 1;
        }
    }

    fn empty(made: Real, f: Roots, g: Roots, inside: bool) -> Walk {
        Walk {
            made,
            f,
            g,
            f_next: 0,
            g_next: 0,
            inside,
            floor: made,
            due: None,
        }
    }

    /// Steps past the root that is due (after its event was processed) and finds the next.
    pub fn consume(&mut self, response: Response) {
        let Some((_, source, kind)) = self.due else {
            return;
        };
        match source {
            Source::Now => {}
            Source::F => {
                self.f_next += 1;
                if kind != Due::Graze {
                    self.inside = kind == Due::Begin;
                }
            }
            Source::G => self.g_next += 1,
        }
        match response {
            Response::None => self.advance_contact(),
            Response::Elastic => self.advance_elastic(),
        }
    }

    fn at(&self, r: Root, source: Source, kind: Due) -> Option<(Real, Source, Due)> {
        Some(((self.made + r.tau).max(self.floor), source, kind))
    }

    fn advance_contact(&mut self) {
        self.due = None;
        while let Some(r) = self.f.get(self.f_next as usize) {
            let found = match (self.inside, r.before, r.after) {
                (false, 1, -1) => Due::Begin,
                (false, 1, 1) => Due::Graze,
                (true, -1, 1) => Due::End,
                _ => {
                    self.f_next += 1;
                    continue;
                }
            };
            self.due = self.at(r, Source::F, found);
            return;
        }
    }

    fn advance_elastic(&mut self) {
        self.due = None;
        loop {
            let rf = self.f.get(self.f_next as usize);
            let rg = self.g.get(self.g_next as usize);
            let (f_first, r) = match (rf, rg) {
                (Some(f), Some(g)) if f.tau <= g.tau => (true, f),
                (_, Some(g)) => (false, g),
                (Some(f), None) => (true, f),
                (None, None) => return,
            };
            if f_first {
                match (self.inside, r.before, r.after) {
                    (false, 1, -1) => return self.due = self.at(r, Source::F, Due::Begin),
                    (false, 1, 1) => return self.due = self.at(r, Source::F, Due::Graze),
                    (true, _, 1) => self.inside = false,
                    _ => {}
                }
                self.f_next += 1;
            } else {
                if self.inside && r.after < 0 {
                    return self.due = self.at(r, Source::G, Due::Begin);
                }
                self.g_next += 1;
            }
        }
    }
}

/// The certificate of one candidate pair.
#[derive(Clone, Copy, Debug)]
pub struct PairCertificate {
    /// The object with the lower id.
    pub a: u32,
    /// The object with the higher id.
    pub b: u32,
    /// How many reasons the structure has to keep the pair.
    refs: u32,
    /// In contact (no response only).
    pub touching: bool,
    pub(crate) walk: PairWalk,
}

impl PairCertificate {
    /// When this certificate fails next (+infinity for never).
    pub fn due_time(&self) -> Real {
        self.walk.due().map_or(Real::INFINITY, |d| d.0)
    }
}

/// How a pair's next event is found: polynomial roots (two balls) or a shape walk.
#[derive(Clone, Copy, Debug)]
pub(crate) enum PairWalk {
    Balls(Walk),
    Shapes(ShapeWalk),
}

impl PairWalk {
    /// The next event: its time and what it is.
    pub(crate) fn due(&self) -> Option<(Real, Due)> {
        match self {
            PairWalk::Balls(w) => w.due.map(|(t, _, d)| (t, d)),
            PairWalk::Shapes(w) => w.due(),
        }
    }
}

/// Why a shape walk stops next.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Stop {
    /// The shapes' state flips (they start or stop to overlap).
    Flip,
    /// The outer balls start to overlap: a search window opens.
    Opens,
    /// The outer balls come apart: the window closes.
    Closes,
    /// The search used its step budget: it goes on from here.
    Budget,
}

/// The walk of a pair that holds a shape other than a ball.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ShapeWalk {
    /// The outer balls' contact walk: its begins and ends open and close search windows.
    outer: Walk,
    /// A window is open (the outer balls overlap) at `from`.
    open: bool,
    /// The shapes overlap or touch at `from`.
    inside: bool,
    /// Where the next search starts.
    from: Real,
    stop: Option<(Real, Stop)>,
}

impl ShapeWalk {
    /// The walk from `now`, with the shapes in state `inside` (overlapping or touching) now.
    pub(crate) fn new(m: &Mover, outer: &Poly, now: Real, inside: bool) -> ShapeWalk {
        let open = outer.c[0] < 0.0 || (outer.c[0] == 0.0 && outer.sign_just_after_zero() <= 0);
        let mut w = ShapeWalk {
            outer: Walk::contact(outer, now, now, open),
            open,
            inside,
            from: now,
            stop: None,
        };
        w.plan(m);
        w
    }

    fn due(&self) -> Option<(Real, Due)> {
        let (t, stop) = self.stop?;
        let due = match (stop, self.inside) {
            (Stop::Flip, false) => Due::Begin,
            // Rounding may leave the search short of the end of an overlap that the outer
            // balls prove over: the contact ends when they come apart at the latest.
            (Stop::Flip | Stop::Closes, true) => Due::End,
            _ => Due::Recheck,
        };
        Some((t, due))
    }

    /// Finds the next stop from `from`.
    fn plan(&mut self, m: &Mover) {
        loop {
            if !self.open {
                self.stop = match self.outer.due {
                    Some((t, _, Due::Begin)) => Some((t, Stop::Opens)),
                    Some((_, _, Due::Graze)) => {
                        // The outer balls only touch: the shapes cannot overlap.
                        self.outer.consume(Response::None);
                        continue;
                    }
                    _ => None,
                };
                return;
            }
            let until = match self.outer.due {
                Some((t, _, Due::End)) => t,
                _ => Real::INFINITY,
            };
            self.stop = match search(m, self.from, until, self.inside) {
                Found::Flip(t) => Some((t, Stop::Flip)),
                Found::Budget(t) => Some((t, Stop::Budget)),
                Found::None if until.is_finite() => Some((until, Stop::Closes)),
                Found::None => None,
            };
            return;
        }
    }

    /// Steps past the stop that was due (its event processed) and finds the next.
    pub(crate) fn consume(&mut self, m: &Mover) {
        let Some((t, stop)) = self.stop else {
            return;
        };
        self.from = t;
        match stop {
            Stop::Flip => self.inside = !self.inside,
            Stop::Budget => {}
            Stop::Opens | Stop::Closes => {
                self.outer.consume(Response::None);
                self.open = stop == Stop::Opens;
                self.inside = false;
            }
        }
        self.plan(m);
    }
}

/// The gap polynomial of two balls (plans and radii) in local time around `t`.
#[inline]
pub fn ball_gap(
    kind: WorldKind,
    pa: &crate::FlightPlan,
    ra: Real,
    pb: &crate::FlightPlan,
    rb: Real,
    t: Real,
) -> Poly {
    let threshold2 = match kind {
        WorldKind::Free => (ra + rb) * (ra + rb),
        WorldKind::Plane => 4.0 * ra * rb,
    };
    ball_ball_gap(
        &pa.local_coefficients(t),
        &pb.local_coefficients(t),
        threshold2,
    )
}

/// The time both current plans began (not after now): a pair's roots are found in its gap
/// around this time, which depends only on the plans, not on when a structure made the pair a
/// candidate, so every structure finds the same roots, bit for bit.
#[inline]
pub fn canonical_base(pa: &crate::FlightPlan, pb: &crate::FlightPlan, now: Real) -> Real {
    pa.t0.max(pb.t0).min(now)
}

/// Candidate pairs by slot, with an index by pair and by object.
#[derive(Debug, Default)]
pub(crate) struct PairTable {
    slots: Vec<Option<PairCertificate>>,
    free: Vec<u32>,
    index: FxHashMap<u64, u32>,
    of_object: Vec<Vec<u32>>,
    live: usize,
}

impl PairTable {
    pub(crate) fn len(&self) -> usize {
        self.live
    }

    pub(crate) fn get(&self, slot: u32) -> &PairCertificate {
        self.slots[slot as usize].as_ref().expect("live slot")
    }

    pub(crate) fn get_mut(&mut self, slot: u32) -> &mut PairCertificate {
        self.slots[slot as usize].as_mut().expect("live slot")
    }

    pub(crate) fn find(&self, a: u32, b: u32) -> Option<u32> {
        self.index.get(&pair_key(a, b)).copied()
    }

    pub(crate) fn slots_of(&self, object: u32) -> Vec<u32> {
        self.of_object
            .get(object as usize)
            .cloned()
            .unwrap_or_default()
    }

    pub(crate) fn iter(&self) -> impl Iterator<Item = (u32, &PairCertificate)> {
        self.slots
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.as_ref().map(|c| (i as u32, c)))
    }

    fn insert(&mut self, cert: PairCertificate) -> u32 {
        let slot = match self.free.pop() {
            Some(s) => s,
            None => {
                self.slots.push(None);
                (self.slots.len() - 1) as u32
            }
        };
        for o in [cert.a, cert.b] {
            if self.of_object.len() <= o as usize {
                self.of_object.resize(o as usize + 1, Vec::new());
            }
            self.of_object[o as usize].push(slot);
        }
        self.index.insert(pair_key(cert.a, cert.b), slot);
        self.slots[slot as usize] = Some(cert);
        self.live += 1;
        slot
    }

    fn remove(&mut self, slot: u32) -> PairCertificate {
        let cert = self.slots[slot as usize].take().expect("live slot");
        for o in [cert.a, cert.b] {
            let list = &mut self.of_object[o as usize];
            if let Some(i) = list.iter().position(|&s| s == slot) {
                list.swap_remove(i);
            }
        }
        self.index.remove(&pair_key(cert.a, cert.b));
        self.free.push(slot);
        self.live -= 1;
        cert
    }
}

impl Simulator {
    /// The gap polynomial of a pair around the current time.
    pub(crate) fn gap(&self, a: u32, b: u32) -> Poly {
        self.gap_at(a, b, self.now)
    }

    /// The gap polynomial in local time around `t`.
    fn gap_at(&self, a: u32, b: u32, t: Real) -> Poly {
        let (pa, pb) = (self.plan_of(a), self.plan_of(b));
        ball_gap(self.kind, &pa, self.radius(a), &pb, self.radius(b), t)
    }

    /// The gap around the time both current plans began (see [`canonical_base`]).
    fn canonical_gap(&self, a: u32, b: u32) -> (Real, Poly) {
        let base = canonical_base(&self.plan_of(a), &self.plan_of(b), self.now);
        (base, self.gap_at(a, b, base))
    }

    pub(crate) fn plan_of(&self, id: u32) -> crate::FlightPlan {
        self.bodies[id as usize].as_ref().expect("live object").plan
    }

    /// Hands every object to `next`, a fresh, empty candidate structure, at the current time,
    /// and returns the structure it replaces. The log does not change: each structure holds
    /// every pair in contact, so a pair both hold keeps its certificate, a pair only `next`
    /// needs gets one (computed from the same canonical gap as it would have had all along),
    /// and a pair only the old structure held goes without an event.
    pub fn replace_structure(
        &mut self,
        mut next: Box<dyn CandidateStructure>,
    ) -> Box<dyn CandidateStructure> {
        let ids: Vec<u32> = (0..self.bodies.len() as u32)
            .filter(|&id| self.bodies[id as usize].is_some())
            .collect();
        let mut changes = std::mem::take(&mut self.changes);
        next.insert_many(&ids, &self.bodies, self.now, &mut changes);
        // The old structure's holds go all at once: every count starts again from the new
        // structure's, and the pairs it does not hold are let go after its pairs are in.
        let held: Vec<u32> = self.pairs.iter().map(|(slot, _)| slot).collect();
        for &slot in &held {
            self.pairs.get_mut(slot).refs = 0;
        }
        self.apply_changes(&mut changes);
        self.changes = changes;
        for slot in held {
            let cert = self.pairs.get(slot);
            if cert.refs == 0 {
                // A structure holds every pair in contact; one it does not is ending now.
                if cert.touching {
                    let (a, b) = (cert.a, cert.b);
                    self.log(a, b, ContactKind::End);
                }
                self.drop_pair(slot);
            }
        }
        std::mem::replace(&mut self.structure, next)
    }

    pub(crate) fn apply_changes(&mut self, changes: &mut Vec<PairChange>) {
        for ch in changes.drain(..) {
            let (a, b) = (ch.a.min(ch.b), ch.a.max(ch.b));
            match self.pairs.find(a, b) {
                Some(slot) => {
                    let cert = self.pairs.get_mut(slot);
                    cert.refs = cert.refs.saturating_add_signed(ch.delta);
                    if cert.refs == 0 {
                        // A structure lets a touching pair go only at the instant its contact
                        // ends (a box and the contact disk meet on the box's edge), when
                        // rounding put the structure's event first: the contact ends now.
                        if cert.touching {
                            let (a, b) = (cert.a, cert.b);
                            self.log(a, b, ContactKind::End);
                        }
                        self.drop_pair(slot);
                    }
                }
                None if ch.delta > 0 => self.new_pair(a, b, ch.delta as u32),
                None => {}
            }
        }
    }

    /// Whether both objects are balls (their pair has a polynomial certificate).
    fn balls(&self, a: u32, b: u32) -> bool {
        let ball = |id: u32| {
            self.bodies[id as usize]
                .as_ref()
                .is_some_and(|b| b.shape.ball_radius().is_some())
        };
        ball(a) && ball(b)
    }

    /// The pair as a mover for the contact search.
    fn mover(&self, a: u32, b: u32) -> Mover<'_> {
        let (ba, bb) = (
            self.bodies[a as usize].as_ref().expect("live object"),
            self.bodies[b as usize].as_ref().expect("live object"),
        );
        Mover {
            shape_a: &ba.shape,
            plan_a: &ba.plan,
            shape_b: &bb.shape,
            plan_b: &bb.plan,
        }
    }

    /// The gap of the pair's outer balls around now, a hair inflated: the windows in which a
    /// shape pair can touch.
    fn outer_gap(&self, a: u32, b: u32) -> Poly {
        let r = (self.radius(a) + self.radius(b)) * (1.0 + 1e-9);
        ball_ball_gap(
            &self.plan_of(a).local_coefficients(self.now),
            &self.plan_of(b).local_coefficients(self.now),
            r * r,
        )
    }

    /// Whether the pair overlaps (or touches) now and just after: its contact state.
    fn touching_now(&self, a: u32, b: u32) -> bool {
        if self.balls(a, b) {
            self.gap(a, b).sign_just_after_zero() <= 0
        } else {
            self.mover(a, b).signed_distance(self.now) <= 0.0
        }
    }

    /// A number that is negative when the pair overlaps now, positive when apart (for balls
    /// the gap polynomial's value, for shapes the signed distance), and the slack within which
    /// the audit lets rounding disagree with a pair's state.
    ///
    /// The slack covers the roundings: of the sizes (1e-9 of the larger), of positions far
    /// from the origin (a few ulps of the coordinates), of event times (1e-12 of the time,
    /// over which fast objects move: a contact time that good puts a pair at speed 1e6 a
    /// distance 1e-6 off), and for balls of the gap polynomial's terms.
    pub(crate) fn separation(&self, a: u32, b: u32) -> (Real, Real) {
        let scale = self.radius(a).max(self.radius(b));
        let (pa, pb) = (self.plan_of(a), self.plan_of(b));
        let far = pa.position_at(self.now).abs().max_element()
            + pb.position_at(self.now).abs().max_element();
        let speed = (pa.velocity_at(self.now) - pb.velocity_at(self.now)).length()
            + pa.angular_velocity.length() * self.radius(a)
            + pb.angular_velocity.length() * self.radius(b);
        let off = 8.0 * Real::EPSILON * far + 1e-12 * self.now.abs().max(1.0) * speed;
        if self.balls(a, b) {
            // The gap polynomial may be expanded about an earlier time: its terms are as
            // large as the square of how far the pair moved apart since then.
            let reach = self.radius(a) + self.radius(b);
            let moved = (pa.position_at(self.now) - pb.position_at(self.now)).length()
                + speed * self.now.abs()
                + (pa.acceleration - pb.acceleration).length() * self.now * self.now;
            let terms = 4.0 * Real::EPSILON * moved * moved;
            (
                self.gap(a, b).c[0],
                1e-9 * scale * scale + 2.0 * reach * off + terms,
            )
        } else {
            (
                self.mover(a, b).signed_distance(self.now),
                1e-9 * scale + off,
            )
        }
    }

    /// A shape pair's walk from now, in state `touching` now.
    fn shape_walk(&self, a: u32, b: u32, touching: bool) -> ShapeWalk {
        ShapeWalk::new(&self.mover(a, b), &self.outer_gap(a, b), self.now, touching)
    }

    /// A new candidate pair: its state now decides the events reported at once.
    fn new_pair(&mut self, a: u32, b: u32, refs: u32) {
        let (walk, touching) = if self.balls(a, b) {
            self.new_ball_walk(a, b)
        } else {
            let touching = self.touching_now(a, b);
            if touching && self.response == Response::None {
                self.log(a, b, ContactKind::Begin);
            }
            (PairWalk::Shapes(self.shape_walk(a, b, touching)), touching)
        };
        let slot = self.pairs.insert(PairCertificate {
            a,
            b,
            refs,
            touching,
            walk,
        });
        self.schedule_pair(slot);
    }

    fn new_ball_walk(&mut self, a: u32, b: u32) -> (PairWalk, bool) {
        let f = self.gap(a, b);
        let (base, fb) = self.canonical_gap(a, b);
        let touching_now = f.c[0] <= 0.0;
        let after = f.sign_just_after_zero();
        match self.response {
            Response::None => {
                if touching_now {
                    self.log(a, b, ContactKind::Begin);
                    if after > 0 {
                        self.log(a, b, ContactKind::End);
                    }
                }
                let touching = touching_now && after <= 0;
                let walk = Walk::contact(&fb, base, self.now, touching);
                (PairWalk::Balls(walk), touching)
            }
            Response::Elastic => (
                PairWalk::Balls(Walk::elastic(&fb, base, self.now, &f)),
                false,
            ),
        }
    }

    /// Recomputes a pair's certificate after one of its objects changed plan.
    pub(crate) fn refresh_pair(&mut self, slot: u32) {
        let (a, b) = {
            let c = self.pairs.get(slot);
            (c.a, c.b)
        };
        let walk = if self.balls(a, b) && self.response == Response::Elastic {
            let f = self.gap(a, b);
            let (base, fb) = self.canonical_gap(a, b);
            PairWalk::Balls(Walk::elastic(&fb, base, self.now, &f))
        } else {
            let was = self.pairs.get(slot).touching;
            let now_touching = self.touching_now(a, b);
            match (was, now_touching) {
                (true, false) => self.log(a, b, ContactKind::End),
                (false, true) => self.log(a, b, ContactKind::Begin),
                _ => {}
            }
            self.pairs.get_mut(slot).touching = now_touching;
            if self.balls(a, b) {
                let (base, fb) = self.canonical_gap(a, b);
                PairWalk::Balls(Walk::contact(&fb, base, self.now, now_touching))
            } else {
                PairWalk::Shapes(self.shape_walk(a, b, now_touching))
            }
        };
        self.pairs.get_mut(slot).walk = walk;
        self.schedule_pair(slot);
    }

    /// Steps a pair's walk past the event that was due.
    pub(crate) fn consume_pair(&mut self, slot: u32) {
        let cert = *self.pairs.get(slot);
        let walk = match cert.walk {
            PairWalk::Balls(mut w) => {
                w.consume(self.response);
                PairWalk::Balls(w)
            }
            PairWalk::Shapes(mut w) => {
                w.consume(&self.mover(cert.a, cert.b));
                PairWalk::Shapes(w)
            }
        };
        self.pairs.get_mut(slot).walk = walk;
        self.schedule_pair(slot);
    }

    pub(crate) fn schedule_pair(&mut self, slot: u32) {
        let c = self.pairs.get(slot);
        match c.walk.due() {
            Some((t, _)) => self.pair_queue.schedule(slot, t, pair_key(c.a, c.b)),
            None => {
                self.pair_queue.remove(slot);
            }
        }
    }

    pub(crate) fn drop_pair(&mut self, slot: u32) {
        self.pair_queue.remove(slot);
        self.pairs.remove(slot);
    }

    pub(crate) fn log(&mut self, a: u32, b: u32, kind: ContactKind) {
        match kind {
            ContactKind::Begin => self.stats.begins += 1,
            ContactKind::End => self.stats.ends += 1,
        }
        self.events.push(ContactEvent {
            time: self.now,
            a: ObjectId(a.min(b)),
            b: ObjectId(a.max(b)),
            kind,
        });
    }
}
