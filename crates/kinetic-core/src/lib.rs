//! # kinetic-core
//!
//! The kinetic core of kinetic-collide: flight plans, certificate roots, an indexed event
//! queue, kinetic sorted lists, the simulator loop and the brute-force reference structure.
//! The hard-sphere simulators built on it are in `kinetic-spheres`; the structures in
//! `kinetic-rolling` and `kinetic-flight`.
//! A kinetic data structure keeps certificates (facts that prove objects are apart), computes
//! when each fails from the objects' flight plans, and processes failures in time order, so
//! contacts are found at their exact time whatever the speeds.
//!
//! ```
//! use kinetic_core::{ContactKind, FlightPlan, Vec3, Simulator, WorldKind};
//!
//! let mut world = Simulator::new(WorldKind::Free);
//! let a = world.add_ball(1.0, FlightPlan::linear(Vec3::ZERO, Vec3::new(2.0, 0.0, 0.0))).unwrap();
//! let b = world.add_ball(1.0, FlightPlan::at_rest(Vec3::new(10.0, 0.0, 0.0))).unwrap();
//! world.advance_to(5.0).unwrap();
//! let events = world.drain_events();
//! assert_eq!((events[0].time, events[0].kind), (4.0, ContactKind::Begin));
//! # let _ = (a, b);
//! ```
#![warn(missing_docs)]
// One audited exception: the prefetch hint (`prefetch.rs`).
#![deny(unsafe_code)]

mod body;
mod brute_force;
pub mod elastic;
pub mod kds;
mod math;
mod plan;
mod prefetch;
mod structure;
mod world;

// The building blocks, by their short paths inside the crate.
pub(crate) use kds::{EventQueue, certificates, geometry, pair_key, poly, queue, roots};

pub use body::{Body, Shape};
pub use brute_force::BruteForce;
pub use math::{Quat, Real, Vec3, floor_int};
pub use plan::FlightPlan;
pub use prefetch::{prefetch, prefetch_all};
pub use structure::CandidateStructure;
pub use world::step::StepKind;
pub use world::{
    ContactEvent, ContactKind, MAX_MAGNITUDE, ObjectId, Response, Simulator, Stats, Walls,
    WorldError, WorldKind,
};
