//! The world's pieces that a hard-sphere simulator reuses, so that it gives the world's event
//! log bit for bit (the cell grid and the periodic box of `kinetic-spheres` are built on
//! them): a ball's motion record, the gap polynomial of two balls and its root walk, the
//! elastic exchange, wall hits and the Zeno guard.

pub use crate::math::{ROUNDING, round_near};
pub use crate::world::motion::Motion;
pub use crate::world::pairs::{Due, Source, Walk, ball_gap, canonical_base};
pub use crate::world::step::{Exchange, ZenoGuard, elastic_exchange};
pub use crate::world::walls::{WallHit, bounced, wall_hit};
