//! # kinetic-collide-cli
//!
//! The command-line tool's parts: drawing a run's frames, writing its files, and the
//! comparison harness (kinetic structures against time stepping, rapier and avian, on the scene
//! families of `kinetic-scenes`) with its chart. The library users add is `kinetic-collide`.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

#[cfg(feature = "avian")]
pub mod avian_run;
pub mod chart;
pub mod compare;
pub mod frames;
pub mod input;
pub mod output;
pub mod process;
pub mod progress;
pub mod rapier_run;
pub mod time_stepped;
