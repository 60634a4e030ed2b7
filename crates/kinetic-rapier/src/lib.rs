//! # kinetic-rapier
//!
//! A kinetic broad phase for rapier3d 0.27, built on the free-flight structures of
//! `kinetic-flight`. Swap it in with one line:
//!
//! ```
//! use kinetic_rapier::KineticBroadPhase;
//! use rapier3d::prelude::*;
//!
//! let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
//! colliders.insert(ColliderBuilder::cuboid(10.0, 0.1, 10.0).build());
//! let ball = bodies.insert(RigidBodyBuilder::dynamic().translation(vector![0.0, 1.0, 0.0]));
//! colliders.insert_with_parent(ColliderBuilder::ball(0.5).build(), ball, &mut bodies);
//!
//! let mut broad_phase = KineticBroadPhase::default(); // instead of DefaultBroadPhase::new()
//! let (mut pipeline, params) = (PhysicsPipeline::new(), IntegrationParameters::default());
//! let (mut islands, mut narrow_phase) = (IslandManager::new(), NarrowPhase::new());
//! let (mut joints, mut multibody_joints) = (ImpulseJointSet::new(), MultibodyJointSet::new());
//! let mut ccd = CCDSolver::new();
//! for _ in 0..120 {
//!     pipeline.step(&vector![0.0, -9.81, 0.0], &params, &mut islands, &mut broad_phase,
//!         &mut narrow_phase, &mut bodies, &mut colliders, &mut joints, &mut multibody_joints,
//!         &mut ccd, &(), &());
//! }
//! // The ball rests on the ground.
//! assert!((bodies[ball].translation().y - 0.6).abs() < 0.05);
//! assert_eq!(broad_phase.stats().pairs, 1);
//! ```
//!
//! ## What it does
//!
//! Each collider is a proxy in a kinetic structure ([`proxy`](crate) module): a ball about its
//! body's centre of mass when the body moves, its own box when the body is fixed. Every
//! moving body has a flight plan fitted to rapier's integrator (position, velocity, and the
//! acceleration it has shown two steps running: gravity and any other constant force). A body
//! that stays within the slack of its plan keeps it; only bodies that left it are re-planned.
//! A body that keeps re-planning (jostled in a pile) has its slack doubled, up to 8 times,
//! and halved back once it keeps its plans. Fixed and sleeping bodies have rest plans and
//! cost nothing per step.
//!
//! rapier 0.27 calls the broad phase once at the start of each step (the user's changes,
//! positions unchanged) and once after each position update. After a position update the
//! structure is advanced one step ahead, through its own events in time order, so a pair is
//! handed to rapier (`AddPair`) in the step during which the two proxies meet at any moment: a
//! fast body cannot skip a pair between steps. Of the structure's candidates, rapier gets those
//! whose two balls can meet within the window. A pair is deleted only once it has been out of
//! the structure for a whole window, or its balls stay apart over a whole window, so never
//! while the colliders touch or are within the prediction distance. The lower collider index
//! comes first; a removed collider's pairs go
//! without events (the narrow phase drops them itself). Same-body pairs and collision groups
//! are filtered by rapier's narrow phase, as with the default broad phase.
//!
//! The structure is picked from the first colliders' sizes unless the caller picks one
//! ([`KineticBroadPhase::with_structure`]). Moving colliders of alike sizes (a rain, a pile)
//! get [`kinetic_flight::LooseGrid`]: each proxy holds a fixed region its box stays in for a
//! while on its plan, so a re-plan that stays inside costs one exit time, not a pass over its
//! neighbours. A spread of sizes (a debris field) gets [`kinetic_flight::Grid`], which sorts
//! the proxies into levels by size and finds the sweep's pairs (boxes that meet) among
//! proxies that share a cell. The sweep (Section 3.1) and guards (Section 3.2) hand over the
//! same or fewer pairs but pay for every swap of three global orders: on the benchmark's rain
//! and debris field the grid was 1.6x to 55x faster than either (README).
#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod motions;
mod pairs;
mod proxy;
pub mod scenes;

use kinetic_core::{Body, CandidateStructure, FlightPlan, PairChange, Real, Shape, Vec3};
use kinetic_flight::{Choice, ConvexShape, Grid, Guards, LooseGrid, Sweep};
use motions::ByBody;
use pairs::{Gate, PairBook, PairOut, proxies_gate, proxies_meet};
use proxy::{Hold, centre_of_mass, dvec, fit};
use rapier3d::prelude::*;

/// Steps over which a body must stay within half its slack to be planned at rest.
const REST_STEPS: Real = 30.0;
/// A body whose last [`RESTLESS_RUN`] re-plans each came within this many position updates of
/// the one before has its slack doubled...
const RESTLESS_UPDATES: u64 = 2;
/// ... (four, so five re-plans in all: not a body that starts to fall, which takes up to three
/// to learn its acceleration)...
const RESTLESS_RUN: u32 = 4;
/// ... up to this many times (a slack 8 times the base)...
const MAX_GROWTH: u32 = 3;
/// ... and halved at a re-plan that comes at least this many updates after the last.
const CALM_UPDATES: u64 = 60;

/// Moving colliders whose radii (the middle 98%) are within this factor get the loose grid.
const SIZES_ALIKE: Real = 8.0;

/// The loose grid's regions cover at most this many steps of a body's flight: a body
/// coasting slowly in a pile holds a region hugging its box, not one stretched over two box
/// widths of its drift (at the end of the rain at 1e4: 23 candidates per body, not 62).
const REGION_STEPS: Real = 4.0;

