//! The library's world: the kinetic simulator ([`kinetic_core::Simulator`]) with the
//! registry's structures.
//!
//! The simulator runs any candidate structure and defaults to the brute force, the exact
//! reference, because the core knows no other. This world knows them all: it starts on the
//! registry's adaptive structure (the brute force for its first few dozen objects, then the
//! box structure the cost model picks for the sizes of the objects it holds, re-picked when
//! they spread past its bounds), and as it is advanced measures the other box structures and
//! the brute force against it, moving to the fastest (`racing.rs`). It builds any other by
//! name ([`Structure`]), and then keeps it. Everything else is the simulator's own: this type
//! derefs to it, and forwards the methods that change the world itself, so that
//! `world.advance_to(world.now() + 1.0)` borrows as it reads.

mod racing;

use crate::structures::{Auto, Slice, Structure};
use kinetic_core::{
    Body, CandidateStructure, ContactEvent, FlightPlan, ObjectId, Real, Response, Shape, StepKind,
    Walls, WorldError, WorldKind,
};
use racing::Racing;
use std::ops::{Deref, DerefMut};

/// A world of moving objects: add objects with flight plans, change plans, advance, drain the
/// exact contact events. Every method of [`kinetic_core::Simulator`] is available on it.
#[derive(Debug)]
pub struct World {
    inner: kinetic_core::Simulator,
    /// The race of the default structure; none on a structure chosen by name.
    racing: Option<Racing>,
}

impl World {
    /// An empty world with no response, no walls and the default structure.
    pub fn new(kind: WorldKind) -> World {
        World::with_response(kind, Response::None, None).expect("no walls are valid walls")
    }

    /// An empty world with the given response and walls, and the default structure: the
    /// adaptive one, raced against the other box structures and the brute force as the
    /// world is advanced ([`World::race`]).
    pub fn with_response(
        kind: WorldKind,
        response: Response,
        walls: Option<Walls>,
    ) -> Result<World, WorldError> {
        let auto = Auto::new();
        let mut world = World::with_candidates(kind, response, walls, Box::new(auto))?;
        world.racing = Some(Racing::new());
        Ok(world)
    }

    /// The same world without the default's race: it keeps the adaptive structure (picked
    /// by the sizes of the objects it holds, as the cost model rules), whatever the clock
    /// says, so that which structure runs does not depend on timing.
    pub fn without_racing(mut self) -> World {
        self.racing = None;
        self
    }

    /// An empty world with the given response, walls and structure. The hard-sphere
    /// simulators ([`Structure::Cells`], [`Structure::Periodic`]) run whole scenes, not
    /// inside a world (see [`crate::spheres`]); the rolling tree needs a plane world and the
    /// guards a free one.
    pub fn with_structure(
        kind: WorldKind,
        response: Response,
        walls: Option<Walls>,
        structure: Structure,
    ) -> Result<World, WorldError> {
        let candidates =
            structure
                .build(kind, &[], 0.0)
                .map_err(|why| WorldError::UnsupportedStructure {
                    structure: structure.name(),
                    why,
                })?;
        World::with_candidates(kind, response, walls, candidates)
    }

    /// An empty world with the given response, walls and a candidate structure of your own
    /// (see [`crate::kds`]).
    pub fn with_candidates(
        kind: WorldKind,
        response: Response,
        walls: Option<Walls>,
        structure: Box<dyn CandidateStructure>,
    ) -> Result<World, WorldError> {
        kinetic_core::Simulator::with_structure(kind, response, walls, structure).map(World::from)
    }

    /// The simulator itself.
    pub fn into_inner(self) -> kinetic_core::Simulator {
        self.inner
    }

    /// Adds a ball (see [`kinetic_core::Simulator::add_ball`]).
    pub fn add_ball(&mut self, radius: Real, plan: FlightPlan) -> Result<ObjectId, WorldError> {
        self.inner.add_ball(radius, plan)
    }

    /// Adds balls together (see [`kinetic_core::Simulator::add_balls`]).
    pub fn add_balls(
        &mut self,
        balls: impl IntoIterator<Item = (Real, FlightPlan)>,
    ) -> Result<Vec<ObjectId>, WorldError> {
        self.inner.add_balls(balls)
    }

