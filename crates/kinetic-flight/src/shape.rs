//! Convex shapes for free flight: cuboids and convex hulls (parry for the geometry), with their
//! centre, inner ball B-, outer ball B+ and fatness.
//!
//! The centre of an object is the origin of its own frame: it follows the flight plan and the
//! object spins about it, so the centre moves as a polynomial even when the object turns, and
//! so do the boxes of B+ (centre +/- outer radius) that the structures sort. B- and B+ are the
//! largest ball about the centre inside the shape and the smallest one about it holding the
//! shape; the fatness is their ratio (a hull whose frame origin lies outside it is not fat).

use kinetic_core::{ConvexGeometry, Pose, Real, Shape, Vec3};
use parry3d_f64::math::Pose as ParryPose;
use parry3d_f64::query::{self, PointQuery};
use parry3d_f64::shape::{Ball, ConvexPolyhedron, Cuboid, Shape as ParryShape};
use std::any::Any;
use std::sync::Arc;

/// Why a shape cannot be built.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// A size is not finite and positive.
    #[error("sizes must be finite and > 0, got {0}")]
    BadSize(Real),
    /// A point is not finite.
    #[error("point {0} is not finite")]
    NonFinitePoint(usize),
    /// Fewer than four points.
    #[error("a convex hull needs at least 4 points, got {0}")]
    TooFewPoints(usize),
    /// The points span no volume.
    #[error("the points of a convex hull are coplanar or degenerate")]
    Flat,
}

/// A cuboid or convex hull, as a [`ConvexGeometry`] for the core.
#[derive(Debug)]
pub struct ConvexShape {
    geometry: Geometry,
    outer: Real,
    inner: Real,
}

#[derive(Debug)]
enum Geometry {
    Cuboid(Cuboid),
    Hull(ConvexPolyhedron),
}

impl ConvexShape {
    /// A cuboid centred on its frame's origin with the given half extents.
    pub fn cuboid(half_extents: Vec3) -> Result<ConvexShape, ShapeError> {
        for k in 0..3 {
            let h = half_extents[k];
            if !(h.is_finite() && h > 0.0) {
                return Err(ShapeError::BadSize(h));
            }
        }
        Ok(ConvexShape {
            geometry: Geometry::Cuboid(Cuboid::new(half_extents)),
            outer: half_extents.length(),
            inner: half_extents.min_element(),
        })
    }

    /// The convex hull of `points`, given in the object's frame.
    pub fn convex_hull(points: &[Vec3]) -> Result<ConvexShape, ShapeError> {
        if let Some(i) = points.iter().position(|p| !p.is_finite()) {
            return Err(ShapeError::NonFinitePoint(i));
        }
        if points.len() < 4 {
            return Err(ShapeError::TooFewPoints(points.len()));
        }
        let span = points
            .iter()
            .map(|p| (*p - points[0]).length())
            .fold(0.0, Real::max);
        if !flat_free(points, span) {
            return Err(ShapeError::Flat);
        }
        let hull = ConvexPolyhedron::from_convex_hull(points).ok_or(ShapeError::Flat)?;
        let outer = hull
            .points()
            .iter()
            .map(|p| p.length())
            .fold(0.0, Real::max);
        let proj = hull.project_local_point(Vec3::ZERO, false);
        let inner = if proj.is_inside {
            proj.point.length()
        } else {
            0.0
        };
        Ok(ConvexShape {
            geometry: Geometry::Hull(hull),
            outer,
            inner,
        })
    }

    /// This shape as a core [`Shape`].
    pub fn into_shape(self) -> Shape {
        Shape::Convex(Arc::new(self))
    }

    /// The radius of B+, the smallest ball about the centre that holds the shape.
    pub fn outer(&self) -> Real {
        self.outer
    }

    /// The radius of B-, the largest ball about the centre inside the shape.
    pub fn inner(&self) -> Real {
        self.inner
    }

    /// The shape for parry.
    pub fn parry(&self) -> &dyn ParryShape {
        match &self.geometry {
            Geometry::Cuboid(c) => c,
            Geometry::Hull(h) => h,
        }
    }
}

/// Whether the points span a volume (some four of them are not coplanar, relative to their
/// extent).
fn flat_free(points: &[Vec3], span: Real) -> bool {
    let p0 = points[0];
    let Some(p1) = points
        .iter()
        .copied()
        .max_by(|a, b| (*a - p0).length().total_cmp(&(*b - p0).length()))
    else {
        return false;
    };
    let e1 = p1 - p0;
    let Some(p2) = points.iter().copied().max_by(|a, b| {
        e1.cross(*a - p0)
            .length()
            .total_cmp(&e1.cross(*b - p0).length())
    }) else {
        return false;
    };
    let n = e1.cross(p2 - p0);
    let tol = 1e-9 * span;
    n.length() > tol * span
        && points
            .iter()
            .any(|p| n.dot(*p - p0).abs() > tol * n.length())
}

/// The fatness of a shape: outer radius over inner radius (infinite when the centre is not
/// inside the shape).
pub fn fatness(shape: &Shape) -> Real {
    let inner = shape.inner_radius();
    if inner > 0.0 {
        shape.outer_radius() / inner
    } else {
        Real::INFINITY
    }
}

fn parry_pose(p: &Pose) -> ParryPose {
    ParryPose::from_parts(p.translation, p.rotation)
}

impl ConvexGeometry for ConvexShape {
    fn name(&self) -> &'static str {
        match self.geometry {
            Geometry::Cuboid(_) => "cuboid",
            Geometry::Hull(_) => "convex_hull",
        }
    }

    fn outer_radius(&self) -> Real {
        self.outer
    }

    fn inner_radius(&self) -> Real {
        self.inner
    }

    fn local_aabb(&self, orientation: glam::DQuat) -> Option<(Vec3, Vec3)> {
        let aabb = self
            .parry()
            .compute_aabb(&ParryPose::from_parts(Vec3::ZERO, orientation));
        Some((aabb.mins, aabb.maxs))
    }

    fn signed_distance(&self, pose: &Pose, other: &Shape, other_pose: &Pose) -> Real {
        let ball;
        let g2: &dyn ParryShape = match other {
            Shape::Convex(g) => match g.as_any().downcast_ref::<ConvexShape>() {
                Some(s) => s.parry(),
                None => {
                    // A geometry from elsewhere: stand in its outer ball.
                    ball = Ball::new(g.outer_radius());
                    &ball
                }
            },
            Shape::Ball { radius } => {
                ball = Ball::new(*radius);
                &ball
            }
        };
        let (p1, p2) = (parry_pose(pose), parry_pose(other_pose));
        match query::contact(&p1, self.parry(), &p2, g2, Real::MAX) {
            Ok(Some(c)) => c.dist,
            // The penetration query gave up (degenerate overlap): overlapping, depth unknown.
            _ => {
                if query::intersection_test(&p1, self.parry(), &p2, g2)
                    .map_or(true, |i| i.intersecting)
                {
                    0.0
                } else {
                    query::distance(&p1, self.parry(), &p2, g2).map_or(0.0, |d| d.distance)
                }
            }
        }
    }

    fn as_any(&self) -> &dyn Any {
        self
    }
}
