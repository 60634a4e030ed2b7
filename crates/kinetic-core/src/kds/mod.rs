//! The building blocks of kinetic data structures, for people who build their own
//! [`CandidateStructure`](crate::CandidateStructure): the indexed event queue, polynomials
//! and their roots, certificates and their failure times, kinetic sorted lists, convex
//! geometry, pair keys, and what a structure reads of the bodies and reports of its pairs.

pub mod certificates;
pub mod geometry;
pub(crate) mod pair_key;
pub(crate) mod poly;
pub(crate) mod queue;
pub mod roots;
pub(crate) mod sorted_list;

pub use crate::structure::{Bodies, PairChange, additions_first};
pub use crate::world::PairCertificate;
pub use certificates::{OrderCertificate, ScalarKey};
pub use geometry::{ConvexGeometry, Pose, signed_distance};
pub use pair_key::{ordered_pair, pair_key};
pub use poly::{Poly, sign};
pub use queue::EventQueue;
pub use sorted_list::{KineticSortedList, SortedListError, Swap};
