//! A live object: its shape and flight plan.

use crate::geometry::ConvexGeometry;
use crate::math::{Real, Vec3};
use crate::plan::FlightPlan;
use std::sync::Arc;

/// The shape of an object. The core knows balls; other convex shapes come with their modules
/// (the free-flight module's cuboids and convex hulls) through [`ConvexGeometry`].
#[derive(Clone, Debug)]
pub enum Shape {
    /// A ball of the given radius.
    Ball {
        /// Its radius.
        radius: Real,
    },
    /// Any other convex shape.
    Convex(Arc<dyn ConvexGeometry>),
}

impl Shape {
    /// The radius of the smallest ball around the centre that holds the shape.
    #[inline]
    pub fn outer_radius(&self) -> Real {
        match self {
            Shape::Ball { radius } => *radius,
            Shape::Convex(g) => g.outer_radius(),
        }
    }

    /// The radius of the largest ball around the centre inside the shape.
    pub fn inner_radius(&self) -> Real {
        match self {
            Shape::Ball { radius } => *radius,
            Shape::Convex(g) => g.inner_radius(),
        }
    }

    /// The ball's radius, if the shape is a ball.
    #[inline]
    pub fn ball_radius(&self) -> Option<Real> {
        match self {
            Shape::Ball { radius } => Some(*radius),
            Shape::Convex(_) => None,
        }
    }

    /// The shape's name in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Ball { .. } => "ball",
            Shape::Convex(g) => g.name(),
        }
    }
}

/// A live object: its shape and flight plan.
#[derive(Clone, Debug)]
pub struct Body {
    /// Its shape.
    pub shape: Shape,
    /// Its flight plan.
    pub plan: FlightPlan,
}

impl Body {
    /// Its box about its centre, as offsets (min, max): its own axis-aligned box when it
    /// does not spin and its geometry gives one, the box of its outer ball otherwise.
    pub fn local_box(&self) -> (Vec3, Vec3) {
        let r = self.shape.outer_radius();
        let own = match &self.shape {
            Shape::Convex(g) if self.plan.angular_velocity == Vec3::ZERO => {
                g.local_aabb(self.plan.orientation)
            }
            _ => None,
        };
        own.unwrap_or((Vec3::splat(-r), Vec3::splat(r)))
    }
}
