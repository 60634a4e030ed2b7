//! The simulator: objects with flight plans, a candidate structure, one disjointness
//! certificate per candidate pair, and the contact events they produce, in time order.
//!
//! Split by operation: `pairs.rs` (pair certificates and their contact state machine),
//! `step.rs` (the event loop and the elastic response), `walls.rs`, `validate.rs`.

pub(crate) mod motion;
pub(crate) mod pairs;
pub(crate) mod step;
mod validate;
pub(crate) mod walls;

use crate::body::{Body, Shape};
use crate::brute_force::BruteForce;
use crate::math::{Real, Vec3};
use crate::plan::FlightPlan;
use crate::queue::EventQueue;
use crate::structure::{CandidateStructure, PairChange};
pub use pairs::PairCertificate;
use std::collections::BTreeMap;

/// Where objects move.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum WorldKind {
    /// Objects fly freely in 3-space.
    #[default]
    Free,
    /// Balls roll on the plane z = 0: positions are tangency points, z is ignored.
    Plane,
}

/// What happens when two objects touch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Response {
    /// Objects pass through each other; every contact begin and end is reported.
    #[default]
    None,
    /// Balls bounce elastically (mass proportional to radius cubed); only begins are reported.
    Elastic,
}

/// An axis-aligned box that holds the scene; balls bounce off it under [`Response::Elastic`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Walls {
    /// The lower corner.
    pub min: Vec3,
    /// The upper corner.
    pub max: Vec3,
}

/// An object's id: its index in the order objects were added (ids are never reused).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct ObjectId(pub u32);

/// Whether a contact begins or ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ContactKind {
    /// The two objects start to touch.
    Begin,
    /// Two touching objects come apart.
    End,
}

/// A contact event between objects `a < b` at time `time`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactEvent {
    /// When it happens.
    pub time: Real,
    /// The object with the lower id.
    pub a: ObjectId,
    /// The object with the higher id.
    pub b: ObjectId,
    /// Begin or end.
    pub kind: ContactKind,
}

/// The largest size, coordinate, speed or acceleration a world takes: certificates square
/// products of these, and must stay finite. (The scene format bounds how far an object gets
/// over a horizon in the same spirit.)
pub const MAX_MAGNITUDE: Real = 1e150;

/// Bad input to the world, or a run that cannot go on.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WorldError {
    /// A shape the world cannot hold: a non-ball in a plane world or under the elastic
    /// response.
    #[error("object {object}: {why}")]
    UnsupportedShape {
        /// The object (the id it would have had).
        object: u32,
        /// Why.
        why: &'static str,
    },
    /// A size is not finite and positive.
    #[error("object {object}: radius must be finite and > 0, got {value}")]
    InvalidRadius {
        /// The object (the id it would have had).
        object: u32,
        /// The value given.
        value: Real,
    },
    /// A shape that cannot be built (see `kinetic_flight::ShapeError`).
    #[error("shape: {0}")]
    InvalidShape(String),
    /// A size or a flight plan's number is beyond [`MAX_MAGNITUDE`]: the certificates'
    /// arithmetic would overflow.
    #[error(
        "object {object}: {what} {value:e} is beyond {MAX_MAGNITUDE:e}, the largest magnitude computed exactly"
    )]
    OutOfRange {
        /// The object.
        object: u32,
        /// Which number.
        what: &'static str,
        /// Its magnitude.
        value: Real,
    },
    /// A flight plan holds a non-finite number.
    #[error("object {object}: flight plan has a non-finite number")]
    NonFinitePlan {
        /// The object.
        object: u32,
    },
    /// The object starts outside the walls.
    #[error("object {object}: starts outside the walls")]
    OutsideWalls {
        /// The object.
        object: u32,
    },
    /// Walls are not a box (a minimum not below its maximum, or not finite).
    #[error("walls: min must be below max on every axis, and finite")]
    InvalidWalls,
    /// No such object.
    #[error("object {0} is not in the world")]
    UnknownObject(u32),
    /// A structure that cannot hold this world.
    #[error("structure {structure}: {why}")]
    UnsupportedStructure {
        /// The structure's name.
        structure: &'static str,
        /// Why.
        why: &'static str,
    },
    /// Time would go backwards.
    #[error("cannot go back in time from {now} to {to}")]
    Backwards {
        /// The world's current time.
        now: Real,
        /// The time asked for.
        to: Real,
    },
    /// Too many events at one instant: a Zeno configuration.
    #[error(
        "more than {limit} events at time {time}: a Zeno configuration ({} last)",
        if a == b { format!("object {a} against a wall") } else { format!("objects {a} and {b}") }
    )]
    Zeno {
        /// The instant.
        time: Real,
        /// How many events were allowed there.
        limit: u64,
        /// The last pair processed.
        a: u32,
        /// The last pair processed.
        b: u32,
    },
}

