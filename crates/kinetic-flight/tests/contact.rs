//! Contact times of shape pairs against closed forms: faces, edges and vertices meeting under
//! linear motion, constant acceleration and spin.

use kinetic_core::{
    BruteForce, ContactEvent, ContactKind, FlightPlan, Quat, Response, Shape, Simulator, Vec3,
    WorldKind,
};
use kinetic_flight::{ConvexShape, Sweep};

fn cuboid(h: [f64; 3]) -> Shape {
    ConvexShape::cuboid(Vec3::from(h)).unwrap().into_shape()
}

/// Runs the objects to `horizon` with both the brute force and the sweep, checks they agree,
/// and returns the events.
fn run(objects: &[(Shape, FlightPlan)], horizon: f64) -> Vec<ContactEvent> {
    let mut logs = Vec::new();
    for sweep in [false, true] {
        let structure: Box<dyn kinetic_core::CandidateStructure> = if sweep {
            Box::new(Sweep::new())
        } else {
            Box::new(BruteForce::new())
        };
        let mut w =
            Simulator::with_structure(WorldKind::Free, Response::None, None, structure).unwrap();
        w.add_objects(objects.iter().cloned()).unwrap();
        while w.step(horizon).unwrap().is_some() {
            w.validate().unwrap();
        }
        logs.push(w.drain_events());
    }
    assert_eq!(logs[0].len(), logs[1].len(), "{logs:?}");
    for (x, y) in logs[0].iter().zip(&logs[1]) {
        assert_eq!((x.a, x.b, x.kind), (y.a, y.b, y.kind));
        assert!((x.time - y.time).abs() < 1e-9 * x.time.abs().max(1.0));
    }
    logs.swap_remove(0)
}

fn assert_times(events: &[ContactEvent], want: &[(ContactKind, f64)]) {
    assert_eq!(events.len(), want.len(), "{events:?} vs {want:?}");
    for (e, (k, t)) in events.iter().zip(want) {
        assert_eq!(e.kind, *k, "{events:?}");
        assert!(
            (e.time - t).abs() <= 1e-9 * t.abs().max(1.0),
            "{} vs {t}: {events:?}",
            e.time
        );
    }
}

#[test]
fn ball_through_a_cube_face_on() {
    let events = run(
        &[
            (cuboid([1.0, 1.0, 1.0]), FlightPlan::at_rest(Vec3::ZERO)),
            (
                Shape::Ball { radius: 0.5 },
                FlightPlan::linear(Vec3::new(-10.0, 0.2, -0.3), Vec3::new(2.0, 0.0, 0.0)),
            ),
        ],
        20.0,
    );
    // Touches the face x = -1 when its centre is at -1.5; leaves x = 1 at 1.5.
    assert_times(
        &events,
        &[(ContactKind::Begin, 4.25), (ContactKind::End, 5.75)],
    );
}

#[test]
fn ball_meets_the_edge_of_a_turned_cube() {
    // A unit cube turned 45 degrees about z presents an edge at x = -sqrt 2.
    let turned = FlightPlan::at_rest(Vec3::ZERO).with_spin(
        Quat::from_rotation_z(std::f64::consts::FRAC_PI_4),
        Vec3::ZERO,
    );
    let events = run(
        &[
            (cuboid([1.0, 1.0, 1.0]), turned),
            (
                Shape::Ball { radius: 0.25 },
                FlightPlan::linear(Vec3::new(-5.0, 0.0, 0.0), Vec3::X),
            ),
        ],
        3.5,
    );
    assert_times(&events, &[(ContactKind::Begin, 5.0 - 2f64.sqrt() - 0.25)]);
}

#[test]
fn spinning_cuboid_sweeps_into_a_wall() {
    // Half extents (a, b) spinning about z at w: its reach along x is |a cos wt| + |b sin wt|,
    // R cos(wt - phi) for wt in [0, pi/2], mirrored about pi/2. A wall face at x = x0 with
    // b < x0 < R is touched for wt within acos(x0 / R) of phi, and of pi - phi.
    let (a, b, x0, w) = (1.0f64, 2.0f64, 2.1f64, 0.7f64);
    let (r, phi) = ((a * a + b * b).sqrt(), b.atan2(a));
    let spin = FlightPlan::at_rest(Vec3::ZERO).with_spin(Quat::IDENTITY, Vec3::new(0.0, 0.0, w));
    let wall = FlightPlan::at_rest(Vec3::new(x0 + 1.0, 0.0, 0.0));
    let pi = std::f64::consts::PI;
    let events = run(
        &[
            (cuboid([a, b, 0.5]), spin),
            (cuboid([1.0, 50.0, 50.0]), wall),
        ],
        pi / w,
    );
    let half_width = (x0 / r).acos();
    assert_times(
        &events,
        &[
            (ContactKind::Begin, (phi - half_width) / w),
            (ContactKind::End, (phi + half_width) / w),
            (ContactKind::Begin, (pi - phi - half_width) / w),
            (ContactKind::End, (pi - phi + half_width) / w),
        ],
    );
}