/// A candidate structure the broad phase can hold across threads.
type Structure = Box<dyn CandidateStructure + Send + Sync>;

/// Figures over the whole run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct BroadPhaseStats {
    /// Physics steps seen.
    pub steps: u64,
    /// Pairs rapier has now.
    pub pairs: usize,
    /// Pairs the kinetic structure holds now (rapier also keeps, for up to a step, pairs
    /// that have just dropped out).
    pub candidates: usize,
    /// Events of the kinetic structure processed.
    pub events: u64,
    /// Bodies re-planned because they left their plan's slack (or came to rest).
    pub replans: u64,
    /// Colliders put into the structure (new ones, changed ones, and proxies grown or shrunk
    /// around a change between steps).
    pub inserts: u64,
    /// `AddPair` events sent.
    pub added: u64,
    /// `DeletePair` events sent.
    pub deleted: u64,
    /// Times a body that kept re-planning had its slack doubled.
    pub slack_growths: u64,
    /// Times a body with grown slack that then kept its plan had it halved.
    pub slack_shrinks: u64,
}

/// Figures over the last physics step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Events of the kinetic structure processed.
    pub events: u64,
    /// Bodies re-planned.
    pub replans: u64,
    /// Colliders put into the structure.
    pub inserts: u64,
    /// `AddPair` events sent.
    pub added: u64,
    /// `DeletePair` events sent.
    pub deleted: u64,
}

/// A collider as the broad phase holds it.
#[derive(Clone, Copy, Debug)]
struct Proxy {
    handle: ColliderHandle,
    hold: Hold,
    /// Grown to cover the time between its change and the structure's clock, until the
    /// positions reach this time.
    grown_until: Option<Real>,
}

/// A moving body's plan and what the broad phase has seen of it.
#[derive(Clone, Debug)]
struct Motion {
    plan: FlightPlan,
    /// The least base slack of its colliders.
    slack: Real,
    /// The slack is the base times `2^growth`: doubled for a body that keeps re-planning
    /// (one jostled in a pile), halved back once it keeps its plans.
    growth: u32,
    /// The position update of its last re-plan, and how many re-plans running came within
    /// [`RESTLESS_UPDATES`] of the one before.
    replanned: u64,
    restless: u32,
    colliders: Vec<u32>,
    /// Its velocity at the last position update that moved it, and which update that was.
    last_v: Vec3,
    seen: u64,
    /// The acceleration it showed over the last update (if seen on the one before).
    last_a: Option<Vec3>,
    /// The acceleration it showed over two updates running: what its plan assumes.
    steady_a: Vec3,
    /// Whether it is in `KineticBroadPhase::moving`.
    listed: bool,
}

/// The broad phase's clock: the time of the colliders' positions and of the structure.
#[derive(Clone, Copy, Debug, Default)]
struct Clock {
    /// The positions' time: the sum of the steps integrated so far.
    pos: Real,
    /// The structure's time: the end of the window it has looked ahead to.
    kds: Real,
    /// The length of the current step, and how much of it is still to be integrated.
    dt: Real,
    left: Real,
    /// Whether the next call is the start of a step (the user's changes).
    in_step: bool,
    /// Position updates seen.
    updates: u64,
}

/// The kinetic broad phase: implements rapier3d 0.27's [`BroadPhase`].
pub struct KineticBroadPhase {
    choice: Option<Choice>,
    slack_fraction: Real,
    min_slack: Real,
    structure: Option<Structure>,
    bodies: Vec<Option<Body>>,
    /// Per collider, the version of its proxy's plan (bumped at every change), for the pair
    /// book's gate to know when to ask again.
    plans: Vec<u32>,
    proxies: Vec<Option<Proxy>>,
    /// Per collider index, the generation of the collider held there and the index of its
    /// moving body (`u32::MAX` for a fixed one): all a position update reads of each moved
    /// collider, kept compact because rapier lists them in its islands' order.
    movers: Vec<Option<(u32, u32)>>,
    /// The bodies moved in this position update, a bit per body index: they are looked at
    /// in index order, each once, whatever order rapier lists their colliders in.
    moved_bits: Vec<u64>,
    motions: ByBody<Motion>,
    /// Bodies whose plans are not at rest, in the order they started moving.
    moving: Vec<RigidBodyHandle>,
    /// Colliders whose proxies may be grown (checked when the positions move on).
    grown: Vec<u32>,
    /// This call's [`KineticBroadPhase::lag_growth`], once worked out.
    lag_reach: Option<Real>,
    book: PairBook,
    clock: Clock,
    /// The window of the last call that handed pairs over.
    emitted: (Real, Real),
    changes: Vec<PairChange>,
    out: Vec<PairOut>,
    stats: BroadPhaseStats,
    step: StepStats,
    audit: bool,
    audit_error: Option<String>,
}

impl Proxy {
    /// Its entry in [`KineticBroadPhase::movers`]: the collider's generation and the index
    /// of its moving body (`u32::MAX` when fixed).
    fn mover(&self) -> (u32, u32) {
        let body = match self.hold {
            Hold::Moving { body, .. } => body.into_raw_parts().0,
            Hold::Fixed { .. } => u32::MAX,
        };
        (self.handle.into_raw_parts().1, body)
    }
}

impl Motion {
    /// How much its base slack is grown: `2^growth`.
    fn scale(&self) -> Real {
        (1u32 << self.growth) as Real
    }

