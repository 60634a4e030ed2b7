//! # kinetic-collide
//!
//! Exact collision detection for moving objects with kinetic data structures, after
//! "Kinetic Collision Detection for Convex Fat Objects" (Abam, de Berg, Poon, Speckmann).
//! Objects move along flight plans; certificates prove pairs apart, their failure times are
//! computed from the plans, and failures are processed in time order, so every contact is
//! found at its exact time, whatever the speeds.
//!
//! Build a world, add objects with flight plans, change a plan, advance, drain the events:
//!
//! ```
//! use kinetic_collide::{ContactKind, FlightPlan, Vec3, World, WorldKind};
//!
//! let mut world = World::new(WorldKind::Free);
//! let a = world.add_ball(0.5, FlightPlan::linear(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)))?;
//! let b = world.add_ball(0.5, FlightPlan::at_rest(Vec3::new(4.0, 0.0, 0.0)))?;
//! world.advance_to(2.0)?;
//! // Push `b` away along +x from t = 2 on: only b's certificates are rescheduled.
//! world.set_plan(b, FlightPlan::linear(Vec3::new(4.0, 0.0, 0.0), Vec3::new(0.5, 0.0, 0.0)).starting_at(2.0))?;
//! world.advance_to(10.0)?;
//! let events = world.drain_events();
//! assert_eq!(events.len(), 2); // a catches b at t = 4 and is through it at t = 8
//! assert_eq!((events[0].a, events[0].b, events[0].kind), (a, b, ContactKind::Begin));
//! assert!((events[0].time - 4.0).abs() < 1e-12);
//! world.remove(a)?;
//! # Ok::<(), kinetic_collide::WorldError>(())
//! ```
//!
//! `World::new` starts with the brute force and moves to the box structure the registry's
//! cost model names for the objects it holds (the loose grid, the grid or the sweep, as
//! sizes spread). Any structure can be named, for example the collision tree of the paper's
//! Section 2 ([`Structure::RollingTree`]) for balls rolling on a plane:
//!
//! ```
//! use kinetic_collide::{FlightPlan, Response, Structure, Vec3, World, WorldKind};
//!
//! let mut world =
//!     World::with_structure(WorldKind::Plane, Response::Elastic, None, Structure::RollingTree)?;
//! world.add_balls([
//!     (0.1, FlightPlan::linear(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0))),
//!     (10.0, FlightPlan::at_rest(Vec3::new(5.0, 0.0, 0.0))),
//! ])?;
//! world.advance_to(10.0)?;
//! // The marble meets the big ball when their tangency points are 2 sqrt(0.1 * 10) = 2 apart.
//! assert_eq!(world.drain_events()[0].time, 3.0);
//! # Ok::<(), kinetic_collide::WorldError>(())
//! ```
//!
//! Bad input gives a typed error ([`WorldError`], [`scene::SceneError`]) naming what is
//! wrong; nothing panics on user data. A scene file ([`scene::Scene`]) runs to its exact event
//! log with [`run::run_scene`]; the format is in `docs/scene-format.md`.
//!
//! ## Features
//!
//! - `rapier`: the kinetic broad phase for rapier3d 0.27, as [`rapier`] (`kinetic-rapier`).
//! - `render`: the headless wgpu renderer, as [`render`] (`kinetic-render`).
//!
//! The default build holds the kinetic core, the rolling, flight and hard-sphere structures
//! and the scene format. The pieces for building your own kinetic structure (event queue,
//! polynomials, roots, certificates, sorted lists, cones, the structures themselves) are in
//! [`kds`]; the hard-sphere simulators (elastic balls in walls, in a periodic box) in
//! [`spheres`].
#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod run;
pub mod scene;
mod structures;
mod world;

pub use kinetic_core::{
    ContactEvent, ContactKind, FlightPlan, ObjectId, Quat, Response, Shape, Stats, StepKind, Vec3,
    Walls, WorldError, WorldKind,
};
pub use kinetic_flight::ConvexShape;
pub use structures::Structure;
pub use world::World;

/// parry3d-f64, whose shapes back [`ConvexShape`] (see [`ConvexShape::parry`]).
pub use parry3d_f64 as parry;

/// The hard-sphere simulators (`kinetic-spheres`): elastic balls in walls on a grid of
/// cells, and in a periodic box with the fluid's bulk figures.
pub use kinetic_spheres as spheres;

/// The kinetic broad phase for rapier3d 0.27 (feature `rapier`).
#[cfg(feature = "rapier")]
pub use kinetic_rapier as rapier;

/// The headless wgpu renderer (feature `render`).
#[cfg(feature = "render")]
pub use kinetic_render as render;

/// Building blocks of kinetic data structures, for people who build their own: the
/// simulator that runs any candidate structure, the indexed event queue, polynomials and
/// their roots, certificates, kinetic sorted lists, geometry, the cones, and the structures
/// themselves.
pub mod kds {
    pub use kinetic_core::kds::*;
    pub use kinetic_core::{
        Body, BruteForce, CandidateStructure, MAX_MAGNITUDE, Real, Simulator, elastic,
    };
    pub use kinetic_flight::{
        Cone, ConeSet, Grid, GuardGrid, Guards, LooseGrid, RHO_MAX, ShapeError, Sweep, fatness,
    };
    pub use kinetic_rolling::{ListLayout, RollingTree};
}
