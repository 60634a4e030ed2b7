//! Lemmas 7 and 9 of the paper as property tests, on random fat shapes (balls and cuboids),
//! placements, rotations and fatness.
//!
//! - Lemma 7: any object at least as large as K (inner radius) and at most rho-fat that
//!   touches K contains one of K's guards ([`GuardGrid`]).
//! - Lemma 9: for a cone of a guard g and an object whose centre lies in the cone and whose
//!   box holds g, the triangle where the plane through the centre, orthogonal to the cone's
//!   representative edge, cuts the cone lies within the object's inner ball. So if the
//!   object holds g, the tetrahedron from g to that triangle lies inside it: the centres of
//!   objects apart from it lie farther along the edge, and centres in the cone keep their
//!   order along the edge while the boxes hold g.

use kinetic_core::Vec3;
use kinetic_flight::{ConeSet, ConvexShape, GuardGrid};
use parry3d_f64::math::Pose;
use parry3d_f64::query;
use parry3d_f64::shape::{Ball, Shape};
use proptest::prelude::*;

/// A ball, or a cuboid at most `rho`-fat, of inner radius `r`.
fn fat_shape(r: f64, rho: f64, kind: u8, a: f64, b: f64) -> Box<dyn Shape> {
    // A cube is sqrt 3 fat already.
    if kind == 0 || rho * rho < 3.0 {
        return Box::new(Ball::new(r));
    }
    // Half extents r, r y, r z with y, z in [1, m], m^2 = (rho^2 - 1) / 2: outer <= rho r.
    let m = ((rho * rho - 1.0) / 2.0).sqrt();
    let (y, z) = (1.0 + a * (m - 1.0), 1.0 + b * (m - 1.0));
    let cuboid = ConvexShape::cuboid(Vec3::new(r, r * y, r * z)).unwrap();
    assert!(cuboid.outer() <= rho * r * (1.0 + 1e-12) && cuboid.inner() == r);
    Box::new(*cuboid.parry().as_cuboid().unwrap())
}

fn rotation(axis: [f64; 3], angle: f64) -> glam::DQuat {
    let axis = Vec3::from(axis).normalize_or(Vec3::X);
    glam::DQuat::from_axis_angle(axis, angle)
}

fn unit(v: [f64; 3]) -> Vec3 {
    Vec3::from(v).normalize_or(Vec3::Z)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    #[test]
    fn lemma_7_a_larger_touching_object_contains_a_guard(
        rho in 1.0f64..3.0,
        r in 0.1f64..10.0,
        grow in 1.0f64..50.0,
        kinds in (0u8..2, 0u8..2),
        shape_a in (0.0f64..1.0, 0.0f64..1.0),
        shape_b in (0.0f64..1.0, 0.0f64..1.0),
        axes in ([-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0], [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0]),
        angles in (0.0f64..6.3, 0.0f64..6.3),
        dir in [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0],
    ) {
        let k = fat_shape(r, rho, kinds.0, shape_a.0, shape_a.1);
        let r2 = r * grow;
        let k2 = fat_shape(r2, rho, kinds.1, shape_b.0, shape_b.1);
        let pose_k = Pose::from_parts(Vec3::ZERO, rotation(axes.0, angles.0));
        let rot2 = rotation(axes.1, angles.1);
        let u = unit(dir);
        // Slide K' in from direction u until it touches K (bisection on the distance).
        let at = |s: f64| Pose::from_parts(u * s, rot2);
        let (mut lo, mut hi) = (0.0, 10.0 * (rho * r + rho * r2));
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if query::distance(&pose_k, &*k, &at(mid), &*k2).unwrap().distance > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let pose2 = at(lo);
        prop_assert!(query::distance(&pose_k, &*k, &pose2, &*k2).unwrap().distance == 0.0);
        let grid = GuardGrid::new(rho);
        let inside = grid
            .guards(Vec3::ZERO, r)
            .any(|g| k2.contains_point(&pose2, g));
        prop_assert!(inside, "no guard of K inside K' (rho {rho}, r {r}, r' {r2})");
    }

    #[test]
    fn lemma_9_the_cone_triangle_through_a_centre_lies_in_the_inner_ball(
        rho in 1.0f64..4.0,
        r in 0.1f64..10.0,
        kind in 0u8..2,
        shape in (0.0f64..1.0, 0.0f64..1.0),
        axis in [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0],
        angle in 0.0f64..6.3,
        cone in 0usize..100_000,
        weights in (0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0),
        depth in 0.0f64..1.0,
        samples in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0, 0.0f64..1.0), 32),
    ) {
        let cones = ConeSet::new(rho);
        let cone = *cones.cone((cone % cones.len()) as u32);
        let k = fat_shape(r, rho, kind, shape.0, shape.1);
        let outer = k.compute_local_bounding_sphere().radius;
        // A centre in the cone (from the guard g at the origin) whose box holds g, for the
        // fattest object allowed (outer radius rho r), mostly near the box's surface where
        // the bound is tight.
        let w = Vec3::new(weights.0, weights.1, weights.2) + Vec3::splat(1e-3);
        let ray = (cone.rays[0] * w.x + cone.rays[1] * w.y + cone.rays[2] * w.z).normalize();
        let reach = ray * (rho * r / ray.abs().max_element());
        let c = reach * (1.0 - depth * depth);
        prop_assert!(cone.normals.iter().all(|n| n.dot(c) >= -1e-12));
        // The triangle x y z: the cone's rays cut by the plane through c orthogonal to the
        // representative edge e.
        let e = cone.edge();
        let triangle = |c: Vec3| cone.rays.map(|q| q * (e.dot(c) / e.dot(q)));
        for x in triangle(c) {
            prop_assert!((x - c).length() <= r * (1.0 + 1e-9),
                "corner {x} is {} from the centre, inner radius {r}", (x - c).length());
        }
        // The same for this object, whose box may be smaller.
        let c = ray * (outer / ray.abs().max_element()) * (1.0 - depth * depth);
        let corners = triangle(c);
        // If the object holds g, it holds the tetrahedron from g to the triangle.
        let pose = Pose::from_parts(c, rotation(axis, angle));
        if k.contains_point(&pose, Vec3::ZERO) {
            for (a, b, d, s) in &samples {
                let t = s.cbrt();
                let sum = a + b + d + 1e-12;
                let p = (corners[0] * a + corners[1] * b + corners[2] * d) / sum * t;
                let dist = k.distance_to_point(&pose, p, true);
                prop_assert!(dist <= 1e-9 * outer, "{p} outside by {dist}");
            }
        }
    }
}