/// Run statistics, as written by the command-line tool.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Stats {
    /// Events processed, by kind: `collision` (pair certificates), `bounce` (walls) and the
    /// structure's own kinds.
    pub events_by_kind: BTreeMap<&'static str, u64>,
    /// Largest number of certificates held at once.
    pub certificates_max: usize,
    /// Sum of certificate counts over samples (one when a run starts, one after each event).
    pub certificates_sum: f64,
    /// Largest number of candidate pairs.
    pub candidate_pairs_max: usize,
    /// Sum of candidate-pair counts over samples.
    pub candidate_pairs_sum: f64,
    /// Number of samples.
    pub samples: u64,
    /// Contacts that began.
    pub begins: u64,
    /// Contacts that ended.
    pub ends: u64,
    /// Wall bounces.
    pub bounces: u64,
}

impl Stats {
    /// All events.
    pub fn events_total(&self) -> u64 {
        self.events_by_kind.values().sum()
    }
    /// Mean number of certificates over samples.
    pub fn certificates_mean(&self) -> f64 {
        self.certificates_sum / self.samples.max(1) as f64
    }
    /// Mean number of candidate pairs over samples.
    pub fn candidate_pairs_mean(&self) -> f64 {
        self.candidate_pairs_sum / self.samples.max(1) as f64
    }
}

/// A world of moving objects whose contacts are detected kinetically.
///
/// ```
/// # use kinetic_core::{Simulator, WorldKind, FlightPlan, Vec3, ContactKind};
/// let mut world = Simulator::new(WorldKind::Free);
/// let a = world.add_ball(0.5, FlightPlan::linear(Vec3::ZERO, Vec3::X)).unwrap();
/// let b = world.add_ball(0.5, FlightPlan::at_rest(Vec3::new(4.0, 0.0, 0.0))).unwrap();
/// world.advance_to(10.0).unwrap();
/// let events = world.drain_events();
/// assert_eq!(events.len(), 2);
/// assert_eq!((events[0].time, events[0].kind), (3.0, ContactKind::Begin));
/// assert_eq!((events[1].time, events[1].kind), (5.0, ContactKind::End));
/// # let _ = (a, b);
/// ```
#[derive(Debug)]
pub struct Simulator {
    kind: WorldKind,
    response: Response,
    walls: Option<Walls>,
    now: Real,
    bodies: Vec<Option<Body>>,
    /// How many of `bodies` are live.
    live: usize,
    structure: Box<dyn CandidateStructure>,
    pairs: pairs::PairTable,
    /// Pair certificate failures, by pair slot; ties by `(a, b)`.
    pair_queue: EventQueue,
    /// Wall contacts, by object id (elastic response with walls only).
    wall_queue: EventQueue,
    wall_due: Vec<Option<walls::WallHit>>,
    events: Vec<ContactEvent>,
    changes: Vec<PairChange>,
    stats: Stats,
    zeno: step::ZenoGuard,
}

impl Simulator {
    /// An empty world with no response, no walls and the brute-force structure.
    pub fn new(kind: WorldKind) -> Simulator {
        Simulator::with_structure(kind, Response::None, None, Box::new(BruteForce::new()))
            .expect("no walls are valid walls")
    }

    /// An empty world with the given response, walls and candidate structure.
    pub fn with_structure(
        kind: WorldKind,
        response: Response,
        walls: Option<Walls>,
        structure: Box<dyn CandidateStructure>,
    ) -> Result<Simulator, WorldError> {
        if let Some(w) = walls {
            let dims = if kind == WorldKind::Plane { 2 } else { 3 };
            if !(0..dims)
                .all(|k| w.min[k].is_finite() && w.max[k].is_finite() && w.min[k] < w.max[k])
            {
                return Err(WorldError::InvalidWalls);
            }
        }
        let world = Simulator {
            kind,
            response,
            walls,
            now: 0.0,
            bodies: Vec::new(),
            live: 0,
            structure,
            pairs: pairs::PairTable::default(),
            pair_queue: EventQueue::new(),
            wall_queue: EventQueue::new(),
            wall_due: Vec::new(),
            events: Vec::new(),
            changes: Vec::new(),
            stats: Stats::default(),
            zeno: step::ZenoGuard::default(),
        };
        Ok(world)
    }

    /// The world's kind.
    pub fn kind(&self) -> WorldKind {
        self.kind
    }

