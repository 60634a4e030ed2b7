//! The broad phase for rapier3d-f64 (feature `f64`): a pile settles as with rapier's own
//! broad phase, far from the origin where f32 positions would be coarse.

use kinetic_rapier::f64::KineticBroadPhase;
use kinetic_rapier::rapier3d_f64::prelude::*;

/// 40 balls dropped in two layers of a 5 by 4 grid, the upper ones onto the lower, onto a
/// ground at `x` = `offset` (at 1e7, f32 would round positions to 1).
fn pile(offset: f64) -> (RigidBodySet, ColliderSet, Vec<RigidBodyHandle>) {
    let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    colliders.insert(
        ColliderBuilder::cuboid(50.0, 0.5, 50.0)
            .translation(vector![offset, -0.5, 0.0])
            .build(),
    );
    let mut balls = Vec::new();
    for k in 0..40 {
        let (layer, cell) = (k / 20, k % 20);
        let at = vector![
            offset + (cell % 5) as f64 * 0.45 + layer as f64 * 0.2,
            0.5 + layer as f64 * 0.6,
            (cell / 5) as f64 * 0.45 + layer as f64 * 0.2
        ];
        let b = bodies.insert(RigidBodyBuilder::dynamic().translation(at));
        colliders.insert_with_parent(ColliderBuilder::ball(0.25), b, &mut bodies);
        balls.push(b);
    }
    (bodies, colliders, balls)
}

fn run(bp: &mut dyn BroadPhase) -> (Vec<f64>, usize) {
    let (mut bodies, mut colliders, balls) = pile(1e7);
    let mut pipeline = PhysicsPipeline::new();
    let params = IntegrationParameters::default();
    let (mut islands, mut narrow) = (IslandManager::new(), NarrowPhase::new());
    let (mut joints, mut multibody) = (ImpulseJointSet::new(), MultibodyJointSet::new());
    let mut ccd = CCDSolver::new();
    for _ in 0..400 {
        pipeline.step(
            &vector![0.0, -9.81, 0.0],
            &params,
            &mut islands,
            bp,
            &mut narrow,
            &mut bodies,
            &mut colliders,
            &mut joints,
            &mut multibody,
            &mut ccd,
            &(),
            &(),
        );
    }
    let heights = balls.iter().map(|&b| bodies[b].translation().y).collect();
    let touching = narrow
        .contact_pairs()
        .filter(|p| p.has_any_active_contact)
        .count();
    (heights, touching)
}

#[test]
fn a_pile_far_from_the_origin_settles_as_with_the_default_broad_phase() {
    let (h2, t2) = run(&mut DefaultBroadPhase::new());
    let top = |h: &[f64]| h.iter().copied().fold(0.0, f64::max);
    // As it comes (a small pile steps), and held to the loose grid (kinetic throughout: its
    // plans far from the origin), audited after every event of its structure.
    for held in [false, true] {
        let mut ours = KineticBroadPhase::new().with_audit();
        if held {
            ours = ours.with_loose_grid(true);
        }
        let (h1, t1) = run(&mut ours);
        assert_eq!(ours.audit_error(), None);
        // Nothing fell through, and the pile stands about as high with both.
        assert!(h1.iter().all(|&y| y > 0.2), "{h1:?}");
        assert!(
            (top(&h1) - top(&h2)).abs() < 0.5,
            "{} {}",
            top(&h1),
            top(&h2)
        );
        assert!(t1 >= 40 && t2 >= 40, "{t1} {t2}");
        assert!(ours.stats().pairs > 0);
        if held {
            assert!(ours.stats().events > 0);
        }
    }
}
