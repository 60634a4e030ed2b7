//! The stepped half of the broad phase: the pairs of a set of boxes found afresh each step,
//! for worlds whose bodies do not keep to flight plans (a pile, a settling rain, a dense gas).
//!
//! - `grid.rs`: the stepped grid, the pairs of overlapping boxes from scratch.
//! - `sweep.rs`: sort and sweep, for a few boxes or boxes that overlap few others on an axis.
//! - `fat_pairs.rs`: the grid's pairs kept from step to step while the boxes keep within fat
//!   boxes (debris, bursts, kinematic bodies on their paths).
//! - `resting.rs`: the boxes at rest (sleeping, fixed) kept filed between steps, so that only
//!   the boxes that moved are filed each step.
//! - `enlarged.rs`: the pairs of an engine's enlarged boxes (avian's), kept per box and
//!   looked at only for the boxes the engine moved.
//! - `moves.rs`: whether two moving boxes meet within a step, the boxes' typical move.
//! - `sorted.rs`: sorted sets' merge and difference.
//!
//! The kinetic half ([`crate::kinetic`]) decides when to step and hands the pairs found here
//! to the engine.

mod enlarged;
mod fat_pairs;
mod grid;
mod moves;
mod resting;
mod sorted;
mod sweep;

pub(crate) use enlarged::EnlargedPairs;
pub(crate) use fat_pairs::FatPairs;
pub(crate) use grid::SteppedGrid;
pub(crate) use moves::{meet_ahead, typical_move};
pub(crate) use resting::Resting;
pub(crate) use sorted::sorted_difference;