    /// Its slack now.
    fn slack_now(&self) -> Real {
        self.slack * self.scale()
    }

    /// Whether the body, at `x` with velocity `v` at time `t`, keeps its plan: within its
    /// slack of it now, and by the end of the step (`dt`) on the path rapier gives it if
    /// nothing touches it ([`fit`], evaluated without building the plan).
    fn keeps_plan(&self, x: Vec3, v: Vec3, t: Real, dt: Real, substeps: Real) -> bool {
        let slack = self.slack_now();
        let slack2 = slack * slack;
        if (x - self.plan.position_at(t)).length_squared() > slack2 {
            return false;
        }
        let (a, end) = (self.steady_a, t + dt);
        let d = end - t;
        let ballistic = x + (v + a * (dt / (2.0 * substeps)) + a * (0.5 * d)) * d;
        (ballistic - self.plan.position_at(end)).length_squared() <= slack2
    }
}

impl Default for KineticBroadPhase {
    fn default() -> Self {
        KineticBroadPhase::new()
    }
}

impl std::fmt::Debug for KineticBroadPhase {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("KineticBroadPhase")
            .field("structure", &self.structure_name())
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

impl KineticBroadPhase {
    /// A broad phase that picks its structure from the first colliders it is given.
    pub fn new() -> KineticBroadPhase {
        KineticBroadPhase {
            choice: None,
            slack_fraction: 0.05,
            min_slack: 1e-3,
            structure: None,
            bodies: Vec::new(),
            plans: Vec::new(),
            proxies: Vec::new(),
            movers: Vec::new(),
            moved_bits: Vec::new(),
            motions: ByBody::default(),
            moving: Vec::new(),
            grown: Vec::new(),
            lag_reach: None,
            book: PairBook::default(),
            clock: Clock::default(),
            emitted: (Real::NAN, Real::NAN),
            changes: Vec::new(),
            out: Vec::new(),
            stats: BroadPhaseStats::default(),
            step: StepStats::default(),
            audit: false,
            audit_error: None,
        }
    }

    /// The same broad phase with the structure chosen by the caller.
    pub fn with_structure(mut self, choice: Choice) -> KineticBroadPhase {
        self.choice = Some(choice);
        self
    }

    /// The same broad phase with another slack: a moving body may stray `fraction` of its
    /// size (at least `min` length units) from its plan before it is re-planned. More slack,
    /// fewer re-plans and more pairs. Default 0.05 and 0.001.
    pub fn with_slack(mut self, fraction: f32, min: f32) -> KineticBroadPhase {
        self.slack_fraction = fraction.max(0.0) as Real;
        self.min_slack = min.max(1e-9) as Real;
        self
    }

    /// The same broad phase, auditing itself after every event of its structure (slow; for
    /// tests). The first failure is kept: see [`KineticBroadPhase::audit_error`].
    pub fn with_audit(mut self) -> KineticBroadPhase {
        self.audit = true;
        self
    }

    /// The first failure of the audit, if any.
    pub fn audit_error(&self) -> Option<&str> {
        self.audit_error.as_deref()
    }

    /// The structure in use: `"grid"`, `"sweep"`, `"guards"`, or `"none"` before the first
    /// collider.
    pub fn structure_name(&self) -> &'static str {
        self.structure.as_ref().map_or("none", |s| s.name())
    }

    /// Figures over the whole run.
    pub fn stats(&self) -> BroadPhaseStats {
        BroadPhaseStats {
            pairs: self.book.reported(),
            candidates: self.book.candidates(),
            ..self.stats
        }
    }

    /// Figures over the last physics step.
    pub fn last_step(&self) -> StepStats {
        self.step
    }

    /// The structure's own figures (e.g. the sweep's box pairs, the guards' watches).
    pub fn structure_counters(&self) -> Vec<(&'static str, f64)> {
        self.structure.as_ref().map_or(Vec::new(), |s| s.counters())
    }

    /// Whether rapier has the pair of these two colliders by this broad phase.
    pub fn has_pair(&self, a: ColliderHandle, b: ColliderHandle) -> bool {
        let (ia, ib) = (a.into_raw_parts().0, b.into_raw_parts().0);
        self.known(a) && self.known(b) && self.book.has(ia, ib)
    }

    /// Recomputes the invariants from scratch: the structure's own, the pair book's, every
    /// enabled collider held, every moving body within its slack of its plan.
    pub fn validate(&self, colliders: &ColliderSet, bodies: &RigidBodySet) -> Result<(), String> {
        if let Some(s) = &self.structure {
            s.validate(&self.bodies, self.clock.kds)?;
        }
        self.book.audit(true, meet(&self.bodies, self.clock))?;
        for (h, co) in colliders.iter() {
            if co.is_enabled() && !self.known(h) {
                return Err(format!("collider {h:?} is not held"));
            }
        }
        for (i, p) in self.proxies.iter().enumerate() {
            let want = p.as_ref().map(Proxy::mover);
            if self.movers.get(i).copied().flatten() != want {
                return Err(format!(
                    "collider {i}: mover entry {:?}, held as {want:?}",
                    self.movers.get(i)
                ));
            }
        }
        for (h, m) in self.motions.iter() {
            let Some(rb) = bodies.get(h) else { continue };
            let off = (centre_of_mass(rb) - m.plan.position_at(self.clock.pos)).length();
            if off > m.slack_now() * (1.0 + 1e-6) {
                return Err(format!(
                    "body {h:?} is {off} from its plan, slack {}",
                    m.slack_now()
                ));
            }
        }
        Ok(())
    }

