//! # kinetic-rolling
//!
//! The kinetic data structure of Section 2 of "Kinetic Collision Detection for Convex Fat
//! Objects" for balls of any sizes rolling on a plane: a *collision tree* whose every node
//! splits its balls into the smaller half `S` and the larger half `L`, and detects the
//! collisions between the two halves with *threshold boxes*. The box `TB(B_i)` of a ball of
//! `L` is the bounding box of the disk of radius `2 sqrt(r_i rho)` around its tangency point
//! (`rho` is at least the radius of every ball in `S`): a ball of `S` can touch `B_i` only while
//! its tangency point is inside that box, and by Lemma 4 a point lies in only a constant number
//! of boxes. Two kinetic sorted lists per node (x and y) find when a tangency point enters or
//! leaves a box; each (point, box) containment is a candidate pair whose ball-ball certificate
//! the simulator keeps.
//!
//! Two layouts of the sorted lists ([`ListLayout`]): per node (`rolling-tree`, Theorem 1:
//! O(n log n) space, O(n^2) events) or two global lists (`rolling-global-lists`, the paper's
//! second remark: fewer certificates touched per event, more events).
//!
//! ```
//! use kinetic_core::{ContactKind, FlightPlan, Response, Vec3, Simulator, WorldKind};
//! use kinetic_rolling::{ListLayout, RollingTree};
//!
//! let tree = RollingTree::new(ListLayout::PerNode);
//! let mut world =
//!     Simulator::with_structure(WorldKind::Plane, Response::None, None, Box::new(tree)).unwrap();
//! // A marble rolls into a big ball at rest: tangency points 2 sqrt(0.25 * 4) = 2 apart touch.
//! world.add_ball(0.25, FlightPlan::linear(Vec3::ZERO, Vec3::X)).unwrap();
//! world.add_ball(4.0, FlightPlan::at_rest(Vec3::new(5.0, 0.0, 0.0))).unwrap();
//! world.advance_to(10.0).unwrap();
//! let events = world.drain_events();
//! assert_eq!((events[0].time, events[0].kind), (3.0, ContactKind::Begin));
//! ```
//!
//! ## Staying balanced
//!
//! The tree is weight-balanced with partial rebuilding (as in a scapegoat tree): a new ball
//! walks down from the root, joining `S` if its radius is below the node's `rho`, `L` if above,
//! the smaller half on a tie, so every node keeps `S <= rho <= L` and its boxes never change
//! size. When an insertion or removal leaves a node on the path with one half larger than
//! 3/4 of the node (plus one), the highest such node's subtree is rebuilt from scratch, split
//! at the median radius as in the paper; a removed ball's parent is replaced by its sibling.
//! The depth stays below log_{4/3} n + O(1), and the rebuilding costs amortised
//! O(log^2 n) list operations per update.
#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod build;
mod event;
mod structure;
mod tree;
mod update;
mod validate;

pub use tree::{ListLayout, RollingTree};
