//! The broad phase's own tests (its private tables).

use super::*;

/// Steps a ground and two falling balls `steps` times with `bp`.
struct World {
    bodies: RigidBodySet,
    colliders: ColliderSet,
    islands: IslandManager,
    narrow: NarrowPhase,
    joints: ImpulseJointSet,
    multibody: MultibodyJointSet,
    pipeline: PhysicsPipeline,
}

impl World {
    fn new() -> (World, [ColliderHandle; 3], RigidBodyHandle) {
        let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
        let ground = colliders.insert(ColliderBuilder::cuboid(10.0, 0.1, 10.0).build());
        let mut balls = [ground; 2];
        let mut first = None;
        for (k, ball) in balls.iter_mut().enumerate() {
            let b = bodies.insert(RigidBodyBuilder::dynamic().translation(vector![
                k as f32 * 2.0,
                1.0,
                0.0
            ]));
            first.get_or_insert(b);
            *ball = colliders.insert_with_parent(ColliderBuilder::ball(0.5), b, &mut bodies);
        }
        let world = World {
            bodies,
            colliders,
            islands: IslandManager::new(),
            narrow: NarrowPhase::new(),
            joints: ImpulseJointSet::new(),
            multibody: MultibodyJointSet::new(),
            pipeline: PhysicsPipeline::new(),
        };
        (world, [ground, balls[0], balls[1]], first.expect("a body"))
    }

    fn step(&mut self, bp: &mut KineticBroadPhase, steps: usize) {
        for _ in 0..steps {
            self.pipeline.step(
                &vector![0.0, -9.81, 0.0],
                &IntegrationParameters::default(),
                &mut self.islands,
                bp,
                &mut self.narrow,
                &mut self.bodies,
                &mut self.colliders,
                &mut self.joints,
                &mut self.multibody,
                &mut CCDSolver::new(),
                &(),
                &(),
            );
            bp.validate(&self.colliders, &self.bodies)
                .expect("a valid broad phase");
        }
    }
}

#[test]
fn the_mover_table_follows_the_held_colliders_and_validate_checks_it() {
    let (mut world, [ground, ball, other], body) = World::new();
    let mut bp = KineticBroadPhase::new();
    world.step(&mut bp, 5);
    let entry =
        |bp: &KineticBroadPhase, h: ColliderHandle| bp.movers[h.into_raw_parts().0 as usize];
    let generation = |h: ColliderHandle| h.into_raw_parts().1;
    assert_eq!(entry(&bp, ground), Some((generation(ground), u32::MAX)));
    assert_eq!(
        entry(&bp, ball),
        Some((generation(ball), body.into_raw_parts().0))
    );
    // A stale entry (the ball taken for fixed) is caught.
    let i = ball.into_raw_parts().0 as usize;
    let kept = bp.movers[i];
    bp.movers[i] = Some((generation(ball), u32::MAX));
    let err = bp
        .validate(&world.colliders, &world.bodies)
        .expect_err("a stale mover entry");
    assert!(err.contains("mover"), "{err}");
    bp.movers[i] = kept;
    // A removed collider leaves no entry; the other ball still moves and is re-planned.
    world
        .colliders
        .remove(other, &mut world.islands, &mut world.bodies, true);
    world.step(&mut bp, 30);
    assert_eq!(entry(&bp, other), None);
    assert!(bp.stats().replans > 0);
    assert!(world.bodies[body].translation().y < 0.9);
}