    fn known(&self, h: ColliderHandle) -> bool {
        let i = h.into_raw_parts().0 as usize;
        self.proxies
            .get(i)
            .and_then(|p| p.as_ref())
            .is_some_and(|p| p.handle == h)
    }

    /// The structure's shape for a hold.
    fn shape(&self, hold: &Hold, choice: Choice) -> Shape {
        match *hold {
            Hold::Moving {
                body,
                radius,
                slack,
            } => {
                // The hold's radius has its base slack; a grown slack adds the rest.
                let extra = self
                    .motions
                    .get(body)
                    .map_or(0.0, |m| slack * (m.scale() - 1.0));
                Shape::Ball {
                    radius: radius + extra,
                }
            }
            Hold::Fixed { min, max } => {
                let half = (max - min) / 2.0;
                match (choice, ConvexShape::cuboid(half)) {
                    (Choice::Sweep | Choice::Grid | Choice::Loose, Ok(cuboid)) => {
                        cuboid.into_shape()
                    }
                    _ => Shape::Ball {
                        radius: half.length().max(1e-9),
                    },
                }
            }
        }
    }

    /// The structure's plan for a collider held by `hold`.
    fn plan_of(&self, hold: &Hold) -> FlightPlan {
        match *hold {
            Hold::Fixed { min, max } => FlightPlan::at_rest((min + max) / 2.0),
            Hold::Moving { body, .. } => self.motions[body].plan,
        }
    }

    /// Drops collider `h` and its pairs without events (it was removed or disabled: rapier's
    /// narrow phase drops its pairs itself).
    fn remove_collider(&mut self, h: ColliderHandle) {
        if self.known(h) {
            self.detach(h.into_raw_parts().0, true);
        }
    }

    /// Takes held collider `i` out of the structure and forgets its proxy. Its pairs go
    /// silently, or (`silent` false) drop out as usual to be deleted once out for a window.
    fn detach(&mut self, i: u32, silent: bool) {
        self.take_out(i);
        let mut changes = std::mem::take(&mut self.changes);
        if silent {
            self.book.forget(i, &mut changes);
        } else {
            self.book.apply(&mut changes, self.clock.kds);
        }
        self.changes = changes;
        let proxy = self.proxies[i as usize].take().expect("held");
        self.movers[i as usize] = None;
        if let Hold::Moving { body, .. } = proxy.hold
            && let Some(m) = self.motions.get_mut(body)
        {
            m.colliders.retain(|&c| c != i);
            if m.colliders.is_empty() {
                self.motions.remove(body);
                self.moving.retain(|&b| b != body);
            }
        }
    }

    /// Takes collider `i` out of the structure, leaving its pair changes in `self.changes`.
    fn take_out(&mut self, i: u32) {
        if let Some(s) = self.structure.as_mut() {
            s.remove(i, &self.bodies, self.clock.kds, &mut self.changes);
        }
        self.bodies[i as usize] = None;
        self.plans[i as usize] = self.plans[i as usize].wrapping_add(1);
    }

    /// Puts collider `i` with `hold` into the structure at its clock, grown by `grow` (a
    /// change that happened `kds - pos` before the structure's clock).
    fn put_in(&mut self, i: u32, hold: Hold, grow: Real) {
        let choice = self.structure_choice();
        let mut shape = self.shape(&hold, choice);
        if grow > 0.0 {
            shape = Shape::Ball {
                radius: shape.outer_radius() + grow,
            };
        }
        let plan = self.plan_of(&hold);
        self.bodies[i as usize] = Some(Body { shape, plan });
        self.plans[i as usize] = self.plans[i as usize].wrapping_add(1);
        let s = self.structure.as_mut().expect("a structure");
        s.insert(i, &self.bodies, self.clock.kds, &mut self.changes);
        self.proxies[i as usize].as_mut().expect("held").grown_until =
            (grow > 0.0).then_some(self.clock.kds);
        if grow > 0.0 {
            self.grown.push(i);
        }
        self.stats.inserts += 1;
        self.step.inserts += 1;
    }

    /// The structure: the caller's, or the one picked for the first colliders, or the grid
    /// before any.
    fn structure_choice(&self) -> Choice {
        self.choice.unwrap_or(Choice::Grid)
    }

    fn grow_slots(&mut self, i: u32) {
        let need = i as usize + 1;
        if self.bodies.len() < need {
            self.bodies.resize(need, None);
            self.plans.resize(need, 0);
            self.proxies.resize(need, None);
            self.movers.resize(need, None);
        }
    }

    /// Starts a motion record for a body seen for the first time, resting where it is.
    fn motion_for(&mut self, h: RigidBodyHandle, rb: &RigidBody, slack: Real) -> &mut Motion {
        let t = self.clock.pos;
        let m = self.motions.get_or_insert_with(h, || Motion {
            plan: FlightPlan::at_rest(centre_of_mass(rb)).starting_at(t),
            slack,
            growth: 0,
            replanned: 0,
            restless: 0,
            colliders: Vec::new(),
            last_v: dvec(rb.linvel()),
            seen: u64::MAX,
            last_a: None,
            steady_a: Vec3::ZERO,
            listed: false,
        });
        m.slack = m.slack.min(slack);
        m
    }

