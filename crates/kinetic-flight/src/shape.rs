//! Convex shapes for free flight: cuboids and convex hulls (parry for the geometry), with their
//! centre, inner ball B-, outer ball B+ and fatness.
//!
//! The centre of an object is the origin of its own frame: it follows the flight plan and the
//! object spins about it, so the centre moves as a polynomial even when the object turns, and
//! so do the boxes of B+ (centre +/- outer radius) that the structures sort. B- and B+ are the
//! largest ball about the centre inside the shape and the smallest one about it holding the
//! shape; the fatness is their ratio (a hull whose frame origin lies outside it is not fat).

use kinetic_core::kds::{ConvexGeometry, Pose};
use kinetic_core::{Real, Shape, Vec3};
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

impl From<ShapeError> for kinetic_core::WorldError {
    fn from(e: ShapeError) -> kinetic_core::WorldError {
        kinetic_core::WorldError::InvalidShape(e.to_string())
    }
}

/// A cuboid or convex hull, as a [`ConvexGeometry`] for the core.
#[derive(Debug)]
pub struct ConvexShape {
    geometry: Geometry,
    outer: Real,
    inner: Real,
    features: Features,
}

/// A polytope's vertices, face normals and edge directions in its own frame: what the
/// separating-axis test needs.
#[derive(Debug)]
struct Features {
    points: Vec<Vec3>,
    normals: Vec<Vec3>,
    edges: Vec<Vec3>,
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
        let h = half_extents;
        let points = (0..8)
            .map(|k| {
                let s = |bit: u32| if k & bit == 0 { -1.0 } else { 1.0 };
                Vec3::new(s(1) * h.x, s(2) * h.y, s(4) * h.z)
            })
            .collect();
        Ok(ConvexShape {
            geometry: Geometry::Cuboid(Cuboid::new(half_extents)),
            outer: half_extents.length(),
            inner: half_extents.min_element(),
            features: Features {
                points,
                normals: vec![Vec3::X, Vec3::Y, Vec3::Z],
                edges: vec![Vec3::X, Vec3::Y, Vec3::Z],
            },
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
        let mut edges: Vec<Vec3> = Vec::new();
        for e in hull.edges() {
            // One direction per family of parallel edges.
            if !edges.iter().any(|d| d.cross(e.dir).length() < 1e-12) {
                edges.push(e.dir);
            }
        }
        let features = Features {
            points: hull.points().to_vec(),
            normals: hull.faces().iter().map(|f| f.normal).collect(),
            edges,
        };
        Ok(ConvexShape {
            geometry: Geometry::Hull(hull),
            outer,
            inner,
            features,
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

/// The separating-axis value of two posed polytopes: the largest gap between their
/// projections over the face normals of both and the cross products of their edges. Positive
/// exactly when they are apart (then at most their distance), otherwise minus the least depth
/// that separates them along one of those axes. Computed about `pa`'s centre.
fn separating_axes(a: &Features, pa: &Pose, b: &Features, pb: &Pose) -> Real {
    let offset = pb.translation - pa.translation;
    let pts_a: Vec<Vec3> = a.points.iter().map(|p| pa.rotation * *p).collect();
    let pts_b: Vec<Vec3> = b.points.iter().map(|p| pb.rotation * *p + offset).collect();
    let span = |pts: &[Vec3], n: Vec3| {
        pts.iter()
            .map(|p| p.dot(n))
            .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            })
    };
    let gap = |n: Vec3| {
        let ((a0, a1), (b0, b1)) = (span(&pts_a, n), span(&pts_b, n));
        (b0 - a1).max(a0 - b1)
    };
    let normals_a = a.normals.iter().map(|n| pa.rotation * *n);
    let normals_b = b.normals.iter().map(|n| pb.rotation * *n);
    let mut best = normals_a
        .chain(normals_b)
        .map(gap)
        .fold(Real::NEG_INFINITY, Real::max);
    for ea in &a.edges {
        let ea = pa.rotation * *ea;
        for eb in &b.edges {
            let c = ea.cross(pb.rotation * *eb);
            let len = c.length();
            if len > 1e-9 {
                best = best.max(gap(c / len));
            }
        }
    }
    best
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
            // GJK found the pair within its tolerance of touching and EPA found no
            // penetration: the shapes are within rounding of each other, where GJK's verdict
            // can flip from one instant to the next. Two polytopes get the separating-axis
            // test, computed about this shape's centre: its sign is exact up to rounding of
            // the shapes' own size, and its magnitude is the gap (apart) or the depth.
            _ if let Shape::Convex(g) = other
                && let Some(o) = g.as_any().downcast_ref::<ConvexShape>() =>
            {
                separating_axes(&self.features, pose, &o.features, other_pose)
            }
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