#[test]
fn cube_falls_onto_a_slab_under_gravity() {
    // Bottom face at z0 - 0.5 - g t^2 / 2 meets the slab top at z = 0.
    let (z0, g) = (10.0, 9.81);
    let fall = FlightPlan::accelerated(
        Vec3::new(0.3, -0.2, z0),
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -g),
    );
    let events = run(
        &[
            (cuboid([0.5, 0.5, 0.5]), fall),
            (
                cuboid([20.0, 20.0, 1.0]),
                FlightPlan::at_rest(Vec3::new(0.0, 0.0, -1.0)),
            ),
        ],
        2.0,
    );
    let t = (2.0 * (z0 - 0.5) / g).sqrt();
    // It passes through (no response): the top face leaves the slab's bottom at z = -2.
    let t_end = (2.0 * (z0 + 0.5 + 2.0) / g).sqrt();
    assert_times(
        &events,
        &[(ContactKind::Begin, t), (ContactKind::End, t_end)],
    );
}

#[test]
fn hull_vertex_lands_on_a_slab() {
    // A tetrahedron with its lowest vertex 1 below its frame origin, falling at speed 2.
    let tetra = ConvexShape::convex_hull(&[
        Vec3::new(0.0, 0.0, -1.0),
        Vec3::new(1.0, 0.0, 0.5),
        Vec3::new(-0.5, 0.8, 0.5),
        Vec3::new(-0.5, -0.8, 0.5),
    ])
    .unwrap()
    .into_shape();
    let events = run(
        &[
            (
                tetra,
                FlightPlan::linear(Vec3::new(0.1, 0.1, 7.0), Vec3::new(0.0, 0.0, -2.0)),
            ),
            (
                cuboid([5.0, 5.0, 1.0]),
                FlightPlan::at_rest(Vec3::new(0.0, 0.0, -1.0)),
            ),
        ],
        3.2,
    );
    assert_times(&events, &[(ContactKind::Begin, 3.0)]);
}

#[test]
fn overlapping_at_the_start_begins_at_zero() {
    let events = run(
        &[
            (cuboid([1.0, 1.0, 1.0]), FlightPlan::at_rest(Vec3::ZERO)),
            (
                cuboid([1.0, 1.0, 1.0]),
                FlightPlan::linear(Vec3::new(1.5, 0.0, 0.0), Vec3::X),
            ),
        ],
        10.0,
    );
    assert_times(
        &events,
        &[(ContactKind::Begin, 0.0), (ContactKind::End, 0.5)],
    );
}

#[test]
fn near_miss_is_not_a_contact() {
    // The ball passes the cube's face 1e-6 away.
    let events = run(
        &[
            (cuboid([1.0, 1.0, 1.0]), FlightPlan::at_rest(Vec3::ZERO)),
            (
                Shape::Ball { radius: 0.5 },
                FlightPlan::linear(Vec3::new(-10.0, 1.5 + 1e-6, 0.0), Vec3::X),
            ),
        ],
        20.0,
    );
    assert!(events.is_empty(), "{events:?}");
}

#[test]
fn coordinates_offset_by_1e6_keep_the_times() {
    let off = Vec3::splat(1e6);
    let events = run(
        &[
            (cuboid([1.0, 1.0, 1.0]), FlightPlan::at_rest(off)),
            (
                Shape::Ball { radius: 0.5 },
                FlightPlan::linear(off + Vec3::new(-10.0, 0.2, -0.3), Vec3::new(2.0, 0.0, 0.0)),
            ),
        ],
        20.0,
    );
    // Positions near 1e6 carry about 1e-10 of rounding: times to 1e-9 still hold.
    assert_times(
        &events,
        &[(ContactKind::Begin, 4.25), (ContactKind::End, 5.75)],
    );
}