    /// Adds the colliders `new` (enabled, not held) at the positions' time.
    fn install(
        &mut self,
        new: &[ColliderHandle],
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        params: &IntegrationParameters,
        update: u64,
    ) {
        if new.is_empty() {
            return;
        }
        let holds: Vec<(ColliderHandle, Hold)> = new
            .iter()
            .filter_map(|&h| {
                let co = colliders.get(h)?;
                Some((
                    h,
                    Hold::of(co, bodies, params, self.slack_fraction, self.min_slack),
                ))
            })
            .collect();
        // Plans first: a body seen for the first time gets a plan fitted to its state now; a
        // body already moving keeps its plan for the collider it gains.
        for &(h, hold) in &holds {
            let i = h.into_raw_parts().0;
            self.grow_slots(i);
            if let Hold::Moving { body, slack, .. } = hold {
                let fresh = !self.motions.contains(body);
                let m = self.motion_for(body, &bodies[body], slack);
                m.colliders.push(i);
                if fresh {
                    m.seen = update;
                    self.refit(body, bodies, params, true);
                }
            }
            let proxy = Proxy {
                handle: h,
                hold,
                grown_until: None,
            };
            self.movers[i as usize] = Some(proxy.mover());
            self.proxies[i as usize] = Some(proxy);
        }
        if self.structure.is_none() {
            let choice = self.choice.unwrap_or_else(|| pick_structure(&holds));
            self.choice = Some(choice);
            self.structure = Some(match choice {
                Choice::Sweep => Box::new(Sweep::new()),
                Choice::Guards => Box::new(Guards::new(1.0)),
                // Both grids give a fast body's region at least a step of flight: a shot
                // then costs an event a step, not one per cell or per two widths it flies.
                Choice::Grid => Box::new(Grid::new().with_least_flight(params.dt as Real)),
                Choice::Loose => {
                    let dt = params.dt as Real;
                    Box::new(
                        LooseGrid::new()
                            .with_horizon(REGION_STEPS * dt)
                            .with_least_flight(dt),
                    )
                }
            });
        }
        let grow = self.lag_growth();
        if grow == 0.0 {
            // Level with the structure's clock: all at once (an empty structure builds in bulk).
            let choice = self.structure_choice();
            let ids: Vec<u32> = holds.iter().map(|(h, _)| h.into_raw_parts().0).collect();
            for (h, hold) in &holds {
                let i = h.into_raw_parts().0 as usize;
                self.bodies[i] = Some(Body {
                    shape: self.shape(hold, choice),
                    plan: self.plan_of(hold),
                });
                self.plans[i] = self.plans[i].wrapping_add(1);
            }
            let s = self.structure.as_mut().expect("a structure");
            s.insert_many(&ids, &self.bodies, self.clock.kds, &mut self.changes);
            self.stats.inserts += ids.len() as u64;
            self.step.inserts += ids.len() as u64;
            self.book.apply(&mut self.changes, self.clock.kds);
            return;
        }
        for (h, hold) in holds {
            let i = h.into_raw_parts().0;
            let g = grow + self.own_reach(&hold);
            self.put_in(i, hold, g);
            self.book.apply(&mut self.changes, self.clock.kds);
        }
    }

    /// How far any moving body can go between the positions' time and the structure's clock:
    /// a change made at the positions' time grows its proxy by this (and its own reach) until
    /// the positions catch up. Zero when they are level. Worked out once per call, from the
    /// plans the call started with: a body re-planned during the call is grown by its own
    /// reach, so the pairs between two grown proxies are covered too.
    fn lag_growth(&mut self) -> Real {
        let lag = self.clock.kds - self.clock.pos;
        if lag <= 0.0 {
            return 0.0;
        }
        if let Some(g) = self.lag_reach {
            return g;
        }
        let g = self
            .moving
            .iter()
            .map(|b| reach_over(&self.motions[*b].plan, self.clock.pos, lag))
            .fold(0.0, Real::max);
        self.lag_reach = Some(g);
        g
    }

    fn own_reach(&self, hold: &Hold) -> Real {
        let lag = self.clock.kds - self.clock.pos;
        match *hold {
            Hold::Moving { body, .. } if lag > 0.0 => {
                reach_over(&self.motions[body].plan, self.clock.pos, lag)
            }
            _ => 0.0,
        }
    }

    /// Fits body `h` a new plan at the positions' time: called for a body that left its
    /// slack ([`Motion::keeps_plan`], checked by the caller) or, `first`, one seen for the
    /// first time (which does not count as a re-plan towards its slack growing). Returns
    /// whether the slack changed with it (and so the size of the body's proxies); `None`
    /// for a body rapier no longer has.
    fn refit(
        &mut self,
        h: RigidBodyHandle,
        bodies: &RigidBodySet,
        params: &IntegrationParameters,
        first: bool,
    ) -> Option<bool> {
        let rb = bodies.get(h)?;
        let t = self.clock.pos;
        let dt = self.clock.dt.max(params.dt as Real);
        let m = self.motions.get_mut(h).expect("a motion");
        let x = centre_of_mass(rb);
        let v = dvec(rb.linvel());
        let substeps = params.num_solver_iterations.get() as Real;
        // Where rapier will put it by the end of the step if nothing touches it.
        let ballistic = fit(x, v, m.steady_a, t, dt, substeps);
        // A body that sleeps, or would stay within half its slack for the next
        // REST_STEPS steps (one resting in a pile), is planned at rest: its box ends then
        // stay put instead of swapping back and forth with its neighbours' as it jitters.
        let horizon = REST_STEPS * dt;
        let drift = ballistic.velocity.length() * horizon
            + ballistic.acceleration.length() * horizon * horizon / 2.0;
        // A body re-planned again soon after the last is given more slack; one that kept its
        // plan a long while, less.
        let update = self.clock.updates;
        let since = update.saturating_sub(m.replanned);
        let mut growth = m.growth;
        if !first {
            m.restless = if since <= RESTLESS_UPDATES {
                m.restless + 1
            } else {
                0
            };
            if m.restless >= RESTLESS_RUN {
                growth = (growth + 1).min(MAX_GROWTH);
                m.restless = 0;
            } else if since >= CALM_UPDATES {
                growth = growth.saturating_sub(1);
            }
        }
        let resized = growth != m.growth;
        if growth > m.growth {
            self.stats.slack_growths += 1;
        } else if growth < m.growth {
            self.stats.slack_shrinks += 1;
        }
        m.growth = growth;
        m.replanned = update;
        let plan = if rb.is_sleeping() || drift <= m.slack_now() / 2.0 {
            FlightPlan::at_rest(x).starting_at(t)
        } else {
            ballistic
        };
        m.plan = plan;
        let rest = plan.velocity == Vec3::ZERO && plan.acceleration == Vec3::ZERO;
        if !rest && !m.listed {
            m.listed = true;
            self.moving.push(h);
        }
        Some(resized)
    }

