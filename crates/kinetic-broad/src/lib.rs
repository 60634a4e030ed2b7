//! # kinetic-broad
//!
//! The kinetic broad phase, engine by engine the same: colliders as proxies in a kinetic
//! structure of `kinetic-flight`, bodies on flight plans fitted to the engine's integrator,
//! the pairs whose proxies can meet within the coming step held, and of those the engine's
//! own handed to it: the pairs whose boxes, as the engine grows them ([`Engine::bounds`]),
//! swept as far over the step as its narrow phase looks ahead ([`Engine::ahead`]), meet.
//! The adapters are thin: `kinetic-rapier` (rapier3d 0.27's `BroadPhase`) and `kinetic-avian`
//! (a plugin for avian3d 0.8) each implement [`Engine`] over their engine's sets and turn
//! [`PairEvent`]s into its pair events.
//!
//! - [`Bound`]: how a collider is held (a ball about a moving body's centre of mass with a
//!   slack, or a fixed collider's box). A body at rest is held by a fat box about each of its
//!   colliders' own boxes instead, where the engine gives them ([`Engine::bounds`]).
//! - [`BroadPhaseCore`]: the proxies, the bodies' plans (a body that stays within its slack
//!   keeps its plan; one that keeps re-planning has its slack grown), the structure's events
//!   over each step in time order, the pair book that holds the candidates, and the pairs
//!   handed to the engine among them ([`BroadPhaseStats::pairs`]; [`BroadPhaseCore::holds_pair`]
//!   asks about the held ones).
//! - Kinetic or stepped: where plans do not hold (a pile, a settling rain, a dense gas) the
//!   core drops its structure and files every collider's box into a grid built afresh each
//!   step, handing over the pairs whose boxes meet within it; it goes back to kinetic once
//!   plans hold again. The choice is made from counts, so a run is the same every time.
//! - An engine that keeps enlarged boxes of its own ([`Engine::enlarged`]: avian's) is
//!   stepped for good on them: each call looks only at the boxes the engine moved and keeps
//!   the pairs of the others, so it costs what changed. Such a world keeps no plans and
//!   reads of a collider only the body it rides ([`Engine::collider_on_boxes`]).
//!
//! The source shows the two halves: `kinetic/` holds the core and its kinetic structure's
//! proxies, plans and pairs; `stepped/` the per-step filing (grid, sort and sweep, fat boxes,
//! resting boxes, the engine's enlarged boxes).
//! Both use one box type, [`Aabb`].
//!
//! An engine calls [`BroadPhaseCore::update`] once at the start of each step (the user's
//! changes, positions unchanged) and once after each position update, the updates together
//! one step long.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod aabb;
mod engine;
mod kinetic;
mod stepped;

pub use aabb::Aabb;
pub use engine::{BodyState, ColliderStatus, Engine, EngineStep, Key, PairEvent};
pub use kinetic::{Bound, BroadPhaseCore, BroadPhaseStats, Slack, StepStats, fit_plan};