    /// The contact response.
    pub fn response(&self) -> Response {
        self.response
    }

    /// The current time.
    pub fn now(&self) -> Real {
        self.now
    }

    /// The name of the candidate structure.
    pub fn structure_name(&self) -> &'static str {
        self.structure.name()
    }

    /// The candidate structure's own figures (see [`CandidateStructure::counters`]).
    pub fn structure_counters(&self) -> Vec<(&'static str, f64)> {
        self.structure.counters()
    }

    /// The statistics so far.
    pub fn stats(&self) -> &Stats {
        &self.stats
    }

    /// Number of live objects.
    pub fn len(&self) -> usize {
        self.live
    }

    /// Whether there are no live objects.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The live object `id`.
    pub fn body(&self, id: ObjectId) -> Option<&Body> {
        self.bodies.get(id.0 as usize).and_then(Option::as_ref)
    }

    /// Every id ever handed out, with the body if it is still live.
    pub fn bodies(&self) -> &[Option<Body>] {
        &self.bodies
    }

    /// Number of candidate pairs (pairs with a disjointness certificate).
    pub fn candidate_pairs(&self) -> usize {
        self.pairs.len()
    }

    /// The candidate pairs, lower id first, in no particular order.
    pub fn candidate_pair_list(&self) -> Vec<(ObjectId, ObjectId)> {
        self.pairs
            .iter()
            .map(|(_, c)| (ObjectId(c.a), ObjectId(c.b)))
            .collect()
    }

    /// The pairs in contact now (response `none` only; under `elastic` contacts are instants).
    pub fn touching_pairs(&self) -> Vec<(ObjectId, ObjectId)> {
        self.pairs
            .iter()
            .filter(|(_, c)| c.touching)
            .map(|(_, c)| (ObjectId(c.a), ObjectId(c.b)))
            .collect()
    }

    /// The boxes the structure keeps now, for pictures ([`CandidateStructure::boxes`]).
    pub fn structure_boxes(&self) -> Vec<(crate::Vec3, crate::Vec3)> {
        self.structure.boxes(&self.bodies, self.now)
    }

    /// Number of certificates: pair certificates, wall certificates and the structure's own.
    pub fn certificates(&self) -> usize {
        self.pairs.len() + self.wall_queue.len() + self.structure.certificates()
    }

    /// Adds a ball of `radius` with `plan` at the current time. The plan's state at its own
    /// `t0` is extrapolated to now. In a plane world only x and y are used.
    pub fn add_ball(&mut self, radius: Real, plan: FlightPlan) -> Result<ObjectId, WorldError> {
        Ok(self.add_balls([(radius, plan)])?[0])
    }

    /// Adds balls `(radius, plan)` together at the current time, so that the structure can
    /// build in bulk. Nothing is added if any ball is invalid.
    pub fn add_balls(
        &mut self,
        balls: impl IntoIterator<Item = (Real, FlightPlan)>,
    ) -> Result<Vec<ObjectId>, WorldError> {
        self.add_objects(
            balls
                .into_iter()
                .map(|(radius, plan)| (Shape::Ball { radius }, plan)),
        )
    }

    /// Adds an object of any shape with `plan` at the current time.
    pub fn add_object(&mut self, shape: Shape, plan: FlightPlan) -> Result<ObjectId, WorldError> {
        Ok(self.add_objects([(shape, plan)])?[0])
    }

    /// Adds objects `(shape, plan)` together at the current time, so that the structure can
    /// build in bulk. Nothing is added if any object is invalid.
    pub fn add_objects(
        &mut self,
        objects: impl IntoIterator<Item = (Shape, FlightPlan)>,
    ) -> Result<Vec<ObjectId>, WorldError> {
        let first = self.bodies.len() as u32;
        let mut new = Vec::new();
        for (k, (shape, plan)) in objects.into_iter().enumerate() {
            new.push(self.check_object(first + k as u32, shape, plan)?);
        }
        let ids: Vec<u32> = (first..first + new.len() as u32).collect();
        self.live += new.len();
        for body in new {
            self.bodies.push(Some(body));
            self.wall_due.push(None);
        }
        let mut changes = std::mem::take(&mut self.changes);
        self.structure
            .insert_many(&ids, &self.bodies, self.now, &mut changes);
        self.apply_changes(&mut changes);
        self.changes = changes;
        for &id in &ids {
            self.refresh_walls(id);
        }
        Ok(ids.into_iter().map(ObjectId).collect())
    }

    /// A valid body for id `object`, or why not.
    fn check_object(
        &self,
        object: u32,
        shape: Shape,
        plan: FlightPlan,
    ) -> Result<Body, WorldError> {
        let radius = shape.outer_radius();
        if !(radius.is_finite() && radius > 0.0) {
            return Err(WorldError::InvalidRadius {
                object,
                value: radius,
            });
        }
        if radius > MAX_MAGNITUDE {
            return Err(WorldError::OutOfRange {
                object,
                what: "size",
                value: radius,
            });
        }
        if let Shape::Convex(_) = shape {
            let why = match (self.kind, self.response) {
                (WorldKind::Plane, _) => Some("a plane world holds balls only"),
                (_, Response::Elastic) => Some("the elastic response applies to balls only"),
                _ => None,
            };
            if let Some(why) = why {
                return Err(WorldError::UnsupportedShape { object, why });
            }
        }
        let body = Body {
            shape,
            plan: self.flatten(plan, object)?,
        };
        if let Some(w) = self.walls.filter(|_| self.response == Response::Elastic) {
            let p = body.plan.position_at(self.now);
            let dims = self.dims();
            if !(0..dims).all(|k| p[k] - radius >= w.min[k] && p[k] + radius <= w.max[k]) {
                return Err(WorldError::OutsideWalls { object });
            }
        }
        Ok(body)
    }

    /// Removes an object; its pairs go without events (a contact it was in is not ended).
    pub fn remove(&mut self, id: ObjectId) -> Result<Body, WorldError> {
        let body = self
            .body(id)
            .cloned()
            .ok_or(WorldError::UnknownObject(id.0))?;
        // Its pairs go silently: not as contacts that end.
        for slot in self.pairs.slots_of(id.0) {
            self.pairs.get_mut(slot).touching = false;
        }
        let mut changes = std::mem::take(&mut self.changes);
        self.structure
            .remove(id.0, &self.bodies, self.now, &mut changes);
        self.apply_changes(&mut changes);
        self.changes = changes;
        for slot in self.pairs.slots_of(id.0) {
            self.drop_pair(slot);
        }
        self.bodies[id.0 as usize] = None;
        self.live -= 1;
        self.wall_queue.remove(id.0);
        self.wall_due[id.0 as usize] = None;
        Ok(body)
    }

    /// Gives object `id` a new flight plan from the current time on. Only that object's
    /// certificates are rescheduled. A plan that teleports the object reports the contacts it
    /// starts or ends at once.
    pub fn set_plan(&mut self, id: ObjectId, plan: FlightPlan) -> Result<(), WorldError> {
        if self.body(id).is_none() {
            return Err(WorldError::UnknownObject(id.0));
        }
        let plan = self.flatten(plan, id.0)?;
        self.replan(id.0, plan);
        Ok(())
    }

    /// Takes the contact events reported so far, in time order, ties by `(a, b)`.
    pub fn drain_events(&mut self) -> Vec<ContactEvent> {
        let mut events = std::mem::take(&mut self.events);
        // Stable: a graze keeps its begin before its end.
        events.sort_by(|x, y| x.time.total_cmp(&y.time).then((x.a, x.b).cmp(&(y.a, y.b))));
        events
    }

    fn dims(&self) -> usize {
        if self.kind == WorldKind::Plane { 2 } else { 3 }
    }

    /// Checks a plan and, in a plane world, drops its z parts.
    fn flatten(&self, mut plan: FlightPlan, object: u32) -> Result<FlightPlan, WorldError> {
        if !plan.is_finite() {
            return Err(WorldError::NonFinitePlan { object });
        }
        for (what, v) in [
            ("position", plan.position),
            ("velocity", plan.velocity),
            ("acceleration", plan.acceleration),
        ] {
            let value = v.abs().max_element();
            if value > MAX_MAGNITUDE {
                return Err(WorldError::OutOfRange {
                    object,
                    what,
                    value,
                });
            }
        }
        if self.kind == WorldKind::Plane {
            plan.position.z = 0.0;
            plan.velocity.z = 0.0;
            plan.acceleration.z = 0.0;
        }
        Ok(plan)
    }

    fn radius(&self, id: u32) -> Real {
        self.bodies[id as usize]
            .as_ref()
            .map_or(0.0, |b| b.shape.outer_radius())
    }

    pub(crate) fn sample(&mut self) {
        let (c, p) = (self.certificates(), self.pairs.len());
        let s = &mut self.stats;
        s.certificates_max = s.certificates_max.max(c);
        s.candidate_pairs_max = s.candidate_pairs_max.max(p);
        s.certificates_sum += c as f64;
        s.candidate_pairs_sum += p as f64;
        s.samples += 1;
    }
}
