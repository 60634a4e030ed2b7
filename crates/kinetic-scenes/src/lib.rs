//! # kinetic-scenes
//!
//! The scenes of kinetic-collide, defined once and shared by the tests, the benches, the
//! examples and the command-line tool's `generate`: seeded random ball and flight scenes
//! ([`BallScene`], [`FlightScene`], [`NestScene`]), hard-sphere systems ([`HardSpheres`]) and
//! the comparison's scene families ([`families::Family`]), the space of scenes the default
//! structure is measured on ([`space::draw`]), and the engines' scenes: the standard ones
//! ([`engines::standard`]) and a space of them ([`engines::space::draw`]), with the engine
//! benches' shared figures ([`engines::results`]). Every generator is deterministic in its
//! seed.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

pub mod audit;
#[cfg(feature = "avian")]
pub mod avian;
pub mod choice;
pub mod engines;
pub mod families;
pub mod generators;
pub mod hard_spheres;
#[cfg(feature = "rapier")]
pub mod rapier;
pub mod space;

pub use generators::{BallScene, FlightScene, NestScene, ShapeMix};
pub use hard_spheres::{HardSpheres, HardSpheresError, Species};
