//! # kinetic-flight
//!
//! The kinetic data structures of Section 3 of "Kinetic Collision Detection for Convex Fat
//! Objects" for convex fat objects flying freely in 3-space: balls, cuboids and convex hulls
//! (parry for the geometry), moving on polynomial flight plans and spinning at constant
//! angular velocity.
//!
//! - [`ConvexShape`]: cuboids and convex hulls with their centre, inner ball B-, outer ball B+
//!   and fatness; the core measures their signed distance through it and finds contact times
//!   by conservative advancement (see `kinetic_core::kds::geometry`).
//! - [`Sweep`] (Section 3.1, Theorem 6): three kinetic sorted lists of the endpoints of the
//!   boxes of the outer balls; every pair of overlapping boxes is a candidate pair. O(n) size
//!   for objects of similar sizes.
//! - [`Guards`] (Section 3.2): a grid of guards around every object (Lemma 7), kept as grid
//!   planes in three kinetic sorted lists beside the boxes; an object is a candidate of each
//!   larger object whose box holds one of its guards, unless a closer object in the same cone
//!   ([`ConeSet`], Lemma 9) proves the guard is not inside it. Candidates stay proportional to
//!   n however sizes differ, where the sweep's grow with every nested box.
//! - [`Grid`] (not in the paper): the sweep's candidates, found among the objects that share
//!   a cell of a hierarchical kinetic grid (one level per box size), so that its events are
//!   cell crossings and box events of neighbours instead of swaps of global orders.
//! - [`LooseGrid`] (not in the paper): each object holds a fixed region its box stays in for
//!   a while on its plan (one certificate per object, its exit time); candidates are the
//!   objects whose regions overlap, a superset of the sweep's. A re-plan that stays inside
//!   the region costs one root computation, so it suits bodies whose plans keep failing.
//!
//! Which of them a scene gets is decided above this crate, in `kinetic-collide`'s registry
//! of structures.
//!
//! ```
//! use kinetic_core::{ContactKind, FlightPlan, Response, Simulator, Vec3, WorldKind};
//! use kinetic_flight::{ConvexShape, Sweep};
//!
//! let mut world =
//!     Simulator::with_structure(WorldKind::Free, Response::None, None, Box::new(Sweep::new()))
//!         .unwrap();
//! // A unit cube at rest, and a ball of radius 0.5 flying at it along x.
//! let cube = ConvexShape::cuboid(Vec3::splat(0.5)).unwrap().into_shape();
//! world.add_object(cube, FlightPlan::at_rest(Vec3::ZERO)).unwrap();
//! world.add_ball(0.5, FlightPlan::linear(Vec3::new(-4.0, 0.0, 0.0), Vec3::X)).unwrap();
//! world.advance_to(10.0).unwrap();
//! let events = world.drain_events();
//! assert_eq!(events[0].kind, ContactKind::Begin);
//! assert!((events[0].time - 3.0).abs() < 1e-9);
//! assert!((events[1].time - 5.0).abs() < 1e-9);
//! ```
#![warn(missing_docs)]
#![forbid(unsafe_code)]

mod axes;
mod cell_math;
mod cones;
mod grid;
mod guards;
mod loose;
mod shape;
mod sweep;

pub use cones::{Cone, ConeSet};
pub use grid::Grid;
pub use guards::{GuardGrid, Guards, RHO_MAX};
pub use loose::{LooseGrid, TRAVEL as LOOSE_TRAVEL};
pub use shape::{ConvexShape, ShapeError, fatness};
pub use sweep::Sweep;
