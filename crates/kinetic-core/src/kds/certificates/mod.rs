//! Certificates, one file per predicate they certify. Each gives its polynomial (in local time
//! around the moment it is made) and the times at which it fails.

mod ball_ball_disjoint;
pub(crate) mod order;
mod wall;

pub use ball_ball_disjoint::ball_ball_gap;
pub use order::{OrderCertificate, ScalarKey, above_just_after};
pub use wall::wall_gap;