    /// Gives the structure body `h`'s new plan for each of its colliders; `resized`: with
    /// proxies of a new size (its slack changed).
    fn replan(&mut self, h: RigidBodyHandle, resized: bool) {
        self.stats.replans += 1;
        self.step.replans += 1;
        let level = self.clock.kds == self.clock.pos;
        let grow = if level { 0.0 } else { self.lag_growth() };
        let plan = self.motions[h].plan;
        for i in self.motions[h].colliders.clone() {
            let Some(proxy) = self.proxies[i as usize] else {
                continue;
            };
            if level && proxy.grown_until.is_none() && !resized {
                let body = self.bodies[i as usize].as_mut().expect("held");
                body.plan = plan;
                self.plans[i as usize] = self.plans[i as usize].wrapping_add(1);
                let s = self.structure.as_mut().expect("a structure");
                s.replan(i, &self.bodies, self.clock.kds, &mut self.changes);
            } else {
                self.take_out(i);
                let own = self.own_reach(&proxy.hold);
                let g = if level { 0.0 } else { grow + own };
                self.put_in(i, proxy.hold, g);
            }
            self.book.apply(&mut self.changes, self.clock.kds);
        }
    }

    /// Runs the structure's events up to `t`.
    fn advance(&mut self, t: Real) {
        let Some(s) = self.structure.as_mut() else {
            self.clock.kds = self.clock.kds.max(t);
            return;
        };
        loop {
            let next = s.next_event_time();
            // A NaN time never comes due.
            if next.is_nan() || next > t {
                break;
            }
            s.process_next_event(&self.bodies, &mut self.changes);
            self.book.apply(&mut self.changes, next);
            self.stats.events += 1;
            self.step.events += 1;
            if self.audit && self.audit_error.is_none() {
                let r = s
                    .validate(&self.bodies, next)
                    .and_then(|_| self.book.audit(false, |_, _| true));
                if let Err(e) = r {
                    self.audit_error = Some(format!("after the event at {next}: {e}"));
                }
            }
        }
        self.clock.kds = self.clock.kds.max(t);
    }
}

/// Whether the proxies of colliders `a` and `b` can meet within the window from the positions'
/// time to the structure's (a missing proxy: yes).
fn meet(bodies: &[Option<Body>], clock: Clock) -> impl Fn(u32, u32) -> bool + '_ {
    move |a, b| match (&bodies[a as usize], &bodies[b as usize]) {
        (Some(x), Some(y)) => proxies_meet(x, y, clock.pos, clock.kds),
        _ => true,
    }
}

/// The structure for the first colliders `holds`: the loose grid when the moving ones are of
/// alike sizes (the middle 98% of their radii within a factor [`SIZES_ALIKE`]: a rain, a
/// pile), the grid otherwise (a debris field, where small pieces drift as fast as large ones
/// and would leave regions sized by their own width every few steps).
fn pick_structure(holds: &[(ColliderHandle, Hold)]) -> Choice {
    let mut r: Vec<Real> = holds
        .iter()
        .filter_map(|(_, h)| match *h {
            Hold::Moving { radius, .. } if radius > 0.0 && radius.is_finite() => Some(radius),
            _ => None,
        })
        .collect();
    if r.is_empty() {
        return Choice::Grid;
    }
    r.sort_unstable_by(Real::total_cmp);
    let pick = |q: Real| r[((r.len() - 1) as Real * q).round() as usize];
    if pick(0.99) <= SIZES_ALIKE * pick(0.01) {
        Choice::Loose
    } else {
        Choice::Grid
    }
}

/// How far a body on `plan` can get from where it is at `t` within `lag`.
fn reach_over(plan: &FlightPlan, t: Real, lag: Real) -> Real {
    plan.velocity_at(t).length() * lag + plan.acceleration.length() * lag * lag / 2.0
}