    /// Adds an object (see [`kinetic_core::Simulator::add_object`]).
    pub fn add_object(&mut self, shape: Shape, plan: FlightPlan) -> Result<ObjectId, WorldError> {
        self.inner.add_object(shape, plan)
    }

    /// Adds objects together (see [`kinetic_core::Simulator::add_objects`]).
    pub fn add_objects(
        &mut self,
        objects: impl IntoIterator<Item = (Shape, FlightPlan)>,
    ) -> Result<Vec<ObjectId>, WorldError> {
        self.inner.add_objects(objects)
    }

    /// Removes an object (see [`kinetic_core::Simulator::remove`]).
    pub fn remove(&mut self, id: ObjectId) -> Result<Body, WorldError> {
        self.inner.remove(id)
    }

    /// Gives an object a new plan (see [`kinetic_core::Simulator::set_plan`]).
    pub fn set_plan(&mut self, id: ObjectId, plan: FlightPlan) -> Result<(), WorldError> {
        self.inner.set_plan(id, plan)
    }

    /// Processes every event up to `t` (see [`kinetic_core::Simulator::advance_to`]). On the
    /// default structure, the time it takes is measured, and the world may move its objects
    /// to a structure measured faster (the events do not change).
    pub fn advance_to(&mut self, t: Real) -> Result<(), WorldError> {
        match self.racing.take() {
            None => self.inner.advance_to(t),
            Some(mut racing) => {
                let result = self.advance_racing(&mut racing, t);
                self.racing = Some(racing);
                result
            }
        }
    }

    /// What the default structure's race has run so far, slice by slice up to now: each
    /// structure tried, from and to which simulated time, and what it cost in wall seconds
    /// (its build included). Empty on a structure chosen by name, and before the first
    /// advance.
    pub fn race(&self) -> Vec<Slice> {
        let Some(racing) = &self.racing else {
            return Vec::new();
        };
        let current = Structure::from_name(self.inner.structure_name());
        racing.slices(current.unwrap_or(Structure::BruteForce), self.inner.now())
    }

    /// Processes the next event up to `until` (see [`kinetic_core::Simulator::step`]).
    pub fn step(&mut self, until: Real) -> Result<Option<StepKind>, WorldError> {
        let Some(racing) = self.racing.as_mut() else {
            return self.inner.step(until);
        };
        let start = std::time::Instant::now();
        let stepped = self.inner.step(until);
        racing.stepped(start.elapsed().as_secs_f64());
        stepped
    }

    /// Hands the world's objects to a fresh structure of kind `structure` at the current time
    /// (its grids giving every region at least `least_flight` time units of flight), without
    /// changing the log: every structure gives the same events, and keeps it (the default's
    /// race stops). Fails, changing nothing, when the structure does not run in this world.
    pub fn switch_structure(
        &mut self,
        structure: Structure,
        least_flight: Real,
    ) -> Result<(), WorldError> {
        self.hand_to(structure, least_flight)?;
        self.racing = None;
        Ok(())
    }

    /// [`World::switch_structure`], the race going on.
    fn hand_to(&mut self, structure: Structure, least_flight: Real) -> Result<(), WorldError> {
        // Only the guards size themselves by the shapes.
        let shapes: Vec<Shape> = if structure == Structure::Guards {
            let bodies = self.inner.bodies().iter().flatten();
            bodies.map(|b| b.shape.clone()).collect()
        } else {
            Vec::new()
        };
        let next = structure
            .build(self.inner.kind(), &shapes, least_flight)
            .map_err(|why| WorldError::UnsupportedStructure {
                structure: structure.name(),
                why,
            })?;
        self.inner.replace_structure(next);
        Ok(())
    }

    /// Takes the contact events so far (see [`kinetic_core::Simulator::drain_events`]).
    pub fn drain_events(&mut self) -> Vec<ContactEvent> {
        self.inner.drain_events()
    }
}

impl From<kinetic_core::Simulator> for World {
    fn from(inner: kinetic_core::Simulator) -> World {
        World {
            inner,
            racing: None,
        }
    }
}

impl Deref for World {
    type Target = kinetic_core::Simulator;

    fn deref(&self) -> &kinetic_core::Simulator {
        &self.inner
    }
}

impl DerefMut for World {
    fn deref_mut(&mut self) -> &mut kinetic_core::Simulator {
        &mut self.inner
    }
}
