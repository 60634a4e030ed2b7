//! Shapes other than balls, and the contact search for pairs that hold one.
//!
//! The core knows balls (their gap is a polynomial with exact roots). Any other convex shape
//! plugs in through [`ConvexGeometry`], which only has to measure the signed distance between
//! two posed shapes; the free-flight module implements it with parry. The contact times of such
//! a pair come from [`search`]: conservative advancement on the signed distance, bounded by the
//! fastest a point of either object can move, so no contact is stepped over, then bisection on
//! the sign to pin the crossing.

use crate::body::Shape;
use crate::math::{Quat, Real, Vec3};
use crate::plan::FlightPlan;
use std::any::Any;

/// Where an object is and how it is turned: the pose of its frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pose {
    /// The frame's origin (the object's centre).
    pub translation: Vec3,
    /// The frame's orientation.
    pub rotation: Quat,
}

impl Pose {
    /// The pose a flight plan gives at time `t`.
    pub fn of_plan(plan: &FlightPlan, t: Real) -> Pose {
        Pose {
            translation: plan.position_at(t),
            rotation: plan.orientation_at(t),
        }
    }
}

/// A convex shape other than a ball, described in its own frame (the frame's origin is the
/// object's centre, which follows the flight plan and about which it spins).
pub trait ConvexGeometry: std::fmt::Debug + Send + Sync {
    /// Its name in scene files (`"cuboid"`, `"convex_hull"`).
    fn name(&self) -> &'static str;
    /// The radius of the smallest ball about the frame's origin that holds the shape.
    fn outer_radius(&self) -> Real;
    /// The radius of the largest ball about the frame's origin inside the shape (0 when the
    /// origin is not inside it).
    fn inner_radius(&self) -> Real;
    /// The signed distance between this shape at `pose` and `other` at `other_pose`: the gap
    /// when they are apart, zero when they touch, and minus a lower bound on the penetration
    /// depth (at most the true depth) when they overlap.
    fn signed_distance(&self, pose: &Pose, other: &Shape, other_pose: &Pose) -> Real;
    /// The shape's axis-aligned box at `orientation`, as offsets `(min, max)` from the frame's
    /// origin, when the geometry can give one tighter than its outer ball's (none by
    /// default). A structure may use it for an object that does not spin.
    fn local_aabb(
        &self,
        orientation: crate::math::Quat,
    ) -> Option<(crate::math::Vec3, crate::math::Vec3)> {
        let _ = orientation;
        None
    }
    /// The concrete type, for implementations that dispatch on the other shape.
    fn as_any(&self) -> &dyn Any;
}

/// The signed distance between two posed shapes: the gap when apart, zero when touching,
/// negative (at most the penetration depth in size) when they overlap.
pub fn signed_distance(a: &Shape, pose_a: &Pose, b: &Shape, pose_b: &Pose) -> Real {
    match (a, b) {
        (Shape::Convex(g), other) => g.signed_distance(pose_a, other, pose_b),
        (ball, Shape::Convex(g)) => g.signed_distance(pose_b, ball, pose_a),
        (Shape::Ball { radius: ra }, Shape::Ball { radius: rb }) => {
            (pose_a.translation - pose_b.translation).length() - ra - rb
        }
    }
}

/// What a contact search found.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Found {
    /// The state flips at `time`, the first time known flipped: the objects start to overlap
    /// (searching from apart) or come apart (searching from overlapping).
    Flip(Real),
    /// No flip before the end of the window.
    None,
    /// The step budget ran out at this time, with no flip before it: search again from there.
    Budget(Real),
}

/// Conservative-advancement steps per search before it hands back a re-check time.
const MAX_STEPS: usize = 256;

/// One pair of shapes with flight plans, for the contact search.
pub(crate) struct Mover<'a> {
    pub shape_a: &'a Shape,
    pub plan_a: &'a FlightPlan,
    pub shape_b: &'a Shape,
    pub plan_b: &'a FlightPlan,
}