impl BroadPhase for KineticBroadPhase {
    fn update(
        &mut self,
        params: &IntegrationParameters,
        colliders: &ColliderSet,
        bodies: &RigidBodySet,
        modified_colliders: &[ColliderHandle],
        removed_colliders: &[ColliderHandle],
        events: &mut Vec<BroadPhasePairEvent>,
    ) {
        // rapier 0.27: one call with the user's changes at the start of a step, then one after
        // each position update, the updates together one step long.
        let dt = params.dt as Real;
        let starts_step = !self.clock.in_step;
        if starts_step {
            self.clock.dt = dt;
            self.clock.left = dt;
            self.clock.in_step = true;
            self.stats.steps += 1;
            self.step = StepStats::default();
        } else {
            self.clock.pos += dt;
            self.clock.left -= dt;
            self.clock.updates += 1;
            if self.clock.left <= 1e-4 * self.clock.dt {
                self.clock.in_step = false;
            }
        }
        let update = self.clock.updates;
        self.lag_reach = None;

        for &h in removed_colliders {
            self.remove_collider(h);
        }

        let mut new = Vec::new();
        let mut moved: Vec<RigidBodyHandle> = Vec::new();
        for &h in modified_colliders {
            if !starts_step {
                // After a position update a held collider has only moved with its body (only
                // the user changes shapes, parents and body types, at the start of a step).
                let (i, generation) = h.into_raw_parts();
                if let Some(Some((g, body))) = self.movers.get(i as usize)
                    && *g == generation
                {
                    if *body != u32::MAX {
                        let (word, bit) = (*body as usize / 64, *body % 64);
                        if self.moved_bits.len() <= word {
                            self.moved_bits.resize(word + 1, 0);
                        }
                        self.moved_bits[word] |= 1 << bit;
                    }
                    continue;
                }
            }
            let Some(co) = colliders.get(h) else { continue };
            if !co.is_enabled() {
                self.remove_collider(h);
                continue;
            }
            if !self.known(h) {
                new.push(h);
                continue;
            }
            let i = h.into_raw_parts().0 as usize;
            let held = self.proxies[i].expect("known").hold;
            let hold = Hold::of(co, bodies, params, self.slack_fraction, self.min_slack);
            if !held.same(&hold) {
                // A new shape, body or body type: held afresh.
                self.detach(i as u32, false);
                new.push(h);
            } else if let Hold::Moving { body, .. } = hold {
                moved.push(body);
            }
        }

        // Bodies that moved: what they showed of their acceleration, then their plans.
        let mut seen_moving = 0;
        let step_dt = self.clock.dt.max(dt);
        let substeps = params.num_solver_iterations.get() as Real;
        for word in 0..self.moved_bits.len() {
            while self.moved_bits[word] != 0 {
                let bits = self.moved_bits[word];
                self.moved_bits[word] = bits & (bits - 1);
                let index = word * 64 + bits.trailing_zeros() as usize;
                let Some(b) = self.motions.handle_at(index) else {
                    continue;
                };
                moved.push(b);
            }
        }
        for &b in &moved {
            let Some(rb) = bodies.get(b) else { continue };
            let Some(m) = self.motions.get_mut(b) else {
                continue;
            };
            if m.seen == update && !starts_step {
                continue;
            }
            let v = dvec(rb.linvel());
            if !starts_step {
                if m.seen.wrapping_add(1) == update {
                    let a = (v - m.last_v) / dt;
                    if let Some(prev) = m.last_a {
                        let agree = |x: Vec3, y: Vec3| {
                            (x - y).length() <= 1e-3 * x.length().max(y.length()) + 1e-3
                        };
                        if agree(a, prev) {
                            m.steady_a = a;
                        } else if !agree(a, m.steady_a) && !agree(prev, m.steady_a) {
                            // Two updates running off the steady acceleration: contact forces
                            // (a body resting on others, a pile settling). Plan it coasting,
                            // which a supported body keeps far longer than free fall.
                            m.steady_a = Vec3::ZERO;
                        }
                    }
                    m.last_a = Some(a);
                } else {
                    m.last_a = None;
                }
                m.last_v = v;
                m.seen = update;
            }
            // Most bodies keep their plans: checked here, with no second look-up.
            if m.keeps_plan(centre_of_mass(rb), v, self.clock.pos, step_dt, substeps) {
                seen_moving += usize::from(m.listed && m.seen == update);
                continue;
            }
            if let Some(resized) = self.refit(b, bodies, params, false) {
                self.replan(b, resized);
            }
            if self
                .motions
                .get(b)
                .is_some_and(|m| m.listed && m.seen == update)
            {
                seen_moving += 1;
            }
        }
        self.install(&new, colliders, bodies, params, update);

        // Unless every moving body moved in this update, some went to sleep or stopped.
        if !starts_step && seen_moving < self.moving.len() {
            // Bodies that did not move in this update went to sleep or stopped: at rest.
            let mut k = 0;
            while k < self.moving.len() {
                let b = self.moving[k];
                let seen = self.motions.get(b).is_some_and(|m| m.seen == update);
                if !seen && bodies.contains(b) {
                    let t = self.clock.pos;
                    let m = self.motions.get_mut(b).expect("listed");
                    let x = centre_of_mass(&bodies[b]);
                    m.plan = FlightPlan::at_rest(x).starting_at(t);
                    m.listed = false;
                    m.last_a = None;
                    self.moving.swap_remove(k);
                    self.replan(b, false);
                } else {
                    k += 1;
                }
            }
            // Proxies grown over a lag the positions have now caught up with.
            let pos = self.clock.pos;
            let proxies = &self.proxies;
            let mut grown = std::mem::take(&mut self.grown);
            grown.sort_unstable();
            grown.dedup();
            let (due, waiting): (Vec<u32>, Vec<u32>) = grown
                .into_iter()
                .filter(|&i| proxies[i as usize].is_some_and(|p| p.grown_until.is_some()))
                .partition(|&i| proxies[i as usize].is_some_and(|p| p.grown_until <= Some(pos)));
            self.grown = waiting;
            for i in due {
                let proxy = self.proxies[i as usize].expect("held");
                self.take_out(i);
                let lag = self.clock.kds > self.clock.pos;
                let grow = if lag {
                    self.lag_growth() + self.own_reach(&proxy.hold)
                } else {
                    0.0
                };
                self.put_in(i, proxy.hold, grow);
                self.book.apply(&mut self.changes, self.clock.kds);
            }
        }

        // Look ahead over the coming step.
        self.advance(self.clock.pos + self.clock.dt);

        // The start of a step with no change since the last call: nothing new to hand over.
        let window = (self.clock.pos, self.clock.kds);
        if !starts_step || self.book.take_changed() || window != self.emitted {
            let (bodies, plans, clock) = (&self.bodies, &self.plans, self.clock);
            self.book.emit(
                clock.pos,
                clock.kds,
                |a, b| match (&bodies[a as usize], &bodies[b as usize]) {
                    (Some(x), Some(y)) => proxies_gate(x, y, clock.pos, clock.kds),
                    _ => Gate {
                        meet: true,
                        wake: Real::NEG_INFINITY,
                    },
                },
                |i| plans[i as usize],
                &mut self.out,
            );
            self.emitted = window;
        }
        for o in self.out.drain(..) {
            let (a, b, add) = match o {
                PairOut::Add(a, b) => (a, b, true),
                PairOut::Delete(a, b) => (a, b, false),
            };
            let (Some(pa), Some(pb)) = (self.proxies[a as usize], self.proxies[b as usize]) else {
                continue;
            };
            let pair = ColliderPair::new(pa.handle, pb.handle);
            if add {
                self.stats.added += 1;
                self.step.added += 1;
                events.push(BroadPhasePairEvent::AddPair(pair));
            } else {
                self.stats.deleted += 1;
                self.step.deleted += 1;
                events.push(BroadPhasePairEvent::DeletePair(pair));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steps a ground and two falling balls `steps` times with `bp`.
    struct World {
        bodies: RigidBodySet,
        colliders: ColliderSet,
        islands: IslandManager,
        narrow: NarrowPhase,
        joints: ImpulseJointSet,
        multibody: MultibodyJointSet,
        pipeline: PhysicsPipeline,
    }

    impl World {
        fn new() -> (World, [ColliderHandle; 3], RigidBodyHandle) {
            let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
            let ground = colliders.insert(ColliderBuilder::cuboid(10.0, 0.1, 10.0).build());
            let mut balls = [ground; 2];
            let mut first = None;
            for (k, ball) in balls.iter_mut().enumerate() {
                let b = bodies.insert(RigidBodyBuilder::dynamic().translation(vector![
                    k as f32 * 2.0,
                    1.0,
                    0.0
                ]));
                first.get_or_insert(b);
                *ball = colliders.insert_with_parent(ColliderBuilder::ball(0.5), b, &mut bodies);
            }
            let world = World {
                bodies,
                colliders,
                islands: IslandManager::new(),
                narrow: NarrowPhase::new(),
                joints: ImpulseJointSet::new(),
                multibody: MultibodyJointSet::new(),
                pipeline: PhysicsPipeline::new(),
            };
            (world, [ground, balls[0], balls[1]], first.expect("a body"))
        }

        fn step(&mut self, bp: &mut KineticBroadPhase, steps: usize) {
            for _ in 0..steps {
                self.pipeline.step(
                    &vector![0.0, -9.81, 0.0],
                    &IntegrationParameters::default(),
                    &mut self.islands,
                    bp,
                    &mut self.narrow,
                    &mut self.bodies,
                    &mut self.colliders,
                    &mut self.joints,
                    &mut self.multibody,
                    &mut CCDSolver::new(),
                    &(),
                    &(),
                );
                bp.validate(&self.colliders, &self.bodies)
                    .expect("a valid broad phase");
            }
        }
    }

    #[test]
    fn the_mover_table_follows_the_held_colliders_and_validate_checks_it() {
        let (mut world, [ground, ball, other], body) = World::new();
        let mut bp = KineticBroadPhase::new();
        world.step(&mut bp, 5);
        let entry =
            |bp: &KineticBroadPhase, h: ColliderHandle| bp.movers[h.into_raw_parts().0 as usize];
        let generation = |h: ColliderHandle| h.into_raw_parts().1;
        assert_eq!(entry(&bp, ground), Some((generation(ground), u32::MAX)));
        assert_eq!(
            entry(&bp, ball),
            Some((generation(ball), body.into_raw_parts().0))
        );
        // A stale entry (the ball taken for fixed) is caught.
        let i = ball.into_raw_parts().0 as usize;
        let kept = bp.movers[i];
        bp.movers[i] = Some((generation(ball), u32::MAX));
        let err = bp
            .validate(&world.colliders, &world.bodies)
            .expect_err("a stale mover entry");
        assert!(err.contains("mover"), "{err}");
        bp.movers[i] = kept;
        // A removed collider leaves no entry; the other ball still moves and is re-planned.
        world
            .colliders
            .remove(other, &mut world.islands, &mut world.bodies, true);
        world.step(&mut bp, 30);
        assert_eq!(entry(&bp, other), None);
        assert!(bp.stats().replans > 0);
        assert!(world.bodies[body].translation().y < 0.9);
    }
}
