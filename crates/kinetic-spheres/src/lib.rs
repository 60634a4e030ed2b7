//! # kinetic-spheres
//!
//! Event-driven simulators of hard spheres, built on the kinetic core's certificates so that
//! their event logs are the world's, bit for bit, where the world can run the same system:
//!
//! - [`ElasticCells`]: elastic balls inside walls on a hierarchical grid of cells, one
//!   scheduled event per ball (the hard-sphere systems of event-driven molecular dynamics,
//!   gases and mixtures of sizes spread widely).
//! - [`ListedSpheres`]: elastic spheres of similar sizes in a periodic box ([`PeriodicBox`])
//!   or inside walls, with neighbour lists, one event per sphere and a calendar queue;
//!   [`Bulk`] gives the collision rate, temperature and pressure of the fluid.
//!
//! ```
//! use kinetic_core::{FlightPlan, Vec3};
//! use kinetic_spheres::{PeriodicBox, ListedSpheres};
//!
//! let cell = PeriodicBox { min: Vec3::ZERO, max: Vec3::splat(10.0) };
//! // Two spheres of radius 0.5 flying at each other along x, 2 apart at t = 0.
//! let spheres = [
//!     (0.5, FlightPlan::linear(Vec3::new(4.0, 5.0, 5.0), Vec3::X)),
//!     (0.5, FlightPlan::linear(Vec3::new(6.0, 5.0, 5.0), -Vec3::X)),
//! ];
//! let mut gas = ListedSpheres::periodic(cell, &spheres).unwrap();
//! gas.advance_to(1.0).unwrap();
//! let events = gas.drain_events();
//! assert_eq!(events.len(), 1);
//! assert!((events[0].time - 0.5).abs() < 1e-12);
//! ```
//!
//! This crate holds the project's `unsafe` code besides the core's prefetch hint: the
//! periodic structure's SIMD lanes (`listed/first_pass.rs`, `listed/grid.rs`), each block with
//! its safety argument, each lane tested against a scalar pass.
#![warn(missing_docs)]
#![deny(unsafe_code)]

mod bulk;
mod cells;
mod listed;

pub use bulk::Bulk;
pub use cells::ElasticCells;
pub use listed::{ListedSpheres, PeriodicBox};