impl Mover<'_> {
    /// The signed distance at time `t`.
    pub(crate) fn signed_distance(&self, t: Real) -> Real {
        let (pa, pb) = (Pose::of_plan(self.plan_a, t), Pose::of_plan(self.plan_b, t));
        signed_distance(self.shape_a, &pa, self.shape_b, &pb)
    }

    /// How fast the signed distance can change at `t` (every point of either object moves at
    /// most at the speed of its centre plus spin times its outer radius), and how fast that
    /// bound can grow (the relative acceleration of the centres).
    fn rates(&self, t: Real) -> (Real, Real) {
        let (pa, pb) = (self.plan_a, self.plan_b);
        let v = (pb.velocity_at(t) - pa.velocity_at(t)).length();
        let spin = pa.angular_velocity.length() * self.shape_a.outer_radius()
            + pb.angular_velocity.length() * self.shape_b.outer_radius();
        (
            (v + spin) * (1.0 + 1e-12),
            (pb.acceleration - pa.acceleration).length(),
        )
    }

    /// The longest step from `t` over which a signed distance of magnitude `s` cannot reach
    /// zero.
    fn safe_step(&self, t: Real, s: Real) -> Real {
        let (l, a) = self.rates(t);
        if l == 0.0 && a == 0.0 {
            return Real::INFINITY;
        }
        2.0 * s / (l + (l * l + 2.0 * a * s).sqrt())
    }

    /// Whether the relative motion is a pure translation at constant velocity: then the signed
    /// distance is convex in time, so once it grows while apart the pair never meets again.
    fn convex_in_time(&self) -> bool {
        let (pa, pb) = (self.plan_a, self.plan_b);
        pa.angular_velocity == Vec3::ZERO
            && pb.angular_velocity == Vec3::ZERO
            && pa.acceleration == pb.acceleration
    }

    /// Distances below this are within the rounding of the distance query.
    fn hover(&self) -> Real {
        1e-12 * (self.shape_a.outer_radius() + self.shape_b.outer_radius())
    }
}

/// The smallest step the search takes: the resolution of time near `t`.
fn crawl(t: Real) -> Real {
    1e-13 * t.abs().max(1.0)
}

/// Searches `[from, until)` for the first time the pair's state flips away from `inside`
/// (overlapping or touching: signed distance <= 0).
///
/// Each step is as long as the distance allows (conservative advancement), so no flip is
/// stepped over, except within a hair of touching: while the distance stays below the
/// query's rounding (`hover`), steps grow from the resolution of time by doubling, so objects
/// that slide along each other at zero distance do not crawl; such steps never exceed what
/// lets the distance change by 1e-6 of the objects' size, the deepest contact that could hide
/// between two samples there. A flip is pinned by bisection on the sign.
pub(crate) fn search(m: &Mover, from: Real, until: Real, inside: bool) -> Found {
    let mut t = from;
    let mut prev: Option<(Real, Real)> = None;
    let mut hovering = 0u32;
    for _ in 0..MAX_STEPS {
        if t >= until {
            return Found::None;
        }
        let s = m.signed_distance(t);
        let flipped = if inside { s > 0.0 } else { s <= 0.0 };
        if flipped {
            return Found::Flip(match prev {
                Some((tp, _)) => bisect(m, tp, t, inside),
                // Flipped already at the start (rounding at a previous event's time).
                None => t,
            });
        }
        if !inside && m.convex_in_time() && prev.is_some_and(|(_, sp)| s > sp) {
            return Found::None;
        }
        let step = m.safe_step(t, s.abs());
        if !step.is_finite() {
            return Found::None;
        }
        let step = if s.abs() <= m.hover() {
            // Grow from the resolution of time, but never so far that a contact deeper than
            // 1e-6 of the objects' size could fit between two samples.
            hovering = (hovering + 1).min(60);
            let cap = m.safe_step(t, 1e6 * m.hover()).max(crawl(t));
            (crawl(t) * (1u64 << hovering) as Real).min(cap)
        } else {
            hovering = 0;
            step.max(crawl(t))
        };
        prev = Some((t, s));
        t += step;
    }
    Found::Budget(t.min(until))
}

/// Bisection between `lo` (state `inside`) and `hi` (flipped): the first time known flipped.
fn bisect(m: &Mover, mut lo: Real, mut hi: Real, inside: bool) -> Real {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        let s = m.signed_distance(mid);
        let flipped = if inside { s > 0.0 } else { s <= 0.0 };
        if flipped {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}
