//! Flight plans: where an object is at any time.

use crate::math::{Quat, Real, Vec3};

/// The motion of an object from time `t0` on: its centre follows
/// `position + velocity (t - t0) + acceleration (t - t0)^2 / 2` and it spins at a constant
/// angular velocity about its centre.
///
/// ```
/// # use kinetic_core::{FlightPlan, Vec3};
/// let plan = FlightPlan::linear(Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0));
/// assert_eq!(plan.position_at(2.0), Vec3::new(2.0, 0.0, 0.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FlightPlan {
    /// The time at which the plan starts (its reference time).
    pub t0: Real,
    /// The centre at `t0`.
    pub position: Vec3,
    /// The velocity at `t0`.
    pub velocity: Vec3,
    /// The constant acceleration.
    pub acceleration: Vec3,
    /// The orientation at `t0`.
    pub orientation: Quat,
    /// The constant angular velocity (radians per unit time, world axes).
    pub angular_velocity: Vec3,
}

impl FlightPlan {
    /// An object resting at `position`.
    pub fn at_rest(position: Vec3) -> FlightPlan {
        FlightPlan::accelerated(position, Vec3::ZERO, Vec3::ZERO)
    }

    /// An object coasting at constant velocity.
    pub fn linear(position: Vec3, velocity: Vec3) -> FlightPlan {
        FlightPlan::accelerated(position, velocity, Vec3::ZERO)
    }

    /// An object under constant acceleration (gravity, a constant push).
    pub fn accelerated(position: Vec3, velocity: Vec3, acceleration: Vec3) -> FlightPlan {
        FlightPlan {
            t0: 0.0,
            position,
            velocity,
            acceleration,
            orientation: Quat::IDENTITY,
            angular_velocity: Vec3::ZERO,
        }
    }

    /// The same plan with an orientation at `t0` and a constant spin.
    pub fn with_spin(self, orientation: Quat, angular_velocity: Vec3) -> FlightPlan {
        FlightPlan {
            orientation,
            angular_velocity,
            ..self
        }
    }

    /// The same plan starting at time `t0` instead of 0 (the given state holds at `t0`).
    pub fn starting_at(self, t0: Real) -> FlightPlan {
        FlightPlan { t0, ..self }
    }

    /// The degree of the translation: 0 at rest, 1 coasting, 2 accelerating.
    pub fn degree(&self) -> u8 {
        if self.acceleration != Vec3::ZERO {
            2
        } else if self.velocity != Vec3::ZERO {
            1
        } else {
            0
        }
    }

    /// The centre at time `t`.
    #[inline]
    pub fn position_at(&self, t: Real) -> Vec3 {
        let d = t - self.t0;
        self.position + (self.velocity + self.acceleration * (0.5 * d)) * d
    }

    /// The velocity at time `t`.
    #[inline]
    pub fn velocity_at(&self, t: Real) -> Vec3 {
        self.velocity + self.acceleration * (t - self.t0)
    }

    /// The orientation at time `t`.
    pub fn orientation_at(&self, t: Real) -> Quat {
        let angle = self.angular_velocity.length() * (t - self.t0);
        if angle == 0.0 {
            return self.orientation;
        }
        let spin = Quat::from_axis_angle(self.angular_velocity.normalize(), angle);
        (spin * self.orientation).normalize()
    }

    /// The plan re-based at time `t`: the same motion, with the state at `t` as its start.
    pub fn rebased(&self, t: Real) -> FlightPlan {
        FlightPlan {
            t0: t,
            position: self.position_at(t),
            velocity: self.velocity_at(t),
            acceleration: self.acceleration,
            orientation: self.orientation_at(t),
            angular_velocity: self.angular_velocity,
        }
    }

    /// A new plan from time `t`: the current position and orientation, a new velocity, the
    /// same acceleration and spin (what an elastic collision or a push does).
    pub fn replanned(&self, t: Real, velocity: Vec3) -> FlightPlan {
        FlightPlan {
            velocity,
            ..self.rebased(t)
        }
    }

    /// The centre as a polynomial in local time `tau = t - now`: `[p(now), v(now), a / 2]`.
    #[inline]
    pub fn local_coefficients(&self, now: Real) -> [Vec3; 3] {
        [
            self.position_at(now),
            self.velocity_at(now),
            self.acceleration * 0.5,
        ]
    }

    /// Whether every number in the plan is finite.
    pub fn is_finite(&self) -> bool {
        self.t0.is_finite()
            && self.position.is_finite()
            && self.velocity.is_finite()
            && self.acceleration.is_finite()
            && self.orientation.is_finite()
            && self.angular_velocity.is_finite()
    }
}
