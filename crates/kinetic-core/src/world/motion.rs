//! A ball's linear motion and radius in one cache line: what the hard-sphere structures
//! (`cells`, `periodic`) read for every pair they test.

use crate::math::{Real, Vec3};
use crate::plan::FlightPlan;

/// A ball's linear motion (its plan without acceleration or spin) and radius: one cache line,
/// its fields in this order (the periodic structure's lanes read it as two 32-byte halves).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(64))]
pub struct Motion {
    /// When the motion starts.
    pub t0: Real,
    /// The centre at `t0`.
    pub position: Vec3,
    /// The constant velocity.
    pub velocity: Vec3,
    /// The ball's radius.
    pub radius: Real,
}

impl Motion {
    /// The linear part of `plan`, with `radius`.
    pub fn of(plan: &FlightPlan, radius: Real) -> Motion {
        Motion {
            t0: plan.t0,
            position: plan.position,
            velocity: plan.velocity,
            radius,
        }
    }

    /// The centre at `t`, as the plan gives it when it has no acceleration, bit for bit.
    #[inline]
    pub fn at(&self, t: Real) -> Vec3 {
        self.position + self.velocity * (t - self.t0)
    }
}
