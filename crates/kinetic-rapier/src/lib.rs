//! # kinetic-rapier
//!
//! A kinetic broad phase for rapier3d 0.27: a thin adapter over the engine-agnostic core of
//! `kinetic-broad` (which `kinetic-avian` shares), built on the free-flight structures of
//! `kinetic-flight`. Features: `f32` (the default) for rapier3d, `f64` for rapier3d-f64
//! (its broad phase is [`f64::KineticBroadPhase`]); both may be on at once. Swap it in with
//! one line:
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
//! Each collider is a proxy in a kinetic structure ([`kinetic_broad::Bound`]): a ball about its
//! body's centre of mass when the body moves, its own box when the body is fixed. Every
//! moving body has a flight plan fitted to rapier's integrator (position, velocity, and the
//! acceleration it has shown two steps running: gravity and any other constant force). A body
//! that stays within the slack of its plan keeps it; only bodies that left it are re-planned.
//! A body that keeps re-planning has its slack doubled, up to 8 times, and halved back once
//! it keeps its plans. Fixed and sleeping bodies have rest plans and
//! cost nothing per step.
//!
//! rapier 0.27 calls the broad phase once at the start of each step (the user's changes,
//! positions unchanged) and once after each position update. After a position update the
//! structure is advanced one step ahead, through its own events in time order, and the
//! structure's candidates of the step are held: a fast body cannot skip one between steps.
//! Of those, rapier gets its own pairs (`AddPair`): those whose boxes, grown by the
//! prediction distance and contact skin as rapier grows them, overlap where the bodies are,
//! each swept ahead only for a body with soft CCD (to where its velocity and forces take it
//! over the step, at most its soft-CCD distance), as rapier's own broad phase does: its
//! narrow phase makes contacts at the poses it has, so a pair further ahead would only cost
//! it, and it gets no pair its own broad phase would not give it. A pair is deleted (`DeletePair`) once those boxes part, so never
//! while the colliders touch or are within the prediction distance. The lower collider index
//! comes first; a removed collider's pairs go
//! without events (the narrow phase drops them itself). Same-body pairs and collision groups
//! are filtered by rapier's narrow phase, as with the default broad phase.
//!
//! Where plans do not hold (a pile, a settling rain, a dense gas: re-plans every few steps),
//! the broad phase *steps* instead: each step it files every collider's box, swept over the
//! step by its own last moves, into a grid built afresh, and hands rapier the pairs whose
//! boxes overlap (as above); where those pairs are few (debris and bursts flying apart) it
//! keeps fat boxes that cover each box's next steps and tests only their candidates. It
//! prices both ways from its counts (re-plans and events against colliders and fat boxes'
//! work) and switches back once plans pay again; `structure_name()` says `"stepped"`
//! meanwhile. A structure the caller picks stays kinetic.
//!
//! The structure is picked from the first colliders' sizes unless the caller picks one
//! ([`KineticBroadPhase::with_structure`]). Moving colliders of alike sizes (a rain, a pile)
//! get `kinetic_flight::LooseGrid`: each proxy holds a fixed region its box stays in for a
//! while on its plan, so a re-plan that stays inside costs one exit time, not a pass over its
//! neighbours. A spread of sizes gets `kinetic_flight::Grid`, which sorts
//! the proxies into levels by size and finds the sweep's pairs (boxes that meet) among
//! proxies that share a cell. The sweep (Section 3.1) and guards (Section 3.2) hand over the
//! same or fewer pairs but pay for every swap of three global orders: on the benchmark's rain
//! and debris field the grid was 1.6x to 55x faster than either (README).
#![warn(missing_docs)]
#![forbid(unsafe_code)]

#[cfg(feature = "f32")]
mod f32;
#[cfg(feature = "f64")]
pub mod f64;

#[cfg(feature = "f32")]
pub use f32::KineticBroadPhase;
pub use kinetic_broad::{BroadPhaseStats, StepStats};
/// The rapier this broad phase plugs into (0.27, f32), as its types appear here.
#[cfg(feature = "f32")]
pub use rapier3d;
/// The f64 rapier this broad phase plugs into (0.27), as its types appear in [`f64`].
#[cfg(feature = "f64")]
pub use rapier3d_f64;
